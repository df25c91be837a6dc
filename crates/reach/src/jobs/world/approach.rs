//! The `approach` workflow: seed 004's motion synthesis next to forbidden zones
//! ([`crate::world::approach`]): joint increments to a goal that keep a safe distance from
//! the obstacles, redundancy in the null space of the task Jacobian, deadlocks handed over to
//! the planner, and optionally seed 004's fitted region as a fast first test.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::check::{SweptPathReport, swept_pair_text};
use super::parse_scene;
use super::timed::{clear_blend, motion_samples, optimal_motion};
use crate::error::{Error, Result};
use crate::ik::IkTarget;
use crate::jobs::input::{Joints, MotionSample, Pose, full_scale, positive, q_display, time_budget};
use crate::jobs::retime::{DEFAULT_BLEND_TOLERANCE, request_error};
use crate::motion::{PathLimits, check_blend_tolerance};
use crate::world::approach::{
    ApproachGoal, ApproachOptions, ApproachStats, FastRegion, MAX_SAMPLES, Outcome, approach as synthesise, grown_robot,
};
use crate::world::planner::{PlanOptions, plan};
use crate::world::{CollisionChecker, SweptPair};
use crate::{Cancel, Robot};

fn default_safe_distance_m() -> f64 {
    ApproachOptions::default().safe_distance
}

fn default_max_step_deg() -> f64 {
    ApproachOptions::default().max_step.to_degrees()
}

fn default_tolerance_m() -> f64 {
    ApproachOptions::default().tolerance
}

fn default_max_samples() -> usize {
    ApproachOptions::default().max_samples
}

fn default_true() -> bool {
    true
}

fn default_time_budget_s() -> f64 {
    1.0
}

fn default_region_step_deg() -> f64 {
    15.0
}

fn default_band() -> f64 {
    2.0
}

/// A motion to a goal that keeps a safe distance from the scene's obstacles. Give exactly one
/// of `to` and `to_pose`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ApproachRequest {
    /// The text of the scene file (TOML: obstacles, tool zone, touching policy).
    pub scene: String,
    /// Start joint values (allowed, and at least the safe distance from every obstacle).
    pub from: Joints,
    /// Goal joint values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<Joints>,
    /// Goal tool pose, or tool position only (`xyz_m` without an orientation: the task of
    /// `varan4` and `planar3`, redundant arms for a position).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to_pose: Option<Pose>,
    /// Safe distance from every obstacle, metres (default 0.05), ≥ 0.
    #[serde(default = "default_safe_distance_m")]
    pub safe_distance_m: f64,
    /// Largest increment, joint-space norm in degrees (default 2.86 = 0.05 rad), > 0.
    #[serde(default = "default_max_step_deg")]
    pub max_step_deg: f64,
    /// Reached when the tool point is this close, metres (joint goal: every joint within
    /// this many radians); default 1e-4, > 0.
    #[serde(default = "default_tolerance_m")]
    pub tolerance_m: f64,
    /// Most samples, start included (default 3000, at most 100 000).
    #[serde(default = "default_max_samples")]
    pub max_samples: usize,
    /// On a deadlock, hand over to the planner (RRT-Connect from the deadlock configuration,
    /// links grown by the safe distance); default true.
    #[serde(default = "default_true")]
    pub handover: bool,
    /// Wall-time budget of the planner after a deadlock, seconds (default 1).
    #[serde(default = "default_time_budget_s")]
    pub planner_time_budget_s: f64,
    /// Fit seed 004's R-function region first and use it as a fast first test of the
    /// candidate increments.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fast_region: Option<FastRegionRequest>,
    /// How the motion is timed (default: `optimal` when every joint has a velocity and an
    /// acceleration limit, its own or its stepper drive's; else `none`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timing: Option<ApproachTiming>,
    /// Optimal timing: multiplies every joint's velocity limit, in (0, 1] (default 1).
    #[serde(default = "full_scale")]
    pub max_velocity_scale: f64,
    /// Optimal timing: multiplies every joint's acceleration limit, in (0, 1] (default 1).
    #[serde(default = "full_scale")]
    pub max_acceleration_scale: f64,
    /// Optimal timing: how far (joint-space Euclidean distance, rad and m) the timed motion may
    /// pass from each sample, cutting the corners with parabolic blends (default
    /// [`DEFAULT_BLEND_TOLERANCE`]; 0 rests at every sample). A blend not proven to keep the
    /// safe distance is tightened (halved, at most [`super::timed::BLEND_TIGHTENINGS`] times,
    /// then 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend_tolerance: Option<f64>,
}

