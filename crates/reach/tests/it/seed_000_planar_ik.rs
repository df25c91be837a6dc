//! Seed 000 (thesis, notes 000 §3.1, §4.1, §6.1–6.3): the planar redundant arm `planar3`.
//!
//! The thesis prints no numeric example (notes 000 §6); the vectors below are the notes' own,
//! computed with the corrected formulas (γ2 = atan2(y, x), D1). Every value is asserted to
//! the notes' 6 decimals (degrees). The paper's printed formulas that cannot be reproduced
//! (D1, D3) are shown to fail and the corrected values are asserted instead.

use std::f64::consts::PI;

use approx::assert_relative_eq;
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use reach::angle::{deg, wrap};
use reach::ik::planar::{PlanarRedundant, ScanRow};
use reach::ik::{IkFailure, IkOptions, IkSolver, IkTarget, SingularityKind};
use reach::model::planar_angles::InteriorAngles;
use reach::model::{Convention, Joint, Robot, RobotSpec, presets};

/// Notes' values are rounded to 6 decimals of a degree.
const NOTES_DEG: f64 = 1.5e-6;

fn planar3() -> (Robot, PlanarRedundant) {
    let robot = presets::get("planar3").unwrap();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    (robot, arm)
}

/// A planar arm of three equal links `l`, standard DH, the paper's limits.
fn equal_arm(l: f64) -> (Robot, PlanarRedundant) {
    let joints = vec![
        Joint::revolute(l, 0.0, 0.0, 0.0).with_limits(0.0, PI),
        Joint::revolute(l, 0.0, 0.0, 0.0).with_limits(-PI, 0.0),
        Joint::revolute(l, 0.0, 0.0, 0.0).with_limits(-PI, 0.0),
    ];
    let robot = Robot::new(RobotSpec::new("planar-l", Convention::Dh, joints)).unwrap();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    (robot, arm)
}

fn row(arm: &PlanarRedundant, target: [f64; 2], alpha_deg: f64) -> ScanRow {
    arm.paper_row(target, deg(alpha_deg)).expect("row exists")
}

fn assert_deg(value: f64, expected_deg: f64) {
    assert_relative_eq!(value.to_degrees(), expected_deg, epsilon = NOTES_DEG);
}

fn tip(robot: &Robot, q: &[f64; 3]) -> [f64; 2] {
    let t = robot.fk(q).unwrap().translation.vector;
    [t.x, t.y]
}

// ---------------------------------------------------------------------------------------------
// §6.2 IK test vectors.
// ---------------------------------------------------------------------------------------------

/// Notes 000 §6.2: (target, α_min, γ and β at α_min, γ and β at 180°, optional γ and β at 120°).
#[allow(clippy::type_complexity)]
const VECTORS: &[([f64; 2], f64, [f64; 2], [f64; 2], Option<[f64; 2]>)] = &[
    ([2.0, 1.0], 90.0, [53.130102, 180.0], [90.0, 90.0], Some([74.434636, 136.778655])),
    ([1.5, 1.5], 82.819244, [72.885567, 180.0], [114.295189, 82.819244], Some([98.895795, 128.298921])),
    ([2.4, 0.2], 101.536959, [28.770005, 180.0], [59.220319, 101.536959], Some([42.677819, 151.306446])),
    ([0.0, 2.0], 75.522488, [118.955024, 180.0], [165.522488, 75.522488], Some([150.0, 120.0])),
    // D11: γ leaves the paper's 0–180° range.
    ([2.5, -1.0], 124.228866, [-3.918979, 180.0], [16.087294, 124.228866], None),
    ([-1.5, 1.5], 82.819244, [162.885567, 180.0], [204.295189, 82.819244], Some([188.895795, 128.298921])),
];

