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
//!
//! Forward kinematics, the link frames and the Jacobian run on [`Chain::fk`], the same product
//! with its motion frames moved onto DH common normals ([`FkChain`]); joint axes and dynamics
//! on this one ([`Chain::product`]). Both take the one walk and the elementary steps of
//! [`FkFrame`]; the tests hold them against an independent product of nalgebra isometries.

use nalgebra::{Isometry3, IsometryMatrix3, Matrix3, Rotation3, Translation3, Unit, Vector3};

use super::fk_chain::{self, FkChain, FkFrame, Stop, WalkLink};
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
    /// Mimic-joint motions between this joint and the next (empty for most robots).
    pub mimics: Vec<MimicStep>,
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
    /// The same product in the form forward kinematics and the Jacobian run on.
    pub fk: FkChain,
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
        let fk = FkChain::new(&first, &first_mimics, &links);
        Chain { first, first_mimics, links, fk }
    }

    /// Whether any mimic joint moves on the chain.
    pub fn has_mimics(&self) -> bool {
        !self.first_mimics.is_empty() || self.links.iter().any(|l| !l.mimics.is_empty())
    }

    /// The whole product for joint values `q` (the tool pose) on the constants as compiled,
    /// showing `visit` every [`Stop`] on the way: the frames dynamics and
    /// [`Robot::joint_axes`](crate::model::Robot::joint_axes) report (forward kinematics takes
    /// the same product on [`Chain::fk`]).
    #[inline(always)]
    pub fn product<'a>(&'a self, q: &[f64], mut visit: impl FnMut(Stop<'a>, &FkFrame)) -> FkFrame {
        let mut t = fk_chain::start(&self.first, &self.first_mimics, q, &mut visit);
        fk_chain::walk(&self.links, &mut t, q, 0..self.links.len(), visit);
        t
    }
}

impl WalkLink for ChainLink {
    #[inline(always)]
    fn prismatic(&self) -> bool {
        self.prismatic
    }

    #[inline(always)]
    fn value(&self, q: f64) -> f64 {
        self.sign * q
    }

    #[inline(always)]
    fn mul_after(&self, t: &mut FkFrame) {
        t.mul_const(&self.after);
    }

    #[inline(always)]
    fn mimics(&self) -> &[MimicStep] {
        &self.mimics
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The reference product (test oracle): the compiled chain as it stands, multiplied out
    /// with nalgebra's isometries, independently of [`FkFrame`] and the walk.
    fn reference_product(chain: &Chain, q: &[f64]) -> IsometryMatrix3<f64> {
        let motion = |t: &mut IsometryMatrix3<f64>, prismatic: bool, v: f64| {
            let m = if prismatic { trans(0.0, 0.0, v) } else { rot_z(v) };
            *t *= m;
        };
        let mimics = |t: &mut IsometryMatrix3<f64>, steps: &[MimicStep]| {
            for m in steps {
                motion(t, m.prismatic, m.value(q));
                *t *= m.after;
            }
        };
        let mut t = chain.first;
        mimics(&mut t, &chain.first_mimics);
        for (link, &v) in chain.links.iter().zip(q) {
            motion(&mut t, link.prismatic, link.sign * v);
            t *= link.after;
            mimics(&mut t, &link.mimics);
        }
        t
    }

    /// The URDF arms of the Pinocchio comparison, as robots.
    fn urdf_arms() -> Vec<(&'static str, crate::model::Robot)> {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/");
        [
            ("ur5", "urdf/ur_description/urdf/ur5.urdf", "ee_link"),
            ("puma560", "urdf/unimation_puma560_description/urdf/puma560_robot.urdf", "link7"),
            ("kr16_2", "urdf/kuka_kr16_support/urdf/kr16_2.urdf", "tool0"),
            ("panda", "panda.urdf", "panda_hand"),
        ]
        .into_iter()
        .map(|(name, file, tip)| {
            let text = std::fs::read_to_string(format!("{dir}{file}")).unwrap();
            let chain = crate::model::UrdfChain { base: None, tip: Some(tip.into()) };
            (name, crate::model::Robot::from_urdf_str(&text, &chain).unwrap())
        })
        .collect()
    }

    #[test]
    fn both_chain_products_equal_the_reference_product() {
        use crate::model::fk_chain::FkStep;
        let ur5 = crate::model::presets::get("ur5").unwrap();
        assert!(ur5.chain.fk.links.iter().all(|l| matches!(l.after, FkStep::Dh(_)) && l.offset == 0.0));
        let mut robots: Vec<(String, crate::model::Robot)> = crate::model::presets::names()
            .iter()
            .map(|n| (n.to_string(), crate::model::presets::get(n).unwrap()))
            .collect();
        robots.extend(urdf_arms().into_iter().map(|(n, r)| (format!("{n} (URDF)"), r)));
        let mut rng = crate::rng::SplitMix64(5);
        for (name, robot) in &robots {
            for _ in 0..200 {
                let q: Vec<f64> = (0..robot.dof()).map(|_| (rng.next_f64() * 2.0 - 1.0) * 3.2).collect();
                let fast = robot.fk_matrix(&q).unwrap();
                let reference = reference_product(&robot.chain, &q);
                let gap = (fast.to_homogeneous() - reference.to_homogeneous()).abs().max();
                assert!(gap < 1e-12, "{name}: {q:?}: {gap:e}");
                let compiled = robot.chain.product(&q, |_, _| {}).isometry();
                let gap = (compiled.to_homogeneous() - reference.to_homogeneous()).abs().max();
                assert!(gap < 1e-12, "{name}: {q:?}: {gap:e}");
            }
        }
    }

    #[test]
    fn urdf_arms_run_on_dh_steps() {
        use crate::model::fk_chain::FkStep;
        for (name, robot) in urdf_arms() {
            let links = &robot.chain.fk.links;
            // Every joint but the last takes a DH step; so does the last (whose constant holds
            // the tool) where that constant is a turned DH step: PUMA's and Panda's, not UR5's
            // (its tool's x axis lies along the last joint's axis) nor KR 16's (5e-12 off).
            let dh = links.iter().filter(|l| matches!(l.after, FkStep::Dh(_))).count();
            let expected = if matches!(name, "ur5" | "kr16_2") { links.len() - 1 } else { links.len() };
            assert_eq!(dh, expected, "{name}: {dh} DH steps of {}", links.len());
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
