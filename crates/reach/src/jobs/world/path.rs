//! The `path` workflow: a collision-free joint-space path through a scene (RRT-Connect with
//! shortcutting, [`crate::world::planner`]), timed and re-checked.
//!
//! The path is timed in one of two ways ([`PathTiming`]): time-optimal under the joints'
//! velocity and acceleration limits ([`crate::motion::optimal`], TOPP-RA, with the exact worst
//! ratio to each limit) along the planner's straight edges with every corner cut by a
//! parabolic blend within [`PathRequest::blend_tolerance`] of its waypoint
//! ([`crate::motion::PiecewiseCubic::blended`]; 0 rests at each waypoint), or one cycloidal segment per edge
//! ([`JointPath`]), resting at every waypoint, taking the fastest synchronised time within the
//! speed limits or a share of `duration_s` proportional to its joint-space length. The swept
//! check runs on the path that is timed — the edges, and the blends' arcs
//! ([`SweptPathReport::check_pieces`]) — so the timed motion is proven clear: the report gives
//! its certified clearance, where the path comes closest and on which link. A blended path
//! not proven clear is blended tighter ([`BLEND_TIGHTENINGS`]), at last not at all.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::check::SweptPathReport;
use super::parse_scene;
pub use super::timed::BLEND_TIGHTENINGS;
use super::timed::{clear_blend, optimal_motion, proven_clear};
use crate::error::{Error, Result};
use crate::ik::IkOptions;
use crate::jobs::input::{Joints, MotionSample, Pose, full_scale, positive, q_display, time_budget};
use crate::jobs::retime::{DEFAULT_BLEND_TOLERANCE, request_error};
use crate::motion::{JointMotion, JointPath, JointRates, OptimalMotion, PathLimits, Profile, check_blend_tolerance};
use crate::world::Scene;
use crate::world::planner::{Goal, PlanError, PlanOptions, PlanStats, path_length, plan};
use crate::{Cancel, Robot};

fn default_seed() -> u64 {
    1
}

fn default_time_budget_s() -> f64 {
    1.0
}

/// Joint-space distance (`path_length` units: rad and m mixed, Euclidean) at or below which
/// the start and the goal are one configuration and there is nothing to plan.
const SAME_CONFIGURATION: f64 = 1e-12;

/// How a planned path is timed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PathTiming {
    /// Time-optimal (TOPP-RA) under every joint's `max_velocity` and `max_acceleration`
    /// (times their scales), proven within them between samples.
    Optimal,
    /// One cycloidal segment per edge: the synchronised minimum time within the speed limits,
    /// or `duration_s` shared by joint-space length.
    Cycloidal,
}

impl PathTiming {
    /// The timing a request gets: the one it names, else `optimal` when no `duration_s` is
    /// given and every joint has a velocity and an acceleration limit (its own, or its stepper
    /// drive's: [`PathLimits::from_robot`]), else `cycloidal`.
    ///
    /// # Errors
    /// [`Error::Request`] for `optimal` with a `duration_s` (the limits set the duration), or
    /// a scale other than 1 with `cycloidal` timing.
    pub fn resolve(robot: &Robot, request: &PathRequest) -> Result<PathTiming> {
        let limited = PathLimits::from_robot(robot, 1.0, 1.0).is_ok();
        let timing = request.timing.unwrap_or(if request.duration_s.is_none() && limited {
            PathTiming::Optimal
        } else {
            PathTiming::Cycloidal
        });
        match timing {
            PathTiming::Optimal if request.duration_s.is_some() => Err(Error::request(
                "duration_s",
                "cannot be given with optimal timing (the limits set the duration): leave it out, or use cycloidal timing",
            )),
            PathTiming::Cycloidal => {
                for (field, scale) in [
                    ("max_velocity_scale", request.max_velocity_scale),
                    ("max_acceleration_scale", request.max_acceleration_scale),
                ] {
                    if scale != 1.0 {
                        return Err(Error::request(
                            field,
                            format!(
                                "{scale} applies to optimal timing only, and the path is timed cycloidal ({})",
                                if request.timing.is_some() {
                                    "as asked"
                                } else if request.duration_s.is_some() {
                                    "a duration is given"
                                } else {
                                    "the robot lacks velocity or acceleration limits"
                                }
                            ),
                        ));
                    }
                }
                Ok(timing)
            }
            PathTiming::Optimal => Ok(timing),
        }
    }
}