#[test]
fn ik_test_vectors_of_section_6_2() {
    let (robot, arm) = planar3();
    for &(target, alpha_min, at_min, at_180, at_120) in VECTORS {
        let scan = arm.paper_scan(target, deg(0.01)).unwrap();
        assert_deg(scan.alpha_min.unwrap(), alpha_min);
        let first = scan.rows[0];
        assert_deg(first.paper.alpha, alpha_min);
        assert_deg(first.paper.gamma, at_min[0]);
        assert_deg(first.paper.beta, at_min[1]);
        let last = row(&arm, target, 180.0);
        assert_deg(last.paper.gamma, at_180[0]);
        assert_deg(last.paper.beta, at_180[1]);
        if let Some([g, b]) = at_120 {
            let r = row(&arm, target, 120.0);
            assert_deg(r.paper.gamma, g);
            assert_deg(r.paper.beta, b);
        }
        // The corrected γ2 (D1): every row of the table reaches the target.
        for r in scan.rows.iter().step_by(97).chain(scan.rows.last()) {
            let k = tip(&robot, &r.q);
            assert!((k[0] - target[0]).hypot(k[1] - target[1]) < 1e-12, "{target:?} row {r:?}");
        }
    }
}

#[test]
fn sub_angles_gamma1_beta1_of_section_6_2() {
    let (_, arm) = planar3();
    // γ1 = γ − atan2(y, x); β1 = β − (180° − α)/2 (eq. 13 for equal links).
    let cases: &[([f64; 2], f64, f64, f64)] = &[
        ([2.0, 1.0], 90.0, 26.565051, 135.0),
        ([2.0, 1.0], 120.0, 47.869585, 106.778655),
        ([1.5, 1.5], 82.819244, 27.885567, 131.409622),
        ([1.5, 1.5], 120.0, 53.895795, 98.298921),
        ([2.4, 0.2], 101.536959, 24.006363, 140.768480),
        ([0.0, 2.0], 120.0, 60.0, 90.0),
    ];
    for &([x, y], alpha, gamma1, beta1) in cases {
        // α_min as printed is rounded (possibly below the true α_min, where β > 180°).
        let a_min = arm.paper_scan([x, y], deg(1.0)).unwrap().alpha_min.unwrap();
        let r = if (deg(alpha) - a_min).abs() < 1e-6 {
            arm.paper_row([x, y], a_min).unwrap()
        } else {
            row(&arm, [x, y], alpha)
        };
        assert_relative_eq!((r.paper.gamma - y.atan2(x)).to_degrees(), gamma1, epsilon = 2.0 * NOTES_DEG);
        assert_relative_eq!((r.paper.beta - (PI - r.paper.alpha) / 2.0).to_degrees(), beta1, epsilon = 2.0 * NOTES_DEG);
    }
    // α = 180° rows, γ1: (2, 1) → 63.434949°, (1.5, 1.5) → 69.295189°, (2.4, 0.2) → 54.456677°.
    for ([x, y], g1) in [([2.0, 1.0], 63.434949), ([1.5, 1.5], 69.295189), ([2.4, 0.2], 54.456677)] {
        let r = row(&arm, [x, y], 180.0);
        assert_relative_eq!((r.paper.gamma - f64::atan2(y, x)).to_degrees(), g1, epsilon = 2.0 * NOTES_DEG);
    }
}

#[test]
fn joint_points_of_section_6_2() {
    let (robot, arm) = planar3();
    // (2, 1) at α = 180°: B = (0, 1), A = (1, 1), K = (2, 1).
    let r = row(&arm, [2.0, 1.0], 180.0);
    let frames = robot.frames(&r.q).unwrap();
    let expected = [[0.0, 1.0], [1.0, 1.0], [2.0, 1.0]];
    for (f, e) in frames.iter().zip(expected) {
        assert_relative_eq!(f.translation.vector.x, e[0], epsilon = 1e-12);
        assert_relative_eq!(f.translation.vector.y, e[1], epsilon = 1e-12);
    }
    // (0, 2) at α = 120°: B = (−0.866025, 0.5), A = (−0.866025, 1.5).
    let r = row(&arm, [0.0, 2.0], 120.0);
    let frames = robot.frames(&r.q).unwrap();
    let c = 0.75f64.sqrt();
    for (f, e) in frames.iter().zip([[-c, 0.5], [-c, 1.5], [0.0, 2.0]]) {
        assert_relative_eq!(f.translation.vector.x, e[0], epsilon = 1e-12);
        assert_relative_eq!(f.translation.vector.y, e[1], epsilon = 1e-12);
    }
}

