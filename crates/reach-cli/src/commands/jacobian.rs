//! `reach jacobian` — the geometric Jacobian and manipulability measures
//! (`reach::jobs::kinematics::jacobian`; `--json` prints its report).

use std::io::Write;

use clap::Args;
use reach::jobs::{JacobianReport, JacobianRequest};

use crate::error::CliError;
use crate::numbers::{JointArgs, limits_text, q_text};
use crate::output::{Table, fixed, fixeds, joint_matrix_table, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach jacobian`.
#[derive(Debug, Clone, Args)]
pub struct JacobianArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Print the report as JSON (docs/schemas/jacobian.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Computes and prints the Jacobian and its measures.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot or joint values; [`CliError::Output`].
pub fn run(args: &JacobianArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let report = reach::jobs::kinematics::jacobian(robot, &JacobianRequest { q: args.joints.joints()? })?;
    if args.json {
        return write_json(out, &report);
    }
    write_text(robot, &report, out)
}

fn write_text(robot: &reach::Robot, r: &JacobianReport, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints, {})", robot.name(), robot.dof(), robot.convention().as_str()));
    head.pair("q", q_text(robot, &r.q_deg));
    head.pair("limits", limits_text(robot, &r.q_si));
    head.write(out, "")?;
    writeln!(
        out,
        "Jacobian (geometric, world frame, tool point; rows vx vy vz in m/s and wx wy wz in rad/s \
         per unit speed of each joint, rad/s or m/s):"
    )?;
    let rows = r.rows.iter().cloned().zip(r.jacobian.iter().map(Vec::as_slice));
    joint_matrix_table(robot.dof(), rows).write(out, "  ")?;
    let mut measures = Table::key_value();
    measures
        .pair("manipulability", format!("{} (Yoshikawa, product of the singular values)", fixed(r.manipulability, 6)));
    measures.pair("sigma_min", fixed(r.sigma_min, 6));
    measures.pair("sigma_max", fixed(r.sigma_max, 6));
    measures.pair("condition", r.condition.map_or_else(|| "infinite (singular)".to_string(), |c| fixed(c, 3)));
    let singular = if r.rank < r.max_rank { " (singular)" } else { "" };
    measures.pair("rank", format!("{} of {}{singular}", r.rank, r.max_rank));
    measures.pair("singular values", fixeds(&r.singular_values, 6));
    measures.write(out, "")
}
