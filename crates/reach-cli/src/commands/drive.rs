//! `reach drive` — stepper step schedules from a sampled motion, a task file or a point-to-point move:
//! a summary for people, CSV/JSON step lists, coil tables, step/direction events or G-code.

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use reach::Robot;
use reach::drive::output::{GcodeDialect, coil_table_csv, gcode, step_dir_text, step_rows, to_csv};
use reach::drive::{
    DriveError, GridError, JointSample, StepSchedule, Verification, axes, grid_error, point_to_point,
    schedule_trajectory, verify,
};
use reach::model::JointKind;
use serde::{Deserialize, Serialize};

use crate::error::{CliError, one_line};
use crate::numbers::{AngleUnit, display_unit, parse_finite, to_si};
use crate::output::{Align, Table, fixed, write_json};
use crate::robot_arg::RobotArgs;
use reach::jobs::motion::{PlanRequest, Task};

/// Output formats of `reach drive`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DriveFormat {
    /// Per-joint steps, rates and the check against the plan, for people.
    Summary,
    /// One line per step: t_s,joint,name,dir,index,position,coils.
    Csv,
    /// {"robot", "duration_s", "joints", "check", "steps": [...]}.
    Json,
    /// G-code for GRBL/Marlin (axes X Y Z A B C in joint degrees).
    Gcode,
    /// Coil line states a1 b1 a2 b2 after every step.
    Coils,
    /// Step/direction event stream (microseconds).
    Events,
}

/// G-code flavour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Dialect {
    /// GRBL / grblHAL (dwell in seconds, `$100…` settings).
    Grbl,
    /// Marlin (dwell in milliseconds, `M92` settings).
    Marlin,
}

/// Arguments of `reach drive`.
#[derive(Debug, Clone, Args)]
pub struct DriveArgs {
    /// The robot (every joint needs `[joints.drive]` data).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Motion to drive: a JSON motion file {"samples": [{"t_s": 0.0, "q_deg": [...]}, ...]}
    /// with revolute joints in degrees and prismatic joints in metres (what `reach move --json`
    /// prints), or a task file (`.toml`, the `reach plan` format) whose motions are planned and
    /// driven one after the other.
    #[arg(value_name = "MOTION|TASK", conflicts_with_all = ["from", "to"])]
    pub motion: Option<PathBuf>,

    /// Point-to-point move: start joint values (degrees, or radians with --rad; metres for
    /// prismatic joints), space- or comma-separated.
    #[arg(long, num_args = 1.., value_delimiter = ',', allow_negative_numbers = true, requires = "to")]
    pub from: Vec<String>,

    /// Point-to-point move: target joint values.
    #[arg(long, num_args = 1.., value_delimiter = ',', allow_negative_numbers = true, requires = "from")]
    pub to: Vec<String>,

    /// Point-to-point duration in seconds (default: the shortest the motors allow).
    #[arg(long, value_name = "S", requires = "to")]
    pub duration: Option<String>,

    /// --from/--to revolute values are in radians.
    #[arg(long)]
    pub rad: bool,

    /// Output format.
    #[arg(long, value_enum, default_value_t = DriveFormat::Summary)]
    pub format: DriveFormat,

    /// G-code flavour.
    #[arg(long, value_enum, default_value_t = Dialect::Grbl)]
    pub dialect: Dialect,

    /// Write the output to FILE instead of stdout (a one-line note goes to stdout).
    #[arg(short = 'o', long = "output", value_name = "FILE")]
    pub output: Option<PathBuf>,
}

/// The part of a motion file `reach drive` reads; other fields (as in the full
/// `reach move --json` report) are ignored.
#[derive(Deserialize)]
struct MotionFile {
    samples: Vec<MotionSample>,
}

#[derive(Deserialize)]
struct MotionSample {
    t_s: f64,
    q_deg: Vec<f64>,
}

/// Per-joint summary in the JSON output.
#[derive(Debug, Serialize)]
struct JointJson {
    joint: usize,
    name: String,
    steps_per_unit: f64,
    start_position: i64,
    end_position: i64,
    steps: usize,
    max_rate_hz: f64,
    max_step_rate_hz: f64,
    max_deviation_steps: f64,
    max_deviation_si: f64,
}

