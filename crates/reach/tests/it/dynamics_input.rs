//! Inertial data in the description formats (TOML, URDF) and bad input to the dynamics
//! functions: every error names the joint, field or vector.

use nalgebra::{Matrix3, Vector3};
use reach::effort::dynamics::{DynamicsError, gravity_torques, inverse_dynamics, mass_matrix, trajectory_energy};
use reach::model::{LinkInertial, ModelError, Robot, UrdfChain, presets};

fn toml_robot(inertial1: &str, inertial2: &str, extra: &str) -> String {
    format!(
        r#"
name = "two"
length_unit = "mm"
angle_unit = "deg"
{extra}

[[joints]]
name = "shoulder"
a = 500
{inertial1}

[[joints]]
name = "elbow"
a = 400
{inertial2}
"#
    )
}

fn error_of(text: &str) -> String {
    Robot::from_toml_str(text).unwrap_err().to_string()
}

#[test]
fn toml_inertials_convert_millimetres_and_default_gravity() {
    let text = toml_robot(
        "inertial = { mass = 2.5, com = [-250, 0, 10], inertia = [1000, 2000, 2500, 10, -20, 30] }",
        "inertial = { mass = 1.0 }",
        "",
    );
    let robot = Robot::from_toml_str(&text).unwrap();
    assert!(robot.has_dynamics());
    let b = &robot.inertials()[0];
    assert_eq!(b.mass, 2.5);
    assert!((b.com - Vector3::new(-0.25, 0.0, 0.01)).amax() < 1e-15);
    // kg·mm² → kg·m²: × 1e-6.
    #[rustfmt::skip]
    let expected = Matrix3::new(
        1000.0, 10.0, -20.0,
        10.0, 2000.0, 30.0,
        -20.0, 30.0, 2500.0,
    ) * 1e-6;
    assert!((b.inertia - expected).amax() < 1e-18);
    assert_eq!(robot.inertials()[1], LinkInertial::point(1.0, Vector3::zeros()));
    assert_eq!(*robot.gravity(), Vector3::new(0.0, 0.0, -9.80665));
}

#[test]
fn toml_gravity_is_in_metres_per_second_squared_whatever_the_length_unit() {
    let text = toml_robot("inertial = { mass = 1 }", "inertial = { mass = 1 }", "gravity = [0, -9.81, 0]");
    let robot = Robot::from_toml_str(&text).unwrap();
    assert_eq!(*robot.gravity(), Vector3::new(0.0, -9.81, 0.0));
}

#[test]
fn toml_bad_inertials_name_the_joint_and_field() {
    let cases = [
        ("inertial = { mass = nan }", "`inertial.mass`"),
        ("inertial = { mass = -1 }", "`inertial.mass`"),
        ("inertial = { mass = 1, com = [0, inf, 0] }", "`inertial.com`"),
        ("inertial = { mass = 1, inertia = [1, 1, -1, 0, 0, 0] }", "positive semi-definite"),
        ("inertial = { mass = 1, inertia = [1, 1, 1, 5, 0, 0] }", "positive semi-definite"),
        ("inertial = { mass = 1, inertia = [1, 1, nan, 0, 0, 0] }", "`inertial.inertia`"),
    ];
    for (bad, needle) in cases {
        let message = error_of(&toml_robot("inertial = { mass = 1 }", bad, ""));
        assert!(message.contains("joint 2 (elbow)") && message.contains(needle), "{bad}: {message}");
    }
    let message = error_of(&toml_robot("inertial = { mass = 1 }", "", ""));
    assert!(message.contains("joint 2 (elbow)") && message.contains("inertial"), "{message}");
    let message = error_of(&toml_robot("inertial = { mass = 1, colour = 3 }", "inertial = { mass = 1 }", ""));
    assert!(message.contains("colour"), "{message}");
    let message = error_of(&toml_robot("inertial = { mass = 1, inertia = [1, 2, 3] }", "inertial = { mass = 1 }", ""));
    assert!(message.contains("line"), "{message}");
    let message = error_of(&toml_robot("inertial = { mass = 1 }", "inertial = { mass = 1 }", "gravity = [0, 0, nan]"));
    assert!(message.contains("gravity"), "{message}");
}

