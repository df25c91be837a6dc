//! Jerk-limited motion (the smoothing pass over TOPP-RA): every proven bound ≤ 1 and above
//! an independent dense sampling, the jerk the derivative of the acceleration, rests where
//! the path has corners, and bad input named.

use reach::model::presets;
use reach::motion::{MotionError, PathLimits, PiecewiseCubic, jerk_limited, jerk_limits, time_optimal};

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// The Panda's published limits (velocity, acceleration, jerk) on a spline through 10 random
/// waypoints: the bounds hold, one binds, a dense sampling stays below them, and the samples
/// are consistent (speed, acceleration and jerk the derivatives of each other).
#[test]
fn spline_motion_is_within_velocity_acceleration_and_jerk_limits() {
    let panda = presets::get("panda").unwrap();
    let limits = PathLimits::from_robot(&panda, 1.0, 1.0).unwrap();
    let jerk = jerk_limits(&panda).unwrap();
    let mut seed = 11;
    let w: Vec<Vec<f64>> = (0..10).map(|_| (0..7).map(|_| 2.0 * lcg(&mut seed) - 1.0).collect()).collect();
    let path = PiecewiseCubic::spline(&w).unwrap();
    let motion = jerk_limited(&path, &limits, &jerk, 0).unwrap();
    let optimal = time_optimal(&path, &limits, 0).unwrap().duration();
    assert!((motion.time_optimal_duration() - optimal).abs() < 1e-12);
    assert!(motion.duration() > optimal && motion.duration() < 3.0 * optimal, "{} vs {optimal}", motion.duration());
    let (ratios, jerk_ratios) = (motion.worst_ratios(), motion.worst_jerk_ratios());
    let all: Vec<f64> = ratios.velocity.iter().chain(&ratios.acceleration).chain(jerk_ratios).copied().collect();
    assert!(all.iter().all(|r| *r <= 1.0), "{all:?}");
    assert!(all.iter().copied().fold(0.0, f64::max) > 0.999_999, "{all:?}");

    let samples = motion.samples(motion.duration() / 20_000.0).unwrap();
    let mut sampled = [0.0f64; 3];
    for (s, qddd) in &samples {
        for j in 0..7 {
            assert!(s.qd[j].abs() <= limits.velocity[j] * ratios.velocity[j] * (1.0 + 1e-9));
            assert!(s.qdd[j].abs() <= limits.acceleration[j] * ratios.acceleration[j] * (1.0 + 1e-9));
            assert!(qddd[j].abs() <= jerk[j] * jerk_ratios[j] * (1.0 + 1e-9));
            sampled[0] = sampled[0].max(s.qd[j].abs() / limits.velocity[j]);
            sampled[1] = sampled[1].max(s.qdd[j].abs() / limits.acceleration[j]);
            sampled[2] = sampled[2].max(qddd[j].abs() / jerk[j]);
        }
    }
    // The proof is not loose: the binding bound is reached by the samples to a few percent.
    assert!(sampled.iter().copied().fold(0.0, f64::max) > 0.95, "{sampled:?}");
    let (first, last) = (&samples[0].0, &samples[samples.len() - 1].0);
    for (s, end) in [(first, &w[0]), (last, &w[9])] {
        assert!(s.qd.iter().chain(&s.qdd).all(|v| v.abs() < 1e-9), "{s:?}");
        assert!(s.q.iter().zip(end).all(|(a, b)| (a - b).abs() < 1e-9), "{s:?}");
    }
    let times = motion.waypoint_times();
    assert_eq!(times.len(), 10);
    assert!(times.windows(2).all(|t| t[0] < t[1]) && times[0] == 0.0);
    for (t, wp) in times.iter().zip(&w) {
        let (at, _) = motion.sample(*t);
        assert!(at.q.iter().zip(wp).all(|(a, b)| (a - b).abs() < 1e-9), "{t}: {at:?} vs {wp:?}");
    }
    let e = 1e-6;
    for k in 1..20 {
        let t = motion.duration() * k as f64 / 20.0 + 1e-4 * lcg(&mut seed);
        let ((m, _), (c, jc), (p, _)) = (motion.sample(t - e), motion.sample(t), motion.sample(t + e));
        for (j, &jerk_here) in jc.iter().enumerate() {
            let close = |a: f64, b: f64, tol: f64| (a - b).abs() <= tol * (1.0 + b.abs());
            assert!(close((p.q[j] - m.q[j]) / (2.0 * e), c.qd[j], 1e-6));
            assert!(close((p.qd[j] - m.qd[j]) / (2.0 * e), c.qdd[j], 1e-5));
            // The jerk jumps at breakpoints: one of the one-sided differences matches it.
            let (left, right) = ((c.qdd[j] - m.qdd[j]) / e, (p.qdd[j] - c.qdd[j]) / e);
            assert!(
                close(left, jerk_here, 1e-3) || close(right, jerk_here, 1e-3),
                "t {t} joint {j}: {left} {right} {jerk_here}"
            );
        }
    }
}

