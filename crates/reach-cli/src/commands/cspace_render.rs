//! `reach cspace` rendering: the fitted region's primitives and confusion counts as text, and
//! the section images of the grid (`--svg DIR`, `--png DIR`).

use std::io::Write;

use clap::Args;
use reach::jobs::world::FitReport;
use reach::world::cspace::CspaceGrid;

use crate::error::CliError;
use crate::output::{Align, Table, fixed};

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

/// Writes the primitives and the confusion counts.
///
/// # Errors
/// [`CliError::Output`].
pub fn write_text(out: &mut dyn Write, json: &FitReport) -> Result<(), CliError> {
    let [a, b, c] = json.joints;
    writeln!(
        out,
        "fitted R-function region in (q{a}, q{b}, q{c}), degrees: F = box ∧ primitives (left-nested, in order) ≥ 0"
    )?;
    let mut t =
        Table::new(&[("name", Align::Left), ("kind", Align::Left), ("cuts F/A", Align::Right), ("X ≥ 0", Align::Left)]);
    for p in &json.primitives {
        t.row(vec![
            p.name.clone(),
            p.kind.to_string(),
            format!("{}/{}", p.cut_forbidden, p.cut_allowed),
            p.equation.clone(),
        ]);
    }
    t.write(out, "  ")?;
    let c = &json.confusion;
    writeln!(out, "confusion against the grid (allowed = positive):")?;
    let mut k = Table::key_value();
    k.pair("true allowed", c.true_allowed.to_string());
    k.pair("false allowed", format!("{} ({} hit an obstacle)", c.false_allowed, c.false_allowed_obstacle));
    k.pair("false forbidden", c.false_forbidden.to_string());
    k.pair("true forbidden", c.true_forbidden.to_string());
    k.pair(
        "misclassified",
        format!("{} of {} ({} %)", c.false_allowed + c.false_forbidden, c.nodes, fixed(100.0 * c.rate, 2)),
    );
    k.write(out, "  ")?;
    Ok(())
}

impl SectionArgs {
    /// Whether any image is asked for.
    #[must_use]
    pub fn any(&self) -> bool {
        self.svg_dir.is_some() || self.png_dir.is_some()
    }

    /// Creates the output directories (before the grid is computed).
    ///
    /// # Errors
    /// [`CliError::BadInput`] when a directory cannot be created.
    pub fn prepare(&self) -> Result<(), CliError> {
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
    ///
    /// # Errors
    /// [`CliError::BadInput`] / [`CliError::Output`] when an image cannot be written.
    pub fn write(&self, robot: &reach::Robot, grid: &CspaceGrid, swept: &[usize]) -> Result<(), CliError> {
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
