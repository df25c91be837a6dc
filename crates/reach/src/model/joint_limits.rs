//! MoveIt's `joint_limits.yaml`: per-joint velocity, acceleration and jerk limits (URDF has
//! only velocity limits; MoveIt configurations keep the others in this file).
//!
//! ```yaml
//! joint_limits:
//!   panda_joint1:
//!     has_velocity_limits: true
//!     max_velocity: 2.175          # rad/s (m/s for prismatic joints)
//!     has_acceleration_limits: true
//!     max_acceleration: 15.0       # rad/s²
//!     has_jerk_limits: true
//!     max_jerk: 7500.0             # rad/s³
//! ```
//!
//! A limit applies when its `has_*_limits` is `true` (then its `max_*` is required); position
//! limits and MoveIt's scaling factors are not read. Joints of the file the robot does not
//! have (a gripper's, in a configuration for the whole arm) are passed over.

use std::collections::BTreeMap;

use serde::Deserialize;

use super::{ModelError, Robot, RobotSpec};

#[derive(Deserialize)]
struct LimitsFile {
    joint_limits: BTreeMap<String, JointLimitsField>,
}

#[derive(Deserialize)]
struct JointLimitsField {
    #[serde(default)]
    has_velocity_limits: bool,
    max_velocity: Option<f64>,
    #[serde(default)]
    has_acceleration_limits: bool,
    max_acceleration: Option<f64>,
    #[serde(default)]
    has_jerk_limits: bool,
    max_jerk: Option<f64>,
}

impl Robot {
    /// This robot with the velocity, acceleration and jerk limits of a MoveIt
    /// `joint_limits.yaml` — `joint_limits: {NAME: {has_velocity_limits, max_velocity,
    /// has_acceleration_limits, max_acceleration, has_jerk_limits, max_jerk}}`, SI units (rad
    /// or m per s, s², s³) — matched by joint name; a limit applies when its `has_*_limits` is
    /// `true`, limits the file does not give are kept, and joints the robot does not have are
    /// passed over. Position limits and scaling factors are not read.
    ///
    /// # Errors
    /// [`ModelError::JointLimits`] for YAML that does not follow the format (with its line), or
    /// a `has_*_limits: true` without its `max_*`; [`ModelError::Joint`] /
    /// [`ModelError::VelocityLimit`] naming the joint for a limit that is not a finite number
    /// > 0.
    pub fn with_moveit_joint_limits(&self, text: &str) -> Result<Robot, ModelError> {
        let file: LimitsFile = serde_norway::from_str(text).map_err(|e| ModelError::JointLimits(e.to_string()))?;
        let mut spec: RobotSpec = self.spec().clone();
        for joint in &mut spec.joints {
            let Some(limits) = file.joint_limits.get(&joint.name) else { continue };
            let need = |has: bool, value: Option<f64>, field: &str| -> Result<Option<f64>, ModelError> {
                match (has, value) {
                    (false, _) => Ok(None),
                    (true, Some(v)) => Ok(Some(v)),
                    (true, None) => Err(ModelError::JointLimits(format!(
                        "joint `{}`: has_{field}_limits is true but max_{field} is missing",
                        joint.name
                    ))),
                }
            };
            if let Some(v) = need(limits.has_velocity_limits, limits.max_velocity, "velocity")? {
                joint.max_velocity = Some(v);
            }
            if let Some(v) = need(limits.has_acceleration_limits, limits.max_acceleration, "acceleration")? {
                joint.max_acceleration = Some(v);
            }
            if let Some(v) = need(limits.has_jerk_limits, limits.max_jerk, "jerk")? {
                joint.max_jerk = Some(v);
            }
        }
        Robot::new(spec)
    }
}
