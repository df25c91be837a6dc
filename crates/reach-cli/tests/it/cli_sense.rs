//! End-to-end tests of `reach sense` and `reach avoid --sensor` (seed 000 §II, §4.5 step 6).

use crate::common::{assert_report, fails, json, num, nums, reach};

/// Two sensors below seed 000's obstacle H = (2.0, 0.7): from (0.5, −0.5) the line of sight is
/// at 38.66° and 1.920937 m (beam 5° off it), from (3, −0.5) at 129.81° and 1.56205 m.
const S1: &str = "0.5,-0.5,43.66,1.920937";
const S2: &str = "3,-0.5,129.81,1.56205";

#[test]
fn sense_json_is_the_library_report_and_finds_the_seed_obstacle() {
    use reach::jobs::world::{SenseRequest, SensorReading};
    use reach::jobs::{Job, Request, RobotInput};
    let reading = |xy_m: [f64; 2], dir_deg: f64, range_m: f64| SensorReading {
        xy_m,
        dir_deg,
        range_m,
        cone_deg: 30.0,
        sigma_m: None,
    };
    let job = Job {
        robot: RobotInput::Preset("planar3".into()),
        request: Request::Sense(SenseRequest {
            sensors: vec![reading([0.5, -0.5], 43.66, 1.920937), reading([3.0, -0.5], 129.81, 1.56205)],
            sigma_m: 0.02,
        }),
    };
    let v = assert_report(
        &["sense", "planar3", "--sensor", S1, "--sensor", S2, "--sigma", "0.02", "--json"],
        &job,
        "sense.report",
    );
    let p = nums(&v["obstacle_m"]);
    assert!((p[0] - 2.0).abs() < 1e-5 && (p[1] - 0.7).abs() < 1e-5, "{p:?}");
    assert_eq!(v["ambiguous"], false);
    // Lines of sight u1 = (1.5, 1.2)/1.920937, u2 = (−1, 1.2)/1.56205 are 91.1° apart: the
    // smallest eigenvalue of Σuuᵀ is 1 − |u1·u2| = 0.980007, so the radius is
    // k·σ/√0.980007 with k = √(−2 ln 0.0027) = 3.439332: 0.069485 m.
    assert!((num(&v["uncertainty_m"]) - 0.069485).abs() < 2e-6, "{}", v["uncertainty_m"]);
    assert!(num(&v["residual_m"]) < 1e-5);
}

#[test]
fn sense_reports_a_symmetric_pair_as_ambiguous() {
    let v = json(&["sense", "planar3", "--sensor", "0,0,0,0.538516,60", "--sensor", "1,0,180,0.538516,60", "--json"]);
    assert_eq!(v["ambiguous"], true);
    assert_eq!(v["ambiguity"], "alternatives");
    let (p, q) = (nums(&v["obstacle_m"]), nums(&v["alternatives_m"][0]));
    assert!((p[0] - 0.5).abs() < 1e-5 && (q[0] - 0.5).abs() < 1e-5 && (p[1] + q[1]).abs() < 1e-9 && p[1].abs() > 0.19);
    // Narrow beams tilted up keep only (0.5, 0.2).
    let v =
        json(&["sense", "planar3", "--sensor", "0,0,21.8,0.538516,10", "--sensor", "1,0,158.2,0.538516,10", "--json"]);
    assert_eq!(v["ambiguous"], false);
    assert!((num(&v["obstacle_m"][1]) - 0.2).abs() < 1e-5);
}

#[test]
fn bad_readings_name_the_sensor_and_the_field() {
    fails(&["sense", "planar3", "--sensor", S1], 2, &["--sensor", "at least 2 sensors, got 1"]);
    fails(
        &["sense", "planar3", "--sensor", S1, "--sensor", "3,-0.5,129.81,-1"],
        2,
        &["--sensor 2 (RANGE): must be > 0 m, got -1"],
    );
    fails(&["sense", "planar3", "--sensor", S1, "--sensor", "3,-0.5,nan,1"], 2, &["--sensor 2 value 3", "finite"]);
    fails(&["sense", "planar3", "--sensor", S1, "--sensor", S2, "--sigma", "0"], 2, &["--sigma: must be > 0 m, got 0"]);
    fails(
        &["sense", "planar3", "--sensor", S1, "--sensor", "3,-0.5,129.81,1.56,200"],
        2,
        &["--sensor 2 (CONE_DEG)", "(0, 180)"],
    );
    fails(
        &["sense", "planar3", "--sensor", S1, "--sensor", "3,-0.5,129.81"],
        2,
        &["--sensor 2: expected 4 or 5 numbers"],
    );
    fails(&["sense", "planar3", "--sensor", S1, "--sensor", "0.5,-0.5,60,1"], 2, &["sensors 1 and 2", "same position"]);
}

