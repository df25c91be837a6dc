//! Seed 004: fitting the paper's R-function region to a classified configuration-space grid,
//! and the confusion counts of a region against a grid (notes 004 §4 B, §8 "Fitting").
//!
//! The paper fits its primitives "experimentally" and prints no coefficient; everything here
//! is computed from the grid. Coordinates are the grid's three swept joints in **degrees**
//! (`(q2, q3, q4)` for the Varan arm with `q1` fixed), as in the paper.
//!
//! # Method
//! The grid classes split the work the way the paper's cases do. Nodes that are allowed or
//! hit only an obstacle form the allowed set *without* the obstacle (the task zone θ and the
//! limits); the obstacle's own nodes are fitted afterwards.
//!
//! 1. **Planes Ω2–Ω4** (eq. 6): support planes of the obstacle-free allowed set. Over 4000
//!    unit normals (a Fibonacci sphere) the plane `d·q = b` with `b = min d·q` over that set
//!    touches it at its support point; the greedy pass keeps, up to three times, the plane
//!    that cuts off the most forbidden nodes not yet cut off. No allowed node is lost.
//! 2. **Elliptic cylinder Ω1** (eq. 4, corrected): fitted to the forbidden nodes (outside θ)
//!    left inside the box and the planes. Start: per section `q2 = const` the centroid of
//!    those nodes, a weighted least-squares line `c(q2)` through the centroids (the paper's
//!    line `l`) and the tilt φ of the principal axis of the pooled, centred nodes; also that
//!    line moved 60°, 120° and 200° away from the allowed nodes with the major axis across
//!    (the ellipse's centre lies on the forbidden side of the contour it bounds). From each
//!    start a pattern search over the centre line `(k3, m3, k4, m4)` and φ, with the semi-axes
//!    optimal for every candidate: `a` on a grid 8 % apart (then 0.5° steps around the best),
//!    `b` by an exact sweep over the node thresholds. The cost is the number of misclassified
//!    nodes among those the model still admits.
//! 3. **Parabolic cylinder Ω6** (eq. 11, corrected, variant `s² − 2p·t`): fitted to the
//!    obstacle nodes that form whole columns along q4 (every node of a `(q2, q3)` column that
//!    the model still admits hits the obstacle: the middle link hits it whatever q4 is).
//!    Boundary points half a step outside the first and last such column of each section;
//!    the axis angle by a 1° scan, and vertex and focal parameter by least squares
//!    `t = A·s² + B·s + C` in the rotated frame (smallest residual wins).
//! 4. **Ω5**: the remaining obstacle nodes; both the paper's elliptic cylinder with a linear
//!    centre (tunnel case, eq. 9; as step 2) and its kinematic ellipse with cubic centre and
//!    semi-axes (two-plane case, eqs. 13–14: per-section centroids and semi-axes, 0.5° grid,
//!    at the common principal tilt, then cubic least squares in q2) are fitted, and the one
//!    with fewer errors is kept.
//!
//! A primitive is kept only when it lowers the error count. The region is composed in the
//! paper's order (box, Ω1, Ω2, Ω3, Ω4, Ω5, Ω6; eqs. 3 and 8); a primitive that cuts no
//! node in that order is dropped. The fit minimises the number of misclassified grid nodes,
//! forbidden nodes classified allowed weighted by [`FitOptions::false_allowed_weight`]. It is
//! not conservative: forbidden nodes may be classified allowed ([`Confusion::false_allowed`]);
//! a larger weight trades them for lost allowed nodes.

use serde::Serialize;

use super::WorldError;
use super::cspace::{CspaceGrid, NodeClass};
use super::rfunction::{Flat, Parabola, Primitive, Region};

/// Number of plane normals tried by the support-plane search.
const PLANE_DIRECTIONS: usize = 4000;
/// Largest grid [`fit_region`] accepts (the search costs grow with the node count; 15° over
/// the Varan box is 2601 nodes, 7.5° is 18 513). Validate on finer grids with [`confusion`].
pub const MAX_FIT_NODES: usize = 20_000;
/// Largest semi-axis tried, degrees.
const MAX_SEMI_AXIS: f64 = 400.0;

