//! The service's state in SQLite: the robot, the scene, each joint's step counter, the job
//! journal and the event log (schema and guarantees in `docs/service.md`).
//!
//! The database runs in WAL mode with `synchronous = FULL`: every commit is on disk when
//! `COMMIT` returns, so a committed step count survives `kill -9` *and* a power cut. (NORMAL
//! would survive `kill -9` only; an arm's position must survive both, and at most 20 commits a
//! second of real-time motion the fsync costs nothing that matters.)

use std::path::Path;

use rusqlite::{Connection, OptionalExtension, params};
use serde::Serialize;
use serde_json::Value;

use crate::error::ServeError;

/// The schema version this build writes (`PRAGMA user_version`).
pub const SCHEMA_VERSION: i64 = 1;

const SCHEMA: &str = "
CREATE TABLE meta (key TEXT PRIMARY KEY, value TEXT NOT NULL);
CREATE TABLE joints (joint INTEGER PRIMARY KEY, name TEXT NOT NULL, steps INTEGER NOT NULL);
CREATE TABLE jobs (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    kind TEXT NOT NULL,
    request TEXT NOT NULL,
    from_current INTEGER NOT NULL DEFAULT 0,
    status TEXT NOT NULL,
    report TEXT,
    message TEXT,
    segment INTEGER NOT NULL DEFAULT 0,
    segments INTEGER,
    created_ms INTEGER NOT NULL,
    updated_ms INTEGER NOT NULL
);
CREATE INDEX jobs_by_status ON jobs (status, id);
CREATE TABLE events (
    id INTEGER PRIMARY KEY AUTOINCREMENT,
    at_ms INTEGER NOT NULL,
    job INTEGER,
    type TEXT NOT NULL,
    message TEXT NOT NULL
);
";

/// Milliseconds since the Unix epoch.
#[must_use]
pub fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}

/// A job's status in the journal (stored and shown as its snake_case name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum JobStatus {
    /// Waiting for the executor.
    Queued,
    /// Being re-planned or scheduled by the executor.
    Planning,
    /// Waiting for the operator's choice of configuration (`POST /jobs/{id}/choose`).
    WaitingOperator,
    /// The motors are playing it.
    Executing,
    /// Executed to its end (or planned only, for reports without motion).
    Done,
    /// Infeasible or unsafe: nothing moved.
    Refused,
    /// An internal failure.
    Failed,
    /// The service stopped during the job (crash, `kill -9`, shutdown).
    Interrupted,
    /// Stopped by `POST /stop` or `POST /estop`.
    Stopped,
}

impl JobStatus {
    /// Every status, in the order of a job's life.
    pub const ALL: [JobStatus; 9] = [
        JobStatus::Queued,
        JobStatus::Planning,
        JobStatus::WaitingOperator,
        JobStatus::Executing,
        JobStatus::Done,
        JobStatus::Refused,
        JobStatus::Failed,
        JobStatus::Interrupted,
        JobStatus::Stopped,
    ];

    /// The name stored and shown.
    #[must_use]
    pub const fn as_str(self) -> &'static str {
        match self {
            JobStatus::Queued => "queued",
            JobStatus::Planning => "planning",
            JobStatus::WaitingOperator => "waiting_operator",
            JobStatus::Executing => "executing",
            JobStatus::Done => "done",
            JobStatus::Refused => "refused",
            JobStatus::Failed => "failed",
            JobStatus::Interrupted => "interrupted",
            JobStatus::Stopped => "stopped",
        }
    }

    /// The status of a stored name.
    #[must_use]
    pub fn parse(name: &str) -> Option<JobStatus> {
        JobStatus::ALL.into_iter().find(|s| s.as_str() == name)
    }

    /// Whether the job has ended.
    #[must_use]
    pub const fn is_final(self) -> bool {
        matches!(
            self,
            JobStatus::Done | JobStatus::Refused | JobStatus::Failed | JobStatus::Interrupted | JobStatus::Stopped
        )
    }
}

/// How a commit of the joint state concerns a job: its segment executed, and the status it
/// ends with when the commit ends it (written in the same transaction).
#[derive(Debug, Clone, Copy)]
pub struct JobCommit<'a> {
    /// The job.
    pub id: i64,
    /// The segment executed (`None`: a commit that does not advance the job's schedule).
    pub segment: Option<i64>,
    /// The final status and message, when this commit ends the job.
    pub end: Option<(JobStatus, Option<&'a str>)>,
}

