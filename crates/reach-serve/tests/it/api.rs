//! The API in-process: jobs run to their end, refusals, errors, the token.

use axum::http::StatusCode;
use serde_json::Value;

use crate::common::{call, config, get, integers, numbers, open, scratch, submit, wait_status};

/// Steps per degree of the default simulated motor (32 000 per revolution).
const STEPS_PER_DEG: f64 = 32_000.0 / 360.0;

#[tokio::test]
async fn a_move_runs_to_its_end_and_commits_every_segment() {
    let dir = scratch("move-runs");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let state = get(&router, "/state").await;
    assert_eq!(state["status"], "idle");
    assert_eq!(integers(&state["steps"]), vec![0; 6], "ur5 starts at home, q = 0");
    assert_eq!(state["drives"][0]["simulated_default"], true, "{state}");
    let id = submit(
        &router,
        r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [10, -20, 0, 0, 5, 0], "duration_s": 1}"#,
    )
    .await;
    let job = wait_status(&router, id, "done").await;
    assert_eq!(job["kind"], "move");
    // 1 s of motion in 50 ms segments: 20 commits, the last one at the end.
    assert_eq!(job["segments"], 20, "{job}");
    assert_eq!(job["segment"], 20, "{job}");
    assert_eq!(job["report"]["kind"], "move", "the library's move report");
    assert_eq!(job["report"]["feasible"], true);
    let state = get(&router, "/state").await;
    let expected: Vec<i64> =
        [10.0, -20.0, 0.0, 0.0, 5.0, 0.0].iter().map(|d: &f64| (d * STEPS_PER_DEG).round() as i64).collect();
    assert_eq!(integers(&state["steps"]), expected, "{state}");
    for (q, want) in numbers(&state["q_deg"]).iter().zip([10.0, -20.0, 0.0, 0.0, 5.0, 0.0]) {
        assert!((q - want).abs() <= 0.5 / STEPS_PER_DEG + 1e-9, "q = {q}, want {want}");
    }
    assert_eq!(state["last_commit"]["job"], id);
    assert_eq!(state["last_commit"]["segment"], 20);
    // The next job starts where this one ended; the library's own request form works too.
    let back = submit(
        &router,
        r#"{"kind": "move", "from": {"joints": {"deg": [10, -20, 0, 0, 5, 0]}}, "to": {"joints": {"deg": [0, 0, 0, 0, 0, 0]}}, "duration_s": 0.5}"#,
    )
    .await;
    wait_status(&router, back, "done").await;
    assert_eq!(integers(&get(&router, "/state").await["steps"]), vec![0; 6]);
    let jobs = get(&router, "/jobs").await;
    assert_eq!(
        jobs.as_array().map(|j| j.iter().map(|j| j["id"].as_i64().unwrap()).collect::<Vec<_>>()),
        Some(vec![id, back])
    );
}

