//! `reach dynamics` — inverse-dynamics torques, gravity torques and the joint-space mass
//! matrix at one state (`reach::jobs::dynamics`; `--json` prints its report).

use std::io::Write;

use clap::Args;
use reach::jobs::{DynamicsReport, DynamicsRequest, Joints};

use crate::error::CliError;
use crate::numbers::{JointArgs, limits_text, parse_joint_list, q_text};
use crate::output::{Align, Table, fixed, joint_matrix_table, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach dynamics`.
#[derive(Debug, Clone, Args)]
pub struct DynamicsArgs {
    /// The robot (it needs mass properties: a preset with them, a URDF with `<inertial>`, a
    /// TOML with `[[links]] mass`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Joint rates, one per joint (deg/s, rad/s with --rad; m/s prismatic); zero if absent.
    #[arg(long, value_name = "QD", allow_hyphen_values = true)]
    pub qd: Option<String>,

    /// Joint accelerations, one per joint (deg/s², rad/s² with --rad; m/s² prismatic); zero if
    /// absent.
    #[arg(long, value_name = "QDD", allow_hyphen_values = true)]
    pub qdd: Option<String>,

    /// Print the report as JSON (docs/schemas/dynamics.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Computes and prints the dynamics at one state.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, joint values or rates, or a robot without mass
/// properties; [`CliError::Output`].
pub fn run(args: &DynamicsArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let unit = |values: Vec<f64>| if args.joints.rad { Joints::Rad(values) } else { Joints::Deg(values) };
    let rates = |option: &str, text: &Option<String>| -> Result<Option<Joints>, CliError> {
        text.as_deref().map(|t| parse_joint_list(option, t).map(unit)).transpose()
    };
    let request =
        DynamicsRequest { q: args.joints.joints()?, qd: rates("--qd", &args.qd)?, qdd: rates("--qdd", &args.qdd)? };
    let report = reach::jobs::dynamics::dynamics(robot, &request)?;
    if args.json {
        return write_json(out, &report);
    }
    write_text(robot, &report, out)
}

fn write_text(robot: &reach::Robot, r: &DynamicsReport, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints, {})", robot.name(), robot.dof(), robot.convention().as_str()));
    head.pair("q", q_text(robot, &r.q_deg));
    head.pair("limits", limits_text(robot, &r.q_si));
    let g = r.gravity_m_s2;
    head.pair("gravity", format!("{} {} {} m/s² (world frame)", fixed(g[0], 5), fixed(g[1], 5), fixed(g[2], 5)));
    head.write(out, "")?;
    writeln!(out, "joint torques (N·m revolute, N prismatic; Newton–Euler, rigid bodies, no friction):")?;
    let mut table = Table::new(&[
        ("joint", Align::Left),
        ("qd [SI/s]", Align::Right),
        ("qdd [SI/s²]", Align::Right),
        ("tau", Align::Right),
        ("gravity", Align::Right),
    ]);
    for (i, joint) in robot.joints().iter().enumerate() {
        table.row(vec![
            format!("{} {}", i + 1, joint.name),
            fixed(r.qd_si[i], 6),
            fixed(r.qdd_si[i], 6),
            fixed(r.tau_si[i], 6),
            fixed(r.gravity_tau_si[i], 6),
        ]);
    }
    table.write(out, "  ")?;
    writeln!(out, "mass matrix M(q) (kg·m² between revolute joints; symmetric):")?;
    let rows = r.mass_matrix_si.iter().enumerate().map(|(i, row)| (format!("q{}", i + 1), row.as_slice()));
    joint_matrix_table(robot.dof(), rows).write(out, "  ")
}
