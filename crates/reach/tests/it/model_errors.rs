//! Error paths of the model and kinematics entry points: every bad value is rejected with a
//! typed error whose message names the joint, the field or the position in the file.

use nalgebra::{Isometry3, Translation3};
use reach::kinematics::KinematicsError;
use reach::model::{Convention, DhParams, Joint, JointGeometry, LinkGeometry, RobotSpec, presets};
use reach::{Jacobian, ModelError, Robot};

/// A valid two-joint file; `{J2}` is replaced by extra lines for joint 2.
const TWO_JOINTS: &str = r#"name = "two"
length_unit = "mm"
angle_unit = "deg"

[[joints]]
name = "shoulder"
a = 300
limits = [-90, 90]

[[joints]]
name = "elbow"
a = 200
{J2}
"#;

fn with_joint2(extra: &str) -> String {
    TWO_JOINTS.replace("{J2}", extra)
}

fn two_link() -> Robot {
    Robot::from_toml_str(&with_joint2("")).unwrap()
}

#[test]
fn the_template_itself_is_valid() {
    let robot = two_link();
    assert_eq!(robot.dof(), 2);
    assert_eq!(robot.joints()[1].name, "elbow");
}

// ---------------------------------------------------------------------------------------
// Non-finite numbers.
// ---------------------------------------------------------------------------------------

#[test]
fn nan_or_infinity_in_every_dh_field_names_joint_and_field() {
    // The field names are those of the file; `theta` is the angle offset.
    for field in ["a", "alpha", "d", "theta"] {
        for literal in ["nan", "inf", "-inf", "+nan"] {
            // Replace joint 2's `a = 200` when the field is `a`, else add the field.
            let text = if field == "a" {
                TWO_JOINTS.replace("a = 200\n{J2}", &format!("a = {literal}\n"))
            } else {
                with_joint2(&format!("{field} = {literal}"))
            };
            let err = Robot::from_toml_str(&text).unwrap_err();
            match &err {
                ModelError::NonFinite { joint, name, field: f, value } => {
                    assert_eq!((*joint, name.as_str(), *f), (2, "elbow", field), "{literal}");
                    assert!(!value.is_finite());
                }
                other => panic!("{field} = {literal}: expected NonFinite, got {other:?}"),
            }
            let message = err.to_string();
            assert!(message.contains("joint 2 (elbow)") && message.contains(&format!("`{field}`")), "{message}");
        }
    }
}

#[test]
fn non_finite_values_through_robot_spec_are_rejected() {
    let third = Joint::revolute(0.1, 0.0, 0.0, 0.0);
    let p = *third.dh().unwrap();
    let spoiled = [
        ("a", Joint { geometry: JointGeometry::Dh(DhParams { a: f64::NAN, ..p }), ..third.clone() }),
        ("alpha", Joint { geometry: JointGeometry::Dh(DhParams { alpha: f64::INFINITY, ..p }), ..third.clone() }),
        ("d", Joint { geometry: JointGeometry::Dh(DhParams { d: f64::NEG_INFINITY, ..p }), ..third.clone() }),
        ("theta", Joint { geometry: JointGeometry::Dh(DhParams { theta_offset: f64::NAN, ..p }), ..third.clone() }),
        ("home", Joint { home: f64::NAN, ..third.clone() }),
    ];
    for (field, joint) in spoiled {
        let joints = vec![Joint::revolute(0.3, 0.0, 0.0, 0.0), Joint::revolute(0.2, 0.0, 0.0, 0.0), joint];
        let err = Robot::new(RobotSpec::new("r", Convention::Mdh, joints)).unwrap_err();
        assert!(matches!(&err, ModelError::NonFinite { joint: 3, field: f, .. } if *f == field), "{field}: {err:?}");
        assert!(err.to_string().contains("joint 3 (joint3)"), "{err}");
    }
}

