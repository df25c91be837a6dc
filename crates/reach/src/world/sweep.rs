//! Continuous collision checking of joint-space motions along straight lines and quadratic
//! arcs: a motion is called clear only with a proven positive clearance, never because samples
//! missed the obstacle.
//!
//! # Method: conservative advancement with certified rates
//!
//! Along the motion `q(s)`, `s ∈ [0, 1]` — the straight line `a + s·(b − a)` or the quadratic
//! arc (Bézier) `(1−s)²·p₀ + 2s(1−s)·p₁ + s²·p₂` ([`JointCurve`]) — every clearance `d_c(s)`
//! (a link against an obstacle, two links, the tool point against its zone's boundary)
//! changes no faster than a rate `B_c` fixed before the sweep: the most any point of the
//! bodies involved can move per unit `s`. With `σ_j` a bound of joint `j`'s speed
//! `|dq_j/ds|` over the motion (`|b_j − a_j|` on a line; on an arc, whose derivative is linear
//! in `s`, the larger of `2|p₁ − p₀|_j` and `2|p₂ − p₁|_j`), a point of link `k` moves at most
//! `Σ_j σ_j·ρ_jk` per unit `s` — over the revolute joints `j` moving link `k`, `ρ_jk` bounding
//! the point's distance from joint `j`'s axis (the chain length from the joint's frame to the
//! far end of link `k`, plus the link's radius) — plus `σ_j` for each prismatic joint.
//! Lengths that depend on the configuration are bounded over the motion's convex hull (the
//! line's ends, the arc's control points: an arc lies in the triangle of its control points).
//! Since a distance between sets moves no faster than the points of the sets,
//! `|d_c(s') − d_c(s)| ≤ B_c·|s' − s|`.
//!
//! **In time.** When the motion is timed, `s` running over `[t_a, t_b]` at a constant rate,
//! an obstacle moving at a constant velocity `v` is at `p0 + v·t` at `t = t_a + s·(t_b − t_a)`:
//! relative to it every link point moves by at most `|v|·(t_b − t_a)` more per unit `s`, so
//! its clearances' rates are `B_c + |v|·(t_b − t_a)` and the same advancement proves the
//! motion clear of the moving obstacle (a fixed one is `v = 0`). The clearances are evaluated
//! with the obstacle where it is at the instant of each evaluated point.
//!
//! From `s` the sweep advances by `Δs = min_c d_c(s)/B_c`: no clearance can reach zero inside
//! the step. Between two evaluated points the clearance is at least
//! `(d_c(s) + d_c(s + Δs) − B_c·Δs)/2` (the two Lipschitz cones meet there), so the sweep
//! gives a **certified lower bound** of the clearance over the whole motion, positive when
//! every evaluated clearance is. A clearance at or below [`SWEEP_FLOOR`] stops the sweep: the
//! motion touches, penetrates, or comes too close to prove it does not. The step count is
//! bounded by `B/floor`; [`MAX_SWEEP_EVALUATIONS`] caps it (not clear when reached).
//!
//! For reports ([`SweepOptions::closest`]), after a clear sweep the intervals whose bound is below the
//! smallest evaluated clearance by more than a tolerance are bisected, so the reported minimum
//! and its lower bound agree to about 0.1 % (or 1 µm).

use serde::Serialize;

use super::WorldError;

/// Clearance (metres) at or below which a motion is not called clear: it touches, penetrates,
/// or comes so close that clearing it would take steps of less than `floor/B`.
pub const SWEEP_FLOOR: f64 = 1e-6;

/// The most clearance evaluations one sweep may make (the resource cap; a sweep that needs
/// more is not called clear). A refining sweep keeps every evaluated point: at most this many
/// vectors of clearances.
pub const MAX_SWEEP_EVALUATIONS: usize = 100_000;

