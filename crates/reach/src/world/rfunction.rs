//! Seed 004: Rvachev R-functions — the R-conjunction and the region primitives that describe
//! the allowed-configuration region Λ in `(q2, q3, q4)` (degrees, as in the paper), with the
//! notes' corrected formulas (notes 004 §3, D4, D5, D8).
//!
//! Every primitive returns a value `X` with `X ≥ 0` on the allowed side. A region is the
//! left-nested R-conjunction of the six joint-limit inequalities `g1…g6` and then the
//! primitives in the paper's order (notes 004 §4 C); `q ∈ Λ ⇔ F(q) ≥ 0`, decided by the
//! conjunction's defining property on the exact values of the limits and primitives
//! ([`Region::contains`], the one membership rule; [`CompiledRegion`] is its fast form).

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

/// `(sin, cos)` of a tilt given in degrees (computed once per primitive by [`Flat::of`]).
fn tilt(phi_deg: f64) -> (f64, f64) {
    phi_deg.to_radians().sin_cos()
}

impl Primitive {
    /// The primitive's value at `q = (q2, q3, q4)` (degrees); `None` when inactive.
    ///
    /// Evaluated in the primitive's flat form (the tilt folded into affine coefficients; see
    /// [`CompiledRegion`]), the one evaluation behind every membership test: the value is
    /// `≥ 0` exactly when [`Region::contains`] and [`CompiledRegion::contains`] count the
    /// primitive as satisfied.
    #[must_use]
    #[inline]
    pub fn value(&self, q: [f64; 3]) -> Option<f64> {
        Flat::of(self).value(q)
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

    /// `F(q)`: the left-nested R-conjunction of the limits and the active primitives' values.
    /// Its sign is the membership ([`Self::contains`]) away from rounding; use it for the
    /// size of `F` (e.g. a band around the boundary), `contains` for the verdict.
    #[must_use]
    #[inline]
    pub fn value(&self, q: [f64; 3]) -> f64 {
        self.primitives.iter().filter_map(|p| p.value(q)).fold(self.box_value(q), r_and)
    }

    /// The region compiled for fast evaluation (see [`CompiledRegion`]).
    #[must_use]
    pub fn compile(&self) -> CompiledRegion {
        CompiledRegion::new(self)
    }

    /// Membership `q ∈ Λ` (degrees, boundary included), the one membership rule of seed 004:
    /// `q` within every limit and every active primitive's [`Primitive::value`] `≥ 0` — the
    /// R-conjunction's defining property `X1 ∧ X2 ≥ 0 ⇔ X1 ≥ 0 and X2 ≥ 0` (eq. 7) applied
    /// to the exact floating-point values. `false` for a NaN coordinate.
    ///
    /// The rounded `F(q) ≥ 0` ([`Self::value`]) can differ only within rounding of a zero:
    /// a primitive value that is negative but tiny next to the others (e.g. −1e-14 at a
    /// node on a support plane) is absorbed by `X1 + X2 − √(X1² + X2²)`, so `F` may round
    /// to 0 where this test says "outside". This test is the stricter one and the one used
    /// everywhere (fit, confusion counts, [`CompiledRegion::contains`], which is this test
    /// bit for bit).
    #[must_use]
    #[inline]
    pub fn contains(&self, q: [f64; 3]) -> bool {
        self.limits.iter().zip(q).all(|([lo, hi], v)| within(*lo, *hi, v))
            && self.primitives.iter().all(|p| Flat::of(p).admits_at(q))
    }
}

/// `lo ≤ v ≤ hi` (`false` for NaN): the limit test of every membership evaluation.
#[inline(always)]
fn within(lo: f64, hi: f64, v: f64) -> bool {
    (v >= lo) & (v <= hi)
}

/// A half-space in the flat form `X = d0·q2 + d1·q3 + d2·q4 − b`: `[d0, d1, d2, b]` (the
/// order of the fit's dot products, so a support point's value is exactly 0).
type Plane = [f64; 4];

/// An elliptic cylinder in the flat form `X = (L1² + L2²) − 1`, each `Lk = c0 + c1·q2 + c2·q3 +
/// c3·q4` (`u/a` and `v/b`): the coefficients `[L1; L2]`.
type Ellipse = [f64; 8];

/// A parabolic cylinder in the flat form `X = L1² + L2`, each `Lk = c0 + c1·q2 + c2·q3` (the
/// squared coordinate and `−2p` times the other): the coefficients `[L1; L2]`.
type Parabolic = [f64; 6];

/// A kinematic ellipse in the flat form `[sin φ, cos φ, m3, m4, a, b]` (each cubic constant
/// term first, evaluated on the powers `q2, q2², q2³`): `X = (u²b² + v²a²)/(a²b²) − 1`,
/// inactive where `a ≤ 0` or `b ≤ 0`.
type Kinematic = [f64; 18];

#[inline(always)]
fn plane_value(c: &Plane, q2: f64, q3: f64, q4: f64) -> f64 {
    c[0] * q2 + c[1] * q3 + c[2] * q4 - c[3]
}

#[inline(always)]
fn plane_admits(c: &Plane, q2: f64, q3: f64, q4: f64) -> bool {
    plane_value(c, q2, q3, q4) >= 0.0
}

/// `L1² + L2²` of an elliptic cylinder (its value plus 1).
#[inline(always)]
fn ellipse_sum(c: &Ellipse, q2: f64, q3: f64, q4: f64) -> f64 {
    let l1 = c[0] + c[1] * q2 + c[2] * q3 + c[3] * q4;
    let l2 = c[4] + c[5] * q2 + c[6] * q3 + c[7] * q4;
    l1 * l1 + l2 * l2
}

/// The ellipse's value `≥ 0`: `fl(X − 1) ≥ 0 ⇔ X ≥ 1` (rounding keeps the difference's sign).
#[inline(always)]
fn ellipse_admits(c: &Ellipse, q2: f64, q3: f64, q4: f64) -> bool {
    ellipse_sum(c, q2, q3, q4) >= 1.0
}

#[inline(always)]
fn parabolic_value(c: &Parabolic, q2: f64, q3: f64) -> f64 {
    let l1 = c[0] + c[1] * q2 + c[2] * q3;
    let l2 = c[3] + c[4] * q2 + c[5] * q3;
    l1 * l1 + l2
}

#[inline(always)]
fn parabolic_admits(c: &Parabolic, q2: f64, q3: f64) -> bool {
    parabolic_value(c, q2, q3) >= 0.0
}

/// A kinematic ellipse's `(a, b, u²b² + v²a², a²b²)` at `q2` (with its powers `p2 = q2²`,
/// `p3 = p2·q2`), `q3`, `q4`.
#[inline(always)]
fn kinematic_terms(k: &Kinematic, q2: f64, p2: f64, p3: f64, q3: f64, q4: f64) -> (f64, f64, f64, f64) {
    let (s, c) = (k[0], k[1]);
    let cubic = |c: &[f64]| c[0] + c[1] * q2 + c[2] * p2 + c[3] * p3;
    let (d3, d4) = (q3 - cubic(&k[2..6]), q4 - cubic(&k[6..10]));
    let (a, b) = (cubic(&k[10..14]), cubic(&k[14..18]));
    let (u, v) = (d3 * c + d4 * s, -d3 * s + d4 * c);
    let (a2, b2) = (a * a, b * b);
    (a, b, u * u * b2 + v * v * a2, a2 * b2)
}

/// Whether a kinematic ellipse with terms `(a, b, n, d)` admits the point: inactive, or
/// `n/d − 1 ≥ 0` decided without the division. With `n, d ≥ 0` (or NaN), correctly rounded
/// `n/d ≥ 1 ⇔ n ≥ d` for a finite `d > 0` (below 1 the floats are 2^-53 apart and `n < d`
/// means `n/d ≤ 1 − 2^-53`); `d = 0` gives `+∞` (admitted) for `n > 0` and NaN for `n = 0`,
/// `d = +∞` gives 0 or NaN (not admitted).
#[inline(always)]
fn kinematic_admits((a, b, n, d): (f64, f64, f64, f64)) -> bool {
    (a <= 0.0) | (b <= 0.0) | ((n >= d) & (n > 0.0) & (d < f64::INFINITY))
}

/// One primitive in flat form: the one evaluation of a primitive's value and sign behind
/// [`Primitive::value`], [`Region::contains`] and [`CompiledRegion`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Flat {
    Plane(Plane),
    Ellipse(Ellipse),
    Parabolic(Parabolic),
    Kinematic(Kinematic),
}