/// How an approach motion is timed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ApproachTiming {
    /// Time-optimal (TOPP-RA) along the samples — and after a handover the planner's
    /// waypoints — with their corners blended, under every joint's velocity and acceleration
    /// limits (its own, or its stepper drive's) times their scales, proven within them between
    /// samples; the blended path is proven to keep the safe distance.
    Optimal,
    /// Not timed: the samples only (a robot without velocity or acceleration limits).
    #[default]
    None,
}

impl ApproachRequest {
    /// A request from `from` in `scene` with every default and no goal (set `to` or
    /// `to_pose`).
    #[must_use]
    pub fn new(scene: String, from: Joints) -> Self {
        ApproachRequest {
            scene,
            from,
            to: None,
            to_pose: None,
            safe_distance_m: default_safe_distance_m(),
            max_step_deg: default_max_step_deg(),
            tolerance_m: default_tolerance_m(),
            max_samples: default_max_samples(),
            handover: true,
            planner_time_budget_s: default_time_budget_s(),
            fast_region: None,
            timing: None,
            max_velocity_scale: 1.0,
            max_acceleration_scale: 1.0,
            blend_tolerance: None,
        }
    }
}

/// The fitted region used as a fast first test.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FastRegionRequest {
    /// The three 1-based joints that are the region's coordinates (default: the last three);
    /// the other joints are held at their `from` values in the fitting grid.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joints: Option<[usize; 3]>,
    /// Step of the fitting grid, degrees (default 15).
    #[serde(default = "default_region_step_deg")]
    pub step_deg: f64,
    /// A candidate is dropped when `F_Λ < −band` (the region's units, degrees; default 2).
    #[serde(default = "default_band")]
    pub band: f64,
}

impl Default for FastRegionRequest {
    fn default() -> Self {
        FastRegionRequest { joints: None, step_deg: default_region_step_deg(), band: default_band() }
    }
}

/// The planner's attempt after a deadlock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct HandoverReport {
    /// Whether the planner found a path from the deadlock configuration to the goal.
    pub found: bool,
    /// Configurations the fitted region (`fast_region`) rejected before the exact check.
    pub first_test_rejections: usize,
    /// Why not.
    pub reason: Option<String>,
    /// Its waypoints (joined by straight edges proven to keep the safe distance), degrees.
    pub waypoints_deg: Vec<Vec<f64>>,
}

