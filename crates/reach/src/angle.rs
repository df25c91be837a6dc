//! Angle helpers: the one place where angles are wrapped.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

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
    // Already in (−π, π]: the `fmod` below would return it unchanged; skip it.
    if is_wrapped(angle) {
        return angle;
    }
    // Within one turn of 0 (an angle plus a joint offset): `angle % TAU` is `angle` itself
    // (|angle| < 2π), so the same result without the `fmod`.
    if angle.abs() < TAU {
        return if angle > PI { angle - TAU } else { angle + TAU };
    }
    let mut a = angle % TAU; // in (−2π, 2π)
    if a > PI {
        a -= TAU;
    } else if a <= -PI {
        a += TAU;
    }
    a
}

/// Whether `angle` (radians) lies in (−π, π], where [`wrap`] returns it unchanged (false for
/// NaN). Branch-free, so it can run over many values at once.
#[must_use]
#[inline(always)]
pub fn is_wrapped(angle: f64) -> bool {
    (angle > -PI) & (angle <= PI)
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
#[inline(always)]
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

/// `atan2(y, x)` in (−π, π], the one evaluation of an angle from two coordinates in the
/// closed-form IK solvers and the IK check.
///
/// fdlibm's `__ieee754_atan2` and `atan` (argument reduction to |t| < 7/16 by four
/// breakpoints, a degree-11 odd polynomial, the quadrant by the signs), ported: no change of
/// the rounding mode and no multi-precision fallback, so about half the standard library's
/// (glibc's correctly rounded) time. Against the standard library it differs by at most
/// 2 units in the last place (checked in this module's tests); the special cases (zeros of
/// either sign, infinities, NaN) follow C99 as the standard library's do.
///
/// # Example
/// ```
/// let a = reach::angle::atan2(1.0, -1.0);
/// assert!((a - 0.75 * std::f64::consts::PI).abs() < 1e-15);
/// ```
#[must_use]
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    if x.is_nan() || y.is_nan() {
        return x + y;
    }
    if x == 1.0 {
        return atan(y);
    }
    let (sy, sx) = (y.is_sign_negative(), x.is_sign_negative());
    if y == 0.0 {
        return match (sx, sy) {
            (false, _) => y,
            (true, false) => PI,
            (true, true) => -PI,
        };
    }
    if x == 0.0 {
        return if sy { -FRAC_PI_2 } else { FRAC_PI_2 };
    }
    if x.is_infinite() || y.is_infinite() {
        return y.atan2(x);
    }
    // |y/x| beyond 2^60 or below 2^-60 (exponent difference), as fdlibm.
    let k = exponent(y) - exponent(x);
    let z = if k > 60 {
        FRAC_PI_2 + 0.5 * PI_LO
    } else if sx && k < -60 {
        0.0
    } else {
        atan((y / x).abs())
    };
    match (sx, sy) {
        (false, false) => z,
        (false, true) => -z,
        (true, false) => PI - (z - PI_LO),
        (true, true) => (z - PI_LO) - PI,
    }
}

/// The biased exponent bits of a finite double (fdlibm's `(hx >> 20) & 0x7ff` on the high word).
#[inline(always)]
fn exponent(v: f64) -> i64 {
    ((v.to_bits() >> 52) & 0x7ff) as i64
}

/// fdlibm's `atan` breakpoints' angles, high parts (`atan(0.5)`, `atan(1)`, `atan(1.5)`,
/// `atan(∞)`).
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
const ATANHI: [f64; 4] = [
    4.636_476_090_008_060_935_15e-01,
    std::f64::consts::FRAC_PI_4, // fdlibm's 7.85398163397448278999e-01, the same double
    9.827_937_232_473_290_540_82e-01,
    FRAC_PI_2, // fdlibm's 1.57079632679489655800e+00, the same double
];

/// The low parts of [`ATANHI`].
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
const ATANLO: [f64; 4] = [
    2.269_877_745_296_168_709_24e-17,
    3.061_616_997_868_383_017_93e-17,
    1.390_331_103_123_099_845_16e-17,
    6.123_233_995_736_766_035_87e-17,
];

/// 2^66: from here on `atan` is ±π/2.
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
const ATAN_HUGE: f64 = 7.378_697_629_483_820_646_4e19;

/// 2^-27: below, `atan(x) = x` to rounding.
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
const ATAN_TINY: f64 = 7.450_580_596_923_828_125e-9;

