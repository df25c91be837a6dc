//! URDF import: `tests/data/three_link.urdf` against the same chain written by hand as a plain
//! product of transforms, and the import's error paths.

use crate::common::{Rng, fd_jacobian, max_abs_diff, rot_axis, tr, xyz_rpy};
use approx::assert_relative_eq;
use nalgebra::{Matrix4, Vector3};
use reach::model::{Convention, JointKind, UrdfChain};
use reach::{ModelError, Robot};

const THREE_LINK: &str = include_str!("../data/three_link.urdf");

/// The fixture by hand: each joint is `origin(xyz, rpy) · motion(axis, q)`, the fixed joint
/// `mid` is a plain origin between j2 and j3, and the fixed `tool` joint ends the chain.
/// Axes are normalised as URDF requires ((1, 0, 1) → (1, 0, 1)/√2).
///
/// Returns the frames of the three moving links' child frames and the tool pose.
fn by_hand(q: &[f64]) -> ([Matrix4<f64>; 3], Matrix4<f64>) {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let a3 = [s, 0.0, s];
    let link1 = xyz_rpy([0.0, 0.0, 0.3], [0.0, 0.0, 0.2]) * rot_axis([0.0, 0.0, -1.0], q[0]);
    let link2 = link1 * xyz_rpy([0.1, -0.05, 0.2], [0.3, -0.4, 0.1]) * rot_axis([0.0, -1.0, 0.0], q[1]);
    let link2b = link2 * xyz_rpy([0.25, 0.0, 0.02], [0.0, 0.5, 0.0]);
    let link3 = link2b * xyz_rpy([0.0, 0.05, 0.1], [0.1, 0.0, -0.2]) * tr(a3[0] * q[2], a3[1] * q[2], a3[2] * q[2]);
    let tool = link3 * xyz_rpy([0.0, 0.0, 0.12], [std::f64::consts::PI, 0.0, 0.0]);
    ([link1, link2, link3], tool)
}

/// The geometric Jacobian from the hand-built frames: a revolute joint turns about its axis
/// (world direction `R_joint · axis`) through the joint frame's origin; the prismatic one
/// slides along its axis.
fn jacobian_by_hand(q: &[f64]) -> nalgebra::Matrix6x3<f64> {
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let ([l1, l2, l3], tool) = by_hand(q);
    let p = tool.fixed_view::<3, 1>(0, 3).into_owned();
    let mut j = nalgebra::Matrix6x3::zeros();
    // The motion does not move a point on the axis, so the joint frame after the motion has
    // the same origin and the same axis direction as before it.
    for (col, (frame, axis)) in
        [(l1, Vector3::new(0.0, 0.0, -1.0)), (l2, Vector3::new(0.0, -1.0, 0.0))].iter().enumerate()
    {
        let z = frame.fixed_view::<3, 3>(0, 0) * axis;
        let o = frame.fixed_view::<3, 1>(0, 3).into_owned();
        j.fixed_view_mut::<3, 1>(0, col).copy_from(&z.cross(&(p - o)));
        j.fixed_view_mut::<3, 1>(3, col).copy_from(&z);
    }
    let z3 = l3.fixed_view::<3, 3>(0, 0) * Vector3::new(s, 0.0, s);
    j.fixed_view_mut::<3, 1>(0, 2).copy_from(&z3);
    j
}

fn import(text: &str) -> Result<Robot, ModelError> {
    Robot::from_urdf_str(text, &UrdfChain::default())
}

fn urdf_message(result: Result<Robot, ModelError>) -> String {
    match result {
        Err(ModelError::Urdf(message)) => message,
        Err(other) => panic!("expected a URDF error, got {other:?}"),
        Ok(robot) => panic!("expected a URDF error, got a robot with {} joints", robot.dof()),
    }
}

