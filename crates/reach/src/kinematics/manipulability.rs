use nalgebra::DMatrix;
use serde::Serialize;

use super::{Jacobian, KinematicsError};
use crate::model::Robot;
use crate::tolerance::SINGULAR_VALUE_RELATIVE;

/// Which rows of the Jacobian a measure uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JacobianAxes {
    /// All six rows (mixes metres and radians, as Yoshikawa's original measure).
    #[default]
    All,
    /// The three translational rows (position manipulability).
    Translation,
    /// The three rotational rows.
    Rotation,
}

/// Dexterity measures of a configuration, from the singular values of the Jacobian.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Manipulability {
    /// Yoshikawa's measure `√det(J Jᵀ)` (for n ≥ rows) or `√det(Jᵀ J)` (for n < rows):
    /// the product of the `min(rows, n)` singular values. Zero at a singularity.
    pub yoshikawa: f64,
    /// Smallest of the `min(rows, n)` singular values (distance to singularity).
    pub sigma_min: f64,
    /// Largest singular value.
    pub sigma_max: f64,
    /// `sigma_max / sigma_min` (infinite at a singularity).
    pub condition: f64,
    /// Numerical rank (singular values above `SINGULAR_VALUE_RELATIVE · sigma_max`).
    pub rank: usize,
    /// The singular values, largest first.
    pub singular_values: Vec<f64>,
}

impl Manipulability {
    /// Measures computed from a Jacobian (rows chosen by `axes`).
    #[must_use]
    pub fn of(jacobian: &Jacobian, axes: JacobianAxes) -> Manipulability {
        let rows = match axes {
            JacobianAxes::All => 0..6,
            JacobianAxes::Translation => 0..3,
            JacobianAxes::Rotation => 3..6,
        };
        let m = DMatrix::from_fn(rows.len(), jacobian.ncols(), |r, c| jacobian[(rows.start + r, c)]);
        let mut sv: Vec<f64> = m.singular_values().iter().copied().collect();
        sv.sort_by(|a, b| b.total_cmp(a));
        sv.truncate(rows.len().min(jacobian.ncols()));
        let sigma_max = sv.first().copied().unwrap_or(0.0);
        let sigma_min = sv.last().copied().unwrap_or(0.0);
        let rank = sv.iter().filter(|&&s| s > SINGULAR_VALUE_RELATIVE * sigma_max.max(f64::MIN_POSITIVE)).count();
        Manipulability {
            yoshikawa: sv.iter().product(),
            sigma_min,
            sigma_max,
            condition: if sigma_min > 0.0 { sigma_max / sigma_min } else { f64::INFINITY },
            rank,
            singular_values: sv,
        }
    }
}

impl Robot {
    /// Yoshikawa manipulability, singular values and condition number at `q`, over all six
    /// rows of the Jacobian (see [`Manipulability::of`] for other row sets).
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    pub fn manipulability(&self, q: &[f64]) -> Result<Manipulability, KinematicsError> {
        Ok(Manipulability::of(&self.jacobian(q)?, JacobianAxes::All))
    }
}
