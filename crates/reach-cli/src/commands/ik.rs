//! `reach ik` — inverse kinematics: every solution for a tool pose (or position), or the one
//! closest to the current configuration; and, for seed 000's planar arm, the thesis's table
//! of configurations (`--scan`).
//!
//! Units on the command line: metres, degrees (prismatic joints in metres). Orientation:
//! `--rpy r,p,y` with `R = Rz(yaw)·Ry(pitch)·Rx(roll)`, or `--matrix` (16 numbers, row-major,
//! last row `0 0 0 1`, orthonormal rotation within `tolerance::ROTATION_ORTHONORMALITY`).
//!
//! Exit status: 0 when a solution within the joint limits exists; 3 when the target has none
//! (unreachable, singular, outside the limits, orientation unreachable, no convergence) — the
//! report is still printed on stdout and the reason goes to stderr as one line; 2 for bad
//! input (including a `--solver` that does not fit the robot).

use std::io::Write;

use clap::{ArgGroup, Args};
use nalgebra::{Isometry3, Matrix3, Matrix4, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use reach::Robot;
use reach::decide::{Criterion, DecideError, IkCriterion, Method, VikorAcceptance, ik_matrix, rank};
use reach::ik::planar::{PaperScan, PlanarRedundant, ScanRow};
use reach::ik::{IkError, IkFailure, IkOptions, IkSolution, IkSolutions, IkTarget, SolverKind};
use reach::model::JointKind;
use reach::model::seed000::PlanarPaperAngles;
use reach::tolerance::{IK_POSITION, ROTATION_ORTHONORMALITY};
use serde::Serialize;

use crate::error::{CliError, one_line};
use crate::numbers::{AngleUnit, display_unit, from_si, parse_finite, parse_joint_values, q_display, q_text};
use crate::output::{Align, Table, fixed, fixeds, num, nums, write_json};
use crate::robot_arg::{RobotArgs, load_preset};

/// Arguments of `reach ik`.
#[derive(Debug, Clone, Args)]
#[command(group(ArgGroup::new("target").required(true).args(["xyz", "matrix"])))]
pub struct IkArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Tool position x,y,z in metres (world frame). Without --rpy the orientation is free.
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true)]
    pub xyz: Option<String>,

    /// Tool orientation roll,pitch,yaw in degrees, R = Rz(yaw)·Ry(pitch)·Rx(roll).
    #[arg(long, value_name = "R,P,Y", allow_hyphen_values = true, requires = "xyz", conflicts_with = "matrix")]
    pub rpy: Option<String>,

    /// Tool pose as a 4x4 homogeneous matrix, 16 numbers row-major (metres).
    #[arg(long, value_name = "M11,..,M44", allow_hyphen_values = true, conflicts_with = "xyz")]
    pub matrix: Option<String>,

    /// List every solution, within the joint limits or not.
    #[arg(long)]
    pub all: bool,

    /// The current configuration q1,..,qn (degrees; prismatic in metres); default: home.
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
    /// (Yoshikawa, more), sigma_min (smallest singular value, more). Default:
    /// change,limits,manipulability.
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

    /// Planar arm (seed 000): print the thesis's table of configurations for the position
    /// --xyz, alpha from alpha_min to 180 in steps of DEG, and the row with the least S.
    #[arg(long, value_name = "DEG", allow_hyphen_values = true, requires = "xyz", conflicts_with_all = ["rpy", "matrix", "all", "json", "solver", "free_angle", "step", "restarts", "joint_weights", "choose"])]
    pub scan: Option<String>,

    /// With --scan: print the full table as CSV.
    #[arg(long, requires = "scan")]
    pub csv: bool,

    /// Print JSON: {"robot", "solver", "status", "reason", "solutions", "chosen"}.
    #[arg(long)]
    pub json: bool,
}

/// The JSON output of `reach ik`.
#[derive(Debug, Clone, Serialize)]
pub struct IkJson {
    /// Robot name.
    pub robot: String,
    /// Name of the solver used.
    pub solver: String,
    /// `ok`, or why there is no solution within limits: `unreachable`, `singular`,
    /// `outside_limits`, `orientation_unreachable`, `no_convergence`.
    pub status: String,
    /// The reason in words (`null` when the status is `ok`).
    pub reason: Option<String>,
    /// With `--all`, or when no solution is within limits: every solution found; otherwise
    /// the chosen one only.
    pub solutions: Vec<SolutionJson>,
    /// Index of the chosen solution in `solutions` (`null` when none is within limits).
    pub chosen: Option<usize>,
    /// With `--choose`: the ranking of the solutions within limits (`solutions` then lists
    /// every solution).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ranking: Option<RankingJson>,
}

/// The `--choose` ranking in the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct RankingJson {
    /// `topsis`, `vikor`, `weighted-sum` or `pareto`.
    pub method: String,
    /// The criteria, in column order, with the normalised weights.
    pub criteria: Vec<CriterionJson>,
    /// Meaning of `score`.
    pub score: String,
    /// The candidates, best first.
    pub ranked: Vec<RankedJson>,
    /// VIKOR only: acceptance conditions C1/C2 and the compromise set (indices into `solutions`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vikor: Option<VikorAcceptance>,
}

/// One criterion of a ranking.
#[derive(Debug, Clone, Serialize)]
pub struct CriterionJson {
    /// Name.
    pub name: String,
    /// Unit of the raw values.
    pub unit: String,
    /// `more_is_better` or `less_is_better`.
    pub direction: reach::decide::Direction,
    /// Weight, normalised to sum 1 (`null` for pareto).
    pub weight: Option<f64>,
}

