//! `reach path` — a collision-free joint-space path through a scene, timed and re-checked
//! (`reach::jobs::world::path`: RRT-Connect with shortcutting, timed along the straight edges
//! time-optimally or by cycloidal segments, resting at every waypoint; `--json` prints its
//! report).

use std::io::Write;

use clap::Args;
use reach::Robot;
use reach::jobs::input::number_text;
use reach::jobs::world::{PathReport, PathRequest, PathRun, PathTiming, TimedPath, path_run_with_cancel};
use reach::jobs::{Joints, Pose};

use crate::commands::check::{read_scene, scene_error};
use crate::error::CliError;
use crate::numbers::parse_finite;
use crate::output::{Table, fixed, fixeds, verdict_exit, write_json};
use crate::pose_arg::{ToPoseArgs, flag_table, joints_arg};
use crate::robot_arg::RobotArgs;

/// The robot, the scene and the two ends of a motion through it: what `reach path` and
/// `reach approach` both read.
#[derive(Debug, Clone, Args)]
pub struct SceneMotionArgs {
    /// The robot (its links need radii for meaningful clearances: `[[links]] radius`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Scene file (TOML: obstacles, tool zone, touching policy).
    #[arg(value_name = "SCENE")]
    pub scene: String,

    /// Start joint values q1,..,qn (degrees, radians with --rad; prismatic in metres).
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub from: String,

    /// Goal joint values q1,..,qn.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub to: Option<String>,

    /// Goal tool pose (instead of --to).
    #[command(flatten)]
    pub to_pose: ToPoseArgs,

    /// Joint values and roll, pitch, yaw are in radians instead of degrees.
    #[arg(long)]
    pub rad: bool,
}

/// The ends of a motion as the library's requests take them.
pub struct Ends {
    /// The scene file's text.
    pub scene: String,
    /// The start.
    pub from: Joints,
    /// The goal in joint values, or
    pub to: Option<Joints>,
    /// the goal as a tool pose.
    pub to_pose: Option<Pose>,
}

impl SceneMotionArgs {
    /// The scene read and the ends parsed.
    ///
    /// # Errors
    /// [`CliError::BadInput`] for an unreadable scene, malformed numbers, both or neither of
    /// `--to` and `--to-pose`.
    pub fn ends(&self) -> Result<Ends, CliError> {
        let pose = self.to_pose.flags();
        if self.to.is_some() == pose.given() {
            return Err(CliError::bad_input("give exactly one of --to and --to-xyz/--to-matrix"));
        }
        Ok(Ends {
            scene: read_scene(&self.scene)?,
            from: joints_arg("--from", &self.from, self.rad)?,
            to: self.to.as_deref().map(|t| joints_arg("--to", t, self.rad)).transpose()?,
            to_pose: if pose.given() { Some(pose.pose(self.rad)?) } else { None },
        })
    }

    /// A library error of the request's fields named by the flags typed; others named with
    /// the scene file.
    #[must_use]
    pub fn error(&self, e: reach::Error, fixed: &[(&str, &str)]) -> CliError {
        match e {
            reach::Error::Request { .. } => {
                let mut table = vec![("from", "--from"), ("to", "--to"), ("to_pose", "--to-xyz")];
                table.extend_from_slice(fixed);
                crate::error::flagged(e, &flag_table(&table, &[(self.to_pose.flags(), "to_pose")]))
            }
            e => scene_error(&self.scene, e),
        }
    }
}

/// How `reach path` times its path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum TimingArg {
    /// Time-optimal under the velocity and acceleration limits.
    Optimal,
    /// One cycloidal segment per edge.
    Cycloidal,
}

/// Arguments of `reach path`.
#[derive(Debug, Clone, Args)]
pub struct PathArgs {
    /// The robot, the scene, --from, and --to or a goal tool pose: with a pose, every
    /// feasible, collision-free IK solution is a goal; the nearest reachable one wins.
    #[command(flatten)]
    pub motion: SceneMotionArgs,

    /// Seed of the planner's random generator.
    #[arg(long, default_value = "1", value_name = "N")]
    pub seed: u64,

    /// Wall-time budget of the search, seconds (the result may depend on the machine's speed
    /// when the budget runs out).
    #[arg(long, default_value = "1", value_name = "S", allow_hyphen_values = true)]
    pub time_budget: String,

    /// Total duration of the timed motion, seconds (cycloidal timing; default: the fastest
    /// synchronised motion within the joints' speed limits, segment by segment).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub duration: Option<String>,

    /// How the path is timed: `optimal` (TOPP-RA under the joints' velocity and acceleration
    /// limits, proven between samples, along the straight edges with their corners blended,
    /// see --blend) or `cycloidal` (one synchronised cycloidal segment per edge, resting at
    /// every waypoint). Default: optimal when no --duration is given and every joint has both
    /// limits, else cycloidal.
    #[arg(long, value_enum, value_name = "LAW")]
    pub timing: Option<TimingArg>,