#[tokio::test]
async fn bad_jobs_are_400_with_the_library_message_and_nothing_is_recorded() {
    let dir = scratch("bad-jobs");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let cases: [(&str, &str); 5] = [
        ("not json", "not JSON"),
        (r#"{"from_deg": [0]}"#, "needs a \"kind\""),
        (r#"{"kind": "fk", "q": {"deg": [0, 0, 0, 0, 0, 0]}}"#, "kind `fk`"),
        (r#"{"kind": "move", "from_deg": [0, 0], "to_deg": [1, 1], "duration_s": 1}"#, "6 joint"),
        (
            r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [1, 1, 1, 1, 1, 1], "duration_s": -1}"#,
            "duration_s",
        ),
    ];
    for (body, says) in cases {
        let (status, reply) = call(&router, "POST", "/jobs", Some(body), None).await;
        assert_eq!(status, StatusCode::BAD_REQUEST, "{body}: {reply}");
        let message = reply["error"].as_str().unwrap_or_default();
        assert!(message.contains(says), "{body}: `{message}` does not say `{says}`");
    }
    assert_eq!(get(&router, "/jobs").await, Value::Array(vec![]));
}

#[tokio::test]
async fn a_job_outside_the_limits_is_refused_with_its_report_and_nothing_moves() {
    let dir = scratch("outside-limits");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let (status, reply) = call(
        &router,
        "POST",
        "/jobs",
        Some(r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [400, 0, 0, 0, 0, 0], "duration_s": 1}"#),
        None,
    )
    .await;
    assert_eq!(status, StatusCode::CREATED, "{reply}");
    assert_eq!(reply["status"], "refused", "{reply}");
    let job = get(&router, &format!("/jobs/{}", reply["id"])).await;
    assert_eq!(job["status"], "refused");
    assert_eq!(job["report"]["feasible"], false, "the library's report says why: {job}");
    assert!(job["message"].as_str().unwrap_or_default().contains("shoulder_pan"), "{job}");
    let state = get(&router, "/state").await;
    assert_eq!(integers(&state["steps"]), vec![0; 6]);
    assert!(state["last_commit"].is_null(), "nothing was committed: {state}");
}

#[tokio::test]
async fn a_job_that_does_not_start_where_the_arm_is_is_refused_naming_the_joint() {
    let dir = scratch("wrong-start");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let id = submit(
        &router,
        r#"{"kind": "move", "from_deg": [0, -90, 0, 0, 0, 0], "to_deg": [0, -80, 0, 0, 0, 0], "duration_s": 1}"#,
    )
    .await;
    let job = wait_status(&router, id, "refused").await;
    let message = job["message"].as_str().unwrap_or_default();
    assert!(message.contains("joint 2 `shoulder_lift` at -90 deg") && message.contains("arm is at 0 deg"), "{message}");
    assert_eq!(integers(&get(&router, "/state").await["steps"]), vec![0; 6]);
}

#[tokio::test]
async fn oversized_bodies_unknown_paths_and_jobs_have_json_errors() {
    let dir = scratch("errors");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let big = format!(r#"{{"kind": "plan", "task": "{}"}}"#, "#".repeat(2 << 20));
    let (status, reply) = call(&router, "POST", "/jobs", Some(&big), None).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{reply}");
    assert!(reply["error"].as_str().unwrap_or_default().contains("limit"), "{reply}");
    let (status, reply) = call(&router, "GET", "/jobs/99", None, None).await;
    assert_eq!((status, reply["error"].as_str().is_some()), (StatusCode::NOT_FOUND, true), "{reply}");
    let (status, _) = call(&router, "GET", "/nowhere", None, None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
}

#[tokio::test]
async fn beyond_loopback_every_request_needs_the_token() {
    let dir = scratch("token");
    let mut c = config("ur5", &dir, 50.0);
    c.listen = "0.0.0.0:0".parse().unwrap();
    let service = open(&c);
    let router = service.router();
    let token = std::fs::read_to_string(dir.join("token")).unwrap();
    assert_eq!(token.len(), 64, "32 random bytes in hex");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(dir.join("token")).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600, "the token file is private");
    }
    for (method, uri) in
        [("POST", "/jobs"), ("POST", "/stop"), ("POST", "/estop"), ("POST", "/resume"), ("GET", "/state")]
    {
        let (status, reply) = call(&router, method, uri, Some("{}"), None).await;
        assert_eq!(status, StatusCode::UNAUTHORIZED, "{method} {uri}: {reply}");
        let (status, _) = call(&router, method, uri, Some("{}"), Some("wrong")).await;
        assert_eq!(status, StatusCode::UNAUTHORIZED, "{method} {uri} with a wrong token");
    }
    let (status, reply) = call(&router, "GET", "/state", None, Some(&token)).await;
    assert_eq!(status, StatusCode::OK, "{reply}");
    let (status, _) = call(&router, "GET", "/openapi.json", None, None).await;
    assert_eq!(status, StatusCode::OK, "the description is public");
    // The same token on the next start; a token file others can read is made private again.
    drop(router);
    service.shutdown();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(dir.join("token"), std::fs::Permissions::from_mode(0o644)).unwrap();
        let again = open(&c);
        assert_eq!(std::fs::read_to_string(dir.join("token")).unwrap(), token);
        let mode = std::fs::metadata(dir.join("token")).unwrap().permissions().mode();
        assert_eq!(mode & 0o777, 0o600);
        drop(again);
    }
}

#[tokio::test]
async fn stop_pauses_the_queue_and_resume_releases_it() {
    let dir = scratch("stop-idle");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let (status, state) = call(&router, "POST", "/stop", None, None).await;
    assert_eq!((status, state["status"].as_str()), (StatusCode::OK, Some("stopped")));
    let id = submit(
        &router,
        r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [1, 0, 0, 0, 0, 0], "duration_s": 0.2}"#,
    )
    .await;
    // Paused: the job stays queued (checked after the executor had a chance to pick it up).
    tokio::time::sleep(std::time::Duration::from_millis(50)).await;
    assert_eq!(get(&router, &format!("/jobs/{id}")).await["status"], "queued");
    let (status, _) = call(&router, "POST", "/resume", None, None).await;
    assert_eq!(status, StatusCode::OK);
    wait_status(&router, id, "done").await;
}

