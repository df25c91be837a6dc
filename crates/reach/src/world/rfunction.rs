//! Seed 004: Rvachev R-functions — the R-conjunction and the region primitives that describe
//! the allowed-configuration region Λ in `(q2, q3, q4)` (degrees, as in the paper), with the
//! notes' corrected formulas (notes 004 §3, D4, D5, D8).
//!
//! Every primitive returns a value `X` with `X ≥ 0` on the allowed side. A region is the
//! left-nested R-conjunction of the six joint-limit inequalities `g1…g6` and then the
//! primitives in the paper's order (notes 004 §4 C); `q ∈ Λ ⇔ F(q) ≥ 0`.

use serde::Serialize;

/// Rvachev's R-conjunction (system R0): `X1 ∧ X2 = X1 + X2 − √(X1² + X2²)` (paper eq. 7).
///
/// `X1 ∧ X2 ≥ 0 ⇔ X1 ≥ 0 and X2 ≥ 0`. Arguments below 1e150 in magnitude (every value in
/// degrees) use the plain square root; larger ones `hypot`, so that nothing overflows.
///
/// # Example
/// ```
/// use reach::world::rfunction::r_and;
/// assert_eq!(r_and(3.0, 4.0), 2.0);
/// assert_eq!(r_and(-3.0, -4.0), -12.0);
/// ```
#[must_use]
#[inline]
pub fn r_and(x1: f64, x2: f64) -> f64 {
    if x1.abs() < 1e150 && x2.abs() < 1e150 { x1 + x2 - (x1 * x1 + x2 * x2).sqrt() } else { x1 + x2 - x1.hypot(x2) }
}

/// Which sign of the squared coordinate a parabolic cylinder uses (notes 004 D8: the printed
/// eq. 11 lost a square; both restorations are offered).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub enum Parabola {
    /// `X = s² − 2p·t` (default: the square restored on the first bracket).
    SquareFirst,
    /// `X = t² − 2p·s`.
    SquareSecond,
}

/// One region primitive; coordinates `q = (q2, q3, q4)` in degrees.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[non_exhaustive]
pub enum Primitive {
    /// Half-space `d·q − b ≥ 0` (eq. 6).
    HalfSpace {
        /// Coefficients `d` of `(q2, q3, q4)`.
        d: [f64; 3],
        /// Free term.
        b: f64,
    },
    /// Outside of an elliptic cylinder along q2 whose centre moves linearly:
    /// `c3 = k3·q2 + m3`, `c4 = k4·q2 + m4`; `u = (q3−c3)cosφ + (q4−c4)sinφ`,
    /// `v = −(q3−c3)sinφ + (q4−c4)cosφ`, `X = u²/a² + v²/b² − 1` (eqs. 4, 9 in the corrected
    /// "centre mode" of notes 004 §3(5): a proper rotation, D4/D5).
    EllipticCylinder {
        /// Tilt of the major axis from +q3 towards +q4, degrees.
        phi_deg: f64,
        /// Semi-axis along `u` (> 0).
        a: f64,
        /// Semi-axis along `v` (> 0).
        b: f64,
        /// Centre line: `[k3, m3, k4, m4]`.
        centre: [f64; 4],
    },
    /// Outside of a parabolic cylinder in `(q2, q3)`, extruded along q4 (eq. 11 corrected,
    /// D8/D9): `s = (q2−c2)cosφ + (q3−c3)sinφ`, `t = −(q2−c2)sinφ + (q3−c3)cosφ`.
    ParabolicCylinder {
        /// Axis tilt from +q2 towards +q3, degrees.
        phi_deg: f64,
        /// Vertex `(c2, c3)`.
        vertex: [f64; 2],
        /// Focal parameter `p` (≠ 0).
        p: f64,
        /// Which restoration of the square.
        variant: Parabola,
    },
    /// Two-plane case (eqs. 13–14 corrected): ellipse with fixed tilt, centre `(m3(q2),
    /// m4(q2))` and semi-axes `a(q2)`, `b(q2)` cubic in q2 (coefficients constant term
    /// first). Where a semi-axis is ≤ 0 the obstacle region is empty and the primitive is
    /// inactive (skipped in the conjunction).
    KinematicEllipse {
        /// Tilt, degrees (paper: ≈ 110°).
        phi_deg: f64,
        /// `m3(q2)` coefficients `[c0, c1, c2, c3]`.
        m3: [f64; 4],
        /// `m4(q2)` coefficients.
        m4: [f64; 4],
        /// `a(q2)` coefficients.
        a: [f64; 4],
        /// `b(q2)` coefficients.
        b: [f64; 4],
    },
}

