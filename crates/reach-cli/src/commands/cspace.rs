//! `reach cspace` — seed 004's configuration-space grid: classify every node
//! (`reach::jobs::world::cspace`; `--json` prints its report).

use std::collections::BTreeMap;
use std::io::Write;

use clap::Args;
use reach::jobs::world::{CspaceReport, CspaceRequest, cspace_axes, cspace_with_cancel};
use reach::world::WorldError;

use crate::commands::check::{read_scene, scene_error};
use crate::commands::cspace_render;
use crate::error::CliError;
use crate::numbers::{parse_count, parse_finite};
use crate::output::{Align, Table, write_json};
use crate::plot::progress::Progress;
use crate::robot_arg::RobotArgs;

pub use crate::commands::cspace_render::SectionArgs;

/// Arguments of `reach cspace`.
#[derive(Debug, Clone, Args)]
pub struct CspaceArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Scene file (TOML: obstacles, tool zone, touching policy).
    #[arg(value_name = "SCENE")]
    pub scene: String,

    /// Grid step in degrees (metres for prismatic joints).
    #[arg(long, default_value = "15", value_name = "DEG")]
    pub step: String,

    /// Fix a joint: `q1=0` (degrees; repeatable). Other joints sweep their limits.
    #[arg(long, value_name = "qI=VALUE")]
    pub fix: Vec<String>,

    /// Largest number of grid nodes to classify (default 20000000, at most 200000000): a
    /// finer grid is refused before anything is allocated.
    #[arg(long, value_name = "N")]
    pub max_nodes: Option<String>,

    /// Print the report as JSON (docs/schemas/cspace.report.schema.json).
    #[arg(long)]
    pub json: bool,

    /// Fit seed 004's R-function region to the grid (exactly three swept joints) and print
    /// its primitives and confusion counts.
    #[arg(long)]
    pub fit: bool,
    /// Section images: --svg DIR, --png DIR, --png-width PX.
    #[command(flatten)]
    pub sections: SectionArgs,
}

impl CspaceArgs {
    /// The library request (the scene file read).
    ///
    /// # Errors
    /// [`CliError::BadInput`] for an unreadable scene, a malformed step or `--fix`.
    pub fn request(&self) -> Result<CspaceRequest, CliError> {
        let mut fix = BTreeMap::new();
        for f in &self.fix {
            let (name, value) =
                f.split_once('=').ok_or_else(|| CliError::bad_input(format!("--fix expects qI=VALUE, got `{f}`")))?;
            fix.insert(name.trim().to_string(), parse_finite(&format!("--fix {}", name.trim()), value)?);
        }
        Ok(CspaceRequest {
            scene: read_scene(&self.scene)?,
            step_deg: parse_finite("--step", &self.step)?,
            fix,
            fit: self.fit,
            max_nodes: self.max_nodes.as_deref().map(|t| parse_count("--max-nodes", t)).transpose()?,
        })
    }
}

/// Classifies the grid and prints the counts.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, scene, step or `--fix`, or `--fit` on a grid
/// that does not sweep three joints; [`CliError::NoSolution`] for `--fit` without an
/// allowed node; [`CliError::Output`].
pub fn run(args: &CspaceArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let robot = &loaded.robot;
    let request = args.request()?;
    let flags = [("step_deg", "--step"), ("max_nodes", "--max-nodes"), ("fix", "--fix")];
    let axes = cspace_axes(robot, &request).map_err(|e| match e {
        e @ reach::Error::Request { .. } => crate::error::flagged(e, &flags),
        e => scene_error(&args.scene, e),
    })?;
    let swept: Vec<usize> = (0..axes.len()).filter(|&j| axes[j].len() > 1).collect();
    if args.sections.any() && !(2..=3).contains(&swept.len()) {
        return Err(CliError::bad_input(format!(
            "--svg/--png section images need 2 or 3 swept joints, this grid sweeps {} (fix the others with --fix)",
            swept.len()
        )));
    }
    args.sections.prepare()?;
    let total = axes.iter().map(Vec::len).product::<usize>();
    let bar = Progress::new(total as u64, "classifying", args.json);
    let result = cspace_with_cancel(robot, &request, &|done, _| bar.set(done as u64), crate::interrupt::cancel());
    bar.finish();
    let (report, grid) = result.map_err(|e| match e {
        reach::Error::World(w @ WorldError::NoAllowedNode) => CliError::NoSolution(format!("--fit: {w}")),
        reach::Error::World(WorldError::Cancelled) => CliError::Interrupted,
        reach::Error::Request { field, reason } if field == "fit" => CliError::bad_input(format!("--fit: {reason}")),
        e => scene_error(&args.scene, e),
    })?;
    args.sections.write(robot, &grid, &swept)?;
    if args.json {
        return write_json(out, &report);
    }
    write_text(&report, out)
}

fn write_text(report: &CspaceReport, out: &mut dyn Write) -> Result<(), CliError> {
    let mut head = Table::key_value();
    head.pair("robot", report.robot.clone());
    head.pair("step", format!("{} deg", report.step_deg));
    head.pair("nodes", report.counts.nodes.to_string());
    head.pair("allowed", report.counts.allowed.to_string());
    head.pair("outside limits", report.counts.outside_limits.to_string());
    head.pair("outside tool zone", report.counts.outside_zone.to_string());
    head.pair("self-collision", report.counts.self_collision.to_string());
    head.pair("obstacle collision", report.counts.obstacle_collision.to_string());
    head.write(out, "")?;
    if let Some(s) = report.sections.first() {
        writeln!(out, "allowed nodes per value of q{}:", s.joint)?;
        let mut t = Table::new(&[("value [deg]", Align::Right), ("nodes", Align::Right), ("allowed", Align::Right)]);
        for s in &report.sections {
            t.row(vec![crate::output::num(s.value_deg), s.counts.nodes.to_string(), s.counts.allowed.to_string()]);
        }
        t.write(out, "  ")?;
    }
    if let Some(f) = &report.fit {
        cspace_render::write_text(out, f)?;
    }
    Ok(())
}
