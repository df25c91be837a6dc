//! The `cspace` workflow: seed 004's configuration-space grid — every node classified,
//! counts per class and per value of the first swept joint — and, on request, the
//! R-function region fitted to it with its confusion counts.

use std::collections::BTreeMap;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::parse_scene;
use crate::error::{Error, Result};
use crate::jobs::input::{AngleUnit, to_si};
use crate::world::WorldError;
use crate::world::cspace::{
    CspaceGrid, DEFAULT_MAX_NODES, GridCounts, GridSpec, MAX_NODES, classify_grid_with_cancel, count_text, grid_axes,
    grid_node_count,
};
use crate::world::fit::{Confusion, FitOptions, fit_region};
use crate::world::rfunction::{Parabola, Primitive};
use crate::{Cancel, Robot};

fn default_step_deg() -> f64 {
    15.0
}

/// A configuration-space grid over a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CspaceRequest {
    /// The text of the scene file (TOML: obstacles, tool zone, touching policy).
    pub scene: String,
    /// Grid step in degrees (default 15), > 0; the same number is the step of prismatic
    /// joints once converted like an angle.
    #[serde(default = "default_step_deg")]
    pub step_deg: f64,
    /// Fixed joints: `{"q1": 0}` (revolute degrees, prismatic metres). Other joints sweep
    /// their limits.
    #[serde(default)]
    pub fix: BTreeMap<String, f64>,
    /// Fit seed 004's R-function region to the grid (exactly three swept joints).
    #[serde(default)]
    pub fit: bool,
    /// Largest number of grid nodes to classify (default [`DEFAULT_MAX_NODES`], at most
    /// [`MAX_NODES`]); a finer grid is refused before anything is allocated.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_nodes: Option<usize>,
}

/// Counts of the nodes at one value of the first swept joint.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CspaceSection {
    /// 1-based joint.
    pub joint: usize,
    /// Its value, degrees.
    pub value_deg: f64,
    /// Counts per class.
    #[serde(flatten)]
    pub counts: GridCounts,
}

/// The classified grid (`reach cspace --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CspaceReport {
    /// Robot name.
    pub robot: String,
    /// Grid step, degrees.
    pub step_deg: f64,
    /// Counts per class over the whole grid (`nodes`, `allowed` — N in the paper — and the
    /// four reasons a node is forbidden).
    #[serde(flatten)]
    pub counts: GridCounts,
    /// Counts per value of the first swept joint.
    pub sections: Vec<CspaceSection>,
    /// With `fit`: the fitted region's primitives and confusion counts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fit: Option<FitReport>,
}

/// The fitted R-function region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FitReport {
    /// 1-based joints that are the region's coordinates `(q2, q3, q4)` in the paper.
    pub joints: [usize; 3],
    /// The joint-limit box, degrees, per coordinate `[lower, upper]`.
    pub limits_deg: [[f64; 2]; 3],
    /// The primitives in composition order (coefficients in degrees).
    pub primitives: Vec<FitPrimitive>,
    /// The fitted region against the grid.
    pub confusion: Confusion,
}

/// One primitive of the fitted region.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct FitPrimitive {
    /// The paper's name (`Ω1` …).
    pub name: String,
    /// `half-space`, `elliptic cylinder (outside)`, …
    pub kind: String,
    /// The inequality `X ≥ 0` (allowed side), degrees.
    pub equation: String,
    /// The primitive's coefficients, degrees.
    pub coefficients: Primitive,
    /// For a half-space: the allowed grid nodes on the plane, degrees.
    pub support_points_deg: Vec<[f64; 3]>,
    /// Truly forbidden nodes this primitive cuts.
    pub cut_forbidden: usize,
    /// Truly allowed nodes this primitive cuts.
    pub cut_allowed: usize,
}

/// The grid specification of a request.
fn spec(robot: &Robot, request: &CspaceRequest) -> Result<GridSpec> {
    if !(request.step_deg.is_finite() && request.step_deg > 0.0) {
        return Err(Error::request("step_deg", format!("must be positive, got {}", request.step_deg)));
    }
    let mut spec = GridSpec::new(robot.dof(), request.step_deg.to_radians());
    for (name, &value) in &request.fix {
        let field = format!("fix.{name}");
        let index = name
            .trim()
            .strip_prefix('q')
            .and_then(|i| i.parse::<usize>().ok())
            .filter(|i| (1..=robot.dof()).contains(i))
            .ok_or_else(|| Error::request(&field, format!("`{name}` is not a joint q1..q{}", robot.dof())))?;
        if !value.is_finite() {
            return Err(Error::request(field, format!("expected a finite number, got {value}")));
        }
        spec = spec.fix(index - 1, to_si(robot.joints()[index - 1].kind, value, AngleUnit::Deg));
    }
    let cap = match request.max_nodes {
        None => DEFAULT_MAX_NODES,
        Some(m) if (1..=MAX_NODES).contains(&m) => m,
        Some(m) => return Err(Error::request("max_nodes", format!("must be between 1 and {MAX_NODES}, got {m}"))),
    };
    // Counted from the axis lengths, before any axis or class is allocated.
    let nodes = grid_node_count(robot, &spec)?;
    if nodes > cap {
        let raise = if cap < MAX_NODES { format!(", or raise the node cap up to {MAX_NODES}") } else { String::new() };
        return Err(Error::request(
            "step_deg",
            format!(
                "a step of {}° gives a grid of {} nodes, more than the cap of {cap} (use a coarser step, fix joints{raise})",
                request.step_deg,
                count_text(nodes)
            ),
        ));
    }
    Ok(spec)
}

