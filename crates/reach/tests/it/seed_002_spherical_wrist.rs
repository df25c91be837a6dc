//! Seed 002 (Khudoliy et al.): geometric IK of PUMA-type arms with a spherical wrist, with the
//! paper's corrections (notes 002 §4.2–4.3, §6), all 8 branches and the lateral shoulder offset
//! of the classic PUMA 560.
//!
//! The paper prints no numbers; the test vectors are the notes' generated ones (§5) for the
//! reference table of §2.3 (the paper's structure, d2 = d3 = 0). Every solution is checked with
//! an independent forward kinematics (`common::dh_product`).

use crate::common;

use std::collections::HashSet;
use std::f64::consts::{FRAC_PI_2, PI};

use crate::common::{find_solution as find, pose_from_rows as pose, seed002_reference as reference};
use nalgebra::{Isometry3, Vector3};
use proptest::prelude::*;
use reach::Robot;
use reach::ik::spherical_wrist::SphericalWrist;
use reach::ik::{IkFailure, IkOptions, IkSolution, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::{Convention, Joint, RobotSpec, presets};

fn solve_with(robot: &Robot, target: &IkTarget, options: &IkOptions) -> IkSolutions {
    SphericalWrist::from_robot(robot).unwrap().solve(robot, target, options).unwrap()
}

fn solve(robot: &Robot, target: Isometry3<f64>) -> IkSolutions {
    solve_with(robot, &IkTarget::Pose(target), &IkOptions::default())
}

fn find_deg(all: &IkSolutions, q_deg: [f64; 6]) -> &IkSolution {
    let q: Vec<f64> = q_deg.iter().map(|v| v.to_radians()).collect();
    // The notes print 6 decimals of a degree.
    find(all, &q, 2e-6_f64.to_radians()).unwrap_or_else(|| {
        let got: Vec<Vec<f64>> = all.solutions.iter().map(|s| s.q.iter().map(|v| v.to_degrees()).collect()).collect();
        panic!("{q_deg:?} not among {got:#?}")
    })
}

fn rad(q_deg: [f64; 6]) -> Vec<f64> {
    q_deg.iter().map(|v| v.to_radians()).collect()
}

fn pose_gap(robot: &Robot, q: &[f64], target: &Isometry3<f64>) -> f64 {
    common::max_abs_diff(&common::dh_product(robot, q), &target.to_homogeneous())
}

fn assert_all_exact(robot: &Robot, all: &IkSolutions, target: &Isometry3<f64>) {
    for s in &all.solutions {
        assert!(pose_gap(robot, &s.q, target) < 1e-9, "{:?}: gap {}", s.q, pose_gap(robot, &s.q, target));
    }
}

/// Notes 002 §5 vector 1: the home pose; branch A is home, branch B the other elbow.
#[test]
fn vector_1_home() {
    let robot = reference();
    let t = pose([[1.0, 0.0, 0.0, 0.4521], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.78805]]);
    assert!(pose_gap(&robot, &[0.0; 6], &t) < 1e-12, "FK(0) is the printed T06");
    let all = solve(&robot, t);
    let a = find_deg(&all, [0.0; 6]);
    assert_eq!(a.branch.to_string(), "shoulder=front elbow=down wrist=noflip");
    let b = find_deg(&all, [0.0, 87.368707, -174.616727, 0.0, 87.248020, 0.0]);
    assert_eq!(b.branch.get("elbow"), Some("up"));
    assert_all_exact(&robot, &all, &t);
}

