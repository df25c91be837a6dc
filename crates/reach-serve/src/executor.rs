//! The executor thread: takes queued jobs in order, asks the operator where a job leaves a
//! choice of configuration (seed 003's dialogue), schedules each job with the library's drive
//! workflow, plays the schedule on the simulated motors in real time (or `--speed` times
//! faster) and commits the joint state at every segment boundary (at most 50 ms of motion
//! apart); handles `POST /stop` (a deceleration along the planned path) and `POST /estop`
//! (halt now).

use std::sync::Arc;
use std::time::{Duration, Instant};

use reach::jobs::drive::DriveMotion;
use reach::jobs::input::{MotionSample, q_display};
use reach::jobs::{Report, Request};
use serde_json::{Value, json};

use crate::db::{JobCommit, JobRow, JobStatus};
use crate::intake;
use crate::schedule::{self, SEGMENT_S, Timeline};
use crate::service::{Control, Motion, Shared, TICK, lock};

/// Runs jobs until the service shuts down. A job that fails (an internal error) pauses the
/// queue, like a stop: the jobs behind it were planned for the arm where it would have ended.
pub fn run(shared: &Arc<Shared>) {
    while let Some(job) = next_job(shared) {
        let outcome = run_job(shared, &job);
        if let Err(message) = outcome {
            let note = format!("{message}; the queue is paused until POST /resume");
            lock(&shared.live).paused = true;
            let _ = lock(&shared.db).set_paused(true);
            finish(shared, job.id, JobStatus::Failed, Some(&note));
        }
        release(shared);
        shared.publish_state(&lock(&shared.live));
    }
}

/// Waits for the oldest job queued (or waiting for its operator) while the queue is not
/// paused; `None` on shutdown.
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

/// Frees the executor when `status` ends the job (`GET /state` no longer shows it, so a client
/// that sees the job end sees the service idle or stopped) and tells the WebSocket clients.
fn announce(shared: &Shared, id: i64, status: JobStatus, message: Option<&str>) {
    if status.is_final() {
        release(shared);
    }
    shared.job_event(id, status, message);
}

/// Sets a job's status in the journal (a final one after freeing the executor, as
/// [`announce`] says why) and tells the WebSocket clients.
fn finish(shared: &Shared, id: i64, status: JobStatus, message: Option<&str>) {
    if status.is_final() {
        release(shared);
    }
    let _ = lock(&shared.db).set_job(id, status, message, None);
    shared.job_event(id, status, message);
}

/// The executor holds no job.
fn release(shared: &Shared) {
    let mut live = lock(&shared.live);
    live.job = None;
    live.control = None;
    live.waiting = false;
}

/// A job's request and report as stored.
fn stored(job: &JobRow) -> Result<(Request, Report), String> {
    let request = serde_json::from_value(job.request.clone()).map_err(|e| format!("stored request: {e}"))?;
    let report =
        serde_json::from_value(job.report.clone().unwrap_or_default()).map_err(|e| format!("stored report: {e}"))?;
    Ok((request, report))
}