/// One ranked solution.
#[derive(Debug, Clone, Serialize)]
pub struct RankedJson {
    /// Index into `solutions`.
    pub solution: usize,
    /// 1-based rank (pareto: 1 for the chosen, then the other non-dominated, then the rest).
    pub rank: usize,
    /// The method's score (`null` for pareto).
    pub score: Option<f64>,
    /// Raw criterion values, in the criteria's units.
    pub values: Vec<f64>,
    /// Normalised values as the method uses them (`null` for pareto).
    pub normalised: Option<Vec<f64>>,
    /// Whether no other candidate is better or equal on every criterion and better on one.
    pub pareto_optimal: bool,
}

/// One solution in the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct SolutionJson {
    /// Joint values: revolute in degrees, prismatic in metres.
    pub q_deg: Vec<f64>,
    /// Branch label, e.g. `shoulder=left elbow=up wrist=noflip`.
    pub branch: String,
    /// Tool position error, metres.
    pub position_error_m: f64,
    /// Tool orientation error, radians.
    pub orientation_error_rad: f64,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
    /// The joints outside their limits.
    pub violations: Vec<ViolationJson>,
    /// Singular configurations the solution sits at: `wrist`, `elbow`, `shoulder`, `jacobian`.
    pub singular: Vec<&'static str>,
}

/// A joint outside its limits, in display units (revolute degrees, prismatic metres).
#[derive(Debug, Clone, Serialize)]
pub struct ViolationJson {
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// The value.
    pub value_deg: f64,
    /// Lower limit (`null` when unbounded).
    pub lower_deg: Option<f64>,
    /// Upper limit (`null` when unbounded).
    pub upper_deg: Option<f64>,
}

/// Runs `reach ik`.
///
/// # Errors
/// [`CliError::BadInput`] for bad arguments or a solver that does not fit the robot;
/// [`CliError::NoSolution`] (after the report was written and flushed to `out`) when no
/// solution is within limits; [`CliError::Output`].
pub fn run(args: &IkArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let from = match &args.from {
        Some(text) => {
            parse_joint_values(robot, &split(text), AngleUnit::Deg)
                .map_err(|e| CliError::bad_input(format!("--from: {e}")))?
                .si
        }
        None => robot.home(),
    };
    if let Some(step) = &args.scan {
        return run_scan(args, robot, &from, step, out);
    }
    let target = target_of(args)?;
    let weights = match &args.joint_weights {
        Some(text) => weights_of(robot, text)?,
        None => vec![1.0; robot.dof()],
    };
    let choice = args.choose.as_deref().map(|m| ChoiceSpec::parse(m, args, &from, &weights)).transpose()?;
    let options = options_of(args, &from)?;
    let (kind, named) = match args.solver.as_deref() {
        None | Some("auto") => (SolverKind::detect(robot), false),
        Some(name) => (SolverKind::parse(name).ok_or_else(|| unknown_solver(name))?, true),
    };
    let solver = kind.build(robot).map_err(ik_error)?;
    let all = solver.solve(robot, &target, &options).map_err(ik_error)?;
    let closest = all.closest_index(&from, &weights);
    let ranking = match &choice {
        Some(c) if closest.is_some() => Some(c.rank(robot, &all)?),
        _ => None,
    };
    let chosen = ranking.as_ref().map_or(closest, |r| r.ranked.first().map(|e| e.solution));
    let shown: Vec<usize> = match chosen {
        Some(i) if !args.all && ranking.is_none() => vec![i],
        _ => (0..all.solutions.len()).collect(),
    };
    if args.json {
        let report = IkJson {
            robot: robot.name().to_string(),
            solver: all.solver.to_string(),
            status: status_of(all.failure.as_ref()),
            reason: all.failure.as_ref().map(|f| one_line(&f.to_string())),
            solutions: shown.iter().map(|&i| solution_json(robot, &all.solutions[i])).collect(),
            chosen: chosen.and_then(|c| shown.iter().position(|&i| i == c)),
            ranking: ranking.clone(),
        };
        write_json(out, &report)?;
    } else {
        let mut head = Table::key_value();
        head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
        head.pair("solver", format!("{} ({})", all.solver, if named { "--solver" } else { "auto-detected" }));
        head.pair("target", target_text(&target));
        let from_note = if args.from.is_some() { "--from" } else { "home" };
        head.pair("from", format!("{} ({from_note})", q_text(robot, &q_display(robot, &from))));
        if args.joint_weights.is_some() {
            head.pair("joint weights", nums(&weights));
        }
        let feasible = all.feasible().count();
        let status = match &all.failure {
            None => format!("ok: {} solution(s), {feasible} within limits", all.solutions.len()),
            Some(f) => format!("{}: {}", status_of(Some(f)), one_line(&f.to_string())),
        };
        head.pair("status", status);
        head.write(out, "")?;
        match chosen {
            Some(i) if ranking.is_some() => {
                if args.all {
                    writeln!(out, "solutions (* = chosen by --choose):")?;
                    write_solution_table(out, robot, &all, chosen, "  ", false)?;
                }
                if let Some(r) = &ranking {
                    write_ranking(out, &all, r)?;
                }
                let method = ranking.as_ref().map_or("", |r| r.method.as_str());
                write_chosen(out, robot, &all.solutions[i], &format!("within limits, rank 1 of --choose {method}"))?;
            }
            Some(i) if !args.all => write_chosen(out, robot, &all.solutions[i], CLOSEST_RULE)?,
            _ if all.solutions.is_empty() => {}
            _ => {
                writeln!(out, "solutions (* = chosen: least Σ wᵢ·|qᵢ − fromᵢ| within limits):")?;
                write_solution_table(out, robot, &all, chosen, "  ", false)?;
            }
        }
    }
    match &all.failure {
        None => Ok(()),
        Some(f) => no_solution(out, one_line(&f.to_string())),
    }
}

