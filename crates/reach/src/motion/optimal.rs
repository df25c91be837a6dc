//! Time-optimal motion along a joint path under velocity and acceleration limits: TOPP-RA,
//! the reachability method of Pham & Pham ("A new approach to time-optimal path
//! parameterization based on reachability analysis", IEEE T-RO 2018), with every limit then
//! **proven** between the grid points, not only at them.
//!
//! # The path and the method
//!
//! A geometric path `q(s)`, `s ∈ [0, S]`, is a chain of cubic pieces ([`PiecewiseCubic`]):
//! a not-a-knot cubic spline through waypoints at uniform parameter `s = 0, 1/(n−1), …, 1`
//! (scipy's `CubicSpline` with its default boundary condition, the path toppra builds from
//! `SplineInterpolator(linspace(0, 1, n), waypoints)`), or the polyline through them. Along it
//! the motion is `ṡ(t)`; with `x = ṡ²` and `u = s̈`,
//! `q̇ = q′(s)·ṡ` and `q̈ = q′(s)·u + q″(s)·x`, so the limits `|q̇ⱼ| ≤ vⱼ`, `|q̈ⱼ| ≤ aⱼ` are
//! linear in `(u, x)` at each point. Each piece is cut into `points_per_piece` equal grid
//! intervals; on interval `i` the acceleration `uᵢ` is constant, so `x` is linear in `s`
//! (`xᵢ₊₁ = xᵢ + 2Δᵢuᵢ`). A backward pass computes the controllable sets (the `x` at each grid
//! point from which the end can be reached at rest, each a two-variable linear program solved
//! exactly); a forward pass from rest takes the largest `u` that stays controllable. A
//! polyline's corners, where `q′` jumps, are passed at rest.
//!
//! # Proven within limits
//!
//! The method enforces the limits at the grid points. Between them, on one interval inside one
//! cubic piece, `q̈ⱼ(s) = q′ⱼ(s)·u + q″ⱼ(s)·x(s)` is a quadratic in `s`: its largest magnitude
//! is found exactly (end points and vertex). `|q̇ⱼ|² = q′ⱼ(s)²·x(s)` has its extrema where
//! `q̈ⱼ = 0` (`d(q̇²)/dt = 2q̇q̈`), the roots of that quadratic: the largest speed is exact too.
//! When a ratio to a limit exceeds 1 (the collocation's gap between grid points, a small
//! fraction of a percent at the default grid), the whole motion is slowed by the factor
//! `k = max(1, ρᵥ, √ρₐ)` — uniform time scaling divides speeds by `k` and accelerations by
//! `k²` — so the result is within every limit everywhere; [`OptimalMotion::worst_ratios`]
//! reports the exact worst ratio of each joint after scaling.

use serde::Serialize;

use super::{MotionError, check_number, check_vector};

/// Most grid points a parameterisation may use (`pieces × points_per_piece + 1`).
pub const MAX_GRID_POINTS: usize = 1_000_000;

/// Grid intervals per cubic piece when the caller does not choose, for paths of up to
/// [`DEFAULT_GRID_INTERVALS`]` / 64` pieces.
pub const DEFAULT_POINTS_PER_PIECE: usize = 64;

/// Grid size the default aims at on long (densely sampled) paths: their pieces get
/// `DEFAULT_GRID_INTERVALS / pieces` intervals each, but never fewer than
/// [`MIN_DEFAULT_POINTS_PER_PIECE`].
pub const DEFAULT_GRID_INTERVALS: usize = 4096;

/// Fewest grid intervals per piece the default gives.
pub const MIN_DEFAULT_POINTS_PER_PIECE: usize = 8;

/// Largest `ṡ²` the method considers: bounds the linear programs where no limit binds (a
/// point of the path where every joint rests).
const X_CAP: f64 = 1e12;

/// A joint path made of cubic pieces: piece `k` covers `[sₖ, sₖ₊₁]` and joint `j` moves as
/// `c₀ + c₁t + c₂t² + c₃t³` in the local parameter `t = s − sₖ`.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseCubic {
    /// The pieces' ends `s₀ = 0 < s₁ < … < sₙ = S`.
    pub(super) knots: Vec<f64>,
    /// The parameter at which the path passes each waypoint it was built from (a blended
    /// corner: the middle of its blend, the point closest to the waypoint).
    pub(super) marks: Vec<f64>,
    /// `coeffs[k][j] = [c₀, c₁, c₂, c₃]` of piece `k`, joint `j`.
    pub(super) coeffs: Vec<Vec<[f64; 4]>>,
    /// Whether the path's tangent jumps at the start of piece `k` (a polyline's corner): the
    /// motion must rest there.
    pub(super) corner: Vec<bool>,
}

fn check_waypoints(waypoints: &[Vec<f64>]) -> Result<usize, MotionError> {
    if waypoints.len() < 2 {
        return Err(MotionError::InvalidInput {
            field: "waypoints".into(),
            reason: format!("needs at least 2 joint vectors, got {}", waypoints.len()),
        });
    }
    let dof = waypoints[0].len();
    if dof == 0 {
        return Err(MotionError::InvalidInput { field: "waypoints".into(), reason: "have no joints".into() });
    }
    for (i, w) in waypoints.iter().enumerate() {
        check_vector(&format!("waypoint {}", i + 1), w, dof)?;
    }
    Ok(dof)
}

