//! Helpers shared by the kinematics integration tests: an independent forward-kinematics
//! implementation (a plain product of 4×4 homogeneous matrices, written out element by
//! element), a finite-difference Jacobian, a small deterministic random generator, and the
//! seed papers' test data used by more than one test file (seed 001's poses T0/T1, the
//! seed-002 reference arm, seed 003's weld).
//!
//! Nothing here calls the library's kinematics except `fd_jacobian`, which differentiates
//! the library's own `fk_matrix` (the Jacobian is then checked against it).

// Each test module uses a different subset of these helpers.
#![allow(dead_code)]

use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, Translation3, UnitQuaternion, Vector3};
use reach::Robot;
use reach::ik::{IkSolution, IkSolutions};
use reach::model::{Convention, Joint, JointGeometry, JointKind, RobotSpec, presets};

/// Homogeneous rotation about x.
#[rustfmt::skip]
pub fn rx(a: f64) -> Matrix4<f64> {
    let (s, c) = a.sin_cos();
    Matrix4::new(1.0, 0.0, 0.0, 0.0,
                 0.0, c,   -s,  0.0,
                 0.0, s,   c,   0.0,
                 0.0, 0.0, 0.0, 1.0)
}

/// Homogeneous rotation about y.
#[rustfmt::skip]
pub fn ry(a: f64) -> Matrix4<f64> {
    let (s, c) = a.sin_cos();
    Matrix4::new(c,   0.0, s,   0.0,
                 0.0, 1.0, 0.0, 0.0,
                 -s,  0.0, c,   0.0,
                 0.0, 0.0, 0.0, 1.0)
}

/// Homogeneous rotation about z.
#[rustfmt::skip]
pub fn rz(a: f64) -> Matrix4<f64> {
    let (s, c) = a.sin_cos();
    Matrix4::new(c,   -s,  0.0, 0.0,
                 s,   c,   0.0, 0.0,
                 0.0, 0.0, 1.0, 0.0,
                 0.0, 0.0, 0.0, 1.0)
}

/// Homogeneous translation.
#[rustfmt::skip]
pub fn tr(x: f64, y: f64, z: f64) -> Matrix4<f64> {
    Matrix4::new(1.0, 0.0, 0.0, x,
                 0.0, 1.0, 0.0, y,
                 0.0, 0.0, 1.0, z,
                 0.0, 0.0, 0.0, 1.0)
}

/// URDF `xyz` + `rpy` (fixed axes X, Y, Z: `R = Rz(yaw)·Ry(pitch)·Rx(roll)`).
pub fn xyz_rpy(xyz: [f64; 3], rpy: [f64; 3]) -> Matrix4<f64> {
    tr(xyz[0], xyz[1], xyz[2]) * rz(rpy[2]) * ry(rpy[1]) * rx(rpy[0])
}

/// Rotation by `angle` about the unit vector `k` (Rodrigues' formula, written out).
pub fn rot_axis(k: [f64; 3], angle: f64) -> Matrix4<f64> {
    let [x, y, z] = k;
    let (s, c) = angle.sin_cos();
    let v = 1.0 - c;
    let mut m = Matrix4::identity();
    m[(0, 0)] = c + x * x * v;
    m[(0, 1)] = x * y * v - z * s;
    m[(0, 2)] = x * z * v + y * s;
    m[(1, 0)] = y * x * v + z * s;
    m[(1, 1)] = c + y * y * v;
    m[(1, 2)] = y * z * v - x * s;
    m[(2, 0)] = z * x * v - y * s;
    m[(2, 1)] = z * y * v + x * s;
    m[(2, 2)] = c + z * z * v;
    m
}

/// An isometry as a 4×4 homogeneous matrix.
pub fn homogeneous(iso: &Isometry3<f64>) -> Matrix4<f64> {
    iso.to_homogeneous()
}

/// Independent forward kinematics for DH and MDH robots: the frames `base · A1 ⋯ Ai` for
/// i = 1..n, with standard DH `Ai = Rz(θ)·Tz(d)·Tx(a)·Rx(α)` and modified DH
/// `Ai = Rx(α)·Tx(a)·Rz(θ)·Tz(d)`; revolute joints add `q` to θ, prismatic ones to d;
/// flipped joints use `−q`.
pub fn dh_frames(robot: &Robot, q: &[f64]) -> Vec<Matrix4<f64>> {
    assert_eq!(q.len(), robot.dof());
    let mut t = homogeneous(robot.base());
    let mut frames = Vec::with_capacity(q.len());
    for (joint, &qi) in robot.joints().iter().zip(q) {
        let JointGeometry::Dh(p) = &joint.geometry else {
            panic!("dh_frames needs a DH or MDH robot");
        };
        let v = if joint.flip { -qi } else { qi };
        let (theta, d) = match joint.kind {
            JointKind::Revolute => (p.theta_offset + v, p.d),
            JointKind::Prismatic => (p.theta_offset, p.d + v),
        };
        t *= match robot.convention() {
            Convention::Dh => rz(theta) * tr(0.0, 0.0, d) * tr(p.a, 0.0, 0.0) * rx(p.alpha),
            Convention::Mdh => rx(p.alpha) * tr(p.a, 0.0, 0.0) * rz(theta) * tr(0.0, 0.0, d),
            Convention::Urdf => unreachable!(),
        };
        frames.push(t);
    }
    frames
}

