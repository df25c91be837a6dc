//! From a planned job to what the simulated motors play: the library's drive workflow
//! ([`reach::jobs::drive`]) turns the job's joint motion into step schedules (re-checking
//! position and speed limits and the motors' rates), the service checks that the motion
//! starts where the arm is and, with a scene, that it is proven clear of it; [`Timeline`] then
//! answers "where is each motor at time t".

use reach::Robot;
use reach::drive::Axis;
use reach::jobs::drive::{DriveMotion, DriveReport, DriveRequest};
use reach::jobs::input::MotionSample;
use reach::jobs::input::{AngleUnit, from_si, number_text, samples_si, unit_name};
use reach::jobs::world::SweptPathReport;
use reach::jobs::world::motion_times;
use reach::jobs::{Report, Request};
use reach::world::Scene;

/// Motion time between two commits of the joint state, seconds (the issue's "at most 50 ms
/// of motion apart").
pub const SEGMENT_S: f64 = 0.05;

/// Sampling step of a path job's timed motion, seconds.
const PATH_DT_S: f64 = 0.01;

/// Every joint's steps over time, from a drive report.
#[derive(Debug, Clone)]
pub struct Timeline {
    /// Start of the schedule, seconds.
    pub start_s: f64,
    /// Its duration, seconds.
    pub duration_s: f64,
    /// Per joint: the counter at the start, then (time, counter after the step) of every step.
    joints: Vec<(i64, Vec<f64>, Vec<i64>)>,
}

impl Timeline {
    /// The timeline of a drive report's steps.
    #[must_use]
    pub fn of(report: &DriveReport) -> Self {
        let mut joints: Vec<(i64, Vec<f64>, Vec<i64>)> = report
            .joints
            .iter()
            .map(|j| (j.start_position, Vec::with_capacity(j.steps), Vec::with_capacity(j.steps)))
            .collect();
        for row in &report.steps {
            if let Some(j) = joints.get_mut(row.joint - 1) {
                j.1.push(row.t_s);
                j.2.push(row.position);
            }
        }
        Timeline { start_s: report.start_s, duration_s: report.duration_s, joints }
    }

    /// Every motor's counter at `t` seconds after the start (the position after the last step
    /// at or before it).
    #[must_use]
    pub fn steps_at(&self, t: f64) -> Vec<i64> {
        let t = self.start_s + t;
        self.joints
            .iter()
            .map(|(start, times, positions)| {
                let k = times.partition_point(|&s| s <= t);
                if k == 0 { *start } else { positions[k - 1] }
            })
            .collect()
    }

    /// Every joint's value (SI) at `t` seconds after the start, continuous: between two steps
    /// the counter is interpolated linearly in time (within one step of the counters of
    /// [`Timeline::steps_at`]).
    #[must_use]
    pub fn values_at(&self, axes: &[Axis], t: f64) -> Vec<f64> {
        let t = self.start_s + t;
        self.joints
            .iter()
            .zip(axes)
            .map(|((start, times, positions), axis)| {
                let k = times.partition_point(|&s| s <= t);
                let (t0, p0) = if k == 0 { (self.start_s, *start) } else { (times[k - 1], positions[k - 1]) };
                let Some((&t1, &p1)) = times.get(k).zip(positions.get(k)) else { return axis.joint_value(p0) };
                let f = if t1 > t0 { ((t - t0) / (t1 - t0)).clamp(0.0, 1.0) } else { 1.0 };
                let (v0, v1) = (axis.joint_value(p0), axis.joint_value(p1));
                v0 + f * (v1 - v0)
            })
            .collect()
    }

    /// The counters at the start.
    #[must_use]
    pub fn start_steps(&self) -> Vec<i64> {
        self.joints.iter().map(|j| j.0).collect()
    }

    /// The number of commit segments (each at most [`SEGMENT_S`] of motion; at least 1).
    #[must_use]
    pub fn segments(&self) -> i64 {
        ((self.duration_s / SEGMENT_S - 1e-9).ceil() as i64).max(1)
    }

    /// The time (from the start) at the end of segment `k` (1-based).
    #[must_use]
    pub fn segment_end(&self, k: i64) -> f64 {
        (k as f64 * SEGMENT_S).min(self.duration_s)
    }
}

