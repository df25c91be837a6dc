//! Tool-space motion (seed 001 §3.7): the tool point moves on a straight line and the tool
//! turns about one fixed axis.
//!
//! # The method (notes 001 §3.7, corrected)
//!
//! Given the start pose `T0 = (R0, p0)` and the end pose `T1 = (R1, p1)`:
//!
//! * `Rf = R0ᵀ·R1` is the rotation to do, in the start tool frame;
//! * its angle `φ1 ∈ [0, π]` and unit axis `e` (in the start tool frame): the thesis's
//!   `φ1 = acos((tr Rf − 1)/2)`, `e = vee(Rf − Rfᵀ)/(2 sin φ1)` — computed here as
//!   `φ1 = atan2(½‖vee‖, (tr Rf − 1)/2)` (accurate at every angle) with the axis from `vee`
//!   when `φ1 ≤ 3π/4` and from the symmetric part `(Rf + Rfᵀ)/2 − cos φ1·I = (1 − cos φ1)·eeᵀ`
//!   otherwise (its largest column, signed to agree with `vee`): this is the robust form near
//!   `φ1 = π`, where `sin φ1 → 0` and the thesis's division fails. Below
//!   [`ROTATION_ANGLE_ZERO`] the motion is a pure translation and `e` is taken as z
//!   (notes 001 §4.4 "edge cases not handled");
//! * `ρ1 = R0ᵀ·(p1 − p0)`, the displacement in the start tool frame;
//! * `T(t) = T0·A(t)`, `A = (Rodrigues(e, λ·φ1), λ·ρ1)` with `λ = λ(τ)` of the
//!   [`Profile`]. The thesis prints `φ(t)` and `ρ(t)` as the *velocity* profile scaled by ½
//!   (which gives `φ(t1) = 0`) and without `R0ᵀ`; the code and this module use `φ = λ·φ1`,
//!   `ρ = λ·R0ᵀ(p1 − p0)` (notes 001 §6.1 item 4).
//!
//! So the tool point is `p0 + λ·(p1 − p0)`, on the straight segment at every instant, and the
//! orientation `R0·Rot(e, λφ1)` is the geodesic (SLERP) between `R0` and `R1`.
//!
//! # Constant speed
//!
//! [`ToolMotion::at_speed`] builds a [`Profile::Linear`] motion whose tool point moves at a
//! given speed (seed 003 §5: welding at 1 mm/s along a straight seam), duration `L / v`.

use std::f64::consts::FRAC_PI_4;

use nalgebra::{Isometry3, Rotation3, Translation3, Unit, UnitQuaternion, Vector3};

use super::sample::{PathSample, ToolPath, grid, sample_times};
use super::{MotionError, Profile, check_number};
use crate::tolerance::ROTATION_ANGLE_ZERO;

/// The tool frame of a straight weld seam from `start` to `end` (seed 003 §5.1–5.2): tool
/// x along the seam `n = (end − start)/|end − start|`, tool y horizontal and across it
/// `e6 = (y₁ − y₂, x₂ − x₁, 0)/|…|`, tool z `l = n × e6`; origin at `start` (world frame).
///
/// # Errors
/// [`MotionError::InvalidInput`] (field `seam`) for a non-finite point, a seam of zero length
/// or a vertical seam (no horizontal direction across it).
pub fn seam_frame(start: &Vector3<f64>, end: &Vector3<f64>) -> Result<Isometry3<f64>, MotionError> {
    let invalid = |reason: &str| MotionError::InvalidInput { field: "seam".into(), reason: reason.into() };
    if !(start.iter().chain(end.iter()).all(|v| v.is_finite())) {
        return Err(invalid("must be finite"));
    }
    let along = end - start;
    let across = Vector3::new(-along.y, along.x, 0.0);
    if along.norm() == 0.0 || across.norm() <= along.norm() * 1e-12 {
        return Err(invalid("needs two distinct points that are not on one vertical line"));
    }
    let n = along.normalize();
    let e6 = across.normalize();
    let rotation = Rotation3::from_basis_unchecked(&[n, e6, n.cross(&e6)]);
    Ok(Isometry3::from_parts(Translation3::from(*start), UnitQuaternion::from_rotation_matrix(&rotation)))
}

