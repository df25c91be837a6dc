//! Time-optimal motion (TOPP-RA): the not-a-knot spline, the bang-bang optimum on a straight
//! line, limits held everywhere (checked against an independent dense sampling), and bad
//! input named.

use reach::model::presets;
use reach::motion::{MotionError, PathLimits, PiecewiseCubic, time_optimal};

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

fn random_waypoints(seed: &mut u64, n: usize, dof: usize) -> Vec<Vec<f64>> {
    (0..n).map(|_| (0..dof).map(|_| 4.0 * lcg(seed) - 2.0).collect()).collect()
}

/// Passes through the waypoints, C² everywhere, and the third derivative is continuous at
/// the second and the last-but-one knot (not-a-knot); 3 points give one parabola.
#[test]
fn spline_is_not_a_knot() {
    let mut seed = 7;
    for n in [2, 3, 4, 5, 6, 10] {
        let w = random_waypoints(&mut seed, n, 3);
        let spline = PiecewiseCubic::spline(&w).unwrap();
        let h = 1.0 / (n - 1) as f64;
        for (i, wi) in w.iter().enumerate() {
            let [q, ..] = spline.eval(i as f64 * h);
            for (a, b) in q.iter().zip(wi) {
                assert!((a - b).abs() < 1e-12, "n {n} knot {i}: {a} vs {b}");
            }
        }
        let e = 1e-10;
        for i in 1..n - 1 {
            let s = i as f64 * h;
            let ([ql, dl, ddl], [qr, dr, ddr]) = (spline.eval(s - e), spline.eval(s + e));
            for j in 0..3 {
                let gaps = [(ql[j] - qr[j]).abs(), (dl[j] - dr[j]).abs(), (ddl[j] - ddr[j]).abs()];
                assert!(gaps[0] < 1e-8 && gaps[1] < 1e-6 && gaps[2] < 1e-4, "n {n} knot {i}: {gaps:?}");
            }
        }
        // Third derivative: the change of q″ across a piece over h, compared on both sides of
        // knots 1 and n − 2.
        if n >= 4 {
            let third = |k: usize| {
                let [_, _, a] = spline.eval(k as f64 * h + 1e-12);
                let [_, _, b] = spline.eval((k + 1) as f64 * h - 1e-12);
                (b[0] - a[0]) / h
            };
            assert!((third(0) - third(1)).abs() < 1e-6 * third(0).abs().max(1.0), "n {n}");
            assert!((third(n - 3) - third(n - 2)).abs() < 1e-6 * third(n - 2).abs().max(1.0), "n {n}");
        }
    }
    // Three points: one parabola through them.
    let spline = PiecewiseCubic::spline(&[vec![0.0], vec![1.0], vec![0.0]]).unwrap();
    let [q, ..] = spline.eval(0.25);
    assert!((q[0] - 0.75).abs() < 1e-12);
}

/// One joint on a straight line from rest to rest: the optimum is bang-bang (trapezoid or
/// triangle). A motion within the limits everywhere cannot beat it, and the grid comes within
/// a fraction of a percent.
#[test]
fn straight_line_meets_the_bang_bang_optimum() {
    for (d, v, a) in [(2.0, 1.0, 2.0), (0.1, 1.0, 2.0), (3.0, 0.5, 10.0)] {
        let path = PiecewiseCubic::polyline(&[vec![0.0], vec![d]]).unwrap();
        let limits = PathLimits::new(vec![v], vec![a]).unwrap();
        let motion = time_optimal(&path, &limits, 400).unwrap();
        let optimum: f64 = if d >= v * v / a { d / v + v / a } else { 2.0 * (d / a).sqrt() };
        let t = motion.duration();
        assert!(t >= optimum * (1.0 - 1e-9) && t <= optimum * 1.005, "d {d}: {t} vs {optimum}");
        let end = motion.sample(t);
        assert!((end.q[0] - d).abs() < 1e-9 && end.qd[0].abs() < 1e-9);
    }
}