impl Flat {
    /// The flat form of `p` (tilt trigonometry and semi-axes folded into coefficients).
    pub(crate) fn of(p: &Primitive) -> Self {
        match p {
            Primitive::HalfSpace { d, b } => Flat::Plane([d[0], d[1], d[2], *b]),
            Primitive::EllipticCylinder { phi_deg, a, b, centre: [k3, m3, k4, m4] } => {
                let (s, c) = tilt(*phi_deg);
                // u = (q3 − k3·q2 − m3)·c + (q4 − k4·q2 − m4)·s, v = −(…)·s + (…)·c.
                let u = [-(m3 * c + m4 * s), -(k3 * c + k4 * s), c, s];
                let v = [m3 * s - m4 * c, k3 * s - k4 * c, -s, c];
                Flat::Ellipse([u[0] / a, u[1] / a, u[2] / a, u[3] / a, v[0] / b, v[1] / b, v[2] / b, v[3] / b])
            }
            Primitive::ParabolicCylinder { phi_deg, vertex: [c2, c3], p, variant } => {
                let (sn, cs) = tilt(*phi_deg);
                // s = (q2 − c2)·cs + (q3 − c3)·sn, t = −(q2 − c2)·sn + (q3 − c3)·cs.
                let s = [-(c2 * cs + c3 * sn), cs, sn];
                let t = [c2 * sn - c3 * cs, -sn, cs];
                let (square, linear) = match variant {
                    Parabola::SquareFirst => (s, t),
                    Parabola::SquareSecond => (t, s),
                };
                let l2 = linear.map(|x| -2.0 * p * x);
                Flat::Parabolic([square[0], square[1], square[2], l2[0], l2[1], l2[2]])
            }
            Primitive::KinematicEllipse { phi_deg, m3, m4, a, b } => {
                let (s, c) = tilt(*phi_deg);
                let mut k = [0.0; 18];
                k[0] = s;
                k[1] = c;
                for (slot, coefficients) in k[2..].chunks_exact_mut(4).zip([m3, m4, a, b]) {
                    slot.copy_from_slice(coefficients);
                }
                Flat::Kinematic(k)
            }
        }
    }

