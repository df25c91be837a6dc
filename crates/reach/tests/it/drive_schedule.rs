//! Step schedules: drift-free quantisation, simulation back to angles, motor limits, and
//! synchronised point-to-point ramps. Expected values are derived in the tests (step counts
//! from the drive data, rates and durations from the trapezoid formulas).

use std::f64::consts::{PI, TAU};

use reach::Robot;
use reach::drive::{Axis, DriveError, StepSchedule, axes, point_to_point, schedule_trajectory, verify};
use reach::model::presets;
use reach::motion::JointSample;

fn deg(v: f64) -> f64 {
    v.to_radians()
}

/// Step intervals of each joint are at least one period of its maximum rate.
fn assert_rates_respected(schedule: &StepSchedule) {
    for j in &schedule.joints {
        let min = 1.0 / j.axis.max_step_rate;
        for w in j.steps.windows(2) {
            assert!(
                w[1].t - w[0].t >= min * (1.0 - 1e-9),
                "joint {}: interval {} < {min}",
                j.axis.joint,
                w[1].t - w[0].t
            );
        }
    }
}

/// Largest acceleration measured from three consecutive steps, steps/s².
fn measured_acceleration(steps: &[reach::drive::Step]) -> f64 {
    steps
        .windows(3)
        .map(|w| {
            let (d1, d2) = (w[1].t - w[0].t, w[2].t - w[1].t);
            ((1.0 / d2 - 1.0 / d1) / (0.5 * (d1 + d2))).abs()
        })
        .fold(0.0, f64::max)
}

/// A back-and-forth path on planar3: three sines with different periods, sampled every
/// `dt`, ending exactly where it started.
fn back_and_forth(robot: &Robot, seconds: f64, dt: f64) -> Vec<JointSample> {
    let n = (seconds / dt).round() as usize;
    (0..=n)
        .map(|i| {
            let t = i as f64 * dt;
            let f = |amp: f64, period: f64, base: f64| deg(base + amp * (TAU * t / period).sin());
            let q = if i == n {
                vec![deg(45.123), deg(-90.456), deg(-30.789)] // exactly the start values
            } else {
                vec![f(12.0, 5.0, 45.123), f(6.0, 2.5, -90.456), f(2.9, 1.25, -30.789)]
            };
            JointSample::of(robot, t, q)
        })
        .collect()
}

#[test]
fn long_back_and_forth_path_has_zero_net_drift() {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let samples = back_and_forth(&robot, 100.0, 0.001); // 20 full periods of the slowest sine
    let schedule = schedule_trajectory(&axes, &samples).unwrap();
    for (j, axis) in schedule.joints.iter().zip(&axes) {
        assert_eq!(j.end_position, j.start_position, "joint {}", axis.joint);
        let net: i64 = j.steps.iter().map(|s| i64::from(s.dir)).sum();
        assert_eq!(net, 0);
        assert_eq!(j.steps.last().map_or(j.start_position, |s| s.position), j.end_position);
        assert!(j.steps.len() > 1000, "the path moves: {} steps", j.steps.len());
    }
    // Rounding each sample increment separately (what accumulating the error avoids) loses
    // steps on this very path: at 1 ms samples every increment is below half a step, so the
    // naive counter falls far behind the plan. The schedule's counter never does.
    let mut worst_naive = 0_i64;
    for (a, axis) in axes.iter().enumerate() {
        let mut naive = axis.quantise(samples[0].q[a]);
        for w in samples.windows(2) {
            naive += (axis.exact_steps(w[1].q[a]) - axis.exact_steps(w[0].q[a])).round() as i64;
            let exact = axis.quantise(w[1].q[a]);
            worst_naive = worst_naive.max((naive - exact).abs());
            let held = schedule.joints[a].position_at(w[1].t);
            assert!((held - exact).abs() <= 1, "joint {} at t = {}", axis.joint, w[1].t);
        }
    }
    assert!(worst_naive > 100, "naive rounding loses {worst_naive} steps");
}

