//! Jerk-limited motion along a joint path: the time-optimal motion of [`super::optimal`]
//! smoothed so its jerk is bounded, then **proven** within velocity, acceleration and jerk
//! limits over the whole motion.
//!
//! # The smoothing pass
//!
//! The time-optimal law `s(t)` has a constant `s̈` on each grid interval, so its acceleration
//! jumps and its jerk is unbounded. Between two rests (the ends, and the corners of a
//! polyline) the law is replaced by its moving average over a window `T`:
//! `s_T(t) = (1/T)·∫ s(τ) dτ` over `[t − T, t]`, with `s` held at its rest values outside the
//! section. Then `ṡ_T` and `s̈_T` are the moving averages of `ṡ` and `s̈`, the section still
//! starts and ends at rest at the same points (one window later), and
//! `s⃛_T(t) = (s̈(t) − s̈(t − T)) / T` is piecewise constant: `s_T` is a cubic in `t` between the
//! grid times and the grid times shifted by `T`. Along the path
//! `q⃛ = q′·s⃛ + 3q″·ṡ·s̈ + q‴·ṡ³`, bounded wherever the path's curvature `q″` is continuous —
//! a spline, or straight segments resting at their corners, but not a parabolic blend, whose
//! curvature jumps where it meets a straight segment ([`jerk_limited`] refuses one).
//!
//! # Proven within limits
//!
//! On each interval of the smoothed law, interval arithmetic bounds `ṡ` (a quadratic in `t`:
//! ends and vertex), `s̈` (linear), `s⃛` (constant) and, over the interval's range of `s`,
//! each joint's `q′`, `q″`, `q‴` (the cubic pieces' derivatives: ends and vertex); the products
//! and sums above, taken with their signs, bound `q̇`, `q̈` and `q⃛` from above. The whole
//! motion is then time-scaled uniformly by the `k` that brings the largest of
//! `ρᵥ`, `√ρₐ`, `∛ρⱼ` to 1 (speeds divide by `k`, accelerations by `k²`, jerks by `k³`), so
//! every bound is ≤ 1 and the binding one is 1 — the motion may be faster than the smoothed
//! law where the smoothing left room. The window is chosen to minimise the resulting
//! duration (a scan over `T = D/2ᵉ`, refined by golden-section search in `log T`, `D` the
//! time-optimal duration). The reported ratios are these proven bounds, not sampled maxima.

use super::optimal::{
    LimitRatios, MotionSample, OptimalMotion, PathLimits, PiecewiseCubic, sample_times, time_optimal,
};
use super::{MotionError, check_number};

/// Largest number of windows the search tries (the coarse scan and the refinement).
const WINDOW_TRIES: usize = 13;
/// Golden-section refinements of the best window of the scan.
const WINDOW_REFINEMENTS: usize = 10;

/// The robot's `max_jerk` per joint (rad/s³; m/s³ for prismatic joints).
///
/// # Errors
/// [`MotionError::InvalidInput`] naming the first joint without one.
pub fn jerk_limits(robot: &crate::model::Robot) -> Result<Vec<f64>, MotionError> {
    robot
        .joints()
        .iter()
        .enumerate()
        .map(|(i, joint)| {
            joint.max_jerk.ok_or_else(|| MotionError::InvalidInput {
                field: format!("joint {} ({}) max_jerk", i + 1, joint.name),
                reason: "is not given in the robot description: add it to the joint in the TOML file, or give a \
                         URDF a MoveIt joint_limits.yaml (--joint-limits)"
                    .into(),
            })
        })
        .collect()
}

/// A closed interval `[lo, hi]` of interval arithmetic.
#[derive(Debug, Clone, Copy)]
struct Span {
    lo: f64,
    hi: f64,
}

impl Span {
    fn of(values: &[f64]) -> Span {
        values
            .iter()
            .fold(Span { lo: f64::INFINITY, hi: f64::NEG_INFINITY }, |r, &v| Span { lo: r.lo.min(v), hi: r.hi.max(v) })
    }

    fn point(v: f64) -> Span {
        Span { lo: v, hi: v }
    }

    fn union(self, o: Span) -> Span {
        Span { lo: self.lo.min(o.lo), hi: self.hi.max(o.hi) }
    }