    /// The primitive's value (`None` when inactive); `≥ 0` exactly when [`Self::admits`].
    #[inline]
    pub(crate) fn value(&self, [q2, q3, q4]: [f64; 3]) -> Option<f64> {
        match self {
            Flat::Plane(c) => Some(plane_value(c, q2, q3, q4)),
            Flat::Ellipse(c) => Some(ellipse_sum(c, q2, q3, q4) - 1.0),
            Flat::Parabolic(c) => Some(parabolic_value(c, q2, q3)),
            Flat::Kinematic(k) => {
                let p2 = q2 * q2;
                let (a, b, n, d) = kinematic_terms(k, q2, p2, p2 * q2, q3, q4);
                (a > 0.0 && b > 0.0).then(|| n / d - 1.0)
            }
        }
    }

    /// The primitive's verdict at `q` ([`Self::admits`] with the powers of `q2`).
    #[inline]
    pub(crate) fn admits_at(&self, [q2, q3, q4]: [f64; 3]) -> bool {
        let p2 = q2 * q2;
        self.admits(q2, p2, p2 * q2, q3, q4)
    }

    /// The primitive's verdict at `(q2, q3, q4)` (`p2 = q2²`, `p3 = p2·q2`): inactive or its
    /// value `≥ 0` (see [`ellipse_admits`], [`kinematic_admits`]); the per-kind tests are the
    /// ones every lane of [`CompiledRegion::contains_into`] evaluates.
    #[inline(always)]
    pub(crate) fn admits(&self, q2: f64, p2: f64, p3: f64, q3: f64, q4: f64) -> bool {
        match self {
            Flat::Plane(c) => plane_admits(c, q2, q3, q4),
            Flat::Ellipse(c) => ellipse_admits(c, q2, q3, q4),
            Flat::Parabolic(c) => parabolic_admits(c, q2, q3),
            Flat::Kinematic(k) => kinematic_admits(kinematic_terms(k, q2, p2, p3, q3, q4)),
        }
    }
}

