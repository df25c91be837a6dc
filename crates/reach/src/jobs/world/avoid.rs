//! The `avoid` workflow: seed 000's planar detour around point obstacles, optionally planning
//! both sides of the obstacle and ranking them.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::Robot;
use crate::decide::Method;
use crate::decide::detour_choice::{DetourCriterion, DetourRanking, choose_detour};
use crate::error::{Error, Result};
use crate::ik::planar::PlanarRedundant;
use crate::jobs::input::{Joints, number_text, q_display, require_within_limits};
use crate::jobs::world::finite;
use crate::jobs::world::sense::{SenseReport, SenseRequest};
use crate::world::detour::{
    Closest, DetourOptions, DetourOutcome, DetourPlan, P2, SweepTest, WaypointRule, plan_detour,
};

/// The thesis's IK scan step, degrees.
const DEFAULT_STEP_DEG: f64 = 0.01;

fn default_step_deg() -> f64 {
    DEFAULT_STEP_DEG
}

/// A move of a planar three-link arm (`planar3`) to a gripper position, around point
/// obstacles. Give exactly one of `start` and `from_xy_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AvoidRequest {
    /// Start joint values `q1, q2, q3`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<Joints>,
    /// Current gripper position `x, y` in metres instead of `start`: the start configuration
    /// is the thesis's minimum-change choice from the home pose.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from_xy_m: Option<[f64; 2]>,
    /// Target gripper position `x, y`, metres.
    pub to_xy_m: [f64; 2],
    /// Point obstacles `x, y`, metres.
    #[serde(default)]
    pub obstacles_xy_m: Vec<[f64; 2]>,
    /// Range readings instead of `obstacles_xy_m`: the obstacle they locate, grown into a disc
    /// of its uncertainty radius (`sense.report`'s `uncertainty_m`), is detoured; an ambiguous
    /// geometry is refused.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sense: Option<SenseRequest>,
    /// IK scan step, degrees (thesis: 0.01), > 0.
    #[serde(default = "default_step_deg")]
    pub step_deg: f64,
    /// Use the thesis's literal obstacle test (k < 1, fixed order) instead of the robust one.
    #[serde(default)]
    pub literal_test: bool,
    /// Use the printed waypoint formulas (Table 6) instead of the perpendicular construction.
    #[serde(default)]
    pub printed_waypoints: bool,
    /// Plan both sides of the obstacle and rank the ones that succeed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choose: Option<AvoidChoice>,
}

/// How the two sides of the obstacle are ranked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AvoidChoice {
    /// `topsis`, `vikor` or `weighted-sum`.
    pub method: String,
    /// Criteria from `s` (Σ S of the legs, less), `clearance` (more), `path_length` (gripper
    /// polyline, less); default all three.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub criteria: Option<Vec<String>>,
    /// One weight per criterion (default equal).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
}

/// One side of the obstacle (`choose`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct AvoidSide {
    /// `base_side`, `far_side` (or `direct`).
    pub side: String,
    /// What the planner decided for this side.
    pub outcome: DetourOutcome,
    /// Criterion values in the order of `criteria` (empty when the side failed).
    pub values: Vec<f64>,
    /// The method's score when two sides were ranked.
    pub score: Option<f64>,
    /// Whether this side is the plan reported.
    pub chosen: bool,
}

/// The planned move (`reach avoid --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct AvoidReport {
    /// Robot name.
    pub robot: String,
    /// What the planner decided.
    pub outcome: DetourOutcome,
    /// Whether the direct move was blocked.
    pub blocked: bool,
    /// Start configuration, degrees.
    pub start_deg: [f64; 3],
    /// Gripper waypoints after the start, metres: `[K1]` (direct) or `[K2, K3, K1]`.
    pub waypoints_m: Vec<[f64; 2]>,
    /// Joint values at each reached waypoint, degrees.
    pub configurations_deg: Vec<[f64; 3]>,
    /// Total joint change `S` of each leg, degrees.
    pub leg_s_deg: Vec<f64>,
    /// Smallest clearance of the arm to an obstacle over the motion, metres.
    pub min_clearance_m: Option<f64>,
    /// Where the arm comes closest to an obstacle (leg, fraction of the leg's motion, link,
    /// obstacle), with the certified lower bound of the clearance over every leg; `null`
    /// without obstacles.
    pub closest: Option<Closest>,
    /// With `choose`: the criteria ranked.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub criteria: Option<Vec<String>>,
    /// With `choose`: every side planned.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sides: Option<Vec<AvoidSide>>,
    /// With `sense`: the located obstacle; the clearances above are to its disc of radius
    /// `uncertainty_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensed: Option<SenseReport>,
}

