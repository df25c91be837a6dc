//! `reach ik` — inverse kinematics (`reach::jobs::ik::ik`; `--json` prints its report): every
//! solution for a tool pose (or position), or the one closest to the current configuration,
//! or the one a multi-criteria method ranks first; and, for seed 000's planar arm, the
//! thesis's table of configurations (`--scan`, `reach::jobs::ik::ik_scan`).
//!
//! Units on the command line: metres, degrees (prismatic joints in metres). Orientation:
//! `--rpy r,p,y` (degrees, radians with `--rad`) with `R = Rz(yaw)·Ry(pitch)·Rx(roll)`,
//! `--quat w,x,y,z`, or `--matrix` (16 numbers, row-major, last row `0 0 0 1`).
//!
//! Exit status: 0 when a solution within the joint limits exists; 3 when the target has none
//! (unreachable, singular, outside the limits, orientation unreachable, no convergence) — the
//! report is still printed on stdout and the reason goes to stderr as one line; 2 for bad
//! input (including a `--solver` that does not fit the robot).

use std::io::Write;

use clap::{ArgGroup, Args};
use reach::jobs::ik::{CHOICE_FIELDS, IkChoice, IkChoiceMethod, IkCriterionName, parse_solver};
use reach::jobs::{IkRequest, IkScanRequest, Joints, Pose};