impl PiecewiseCubic {
    /// The not-a-knot cubic spline through `waypoints` (one joint vector each, SI units) at
    /// uniform parameter over `[0, 1]`: twice continuously differentiable, with a continuous
    /// third derivative at the second and the last-but-one waypoint. Two waypoints give the
    /// straight line, three the parabola through them (as scipy's `CubicSpline`).
    ///
    /// # Errors
    /// [`MotionError`] for fewer than two waypoints, rows of different lengths, or a NaN or
    /// infinite value (naming the waypoint, 1-based).
    pub fn spline(waypoints: &[Vec<f64>]) -> Result<Self, MotionError> {
        let dof = check_waypoints(waypoints)?;
        let n = waypoints.len();
        let h = 1.0 / (n - 1) as f64;
        let mut coeffs = vec![vec![[0.0; 4]; dof]; n - 1];
        let mut m = vec![0.0; n];
        for j in 0..dof {
            let y: Vec<f64> = waypoints.iter().map(|w| w[j]).collect();
            second_derivatives(&y, h, &mut m);
            for k in 0..n - 1 {
                let slope = (y[k + 1] - y[k]) / h;
                coeffs[k][j] =
                    [y[k], slope - h * (2.0 * m[k] + m[k + 1]) / 6.0, m[k] / 2.0, (m[k + 1] - m[k]) / (6.0 * h)];
            }
        }
        let knots = uniform_knots(n, h);
        Ok(PiecewiseCubic { marks: knots.clone(), knots, coeffs, corner: vec![false; n - 1] })
    }

    /// The polyline through `waypoints` at uniform parameter over `[0, 1]`; the motion rests
    /// at every interior waypoint where the direction changes.
    ///
    /// # Errors
    /// As [`PiecewiseCubic::spline`].
    pub fn polyline(waypoints: &[Vec<f64>]) -> Result<Self, MotionError> {
        let dof = check_waypoints(waypoints)?;
        let n = waypoints.len();
        let h = 1.0 / (n - 1) as f64;
        let coeffs: Vec<Vec<[f64; 4]>> = waypoints
            .windows(2)
            .map(|w| (0..dof).map(|j| [w[0][j], (w[1][j] - w[0][j]) / h, 0.0, 0.0]).collect())
            .collect();
        let corner = (0..n - 1)
            .map(|k| {
                k > 0 && {
                    let (a, b) = (&coeffs[k - 1], &coeffs[k]);
                    // Parallel and same sense: no corner (compare the directions exactly up
                    // to rounding of the slopes).
                    let dot: f64 = (0..dof).map(|j| a[j][1] * b[j][1]).sum();
                    let na: f64 = (0..dof).map(|j| a[j][1] * a[j][1]).sum::<f64>().sqrt();
                    let nb: f64 = (0..dof).map(|j| b[j][1] * b[j][1]).sum::<f64>().sqrt();
                    !(dot > 0.0 && (dot - na * nb).abs() <= 1e-12 * na * nb)
                }
            })
            .collect();
        let knots = uniform_knots(n, h);
        Ok(PiecewiseCubic { marks: knots.clone(), knots, coeffs, corner })
    }

    /// The polyline through `waypoints` with every corner cut by a parabolic blend that stays
    /// within `tolerance` of the corner (joint-space Euclidean distance, rad and m as in
    /// [`crate::world::planner::path_length`]; MoveIt's `path_tolerance`), parameterised by
    /// joint-space arc length on the straight parts, so the motion need not stop at a corner.
    ///
    /// At a corner `w` between the unit directions `d₁` (in) and `d₂` (out), the blend leaves
    /// the first segment at `w − L·d₁` and joins the second at `w + L·d₂`:
    /// `q(t) = w − L·d₁ + t·d₁ + t²·(d₂ − d₁)/(4L)`, `t ∈ [0, 2L]` — the quadratic arc (Bézier)
    /// with control points `w − L·d₁`, `w`, `w + L·d₂`, tangent to both segments, whose point
    /// farthest from `w` is its middle, at `L·|d₂ − d₁|/4`. So
    /// `L = min(4·tolerance/|d₂ − d₁|, ℓ₁/2, ℓ₂/2)` (`ℓ`: the segments' lengths, shared by
    /// the blends at their ends). The path is continuously differentiable; tolerance 0 gives
    /// the polyline, resting at each corner. Repeated waypoints are passed once.
    ///
    /// # Errors
    /// As [`PiecewiseCubic::spline`]; [`MotionError::InvalidInput`] for a tolerance that is
    /// not finite and ≥ 0, or waypoints that are all one configuration.
    pub fn blended(waypoints: &[Vec<f64>], tolerance: f64) -> Result<Self, MotionError> {
        let dof = check_waypoints(waypoints)?;
        check_blend_tolerance(tolerance)?;
        // The distinct corners, and for each waypoint the corner it is.
        let mut points: Vec<&[f64]> = vec![&waypoints[0]];
        let mut corner_of = vec![0usize];
        for w in &waypoints[1..] {
            let last = points[points.len() - 1];
            if distance(last, w) > SAME_POINT {
                points.push(w);
            }
            corner_of.push(points.len() - 1);
        }
        if points.len() < 2 {
            return Err(MotionError::InvalidInput {
                field: "waypoints".into(),
                reason: "are all one configuration: there is no path to time".into(),
            });
        }
        let m = points.len();
        let lengths: Vec<f64> = points.windows(2).map(|w| distance(w[0], w[1])).collect();
        let directions: Vec<Vec<f64>> =
            points.windows(2).zip(&lengths).map(|(w, l)| (0..dof).map(|j| (w[1][j] - w[0][j]) / l).collect()).collect();
        // Blend half-lengths per corner (0 at the ends), and whether an unblended corner turns.
        let mut half = vec![0.0; m];
        let mut turns = vec![false; m];
        for c in 1..m - 1 {
            let turn = distance(&directions[c - 1], &directions[c]);
            turns[c] = turn > SAME_DIRECTION;
            if turns[c] && tolerance > 0.0 {
                half[c] = (4.0 * tolerance / turn).min(lengths[c - 1] / 2.0).min(lengths[c] / 2.0);
            }
        }
        let mut knots = vec![0.0];
        let mut coeffs = Vec::new();
        let mut corner = Vec::new();
        let mut corner_at = vec![0.0; m];
        let mut push = |piece: Vec<[f64; 4]>, len: f64, rest: bool, knots: &mut Vec<f64>| {
            knots.push(knots[knots.len() - 1] + len);
            coeffs.push(piece);
            corner.push(rest);
        };
        for i in 0..m - 1 {
            let (d, l) = (&directions[i], lengths[i]);
            let line = l - half[i] - half[i + 1];
            // A corner passed without a blend is a rest point at the start of this segment.
            let rest = turns[i] && half[i] == 0.0;
            if line > SAME_POINT * l.max(1.0) || half[i + 1] == 0.0 {
                let start: Vec<f64> = (0..dof).map(|j| points[i][j] + half[i] * d[j]).collect();
                push((0..dof).map(|j| [start[j], d[j], 0.0, 0.0]).collect(), line.max(0.0), rest, &mut knots);
            }
            let s_end = knots[knots.len() - 1];
            if half[i + 1] > 0.0 {
                let (big_l, next) = (half[i + 1], &directions[i + 1]);
                corner_at[i + 1] = s_end + big_l;
                let piece = (0..dof)
                    .map(|j| [points[i + 1][j] - big_l * d[j], d[j], (next[j] - d[j]) / (4.0 * big_l), 0.0])
                    .collect();
                push(piece, 2.0 * big_l, false, &mut knots);
            } else {
                corner_at[i + 1] = s_end;
            }
        }
        let marks = corner_of.iter().map(|&c| corner_at[c]).collect();
        Ok(PiecewiseCubic { knots, marks, coeffs, corner })
    }