/// Configurations per block of [`CompiledRegion::contains_into`] (four SSE2 registers of two
/// values per quantity).
pub const MEMBERSHIP_LANES: usize = 64;

/// All ones where `c` holds, else 0: a comparison as a lane mask.
#[inline(always)]
fn mask(c: bool) -> u64 {
    u64::from(c).wrapping_neg()
}

/// [`CompiledRegion::contains_into`] as a [`crate::simd::Kernel`].
struct Membership<'a> {
    region: &'a CompiledRegion,
    qs: &'a [[f64; 3]],
    out: &'a mut Vec<bool>,
}

impl crate::simd::Kernel for Membership<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        self.region.contains_into_at(self.qs, self.out);
    }
}

/// A [`Region`] compiled into flat coefficient arrays (seed 004's fitted R-function region as
/// a fast membership test).
///
/// * [`CompiledRegion::contains`] is [`Region::contains`] — the same verdict for every `q`,
///   computed by the same expressions on the same coefficients — in a flat, branch-free pass
///   over contiguous coefficients grouped by primitive kind (no square root, no tilt
///   trigonometry — it is folded into the coefficients — and no allocation). Half-spaces are
///   affine in `q`, an elliptic cylinder is `L1² + L2² ≥ 1` and a parabolic one `L1² + L2 ≥
///   0` with `Lk` affine; a kinematic ellipse with semi-axes `a, b > 0` is decided without
///   its division (`u²b² + v²a² ≥ a²b²`, exactly the sign of its value).
/// * [`CompiledRegion::value`] is `F(q)` itself, bit for bit [`Region::value`], with each
///   primitive's flat form computed once instead of at every evaluation (used where
///   the size of `F` matters, e.g. the first test's band, [`super::approach::FastRegion`]).
#[derive(Debug, Clone, PartialEq)]
pub struct CompiledRegion {
    source: Region,
    lower: [f64; 3],
    upper: [f64; 3],
    planes: Vec<Plane>,
    ellipses: Vec<Ellipse>,
    parabolas: Vec<Parabolic>,
    kinematic: Vec<Kinematic>,
    /// Every primitive's flat form in composition order (for [`Self::value`]).
    ops: Vec<Flat>,
}

impl CompiledRegion {
    /// Compiles `region`.
    #[must_use]
    pub fn new(region: &Region) -> Self {
        let ops: Vec<Flat> = region.primitives.iter().map(Flat::of).collect();
        let (mut planes, mut ellipses, mut parabolas, mut kinematic) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for op in &ops {
            match *op {
                Flat::Plane(c) => planes.push(c),
                Flat::Ellipse(c) => ellipses.push(c),
                Flat::Parabolic(c) => parabolas.push(c),
                Flat::Kinematic(k) => kinematic.push(k),
            }
        }
        CompiledRegion {
            source: region.clone(),
            lower: region.limits.map(|l| l[0]),
            upper: region.limits.map(|l| l[1]),
            planes,
            ellipses,
            parabolas,
            kinematic,
            ops,
        }
    }

    /// The region it was compiled from.
    #[must_use]
    pub fn region(&self) -> &Region {
        &self.source
    }

    /// Membership `q ∈ Λ` (degrees, boundary included): [`Region::contains`] (see the type's
    /// documentation). `false` for a NaN coordinate.
    #[must_use]
    #[inline]
    pub fn contains(&self, q: [f64; 3]) -> bool {
        let [q2, q3, q4] = q;
        self.contains_lanes(&[q2], &[q3], &[q4])[0]
    }

