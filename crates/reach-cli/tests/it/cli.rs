//! End-to-end tests of the `reach` binary: each command's output checked against values
//! derived by hand (or, where noted, computed by the library), negative numbers as plain
//! arguments, every error path (exit status 2, one line on stderr, nothing on stdout),
//! robot files written to a temporary directory, and a closed stdout.

use std::f64::consts::{FRAC_PI_2, PI};
use std::process::Stdio;

use serde_json::Value;

use crate::common::{Run, fails, json, num, nums, ok, reach, reach_command, temp_file};

// ---------------------------------------------------------------------------------------
// Helpers (the shared ones are in common/mod.rs)

/// A clap usage error: exit 2, nothing on stdout, an error or the usage on stderr, no panic.
fn usage_error(args: &[&str]) {
    let run = reach(args);
    assert_eq!(run.code, 2, "reach {args:?}: {}", run.stderr);
    assert!(run.stdout.is_empty(), "reach {args:?} printed on stdout: {}", run.stdout);
    assert!(run.stderr.starts_with("error: ") || run.stderr.contains("Usage: reach"), "{}", run.stderr);
    assert!(!run.stderr.contains("panicked"), "{}", run.stderr);
}

fn matrix(v: &Value) -> Vec<Vec<f64>> {
    v.as_array().unwrap_or_else(|| panic!("not a matrix: {v}")).iter().map(nums).collect()
}

#[track_caller]
fn assert_close(got: f64, want: f64, tol: f64) {
    assert!((got - want).abs() <= tol, "got {got}, want {want} (tolerance {tol})");
}

#[track_caller]
fn assert_all_close(got: &[f64], want: &[f64], tol: f64) {
    assert_eq!(got.len(), want.len(), "got {got:?}, want {want:?}");
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() <= tol, "got {got:?}, want {want:?} (tolerance {tol})");
    }
}

#[track_caller]
fn assert_matrix(got: &[Vec<f64>], want: [[f64; 4]; 4], tol: f64) {
    assert_eq!(got.len(), 4);
    for (g, w) in got.iter().zip(want) {
        assert_all_close(g, &w, tol);
    }
}

/// A two-joint arm in millimetres: a revolute yaw joint with a 500 mm link, then a
/// prismatic joint lifting along z (0..200 mm) with a 300 mm link, on a base 100 mm high.
const MM_ROBOT: &str = r#"
name = "mm-arm"
description = "test arm written in millimetres"
convention = "dh"
length_unit = "mm"
angle_unit = "deg"

[base]
xyz = [0, 0, 100]

[[joints]]
name = "yaw"
a = 500
limits = [-90, 90]
max_velocity = 90

[[joints]]
name = "lift"
kind = "prismatic"
a = 300
limits = [0, 200]
max_velocity = 50
"#;

/// A URDF tree: base_link → j1 (revolute about z, 0.1 m up) → link1 → j2 (continuous, 0.5 m
/// up, frame turned 90° about z, axis y of that frame = world −x at q1 = 0) → link2 → fixed
/// 0.3 m up → tool0.
const URDF_ROBOT: &str = r#"<?xml version="1.0"?>
<robot name="twolink">
  <link name="base_link"/>
  <link name="link1"/>
  <link name="link2"/>
  <link name="tool0"/>
  <joint name="j1" type="revolute">
    <parent link="base_link"/>
    <child link="link1"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" effort="1" velocity="2"/>
  </joint>
  <joint name="j2" type="continuous">
    <parent link="link1"/>
    <child link="link2"/>
    <origin xyz="0 0 0.5" rpy="0 0 1.5707963267948966"/>
    <axis xyz="0 1 0"/>
  </joint>
  <joint name="tool" type="fixed">
    <parent link="link2"/>
    <child link="tool0"/>
    <origin xyz="0 0 0.3" rpy="0 0 0"/>
  </joint>
</robot>
"#;