    /// Each piece as the control points of a straight line (2) or a quadratic arc (3, the
    /// Bézier form: ends and the intersection of the end tangents), for the swept collision
    /// check ([`crate::world::sweep::JointCurve`]): the pieces of a polyline or a blended path.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] when a piece is a true cubic (a spline's): the swept
    /// check takes lines and arcs.
    pub fn control_points(&self) -> Result<Vec<Vec<Vec<f64>>>, MotionError> {
        self.coeffs
            .iter()
            .enumerate()
            .map(|(k, piece)| {
                let len = self.knots[k + 1] - self.knots[k];
                let end = || piece.iter().map(|c| c[0] + len * (c[1] + len * (c[2] + len * c[3]))).collect();
                let start = piece.iter().map(|c| c[0]).collect();
                if piece.iter().any(|c| c[3] != 0.0) {
                    Err(MotionError::InvalidInput {
                        field: "path".into(),
                        reason: format!("piece {} is a cubic: only lines and quadratic arcs can be swept", k + 1),
                    })
                } else if piece.iter().all(|c| c[2] == 0.0) {
                    Ok(vec![start, end()])
                } else {
                    Ok(vec![start, piece.iter().map(|c| c[0] + 0.5 * len * c[1]).collect(), end()])
                }
            })
            .collect()
    }

    /// Number of joints.
    #[must_use]
    pub fn dof(&self) -> usize {
        self.coeffs[0].len()
    }

    /// Number of cubic pieces.
    #[must_use]
    pub fn pieces(&self) -> usize {
        self.coeffs.len()
    }

    /// Parameter length `S`: 1 for [`PiecewiseCubic::spline`] and
    /// [`PiecewiseCubic::polyline`], the joint-space arc length for
    /// [`PiecewiseCubic::blended`].
    #[must_use]
    pub fn length(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// The 0-based waypoint that piece `k` starts at or after (the segment it lies on).
    #[must_use]
    pub fn waypoint_of_piece(&self, k: usize) -> usize {
        let start = self.knots[k.min(self.coeffs.len() - 1)];
        self.marks.partition_point(|m| *m <= start).saturating_sub(1).min(self.marks.len().saturating_sub(2))
    }

    /// Parameter length of piece `k`.
    pub(super) fn piece_length(&self, k: usize) -> f64 {
        self.knots[k + 1] - self.knots[k]
    }

    /// The smallest and the largest value joint `j` takes along the whole path (exact: the
    /// cubics' ends and the roots of their derivatives), each with the 0-based piece where it
    /// is reached.
    #[must_use]
    pub fn joint_range(&self, j: usize) -> ((f64, usize), (f64, usize)) {
        let (mut low, mut high) = ((f64::INFINITY, 0), (f64::NEG_INFINITY, 0));
        let mut roots = Vec::new();
        for (k, piece) in self.coeffs.iter().enumerate() {
            let [c0, c1, c2, c3] = piece[j];
            let len = self.piece_length(k);
            roots_in([c1, 2.0 * c2, 3.0 * c3], len, &mut roots);
            for t in [0.0, len].iter().chain(&roots) {
                let q = c0 + t * (c1 + t * (c2 + t * c3));
                if q < low.0 {
                    low = (q, k);
                }
                if q > high.0 {
                    high = (q, k);
                }
            }
        }
        (low, high)
    }

    /// `(piece, local parameter)` of `s` (clamped to the path).
    pub(super) fn locate(&self, s: f64) -> (usize, f64) {
        let last = self.coeffs.len() - 1;
        let k = self.knots[1..].partition_point(|x| *x <= s).min(last);
        (k, (s - self.knots[k]).clamp(0.0, self.piece_length(k)))
    }

    /// Joint values, first and second derivatives with respect to `s` at `s` (clamped).
    #[must_use]
    pub fn eval(&self, s: f64) -> [Vec<f64>; 3] {
        let (k, t) = self.locate(s);
        self.eval_in(k, t)
    }

    pub(super) fn eval_in(&self, k: usize, t: f64) -> [Vec<f64>; 3] {
        let c = &self.coeffs[k];
        [
            c.iter().map(|c| c[0] + t * (c[1] + t * (c[2] + t * c[3]))).collect(),
            c.iter().map(|c| c[1] + t * (2.0 * c[2] + 3.0 * t * c[3])).collect(),
            c.iter().map(|c| 2.0 * c[2] + 6.0 * t * c[3]).collect(),
        ]
    }
}

/// Joint-space distance (rad / m) at or below which two waypoints are one.
const SAME_POINT: f64 = 1e-12;

/// Distance between unit directions at or below which a corner does not turn.
const SAME_DIRECTION: f64 = 1e-12;

/// Checks a blend tolerance ([`PiecewiseCubic::blended`]): finite and ≥ 0.
///
/// # Errors
/// [`MotionError::InvalidInput`] naming `blend_tolerance`.
pub fn check_blend_tolerance(tolerance: f64) -> Result<(), MotionError> {
    check_number("blend_tolerance", tolerance, false)?;
    if tolerance < 0.0 {
        return Err(MotionError::InvalidInput {
            field: "blend_tolerance".into(),
            reason: format!("must be ≥ 0 (rad), got {tolerance}"),
        });
    }
    Ok(())
}

/// Euclidean distance between two joint vectors.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (y - x) * (y - x)).sum::<f64>().sqrt()
}

