//! Seed 003 (Knapczyk & Kisiel 1987): inverse kinematics of the RERR welding robot by the
//! vector method (`ik::parallel_axes`), against the test vectors of notes 003 §5.3–5.5.
//!
//! The paper prints no numbers (its Fig. 8 is lost); the notes reconstruct them in the
//! paper's sign convention (notes 003 §2.6: w = e2 = e3 = −e4, i.e. the standard-DH table
//! with α3 = 180° instead of the printed 0°), which is the `welder6r` preset. The
//! "table-consistent" convention (α3 = 0°, Table 1 as printed) is built here as a second robot
//! and checked against the notes' mapping θ4' = −180° − θ4, θ5' = θ5 + 180°.
//!
//! The weld (notes 003 §5.1–5.2): the tool point moves on the straight line from
//! P = (50, 740, 70) mm to M = (500, 200, 700) mm with the constant orientation
//! n = (M − P)/|MP| (tool x axis), e6 = (y1 − y2, x2 − x1, 0)/|M1P1| (tool y axis),
//! l = n × e6 (tool z axis; the printed `l_x = n_z e_6y` lacks its minus, notes 003 §6.4).

use crate::common;

use std::f64::consts::{PI, TAU};

use crate::common::{WELD_M_MM as M_MM, WELD_P_MM as P_MM};
use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;
use reach::Robot;
use reach::ik::parallel_axes::{ParallelAxes, Shoulder, Wrist};
use reach::ik::{IkFailure, IkOptions, IkSolution, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::{Convention, Joint, JointGeometry, RobotSpec, presets};

fn welder() -> Robot {
    presets::get("welder6r").unwrap()
}

/// Table 1 as printed (α3 = 0°): the notes' "table-consistent" convention.
fn welder_table() -> Robot {
    let mut spec = welder().spec().clone();
    if let JointGeometry::Dh(p) = &mut spec.joints[2].geometry {
        p.alpha = 0.0;
    }
    spec.name = "welder6r-table".into();
    Robot::new(spec).unwrap()
}

/// Tool pose at arc length `s_mm` from P along the weld.
fn weld_pose(s_mm: f64) -> Isometry3<f64> {
    common::weld_pose(s_mm / 1000.0)
}

fn solve(robot: &Robot, pose: Isometry3<f64>, options: &IkOptions) -> IkSolutions {
    ParallelAxes::from_robot(robot).unwrap().solve(robot, &IkTarget::Pose(pose), options).unwrap()
}

fn branch<'a>(all: &'a IkSolutions, shoulder: &str, config: &str, wrist: &str) -> &'a IkSolution {
    all.solutions
        .iter()
        .find(|s| {
            s.branch.get("shoulder") == Some(shoulder)
                && s.branch.get("config") == Some(config)
                && s.branch.get("wrist") == Some(wrist)
        })
        .unwrap_or_else(|| panic!("no branch {shoulder} {config} {wrist} in {:#?}", all.solutions))
}

/// The paper's configuration `config` (shoulder `w`, wrist `e5`: notes 003 §3.7).
fn paper<'a>(all: &'a IkSolutions, config: &str) -> &'a IkSolution {
    branch(all, "w", config, "e5")
}

fn degrees(s: &IkSolution) -> Vec<f64> {
    s.q.iter().map(|v| v.to_degrees()).collect()
}

fn assert_degrees(actual: &[f64], expected: &[f64], tolerance: f64, what: &str) {
    for (i, (a, e)) in actual.iter().zip(expected).enumerate() {
        let diff = (a - e + 540.0).rem_euclid(360.0) - 180.0;
        assert!(diff.abs() < tolerance, "{what}: θ{} = {a:.6}°, expected {e}°", i + 1);
    }
}

// ---------------------------------------------------------------------------------------------
// Notes 003 §5.3: end points, both configurations, printed to 4 decimals.
// ---------------------------------------------------------------------------------------------

const START_PLUS: [f64; 6] = [105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315];
const START_MINUS: [f64; 6] = [105.2482, 3.9000, -43.3392, 140.5608, -155.4427, 138.1315];
const END_PLUS: [f64; 6] = [13.5666, 25.8448, 77.2028, -76.9524, -63.7610, 138.1315];
const END_MINUS: [f64; 6] = [13.5666, 90.0350, -77.2028, -167.1678, -63.7610, 138.1315];
/// Half a unit in the 4th decimal plus round-off.
const TABLE_4DP: f64 = 1e-4;

