//! The batch kernels (`reach::batch::fk_many`, `jacobian_many`) against the one-row functions
//! (`Robot::fk_matrix`, `Robot::jacobian`), row by row to 1e-12: blocks of rows go through the
//! structure-of-arrays kernel (8 rows for FK, 4 for the Jacobian), the remainder through the
//! one-row path, so the row counts below cover both, on every preset, on URDF arms (tilted axes, prismatic and mimic
//! joints) and on random DH / MDH / URDF chains with prismatic and flipped joints, with joint
//! values beyond the fast sine range in some rows.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use proptest::prelude::*;
use reach::Robot;
use reach::batch::{fk_many, jacobian_many};
use reach::model::{Convention, Joint, JointGeometry, JointKind, MimicJoint, RobotSpec, UrdfChain, presets};

use crate::common::Rng;

/// Largest allowed difference from the one-row result (metres, or unitless rotation entries),
/// relative for entries beyond 1 in magnitude (the far joint values below move prismatic mimic
/// joints by up to 1e15 m).
const TOLERANCE: f64 = 1e-12;

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= TOLERANCE * b.abs().max(1.0)
}

/// Checks every row of `fk_many` and `jacobian_many` of `q` (`N × dof`) against the one-row
/// functions; returns the first mismatch as a message.
fn compare(robot: &Robot, q: &[f64]) -> Result<(), String> {
    let dof = robot.dof();
    let t = fk_many(robot, q).map_err(|e| e.to_string())?;
    let j = jacobian_many(robot, q).map_err(|e| e.to_string())?;
    let n = q.len() / dof;
    if t.len() != n * 16 || j.len() != n * 6 * dof {
        return Err(format!("{n} rows: {} pose and {} Jacobian numbers", t.len(), j.len()));
    }
    for (i, row) in q.chunks_exact(dof).enumerate() {
        let one = robot.fk_matrix(row).unwrap().to_homogeneous();
        for k in 0..16 {
            let (a, b) = (t[i * 16 + k], one[(k / 4, k % 4)]);
            if !close(a, b) {
                return Err(format!("row {i} of {n}, pose entry {k}: {a} vs {b} (q = {row:?})"));
            }
        }
        let one = robot.jacobian(row).unwrap();
        for k in 0..6 * dof {
            let (a, b) = (j[i * 6 * dof + k], one[(k / dof, k % dof)]);
            if !close(a, b) {
                return Err(format!("row {i} of {n}, Jacobian entry {k}: {a} vs {b} (q = {row:?})"));
            }
        }
    }
    Ok(())
}

/// `n` joint vectors of `robot`: within ±π (±1 m for prismatic joints), with every 5th value
/// of every 7th row, if revolute, far beyond the fast sine range (200 rad to 1e15 rad: where
/// the branch-free reduction loses its accuracy, from about 1e6 rad, each such lane must take
/// the standard library's path).
fn joint_rows(robot: &Robot, n: usize, rng: &mut Rng) -> Vec<f64> {
    let dof = robot.dof();
    let mut q = Vec::with_capacity(n * dof);
    for i in 0..n {
        for (j, joint) in robot.joints().iter().enumerate() {
            let v = if joint.kind == JointKind::Prismatic { rng.uniform(-1.0, 1.0) } else { rng.uniform(-3.2, 3.2) };
            let far = i % 7 == 3 && (i * dof + j).is_multiple_of(5) && joint.kind == JointKind::Revolute;
            q.push(if far { v.signum() * 10f64.powf(rng.uniform(2.3, 15.0)) } else { v });
        }
    }
    q
}

/// Row counts: within one block, one block plus the remainder, across the parallel chunks
/// (64 rows) with a remainder.
const ROW_COUNTS: [usize; 8] = [1, 3, 4, 7, 8, 13, 64, 203];

fn urdf_robot(text: &str, base: Option<&str>, tip: &str) -> Robot {
    Robot::from_urdf_str(text, &UrdfChain { base: base.map(Into::into), tip: Some(tip.into()) }).unwrap()
}

