//! Seed 003 (Knapczyk & Kisiel 1987), notes 003 §5.3: the `welder6r` preset reproduces the
//! test vectors at the end points of the welding path.
//!
//! The notes give, for the start point P and the end point M of the weld, the joint angles of
//! both configurations ("+β" and "−β") in the paper's sign convention (notes 003 §2.6:
//! w = e2 = e3 = −e4). Forward kinematics of those angles must return the tool point and the
//! gripper axes: x₆ = n (along the weld line), z₆ = l (the gripper's orientation vector).
//! That convention is the standard-DH table α = (90, 0, **180**, −90, 90, 90)°,
//! a = (0, 400, 300, 0, 0, 50) mm, d = (0, 0, 0, 0, 200, 250) mm — Table 1 with α3 = 180°
//! instead of the printed 0° — which is what `robots/welder6r.toml` holds.

use crate::common::{WELD_M_MM as M_MM, WELD_P_MM as P_MM};
use nalgebra::Vector3;
use reach::Robot;
use reach::model::presets;

/// The angles are printed to 4 decimals (±0.00005° ≈ ±8.7e-7 rad per joint); with lever
/// arms below 1 m this moves the tool point by at most ~6·0.9 m·8.7e-7 ≈ 5e-6 m.
const POSITION_TOLERANCE_M: f64 = 1e-5; // 0.01 mm
/// n and l are printed to 6 decimals; the angle rounding adds < 6·8.7e-7 rad.
const AXIS_TOLERANCE: f64 = 1e-5;

/// Start point P = (50, 740, 70) mm and end point M = (500, 200, 700) mm (notes 003 §5.1).
/// n = (M − P)/|MP| and l (notes 003 §5.2); the orientation is constant along the path.
const N: [f64; 3] = [0.476731, -0.572078, 0.667424];
const L: [f64; 3] = [-0.427274, 0.512729, 0.744678];
/// e6 = l × n, the tool y axis (notes 003 §5.2).
const E6: [f64; 3] = [0.768221, 0.640184, 0.0];

/// Notes 003 §5.3, paper convention, degrees.
const START_PLUS_BETA: [f64; 6] = [105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315];
const START_MINUS_BETA: [f64; 6] = [105.2482, 3.9000, -43.3392, 140.5608, -155.4427, 138.1315];
const END_PLUS_BETA: [f64; 6] = [13.5666, 25.8448, 77.2028, -76.9524, -63.7610, 138.1315];
const END_MINUS_BETA: [f64; 6] = [13.5666, 90.0350, -77.2028, -167.1678, -63.7610, 138.1315];

fn radians(q_deg: [f64; 6]) -> Vec<f64> {
    q_deg.iter().map(|v| v.to_radians()).collect()
}

fn assert_pose(robot: &Robot, q_deg: [f64; 6], point_mm: [f64; 3], label: &str) {
    let t = robot.fk_matrix(&radians(q_deg)).unwrap();
    let p = t.translation.vector;
    let expected = Vector3::from(point_mm) * 1e-3;
    assert!(
        (p - expected).amax() < POSITION_TOLERANCE_M,
        "{label}: tool point {:?} mm, expected {point_mm:?} mm",
        (p * 1e3).as_slice()
    );
    let r = t.rotation.matrix();
    for (axis, column, name) in [(N, 0, "x = n"), (E6, 1, "y = e6"), (L, 2, "z = l")] {
        let got = r.column(column).into_owned();
        assert!(
            (got - Vector3::from(axis)).amax() < AXIS_TOLERANCE,
            "{label}: tool axis {name}: got {:?}, expected {axis:?}",
            got.as_slice()
        );
    }
}

/// notes 003 §5.3, start point P, configuration "+β".
#[test]
fn start_point_plus_beta() {
    let robot = presets::get("welder6r").unwrap();
    assert_pose(&robot, START_PLUS_BETA, P_MM, "P, +β");
}

/// notes 003 §5.3, start point P, configuration "−β": the same pose.
#[test]
fn start_point_minus_beta() {
    let robot = presets::get("welder6r").unwrap();
    assert_pose(&robot, START_MINUS_BETA, P_MM, "P, −β");
}

