//! End-to-end tests of `reach retime`: the report equals the library's and its schema, the
//! samples respect the limits and pass the waypoints, the CSV carries units, the output of
//! `reach path --json` chains in through standard input, `--ros FILE` writes the ROS
//! `JointTrajectory` message (JSON or YAML), and bad input is one line.

use std::io::Write;
use std::process::Stdio;

use reach::jobs::retime::{Interpolation, RetimeRequest};
use reach::jobs::{Job, Joints, Request, RobotInput};

use crate::common::{
    Run, assert_report, assert_valid, fails, nums, ok, reach_command, scratch, stdout_json, temp_file,
};

const PANDA: &str = "../../examples/panda_waypoints.csv";

fn example(name: &str) -> String {
    format!("{}/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn panda_spline_report_is_the_library_one_and_within_limits() {
    let path = example(PANDA);
    let waypoints = vec![
        Joints::Deg(vec![0.0, -17.0, 0.0, -126.0, 0.0, 115.0, 45.0]),
        Joints::Deg(vec![30.0, 0.0, 20.0, -100.0, 10.0, 90.0, 0.0]),
        Joints::Deg(vec![60.0, 20.0, -20.0, -80.0, -10.0, 120.0, -30.0]),
        Joints::Deg(vec![10.0, -30.0, 0.0, -140.0, 0.0, 100.0, 45.0]),
    ];
    let request = RetimeRequest {
        waypoints: waypoints.clone(),
        interpolation: Interpolation::Spline,
        blend_tolerance: None,
        dt: Some(0.005),
        max_velocity_scale: 1.0,
        max_acceleration_scale: 0.5,
        points_per_piece: None,
    };
    let job = Job { robot: RobotInput::Preset("panda".into()), request: Request::Retime(request) };
    let v = assert_report(
        &["retime", "panda", &path, "--dt", "0.005", "--max-acceleration-scale", "0.5", "--json"],
        &job,
        "retime.report",
    );
    assert_eq!(v["waypoints"], 4);
    let duration = v["duration_s"].as_f64().unwrap();
    let vmax = nums(&v["velocity_limits"]);
    let amax = nums(&v["acceleration_limits"]);
    // Franka's joint-1 limits, the acceleration halved.
    assert!((vmax[0] - 2.175).abs() < 1e-12 && (amax[0] - 7.5).abs() < 1e-12, "{vmax:?} {amax:?}");
    // The exact worst ratios are within the limits and some limit binds (time-optimal).
    let worst: Vec<f64> =
        nums(&v["worst_velocity_ratio"]).into_iter().chain(nums(&v["worst_acceleration_ratio"])).collect();
    assert!(worst.iter().all(|&r| r <= 1.0 + 1e-9), "{worst:?}");
    assert!(worst.iter().any(|&r| r > 0.99), "no limit binds: {worst:?}");
    // Every sample is within the limits, rests at both ends, and the path starts and ends at
    // the first and last waypoint.
    let samples = v["samples"].as_array().unwrap();
    let whole = (duration / 0.005).floor() as usize;
    assert!(samples.len() == whole + 1 || samples.len() == whole + 2, "{} samples over {duration} s", samples.len());
    for s in samples {
        for (j, (qd, qdd)) in nums(&s["qd"]).into_iter().zip(nums(&s["qdd"])).enumerate() {
            assert!(qd.abs() <= vmax[j] * (1.0 + 1e-9) && qdd.abs() <= amax[j] * (1.0 + 1e-9), "{s}");
        }
    }
    let deg = |s: &serde_json::Value| nums(&s["q"]).into_iter().map(f64::to_degrees).collect::<Vec<_>>();
    let (first, last) = (samples.first().unwrap(), samples.last().unwrap());
    let Joints::Deg(start) = &waypoints[0] else { unreachable!() };
    let Joints::Deg(goal) = &waypoints[3] else { unreachable!() };
    for (got, want) in deg(first).iter().zip(start).chain(deg(last).iter().zip(goal)) {
        assert!((got - want).abs() < 1e-9, "{got} vs {want}");
    }
    assert_eq!(last["t_s"].as_f64().unwrap(), duration);
    assert!(nums(&first["qd"]).iter().chain(&nums(&last["qd"])).all(|v| v.abs() < 1e-9));
    // Halving the acceleration limit makes the motion slower, not faster.
    let full = crate::common::json(&["retime", "panda", &path, "--json"]);
    assert!(full["duration_s"].as_f64().unwrap() < duration);
}

#[test]
fn text_summary_and_csv_with_units() {
    let path = example(PANDA);
    let csv = temp_file("timed.csv", "");
    let text = ok(&["retime", "panda", &path, "--interpolation", "linear", "--csv", csv.to_str().unwrap()]);
    assert!(text.contains("straight segments, resting at each waypoint"), "{text}");
    assert!(text.contains("panda_joint7") && text.contains("deg/s²"), "{text}");
    let table = std::fs::read_to_string(&*csv).unwrap();
    let header = table.lines().next().unwrap();
    assert!(header.starts_with("t_s,q1_deg,q2_deg"), "{header}");
    assert!(header.contains(",qd7_deg_s,qdd1_deg_s2,") && header.ends_with("qdd7_deg_s2"), "{header}");
    // Linear interpolation rests at every waypoint: some inner sample is near the second
    // waypoint with nearly zero speed, and the rows hold 1 + 3 × 7 values.
    let rows: Vec<Vec<f64>> =
        table.lines().skip(1).map(|l| l.split(',').map(|c| c.parse().unwrap()).collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 22));
    let second = [30.0, 0.0, 20.0, -100.0, 10.0, 90.0, 0.0];
    let distance = |r: &Vec<f64>| r[1..8].iter().zip(&second).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
    let speed = |r: &Vec<f64>| r[8..15].iter().map(|v| v * v).sum::<f64>().sqrt();
    let nearest = rows.iter().min_by(|a, b| distance(a).total_cmp(&distance(b))).unwrap();
    let top_speed = rows.iter().map(speed).fold(0.0, f64::max);
    assert!(distance(nearest) < 1.0, "{nearest:?}");
    assert!(speed(nearest) < 0.1 * top_speed, "{nearest:?} against top speed {top_speed}");
}