impl AvoidReport {
    /// Whether the move failed: target unreachable or no detour (exit status 3 of the CLI).
    #[must_use]
    pub fn failed(&self) -> bool {
        !matches!(self.outcome, DetourOutcome::Direct | DetourOutcome::Detour { .. })
    }
}

/// The report with what a drawing of the detour needs.
#[derive(Debug, Clone)]
pub struct AvoidRun {
    /// The report.
    pub report: AvoidReport,
    /// The arm.
    pub arm: PlanarRedundant,
    /// Start configuration, radians.
    pub start: [f64; 3],
    /// The plan reported (the chosen side with `choose`).
    pub plan: DetourPlan,
    /// The obstacles, metres.
    pub obstacles: Vec<P2>,
    /// Radius of the waypoint circle, metres.
    pub circle_radius_m: f64,
    /// Radius the obstacles are grown by (a sensed obstacle's uncertainty), metres.
    pub obstacle_radius_m: f64,
}

/// Plans the move (see [`avoid_run`]).
///
/// # Errors
/// As [`avoid_run`].
pub fn avoid(robot: &Robot, request: &AvoidRequest) -> Result<AvoidReport> {
    Ok(avoid_run(robot, request)?.report)
}

/// Plans the move: the direct move or a detour, or both sides ranked with `choose`. An
/// unreachable target or a missing detour is an answer ([`AvoidReport::failed`]), not an error.
///
/// # Errors
/// [`Error::Ik`] for a robot that is not a planar three-link arm; [`Error::Request`] for
/// non-finite positions, a step that is not > 0, both or neither of `start` and `from_xy_m`,
/// a `from_xy_m` outside the workspace, an unknown method or criterion, `choose` with
/// `printed_waypoints`, `sense` with `obstacles_xy_m` or `literal_test`, readings that are
/// invalid or ambiguous (see [`SenseRequest::locate`]); [`Error::Decide`] for bad weights.
pub fn avoid_run(robot: &Robot, request: &AvoidRequest) -> Result<AvoidRun> {
    let arm = PlanarRedundant::from_robot(robot)?;
    if !(request.step_deg.is_finite() && request.step_deg > 0.0) {
        return Err(Error::request("step_deg", format!("must be positive, got {}", request.step_deg)));
    }
    finite("to_xy_m", &request.to_xy_m)?;
    for (i, o) in request.obstacles_xy_m.iter().enumerate() {
        finite(&format!("obstacles_xy_m[{}]", i + 1), o)?;
    }
    let step = request.step_deg.to_radians();
    let (start, start_deg) = match (&request.start, request.from_xy_m) {
        (Some(q), None) => {
            let si = q.si(robot, "start")?;
            require_within_limits(robot, &si, q.unit(), "start")?;
            let display = q.display(robot);
            ([si[0], si[1], si[2]], [display[0], display[1], display[2]])
        }
        (None, Some(k)) => {
            finite("from_xy_m", &k)?;
            let home = robot.home();
            let options = DetourOptions { step, ..DetourOptions::default() };
            let plan = plan_detour(&arm, &[home[0], home[1], home[2]], k, &[], &options)?;
            let q = *plan.configurations.first().ok_or_else(|| {
                Error::request("from_xy_m", format!("({}, {}) m is outside the workspace", k[0], k[1]))
            })?;
            let d = q_display(robot, &q);
            (q, [d[0], d[1], d[2]])
        }
        _ => return Err(Error::request("start", "give exactly one of `start` and `from_xy_m`")),
    };
    let (obstacles, sensed) = sensed_obstacles(robot, request)?;
    let options = DetourOptions {
        step,
        sweep_test: if request.literal_test { SweepTest::PaperLiteral } else { SweepTest::Robust },
        waypoints: if request.printed_waypoints { WaypointRule::PaperPrinted } else { WaypointRule::Perpendicular },
        obstacle_radius: sensed.as_ref().and_then(|s| s.uncertainty_m).unwrap_or(0.0),
        ..DetourOptions::default()
    };
    let target = request.to_xy_m;
    let (plan, sides, criteria) = match &request.choose {
        None => (plan_detour(&arm, &start, target, &obstacles, &options)?, None, None),
        Some(choice) => {
            if request.printed_waypoints {
                return Err(Error::request(
                    "choose",
                    "ranks the two perpendicular detours; it cannot be combined with `printed_waypoints`",
                ));
            }
            let (sides, names, plan) = choose(&arm, &start, target, &obstacles, &options, choice)?;
            (plan, Some(sides), Some(names))
        }
    };
    let deg3 = |q: &[f64; 3]| q.map(f64::to_degrees);
    let report = AvoidReport {
        robot: robot.name().to_string(),
        outcome: plan.outcome,
        blocked: plan.blocked,
        start_deg,
        waypoints_m: plan.waypoints.clone(),
        configurations_deg: plan.configurations.iter().map(deg3).collect(),
        leg_s_deg: plan.leg_s.iter().map(|s| s.to_degrees()).collect(),
        min_clearance_m: plan.min_clearance,
        closest: plan.closest,
        criteria,
        sides,
        sensed,
    };
    let obstacle_radius_m = options.obstacle_radius;
    let circle_radius_m = options.circle_radius(&arm) + obstacle_radius_m;
    Ok(AvoidRun { report, arm, start, plan, obstacles, circle_radius_m, obstacle_radius_m })
}