/// The grid's axes (one value for a fixed joint), radians / metres: what a front end needs
/// before the classification (node count, swept joints).
///
/// # Errors
/// [`Error::Request`] for a bad step or `fix`, or a grid of more nodes than the cap
/// (`max_nodes`); [`Error::World`] for infinite limits of a swept joint.
pub fn cspace_axes(robot: &Robot, request: &CspaceRequest) -> Result<Vec<Vec<f64>>> {
    Ok(grid_axes(robot, &spec(robot, request)?)?)
}

/// Classifies the grid (see [`cspace_with_grid`]).
///
/// # Errors
/// As [`cspace_with_grid`].
pub fn cspace(robot: &Robot, request: &CspaceRequest) -> Result<CspaceReport> {
    Ok(cspace_with_grid(robot, request, &|_, _| {})?.0)
}

/// Classifies the grid, reporting progress (`progress(done, total)` nodes), and returns the
/// report with the grid itself (for section images).
///
/// # Errors
/// [`Error::World`] for a malformed scene, a bad grid, and
/// [`WorldError::NoAllowedNode`] for `fit` on a grid without an allowed node (valid input,
/// nothing to fit); [`Error::Request`] for a bad step or `fix`, and for `fit` on a grid that
/// does not sweep exactly three joints.
pub fn cspace_with_grid(
    robot: &Robot,
    request: &CspaceRequest,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<(CspaceReport, CspaceGrid)> {
    cspace_with_cancel(robot, request, progress, &Cancel::default())
}

/// [`cspace_with_grid`] that stops when `cancel` is set.
///
/// # Errors
/// As [`cspace_with_grid`]; [`Error::World`] with [`WorldError::Cancelled`] once `cancel`
/// is set.
pub fn cspace_with_cancel(
    robot: &Robot,
    request: &CspaceRequest,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &Cancel,
) -> Result<(CspaceReport, CspaceGrid)> {
    let scene = parse_scene(&request.scene)?;
    let spec = spec(robot, request)?;
    let grid = classify_grid_with_cancel(robot, &scene, &spec, progress, cancel)?;
    let first = grid.axes.iter().position(|a| a.len() > 1);
    let sections: Vec<CspaceSection> = first.map_or_else(Vec::new, |j| {
        grid.counts_by(j)
            .into_iter()
            .zip(&grid.axes[j])
            .map(|(counts, v)| CspaceSection { joint: j + 1, value_deg: v.to_degrees(), counts })
            .collect()
    });
    let fit = if request.fit { Some(fit(&grid)?) } else { None };
    let report = CspaceReport {
        robot: robot.name().to_string(),
        step_deg: request.step_deg,
        counts: grid.counts,
        sections,
        fit,
    };
    Ok((report, grid))
}

fn fit(grid: &CspaceGrid) -> Result<FitReport> {
    let fit = fit_region(grid, &FitOptions::default()).map_err(|e| match e {
        WorldError::NoAllowedNode => Error::World(e),
        e => Error::request("fit", e.to_string()),
    })?;
    let labels = fit.joints.map(|j| format!("q{}", j + 1));
    let primitives = fit
        .parts
        .iter()
        .map(|p| {
            let (kind, equation) = describe(&p.primitive, &labels);
            FitPrimitive {
                name: p.name.clone(),
                kind: kind.to_string(),
                equation,
                coefficients: p.primitive.clone(),
                support_points_deg: p.support_points_deg.clone(),
                cut_forbidden: p.cut_forbidden,
                cut_allowed: p.cut_allowed,
            }
        })
        .collect();
    Ok(FitReport {
        joints: fit.joints.map(|j| j + 1),
        limits_deg: fit.region.limits,
        primitives,
        confusion: fit.confusion,
    })
}

fn fixed(v: f64, digits: usize) -> String {
    let s = format!("{v:.digits$}");
    // No "-0.000": a value that rounds to zero prints as zero.
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') { s[1..].to_string() } else { s }
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
    }
}