/// Schedules and plays one job. `Err`: an internal failure (the job is marked `failed`).
fn run_job(shared: &Arc<Shared>, job: &JobRow) -> Result<(), String> {
    let robot = &shared.robot;
    let (mut request, mut report) = stored(job)?;
    if job.from_current {
        // Re-planned from where the arm is now.
        finish(shared, job.id, JobStatus::Planning, None);
        let q = shared.q_deg(&lock(&shared.live).steps);
        request = intake::start_here(&request, &q);
        report = match intake::plan(robot, &request) {
            Ok(r) => r,
            Err(e) => {
                finish(shared, job.id, JobStatus::Refused, Some(&e.message));
                return Ok(());
            }
        };
        let (rq, rp) =
            (serde_json::to_value(&request).unwrap_or_default(), serde_json::to_value(&report).unwrap_or_default());
        lock(&shared.db).set_plan(job.id, &rq, &rp).map_err(|e| e.to_string())?;
        if let Some(why) = intake::refusal(&report) {
            finish(shared, job.id, JobStatus::Refused, Some(&why));
            return Ok(());
        }
    }
    let Some((request, report)) = ask_operator(shared, job.id, request, report)? else {
        return Ok(());
    };
    finish(shared, job.id, JobStatus::Planning, None);
    let Some(motion) = schedule::motion_of(robot, &request, &report)? else {
        let note = format!("planned only: a `{}` report holds no joint motion to drive", job.kind);
        finish(shared, job.id, JobStatus::Done, Some(&note));
        return Ok(());
    };
    if let Some(scene) = crate::service::scene(shared)
        && let Err(why) = schedule::require_clear(robot, &scene, &motion)
    {
        finish(shared, job.id, JobStatus::Refused, Some(&why));
        return Ok(());
    }
    let samples = match &motion {
        DriveMotion::Samples(samples) => samples.clone(),
        _ => Vec::new(),
    };
    let timeline = match schedule::drive(robot, motion) {
        Ok(drive) => Arc::new(Timeline::of(&drive)),
        Err(why) => {
            finish(shared, job.id, JobStatus::Refused, Some(&why));
            return Ok(());
        }
    };
    let steps = lock(&shared.live).steps.clone();
    if let Err(why) = schedule::require_start(robot, &shared.axes, &timeline, &steps) {
        finish(shared, job.id, JobStatus::Refused, Some(&why));
        return Ok(());
    }
    lock(&shared.db)
        .set_job(job.id, JobStatus::Executing, None, Some(timeline.segments()))
        .map_err(|e| e.to_string())?;
    shared.job_event(job.id, JobStatus::Executing, None);
    let events = k_events(&report, timeline.start_s);
    let (mut timeline, mut samples, mut playing, mut from_t) = (timeline, samples, Playing::Job(&events), 0.0);
    loop {
        match play(shared, job.id, &timeline, &playing, from_t)? {
            Played::Done => announce(shared, job.id, JobStatus::Done, None),
            Played::Shutdown => {} // left `executing`: the next start marks it `interrupted`
            Played::Control(control, t) => stop(shared, job.id, &timeline, control, t)?,
            Played::SceneChanged(t) => match replan(shared, job.id, &timeline, &samples, t)? {
                Replanned::Clear => {
                    from_t = t;
                    continue;
                }
                Replanned::Detour(detour, path) => {
                    (timeline, samples, playing, from_t) = (detour, path, Playing::Detour, 0.0);
                    continue;
                }
                Replanned::Ended => {}
            },
        }
        break;
    }
    Ok(())
}

/// Ends the job after `POST /stop` or `POST /estop` at time `t` of `timeline`: an estop halts
/// at once, a stop decelerates along the path ([`stop_ramp`]); the position reached and the
/// job's `stopped` are committed together.
fn stop(shared: &Shared, id: i64, timeline: &Arc<Timeline>, control: Control, t: f64) -> Result<(), String> {
    let k = ((t / SEGMENT_S).floor() as i64).min(timeline.segments());
    let mut message = format!(
        "stopped by POST /{} at t = {t:.3} s of {:.3} s (after segment {k} of {})",
        if control == Control::Stop { "stop" } else { "estop" },
        timeline.duration_s,
        timeline.segments()
    );
    let at = match control {
        Control::Estop => timeline.steps_at(t),
        Control::Stop => brake(shared, id, timeline, t, &mut message)?.0,
    };
    halt(shared, id, &at, Some(&message))
}

/// Decelerates along the path from time `t` of `timeline` ([`stop_ramp`]) and returns the
/// counters where the arm came to rest (or where a second stop or estop halted it, or at `t`
/// when there is no deceleration), and whether a stop or estop cut the deceleration short;
/// says how in `message`.
fn brake(
    shared: &Shared,
    id: i64,
    timeline: &Timeline,
    t: f64,
    message: &mut String,
) -> Result<(Vec<i64>, bool), String> {
    Ok(match stop_ramp(shared, timeline, t) {
        Ok(Some(ramp)) => {
            let ramp = Arc::new(ramp);
            match play(shared, id, &ramp, &Playing::Braking, 0.0)? {
                Played::Control(_, t2) => {
                    message.push_str(&format!("; halted {t2:.3} s into the deceleration"));
                    (ramp.steps_at(t2), true)
                }
                _ => {
                    message
                        .push_str(&format!("; decelerated to rest along the planned path in {:.3} s", ramp.duration_s));
                    (ramp.steps_at(ramp.duration_s), false)
                }
            }
        }
        Ok(None) => (timeline.steps_at(t), false),
        Err(why) => {
            message.push_str(&format!("; halted at once: no deceleration ({why})"));
            (timeline.steps_at(t), false)
        }
    })
}

