//! The `drive` workflow: stepper step schedules for a sampled motion, a task file or a
//! synchronised point-to-point move, checked against the plan, with an optional program text
//! (CSV step list, coil table, step/direction events, G-code).
//!
//! Every joint value the motors are asked to reach is checked against the joint's position
//! limits, and every interval of the plan against the joint's speed limit (`max_velocity`,
//! where the robot gives one): a motion that breaks them is refused before any schedule or
//! program is made.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::{
    AngleUnit, Joints, MotionSample, from_si, number_text, require_within_limits, samples_si, unit_name,
};
use super::motion::{PlanRequest, plan};
use crate::Robot;
use crate::drive::output::{GcodeDialect, StepRow, coil_table_csv, gcode, step_dir_text, step_rows, to_csv};
use crate::drive::{
    DriveError, GridError, Step, StepSchedule, Verification, axes, grid_error, point_to_point, schedule_trajectory,
    verify,
};
use crate::error::{Error, Result};
use crate::model::JointKind;
use crate::motion::JointSample;

/// Drive a motion with the robot's stepper motors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DriveRequest {
    /// The motion.
    pub motion: DriveMotion,
    /// A program text to make besides the step list (`null`: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<DriveProgram>,
}

/// What to drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DriveMotion {
    /// A sampled motion: `reach move --json`'s `samples` (other fields are ignored); see
    /// [`super::input::parse_motion_json`].
    Samples(Vec<MotionSample>),
    /// The text of a task file (TOML, `reach plan` format): its motions are planned and driven
    /// one after the other; each must start where the previous one ended.
    Task(String),
    /// A synchronised point-to-point move.
    PointToPoint(PointToPointRequest),
}

/// A synchronised point-to-point move: all motors start and stop together.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointToPointRequest {
    /// Start joint values.
    pub from: Joints,
    /// Target joint values.
    pub to: Joints,
    /// Duration, seconds (`null`: the shortest the motors allow).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
}

/// A program text made from the schedule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DriveProgram {
    /// One line per step: `t_s,joint,name,dir,index,position,coils`.
    Csv,
    /// Coil line states a1 b1 a2 b2 after every step.
    Coils,
    /// Step/direction events (microseconds).
    Events,
    /// G-code for GRBL or Marlin (axes X Y Z A B C in joint degrees or millimetres).
    Gcode(GcodeDialect),
}

/// Where the driven motion came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum DriveMotionKind {
    /// A sampled motion.
    Samples,
    /// A task file.
    Task,
    /// A point-to-point move.
    PointToPoint,
}

/// One joint's motor in the schedule.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DriveJointReport {
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// Revolute or prismatic.
    pub joint_kind: JointKind,
    /// Steps per radian (revolute) or per metre (prismatic).
    pub steps_per_unit: f64,
    /// Step counter at the start.
    pub start_position: i64,
    /// Step counter at the end.
    pub end_position: i64,
    /// Number of steps.
    pub steps: usize,
    /// Highest step rate between consecutive steps, Hz.
    pub max_rate_hz: f64,
    /// The motor's maximum step rate, Hz.
    pub max_step_rate_hz: f64,
    /// Largest deviation of the motor from the plan, steps.
    pub max_deviation_steps: f64,
    /// The same in SI (radians or metres).
    pub max_deviation_si: f64,
}

/// A step schedule and its check (`reach drive --format json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct DriveReport {
    /// Robot name.
    pub robot: String,
    /// Where the motion came from.
    pub motion: DriveMotionKind,
    /// Start of the schedule, seconds.
    pub start_s: f64,
    /// Its duration, seconds.
    pub duration_s: f64,
    /// One entry per joint, base to tip.
    pub joints: Vec<DriveJointReport>,
    /// The schedule integrated back into joint values and compared with the plan.
    pub check: Verification,
    /// Point-to-point only: how rounding the target to whole steps moves the tool.
    pub target_grid_error: Option<GridError>,
    /// Every step of every joint, in time order.
    pub steps: Vec<StepRow>,
    /// The program text asked for (`null` when none was).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program: Option<String>,
}