/// A collision-free path from a configuration to a configuration or a tool pose. Give exactly
/// one of `to` and `to_pose`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PathRequest {
    /// The text of the scene file (TOML: obstacles, tool zone, touching policy).
    pub scene: String,
    /// Start joint values.
    pub from: Joints,
    /// Goal joint values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<Joints>,
    /// Goal tool pose: every feasible, collision-free IK solution is a goal; the nearest
    /// reachable one wins.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to_pose: Option<Pose>,
    /// Seed of the planner's random generator (default 1).
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// Wall-time budget of the search, seconds (default 1; at most one day).
    #[serde(default = "default_time_budget_s")]
    pub time_budget_s: f64,
    /// Total duration of the timed motion, seconds (default: the fastest synchronised motion
    /// within the joints' speed limits, segment by segment).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// How the path is timed (default: `optimal` when no `duration_s` is given and every
    /// joint has velocity and acceleration limits, else `cycloidal`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub timing: Option<PathTiming>,
    /// Optimal timing: multiplies every joint's `max_velocity`, in (0, 1] (MoveIt's scaling
    /// factor; default 1).
    #[serde(default = "full_scale")]
    pub max_velocity_scale: f64,
    /// Optimal timing: multiplies every joint's `max_acceleration`, in (0, 1] (default 1).
    #[serde(default = "full_scale")]
    pub max_acceleration_scale: f64,
    /// Optimal timing: how far (joint-space Euclidean distance, rad and m) the timed motion
    /// may pass from each interior waypoint, cutting the corner with a parabolic blend so it
    /// need not stop there (default [`DEFAULT_BLEND_TOLERANCE`], MoveIt's `path_tolerance`;
    /// 0 rests at every waypoint). A blend that is not proven clear is tightened (halved, at
    /// most [`BLEND_TIGHTENINGS`] times, then 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend_tolerance: Option<f64>,
}

/// Planning statistics.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PathStatsReport {
    /// RRT-Connect iterations (0 when the straight edge was free).
    pub iterations: usize,
    /// Tree nodes over both trees.
    pub nodes: usize,
    /// Single-configuration collision checks during the search and shortcutting.
    pub checks: usize,
    /// Waypoints before shortcutting.
    pub raw_waypoints: usize,
    /// Joint-space length before shortcutting (rad / m).
    pub raw_length: f64,
    /// Joint-space length of the returned path (rad / m).
    pub length: Option<f64>,
    /// Wall time of the planner call, s (varies from run to run).
    pub time_s: f64,
}

/// The planned, timed and re-checked path (`reach path --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PathReport {
    /// Robot name.
    pub robot: String,
    /// Whether a path was found.
    pub found: bool,
    /// Why not (`null` when found).
    pub reason: Option<String>,
    /// Seed of the planner.
    pub seed: u64,
    /// Wall-time budget of the search, s.
    pub time_budget_s: f64,
    /// Waypoints from start to goal (revolute degrees, prismatic metres).
    pub waypoints_deg: Vec<Vec<f64>>,
    /// Planning statistics.
    pub stats: PathStatsReport,
    /// Duration of the timed motion, s.
    pub duration_s: Option<f64>,
    /// Duration of each segment, s.
    pub segment_durations_s: Vec<f64>,
    /// How the path is timed.
    pub timing: PathTiming,
    /// The velocity limits' scale (optimal timing; 1 otherwise).
    pub max_velocity_scale: f64,
    /// The acceleration limits' scale (optimal timing; 1 otherwise).
    pub max_acceleration_scale: f64,
    /// Optimal timing: per joint, the exact largest `|q̇| / limit` over the whole motion
    /// (≤ 1; the limit after scaling); `null` for cycloidal timing or without a path.
    pub worst_velocity_ratio: Option<Vec<f64>>,
    /// Optimal timing: per joint, the exact largest `|q̈| / limit` (≤ 1); `null` otherwise.
    pub worst_acceleration_ratio: Option<Vec<f64>>,
    /// Optimal timing: the blend tolerance of the timed motion (rad and m; the requested one,
    /// or tighter when a blend was not proven clear; 0: resting at every waypoint); `null` for
    /// cycloidal timing.
    #[serde(default)]
    pub blend_tolerance: Option<f64>,
    /// Whether the timed motion is proven clear by the swept check (`null` without a path).
    pub collision_free: Option<bool>,
    /// The swept (continuous) check of the timed motion's path — the straight edges between
    /// waypoints, and with blends the arcs that cut their corners (`segment` then numbers the
    /// lines and arcs in order): where the path comes closest and the certified lower bound of
    /// its clearance over the whole path (`null` when no path was found or nothing is checked:
    /// no obstacle, zone or link pair).
    pub swept: Option<SweptPathReport>,
}

