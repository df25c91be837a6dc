//! Seed 004 (notes 004 §2.2, §5.4): IK of the `varan4` arm — base yaw plus a planar
//! three-link arm (900/700/500 mm) — with the redundancy exposed as the absolute angle of the
//! last link, `φ = q2 + q3 + q4`.

use std::f64::consts::{FRAC_PI_2, PI};

use approx::assert_relative_eq;
use nalgebra::{Isometry3, Point3, Vector3};
use proptest::prelude::*;
use reach::angle::{deg, wrap};
use reach::ik::yaw_planar3::YawPlanar3;
use reach::ik::{IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::{Convention, Joint, Robot, RobotSpec, presets};

fn varan() -> (Robot, YawPlanar3) {
    let robot = presets::get("varan4").unwrap();
    let s = YawPlanar3::from_robot(&robot).unwrap();
    (robot, s)
}

fn contains(sols: &IkSolutions, q: &[f64], tol: f64) -> bool {
    sols.solutions.iter().any(|s| s.q.iter().zip(q).all(|(a, b)| wrap(a - b).abs() < tol))
}

#[test]
fn detected_for_the_preset() {
    assert_eq!(SolverKind::detect(&presets::get("varan4").unwrap()), SolverKind::YawPlanar3);
}

#[test]
fn fk_vectors_of_section_5_4_solved_back() {
    // Notes 004 §5.4: (q2, q3, q4) in degrees → O4 in mm (O1 frame, q1 = 0). The preset
    // reaches the printed O4 (rounded to 1e-3 mm); solving for that point with
    // φ = q2 + q3 + q4 gives the configuration back.
    let rows: [([f64; 3], [f64; 2]); 7] = [
        ([0.0, 0.0, 0.0], [2100.0, 0.0]),
        ([30.0, 0.0, 0.0], [1818.653, 1050.0]),
        ([30.0, -120.0, 120.0], [1212.436, 0.0]),
        ([60.0, 45.0, -30.0], [398.236, 1938.534]),
        ([90.0, -90.0, 0.0], [1200.0, 900.0]),
        ([120.0, -120.0, -120.0], [0.0, 346.410]),
        ([45.0, 30.0, 60.0], [464.016, 1666.098]),
    ];
    let (robot, s) = varan();
    for (q_deg, o4) in rows {
        for yaw_deg in [0.0, 30.0, -135.0] {
            let yaw = deg(yaw_deg);
            let q = [yaw, deg(q_deg[0]), deg(q_deg[1]), deg(q_deg[2])];
            let p = Point3::from(robot.fk(&q).unwrap().translation.vector);
            let (x, z) = (o4[0] / 1000.0, o4[1] / 1000.0);
            assert!((p - Point3::new(x * yaw.cos(), x * yaw.sin(), z)).norm() < 1e-6, "{q_deg:?}: {p}");
            let phi = deg(q_deg.iter().sum());
            let seed = vec![yaw, 0.0, 0.0, 0.0];
            let opts = IkOptions { free_parameter: Some(phi), seed: Some(seed), ..IkOptions::default() };
            let sols = s.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
            let found = sols
                .solutions
                .iter()
                .find(|s| s.q.iter().zip(&q).all(|(a, b)| wrap(a - b).abs() < 1e-9))
                .unwrap_or_else(|| panic!("{q_deg:?} yaw {yaw_deg}: {:?}", sols.solutions));
            assert!(found.within_limits, "{q_deg:?}");
            assert!(found.position_error < 1e-12);
            // Stretched arms ((0, 0, 0) and (30, 0, 0): q3 = 0) are elbow singularities.
            assert_eq!(found.singularities.contains(&SingularityKind::Elbow), q_deg[1] == 0.0, "{q_deg:?}");
        }
    }
    // (0, 0, 0) is fully stretched, (120, −120, −120) puts the tool on the yaw axis.
    let opts = IkOptions { free_parameter: Some(0.0), ..IkOptions::default() };
    let sols = s.solve(&robot, &IkTarget::Position(Point3::new(2.1, 0.0, 0.0)), &opts).unwrap();
    assert_eq!(sols.solutions.len(), 1);
    assert_eq!(sols.solutions[0].singularities, vec![SingularityKind::Elbow]);
    let opts = IkOptions { free_parameter: Some(deg(-120.0)), ..IkOptions::default() };
    let sols = s.solve(&robot, &IkTarget::Position(Point3::new(0.0, 0.0, 0.34641)), &opts).unwrap();
    assert!(sols.solutions.iter().all(|s| s.singularities.contains(&SingularityKind::Shoulder) && s.q[0] == 0.0));
    assert!(sols.solutions.iter().all(|s| s.branch.get("base") == Some("front")));
}

#[test]
fn both_elbows_at_a_fixed_phi() {
    // (90, −90, 0): O4 = (1.2, 0, 0.9), wrist O3 = (0.7, 0.9). The other elbow mirrors link 2
    // about the line O1–O3: q2' = 2·atan2(0.9, 0.7) − 90°, q3' = +90°, q4' = −(q2' + 90°).
    let (robot, s) = varan();
    let opts = IkOptions { free_parameter: Some(0.0), ..IkOptions::default() };
    let sols = s.solve(&robot, &IkTarget::Position(Point3::new(1.2, 0.0, 0.9)), &opts).unwrap();
    let find = |elbow: &str| {
        sols.solutions
            .iter()
            .find(|s| s.branch.get("base") == Some("front") && s.branch.get("elbow") == Some(elbow))
            .unwrap()
    };
    let up = find("up");
    for (a, e) in up.q.iter().zip([0.0, FRAC_PI_2, -FRAC_PI_2, 0.0]) {
        assert_relative_eq!(*a, e, epsilon = 1e-12);
    }
    let q2 = 2.0 * 0.9f64.atan2(0.7) - FRAC_PI_2;
    for (a, e) in find("down").q.iter().zip([0.0, q2, FRAC_PI_2, -(q2 + FRAC_PI_2)]) {
        assert_relative_eq!(*a, e, epsilon = 1e-12);
    }
    assert_relative_eq!(q2.to_degrees(), 14.250032, epsilon = 1e-6);
    assert_eq!(up.branch.get("phi_deg"), Some("0.0000"));
}

#[test]
fn sampled_self_motion() {
    let (robot, s) = varan();
    let q = [0.2, deg(45.0), deg(30.0), deg(60.0)];
    let p = Point3::from(robot.fk(&q).unwrap().translation.vector);
    let opts = IkOptions { redundancy_step: deg(2.0), ..IkOptions::default() };
    let sols = s.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
    assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
    // Every solution's φ label is its last link's angle.
    for sol in &sols.solutions {
        let phi: f64 = sol.branch.get("phi_deg").unwrap().parse().unwrap();
        let q4: [f64; 4] = sol.q.clone().try_into().unwrap();
        assert!(wrap(deg(phi) - s.last_link_angle(&q4)).abs() < 1e-5);
    }
    // Samples ≤ 2° apart along each feasible interval, two elbows inside, one at the ends.
    let [front, back] = s.feasible_intervals(&p);
    let expected: usize = front
        .iter()
        .chain(&back)
        .map(|iv| {
            let n = (iv.width() / deg(2.0)).ceil() as usize;
            if iv.width() >= 2.0 * PI - 1e-9 { 2 * n } else { 2 * (n + 1) - 2 }
        })
        .sum();
    assert_eq!(sols.solutions.len(), expected);
    assert!(sols.feasible().count() > 10);
    // The sample closest to the original φ is within one step of the original q.
    let phi0 = s.last_link_angle(&q);
    assert!(sols.solutions.iter().any(|sol| {
        let q4: [f64; 4] = sol.q.clone().try_into().unwrap();
        wrap(s.last_link_angle(&q4) - phi0).abs() <= deg(1.0) + 1e-9 && sol.branch.get("elbow") == Some("down")
    }));
}

#[test]
fn failures() {
    let (robot, s) = varan();
    let sols = s.solve(&robot, &IkTarget::Position(Point3::new(2.2, 0.0, 0.0)), &IkOptions::default()).unwrap();
    assert!(sols.solutions.is_empty());
    match sols.failure {
        Some(IkFailure::Unreachable { distance, reach, .. }) => {
            assert_relative_eq!(distance, 2.2, epsilon = 1e-12);
            assert_relative_eq!(reach, 2.1, epsilon = 1e-12);
        }
        other => panic!("{other:?}"),
    }
    // Reachable position, but the last link cannot point backwards there.
    let opts = IkOptions { free_parameter: Some(PI), ..IkOptions::default() };
    let sols = s.solve(&robot, &IkTarget::Position(Point3::new(1.818653, 0.0, 1.05)), &opts).unwrap();
    assert!(sols.solutions.is_empty());
    assert_eq!(sols.failure, Some(IkFailure::OrientationUnreachable));
    // A pose whose orientation is not reachable (tool turned about its own x axis).
    let q = [0.3, 0.6, -0.4, 0.2];
    let pose = robot.fk(&q).unwrap();
    let turned = pose * Isometry3::rotation(Vector3::new(0.4, 0.0, 0.0));
    let sols = s.solve(&robot, &IkTarget::Pose(turned), &IkOptions::default()).unwrap();
    assert!(sols.solutions.is_empty());
    assert_eq!(sols.failure, Some(IkFailure::OrientationUnreachable));
    // Every solution outside the paper's limits: reaching back needs q2 > 120°.
    let q = [0.0, deg(150.0), deg(-30.0), deg(-30.0)];
    let pose = robot.fk(&q).unwrap();
    let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
    assert!(contains(&sols, &q, 1e-9));
    assert!(matches!(sols.failure, Some(IkFailure::OutsideLimits { .. })), "{:?}", sols.failure);
}

/// A yaw + planar-3 arm with offsets everywhere the solver allows.
fn offset_arm(offsets: [f64; 4], flip: [bool; 4], lateral: f64) -> Robot {
    let mut joints = vec![
        Joint::revolute(0.15, -FRAC_PI_2, 0.5, offsets[0]),
        Joint::revolute(0.9, 0.0, lateral, offsets[1]),
        Joint::revolute(0.6, 0.0, 0.0, offsets[2]),
        Joint::revolute(0.3, 0.0, -0.02, offsets[3]),
    ];
    for (j, f) in joints.iter_mut().zip(flip) {
        j.flip = f;
    }
    let mut spec = RobotSpec::new("offset-varan", Convention::Dh, joints);
    spec.base = Isometry3::new(Vector3::new(0.1, 0.2, 0.3), Vector3::new(0.0, 0.1, 0.7));
    spec.tool = Isometry3::new(Vector3::new(0.05, 0.0, 0.02), Vector3::new(0.0, 0.0, 0.3));
    Robot::new(spec).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn varan4_round_trip(q in prop::array::uniform4(-PI..PI)) {
        let (robot, s) = varan();
        let pose = robot.fk(&q).unwrap();
        let p = Point3::from(pose.translation.vector);
        let opts = IkOptions { free_parameter: Some(s.last_link_angle(&q)), ..IkOptions::default() };
        let sols = s.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
        prop_assert!(sols.solutions.len() <= 4);
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q, 1e-7), "{:?} not in {:?}", q, sols.solutions);
        let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(sols.solutions.iter().all(|s| s.orientation_error < 1e-9));
        prop_assert!(singular || contains(&sols, &q, 1e-7));
        let opts = IkOptions { redundancy_step: deg(10.0), ..IkOptions::default() };
        let sols = s.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
        prop_assert!(!sols.solutions.is_empty());
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
    }

    #[test]
    fn offset_arms_round_trip(
        offsets in prop::array::uniform4(-PI..PI),
        flip in prop::array::uniform4(any::<bool>()),
        lateral in prop_oneof![Just(0.0), -0.3f64..0.3],
        q in prop::array::uniform4(-PI..PI),
    ) {
        let robot = offset_arm(offsets, flip, lateral);
        let s = YawPlanar3::from_robot(&robot).unwrap();
        let pose = robot.fk(&q).unwrap();
        let p = Point3::from(pose.translation.vector);
        let opts = IkOptions { free_parameter: Some(s.last_link_angle(&q)), ..IkOptions::default() };
        let sols = s.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q, 1e-7), "{:?} not in {:?}", q, sols.solutions);
        let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(singular || contains(&sols, &q, 1e-7));
    }
}
