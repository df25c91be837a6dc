//! Normalised time laws `λ(τ)`: `τ ∈ [0, 1]` is the normalised time, `λ ∈ [0, 1]` the
//! fraction of the motion done.
//!
//! A motion of duration `T` with displacement `D` (a joint change, a path length, an
//! angle) is `x(t) = x0 + λ(τ)·D` with `τ = (t − t0)/T`; its velocity is `λ'(τ)·D/T` and its
//! acceleration `λ''(τ)·D/T²`, where `'` is `d/dτ`. Every profile has `λ(0) = 0`,
//! `λ(1) = 1`, and is non-decreasing, so each coordinate moves monotonically.
//!
//! | profile | `λ(τ)` | peak `λ'` | peak `|λ''|` | ends |
//! |---|---|---|---|---|
//! | [`Profile::Linear`] | `τ` | 1 | 0 (∞ at the ends) | constant speed |
//! | [`Profile::Cycloidal`] | `τ − sin(2πτ)/(2π)` (seed 001 §3.6) | 2 | 2π | `λ' = λ'' = 0` |
//! | [`Profile::Quintic`] | `10τ³ − 15τ⁴ + 6τ⁵` | 15/8 | 10/√3 | `λ' = λ'' = 0` |
//! | [`Profile::Trapezoidal`] | accelerate, cruise, decelerate | `1/(1 − f)` | `1/(f(1 − f))` | `λ' = 0` |
//!
//! `f` is the trapezoid's acceleration fraction: the acceleration phase lasts `f·T`, the
//! deceleration phase too, the cruise `(1 − 2f)·T`; `f = ½` is the triangular profile.
//! [`Profile::trapezoidal_for`] builds the fastest trapezoid for a distance and velocity and
//! acceleration limits.

use std::f64::consts::TAU;

use serde::Serialize;

use super::{MotionError, check_number};

/// A normalised time law (see the module docs).
///
/// # Example
/// ```
/// use reach::motion::Profile;
/// let v = Profile::Cycloidal.eval(0.5);
/// assert_eq!(v.position, 0.5);
/// assert!((v.velocity - 2.0).abs() < 1e-15); // peak of seed 001's profile
/// assert!(Profile::Quintic.eval(1.0).velocity.abs() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Profile {
    /// `λ = τ`: constant speed (a path at a given tool speed, seed 003 §5).
    Linear,
    /// Seed 001's "acceleration–deceleration" law `λ = τ − sin(2πτ)/(2π)`, whose velocity is
    /// `λ' = 2·sin²(πτ)` (notes 001 §3.6).
    Cycloidal,
    /// The quintic polynomial with zero velocity and acceleration at both ends.
    Quintic,
    /// Trapezoidal velocity: constant acceleration for `f·T`, cruise, constant deceleration
    /// for `f·T`. Build with [`Profile::trapezoidal`] or [`Profile::trapezoidal_for`].
    Trapezoidal {
        /// `f ∈ (0, ½]`: fraction of the duration spent accelerating (½: triangular).
        accel_fraction: f64,
    },
}

/// `λ`, `λ'` and `λ''` at one normalised time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ProfileValue {
    /// `λ(τ)`, the fraction of the motion done.
    pub position: f64,
    /// `dλ/dτ`.
    pub velocity: f64,
    /// `d²λ/dτ²`.
    pub acceleration: f64,
}

impl Profile {
    /// A trapezoidal profile with acceleration fraction `accel_fraction ∈ (0, ½]`.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] when the fraction is NaN or outside `(0, ½]`.
    pub fn trapezoidal(accel_fraction: f64) -> Result<Profile, MotionError> {
        check_number("accel_fraction", accel_fraction, true)?;
        if accel_fraction > 0.5 {
            return Err(MotionError::InvalidInput {
                field: "accel_fraction".into(),
                reason: format!("must be in (0, 0.5], got {accel_fraction}"),
            });
        }
        Ok(Profile::Trapezoidal { accel_fraction })
    }

