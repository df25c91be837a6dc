//! Rendering of the `reach tasks` report: the text tables and the top view.

use std::io::Write;

use reach::Robot;
use reach::decide::sequence::ENERGY_INTERVALS_PER_LEG;
use reach::jobs::tasks::{CostKind, TaskKind, TaskPlanReport, TaskPointReport, TasksReport};

use crate::error::CliError;
use crate::numbers::q_text;
use crate::output::{Align, Table, fixed, fixeds};
use crate::plot::Svg;
use crate::plot::drawings::{Route, tour_top_view};

/// The plan seen from above: the base, node 0 (the start tool position or the container), the
/// points in plan order (the budget's plan when a budget is given), unreachable points grey.
///
/// # Errors
/// [`CliError::Internal`] for a report without a plan (an unreachable container).
pub fn top_view(report: &TasksReport) -> Result<Svg, CliError> {
    let (Some(plan), Some(start)) = (report.within_budget.as_ref().or(report.plan.as_ref()), report.node0_xyz_m) else {
        return Err(CliError::internal("no plan to draw"));
    };
    let xy = |v: &[f64; 3]| [v[0], v[1]];
    let points: Vec<[f64; 2]> = report.points.iter().map(|p| xy(&p.xyz_m)).collect();
    let order: Vec<usize> = plan.order.iter().map(|&k| k - 1).collect();
    let (route, start_label, what) = match report.task {
        TaskKind::Visiting => (Route::Open, "start", "visiting"),
        TaskKind::Collection => (Route::Trips, "container", "collection"),
    };
    let budget = report.budget_s.map_or(String::new(), |b| format!(", budget {b} s"));
    let cost = match plan.total_energy_j {
        Some(e) => format!("energy {e:.2} J"),
        None => format!("J1 {:.4} rad", plan.total_j1_rad),
    };
    let title = format!("{} — {what}: {} of {} points, {cost}{budget}", report.robot, order.len(), points.len());
    tour_top_view(&title, xy(&report.base_xyz_m), (xy(&start), start_label), &points, &order, route)
}

fn write_plan(
    out: &mut dyn Write,
    kind: TaskKind,
    p: &TaskPlanReport,
    points: &[TaskPointReport],
) -> Result<(), CliError> {
    let collection = kind == TaskKind::Collection;
    let leg = if collection { "trip" } else { "leg" };
    let energy = p.total_energy_j.is_some();
    let mut columns = vec![
        ("step", Align::Right),
        ("point", Align::Right),
        ("xyz [m]", Align::Left),
        (if collection { "trip J1 [rad]" } else { "leg J1 [rad]" }, Align::Right),
    ];
    if energy {
        columns.push((if collection { "trip energy [J]" } else { "leg energy [J]" }, Align::Right));
    }
    columns.push((if collection { "trip [s]" } else { "leg [s]" }, Align::Right));
    columns.push(("cumulative [s]", Align::Right));
    let mut t = Table::new(&columns);
    let mut cumulative = 0.0;
    for (k, l) in p.legs.iter().enumerate() {
        let point = &points[l.point - 1];
        cumulative += l.duration_s.unwrap_or(0.0);
        let mut row = vec![(k + 1).to_string(), l.point.to_string(), fixeds(&point.xyz_m, 3), fixed(l.j1_rad, 4)];
        if energy {
            row.push(l.energy_j.map_or("-".into(), |e| fixed(e, 3)));
        }
        row.push(l.duration_s.map_or("-".into(), |d| fixed(d, 3)));
        row.push(l.duration_s.map_or("-".into(), |_| fixed(cumulative, 3)));
        t.row(row);
    }
    t.write(out, "  ")?;
    let total_time = p.total_duration_s.map_or(String::new(), |d| format!(", duration {} s", fixed(d, 3)));
    let total_energy = p.total_energy_j.map_or(String::new(), |e| format!(", energy {} J", fixed(e, 3)));
    writeln!(out, "  total: {} {leg}(s), J1 {} rad{total_energy}{total_time}", p.legs.len(), fixed(p.total_j1_rad, 4))?;
    Ok(())
}

/// The report for people: the head, the unreachable points, the plan and the budget's plan.
///
/// # Errors
/// I/O errors of `out`.
pub fn write_text(out: &mut dyn Write, robot: &Robot, r: &TasksReport) -> Result<(), CliError> {
    if !r.description.is_empty() {
        writeln!(out, "{}", r.description)?;
    }
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", r.robot, robot.dof()));
    let (kind, node) = match r.task {
        TaskKind::Collection => ("collection: trips container -> object -> container", "container q"),
        TaskKind::Visiting => ("visiting: one open tour from the start", "start q"),
    };
    head.pair("task", kind);
    if let Some(q) = &r.node0_q_deg {
        let shown: Vec<f64> = q.iter().map(|v| (v * 1e4).round() / 1e4 + 0.0).collect();
        head.pair(node, q_text(robot, &shown));
    }
    head.pair("solver", r.solver.clone());
    head.pair("choice", r.choice.clone());
    head.pair(
        "cost",
        match r.cost {
            CostKind::J1 => {
                "J1 = Σ wᵢ·|Δqᵢ| between configurations [rad]; durations synchronised within the speed limits"
                    .to_string()
            }
            CostKind::Energy => format!(
                "mechanical energy ∫ Σ|τᵢ·q̇ᵢ| dt [J] of each synchronised point-to-point move (Newton–Euler with gravity, {} samples per leg)",
                ENERGY_INTERVALS_PER_LEG + 1
            ),
            CostKind::PositiveWork => format!(
                "positive work ∫ Σ max(τᵢ·q̇ᵢ, 0) dt [J] of each synchronised point-to-point move, braking free (Newton–Euler with gravity, {} samples per leg)",
                ENERGY_INTERVALS_PER_LEG + 1
            ),
        },
    );
    let reachable = r.points.len() - r.unreachable.len();
    head.pair("points", format!("{} ({reachable} reachable, {} unreachable)", r.points.len(), r.unreachable.len()));
    head.write(out, "")?;
    if !r.unreachable.is_empty() {
        writeln!(out, "unreachable (skipped):")?;
        for p in r.points.iter().filter(|p| p.reason.is_some()) {
            writeln!(
                out,
                "  point {} at {} m: {}",
                p.index,
                fixeds(&p.xyz_m, 3),
                p.reason.clone().unwrap_or_default()
            )?;
        }
    }
    if let Some(plan) = &r.plan {
        writeln!(out, "plan over every reachable point ({}):", plan.method)?;
        write_plan(out, r.task, plan, &r.points)?;
    }
    if let (Some(b), Some(p)) = (r.budget_s, &r.within_budget) {
        writeln!(
            out,
            "within the budget of {} s: {} of {reachable} point(s) ({}):",
            fixed(b, 3),
            p.legs.len(),
            p.method
        )?;
        write_plan(out, r.task, p, &r.points)?;
    }
    Ok(())
}
