//! Effort and energy: the seeds' kinematic cost functionals J1, J2 and S, and (in
//! [`dynamics`]) the physical model — Newton–Euler joint torques and the mechanical energy
//! `∫ Σ|τᵢ·q̇ᵢ| dt` of a motion, for robots whose description gives link masses.
//!
//! These are the seeds' stand-ins for energy, computed from joint values only (no masses):
//!
//! * [`j1`] — seed 001 §3.8: `J1 = Σᵢ wᵢ·|qᵢ(t1) − qᵢ(t0)|`, the weighted joint excursion of a
//!   point-to-point motion whose joints move monotonically;
//! * [`j2`] — seed 001 §3.8: `J2 = Σᵢ wᵢ·Σₖ |qᵢ(tₖ₊₁) − qᵢ(tₖ)|`, the weighted **total
//!   variation** of the sampled joint motion, which counts every reversal and jump. The thesis
//!   writes it as a sum over the local extrema of `qᵢ(t)` ("k = 2 when there are none", an
//!   indexing slip, notes 001 §3.8 / §6.1 item 10); for sampled data the two are the same;
//!   for a monotone motion `J2 = J1`;
//! * [`total_change`] — seed 000's `S = Σᵢ |Δqᵢ|` (unweighted; notes 000 §4.1 step 4), the
//!   criterion its IK uses to choose among configurations (there in degrees, here radians).
//!
//! The weights default to seed 001's [`DEFAULT_SIX_JOINT_WEIGHTS`] `(1/3, 1/3, 1/6, 1/18, 1/18, 1/18)`,
//! "determined from the dynamic characteristics" (no derivation given): proximal joints,
//! which move more mass, weigh more.
//!
//! # Differences and wrapping
//!
//! [`Differences`] says how a joint difference is taken: literally, or as the shortest signed
//! angle `wrap(b − a)` ("wrap-safe": an IK that reports −179° after +179° has moved 2°, not
//! 358°). [`Differences::for_robot`] is the crate's one rule,
//! [`Joint::difference`](crate::model::Joint::difference): the distance a joint travels —
//! wrapped for a revolute joint without limits, literal for every bounded or prismatic joint —
//! the same difference a [`JointMotion`](crate::motion::JointMotion) interpolates, times and
//! costs, so J1 of a monotone move equals its J2.

pub mod dynamics;

use serde::Serialize;
use thiserror::Error;

use crate::model::Robot;

/// The default joint weights of a six-joint arm, `ω = (1/3, 1/3, 1/6, 1/18, 1/18, 1/18)`:
/// seed 001's weights (notes 001 §3.8, §7), heavier on the base joints that move more mass.
pub const DEFAULT_SIX_JOINT_WEIGHTS: [f64; 6] = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0];

/// Bad input to an effort functional.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum EffortError {
    /// A vector does not have the expected length.
    #[error("`{field}` has {found} values, expected {expected}")]
    Length {
        /// The offending field (`q1`, `weights`, `sample 3`, …).
        field: String,
        /// Needed length.
        expected: usize,
        /// Given length.
        found: usize,
    },
    /// A value is NaN or infinite, or a weight is negative.
    #[error("`{field}` must be a finite number{extra}, got {value}")]
    InvalidValue {
        /// The offending field.
        field: String,
        /// The value.
        value: f64,
        /// Further condition (`" ≥ 0"` for weights).
        extra: &'static str,
    },
    /// No samples were given.
    #[error("a trajectory needs at least one sample")]
    Empty,
}

/// How joint differences are taken (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub enum Differences {
    /// `b − a` for every joint.
    Literal,
    /// `wrap(b − a) ∈ (−π, π]` for every joint.
    Wrapped,
    /// Per joint: `true` wraps, `false` is literal.
    PerJoint(Vec<bool>),
}

impl Differences {
    /// The robot's own rule, [`Joint::difference`](crate::model::Joint::difference): wrapped for
    /// revolute joints without limits, literal for every other joint.
    #[must_use]
    pub fn for_robot(robot: &Robot) -> Self {
        Differences::PerJoint(robot.joints().iter().map(crate::model::Joint::wraps).collect())
    }

