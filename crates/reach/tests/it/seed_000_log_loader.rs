//! Seed 000 appendix P2011 (notes 000 §3.5, §6.1 D9–D10): the log loader (`log-loader`),
//! a base yaw plus two links in a vertical plane.

use std::f64::consts::{FRAC_PI_2, PI};

use approx::assert_relative_eq;
use nalgebra::{Isometry3, Point3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use reach::angle::{deg, wrap};
use reach::ik::yaw_two_link::{YawTwoLink, base_angle, shortest_base_rotation};
use reach::ik::{IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::planar_angles::LogLoaderAngles;
use reach::model::{Convention, Joint, Robot, RobotSpec, presets};

fn loader() -> (Robot, YawTwoLink) {
    let robot = presets::get("log-loader").unwrap();
    let s = YawTwoLink::from_robot(&robot).unwrap();
    (robot, s)
}

fn solve(target: IkTarget, options: &IkOptions) -> IkSolutions {
    let (robot, s) = loader();
    s.solve(&robot, &target, options).unwrap()
}

fn branch<'a>(sols: &'a IkSolutions, base: &str, elbow: &str) -> &'a reach::ik::IkSolution {
    sols.solutions
        .iter()
        .find(|s| s.branch.get("base") == Some(base) && s.branch.get("elbow") == Some(elbow))
        .unwrap_or_else(|| panic!("no {base}/{elbow} in {:?}", sols.solutions))
}

fn assert_q_deg(q: &[f64], expected: [f64; 3]) {
    for (a, e) in q.iter().zip(expected) {
        assert!(
            wrap(a - deg(e)).abs() < 1e-9,
            "{:?} vs {expected:?} (deg)",
            q.iter().map(|v| v.to_degrees()).collect::<Vec<_>>()
        );
    }
}

#[test]
fn detected_for_the_preset() {
    assert_eq!(SolverKind::detect(&presets::get("log-loader").unwrap()), SolverKind::YawTwoLink);
}

// ---------------------------------------------------------------------------------------------
// Quadrant table (P2011 Table 1) and shortest rotation.
// ---------------------------------------------------------------------------------------------

#[test]
fn quadrant_table_all_cells() {
    // Every cell of P2011 Table 1 with the D9 correction, range (−180°, 180°].
    let cells = [
        ((-1.0, -1.0), Some(-135.0)),
        ((0.0, -2.0), Some(-90.0)),
        ((1.0, -1.0), Some(-45.0)),
        ((-3.0, 0.0), Some(180.0)),
        ((0.0, 0.0), None),
        ((3.0, 0.0), Some(0.0)),
        ((-1.0, 1.0), Some(135.0)),
        ((0.0, 2.0), Some(90.0)),
        ((1.0, 1.0), Some(45.0)),
        // D9 examples: the printed cell atan(y/|x|) + 90° gives 153.434949° and 116.565051°.
        ((-1.0, 2.0), Some(116.565051)),
        ((-2.0, 1.0), Some(153.434949)),
    ];
    for ((x, y), expected) in cells {
        match (base_angle(x, y), expected) {
            (None, None) => {}
            (Some(a), Some(e)) => assert_relative_eq!(a.to_degrees(), e, epsilon = 1e-6),
            (a, e) => panic!("({x}, {y}): {a:?} vs {e:?}"),
        }
    }
    // The printed cell is wrong except at |x| = y.
    let printed = |x: f64, y: f64| ((y / x.abs()).atan() + FRAC_PI_2).to_degrees();
    assert_relative_eq!(printed(-1.0, 2.0), 153.434949, epsilon = 1e-6);
    assert_relative_eq!(printed(-2.0, 1.0), 116.565051, epsilon = 1e-6);
    assert_relative_eq!(printed(-1.0, 1.0), base_angle(-1.0, 1.0).unwrap().to_degrees(), epsilon = 1e-12);
}

#[test]
fn shortest_rotation_with_the_sign_bug_fixed() {
    let d = |a1: f64, a2: f64| shortest_base_rotation(deg(a1), deg(a2)).to_degrees();
    // D10: the paper gives −20° and −150° here.
    assert_relative_eq!(d(170.0, -170.0), 20.0, epsilon = 1e-9);
    assert_relative_eq!(d(120.0, -90.0), 150.0, epsilon = 1e-9);
    // Cases the paper gets right.
    assert_relative_eq!(d(-170.0, 170.0), -20.0, epsilon = 1e-9);
    assert_relative_eq!(d(10.0, 50.0), 40.0, epsilon = 1e-9);
    assert_relative_eq!(d(50.0, 10.0), -40.0, epsilon = 1e-9);
    assert_relative_eq!(d(-90.0, 90.0), 180.0, epsilon = 1e-9);
}

