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
    fn shortest_difference_crosses_pi() {
        let d = shortest_difference(deg(170.0), deg(-170.0));
        assert!((d - deg(20.0)).abs() < 1e-12);
    }
}