/// The timed path's samples (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct TimedPath {
    /// Sample times, s.
    pub times: Vec<f64>,
    /// Joint positions at each time.
    pub q: Vec<Vec<f64>>,
    /// Joint velocities at each time.
    pub qd: Vec<Vec<f64>>,
    /// Tool point at each time, metres (world frame).
    pub tool_xyz_m: Vec<[f64; 3]>,
}

/// The report with what a drawing needs.
#[derive(Debug, Clone)]
pub struct PathRun {
    /// The report.
    pub report: PathReport,
    /// The parsed scene.
    pub scene: Scene,
    /// The planner's waypoints, SI (empty when no path was found).
    pub waypoints: Vec<Vec<f64>>,
    /// The tool point at each waypoint, metres (world frame).
    pub waypoints_tool_xyz_m: Vec<[f64; 3]>,
    /// The timed path (`None` when no path was found).
    pub timed: Option<TimedPath>,
}

/// Plans, times and re-checks the path (see [`path_run`]).
///
/// # Errors
/// As [`path_run`].
pub fn path(robot: &Robot, request: &PathRequest) -> Result<PathReport> {
    Ok(path_run(robot, request)?.report)
}

/// Plans, times and re-checks the path. No path (budget exhausted, start or goal in
/// collision, no IK solution for the goal pose) is an answer: `found` is false and `reason`
/// says why.
///
/// # Errors
/// [`Error::World`] for a malformed scene; [`Error::Request`] for bad joint values (`from`,
/// `to`), a bad pose (`to_pose`), both or neither goal, a `duration_s` that is not > 0, a goal
/// that is the start; [`Error::Plan`] for input the planner rejects (limits, IK options);
/// [`Error::Motion`] when the path cannot be timed (a joint without a speed limit and no
/// `duration_s`).
pub fn path_run(robot: &Robot, request: &PathRequest) -> Result<PathRun> {
    path_run_with_cancel(robot, request, &Cancel::default())
}

