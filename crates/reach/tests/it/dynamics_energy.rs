//! Mechanical energy `∫ Σ |τᵢ q̇ᵢ| dt` of sampled motions and the finite-difference rates it
//! uses, against closed forms.

use std::f64::consts::{PI, TAU};

use nalgebra::Vector3;
use reach::effort::dynamics::{joint_rates, mechanical_energy, potential_energy, trajectory_energy};
use reach::model::{Convention, Joint, LinkInertial, Robot, RobotSpec, presets};

/// Rest-to-rest cycloidal motion by `delta` in `duration`: position, rate, acceleration.
fn cycloidal(t: f64, delta: f64, duration: f64) -> (f64, f64, f64) {
    let u = t / duration;
    let q = delta * (u - (TAU * u).sin() / TAU);
    let qd = delta / duration * (1.0 - (TAU * u).cos());
    let qdd = delta / (duration * duration) * TAU * (TAU * u).sin();
    (q, qd, qdd)
}

/// One revolute joint about the vertical, a point mass `m` at radius `r`: no gravity torque.
fn turntable(m: f64, r: f64) -> Robot {
    let mut spec = RobotSpec::new("turntable", Convention::Dh, vec![Joint::revolute(r, 0.0, 0.0, 0.0)]);
    spec.inertials = vec![LinkInertial::point(m, Vector3::zeros())];
    Robot::new(spec).unwrap()
}

#[test]
fn accelerating_and_braking_a_turntable_costs_twice_the_peak_kinetic_energy() {
    let (m, r, delta, duration) = (3.0, 0.5, 2.0, 1.5);
    let robot = turntable(m, r);
    let times: Vec<f64> = (0..=400).map(|k| duration * k as f64 / 400.0).collect();
    let q: Vec<[f64; 1]> = times.iter().map(|&t| [cycloidal(t, delta, duration).0]).collect();
    // Peak rate 2Δ/T; braking energy counts too: E = 2 · ½ (m r²) (2Δ/T)².
    let expected = m * r * r * (2.0 * delta / duration).powi(2);
    let e = trajectory_energy(&robot, &times, &q).unwrap();
    assert!((e - expected).abs() < 1e-3 * expected, "{e} vs {expected}");
    // With the exact rates the only error is the trapezoid rule's.
    let qd: Vec<[f64; 1]> = times.iter().map(|&t| [cycloidal(t, delta, duration).1]).collect();
    let qdd: Vec<[f64; 1]> = times.iter().map(|&t| [cycloidal(t, delta, duration).2]).collect();
    let exact = mechanical_energy(&robot, &times, &q, &qd, &qdd).unwrap();
    assert!((exact - expected).abs() < 1e-4 * expected, "{exact} vs {expected}");
}

#[test]
fn slowly_lifting_the_puma_arm_costs_its_potential_energy() {
    // The shoulder raises the arm slowly enough that gravity dominates: power never
    // changes sign, so E = ΔV (+ ΔT = 0, rest to rest).
    let puma = presets::get("puma560").unwrap();
    let duration = 6.0;
    let start = [0.3, 0.2, -0.4, 0.1, 0.5, 0.0];
    let delta = [0.0, 0.6, 0.0, 0.0, 0.0, 0.0];
    let times: Vec<f64> = (0..=600).map(|k| duration * k as f64 / 600.0).collect();
    let q: Vec<Vec<f64>> =
        times.iter().map(|&t| (0..6).map(|i| start[i] + cycloidal(t, delta[i], duration).0).collect()).collect();
    let lift = potential_energy(&puma, &q[600]).unwrap() - potential_energy(&puma, &q[0]).unwrap();
    assert!(lift > 10.0, "{lift}");
    let e = trajectory_energy(&puma, &times, &q).unwrap();
    assert!((e - lift).abs() < 1e-3 * lift, "{e} vs ΔV {lift}");
}

