//! Text and CSV rendering of `reach ik`'s reports (`reach::jobs::ik`), and `reach demo`'s IK
//! section.

use std::io::Write;

use reach::Robot;
use reach::jobs::ik::{CriterionDirection, IkChoiceMethod, IkRanking, IkReport, IkScanReport, IkSolutionReport};
use reach::jobs::{IkRequest, Pose};
use reach::model::JointKind;

use super::ik::IkArgs;
use crate::error::{CliError, one_line};
use crate::numbers::{display_unit, q_text};
use crate::output::{Align, Table, fixed, fixeds, num, nums};
use crate::robot_arg::load_preset;

/// Why the solution was chosen without --choose.
const CLOSEST_RULE: &str = "within limits, least Σ wᵢ·|qᵢ − fromᵢ|; --all lists every solution";

/// The human-readable form of an `ik` report.
pub(super) fn write_report(out: &mut dyn Write, robot: &Robot, r: &IkReport, args: &IkArgs) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
    let named = args.solver.as_deref().is_some_and(|s| s != "auto");
    head.pair("solver", format!("{} ({})", r.solver, if named { "--solver" } else { "auto-detected" }));
    head.pair("target", target_text(r));
    let from_note = if args.from.is_some() { "--from" } else { "home" };
    head.pair("from", format!("{} ({from_note})", q_text(robot, &r.from_q_deg)));
    if args.joint_weights.is_some() {
        head.pair("joint weights", nums(&r.joint_weights));
    }
    let status = match &r.reason {
        None => format!("ok: {} solution(s), {} within limits", r.found, r.within_limits),
        Some(reason) => format!("{}: {}", r.status, one_line(reason)),
    };
    head.pair("status", status);
    head.write(out, "")?;
    match (r.chosen, &r.ranking) {
        (Some(i), Some(ranking)) => {
            if args.all {
                writeln!(out, "solutions (* = chosen by --choose):")?;
                write_solution_table(out, robot, &r.solutions, r.chosen, "  ", false)?;
            }
            write_ranking(out, &r.solutions, ranking)?;
            let method = method_name(ranking.method);
            write_chosen(out, robot, &r.solutions[i], &format!("within limits, rank 1 of --choose {method}"))
        }
        (Some(i), None) if !args.all => write_chosen(out, robot, &r.solutions[i], CLOSEST_RULE),
        _ if r.solutions.is_empty() => Ok(()),
        _ => {
            if r.solutions.len() < r.found {
                writeln!(out, "{} of the {} solutions, evenly spaced (--max):", r.solutions.len(), r.found)?;
            }
            writeln!(out, "solutions (* = chosen: least Σ wᵢ·|qᵢ − fromᵢ| within limits):")?;
            write_solution_table(out, robot, &r.solutions, r.chosen, "  ", false)
        }
    }
}

fn method_name(method: IkChoiceMethod) -> &'static str {
    match method {
        IkChoiceMethod::Topsis => "topsis",
        IkChoiceMethod::Vikor => "vikor",
        IkChoiceMethod::WeightedSum => "weighted-sum",
        IkChoiceMethod::Pareto => "pareto",
    }
}

fn target_text(r: &IkReport) -> String {
    let p = fixeds(&r.target.xyz_m, 6);
    match &r.target.rpy_deg {
        None => format!("position {p} [m], orientation free"),
        Some(rpy) => format!("position {p} [m], rpy {} [deg]", fixeds(rpy, 4)),
    }
}

