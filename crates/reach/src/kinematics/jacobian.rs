use nalgebra::{Matrix6xX, Vector3};

use super::{KinematicsError, check_q};
use crate::model::Robot;
use crate::model::fk_chain::Stop;

/// The 6×n geometric Jacobian: rows `vx vy vz ωx ωy ωz` in the world frame, one column per joint.
pub type Jacobian = Matrix6xX<f64>;

impl Robot {
    /// Geometric Jacobian of the tool point in the world frame (allocates the matrix).
    ///
    /// Column *i* is `[zᵢ × (p − oᵢ); zᵢ]` for a revolute joint and `[zᵢ; 0]` for a
    /// prismatic one, where `zᵢ` is the joint axis and `oᵢ` a point on it (negated for
    /// flipped joints). A mimic joint following joint *m* with `multiplier` adds
    /// `multiplier ×` its own column to column *m* (chain rule).
    ///
    /// # Errors
    /// [`KinematicsError`] when `q` has the wrong length or a non-finite value.
    pub fn jacobian(&self, q: &[f64]) -> Result<Jacobian, KinematicsError> {
        let mut j = Jacobian::zeros(self.dof());
        self.jacobian_into(q, &mut j)?;
        Ok(j)
    }

    /// Geometric Jacobian written into `out` (6×dof), without allocating.
    ///
    /// # Errors
    /// [`KinematicsError`] for a bad `q` or when `out` does not have `dof` columns.
    pub fn jacobian_into(&self, q: &[f64], out: &mut Jacobian) -> Result<(), KinematicsError> {
        check_q(self.dof(), q)?;
        if out.ncols() != self.dof() {
            return Err(KinematicsError::BufferSize {
                buffer: "jacobian columns",
                expected: self.dof(),
                found: out.ncols(),
            });
        }
        // First pass: store the axis in the angular rows and the axis point in the linear rows.
        let t = self.chain.fk.product(q, |stop, t| {
            if let Stop::Joint(i) = stop {
                let mut col = out.column_mut(i);
                col.fixed_rows_mut::<3>(0).copy_from(&t.translation());
                col.fixed_rows_mut::<3>(3).copy_from(&t.z_axis());
            }
        });
        let p = t.translation();
        for (i, link) in self.chain.links.iter().enumerate() {
            let mut col = out.column_mut(i);
            let z = Vector3::new(col[3], col[4], col[5]);
            if link.prismatic {
                col.fixed_rows_mut::<3>(0).copy_from(&(z * link.sign));
                col.fixed_rows_mut::<3>(3).fill(0.0);
            } else {
                let o = Vector3::new(col[0], col[1], col[2]);
                col.fixed_rows_mut::<3>(0).copy_from(&(z.cross(&(p - o)) * link.sign));
                col.fixed_rows_mut::<3>(3).copy_from(&(z * link.sign));
            }
        }
        if self.chain.has_mimics() {
            self.add_mimic_columns(q, &p, out);
        }
        Ok(())
    }

    /// Second pass for robots with mimic joints: adds `multiplier ×` each mimic joint's column
    /// to its master's column. `p` is the tool point.
    fn add_mimic_columns(&self, q: &[f64], p: &Vector3<f64>, out: &mut Jacobian) {
        self.chain.fk.product(q, |stop, t| {
            let Stop::Mimic(m) = stop else { return };
            let z = t.z_axis();
            let mut col = out.column_mut(m.master);
            if m.prismatic {
                let v = z * m.multiplier;
                col.fixed_rows_mut::<3>(0).zip_apply(&v, |a, b| *a += b);
            } else {
                let v = z.cross(&(p - t.translation())) * m.multiplier;
                let w = z * m.multiplier;
                col.fixed_rows_mut::<3>(0).zip_apply(&v, |a, b| *a += b);
                col.fixed_rows_mut::<3>(3).zip_apply(&w, |a, b| *a += b);
            }
        });
    }
}
