//! `reach fk` — forward kinematics: the tool pose for given joint values
//! (`reach::jobs::kinematics::fk`; `--json` prints its report).

use std::io::Write;

use clap::Args;
use reach::jobs::{FkReport, FkRequest};

use crate::error::CliError;
use crate::numbers::{JointArgs, limits_text, q_text};
use crate::output::{Align, Table, fixed, write_json, write_pose};
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

    /// Print the report as JSON (docs/schemas/fk.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Computes and prints the tool pose.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot or joint values; [`CliError::Output`].
pub fn run(args: &FkArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let report = reach::jobs::kinematics::fk(robot, &FkRequest { q: args.joints.joints()? })?;
    if args.json {
        return write_json(out, &report);
    }
    write_text(robot, &report, out)
}

fn write_text(robot: &reach::Robot, report: &FkReport, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints, {})", robot.name(), robot.dof(), robot.convention().as_str()));
    head.pair("q", q_text(robot, &report.q_deg));
    head.pair("limits", limits_text(robot, &report.q_si));
    head.write(out, "")?;
    writeln!(out, "tool pose (world frame):")?;
    write_pose(out, &report.pose, "  ")?;
    writeln!(out, "frame origins [m] (world frame):")?;
    let mut table = Table::new(&[
        ("frame", Align::Right),
        ("joint", Align::Left),
        ("x", Align::Right),
        ("y", Align::Right),
        ("z", Align::Right),
    ]);
    for (i, (f, j)) in report.frames.iter().zip(robot.joints()).enumerate() {
        table.row(vec![(i + 1).to_string(), j.name.clone(), fixed(f[0][3], 6), fixed(f[1][3], 6), fixed(f[2][3], 6)]);
    }
    table.write(out, "  ")
}
