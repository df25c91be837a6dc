//! Time profiles and synchronised timing: boundary conditions, limits respected, and seed
//! 000's motor synchronisation example (notes 000 §3.5, D8).

use proptest::prelude::*;
use reach::motion::{JointMotion, JointRates, Profile, Timing};

/// The largest |λ'| and |λ''| seen on a fine grid of τ.
fn sampled_peaks(p: Profile) -> (f64, f64) {
    let (mut v, mut a) = (0.0_f64, 0.0_f64);
    for k in 1..100_000 {
        let e = p.eval(f64::from(k) / 100_000.0);
        v = v.max(e.velocity.abs());
        a = a.max(e.acceleration.abs());
    }
    (v, a)
}

/// The peaks stated by `peak_velocity` / `peak_acceleration` are the true maxima.
#[test]
fn stated_peaks_are_the_sampled_maxima() {
    for p in [Profile::Linear, Profile::Cycloidal, Profile::Quintic, Profile::Trapezoidal { accel_fraction: 0.2 }] {
        let (v, a) = sampled_peaks(p);
        assert!((v - p.peak_velocity()).abs() < 1e-6, "{p:?}: {v}");
        assert!((a - p.peak_acceleration()).abs() < 1e-4, "{p:?}: {a}");
    }
}

/// Cycloidal (seed 001 §3.6): peak λ' = 2 at the midpoint, |λ''| = 2π at τ = ¼ and ¾.
#[test]
fn cycloidal_peaks_are_where_the_notes_say() {
    let p = Profile::Cycloidal;
    assert!((p.eval(0.5).velocity - 2.0).abs() < 1e-15);
    assert!((p.eval(0.25).acceleration - 2.0 * std::f64::consts::PI).abs() < 1e-12);
    assert!((p.eval(0.75).acceleration + 2.0 * std::f64::consts::PI).abs() < 1e-12);
}

/// Quintic: λ = 10τ³ − 15τ⁴ + 6τ⁵; λ(½) = ½, λ'(½) = 15/8.
#[test]
fn quintic_values() {
    let p = Profile::Quintic;
    assert_eq!(p.eval(0.5).position, 0.5);
    assert!((p.eval(0.5).velocity - 1.875).abs() < 1e-15);
    assert!((p.position(0.2) - (10.0 * 0.008 - 15.0 * 0.0016 + 6.0 * 0.00032)).abs() < 1e-15);
}

/// The trapezoid by hand: D = 2 rad, v = 1 rad/s, a = 1 rad/s² → accelerate 1 s (0.5 rad),
/// cruise 1 s (1 rad), brake 1 s: T = 3 s. D = 0.5 rad with the same limits never reaches
/// 1 rad/s: triangle with T = 2√(0.5) s and peak speed √0.5 rad/s.
#[test]
fn trapezoid_by_hand() {
    let (p, t) = Profile::trapezoidal_for(2.0, 1.0, 1.0).unwrap();
    assert!((t - 3.0).abs() < 1e-15);
    let m = JointMotion::new(&[0.0], &[2.0], 0.0, t, p).unwrap();
    assert!((m.position(1.0)[0] - 0.5).abs() < 1e-12);
    assert!((m.position(2.0)[0] - 1.5).abs() < 1e-12);
    assert!((m.velocity(1.5)[0] - 1.0).abs() < 1e-12);
    assert!((m.acceleration(0.5)[0] - 1.0).abs() < 1e-12);
    assert!((m.acceleration(2.5)[0] + 1.0).abs() < 1e-12);

    let (p, t) = Profile::trapezoidal_for(0.5, 1.0, 1.0).unwrap();
    assert_eq!(p, Profile::Trapezoidal { accel_fraction: 0.5 });
    assert!((t - 2.0 * 0.5f64.sqrt()).abs() < 1e-15);
    let m = JointMotion::new(&[0.0], &[0.5], 0.0, t, p).unwrap();
    assert!((m.velocity(t / 2.0)[0] - 0.5f64.sqrt()).abs() < 1e-12);
    let (_, t0) = Profile::trapezoidal_for(0.0, 1.0, 1.0).unwrap();
    assert_eq!(t0, 0.0);
}

