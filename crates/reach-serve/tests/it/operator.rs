//! Seed 003's dialogue with the operator: a tool-space move with several feasible
//! configurations waits for `POST /jobs/{id}/choose`; without an answer the configured
//! criterion (or the default configuration) decides after the timeout.

use axum::Router;
use axum::http::StatusCode;
use reach::jobs::motion::{ChoiceSpec, IntervalChoice, MoveReport, MoveRequest, move_motion};
use reach::model::presets;
use serde_json::{Value, json};

use crate::common::{call, config, get, numbers, open, scratch, submit, wait_job, wait_status};

/// The first 300 mm of seed 003's weld (P towards M at constant orientation, 30 s): both of the
/// welder's configurations are feasible there (−β's θ4 leaves its range only at s = 618 mm).
fn weld() -> Value {
    let (p, m) = ([0.05, 0.74, 0.07], [0.5, 0.2, 0.7]);
    let d: Vec<f64> = (0..3).map(|i| m[i] - p[i]).collect();
    let norm = d.iter().map(|x| x * x).sum::<f64>().sqrt();
    let to: Vec<f64> = (0..3).map(|i| p[i] + 0.3 * d[i] / norm).collect();
    let rpy = [0.0, -41.86854343693031, -50.19442890773481];
    json!({
        "kind": "move", "space": "tool", "duration_s": 30.0,
        "from": {"pose": {"xyz_m": p, "rpy_deg": rpy}},
        "to": {"pose": {"xyz_m": to, "rpy_deg": rpy}},
    })
}

/// The library's plan of the weld with `choices` / `choose` added.
fn planned(choices: Vec<IntervalChoice>, choose: Option<ChoiceSpec>) -> MoveReport {
    let mut job = weld();
    job.as_object_mut().unwrap().remove("kind");
    let mut request: MoveRequest = serde_json::from_value(job).unwrap();
    request.choices = choices;
    request.choose = choose;
    move_motion(&presets::get("welder6r").unwrap(), &request).unwrap()
}

/// Moves the arm (joint space, from where it is) to `q_deg` and waits until it is there.
async fn go_to(router: &Router, q_deg: &[f64]) {
    let id = submit(router, &json!({"kind": "move", "to_deg": q_deg, "duration_s": 20.0}).to_string()).await;
    wait_status(router, id, "done").await;
}

/// Asserts the arm is at `q_deg` within one step of the default simulated motor.
async fn assert_at(router: &Router, q_deg: &[f64]) {
    let state = get(router, "/state").await;
    for (q, want) in numbers(&state["q_deg"]).iter().zip(q_deg) {
        assert!((q - want).abs() <= 360.0 / 32_000.0, "q = {q}, want {want}: {state}");
    }
}

#[tokio::test]
async fn the_operator_chooses_the_configuration_and_the_arm_follows_it() {
    let dir = scratch("operator-chooses");
    let service = open(&config("welder6r", &dir, 200.0));
    let router = service.router();
    let default = planned(Vec::new(), None);
    let other = default.intervals[0].alternatives[1].clone();
    let chosen = planned(vec![IntervalChoice { interval: 1, configuration: other.clone() }], None);
    go_to(&router, &chosen.samples[0].q_deg).await;

    let id = submit(&router, &weld().to_string()).await;
    let job = wait_job(&router, id, "waiting", |j| j["status"] == "waiting_operator").await;
    let question = &job["questions"][0];
    assert_eq!(question["interval"], 1, "{job}");
    assert_eq!(question["alternatives"], json!(default.intervals[0].alternatives), "{job}");
    assert_eq!(question["proposed"], json!(default.intervals[0].configuration), "{job}");
    let state = wait_state(&router, "waiting").await;
    assert_eq!(state["job"], id, "the queue waits for the operator: {state}");

    // Bad answers are refused with the library's words; the job keeps waiting.
    let bad = json!({"choices": [{"interval": 1, "configuration": "elbow sideways"}]}).to_string();
    let (status, reply) = call(&router, "POST", &format!("/jobs/{id}/choose"), Some(&bad), None).await;
    assert_eq!(status, StatusCode::BAD_REQUEST, "{reply}");
    assert!(reply["error"].as_str().unwrap().contains("no configuration `elbow sideways`"), "{reply}");
    let (status, _) = call(&router, "POST", "/jobs/999/choose", Some(&bad), None).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(get(&router, &format!("/jobs/{id}")).await["status"], "waiting_operator");

    let answer = json!({"choices": [{"interval": 1, "configuration": other}]}).to_string();
    let (status, reply) = call(&router, "POST", &format!("/jobs/{id}/choose"), Some(&answer), None).await;
    assert_eq!(status, StatusCode::OK, "{reply}");
    let job = wait_status(&router, id, "done").await;
    let interval = &job["report"]["intervals"][0];
    assert_eq!(interval["decision"], "operator", "{job}");
    assert_eq!(interval["configuration"], json!(other), "{job}");
    assert_at(&router, &chosen.samples.last().unwrap().q_deg).await;
    // Answered once: a second answer finds nothing waiting.
    let (status, reply) = call(&router, "POST", &format!("/jobs/{id}/choose"), Some(&answer), None).await;
    assert_eq!(status, StatusCode::CONFLICT, "{reply}");
}

