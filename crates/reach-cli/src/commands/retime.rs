//! `reach retime` — the time-optimal motion through a path's waypoints under the joints'
//! velocity and acceleration limits (`reach::jobs::retime`; `--json` prints its report,
//! `--csv FILE` writes its samples, `--ros FILE` the ROS `JointTrajectory` message).

use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Args;
use reach::Robot;
use reach::jobs::JointTrajectory;
use reach::jobs::input::{AngleUnit, from_si, joint_columns, number_text, parse_path_file, unit_name};
use reach::jobs::retime::{Interpolation, RetimeReport, RetimeRequest};

use crate::error::{CliError, flagged};
use crate::numbers::parse_finite;
use crate::output::{Align, Table, fixed, read_file, write_file, write_json};
use crate::robot_arg::RobotArgs;

/// `--interpolation`: `spline`, `linear`, `blend` or `blend:TOL` (TOL in radians; metres for
/// prismatic joints), as the request's interpolation and blend tolerance.
///
/// # Errors
/// [`CliError::BadInput`] for another word or a TOL that is not a finite number.
pub fn parse_interpolation(text: &str) -> Result<(Interpolation, Option<f64>), CliError> {
    match text.split_once(':') {
        None if text == "spline" => Ok((Interpolation::Spline, None)),
        None if text == "linear" => Ok((Interpolation::Linear, None)),
        None if text == "blend" => Ok((Interpolation::Blend, None)),
        Some(("blend", tol)) => Ok((Interpolation::Blend, Some(parse_finite("--interpolation blend:TOL", tol)?))),
        _ => Err(CliError::bad_input(format!(
            "--interpolation: `{text}` is not one of spline, linear, blend, blend:TOL (TOL in rad)"
        ))),
    }
}

/// The limits' scales of a time-optimal motion (MoveIt's scaling factors): what `reach retime`
/// and `reach path --timing optimal` both read.
#[derive(Debug, Clone, Args)]
pub struct LimitScaleArgs {
    /// Multiplies every joint's velocity limit, in (0, 1].
    #[arg(long, value_name = "F", default_value = "1")]
    pub max_velocity_scale: String,

    /// Multiplies every joint's acceleration limit, in (0, 1].
    #[arg(long, value_name = "F", default_value = "1")]
    pub max_acceleration_scale: String,
}

impl LimitScaleArgs {
    /// The library's field names and their flags, for [`flagged`].
    pub const FLAGS: [(&'static str, &'static str); 2] =
        [("max_velocity_scale", "--max-velocity-scale"), ("max_acceleration_scale", "--max-acceleration-scale")];

    /// The velocity and the acceleration scale.
    ///
    /// # Errors
    /// [`CliError::BadInput`] for a value that is not a finite number.
    pub fn parse(&self) -> Result<(f64, f64), CliError> {
        Ok((
            parse_finite("--max-velocity-scale", &self.max_velocity_scale)?,
            parse_finite("--max-acceleration-scale", &self.max_acceleration_scale)?,
        ))
    }
}

/// Arguments of `reach retime`.
#[derive(Debug, Clone, Args)]
pub struct RetimeArgs {
    /// The robot (its joints' `max_velocity` and `max_acceleration` are the limits).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The path: a CSV with one joint vector per row (degrees, or radians with --rad;
    /// prismatic joints in metres; a header row and `#` comments are skipped), or the JSON of
    /// `reach path`, `reach approach` or `reach move`; `-` reads standard input.
    #[arg(value_name = "PATH")]
    pub path: PathBuf,

    /// How the waypoints are joined: `spline` (the not-a-knot cubic spline at uniform
    /// parameter, toppra's: no stop at the waypoints), `linear` (straight segments, resting at
    /// every waypoint), `blend` or `blend:TOL` (straight segments whose corners are cut by
    /// parabolic blends passing within TOL of each waypoint, joint-space distance in radians —
    /// metres for prismatic joints; default 0.1, MoveIt's path tolerance; no stop).
    #[arg(long, value_name = "HOW", default_value = "spline")]
    pub interpolation: String,

