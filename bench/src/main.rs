//! reach next to other Rust kinematics crates, in one process, on the same poses.
//!
//! ```text
//! cargo run --release --manifest-path bench/Cargo.toml            # 1000 poses per arm
//! cargo run --release --manifest-path bench/Cargo.toml -- --poses 200 --rounds 9
//! ```
//!
//! Peers: [`rs-opw-kinematics`](https://crates.io/crates/rs-opw-kinematics) 3.0 (closed-form
//! OPW kinematics: arms with an orthogonal parallel base and a spherical wrist; here the
//! Puma 560 preset and the KUKA KR 16-2 read from its URDF file, which reach solves in closed
//! form found from the geometry; its Jacobian is by finite differences) and
//! [`k`](https://crates.io/crates/k) 0.32 (general chains of nodes; Jacobian; a
//! Jacobian-pseudo-inverse IK from the current joint values; UR5 and Puma 560) and
//! [`ik-geo`](https://crates.io/crates/ik-geo) 0.1.2 (IK-Geo's subproblem decomposition; the
//! UR5's closed form; it builds the NLopt C library, so `cmake` must be installed). Each peer
//! is built from the same robot as reach and checked against reach's forward kinematics to
//! 1e-9 before anything is timed, so both solve the same chain.
//!
//! Building: besides Rust, the peers need **CMake** and a C compiler — `ik-geo` depends on
//! the `nlopt` crate (0.7), whose build script compiles the NLopt C library with CMake (the
//! `cmake` crate), e.g. `apt-get install cmake build-essential`. `k` and `rs-opw-kinematics`
//! are plain Rust. (The Python and C++ peers of `bench/peers/` have their own requirements,
//! listed in its README.)
//!
//! Timing: for every comparison, rounds alternate between reach and the peer (each round one
//! pass over all poses), after a warm-up pass each; the reported time per call is the median
//! over the rounds, the ratio is reach / peer of those medians. Absolute times drift with the
//! load of the machine; the ratios of alternating rounds much less.

use std::alloc::{GlobalAlloc, Layout, System};
use std::f64::consts::PI;
use std::hint::black_box;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use nalgebra::{Isometry3, IsometryMatrix3, Rotation3, Translation3, UnitQuaternion, Vector3};
use reach::Robot;
use reach::ik::numeric::{Numeric, NumericOptions, SearchMode};
use reach::ik::{IkOptions, IkSolutions, IkSolver, IkTarget, SolverKind};
use reach::kinematics::Jacobian;
use reach::model::{Convention, DhParams, JointGeometry, JointKind, presets};
use reach_peers_bench::median;
use rs_opw_kinematics::glam::{DQuat, DVec3};
use rs_opw_kinematics::kinematic_traits::{Joints, Kinematics, Pose};
use rs_opw_kinematics::kinematics_impl::OPWKinematics;
use rs_opw_kinematics::parameters::opw_kinematics::Parameters;

/// The system allocator, counting allocations (and reallocations) while [`COUNTING`] is set:
/// the evidence for "no allocation" claims. Off during the timed rounds.
struct CountingAlloc;

static COUNTING: AtomicBool = AtomicBool::new(false);
static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to `System` unchanged; the counter has no effect on memory.
unsafe impl GlobalAlloc for CountingAlloc {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is System's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: the caller's contract is System's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        if COUNTING.load(Ordering::Relaxed) {
            ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        }
        // SAFETY: the caller's contract is System's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAlloc = CountingAlloc;

/// Allocations per call of `f` over `n` items (mean).
fn allocations_per_call(n: usize, mut f: impl FnMut(usize)) -> f64 {
    ALLOCATIONS.store(0, Ordering::Relaxed);
    COUNTING.store(true, Ordering::Relaxed);
    for i in 0..n {
        f(i);
    }
    COUNTING.store(false, Ordering::Relaxed);
    ALLOCATIONS.load(Ordering::Relaxed) as f64 / n as f64
}

/// SplitMix64 with the mapping of reach's IK protocol (`examples/ik_protocol.rs`).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Random joint vectors inside the limits, revolute ranges cut to [−π, π] (the protocol's).
fn random_qs(robot: &Robot, n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut rng = Rng(seed);
    (0..n)
        .map(|_| {
            robot
                .joints()
                .iter()
                .map(|j| {
                    let (lo, hi) = (j.limits.lower.max(-PI), j.limits.upper.min(PI));
                    lo + (hi - lo) * rng.uniform()
                })
                .collect()
        })
        .collect()
}

/// [`race`] of reach's forward kinematics (`fk_matrix`) at the joint vectors `qs` against `peer`.
fn race_fk(robot: &Robot, qs: &[Vec<f64>], rounds: usize, peer: impl FnMut(usize)) -> (f64, f64) {
    let reach = |i: usize| {
        black_box(robot.fk_matrix(black_box(&qs[i])).expect("fk"));
    };
    race(qs.len(), rounds, reach, peer)
}

