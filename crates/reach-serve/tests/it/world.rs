//! Jobs in a scene: a straight joint move through an obstacle is refused by the swept check;
//! a path job (planned around it) and a plan job run.

use crate::common::{call, config, get, integers, open, scratch, submit, wait_status};

const SCENE: &str = include_str!("../../../../examples/path_planar3_post.toml");

#[tokio::test(flavor = "multi_thread")]
async fn in_a_scene_a_blocked_move_is_refused_and_a_path_around_it_runs() {
    let dir = scratch("scene");
    let mut c = config("planar3", &dir, 50.0);
    c.scene = Some(SCENE.to_string());
    let service = open(&c);
    let router = service.router();
    let to_start = submit(&router, r#"{"kind": "move", "to_deg": [60, -40, -30], "duration_s": 10}"#).await;
    let job = wait_status(&router, to_start, "done").await;
    assert_eq!(job["segments"], 200, "{job}");
    // Straight through the post (README: `reach check ... --to 0,-30,-30` is not clear).
    let blocked =
        submit(&router, r#"{"kind": "move", "from_deg": [60, -40, -30], "to_deg": [0, -30, -30], "duration_s": 10}"#)
            .await;
    let job = wait_status(&router, blocked, "refused").await;
    let message = job["message"].as_str().unwrap_or_default();
    assert!(message.contains("not proven clear"), "{message}");
    let before = get(&router, "/state").await;
    // The same goal by a planned path: every edge proven clear by the library.
    let scene = serde_json::to_string(SCENE).unwrap();
    let path = submit(
        &router,
        &format!(r#"{{"kind": "path", "scene": {scene}, "from": {{"deg": [60, -40, -30]}}, "to": {{"deg": [0, -30, -30]}}, "duration_s": 20}}"#),
    )
    .await;
    let job = wait_status(&router, path, "done").await;
    assert_eq!(job["report"]["found"], true, "{job}");
    let after = get(&router, "/state").await;
    assert_ne!(integers(&before["steps"]), integers(&after["steps"]));
    let q: Vec<f64> = after["q_deg"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for (got, want) in q.iter().zip([0.0, -30.0, -30.0]) {
        assert!((got - want).abs() < 0.05, "at {q:?}");
    }
    let (status, _) = call(&router, "GET", &format!("/jobs/{path}"), None, None).await;
    assert!(status.is_success());
}

#[tokio::test(flavor = "multi_thread")]
async fn a_plan_job_drives_every_motion_of_its_task_file_in_turn() {
    let dir = scratch("plan");
    let service = open(&config("planar3", &dir, 100.0));
    let router = service.router();
    let task = serde_json::to_string(include_str!("../../../../examples/drive_planar3.toml")).unwrap();
    let id = submit(&router, &format!(r#"{{"kind": "plan", "task": {task}}}"#)).await;
    let job = wait_status(&router, id, "done").await;
    // 10 + 12 + 16 s of motion in 50 ms segments.
    assert_eq!(job["segments"], 760, "{job}");
    assert_eq!(job["report"]["motions"].as_array().map(Vec::len), Some(3));
    assert_eq!(integers(&get(&router, "/state").await["steps"]), vec![0, 0, 0], "back home");
}

#[tokio::test(flavor = "multi_thread")]
async fn an_obstacle_added_at_run_time_refuses_the_moves_through_it() {
    let dir = scratch("obstacle");
    let service = open(&config("planar3", &dir, 50.0));
    let router = service.router();
    let to_start = submit(&router, r#"{"kind": "move", "to_deg": [60, -40, -30], "duration_s": 10}"#).await;
    wait_status(&router, to_start, "done").await;
    // The library's scene check names what is wrong.
    let (status, reply) =
        call(&router, "POST", "/scene/obstacles", Some(r#"{"name": "post", "shape": "capsule", "radius": -1}"#), None)
            .await;
    assert_eq!(status, axum::http::StatusCode::BAD_REQUEST, "{reply}");
    assert!(reply["error"].as_str().unwrap_or_default().contains("post"), "{reply}");
    // The service keeps no clock for obstacles: one that moves is refused, named.
    let moving = r#"{"name": "ball", "shape": "sphere", "center": [2, 0, 0], "radius": 0.1, "velocity": [0, 0.1, 0]}"#;
    let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(moving), None).await;
    assert_eq!(status, axum::http::StatusCode::BAD_REQUEST, "{reply}");
    assert!(reply["error"].as_str().unwrap_or_default().contains("`ball` moves"), "{reply}");
    // The post of examples/path_planar3_post.toml (metres).
    let post =
        r#"{"name": "post", "shape": "capsule", "a": [2.68, -0.16, -0.5], "b": [2.68, -0.16, 0.5], "radius": 0.15}"#;
    let (status, reply) = call(&router, "POST", "/scene/obstacles", Some(post), None).await;
    assert_eq!((status, reply["obstacles"].as_i64()), (axum::http::StatusCode::CREATED, Some(1)), "{reply}");
    let blocked = submit(&router, r#"{"kind": "move", "to_deg": [0, -30, -30], "duration_s": 10}"#).await;
    let job = wait_status(&router, blocked, "refused").await;
    assert!(job["message"].as_str().unwrap_or_default().contains("`post`"), "{job}");
    // Kept across a restart.
    drop(router);
    service.shutdown();
    let service = open(&config("planar3", &dir, 50.0));
    let router = service.router();
    let again = submit(&router, r#"{"kind": "move", "to_deg": [0, -30, -30], "duration_s": 10}"#).await;
    wait_status(&router, again, "refused").await;
}

/// `POST /sense`: two range readings of a point that link 3 passes on the straight move
/// (60, −40, −30)° → (0, −30, −30)° locate it (the library's sense report); the located
/// obstacle joins the scene and the move through it is refused. Ambiguous readings add nothing.
#[tokio::test(flavor = "multi_thread")]
async fn sensed_obstacles_join_the_scene() {
    use serde_json::json;
    let dir = scratch("sense");
    let service = open(&config("planar3", &dir, 50.0));
    let router = service.router();
    let to_start = submit(&router, r#"{"kind": "move", "to_deg": [60, -40, -30], "duration_s": 10}"#).await;
    wait_status(&router, to_start, "done").await;
    // The tool point halfway through the move: on link 3 at that moment.
    let robot = reach::model::presets::get("planar3").unwrap();
    let mid = robot.fk(&[30f64.to_radians(), (-35f64).to_radians(), (-30f64).to_radians()]).unwrap();
    let h = [mid.translation.x, mid.translation.y];
    let reading = |s: [f64; 2]| {
        let d = [h[0] - s[0], h[1] - s[1]];
        json!({"xy_m": s, "dir_deg": d[1].atan2(d[0]).to_degrees(), "range_m": d[0].hypot(d[1])})
    };
    let body = json!({"sensors": [reading([0.5, -0.5]), reading([3.0, -0.5])], "sigma_m": 0.01}).to_string();
    let (status, reply) = call(&router, "POST", "/sense", Some(&body), None).await;
    assert_eq!(status, axum::http::StatusCode::OK, "{reply}");
    assert_eq!((reply["added"].as_bool(), reply["obstacles"].as_i64()), (Some(true), Some(1)), "{reply}");
    let located = &reply["report"]["obstacle_m"];
    assert!((located[0].as_f64().unwrap() - h[0]).hypot(located[1].as_f64().unwrap() - h[1]) < 1e-6, "{reply}");
    let blocked = submit(&router, r#"{"kind": "move", "to_deg": [0, -30, -30], "duration_s": 10}"#).await;
    let job = wait_status(&router, blocked, "refused").await;
    assert!(job["message"].as_str().unwrap_or_default().contains("sensed"), "{job}");
    // Two sensors facing each other: both mirror points fit; nothing is added.
    let face =
        |x: f64, dir: f64| json!({"xy_m": [x, 0.0], "dir_deg": dir, "range_m": 0.5f64.hypot(0.2), "cone_deg": 60.0});
    let body = json!({"sensors": [face(0.0, 0.0), face(1.0, 180.0)]}).to_string();
    let (status, reply) = call(&router, "POST", "/sense", Some(&body), None).await;
    assert_eq!((status, reply["added"].as_bool()), (axum::http::StatusCode::OK, Some(false)), "{reply}");
    assert_eq!(reply["report"]["ambiguous"], true);
    // Bad readings: the library's message.
    let (status, reply) = call(&router, "POST", "/sense", Some(r#"{"sensors": []}"#), None).await;
    assert_eq!(status, axum::http::StatusCode::BAD_REQUEST, "{reply}");
}

/// Seed 000 §4.5: an obstacle joins the scene while a move executes. One away from the rest of
/// the motion changes nothing (every segment still runs, once); the post on the rest of the
/// motion makes the arm stop along its path and drive a detour, planned around the post by the
/// library's planner, to the move's goal.
#[tokio::test(flavor = "multi_thread")]
async fn an_obstacle_on_the_rest_of_the_motion_makes_a_detour_to_the_goal() {
    use crate::common::wait_job;
    let dir = scratch("detour");
    let service = open(&config("planar3", &dir, 5.0));
    let router = service.router();
    let to_start = submit(&router, r#"{"kind": "move", "to_deg": [60, -40, -30], "duration_s": 10}"#).await;
    wait_status(&router, to_start, "done").await;
    let far = r#"{"name": "far", "shape": "sphere", "center": [-3, -3, 0], "radius": 0.2}"#;
    let post =
        r#"{"name": "post", "shape": "capsule", "a": [2.68, -0.16, -0.5], "b": [2.68, -0.16, 0.5], "radius": 0.15}"#;
    // Far away: the move goes on where it was.
    let on = submit(&router, r#"{"kind": "move", "to_deg": [30, -40, -30], "duration_s": 5}"#).await;
    wait_job(&router, on, "moving", |j| j["segment"].as_i64().unwrap_or(0) >= 10).await;
    let (status, _) = call(&router, "POST", "/scene/obstacles", Some(far), None).await;
    assert_eq!(status, axum::http::StatusCode::CREATED);
    let job = wait_status(&router, on, "done").await;
    assert_eq!((job["segment"].as_i64(), job["segments"].as_i64()), (Some(100), Some(100)), "{job}");
    assert!(job["message"].is_null(), "{job}");
    let back = submit(&router, r#"{"kind": "move", "to_deg": [60, -40, -30], "duration_s": 5}"#).await;
    wait_status(&router, back, "done").await;
    // The post, on the rest of the swing: stop, detour, goal.
    let swing = submit(&router, r#"{"kind": "move", "to_deg": [0, -30, -30], "duration_s": 10}"#).await;
    wait_job(&router, swing, "moving", |j| j["segment"].as_i64().unwrap_or(0) >= 10).await;
    let (status, _) = call(&router, "POST", "/scene/obstacles", Some(post), None).await;
    assert_eq!(status, axum::http::StatusCode::CREATED);
    let job = wait_status(&router, swing, "done").await;
    let message = job["message"].as_str().unwrap_or_default();
    assert!(message.contains("`post`") && message.contains("detour around it to the goal"), "{message}");
    assert!(job["segment"].as_i64().unwrap() < 200, "the straight swing was left: {job}");
    let q: Vec<f64> =
        get(&router, "/state").await["q_deg"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for (got, want) in q.iter().zip([0.0, -30.0, -30.0]) {
        assert!((got - want).abs() < 0.05, "at the goal: {q:?}");
    }
}

/// A ball on the log loader's straight swing from (0, 0, 0)° to (90, 0, 0)°.
const LOG_LOADER_BALL: &str = include_str!("../../../../examples/log_loader_ball.toml");

/// The step counts the service commits at the end of every segment of `job`'s motion: its
/// own rule (`reach_serve::schedule`) on the stored request and report.
fn committed_counts(robot: &reach::Robot, job: &serde_json::Value) -> Vec<Vec<i64>> {
    use reach_serve::schedule::{Timeline, drive, motion_of};
    let request: reach::jobs::Request = serde_json::from_value(job["request"].clone()).expect("a request");
    let report = match &request {
        reach::jobs::Request::Path(_) => {
            reach::jobs::Report::Path(serde_json::from_value(job["report"].clone()).expect("a path report"))
        }
        reach::jobs::Request::Approach(_) => {
            reach::jobs::Report::Approach(serde_json::from_value(job["report"].clone()).expect("an approach report"))
        }
        other => panic!("not a path or approach job: {other:?}"),
    };
    let motion = motion_of(robot, &request, &report).unwrap().expect("a motion");
    let timeline = Timeline::of(&drive(robot, motion).unwrap());
    assert_eq!(job["segments"].as_i64(), Some(timeline.segments()), "{job}");
    (0..=timeline.segments()).map(|k| timeline.steps_at(timeline.segment_end(k))).collect()
}

/// Issue 33: seed 000's log loader, whose only limits are its stepper drives (500 Hz and
/// 2000 steps/s² at 33.3 steps per degree: 15°/s, 60°/s²), runs a path job timed
/// time-optimally with blended corners and an approach job timed the same way; the step counts
/// committed every 50 ms stay within the motors' rate and ramp.
#[tokio::test(flavor = "multi_thread")]
async fn blended_path_and_approach_jobs_stay_within_the_motor_limits() {
    let dir = scratch("motor-limits");
    let service = open(&config("log-loader", &dir, 20.0));
    let router = service.router();
    let robot = reach::model::presets::get("log-loader").unwrap();
    let scene = serde_json::to_string(LOG_LOADER_BALL).unwrap();
    let path = submit(
        &router,
        &format!(r#"{{"kind": "path", "scene": {scene}, "from": {{"deg": [0, 0, 0]}}, "to": {{"deg": [90, 0, 0]}}}}"#),
    )
    .await;
    let path = wait_status(&router, path, "done").await;
    let report = &path["report"];
    assert_eq!(
        (report["timing"].as_str(), report["collision_free"].as_bool()),
        (Some("optimal"), Some(true)),
        "{path}"
    );
    assert!(report["blend_tolerance"].as_f64().unwrap() > 0.0, "the corners are blended: {report}");
    assert!(report["waypoints_deg"].as_array().unwrap().len() > 2, "around the ball: {report}");
    let approach = submit(
        &router,
        &format!(
            r#"{{"kind": "approach", "scene": {scene}, "from": {{"deg": [90, 0, 0]}}, "to": {{"deg": [90, 60, -90]}}}}"#
        ),
    )
    .await;
    let approach = wait_status(&router, approach, "done").await;
    let report = &approach["report"];
    assert_eq!(
        (report["timing"].as_str(), report["collision_free"].as_bool()),
        (Some("optimal"), Some(true)),
        "{approach}"
    );
    // 33.3 steps per degree: the end, as committed.
    let end = integers(&get(&router, "/state").await["steps"]);
    assert_eq!(end, vec![3000, 2000, -3000]);
    let segment = reach_serve::schedule::SEGMENT_S;
    for job in [&path, &approach] {
        let counts = committed_counts(&robot, job);
        for (j, joint) in robot.joints().iter().enumerate() {
            let drive = joint.drive.as_ref().unwrap();
            let at = |k: usize| counts[k][j];
            // Quantisation: a count is within half a step of the exact motion, so one
            // segment's difference carries at most one step more, a change of two at most two.
            let max_steps = drive.max_step_rate * segment + 1.0;
            let max_change = drive.max_acceleration.unwrap() * segment * segment + 2.0;
            for k in 1..counts.len() {
                let steps = (at(k) - at(k - 1)) as f64;
                assert!(steps.abs() <= max_steps, "joint {}: {steps} steps in segment {k}", j + 1);
                if k >= 2 {
                    let change = steps - (at(k - 1) - at(k - 2)) as f64;
                    assert!(change.abs() <= max_change, "joint {}: rate change {change} steps at segment {k}", j + 1);
                }
            }
        }
        // The motion runs at the motors' limits: the fastest segment is within a step of the
        // rate limit.
        let fastest = counts.windows(2).flat_map(|w| w[1].iter().zip(&w[0]).map(|(b, a)| (b - a).abs())).max();
        assert!(fastest >= Some(24), "{fastest:?} steps per 50 ms at most: not at the 500 Hz limit");
    }
    assert_eq!(committed_counts(&robot, &approach).last(), Some(&end));
}