// ---------------------------------------------------------------------------------------------
// P2011 eqs. (2)–(4) and all branches.
// ---------------------------------------------------------------------------------------------

#[test]
fn p2011_equations_3_and_4() {
    // Notes 000 §6.1 "verified correct", A = B = 1: (1, 0.5, 0.8) → β = 86.847141°,
    // γ = 82.161732°; (1.2, 0, 0.3) → β = 76.408377°, γ = 65.832055°. They are the front,
    // elbow-up branch (q3 = β − 180° ≤ 0).
    for ([x, y, z], beta, gamma) in [([1.0, 0.5, 0.8], 86.847141, 82.161732), ([1.2, 0.0, 0.3], 76.408377, 65.832055)] {
        let sols = solve(IkTarget::Position(Point3::new(x, y, z)), &IkOptions::default());
        let s = branch(&sols, "front", "up");
        let p = LogLoaderAngles::from_joints([s.q[0], s.q[1], s.q[2]]);
        assert_relative_eq!(p.alpha, base_angle(x, y).unwrap(), epsilon = 1e-12);
        assert_relative_eq!(p.beta.to_degrees(), beta, epsilon = 1e-6);
        assert_relative_eq!(p.gamma.to_degrees(), gamma, epsilon = 1e-6);
        assert!(s.within_limits && s.singularities.is_empty());
        assert_eq!(sols.solutions.len(), 4);
    }
}

#[test]
fn four_branches_of_a_simple_target() {
    // Target (1, 0, 1): front up (0, 90, −90), front down (0, 0, 90); reaching back over the
    // top: base 180°, up (180, 90, 90), down (180, 180, −90). All within the preset's limits.
    let sols = solve(IkTarget::Position(Point3::new(1.0, 0.0, 1.0)), &IkOptions::default());
    assert_eq!(sols.solutions.len(), 4);
    assert_q_deg(&branch(&sols, "front", "up").q, [0.0, 90.0, -90.0]);
    assert_q_deg(&branch(&sols, "front", "down").q, [0.0, 0.0, 90.0]);
    assert_q_deg(&branch(&sols, "back", "up").q, [180.0, 90.0, 90.0]);
    assert_q_deg(&branch(&sols, "back", "down").q, [180.0, 180.0, -90.0]);
    assert!(sols.solutions.iter().all(|s| s.within_limits));
    // The back branches are outside the limits when the shoulder cannot pass the vertical.
    // (1, 0.5, 1.2): elevations 81.9° (up) and 12.1° (down) in front, 98.1° and 167.9° behind.
    let target = IkTarget::Position(Point3::new(1.0, 0.5, 1.2));
    let (robot, s) = loader();
    let mut spec = robot.spec().clone();
    spec.joints[1].limits.upper = FRAC_PI_2;
    let limited = Robot::new(spec).unwrap();
    let sols = s.solve(&limited, &target, &IkOptions::default()).unwrap();
    assert_eq!(sols.feasible().count(), 2);
    assert!(sols.feasible().all(|s| s.branch.get("base") == Some("front")));
}

