//! Property tests of the kinematics core over random joint vectors of every preset:
//! the Jacobian matches finite differences of FK, the FK rotation is a proper rotation,
//! `fk` and `fk_matrix` agree, and `jacobian_into` equals `jacobian`.

use crate::common::{fd_jacobian, max_abs_diff};
use nalgebra::{IsometryMatrix3, Matrix3};
use proptest::prelude::*;
use reach::model::presets;
use reach::{Jacobian, Robot};

/// Finite-difference step and tolerance (see `kinematics_presets.rs` for the error budget).
const FD_STEP: f64 = 1e-6;
const FD_TOLERANCE: f64 = 1e-6;

/// A preset name and a joint vector inside its limits (unlimited joints: within ±2π).
fn preset_and_q() -> impl Strategy<Value = (&'static str, Vec<f64>)> {
    proptest::sample::select(presets::names()).prop_flat_map(|name| {
        let robot = presets::get(name).unwrap();
        let ranges: Vec<_> = robot
            .joints()
            .iter()
            .map(|j| {
                let (lo, hi) = if j.limits.is_bounded() {
                    (j.limits.lower, j.limits.upper)
                } else {
                    (-std::f64::consts::TAU, std::f64::consts::TAU)
                };
                lo..=hi
            })
            .collect();
        (Just(name), ranges)
    })
}

fn robot(name: &str) -> Robot {
    presets::get(name).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn jacobian_matches_finite_differences((name, q) in preset_and_q()) {
        let robot = robot(name);
        let j = robot.jacobian(&q).unwrap();
        let err = max_abs_diff(&j, &fd_jacobian(&robot, &q, FD_STEP));
        prop_assert!(err < FD_TOLERANCE, "{} q={:?}: |J − J_fd| = {:e}", name, q, err);
    }

    #[test]
    fn fk_rotation_is_orthonormal_with_determinant_one((name, q) in preset_and_q()) {
        let t = robot(name).fk_matrix(&q).unwrap();
        let r: &Matrix3<f64> = t.rotation.matrix();
        prop_assert!(max_abs_diff(&(r.transpose() * r), &Matrix3::identity()) < 1e-12);
        prop_assert!((r.determinant() - 1.0).abs() < 1e-12);
        let quaternion = robot(name).fk(&q).unwrap().rotation;
        prop_assert!((quaternion.norm() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn fk_and_fk_matrix_agree((name, q) in preset_and_q()) {
        let robot = robot(name);
        let a = robot.fk(&q).unwrap().to_homogeneous();
        let b = robot.fk_matrix(&q).unwrap().to_homogeneous();
        prop_assert!(max_abs_diff(&a, &b) < 1e-12, "{}: {} vs {}", name, a, b);
        let frames = robot.frames(&q).unwrap();
        let tool: IsometryMatrix3<f64> = frames[robot.dof() - 1]
            * IsometryMatrix3::from_parts(robot.tool().translation, robot.tool().rotation.to_rotation_matrix());
        prop_assert!(max_abs_diff(&tool.to_homogeneous(), &b) < 1e-12);
    }

    #[test]
    fn jacobian_into_equals_jacobian((name, q) in preset_and_q()) {
        let robot = robot(name);
        // A buffer holding garbage from a previous call must be fully overwritten.
        let mut out = Jacobian::from_element(robot.dof(), 7.5);
        robot.jacobian_into(&q, &mut out).unwrap();
        prop_assert_eq!(&out, &robot.jacobian(&q).unwrap());
        let q2: Vec<f64> = q.iter().map(|v| v * 0.5).collect();
        robot.jacobian_into(&q2, &mut out).unwrap();
        prop_assert_eq!(&out, &robot.jacobian(&q2).unwrap());
    }
}