/// The joint motion a planned job asks the motors to follow, as the drive workflow reads it;
/// `None` for a job whose report holds no motion (tasks, avoid: planned only).
///
/// # Errors
/// The library's message when a path's waypoints cannot be timed.
pub fn motion_of(robot: &Robot, request: &Request, report: &Report) -> Result<Option<DriveMotion>, String> {
    Ok(match (request, report) {
        (_, Report::Move(m)) => Some(DriveMotion::Samples(m.samples.iter().map(MotionSample::from).collect())),
        (Request::Plan(p), Report::Plan(_)) => Some(DriveMotion::Task(p.task.clone())),
        (_, Report::Path(p)) => {
            let samples = p.motion(robot, PATH_DT_S).map_err(|e| e.to_string())?;
            (samples.len() >= 2).then_some(DriveMotion::Samples(samples))
        }
        (_, Report::Approach(a)) => {
            let samples = a.motion(robot, PATH_DT_S).map_err(|e| e.to_string())?;
            (samples.len() >= 2).then_some(DriveMotion::Samples(samples))
        }
        _ => None,
    })
}

/// Runs the library's drive workflow on `motion` (limits, speeds, motor rates re-checked).
///
/// # Errors
/// The library's message.
pub fn drive(robot: &Robot, motion: DriveMotion) -> Result<DriveReport, String> {
    reach::jobs::drive::drive(robot, &DriveRequest { motion, program: None })
        .map_err(|e| reach::one_line(&e.to_string()))
}

/// [`drive`] for a motion whose pace the service chose (a detour): when a motor's rate or
/// acceleration limit is exceeded, the same path is slowed uniformly to the duration the drive
/// workflow suggests (every sample's time scaled) and scheduled again. Returns the schedule and
/// the samples it follows.
///
/// # Errors
/// The library's message.
pub fn drive_slowed(robot: &Robot, samples: Vec<MotionSample>) -> Result<(DriveReport, Vec<MotionSample>), String> {
    use reach::drive::DriveError;
    let request = |samples| DriveRequest { motion: DriveMotion::Samples(samples), program: None };
    match reach::jobs::drive::drive(robot, &request(samples.clone())) {
        Ok(report) => Ok((report, samples)),
        Err(reach::Error::Drive(
            DriveError::RateLimit { suggested, duration, .. }
            | DriveError::AccelerationLimit { suggested, duration, .. },
        )) if duration > 0.0 => {
            let scale = suggested / duration * 1.01;
            let t0 = samples.first().map_or(0.0, |s| s.t_s);
            let slowed: Vec<MotionSample> =
                samples.into_iter().map(|s| MotionSample { t_s: t0 + (s.t_s - t0) * scale, ..s }).collect();
            Ok((drive(robot, DriveMotion::Samples(slowed.clone()))?, slowed))
        }
        Err(e) => Err(reach::one_line(&e.to_string())),
    }
}

/// Refuses a schedule that does not start where the arm is (more than one step away),
/// naming the first such joint and both values.
///
/// # Errors
/// The refusal message.
pub fn require_start(robot: &Robot, axes: &[Axis], timeline: &Timeline, steps: &[i64]) -> Result<(), String> {
    for (i, (start, now)) in timeline.start_steps().iter().zip(steps).enumerate() {
        if (start - now).abs() > 1 {
            let joint = &robot.joints()[i];
            let shown = |s: i64| number_text(from_si(joint.kind, axes[i].joint_value(s), AngleUnit::Deg));
            let unit = unit_name(joint.kind, AngleUnit::Deg);
            return Err(format!(
                "the job starts with joint {} `{}` at {} {unit}, but the arm is at {} {unit} (step {now}); \
                 submit a job that starts where the arm is (GET /state)",
                i + 1,
                joint.name,
                shown(*start),
                shown(*now)
            ));
        }
    }
    Ok(())
}

/// With a scene: proves every straight joint-space piece the motors follow (the drive's
/// piecewise-linear interpolation of the samples) clear of it with the library's swept check.
///
/// # Errors
/// The first piece not proven clear, with the check's words.
pub fn require_clear(robot: &Robot, scene: &Scene, motion: &DriveMotion) -> Result<(), String> {
    let DriveMotion::Samples(samples) = motion else {
        return Err("a plan job cannot be proven clear of the service's scene; submit its motions as move jobs".into());
    };
    let si = samples_si(robot, samples, "motion").map_err(|e| e.to_string())?;
    // Timed from the first sample (the service's scene has no moving obstacles: it refuses
    // them; the times keep the check the library's one for timed motions).
    let times = motion_times(&si, "motion").map_err(|e| e.to_string())?;
    let q: Vec<Vec<f64>> = si.into_iter().map(|s| s.q).collect();
    match SweptPathReport::check(robot, scene, &q, Some(&times)).map_err(|e| e.to_string())? {
        Some(p) if !p.swept.clear => {
            // Segment k (1-based) runs from sample k to sample k + 1.
            let (a, b) = (&samples[p.segment - 1], &samples[p.segment]);
            Err(format!(
                "the motion is not proven clear of the scene between t = {:.3} s and {:.3} s: {}",
                a.t_s,
                b.t_s,
                p.swept.pair_text.unwrap_or_default()
            ))
        }
        _ => Ok(()),
    }
}