/// [`race`] of reach's Jacobian (`jacobian_into` a reused matrix) at `qs` against `peer`.
fn race_jacobian(robot: &Robot, qs: &[Vec<f64>], rounds: usize, peer: impl FnMut(usize)) -> (f64, f64) {
    let mut jac = Jacobian::zeros(robot.dof());
    let reach = |i: usize| {
        robot.jacobian_into(black_box(&qs[i]), &mut jac).expect("jacobian");
        black_box(&jac);
    };
    race(qs.len(), rounds, reach, peer)
}

/// [`race`] of reach's closed form `solver` (`solve_into` a reused buffer, default options: what
/// a real-time loop calls) on `targets` against `peer`.
fn race_ik(
    robot: &Robot,
    solver: &dyn IkSolver,
    targets: &[IkTarget],
    rounds: usize,
    peer: impl FnMut(usize),
) -> (f64, f64) {
    let options = IkOptions::default();
    let mut out = IkSolutions::default();
    let reach = |i: usize| {
        solver.solve_into(robot, black_box(&targets[i]), &options, &mut out).expect("solve");
        black_box(&out);
    };
    race(targets.len(), rounds, reach, peer)
}

/// Median time per call (ns) of `a` and of `b`, alternating rounds over `n` items.
fn race(n: usize, rounds: usize, mut a: impl FnMut(usize), mut b: impl FnMut(usize)) -> (f64, f64) {
    let pass = |f: &mut dyn FnMut(usize)| {
        let t0 = Instant::now();
        for i in 0..n {
            f(i);
        }
        t0.elapsed().as_secs_f64() * 1e9 / n as f64
    };
    pass(&mut a);
    pass(&mut b);
    let (mut ta, mut tb) = (Vec::with_capacity(rounds), Vec::with_capacity(rounds));
    for _ in 0..rounds {
        ta.push(pass(&mut a));
        tb.push(pass(&mut b));
    }
    (median(&mut ta), median(&mut tb))
}

// ------------------------------------------------------------------------------------------
// k: the chain built from reach's standard-DH preset.
// ------------------------------------------------------------------------------------------

fn to_k(iso: &IsometryMatrix3<f64>) -> k::Isometry3<f64> {
    let t = iso.translation.vector;
    let q = UnitQuaternion::from_rotation_matrix(&iso.rotation);
    k::Isometry3::from_parts(
        k::Translation3::new(t.x, t.y, t.z),
        k::UnitQuaternion::from_quaternion(k::nalgebra::Quaternion::new(q.w, q.i, q.j, q.k)),
    )
}

fn from_k(iso: &k::Isometry3<f64>) -> Isometry3<f64> {
    let t = iso.translation.vector;
    let q = iso.rotation;
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, t.z),
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(q.w, q.i, q.j, q.k)),
    )
}

/// A `k` serial chain of a standard-DH, all-revolute, unflipped robot:
/// `base · Π Rz(θᵢ + offᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ) · tool`, one rotational node per joint
/// (origin: the previous joint's fixed part and this joint's offset), a fixed end node.
fn k_chain(robot: &Robot) -> k::SerialChain<f64> {
    assert_eq!(robot.convention(), Convention::Dh, "k_chain: standard DH only");
    let base = robot.base();
    let mut before = IsometryMatrix3::from_parts(base.translation, base.rotation.to_rotation_matrix());
    let mut nodes: Vec<k::Node<f64>> = Vec::new();
    for (i, j) in robot.joints().iter().enumerate() {
        assert!(j.kind == JointKind::Revolute && !j.flip, "k_chain: unflipped revolute joints only");
        let JointGeometry::Dh(p) = &j.geometry else { panic!("k_chain: DH joints only") };
        let origin = before * Rotation3::from_axis_angle(&Vector3::z_axis(), p.theta_offset);
        let node: k::Node<f64> = k::NodeBuilder::new()
            .name(&format!("j{i}"))
            .joint_type(k::JointType::Rotational { axis: k::Vector3::z_axis() })
            .origin(to_k(&origin))
            .limits(Some(k::joint::Range { min: j.limits.lower, max: j.limits.upper }))
            .into_node();
        if let Some(parent) = nodes.last() {
            node.set_parent(parent);
        }
        nodes.push(node);
        before = IsometryMatrix3::from_parts(Translation3::new(0.0, 0.0, p.d), Rotation3::identity())
            * IsometryMatrix3::from_parts(Translation3::new(p.a, 0.0, 0.0), Rotation3::identity())
            * IsometryMatrix3::from_parts(
                Translation3::identity(),
                Rotation3::from_axis_angle(&Vector3::x_axis(), p.alpha),
            );
    }
    let tool = robot.tool();
    let end = before * IsometryMatrix3::from_parts(tool.translation, tool.rotation.to_rotation_matrix());
    let tip: k::Node<f64> =
        k::NodeBuilder::new().name("tip").joint_type(k::JointType::Fixed).origin(to_k(&end)).into_node();
    tip.set_parent(nodes.last().expect("joints"));
    nodes.push(tip);
    k::SerialChain::new_unchecked(k::Chain::from_nodes(nodes))
}

