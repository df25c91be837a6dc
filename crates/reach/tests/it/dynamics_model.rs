//! Inverse dynamics, mass matrix and energies against textbook closed forms, hand
//! computations and physical identities (power balance, `T = ½ q̇ᵀ M q̇`, `g = ∂V/∂q`).

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, FRAC_PI_6};

use nalgebra::{DMatrix, Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use reach::effort::dynamics::{
    Dynamics, gravity_torques, inverse_dynamics, kinetic_energy, mass_matrix, potential_energy,
};
use reach::model::{Convention, Joint, JointGeometry, JointKind, LinkInertial, Robot, RobotSpec, presets};

const G: f64 = 9.80665;

/// A planar two-link arm (standard DH, joints about z) in a vertical plane: gravity along −y.
/// Link i: length `l[i]`, mass `m[i]` with its centre `lc[i]` from joint i, inertia `inertia[i]`
/// about the centre (about z; the x/y moments do not matter in the plane but are given).
struct TwoLink {
    l: [f64; 2],
    lc: [f64; 2],
    m: [f64; 2],
    inertia: [f64; 2],
}

impl TwoLink {
    fn robot(&self) -> Robot {
        let mut spec = RobotSpec::new(
            "two-link",
            Convention::Dh,
            vec![Joint::revolute(self.l[0], 0.0, 0.0, 0.0), Joint::revolute(self.l[1], 0.0, 0.0, 0.0)],
        );
        // DH frame i sits at the far end of link i, x along the link.
        spec.inertials = (0..2)
            .map(|i| {
                let iz = self.inertia[i];
                LinkInertial::new(
                    self.m[i],
                    Vector3::new(self.lc[i] - self.l[i], 0.0, 0.0),
                    [0.1 * iz, iz, iz, 0.0, 0.0, 0.0],
                )
            })
            .collect();
        spec.gravity = Vector3::new(0.0, -G, 0.0);
        Robot::new(spec).unwrap()
    }

    /// Spong, Hutchinson & Vidyasagar, "Robot Modeling and Control", §7.4.2 (Lagrange).
    fn closed_form(&self, q: [f64; 2], qd: [f64; 2], qdd: [f64; 2]) -> [f64; 2] {
        let [l1, _] = self.l;
        let [lc1, lc2] = self.lc;
        let [m1, m2] = self.m;
        let [i1, i2] = self.inertia;
        let (c1, c2, c12) = (q[0].cos(), q[1].cos(), (q[0] + q[1]).cos());
        let s2 = q[1].sin();
        let d11 = m1 * lc1 * lc1 + m2 * (l1 * l1 + lc2 * lc2 + 2.0 * l1 * lc2 * c2) + i1 + i2;
        let d12 = m2 * (lc2 * lc2 + l1 * lc2 * c2) + i2;
        let d22 = m2 * lc2 * lc2 + i2;
        let h = -m2 * l1 * lc2 * s2;
        let g1 = (m1 * lc1 + m2 * l1) * G * c1 + m2 * lc2 * G * c12;
        let g2 = m2 * lc2 * G * c12;
        [
            d11 * qdd[0] + d12 * qdd[1] + 2.0 * h * qd[0] * qd[1] + h * qd[1] * qd[1] + g1,
            d12 * qdd[0] + d22 * qdd[1] - h * qd[0] * qd[0] + g2,
        ]
    }
}

const ARM: TwoLink = TwoLink { l: [0.8, 0.6], lc: [0.35, 0.25], m: [3.0, 2.0], inertia: [0.16, 0.06] };

#[test]
fn two_link_arm_matches_the_textbook_equations() {
    let robot = ARM.robot();
    let states = [
        ([0.0, 0.0], [0.0, 0.0], [0.0, 0.0]),
        ([FRAC_PI_6, FRAC_PI_4], [0.0, 0.0], [1.0, -2.0]),
        ([-1.2, 2.3], [1.5, -0.7], [0.3, 2.2]),
        ([2.9, -1.1], [-3.0, 2.5], [-4.0, 1.0]),
    ];
    for (q, qd, qdd) in states {
        let tau = inverse_dynamics(&robot, &q, &qd, &qdd).unwrap();
        let expected = ARM.closed_form(q, qd, qdd);
        for i in 0..2 {
            assert!((tau[i] - expected[i]).abs() < 1e-12, "q {q:?}: τ{} {} vs {}", i + 1, tau[i], expected[i]);
        }
    }
}

#[test]
fn static_torques_by_hand() {
    // Point masses at the link ends: 2 kg at the elbow, 1 kg at the tip; q = (30°, 45°).
    let arm = TwoLink { l: [1.0, 0.5], lc: [1.0, 0.5], m: [2.0, 1.0], inertia: [0.0, 0.0] };
    let robot = arm.robot();
    let q = [FRAC_PI_6, FRAC_PI_4];
    let g = gravity_torques(&robot, &q).unwrap();
    // Lever arms are the horizontal distances from each joint: cos 30° and cos 75°.
    let tip_from_elbow = 0.5 * (75.0_f64).to_radians().cos();
    let elbow = (30.0_f64).to_radians().cos();
    assert!((g[1] - 1.0 * G * tip_from_elbow).abs() < 1e-12, "{g:?}");
    assert!((g[0] - (2.0 * G * elbow + 1.0 * G * (elbow + tip_from_elbow))).abs() < 1e-12, "{g:?}");
    // Straight up, nothing to hold.
    let up = gravity_torques(&robot, &[FRAC_PI_2, 0.0]).unwrap();
    assert!(up.iter().all(|t| t.abs() < 1e-12), "{up:?}");
}

/// A rotating arm with a slider along it (URDF convention, prismatic joint), a point mass `m`
/// at the slider: `τ = m r² θ̈ + 2 m r ṙ θ̇ + m g r cos θ`, `f = m r̈ − m r θ̇² + m g sin θ`.
#[test]
fn polar_arm_with_prismatic_joint_matches_the_closed_form() {
    let m = 1.7;
    let axis = |v: Vector3<f64>| JointGeometry::Axis { origin: Isometry3::identity(), axis: Unit::new_normalize(v) };
    let revolute = Joint { geometry: axis(Vector3::z()), ..Joint::revolute(0.0, 0.0, 0.0, 0.0) };
    let prismatic =
        Joint { kind: JointKind::Prismatic, geometry: axis(Vector3::x()), ..Joint::revolute(0.0, 0.0, 0.0, 0.0) };
    let mut spec = RobotSpec::new("polar", Convention::Urdf, vec![revolute, prismatic]);
    spec.inertials = vec![LinkInertial::zero(), LinkInertial::point(m, Vector3::zeros())];
    spec.gravity = Vector3::new(0.0, -G, 0.0);
    let robot = Robot::new(spec).unwrap();
    for (q, qd, qdd) in [([0.4, 0.8], [1.3, -0.4], [0.7, 2.0]), ([-2.0, 1.5], [-0.5, 0.9], [-1.0, -3.0])] {
        let (th, r) = (q[0], q[1]);
        let tau = inverse_dynamics(&robot, &q, &qd, &qdd).unwrap();
        let t1 = m * r * r * qdd[0] + 2.0 * m * r * qd[1] * qd[0] + m * G * r * th.cos();
        let f2 = m * qdd[1] - m * r * qd[0] * qd[0] + m * G * th.sin();
        assert!((tau[0] - t1).abs() < 1e-12 && (tau[1] - f2).abs() < 1e-12, "{tau:?} vs [{t1}, {f2}]");
    }
}

/// Deterministic pseudo-random numbers in [lo, hi) (SplitMix64).
struct Rng(u64);

impl Rng {
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        lo + (hi - lo) * (z >> 11) as f64 / (1u64 << 53) as f64
    }

    fn vector(&mut self, n: usize, lo: f64, hi: f64) -> Vec<f64> {
        (0..n).map(|_| self.uniform(lo, hi)).collect()
    }
}