/// Random 7-joint splines with the Panda's limits: the reported worst ratios are ≤ 1, and an
/// independent dense sampling (10 000 samples, the speeds and accelerations the trajectory
/// gives) never exceeds them.
#[test]
fn limits_hold_between_grid_points() {
    let panda = presets::get("panda").unwrap();
    let limits = PathLimits::from_robot(&panda, 1.0, 1.0).unwrap();
    let mut seed = 3;
    for per in [4, 32] {
        let w = random_waypoints(&mut seed, 10, 7);
        let path = PiecewiseCubic::spline(&w).unwrap();
        let motion = time_optimal(&path, &limits, per).unwrap();
        let ratios = motion.worst_ratios();
        for j in 0..7 {
            assert!(ratios.velocity[j] <= 1.0 && ratios.acceleration[j] <= 1.0, "{ratios:?}");
        }
        // Some joint is at a limit somewhere (time-optimal: no slack everywhere).
        let top = ratios.velocity.iter().chain(&ratios.acceleration).copied().fold(0.0, f64::max);
        assert!(top > 0.999, "{top}");
        let samples = motion.samples(motion.duration() / 10_000.0).unwrap();
        for sample in &samples {
            for j in 0..7 {
                assert!(sample.qd[j].abs() <= limits.velocity[j] * ratios.velocity[j] * (1.0 + 1e-9));
                assert!(sample.qdd[j].abs() <= limits.acceleration[j] * ratios.acceleration[j] * (1.0 + 1e-9));
            }
        }
        // Ends at rest on the last waypoint; speeds are the derivative of positions.
        let last = samples.last().unwrap();
        assert!(last.qd.iter().all(|v| v.abs() < 1e-9));
        for (a, b) in last.q.iter().zip(&w[9]) {
            assert!((a - b).abs() < 1e-9);
        }
        let (t, e) = (motion.duration() * 0.37, 1e-6);
        let (p, m, c) = (motion.sample(t + e), motion.sample(t - e), motion.sample(t));
        for j in 0..7 {
            assert!(((p.q[j] - m.q[j]) / (2.0 * e) - c.qd[j]).abs() < 1e-5 * (1.0 + c.qd[j].abs()));
        }
    }
}

/// A polyline rests at each corner: each leg is its own bang-bang motion.
#[test]
fn polyline_stops_at_corners() {
    let path = PiecewiseCubic::polyline(&[vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]]).unwrap();
    let limits = PathLimits::new(vec![1.0, 1.0], vec![1.0, 1.0]).unwrap();
    let motion = time_optimal(&path, &limits, 200).unwrap();
    // Each leg: d = 1 = v²/a, the triangle 2 s.
    assert!((motion.duration() - 4.0).abs() < 0.02, "{}", motion.duration());
    let corner = motion.samples(0.001).unwrap().into_iter().find(|s| (s.q[0] - 1.0).abs() < 1e-12).unwrap();
    assert!(corner.qd.iter().all(|v| v.abs() < 1e-6), "{corner:?}");
    // The knot times: each leg takes half the motion, and the motion is at rest on the corner.
    let knots = motion.waypoint_times();
    assert_eq!(knots.len(), 3);
    assert!((knots[1] - motion.duration() / 2.0).abs() < 1e-12 && knots[2] == motion.duration(), "{knots:?}");
    let at = motion.sample(knots[1]);
    assert!((at.q[0] - 1.0).abs() < 1e-12 && at.q[1].abs() < 1e-12 && at.qd.iter().all(|v| v.abs() < 1e-9), "{at:?}");
}

