//! End-to-end tests of `reach move` and `reach plan`: seed 001's J values (notes 001 §5–6, the
//! values crates/reach/tests/it/seed_001_motion.rs pins), seed 003's weld (notes 003 §5.5), the
//! JSON feeding `reach drive`, and the error paths (exit 2 bad input, 3 infeasible).

use crate::common;

use std::f64::consts::PI;
use std::path::PathBuf;

use serde_json::Value;

use crate::common::{nums, reach};
// Short names for the shared helpers, as used throughout this file.
use crate::common::{num as f, stdout_json as json};

/// Bad input with one needle (see [`common::fails`]).
fn fails(args: &[&str], code: i32, needle: &str) {
    common::fails(args, code, &[needle]);
}

fn q(sample: &Value) -> Vec<f64> {
    nums(&sample["q_deg"])
}

const SPBU6_MOVE: [&str; 10] =
    ["move", "spbu6", "--from", "0,0,0,0,0,0", "--to", "90,0,0,90,0,0", "--duration", "10", "--dt", "0.1"];

/// Seed 001's joint motion: q(t) = λ(t/10)·(90, 0, 0, 90, 0, 0)°, λ = τ − sin(2πτ)/(2π).
#[test]
fn joint_move_endpoints_profile_and_j_values() {
    let mut args = SPBU6_MOVE.to_vec();
    args.push("--json");
    let run = reach(&args);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let v = json(&run);
    assert_eq!(v["robot"], "spbu6");
    assert_eq!(v["space"], "joint");
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 101);
    assert_eq!(q(&samples[0]), vec![0.0; 6]);
    let last = q(&samples[100]);
    for (got, want) in last.iter().zip([90.0, 0.0, 0.0, 90.0, 0.0, 0.0]) {
        assert!((got - want).abs() < 1e-9, "{last:?}");
    }
    for k in [10, 37, 50, 81] {
        let t = f(&samples[k]["t_s"]);
        let tau = t / 10.0;
        let lambda = tau - (2.0 * PI * tau).sin() / (2.0 * PI);
        assert!((q(&samples[k])[0] - 90.0 * lambda).abs() < 1e-9, "t = {t}");
        // λ' = 2 sin²(πτ)/T: 18 deg/s at mid-move.
        let qd = f(&samples[k]["qd_deg_s"][3]);
        assert!((qd - 90.0 * 2.0 * (PI * tau).sin().powi(2) / 10.0).abs() < 1e-9, "t = {t}");
    }
    // Tool point: the pole (3 cos q1, 3 sin q1, 5) (notes 001 §5.2).
    let x = &samples[50]["xyz_m"];
    assert!((f(&x[0]) - 3.0 * (PI / 4.0).cos()).abs() < 1e-9 && (f(&x[2]) - 5.0).abs() < 1e-9);
    // J1 = (1/3)·π/2 + (1/18)·π/2 = 7π/36; monotone, so J2 = J1; spbu6 has no link masses.
    assert!((f(&v["effort"]["j1"]) - 7.0 * PI / 36.0).abs() < 1e-12);
    assert!((f(&v["effort"]["j2"]) - 7.0 * PI / 36.0).abs() < 1e-12);
    assert!(v["effort"]["energy_j"].is_null());
    let note = v["effort"]["energy_note"].as_str().unwrap();
    assert!(note.contains("spbu6") && note.contains("inertial"), "{note}");
    assert_eq!(v["intervals"][0]["feasible"], true);
}

