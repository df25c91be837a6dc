//! Shared helpers: a service on a scratch state directory, requests through the router,
//! polling with generous timeouts (never a sleep as an assertion).

use std::path::PathBuf;
use std::time::{Duration, Instant};

use axum::Router;
use axum::body::Body;
use axum::http::{Request, StatusCode};
use reach::jobs::RobotInput;
use reach_serve::db::JobStatus;
use reach_serve::{Config, Service};
use serde_json::Value;
use tower::ServiceExt;

/// A fresh scratch directory for one test.
pub fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("reach-serve-it-{}", std::process::id())).join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The configuration of `preset` with state in `dir`, `speed` times real time.
pub fn config(preset: &str, dir: &std::path::Path, speed: f64) -> Config {
    let mut c = Config::new(RobotInput::Preset(preset.into()));
    c.state_dir = dir.to_path_buf();
    c.speed = speed;
    c
}

/// Opens a service.
pub fn open(config: &Config) -> Service {
    Service::open(config).expect("the service opens")
}

/// One request through the router: status and JSON body (`Null` when not JSON).
pub async fn call(
    router: &Router,
    method: &str,
    uri: &str,
    body: Option<&str>,
    token: Option<&str>,
) -> (StatusCode, Value) {
    let mut request = Request::builder().method(method).uri(uri);
    if let Some(t) = token {
        request = request.header("authorization", format!("Bearer {t}"));
    }
    let request = request
        .header("content-type", "application/json")
        .body(body.map_or_else(Body::empty, |b| Body::from(b.to_string())))
        .unwrap();
    let response = router.clone().oneshot(request).await.unwrap();
    let status = response.status();
    let bytes = axum::body::to_bytes(response.into_body(), usize::MAX).await.unwrap();
    (status, serde_json::from_slice(&bytes).unwrap_or(Value::Null))
}

/// `GET uri`, expecting 200.
pub async fn get(router: &Router, uri: &str) -> Value {
    let (status, body) = call(router, "GET", uri, None, None).await;
    assert_eq!(status, StatusCode::OK, "GET {uri}: {body}");
    body
}

/// `POST /jobs`, expecting 201; returns the job id.
pub async fn submit(router: &Router, job: &str) -> i64 {
    let (status, body) = call(router, "POST", "/jobs", Some(job), None).await;
    assert_eq!(status, StatusCode::CREATED, "POST /jobs {job}: {body}");
    body["id"].as_i64().expect("an id")
}

/// Polls `GET /jobs/{id}` until `done(job)` holds (at most 60 s); returns the job.
pub async fn wait_job(router: &Router, id: i64, what: &str, done: impl Fn(&Value) -> bool) -> Value {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let job = get(router, &format!("/jobs/{id}")).await;
        if done(&job) {
            return job;
        }
        assert!(Instant::now() < deadline, "job {id} never became {what}: {job}");
        tokio::time::sleep(Duration::from_millis(5)).await;
    }
}

/// Polls until job `id` ends (or has `status`); asserts it has `status`.
pub async fn wait_status(router: &Router, id: i64, status: &str) -> Value {
    let ended = |j: &Value| j["status"].as_str().and_then(JobStatus::parse).is_some_and(JobStatus::is_final);
    let job = wait_job(router, id, status, |j| j["status"] == status || ended(j)).await;
    assert_eq!(job["status"], status, "job {id}: {job}");
    job
}

/// The numbers of a JSON array.
pub fn numbers(v: &Value) -> Vec<f64> {
    v.as_array().expect("an array").iter().map(|x| x.as_f64().expect("a number")).collect()
}

/// The integers of a JSON array.
pub fn integers(v: &Value) -> Vec<i64> {
    v.as_array().expect("an array").iter().map(|x| x.as_i64().expect("an integer")).collect()
}