fn k_fk(arm: &k::SerialChain<f64>, q: &[f64]) -> k::Isometry3<f64> {
    arm.set_joint_positions_unchecked(q);
    arm.update_transforms();
    arm.end_transform()
}

/// Largest position (m) and rotation (rad) difference; the angle from the relative
/// quaternion's vector part (`2·asin |v|`), exact near 0 where `acos` of its scalar part reads
/// rounding as 1e-8 rad.
fn pose_gap(a: &Isometry3<f64>, b: &Isometry3<f64>) -> (f64, f64) {
    let v = (a.rotation.inverse() * b.rotation).imag().norm();
    ((a.translation.vector - b.translation.vector).norm(), 2.0 * v.min(1.0).asin())
}

// ------------------------------------------------------------------------------------------
// rs-opw-kinematics: OPW parameters of reach's robots, signs and offsets found by search.
// ------------------------------------------------------------------------------------------

fn opw_pose(p: &Pose) -> Isometry3<f64> {
    let t = p.translation;
    let r = p.rotation;
    Isometry3::from_parts(
        Translation3::new(t.x, t.y, t.z),
        UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(r.w, r.x, r.y, r.z)),
    )
}

fn to_opw_pose(p: &Isometry3<f64>) -> Pose {
    let t = p.translation.vector;
    let r = p.rotation;
    Pose::from_parts(DVec3::new(t.x, t.y, t.z), DQuat::from_xyzw(r.i, r.j, r.k, r.w))
}

fn joints6(q: &[f64]) -> Joints {
    [q[0], q[1], q[2], q[3], q[4], q[5]]
}

/// The DH rows of a robot described in DH (a preset), one per joint.
fn dh_table(robot: &Robot) -> Vec<DhParams> {
    let row = |j: &reach::model::Joint| match &j.geometry {
        JointGeometry::Dh(p) => *p,
        _ => panic!("{}: joint {} is not described in DH", robot.name(), j.name),
    };
    robot.joints().iter().map(row).collect()
}

/// OPW geometries of reach's `puma560` preset, in reach's joint coordinates: from the DH
/// table (a1 = 0, a2 = ∓a3, b = ±d3, c1 = d1, c2 = a2, c3 = d4, c4 = d6), both signs of a2
/// and b (the search in [`opw_match`] keeps the one that reproduces reach).
fn opw_puma_geometries(robot: &Robot) -> Vec<Parameters> {
    let dh = dh_table(robot);
    let mut out = Vec::new();
    for s_a2 in [1.0, -1.0] {
        for s_b in [1.0, -1.0] {
            out.push(Parameters {
                a1: 0.0,
                a2: s_a2 * dh[2].a,
                b: s_b * dh[2].d,
                c1: dh[0].d,
                c2: dh[1].a,
                c3: dh[3].d,
                c4: dh[5].d,
                offsets: [0.0; 6],
                sign_corrections: [1; 6],
                dof: 6,
            });
        }
    }
    out
}

/// OPW geometries of the KUKA KR 16-2 as its URDF file gives it
/// (`examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf`: joint a1 at z 0.675, a2 at x 0.26,
/// a3 0.68 further, a4 at x 0.67 z −0.035, tool0 0.158 past the wrist centre), both signs of
/// a2 (the search in [`opw_match`] keeps the one that reproduces reach).
fn opw_kr16_geometries() -> Vec<Parameters> {
    [-0.035, 0.035]
        .map(|a2| Parameters {
            a1: 0.26,
            a2,
            b: 0.0,
            c1: 0.675,
            c2: 0.68,
            c3: 0.67,
            c4: 0.158,
            offsets: [0.0; 6],
            sign_corrections: [1; 6],
            dof: 6,
        })
        .to_vec()
}

/// The wrist centre of a flange `pose` whose z axis is the last joint's, `c4` metres back.
fn wrist_centre(pose: &Isometry3<f64>, c4: f64) -> Vector3<f64> {
    pose.translation.vector - c4 * (pose.rotation * Vector3::z())
}

