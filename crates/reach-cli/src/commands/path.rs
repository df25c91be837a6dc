//! `reach path` — a collision-free joint-space path through a scene, timed and re-checked
//! (`reach::jobs::world::path`: RRT-Connect with shortcutting, cycloidal segments that stop
//! at every waypoint; `--json` prints its report).

use std::io::Write;

use clap::Args;
use reach::Robot;
use reach::jobs::world::{PathReport, PathRequest, PathRun, TimedPath, path_run};
use reach::jobs::{Joints, Pose};

use crate::commands::check::{read_scene, scene_error};
use crate::error::CliError;
use crate::numbers::{parse_exact, parse_finite, parse_list};
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

    /// Print the report as JSON (docs/schemas/path.report.schema.json); lengths are
    /// joint-space (rad / m).
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg FILE, --png FILE, --png-width PX (joint curves and tool path with the
    /// obstacles projected on xy and xz).
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

impl PathArgs {
    /// The library request (the scene file read).
    ///
    /// # Errors
    /// [`CliError::BadInput`] for an unreadable scene, malformed numbers, both or neither of
    /// `--to` and `--to-pose`.
    pub fn request(&self) -> Result<PathRequest, CliError> {
        let to_pose = match &self.to_pose {
            Some(t) => {
                let v = parse_exact("--to-pose", t, 6, "x,y,z in metres, roll,pitch,yaw in degrees")?;
                Some(Pose::xyz_rpy_deg([v[0], v[1], v[2]], [v[3], v[4], v[5]]))
            }
            None => None,
        };
        if self.to.is_some() == to_pose.is_some() {
            return Err(CliError::bad_input("give exactly one of --to and --to-pose"));
        }
        Ok(PathRequest {
            scene: read_scene(&self.scene)?,
            from: Joints::Deg(parse_list("--from", &self.from)?),
            to: self.to.as_deref().map(|t| parse_list("--to", t).map(Joints::Deg)).transpose()?,
            to_pose,
            seed: self.seed,
            budget_ms: self.budget_ms,
            duration_s: self.duration.as_deref().map(|d| parse_finite("--duration", d)).transpose()?,
        })
    }
}

/// Plans, times and re-checks the path and prints the report.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments, robot or scene; [`CliError::NoSolution`] (after
/// the report) when no path was found: budget exhausted, start or goal in collision, no IK
/// solution for the goal pose.
pub fn run(args: &PathArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = args.robot.load()?.robot;
    let request = args.request()?;
    args.draw.check_files()?;
    let run = path_run(&robot, &request).map_err(|e| scene_error(&args.scene, e))?;
    if let (true, Some(timed)) = (args.draw.any(), &run.timed) {
        args.draw.write(&drawing(&robot, &run, timed))?;
    }
    let report = &run.report;
    if args.json {
        write_json(out, report)?;
    } else {
        write_report(out, &args.scene, report)?;
    }
    match (&report.reason, report.collision_free) {
        (Some(r), _) => {
            out.flush()?;
            Err(CliError::NoSolution(format!("no path: {r}")))
        }
        (None, Some(false)) => Err(CliError::internal("the timed path collides although its edges were checked")),
        _ => Ok(()),
    }
}

fn write_report(out: &mut dyn Write, scene: &str, j: &PathReport) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", j.robot.clone());
    head.pair("scene", scene.to_string());
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

fn drawing(robot: &Robot, run: &PathRun, timed: &TimedPath) -> crate::plot::Svg {
    use crate::plot::drawings::{TrajectoryDrawing, joint_series_si, title, trajectory};
    let tool =
        |q: &Vec<f64>| robot.fk(q).map(|p| p.translation.vector).map(|v| [v.x, v.y, v.z]).unwrap_or([f64::NAN; 3]);
    trajectory(&TrajectoryDrawing {
        title: title(
            robot,
            &format!(
                "planned path, {} waypoints, {} s, cycloidal segments",
                run.waypoints.len(),
                fixed(timed.times.last().copied().unwrap_or(0.0), 3)
            ),
        ),
        times: timed.times.clone(),
        joints: joint_series_si(robot, &timed.q, &timed.qd),
        tool: timed.q.iter().map(tool).collect(),
        tool_waypoints: run.waypoints.iter().map(tool).collect(),
        obstacles: &run.scene.obstacles,
    })
}
