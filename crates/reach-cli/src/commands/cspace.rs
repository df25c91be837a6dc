//! `reach cspace` — seed 004's configuration-space grid: classify every node.

use std::io::Write;

use clap::Args;
use reach::world::cspace::{CspaceGrid, GridCounts, GridSpec, classify_grid_with_progress, grid_axes};
use serde::Serialize;

use crate::commands::check::load_scene;
use crate::commands::cspace_fit;
use crate::error::CliError;
use crate::numbers::parse_finite;
use crate::output::{Align, Table, write_json};
use crate::plot::progress::Progress;
use crate::robot_arg::RobotArgs;

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

    /// Print JSON.
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

/// Where `reach cspace` draws its section images.
#[derive(Debug, Clone, Default, Args)]
pub struct SectionArgs {
    /// Write one SVG image per value of the first swept joint into DIR (created if needed):
    /// the next two swept joints, each node coloured by its class.
    #[arg(long = "svg", value_name = "DIR")]
    pub svg_dir: Option<std::path::PathBuf>,

    /// The same images as PNG into DIR.
    #[arg(long = "png", value_name = "DIR")]
    pub png_dir: Option<std::path::PathBuf>,

    /// Width of the PNG images in pixels (default 920).
    #[arg(long, value_name = "PX", requires = "png_dir")]
    pub png_width: Option<u32>,
}

/// JSON output of `reach cspace`.
#[derive(Debug, Serialize)]
struct CspaceJson {
    robot: String,
    step_deg: f64,
    nodes: usize,
    allowed: usize,
    outside_limits: usize,
    outside_zone: usize,
    self_collision: usize,
    obstacle_collision: usize,
    /// Counts per value of the first swept joint.
    sections: Vec<Section>,
    /// `--fit`: the fitted region's primitives and confusion counts.
    #[serde(skip_serializing_if = "Option::is_none")]
    fit: Option<cspace_fit::FitJson>,
}

#[derive(Debug, Serialize)]
struct Section {
    joint: usize,
    value_deg: f64,
    #[serde(flatten)]
    counts: GridCounts,
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
    let scene = load_scene(&args.scene)?;
    let step_deg = parse_finite("--step", &args.step)?;
    if step_deg <= 0.0 {
        return Err(CliError::bad_input(format!("--step must be positive, got {step_deg}")));
    }
    let mut spec = GridSpec::new(robot.dof(), step_deg.to_radians());
    for f in &args.fix {
        let (name, value) =
            f.split_once('=').ok_or_else(|| CliError::bad_input(format!("--fix expects qI=VALUE, got `{f}`")))?;
        let index: usize =
            name.trim()
                .trim_start_matches('q')
                .parse()
                .ok()
                .filter(|i| (1..=robot.dof()).contains(i))
                .ok_or_else(|| CliError::bad_input(format!("--fix: `{name}` is not a joint q1..q{}", robot.dof())))?;
        let v = parse_finite(&format!("--fix {name}"), value)?;
        spec = spec.fix(index - 1, v.to_radians());
    }
    let axes = grid_axes(robot, &spec).map_err(|e| CliError::bad_input(e.to_string()))?;
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
    let grid = classify_grid_with_progress(robot, &scene, &spec, &|done, _| bar.set(done as u64))
        .map_err(|e| CliError::bad_input(e.to_string()))?;
    bar.finish();
    args.sections.write(robot, &grid, &swept)?;
    let first = grid.axes.iter().position(|a| a.len() > 1);
    let sections: Vec<Section> = first.map_or_else(Vec::new, |j| {
        grid.counts_by(j)
            .into_iter()
            .zip(&grid.axes[j])
            .map(|(counts, v)| Section { joint: j + 1, value_deg: v.to_degrees(), counts })
            .collect()
    });
    let fit = if args.fit { Some(cspace_fit::fit(&grid)?.1) } else { None };
    let c = grid.counts;
    if args.json {
        return write_json(
            out,
            &CspaceJson {
                robot: robot.name().to_string(),
                step_deg,
                nodes: c.nodes,
                allowed: c.allowed,
                outside_limits: c.outside_limits,
                outside_zone: c.outside_zone,
                self_collision: c.self_collision,
                obstacle_collision: c.obstacle_collision,
                sections,
                fit,
            },
        );
    }
    let mut head = Table::key_value();
    head.pair("robot", robot.name().to_string());
    head.pair("step", format!("{step_deg} deg"));
    head.pair("nodes", c.nodes.to_string());
    head.pair("allowed", c.allowed.to_string());
    head.pair("outside limits", c.outside_limits.to_string());
    head.pair("outside tool zone", c.outside_zone.to_string());
    head.pair("self-collision", c.self_collision.to_string());
    head.pair("obstacle collision", c.obstacle_collision.to_string());
    head.write(out, "")?;
    if let Some(s) = sections.first() {
        writeln!(out, "allowed nodes per value of q{}:", s.joint)?;
        let mut t = Table::new(&[("value [deg]", Align::Right), ("nodes", Align::Right), ("allowed", Align::Right)]);
        for s in &sections {
            t.row(vec![
                format!("{}", (s.value_deg * 1e9).round() / 1e9),
                s.counts.nodes.to_string(),
                s.counts.allowed.to_string(),
            ]);
        }
        t.write(out, "  ")?;
    }
    if let Some(f) = &fit {
        cspace_fit::write_text(out, f)?;
    }
    Ok(())
}