/// How far (rad or m) a task's motion may start from where the previous one ended.
const JOIN_TOLERANCE: f64 = 1e-6;

/// Runs the drive workflow.
///
/// # Errors
/// [`Error::Request`] for a joint value outside its limits (field `motion`, `from`, `to`), a
/// wrong joint count or a task whose motions do not join; [`Error::Motion`] for a motion
/// longer than [`crate::motion::sample::MAX_DURATION_S`] (one day); [`Error::Drive`] for missing drive
/// data, an infeasible task motion, or a motion beyond the motors' rate, acceleration or
/// step-count limits; [`Error::File`] for a bad task file.
pub fn drive(robot: &Robot, request: &DriveRequest) -> Result<DriveReport> {
    let axes = axes(robot)?;
    let unit = match &request.motion {
        DriveMotion::PointToPoint(p) => p.from.unit(),
        DriveMotion::Samples(_) | DriveMotion::Task(_) => AngleUnit::Deg,
    };
    let (kind, schedule, plan_samples, target_grid_error) = match &request.motion {
        DriveMotion::Samples(samples) => {
            let samples = samples_si(robot, samples, "motion")?;
            (DriveMotionKind::Samples, schedule_trajectory(&axes, &samples)?, samples, None)
        }
        DriveMotion::Task(text) => {
            let samples = task_samples(robot, text)?;
            (DriveMotionKind::Task, schedule_trajectory(&axes, &samples)?, samples, None)
        }
        DriveMotion::PointToPoint(p) => {
            let from = p.from.si(robot, "from")?;
            let to = p.to.si(robot, "to")?;
            require_within_limits(robot, &from, p.from.unit(), "from")?;
            require_within_limits(robot, &to, p.to.unit(), "to")?;
            let p2p = point_to_point(&axes, &from, &to, p.duration_s, 0.0)?;
            let grid = grid_error(robot, &axes, &to)?;
            // One plan sample per 20 ms, at least 10 and at most 2000 intervals.
            let segments = ((p2p.duration / 0.02).ceil() as usize).clamp(10, 2000);
            let samples = p2p.samples(robot, segments);
            (DriveMotionKind::PointToPoint, p2p.schedule, samples, Some(grid))
        }
    };
    let field = if kind == DriveMotionKind::PointToPoint { "duration_s" } else { "motion" };
    crate::motion::sample::check_duration(field, schedule.end_time - schedule.start_time)?;
    require_within_speed(robot, &plan_samples, unit)?;
    let check = verify(robot, &schedule, &plan_samples)?;
    let program = match request.program {
        None => None,
        Some(DriveProgram::Csv) => Some(to_csv(&schedule)),
        Some(DriveProgram::Coils) => Some(coil_table_csv(&schedule)?),
        Some(DriveProgram::Events) => Some(step_dir_text(&schedule)),
        Some(DriveProgram::Gcode(dialect)) => {
            let times: Vec<f64> = plan_samples.iter().map(|s| s.t).collect();
            if schedule.end_time <= schedule.start_time {
                return Err(Error::request("program", "G-code needs a move that takes time"));
            }
            Some(gcode(&schedule, &times, dialect, robot.name())?)
        }
    };
    Ok(report(robot, kind, &schedule, check, target_grid_error, program))
}

/// Relative slack on joint speed limits (rounding of the sample times and values).
const SPEED_SLACK: f64 = 1e-9;