/// The task file: both motion types; the tool motion's J2 = 0.876425 (the per-sample IK nearest
/// to the previous sample, the library's pinned value) and it is infeasible (exit 3), its
/// samples on the straight line (3,0,5) → (0,3,5).
#[test]
fn seed001_plan_compares_joint_and_tool_space() {
    let run = reach(&["plan", "examples/seed001_tool_vs_joint.toml", "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1);
    assert!(run.stderr.contains("tool space"), "{}", run.stderr);
    let v = json(&run);
    let motions = v["motions"].as_array().unwrap();
    assert_eq!(motions.len(), 2);
    let (joint, tool) = (&motions[0], &motions[1]);
    assert!((f(&joint["effort"]["j1"]) - 7.0 * PI / 36.0).abs() < 1e-9);
    assert!((f(&joint["effort"]["j2"]) - 7.0 * PI / 36.0).abs() < 1e-9);
    assert_eq!(joint["feasible"], true);
    assert!((f(&tool["effort"]["j2"]) - 0.876425).abs() < 1e-6);
    assert!(f(&tool["effort"]["j2"]) > f(&joint["effort"]["j2"]));
    assert_eq!(tool["feasible"], false);
    let samples = tool["samples"].as_array().unwrap();
    assert_eq!(samples.len(), 101);
    for s in samples {
        let x = &s["xyz_m"];
        assert!((f(&x[0]) + f(&x[1]) - 3.0).abs() < 1e-6 && (f(&x[2]) - 5.0).abs() < 1e-6, "{s}");
    }
    // The end poses are T0 and T1 (tool z axis (1,0,0) → (0,1,0)... checked via position).
    assert!((f(&samples[100]["xyz_m"][1]) - 3.0).abs() < 1e-6);
    // The human-readable form prints the comparison too.
    let text = reach(&["plan", "examples/seed001_tool_vs_joint.toml"]);
    assert_eq!(text.code, 3);
    assert!(text.stdout.contains("J2 = 0.876425"), "{}", text.stdout);
}

/// Seed 003's weld: +β realised over the whole path; −β breaks θ4's range on
/// s ∈ (618.1, 882.2) mm (notes 003 §5.5); no singular position, so one interval; the θ4 wrap
/// of −β and the sampled rates give no spike (|q̇| ≪ 360°/10 s).
#[test]
fn seed003_plan_tracks_both_configurations() {
    let run = reach(&["plan", "examples/seed003_welding.toml", "--json"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let m = &json(&run)["motions"][0];
    assert!((f(&m["duration_s"]) - 943.927963).abs() < 1e-5);
    let intervals = m["intervals"].as_array().unwrap();
    assert_eq!(intervals.len(), 1);
    assert!(intervals[0]["configuration"].as_str().unwrap().contains("config=+β"));
    let reason = intervals[0]["reasons"][0].as_str().unwrap();
    assert!(reason.contains("config=−β") && reason.contains("joint 4"), "{reason}");
    assert!(reason.contains("t = 618.10") && reason.contains("t = 882.21"), "{reason}");
    let codes: Vec<&str> = m["events"].as_array().unwrap().iter().map(|e| e["code"].as_str().unwrap()).collect();
    for c in ["K3", "K6", "K7", "K9", "K11"] {
        assert!(codes.contains(&c), "{codes:?}");
    }
    assert!(!codes.contains(&"K2"), "no singular position: {codes:?}");
    // The events carry their data next to the text: K7 is θ4 (0-based joint 3) of −β leaving
    // [−175°, 150°] (radians) on s ∈ (0.618, 0.882) m.
    let k7 = m["events"].as_array().unwrap().iter().find(|e| e["code"] == "K7").expect("a K7 event");
    let detail = &k7["detail"];
    assert_eq!(detail["type"], "joint_limit", "{k7}");
    assert_eq!(detail["joint"], 3, "{k7}");
    assert!((f(&detail["lower"]) - (-175f64).to_radians()).abs() < 1e-9, "{k7}");
    assert!((f(&detail["s_start"]) - 0.6181).abs() < 1e-3 && (f(&detail["s_end"]) - 0.8822).abs() < 1e-3, "{k7}");
    assert!(k7["message"].as_str().unwrap().contains("[-175.00, 150.00] deg"), "{k7}");
    let samples = m["samples"].as_array().unwrap();
    let first = q(&samples[0]);
    for (got, want) in first.iter().zip([105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315]) {
        assert!((got - want).abs() < 1e-3, "{first:?}"); // notes 003 §5.2, +β at P
    }
    for s in samples {
        for r in s["qd_deg_s"].as_array().unwrap() {
            assert!(f(r).abs() < 1.0, "{s}");
        }
    }
}

/// The samples of `reach move --json` are a motion file for `reach drive`.
#[test]
fn move_json_feeds_drive() {
    let run = reach(&["move", "planar3", "--from", "10,-20,-30", "--to", "28,-20,-30", "--duration", "4", "--json"]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_move_planar3.json");
    // `reach drive` rejects unknown top-level fields (drive.rs: deny_unknown_fields on the
    // file), so the samples array is passed on as it is, under "samples".
    let samples = serde_json::json!({ "samples": json(&run)["samples"] });
    std::fs::write(&path, samples.to_string()).unwrap();
    let drive = reach(&["drive", "planar3", path.to_str().unwrap(), "--format", "json"]);
    assert_eq!(drive.code, 0, "{}", drive.stderr);
    let d: Value = serde_json::from_str(&drive.stdout).unwrap();
    assert_eq!(d["motion"], "samples", "{d}");
}

/// CSV output: a header and one row per sample; the last row is the target.
#[test]
fn csv_file() {
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("cli_move.csv");
    let mut args = SPBU6_MOVE.to_vec();
    args.extend(["--csv", path.to_str().unwrap()]);
    assert_eq!(reach(&args).code, 0);
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 102);
    assert!(lines[0].starts_with("t_s,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg,qd1_deg_s"), "{}", lines[0]);
    let last: Vec<f64> = lines[101].split(',').map(|c| c.parse().unwrap()).collect();
    assert!((last[0] - 10.0).abs() < 1e-12 && (last[1] - 90.0).abs() < 1e-9 && (last[4] - 90.0).abs() < 1e-9);
}

#[test]
fn bad_input_and_infeasible() {
    let base = ["move", "spbu6", "--from", "0,0,0,0,0,0", "--to", "90,0,0,90,0,0"];
    let with =
        |extra: &[&'static str]| -> Vec<&'static str> { base.iter().copied().chain(extra.iter().copied()).collect() };
    fails(&with(&["--duration", "0"]), 2, "duration");
    fails(&with(&["--duration", "-1"]), 2, "duration");
    fails(&with(&["--duration", "NaN"]), 2, "--duration");
    fails(&with(&["--duration", "10", "--dt", "0"]), 2, "dt");
    fails(
        &["move", "spbu6", "--from", "0,0,0", "--to", "90,0,0,90,0,0", "--duration", "1"],
        2,
        "--from: robot `spbu6` has 6 joints, got 3",
    );
    fails(
        &[
            "move",
            "spbu6",
            "--from-xyz",
            "30,0,0",
            "--from-rpy",
            "0,0,0",
            "--to-xyz",
            "0,3,5",
            "--to-rpy",
            "-90,0,0",
            "--duration",
            "1",
        ],
        2,
        "start pose",
    );
    fails(&with(&["--speed", "1"]), 2, "--speed");
    // A target outside the limits: the report is printed, exit 3, the joint named.
    let run = reach(&["move", "spbu6", "--from", "0,0,0,0,0,0", "--to", "0,0,0,120,0,0", "--duration", "2"]);
    assert_eq!(run.code, 3);
    assert!(run.stdout.contains("NOT feasible"), "{}", run.stdout);
    assert!(run.stderr.contains("joint 4 (q4) position outside -90.000 .. 90.000 deg"), "{}", run.stderr);
}

/// Puma 560 (link masses in its robot file): the mechanical energy of a rest-to-rest move is
/// reported, and it is at least the potential energy gained, `∫|P| dt ≥ |∫P dt| = |ΔV|`.
#[test]
fn puma560_move_reports_mechanical_energy() {
    let args = ["move", "puma560", "--from", "0,0,0,0,0,0", "--to", "20,-40,30,0,10,0", "--duration", "2"];
    let run = reach(&[&args[..], &["--json"]].concat());
    assert_eq!(run.code, 0, "{}", run.stderr);
    let v = json(&run);
    let energy = f(&v["effort"]["energy_j"]);
    assert!(v["effort"]["energy_note"].is_null());
    let puma = reach::model::presets::get("puma560").unwrap();
    let rad = |d: [f64; 6]| d.map(f64::to_radians);
    let dv = reach::effort::dynamics::potential_energy(&puma, &rad([20.0, -40.0, 30.0, 0.0, 10.0, 0.0])).unwrap()
        - reach::effort::dynamics::potential_energy(&puma, &[0.0; 6]).unwrap();
    assert!(dv.abs() > 5.0 && energy >= dv.abs(), "E = {energy} J, ΔV = {dv} J");
    // The same motion's samples through the library give the same number.
    let samples = v["samples"].as_array().unwrap();
    let times: Vec<f64> = samples.iter().map(|s| f(&s["t_s"])).collect();
    let qs: Vec<Vec<f64>> = samples.iter().map(|s| q(s).iter().map(|d| d.to_radians()).collect()).collect();
    let qds: Vec<Vec<f64>> =
        samples.iter().map(|s| s["qd_deg_s"].as_array().unwrap().iter().map(|d| f(d).to_radians()).collect()).collect();
    let lib = reach::effort::dynamics::trajectory_energy_with_rates(&puma, &times, &qs, &qds).unwrap();
    assert!((lib - energy).abs() < 1e-6 * energy, "{lib} vs {energy}");
    let text = reach(&args);
    assert!(text.stdout.contains("energy: ") && text.stdout.contains(" J"), "{}", text.stdout);
}

/// A long tool-space motion (1889 samples, over the progress-bar threshold of 1000) run with
/// stdout and stderr piped: no progress bar, nothing on stderr, in `reach move` and in
/// `reach plan`, in text and JSON mode.
#[test]
fn long_tool_motions_show_no_progress_bar_when_not_on_a_terminal() {
    let weld = [
        "move",
        "welder6r",
        "--from-xyz",
        "0.050,0.740,0.070",
        "--from-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--to-xyz",
        "0.500,0.200,0.700",
        "--to-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--space",
        "tool",
        "--speed",
        "0.001",
        "--dt",
        "0.5",
    ];
    let run = reach(&[weld.as_slice(), &["--json"]].concat());
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert_eq!(json(&run)["samples"].as_array().unwrap().len(), 1889);
    assert!(run.stderr.is_empty(), "no progress bar when not on a terminal: {}", run.stderr);
    let run = reach(&weld);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stdout.contains("feasible"), "{}", run.stdout);
    assert!(run.stderr.is_empty(), "no progress bar when not on a terminal: {}", run.stderr);
    // The same motion from a task file.
    let dir = std::env::temp_dir().join(format!("reach-cli-move-{}-progress", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let task = dir.join("weld.toml");
    let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/seed003_welding.toml"))
        .unwrap()
        .replace("dt = 10.0", "dt = 0.5");
    assert!(text.contains("dt = 0.5"));
    std::fs::write(&task, text).unwrap();
    for extra in [&[][..], &["--json"]] {
        let run = reach(&[&["plan", task.to_str().unwrap()], extra].concat());
        assert_eq!(run.code, 0, "{}", run.stderr);
        assert!(run.stderr.is_empty(), "no progress bar when not on a terminal: {}", run.stderr);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Regression: UR5's joint 1 (limits ±360°) from 170° to −170° turns the literal 340° in a
/// joint-space move, and J1 used to report the wrapped 20° (0.116) next to J2 = 1.978. With the
/// one joint-difference rule (literal for bounded joints) J1 = J2 for this monotone move.
#[test]
fn move_crossing_180_reports_j1_equal_to_j2() {
    let v = common::json(&[
        "move",
        "ur5",
        "--from",
        "170,-90,90,0,90,0",
        "--to",
        "-170,-90,90,0,90,0",
        "--duration",
        "4",
        "--json",
    ]);
    let (j1, j2) = (f(&v["effort"]["j1"]), f(&v["effort"]["j2"]));
    let w1 = f(&v["effort"]["weights"][0]);
    assert!((j1 - w1 * 340f64.to_radians()).abs() < 1e-9, "J1 = {j1}");
    assert!((j1 - j2).abs() < 1e-9, "J1 = {j1}, J2 = {j2}");
    let samples = v["samples"].as_array().unwrap();
    assert!((q(&samples[samples.len() - 1])[0] + 170.0).abs() < 1e-9);
}

/// `reach move --json` (joint and tool space) and `reach plan --json` are the library's
/// reports for the same jobs, and match their schemas.
#[test]
fn move_and_plan_json_are_the_library_reports() {
    use reach::jobs::motion::{End, MoveRequest, Space};
    use reach::jobs::{Job, Joints, PlanRequest, Pose, Request, RobotInput};
    let joint = MoveRequest {
        duration_s: Some(2.0),
        ..MoveRequest::joints(
            Joints::Deg(vec![0.0, -90.0, 90.0, 0.0, 90.0, 0.0]),
            Joints::Deg(vec![30.0, -60.0, 60.0, 0.0, 90.0, 0.0]),
        )
    };
    let job = Job { robot: RobotInput::Preset("ur5".into()), request: Request::Move(joint) };
    crate::common::assert_report(
        &["move", "ur5", "--from", "0,-90,90,0,90,0", "--to", "30,-60,60,0,90,0", "--duration", "2", "--json"],
        &job,
        "move.report",
    );
    let weld = |x: f64, y: f64, z: f64| Pose::xyz_rpy_deg([x, y, z], [0.0, -41.86854343693031, -50.19442890773481]);
    let tool = MoveRequest {
        from: End::Pose(weld(0.05, 0.74, 0.07)),
        to: End::Pose(weld(0.5, 0.2, 0.7)),
        space: Space::Tool,
        speed_m_s: Some(0.001),
        dt_s: Some(10.0),
        ..MoveRequest::joints(Joints::Deg(Vec::new()), Joints::Deg(Vec::new()))
    };
    let job = Job { robot: RobotInput::Preset("welder6r".into()), request: Request::Move(tool) };
    let v = crate::common::assert_report(
        &[
            "move",
            "welder6r",
            "--from-xyz",
            "0.05,0.74,0.07",
            "--from-rpy",
            "0,-41.86854343693031,-50.19442890773481",
            "--to-xyz",
            "0.5,0.2,0.7",
            "--to-rpy",
            "0,-41.86854343693031,-50.19442890773481",
            "--space",
            "tool",
            "--speed",
            "0.001",
            "--dt",
            "10",
            "--json",
        ],
        &job,
        "move.report",
    );
    assert_eq!(v["space"], "tool");
    assert_eq!(v["intervals"][0]["decision"], "default");
    let path = "examples/seed003_welding.toml";
    let task =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/seed003_welding.toml")).unwrap();
    let job =
        Job { robot: RobotInput::Preset("welder6r".into()), request: Request::Plan(PlanRequest { task, scene: None }) };
    let v = crate::common::assert_report(&["plan", path, "--json"], &job, "plan.report");
    assert_eq!(v["motions"][0]["name"], "weld P -> M");
}

/// Joint vectors and poses are typed as in `reach ik`: `--rad` for radians, a pose by
/// `--…-xyz` with `--…-rpy` or `--…-quat`, or `--…-matrix`; all give the same motion.
#[test]
fn move_takes_radians_and_every_pose_form() {
    let run = |args: &[&str]| -> Value {
        let all = [&["move", "ur5", "--duration", "2", "--dt", "0.5", "--json"][..], args].concat();
        let r = reach(&all);
        assert_eq!(r.code, 0, "{all:?}: {}", r.stderr);
        json(&r)
    };
    let degrees = run(&["--from", "0,-90,90,0,90,0", "--to", "45,-60,60,0,90,0"]);
    let radians = run(&[
        "--rad",
        "--from",
        "0 -1.5707963267948966 1.5707963267948966 0 1.5707963267948966 0",
        "--to",
        "0.7853981633974483,-1.0471975511965976,1.0471975511965976,0,1.5707963267948966,0",
    ]);
    for (a, b) in degrees["samples"].as_array().unwrap().iter().zip(radians["samples"].as_array().unwrap()) {
        for (x, y) in q(a).iter().zip(q(b)) {
            assert!((x - y).abs() < 1e-9, "{a} vs {b}");
        }
    }
    // Tool-space ends: rpy (180, 0, 0) is the quaternion (0, 1, 0, 0) and the matrix diag(1, −1, −1).
    let tool = ["--space", "tool", "--from-xyz", "0.4,-0.2,0.3"];
    let rpy = run(&[&tool[..], &["--from-rpy", "180,0,0", "--to-xyz", "0.4,0.2,0.3", "--to-rpy", "180,0,0"]].concat());
    let quat =
        run(&[&tool[..], &["--from-quat", "0,1,0,0", "--to-matrix", "1,0,0,0.4,0,-1,0,0.2,0,0,-1,0.3,0,0,0,1"]]
            .concat());
    let (a, b) = (rpy["samples"].as_array().unwrap(), quat["samples"].as_array().unwrap());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        for (u, v) in nums(&x["xyz_m"]).iter().zip(nums(&y["xyz_m"])) {
            assert!((u - v).abs() < 1e-9, "{x} vs {y}");
        }
    }
    // Errors name the flag typed.
    fails(
        &[
            "move",
            "ur5",
            "--space",
            "tool",
            "--from-xyz",
            "0.4,-0.2,0.3",
            "--from-rpy",
            "180,0,0",
            "--to-xyz",
            "0.4,0.2,0.3",
            "--to-quat",
            "0,0,0,0",
        ],
        2,
        "--to-quat",
    );
    fails(&["move", "ur5", "--from", "0,-90,x,0,90,0", "--to", "0,0,0,0,0,0"], 2, "--from joint 3");
}

/// `--choice INTERVAL=CONFIGURATION`: the operator's configuration of a tool-space interval
/// (a label of the report's `alternatives`), realised with decision `operator`; a malformed
/// or infeasible choice exits 2 with one line naming it.
#[test]
fn choice_realises_the_named_configuration() {
    let base = [
        "move",
        "welder6r",
        "--from-xyz",
        "0.05,0.74,0.07",
        "--from-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--to-xyz",
        "0.1,0.68,0.14",
        "--to-rpy",
        "0,-41.86854343693031,-50.19442890773481",
        "--space",
        "tool",
        "--duration",
        "10",
        "--json",
    ];
    let auto = json(&reach(&base));
    let alternatives = auto["intervals"][0]["alternatives"].as_array().unwrap();
    assert_eq!(alternatives.len(), 2, "{auto}");
    assert_eq!(auto["intervals"][0]["decision"], "default");
    let other = alternatives[1].as_str().unwrap();
    let choice = format!("1={other}");
    let chosen = json(&reach(&[&base[..], &["--choice", &choice]].concat()));
    assert_eq!(chosen["intervals"][0]["decision"], "operator", "{chosen}");
    assert_eq!(chosen["intervals"][0]["configuration"], other);
    assert_ne!(q(&chosen["samples"][0]), q(&auto["samples"][0]), "another branch");
    fails(&[&base[..], &["--choice", "one"]].concat(), 2, "--choice `one`");
    fails(&[&base[..], &["--choice", "2=x"]].concat(), 2, "interval 2 does not exist");
}