#[test]
fn simulated_angles_stay_within_one_step_of_the_plan() {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let samples = back_and_forth(&robot, 10.0, 0.004);
    let schedule = schedule_trajectory(&axes, &samples).unwrap();
    let v = verify(&robot, &schedule, &samples).unwrap();
    assert!(v.within_one_step);
    for (j, a) in axes.iter().enumerate() {
        // Rounding: half a step at the samples, unless chatter was dropped (< 1 step).
        assert!(v.max_deviation_steps[j] <= 0.5 + 1e-9, "joint {}: {}", a.joint, v.max_deviation_steps[j]);
        assert!((v.max_deviation[j] - v.max_deviation_steps[j] / a.steps_per_unit).abs() < 1e-15);
        assert!(v.max_deviation_steps[j] > 0.3, "the test path exercises the rounding");
    }
    // Tool space: planar3 has 1 m links, so a joint error of e rad moves the tool by at most
    // (3 + 2 + 1)·e for joints 1..3 combined.
    let bound: f64 = v.max_deviation[0] * 3.0 + v.max_deviation[1] * 2.0 + v.max_deviation[2];
    assert!(v.tool_position_error > 0.0 && v.tool_position_error <= bound + 1e-12);
    // Between samples, against the linear interpolation the schedule quantises.
    for w in samples.windows(2).step_by(37) {
        for frac in [0.1, 0.5, 0.9] {
            let t = w[0].t + frac * (w[1].t - w[0].t);
            let held = schedule.joint_values_at(t);
            for (a, axis) in axes.iter().enumerate() {
                let plan = w[0].q[a] + frac * (w[1].q[a] - w[0].q[a]);
                assert!(((held[a] - plan) * axis.steps_per_unit).abs() <= 0.5 + 1e-6);
            }
        }
    }
    assert_rates_respected(&schedule);
}

#[test]
fn plan_turning_back_at_a_step_boundary_does_not_chatter() {
    // A motor hovering around a half-step boundary: s = 0.5 + 0.3·sin(2π·200·t) steps, peak rate
    // 0.3·2π·200 = 377 Hz < 500 Hz. Plain rounding would step up and back within < 2 ms.
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let k = axes[0].steps_per_unit;
    let samples: Vec<JointSample> = (0..=2000)
        .map(|i| {
            let t = i as f64 * 1e-4;
            let s = 0.5 + 0.3 * (TAU * 200.0 * t).sin();
            JointSample::of(&robot, t, vec![s / k, 0.0, 0.0])
        })
        .collect();
    let schedule = schedule_trajectory(&axes, &samples).unwrap();
    assert_rates_respected(&schedule);
    let v = verify(&robot, &schedule, &samples).unwrap();
    assert!(v.within_one_step, "{:?}", v.max_deviation_steps);
    assert!(v.max_deviation_steps[0] > 0.5, "the chatter was dropped, so the plan leads by more than half a step");
}

#[test]
fn a_too_fast_trajectory_names_the_joint_the_time_and_a_slower_duration() {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    // Joint 2 moves 36° in 1 s (1000 Hz at 27.78 steps/deg) from t = 1 s to 2 s; at rest before.
    let samples: Vec<JointSample> = (0..=300)
        .map(|i| {
            let t = i as f64 * 0.01;
            let u = ((t - 1.0).clamp(0.0, 1.0)).min(1.0);
            JointSample::of(&robot, t, vec![0.0, deg(-36.0 * u), 0.0])
        })
        .collect();
    let err = schedule_trajectory(&axes, &samples).unwrap_err();
    match &err {
        DriveError::RateLimit { joint, name, time, rate, limit, duration, suggested } => {
            assert_eq!((*joint, name.as_str()), (2, "B"));
            assert!((*time - 1.0).abs() < 1e-9, "first violation at t = 1 s, got {time}");
            assert!((*rate - 1000.0).abs() < 1e-6);
            assert_eq!(*limit, 500.0);
            assert!((*duration - 3.0).abs() < 1e-12);
            assert!((*suggested - 6.0).abs() < 1e-6, "twice as slow: {suggested}");
        }
        other => panic!("expected a rate error, got {other:?}"),
    }
    let message = err.to_string();
    assert!(message.contains("joint 2 (B)") && message.contains("t = 1.0000 s") && message.contains("6.0000 s"));
    // The suggestion works; 1 % faster than it does not.
    let retimed = |factor: f64| -> Vec<JointSample> {
        samples.iter().map(|s| JointSample { t: s.t * factor, ..s.clone() }).collect()
    };
    let ok = schedule_trajectory(&axes, &retimed(2.0)).unwrap();
    assert_rates_respected(&ok);
    assert_eq!(ok.joints[1].steps.len(), 1000);
    assert!(matches!(schedule_trajectory(&axes, &retimed(1.98)), Err(DriveError::RateLimit { .. })));
}

