//! Forward kinematics, the geometric Jacobian and manipulability measures.
//!
//! All methods are on [`Robot`](crate::model::Robot):
//!
//! * [`fk`](crate::model::Robot::fk) — tool pose as an `Isometry3` (quaternion rotation);
//! * [`fk_matrix`](crate::model::Robot::fk_matrix) — tool pose with a rotation matrix (the
//!   fastest form; no allocation);
//! * [`frames`](crate::model::Robot::frames) / [`frames_into`](crate::model::Robot::frames_into)
//!   — every link frame;
//! * [`jacobian`](crate::model::Robot::jacobian) /
//!   [`jacobian_into`](crate::model::Robot::jacobian_into) — the 6×n geometric Jacobian in
//!   the base (world) frame, rows `vx vy vz ωx ωy ωz`, for the tool point;
//! * [`manipulability`](crate::model::Robot::manipulability) — Yoshikawa's measure and the
//!   singular values.
//!
//! The joint vector is checked on every call (length and finiteness); the checks are cheap
//! and keep NaN from spreading silently.

mod forward;
mod jacobian;
pub(crate) mod lanes;
mod manipulability;

pub use forward::JointAxis;
pub use jacobian::Jacobian;
pub use manipulability::{JacobianAxes, Manipulability};

pub(crate) use lanes::{FrameLanes, Lanes};

use thiserror::Error;

/// Why a kinematics query was rejected.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum KinematicsError {
    /// The joint vector does not have one value per joint.
    #[error("expected {expected} joint values, got {found}")]
    JointCount {
        /// The robot's number of joints.
        expected: usize,
        /// Length of the given vector.
        found: usize,
    },
    /// A joint value is NaN or infinite.
    #[error("joint {joint}: value must be a finite number, got {value}")]
    NonFinite {
        /// 1-based joint number.
        joint: usize,
        /// The offending value.
        value: f64,
    },
    /// An output buffer has the wrong size.
    #[error("output buffer `{buffer}` has room for {found} entries, needs {expected}")]
    BufferSize {
        /// Which buffer.
        buffer: &'static str,
        /// Needed size.
        expected: usize,
        /// Given size.
        found: usize,
    },
}

/// Checks that `q` has `dof` finite values.
///
/// One pass without branches decides (the compiler vectorises it); the first bad joint is
/// looked for only when there is one. (The search alone, a branch per value, took 54
/// instructions per call for 6 joints, 4 % of `fk_matrix`.)
#[inline]
pub(crate) fn check_q(dof: usize, q: &[f64]) -> Result<(), KinematicsError> {
    if q.len() != dof {
        return Err(KinematicsError::JointCount { expected: dof, found: q.len() });
    }
    if !q.iter().fold(true, |finite, v| finite & v.is_finite())
        && let Some(i) = q.iter().position(|v| !v.is_finite())
    {
        return Err(KinematicsError::NonFinite { joint: i + 1, value: q[i] });
    }
    Ok(())
}
