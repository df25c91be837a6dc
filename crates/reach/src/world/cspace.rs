//! Seed 004: configuration-space grids — enumerate joint values on a grid and classify
//! every node (notes 004 §4 A).

use std::sync::atomic::{AtomicUsize, Ordering};

use serde::Serialize;

use super::{CollisionChecker, Scene, Verdict, WorldError};
use crate::Cancel;
use crate::model::Robot;
use crate::tolerance::{LIMIT_SLACK, SCAN_GRID};

/// Largest number of grid nodes accepted at all, whatever a request asks (one byte of class
/// per node: 200 MB; more would not fit beside the rest in memory). Checked before anything
/// is allocated, from the axis lengths alone.
pub const MAX_NODES: usize = 200_000_000;

/// Default cap on the grid nodes of one request (`cspace`'s `max_nodes`, CLI
/// `--max-nodes`): a grid this size is classified in about a minute; a request may raise it
/// up to [`MAX_NODES`].
pub const DEFAULT_MAX_NODES: usize = 20_000_000;

/// What a grid node is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum NodeClass {
    /// Within limits, tool in its zone, no collision.
    Allowed = 0,
    /// A joint value outside the robot's limits.
    OutsideLimits = 1,
    /// The tool point not strictly inside the scene's tool zone.
    OutsideZone = 2,
    /// Two non-adjacent links collide.
    SelfCollision = 3,
    /// A link collides with an obstacle.
    ObstacleCollision = 4,
}

/// Which joint values the grid visits.
#[derive(Debug, Clone, PartialEq)]
pub struct GridSpec {
    /// Grid step, radians (metres for prismatic joints), > 0.
    pub step: f64,
    /// Per joint: `Some(value)` fixes it, `None` sweeps it.
    pub fixed: Vec<Option<f64>>,
    /// Per joint: the swept range `[lo, hi]`; `None` takes the joint's limits (which must
    /// then be finite). Both ends are nodes; when `step` does not divide the range, `hi` is
    /// added as a last, shorter step.
    pub ranges: Vec<Option<(f64, f64)>>,
}

impl GridSpec {
    /// Sweep every joint over its limits at `step`, except the listed fixed joints.
    #[must_use]
    pub fn new(dof: usize, step: f64) -> Self {
        GridSpec { step, fixed: vec![None; dof], ranges: vec![None; dof] }
    }

    /// Fixes joint `index` (0-based) at `value` (builder style).
    #[must_use]
    pub fn fix(mut self, index: usize, value: f64) -> Self {
        if let Some(f) = self.fixed.get_mut(index) {
            *f = Some(value);
        }
        self
    }
}

/// Counts per class.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct GridCounts {
    /// Number of nodes.
    pub nodes: usize,
    /// Allowed nodes (N in the paper).
    pub allowed: usize,
    /// Nodes outside the joint limits.
    pub outside_limits: usize,
    /// Nodes whose tool point is outside the zone.
    pub outside_zone: usize,
    /// Self-colliding nodes.
    pub self_collision: usize,
    /// Nodes colliding with an obstacle.
    pub obstacle_collision: usize,
}

impl GridCounts {
    fn add(&mut self, c: NodeClass) {
        self.nodes += 1;
        match c {
            NodeClass::Allowed => self.allowed += 1,
            NodeClass::OutsideLimits => self.outside_limits += 1,
            NodeClass::OutsideZone => self.outside_zone += 1,
            NodeClass::SelfCollision => self.self_collision += 1,
            NodeClass::ObstacleCollision => self.obstacle_collision += 1,
        }
    }
}

/// A classified grid.
#[derive(Debug, Clone, PartialEq)]
pub struct CspaceGrid {
    /// Per joint, its values on the grid (one value for a fixed joint).
    pub axes: Vec<Vec<f64>>,
    /// Class of every node, row-major (the first joint varies slowest).
    pub classes: Vec<NodeClass>,
    /// Totals.
    pub counts: GridCounts,
}

impl CspaceGrid {
    /// Counts per value of joint `joint` (0-based): one [`GridCounts`] per value on that axis
    /// (seed 004's sections `q2 = const`).
    #[must_use]
    pub fn counts_by(&self, joint: usize) -> Vec<GridCounts> {
        let Some(axis) = self.axes.get(joint) else { return Vec::new() };
        let mut out = vec![GridCounts::default(); axis.len()];
        for (i, c) in self.classes.iter().enumerate() {
            if let Some(k) = self.axis_index(i, joint) {
                out[k].add(*c);
            }
        }
        out
    }