/// What [`replan`] decided.
enum Replanned {
    /// The rest of the motion is proven clear of the new scene: go on.
    Clear,
    /// The arm stopped; this detour (its schedule and samples) leads to the motion's goal.
    Detour(Arc<Timeline>, Vec<MotionSample>),
    /// The job has ended (stopped: no detour, or a stop during the deceleration).
    Ended,
}

/// An obstacle joined the scene at time `t` of the job's `timeline` (seed 000 §4.5: the range
/// finders see an obstacle, the system plans a detour). The rest of the motion (`samples`, the
/// job's joint motion, from the position now) is checked with the library's swept check; when
/// it is not proven clear, the arm decelerates along its path (itself proven clear, else it
/// halts at once), the library's planner (`path` workflow) plans a collision-free path from
/// there to the motion's goal in the new scene, and the drive workflow schedules it. Without a
/// detour the job ends `stopped` and the queue pauses (the jobs behind it start at its goal).
///
/// # Errors
/// An internal failure (the database).
fn replan(
    shared: &Shared,
    id: i64,
    timeline: &Arc<Timeline>,
    samples: &[MotionSample],
    t: f64,
) -> Result<Replanned, String> {
    let Some(scene) = crate::service::scene(shared) else { return Ok(Replanned::Clear) };
    let robot = &shared.robot;
    let why = if samples.is_empty() {
        "the rest of a plan job cannot be proven clear of it".to_string()
    } else {
        let now =
            MotionSample { t_s: timeline.start_s + t, q_deg: q_display(robot, &timeline.values_at(&shared.axes, t)) };
        let rest: Vec<MotionSample> =
            std::iter::once(now).chain(samples.iter().filter(|s| s.t_s > timeline.start_s + t).cloned()).collect();
        match schedule::require_clear(robot, &scene, &DriveMotion::Samples(rest)) {
            Ok(()) => return Ok(Replanned::Clear),
            Err(why) => why,
        }
    };
    let mut message = format!("an obstacle joined the scene at t = {t:.3} s: {why}; stopping");
    let (at, cut_short) = brake(shared, id, timeline, t, &mut message)?;
    if cut_short {
        // A stop or estop during the deceleration: the operator ends the job.
        halt(shared, id, &at, Some(&message))?;
        return Ok(Replanned::Ended);
    }
    halt(shared, id, &at, None)?;
    let scene_text = lock(&shared.db).scene().map_err(|e| e.to_string())?.unwrap_or_default();
    let goal = samples.last().ok_or_else(|| "a plan job's goal is not one configuration".to_string());
    let request = goal.map(|goal| {
        reach::jobs::Request::Path(reach::jobs::world::PathRequest {
            scene: scene_text,
            from: reach::jobs::Joints::Deg(shared.q_deg(&at)),
            to: Some(reach::jobs::Joints::Deg(goal.q_deg.clone())),
            to_pose: None,
            seed: 1,
            time_budget_s: DETOUR_BUDGET_S,
            // At the job's pace; slowed when a motor would be too fast.
            duration_s: Some(timeline.duration_s),
            timing: None,
            max_velocity_scale: 1.0,
            max_acceleration_scale: 1.0,
            blend_tolerance: None,
        })
    });
    let detour = request.and_then(|request| {
        let report = intake::plan(robot, &request).map_err(|e| e.message)?;
        if let Some(why) = intake::refusal(&report) {
            return Err(why);
        }
        let motion = schedule::motion_of(robot, &request, &report)?.ok_or("the detour holds no motion")?;
        let DriveMotion::Samples(path) = motion else { return Err("the detour is not a joint motion".into()) };
        let (drive, path) = schedule::drive_slowed(robot, path)?;
        let timeline = Arc::new(Timeline::of(&drive));
        schedule::require_start(robot, &shared.axes, &timeline, &at)?;
        Ok((timeline, path, report))
    });
    match detour {
        Ok((timeline, path, report)) => {
            let Report::Path(p) = &report else { return Err("the detour is not a path".into()) };
            message.push_str(&format!(
                "; detour around it to the goal: {} waypoints, {:.3} s",
                p.waypoints_deg.len(),
                timeline.duration_s
            ));
            let _ = lock(&shared.db).set_job(id, JobStatus::Executing, Some(&message), None);
            shared.job_event_with(id, JobStatus::Executing, Some(&message), json!({"detour": report}));
            Ok(Replanned::Detour(timeline, path))
        }
        Err(why) => {
            message.push_str(&format!("; no detour to the goal ({why}); the queue is paused until POST /resume"));
            lock(&shared.live).paused = true;
            let _ = lock(&shared.db).set_paused(true);
            halt(shared, id, &at, Some(&message))?;
            Ok(Replanned::Ended)
        }
    }
}

