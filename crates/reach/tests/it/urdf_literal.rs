//! URDF forward kinematics against the file itself: for every URDF the tests and examples
//! carry, the Lynxmotion AL5D of rtb-data (origins a few 1e-10 rad off π and π/2) and
//! synthetic chains whose consecutive axes are parallel to within 1e-6 … 1e-12 rad, the tool
//! pose, the link frames and the geometric Jacobian equal the literal product of the file's
//! transforms (per joint `T_origin(xyz, rpy) · motion(axis, q)`, in URDF order) to 1e-12,
//! translations relative to the chain's length (the sum of its origins' lengths).

use crate::common::{Rng, rot_axis, tr, xyz_rpy};
use nalgebra::{Matrix4, Vector3};
use reach::Robot;
use reach::model::{UrdfChain, urdf_chain_links};

/// The chain's literal product: tool pose, the frames of the independent joints' child
/// links, the geometric Jacobian (rows: linear, angular; a mimic joint's motion adds to its
/// master's column times its multiplier; a master off the chain stands at 0) and the chain's
/// length scale.
struct Literal {
    tool: Matrix4<f64>,
    frames: Vec<Matrix4<f64>>,
    jacobian: nalgebra::DMatrix<f64>,
    scale: f64,
}

fn literal(text: &str, chain: &UrdfChain, q: &[f64]) -> Literal {
    let urdf = urdf_rs::read_from_string(text).unwrap();
    let (base, tip) = urdf_chain_links(text, chain).unwrap();
    // The joints from base to tip, found from the tip up.
    let mut path = Vec::new();
    let mut link = tip;
    while link != base {
        let j = urdf.joints.iter().find(|j| j.child.link == link).expect("a joint leads to every chain link");
        path.push(j);
        link = j.parent.link.clone();
    }
    path.reverse();
    let movable = |j: &urdf_rs::Joint| !matches!(j.joint_type, urdf_rs::JointType::Fixed);
    let independent: Vec<&str> =
        path.iter().filter(|j| movable(j) && j.mimic.is_none()).map(|j| j.name.as_str()).collect();
    assert_eq!(independent.len(), q.len());
    let mut t = Matrix4::identity();
    let mut frames = Vec::new();
    let mut scale = 0.0;
    // (joint index, multiplier, revolute, frame after the motion, axis in that frame).
    let mut motions = Vec::new();
    for j in &path {
        let o = &j.origin;
        t *= xyz_rpy(o.xyz.0, o.rpy.0);
        scale += Vector3::from(o.xyz.0).norm();
        if !movable(j) {
            continue;
        }
        let axis = Vector3::from(j.axis.xyz.0).normalize();
        let (index, multiplier, value) = match &j.mimic {
            None => {
                let i = independent.iter().position(|n| *n == j.name).unwrap();
                (Some(i), 1.0, q[i])
            }
            Some(m) => {
                let i = independent.iter().position(|n| *n == m.joint);
                let (k, c) = (m.multiplier.unwrap_or(1.0), m.offset.unwrap_or(0.0));
                (i, k, k * i.map_or(0.0, |i| q[i]) + c)
            }
        };
        let revolute = !matches!(j.joint_type, urdf_rs::JointType::Prismatic);
        t *= if revolute {
            rot_axis([axis.x, axis.y, axis.z], value)
        } else {
            tr(axis.x * value, axis.y * value, axis.z * value)
        };
        if j.mimic.is_none() {
            frames.push(t);
        }
        if let Some(i) = index {
            motions.push((i, multiplier, revolute, t, axis));
        }
    }
    let p = t.fixed_view::<3, 1>(0, 3).into_owned();
    let mut jacobian = nalgebra::DMatrix::zeros(6, q.len());
    for (i, k, revolute, f, axis) in motions {
        let w = f.fixed_view::<3, 3>(0, 0) * axis;
        let o = f.fixed_view::<3, 1>(0, 3).into_owned();
        let (v, w) = if revolute { (w.cross(&(p - o)), w) } else { (w, Vector3::zeros()) };
        for r in 0..3 {
            jacobian[(r, i)] += k * v[r];
            jacobian[(r + 3, i)] += k * w[r];
        }
    }
    Literal { tool: t, frames, jacobian, scale }
}

/// The largest gap of `got` from `want`: rotation entries as they are, translation entries
/// relative to `scale`.
fn gap(got: &Matrix4<f64>, want: &Matrix4<f64>, scale: f64) -> f64 {
    let d = got - want;
    let rotation = d.fixed_view::<3, 3>(0, 0).amax();
    let translation = d.fixed_view::<3, 1>(0, 3).amax() / scale;
    rotation.max(translation)
}