#[test]
fn beta_is_180_at_alpha_min_and_alpha_min_at_180() {
    // Notes 000 §6.1 "verified correct": β(α_min) = 180°, β(180°) = α_min; along the table γ
    // increases and β decreases.
    let (_, arm) = planar3();
    for &(target, ..) in VECTORS {
        let scan = arm.paper_scan(target, deg(0.5)).unwrap();
        let a_min = scan.alpha_min.unwrap();
        assert_relative_eq!(scan.rows[0].paper.beta, PI, epsilon = 1e-9);
        assert_relative_eq!(row(&arm, target, 180.0).paper.beta, a_min, epsilon = 1e-9);
        for w in scan.rows.windows(2) {
            assert!(w[1].paper.gamma > w[0].paper.gamma && w[1].paper.beta < w[0].paper.beta, "{target:?}");
        }
    }
}

#[test]
fn d1_printed_gamma2_mirrors_the_arm() {
    // Notes 000 §6.1 D1 / §6.2: with the printed γ2 = atan(x/y), the target (2, 1) at α_min
    // gives γ = 90°, β = 180°, and the arm reaches (1, 2), the mirror image, not (2, 1).
    let (robot, arm) = planar3();
    let r = row(&arm, [2.0, 1.0], 90.0);
    let gamma1 = r.paper.gamma - 1f64.atan2(2.0);
    let printed = InteriorAngles { gamma: gamma1 + (2.0f64 / 1.0).atan(), ..r.paper };
    assert_relative_eq!(printed.gamma.to_degrees(), 90.0, epsilon = 1e-9);
    let k = tip(&robot, &printed.to_joints());
    assert_relative_eq!(k[0], 1.0, epsilon = 1e-12);
    assert_relative_eq!(k[1], 2.0, epsilon = 1e-12);
    // The corrected row reaches the target.
    let k = tip(&robot, &r.q);
    assert_relative_eq!(k[0], 2.0, epsilon = 1e-12);
    assert_relative_eq!(k[1], 1.0, epsilon = 1e-12);
}

#[test]
fn d3_printed_last_row_is_undefined_corrected_one_is_not() {
    // Notes 000 §6.1 D3: the printed α = 180° argument 3(x² + y² − L²)/(2L·r) is 2.47 for
    // (1.5, 1.5), outside acos's domain; the corrected (x² + y² − 3L²)/(2L·r) gives γ.
    let (x, y) = (1.5f64, 1.5f64);
    let r = x.hypot(y);
    let printed = 3.0 * (x * x + y * y - 1.0) / (2.0 * r);
    assert_relative_eq!(printed, 2.474873734, epsilon = 1e-9);
    assert!(printed > 1.0);
    let corrected = ((x * x + y * y - 3.0) / (2.0 * r)).acos() + y.atan2(x);
    assert_relative_eq!(corrected.to_degrees(), 114.295189, epsilon = NOTES_DEG);
    let (_, arm) = planar3();
    let scan = arm.paper_scan([x, y], deg(0.01)).unwrap();
    assert_relative_eq!(scan.rows.last().unwrap().paper.gamma, corrected, epsilon = 1e-6);
}

#[test]
fn d11_gamma_outside_the_papers_range_is_flagged_not_filtered() {
    let (_, arm) = planar3();
    let scan = arm.paper_scan([2.5, -1.0], deg(0.01)).unwrap();
    assert!(scan.rows[0].paper.gamma < 0.0);
    assert!(!scan.rows[0].within_limits);
    assert!(scan.rows.iter().any(|r| r.within_limits));
    let scan = arm.paper_scan([-1.5, 1.5], deg(0.01)).unwrap();
    assert!(scan.rows.last().unwrap().paper.gamma > PI);
    assert!(!scan.rows.last().unwrap().within_limits);
}

#[test]
fn scale_invariance_l100() {
    // Notes 000 §6.2 last row: L = 100, target (150, 150) gives the angles of (1.5, 1.5).
    let (_, arm) = equal_arm(100.0);
    let scan = arm.paper_scan([150.0, 150.0], deg(0.01)).unwrap();
    assert_deg(scan.alpha_min.unwrap(), 82.819244);
    assert_deg(scan.rows[0].paper.gamma, 72.885567);
    let r = row(&arm, [150.0, 150.0], 120.0);
    assert_deg(r.paper.gamma, 98.895795);
    assert_deg(r.paper.beta, 128.298921);
}

