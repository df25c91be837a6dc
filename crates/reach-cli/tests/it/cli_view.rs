//! `reach view`: one self-contained HTML file whose embedded data is the library's view
//! report for the same request (and valid against its schema). The page itself is tested in
//! a real browser by `web/tests/` (`scripts/test`).

use serde_json::Value;

use crate::common::{REPO_ROOT, assert_valid, fails, ok, scratch};

/// The view report embedded in an exported page.
fn embedded(html: &str) -> Value {
    let open = r#"<script id="reach-view-data" type="application/json">"#;
    let start = html.find(open).expect("data script") + open.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

#[test]
fn the_page_embeds_the_library_report_and_needs_no_network() {
    let dir = scratch("view");
    let motion = dir.join("m.json");
    let text =
        ok(&["move", "ur5", "--from", "0,-90,90,0,90,0", "--to", "45,-60,60,30,60,20", "--duration", "2", "--json"]);
    std::fs::write(&motion, &text).unwrap();
    let html_path = dir.join("v.html");
    let line = ok(&[
        "view",
        "ur5",
        "--motion",
        motion.to_str().unwrap(),
        "--scene",
        &format!("{REPO_ROOT}/examples/seed004_ceiling.toml"),
        "-o",
        html_path.to_str().unwrap(),
    ]);
    assert!(line.starts_with("wrote ") && line.contains("IK ghosts"), "{line}");
    let html = std::fs::read_to_string(&html_path).unwrap();
    assert!(!html.contains("<script src"), "every script is inline");
    let data = embedded(&html);
    assert_valid("view.report", &data);
    let request = reach::jobs::ViewRequest {
        samples: Some(reach::jobs::input::parse_motion_json(&text).unwrap()),
        events: reach::jobs::view::parse_motion_events(&text).unwrap(),
        scene: Some(std::fs::read_to_string(format!("{REPO_ROOT}/examples/seed004_ceiling.toml")).unwrap()),
        ..Default::default()
    };
    let expected = reach::jobs::view::view(&reach::model::presets::get("ur5").unwrap(), &request).unwrap();
    assert_eq!(data, serde_json::to_value(&expected).unwrap());
    let samples = serde_json::from_str::<Value>(&text).unwrap()["samples"].as_array().unwrap().len();
    assert_eq!(data["states"].as_array().unwrap().len(), samples);
}

#[test]
fn bad_input_is_one_line_and_exit_2() {
    let dir = scratch("view-bad");
    let out = dir.join("v.html");
    let out = out.to_str().unwrap();
    fails(&["view", "ur5", "0", "0", "-o", out], 2, &["6 joints, got 2"]);
    fails(&["view", "ur5", "--motion", "/nonexistent/m.json", "-o", out], 2, &["/nonexistent/m.json"]);
    fails(&["view", "ur5", "--ik-xyz", "0.4,0.2", "-o", out], 2, &["--ik-xyz"]);
    assert!(!std::path::Path::new(out).exists(), "nothing written on bad input");
}