impl SectionArgs {
    fn any(&self) -> bool {
        self.svg_dir.is_some() || self.png_dir.is_some()
    }

    /// Creates the output directories (before the grid is computed).
    fn prepare(&self) -> Result<(), CliError> {
        if let Some(d) = &self.svg_dir {
            crate::plot::ensure_dir("--svg", d)?;
        }
        if let Some(d) = &self.png_dir {
            crate::plot::ensure_dir("--png", d)?;
        }
        Ok(())
    }

    /// One image per value of the first swept joint (`swept[0]`; a single image for a
    /// two-joint grid) over the last two swept joints, named `section-qJ-VALUE.svg`.
    fn write(&self, robot: &reach::Robot, grid: &CspaceGrid, swept: &[usize]) -> Result<(), CliError> {
        if !self.any() {
            return Ok(());
        }
        let shown =
            |j: usize, v: f64| crate::numbers::from_si(robot.joints()[j].kind, v, crate::numbers::AngleUnit::Deg);
        let name = |j: usize| format!("q{} [{}]", j + 1, crate::numbers::display_unit(robot.joints()[j].kind));
        let (section, jx, jy) = match swept {
            [a, b, c] => (Some(*a), *b, *c),
            [b, c] => (None, *b, *c),
            _ => return Ok(()),
        };
        let xs: Vec<f64> = grid.axes[jx].iter().map(|v| shown(jx, *v)).collect();
        let ys: Vec<f64> = grid.axes[jy].iter().map(|v| shown(jy, *v)).collect();
        let sections: Vec<Option<usize>> = match section {
            Some(j) => (0..grid.axes[j].len()).map(Some).collect(),
            None => vec![None],
        };
        // Row-major strides: node index = Σ index_j · stride_j.
        let mut stride = vec![1usize; grid.axes.len()];
        for j in (0..grid.axes.len().saturating_sub(1)).rev() {
            stride[j] = stride[j + 1] * grid.axes[j + 1].len();
        }
        let fixed: Vec<String> = (0..grid.axes.len())
            .filter(|j| grid.axes[*j].len() == 1)
            .map(|j| format!("q{} = {}", j + 1, crate::output::num(shown(j, grid.axes[j][0]))))
            .collect();
        for s in sections {
            let (base, what, file) = match (section, s) {
                (Some(j), Some(k)) => {
                    let v = shown(j, grid.axes[j][k]);
                    (
                        k * stride[j],
                        format!(
                            "section q{} = {} {}",
                            j + 1,
                            crate::output::num(v),
                            crate::numbers::display_unit(robot.joints()[j].kind)
                        ),
                        format!("section-q{}-{}", j + 1, crate::plot::file_number(v)),
                    )
                }
                _ => (0, "C-space".to_string(), "section".to_string()),
            };
            let title = if fixed.is_empty() {
                format!("{} — {what}", robot.name())
            } else {
                format!("{} — {what} ({})", robot.name(), fixed.join(", "))
            };
            let class_at = |ix: usize, iy: usize| grid.classes[base + ix * stride[jx] + iy * stride[jy]];
            let drawing = crate::plot::drawings::cspace_section(&title, (&name(jx), &xs), (&name(jy), &ys), &class_at);
            if let Some(d) = &self.svg_dir {
                crate::plot::write_svg("--svg", &d.join(format!("{file}.svg")), &drawing)?;
            }
            if let Some(d) = &self.png_dir {
                crate::plot::write_png("--png", &d.join(format!("{file}.png")), &drawing, self.png_width)?;
            }
        }
        Ok(())
    }
}