/// rs-opw parameters that reproduce `robot`'s forward kinematics up to a constant rotation of
/// the flange frame, which is returned (`reach flange = opw flange · C`): among `geometries`,
/// every joint's sign and offset (0, ±π/2, π) found by search on five of `qs` (wrist centres to
/// 1e-9 m for the arm's joints, then positions to 1e-9 m and the flange rotation's constant C
/// to 1e-9 rad for the wrist's; reach's flange z must be the last joint's axis). The caller
/// checks the result on all poses.
fn opw_match(name: &str, robot: &Robot, geometries: &[Parameters], qs: &[Vec<f64>]) -> (OPWKinematics, Rotation3<f64>) {
    let offsets = [0.0, PI / 2.0, PI, -PI / 2.0];
    let probe = &qs[..5];
    let reach_poses: Vec<Isometry3<f64>> = probe.iter().map(|q| robot.fk(q).expect("fk")).collect();
    let choices = |k: usize| (k % 2, (k / 2) % 4); // (sign index, offset index)
    let with = |g: &Parameters, sign: [i8; 6], off: [f64; 6]| {
        OPWKinematics::new(Parameters { offsets: off, sign_corrections: sign, ..*g })
    };
    for geometry in geometries {
        for arm in 0..512 {
            let mut sign = [1i8; 6];
            let mut off = [0.0; 6];
            for j in 0..3 {
                let (s, o) = choices(arm >> (3 * j));
                sign[j] = if s == 0 { 1 } else { -1 };
                off[j] = offsets[o];
            }
            let opw = with(geometry, sign, off);
            let centres_match = probe.iter().zip(&reach_poses).all(|(q, t)| {
                (wrist_centre(&opw_pose(&opw.forward(&joints6(q))), geometry.c4) - wrist_centre(t, geometry.c4)).norm()
                    < 1e-9
            });
            if !centres_match {
                continue;
            }
            for wrist in 0..512 {
                for j in 3..6 {
                    let (s, o) = choices(wrist >> (3 * (j - 3)));
                    sign[j] = if s == 0 { 1 } else { -1 };
                    off[j] = offsets[o];
                }
                let opw = with(geometry, sign, off);
                let c = |k: usize| {
                    let r_opw = opw_pose(&opw.forward(&joints6(&probe[k]))).rotation.to_rotation_matrix();
                    r_opw.inverse() * reach_poses[k].rotation.to_rotation_matrix()
                };
                let c0 = c(0);
                let positions_match = probe.iter().zip(&reach_poses).all(|(q, t)| {
                    (opw_pose(&opw.forward(&joints6(q))).translation.vector - t.translation.vector).norm() < 1e-9
                });
                // Compared as matrices: an angle by `acos` reads rounding as 1e-8 rad.
                if positions_match && (1..probe.len()).all(|k| (c(k).matrix() - c0.matrix()).norm() < 1e-9) {
                    return (opw, c0);
                }
            }
        }
    }
    panic!("no OPW parameters reproduce reach's {name}");
}

// ------------------------------------------------------------------------------------------
// ik-geo: reach's arms in ik-geo's product-of-exponentials form (the UR5 in ik-geo's own layout,
// signs and offsets found by search; spherical-wrist arms read off reach's zero configuration).
// ------------------------------------------------------------------------------------------

/// ik-geo's form of an arm: its solver, and per joint `q_geo = sign · q − offset`.
struct GeoArm {
    solver: ik_geo::robot::Robot,
    sign: [f64; 6],
    offset: [f64; 6],
}

impl GeoArm {
    /// ik-geo's joint values for reach's `q`.
    fn to_geo(&self, q: &[f64]) -> [f64; 6] {
        std::array::from_fn(|j| self.sign[j] * q[j] - self.offset[j])
    }

    /// reach's joint values for ik-geo's `q`.
    fn reach_joints(&self, q: &[f64]) -> Vec<f64> {
        (0..6).map(|j| self.sign[j] * (q[j] + self.offset[j])).collect()
    }

    /// ik-geo's forward kinematics at reach's joint values: rotation (row-major) and position.
    fn fk(&self, q: &[f64]) -> (Rotation3<f64>, Vector3<f64>) {
        let (r, p) = self.solver.fk(&self.to_geo(q));
        (Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_fn(|i, j| r[(i, j)])), Vector3::new(p[0], p[1], p[2]))
    }
}