/// Notes 002 §5 vector 2 (generic): q = (30, 45, −60, 20, 50, −30)° is branch A (the
/// paper's "positive" pair, elbow down for α1 = +90°); branch B is
/// (30, 72.323728, −114.616727, 15.662480, 76.045627, −20.700259)°. With both shoulders and
/// both wrists there are 8 distinct solutions with 8 distinct labels.
#[test]
fn vector_2_generic_pose_has_8_solutions() {
    let robot = reference();
    #[rustfmt::skip]
    let t = pose([[0.869060689, -0.371145454, -0.327084959, 0.359790492],
                  [0.179066946,  0.852340019, -0.491377167, 0.190707567],
                  [0.461160002,  0.368466475,  0.807195088, 1.062566177]]);
    let q_in = rad([30.0, 45.0, -60.0, 20.0, 50.0, -30.0]);
    assert!(pose_gap(&robot, &q_in, &t) < 1e-8, "FK(q_in) is the printed T06");
    let all = solve(&robot, robot.fk(&q_in).unwrap());
    let a = find_deg(&all, [30.0, 45.0, -60.0, 20.0, 50.0, -30.0]);
    assert_eq!(a.branch.to_string(), "shoulder=front elbow=down wrist=noflip");
    let b = find_deg(&all, [30.0, 72.323728, -114.616727, 15.662480, 76.045627, -20.700259]);
    assert_eq!(b.branch.to_string(), "shoulder=front elbow=up wrist=noflip");
    // The flipped wrists: (θ4 + 180°, −θ5, θ6 + 180°).
    find_deg(&all, [30.0, 45.0, -60.0, -160.0, -50.0, 150.0]);
    assert_eq!(all.solutions.len(), 8);
    let labels: HashSet<String> = all.solutions.iter().map(|s| s.branch.to_string()).collect();
    assert_eq!(labels.len(), 8);
    for s in &all.solutions {
        assert!(s.singularities.is_empty());
        if s.branch.get("shoulder") == Some("back") {
            assert!((reach::angle::wrap(s.q[0] - 210f64.to_radians())).abs() < 1e-12);
        }
    }
    assert_all_exact(&robot, &all, &robot.fk(&q_in).unwrap());
}

/// Notes 002 §5 vector 3: q = (−120, 100, 150, −45, 80, 170)° is branch B; branch A is
/// (−120, −22.807379, 35.383273, −126.816694, 60.441199, −53.237132)°.
#[test]
fn vector_3_branch_b() {
    let robot = reference();
    #[rustfmt::skip]
    let t = pose([[0.667056928, -0.626986937,  0.402395868, -0.139282723],
                  [0.667956121,  0.264111493, -0.695758392, -0.319585730],
                  [0.329954050,  0.732893239,  0.594977163,  0.591947395]]);
    let q_in = [-120.0, 100.0, 150.0, -45.0, 80.0, 170.0];
    assert!(pose_gap(&robot, &rad(q_in), &t) < 1e-8);
    let all = solve(&robot, robot.fk(&rad(q_in)).unwrap());
    assert_eq!(find_deg(&all, q_in).branch.get("elbow"), Some("up"));
    let a = find_deg(&all, [-120.0, -22.807379, 35.383273, -126.816694, 60.441199, -53.237132]);
    assert_eq!(a.branch.get("elbow"), Some("down"));
    assert_eq!(all.solutions.len(), 8);
}

/// Notes 002 §5 vector 4: θ5 = 0 — θ4 is undetermined; it is kept from the seed (else 0) and
/// θ6 takes the rest (the literal formulas return round-off noise for θ4 there).
#[test]
fn vector_4_wrist_singularity_keeps_the_seeds_theta4() {
    let robot = reference();
    #[rustfmt::skip]
    let t = pose([[ 0.969846310, -0.173648178, 0.171010072, 0.471417978],
                  [ 0.171010072,  0.984807753, 0.030153690, 0.083123709],
                  [-0.173648178,  0.0,         0.984807753, 0.561210366]]);
    let q_in = rad([10.0, -30.0, 20.0, 0.0, 0.0, 0.0]);
    assert!(pose_gap(&robot, &q_in, &t) < 1e-8);
    let target = robot.fk(&q_in).unwrap();
    let all = solve(&robot, target);
    let a = find_deg(&all, [10.0, -30.0, 20.0, 0.0, 0.0, 0.0]);
    assert!(a.singularities.contains(&SingularityKind::Wrist));
    // Branch B has a regular wrist.
    let b = find_deg(&all, [10.0, 77.394320, 165.383273, 0.0, 107.222407, 0.0]);
    assert!(b.singularities.is_empty());
    // Only the front elbow-down arm has z3 ∥ a: 1 singular wrist + 3 arms × 2 wrists.
    assert_eq!(all.solutions.len(), 7);
    let singular: Vec<String> = all
        .solutions
        .iter()
        .filter(|s| s.singularities.contains(&SingularityKind::Wrist))
        .map(|s| s.branch.to_string())
        .collect();
    assert_eq!(singular, ["shoulder=front elbow=down wrist=noflip"]);
    assert_all_exact(&robot, &all, &target);

    let seeded = IkOptions { seed: Some(vec![0.0, 0.0, 0.0, 0.3, 0.0, 0.0]), ..IkOptions::default() };
    let all = solve_with(&robot, &IkTarget::Pose(target), &seeded);
    let a = find(&all, &[q_in[0], q_in[1], q_in[2], 0.3, 0.0, -0.3], 1e-9).expect("θ4 from the seed, θ6 = −θ4");
    assert!(a.singularities.contains(&SingularityKind::Wrist));

    // The notes' second singular check: only θ4 + θ6 = 28.648° is determined.
    let q_in = rad([17.189, 28.648, 22.918, 40.107, 0.0, -11.459]);
    let target = robot.fk(&q_in).unwrap();
    let all = solve(&robot, target);
    find_deg(&all, [17.189, 28.648, 22.918, 0.0, 0.0, 28.648]);
    let seeded = IkOptions { seed: Some(q_in.clone()), ..IkOptions::default() };
    assert!(find(&solve_with(&robot, &IkTarget::Pose(target), &seeded), &q_in, 1e-9).is_some());
}

