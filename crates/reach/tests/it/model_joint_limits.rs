//! Acceleration and jerk limits: the TOML fields, MoveIt's `joint_limits.yaml`, the Panda's
//! published values, and every bad value rejected with the joint and the field named.

use reach::model::presets;
use reach::{ModelError, Robot};

const TWO_JOINTS: &str = r#"name = "two"
length_unit = "mm"
angle_unit = "deg"

[[joints]]
name = "shoulder"
a = 300
max_velocity = 90
max_acceleration = 180
max_jerk = 3600

[[joints]]
name = "slide"
kind = "prismatic"
theta = 90
max_acceleration = {ACC}
"#;

fn two(acc: &str) -> Result<Robot, ModelError> {
    Robot::from_toml_str(&TWO_JOINTS.replace("{ACC}", acc))
}

#[test]
fn toml_limits_are_read_in_the_files_units() {
    let robot = two("500").unwrap();
    let [shoulder, slide] = robot.joints() else { panic!("two joints") };
    let deg = std::f64::consts::PI / 180.0;
    assert!((shoulder.max_velocity.unwrap() - 90.0 * deg).abs() < 1e-12);
    assert!((shoulder.max_acceleration.unwrap() - 180.0 * deg).abs() < 1e-12);
    assert!((shoulder.max_jerk.unwrap() - 3600.0 * deg).abs() < 1e-12);
    // A prismatic joint's limits are in the length unit: 500 mm/s² = 0.5 m/s².
    assert!((slide.max_acceleration.unwrap() - 0.5).abs() < 1e-12);
    assert_eq!(slide.max_jerk, None);
}

#[test]
fn zero_negative_or_nan_toml_limits_name_joint_and_field() {
    for bad in ["0", "-1", "nan", "inf"] {
        let err = two(bad).unwrap_err();
        let message = err.to_string();
        assert!(message.contains("slide") && message.contains("max_acceleration"), "{bad}: {message}");
    }
}

#[test]
fn panda_preset_carries_frankas_published_limits() {
    let panda = presets::get("panda").unwrap();
    let acc: Vec<f64> = panda.joints().iter().map(|j| j.max_acceleration.unwrap()).collect();
    let jerk: Vec<f64> = panda.joints().iter().map(|j| j.max_jerk.unwrap()).collect();
    assert_eq!(acc, [15.0, 7.5, 10.0, 12.5, 15.0, 20.0, 20.0]);
    assert_eq!(jerk, [7500.0, 3750.0, 5000.0, 6250.0, 7500.0, 10000.0, 10000.0]);
}

const LIMITS_YAML: &str = "joint_limits:
  shoulder:
    has_velocity_limits: true
    max_velocity: 2.0
    has_acceleration_limits: true
    max_acceleration: 4.0
    has_jerk_limits: false
  slide:
    has_acceleration_limits: true
    max_acceleration: 1.5
    has_jerk_limits: true
    max_jerk: 30
  gripper_finger:
    has_velocity_limits: true
    max_velocity: 0.1
";

#[test]
fn moveit_joint_limits_yaml_overrides_by_name_and_keeps_the_rest() {
    let robot = two("500").unwrap().with_moveit_joint_limits(LIMITS_YAML).unwrap();
    let [shoulder, slide] = robot.joints() else { panic!("two joints") };
    assert_eq!(shoulder.max_velocity, Some(2.0));
    assert_eq!(shoulder.max_acceleration, Some(4.0));
    // has_jerk_limits: false keeps the model's own jerk limit (3600 deg/s³).
    assert!((shoulder.max_jerk.unwrap() - 3600f64.to_radians()).abs() < 1e-12);
    assert_eq!(slide.max_acceleration, Some(1.5));
    assert_eq!(slide.max_jerk, Some(30.0));
}

#[test]
fn moveit_joint_limits_yaml_errors_say_what_is_wrong() {
    let robot = two("500").unwrap();
    let missing = "joint_limits:\n  slide:\n    has_jerk_limits: true\n";
    let message = robot.with_moveit_joint_limits(missing).unwrap_err().to_string();
    assert!(message.contains("`slide`") && message.contains("max_jerk is missing"), "{message}");

    for bad in ["-2", "0", ".nan"] {
        let text =
            format!("joint_limits:\n  shoulder:\n    has_acceleration_limits: true\n    max_acceleration: {bad}\n");
        let message = robot.with_moveit_joint_limits(&text).unwrap_err().to_string();
        assert!(message.contains("shoulder") && message.contains("max_acceleration"), "{bad}: {message}");
    }

    let not_yaml = "joint_limits: [1, 2";
    let message = robot.with_moveit_joint_limits(not_yaml).unwrap_err().to_string();
    assert!(message.starts_with("joint limits file:"), "{message}");
    let wrong_type = "joint_limits:\n  shoulder:\n    max_velocity: fast\n";
    assert!(robot.with_moveit_joint_limits(wrong_type).is_err());
}