/// One job of the journal.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JobRow {
    /// Job number, in submission order.
    pub id: i64,
    /// The request's kind (`move`, `plan`, …).
    pub kind: String,
    /// The library request (`reach::jobs::Request`) as submitted (after the shorthand).
    pub request: Value,
    /// A move that starts wherever the arm is when the job starts (re-planned then).
    pub from_current: bool,
    /// Its status.
    pub status: JobStatus,
    /// The library's report of the planned job (`null` before it is planned).
    pub report: Option<Value>,
    /// Why the job was refused, failed, stopped or interrupted; `null` otherwise.
    pub message: Option<String>,
    /// Segments executed and committed (each at most 50 ms of motion).
    pub segment: i64,
    /// Segments of the job's schedule (`null` before it is scheduled).
    pub segments: Option<i64>,
    /// Submission time, ms since the Unix epoch.
    pub created_ms: i64,
    /// Last change, ms since the Unix epoch.
    pub updated_ms: i64,
}

/// The last commit of the joint state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LastCommit {
    /// When, ms since the Unix epoch.
    pub at_ms: i64,
    /// The job executing then (`null` when none).
    pub job: Option<i64>,
    /// The job's segment committed (`null` when none).
    pub segment: Option<i64>,
}

/// What opening the state found.
#[derive(Debug, Clone, Default)]
pub struct Recovery {
    /// Whether the database was created now.
    pub created: bool,
    /// The job that was executing when the service stopped, now `interrupted`.
    pub interrupted: Option<i64>,
}

/// The open state database.
pub struct Db {
    conn: Connection,
    /// `dir/lock`, held exclusively while the service runs: a second service on the same
    /// state directory is refused before it recovers or changes anything.
    _lock: std::fs::File,
}