/// Wall-time budget of the planner for a detour, seconds.
const DETOUR_BUDGET_S: f64 = 2.0;

/// Seed 003's dialogue. When the plan leaves the operator a choice of configuration
/// ([`intake::questions`]), the job waits (`waiting_operator`, `GET /state` says `waiting`)
/// for `POST /jobs/{id}/choose` for at most the configured timeout; then the configured
/// criterion answers (or, without one, the default configuration stands). Returns the request
/// and report to execute; `None` when the job is not to run now: a stop, an estop or a
/// shutdown came first (the job keeps waiting and asks again once the queue resumes), or the
/// criterion's plan is refused.
///
/// # Errors
/// An internal failure (a stored plan that cannot be read, the database).
fn ask_operator(
    shared: &Shared,
    id: i64,
    request: Request,
    report: Report,
) -> Result<Option<(Request, Report)>, String> {
    let questions = intake::questions(&request, &report);
    if questions.is_empty() {
        return Ok(Some((request, report)));
    }
    let timeout = shared.operator_timeout;
    let deadline = Instant::now() + timeout;
    let deadline_ms = crate::db::now_ms() + i64::try_from(timeout.as_millis()).unwrap_or(i64::MAX);
    let message = format!(
        "several configurations are feasible in interval(s) {}: POST /jobs/{id}/choose within {:.0} s",
        questions.iter().map(|q| q.interval.to_string()).collect::<Vec<_>>().join(", "),
        timeout.as_secs_f64()
    );
    lock(&shared.db).set_job(id, JobStatus::WaitingOperator, Some(&message), None).map_err(|e| e.to_string())?;
    lock(&shared.live).waiting = true;
    shared.job_event_with(
        id,
        JobStatus::WaitingOperator,
        Some(&message),
        json!({"questions": questions, "deadline_ms": deadline_ms}),
    );
    loop {
        let mut live = lock(&shared.live);
        if live.shutdown || live.control.take().is_some() {
            live.waiting = false;
            return Ok(None);
        }
        let row = lock(&shared.db).job(id).map_err(|e| e.to_string())?.ok_or("the job vanished")?;
        if row.status == JobStatus::Queued {
            live.waiting = false;
            return stored(&row).map(Some);
        }
        let now = Instant::now();
        if now >= deadline {
            live.waiting = false;
            break;
        }
        let pause = (deadline - now).min(Duration::from_millis(200));
        drop(shared.wake.wait_timeout(live, pause).map_or_else(|e| e.into_inner().0, |r| r.0));
    }
    let waited = format!("no answer within {:.0} s", timeout.as_secs_f64());
    let (request, report, note) = match &shared.operator_criterion {
        Some(criterion) => {
            let request = intake::with_criterion(&request, criterion);
            match intake::plan(&shared.robot, &request) {
                Ok(report) => {
                    let note = format!("{waited}: the criterion ({}) chose", criterion.method);
                    (request, report, note)
                }
                Err(e) => {
                    finish(shared, id, JobStatus::Refused, Some(&format!("{waited}; the criterion: {}", e.message)));
                    return Ok(None);
                }
            }
        }
        None => (request, report, format!("{waited}: the default configuration stands")),
    };
    if let Some(why) = intake::refusal(&report) {
        finish(shared, id, JobStatus::Refused, Some(&format!("{note}, but {why}")));
        return Ok(None);
    }
    let (rq, rp) =
        (serde_json::to_value(&request).unwrap_or_default(), serde_json::to_value(&report).unwrap_or_default());
    let db = lock(&shared.db);
    if !db.answer(id, &rq, &rp, &note).map_err(|e| e.to_string())? {
        // The operator answered in the meantime: the answer wins.
        let row = db.job(id).map_err(|e| e.to_string())?.ok_or("the job vanished")?;
        return stored(&row).map(Some);
    }
    drop(db);
    shared.job_event(id, JobStatus::Queued, Some(&note));
    Ok(Some((request, report)))
}