/// The synthesised motion (`reach approach --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ApproachReport {
    /// Robot name.
    pub robot: String,
    /// `reached`, `deadlock` (the goal direction and the barrier oppose: handed over to the
    /// planner) or `unreachable` (the goal violates the limits or the safe distance, or has no
    /// IK solution that keeps it).
    pub outcome: Outcome,
    /// Why, when not reached.
    pub reason: Option<String>,
    /// Number of configurations of the motion, start included.
    pub samples: usize,
    /// The safe distance, metres.
    pub safe_distance_m: f64,
    /// Certified lower bound, over the whole motion (between the samples too), of the margin
    /// beyond the safe distance: obstacle clearance minus the safe distance, the tool point's
    /// depth inside its zone, the gap of non-adjacent links minus twice the safe distance.
    /// Positive for every motion reported; `null` without a motion.
    pub min_margin_m: Option<f64>,
    /// What that margin measures, in words (`null` without a motion).
    pub closest: Option<String>,
    /// The same as data.
    pub closest_pair: Option<SweptPair>,
    /// Tool-point distance to the goal at the end, metres (pose goals).
    pub position_error_m: Option<f64>,
    /// Orientation error at the end, degrees (pose goals with an orientation).
    pub orientation_error_deg: Option<f64>,
    /// Largest joint error at the end, degrees (prismatic: metres) (joint goals).
    pub joint_error_deg: Option<f64>,
    /// The motion, start first (revolute degrees, prismatic metres).
    pub motion_deg: Vec<Vec<f64>>,
    /// Candidate tests: candidates, dropped by the fitted region, exact swept checks.
    pub stats: ApproachStats,
    /// After a deadlock with `handover`: the planner's attempt.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub handover: Option<HandoverReport>,
    /// How the motion is timed.
    #[serde(default)]
    pub timing: ApproachTiming,
    /// Duration of the timed motion — the samples, then the planner's waypoints when it found
    /// a path — s (`null` untimed or without a motion).
    #[serde(default)]
    pub duration_s: Option<f64>,
    /// The velocity limits' scale (1 untimed).
    #[serde(default = "full_scale")]
    pub max_velocity_scale: f64,
    /// The acceleration limits' scale (1 untimed).
    #[serde(default = "full_scale")]
    pub max_acceleration_scale: f64,
    /// The blend tolerance of the timed motion (rad and m; the requested one, or tighter when
    /// a blend was not proven to keep the safe distance; 0: resting at every sample); `null`
    /// untimed.
    #[serde(default)]
    pub blend_tolerance: Option<f64>,
    /// Per joint, the exact largest `|q̇| / limit` over the timed motion (≤ 1); `null`
    /// untimed.
    #[serde(default)]
    pub worst_velocity_ratio: Option<Vec<f64>>,
    /// Per joint, the exact largest `|q̈| / limit` (≤ 1); `null` untimed.
    #[serde(default)]
    pub worst_acceleration_ratio: Option<Vec<f64>>,
    /// Whether the timed (blended) motion is proven to keep the safe distance (`null`
    /// untimed or without a motion).
    #[serde(default)]
    pub collision_free: Option<bool>,
    /// The swept check of the timed motion's path with every link grown by the safe distance
    /// (its clearances are margins beyond the safe distance; `segment` numbers the lines and
    /// blend arcs in order); `null` untimed, without a motion, or with nothing to check.
    #[serde(default)]
    pub swept: Option<SweptPathReport>,
}

impl ApproachReport {
    /// Whether the goal was not reached by the synthesis (exit status 3 of the CLI).
    #[must_use]
    pub fn failed(&self) -> bool {
        self.outcome != Outcome::Reached
    }

    /// Whether the motion ends at the goal: reached by the synthesis, or after a deadlock by
    /// the planner's path.
    #[must_use]
    pub fn arrives(&self) -> bool {
        !self.failed() || self.handover.as_ref().is_some_and(|h| h.found)
    }

    /// The timed motion ([`ApproachReport::motion_deg`], then the planner's waypoints when it
    /// found a path, with the report's blend and scales) sampled every `dt_s` seconds (and at
    /// the end), as a drive follows it; empty without a motion.
    ///
    /// # Errors
    /// [`Error::Request`] naming `timing` for an untimed report, bad samples, or a `dt_s` that
    /// is not positive or gives too many samples.
    pub fn motion(&self, robot: &Robot, dt_s: f64) -> Result<Vec<MotionSample>> {
        if self.timing != ApproachTiming::Optimal {
            return Err(Error::request(
                "timing",
                "the approach is not timed (give every joint max_velocity and max_acceleration, or a stepper drive \
                 with a ramp limit)",
            ));
        }
        let handover = self.handover.iter().filter(|h| h.found).flat_map(|h| h.waypoints_deg.iter().skip(1));
        let waypoints = self
            .motion_deg
            .iter()
            .chain(handover)
            .map(|w| Joints::Deg(w.clone()).si(robot, "motion_deg"))
            .collect::<Result<Vec<_>>>()?;
        if waypoints.len() < 2 {
            return Ok(Vec::new());
        }
        let tolerance = self.blend_tolerance.unwrap_or(0.0);
        let motion =
            optimal_motion(robot, &waypoints, tolerance, self.max_velocity_scale, self.max_acceleration_scale)?;
        motion_samples(robot, &motion, dt_s)
    }
}