#[test]
fn fixture_imports_as_three_joints_with_limits_and_tool() {
    let robot = import(THREE_LINK).unwrap();
    assert_eq!(robot.name(), "three_link");
    assert_eq!(robot.convention(), Convention::Urdf);
    assert_eq!(robot.dof(), 3);
    let j = robot.joints();
    assert_eq!([j[0].name.as_str(), j[1].name.as_str(), j[2].name.as_str()], ["j1", "j2", "j3"]);
    assert_eq!([j[0].kind, j[1].kind, j[2].kind], [JointKind::Revolute, JointKind::Revolute, JointKind::Prismatic]);
    assert_eq!((j[0].limits.lower, j[0].limits.upper), (-2.5, 2.5));
    assert!(!j[1].limits.is_bounded(), "continuous joints are unlimited");
    assert_eq!((j[2].limits.lower, j[2].limits.upper), (0.0, 0.2));
    assert_eq!(j[0].max_velocity, Some(1.5));
    assert_eq!(j[2].max_velocity, Some(0.3));
    assert_eq!(robot.home(), vec![0.0, 0.0, 0.0]);
    // The fixed tool joint becomes the tool transform.
    let tool = xyz_rpy([0.0, 0.0, 0.12], [std::f64::consts::PI, 0.0, 0.0]);
    assert!(max_abs_diff(&robot.tool().to_homogeneous(), &tool) < 1e-15);
}

#[test]
fn fk_frames_and_jacobian_agree_with_the_hand_written_chain() {
    let robot = import(THREE_LINK).unwrap();
    let mut rng = Rng::new(0x00bd_f001);
    let mut qs: Vec<Vec<f64>> = vec![vec![0.0; 3], vec![0.7, -1.2, 0.15]];
    qs.extend((0..30).map(|_| rng.joints(&robot)));
    for q in &qs {
        let (frames, tool) = by_hand(q);
        let t = robot.fk_matrix(q).unwrap().to_homogeneous();
        assert!(max_abs_diff(&t, &tool) < 1e-12, "q={q:?}\n{t}\n{tool}");
        assert!(max_abs_diff(&robot.fk(q).unwrap().to_homogeneous(), &tool) < 1e-12);
        for (i, (f, e)) in robot.frames(q).unwrap().iter().zip(&frames).enumerate() {
            assert!(max_abs_diff(&f.to_homogeneous(), e) < 1e-12, "frame of link {} at q={q:?}", i + 1);
        }
        let j = robot.jacobian(q).unwrap();
        assert!(max_abs_diff(&j, &jacobian_by_hand(q)) < 1e-12, "q={q:?}\n{j}");
        assert!(max_abs_diff(&j, &fd_jacobian(&robot, q, 1e-6)) < 1e-6, "q={q:?}");
    }
}

/// At q = 0 the tool point, multiplied out by hand once more with different tools: the
/// position is the sum of the origins rotated by the accumulated rpy rotations.
#[test]
fn zero_configuration_tool_point() {
    let robot = import(THREE_LINK).unwrap();
    let r = |rpy: [f64; 3]| xyz_rpy([0.0; 3], rpy).fixed_view::<3, 3>(0, 0).into_owned();
    let r1 = r([0.0, 0.0, 0.2]);
    let r2 = r1 * r([0.3, -0.4, 0.1]);
    let r2b = r2 * r([0.0, 0.5, 0.0]);
    let r3 = r2b * r([0.1, 0.0, -0.2]);
    let p = Vector3::new(0.0, 0.0, 0.3)
        + r1 * Vector3::new(0.1, -0.05, 0.2)
        + r2 * Vector3::new(0.25, 0.0, 0.02)
        + r2b * Vector3::new(0.0, 0.05, 0.1)
        + r3 * Vector3::new(0.0, 0.0, 0.12);
    assert_relative_eq!(robot.fk_matrix(&[0.0; 3]).unwrap().translation.vector, p, epsilon = 1e-12);
}

#[test]
fn chosen_base_and_tip_give_a_sub_chain() {
    // From link1 to link3: joints j2 and j3, base frame = link1, no tool.
    let chain = UrdfChain { base: Some("link1".into()), tip: Some("link3".into()) };
    let robot = Robot::from_urdf_str(THREE_LINK, &chain).unwrap();
    assert_eq!(robot.dof(), 2);
    let q = [0.4, 0.1];
    let ([l1, _, l3], _) = by_hand(&[0.0, q[0], q[1]]);
    // by_hand starts at base_link; express link3 in link1's frame.
    let expected = l1.try_inverse().unwrap() * l3;
    assert!(max_abs_diff(&robot.fk_matrix(&q).unwrap().to_homogeneous(), &expected) < 1e-12);
}

