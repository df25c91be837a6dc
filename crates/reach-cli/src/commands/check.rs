//! `reach check` — collisions and clearances of one configuration in a scene, and the swept
//! (continuous) check of a motion from it: with `--to` the straight joint motion to a second
//! configuration, with `--motion FILE` a sampled motion (`reach::jobs::world::check`;
//! `--json` prints its report).
//!
//! Exit status: 0 when the configuration is free and its motion, if any, proven clear; 3
//! otherwise (a collision, a tool outside its zone, a motion not proven clear), after
//! printing the report, with the verdict as one line on stderr; 2 for bad input.

use std::io::Write;

use clap::Args;
use reach::jobs::world::SweptReport;
use reach::jobs::{CheckReport, CheckRequest};
use reach::world::sweep::SWEEP_FLOOR;

use crate::error::{CliError, one_line};
use crate::numbers::{JointArgs, q_text};
use crate::output::{Align, Table, fixed, read_motion_file, verdict_exit, write_json};
use crate::pose_arg::joints_arg;
use crate::robot_arg::RobotArgs;

/// Arguments of `reach check`.
#[derive(Debug, Clone, Args)]
pub struct CheckArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Scene file (TOML: obstacles, tool zone, touching policy).
    #[arg(value_name = "SCENE")]
    pub scene: String,

    /// The joint values.
    #[command(flatten)]
    pub joints: JointArgs,

    /// Also check the straight joint-space motion to these joint values q1,..,qn, continuously:
    /// proven clear or not, the certified clearance bound and where it comes closest.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub to: Option<String>,

    /// With --to: the motion's duration in seconds (the joints move linearly in time). Needed
    /// when the scene has a moving obstacle (`velocity`): the motion is then checked in time,
    /// the obstacle where it is at each instant.
    #[arg(long, value_name = "S", requires = "to")]
    pub duration: Option<f64>,

    /// Instead of --to: check a sampled motion continuously, the piecewise-linear joint path
    /// from the joint values through its samples (the path `reach drive` steps along). FILE is
    /// `reach move --json`'s output or any JSON {"samples": [{"t_s", "q_deg"}, ...]}; `-`
    /// reads standard input.
    #[arg(long, value_name = "FILE", conflicts_with = "to")]
    pub motion: Option<std::path::PathBuf>,

    /// Print the report as JSON (docs/schemas/check.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// Reads a scene file's text (the library parses it).
///
/// # Errors
/// [`CliError::BadInput`] naming the file when it cannot be read.
pub fn read_scene(path: &str) -> Result<String, CliError> {
    std::fs::read_to_string(path).map_err(|e| CliError::bad_input(format!("cannot read scene `{path}`: {e}")))
}

/// Reads a scene file's text and validates it, for requests that carry a scene beside other
/// input (`reach move --scene`, `reach plan --scene`): a scene that does not parse is
/// reported with the file's name.
///
/// # Errors
/// [`CliError::BadInput`] naming the file.
pub fn read_valid_scene(path: &str) -> Result<String, CliError> {
    let text = read_scene(path)?;
    reach::jobs::world::parse_scene(&text).map_err(|e| scene_error(path, e))?;
    Ok(text)
}

/// A library error of a request with the scene of file `path`: a scene that does not parse is
/// reported with the file's name, anything else as it is.
#[must_use]
pub fn scene_error(path: &str, e: reach::Error) -> CliError {
    match e {
        reach::Error::World(w @ (reach::world::WorldError::Parse { .. } | reach::world::WorldError::Shape { .. })) => {
            CliError::bad_input(one_line(&format!("{path}: {w}")))
        }
        e => e.into(),
    }
}

/// Checks the configuration and prints the report; the exit status is the verdict of the
/// whole check ([`CheckReport::is_clear`]): 0 when the configuration is free and its motion
/// (`--to`, `--motion`) proven clear, 3 otherwise (after the report, with the verdict as the
/// one line on stderr).
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, scene or joint values; [`CliError::NoSolution`]
/// when the check does not hold; [`CliError::Output`].
pub fn run(args: &CheckArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let request = CheckRequest {
        scene: read_scene(&args.scene)?,
        q: args.joints.joints()?,
        to: args.to.as_deref().map(|t| joints_arg("--to", t, args.joints.rad)).transpose()?,
        duration_s: args.duration,
        samples: args.motion.as_deref().map(read_motion_file).transpose()?,
    };
    let report = reach::jobs::world::check(robot, &request).map_err(|e| match e {
        reach::Error::Request { .. } => crate::error::flagged(
            e,
            &[("q", "joint values"), ("to", "--to"), ("duration_s", "--duration"), ("samples", "--motion")],
        ),
        e => scene_error(&args.scene, e),
    })?;
    if args.json {
        write_json(out, &report)?;
    } else {
        write_text(robot, &report, out)?;
    }
    verdict_exit(out, (!report.is_clear()).then(|| failure_line(&report)))
}