    /// Sample step of the output, seconds.
    #[arg(long, value_name = "S", default_value = "0.01")]
    pub dt: String,

    /// --max-velocity-scale, --max-acceleration-scale.
    #[command(flatten)]
    pub scales: LimitScaleArgs,

    /// Grid intervals per path piece (default 64, fewer on long paths).
    #[arg(long, value_name = "N")]
    pub points_per_piece: Option<usize>,

    /// The CSV's revolute values, and the output's, are in radians.
    #[arg(long)]
    pub rad: bool,

    /// Print the report as JSON (docs/schemas/retime.report.schema.json; SI units).
    #[arg(long)]
    pub json: bool,

    /// Write the samples to FILE: t_s, then per joint q, qd, qdd in the unit of the CSV
    /// (degrees, or radians with --rad; prismatic metres), named in the header.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Write the motion to FILE as the ROS 2 message `trajectory_msgs/msg/JointTrajectory`
    /// (docs/schemas/joint_trajectory.schema.json): the robot's joint names, one point per
    /// sample with positions, velocities and accelerations in SI units (rad, m, s) and
    /// `time_from_start` to the nanosecond. YAML when FILE ends in `.yaml` or `.yml` (a message
    /// file, `ros2 topic pub`'s form), JSON when it ends in `.json`.
    #[arg(long, value_name = "FILE")]
    pub ros: Option<PathBuf>,
}

/// How `--ros FILE` writes the message, by FILE's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RosFormat {
    Yaml,
    Json,
}

/// The format of `--ros FILE`: YAML for `.yaml`/`.yml`, JSON for `.json` (any case).
fn ros_format(path: &Path) -> Result<RosFormat, CliError> {
    let extension = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("yaml" | "yml") => Ok(RosFormat::Yaml),
        Some("json") => Ok(RosFormat::Json),
        _ => Err(CliError::bad_input(format!(
            "--ros {}: the file name must end in .yaml or .yml (YAML) or .json (JSON)",
            path.display()
        ))),
    }
}

/// Writes the motion as the ROS `JointTrajectory` message to `path` in `format`.
fn write_ros(robot: &Robot, report: &RetimeReport, path: &Path, format: RosFormat) -> Result<(), CliError> {
    let names = robot.joints().iter().map(|j| j.name.clone()).collect();
    let message = JointTrajectory::from_retime(report, names)
        .map_err(|e| CliError::bad_input(format!("--ros {}: {}", path.display(), reach::one_line(&e.to_string()))))?;
    let text = match format {
        RosFormat::Yaml => message.to_yaml().map_err(|e| CliError::internal(e.to_string()))?.into_bytes(),
        RosFormat::Json => {
            let mut text = Vec::new();
            write_json(&mut text, &message)?;
            text
        }
    };
    write_file("--ros", path, text)
}

/// Times the path and prints the report.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, path file, number or limit (the message names the
/// flag, the file's line or the joint).
pub fn run(args: &RetimeArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let ros_format = args.ros.as_deref().map(ros_format).transpose()?;
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let unit = if args.rad { AngleUnit::Rad } else { AngleUnit::Deg };
    let text = read_file(&args.path)?;
    let source =
        if args.path == Path::new("-") { "standard input".to_string() } else { args.path.display().to_string() };
    let waypoints = parse_path_file(&text, unit)
        .map_err(|e| CliError::bad_input(format!("{source}: {}", reach::one_line(&e.to_string()))))?;
    let (max_velocity_scale, max_acceleration_scale) = args.scales.parse()?;
    let (interpolation, blend_tolerance) = parse_interpolation(&args.interpolation)?;
    let request = RetimeRequest {
        waypoints,
        interpolation,
        blend_tolerance,
        dt: Some(parse_finite("--dt", &args.dt)?),
        max_velocity_scale,
        max_acceleration_scale,
        points_per_piece: args.points_per_piece,
    };
    let report = reach::jobs::retime::retime(robot, &request).map_err(|e| {
        flagged(
            e,
            &[
                ("waypoint", format!("{source} waypoint")),
                ("dt", "--dt".into()),
                ("blend_tolerance", "--interpolation blend:TOL".into()),
                (LimitScaleArgs::FLAGS[0].0, LimitScaleArgs::FLAGS[0].1.into()),
                (LimitScaleArgs::FLAGS[1].0, LimitScaleArgs::FLAGS[1].1.into()),
                ("points_per_piece", "--points-per-piece".into()),
            ],
        )
    })?;
    if let Some(path) = &args.csv {
        write_file("--csv", path, csv_text(robot, &report, unit))?;
    }
    if let (Some(path), Some(format)) = (&args.ros, ros_format) {
        write_ros(robot, &report, path, format)?;
    }
    if args.json {
        return write_json(out, &report);
    }
    write_text(robot, &report, unit, out)
}

