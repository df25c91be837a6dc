//! Restarts: the state a restart finds is the last committed one (the real-binary SIGKILL
//! test is in `reach-cli`'s `cli_serve`).

use reach::jobs::drive::{DriveMotion, DriveRequest, drive};
use reach::jobs::input::MotionSample;
use reach::jobs::{MoveReport, Report};
use serde_json::Value;

use crate::common::{call, config, get, integers, open, scratch, submit, wait_job, wait_status};

/// The step counters the library's drive workflow gives for `report`'s motion at `t` seconds:
/// the independent value a committed segment must hold.
fn schedule_steps_at(report: &Value, t: f64) -> Vec<i64> {
    let report: MoveReport = serde_json::from_value(report.clone()).expect("a move report");
    let samples = report.samples.iter().map(MotionSample::from).collect();
    let robot = reach::drive::with_simulated_drives(&reach::model::presets::get("ur5").unwrap()).unwrap().0;
    let drive = drive(&robot, &DriveRequest { motion: DriveMotion::Samples(samples), program: None }).unwrap();
    drive
        .joints
        .iter()
        .map(|j| {
            let last = drive.steps.iter().rfind(|s| s.joint == j.joint && s.t_s <= t);
            last.map_or(j.start_position, |s| s.position)
        })
        .collect()
}

#[tokio::test(flavor = "multi_thread")]
async fn a_restart_shows_the_committed_counts_interrupts_the_job_and_keeps_the_queue() {
    let dir = scratch("restart");
    let c = config("ur5", &dir, 5.0);
    let service = open(&c);
    let router = service.router();
    let long = submit(
        &router,
        r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [90, -45, 30, 0, 0, 10], "duration_s": 20}"#,
    )
    .await;
    // Starts wherever the arm is when it runs.
    let home = submit(&router, r#"{"kind": "move", "to_deg": [0, 0, 0, 0, 0, 0], "duration_s": 1}"#).await;
    wait_job(&router, long, "past segment 4", |j| j["segment"].as_i64().unwrap_or(0) >= 4).await;
    drop(router);
    service.shutdown(); // like a crash between two commits: the motion's job stays `executing`

    let service = open(&c);
    assert_eq!(service.interrupted(), Some(long));
    let router = service.router();
    let job = get(&router, &format!("/jobs/{long}")).await;
    assert_eq!(job["status"], "interrupted", "{job}");
    let k = job["segment"].as_i64().unwrap();
    assert!((4..400).contains(&k), "segment {k} of 400");
    let state = get(&router, "/state").await;
    assert_eq!(state["status"], "stopped", "the queue waits for resume: {state}");
    assert_eq!(state["last_commit"]["segment"], k);
    let want = schedule_steps_at(&job["report"], k as f64 * 0.05);
    assert_eq!(integers(&state["steps"]), want, "the counters of segment {k}");
    assert_eq!(get(&router, &format!("/jobs/{home}")).await["status"], "queued");
    let (status, _) = call(&router, "POST", "/resume", None, None).await;
    assert!(status.is_success());
    let done = wait_status(&router, home, "done").await;
    assert_eq!(
        done["request"]["from"]["joints"]["deg"].as_array().map(Vec::len),
        Some(6),
        "re-planned from the arm: {done}"
    );
    assert_eq!(integers(&get(&router, "/state").await["steps"]), vec![0; 6]);
    // The job interrupted never runs again.
    assert_eq!(get(&router, &format!("/jobs/{long}")).await["status"], "interrupted");
    let _: Option<Report> = None;
}

/// A second service on a state directory in use is refused before it recovers or changes
/// anything: the running job stays `executing` and the queue is not paused.
#[tokio::test(flavor = "multi_thread")]
async fn a_second_service_on_the_same_state_is_refused() {
    let dir = scratch("two-services");
    let first = open(&config("ur5", &dir, 1.0));
    let router = first.router();
    let id = crate::common::submit(&router, r#"{"kind": "move", "to_deg": [30, -90, 90, 0, 90, 0], "duration_s": 30}"#)
        .await;
    crate::common::wait_status(&router, id, "executing").await;
    let Err(e) = reach_serve::Service::open(&config("ur5", &dir, 1.0)) else { panic!("a second service opened") };
    assert!(e.to_string().contains("in use by another reach serve"), "{e}");
    let job = crate::common::get(&router, &format!("/jobs/{id}")).await;
    assert_eq!(job["status"], "executing", "{job}");
    assert_eq!(crate::common::get(&router, "/state").await["status"], "executing");
    crate::common::call(&router, "POST", "/estop", None, None).await;
    drop(router);
    first.shutdown();
    // Released with the service: it opens again.
    drop(open(&config("ur5", &dir, 1.0)));
}

#[tokio::test(flavor = "multi_thread")]
async fn another_robot_on_the_same_state_is_refused() {
    let dir = scratch("other-robot");
    drop(open(&config("ur5", &dir, 1.0)));
    let Err(e) = reach_serve::Service::open(&config("panda", &dir, 1.0)) else { panic!("panda opened ur5's state") };
    let message = e.to_string();
    assert!(message.contains("preset `ur5`") && message.contains("preset `panda`"), "{message}");
}

#[tokio::test(flavor = "multi_thread")]
async fn stop_decelerates_within_the_limits_and_estop_halts_at_once() {
    let dir = scratch("stop");
    let service = open(&config("ur5", &dir, 2.0));
    let router = service.router();
    let id = submit(
        &router,
        r#"{"kind": "move", "from_deg": [0, 0, 0, 0, 0, 0], "to_deg": [90, 0, 0, 0, 0, 0], "duration_s": 4}"#,
    )
    .await;
    wait_job(&router, id, "moving", |j| j["segment"].as_i64().unwrap_or(0) >= 10).await;
    let (status, _) = call(&router, "POST", "/stop", None, None).await;
    assert!(status.is_success());
    let job = wait_status(&router, id, "stopped").await;
    let message = job["message"].as_str().unwrap_or_default();
    assert!(message.contains("POST /stop") && message.contains("decelerated to rest"), "{message}");
    let state = get(&router, "/state").await;
    assert_eq!(state["status"], "stopped");
    let q = state["q_deg"][0].as_f64().unwrap();
    assert!(q > 0.0 && q < 90.0, "stopped on the way: {q}");
    // Braking goes on in the direction of motion: past the last committed segment's position.
    let k = job["segment"].as_i64().unwrap();
    let at_k = schedule_steps_at(&job["report"], k as f64 * 0.05)[0];
    assert!(state["steps"][0].as_i64().unwrap() >= at_k, "{state} vs segment {k} at {at_k}");
    let (status, _) = call(&router, "POST", "/resume", None, None).await;
    assert!(status.is_success());
    let back = submit(&router, r#"{"kind": "move", "to_deg": [0, 0, 0, 0, 0, 0], "duration_s": 4}"#).await;
    wait_job(&router, back, "moving", |j| j["segment"].as_i64().unwrap_or(0) >= 5).await;
    let (status, _) = call(&router, "POST", "/estop", None, None).await;
    assert!(status.is_success());
    let job = wait_status(&router, back, "stopped").await;
    assert!(job["message"].as_str().unwrap_or_default().contains("POST /estop"), "{job}");
}
