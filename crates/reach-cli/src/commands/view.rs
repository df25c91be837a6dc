//! `reach view` — one self-contained HTML file that shows the robot in 3-D
//! (`reach::jobs::view::view` computes every pose; the embedded viewer bundle,
//! `web/dist/viewer.js`, only draws them). The file needs no network: the bundle and the data
//! are inlined.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;
use reach::jobs::ViewRequest;

use crate::commands::check::{read_valid_scene, scene_error};
use crate::error::CliError;
use crate::numbers::JointArgs;
use crate::output::{read_file, read_motion_file, write_file};
use crate::pose_arg::PoseFlags;
use crate::robot_arg::RobotArgs;

/// Arguments of `reach view`.
#[derive(Debug, Clone, Args)]
pub struct ViewArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The configuration shown (default: home) when there is no motion.
    #[command(flatten)]
    pub joints: JointArgs,

    /// A motion file (`reach move --json`'s output): its samples are played on the timeline,
    /// its events and infeasible intervals marked.
    #[arg(long, value_name = "REPORT.json", conflicts_with = "plan")]
    pub motion: Option<PathBuf>,

    /// A task file (TOML, docs/task-format.md) planned for ROBOT; its motions are played one
    /// after the other.
    #[arg(long, value_name = "TASK.toml")]
    pub plan: Option<PathBuf>,

    /// A scene file (TOML, docs/scene-format.md): obstacles and tool zone are drawn (and a
    /// --plan is checked against it).
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<String>,

    /// IK target position x,y,z in metres: every IK solution is drawn as a ghost arm.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub ik_xyz: Option<String>,
    /// IK target orientation roll,pitch,yaw in degrees (radians with --rad).
    #[arg(long, value_name = "R,P,Y", allow_hyphen_values = true, requires = "ik_xyz")]
    pub ik_rpy: Option<String>,
    /// IK target orientation as a unit quaternion w,x,y,z.
    #[arg(long, value_name = "W,X,Y,Z", allow_hyphen_values = true, requires = "ik_xyz", conflicts_with = "ik_rpy")]
    pub ik_quat: Option<String>,

    /// The HTML file to write.
    #[arg(short = 'o', long = "output", value_name = "FILE.html")]
    pub output: PathBuf,
}

/// Builds the view and writes the HTML file; prints one line naming it.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, joint values, motion, task, scene or target;
/// [`CliError::Output`].
pub fn run(args: &ViewArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let scene = args.scene.as_deref().map(read_valid_scene).transpose()?;
    let (samples, events) = match &args.motion {
        Some(path) => {
            let events = reach::jobs::view::parse_motion_events(&read_file(path)?)
                .map_err(|e| CliError::bad_input(format!("{}: {}", path.display(), reach::one_line(&e.to_string()))))?;
            (Some(read_motion_file(path)?), events)
        }
        None => (None, Vec::new()),
    };
    let ik = PoseFlags {
        prefix: "ik-",
        xyz: args.ik_xyz.as_deref(),
        rpy: args.ik_rpy.as_deref(),
        quat: args.ik_quat.as_deref(),
        matrix: None,
    };
    let request = ViewRequest {
        q: if args.joints.q.is_empty() { None } else { Some(args.joints.joints()?) },
        samples,
        events,
        task: args.plan.as_deref().map(read_file).transpose()?,
        scene: scene.clone(),
        ik_target: if ik.given() { Some(ik.pose(args.joints.rad)?) } else { None },
    };
    let report = reach::jobs::view::view(robot, &request).map_err(|e| match &args.scene {
        Some(path) => scene_error(path, e),
        None => e.into(),
    })?;
    let html = reach::jobs::view::page(&report.robot, &serde_json::to_string(&report)?, false);
    write_file("-o", &args.output, html)?;
    writeln!(
        out,
        "wrote {} ({} states of {} samples, {} events, {} shapes, {} IK ghosts)",
        args.output.display(),
        report.states.len(),
        report.samples_total,
        report.events.len(),
        report.shapes.len(),
        report.ghosts.len()
    )?;
    Ok(())
}