/// reach's `ur5` preset in ik-geo's UR5 layout (its `Ur5::get_kin`: joint axes z, y, y, y,
/// −z, y at zero) with the preset's own lengths from its DH table (ik-geo's hard-coded UR5
/// differs from it by 5e-5 m in a3 and d5), solved by ik-geo's `three_parallel_two_intersecting`;
/// every joint's sign and offset (0, ±π/2, π) found by search so that ik-geo's tool position
/// equals reach's on five of `qs` (1e-9 m; the position does not depend on the last joint),
/// then the last joint's and the constant flange rotation C (`reach flange = geo flange · C`,
/// to 1e-9 as matrices). The caller checks the result on all poses.
fn ikgeo_ur5(robot: &Robot, qs: &[Vec<f64>]) -> (GeoArm, Rotation3<f64>) {
    use ik_geo::inverse_kinematics::auxiliary::Matrix3x7;
    use ik_geo::nalgebra::{Matrix3x6, Vector3 as V3};
    let dh = dh_table(robot);
    let (ex, ey, ez) = (V3::x(), V3::y(), V3::z());
    let h = Matrix3x6::from_columns(&[ez, ey, ey, ey, -ez, ey]);
    let p = Matrix3x7::from_columns(&[
        dh[0].d * ez,
        V3::zeros(),
        dh[1].a.abs() * ex,
        dh[2].a.abs() * ex,
        dh[3].d * ey,
        -dh[4].d * ez,
        dh[5].d * ey,
    ]);
    let offsets = [0.0, PI / 2.0, PI, -PI / 2.0];
    let probe = &qs[..5];
    let reach_poses: Vec<Isometry3<f64>> = probe.iter().map(|q| robot.fk(q).expect("fk")).collect();
    let mut arm =
        GeoArm { solver: ik_geo::robot::three_parallel_two_intersecting(h, p), sign: [1.0; 6], offset: [0.0; 6] };
    let choose = |arm: &mut GeoArm, j: usize, k: usize| {
        arm.sign[j] = if k.is_multiple_of(2) { 1.0 } else { -1.0 };
        arm.offset[j] = offsets[(k / 2) % 4];
    };
    for first in 0..8usize.pow(5) {
        for j in 0..5 {
            choose(&mut arm, j, first >> (3 * j));
        }
        let positions_match =
            probe.iter().zip(&reach_poses).all(|(q, t)| (arm.fk(q).1 - t.translation.vector).norm() < 1e-9);
        if !positions_match {
            continue;
        }
        for last in 0..8 {
            choose(&mut arm, 5, last);
            let c = |k: usize| arm.fk(&probe[k]).0.inverse() * reach_poses[k].rotation.to_rotation_matrix();
            let c0 = c(0);
            if (1..probe.len()).all(|k| (c(k).matrix() - c0.matrix()).norm() < 1e-9) {
                return (arm, c0);
            }
        }
    }
    panic!("no ik-geo form reproduces reach's ur5");
}

/// reach's spherical-wrist `robot` (joints 2 and 3 parallel) in ik-geo's product-of-exponentials
/// form read off its own zero configuration, for ik-geo's `spherical_two_parallel`: joint `i`'s
/// world axis `h_i` is the angular part of the Jacobian's column at q = 0, a point on it the one
/// closest to the tool point (`p_e + ω × v`) — for joints 4–6 the wrist centre, where their
/// axes meet — and `p` the vectors between consecutive points. ik-geo's joint values are then
/// reach's, and the constant flange rotation is `C = R(0)` (`reach flange = geo flange · C`).
/// The caller checks the form on every pose.
fn ikgeo_spherical(robot: &Robot) -> (GeoArm, Rotation3<f64>) {
    use ik_geo::inverse_kinematics::auxiliary::Matrix3x7;
    use ik_geo::nalgebra::{Matrix3x6, Vector3 as V3};
    let zero = [0.0; 6];
    let t0 = robot.fk(&zero).expect("fk");
    let jac = robot.jacobian(&zero).expect("jacobian");
    let tip = t0.translation.vector;
    let axis = |i: usize| Vector3::new(jac[(3, i)], jac[(4, i)], jac[(5, i)]);
    let point = |i: usize| tip + axis(i).cross(&Vector3::new(jac[(0, i)], jac[(1, i)], jac[(2, i)]));
    // The wrist centre: the point of axis 4 closest to axis 5 (they meet there).
    let (a, u, w) = (point(3), axis(3), axis(4));
    let r = a - point(4);
    let uw = u.dot(&w);
    let centre = a + (uw * w.dot(&r) - u.dot(&r)) / (1.0 - uw * uw) * u;
    let o = [point(0), point(1), point(2), centre, centre, centre];
    let geo = |x: Vector3<f64>| V3::new(x.x, x.y, x.z);
    let h = Matrix3x6::from_columns(&std::array::from_fn::<_, 6, _>(|i| geo(axis(i))));
    let p = Matrix3x7::from_columns(&[
        geo(o[0]),
        geo(o[1] - o[0]),
        geo(o[2] - o[1]),
        geo(o[3] - o[2]),
        V3::zeros(),
        V3::zeros(),
        geo(tip - o[5]),
    ]);
    let arm = GeoArm { solver: ik_geo::robot::spherical_two_parallel(h, p), sign: [1.0; 6], offset: [0.0; 6] };
    (arm, t0.rotation.to_rotation_matrix())
}