/// Options of [`fit_region`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FitOptions {
    /// Most half-spaces fitted (the paper uses 3).
    pub max_planes: usize,
    /// Cost of a forbidden node classified allowed, relative to an allowed node classified
    /// forbidden (1: minimise the total error; larger: a more conservative region that loses
    /// allowed nodes to admit fewer forbidden ones). Finite and positive.
    pub false_allowed_weight: f64,
}

impl Default for FitOptions {
    fn default() -> Self {
        FitOptions { max_planes: 3, false_allowed_weight: 1.0 }
    }
}

/// One fitted primitive.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FittedPart {
    /// The paper's name: `Ω1` (elliptic cylinder), `Ω2`–`Ω4` (planes), `Ω5` (obstacle
    /// ellipse), `Ω6` (parabolic cylinder).
    pub name: String,
    /// The primitive, degrees.
    pub primitive: Primitive,
    /// For a half-space: the grid nodes of the allowed set on the plane (its support
    /// points), `(q2, q3, q4)` in degrees; empty otherwise.
    pub support_points_deg: Vec<[f64; 3]>,
    /// Grid nodes this primitive alone moves from allowed to forbidden when it is added:
    /// correctly (truly forbidden).
    pub cut_forbidden: usize,
    /// … and wrongly (truly allowed).
    pub cut_allowed: usize,
}

/// Confusion counts of a region against grid truth ("allowed" is the positive class).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Confusion {
    /// Grid nodes.
    pub nodes: usize,
    /// Allowed in the grid and in the region.
    pub true_allowed: usize,
    /// Forbidden in the grid, allowed by the region.
    pub false_allowed: usize,
    /// Allowed in the grid, forbidden by the region.
    pub false_forbidden: usize,
    /// Forbidden in both.
    pub true_forbidden: usize,
    /// Of `false_allowed`: nodes whose link hits an obstacle (the rest are outside the task
    /// zone, the limits or self-colliding).
    pub false_allowed_obstacle: usize,
    /// Per primitive of the region (in order): truly allowed nodes it puts outside (`X < 0`).
    pub false_forbidden_by_primitive: Vec<usize>,
    /// `(false_allowed + false_forbidden) / nodes`.
    pub rate: f64,
}

/// A fitted region with its parts and its confusion counts on the fitting grid.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fit {
    /// The region, `(q2, q3, q4)` = the grid's swept joints, degrees.
    pub region: Region,
    /// 0-based indices of the swept joints that are the region's coordinates.
    pub joints: [usize; 3],
    /// The region's primitives with their names and support points, in composition order.
    pub parts: Vec<FittedPart>,
    /// The fitted region against the grid it was fitted on.
    pub confusion: Confusion,
}

/// Grid nodes in degrees with their classes.
struct Nodes {
    joints: [usize; 3],
    limits: [[f64; 2]; 3],
    /// Per coordinate, the axis values in degrees.
    axes: [Vec<f64>; 3],
    q: Vec<[f64; 3]>,
    /// Axis indices of each node.
    idx: Vec<[usize; 3]>,
    class: Vec<NodeClass>,
}

fn nodes(grid: &CspaceGrid) -> Result<Nodes, WorldError> {
    let swept: Vec<usize> = (0..grid.axes.len()).filter(|&j| grid.axes[j].len() > 1).collect();
    if swept.len() != 3 {
        return Err(WorldError::Input(format!(
            "an R-function region needs a grid with exactly three swept joints (fix the others), got {}",
            swept.len()
        )));
    }
    let joints = [swept[0], swept[1], swept[2]];
    // Degrees rounded to 1e-9 so that nodes on the limits lie exactly on the box faces.
    let axes = joints.map(|j| grid.axes[j].iter().map(|v| (v.to_degrees() * 1e9).round() / 1e9).collect::<Vec<f64>>());
    let limits = [0, 1, 2].map(|k| {
        let a = &axes[k];
        [a.iter().copied().fold(f64::INFINITY, f64::min), a.iter().copied().fold(f64::NEG_INFINITY, f64::max)]
    });
    let mut q = Vec::with_capacity(grid.classes.len());
    let mut idx = Vec::with_capacity(grid.classes.len());
    for i in 0..grid.classes.len() {
        // The swept joints have axes of at least two values.
        let k = joints.map(|j| grid.axis_index(i, j).unwrap_or(0));
        idx.push(k);
        q.push([axes[0][k[0]], axes[1][k[1]], axes[2][k[2]]]);
    }
    Ok(Nodes { joints, limits, axes, q, idx, class: grid.classes.clone() })
}

