//! Issue 36: every size a request carries is bounded (refused with 400 and the library's
//! message before anything is stored), a wrong obstacle can be removed, and the state is its
//! owner's only.

use axum::http::StatusCode;
use serde_json::Value;

use crate::common::{call, config, get, open, scratch, submit, wait_status};

/// A move of `duration_s = 1e308` (issue 36's reproduction) would hold the queue for ever:
/// refused before it is stored, naming the field and the one-day cap; a report too large to
/// store (200 000 samples) is refused too, saying how to make it smaller.
#[tokio::test(flavor = "multi_thread")]
async fn durations_and_report_sizes_are_capped_before_anything_is_stored() {
    let dir = scratch("caps");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let cases = [
        (r#"{"kind": "move", "to_deg": [10, 0, 0, 0, 0, 0], "duration_s": 1e308}"#, "`duration_s` at most 86400 s"),
        (
            r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [10, 0, 0, 0, 0, 0], "duration_s": 90000}"#,
            "`duration_s` at most 86400 s",
        ),
        (
            r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [10, 0, 0, 0, 0, 0], "duration_s": 200, "dt_s": 0.001}"#,
            "larger `dt_s`",
        ),
    ];
    for (body, says) in cases {
        let (status, reply) = call(&router, "POST", "/jobs", Some(body), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}: {reply}");
        let message = reply["error"].as_str().unwrap_or_default();
        assert!(message.contains(says), "{body}: `{message}` does not say `{says}`");
    }
    assert_eq!(get(&router, "/jobs").await, Value::Array(vec![]), "nothing is stored");
    // A day is allowed.
    let day = submit(&router, r#"{"kind": "move", "to_deg": [10, 0, 0, 0, 0, 0], "duration_s": 86400}"#).await;
    let (status, _) = call(&router, "POST", "/stop", None, None).await;
    assert_eq!(status, StatusCode::OK);
    let job = get(&router, &format!("/jobs/{day}")).await;
    assert_ne!(job["status"], "refused", "{job}");
    service.shutdown();
}

