//! Closed forms from the geometry, not the file format (issue 16): real arms described by
//! URDF (`examples/urdf/`) and an MDH table get the closed-form solver their axes fit,
//! through their standard-DH equivalent (`Robot::dh_equivalent`), with every branch, every
//! solution verified against the robot itself and its joint values as the robot takes them.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Vector3};
use reach::Robot;
use reach::ik::{IkOptions, IkTarget, SolverKind};
use reach::model::{Convention, Joint, Limits, RobotSpec, UrdfChain, presets};

use crate::common::{Rng, find_solution};

const KR16: &str = include_str!("../../../../examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf");
const KR120: &str = include_str!("../../../../examples/urdf/kuka_kr120_support/urdf/kr120r2500pro.urdf");
const PUMA: &str = include_str!("../../../../examples/urdf/unimation_puma560_description/urdf/puma560_robot.urdf");
const UR5: &str = include_str!("../../../../examples/urdf/ur_description/urdf/ur5.urdf");
const PANDA: &str = include_str!("../../../../examples/panda.urdf");

/// The chain of a URDF file from its root to `tip` (the KUKA files branch at the base link,
/// which also carries the `base` frame of ROS-Industrial).
fn urdf_to(text: &str, tip: &str) -> Robot {
    Robot::from_urdf_str(text, &UrdfChain { base: None, tip: Some(tip.into()) }).unwrap()
}

fn urdf(text: &str) -> Robot {
    Robot::from_urdf_str(text, &UrdfChain::default()).unwrap()
}

/// Craig's modified-DH table of the PUMA 560 (Craig, *Introduction to Robotics*, 3rd ed.,
/// Fig. 3.21): α_{i−1} = 0, −90, 0, −90, 90, −90°; a2 = 0.4318, a3 = 0.0203,
/// d3 = 0.15005, d4 = 0.4318 m; limits ±160°, ±120°, ±135°, ±266°, ±100°, ±266°.
fn puma_mdh() -> Robot {
    let row = |a: f64, alpha_deg: f64, d: f64, limit_deg: f64| {
        Joint::revolute(a, alpha_deg.to_radians(), d, 0.0).with_limits(-limit_deg.to_radians(), limit_deg.to_radians())
    };
    Robot::new(RobotSpec::new(
        "puma560-mdh",
        Convention::Mdh,
        vec![
            row(0.0, 0.0, 0.0, 160.0),
            row(0.0, -90.0, 0.0, 120.0),
            row(0.4318, 0.0, 0.15005, 135.0),
            row(0.0203, -90.0, 0.4318, 266.0),
            row(0.0, 90.0, 0.0, 100.0),
            row(0.0, -90.0, 0.0, 266.0),
        ],
    ))
    .unwrap()
}

/// The arms and the closed form their axes fit.
fn arms() -> Vec<(Robot, SolverKind)> {
    vec![
        (urdf_to(KR16, "tool0"), SolverKind::SphericalWrist),
        (urdf_to(KR120, "tool0"), SolverKind::SphericalWrist),
        (urdf(PUMA), SolverKind::SphericalWrist),
        (urdf(UR5), SolverKind::ParallelAxes),
        (puma_mdh(), SolverKind::SphericalWrist),
    ]
}

/// `max |a − b|` over the homogeneous matrices.
fn gap(a: &nalgebra::IsometryMatrix3<f64>, b: &nalgebra::IsometryMatrix3<f64>) -> f64 {
    (a.to_homogeneous() - b.to_homogeneous()).abs().max()
}

#[test]
fn every_arm_gets_its_closed_form() {
    for (robot, kind) in arms() {
        assert_eq!(SolverKind::detect(&robot), kind, "{}", robot.name());
        assert_eq!(kind.build(&robot).unwrap().name(), kind.as_str());
    }
}