#[test]
fn end_points_reproduce_section_5_3() {
    let robot = welder();
    let start = solve(&robot, weld_pose(0.0), &IkOptions::default());
    assert_degrees(&degrees(paper(&start, "+β")), &START_PLUS, TABLE_4DP, "P, +β");
    assert_degrees(&degrees(paper(&start, "−β")), &START_MINUS, TABLE_4DP, "P, −β");
    let length = (Vector3::from(M_MM) - Vector3::from(P_MM)).norm();
    assert!((length - 943.927963).abs() < 1e-6, "|MP| (notes §5.2)");
    let end = solve(&robot, weld_pose(length), &IkOptions::default());
    assert_degrees(&degrees(paper(&end, "+β")), &END_PLUS, TABLE_4DP, "M, +β");
    assert_degrees(&degrees(paper(&end, "−β")), &END_MINUS, TABLE_4DP, "M, −β");
    // Notes 003 §3.7/§6.2: a Newton search finds 8 solutions at P and 4 at M (at M the
    // flipped-wrist branches have r2 > 700 mm). The wrist label is relative to each
    // solution's own w = z1, so for the shoulder `−w` the paper's e5 geometry (B = C − λ5·e5)
    // is the branch labelled `−e5`.
    assert_eq!(start.solutions.len(), 8);
    let mut labels: Vec<String> = end.solutions.iter().map(|s| s.branch.to_string()).collect();
    labels.sort();
    assert_eq!(
        labels,
        [
            "shoulder=w config=+β wrist=e5",
            "shoulder=w config=−β wrist=e5",
            "shoulder=−w config=+β wrist=−e5",
            "shoulder=−w config=−β wrist=−e5",
        ]
    );
    // Either shoulder: wrist `e5` ⟺ θ5 ∈ [−180°, 0°] (the paper's choice, notes 003 §3.4).
    for s in start.solutions.iter().chain(&end.solutions) {
        assert_eq!(s.branch.get("wrist") == Some("e5"), s.q[4] <= 0.0, "{}", s.branch);
    }
    // The shoulder flip is θ1 − 180° (notes 003 §6.2 item 4).
    let flip = branch(&start, "−w", "+β", "e5");
    assert_degrees(&[flip.q[0].to_degrees()], &[105.2482 - 180.0], TABLE_4DP, "P, −w");
    // "+β" is the default and feasible; the solution set has no failure.
    assert!(start.failure.is_none() && end.failure.is_none());
}

#[test]
fn intermediate_quantities_of_section_5_3() {
    // r2 = |OB| and Δ = cos β of the paper's branch (notes 003 §5.3).
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let length = (Vector3::from(M_MM) - Vector3::from(P_MM)).norm();
    for (s, r2_mm, delta, beta_deg) in
        [(0.0, 651.577188, 0.948761, 18.420861), (length, 550.599706, 0.847167, 32.095111)]
    {
        let m = solver.measures(&robot, &weld_pose(s), &IkOptions::default()).unwrap();
        let arm = m.paper().unwrap();
        assert!((arm.r2 * 1000.0 - r2_mm).abs() < 1e-6, "r2 = {}", arm.r2 * 1000.0);
        assert!((arm.delta - delta).abs() < 1e-6, "Δ = {}", arm.delta);
        assert!((arm.beta().unwrap().to_degrees() - beta_deg).abs() < 1e-6);
        // The path is far from the shoulder and wrist singularities (notes 003 §3.6).
        assert!(m.shoulder_margin() > 0.26 && arm.wrist_sine > 0.4);
        assert_eq!(m.lateral_offset, 0.0);
    }
    // ρ of C at P: C = (−165.891885, 608.557778, 36.628809) mm.
    let m = solver.measures(&robot, &weld_pose(0.0), &IkOptions::default()).unwrap();
    assert!((m.column_distance * 1000.0 - 165.891885f64.hypot(608.557778)).abs() < 1e-5);
    // At M the flipped wrist is out of reach: r2 > 700 mm, |Δ| > 1.
    let m = solver.measures(&robot, &weld_pose(length), &IkOptions::default()).unwrap();
    let flipped = m.arm(Shoulder::W, Wrist::MinusE5).unwrap();
    assert!(flipped.r2 > 0.7 && flipped.delta > 1.0 && flipped.beta().is_none() && flipped.elbow_margin() < 0.0);
}

// ---------------------------------------------------------------------------------------------
// Notes 003 §5.4: the angle tables along the path (3 decimals).
// ---------------------------------------------------------------------------------------------

/// s [mm], Δ, r2 [mm], β [deg], θ1…θ6 [deg] of "+β".
const PLUS_TABLE: [[f64; 10]; 20] = [
    [0.000, 0.948761, 651.577, 18.421, 105.248, -32.942, 43.339, -169.602, -155.443, 138.131],
    [50.000, 0.907045, 611.086, 24.900, 103.763, -37.183, 59.051, -158.132, -153.958, 138.131],
    [100.000, 0.868071, 572.101, 29.765, 102.102, -39.489, 71.211, -148.278, -152.296, 138.131],
    [150.000, 0.832256, 534.951, 33.669, 100.235, -40.460, 81.331, -139.129, -150.429, 138.131],
    [200.000, 0.800042, 500.046, 36.866, 98.125, -40.292, 89.989, -130.303, -148.319, 138.131],
    [250.000, 0.771871, 467.889, 39.478, 95.730, -39.051, 97.441, -121.610, -145.924, 138.131],
    [300.000, 0.748132, 439.082, 41.571, 92.997, -36.756, 103.790, -112.966, -143.191, 138.131],
    [350.000, 0.729094, 414.327, 43.189, 89.865, -33.431, 109.050, -104.381, -140.059, 138.131],
    [400.000, 0.714846, 394.386, 44.369, 86.263, -29.140, 113.178, -95.962, -136.458, 138.131],
    [450.000, 0.705275, 380.018, 45.148, 82.114, -24.022, 116.100, -87.921, -132.308, 138.131],
    [500.000, 0.700134, 371.869, 45.562, 77.335, -18.300, 117.741, -80.559, -127.530, 138.131],
    [550.000, 0.699201, 370.352, 45.637, 71.857, -12.267, 118.045, -74.222, -122.051, 138.131],
    [600.000, 0.702426, 375.545, 45.378, 65.636, -6.232, 117.002, -69.229, -115.831, 138.131],
    [650.000, 0.709967, 387.178, 44.768, 58.689, -0.459, 114.649, -65.810, -108.883, 138.131],
    [700.000, 0.722083, 404.698, 43.773, 51.116, 4.882, 111.054, -64.064, -101.311, 138.131],
    [750.000, 0.738961, 427.380, 42.357, 43.124, 9.734, 106.297, -63.970, -93.318, 138.131],
    [800.000, 0.760605, 454.453, 40.482, 35.001, 14.146, 100.436, -65.418, -85.195, 138.131],
    [850.000, 0.786821, 485.181, 38.111, 27.066, 18.251, 93.487, -68.261, -77.260, 138.131],
    [900.000, 0.817266, 518.916, 35.188, 19.596, 22.242, 85.394, -72.364, -69.790, 138.131],
    [943.928, 0.847167, 550.600, 32.095, 13.567, 25.845, 77.203, -76.952, -63.761, 138.131],
];