/// The confusion counts of `region` against `grid` (coordinates: the grid's three swept
/// joints in degrees, in joint order).
///
/// # Errors
/// [`WorldError::Input`] when the grid does not sweep exactly three joints.
pub fn confusion(region: &Region, grid: &CspaceGrid) -> Result<Confusion, WorldError> {
    let n = nodes(grid)?;
    Ok(confusion_of(region, &n))
}

fn confusion_of(region: &Region, n: &Nodes) -> Confusion {
    let mut c = Confusion {
        nodes: n.q.len(),
        true_allowed: 0,
        false_allowed: 0,
        false_forbidden: 0,
        true_forbidden: 0,
        false_allowed_obstacle: 0,
        false_forbidden_by_primitive: vec![0; region.primitives.len()],
        rate: 0.0,
    };
    // The region's one membership test (`Region::contains`, here in its compiled batch form).
    let mut admitted = Vec::with_capacity(n.q.len());
    region.compile().contains_into(&n.q, &mut admitted);
    let flat: Vec<Flat> = region.primitives.iter().map(Flat::of).collect();
    for ((q, class), admitted) in n.q.iter().zip(&n.class).zip(admitted) {
        let truth = *class == NodeClass::Allowed;
        match (truth, admitted) {
            (true, true) => c.true_allowed += 1,
            (false, true) => {
                c.false_allowed += 1;
                if *class == NodeClass::ObstacleCollision {
                    c.false_allowed_obstacle += 1;
                }
            }
            (true, false) => {
                c.false_forbidden += 1;
                for (k, p) in flat.iter().enumerate() {
                    if !p.admits_at(*q) {
                        c.false_forbidden_by_primitive[k] += 1;
                    }
                }
            }
            (false, false) => c.true_forbidden += 1,
        }
    }
    c.rate = if c.nodes == 0 { 0.0 } else { (c.false_allowed + c.false_forbidden) as f64 / c.nodes as f64 };
    c
}