/// Synthesises the motion (see [`approach_with_cancel`]).
///
/// # Errors
/// As [`approach_with_cancel`].
pub fn approach(robot: &Robot, request: &ApproachRequest) -> Result<ApproachReport> {
    approach_with_cancel(robot, request, &Cancel::default())
}

/// Synthesises the motion; after a deadlock (with `handover`) the planner takes over from the
/// deadlock configuration, stopping when `cancel` is set.
///
/// # Errors
/// [`Error::World`] for a malformed scene; [`Error::Request`] for bad joint values (`from`,
/// `to`), a bad pose, both or neither goal, a start closer than the safe distance, and
/// numbers out of range (`safe_distance_m`, `max_step_deg`, `tolerance_m`, `max_samples`,
/// `planner_time_budget_s`, `fast_region`).
pub fn approach_with_cancel(robot: &Robot, request: &ApproachRequest, cancel: &Cancel) -> Result<ApproachReport> {
    let scene = parse_scene(&request.scene)?;
    let (start, goal) = super::start_and_goal(robot, &request.from, request.to.as_ref(), request.to_pose.as_ref())?;
    let d = request.safe_distance_m;
    if !(d.is_finite() && d >= 0.0) {
        return Err(Error::request("safe_distance_m", format!("must be ≥ 0, got {d}")));
    }
    positive("max_step_deg", Some(request.max_step_deg))?;
    positive("tolerance_m", Some(request.tolerance_m))?;
    if !(2..=MAX_SAMPLES).contains(&request.max_samples) {
        return Err(Error::request(
            "max_samples",
            format!("must be between 2 and {MAX_SAMPLES}, got {}", request.max_samples),
        ));
    }
    let budget = time_budget("planner_time_budget_s", Some(request.planner_time_budget_s))?;
    let timing = request.timing.unwrap_or(if PathLimits::from_robot(robot, 1.0, 1.0).is_ok() {
        ApproachTiming::Optimal
    } else {
        ApproachTiming::None
    });
    match timing {
        // Bad limits or scales are refused before the synthesis.
        ApproachTiming::Optimal => {
            PathLimits::from_robot(robot, request.max_velocity_scale, request.max_acceleration_scale)
                .map_err(request_error)?;
            if let Some(tolerance) = request.blend_tolerance {
                check_blend_tolerance(tolerance).map_err(request_error)?;
            }
        }
        ApproachTiming::None => {
            for (field, given) in [
                ("max_velocity_scale", request.max_velocity_scale != 1.0),
                ("max_acceleration_scale", request.max_acceleration_scale != 1.0),
                ("blend_tolerance", request.blend_tolerance.is_some()),
            ] {
                if given {
                    return Err(Error::request(field, "applies to optimal timing only, and the approach is not timed"));
                }
            }
        }
    }
    let grown = grown_robot(robot, d)?;
    let verdict = CollisionChecker::try_new(&grown, &scene)?.check(&start)?;
    if !verdict.is_free() {
        return Err(Error::request(
            "from",
            format!("the start is not allowed with a safe distance of {d} m ({verdict:?})"),
        ));
    }
    let fast = request.fast_region.as_ref().map(|f| fast_region(robot, &scene, d, &start, f)).transpose()?;
    let options = ApproachOptions {
        safe_distance: d,
        max_step: request.max_step_deg.to_radians(),
        tolerance: request.tolerance_m,
        max_samples: request.max_samples,
        ..ApproachOptions::default()
    };
    let a = synthesise(robot, &scene, &start, &goal, &options, fast.as_ref())?;
    let moved = a.samples.len() > 1;
    let (position_error_m, orientation_error_deg, joint_error_deg) = match &goal {
        ApproachGoal::Joints(_) => (None, None, Some(joint_error(robot, &a.samples, &a.goals))),
        ApproachGoal::Target(IkTarget::Position(_)) => (Some(a.error), None, None),
        ApproachGoal::Target(IkTarget::Pose(_)) => (Some(a.error), Some(a.orientation_error.to_degrees()), None),
    };
    let mut planned: Vec<Vec<f64>> = Vec::new();
    let handover = if a.outcome == Outcome::Deadlock && request.handover {
        let from = a.samples.last().cloned().unwrap_or_else(|| start.clone());
        let target = goal.clone();
        let ik = crate::ik::IkOptions { cancel: cancel.clone(), ..crate::ik::IkOptions::default() };
        let options = PlanOptions { max_time: budget, ik, first_test: fast.clone(), ..PlanOptions::default() };
        Some(match plan(&grown, &scene, &from, &target, &options) {
            Ok(p) => {
                planned = p.waypoints;
                HandoverReport {
                    found: true,
                    first_test_rejections: p.stats.first_test_rejections,
                    reason: None,
                    waypoints_deg: planned.iter().map(|q| q_display(robot, q)).collect(),
                }
            }
            Err(e) => HandoverReport {
                found: false,
                first_test_rejections: 0,
                reason: Some(crate::one_line(&e.to_string())),
                waypoints_deg: vec![],
            },
        })
    } else {
        None
    };
    let mut report = ApproachReport {
        robot: robot.name().to_string(),
        outcome: a.outcome,
        reason: a.reason,
        samples: a.samples.len(),
        safe_distance_m: d,
        min_margin_m: moved.then_some(a.min_margin).filter(|m| m.is_finite()),
        closest: a.closest.map(|p| swept_pair_text(&p, &CollisionChecker::new(robot, &scene))),
        closest_pair: a.closest,
        position_error_m,
        orientation_error_deg,
        joint_error_deg,
        motion_deg: a.samples.iter().map(|q| q_display(robot, q)).collect(),
        stats: a.stats,
        handover,
        timing,
        duration_s: None,
        max_velocity_scale: request.max_velocity_scale,
        max_acceleration_scale: request.max_acceleration_scale,
        blend_tolerance: None,
        worst_velocity_ratio: None,
        worst_acceleration_ratio: None,
        collision_free: None,
        swept: None,
    };
    // The motion the arm follows: the samples, then the planner's path (its first waypoint is
    // the last sample), blended as widely as stays proven at the safe distance, then timed.
    let waypoints: Vec<Vec<f64>> = a.samples.into_iter().chain(planned.into_iter().skip(1)).collect();
    if timing == ApproachTiming::Optimal && waypoints.len() >= 2 {
        let requested = request.blend_tolerance.unwrap_or(DEFAULT_BLEND_TOLERANCE);
        let blend = clear_blend(&grown, &scene, &waypoints, requested)?;
        let motion = optimal_motion(
            robot,
            &waypoints,
            blend.tolerance,
            request.max_velocity_scale,
            request.max_acceleration_scale,
        )?;
        report.duration_s = Some(motion.duration());
        report.worst_velocity_ratio = Some(motion.worst_ratios().velocity.clone());
        report.worst_acceleration_ratio = Some(motion.worst_ratios().acceleration.clone());
        report.blend_tolerance = Some(blend.tolerance);
        report.collision_free = Some(super::timed::proven_clear(blend.swept.as_ref()));
        report.swept = blend.swept;
    }
    Ok(report)
}