#[test]
fn spec_with_wrong_number_of_inertials_is_rejected() {
    let puma = presets::get("puma560").unwrap();
    let err = puma.with_inertials(vec![LinkInertial::zero(); 5]).unwrap_err();
    assert!(matches!(err, ModelError::Dynamics(_)), "{err}");
    assert!(err.to_string().contains("5 inertial entries for 6 joints"), "{err}");
    // Removing them is allowed and removes the dynamics.
    assert!(!puma.with_inertials(Vec::new()).unwrap().has_dynamics());
}

#[test]
fn robot_without_masses_is_a_typed_error() {
    let spbu6 = presets::get("spbu6").unwrap();
    let err = inverse_dynamics(&spbu6, &[0.0; 6], &[0.0; 6], &[0.0; 6]).unwrap_err();
    assert_eq!(err, DynamicsError::NoInertialData { robot: "spbu6".into() });
    assert!(err.to_string().contains("spbu6"));
    assert!(trajectory_energy(&spbu6, &[0.0, 1.0], &[[0.0; 6], [0.1; 6]]).is_err());
}

#[test]
fn bad_vectors_are_named() {
    let puma = presets::get("puma560").unwrap();
    let z = [0.0; 6];
    let err = inverse_dynamics(&puma, &z[..5], &z, &z).unwrap_err();
    assert_eq!(err, DynamicsError::Length { field: "q".into(), expected: 6, found: 5 });
    let err = inverse_dynamics(&puma, &z, &[0.0; 7], &z).unwrap_err();
    assert!(matches!(err, DynamicsError::Length { ref field, .. } if field == "qd"), "{err}");
    let mut nan = z;
    nan[3] = f64::NAN;
    let err = inverse_dynamics(&puma, &z, &z, &nan).unwrap_err();
    assert!(matches!(err, DynamicsError::NonFinite { ref field, .. } if field == "qdd[3]"), "{err}");
    assert!(gravity_torques(&puma, &nan).is_err());
    assert!(mass_matrix(&puma, &[0.0; 2]).is_err());
    let err = trajectory_energy(&puma, &[0.0, 1.0, 1.0], &[z, z, z]).unwrap_err();
    assert!(matches!(err, DynamicsError::Times { index: 2, .. }), "{err}");
    let err = trajectory_energy(&puma, &[0.0, 1.0], &[z]).unwrap_err();
    assert!(matches!(err, DynamicsError::Length { .. }), "{err}");
    let err = trajectory_energy(&puma, &[0.0, f64::NAN], &[z, z]).unwrap_err();
    assert!(matches!(err, DynamicsError::NonFinite { ref field, .. } if field == "times[1]"), "{err}");
}

/// A chain with inertials: link1's inertial frame is turned 90° about z, link2 carries a fixed
/// child `link2b` (folded in), the tool link is folded into link3, the base mass is ignored.
const URDF: &str = r#"<?xml version="1.0"?>
<robot name="massive">
  <link name="base_link">
    <inertial><mass value="50"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial>
  </link>
  <link name="link1">
    <inertial>
      <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
      <mass value="2"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.025"/>
    </inertial>
  </link>
  <link name="link2">
    <inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <link name="link2b">
    <inertial><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <link name="link3">
    <inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>
  </link>
  <link name="tool0">
    <inertial><mass value="0.5"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>
  </link>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="link1"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 0.2" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="1" velocity="1"/>
  </joint>
  <joint name="mid" type="fixed">
    <parent link="link2"/><child link="link2b"/><origin xyz="0.3 0 0"/>
  </joint>
  <joint name="j3" type="prismatic">
    <parent link="link2b"/><child link="link3"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/><limit lower="0" upper="0.3" effort="1" velocity="1"/>
  </joint>
  <joint name="tool" type="fixed">
    <parent link="link3"/><child link="tool0"/><origin xyz="0 0 0.2" rpy="0 1.5707963267948966 0"/>
  </joint>