/// notes 003 §5.3, end point M, both configurations.
#[test]
fn end_point_both_configurations() {
    let robot = presets::get("welder6r").unwrap();
    assert_pose(&robot, END_PLUS_BETA, M_MM, "M, +β");
    assert_pose(&robot, END_MINUS_BETA, M_MM, "M, −β");
}

/// notes 003 §5.3: the "+β" start configuration's θ4 = −169.6° is inside its range
/// [−175°, 150°] (the paper: "+β" is feasible), and the "−β" one's θ4 = 140.6° too at P —
/// the paper's violation by "−β" happens later on the path.
#[test]
fn start_configurations_are_within_the_table_limits() {
    let robot = presets::get("welder6r").unwrap();
    for q in [START_PLUS_BETA, START_MINUS_BETA, END_PLUS_BETA, END_MINUS_BETA] {
        assert_eq!(robot.first_joint_outside_limits(&radians(q), 0.0), None, "{q:?}");
    }
}

/// Table 1 as printed (α3 = 0°) with the same angles does not reach P: this is why the
/// preset carries α3 = 180° (notes 003 §2.6).
#[test]
fn printed_table_with_alpha3_zero_does_not_reproduce_the_vectors() {
    let printed = Robot::from_toml_str(&table(0.0)).unwrap();
    let t = printed.fk_matrix(&radians(START_PLUS_BETA)).unwrap();
    let miss = (t.translation.vector - Vector3::from(P_MM) * 1e-3).norm();
    assert!(miss > 0.1, "printed table reaches P within {miss} m");
}

/// notes 003 §2.6 / §5.3: in the "table-consistent" convention (α3 = 0°, e2 = e3 = e4 = w) the
/// angles are the same except θ4ᵗ = −180° − θ4 and θ5ᵗ = θ5 + 180° (mod 360°); FK of the
/// printed table with those angles reaches the same pose.
#[test]
fn table_consistent_convention_reaches_the_same_pose_with_shifted_angles() {
    let printed = Robot::from_toml_str(&table(0.0)).unwrap();
    let preset_equivalent = Robot::from_toml_str(&table(180.0)).unwrap();
    for (q, point, label) in [
        (START_PLUS_BETA, P_MM, "P, +β"),
        (START_MINUS_BETA, P_MM, "P, −β"),
        (END_PLUS_BETA, M_MM, "M, +β"),
        (END_MINUS_BETA, M_MM, "M, −β"),
    ] {
        let mut shifted = q;
        shifted[3] = -180.0 - q[3];
        shifted[4] = q[4] + 180.0;
        assert_pose(&printed, shifted, point, label);
        assert_pose(&preset_equivalent, q, point, label);
    }
    // The notes' printed values of θ4ᵗ and θ5ᵗ (wrapped into (−180°, 180°]).
    let wrap = |deg: f64| reach::angle::wrap(deg.to_radians()).to_degrees();
    for (paper, table_consistent) in [
        (START_PLUS_BETA[3], -10.398),
        (START_MINUS_BETA[3], 39.439),
        (END_PLUS_BETA[3], -103.048),
        (END_MINUS_BETA[3], -12.832),
    ] {
        assert!((wrap(-180.0 - paper) - table_consistent).abs() < 1e-3, "θ4 = {paper}");
    }
    assert!((wrap(START_PLUS_BETA[4] + 180.0) - 24.557).abs() < 1e-3);
    assert!((wrap(END_PLUS_BETA[4] + 180.0) - 116.239).abs() < 1e-3);
}

/// Table 1 of the paper as a TOML file, with α3 given.
fn table(alpha3_deg: f64) -> String {
    format!(
        r#"
name = "welder6r-table"
length_unit = "mm"
angle_unit = "deg"
joints = [
  {{ alpha = 90 }},
  {{ a = 400 }},
  {{ a = 300, alpha = {alpha3_deg} }},
  {{ alpha = -90 }},
  {{ d = 200, alpha = 90 }},
  {{ d = 250, a = 50, alpha = 90 }},
]
"#
    )
}
