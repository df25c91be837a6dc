//! Motion: time profiles, joint- and tool-space motion, synchronised timing, path tracking
//! through IK with branch continuity, singular positions, intervals and events.
//!
//! # The pieces
//!
//! * [`profile`] — normalised time laws `λ(τ)`, `τ ∈ [0, 1]`: linear (constant speed),
//!   cycloidal (seed 001), quintic, trapezoidal velocity (with the triangular case).
//! * [`timing`] — synchronised timing: the duration is set by the joint that needs longest
//!   and every joint starts and stops together (seed 000's intent, corrected: notes 000 D8).
//! * [`optimal`] — time-optimal motion along a joint path (TOPP-RA) under velocity and
//!   acceleration limits, proven within them between the grid points; the path a not-a-knot
//!   cubic spline or a polyline through waypoints ([`PiecewiseCubic`]).
//! * [`joint_space`] — `q(t) = q0 + λ(τ)·Δq` between two joint vectors or two poses (IK at
//!   both ends), and through several waypoints (stopping at each, [`JointPath`], or smoothly,
//!   [`SmoothJointPath`]).
//! * [`tool_space`] — seed 001's tool motion: the tool point on a straight line, the
//!   orientation turning about one fixed axis (Rodrigues).
//! * [`sample`] — sampled paths: [`sample::ToolPath`] (time, arc length, pose per sample),
//!   [`sample::JointTrajectory`] (time, joint vector per sample) and a simple per-sample IK
//!   ([`sample::ToolPath::to_joints`]). These are the plain values the path tracking and the
//!   effort functionals consume.
//! * `tracking` — path tracking with branch continuity (its own module docs).
//!
//! # Time
//!
//! A motion runs over `[t0, t0 + T]`; the normalised time is `τ = (t − t0)/T` (seed 001's
//! `t/(t1 − t0)` is right only for `t0 = 0`, notes 001 §6.1 item 11). Times outside the
//! interval are clamped: the motion rests at its end points.

pub mod jerk;
pub mod joint_space;
pub mod optimal;
pub mod profile;
pub mod sample;
pub mod timing;
pub mod tool_space;
pub mod tracking;

use thiserror::Error;

use crate::ik::{IkError, IkFailure};
use crate::kinematics::KinematicsError;

pub use jerk::{JerkLimitedMotion, jerk_limited, jerk_limits};
pub use joint_space::{JointMotion, JointPath, SmoothJointPath};
pub use optimal::{
    LimitRatios, MotionSample, OptimalMotion, PathLimits, PiecewiseCubic, check_blend_tolerance, time_optimal,
};
pub use profile::{Profile, ProfileValue};
pub use sample::{JointSample, JointTrajectory, PathSample, ToolPath};
pub use timing::{JointRates, Timing};
pub use tool_space::ToolMotion;

/// Why a motion could not be built or sampled.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum MotionError {
    /// A number is NaN, infinite or outside its domain (the field is named).
    #[error("invalid motion input: `{field}` {reason}")]
    InvalidInput {
        /// The offending field (`duration`, `dt`, `q0[3]`, …).
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A vector does not have one value per joint.
    #[error("`{field}` has {found} values, expected {expected} (one per joint)")]
    Length {
        /// The offending field.
        field: String,
        /// Needed length.
        expected: usize,
        /// Given length.
        found: usize,
    },
    /// Inverse kinematics found no solution for a pose of the motion.
    #[error("no IK solution for {which}: {failure}")]
    NoIkSolution {
        /// Which pose (`start pose`, `end pose`, `sample 12 (t = 1.2 s)`).
        which: String,
        /// The solver's reason.
        failure: IkFailure,
    },
    /// The IK solver rejected its input.
    #[error(transparent)]
    Ik(#[from] IkError),
    /// Forward kinematics rejected a joint vector.
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}

/// Checks that `value` is finite (and, if `positive`, strictly positive).
pub(crate) fn check_number(field: &str, value: f64, positive: bool) -> Result<(), MotionError> {
    if !value.is_finite() {
        return Err(MotionError::InvalidInput { field: field.into(), reason: format!("must be finite, got {value}") });
    }
    if positive && value <= 0.0 {
        return Err(MotionError::InvalidInput { field: field.into(), reason: format!("must be > 0, got {value}") });
    }
    Ok(())
}

/// Checks that every entry of `values` is finite and that there are `expected` of them.
pub(crate) fn check_vector(field: &str, values: &[f64], expected: usize) -> Result<(), MotionError> {
    if values.len() != expected {
        return Err(MotionError::Length { field: field.into(), expected, found: values.len() });
    }
    for (i, v) in values.iter().enumerate() {
        check_number(&format!("{field}[{}]", i + 1), *v, false)?;
    }
    Ok(())
}
