//! `L` rigid transforms in structure-of-arrays form ([`FrameLanes`]: every matrix entry is an
//! array of `L` lanes) and the chain's elementary right-multiplications on them (a joint
//! motion, a DH step, a general constant). The scalar frame
//! [`FkFrame`](super::fk_chain::FkFrame) is one lane of it, so the scalar walk and the batch
//! kernels of [`crate::kinematics::lanes`] run the same operations in the same order.
#![allow(
    clippy::needless_range_loop,
    reason = "the lane loops index several arrays by the same lane: the form that vectorises"
)]

use nalgebra::IsometryMatrix3;

use super::fk_chain::{DhStep, FkStep};
use crate::angle::sin_cos_lanes;

/// One value per lane.
pub(crate) type Lanes<const L: usize> = [f64; L];

/// `L` rigid transforms entry by entry: `r[i][j][l]` is entry `(i, j)` of lane `l`'s rotation,
/// `p[i][l]` entry `i` of its translation (metres).
#[derive(Debug, Clone, Copy)]
pub(crate) struct FrameLanes<const L: usize> {
    /// Rotation entries, row by row.
    pub r: [[Lanes<L>; 3]; 3],
    /// Translation entries.
    pub p: [Lanes<L>; 3],
}

impl<const L: usize> FrameLanes<L> {
    /// The same transform `t` in every lane.
    #[inline(always)]
    pub(crate) fn splat(t: &IsometryMatrix3<f64>) -> Self {
        let m = t.rotation.matrix();
        let v = t.translation.vector;
        FrameLanes {
            r: std::array::from_fn(|i| std::array::from_fn(|j| [m[(i, j)]; L])),
            p: std::array::from_fn(|i| [v[i]; L]),
        }
    }

    /// Column `j` of the rotation (`j = 2`: the z axis).
    #[inline(always)]
    pub(crate) fn column(&self, j: usize) -> [Lanes<L>; 3] {
        [self.r[0][j], self.r[1][j], self.r[2][j]]
    }

    /// Right-multiplies every lane by `Rz(v)` given as `(sin v, cos v)`.
    #[inline(always)]
    pub(crate) fn rotate_z(&mut self, s: &Lanes<L>, c: &Lanes<L>) {
        for row in &mut self.r {
            for l in 0..L {
                let (x, y) = (row[0][l], row[1][l]);
                row[0][l] = c[l] * x + s[l] * y;
                row[1][l] = c[l] * y - s[l] * x;
            }
        }
    }

    /// Right-multiplies every lane by `Tz(v)`.
    #[inline(always)]
    pub(crate) fn slide_z(&mut self, v: &Lanes<L>) {
        for i in 0..3 {
            for l in 0..L {
                self.p[i][l] += self.r[i][2][l] * v[l];
            }
        }
    }

    /// Right-multiplies every lane by its joint motion: `Rz(v)` (radians) or `Tz(v)` (metres).
    #[inline(always)]
    pub(crate) fn motion(&mut self, prismatic: bool, v: &Lanes<L>) {
        if prismatic {
            self.slide_z(v);
        } else {
            let (s, c) = sin_cos_lanes(v);
            self.rotate_z(&s, &c);
        }
    }

    /// Right-multiplies every lane by the constant `m`.
    #[inline(always)]
    pub(crate) fn mul_const(&mut self, m: &IsometryMatrix3<f64>) {
        let k = m.rotation.matrix();
        let u = m.translation.vector;
        for i in 0..3 {
            let row = self.r[i];
            for l in 0..L {
                self.p[i][l] += row[0][l] * u[0] + row[1][l] * u[1] + row[2][l] * u[2];
            }
            for j in 0..3 {
                for l in 0..L {
                    self.r[i][j][l] = row[0][l] * k[(0, j)] + row[1][l] * k[(1, j)] + row[2][l] * k[(2, j)];
                }
            }
        }
    }

    /// Right-multiplies every lane by the DH step `Tz(d)·Tx(a)·Rx(α)`.
    #[inline(always)]
    pub(crate) fn mul_dh(&mut self, dh: &DhStep) {
        let (a, d, c, s) = (dh.a, dh.d, dh.cos_alpha, dh.sin_alpha);
        for i in 0..3 {
            let [x, y, z] = self.r[i];
            for l in 0..L {
                self.p[i][l] += x[l] * a + z[l] * d;
                self.r[i][1][l] = y[l] * c + z[l] * s;
                self.r[i][2][l] = z[l] * c - y[l] * s;
            }
        }
    }

    /// Right-multiplies every lane by the constant `step`.
    #[inline(always)]
    pub(crate) fn mul_step(&mut self, step: &FkStep) {
        match step {
            FkStep::Dh(dh) => self.mul_dh(dh),
            FkStep::General(m) => self.mul_const(m),
        }
    }
}