const IDENTITY: [[f64; 4]; 4] =
    [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

// ---------------------------------------------------------------------------------------
// Help

#[test]
fn help_explains_every_command_with_an_example() {
    let text = ok(&["--help"]);
    for command in ["robots", "robot", "fk", "jacobian", "demo"] {
        assert!(text.contains(&format!("\n  {command} ")), "command {command} missing:\n{text}");
    }
    for example in ["reach robots", "reach robot show ", "reach fk ", "reach jacobian ", "reach demo", "--json"] {
        assert!(text.contains(example), "no example `{example}`:\n{text}");
    }
    assert!(text.contains("Exit status"), "{text}");
    for command in [&["robots"][..], &["robot", "show"], &["fk"], &["jacobian"], &["demo"]] {
        let mut args = command.to_vec();
        args.push("--help");
        let text = ok(&args);
        assert!(text.contains("Example"), "reach {command:?} --help has no example:\n{text}");
        assert!(text.contains(&format!("reach {}", command.join(" "))), "{text}");
    }
}

// ---------------------------------------------------------------------------------------
// robots

#[test]
fn robots_lists_every_preset_with_dof_and_description() {
    let text = ok(&["robots"]);
    let want = [
        ("planar3", 3),
        ("planar4", 4),
        ("log-loader", 3),
        ("spbu6", 6),
        ("puma560", 6),
        ("welder6r", 6),
        ("varan4", 4),
        ("ur5", 6),
        ("panda", 7),
    ];
    assert_eq!(text.lines().count(), want.len() + 1, "{text}");
    for (name, dof) in want {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("{name} missing:\n{text}"));
        assert_eq!(line.split_whitespace().nth(1), Some(dof.to_string().as_str()), "{line}");
    }
    assert!(text.contains("Franka Emika Panda, 7 joints, modified DH, with hand"), "{text}");

    let list = json(&["robots", "--json"]);
    let list = list.as_array().unwrap();
    assert_eq!(list.len(), want.len());
    for (entry, (name, dof)) in list.iter().zip(want) {
        assert_eq!(entry["name"], name);
        assert_eq!(entry["dof"], dof);
        assert!(!entry["description"].as_str().unwrap().is_empty());
    }
    assert_eq!(list[8]["convention"], "mdh");
    assert_eq!(serde_json::to_value(reach::jobs::model::preset_list().unwrap()).unwrap(), serde_json::json!(list));
    crate::common::assert_valid("presets.report", &serde_json::json!(list));
}

// ---------------------------------------------------------------------------------------
// robot show

#[test]
fn robot_show_prints_the_dh_table_in_the_file_units() {
    let text = ok(&["robot", "show", "puma560"]);
    for needle in ["puma560", "a [m]", "alpha [deg]", "0.4318", "0.6718", "0.15005", "-45 .. 225 deg", "standard"] {
        assert!(text.contains(needle), "no `{needle}`:\n{text}");
    }
    // varan4 is written in millimetres.
    let text = ok(&["robot", "show", "varan4"]);
    assert!(text.contains("a [mm]") && text.contains("lengths in mm"), "{text}");
    let row = text.lines().find(|l| l.contains(" q2 ")).unwrap();
    assert!(row.contains(" 900 ") && row.contains("0 .. 120 deg"), "{row}");
    // welder6r gives speeds in rev/min: 5 rpm = 30 deg/s.
    let text = ok(&["robot", "show", "welder6r"]);
    assert!(text.contains("30 deg/s") && text.contains("36 deg/s"), "{text}");
    // panda is modified DH in radians, with a tool offset.
    let text = ok(&["robot", "show", "panda"]);
    assert!(text.contains("mdh") && text.contains("alpha [rad]"), "{text}");
    assert!(text.contains("tool  xyz [m] 0 0 0.103"), "{text}");
}

#[test]
fn robot_show_json_is_in_si_units() {
    let job = reach::jobs::Job {
        robot: reach::jobs::RobotInput::Preset("puma560".into()),
        request: reach::jobs::Request::Model(reach::jobs::ModelRequest {}),
    };
    let v = crate::common::assert_report(&["robot", "show", "puma560", "--json"], &job, "model.report");
    assert_eq!(v["name"], "puma560");
    assert_eq!(v["convention"], "dh");
    let joints = v["joints"].as_array().unwrap();
    assert_eq!(joints.len(), 6);
    assert_eq!(joints[0]["name"], "waist");
    assert_eq!(joints[0]["kind"], "revolute");
    assert_close(num(&joints[0]["d_m"]), 0.6718, 1e-12);
    assert_close(num(&joints[0]["alpha_rad"]), FRAC_PI_2, 1e-12);
    assert_close(num(&joints[1]["a_m"]), 0.4318, 1e-12);
    assert_close(num(&joints[2]["alpha_rad"]), -FRAC_PI_2, 1e-12);
    assert_close(num(&joints[2]["theta_offset_rad"]), 0.0, 0.0);
    assert_all_close(&nums(&joints[1]["limits"]), &[-PI / 4.0, 5.0 * PI / 4.0], 1e-12);
    assert!(joints[0]["max_velocity"].is_null());
    assert_eq!(joints[0]["home"], 0.0);
    assert_eq!(joints[0]["flip"], false);
    assert_matrix(&matrix(&v["base"]), IDENTITY, 0.0);
    assert_matrix(&matrix(&v["tool"]), IDENTITY, 0.0);

    // UR5: 180 deg/s = π rad/s.
    let v = json(&["robot", "show", "ur5", "--json"]);
    assert_close(num(&v["joints"][0]["max_velocity"]), PI, 1e-12);
    // welder6r: 5 rpm = π/6 rad/s; 400 mm = 0.4 m.
    let v = json(&["robot", "show", "welder6r", "--json"]);
    assert_close(num(&v["joints"][0]["max_velocity"]), PI / 6.0, 1e-12);
    assert_close(num(&v["joints"][1]["a_m"]), 0.4, 1e-12);
    // Panda: hand 0.103 m along z, turned −45° about z.
    let v = json(&["robot", "show", "panda", "--json"]);
    assert_eq!(v["convention"], "mdh");
    let c = (PI / 4.0).cos();
    assert_matrix(
        &matrix(&v["tool"]),
        [[c, c, 0.0, 0.0], [-c, c, 0.0, 0.0], [0.0, 0.0, 1.0, 0.103], [0.0, 0.0, 0.0, 1.0]],
        1e-12,
    );
}

