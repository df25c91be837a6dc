//! The running service: its configuration, the state shared by the HTTP handlers and the
//! executor thread, and the JSON of `GET /state`.

use std::net::SocketAddr;
use std::path::PathBuf;
use std::sync::{Arc, Condvar, Mutex, MutexGuard, RwLock};

use reach::Robot;
use reach::drive::{Axis, axes, with_simulated_drives};
use reach::jobs::RobotInput;
use reach::jobs::input::q_display;
use reach::world::Scene;
use serde_json::{Value, json};
use tokio::sync::broadcast;

use crate::db::{Db, JobStatus, LastCommit, Recovery};
use crate::error::ServeError;

/// Largest request body, bytes (larger ones get 413).
pub const MAX_BODY_BYTES: usize = 1 << 20;

/// Largest report a job may store, bytes of JSON (a longer one is refused with 400 before it
/// is stored: a move's samples are its bulk; a larger `dt_s` makes fewer).
pub const MAX_REPORT_BYTES: usize = 16 << 20;

/// Most obstacles the service's scene holds (`POST /scene/obstacles` beyond it gets 400;
/// `DELETE /scene/obstacles/{name}` makes room).
pub const MAX_OBSTACLES: usize = 1000;

/// Most plans computed at once; further submissions wait their turn.
pub const MAX_PLANNING: usize = 2;

/// Most jobs waiting in the queue (more get 409).
pub const MAX_QUEUED_JOBS: i64 = 10_000;

/// Interval between joint-state messages on the WebSocket while moving (50 Hz).
pub const TICK: std::time::Duration = std::time::Duration::from_millis(20);

/// How long a job waits for the operator by default, seconds.
pub const DEFAULT_OPERATOR_TIMEOUT_S: f64 = 60.0;

/// The longest operator timeout, seconds (a day).
pub const MAX_OPERATOR_TIMEOUT_S: f64 = 86_400.0;

/// How the service is started (`reach serve`'s options).
#[derive(Debug, Clone)]
pub struct Config {
    /// The robot (a preset, or the text of a description).
    pub robot: RobotInput,
    /// The text of a scene file: job motions must be proven clear of it.
    pub scene: Option<String>,
    /// The state directory (database, token).
    pub state_dir: PathBuf,
    /// The address to listen on; beyond loopback every request needs the token.
    pub listen: SocketAddr,
    /// Simulation speed: 1 = real time, 10 = ten times faster.
    pub speed: f64,
    /// An origin allowed to call the API from a browser (CORS); `None`: none.
    pub cors: Option<String>,
    /// How long a job waits for the operator's choice of configuration, seconds (seed 003's
    /// dialogue); then `operator_criterion` answers.
    pub operator_timeout_s: f64,
    /// What answers when the operator does not: a ranking of the feasible configurations;
    /// `None`: the default configuration stands (seed 003's `config=+β`).
    pub operator_criterion: Option<reach::jobs::motion::ChoiceSpec>,
}

impl Config {
    /// A configuration with the defaults: state in `./reach-state/`, loopback port 7878, real
    /// time, no scene, no CORS.
    #[must_use]
    pub fn new(robot: RobotInput) -> Self {
        Config {
            robot,
            scene: None,
            state_dir: PathBuf::from("reach-state"),
            listen: SocketAddr::from(([127, 0, 0, 1], 7878)),
            speed: 1.0,
            cors: None,
            operator_timeout_s: DEFAULT_OPERATOR_TIMEOUT_S,
            operator_criterion: None,
        }
    }
}

/// What the executor is asked to do with the running job.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Decelerate to rest within the joints' acceleration limits.
    Stop,
    /// Halt now.
    Estop,
}

/// The schedule the motors are playing.
#[derive(Debug, Clone)]
pub struct Motion {
    /// The schedule.
    pub timeline: Arc<crate::schedule::Timeline>,
    /// When it started (wall time).
    pub start: std::time::Instant,
}

impl Motion {
    /// The step counters now: the schedule at the simulated time (wall time × speed), at most
    /// `until` seconds into it.
    #[must_use]
    pub fn steps_now(&self, speed: f64, until: f64) -> Vec<i64> {
        self.timeline.steps_at((self.start.elapsed().as_secs_f64() * speed).min(until))
    }
}

/// The state that changes while the service runs (the durable part is in the database).
#[derive(Debug)]
pub struct Live {
    /// The motors' step counters now (between commits: simulated, not yet durable).
    pub steps: Vec<i64>,
    /// The job being planned or executed (or waiting for its operator).
    pub job: Option<i64>,
    /// Whether that job waits for the operator's choice.
    pub waiting: bool,
    /// An obstacle joined the scene while the job executes: the executor re-checks the rest of
    /// its motion.
    pub scene_changed: bool,
    /// Whether the queue waits for `POST /resume`.
    pub paused: bool,
    /// A stop asked for and not yet handled.
    pub control: Option<Control>,
    /// The schedule being played (the publisher reads the motors' position from it).
    pub motion: Option<Motion>,
    /// The last durable commit of the joint state.
    pub last_commit: Option<LastCommit>,
    /// Set when the service shuts down.
    pub shutdown: bool,
}