/// The `π` low part of fdlibm's `atan2` (`π − pi_lo` is π to twice the precision).
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
const PI_LO: f64 = 1.224_646_799_147_353_177_2e-16;

/// fdlibm's `atan` (s_atan.c) for a finite argument.
#[inline]
fn atan(x: f64) -> f64 {
    let negative = x.is_sign_negative();
    let ax = x.abs();
    if ax >= ATAN_HUGE {
        // |x| ≥ 2^66: ±π/2.
        let z = ATANHI[3] + ATANLO[3];
        return if negative { -z } else { z };
    }
    let (id, t) = if ax < 0.4375 {
        if ax < ATAN_TINY {
            return x; // |x| < 2^-27: atan(x) = x to rounding
        }
        (None, x)
    } else if ax < 1.1875 {
        if ax < 0.6875 { (Some(0), (2.0 * ax - 1.0) / (2.0 + ax)) } else { (Some(1), (ax - 1.0) / (ax + 1.0)) }
    } else if ax < 2.4375 {
        (Some(2), (ax - 1.5) / (1.0 + 1.5 * ax))
    } else {
        (Some(3), -1.0 / ax)
    };
    let series = atan_series(t);
    match id {
        None => t - series,
        Some(i) => {
            let z = ATANHI[i] - ((series - ATANLO[i]) - t);
            if negative { -z } else { z }
        }
    }
}

/// `t·(s1 + s2)`: fdlibm's degree-11 odd polynomial of `atan` on the reduced argument
/// (|t| < 7/16), less its first term `t`.
#[inline(always)]
#[allow(clippy::excessive_precision, reason = "fdlibm's constants as published; each parses to the intended double")]
fn atan_series(t: f64) -> f64 {
    const AT: [f64; 11] = [
        3.333_333_333_333_293_180_27e-01,
        -1.999_999_999_987_648_324_76e-01,
        1.428_571_427_250_346_637_11e-01,
        -1.111_111_040_546_235_578_80e-01,
        9.090_887_133_436_506_561_96e-02,
        -7.691_876_205_044_829_994_95e-02,
        6.661_073_137_387_531_206_69e-02,
        -5.833_570_133_790_573_486_45e-02,
        4.976_877_994_615_932_360_17e-02,
        -3.653_157_274_421_691_552_70e-02,
        1.628_582_011_536_578_236_23e-02,
    ];
    let z = t * t;
    let w = z * z;
    let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    t * (s1 + s2)
}

/// [`atan`] of a finite argument without branches (the reduction interval and the tiny and
/// huge cases chosen by selects, one division for every interval), bit for bit [`atan`]: the
/// same operations on the same values (`x / 1` is `x`).
#[inline(always)]
fn atan_select(x: f64) -> f64 {
    let ax = x.abs();
    let (below, low, mid, high) = (ax < 0.4375, ax < 0.6875, ax < 1.1875, ax < 2.4375);
    // Interval 0 … 3 (none below 7/16): its numerator and denominator, and its breakpoint's
    // angle, selected as values (no table lookup by lane: a gather).
    let (num, den, hi, lo) = if below {
        (x, 1.0, ATANHI[0], ATANLO[0])
    } else if low {
        (2.0 * ax - 1.0, 2.0 + ax, ATANHI[0], ATANLO[0])
    } else if mid {
        (ax - 1.0, ax + 1.0, ATANHI[1], ATANLO[1])
    } else if high {
        (ax - 1.5, 1.0 + 1.5 * ax, ATANHI[2], ATANLO[2])
    } else {
        (-1.0, ax, ATANHI[3], ATANLO[3])
    };
    let t = num / den;
    let series = atan_series(t);
    let reduced = hi - ((series - lo) - t);
    let reduced = if x.is_sign_negative() { -reduced } else { reduced };
    let huge = ATANHI[3] + ATANLO[3];
    let huge = if x.is_sign_negative() { -huge } else { huge };
    if ax >= ATAN_HUGE {
        huge
    } else if ax < ATAN_TINY {
        x
    } else if below {
        t - series
    } else {
        reduced
    }
}

