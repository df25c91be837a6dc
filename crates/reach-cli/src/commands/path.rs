//! `reach path` — a collision-free joint-space path through a scene (RRT-Connect with
//! shortcutting, [`reach::world::planner`]), timed waypoint to waypoint and re-checked.
//!
//! The path is timed with [`JointPath`]: one cycloidal segment per edge, stopping at every
//! waypoint, so the timed motion stays on the planner's straight joint-space edges. Each
//! segment takes the fastest synchronised time within the joints' speed limits, or a share
//! of `--duration` proportional to its joint-space length. The timed trajectory is then
//! sampled and every sample re-checked with [`CollisionChecker::report`]: the smallest
//! obstacle and self clearances are reported.

use std::io::Write;
use std::time::Duration;

use clap::Args;
use reach::Robot;
use reach::ik::IkTarget;
use reach::motion::{JointMotion, JointPath, JointRates, Profile};
use reach::world::planner::{Goal, PlanError, PlanOptions, PlanStats, path_length, plan};
use reach::world::{CollisionChecker, Scene};
use serde::Serialize;

use crate::commands::check::load_scene;
use crate::commands::move_cmd::pose_arg;
use crate::error::{CliError, one_line};
use crate::numbers::{AngleUnit, parse_finite, parse_joint_values, q_display};
use crate::output::{Table, fixed, fixeds, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach path`.
#[derive(Debug, Clone, Args)]
pub struct PathArgs {
    /// The robot (its links need radii for meaningful clearances: `[[links]] radius`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Scene file (TOML: obstacles, tool zone, touching policy).
    #[arg(value_name = "SCENE")]
    pub scene: String,

    /// Start joint values q1,..,qn (degrees; prismatic in metres).
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub from: String,

    /// Goal joint values q1,..,qn (degrees; prismatic in metres).
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true, conflicts_with = "to_pose")]
    pub to: Option<String>,

    /// Goal tool pose x,y,z,roll,pitch,yaw (metres, degrees): every feasible, collision-free IK
    /// solution is a goal; the nearest reachable one wins.
    #[arg(long, value_name = "X,Y,Z,R,P,Y", allow_hyphen_values = true)]
    pub to_pose: Option<String>,

    /// Seed of the planner's random generator.
    #[arg(long, default_value = "1", value_name = "N")]
    pub seed: u64,

    /// Wall-time budget of the search, milliseconds.
    #[arg(long, default_value = "1000", value_name = "MS")]
    pub budget_ms: u64,

    /// Total duration of the timed motion, seconds (default: the fastest synchronised
    /// motion within the joints' speed limits, segment by segment).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub duration: Option<String>,

    /// Print JSON: {"robot", "scene", "found", "reason", "seed", "budget_ms", "waypoints_deg",
    /// "stats": {"iterations", "nodes", "checks", "raw_waypoints", "raw_length", "length",
    /// "time_s"}, "duration_s", "segment_durations_s", "samples", "collision_free",
    /// "min_clearance_m", "min_self_clearance_m"}; lengths are joint-space (rad / m).
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg FILE, --png FILE, --png-width PX (joint curves and tool path with the
    /// obstacles projected on xy and xz).
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

/// Planning statistics of the JSON output.
#[derive(Debug, Clone, Serialize)]
struct StatsJson {
    /// RRT-Connect iterations (0 when the straight edge was free).
    iterations: usize,
    /// Tree nodes over both trees.
    nodes: usize,
    /// Single-configuration collision checks during the search and shortcutting.
    checks: usize,
    /// Waypoints before shortcutting.
    raw_waypoints: usize,
    /// Joint-space length before shortcutting (rad / m).
    raw_length: f64,
    /// Joint-space length of the returned path (rad / m).
    length: Option<f64>,
    /// Wall time of the planner call, s.
    time_s: f64,
}

/// The JSON output of `reach path`.
#[derive(Debug, Clone, Serialize)]
struct PathJson {
    robot: String,
    scene: String,
    /// Whether a path was found.
    found: bool,
    /// Why not (null when found).
    reason: Option<String>,
    seed: u64,
    budget_ms: u64,
    /// Waypoints from start to goal (degrees; prismatic metres).
    waypoints_deg: Vec<Vec<f64>>,
    stats: StatsJson,
    /// Duration of the timed motion, s.
    duration_s: Option<f64>,
    /// Duration of each segment, s.
    segment_durations_s: Vec<f64>,
    /// Samples re-checked.
    samples: usize,
    /// Whether every sample of the timed motion is free.
    collision_free: Option<bool>,
    /// Smallest link–obstacle clearance over the samples, m (null without obstacles).
    min_clearance_m: Option<f64>,
    /// Smallest link–link clearance over the samples, m.
    min_self_clearance_m: Option<f64>,
}

/// The timed, re-checked path.
struct Timed {
    durations: Vec<f64>,
    times: Vec<f64>,
    q: Vec<Vec<f64>>,
    qd: Vec<Vec<f64>>,
    collision_free: bool,
    min_clearance: Option<f64>,
    min_self: Option<f64>,
}

fn motion_error(e: impl std::fmt::Display) -> CliError {
    CliError::bad_input(one_line(&e.to_string()))
}

/// Segment durations: the synchronised minimum time per edge within the speed limits, or
/// `total` shared by joint-space length.
fn durations(robot: &Robot, waypoints: &[Vec<f64>], total: Option<f64>) -> Result<Vec<f64>, CliError> {
    match total {
        Some(t) => {
            let lengths: Vec<f64> = waypoints.windows(2).map(path_length).collect();
            let sum: f64 = lengths.iter().sum();
            Ok(lengths.iter().map(|l| t * l / sum).collect())
        }
        None => {
            let rates = JointRates::from_robot(robot, None)
                .map_err(|e| CliError::bad_input(format!("give --duration: {}", one_line(&e.to_string()))))?;
            waypoints
                .windows(2)
                .map(|w| {
                    JointMotion::synchronised(robot, &w[0], &w[1], 0.0, &rates, Profile::Cycloidal)
                        .map(|(m, _)| m.duration())
                        .map_err(motion_error)
                })
                .collect()
        }
    }
}

fn time_and_check(robot: &Robot, scene: &Scene, waypoints: &[Vec<f64>], total: Option<f64>) -> Result<Timed, CliError> {
    let durations = durations(robot, waypoints, total)?;
    let path = JointPath::through(robot, waypoints, &durations, 0.0, Profile::Cycloidal).map_err(motion_error)?;
    let steps = (20 * durations.len()).clamp(200, 2000);
    let traj = path.sample(path.duration() / steps as f64).map_err(motion_error)?;
    let times = traj.times();
    let q: Vec<Vec<f64>> = traj.samples.into_iter().map(|s| s.q).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|t| path.velocity(*t)).collect();
    let mut checker = CollisionChecker::new(robot, scene);
    let (mut free, mut min_clearance, mut min_self) = (true, None::<f64>, None::<f64>);
    for qk in &q {
        let report = checker.report(qk).map_err(|e| CliError::internal(e.to_string()))?;
        free &= report.verdict.is_free();
        if let Some(c) = report.min_obstacle_clearance_m {
            min_clearance = Some(min_clearance.map_or(c, |m| m.min(c)));
        }
        if let Some(c) = report.min_self_clearance_m {
            min_self = Some(min_self.map_or(c, |m| m.min(c)));
        }
    }
    Ok(Timed { durations, times, q, qd, collision_free: free, min_clearance, min_self })
}

/// Joint-space distance (`path_length` units: rad and m mixed, Euclidean) at or below which
/// the start and the goal are one configuration and there is nothing to plan.
const SAME_CONFIGURATION: f64 = 1e-12;

/// Plans, times and re-checks the path and prints the report.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments, robot or scene; [`CliError::NoSolution`] (after
/// the report) when no path was found: budget exhausted, start or goal in collision, no IK
/// solution for the goal pose.
pub fn run(args: &PathArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = args.robot.load()?.robot;
    let scene = load_scene(&args.scene)?;
    let split = |t: &str| t.split(',').map(str::to_string).collect::<Vec<_>>();
    let from = parse_joint_values(&robot, &split(&args.from), AngleUnit::Deg)
        .map_err(|e| CliError::bad_input(format!("--from: {e}")))?;
    let start = from.si.clone();
    // The ends as typed (no round trip through radians in the report).
    let mut typed_goal = None;
    let goal = match (&args.to, &args.to_pose) {
        (Some(t), None) => {
            let to = parse_joint_values(&robot, &split(t), AngleUnit::Deg)
                .map_err(|e| CliError::bad_input(format!("--to: {e}")))?;
            typed_goal = Some(to.deg);
            Goal::Joints(to.si)
        }
        (None, Some(p)) => Goal::Target(IkTarget::Pose(pose_arg("--to-pose", p)?.isometry("--to-pose")?)),
        _ => return Err(CliError::bad_input("give exactly one of --to and --to-pose")),
    };
    let same = || CliError::bad_input("--from and --to are the same configuration: nothing to plan");
    // A joint goal is compared before planning; a pose goal only once IK has chosen its
    // configuration (below).
    if let Goal::Joints(q) = &goal
        && path_length(&[start.clone(), q.clone()]) <= SAME_CONFIGURATION
    {
        return Err(same());
    }
    let total = match &args.duration {
        Some(d) => {
            let v = parse_finite("--duration", d)?;
            if v <= 0.0 {
                return Err(CliError::bad_input(format!("--duration must be positive, got {v}")));
            }
            Some(v)
        }
        None => None,
    };
    args.draw.check_files()?;
    let options = PlanOptions {
        seed: args.seed,
        max_time: Some(Duration::from_millis(args.budget_ms)),
        ..PlanOptions::default()
    };
    let mut json = PathJson {
        robot: robot.name().to_string(),
        scene: args.scene.clone(),
        found: false,
        reason: None,
        seed: args.seed,
        budget_ms: args.budget_ms,
        waypoints_deg: Vec::new(),
        stats: StatsJson {
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
        samples: 0,
        collision_free: None,
        min_clearance_m: None,
        min_self_clearance_m: None,
    };
    match plan(&robot, &scene, &start, &goal, &options) {
        Ok(p) => {
            let PlanStats { iterations, nodes, checks, raw_waypoints, raw_length, time_s, .. } = p.stats;
            let length = path_length(&p.waypoints);
            json.stats =
                StatsJson { iterations, nodes, checks, raw_waypoints, raw_length, length: Some(length), time_s };
            json.found = true;
            json.waypoints_deg = p.waypoints.iter().map(|q| q_display(&robot, q)).collect();
            json.waypoints_deg[0].clone_from(&from.deg);
            if let (Some(last), Some(g)) = (json.waypoints_deg.last_mut(), typed_goal) {
                *last = g;
            }
            if length <= SAME_CONFIGURATION {
                return Err(same());
            }
            let timed = time_and_check(&robot, &scene, &p.waypoints, total)?;
            json.duration_s = timed.times.last().copied();
            json.segment_durations_s = timed.durations.clone();
            json.samples = timed.q.len();
            json.collision_free = Some(timed.collision_free);
            json.min_clearance_m = timed.min_clearance;
            json.min_self_clearance_m = timed.min_self;
            if args.draw.any() {
                args.draw.write(&drawing(&robot, &scene, &p.waypoints, &timed))?;
            }
        }
        Err(e @ (PlanError::Input(_) | PlanError::World(_) | PlanError::Ik(_))) => {
            return Err(CliError::bad_input(one_line(&e.to_string())));
        }
        Err(e) => {
            if let PlanError::BudgetExhausted { iterations, nodes, time_s } = e {
                json.stats.iterations = iterations;
                json.stats.nodes = nodes;
                json.stats.time_s = time_s;
            }
            json.reason = Some(one_line(&e.to_string()));
        }
    }
    if args.json {
        write_json(out, &json)?;
    } else {
        write_report(out, &json)?;
    }
    match (&json.reason, json.collision_free) {
        (Some(r), _) => {
            out.flush()?;
            Err(CliError::NoSolution(format!("no path: {r}")))
        }
        (None, Some(false)) => Err(CliError::internal("the timed path collides although its edges were checked")),
        _ => Ok(()),
    }
}

fn write_report(out: &mut dyn Write, j: &PathJson) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", j.robot.clone());
    head.pair("scene", j.scene.clone());
    head.pair("result", if j.found { "path found".to_string() } else { "NO PATH".to_string() });
    if let Some(r) = &j.reason {
        head.pair("reason", r.clone());
    }
    let s = &j.stats;
    head.pair(
        "planning",
        format!("{} iterations, {} nodes, {} checks, {} s", s.iterations, s.nodes, s.checks, fixed(s.time_s, 3)),
    );
    if j.found {
        head.pair(
            "path length",
            format!(
                "{} before shortcutting ({} waypoints), {} after ({} waypoints) [joint space, rad/m]",
                fixed(s.raw_length, 4),
                s.raw_waypoints,
                fixed(s.length.unwrap_or(0.0), 4),
                j.waypoints_deg.len()
            ),
        );
        head.pair("duration", format!("{} s (cycloidal, stops at waypoints)", fixed(j.duration_s.unwrap_or(0.0), 3)));
        head.pair(
            "min clearance",
            j.min_clearance_m
                .map_or_else(|| "- (no obstacles)".into(), |c| format!("{} m over {} samples", fixed(c, 4), j.samples)),
        );
        head.pair(
            "min self clearance",
            j.min_self_clearance_m.map_or_else(|| "-".into(), |c| format!("{} m", fixed(c, 4))),
        );
    }
    head.write(out, "")?;
    if j.found {
        writeln!(out, "waypoints [deg]:")?;
        for (k, w) in j.waypoints_deg.iter().enumerate() {
            writeln!(out, "  {:>2}  {}", k + 1, fixeds(w, 3))?;
        }
    }
    Ok(())
}

fn drawing(robot: &Robot, scene: &Scene, waypoints: &[Vec<f64>], timed: &Timed) -> crate::plot::Svg {
    use crate::plot::drawings::{TrajectoryDrawing, joint_series_si, title, trajectory};
    let tool =
        |q: &Vec<f64>| robot.fk(q).map(|p| p.translation.vector).map(|v| [v.x, v.y, v.z]).unwrap_or([f64::NAN; 3]);
    trajectory(&TrajectoryDrawing {
        title: title(
            robot,
            &format!(
                "planned path, {} waypoints, {} s, cycloidal segments",
                waypoints.len(),
                fixed(timed.times.last().copied().unwrap_or(0.0), 3)
            ),
        ),
        times: timed.times.clone(),
        joints: joint_series_si(robot, &timed.q, &timed.qd),
        tool: timed.q.iter().map(tool).collect(),
        tool_waypoints: waypoints.iter().map(tool).collect(),
        obstacles: &scene.obstacles,
    })
}
