//! End-to-end tests of the drawings (`--svg`, `--png`) of `reach move`, `reach plan`,
//! `reach avoid`, `reach cspace`, `reach path` and `reach tasks`, and of `reach path` itself.

use std::path::Path;

use serde_json::Value;

use crate::common::{one_error_line, reach, scratch};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Parses an SVG file as XML and returns its text.
fn svg_text(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    roxmltree::Document::parse(&text).unwrap_or_else(|e| panic!("{}: not XML: {e}", path.display()));
    text
}

/// Elements whose class attribute contains the word `class`.
fn count_class(text: &str, class: &str) -> usize {
    let doc = roxmltree::Document::parse(text).unwrap();
    doc.descendants().filter(|n| n.attribute("class").is_some_and(|c| c.split_whitespace().any(|w| w == class))).count()
}

/// Width and height from a PNG's IHDR chunk, after checking the signature.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{} has no PNG signature", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    (be(16), be(20))
}

fn svg_size(text: &str) -> (f64, f64) {
    let doc = roxmltree::Document::parse(text).unwrap();
    let root = doc.root_element();
    (root.attribute("width").unwrap().parse().unwrap(), root.attribute("height").unwrap().parse().unwrap())
}

#[test]
fn move_draws_one_row_per_joint_with_limit_bands_and_the_tool_path() {
    let dir = scratch("move");
    let (svg, png) = (dir.join("m.svg"), dir.join("m.png"));
    let run = reach(&[
        "move",
        "ur5",
        "--from",
        "0,-90,90,0,90,0",
        "--to",
        "45,-60,60,0,90,0",
        "--profile",
        "quintic",
        "--duration",
        "2",
        "--svg",
        s(&svg),
        "--png",
        s(&png),
        "--png-width",
        "400",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = svg_text(&svg);
    assert_eq!(count_class(&text, "joint-position"), 6);
    assert_eq!(count_class(&text, "joint-rate"), 6);
    // UR5: finite position limits on every joint and speed limits: one band per panel.
    assert_eq!(count_class(&text, "limit-band") - 1, 12, "12 panel bands plus the legend swatch");
    assert_eq!(count_class(&text, "tool-path"), 2);
    assert!(text.contains("ur5") && text.contains("quintic profile"));
    let (w, h) = svg_size(&text);
    assert_eq!(png_size(&png), (400, (h * 400.0 / w).round() as u32));
}

#[test]
fn plan_writes_one_drawing_per_motion_even_when_a_motion_is_infeasible() {
    let dir = scratch("plan");
    let out = dir.join("svgs");
    let run = reach(&["plan", "examples/seed001_tool_vs_joint.toml", "--svg", s(&out)]);
    assert_eq!(run.code, 3, "the tool-space motion breaks a limit: {}", run.stderr);
    for k in 1..=2 {
        let text = svg_text(&out.join(format!("motion-{k}.svg")));
        assert_eq!(count_class(&text, "joint-position"), 6);
    }
}

#[test]
fn avoid_draws_the_detour_like_the_thesis_figure() {
    let dir = scratch("avoid");
    let svg = dir.join("a.svg");
    let run = reach(&[
        "avoid",
        "planar3",
        "--from",
        "60,-40,-30",
        "--to-xy",
        "2.4,0.2",
        "--obstacle",
        "2.0,0.7",
        "--svg",
        s(&svg),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let text = svg_text(&svg);
    // Start, K2, K3, target: four arm poses; the three swept polygons of the direct move;
    // one L/7 circle around the obstacle; the waypoint labels.
    assert_eq!(count_class(&text, "arm"), 4);
    assert_eq!(count_class(&text, "sweep") - 1, 3);
    assert_eq!(count_class(&text, "circle") - 1, 1);
    for label in [">K2<", ">K3<", ">K1<", ">H1<", "K (start)"] {
        assert!(text.contains(label), "missing {label}");
    }
}

#[test]
fn cspace_sections_match_the_counts_of_the_grid() {
    let dir = scratch("cspace");
    let (svgs, pngs) = (dir.join("svg"), dir.join("png"));
    let run = reach(&[
        "cspace",
        "varan4",
        "examples/seed004_ceiling.toml",
        "--fix",
        "q1=0",
        "--json",
        "--svg",
        s(&svgs),
        "--png",
        s(&pngs),
        "--png-width",
        "460",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    assert!(run.stderr.is_empty(), "no progress bar when not on a terminal: {}", run.stderr);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    let sections = v["sections"].as_array().unwrap();
    assert_eq!(sections.len(), 9);
    for sec in sections {
        let q2 = sec["value_deg"].as_f64().unwrap().round() as i64;
        let text = svg_text(&svgs.join(format!("section-q2-{q2}.svg")));
        assert!(text.contains(&format!("section q2 = {q2} deg (q1 = 0)")));
        for (key, label) in [
            ("allowed", "allowed"),
            ("outside_zone", "tool outside zone"),
            ("obstacle_collision", "obstacle collision"),
            ("self_collision", "self-collision"),
        ] {
            let n = sec[key].as_u64().unwrap();
            assert!(text.contains(&format!(">{label} ({n})<")), "q2 = {q2}: {label} should be {n}");
        }
        assert_eq!(png_size(&pngs.join(format!("section-q2-{q2}.png"))), (460, 350));
    }
    // Notes 004 §5.4, ceiling at 1200 mm: 103 allowed nodes at q2 = 30°.
    assert_eq!(sections[2]["allowed"], 103);
}

#[test]
fn bad_drawing_paths_are_bad_input() {
    let dir = scratch("bad");
    let file = dir.join("plain-file");
    std::fs::write(&file, "x").unwrap();
    let missing = dir.join("no/such/dir/m.svg");
    for args in [
        vec!["move", "ur5", "--from", "0,0,0,0,0,0", "--to", "10,0,0,0,0,0", "--duration", "1", "--svg", s(&missing)],
        vec!["move", "ur5", "--from", "0,0,0,0,0,0", "--to", "10,0,0,0,0,0", "--duration", "1", "--png", s(&dir)],
        vec!["cspace", "varan4", "examples/seed004_free.toml", "--fix", "q1=0", "--svg", s(&file)],
        vec!["cspace", "varan4", "examples/seed004_free.toml", "--svg", s(&dir)],
        vec!["avoid", "planar3", "--from", "60,-40,-30", "--to-xy", "2.4,0.2", "--png", s(&missing)],
    ] {
        let run = reach(&args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        one_error_line(&run);
    }
    assert!(!missing.exists());
}

const POST: &str = "examples/path_planar3_post.toml";

#[test]
fn path_goes_around_an_obstacle_that_blocks_the_straight_line() {
    // The straight joint-space line from start to goal passes through the post.
    let mid = reach(&["check", "planar3", POST, "30", "-35", "-30", "--json"]);
    let mid: Value = serde_json::from_str(&mid.stdout).unwrap();
    assert_eq!(mid["verdict"]["verdict"], "obstacle", "{mid}");
    let dir = scratch("path");
    let svg = dir.join("p.svg");
    let run = reach(&[
        "path",
        "planar3",
        POST,
        "--from",
        "60,-40,-30",
        "--to",
        "0,-30,-30",
        "--duration",
        "10",
        "--json",
        "--svg",
        s(&svg),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["found"], true);
    assert_eq!(v["collision_free"], true);
    let w = v["waypoints_deg"].as_array().unwrap();
    assert!(w.len() >= 3, "a detour needs an intermediate waypoint: {w:?}");
    assert_eq!(w[0], serde_json::json!([60.0, -40.0, -30.0]));
    assert!(v["swept"]["lower_bound_m"].as_f64().unwrap() > 0.0);
    assert!((v["duration_s"].as_f64().unwrap() - 10.0).abs() < 1e-9);
    let stats = &v["stats"];
    assert!(stats["length"].as_f64().unwrap() <= stats["raw_length"].as_f64().unwrap() + 1e-12);
    let text = svg_text(&svg);
    assert_eq!(count_class(&text, "joint-position"), 3);
    assert!(count_class(&text, "obstacle") >= 3, "the post in both projections and the legend");
    assert_eq!(count_class(&text, "waypoint"), 2 * w.len() + 1);
}

#[test]
fn path_without_a_solution_exits_3_after_the_report() {
    // Goal in the post.
    let run = reach(&["path", "planar3", POST, "--from", "60,-40,-30", "--to", "30,-35,-30", "--duration", "5"]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    assert!(run.stdout.contains("NO PATH") && run.stdout.contains("goal configuration in collision"), "{}", run.stdout);
    assert_eq!(run.stderr.lines().count(), 1);
    // No time to search.
    let run = reach(&[
        "path",
        "planar3",
        POST,
        "--from",
        "60,-40,-30",
        "--to",
        "0,-30,-30",
        "--duration",
        "5",
        "--time-budget",
        "0.000001",
        "--json",
    ]);
    assert_eq!(run.code, 3, "{}", run.stderr);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    assert_eq!(v["found"], false);
    assert!(v["reason"].as_str().unwrap().contains("budget"), "{v}");
}

#[test]
fn path_bad_input_exits_2_with_one_line() {
    for args in [
        vec!["path", "planar3", POST, "--from", "60,-40", "--to", "0,-30,-30"],
        vec!["path", "planar3", POST, "--from", "60,-40,-30"],
        vec!["path", "planar3", POST, "--from", "60,-40,nan", "--to", "0,-30,-30"],
        vec!["path", "planar3", POST, "--from", "60,-40,-30", "--to-xyz", "1,2"],
        vec!["path", "planar3", "no-such-scene.toml", "--from", "60,-40,-30", "--to", "0,-30,-30"],
        vec!["path", "planar3", POST, "--from", "60,-40,-30", "--to", "0,-30,-30", "--duration", "-1"],
    ] {
        let run = reach(&args);
        assert_eq!(run.code, 2, "{args:?}: {}", run.stderr);
        one_error_line(&run);
    }
}

#[test]
fn path_between_one_configuration_and_itself_is_bad_input() {
    let run = reach(&["path", "planar3", POST, "--from", "60,-40,-30", "--to", "60,-40,-30"]);
    assert_eq!(run.code, 2, "{}", run.stderr);
    assert!(run.stderr.contains("same configuration"), "{}", run.stderr);
    one_error_line(&run);
}

#[test]
fn path_to_a_pose_ends_at_the_pose() {
    let run = reach(&[
        "path",
        "ur5",
        POST,
        "--from",
        "0,-90,90,-90,-90,0",
        "--to-xyz",
        "0.4,-0.2,0.3",
        "--to-rpy",
        "180,0,0",
        "--json",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let v: Value = serde_json::from_str(&run.stdout).unwrap();
    let last: Vec<String> = v["waypoints_deg"]
        .as_array()
        .unwrap()
        .last()
        .unwrap()
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.to_string())
        .collect();
    let mut args = vec!["fk", "ur5", "--json", "--"];
    args.extend(last.iter().map(String::as_str));
    let fk = reach(&args);
    assert_eq!(fk.code, 0, "{}", fk.stderr);
    let fk: Value = serde_json::from_str(&fk.stdout).unwrap();
    for (got, want) in fk["pose"]["xyz_m"].as_array().unwrap().iter().zip([0.4, -0.2, 0.3]) {
        assert!((got.as_f64().unwrap() - want).abs() < 1e-6, "{fk}");
    }
}

#[test]
fn tasks_draw_the_plan_from_above() {
    let dir = scratch("tasks");
    // Visiting within a 6 s budget: one open route through the points of the budget's plan.
    let visiting = dir.join("v.svg");
    let run = reach(&[
        "tasks",
        "ur5",
        "visiting",
        "examples/tasks_visiting.toml",
        "--budget",
        "6",
        "--json",
        "--svg",
        s(&visiting),
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: Value = serde_json::from_str(&run.stdout).unwrap();
    let fitted = report["within_budget"]["order"].as_array().unwrap().len();
    let points = report["points"].as_array().unwrap().len();
    let text = svg_text(&visiting);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let routes: Vec<_> = doc
        .descendants()
        .filter(|n| n.tag_name().name() == "polyline" && n.attribute("class") == Some("route"))
        .collect();
    assert_eq!(routes.len(), 1);
    // start + every point of the plan
    assert_eq!(routes[0].attribute("points").unwrap().split_whitespace().count(), fitted + 1);
    assert_eq!(count_class(&text, "waypoint") - 1, fitted - 1, "one legend box, the last point is `end`");
    assert!(fitted < points, "the budget leaves points out: {fitted} of {points}");
    // Collection: one round trip per object, as PNG too.
    let (svg, png) = (dir.join("c.svg"), dir.join("c.png"));
    let run = reach(&[
        "tasks",
        "ur5",
        "collection",
        "examples/tasks_collection.toml",
        "--json",
        "--svg",
        s(&svg),
        "--png",
        s(&png),
        "--png-width",
        "410",
    ]);
    assert_eq!(run.code, 0, "{}", run.stderr);
    let report: Value = serde_json::from_str(&run.stdout).unwrap();
    let trips = report["plan"]["order"].as_array().unwrap().len();
    let text = svg_text(&svg);
    let doc = roxmltree::Document::parse(&text).unwrap();
    let routes =
        doc.descendants().filter(|n| n.tag_name().name() == "polyline" && n.attribute("class") == Some("route"));
    assert_eq!(routes.count(), trips);
    assert_eq!(png_size(&png).0, 410);
    // A drawing into a missing directory is bad input, before any work.
    let run = reach(&["tasks", "ur5", "visiting", "examples/tasks_visiting.toml", "--svg", "/no/such/dir/t.svg"]);
    assert_eq!(run.code, 2);
    one_error_line(&run);
}