/// Fits the paper's region to `grid` (method in the module documentation).
///
/// # Errors
/// [`WorldError::NoAllowedNode`] when the grid has no allowed node (checked before the grid's
/// shape and size); [`WorldError::Input`] when the grid does not sweep exactly three joints or
/// has more than [`MAX_FIT_NODES`] nodes, `max_planes` exceeds 3 or `false_allowed_weight` is
/// not finite and positive.
pub fn fit_region(grid: &CspaceGrid, options: &FitOptions) -> Result<Fit, WorldError> {
    if options.max_planes > 3 {
        return Err(WorldError::Input(format!("max_planes is at most 3 (Ω2–Ω4), got {}", options.max_planes)));
    }
    let w = options.false_allowed_weight;
    if !(w.is_finite() && w > 0.0) {
        return Err(WorldError::Input(format!("false_allowed_weight must be finite and positive, got {w}")));
    }
    if !grid.classes.contains(&NodeClass::Allowed) {
        return Err(WorldError::NoAllowedNode);
    }
    if grid.classes.len() > MAX_FIT_NODES {
        return Err(WorldError::Input(format!(
            "fitting takes a grid of at most {MAX_FIT_NODES} nodes, got {} (use a coarser step)",
            grid.classes.len()
        )));
    }
    let n = nodes(grid)?;
    let truth: Vec<bool> = n.class.iter().map(|c| *c == NodeClass::Allowed).collect();
    let obstacle: Vec<bool> = n.class.iter().map(|c| *c == NodeClass::ObstacleCollision).collect();
    let free: Vec<bool> = truth.iter().zip(&obstacle).map(|(a, o)| *a || *o).collect();
    let weights = (options.false_allowed_weight, 1.0);
    // `inside[i]`: the model so far admits node i (every node lies in the box).
    let mut inside = vec![true; n.q.len()];

    let planes = fit_planes(&n, &free, &mut inside, options.max_planes);
    // Ω1: forbidden nodes outside θ left inside the planes, against the obstacle-free set.
    let targets: Vec<bool> = (0..n.q.len()).map(|i| inside[i] && !free[i]).collect();
    let omega1 = fit_cylinder(&n, &targets, &free, &inside, weights);
    if let Some((p, _)) = &omega1 {
        apply(p, &n, &mut inside, |_| ());
    }
    // Obstacle: Ω6 on whole q4 columns, then Ω5 on the rest.
    let targets: Vec<bool> = (0..n.q.len()).map(|i| inside[i] && obstacle[i]).collect();
    let omega6 = fit_parabola(&n, &targets, &truth, &inside, weights);
    let mut inside5 = inside.clone();
    if let Some(p) = &omega6 {
        apply(p, &n, &mut inside5, |_| ());
    }
    let targets5: Vec<bool> = (0..n.q.len()).map(|i| inside5[i] && obstacle[i]).collect();
    let cyl = fit_cylinder(&n, &targets5, &truth, &inside5, weights);
    let kin = fit_kinematic(&n, &targets5, &truth, &inside5, weights);
    let omega5 = match (cyl, kin) {
        (Some(c), Some(k)) => Some(if k.1 < c.1 { k } else { c }),
        (c, k) => c.or(k),
    };

    let mut parts: Vec<(String, Primitive, Vec<[f64; 3]>)> = Vec::new();
    if let Some((p, _)) = omega1 {
        parts.push(("Ω1".into(), p, Vec::new()));
    }
    for (k, (p, support)) in planes.into_iter().enumerate() {
        parts.push((format!("Ω{}", k + 2), p, support));
    }
    if let Some((p, _)) = omega5 {
        parts.push(("Ω5".into(), p, Vec::new()));
    }
    if let Some(p) = omega6 {
        parts.push(("Ω6".into(), p, Vec::new()));
    }
    // What each primitive cuts when added in composition order; parts that cut nothing go.
    let mut admitted = vec![true; n.q.len()];
    let parts: Vec<FittedPart> = parts
        .into_iter()
        .map(|(name, primitive, support_points_deg)| {
            let (mut cut_forbidden, mut cut_allowed) = (0, 0);
            apply(&primitive, &n, &mut admitted, |i| {
                if truth[i] {
                    cut_allowed += 1;
                } else {
                    cut_forbidden += 1;
                }
            });
            FittedPart { name, primitive, support_points_deg, cut_forbidden, cut_allowed }
        })
        .filter(|p| p.cut_forbidden + p.cut_allowed > 0)
        .collect();
    let region = Region { limits: n.limits, primitives: parts.iter().map(|p| p.primitive.clone()).collect() };
    let confusion = confusion_of(&region, &n);
    Ok(Fit { region, joints: n.joints, parts, confusion })
}

