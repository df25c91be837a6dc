//! The compiled form of a chain that forward kinematics and the Jacobian run on.
//!
//! Every convention is rewritten as one product
//!
//! ```text
//! T(q) = F0 · M1(q1) · F1 · M2(q2) · F2 ⋯ Mn(qn) · Fn
//! ```
//!
//! where each `Mi` is a rotation about (or translation along) the local **z** axis and the
//! `Fi` are constant isometries:
//!
//! * standard DH, `Ai = Rz(θ)·Tz(d)·Tx(a)·Rx(α)` with `θ = q + offset`:
//!   `Mi = Rz(q)`, fixed part `Rz(offset)·Tz(d)·Tx(a)·Rx(α)` after it
//!   (for prismatic joints `Mi = Tz(q)`, which commutes with `Rz(offset)`);
//! * modified DH, `Ai = Rx(α)·Tx(a)·Rz(θ)·Tz(d)`: fixed part `Rx(α)·Tx(a)·Rz(offset)·Tz(d)`
//!   before `Mi = Rz(q)` (`Rz` and `Tz` commute);
//! * URDF, `origin·M(axis, q)`: with `Ra` any rotation taking z onto the axis,
//!   `M(axis, q) = Ra·Rz(q)·Raᵀ`, so `Ra` joins the fixed part before and `Raᵀ` the one after.
//!
//! The frame reported for joint *i* (the frame of link *i*) is the running product after
//! `Mi` times a constant `Gi` (the DH fixed part for standard DH, identity for MDH, `Raᵀ`
//! for URDF). Base and tool fold into `F0` and `Fn`.
//!
//! A mimic joint (URDF `<mimic>`, see [`MimicJoint`](super::MimicJoint)) adds a motion
//! `Rz(multiplier·q_master + offset)` (or `Tz`) with its own constant after it. The mimic
//! motions that sit after independent joint *i* are in that joint's `mimics` (its `after` then
//! leads to the first of them), those before the first joint in [`Chain::first_mimics`].

use nalgebra::{Isometry3, IsometryMatrix3, Matrix3, Rotation3, Translation3, Unit, Vector3};

use super::{Convention, JointGeometry, JointKind, RobotSpec};

/// One joint of the compiled chain.
#[derive(Debug, Clone)]
pub(crate) struct ChainLink {
    /// Translation along z instead of rotation about z.
    pub prismatic: bool,
    /// −1 for a flipped joint, +1 otherwise.
    pub sign: f64,
    /// Constant from the frame after the motion to the reported link frame (`Gi`).
    pub to_frame: IsometryMatrix3<f64>,
    /// Constant from the frame after the motion to the next motion frame (`Fi`: the next
    /// joint's, or the first of `mimics`); for the last motion it includes the tool transform.
    pub after: IsometryMatrix3<f64>,
    /// `after` when it has the form `Tz(d)·Tx(a)·Rx(α)` (every standard-DH joint but one
    /// with a tool): `[a, d, cos α, sin α]`, so that [`ChainLink::apply_after`] skips the zero
    /// entries (12 + 6 products instead of 27 + 9).
    pub dh_after: Option<[f64; 4]>,
    /// Mimic-joint motions between this joint and the next (empty for most robots).
    pub mimics: Vec<MimicStep>,
}

impl ChainLink {
    /// Right-multiplies `t` by this joint's motion for joint value `q` and by `after`:
    /// the step of forward kinematics over one joint (mimic motions excluded).
    #[inline(always)]
    pub fn advance(&self, t: &mut IsometryMatrix3<f64>, q: f64) {
        apply_motion(t, self.prismatic, self.sign * q);
        self.apply_after(t);
    }

    /// Right-multiplies `t` by `after` in place.
    #[inline(always)]
    pub fn apply_after(&self, t: &mut IsometryMatrix3<f64>) {
        let Some([a, d, c, s]) = self.dh_after else {
            *t *= self.after;
            return;
        };
        let m = t.rotation.matrix();
        let (x, y, z) = (m.column(0).into_owned(), m.column(1).into_owned(), m.column(2).into_owned());
        t.translation.vector += x * a + z * d;
        // SAFETY of orthonormality: a rotation times Rx(α) is a rotation.
        let m = t.rotation.matrix_mut_unchecked();
        m.set_column(1, &(y * c + z * s));
        m.set_column(2, &(z * c - y * s));
    }
}

/// `[a, d, cos α, sin α]` when `after` is exactly `Tz(d)·Tx(a)·Rx(α)`.
fn dh_form(after: &IsometryMatrix3<f64>) -> Option<[f64; 4]> {
    let r = after.rotation.matrix();
    let t = after.translation.vector;
    let x_fixed = r[(0, 0)] == 1.0 && r[(0, 1)] == 0.0 && r[(0, 2)] == 0.0 && r[(1, 0)] == 0.0 && r[(2, 0)] == 0.0;
    let rx = r[(2, 2)] == r[(1, 1)] && r[(1, 2)] == -r[(2, 1)];
    (x_fixed && rx && t.y == 0.0).then_some([t.x, t.z, r[(1, 1)], r[(2, 1)]])
}