    /// [`Self::contains`] of every configuration of `qs` (degrees), into `out` (cleared
    /// first; `out[i]` is `contains(qs[i])`, bit for bit the same arithmetic).
    ///
    /// The configurations are evaluated [`MEMBERSHIP_LANES`] at a time in
    /// structure-of-arrays lanes: each primitive's coefficients are loaded once per block and
    /// its sign computed for every lane by the same few multiplications and additions, which
    /// the compiler turns into packed vector instructions.
    ///
    /// # Example
    /// ```
    /// use reach::world::rfunction::{Primitive, Region};
    /// let region = Region {
    ///     limits: [[0.0, 120.0], [-120.0, 120.0], [-120.0, 120.0]],
    ///     primitives: vec![Primitive::HalfSpace { d: [0.0, 1.0, 1.0], b: 0.0 }],
    /// };
    /// let compiled = region.compile();
    /// let qs = [[10.0, 5.0, 5.0], [10.0, -5.0, -5.0], [130.0, 5.0, 5.0]];
    /// let mut inside = Vec::new();
    /// compiled.contains_into(&qs, &mut inside);
    /// assert_eq!(inside, [true, false, false]);
    /// ```
    pub fn contains_into(&self, qs: &[[f64; 3]], out: &mut Vec<bool>) {
        crate::simd::run(Membership { region: self, qs, out });
    }

    /// [`Self::contains_into`]'s kernel, compiled for the level [`crate::simd::run`] picks.
    #[inline(always)]
    fn contains_into_at(&self, qs: &[[f64; 3]], out: &mut Vec<bool>) {
        out.clear();
        out.reserve(qs.len());
        let mut blocks = qs.chunks_exact(MEMBERSHIP_LANES);
        for block in &mut blocks {
            let lanes = |k: usize| -> [f64; MEMBERSHIP_LANES] { std::array::from_fn(|l| block[l][k]) };
            out.extend_from_slice(&self.contains_lanes(&lanes(0), &lanes(1), &lanes(2)));
        }
        let rest = blocks.remainder();
        if let Some(last) = rest.last() {
            // The partial block padded with its last configuration.
            let lanes =
                |k: usize| -> [f64; MEMBERSHIP_LANES] { std::array::from_fn(|l| rest.get(l).unwrap_or(last)[k]) };
            out.extend_from_slice(&self.contains_lanes(&lanes(0), &lanes(1), &lanes(2))[..rest.len()]);
        }
    }

