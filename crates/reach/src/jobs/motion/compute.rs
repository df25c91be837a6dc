//! Computing one motion: joint space or tool space, limit reasons, J1/J2, energy.

use std::cell::RefCell;

use crate::effort::dynamics::{joint_rates, trajectory_energy_with_rates};
use crate::effort::{Differences, j1, j2, joint_weights};
use crate::error::{Error, Result};
use crate::jobs::input::{
    AngleUnit, from_si, joints_outside_limits, number_text, positive, q_display, rpy_deg, unit_name,
};
use crate::jobs::world::{SweptPathReport, parse_scene};
use crate::motion::joint_space::EndChoice;
use crate::motion::sample::PerSampleIk;
use crate::motion::tracking::{ConfigurationCriterion, TrackedPath, TrackingOptions, describe, track_with_progress};
use crate::motion::{JointMotion, JointRates, ToolMotion};
use crate::{Cancel, Robot};

use super::report::{MoveEffort, MoveEvent, MoveInterval, MoveReport, MoveSample};
use super::request::{End, MoveRequest, ProfileName, Space};

/// Relative slack on a joint's speed limit before a sample counts as too fast.
const SPEED_SLACK: f64 = 1e-9;

/// Computes one motion. Bad input is an error; infeasibility is in the report.
///
/// # Errors
/// [`Error::Request`] naming the field: wrong joint counts, non-finite or non-positive
/// `duration_s`/`speed_m_s`/`dt_s`, contradicting options (a speed in joint space, no duration
/// where one is needed, mixed ends in joint space), bad `joint_weights` or `choose`;
/// [`Error::Motion`] or [`Error::Tracking`] for unreachable end poses and the like.
pub fn move_motion(robot: &Robot, request: &MoveRequest) -> Result<MoveReport> {
    move_motion_with_progress(robot, request, &mut |_, _| {}, &Cancel::default())
}

/// [`move_motion`] that reports the tracking's progress of a tool-space motion as
/// `progress(samples done, samples in all)` (a joint-space motion reports nothing), and stops
/// a tool-space motion's tracking once `cancel` is set.
///
/// # Errors
/// As [`move_motion`]; [`Error::Tracking`] with [`crate::motion::tracking::TrackingError::Cancelled`] once `cancel`
/// is set.
pub fn move_motion_with_progress(
    robot: &Robot,
    request: &MoveRequest,
    progress: &mut dyn FnMut(usize, usize),
    cancel: &Cancel,
) -> Result<MoveReport> {
    if let Some(d) = positive("duration_s", request.duration_s)? {
        crate::motion::sample::check_duration("duration_s", d)?;
    }
    positive("speed_m_s", request.speed_m_s)?;
    positive("dt_s", request.dt_s)?;
    let scene = request.scene.as_deref().map(parse_scene).transpose()?;
    let weights = joint_weights(robot, request.joint_weights.as_deref())
        .map_err(|e| Error::request("joint_weights", e.to_string()))?;
    let computed = match request.space {
        Space::Joint => joint_space(robot, request)?,
        Space::Tool => tool_space(robot, request, progress, cancel)?,
    };
    let Computed { times, q, qd, intervals, events } = computed;
    let differences = Differences::for_robot(robot);
    let (j1v, j2v) = match (q.first(), q.last()) {
        (Some(a), Some(b)) => (j1(a, b, &weights, &differences)?, j2(&q, &weights, &differences)?),
        _ => (0.0, 0.0),
    };
    let (energy_j, energy_note) = match trajectory_energy_with_rates(robot, &times, &q, &qd) {
        Ok(e) => (Some(e), None),
        Err(e) => (None, Some(e.to_string())),
    };
    let mut samples = Vec::with_capacity(q.len());
    for ((t, qk), qdk) in times.iter().zip(&q).zip(&qd) {
        let pose = robot.fk(qk)?;
        samples.push(MoveSample {
            t_s: *t,
            q_deg: q_display(robot, qk),
            qd_deg_s: q_display(robot, qdk),
            xyz_m: pose.translation.vector.into(),
            rpy_deg: rpy_deg(&pose.rotation),
        });
    }
    let mut reasons: Vec<String> =
        intervals.iter().filter(|i| !i.feasible).flat_map(|i| i.reasons.iter().cloned()).collect();
    let swept = match &scene {
        Some(scene) => SweptPathReport::check(robot, scene, &q, Some(&times))?,
        None => None,
    };
    if let Some(s) = swept.as_ref().filter(|s| !s.swept.clear) {
        reasons.push(format!(
            "not proven clear of the scene: {} at t = {} s",
            s.swept.pair_text.as_deref().unwrap_or("-"),
            number_text(s.swept.t_s.unwrap_or(f64::NAN))
        ));
    }
    let feasible =
        intervals.iter().all(|i| i.feasible) && !samples.is_empty() && swept.as_ref().is_none_or(|s| s.swept.clear);
    Ok(MoveReport {
        name: request.name.clone(),
        robot: robot.name().to_string(),
        space: request.space,
        duration_s: times.last().copied().unwrap_or(0.0) - times.first().copied().unwrap_or(0.0),
        samples,
        intervals,
        events,
        effort: MoveEffort { j1: j1v, j2: j2v, energy_j, energy_note, weights },
        feasible,
        reasons,
        swept,
    })
}

