//! The `model` workflow: a robot's parsed model in SI units (`reach robot show --json`), and
//! the list of presets (`reach robots --json`). What a viewer or a Python user reads to know
//! the arm.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::matrix_rows;
use crate::Robot;
use crate::error::Result;
use crate::model::{Convention, Joint, JointGeometry, JointKind, Limits, presets};

/// Ask for the model of the job's robot (no parameters).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ModelRequest {}

/// A robot model in SI units (metres, radians, rad/s or m/s); matrices row-major.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ModelReport {
    /// Robot name.
    pub name: String,
    /// One-line description.
    pub description: String,
    /// `dh`, `mdh` or `urdf`.
    pub convention: Convention,
    /// Number of joints.
    pub dof: usize,
    /// The joints, base to tip.
    pub joints: Vec<ModelJoint>,
    /// Base transform (world ← first frame), row-major.
    pub base: [[f64; 4]; 4],
    /// Tool transform (last frame ← tool point), row-major.
    pub tool: [[f64; 4]; 4],
}

/// One joint of a [`ModelReport`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ModelJoint {
    /// Joint name.
    pub name: String,
    /// `revolute` or `prismatic`.
    pub kind: JointKind,
    /// DH parameters or URDF origin and axis.
    #[serde(flatten)]
    pub geometry: ModelGeometry,
    /// `[lower, upper]` (rad or m; `null` for an infinite bound), or `null` when unlimited.
    pub limits: Option<[Option<f64>; 2]>,
    /// Speed limit, rad/s or m/s, or `null`.
    pub max_velocity: Option<f64>,
    /// Acceleration limit, rad/s² or m/s², or `null`.
    pub max_acceleration: Option<f64>,
    /// Jerk limit, rad/s³ or m/s³, or `null`.
    pub max_jerk: Option<f64>,
    /// Home position, rad or m.
    pub home: f64,
    /// Whether the joint direction is reversed.
    pub flip: bool,
}

/// Joint geometry of a [`ModelJoint`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(untagged)]
pub enum ModelGeometry {
    /// DH or MDH parameters.
    Dh {
        /// Link length, metres.
        a_m: f64,
        /// Link twist, radians.
        alpha_rad: f64,
        /// Link offset, metres.
        d_m: f64,
        /// Joint angle offset, radians.
        theta_offset_rad: f64,
    },
    /// URDF origin and axis.
    Axis {
        /// Joint frame in the previous joint frame, row-major.
        origin: [[f64; 4]; 4],
        /// Unit axis in the joint frame.
        axis: [f64; 3],
    },
}

/// One preset robot (`reach robots --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PresetEntry {
    /// Preset name.
    pub name: String,
    /// Number of joints.
    pub dof: usize,
    /// `dh`, `mdh` or `urdf`.
    pub convention: Convention,
    /// One-line description.
    pub description: String,
}

/// Limits as JSON: `null` when unlimited, else `[lower, upper]` with `null` for an infinite
/// bound (JSON has no infinity).
#[must_use]
pub fn limits_json(limits: &Limits) -> Option<[Option<f64>; 2]> {
    let bound = |v: f64| v.is_finite().then_some(v);
    if limits.lower.is_finite() || limits.upper.is_finite() {
        Some([bound(limits.lower), bound(limits.upper)])
    } else {
        None
    }
}

impl ModelJoint {
    /// The report of `joint`.
    #[must_use]
    pub fn of(joint: &Joint) -> Self {
        let geometry = match &joint.geometry {
            JointGeometry::Dh(p) => {
                ModelGeometry::Dh { a_m: p.a, alpha_rad: p.alpha, d_m: p.d, theta_offset_rad: p.theta_offset }
            }
            JointGeometry::Axis { origin, axis } => {
                ModelGeometry::Axis { origin: matrix_rows(origin), axis: [axis.x, axis.y, axis.z] }
            }
        };
        ModelJoint {
            name: joint.name.clone(),
            kind: joint.kind,
            geometry,
            limits: limits_json(&joint.limits),
            max_velocity: joint.max_velocity,
            max_acceleration: joint.max_acceleration,
            max_jerk: joint.max_jerk,
            home: joint.home,
            flip: joint.flip,
        }
    }
}

/// The model of `robot`.
///
/// # Errors
/// None today; the signature matches every other workflow.
pub fn model(robot: &Robot, _request: &ModelRequest) -> Result<ModelReport> {
    Ok(ModelReport {
        name: robot.name().to_string(),
        description: robot.description().to_string(),
        convention: robot.convention(),
        dof: robot.dof(),
        joints: robot.joints().iter().map(ModelJoint::of).collect(),
        base: matrix_rows(robot.base()),
        tool: matrix_rows(robot.tool()),
    })
}

/// Every preset robot, in [`presets::names`] order.
///
/// # Errors
/// [`crate::Error::Model`] if a preset does not parse (a bug, caught by the tests).
pub fn preset_list() -> Result<Vec<PresetEntry>> {
    presets::names()
        .into_iter()
        .map(|name| {
            let robot = presets::get(name)?;
            Ok(PresetEntry {
                name: name.to_string(),
                dof: robot.dof(),
                convention: robot.convention(),
                description: robot.description().to_string(),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_json_uses_null_for_infinite_bounds() {
        assert_eq!(limits_json(&Limits::UNLIMITED), None);
        assert_eq!(limits_json(&Limits::new(-1.0, 2.0)), Some([Some(-1.0), Some(2.0)]));
        assert_eq!(limits_json(&Limits::new(f64::NEG_INFINITY, 2.0)), Some([None, Some(2.0)]));
    }

    #[test]
    fn every_preset_is_listed_with_its_model() {
        let list = preset_list().unwrap();
        assert_eq!(list.len(), presets::names().len());
        for entry in list {
            let robot = presets::get(&entry.name).unwrap();
            let m = model(&robot, &ModelRequest {}).unwrap();
            assert_eq!((m.dof, m.convention, m.joints.len()), (entry.dof, entry.convention, robot.dof()));
        }
    }
}