    /// The difference from `a` to `b` for joint `i` (0-based).
    #[must_use]
    #[inline]
    pub fn diff(&self, i: usize, a: f64, b: f64) -> f64 {
        let wrap = match self {
            Differences::Literal => false,
            Differences::Wrapped => true,
            Differences::PerJoint(w) => w.get(i).copied().unwrap_or(false),
        };
        if wrap { crate::angle::wrap(b - a) } else { b - a }
    }

    fn check(&self, n: usize) -> Result<(), EffortError> {
        if let Differences::PerJoint(w) = self
            && w.len() != n
        {
            return Err(EffortError::Length { field: "differences".into(), expected: n, found: w.len() });
        }
        Ok(())
    }
}

fn check_values(field: &str, values: &[f64], n: usize) -> Result<(), EffortError> {
    if values.len() != n {
        return Err(EffortError::Length { field: field.into(), expected: n, found: values.len() });
    }
    for (i, &v) in values.iter().enumerate() {
        if !v.is_finite() {
            return Err(EffortError::InvalidValue { field: format!("{field}[{}]", i + 1), value: v, extra: "" });
        }
    }
    Ok(())
}

/// The joint weights of `robot` for [`j1`]/[`j2`]: `weights` when given, checked, else the
/// default — seed 001's [`DEFAULT_SIX_JOINT_WEIGHTS`] for a six-joint robot, 1 for every joint otherwise.
///
/// # Errors
/// [`EffortError::Length`] when `weights` does not have one value per joint;
/// [`EffortError::InvalidValue`] naming the first weight (`weights[i]`, 1-based) that is NaN,
/// infinite or negative.
pub fn joint_weights(robot: &Robot, weights: Option<&[f64]>) -> Result<Vec<f64>, EffortError> {
    let n = robot.dof();
    match weights {
        Some(w) => {
            check_weights(w, n)?;
            Ok(w.to_vec())
        }
        None if n == 6 => Ok(DEFAULT_SIX_JOINT_WEIGHTS.to_vec()),
        None => Ok(vec![1.0; n]),
    }
}

fn check_weights(weights: &[f64], n: usize) -> Result<(), EffortError> {
    check_values("weights", weights, n)?;
    for (i, &w) in weights.iter().enumerate() {
        if w < 0.0 {
            return Err(EffortError::InvalidValue { field: format!("weights[{}]", i + 1), value: w, extra: " ≥ 0" });
        }
    }
    Ok(())
}

/// `J1 = Σ wᵢ·|diff(q0ᵢ, q1ᵢ)|` (seed 001 §3.8).
///
/// # Errors
/// [`EffortError`] when the vectors and weights differ in length, hold NaN/infinity, or a
/// weight is negative.
///
/// # Example
/// Seed 001's joint-space example: home → (90°, 0, 0, 90°, 0, 0), `J1 = π/6 + π/36 = 7π/36`.
/// ```
/// use reach::effort::{Differences, DEFAULT_SIX_JOINT_WEIGHTS, j1};
/// use std::f64::consts::{FRAC_PI_2, PI};
/// let q1 = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, 0.0, 0.0];
/// let j = j1(&[0.0; 6], &q1, &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::Literal).unwrap();
/// assert!((j - 7.0 * PI / 36.0).abs() < 1e-15);
/// ```
pub fn j1(q0: &[f64], q1: &[f64], weights: &[f64], differences: &Differences) -> Result<f64, EffortError> {
    let n = q0.len();
    check_values("q0", q0, n)?;
    check_values("q1", q1, n)?;
    check_weights(weights, n)?;
    differences.check(n)?;
    Ok((0..n).map(|i| weights[i] * differences.diff(i, q0[i], q1[i]).abs()).sum())
}