/// A sampled motion before it is reported (SI units).
struct Computed {
    times: Vec<f64>,
    q: Vec<Vec<f64>>,
    qd: Vec<Vec<f64>>,
    intervals: Vec<MoveInterval>,
    events: Vec<MoveEvent>,
}

/// `x` with `decimals` decimals, without a sign on a value that rounds to zero.
fn fixed(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') { s[1..].to_string() } else { s }
}

fn joint_space(robot: &Robot, request: &MoveRequest) -> Result<Computed> {
    if request.speed_m_s.is_some() {
        return Err(Error::request("speed_m_s", "a tool speed needs a tool-space move; give a duration"));
    }
    if request.choose.is_some() {
        return Err(Error::request("choose", "a joint-space move has no configuration to choose; use tool space"));
    }
    if !request.choices.is_empty() {
        return Err(Error::request("choices", "a joint-space move has no configuration to choose; use tool space"));
    }
    let profile = request.profile.unwrap_or(ProfileName::Cycloidal).profile()?;
    let motion = match (&request.from, &request.to) {
        (End::Joints(a), End::Joints(b)) => {
            let (q0, q1) = (a.si(robot, "from")?, b.si(robot, "to")?);
            match request.duration_s {
                Some(d) => JointMotion::for_robot(robot, &q0, &q1, 0.0, d, profile)?,
                None => {
                    let rates = JointRates::from_robot(robot, None).map_err(|e| {
                        Error::request("duration_s", format!("needed: the robot has no speed limits to go by ({e})"))
                    })?;
                    JointMotion::synchronised(robot, &q0, &q1, 0.0, &rates, profile)?.0
                }
            }
        }
        (End::Pose(a), End::Pose(b)) => {
            let d = request
                .duration_s
                .ok_or_else(|| Error::request("duration_s", "a joint-space move between poses needs a duration"))?;
            let (start, end) = (a.isometry("from.pose")?, b.isometry("to.pose")?);
            JointMotion::between_poses(robot, &start, &end, 0.0, d, profile, &EndChoice::default())?
        }
        _ => return Err(Error::request("to", "give both ends as joint values or both as poses in joint space")),
    };
    let dt = request.dt_s.unwrap_or(motion.duration() / 100.0);
    let traj = motion.sample(dt)?;
    let times = traj.times();
    let q: Vec<Vec<f64>> = traj.samples.iter().map(|s| s.q.clone()).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|t| motion.velocity(*t)).collect();
    let reasons = limit_reasons(robot, &times, &q, &qd);
    let interval = MoveInterval {
        start_s: motion.t0(),
        end_s: motion.t1(),
        configuration: Some("joint".into()),
        feasible: reasons.is_empty(),
        reasons,
        decision: None,
        alternatives: Vec::new(),
    };
    Ok(Computed { times, q, qd, intervals: vec![interval], events: Vec::new() })
}

/// One kind of limit check: its name, whether sample `k` passes, and the limit as text.
type LimitCheck<'a> = (&'a str, &'a dyn Fn(usize) -> bool, String);

/// Stretches of samples where a joint is outside its range or above its speed limit, in
/// degrees (metres) as operators read them.
fn limit_reasons(robot: &Robot, times: &[f64], q: &[Vec<f64>], qd: &[Vec<f64>]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, joint) in robot.joints().iter().enumerate() {
        let unit = unit_name(joint.kind, AngleUnit::Deg);
        let shown = |v: f64| from_si(joint.kind, v, AngleUnit::Deg);
        let position = |k: usize| !joints_outside_limits(robot, &q[k]).contains(&(i + 1));
        let speed = |k: usize| joint.max_velocity.is_none_or(|m| qd[k][i].abs() <= m * (1.0 + SPEED_SLACK));
        let checks: [LimitCheck<'_>; 2] = [
            (
                "position",
                &position,
                format!(
                    "outside {} .. {} {unit}",
                    fixed(shown(joint.limits.lower), 3),
                    fixed(shown(joint.limits.upper), 3)
                ),
            ),
            ("speed", &speed, format!("above {} {unit}/s", joint.max_velocity.map_or(0.0, shown))),
        ];
        for (what, ok, text) in checks {
            let mut k = 0;
            while k < times.len() {
                if ok(k) {
                    k += 1;
                    continue;
                }
                let start = k;
                while k < times.len() && !ok(k) {
                    k += 1;
                }
                out.push(format!(
                    "joint {} ({}) {what} {text} from t = {} s to t = {} s",
                    i + 1,
                    joint.name,
                    fixed(times[start], 3),
                    fixed(times[k - 1], 3)
                ));
            }
        }
    }
    out
}