/// The K-events of a move's report as WebSocket messages, by their time from the schedule's
/// start (`start_s`: the schedule's start in the report's time).
fn k_events(report: &Report, start_s: f64) -> Vec<(f64, Value)> {
    let Report::Move(m) = report else { return Vec::new() };
    m.events
        .iter()
        .map(|e| {
            (
                e.t_s - start_s,
                json!({"type": "event", "code": e.code, "t_s": e.t_s, "message": e.message, "detail": e.detail}),
            )
        })
        .collect()
}

/// What a schedule being played is.
enum Playing<'a> {
    /// A job's schedule: each commit records its segment, the last one ends the job `done`;
    /// the job's K-events are sent as their time passes.
    Job(&'a [(f64, Value)]),
    /// A detour after an obstacle joined the scene: the last commit ends the job `done`.
    Detour,
    /// A deceleration: commits move the counters only.
    Braking,
}

/// How playing a schedule ended.
enum Played {
    /// Every segment executed and committed.
    Done,
    /// A stop or emergency stop at this time (seconds from the schedule's start).
    Control(Control, f64),
    /// An obstacle joined the scene at this time (a job or a detour only).
    SceneChanged(f64),
    /// The service shuts down.
    Shutdown,
}

/// Plays `timeline` on the simulated motors: waits for each segment's end (scaled by the
/// speed) and commits the counters at the boundary in one transaction (with a job's segment;
/// the last commit of a job also sets it `done`). The joint states between commits are
/// published by [`publish`], so their rate does not depend on the disk.
fn play(
    shared: &Shared,
    job: i64,
    timeline: &Arc<Timeline>,
    playing: &Playing<'_>,
    from_t: f64,
) -> Result<Played, String> {
    // Started `from_t` seconds (of schedule time) ago: a schedule resumed after a re-check.
    let start = Instant::now().checked_sub(Duration::from_secs_f64(from_t / shared.speed)).unwrap_or_else(Instant::now);
    lock(&shared.live).motion = Some(Motion { timeline: timeline.clone(), start });
    let played = play_segments(shared, job, timeline, playing, start, from_t);
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
    playing: &Playing<'_>,
    start: Instant,
    from_t: f64,
) -> Result<Played, String> {
    let sim_time = |now: Instant| now.duration_since(start).as_secs_f64() * shared.speed;
    let segments = timeline.segments();
    let first = ((from_t / SEGMENT_S + 1e-9).floor() as i64 + 1).min(segments);
    for k in first..=segments {
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
            if !matches!(playing, Playing::Braking) && std::mem::take(&mut live.scene_changed) {
                return Ok(Played::SceneChanged(sim_time(Instant::now()).min(t_end)));
            }
            let now = Instant::now();
            if now >= due {
                break;
            }
            live = shared.wake.wait_timeout(live, due - now).map_or_else(|e| e.into_inner().0, |r| r.0);
        }
        let steps = timeline.steps_at(t_end);
        let segment = matches!(playing, Playing::Job(_)).then_some(k);
        if k == segments && !matches!(playing, Playing::Braking) {
            // The last commit ends the job: the executor is freed (see `announce`) and the state
            // updated while the commit is made, so a client that sees the job `done` sees the
            // state after it.
            live.job = None;
            live.steps.clone_from(&steps);
            let end = JobCommit { id: job, segment, end: Some((JobStatus::Done, None)) };
            live.last_commit = Some(lock(&shared.db).commit_steps(&steps, Some(end)).map_err(|e| e.to_string())?);
        } else {
            drop(live);
            let commit = JobCommit { id: job, segment, end: None };
            let commit = lock(&shared.db).commit_steps(&steps, Some(commit)).map_err(|e| e.to_string())?;
            lock(&shared.live).last_commit = Some(commit);
        }
        if let Playing::Job(events) = playing {
            let t_start = timeline.segment_end(k - 1);
            for (_, event) in events.iter().filter(|(t, _)| *t > t_start - 1e-9 && *t <= t_end + 1e-9) {
                shared.publish(event);
            }
        }
    }
    Ok(Played::Done)
}