/// Cuts off the nodes still `inside` that `p` forbids (the test of [`Region::contains`]),
/// calling `on_cut` with each.
fn apply(p: &Primitive, n: &Nodes, inside: &mut [bool], mut on_cut: impl FnMut(usize)) {
    let p = Flat::of(p);
    for (i, q) in n.q.iter().enumerate() {
        if inside[i] && !p.admits_at(*q) {
            inside[i] = false;
            on_cut(i);
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Greedy support planes of the set `keep` (module documentation, step 1).
fn fit_planes(n: &Nodes, keep: &[bool], inside: &mut [bool], max: usize) -> Vec<(Primitive, Vec<[f64; 3]>)> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let dirs: Vec<[f64; 3]> = (0..PLANE_DIRECTIONS)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / PLANE_DIRECTIONS as f64;
            let r = (1.0 - z * z).sqrt();
            let t = golden * k as f64;
            [r * t.cos(), r * t.sin(), z]
        })
        .collect();
    let kept: Vec<[f64; 3]> = n.q.iter().zip(keep).filter(|(_, k)| **k).map(|(q, _)| *q).collect();
    let mut out = Vec::new();
    for _ in 0..max {
        let mut best: Option<(usize, [f64; 3], f64)> = None;
        for d in &dirs {
            let b = kept.iter().map(|q| dot(*d, *q)).fold(f64::INFINITY, f64::min);
            let cut = (0..n.q.len()).filter(|&i| inside[i] && !keep[i] && dot(*d, n.q[i]) < b).count();
            if cut > best.map_or(0, |x| x.0) {
                best = Some((cut, *d, b));
            }
        }
        let Some((_, d, b)) = best else { break };
        let support: Vec<[f64; 3]> = kept.iter().filter(|q| dot(d, **q) - b <= 1e-9).copied().collect();
        for (i, q) in n.q.iter().enumerate() {
            if dot(d, *q) < b {
                inside[i] = false;
            }
        }
        out.push((Primitive::HalfSpace { d, b }, support));
    }
    out
}

/// Weighted least-squares polynomial of degree `deg` (≤ 3) through `(x, y, w)`; constant
/// term first, padded to four coefficients. `None` when singular.
fn polyfit(points: &[(f64, f64, f64)], deg: usize) -> Option<[f64; 4]> {
    let m = deg + 1;
    let mut ata = nalgebra::DMatrix::<f64>::zeros(m, m);
    let mut atb = nalgebra::DVector::<f64>::zeros(m);
    for &(x, y, w) in points {
        let pow: Vec<f64> = (0..m).map(|k| x.powi(k as i32)).collect();
        for r in 0..m {
            atb[r] += w * pow[r] * y;
            for c in 0..m {
                ata[(r, c)] += w * pow[r] * pow[c];
            }
        }
    }
    let sol = ata.lu().solve(&atb)?;
    let mut out = [0.0; 4];
    for k in 0..m {
        out[k] = sol[k];
    }
    Some(out)
}

/// Per section (index along the first coordinate): centroid `(q3, q4)` and count of targets.
fn section_centroids(n: &Nodes, targets: &[bool]) -> Vec<(usize, f64, f64, usize)> {
    let mut acc = vec![(0.0, 0.0, 0_usize); n.axes[0].len()];
    for (i, q) in n.q.iter().enumerate() {
        if targets[i] {
            let a = &mut acc[n.idx[i][0]];
            a.0 += q[1];
            a.1 += q[2];
            a.2 += 1;
        }
    }
    acc.into_iter()
        .enumerate()
        .filter(|(_, a)| a.2 > 0)
        .map(|(s, a)| (s, a.0 / a.2 as f64, a.1 / a.2 as f64, a.2))
        .collect()
}

/// Tilt (degrees, `[0, 180)`) of the principal axis of the targets, each centred on
/// `centre(node)` (the `(q3, q4)` centre of the node's section).
fn principal_tilt(n: &Nodes, targets: &[bool], centre: impl Fn(usize) -> (f64, f64)) -> f64 {
    let (mut sxx, mut syy, mut sxy) = (0.0, 0.0, 0.0);
    for (i, q) in n.q.iter().enumerate() {
        if targets[i] {
            let (c3, c4) = centre(i);
            let (x, y) = (q[1] - c3, q[2] - c4);
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
        }
    }
    (0.5 * (2.0 * sxy).atan2(sxx - syy)).to_degrees().rem_euclid(180.0)
}

/// Coordinates `(u, v)` of `(q3, q4)` in the frame of an ellipse centred at `c`, tilt `phi`.
fn ellipse_frame(phi_deg: f64, q: [f64; 3], c: (f64, f64)) -> (f64, f64) {
    let (s, co) = phi_deg.to_radians().sin_cos();
    let (d3, d4) = (q[1] - c.0, q[2] - c.1);
    (d3 * co + d4 * s, -d3 * s + d4 * co)
}