#[test]
fn acceleration_limits_are_checked_on_sampled_trajectories() {
    let robot = presets::get("log-loader").unwrap();
    let axes = axes(&robot).unwrap();
    let k = axes[2].steps_per_unit; // 33.33 steps/deg, 2000 steps/s², 500 Hz
    // Joint 3 accelerates at 3000 steps/s² for 0.1 s (to 300 Hz), then cruises.
    let samples: Vec<JointSample> = (0..=100)
        .map(|i| {
            let t = i as f64 * 0.002;
            let s = if t <= 0.1 { 1500.0 * t * t } else { 15.0 + 300.0 * (t - 0.1) };
            JointSample::of(&robot, t, vec![0.0, 0.0, s / k])
        })
        .collect();
    match schedule_trajectory(&axes, &samples).unwrap_err() {
        DriveError::AccelerationLimit { joint, acceleration, limit, suggested, duration, .. } => {
            assert_eq!(joint, 3);
            assert!((acceleration - 3000.0).abs() < 1e-6, "{acceleration}");
            assert_eq!(limit, 2000.0);
            // Slowing time by c divides accelerations by c²: c = √(3000/2000).
            assert!((suggested - duration * 1.5_f64.sqrt()).abs() < 1e-9);
        }
        other => panic!("expected an acceleration error, got {other:?}"),
    }
}

#[test]
fn malformed_trajectories_are_rejected() {
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let s = |t: f64, q: Vec<f64>| JointSample::of(&robot, t, q);
    let cases = [
        (vec![s(0.0, vec![0.0; 3])], "at least 2"),
        (vec![s(0.0, vec![0.0; 3]), s(1.0, vec![0.0; 2])], "sample 1 has 2"),
        (vec![s(0.0, vec![0.0; 3]), s(0.0, vec![0.0; 3])], "increase"),
        (vec![s(0.0, vec![0.0; 3]), s(1.0, vec![0.0, f64::NAN, 0.0])], "joint 2"),
        (vec![s(f64::NAN, vec![0.0; 3]), s(1.0, vec![0.0; 3])], "time"),
    ];
    for (samples, needle) in cases {
        let e = schedule_trajectory(&axes, &samples).unwrap_err().to_string();
        assert!(e.contains(needle), "{needle}: {e}");
    }
}

fn loader_axes() -> (reach::Robot, Vec<Axis>) {
    let robot = presets::get("log-loader").unwrap();
    let axes = axes(&robot).unwrap();
    (robot, axes)
}

#[test]
fn point_to_point_trapezoid_is_synchronised_and_within_limits() {
    let (robot, axes) = loader_axes();
    // 33.33 steps/deg: 90°, −45°, 30° = 3000, 1500, 1000 steps.
    let to = [deg(90.0), deg(-45.0), deg(30.0)];
    let plan = point_to_point(&axes, &[0.0; 3], &to, None, 0.0).unwrap();
    assert_eq!(plan.to_steps, [3000, -1500, 1000]);
    // Bottleneck joint 1: f/φ = 500/3000, a/φ = 2000/(1.02·3000) (2 % ramp margin).
    let (v, a) = (500.0 / 3000.0, 2000.0 / (1.02 * 3000.0));
    assert!((plan.cruise - v).abs() < 1e-12);
    assert!((plan.acceleration.unwrap() - a).abs() < 1e-12);
    let expected = 1.0 / v + v / a; // trapezoid: distance/speed + ramp time
    assert!((plan.duration - expected).abs() < 1e-9, "{} vs {expected}", plan.duration);
    for j in &plan.schedule.joints {
        let last = j.steps.last().unwrap();
        assert!((last.t - plan.duration).abs() < 1e-12, "joint {} ends at {}", j.axis.joint, last.t);
        assert!(measured_acceleration(&j.steps) <= j.axis.max_acceleration.unwrap(), "joint {}", j.axis.joint);
    }
    assert_rates_respected(&plan.schedule);
    // Joint 1 cruises at exactly its maximum rate (the seed's "longest move at maximum speed").
    let steps = &plan.schedule.joints[0].steps;
    let mid = &steps[1500..1502];
    assert!((1.0 / (mid[1].t - mid[0].t) - 500.0).abs() < 1e-6);
    // Simulated angles within one step of the (grid-snapped) plan.
    let check = verify(&robot, &plan.schedule, &plan.samples(&robot, 2000)).unwrap();
    assert!(check.within_one_step, "{:?}", check.max_deviation_steps);
}