#[test]
fn robot_show_reads_a_millimetre_toml_file() {
    let path = temp_file("mm-arm.toml", MM_ROBOT);
    let path = path.to_str().unwrap();
    let text = ok(&["robot", "show", path]);
    for needle in [
        "mm-arm",
        "a [mm]",
        "d [mm]",
        "lengths in mm, angles in deg",
        "0 .. 200 mm",
        "-90 .. 90 deg",
        "90 deg/s",
        "50 mm/s",
        "prismatic",
        "base  xyz [mm] 0 0 100",
    ] {
        assert!(text.contains(needle), "no `{needle}`:\n{text}");
    }
    let lift = text.lines().find(|l| l.contains("lift")).unwrap();
    assert!(lift.contains(" 300 "), "{lift}");

    let v = json(&["robot", "show", path, "--json"]);
    assert_eq!(v["name"], "mm-arm");
    let j = &v["joints"];
    assert_close(num(&j[0]["a_m"]), 0.5, 1e-15);
    assert_eq!(j[1]["kind"], "prismatic");
    assert_close(num(&j[1]["a_m"]), 0.3, 1e-15);
    assert_all_close(&nums(&j[1]["limits"]), &[0.0, 0.2], 1e-15);
    assert_close(num(&j[1]["max_velocity"]), 0.05, 1e-15);
    assert_close(num(&j[0]["max_velocity"]), FRAC_PI_2, 1e-12);
    assert_matrix(
        &matrix(&v["base"]),
        [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.1], [0.0, 0.0, 0.0, 1.0]],
        1e-15,
    );
}

#[test]
fn robot_show_reads_a_urdf_file() {
    let path = temp_file("twolink.urdf", URDF_ROBOT);
    let path = path.to_str().unwrap();
    let text = ok(&["robot", "show", path]);
    for needle in ["twolink", "urdf", "origin xyz [m]", "origin rpy [deg]", "0 0 0.5", "0 0 90", "0 1 0", "unlimited"] {
        assert!(text.contains(needle), "no `{needle}`:\n{text}");
    }
    assert!(text.contains("tool  xyz [m] 0 0 0.3"), "{text}");

    let v = json(&["robot", "show", path, "--json"]);
    assert_eq!(v["convention"], "urdf");
    let j = &v["joints"];
    assert_eq!(j.as_array().unwrap().len(), 2);
    assert!(j[0].get("a_m").is_none(), "URDF joints have no DH parameters: {}", j[0]);
    assert_all_close(&nums(&j[0]["axis"]), &[0.0, 0.0, 1.0], 0.0);
    assert_all_close(&nums(&j[0]["limits"]), &[-3.0, 3.0], 0.0);
    assert_close(num(&j[0]["max_velocity"]), 2.0, 0.0);
    assert_matrix(
        &matrix(&j[0]["origin"]),
        [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.1], [0.0, 0.0, 0.0, 1.0]],
        1e-15,
    );
    assert!(j[1]["limits"].is_null(), "continuous joint is unlimited: {}", j[1]);
    assert_matrix(
        &matrix(&j[1]["origin"]),
        [[0.0, -1.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.5], [0.0, 0.0, 0.0, 1.0]],
        1e-12,
    );
    assert_all_close(&nums(&j[1]["axis"]), &[0.0, 1.0, 0.0], 0.0);
    assert_matrix(
        &matrix(&v["tool"]),
        [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.3], [0.0, 0.0, 0.0, 1.0]],
        1e-15,
    );
}

// ---------------------------------------------------------------------------------------
// fk