/// One mimic-joint motion: `M(multiplier·q[master] + offset) · after`.
#[derive(Debug, Clone)]
pub(crate) struct MimicStep {
    /// Translation along z instead of rotation about z.
    pub prismatic: bool,
    /// 0-based index of the master joint in `q`.
    pub master: usize,
    /// Factor on the master's value.
    pub multiplier: f64,
    /// Added to the scaled value.
    pub offset: f64,
    /// Constant from the frame after the motion to the next motion frame (tool included for
    /// the last motion of the chain).
    pub after: IsometryMatrix3<f64>,
}

impl MimicStep {
    /// The motion value for joint values `q`.
    #[inline]
    pub fn value(&self, q: &[f64]) -> f64 {
        self.multiplier * q[self.master] + self.offset
    }
}

/// `T(q) = first · Π(first_mimics) · Π (Mi · after_i · Π(mimics_i))`.
#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub first: IsometryMatrix3<f64>,
    /// Mimic motions before the first joint (empty for most robots).
    pub first_mimics: Vec<MimicStep>,
    pub links: Vec<ChainLink>,
}

fn matrix(iso: &Isometry3<f64>) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(iso.translation, iso.rotation.to_rotation_matrix())
}

fn rot_x(angle: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(Translation3::identity(), Rotation3::from_axis_angle(&Vector3::x_axis(), angle))
}

fn rot_z(angle: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(Translation3::identity(), Rotation3::from_axis_angle(&Vector3::z_axis(), angle))
}

fn trans(x: f64, y: f64, z: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(Translation3::new(x, y, z), Rotation3::identity())
}

/// A rotation taking +z onto `axis`, accurate to rounding for every direction.
///
/// For a unit vector `b` with `c = b·z > −1`, the rotation about `z × b = (−b_y, b_x, 0)` that
/// takes z onto b is `I + [v]× + [v]×²/(1 + c)` (Rodrigues' formula without trigonometry; an
/// angle from `acos(c)` would lose half the digits for axes within ~1e-8 of ±z). For `c < 0`
/// the formula is applied to `−axis` and followed by `Rx(π)`, which maps z to −z.
fn z_onto(axis: &Unit<Vector3<f64>>) -> Rotation3<f64> {
    let flip = axis.z < 0.0;
    let b = if flip { -axis.into_inner() } else { axis.into_inner() };
    let (x, y, c) = (b.x, b.y, b.z);
    let k = 1.0 / (1.0 + c);
    let s = if flip { -1.0 } else { 1.0 };
    // Columns 2 and 3 change sign under the trailing Rx(π) = diag(1, −1, −1).
    #[rustfmt::skip]
    let m = Matrix3::new(
        1.0 - k * x * x, -s * k * x * y,        s * x,
        -k * x * y,      s * (1.0 - k * y * y), s * y,
        -x,              -s * y,                s * c,
    );
    Rotation3::from_matrix_unchecked(m)
}