/// reach's closed form next to ik-geo's form `geo` of the same arm (`reach flange = geo flange
/// · c`) on the joint vectors `qs`: both FK-checked, ik-geo's least-squares answers (not
/// solutions) left out.
fn vs_ikgeo(
    name: &str,
    robot: &Robot,
    (geo, c): (GeoArm, Rotation3<f64>),
    qs: &[Vec<f64>],
    rounds: usize,
    row: &impl Fn(&str, &str, &str, (f64, f64), &str),
) {
    use ik_geo::nalgebra::{Matrix3 as M3, Vector3 as V3};
    use ik_geo::robot::IKSolver;
    let n = qs.len();
    let targets: Vec<Isometry3<f64>> = qs.iter().map(|q| robot.fk(q).expect("fk")).collect();
    for (q, t) in qs.iter().zip(&targets) {
        let (r, p) = geo.fk(q);
        let (dp, da) = pose_gap(&Isometry3::from_parts(p.into(), UnitQuaternion::from_rotation_matrix(&(r * c))), t);
        assert!(dp < 1e-9 && da < 1e-9, "{name}: ik-geo's form differs from reach by {dp} m, {da} rad");
    }
    let c_inv = c.inverse();
    let geo_targets: Vec<(M3<f64>, V3<f64>)> = targets
        .iter()
        .map(|t| {
            let r = t.rotation.to_rotation_matrix() * c_inv;
            let p = t.translation.vector;
            (M3::from_fn(|i, j| r[(i, j)]), V3::new(p.x, p.y, p.z))
        })
        .collect();
    let cform = SolverKind::detect(robot).build(robot).expect("closed form");
    let options = IkOptions::default();
    let reach_targets: Vec<IkTarget> = targets.iter().map(|t| IkTarget::Pose(*t)).collect();
    let (mut reach_n, mut geo_n, mut geo_ls) = (0usize, 0usize, 0usize);
    for i in 0..n {
        reach_n += cform.solve(robot, &reach_targets[i], &options).expect("solve").solutions.len();
        for (q, least_squares) in geo.solver.ik(geo_targets[i].0, geo_targets[i].1) {
            if least_squares {
                geo_ls += 1;
                continue;
            }
            let q = geo.reach_joints(q.as_slice());
            let (dp, da) = pose_gap(&robot.fk(&q).expect("fk"), &targets[i]);
            assert!(dp < 1e-6 && da < 1e-6, "{name}: ik-geo solution off by {dp} m, {da} rad");
            geo_n += 1;
        }
    }
    let ik = race_ik(robot, cform.as_ref(), &reach_targets, rounds, |i| {
        black_box(geo.solver.ik(black_box(geo_targets[i].0), black_box(geo_targets[i].1)));
    });
    let note = format!(
        "all branches; mean solutions per pose: reach {:.2} (FK-verified, labelled, limits flagged), ik-geo {:.2} exact (checked here by reach's FK; not by itself) + {:.2} least-squares answers",
        reach_n as f64 / n as f64,
        geo_n as f64 / n as f64,
        geo_ls as f64 / n as f64
    );
    row(name, "closed-form IK", "ik-geo", ik, &note);
}

/// The usage line, printed with an error for a bad argument.
const USAGE: &str = "usage: reach-peers-bench [--poses N] [--rounds N] [--profile-ik N [--arm puma560|kr16_2|ur5]]";

/// Exits with `message` and the usage line (status 2).
fn usage_error(message: &str) -> ! {
    eprintln!("reach-peers-bench: {message}\n{USAGE}");
    std::process::exit(2)
}