/// `0, h, 2h, …` (`n` values).
fn uniform_knots(n: usize, h: f64) -> Vec<f64> {
    (0..n).map(|k| k as f64 * h).collect()
}

/// The second derivatives `m` of the not-a-knot spline through `y` at spacing `h`.
///
/// Interior rows `mᵢ₋₁ + 4mᵢ + mᵢ₊₁ = rᵢ = 6(yᵢ₊₁ − 2yᵢ + yᵢ₋₁)/h²`; not-a-knot makes the
/// third derivative continuous at knots 1 and n−2: `m₀ − 2m₁ + m₂ = 0` (and its mirror), which
/// substituted into row 1 gives `m₁ = r₁/6` (and `mₙ₋₂ = rₙ₋₂/6`). The rows in between are
/// tridiagonal (Thomas algorithm, diagonally dominant); `m₀`, `mₙ₋₁` follow linearly.
fn second_derivatives(y: &[f64], h: f64, m: &mut [f64]) {
    let n = y.len();
    let r = |i: usize| 6.0 * (y[i + 1] - 2.0 * y[i] + y[i - 1]) / (h * h);
    match n {
        2 => m.fill(0.0),
        3 => m.fill(r(1) / 6.0),
        _ => {
            m[1] = r(1) / 6.0;
            m[n - 2] = r(n - 2) / 6.0;
            // Unknowns m[2..=n-3]: rows i = 2..=n-3, m[1] and m[n-2] known.
            let (lo, hi) = (2, n - 3);
            if lo <= hi {
                let count = hi - lo + 1;
                let mut c_prime = vec![0.0; count];
                let mut d_prime = vec![0.0; count];
                for (idx, i) in (lo..=hi).enumerate() {
                    let mut d = r(i);
                    if i == lo {
                        d -= m[1];
                    }
                    if i == hi {
                        d -= m[n - 2];
                    }
                    let (sub, sup) = (if idx == 0 { 0.0 } else { 1.0 }, if i == hi { 0.0 } else { 1.0 });
                    let denom = 4.0 - sub * if idx == 0 { 0.0 } else { c_prime[idx - 1] };
                    c_prime[idx] = sup / denom;
                    d_prime[idx] = (d - sub * if idx == 0 { 0.0 } else { d_prime[idx - 1] }) / denom;
                }
                for idx in (0..count).rev() {
                    let next = if idx + 1 < count { m[lo + idx + 1] } else { 0.0 };
                    m[lo + idx] = d_prime[idx] - c_prime[idx] * next;
                }
            }
            m[0] = 2.0 * m[1] - m[2];
            m[n - 1] = 2.0 * m[n - 2] - m[n - 3];
        }
    }
}

/// Symmetric per-joint limits for [`time_optimal`]: `|q̇ⱼ| ≤ velocity[j]`,
/// `|q̈ⱼ| ≤ acceleration[j]` (rad/s, rad/s²; m/s, m/s² for prismatic joints).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PathLimits {
    /// Largest speed of each joint, > 0.
    pub velocity: Vec<f64>,
    /// Largest acceleration of each joint, > 0.
    pub acceleration: Vec<f64>,
}

impl PathLimits {
    /// Explicit limits.
    ///
    /// # Errors
    /// [`MotionError`] for a limit that is not a finite number > 0 (named `velocity[j]` or
    /// `acceleration[j]`, 1-based) or vectors of different lengths.
    pub fn new(velocity: Vec<f64>, acceleration: Vec<f64>) -> Result<Self, MotionError> {
        if acceleration.len() != velocity.len() {
            return Err(MotionError::Length {
                field: "acceleration".into(),
                expected: velocity.len(),
                found: acceleration.len(),
            });
        }
        for (name, values) in [("velocity", &velocity), ("acceleration", &acceleration)] {
            for (i, v) in values.iter().enumerate() {
                check_number(&format!("{name}[{}]", i + 1), *v, true)?;
            }
        }
        Ok(PathLimits { velocity, acceleration })
    }