#[derive(Debug, Serialize)]
struct DriveJson {
    robot: String,
    kind: &'static str,
    start_s: f64,
    duration_s: f64,
    joints: Vec<JointJson>,
    check: Verification,
    /// Point-to-point only: the target's rounding to the step grid.
    target_grid_error: Option<GridError>,
    steps: Vec<reach::drive::output::StepRow>,
}

fn drive_error(e: DriveError) -> CliError {
    let message = one_line(&e.to_string());
    match e {
        DriveError::RateLimit { .. } | DriveError::AccelerationLimit { .. } | DriveError::DurationTooShort { .. } => {
            CliError::NoSolution(message)
        }
        DriveError::Kinematics(_) => CliError::internal(message),
        _ => CliError::BadInput(message),
    }
}

fn parse_q(robot: &Robot, label: &str, texts: &[String], unit: AngleUnit) -> Result<Vec<f64>, CliError> {
    if texts.len() != robot.dof() {
        return Err(CliError::bad_input(format!(
            "{label}: robot `{}` has {} joints, got {} values",
            robot.name(),
            robot.dof(),
            texts.len()
        )));
    }
    robot
        .joints()
        .iter()
        .zip(texts)
        .enumerate()
        .map(|(i, (j, t))| Ok(to_si(j.kind, parse_finite(&format!("{label} joint {}", i + 1), t)?, unit)))
        .collect()
}

/// One sample in the file units (`q_deg`: degrees, prismatic metres) to SI; extra values are
/// kept so the schedule reports the length mismatch.
fn sample_si(robot: &Robot, t_s: f64, q_deg: &[f64]) -> JointSample {
    let q = robot
        .joints()
        .iter()
        .zip(q_deg)
        .map(|(j, &v)| to_si(j.kind, v, AngleUnit::Deg))
        .chain(q_deg.iter().skip(robot.dof()).copied())
        .collect();
    JointSample::new(t_s, q)
}

/// Reads the motion to drive: a task file (`.toml`) is planned motion by motion, anything else
/// is read as a JSON motion file.
fn read_motion(robot: &Robot, path: &Path) -> Result<Vec<JointSample>, CliError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::bad_input(format!("cannot read motion file `{}`: {e}", path.display())))?;
    if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
        return task_samples(robot, &text, path);
    }
    let file: MotionFile = serde_json::from_str(&text)
        .map_err(|e| CliError::bad_input(format!("motion file `{}`: {}", path.display(), one_line(&e.to_string()))))?;
    Ok(file.samples.iter().map(|s| sample_si(robot, s.t_s, &s.q_deg)).collect())
}

/// How far (rad or m) a task's motion may start from where the previous one ended.
const JOIN_TOLERANCE: f64 = 1e-6;

