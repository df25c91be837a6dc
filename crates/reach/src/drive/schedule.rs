use serde::Serialize;

use super::{Axis, DriveError};
use crate::Robot;
use crate::motion::JointSample;
use crate::tolerance::DRIVE_LIMIT_SLACK;

/// The most steps one joint's schedule may hold: a plan that asks for more is refused before
/// anything is allocated. 2 million steps are 10 s at a 200 kHz step rate; they take 48 MB as
/// [`Step`]s and about 250 MB as the drive report's step rows, so a six-joint motion stays
/// within about 1.5 GB.
pub const MAX_STEPS_PER_JOINT: u64 = 2_000_000;

/// One motor step.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Step {
    /// Time of the pulse, s.
    pub t: f64,
    /// Motor direction: +1 or −1 (the level of the DIR line).
    pub dir: i8,
    /// Step counter after this step.
    pub position: i64,
}

/// The steps of one joint's motor.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointSchedule {
    /// The joint's conversion data and limits.
    pub axis: Axis,
    /// Step counter at the start.
    pub start_position: i64,
    /// Step counter at the end.
    pub end_position: i64,
    /// The steps in time order.
    pub steps: Vec<Step>,
}

impl JointSchedule {
    /// The step counter at time `t`: the position after the last step at or before `t`.
    #[must_use]
    pub fn position_at(&self, t: f64) -> i64 {
        let k = self.steps.partition_point(|s| s.t <= t);
        if k == 0 { self.start_position } else { self.steps[k - 1].position }
    }
}

/// Step timestamps for every joint of a robot.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StepSchedule {
    /// Start of the plan, s.
    pub start_time: f64,
    /// End of the plan, s.
    pub end_time: f64,
    /// One entry per joint, base to tip.
    pub joints: Vec<JointSchedule>,
}

impl StepSchedule {
    /// Total number of steps over all joints.
    #[must_use]
    pub fn step_count(&self) -> usize {
        self.joints.iter().map(|j| j.steps.len()).sum()
    }

    /// Joint values (SI) held by the motors at time `t`.
    #[must_use]
    pub fn joint_values_at(&self, t: f64) -> Vec<f64> {
        self.joints.iter().map(|j| j.axis.joint_value(j.position_at(t))).collect()
    }
}

fn check_samples(axes: &[Axis], samples: &[JointSample]) -> Result<(), DriveError> {
    if samples.len() < 2 {
        return Err(DriveError::Trajectory(format!("needs at least 2 samples, got {}", samples.len())));
    }
    for (i, s) in samples.iter().enumerate() {
        if s.q.len() != axes.len() {
            return Err(DriveError::Trajectory(format!(
                "sample {i} has {} joint values, the robot has {} joints",
                s.q.len(),
                axes.len()
            )));
        }
        if !s.t.is_finite() {
            return Err(DriveError::Trajectory(format!("sample {i}: time must be finite, got {}", s.t)));
        }
        if let Some(j) = s.q.iter().position(|v| !v.is_finite()) {
            return Err(DriveError::Trajectory(format!("sample {i}: joint {} must be finite, got {}", j + 1, s.q[j])));
        }
        if i > 0 && s.t <= samples[i - 1].t {
            return Err(DriveError::Trajectory(format!(
                "sample times must increase: sample {i} at {} s follows {} s",
                s.t,
                samples[i - 1].t
            )));
        }
    }
    Ok(())
}

/// A limit violation found while checking a plan.
struct Violation {
    axis: usize,
    time: f64,
    value: f64,
    acceleration: bool,
}