/// [`atan2`] of every lane, `atan2(y[l], x[l])`, equal to [`atan2`] of each lane bit for bit.
///
/// The lanes go through [`atan2`]'s general path together, its branches turned into selects (a
/// loop without branches over `L` lanes, which the compiler turns into vector instructions);
/// only a lane with a zero, an infinity or NaN is recomputed by [`atan2`].
///
/// # Example
/// ```
/// let (y, x) = ([1.0, -2.0, 0.0, 3e-300], [-1.0, 0.5, -1.0, 1.0]);
/// let a = reach::angle::atan2_lanes(&y, &x);
/// for l in 0..4 {
///     assert_eq!(a[l].to_bits(), reach::angle::atan2(y[l], x[l]).to_bits());
/// }
/// ```
#[must_use]
#[inline(always)]
pub fn atan2_lanes<const L: usize>(y: &[f64; L], x: &[f64; L]) -> [f64; L] {
    let mut out = [0.0; L];
    let mut special = false;
    for l in 0..L {
        let (y, x) = (y[l], x[l]);
        special |= !(y.is_finite() & x.is_finite()) | (y == 0.0) | (x == 0.0);
        let (sy, sx) = (y.is_sign_negative(), x.is_sign_negative());
        let one = x == 1.0;
        let k = exponent(y) - exponent(x);
        // x = 1: atan(y) itself (y / 1 is y).
        let a = atan_select(if one { y } else { (y / x).abs() });
        let z = if k > 60 {
            FRAC_PI_2 + 0.5 * PI_LO
        } else if sx & (k < -60) {
            0.0
        } else {
            a
        };
        let pi_side = PI - (z - PI_LO);
        let minus_pi_side = (z - PI_LO) - PI;
        let quadrant = if sx {
            if sy { minus_pi_side } else { pi_side }
        } else if sy {
            -z
        } else {
            z
        };
        out[l] = if one { a } else { quadrant };
    }
    if special {
        for l in 0..L {
            let (y, x) = (y[l], x[l]);
            if !(y.is_finite() & x.is_finite()) | (y == 0.0) | (x == 0.0) {
                out[l] = atan2(y, x);
            }
        }
    }
    out
}