/// Best semi-axes `(a, b, cost)` of an ellipse for nodes given as `(u, v, is_target)`: a node
/// is inside (cut) when `u²/a² + v²/b² < 1`; cost = `w.0`·targets outside + `w.1`·others
/// inside. `a` from `a_values`, `b` by an exact sweep over the node thresholds (the midpoint
/// between consecutive thresholds, for margin on both sides).
fn best_axes(pts: &[(f64, f64, bool)], a_values: &[f64], w: (f64, f64)) -> Option<(f64, f64, f64)> {
    let total_targets = pts.iter().filter(|p| p.2).count() as f64;
    let mut best: Option<(f64, f64, f64)> = None;
    let mut th: Vec<(f64, bool)> = Vec::with_capacity(pts.len());
    for &a in a_values {
        th.clear();
        for &(u, v, t) in pts {
            let r = 1.0 - (u / a).powi(2);
            if r > 0.0 {
                th.push((v.abs() / r.sqrt(), t));
            }
        }
        th.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        // b below the first threshold: nothing inside.
        let mut cost = w.0 * total_targets;
        let mut k = 0;
        while k < th.len() {
            let t0 = th[k].0;
            while k < th.len() && th[k].0 == t0 {
                cost += if th[k].1 { -w.0 } else { w.1 };
                k += 1;
            }
            let next = if k < th.len() { th[k].0 } else { t0 + 1.0 };
            let b = 0.5 * (t0 + next).max(0.5);
            if b > t0 && b <= MAX_SEMI_AXIS && best.is_none_or(|x| cost < x.2) {
                best = Some((a, b, cost));
            }
        }
    }
    best
}

/// Semi-axis candidates: coarse (geometric, 8 % apart) for searching, then 0.5° steps
/// within ±10 % of the coarse optimum.
fn coarse_axes() -> Vec<f64> {
    std::iter::successors(Some(2.0), |a| Some(a * 1.08)).take_while(|a| *a <= MAX_SEMI_AXIS).collect()
}

fn fine_axes(a: f64) -> Vec<f64> {
    let lo = (0.9 * a).max(0.5);
    (0..).map(|k| lo + 0.5 * f64::from(k)).take_while(|x| *x <= (1.1 * a).min(MAX_SEMI_AXIS)).collect()
}

/// The cost of cutting with `p` the admitted nodes, relative to not cutting.
fn cut_cost(p: &Primitive, n: &Nodes, targets: &[bool], positives: &[bool], inside: &[bool], w: (f64, f64)) -> f64 {
    let mut cost = 0.0;
    let p = Flat::of(p);
    for (i, q) in n.q.iter().enumerate() {
        if inside[i] && !p.admits_at(*q) {
            if targets[i] {
                cost -= w.0;
            } else if positives[i] {
                cost += w.1;
            }
        }
    }
    cost
}