fn main() {
    let mut poses = 1000;
    let mut rounds = 15;
    let mut profile = None;
    let mut profile_arm = String::from("puma560");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || -> usize {
            match args.next().map(|v| v.parse::<usize>()) {
                Some(Ok(n)) if n > 0 => n,
                _ => usage_error(&format!("{a} needs a positive whole number")),
            }
        };
        match a.as_str() {
            "--poses" => poses = value(),
            "--rounds" => rounds = value(),
            // Only reach's closed-form IK of one arm (the lean path, as in the table), N passes
            // over the poses: for a profiler.
            "--profile-ik" => profile = Some(value()),
            "--arm" => match args.next().as_deref() {
                Some(arm @ ("puma560" | "kr16_2" | "ur5")) => profile_arm = arm.to_string(),
                _ => usage_error("--arm needs puma560, kr16_2 or ur5"),
            },
            "-h" | "--help" => {
                println!("{USAGE}");
                return;
            }
            other => usage_error(&format!("unknown argument `{other}`")),
        }
    }
    if let Some(passes) = profile {
        let robot = if profile_arm == "kr16_2" { kr16_urdf() } else { presets::get(&profile_arm).expect("preset") };
        let targets: Vec<IkTarget> =
            random_qs(&robot, poses, 2024).iter().map(|q| IkTarget::Pose(robot.fk(q).expect("fk"))).collect();
        let cform = SolverKind::detect(&robot).build(&robot).expect("closed form");
        let options = IkOptions::default();
        let mut out = IkSolutions::default();
        let t0 = Instant::now();
        for _ in 0..passes {
            for t in &targets {
                cform.solve_into(&robot, black_box(t), &options, &mut out).expect("solve");
                black_box(&out);
            }
        }
        println!("{:.0} ns per solve", t0.elapsed().as_secs_f64() * 1e9 / (passes * targets.len()) as f64);
        return;
    }
    println!(
        "reach vs peers, {poses} random joint vectors per arm (SplitMix64 seed 2024), median of {rounds} alternating rounds; ratio = reach / peer (< 1: reach faster); reach SIMD level: {}",
        reach::simd::level().name()
    );
    println!("| arm | operation | peer | reach ns/call | peer ns/call | ratio | note |");
    println!("|---|---|---|---|---|---|---|");
    let row = |arm: &str, op: &str, peer: &str, (a, b): (f64, f64), note: &str| {
        println!("| {arm} | {op} | {peer} | {a:.0} | {b:.0} | {:.2} | {note} |", a / b);
    };

    for name in ["ur5", "puma560"] {
        let robot = presets::get(name).expect("preset");
        let qs = random_qs(&robot, poses, 2024);
        let n = qs.len();

        // --- k: the same chain, checked.
        let arm = k_chain(&robot);
        for q in &qs {
            let (dp, da) = pose_gap(&from_k(&k_fk(&arm, q)), &robot.fk(q).expect("fk"));
            assert!(dp < 1e-9 && da < 1e-9, "{name}: k chain differs from reach by {dp} m, {da} rad");
        }
        let fk = race_fk(&robot, &qs, rounds, |i| {
            black_box(k_fk(&arm, black_box(&qs[i])));
        });
        row(name, "FK", "k", fk, "k: set positions + update_transforms + end_transform");
        let jacobian = race_jacobian(&robot, &qs, rounds, |i| {
            k_fk(&arm, black_box(&qs[i]));
            black_box(k::jacobian(&arm));
        });
        row(name, "Jacobian", "k", jacobian, "both from joint values (k: FK update included)");

        // Numeric IK from a seed 0.1 rad from the solution in every joint (tracking), 1e-6.
        let solver = Numeric::from_robot(&robot).expect("numeric");
        let targets: Vec<Isometry3<f64>> = qs.iter().map(|q| robot.fk(q).expect("fk")).collect();
        let seeds: Vec<Vec<f64>> = qs
            .iter()
            .map(|q| {
                q.iter().zip(robot.joints()).map(|(v, j)| (v + 0.1).clamp(j.limits.lower, j.limits.upper)).collect()
            })
            .collect();
        let options = |i: usize| IkOptions {
            seed: Some(seeds[i].clone()),
            restarts: 1,
            max_iterations: 100,
            numeric: NumericOptions { mode: SearchMode::FirstFound, ..NumericOptions::default() },
            ..IkOptions::default()
        };
        let k_solver = k::JacobianIkSolver::new(1e-6, 1e-6, 1.0, 100);
        let (mut reach_ok, mut k_ok) = (0, 0);
        for i in 0..n {
            let all = solver.solve(&robot, &IkTarget::Pose(targets[i]), &options(i)).expect("solve");
            reach_ok += usize::from(all.feasible().next().is_some());
            arm.set_joint_positions_unchecked(&seeds[i]);
            arm.update_transforms();
            if k::InverseKinematicsSolver::solve(&k_solver, &arm, &to_k_iso(&targets[i])).is_ok() {
                let (dp, da) = pose_gap(&robot.fk(&arm.joint_positions()).expect("fk"), &targets[i]);
                k_ok += usize::from(dp <= 1e-6 && da <= 1e-6);
            }
        }
        let ik = race(
            n,
            rounds.min(5),
            |i| {
                black_box(solver.solve(&robot, &IkTarget::Pose(targets[i]), &options(i)).expect("solve"));
            },
            |i| {
                arm.set_joint_positions_unchecked(&seeds[i]);
                arm.update_transforms();
                let _ = black_box(k::InverseKinematicsSolver::solve(&k_solver, &arm, &to_k_iso(&targets[i])));
            },
        );
        let note = format!(
            "seed = solution + 0.1 rad, 1e-6 m / 1e-6 rad, ≤ 100 iterations; solved: reach {:.1} %, k {:.1} %",
            100.0 * reach_ok as f64 / n as f64,
            100.0 * k_ok as f64 / n as f64
        );
        row(name, "numeric IK", "k JacobianIkSolver", ik, &note);

        if name == "puma560" {
            let (opw, c) = opw_match(name, &robot, &opw_puma_geometries(&robot), &qs);
            vs_rs_opw(name, &robot, &opw, c, &qs, rounds, &row);
            vs_ikgeo(name, &robot, ikgeo_spherical(&robot), &qs, rounds, &row);
        } else {
            vs_ikgeo(name, &robot, ikgeo_ur5(&robot, &qs), &qs, rounds, &row);
        }
    }
    // The KUKA KR 16-2 from its URDF file: reach's closed form found from the geometry.
    let kr16 = kr16_urdf();
    let qs = random_qs(&kr16, poses, 2024);
    let (opw, c) = opw_match("kr16_2", &kr16, &opw_kr16_geometries(), &qs);
    vs_rs_opw("kr16_2 (URDF)", &kr16, &opw, c, &qs, rounds, &row);
    vs_ikgeo("kr16_2 (URDF)", &kr16, ikgeo_spherical(&kr16), &qs, rounds, &row);
}

/// The KUKA KR 16-2 read from its URDF file, base_link to tool0.
fn kr16_urdf() -> Robot {
    let text = include_str!("../../examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf");
    let chain = reach::model::UrdfChain { base: None, tip: Some("tool0".into()) };
    Robot::from_urdf_str(text, &chain).expect("kr16_2 urdf")
}

