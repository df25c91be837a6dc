//! Forward kinematics and the Jacobian of several joint vectors at once, in
//! structure-of-arrays form: every matrix entry is an array of `L` lanes, one per joint vector,
//! so each step of the chain product is the same few multiplications and additions over `L`
//! independent values, which the compiler turns into vector instructions (and which keep the
//! floating-point units busy even where it does not).
//!
//! The steps are those of [`Robot::fk_matrix`] and [`Robot::jacobian_into`] (the
//! [`FkChain`](crate::model::fk_chain::FkChain): `first`, each joint's motion with its angle
//! offset, its DH step or general constant, mimic motions): the scalar walk's frame
//! [`FkFrame`](crate::model::fk_chain::FkFrame) is one lane of [`FrameLanes`], so every lane
//! runs the scalar operations in the same order and is the scalar result bit for bit. Sines
//! and cosines come from [`sin_cos_lanes`](crate::angle::sin_cos_lanes). [`crate::batch`] feeds blocks of `L` rows through
//! these kernels and the remainder through the scalar functions.
//!
//! The kernels do not check their input: the callers reject non-finite joint values first (a
//! NaN lane would only give NaN in that lane).
#![allow(
    clippy::needless_range_loop,
    reason = "the lane loops index several arrays by the same lane: the form that vectorises"
)]

use crate::model::Robot;
use crate::model::chain::MimicStep;
pub(crate) use crate::model::frame_lanes::{FrameLanes, Lanes};

/// A motion of the chain, reported to the visitor of [`Robot::walk_lanes`] with the frame
/// just before it.
enum Motion<'a> {
    /// Independent joint `i` (0-based).
    Joint(usize),
    /// A mimic joint.
    Mimic(&'a MimicStep),
}

impl<const L: usize> FrameLanes<L> {
    /// Applies the mimic motions `steps` for joint values `q` (one lane array per joint),
    /// calling `visit` before each.
    #[inline(always)]
    fn mimics<'a>(&mut self, steps: &'a [MimicStep], q: &[Lanes<L>], visit: &mut impl FnMut(Motion<'a>, &Self)) {
        for m in steps {
            visit(Motion::Mimic(m), self);
            let v: Lanes<L> = std::array::from_fn(|l| m.multiplier * q[m.master][l] + m.offset);
            self.motion(m.prismatic, &v);
            self.mul_const(&m.after);
        }
    }
}

impl Robot {
    /// The chain product for `L` joint vectors (`q[j][l]`: joint `j` of lane `l`, SI),
    /// calling `visit` with every motion and the frame just before it; returns the tool poses.
    #[inline(always)]
    fn walk_lanes<'a, const L: usize>(
        &'a self,
        q: &[Lanes<L>],
        mut visit: impl FnMut(Motion<'a>, &FrameLanes<L>),
    ) -> FrameLanes<L> {
        debug_assert_eq!(q.len(), self.dof());
        let fk = &self.chain.fk;
        let mut t = FrameLanes::splat(&fk.first);
        t.mimics(&fk.first_mimics, q, &mut visit);
        self.walk_links(&mut t, 0, q, &mut visit);
        t
    }

    /// The chain product from joint `from` on (its motion, constant and mimics, then the next
    /// joints' up to `q.len()`), applied to `t`: the loop of [`Robot::walk_lanes`].
    #[inline(always)]
    fn walk_links<'a, const L: usize>(
        &'a self,
        t: &mut FrameLanes<L>,
        from: usize,
        q: &[Lanes<L>],
        visit: &mut impl FnMut(Motion<'a>, &FrameLanes<L>),
    ) {
        // Indexed loops, not iterator adapters or `array::from_fn`: those stayed out-of-line
        // calls (`Enumerate::nth`, `try_from_fn`) inside the wide IK kernels.
        let links = &self.chain.fk.links;
        for i in from..links.len().min(q.len()) {
            let (link, qj) = (&links[i], &q[i]);
            visit(Motion::Joint(i), t);
            let mut v: Lanes<L> = [0.0; L];
            for l in 0..L {
                v[l] = link.value(qj[l]);
            }
            t.motion(link.prismatic, &v);
            t.mul_step(&link.after);
            t.mimics(&link.mimics, q, visit);
        }
    }

    /// Whether the first `k` joints' part of the chain has no mimic joint, so that
    /// [`Robot::fk_lanes_shared`] may walk it on fewer lanes.
    pub(crate) fn prefix_without_mimics(&self, k: usize) -> bool {
        let fk = &self.chain.fk;
        k <= fk.links.len() && fk.first_mimics.is_empty() && fk.links[..k].iter().all(|l| l.mimics.is_empty())
    }

