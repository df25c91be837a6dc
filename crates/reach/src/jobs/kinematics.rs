//! The `fk` and `jacobian` workflows: the tool pose, every frame, the Jacobian and its
//! measures at one configuration.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::{Joints, PoseReport, dense_rows, joints_outside_limits, matrix_rows};
use crate::Robot;
use crate::error::Result;
use crate::kinematics::{JacobianAxes, Manipulability};

/// Forward kinematics at one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FkRequest {
    /// The joint values.
    pub q: Joints,
}

/// The tool pose and every joint frame (`reach fk --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FkReport {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint values in SI: radians, metres.
    pub q_si: Vec<f64>,
    /// 1-based numbers of the joints outside their limits (FK is computed regardless).
    pub outside_limits: Vec<usize>,
    /// Tool pose in the world frame.
    pub pose: PoseReport,
    /// Every link frame in the world frame (one per joint, see `Robot::frames`), row-major.
    pub frames: Vec<[[f64; 4]; 4]>,
}

/// Runs forward kinematics.
///
/// # Errors
/// [`crate::Error::Request`] for a wrong joint count or a non-finite value (field `q`).
pub fn fk(robot: &Robot, request: &FkRequest) -> Result<FkReport> {
    let q = request.q.si(robot, "q")?;
    let pose = robot.fk(&q)?;
    let frames = robot.frames(&q)?;
    Ok(FkReport {
        robot: robot.name().to_string(),
        q_deg: request.q.display(robot),
        outside_limits: joints_outside_limits(robot, &q),
        pose: PoseReport::of(&pose),
        frames: frames.iter().map(|f| matrix_rows(&nalgebra::convert(*f))).collect(),
        q_si: q,
    })
}

/// The Jacobian at one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct JacobianRequest {
    /// The joint values.
    pub q: Joints,
}

/// Row labels of the geometric Jacobian.
pub const JACOBIAN_ROWS: [&str; 6] = ["vx", "vy", "vz", "wx", "wy", "wz"];

/// The Jacobian and its measures (`reach jacobian --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct JacobianReport {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint values in SI: radians, metres.
    pub q_si: Vec<f64>,
    /// 1-based numbers of the joints outside their limits.
    pub outside_limits: Vec<usize>,
    /// Row labels, `vx vy vz wx wy wz`.
    pub rows: Vec<String>,
    /// The 6×n geometric Jacobian, row-major (world frame, tool point, SI units).
    pub jacobian: Vec<Vec<f64>>,
    /// Yoshikawa's measure, the product of the singular values.
    pub manipulability: f64,
    /// Smallest singular value.
    pub sigma_min: f64,
    /// Largest singular value.
    pub sigma_max: f64,
    /// `sigma_max / sigma_min`, `null` at a singularity (infinite).
    pub condition: Option<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// Largest possible rank, `min(6, n)`.
    pub max_rank: usize,
    /// Singular values, largest first.
    pub singular_values: Vec<f64>,
}

/// Computes the Jacobian and its measures.
///
/// # Errors
/// [`crate::Error::Request`] for a wrong joint count or a non-finite value (field `q`).
pub fn jacobian(robot: &Robot, request: &JacobianRequest) -> Result<JacobianReport> {
    let q = request.q.si(robot, "q")?;
    let jac = robot.jacobian(&q)?;
    let m = Manipulability::of(&jac, JacobianAxes::All);
    Ok(JacobianReport {
        robot: robot.name().to_string(),
        q_deg: request.q.display(robot),
        outside_limits: joints_outside_limits(robot, &q),
        q_si: q,
        rows: JACOBIAN_ROWS.iter().map(|s| (*s).to_string()).collect(),
        jacobian: dense_rows(&jac),
        manipulability: m.yoshikawa,
        sigma_min: m.sigma_min,
        sigma_max: m.sigma_max,
        condition: m.condition.is_finite().then_some(m.condition),
        rank: m.rank,
        max_rank: robot.dof().min(6),
        singular_values: m.singular_values,
    })
}