/// The Puma 560 written in modified DH (Craig), its inertials moved into the MDH frames:
/// MDH frame i = DH frame i · (Tx(aᵢ)·Rx(αᵢ))⁻¹, so a DH-frame body is moved by Tx(aᵢ)·Rx(αᵢ).
fn puma_mdh(dh: &Robot) -> Robot {
    let rows: Vec<_> = dh.joints().iter().map(|j| *j.dh().unwrap()).collect();
    let mut joints = Vec::new();
    for i in 0..6 {
        let (a_prev, alpha_prev) = if i == 0 { (0.0, 0.0) } else { (rows[i - 1].a, rows[i - 1].alpha) };
        joints.push(Joint::revolute(a_prev, alpha_prev, rows[i].d, rows[i].theta_offset));
    }
    let mut spec = RobotSpec::new("puma-mdh", Convention::Mdh, joints);
    spec.tool = Isometry3::from_parts(
        Translation3::new(rows[5].a, 0.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), rows[5].alpha),
    );
    spec.inertials = dh
        .inertials()
        .iter()
        .zip(&rows)
        .map(|(b, r)| {
            b.transformed(&Isometry3::from_parts(
                Translation3::new(r.a, 0.0, 0.0),
                UnitQuaternion::from_axis_angle(&Vector3::x_axis(), r.alpha),
            ))
        })
        .collect();
    Robot::new(spec).unwrap()
}

