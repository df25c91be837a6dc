//! Synchronised timing: every joint starts and stops together, and the duration is set by the
//! joint that needs longest.
//!
//! # Seed 000's rule, corrected (notes 000 §3.5, item D8)
//!
//! Seed 000 (P2011 appendix) synchronises three stepper motors with a linear program,
//! `max Σ φᵢ·ωᵢ` subject to `φ₁ω₁ = φ₂ω₂ = φ₃ω₃` and `ωᵢ ≤ 500`, where `φᵢ` is motor *i*'s
//! pulse count and `ωᵢ` its pulse rate. Its stated intent is "the motor that has to work
//! longest turns at maximum speed and the others are matched to it", but the constraint is
//! wrong: motor *i* runs for `tᵢ = φᵢ/ωᵢ`, so equal durations need **`φᵢ/ωᵢ` equal**, not
//! `φᵢ·ωᵢ`. For `φ = (100, 400, 200)` pulses and 500 Hz the literal LP gives
//! `ω = (500, 125, 250)` and durations `(0.2, 3.2, 0.8)` s; the intent gives
//! `ω = 500·φ/max φ = (125, 500, 250)` and 0.8 s for all three. This module implements the
//! intent, for any [`Profile`]:
//!
//! * a fixed profile shape with peak normalised speed `λ'max` and acceleration `λ''max`:
//!   joint *i* moving `Dᵢ` needs `T ≥ λ'max·|Dᵢ|/vᵢ` and `T ≥ √(λ''max·|Dᵢ|/aᵢ)`; the
//!   duration is the largest of these over the joints ([`Timing::synchronised`]);
//! * a trapezoid whose acceleration fraction is chosen too: with `V = maxᵢ |Dᵢ|/vᵢ` and
//!   `A = maxᵢ |Dᵢ|/aᵢ`, `T = V + A/V` when `A ≤ V²`, else the triangle `T = 2√A`
//!   ([`Timing::synchronised_trapezoid`]); the joints sharing one normalised profile, each
//!   stays within both its limits.
//!
//! Joint *i*'s peak speed is then `λ'max·|Dᵢ|/T`: the limiting joint runs at its limit, the
//! others proportionally slower (the seed's "matched" motors).

use serde::Serialize;

use super::profile::trapezoid_shape;
use super::{MotionError, Profile, check_number};
use crate::model::Robot;

/// Per-joint rate limits: speeds (rad/s or m/s) and optional accelerations (rad/s², m/s²),
/// all symmetric (`|q̇ᵢ| ≤ velocity[i]`).
///
/// # Example
/// ```
/// use reach::motion::JointRates;
/// let rates = JointRates::new(vec![1.0, 2.0], Some(vec![4.0, 4.0])).unwrap();
/// assert_eq!(rates.velocity, [1.0, 2.0]);
/// assert!(JointRates::new(vec![1.0, 0.0], None).is_err());
/// ```
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointRates {
    /// Largest speed of each joint, > 0.
    pub velocity: Vec<f64>,
    /// Largest acceleration of each joint, > 0, if limited.
    pub acceleration: Option<Vec<f64>>,
}

impl JointRates {
    /// Explicit limits.
    ///
    /// # Errors
    /// [`MotionError`] when a limit is not a positive finite number or the two vectors differ
    /// in length.
    pub fn new(velocity: Vec<f64>, acceleration: Option<Vec<f64>>) -> Result<Self, MotionError> {
        for (i, v) in velocity.iter().enumerate() {
            check_number(&format!("velocity[{}]", i + 1), *v, true)?;
        }
        if let Some(acc) = &acceleration {
            if acc.len() != velocity.len() {
                return Err(MotionError::Length {
                    field: "acceleration".into(),
                    expected: velocity.len(),
                    found: acc.len(),
                });
            }
            for (i, a) in acc.iter().enumerate() {
                check_number(&format!("acceleration[{}]", i + 1), *a, true)?;
            }
        }
        Ok(JointRates { velocity, acceleration })
    }

    /// The robot's speed limits ([`Joint::max_velocity`](crate::model::Joint::max_velocity)),
    /// with optional acceleration limits.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] naming the first joint without a speed limit, or the
    /// errors of [`JointRates::new`].
    pub fn from_robot(robot: &Robot, acceleration: Option<Vec<f64>>) -> Result<Self, MotionError> {
        let mut velocity = Vec::with_capacity(robot.dof());
        for (i, joint) in robot.joints().iter().enumerate() {
            match joint.max_velocity {
                Some(v) => velocity.push(v),
                None => {
                    return Err(MotionError::InvalidInput {
                        field: format!("joint {} ({}) max_velocity", i + 1, joint.name),
                        reason: "is not given in the robot description; pass explicit limits".into(),
                    });
                }
            }
        }
        JointRates::new(velocity, acceleration)
    }

    /// Number of joints.
    #[must_use]
    pub fn len(&self) -> usize {
        self.velocity.len()
    }

    /// Whether there are no joints.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.velocity.is_empty()
    }
}