#[test]
fn lowering_costs_as_much_as_lifting() {
    // |τ q̇| counts the braking work of lowering the arm (no regeneration).
    let puma = presets::get("puma560").unwrap();
    let times: Vec<f64> = (0..=300).map(|k| 3.0 * k as f64 / 300.0).collect();
    let up: Vec<Vec<f64>> = times.iter().map(|&t| vec![0.0, cycloidal(t, 0.5, 3.0).0, 0.0, 0.0, 0.0, 0.0]).collect();
    let down: Vec<Vec<f64>> = up.iter().rev().cloned().collect();
    let (e_up, e_down) =
        (trajectory_energy(&puma, &times, &up).unwrap(), trajectory_energy(&puma, &times, &down).unwrap());
    assert!(e_up > 1.0 && (e_up - e_down).abs() < 1e-9 * e_up, "{e_up} vs {e_down}");
}

#[test]
fn rates_are_exact_for_a_quadratic_on_uneven_steps() {
    let robot = turntable(1.0, 1.0);
    let times = [0.0, 0.1, 0.25, 0.3, 0.7, 1.0];
    let f = |t: f64| 0.2 + 0.5 * t - 1.5 * t * t;
    let q: Vec<[f64; 1]> = times.iter().map(|&t| [f(t)]).collect();
    let (qd, qdd) = joint_rates(&robot, &times, &q).unwrap();
    for (k, &t) in times.iter().enumerate() {
        assert!((qd[k][0] - (0.5 - 3.0 * t)).abs() < 1e-12, "q̇ at {t}: {}", qd[k][0]);
        assert!((qdd[k][0] + 3.0).abs() < 1e-10, "q̈ at {t}: {}", qdd[k][0]);
    }
    // Two samples: constant rate; one sample: zeros.
    let (qd, qdd) = joint_rates(&robot, &[0.0, 2.0], &[[0.0], [1.0]]).unwrap();
    assert_eq!((qd, qdd), (vec![vec![0.5]; 2], vec![vec![0.0]; 2]));
    let (qd, _) = joint_rates(&robot, &[0.0], &[[1.0]]).unwrap();
    assert_eq!(qd, vec![vec![0.0]]);
    assert_eq!(trajectory_energy(&turntable(1.0, 1.0), &[0.0], &[[1.0]]).unwrap(), 0.0);
}

#[test]
fn rates_are_wrap_safe_for_revolute_joints() {
    // A joint turning steadily at 1 rad/s through ±π, reported wrapped to (−π, π].
    let robot = turntable(1.0, 1.0);
    let times: Vec<f64> = (0..=20).map(|k| k as f64 * 0.05).collect();
    let q: Vec<[f64; 1]> = times.iter().map(|&t| [reach::angle::wrap(PI - 0.5 + t)]).collect();
    assert!(q.iter().any(|v| v[0] < 0.0) && q.iter().any(|v| v[0] > 3.0));
    let (qd, qdd) = joint_rates(&robot, &times, &q).unwrap();
    assert!(qd.iter().all(|v| (v[0] - 1.0).abs() < 1e-9), "{qd:?}");
    assert!(qdd.iter().all(|v| v[0].abs() < 1e-6), "{qdd:?}");
}

#[test]
fn energy_with_known_rates_agrees_with_energy_from_positions() {
    let (m, r, delta, duration) = (2.0, 0.4, 1.2, 1.0);
    let robot = turntable(m, r);
    let times: Vec<f64> = (0..=200).map(|k| duration * k as f64 / 200.0).collect();
    let q: Vec<Vec<f64>> = times.iter().map(|&t| vec![cycloidal(t, delta, duration).0]).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|&t| vec![cycloidal(t, delta, duration).1]).collect();
    let expected = m * r * r * (2.0 * delta / duration).powi(2);
    let with_rates = reach::effort::dynamics::trajectory_energy_with_rates(&robot, &times, &q, &qd).unwrap();
    assert!((with_rates - expected).abs() < 1e-3 * expected, "{with_rates} vs {expected}");
    let from_positions = trajectory_energy(&robot, &times, &q).unwrap();
    assert!((with_rates - from_positions).abs() < 1e-3 * expected);
    let err = reach::effort::dynamics::trajectory_energy_with_rates(&robot, &times, &q, &qd[..10]).unwrap_err();
    assert!(err.to_string().contains("qd samples"), "{err}");
}