/// Elliptic cylinder with a linear centre (module documentation, step 2); `None` when there
/// are no targets or it does not lower the cost.
fn fit_cylinder(
    n: &Nodes,
    targets: &[bool],
    positives: &[bool],
    inside: &[bool],
    w: (f64, f64),
) -> Option<(Primitive, f64)> {
    let cents = section_centroids(n, targets);
    if cents.is_empty() {
        return None;
    }
    let deg = usize::from(cents.len() > 1);
    let pts3: Vec<(f64, f64, f64)> = cents.iter().map(|c| (n.axes[0][c.0], c.1, c.3 as f64)).collect();
    let pts4: Vec<(f64, f64, f64)> = cents.iter().map(|c| (n.axes[0][c.0], c.2, c.3 as f64)).collect();
    let (l3, l4) = (polyfit(&pts3, deg)?, polyfit(&pts4, deg)?);
    let phi = principal_tilt(n, targets, |i| {
        let q2 = n.q[i][0];
        (l3[1] * q2 + l3[0], l4[1] * q2 + l4[0])
    });
    let nodes: Vec<([f64; 3], bool)> =
        (0..n.q.len()).filter(|&i| inside[i] && (targets[i] || positives[i])).map(|i| (n.q[i], targets[i])).collect();
    // x = [k3, m3, k4, m4, φ]; the semi-axes are optimal for each x.
    let coarse = coarse_axes();
    let eval = |x: &[f64; 5], a_values: &[f64]| {
        let pts: Vec<(f64, f64, bool)> = nodes
            .iter()
            .map(|(q, t)| {
                let (u, v) = ellipse_frame(x[4], *q, (x[0] * q[0] + x[1], x[2] * q[0] + x[3]));
                (u, v, *t)
            })
            .collect();
        best_axes(&pts, a_values, w)
    };
    // Pattern search from the centroid line with the principal tilt, and from that line moved
    // away from the admitted allowed nodes (the ellipse's centre lies on the forbidden side
    // of the contour it bounds) with the major axis across that direction.
    let mean = |sel: &dyn Fn(usize) -> bool| {
        let (mut s3, mut s4, mut k) = (0.0, 0.0, 0.0_f64);
        for (i, q) in n.q.iter().enumerate() {
            if inside[i] && sel(i) {
                (s3, s4, k) = (s3 + q[1], s4 + q[2], k + 1.0);
            }
        }
        (s3 / k.max(1.0), s4 / k.max(1.0))
    };
    let (t, a) = (mean(&|i| targets[i]), mean(&|i| positives[i] && !targets[i]));
    let (dx, dy) = (t.0 - a.0, t.1 - a.1);
    let norm = dx.hypot(dy).max(1e-9);
    let across = dy.atan2(dx).to_degrees() + 90.0;
    let mut best: Option<([f64; 5], (f64, f64, f64))> = None;
    for (shift, tilt) in [(0.0, phi), (60.0, across), (120.0, across), (200.0, across)] {
        let mut x = [l3[1], l3[0] + shift * dx / norm, l4[1], l4[0] + shift * dy / norm, tilt];
        let Some(mut fx) = eval(&x, &coarse) else { continue };
        let mut h = [0.25, 20.0, 0.25, 20.0, 20.0];
        while h[4] >= 2.0 {
            let mut improved = false;
            for k in 0..5 {
                for sign in [1.0, -1.0] {
                    let mut y = x;
                    y[k] += sign * h[k];
                    if let Some(fy) = eval(&y, &coarse)
                        && fy.2 < fx.2
                    {
                        (x, fx, improved) = (y, fy, true);
                    }
                }
            }
            if !improved {
                h.iter_mut().for_each(|v| *v *= 0.5);
            }
        }
        if best.is_none_or(|b| fx.2 < b.1.2) {
            best = Some((x, fx));
        }
    }
    let (x, coarse_fx) = best?;
    let fx = eval(&x, &fine_axes(coarse_fx.0))?;
    let p = Primitive::EllipticCylinder {
        phi_deg: x[4].rem_euclid(180.0),
        a: fx.0,
        b: fx.1,
        centre: [x[0], x[1], x[2], x[3]],
    };
    let cost = cut_cost(&p, n, targets, positives, inside, w);
    (cost < 0.0).then_some((p, cost))
}