/// `within limits`, or the violated joints: `joint 4 (wrist) 170.2 outside -160 .. 160 deg`.
fn limits_cell(robot: &Robot, s: &IkSolutionReport) -> String {
    if s.within_limits {
        return "within limits".into();
    }
    s.violations
        .iter()
        .map(|v| {
            let kind = robot.joints()[v.joint - 1].kind;
            let digits = if kind == JointKind::Revolute { 2 } else { 4 };
            format!(
                "joint {} ({}) {} outside {} .. {} {}",
                v.joint,
                v.name,
                fixed(v.value_deg, digits),
                v.lower_deg.map_or("-inf".into(), num),
                v.upper_deg.map_or("inf".into(), num),
                display_unit(kind)
            )
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// `ok`, or the 1-based numbers of the joints outside their limits: `outside: 4 5`.
fn compact_limits_cell(s: &IkSolutionReport) -> String {
    if s.within_limits {
        return "ok".into();
    }
    let joints: Vec<String> = s.violations.iter().map(|v| v.joint.to_string()).collect();
    format!("joints outside: {}", joints.join(" "))
}

fn singular_cell(s: &IkSolutionReport) -> String {
    if s.singular.is_empty() { "-".into() } else { s.singular.join(",") }
}

fn write_chosen(out: &mut dyn Write, robot: &Robot, s: &IkSolutionReport, why: &str) -> Result<(), CliError> {
    writeln!(out, "chosen ({why}):")?;
    let mut t = Table::key_value();
    t.pair("branch", s.branch.clone());
    t.pair("q", q_text(robot, &s.q_deg.iter().map(|v| (v * 1e6).round() / 1e6).collect::<Vec<_>>()));
    t.pair("error", format!("position {:.1e} m, orientation {:.1e} rad", s.position_error_m, s.orientation_error_rad));
    t.pair("limits", limits_cell(robot, s));
    t.pair("singular", singular_cell(s));
    t.write(out, "  ")
}

/// The table of solutions: number (`*` marks `chosen`), branch, q, errors, limits, singular.
fn write_solution_table(
    out: &mut dyn Write,
    robot: &Robot,
    solutions: &[IkSolutionReport],
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
    for (i, s) in solutions.iter().enumerate() {
        let mark = if chosen == Some(i) { "*" } else { "" };
        let q: Vec<String> = s.q_deg.iter().map(|&v| format!("{:>9}", fixed(v, 4))).collect();
        t.row(vec![
            format!("{mark}{}", i + 1),
            s.branch.clone(),
            q.join(" ").trim_start().to_string(),
            format!("{:.1e}", s.position_error_m),
            format!("{:.1e}", s.orientation_error_rad),
            singular_cell(s),
            if compact { compact_limits_cell(s) } else { limits_cell(robot, s) },
        ]);
    }
    t.write(out, indent)
}

/// The ranking table: rank, solution, branch, per criterion raw [unit] and normalised value,
/// score, Pareto flag.
fn write_ranking(out: &mut dyn Write, solutions: &[IkSolutionReport], r: &IkRanking) -> Result<(), CliError> {
    let weights: Vec<String> =
        r.criteria.iter().map(|c| c.weight.map_or(c.name.clone(), |w| format!("{} {}", c.name, fixed(w, 3)))).collect();
    let label = if r.criteria.iter().any(|c| c.weight.is_some()) { "weights" } else { "criteria" };
    writeln!(out, "ranking (--choose {}; {label} {}):", method_name(r.method), weights.join(", "))?;
    let mut headers: Vec<(String, Align)> =
        vec![("rank".into(), Align::Right), ("#".into(), Align::Right), ("branch".into(), Align::Left)];
    for c in &r.criteria {
        let arrow = match c.direction {
            CriterionDirection::MoreIsBetter => "↑",
            CriterionDirection::LessIsBetter => "↓",
        };
        headers.push((format!("{}{arrow} [{}]", c.name, c.unit), Align::Right));
        if r.ranked.first().is_some_and(|e| e.normalised.is_some()) {
            headers.push((format!("{} norm", c.name), Align::Right));
        }
    }
    let score_header = match r.method {
        IkChoiceMethod::Topsis => "closeness",
        IkChoiceMethod::Vikor => "Q",
        IkChoiceMethod::WeightedSum => "score",
        IkChoiceMethod::Pareto => "",
    };
    if !score_header.is_empty() {
        headers.push((score_header.into(), Align::Right));
    }
    headers.push(("pareto".into(), Align::Left));
    let refs: Vec<(&str, Align)> = headers.iter().map(|(h, a)| (h.as_str(), *a)).collect();
    let mut t = Table::new(&refs);
    for e in &r.ranked {
        let mut row = vec![e.rank.to_string(), (e.solution + 1).to_string(), solutions[e.solution].branch.clone()];
        for (j, v) in e.values.iter().enumerate() {
            // Small raw values (seed 003's accuracy is ~1e-4 m) keep four significant digits.
            row.push(if *v != 0.0 && v.abs() < 0.01 { format!("{v:.4e}") } else { fixed(*v, 4) });
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

/// The scan table as CSV, every row.
pub(super) fn write_scan_csv(out: &mut dyn Write, r: &IkScanReport) -> Result<(), CliError> {
    let header =
        ["alpha_deg", "beta_deg", "gamma_deg", "q1_deg", "q2_deg", "q3_deg", "S_deg", "within_limits", "chosen"];
    writeln!(out, "{}", header.join(","))?;
    for (i, row) in r.rows.iter().enumerate() {
        let p = &row.paper;
        let mut cells: Vec<String> = [p.alpha_deg, p.beta_deg, p.gamma_deg]
            .into_iter()
            .chain(row.q_deg)
            .chain([row.s_deg])
            .map(|v| format!("{v}"))
            .collect();
        cells.push(row.within_limits.to_string());
        cells.push((r.chosen == Some(i)).to_string());
        writeln!(out, "{}", cells.join(","))?;
    }
    Ok(())
}

/// The scan report for people: the head, and the first, last and chosen rows.
pub(super) fn write_scan(out: &mut dyn Write, robot: &Robot, r: &IkScanReport, from: bool) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
    head.pair("method", format!("seed 000 table of configurations (notes 000 §4.1), Δα = {} deg", num(r.step_deg)));
    head.pair("target", format!("x y = {} [m] in the arm's plane", fixeds(&r.plane_xy_m, 6)));
    if let Some(a) = r.alpha_min_deg {
        head.pair("alpha_min", format!("{} deg", fixed(a, 6)));
    }
    head.pair("rows", format!("{} ({} within limits)", r.rows.len(), r.within_limits));
    let s = &r.from_paper;
    head.pair(
        "from",
        format!(
            "alpha beta gamma = {} [deg] ({} q = {})",
            fixeds(&[s.alpha_deg, s.beta_deg, s.gamma_deg], 6),
            if from { "--from" } else { "home" },
            q_text(robot, &r.from_q_deg)
        ),
    );
    let status = match &r.reason {
        None => "ok".to_string(),
        Some(reason) => format!("{}: {}", r.status, one_line(reason)),
    };
    head.pair("status", status);
    head.write(out, "")?;
    let Some(last) = r.rows.len().checked_sub(1) else { return Ok(()) };
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
    for (label, index) in [("first", Some(0)), ("last", Some(last)), ("chosen", r.chosen)] {
        let Some(i) = index else { continue };
        let row = &r.rows[i];
        let p = &row.paper;
        let mut cells = vec![label.to_string(), (i + 1).to_string()];
        cells.extend(
            [p.alpha_deg, p.beta_deg, p.gamma_deg].into_iter().chain(row.q_deg).chain([row.s_deg]).map(|v| fixed(v, 6)),
        );
        cells.push(if row.within_limits { "within limits" } else { "outside limits" }.to_string());
        t.row(cells);
    }
    writeln!(out, "rows [deg] (chosen: least S = |α − α0| + |β − β0| + |γ − γ0|; --csv FILE writes all):")?;
    t.write(out, "  ")
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
    // puma560 at q = (20, −40, 30, 10, 40, −30)°: the pose is its forward kinematics.
    let puma = load_preset("puma560")?.robot;
    let q = reach::jobs::Joints::Deg(vec![20.0, -40.0, 30.0, 10.0, 40.0, -30.0]);
    let fk = reach::jobs::kinematics::fk(&puma, &reach::jobs::FkRequest { q })?;
    let pose = Pose { matrix: Some(fk.pose.matrix), ..Pose::default() };
    demo_case(out, &puma, "fk(20, -40, 30, 10, 40, -30 deg)", pose)?;

    // Seed 003 (notes 003 §5.1–5.2): the weld starts at P = (50, 740, 70) mm towards
    // M = (500, 200, 700) mm; tool x = n = (M − P)/|MP|, y = e6 = (y1 − y2, x2 − x1, 0)/|M1P1|,
    // z = l = n × e6 (n ≈ (0.476731, −0.572078, 0.667424), l ≈ (−0.427274, 0.512729, 0.744678)).
    let welder = load_preset("welder6r")?.robot;
    let seam = reach::motion::tool_space::seam_frame(
        &nalgebra::Vector3::new(0.05, 0.74, 0.07),
        &nalgebra::Vector3::new(0.5, 0.2, 0.7),
    )
    .map_err(|e| CliError::internal(e.to_string()))?;
    let pose = Pose { matrix: Some(reach::jobs::input::matrix_rows(&seam)), ..Pose::default() };
    demo_case(out, &welder, "seed 003 weld start P = (50, 740, 70) mm, tool x = n, z = l", pose)?;

    // Seed 001 (notes 001 §5.1): goal pose T1.
    let spbu = load_preset("spbu6")?.robot;
    let t1 = [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 3.0], [0.0, -1.0, 0.0, 5.0], [0.0, 0.0, 0.0, 1.0]];
    demo_case(out, &spbu, "seed 001 goal pose T1", Pose { matrix: Some(t1), ..Pose::default() })
}

fn demo_case(out: &mut dyn Write, robot: &Robot, what: &str, target: Pose) -> Result<(), CliError> {
    let request = IkRequest { all: true, ..IkRequest::new(target) };
    let r = reach::jobs::ik::ik(robot, &request)
        .map_err(|e| CliError::internal(format!("IK of preset `{}`: {}", robot.name(), one_line(&e.to_string()))))?;
    writeln!(out)?;
    writeln!(out, "{} — {what}", robot.name())?;
    writeln!(out, "  target    {}", target_text(&r))?;
    writeln!(
        out,
        "  solver    {}: {} solutions, {} within limits (* = closest to home)",
        r.solver, r.found, r.within_limits
    )?;
    write_solution_table(out, robot, &r.solutions, r.chosen, "  ", true)
}

/// The n-link scan for people: grid counts and the chosen configuration.
pub(super) fn write_planar_scan(out: &mut dyn Write, r: &reach::jobs::PlanarScanReport) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", r.robot.clone());
    head.pair("from q [deg]", r.from_q_deg.iter().map(|v| fixed(*v, 6)).collect::<Vec<_>>().join(", "));
    match (&r.q_deg, r.s_deg) {
        (Some(q), Some(s)) => {
            head.pair(
                "scan",
                format!(
                    "joints 3..n every {} deg: {} nodes, {} configurations, {} within limits",
                    r.step_deg, r.nodes, r.configurations, r.within_limits
                ),
            );
            head.pair("chosen q [deg]", q.iter().map(|v| fixed(*v, 6)).collect::<Vec<_>>().join(", "));
            head.pair("S [deg]", fixed(s, 6));
        }
        _ => head.pair("chosen", r.reason.clone().unwrap_or_default()),
    }
    head.write(out, "")
}
