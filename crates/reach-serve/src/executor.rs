//! The executor thread: takes queued jobs in order, schedules each with the library's drive
//! workflow, plays the schedule on the simulated motors in real time (or `--speed` times
//! faster) and commits the joint state at every segment boundary (at most 50 ms of motion
//! apart); handles `POST /stop` (a deceleration ramp) and `POST /estop` (halt now).

use std::sync::Arc;
use std::time::{Duration, Instant};

use reach::jobs::drive::DriveMotion;
use reach::jobs::input::MotionSample;
use reach::jobs::{Report, Request};
use reach::motion::Profile;

use crate::db::JobRow;
use crate::schedule::{self, SEGMENT_S, Timeline};
use crate::service::{Control, Motion, Shared, TICK, lock};

/// Runs jobs until the service shuts down.
pub fn run(shared: &Arc<Shared>) {
    while let Some(job) = next_job(shared) {
        let outcome = run_job(shared, &job);
        let mut live = lock(&shared.live);
        live.job = None;
        live.control = None;
        if let Err(message) = outcome {
            drop(live);
            finish(shared, job.id, "failed", Some(&message));
            live = lock(&shared.live);
        }
        shared.publish_state(&live);
    }
}

/// Waits for the oldest queued job while the queue is not paused; `None` on shutdown.
fn next_job(shared: &Shared) -> Option<JobRow> {
    let mut live = lock(&shared.live);
    loop {
        if live.shutdown {
            return None;
        }
        if !live.paused
            && let Ok(Some(job)) = lock(&shared.db).next_queued()
        {
            live.job = Some(job.id);
            return Some(job);
        }
        live = shared.wake.wait_timeout(live, Duration::from_millis(500)).map_or_else(|e| e.into_inner().0, |r| r.0);
    }
}

/// The statuses that end a job.
const FINAL: [&str; 5] = ["done", "refused", "failed", "stopped", "interrupted"];

/// Sets a job's status and tells the WebSocket clients. A final status first frees the
/// executor (`GET /state` no longer shows the job), so that a client that sees the job end
/// sees the service idle or stopped.
fn finish(shared: &Shared, id: i64, status: &str, message: Option<&str>) {
    if FINAL.contains(&status) {
        let mut live = lock(&shared.live);
        live.job = None;
        live.control = None;
    }
    let _ = lock(&shared.db).set_job(id, status, message, None);
    shared.job_event(id, status, message);
}