/// Kinematic ellipse with cubic centre and semi-axes (module documentation, step 4).
fn fit_kinematic(
    n: &Nodes,
    targets: &[bool],
    positives: &[bool],
    inside: &[bool],
    w: (f64, f64),
) -> Option<(Primitive, f64)> {
    let cents = section_centroids(n, targets);
    if cents.len() < 2 {
        return None;
    }
    let mut centre_of = vec![None; n.axes[0].len()];
    for c in &cents {
        centre_of[c.0] = Some((c.1, c.2));
    }
    // Every target lies in a section with a centroid.
    let phi = principal_tilt(n, targets, |i| centre_of[n.idx[i][0]].unwrap_or((0.0, 0.0)));
    let (mut m3, mut m4, mut aa, mut bb) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // Per section there are few nodes: every semi-axis on a 0.5° grid.
    let section_axes: Vec<f64> = (1..=(2.0 * MAX_SEMI_AXIS) as u32).map(|k| 0.5 * f64::from(k)).collect();
    for c in &cents {
        let pts: Vec<(f64, f64, bool)> = (0..n.q.len())
            .filter(|&i| n.idx[i][0] == c.0 && inside[i] && (targets[i] || positives[i]))
            .map(|i| {
                let (u, v) = ellipse_frame(phi, n.q[i], (c.1, c.2));
                (u, v, targets[i])
            })
            .collect();
        let Some((a, b, _)) = best_axes(&pts, &section_axes, w) else { continue };
        let x = n.axes[0][c.0];
        m3.push((x, c.1, 1.0));
        m4.push((x, c.2, 1.0));
        aa.push((x, a, 1.0));
        bb.push((x, b, 1.0));
    }
    if m3.len() < 2 {
        return None;
    }
    let deg = (m3.len() - 1).min(3);
    let p = Primitive::KinematicEllipse {
        phi_deg: phi,
        m3: polyfit(&m3, deg)?,
        m4: polyfit(&m4, deg)?,
        a: polyfit(&aa, deg)?,
        b: polyfit(&bb, deg)?,
    };
    let cost = cut_cost(&p, n, targets, positives, inside, w);
    (cost < 0.0).then_some((p, cost))
}

/// Parabolic cylinder along q4 (module documentation, step 3).
fn fit_parabola(n: &Nodes, targets: &[bool], positives: &[bool], inside: &[bool], w: (f64, f64)) -> Option<Primitive> {
    let (n2, n3) = (n.axes[0].len(), n.axes[1].len());
    // Per (q2, q3) column: admitted targets and admitted others.
    let mut cols = vec![(0_usize, 0_usize); n2 * n3];
    for i in 0..n.q.len() {
        if inside[i] {
            let c = &mut cols[n.idx[i][0] * n3 + n.idx[i][1]];
            if targets[i] {
                c.0 += 1;
            } else {
                c.1 += 1;
            }
        }
    }
    let mut boundary = Vec::new();
    for s in 0..n2 {
        let band: Vec<usize> = (0..n3).filter(|&k| cols[s * n3 + k].0 >= 2 && cols[s * n3 + k].1 == 0).collect();
        if let (Some(&lo), Some(&hi)) = (band.first(), band.last()) {
            let ax = &n.axes[1];
            let below = if lo > 0 { 0.5 * (ax[lo] + ax[lo - 1]) } else { ax[lo] };
            let above = if hi + 1 < n3 { 0.5 * (ax[hi] + ax[hi + 1]) } else { ax[hi] };
            boundary.push([n.axes[0][s], below]);
            boundary.push([n.axes[0][s], above]);
        }
    }
    if boundary.len() < 4 {
        return None;
    }
    let mut best: Option<(f64, f64, [f64; 4])> = None;
    for k in 0..360 {
        let phi = f64::from(k);
        let (sn, cs) = phi.to_radians().sin_cos();
        let st: Vec<(f64, f64, f64)> =
            boundary.iter().map(|p| (p[0] * cs + p[1] * sn, -p[0] * sn + p[1] * cs, 1.0)).collect();
        let Some(c) = polyfit(&st, 2) else { continue };
        if c[2] <= 1e-9 {
            continue;
        }
        let rss: f64 = st.iter().map(|(s, t, _)| (t - (c[2] * s * s + c[1] * s + c[0])).powi(2)).sum();
        if best.is_none_or(|b| rss < b.0) {
            best = Some((rss, phi, c));
        }
    }
    let (_, phi, c) = best?;
    let (sn, cs) = phi.to_radians().sin_cos();
    let s0 = -c[1] / (2.0 * c[2]);
    let t0 = c[0] - c[2] * s0 * s0;
    let p = Primitive::ParabolicCylinder {
        phi_deg: phi,
        vertex: [s0 * cs - t0 * sn, s0 * sn + t0 * cs],
        p: 1.0 / (2.0 * c[2]),
        variant: Parabola::SquareFirst,
    };
    (cut_cost(&p, n, targets, positives, inside, w) < 0.0).then_some(p)
}