/// Clearances that change at a bounded rate along joint-space motions.
pub trait Clearances {
    /// Prepares a motion that stays inside the convex hull of the configurations `hull`
    /// (the two ends of a line, the three control points of an arc) with joint `j`'s speed
    /// `|dq_j/ds| ≤ speed[j]`, and returns the rate bound of every clearance per unit of `s`
    /// (metres); its length is the number of clearances [`Clearances::evaluate`] fills.
    ///
    /// # Errors
    /// As [`Clearances::evaluate`].
    fn prepare(&mut self, hull: &[&[f64]], speed: &[f64]) -> Result<Vec<f64>, WorldError>;

    /// Every clearance at `q`, the point `s ∈ [0, 1]` of the motion prepared last, metres,
    /// into `out` (≤ 0: touching or penetrating). `s` places what moves with time along the
    /// motion (an obstacle at a known velocity); clearances of fixed things depend on `q` only.
    ///
    /// # Errors
    /// [`WorldError`] for a configuration the model rejects (wrong length, NaN).
    fn evaluate(&mut self, s: f64, q: &[f64], out: &mut [f64]) -> Result<(), WorldError>;
}

/// The outcome of a swept check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sweep {
    /// Whether the motion is proven clear: every clearance stays above [`SWEEP_FLOOR`] over
    /// the whole motion.
    pub clear: bool,
    /// Certified lower bound of the smallest clearance over the motion (clear) or up to where
    /// the sweep stopped, metres; `+∞` without constraints.
    pub lower_bound: f64,
    /// Smallest clearance evaluated, metres (the true minimum lies between `lower_bound` and
    /// this); `+∞` without constraints.
    pub min_clearance: f64,
    /// Where the smallest clearance was found (or where the sweep stopped), as the fraction
    /// `s ∈ [0, 1]` of the motion.
    pub at: f64,
    /// Which clearance (index into the [`Clearances`]) is smallest there.
    pub constraint: usize,
    /// Clearance evaluations made.
    pub evaluations: usize,
}

/// One evaluated point of the sweep.
struct Point {
    s: f64,
    d: Vec<f64>,
}

/// How a sweep runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SweepOptions {
    /// After a clear sweep, bisect until the reported minimum and its certified lower bound
    /// agree to about 0.1 % (what reports need; planners only need the verdict).
    pub closest: bool,
    /// Evaluations after which the sweep stops, not clear (at most
    /// [`MAX_SWEEP_EVALUATIONS`]). A planner may set a small budget per edge: an edge that
    /// needs more is rejected, which is safe.
    pub max_evaluations: usize,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions { closest: true, max_evaluations: MAX_SWEEP_EVALUATIONS }
    }
}

/// A joint-space motion over `s ∈ [0, 1]` that [`sweep_curve`] checks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointCurve<'a> {
    /// The straight line `a + s·(b − a)`.
    Line(&'a [f64], &'a [f64]),
    /// The quadratic arc (Bézier) `(1−s)²·p₀ + 2s(1−s)·p₁ + s²·p₂` from `p₀` to `p₂`, tangent
    /// there to `p₁ − p₀` and `p₂ − p₁` (a blend between two straight motions).
    Quadratic(&'a [f64], &'a [f64], &'a [f64]),
}