/// The report is on stdout already: flush it (the caller discards unflushed output on an
/// error), then fail with exit status 3 and the reason.
fn no_solution(out: &mut dyn Write, reason: String) -> Result<(), CliError> {
    out.flush()?;
    Err(CliError::NoSolution(reason))
}

/// Splits a comma list (blanks around values are allowed).
fn split(text: &str) -> Vec<String> {
    text.split(',').map(|s| s.trim().to_string()).collect()
}

/// Parses a comma list of exactly `count` finite numbers for `option`.
fn number_list(option: &str, text: &str, count: usize, what: &str) -> Result<Vec<f64>, CliError> {
    let parts = split(text);
    if parts.len() != count {
        return Err(CliError::bad_input(format!(
            "{option}: expected {count} comma-separated numbers ({what}), got {}",
            parts.len()
        )));
    }
    parts.iter().enumerate().map(|(i, t)| parse_finite(&format!("{option} value {}", i + 1), t)).collect()
}

/// The IK target given by `--xyz` (+ `--rpy`) or `--matrix`.
fn target_of(args: &IkArgs) -> Result<IkTarget, CliError> {
    if let Some(text) = &args.matrix {
        return Ok(IkTarget::Pose(pose_from_matrix(&number_list("--matrix", text, 16, "a 4x4 matrix, row-major")?)?));
    }
    let Some(text) = &args.xyz else {
        return Err(CliError::bad_input("give the target with --xyz or --matrix"));
    };
    let p = number_list("--xyz", text, 3, "x,y,z in metres")?;
    let point = Point3::new(p[0], p[1], p[2]);
    Ok(match &args.rpy {
        None => IkTarget::Position(point),
        Some(text) => {
            let a = number_list("--rpy", text, 3, "roll,pitch,yaw in degrees")?;
            let rotation = UnitQuaternion::from_euler_angles(a[0].to_radians(), a[1].to_radians(), a[2].to_radians());
            IkTarget::Pose(Isometry3::from_parts(Translation3::from(point.coords), rotation))
        }
    })
}

/// A pose from 16 numbers, row-major: the last row must be exactly `0 0 0 1` and the rotation
/// part orthonormal (`max |RᵀR − I| ≤ ROTATION_ORTHONORMALITY`) with determinant +1.
fn pose_from_matrix(v: &[f64]) -> Result<Isometry3<f64>, CliError> {
    let m = Matrix4::from_row_slice(v);
    let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
    if last != [0.0, 0.0, 0.0, 1.0] {
        return Err(CliError::bad_input(format!("--matrix: the last row must be 0 0 0 1, got {}", nums(&last))));
    }
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    let deviation = (r.transpose() * r - Matrix3::identity()).abs().max();
    if deviation > ROTATION_ORTHONORMALITY {
        return Err(CliError::bad_input(format!(
            "--matrix: the rotation part (rows and columns 1-3) is not orthonormal: max |RᵀR − I| = {deviation:.3e}, \
             more than {ROTATION_ORTHONORMALITY:e}"
        )));
    }
    if r.determinant() < 0.0 {
        return Err(CliError::bad_input(
            "--matrix: the rotation part is a reflection (determinant −1), not a rotation",
        ));
    }
    let translation = Translation3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]);
    // Closed form (Shepperd): `UnitQuaternion::from_matrix`'s iteration starts at the identity
    // and stalls on half-turns (diag(−1, 1, −1) came back as a 0.0155° roll).
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Isometry3::from_parts(translation, rotation))
}

/// `--joint-weights`: one finite, non-negative weight per joint.
fn weights_of(robot: &Robot, text: &str) -> Result<Vec<f64>, CliError> {
    let w = number_list("--joint-weights", text, robot.dof(), "one weight per joint")?;
    // `number_list` checked the count and finiteness: what is left is a negative weight, whose
    // field is `weights[i]` (1-based).
    reach::effort::joint_weights(robot, Some(&w)).map_err(|e| match e {
        reach::effort::EffortError::InvalidValue { field, value, .. } => {
            let i = field.strip_prefix("weights[").and_then(|f| f.strip_suffix(']')).unwrap_or(&field);
            CliError::bad_input(format!("--joint-weights value {i}: must not be negative, got {}", num(value)))
        }
        e => CliError::bad_input(format!("--joint-weights: {e}")),
    })
}

/// The solver options from `--from`, `--free-angle`, `--step`, `--restarts`.
fn options_of(args: &IkArgs, from: &[f64]) -> Result<IkOptions, CliError> {
    let mut options = IkOptions { seed: Some(from.to_vec()), ..IkOptions::default() };
    if let Some(text) = &args.free_angle {
        options.free_parameter = Some(parse_finite("--free-angle", text)?.to_radians());
    }
    if let Some(text) = &args.step {
        let step = parse_finite("--step", text)?;
        if step <= 0.0 {
            return Err(CliError::bad_input(format!("--step: must be a positive angle in degrees, got {text:?}")));
        }
        options.redundancy_step = step.to_radians();
    }
    if let Some(text) = &args.restarts {
        options.restarts = match text.trim().parse::<usize>() {
            Ok(n) if n >= 1 => n,
            _ => return Err(CliError::bad_input(format!("--restarts: expected a whole number ≥ 1, got {text:?}"))),
        };
    }
    Ok(options)
}