#[test]
fn singular_targets() {
    // Fully stretched: one elbow per base branch, flagged.
    let (robot, _) = loader();
    let q = [0.3, 0.5, 0.0];
    let p = Point3::from(robot.fk(&q).unwrap().translation.vector);
    let sols = solve(IkTarget::Position(p), &IkOptions::default());
    assert_eq!(sols.solutions.len(), 2);
    assert!(sols.solutions.iter().all(|s| s.singularities == vec![SingularityKind::Elbow]));
    assert_q_deg(&branch(&sols, "front", "stretched").q, [0.3f64.to_degrees(), 0.5f64.to_degrees(), 0.0]);
    assert_q_deg(&branch(&sols, "back", "stretched").q, [(0.3 - PI).to_degrees(), (PI - 0.5).to_degrees(), 0.0]);
    // On the base axis: the base angle is free; it is the seed's, and both elbows remain.
    let opts = IkOptions { seed: Some(vec![0.7, 1.0, -1.0]), ..IkOptions::default() };
    let sols = solve(IkTarget::Position(Point3::new(0.0, 0.0, 1.5)), &opts);
    assert_eq!(sols.solutions.len(), 2);
    for s in &sols.solutions {
        assert!(s.singularities.contains(&SingularityKind::Shoulder));
        assert_relative_eq!(s.q[0], 0.7, epsilon = 1e-15);
    }
    // Without a seed the base angle is 0.
    let sols = solve(IkTarget::Position(Point3::new(0.0, 0.0, 1.5)), &IkOptions::default());
    assert!(sols.solutions.iter().all(|s| s.q[0] == 0.0));
    // On the axis with a pose target, the orientation fixes the base angle.
    let q = [0.9, 1.2, PI - 2.4];
    let pose = robot.fk(&q).unwrap();
    assert!(pose.translation.vector.xy().norm() < 1e-12);
    let sols = solve(IkTarget::Pose(pose), &IkOptions::default());
    assert_eq!(sols.solutions.len(), 1);
    assert!(sols.solutions[0].singularities.contains(&SingularityKind::Shoulder));
    assert!(sols.solutions[0].q.iter().zip(&q).all(|(a, b)| wrap(a - b).abs() < 1e-9));
}

#[test]
fn unreachable_and_orientation() {
    let sols = solve(IkTarget::Position(Point3::new(3.0, 0.0, 0.0)), &IkOptions::default());
    assert!(sols.solutions.is_empty());
    assert_eq!(
        sols.failure,
        Some(IkFailure::Unreachable { distance: 3.0, reach: 2.0, point: "the target", from: "joint 2" })
    );
    // A pose target: only the branch with the target's orientation survives.
    let (robot, _) = loader();
    let q = [0.4, 1.0, -1.2];
    let pose = robot.fk(&q).unwrap();
    let sols = solve(IkTarget::Pose(pose), &IkOptions::default());
    assert_eq!(sols.solutions.len(), 1);
    assert!(sols.solutions[0].q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9));
    // The same position with an orientation the arm cannot take.
    let turned = Isometry3::from_parts(
        pose.translation,
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3) * pose.rotation,
    );
    let sols = solve(IkTarget::Pose(turned), &IkOptions::default());
    assert!(sols.solutions.is_empty());
    assert_eq!(sols.failure, Some(IkFailure::OrientationUnreachable));
}

// ---------------------------------------------------------------------------------------------
// Round trips.
// ---------------------------------------------------------------------------------------------

/// A yaw + two-link arm with every offset the solver allows: shoulder height and radial offset,
/// sideways offset of the arm plane, angle offsets, flipped joints, a tool with an offset.
fn offset_arm(offsets: [f64; 3], flip: [bool; 3], lateral: f64) -> Robot {
    let mut joints = vec![
        Joint::revolute(0.2, FRAC_PI_2, 0.4, offsets[0]),
        Joint::revolute(1.0, 0.0, lateral, offsets[1]),
        Joint::revolute(0.7, 0.0, -0.05, offsets[2]),
    ];
    for (j, f) in joints.iter_mut().zip(flip) {
        j.flip = f;
    }
    let mut spec = RobotSpec::new("offset-loader", Convention::Dh, joints);
    spec.base = Isometry3::new(Vector3::new(0.3, -0.2, 0.1), Vector3::new(0.1, 0.2, -0.3));
    spec.tool = Isometry3::new(Vector3::new(0.1, 0.05, 0.0), Vector3::new(0.3, 0.0, 0.2));
    Robot::new(spec).unwrap()
}

fn contains(sols: &IkSolutions, q: &[f64]) -> bool {
    sols.solutions.iter().any(|s| s.q.iter().zip(q).all(|(a, b)| wrap(a - b).abs() < 1e-7))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn log_loader_round_trip(q in prop::array::uniform3(-PI..PI)) {
        let (robot, s) = loader();
        let pose = robot.fk(&q).unwrap();
        let p = Point3::from(pose.translation.vector);
        let sols = s.solve(&robot, &IkTarget::Position(p), &IkOptions::default()).unwrap();
        prop_assert!(!sols.solutions.is_empty() && sols.solutions.len() <= 4);
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q), "{:?} not in {:?}", q, sols.solutions);
        let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(contains(&sols, &q) || singular);
    }

    #[test]
    fn offset_arms_round_trip(
        offsets in prop::array::uniform3(-PI..PI),
        flip in prop::array::uniform3(any::<bool>()),
        lateral in prop_oneof![Just(0.0), -0.3f64..0.3],
        q in prop::array::uniform3(-PI..PI),
    ) {
        let robot = offset_arm(offsets, flip, lateral);
        let s = YawTwoLink::from_robot(&robot).unwrap();
        let pose = robot.fk(&q).unwrap();
        let p = Point3::from(pose.translation.vector);
        let sols = s.solve(&robot, &IkTarget::Position(p), &IkOptions::default()).unwrap();
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q), "{:?} not in {:?}", q, sols.solutions);
        let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(singular || contains(&sols, &q));
        prop_assert!(sols.solutions.iter().all(|s| s.orientation_error < 1e-9));
    }
}