#[test]
fn modified_dh_model_gives_the_same_torques_as_standard_dh() {
    let dh = presets::get("puma560").unwrap();
    let mdh = puma_mdh(&dh);
    let mut rng = Rng(7);
    for _ in 0..20 {
        let (q, qd, qdd) = (rng.vector(6, -3.0, 3.0), rng.vector(6, -2.0, 2.0), rng.vector(6, -5.0, 5.0));
        assert!(
            (dh.fk_matrix(&q).unwrap().to_homogeneous() - mdh.fk_matrix(&q).unwrap().to_homogeneous()).amax() < 1e-12
        );
        let a = inverse_dynamics(&dh, &q, &qd, &qdd).unwrap();
        let b = inverse_dynamics(&mdh, &q, &qd, &qdd).unwrap();
        for i in 0..6 {
            assert!((a[i] - b[i]).abs() < 1e-10, "joint {}: {} vs {}", i + 1, a[i], b[i]);
        }
    }
}

#[test]
fn flipped_joint_reverses_rate_and_torque() {
    let dh = presets::get("puma560").unwrap();
    let mut spec = dh.spec().clone();
    spec.joints[1].flip = true;
    spec.joints[4].flip = true;
    let flipped = Robot::new(spec).unwrap();
    let s = [1.0, -1.0, 1.0, 1.0, -1.0, 1.0];
    let mut rng = Rng(11);
    for _ in 0..10 {
        let (q, qd, qdd) = (rng.vector(6, -3.0, 3.0), rng.vector(6, -2.0, 2.0), rng.vector(6, -5.0, 5.0));
        let neg = |v: &[f64]| v.iter().zip(s).map(|(x, s)| x * s).collect::<Vec<_>>();
        let a = inverse_dynamics(&dh, &q, &qd, &qdd).unwrap();
        let b = inverse_dynamics(&flipped, &neg(&q), &neg(&qd), &neg(&qdd)).unwrap();
        for i in 0..6 {
            assert!((a[i] - s[i] * b[i]).abs() < 1e-10, "joint {}", i + 1);
        }
    }
}

/// `q(t) = q0 + A·sin(ωt + φ)` per joint, with exact rates.
fn smooth(t: f64, k: usize) -> ([f64; 6], [f64; 6], [f64; 6]) {
    let (mut q, mut qd, mut qdd) = ([0.0; 6], [0.0; 6], [0.0; 6]);
    for i in 0..6 {
        let (q0, a, w, p) = (0.3 * i as f64 - 0.7, 0.9 - 0.1 * i as f64, 1.0 + 0.4 * (i + k) as f64, 0.5 * i as f64);
        q[i] = q0 + a * (w * t + p).sin();
        qd[i] = a * w * (w * t + p).cos();
        qdd[i] = -a * w * w * (w * t + p).sin();
    }
    (q, qd, qdd)
}