    /// The robot's `max_velocity` and `max_acceleration` — for a joint with a stepper drive the
    /// tighter of them and the motor's ([`crate::model::Joint::drive_limits`]), so the step
    /// schedule of the motion stays within the motor's rate and ramp — each multiplied by its
    /// scale (MoveIt's `max_velocity_scaling_factor` / `max_acceleration_scaling_factor`, in
    /// `(0, 1]`).
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] naming the first joint without a limit, or a scale
    /// outside `(0, 1]`.
    pub fn from_robot(
        robot: &crate::model::Robot,
        velocity_scale: f64,
        acceleration_scale: f64,
    ) -> Result<Self, MotionError> {
        for (name, scale) in [("max_velocity_scale", velocity_scale), ("max_acceleration_scale", acceleration_scale)] {
            check_number(name, scale, true)?;
            if scale > 1.0 {
                return Err(MotionError::InvalidInput {
                    field: name.into(),
                    reason: format!("must be ≤ 1, got {scale}"),
                });
            }
        }
        let mut velocity = Vec::with_capacity(robot.dof());
        let mut acceleration = Vec::with_capacity(robot.dof());
        for (i, joint) in robot.joints().iter().enumerate() {
            let missing = |field: &str| MotionError::InvalidInput {
                field: format!("joint {} ({}) {field}", i + 1, joint.name),
                reason: "is not given in the robot description, nor by the joint's stepper drive: add it to \
                         the joint in the TOML file, or give a URDF a MoveIt joint_limits.yaml (--joint-limits)"
                    .into(),
            };
            let (drive_velocity, drive_acceleration) = joint.drive_limits();
            let tighter = |a: Option<f64>, b: Option<f64>| match (a, b) {
                (Some(a), Some(b)) => Some(a.min(b)),
                (a, b) => a.or(b),
            };
            velocity.push(
                tighter(joint.max_velocity, drive_velocity).ok_or_else(|| missing("max_velocity"))? * velocity_scale,
            );
            acceleration.push(
                tighter(joint.max_acceleration, drive_acceleration).ok_or_else(|| missing("max_acceleration"))?
                    * acceleration_scale,
            );
        }
        PathLimits::new(velocity, acceleration)
    }
}

/// The worst ratio of each joint's speed and acceleration to its limit over the whole motion
/// (exact maxima between grid points; ≤ 1 for a result of [`time_optimal`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitRatios {
    /// `max |q̇ⱼ| / vⱼ` per joint.
    pub velocity: Vec<f64>,
    /// `max |q̈ⱼ| / aⱼ` per joint.
    pub acceleration: Vec<f64>,
}

/// A time-optimal motion along a [`PiecewiseCubic`] path.
#[derive(Debug, Clone)]
pub struct OptimalMotion {
    pub(super) path: PiecewiseCubic,
    /// Grid parameter values.
    pub(super) s: Vec<f64>,
    /// `ṡ²` at each grid point.
    pub(super) x: Vec<f64>,
    /// `s̈` on each grid interval.
    pub(super) u: Vec<f64>,
    /// Time at each grid point.
    pub(super) t: Vec<f64>,
    /// Piece of each grid interval.
    pub(super) piece: Vec<usize>,
    ratios: LimitRatios,
    slowdown: f64,
}

/// One sample of a timed motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MotionSample {
    /// Time, s.
    pub t: f64,
    /// Joint values (rad / m).
    pub q: Vec<f64>,
    /// Joint speeds (rad/s / m/s).
    pub qd: Vec<f64>,
    /// Joint accelerations (rad/s² / m/s²).
    pub qdd: Vec<f64>,
}

/// A linear constraint `a·u + b·x ≤ c` of one grid point's program.
#[derive(Debug, Clone, Copy)]
struct Row {
    a: f64,
    b: f64,
    c: f64,
}

/// Path derivatives of one grid interval, flat (`dof` values each): `q′`, `q″` at its start
/// and (from the same piece, a left limit) at its end.
struct IntervalDerivatives {
    dof: usize,
    d0: Vec<f64>,
    dd0: Vec<f64>,
    d1: Vec<f64>,
    dd1: Vec<f64>,
}

impl IntervalDerivatives {
    fn get(&self, i: usize) -> [&[f64]; 4] {
        let r = i * self.dof..(i + 1) * self.dof;
        [&self.d0[r.clone()], &self.dd0[r.clone()], &self.d1[r.clone()], &self.dd1[r]]
    }
}

/// The rows of interval `i`'s program in `(u, x)` with `x = ṡ²` at its start and `u` its
/// constant `s̈` (first-order interpolation, Pham & Pham §V): the acceleration limits at both
/// ends (at the end `x + 2Δu`), the speed limits at both ends, the next point's controllable
/// set `[0, next_hi]`, and `0 ≤ x ≤ X_CAP`.
fn interval_rows(derivs: [&[f64]; 4], delta: f64, next_hi: f64, limits: &PathLimits, rows: &mut Vec<Row>) {
    let [d0, dd0, d1, dd1] = derivs;
    rows.clear();
    let (mut x0_max, mut x1_max) = (X_CAP, next_hi);
    for j in 0..d0.len() {
        let a = limits.acceleration[j];
        rows.push(Row { a: d0[j], b: dd0[j], c: a });
        rows.push(Row { a: -d0[j], b: -dd0[j], c: a });
        let end = d1[j] + 2.0 * delta * dd1[j];
        rows.push(Row { a: end, b: dd1[j], c: a });
        rows.push(Row { a: -end, b: -dd1[j], c: a });
        let v = limits.velocity[j];
        if d0[j] != 0.0 {
            x0_max = x0_max.min((v / d0[j]).powi(2));
        }
        if d1[j] != 0.0 {
            x1_max = x1_max.min((v / d1[j]).powi(2));
        }
    }
    rows.push(Row { a: 0.0, b: 1.0, c: x0_max });
    rows.push(Row { a: 0.0, b: -1.0, c: 0.0 });
    // 0 ≤ x + 2Δu ≤ min(next_hi, end speed bound)
    rows.push(Row { a: 2.0 * delta, b: 1.0, c: x1_max });
    rows.push(Row { a: -2.0 * delta, b: -1.0, c: 0.0 });
}