fn tool_space(
    robot: &Robot,
    request: &MoveRequest,
    progress: &mut dyn FnMut(usize, usize),
    cancel: &Cancel,
) -> Result<Computed> {
    let (start, end) = (request.from.pose(robot, "from")?, request.to.pose(robot, "to")?);
    let motion = match (request.duration_s, request.speed_m_s) {
        (Some(d), None) => {
            ToolMotion::new(start, end, 0.0, d, request.profile.unwrap_or(ProfileName::Cycloidal).profile()?)?
        }
        (None, Some(v)) => {
            let length = (end.translation.vector - start.translation.vector).norm();
            if length <= 0.0 {
                return Err(Error::request("speed_m_s", "the tool point does not move; give a duration"));
            }
            ToolMotion::new(start, end, 0.0, length / v, request.profile.unwrap_or(ProfileName::Linear).profile()?)?
        }
        (Some(_), Some(_)) => return Err(Error::request("speed_m_s", "give a duration or a speed, not both")),
        (None, None) => return Err(Error::request("duration_s", "a tool-space move needs a duration or a speed")),
    };
    let dt = request.dt_s.unwrap_or(motion.duration() / 100.0);
    let path = motion.sample_time(dt)?;
    let tracked = TrackedPath::sampled(&path.samples)?;
    let chooser = request.choose.as_ref().map(|c| c.chooser(robot, request.joint_weights.as_deref())).transpose()?;
    let criterion = chooser.as_ref().map(|c| c as &dyn ConfigurationCriterion);
    let progress = RefCell::new(progress);
    let choices = request.choices.iter().map(|c| (c.interval, c.configuration.clone())).collect();
    // A move from joint values starts there, on their branch (not the same pose on another).
    let start = match &request.from {
        End::Joints(q) => Some(q.si(robot, "from.joints")?),
        End::Pose(_) => None,
    };
    let options =
        TrackingOptions { cancel: cancel.clone(), choices, start: start.clone(), ..TrackingOptions::default() };
    let report = track_with_progress(robot, &tracked, &options, criterion, &|done, total| {
        (progress.borrow_mut())(done, total);
    })?;
    // Samples: the realised trajectory when every interval is realised; otherwise the per-sample
    // IK nearest to the previous sample with the limits ignored (so that J1/J2 and the curves
    // are still reported next to the reasons), or the realised part when even that fails.
    let fallback = if report.feasible {
        None
    } else {
        path.to_joints(robot, &PerSampleIk { allow_outside_limits: true, start, ..PerSampleIk::default() }).ok()
    };
    let (times, q): (Vec<f64>, Vec<Vec<f64>>) = match fallback {
        Some(traj) => (traj.times(), traj.samples.into_iter().map(|s| s.q).collect()),
        None => {
            (report.trajectory.iter().map(|p| p.t).collect(), report.trajectory.iter().map(|p| p.q.clone()).collect())
        }
    };
    // The one rate estimator (`effort::dynamics::joint_rates`: the robot's joint-difference rule,
    // uneven steps), also behind the energy.
    let qd = joint_rates(robot, &times, &q)?.0;
    let intervals = report
        .intervals
        .iter()
        .map(|iv| {
            let mut reasons = Vec::new();
            if !iv.reachable {
                reasons.push(format!(
                    "outside the workspace from t = {} s to t = {} s",
                    fixed(iv.t_start, 3),
                    fixed(iv.t_end, 3)
                ));
            }
            for (c, track) in iv.configurations.iter().enumerate() {
                for v in &track.violations {
                    let kind = v.joint.map(|j| robot.joints()[j - 1].kind);
                    let joint = v.joint.map_or_else(|| "branch lost".to_string(), |j| format!("joint {j} ({})", v.name));
                    let unit = kind.map_or("", |k| unit_name(k, AngleUnit::Deg));
                    let shown = |x: f64| kind.map_or(x, |k| from_si(k, x, AngleUnit::Deg));
                    reasons.push(format!(
                        "configuration {c} ({}): {joint} {} limit {} .. {} {unit} broken (worst {}) from t = {} s to t = {} s",
                        report.configurations.get(c).map(ToString::to_string).unwrap_or_default(),
                        format!("{:?}", v.kind).to_lowercase(),
                        fixed(shown(v.lower), 3),
                        fixed(shown(v.upper), 3),
                        fixed(shown(v.worst), 3),
                        fixed(v.t_start, 3),
                        fixed(v.t_end, 3)
                    ));
                }
            }
            MoveInterval {
                start_s: iv.t_start,
                end_s: iv.t_end,
                configuration: iv.chosen.and_then(|c| report.configurations.get(c)).map(ToString::to_string),
                feasible: iv.chosen.is_some(),
                reasons,
                decision: Some(iv.decision),
                alternatives: iv
                    .configurations
                    .iter()
                    .enumerate()
                    .filter(|(_, t)| t.feasible)
                    .filter_map(|(c, _)| report.configurations.get(c).map(ToString::to_string))
                    .collect(),
            }
        })
        .collect();
    let degrees = request.angle_unit() == AngleUnit::Deg;
    let events = report
        .events
        .iter()
        .map(|e| MoveEvent {
            t_s: e.t,
            code: e.code.as_str().into(),
            message: describe(e, robot, degrees),
            detail: e.detail.clone(),
        })
        .collect();
    Ok(Computed { times, q, qd, intervals, events })
}