/// [`atan2`] of every lane, as the lane kernels evaluate it: [`atan2_lanes`] (the lanes
/// together, branch-free) when `WIDE`, else [`atan2`] lane by lane — the same bits either way.
///
/// `WIDE` is the kernel's choice for its SIMD level: with two lanes per instruction (the
/// x86-64 baseline, SSE2; aarch64's NEON) the branch-free form evaluates every reduction
/// interval of every lane and costs more than the scalar [`atan2`]'s one branch per lane; from
/// four lanes per instruction on it costs less.
#[must_use]
#[inline(always)]
pub(crate) fn atan2_each<const WIDE: bool, const L: usize>(y: &[f64; L], x: &[f64; L]) -> [f64; L] {
    if WIDE { atan2_lanes(y, x) } else { std::array::from_fn(|l| atan2(y[l], x[l])) }
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

    #[test]
    fn wrap_within_a_turn_is_the_remainder_rule_bit_for_bit() {
        // The shortcut for |angle| < 2π returns what the `fmod` path returns, to the bit.
        let by_fmod = |angle: f64| {
            let mut a = angle % TAU;
            if a > PI {
                a -= TAU;
            } else if a <= -PI {
                a += TAU;
            }
            a
        };
        let mut rng = crate::rng::SplitMix64(11);
        let mut xs = vec![PI, -PI, TAU, -TAU, PI + 1e-15, -PI - 1e-15, TAU - 1e-15, -TAU + 1e-15, 1.5 * PI];
        xs.extend((0..50_000).map(|_| (2.0 * rng.next_f64() - 1.0) * 2.5 * TAU));
        for x in xs {
            let want = if is_wrapped(x) { x } else { by_fmod(x) };
            assert_eq!(wrap(x).to_bits(), want.to_bits(), "{x}");
        }
    }

    /// Units in the last place of `b` between `a` and `b`.
    fn ulps(a: f64, b: f64) -> f64 {
        let step = f64::from_bits(b.abs().to_bits() + 1) - b.abs();
        (a - b).abs() / step
    }

    #[test]
    fn atan2_agrees_with_the_standard_library() {
        let mut rng = crate::rng::SplitMix64(11);
        let mut pairs: Vec<(f64, f64)> = Vec::new();
        for scale in [1e-3, 1.0, 1e3] {
            for _ in 0..100_000 {
                pairs.push(((rng.next_f64() * 2.0 - 1.0) * scale, rng.next_f64() * 2.0 - 1.0));
            }
        }
        // Every reduction interval of atan's argument, both signs, and the breakpoints.
        for &t in &[1e-30, 1e-9, 0.1, 0.4375, 0.5, 0.6875, 1.0, 1.1875, 2.0, 2.4375, 10.0, 1e10, 1e20, 1e30] {
            for (sy, sx) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                pairs.push((sy * t, sx * 1.0));
                pairs.push((sy * t * 3.7, sx * 3.7));
                pairs.push((sy * 1.0, sx * t));
            }
        }
        let specials = [0.0, -0.0, 1.0, -1.0, f64::INFINITY, f64::NEG_INFINITY, 1e-310, -1e-310];
        for &y in &specials {
            for &x in &specials {
                pairs.push((y, x));
            }
        }
        for &(y, x) in &pairs {
            let (a, b) = (atan2(y, x), y.atan2(x));
            assert!(ulps(a, b) <= 2.0, "atan2({y}, {x}) = {a} vs {b}");
            assert_eq!(a.is_sign_negative(), b.is_sign_negative(), "atan2({y}, {x}) = {a} vs {b}");
        }
        assert!(atan2(f64::NAN, 1.0).is_nan() && atan2(1.0, f64::NAN).is_nan());
    }

    /// [`atan2_lanes`] over chunks of 8 pairs, as a kernel (for every SIMD level).
    struct Atan2Lanes<'a>(&'a [(f64, f64)]);

    impl crate::simd::Kernel for Atan2Lanes<'_> {
        type Output = Vec<u64>;
        #[inline(always)]
        fn run(self) -> Vec<u64> {
            let mut out = Vec::with_capacity(self.0.len());
            for chunk in self.0.chunks_exact(8) {
                let y: [f64; 8] = std::array::from_fn(|l| chunk[l].0);
                let x: [f64; 8] = std::array::from_fn(|l| chunk[l].1);
                out.extend(atan2_lanes(&y, &x).map(f64::to_bits));
            }
            out
        }
    }

    #[test]
    fn atan2_lanes_is_atan2_bit_for_bit_at_every_level() {
        let mut rng = crate::rng::SplitMix64(12);
        let mut pairs: Vec<(f64, f64)> = Vec::new();
        for scale in [1e-20, 1e-3, 1.0, 1e3, 1e25] {
            for _ in 0..20_000 {
                pairs.push(((rng.next_f64() * 2.0 - 1.0) * scale, rng.next_f64() * 2.0 - 1.0));
                pairs.push((rng.next_f64() * 2.0 - 1.0, (rng.next_f64() * 2.0 - 1.0) * scale));
            }
        }
        // Every reduction interval and breakpoint, both signs, x = 1 (atan itself), the
        // exponent cut-offs at 2^±60, the tiny and huge cases, and the special values.
        let mut values = vec![1e-30, 1e-9, 7.450_580_596_923_828e-9, 0.1, 0.4375, 0.5, 0.6875, 1.0, 1.1875, 2.0];
        values.extend([2.4375, 10.0, 1e10, 2f64.powi(60), 2f64.powi(61), 1e20, 7.378_697_629_483_82e19, 1e30]);
        values.extend([1e-310, 0.0, f64::INFINITY, f64::NAN, f64::MIN_POSITIVE, f64::MAX, 2f64.powi(-61)]);
        for &t in &values {
            for &u in &values {
                for (sy, sx) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                    pairs.push((sy * t, sx * u));
                    pairs.push((sy * t, sx));
                    pairs.push((sy * t * 3.7, sx * 3.7));
                }
            }
        }
        while !pairs.len().is_multiple_of(8) {
            pairs.push((0.3, 1.0));
        }
        let scalar: Vec<u64> = pairs.iter().map(|&(y, x)| atan2(y, x).to_bits()).collect();
        let same = |a: u64, b: u64| a == b || (f64::from_bits(a).is_nan() && f64::from_bits(b).is_nan());
        for level in crate::simd::levels() {
            let lanes = crate::simd::run_at(level, Atan2Lanes(&pairs));
            for (k, (&a, &b)) in lanes.iter().zip(&scalar).enumerate() {
                let (y, x) = pairs[k];
                assert!(
                    same(a, b),
                    "{}: atan2({y}, {x}) lanes {} vs {}",
                    level.name(),
                    f64::from_bits(a),
                    f64::from_bits(b)
                );
            }
        }
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