#[test]
fn power_balance_along_a_smooth_motion() {
    // Σ τᵢ q̇ᵢ = d/dt (T + V), T and V from link velocities and heights (not from the recursion).
    for robot in [presets::get("puma560").unwrap(), mixed_arm(), puma_mdh(&presets::get("puma560").unwrap())] {
        let mut dynamics = Dynamics::new(&robot).unwrap();
        let n = robot.dof();
        let mut tau = vec![0.0; n];
        for step in 0..12 {
            let t = 0.17 * step as f64;
            let (q, qd, qdd) = smooth(t, step % 2);
            let (q, qd, qdd) = (&q[..n], &qd[..n], &qdd[..n]);
            dynamics.inverse_dynamics_into(q, qd, qdd, &mut tau).unwrap();
            let power: f64 = tau.iter().zip(qd).map(|(a, b)| a * b).sum();
            let energy = |s: f64| {
                let (q, qd, _) = smooth(s, step % 2);
                kinetic_energy(&robot, &q[..n], &qd[..n]).unwrap() + potential_energy(&robot, &q[..n]).unwrap()
            };
            let h = 1e-4;
            // Fourth-order central difference.
            let de =
                (energy(t - 2.0 * h) - 8.0 * energy(t - h) + 8.0 * energy(t + h) - energy(t + 2.0 * h)) / (12.0 * h);
            assert!((power - de).abs() < 1e-6 * (1.0 + power.abs()), "{} t = {t}: {power} vs {de}", robot.name());
        }
    }
}

/// A robot mixing everything: URDF axes (oblique), a prismatic joint, a flipped joint, full
/// inertia tensors with products, a tilted gravity.
fn mixed_arm() -> Robot {
    let pose = |x: f64, y: f64, z: f64, r: f64, p: f64, w: f64| {
        Isometry3::from_parts(Translation3::new(x, y, z), UnitQuaternion::from_euler_angles(r, p, w))
    };
    let joint = |kind: JointKind, origin: Isometry3<f64>, axis: Vector3<f64>| Joint {
        kind,
        geometry: JointGeometry::Axis { origin, axis: Unit::new_normalize(axis) },
        ..Joint::revolute(0.0, 0.0, 0.0, 0.0)
    };
    let mut joints = vec![
        joint(JointKind::Revolute, pose(0.0, 0.0, 0.3, 0.0, 0.0, 0.2), Vector3::new(0.0, 0.0, 1.0)),
        joint(JointKind::Revolute, pose(0.1, -0.05, 0.2, 0.3, -0.4, 0.1), Vector3::new(0.0, -1.0, 0.2)),
        joint(JointKind::Prismatic, pose(0.25, 0.0, 0.02, 0.0, 0.5, 0.0), Vector3::new(1.0, 0.0, 1.0)),
        joint(JointKind::Revolute, pose(0.0, 0.05, 0.1, 0.1, 0.0, -0.2), Vector3::new(0.3, 0.4, -0.5)),
    ];
    joints[1].flip = true;
    let mut spec = RobotSpec::new("mixed", Convention::Urdf, joints);
    spec.tool = pose(0.0, 0.0, 0.12, 0.0, 0.0, 0.0);
    spec.gravity = Vector3::new(1.0, -2.0, -9.0);
    spec.inertials = vec![
        LinkInertial::new(2.0, Vector3::new(0.01, 0.02, 0.1), [0.03, 0.04, 0.02, 0.001, -0.002, 0.003]),
        LinkInertial::new(1.5, Vector3::new(0.12, -0.01, 0.0), [0.01, 0.02, 0.025, -0.001, 0.0, 0.002]),
        LinkInertial::new(0.8, Vector3::new(0.0, 0.03, -0.02), [0.004, 0.005, 0.006, 0.0, 0.001, 0.0]),
        LinkInertial::point(0.5, Vector3::new(0.02, 0.0, 0.1)),
    ];
    Robot::new(spec).unwrap()
}

#[test]
fn mass_matrix_is_symmetric_positive_definite_and_gives_the_kinetic_energy() {
    let mut rng = Rng(3);
    for robot in [presets::get("puma560").unwrap(), mixed_arm(), ARM.robot()] {
        let n = robot.dof();
        for _ in 0..20 {
            let (q, qd, qdd) = (rng.vector(n, -3.0, 3.0), rng.vector(n, -2.0, 2.0), rng.vector(n, -5.0, 5.0));
            let m = mass_matrix(&robot, &q).unwrap();
            assert_eq!(m, m.transpose());
            assert!(m.clone().cholesky().is_some(), "{}: not positive definite at {q:?}", robot.name());
            let qd_v = DMatrix::from_column_slice(n, 1, &qd);
            let t = 0.5 * (qd_v.transpose() * &m * &qd_v)[(0, 0)];
            let t_links = kinetic_energy(&robot, &q, &qd).unwrap();
            assert!((t - t_links).abs() < 1e-10 * (1.0 + t), "{}: ½q̇ᵀMq̇ {t} vs {t_links}", robot.name());
            // τ = M q̈ + τ(q, q̇, 0).
            let bias = inverse_dynamics(&robot, &q, &qd, &vec![0.0; n]).unwrap();
            let tau = inverse_dynamics(&robot, &q, &qd, &qdd).unwrap();
            let mqdd = &m * DMatrix::from_column_slice(n, 1, &qdd);
            for i in 0..n {
                assert!((tau[i] - bias[i] - mqdd[i]).abs() < 1e-10, "{} joint {}", robot.name(), i + 1);
            }
        }
    }
}