/// Schedules and plays one job. `Err`: an internal failure (the job is marked `failed`).
fn run_job(shared: &Arc<Shared>, job: &JobRow) -> Result<(), String> {
    finish(shared, job.id, "planning", None);
    let request: Request = serde_json::from_value(job.request.clone()).map_err(|e| format!("stored request: {e}"))?;
    let mut report: Report =
        serde_json::from_value(job.report.clone().unwrap_or_default()).map_err(|e| format!("stored report: {e}"))?;
    let robot = &shared.robot;
    let mut request = request;
    if job.from_current {
        // Re-planned from where the arm is now.
        let q = shared.q_deg(&lock(&shared.live).steps);
        request = crate::intake::start_here(&request, &q);
        report = match crate::intake::plan(robot, &request) {
            Ok(r) => r,
            Err(e) => {
                finish(shared, job.id, "refused", Some(&e.message));
                return Ok(());
            }
        };
        let (rq, rp) =
            (serde_json::to_value(&request).unwrap_or_default(), serde_json::to_value(&report).unwrap_or_default());
        lock(&shared.db).set_plan(job.id, &rq, &rp).map_err(|e| e.to_string())?;
        if let Some(why) = crate::intake::refusal(&report) {
            finish(shared, job.id, "refused", Some(&why));
            return Ok(());
        }
    }
    let Some(motion) = schedule::motion_of(robot, &request, &report)? else {
        let note = format!("planned only: a `{}` report holds no joint motion to drive", job.kind);
        finish(shared, job.id, "done", Some(&note));
        return Ok(());
    };
    if let Some(scene) = crate::service::scene(shared)
        && let Err(why) = schedule::require_clear(robot, &scene, &motion)
    {
        finish(shared, job.id, "refused", Some(&why));
        return Ok(());
    }
    let timeline = match schedule::drive(robot, motion) {
        Ok(drive) => Arc::new(Timeline::of(&drive)),
        Err(why) => {
            finish(shared, job.id, "refused", Some(&why));
            return Ok(());
        }
    };
    let steps = lock(&shared.live).steps.clone();
    if let Err(why) = schedule::require_start(robot, &shared.axes, &timeline, &steps) {
        finish(shared, job.id, "refused", Some(&why));
        return Ok(());
    }
    lock(&shared.db).set_job(job.id, "executing", None, Some(timeline.segments())).map_err(|e| e.to_string())?;
    shared.job_event(job.id, "executing", None);
    match play(shared, job.id, &timeline, true)? {
        Played::Done => finish(shared, job.id, "done", None),
        Played::Shutdown => {} // left `executing`: the next start marks it `interrupted`
        Played::Control(control, t) => {
            let k = ((t / SEGMENT_S).floor() as i64).min(timeline.segments());
            let mut message = format!(
                "stopped by POST /{} at t = {t:.3} s of {:.3} s (after segment {k} of {})",
                if control == Control::Stop { "stop" } else { "estop" },
                timeline.duration_s,
                timeline.segments()
            );
            match control {
                Control::Estop => halt(shared, job.id, &timeline.steps_at(t))?,
                Control::Stop => match stop_ramp(shared, &timeline, t) {
                    Ok(Some(ramp)) => {
                        let ramp = Arc::new(ramp);
                        message.push_str(&format!("; decelerated to rest in {:.3} s", ramp.duration_s));
                        if let Played::Control(..) = play(shared, job.id, &ramp, false)? {
                            halt(shared, job.id, &ramp.steps_at(ramp.duration_s))?;
                        }
                    }
                    Ok(None) => halt(shared, job.id, &timeline.steps_at(t))?,
                    Err(why) => {
                        message.push_str(&format!("; halted at once: no ramp ({why})"));
                        halt(shared, job.id, &timeline.steps_at(t))?;
                    }
                },
            }
            finish(shared, job.id, "stopped", Some(&message));
        }
    }
    Ok(())
}

/// How playing a schedule ended.
enum Played {
    /// Every segment executed and committed.
    Done,
    /// A stop or emergency stop at this time (seconds from the schedule's start).
    Control(Control, f64),
    /// The service shuts down.
    Shutdown,
}

/// Plays `timeline` on the simulated motors: waits for each segment's end (scaled by the
/// speed) and commits the counters at the boundary (and, when `count` is set, the job's
/// segment) in one transaction. The joint states between commits are published by
/// [`publish`], so their rate does not depend on the disk.
fn play(shared: &Shared, job: i64, timeline: &Arc<Timeline>, count: bool) -> Result<Played, String> {
    let start = Instant::now();
    lock(&shared.live).motion = Some(Motion { timeline: timeline.clone(), start });
    let played = play_segments(shared, job, timeline, count, start);
    let mut live = lock(&shared.live);
    live.motion = None;
    if let Ok(Played::Done) = played {
        live.steps = timeline.steps_at(timeline.duration_s);
    }
    shared.publish_state(&live);
    played
}

fn play_segments(
    shared: &Shared,
    job: i64,
    timeline: &Timeline,
    count: bool,
    start: Instant,
) -> Result<Played, String> {
    let sim_time = |now: Instant| now.duration_since(start).as_secs_f64() * shared.speed;
    for k in 1..=timeline.segments() {
        let t_end = timeline.segment_end(k);
        let due = start + Duration::from_secs_f64(t_end / shared.speed);
        let mut live = lock(&shared.live);
        loop {
            if live.shutdown {
                return Ok(Played::Shutdown);
            }
            if let Some(control) = live.control.take() {
                return Ok(Played::Control(control, sim_time(Instant::now()).min(t_end)));
            }
            let now = Instant::now();
            if now >= due {
                break;
            }
            live = shared.wake.wait_timeout(live, due - now).map_or_else(|e| e.into_inner().0, |r| r.0);
        }
        drop(live);
        let steps = timeline.steps_at(t_end);
        let commit =
            lock(&shared.db).commit_steps(&steps, Some((job, count.then_some(k)))).map_err(|e| e.to_string())?;
        lock(&shared.live).last_commit = Some(commit);
    }
    Ok(Played::Done)
}

