//! Rendering of `reach move` and `reach plan` reports: text, CSV, drawings, and the `reach
//! demo` sections of seeds 001 and 003 (which plan the embedded example task files).

use std::io::Write;
use std::path::Path;

use reach::Robot;
use reach::jobs::motion::{MoveInterval, MoveReport, MoveRequest, ProfileName, Space};
use reach::motion::tracking::Decision;

use crate::commands::plan::plan_task;
use crate::error::CliError;
use crate::output::{fixed, fixeds};

/// `interval 0.000 .. 1.000 s` and the configuration realised in it.
fn interval_head(iv: &MoveInterval) -> (String, &str) {
    let span = format!("interval {} .. {} s", fixed(iv.start_s, 3), fixed(iv.end_s, 3));
    (span, iv.configuration.as_deref().unwrap_or("no configuration"))
}

fn space_name(space: Space) -> &'static str {
    match space {
        Space::Joint => "joint-space",
        Space::Tool => "tool-space",
    }
}

/// Writes the human-readable report of one motion, every `every`-th sample and the last.
///
/// # Errors
/// Output errors.
pub fn write_report(out: &mut dyn Write, m: &MoveReport, every: usize) -> Result<(), CliError> {
    let title = if m.name.is_empty() { String::new() } else { format!("{}: ", m.name) };
    writeln!(
        out,
        "{title}{} move of {}, {} s, {} samples",
        space_name(m.space),
        m.robot,
        fixed(m.duration_s, 3),
        m.samples.len()
    )?;
    writeln!(out, "  t [s]      q [deg]                                    xyz [m]")?;
    let step = every.max(1);
    for (k, s) in m.samples.iter().enumerate() {
        if k % step == 0 || k + 1 == m.samples.len() {
            writeln!(out, "  {:<9}  {:<42} {}", fixed(s.t_s, 3), fixeds(&s.q_deg, 3), fixeds(&s.xyz_m, 4))?;
        }
    }
    for iv in &m.intervals {
        let (span, configuration) = interval_head(iv);
        writeln!(
            out,
            "  {span}: {} ({configuration}){}",
            if iv.feasible { "feasible" } else { "NOT feasible" },
            match iv.decision {
                Some(Decision::Criterion) => ", chosen by the criteria",
                Some(Decision::CriterionRejected) => ", criteria not met: default kept (K14)",
                _ => "",
            }
        )?;
        for r in &iv.reasons {
            writeln!(out, "    {r}")?;
        }
    }
    for e in &m.events {
        writeln!(out, "  {} [t = {} s] {}", e.code, fixed(e.t_s, 3), e.message)?;
    }
    if let Some(p) = &m.swept {
        writeln!(out, "  swept check: {}", crate::commands::check::swept_text(&p.swept, Some(p.segment)))?;
    }
    let energy = match (m.effort.energy_j, &m.effort.energy_note) {
        (Some(e), _) => format!("{} J", fixed(e, 3)),
        (None, note) => format!("n/a ({})", note.as_deref().unwrap_or("not computed")),
    };
    writeln!(out, "  J1 = {}  J2 = {}  energy: {energy}", fixed(m.effort.j1, 6), fixed(m.effort.j2, 6))?;
    writeln!(
        out,
        "  {}",
        if m.feasible { "feasible".to_string() } else { format!("INFEASIBLE: {} reason(s)", m.reasons.len()) }
    )?;
    Ok(())
}

/// Why a motion is infeasible, for its exit-3 line (`crate::output::verdict_exit`): its first reason.
#[must_use]
pub fn infeasible(m: &MoveReport) -> String {
    format!(
        "motion{} infeasible: {}",
        if m.name.is_empty() { String::new() } else { format!(" `{}`", m.name) },
        m.reasons.first().cloned().unwrap_or_else(|| "no feasible samples".into())
    )
}

/// A one-line-per-motion comparison table (J1, J2, feasibility).
///
/// # Errors
/// Output errors.
pub fn write_comparison(out: &mut dyn Write, motions: &[MoveReport]) -> Result<(), CliError> {
    writeln!(out, "comparison:")?;
    for m in motions {
        writeln!(
            out,
            "  {:<24} {:<5} J1 = {}  J2 = {}  {}",
            m.name,
            m.space.as_str(),
            fixed(m.effort.j1, 6),
            fixed(m.effort.j2, 6),
            if m.feasible { "feasible".to_string() } else { format!("infeasible ({})", m.reasons.len()) }
        )?;
    }
    Ok(())
}