/// Angle `φ ∈ [0, π]` and unit axis of a rotation matrix (see the module docs); the axis is z
/// when the angle is below [`ROTATION_ANGLE_ZERO`].
///
/// # Example
/// ```
/// use nalgebra::{Rotation3, Vector3};
/// use reach::motion::tool_space::axis_angle;
/// let r = Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
/// let (axis, angle) = axis_angle(&r);
/// assert!((angle - std::f64::consts::PI).abs() < 1e-12);
/// assert!((axis.x.abs() - 1.0).abs() < 1e-12);
/// ```
#[must_use]
pub fn axis_angle(r: &Rotation3<f64>) -> (Unit<Vector3<f64>>, f64) {
    let m = r.matrix();
    let vee = Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]);
    let cos = (0.5 * (m.trace() - 1.0)).clamp(-1.0, 1.0);
    let angle = (0.5 * vee.norm()).atan2(cos);
    if angle < ROTATION_ANGLE_ZERO {
        return (Vector3::z_axis(), 0.0);
    }
    if angle <= 3.0 * FRAC_PI_4 {
        return (Unit::new_normalize(vee), angle);
    }
    // (R + Rᵀ)/2 − cos φ·I = (1 − cos φ)·e·eᵀ: take its largest column.
    let sym = (m + m.transpose()) * 0.5 - nalgebra::Matrix3::identity() * cos;
    let k = (0..3).max_by(|&a, &b| sym[(a, a)].total_cmp(&sym[(b, b)])).unwrap_or(0);
    let mut axis = sym.column(k).into_owned();
    if axis.dot(&vee) < 0.0 {
        axis = -axis;
    }
    (Unit::new_normalize(axis), angle)
}

/// A tool-space motion between two poses (see the module docs).
///
/// # Example
/// Seed 001's example (notes 001 §5.2): a 120° turn about `(1, −1, 1)/√3` of the start tool
/// frame, the tool point on the segment (3, 0, 5) → (0, 3, 5).
/// ```
/// use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
/// use reach::motion::{Profile, ToolMotion};
/// let pose = |r: [[f64; 3]; 3], p: [f64; 3]| Isometry3::from_parts(
///     Translation3::new(p[0], p[1], p[2]),
///     UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(Matrix3::from_fn(|i, j| r[i][j]))));
/// let t0 = pose([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]], [3.0, 0.0, 5.0]);
/// let t1 = pose([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]], [0.0, 3.0, 5.0]);
/// let m = ToolMotion::new(t0, t1, 0.0, 10.0, Profile::Cycloidal).unwrap();
/// assert!((m.angle().to_degrees() - 120.0).abs() < 1e-9);
/// let k = 1.0 / 3f64.sqrt();
/// assert!((m.axis().into_inner() - nalgebra::Vector3::new(k, -k, k)).norm() < 1e-12);
/// let mid = m.pose_at(5.0);
/// assert!((mid.translation.vector - nalgebra::Vector3::new(1.5, 1.5, 5.0)).norm() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ToolMotion {
    start: Isometry3<f64>,
    end: Isometry3<f64>,
    axis: Unit<Vector3<f64>>,
    angle: f64,
    displacement: Vector3<f64>,
    t0: f64,
    duration: f64,
    profile: Profile,
}

impl ToolMotion {
    /// A motion from `start` to `end` over `[t0, t0 + duration]` with the time law `profile`.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] when a pose holds NaN/infinity, `t0` is not finite or
    /// `duration` is not a positive finite number.
    pub fn new(
        start: Isometry3<f64>,
        end: Isometry3<f64>,
        t0: f64,
        duration: f64,
        profile: Profile,
    ) -> Result<Self, MotionError> {
        check_pose("start", &start)?;
        check_pose("end", &end)?;
        check_number("t0", t0, false)?;
        check_number("duration", duration, true)?;
        let r0 = start.rotation.to_rotation_matrix();
        let rf = r0.transpose() * end.rotation.to_rotation_matrix();
        let (axis, angle) = axis_angle(&rf);
        let displacement = r0.transpose() * (end.translation.vector - start.translation.vector);
        Ok(ToolMotion { start, end, axis, angle, displacement, t0, duration, profile })
    }

