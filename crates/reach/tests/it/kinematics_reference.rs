//! External check of the kinematics core against the Robotics Toolbox for Python 1.5.
//!
//! `tests/data/reference/*.json` (copied from the project's `reference/` folder) hold, for
//! Puma 560 (standard DH), UR5 (standard DH) and Panda (modified DH), the Toolbox's own DH
//! table, base and tool, and 100 random joint vectors with the tool pose `T` (4×4, row-major)
//! and the geometric Jacobian `J0` (6×n, base frame, rows vx vy vz ωx ωy ωz). Each robot is
//! built from the file's table through `RobotSpec` / `Robot::new` (not from our presets,
//! whose numbers differ slightly, e.g. UR5 d1) and every case is compared to 1e-9.

use approx::assert_relative_eq;
use nalgebra::{Isometry3, Matrix3, Matrix4, Rotation3, Translation3, UnitQuaternion};
use reach::model::{Convention, Joint, Robot, RobotSpec};
use serde_json::Value;

/// Largest accepted absolute difference in any entry of T (metres or unitless) or J0.
const TOLERANCE: f64 = 1e-9;

fn matrix4(v: &Value) -> Matrix4<f64> {
    let rows = v.as_array().expect("4x4 matrix");
    assert_eq!(rows.len(), 4);
    Matrix4::from_fn(|r, c| rows[r][c].as_f64().expect("number"))
}

fn isometry(m: &Matrix4<f64>) -> Isometry3<f64> {
    // The files' transforms are exact rigid motions; check before trusting them.
    assert_eq!(m.fixed_view::<1, 4>(3, 0), Matrix4::identity().fixed_view::<1, 4>(3, 0));
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    assert_relative_eq!(r.transpose() * r, Matrix3::identity(), epsilon = 1e-12);
    Isometry3::from_parts(
        Translation3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]),
        UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r)),
    )
}

/// The robot described by the file's own DH table.
fn robot_from_reference(doc: &Value) -> Robot {
    let convention = match doc["convention"].as_str().unwrap() {
        "dh" => Convention::Dh,
        "mdh" => Convention::Mdh,
        other => panic!("unknown convention {other}"),
    };
    let joints = doc["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| {
            let f = |key: &str| j[key].as_f64().unwrap_or_else(|| panic!("{key}"));
            let joint = Joint::revolute(f("a_m"), f("alpha_rad"), f("d_m"), f("theta_offset_rad"));
            match j["limits_rad"].as_array() {
                None => joint,
                Some(l) => {
                    let (lo, hi) = (l[0].as_f64().unwrap(), l[1].as_f64().unwrap());
                    // `home` must lie within the limits (Panda joint 4 excludes 0).
                    Joint { home: 0.0f64.clamp(lo, hi), ..joint.with_limits(lo, hi) }
                }
            }
        })
        .collect();
    let mut spec = RobotSpec::new(doc["robot"].as_str().unwrap(), convention, joints);
    spec.base = isometry(&matrix4(&doc["base"]));
    spec.tool = isometry(&matrix4(&doc["tool"]));
    Robot::new(spec).unwrap()
}

fn check_reference(text: &str, expected_dof: usize) {
    let doc: Value = serde_json::from_str(text).unwrap();
    let robot = robot_from_reference(&doc);
    assert_eq!(robot.dof(), expected_dof);
    let cases = doc["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 100, "the reference files hold 100 cases each");
    let mut worst_t: f64 = 0.0;
    let mut worst_j: f64 = 0.0;
    for (k, case) in cases.iter().enumerate() {
        let q: Vec<f64> = case["q_rad"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let t_ref = matrix4(&case["T"]);
        let j_rows = case["J0"].as_array().unwrap();
        assert_eq!(j_rows.len(), 6);

        let t = robot.fk_matrix(&q).unwrap().to_homogeneous();
        let t_quat = robot.fk(&q).unwrap().to_homogeneous();
        let j = robot.jacobian(&q).unwrap();
        assert_eq!(j.ncols(), expected_dof);
        for r in 0..4 {
            for c in 0..4 {
                let e = (t[(r, c)] - t_ref[(r, c)]).abs();
                worst_t = worst_t.max(e);
                assert!(e <= TOLERANCE, "{} case {k}: T[{r}][{c}] = {} vs {}", robot.name(), t[(r, c)], t_ref[(r, c)]);
                let e = (t_quat[(r, c)] - t_ref[(r, c)]).abs();
                assert!(e <= TOLERANCE, "{} case {k}: fk() T[{r}][{c}] off by {e}", robot.name());
            }
        }
        for (r, row) in j_rows.iter().enumerate() {
            let row = row.as_array().unwrap();
            assert_eq!(row.len(), expected_dof);
            for (c, v) in row.iter().enumerate() {
                let v = v.as_f64().unwrap();
                let e = (j[(r, c)] - v).abs();
                worst_j = worst_j.max(e);
                assert!(e <= TOLERANCE, "{} case {k}: J0[{r}][{c}] = {} vs {v}", robot.name(), j[(r, c)]);
            }
        }
    }
    // Visible with `--nocapture`; the asserts above are the test.
    println!("{}: worst |ΔT| = {worst_t:.2e}, worst |ΔJ0| = {worst_j:.2e}", robot.name());
}

#[test]
fn puma560_matches_robotics_toolbox() {
    check_reference(include_str!("../data/reference/puma560.json"), 6);
}

#[test]
fn ur5_matches_robotics_toolbox() {
    check_reference(include_str!("../data/reference/ur5.json"), 6);
}

#[test]
fn panda_modified_dh_matches_robotics_toolbox() {
    check_reference(include_str!("../data/reference/panda_mdh.json"), 7);
}

/// The reference Panda table is the one of our `panda` preset (same MDH rows, same hand):
/// the preset must then give the same poses.
#[test]
fn panda_preset_matches_the_reference_table() {
    let doc: Value = serde_json::from_str(include_str!("../data/reference/panda_mdh.json")).unwrap();
    let preset = reach::model::presets::get("panda").unwrap();
    for case in doc["cases"].as_array().unwrap().iter().take(20) {
        let q: Vec<f64> = case["q_rad"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
        let t = preset.fk_matrix(&q).unwrap().to_homogeneous();
        assert_relative_eq!(t, matrix4(&case["T"]), epsilon = 1e-9);
    }
}