impl Chain {
    /// Rewrites a validated spec as a product of constant isometries and z motions.
    pub fn compile(spec: &RobotSpec) -> Chain {
        let n = spec.joints.len();
        let tool = matrix(&spec.tool);
        // Every motion in chain order: independent joints interleaved with mimic joints.
        // For MDH and URDF the fixed part of motion k+1 sits before it; it is appended to
        // `after` of motion k (or to `first` for the first motion).
        let mut before_next: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n + spec.mimics.len());
        let mut to_frames: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n);
        let mut dh_after: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n + spec.mimics.len());
        // `Ok(i)`: independent joint i; `Err(k)`: mimic joint k.
        let mut order: Vec<Result<usize, usize>> = Vec::with_capacity(n + spec.mimics.len());
        let mut mimics = spec.mimics.iter().enumerate().peekable();
        let urdf_motion = |origin: &nalgebra::Isometry3<f64>, axis: &Unit<Vector3<f64>>| {
            let ra = z_onto(axis);
            (
                matrix(origin) * IsometryMatrix3::from_parts(Translation3::identity(), ra),
                IsometryMatrix3::from_parts(Translation3::identity(), ra.inverse()),
            )
        };
        for i in 0..=n {
            while let Some((k, m)) = mimics.next_if(|(_, m)| m.position <= i) {
                let (before, back) = urdf_motion(&m.origin, &m.axis);
                before_next.push(before);
                dh_after.push(back);
                order.push(Err(k));
            }
            let Some(joint) = spec.joints.get(i) else { break };
            order.push(Ok(i));
            match (&joint.geometry, spec.convention) {
                (JointGeometry::Dh(p), Convention::Dh) => {
                    let fixed = rot_z(p.theta_offset) * trans(0.0, 0.0, p.d) * trans(p.a, 0.0, 0.0) * rot_x(p.alpha);
                    before_next.push(IsometryMatrix3::identity());
                    to_frames.push(fixed);
                    dh_after.push(fixed);
                }
                (JointGeometry::Dh(p), _) => {
                    let fixed = rot_x(p.alpha) * trans(p.a, 0.0, 0.0) * rot_z(p.theta_offset) * trans(0.0, 0.0, p.d);
                    before_next.push(fixed);
                    to_frames.push(IsometryMatrix3::identity());
                    dh_after.push(IsometryMatrix3::identity());
                }
                (JointGeometry::Axis { origin, axis }, _) => {
                    let (before, back) = urdf_motion(origin, axis);
                    before_next.push(before);
                    to_frames.push(back);
                    dh_after.push(back);
                }
            }
        }
        let first = matrix(&spec.base) * before_next[0];
        let mut first_mimics = Vec::new();
        let mut links: Vec<ChainLink> = Vec::with_capacity(n);
        for (k, step) in order.iter().enumerate() {
            let after = dh_after[k] * before_next.get(k + 1).copied().unwrap_or(tool);
            match *step {
                Ok(i) => links.push(ChainLink {
                    prismatic: spec.joints[i].kind == JointKind::Prismatic,
                    sign: if spec.joints[i].flip { -1.0 } else { 1.0 },
                    to_frame: to_frames[i],
                    after,
                    dh_after: dh_form(&after),
                    mimics: Vec::new(),
                }),
                Err(m) => {
                    let mimic = &spec.mimics[m];
                    let step = MimicStep {
                        prismatic: mimic.kind == JointKind::Prismatic,
                        master: mimic.master,
                        multiplier: mimic.multiplier,
                        offset: mimic.offset,
                        after,
                    };
                    match links.last_mut() {
                        Some(link) => link.mimics.push(step),
                        None => first_mimics.push(step),
                    }
                }
            }
        }
        Chain { first, first_mimics, links }
    }

    /// Whether any mimic joint moves on the chain.
    pub fn has_mimics(&self) -> bool {
        !self.first_mimics.is_empty() || self.links.iter().any(|l| !l.mimics.is_empty())
    }

    /// Applies the mimic motions `steps` to `t` in place.
    #[inline(always)]
    pub fn apply_mimics(t: &mut IsometryMatrix3<f64>, steps: &[MimicStep], q: &[f64]) {
        for m in steps {
            apply_motion(t, m.prismatic, m.value(q));
            *t *= m.after;
        }
    }
}

/// Right-multiplies `t` by the joint motion `Rz(v)` or `Tz(v)` in place.
#[inline(always)]
pub(crate) fn apply_motion(t: &mut IsometryMatrix3<f64>, prismatic: bool, v: f64) {
    if prismatic {
        let z = t.rotation.matrix().column(2).into_owned();
        t.translation.vector += z * v;
    } else {
        let (s, c) = crate::angle::sin_cos(v);
        // SAFETY of orthonormality: a rotation times Rz(v) is a rotation.
        let m = t.rotation.matrix_mut_unchecked();
        for r in 0..3 {
            let x = m[(r, 0)];
            let y = m[(r, 1)];
            m[(r, 0)] = c * x + s * y;
            m[(r, 1)] = c * y - s * x;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dh_shortcut_equals_the_general_product() {
        let ur5 = crate::model::presets::get("ur5").unwrap();
        assert!(ur5.chain.links.iter().all(|l| l.dh_after.is_some()));
        for name in crate::model::presets::names() {
            let robot = crate::model::presets::get(name).unwrap();
            for k in 0..20 {
                let q: Vec<f64> = (0..robot.dof()).map(|j| ((k * 7 + j * 3) as f64 * 0.37).sin() * 1.5).collect();
                let mut general = robot.chain.first;
                Chain::apply_mimics(&mut general, &robot.chain.first_mimics, &q);
                for (link, &v) in robot.chain.links.iter().zip(&q) {
                    apply_motion(&mut general, link.prismatic, link.sign * v);
                    general *= link.after;
                    Chain::apply_mimics(&mut general, &link.mimics, &q);
                }
                let fast = robot.fk_matrix(&q).unwrap();
                assert!((fast.to_homogeneous() - general.to_homogeneous()).abs().max() < 1e-14, "{name}: {q:?}");
            }
        }
    }

    #[test]
    fn z_onto_is_a_proper_rotation_taking_z_to_the_axis() {
        let axes = [
            Vector3::z(),
            -Vector3::z(),
            Vector3::x(),
            -Vector3::y(),
            Vector3::new(1.0, 0.0, 1.0),
            Vector3::new(0.3, -0.5, -0.8),
            Vector3::new(1e-9, 2e-9, 1.0),
            Vector3::new(-1e-9, 3e-10, -1.0),
            Vector3::new(1.0, 1e-12, -1e-12),
        ];
        for a in axes {
            let axis = Unit::new_normalize(a);
            let r = z_onto(&axis);
            let m = r.matrix();
            assert!((m * Vector3::z() - axis.into_inner()).amax() < 1e-15, "{a:?}");
            assert!((m.transpose() * m - Matrix3::identity()).amax() < 1e-15, "{a:?}");
            assert!((m.determinant() - 1.0).abs() < 1e-15, "{a:?}");
        }
    }
}