/// `--csv FILE`: a header with units (`t_s`, `q1_deg …`, `qd1_deg_s …`, the tool pose) and
/// one row per sample; `reach drive/view/check --motion` and `reach retime` read it back.
///
/// # Errors
/// [`CliError::BadInput`] naming the file when it cannot be written.
pub fn write_csv(path: &Path, robot: &Robot, m: &MoveReport) -> Result<(), CliError> {
    use reach::jobs::input::{AngleUnit, joint_columns};
    let columns: Vec<String> = std::iter::once("t_s".to_string())
        .chain(joint_columns(robot, AngleUnit::Deg, "q", ""))
        .chain(joint_columns(robot, AngleUnit::Deg, "qd", "_s"))
        .chain(["x_m", "y_m", "z_m", "roll_deg", "pitch_deg", "yaw_deg"].map(String::from))
        .collect();
    let mut text = columns.join(",");
    text.push('\n');
    for s in &m.samples {
        let cells: Vec<String> = std::iter::once(s.t_s)
            .chain(s.q_deg.iter().copied())
            .chain(s.qd_deg_s.iter().copied())
            .chain(s.xyz_m)
            .chain(s.rpy_deg)
            .map(|v| format!("{v}"))
            .collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    crate::output::write_file("--csv", path, text)
}

/// The joint curves and tool path of one computed motion.
#[must_use]
pub fn move_drawing(robot: &Robot, request: &MoveRequest, m: &MoveReport) -> crate::plot::Svg {
    use crate::plot::drawings::{TrajectoryDrawing, joint_series, title, trajectory};
    let default = if request.space == Space::Tool && request.speed_m_s.is_some() {
        ProfileName::Linear
    } else {
        ProfileName::Cycloidal
    };
    let profile = request.profile.unwrap_or(default).as_str();
    let label = if m.name.is_empty() { String::new() } else { format!("{}: ", m.name) };
    let q: Vec<Vec<f64>> = m.samples.iter().map(|s| s.q_deg.clone()).collect();
    let qd: Vec<Vec<f64>> = m.samples.iter().map(|s| s.qd_deg_s.clone()).collect();
    trajectory(&TrajectoryDrawing {
        title: title(
            robot,
            &format!("{label}{} move, {profile} profile, {} s", space_name(m.space), fixed(m.duration_s, 3)),
        ),
        times: m.samples.iter().map(|s| s.t_s).collect(),
        joints: joint_series(robot, &q, &qd),
        tool: m.samples.iter().map(|s| s.xyz_m).collect(),
        tool_waypoints: Vec::new(),
        obstacles: &[],
    })
}

/// `reach plan --svg DIR / --png DIR`: one drawing per motion, `DIR/motion-K.svg` (`.png`).
///
/// # Errors
/// [`CliError::BadInput`] for a directory that cannot be made or a file that cannot be written.
pub fn write_plan(
    draw: &crate::plot::DrawArgs,
    robot: &Robot,
    requests: &[MoveRequest],
    motions: &[MoveReport],
) -> Result<(), CliError> {
    for (option, dir) in [("--svg", &draw.svg), ("--png", &draw.png)] {
        if let Some(dir) = dir {
            crate::plot::ensure_dir(option, dir)?;
        }
    }
    for (k, (request, m)) in requests.iter().zip(motions).enumerate() {
        let drawing = move_drawing(robot, request, m);
        if let Some(dir) = &draw.svg {
            crate::plot::write_svg("--svg", &dir.join(format!("motion-{}.svg", k + 1)), &drawing)?;
        }
        if let Some(dir) = &draw.png {
            crate::plot::write_png("--png", &dir.join(format!("motion-{}.png", k + 1)), &drawing, draw.png_width)?;
        }
    }
    Ok(())
}

/// The seed examples, embedded so that `reach demo` runs from any directory.
const SEED001_TASK: &str = include_str!("../../../../examples/seed001_tool_vs_joint.toml");
const SEED003_TASK: &str = include_str!("../../../../examples/seed003_welding.toml");

/// `reach demo` section: seed 001, J1 and J2 of the joint-space and tool-space motions.
///
/// # Errors
/// Output errors; [`CliError::Internal`] if the embedded example breaks.
pub fn demo_seed001(out: &mut dyn Write) -> Result<(), CliError> {
    let (_, _, report) = plan_task(SEED001_TASK, "examples/seed001_tool_vs_joint.toml", None, true)
        .map_err(|e| CliError::internal(e.to_string()))?;
    writeln!(out)?;
    writeln!(out, "{} (reach plan examples/seed001_tool_vs_joint.toml)", report.description)?;
    write_comparison(out, &report.motions)?;
    writeln!(
        out,
        "  J_tool > J_joint, as the thesis claims; its printed 0.6981 / 1.3307 are not reproducible (notes 001 §6)."
    )?;
    if let Some(tool) = report.motions.iter().find(|m| m.space == Space::Tool) {
        for r in tool.reasons.iter().take(2) {
            writeln!(out, "  tool space: {r}")?;
        }
    }
    Ok(())
}

/// `reach demo` section: seed 003, per-configuration feasibility of the weld and the events.
///
/// # Errors
/// Output errors; [`CliError::Internal`] if the embedded example breaks.
pub fn demo_seed003(out: &mut dyn Write) -> Result<(), CliError> {
    let (_, _, report) = plan_task(SEED003_TASK, "examples/seed003_welding.toml", None, true)
        .map_err(|e| CliError::internal(e.to_string()))?;
    writeln!(out)?;
    writeln!(out, "{} (reach plan examples/seed003_welding.toml)", report.description)?;
    for m in &report.motions {
        for iv in &m.intervals {
            let (span, configuration) = interval_head(iv);
            writeln!(out, "  {span}: realised in {configuration}")?;
            for r in &iv.reasons {
                writeln!(out, "    {r}")?;
            }
        }
        writeln!(out, "  events:")?;
        for e in &m.events {
            writeln!(out, "    {} [t = {} s] {}", e.code, fixed(e.t_s, 3), e.message)?;
        }
    }
    write_comparison(out, &report.motions)
}
