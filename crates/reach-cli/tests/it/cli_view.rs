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
    let scene = format!("{REPO_ROOT}/examples/seed004_ceiling.toml");
    fails(&["view", "varan4", "--scene", &scene, "--cspace", "2", "-o", out], 2, &["--cspace: two joints"]);
    fails(&["view", "varan4", "--scene", &scene, "--cspace", "2,7", "-o", out], 2, &["joints 2 and 7"]);
    assert!(!std::path::Path::new(out).exists(), "nothing written on bad input");
}

const KR16: &str = "examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf";

#[test]
fn a_urdf_robot_is_drawn_with_its_visual_meshes_inlined() {
    use base64::Engine as _;
    let dir = scratch("view-urdf");
    let html_path = dir.join("kr16.html");
    let urdf = format!("{REPO_ROOT}/{KR16}");
    let line =
        ok(&["view", &urdf, "--tip", "tool0", "0", "-90", "90", "0", "45", "0", "-o", html_path.to_str().unwrap()]);
    assert!(line.trim_end().ends_with("7 meshes)"), "{line}");
    let data = embedded(&std::fs::read_to_string(&html_path).unwrap());
    assert_valid("view.report", &data);
    let doc = &data["urdf"];
    assert_eq!((doc["base_link"].as_str(), doc["tip_link"].as_str()), (Some("base_link"), Some("tool0")));
    assert_eq!(doc["text"].as_str().unwrap(), std::fs::read_to_string(&urdf).unwrap());
    let meshes = doc["meshes"].as_array().unwrap();
    let visual = format!("{REPO_ROOT}/examples/urdf/kuka_kr16_support/meshes/kr16_2/visual");
    for (mesh, link) in meshes.iter().zip(["base_link", "link_1", "link_2", "link_3", "link_4", "link_5", "link_6"]) {
        let filename = mesh["filename"].as_str().unwrap();
        assert_eq!(filename, format!("package://kuka_kr16_support/meshes/kr16_2/visual/{link}.dae"));
        let bytes = base64::engine::general_purpose::STANDARD.decode(mesh["base64"].as_str().unwrap()).unwrap();
        assert_eq!(bytes, std::fs::read(format!("{visual}/{link}.dae")).unwrap(), "{filename}");
    }
    assert_eq!(meshes.len(), 7, "visual meshes only, each once");

    // --no-meshes: the chain as capsules, no document.
    ok(&["view", &urdf, "--tip", "tool0", "--no-meshes", "-o", html_path.to_str().unwrap()]);
    assert!(embedded(&std::fs::read_to_string(&html_path).unwrap()).get("urdf").is_none());
}

#[test]
fn a_missing_or_oversized_mesh_is_one_line_naming_the_file() {
    let dir = scratch("view-urdf-bad");
    let out = dir.join("v.html");
    let out = out.to_str().unwrap();
    let text = std::fs::read_to_string(format!("{REPO_ROOT}/{KR16}")).unwrap();

    // The package layout without its meshes directory.
    let package = dir.join("kuka_kr16_support/urdf");
    std::fs::create_dir_all(&package).unwrap();
    let urdf = package.join("kr16_2.urdf");
    std::fs::write(&urdf, &text).unwrap();
    let urdf = urdf.to_str().unwrap();
    fails(
        &["view", urdf, "--tip", "tool0", "-o", out],
        2,
        &["package://kuka_kr16_support/meshes/kr16_2/visual/base_link.dae", "kuka_kr16_support/meshes", "--no-meshes"],
    );
    ok(&["view", urdf, "--tip", "tool0", "--no-meshes", "-o", out]);
    std::fs::remove_file(out).unwrap();

    // No directory named after the package above or beside the file.
    let apart = dir.join("apart");
    std::fs::create_dir_all(&apart).unwrap();
    let alone = apart.join("kr16_2.urdf");
    std::fs::write(&alone, &text).unwrap();
    fails(
        &["view", alone.to_str().unwrap(), "--tip", "tool0", "-o", out],
        2,
        &["no directory `kuka_kr16_support` above or beside"],
    );

    // A relative mesh address over the cap (a sparse file: nothing is written to disk).
    let big = dir.join("big.urdf");
    let doc = text.replacen("package://kuka_kr16_support/meshes/kr16_2/visual/base_link.dae", "meshes/big.stl", 1);
    std::fs::write(&big, doc).unwrap();
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    let file = std::fs::File::create(dir.join("meshes/big.stl")).unwrap();
    file.set_len((reach::jobs::view::MAX_VIEW_MESH_BYTES + 1) as u64).unwrap();
    fails(&["view", big.to_str().unwrap(), "--tip", "tool0", "-o", out], 2, &["64 MiB", "meshes/big.stl"]);

    // A mesh format the viewer cannot draw.
    let obj = dir.join("obj.urdf");
    std::fs::write(&obj, text.replacen("visual/base_link.dae", "visual/base_link.obj", 1)).unwrap();
    fails(&["view", obj.to_str().unwrap(), "--tip", "tool0", "-o", out], 2, &["base_link.obj", "STL and Collada"]);
    assert!(!std::path::Path::new(out).exists(), "nothing written on bad input");
}