fn unknown_solver(name: &str) -> CliError {
    let known: Vec<&str> = std::iter::once("auto").chain(SolverKind::ALL.iter().map(|k| k.as_str())).collect();
    CliError::bad_input(format!("unknown solver `{name}` (known: {})", known.join(", ")))
}

/// IK errors are the user's input (a bad option, a solver that does not fit the robot).
fn ik_error(e: IkError) -> CliError {
    CliError::bad_input(one_line(&e.to_string()))
}

/// The status word: `ok` or the failure's snake_case name (as the library serialises it).
fn status_of(failure: Option<&IkFailure>) -> String {
    let Some(f) = failure else { return "ok".into() };
    serde_json::to_value(f)
        .ok()
        .and_then(|v| v.get("reason").and_then(|r| r.as_str()).map(str::to_string))
        .unwrap_or_else(|| "no_solution".into())
}

fn solution_json(robot: &Robot, s: &IkSolution) -> SolutionJson {
    let display = |joint: usize, v: f64| from_si(robot.joints()[joint - 1].kind, v, AngleUnit::Deg);
    let bound = |joint: usize, v: f64| v.is_finite().then(|| display(joint, v));
    SolutionJson {
        // `+ 0.0` turns −0 into 0.
        q_deg: q_display(robot, &s.q).into_iter().map(|v| v + 0.0).collect(),
        branch: s.branch.to_string(),
        position_error_m: s.position_error,
        orientation_error_rad: s.orientation_error,
        within_limits: s.within_limits,
        violations: s
            .violations
            .iter()
            .map(|v| ViolationJson {
                joint: v.joint,
                name: v.name.clone(),
                value_deg: display(v.joint, v.value),
                lower_deg: bound(v.joint, v.lower),
                upper_deg: bound(v.joint, v.upper),
            })
            .collect(),
        singular: s.singularities.iter().map(|k| k.as_str()).collect(),
    }
}

fn target_text(target: &IkTarget) -> String {
    let p = target.position();
    match target {
        IkTarget::Position(_) => format!("position {} [m], orientation free", fixeds(&[p.x, p.y, p.z], 6)),
        IkTarget::Pose(pose) => {
            let (r, pi, y) = pose.rotation.euler_angles();
            let rpy = [r, pi, y].map(f64::to_degrees);
            format!("position {} [m], rpy {} [deg]", fixeds(&[p.x, p.y, p.z], 6), fixeds(&rpy, 4))
        }
    }
}