/// [`path_run`] whose planner stops when `cancel` is set (as if its time budget were spent).
///
/// # Errors
/// As [`path_run`].
pub fn path_run_with_cancel(robot: &Robot, request: &PathRequest, cancel: &Cancel) -> Result<PathRun> {
    let scene = parse_scene(&request.scene)?;
    let (start, goal) = super::start_and_goal(robot, &request.from, request.to.as_ref(), request.to_pose.as_ref())?;
    let total = positive("duration_s", request.duration_s)?;
    let timing = PathTiming::resolve(robot, request)?;
    // Bad limits or scales are refused before planning.
    if timing == PathTiming::Optimal {
        PathLimits::from_robot(robot, request.max_velocity_scale, request.max_acceleration_scale)
            .map_err(request_error)?;
    }
    if let Some(tolerance) = request.blend_tolerance {
        if timing != PathTiming::Optimal {
            return Err(Error::request("blend_tolerance", "applies to optimal timing only"));
        }
        check_blend_tolerance(tolerance).map_err(request_error)?;
    }
    let budget = time_budget("time_budget_s", Some(request.time_budget_s))?;
    let same = || Error::request("to", "the same configuration as `from`: nothing to plan");
    // A joint goal is compared before planning; a pose goal only once IK has chosen its
    // configuration.
    if let Goal::Joints(q) = &goal
        && path_length(&[start.clone(), q.clone()]) <= SAME_CONFIGURATION
    {
        return Err(same());
    }
    let ik = IkOptions { cancel: cancel.clone(), ..IkOptions::default() };
    let options = PlanOptions { seed: request.seed, max_time: budget, ik, ..PlanOptions::default() };
    let mut report = PathReport {
        robot: robot.name().to_string(),
        found: false,
        reason: None,
        seed: request.seed,
        time_budget_s: request.time_budget_s,
        waypoints_deg: Vec::new(),
        stats: PathStatsReport {
            iterations: 0,
            nodes: 0,
            checks: 0,
            raw_waypoints: 0,
            raw_length: 0.0,
            length: None,
            time_s: 0.0,
        },
        duration_s: None,
        segment_durations_s: Vec::new(),
        timing,
        max_velocity_scale: request.max_velocity_scale,
        max_acceleration_scale: request.max_acceleration_scale,
        worst_velocity_ratio: None,
        worst_acceleration_ratio: None,
        blend_tolerance: None,
        collision_free: None,
        swept: None,
    };
    match plan(robot, &scene, &start, &goal, &options) {
        Ok(p) => {
            let PlanStats { iterations, nodes, checks, raw_waypoints, raw_length, time_s, .. } = p.stats;
            let length = path_length(&p.waypoints);
            if length <= SAME_CONFIGURATION {
                return Err(same());
            }
            report.stats =
                PathStatsReport { iterations, nodes, checks, raw_waypoints, raw_length, length: Some(length), time_s };
            report.found = true;
            report.waypoints_deg = p.waypoints.iter().map(|q| q_display(robot, q)).collect();
            // The ends as typed (no round trip through radians).
            report.waypoints_deg[0] = request.from.display(robot);
            if let (Some(last), Some(to)) = (report.waypoints_deg.last_mut(), &request.to) {
                *last = to.display(robot);
            }
            let cycloidal = match report.timing {
                PathTiming::Cycloidal => durations(robot, &p.waypoints, total)?,
                PathTiming::Optimal => Vec::new(),
            };
            // Optimal timing: the widest blend proven clear, at last 0 (the polyline, whose
            // edges the planner proved clear). Cycloidal timing: the edges.
            match timing {
                PathTiming::Optimal => {
                    let requested = request.blend_tolerance.unwrap_or(DEFAULT_BLEND_TOLERANCE);
                    let blend = clear_blend(robot, &scene, &p.waypoints, requested)?;
                    report.blend_tolerance = Some(blend.tolerance);
                    report.swept = blend.swept;
                }
                PathTiming::Cycloidal => report.swept = SweptPathReport::check(robot, &scene, &p.waypoints, None)?,
            }
            report.collision_free = Some(proven_clear(report.swept.as_ref()));
            let law = TimingLaw::new(robot, &p.waypoints, &report, &cycloidal)?;
            let timed = law.timed_path(robot)?;
            report.duration_s = timed.times.last().copied();
            report.segment_durations_s = law.segment_durations();
            if let TimingLaw::Optimal(m) = &law {
                report.worst_velocity_ratio = Some(m.worst_ratios().velocity.clone());
                report.worst_acceleration_ratio = Some(m.worst_ratios().acceleration.clone());
            }
            let waypoints_tool_xyz_m = tool_points(robot, &p.waypoints)?;
            return Ok(PathRun { report, scene, waypoints: p.waypoints, waypoints_tool_xyz_m, timed: Some(timed) });
        }
        Err(e @ (PlanError::Input(_) | PlanError::World(_) | PlanError::Ik(_))) => return Err(e.into()),
        Err(e) => {
            if let PlanError::BudgetExhausted { iterations, nodes, time_s } = e {
                report.stats.iterations = iterations;
                report.stats.nodes = nodes;
                report.stats.time_s = time_s;
            }
            report.reason = Some(e.to_string().split_whitespace().collect::<Vec<_>>().join(" "));
        }
    }
    Ok(PathRun { report, scene, waypoints: Vec::new(), waypoints_tool_xyz_m: Vec::new(), timed: None })
}

/// Segment durations: the synchronised minimum time per edge within the speed limits, or
/// `total` shared by joint-space length.
fn durations(robot: &Robot, waypoints: &[Vec<f64>], total: Option<f64>) -> Result<Vec<f64>> {
    match total {
        Some(t) => {
            let lengths: Vec<f64> = waypoints.windows(2).map(path_length).collect();
            let sum: f64 = lengths.iter().sum();
            Ok(lengths.iter().map(|l| t * l / sum).collect())
        }
        None => {
            let rates = JointRates::from_robot(robot, None).map_err(|e| {
                Error::request("duration_s", format!("needed: the robot's speed limits cannot time the path ({e})"))
            })?;
            waypoints
                .windows(2)
                .map(|w| {
                    Ok(JointMotion::synchronised(robot, &w[0], &w[1], 0.0, &rates, Profile::Cycloidal)
                        .map(|(m, _)| m.duration())?)
                })
                .collect()
        }
    }
}