/// The publisher thread: every [`TICK`] while a schedule plays, sets the motors' counters
/// from it and sends the joint state to WebSocket clients (≥ 50 Hz, whatever the disk does).
pub fn publish(shared: &Arc<Shared>) {
    let mut next = Instant::now();
    loop {
        next += TICK;
        let now = Instant::now();
        if next > now {
            std::thread::sleep(next - now);
        }
        let mut live = lock(&shared.live);
        if live.shutdown {
            return;
        }
        if let Some(motion) = live.motion.clone() {
            live.steps = motion.steps_now(shared.speed, motion.timeline.duration_s);
            shared.publish_state(&live);
        }
    }
}

/// Commits `steps` now (the motors halt where they are).
fn halt(shared: &Shared, job: i64, steps: &[i64]) -> Result<(), String> {
    let commit = lock(&shared.db).commit_steps(steps, Some((job, None))).map_err(|e| e.to_string())?;
    let mut live = lock(&shared.live);
    live.steps = steps.to_vec();
    live.last_commit = Some(commit);
    shared.publish_state(&live);
    Ok(())
}

/// The controlled stop from time `t` of `timeline`: every joint keeps its direction and slows
/// down at a constant rate to rest, all joints together, in the shortest time `T` the joints'
/// acceleration limits (their drives' `max_acceleration`) allow: `T = maxᵢ |vᵢ|/aᵢ`. The ramp
/// is the second half of the library's triangular profile (`λ` of a trapezoid with `f = ½`
/// from `τ = ½` to 1), scheduled by the drive workflow, which re-checks position limits.
/// `Ok(None)`: the arm is already at rest (or no joint has an acceleration limit).
///
/// # Errors
/// The drive workflow's message (e.g. a joint would pass its position limit while braking).
fn stop_ramp(shared: &Shared, timeline: &Timeline, t: f64) -> Result<Option<Timeline>, String> {
    let h = SEGMENT_S.min(t);
    if h <= 0.0 {
        return Ok(None);
    }
    let (now, before) = (timeline.steps_at(t), timeline.steps_at(t - h));
    let q_now: Vec<f64> = shared.axes.iter().zip(&now).map(|(a, &s)| a.joint_value(s)).collect();
    // Velocity over the last segment, joint units per second.
    let v: Vec<f64> = shared
        .axes
        .iter()
        .zip(now.iter().zip(&before))
        .map(|(a, (&n, &b))| (a.joint_value(n) - a.joint_value(b)) / h)
        .collect();
    let duration = shared
        .axes
        .iter()
        .zip(&v)
        .filter_map(|(a, vi)| a.max_acceleration.map(|acc| vi.abs() / (acc / a.steps_per_unit)))
        .fold(0.0, f64::max);
    if duration < 1e-3 {
        return Ok(None);
    }
    let ramp = Profile::Trapezoidal { accel_fraction: 0.5 };
    let n = ((duration / 0.005).ceil() as usize).max(4);
    let samples: Vec<MotionSample> = (0..=n)
        .map(|j| {
            let s = duration * j as f64 / n as f64;
            let lambda = ramp.position(0.5 + s / (2.0 * duration)) - 0.5;
            let q: Vec<f64> = q_now.iter().zip(&v).map(|(q0, vi)| q0 + vi * duration * lambda).collect();
            MotionSample { t_s: s, q_deg: reach::jobs::input::q_display(&shared.robot, &q) }
        })
        .collect();
    schedule::drive(&shared.robot, DriveMotion::Samples(samples)).map(|d| Some(Timeline::of(&d)))
}
