//! Unit tests of the numeric solver's parts.

use std::f64::consts::PI;

use nalgebra::{Rotation3, Unit, Vector6};

use super::descent::Work;
use super::starts::{START_SEED, Start, Starts, same_configuration};
use super::*;
use crate::model::presets;
use crate::rng::SplitMix64;

#[test]
fn rotation_log_inverts_the_exponential_everywhere() {
    let axes = [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.3, -0.8, 0.5), Vector3::new(-0.2, 0.1, -0.9)];
    for axis in axes {
        let axis = Unit::new_normalize(axis);
        for angle in [0.0, 1e-12, 1e-7, 0.3, 2.0, 2.1, PI - 1e-3, PI - 1e-9] {
            let r = Rotation3::from_axis_angle(&axis, angle);
            let (w, a) = rotation_log(r.matrix());
            assert!((a - angle).abs() < 1e-9, "angle {angle}: {a}");
            assert!((w - axis.into_inner() * angle).norm() < 1e-8, "angle {angle}: {w:?}");
        }
        // Exactly π: the axis is defined up to sign.
        let (w, a) = rotation_log(Rotation3::from_axis_angle(&axis, PI).matrix());
        assert!((a - PI).abs() < 1e-12);
        assert!((w.norm() - PI).abs() < 1e-12 && w.normalize().dot(&axis).abs() > 1.0 - 1e-12);
    }
}

#[test]
fn splitmix64_matches_the_reference_sequence() {
    // Reference outputs of SplitMix64 from state 0 (Vigna's splitmix64.c).
    let mut rng = SplitMix64(0);
    assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
    assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
    let mut rng = SplitMix64(START_SEED);
    for _ in 0..1000 {
        let x = rng.next_f64();
        assert!((0.0..1.0).contains(&x));
    }
}

#[test]
fn starts_lie_within_the_limits() {
    for name in presets::names() {
        let robot = presets::get(name).unwrap();
        let mut starts = Starts::new(&robot, None, 1.0);
        let mut q = vec![0.0; robot.dof()];
        for k in 0..50 {
            starts.next_into(k, &mut q);
            assert_eq!(robot.first_joint_outside_limits(&q, 0.0), None, "{name} start {k}: {q:?}");
        }
    }
    // A seed outside the limits is moved inside (by whole turns, else clamped).
    let puma = presets::get("puma560").unwrap();
    let seed = [3.0, 0.1 + 2.0 * PI, 0.0, 0.0, -2.5, 0.0];
    let mut starts = Starts::new(&puma, Some(&seed), 1.0);
    let mut q = vec![0.0; 6];
    assert!(matches!(starts.next_into(0, &mut q), Start::Seed));
    assert!((q[0] - 160f64.to_radians()).abs() < 1e-12);
    assert!((q[1] - 0.1).abs() < 1e-12);
    assert!((q[4] + 100f64.to_radians()).abs() < 1e-12);
}

#[test]
fn a_step_never_leaves_the_limits() {
    // Two-link arm, 1 m links, q1 ∈ [0, 0.5]: pulling the tip far along −y pushes q1 below 0;
    // the step must stop joint 1 exactly at its limit and move joint 2 instead.
    let joints = vec![
        crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0).with_limits(0.0, 0.5),
        crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0),
    ];
    let robot = Robot::new(crate::model::RobotSpec::new("two", crate::model::Convention::Dh, joints)).unwrap();
    let mut work = Work::new(&robot, 1.0);
    work.q.copy_from_slice(&[0.1, 0.3]);
    robot.jacobian_into(&work.q, &mut work.jac).unwrap();
    let e = Vector6::new(0.0, -1.0, 0.0, 0.0, 0.0, 0.0);
    assert!(work.step(&e, 1e-6));
    assert_eq!(work.trial[0], 0.0);
    assert!(work.trial[1] < 0.3, "joint 2 takes over: {:?}", work.trial);
    // The unconstrained step would have moved joint 1 below its limit.
    let free = Robot::new(crate::model::RobotSpec::new(
        "free",
        crate::model::Convention::Dh,
        vec![crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0), crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0)],
    ))
    .unwrap();
    let mut unconstrained = Work::new(&free, 1.0);
    unconstrained.q.copy_from_slice(&[0.1, 0.3]);
    free.jacobian_into(&unconstrained.q, &mut unconstrained.jac).unwrap();
    assert!(unconstrained.step(&e, 1e-6));
    assert!(unconstrained.trial[0] < 0.0);
}

#[test]
fn same_configuration_wraps_revolute_joints_only() {
    let rp = Robot::from_toml_str(
        "name = \"rp\"\nlength_unit = \"m\"\nangle_unit = \"rad\"\n[[joints]]\nalpha = 1.5\n[[joints]]\nkind = \"prismatic\"\n",
    )
    .unwrap();
    assert!(same_configuration(&rp, &[PI - 1e-6, 0.2], &[-PI + 1e-6, 0.2]));
    assert!(!same_configuration(&rp, &[0.0, 0.2], &[0.0, 0.2 + 2.0 * PI]));
    assert!(!same_configuration(&rp, &[0.0, 0.2], &[1e-3, 0.2]));
}

#[test]
fn configurations_are_one_any_solution_followed_by_nearness() {
    let panda = presets::get("panda").unwrap();
    let s = Numeric::from_robot(&panda).unwrap();
    assert_eq!(s.configurations(&panda), [Branch::default()]);
    assert!(!s.enumerates_all_branches());
    assert!(s.singularity_measures(&panda, &[Branch::default()]).is_none());
}