/// Plans every motion of a task file (as `reach plan` does) and joins them into one
/// trajectory: each motion starts where the previous one ended, in time and in joint space.
///
/// # Errors
/// [`CliError::BadInput`] when the task names another robot or a motion does not start where
/// the previous one ended; [`CliError::NoSolution`] for an infeasible motion.
fn task_samples(robot: &Robot, text: &str, path: &Path) -> Result<Vec<JointSample>, CliError> {
    let task = Task::parse(text)
        .map_err(|e| CliError::bad_input(format!("{}: {}", path.display(), one_line(&e.to_string()))))?;
    let task_robot =
        crate::robot_arg::load_robot(&task.robot, &reach::model::UrdfChain { base: None, tip: None })?.robot;
    if task_robot.name() != robot.name() || task_robot.dof() != robot.dof() {
        return Err(CliError::bad_input(format!(
            "task file `{}` is for robot `{}`, not `{}`",
            path.display(),
            task_robot.name(),
            robot.name()
        )));
    }
    let report = reach::jobs::motion::plan(robot, &PlanRequest { task: text.to_string() })?;
    let motions = &report.motions;
    let mut samples: Vec<JointSample> = Vec::new();
    for m in motions {
        if !m.feasible {
            return Err(CliError::NoSolution(format!(
                "motion `{}` is infeasible: {}",
                m.name,
                m.reasons.first().map_or("see `reach plan`", String::as_str)
            )));
        }
        let offset = samples.last().map_or(0.0, |s| s.t);
        let mut rows = m.samples.iter();
        if let (Some(last), Some(first)) = (samples.last(), m.samples.first()) {
            let start = sample_si(robot, offset, &first.q_deg);
            // The one joint-difference rule: what a joint-space move from `a` to `b` travels.
            let jump =
                (0..robot.dof()).position(|i| robot.joint_difference(i, last.q[i], start.q[i]).abs() > JOIN_TOLERANCE);
            if let Some(i) = jump {
                return Err(CliError::bad_input(format!(
                    "task file `{}`: motion `{}` starts away from where the previous motion ended \
                     (joint {} `{}`); a drive cannot jump",
                    path.display(),
                    m.name,
                    i + 1,
                    robot.joints()[i].name
                )));
            }
            rows.next();
        }
        samples.extend(rows.map(|s| sample_si(robot, offset + s.t_s - m.samples[0].t_s, &s.q_deg)));
    }
    Ok(samples)
}

/// Builds the schedule and writes the chosen output.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, missing drive data, unreadable motion or bad
/// numbers; [`CliError::NoSolution`] when the motion exceeds a motor's limits.
pub fn run(args: &DriveArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let axes = axes(robot).map_err(drive_error)?;
    let unit = if args.rad { AngleUnit::Rad } else { AngleUnit::Deg };
    let mut target_error = None;
    let (kind, schedule, plan, waypoints): (&str, StepSchedule, Vec<JointSample>, Vec<f64>) =
        match (&args.motion, args.from.is_empty()) {
            (Some(path), true) => {
                let samples = read_motion(robot, path)?;
                let schedule = schedule_trajectory(&axes, &samples).map_err(drive_error)?;
                let times = samples.iter().map(|s| s.t).collect();
                ("trajectory", schedule, samples, times)
            }
            (None, false) => {
                let from = parse_q(robot, "--from", &args.from, unit)?;
                let to = parse_q(robot, "--to", &args.to, unit)?;
                let duration = args.duration.as_deref().map(|d| parse_finite("--duration", d)).transpose()?;
                let p2p = point_to_point(&axes, &from, &to, duration, 0.0).map_err(drive_error)?;
                target_error = Some(grid_error(robot, &axes, &to).map_err(drive_error)?);
                let segments = ((p2p.duration / 0.02).ceil() as usize).clamp(10, 2000);
                let samples = p2p.samples(segments);
                let times = samples.iter().map(|s| s.t).collect();
                ("point_to_point", p2p.schedule, samples, times)
            }
            _ => {
                return Err(CliError::bad_input(
                    "give a motion file, or a point-to-point move with --from Q… --to Q… (not both)",
                ));
            }
        };
    let check = verify(robot, &schedule, &plan).map_err(drive_error)?;
    let text = match args.format {
        DriveFormat::Csv => to_csv(&schedule),
        DriveFormat::Coils => coil_table_csv(&schedule).map_err(drive_error)?,
        DriveFormat::Events => step_dir_text(&schedule),
        DriveFormat::Gcode => {
            let dialect = match args.dialect {
                Dialect::Grbl => GcodeDialect::Grbl,
                Dialect::Marlin => GcodeDialect::Marlin,
            };
            if waypoints.len() < 2 {
                return Err(CliError::bad_input("G-code needs a move that takes time"));
            }
            gcode(&schedule, &waypoints, dialect, robot.name()).map_err(drive_error)?
        }
        DriveFormat::Json => {
            let mut buffer = Vec::new();
            write_json(&mut buffer, &json(robot, kind, &schedule, &check, target_error))?;
            String::from_utf8(buffer).map_err(|e| CliError::internal(e.to_string()))?
        }
        DriveFormat::Summary => summary(robot, kind, &schedule, &check, target_error.as_ref())?,
    };
    match &args.output {
        Some(path) => {
            std::fs::write(path, &text)
                .map_err(|e| CliError::bad_input(format!("cannot write `{}`: {e}", path.display())))?;
            writeln!(out, "wrote {} lines to {}", text.lines().count(), path.display())?;
        }
        None => out.write_all(text.as_bytes())?,
    }
    Ok(())
}

