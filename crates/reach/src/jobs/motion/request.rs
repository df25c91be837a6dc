//! The request of one motion: its ends, where it is interpolated, its time law and sampling,
//! and the optional configuration choice of tool-space intervals.

use std::collections::BTreeMap;

use nalgebra::Isometry3;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::Robot;
use crate::decide::motion_criteria::Requirement;
use crate::decide::{Method, MotionCriterion, TrackChooser};
use crate::error::{Error, Result};
use crate::jobs::input::{AngleUnit, Joints, Pose};
use crate::motion::Profile;

/// Where a motion is interpolated.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Space {
    /// `q(t) = q0 + λ(τ)·(q1 − q0)`.
    #[default]
    Joint,
    /// Straight tool line, rotation about one fixed axis, IK per sample.
    Tool,
}

impl Space {
    /// `joint` or `tool`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Space::Joint => "joint",
            Space::Tool => "tool",
        }
    }
}

/// The time law λ(τ).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum ProfileName {
    /// Seed 001's λ = τ − sin(2πτ)/(2π).
    Cycloidal,
    /// Trapezoidal velocity (a third of the time accelerating, a third decelerating).
    Trapezoid,
    /// Quintic: zero velocity and acceleration at both ends.
    Quintic,
    /// Constant speed.
    Linear,
}

impl ProfileName {
    /// `cycloidal`, `trapezoid`, `quintic` or `linear`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            ProfileName::Cycloidal => "cycloidal",
            ProfileName::Trapezoid => "trapezoid",
            ProfileName::Quintic => "quintic",
            ProfileName::Linear => "linear",
        }
    }

    /// The time law.
    ///
    /// # Errors
    /// None in practice (the trapezoid's fixed third is valid); a [`crate::motion::MotionError`] would
    /// be passed on.
    pub fn profile(self) -> Result<Profile> {
        Ok(match self {
            ProfileName::Cycloidal => Profile::Cycloidal,
            ProfileName::Quintic => Profile::Quintic,
            ProfileName::Linear => Profile::Linear,
            ProfileName::Trapezoid => Profile::trapezoidal(1.0 / 3.0)?,
        })
    }
}

/// One end of a motion: joint values, or a tool pose.
///
/// JSON: `{"joints": {"deg": [0, -90, 90, 0, 90, 0]}}` or
/// `{"pose": {"xyz_m": [0.4, 0.1, 0.3], "rpy_deg": [180, 0, 0]}}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
#[allow(
    clippy::large_enum_variant,
    reason = "a request is built once per job; boxing would only complicate its construction"
)]
pub enum End {
    /// Joint values.
    Joints(Joints),
    /// A full tool pose (position and orientation).
    Pose(Pose),
}

impl End {
    /// The tool pose of this end: the pose itself, or forward kinematics of the joints.
    ///
    /// # Errors
    /// [`Error::Request`] naming `field` for bad joint values or pose.
    pub fn pose(&self, robot: &Robot, field: &str) -> Result<Isometry3<f64>> {
        match self {
            End::Pose(p) => p.isometry(&format!("{field}.pose")),
            End::Joints(q) => Ok(robot.fk(&q.si(robot, &format!("{field}.joints"))?)?),
        }
    }

    /// The angle unit this end is typed in: its joints' unit, `rad` for a pose given by
    /// `rpy_rad`, `deg` for one given by `rpy_deg`; `None` otherwise (quaternion, matrix).
    #[must_use]
    pub fn angle_unit(&self) -> Option<AngleUnit> {
        match self {
            End::Joints(q) => Some(q.unit()),
            End::Pose(p) if p.rpy_rad.is_some() => Some(AngleUnit::Rad),
            End::Pose(p) if p.rpy_deg.is_some() => Some(AngleUnit::Deg),
            End::Pose(_) => None,
        }
    }
}

