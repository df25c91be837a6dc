//! Inertial data of the links (mass, centre of mass, inertia tensor) and gravity.

use nalgebra::{AbstractRotation, Isometry, Matrix3, Rotation3, SymmetricEigen, Vector3};

/// Standard gravity, m/s² (the default gravity is this value along −z of the world frame).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Tolerance of the symmetry, positive-semi-definiteness and triangle-inequality checks on an
/// inertia tensor, relative to its largest entry.
const INERTIA_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Mass properties of one link (the body moved by the joint of the same index).
///
/// # Frames
/// `com` and `inertia` are expressed in the **link frame** that [`Robot::frames`]
/// reports for that joint:
///
/// * standard DH: frame *i* at the far end of link *i* (after `Aᵢ`), as the Robotics
///   Toolbox's `r` and `I` of `Link` *i* (Corke);
/// * modified DH: frame *i* at joint *i*, attached to link *i* (Craig);
/// * URDF: the child link frame of the joint (the `<inertial>` origin of that link, with
///   fixed-joint children folded in).
///
/// `inertia` is taken about the centre of mass, with axes parallel to the link frame.
///
/// [`Robot::frames`]: crate::model::Robot::frames
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkInertial {
    /// Mass, kg (≥ 0).
    pub mass: f64,
    /// Centre of mass in the link frame, metres.
    pub com: Vector3<f64>,
    /// Inertia tensor about the centre of mass, axes of the link frame, kg·m²
    /// (symmetric, positive semi-definite).
    pub inertia: Matrix3<f64>,
}

impl LinkInertial {
    /// A point mass `mass` (kg) at `com` (m, link frame), no rotational inertia.
    #[must_use]
    pub fn point(mass: f64, com: Vector3<f64>) -> Self {
        LinkInertial { mass, com, inertia: Matrix3::zeros() }
    }

    /// A body with the inertia tensor given by its six entries (kg·m², about the centre of mass):
    /// `[ixx, iyy, izz, ixy, ixz, iyz]`.
    #[must_use]
    pub fn new(mass: f64, com: Vector3<f64>, [ixx, iyy, izz, ixy, ixz, iyz]: [f64; 6]) -> Self {
        #[rustfmt::skip]
        let inertia = Matrix3::new(
            ixx, ixy, ixz,
            ixy, iyy, iyz,
            ixz, iyz, izz,
        );
        LinkInertial { mass, com, inertia }
    }

    /// A massless, inertia-free link.
    #[must_use]
    pub fn zero() -> Self {
        LinkInertial::point(0.0, Vector3::zeros())
    }

    /// The same body described in another frame: `pose` places this body's frame in the new
    /// frame (new ← old). The inertia about the centre of mass is rotated, not shifted.
    /// `pose` may hold its rotation as a unit quaternion ([`nalgebra::Isometry3`]) or as a rotation matrix
    /// ([`nalgebra::IsometryMatrix3`], the type of the robot's frames).
    #[must_use]
    pub fn transformed<R>(&self, pose: &Isometry<f64, R, 3>) -> Self
    where
        R: AbstractRotation<f64, 3> + Copy + Into<Rotation3<f64>>,
    {
        let r: Rotation3<f64> = pose.rotation.into();
        LinkInertial {
            mass: self.mass,
            com: pose.transform_point(&self.com.into()).coords,
            inertia: r.matrix() * self.inertia * r.matrix().transpose(),
        }
    }

    /// The rigid union of two bodies given in the same frame: masses add, the centre of mass is
    /// the mass-weighted mean, and each inertia is moved to the common centre of mass with the
    /// parallel-axis theorem `I + m·(|d|²·E − d·dᵀ)`. Two massless bodies keep `com = 0`.
    #[must_use]
    pub fn combined(&self, other: &LinkInertial) -> Self {
        let mass = self.mass + other.mass;
        if mass <= 0.0 {
            return LinkInertial { mass: 0.0, com: Vector3::zeros(), inertia: self.inertia + other.inertia };
        }
        let com = (self.com * self.mass + other.com * other.mass) / mass;
        let shifted = |b: &LinkInertial| {
            let d = b.com - com;
            b.inertia + (Matrix3::identity() * d.norm_squared() - d * d.transpose()) * b.mass
        };
        LinkInertial { mass, com, inertia: shifted(self) + shifted(other) }
    }

    /// The principal moments of inertia, ascending, kg·m².
    #[must_use]
    pub fn principal_moments(&self) -> [f64; 3] {
        let mut moments = SymmetricEigen::new(self.inertia).eigenvalues;
        moments.as_mut_slice().sort_by(f64::total_cmp);
        [moments[0], moments[1], moments[2]]
    }

    /// Whether the principal moments satisfy the triangle inequality `I₁ + I₂ ≥ I₃` (to a
    /// relative 1e-9), as those of every rigid body do.
    ///
    /// Not enforced by validation: published identified parameter sets break it where they
    /// lump rotor or link inertias about one axis — Corke's Puma 560 link 1 (mass 0,
    /// `Iyy = 0.35 kg·m²` only) and link 3 (`0.066 + 0.0125 < 0.086 kg·m²`).
    #[must_use]
    pub fn triangle_inequality_holds(&self) -> bool {
        let [a, b, c] = self.principal_moments();
        a + b >= c - INERTIA_RELATIVE_TOLERANCE * self.inertia.amax()
    }