/// Independent tool pose: `base · A1 ⋯ An · tool` (see [`dh_frames`]).
pub fn dh_product(robot: &Robot, q: &[f64]) -> Matrix4<f64> {
    dh_frames(robot, q).last().unwrap() * homogeneous(robot.tool())
}

/// Largest absolute entry of a difference (the shapes must agree).
pub fn max_abs_diff<R1, C1, S1, R2, C2, S2>(
    a: &nalgebra::Matrix<f64, R1, C1, S1>,
    b: &nalgebra::Matrix<f64, R2, C2, S2>,
) -> f64
where
    R1: nalgebra::Dim,
    C1: nalgebra::Dim,
    R2: nalgebra::Dim,
    C2: nalgebra::Dim,
    S1: nalgebra::RawStorage<f64, R1, C1>,
    S2: nalgebra::RawStorage<f64, R2, C2>,
{
    assert_eq!(a.shape(), b.shape());
    // Both iterate in column-major order.
    a.iter().zip(b.iter()).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// The rotation vector (log map) of a rotation matrix, accurate for small angles: the vee of
/// the skew part `(R − Rᵀ)/2` is `sin θ · axis`, and `θ = atan2(sin θ, (tr R − 1)/2)`.
/// (nalgebra's `Rotation3::scaled_axis` takes θ from `acos`, which loses about half the
/// digits for θ ≈ 1e-6, too coarse for finite differences.)
pub fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    let v = 0.5 * Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]);
    let s = v.norm();
    let c = 0.5 * (r.trace() - 1.0);
    let theta = s.atan2(c);
    assert!(theta < 3.0, "log_so3 is used for small relative rotations only");
    if s < 1e-300 { v } else { v * (theta / s) }
}

/// Central finite-difference Jacobian of the library's `fk_matrix`, rows `vx vy vz ωx ωy ωz`.
///
/// Position rows: `(p(q+h) − p(q−h)) / 2h`. Orientation rows: the rotation vector (log map)
/// of `R(q+h)·R(q−h)ᵀ`, divided by `2h`; that relative rotation is expressed in the world
/// frame, as the geometric Jacobian's angular rows are.
pub fn fd_jacobian(robot: &Robot, q: &[f64], h: f64) -> reach::Jacobian {
    let n = robot.dof();
    let mut j = reach::Jacobian::zeros(n);
    let mut qp = q.to_vec();
    let mut qm = q.to_vec();
    for i in 0..n {
        qp[i] = q[i] + h;
        qm[i] = q[i] - h;
        let tp = robot.fk_matrix(&qp).unwrap();
        let tm = robot.fk_matrix(&qm).unwrap();
        let dp = (tp.translation.vector - tm.translation.vector) / (2.0 * h);
        let r: Matrix3<f64> = tp.rotation.matrix() * tm.rotation.matrix().transpose();
        let w: Vector3<f64> = log_so3(&r) / (2.0 * h);
        for k in 0..3 {
            j[(k, i)] = dp[k];
            j[(k + 3, i)] = w[k];
        }
        qp[i] = q[i];
        qm[i] = q[i];
    }
    j
}

/// Every shipped preset, built.
pub fn all_presets() -> Vec<Robot> {
    presets::names().into_iter().map(|n| presets::get(n).unwrap_or_else(|e| panic!("{n}: {e}"))).collect()
}

/// A small deterministic generator (SplitMix64), so that failures reproduce.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// A joint vector inside the robot's limits (`[−π, π]` or `[−1, 1]` m for unlimited joints).
    pub fn joints(&mut self, robot: &Robot) -> Vec<f64> {
        robot
            .joints()
            .iter()
            .map(|j| {
                let (lo, hi) = if j.limits.is_bounded() {
                    (j.limits.lower, j.limits.upper)
                } else if j.kind == JointKind::Revolute {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                } else {
                    (-1.0, 1.0)
                };
                self.uniform(lo, hi)
            })
            .collect()
    }
}

