//! Seed 001 (Vodolaga 2021): closed-form IK of the `spbu6` arm — two links on a ball-joint
//! shoulder with a spherical wrist (notes 001 §3.3–3.4, §4.2, §5.2, §6).
//!
//! Every solution is checked with an independent forward kinematics (`common::dh_product`,
//! a plain product of the DH matrices), not only by the solver's own FK check.

use crate::common;

use std::f64::consts::{FRAC_PI_2, FRAC_PI_4, PI, TAU};

use crate::common::{SPBU6_T0 as T0, SPBU6_T1 as T1, find_solution as find, pose_from_rows as pose};
use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use reach::Robot;
use reach::ik::two_link_wrist::TwoLinkWrist;
use reach::ik::{IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::presets;

fn spbu6() -> Robot {
    presets::get("spbu6").unwrap()
}

fn solve_with(robot: &Robot, target: &IkTarget, options: &IkOptions) -> IkSolutions {
    TwoLinkWrist::from_robot(robot).unwrap().solve(robot, target, options).unwrap()
}

fn solve(robot: &Robot, target: Isometry3<f64>) -> IkSolutions {
    solve_with(robot, &IkTarget::Pose(target), &IkOptions::default())
}

/// Largest entry of |T_independent(q) − T_target|.
fn pose_gap(robot: &Robot, q: &[f64], target: &Isometry3<f64>) -> f64 {
    common::max_abs_diff(&common::dh_product(robot, q), &target.to_homogeneous())
}

#[test]
fn detect_picks_this_solver_for_spbu6() {
    assert_eq!(SolverKind::detect(&spbu6()), SolverKind::TwoLinkWrist);
    let all = solve(&spbu6(), pose(T0));
    assert_eq!(all.solver, "two-link-wrist");
}

/// Notes 001 §5.2: IK(T0) = 0, through the r̃33 = 1 singular branch (the home pose is a wrist
/// singularity). The wrist is singular only on the two arm branches whose link 2 lies along
/// the approach vector (elbow up, front and back); the two elbow-down branches have a regular
/// wrist with two solutions each: 2 + 4 = 6 solutions.
#[test]
fn ik_of_t0_is_home_through_the_singular_branch() {
    let robot = spbu6();
    let all = solve(&robot, pose(T0));
    let home = find(&all, &[0.0; 6], 1e-12).expect("q = 0 among the solutions");
    assert!(home.singularities.contains(&SingularityKind::Wrist));
    assert!(home.within_limits);
    assert_eq!(home.branch.to_string(), "shoulder=front elbow=up wrist=noflip");
    assert_eq!(all.solutions.len(), 6, "{:#?}", all.solutions);
    for s in &all.solutions {
        let singular = s.singularities.contains(&SingularityKind::Wrist);
        assert_eq!(singular, s.branch.get("elbow") == Some("up"), "{:?}", s.branch);
        assert!(pose_gap(&robot, &s.q, &pose(T0)) < 1e-12);
    }
    // The back-shoulder twin of home: (180°, 0, 180°, 180°, 0, 0).
    assert!(find(&all, &[PI, 0.0, PI, PI, 0.0, 0.0], 1e-12).is_some());
}

/// Notes 001 §5.2: IK(T1) = (90°, 0, 0, 90°, 0, 0) with the text's multiplication order
/// (singular branch r̃33 = 1, q6 = 0 as the thesis sets it).
#[test]
fn ik_of_t1_is_90_0_0_90_0_0() {
    let robot = spbu6();
    let all = solve(&robot, pose(T1));
    let s = find(&all, &[FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, 0.0, 0.0], 1e-12).expect("(90°, 0, 0, 90°, 0, 0)");
    assert!(s.within_limits && s.singularities.contains(&SingularityKind::Wrist));
    assert!(pose_gap(&robot, &s.q, &pose(T1)) < 1e-12);
    assert!(all.failure.is_none());
}

/// Notes 001 §6.1 item 1: the appendix code multiplies `inv(A1)·inv(A2)·inv(A3)·T`; the text's
/// `inv(A3)·inv(A2)·inv(A1)·T` is right. Computed here with the thesis's printed matrices
/// A1…A3 (notes §2.3) at q1 = 90°, q2 = q3 = 0: the code order gives R̃ = Rx(90°), hence
/// IK = (90°, 0, 0, −90°, 90°, 90°), whose FK is [[0,0,−1,0],[0,1,0,3],[1,0,0,5]] ≠ T1; the
/// text order gives R̃ = Rz(90°), i.e. the solver's answer.
#[test]
fn the_appendix_codes_inverse_order_is_wrong_and_not_used() {
    let (l1, l2) = (5.0, 3.0);
    let (c1, s1, c2, s2, c3, s3) = (0.0, 1.0, 1.0, 0.0, 1.0, 0.0); // q1 = 90°, q2 = q3 = 0
    #[rustfmt::skip]
    let a1 = Matrix4::new(c1, 0.0, -s1, 0.0,  s1, 0.0, c1, 0.0,  0.0, -1.0, 0.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    #[rustfmt::skip]
    let a2 = Matrix4::new(s2, c2, 0.0, l1 * s2,  -c2, s2, 0.0, -l1 * c2,  0.0, 0.0, 1.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    #[rustfmt::skip]
    let a3 = Matrix4::new(c3, 0.0, -s3, -l2 * s3,  s3, 0.0, c3, l2 * c3,  0.0, -1.0, 0.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    let t1 = pose(T1).to_homogeneous();
    let inv = |m: Matrix4<f64>| m.try_inverse().unwrap();
    let code = inv(a1) * inv(a2) * inv(a3) * t1;
    let text = inv(a3) * inv(a2) * inv(a1) * t1;
    let rot = |m: Matrix4<f64>| m.fixed_view::<3, 3>(0, 0).into_owned();
    let rx90 = Rotation3::from_axis_angle(&Vector3::x_axis(), FRAC_PI_2);
    let rz90 = Rotation3::from_axis_angle(&Vector3::z_axis(), FRAC_PI_2);
    assert!(common::max_abs_diff(&rot(code), rx90.matrix()) < 1e-12);
    assert!(common::max_abs_diff(&rot(text), rz90.matrix()) < 1e-12);
    assert!(text.fixed_view::<3, 1>(0, 3).norm() < 1e-12, "the wrist centre is the tool point");

    let robot = spbu6();
    let code_answer = [FRAC_PI_2, 0.0, 0.0, -FRAC_PI_2, FRAC_PI_2, FRAC_PI_2];
    #[rustfmt::skip]
    let printed = Matrix4::new(0.0, 0.0, -1.0, 0.0,  0.0, 1.0, 0.0, 3.0,  1.0, 0.0, 0.0, 5.0,  0.0, 0.0, 0.0, 1.0);
    assert!(common::max_abs_diff(&common::dh_product(&robot, &code_answer), &printed) < 1e-12);
    assert!(pose_gap(&robot, &code_answer, &pose(T1)) > 0.5);
    assert!(find(&solve(&robot, pose(T1)), &code_answer, 1e-6).is_none());
}

/// Notes 001 §5.2: the mid-point pose T(5) of the tool-space motion has both wrist branches,
/// (45°, −10.110°, 8.627°, ±180°, 20.954°, −135°) — the thesis's (+) branch, outside the
/// q4 limit — and (45°, −10.110°, 8.627°, 0°, −20.954°, 45°), within limits.
#[test]
fn ik_of_the_midpoint_pose_has_both_wrist_branches() {
    let robot = spbu6();
    let (a, b) = (2.0 / 3.0, 1.0 / 3.0);
    let t5 = pose([[a, b, a, 1.5], [-b, -a, a, 1.5], [a, -a, -b, 5.0]]);
    let all = solve(&robot, t5);
    let plus = find(&all, &[FRAC_PI_4, -0.176449, 0.150568, PI, 0.365718, -3.0 * FRAC_PI_4], 1e-6).expect("(+) branch");
    let minus = find(&all, &[FRAC_PI_4, -0.176449, 0.150568, 0.0, -0.365718, FRAC_PI_4], 1e-6).expect("(−) branch");
    assert_eq!(plus.branch.get("wrist"), Some("noflip"));
    assert_eq!(minus.branch.get("wrist"), Some("flip"));
    assert!(!plus.within_limits && plus.violations.iter().any(|v| v.joint == 4));
    assert!(minus.within_limits);
    assert_eq!(all.solutions.len(), 8);
    for s in &all.solutions {
        assert!(pose_gap(&robot, &s.q, &t5) < 1e-12, "{:?}", s.q);
    }
}

/// Notes 001 §5.2 "extra FK/IK vectors": the thesis's IK (s5 > 0 branch) of
/// FK(0.3, −0.4, 0.5, 0.7, −0.2, 1.1) is (0.3, −0.4, 0.5, 0.7 − π, 0.2, 1.1 − π); the
/// generating q is the flipped wrist. FK(1.0, 0.5, −0.3, 0.4, 0.8, −0.6) comes back exactly.
#[test]
fn reproduces_the_notes_extra_vectors() {
    let robot = spbu6();
    let q = [0.3, -0.4, 0.5, 0.7, -0.2, 1.1];
    let all = solve(&robot, robot.fk(&q).unwrap());
    let thesis = find(&all, &[0.3, -0.4, 0.5, -2.441593, 0.2, -2.041593], 1e-6).expect("thesis branch");
    assert_eq!(thesis.branch.get("wrist"), Some("noflip"));
    assert_eq!(find(&all, &q, 1e-9).expect("generating q").branch.get("wrist"), Some("flip"));

    let q = [1.0, 0.5, -0.3, 0.4, 0.8, -0.6];
    let all = solve(&robot, robot.fk(&q).unwrap());
    let s = find(&all, &q, 1e-12).expect("exact round trip");
    assert_eq!(s.branch.get("shoulder"), Some("front"));
    assert_eq!(s.branch.get("wrist"), Some("noflip"));
}

/// The thesis's own closed form (notes 001 §4.2, text order, upper-sign wrist branch) computed
/// here literally: its answer is the solution labelled `shoulder=front elbow=up wrist=noflip`.
#[test]
fn thesis_branch_is_front_up_noflip() {
    let robot = spbu6();
    let (l1, l2) = (5.0_f64, 3.0_f64);
    let mut rng = common::Rng::new(1);
    for _ in 0..200 {
        let q: Vec<f64> = (0..6).map(|_| rng.uniform(-1.5, 1.5)).collect();
        let t = robot.fk_matrix(&q).unwrap();
        let p = t.translation.vector;
        let r2 = p.norm_squared();
        let rho = p.x.hypot(p.y);
        let q1 = p.y.atan2(p.x);
        let q2 = rho.atan2(p.z) - ((l1 * l1 + r2 - l2 * l2) / (2.0 * l1 * r2.sqrt())).acos();
        let q3 = ((l1 * l1 + l2 * l2 - r2) / (2.0 * l1 * l2)).asin();
        // A3⁻¹·A2⁻¹·A1⁻¹·T with the printed link matrices, via the DH rewrite (notes §2.4).
        let (s1, c1) = q1.sin_cos();
        let (s2, c2) = q2.sin_cos();
        let (s3, c3) = q3.sin_cos();
        #[rustfmt::skip]
        let a1 = Matrix3::new(c1, 0.0, -s1,  s1, 0.0, c1,  0.0, -1.0, 0.0);
        #[rustfmt::skip]
        let a2 = Matrix3::new(s2, c2, 0.0,  -c2, s2, 0.0,  0.0, 0.0, 1.0);
        #[rustfmt::skip]
        let a3 = Matrix3::new(c3, 0.0, -s3,  s3, 0.0, c3,  0.0, -1.0, 0.0);
        let m = (a1 * a2 * a3).transpose() * t.rotation.matrix();
        let q4 = m[(1, 2)].atan2(m[(0, 2)]);
        let q5 = m[(0, 2)].hypot(m[(1, 2)]).atan2(m[(2, 2)]);
        let q6 = m[(2, 1)].atan2(-m[(2, 0)]);
        let thesis = [q1, q2, q3, q4, q5, q6];
        assert!(
            pose_gap(
                &robot,
                &thesis,
                &Isometry3::from_parts(t.translation, UnitQuaternion::from_rotation_matrix(&t.rotation))
            ) < 1e-9
        );
        let all = solve(&robot, robot.fk(&q).unwrap());
        let s = find(&all, &thesis, 1e-9).unwrap_or_else(|| panic!("q = {q:?}: thesis {thesis:?} not among {all:#?}"));
        assert_eq!(s.branch.to_string(), "shoulder=front elbow=up wrist=noflip", "q = {q:?}");
    }
}

/// Notes 001 §2.6 discrepancy 3: q1's range is [0°, 360°] while atan2 returns (−180°, 180°];
/// targets with p2 < 0 get q1 moved by a whole turn into the range, not flagged.
#[test]
fn q1_is_reported_inside_its_0_to_360_range() {
    let robot = spbu6();
    let q = [5.0, 0.2, 0.1, 0.3, 0.4, 0.2]; // q1 ≈ 286°: p2 < 0
    let target = robot.fk(&q).unwrap();
    assert!(target.translation.vector.y < 0.0);
    let all = solve(&robot, target);
    let s = find(&all, &q, 1e-9).unwrap();
    assert!((s.q[0] - 5.0).abs() < 1e-9, "q1 = {}", s.q[0]);
    assert!(s.within_limits);
    for s in &all.solutions {
        assert!((0.0..=TAU).contains(&s.q[0]), "{:?}", s.q);
    }
}

/// Notes 001 §2.6 discrepancies 1–2: the workspace is the shell |l1 − l2| ≤ r ≤ l1 + l2.
#[test]
fn targets_outside_the_shell_are_unreachable() {
    let robot = spbu6();
    for (x, bound) in [(9.0, 8.0), (1.0, 2.0), (0.0, 2.0)] {
        let all = solve(&robot, Isometry3::translation(x, 0.0, 0.0));
        assert!(all.solutions.is_empty());
        match all.failure {
            Some(IkFailure::Unreachable { distance, reach, .. }) => {
                assert!((distance - x).abs() < 1e-12 && (reach - bound).abs() < 1e-12, "{distance} {reach}");
            }
            ref other => panic!("x = {x}: {other:?}"),
        }
    }
    // On both spheres the arm is stretched / folded: reachable, flagged as elbow singular.
    for (x, q3) in [(8.0, -FRAC_PI_2), (2.0, FRAC_PI_2)] {
        let all = solve(&robot, Isometry3::translation(x, 0.0, 0.0));
        assert!(!all.solutions.is_empty(), "r = {x}");
        for s in &all.solutions {
            assert!(s.singularities.contains(&SingularityKind::Elbow));
            assert!((reach::angle::wrap(s.q[2] - q3)).abs() < 1e-4, "{:?}", s.q);
        }
    }
}

/// Notes 001 §3.4: r̃33 = −1 (q5 = 180°, always outside the q5 limit) is the other wrist
/// singularity: q4 = atan2(−r12, −r11) + q6 with q6 = 0.
#[test]
fn r33_minus_one_is_singular_and_outside_limits() {
    let robot = spbu6();
    let q = [0.2, 0.1, 0.3, 0.5, PI, 0.0];
    let all = solve(&robot, robot.fk(&q).unwrap());
    let s = find(&all, &q, 1e-9).expect("generating q");
    assert!(s.singularities.contains(&SingularityKind::Wrist));
    assert!(!s.within_limits);
    assert_eq!(all.failure, Some(IkFailure::OutsideLimits { joint: 5, name: "q5".into() }));
}

/// Notes 001 §4.2: p1 = p2 = 0 leaves q1 undetermined — kept from the seed (else 0).
#[test]
fn wrist_centre_on_the_base_axis_keeps_the_seeds_q1() {
    let robot = spbu6();
    // 5·sin q2 + 3·cos(q2 + q3) = 0 puts the wrist centre on the base axis (notes §2.5).
    let q3: f64 = 0.5;
    let q2 = (-3.0 * q3.cos()).atan2(5.0 - 3.0 * q3.sin());
    let q = [0.9, q2, q3, 0.2, 0.3, 0.4];
    let target = robot.fk(&q).unwrap();
    assert!(target.translation.vector.xy().norm() < 1e-12);
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 4, "one shoulder × two elbows × two wrists");
    for s in &all.solutions {
        assert!(s.singularities.contains(&SingularityKind::Shoulder));
        assert_eq!(s.q[0], 0.0);
        assert!(pose_gap(&robot, &s.q, &target) < 1e-9);
    }
    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let all = solve_with(&robot, &IkTarget::Pose(target), &options);
    assert!(find(&all, &q, 1e-9).is_some(), "{:#?}", all.solutions);
}

#[test]
fn position_targets_solve_the_arm_and_keep_the_seeds_wrist() {
    let robot = spbu6();
    let q = [0.7, -0.3, 0.4, 0.1, 0.2, 0.3];
    let p = robot.fk(&q).unwrap().translation.vector;
    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let all = solve_with(&robot, &IkTarget::Position(p.into()), &options);
    assert!(find(&all, &q, 1e-9).is_some());
    for s in &all.solutions {
        let t = common::dh_product(&robot, &s.q);
        assert!((t.fixed_view::<3, 1>(0, 3) - p).norm() < 1e-9);
    }
}

#[test]
fn invalid_input_is_an_error_not_a_panic() {
    let robot = spbu6();
    let solver = TwoLinkWrist::from_robot(&robot).unwrap();
    let nan = IkTarget::Pose(Isometry3::translation(f64::NAN, 0.0, 0.0));
    assert!(solver.solve(&robot, &nan, &IkOptions::default()).is_err());
    let short_seed = IkOptions { seed: Some(vec![0.0; 3]), ..IkOptions::default() };
    assert!(solver.solve(&robot, &IkTarget::Pose(robot.fk(&[0.0; 6]).unwrap()), &short_seed).is_err());
}

/// Base and tool transforms are removed before solving (`chain_target`).
#[test]
fn base_and_tool_transforms_are_honoured() {
    let robot = spbu6()
        .with_base(Isometry3::new(Vector3::new(1.0, -2.0, 0.5), Vector3::new(0.1, 0.2, 0.3)))
        .unwrap()
        .with_tool(Isometry3::new(Vector3::new(0.0, 0.0, 0.4), Vector3::new(0.0, 0.3, 0.0)))
        .unwrap();
    let q = [0.4, 0.3, -0.5, 0.6, 0.7, -0.8];
    let target = robot.fk(&q).unwrap();
    let all = solve(&robot, target);
    assert_eq!(all.solutions.len(), 8);
    assert!(find(&all, &q, 1e-9).is_some());
    for s in &all.solutions {
        assert!(pose_gap(&robot, &s.q, &target) < 1e-9);
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// FK∘IK round trip over random joint vectors (full circle per joint): every solution
    /// reproduces the pose (independent FK), and the generating q is among them.
    #[test]
    fn round_trip(q in proptest::collection::vec(-PI..PI, 6)) {
        let robot = spbu6();
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        for s in &all.solutions {
            prop_assert!(pose_gap(&robot, &s.q, &target) < 1e-9, "{:?}", s.q);
        }
        let singular = q[4].sin().abs() < 1e-6;
        if !singular {
            prop_assert!(find(&all, &q, 1e-7).is_some(), "q = {:?} not among {:#?}", q, all.solutions);
        }
    }
}

/// A deterministic sweep for the report: 5000 random q, every one round-trips.
#[test]
fn round_trip_sweep() {
    let robot = spbu6();
    let mut rng = common::Rng::new(2024);
    let (mut found, mut total, mut max_gap, mut eight) = (0, 0, 0.0_f64, 0);
    for _ in 0..5000 {
        let q: Vec<f64> = (0..6).map(|_| rng.uniform(-PI, PI)).collect();
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        total += 1;
        if all.solutions.len() == 8 {
            eight += 1;
        }
        if find(&all, &q, 1e-7).is_some() {
            found += 1;
        }
        for s in &all.solutions {
            max_gap = max_gap.max(pose_gap(&robot, &s.q, &target));
        }
    }
    println!(
        "spbu6 sweep: {found}/{total} generating q found, {eight}/{total} with 8 solutions, max |ΔT| = {max_gap:.2e}"
    );
    assert_eq!(found, total);
    assert_eq!(eight, total);
    assert!(max_gap < 1e-12);
}

/// Targets approaching the wrist and elbow singularities: every solution still reproduces the
/// pose and nothing is NaN. Below `IK_PARALLEL_SINE` (1e-9) the wrist is treated as exactly
/// singular, which costs up to ~2·|sin q5| of orientation: hence the 3e-9 bound.
#[test]
fn near_singular_targets_stay_exact() {
    let robot = spbu6();
    for eps in [1e-3, 1e-6, 1e-8, 1e-9, 1e-10, 1e-12, 1e-15, 0.0] {
        for q in [
            [0.2, 0.3, -0.4, 0.5, eps, 0.6],             // wrist, q5 → 0
            [0.2, 0.3, -0.4, 0.5, PI - eps, 0.6],        // wrist, q5 → π
            [0.2, 0.3, -FRAC_PI_2 + eps, 0.5, 0.7, 0.6], // stretched
            [0.2, 0.3, FRAC_PI_2 - eps, 0.5, 0.7, 0.6],  // folded
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

/// A random arm of the family: random α signs (α5 = ±α4), link lengths of either sign, a
/// shoulder height d1, a flange offset d6, joint offsets and flipped joints.
fn random_robot(params: &[f64]) -> Robot {
    use reach::model::{Convention, Joint, RobotSpec};
    let sign = |x: f64| if x < 0.0 { -1.0 } else { 1.0 };
    let quarter = |x: f64| sign(x) * FRAC_PI_2;
    let p = |i: usize| params[i];
    let mut joints = vec![
        Joint::revolute(0.0, quarter(p(0)), p(1), p(2)),
        Joint::revolute(sign(p(3)) * (1.0 + 4.0 * p(3).abs()), 0.0, 0.0, p(4)),
        Joint::revolute(0.0, quarter(p(5)), 0.0, p(6)),
        Joint::revolute(0.0, quarter(p(7)), sign(p(8)) * (1.0 + 3.0 * p(8).abs()), p(9)),
        Joint::revolute(0.0, quarter(p(10)), 0.0, p(11)),
        Joint::revolute(0.0, 0.0, p(12), p(13)),
    ];
    for (j, &f) in joints.iter_mut().zip(&params[14..20]) {
        j.flip = f < 0.0;
    }
    Robot::new(RobotSpec::new("random-two-link-wrist", Convention::Dh, joints)).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Every sign convention of the family round-trips.
    #[test]
    fn any_convention_round_trip(
        params in proptest::collection::vec(-1.0..1.0f64, 20),
        q in proptest::collection::vec(-PI..PI, 6),
    ) {
        let robot = random_robot(&params);
        prop_assert_eq!(SolverKind::detect(&robot), SolverKind::TwoLinkWrist);
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target);
        for s in &all.solutions {
            prop_assert!(pose_gap(&robot, &s.q, &target) < 1e-9, "{:?}", s.q);
        }
        let q5 = if params[18] < 0.0 { -q[4] } else { q[4] };
        let theta5 = q5 + robot.joints()[4].dh().unwrap().theta_offset;
        if theta5.sin().abs() > 1e-6 {
            prop_assert!(find(&all, &q, 1e-7).is_some(), "q = {:?} not among {:#?}", q, all.solutions);
        }
    }
}