/// Puma 560 at q = 0, by hand from the DH table: A1 lifts 0.6718 and turns x-up, A2 moves
/// 0.4318 along x, A3 moves 0.15005 along z1 = −y0 and 0.0203 along x, A4 lifts 0.4318;
/// the twists cancel (90 − 90 + 90 − 90), so R = I and p = (0.4521, −0.15005, 1.1036).
#[test]
fn fk_puma560_at_zero_matches_the_hand_computation() {
    let v = json(&["fk", "puma560", "0", "0", "0", "0", "0", "0", "--json"]);
    assert_eq!(v["robot"], "puma560");
    assert_all_close(&nums(&v["q_deg"]), &[0.0; 6], 0.0);
    let pose = &v["pose"];
    assert_matrix(
        &matrix(&pose["matrix"]),
        [[1.0, 0.0, 0.0, 0.4521], [0.0, 1.0, 0.0, -0.15005], [0.0, 0.0, 1.0, 1.1036], [0.0, 0.0, 0.0, 1.0]],
        1e-12,
    );
    assert_all_close(&nums(&pose["xyz_m"]), &[0.4521, -0.15005, 1.1036], 1e-12);
    assert_all_close(&nums(&pose["rpy_deg"]), &[0.0, 0.0, 0.0], 1e-9);
    assert_all_close(&nums(&pose["quat_wxyz"]), &[1.0, 0.0, 0.0, 0.0], 1e-12);
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 6);
    // Frame 1: 0.6718 up, turned +90° about x.
    assert_matrix(
        &matrix(&frames[0]),
        [[1.0, 0.0, 0.0, 0.0], [0.0, 0.0, -1.0, 0.0], [0.0, 1.0, 0.0, 0.6718], [0.0, 0.0, 0.0, 1.0]],
        1e-12,
    );
    // Frame 3: the elbow, still at the shoulder height.
    let f3 = matrix(&frames[2]);
    assert_all_close(&[f3[0][3], f3[1][3], f3[2][3]], &[0.4521, -0.15005, 0.6718], 1e-12);
    assert_eq!(v["outside_limits"].as_array().unwrap().len(), 0);

    let text = ok(&["fk", "puma560", "0", "0", "0", "0", "0", "0"]);
    assert!(text.contains("0.452100 -0.150050 1.103600"), "{text}");
    assert!(text.contains("1.000000 0.000000 0.000000 0.000000"), "quaternion:\n{text}");
    assert!(text.contains("all joints within limits"), "{text}");
}

/// UR5 at q = 0, by hand: p = (a2 + a3, −(d4 + d6), d1 − d5) = (−0.81725, −0.19145,
/// −0.005491); the twists leave R = Rx(90°).
#[test]
fn fk_ur5_at_zero_matches_the_hand_computation() {
    let v = json(&["fk", "ur5", "0", "0", "0", "0", "0", "0", "--json"]);
    assert_matrix(
        &matrix(&v["pose"]["matrix"]),
        [[1.0, 0.0, 0.0, -0.81725], [0.0, 0.0, -1.0, -0.19145], [0.0, 1.0, 0.0, -0.005491], [0.0, 0.0, 0.0, 1.0]],
        1e-12,
    );
    assert_all_close(&nums(&v["pose"]["rpy_deg"]), &[90.0, 0.0, 0.0], 1e-9);
    let h = 0.5_f64.sqrt();
    assert_all_close(&nums(&v["pose"]["quat_wxyz"]), &[h, h, 0.0, 0.0], 1e-12);
}

/// Planar 3R with 1 m links at q = (90°, −90°, −90°): the links point +y, +x, −y, so the
/// tool is at (1, 0, 0) with yaw −90°.
#[test]
fn fk_accepts_negative_numbers_as_plain_arguments() {
    let v = json(&["fk", "planar3", "90", "-90", "-90", "--json"]);
    assert_all_close(&nums(&v["q_deg"]), &[90.0, -90.0, -90.0], 0.0);
    assert_all_close(&nums(&v["q_si"]), &[FRAC_PI_2, -FRAC_PI_2, -FRAC_PI_2], 1e-15);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[1.0, 0.0, 0.0], 1e-12);
    assert_all_close(&nums(&v["pose"]["rpy_deg"]), &[0.0, 0.0, -90.0], 1e-9);
    let h = 0.5_f64.sqrt();
    assert_all_close(&nums(&v["pose"]["quat_wxyz"]), &[h, 0.0, 0.0, -h], 1e-12);

    // The same in radians, options first, and with `--` before the values.
    let r = FRAC_PI_2.to_string();
    let m = (-FRAC_PI_2).to_string();
    for args in [
        vec!["fk", "--rad", "--json", "planar3", &r, &m, &m],
        vec!["fk", "planar3", "--rad", &r, &m, &m, "--json"],
        vec!["fk", "--json", "--rad", "--", "planar3", &r, &m, &m],
    ] {
        let v = json(&args);
        assert_all_close(&nums(&v["pose"]["xyz_m"]), &[1.0, 0.0, 0.0], 1e-12);
        assert_all_close(&nums(&v["q_deg"]), &[90.0, -90.0, -90.0], 1e-12);
    }

    // The example of the issue, against the library; `-.5`-style and exponent forms too.
    let ur5 = reach::model::presets::get("ur5").unwrap();
    for (args, q_deg) in [
        (vec!["-90", "-45.5", "0", "0", "0", "0"], [-90.0, -45.5, 0.0, 0.0, 0.0, 0.0]),
        (vec!["-.5", "-1e1", "2.5E1", "-0", "+3", "-179.75"], [-0.5, -10.0, 25.0, 0.0, 3.0, -179.75]),
    ] {
        let mut full = vec!["fk", "ur5"];
        full.extend(&args);
        full.push("--json");
        let v = json(&full);
        assert_all_close(&nums(&v["q_deg"]), &q_deg, 0.0);
        let q: Vec<f64> = q_deg.iter().map(|d| d.to_radians()).collect();
        let want = ur5.fk(&q).unwrap().translation.vector;
        assert_all_close(&nums(&v["pose"]["xyz_m"]), &[want.x, want.y, want.z], 1e-12);
    }
    let text = ok(&["fk", "ur5", "-90", "-45.5", "0", "0", "0", "0"]);
    assert!(text.contains("-90 -45.5 0 0 0 0 [deg]"), "{text}");
}