    /// The position of node `index` on the axis of joint `joint` (0-based both; nodes are
    /// row-major, the first joint varying slowest): `axes[joint][axis_index(index, joint)]`
    /// is the node's value of that joint. `None` for a joint without an axis or with no
    /// values on it (a grid without nodes).
    #[must_use]
    pub fn axis_index(&self, index: usize, joint: usize) -> Option<usize> {
        let axis = self.axes.get(joint).filter(|a| !a.is_empty())?;
        let inner: usize = self.axes[joint + 1..].iter().map(Vec::len).product();
        Some((index / inner.max(1)) % axis.len())
    }

    /// Joint values of node `index`.
    #[must_use]
    pub fn node(&self, index: usize) -> Vec<f64> {
        (0..self.axes.len()).map(|j| self.axis_index(index, j).map_or(f64::NAN, |k| self.axes[j][k])).collect()
    }
}

/// Whole steps of `step` in `[lo, hi]` plus one, as a float (no overflow: a tiny step gives a
/// huge number, compared with the caps before anything is allocated).
fn axis_steps(lo: f64, hi: f64, step: f64) -> f64 {
    ((hi - lo) / step + SCAN_GRID).floor() + 1.0
}

/// The number of values [`axis_values`] gives, computed without building them; saturates
/// at `usize::MAX`.
fn axis_len(lo: f64, hi: f64, step: f64) -> usize {
    let n = axis_steps(lo, hi, step);
    if n >= usize::MAX as f64 {
        return usize::MAX;
    }
    let n = n as usize;
    let last = lo + (n - 1) as f64 * step;
    if hi - last > SCAN_GRID * step { n + 1 } else { n }
}

fn axis_values(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    let n = axis_steps(lo, hi, step) as usize;
    let mut v: Vec<f64> = (0..n).map(|i| lo + i as f64 * step).collect();
    if let Some(&last) = v.last()
        && hi - last > SCAN_GRID * step
    {
        v.push(hi);
    }
    v
}

/// The number of nodes of the grid of `spec` for `robot`, computed from the axis lengths
/// without allocating them (saturating at `usize::MAX`): what a caller compares with its cap
/// before [`grid_axes`] or [`classify_grid`].
///
/// # Errors
/// [`WorldError::Input`] for a step that is not positive and finite, a spec of the wrong
/// length, a NaN value, or a swept joint without finite limits or range.
///
/// # Example
/// ```
/// use reach::world::cspace::{GridSpec, grid_node_count};
/// let varan = reach::model::presets::get("varan4").unwrap();
/// let spec = GridSpec::new(4, 15f64.to_radians()).fix(0, 0.0);
/// assert_eq!(grid_node_count(&varan, &spec).unwrap(), 9 * 17 * 17);
/// // A step of 1e-9° is counted, not built.
/// let tiny = GridSpec::new(4, 1e-9f64.to_radians()).fix(0, 0.0);
/// assert!(grid_node_count(&varan, &tiny).unwrap() > 1_000_000_000_000);
/// ```
pub fn grid_node_count(robot: &Robot, spec: &GridSpec) -> Result<usize, WorldError> {
    let mut total: usize = 1;
    for range in swept_ranges(robot, spec)? {
        total = total.saturating_mul(range.map_or(1, |(lo, hi)| axis_len(lo, hi, spec.step)));
    }
    Ok(total)
}

/// Per joint: `None` for a fixed joint, else its finite swept range (validated).
fn swept_ranges(robot: &Robot, spec: &GridSpec) -> Result<Vec<Option<(f64, f64)>>, WorldError> {
    let n = robot.dof();
    if !(spec.step.is_finite() && spec.step > 0.0) {
        return Err(WorldError::Input(format!("grid step must be positive and finite, got {}", spec.step)));
    }
    if spec.fixed.len() != n || spec.ranges.len() != n {
        return Err(WorldError::Input(format!("grid spec needs one entry per joint ({n})")));
    }
    let mut out = Vec::with_capacity(n);
    for (j, joint) in robot.joints().iter().enumerate() {
        if let Some(v) = spec.fixed[j] {
            if !v.is_finite() {
                return Err(WorldError::Input(format!("joint {} ({}): fixed value must be finite", j + 1, joint.name)));
            }
            out.push(None);
        } else {
            let (lo, hi) = spec.ranges[j].unwrap_or((joint.limits.lower, joint.limits.upper));
            if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                return Err(WorldError::Input(format!(
                    "joint {} ({}): swept range must be finite with lower ≤ upper, got [{lo}, {hi}] (fix the joint or give a range)",
                    j + 1,
                    joint.name
                )));
            }
            out.push(Some((lo, hi)));
        }
    }
    Ok(out)
}

