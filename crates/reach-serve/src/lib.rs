//! `reach serve`: the control service — an HTTP + WebSocket adapter over [`reach::jobs`], with
//! the robot, the scene, every joint's step counter, the job journal and the event log in an
//! SQLite database, and a simulated drive that plays each job's step schedule.
//!
//! * [`Config`] — how the service is started; [`Service::open`] opens (or creates) the state
//!   and starts the executor thread; [`Service::router`] is the axum router (tests call it
//!   in-process); [`serve`] runs it on a socket until Ctrl-C.
//! * A job is a library request ([`reach::jobs::Request`], kinds move, plan, path, approach, tasks,
//!   avoid; plus the move shorthand of [`intake::parse_request`]). `POST /jobs` plans it with
//!   [`reach::jobs::run`]: bad input is a 400 with the library's message, an infeasible plan is
//!   recorded `refused` with its report. The executor ([`executor`]) turns a queued job's motion
//!   into step schedules with [`reach::jobs::drive`] (limits re-checked), refuses it unless it
//!   starts where the arm is (within one step) and, with a scene, is proven clear of it, then
//!   plays it and commits the counters at every segment boundary (at most 50 ms of motion).
//! * Durability (`docs/service.md`): one transaction per segment stores the counters and the
//!   job's segment; after `kill -9` a restart shows the last committed counters, marks the
//!   running job `interrupted` and keeps the queue, paused until `POST /resume`.
//! * `POST /scene/obstacles` adds an obstacle (checked by the library's scene parser, stored);
//!   jobs that start afterwards must be proven clear of it.
//! * Security: loopback by default; beyond it, every request (except `GET /openapi.json`)
//!   needs the bearer token from `STATE/token` (mode 0600, made on the first start). Bodies
//!   are limited to [`service::MAX_BODY_BYTES`]; browser origins are refused unless allowed by
//!   `--cors`.

pub mod api;
pub mod auth;
pub mod db;
pub mod error;
pub mod executor;
pub mod intake;
pub mod schedule;
pub mod service;

use std::sync::Arc;
use std::thread::JoinHandle;

pub use error::{ApiError, ServeError};
pub use service::Config;
use service::{Shared, lock};

/// A running service: the shared state and its executor thread.
pub struct Service {
    shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
}

impl Service {
    /// Opens the state directory (creating it, the database and the token on the first
    /// start) and starts the executor.
    ///
    /// # Errors
    /// [`ServeError`] for a bad robot, scene or speed, a state directory of another robot, or
    /// a database that cannot be opened.
    pub fn open(config: &Config) -> Result<Service, ServeError> {
        let shared = Arc::new(Shared::open(config)?);
        let mut threads = Vec::new();
        let worker = shared.clone();
        threads.push(
            std::thread::Builder::new()
                .name("reach-executor".into())
                .spawn(move || executor::run(&worker))
                .map_err(|e| ServeError::Io(format!("cannot start the executor: {e}")))?,
        );
        let worker = shared.clone();
        threads.push(
            std::thread::Builder::new()
                .name("reach-publisher".into())
                .spawn(move || executor::publish(&worker))
                .map_err(|e| ServeError::Io(format!("cannot start the publisher: {e}")))?,
        );
        let service = Service { shared, threads };
        Ok(service)
    }

    /// The HTTP router.
    pub fn router(&self) -> axum::Router {
        api::router(self.shared.clone())
    }

    /// The job left `interrupted` by the previous run, if any.
    #[must_use]
    pub fn interrupted(&self) -> Option<i64> {
        self.shared.recovery.interrupted
    }

    /// Whether requests need the bearer token (the service listens beyond loopback).
    #[must_use]
    pub fn needs_token(&self) -> bool {
        self.shared.token.is_some()
    }

    /// Stops the executor (a job in motion stays `executing` in the database, so the next
    /// start reports it `interrupted`, like a crash would).
    pub fn shutdown(mut self) {
        self.stop_executor();
    }

    fn stop_executor(&mut self) {
        lock(&self.shared.live).shutdown = true;
        self.shared.wake.notify_all();
        for handle in self.threads.drain(..) {
            let _ = handle.join();
        }
    }
}

impl Drop for Service {
    fn drop(&mut self) {
        self.stop_executor();
    }
}

/// Serves `service` on `listener` until `shutdown` resolves.
///
/// Every connection is set `TCP_NODELAY`: a joint state is one small WebSocket frame every
/// 20 ms, and Nagle's algorithm would hold it until the client's (delayed) acknowledgement
/// of the previous one, up to 40 ms later.
///
/// # Errors
/// [`ServeError::Io`] when the server fails.
pub async fn serve_on(
    listener: tokio::net::TcpListener,
    service: &Service,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> Result<(), ServeError> {
    use axum::serve::ListenerExt as _;
    let listener = listener.tap_io(|tcp| {
        // Without it the service still works, only with Nagle's delays.
        let _ = tcp.set_nodelay(true);
    });
    axum::serve(listener, service.router())
        .with_graceful_shutdown(shutdown)
        .await
        .map_err(|e| ServeError::Io(format!("server: {e}")))
}

/// Runs the service of `config` until `shutdown` resolves: opens the state, binds the
/// address, prints one line saying where it listens (and where the token is), serves.
///
/// # Errors
/// [`ServeError`] for a bad configuration or state, or an address that cannot be bound.
pub fn serve(
    config: &Config,
    shutdown: impl std::future::Future<Output = ()> + Send + 'static,
) -> Result<(), ServeError> {
    let service = Service::open(config)?;
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        .build()
        .map_err(|e| ServeError::Io(format!("cannot start the runtime: {e}")))?;
    runtime.block_on(async {
        let listener = tokio::net::TcpListener::bind(config.listen)
            .await
            .map_err(|e| ServeError::Io(format!("cannot listen on {}: {e}", config.listen)))?;
        let addr = listener.local_addr().map_err(|e| ServeError::Io(e.to_string()))?;
        let mut line = format!("reach serve: listening on http://{addr} (state in {})", config.state_dir.display());
        if service.needs_token() {
            line.push_str(&format!("; requests need the token in {}", config.state_dir.join("token").display()));
        }
        if let Some(id) = service.interrupted() {
            line.push_str(&format!("; job {id} was interrupted, the queue waits for POST /resume"));
        }
        println!("{line}");
        use std::io::Write as _;
        let _ = std::io::stdout().flush();
        serve_on(listener, &service, shutdown).await
    })?;
    service.shutdown();
    Ok(())
}