#[test]
fn fk_reports_joints_outside_their_limits_but_computes_the_pose() {
    // planar3: q2 must lie in [−180°, 0°].
    let v = json(&["fk", "planar3", "0", "90", "0", "--json"]);
    assert_eq!(v["outside_limits"], serde_json::json!([2]));
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[1.0, 2.0, 0.0], 1e-12);
    let text = ok(&["fk", "planar3", "0", "90", "0"]);
    assert!(text.contains("joint 2 (B) outside -180 .. 0 deg"), "{text}");
}

/// The millimetre arm at q = (90°, 0.2 m): the yaw link ends at (0, 0.5, 0.1); the lift
/// raises the second link by 0.2 m and it points along world y: (0, 0.8, 0.3), yaw 90°.
#[test]
fn fk_of_a_millimetre_toml_file_with_a_prismatic_joint() {
    let path = temp_file("mm-arm.toml", MM_ROBOT);
    let path = path.to_str().unwrap();
    let v = json(&["fk", path, "90", "0.2", "--json"]);
    assert_eq!(v["robot"], "mm-arm");
    assert_all_close(&nums(&v["q_deg"]), &[90.0, 0.2], 0.0);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, 0.8, 0.3], 1e-12);
    assert_all_close(&nums(&v["pose"]["rpy_deg"]), &[0.0, 0.0, 90.0], 1e-9);
    assert_eq!(v["outside_limits"].as_array().unwrap().len(), 0, "0.2 m is the upper limit");
    // Prismatic values stay in metres with --rad.
    let v = json(&["fk", path, "--rad", &FRAC_PI_2.to_string(), "0.2", "--json"]);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, 0.8, 0.3], 1e-12);
    let v = json(&["fk", path, "-90", "0.25", "--json"]);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, -0.8, 0.35], 1e-12);
    assert_eq!(v["outside_limits"], serde_json::json!([2]));
    let text = ok(&["fk", path, "90", "0.2"]);
    assert!(text.contains("90 deg, 0.2 m"), "{text}");
    assert!(text.contains("0.000000 0.800000 0.300000"), "{text}");
}

/// The URDF arm: at q = (0, 90°) joint 2 turns about world −x, taking the 0.3 m tool
/// offset from +z to +y: (0, 0.3, 0.6).
#[test]
fn fk_of_a_urdf_file_with_base_and_tip() {
    let path = temp_file("twolink.urdf", URDF_ROBOT);
    let path = path.to_str().unwrap();
    let v = json(&["fk", path, "0", "0", "--json"]);
    assert_eq!(v["robot"], "twolink");
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, 0.0, 0.9], 1e-12);
    let v = json(&["fk", path, "0", "90", "--json"]);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, 0.3, 0.6], 1e-12);
    assert_eq!(v["frames"].as_array().unwrap().len(), 2);
    // Joint 1 at 90° turns everything about world z: (−0.3, 0, 0.6).
    let v = json(&["fk", path, "90", "90", "--json"]);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[-0.3, 0.0, 0.6], 1e-12);
    // Chain ending at link2: no tool offset.
    let v = json(&["fk", path, "--tip", "link2", "0", "0", "--json"]);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, 0.0, 0.6], 1e-12);
    // Chain from link1 to tool0: one joint, poses relative to link1. −90° about −x is +90°
    // about +x, which takes +z to −y.
    let v = json(&["fk", path, "--base", "link1", "--tip", "tool0", "-90", "--json"]);
    assert_eq!(v["q_deg"].as_array().unwrap().len(), 1);
    assert_all_close(&nums(&v["pose"]["xyz_m"]), &[0.0, -0.3, 0.5], 1e-12);
}