/// The largest joint error of the last sample against the goal, degrees (prismatic metres).
fn joint_error(robot: &Robot, samples: &[Vec<f64>], goals: &[Vec<f64>]) -> f64 {
    match (samples.last(), goals.first()) {
        (Some(q), Some(g)) => {
            let diff: Vec<f64> = q.iter().zip(g).map(|(a, b)| b - a).collect();
            q_display(robot, &diff).iter().fold(0.0, |m, v| m.max(v.abs()))
        }
        _ => f64::NAN,
    }
}

/// Fits the fast region of a request.
fn fast_region(
    robot: &Robot,
    scene: &crate::world::Scene,
    safe_distance: f64,
    start: &[f64],
    f: &FastRegionRequest,
) -> Result<FastRegion> {
    let n = robot.dof();
    if n < 3 {
        return Err(Error::request("fast_region", format!("needs at least three joints, the robot has {n}")));
    }
    let joints = f.joints.unwrap_or([n - 2, n - 1, n]);
    if joints.iter().any(|&j| !(1..=n).contains(&j))
        || joints[0] == joints[1]
        || joints[1] == joints[2]
        || joints[0] == joints[2]
    {
        return Err(Error::request("fast_region.joints", format!("three different joints of 1..{n}, got {joints:?}")));
    }
    if !(f.step_deg.is_finite() && f.step_deg >= 1.0) {
        return Err(Error::request("fast_region.step_deg", format!("must be at least 1, got {}", f.step_deg)));
    }
    if !(f.band.is_finite() && f.band >= 0.0) {
        return Err(Error::request("fast_region.band", format!("must be ≥ 0, got {}", f.band)));
    }
    let fixed: Vec<(usize, f64)> = (0..n).filter(|j| !joints.contains(&(j + 1))).map(|j| (j, start[j])).collect();
    FastRegion::fit(robot, scene, safe_distance, &fixed, f.step_deg.to_radians(), f.band).map_err(|e| match e {
        crate::world::WorldError::Input(m) => Error::request("fast_region", m),
        e => Error::World(e),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::{Job, Report};

    fn job(to_xyz_m: [f64; 3]) -> Job {
        let scene = include_str!("../../../../../examples/seed004_ceiling.toml");
        serde_json::from_value(serde_json::json!({
            "robot": {"preset": "varan4"},
            "request": {"kind": "approach", "scene": scene, "from": {"deg": [0, 30, 0, 0]},
                        "to_pose": {"xyz_m": to_xyz_m}, "safe_distance_m": 0.05}
        }))
        .unwrap()
    }

    #[test]
    fn a_goal_below_the_ceiling_is_reached_with_the_safe_distance() {
        let Report::Approach(r) = job([1.5, 0.0, 0.6]).run().unwrap() else { panic!("not an approach report") };
        assert_eq!(r.outcome, Outcome::Reached, "{:?}", r.reason);
        assert!(r.position_error_m.unwrap() <= 1e-4 && r.min_margin_m.unwrap() > 0.0, "{r:?}");
        assert_eq!(r.samples, r.motion_deg.len());
        assert!(r.handover.is_none() && !r.failed());
    }

    #[test]
    fn a_deadlock_under_the_ceiling_is_handed_over_to_the_planner() {
        // Goal 16 of the 1000 random goals of tests/it/seed_004_approach.rs: the increments
        // towards it run into the barrier; the planner goes around.
        let Report::Approach(r) = job([0.7231, 0.0, 0.5006]).run().unwrap() else { panic!("not an approach report") };
        assert_eq!(r.outcome, Outcome::Deadlock, "{r:?}");
        assert!(r.failed() && r.min_margin_m.unwrap() > 0.0);
        let h = r.handover.unwrap();
        assert!(h.found, "{:?}", h.reason);
        assert_eq!(h.waypoints_deg.first(), r.motion_deg.last());
    }

    #[test]
    fn bad_requests_name_their_field() {
        let mut j = job([1.5, 0.0, 0.6]);
        let crate::jobs::Request::Approach(r) = &mut j.request else { unreachable!() };
        r.safe_distance_m = -1.0;
        assert!(j.run().unwrap_err().to_string().starts_with("safe_distance_m: "));
        // The start (30°, 0, 0) has its tool 0.15 m below the ceiling: a safe distance of 0.2 m
        // refuses it.
        let mut j = job([1.5, 0.0, 0.6]);
        let crate::jobs::Request::Approach(r) = &mut j.request else { unreachable!() };
        r.safe_distance_m = 0.2;
        assert!(j.run().unwrap_err().to_string().starts_with("from: the start is not allowed"));
        let mut j = job([1.5, 0.0, 0.6]);
        let crate::jobs::Request::Approach(r) = &mut j.request else { unreachable!() };
        r.max_samples = 1;
        assert!(j.run().unwrap_err().to_string().starts_with("max_samples: "));
    }

    #[test]
    fn an_unreachable_goal_is_an_answer() {
        // 3 m away: beyond the arm's 2.1 m reach.
        let Report::Approach(r) = job([3.0, 0.0, 0.5]).run().unwrap() else { panic!("not an approach report") };
        assert_eq!((r.outcome, r.samples, r.min_margin_m), (Outcome::Unreachable, 1, None), "{r:?}");
    }
}