#[test]
fn point_to_point_short_moves_are_triangular_and_durations_are_checked() {
    let (_, axes) = loader_axes();
    // 60 steps on joint 2 only: v²/a = (500/60)²/(2000/(1.02·60)) > 1 → triangle, T = 2/√a.
    let to = [0.0, deg(1.8), 0.0];
    let plan = point_to_point(&axes, &[0.0; 3], &to, None, 0.0).unwrap();
    let a: f64 = 2000.0 / (1.02 * 60.0);
    assert!((plan.duration - 2.0 / a.sqrt()).abs() < 1e-9);
    assert!(measured_acceleration(&plan.schedule.joints[1].steps) <= 2000.0);
    assert_rates_respected(&plan.schedule);
    // Too short a duration names the limiting joint and the shortest feasible duration.
    match point_to_point(&axes, &[0.0; 3], &to, Some(0.1), 0.0).unwrap_err() {
        DriveError::DurationTooShort { needed, joint, .. } => {
            assert_eq!(joint, 2);
            assert!((needed - plan.duration).abs() < 1e-12);
        }
        other => panic!("{other:?}"),
    }
    // A longer duration keeps the ramp acceleration and lowers the cruise rate; still ends on time.
    let slow = point_to_point(&axes, &[0.0; 3], &to, Some(2.0), 0.5).unwrap();
    assert!((slow.duration - 2.0).abs() < 1e-15);
    let steps = &slow.schedule.joints[1].steps;
    assert!((steps.last().unwrap().t - 2.5).abs() < 1e-12);
    assert!(slow.cruise * 60.0 < 500.0);
    // Check v from the trapezoid relation: distance 1 = v·(T − v/a).
    assert!((slow.cruise * (2.0 - slow.cruise / a) - 1.0).abs() < 1e-9);
    assert!(measured_acceleration(steps) <= 2000.0);
}

#[test]
fn no_motion_and_bad_inputs() {
    let (_, axes) = loader_axes();
    let plan = point_to_point(&axes, &[0.1; 3], &[0.1; 3], None, 0.0).unwrap();
    assert_eq!(plan.duration, 0.0);
    assert_eq!(plan.schedule.step_count(), 0);
    let e = point_to_point(&axes, &[0.0; 3], &[0.0, f64::INFINITY, 0.0], None, 0.0).unwrap_err().to_string();
    assert!(e.contains("joint 2"), "{e}");
    let e = point_to_point(&axes, &[0.0; 2], &[0.0; 3], None, 0.0).unwrap_err().to_string();
    assert!(e.contains("2 joint values"), "{e}");
    let e = point_to_point(&axes, &[0.0; 3], &[0.0; 3], Some(-1.0), 0.0).unwrap_err().to_string();
    assert!(e.contains("duration"), "{e}");
    let _ = PI;
}

#[test]
fn grid_error_of_an_end_point_in_joint_and_tool_space() {
    // planar3: 27.78 steps/deg. −30° is −833.33 steps → −833 = −29.988°: error +0.012° on
    // joint 3 only; the tool (1 m from joint A) moves by 2·sin(0.006°) m.
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let q = [deg(90.0), deg(-45.0), deg(-30.0)];
    let g = reach::drive::grid_error(&robot, &axes, &q).unwrap();
    let e3 = 30.0 - 833.0 * 0.036; // degrees: 833 steps of 0.036°
    assert!(g.joint_error[0].abs() < 1e-12 && g.joint_error[1].abs() < 1e-12);
    assert!((g.joint_error[2].to_degrees() - e3).abs() < 1e-9);
    let chord = 2.0 * (deg(e3) / 2.0).sin().abs();
    assert!((g.tool_position_error - chord).abs() < 1e-12, "{} vs {chord}", g.tool_position_error);
    assert!((g.tool_orientation_error - deg(e3).abs()).abs() < 1e-12);
}