/// On loopback, a request for a host that is not a loopback name (a page of another site
/// resolving to 127.0.0.1: DNS rebinding) is refused; loopback names pass.
#[tokio::test]
async fn a_loopback_service_answers_only_to_loopback_names() {
    use axum::body::Body;
    use tower::ServiceExt;
    let dir = scratch("host-check");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    for (host, expected) in [("evil.example:7878", StatusCode::FORBIDDEN), ("localhost:7878", StatusCode::OK)] {
        let request = axum::http::Request::get("/state").header("host", host).body(Body::empty()).unwrap();
        let response = router.clone().oneshot(request).await.unwrap();
        assert_eq!(response.status(), expected, "{host}");
    }
}

/// Issue 36 point 4: the Host check reads the whole header, not up to `]` or the first colon,
/// and a second Host header is refused.
#[tokio::test]
async fn host_is_parsed_strictly_and_only_one_host_header_is_accepted() {
    use axum::body::Body;
    use tower::ServiceExt;
    let dir = scratch("host-strict");
    let service = open(&config("ur5", &dir, 50.0));
    let router = service.router();
    let refused = [
        "[::1].evil.com",
        "[::1]evil.com:80",
        "localhost.evil.com",
        "127.0.0.1.evil.com:80",
        "127.0.0.1:80x",
        "localhost:",
        "[::1]:",
        "evil.com:127.0.0.1",
        "127.1",
        "localhost:123456",
    ];
    for host in refused {
        let request = axum::http::Request::get("/state").header("host", host).body(Body::empty()).unwrap();
        let response = router.clone().oneshot(request).await.unwrap();
        assert_eq!(response.status(), StatusCode::FORBIDDEN, "{host}");
    }
    for host in ["localhost", "LocalHost:7878", "127.0.0.1", "127.0.0.1:80", "127.0.0.2:7878", "[::1]", "[::1]:7878"] {
        let request = axum::http::Request::get("/state").header("host", host).body(Body::empty()).unwrap();
        let response = router.clone().oneshot(request).await.unwrap();
        assert_eq!(response.status(), StatusCode::OK, "{host}");
    }
    let request = axum::http::Request::get("/state")
        .header("host", "localhost:7878")
        .header("host", "evil.example")
        .body(Body::empty())
        .unwrap();
    let response = router.clone().oneshot(request).await.unwrap();
    assert_eq!(response.status(), StatusCode::BAD_REQUEST, "two Host headers");
}