/// `J1 = Σ wᵢ·|Δqᵢ|` for the joint differences a motion travels (e.g.
/// [`JointMotion::delta`](crate::motion::JointMotion::delta)).
///
/// # Errors
/// As [`j1`].
pub fn j1_of_delta(delta: &[f64], weights: &[f64]) -> Result<f64, EffortError> {
    check_values("delta", delta, delta.len())?;
    check_weights(weights, delta.len())?;
    Ok(delta.iter().zip(weights).map(|(d, w)| w * d.abs()).sum())
}

/// `J2 = Σᵢ wᵢ·Σₖ |diff(qᵢ(tₖ), qᵢ(tₖ₊₁))|`, the weighted total variation of sampled joint
/// vectors (seed 001 §3.8; see the module docs). One sample gives 0.
///
/// # Errors
/// [`EffortError::Empty`] for no samples; as [`j1`] for lengths and values (the sample is named).
///
/// # Example
/// A joint that goes 0 → 1 → 0.5 travels 1.5; wrapped, 3.1 → −3.1 is a 0.083 step.
/// ```
/// use reach::effort::{Differences, j2};
/// let j = j2(&[[0.0], [1.0], [0.5]], &[2.0], &Differences::Literal).unwrap();
/// assert!((j - 3.0).abs() < 1e-15);
/// let j = j2(&[[3.1], [-3.1]], &[1.0], &Differences::Wrapped).unwrap();
/// assert!((j - (std::f64::consts::TAU - 6.2)).abs() < 1e-12);
/// ```
pub fn j2<Q: AsRef<[f64]>>(samples: &[Q], weights: &[f64], differences: &Differences) -> Result<f64, EffortError> {
    let first = samples.first().ok_or(EffortError::Empty)?.as_ref();
    let n = first.len();
    check_weights(weights, n)?;
    differences.check(n)?;
    for (k, s) in samples.iter().enumerate() {
        check_values(&format!("sample {k}"), s.as_ref(), n)?;
    }
    let mut total = 0.0;
    for pair in samples.windows(2) {
        let (a, b) = (pair[0].as_ref(), pair[1].as_ref());
        total += (0..n).map(|i| weights[i] * differences.diff(i, a[i], b[i]).abs()).sum::<f64>();
    }
    Ok(total)
}

/// Seed 000's `S = Σᵢ |diff(q0ᵢ, q1ᵢ)|`, the unweighted total joint change (radians / metres).
///
/// # Errors
/// As [`j1`].
///
/// # Example
/// ```
/// use reach::effort::{Differences, total_change};
/// let s = total_change(&[0.1, 0.2, 0.3], &[0.2, 0.0, 0.3], &Differences::Literal).unwrap();
/// assert!((s - 0.3).abs() < 1e-15);
/// ```
pub fn total_change(q0: &[f64], q1: &[f64], differences: &Differences) -> Result<f64, EffortError> {
    j1(q0, q1, &vec![1.0; q0.len()], differences)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn joint_weights_default_and_checks() {
        let six = presets::get("spbu6").unwrap();
        assert_eq!(joint_weights(&six, None).unwrap(), DEFAULT_SIX_JOINT_WEIGHTS.to_vec());
        let given = [1.0, 2.0, 0.0, 0.5, 0.5, 0.5];
        assert_eq!(joint_weights(&six, Some(&given)).unwrap(), given.to_vec());
        let other = presets::names().into_iter().map(|n| presets::get(n).unwrap()).find(|r| r.dof() != 6).unwrap();
        assert_eq!(joint_weights(&other, None).unwrap(), vec![1.0; other.dof()]);
        assert!(matches!(joint_weights(&six, Some(&[1.0; 5])), Err(EffortError::Length { expected: 6, found: 5, .. })));
        for (bad, field) in [(-1.0, "weights[2]"), (f64::NAN, "weights[2]"), (f64::INFINITY, "weights[2]")] {
            let w = [1.0, bad, 1.0, 1.0, 1.0, 1.0];
            match joint_weights(&six, Some(&w)) {
                Err(EffortError::InvalidValue { field: f, .. }) => assert_eq!(f, field),
                other => panic!("expected an invalid weight, got {other:?}"),
            }
        }
    }
}