fn cubic(c: &[f64; 4], x: f64) -> f64 {
    ((c[3] * x + c[2]) * x + c[1]) * x + c[0]
}

fn ellipse_outside(phi_deg: f64, d3: f64, d4: f64, a: f64, b: f64) -> f64 {
    let (s, c) = phi_deg.to_radians().sin_cos();
    let u = d3 * c + d4 * s;
    let v = -d3 * s + d4 * c;
    (u / a).powi(2) + (v / b).powi(2) - 1.0
}

impl Primitive {
    /// The primitive's value at `q = (q2, q3, q4)` (degrees); `None` when inactive.
    #[must_use]
    #[inline]
    pub fn value(&self, q: [f64; 3]) -> Option<f64> {
        let [q2, q3, q4] = q;
        match self {
            Primitive::HalfSpace { d, b } => Some(d[0] * q2 + d[1] * q3 + d[2] * q4 - b),
            Primitive::EllipticCylinder { phi_deg, a, b, centre } => {
                let (c3, c4) = (centre[0] * q2 + centre[1], centre[2] * q2 + centre[3]);
                Some(ellipse_outside(*phi_deg, q3 - c3, q4 - c4, *a, *b))
            }
            Primitive::ParabolicCylinder { phi_deg, vertex, p, variant } => {
                let (sn, cs) = phi_deg.to_radians().sin_cos();
                let (d2, d3) = (q2 - vertex[0], q3 - vertex[1]);
                let s = d2 * cs + d3 * sn;
                let t = -d2 * sn + d3 * cs;
                Some(match variant {
                    Parabola::SquareFirst => s * s - 2.0 * p * t,
                    Parabola::SquareSecond => t * t - 2.0 * p * s,
                })
            }
            Primitive::KinematicEllipse { phi_deg, m3, m4, a, b } => {
                let (aa, bb) = (cubic(a, q2), cubic(b, q2));
                if aa <= 0.0 || bb <= 0.0 {
                    return None;
                }
                Some(ellipse_outside(*phi_deg, q3 - cubic(m3, q2), q4 - cubic(m4, q2), aa, bb))
            }
        }
    }
}

/// A region `F(q) = ((((g1 ∧ g2) ∧ …) ∧ g6) ∧ X1) ∧ … ∧ Xm`, degrees.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Region {
    /// Joint-limit box `[lower, upper]` for `(q2, q3, q4)`, degrees (paper eq. 2).
    pub limits: [[f64; 2]; 3],
    /// The primitives in composition order.
    pub primitives: Vec<Primitive>,
}

impl Region {
    /// `F_Ω`: the R-conjunction of the six limit inequalities `g1 = q2 − q2min`,
    /// `g2 = q2max − q2`, … in the paper's order (notes 004 §3(2), §4 C).
    #[must_use]
    #[inline]
    pub fn box_value(&self, q: [f64; 3]) -> f64 {
        let mut f = q[0] - self.limits[0][0];
        f = r_and(f, self.limits[0][1] - q[0]);
        for (v, [lo, hi]) in q.iter().zip(&self.limits).skip(1) {
            f = r_and(f, v - lo);
            f = r_and(f, hi - v);
        }
        f
    }

    /// `F(q)`; `q ∈ Λ ⇔ F(q) ≥ 0` (boundary included).
    #[must_use]
    #[inline]
    pub fn value(&self, q: [f64; 3]) -> f64 {
        let mut f = self.box_value(q);
        for p in &self.primitives {
            if let Some(x) = p.value(q) {
                f = r_and(f, x);
            }
        }
        f
    }

    /// Membership test `F(q) ≥ 0`.
    #[must_use]
    #[inline]
    pub fn contains(&self, q: [f64; 3]) -> bool {
        self.value(q) >= 0.0
    }
}

/// The half-space through three support points `p1, p2, p3` of `(q2, q3, q4)`, oriented so
/// that `interior` is on the allowed side (notes 004 §3(6), derived procedure).
/// `None` when the points are collinear or `interior` lies on the plane.
#[must_use]
pub fn plane_through(p1: [f64; 3], p2: [f64; 3], p3: [f64; 3], interior: [f64; 3]) -> Option<Primitive> {
    let v = |p: [f64; 3]| nalgebra::Vector3::from(p);
    let n = (v(p2) - v(p1)).cross(&(v(p3) - v(p1)));
    if n.norm() <= f64::EPSILON * (v(p2) - v(p1)).norm() * (v(p3) - v(p1)).norm() {
        return None;
    }
    let b = n.dot(&v(p1));
    let side = n.dot(&v(interior)) - b;
    if side == 0.0 {
        return None;
    }
    let s = side.signum();
    Some(Primitive::HalfSpace { d: [s * n.x, s * n.y, s * n.z], b: s * b })
}