    fn mul(self, o: Span) -> Span {
        Span::of(&[self.lo * o.lo, self.lo * o.hi, self.hi * o.lo, self.hi * o.hi])
    }

    fn add(self, o: Span) -> Span {
        Span { lo: self.lo + o.lo, hi: self.hi + o.hi }
    }

    fn scale(self, k: f64) -> Span {
        self.mul(Span::point(k))
    }

    fn magnitude(self) -> f64 {
        self.lo.abs().max(self.hi.abs())
    }
}

/// A time law `s(t)` with constant `s⃛` between breakpoints.
#[derive(Debug, Clone, Default)]
struct Law {
    /// Breakpoint times, from 0.
    t: Vec<f64>,
    /// `s`, `ṡ`, `s̈` at each breakpoint.
    s: Vec<f64>,
    sd: Vec<f64>,
    sdd: Vec<f64>,
    /// `s⃛` on each interval.
    jerk: Vec<f64>,
}

impl Law {
    fn duration(&self) -> f64 {
        *self.t.last().unwrap_or(&0.0)
    }

    /// The law uniformly slowed by `k` (`t → k·t`).
    fn scaled(&self, k: f64) -> Law {
        Law {
            t: self.t.iter().map(|t| t * k).collect(),
            s: self.s.clone(),
            sd: self.sd.iter().map(|v| v / k).collect(),
            sdd: self.sdd.iter().map(|a| a / (k * k)).collect(),
            jerk: self.jerk.iter().map(|j| j / (k * k * k)).collect(),
        }
    }

    /// `s`, `ṡ`, `s̈`, `s⃛` at time `t` (clamped).
    fn at(&self, t: f64) -> [f64; 4] {
        let n = self.jerk.len();
        let t = t.clamp(0.0, self.duration());
        let i = self.t.partition_point(|ti| *ti <= t).saturating_sub(1).min(n - 1);
        let tau = t - self.t[i];
        let (s0, v0, a0, j) = (self.s[i], self.sd[i], self.sdd[i], self.jerk[i]);
        let s = (s0 + tau * (v0 + tau * (0.5 * a0 + tau * j / 6.0))).clamp(s0, self.s[i + 1].max(s0));
        [s, (v0 + tau * (a0 + 0.5 * tau * j)).max(0.0), a0 + tau * j, j]
    }
}

/// The grid points where the time-optimal motion rests: its ends and a polyline's corners.
fn rests(base: &OptimalMotion) -> Vec<usize> {
    let n = base.u.len();
    (0..=n)
        .filter(|&i| i == 0 || i == n || (base.piece[i] != base.piece[i - 1] && base.path.corner[base.piece[i]]))
        .collect()
}

/// The moving average of `base`'s law over `window` seconds, section by section between
/// its rests (module docs).
fn smoothed(base: &OptimalMotion, sections: &[usize], window: f64) -> Law {
    let mut law = Law { t: vec![0.0], s: vec![base.s[0]], sd: vec![0.0], sdd: vec![0.0], jerk: Vec::new() };
    for pair in sections.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let origin = base.t[a];
        let times: Vec<f64> = base.t[a..=b].iter().map(|t| t - origin).collect();
        let end = times[times.len() - 1];
        // s̈ of the time-optimal law at local time τ (0 outside the section).
        let accel = |tau: f64, at: &mut usize| -> f64 {
            if tau < 0.0 || tau >= end {
                return 0.0;
            }
            while *at + 1 < times.len() - 1 && times[*at + 1] <= tau {
                *at += 1;
            }
            base.u[a + *at]
        };
        // Breakpoints: the grid times and the grid times shifted by the window, merged.
        let mut marks: Vec<f64> = Vec::with_capacity(2 * times.len());
        let (mut i, mut k) = (0, 0);
        while i < times.len() || k < times.len() {
            let next = match (times.get(i), times.get(k).map(|t| t + window)) {
                (Some(&p), Some(q)) if p <= q => {
                    i += 1;
                    p
                }
                (Some(&p), None) => {
                    i += 1;
                    p
                }
                (_, Some(q)) => {
                    k += 1;
                    q
                }
                (None, None) => break,
            };
            if marks.last().is_none_or(|m| next > *m) {
                marks.push(next);
            }
        }
        let offset = law.duration();
        let (mut s, mut v, mut acc) = (base.s[a], 0.0, 0.0);
        let (mut now_at, mut then_at) = (0, 0);
        for m in marks.windows(2) {
            let h = m[1] - m[0];
            let mid = 0.5 * (m[0] + m[1]);
            let j = (accel(mid, &mut now_at) - accel(mid - window, &mut then_at)) / window;
            law.jerk.push(j);
            s += h * (v + h * (0.5 * acc + h * j / 6.0));
            v += h * (acc + 0.5 * h * j);
            acc += h * j;
            law.t.push(offset + m[1]);
            law.s.push(s);
            law.sd.push(v);
            law.sdd.push(acc);
        }
        // The section ends at rest at its end point; this removes the rounding of the sums.
        let last = law.s.len() - 1;
        (law.s[last], law.sd[last], law.sdd[last]) = (base.s[b], 0.0, 0.0);
    }
    law
}

