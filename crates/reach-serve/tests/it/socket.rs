//! The service on a real socket: the WebSocket streams joint states while moving and job
//! events as they happen.

use std::time::{Duration, Instant};

use serde_json::Value;

use crate::common::{config, open, scratch};

#[test]
fn the_websocket_streams_states_while_moving_and_job_events_in_order() {
    let dir = scratch("ws");
    let service = open(&config("ur5", &dir, 1.0));
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let router = service.router();
    runtime.spawn(async move { axum::serve(listener, router).await });

    let (mut ws, _) = tungstenite::connect(format!("ws://{addr}/ws")).expect("a WebSocket");
    let first: Value = serde_json::from_str(ws.read().unwrap().to_text().unwrap()).unwrap();
    assert_eq!(first["type"], "state", "{first}");
    let body = r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [5, 0, 0, 0, 0, 0], "duration_s": 1}"#;
    let reply =
        ureq::post(format!("http://{addr}/jobs")).content_type("application/json").send(body).expect("POST /jobs");
    assert_eq!(reply.status(), 201);
    let mut job_events = Vec::new();
    let mut states_while_moving = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(60);
    while !job_events.iter().any(|s: &String| s == "done") {
        assert!(Instant::now() < deadline, "no `done` event; saw {job_events:?}");
        let message: Value = serde_json::from_str(ws.read().unwrap().to_text().unwrap()).unwrap();
        match message["type"].as_str() {
            Some("job") => job_events.push(message["status"].as_str().unwrap_or_default().to_string()),
            Some("state") if message["status"] == "executing" => {
                states_while_moving.push(message["t_ms"].as_i64().unwrap())
            }
            _ => {}
        }
    }
    assert_eq!(job_events, ["queued", "planning", "executing", "done"]);
    // 1 s of motion at 50 Hz: 50 ticks (a late tick is sent late, never skipped; a few at
    // the ends may fall outside the motion).
    assert!(states_while_moving.len() >= 45, "{} states while moving", states_while_moving.len());
    let _ = ws.close(None);
}

/// Seed 003's weld as a job (its first 300 mm, a criterion choosing the configuration): the
/// K-events of the library's report arrive on the WebSocket, in the report's order, while the
/// weld executes — before the job's `done`.
#[test]
fn the_k_events_of_a_weld_arrive_on_the_websocket_in_order() {
    use reach::jobs::motion::{ChoiceSpec, MoveRequest, move_motion};
    let dir = scratch("ws-k-events");
    let service = open(&config("welder6r", &dir, 50.0));
    let runtime = tokio::runtime::Builder::new_multi_thread().worker_threads(2).enable_all().build().unwrap();
    let listener = runtime.block_on(tokio::net::TcpListener::bind("127.0.0.1:0")).unwrap();
    let addr = listener.local_addr().unwrap();
    let router = service.router();
    runtime.spawn(async move { axum::serve(listener, router).await });
    let post = |body: &str| {
        let reply = ureq::post(format!("http://{addr}/jobs")).content_type("application/json").send(body).unwrap();
        assert_eq!(reply.status(), 201);
    };

    let rpy = [0.0, -41.86854343693031, -50.19442890773481];
    let (p, m) = ([0.05, 0.74, 0.07], [0.5, 0.2, 0.7]);
    let norm = (0..3).map(|i| (m[i] - p[i]) * (m[i] - p[i])).sum::<f64>().sqrt();
    let to: Vec<f64> = (0..3).map(|i| p[i] + 0.3 * (m[i] - p[i]) / norm).collect();
    let criterion = ChoiceSpec {
        method: "topsis".into(),
        criteria: vec!["limits".into(), "manipulability".into()],
        weights: None,
        require: Default::default(),
    };
    let weld = serde_json::json!({
        "space": "tool", "duration_s": 30.0, "choose": criterion,
        "from": {"pose": {"xyz_m": p, "rpy_deg": rpy}}, "to": {"pose": {"xyz_m": to, "rpy_deg": rpy}},
    });
    let request: MoveRequest = serde_json::from_value(weld.clone()).unwrap();
    let report = move_motion(&reach::model::presets::get("welder6r").unwrap(), &request).unwrap();
    let expected: Vec<String> = report.events.iter().map(|e| e.code.clone()).collect();
    assert!(expected.len() >= 3, "{expected:?}");
    post(&serde_json::json!({"kind": "move", "to_deg": report.samples[0].q_deg, "duration_s": 20}).to_string());

    let (mut ws, _) = tungstenite::connect(format!("ws://{addr}/ws")).expect("a WebSocket");
    let mut weld_job = weld;
    weld_job["kind"] = "move".into();
    let mut codes = Vec::new();
    let mut done = 0;
    let mut submitted = false;
    let deadline = Instant::now() + Duration::from_secs(120);
    while done < 2 {
        assert!(Instant::now() < deadline, "the weld did not end; K-events so far {codes:?}");
        let message: Value = serde_json::from_str(ws.read().unwrap().to_text().unwrap()).unwrap();
        match message["type"].as_str() {
            Some("job") if message["status"] == "done" => {
                done += 1;
                if !submitted {
                    // The arm is at the weld's start: the weld.
                    post(&weld_job.to_string());
                    submitted = true;
                }
            }
            Some("event") => codes.push(message["code"].as_str().unwrap_or_default().to_string()),
            _ => {}
        }
    }
    assert_eq!(codes, expected, "the K-events in the report's order, before `done`");
    let _ = ws.close(None);
}