/// Converts a sampled joint trajectory into per-joint step timestamps.
///
/// # Behavior
/// The plan is the piecewise-linear interpolation of the samples. Each motor's counter is
/// `⌊s(q(t)) + ½⌋` (see [`Axis::exact_steps`]): a step is taken at the instant the plan crosses
/// a half-step boundary, found by linear interpolation inside the sample interval. The counter
/// depends only on the plan position, so rounding errors never accumulate: over any path the
/// net step count is exactly `round(s(q_end)) − round(s(q_start))`. Where the plan turns back
/// across a boundary within one step period (`1/max_step_rate`), the step and its undo are
/// dropped; the counter then stays within one step of the plan.
///
/// Before quantising, every interval's step rate `|Δs|/Δt` is checked against the motor's
/// `max_step_rate`, and the rate change between consecutive intervals (divided by the mean
/// interval length) against `max_acceleration`. The first and last samples are taken as the
/// motor starts and ends them (a plan should start and end at rest).
///
/// # Errors
/// [`DriveError::Trajectory`] for fewer than two samples, a wrong joint count, NaN or
/// non-increasing times; [`DriveError::RateLimit`] / [`DriveError::AccelerationLimit`] naming
/// the joint and the time of the first violation and the shortest duration of the uniformly
/// slowed plan that respects every limit.
///
/// # Performance
/// O(samples × joints + steps), no allocation per sample.
pub fn schedule_trajectory(axes: &[Axis], samples: &[JointSample]) -> Result<StepSchedule, DriveError> {
    check_samples(axes, samples)?;
    let (t0, t_end) = (samples[0].t, samples[samples.len() - 1].t);
    let mut slow_down = 1.0_f64; // uniform time-scaling factor that satisfies every limit
    let mut first: Option<Violation> = None;
    let mut joints = Vec::with_capacity(axes.len());
    let mut exact = vec![0.0; samples.len()]; // one joint's exact step counter per sample
    for (a, axis) in axes.iter().enumerate() {
        for (e, sample) in exact.iter_mut().zip(samples) {
            *e = axis.exact_steps(sample.q[a]);
        }
        // Pass 1: limits, and the path length in steps (to size the step list).
        let rate_cap = axis.max_step_rate * (1.0 + DRIVE_LIMIT_SLACK);
        let acc_cap = axis.max_acceleration.map(|v| v * (1.0 + DRIVE_LIMIT_SLACK));
        let mut v_prev: Option<(f64, f64)> = None; // (rate, interval length)
        let mut travel = 0.0;
        for (i, w) in samples.windows(2).enumerate() {
            let (ta, dt) = (w[0].t, w[1].t - w[0].t);
            let ds = exact[i + 1] - exact[i];
            travel += ds.abs();
            let v = ds / dt;
            if v.abs() > rate_cap {
                slow_down = slow_down.max(v.abs() / axis.max_step_rate);
                if first.as_ref().is_none_or(|f| ta < f.time) {
                    first = Some(Violation { axis: a, time: ta, value: v.abs(), acceleration: false });
                }
            }
            if let (Some(cap), Some((v0, dt0))) = (acc_cap, v_prev) {
                let acc = ((v - v0) / (0.5 * (dt + dt0))).abs();
                if acc > cap {
                    slow_down = slow_down.max((acc / axis.max_acceleration.unwrap_or(cap)).sqrt());
                    if first.as_ref().is_none_or(|f| ta < f.time) {
                        first = Some(Violation { axis: a, time: ta, value: acc, acceleration: true });
                    }
                }
            }
            v_prev = Some((v, dt));
        }
        if first.is_some() {
            continue; // keep checking the other joints for the suggested duration
        }
        too_many_steps(axis, travel)?;
        // Pass 2: boundary crossings, up while s ≥ n + ½, down while s < n − ½. The counter
        // after a step equals the rounding counter `n` (a dropped chatter pair nets zero).
        let min_interval = 1.0 / axis.max_step_rate;
        let start = (exact[0] + 0.5).floor() as i64;
        let mut n = start;
        let mut steps: Vec<Step> = Vec::with_capacity(travel as usize + 1);
        for (i, w) in samples.windows(2).enumerate() {
            let (ta, tb) = (w[0].t, w[1].t);
            let (s_prev, s_next) = (exact[i], exact[i + 1]);
            let ds = s_next - s_prev;
            if ds > 0.0 {
                let per_step = (tb - ta) / ds;
                while s_next >= n as f64 + 0.5 {
                    let t = (ta + (n as f64 + 0.5 - s_prev) * per_step).clamp(ta, tb);
                    n += 1;
                    push_step(&mut steps, t, 1, n, min_interval);
                }
            } else if ds < 0.0 {
                let per_step = (tb - ta) / ds;
                while s_next < n as f64 - 0.5 {
                    let t = (ta + (n as f64 - 0.5 - s_prev) * per_step).clamp(ta, tb);
                    n -= 1;
                    push_step(&mut steps, t, -1, n, min_interval);
                }
            }
        }
        joints.push(JointSchedule { axis: axis.clone(), start_position: start, end_position: n, steps });
    }
    if let Some(v) = first {
        let axis = &axes[v.axis];
        let duration = t_end - t0;
        let suggested = duration * slow_down;
        return Err(if v.acceleration {
            DriveError::AccelerationLimit {
                joint: axis.joint,
                name: axis.name.clone(),
                time: v.time,
                acceleration: v.value,
                limit: axis.max_acceleration.unwrap_or(f64::INFINITY),
                duration,
                suggested,
            }
        } else {
            DriveError::RateLimit {
                joint: axis.joint,
                name: axis.name.clone(),
                time: v.time,
                rate: v.value,
                limit: axis.max_step_rate,
                duration,
                suggested,
            }
        });
    }
    Ok(StepSchedule { start_time: t0, end_time: t_end, joints })
}