/// Time, joint positions and joint speeds (SI).
type TimedSample = (f64, Vec<f64>, Vec<f64>);

/// The timed motion along the path between waypoints ([`PathTiming`]).
enum TimingLaw {
    Optimal(Box<OptimalMotion>),
    Cycloidal(JointPath),
}

impl TimingLaw {
    /// The law of `report.timing` along `waypoints`: optimal with the report's scales, or
    /// cycloidal with `durations` per segment.
    fn new(robot: &Robot, waypoints: &[Vec<f64>], report: &PathReport, durations: &[f64]) -> Result<TimingLaw> {
        Ok(match report.timing {
            PathTiming::Optimal => TimingLaw::Optimal(Box::new(optimal_motion(
                robot,
                waypoints,
                report.blend_tolerance.unwrap_or(0.0),
                report.max_velocity_scale,
                report.max_acceleration_scale,
            )?)),
            PathTiming::Cycloidal => {
                TimingLaw::Cycloidal(JointPath::through(robot, waypoints, durations, 0.0, Profile::Cycloidal)?)
            }
        })
    }

    /// Duration of each segment, s.
    fn segment_durations(&self) -> Vec<f64> {
        match self {
            TimingLaw::Optimal(m) => m.waypoint_times().windows(2).map(|w| w[1] - w[0]).collect(),
            TimingLaw::Cycloidal(p) => p.segments().iter().map(JointMotion::duration).collect(),
        }
    }

    /// Time, positions and speeds every `dt` seconds from 0, and at the end.
    fn samples(&self, dt: f64) -> Result<Vec<TimedSample>> {
        Ok(match self {
            TimingLaw::Optimal(m) => {
                m.samples(dt).map_err(request_error)?.into_iter().map(|s| (s.t, s.q, s.qd)).collect()
            }
            TimingLaw::Cycloidal(p) => p.sample(dt)?.samples.into_iter().map(|s| (s.t, s.q, p.velocity(s.t))).collect(),
        })
    }

    /// The motion sampled for drawings and callers (200 to 2000 samples).
    fn timed_path(&self, robot: &Robot) -> Result<TimedPath> {
        let (segments, duration) = match self {
            TimingLaw::Optimal(m) => (m.waypoint_times().len() - 1, m.duration()),
            TimingLaw::Cycloidal(p) => (p.segments().len(), p.duration()),
        };
        let steps = (20 * segments).clamp(200, 2000);
        let (mut times, mut q, mut qd) = (Vec::new(), Vec::new(), Vec::new());
        for (t, qk, qdk) in self.samples(duration / steps as f64)? {
            times.push(t);
            q.push(qk);
            qd.push(qdk);
        }
        let tool_xyz_m = tool_points(robot, &q)?;
        Ok(TimedPath { times, q, qd, tool_xyz_m })
    }
}

impl PathReport {
    /// The timed motion of a found path ([`PathReport::waypoints_deg`] with the report's
    /// timing: its scales, or its [`PathReport::segment_durations_s`]) sampled every `dt_s`
    /// seconds (and at the end), as a drive follows it; empty when no path was found.
    ///
    /// # Errors
    /// The motion module's error for a `dt_s` that is not positive or gives too many samples;
    /// [`Error::Request`] for waypoints that do not fit the robot.
    pub fn motion(&self, robot: &Robot, dt_s: f64) -> Result<Vec<MotionSample>> {
        if self.waypoints_deg.len() < 2 {
            return Ok(Vec::new());
        }
        let waypoints = self
            .waypoints_deg
            .iter()
            .map(|w| Joints::Deg(w.clone()).si(robot, "waypoints_deg"))
            .collect::<Result<Vec<_>>>()?;
        let law = TimingLaw::new(robot, &waypoints, self, &self.segment_durations_s)?;
        Ok(law
            .samples(dt_s)?
            .into_iter()
            .map(|(t_s, q, _)| MotionSample { t_s, q_deg: q_display(robot, &q) })
            .collect())
    }
}

/// The tool point (world frame, metres) of each configuration.
fn tool_points(robot: &Robot, q: &[Vec<f64>]) -> Result<Vec<[f64; 3]>> {
    q.iter().map(|qk| Ok(robot.fk(qk)?.translation.vector.into())).collect()
}