/// Axes within 1e-8 of ±z (and exactly −z) keep full precision: the motion is a rotation
/// about exactly the normalised axis.
#[test]
fn nearly_vertical_axes_are_exact() {
    for axis in [[1e-8, 3e-9, 1.0], [-2e-9, 1e-8, -1.0], [0.0, 0.0, -1.0], [1e-7, 0.0, -1.0]] {
        let text = format!(
            r#"<robot name="r"><link name="a"/><link name="b"/>
  <joint name="j" type="continuous"><parent link="a"/><child link="b"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.4 0.5 0.6"/><axis xyz="{} {} {}"/></joint></robot>"#,
            axis[0], axis[1], axis[2]
        );
        let robot = import(&text).unwrap();
        let n = Vector3::from(axis).normalize();
        let q = 0.7;
        let expected = xyz_rpy([0.1, 0.2, 0.3], [0.4, 0.5, 0.6]) * rot_axis([n.x, n.y, n.z], q);
        assert!(max_abs_diff(&robot.fk_matrix(&[q]).unwrap().to_homogeneous(), &expected) < 1e-15, "{axis:?}");
        let world_axis = xyz_rpy([0.0; 3], [0.4, 0.5, 0.6]).fixed_view::<3, 3>(0, 0) * n;
        let j = robot.jacobian(&[q]).unwrap();
        assert!((j.fixed_view::<3, 1>(3, 0) - world_axis).amax() < 1e-15, "{axis:?}");
    }
}

// ---------------------------------------------------------------------------------------
// Error paths.
// ---------------------------------------------------------------------------------------

/// The fixture with a camera link hanging off link2 by a fixed joint.
fn branched() -> String {
    THREE_LINK.replace(
        "</robot>",
        r#"  <link name="camera"/>
  <joint name="camera_mount" type="fixed">
    <parent link="link2"/>
    <child link="camera"/>
    <origin xyz="0 0.1 0" rpy="0 0 0"/>
  </joint>
</robot>"#,
    )
}

#[test]
fn branched_tree_without_tip_names_the_branching_link() {
    let message = urdf_message(import(&branched()));
    assert!(message.contains("branches at link `link2`"), "{message}");
    assert!(message.contains("camera") && message.contains("link2b"), "{message}");
    // Choosing the tip resolves it, and gives the original chain.
    let chain = UrdfChain { base: None, tip: Some("tool0".into()) };
    let robot = Robot::from_urdf_str(&branched(), &chain).unwrap();
    let q = [0.3, -0.6, 0.05];
    assert!(max_abs_diff(&robot.fk_matrix(&q).unwrap().to_homogeneous(), &by_hand(&q).1) < 1e-12);
}

#[test]
fn unknown_link_names_are_reported_with_the_known_ones() {
    for chain in
        [UrdfChain { base: Some("nope".into()), tip: None }, UrdfChain { base: None, tip: Some("nope".into()) }]
    {
        let message = urdf_message(Robot::from_urdf_str(THREE_LINK, &chain));
        assert!(message.contains("`nope`") && message.contains("link2b"), "{message}");
    }
}

#[test]
fn tip_not_below_base_is_rejected() {
    let chain = UrdfChain { base: Some("link2".into()), tip: Some("link1".into()) };
    let message = urdf_message(Robot::from_urdf_str(THREE_LINK, &chain));
    assert!(message.contains("`link1` is not below link `link2`"), "{message}");
}

