//! `reach drive` — stepper step schedules from a sampled motion, a task file or a point-to-point move:
//! a summary for people, CSV/JSON step lists, coil tables, step/direction events or G-code.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use reach::Robot;
use reach::drive::DriveError;
use reach::drive::output::GcodeDialect;
use reach::jobs::drive::{DriveMotion, DriveMotionKind, DriveProgram, DriveReport, DriveRequest, PointToPointRequest};
use reach::jobs::motion::Task;
use reach::model::{JointKind, UrdfChain};

use crate::error::{CliError, flagged, one_line};
use crate::numbers::{display_unit, parse_finite};
use crate::output::{Align, Table, fixed, read_file, read_motion_file, write_file, write_json};
use crate::pose_arg::joints_arg;
use crate::robot_arg::{RobotArgs, load_robot};

/// Output formats of `reach drive`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum DriveFormat {
    /// Per-joint steps, rates and the check against the plan, for people.
    Summary,
    /// One line per step: t_s,joint,name,dir,index,position,coils.
    Csv,
    /// The report (docs/schemas/drive.report.schema.json): joints, check, steps.
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
    /// The robot (its `[joints.drive]` data; a joint without gets the default simulated motor
    /// of `reach serve`, `reach::drive::simulated`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Motion to drive: a JSON motion file {"samples": [{"t_s": 0.0, "q_deg": [...]}, ...]}
    /// with revolute joints in degrees and prismatic joints in metres (what `reach move --json`
    /// prints), or a task file (`.toml`, the `reach plan` format) whose motions are planned and
    /// driven one after the other.
    #[arg(value_name = "MOTION|TASK", conflicts_with_all = ["from", "to"])]
    pub motion: Option<PathBuf>,

    /// Point-to-point move: start joint values q1,..,qn (degrees, or radians with --rad;
    /// metres for prismatic joints), comma- or blank-separated.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true, requires = "to")]
    pub from: Option<String>,

    /// Point-to-point move: target joint values q1,..,qn.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true, requires = "from")]
    pub to: Option<String>,

    /// Point-to-point duration in seconds (default: the shortest the motors allow).
    #[arg(long, value_name = "S", allow_hyphen_values = true, requires = "to")]
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

/// The request of these arguments: the motion file or task file read, numbers parsed.
///
/// # Errors
/// [`CliError::BadInput`] for an unreadable file, a task file for another robot, bad numbers,
/// or neither/both of a file and `--from/--to`.
fn request(args: &DriveArgs, robot: &Robot) -> Result<DriveRequest, CliError> {
    let motion = match (&args.motion, &args.from, &args.to) {
        (Some(path), None, None) => {
            if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) {
                let text = read_file(path)?;
                let task = Task::parse(&text)
                    .map_err(|e| CliError::bad_input(format!("{}: {}", path.display(), one_line(&e.to_string()))))?;
                let task_robot = load_robot(&task.robot, &UrdfChain { base: None, tip: None })?.robot;
                if task_robot.name() != robot.name() || task_robot.dof() != robot.dof() {
                    return Err(CliError::bad_input(format!(
                        "task file `{}` is for robot `{}`, not `{}`",
                        path.display(),
                        task_robot.name(),
                        robot.name()
                    )));
                }
                DriveMotion::Task(text)
            } else {
                DriveMotion::Samples(read_motion_file(path)?)
            }
        }
        (None, Some(from), Some(to)) => DriveMotion::PointToPoint(PointToPointRequest {
            from: joints_arg("--from", from, args.rad)?,
            to: joints_arg("--to", to, args.rad)?,
            duration_s: args.duration.as_deref().map(|d| parse_finite("--duration", d)).transpose()?,
        }),
        _ => {
            return Err(CliError::bad_input(
                "give a motion file, or a point-to-point move with --from Q1,..,QN --to Q1,..,QN (not both)",
            ));
        }
    };
    let program = match args.format {
        DriveFormat::Summary | DriveFormat::Json => None,
        DriveFormat::Csv => Some(DriveProgram::Csv),
        DriveFormat::Coils => Some(DriveProgram::Coils),
        DriveFormat::Events => Some(DriveProgram::Events),
        DriveFormat::Gcode => Some(DriveProgram::Gcode(match args.dialect {
            Dialect::Grbl => GcodeDialect::Grbl,
            Dialect::Marlin => GcodeDialect::Marlin,
        })),
    };
    Ok(DriveRequest { motion, program })
}

