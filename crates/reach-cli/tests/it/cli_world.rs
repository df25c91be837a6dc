//! End-to-end tests of `reach check`, `reach avoid` and `reach cspace` (seeds 000 and 004).

use crate::common;

use crate::common::{fails, json, ok, reach};

#[test]
fn cspace_reference_counts() {
    // Notes 004 §5.4: 1041 (free), 635 (ceiling z = 1200, closed), 769 (quadrant z ≥ 1200, x ≥ 800).
    for (scene, allowed) in [
        ("examples/seed004_free.toml", 1041),
        ("examples/seed004_ceiling.toml", 635),
        ("examples/seed004_two_planes.toml", 769),
    ] {
        let v = json(&["cspace", "varan4", scene, "--fix", "q1=0", "--json"]);
        assert_eq!(v["nodes"], 2601, "{scene}");
        assert_eq!(v["allowed"], allowed, "{scene}");
        let sum: u64 = ["allowed", "outside_limits", "outside_zone", "self_collision", "obstacle_collision"]
            .iter()
            .map(|k| v[k].as_u64().unwrap())
            .sum();
        assert_eq!(sum, 2601);
        assert_eq!(v["sections"].as_array().unwrap().len(), 9);
    }
    let v = json(&["cspace", "varan4", "examples/seed004_ceiling.toml", "--fix", "q1=0", "--json"]);
    assert_eq!(v["sections"][0]["allowed"], 120);
}

#[test]
fn check_touching_node() {
    // (q1, q2, q3, q4) = (0, 0, 90, 0): O4 = (900, 1200) mm touches the ceiling (closed set).
    let v = common::reported(&["check", "varan4", "examples/seed004_ceiling.toml", "0", "0", "90", "0", "--json"], 3);
    assert_eq!(v["verdict"]["verdict"], "obstacle");
    assert!(v["min_obstacle_clearance_m"].as_f64().unwrap().abs() < 1e-9);
    // (0, 30, 0, 0): O4 = (1818.653, 1050) mm, 150 mm below the ceiling.
    let v = json(&["check", "varan4", "examples/seed004_ceiling.toml", "0", "30", "0", "-0", "--json"]);
    assert_eq!(v["verdict"]["verdict"], "free");
    assert!((v["min_obstacle_clearance_m"].as_f64().unwrap() - 0.15).abs() < 1e-9);
}