#[test]
fn avoid_detours_around_the_sensed_obstacle() {
    let v = json(&[
        "avoid",
        "planar3",
        "--from",
        "60,-40,-30",
        "--to-xy",
        "2.4,0.2",
        "--sensor",
        S1,
        "--sensor",
        S2,
        "--json",
    ]);
    assert_eq!(v["outcome"]["outcome"], "detour");
    let radius = num(&v["sensed"]["uncertainty_m"]);
    assert!((radius - 0.069485 / 2.0).abs() < 2e-6, "{radius}");
    assert!(num(&v["closest"]["lower_bound_m"]) > 0.0);
    // The waypoints lie on the circle of L/7 + radius about the sensed obstacle.
    let h = nums(&v["sensed"]["obstacle_m"]);
    for w in v["waypoints_m"].as_array().unwrap()[..2].iter().map(nums) {
        assert!(((w[0] - h[0]).hypot(w[1] - h[1]) - (1.0 / 7.0 + radius)).abs() < 1e-9, "{w:?}");
    }
    fails(
        &[
            "avoid",
            "planar3",
            "--from",
            "60,-40,-30",
            "--to-xy",
            "2.4,0.2",
            "--sensor",
            "0,0,0,0.538516,60",
            "--sensor",
            "1,0,180,0.538516,60",
        ],
        2,
        &["--sensor: the readings do not locate the obstacle unambiguously"],
    );
    // clap refuses the combination (its usage message, exit status 2).
    let run = reach(&[
        "avoid",
        "planar3",
        "--from",
        "60,-40,-30",
        "--to-xy",
        "2.4,0.2",
        "--sensor",
        S1,
        "--obstacle",
        "2,0.7",
    ]);
    assert_eq!(run.code, 2);
    assert!(run.stderr.contains("cannot be used with") && run.stdout.is_empty(), "{}", run.stderr);
}

/// Seed 000's future work: `reach ik planar4 --scan` chooses the minimum-change configuration of
/// the four-link arm (the library's `planar_scan` report).
#[test]
fn ik_scan_of_planar4_is_the_minimum_change_choice() {
    use reach::jobs::{Job, Joints, PlanarScanRequest, Request, RobotInput};
    let job = Job {
        robot: RobotInput::Preset("planar4".into()),
        request: Request::PlanarScan(PlanarScanRequest {
            xyz_m: [2.4, 0.2, 0.0],
            step_deg: 1.0,
            from: Some(Joints::Deg(vec![60.0, -40.0, -30.0, -20.0])),
        }),
    };
    let v = assert_report(
        &["ik", "planar4", "--xyz", "2.4,0.2,0", "--from", "60,-40,-30,-20", "--scan", "1", "--json"],
        &job,
        "planar_scan.report",
    );
    assert_eq!(v["status"], "ok");
    assert_eq!(v["nodes"], 181 * 181);
    let q: Vec<f64> = nums(&v["q_deg"]).iter().map(|d| d.to_radians()).collect();
    let robot = reach::model::presets::get("planar4").unwrap();
    let tool = robot.fk(&q).unwrap().translation.vector;
    assert!((tool.x - 2.4).abs() < 1e-9 && (tool.y - 0.2).abs() < 1e-9);
    let s: f64 = nums(&v["q_deg"]).iter().zip([60.0, -40.0, -30.0, -20.0]).map(|(a, b)| (a - b).abs()).sum();
    assert!((num(&v["s_deg"]) - s).abs() < 1e-9);
    let text = crate::common::ok(&["ik", "planar4", "--xyz", "2.4,0.2,0", "--from", "60,-40,-30,-20", "--scan", "1"]);
    assert!(text.contains("32761 nodes") && text.contains("chosen q [deg]"), "{text}");
    // No configuration: the report, then exit status 3 with the reason.
    let run = reach(&["ik", "planar4", "--xyz", "4.5,0,0", "--scan", "1"]);
    assert_eq!(run.code, 3);
    assert!(run.stdout.contains("target out of reach") && run.stderr.contains("out of reach"), "{}", run.stderr);
    fails(&["ik", "planar4", "--xyz", "2,0,0", "--scan", "1", "--csv", "t.csv"], 2, &["--csv", "not stored"]);
}