/// The one line on stderr of a check that does not hold: its verdict, and where a motion is
/// not proven clear.
fn failure_line(report: &CheckReport) -> String {
    let swept = match (&report.motion, &report.samples) {
        (Some(m), _) if !m.swept.clear => Some(swept_text(&m.swept, None)),
        (_, Some(p)) if !p.swept.clear => Some(swept_text(&p.swept, Some(p.segment))),
        _ => None,
    };
    match swept {
        Some(s) => format!("check {}; swept check {s}", verdict_line(report)),
        None => format!("check {}", verdict_line(report)),
    }
}

/// The verdict of the whole check in words: the configuration's alone, or with a motion
/// `clear` / `NOT clear` followed by the start's verdict and the swept check's.
#[must_use]
pub fn verdict_line(report: &CheckReport) -> String {
    let swept = report.motion.as_ref().map(|m| &m.swept).or(report.samples.as_ref().map(|p| &p.swept));
    match swept {
        None => report.verdict_text.clone(),
        Some(w) => format!(
            "{}: start {}, motion {}",
            if report.is_clear() { "clear" } else { "NOT clear" },
            report.verdict_text,
            if w.clear { "proven clear" } else { "NOT proven clear" }
        ),
    }
}

/// A swept check in words: proven clear with its certified bound and closest approach, or
/// where it is not. `segment`: the 1-based segment of a path's check.
#[must_use]
pub fn swept_text(w: &SweptReport, segment: Option<usize>) -> String {
    let at = match segment {
        Some(k) => format!("{} % of segment {k}", fixed(100.0 * w.at, 1)),
        None => format!("{} % of the motion", fixed(100.0 * w.at, 1)),
    };
    let at = match w.t_s {
        Some(t) => format!("{at}, t = {} s", fixed(t, 4)),
        None => at,
    };
    match (w.clear, &w.pair_text, w.lower_bound_m, w.min_clearance_m) {
        (true, None, ..) => "proven clear (nothing to collide with)".to_string(),
        (true, Some(pair), Some(lb), Some(min)) => format!(
            "proven clear: clearance ≥ {} m over the whole motion (closest {} m, {pair}, at {at})",
            fixed(lb, 6),
            fixed(min, 6)
        ),
        (_, pair, _, min) => format!(
            "NOT proven clear: {} at {at} ({})",
            pair.as_deref().unwrap_or("-"),
            match min {
                Some(c) if c > SWEEP_FLOOR => format!("clearance {} m", fixed(c, 6)),
                _ => "touching or colliding".to_string(),
            }
        ),
    }
}

fn write_text(robot: &reach::Robot, report: &CheckReport, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("verdict", verdict_line(report));
    head.pair("robot", robot.name().to_string());
    head.pair("q", q_text(robot, &report.q_deg));
    let mm = |v: Option<f64>| v.map_or("-".to_string(), |c| format!("{} m", fixed(c, 6)));
    head.pair("min obstacle clearance", mm(report.min_obstacle_clearance_m));
    head.pair("min self clearance", mm(report.min_self_clearance_m));
    if let Some(m) = &report.motion {
        head.pair("motion to", q_text(robot, &m.to_deg));
        head.pair("swept check", swept_text(&m.swept, None));
    }
    if let Some(p) = &report.samples {
        head.pair("motion (samples)", swept_text(&p.swept, Some(p.segment)));
    }
    head.write(out, "")?;
    if !report.tool_zone.is_empty() {
        writeln!(out, "tool zone (signed distance, negative = inside):")?;
        let mut t = Table::new(&[("zone", Align::Left), ("distance [m]", Align::Right), ("inside", Align::Left)]);
        for z in &report.tool_zone {
            t.row(vec![z.zone.clone(), fixed(z.signed_distance_m, 6), z.inside.to_string()]);
        }
        t.write(out, "  ")?;
    }
    if !report.links.is_empty() {
        writeln!(out, "link clearances (negative = penetration):")?;
        let mut t = Table::new(&[
            ("link", Align::Left),
            ("obstacle", Align::Left),
            ("clearance [m]", Align::Right),
            ("colliding", Align::Left),
        ]);
        for l in &report.links {
            t.row(vec![
                format!("{} {}", l.link, l.link_name),
                l.obstacle.clone(),
                fixed(l.clearance_m, 6),
                l.colliding.to_string(),
            ]);
        }
        t.write(out, "  ")?;
    }
    if !report.self_pairs.is_empty() {
        writeln!(out, "non-adjacent link pairs:")?;
        let mut t = Table::new(&[("links", Align::Left), ("clearance [m]", Align::Right), ("colliding", Align::Left)]);
        for p in &report.self_pairs {
            t.row(vec![
                format!("{}-{} {} / {}", p.link_a, p.link_b, p.name_a, p.name_b),
                fixed(p.clearance_m, 6),
                p.colliding.to_string(),
            ]);
        }
        t.write(out, "  ")?;
    }
    Ok(())
}
