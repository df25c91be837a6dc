//! URDF files as people write them: the Franka Panda (`examples/panda.urdf`) with its mimic
//! finger joint, on the command line.

use crate::common::{fails, json, ok, temp_file};

const PANDA: &str = "examples/panda.urdf";

fn nums(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect()
}

/// The left finger's chain has 7 arm joints and the finger: 8 values. The pose equals
/// Pinocchio's (first configuration of the library's fixture, given in radians).
#[test]
fn fk_of_the_panda_to_a_finger() {
    let fixture: serde_json::Value =
        serde_json::from_str(include_str!("../../../reach/tests/data/panda_urdf_reference.json")).unwrap();
    let case = &fixture["cases"][1];
    assert_eq!(case["tip"], "panda_leftfinger");
    let sample = &case["samples"][0];
    let q: Vec<String> = nums(&sample["q"]).iter().map(|v| format!("{v:?}")).collect();
    let mut args = vec!["fk", PANDA, "--base", "panda_link0", "--tip", "panda_leftfinger", "--rad", "--json"];
    args.extend(q.iter().map(String::as_str));
    let v = json(&args);
    let xyz = nums(&v["pose"]["xyz_m"]);
    for (got, want) in xyz.iter().zip(nums(&sample["position"])) {
        assert!((got - want).abs() < 1e-12, "{xyz:?} vs {}", sample["position"]);
    }
    assert_eq!(v["frames"].as_array().unwrap().len(), 8);

    let text = ok(&[
        "fk",
        PANDA,
        "--base",
        "panda_link0",
        "--tip",
        "panda_leftfinger",
        "0",
        "-17",
        "0",
        "-126",
        "0",
        "115",
        "45",
        "0.02",
    ]);
    assert!(!text.is_empty());
    // Seven values for eight joints: the count is named, not a cut-off chain.
    fails(
        &["fk", PANDA, "--base", "panda_link0", "--tip", "panda_leftfinger", "0", "-17", "0", "-126", "0", "115", "45"],
        2,
        &["8"],
    );
}

/// The right finger's joint mimics the left finger's, which is off that chain: 7 joints, and
/// `robot show` says the finger is held at its offset.
#[test]
fn panda_right_finger_chain_says_its_mimic_is_fixed() {
    let base_tip = ["--base", "panda_link0", "--tip", "panda_rightfinger"];
    let mut args = vec!["fk", PANDA];
    args.extend(base_tip);
    args.extend(["0", "-17", "0", "-126", "0", "115", "45"]);
    ok(&args);
    let mut args = vec!["robot", "show", PANDA];
    args.extend(base_tip);
    let text = ok(&args);
    assert!(text.contains("`panda_finger_joint2` mimics `panda_finger_joint1`, which is off the chain"), "{text}");
}

#[test]
fn undeclared_parent_link_is_named() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/panda.urdf")).unwrap();
    let broken = text.replacen(r#"<link name="panda_link3">"#, r#"<link name="panda_link3x">"#, 1);
    let path = temp_file("panda_broken.urdf", &broken);
    fails(&["fk", path.to_str().unwrap(), "0", "0"], 2, &["joint `panda_joint3`", "`panda_link3` is not declared"]);
}

/// `--joint-limits` reads MoveIt's `joint_limits.yaml` into a URDF robot; a bad value names
/// the joint and the field, and a preset refuses the flag.
#[test]
fn moveit_joint_limits_file_sets_acceleration_and_jerk() {
    let yaml = "joint_limits:\n  panda_joint1:\n    has_acceleration_limits: true\n    max_acceleration: 3.75\n  \
                panda_joint2:\n    has_jerk_limits: true\n    max_jerk: 100\n";
    let file = temp_file("joint_limits.yaml", yaml);
    let path = file.to_str().unwrap();
    let v = json(&["robot", "show", PANDA, "--tip", "panda_hand", "--joint-limits", path, "--json"]);
    assert_eq!(v["joints"][0]["max_acceleration"], 3.75);
    assert_eq!(v["joints"][1]["max_jerk"], 100.0);
    assert!(v["joints"][2]["max_acceleration"].is_null());

    let bad = temp_file("joint_limits.yaml", &yaml.replace("100", "-1"));
    fails(
        &["robot", "show", PANDA, "--tip", "panda_hand", "--joint-limits", bad.to_str().unwrap()],
        2,
        &["panda_joint2", "max_jerk"],
    );
    fails(&["robot", "show", "panda", "--joint-limits", path], 2, &["--joint-limits", "URDF robots only"]);
}
