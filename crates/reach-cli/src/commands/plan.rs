//! `reach plan` — every motion of a task file (docs/task-format.md): the CLI reads the file and
//! loads the robot its `robot` key names; `reach::jobs::motion::plan` parses the text and
//! computes each motion as `reach move` would; rendering is shared with `reach move`
//! (`move_render.rs`). `--json` prints the report (docs/schemas/plan.report.schema.json).
//!
//! Exit status: 0 when every motion is feasible; 3 when one is not (all reports are printed,
//! the first infeasible motion's reason on stderr); 2 for bad input.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;
use reach::Robot;
use reach::jobs::motion::{PlanReport, PlanRequest, Task};
use reach::model::UrdfChain;

use crate::commands::check::read_valid_scene;
use crate::commands::move_cmd::Bars;
use crate::commands::move_render::{infeasible, write_comparison, write_plan, write_report};
use crate::error::CliError;
use crate::output::{read_file, verdict_exit, write_json};
use crate::robot_arg::load_robot;

/// Arguments of `reach plan`.
#[derive(Debug, Clone, Args)]
pub struct PlanArgs {
    /// Task file (TOML, docs/task-format.md).
    #[arg(value_name = "TASK")]
    pub task: PathBuf,

    /// Scene file (TOML: obstacles, tool zone): every motion is checked continuously against
    /// it (as `reach move --scene`).
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<String>,

    /// Print the report as JSON (docs/schemas/plan.report.schema.json): robot, description,
    /// motions (each as `reach move --json`).
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg DIR, --png DIR (one file per motion), --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

/// Parses a task file's text, loads the robot its `robot` key names and plans every motion
/// (with progress bars unless `json`), checked against `scene` (its text) when given.
///
/// # Errors
/// [`CliError::BadInput`] for a malformed file (prefixed with `origin`), an unknown robot, a
/// bad motion.
pub fn plan_task(
    text: &str,
    origin: &str,
    scene: Option<String>,
    json: bool,
) -> Result<(Robot, Task, PlanReport), CliError> {
    let prefixed =
        |e: reach::Error| CliError::bad_input(format!("{origin}: {}", crate::error::one_line(&e.to_string())));
    let task = Task::parse(text).map_err(prefixed)?;
    let robot = load_robot(&task.robot, &UrdfChain { base: None, tip: None })?.robot;
    let mut bars = Bars { json, current: None };
    let report = reach::jobs::motion::plan_with_progress(
        &robot,
        &PlanRequest { task: text.to_string(), scene },
        &mut |name, done, total| bars.report(name, done, total),
        crate::interrupt::cancel(),
    )
    .map_err(prefixed)?;
    Ok((robot, task, report))
}

/// Runs `reach plan`.
///
/// # Errors
/// See the module docs.
pub fn run_plan(args: &PlanArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let text = read_file(&args.task)?;
    let scene = args.scene.as_deref().map(read_valid_scene).transpose()?;
    let (robot, task, report) = plan_task(&text, &args.task.display().to_string(), scene, args.json)?;
    write_plan(&args.draw, &robot, &task.motions, &report.motions)?;
    if args.json {
        write_json(out, &report)?;
    } else {
        if !report.description.is_empty() {
            writeln!(out, "{}", report.description)?;
        }
        for m in &report.motions {
            write_report(out, m, m.samples.len().div_ceil(10))?;
        }
        write_comparison(out, &report.motions)?;
    }
    verdict_exit(out, report.motions.iter().find(|m| !m.feasible).map(infeasible))
}