    /// The membership kernel over `L` lanes of `(q2, q3, q4)`: the one evaluation behind
    /// [`Self::contains`] (`L = 1`) and [`Self::contains_into`], lane by lane the verdicts of
    /// [`within`] and [`Flat::admits`] (the primitives grouped by kind).
    #[inline(always)]
    #[allow(
        clippy::needless_range_loop,
        reason = "the lane loops index several arrays by the same lane: the form that vectorises"
    )]
    fn contains_lanes<const L: usize>(&self, q2: &[f64; L], q3: &[f64; L], q4: &[f64; L]) -> [bool; L] {
        // Lane masks (all ones while every test holds): packed compares and `and`s.
        let mut inside = [u64::MAX; L];
        for (k, q) in [q2, q3, q4].into_iter().enumerate() {
            let (lo, hi) = (self.lower[k], self.upper[k]);
            for l in 0..L {
                inside[l] &= mask(within(lo, hi, q[l]));
            }
        }
        for c in &self.planes {
            for l in 0..L {
                inside[l] &= mask(plane_admits(c, q2[l], q3[l], q4[l]));
            }
        }
        for c in &self.ellipses {
            for l in 0..L {
                inside[l] &= mask(ellipse_admits(c, q2[l], q3[l], q4[l]));
            }
        }
        for c in &self.parabolas {
            for l in 0..L {
                inside[l] &= mask(parabolic_admits(c, q2[l], q3[l]));
            }
        }
        if !self.kinematic.is_empty() {
            // Powers of q2 shared by the four cubics of every kinematic ellipse.
            let p2: [f64; L] = std::array::from_fn(|l| q2[l] * q2[l]);
            let p3: [f64; L] = std::array::from_fn(|l| p2[l] * q2[l]);
            for k in &self.kinematic {
                for l in 0..L {
                    inside[l] &= mask(kinematic_admits(kinematic_terms(k, q2[l], p2[l], p3[l], q3[l], q4[l])));
                }
            }
        }
        inside.map(|m| m != 0)
    }

    /// `F(q)` (degrees), bit for bit [`Region::value`].
    #[must_use]
    #[inline]
    pub fn value(&self, q: [f64; 3]) -> f64 {
        self.ops.iter().filter_map(|p| p.value(q)).fold(self.source.box_value(q), r_and)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every primitive kind and variant (the fit never makes a `SquareSecond` parabola), a
    /// kinematic ellipse inactive over part of the range: the compiled membership is every
    /// argument's sign, the compiled value the region's bit for bit.
    #[test]
    fn compiled_membership_is_every_sign_for_every_primitive_kind() {
        let region = Region {
            limits: [[0.0, 120.0], [-120.0, 120.0], [-120.0, 120.0]],
            primitives: vec![
                Primitive::HalfSpace { d: [0.3, -1.0, 0.2], b: -100.0 },
                Primitive::EllipticCylinder { phi_deg: 25.0, a: 40.0, b: 20.0, centre: [0.2, -10.0, -0.3, 30.0] },
                Primitive::ParabolicCylinder {
                    phi_deg: 200.0,
                    vertex: [60.0, 90.0],
                    p: 15.0,
                    variant: Parabola::SquareFirst,
                },
                Primitive::ParabolicCylinder {
                    phi_deg: 70.0,
                    vertex: [10.0, -80.0],
                    p: -25.0,
                    variant: Parabola::SquareSecond,
                },
                Primitive::KinematicEllipse {
                    phi_deg: 110.0,
                    m3: [-30.0, 0.5, 0.0, 0.0],
                    m4: [20.0, -0.2, 0.001, 0.0],
                    a: [-20.0, 1.0, 0.0, 0.0],
                    b: [10.0, 0.3, 0.0, -1e-5],
                },
            ],
        };
        let compiled = region.compile();
        let mut s = 3_u64;
        let mut next = || {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut inside, mut cut) = (0, vec![0; region.primitives.len()]);
        let qs: Vec<[f64; 3]> =
            (0..50_001).map(|_| [130.0 * next() - 5.0, 250.0 * next() - 125.0, 250.0 * next() - 125.0]).collect();
        // The batch kernel gives `contains` lane by lane (a partial last block included).
        let mut batch = Vec::new();
        compiled.contains_into(&qs, &mut batch);
        assert_eq!(batch.len(), qs.len());
        // The same verdicts at every vector-instruction level the machine has.
        for level in crate::simd::levels() {
            let mut at = Vec::new();
            crate::simd::run_at(level, Membership { region: &compiled, qs: &qs, out: &mut at });
            assert_eq!(at, batch, "level {}", level.name());
        }
        for (i, &q) in qs.iter().enumerate() {
            assert_eq!(compiled.value(q).to_bits(), region.value(q).to_bits(), "{q:?}");
            let values: Vec<Option<f64>> = region.primitives.iter().map(|p| p.value(q)).collect();
            let in_box = region.limits.iter().zip(q).all(|(l, v)| v >= l[0] && v <= l[1]);
            let every = in_box && values.iter().all(|x| x.is_none_or(|x| x >= 0.0));
            assert_eq!(compiled.contains(q), every, "{q:?} {values:?}");
            assert_eq!(batch[i], every, "{q:?}");
            inside += usize::from(every);
            for (c, x) in cut.iter_mut().zip(&values) {
                *c += usize::from(in_box && x.is_some_and(|x| x < 0.0));
            }
        }
        // The sample sees both verdicts and every primitive cutting.
        assert!(inside > 1000 && inside < 49_000, "{inside}");
        assert!(cut.iter().all(|&c| c > 100), "{cut:?}");
    }
}