/// `within limits`, or the violated joints: `joint 4 (wrist) 170.2 outside -160 .. 160 deg`.
fn limits_cell(robot: &Robot, s: &IkSolution) -> String {
    if s.within_limits {
        return "within limits".into();
    }
    s.violations
        .iter()
        .map(|v| {
            let kind = robot.joints()[v.joint - 1].kind;
            let d = |x: f64| num(from_si(kind, x, AngleUnit::Deg));
            let digits = if kind == JointKind::Revolute { 2 } else { 4 };
            format!(
                "joint {} ({}) {} outside {} .. {} {}",
                v.joint,
                v.name,
                fixed(from_si(kind, v.value, AngleUnit::Deg), digits),
                d(v.lower),
                d(v.upper),
                display_unit(kind)
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// `ok`, or the 1-based numbers of the joints outside their limits: `outside: 4 5`.
fn compact_limits_cell(s: &IkSolution) -> String {
    if s.within_limits {
        return "ok".into();
    }
    let joints: Vec<String> = s.violations.iter().map(|v| v.joint.to_string()).collect();
    format!("joints outside: {}", joints.join(" "))
}

fn singular_cell(s: &IkSolution) -> String {
    if s.singularities.is_empty() {
        "-".into()
    } else {
        s.singularities.iter().map(|k| k.as_str()).collect::<Vec<_>>().join(",")
    }
}

/// Why the solution was chosen without --choose.
const CLOSEST_RULE: &str = "within limits, least Σ wᵢ·|qᵢ − fromᵢ|; --all lists every solution";

fn write_chosen(out: &mut dyn Write, robot: &Robot, s: &IkSolution, why: &str) -> Result<(), CliError> {
    writeln!(out, "chosen ({why}):")?;
    let mut t = Table::key_value();
    t.pair("branch", s.branch.to_string());
    let q = q_display(robot, &s.q);
    t.pair("q", q_text(robot, &q.iter().map(|v| (v * 1e6).round() / 1e6).collect::<Vec<_>>()));
    t.pair("error", format!("position {:.1e} m, orientation {:.1e} rad", s.position_error, s.orientation_error));
    t.pair("limits", limits_cell(robot, s));
    t.pair("singular", singular_cell(s));
    t.write(out, "  ")
}

/// The table of solutions: number (`*` marks `chosen`), branch, q, errors, limits, singular.
fn write_solution_table(
    out: &mut dyn Write,
    robot: &Robot,
    all: &IkSolutions,
    chosen: Option<usize>,
    indent: &str,
    compact: bool,
) -> Result<(), CliError> {
    let units: Vec<&str> = robot.joints().iter().map(|j| display_unit(j.kind)).collect();
    let unit = if units.windows(2).all(|w| w[0] == w[1]) { units.first().copied().unwrap_or("") } else { "deg|m" };
    let q_header = format!("q [{unit}]");
    let mut t = Table::new(&[
        ("#", Align::Right),
        ("branch", Align::Left),
        (q_header.as_str(), Align::Left),
        ("err [m]", Align::Right),
        ("err [rad]", Align::Right),
        ("singular", Align::Left),
        ("limits", Align::Left),
    ]);
    for (i, s) in all.solutions.iter().enumerate() {
        let mark = if chosen == Some(i) { "*" } else { "" };
        let q: Vec<String> = q_display(robot, &s.q).iter().map(|&v| format!("{:>9}", fixed(v, 4))).collect();
        t.row(vec![
            format!("{mark}{}", i + 1),
            s.branch.to_string(),
            q.join(" ").trim_start().to_string(),
            format!("{:.1e}", s.position_error),
            format!("{:.1e}", s.orientation_error),
            singular_cell(s),
            if compact { compact_limits_cell(s) } else { limits_cell(robot, s) },
        ]);
    }
    t.write(out, indent)
}

// ---------------------------------------------------------------------------------------------
// --scan: seed 000's table of configurations.
// ---------------------------------------------------------------------------------------------

/// The thesis's angles of configuration `q` of `arm` (notes 000 §2): `γ = φ1`,
/// `β = φ2 − φ1 + 180°`, `α = φ3 − φ2 + 180°` from the absolute link angles `φ`.
fn paper_angles(arm: &PlanarRedundant, q: &[f64]) -> PlanarPaperAngles {
    let phi = arm.link_angles(&[q[0], q[1], q[2]]);
    let pi = std::f64::consts::PI;
    PlanarPaperAngles { gamma: phi[0], beta: phi[1] - phi[0] + pi, alpha: phi[2] - phi[1] + pi }
}

/// `S` of a row against the start (notes 000 §6.3), radians.
fn s_of(row: &ScanRow, start: &PlanarPaperAngles) -> f64 {
    let p = &row.paper;
    (p.alpha - start.alpha).abs() + (p.beta - start.beta).abs() + (p.gamma - start.gamma).abs()
}

fn run_scan(args: &IkArgs, robot: &Robot, from: &[f64], step: &str, out: &mut dyn Write) -> Result<(), CliError> {
    let arm = PlanarRedundant::from_robot(robot).map_err(ik_error)?;
    let step_deg = parse_finite("--scan", step)?;
    if step_deg <= 0.0 {
        return Err(CliError::bad_input(format!("--scan: the step must be a positive angle in degrees, got {step:?}")));
    }
    let p = number_list("--xyz", args.xyz.as_deref().unwrap_or_default(), 3, "x,y,z in metres")?;
    let (x, y, offset) = arm.plane_coordinates(&Point3::new(p[0], p[1], p[2]));
    let scan = if offset.abs() > IK_POSITION {
        let failure = IkFailure::Unreachable { distance: offset.abs(), reach: 0.0 };
        PaperScan { alpha_min: None, rows: Vec::new(), failure: Some(failure) }
    } else {
        arm.paper_scan([x, y], step_deg.to_radians()).map_err(ik_error)?
    };
    let start = paper_angles(&arm, from);
    let chosen = scan.select_min_s(&start).map(|(i, _)| i);
    let header =
        ["alpha_deg", "beta_deg", "gamma_deg", "q1_deg", "q2_deg", "q3_deg", "S_deg", "within_limits", "chosen"];
    if args.csv {
        writeln!(out, "{}", header.join(","))?;
        for (i, row) in scan.rows.iter().enumerate() {
            let p = &row.paper;
            let mut cells: Vec<String> = [p.alpha, p.beta, p.gamma]
                .into_iter()
                .chain(row.q)
                .chain([s_of(row, &start)])
                .map(|v| format!("{}", v.to_degrees()))
                .collect();
            cells.push(row.within_limits.to_string());
            cells.push((chosen == Some(i)).to_string());
            writeln!(out, "{}", cells.join(","))?;
        }
    } else {
        let within = scan.rows.iter().filter(|r| r.within_limits).count();
        let mut head = Table::key_value();
        head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
        head.pair("method", format!("seed 000 table of configurations (notes 000 §4.1), Δα = {} deg", num(step_deg)));
        head.pair("target", format!("x y = {} [m] in the arm's plane", fixeds(&[x, y], 6)));
        if let Some(a) = scan.alpha_min {
            head.pair("alpha_min", format!("{} deg", fixed(a.to_degrees(), 6)));
        }
        head.pair("rows", format!("{} ({within} within limits)", scan.rows.len()));
        let from_note = if args.from.is_some() { "--from" } else { "home" };
        head.pair(
            "from",
            format!(
                "alpha beta gamma = {} [deg] ({from_note} q = {})",
                fixeds(&[start.alpha, start.beta, start.gamma].map(f64::to_degrees), 6),
                q_text(robot, &q_display(robot, from))
            ),
        );
        let status = match &scan.failure {
            None => "ok".to_string(),
            Some(f) => format!("{}: {}", status_of(Some(f)), one_line(&f.to_string())),
        };
        head.pair("status", status);
        head.write(out, "")?;
        if !scan.rows.is_empty() {
            let mut t = Table::new(&[
                ("", Align::Left),
                ("row", Align::Right),
                ("alpha", Align::Right),
                ("beta", Align::Right),
                ("gamma", Align::Right),
                ("q1", Align::Right),
                ("q2", Align::Right),
                ("q3", Align::Right),
                ("S", Align::Right),
                ("limits", Align::Left),
            ]);
            let last = scan.rows.len() - 1;
            let picks = [("first", Some(0)), ("last", Some(last)), ("chosen", chosen)];
            for (label, index) in picks {
                let Some(i) = index else { continue };
                let row = &scan.rows[i];
                let p = &row.paper;
                let mut cells = vec![label.to_string(), (i + 1).to_string()];
                cells.extend(
                    [p.alpha, p.beta, p.gamma]
                        .into_iter()
                        .chain(row.q)
                        .chain([s_of(row, &start)])
                        .map(|v| fixed(v.to_degrees(), 6)),
                );
                cells.push(if row.within_limits { "within limits" } else { "outside limits" }.to_string());
                t.row(cells);
            }
            writeln!(out, "rows [deg] (chosen: least S = |α − α0| + |β − β0| + |γ − γ0|; --csv prints all):")?;
            t.write(out, "  ")?;
        }
    }
    match &scan.failure {
        None => Ok(()),
        Some(f) => no_solution(out, one_line(&f.to_string())),
    }
}

// ---------------------------------------------------------------------------------------------
// The demo section.
// ---------------------------------------------------------------------------------------------

/// `reach demo`'s IK section: all solutions, with branch labels, for one pose of puma560,
/// the start of seed 003's weld (welder6r) and seed 001's goal pose T1 (spbu6).
///
/// # Errors
/// [`CliError::Output`] when writing fails; [`CliError::Internal`] if a preset or solver breaks.
pub fn demo(out: &mut dyn Write) -> Result<(), CliError> {
    // puma560 at q = (20, −40, 30, 10, 40, −30)°.
    let puma = load_preset("puma560")?.robot;
    let q: Vec<f64> = [20.0, -40.0, 30.0, 10.0, 40.0, -30.0].iter().map(|v: &f64| v.to_radians()).collect();
    let pose = puma.fk(&q)?;
    demo_case(out, &puma, "fk(20, -40, 30, 10, 40, -30 deg)", &pose)?;

    // Seed 003 (notes 003 §5.1–5.2): the weld starts at P = (50, 740, 70) mm towards
    // M = (500, 200, 700) mm; tool x = n = (M − P)/|MP|, y = e6 = (y1 − y2, x2 − x1, 0)/|M1P1|,
    // z = l = n × e6 (n ≈ (0.476731, −0.572078, 0.667424), l ≈ (−0.427274, 0.512729, 0.744678)).
    let welder = load_preset("welder6r")?.robot;
    let (p, m) = (Vector3::new(50.0, 740.0, 70.0), Vector3::new(500.0, 200.0, 700.0));
    let n = (m - p).normalize();
    let e6 = Vector3::new(p.y - m.y, m.x - p.x, 0.0).normalize();
    let l = n.cross(&e6);
    let rotation = UnitQuaternion::from_matrix(&Matrix3::from_columns(&[n, e6, l]));
    let pose = Isometry3::from_parts(Translation3::from(p / 1000.0), rotation);
    demo_case(out, &welder, "seed 003 weld start P = (50, 740, 70) mm, tool x = n, z = l", &pose)?;

    // Seed 001 (notes 001 §5.1): goal pose T1.
    let spbu = load_preset("spbu6")?.robot;
    #[rustfmt::skip]
    let t1 = Matrix4::new(1.0, 0.0, 0.0, 0.0,
                          0.0, 0.0, 1.0, 3.0,
                          0.0, -1.0, 0.0, 5.0,
                          0.0, 0.0, 0.0, 1.0);
    let pose = pose_from_matrix(t1.transpose().as_slice())
        .map_err(|e| CliError::internal(format!("seed 001 T1 is not a pose: {e}")))?;
    demo_case(out, &spbu, "seed 001 goal pose T1", &pose)
}

fn demo_case(out: &mut dyn Write, robot: &Robot, what: &str, pose: &Isometry3<f64>) -> Result<(), CliError> {
    let target = IkTarget::Pose(*pose);
    let all = SolverKind::detect(robot)
        .build(robot)
        .and_then(|s| s.solve(robot, &target, &IkOptions { seed: Some(robot.home()), ..IkOptions::default() }))
        .map_err(|e| CliError::internal(format!("IK of preset `{}`: {}", robot.name(), one_line(&e.to_string()))))?;
    let chosen = all.closest_index(&robot.home(), &[]);
    writeln!(out)?;
    writeln!(out, "{} — {what}", robot.name())?;
    writeln!(out, "  target    {}", target_text(&target))?;
    writeln!(
        out,
        "  solver    {}: {} solutions, {} within limits (* = closest to home)",
        all.solver,
        all.solutions.len(),
        all.feasible().count()
    )?;
    write_solution_table(out, robot, &all, chosen, "  ", true)
}

// ---------------------------------------------------------------------------------------------
// --choose: multi-criteria choice among the solutions within limits.
// ---------------------------------------------------------------------------------------------

/// IK criteria names accepted by `--criteria`.
const IK_CRITERIA: [&str; 4] = ["change", "limits", "manipulability", "sigma_min"];

/// A `--choose` method: a ranking method, or the Pareto filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum ChoiceMethod {
    Rank(Method),
    Pareto,
}

/// `--choose`, `--criteria`, `--weights` (or a task file's `[choose]`), checked.
#[derive(Debug, Clone)]
pub(crate) struct ChoiceSpec {
    method: ChoiceMethod,
    criteria: Vec<IkCriterion>,
    weights: Vec<f64>,
    /// The joint change from --from (pareto's tie-break among the non-dominated).
    change: IkCriterion,
    /// How the method is named in messages (`--choose`, `[choose] method`).
    label: String,
}

impl ChoiceSpec {
    fn parse(method: &str, args: &IkArgs, from: &[f64], joint_weights: &[f64]) -> Result<Self, CliError> {
        let weights = match &args.weights {
            None => None,
            Some(text) => Some(
                split(text)
                    .iter()
                    .enumerate()
                    .map(|(i, t)| parse_finite(&format!("--weights value {}", i + 1), t))
                    .collect::<Result<Vec<f64>, _>>()?,
            ),
        };
        let names = split(args.criteria.as_deref().unwrap_or("change,limits,manipulability"));
        Self::new(method, &names, weights.as_deref(), from, joint_weights, ["--choose", "--criteria", "--weights"])
    }

    /// Checks a method name, criterion names and weights; `labels` name the three inputs in
    /// messages (`--choose`, `--criteria`, `--weights` or a task file's keys).
    pub(crate) fn new(
        method: &str,
        names: &[String],
        weights: Option<&[f64]>,
        from: &[f64],
        joint_weights: &[f64],
        labels: [&str; 3],
    ) -> Result<Self, CliError> {
        let [method_label, criteria_label, weights_label] = labels;
        let method = match method.trim().to_ascii_lowercase().as_str() {
            "pareto" => ChoiceMethod::Pareto,
            m => ChoiceMethod::Rank(Method::parse(m).ok_or_else(|| {
                CliError::bad_input(format!(
                    "{method_label}: unknown method `{method}` (known: topsis, vikor, weighted-sum, pareto)"
                ))
            })?),
        };
        let change = IkCriterion::JointChange { reference: from.to_vec(), weights: joint_weights.to_vec() };
        if names.is_empty() {
            return Err(CliError::bad_input(format!("{criteria_label}: no criteria given")));
        }
        let mut criteria = Vec::with_capacity(names.len());
        for (k, name) in names.iter().enumerate() {
            let c = match name.to_ascii_lowercase().replace('-', "_").as_str() {
                "change" => change.clone(),
                "limits" => IkCriterion::LimitMargin,
                "manipulability" => IkCriterion::Manipulability,
                "sigma_min" => IkCriterion::SigmaMin,
                _ => {
                    return Err(CliError::bad_input(format!(
                        "{criteria_label}: unknown criterion `{name}` (known: {})",
                        IK_CRITERIA.join(", ")
                    )));
                }
            };
            if criteria.contains(&c) || names[..k].iter().any(|n| n.eq_ignore_ascii_case(name)) {
                return Err(CliError::bad_input(format!("{criteria_label}: `{name}` is given twice")));
            }
            criteria.push(c);
        }
        let weights = match (weights, method) {
            (Some(_), ChoiceMethod::Pareto) => {
                return Err(CliError::bad_input(format!("{weights_label}: the pareto filter takes no weights")));
            }
            (Some(w), _) => {
                reach::decide::mcdm::normalise_weights(names, w).map_err(|e| match e {
                    DecideError::WeightCount { expected, found } => CliError::bad_input(format!(
                        "{weights_label}: expected {expected} weights, one per criterion ({}), got {found}",
                        names.join(",")
                    )),
                    DecideError::InvalidWeight { criterion, value } => {
                        let i = names.iter().position(|n| *n == criterion).map_or(0, |i| i + 1);
                        CliError::bad_input(format!(
                            "{weights_label} value {i} ({criterion}): must be finite and not negative, got {}",
                            num(value)
                        ))
                    }
                    DecideError::ZeroWeights => CliError::bad_input(format!("{weights_label}: all weights are zero")),
                    e => CliError::bad_input(format!("{weights_label}: {}", one_line(&e.to_string()))),
                })?;
                w.to_vec()
            }
            (None, _) => vec![1.0; criteria.len()],
        };
        Ok(ChoiceSpec { method, criteria, weights, change, label: method_label.to_string() })
    }

    /// Ranks the solutions within limits; indices refer to `all.solutions`.
    pub(crate) fn rank(&self, robot: &Robot, all: &IkSolutions) -> Result<RankingJson, CliError> {
        let candidates: Vec<usize> = (0..all.solutions.len()).filter(|&i| all.solutions[i].within_limits).collect();
        let solutions: Vec<IkSolution> = candidates.iter().map(|&i| all.solutions[i].clone()).collect();
        let decide = |e: DecideError| CliError::bad_input(format!("{}: {}", self.label, one_line(&e.to_string())));
        let matrix = ik_matrix(robot, &solutions, &self.criteria).map_err(decide)?;
        matrix.reject_zero_columns().map_err(decide)?;
        let describe = |weight: Option<&f64>, c: &Criterion| CriterionJson {
            name: c.name.clone(),
            unit: c.unit.clone(),
            direction: c.direction,
            weight: weight.copied(),
        };
        match self.method {
            ChoiceMethod::Rank(method) => {
                let ranking = rank(&matrix, &self.weights, method).map_err(decide)?;
                Ok(RankingJson {
                    method: method.as_str().into(),
                    criteria: ranking
                        .criteria
                        .iter()
                        .zip(&ranking.weights)
                        .map(|(c, w)| describe(Some(w), c))
                        .collect(),
                    score: match method {
                        Method::WeightedSum => "weighted sum of min-max scores (1 = best), higher is better",
                        Method::Topsis => "closeness C = d-/(d+ + d-) to the ideal, higher is better",
                        Method::Vikor => "compromise index Q (v = 0.5), lower is better",
                    }
                    .into(),
                    ranked: ranking
                        .ranked
                        .iter()
                        .map(|e| RankedJson {
                            solution: candidates[e.index],
                            rank: e.rank,
                            score: Some(e.score),
                            values: matrix.rows()[e.index].clone(),
                            normalised: Some(e.normalised.clone()),
                            pareto_optimal: e.pareto_optimal,
                        })
                        .collect(),
                    vikor: ranking.vikor.map(|v| VikorAcceptance {
                        compromise: v.compromise.iter().map(|&i| candidates[i]).collect(),
                        ..v
                    }),
                })
            }
            ChoiceMethod::Pareto => {
                // The non-dominated ones first, least weighted joint change first (the seeds'
                // rule), then the dominated ones in the same order.
                let front = matrix.pareto();
                let cost: Vec<f64> = solutions
                    .iter()
                    .map(|s| self.change.evaluate(robot, &s.q))
                    .collect::<Result<_, _>>()
                    .map_err(decide)?;
                let mut order: Vec<usize> = (0..solutions.len()).collect();
                order.sort_by(|&a, &b| {
                    (!front.contains(&a)).cmp(&!front.contains(&b)).then(cost[a].total_cmp(&cost[b])).then(a.cmp(&b))
                });
                Ok(RankingJson {
                    method: "pareto".into(),
                    criteria: matrix.criteria().iter().map(|c| describe(None, c)).collect(),
                    score: "none: non-dominated first, then least joint change from --from".into(),
                    ranked: order
                        .iter()
                        .enumerate()
                        .map(|(k, &i)| RankedJson {
                            solution: candidates[i],
                            rank: k + 1,
                            score: None,
                            values: matrix.rows()[i].clone(),
                            normalised: None,
                            pareto_optimal: front.contains(&i),
                        })
                        .collect(),
                    vikor: None,
                })
            }
        }
    }
}

/// The ranking table: rank, solution, branch, per criterion raw [unit] and normalised value,
/// score, Pareto flag.
fn write_ranking(out: &mut dyn Write, all: &IkSolutions, r: &RankingJson) -> Result<(), CliError> {
    let weights: Vec<String> =
        r.criteria.iter().map(|c| c.weight.map_or(c.name.clone(), |w| format!("{} {}", c.name, fixed(w, 3)))).collect();
    let label = if r.criteria.iter().any(|c| c.weight.is_some()) { "weights" } else { "criteria" };
    writeln!(out, "ranking (--choose {}; {label} {}):", r.method, weights.join(", "))?;
    let mut headers: Vec<(String, Align)> =
        vec![("rank".into(), Align::Right), ("#".into(), Align::Right), ("branch".into(), Align::Left)];
    for c in &r.criteria {
        let arrow = match c.direction {
            reach::decide::Direction::MoreIsBetter => "↑",
            reach::decide::Direction::LessIsBetter => "↓",
        };
        headers.push((format!("{}{arrow} [{}]", c.name, c.unit), Align::Right));
        if r.ranked.first().is_some_and(|e| e.normalised.is_some()) {
            headers.push((format!("{} norm", c.name), Align::Right));
        }
    }
    let score_header = match r.method.as_str() {
        "topsis" => "closeness",
        "vikor" => "Q",
        "weighted-sum" => "score",
        _ => "",
    };
    if !score_header.is_empty() {
        headers.push((score_header.into(), Align::Right));
    }
    headers.push(("pareto".into(), Align::Left));
    let refs: Vec<(&str, Align)> = headers.iter().map(|(h, a)| (h.as_str(), *a)).collect();
    let mut t = Table::new(&refs);
    for e in &r.ranked {
        let mut row =
            vec![e.rank.to_string(), (e.solution + 1).to_string(), all.solutions[e.solution].branch.to_string()];
        for (j, v) in e.values.iter().enumerate() {
            row.push(fixed(*v, 4));
            if let Some(n) = &e.normalised {
                row.push(fixed(n[j], 4));
            }
        }
        if let Some(s) = e.score {
            row.push(fixed(s, 4));
        }
        row.push(if e.pareto_optimal { "yes" } else { "dominated" }.into());
        t.row(row);
    }
    t.write(out, "  ")?;
    writeln!(out, "  score: {}; ↑ more is better, ↓ less is better", r.score)?;
    if let Some(v) = &r.vikor {
        let yes = |b: bool| if b { "holds" } else { "fails" };
        let set: Vec<String> = v.compromise.iter().map(|i| format!("#{}", i + 1)).collect();
        let verdict = if v.accepted() { "compromise" } else { "compromise set" };
        writeln!(
            out,
            "  VIKOR: C1 advantage (ΔQ ≥ DQ = {}) {}, C2 stability (also best by S or R) {} → {verdict} {}",
            fixed(v.dq, 3),
            yes(v.acceptable_advantage),
            yes(v.acceptable_stability),
            set.join(", ")
        )?;
    }
    Ok(())
}