#[test]
fn workspace_test_is_strict() {
    // Notes 000 §6.2: (0.5, 0.5), (1, 0), (3, 0), (0, 3.2) are rejected (3L > KO > L).
    let (_, arm) = planar3();
    for (target, bound) in [([0.5, 0.5], 1.0), ([1.0, 0.0], 1.0), ([3.0, 0.0], 3.0), ([0.0, 3.2], 3.0)] {
        let scan = arm.paper_scan(target, deg(0.01)).unwrap();
        assert!(scan.rows.is_empty() && scan.alpha_min.is_none());
        match scan.failure {
            Some(IkFailure::Unreachable { distance, reach, .. }) => {
                assert_relative_eq!(distance, f64::hypot(target[0], target[1]), epsilon = 1e-15);
                assert_eq!(reach, bound);
            }
            other => panic!("{target:?}: {other:?}"),
        }
    }
}

// ---------------------------------------------------------------------------------------------
// §6.3 selection by minimum S.
// ---------------------------------------------------------------------------------------------

fn paper_deg(alpha: f64, beta: f64, gamma: f64) -> InteriorAngles {
    InteriorAngles { alpha: deg(alpha), beta: deg(beta), gamma: deg(gamma) }
}

#[test]
fn min_s_selection_of_section_6_3() {
    let (_, arm) = planar3();
    // (initial α0 β0 γ0, target, Δα, rows, S, i, α, β, γ) — notes 000 §6.3.
    #[allow(clippy::type_complexity)]
    let cases: &[([f64; 3], [f64; 2], f64, usize, f64, usize, [f64; 3])] = &[
        ([150.0, 140.0, 60.0], [2.4, 0.2], 0.01, 7847, 23.756601, 4846, [149.996959, 121.048252, 55.198188]),
        ([150.0, 140.0, 60.0], [2.4, 0.2], 0.001, 78464, 23.755217, 48463, [149.999959, 121.045829, 55.198996]),
        ([100.0, 150.0, 80.0], [2.0, 0.5], 0.01, 10081, 23.582372, 2080, [99.993077, 147.142506, 59.282045]),
        ([120.0, 120.0, 100.0], [1.5, 1.5], 0.01, 9719, 8.224232, 3941, [122.229244, 125.993423, 100.001565]),
        ([150.0, 100.0, 60.0], [2.0, 1.0], 0.01, 9001, 35.068953, 6000, [150.0, 108.976675, 86.092278]),
        ([120.0, 120.0, 100.0], [2.5, 0.5], 0.01, 6798, 88.081878, 4443, [156.454313, 126.960322, 55.332757]),
    ];
    for &(start, target, step, rows, s, index, [a, b, g]) in cases {
        let scan = arm.paper_scan(target, deg(step)).unwrap();
        assert_eq!(scan.rows.len(), rows, "{target:?} step {step}");
        let (i, best_s) = scan.select_min_s(&paper_deg(start[0], start[1], start[2])).unwrap();
        assert_eq!(i, index, "{target:?} step {step}");
        assert_deg(best_s, s);
        let p = scan.rows[i].paper;
        assert_deg(p.alpha, a);
        assert_deg(p.beta, b);
        assert_deg(p.gamma, g);
    }
}

