//! The `path` workflow: a collision-free joint-space path through a scene (RRT-Connect with
//! shortcutting, [`crate::world::planner`]), timed waypoint to waypoint and re-checked.
//!
//! The path is timed with [`JointPath`]: one cycloidal segment per edge, stopping at every
//! waypoint, so the timed motion stays on the planner's straight joint-space edges. Each
//! segment takes the fastest synchronised time within the joints' speed limits, or a share
//! of `duration_s` proportional to its joint-space length. Because the timed motion stays on
//! the straight edges, the swept check of the edges ([`SweptPathReport`]) proves the timed
//! motion clear: the report gives its certified clearance, where the path comes closest and
//! on which link.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::check::SweptPathReport;
use super::parse_scene;
use crate::error::{Error, Result};
use crate::ik::IkOptions;
use crate::jobs::input::{Joints, MotionSample, Pose, positive, q_display, time_budget};
use crate::motion::{JointMotion, JointPath, JointRates, Profile};
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
    /// Whether the timed motion is proven clear by the swept check (`null` without a path).
    pub collision_free: Option<bool>,
    /// The swept (continuous) check of every segment between waypoints: where the path comes
    /// closest and the certified lower bound of its clearance over the whole path (`null`
    /// when no path was found or nothing is checked: no obstacle, zone or link pair).
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
            let (durations, timed) = timed_path(robot, &p.waypoints, total)?;
            report.duration_s = timed.times.last().copied();
            report.segment_durations_s = durations;
            report.swept = SweptPathReport::check(robot, &scene, &p.waypoints, None)?;
            report.collision_free = Some(report.swept.as_ref().is_none_or(|s| s.swept.clear));
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

/// The timed motion along `waypoints`, sampled for drawings and callers (200 to 2000
/// samples).
fn timed_path(robot: &Robot, waypoints: &[Vec<f64>], total: Option<f64>) -> Result<(Vec<f64>, TimedPath)> {
    let durations = durations(robot, waypoints, total)?;
    let path = timing(robot, waypoints, &durations)?;
    let steps = (20 * durations.len()).clamp(200, 2000);
    let traj = path.sample(path.duration() / steps as f64)?;
    let times = traj.times();
    let q: Vec<Vec<f64>> = traj.samples.into_iter().map(|s| s.q).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|t| path.velocity(*t)).collect();
    let tool_xyz_m = tool_points(robot, &q)?;
    Ok((durations, TimedPath { times, q, qd, tool_xyz_m }))
}

/// The path's timing: one cycloidal segment per edge, stopping at every waypoint (so the
/// motion stays on the straight edges the planner proved clear).
fn timing(robot: &Robot, waypoints: &[Vec<f64>], durations: &[f64]) -> Result<JointPath> {
    Ok(JointPath::through(robot, waypoints, durations, 0.0, Profile::Cycloidal)?)
}

impl PathReport {
    /// The timed motion of a found path ([`PathReport::waypoints_deg`],
    /// [`PathReport::segment_durations_s`], the workflow's timing) sampled every `dt_s`
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
        let path = timing(robot, &waypoints, &self.segment_durations_s)?;
        let trajectory = path.sample(dt_s)?;
        Ok(trajectory.samples.iter().map(|s| MotionSample { t_s: s.t, q_deg: q_display(robot, &s.q) }).collect())
    }
}

/// The tool point (world frame, metres) of each configuration.
fn tool_points(robot: &Robot, q: &[Vec<f64>]) -> Result<Vec<[f64; 3]>> {
    q.iter().map(|qk| Ok(robot.fk(qk)?.translation.vector.into())).collect()
}