    /// Optimal timing: how far the motion may pass from each waypoint, cutting the corner with
    /// a parabolic blend so it need not stop (joint-space distance in radians, metres for
    /// prismatic joints; default 0.1, MoveIt's path tolerance; 0 rests at every waypoint).
    /// The blended path is proven clear; a blend that is not is tightened.
    #[arg(long, value_name = "TOL", allow_hyphen_values = true)]
    pub blend: Option<String>,

    /// --max-velocity-scale, --max-acceleration-scale (optimal timing).
    #[command(flatten)]
    pub scales: crate::commands::retime::LimitScaleArgs,

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
        let Ends { scene, from, to, to_pose } = self.motion.ends()?;
        let (max_velocity_scale, max_acceleration_scale) = self.scales.parse()?;
        Ok(PathRequest {
            scene,
            from,
            to,
            to_pose,
            seed: self.seed,
            time_budget_s: parse_finite("--time-budget", &self.time_budget)?,
            duration_s: self.duration.as_deref().map(|d| parse_finite("--duration", d)).transpose()?,
            timing: self.timing.map(|t| match t {
                TimingArg::Optimal => PathTiming::Optimal,
                TimingArg::Cycloidal => PathTiming::Cycloidal,
            }),
            max_velocity_scale,
            max_acceleration_scale,
            blend_tolerance: self.blend.as_deref().map(|b| parse_finite("--blend", b)).transpose()?,
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
    let robot = args.motion.robot.load()?.robot;
    let request = args.request()?;
    args.draw.check_files()?;
    let run = path_run_with_cancel(&robot, &request, crate::interrupt::cancel()).map_err(|e| {
        let [velocity, acceleration] = crate::commands::retime::LimitScaleArgs::FLAGS;
        args.motion.error(
            e,
            &[
                ("duration_s", "--duration"),
                ("time_budget_s", "--time-budget"),
                ("blend_tolerance", "--blend"),
                velocity,
                acceleration,
            ],
        )
    })?;
    if let (true, Some(timed)) = (args.draw.any(), &run.timed) {
        args.draw.write(&drawing(&robot, &run, timed))?;
    }
    let report = &run.report;
    if args.json {
        write_json(out, report)?;
    } else {
        write_report(out, &args.motion.scene, report)?;
    }
    match (&report.reason, report.collision_free) {
        (Some(r), _) => verdict_exit(out, Some(format!("no path: {r}"))),
        (None, Some(false)) => {
            Err(CliError::internal("the path is not proven clear although the planner proved its edges clear"))
        }
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
        let law = match j.timing {
            PathTiming::Optimal => optimal_law_text(
                j.max_velocity_scale,
                j.max_acceleration_scale,
                j.blend_tolerance,
                j.worst_velocity_ratio.as_deref(),
                j.worst_acceleration_ratio.as_deref(),
                "waypoints",
            ),
            PathTiming::Cycloidal => "cycloidal, stops at waypoints".to_string(),
        };
        head.pair("duration", format!("{} s ({law})", fixed(j.duration_s.unwrap_or(0.0), 3)));
        if let Some(p) = &j.swept {
            head.pair("swept check", crate::commands::check::swept_text(&p.swept, Some(p.segment)));
        }
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

/// How a time-optimal motion is timed, in words: its scales, its blends (resting at its
/// `points` without), its worst ratio to a limit.
pub fn optimal_law_text(
    velocity_scale: f64,
    acceleration_scale: f64,
    blend_tolerance: Option<f64>,
    worst_velocity: Option<&[f64]>,
    worst_acceleration: Option<&[f64]>,
    points: &str,
) -> String {
    let worst = |r: Option<&[f64]>| r.iter().copied().flatten().copied().fold(0.0, f64::max);
    let corners = match blend_tolerance {
        Some(t) if t > 0.0 => format!("blends corners within {} rad", number_text(t)),
        _ => format!("rests at {points}"),
    };
    format!(
        "time-optimal under the velocity and acceleration limits ×{velocity_scale} / ×{acceleration_scale}, \
         {corners}; worst ratio to a limit: velocity {}, acceleration {}",
        fixed(worst(worst_velocity), 4),
        fixed(worst(worst_acceleration), 4)
    )
}

fn drawing(robot: &Robot, run: &PathRun, timed: &TimedPath) -> crate::plot::Svg {
    use crate::plot::drawings::{TrajectoryDrawing, joint_series_si, title, trajectory};
    trajectory(&TrajectoryDrawing {
        title: title(
            robot,
            &format!(
                "planned path, {} waypoints, {} s, {}",
                run.waypoints.len(),
                fixed(timed.times.last().copied().unwrap_or(0.0), 3),
                match run.report.timing {
                    PathTiming::Optimal => "time-optimal",
                    PathTiming::Cycloidal => "cycloidal segments",
                }
            ),
        ),
        times: timed.times.clone(),
        joints: joint_series_si(robot, &timed.q, &timed.qd),
        tool: timed.tool_xyz_m.clone(),
        tool_waypoints: run.waypoints_tool_xyz_m.clone(),
        obstacles: &run.scene.obstacles,
    })
}