/// Everything the handlers and the executor share.
pub struct Shared {
    /// The robot, with simulated drives on joints that have none.
    pub robot: Robot,
    /// Its motor axes.
    pub axes: Vec<Axis>,
    /// Joints (0-based) driven by the default simulated motor.
    pub simulated: Vec<usize>,
    /// The scene motions must be proven clear of (obstacles may be added while running).
    pub scene: RwLock<Option<Scene>>,
    /// The state database.
    pub db: Mutex<Db>,
    /// The changing state; `wake` signals changes to the executor.
    pub live: Mutex<Live>,
    /// Wakes the executor (new job, stop, resume, shutdown).
    pub wake: Condvar,
    /// Messages for WebSocket clients (JSON text).
    pub events: broadcast::Sender<Arc<str>>,
    /// The bearer token every request must carry (`None` on loopback).
    pub token: Option<String>,
    /// An origin allowed by CORS.
    pub cors: Option<String>,
    /// Simulation speed factor.
    pub speed: f64,
    /// What opening the state found.
    pub recovery: Recovery,
    /// Plans being computed at once (`POST /jobs`, `POST /jobs/{id}/choose`): at most
    /// [`MAX_PLANNING`].
    pub planning: tokio::sync::Semaphore,
    /// How long a job waits for the operator.
    pub operator_timeout: std::time::Duration,
    /// What answers when the operator does not.
    pub operator_criterion: Option<reach::jobs::motion::ChoiceSpec>,
}

/// What a scene must be for the service to keep it (at start with `--scene`, and after every
/// obstacle added): fixed obstacles only ([`crate::api::FIXED_SCENE`]), every one within the
/// robot's workcell ([`reach::jobs::world::require_workcell`]), at most [`MAX_OBSTACLES`].
///
/// # Errors
/// The library's message, or the count against the cap.
pub fn require_keepable(robot: &Robot, scene: &Scene) -> Result<(), String> {
    scene.require_fixed(crate::api::FIXED_SCENE).map_err(|e| e.to_string())?;
    reach::jobs::world::require_workcell(robot, scene).map_err(|e| e.to_string())?;
    if scene.obstacles.len() > MAX_OBSTACLES {
        return Err(format!(
            "{} obstacles, the service keeps at most {MAX_OBSTACLES}; remove one first (DELETE /scene/obstacles/{{name}})",
            scene.obstacles.len()
        ));
    }
    Ok(())
}

/// The scene now (a copy).
#[must_use]
pub fn scene(shared: &Shared) -> Option<Scene> {
    shared.scene.read().unwrap_or_else(std::sync::PoisonError::into_inner).clone()
}

/// Locks a mutex, recovering the data if a thread panicked while holding it.
pub fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

impl Shared {
    /// Opens the state and builds the shared state (see [`crate::Service::open`]).
    ///
    /// # Errors
    /// [`ServeError`] for a bad robot or scene, a bad speed, or a state that cannot be opened.
    pub fn open(config: &Config) -> Result<Shared, ServeError> {
        if !(config.speed.is_finite() && config.speed > 0.0 && config.speed <= 1e6) {
            return Err(ServeError::Config(format!("--speed must be a number in (0, 1e6], got {}", config.speed)));
        }
        let timeout = config.operator_timeout_s;
        if !(timeout.is_finite() && (0.0..=MAX_OPERATOR_TIMEOUT_S).contains(&timeout)) {
            return Err(ServeError::Config(format!(
                "--operator-timeout must be a number of seconds in [0, {MAX_OPERATOR_TIMEOUT_S}], got {timeout}"
            )));
        }
        let loaded = config.robot.load()?;
        let (robot, simulated) = with_simulated_drives(&loaded.robot).map_err(reach::Error::from)?;
        let axes = axes(&robot).map_err(reach::Error::from)?;
        let names: Vec<String> = robot.joints().iter().map(|j| j.name.clone()).collect();
        let home: Vec<i64> = axes.iter().zip(robot.home()).map(|(a, q)| a.quantise(q)).collect();
        let robot_json = serde_json::to_string(&config.robot).map_err(|e| ServeError::Config(e.to_string()))?;
        if let Some(text) = &config.scene {
            let scene = reach::jobs::world::parse_scene(text)?;
            require_keepable(&robot, &scene).map_err(|e| ServeError::Config(format!("--scene: {e}")))?;
        }
        let (db, recovery) = Db::open(&config.state_dir, &robot_json, &names, &home, config.scene.as_deref())?;
        let scene = db.scene()?.map(|t| reach::jobs::world::parse_scene(&t)).transpose()?;
        let token = crate::auth::token(&config.state_dir)?;
        let token = (!config.listen.ip().is_loopback()).then_some(token);
        let live = Live {
            steps: db.steps()?,
            job: None,
            waiting: false,
            scene_changed: false,
            paused: db.paused()?,
            control: None,
            motion: None,
            last_commit: db.last_commit()?,
            shutdown: false,
        };
        Ok(Shared {
            robot,
            axes,
            simulated,
            scene: RwLock::new(scene),
            db: Mutex::new(db),
            live: Mutex::new(live),
            wake: Condvar::new(),
            events: broadcast::channel(1024).0,
            token,
            cors: config.cors.clone(),
            speed: config.speed,
            recovery,
            planning: tokio::sync::Semaphore::new(MAX_PLANNING),
            operator_timeout: std::time::Duration::from_secs_f64(timeout),
            operator_criterion: config.operator_criterion.clone(),
        })
    }