/// Proven upper bounds of `|q̇ⱼ| / vⱼ`, `|q̈ⱼ| / aⱼ` and `|q⃛ⱼ| / jⱼ` over the whole law
/// (module docs).
fn bounds(path: &PiecewiseCubic, law: &Law, limits: &PathLimits, jerk: &[f64]) -> (LimitRatios, Vec<f64>) {
    let dof = path.dof();
    let (mut vel, mut acc, mut jer) = (vec![0.0f64; dof], vec![0.0f64; dof], vec![0.0f64; dof]);
    let mut derivs = vec![[Span::point(0.0); 3]; dof];
    for i in 0..law.jerk.len() {
        let h = law.t[i + 1] - law.t[i];
        let (v0, a0, j) = (law.sd[i], law.sdd[i], law.jerk[i]);
        // ṡ's vertex, where s̈ = 0 inside the interval (else a repeated end).
        let tau = if j != 0.0 { (-a0 / j).clamp(0.0, h) } else { 0.0 };
        let sd = Span::of(&[v0, law.sd[i + 1], v0 + h * (a0 + 0.5 * h * j), v0 + tau * (a0 + 0.5 * tau * j)]);
        let sdd = Span::of(&[a0, law.sdd[i + 1], a0 + h * j]);
        let sd2 = sd.mul(sd);
        let (s_lo, s_hi) = (law.s[i].min(law.s[i + 1]), law.s[i].max(law.s[i + 1]));
        let (first, _) = path.locate(s_lo);
        let (last, _) = path.locate(s_hi);
        for (p, piece) in path.coeffs.iter().enumerate().take(last + 1).skip(first) {
            let z0 = (s_lo - path.knots[p]).clamp(0.0, path.piece_length(p));
            let z1 = (s_hi - path.knots[p]).clamp(z0, path.piece_length(p));
            for (jn, c) in piece.iter().enumerate() {
                let d1 = |z: f64| c[1] + z * (2.0 * c[2] + 3.0 * z * c[3]);
                // q′'s vertex inside [z0, z1] (else a repeated end).
                let vertex = if c[3] != 0.0 { (-c[2] / (3.0 * c[3])).clamp(z0, z1) } else { z0 };
                let spans = [
                    Span::of(&[d1(z0), d1(z1), d1(vertex)]),
                    Span::of(&[2.0 * c[2] + 6.0 * c[3] * z0, 2.0 * c[2] + 6.0 * c[3] * z1]),
                    Span::point(6.0 * c[3]),
                ];
                derivs[jn] = if p == first {
                    spans
                } else {
                    [derivs[jn][0].union(spans[0]), derivs[jn][1].union(spans[1]), derivs[jn][2].union(spans[2])]
                };
            }
        }
        for jn in 0..dof {
            let [d1, d2, d3] = derivs[jn];
            let qd = d1.mul(sd);
            let qdd = d1.mul(sdd).add(d2.mul(sd2));
            let qddd = d1.scale(j).add(d2.mul(sd).mul(sdd).scale(3.0)).add(d3.mul(sd2).mul(sd));
            vel[jn] = vel[jn].max(qd.magnitude() / limits.velocity[jn]);
            acc[jn] = acc[jn].max(qdd.magnitude() / limits.acceleration[jn]);
            jer[jn] = jer[jn].max(qddd.magnitude() / jerk[jn]);
        }
    }
    (LimitRatios { velocity: vel, acceleration: acc }, jer)
}