/// Notes 000 D8: φ = (100, 400, 200) pulses, every motor at most 500 Hz. The paper's LP
/// constraint φᵢ·ωᵢ = const gives ω = (500, 125, 250) and durations (0.2, 3.2, 0.8) s — not
/// synchronous. The intent (φᵢ/ωᵢ equal, the longest-working motor at full speed) gives
/// ω = (125, 500, 250) and t = 0.8 s for all three.
#[test]
fn seed000_d8_motor_synchronisation() {
    let phi = [100.0, 400.0, 200.0];
    let rates = JointRates::new(vec![500.0; 3], None).unwrap();
    let timing = Timing::synchronised(&phi, &rates, Profile::Linear).unwrap();
    assert!((timing.duration - 0.8).abs() < 1e-12);
    assert_eq!(timing.limiting_joint, Some(1));
    let omega = &timing.peak_velocity;
    for (got, want) in omega.iter().zip([125.0, 500.0, 250.0]) {
        assert!((got - want).abs() < 1e-9, "{omega:?}");
    }
    // Every motor's own duration φᵢ/ωᵢ is the common one.
    for (p, w) in phi.iter().zip(omega) {
        assert!((p / w - 0.8).abs() < 1e-12);
    }
    // The literal LP's optimum is not synchronous (the reason for the correction).
    let literal = [500.0, 125.0, 250.0];
    let products: Vec<f64> = phi.iter().zip(literal).map(|(p, w)| p * w).collect();
    assert!(products.iter().all(|v| (v - 50_000.0).abs() < 1e-9)); // satisfies φ·ω = const
    let durations: Vec<f64> = phi.iter().zip(literal).map(|(p, w)| p / w).collect();
    assert_eq!(durations, vec![0.2, 3.2, 0.8]);
}

/// A fixed shape: the duration is set by the joint that needs longest, by speed or acceleration.
#[test]
fn fixed_shape_timing_picks_the_binding_limit() {
    // Cycloidal: T ≥ 2·D/v and T ≥ √(2π·D/a).
    let rates = JointRates::new(vec![1.0, 1.0], Some(vec![100.0, 0.1])).unwrap();
    let t = Timing::synchronised(&[1.0, 0.5], &rates, Profile::Cycloidal).unwrap();
    let by_speed = 2.0_f64;
    let by_acc = (2.0 * std::f64::consts::PI * 0.5 / 0.1_f64).sqrt();
    assert!((t.duration - by_speed.max(by_acc)).abs() < 1e-12);
    assert_eq!(t.limiting_joint, Some(1));
    assert!(t.peak_acceleration[1] <= 0.1 + 1e-12);
    // Nothing moves: zero duration, no limiting joint.
    let t = Timing::synchronised(&[0.0, 0.0], &rates, Profile::Quintic).unwrap();
    assert_eq!((t.duration, t.limiting_joint), (0.0, None));
    // Bad input is an error, not a panic.
    assert!(Timing::synchronised(&[1.0], &rates, Profile::Quintic).is_err());
    assert!(Timing::synchronised(&[f64::NAN, 1.0], &rates, Profile::Quintic).is_err());
    assert!(Timing::synchronised_trapezoid(&[1.0, 1.0], &JointRates::new(vec![1.0, 1.0], None).unwrap()).is_err());
    assert!(JointRates::new(vec![1.0], Some(vec![1.0, 2.0])).is_err());
}

/// Robot speed limits: taken from the joints; a joint without one is named in the error.
#[test]
fn rates_from_robot_name_the_joint_without_a_limit() {
    let robot = reach::model::presets::get("planar3").unwrap();
    let mut spec = robot.spec().clone();
    for (i, j) in spec.joints.iter_mut().enumerate() {
        j.max_velocity = if i == 1 { None } else { Some(1.5) };
    }
    let missing = reach::Robot::new(spec.clone()).unwrap();
    let err = JointRates::from_robot(&missing, None).unwrap_err().to_string();
    assert!(err.contains("joint 2"), "{err}");
    spec.joints[1].max_velocity = Some(0.5);
    let full = reach::Robot::new(spec).unwrap();
    assert_eq!(JointRates::from_robot(&full, None).unwrap().velocity, vec![1.5, 0.5, 1.5]);
}