#[test]
fn initial_poses_and_selected_wrist_points_of_section_6_3() {
    let (robot, arm) = planar3();
    // Initial (150, 140, 60): B = (0.5, 0.866025), A = (1.439693, 1.208046), K = (2.4245, 1.034397).
    let q0 = paper_deg(150.0, 140.0, 60.0).to_joints();
    let f = robot.frames(&q0).unwrap();
    let pts: Vec<[f64; 2]> = f.iter().map(|m| [m.translation.vector.x, m.translation.vector.y]).collect();
    for (p, e) in pts.iter().zip([[0.5, 0.866025], [1.439693, 1.208046], [2.4245, 1.034397]]) {
        assert_relative_eq!(p[0], e[0], epsilon = 1e-6);
        assert_relative_eq!(p[1], e[1], epsilon = 1e-6);
    }
    for (start, k) in [([100.0, 150.0, 80.0], [1.682461, 1.250852]), ([120.0, 120.0, 100.0], [1.532089, 1.285575])] {
        let t = tip(&robot, &paper_deg(start[0], start[1], start[2]).to_joints());
        assert_relative_eq!(t[0], k[0], epsilon = 1e-6);
        assert_relative_eq!(t[1], k[1], epsilon = 1e-6);
    }
    // Selected rows: B1 = (0.570740, 0.821131), A1 = (1.568594, 0.755666) for K1 = (2.4, 0.2);
    // A1 = (1.406334, 1.304711) for K1 = (2.0, 0.5).
    let scan = arm.paper_scan([2.4, 0.2], deg(0.01)).unwrap();
    let (i, _) = scan.select_min_s(&paper_deg(150.0, 140.0, 60.0)).unwrap();
    let f = robot.frames(&scan.rows[i].q).unwrap();
    assert_relative_eq!(f[0].translation.vector.x, 0.570740, epsilon = 1e-6);
    assert_relative_eq!(f[0].translation.vector.y, 0.821131, epsilon = 1e-6);
    assert_relative_eq!(f[1].translation.vector.x, 1.568594, epsilon = 1e-6);
    assert_relative_eq!(f[1].translation.vector.y, 0.755666, epsilon = 1e-6);
    let scan = arm.paper_scan([2.0, 0.5], deg(0.01)).unwrap();
    let (i, _) = scan.select_min_s(&paper_deg(100.0, 150.0, 80.0)).unwrap();
    let f = robot.frames(&scan.rows[i].q).unwrap();
    assert_relative_eq!(f[1].translation.vector.x, 1.406334, epsilon = 1e-6);
    assert_relative_eq!(f[1].translation.vector.y, 1.304711, epsilon = 1e-6);
}

// ---------------------------------------------------------------------------------------------
// The closed-form self-motion agrees with the thesis's table.
// ---------------------------------------------------------------------------------------------

#[test]
fn every_paper_row_is_a_closed_form_solution() {
    let (robot, arm) = planar3();
    let target = [2.4, 0.2];
    let scan = arm.paper_scan(target, deg(1.0)).unwrap();
    let intervals = arm.feasible_intervals(target);
    for r in &scan.rows {
        let phi = arm.link_angles(&r.q)[2];
        assert!(
            intervals.iter().any(|iv| wrap(phi - (iv.start + iv.end) / 2.0).abs() <= iv.width() / 2.0 + 1e-9),
            "φ {phi} {intervals:?} {r:?}"
        );
        let opts = IkOptions { free_parameter: Some(phi), ..IkOptions::default() };
        let sols = arm.solve(&robot, &IkTarget::Position(Point3::new(target[0], target[1], 0.0)), &opts).unwrap();
        // The row is the clockwise ("up") elbow, or the stretched one at α_min (β = 180°).
        let up = sols.solutions.iter().find(|s| matches!(s.branch.get("elbow"), Some("up" | "stretched"))).unwrap();
        for (a, b) in up.q.iter().zip(&r.q) {
            assert!(wrap(a - b).abs() < 1e-9, "{:?} vs {:?}", up.q, r.q);
        }
        assert_eq!(up.within_limits, r.within_limits);
    }
}