/// The interval of `u` the rows allow at a given `x` (empty when `lo > hi`).
fn u_range(rows: &[Row], x: f64) -> (f64, f64, usize, usize) {
    let (mut lo, mut hi, mut lo_at, mut hi_at) = (f64::NEG_INFINITY, f64::INFINITY, usize::MAX, usize::MAX);
    for (k, r) in rows.iter().enumerate() {
        if r.a > 0.0 {
            let bound = (r.c - r.b * x) / r.a;
            if bound < hi {
                (hi, hi_at) = (bound, k);
            }
        } else if r.a < 0.0 {
            let bound = (r.c - r.b * x) / r.a;
            if bound > lo {
                (lo, lo_at) = (bound, k);
            }
        }
    }
    (lo, hi, lo_at, hi_at)
}

/// The largest `x` of the polygon `rows` (which contains `(0, 0)`).
///
/// `g(x) = hi(x) − lo(x)` of [`u_range`] is concave and piecewise linear with `g(0) ≥ 0`; from
/// the largest `x` the rows without `u` allow, each step moves to the root of the active
/// pieces' line, which is never below the true root (concavity): a finite descent onto it.
/// Should it not settle within 64 steps (degenerate rows), the polygon's vertices decide.
fn largest_x(rows: &[Row]) -> f64 {
    let mut x = rows.iter().filter(|r| r.a == 0.0 && r.b > 0.0).map(|r| r.c / r.b).fold(X_CAP, f64::min);
    for _ in 0..64 {
        let (lo, hi, lo_at, hi_at) = u_range(rows, x);
        if hi - lo >= -1e-12 * (lo.abs() + hi.abs()) || lo_at == usize::MAX || hi_at == usize::MAX {
            return x.max(0.0);
        }
        let (p, q) = (rows[hi_at], rows[lo_at]);
        // (c_p − b_p x)/a_p = (c_q − b_q x)/a_q
        let next = (p.c / p.a - q.c / q.a) / (p.b / p.a - q.b / q.a);
        if !(next.is_finite() && next < x) {
            break;
        }
        x = next;
        if x <= 0.0 {
            return 0.0;
        }
    }
    x_range(rows).map_or(0.0, |(_, hi)| hi.max(0.0))
}

/// Smallest and largest `x` over the polygon `rows` in `(u, x)`, by its vertices (each
/// checked against every row to a relative 1e-9); `None` when the polygon is empty.
fn x_range(rows: &[Row]) -> Option<(f64, f64)> {
    let feasible = |u: f64, x: f64| {
        rows.iter().all(|r| r.a * u + r.b * x - r.c <= 1e-9 * (r.c.abs() + (r.a * u).abs() + (r.b * x).abs()))
    };
    let mut range: Option<(f64, f64)> = None;
    for (i, p) in rows.iter().enumerate() {
        for q in &rows[i + 1..] {
            let det = p.a * q.b - p.b * q.a;
            if det.abs() <= 1e-14 * (p.a.abs() + p.b.abs()) * (q.a.abs() + q.b.abs()) {
                continue;
            }
            let u = (p.c * q.b - p.b * q.c) / det;
            let x = (p.a * q.c - p.c * q.a) / det;
            if x.is_finite() && u.is_finite() && feasible(u, x) {
                range = Some(range.map_or((x, x), |(lo, hi)| (lo.min(x), hi.max(x))));
            }
        }
    }
    range
}