#[test]
fn non_finite_base_tool_velocity_home_and_radius_are_rejected() {
    let base =
        with_joint2("").replace("angle_unit = \"deg\"\n", "angle_unit = \"deg\"\nbase = { xyz = [0, nan, 0] }\n");
    let err = Robot::from_toml_str(&base).unwrap_err();
    assert!(matches!(&err, ModelError::Transform { which, .. } if which == "base"), "{err:?}");
    let tool =
        with_joint2("").replace("angle_unit = \"deg\"\n", "angle_unit = \"deg\"\ntool = { rpy = [0, inf, 0] }\n");
    let err = Robot::from_toml_str(&tool).unwrap_err();
    assert!(matches!(&err, ModelError::Transform { which, .. } if which == "tool"), "{err:?}");
    assert!(err.to_string().contains("`tool`"), "{err}");

    for extra in
        ["max_velocity = nan", "max_velocity = inf", "max_velocity = 0", "max_velocity = -3", "max_velocity_rpm = nan"]
    {
        let err = Robot::from_toml_str(&with_joint2(extra)).unwrap_err();
        assert!(matches!(&err, ModelError::VelocityLimit { joint: 2, .. }), "{extra}: {err:?}");
    }
    let err = Robot::from_toml_str(&with_joint2("home = nan")).unwrap_err();
    assert!(matches!(&err, ModelError::NonFinite { joint: 2, field: "home", .. }), "{err:?}");
    let err = Robot::from_toml_str(&format!("{}\n[[links]]\nradius = 10\n[[links]]\nradius = nan\n", with_joint2("")))
        .unwrap_err();
    assert!(matches!(&err, ModelError::Links(m) if m.contains("link 2") && m.contains("radius")), "{err:?}");
}

// ---------------------------------------------------------------------------------------
// Limits, home, joints, links.
// ---------------------------------------------------------------------------------------

#[test]
fn unordered_or_empty_or_nan_limits_are_rejected() {
    for limits in ["[90, -90]", "[10, 10]", "[nan, 90]", "[-90, nan]", "[inf, inf]"] {
        let err = Robot::from_toml_str(&with_joint2(&format!("limits = {limits}\nhome = 0"))).unwrap_err();
        match &err {
            ModelError::LimitsOrder { joint: 2, name, .. } => assert_eq!(name, "elbow"),
            other => panic!("limits = {limits}: {other:?}"),
        }
        assert!(err.to_string().contains("joint 2 (elbow)"), "{err}");
    }
    // Unlimited on one side is fine.
    assert!(Robot::from_toml_str(&with_joint2("limits = [-inf, 90]")).is_ok());
}

#[test]
fn home_outside_limits_is_rejected() {
    let err = Robot::from_toml_str(&with_joint2("limits = [-90, 90]\nhome = 120")).unwrap_err();
    match &err {
        ModelError::Joint { joint: 2, name, message } => {
            assert_eq!(name, "elbow");
            assert!(message.contains("home") && message.contains("outside"), "{message}");
        }
        other => panic!("{other:?}"),
    }
    // Without an explicit home, a range excluding 0 gets its middle: [30°, 90°] → 60°.
    let robot = Robot::from_toml_str(&with_joint2("limits = [30, 90]")).unwrap();
    assert!((robot.home()[1] - 60f64.to_radians()).abs() < 1e-15);
    // Through the spec: the default home 0 of `Joint::revolute` lies outside [0.5, 1].
    let spec = RobotSpec::new("r", Convention::Dh, vec![Joint::revolute(1.0, 0.0, 0.0, 0.0).with_limits(0.5, 1.0)]);
    assert!(matches!(Robot::new(spec).unwrap_err(), ModelError::Joint { joint: 1, .. }));
}

#[test]
fn no_joints_is_rejected() {
    let err = Robot::new(RobotSpec::new("empty", Convention::Dh, vec![])).unwrap_err();
    assert_eq!(err, ModelError::NoJoints);
    let text = "name = \"empty\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\njoints = []\n";
    assert_eq!(Robot::from_toml_str(text).unwrap_err(), ModelError::NoJoints);
}

#[test]
fn links_count_mismatch_is_rejected() {
    let text = format!("{}\n[[links]]\nradius = 10\n", with_joint2(""));
    let err = Robot::from_toml_str(&text).unwrap_err();
    assert!(matches!(&err, ModelError::Links(m) if m.contains("1 link entries for 2 joints")), "{err:?}");
    let mut spec = RobotSpec::new("r", Convention::Dh, vec![Joint::revolute(1.0, 0.0, 0.0, 0.0)]);
    spec.links = vec![LinkGeometry { radius: 0.1 }; 3];
    assert!(matches!(Robot::new(spec.clone()).unwrap_err(), ModelError::Links(_)));
    spec.links = vec![LinkGeometry { radius: -0.1 }];
    assert!(matches!(Robot::new(spec.clone()).unwrap_err(), ModelError::Links(m) if m.contains("link 1")));
    spec.links = vec![LinkGeometry { radius: 0.1 }];
    assert!(Robot::new(spec).is_ok());
}