#[test]
fn floating_and_planar_joints_are_rejected_by_name() {
    for kind in ["floating", "planar"] {
        let text =
            THREE_LINK.replace(r#"<joint name="mid" type="fixed">"#, &format!(r#"<joint name="mid" type="{kind}">"#));
        let message = urdf_message(import(&text));
        assert!(message.contains("joint `mid`") && message.to_lowercase().contains(kind), "{message}");
    }
}

#[test]
fn mimic_of_an_unknown_joint_and_zero_axis_are_rejected() {
    let mimic = THREE_LINK.replace(r#"<axis xyz="0 -1 0"/>"#, r#"<axis xyz="0 -1 0"/><mimic joint="j9"/>"#);
    let message = urdf_message(import(&mimic));
    assert!(message.contains("joint `j2` mimics joint `j9`, which does not exist"), "{message}");
    // Following an existing joint, it is no longer a joint of the robot.
    let mimic = THREE_LINK.replace(r#"<axis xyz="0 -1 0"/>"#, r#"<axis xyz="0 -1 0"/><mimic joint="j1"/>"#);
    let robot = import(&mimic).unwrap();
    assert_eq!(robot.dof(), 2);
    assert_eq!(robot.mimics()[0].name, "j2");
    let zero = THREE_LINK.replace(r#"<axis xyz="1 0 1"/>"#, r#"<axis xyz="0 0 0"/>"#);
    let message = urdf_message(import(&zero));
    assert!(message.contains("joint `j3`") && message.contains("axis"), "{message}");
}

#[test]
fn malformed_xml_is_an_error_not_a_panic() {
    let truncated = &THREE_LINK[..THREE_LINK.len() / 2];
    let message = urdf_message(import(truncated));
    assert!(!message.is_empty() && !message.contains('\n'));
    urdf_message(import("this is not xml"));
    urdf_message(import(""));
    // Well-formed XML that is not a robot.
    urdf_message(import("<robot name=\"r\"><joint name=\"j\" type=\"revolute\"/></robot>"));
}

#[test]
fn non_finite_origin_is_rejected() {
    let text = THREE_LINK.replace(r#"xyz="0.1 -0.05 0.2""#, r#"xyz="0.1 NaN 0.2""#);
    match import(&text) {
        Err(ModelError::Transform { which, .. }) => assert!(which.contains("j2"), "{which}"),
        Err(ModelError::Urdf(_)) => {} // the XML layer may refuse the number itself
        other => panic!("expected an error, got {other:?}"),
    }
}

/// A link tree with a cycle (every link has a parent) must be reported, not loop forever.
#[test]
fn cycle_is_reported() {
    let text = r#"<robot name="loop">
  <link name="a"/><link name="b"/>
  <joint name="ab" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="ba" type="continuous"><parent link="b"/><child link="a"/><axis xyz="0 0 1"/></joint>
</robot>"#;
    let message = urdf_message(import(text));
    assert!(message.contains("cycle") && message.contains("joint `"), "{message}");
}

/// A cycle beside a proper chain, with base and tip chosen so that the walk from the tip
/// enters the cycle: the import must stop with an error instead of hanging.
#[test]
fn walk_into_a_cycle_terminates() {
    let text = r#"<robot name="loop">
  <link name="root"/><link name="x"/><link name="a"/><link name="b"/>
  <joint name="rx" type="continuous"><parent link="root"/><child link="x"/><axis xyz="0 0 1"/></joint>
  <joint name="ab" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
  <joint name="ba" type="continuous"><parent link="b"/><child link="a"/><axis xyz="0 0 1"/></joint>
</robot>"#;
    let up = UrdfChain { base: Some("root".into()), tip: Some("a".into()) };
    let message = urdf_message(Robot::from_urdf_str(text, &up));
    assert!(message.contains("not below") || message.contains("cycle"), "{message}");
    let down = UrdfChain { base: Some("a".into()), tip: None };
    let message = urdf_message(Robot::from_urdf_str(text, &down));
    assert!(message.contains("cycle"), "{message}");
}

/// URDF 1.0 requires `<limit>` on revolute joints; a missing one is named as such rather than
/// reported as the `[0, 0]` ordering error urdf-rs's default would give.
#[test]
fn revolute_joint_without_limit_is_named() {
    let text = r#"<robot name="r">
  <link name="a"/><link name="b"/>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/></joint>
</robot>"#;
    let message = urdf_message(import(text));
    assert!(message.contains("joint `j`") && message.contains("<limit"), "{message}");
}