/// `--ros x.json`: the ROS 2 `trajectory_msgs/JointTrajectory` of the same motion as `--json`:
/// the robot's joint names, one point per sample with its SI values, `time_from_start` the
/// sample's time to the nanosecond and strictly increasing; the file matches its schema.
#[test]
fn ros_json_is_the_joint_trajectory_of_the_report() {
    let path = example(PANDA);
    let dir = scratch("ros");
    let file = dir.join("timed.json");
    let report =
        crate::common::json(&["retime", "panda", &path, "--dt", "0.05", "--ros", file.to_str().unwrap(), "--json"]);
    let message: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&file).unwrap()).unwrap();
    assert_valid("joint_trajectory", &message);
    let robot = reach::jobs::RobotInput::Preset("panda".into()).load().unwrap().robot;
    let names: Vec<&str> = robot.joints().iter().map(|j| j.name.as_str()).collect();
    let got: Vec<&str> = message["joint_names"].as_array().unwrap().iter().map(|n| n.as_str().unwrap()).collect();
    assert_eq!(got, names);
    assert_eq!(message["header"], serde_json::json!({"stamp": {"sec": 0, "nanosec": 0}, "frame_id": ""}));
    let samples = report["samples"].as_array().unwrap();
    let points = message["points"].as_array().unwrap();
    assert!(samples.len() > 10);
    assert_eq!(points.len(), samples.len());
    let mut previous: Option<(i64, u64)> = None;
    for (p, s) in points.iter().zip(samples) {
        let time = &p["time_from_start"];
        let (sec, nanosec) = (time["sec"].as_i64().unwrap(), time["nanosec"].as_u64().unwrap());
        assert!(nanosec < 1_000_000_000, "{time}");
        let t = sec as f64 + nanosec as f64 * 1e-9;
        assert!((t - s["t_s"].as_f64().unwrap()).abs() <= 1e-9, "{time} against {}", s["t_s"]);
        assert!(previous.is_none_or(|before| before < (sec, nanosec)), "{previous:?} then {time}");
        previous = Some((sec, nanosec));
        assert_eq!(p["positions"], s["q"]);
        assert_eq!(p["velocities"], s["qd"]);
        assert_eq!(p["accelerations"], s["qdd"]);
        assert_eq!(p["effort"], serde_json::json!([]));
    }
}

/// `--ros x.yaml` writes the same message as YAML, which reads back to the JSON one.
#[test]
fn ros_yaml_reads_back_to_the_json_message() {
    let path = example(PANDA);
    let dir = scratch("ros");
    let (json, yaml) = (dir.join("timed.json"), dir.join("timed.yaml"));
    for file in [&json, &yaml] {
        ok(&["retime", "panda", &path, "--interpolation", "blend", "--dt", "0.1", "--ros", file.to_str().unwrap()]);
    }
    let text = std::fs::read_to_string(&yaml).unwrap();
    assert!(text.starts_with("header:") && text.contains("time_from_start:"), "{text}");
    let from_yaml = reach::jobs::JointTrajectory::from_yaml(&text).unwrap();
    let from_json: reach::jobs::JointTrajectory =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert!(!from_yaml.points.is_empty());
    assert_eq!(from_yaml, from_json);
}