/// Refuses a joint whose plan travels more than [`MAX_STEPS_PER_JOINT`] steps (`travel`, a
/// bound on its step count: path length in steps).
fn too_many_steps(axis: &Axis, travel: f64) -> Result<(), DriveError> {
    if travel.is_nan() || travel > MAX_STEPS_PER_JOINT as f64 {
        return Err(DriveError::TooManySteps {
            joint: axis.joint,
            name: axis.name.clone(),
            steps: travel,
            limit: MAX_STEPS_PER_JOINT,
        });
    }
    Ok(())
}

/// Appends a step, or drops it together with the previous step when it undoes that step
/// within `min_interval` (chatter of a plan turning back across one boundary).
#[inline]
fn push_step(steps: &mut Vec<Step>, t: f64, dir: i8, position: i64, min_interval: f64) {
    if let Some(last) = steps.last()
        && last.dir == -dir
        && t - last.t < min_interval
    {
        steps.pop();
        return;
    }
    steps.push(Step { t, dir, position });
}

/// A synchronised point-to-point move: every joint follows the same normalised trapezoidal
/// profile `u(t)` from 0 to 1, so all start and stop together.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointToPoint {
    /// Start time, s.
    pub start_time: f64,
    /// Duration, s.
    pub duration: f64,
    /// Cruise value of `u̇`, 1/s (joint *i* then steps at `φᵢ·cruise` Hz).
    pub cruise: f64,
    /// Value of `ü` during the ramps, 1/s² (`None` = no ramps: constant rates).
    pub acceleration: Option<f64>,
    /// Step counters at the start, one per joint (the start snapped to the step grid).
    pub from_steps: Vec<i64>,
    /// Step counters at the end (the target snapped to the step grid).
    pub to_steps: Vec<i64>,
    /// The step schedule.
    pub schedule: StepSchedule,
}

impl PointToPoint {
    /// The normalised progress `u ∈ [0, 1]` at time `t`.
    #[must_use]
    pub fn progress(&self, t: f64) -> f64 {
        let tau = (t - self.start_time).clamp(0.0, self.duration);
        let v = self.cruise;
        match self.acceleration {
            None => (tau * v).min(1.0),
            Some(acc) => {
                let ta = v / acc;
                if tau <= ta {
                    0.5 * acc * tau * tau
                } else if tau <= self.duration - ta {
                    0.5 * v * ta + v * (tau - ta)
                } else {
                    let r = self.duration - tau;
                    1.0 - 0.5 * acc * r * r
                }
            }
        }
    }