/// The grid axes of `spec` for `robot`.
///
/// The node count is checked against [`MAX_NODES`] from the axis lengths
/// ([`grid_node_count`]) before any axis is built.
///
/// # Errors
/// [`WorldError::Input`] for a step that is not positive and finite, a spec of the wrong
/// length, a NaN value, a swept joint without finite limits or range, or more than
/// [`MAX_NODES`] nodes.
pub fn grid_axes(robot: &Robot, spec: &GridSpec) -> Result<Vec<Vec<f64>>, WorldError> {
    let total = grid_node_count(robot, spec)?;
    if total > MAX_NODES {
        return Err(WorldError::Input(format!("the grid has {} nodes, more than {MAX_NODES}", count_text(total))));
    }
    let ranges = swept_ranges(robot, spec)?;
    Ok(ranges
        .into_iter()
        .zip(&spec.fixed)
        .map(|(range, fixed)| match (range, fixed) {
            (Some((lo, hi)), _) => axis_values(lo, hi, spec.step),
            (None, v) => vec![v.unwrap_or(0.0)],
        })
        .collect())
}

/// A node count for a message (`usize::MAX` is "more than 1.8e19").
#[must_use]
pub fn count_text(n: usize) -> String {
    if n == usize::MAX { format!("more than {:.1e}", usize::MAX as f64) } else { n.to_string() }
}

/// Classifies one configuration (the classification order of notes 004 §4 A: limits, tool
/// zone, self-collision, obstacles). [`classify_grid`] gives every node this class (it
/// tests each axis value against the limits once and reuses the link frames of the outer
/// joints between nodes).
///
/// # Errors
/// As [`CollisionChecker::check`].
///
/// # Example
/// ```
/// use reach::world::{CollisionChecker, Scene, cspace::{NodeClass, classify_node}};
/// let varan = reach::model::presets::get("varan4").unwrap();
/// let scene = Scene::new();
/// let mut checker = CollisionChecker::new(&varan, &scene);
/// assert_eq!(classify_node(&mut checker, &[0.0, 0.5, 0.3, -0.2]).unwrap(), NodeClass::Allowed);
/// assert_eq!(classify_node(&mut checker, &[0.0, 9.0, 0.0, 0.0]).unwrap(), NodeClass::OutsideLimits);
/// ```
pub fn classify_node(checker: &mut CollisionChecker<'_>, q: &[f64]) -> Result<NodeClass, WorldError> {
    if checker.robot().first_joint_outside_limits(q, LIMIT_SLACK).is_some() {
        return Ok(NodeClass::OutsideLimits);
    }
    Ok(class_of(checker.check(q)?))
}

/// The class of a configuration within the limits with this verdict.
fn class_of(verdict: Verdict) -> NodeClass {
    match verdict {
        Verdict::Free => NodeClass::Allowed,
        Verdict::OutsideZone { .. } => NodeClass::OutsideZone,
        Verdict::SelfCollision { .. } => NodeClass::SelfCollision,
        Verdict::Obstacle { .. } => NodeClass::ObstacleCollision,
    }
}

fn classify_range(
    robot: &Robot,
    scene: &Scene,
    axes: &[Vec<f64>],
    start: usize,
    out: &mut [NodeClass],
    cancel: &Cancel,
) -> Result<(), WorldError> {
    if cancel.is_cancelled() {
        return Err(WorldError::Cancelled);
    }
    let mut checker = CollisionChecker::new(robot, scene);
    // Per axis value: within the joint's limits (the limit test of `classify_node`, once per
    // value instead of once per node).
    let joints = robot.joints();
    let within: Vec<Vec<bool>> = axes
        .iter()
        .zip(joints)
        .map(|(axis, joint)| axis.iter().map(|&v| joint.limits.contains(v, LIMIT_SLACK)).collect())
        .collect();
    let mut q = vec![0.0; axes.len()];
    let mut index = vec![0; axes.len()];
    // The axis positions of the node whose frames the checker holds (none yet).
    let mut checked: Vec<usize> = vec![usize::MAX; axes.len()];
    for (offset, slot) in out.iter_mut().enumerate() {
        let mut rest = start + offset;
        for (j, axis) in axes.iter().enumerate().rev() {
            index[j] = rest % axis.len();
            q[j] = axis[index[j]];
            rest /= axis.len();
        }
        if index.iter().zip(&within).any(|(&k, w)| !w[k]) {
            *slot = NodeClass::OutsideLimits;
            continue;
        }
        // Row-major order: mostly only the last joints changed since the last checked node.
        let changed = index.iter().zip(&checked).position(|(a, b)| a != b).unwrap_or(index.len());
        checked.clone_from(&index);
        *slot = class_of(checker.check_changed(&q, changed)?);
    }
    Ok(())
}

