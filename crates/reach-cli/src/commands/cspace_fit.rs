//! `reach cspace --fit`: seed 004's R-function region fitted to the grid, its primitives and
//! its confusion counts against the grid (library: `reach::world::fit`).

use std::io::Write;

use reach::world::WorldError;
use reach::world::cspace::CspaceGrid;
use reach::world::fit::{Confusion, Fit, FitOptions, fit_region};
use reach::world::rfunction::{Parabola, Primitive};
use serde::Serialize;

use crate::error::CliError;
use crate::output::{Align, Table, fixed};

/// The `"fit"` object of `reach cspace --fit --json`.
#[derive(Debug, Serialize)]
pub struct FitJson {
    /// 1-based joints that are the region's coordinates `(q2, q3, q4)` in the paper.
    joints: [usize; 3],
    /// The joint-limit box, degrees, per coordinate `[lower, upper]`.
    limits_deg: [[f64; 2]; 3],
    /// The primitives in composition order (coefficients in degrees).
    primitives: Vec<PrimitiveJson>,
    /// The fitted region against the grid.
    confusion: Confusion,
}

#[derive(Debug, Serialize)]
struct PrimitiveJson {
    name: String,
    kind: &'static str,
    /// The inequality `X ≥ 0` (allowed side), degrees.
    equation: String,
    coefficients: Primitive,
    support_points_deg: Vec<[f64; 3]>,
    cut_forbidden: usize,
    cut_allowed: usize,
}

/// Fits the region to `grid`.
///
/// # Errors
/// [`CliError::NoSolution`] when the grid has no allowed node; [`CliError::BadInput`] when it
/// does not sweep exactly three joints.
pub fn fit(grid: &CspaceGrid) -> Result<(Fit, FitJson), CliError> {
    let fit = fit_region(grid, &FitOptions::default()).map_err(|e| match e {
        WorldError::NoAllowedNode => CliError::NoSolution(format!("--fit: {e}")),
        e => CliError::bad_input(format!("--fit: {e}")),
    })?;
    let labels = fit.joints.map(|j| format!("q{}", j + 1));
    let primitives = fit
        .parts
        .iter()
        .map(|p| {
            let (kind, equation) = describe(&p.primitive, &labels);
            PrimitiveJson {
                name: p.name.clone(),
                kind,
                equation,
                coefficients: p.primitive.clone(),
                support_points_deg: p.support_points_deg.clone(),
                cut_forbidden: p.cut_forbidden,
                cut_allowed: p.cut_allowed,
            }
        })
        .collect();
    let json = FitJson {
        joints: fit.joints.map(|j| j + 1),
        limits_deg: fit.region.limits,
        primitives,
        confusion: fit.confusion.clone(),
    };
    Ok((fit, json))
}

fn poly(c: &[f64; 4], x: &str) -> String {
    format!("{} {:+.4e}·{x} {:+.4e}·{x}² {:+.4e}·{x}³", fixed(c[0], 3), c[1], c[2], c[3])
}

/// Kind and equation (degrees) of a primitive over the coordinates `l = [q2, q3, q4]`.
fn describe(p: &Primitive, l: &[String; 3]) -> (&'static str, String) {
    let f = |x: f64| fixed(x, 4);
    match p {
        Primitive::HalfSpace { d, b } => {
            ("half-space", format!("{}·{} {:+.4}·{} {:+.4}·{} {:+.4} ≥ 0", f(d[0]), l[0], d[1], l[1], d[2], l[2], -b))
        }
        Primitive::EllipticCylinder { phi_deg, a, b, centre } => (
            "elliptic cylinder (outside)",
            format!(
                "u²/a² + v²/b² − 1 ≥ 0, φ = {}°, a = {}°, b = {}°, centre {} = {}·{} {:+.2}°, {} = {}·{} {:+.2}°",
                fixed(*phi_deg, 2),
                fixed(*a, 2),
                fixed(*b, 2),
                l[1],
                f(centre[0]),
                l[0],
                centre[1],
                l[2],
                f(centre[2]),
                l[0],
                centre[3]
            ),
        ),
        Primitive::ParabolicCylinder { phi_deg, vertex, p, variant } => (
            "parabolic cylinder (outside)",
            format!(
                "{} ≥ 0 in ({}, {}), φ = {}°, vertex = ({}, {})°, p = {}°",
                if *variant == Parabola::SquareFirst { "s² − 2p·t" } else { "t² − 2p·s" },
                l[0],
                l[1],
                fixed(*phi_deg, 2),
                fixed(vertex[0], 2),
                fixed(vertex[1], 2),
                f(*p)
            ),
        ),
        Primitive::KinematicEllipse { phi_deg, m3, m4, a, b } => (
            "kinematic ellipse (outside)",
            format!(
                "φ = {}°; centre {} = {}, {} = {}; a = {}; b = {} (degrees)",
                fixed(*phi_deg, 2),
                l[1],
                poly(m3, &l[0]),
                l[2],
                poly(m4, &l[0]),
                poly(a, &l[0]),
                poly(b, &l[0])
            ),
        ),
        _ => ("primitive", format!("{p:?}")),
    }
}

/// Writes the primitives and the confusion counts.
///
/// # Errors
/// [`CliError::Output`].
pub fn write_text(out: &mut dyn Write, json: &FitJson) -> Result<(), CliError> {
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
