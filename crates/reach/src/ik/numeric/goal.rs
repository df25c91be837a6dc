//! The target in the form the iteration uses: the weighted error vector of a pose, the
//! Jacobian rows that match it, and the rotation log (accurate near 0 and near π).

use nalgebra::{IsometryMatrix3, Matrix3, Vector3, Vector6};

use super::TaskAxes;
use crate::ik::IkTarget;
use crate::kinematics::Jacobian;

/// The orientation part of a goal.
pub(super) enum Orientation {
    /// Position only.
    None,
    /// The full target rotation matrix.
    Full(Matrix3<f64>),
    /// The target's z axis (approach direction).
    Approach(Vector3<f64>),
}

/// The target in the form the iteration uses.
pub(super) struct Goal {
    position: Vector3<f64>,
    orientation: Orientation,
    /// `1/L`: weight of the position rows.
    scale: f64,
}

impl Goal {
    pub(super) fn new(target: &IkTarget, axes: TaskAxes, length_scale: f64) -> Goal {
        let scale = 1.0 / length_scale;
        let position = target.position().coords;
        let orientation = match (target, axes) {
            (IkTarget::Position(_), _) | (_, TaskAxes::Position) => Orientation::None,
            (IkTarget::Pose(pose), TaskAxes::Pose) => Orientation::Full(*pose.rotation.to_rotation_matrix().matrix()),
            (IkTarget::Pose(pose), TaskAxes::PositionApproach) => {
                Orientation::Approach(pose.rotation.to_rotation_matrix().matrix().column(2).into_owned())
            }
        };
        Goal { position, orientation, scale }
    }

    /// Weighted error vector, position error (m) and orientation error (rad) of the pose `t`.
    #[inline]
    pub(super) fn error(&self, t: &IsometryMatrix3<f64>) -> (Vector6<f64>, f64, f64) {
        let dp = self.position - t.translation.vector;
        let (w, angle) = match &self.orientation {
            Orientation::Full(r) => rotation_log(&(r * t.rotation.matrix().transpose())),
            Orientation::Approach(z) => tilt(t.rotation.matrix(), z),
            Orientation::None => (Vector3::zeros(), 0.0),
        };
        let s = self.scale;
        (Vector6::new(dp.x * s, dp.y * s, dp.z * s, w.x, w.y, w.z), dp.norm(), angle)
    }

    /// Turns the geometric Jacobian at the pose `t` into the Jacobian of [`Goal::error`]
    /// (up to sign): position rows scaled by `1/L`; rotation rows kept (full pose), projected
    /// across the current approach axis (approach), or zeroed (position only).
    #[inline]
    pub(super) fn weigh(&self, jac: &mut Jacobian, t: &IsometryMatrix3<f64>) {
        for r in 0..3 {
            jac.row_mut(r).scale_mut(self.scale);
        }
        match &self.orientation {
            Orientation::Full(_) => {}
            Orientation::None => {
                for r in 3..6 {
                    jac.row_mut(r).fill(0.0);
                }
            }
            Orientation::Approach(_) => {
                // Only rotations across the current z axis tilt it: ω ↦ (I − z zᵀ) ω.
                let z: Vector3<f64> = t.rotation.matrix().column(2).into_owned();
                for c in 0..jac.ncols() {
                    let w = Vector3::new(jac[(3, c)], jac[(4, c)], jac[(5, c)]);
                    let p = w - z * z.dot(&w);
                    jac[(3, c)] = p.x;
                    jac[(4, c)] = p.y;
                    jac[(5, c)] = p.z;
                }
            }
        }
    }
}

/// Rotation vector (across the current z axis) that turns the z axis of `r` onto `target_z`,
/// and its angle.
pub(super) fn tilt(r: &Matrix3<f64>, target_z: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let z = r.column(2).into_owned();
    let cross = z.cross(target_z);
    let sin = cross.norm();
    let angle = sin.atan2(z.dot(target_z));
    if angle < 1e-6 {
        // θ / sin θ = 1 + θ²/6 + …
        return (cross * (1.0 + angle * angle / 6.0), angle);
    }
    if sin > 1e-12 {
        return (cross * (angle / sin), angle);
    }
    // Opposite axes: any axis across z will do; take the current x axis.
    (r.column(0).into_owned() * angle, angle)
}

/// Rotation vector (axis · angle, angle in [0, π]) of a rotation matrix, and the angle;
/// accurate near 0 and near π.
pub(crate) fn rotation_log(r: &Matrix3<f64>) -> (Vector3<f64>, f64) {
    let cos = ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0);
    // vee(R − Rᵀ) = 2 sin θ · axis
    let vee = Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]);
    let sin = 0.5 * vee.norm();
    let angle = sin.atan2(cos);
    if cos > -0.5 {
        // θ < 120°: θ / (2 sin θ) is well conditioned (series near 0).
        let k = if angle < 1e-6 { 0.5 + angle * angle / 12.0 } else { 0.5 * angle / sin };
        return (vee * k, angle);
    }
    // Near π the antisymmetric part vanishes; take the axis from the symmetric part
    // (R + Rᵀ)/2 − cos θ·I = (1 − cos θ)·axis·axisᵀ, column of the largest diagonal entry.
    let b = (r + r.transpose()) * 0.5 - Matrix3::identity() * cos;
    let i = (0..3).max_by(|&a, &c| b[(a, a)].total_cmp(&b[(c, c)])).unwrap_or(0);
    let col = b.column(i).into_owned();
    let norm = col.norm();
    if norm <= 0.0 {
        return (Vector3::zeros(), angle);
    }
    let mut axis = col / norm;
    if axis.dot(&vee) < 0.0 {
        axis = -axis;
    }
    (axis * angle, angle)
}