#[test]
fn a_dh_joint_in_a_urdf_robot_is_rejected() {
    let spec = RobotSpec::new("r", Convention::Urdf, vec![Joint::revolute(1.0, 0.0, 0.0, 0.0)]);
    let err = Robot::new(spec).unwrap_err();
    assert!(matches!(err, ModelError::MixedConvention { joint: 1, convention: "urdf", .. }), "{err:?}");
}

#[test]
fn both_velocity_forms_or_rpm_on_a_prismatic_joint_are_rejected() {
    let err = Robot::from_toml_str(&with_joint2("max_velocity = 10\nmax_velocity_rpm = 5")).unwrap_err();
    assert!(matches!(&err, ModelError::Joint { joint: 2, message, .. } if message.contains("not both")), "{err:?}");
    let err = Robot::from_toml_str(&with_joint2("kind = \"prismatic\"\nmax_velocity_rpm = 5")).unwrap_err();
    assert!(matches!(&err, ModelError::Joint { joint: 2, message, .. } if message.contains("revolute")), "{err:?}");
}

// ---------------------------------------------------------------------------------------
// Parse errors carry line and column.
// ---------------------------------------------------------------------------------------

fn parse_error(text: &str) -> (usize, usize, String) {
    match Robot::from_toml_str(text).unwrap_err() {
        ModelError::Parse { line, column, message } => (line, column, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

#[test]
fn unknown_field_reports_line_and_column() {
    // `lenght` on line 13 (joint 2), column 1.
    let text = with_joint2("lenght = 5");
    assert_eq!(text.lines().nth(12), Some("lenght = 5"));
    let (line, column, message) = parse_error(&text);
    assert_eq!((line, column), (13, 1), "{message}");
    assert!(message.contains("lenght"), "{message}");
    let err = Robot::from_toml_str(&text).unwrap_err().to_string();
    assert!(err.starts_with("robot file, line 13, column 1:"), "{err}");

    // An unknown top-level key.
    let text = with_joint2("").replace("angle_unit = \"deg\"\n", "angle_unit = \"deg\"\ncolour = \"red\"\n");
    let (line, column, message) = parse_error(&text);
    assert_eq!((line, column), (4, 1), "{message}");
    assert!(message.contains("colour"), "{message}");
    // An unknown key in an inline table.
    let text = with_joint2("")
        .replace("angle_unit = \"deg\"\n", "angle_unit = \"deg\"\nbase = { xyz = [0, 0, 0], ypr = [0, 0, 0] }\n");
    let (line, column, message) = parse_error(&text);
    assert_eq!(line, 4, "{message}");
    assert!(column > 1 && message.contains("ypr"), "{column}: {message}");
}

#[test]
fn syntax_type_and_missing_field_errors_report_positions() {
    // Syntax error on line 7 (`a = = 300`).
    let text = with_joint2("").replace("a = 300", "a = = 300");
    let (line, _, _) = parse_error(&text);
    assert_eq!(line, 7);
    // A string where a number belongs, line 7.
    let text = with_joint2("").replace("a = 300", "a = \"300\"");
    let (line, column, _) = parse_error(&text);
    assert_eq!((line, column), (7, 5));
    // Unknown unit.
    let text = with_joint2("").replace("\"mm\"", "\"inch\"");
    let (line, _, message) = parse_error(&text);
    assert_eq!(line, 2, "{message}");
    // Unknown convention and kind.
    let (_, _, message) = parse_error(&format!("convention = \"xyz\"\n{}", with_joint2("")));
    assert!(message.contains("xyz") || message.contains("variant"), "{message}");
    let (line, _, _) = parse_error(&with_joint2("kind = \"spherical\""));
    assert_eq!(line, 13);
    // Missing `length_unit`: reported (position may be the document start).
    let (_, _, message) = parse_error(&with_joint2("").replace("length_unit = \"mm\"\n", ""));
    assert!(message.contains("length_unit"), "{message}");
}

// ---------------------------------------------------------------------------------------
// Kinematics entry points.
// ---------------------------------------------------------------------------------------

#[test]
fn wrong_joint_count_is_rejected_by_every_entry_point() {
    let robot = presets::get("puma560").unwrap();
    for q in [&[0.0; 5][..], &[0.0; 7][..], &[][..]] {
        let expected = KinematicsError::JointCount { expected: 6, found: q.len() };
        assert_eq!(robot.fk(q).unwrap_err(), expected);
        assert_eq!(robot.fk_matrix(q).unwrap_err(), expected);
        assert_eq!(robot.jacobian(q).unwrap_err(), expected);
        assert_eq!(robot.frames(q).unwrap_err(), expected);
        assert_eq!(robot.joint_positions(q).unwrap_err(), expected);
        assert_eq!(robot.manipulability(q).unwrap_err(), expected);
        let mut j = Jacobian::zeros(6);
        assert_eq!(robot.jacobian_into(q, &mut j).unwrap_err(), expected);
    }
    let message = robot.fk(&[0.0; 5]).unwrap_err().to_string();
    assert!(message.contains('6') && message.contains('5'), "{message}");
}

#[test]
fn nan_or_infinite_joint_values_name_the_joint() {
    let robot = presets::get("ur5").unwrap();
    for (index, value) in [(0, f64::NAN), (3, f64::INFINITY), (5, f64::NEG_INFINITY)] {
        let mut q = [0.1; 6];
        q[index] = value;
        let check = |err: KinematicsError| match err {
            KinematicsError::NonFinite { joint, value: v } => {
                assert_eq!(joint, index + 1);
                assert!(!v.is_finite());
            }
            other => panic!("{other:?}"),
        };
        check(robot.fk(&q).unwrap_err());
        check(robot.fk_matrix(&q).unwrap_err());
        check(robot.jacobian(&q).unwrap_err());
        check(robot.frames(&q).unwrap_err());
        check(robot.manipulability(&q).unwrap_err());
        let mut j = Jacobian::zeros(6);
        check(robot.jacobian_into(&q, &mut j).unwrap_err());
        let message = robot.fk(&q).unwrap_err().to_string();
        assert!(message.contains(&format!("joint {}", index + 1)), "{message}");
    }
}

#[test]
fn wrong_buffer_sizes_are_rejected() {
    let robot = presets::get("panda").unwrap();
    let q = robot.home();
    for cols in [0, 6, 8] {
        let mut j = Jacobian::zeros(cols);
        let err = robot.jacobian_into(&q, &mut j).unwrap_err();
        assert!(matches!(err, KinematicsError::BufferSize { expected: 7, found, .. } if found == cols), "{err:?}");
        assert!(j.iter().all(|&v| v == 0.0), "the buffer is left untouched");
    }
    let mut frames = vec![nalgebra::IsometryMatrix3::identity(); 3];
    let err = robot.frames_into(&q, &mut frames).unwrap_err();
    assert!(matches!(err, KinematicsError::BufferSize { expected: 7, found: 3, .. }), "{err:?}");
    let mut j = Jacobian::zeros(7);
    robot.jacobian_into(&q, &mut j).unwrap();
    assert_eq!(j, robot.jacobian(&q).unwrap());
}

#[test]
fn with_tool_and_with_base_validate() {
    let robot = presets::get("puma560").unwrap();
    let bad = Isometry3::from_parts(Translation3::new(f64::NAN, 0.0, 0.0), nalgebra::UnitQuaternion::identity());
    assert!(matches!(robot.with_tool(bad).unwrap_err(), ModelError::Transform { which, .. } if which == "tool"));
    assert!(matches!(robot.with_base(bad).unwrap_err(), ModelError::Transform { which, .. } if which == "base"));
    let moved = robot.with_base(Isometry3::translation(0.0, 0.0, 1.0)).unwrap();
    let (a, b) = (robot.fk_matrix(&[0.0; 6]).unwrap(), moved.fk_matrix(&[0.0; 6]).unwrap());
    assert!((b.translation.vector.z - a.translation.vector.z - 1.0).abs() < 1e-15);
}

/// A range open on one side that excludes 0, with no `home` given: home is the finite bound
/// (the middle of the range would be infinite).
#[test]
fn default_home_of_a_half_open_range_is_its_finite_bound() {
    let robot = Robot::from_toml_str(&with_joint2("limits = [10, inf]")).unwrap();
    assert!((robot.home()[1] - 10f64.to_radians()).abs() < 1e-15);
    let robot = Robot::from_toml_str(&with_joint2("limits = [-inf, -20]")).unwrap();
    assert!((robot.home()[1] + 20f64.to_radians()).abs() < 1e-15);
    let urdf = r#"<robot name="r"><link name="a"/><link name="b"/>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="0.5" upper="inf" effort="1" velocity="1"/></joint></robot>"#;
    let robot = Robot::from_urdf_str(urdf, &reach::model::UrdfChain::default()).unwrap();
    assert_eq!(robot.home(), vec![0.5]);
}