/// Notes 002 §5 vector 5: the home pose moved 1 m along x is out of reach; the arccos argument
/// would exceed 1 (NaN in the literal formula).
#[test]
fn vector_5_unreachable() {
    let robot = reference();
    let t = pose([[1.0, 0.0, 0.0, 1.4521], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.78805]]);
    let all = solve(&robot, t);
    assert!(all.solutions.is_empty());
    // Independently: wrist centre (1.4521, 0, 0.7318), shoulder axis at height d1 = 0.3.
    let (u, v) = (1.4521_f64, 0.7318_f64 - 0.3);
    let reach = 0.4318 + 0.0203_f64.hypot(0.4318);
    match all.failure {
        Some(IkFailure::Unreachable { distance, reach: bound, .. }) => {
            assert!((distance - u.hypot(v)).abs() < 1e-12 && (bound - reach).abs() < 1e-12, "{distance} {bound}");
        }
        other => panic!("{other:?}"),
    }
}

/// Notes 002 §6 items 3–5: the printed argument orders of eqs. 23 and 31 and the printed
/// x6 = a6 (eq. 34) do not recover vector 2's wrist; the corrected ones do. Computed here from
/// the robot's own frames, independently of the solver.
#[test]
fn the_papers_printed_wrist_formulas_fail() {
    let robot = reference();
    let q = rad([30.0, 45.0, -60.0, 20.0, 50.0, -30.0]);
    let frames = common::dh_frames(&robot, &q);
    let col = |i: usize, c: usize| frames[i].fixed_view::<3, 1>(0, c).into_owned();
    let (x3, y3, z3) = (col(2, 0), col(2, 1), col(2, 2));
    let (x5, y5) = (col(4, 0), col(4, 1));
    let (n, a) = (col(5, 0), col(5, 2));
    let z4 = z3.cross(&a);
    let (sq_x, sq_y) = (z4.dot(&x3), -z4.dot(&y3));
    assert!((sq_x.atan2(sq_y).to_degrees() - 20.0).abs() < 1e-9, "corrected eq. 23");
    assert!((sq_y.atan2(sq_x).to_degrees() - 70.0).abs() < 1e-9, "printed eq. 23 gives 90° − θ4");
    assert!((n.dot(&y5).atan2(n.dot(&x5)).to_degrees() + 30.0).abs() < 1e-9, "corrected eqs. 31, 34");
    assert!(a.dot(&x5).abs() < 1e-12 && a.dot(&y5).abs() < 1e-12, "printed eq. 34: atan2 of round-off");
    assert!((a.dot(&z3).acos().to_degrees() - 50.0).abs() < 1e-9, "eq. 22");
}