/// The result of synchronised timing.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Timing {
    /// Duration of the motion, seconds (0 when no joint moves).
    pub duration: f64,
    /// The time law all joints share.
    pub profile: Profile,
    /// 0-based index of the joint whose limit sets the duration (`None` when nothing moves).
    pub limiting_joint: Option<usize>,
    /// Peak speed of each joint, `λ'max·|Dᵢ|/T` (rad/s or m/s).
    pub peak_velocity: Vec<f64>,
    /// Peak acceleration of each joint, `λ''max·|Dᵢ|/T²` (0 for the linear profile, whose
    /// speed jumps at the ends).
    pub peak_acceleration: Vec<f64>,
}

impl Timing {
    /// The shortest duration in which every joint moves its `delta` with the shape `profile`
    /// within `rates` (see the module docs). Acceleration limits are ignored for
    /// [`Profile::Linear`], whose speed jumps at the ends.
    ///
    /// # Errors
    /// [`MotionError`] when `delta` has NaN/infinite values or not one value per limit.
    ///
    /// # Example
    /// Seed 000's three motors (notes 000 D8): `φ = (100, 400, 200)` pulses at 500 Hz.
    /// ```
    /// use reach::motion::{JointRates, Profile, Timing};
    /// let rates = JointRates::new(vec![500.0; 3], None).unwrap();
    /// let t = Timing::synchronised(&[100.0, 400.0, 200.0], &rates, Profile::Linear).unwrap();
    /// assert!((t.duration - 0.8).abs() < 1e-12);
    /// assert_eq!(t.limiting_joint, Some(1));
    /// assert!((t.peak_velocity[0] - 125.0).abs() < 1e-9);
    /// assert!((t.peak_velocity[2] - 250.0).abs() < 1e-9);
    /// ```
    pub fn synchronised(delta: &[f64], rates: &JointRates, profile: Profile) -> Result<Timing, MotionError> {
        check_delta(delta, rates)?;
        let (pv, pa) = (profile.peak_velocity(), profile.peak_acceleration());
        let mut duration = 0.0;
        let mut limiting = None;
        for (i, d) in delta.iter().enumerate() {
            let d = d.abs();
            let mut need = pv * d / rates.velocity[i];
            if let Some(acc) = &rates.acceleration
                && pa > 0.0
            {
                need = need.max((pa * d / acc[i]).sqrt());
            }
            if need > duration {
                duration = need;
                limiting = Some(i);
            }
        }
        Ok(finish(delta, duration, limiting, profile))
    }

    /// The shortest synchronised trapezoidal motion: the duration and the acceleration
    /// fraction are both chosen (see the module docs). Needs acceleration limits.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] when `rates` has no acceleration limits; the errors of
    /// [`Timing::synchronised`].
    ///
    /// # Example
    /// ```
    /// use reach::motion::{JointRates, Profile, Timing};
    /// let rates = JointRates::new(vec![1.0, 1.0], Some(vec![2.0, 2.0])).unwrap();
    /// let t = Timing::synchronised_trapezoid(&[1.0, -0.5], &rates).unwrap();
    /// assert!((t.duration - 1.5).abs() < 1e-12); // 1/1 + 1/2
    /// assert!((t.peak_velocity[1] - 0.5).abs() < 1e-12);
    /// ```
    pub fn synchronised_trapezoid(delta: &[f64], rates: &JointRates) -> Result<Timing, MotionError> {
        check_delta(delta, rates)?;
        let Some(acc) = &rates.acceleration else {
            return Err(MotionError::InvalidInput {
                field: "acceleration".into(),
                reason: "limits are needed for a trapezoidal profile".into(),
            });
        };
        let (mut v_demand, mut a_demand) = (0.0_f64, 0.0_f64);
        let (mut v_joint, mut a_joint) = (None, None);
        for (i, d) in delta.iter().enumerate() {
            let (v, a) = (d.abs() / rates.velocity[i], d.abs() / acc[i]);
            if v > v_demand {
                v_demand = v;
                v_joint = Some(i);
            }
            if a > a_demand {
                a_demand = a;
                a_joint = Some(i);
            }
        }
        let (fraction, duration) = trapezoid_shape(v_demand, a_demand);
        // The speed-limited joint sets the pace unless the profile is triangular.
        let limiting = if fraction < 0.5 { v_joint } else { a_joint };
        Ok(finish(delta, duration, limiting, Profile::Trapezoidal { accel_fraction: fraction }))
    }
}

fn check_delta(delta: &[f64], rates: &JointRates) -> Result<(), MotionError> {
    super::check_vector("delta", delta, rates.len())
}

fn finish(delta: &[f64], duration: f64, limiting: Option<usize>, profile: Profile) -> Timing {
    let (pv, pa) = (profile.peak_velocity(), profile.peak_acceleration());
    let scale = |k: f64, power: i32| -> Vec<f64> {
        delta.iter().map(|d| if duration > 0.0 { k * d.abs() / duration.powi(power) } else { 0.0 }).collect()
    };
    Timing {
        duration,
        profile,
        limiting_joint: if duration > 0.0 { limiting } else { None },
        peak_velocity: scale(pv, 1),
        peak_acceleration: scale(pa, 2),
    }
}