/// One motion (`reach move`; a task file's `[[motion]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MoveRequest {
    /// A label for the report (task files name their motions; empty by default).
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub name: String,
    /// Start.
    pub from: End,
    /// Target.
    pub to: End,
    /// Joint space (default) or tool space.
    #[serde(default)]
    pub space: Space,
    /// Time law (default cycloidal; linear in tool space with `speed_m_s`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileName>,
    /// Duration in seconds, > 0. Joint space between joint vectors without it: the fastest
    /// synchronised move within the robot's speed limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Tool speed in m/s, > 0 (tool space only, instead of `duration_s`): duration = path
    /// length / speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_m_s: Option<f64>,
    /// Sampling step in seconds, > 0 (default duration / 100).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt_s: Option<f64>,
    /// Joint weights of J1/J2, one per joint, ≥ 0 (default seed 001's for 6 joints, else 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_weights: Option<Vec<f64>>,
    /// Tool space: rank the feasible configurations of each path interval by motion criteria.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choose: Option<ChoiceSpec>,
    /// The text of a scene file (TOML: obstacles, tool zone, touching policy). The motion is
    /// checked continuously against it — the piecewise-linear joint path through its samples,
    /// the path a drive schedule follows ([`crate::jobs::world::SweptPathReport`]); a motion
    /// not proven clear is infeasible.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// Tool space: the operator's choice of configuration for named intervals (seed 003's
    /// dialogue); each must be feasible in its interval. Intervals not named are chosen as
    /// usual (`choose`, else the default configuration).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub choices: Vec<IntervalChoice>,
}

/// The configuration an operator chose for one interval of a tool-space move.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IntervalChoice {
    /// The interval, 1-based (the paper's `P_t`; the report's `intervals` in order).
    pub interval: usize,
    /// The configuration's label, as the report names it (`configuration`, `alternatives`).
    pub configuration: String,
}

impl MoveRequest {
    /// The angle unit of the request, the one its report's texts (events) use: that of the
    /// `from` end, else of the `to` end ([`End::angle_unit`]), else degrees.
    #[must_use]
    pub fn angle_unit(&self) -> AngleUnit {
        self.from.angle_unit().or_else(|| self.to.angle_unit()).unwrap_or_default()
    }

    /// A joint-space motion between two joint vectors, every option at its default.
    #[must_use]
    pub fn joints(from: Joints, to: Joints) -> Self {
        MoveRequest {
            name: String::new(),
            from: End::Joints(from),
            to: End::Joints(to),
            space: Space::Joint,
            profile: None,
            duration_s: None,
            speed_m_s: None,
            dt_s: None,
            joint_weights: None,
            choose: None,
            scene: None,
            choices: Vec::new(),
        }
    }
}

/// How the configuration of each tool-space interval is chosen (a task file's `[choose]`,
/// `reach move --choose`; docs/choosing.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ChoiceSpec {
    /// `topsis`, `vikor` or `weighted-sum`.
    pub method: String,
    /// Motion criterion names (`j1`, `j2`, `duration`, `peak_velocity`, `peak_acceleration`,
    /// `limits`, `manipulability`, `sigma_min`, `stiffness`, `accuracy`, `path_length`, …;
    /// docs/choosing.md).
    pub criteria: Vec<String>,
    /// One weight per criterion, ≥ 0, not all 0 (default equal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
    /// Hard bounds `criterion = bound` on listed criteria (a maximum for less-is-better, a
    /// minimum for more-is-better ones): a configuration breaking one does not satisfy the
    /// choice; when none does, the default is realised (K14).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub require: BTreeMap<String, f64>,
}

impl ChoiceSpec {
    /// The chooser for `robot` (J1/J2 criteria use the motion's `joint_weights`).
    ///
    /// # Errors
    /// [`Error::Request`] naming `choose.method`, `choose.criteria`, `choose.weights` or
    /// `choose.require`.
    pub fn chooser<'r>(&self, robot: &'r Robot, joint_weights: Option<&[f64]>) -> Result<TrackChooser<'r>> {
        let method = Method::parse(&self.method).ok_or_else(|| {
            Error::request("choose.method", format!("unknown `{}` (known: topsis, vikor, weighted-sum)", self.method))
        })?;
        let criteria = self
            .criteria
            .iter()
            .map(|n| MotionCriterion::parse(n, robot, joint_weights, None))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| Error::request("choose.criteria", e.to_string()))?;
        let weights = self.weights.clone().unwrap_or_else(|| vec![1.0; criteria.len()]);
        let mut requirements = Vec::with_capacity(self.require.len());
        for (name, &bound) in &self.require {
            let key = name.replace('-', "_");
            let Some(criterion) = criteria.iter().position(|c| c.describe().name == key) else {
                return Err(Error::request(
                    "choose.require",
                    format!("`{name}` is not one of the criteria ({})", self.criteria.join(", ")),
                ));
            };
            requirements.push(Requirement { criterion, bound });
        }
        TrackChooser::new(robot, criteria, weights, method)
            .map_err(|e| Error::request("choose.weights", e.to_string()))?
            .with_requirements(requirements)
            .map_err(|e| Error::request("choose.require", e.to_string()))
    }
}