#[tokio::test]
async fn without_an_answer_the_criterion_decides_after_the_timeout() {
    let dir = scratch("operator-timeout");
    let mut cfg = config("welder6r", &dir, 200.0);
    let criterion = ChoiceSpec {
        method: "topsis".into(),
        criteria: vec!["limits".into(), "manipulability".into()],
        weights: None,
        require: Default::default(),
    };
    cfg.operator_timeout_s = 0.3;
    cfg.operator_criterion = Some(criterion.clone());
    let service = open(&cfg);
    let router = service.router();
    let expected = planned(Vec::new(), Some(criterion));
    go_to(&router, &expected.samples[0].q_deg).await;
    let id = submit(&router, &weld().to_string()).await;
    let job = wait_status(&router, id, "done").await;
    assert_eq!(job["report"]["intervals"][0]["decision"], "criterion", "{job}");
    assert_eq!(job["report"]["intervals"][0]["configuration"], json!(expected.intervals[0].configuration));
    assert!(job["message"].as_str().unwrap().contains("no answer within 0 s: the criterion (topsis) chose"), "{job}");
    assert_at(&router, &expected.samples.last().unwrap().q_deg).await;
}

#[tokio::test]
async fn a_stop_while_waiting_keeps_the_question_until_resume() {
    let dir = scratch("operator-stop");
    let mut cfg = config("welder6r", &dir, 200.0);
    cfg.operator_timeout_s = 3600.0;
    let service = open(&cfg);
    let router = service.router();
    let default = planned(Vec::new(), None);
    go_to(&router, &default.samples[0].q_deg).await;
    let id = submit(&router, &weld().to_string()).await;
    wait_state(&router, "waiting").await;
    let (status, state) = call(&router, "POST", "/stop", None, None).await;
    assert_eq!(status, StatusCode::OK, "{state}");
    let state = wait_state(&router, "stopped").await;
    assert_eq!(state["job"], Value::Null, "{state}");
    assert_eq!(get(&router, &format!("/jobs/{id}")).await["status"], "waiting_operator");
    let (status, _) = call(&router, "POST", "/resume", None, None).await;
    assert_eq!(status, StatusCode::OK);
    assert_eq!(wait_state(&router, "waiting").await["job"], id, "asked again after the resume");
    let proposed = default.intervals[0].configuration.clone().unwrap();
    let answer = json!({"choices": [{"interval": 1, "configuration": proposed}]}).to_string();
    let (status, reply) = call(&router, "POST", &format!("/jobs/{id}/choose"), Some(&answer), None).await;
    assert_eq!(status, StatusCode::OK, "{reply}");
    wait_status(&router, id, "done").await;
    assert_at(&router, &default.samples.last().unwrap().q_deg).await;
}

/// Polls `GET /state` until its status is `status` (at most 60 s).
async fn wait_state(router: &Router, status: &str) -> Value {
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    loop {
        let state = get(router, "/state").await;
        if state["status"] == status {
            return state;
        }
        assert!(std::time::Instant::now() < deadline, "the service never became {status}: {state}");
        tokio::time::sleep(std::time::Duration::from_millis(5)).await;
    }
}