/// Issue 36's obstacle of radius (or centre) 1e308 would disable the cell: refused with the
/// library's message, nothing stored; a wrong obstacle is removed with
/// `DELETE /scene/obstacles/{name}`, journalled and announced, and a taken name is a 409.
#[tokio::test(flavor = "multi_thread")]
async fn obstacles_beyond_the_workcell_are_refused_and_a_wrong_one_can_be_removed() {
    let dir = scratch("obstacle-caps");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    for body in [
        r#"{"name": "h", "shape": "sphere", "center": [5, 5, 5], "radius": 1e308}"#,
        r#"{"name": "h", "shape": "sphere", "center": [1e308, 0, 0], "radius": 0.1}"#,
        r#"{"name": "h", "shape": "box", "center": [0, 0, 0], "half_extents": [1e6, 1, 1]}"#,
        r#"{"name": "h", "shape": "halfspace", "point": [0, 0, -1e9], "outward_normal": [0, 0, 1]}"#,
    ] {
        let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(body), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}: {reply}");
        let message = reply["error"].as_str().unwrap_or_default();
        assert!(message.contains("obstacle `h`") && message.contains("10 × the reach of ur5"), "{message}");
    }
    assert_eq!(get(&router, "/state").await["queued"], 0);
    let db = rusqlite::Connection::open(dir.join("state.sqlite3")).unwrap();
    let scene: Option<String> =
        db.query_row("SELECT value FROM meta WHERE key = 'scene'", [], |r| r.get(0)).unwrap_or(None);
    assert!(scene.is_none_or(|s| !s.contains("1e308") && !s.contains("obstacles")), "nothing stored");

    // A ball where the upright arm's tool is (put there by mistake), a table and an unnamed ball.
    let wrong = r#"{"name": "wrong", "shape": "sphere", "center": [0, -0.19145, 1.001], "radius": 0.05}"#;
    let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(wrong), None).await;
    assert_eq!((status, reply["obstacles"].as_i64()), (StatusCode::CREATED, Some(1)), "{reply}");
    let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(wrong), None).await;
    assert_eq!(status, StatusCode::CONFLICT, "a taken name: {reply}");
    let table = r#"{"name": "table", "shape": "box", "center": [0.6, 0, -0.05], "half_extents": [0.3, 0.3, 0.05]}"#;
    let (status, _) = call(&router, "POST", "/scene/obstacles", Some(table), None).await;
    assert_eq!(status, StatusCode::CREATED);
    let unnamed = r#"{"shape": "sphere", "center": [0.8, 0.8, 0.8], "radius": 0.05}"#;
    let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(unnamed), None).await;
    assert_eq!((status, reply["obstacles"].as_i64()), (StatusCode::CREATED, Some(3)), "{reply}");

    let upright = r#"{"kind": "move", "to_deg": [0, -90, 0, -90, 0, 0], "duration_s": 1}"#;
    let blocked = submit(&router, upright).await;
    let job = wait_status(&router, blocked, "refused").await;
    assert!(job["message"].as_str().unwrap_or_default().contains("`wrong`"), "{job}");
    let (status, reply) = call(&router, "DELETE", "/scene/obstacles/nothing", None, None).await;
    assert_eq!(status, StatusCode::NOT_FOUND, "{reply}");
    assert!(reply["error"].as_str().unwrap_or_default().contains("wrong, table, obstacle3"), "{reply}");
    let (status, reply) = call(&router, "DELETE", "/scene/obstacles/wrong", None, None).await;
    assert_eq!((status, reply["obstacles"].as_i64()), (StatusCode::OK, Some(2)), "{reply}");
    // The unnamed obstacle keeps its name; the journal says what was removed.
    let names: Vec<String> = reach_serve_scene(&dir).obstacles.iter().map(|o| o.name.clone()).collect();
    assert_eq!(names, ["table", "obstacle3"]);
    let removed: String = db
        .query_row("SELECT message FROM events WHERE type = 'obstacle_removed'", [], |r| r.get(0))
        .expect("the removal is journalled");
    assert_eq!(removed, "wrong");
    // The move it blocked runs now; the scene survives a restart.
    let through = submit(&router, upright).await;
    wait_status(&router, through, "done").await;
    drop(router);
    service.shutdown();
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let (status, reply) = call(&router, "DELETE", "/scene/obstacles/obstacle3", None, None).await;
    assert_eq!((status, reply["obstacles"].as_i64()), (StatusCode::OK, Some(1)), "{reply}");
    service.shutdown();
}

/// The scene stored in a state directory.
fn reach_serve_scene(dir: &std::path::Path) -> reach::world::Scene {
    let db = rusqlite::Connection::open(dir.join("state.sqlite3")).unwrap();
    let text: String = db.query_row("SELECT value FROM meta WHERE key = 'scene'", [], |r| r.get(0)).unwrap();
    reach::jobs::world::parse_scene(&text).unwrap()
}

/// The state directory the service makes is its owner's only (0700), and every file in it
/// (database, its WAL, the token, the lock) is 0600; a database left readable is made private
/// again at start.
#[cfg(unix)]
#[test]
fn the_state_directory_and_its_files_are_the_owners_only() {
    use std::os::unix::fs::PermissionsExt;
    let dir = scratch("private").join("state");
    let mode = |p: &std::path::Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    let service = open(&config("ur5", &dir, 50.0));
    assert_eq!(mode(&dir), 0o700);
    let files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    for name in ["state.sqlite3", "state.sqlite3-wal", "token", "lock"] {
        assert!(files.contains(&dir.join(name)), "{name} in {files:?}");
    }
    for file in &files {
        assert_eq!(mode(file), 0o600, "{}", file.display());
    }
    service.shutdown();
    std::fs::set_permissions(dir.join("state.sqlite3"), std::fs::Permissions::from_mode(0o644)).unwrap();
    let service = open(&config("ur5", &dir, 50.0));
    assert_eq!(mode(&dir.join("state.sqlite3")), 0o600);
    service.shutdown();
}
