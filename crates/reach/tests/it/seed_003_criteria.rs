//! Seed 003 (Knapczyk & Kisiel 1987), §4 step 4 and Conclusion 5: "a stiffness criterion; an
//! accuracy criterion" for choosing between feasible configurations. Implemented as the
//! isotropy of the tool's translational stiffness, `σ_min/σ_max` of the position Jacobian, and
//! the position-error amplification `σ_max(J_p)·δq` (`decide::ik_criteria`). The values are
//! checked against hand-computed singular values of planar arms and, for spatial arms, the
//! eigenvalues of `J_p J_pᵀ` (an independent decomposition).

use nalgebra::{Matrix3, SymmetricEigen};
use reach::decide::ik_criteria::DEFAULT_JOINT_RESOLUTION;
use reach::decide::motion_criteria::SampledMotion;
use reach::decide::{IkCriterion, MotionCriterion};
use reach::kinematics::Manipulability;
use reach::model::presets;

fn d(v: f64) -> f64 {
    v.to_radians()
}

fn value(c: &IkCriterion, robot: &str, q: &[f64]) -> f64 {
    c.evaluate(&presets::get(robot).unwrap(), q).unwrap()
}

const ACCURACY: IkCriterion = IkCriterion::Accuracy { resolution: DEFAULT_JOINT_RESOLUTION };

#[test]
fn planar_arm_values_are_the_hand_computed_singular_values() {
    // Unit links, q = (0°, 90°, −90°): O (0,0), B (1,0), A (1,1), K (2,1). Columns z × (K − joint):
    // (−1, 2), (−1, 1), (0, 1); J_p J_pᵀ = [[2, −3], [−3, 6]], eigenvalues 4 ± √13.
    let q = [0.0, d(90.0), d(-90.0)];
    let (hi, lo) = ((4.0 + 13f64.sqrt()).sqrt(), (4.0 - 13f64.sqrt()).sqrt());
    assert!((value(&IkCriterion::Stiffness, "planar3", &q) - lo / hi).abs() < 1e-12);
    assert!((value(&ACCURACY, "planar3", &q) - hi * DEFAULT_JOINT_RESOLUTION).abs() < 1e-15);
    // Stretched along x: columns (0, 3), (0, 2), (0, 1); σ = √14 and 0 — a singularity.
    let q = [0.0, 0.0, 0.0];
    assert_eq!(value(&IkCriterion::Stiffness, "planar3", &q), 0.0);
    assert!((value(&ACCURACY, "planar3", &q) - 14f64.sqrt() * DEFAULT_JOINT_RESOLUTION).abs() < 1e-15);
    // A square fold, q = (90°, −90°, −90°): O (0,0), B (0,1), A (1,1), K (1,0). Columns (0, 1),
    // (1, 1), (1, 0): J_p J_pᵀ = [[2, 1], [1, 2]], eigenvalues 3 and 1.
    let q = [d(90.0), d(-90.0), d(-90.0)];
    assert!((value(&IkCriterion::Stiffness, "planar3", &q) - 1.0 / 3f64.sqrt()).abs() < 1e-12);
    assert!((value(&ACCURACY, "planar3", &q) - 3f64.sqrt() * DEFAULT_JOINT_RESOLUTION).abs() < 1e-15);
    // The default resolution is seed 000's 0.01°, and the criterion is linear in it.
    assert!((DEFAULT_JOINT_RESOLUTION - 0.01f64.to_radians()).abs() < 1e-18);
    let coarse = IkCriterion::Accuracy { resolution: 0.1f64.to_radians() };
    assert!((value(&coarse, "planar3", &q) - 10.0 * value(&ACCURACY, "planar3", &q)).abs() < 1e-15);
    let e = IkCriterion::Accuracy { resolution: 0.0 }.evaluate(&presets::get("planar3").unwrap(), &q).unwrap_err();
    assert!(e.to_string().contains("joint resolution"), "{e}");
}

#[test]
fn spatial_arm_values_are_the_eigenvalues_of_jp_jpt() {
    for (robot, q) in [
        ("ur5", vec![0.3, -1.2, 1.4, -0.5, 1.1, 0.2]),
        ("puma560", vec![0.3, 0.6, -0.9, 0.4, 0.7, -0.2]),
        ("panda", vec![0.1, -0.4, 0.2, -2.0, 0.1, 1.6, 0.7]),
    ] {
        let r = presets::get(robot).unwrap();
        let j = r.jacobian(&q).unwrap();
        let jp = j.fixed_rows::<3>(0).into_owned();
        let eig = SymmetricEigen::new(Matrix3::from(&jp * jp.transpose())).eigenvalues;
        let (lo, hi) = (eig.min().sqrt(), eig.max().sqrt());
        assert!((value(&IkCriterion::Stiffness, robot, &q) - lo / hi).abs() < 1e-9, "{robot}");
        assert!((value(&ACCURACY, robot, &q) - hi * DEFAULT_JOINT_RESOLUTION).abs() < 1e-15, "{robot}");
        assert_eq!(Manipulability::position(&j).singular_values.len(), 3, "{robot} is not planar");
    }
}

#[test]
fn motion_criteria_take_the_worst_sample() {
    let robot = presets::get("planar3").unwrap();
    let t = [0.0, 1.0, 2.0];
    let q = vec![vec![d(90.0), d(-90.0), d(-90.0)], vec![0.0, d(90.0), d(-90.0)], vec![d(10.0), d(-20.0), d(-30.0)]];
    let motion = SampledMotion::new(&t, &q);
    let each = |c: &IkCriterion| q.iter().map(|qk| c.evaluate(&robot, qk).unwrap()).collect::<Vec<_>>();
    let stiffness = MotionCriterion::parse("stiffness", &robot, None, None).unwrap();
    let worst = each(&IkCriterion::Stiffness).into_iter().fold(f64::INFINITY, f64::min);
    assert_eq!(stiffness.evaluate(&robot, &motion).unwrap(), worst);
    let accuracy = MotionCriterion::parse("accuracy", &robot, None, None).unwrap();
    let worst = each(&ACCURACY).into_iter().fold(0.0, f64::max);
    assert_eq!(accuracy.evaluate(&robot, &motion).unwrap(), worst);
    // The nearly stretched third sample (links at 10°, −10°, −40°) is the least accurate:
    // σ_max grows as the arm stretches (√14 when straight).
    assert_eq!(worst, each(&ACCURACY)[2]);
}
