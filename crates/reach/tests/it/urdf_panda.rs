//! URDF as people write it: the Franka Panda (`examples/panda.urdf`, with its `<mimic>` finger
//! joint) and a made-up arm with mimic joints on its chain (`tests/data/mimic_arm.urdf`),
//! against Pinocchio (`tests/data/panda_urdf_reference.json`, written by
//! `bench/peers/urdf_reference.py`); and the loader's refusals, each naming the joint.

use crate::common::{fd_jacobian, max_abs_diff};
use nalgebra::{Matrix3, Unit, Vector3};
use reach::model::{Convention, Joint, JointGeometry, JointKind, Limits, MimicJoint, RobotSpec, UrdfChain};
use reach::{ModelError, Robot};

const PANDA: &str = include_str!("../../../../examples/panda.urdf");
const MIMIC_ARM: &str = include_str!("../data/mimic_arm.urdf");
const REFERENCE: &str = include_str!("../data/panda_urdf_reference.json");

fn chain(base: &str, tip: &str) -> UrdfChain {
    UrdfChain { base: Some(base.into()), tip: Some(tip.into()) }
}

fn load(text: &str, base: &str, tip: &str) -> Robot {
    Robot::from_urdf_str(text, &chain(base, tip)).unwrap_or_else(|e| panic!("{base} → {tip}: {e}"))
}

fn urdf_message(result: Result<Robot, ModelError>) -> String {
    match result {
        Err(ModelError::Urdf(message)) => message,
        Err(other) => panic!("expected a URDF error, got {other:?}"),
        Ok(robot) => panic!("expected a URDF error, got a robot with {} joints", robot.dof()),
    }
}

