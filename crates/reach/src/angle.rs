//! Angle helpers: the one place where angles are wrapped.

use std::f64::consts::{PI, TAU};

/// Wraps an angle in radians into the half-open interval (−π, π].
///
/// # Example
/// ```
/// use reach::angle::wrap;
/// assert_eq!(wrap(std::f64::consts::PI), std::f64::consts::PI);
/// assert!((wrap(-std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-15);
/// assert!((wrap(3.0 * std::f64::consts::PI / 2.0) + std::f64::consts::FRAC_PI_2).abs() < 1e-15);
/// ```
#[must_use]
#[inline]
pub fn wrap(angle: f64) -> f64 {
    let mut a = angle % TAU; // in (−2π, 2π)
    if a > PI {
        a -= TAU;
    } else if a <= -PI {
        a += TAU;
    }
    a
}

/// The signed shortest rotation from `from` to `to`, in (−π, π].
#[must_use]
#[inline]
pub fn shortest_difference(from: f64, to: f64) -> f64 {
    wrap(to - from)
}

/// Largest |x| that [`sin_cos`] reduces itself (≈ 20 turns); beyond, the standard library's.
const SIN_COS_FAST_RANGE: f64 = 128.0;

/// `(sin x, cos x)`, the one evaluation of a joint's rotation (forward kinematics, Jacobians,
/// dynamics all turn their joints through it).
///
/// For |x| ≤ 128 rad it is branch-free: Cody–Waite reduction by π/2 in three parts (exact
/// products for these multiples) and fdlibm's `__kernel_sin` / `__kernel_cos` polynomials on
/// [−π/4, π/4], the quadrant chosen by selects. Against the standard library it differs by at
/// most 2.3e-16 absolute and, where |sin x| and |cos x| exceed 1e-3, by at most 2 units in the
/// last place (1 for |x| ≤ 25); checked in this module's tests. It costs about a third of
/// `f64::sin_cos` (≈ 5 ns against ≈ 15 ns on the 2-core test machine), which is most of a 6R
/// arm's forward kinematics. Beyond 128 rad, and for NaN or infinities, it is
/// `f64::sin_cos`. [`sin_cos_lanes`] is the same function over several values at once.
///
/// # Example
/// ```
/// let (s, c) = reach::angle::sin_cos(0.5);
/// assert!((s - 0.5f64.sin()).abs() < 1e-16 && (c - 0.5f64.cos()).abs() < 1e-16);
/// ```
#[must_use]
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    if !in_fast_range(x) {
        return x.sin_cos();
    }
    let (sin_r, cos_r, quadrant) = sin_cos_kernels(x);
    let (s, c) = if quadrant & 1 == 0 { (sin_r, cos_r) } else { (cos_r, sin_r) };
    let s = if quadrant & 2 == 0 { s } else { -s };
    let c = if (quadrant + 1) & 2 == 0 { c } else { -c };
    (s, c)
}

/// [`sin_cos`] of every lane of `x`: `(sin, cos)` lane by lane, equal to [`sin_cos`] of each
/// lane bit for bit.
///
/// The lanes go through the branch-free evaluation together (a loop without branches over
/// `L` lanes, which the compiler turns into vector instructions: the quadrant's swap and signs
/// are integer masks here, where [`sin_cos`] selects, which is faster for one value); only
/// when a lane is beyond 128 rad, NaN or infinite is that lane recomputed by `f64::sin_cos`.
///
/// # Example
/// ```
/// let (s, c) = reach::angle::sin_cos_lanes(&[0.5, -2.0, 1e6, f64::NAN]);
/// for (k, x) in [0.5, -2.0, 1e6].into_iter().enumerate() {
///     assert_eq!((s[k], c[k]), reach::angle::sin_cos(x));
/// }
/// assert!(s[3].is_nan() && c[3].is_nan());
/// ```
#[must_use]
#[inline]
pub fn sin_cos_lanes<const L: usize>(x: &[f64; L]) -> ([f64; L], [f64; L]) {
    let mut s = [0.0; L];
    let mut c = [0.0; L];
    let mut all_fast = true;
    for l in 0..L {
        let (sin_r, cos_r, quadrant) = sin_cos_kernels(x[l]);
        // Quadrants 1 and 3 swap sine and cosine (mask all ones or zero); 2 and 3 negate the
        // sine, 1 and 2 the cosine (bit 1 of the quadrant moved to the sign bit).
        let swap = 0u64.wrapping_sub(quadrant & 1);
        let (sin_bits, cos_bits) = (sin_r.to_bits(), cos_r.to_bits());
        let sin_bits_q = (sin_bits & !swap) | (cos_bits & swap);
        let cos_bits_q = (cos_bits & !swap) | (sin_bits & swap);
        s[l] = f64::from_bits(sin_bits_q ^ ((quadrant & 2) << 62));
        c[l] = f64::from_bits(cos_bits_q ^ (((quadrant + 1) & 2) << 62));
        all_fast &= in_fast_range(x[l]);
    }
    if !all_fast {
        for l in 0..L {
            if !in_fast_range(x[l]) {
                (s[l], c[l]) = x[l].sin_cos();
            }
        }
    }
    (s, c)
}