/// One joint on a straight line: the smoothed motion is within a known margin of the
/// jerk-limited optimum (the seven-phase S-curve).
#[test]
fn straight_line_is_close_to_the_s_curve_optimum() {
    let path = PiecewiseCubic::polyline(&[vec![0.0], vec![10.0]]).unwrap();
    let limits = PathLimits::new(vec![2.0], vec![1.0]).unwrap();
    let motion = jerk_limited(&path, &limits, &[1.0], 400).unwrap();
    // S-curve with v = 2, a = 1, j = 1: jerk phases 1 s (0.5 m/s each), the constant
    // acceleration 1 s; the ramp to v takes 3 s and covers 3 m each way (mean speed v/2), the
    // cruise 4 m at 2 m/s: 3 + 2 + 3 = 8 s.
    let s_curve = 8.0;
    assert!(motion.duration() >= s_curve * (1.0 - 1e-3), "{}", motion.duration());
    assert!(motion.duration() <= 1.01 * s_curve, "{}", motion.duration());
    let (end, _) = motion.sample(motion.duration());
    assert!((end.q[0] - 10.0).abs() < 1e-12 && end.qd[0].abs() < 1e-12);
}

/// A polyline rests at each corner, so its corners need no blend: the motion passes the
/// corner at rest and the jerk stays bounded on both sides.
#[test]
fn polyline_motion_rests_at_the_corners() {
    let path = PiecewiseCubic::polyline(&[vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]]).unwrap();
    let limits = PathLimits::new(vec![1.0, 1.0], vec![1.0, 1.0]).unwrap();
    let motion = jerk_limited(&path, &limits, &[2.0, 2.0], 200).unwrap();
    let times = motion.waypoint_times();
    let (corner, _) = motion.sample(times[1]);
    assert!((corner.q[0] - 1.0).abs() < 1e-9 && corner.q[1].abs() < 1e-9, "{corner:?}");
    assert!(corner.qd.iter().chain(&corner.qdd).all(|v| v.abs() < 1e-9), "{corner:?}");
    assert!(motion.worst_jerk_ratios().iter().all(|r| *r <= 1.0));
    assert!(motion.worst_jerk_ratios().iter().copied().fold(0.0, f64::max) > 0.5);
}

#[test]
fn bad_input_is_named() {
    let limits = PathLimits::new(vec![1.0, 1.0], vec![1.0, 1.0]).unwrap();
    let corners = [vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let blended = PiecewiseCubic::blended(&corners, 0.1).unwrap();
    let err = jerk_limited(&blended, &limits, &[1.0, 1.0], 0).unwrap_err();
    assert!(
        matches!(&err, MotionError::InvalidInput { field, reason } if field == "path" && reason.contains("piece 2")),
        "{err}"
    );
    let line = PiecewiseCubic::polyline(&corners).unwrap();
    for (jerk, field) in [(vec![1.0], "jerk"), (vec![1.0, 0.0], "jerk[2]"), (vec![f64::NAN, 1.0], "jerk[1]")] {
        let err = jerk_limited(&line, &limits, &jerk, 0).unwrap_err();
        assert!(err.to_string().contains(field), "{err}");
    }
    let ur5 = presets::get("ur5").unwrap();
    let err = jerk_limits(&ur5).unwrap_err();
    assert!(err.to_string().contains("joint 1") && err.to_string().contains("max_jerk"), "{err}");
}