impl Db {
    /// Opens (or creates) `dir/state.sqlite3` for the robot `robot_json` (its `RobotInput`
    /// JSON) with joints `names`, starting at `initial_steps` when new.
    ///
    /// On an existing database the robot must be the same, else [`ServeError::RobotMismatch`].
    /// A start never moves the arm by itself: whenever a job was left in the queue and not
    /// ended (queued, planning, waiting for its operator, executing) when the service stopped,
    /// the queue is paused until `POST /resume`, and each such job's message says why: a job
    /// left `executing` becomes `interrupted` (its committed segment kept), one left
    /// `planning` (nothing moved yet) is queued again, one left `waiting_operator` keeps
    /// waiting, a queued one stays queued.
    ///
    /// # Errors
    /// [`ServeError`] for a database that cannot be opened, has a newer schema, or holds
    /// another robot.
    pub fn open(
        dir: &Path,
        robot_json: &str,
        names: &[String],
        initial_steps: &[i64],
        scene: Option<&str>,
    ) -> Result<(Db, Recovery), ServeError> {
        if !dir.exists() {
            // A directory made here is the owner's only (0700); one the user gave is left as it
            // is (`--state .` must not change a working directory's mode): its files are 0600.
            std::fs::create_dir_all(dir).map_err(|e| ServeError::io(dir, &e))?;
            crate::auth::make_private(dir)?;
        }
        let lock_path = dir.join("lock");
        let lock = std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&lock_path)
            .map_err(|e| ServeError::io(&lock_path, &e))?;
        match lock.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                return Err(ServeError::Config(format!(
                    "the state directory `{}` is in use by another reach serve; stop it or use another --state directory",
                    dir.display()
                )));
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(ServeError::io(&lock_path, &e)),
        }
        let path = dir.join("state.sqlite3");
        // The database is made (empty) with the owner's permissions only: SQLite gives its
        // `-wal` and `-shm` files the database's.
        std::fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(|e| ServeError::io(&path, &e))?;
        crate::auth::make_private(&lock_path)?;
        crate::auth::make_private(&path)?;
        let mut conn = Connection::open(&path)?;
        conn.busy_timeout(std::time::Duration::from_secs(5))?;
        conn.pragma_update(None, "journal_mode", "WAL")?;
        for suffix in ["-wal", "-shm"] {
            let file = dir.join(format!("state.sqlite3{suffix}"));
            if file.exists() {
                crate::auth::make_private(&file)?;
            }
        }
        conn.pragma_update(None, "synchronous", "FULL")?;
        let version: i64 = conn.pragma_query_value(None, "user_version", |r| r.get(0))?;
        let mut recovery = Recovery::default();
        if version == 0 {
            let tx = conn.transaction()?;
            tx.execute_batch(SCHEMA)?;
            tx.execute("INSERT INTO meta (key, value) VALUES ('robot', ?1)", params![robot_json])?;
            tx.execute("INSERT INTO meta (key, value) VALUES ('paused', '0')", [])?;
            for (i, (name, steps)) in names.iter().zip(initial_steps).enumerate() {
                tx.execute(
                    "INSERT INTO joints (joint, name, steps) VALUES (?1, ?2, ?3)",
                    params![i as i64 + 1, name, steps],
                )?;
            }
            tx.pragma_update(None, "user_version", SCHEMA_VERSION)?;
            tx.commit()?;
            recovery.created = true;
        } else if version != SCHEMA_VERSION {
            return Err(ServeError::Schema {
                path: path.display().to_string(),
                found: version,
                expected: SCHEMA_VERSION,
            });
        }
        let stored: String = conn.query_row("SELECT value FROM meta WHERE key = 'robot'", [], |r| r.get(0))?;
        if !same_json(&stored, robot_json) {
            return Err(ServeError::RobotMismatch {
                dir: dir.display().to_string(),
                stored: robot_summary(&stored),
                given: robot_summary(robot_json),
            });
        }
        let tx = conn.transaction()?;
        if let Some(text) = scene {
            tx.execute("INSERT OR REPLACE INTO meta (key, value) VALUES ('scene', ?1)", params![text])?;
        }
        let now = now_ms();
        // One rule: a job not ended (queued, planning, waiting for its operator, executing)
        // when the service stopped pauses the queue until `POST /resume` (a kill between two
        // jobs must not let the next one start by itself); its status and message say why.
        // Only an executing job may have moved: it ends `interrupted`.
        let caught: Vec<(i64, String, i64)> = {
            let mut stmt =
                tx.prepare("SELECT id, status, segment FROM jobs WHERE status IN (?1, ?2, ?3, ?4) ORDER BY id")?;
            let rows = stmt.query_map(
                params![
                    JobStatus::Queued.as_str(),
                    JobStatus::Planning.as_str(),
                    JobStatus::WaitingOperator.as_str(),
                    JobStatus::Executing.as_str()
                ],
                |r| Ok((r.get(0)?, r.get(1)?, r.get(2)?)),
            )?;
            rows.collect::<Result<_, _>>()?
        };
        let mut interrupted = None;
        for (id, status, segment) in &caught {
            let (next, message) = match JobStatus::parse(status) {
                Some(JobStatus::Executing) => {
                    interrupted = Some(*id);
                    (
                        JobStatus::Interrupted,
                        format!(
                            "interrupted: the service stopped during the job; segment {segment} was the last committed; the queue is paused until POST /resume"
                        ),
                    )
                }
                Some(JobStatus::WaitingOperator) => (
                    JobStatus::WaitingOperator,
                    "the service stopped while the job waited for the operator; the queue is paused until POST /resume"
                        .to_string(),
                ),
                Some(JobStatus::Planning) => (
                    JobStatus::Queued,
                    "the service stopped while the job was planned (nothing moved); queued again, the queue is paused until POST /resume"
                        .to_string(),
                ),
                _ => (
                    JobStatus::Queued,
                    "the service stopped before the job ran (nothing moved); it stays queued, the queue is paused until POST /resume"
                        .to_string(),
                ),
            };
            tx.execute(
                "UPDATE jobs SET status = ?2, message = ?3, updated_ms = ?4 WHERE id = ?1",
                params![id, next.as_str(), message, now],
            )?;
            tx.execute(
                "INSERT INTO events (at_ms, job, type, message) VALUES (?1, ?2, ?3, ?4)",
                params![now, id, next.as_str(), message],
            )?;
        }
        if !caught.is_empty() {
            tx.execute("UPDATE meta SET value = '1' WHERE key = 'paused'", [])?;
        }
        tx.commit()?;
        recovery.interrupted = interrupted;
        Ok((Db { conn, _lock: lock }, recovery))
    }

    /// The scene text stored (the last one given).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn scene(&self) -> Result<Option<String>, ServeError> {
        Ok(self.conn.query_row("SELECT value FROM meta WHERE key = 'scene'", [], |r| r.get(0)).optional()?)
    }

    /// Stores the scene text.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn set_scene(&self, text: &str) -> Result<(), ServeError> {
        self.conn.execute("INSERT OR REPLACE INTO meta (key, value) VALUES ('scene', ?1)", params![text])?;
        Ok(())
    }

    /// Every joint's committed step counter, base to tip.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn steps(&self) -> Result<Vec<i64>, ServeError> {
        let mut stmt = self.conn.prepare_cached("SELECT steps FROM joints ORDER BY joint")?;
        let rows = stmt.query_map([], |r| r.get(0))?;
        Ok(rows.collect::<Result<Vec<i64>, _>>()?)
    }

    /// Whether the queue waits for `POST /resume`.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn paused(&self) -> Result<bool, ServeError> {
        let v: String = self.conn.query_row("SELECT value FROM meta WHERE key = 'paused'", [], |r| r.get(0))?;
        Ok(v == "1")
    }

    /// Pauses or resumes the queue (durably).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn set_paused(&self, paused: bool) -> Result<(), ServeError> {
        self.conn
            .execute("UPDATE meta SET value = ?1 WHERE key = 'paused'", params![if paused { "1" } else { "0" }])?;
        Ok(())
    }

    /// The last commit of the joint state (`null` fields before any motion).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn last_commit(&self) -> Result<Option<LastCommit>, ServeError> {
        let text: Option<String> =
            self.conn.query_row("SELECT value FROM meta WHERE key = 'last_commit'", [], |r| r.get(0)).optional()?;
        Ok(text.and_then(|t| serde_json::from_str::<Value>(&t).ok()).map(|v| LastCommit {
            at_ms: v["at_ms"].as_i64().unwrap_or(0),
            job: v["job"].as_i64(),
            segment: v["segment"].as_i64(),
        }))
    }

    /// Records a new job; returns its id.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn insert_job(
        &self,
        kind: &str,
        request: &Value,
        from_current: bool,
        status: JobStatus,
        report: Option<&Value>,
        message: Option<&str>,
    ) -> Result<i64, ServeError> {
        let now = now_ms();
        self.conn.execute(
            "INSERT INTO jobs (kind, request, from_current, status, report, message, created_ms, updated_ms) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?7)",
            params![kind, request.to_string(), from_current, status.as_str(), report.map(Value::to_string), message, now],
        )?;
        Ok(self.conn.last_insert_rowid())
    }

    /// Sets a job's status, and its message and segment count when given.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn set_job(
        &self,
        id: i64,
        status: JobStatus,
        message: Option<&str>,
        segments: Option<i64>,
    ) -> Result<(), ServeError> {
        self.conn.execute(
            "UPDATE jobs SET status = ?2, message = COALESCE(?3, message), segments = COALESCE(?4, segments), updated_ms = ?5 WHERE id = ?1",
            params![id, status.as_str(), message, segments, now_ms()],
        )?;
        Ok(())
    }

    /// The answer to a job waiting for the operator: its request and report replaced and the
    /// job queued, if it still waits (`false`: it does not, e.g. the criterion answered first).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn answer(&self, id: i64, request: &Value, report: &Value, message: &str) -> Result<bool, ServeError> {
        let changed = self.conn.execute(
            "UPDATE jobs SET status = ?2, request = ?3, report = ?4, message = ?5, updated_ms = ?6 \
             WHERE id = ?1 AND status = ?7",
            params![
                id,
                JobStatus::Queued.as_str(),
                request.to_string(),
                report.to_string(),
                message,
                now_ms(),
                JobStatus::WaitingOperator.as_str()
            ],
        )?;
        Ok(changed == 1)
    }

    /// Replaces a job's request and report (a move re-planned from where the arm is).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn set_plan(&self, id: i64, request: &Value, report: &Value) -> Result<(), ServeError> {
        self.conn.execute(
            "UPDATE jobs SET request = ?2, report = ?3, updated_ms = ?4 WHERE id = ?1",
            params![id, request.to_string(), report.to_string(), now_ms()],
        )?;
        Ok(())
    }

    /// Commits, in one transaction, every joint's step counter and (with a job) the job's
    /// executed segment and, when the commit ends the job, its final status: after a crash the
    /// database holds either the state before or the state after this call, never a mix.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn commit_steps(&mut self, steps: &[i64], job: Option<JobCommit<'_>>) -> Result<LastCommit, ServeError> {
        let now = now_ms();
        let tx = self.conn.transaction()?;
        {
            let mut update = tx.prepare_cached("UPDATE joints SET steps = ?2 WHERE joint = ?1")?;
            for (i, s) in steps.iter().enumerate() {
                update.execute(params![i as i64 + 1, s])?;
            }
        }
        let (job_id, segment) = job.map_or((None, None), |j| (Some(j.id), j.segment));
        if let (Some(id), Some(seg)) = (job_id, segment) {
            tx.execute("UPDATE jobs SET segment = ?2, updated_ms = ?3 WHERE id = ?1", params![id, seg, now])?;
        }
        if let Some(JobCommit { id, end: Some((status, message)), .. }) = job {
            tx.execute(
                "UPDATE jobs SET status = ?2, message = COALESCE(?3, message), updated_ms = ?4 WHERE id = ?1",
                params![id, status.as_str(), message, now],
            )?;
        }
        let commit = LastCommit { at_ms: now, job: job_id, segment };
        let text = serde_json::json!({"at_ms": now, "job": job_id, "segment": segment}).to_string();
        tx.execute("INSERT OR REPLACE INTO meta (key, value) VALUES ('last_commit', ?1)", params![text])?;
        tx.commit()?;
        Ok(commit)
    }

    /// Appends an event (operator message, job transition) to the log.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn add_event(&self, job: Option<i64>, kind: &str, message: &str) -> Result<(), ServeError> {
        self.conn.execute(
            "INSERT INTO events (at_ms, job, type, message) VALUES (?1, ?2, ?3, ?4)",
            params![now_ms(), job, kind, message],
        )?;
        Ok(())
    }

    /// The oldest job queued or waiting for the operator (the queue keeps its order: a job
    /// waiting for its operator holds the ones behind it).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn next_queued(&self) -> Result<Option<JobRow>, ServeError> {
        self.query_jobs(
            "WHERE status IN (?1, ?2) ORDER BY id LIMIT 1",
            [JobStatus::Queued.as_str(), JobStatus::WaitingOperator.as_str()],
        )
        .map(|mut v| v.pop())
    }

    /// One job.
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn job(&self, id: i64) -> Result<Option<JobRow>, ServeError> {
        self.query_jobs("WHERE id = ?1", [id]).map(|mut v| v.pop())
    }

    /// Every job in submission order (at most `limit`, the newest ones).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn jobs(&self, limit: i64) -> Result<Vec<JobRow>, ServeError> {
        let mut v = self.query_jobs("ORDER BY id DESC LIMIT ?1", [limit])?;
        v.reverse();
        Ok(v)
    }

    /// The number of jobs waiting in the queue (queued or waiting for the operator).
    ///
    /// # Errors
    /// [`ServeError::Db`].
    pub fn queued_count(&self) -> Result<i64, ServeError> {
        Ok(self.conn.query_row(
            "SELECT COUNT(*) FROM jobs WHERE status IN (?1, ?2)",
            [JobStatus::Queued.as_str(), JobStatus::WaitingOperator.as_str()],
            |r| r.get(0),
        )?)
    }

    fn query_jobs<P: rusqlite::Params>(&self, tail: &str, p: P) -> Result<Vec<JobRow>, ServeError> {
        let sql = format!(
            "SELECT id, kind, request, status, report, message, segment, segments, created_ms, updated_ms, from_current FROM jobs {tail}"
        );
        let mut stmt = self.conn.prepare_cached(&sql)?;
        let rows = stmt.query_map(p, |r| {
            let request: String = r.get(2)?;
            let report: Option<String> = r.get(4)?;
            Ok(JobRow {
                id: r.get(0)?,
                kind: r.get(1)?,
                request: serde_json::from_str(&request).unwrap_or(Value::Null),
                status: {
                    let name: String = r.get(3)?;
                    JobStatus::parse(&name).ok_or_else(|| {
                        rusqlite::Error::FromSqlConversionFailure(
                            3,
                            rusqlite::types::Type::Text,
                            format!("unknown job status `{name}`").into(),
                        )
                    })?
                },
                report: report.and_then(|t| serde_json::from_str(&t).ok()),
                message: r.get(5)?,
                segment: r.get(6)?,
                segments: r.get(7)?,
                created_ms: r.get(8)?,
                updated_ms: r.get(9)?,
                from_current: r.get(10)?,
            })
        })?;
        Ok(rows.collect::<Result<Vec<_>, _>>()?)
    }
}

/// Whether two JSON texts hold the same value.
fn same_json(a: &str, b: &str) -> bool {
    match (serde_json::from_str::<Value>(a), serde_json::from_str::<Value>(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

/// A robot input in a few words: `preset ur5`, `TOML text "…"`.
fn robot_summary(json: &str) -> String {
    let v: Value = serde_json::from_str(json).unwrap_or(Value::Null);
    if let Some(name) = v["preset"].as_str() {
        return format!("preset `{name}`");
    }
    let (kind, text) = if v["toml"].is_object() { ("TOML", &v["toml"]["text"]) } else { ("URDF", &v["urdf"]["text"]) };
    let text = text.as_str().unwrap_or("");
    let first = text.lines().find(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#')).unwrap_or("");
    format!("a {kind} description starting `{}`", first.chars().take(60).collect::<String>())
}