    /// The planned (grid-snapped) joint values at time `t`, SI.
    #[must_use]
    pub fn planned_at(&self, t: f64) -> Vec<f64> {
        let u = self.progress(t);
        self.schedule
            .joints
            .iter()
            .zip(self.from_steps.iter().zip(&self.to_steps))
            .map(|(j, (&a, &b))| {
                let s = a as f64 + (b - a) as f64 * u;
                j.axis.home + (s - j.axis.home_steps as f64) / (f64::from(j.axis.direction) * j.axis.steps_per_unit)
            })
            .collect()
    }

    /// `count + 1` samples of the planned move at equal time intervals (for [`super::verify`]
    /// and G-code), flagged against `robot`'s position limits.
    #[must_use]
    pub fn samples(&self, robot: &Robot, count: usize) -> Vec<JointSample> {
        let count = count.max(1);
        (0..=count)
            .map(|i| {
                let t = self.start_time + self.duration * i as f64 / count as f64;
                JointSample::of(robot, t, self.planned_at(t))
            })
            .collect()
    }

    /// Time within the move at which progress `u` is reached (inverse of [`Self::progress`]).
    fn time_of(&self, u: f64) -> f64 {
        let v = self.cruise;
        match self.acceleration {
            None => u / v,
            Some(acc) => {
                let ta = v / acc;
                let ua = 0.5 * v * ta;
                if u <= ua {
                    (2.0 * u / acc).sqrt()
                } else if u <= 1.0 - ua {
                    ta + (u - ua) / v
                } else {
                    self.duration - (2.0 * (1.0 - u).max(0.0) / acc).sqrt()
                }
            }
        }
    }
}

