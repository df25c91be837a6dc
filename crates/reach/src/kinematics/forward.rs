use nalgebra::{Isometry3, IsometryMatrix3, UnitQuaternion, Vector3};

use super::{KinematicsError, check_q};
use crate::model::Robot;
use crate::model::fk_chain::{FkFrame, Stop};

/// A joint axis in the world frame: `(point on the axis, unit direction)`.
pub type JointAxis = (Vector3<f64>, Vector3<f64>);

impl Robot {
    /// Tool pose in the world frame for joint values `q` (radians / metres).
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    ///
    /// # Performance
    /// No allocation; one `sin_cos` and two small matrix products per joint, plus one
    /// rotation-matrix-to-quaternion conversion ([`Robot::fk_matrix`] skips it).
    pub fn fk(&self, q: &[f64]) -> Result<Isometry3<f64>, KinematicsError> {
        let t = self.fk_matrix(q)?;
        Ok(Isometry3::from_parts(t.translation, UnitQuaternion::from_rotation_matrix(&t.rotation)))
    }

    /// Tool pose in the world frame, with the rotation as a matrix.
    ///
    /// # Performance
    /// Runs compiled for the widest vector level the processor has ([`crate::simd`]): the
    /// sines and cosines of all joints of a 6- or 7-joint arm in one AVX-512 vector (two AVX2
    /// ones; those of a 6-joint arm in three two-lane vectors at the baseline level, SSE2 or
    /// NEON); the result is the same bit for bit at every level.
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    #[inline]
    pub fn fk_matrix(&self, q: &[f64]) -> Result<IsometryMatrix3<f64>, KinematicsError> {
        check_q(self.dof(), q)?;
        Ok(self.chain.fk.product_at(q, crate::simd::level()).isometry())
    }

    /// Every link frame in the world frame: `out[i]` is the frame of link `i + 1`
    /// (standard DH: frame *i*; MDH: frame *i*; URDF: the joint's child link frame). Mimic
    /// joints (see [`MimicJoint`](crate::model::MimicJoint)) have no entry.
    /// Returns the tool pose.
    ///
    /// # Errors
    /// [`KinematicsError`] for a bad `q` or when `out` does not have one entry per joint.
    pub fn frames_into(
        &self,
        q: &[f64],
        out: &mut [IsometryMatrix3<f64>],
    ) -> Result<IsometryMatrix3<f64>, KinematicsError> {
        check_q(self.dof(), q)?;
        if out.len() != self.dof() {
            return Err(KinematicsError::BufferSize { buffer: "frames", expected: self.dof(), found: out.len() });
        }
        Ok(self.frames_over(q, 0, None, out))
    }

    /// [`Robot::frames_into`] that recomputes only the joints from `from` (0-based) on: the
    /// frames of the joints before `from` in `out` and the transforms in `before` are those
    /// of the previous call with the same buffers, whose `q` had the same values there (the
    /// caller's promise; a configuration-space grid changes its inner joints most often).
    /// `before[i]` is the transform before joint `i`'s motion, `before[dof]` the tool pose.
    /// A chain with mimic joints is recomputed from its base (a mimic joint may follow a later
    /// joint). The frames are bit for bit those of [`Robot::frames_into`].
    pub(crate) fn frames_from(
        &self,
        q: &[f64],
        from: usize,
        before: &mut [IsometryMatrix3<f64>],
        out: &mut [IsometryMatrix3<f64>],
    ) -> Result<IsometryMatrix3<f64>, KinematicsError> {
        check_q(self.dof(), q)?;
        let n = self.dof();
        if out.len() != n {
            return Err(KinematicsError::BufferSize { buffer: "frames", expected: n, found: out.len() });
        }
        if before.len() != n + 1 {
            return Err(KinematicsError::BufferSize { buffer: "before", expected: n + 1, found: before.len() });
        }
        let from = if self.chain.has_mimics() { 0 } else { from.min(n) };
        Ok(self.frames_over(q, from, Some(before), out))
    }

    /// The frame loop of [`Robot::frames_into`] and [`Robot::frames_from`] (checked inputs):
    /// from joint `from` on, starting at `before[from]` when `from > 0` (else at the base),
    /// recording into `before`, when given, the transform before each joint's motion and the
    /// tool pose. Returns the tool pose.
    fn frames_over(
        &self,
        q: &[f64],
        from: usize,
        mut before: Option<&mut [IsometryMatrix3<f64>]>,
        out: &mut [IsometryMatrix3<f64>],
    ) -> IsometryMatrix3<f64> {
        let fk = &self.chain.fk;
        let mut t = match before.as_deref() {
            Some(b) if from > 0 => FkFrame::of(&b[from]),
            _ => fk.start(q, &mut |_, _| {}),
        };
        fk.walk(&mut t, q, from..self.dof(), |stop, t| match stop {
            Stop::Joint(i) => {
                if let Some(b) = before.as_deref_mut() {
                    b[i] = t.isometry();
                }
            }
            Stop::Moved(i) => out[i] = t.isometry() * fk.links[i].to_frame,
            Stop::Mimic(_) => {}
        });
        let tool = t.isometry();
        if let Some(b) = before {
            b[self.dof()] = tool;
        }
        tool
    }

    /// Every link frame in the world frame (see [`Robot::frames_into`]), allocating the vector.
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    pub fn frames(&self, q: &[f64]) -> Result<Vec<IsometryMatrix3<f64>>, KinematicsError> {
        let mut out = vec![IsometryMatrix3::identity(); self.dof()];
        self.frames_into(q, &mut out)?;
        Ok(out)
    }

    /// Every joint's axis in the world frame: `(point on the axis, unit direction)`, the
    /// direction signed as the joint value turns or slides (the Jacobian's `zᵢ`, see
    /// [`Robot::jacobian`]). Mimic joints have no entry.
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    pub fn joint_axes(&self, q: &[f64]) -> Result<Vec<JointAxis>, KinematicsError> {
        check_q(self.dof(), q)?;
        let mut axes = Vec::with_capacity(self.dof());
        let links = &self.chain.links;
        self.chain.product(q, |stop, t| {
            if let Stop::Joint(i) = stop {
                axes.push((t.translation(), t.z_axis() * links[i].sign));
            }
        });
        Ok(axes)
    }

    /// World positions of the base origin, every link-frame origin and the tool point:
    /// the polyline a drawing or a segment collision model uses (`dof + 2` points).
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    pub fn joint_positions(&self, q: &[f64]) -> Result<Vec<nalgebra::Point3<f64>>, KinematicsError> {
        let frames = self.frames(q)?;
        let tool = self.fk_matrix(q)?;
        let mut pts = Vec::with_capacity(self.dof() + 2);
        pts.push(nalgebra::Point3::from(self.base().translation.vector));
        pts.extend(frames.iter().map(|f| nalgebra::Point3::from(f.translation.vector)));
        pts.push(nalgebra::Point3::from(tool.translation.vector));
        Ok(pts)
    }
}