/// `--ros` with another extension is one line naming the flag and the accepted extensions,
/// before any work, and writes nothing.
#[test]
fn ros_with_another_extension_is_one_line_and_no_file() {
    let path = example(PANDA);
    let dir = scratch("ros");
    for name in ["timed.txt", "timed"] {
        let file = dir.join(name);
        fails(&["retime", "panda", &path, "--ros", file.to_str().unwrap()], 2, &["--ros", ".yaml", ".yml", ".json"]);
        assert!(!file.exists(), "{} was written", file.display());
    }
}

#[test]
fn a_planned_path_chains_in_through_standard_input() {
    let scene = example("../../examples/ur5_ball.toml");
    let path = ok(&["path", "ur5", &scene, "--from", "90,-90,90,-90,-90,0", "--to", "-90,-60,60,-90,-90,0", "--json"]);
    let mut child = reach_command(&["retime", "ur5", "-", "--json"])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(path.as_bytes()).unwrap();
    let run = Run::from_output(child.wait_with_output().unwrap());
    let v = stdout_json(&run);
    let planned: serde_json::Value = serde_json::from_str(&path).unwrap();
    assert_eq!(v["waypoints"].as_u64().unwrap() as usize, planned["waypoints_deg"].as_array().unwrap().len());
    // UR's MoveIt configuration: 5 rad/s² on every joint.
    assert!(nums(&v["acceleration_limits"]).iter().all(|&a| (a - 5.0).abs() < 1e-6));
    assert!(nums(&v["worst_acceleration_ratio"]).iter().all(|&r| r <= 1.0 + 1e-9));
}

#[test]
fn bad_input_is_one_line_naming_the_place() {
    let bad = temp_file("bad.csv", "0,-90,0,-90,0,0\n30,nan,20,-90,10,0\n");
    fails(&["retime", "ur5", bad.to_str().unwrap()], 2, &["line 2, column 2", "\"nan\""]);
    let ragged = temp_file("ragged.csv", "0,-90,0,-90,0,0\n30,-60,20\n");
    fails(&["retime", "ur5", ragged.to_str().unwrap()], 2, &["line 2", "3 values", "first row has 6"]);
    let one = temp_file("one.csv", "# a single waypoint\n0,-90,0,-90,0,0\n");
    fails(&["retime", "ur5", one.to_str().unwrap()], 2, &["at least 2"]);
    let outside = temp_file("outside.csv", "0,0,0,0,0,0\n350,0,0,0,0,0\n-350,0,0,0,0,0\n");
    fails(
        &["retime", "ur5", outside.to_str().unwrap()],
        2,
        &["spline", "joint 1 (shoulder_pan)", "360 deg", "between waypoints 1 and 2", "364.58"],
    );
    let two = temp_file("two.csv", "0,-90,0,-90,0,0\n30,-60,20,-90,10,0\n");
    let two = two.to_str().unwrap();
    fails(&["retime", "ur5", two, "--dt", "0"], 2, &["--dt", "> 0"]);
    fails(&["retime", "ur5", two, "--max-velocity-scale", "1.5"], 2, &["--max-velocity-scale", "≤ 1"]);
    fails(&["retime", "ur5", two, "--points-per-piece", "2000000"], 2, &["--points-per-piece", "cap"]);
    fails(&["retime", "ur5", two, "--dt", "1e-9"], 2, &["--dt", "samples"]);
    // A preset without acceleration limits names the joint and says where the limit goes.
    let puma = temp_file("puma.csv", "0,0,0,0,0,0\n10,10,10,0,0,0\n");
    fails(&["retime", "puma560", puma.to_str().unwrap()], 2, &["joint 1", "max_velocity", "--joint-limits"]);
}