fn max_rate(steps: &[reach::drive::Step]) -> f64 {
    steps.windows(2).map(|w| 1.0 / (w[1].t - w[0].t)).fold(0.0, f64::max)
}

fn json(
    robot: &Robot,
    kind: &'static str,
    schedule: &StepSchedule,
    check: &Verification,
    target_grid_error: Option<GridError>,
) -> DriveJson {
    DriveJson {
        robot: robot.name().to_string(),
        kind,
        start_s: schedule.start_time,
        duration_s: schedule.end_time - schedule.start_time,
        joints: schedule
            .joints
            .iter()
            .enumerate()
            .map(|(i, j)| JointJson {
                joint: j.axis.joint,
                name: j.axis.name.clone(),
                steps_per_unit: j.axis.steps_per_unit,
                start_position: j.start_position,
                end_position: j.end_position,
                steps: j.steps.len(),
                max_rate_hz: max_rate(&j.steps),
                max_step_rate_hz: j.axis.max_step_rate,
                max_deviation_steps: check.max_deviation_steps[i],
                max_deviation_si: check.max_deviation[i],
            })
            .collect(),
        check: check.clone(),
        target_grid_error,
        steps: step_rows(schedule),
    }
}

fn summary(
    robot: &Robot,
    kind: &str,
    schedule: &StepSchedule,
    check: &Verification,
    target: Option<&GridError>,
) -> Result<String, CliError> {
    let mut buffer: Vec<u8> = Vec::new();
    let out: &mut dyn Write = &mut buffer;
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
    head.pair("motion", kind.replace('_', "-"));
    head.pair("time", format!("{} .. {} s", fixed(schedule.start_time, 4), fixed(schedule.end_time, 4)));
    head.pair("steps", schedule.step_count().to_string());
    head.pair(
        "tool error",
        format!(
            "{} mm, {} deg (simulated vs planned, worst sample)",
            fixed(check.tool_position_error * 1e3, 4),
            fixed(check.tool_orientation_error.to_degrees(), 5)
        ),
    );
    if let Some(g) = target {
        head.pair(
            "target on step grid",
            format!(
                "tool moved {} mm, {} deg by rounding the target to whole steps",
                fixed(g.tool_position_error * 1e3, 4),
                fixed(g.tool_orientation_error.to_degrees(), 5)
            ),
        );
    }
    head.write(out, "")?;
    let mut table = Table::new(&[
        ("joint", Align::Right),
        ("name", Align::Left),
        ("steps/unit", Align::Right),
        ("start", Align::Right),
        ("end", Align::Right),
        ("steps", Align::Right),
        ("max Hz", Align::Right),
        ("limit Hz", Align::Right),
        ("max dev [steps]", Align::Right),
        ("max dev", Align::Right),
    ]);
    for (i, j) in schedule.joints.iter().enumerate() {
        let (unit, scale) = match j.axis.kind {
            JointKind::Revolute => (display_unit(JointKind::Revolute), 180.0 / std::f64::consts::PI),
            JointKind::Prismatic => ("mm", 1000.0),
        };
        table.row(vec![
            j.axis.joint.to_string(),
            j.axis.name.clone(),
            format!("{} /{unit}", fixed(j.axis.steps_per_unit / scale, 4)),
            j.start_position.to_string(),
            j.end_position.to_string(),
            j.steps.len().to_string(),
            fixed(max_rate(&j.steps), 1),
            fixed(j.axis.max_step_rate, 1),
            fixed(check.max_deviation_steps[i], 3),
            format!("{} {unit}", fixed(check.max_deviation[i] * scale, 5)),
        ]);
    }
    table.write(out, "  ")?;
    String::from_utf8(buffer).map_err(|e| CliError::internal(e.to_string()))
}