/// Enumerates the grid of `spec` and classifies every node.
///
/// With the default cargo feature `parallel` the nodes are split over the threads of the
/// rayon pool; without it the sweep runs on the calling thread. The result is the same.
///
/// # Errors
/// See [`grid_axes`].
///
/// # Example
/// ```
/// use reach::world::{Scene, cspace::{GridSpec, classify_grid}};
/// let varan = reach::model::presets::get("varan4").unwrap();
/// let spec = GridSpec::new(4, 15f64.to_radians()).fix(0, 0.0);
/// let grid = classify_grid(&varan, &Scene::new(), &spec).unwrap();
/// assert_eq!(grid.counts.nodes, 9 * 17 * 17);
/// ```
pub fn classify_grid(robot: &Robot, scene: &Scene, spec: &GridSpec) -> Result<CspaceGrid, WorldError> {
    classify_grid_with_progress(robot, scene, spec, &|_, _| {})
}

/// Nodes classified between two calls of the progress hook of
/// [`classify_grid_with_progress`] (one chunk).
pub const PROGRESS_CHUNK: usize = 4096;

/// [`classify_grid`] that reports its progress: `progress(done, total)` is called after every
/// chunk of [`PROGRESS_CHUNK`] nodes (from the worker threads, in no particular order;
/// `done` counts the nodes classified so far and reaches `total` on the last call).
///
/// # Errors
/// See [`grid_axes`].
///
/// # Example
/// ```
/// use std::sync::atomic::{AtomicUsize, Ordering};
/// use reach::world::{Scene, cspace::{GridSpec, classify_grid_with_progress}};
/// let varan = reach::model::presets::get("varan4").unwrap();
/// let spec = GridSpec::new(4, 5f64.to_radians()).fix(0, 0.0);
/// let most = AtomicUsize::new(0);
/// let grid = classify_grid_with_progress(&varan, &Scene::new(), &spec, &|done, _total| {
///     most.fetch_max(done, Ordering::Relaxed);
/// })
/// .unwrap();
/// assert_eq!(most.into_inner(), grid.counts.nodes);
/// ```
pub fn classify_grid_with_progress(
    robot: &Robot,
    scene: &Scene,
    spec: &GridSpec,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<CspaceGrid, WorldError> {
    classify_grid_with_cancel(robot, scene, spec, progress, &Cancel::default())
}

/// [`classify_grid_with_progress`] that stops when `cancel` is set (looked at before every
/// chunk of [`PROGRESS_CHUNK`] nodes).
///
/// # Errors
/// See [`grid_axes`]; [`WorldError::Cancelled`] once `cancel` is set; [`WorldError::Input`]
/// for a scene with a moving obstacle ([`Scene::require_fixed`]).
///
/// # Example
/// ```
/// use reach::world::{Scene, WorldError, cspace::{GridSpec, classify_grid_with_cancel}};
/// let varan = reach::model::presets::get("varan4").unwrap();
/// let spec = GridSpec::new(4, 15f64.to_radians()).fix(0, 0.0);
/// let cancel = reach::Cancel::new();
/// cancel.cancel();
/// let e = classify_grid_with_cancel(&varan, &Scene::new(), &spec, &|_, _| {}, &cancel);
/// assert_eq!(e.unwrap_err(), WorldError::Cancelled);
/// ```
pub fn classify_grid_with_cancel(
    robot: &Robot,
    scene: &Scene,
    spec: &GridSpec,
    progress: &(dyn Fn(usize, usize) + Sync),
    cancel: &Cancel,
) -> Result<CspaceGrid, WorldError> {
    scene.require_fixed("the configuration-space grid (a map of fixed obstacles)")?;
    let axes = grid_axes(robot, spec)?;
    let total: usize = axes.iter().map(Vec::len).product();
    let mut classes = vec![NodeClass::Allowed; total];
    let done = AtomicUsize::new(0);
    let chunk_done = |n: usize| progress(done.fetch_add(n, Ordering::Relaxed) + n, total);
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        classes.par_chunks_mut(PROGRESS_CHUNK).enumerate().try_for_each(|(c, chunk)| {
            classify_range(robot, scene, &axes, c * PROGRESS_CHUNK, chunk, cancel)?;
            chunk_done(chunk.len());
            Ok::<(), WorldError>(())
        })?;
    }
    #[cfg(not(feature = "parallel"))]
    for (c, chunk) in classes.chunks_mut(PROGRESS_CHUNK).enumerate() {
        classify_range(robot, scene, &axes, c * PROGRESS_CHUNK, chunk, cancel)?;
        chunk_done(chunk.len());
    }
    let mut counts = GridCounts::default();
    for c in &classes {
        counts.add(*c);
    }
    Ok(CspaceGrid { axes, classes, counts })
}