/// `reach path` times a planned path time-optimally by default when the robot has velocity and
/// acceleration limits, along the straight edges the swept check proved clear.
#[test]
fn a_planned_path_is_timed_optimally_by_default() {
    let scene = example("../../examples/ur5_ball.toml");
    let base = ["path", "ur5", &scene, "--from", "90,-90,90,-90,-90,0", "--to", "-90,-60,60,-90,-90,0", "--json"];
    let optimal = crate::common::json(&base);
    assert_eq!(optimal["timing"], "optimal");
    assert_eq!(optimal["collision_free"], true);
    let duration = optimal["duration_s"].as_f64().unwrap();
    let segments = nums(&optimal["segment_durations_s"]);
    assert_eq!(segments.len() + 1, optimal["waypoints_deg"].as_array().unwrap().len());
    assert!((segments.iter().sum::<f64>() - duration).abs() < 1e-9, "{segments:?} against {duration}");
    // Time-optimal: within every limit, and some limit is reached.
    let worst: Vec<f64> =
        nums(&optimal["worst_velocity_ratio"]).into_iter().chain(nums(&optimal["worst_acceleration_ratio"])).collect();
    assert!(worst.iter().all(|&r| r <= 1.0 + 1e-9), "{worst:?}");
    assert!(worst.iter().any(|&r| r > 0.99), "{worst:?}");
    // Half the acceleration: slower, still within the scaled limits.
    let slower = crate::common::json(&[&base[..], &["--max-acceleration-scale", "0.5"]].concat());
    assert!(slower["duration_s"].as_f64().unwrap() > duration);
    assert!(nums(&slower["worst_acceleration_ratio"]).iter().all(|&r| r <= 1.0 + 1e-9));
    // A fixed duration means cycloidal timing; optimal timing cannot take one.
    let fixed = crate::common::json(&[&base[..], &["--duration", "6"]].concat());
    assert_eq!(fixed["timing"], "cycloidal");
    assert!((fixed["duration_s"].as_f64().unwrap() - 6.0).abs() < 1e-9);
    assert!(fixed["worst_velocity_ratio"].is_null());
    fails(&[&base[..], &["--timing", "optimal", "--duration", "6"]].concat(), 2, &["--duration", "optimal timing"]);
    fails(
        &[&base[..], &["--duration", "6", "--max-velocity-scale", "0.5"]].concat(),
        2,
        &["--max-velocity-scale", "a duration is given"],
    );
    // A robot without acceleration limits is timed cycloidal unless optimal is asked for.
    let post = example("../../examples/path_planar3_post.toml");
    let planar = crate::common::json(&[
        "path",
        "planar3",
        &post,
        "--from",
        "60,-40,-30",
        "--to",
        "0,-30,-30",
        "--duration",
        "5",
        "--json",
    ]);
    assert_eq!(planar["timing"], "cycloidal");
    fails(
        &["path", "planar3", &post, "--from", "60,-40,-30", "--to", "0,-30,-30", "--timing", "optimal"],
        2,
        &["joint 1", "--joint-limits"],
    );
}

/// Blends: `retime --interpolation blend[:TOL]` passes the corners without stopping (shorter
/// than `linear`, within the limits), `path --blend` times the planned path the same way, and
/// a bad tolerance or word is one line naming the flag.
#[test]
fn blends_cut_the_corners_of_retime_and_path() {
    let path = example(PANDA);
    let duration = |extra: &[&str]| {
        let v = crate::common::json(&[&["retime", "panda", &path, "--json"][..], extra].concat());
        let worst: Vec<f64> =
            nums(&v["worst_velocity_ratio"]).into_iter().chain(nums(&v["worst_acceleration_ratio"])).collect();
        assert!(worst.iter().all(|&r| r <= 1.0), "{worst:?}");
        (v["duration_s"].as_f64().unwrap(), v)
    };
    let (linear, _) = duration(&["--interpolation", "linear"]);
    let (blend, v) = duration(&["--interpolation", "blend"]);
    let (tight, _) = duration(&["--interpolation", "blend:0.01"]);
    assert_eq!(v["interpolation"], "blend");
    assert_eq!(v["blend_tolerance"], 0.1);
    assert_eq!(nums(&v["waypoint_times_s"]).len(), v["waypoints"].as_u64().unwrap() as usize);
    assert!(blend < tight && tight < linear, "blend {blend}, blend:0.01 {tight}, linear {linear}");
    fails(&["retime", "panda", &path, "--interpolation", "blend:-1"], 2, &["--interpolation blend:TOL", "≥ 0"]);
    fails(&["retime", "panda", &path, "--interpolation", "wobble"], 2, &["--interpolation", "spline, linear, blend"]);

    let scene = example("../../examples/ur5_ball.toml");
    let base = ["path", "ur5", &scene, "--from", "90,-90,90,-90,-90,0", "--to", "-90,-60,60,-90,-90,0", "--json"];
    let blended = crate::common::json(&base);
    let stop = crate::common::json(&[&base[..], &["--blend", "0"]].concat());
    assert!(blended["blend_tolerance"].as_f64().unwrap() > 0.0 && stop["blend_tolerance"] == 0.0);
    assert_eq!(blended["collision_free"], true);
    assert!(blended["duration_s"].as_f64().unwrap() <= stop["duration_s"].as_f64().unwrap());
    let text = ok(&base[..base.len() - 1]);
    assert!(text.contains("blends corners within"), "{text}");
    fails(&[&base[..], &["--blend", "x"]].concat(), 2, &["--blend"]);
    fails(&[&base[..], &["--blend", "0.1", "--duration", "5"]].concat(), 2, &["--blend", "optimal timing only"]);
}
