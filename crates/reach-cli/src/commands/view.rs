//! `reach view` — one self-contained HTML file that shows the robot in 3-D
//! (`reach::jobs::view::view` computes every pose; the embedded viewer bundle,
//! `web/dist/viewer.js`, only draws them). The file needs no network: the bundle and the data
//! are inlined. A robot read from a URDF file is drawn with its visual meshes, inlined too.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;
use reach::jobs::view::{ViewCspaceRequest, ViewUrdf};
use reach::jobs::{RobotInput, ViewRequest};

use crate::commands::check::{read_valid_scene, scene_error};
use crate::error::CliError;
use crate::numbers::JointArgs;
use crate::output::{read_file, read_motion_file, write_file};
use crate::pose_arg::PoseFlags;
use crate::robot_arg::{LoadedRobot, RobotArgs, RobotSource};

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
    /// its events and infeasible intervals marked; `-` reads standard input.
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

    /// A C-space section beside the 3-D view: joints I,J (1-based) swept over their limits,
    /// the others fixed at the first state's values; forbidden cells by the scene (needs
    /// --scene), the motion's path in it.
    #[arg(long, value_name = "I,J", value_delimiter = ',', requires = "scene")]
    pub cspace: Option<Vec<usize>>,
    /// Grid step of --cspace, degrees.
    #[arg(long, value_name = "DEG", default_value_t = 5.0, requires = "cspace")]
    pub cspace_step: f64,

    /// URDF robots: draw the chain as link capsules, without the document's meshes (e.g. when
    /// the mesh files are not at hand).
    #[arg(long)]
    pub no_meshes: bool,

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
        urdf: if args.no_meshes { None } else { urdf_with_meshes(args, &loaded)? },
        cspace: match args.cspace.as_deref() {
            None => None,
            Some(&[a, b]) => Some(ViewCspaceRequest { joints: [a, b], step_deg: args.cspace_step }),
            Some(other) => {
                return Err(CliError::bad_input(format!("--cspace: two joints I,J, got {}", other.len())));
            }
        },
    };
    let report = reach::jobs::view::view(robot, &request).map_err(|e| match &args.scene {
        Some(path) => scene_error(path, e),
        None => e.into(),
    })?;
    let html = reach::jobs::view::page(&report.robot, &serde_json::to_string(&report)?, false);
    write_file("-o", &args.output, html)?;
    writeln!(
        out,
        "wrote {} ({} states of {} samples, {} events, {} shapes, {} IK ghosts, {} meshes)",
        args.output.display(),
        report.states.len(),
        report.samples_total,
        report.events.len(),
        report.shapes.len(),
        report.ghosts.len(),
        report.urdf.as_ref().map_or(0, |u| u.meshes.len())
    )?;
    Ok(())
}

/// For a robot read from a URDF file: the document (as read for the robot) with every visual
/// mesh it references, read from disk ([`reach::model::mesh_file_path`] resolves the addresses); `None` for other
/// robots.
fn urdf_with_meshes(args: &ViewArgs, loaded: &LoadedRobot) -> Result<Option<ViewUrdf>, CliError> {
    let (RobotSource::File { path, .. }, RobotInput::Urdf { text, .. }) = (&loaded.source, &loaded.input) else {
        return Ok(None);
    };
    let urdf = ViewUrdf::read(text, &args.robot.urdf_chain(), |filename| {
        let fail = |message: String| reach::Error::File { what: "mesh file", message };
        let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.clone());
        let file = reach::model::mesh_file_path(&canonical, filename, &|d: &std::path::Path| d.is_dir())
            .map_err(|why| fail(format!("`{filename}`: {why}")))?;
        std::fs::read(&file).map_err(|e| fail(format!("`{filename}` ({}): {e}", file.display())))
    })
    .map_err(|e| {
        CliError::bad_input(format!(
            "{}: {} (--no-meshes draws the arm without its meshes)",
            path.display(),
            reach::one_line(&e.to_string())
        ))
    })?;
    Ok(Some(urdf))
}