/// The wrist centre on the base axis (d = 0): θ1 is undetermined and kept from the seed.
#[test]
fn shoulder_singularity_on_the_base_axis() {
    let robot = reference();
    // u = 0 in frame 1: θ2 = 90° − atan2(Y, X) with (X, Y) the wrist centre in frame 2.
    let (a2, a3, d4, t3) = (0.4318_f64, 0.0203_f64, 0.4318_f64, -0.8_f64);
    let (x, y) = (a2 + a3 * t3.cos() - d4 * t3.sin(), a3 * t3.sin() + d4 * t3.cos());
    let q = [0.6, FRAC_PI_2 - y.atan2(x), t3, 0.4, 0.5, 0.6];
    let target = robot.fk(&q).unwrap();
    let frames = common::dh_frames(&robot, &q);
    assert!(frames[3].fixed_view::<2, 1>(0, 3).norm() < 1e-12, "wrist centre on the base axis");
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 4, "one shoulder × 2 elbows × 2 wrists");
    for s in &all.solutions {
        assert!(s.singularities.contains(&SingularityKind::Shoulder));
        assert_eq!(s.q[0], 0.0);
    }
    assert_all_exact(&robot, &all, &target);
    let seeded = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    assert!(find(&solve_with(&robot, &IkTarget::Pose(target), &seeded), &q, 1e-9).is_some());
}

fn puma() -> Robot {
    presets::get("puma560").unwrap()
}

#[test]
fn detect_picks_this_solver_for_the_puma_and_not_for_the_ur5() {
    assert_eq!(SolverKind::detect(&puma()), SolverKind::SphericalWrist);
    let err = SphericalWrist::from_robot(&presets::get("ur5").unwrap()).unwrap_err().to_string();
    assert!(err.contains("d5") && err.contains("spherical wrist"), "{err}");
    assert_ne!(SolverKind::detect(&presets::get("ur5").unwrap()), SolverKind::SphericalWrist);
}

/// The `puma560` preset has the shoulder offset d3 = 0.15005 m that the paper's formulas
/// cannot handle (notes 002 §2.2 item 4); a generic pose has 8 distinct solutions.
#[test]
fn puma560_generic_pose_has_8_distinct_solutions() {
    let robot = puma();
    let q = [0.3, 0.5, -0.4, 0.7, 0.9, -0.2];
    let target = robot.fk(&q).unwrap();
    let all = solve(&robot, target);
    assert_eq!(all.solver, "spherical-wrist");
    assert_eq!(all.solutions.len(), 8);
    let labels: HashSet<String> = all.solutions.iter().map(|s| s.branch.to_string()).collect();
    assert_eq!(labels.len(), 8, "{labels:?}");
    for (i, a) in all.solutions.iter().enumerate() {
        for b in &all.solutions[i + 1..] {
            let gap = a.q.iter().zip(&b.q).map(|(x, y)| reach::angle::wrap(x - y).abs()).fold(0.0, f64::max);
            assert!(gap > 1e-3, "{:?} ~ {:?}", a.q, b.q);
        }
    }
    let s = find(&all, &q, 1e-9).expect("generating q");
    assert!(s.within_limits);
    // Left/right: the offset puts the arm plane on one side of the base axis.
    let sides: HashSet<&str> = all.solutions.iter().filter_map(|s| s.branch.get("shoulder")).collect();
    assert_eq!(sides, HashSet::from(["left", "right"]));
    assert_all_exact(&robot, &all, &target);
}