// ---------------------------------------------------------------------------------------
// jacobian

/// Planar 3R (1 m links) at q = (0, −90°, −45°): joints at (0,0), (1,0), (1,−1). Only the
/// rows vx, vy, ωz are non-zero, and their 3×3 determinant is (o3 − o1) × (o3 − o2) = −1, so
/// Yoshikawa's measure is 1. At q = 0 the arm is stretched: rank 2, condition infinite.
#[test]
fn jacobian_of_planar3_matches_the_hand_computation() {
    let v = json(&["jacobian", "planar3", "0", "-90", "-45", "--json"]);
    assert_eq!(v["rows"], serde_json::json!(["vx", "vy", "vz", "wx", "wy", "wz"]));
    let j = matrix(&v["jacobian"]);
    assert_eq!(j.len(), 6);
    let (c, s) = (0.5_f64.sqrt(), 0.5_f64.sqrt());
    // Tool p = (1 + cos(−135°), −1 + sin(−135°)) = (1 − c, −1 − s).
    let p = [1.0 - c, -1.0 - s];
    let joints = [[0.0, 0.0], [1.0, 0.0], [1.0, -1.0]];
    for (col, o) in joints.iter().enumerate() {
        assert_close(j[0][col], -(p[1] - o[1]), 1e-12);
        assert_close(j[1][col], p[0] - o[0], 1e-12);
        for row in [2, 3, 4] {
            assert_close(j[row][col], 0.0, 1e-12);
        }
        assert_close(j[5][col], 1.0, 1e-12);
    }
    assert_close(num(&v["manipulability"]), 1.0, 1e-12);
    assert_eq!(v["rank"], 3);
    assert_eq!(v["max_rank"], 3);
    let sv = nums(&v["singular_values"]);
    assert_eq!(sv.len(), 3);
    assert_close(sv.iter().product(), 1.0, 1e-12);
    assert_close(num(&v["sigma_min"]), sv[2], 0.0);
    assert_close(num(&v["condition"]), sv[0] / sv[2], 1e-9);

    let v = json(&["jacobian", "planar3", "0", "0", "0", "--json"]);
    assert_eq!(v["rank"], 2);
    assert!(v["condition"].is_null(), "{}", v["condition"]);
    assert_close(num(&v["manipulability"]), 0.0, 1e-12);
    let j = matrix(&v["jacobian"]);
    assert_all_close(&j[1], &[3.0, 2.0, 1.0], 1e-12);

    let text = ok(&["jacobian", "planar3", "0", "-90", "-45"]);
    for needle in ["manipulability", "1.000000", "sigma_min", "condition", "rank             3 of 3", " vx ", " wz "] {
        assert!(text.contains(needle), "no `{needle}`:\n{text}");
    }
    let text = ok(&["jacobian", "planar3", "0", "0", "0"]);
    assert!(text.contains("infinite (singular)") && text.contains("2 of 3 (singular)"), "{text}");
}

/// Puma 560: the first column is z0 × p (joint 1 turns about the world z axis through the
/// origin), checked against the tool position `reach fk` prints; the measures against the
/// library.
#[test]
fn jacobian_of_puma560_is_consistent_with_fk_and_the_library() {
    let q = ["10", "45", "-90", "20", "30", "-40"];
    let mut args = vec!["jacobian", "puma560"];
    args.extend(q);
    args.push("--json");
    let v = json(&args);
    let mut fk_args = vec!["fk", "puma560"];
    fk_args.extend(q);
    fk_args.push("--json");
    let p = nums(&json(&fk_args)["pose"]["xyz_m"]);
    let j = matrix(&v["jacobian"]);
    assert_eq!(j[0].len(), 6);
    let col0: Vec<f64> = j.iter().map(|row| row[0]).collect();
    assert_all_close(&col0, &[-p[1], p[0], 0.0, 0.0, 0.0, 1.0], 1e-12);

    let puma = reach::model::presets::get("puma560").unwrap();
    let qr: Vec<f64> = q.iter().map(|d| d.parse::<f64>().unwrap().to_radians()).collect();
    let m = puma.manipulability(&qr).unwrap();
    assert_close(num(&v["manipulability"]), m.yoshikawa, 1e-12);
    assert_close(num(&v["sigma_min"]), m.sigma_min, 1e-12);
    assert_close(num(&v["condition"]), m.condition, 1e-6);
    assert_eq!(v["rank"], 6);
    let want = puma.jacobian(&qr).unwrap();
    for (r, row) in j.iter().enumerate() {
        for (c, x) in row.iter().enumerate() {
            assert_close(*x, want[(r, c)], 1e-12);
        }
    }
    // q5 = 0 aligns the wrist axes 4 and 6: rank 5.
    let v = json(&["jacobian", "puma560", "0", "45", "-90", "0", "0", "0", "--json"]);
    assert_eq!(v["rank"], 5);
    assert!(v["condition"].is_null());
}

