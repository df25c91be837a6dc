//! End-to-end tests of `reach approach` (seed 004: motion synthesis next to forbidden zones).

use crate::common::{fails, json, reach, stdout_json};

const CEILING: &str = "examples/seed004_ceiling.toml";

#[test]
fn a_goal_below_the_ceiling_is_reached_and_the_json_is_the_report() {
    let v = json(&["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "1.5,0,0.6", "--json"]);
    assert_eq!(v["outcome"], "reached");
    assert!(v["position_error_m"].as_f64().unwrap() <= 1e-4);
    assert!(v["min_margin_m"].as_f64().unwrap() > 0.0);
    assert_eq!(v["safe_distance_m"], 0.05);
    let motion = v["motion_deg"].as_array().unwrap();
    assert_eq!(motion.len() as u64, v["samples"].as_u64().unwrap());
    let first: Vec<f64> = motion[0].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect();
    assert!(first.iter().zip([0.0, 30.0, 0.0, 0.0]).all(|(a, b)| (a - b).abs() < 1e-9), "{first:?}");
}

#[test]
fn a_deadlock_exits_3_after_the_report_with_the_planner_s_path() {
    let args = ["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "0.7231,0,0.5006", "--json"];
    let run = reach(&args);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(run.stderr.contains("goal not reached"), "{}", run.stderr);
    let v = stdout_json(&run);
    assert_eq!(v["outcome"], "deadlock");
    assert_eq!(v["handover"]["found"], true);
    // Text output too.
    let run = reach(&args[..args.len() - 1]);
    assert_eq!(run.code, 3);
    assert!(
        run.stdout.contains("outcome         deadlock") && run.stdout.contains("planner found a path"),
        "{}",
        run.stdout
    );
}

#[test]
fn bad_input_names_the_flag() {
    fails(
        &["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "1.5,0,0.6", "--safe-distance", "-1"],
        2,
        &["--safe-distance"],
    );
    fails(&["approach", "varan4", CEILING, "--from", "0,30,0,0"], 2, &["--to"]);
    // The start is 0.15 m below the ceiling: a 0.2 m safe distance refuses it.
    fails(
        &["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "1.5,0,0.6", "--safe-distance", "0.2"],
        2,
        &["--from", "safe distance"],
    );
}

/// Issue 33: an approach is timed time-optimally when the robot has limits — the log loader's
/// come from its stepper drives (15°/s, 60°/s²) — with its samples' corners blended and the
/// blended path proven to keep the safe distance; untimed without limits.
#[test]
fn the_motion_is_timed_within_the_limits_when_the_robot_has_them() {
    let ball = "examples/log_loader_ball.toml";
    let base = ["approach", "log-loader", ball, "--from", "90,0,0", "--to", "90,60,-90", "--json"];
    let v = json(&base);
    assert_eq!((v["outcome"].as_str(), v["timing"].as_str()), (Some("reached"), Some("optimal")), "{v}");
    assert_eq!((v["collision_free"].as_bool(), v["swept"]["clear"].as_bool()), (Some(true), Some(true)), "{v}");
    assert!(v["blend_tolerance"].as_f64().unwrap() > 0.0, "{v}");
    let worst = |key: &str| v[key].as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).fold(0.0, f64::max);
    // Joint 3 travels 90° at 15°/s at most, ramping at 60°/s²: at least 6 s + 0.25 s.
    let duration = v["duration_s"].as_f64().unwrap();
    assert!((6.25..6.5).contains(&duration), "{duration}");
    assert!(worst("worst_velocity_ratio") <= 1.0 + 1e-9 && worst("worst_velocity_ratio") > 0.99, "{v}");
    assert!(worst("worst_acceleration_ratio") <= 1.0 + 1e-9, "{v}");
    // Half the speed: longer.
    let slow = json(&[&base[..], &["--max-velocity-scale", "0.5"]].concat());
    assert!(slow["duration_s"].as_f64().unwrap() > 1.9 * (duration - 0.25), "{slow}");
    // Text: the duration line and the check of the blended path.
    let run = reach(&base[..base.len() - 1]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(
        run.stdout.contains("time-optimal") && run.stdout.contains("links grown by the safe distance"),
        "{}",
        run.stdout
    );
    // varan4 has no velocity or acceleration limits: not timed, and asking names what is missing.
    let v = json(&["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "1.5,0,0.6", "--json"]);
    assert_eq!((v["timing"].as_str(), v["duration_s"].as_f64()), (Some("none"), None), "{v}");
    let untimed = ["approach", "varan4", CEILING, "--from", "0,30,0,0", "--to-xyz", "1.5,0,0.6"];
    fails(&[&untimed[..], &["--timing", "optimal"]].concat(), 2, &["max_velocity"]);
    fails(&[&untimed[..], &["--blend", "0.05"]].concat(), 2, &["--blend", "optimal timing"]);
    fails(&[&base[..], &["--blend", "-1"]].concat(), 2, &["--blend"]);
    fails(&[&base[..], &["--max-acceleration-scale", "0"]].concat(), 2, &["--max-acceleration-scale"]);
}