/// The wrist centre on the cylinder of radius d3 around the base axis: the two shoulder
/// solutions merge (shoulder singularity of the offset arm).
#[test]
fn puma560_shoulder_cylinder_is_singular() {
    let robot = puma();
    let (a2, a3, d4, t3) = (0.4318_f64, 0.0203_f64, 0.4318_f64, -0.8_f64);
    let (x, y) = (a2 + a3 * t3.cos() - d4 * t3.sin(), a3 * t3.sin() + d4 * t3.cos());
    let q = [0.6, FRAC_PI_2 - y.atan2(x), t3, 0.4, 0.5, 0.6];
    let frames = common::dh_frames(&robot, &q);
    assert!((frames[3].fixed_view::<2, 1>(0, 3).norm() - 0.15005).abs() < 1e-12, "on the cylinder");
    let target = robot.fk(&q).unwrap();
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 4);
    assert!(all.solutions.iter().all(|s| s.singularities.contains(&SingularityKind::Shoulder)));
    assert!(find(&all, &q, 1e-9).is_some());
    assert_all_exact(&robot, &all, &target);
    // Inside the cylinder: unreachable, reported against the offset.
    let inside = Isometry3::translation(0.05, 0.0, 0.9);
    match solve(&robot, inside).failure {
        Some(IkFailure::Unreachable { distance, reach, .. }) => {
            assert!((distance - 0.05).abs() < 1e-12 && (reach - 0.15005).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
}

/// Stretched arm (θ3 = −α): |cos φ| = 1, the elbow branches merge.
#[test]
fn puma560_stretched_elbow_is_singular() {
    let robot = puma();
    let alpha = 0.4318_f64.atan2(0.0203);
    let q = [0.2, 0.3, -alpha, 0.4, 0.5, 0.6];
    let target = robot.fk(&q).unwrap();
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 4, "2 shoulders × 2 wrists");
    assert!(all.solutions.iter().all(|s| s.singularities.contains(&SingularityKind::Elbow)));
    assert!(find(&all, &q, 1e-6).is_some());
    assert_all_exact(&robot, &all, &target);
}

#[test]
fn puma560_base_tool_and_position_targets() {
    let robot = puma()
        .with_base(Isometry3::new(Vector3::new(0.2, 0.1, 0.3), Vector3::new(0.0, 0.0, 0.7)))
        .unwrap()
        .with_tool(Isometry3::new(Vector3::new(0.01, 0.0, 0.12), Vector3::new(0.2, 0.0, 0.0)))
        .unwrap();
    let q = [-0.5, 0.8, -1.1, 1.2, -0.6, 2.0];
    let target = robot.fk(&q).unwrap();
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 8);
    assert!(find(&all, &q, 1e-9).is_some());
    assert_all_exact(&robot, &all, &target);

    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let p = target.translation.vector;
    let all = solve_with(&robot, &IkTarget::Position(p.into()), &options);
    assert!(find(&all, &q, 1e-9).is_some());
    for s in &all.solutions {
        assert!((common::dh_product(&robot, &s.q).fixed_view::<3, 1>(0, 3) - p).norm() < 1e-9);
    }
}

#[test]
fn puma560_limits_are_flagged() {
    let robot = puma();
    // The flags of a generic pose's 8 solutions agree with the preset's limits; some of the
    // 8 lie outside them (e.g. the flipped wrists need |wrist2| = 0.9 rad on the other side).
    let q = [0.3, 0.5, -0.4, 0.7, 0.9, -0.2];
    let all = solve(&robot, robot.fk(&q).unwrap());
    for s in &all.solutions {
        let inside = robot.joints().iter().zip(&s.q).all(|(j, v)| j.limits.contains(*v, 1e-9));
        assert_eq!(s.within_limits, inside, "{:?}", s.q);
    }
    assert!(all.solutions.iter().any(|s| !s.within_limits));
}

/// A random robot of the family: random α signs (notes 002 §4.3), lengths of both signs, a
/// lateral offset, a1, joint offsets and flipped joints.
fn random_robot(params: &[f64]) -> Robot {
    let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
    let quarter = |x: f64| sign(x) * FRAC_PI_2;
    let p = |i: usize| params[i];
    let mut joints = vec![
        Joint::revolute(0.3 * p(0), quarter(p(1)), 0.5 * p(2), p(3)),
        Joint::revolute(0.6 * sign(p(4)) * (0.5 + p(4).abs()), 0.0, 0.2 * p(5), p(6)),
        Joint::revolute(0.2 * p(7), quarter(p(8)), 0.2 * p(9), p(10)),
        Joint::revolute(0.0, quarter(p(11)), 0.5 * sign(p(12)) * (0.4 + p(12).abs()), p(13)),
        Joint::revolute(0.0, quarter(p(14)), 0.0, p(15)),
        Joint::revolute(0.0, 0.0, 0.2 * p(16), p(17)),
    ];
    for (j, &f) in joints.iter_mut().zip(&params[18..24]) {
        j.flip = f < 0.0;
    }
    Robot::new(RobotSpec::new("random-spherical-wrist", Convention::Dh, joints)).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// FK∘IK round trip on the `puma560` preset, full circle per joint.
    #[test]
    fn puma560_round_trip(q in proptest::collection::vec(-PI..PI, 6)) {
        let robot = puma();
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        for s in &all.solutions {
            prop_assert!(pose_gap(&robot, &s.q, &target) < 1e-9, "{:?}", s.q);
        }
        if q[4].sin().abs() > 1e-6 {
            prop_assert!(find(&all, &q, 1e-7).is_some(), "q = {:?} not among {:#?}", q, all.solutions);
        }
    }

    /// The same on the paper's reference table.
    #[test]
    fn reference_round_trip(q in proptest::collection::vec(-PI..PI, 6)) {
        let robot = reference();
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        for s in &all.solutions {
            prop_assert!(pose_gap(&robot, &s.q, &target) < 1e-9, "{:?}", s.q);
        }
        if q[4].sin().abs() > 1e-6 {
            prop_assert!(find(&all, &q, 1e-7).is_some(), "q = {:?} not among {:#?}", q, all.solutions);
        }
    }

    /// Every α-sign convention, offsets, flips and lengths of either sign.
    #[test]
    fn any_convention_round_trip(
        params in proptest::collection::vec(-1.0..1.0f64, 24),
        q in proptest::collection::vec(-PI..PI, 6),
    ) {
        let robot = random_robot(&params);
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        for s in &all.solutions {
            prop_assert!(pose_gap(&robot, &s.q, &target) < 1e-9, "{:?}", s.q);
        }
        let theta5 = if params[22] < 0.0 { -q[4] } else { q[4] } + robot.joints()[4].dh().unwrap().theta_offset;
        if theta5.sin().abs() > 1e-6 {
            prop_assert!(find(&all, &q, 1e-7).is_some(), "q = {:?} not among {:#?}", q, all.solutions);
        }
    }
}

