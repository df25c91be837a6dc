//! `reach tasks` — seed 001's planning tasks on the energy functional J1 (notes 001 §8):
//! *collection* (pick-and-place trips container → object → container) and *visiting* (an
//! open tour of target points), with unreachable points reported and skipped, and the largest
//! number of points that fit a time budget. The workflow is the library's
//! [`reach::jobs::tasks`]; this command reads the task file, builds the request, and renders
//! the report (text, `--json`, a top view). See `docs/task-format.md`.
//!
//! Exit status: 0; 2 for bad input, including a task in which no point is reachable; 3 when
//! the container itself is unreachable.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use reach::jobs::tasks::{TaskKind, TasksRequest};
use reach::jobs::{Report, Request};

use super::tasks_render::{top_view, write_text};
use crate::error::{CliError, one_line};
use crate::numbers::parse_finite;
use crate::output::write_json;
use crate::plot::DrawArgs;
use crate::robot_arg::RobotArgs;

/// Which planning task.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum TaskKindArg {
    /// Trips container → object → container for every object.
    Collection,
    /// One open tour from the start through every target.
    Visiting,
}

impl From<TaskKindArg> for TaskKind {
    fn from(k: TaskKindArg) -> Self {
        match k {
            TaskKindArg::Collection => TaskKind::Collection,
            TaskKindArg::Visiting => TaskKind::Visiting,
        }
    }
}

/// Arguments of `reach tasks`.
#[derive(Debug, Clone, Args)]
pub struct TasksArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The task: collection or visiting.
    #[arg(value_name = "TASK_KIND")]
    pub kind: TaskKindArg,

    /// Task file (TOML, docs/task-format.md "reach tasks").
    #[arg(value_name = "TASK_FILE")]
    pub file: PathBuf,

    /// Time budget in seconds: also report the largest number of points that fit (overrides
    /// the file's `budget_s`).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub budget: Option<String>,

    /// Print JSON: the `tasks` report (docs/schemas/tasks.report.schema.json).
    #[arg(long)]
    pub json: bool,

    /// Draw the plan from above (xy): --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: DrawArgs,
}

/// The library's error in the command's words: problems inside the task file are prefixed
/// with its path, the budget names `--budget`.
fn located(e: reach::Error, origin: &str) -> CliError {
    match e {
        reach::Error::Request { field, reason } if field == "task" => {
            CliError::bad_input(format!("{origin}: {}", one_line(&reason)))
        }
        reach::Error::Request { field, reason } if field == "budget_s" => {
            CliError::bad_input(format!("--budget (or budget_s): {}", one_line(&reason)))
        }
        reach::Error::File { message, .. } => CliError::bad_input(format!("{origin}: {}", one_line(&message))),
        e => CliError::from(e),
    }
}

/// The request of `args`: the task file's text, the kind and the budget.
///
/// # Errors
/// [`CliError::BadInput`] for an unreadable file or a `--budget` that is not a number.
pub fn request(args: &TasksArgs) -> Result<TasksRequest, CliError> {
    let origin = args.file.display();
    let task = std::fs::read_to_string(&args.file).map_err(|e| CliError::bad_input(format!("{origin}: {e}")))?;
    let budget_s = args.budget.as_deref().map(|t| parse_finite("--budget", t)).transpose()?;
    Ok(TasksRequest { task_kind: args.kind.into(), task, budget_s })
}

/// Runs `reach tasks`.
///
/// # Errors
/// See the module docs.
pub fn run(args: &TasksArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    args.draw.check_files()?;
    let request = request(args)?;
    let report = reach::jobs::run(&loaded.robot, &Request::Tasks(request))
        .map_err(|e| located(e, &args.file.display().to_string()))?;
    let Report::Tasks(report) = report else { return Err(CliError::internal("not a tasks report")) };
    if let Some(reason) = &report.container_unreachable {
        return Err(CliError::NoSolution(format!("the container is unreachable: {reason}")));
    }
    if args.draw.any() {
        args.draw.write(&top_view(&report)?)?;
    }
    if args.json {
        return write_json(out, &report);
    }
    write_text(out, &loaded.robot, &report)
}