/// reach next to rs-opw-kinematics (`opw`, whose flange is reach's · `c⁻¹`) on `robot` at the
/// joint vectors `qs`: FK, Jacobian and closed-form IK rows of the table.
fn vs_rs_opw(
    name: &str,
    robot: &Robot,
    opw: &OPWKinematics,
    c: Rotation3<f64>,
    qs: &[Vec<f64>],
    rounds: usize,
    row: &impl Fn(&str, &str, &str, (f64, f64), &str),
) {
    let n = qs.len();
    let targets: Vec<Isometry3<f64>> = qs.iter().map(|q| robot.fk(q).expect("fk")).collect();
    // Forward kinematics of rs-opw checked against reach on every pose.
    for q in qs {
        let t = opw_pose(&opw.forward(&joints6(q)));
        let t = Isometry3::from_parts(t.translation, t.rotation * UnitQuaternion::from_rotation_matrix(&c));
        let (dp, da) = pose_gap(&t, &robot.fk(q).expect("fk"));
        assert!(dp < 1e-9 && da < 1e-9, "{name}: OPW parameters differ from reach by {dp} m, {da} rad");
    }
    let q6: Vec<Joints> = qs.iter().map(|q| joints6(q)).collect();
    let fk = race_fk(robot, qs, rounds, |i| {
        black_box(opw.forward(black_box(&q6[i])));
    });
    row(name, "FK", "rs-opw-kinematics", fk, "");
    let jacobian = race_jacobian(robot, qs, rounds, |i| {
        black_box(rs_opw_kinematics::jacobian::Jacobian::new(opw, black_box(&q6[i]), 1e-6));
    });
    row(name, "Jacobian", "rs-opw-kinematics", jacobian, "rs-opw: finite differences (6 extra FK)");
    // Closed-form IK, every branch, each checked by FK in both libraries. rs-opw is given
    // the same poses in its flange frame (reach flange · C⁻¹) and has no joint limits;
    // reach flags branches outside the preset's limits. reach is timed on its lean path
    // (`solve_into` a reused `IkSolutions`, what a real-time loop calls; equal to `solve`'s
    // result, checked here on every pose); allocations are counted for both of its paths.
    let cform = SolverKind::detect(robot).build(robot).expect("closed form");
    let options = IkOptions::default();
    let reach_targets: Vec<IkTarget> = targets.iter().map(|t| IkTarget::Pose(*t)).collect();
    let c_inv = UnitQuaternion::from_rotation_matrix(&c.inverse());
    let opw_targets: Vec<Pose> =
        targets.iter().map(|t| to_opw_pose(&Isometry3::from_parts(t.translation, t.rotation * c_inv))).collect();
    let (mut reach_n, mut reach_feasible, mut opw_n) = (0usize, 0usize, 0usize);
    let mut out = IkSolutions::default();
    for i in 0..n {
        let all = cform.solve(robot, &reach_targets[i], &options).expect("solve");
        cform.solve_into(robot, &reach_targets[i], &options, &mut out).expect("solve");
        assert_eq!(out, all, "solve_into differs from solve");
        reach_n += all.solutions.len();
        reach_feasible += all.feasible().count();
        let sols = opw.inverse(&opw_targets[i]);
        for s in &sols {
            let (dp, da) = pose_gap(&robot.fk(s).expect("fk"), &targets[i]);
            assert!(dp < 1e-6 && da < 1e-6, "rs-opw solution off by {dp} m, {da} rad");
        }
        opw_n += sols.len();
    }
    let reach_allocs = allocations_per_call(n, |i| {
        cform.solve_into(robot, &reach_targets[i], &options, &mut out).expect("solve");
        black_box(&out);
    });
    let reach_solve_allocs = allocations_per_call(n, |i| {
        black_box(cform.solve(robot, &reach_targets[i], &options).expect("solve"));
    });
    let opw_allocs = allocations_per_call(n, |i| {
        black_box(opw.inverse(&opw_targets[i]));
    });
    let ik = race_ik(robot, cform.as_ref(), &reach_targets, rounds, |i| {
        black_box(opw.inverse(black_box(&opw_targets[i])));
    });
    let note = format!(
        "all branches, FK-checked; mean solutions per pose: reach {:.2} (of which within limits {:.2}; labelled), rs-opw {:.2} (no limits); reach timed on `solve_into` a reused buffer; heap allocations per solve: reach {reach_allocs:.2} (`solve_into`; `solve`, returning new vectors: {reach_solve_allocs:.2}), rs-opw {opw_allocs:.2}",
        reach_n as f64 / n as f64,
        reach_feasible as f64 / n as f64,
        opw_n as f64 / n as f64
    );
    row(name, "closed-form IK", "rs-opw-kinematics", ik, &note);
}

fn to_k_iso(t: &Isometry3<f64>) -> k::Isometry3<f64> {
    to_k(&IsometryMatrix3::from_parts(t.translation, t.rotation.to_rotation_matrix()))
}