/// Ticks between two joint-state messages while the arm is idle (1 s).
const IDLE_TICKS: u32 = 50;

/// The publisher thread: every [`TICK`] while a schedule plays, sets the motors' counters
/// from it and sends the joint state to WebSocket clients (≥ 50 Hz, whatever the disk does);
/// while the arm is idle, the joint state every [`IDLE_TICKS`] ticks (1 Hz), as a robot's
/// joint-state topic keeps publishing (a client counting states is never left waiting).
pub fn publish(shared: &Arc<Shared>) {
    let mut next = Instant::now();
    let mut idle = 0;
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
            idle = 0;
        } else {
            idle += 1;
            if idle >= IDLE_TICKS {
                shared.publish_state(&live);
                idle = 0;
            }
        }
    }
}

/// Commits `steps` now (the motors halt where they are); with `stopped`, ends the job
/// `stopped` with that message in the same transaction.
fn halt(shared: &Shared, job: i64, steps: &[i64], stopped: Option<&str>) -> Result<(), String> {
    // The state is updated while the commit is made (a client that sees the job `stopped` sees
    // the state after it).
    let mut live = lock(&shared.live);
    live.steps = steps.to_vec();
    if stopped.is_some() {
        live.job = None;
        live.control = None;
    }
    let end = stopped.map(|message| (JobStatus::Stopped, Some(message)));
    let commit = JobCommit { id: job, segment: None, end };
    live.last_commit = Some(lock(&shared.db).commit_steps(steps, Some(commit)).map_err(|e| e.to_string())?);
    shared.publish_state(&live);
    drop(live);
    if let Some(message) = stopped {
        announce(shared, job, JobStatus::Stopped, Some(message));
    }
    Ok(())
}

/// How much longer than the shortest deceleration a stop takes: the braking term uses at most
/// `1/m` of each motor's acceleration, the rest is left for the path's own acceleration (which
/// the warp scales down by the square of its rate).
const BRAKING_MARGIN: f64 = 1.5;

/// The controlled stop from time `t` of `timeline`: the arm slows down *along the planned
/// path*, so it never leaves the motion that was checked (limits, scene): the schedule is
/// replayed with the time warp `t(τ) = t + τ − τ²/(2T)`, `τ ∈ [0, T]`, whose rate `1 − τ/T`
/// falls linearly from 1 to 0 — every joint's velocity is the planned one times that rate,
/// and the braking term of its acceleration is `vᵢ/T`. `T = m·maxᵢ |vᵢ|/aᵢ` over the joints'
/// velocities now and their drives' `max_acceleration`, with the margin
/// `m =` [`BRAKING_MARGIN`] leaving room for the path's own acceleration. The warped samples (every 5 ms) are
/// scheduled by the drive workflow, which re-checks position and speed limits and the motors'
/// rates, and with a scene they are proven clear of it. `Ok(None)`: the arm is already at rest
/// (or no joint has an acceleration limit).
///
/// # Errors
/// Why there is no deceleration (the drive workflow's or the scene check's message).
fn stop_ramp(shared: &Shared, timeline: &Timeline, t: f64) -> Result<Option<Timeline>, String> {
    let h = SEGMENT_S.min(t);
    if h <= 0.0 {
        return Ok(None);
    }
    let (now, before) = (timeline.steps_at(t), timeline.steps_at(t - h));
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
        .fold(0.0, f64::max)
        * BRAKING_MARGIN;
    if duration < 1e-3 {
        return Ok(None);
    }
    let n = ((duration / 0.005).ceil() as usize).max(4);
    let samples: Vec<MotionSample> = (0..=n)
        .map(|j| {
            let tau = duration * j as f64 / n as f64;
            let warped = t + tau - tau * tau / (2.0 * duration);
            MotionSample { t_s: tau, q_deg: q_display(&shared.robot, &timeline.values_at(&shared.axes, warped)) }
        })
        .collect();
    let motion = DriveMotion::Samples(samples);
    if let Some(scene) = crate::service::scene(shared) {
        schedule::require_clear(&shared.robot, &scene, &motion)?;
    }
    schedule::drive(&shared.robot, motion).map(|d| Some(Timeline::of(&d)))
}
