//! `reach fk` — forward kinematics: the tool pose for given joint values.

use std::io::Write;

use clap::Args;
use serde::Serialize;

use crate::error::CliError;
use crate::numbers::{JointArgs, joints_outside_limits, limits_text, q_text};
use crate::output::{Align, Matrix4Rows, PoseJson, Table, fixed, matrix_rows_m, write_json, write_pose};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach fk`.
#[derive(Debug, Clone, Args)]
pub struct FkArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Print JSON: {"robot", "q_deg", "q_si", "outside_limits", "pose", "frames"}.
    #[arg(long)]
    pub json: bool,
}

/// The JSON output of `reach fk`.
#[derive(Debug, Clone, Serialize)]
pub struct FkJson {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint values in SI: radians, metres.
    pub q_si: Vec<f64>,
    /// 1-based numbers of the joints outside their limits (FK is computed regardless).
    pub outside_limits: Vec<usize>,
    /// Tool pose in the world frame.
    pub pose: PoseJson,
    /// Every link frame in the world frame (one per joint, see `Robot::frames`), row-major.
    pub frames: Vec<Matrix4Rows>,
}

/// Computes and prints the tool pose.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot or joint values; [`CliError::Output`].
pub fn run(args: &FkArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let values = args.joints.resolve(robot)?;
    let q = &values.si;
    let pose = robot.fk(q)?;
    let frames = robot.frames(q)?;
    if args.json {
        return write_json(
            out,
            &FkJson {
                robot: robot.name().to_string(),
                q_deg: values.deg.clone(),
                q_si: q.clone(),
                outside_limits: joints_outside_limits(robot, q),
                pose: PoseJson::of(&pose),
                frames: frames.iter().map(matrix_rows_m).collect(),
            },
        );
    }
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints, {})", robot.name(), robot.dof(), robot.convention().as_str()));
    head.pair("q", q_text(robot, &values.deg));
    head.pair("limits", limits_text(robot, q));
    head.write(out, "")?;
    writeln!(out, "tool pose (world frame):")?;
    write_pose(out, &pose, "  ")?;
    writeln!(out, "frame origins [m] (world frame):")?;
    let mut table = Table::new(&[
        ("frame", Align::Right),
        ("joint", Align::Left),
        ("x", Align::Right),
        ("y", Align::Right),
        ("z", Align::Right),
    ]);
    for (i, (f, j)) in frames.iter().zip(robot.joints()).enumerate() {
        let p = f.translation.vector;
        table.row(vec![(i + 1).to_string(), j.name.clone(), fixed(p.x, 6), fixed(p.y, 6), fixed(p.z, 6)]);
    }
    table.write(out, "  ")
}