/// s [mm], θ1…θ6 [deg] of "−β" (θ4 outside [−175°, 150°] for s = 650…850).
const MINUS_TABLE: [[f64; 7]; 20] = [
    [0.000, 105.248, 3.900, -43.339, 140.561, -155.443, 138.131],
    [50.000, 103.763, 12.617, -59.051, 133.566, -153.958, 138.131],
    [100.000, 102.102, 20.041, -71.211, 128.830, -152.296, 138.131],
    [150.000, 100.235, 26.878, -81.331, 125.547, -150.429, 138.131],
    [200.000, 98.125, 33.439, -89.989, 123.451, -148.319, 138.131],
    [250.000, 95.730, 39.905, -97.441, 122.464, -145.924, 138.131],
    [300.000, 92.997, 46.386, -103.790, 122.596, -143.191, 138.131],
    [350.000, 89.865, 52.948, -109.050, 123.898, -140.059, 138.131],
    [400.000, 86.263, 59.599, -113.178, 126.421, -136.458, 138.131],
    [450.000, 82.114, 66.275, -116.100, 130.175, -132.308, 138.131],
    [500.000, 77.335, 72.825, -117.741, 135.084, -127.530, 138.131],
    [550.000, 71.857, 79.007, -118.045, 140.962, -122.051, 138.131],
    [600.000, 65.636, 84.525, -117.002, 147.522, -115.831, 138.131],
    [650.000, 58.689, 89.077, -114.649, 154.428, -108.883, 138.131],
    [700.000, 51.116, 92.428, -111.054, 161.374, -101.311, 138.131],
    [750.000, 43.124, 94.448, -106.297, 168.151, -93.318, 138.131],
    [800.000, 35.001, 95.111, -100.436, 174.675, -85.195, 138.131],
    [850.000, 27.066, 94.472, -93.487, -179.015, -77.260, 138.131],
    [900.000, 19.596, 92.618, -85.394, -172.775, -69.790, 138.131],
    [943.928, 13.567, 90.035, -77.203, -167.168, -63.761, 138.131],
];

/// Half a unit in the 3rd decimal plus round-off.
const TABLE_3DP: f64 = 1e-3;