    /// Joint values of step counters: revolute joints in degrees, prismatic in metres.
    #[must_use]
    pub fn q_deg(&self, steps: &[i64]) -> Vec<f64> {
        let q: Vec<f64> = self.axes.iter().zip(steps).map(|(a, &s)| a.joint_value(s)).collect();
        q_display(&self.robot, &q)
    }

    /// `GET /state` (and the WebSocket's `state` message without its `type`).
    #[must_use]
    pub fn state(&self, live: &Live) -> Value {
        let status = if live.waiting {
            "waiting"
        } else if live.job.is_some() {
            "executing"
        } else if live.paused {
            "stopped"
        } else {
            "idle"
        };
        json!({
            "robot": self.robot.name(),
            "q_deg": self.q_deg(&live.steps),
            "steps": live.steps,
            "job": live.job,
            "status": status,
            "last_commit": live.last_commit,
        })
    }

    /// Sends a message to every WebSocket client (none listening is fine).
    pub fn publish(&self, message: &Value) {
        let _ = self.events.send(Arc::from(message.to_string()));
    }

    /// The WebSocket's `state` message: [`Shared::state`] with its `type`, the time `t_ms`
    /// (Unix ms) and `view`, the arm as the viewer draws it (the library's view state: frames,
    /// tool, joint axes).
    #[must_use]
    pub fn state_message(&self, live: &Live) -> Value {
        let mut state = self.state(live);
        state["type"] = json!("state");
        state["t_ms"] = json!(crate::db::now_ms());
        let q: Vec<f64> = self.axes.iter().zip(&live.steps).map(|(a, &s)| a.joint_value(s)).collect();
        state["view"] = reach::jobs::view::view_state(&self.robot, 0.0, &q)
            .ok()
            .and_then(|v| serde_json::to_value(v).ok())
            .unwrap_or(Value::Null);
        state
    }

    /// Publishes the joint state.
    pub fn publish_state(&self, live: &Live) {
        self.publish(&self.state_message(live));
    }

    /// Records a job event in the log and sends it to WebSocket clients.
    pub fn job_event(&self, id: i64, status: JobStatus, message: Option<&str>) {
        self.job_event_with(id, status, message, json!({}));
    }

    /// [`Shared::job_event`] with more fields in the WebSocket message (`extra`, an object).
    pub fn job_event_with(&self, id: i64, status: JobStatus, message: Option<&str>, extra: Value) {
        let db = lock(&self.db);
        let _ = db.add_event(Some(id), status.as_str(), message.unwrap_or(""));
        let segment = db.job(id).ok().flatten().map(|j| j.segment);
        drop(db);
        let mut event = json!({"type": "job", "id": id, "status": status, "segment": segment, "message": message});
        if let (Some(event), Value::Object(extra)) = (event.as_object_mut(), extra) {
            event.extend(extra);
        }
        self.publish(&event);
    }

    /// The drive data in use, per joint (shown by `GET /state`'s `drives`).
    #[must_use]
    pub fn drives(&self) -> Value {
        let per_joint: Vec<Value> = self
            .axes
            .iter()
            .enumerate()
            .map(|(i, a)| {
                json!({
                    "joint": a.joint,
                    "name": a.name,
                    "simulated_default": self.simulated.contains(&i),
                    "steps_per_unit": a.steps_per_unit,
                    "max_step_rate_hz": a.max_step_rate,
                    "max_acceleration_steps_s2": a.max_acceleration,
                })
            })
            .collect();
        Value::Array(per_joint)
    }
}