#[test]
fn the_equivalent_has_the_robots_kinematics_and_joints() {
    let mut rng = Rng::new(16);
    for (robot, _) in arms() {
        let dh = robot.dh_equivalent().unwrap();
        assert_eq!(dh.convention(), Convention::Dh);
        for (a, b) in robot.joints().iter().zip(dh.joints()) {
            assert_eq!((&a.name, a.limits, a.home), (&b.name, b.limits, b.home));
        }
        for _ in 0..50 {
            let q = rng.joints(&robot);
            let d = gap(&robot.fk_matrix(&q).unwrap(), &dh.fk_matrix(&q).unwrap());
            // Exact files agree to rounding; the PUMA file's 1.570796325 (π/2 − 1.8e-9) is
            // made exact in the equivalent, which moves the tool by a few 1e-9.
            let bound = if robot.name() == "Puma560" { 1e-8 } else { 1e-12 };
            assert!(d < bound, "{}: {d:e} at {q:?}", robot.name());
        }
    }
    // The KR16's first axis points down in the file (`0 0 -1`): the equivalent turns it up
    // and flips the joint; axes 4 and 6 (`-1 0 0`) keep their direction.
    let kr16 = urdf_to(KR16, "tool0").dh_equivalent().unwrap();
    let flips: Vec<bool> = kr16.joints().iter().map(|j| j.flip).collect();
    assert_eq!(flips, [true, false, false, false, false, false]);
    let p: Vec<_> = kr16.joints().iter().map(|j| *j.dh().unwrap()).collect();
    let lengths = [p[0].a, p[0].d, p[1].a, p[2].a, p[3].d];
    let expected = [0.26, 0.675, 0.68, 0.035, 0.67];
    for (got, want) in lengths.iter().zip(expected) {
        assert!((got.abs() - want).abs() < 1e-12, "{lengths:?}");
    }
}

/// ROS-Industrial's UR5 layout and Universal Robots' DH table are the same arm: the URDF's
/// base link is the DH base turned 180° about z, and the tool differs by a fixed transform.
#[test]
fn the_ur5_urdf_is_the_ur5_preset() {
    let (file, preset) = (urdf(UR5), presets::get("ur5").unwrap());
    let zero = [0.0; 6];
    let base = nalgebra::IsometryMatrix3::rotation(Vector3::z() * PI);
    let tool = (base * preset.fk_matrix(&zero).unwrap()).inverse() * file.fk_matrix(&zero).unwrap();
    let mut rng = Rng::new(5);
    for _ in 0..100 {
        let q = rng.joints(&file);
        let via_preset = base * preset.fk_matrix(&q).unwrap() * tool;
        let d = gap(&file.fk_matrix(&q).unwrap(), &via_preset);
        assert!(d < 1e-12, "{d:e} at {q:?}");
    }
    // The tool transform is the URDF's ee_link convention: x along the flange axis.
    let r = tool.rotation.matrix();
    assert!((tool.translation.vector.norm()) < 1e-12, "{tool:?}");
    assert!((r * Vector3::x() - Vector3::z()).norm() < 1e-12, "{r}");
}

/// 200 poses from random joint vectors within the limits, per arm: every solution is within
/// 1e-9 of the target by the robot's own forward kinematics and flagged within limits exactly
/// when it is, the generating joint vector is among them (modulo whole turns), and the
/// solutions are as many as the equivalent closed form finds without limits (its own DH
/// table, no limits): all branches, 8 where all 8 exist.
#[test]
fn every_branch_of_200_poses_round_trips() {
    for (robot, kind) in arms() {
        let solver = kind.build(&robot).unwrap();
        let mut free = robot.dh_equivalent().unwrap().spec().clone();
        for j in &mut free.joints {
            j.limits = Limits::UNLIMITED;
        }
        let free = Robot::new(free).unwrap();
        let free_solver = kind.build(&free).unwrap();
        let mut rng = Rng::new(0x16);
        let mut all_eight = 0;
        for _ in 0..200 {
            let q = rng.joints(&robot);
            let pose = robot.fk(&q).unwrap();
            let target = IkTarget::Pose(pose);
            let sols = solver.solve(&robot, &target, &IkOptions::default()).unwrap();
            assert_eq!(sols.solver, kind.as_str());
            for s in &sols.solutions {
                let t = robot.fk_matrix(&s.q).unwrap();
                let dp = (t.translation.vector - pose.translation.vector).norm();
                let dr = (t.rotation.matrix() - pose.rotation.to_rotation_matrix().matrix()).abs().max();
                assert!(dp < 1e-9 && dr < 1e-9, "{}: {dp:e} m, {dr:e} at {:?}", robot.name(), s.q);
                assert!(s.position_error < 1e-9 && s.orientation_error < 1e-9, "{}: {s:?}", robot.name());
                let inside = robot.first_joint_outside_limits(&s.q, 1e-9).is_none();
                assert_eq!(s.within_limits, inside, "{}: {s:?}", robot.name());
            }
            assert!(find_solution(&sols, &q, 1e-7).is_some(), "{}: {q:?} not among {sols:?}", robot.name());
            let unlimited = free_solver.solve(&free, &target, &IkOptions::default()).unwrap();
            assert_eq!(sols.solutions.len(), unlimited.solutions.len(), "{}: {q:?}", robot.name());
            all_eight += usize::from(sols.solutions.len() == 8);
        }
        println!("{}: {all_eight} of 200 poses with all 8 branches", robot.name());
        assert!(all_eight >= 100, "{}: {all_eight} of 200 poses with all 8 branches", robot.name());
    }
}