    /// [`Robot::fk_lanes`] of `L` joint vectors whose first `k` joint values are shared by
    /// groups of `L / H` consecutive lanes (lanes `g·L/H … (g+1)·L/H − 1` take their first `k`
    /// joints from lane `g` of `prefix`): the chain up to joint `k` is walked on `H` lanes, each
    /// frame then copied into its group's lanes, and the rest walked on `L` lanes. Every lane is
    /// bit for bit [`Robot::fk_lanes`]' (the same operations in the same order on the same
    /// values; the copy is exact). `q` holds all joints (its first `k` are not read);
    /// [`Robot::prefix_without_mimics`] must hold for `k`.
    #[inline(always)]
    pub(crate) fn fk_lanes_shared<const H: usize, const L: usize>(
        &self,
        prefix: &[Lanes<H>],
        q: &[Lanes<L>],
    ) -> FrameLanes<L> {
        let k = prefix.len();
        debug_assert!(L.is_multiple_of(H) && self.prefix_without_mimics(k) && q.len() == self.dof());
        let fk = &self.chain.fk;
        let mut h = FrameLanes::<H>::splat(&fk.first);
        self.walk_links(&mut h, 0, prefix, &mut |_, _| {});
        // Each of the H frames copied into its group of L / H lanes (loops: `array::map` stayed
        // an out-of-line `try_map` call inside the wide IK kernels).
        let group = L / H;
        let mut t = FrameLanes { r: [[[0.0; L]; 3]; 3], p: [[0.0; L]; 3] };
        for l in 0..L {
            for a in 0..3 {
                for b in 0..3 {
                    t.r[a][b][l] = h.r[a][b][l / group];
                }
                t.p[a][l] = h.p[a][l / group];
            }
        }
        self.walk_links(&mut t, k, q, &mut |_, _| {});
        t
    }

    /// Tool poses of `L` joint vectors (`q[j][l]`: joint `j` of lane `l`, radians / metres,
    /// finite; `q.len() == dof`): lane `l` is [`Robot::fk_matrix`] of that joint vector.
    #[inline(always)]
    pub(crate) fn fk_lanes<const L: usize>(&self, q: &[Lanes<L>]) -> FrameLanes<L> {
        self.walk_lanes(q, |_, _| {})
    }

    /// Geometric Jacobians of `L` joint vectors (`q` as in [`Robot::fk_lanes`]) into `out`
    /// (`6 × dof` row-major entries of lanes, `out[r * dof + c][l]`): lane `l` is
    /// [`Robot::jacobian_into`] of that joint vector. Returns the tool poses.
    #[inline(always)]
    pub(crate) fn jacobian_lanes<const L: usize>(&self, q: &[Lanes<L>], out: &mut [Lanes<L>]) -> FrameLanes<L> {
        let dof = self.dof();
        debug_assert_eq!(out.len(), 6 * dof);
        // First pass, as the scalar one: the axis in the angular rows, the point on it in the
        // linear rows; mimic joints' axes and points aside (no allocation without mimics).
        let mut mimic_axes: Vec<(&MimicStep, [Lanes<L>; 3], [Lanes<L>; 3])> = Vec::new();
        let end = self.walk_lanes(q, |motion, t| match motion {
            Motion::Joint(c) => {
                for k in 0..3 {
                    out[k * dof + c] = t.p[k];
                    out[(k + 3) * dof + c] = t.r[k][2];
                }
            }
            Motion::Mimic(m) => mimic_axes.push((m, t.column(2), t.p)),
        });
        let p = end.p;
        for (c, link) in self.chain.links.iter().enumerate() {
            let z: [Lanes<L>; 3] = std::array::from_fn(|k| out[(k + 3) * dof + c]);
            let sign = link.sign;
            if link.prismatic {
                for k in 0..3 {
                    out[k * dof + c] = z[k].map(|v| v * sign);
                    out[(k + 3) * dof + c] = [0.0; L];
                }
            } else {
                let o: [Lanes<L>; 3] = std::array::from_fn(|k| out[k * dof + c]);
                let lin = cross(&z, &sub(&p, &o));
                for k in 0..3 {
                    out[k * dof + c] = lin[k].map(|v| v * sign);
                    out[(k + 3) * dof + c] = z[k].map(|v| v * sign);
                }
            }
        }
        // Second pass for mimic joints: `multiplier ×` each one's column onto its master's.
        for (m, z, o) in mimic_axes {
            let c = m.master;
            let lin = if m.prismatic { z } else { cross(&z, &sub(&p, &o)) };
            for k in 0..3 {
                for l in 0..L {
                    out[k * dof + c][l] += lin[k][l] * m.multiplier;
                }
            }
            if !m.prismatic {
                for k in 0..3 {
                    for l in 0..L {
                        out[(k + 3) * dof + c][l] += z[k][l] * m.multiplier;
                    }
                }
            }
        }
        end
    }
}

/// `a − b`, lane by lane.
#[inline(always)]
fn sub<const L: usize>(a: &[Lanes<L>; 3], b: &[Lanes<L>; 3]) -> [Lanes<L>; 3] {
    std::array::from_fn(|k| std::array::from_fn(|l| a[k][l] - b[k][l]))
}

/// `a × b`, lane by lane (the same products as nalgebra's `cross`).
#[inline(always)]
fn cross<const L: usize>(a: &[Lanes<L>; 3], b: &[Lanes<L>; 3]) -> [Lanes<L>; 3] {
    std::array::from_fn(|k| {
        let (i, j) = ((k + 1) % 3, (k + 2) % 3);
        std::array::from_fn(|l| a[i][l] * b[j][l] - a[j][l] * b[i][l])
    })
}