#[test]
fn path_tables_of_section_5_4() {
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    for row in PLUS_TABLE {
        let s = row[0];
        let all = solve(&robot, weld_pose(s), &IkOptions::default());
        assert_degrees(&degrees(paper(&all, "+β")), &row[4..], TABLE_3DP, &format!("+β at s = {s}"));
        let m = solver.measures(&robot, &weld_pose(s), &IkOptions::default()).unwrap();
        let arm = m.paper().unwrap();
        assert!((arm.delta - row[1]).abs() < 1e-6, "Δ at s = {s}: {}", arm.delta);
        assert!((arm.r2 * 1000.0 - row[2]).abs() < 1e-3, "r2 at s = {s}");
        assert!((arm.beta().unwrap().to_degrees() - row[3]).abs() < TABLE_3DP, "β at s = {s}");
        // "+β" is within every limit on the whole path (notes 003 §5.5).
        assert!(paper(&all, "+β").within_limits, "+β at s = {s}");
    }
    for row in MINUS_TABLE {
        let s = row[0];
        let all = solve(&robot, weld_pose(s), &IkOptions::default());
        let minus = paper(&all, "−β");
        assert_degrees(&degrees(minus), &row[1..], TABLE_3DP, &format!("−β at s = {s}"));
        // The bold entries of the table: θ4 outside [−175°, 150°], and only θ4.
        let outside = (650.0..=850.0).contains(&s);
        assert_eq!(!minus.within_limits, outside, "−β limits at s = {s}");
        if outside {
            assert_eq!(minus.violations.len(), 1);
            assert_eq!(minus.violations[0].joint, 4);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Notes 003 §5.5: events and invariants along the path.
// ---------------------------------------------------------------------------------------------

fn minus_beta_theta4(s: f64) -> (f64, bool) {
    let all = solve(&welder(), weld_pose(s), &IkOptions::default());
    let m = paper(&all, "−β");
    (m.q[3].to_degrees(), m.within_limits)
}

#[test]
fn minus_beta_leaves_the_theta4_range_between_618_10_and_882_21_mm() {
    // θ4 exceeds 150° from s = 618.10 mm ...
    let (t, ok) = minus_beta_theta4(618.05);
    assert!(ok && t < 150.0, "{t}");
    let (t, ok) = minus_beta_theta4(618.15);
    assert!(!ok && t > 150.0, "{t}");
    // ... wraps from +180° to −180° at s = 842.12 mm (the paper's "large jump on a short
    // final section", notes 003 §5.1 item 1) ...
    let (before, _) = minus_beta_theta4(842.10);
    let (after, _) = minus_beta_theta4(842.14);
    assert!(before > 179.99 && after < -179.99, "{before} → {after}");
    // ... and is below −175° until s = 882.21 mm.
    let (t, ok) = minus_beta_theta4(882.16);
    assert!(!ok && t < -175.0, "{t}");
    let (t, ok) = minus_beta_theta4(882.26);
    assert!(ok && t > -175.0, "{t}");
}

#[test]
fn whole_path_events_and_invariants() {
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let length = (Vector3::from(M_MM) - Vector3::from(P_MM)).norm();
    let steps = 1000;
    let (mut delta_min, mut s_at_min) = (f64::INFINITY, 0.0);
    let (mut theta3_max, mut s_theta3) = (f64::NEG_INFINITY, 0.0);
    for k in 0..=steps {
        let s = length * f64::from(k) / f64::from(steps);
        let all = solve(&robot, weld_pose(s), &IkOptions::default());
        assert!(all.failure.is_none(), "s = {s}");
        let plus = paper(&all, "+β");
        let minus = paper(&all, "−β");
        assert!(plus.within_limits, "+β feasible on the whole path, s = {s}");
        assert!(plus.singularities.is_empty() && minus.singularities.is_empty());
        let (p, m) = (degrees(plus), degrees(minus));
        // θ1 + θ5 = −50.1944°, θ6 = 138.1315°; θ1, θ5, θ6 shared; θ3(−β) = −θ3(+β);
        // θ2 + θ3 − θ4 ≡ 180° (mod 360°) in both configurations (e5 = k).
        assert_degrees(&[p[0] + p[4], p[5]], &[-50.1944, 138.1315], 1e-4, &format!("invariants at s = {s}"));
        assert_degrees(&[m[0], m[4], m[5], -m[2]], &[p[0], p[4], p[5], p[2]], 1e-9, "shared angles");
        assert_degrees(&[p[1] + p[2] - p[3], m[1] + m[2] - m[3]], &[180.0, 180.0], 1e-9, "θ2 + θ3 − θ4");
        // The paper's wrist branch: θ5 ∈ [−180°, 0°].
        assert!(p[4] <= 0.0);
        // −β: every angle but θ4 within limits (θ2 ∈ [3.900, 95.111], notes 003 §5.5).
        assert!(minus.violations.iter().all(|v| v.joint == 4));
        if p[2] > theta3_max {
            (theta3_max, s_theta3) = (p[2], s);
        }
        let arm = *solver.measures(&robot, &weld_pose(s), &IkOptions::default()).unwrap().paper().unwrap();
        if arm.delta < delta_min {
            (delta_min, s_at_min) = (arm.delta, s);
        }
        // No singular position on the path: Δ stays well inside (−1, 1).
        assert!(arm.elbow_margin() > 0.05);
    }
    // Δ_min = 0.699046 at s = 536.245 mm; θ3 max 118.096° at s = 536.25 mm (a near miss of 120°).
    // The 0.944 mm sampling is refined by the flat minimum: |Δ'' · (0.47 mm)²| < 1e-6.
    assert!((delta_min - 0.699046).abs() < 2e-6 && (s_at_min - 536.245).abs() < 1.0, "{delta_min} at {s_at_min}");
    assert!((theta3_max - 118.096).abs() < 2e-3 && (s_theta3 - 536.25).abs() < 1.0, "{theta3_max} at {s_theta3}");
}

// ---------------------------------------------------------------------------------------------
// The table-consistent convention (notes 003 §2.6, §5.3): α3 = 0 as printed.
// ---------------------------------------------------------------------------------------------

#[test]
fn table_convention_values_of_section_5_3() {
    let robot = welder_table();
    let length = (Vector3::from(M_MM) - Vector3::from(P_MM)).norm();
    // θ4 and θ5 of the notes (3 decimals); the other angles are the paper convention's.
    for (s, plus4, minus4, theta5) in [(0.0, -10.398, 39.439, 24.557), (length, -103.048, -12.832, 116.239)] {
        let all = solve(&robot, weld_pose(s), &IkOptions::default());
        let (p, m) = (degrees(paper(&all, "+β")), degrees(paper(&all, "−β")));
        assert_degrees(&[p[3], m[3], p[4], m[4]], &[plus4, minus4, theta5, theta5], TABLE_3DP, &format!("s = {s}"));
        // Both configurations are inside every limit here (why the notes reject this reading).
        assert!(paper(&all, "+β").within_limits && paper(&all, "−β").within_limits);
    }
    // The mapping θ4' = −180° − θ4, θ5' = θ5 + 180° on every row of the §5.4 tables.
    let paper_robot = welder();
    for row in PLUS_TABLE {
        let a = solve(&paper_robot, weld_pose(row[0]), &IkOptions::default());
        let b = solve(&robot, weld_pose(row[0]), &IkOptions::default());
        for config in ["+β", "−β"] {
            let (pa, tb) = (degrees(paper(&a, config)), degrees(paper(&b, config)));
            let mapped = [pa[0], pa[1], pa[2], -180.0 - pa[3], pa[4] + 180.0, pa[5]];
            assert_degrees(&tb, &mapped, 1e-9, &format!("mapping at s = {}", row[0]));
        }
    }
}

// ---------------------------------------------------------------------------------------------
// Unreachable and singular targets.
// ---------------------------------------------------------------------------------------------

/// A tool pose from its axes (columns x, y, z) and position, metres.
fn pose(x: [f64; 3], y: [f64; 3], z: [f64; 3], p: [f64; 3]) -> Isometry3<f64> {
    let m = Matrix3::from_columns(&[Vector3::from(x), Vector3::from(y), Vector3::from(z)]);
    Isometry3::from_parts(Translation3::from(Vector3::from(p)), UnitQuaternion::from_matrix(&m))
}

#[test]
fn too_far_is_unreachable_with_the_nearest_branch_distance() {
    // n = x, e6 = z, l = −y; C = P − 0.05 n − 0.25 e6 = (1.0, 0, 0.3). Every branch has
    // e5 = ±x, so B = C ± 0.2 x: r2 = |(1.2, 0, 0.3)| or |(0.8, 0, 0.3)| = 0.854400 m > 0.7 m.
    let robot = welder();
    let target = pose([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.05, 0.0, 0.55]);
    let all = solve(&robot, target, &IkOptions::default());
    assert!(all.solutions.is_empty());
    match all.failure {
        Some(IkFailure::Unreachable { distance, reach, .. }) => {
            assert!((distance - 0.73f64.sqrt()).abs() < 1e-12, "{distance}");
            assert!((reach - 0.7).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn too_close_to_the_column_is_unreachable_for_the_ur5() {
    // UR5: the arm plane is offset D = d4 = 0.10915 m from the column axis, so the wrist
    // point C (= P − d6 z6) must be at least that far from it.
    let robot = presets::get("ur5").unwrap();
    let target = pose([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.05, 0.0, 0.3 + 0.0823]);
    let all = solve(&robot, target, &IkOptions::default());
    match all.failure {
        Some(IkFailure::Unreachable { distance, reach, .. }) => {
            assert!((distance - 0.05).abs() < 1e-12 && (reach - 0.10915).abs() < 1e-12, "{distance} {reach}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn the_outer_reach_boundary_is_r2_700_mm() {
    // C on the x axis at 0.65 m with e5 = ±z (e6 = x ⟂ w = −y):
    // B = C ∓ 0.2 z gives r2 = |(0.65, 0, ∓0.2)| = 0.68007 < 0.7 for both wrists, and the
    // shoulder flip sees the same distances: all 8 reachable. Moving C to 0.69 m puts
    // r2 = 0.7183 > 0.7 — out of reach for every branch.
    let robot = welder();
    // e6 = y6 = x, n = x6 = z, l = z6 = x6 × y6 = z × x = y.
    let at = |cx: f64| pose([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [cx + 0.25, 0.0, 0.05]);
    let near = solve(&robot, at(0.65), &IkOptions::default());
    assert_eq!(near.solutions.len(), 8);
    let far = solve(&robot, at(0.69), &IkOptions::default());
    assert!(far.solutions.is_empty());
    assert!(matches!(far.failure, Some(IkFailure::Unreachable { reach, .. }) if (reach - 0.7).abs() < 1e-12));
}

#[test]
fn stretched_and_folded_elbow_are_flagged_and_merge_the_configurations() {
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    // θ3 = 0: links 2 and 3 in line, r2 = 700 mm, Δ = 1 (notes 003 §3.6).
    for q in [[0.3, 0.2, 0.0, -0.5, -0.9, 0.4], [1.0, -0.3, PI, 0.5, -1.2, 0.4]] {
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target, &IkOptions::default());
        let found = all.solutions.iter().find(|s| close(&s.q, &q, 1e-7)).expect("q among the solutions");
        assert!(found.singularities.contains(&SingularityKind::Elbow), "{found:?}");
        // "+β" and "−β" of that arm are one solution (merged by the duplicate check).
        let (sh, wr) = (found.branch.get("shoulder").unwrap(), found.branch.get("wrist").unwrap());
        let same_arm = all
            .solutions
            .iter()
            .filter(|s| s.branch.get("shoulder") == Some(sh) && s.branch.get("wrist") == Some(wr))
            .count();
        assert_eq!(same_arm, 1);
        let m = solver.measures(&robot, &target, &IkOptions::default()).unwrap();
        let arm = m.arm(
            if sh == "w" { Shoulder::W } else { Shoulder::MinusW },
            if wr == "e5" { Wrist::E5 } else { Wrist::MinusE5 },
        );
        let arm = arm.unwrap();
        assert!(arm.elbow_margin().abs() < 1e-12 && (arm.delta - 1.0).abs() < 1e-12, "{arm:?}");
        let r2 = if q[2] == 0.0 { 0.7 } else { 0.1 };
        assert!((arm.r2 - r2).abs() < 1e-12);
    }
}

#[test]
fn folded_arm_with_equal_links_keeps_the_seed_theta2() {
    // With l2 = l3 the folded arm puts the elbow-triangle apex on the shoulder axis (r2 = 0):
    // θ2 is undetermined. Here Δ = r2/(2·l2) → 0, so the paper's |Δ| = 1 test misses this
    // singularity; the cosine of the elbow angle (−1) catches it.
    let mut spec = welder().spec().clone();
    if let JointGeometry::Dh(p) = &mut spec.joints[2].geometry {
        p.a = 0.4;
    }
    let robot = Robot::new(spec).unwrap();
    let q = [0.3, 0.5, PI, -1.0, -0.8, 0.4];
    let target = robot.fk(&q).unwrap();
    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let all = solve(&robot, target, &options);
    let found = all.solutions.iter().find(|s| close(&s.q, &q, 1e-9)).expect("q among the solutions");
    assert!(found.singularities.contains(&SingularityKind::Elbow));
    let m = ParallelAxes::from_robot(&robot).unwrap().measures(&robot, &target, &options).unwrap();
    let arm = m.arms.iter().flatten().find(|a| a.r2 < 1e-12).expect("an arm with r2 = 0");
    assert!(arm.delta.abs() < 1e-9 && (arm.cos_elbow + 1.0).abs() < 1e-12 && arm.elbow_margin().abs() < 1e-12);
}

#[test]
fn wrist_point_on_the_column_axis_keeps_the_seed_theta1() {
    // C = (0, 0, 0.5): n = x, e6 = y6 = z, l = x × z = −y; P = C + 0.05 n + 0.25 e6.
    let robot = welder();
    let target = pose([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.05, 0.0, 0.75]);
    for (seed_q1, expected_q1) in [(Some(0.7), 0.7), (None, 0.0)] {
        let options = IkOptions { seed: seed_q1.map(|v| vec![v, 0.0, 0.0, 0.0, 0.0, 0.0]), ..IkOptions::default() };
        let all = solve(&robot, target, &options);
        assert_eq!(all.solutions.len(), 8);
        for s in &all.solutions {
            assert!(s.singularities.contains(&SingularityKind::Shoulder));
            let expected = if s.branch.get("shoulder") == Some("w") { expected_q1 } else { expected_q1 + PI };
            assert!(reach::angle::wrap(s.q[0] - expected).abs() < 1e-12, "{:?}", s.q);
        }
        let m = ParallelAxes::from_robot(&robot).unwrap().measures(&robot, &target, &options).unwrap();
        assert!(m.column_distance < 1e-12 && m.shoulder_margin() < 1e-12);
    }
}

#[test]
fn axis_6_parallel_to_w_keeps_the_seed_theta6() {
    // θ5 = 0 puts e6 ∥ w for the welder (notes 003 §3.4: θ5 ∈ {0°, ±180°} is the wrist singularity).
    let robot = welder();
    let q = [0.3, 0.2, 0.9, -1.0, 0.0, 0.4];
    let target = robot.fk(&q).unwrap();
    let m = ParallelAxes::from_robot(&robot).unwrap().measures(&robot, &target, &IkOptions::default()).unwrap();
    assert!(m.paper().unwrap().wrist_sine < 1e-12);
    // With the seed: the solutions keep θ6 = 0.4 (wrist e5) or 0.4 + π (−e5), and q is among them.
    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let all = solve(&robot, target, &options);
    assert!(all.solutions.iter().any(|s| close(&s.q, &q, 1e-9)), "{:#?}", all.solutions);
    for s in &all.solutions {
        assert!(s.singularities.contains(&SingularityKind::Wrist));
        let expected = if s.branch.get("wrist") == Some("e5") { 0.4 } else { 0.4 + PI };
        assert!(reach::angle::wrap(s.q[5] - expected).abs() < 1e-9);
    }
    // Without a seed θ6 = 0 or π, and the pose is still reached (finish checks it by FK).
    let all = solve(&robot, target, &IkOptions::default());
    assert!(!all.solutions.is_empty());
    assert!(all.solutions.iter().all(|s| s.q[5].abs() < 1e-9 || (s.q[5].abs() - PI).abs() < 1e-9));
}

#[test]
fn ur5_shoulder_singularity_merges_the_shoulder_roots() {
    // With a lateral offset D = d4 the shoulder is singular at ρ = |D|: the roots
    // θ1 = φ + asin(D/ρ) and φ + π − asin(D/ρ) coincide. C = (0.10915, 0, 0.3), z6 = z.
    let robot = presets::get("ur5").unwrap();
    let target = pose([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.10915, 0.0, 0.3 + 0.0823]);
    let all = solve(&robot, target, &IkOptions::default());
    assert!(!all.solutions.is_empty());
    let q1 = all.solutions[0].q[0];
    for s in &all.solutions {
        assert!(s.singularities.contains(&SingularityKind::Shoulder), "{s:?}");
        assert!((s.q[0] - q1).abs() < 1e-9);
    }
    // sin(θ1 − φ) = D/ρ = 1 with φ = 0: θ1 = 90°.
    assert!((q1 - PI / 2.0).abs() < 1e-9, "{q1}");
    let m = ParallelAxes::from_robot(&robot).unwrap().measures(&robot, &target, &IkOptions::default()).unwrap();
    assert!(m.shoulder_margin().abs() < 1e-12 && (m.lateral_offset - 0.10915).abs() < 1e-15);
}

/// The number of solutions `measures` predicts: two per reachable (shoulder, wrist) arm
/// (reachable: 1 − |cos θ_elbow| ≥ −BOUNDARY, the solver's clamping tolerance).
fn predicted_count(robot: &Robot, target: &Isometry3<f64>, options: &IkOptions) -> usize {
    let m = ParallelAxes::from_robot(robot).unwrap().measures(robot, target, options).unwrap();
    m.arms.iter().flatten().filter(|a| a.elbow_margin() >= -reach::tolerance::BOUNDARY).count() * 2
}

#[test]
fn near_singular_targets_keep_every_branch() {
    // Just above and below the singularity tolerances every branch must survive the FK check
    // (`finish` silently drops a candidate that misses the pose), and q must come back.
    let robot = welder();
    for eps in [1e-4, 1e-6, 1e-8, 1e-10, 1e-12] {
        // Wrist: θ5 = ε (sin∠(w, e6) = ε). Seeded with q, so the singular branch keeps θ6.
        let q = [0.3, 0.2, 0.9, -1.0, eps, 0.4];
        let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target, &options);
        assert_eq!(all.solutions.len(), predicted_count(&robot, &target, &options), "wrist ε = {eps}");
        assert!(all.solutions.len() >= 4);
        assert!(all.solutions.iter().any(|s| close(&s.q, &q, 1e-6)), "wrist ε = {eps}: {:#?}", all.solutions);
        // Elbow: θ3 = ε; the two configurations merge once 1 − |Δ| < BOUNDARY (|θ3| < 4.5e-5).
        let q = [0.3, 0.2, eps, -1.0, -0.8, 0.4];
        let target = robot.fk(&q).unwrap();
        let all = solve(&robot, target, &IkOptions::default());
        let predicted = predicted_count(&robot, &target, &IkOptions::default());
        let merged = all.solutions.iter().filter(|s| s.singularities.contains(&SingularityKind::Elbow)).count();
        assert_eq!(all.solutions.len() + merged, predicted, "elbow ε = {eps}");
        assert_eq!(merged > 0, eps < 4.5e-5, "elbow ε = {eps}");
        assert!(all.solutions.iter().any(|s| close(&s.q, &q, 1e-4)), "elbow ε = {eps}");
    }
    // Shoulder: C at distance ε from the column axis (n = x, e6 = z, l = −y as above).
    for eps in [1e-6, 1e-8, 1e-10, 1e-12] {
        let target = pose([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [0.05 + eps, 0.0, 0.75]);
        let all = solve(&robot, target, &IkOptions::default());
        assert_eq!(all.solutions.len(), 8, "shoulder ε = {eps}");
        assert_eq!(all.solutions.iter().all(|s| s.singularities.contains(&SingularityKind::Shoulder)), eps <= 1e-9);
    }
}

// ---------------------------------------------------------------------------------------------
// Limits, position-only targets, detection.
// ---------------------------------------------------------------------------------------------

#[test]
fn all_solutions_outside_limits_report_outside_limits() {
    // θ6 of the weld is 138.13° (wrist e5) or −41.87° (−e5): a joint 6 limited to ±30° rejects both.
    let mut spec = welder().spec().clone();
    spec.joints[5].limits = reach::model::Limits::new(-30f64.to_radians(), 30f64.to_radians());
    let robot = Robot::new(spec).unwrap();
    let all = solve(&robot, weld_pose(0.0), &IkOptions::default());
    assert_eq!(all.solutions.len(), 8);
    assert!(all.solutions.iter().all(|s| s.violations.iter().any(|v| v.joint == 6)));
    assert!(matches!(all.failure, Some(IkFailure::OutsideLimits { .. })), "{:?}", all.failure);
}

#[test]
fn position_target_keeps_the_seed_orientation() {
    let robot = welder();
    let q = [0.3, 0.2, 0.9, -1.0, -0.8, 0.4];
    let p = robot.fk(&q).unwrap().translation.vector;
    let options = IkOptions { seed: Some(q.to_vec()), ..IkOptions::default() };
    let all = ParallelAxes::from_robot(&robot).unwrap().solve(&robot, &IkTarget::Position(p.into()), &options).unwrap();
    assert!(all.solutions.iter().any(|s| close(&s.q, &q, 1e-9)));
}

#[test]
fn detected_for_the_family_and_rejects_bad_input() {
    assert_eq!(SolverKind::detect(&welder()), SolverKind::ParallelAxes);
    assert_eq!(SolverKind::detect(&welder_table()), SolverKind::ParallelAxes);
    // The UR5 is the same family (the spherical-wrist solver must not claim it).
    assert_eq!(SolverKind::detect(&presets::get("ur5").unwrap()), SolverKind::ParallelAxes);
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let nan = IkTarget::Position(nalgebra::Point3::new(f64::NAN, 0.0, 0.0));
    assert!(solver.solve(&robot, &nan, &IkOptions::default()).is_err());
    let bad_seed = IkOptions { seed: Some(vec![0.0; 5]), ..IkOptions::default() };
    assert!(solver.solve(&robot, &IkTarget::Pose(weld_pose(0.0)), &bad_seed).is_err());
}

// ---------------------------------------------------------------------------------------------
// UR5: the same family with a lateral offset, against the Robotics Toolbox reference poses.
// ---------------------------------------------------------------------------------------------

#[test]
fn ur5_reference_poses_give_back_their_joint_vectors() {
    // tests/data/reference/ur5.json: 100 (q, T) pairs computed by the Robotics Toolbox for
    // Python from its own UR5 table (d1 = 0.089459). T is the target; q must be a solution.
    let doc: serde_json::Value = serde_json::from_str(include_str!("../data/reference/ur5.json")).unwrap();
    let joints: Vec<Joint> = doc["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let f = |k: &str| j[k].as_f64().unwrap();
            Joint::revolute(f("a_m"), f("alpha_rad"), f("d_m"), f("theta_offset_rad"))
        })
        .collect();
    let robot = Robot::new(RobotSpec::new("ur5-rtb", Convention::Dh, joints)).unwrap();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let mut eight = 0;
    for case in doc["cases"].as_array().unwrap() {
        let q: Vec<f64> = case["q_rad"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let rows: Vec<Vec<f64>> = case["T"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r.as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect())
            .collect();
        let t = Matrix4::from_fn(|i, j| rows[i][j]);
        let rot = Rotation3::from_matrix(&t.fixed_view::<3, 3>(0, 0).into_owned());
        let target = Isometry3::from_parts(
            Translation3::new(t[(0, 3)], t[(1, 3)], t[(2, 3)]),
            UnitQuaternion::from_rotation_matrix(&rot),
        );
        let all = solver.solve(&robot, &IkTarget::Pose(target), &IkOptions::default()).unwrap();
        assert!(all.solutions.iter().any(|s| close(&s.q, &q, 1e-7)), "q = {q:?} not in {:#?}", all.solutions);
        if all.solutions.len() == 8 {
            eight += 1;
        }
    }
    assert!(eight > 50, "most UR5 poses have 8 solutions, got {eight}/100");
}

// ---------------------------------------------------------------------------------------------
// Round trips: FK ∘ IK over random joint vectors, for every supported variation.
// ---------------------------------------------------------------------------------------------

/// Every angle equal modulo 2π within `tolerance`.
fn close(a: &[f64], b: &[f64], tolerance: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| {
        let d = (x - y).rem_euclid(TAU);
        d.min(TAU - d) < tolerance
    })
}

/// A member of the family with every supported offset: d1, a1, d2…d4 (lateral offset), a4,
/// a6, α6 ≠ 90°, θ offsets, flipped joints, negative α1, α2 = 180°, base and tool transforms.
fn general_robot() -> Robot {
    let deg = f64::to_radians;
    let mut joints = vec![
        Joint::revolute(0.08, deg(-90.0), 0.35, deg(10.0)),
        Joint::revolute(0.45, deg(180.0), 0.06, deg(-20.0)),
        Joint::revolute(-0.38, deg(0.0), -0.02, deg(5.0)),
        Joint::revolute(0.04, deg(90.0), 0.03, deg(30.0)),
        Joint::revolute(0.0, deg(-90.0), 0.12, deg(0.0)),
        Joint::revolute(0.03, deg(35.0), 0.09, deg(-45.0)),
    ];
    joints[1].flip = true;
    joints[4].flip = true;
    let mut spec = RobotSpec::new("general-rerr", Convention::Dh, joints);
    spec.base = Isometry3::new(Vector3::new(0.1, -0.2, 0.3), Vector3::new(0.1, 0.2, -0.3));
    spec.tool = Isometry3::new(Vector3::new(0.01, 0.02, 0.15), Vector3::new(-0.2, 0.1, 0.05));
    Robot::new(spec).unwrap()
}

fn robots() -> Vec<Robot> {
    vec![welder(), welder_table(), presets::get("ur5").unwrap(), general_robot()]
}

/// Whether q is away from the three singularities (the original q is then a distinct branch).
fn regular(robot: &Robot, q: &[f64]) -> bool {
    let target = robot.fk(q).unwrap();
    let solver = ParallelAxes::from_robot(robot).unwrap();
    let m = solver.measures(robot, &target, &IkOptions::default()).unwrap();
    m.shoulder_margin() > 1e-6 && m.arms.iter().flatten().all(|a| a.wrist_sine > 1e-6 && a.elbow_margin().abs() > 1e-9)
}

/// Round trip of one q: (q found, solution count, max position error, max orientation error).
fn round_trip(robot: &Robot, q: &[f64]) -> (bool, usize, f64, f64) {
    let target = robot.fk(q).unwrap();
    let all = solve(robot, target, &IkOptions::default());
    let (mut dp, mut dr) = (0.0f64, 0.0f64);
    for s in &all.solutions {
        let t = robot.fk(&s.q).unwrap();
        dp = dp.max((t.translation.vector - target.translation.vector).norm());
        dr = dr.max(t.rotation.angle_to(&target.rotation));
    }
    (all.solutions.iter().any(|s| close(&s.q, q, 1e-7)), all.solutions.len(), dp, dr)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn fk_ik_round_trip(which in 0usize..4, q in prop::array::uniform6(-PI..PI)) {
        let robot = &robots()[which];
        let (found, count, dp, dr) = round_trip(robot, &q);
        prop_assert!(dp < 1e-9 && dr < 1e-9, "{}: errors {dp:e} m {dr:e} rad", robot.name());
        prop_assert!((1..=8).contains(&count));
        if regular(robot, &q) {
            prop_assert!(found, "{}: q = {q:?} not among the solutions", robot.name());
        }
    }
}

/// A deterministic sweep: success rate and worst errors over many random joint vectors
/// (printed with `--nocapture`; the numbers go into the report).
#[test]
fn round_trip_sweep() {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for robot in robots() {
        let n: u32 = 5000;
        let (mut ok, mut singular, mut dp_max, mut dr_max, mut solutions) = (0, 0, 0.0f64, 0.0f64, 0usize);
        for _ in 0..n {
            let q: Vec<f64> = (0..6).map(|_| (2.0 * uniform() - 1.0) * PI).collect();
            let (found, count, dp, dr) = round_trip(&robot, &q);
            assert!(found || !regular(&robot, &q), "{}: q = {q:?}", robot.name());
            ok += usize::from(found);
            singular += usize::from(!regular(&robot, &q));
            solutions += count;
            dp_max = dp_max.max(dp);
            dr_max = dr_max.max(dr);
        }
        eprintln!(
            "{}: q recovered {ok}/{n} ({singular} within the singularity tolerances), mean {:.2} solutions, \
             max position error {dp_max:.2e} m, max orientation error {dr_max:.2e} rad",
            robot.name(),
            solutions as f64 / f64::from(n)
        );
        // A q within the clamping tolerance of a singularity (e.g. |θ3| < 4.5e-5 rad, where
        // 1 − |Δ| < BOUNDARY) comes back as the merged singular solution instead.
        assert!(ok + singular >= n as usize);
        assert!(dp_max < 1e-9 && dr_max < 1e-9);
    }
}