    /// Checks the numbers; `Err` holds the offending field (`inertial.mass`, `inertial.com`,
    /// `inertial.inertia`) and what is wrong.
    ///
    /// Rules: mass finite and ≥ 0; centre of mass finite; inertia finite, symmetric and positive
    /// semi-definite (to a relative 1e-9). The triangle inequality is not required (see
    /// [`LinkInertial::triangle_inequality_holds`]).
    pub(crate) fn check(&self) -> Result<(), (&'static str, String)> {
        if !(self.mass.is_finite() && self.mass >= 0.0) {
            return Err(("inertial.mass", format!("must be a finite number ≥ 0 kg, got {}", self.mass)));
        }
        if let Some(v) = self.com.iter().find(|v| !v.is_finite()) {
            return Err(("inertial.com", format!("must be finite, got {v}")));
        }
        let i = &self.inertia;
        if let Some(v) = i.iter().find(|v| !v.is_finite()) {
            return Err(("inertial.inertia", format!("must be finite, got {v}")));
        }
        let tol = INERTIA_RELATIVE_TOLERANCE * i.amax();
        if (i - i.transpose()).amax() > tol {
            return Err(("inertial.inertia", "the inertia tensor must be symmetric".into()));
        }
        let smallest = self.principal_moments()[0];
        if smallest < -tol {
            return Err((
                "inertial.inertia",
                format!("must be positive semi-definite, has principal moment {smallest:.6e} kg·m²"),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Isometry3, Translation3, UnitQuaternion};

    #[test]
    fn combining_two_point_masses_gives_the_dumbbell_inertia() {
        let a = LinkInertial::point(1.0, Vector3::new(-1.0, 0.0, 0.0));
        let b = LinkInertial::point(3.0, Vector3::new(1.0, 0.0, 0.0));
        let c = a.combined(&b);
        assert!((c.mass - 4.0).abs() < 1e-15);
        assert!((c.com - Vector3::new(0.5, 0.0, 0.0)).norm() < 1e-15);
        // About the COM: 1·1.5² + 3·0.5² = 3 about y and z, 0 about x.
        assert!((c.inertia - Matrix3::from_diagonal(&Vector3::new(0.0, 3.0, 3.0))).amax() < 1e-14);
        assert!(c.check().is_ok());
    }

    #[test]
    fn transforming_moves_the_com_and_rotates_the_inertia() {
        let body = LinkInertial::new(2.0, Vector3::new(1.0, 0.0, 0.0), [1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
        let pose = Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 1.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), std::f64::consts::FRAC_PI_2),
        );
        let moved = body.transformed(&pose);
        assert!((moved.com - Vector3::new(0.0, 1.0, 1.0)).norm() < 1e-15);
        assert!((moved.inertia - Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 3.0))).amax() < 1e-15);
        // The same pose with a rotation matrix (the robot's frame type) gives the same body.
        let as_matrix = nalgebra::IsometryMatrix3::from_parts(pose.translation, pose.rotation.to_rotation_matrix());
        let again = body.transformed(&as_matrix);
        assert!((again.com - moved.com).norm() < 1e-15);
        assert!((again.inertia - moved.inertia).amax() < 1e-15);
    }

    #[test]
    fn check_names_the_field() {
        let bad = [
            (LinkInertial::point(f64::NAN, Vector3::zeros()), "inertial.mass"),
            (LinkInertial::point(-1.0, Vector3::zeros()), "inertial.mass"),
            (LinkInertial::point(1.0, Vector3::new(0.0, f64::INFINITY, 0.0)), "inertial.com"),
            (LinkInertial::new(1.0, Vector3::zeros(), [1.0, 1.0, f64::NAN, 0.0, 0.0, 0.0]), "inertial.inertia"),
            (LinkInertial::new(1.0, Vector3::zeros(), [1.0, 1.0, -1.0, 0.0, 0.0, 0.0]), "inertial.inertia"),
            (LinkInertial::new(1.0, Vector3::zeros(), [1.0, 1.0, 1.0, 2.0, 0.0, 0.0]), "inertial.inertia"),
        ];
        for (body, field) in bad {
            assert_eq!(body.check().unwrap_err().0, field, "{body:?}");
        }
        let mut asym = LinkInertial::new(1.0, Vector3::zeros(), [1.0, 1.0, 1.0, 0.0, 0.0, 0.0]);
        asym.inertia[(0, 1)] = 0.5;
        assert_eq!(asym.check().unwrap_err().0, "inertial.inertia");
        // Lumped inertias that break the triangle inequality are accepted (Corke's Puma 560).
        let lumped = LinkInertial::new(4.8, Vector3::zeros(), [0.066, 0.086, 0.0125, 0.0, 0.0, 0.0]);
        assert!(lumped.check().is_ok());
        assert!(!lumped.triangle_inequality_holds());
        let rigid = LinkInertial::new(1.0, Vector3::zeros(), [1.0, 2.0, 3.0, 0.0, 0.0, 0.0]);
        assert!(rigid.triangle_inequality_holds());
        assert_eq!(rigid.principal_moments(), [1.0, 2.0, 3.0]);
    }
}
