use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::{DriveError, StepSchedule};
use crate::Robot;
use crate::motion::JointSample;

/// A schedule integrated back into joint angles and compared with its plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Verification {
    /// Largest |simulated − planned| per joint over all samples, SI (radians or metres).
    pub max_deviation: Vec<f64>,
    /// The same in motor steps.
    pub max_deviation_steps: Vec<f64>,
    /// Time of each joint's largest deviation, s.
    pub worst_time: Vec<f64>,
    /// Largest tool-point distance between simulated and planned poses, metres.
    pub tool_position_error: f64,
    /// Largest tool-orientation difference (rotation angle), radians.
    pub tool_orientation_error: f64,
    /// Largest deviation at the last sample per joint, SI: the quantisation error of the end point.
    pub end_deviation: Vec<f64>,
    /// Whether every joint stayed within one step of the plan at every sample.
    pub within_one_step: bool,
}

/// The joint values (SI) the motors hold at each time in `times`: each step counter
/// integrated up to that instant (steps at exactly the instant included) and converted back
/// with [`super::Axis::joint_value`].
#[must_use]
pub fn simulate(schedule: &StepSchedule, times: &[f64]) -> Vec<Vec<f64>> {
    times.iter().map(|&t| schedule.joint_values_at(t)).collect()
}

/// Integrates `schedule` back into joint angles at every sample of `plan` and compares, in
/// joint space (per joint) and in tool space (forward kinematics of `robot`).
///
/// # Errors
/// [`DriveError::Trajectory`] when a sample's length differs from the schedule's joint count;
/// [`DriveError::Kinematics`] when forward kinematics rejects a sample.
pub fn verify(robot: &Robot, schedule: &StepSchedule, plan: &[JointSample]) -> Result<Verification, DriveError> {
    let n = schedule.joints.len();
    let mut v = Verification {
        max_deviation: vec![0.0; n],
        max_deviation_steps: vec![0.0; n],
        worst_time: vec![schedule.start_time; n],
        tool_position_error: 0.0,
        tool_orientation_error: 0.0,
        end_deviation: vec![0.0; n],
        within_one_step: true,
    };
    for (i, sample) in plan.iter().enumerate() {
        if sample.q.len() != n {
            return Err(DriveError::Trajectory(format!(
                "sample {i} has {} joint values, the schedule has {n} joints",
                sample.q.len()
            )));
        }
        let held = schedule.joint_values_at(sample.t);
        for (j, (joint, (&h, &p))) in schedule.joints.iter().zip(held.iter().zip(&sample.q)).enumerate() {
            let d = (h - p).abs();
            if d > v.max_deviation[j] {
                v.max_deviation[j] = d;
                v.max_deviation_steps[j] = d * joint.axis.steps_per_unit;
                v.worst_time[j] = sample.t;
            }
            if i + 1 == plan.len() {
                v.end_deviation[j] = d;
            }
        }
        let (a, b) = (robot.fk(&held)?, robot.fk(&sample.q)?);
        v.tool_position_error = v.tool_position_error.max((a.translation.vector - b.translation.vector).norm());
        v.tool_orientation_error = v.tool_orientation_error.max(a.rotation.angle_to(&b.rotation));
    }
    v.within_one_step = v.max_deviation_steps.iter().all(|&d| d <= 1.0 + crate::tolerance::DRIVE_LIMIT_SLACK);
    Ok(v)
}

/// How far the step grid moves a configuration: the joint values the motors can hold
/// nearest to `q`, and the errors that rounding to them causes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct GridError {
    /// The nearest joint values on the step grid, SI.
    pub snapped: Vec<f64>,
    /// `snapped − q` per joint, SI (at most half a step in size).
    pub joint_error: Vec<f64>,
    /// Distance between the tool points of `q` and `snapped`, metres.
    pub tool_position_error: f64,
    /// Rotation angle between the tool orientations, radians.
    pub tool_orientation_error: f64,
}

/// The quantisation error of configuration `q` (SI) on the motors' step grid, in joint space
/// and in tool space (forward kinematics of `robot`). Used for the end points of
/// point-to-point moves, which [`super::point_to_point`] snaps to the grid.
///
/// # Errors
/// [`DriveError::Trajectory`] when `q` and `axes` differ in length;
/// [`DriveError::Kinematics`] when forward kinematics rejects `q` (wrong length, NaN).
pub fn grid_error(robot: &Robot, axes: &[super::Axis], q: &[f64]) -> Result<GridError, DriveError> {
    if q.len() != axes.len() {
        return Err(DriveError::Trajectory(format!("{} joint values for {} axes", q.len(), axes.len())));
    }
    let snapped: Vec<f64> = axes.iter().zip(q).map(|(a, &v)| a.joint_value(a.quantise(v))).collect();
    let joint_error = snapped.iter().zip(q).map(|(s, v)| s - v).collect();
    let (a, b) = (robot.fk(q)?, robot.fk(&snapped)?);
    Ok(GridError {
        tool_position_error: (a.translation.vector - b.translation.vector).norm(),
        tool_orientation_error: a.rotation.angle_to(&b.rotation),
        snapped,
        joint_error,
    })
}
