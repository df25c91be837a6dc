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

/// Relative tolerance under which two joint axes (the angular columns of the Jacobian) count
/// as parallel for [`Manipulability::position`]: `|zᵢ × zⱼ| ≤ 1e-9·|zᵢ||zⱼ|`, far above the
/// rounding of a frame product and far below any axis that is meant to be tilted.
const PARALLEL_AXES: f64 = 1e-9;

impl Manipulability {
    /// Measures of the **position** task: the singular values of the three translational rows,
    /// truncated to the dimension of the space the tool point can move in — 2 for a planar arm
    /// (every joint revolute, all axes parallel: the third singular value is zero at every
    /// configuration, so it says nothing about the configuration), else `min(3, n)`.
    ///
    /// # Example
    /// ```
    /// use reach::kinematics::Manipulability;
    /// let robot = reach::model::presets::get("planar3").unwrap();
    /// let d = f64::to_radians;
    /// // Unit links at q = (0°, 90°, −90°): J_p = [[−1, −1, 0], [2, 1, 1]], so
    /// // J_p J_pᵀ = [[2, −3], [−3, 6]] with eigenvalues 4 ± √13.
    /// let m = Manipulability::position(&robot.jacobian(&[0.0, d(90.0), d(-90.0)]).unwrap());
    /// assert_eq!(m.singular_values.len(), 2);
    /// assert!((m.sigma_max - (4.0 + 13f64.sqrt()).sqrt()).abs() < 1e-12);
    /// assert!((m.sigma_min - (4.0 - 13f64.sqrt()).sqrt()).abs() < 1e-12);
    /// ```
    #[must_use]
    pub fn position(jacobian: &Jacobian) -> Manipulability {
        let mut m = Manipulability::of(jacobian, JacobianAxes::Translation);
        if planar(jacobian) && m.singular_values.len() > 2 {
            m.singular_values.truncate(2);
            m.sigma_min = m.singular_values[1];
            m.yoshikawa = m.sigma_max * m.sigma_min;
            m.condition = if m.sigma_min > 0.0 { m.sigma_max / m.sigma_min } else { f64::INFINITY };
            let floor = SINGULAR_VALUE_RELATIVE * m.sigma_max.max(f64::MIN_POSITIVE);
            m.rank = m.singular_values.iter().filter(|&&s| s > floor).count();
        }
        m
    }
}

/// Whether every joint is revolute (a non-zero angular column) and all axes are parallel.
fn planar(jacobian: &Jacobian) -> bool {
    let axis = |c: usize| nalgebra::Vector3::new(jacobian[(3, c)], jacobian[(4, c)], jacobian[(5, c)]);
    let first = axis(0);
    jacobian.ncols() > 0
        && (0..jacobian.ncols()).all(|c| {
            let z = axis(c);
            z.norm() > 0.0 && first.cross(&z).norm() <= PARALLEL_AXES * first.norm() * z.norm()
        })
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