#[test]
fn sampled_self_motion_covers_the_intervals() {
    let (robot, arm) = planar3();
    let target = IkTarget::Position(Point3::new(2.0, 1.0, 0.0));
    let opts = IkOptions { redundancy_step: deg(1.0), ..IkOptions::default() };
    let sols = arm.solve(&robot, &target, &opts).unwrap();
    // (2, 1), l = 1: |W| ≤ 2 ⇔ cos(φ − ψ) ≥ (5 + 1 − 4)/(2√5), i.e. |φ − ψ| ≤ 63.4349°; the
    // inner bound is 0, so one interval of 126.87°: 127 steps of ≤ 1°, 128 samples, two
    // elbows each except at the two stretched ends.
    let ivs = arm.feasible_intervals([2.0, 1.0]);
    assert_eq!(ivs.len(), 1);
    assert_relative_eq!(ivs[0].width().to_degrees(), 2.0 * 63.434948822922, epsilon = 1e-9);
    assert_eq!(sols.solutions.len(), 2 * 128 - 2);
    assert!(sols.solutions.iter().all(|s| s.position_error < 1e-12));
    let stretched: Vec<_> =
        sols.solutions.iter().filter(|s| s.singularities.contains(&SingularityKind::Elbow)).collect();
    assert_eq!(stretched.len(), 2);
    assert!(stretched.iter().all(|s| s.branch.get("elbow") == Some("stretched")));
    // The paper's limits keep the clockwise branch only (q2, q3 ≤ 0) and not all of it.
    assert!(sols.feasible().all(|s| s.branch.get("elbow") != Some("down")));
    assert!(sols.feasible().count() > 10);
    assert!(sols.failure.is_none());
}

#[test]
fn pose_target_fixes_the_heading() {
    let (robot, arm) = planar3();
    // Tool at (2, 1) heading 0°: the wrist is at (1, 1); elbow up is B = (0, 1): q = (90°, −90°, 0).
    let pose = Isometry3::from_parts(Translation3::new(2.0, 1.0, 0.0), UnitQuaternion::identity());
    let sols = arm.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
    assert_eq!(sols.solutions.len(), 2);
    let up = sols.solutions.iter().find(|s| s.branch.get("elbow") == Some("up")).unwrap();
    for (a, e) in up.q.iter().zip([90.0, -90.0, 0.0]) {
        assert_relative_eq!(a.to_degrees(), e, epsilon = 1e-9);
    }
    // The other elbow: B = (1, 0), q = (0°, 90°, −90°), outside the paper's limits.
    let down = sols.solutions.iter().find(|s| s.branch.get("elbow") == Some("down")).unwrap();
    for (a, e) in down.q.iter().zip([0.0, 90.0, -90.0]) {
        assert_relative_eq!(a.to_degrees(), e, epsilon = 1e-9);
    }
    assert!(!down.within_limits && up.within_limits);
    // A tilted tool orientation cannot be reached by a planar arm.
    let tilted = Isometry3::from_parts(
        Translation3::new(2.0, 1.0, 0.0),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), 0.3),
    );
    let sols = arm.solve(&robot, &IkTarget::Pose(tilted), &IkOptions::default()).unwrap();
    assert!(sols.solutions.is_empty());
    assert_eq!(sols.failure, Some(IkFailure::OrientationUnreachable));
}

#[test]
fn unreachable_off_plane_and_singular_targets() {
    let (robot, arm) = planar3();
    let solve = |p: Point3<f64>, opts: &IkOptions| arm.solve(&robot, &IkTarget::Position(p), opts).unwrap();
    let d = IkOptions::default();
    let s = solve(Point3::new(3.5, 0.0, 0.0), &d);
    assert_eq!(
        s.failure,
        Some(IkFailure::Unreachable { distance: 3.5, reach: 3.0, point: "the target", from: "joint 1" })
    );
    let s = solve(Point3::new(2.0, 1.0, 0.01), &d);
    assert_eq!(
        s.failure,
        Some(IkFailure::Unreachable { distance: 0.01, reach: 0.0, point: "the target", from: "the arm's plane" })
    );
    // φ = 180° for (2, 1): the wrist (3, 1) is beyond 2 links; the position is reachable.
    let s = solve(Point3::new(2.0, 1.0, 0.0), &IkOptions { free_parameter: Some(PI), ..d.clone() });
    assert_eq!(s.failure, Some(IkFailure::OrientationUnreachable));
    // Fully stretched (r = 3L): one configuration, flagged, all links along the target.
    let s = solve(Point3::new(0.0, 3.0, 0.0), &d);
    assert_eq!(s.solutions.len(), 1);
    let sol = &s.solutions[0];
    assert!(sol.singularities.contains(&SingularityKind::Elbow));
    for (a, e) in sol.q.iter().zip([90.0, 0.0, 0.0]) {
        assert_relative_eq!(a.to_degrees(), e, epsilon = 1e-6);
    }
    // Wrist on the base axis: with φ = 0 the target (1, 0) puts W at O; φ1 comes from the seed.
    let opts = IkOptions { free_parameter: Some(0.0), seed: Some(vec![0.4, -2.0, -1.0]), ..d.clone() };
    let s = solve(Point3::new(1.0, 0.0, 0.0), &opts);
    assert_eq!(s.solutions.len(), 1);
    assert!(s.solutions[0].singularities.contains(&SingularityKind::Shoulder));
    assert_relative_eq!(s.solutions[0].q[0], 0.4, epsilon = 1e-12);
    assert_relative_eq!(s.solutions[0].q[1], -PI, epsilon = 1e-12);
}

