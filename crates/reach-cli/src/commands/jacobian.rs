//! `reach jacobian` — the geometric Jacobian and manipulability measures.

use std::io::Write;

use clap::Args;
use reach::kinematics::JacobianAxes;
use reach::{Jacobian, Manipulability};
use serde::Serialize;

use crate::error::CliError;
use crate::numbers::{JointArgs, limits_text, q_text};
use crate::output::{Align, Table, fixed, fixeds, write_json};
use crate::robot_arg::RobotArgs;

/// Row labels of the Jacobian.
pub const ROWS: [&str; 6] = ["vx", "vy", "vz", "wx", "wy", "wz"];

/// Arguments of `reach jacobian`.
#[derive(Debug, Clone, Args)]
pub struct JacobianArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Print JSON: {"robot", "q_deg", "q_si", "rows", "jacobian", "manipulability",
    /// "sigma_min", "sigma_max", "condition", "rank", "max_rank", "singular_values"}.
    #[arg(long)]
    pub json: bool,
}

/// The JSON output of `reach jacobian`.
#[derive(Debug, Clone, Serialize)]
pub struct JacobianJson {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// Joint values in SI: radians, metres.
    pub q_si: Vec<f64>,
    /// Row labels, `vx vy vz wx wy wz`.
    pub rows: [&'static str; 6],
    /// The 6×n geometric Jacobian, row-major (world frame, tool point, SI units).
    pub jacobian: Vec<Vec<f64>>,
    /// Yoshikawa's measure, the product of the singular values.
    pub manipulability: f64,
    /// Smallest singular value.
    pub sigma_min: f64,
    /// Largest singular value.
    pub sigma_max: f64,
    /// `sigma_max / sigma_min`, `null` at a singularity (infinite).
    pub condition: Option<f64>,
    /// Numerical rank.
    pub rank: usize,
    /// Largest possible rank, `min(6, n)`.
    pub max_rank: usize,
    /// Singular values, largest first.
    pub singular_values: Vec<f64>,
}

/// Computes and prints the Jacobian and its measures.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot or joint values; [`CliError::Output`].
pub fn run(args: &JacobianArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let values = args.joints.resolve(robot)?;
    let q = &values.si;
    let jac = robot.jacobian(q)?;
    let m = Manipulability::of(&jac, JacobianAxes::All);
    let max_rank = robot.dof().min(6);
    if args.json {
        return write_json(
            out,
            &JacobianJson {
                robot: robot.name().to_string(),
                q_deg: values.deg.clone(),
                q_si: q.clone(),
                rows: ROWS,
                jacobian: rows_of(&jac),
                manipulability: m.yoshikawa,
                sigma_min: m.sigma_min,
                sigma_max: m.sigma_max,
                condition: m.condition.is_finite().then_some(m.condition),
                rank: m.rank,
                max_rank,
                singular_values: m.singular_values.clone(),
            },
        );
    }
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints, {})", robot.name(), robot.dof(), robot.convention().as_str()));
    head.pair("q", q_text(robot, &values.deg));
    head.pair("limits", limits_text(robot, q));
    head.write(out, "")?;
    writeln!(
        out,
        "Jacobian (geometric, world frame, tool point; rows vx vy vz in m/s and wx wy wz in rad/s \
         per unit speed of each joint, rad/s or m/s):"
    )?;
    let headers: Vec<String> = (1..=robot.dof()).map(|i| format!("q{i}")).collect();
    let mut columns = vec![("", Align::Left)];
    columns.extend(headers.iter().map(|h| (h.as_str(), Align::Right)));
    let mut table = Table::new(&columns);
    for (label, row) in ROWS.iter().zip(rows_of(&jac)) {
        let mut cells = vec![(*label).to_string()];
        cells.extend(row.iter().map(|&v| fixed(v, 6)));
        table.row(cells);
    }
    table.write(out, "  ")?;
    let mut measures = Table::key_value();
    measures.pair("manipulability", format!("{} (Yoshikawa, product of the singular values)", fixed(m.yoshikawa, 6)));
    measures.pair("sigma_min", fixed(m.sigma_min, 6));
    measures.pair("sigma_max", fixed(m.sigma_max, 6));
    let condition = if m.condition.is_finite() { fixed(m.condition, 3) } else { "infinite (singular)".to_string() };
    measures.pair("condition", condition);
    let rank = if m.rank < max_rank {
        format!("{} of {max_rank} (singular)", m.rank)
    } else {
        format!("{} of {max_rank}", m.rank)
    };
    measures.pair("rank", rank);
    measures.pair("singular values", fixeds(&m.singular_values, 6));
    measures.write(out, "")
}

/// The matrix as rows of columns.
fn rows_of(jac: &Jacobian) -> Vec<Vec<f64>> {
    (0..jac.nrows()).map(|r| (0..jac.ncols()).map(|c| jac[(r, c)]).collect()).collect()
}