impl JointCurve<'_> {
    /// The configurations whose convex hull holds the motion.
    fn hull(&self) -> Vec<&[f64]> {
        match *self {
            JointCurve::Line(a, b) => vec![a, b],
            JointCurve::Quadratic(p0, p1, p2) => vec![p0, p1, p2],
        }
    }

    /// The first configuration.
    #[must_use]
    pub fn start(&self) -> &[f64] {
        match *self {
            JointCurve::Line(a, _) | JointCurve::Quadratic(a, _, _) => a,
        }
    }

    /// The last configuration.
    #[must_use]
    pub fn end(&self) -> &[f64] {
        match *self {
            JointCurve::Line(_, b) | JointCurve::Quadratic(_, _, b) => b,
        }
    }

    /// Each joint's largest `|dq_j/ds|` over the motion (exact: the derivative is constant on
    /// a line and linear on an arc).
    fn speed(&self) -> Vec<f64> {
        match *self {
            JointCurve::Line(a, b) => a.iter().zip(b).map(|(x, y)| (y - x).abs()).collect(),
            JointCurve::Quadratic(p0, p1, p2) => {
                (0..p0.len()).map(|j| 2.0 * (p1[j] - p0[j]).abs().max((p2[j] - p1[j]).abs())).collect()
            }
        }
    }

    /// The configuration at `s` into `out`.
    fn at(&self, s: f64, out: &mut [f64]) {
        match *self {
            JointCurve::Line(a, b) => {
                for ((o, x), y) in out.iter_mut().zip(a).zip(b) {
                    *o = x + s * (y - x);
                }
            }
            JointCurve::Quadratic(p0, p1, p2) => {
                let (w0, w1, w2) = ((1.0 - s) * (1.0 - s), 2.0 * s * (1.0 - s), s * s);
                for (j, o) in out.iter_mut().enumerate() {
                    *o = w0 * p0[j] + w1 * p1[j] + w2 * p2[j];
                }
            }
        }
    }
}

/// Sweeps the straight motion `a → b` (see the module docs).
///
/// # Errors
/// [`WorldError::Input`] when `a` and `b` differ in length or hold a non-finite value; as
/// [`Clearances::evaluate`].
pub fn sweep<C: Clearances + ?Sized>(
    clearances: &mut C,
    a: &[f64],
    b: &[f64],
    options: &SweepOptions,
) -> Result<Sweep, WorldError> {
    sweep_curve(clearances, &JointCurve::Line(a, b), options)
}

/// Sweeps the motion along `curve` (see the module docs): a straight line as [`sweep`], or a
/// quadratic arc.
///
/// # Errors
/// [`WorldError::Input`] when the curve's configurations differ in length or hold a
/// non-finite value; as [`Clearances::evaluate`].
pub fn sweep_curve<C: Clearances + ?Sized>(
    clearances: &mut C,
    curve: &JointCurve,
    options: &SweepOptions,
) -> Result<Sweep, WorldError> {
    let cap = options.max_evaluations.min(MAX_SWEEP_EVALUATIONS);
    let closest = options.closest;
    let hull = curve.hull();
    let dof = hull[0].len();
    if hull.iter().any(|p| p.len() != dof || !p.iter().all(|v| v.is_finite())) {
        let lengths: Vec<String> = hull.iter().map(|p| p.len().to_string()).collect();
        return Err(WorldError::Input(format!(
            "swept check: the motion's configurations must be finite joint vectors of one length, got {} values",
            lengths.join(", ")
        )));
    }
    let rates = clearances.prepare(&hull, &curve.speed())?;
    let n = rates.len();
    let mut result = Sweep {
        clear: true,
        lower_bound: f64::INFINITY,
        min_clearance: f64::INFINITY,
        at: 0.0,
        constraint: 0,
        evaluations: 0,
    };
    if n == 0 {
        return Ok(result);
    }
    let mut q = vec![0.0; dof];
    let mut eval = |s: f64, result: &mut Sweep, clearances: &mut C| -> Result<Point, WorldError> {
        curve.at(s, &mut q);
        let mut d = vec![0.0; n];
        clearances.evaluate(s, &q, &mut d)?;
        result.evaluations += 1;
        let (c, &m) = d.iter().enumerate().min_by(|x, y| x.1.total_cmp(y.1)).unwrap_or((0, &f64::INFINITY));
        if m < result.min_clearance {
            result.min_clearance = m;
            result.at = s;
            result.constraint = c;
        }
        Ok(Point { s, d })
    };
    let mut points = vec![eval(0.0, &mut result, clearances)?];
    // Without refinement only the last point is kept; the bound of what was dropped is here.
    let mut dropped = f64::INFINITY;
    loop {
        let last = points.last().map_or(0.0, |p| p.s);
        let d = &points[points.len() - 1].d;
        if let Some((c, &v)) = d.iter().enumerate().find(|(_, v)| v.is_nan() || **v <= SWEEP_FLOOR) {
            result.clear = false;
            result.at = last;
            result.constraint = c;
            result.lower_bound = v.min(dropped).min(bounds_of(&points, &rates));
            return Ok(result);
        }
        if last >= 1.0 {
            break;
        }
        if result.evaluations >= cap {
            result.clear = false;
            result.at = last;
            result.lower_bound = dropped.min(bounds_of(&points, &rates));
            return Ok(result);
        }
        let step = d.iter().zip(&rates).map(|(v, r)| if *r > 0.0 { v / r } else { f64::INFINITY }).fold(1.0, f64::min);
        let next = (last + step).min(1.0);
        points.push(eval(next, &mut result, clearances)?);
        if !closest {
            dropped = dropped.min(bounds_of(&points, &rates));
            points.remove(0);
        }
    }
    if closest {
        refine(&mut points, &rates, &mut result, &mut eval, clearances, cap)?;
    }
    result.lower_bound = dropped.min(bounds_of(&points, &rates));
    Ok(result)
}