/// The uniform slow-down (`< 1`: a speed-up) that brings the largest proven ratio to 1.
fn fitting_scale(ratios: &LimitRatios, jerk: &[f64]) -> f64 {
    let worst = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
    worst(&ratios.velocity).max(worst(&ratios.acceleration).sqrt()).max(worst(jerk).cbrt())
}

/// A jerk-limited motion along a [`PiecewiseCubic`] path ([`jerk_limited`]).
#[derive(Debug, Clone)]
pub struct JerkLimitedMotion {
    path: PiecewiseCubic,
    law: Law,
    window: f64,
    slowdown: f64,
    time_optimal: f64,
    grid_points: usize,
    ratios: LimitRatios,
    jerk_ratios: Vec<f64>,
}

/// Times `path` under `limits` and the per-joint jerk limits `jerk` (rad/s³, m/s³), starting
/// and ending at rest: the time-optimal motion ([`time_optimal`], `points_per_piece` as
/// there) smoothed and proven (module docs).
///
/// # Errors
/// [`MotionError`] as [`time_optimal`]; a jerk limit that is not a finite number > 0 or not
/// one per joint; [`MotionError::InvalidInput`] (field `path`) for a path whose curvature
/// jumps where the motion does not rest (a parabolic blend), naming the piece.
pub fn jerk_limited(
    path: &PiecewiseCubic,
    limits: &PathLimits,
    jerk: &[f64],
    points_per_piece: usize,
) -> Result<JerkLimitedMotion, MotionError> {
    if jerk.len() != path.dof() {
        return Err(MotionError::Length { field: "jerk".into(), expected: path.dof(), found: jerk.len() });
    }
    for (i, j) in jerk.iter().enumerate() {
        check_number(&format!("jerk[{}]", i + 1), *j, true)?;
    }
    for k in 1..path.pieces() {
        if path.corner[k] {
            continue;
        }
        let (before, after) = (&path.coeffs[k - 1], &path.coeffs[k]);
        let len = path.piece_length(k - 1);
        for (b, a) in before.iter().zip(after) {
            let (left, right) = (2.0 * b[2] + 6.0 * b[3] * len, 2.0 * a[2]);
            if (left - right).abs() > 1e-9 * (1.0 + left.abs().max(right.abs())) {
                return Err(MotionError::InvalidInput {
                    field: "path".into(),
                    reason: format!(
                        "its curvature jumps at the start of piece {} (where a blend meets a straight segment): no \
                         motion with bounded jerk passes there without stopping; use a spline, or straight \
                         segments resting at the corners",
                        k + 1
                    ),
                });
            }
        }
    }
    let base = time_optimal(path, limits, points_per_piece)?;
    let sections = rests(&base);
    let optimal = base.duration();
    let candidate = |window: f64| {
        let law = smoothed(&base, &sections, window);
        let (ratios, jerk_ratios) = bounds(path, &law, limits, jerk);
        let k = fitting_scale(&ratios, &jerk_ratios);
        (k * law.duration(), window, law, k)
    };
    // Coarse scan over T = D/2ᵉ, then golden-section search in log T around the best.
    let mut best = candidate(optimal);
    let mut best_e = 0.0;
    for e in 1..WINDOW_TRIES {
        let c = candidate(optimal / 2f64.powi(e as i32));
        if c.0 < best.0 {
            (best, best_e) = (c, e as f64);
        }
    }
    // Golden-section search: each step keeps one of its two interior points.
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let (mut lo, mut hi) = (best_e - 1.0, best_e + 1.0);
    let at = |e: f64| candidate(optimal / e.exp2());
    let (mut e1, mut e2) = (hi - ratio * (hi - lo), lo + ratio * (hi - lo));
    let (mut c1, mut c2) = (at(e1), at(e2));
    for _ in 0..WINDOW_REFINEMENTS {
        if c1.0 <= c2.0 {
            (hi, e2) = (e2, e1);
            e1 = hi - ratio * (hi - lo);
            let next = at(e1);
            let kept = std::mem::replace(&mut c1, next);
            if kept.0 < best.0 {
                best = kept.clone();
            }
            c2 = kept;
        } else {
            (lo, e1) = (e1, e2);
            e2 = lo + ratio * (hi - lo);
            let next = at(e2);
            let kept = std::mem::replace(&mut c2, next);
            if kept.0 < best.0 {
                best = kept.clone();
            }
            c1 = kept;
        }
    }
    for c in [c1, c2] {
        if c.0 < best.0 {
            best = c;
        }
    }
    let (_, window, law, k) = best;
    let k = k * (1.0 + 1e-12);
    let law = law.scaled(k);
    let (ratios, jerk_ratios) = bounds(path, &law, limits, jerk);
    Ok(JerkLimitedMotion {
        path: path.clone(),
        law,
        window: window * k,
        slowdown: k,
        time_optimal: optimal,
        grid_points: base.grid_points(),
        ratios,
        jerk_ratios,
    })
}