/// The obstacles to detour: the request's points, or the one its readings locate.
fn sensed_obstacles(robot: &Robot, request: &AvoidRequest) -> Result<(Vec<P2>, Option<SenseReport>)> {
    let Some(sense) = &request.sense else { return Ok((request.obstacles_xy_m.clone(), None)) };
    if !request.obstacles_xy_m.is_empty() {
        return Err(Error::request("sense", "give either `obstacles_xy_m` or `sense` readings, not both"));
    }
    if request.literal_test {
        return Err(Error::request(
            "sense",
            "a sensed obstacle is a disc (its uncertainty); the literal test takes points only",
        ));
    }
    let report = SenseReport::of(robot, &sense.locate()?);
    if report.ambiguous {
        let at = |p: &[f64; 2]| format!("({}, {})", number_text(p[0]), number_text(p[1]));
        let why = match &report.alternatives_m[..] {
            [] => "the sensors are nearly in line with the obstacle".to_string(),
            others => format!(
                "{} and {} m fit the readings",
                at(&report.obstacle_m),
                others.iter().map(at).collect::<Vec<_>>().join(", ")
            ),
        };
        return Err(Error::request(
            "sense",
            format!("the readings do not locate the obstacle unambiguously: {why}; add a sensor or narrow the cones"),
        ));
    }
    Ok((vec![report.obstacle_m], Some(report)))
}

/// Plans both sides, ranks them; returns the sides, the criterion names and the plan shown
/// (the chosen side, or the first when none succeeds).
fn choose(
    arm: &PlanarRedundant,
    start: &[f64; 3],
    target: P2,
    obstacles: &[P2],
    options: &DetourOptions,
    choice: &AvoidChoice,
) -> Result<(Vec<AvoidSide>, Vec<String>, DetourPlan)> {
    let method = Method::parse(&choice.method).ok_or_else(|| {
        Error::request(
            "choose.method",
            format!("unknown method `{}` (known: topsis, vikor, weighted-sum)", choice.method),
        )
    })?;
    let names: Vec<String> = choice
        .criteria
        .clone()
        .unwrap_or_else(|| ["s", "clearance", "path_length"].iter().map(|s| (*s).to_string()).collect());
    let criteria = names
        .iter()
        .map(|n| {
            DetourCriterion::parse(n).ok_or_else(|| {
                Error::request("choose.criteria", format!("unknown criterion `{n}` (known: s, clearance, path_length)"))
            })
        })
        .collect::<Result<Vec<_>>>()?;
    let weights = choice.weights.clone().unwrap_or_else(|| vec![1.0; criteria.len()]);
    finite("choose.weights", &weights)?;
    let ranking = DetourRanking { criteria: &criteria, weights: &weights, method };
    let result = choose_detour(arm, start, target, obstacles, options, &ranking)?;
    let score = |i: usize| {
        let r = result.ranking.as_ref()?;
        let row = result.successful.iter().position(|&k| k == i)?;
        r.candidate(row).map(|c| c.score)
    };
    let sides = result
        .candidates
        .iter()
        .enumerate()
        .map(|(i, c)| AvoidSide {
            side: c.side.to_string(),
            outcome: c.plan.outcome,
            values: c.values.clone(),
            score: score(i),
            chosen: result.chosen == Some(i),
        })
        .collect();
    let shown = result.chosen.unwrap_or(0);
    Ok((sides, names, result.candidates[shown].plan.clone()))
}