// ---------------------------------------------------------------------------------------
// demo

#[test]
fn demo_prints_fk_of_every_preset_at_home() {
    let text = ok(&["demo"]);
    assert!(text.starts_with("reach demo"), "{text}");
    assert!(text.contains("1. Forward kinematics of every preset at its home pose"), "{text}");
    for name in ["planar3", "log-loader", "spbu6", "puma560", "welder6r", "varan4", "ur5", "panda"] {
        assert!(text.contains(&format!("\n{name} — ")), "{name} missing:\n{text}");
    }
    // Puma at home (q = 0), see the fk test; spbu6 at q = 0 is the paper's T0 = (3, 0, 5).
    assert!(text.contains("0.452100 -0.150050 1.103600"), "{text}");
    assert!(text.contains("3.000000 0.000000 5.000000"), "{text}");
    // varan4: 900 + 700 + 500 mm stretched out along x.
    assert!(text.contains("2.100000 0.000000 0.000000"), "{text}");
}

// ---------------------------------------------------------------------------------------
// Errors

#[test]
fn wrong_joint_count_is_bad_input() {
    fails(&["fk", "puma560", "0", "0", "0"], 2, &["puma560", "6 joints", "got 3"]);
    fails(&["fk", "puma560"], 2, &["6 joints", "got 0"]);
    fails(&["jacobian", "planar3", "1", "2", "3", "4"], 2, &["3 joints", "got 4"]);
    fails(&["fk", "ur5", "-90", "-45.5", "0", "0", "0"], 2, &["6 joints", "got 5"]);
}