impl JerkLimitedMotion {
    /// Duration, s.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.law.duration()
    }

    /// The duration of the time-optimal motion without the jerk limits, s.
    #[must_use]
    pub fn time_optimal_duration(&self) -> f64 {
        self.time_optimal
    }

    /// The averaging window of the smoothing pass, s (after the time scaling).
    #[must_use]
    pub fn window(&self) -> f64 {
        self.window
    }

    /// The uniform time scaling applied after the smoothing (< 1: the smoothed law was sped
    /// up).
    #[must_use]
    pub fn slowdown(&self) -> f64 {
        self.slowdown
    }

    /// Grid points of the underlying time-optimal parameterisation.
    #[must_use]
    pub fn grid_points(&self) -> usize {
        self.grid_points
    }

    /// Proven upper bounds of each joint's speed and acceleration over the whole motion, as
    /// ratios to the limits (≤ 1).
    #[must_use]
    pub fn worst_ratios(&self) -> &LimitRatios {
        &self.ratios
    }

    /// Proven upper bounds of each joint's jerk over the whole motion, as ratios to the
    /// limits (≤ 1).
    #[must_use]
    pub fn worst_jerk_ratios(&self) -> &[f64] {
        &self.jerk_ratios
    }

    /// Position, speed, acceleration and jerk (rad/s³, m/s³) at time `t` (clamped to
    /// `[0, duration]`).
    #[must_use]
    pub fn sample(&self, t: f64) -> (MotionSample, Vec<f64>) {
        let t = t.clamp(0.0, self.duration());
        let [s, sd, sdd, j] = self.law.at(t);
        let (k, z) = self.path.locate(s);
        let [q, d1, d2] = self.path.eval_in(k, z);
        let d3 = self.path.coeffs[k].iter().map(|c| 6.0 * c[3]);
        let qd = d1.iter().map(|d| d * sd).collect();
        let qdd = d1.iter().zip(&d2).map(|(d, dd)| d * sdd + dd * sd * sd).collect();
        let qddd =
            d1.iter().zip(&d2).zip(d3).map(|((d, dd), ddd)| d * j + 3.0 * dd * sd * sdd + ddd * sd.powi(3)).collect();
        (MotionSample { t, q, qd, qdd }, qddd)
    }

    /// Samples (and the jerk at each) every `dt` seconds from 0, and the end, by the rule of
    /// [`OptimalMotion::samples`].
    ///
    /// # Errors
    /// As [`OptimalMotion::samples`].
    pub fn samples(&self, dt: f64) -> Result<Vec<(MotionSample, Vec<f64>)>, MotionError> {
        Ok(sample_times(self.duration(), dt)?.into_iter().map(|t| self.sample(t)).collect())
    }

    /// The time at which the motion passes each waypoint the path was built from.
    #[must_use]
    pub fn waypoint_times(&self) -> Vec<f64> {
        self.path.marks.iter().map(|&m| self.time_at(m)).collect()
    }

    /// The first time the motion reaches the parameter `m`: bisection on the monotone law.
    fn time_at(&self, m: f64) -> f64 {
        let law = &self.law;
        let i = law.s.partition_point(|s| *s < m);
        if i == 0 {
            return 0.0;
        }
        if i >= law.s.len() {
            return law.duration();
        }
        let (mut lo, mut hi) = (law.t[i - 1], law.t[i]);
        for _ in 0..64 {
            let mid = 0.5 * (lo + hi);
            if law.at(mid)[0] < m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        hi
    }
}