/// Whether [`sin_cos_kernels`] is accurate for `x` (false for NaN).
#[inline(always)]
fn in_fast_range(x: f64) -> bool {
    x.abs() <= SIN_COS_FAST_RANGE
}

/// The branch-free part of [`sin_cos`]: `(sin r, cos r, j mod 4)` for `x = j·π/2 + r`,
/// |r| ≤ π/4; accurate for |x| ≤ 128 rad, a meaningless value (never a panic) beyond, for NaN
/// and for infinities.
#[inline(always)]
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
fn sin_cos_kernels(x: f64) -> (f64, f64, u64) {
    // π/2 in three 33-bit parts (fdlibm's pio2_1, pio2_2, pio2_3): j·part is exact for |j| < 2^20.
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17e+00;
    const PIO2_2: f64 = 6.077_100_506_303_965_976_60e-11;
    const PIO2_3: f64 = 2.022_266_248_711_166_455_80e-21;
    // 1.5·2^52: adding it rounds to an integer held in the low mantissa bits.
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    const S1: f64 = -1.666_666_666_666_663_243_48e-01;
    const S2: f64 = 8.333_333_333_322_489_461_24e-03;
    const S3: f64 = -1.984_126_982_985_794_931_34e-04;
    const S4: f64 = 2.755_731_370_707_006_767_89e-06;
    const S5: f64 = -2.505_076_025_340_686_341_95e-08;
    const S6: f64 = 1.589_690_995_211_550_102_21e-10;
    const C1: f64 = 4.166_666_666_666_660_190_37e-02;
    const C2: f64 = -1.388_888_888_887_410_957_49e-03;
    const C3: f64 = 2.480_158_728_947_672_941_78e-05;
    const C4: f64 = -2.755_731_435_139_066_330_35e-07;
    const C5: f64 = 2.087_572_321_298_174_827_90e-09;
    const C6: f64 = -1.135_964_755_778_819_482_65e-11;
    let shifted = x * std::f64::consts::FRAC_2_PI + SHIFT;
    let j = shifted - SHIFT;
    // j mod 4 (the mantissa holds 2^51 + j, and 2^51 is a multiple of 4).
    let quadrant = shifted.to_bits() & 3;
    let r = ((x - j * PIO2_1) - j * PIO2_2) - j * PIO2_3;
    let z = r * r;
    // __kernel_sin(r, 0): r + r³·(S1 + z·(S2 + … ))
    let sin_r = r + z * r * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))));
    // __kernel_cos(r, 0): 1 − z/2 + z²·(C1 + …), with the rounding of 1 − z/2 compensated
    let w = z * z;
    let tail = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    let half = 0.5 * z;
    let one_minus = 1.0 - half;
    let cos_r = one_minus + (((1.0 - one_minus) - half) + z * tail);
    (sin_r, cos_r, quadrant)
}

/// Degrees to radians.
#[must_use]
#[inline]
pub fn deg(value: f64) -> f64 {
    value.to_radians()
}