#[test]
fn non_numeric_values_are_bad_input_naming_the_joint() {
    let line = fails(&["fk", "puma560", "0", "0", "abc", "0", "0", "0"], 2, &["joint 3", "\"abc\""]);
    assert_eq!(line, r#"error: joint 3: expected a number, got "abc""#);
    fails(&["fk", "puma560", "0", "-abc", "0", "0", "0", "0"], 2, &["joint 2", "\"-abc\""]);
    fails(&["fk", "planar3", "1", "2", "3deg"], 2, &["joint 3", "\"3deg\""]);
    fails(&["fk", "planar3", "1,5", "2", "3"], 2, &["3 joints", "got 4"]);
    fails(&["fk", "planar3", "1,x", "2"], 2, &["joint 2", "\"x\""]);
    fails(&["fk", "planar3", "1", ",", "3"], 2, &["joint 2", "expected a number"]);
    fails(&["jacobian", "planar3", "1", "", "3"], 2, &["joint 2", "expected a number"]);
    fails(&["jacobian", "planar3", "0x10", "0", "0", "--json"], 2, &["joint 1", "\"0x10\""]);
}

#[test]
fn non_finite_values_are_bad_input_naming_the_joint() {
    for (value, joint) in [("nan", 1), ("NaN", 2), ("inf", 3), ("-inf", 1), ("infinity", 2), ("-nan", 3), ("1e400", 1)]
    {
        let mut q = vec!["0"; 3];
        q[joint - 1] = value;
        for command in ["fk", "jacobian"] {
            let mut args = vec![command, "planar3"];
            args.extend(&q);
            fails(&args, 2, &[&format!("joint {joint}"), "finite", &format!("\"{value}\"")]);
        }
    }
    fails(&["fk", "ur5", "0", "0", "0", "0", "0", "inf", "--rad"], 2, &["joint 6", "finite"]);
}

#[test]
fn unknown_presets_and_unreadable_or_malformed_files_are_bad_input() {
    fails(&["fk", "nosuchbot", "0"], 2, &["nosuchbot", "puma560"]);
    fails(&["jacobian", "nosuchbot", "0"], 2, &["nosuchbot"]);
    fails(&["robot", "show", "nosuchbot"], 2, &["unknown robot `nosuchbot`"]);

    let missing = std::env::temp_dir().join("reach-cli-test-no-such-dir").join("robot.toml");
    let missing = missing.to_str().unwrap();
    fails(&["fk", missing, "0"], 2, &["cannot read", "robot.toml"]);
    fails(&["robot", "show", missing], 2, &["cannot read"]);
    fails(&["robot", "show", std::env::temp_dir().to_str().unwrap()], 2, &["cannot read"]);

    let syntax = temp_file("syntax.toml", "name = \"x\"\nlength_unit = \"m\"\nangle_unit = \n");
    fails(&["robot", "show", syntax.to_str().unwrap()], 2, &["syntax.toml", "line 3"]);
    let unknown_field = temp_file(
        "field.toml",
        "name = \"x\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\na = 1\nlenght = 2\n",
    );
    fails(&["fk", unknown_field.to_str().unwrap(), "0"], 2, &["field.toml", "line 6", "lenght"]);
    let bad_unit =
        temp_file("unit.toml", "name = \"x\"\nlength_unit = \"cm\"\nangle_unit = \"deg\"\n[[joints]]\na = 1\n");
    fails(&["fk", bad_unit.to_str().unwrap(), "0"], 2, &["unit.toml", "line 2"]);
    let bad_limits = temp_file(
        "limits.toml",
        "name = \"x\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nname = \"j\"\na = 1\nlimits = [10, -10]\n",
    );
    fails(&["robot", "show", bad_limits.to_str().unwrap(), "--json"], 2, &["joint 1 (j)", "limits"]);
    let no_joints = temp_file("empty.toml", "name = \"x\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\njoints = []\n");
    fails(&["robot", "show", no_joints.to_str().unwrap()], 2, &["no joints"]);

    let broken_urdf = temp_file("broken.urdf", "<robot name=\"x\"><link name=\"a\"/><joint name=\"j\"");
    fails(&["fk", broken_urdf.to_str().unwrap(), "0"], 2, &["broken.urdf", "URDF"]);
    let urdf = temp_file("twolink.urdf", URDF_ROBOT);
    let urdf = urdf.to_str().unwrap();
    fails(&["fk", urdf, "--tip", "nolink", "0", "0"], 2, &["nolink", "links: base_link"]);
    fails(&["fk", urdf, "--base", "link2", "--tip", "link1", "0"], 2, &["not below"]);
    fails(&["fk", urdf, "0", "0", "0"], 2, &["2 joints", "got 3"]);
    fails(&["fk", "puma560", "--base", "x", "0", "0", "0", "0", "0", "0"], 2, &["--base", "URDF"]);
    fails(&["robot", "show", "ur5", "--tip", "tool0"], 2, &["--tip", "URDF"]);
}

#[test]
fn usage_errors_exit_with_status_2() {
    usage_error(&[]); // prints the short help on stderr
    usage_error(&["bogus"]);
    usage_error(&["fk"]);
    usage_error(&["fk", "ur5", "--jsn", "0"]);
    usage_error(&["robot"]);
    usage_error(&["robot", "show"]);
    usage_error(&["robots", "extra"]);
    usage_error(&["fk", "ur5", "--tip"]);
}

/// `reach robots | head -1`: the reader goes away; reach must neither panic nor complain.
#[test]
fn a_closed_stdout_is_not_an_error() {
    for args in [&["robots"][..], &["demo"], &["fk", "ur5", "-90", "0", "0", "0", "0", "0", "--json"], &["--help"]] {
        let (reader, writer) = std::io::pipe().expect("pipe");
        drop(reader);
        let out = reach_command(args).stdout(writer).stderr(Stdio::piped()).output().expect("run reach");
        let run = Run::from_output(out);
        assert_eq!(run.code, 0, "reach {args:?}: {}", run.stderr);
        assert!(!run.stderr.contains("panicked"), "reach {args:?}: {}", run.stderr);
        assert!(run.stderr.is_empty(), "reach {args:?}: {}", run.stderr);
    }
}

#[test]
fn fk_and_jacobian_json_are_the_library_reports_and_match_their_schemas() {
    use reach::jobs::{FkRequest, JacobianRequest, Job, Joints, Request, RobotInput};
    let q = Joints::Deg(vec![0.0, -90.0, 90.0, 0.0, 90.0, 0.0]);
    let robot = RobotInput::Preset("ur5".into());
    let fk = Job { robot: robot.clone(), request: Request::Fk(FkRequest { q: q.clone() }) };
    crate::common::assert_report(&["fk", "ur5", "0", "-90", "90", "0", "90", "0", "--json"], &fk, "fk.report");
    let jac = Job { robot, request: Request::Jacobian(JacobianRequest { q }) };
    crate::common::assert_report(
        &["jacobian", "ur5", "0", "-90", "90", "0", "90", "0", "--json"],
        &jac,
        "jacobian.report",
    );
    let rad = Job {
        robot: RobotInput::Preset("planar3".into()),
        request: Request::Fk(FkRequest { q: Joints::Rad(vec![0.5, -0.25, 1.0]) }),
    };
    crate::common::assert_report(&["fk", "planar3", "0.5", "-0.25", "1", "--rad", "--json"], &rad, "fk.report");
}