#[test]
fn unequal_links_workspace_and_intervals() {
    // l = (2, 0.5, 0.4): inner radius 2 − 0.9 = 1.1; a target at 1.0 is unreachable.
    let joints = vec![
        Joint::revolute(2.0, 0.0, 0.0, 0.0),
        Joint::revolute(0.5, 0.0, 0.0, 0.0),
        Joint::revolute(0.4, 0.0, 0.0, 0.0),
    ];
    let robot = Robot::new(RobotSpec::new("uneven", Convention::Dh, joints)).unwrap();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    let (inner, outer) = arm.workspace();
    assert_relative_eq!(inner, 1.1, epsilon = 1e-12);
    assert_relative_eq!(outer, 2.9, epsilon = 1e-12);
    let s = arm.solve(&robot, &IkTarget::Position(Point3::new(0.0, 1.0, 0.0)), &IkOptions::default()).unwrap();
    match s.failure {
        Some(IkFailure::Unreachable { distance, reach, .. }) => {
            assert_eq!(distance, 1.0);
            assert_relative_eq!(reach, 1.1, epsilon = 1e-12);
        }
        other => panic!("{other:?}"),
    }
    // r = 2: |W|² = 4.16 − 1.6 cos ω must lie in [1.5², 2.5²] → cos ω ∈ [−1.3, 1.19375]: all φ.
    assert_eq!(arm.feasible_intervals([2.0, 0.0]).len(), 1);
    assert_relative_eq!(arm.feasible_intervals([2.0, 0.0])[0].width(), 2.0 * PI);
    // r = 2.7: cos ω ≥ (7.29 + 0.16 − 6.25)/(2·2.7·0.4) = 0.5556: |ω| ≤ 56.25°.
    let ivs = arm.feasible_intervals([2.7, 0.0]);
    assert_eq!(ivs.len(), 1);
    assert_relative_eq!(ivs[0].end.to_degrees(), (1.2f64 / 2.16).acos().to_degrees(), epsilon = 1e-9);
    // r = 1.2: cos ω ≤ (1.44 + 0.16 − 2.25)/(0.96) < 0 …and ≥ −1: two intervals around ±180°
    // merge into one through 180°.
    let ivs = arm.feasible_intervals([1.2, 0.0]);
    assert_eq!(ivs.len(), 1);
    assert_relative_eq!(ivs[0].start + ivs[0].end, 2.0 * PI, epsilon = 1e-12);
    assert_relative_eq!(ivs[0].start, (-0.65f64 / 0.96).acos(), epsilon = 1e-12);
}

#[test]
fn detected_for_the_preset() {
    assert_eq!(reach::ik::SolverKind::detect(&presets::get("planar3").unwrap()), reach::ik::SolverKind::Planar);
}

#[test]
fn nearly_folded_equal_links_keep_both_exact_branches() {
    // q2 = π − 5.7e-6: the wrist is 5.7e-6 m from the base axis. Snapping the elbow to 180°
    // (by the acos argument) would put it on the axis, 5.7e-6 m off; both exact branches are
    // returned, flagged.
    let (robot, arm) = planar3();
    let q = [1.1453968968165593, 3.14158694907791, -0.8863789513191007];
    let sols = arm.solve(&robot, &IkTarget::Pose(robot.fk(&q).unwrap()), &IkOptions::default()).unwrap();
    assert_eq!(sols.solutions.len(), 2);
    assert!(sols.solutions.iter().all(|s| s.singularities == vec![SingularityKind::Elbow]));
    assert!(contains(&sols, &q));
}

