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