/// Plans a synchronised point-to-point move from `from` to `to` (SI joint values).
///
/// # Behavior
/// Both ends are snapped to the step grid (`φᵢ = |round(s(to)) − round(s(from))|` steps). All
/// joints share one trapezoidal profile `u(t)`, so joint *i* steps at `φᵢ·u̇(t)` Hz and all
/// start and end together — seed 000's intent with the corrected synchronisation (notes 000,
/// D8: equal durations `φᵢ/ωᵢ`, not equal products `φᵢ·ωᵢ`). The cruise rate is
/// `min(fᵢ/φᵢ)` and the ramp `min(aᵢ/φᵢ)`, so the bottleneck motor runs at its limit; without
/// acceleration limits the rates are constant: `ωᵢ = f_max·φᵢ / max φ`. A longer `duration`
/// keeps the ramp acceleration and lowers the cruise rate. Step `k` of joint *i* is taken when
/// `φᵢ·u(t)` reaches `k`, so the last step of every joint falls at the end time.
///
/// # Errors
/// [`DriveError::Trajectory`] for wrong lengths or non-finite values or a non-positive
/// duration; [`DriveError::DurationTooShort`] naming the limiting joint and the shortest
/// feasible duration.
pub fn point_to_point(
    axes: &[Axis],
    from: &[f64],
    to: &[f64],
    duration: Option<f64>,
    start_time: f64,
) -> Result<PointToPoint, DriveError> {
    for (what, q) in [("start", from), ("target", to)] {
        if q.len() != axes.len() {
            return Err(DriveError::Trajectory(format!(
                "the {what} has {} joint values, the robot has {} joints",
                q.len(),
                axes.len()
            )));
        }
        if let Some(j) = q.iter().position(|v| !v.is_finite()) {
            return Err(DriveError::Trajectory(format!("{what}: joint {} must be finite, got {}", j + 1, q[j])));
        }
    }
    if !start_time.is_finite() {
        return Err(DriveError::Trajectory(format!("start time must be finite, got {start_time}")));
    }
    if let Some(d) = duration
        && !(d.is_finite() && d > 0.0)
    {
        return Err(DriveError::Trajectory(format!("duration must be a positive number of seconds, got {d}")));
    }
    for (axis, (&a, &b)) in axes.iter().zip(from.iter().zip(to)) {
        too_many_steps(axis, (axis.exact_steps(b) - axis.exact_steps(a)).abs())?;
    }
    let from_steps: Vec<i64> = axes.iter().zip(from).map(|(a, &q)| a.quantise(q)).collect();
    let to_steps: Vec<i64> = axes.iter().zip(to).map(|(a, &q)| a.quantise(q)).collect();
    let phi: Vec<f64> = from_steps.iter().zip(&to_steps).map(|(a, b)| (b - a).abs() as f64).collect();
    // Bottleneck cruise (u̇) and ramp (ü) values, with the joints that set them.
    let mut v_max = (f64::INFINITY, 0usize);
    let mut a_max = (f64::INFINITY, 0usize);
    for (i, (axis, &p)) in axes.iter().zip(&phi).enumerate() {
        if p > 0.0 {
            let v = axis.max_step_rate / p;
            if v < v_max.0 {
                v_max = (v, i);
            }
            if let Some(acc) = axis.max_acceleration {
                let a = acc / (p * (1.0 + crate::tolerance::DRIVE_RAMP_MARGIN));
                if a < a_max.0 {
                    a_max = (a, i);
                }
            }
        }
    }
    let moving = v_max.0.is_finite();
    let (min_duration, limiting) = if !moving {
        (0.0, 0)
    } else if a_max.0.is_infinite() {
        (1.0 / v_max.0, v_max.1)
    } else if v_max.0 * v_max.0 / a_max.0 >= 1.0 {
        (2.0 / a_max.0.sqrt(), a_max.1) // triangular: the ramp limit decides
    } else {
        (1.0 / v_max.0 + v_max.0 / a_max.0, v_max.1)
    };
    let duration = match duration {
        Some(d) if d < min_duration * (1.0 - DRIVE_LIMIT_SLACK) => {
            return Err(DriveError::DurationTooShort {
                duration: d,
                needed: min_duration,
                joint: limiting + 1,
                name: axes[limiting].name.clone(),
            });
        }
        Some(d) => d.max(min_duration),
        None => min_duration,
    };
    let (cruise, acceleration) = if !moving || duration == 0.0 {
        (0.0, None)
    } else if a_max.0.is_infinite() {
        (1.0 / duration, None)
    } else {
        let (a, t) = (a_max.0, duration);
        // Trapezoid of duration t with ramp acceleration a: v = (a t − √(a²t² − 4a)) / 2.
        let disc = (a * a * t * t - 4.0 * a).max(0.0);
        ((a * t - disc.sqrt()) / 2.0, Some(a))
    };
    let mut plan = PointToPoint {
        start_time,
        duration,
        cruise,
        acceleration,
        from_steps: from_steps.clone(),
        to_steps: to_steps.clone(),
        schedule: StepSchedule { start_time, end_time: start_time + duration, joints: Vec::new() },
    };
    let mut joints = Vec::with_capacity(axes.len());
    for (i, axis) in axes.iter().enumerate() {
        let (a, b) = (from_steps[i], to_steps[i]);
        let count = (b - a).unsigned_abs();
        let dir: i8 = if b >= a { 1 } else { -1 };
        let mut steps = Vec::with_capacity(count as usize);
        for k in 1..=count {
            let t = if k == count { duration } else { plan.time_of(k as f64 / count as f64) };
            steps.push(Step { t: start_time + t, dir, position: a + i64::from(dir) * k as i64 });
        }
        joints.push(JointSchedule { axis: axis.clone(), start_position: a, end_position: b, steps });
    }
    plan.schedule.joints = joints;
    Ok(plan)
}