/// A deterministic sweep for the report: random q on `puma560` and the reference table.
#[test]
fn round_trip_sweep() {
    for robot in [puma(), reference()] {
        let mut rng = common::Rng::new(7);
        let (mut found, mut eight, mut max_gap, n) = (0, 0, 0.0_f64, 5000);
        for _ in 0..n {
            let q: Vec<f64> = (0..6).map(|_| rng.uniform(-PI, PI)).collect();
            let target = robot.fk(&q).unwrap();
            let all = solve(&robot, target);
            found += usize::from(find(&all, &q, 1e-7).is_some());
            eight += usize::from(all.solutions.len() == 8);
            for s in &all.solutions {
                max_gap = max_gap.max(pose_gap(&robot, &s.q, &target));
            }
        }
        println!(
            "{}: {found}/{n} generating q found, {eight}/{n} with 8 solutions, max |ΔT| = {max_gap:.2e}",
            robot.name()
        );
        assert_eq!(found, n);
        assert_eq!(eight, n);
        assert!(max_gap < 1e-12);
    }
}

/// Targets approaching each singularity: every solution still reproduces the pose, the
/// generating q is found while the configuration is not exactly singular, and nothing is NaN.
/// Below `IK_PARALLEL_SINE` (1e-9) the wrist is treated as exactly singular, which costs up
/// to ~2·|sin θ5| of orientation: hence the 3e-9 bound.
#[test]
fn near_singular_targets_stay_exact() {
    let robot = puma();
    let alpha = 0.4318_f64.atan2(0.0203);
    for eps in [1e-3, 1e-6, 1e-8, 1e-9, 1e-10, 1e-12, 1e-15, 0.0] {
        for q in [
            [0.2, 0.3, -0.4, 0.5, eps, 0.6],              // wrist, θ5 → 0
            [0.2, 0.3, -0.4, 0.5, PI - eps, 0.6],         // wrist, θ5 → π
            [0.2, 0.3, -alpha + eps, 0.5, 0.7, 0.6],      // elbow stretched
            [0.2, 0.3, -alpha + PI - eps, 0.5, 0.7, 0.6], // elbow folded
        ] {
            let target = robot.fk(&q).unwrap();
            let all = solve(&robot, target);
            assert!(all.solutions.len() >= 4, "eps {eps}, q {q:?}: {}", all.solutions.len());
            for s in &all.solutions {
                assert!(s.q.iter().all(|v| v.is_finite()));
                assert!(pose_gap(&robot, &s.q, &target) < 3e-9, "eps {eps}, {:?}", s.q);
            }
            if eps >= 1e-8 {
                let tol = if eps > 1e-6 { 1e-7 } else { 1e-4 };
                assert!(find(&all, &q, tol).is_some(), "eps {eps}: {q:?} not found");
            }
        }
    }
}