    /// A constant-speed motion ([`Profile::Linear`]): the tool point moves at `speed` (m/s),
    /// taking `|p1 − p0| / speed` seconds; the rotation is spread evenly over that time.
    ///
    /// # Errors
    /// As [`ToolMotion::new`]; [`MotionError::InvalidInput`] when `speed` is not positive or the
    /// tool point does not move (a pure rotation has no duration at a tool speed).
    ///
    /// # Example
    /// Seed 003's weld (notes 003 §5.2): 943.928 mm at 1 mm/s.
    /// ```
    /// use nalgebra::Isometry3;
    /// use reach::motion::ToolMotion;
    /// let a = Isometry3::translation(0.050, 0.740, 0.070);
    /// let b = Isometry3::translation(0.500, 0.200, 0.700);
    /// let m = ToolMotion::at_speed(a, b, 0.0, 0.001).unwrap();
    /// assert!((m.duration() - 943.927963).abs() < 1e-6);
    /// ```
    pub fn at_speed(start: Isometry3<f64>, end: Isometry3<f64>, t0: f64, speed: f64) -> Result<Self, MotionError> {
        check_number("speed", speed, true)?;
        check_pose("start", &start)?;
        check_pose("end", &end)?;
        let length = (end.translation.vector - start.translation.vector).norm();
        if length <= 0.0 {
            return Err(MotionError::InvalidInput {
                field: "end".into(),
                reason: "has the start's position: a tool speed gives no duration for a pure rotation".into(),
            });
        }
        ToolMotion::new(start, end, t0, length / speed, Profile::Linear)
    }

    /// Start pose.
    #[must_use]
    pub fn start(&self) -> &Isometry3<f64> {
        &self.start
    }

    /// End pose.
    #[must_use]
    pub fn end(&self) -> &Isometry3<f64> {
        &self.end
    }

    /// Rotation axis `e`, unit, in the start tool frame.
    #[must_use]
    pub fn axis(&self) -> Unit<Vector3<f64>> {
        self.axis
    }

    /// Rotation axis in the world frame, `R0·e`.
    #[must_use]
    pub fn axis_world(&self) -> Unit<Vector3<f64>> {
        Unit::new_unchecked(self.start.rotation * self.axis.into_inner())
    }

    /// Total rotation angle `φ1 ∈ [0, π]`, radians.
    #[must_use]
    pub fn angle(&self) -> f64 {
        self.angle
    }

    /// Displacement `ρ1 = R0ᵀ(p1 − p0)` in the start tool frame, metres.
    #[must_use]
    pub fn displacement(&self) -> Vector3<f64> {
        self.displacement
    }

    /// Length of the tool point's path `|p1 − p0|`, metres.
    #[must_use]
    pub fn length(&self) -> f64 {
        self.displacement.norm()
    }

    /// Start time.
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// Duration, seconds.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// The time law.
    #[must_use]
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// `λ` at time `t` (clamped to the motion's interval).
    #[must_use]
    pub fn fraction_at(&self, t: f64) -> f64 {
        self.profile.position(((t - self.t0) / self.duration).clamp(0.0, 1.0))
    }

    /// The pose after the fraction `lambda` of the motion: `T0·(Rot(e, λφ1), λρ1)`; exactly
    /// `T1` at `λ = 1`.
    #[must_use]
    pub fn pose_at_fraction(&self, lambda: f64) -> Isometry3<f64> {
        if lambda >= 1.0 {
            return self.end;
        }
        let lambda = lambda.max(0.0);
        let a = Isometry3::from_parts(
            Translation3::from(lambda * self.displacement),
            UnitQuaternion::from_axis_angle(&self.axis, lambda * self.angle),
        );
        self.start * a
    }

    /// The pose after `s` metres of the tool point's path, `pose_at_fraction(s / L)` — an exact
    /// evaluator over arc length, e.g. for path tracking between samples. A path whose tool
    /// point does not move (`L = 0`) gives the start pose.
    #[must_use]
    pub fn pose_at_length(&self, s: f64) -> Isometry3<f64> {
        let length = self.length();
        if length > 0.0 { self.pose_at_fraction(s / length) } else { self.start }
    }

    /// The pose at time `t`.
    #[must_use]
    pub fn pose_at(&self, t: f64) -> Isometry3<f64> {
        self.pose_at_fraction(self.fraction_at(t))
    }

    /// Tool velocity at `t` in the world frame: (linear m/s, angular rad/s).
    #[must_use]
    pub fn velocity_at(&self, t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let tau = ((t - self.t0) / self.duration).clamp(0.0, 1.0);
        let rate = self.profile.eval(tau).velocity / self.duration;
        let r0 = self.start.rotation;
        (r0 * (rate * self.displacement), self.axis_world().into_inner() * (rate * self.angle))
    }

    fn sample_at(&self, t: f64, lambda: f64) -> PathSample {
        PathSample { t, s: lambda * self.length(), angle: lambda * self.angle, pose: self.pose_at_fraction(lambda) }
    }