/// Times `path` under `limits`, starting and ending at rest, with `points_per_piece` grid
/// intervals per cubic piece (0: [`DEFAULT_POINTS_PER_PIECE`], fewer on long paths — see
/// [`DEFAULT_GRID_INTERVALS`]). The grid's size changes how close to time-optimal the result
/// is, never whether it is within the limits.
///
/// # Errors
/// [`MotionError`] when the limits do not have one value per joint or the grid would exceed
/// [`MAX_GRID_POINTS`].
pub fn time_optimal(
    path: &PiecewiseCubic,
    limits: &PathLimits,
    points_per_piece: usize,
) -> Result<OptimalMotion, MotionError> {
    let dof = path.dof();
    if limits.velocity.len() != dof {
        return Err(MotionError::Length { field: "limits".into(), expected: dof, found: limits.velocity.len() });
    }
    let per = if points_per_piece == 0 {
        (DEFAULT_GRID_INTERVALS / path.pieces().max(1)).clamp(MIN_DEFAULT_POINTS_PER_PIECE, DEFAULT_POINTS_PER_PIECE)
    } else {
        points_per_piece
    };
    let n_int =
        path.pieces().checked_mul(per).filter(|n| *n < MAX_GRID_POINTS).ok_or_else(|| MotionError::InvalidInput {
            field: "points_per_piece".into(),
            reason: format!(
                "{} pieces × {per} points per piece exceed the cap of {MAX_GRID_POINTS} grid points",
                path.pieces()
            ),
        })?;

    let mut s = Vec::with_capacity(n_int + 1);
    let mut piece = Vec::with_capacity(n_int);
    let mut derivs = IntervalDerivatives {
        dof,
        d0: Vec::with_capacity(n_int * dof),
        dd0: Vec::with_capacity(n_int * dof),
        d1: Vec::with_capacity(n_int * dof),
        dd1: Vec::with_capacity(n_int * dof),
    };
    for (k, coeffs) in path.coeffs.iter().enumerate() {
        let step = path.piece_length(k) / per as f64;
        for i in 0..per {
            let (t0, t1) = (i as f64 * step, (i + 1) as f64 * step);
            s.push(path.knots[k] + t0);
            piece.push(k);
            for c in coeffs {
                derivs.d0.push(c[1] + t0 * (2.0 * c[2] + 3.0 * t0 * c[3]));
                derivs.dd0.push(2.0 * c[2] + 6.0 * t0 * c[3]);
                derivs.d1.push(c[1] + t1 * (2.0 * c[2] + 3.0 * t1 * c[3]));
                derivs.dd1.push(2.0 * c[2] + 6.0 * t1 * c[3]);
            }
        }
    }
    s.push(path.length());
    // At rest at the corners and the ends.
    let rest: Vec<bool> = (0..=n_int).map(|i| i == 0 || i == n_int || (i % per == 0 && path.corner[i / per])).collect();

    // Backward pass: the controllable sets are [0, hi] (rest is always controllable).
    let mut hi = vec![0.0; n_int + 1];
    let mut rows = Vec::with_capacity(4 * dof + 4);
    for i in (0..n_int).rev() {
        if rest[i] && i != 0 {
            continue;
        }
        interval_rows(derivs.get(i), s[i + 1] - s[i], hi[i + 1], limits, &mut rows);
        hi[i] = if rest[i] { 0.0 } else { largest_x(&rows) };
    }

    // Forward pass from rest: the largest u that stays controllable.
    let mut x = vec![0.0; n_int + 1];
    let mut u = vec![0.0; n_int];
    for i in 0..n_int {
        let delta = s[i + 1] - s[i];
        interval_rows(derivs.get(i), delta, hi[i + 1], limits, &mut rows);
        let (u_lo, u_hi, ..) = u_range(&rows, x[i]);
        let ui = u_hi.max(u_lo.min(u_hi));
        x[i + 1] = (x[i] + 2.0 * delta * ui).clamp(0.0, hi[i + 1]);
        u[i] = (x[i + 1] - x[i]) / (2.0 * delta);
    }

    let mut motion = OptimalMotion {
        path: path.clone(),
        s,
        x,
        u,
        t: Vec::new(),
        piece,
        ratios: LimitRatios { velocity: vec![], acceleration: vec![] },
        slowdown: 1.0,
    };
    let ratios = motion.exact_ratios(limits);
    let worst_v = ratios.velocity.iter().copied().fold(0.0, f64::max);
    let worst_a = ratios.acceleration.iter().copied().fold(0.0, f64::max);
    let k = worst_v.max(worst_a.sqrt());
    if k > 1.0 {
        let k = k * (1.0 + 1e-12);
        motion.slowdown = k;
        let k2 = k * k;
        motion.x.iter_mut().for_each(|x| *x /= k2);
        motion.u.iter_mut().for_each(|u| *u /= k2);
        motion.ratios = motion.exact_ratios(limits);
    } else {
        motion.ratios = ratios;
    }
    motion.t = times(&motion.s, &motion.x);
    Ok(motion)
}

/// Grid times: `Δtᵢ = 2Δᵢ / (√xᵢ + √xᵢ₊₁)` (constant `s̈` on the interval).
fn times(s: &[f64], x: &[f64]) -> Vec<f64> {
    let mut t = vec![0.0; s.len()];
    for i in 0..s.len() - 1 {
        let v = x[i].sqrt() + x[i + 1].sqrt();
        let dt = if v > 0.0 { 2.0 * (s[i + 1] - s[i]) / v } else { 0.0 };
        t[i + 1] = t[i] + dt;
    }
    t
}

/// Real roots of `c₀ + c₁z + c₂z²` inside `[0, len]`.
fn roots_in(c: [f64; 3], len: f64, out: &mut Vec<f64>) {
    out.clear();
    let [c0, c1, c2] = c;
    let scale = c0.abs().max(c1.abs() * len).max(c2.abs() * len * len);
    if scale == 0.0 {
        return;
    }
    if c2.abs() * len * len <= 1e-14 * scale {
        if c1 != 0.0 {
            out.push(-c0 / c1);
        }
    } else {
        let disc = c1 * c1 - 4.0 * c2 * c0;
        if disc >= 0.0 {
            let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
            out.push(q / c2);
            if q != 0.0 {
                out.push(c0 / q);
            }
        }
    }
    out.retain(|z| (0.0..=len).contains(z));
}

impl OptimalMotion {
    /// The exact largest ratios between grid points (module docs).
    fn exact_ratios(&self, limits: &PathLimits) -> LimitRatios {
        let dof = self.path.dof();
        let mut vel = vec![0.0f64; dof];
        let mut acc = vec![0.0f64; dof];
        let mut roots = Vec::new();
        for i in 0..self.u.len() {
            let k = self.piece[i];
            let t0 = self.s[i] - self.path.knots[k];
            let len = self.s[i + 1] - self.s[i];
            let (x0, u) = (self.x[i], self.u[i]);
            for j in 0..dof {
                let [_, c1, c2, c3] = self.path.coeffs[k][j];
                // In z = s − s_i: q′ = p0 + p1 z + p2 z², q″ = r0 + r1 z, x = x0 + 2u z.
                let p0 = c1 + t0 * (2.0 * c2 + 3.0 * t0 * c3);
                let p1 = 2.0 * c2 + 6.0 * t0 * c3;
                let p2 = 3.0 * c3;
                let (r0, r1) = (2.0 * c2 + 6.0 * t0 * c3, 6.0 * c3);
                // q̈ = u q′ + q″ x: a quadratic in z.
                let qdd = [u * p0 + r0 * x0, u * p1 + r0 * 2.0 * u + r1 * x0, u * p2 + r1 * 2.0 * u];
                let eval = |c: [f64; 3], z: f64| c[0] + z * (c[1] + z * c[2]);
                let speed = |z: f64| (p0 + z * (p1 + z * p2)).abs() * (x0 + 2.0 * u * z).max(0.0).sqrt();
                let mut candidates = vec![0.0, len];
                if qdd[2] != 0.0 {
                    let vertex = -qdd[1] / (2.0 * qdd[2]);
                    if (0.0..=len).contains(&vertex) {
                        candidates.push(vertex);
                    }
                }
                for z in &candidates {
                    acc[j] = acc[j].max(eval(qdd, *z).abs() / limits.acceleration[j]);
                }
                roots_in(qdd, len, &mut roots);
                for z in candidates.iter().chain(&roots) {
                    vel[j] = vel[j].max(speed(*z) / limits.velocity[j]);
                }
            }
        }
        LimitRatios { velocity: vel, acceleration: acc }
    }