/// A pose from the rows `[R | p]` of a printed homogeneous matrix (exactly orthonormal ones).
pub fn pose_from_rows(rows: [[f64; 4]; 3]) -> Isometry3<f64> {
    let rot = Rotation3::from_matrix_unchecked(Matrix3::from_fn(|i, j| rows[i][j]));
    Isometry3::from_parts(
        Translation3::new(rows[0][3], rows[1][3], rows[2][3]),
        UnitQuaternion::from_rotation_matrix(&rot),
    )
}

/// The solution equal to `q` up to whole turns (every joint within `tol` radians), if any.
pub fn find_solution<'a>(all: &'a IkSolutions, q: &[f64], tol: f64) -> Option<&'a IkSolution> {
    all.solutions.iter().find(|s| s.q.iter().zip(q).all(|(a, b)| reach::angle::wrap(a - b).abs() < tol))
}

/// Seed 001's start pose T0 of `spbu6` (notes 001 §5.1), rows `[R | p]`, metres.
#[rustfmt::skip]
pub const SPBU6_T0: [[f64; 4]; 3] = [[0.0, 0.0, 1.0, 3.0],
                                     [0.0, -1.0, 0.0, 0.0],
                                     [1.0, 0.0, 0.0, 5.0]];
/// Seed 001's end pose T1 of `spbu6` (notes 001 §5.1), rows `[R | p]`, metres.
#[rustfmt::skip]
pub const SPBU6_T1: [[f64; 4]; 3] = [[1.0, 0.0, 0.0, 0.0],
                                     [0.0, 0.0, 1.0, 3.0],
                                     [0.0, -1.0, 0.0, 5.0]];

/// Notes 002 §2.3: the paper's PUMA-type structure without the lateral offset (d2 = d3 = 0):
/// d1 = 0.3, α1 = +90°; a2 = 0.4318; a3 = 0.0203, α3 = −90°; d4 = 0.4318, α4 = +90°;
/// α5 = −90°; d6 = 0.05625 (metres).
pub fn seed002_reference() -> Robot {
    let r = |a: f64, alpha_deg: f64, d: f64| Joint::revolute(a, alpha_deg.to_radians(), d, 0.0);
    Robot::new(RobotSpec::new(
        "seed002-reference",
        Convention::Dh,
        vec![
            r(0.0, 90.0, 0.3),
            r(0.4318, 0.0, 0.0),
            r(0.0203, -90.0, 0.0),
            r(0.0, 90.0, 0.4318),
            r(0.0, -90.0, 0.0),
            r(0.0, 0.0, 0.05625),
        ],
    ))
    .unwrap()
}

/// Seed 003's weld start P, millimetres (notes 003 §5.1).
pub const WELD_P_MM: [f64; 3] = [50.0, 740.0, 70.0];
/// Seed 003's weld end M, millimetres (notes 003 §5.1).
pub const WELD_M_MM: [f64; 3] = [500.0, 200.0, 700.0];

/// The weld's constant orientation: columns n, e6, l (notes 003 §5.1, corrected sign of l_x).
pub fn weld_rotation() -> UnitQuaternion<f64> {
    let (x1, y1, z1) = (WELD_P_MM[0], WELD_P_MM[1], WELD_P_MM[2]);
    let (x2, y2, z2) = (WELD_M_MM[0], WELD_M_MM[1], WELD_M_MM[2]);
    let n = Vector3::new(x2 - x1, y2 - y1, z2 - z1).normalize();
    let e6 = Vector3::new(y1 - y2, x2 - x1, 0.0).normalize();
    let l = Vector3::new(-n.z * e6.y, n.z * e6.x, n.x * e6.y - n.y * e6.x);
    UnitQuaternion::from_matrix(&Matrix3::from_columns(&[n, e6, l]))
}

/// The weld's tool pose at arc length `s` (metres) from P.
pub fn weld_pose(s: f64) -> Isometry3<f64> {
    let p = Vector3::from(WELD_P_MM) / 1000.0;
    let m = Vector3::from(WELD_M_MM) / 1000.0;
    Isometry3::from_parts(Translation3::from(p + (m - p).normalize() * s), weld_rotation())
}

/// The UR5 preset's stick figure with 3 cm capsules on every link, instead of the preset's
/// body (the planner and swept-check tests' arm, whose scenes are laid out for it).
#[allow(dead_code, reason = "not every test module plans")]
pub fn ur5_with_capsules() -> Robot {
    let ur5 = presets::get("ur5").unwrap();
    let links = vec![reach::model::LinkGeometry { radius: 0.03 }; 6];
    Robot::new(RobotSpec { links, bodies: Vec::new(), disabled_collisions: Vec::new(), ..ur5.spec().clone() }).unwrap()
}