/// The largest gap of `robot`'s tool pose, link frames and Jacobian (linear rows relative to
/// the scale) from the literal product at `q`.
fn worst_gap(robot: &Robot, text: &str, chain: &UrdfChain, q: &[f64]) -> f64 {
    let want = literal(text, chain, q);
    let s = want.scale.max(f64::MIN_POSITIVE);
    let mut worst = gap(&robot.fk_matrix(q).unwrap().to_homogeneous(), &want.tool, s);
    worst = worst.max(gap(&robot.fk(q).unwrap().to_homogeneous(), &want.tool, s));
    let frames = robot.frames(q).unwrap();
    assert_eq!(frames.len(), want.frames.len());
    for (f, e) in frames.iter().zip(&want.frames) {
        worst = worst.max(gap(&f.to_homogeneous(), e, s));
    }
    let j = robot.jacobian(q).unwrap();
    for c in 0..q.len() {
        for r in 0..6 {
            let d = (j[(r, c)] - want.jacobian[(r, c)]).abs();
            worst = worst.max(if r < 3 { d / s } else { d });
        }
    }
    worst
}

/// Checks `text`'s chain at q = 0, at `extra` and at 20 random joint vectors; returns the
/// worst gap.
fn check(name: &str, text: &str, chain: &UrdfChain, extra: &[Vec<f64>]) -> f64 {
    let robot = Robot::from_urdf_str(text, chain).unwrap_or_else(|e| panic!("{name}: {e}"));
    let mut rng = Rng::new(0x0011_e7a1);
    let mut qs = vec![vec![0.0; robot.dof()]];
    qs.extend(extra.iter().cloned());
    qs.extend((0..20).map(|_| rng.joints(&robot)));
    let mut worst: f64 = 0.0;
    for q in &qs {
        let g = worst_gap(&robot, text, chain, q);
        assert!(g <= 1e-12, "{name}: gap {g:e} from the literal product at q = {q:?}");
        worst = worst.max(g);
    }
    worst
}

const AL5D: &str = include_str!("../data/al5d_robot.urdf");

#[test]
fn al5d_is_the_literal_product_of_its_file() {
    let worst = check("AL5D", AL5D, &UrdfChain::default(), &[vec![0.3, 0.0, 0.0, 0.0], vec![0.0, 0.4, -0.7, 1.1]]);
    eprintln!("AL5D: worst gap {worst:e}");
}

#[test]
fn every_urdf_file_is_the_literal_product_of_its_file() {
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let files: [(&str, Option<&str>, Option<&str>); 10] = [
        ("examples/panda.urdf", Some("panda_link0"), Some("panda_hand")),
        ("crates/reach/tests/data/three_link.urdf", None, None),
        ("crates/reach/tests/data/mimic_arm.urdf", Some("base"), Some("tool")),
        ("crates/reach/tests/data/ur5/ur5.urdf", None, Some("ee_link")),
        ("crates/reach/tests/data/mbm/panda.urdf", Some("panda_link0"), Some("panda_hand")),
        ("crates/reach/tests/data/mbm/panda_spherized.urdf", Some("panda_link0"), Some("panda_hand")),
        ("examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf", Some("base_link"), Some("tool0")),
        ("examples/urdf/unimation_puma560_description/urdf/puma560_robot.urdf", None, None),
        ("examples/urdf/ur_description/urdf/ur5.urdf", None, Some("ee_link")),
        ("examples/urdf/kuka_kr120_support/urdf/kr120r2500pro.urdf", Some("base_link"), Some("tool0")),
    ];
    for (path, base, tip) in files {
        let text = std::fs::read_to_string(format!("{root}/{path}")).unwrap();
        let chain = UrdfChain { base: base.map(Into::into), tip: tip.map(Into::into) };
        let worst = check(path, &text, &chain, &[]);
        eprintln!("{path}: worst gap {worst:e}");
    }
}

/// A four-joint chain whose consecutive axes are parallel (`flip`: antiparallel) to within
/// `tilt` rad, each next axis offset from the last.
fn near_parallel(tilt: f64, flip: bool) -> String {
    let roll = if flip { std::f64::consts::PI - tilt } else { tilt };
    let mut text = String::from(r#"<robot name="near_parallel"><link name="l0"/>"#);
    for i in 1..=4 {
        let (xyz, rpy) = if i == 1 {
            ("0 0 0.1".to_string(), "0 0 0".to_string())
        } else {
            ("0.25 0.05 0.03".to_string(), format!("{roll:e} {:e} 0.3", 0.5 * tilt))
        };
        text += &format!(
            r#"<link name="l{i}"/><joint name="j{i}" type="continuous"><parent link="l{}"/><child link="l{i}"/>
  <origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/></joint>"#,
            i - 1
        );
    }
    text += r#"<link name="tool"/><joint name="t" type="fixed"><parent link="l4"/><child link="tool"/>
  <origin xyz="0.1 0 0.02" rpy="0 0 0"/></joint></robot>"#;
    text
}

#[test]
fn nearly_parallel_axes_are_the_literal_product() {
    for tilt in [1e-6, 1e-8, 1e-10, 1e-12] {
        for flip in [false, true] {
            let text = near_parallel(tilt, flip);
            let worst = check(&format!("tilt {tilt:e}, flip {flip}"), &text, &UrdfChain::default(), &[]);
            eprintln!("tilt {tilt:e} flip {flip}: worst gap {worst:e}");
        }
    }
}