    fn path(&self, samples: Vec<PathSample>) -> ToolPath {
        ToolPath { samples, length: self.length(), angle: self.angle }
    }

    /// Samples the motion every `dt` seconds, both ends included.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for a bad `dt`.
    pub fn sample_time(&self, dt: f64) -> Result<ToolPath, MotionError> {
        let times = sample_times(self.t0, self.duration, dt)?;
        let last = times.len() - 1;
        Ok(self.path(
            times
                .into_iter()
                .enumerate()
                .map(|(k, t)| self.sample_at(t, if k == last { 1.0 } else { self.fraction_at(t) }))
                .collect(),
        ))
    }

    /// Samples the motion every `ds` metres of the tool point's path, both ends included; the
    /// time of each sample is found by inverting the profile ([`Profile::inverse`]).
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for a bad `ds`, or when the tool point does not move.
    pub fn sample_length(&self, ds: f64) -> Result<ToolPath, MotionError> {
        let length = self.length();
        if length <= 0.0 {
            return Err(MotionError::InvalidInput {
                field: "ds".into(),
                reason: "the tool point does not move: sample by time instead".into(),
            });
        }
        let arcs = grid(0.0, length, ds, "length", "ds")?;
        let last = arcs.len() - 1;
        Ok(self.path(
            arcs.into_iter()
                .enumerate()
                .map(|(k, s)| {
                    let lambda = if k == last { 1.0 } else { s / length };
                    let t = self.t0 + self.profile.inverse(lambda) * self.duration;
                    self.sample_at(t, lambda)
                })
                .collect(),
        ))
    }
}

fn check_pose(which: &str, pose: &Isometry3<f64>) -> Result<(), MotionError> {
    let finite =
        pose.translation.vector.iter().all(|v| v.is_finite()) && pose.rotation.coords.iter().all(|v| v.is_finite());
    if finite {
        Ok(())
    } else {
        Err(MotionError::InvalidInput { field: which.into(), reason: "pose contains NaN or infinity".into() })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn axis_angle_is_robust_at_zero_and_pi() {
        for axis in [Vector3::new(1.0, 2.0, -0.5), Vector3::new(0.0, 0.0, -1.0), Vector3::new(-1.0, 1.0, 1.0)] {
            let axis = Unit::new_normalize(axis);
            for angle in [0.0, 1e-12, 1e-7, 0.3, 2.0, 3.0 * FRAC_PI_4, 2.5, PI - 1e-7, PI - 1e-12, PI] {
                let r = Rotation3::from_axis_angle(&axis, angle);
                let (e, phi) = axis_angle(&r);
                assert!((phi - angle).abs() < 1e-9, "{angle}: {phi}");
                // Whatever axis is returned, rotating by φ about it gives R back.
                let back = Rotation3::from_axis_angle(&e, phi);
                assert!((back.matrix() - r.matrix()).amax() < 1e-9, "{angle}");
                if angle > 1e-6 && angle < PI - 1e-6 {
                    assert!((e.into_inner() - axis.into_inner()).norm() < 1e-6, "{angle}");
                }
            }
        }
    }
}

#[cfg(test)]
mod seam_tests {
    use super::*;

    #[test]
    fn seed_003_seam_frame() {
        // Notes 003 §5.2: P = (50, 740, 70) mm to M = (500, 200, 700) mm gives
        // n ≈ (0.476731, −0.572078, 0.667424) and l ≈ (−0.427274, 0.512729, 0.744678).
        let f = seam_frame(&Vector3::new(0.05, 0.74, 0.07), &Vector3::new(0.5, 0.2, 0.7)).unwrap();
        let r = f.rotation.to_rotation_matrix();
        for (got, want) in r.matrix().column(0).iter().zip([0.476731, -0.572078, 0.667424]) {
            assert!((got - want).abs() < 1e-6, "{r}");
        }
        for (got, want) in r.matrix().column(2).iter().zip([-0.427274, 0.512729, 0.744678]) {
            assert!((got - want).abs() < 1e-6, "{r}");
        }
        assert!(r.matrix().column(1)[2].abs() < 1e-15, "tool y is horizontal");
        assert!(seam_frame(&Vector3::zeros(), &Vector3::new(0.0, 0.0, 1.0)).is_err());
        assert!(seam_frame(&Vector3::zeros(), &Vector3::new(f64::NAN, 0.0, 1.0)).is_err());
    }
}