fn numbers(v: &serde_json::Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

/// Every case of the Pinocchio fixture: the chain's joint names, then FK (position and
/// rotation) to 1e-12 and the geometric Jacobian, mimic chain rule included, to 1e-12 on each
/// of the 100 configurations.
#[test]
fn fk_and_jacobian_match_pinocchio() {
    let reference: serde_json::Value = serde_json::from_str(REFERENCE).unwrap();
    let cases = reference["cases"].as_array().unwrap();
    assert_eq!(cases.len(), 5);
    for case in cases {
        let (base, tip) = (case["base"].as_str().unwrap(), case["tip"].as_str().unwrap());
        let text = if case["urdf"] == "examples/panda.urdf" { PANDA } else { MIMIC_ARM };
        let robot = load(text, base, tip);
        let names: Vec<&str> = case["joints"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
        let ours: Vec<&str> = robot.joints().iter().map(|j| j.name.as_str()).collect();
        assert_eq!(ours, names, "{tip}");
        let samples = case["samples"].as_array().unwrap();
        assert_eq!(samples.len(), 100);
        for s in samples {
            let q = numbers(&s["q"]);
            let t = robot.fk_matrix(&q).unwrap();
            let p = Vector3::from_vec(numbers(&s["position"]));
            let rows: Vec<Vec<f64>> = s["rotation"].as_array().unwrap().iter().map(numbers).collect();
            let r = Matrix3::from_fn(|i, k| rows[i][k]);
            assert!(max_abs_diff(&t.translation.vector, &p) < 1e-12, "{tip} {q:?}: {} vs {p}", t.translation.vector);
            assert!(max_abs_diff(t.rotation.matrix(), &r) < 1e-12, "{tip} {q:?}");
            let jac_rows: Vec<Vec<f64>> = s["jacobian"].as_array().unwrap().iter().map(numbers).collect();
            let expected = reach::Jacobian::from_fn(robot.dof(), |i, k| jac_rows[i][k]);
            let jac = robot.jacobian(&q).unwrap();
            assert!(max_abs_diff(&jac, &expected) < 1e-12, "{tip} {q:?}:\n{jac}\nvs Pinocchio\n{expected}");
        }
    }
}

/// The Jacobian is the derivative of FK, also through mimic joints before the first joint,
/// between joints (revolute on a tilted axis, prismatic) and following a later joint.
#[test]
fn jacobian_is_the_derivative_of_fk_through_mimic_joints() {
    let robot = load(MIMIC_ARM, "base", "tool");
    assert_eq!(robot.mimics().len(), 3);
    for q in [[0.0, 0.0, 0.0], [0.4, -0.7, 1.1], [-2.0, 1.2, -1.9]] {
        let jac = robot.jacobian(&q).unwrap();
        let fd = fd_jacobian(&robot, &q, 1e-6);
        assert!(max_abs_diff(&jac, &fd) < 1e-8, "{q:?}:\n{jac}\nvs finite differences\n{fd}");
    }
    // Without the chain rule the master's column misses the mimic's contribution: joint 1
    // (master of the tilted revolute `joint3`, multiplier −2) is far from its own column.
    let q = [0.4, -0.7, 1.1];
    let frames = robot.frames(&q).unwrap();
    let tool = robot.fk_matrix(&q).unwrap();
    let z1 = frames[0].rotation.matrix().column(2).into_owned();
    let own = z1.cross(&(tool.translation.vector - frames[0].translation.vector));
    let jac = robot.jacobian(&q).unwrap();
    assert!((jac.fixed_view::<3, 1>(0, 0) - own).norm() > 0.1);
}

#[test]
fn panda_chains_count_only_independent_joints() {
    let hand = load(PANDA, "panda_link0", "panda_hand");
    assert_eq!(hand.dof(), 7);
    assert!(hand.has_dynamics());
    let left = load(PANDA, "panda_link0", "panda_leftfinger");
    assert_eq!(left.dof(), 8);
    assert_eq!(left.joints()[7].name, "panda_finger_joint1");
    assert_eq!(left.joints()[7].kind, JointKind::Prismatic);
    assert_eq!(left.joints()[7].limits, Limits::new(0.0, 0.04));
    assert!(left.mimics().is_empty());
    // The right finger's joint mimics the left finger's, which is not on this chain.
    let right = load(PANDA, "panda_link0", "panda_rightfinger");
    assert_eq!(right.dof(), 7);
    assert!(right.mimics().is_empty());
    assert!(
        right.description().contains(
            "joint `panda_finger_joint2` mimics `panda_finger_joint1`, which is off the chain: fixed at its offset 0 m"
        ),
        "{}",
        right.description()
    );
    assert!(!left.description().contains("mimics"), "{}", left.description());
}

/// Off the chain, the mimic joint is fixed at its offset: `side_tip`'s chain holds the turret
/// joint (master `joint5` off this chain) at 0 rad, and `side_follower` follows `side_master`.
#[test]
fn mimic_with_master_off_the_chain_is_fixed_at_its_offset_and_said() {
    let robot = load(MIMIC_ARM, "base", "side_tip");
    assert_eq!(robot.dof(), 3);
    assert_eq!(robot.mimics().len(), 1);
    let m = &robot.mimics()[0];
    assert_eq!((m.name.as_str(), m.master, m.multiplier, m.offset), ("side_follower", 2, 2.0, 0.1));
    assert!(
        robot
            .description()
            .contains("joint `turret_joint` mimics `joint5`, which is off the chain: fixed at its offset 0 rad")
    );
    // A non-zero offset turns the fixed joint: the turret at 0.25 rad moves the tip as if
    // the whole arm were turned by 0.25 rad about the base z axis (the turret axis).
    let turned =
        MIMIC_ARM.replace(r#"<mimic joint="joint5" multiplier="0.5"/>"#, r#"<mimic joint="joint5" offset="0.25"/>"#);
    let turned = load(&turned, "base", "side_tip");
    assert!(turned.description().contains("fixed at its offset 0.25 rad"), "{}", turned.description());
    let q = [0.3, -0.2, 0.5];
    let a = robot.fk_matrix(&q).unwrap().translation.vector;
    let b = turned.fk_matrix(&q).unwrap().translation.vector;
    let rz = nalgebra::Rotation3::from_axis_angle(&Vector3::z_axis(), 0.25);
    assert!(max_abs_diff(&(rz * a), &b) < 1e-15, "{a} {b}");
}

#[test]
fn mimic_chain_with_masses_has_no_dynamics_and_says_so() {
    let massive = MIMIC_ARM.replace(
        r#"<link name="link3"/>"#,
        r#"<link name="link3"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>"#,
    );
    let robot = load(&massive, "base", "tool");
    assert!(!robot.has_dynamics());
    assert!(robot.description().contains("no dynamics"), "{}", robot.description());
}

fn panda_with(from: &str, to: &str) -> String {
    assert!(PANDA.contains(from), "{from}");
    PANDA.replacen(from, to, 1)
}

#[test]
fn undeclared_parent_link_is_named_not_cut_off() {
    // Without the `panda_link3` declaration, joint 3 used to start a separate tree, and the
    // chain silently ended at link 2.
    let text = panda_with(r#"<link name="panda_link3">"#, r#"<link name="panda_link3_renamed">"#);
    let message = urdf_message(Robot::from_urdf_str(&text, &UrdfChain::default()));
    assert!(
        message.contains("joint `panda_joint3`") && message.contains("link `panda_link3` is not declared"),
        "{message}"
    );
    let message = urdf_message(Robot::from_urdf_str(&text, &chain("panda_link0", "panda_hand")));
    assert!(message.contains("joint `panda_joint3`"), "{message}");
}

#[test]
fn cycle_is_rejected_naming_a_joint_on_it() {
    // A cycle beside the arm: the arm's chain is fine, the file is not a tree.
    let text = panda_with(
        "</robot>",
        r#"<link name="a"/><link name="b"/>
  <joint name="ab" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="ba" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>"#,
    );
    let message = urdf_message(Robot::from_urdf_str(&text, &chain("panda_link0", "panda_hand")));
    assert!(
        message.contains("cycle") && (message.contains("joint `ab`") || message.contains("joint `ba`")),
        "{message}"
    );
}

#[test]
fn zero_axis_is_rejected_naming_the_joint_also_on_a_mimic_joint() {
    let text = panda_with(r#"<axis xyz="0 -1 0"/>"#, r#"<axis xyz="0 0 0"/>"#);
    let message = urdf_message(Robot::from_urdf_str(&text, &chain("panda_link0", "panda_rightfinger")));
    assert!(message.contains("joint `panda_finger_joint2`") && message.contains("axis"), "{message}");
    let text = MIMIC_ARM.replace(r#"<axis xyz="0 0.6 0.8"/>"#, r#"<axis xyz="0 0 0"/>"#);
    let message = urdf_message(Robot::from_urdf_str(&text, &chain("base", "tool")));
    assert!(message.contains("joint `joint3`") && message.contains("axis"), "{message}");
}

#[test]
fn floating_and_planar_joints_are_refused_naming_joint_and_type() {
    for kind in ["floating", "planar"] {
        let text = panda_with(
            r#"<joint name="panda_joint4" type="revolute">"#,
            &format!(r#"<joint name="panda_joint4" type="{kind}">"#),
        );
        let message = urdf_message(Robot::from_urdf_str(&text, &chain("panda_link0", "panda_hand")));
        assert!(message.contains(&format!("joint `panda_joint4` is a {kind} joint")), "{message}");
        assert!(!message.contains('\n'));
        // Off the chosen chain it does not matter.
        assert_eq!(load(&text, "panda_link4", "panda_hand").dof(), 3);
    }
}

#[test]
fn mimic_of_a_missing_fixed_or_mimic_joint_is_named() {
    for (master, why) in [
        ("nope", "which does not exist"),
        ("tool_joint", "which is a fixed joint"),
        ("joint3", "which is itself a mimic joint"),
    ] {
        let text = MIMIC_ARM.replace(
            r#"<mimic joint="joint2" multiplier="0.1""#,
            &format!(r#"<mimic joint="{master}" multiplier="0.1""#),
        );
        let message = urdf_message(Robot::from_urdf_str(&text, &chain("base", "tool")));
        assert_eq!(message, format!("joint `joint4` mimics joint `{master}`, {why}"));
    }
}

fn urdf_joint(name: &str, x: f64) -> Joint {
    let axis = Unit::new_normalize(Vector3::z());
    let origin = nalgebra::Isometry3::translation(x, 0.0, 0.0);
    Joint {
        name: name.into(),
        kind: JointKind::Revolute,
        geometry: JointGeometry::Axis { origin, axis },
        limits: Limits::new(-1.0, 1.0),
        max_velocity: None,
        max_acceleration: None,
        max_jerk: None,
        home: 0.0,
        drive: None,
        flip: false,
    }
}

fn mimic(master: usize, position: usize) -> MimicJoint {
    MimicJoint {
        name: "m".into(),
        kind: JointKind::Revolute,
        position,
        origin: nalgebra::Isometry3::translation(0.1, 0.0, 0.0),
        axis: Unit::new_normalize(Vector3::x()),
        master,
        multiplier: 1.0,
        offset: 0.0,
    }
}

/// `Robot::new` checks hand-built mimic joints: the master exists, the numbers are finite,
/// the order is the chain's, the convention is URDF.
#[test]
fn robot_new_checks_mimic_joints() {
    let spec = |mimics: Vec<MimicJoint>| RobotSpec {
        mimics,
        ..RobotSpec::new("m", Convention::Urdf, vec![urdf_joint("a", 0.0), urdf_joint("b", 0.3)])
    };
    assert!(Robot::new(spec(vec![mimic(1, 0), mimic(0, 2)])).is_ok());
    let message = |s: RobotSpec| match Robot::new(s) {
        Err(e @ ModelError::Mimic { .. }) => e.to_string(),
        other => panic!("expected a mimic error, got {other:?}"),
    };
    assert!(message(spec(vec![mimic(2, 1)])).contains("master joint 3 does not exist"));
    assert!(message(spec(vec![mimic(0, 2), mimic(0, 1)])).contains("out of chain order"));
    assert!(message(spec(vec![mimic(0, 3)])).contains("out of chain order"));
    assert!(message(spec(vec![MimicJoint { offset: f64::NAN, ..mimic(0, 1) }])).contains("`offset`"));
    let dh = RobotSpec {
        mimics: vec![mimic(0, 1)],
        ..RobotSpec::new("d", Convention::Dh, vec![Joint::revolute(1.0, 0.0, 0.0, 0.0)])
    };
    assert!(message(dh).contains("only in the `urdf` convention"));
}
