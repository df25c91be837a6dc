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

use nalgebra::{Isometry3, IsometryMatrix3, Rotation3, Translation3, Unit, Vector3};

use crate::model::{Convention, JointGeometry, JointKind, RobotSpec};

/// One joint of the compiled chain.
#[derive(Debug, Clone)]
pub(crate) struct ChainLink {
    /// Translation along z instead of rotation about z.
    pub prismatic: bool,
    /// −1 for a flipped joint, +1 otherwise.
    pub sign: f64,
    /// Constant from the frame after the motion to the reported link frame (`Gi`).
    pub to_frame: IsometryMatrix3<f64>,
    /// Constant from the frame after the motion to the next joint's motion frame (`Fi`);
    /// for the last joint it includes the tool transform.
    pub after: IsometryMatrix3<f64>,
}

/// `T(q) = first · Π (Mi · after_i)`.
#[derive(Debug, Clone)]
pub(crate) struct Chain {
    pub first: IsometryMatrix3<f64>,
    pub links: Vec<ChainLink>,
}

fn matrix(iso: &Isometry3<f64>) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(iso.translation, iso.rotation.to_rotation_matrix())
}

fn rot_x(angle: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::identity(),
        Rotation3::from_axis_angle(&Vector3::x_axis(), angle),
    )
}

fn rot_z(angle: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(
        Translation3::identity(),
        Rotation3::from_axis_angle(&Vector3::z_axis(), angle),
    )
}

fn trans(x: f64, y: f64, z: f64) -> IsometryMatrix3<f64> {
    IsometryMatrix3::from_parts(Translation3::new(x, y, z), Rotation3::identity())
}

/// A rotation taking +z onto `axis`.
fn z_onto(axis: &Unit<Vector3<f64>>) -> Rotation3<f64> {
    Rotation3::rotation_between(&Vector3::z(), axis)
        .unwrap_or_else(|| Rotation3::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI))
}

impl Chain {
    /// Rewrites a validated spec as a product of constant isometries and z motions.
    pub fn compile(spec: &RobotSpec) -> Chain {
        let n = spec.joints.len();
        let tool = matrix(&spec.tool);
        let mut first = matrix(&spec.base);
        let mut links = Vec::with_capacity(n);
        // For MDH and URDF the fixed part of joint i+1 sits before its motion; it is appended
        // to `after` of joint i (or to `first` for joint 1).
        let mut before_next: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n);
        let mut to_frames: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n);
        let mut dh_after: Vec<IsometryMatrix3<f64>> = Vec::with_capacity(n);
        for joint in &spec.joints {
            match (&joint.geometry, spec.convention) {
                (JointGeometry::Dh(p), Convention::Dh) => {
                    let fixed = rot_z(p.theta_offset)
                        * trans(0.0, 0.0, p.d)
                        * trans(p.a, 0.0, 0.0)
                        * rot_x(p.alpha);
                    before_next.push(IsometryMatrix3::identity());
                    to_frames.push(fixed);
                    dh_after.push(fixed);
                }
                (JointGeometry::Dh(p), _) => {
                    let fixed = rot_x(p.alpha)
                        * trans(p.a, 0.0, 0.0)
                        * rot_z(p.theta_offset)
                        * trans(0.0, 0.0, p.d);
                    before_next.push(fixed);
                    to_frames.push(IsometryMatrix3::identity());
                    dh_after.push(IsometryMatrix3::identity());
                }
                (JointGeometry::Axis { origin, axis }, _) => {
                    let ra = z_onto(axis);
                    before_next.push(
                        matrix(origin) * IsometryMatrix3::from_parts(Translation3::identity(), ra),
                    );
                    let back = IsometryMatrix3::from_parts(Translation3::identity(), ra.inverse());
                    to_frames.push(back);
                    dh_after.push(back);
                }
            }
        }
        first *= before_next[0];
        for i in 0..n {
            let next = if i + 1 < n { before_next[i + 1] } else { tool };
            links.push(ChainLink {
                prismatic: spec.joints[i].kind == JointKind::Prismatic,
                sign: if spec.joints[i].flip { -1.0 } else { 1.0 },
                to_frame: to_frames[i],
                after: dh_after[i] * next,
            });
        }
        Chain { first, links }
    }
}

/// Right-multiplies `t` by the joint motion `Rz(v)` or `Tz(v)` in place.
#[inline(always)]
pub(crate) fn apply_motion(t: &mut IsometryMatrix3<f64>, prismatic: bool, v: f64) {
    if prismatic {
        let z = t.rotation.matrix().column(2).into_owned();
        t.translation.vector += z * v;
    } else {
        let (s, c) = v.sin_cos();
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