#[test]
fn batch_rows_equal_one_row_results_on_presets_and_urdf_arms() {
    let mut robots: Vec<(String, Robot)> =
        presets::names().iter().map(|name| ((*name).to_string(), presets::get(name).unwrap())).collect();
    robots.extend([
        (
            "kr16".into(),
            urdf_robot(include_str!("../../../../examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf"), None, "tool0"),
        ),
        (
            "ur5 urdf".into(),
            urdf_robot(include_str!("../../../../examples/urdf/ur_description/urdf/ur5.urdf"), None, "ee_link"),
        ),
        (
            "panda urdf".into(),
            urdf_robot(include_str!("../../../../examples/panda.urdf"), Some("panda_link0"), "panda_hand"),
        ),
        ("mimic arm".into(), urdf_robot(include_str!("../data/mimic_arm.urdf"), Some("base"), "tool")),
        (
            "three link".into(),
            Robot::from_urdf_str(include_str!("../data/three_link.urdf"), &UrdfChain::default()).unwrap(),
        ),
    ]);
    let mut rng = Rng::new(16);
    for (name, robot) in &robots {
        for n in ROW_COUNTS {
            let q = joint_rows(robot, n, &mut rng);
            compare(robot, &q).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
    }
    assert!(robots.iter().any(|(_, r)| r.joints().iter().any(|j| j.kind == JointKind::Prismatic)));
    assert!(robots.iter().any(|(_, r)| r.spec().mimics.len() > 1));
}

#[test]
fn a_bad_row_is_named_wherever_it_falls() {
    let ur5 = presets::get("ur5").unwrap();
    // in a block of the structure-of-arrays kernel, and in the remainder of the last chunk
    for (row, joint) in [(2, 4), (66, 1), (201, 6)] {
        let mut q = vec![0.1; 203 * 6];
        q[row * 6 + joint - 1] = f64::INFINITY;
        q[202 * 6] = f64::NAN; // a later bad row is not the one named
        for e in [fk_many(&ur5, &q).unwrap_err(), jacobian_many(&ur5, &q).unwrap_err()] {
            let e = e.to_string();
            assert!(e.contains(&format!("q[{row}]")) && e.contains(&format!("joint {joint}")), "{e}");
        }
    }
}

/// A random unit vector, or now and then a coordinate axis (exact zeros in the chain).
fn axis(rng: &mut Rng) -> Unit<Vector3<f64>> {
    let k = rng.next_u64() % 8;
    if k < 3 {
        let mut v = Vector3::zeros();
        v[k as usize] = if rng.next_u64().is_multiple_of(2) { 1.0 } else { -1.0 };
        return Unit::new_unchecked(v);
    }
    Unit::new_normalize(Vector3::new(rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(0.05, 1.0)))
}

fn pose(rng: &mut Rng) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)),
        UnitQuaternion::from_axis_angle(&axis(rng), rng.uniform(-3.0, 3.0)),
    )
}

/// A random chain of `dof` joints in `convention` (0: DH, 1: MDH, 2: URDF, with mimic joints
/// sometimes), revolute or prismatic, some flipped, with a random base and tool.
fn random_robot(convention: usize, dof: usize, seed: u64) -> Robot {
    let mut rng = Rng::new(seed);
    let joints: Vec<Joint> = (0..dof)
        .map(|i| {
            let (a, alpha, d, offset) =
                (rng.uniform(-0.5, 0.5), rng.uniform(-3.2, 3.2), rng.uniform(-0.5, 0.5), rng.uniform(-3.2, 3.2));
            // Some DH rows with α = 0 or a = 0, as real tables have.
            let (a, alpha) = match rng.next_u64() % 4 {
                0 => (0.0, alpha),
                1 => (a, 0.0),
                _ => (a, alpha),
            };
            let mut joint = if rng.next_u64().is_multiple_of(3) {
                Joint::prismatic(a, alpha, d, offset)
            } else {
                Joint::revolute(a, alpha, d, offset)
            };
            if convention == 2 {
                joint.geometry = JointGeometry::Axis { origin: pose(&mut rng), axis: axis(&mut rng) };
            }
            joint.flip = rng.next_u64().is_multiple_of(4);
            joint.named(format!("j{}", i + 1))
        })
        .collect();
    let convention = [Convention::Dh, Convention::Mdh, Convention::Urdf][convention];
    let mut spec =
        RobotSpec { base: pose(&mut rng), tool: pose(&mut rng), ..RobotSpec::new("random", convention, joints) };
    if convention == Convention::Urdf {
        let mut positions: Vec<usize> =
            (0..rng.next_u64() % 3).map(|_| (rng.next_u64() % (dof as u64 + 1)) as usize).collect();
        positions.sort_unstable();
        spec.mimics = positions
            .into_iter()
            .enumerate()
            .map(|(k, position)| MimicJoint {
                name: format!("m{}", k + 1),
                kind: if rng.next_u64().is_multiple_of(3) { JointKind::Prismatic } else { JointKind::Revolute },
                position,
                origin: pose(&mut rng),
                axis: axis(&mut rng),
                master: (rng.next_u64() % dof as u64) as usize,
                multiplier: rng.uniform(-2.0, 2.0),
                offset: rng.uniform(-1.0, 1.0),
            })
            .collect();
    }
    Robot::new(spec).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn batch_rows_equal_one_row_results_on_random_chains(
        convention in 0usize..3,
        dof in 1usize..=8,
        rows in 1usize..=23,
        seed in any::<u64>(),
    ) {
        let robot = random_robot(convention, dof, seed);
        let q = joint_rows(&robot, rows, &mut Rng::new(seed ^ 0x5eed));
        if let Err(e) = compare(&robot, &q) {
            prop_assert!(false, "{:?}: {}", robot.spec(), e);
        }
    }
}