#[test]
fn avoid_seed000_scenario() {
    // Notes 000 §6.3: start (α, β, γ) = (150, 140, 60) → q = (60, −40, −30) deg.
    let v =
        json(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.0,0.7", "--json"]);
    assert_eq!(v["blocked"], true);
    let w = v["waypoints_m"].as_array().unwrap();
    assert_eq!(w.len(), 3);
    assert!((w[0][0].as_f64().unwrap() - 1.911599).abs() < 1e-6);
    assert!((w[1][1].as_f64().unwrap() - 0.610758).abs() < 1e-6);
    assert_eq!(v["configurations_deg"].as_array().unwrap().len(), 3);
    let c = v["min_clearance_m"].as_f64().unwrap();
    assert!((0.075..1.0 / 7.0).contains(&c), "{c}");
    // No obstacle: direct.
    let v = json(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--json"]);
    assert_eq!(v["blocked"], false);
    assert_eq!(v["outcome"]["outcome"], "direct");
}

#[test]
fn avoid_failures_and_bad_input() {
    let run = reach(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "3.2,0", "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(run.stdout.contains("target_unreachable"));
    assert!(run.stderr.starts_with("error: target outside the workspace"));
    let run = reach(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.35,0.3"]);
    assert_eq!(run.code, 3);
    assert!(run.stderr.contains("within the detour radius"), "{}", run.stderr);
    fails(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "nan,0.2"], 2, &["--to"]);
    fails(&["check", "varan4", "examples/no_such_scene.toml", "0", "0", "0", "0"], 2, &["no_such_scene"]);
}

#[test]
fn cspace_fit_prints_primitives_and_confusion() {
    // Seed 004: the R-function region fitted to the 15° grid of the ceiling scene (635 allowed).
    let v = json(&["cspace", "varan4", "examples/seed004_ceiling.toml", "--fix", "q1=0", "--fit", "--json"]);
    let fit = &v["fit"];
    assert_eq!(fit["joints"], serde_json::json!([2, 3, 4]));
    let names: Vec<&str> = fit["primitives"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
    assert_eq!(&names[..4], ["Ω1", "Ω2", "Ω3", "Ω4"]);
    assert!(names.contains(&"Ω5"), "{names:?}");
    assert_eq!(fit["primitives"][1]["kind"], "half-space");
    assert!(fit["primitives"][1]["coefficients"]["HalfSpace"]["d"].is_array());
    let c = &fit["confusion"];
    let n = |k: &str| c[k].as_u64().unwrap();
    assert_eq!(n("true_allowed") + n("false_allowed") + n("false_forbidden") + n("true_forbidden"), 2601);
    assert_eq!(n("true_allowed") + n("false_forbidden"), 635);
    assert!(c["rate"].as_f64().unwrap() < 0.08);
    // Without --fit there is no "fit" key.
    let v = json(&["cspace", "varan4", "examples/seed004_free.toml", "--fix", "q1=0", "--json"]);
    assert!(v.get("fit").is_none());
    // Text: the primitives table and the confusion block.
    let text = ok(&["cspace", "varan4", "examples/seed004_free.toml", "--fix", "q1=0", "--fit"]);
    assert!(text.contains("elliptic cylinder (outside)") && text.contains("false allowed"), "{text}");
    // Four swept joints: bad input, one line on stderr.
    fails(
        &["cspace", "varan4", "examples/seed004_free.toml", "--step", "60", "--fit"],
        2,
        &["exactly three swept joints"],
    );
}

#[test]
fn cspace_fit_without_allowed_nodes_is_infeasible() {
    // The task zone moved beyond reach: a valid grid with nothing to fit, exit 3 (infeasible).
    let free = std::fs::read_to_string(format!("{}/examples/seed004_free.toml", common::REPO_ROOT)).unwrap();
    let far = free.replace("point = [500, 0, 0]", "point = [50000, 0, 0]");
    assert_ne!(far, free);
    let file = common::temp_file("seed004_far.toml", &far);
    fails(
        &["cspace", "varan4", file.to_str().unwrap(), "--fix", "q1=0", "--step", "30", "--fit"],
        3,
        &["--fit", "no allowed node"],
    );
}

/// The text of a file of the repository.
fn repo_text(path: &str) -> String {
    std::fs::read_to_string(format!("{}/{path}", common::REPO_ROOT)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn check_avoid_and_cspace_json_are_the_library_reports_and_match_their_schemas() {
    use reach::jobs::{AvoidRequest, CheckRequest, CspaceRequest, Job, Joints, Request, RobotInput};
    let avoid = Job {
        robot: RobotInput::Preset("planar3".into()),
        request: Request::Avoid(AvoidRequest {
            start: Some(Joints::Deg(vec![60.0, -40.0, -30.0])),
            from_xy_m: None,
            to_xy_m: [2.4, 0.2],
            obstacles_xy_m: vec![[2.0, 0.7]],
            step_deg: 0.01,
            literal_test: false,
            printed_waypoints: false,
            choose: None,
            sense: None,
        }),
    };
    let v = crate::common::assert_report(
        &["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.0,0.7", "--json"],
        &avoid,
        "avoid.report",
    );
    assert_eq!(v["outcome"]["outcome"], "detour");
    let cspace = Job {
        robot: RobotInput::Preset("varan4".into()),
        request: Request::Cspace(CspaceRequest {
            scene: repo_text("examples/seed004_ceiling.toml"),
            step_deg: 15.0,
            fix: [("q1".to_string(), 0.0)].into(),
            fit: false,
            max_nodes: None,
        }),
    };
    let v = crate::common::assert_report(
        &["cspace", "varan4", "examples/seed004_ceiling.toml", "--step", "15", "--fix", "q1=0", "--json"],
        &cspace,
        "cspace.report",
    );
    assert_eq!(v["allowed"], 635);
    let check = Job {
        robot: RobotInput::Preset("varan4".into()),
        request: Request::Check(CheckRequest {
            scene: repo_text("examples/seed004_two_planes.toml"),
            q: Joints::Deg(vec![0.0, 60.0, -30.0, -30.0]),
            to: None,
            duration_s: None,
            samples: None,
        }),
    };
    let v = crate::common::assert_report(
        &["check", "varan4", "examples/seed004_two_planes.toml", "0", "60", "-30", "-30", "--json"],
        &check,
        "check.report",
    );
    assert_eq!(v["q_deg"], serde_json::json!([0.0, 60.0, -30.0, -30.0]));
}

#[test]
fn path_json_is_the_library_report_and_matches_its_schema() {
    use reach::jobs::{Job, Joints, PathRequest, Report, Request, RobotInput};
    let job = Job {
        robot: RobotInput::Preset("planar3".into()),
        request: Request::Path(PathRequest {
            scene: repo_text("examples/path_planar3_post.toml"),
            from: Joints::Deg(vec![60.0, -40.0, -30.0]),
            to: Some(Joints::Deg(vec![0.0, -30.0, -30.0])),
            to_pose: None,
            seed: 1,
            time_budget_s: 1.0,
            duration_s: Some(10.0),
            timing: None,
            max_velocity_scale: 1.0,
            max_acceleration_scale: 1.0,
            blend_tolerance: None,
        }),
    };
    let args = [
        "path",
        "planar3",
        "examples/path_planar3_post.toml",
        "--from",
        "60,-40,-30",
        "--to",
        "0,-30,-30",
        "--duration",
        "10",
        "--json",
    ];
    let mut output = json(&args);
    common::assert_valid("path.report", &output);
    let Report::Path(report) = job.run().unwrap() else { panic!("not a path report") };
    let mut expected = serde_json::to_value(&report).unwrap();
    // The planner's wall time differs from run to run; everything else is seeded.
    for v in [&mut output, &mut expected] {
        let time = v["stats"].as_object_mut().unwrap().remove("time_s").unwrap();
        assert!(time.as_f64().unwrap() >= 0.0);
    }
    assert_eq!(output, expected);
    assert_eq!(output["found"], true);
    // Every segment is proven clear, with a certified bound below the closest clearance found.
    let swept = &output["swept"];
    assert_eq!(swept["clear"], true, "{swept}");
    assert_eq!(output["collision_free"], true);
    let lb = swept["lower_bound_m"].as_f64().unwrap();
    assert!(lb > 0.0 && lb <= swept["min_clearance_m"].as_f64().unwrap(), "{swept}");
    let segments = output["waypoints_deg"].as_array().unwrap().len() - 1;
    assert!((1..=segments).contains(&(swept["segment"].as_u64().unwrap() as usize)), "{swept}");
}

#[test]
fn a_scene_that_does_not_parse_names_the_file_line_and_column() {
    let file = common::temp_file("broken_scene.toml", "[[obstacles]]\nshape = \"box\"\nsize = [1, 2\n");
    let line = fails(&["check", "planar3", file.to_str().unwrap(), "0", "0", "0"], 2, &["broken_scene.toml", "line"]);
    assert!(line.contains("column"), "{line}");
}

/// The issue's case: the chord test and sampled clearance called this move "direct"; link 3
/// sweeps over the obstacle, so the continuous check blocks it.
#[test]
fn avoid_blocks_a_link_that_sweeps_over_the_obstacle() {
    let run =
        reach(&["avoid", "planar3", "--from-xy", "2.2,0.9", "--to-xy", "0.3,2.3", "--obstacle", "1.45,1.75", "--json"]);
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["blocked"], true, "{v}");
    assert_ne!(v["outcome"]["outcome"], "direct", "{v}");
    // A clear detour reports where it comes closest, with a certified bound below the minimum.
    let v =
        json(&["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--obstacle", "2.0,0.7", "--json"]);
    let c = &v["closest"];
    let (m, lb) = (c["clearance_m"].as_f64().unwrap(), c["lower_bound_m"].as_f64().unwrap());
    assert!(lb > 0.0 && lb <= m && m == v["min_clearance_m"].as_f64().unwrap(), "{c}");
    assert!((1..=3).contains(&c["link"].as_u64().unwrap()) && (1..=3).contains(&c["leg"].as_u64().unwrap()), "{c}");
}

/// `reach check --to`: the straight joint motion between two free configurations is checked
/// continuously. Through the post: not clear, naming link 3 and the post; around it: proven
/// clear with a certified bound. The JSON is the library report.
#[test]
fn check_to_sweeps_the_joint_motion() {
    use reach::jobs::{CheckRequest, Job, Joints, Request, RobotInput};
    let scene = "examples/path_planar3_post.toml";
    let v = common::reported(&["check", "planar3", scene, "60", "-40", "-30", "--to", "0,-30,-30", "--json"], 3);
    let m = &v["motion"];
    assert_eq!(m["clear"], false, "{m}");
    assert_eq!(m["pair"]["kind"], "obstacle");
    assert_eq!(m["pair"]["link"], 3);
    assert!(m["pair_text"].as_str().unwrap().contains("post"), "{m}");
    let job = Job {
        robot: RobotInput::Preset("planar3".into()),
        request: Request::Check(CheckRequest {
            scene: repo_text(scene),
            q: Joints::Deg(vec![60.0, -40.0, -30.0]),
            to: Some(Joints::Deg(vec![99.381, -51.972, -38.454])),
            duration_s: None,
            samples: None,
        }),
    };
    let v = crate::common::assert_report(
        &["check", "planar3", scene, "60", "-40", "-30", "--to", "99.381,-51.972,-38.454", "--json"],
        &job,
        "check.report",
    );
    let m = &v["motion"];
    assert_eq!(m["clear"], true, "{m}");
    let (lb, min) = (m["lower_bound_m"].as_f64().unwrap(), m["min_clearance_m"].as_f64().unwrap());
    assert!(lb > 0.0 && lb <= min, "{m}");
    fails(&["check", "planar3", scene, "60", "-40", "-30", "--to", "0,x,-30"], 2, &["--to joint 2"]);
}

/// `reach move --scene`: swinging through the post is infeasible (exit 3, one line naming link
/// 3, the post and the time) and its `--csv` is not written; around the post the move is
/// proven clear and the CSV is written. `reach check --motion` checks the sampled motion of
/// `reach move --json` the same way, and `reach plan --scene` every motion of a task file.
#[test]
fn moves_and_sampled_motions_are_checked_against_a_scene() {
    let dir = common::scratch("scene-move");
    let scene = "examples/path_planar3_post.toml";
    let csv = dir.join("through.csv");
    let through = ["move", "planar3", "--from", "60,-40,-30", "--to", "0,-30,-30", "--duration", "2"];
    let run = reach(&[&through[..], &["--scene", scene, "--csv", csv.to_str().unwrap()]].concat());
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert_eq!(run.stderr.lines().count(), 1, "{}", run.stderr);
    assert!(run.stderr.contains("not proven clear of the scene: link 3 (`A`) and `post` at t = "), "{}", run.stderr);
    assert!(!csv.exists(), "an infeasible motion's samples are not written");
    assert!(run.stdout.contains("swept check: NOT proven clear: link 3 (`A`) and `post`"), "{}", run.stdout);
    let around = dir.join("around.csv");
    let text = ok(&[
        "move",
        "planar3",
        "--from",
        "60,-40,-30",
        "--to",
        "99.381,-51.972,-38.454",
        "--duration",
        "2",
        "--scene",
        scene,
        "--csv",
        around.to_str().unwrap(),
    ]);
    assert!(text.contains("swept check: proven clear: clearance ≥ "), "{text}");
    assert!(around.exists());
    // The sampled motion without the scene, checked by `reach check --motion`.
    let motion = dir.join("through.json");
    std::fs::write(&motion, ok(&[&through[..], &["--json"]].concat())).unwrap();
    let v = common::reported(
        &["check", "planar3", scene, "60", "-40", "-30", "--motion", motion.to_str().unwrap(), "--json"],
        3,
    );
    common::assert_valid("check.report", &v);
    let s = &v["samples"];
    assert_eq!(s["clear"], false, "{s}");
    assert_eq!(s["pair"]["link"], 3);
    assert!(s["segment"].as_u64().unwrap() > 1, "{s}");
    fails(&["check", "planar3", scene, "60", "-40", "-30", "--motion", "/nonexistent.json"], 2, &["/nonexistent.json"]);
    let bad = common::temp_file("motion_outside.json", r#"{"samples": [{"t_s": 0, "q_deg": [0, 0, 400]}]}"#);
    fails(
        &["check", "planar3", scene, "0", "0", "0", "--motion", bad.to_str().unwrap()],
        2,
        &["--motion: sample 0", "joint 3"],
    );
    // A task file with the scene.
    let task = common::temp_file(
        "swing_task.toml",
        "robot = \"planar3\"\n[[motion]]\nname = \"swing\"\nfrom = [60, -40, -30]\nto = [0, -30, -30]\nduration = 2\n",
    );
    let run = reach(&["plan", task.to_str().unwrap(), "--scene", scene, "--json"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let v: serde_json::Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["motions"][0]["swept"]["clear"], false);
    let broken = common::temp_file("broken_post.toml", "[[obstacles]]\nshape = 1\n");
    fails(&[&through[..], &["--scene", broken.to_str().unwrap()]].concat(), 2, &["broken_post.toml"]);
}

/// A scene with a moving obstacle (a ball closing on `planar3`'s tool at 0.2 m/s, contact at
/// 0.4 m / 0.2 m/s = 2 s): `check --to --duration` checks the motion in time (clear for 1.9 s,
/// stopped at t = 2 s for 3 s, the report valid against its schema); without `--duration`,
/// and in `path`, `cspace` and `approach` (untimed), the obstacle is refused by name.
#[test]
fn moving_obstacles_are_checked_in_time_or_refused() {
    let scene = common::temp_file(
        "moving_ball.toml",
        "length_unit = \"mm\"\nangle_unit = \"deg\"\n\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\n\
         center = [3500, 0, 0]\nradius = 100\nvelocity = [-200, 0, 0]\n",
    );
    let path = scene.to_str().unwrap();
    let check = |duration: &str, code: i32| {
        let v = common::reported(
            &["check", "planar3", path, "0", "0", "0", "--to", "0,0,0", "--duration", duration, "--json"],
            code,
        );
        common::assert_valid("check.report", &v);
        v["motion"].clone()
    };
    let clear = check("1.9", 0);
    assert_eq!(clear["clear"], true, "{clear}");
    assert!((clear["min_clearance_m"].as_f64().unwrap() - 0.02).abs() < 1e-9, "{clear}");
    let hit = check("3", 3);
    assert_eq!(hit["clear"], false, "{hit}");
    assert!((hit["t_s"].as_f64().unwrap() - 2.0).abs() < 1e-5, "{hit}");
    assert_eq!(hit["pair_text"], "link 3 (`A`) and `ball`");
    let text = reach(&["check", "planar3", path, "0", "0", "0", "--to", "0,0,0", "--duration", "3"]).stdout;
    assert!(text.contains("NOT proven clear: link 3 (`A`) and `ball` at") && text.contains("t = 2.0000 s"), "{text}");

    fails(&["check", "planar3", path, "0", "0", "0", "--to", "0,0,0"], 2, &["--duration", "`ball` moves"]);
    fails(&["check", "planar3", path, "0", "0", "0", "--to", "0,0,0", "--duration", "0"], 2, &["--duration"]);
    let run = reach(&["path", "planar3", path, "--from", "10,-10,-10", "--to", "20,-10,-10"]);
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("`ball` moves") && run.stderr.contains("the planner"), "{}", run.stderr);
    let run = reach(&["cspace", "planar3", path, "--step", "30"]);
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("`ball` moves"), "{}", run.stderr);
    let run = reach(&["approach", "planar3", path, "--from", "10,-10,-10", "--to", "20,-10,-10"]);
    assert_ne!(run.code, 0);
    assert!(run.stderr.contains("`ball` moves"), "{}", run.stderr);
    // A configuration alone is checked at time 0: the ball 0.4 m from the tool.
    let v = json(&["check", "planar3", path, "0", "0", "0", "--json"]);
    assert!((v["min_obstacle_clearance_m"].as_f64().unwrap() - 0.4).abs() < 1e-9, "{v}");
}

/// The UR5 preset is checked as its body: upright, the ball of `examples/ur5_ball.toml`
/// (2 cm, 13.6 cm beside the upper arm's DH segment) is inside the real upper arm and named;
/// the exempt housing pairs are listed as exempt, not as collisions.
#[test]
fn check_ur5_uses_the_presets_body() {
    let v =
        common::reported(&["check", "ur5", "examples/ur5_ball.toml", "0", "-90", "0", "-90", "0", "0", "--json"], 3);
    assert_eq!(v["verdict"]["verdict"], "obstacle", "{v}");
    assert!(v["verdict_text"].as_str().unwrap().contains("link 3 (`upper_arm_link`) with `ball`"), "{v}");
    assert!(v["min_obstacle_clearance_m"].as_f64().unwrap() < -0.09);
    let pairs = v["self_pairs"].as_array().unwrap();
    let exempt: Vec<(&str, &str)> = pairs
        .iter()
        .filter(|p| p["exempt"] == true)
        .map(|p| (p["name_a"].as_str().unwrap(), p["name_b"].as_str().unwrap()))
        .collect();
    assert_eq!(
        exempt,
        [("base_link", "upper_arm_link"), ("forearm_link", "wrist_2_link"), ("wrist_1_link", "wrist_3_link")]
    );
    assert!(v["min_self_clearance_m"].as_f64().unwrap() > 0.0);
}