/// Refuses a plan in which a joint moves faster than its speed limit (`max_velocity`). The
/// motors follow the samples' piecewise-linear interpolation, so the speed of an interval is
/// exactly its joint difference over its duration.
fn require_within_speed(robot: &Robot, samples: &[JointSample], unit: AngleUnit) -> Result<()> {
    for (i, joint) in robot.joints().iter().enumerate() {
        let Some(limit) = joint.max_velocity else { continue };
        for w in samples.windows(2) {
            let dt = w[1].t - w[0].t;
            let speed = robot.joint_difference(i, w[0].q[i], w[1].q[i]).abs() / dt;
            if dt > 0.0 && speed > limit * (1.0 + SPEED_SLACK) {
                let shown = |v: f64| number_text(from_si(joint.kind, v, unit));
                let name = unit_name(joint.kind, unit);
                return Err(Error::request(
                    "motion",
                    format!(
                        "joint {} `{}` moves at {} {name}/s from t = {:.4} s, above its limit of {} {name}/s; \
                         make the motion slower",
                        i + 1,
                        joint.name,
                        shown(speed),
                        w[0].t,
                        shown(limit)
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Samples as typed (degrees, metres) in SI, checked for length, finiteness and limits.
/// Plans every motion of a task file and joins them into one trajectory: each motion starts
/// where the previous one ended, in time and in joint space.
fn task_samples(robot: &Robot, text: &str) -> Result<Vec<JointSample>> {
    let report = plan(robot, &PlanRequest { task: text.to_string(), scene: None })?;
    let mut samples: Vec<JointSample> = Vec::new();
    for m in &report.motions {
        if !m.feasible {
            return Err(DriveError::InfeasibleMotion {
                motion: m.name.clone(),
                reason: m.reasons.first().map_or_else(|| "see `reach plan`".to_string(), Clone::clone),
            }
            .into());
        }
        let field = format!("motion `{}`", m.name);
        let Some(first) = m.samples.first() else { continue };
        let offset = samples.last().map_or(0.0, |s| s.t) - first.t_s;
        let typed: Vec<MotionSample> =
            m.samples.iter().map(|s| MotionSample { t_s: offset + s.t_s, q_deg: s.q_deg.clone() }).collect();
        let mut motion = samples_si(robot, &typed, &field)?;
        if let (Some(last), Some(start)) = (samples.last(), motion.first()) {
            // The one joint-difference rule: what a joint-space move from `a` to `b` travels.
            let jump =
                (0..robot.dof()).position(|i| robot.joint_difference(i, last.q[i], start.q[i]).abs() > JOIN_TOLERANCE);
            if let Some(i) = jump {
                return Err(Error::request(
                    field,
                    format!(
                        "starts away from where the previous motion ended (joint {} `{}`); a drive cannot jump",
                        i + 1,
                        robot.joints()[i].name
                    ),
                ));
            }
            motion.remove(0); // the previous motion's last sample
        }
        samples.extend(motion);
    }
    Ok(samples)
}

/// Highest rate between consecutive steps, Hz.
fn max_rate(steps: &[Step]) -> f64 {
    steps.windows(2).map(|w| 1.0 / (w[1].t - w[0].t)).fold(0.0, f64::max)
}

fn report(
    robot: &Robot,
    motion: DriveMotionKind,
    schedule: &StepSchedule,
    check: Verification,
    target_grid_error: Option<GridError>,
    program: Option<String>,
) -> DriveReport {
    DriveReport {
        robot: robot.name().to_string(),
        motion,
        start_s: schedule.start_time,
        duration_s: schedule.end_time - schedule.start_time,
        joints: schedule
            .joints
            .iter()
            .enumerate()
            .map(|(i, j)| DriveJointReport {
                joint: j.axis.joint,
                name: j.axis.name.clone(),
                joint_kind: j.axis.kind,
                steps_per_unit: j.axis.steps_per_unit,
                start_position: j.start_position,
                end_position: j.end_position,
                steps: j.steps.len(),
                max_rate_hz: max_rate(&j.steps),
                max_step_rate_hz: j.axis.max_step_rate,
                max_deviation_steps: check.max_deviation_steps[i],
                max_deviation_si: check.max_deviation[i],
            })
            .collect(),
        check,
        target_grid_error,
        steps: step_rows(schedule),
        program,
    }
}