/// Exit status 3 for a motion the motors cannot follow, 2 for other bad input, flags named.
fn drive_error(e: reach::Error) -> CliError {
    match &e {
        reach::Error::Drive(
            DriveError::RateLimit { .. }
            | DriveError::AccelerationLimit { .. }
            | DriveError::DurationTooShort { .. }
            | DriveError::InfeasibleMotion { .. },
        ) => CliError::NoSolution(one_line(&e.to_string())),
        _ => flagged(e, &[("from", "--from"), ("to", "--to"), ("duration_s", "--duration"), ("program", "--format")]),
    }
}

/// Builds the schedule and writes the chosen output.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, missing drive data, unreadable motion, bad numbers
/// or joint values outside their limits; [`CliError::NoSolution`] when the motion exceeds a
/// motor's limits.
pub fn run(args: &DriveArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    // Joints without `[joints.drive]` data get the default simulated motors, as in `reach serve`.
    let (robot, simulated) = reach::drive::with_simulated_drives(&loaded.robot).map_err(reach::Error::from)?;
    let robot = &robot;
    let request = request(args, robot)?;
    let report = reach::jobs::drive::drive(robot, &request).map_err(drive_error)?;
    let text = match (args.format, &report.program) {
        (DriveFormat::Json, _) => {
            let mut buffer = Vec::new();
            write_json(&mut buffer, &report)?;
            String::from_utf8(buffer).map_err(|e| CliError::internal(e.to_string()))?
        }
        (DriveFormat::Summary, _) => summary(robot, &report, &simulated)?,
        (_, Some(program)) => program.clone(),
        (_, None) => return Err(CliError::internal("the drive report has no program text")),
    };
    match &args.output {
        Some(path) => {
            write_file("--output", path, &text)?;
            writeln!(out, "wrote {} lines to {}", text.lines().count(), path.display())?;
        }
        None => out.write_all(text.as_bytes())?,
    }
    Ok(())
}

/// The summary text; `simulated`: the 0-based joints driven by default simulated motors.
fn summary(robot: &Robot, report: &DriveReport, simulated: &[usize]) -> Result<String, CliError> {
    let mut buffer: Vec<u8> = Vec::new();
    let out: &mut dyn Write = &mut buffer;
    let check = &report.check;
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
    if !simulated.is_empty() {
        let joints: Vec<String> = simulated.iter().map(|j| (j + 1).to_string()).collect();
        head.pair("simulated drives", format!("joints {} (no [joints.drive] data: default motors)", joints.join(", ")));
    }
    let motion = match report.motion {
        DriveMotionKind::Samples => "trajectory",
        DriveMotionKind::Task => "task",
        DriveMotionKind::PointToPoint => "point-to-point",
    };
    head.pair("motion", motion.to_string());
    let end = report.start_s + report.duration_s;
    head.pair("time", format!("{} .. {} s", fixed(report.start_s, 4), fixed(end, 4)));
    head.pair("steps", report.steps.len().to_string());
    head.pair(
        "tool error",
        format!(
            "{} mm, {} deg (simulated vs planned, worst sample)",
            fixed(check.tool_position_error * 1e3, 4),
            fixed(check.tool_orientation_error.to_degrees(), 5)
        ),
    );
    if let Some(g) = &report.target_grid_error {
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
    for j in &report.joints {
        let (unit, scale) = match j.joint_kind {
            JointKind::Revolute => (display_unit(JointKind::Revolute), 180.0 / std::f64::consts::PI),
            JointKind::Prismatic => ("mm", 1000.0),
        };
        table.row(vec![
            j.joint.to_string(),
            j.name.clone(),
            format!("{} /{unit}", fixed(j.steps_per_unit / scale, 4)),
            j.start_position.to_string(),
            j.end_position.to_string(),
            j.steps.to_string(),
            fixed(j.max_rate_hz, 1),
            fixed(j.max_step_rate_hz, 1),
            fixed(j.max_deviation_steps, 3),
            format!("{} {unit}", fixed(j.max_deviation_si * scale, 5)),
        ]);
    }
    table.write(out, "  ")?;
    String::from_utf8(buffer).map_err(|e| CliError::internal(e.to_string()))
}
