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