pub use super::ik_render::demo;
use super::ik_render::{write_report, write_scan, write_scan_csv};
use crate::error::CliError;
use crate::numbers::{parse_count, parse_exact, parse_finite, parse_list};
use crate::output::{verdict_exit, write_json};
use crate::pose_arg::{PoseFlags, joints_arg};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach ik`.
#[derive(Debug, Clone, Args)]
#[command(group(ArgGroup::new("target").required(true).args(["xyz", "matrix"])))]
pub struct IkArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Tool position x,y,z in metres (world frame). Without --rpy or --quat the orientation
    /// is free.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub xyz: Option<String>,

    /// Tool orientation roll,pitch,yaw in degrees (radians with --rad),
    /// R = Rz(yaw)·Ry(pitch)·Rx(roll).
    #[arg(long, value_name = "R,P,Y", allow_hyphen_values = true, requires = "xyz", conflicts_with = "matrix")]
    pub rpy: Option<String>,

    /// --rpy and --from are in radians instead of degrees.
    #[arg(long)]
    pub rad: bool,

    /// Tool orientation as a unit quaternion w,x,y,z (normalised).
    #[arg(long, value_name = "W,X,Y,Z", allow_hyphen_values = true, requires = "xyz", conflicts_with_all = ["matrix", "rpy"])]
    pub quat: Option<String>,

    /// Tool pose as a 4x4 homogeneous matrix, 16 numbers row-major (metres).
    #[arg(long, value_name = "M11,..,M44", allow_hyphen_values = true, conflicts_with = "xyz")]
    pub matrix: Option<String>,

    /// List every solution, within the joint limits or not.
    #[arg(long)]
    pub all: bool,

    /// With --all: list at most N solutions, evenly spaced in the solver's order (a redundant
    /// arm's self-motion parameter), always with the chosen one.
    #[arg(long, value_name = "N", requires = "all", conflicts_with = "choose")]
    pub max: Option<String>,

    /// The current configuration q1,..,qn (degrees, radians with --rad; prismatic in metres);
    /// default: home.
    /// The chosen solution is the one closest to it.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub from: Option<String>,

    /// Weights w1,..,wn of the joint changes Σ wᵢ·|qᵢ − fromᵢ| (the closest-solution rule and
    /// the `change` criterion; default: all 1).
    #[arg(long, value_name = "W1,..,WN", allow_hyphen_values = true)]
    pub joint_weights: Option<String>,

    /// Choose among the solutions within limits by several criteria: topsis, vikor,
    /// weighted-sum or pareto (the non-dominated ones; among them the least joint change).
    /// Default without --choose: the least joint change.
    #[arg(long, value_name = "METHOD")]
    pub choose: Option<String>,

    /// With --choose: the criteria, comma-separated, from change (Σ wᵢ·|qᵢ − fromᵢ| [rad],
    /// less), limits (smallest normalised distance to a joint limit, more), manipulability
    /// (Yoshikawa, more), sigma_min (smallest singular value, more), stiffness (σmin/σmax of
    /// the position Jacobian, more), accuracy (σmax of the position Jacobian × 0.01° [m],
    /// less). Default: change,limits,manipulability.
    #[arg(long, value_name = "C1,..,CK", requires = "choose")]
    pub criteria: Option<String>,

    /// With --choose (not pareto): one weight per criterion, >= 0, not all 0 (normalised to
    /// sum 1). Default: equal weights.
    #[arg(long, value_name = "W1,..,WK", allow_hyphen_values = true, requires = "choose")]
    pub weights: Option<String>,

    /// Solver name (auto, planar, yaw-two-link, yaw-planar3, two-link-wrist,
    /// spherical-wrist, parallel-axes, numeric); default: auto-detected.
    #[arg(long, value_name = "NAME")]
    pub solver: Option<String>,

    /// Redundant arms: the free parameter in degrees (planar3: absolute angle of the last
    /// link). Default: sample the self-motion with --step.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub free_angle: Option<String>,

    /// Redundant arms: sampling step of the self-motion in degrees (default 1).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub step: Option<String>,

    /// Numeric solver: number of starts (default 16).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub restarts: Option<String>,

    /// Numeric solver: wall-time budget in seconds (default: none; the result then depends on
    /// the machine's speed).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub time_budget: Option<String>,

    /// Planar arm (seed 000): print the thesis's table of configurations for the position
    /// --xyz, alpha from alpha_min to 180 in steps of DEG, and the row with the least S. For 4
    /// to 6 links (`planar4`): joints 3..n stepped over their limits by DEG, the configuration
    /// with the least S chosen (the table is counted, not listed;
    /// docs/schemas/planar_scan.report.schema.json).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, requires = "xyz", conflicts_with_all = ["rpy", "quat", "matrix", "all", "solver", "free_angle", "step", "restarts", "time_budget", "joint_weights", "choose"])]
    pub scan: Option<String>,

    /// With --scan: also write the full table as CSV to FILE.
    #[arg(long, value_name = "FILE", requires = "scan")]
    pub csv: Option<std::path::PathBuf>,

    /// Print the report as JSON (docs/schemas/ik.report.schema.json; with --scan
    /// docs/schemas/ik_scan.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Where the request's fields come from on the command line, for messages.
const FLAGS: [(&str, &str); 17] = [
    ("target.xyz_m", "--xyz"),
    ("target.rpy_deg", "--rpy"),
    ("target.rpy_rad", "--rpy"),
    ("target.quat_wxyz", "--quat"),
    ("target.matrix", "--matrix"),
    ("from", "--from"),
    ("joint_weights", "--joint-weights"),
    ("choose.method", "--choose"),
    ("choose.criteria", "--criteria"),
    ("choose.weights", "--weights"),
    ("choose", "--choose"),
    ("solver", "--solver"),
    ("free_angle_deg", "--free-angle"),
    ("step_deg", "--step"),
    ("max_solutions", "--max"),
    ("numeric.restarts", "--restarts"),
    ("numeric.time_budget_s", "--time-budget"),
];

/// Runs `reach ik`.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments or a solver that does not fit the robot;
/// [`CliError::NoSolution`] (after the report was written and flushed to `out`) when no
/// solution is within limits; [`CliError::Output`].
pub fn run(args: &IkArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let from = args.from.as_deref().map(|t| joints_arg("--from", t, args.rad)).transpose()?;
    if let Some(step) = &args.scan
        && robot.dof() != 3
    {
        if args.csv.is_some() {
            return Err(CliError::bad_input("--csv: the table of a planar arm of 4 or more links is not stored"));
        }
        let xyz = parse_exact("--xyz", args.xyz.as_deref().unwrap_or_default(), 3, "x,y,z in metres")?;
        let request = reach::jobs::PlanarScanRequest {
            xyz_m: [xyz[0], xyz[1], xyz[2]],
            step_deg: parse_finite("--scan", step)?,
            from,
        };
        let scan_flags = [("step_deg", "--scan"), ("xyz_m", "--xyz"), ("from", "--from")];
        let report = reach::jobs::planar_scan::planar_scan(robot, &request)
            .map_err(|e| crate::error::flagged(e, &scan_flags))?;
        if args.json {
            write_json(out, &report)?;
        } else {
            super::ik_render::write_planar_scan(out, &report)?;
        }
        return verdict_exit(out, report.reason);
    }
    if let Some(step) = &args.scan {
        let xyz = parse_exact("--xyz", args.xyz.as_deref().unwrap_or_default(), 3, "x,y,z in metres")?;
        let request = IkScanRequest { xyz_m: [xyz[0], xyz[1], xyz[2]], step_deg: parse_finite("--scan", step)?, from };
        let scan_flags = [("step_deg", "--scan"), ("xyz_m", "--xyz"), ("from", "--from")];
        let report = reach::jobs::ik::ik_scan(robot, &request).map_err(|e| crate::error::flagged(e, &scan_flags))?;
        if let Some(path) = &args.csv {
            let mut table = Vec::new();
            write_scan_csv(&mut table, &report)?;
            crate::output::write_file("--csv", path, table)?;
        }
        if args.json {
            write_json(out, &report)?;
        } else {
            write_scan(out, robot, &report, args.from.is_some())?;
        }
        return verdict_exit(out, report.reason);
    }
    let request = request_of(args, from)?;
    let report = reach::jobs::ik::ik_with_cancel(robot, &request, crate::interrupt::cancel())
        .map_err(|e| crate::error::flagged(e, &FLAGS))?;
    if args.json {
        write_json(out, &report)?;
    } else {
        write_report(out, robot, &report, args)?;
    }
    verdict_exit(out, report.reason)
}

/// The target from `--xyz` (+ `--rpy`/`--rad` or `--quat`) or `--matrix`.
fn pose_of(args: &IkArgs) -> Result<Pose, CliError> {
    PoseFlags {
        prefix: "",
        xyz: args.xyz.as_deref(),
        rpy: args.rpy.as_deref(),
        quat: args.quat.as_deref(),
        matrix: args.matrix.as_deref(),
    }
    .pose(args.rad)
}

/// The request from the arguments (`from` parsed already).
fn request_of(args: &IkArgs, from: Option<Joints>) -> Result<IkRequest, CliError> {
    let mut request = IkRequest::new(pose_of(args)?);
    request.all = args.all;
    request.from = from;
    request.joint_weights = args.joint_weights.as_deref().map(|t| parse_list("--joint-weights", t)).transpose()?;
    request.solver = args
        .solver
        .as_deref()
        .map(|name| parse_solver("solver", name))
        .transpose()
        .map_err(|e| crate::error::flagged(e, &FLAGS))?
        .flatten();
    if let Some(method) = &args.choose {
        let [method_field, criteria_field, _] = CHOICE_FIELDS;
        let parse = || -> Result<IkChoice, reach::Error> {
            let method = IkChoiceMethod::parse(method_field, method)?;
            let criteria = match &args.criteria {
                None => vec![IkCriterionName::Change, IkCriterionName::Limits, IkCriterionName::Manipulability],
                Some(text) => text
                    .split(',')
                    .map(|name| IkCriterionName::parse(criteria_field, name))
                    .collect::<Result<_, _>>()?,
            };
            Ok(IkChoice { method, criteria, weights: None })
        };
        let mut choice = parse().map_err(|e| crate::error::flagged(e, &FLAGS))?;
        choice.weights = args.weights.as_deref().map(|t| parse_list("--weights", t)).transpose()?;
        request.choose = Some(choice);
    }
    request.free_angle_deg = args.free_angle.as_deref().map(|t| parse_finite("--free-angle", t)).transpose()?;
    request.step_deg = args.step.as_deref().map(|t| parse_finite("--step", t)).transpose()?;
    request.max_solutions = args.max.as_deref().map(|t| parse_count("--max", t)).transpose()?;
    request.numeric.restarts = args.restarts.as_deref().map(|t| parse_count("--restarts", t)).transpose()?;
    request.numeric.time_budget_s =
        args.time_budget.as_deref().map(|t| parse_finite("--time-budget", t)).transpose()?;
    Ok(request)
}