/// The certified lower bound of the clearance over the intervals between `points`.
fn bounds_of(points: &[Point], rates: &[f64]) -> f64 {
    let mut lb = points.iter().flat_map(|p| p.d.iter().copied()).fold(f64::INFINITY, f64::min);
    for w in points.windows(2) {
        lb = lb.min(interval_bound(&w[0], &w[1], rates));
    }
    lb
}

/// Lower bound of every clearance between two evaluated points.
fn interval_bound(p: &Point, q: &Point, rates: &[f64]) -> f64 {
    let ds = q.s - p.s;
    p.d.iter().zip(&q.d).zip(rates).map(|((x, y), r)| 0.5 * (x + y - r * ds)).fold(f64::INFINITY, f64::min)
}

/// Bisects the intervals whose bound is below the smallest evaluated clearance by more than
/// the tolerance, until the bound is tight (or the evaluation cap is reached).
fn refine<C: Clearances + ?Sized>(
    points: &mut Vec<Point>,
    rates: &[f64],
    result: &mut Sweep,
    eval: &mut impl FnMut(f64, &mut Sweep, &mut C) -> Result<Point, WorldError>,
    clearances: &mut C,
    cap: usize,
) -> Result<(), WorldError> {
    let mut i = 0;
    while i + 1 < points.len() && result.evaluations < cap {
        let tolerance = (1e-3 * result.min_clearance).max(1e-6);
        let (p, q) = (&points[i], &points[i + 1]);
        if interval_bound(p, q, rates) >= result.min_clearance - tolerance || q.s - p.s <= f64::EPSILON {
            i += 1;
            continue;
        }
        let mid = eval(0.5 * (p.s + q.s), result, clearances)?;
        points.insert(i + 1, mid);
    }
    Ok(())
}