    /// The fastest trapezoid that moves `distance` within `max_velocity` and
    /// `max_acceleration`: returns the profile and its duration.
    ///
    /// # Behavior
    /// With `V = D/v` and `A = D/a`: if `A ≤ V²` (the top speed is reached) the duration is
    /// `T = V + A/V = D/v + v/a` with `f = (v/a)/T`; otherwise the profile is triangular,
    /// `T = 2·√(D/a)`, `f = ½`, and the peak speed `√(D·a)` stays below `v`. A zero distance
    /// gives a zero duration (a motion that does not move).
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] when a number is NaN or infinite, the distance is
    /// negative, or a limit is not positive.
    ///
    /// # Example
    /// ```
    /// use reach::motion::Profile;
    /// // 1 rad at 1 rad/s and 2 rad/s²: 0.5 s accelerating, 0.5 s cruising, 0.5 s braking.
    /// let (p, t) = Profile::trapezoidal_for(1.0, 1.0, 2.0).unwrap();
    /// assert!((t - 1.5).abs() < 1e-12);
    /// assert_eq!(p, Profile::Trapezoidal { accel_fraction: 0.5 / 1.5 });
    /// ```
    pub fn trapezoidal_for(
        distance: f64,
        max_velocity: f64,
        max_acceleration: f64,
    ) -> Result<(Profile, f64), MotionError> {
        check_number("distance", distance, false)?;
        check_number("max_velocity", max_velocity, true)?;
        check_number("max_acceleration", max_acceleration, true)?;
        if distance < 0.0 {
            return Err(MotionError::InvalidInput {
                field: "distance".into(),
                reason: format!("must be ≥ 0, got {distance}"),
            });
        }
        let (fraction, duration) = trapezoid_shape(distance / max_velocity, distance / max_acceleration);
        Ok((Profile::Trapezoidal { accel_fraction: fraction }, duration))
    }

    /// `λ`, `λ'`, `λ''` at `tau` (clamped into `[0, 1]`: the motion rests outside).
    ///
    /// At the corners of the trapezoid and at the ends of the linear profile the acceleration
    /// is a jump; the value returned there is the one of the phase that starts at `τ`.
    #[must_use]
    pub fn eval(&self, tau: f64) -> ProfileValue {
        if tau.is_nan() {
            return ProfileValue { position: f64::NAN, velocity: f64::NAN, acceleration: f64::NAN };
        }
        if tau <= 0.0 || tau >= 1.0 {
            let position = if tau <= 0.0 { 0.0 } else { 1.0 };
            return ProfileValue { position, velocity: 0.0, acceleration: 0.0 };
        }
        match *self {
            Profile::Linear => ProfileValue { position: tau, velocity: 1.0, acceleration: 0.0 },
            Profile::Cycloidal => {
                let (s, c) = (TAU * tau).sin_cos();
                ProfileValue { position: tau - s / TAU, velocity: 1.0 - c, acceleration: TAU * s }
            }
            Profile::Quintic => {
                let (t2, t3) = (tau * tau, tau * tau * tau);
                ProfileValue {
                    position: t3 * (10.0 - 15.0 * tau + 6.0 * t2),
                    velocity: 30.0 * t2 * (1.0 - tau) * (1.0 - tau),
                    acceleration: 60.0 * tau * (1.0 - 3.0 * tau + 2.0 * t2),
                }
            }
            Profile::Trapezoidal { accel_fraction: f } => {
                let peak = 1.0 / (1.0 - f); // cruise speed
                let acc = peak / f;
                if tau < f {
                    ProfileValue { position: 0.5 * acc * tau * tau, velocity: acc * tau, acceleration: acc }
                } else if tau <= 1.0 - f {
                    ProfileValue { position: peak * (tau - 0.5 * f), velocity: peak, acceleration: 0.0 }
                } else {
                    let r = 1.0 - tau;
                    ProfileValue { position: 1.0 - 0.5 * acc * r * r, velocity: acc * r, acceleration: -acc }
                }
            }
        }
    }

    /// `λ(τ)` only (see [`Profile::eval`]).
    #[must_use]
    #[inline]
    pub fn position(&self, tau: f64) -> f64 {
        self.eval(tau).position
    }

    /// Largest `λ'` over `[0, 1]` (see the table in the module docs).
    #[must_use]
    pub fn peak_velocity(&self) -> f64 {
        match *self {
            Profile::Linear => 1.0,
            Profile::Cycloidal => 2.0,
            Profile::Quintic => 1.875,
            Profile::Trapezoidal { accel_fraction: f } => 1.0 / (1.0 - f),
        }
    }

    /// Largest `|λ''|` over the open interval `(0, 1)` (0 for the linear profile, whose
    /// acceleration is an impulse at the ends).
    #[must_use]
    pub fn peak_acceleration(&self) -> f64 {
        match *self {
            Profile::Linear => 0.0,
            Profile::Cycloidal => TAU,
            Profile::Quintic => 10.0 / 3f64.sqrt(),
            Profile::Trapezoidal { accel_fraction: f } => 1.0 / (f * (1.0 - f)),
        }
    }

    /// Whether the velocity is zero at both ends (rest to rest).
    #[must_use]
    pub fn starts_and_stops_at_rest(&self) -> bool {
        !matches!(self, Profile::Linear)
    }

    /// The normalised time `τ` at which `λ(τ) = fraction` (`fraction` clamped into `[0, 1]`).
    ///
    /// Every profile is non-decreasing; where it is flat (never inside `(0, 1)`) the first
    /// `τ` is returned. Closed forms for the linear and trapezoidal profiles; for the
    /// cycloidal and quintic profiles bisection refined by Newton steps, to ~1e-15.
    #[must_use]
    pub fn inverse(&self, fraction: f64) -> f64 {
        if fraction.is_nan() {
            return f64::NAN;
        }
        if fraction <= 0.0 {
            return 0.0;
        }
        if fraction >= 1.0 {
            return 1.0;
        }
        match *self {
            Profile::Linear => fraction,
            Profile::Trapezoidal { accel_fraction: f } => {
                let peak = 1.0 / (1.0 - f);
                let acc = peak / f;
                let knee = 0.5 * acc * f * f; // λ at the end of the acceleration phase
                if fraction < knee {
                    (2.0 * fraction / acc).sqrt()
                } else if fraction <= 1.0 - knee {
                    fraction / peak + 0.5 * f
                } else {
                    1.0 - (2.0 * (1.0 - fraction) / acc).sqrt()
                }
            }
            Profile::Cycloidal | Profile::Quintic => {
                let (mut lo, mut hi) = (0.0_f64, 1.0_f64);
                for _ in 0..30 {
                    let mid = 0.5 * (lo + hi);
                    if self.position(mid) < fraction {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let mut tau = 0.5 * (lo + hi);
                for _ in 0..4 {
                    let v = self.eval(tau);
                    if v.velocity <= 0.0 {
                        break;
                    }
                    let next = tau - (v.position - fraction) / v.velocity;
                    if !(lo..=hi).contains(&next) {
                        break;
                    }
                    tau = next;
                }
                tau
            }
        }
    }
}

/// The time-optimal trapezoid for the normalised demands `V = D/v` (time at top speed) and
/// `A = D/a`: returns `(f, T)`. Shared with the synchronised timing, where `V` and `A` are the
/// largest demands over the joints. `T = V + A/V` when `A ≤ V²`, else `2√A` (triangular);
/// `V = A = 0` gives `(½, 0)`.
pub(crate) fn trapezoid_shape(v_demand: f64, a_demand: f64) -> (f64, f64) {
    if v_demand <= 0.0 || a_demand <= 0.0 {
        return (0.5, 0.0);
    }
    if a_demand <= v_demand * v_demand {
        let duration = v_demand + a_demand / v_demand;
        (a_demand / (v_demand * v_demand + a_demand), duration)
    } else {
        (0.5, 2.0 * a_demand.sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: [Profile; 5] = [
        Profile::Linear,
        Profile::Cycloidal,
        Profile::Quintic,
        Profile::Trapezoidal { accel_fraction: 0.25 },
        Profile::Trapezoidal { accel_fraction: 0.5 },
    ];

    #[test]
    fn boundary_values() {
        for p in ALL {
            assert_eq!(p.position(0.0), 0.0, "{p:?}");
            assert!((p.position(1.0) - 1.0).abs() < 1e-15, "{p:?}");
            // Just inside the ends: the rest-to-rest profiles start with zero speed.
            let v = p.eval(1e-9).velocity;
            if p.starts_and_stops_at_rest() {
                assert!(v < 1e-6, "{p:?}: {v}");
            } else {
                assert_eq!(v, 1.0);
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for p in ALL {
            for k in 1..20 {
                let tau = f64::from(k) / 20.0 + 0.013; // away from the trapezoid's corners
                if tau >= 1.0 {
                    continue;
                }
                let v = p.eval(tau);
                let dv = (p.position(tau + h) - p.position(tau - h)) / (2.0 * h);
                let da = (p.eval(tau + h).velocity - p.eval(tau - h).velocity) / (2.0 * h);
                assert!((v.velocity - dv).abs() < 1e-7, "{p:?} τ={tau}");
                assert!((v.acceleration - da).abs() < 1e-5, "{p:?} τ={tau}");
            }
        }
    }

    #[test]
    fn inverse_undoes_position() {
        for p in ALL {
            for k in 0..=50 {
                let tau = f64::from(k) / 50.0;
                let back = p.inverse(p.position(tau));
                assert!((back - tau).abs() < 1e-12, "{p:?} τ={tau} → {back}");
            }
        }
    }

    #[test]
    fn trapezoid_rejects_bad_fraction() {
        assert!(Profile::trapezoidal(0.0).is_err());
        assert!(Profile::trapezoidal(0.6).is_err());
        assert!(Profile::trapezoidal(f64::NAN).is_err());
        assert!(Profile::trapezoidal(0.5).is_ok());
        assert!(Profile::trapezoidal_for(-1.0, 1.0, 1.0).is_err());
        assert!(Profile::trapezoidal_for(1.0, 0.0, 1.0).is_err());
    }
}