/// Branch labels and the one-branch solve carry over: `solve_branch` returns exactly the
/// solution of the full solve labelled so.
#[test]
fn one_branch_equals_the_full_solve_restricted() {
    for (robot, kind) in arms() {
        let solver = kind.build(&robot).unwrap();
        let q = Rng::new(7).joints(&robot);
        let target = IkTarget::Pose(robot.fk(&q).unwrap());
        let all = solver.solve(&robot, &target, &IkOptions::default()).unwrap();
        for s in &all.solutions {
            let one = solver.solve_branch(&robot, &target, &s.branch, &IkOptions::default()).unwrap();
            assert_eq!(one.solutions, vec![s.clone()], "{}: {}", robot.name(), s.branch);
        }
    }
}

/// A solver built for a robot still solves a copy with another tool and base, as for a
/// DH robot.
#[test]
fn another_tool_and_base_are_honoured() {
    let robot = urdf_to(KR16, "tool0");
    let solver = SolverKind::SphericalWrist.build(&robot).unwrap();
    let moved = robot
        .with_tool(Isometry3::translation(0.0, 0.05, 0.2))
        .unwrap()
        .with_base(Isometry3::rotation(Vector3::new(0.1, -0.2, FRAC_PI_2)))
        .unwrap();
    let q = [0.4, -1.0, 0.7, 2.0, 0.9, -0.3];
    let target = IkTarget::Pose(moved.fk(&q).unwrap());
    let sols = solver.solve(&moved, &target, &IkOptions::default()).unwrap();
    assert!(find_solution(&sols, &q, 1e-9).is_some(), "{sols:?}");
    // The same solutions as a solver built for the moved robot (its own equivalent).
    let own = SolverKind::SphericalWrist.build(&moved).unwrap().solve(&moved, &target, &IkOptions::default()).unwrap();
    assert_eq!(sols.solutions.len(), own.solutions.len());
    for (a, b) in sols.solutions.iter().zip(&own.solutions) {
        assert_eq!(a.branch, b.branch);
        assert!(a.q.iter().zip(&b.q).all(|(x, y)| (x - y).abs() < 1e-9), "{a:?} vs {b:?}");
    }
}

/// Chains whose axes fit no closed form keep the numeric solver: the Panda (7 joints), and
/// the KR16 with axis 6 moved 1 cm off the wrist centre (a non-spherical wrist).
#[test]
fn chains_that_do_not_fit_stay_numeric() {
    let panda =
        Robot::from_urdf_str(PANDA, &UrdfChain { base: Some("panda_link0".into()), tip: Some("panda_link8".into()) })
            .unwrap();
    assert_eq!(panda.dof(), 7);
    assert_eq!(SolverKind::detect(&panda), SolverKind::Numeric);
    let moved = KR16.replacen(
        "<origin rpy=\"0 0 0\" xyz=\"0 0 0\"/>\n    <parent link=\"link_5\"/>",
        "<origin rpy=\"0 0 0\" xyz=\"0 0.01 0\"/>\n    <parent link=\"link_5\"/>",
        1,
    );
    assert_ne!(moved, KR16, "the joint_a6 origin was not found");
    let robot = urdf_to(&moved, "tool0");
    assert_eq!(SolverKind::detect(&robot), SolverKind::Numeric);
    let err = SolverKind::SphericalWrist.build(&robot).err().unwrap().to_string();
    assert!(err.contains("d5") && err.contains("standard-DH equivalent"), "{err}");
}