</robot>
"#;

#[test]
fn urdf_inertials_are_read_rotated_and_folded_by_hand() {
    let robot = Robot::from_urdf_str(URDF, &UrdfChain::default()).unwrap();
    assert_eq!(robot.dof(), 3);
    let b = robot.inertials();
    // link1: the inertial frame turned 90° about z swaps ixx and iyy.
    assert_eq!(b[0].mass, 2.0);
    assert!((b[0].com - Vector3::new(0.0, 0.0, 0.1)).amax() < 1e-15);
    assert!((b[0].inertia - Matrix3::from_diagonal(&Vector3::new(0.02, 0.01, 0.025))).amax() < 1e-15);
    // link2 + link2b: 1 kg at x = 0.1 and 1 kg at x = 0.3 → 2 kg at 0.2, ±0.1 m arms: 0.02 kg·m².
    assert_eq!(b[1].mass, 2.0);
    assert!((b[1].com - Vector3::new(0.2, 0.0, 0.0)).amax() < 1e-15);
    assert!((b[1].inertia - Matrix3::from_diagonal(&Vector3::new(0.0, 0.02, 0.02))).amax() < 1e-15);
    // link3 + tool0: 0.5 kg each, at z = 0 and z = 0.2 → 1 kg at z = 0.1; 0.001 + 2·0.5·0.01.
    assert_eq!(b[2].mass, 1.0);
    assert!((b[2].com - Vector3::new(0.0, 0.0, 0.1)).amax() < 1e-15);
    assert!((b[2].inertia - Matrix3::from_diagonal(&Vector3::new(0.011, 0.011, 0.001))).amax() < 1e-15);
}

#[test]
fn urdf_model_equals_the_hand_folded_model() {
    let imported = Robot::from_urdf_str(URDF, &UrdfChain::default()).unwrap();
    // The same chain with the folding written by hand into the links' own inertials.
    let folded = URDF
        .replace(
            r#"<inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" izz="0"/></inertial>"#,
            r#"<inertial><origin xyz="0.2 0 0"/><mass value="2"/><inertia ixx="0" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.02"/></inertial>"#,
        )
        .replace(
            r#"<inertial><mass value="0.5"/><inertia ixx="0.001" ixy="0" ixz="0" iyy="0.001" iyz="0" izz="0.001"/></inertial>"#,
            r#"<inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.011" ixy="0" ixz="0" iyy="0.011" iyz="0" izz="0.001"/></inertial>"#,
        )
        .replace(r#"<mass value="0.5"/><inertia ixx="0" "#, r#"<mass value="0"/><inertia ixx="0" "#)
        .replace(r#"<inertial><mass value="1"/><inertia ixx="0" "#, r#"<inertial><mass value="0"/><inertia ixx="0" "#);
    assert_ne!(folded, URDF);
    let by_hand = Robot::from_urdf_str(&folded, &UrdfChain::default()).unwrap();
    let (q, qd, qdd) = ([0.4, -0.8, 0.1], [1.0, 0.5, -0.2], [-2.0, 1.0, 3.0]);
    let a = inverse_dynamics(&imported, &q, &qd, &qdd).unwrap();
    let b = inverse_dynamics(&by_hand, &q, &qd, &qdd).unwrap();
    for i in 0..3 {
        assert!((a[i] - b[i]).abs() < 1e-12, "joint {}: {} vs {}", i + 1, a[i], b[i]);
    }
    assert!(a.iter().all(|t| t.abs() > 1e-3), "{a:?}");
}

#[test]
fn urdf_without_masses_has_no_dynamics() {
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/three_link.urdf")).unwrap();
    let robot = Robot::from_urdf_str(&text, &UrdfChain::default()).unwrap();
    assert!(!robot.has_dynamics());
}