#[test]
fn gravity_torques_are_the_gradient_of_the_potential_energy() {
    let mut rng = Rng(5);
    for robot in [presets::get("puma560").unwrap(), mixed_arm()] {
        let n = robot.dof();
        for _ in 0..10 {
            let q = rng.vector(n, -2.5, 2.5);
            let g = gravity_torques(&robot, &q).unwrap();
            for i in 0..n {
                let h = 1e-6;
                let (mut a, mut b) = (q.clone(), q.clone());
                a[i] += h;
                b[i] -= h;
                let dv = (potential_energy(&robot, &a).unwrap() - potential_energy(&robot, &b).unwrap()) / (2.0 * h);
                assert!((g[i] - dv).abs() < 1e-6, "{} joint {}: {} vs {dv}", robot.name(), i + 1, g[i]);
            }
        }
    }
}

#[test]
fn puma_home_shoulder_holds_the_arm() {
    // At q = 0 the upper arm and forearm stretch out horizontally: the shoulder holds them, the
    // waist (vertical axis) holds nothing.
    let puma = presets::get("puma560").unwrap();
    let g = gravity_torques(&puma, &[0.0; 6]).unwrap();
    assert!(g[0].abs() < 1e-12, "{g:?}");
    assert!(g[1] > 30.0, "{g:?}");
    assert_eq!(puma.inertials().iter().map(|b| b.mass).collect::<Vec<_>>(), vec![0.0, 17.4, 4.8, 0.82, 0.34, 0.09]);
}

/// The `ur5` preset carries the published point masses: at random joint values each joint's
/// gravity torque is the moment about its axis of the weights of the links beyond it, their
/// centres placed by the preset's frames (`com` in DH frame i).
#[test]
fn ur5_gravity_torques_are_the_moments_of_its_published_point_masses() {
    let ur5 = presets::get("ur5").unwrap();
    assert!(ur5.has_dynamics());
    let masses: Vec<f64> = ur5.inertials().iter().map(|l| l.mass).collect();
    assert_eq!(masses, [3.7, 8.393, 2.33, 1.219, 1.219, 0.1897]);
    let coms = [
        [0.0, -0.02561, 0.00193],
        [0.2125, 0.0, 0.11336],
        [0.15, 0.0, 0.0265],
        [0.0, -0.0018, 0.01634],
        [0.0, -0.0018, 0.01634],
        [0.0, 0.0, -0.001159],
    ];
    for q in [[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [0.3, -1.1, 0.7, -2.0, 0.4, 1.3], [-2.0, -0.4, 2.2, 0.5, -1.0, 0.2]] {
        let frames = ur5.frames(&q).unwrap();
        let tau = gravity_torques(&ur5, &q).unwrap();
        for j in 0..6 {
            // Joint j turns about z of the frame before it (standard DH).
            let before = if j == 0 { nalgebra::IsometryMatrix3::identity() } else { frames[j - 1] };
            let (axis, origin) = (before.rotation * Vector3::z(), before.translation.vector);
            let moment: f64 = (j..6)
                .map(|i| {
                    let c = frames[i] * nalgebra::Point3::from(Vector3::from(coms[i]));
                    (c.coords - origin).cross(&Vector3::new(0.0, 0.0, -G * masses[i])).dot(&axis)
                })
                .sum();
            // τ holds the weight up: it is minus the weight's moment.
            assert!((tau[j] + moment).abs() < 1e-9, "q = {q:?}, joint {}: τ = {}, moment {moment}", j + 1, tau[j]);
        }
    }
}