// ---------------------------------------------------------------------------------------------
// Regressions and other descriptions.
// ---------------------------------------------------------------------------------------------

#[test]
fn near_singular_pose_targets_are_solved_exactly() {
    // Nearly stretched (q3 = −6.2e-5 rad): a clamped acos argument would return q3 = 0, whose
    // orientation misses the pose by 6.2e-5 rad; the solution must be the exact one.
    let (robot, s) = loader();
    for q in [[0.6991583606481488, -0.1081137461706026, -6.198654252122826e-5], [2.2, 0.4, 3e-7]] {
        let sols = s.solve(&robot, &IkTarget::Pose(robot.fk(&q).unwrap()), &IkOptions::default()).unwrap();
        assert!(contains(&sols, &q), "{q:?}: {:?}", sols.solutions);
    }
    // Folded (q3 = −(π − 1e-7)) with link A horizontal: the tool is 7e-10 m from the base axis
    // and 1e-7 m from the shoulder; the base angle comes from the orientation.
    let q = [-2.298641555424143, -0.007402953921501868, -(PI - 1e-7)];
    let sols = s.solve(&robot, &IkTarget::Pose(robot.fk(&q).unwrap()), &IkOptions::default()).unwrap();
    assert!(contains(&sols, &q), "{:?}", sols.solutions);
    assert!(sols.solutions.iter().all(|s| s.singularities.contains(&SingularityKind::Shoulder)));
    // Exactly folded onto the shoulder: link A's angle comes from the orientation too.
    let q = [0.5, 1.3, PI];
    let sols = s.solve(&robot, &IkTarget::Pose(robot.fk(&q).unwrap()), &IkOptions::default()).unwrap();
    assert!(contains(&sols, &q), "{:?}", sols.solutions);
}

const URDF_LOADER: &str = r#"<robot name="urdf-loader">
  <link name="base"/><link name="turret"/><link name="boom"/><link name="stick"/><link name="tip"/>
  <joint name="yaw" type="revolute"><parent link="base"/><child link="turret"/>
    <origin xyz="0 0 0.5"/><axis xyz="0 0 1"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="shoulder" type="revolute"><parent link="turret"/><child link="boom"/>
    <origin xyz="0.1 0 0.2" rpy="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="boom"/><child link="stick"/>
    <origin xyz="1.2 0 0"/><axis xyz="0 AXIS 0"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>
  <joint name="tool" type="fixed"><parent link="stick"/><child link="tip"/><origin xyz="0.8 0 0.05"/></joint>
</robot>"#;

#[test]
fn urdf_description_is_recognised() {
    let robot = Robot::from_urdf_str(&URDF_LOADER.replace("AXIS", "1"), &Default::default()).unwrap();
    assert_eq!(SolverKind::detect(&robot), SolverKind::YawTwoLink);
    let s = YawTwoLink::from_robot(&robot).unwrap();
    assert_relative_eq!(s.lengths()[0], 1.2, epsilon = 1e-12);
    for q in [[0.3, -0.5, 1.0], [-2.0, 0.2, -0.7], [1.0, -2.5, 2.0]] {
        let pose = robot.fk(&q).unwrap();
        let sols =
            s.solve(&robot, &IkTarget::Position(Point3::from(pose.translation.vector)), &IkOptions::default()).unwrap();
        assert!(contains(&sols, &q), "{q:?}");
        let sols = s.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        assert!(contains(&sols, &q), "{q:?}");
    }
    // An elbow axis pointing the other way is not this solver's structure.
    let robot = Robot::from_urdf_str(&URDF_LOADER.replace("AXIS", "-1"), &Default::default()).unwrap();
    let err = YawTwoLink::from_robot(&robot).unwrap_err();
    assert!(err.to_string().contains("antiparallel"), "{err}");
}