/// Rate bound of the points of a serial chain's segment along a straight joint motion.
///
/// `lengths[i]` bounds the length of segment `i` (between chain points `i` and `i + 1`) over
/// the motion; the axis of joint `j` passes through chain point `j` or `j + 1`; segment `k`
/// is moved by joints `0..=min(k, joints − 1)`. Relative to a segment that the joints before
/// `first` move rigidly together with segment `k`, a point within `radius` of segment `k`
/// moves at most `Σ_j |Δq_j|·(Σ_{i=j..=k} lengths[i] + radius)` over the revolute
/// joints `j ∈ first..=k`, plus `Σ |Δq_j|` over the prismatic ones, per unit of `s`
/// (`first = 0`: relative to the base).
#[must_use]
pub fn segment_rate(lengths: &[f64], revolute: &[bool], delta: &[f64], first: usize, k: usize, radius: f64) -> f64 {
    let chain = &lengths[..=k.min(lengths.len().saturating_sub(1))];
    delta
        .iter()
        .zip(revolute)
        .enumerate()
        .take(k + 1)
        .skip(first)
        .map(|(j, (dq, &rev))| {
            dq.abs() * if rev { chain.get(j..).map_or(0.0, |l| l.iter().sum::<f64>()) + radius } else { 1.0 }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One clearance `d(s) = |s − c| − gap` along a one-joint motion, rate 1.
    struct Line {
        c: f64,
        gap: f64,
    }

    impl Clearances for Line {
        fn prepare(&mut self, _hull: &[&[f64]], speed: &[f64]) -> Result<Vec<f64>, WorldError> {
            Ok(vec![speed[0]])
        }
        fn evaluate(&mut self, _s: f64, q: &[f64], out: &mut [f64]) -> Result<(), WorldError> {
            out[0] = (q[0] - self.c).abs() - self.gap;
            Ok(())
        }
    }

    #[test]
    fn a_crossing_between_any_samples_is_found() {
        // The point 0.4137 is crossed: never clear, whatever a sampling grid would see.
        let s = sweep(&mut Line { c: 0.4137, gap: 0.0 }, &[0.0], &[1.0], &SweepOptions::default()).unwrap();
        assert!(!s.clear);
        assert!((s.at - 0.4137).abs() < 1e-5, "{s:?}");
        assert!(s.lower_bound <= SWEEP_FLOOR);
    }

    #[test]
    fn a_near_miss_is_clear_with_a_tight_certified_bound() {
        // Passing 0.01 beside the obstacle: d(s) = |s − 2| − 0.99, minimum 0.01 at s = 1.
        let s = sweep(&mut Line { c: 2.0, gap: 0.99 }, &[0.0], &[1.0], &SweepOptions::default()).unwrap();
        assert!(s.clear, "{s:?}");
        assert!((s.min_clearance - 0.01).abs() < 1e-12, "{s:?}");
        assert!(s.lower_bound > 0.0 && s.lower_bound <= 0.01 + 1e-12, "{s:?}");
        assert!(s.lower_bound >= 0.01 * 0.998, "tight: {s:?}");
    }

    #[test]
    fn an_arc_is_checked_where_it_bends_not_along_its_chord() {
        // q(s) = 4s(1 − s): from 0 out to 1 at s = ½ and back; its chord never moves.
        let arc = JointCurve::Quadratic(&[0.0], &[2.0], &[0.0]);
        let hit = sweep_curve(&mut Line { c: 0.9, gap: 0.0 }, &arc, &SweepOptions::default()).unwrap();
        assert!(!hit.clear && (4.0 * hit.at * (1.0 - hit.at) - 0.9).abs() < 1e-5, "{hit:?}");
        let miss = sweep_curve(&mut Line { c: 1.05, gap: 0.0 }, &arc, &SweepOptions::default()).unwrap();
        assert!(miss.clear && (miss.min_clearance - 0.05).abs() < 1e-9 && (miss.at - 0.5).abs() < 1e-3, "{miss:?}");
        assert!(miss.lower_bound > 0.0 && miss.lower_bound <= 0.05, "{miss:?}");
        let chord = sweep(&mut Line { c: 0.9, gap: 0.0 }, &[0.0], &[0.0], &SweepOptions::default()).unwrap();
        assert!(chord.clear);
    }

    #[test]
    fn without_motion_or_constraints_nothing_moves() {
        let s = sweep(&mut Line { c: 2.0, gap: 0.5 }, &[0.0], &[0.0], &SweepOptions::default()).unwrap();
        assert!(s.clear && s.evaluations == 2 && (s.min_clearance - 1.5).abs() < 1e-12, "{s:?}");
        assert!(sweep(&mut Line { c: 2.0, gap: 0.5 }, &[0.0], &[f64::NAN], &SweepOptions::default()).is_err());
    }
}