// ---------------------------------------------------------------------------------------------
// Round trips over random arms and configurations.
// ---------------------------------------------------------------------------------------------

fn random_arm(l: [f64; 3], offsets: [f64; 3], d: [f64; 3], flip: [bool; 3], mdh: bool, base: [f64; 6]) -> Robot {
    let mut joints: Vec<Joint> = if mdh {
        // MDH: a and α belong to the preceding link; the last link is the tool translation.
        (0..3).map(|i| Joint::revolute(if i == 0 { 0.3 } else { l[i - 1] }, 0.0, d[i], offsets[i])).collect()
    } else {
        (0..3).map(|i| Joint::revolute(l[i], 0.0, d[i], offsets[i])).collect()
    };
    for (j, f) in joints.iter_mut().zip(flip) {
        j.flip = f;
    }
    let mut spec = RobotSpec::new("random-planar", if mdh { Convention::Mdh } else { Convention::Dh }, joints);
    spec.base = Isometry3::new(Vector3::new(base[0], base[1], base[2]), Vector3::new(base[3], base[4], base[5]));
    spec.tool = if mdh {
        Isometry3::new(Vector3::new(l[2], 0.0, 0.05), Vector3::new(0.0, 0.0, 0.4))
    } else {
        Isometry3::new(Vector3::new(0.0, 0.1, 0.0), Vector3::new(0.2, -0.1, 0.3))
    };
    Robot::new(spec).unwrap()
}

fn contains(sols: &reach::ik::IkSolutions, q: &[f64]) -> bool {
    sols.solutions.iter().any(|s| s.q.iter().zip(q).all(|(a, b)| wrap(a - b).abs() < 1e-7))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn planar3_round_trip(q in prop::array::uniform3(-PI..PI)) {
        let (robot, arm) = planar3();
        let pose = robot.fk(&q).unwrap();
        // Pose target: the heading fixes φ; q is one of the (≤ 2) solutions.
        let sols = arm.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q), "{:?} not in {:?}", q, sols.solutions);
        // Position target with φ = absolute angle of the last link.
        let p = Point3::from(pose.translation.vector);
        let opts = IkOptions { free_parameter: Some(arm.link_angles(&q)[2]), ..IkOptions::default() };
        let sols = arm.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
        prop_assert!(singular || contains(&sols, &q));
        // The sampled self-motion: every sample reaches the position.
        let sols = arm.solve(&robot, &IkTarget::Position(p), &IkOptions { redundancy_step: deg(5.0), ..IkOptions::default() }).unwrap();
        prop_assert!(!sols.solutions.is_empty());
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9));
    }

    #[test]
    fn arbitrary_planar_arms_round_trip(
        l in prop::array::uniform3(0.2f64..2.0),
        offsets in prop::array::uniform3(-PI..PI),
        d in prop::array::uniform3(-0.5f64..0.5),
        flip in prop::array::uniform3(any::<bool>()),
        mdh in any::<bool>(),
        base in prop::array::uniform6(-1.0f64..1.0),
        q in prop::array::uniform3(-PI..PI),
    ) {
        let robot = random_arm(l, offsets, d, flip, mdh, base);
        let arm = PlanarRedundant::from_robot(&robot).unwrap();
        let pose = robot.fk(&q).unwrap();
        let sols = arm.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        prop_assert!(!sols.solutions.is_empty());
        prop_assert!(sols.solutions.iter().all(|s| s.position_error < 1e-9 && s.orientation_error < 1e-9));
        let singular = sols.solutions.iter().any(|s| !s.singularities.is_empty());
        prop_assert!(singular || contains(&sols, &q), "{:?} not in {:?}", q, sols.solutions);
        let p = Point3::from(pose.translation.vector);
        let opts = IkOptions { free_parameter: Some(arm.link_angles(&q)[2]), ..IkOptions::default() };
        let sols = arm.solve(&robot, &IkTarget::Position(p), &opts).unwrap();
        prop_assert!(singular || contains(&sols, &q));
        let (_, _, off) = arm.plane_coordinates(&p);
        prop_assert!(off.abs() < 1e-12);
    }
}
