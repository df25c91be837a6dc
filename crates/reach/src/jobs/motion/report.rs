//! The reports of `move` (one motion) and `plan` (every motion of a task file).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::request::Space;
use crate::jobs::world::SweptPathReport;
use crate::motion::tracking::{Decision, EventDetail};

/// One sample of a motion (what `reach drive` reads: `t_s`, `q_deg`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MoveSample {
    /// Time, seconds.
    pub t_s: f64,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint rates: revolute joints in degrees/s, prismatic joints in m/s.
    pub qd_deg_s: Vec<f64>,
    /// Tool position, metres.
    pub xyz_m: [f64; 3],
    /// Tool orientation: roll, pitch, yaw in degrees, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub rpy_deg: [f64; 3],
}

impl From<&MoveSample> for crate::jobs::input::MotionSample {
    /// The sample as a request gives it (`t_s`, `q_deg`), e.g. to drive a planned motion.
    fn from(s: &MoveSample) -> Self {
        crate::jobs::input::MotionSample { t_s: s.t_s, q_deg: s.q_deg.clone() }
    }
}

/// One interval of a motion (joint space: the whole motion; tool space: between singular
/// positions and workspace boundaries).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MoveInterval {
    /// Start time, seconds.
    pub start_s: f64,
    /// End time, seconds.
    pub end_s: f64,
    /// Configuration realised (`joint` for a joint-space move, a branch label in tool space,
    /// `null` when none is feasible).
    pub configuration: Option<String>,
    /// Whether the interval is realised within every limit.
    pub feasible: bool,
    /// Every limit broken (by any configuration tracked), with where, in degrees (metres).
    pub reasons: Vec<String>,
    /// How the configuration was chosen (tool space only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub decision: Option<Decision>,
    /// Tool space: every configuration feasible in the interval (labels, the realised one
    /// among them) — what an operator may choose from (the request's `choices`).
    #[serde(default)]
    pub alternatives: Vec<String>,
}

/// One event of the tracking log (tool space).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MoveEvent {
    /// Time, seconds.
    pub t_s: f64,
    /// `K1` … `K14`.
    pub code: String,
    /// The text, angles in the request's unit ([`MoveRequest::angle_unit`](super::MoveRequest::angle_unit)).
    pub message: String,
    /// What the event says as data: SI units and radians, 0-based joint indices, path
    /// parameters `s` as the tool point's arc length from the start, metres.
    pub detail: EventDetail,
}

/// Effort functionals of a motion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MoveEffort {
    /// `Σ wᵢ|Δᵢ(q(t0), q(t1))|` (radians; metres for prismatic joints), `Δ` the robot's joint
    /// difference (literal for bounded joints).
    pub j1: f64,
    /// `Σ wᵢ·(total variation of qᵢ over the samples)`, same differences.
    pub j2: f64,
    /// Mechanical energy `∫ Σ|τᵢ·q̇ᵢ| dt`, joules (rigid links, no friction); `null` when it
    /// cannot be computed (see `energy_note`).
    pub energy_j: Option<f64>,
    /// Why `energy_j` is `null` (e.g. no link masses in the robot file); `null` otherwise.
    pub energy_note: Option<String>,
    /// The joint weights used.
    pub weights: Vec<f64>,
}

/// One motion (`reach move --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MoveReport {
    /// The request's label (empty on the command line).
    pub name: String,
    /// Robot name.
    pub robot: String,
    /// `joint` or `tool`.
    pub space: Space,
    /// Duration, seconds.
    pub duration_s: f64,
    /// The samples.
    pub samples: Vec<MoveSample>,
    /// Per-interval status.
    pub intervals: Vec<MoveInterval>,
    /// Event log (tool space: K1–K14).
    pub events: Vec<MoveEvent>,
    /// J1, J2, energy.
    pub effort: MoveEffort,
    /// Whether the whole motion respects every limit (and, with a scene, is proven clear).
    pub feasible: bool,
    /// Why not, one line each.
    pub reasons: Vec<String>,
    /// With a scene: the swept (continuous) check of the motion, segment `k` running from
    /// sample `k` to sample `k + 1` (1-based).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swept: Option<SweptPathReport>,
}

/// Every motion of a task file (`reach plan --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PlanReport {
    /// Robot name.
    pub robot: String,
    /// The task's description.
    pub description: String,
    /// One report per `[[motion]]`, in order.
    pub motions: Vec<MoveReport>,
}

impl PlanReport {
    /// Whether every motion is feasible.
    #[must_use]
    pub fn feasible(&self) -> bool {
        self.motions.iter().all(|m| m.feasible)
    }
}