/// Represents `angle` inside `limits` if any representative `angle + 2πk` lies there,
/// preferring the one in (−π, π]; otherwise returns the wrapped value (still outside).
///
/// This is how IK results are reported: wrapped into (−π, π], or moved by whole turns into a
/// joint range that does not contain the wrapped value (e.g. seed 001's q1 ∈ [0, 2π]).
#[must_use]
pub fn fit_into_limits(angle: f64, limits: &crate::model::Limits, slack: f64) -> f64 {
    let w = wrap(angle);
    if limits.contains(w, slack) {
        return w;
    }
    for k in 1..=3 {
        for candidate in [w + f64::from(k) * TAU, w - f64::from(k) * TAU] {
            if limits.contains(candidate, slack) {
                return candidate;
            }
        }
    }
    w
}

/// The representative `angle + 2πk` closest to `reference` (for continuity along paths).
#[must_use]
#[inline]
pub fn nearest_equivalent(angle: f64, reference: f64) -> f64 {
    reference + wrap(angle - reference)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_into_half_open_interval() {
        for k in -5..=5 {
            let a = wrap(PI + f64::from(k) * TAU);
            assert!((a - PI).abs() < 1e-12, "k={k}: {a}");
            let b = wrap(0.3 + f64::from(k) * TAU);
            assert!((b - 0.3).abs() < 1e-12);
        }
        assert!(wrap(-PI) > 0.0);
        assert_eq!(wrap(0.0), 0.0);
    }

    /// Units in the last place of `b` between `a` and `b`.
    fn ulps(a: f64, b: f64) -> f64 {
        let step = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / step
    }

    #[test]
    fn sin_cos_agrees_with_the_standard_library() {
        let mut rng = crate::rng::SplitMix64(7);
        let mut xs: Vec<f64> = Vec::new();
        for range in [1.0, 4.0, 25.0, 128.0, 1e3] {
            xs.extend((0..100_000).map(|_| (rng.next_f64() * 2.0 - 1.0) * range));
        }
        // Near every multiple of π/2 up to the fast range's end: the reduction's hard cases.
        for k in -82..=82 {
            let x = f64::from(k) * std::f64::consts::FRAC_PI_2;
            for d in -2i64..=2 {
                xs.push(x + f64::from(d as i32) * 1e-15 * x.abs().max(1.0));
            }
        }
        xs.extend([0.0, -0.0, 1e-300, -1e-300, 128.0, -128.0, 128.000_000_1, f64::MAX]);
        for &x in &xs {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            assert!((s - s0).abs() <= 2.3e-16 && (c - c0).abs() <= 2.3e-16, "{x}: ({s}, {c}) vs ({s0}, {c0})");
            if s0.abs() > 1e-3 && c0.abs() > 1e-3 {
                let allowed = if x.abs() <= 25.0 { 1.0 } else { 2.0 };
                assert!(ulps(s, s0) <= allowed && ulps(c, c0) <= allowed, "{x}: ({s}, {c}) vs ({s0}, {c0})");
            }
        }
        let (s, c) = sin_cos(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        // Lane by lane the same bits, the lanes beyond the fast range (and NaN) included.
        let special = [0.3, f64::NAN, 1.0, f64::INFINITY, -f64::INFINITY, 5e9, -128.000_000_1, 2.0];
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan());
        for chunk in special.iter().chain(&xs).copied().collect::<Vec<_>>().chunks_exact(8) {
            let lanes: [f64; 8] = chunk.try_into().unwrap();
            let (s, c) = sin_cos_lanes(&lanes);
            for (l, &x) in lanes.iter().enumerate() {
                let (s1, c1) = sin_cos(x);
                assert!(same(s[l], s1) && same(c[l], c1), "{x}: lanes ({}, {}) vs ({s1}, {c1})", s[l], c[l]);
            }
        }
    }

    #[test]
    fn shortest_difference_crosses_pi() {
        let d = shortest_difference(deg(170.0), deg(-170.0));
        assert!((d - deg(20.0)).abs() < 1e-12);
    }
}