/// Distance from `q` to the polyline through `w`.
fn polyline_distance(q: &[f64], w: &[Vec<f64>]) -> f64 {
    w.windows(2)
        .map(|seg| {
            let d: Vec<f64> = seg[1].iter().zip(&seg[0]).map(|(b, a)| b - a).collect();
            let dd: f64 = d.iter().map(|x| x * x).sum();
            let t = if dd > 0.0 {
                (q.iter().zip(&seg[0]).zip(&d).map(|((q, a), d)| (q - a) * d).sum::<f64>() / dd).clamp(0.0, 1.0)
            } else {
                0.0
            };
            q.iter().zip(&seg[0]).zip(&d).map(|((q, a), d)| (q - a - t * d).powi(2)).sum::<f64>().sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

/// A blended path stays within its tolerance of the polyline and of each corner, starts and
/// ends on the end waypoints, is continuously differentiable, and its pieces are lines and
/// quadratic arcs whose middle control point is the corner.
#[test]
fn blends_stay_within_the_tolerance_and_are_smooth() {
    let mut seed = 11;
    for tol in [0.01, 0.1, 1.0] {
        let w = random_waypoints(&mut seed, 7, 3);
        let path = PiecewiseCubic::blended(&w, tol).unwrap();
        let length = path.length();
        let polyline: f64 =
            w.windows(2).map(|p| p[0].iter().zip(&p[1]).map(|(a, b)| (b - a).powi(2)).sum::<f64>().sqrt()).sum();
        assert!(length <= polyline + 1e-12 && length > 0.5 * polyline, "{length} vs {polyline}");
        for i in 0..=10_000 {
            let [q, d, _] = path.eval(length * i as f64 / 10_000.0);
            let off = polyline_distance(&q, &w);
            assert!(off <= tol + 1e-12, "tol {tol}: {off} off the polyline");
            let speed = d.iter().map(|x| x * x).sum::<f64>().sqrt();
            assert!(speed <= 1.0 + 1e-12, "arc-length parameter: |q'| = {speed}");
        }
        for (q, end) in [(path.eval(0.0)[0].clone(), &w[0]), (path.eval(length)[0].clone(), &w[6])] {
            assert!(q.iter().zip(end).all(|(a, b)| (a - b).abs() < 1e-12), "{q:?} vs {end:?}");
        }
        let pieces = path.control_points().unwrap();
        let mut s = 0.0;
        let mut arcs = 0;
        for piece in &pieces {
            let e = 1e-9;
            let ([_, dl, _], [_, dr, _]) = (path.eval(s - e), path.eval(s + e));
            assert!(dl.iter().zip(&dr).all(|(a, b)| (a - b).abs() < 1e-6), "tangent jumps at s = {s}");
            let chord: f64 =
                piece[0].iter().zip(piece.last().unwrap()).map(|(a, b)| (b - a).powi(2)).sum::<f64>().sqrt();
            if piece.len() == 3 {
                arcs += 1;
                // The middle control point is a waypoint (the corner the arc cuts), and the
                // arc's middle, half its parameter length in, is its closest point to it.
                assert!(w.iter().any(|c| c.iter().zip(&piece[1]).all(|(a, b)| (a - b).abs() < 1e-12)));
                let half = piece[0].iter().zip(&piece[1]).map(|(a, b)| (b - a).powi(2)).sum::<f64>().sqrt();
                let [mid, ..] = path.eval(s + half);
                let gap = mid.iter().zip(&piece[1]).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
                assert!(gap <= tol + 1e-12 && gap < chord, "tol {tol}: the arc passes its corner at {gap}");
                s += 2.0 * half;
            } else {
                // A line is parameterised by its length.
                s += chord;
            }
        }
        assert_eq!(arcs, 5, "one blend per corner");
        assert!((s - length).abs() < 1e-9, "{s} vs {length}");
        // Each waypoint's mark is within the tolerance of it.
        let limits = PathLimits::new(vec![1.0; 3], vec![2.0; 3]).unwrap();
        let motion = time_optimal(&path, &limits, 0).unwrap();
        for (t, wi) in motion.waypoint_times().iter().zip(&w) {
            let q = motion.sample(*t).q;
            let gap = q.iter().zip(wi).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
            assert!(gap <= tol + 1e-9, "tol {tol}: passes waypoint {wi:?} at {gap}");
        }
    }
    // Tolerance 0: the polyline, resting at every corner.
    let w = random_waypoints(&mut seed, 4, 2);
    assert!(PiecewiseCubic::blended(&w, 0.0).unwrap().control_points().unwrap().iter().all(|p| p.len() == 2));
}

/// Blending the corner of `(0,0) → (1,0) → (1,1)` lets the motion keep moving there: shorter
/// than the polyline's stop (4 s), within the limits everywhere (an independent dense
/// sampling), and a full reversal `0 → 1 → 0` is passed too.
#[test]
fn blends_do_not_stop_at_corners() {
    let limits = PathLimits::new(vec![1.0, 1.0], vec![1.0, 1.0]).unwrap();
    let w = [vec![0.0, 0.0], vec![1.0, 0.0], vec![1.0, 1.0]];
    let stop = time_optimal(&PiecewiseCubic::polyline(&w).unwrap(), &limits, 200).unwrap().duration();
    let mut last = stop;
    for tol in [0.0, 0.05, 0.2] {
        let motion = time_optimal(&PiecewiseCubic::blended(&w, tol).unwrap(), &limits, 200).unwrap();
        let t = motion.duration();
        if tol == 0.0 {
            assert!((t - stop).abs() < 1e-9 * stop, "{t} vs {stop}");
        } else {
            assert!(t < last, "tol {tol}: {t} not shorter than {last}");
            let corner = motion.sample(motion.waypoint_times()[1]);
            assert!(corner.qd.iter().map(|v| v * v).sum::<f64>().sqrt() > 0.1, "{corner:?}");
        }
        last = t;
        let r = motion.worst_ratios();
        for j in 0..2 {
            assert!(r.velocity[j] <= 1.0 && r.acceleration[j] <= 1.0, "{r:?}");
        }
        for s in motion.samples(t / 20_000.0).unwrap() {
            assert!(s.qd.iter().chain(&s.qdd).all(|v| v.abs() <= 1.0 + 1e-9), "{s:?}");
        }
    }
    let one = PathLimits::new(vec![1.0], vec![1.0]).unwrap();
    let back =
        time_optimal(&PiecewiseCubic::blended(&[vec![0.0], vec![1.0], vec![0.0]], 0.1).unwrap(), &one, 0).unwrap();
    assert!(back.duration().is_finite() && back.worst_ratios().acceleration[0] <= 1.0);
    let end = back.sample(back.duration());
    assert!(end.q[0].abs() < 1e-9 && end.qd[0].abs() < 1e-9, "{end:?}");
}

#[test]
fn bad_input_is_named() {
    let err = PiecewiseCubic::spline(&[vec![0.0, 1.0], vec![f64::NAN, 0.0]]).unwrap_err();
    assert!(err.to_string().contains("waypoint 2"), "{err}");
    assert!(PiecewiseCubic::spline(&[vec![0.0]]).is_err());
    assert!(PiecewiseCubic::polyline(&[vec![0.0, 1.0], vec![0.0]]).is_err());
    for bad in [0.0, -1.0, f64::NAN] {
        let err = PathLimits::new(vec![1.0, bad], vec![1.0, 1.0]).unwrap_err();
        assert!(err.to_string().contains("velocity[2]"), "{err}");
    }
    // The Puma 560 preset carries no speed or acceleration limits.
    let puma = presets::get("puma560").unwrap();
    let err = PathLimits::from_robot(&puma, 1.0, 1.0).unwrap_err();
    assert!(matches!(err, MotionError::InvalidInput { .. }) && err.to_string().contains("joint 1"), "{err}");
    let panda = presets::get("panda").unwrap();
    assert!(PathLimits::from_robot(&panda, 1.5, 1.0).unwrap_err().to_string().contains("max_velocity_scale"));
    let path = PiecewiseCubic::spline(&[vec![0.0; 7], vec![1.0; 7]]).unwrap();
    let limits = PathLimits::from_robot(&panda, 1.0, 1.0).unwrap();
    assert!(time_optimal(&path, &limits, 2_000_000).unwrap_err().to_string().contains("cap"));
    let motion = time_optimal(&path, &limits, 0).unwrap();
    assert!(motion.samples(0.0).is_err() && motion.samples(1e-12).is_err());
    let short = PathLimits::new(vec![1.0], vec![1.0]).unwrap();
    assert!(time_optimal(&path, &short, 0).is_err());
}