/// A robot's synchronised motion: the duration from the robot's speed limits (and explicit
/// acceleration limits), every joint starting and stopping together, none over its limit.
#[test]
fn synchronised_robot_motion_starts_and_stops_together() {
    let robot = reach::model::presets::get("planar3").unwrap();
    let mut spec = robot.spec().clone();
    for (j, v) in spec.joints.iter_mut().zip([1.0, 2.0, 4.0]) {
        j.max_velocity = Some(v);
    }
    let robot = reach::Robot::new(spec).unwrap();
    let rates = JointRates::from_robot(&robot, Some(vec![2.0, 2.0, 2.0])).unwrap();
    let (q0, q1) = ([0.0, 0.5, -0.5], [0.6, -1.5, 0.5]);
    // Trapezoid: V = max(0.6/1, 2/2, 1/4) = 1, A = max(0.3, 1, 0.5) = 1 = V²: T = V + A/V = 2.
    let (m, timing) =
        JointMotion::synchronised(&robot, &q0, &q1, 0.5, &rates, Profile::Trapezoidal { accel_fraction: 0.5 }).unwrap();
    assert!((timing.duration - 2.0).abs() < 1e-12);
    assert_eq!(timing.limiting_joint, Some(1));
    assert!((m.t1() - 2.5).abs() < 1e-12);
    for t in [0.5, 2.5] {
        assert!(m.velocity(t).iter().all(|v| v.abs() < 1e-12));
    }
    assert!(m.position(2.5).iter().zip(q1).all(|(a, b)| (a - b).abs() < 1e-12));
    for k in 0..=200 {
        let t = 0.5 + 2.0 * f64::from(k) / 200.0;
        for (v, lim) in m.velocity(t).iter().zip([1.0, 2.0, 4.0]) {
            assert!(v.abs() <= lim * (1.0 + 1e-12));
        }
    }
    // Cycloidal, speed only: T = λ'max · max(0.6/1, 2/2, 1/4) = 2 · 1 = 2 s.
    let rates = JointRates::from_robot(&robot, None).unwrap();
    let (_, timing) = JointMotion::synchronised(&robot, &q0, &q1, 0.0, &rates, Profile::Cycloidal).unwrap();
    assert!((timing.duration - 2.0).abs() < 1e-12);
    assert!(JointMotion::synchronised(&robot, &q0, &q0, 0.0, &rates, Profile::Cycloidal).is_err());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    /// Every profile: λ(0) = 0, λ(1) = 1, non-decreasing.
    #[test]
    fn profiles_are_monotone_from_0_to_1(f in 0.01f64..=0.5, a in 0.0f64..1.0, b in 0.0f64..1.0) {
        for p in [Profile::Linear, Profile::Cycloidal, Profile::Quintic, Profile::Trapezoidal { accel_fraction: f }] {
            prop_assert_eq!(p.position(0.0), 0.0);
            prop_assert!((p.position(1.0) - 1.0).abs() < 1e-15);
            let (lo, hi) = if a < b { (a, b) } else { (b, a) };
            prop_assert!(p.position(lo) <= p.position(hi) + 1e-15);
        }
    }

    /// The synchronised trapezoid: all joints share the duration, every joint stays within its
    /// speed and acceleration limits (checked on samples of the actual motion), and the
    /// binding joint reaches one of its limits.
    #[test]
    fn synchronised_trapezoid_respects_every_limit(
        delta in prop::collection::vec(-3.0f64..3.0, 1..7),
        v in prop::collection::vec(0.1f64..3.0, 7),
        a in prop::collection::vec(0.1f64..10.0, 7),
    ) {
        let n = delta.len();
        prop_assume!(delta.iter().any(|d| d.abs() > 1e-3));
        let rates = JointRates::new(v[..n].to_vec(), Some(a[..n].to_vec())).unwrap();
        let timing = Timing::synchronised_trapezoid(&delta, &rates).unwrap();
        let q1: Vec<f64> = delta.clone();
        let m = JointMotion::new(&vec![0.0; n], &q1, 0.0, timing.duration, timing.profile).unwrap();
        let mut reached = false;
        for k in 0..=400 {
            let t = timing.duration * f64::from(k) / 400.0;
            for (i, (qd, qdd)) in m.velocity(t).iter().zip(m.acceleration(t)).enumerate() {
                prop_assert!(qd.abs() <= v[i] * (1.0 + 1e-9), "joint {i} speed {qd} > {}", v[i]);
                prop_assert!(qdd.abs() <= a[i] * (1.0 + 1e-9), "joint {i} acc {qdd} > {}", a[i]);
                if (qd.abs() - v[i]).abs() < 1e-6 * v[i] || (qdd.abs() - a[i]).abs() < 1e-6 * a[i] {
                    reached = true;
                }
            }
        }
        prop_assert!(reached, "no joint reaches a limit: the duration is not minimal");
        // And each joint alone could not go faster than the binding one.
        let single: f64 = delta.iter().enumerate()
            .map(|(i, d)| Profile::trapezoidal_for(d.abs(), v[i], a[i]).unwrap().1)
            .fold(0.0, f64::max);
        prop_assert!(timing.duration >= single - 1e-12);
    }

    /// A fixed shape (quintic): every joint within its speed limit, the binding one at it.
    #[test]
    fn synchronised_fixed_shape_respects_speed_limits(
        delta in prop::collection::vec(-3.0f64..3.0, 1..7),
        v in prop::collection::vec(0.1f64..3.0, 7),
    ) {
        let n = delta.len();
        prop_assume!(delta.iter().any(|d| d.abs() > 1e-3));
        let rates = JointRates::new(v[..n].to_vec(), None).unwrap();
        let timing = Timing::synchronised(&delta, &rates, Profile::Quintic).unwrap();
        let m = JointMotion::new(&vec![0.0; n], &delta, 0.0, timing.duration, Profile::Quintic).unwrap();
        let qd = m.velocity(timing.duration / 2.0); // the quintic's peak speed is at τ = ½
        let mut at_limit = false;
        for i in 0..n {
            prop_assert!(qd[i].abs() <= v[i] * (1.0 + 1e-12));
            at_limit |= (qd[i].abs() - v[i]).abs() < 1e-9 * v[i];
        }
        prop_assert!(at_limit);
    }
}