/// The samples as CSV in the display unit `unit`.
fn csv_text(robot: &Robot, r: &RetimeReport, unit: AngleUnit) -> String {
    let joints = robot.joints();
    let mut text = String::from("t_s");
    for (quantity, per) in [("q", ""), ("qd", "_s"), ("qdd", "_s2")] {
        for name in joint_columns(robot, unit, quantity, per) {
            text.push(',');
            text.push_str(&name);
        }
    }
    text.push('\n');
    for s in &r.samples {
        let mut cells = vec![format!("{}", s.t_s)];
        for values in [&s.q, &s.qd, &s.qdd] {
            cells.extend(values.iter().zip(joints).map(|(&v, j)| format!("{}", from_si(j.kind, v, unit))));
        }
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    text
}

fn write_text(robot: &Robot, r: &RetimeReport, unit: AngleUnit, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", format!("{} ({} joints)", robot.name(), robot.dof()));
    let how = match r.interpolation {
        Interpolation::Spline => "cubic spline (not-a-knot, uniform parameter)".to_string(),
        Interpolation::Linear => "straight segments, resting at each waypoint".to_string(),
        Interpolation::Blend => format!(
            "straight segments blended at the corners within {} rad of each waypoint",
            number_text(r.blend_tolerance.unwrap_or_default())
        ),
    };
    head.pair("path", format!("{} waypoints, {how}", r.waypoints));
    head.pair("duration", format!("{} s (time-optimal, rest to rest)", fixed(r.duration_s, 6)));
    head.pair(
        "grid",
        format!("{} points; slow-down {} so the limits hold between them", r.grid_points, fixed(r.slowdown, 6)),
    );
    head.write(out, "")?;
    let mut table = Table::new(&[
        ("joint", Align::Right),
        ("name", Align::Left),
        ("max speed", Align::Right),
        ("worst speed ratio", Align::Right),
        ("max acceleration", Align::Right),
        ("worst acceleration ratio", Align::Right),
    ]);
    for (i, j) in robot.joints().iter().enumerate() {
        let u = unit_name(j.kind, unit);
        table.row(vec![
            (i + 1).to_string(),
            j.name.clone(),
            format!("{} {u}/s", fixed(from_si(j.kind, r.velocity_limits[i], unit), 3)),
            fixed(r.worst_velocity_ratio[i], 6),
            format!("{} {u}/s²", fixed(from_si(j.kind, r.acceleration_limits[i], unit), 3)),
            fixed(r.worst_acceleration_ratio[i], 6),
        ]);
    }
    writeln!(out, "limits (worst ratio: exact largest |value| / limit over the whole motion, not only at samples):")?;
    table.write(out, "  ")?;
    let step = r.samples.get(1).map_or(0.0, |s| s.t_s);
    writeln!(
        out,
        "{} samples every {} s (--json prints them, --csv FILE writes them, --ros FILE as a ROS JointTrajectory)",
        r.samples.len(),
        fixed(step, 6)
    )?;
    Ok(())
}