    /// Duration, s.
    #[must_use]
    pub fn duration(&self) -> f64 {
        *self.t.last().unwrap_or(&0.0)
    }

    /// The exact worst ratio of each joint's speed and acceleration to its limit (≤ 1).
    #[must_use]
    pub fn worst_ratios(&self) -> &LimitRatios {
        &self.ratios
    }

    /// The uniform slow-down applied to close the gaps between grid points (1 when none).
    #[must_use]
    pub fn slowdown(&self) -> f64 {
        self.slowdown
    }

    /// The time at which the motion passes each waypoint the path was built from (a blended
    /// corner: the middle of its blend), from 0 to [`OptimalMotion::duration`].
    #[must_use]
    pub fn waypoint_times(&self) -> Vec<f64> {
        self.path.marks.iter().map(|&m| self.time_at(m)).collect()
    }

    /// The time at which the motion reaches the parameter `m` (clamped to the path).
    fn time_at(&self, m: f64) -> f64 {
        let i = self.s.partition_point(|s| *s <= m).saturating_sub(1).min(self.u.len() - 1);
        let delta = (m - self.s[i]).max(0.0);
        if delta == 0.0 {
            return self.t[i];
        }
        if m >= self.s[i + 1] {
            return self.t[i + 1];
        }
        // s − sᵢ = ṡᵢτ + ½uτ², solved for τ without cancellation.
        let sd0 = self.x[i].sqrt();
        let root = (sd0 * sd0 + 2.0 * self.u[i] * delta).max(0.0).sqrt();
        let tau = if sd0 + root > 0.0 { 2.0 * delta / (sd0 + root) } else { 0.0 };
        (self.t[i] + tau).min(self.t[i + 1])
    }

    /// Number of grid points.
    #[must_use]
    pub fn grid_points(&self) -> usize {
        self.s.len()
    }

    /// Position, speed and acceleration at time `t` (clamped to `[0, duration]`).
    #[must_use]
    pub fn sample(&self, t: f64) -> MotionSample {
        let t = t.clamp(0.0, self.duration());
        let i = self.t.partition_point(|ti| *ti <= t).saturating_sub(1).min(self.u.len() - 1);
        let tau = t - self.t[i];
        let (x0, u) = (self.x[i], self.u[i]);
        let sd0 = x0.sqrt();
        let s = (self.s[i] + sd0 * tau + 0.5 * u * tau * tau).clamp(self.s[i], self.s[i + 1]);
        // ṡ is linear in t under constant s̈ (no square root of a rounded x near rest).
        let sd = (sd0 + u * tau).clamp(0.0, self.x[i].max(self.x[i + 1]).sqrt());
        let k = self.piece[i];
        let [q, dq, ddq] = self.path.eval_in(k, s - self.path.knots[k]);
        let qd = dq.iter().map(|d| d * sd).collect();
        let qdd = dq.iter().zip(&ddq).map(|(d, dd)| d * u + dd * sd * sd).collect();
        MotionSample { t, q, qd, qdd }
    }

    /// Samples every `dt` seconds from 0, and the end; an end less than `dt / 2` after the
    /// last regular sample replaces it, so every interval lasts at least `dt / 2` (a drive
    /// differentiating the samples never divides by a sliver of time).
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for `dt` not finite and > 0, or more than
    /// [`MAX_GRID_POINTS`] samples.
    pub fn samples(&self, dt: f64) -> Result<Vec<MotionSample>, MotionError> {
        Ok(sample_times(self.duration(), dt)?.into_iter().map(|t| self.sample(t)).collect())
    }
}

/// The sample times of a motion of `duration` seconds: every `dt` from 0, and the end; an end
/// less than `dt / 2` after the last regular sample replaces it (the rule of
/// [`OptimalMotion::samples`]).
///
/// # Errors
/// [`MotionError::InvalidInput`] for `dt` not finite and > 0, or more than
/// [`MAX_GRID_POINTS`] samples.
pub(super) fn sample_times(duration: f64, dt: f64) -> Result<Vec<f64>, MotionError> {
    check_number("dt", dt, true)?;
    let count = (duration / dt).floor();
    if count >= MAX_GRID_POINTS as f64 {
        return Err(MotionError::InvalidInput {
            field: "dt".into(),
            reason: format!("{dt} s gives more than {MAX_GRID_POINTS} samples over {duration:.6} s"),
        });
    }
    let mut out: Vec<f64> = (0..=count as usize).map(|i| i as f64 * dt).collect();
    if out.len() > 1 && out.last().is_some_and(|t| duration - t < 0.5 * dt) {
        out.pop();
    }
    if out.last().is_none_or(|t| *t < duration) {
        out.push(duration);
    }
    Ok(out)
}
