//! `reach job submit|status|watch|stop|resume|choose|add-obstacle|remove-obstacle` — a client of a
//! running `reach serve`.

use std::io::{Read, Write};
use std::time::{Duration, Instant};

use clap::{Args, Subcommand};
use serde_json::Value;

use crate::error::{CliError, one_line};
use crate::output::write_json;

/// Where the service is.
#[derive(Debug, Clone, Args)]
pub struct ServiceArgs {
    /// The service's URL.
    #[arg(long, value_name = "URL", default_value = "http://127.0.0.1:7878", global = true)]
    pub url: String,

    /// The bearer token (a service beyond loopback needs it; default: $REACH_TOKEN).
    #[arg(long, value_name = "TOKEN", global = true)]
    pub token: Option<String>,
}

/// `reach job …`.
#[derive(Debug, Clone, Args)]
pub struct JobArgs {
    /// The service.
    #[command(flatten)]
    pub service: ServiceArgs,

    /// What to do.
    #[command(subcommand)]
    pub command: JobCommand,
}

/// The `reach job` subcommands.
#[derive(Debug, Clone, Subcommand)]
pub enum JobCommand {
    /// Submit a job: JSON inline (`{"kind": "move", ...}`), from a file, or `-` for stdin.
    Submit {
        /// The job.
        #[arg(value_name = "JOB")]
        job: String,
        /// Wait until the job ends and print it; exit 3 when it is refused, failed or stopped.
        #[arg(long)]
        wait: bool,
    },
    /// Print a job (`GET /jobs/ID`), or the service's state without an ID (`GET /state`).
    Status {
        /// The job number.
        #[arg(value_name = "ID")]
        id: Option<i64>,
    },
    /// Print the service's messages (joint states, job events) as JSON lines.
    Watch {
        /// Stop after this many messages (default: until Ctrl-C).
        #[arg(long, value_name = "N")]
        count: Option<usize>,
    },
    /// Stop the arm with a controlled deceleration (`--estop`: halt now); the queue pauses.
    Stop {
        /// Emergency stop: halt at once.
        #[arg(long)]
        estop: bool,
    },
    /// Let the queued jobs run again after a stop or an interrupted job.
    Resume,
    /// Add an obstacle to the service's scene (`POST /scene/obstacles`): JSON in the scene
    /// file's format (`{"name": "post", "shape": "sphere", ...}`), inline, from a file, or `-`.
    AddObstacle {
        /// The obstacle.
        #[arg(value_name = "OBSTACLE")]
        obstacle: String,
    },
    /// Remove an obstacle from the service's scene by name (`DELETE /scene/obstacles/NAME`).
    RemoveObstacle {
        /// The obstacle's name.
        #[arg(value_name = "NAME")]
        name: String,
    },
    /// Answer a job waiting for the operator (its `questions`): the configuration per interval.
    Choose {
        /// The job number.
        #[arg(value_name = "ID")]
        id: i64,
        /// INTERVAL=CONFIGURATION, e.g. `1=config=-β` (repeat for several intervals).
        #[arg(long = "choice", value_name = "INTERVAL=CONFIGURATION", required = true)]
        choices: Vec<String>,
    },
}

/// Whether a job's status (as the service shows it) ends the job.
fn is_final(status: Option<&str>) -> bool {
    status.and_then(reach_serve::db::JobStatus::parse).is_some_and(reach_serve::db::JobStatus::is_final)
}

/// Runs one `reach job` command.
///
/// # Errors
/// [`CliError::BadInput`] for an unreachable service or an error reply (its message);
/// [`CliError::NoSolution`] when a waited-for job does not end `done`.
pub fn run(args: &JobArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let client = Client::new(&args.service);
    match &args.command {
        JobCommand::Submit { job, wait } => {
            let body = json_text(job, "job")?;
            let reply = client.call("POST", "/jobs", Some(&body))?;
            if !wait {
                return write_json(out, &reply);
            }
            let id = reply["id"].as_i64().ok_or_else(|| CliError::internal(format!("no job id in {reply}")))?;
            let job = loop {
                let job = client.call("GET", &format!("/jobs/{id}"), None)?;
                if is_final(job["status"].as_str()) {
                    break job;
                }
                crate::interrupt::check()?;
                std::thread::sleep(Duration::from_millis(50));
            };
            write_json(out, &job)?;
            match job["status"].as_str() {
                Some("done") => Ok(()),
                status => Err(CliError::NoSolution(format!(
                    "job {id} ended {}: {}",
                    status.unwrap_or("?"),
                    job["message"].as_str().unwrap_or("")
                ))),
            }
        }
        JobCommand::Status { id } => {
            let path = id.map_or_else(|| "/state".to_string(), |id| format!("/jobs/{id}"));
            write_json(out, &client.call("GET", &path, None)?)
        }
        JobCommand::Stop { estop } => {
            write_json(out, &client.call("POST", if *estop { "/estop" } else { "/stop" }, None)?)
        }
        JobCommand::Resume => write_json(out, &client.call("POST", "/resume", None)?),
        JobCommand::Choose { id, choices } => {
            let choices = choices
                .iter()
                .map(|c| crate::commands::move_cmd::parse_choice(c))
                .collect::<Result<Vec<_>, CliError>>()?;
            let body = serde_json::json!({ "choices": choices }).to_string();
            write_json(out, &client.call("POST", &format!("/jobs/{id}/choose"), Some(&body))?)
        }
        JobCommand::Watch { count } => client.watch(*count, out),
        JobCommand::AddObstacle { obstacle } => {
            let body = json_text(obstacle, "obstacle")?;
            write_json(out, &client.call("POST", "/scene/obstacles", Some(&body))?)
        }
        JobCommand::RemoveObstacle { name } => {
            write_json(out, &client.call("DELETE", &format!("/scene/obstacles/{}", path_segment(name)), None)?)
        }
    }
}

/// A JSON argument (a job, an obstacle; `what` names it): inline, `-` (stdin) or a file.
fn json_text(arg: &str, what: &str) -> Result<String, CliError> {
    if arg.trim_start().starts_with('{') {
        return Ok(arg.to_string());
    }
    if arg == "-" {
        let mut text = String::new();
        std::io::stdin().read_to_string(&mut text)?;
        return Ok(text);
    }
    std::fs::read_to_string(arg)
        .map_err(|e| CliError::bad_input(format!("cannot read {what} file `{arg}`: {}", one_line(&e.to_string()))))
}

/// `text` as one URL path segment: unreserved characters as they are, every other byte
/// percent-encoded (a sensed obstacle's name holds a blank).
fn path_segment(text: &str) -> String {
    text.bytes()
        .map(|b| {
            if b.is_ascii_alphanumeric() || b"-._~".contains(&b) {
                (b as char).to_string()
            } else {
                format!("%{b:02X}")
            }
        })
        .collect()
}

/// An HTTP client of the service.
struct Client {
    agent: ureq::Agent,
    base: String,
    token: Option<String>,
}

impl Client {
    fn new(service: &ServiceArgs) -> Self {
        let agent = ureq::Agent::config_builder()
            .http_status_as_error(false)
            .timeout_global(Some(Duration::from_secs(120)))
            .build()
            .into();
        let token = service.token.clone().or_else(|| std::env::var("REACH_TOKEN").ok());
        Client { agent, base: service.url.trim_end_matches('/').to_string(), token }
    }

    /// `METHOD path`: the JSON reply, or the service's `error` as a bad-input error.
    fn call(&self, method: &str, path: &str, body: Option<&str>) -> Result<Value, CliError> {
        let url = format!("{}{path}", self.base);
        let auth = self.token.as_ref().map(|t| format!("Bearer {t}"));
        let result = if method == "GET" || method == "DELETE" {
            let mut r = if method == "GET" { self.agent.get(&url) } else { self.agent.delete(&url) };
            if let Some(a) = &auth {
                r = r.header("authorization", a);
            }
            r.call()
        } else {
            let mut r = self.agent.post(&url).content_type("application/json");
            if let Some(a) = &auth {
                r = r.header("authorization", a);
            }
            r.send(body.unwrap_or(""))
        };
        let mut response = result.map_err(|e| {
            CliError::bad_input(format!("cannot reach the service at {}: {}", self.base, one_line(&e.to_string())))
        })?;
        let status = response.status();
        let text = response
            .body_mut()
            .with_config()
            .limit(256 << 20)
            .read_to_string()
            .map_err(|e| CliError::bad_input(format!("{method} {path}: {}", one_line(&e.to_string()))))?;
        let value: Value = serde_json::from_str(&text).unwrap_or(Value::String(text));
        if status.is_success() {
            Ok(value)
        } else {
            let message = value["error"].as_str().map_or_else(|| value.to_string(), str::to_string);
            Err(CliError::bad_input(format!("{method} {path}: {} {message}", status.as_u16())))
        }
    }

    /// Prints WebSocket messages as JSON lines.
    fn watch(&self, count: Option<usize>, out: &mut dyn Write) -> Result<(), CliError> {
        let ws_base = self.base.replacen("http://", "ws://", 1);
        if ws_base.starts_with("https://") {
            return Err(CliError::bad_input("`reach job watch` speaks plain ws:// only (no TLS)"));
        }
        let url = match &self.token {
            Some(t) => format!("{ws_base}/ws?token={t}"),
            None => format!("{ws_base}/ws"),
        };
        let (mut socket, _) = tungstenite::connect(url.as_str()).map_err(|e| {
            CliError::bad_input(format!("cannot watch the service at {}: {}", self.base, one_line(&e.to_string())))
        })?;
        if let tungstenite::stream::MaybeTlsStream::Plain(stream) = socket.get_ref() {
            let _ = stream.set_read_timeout(Some(Duration::from_millis(200)));
        }
        let mut seen = 0;
        let started = Instant::now();
        while count.is_none_or(|n| seen < n) {
            crate::interrupt::check()?;
            match socket.read() {
                Ok(tungstenite::Message::Text(text)) => {
                    writeln!(out, "{}", text.as_str())?;
                    out.flush()?;
                    seen += 1;
                }
                Ok(tungstenite::Message::Close(_)) => break,
                Ok(_) => {}
                Err(tungstenite::Error::Io(e))
                    if matches!(e.kind(), std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut) => {}
                Err(e) => {
                    return Err(CliError::bad_input(format!(
                        "the service closed the stream after {:.1} s: {}",
                        started.elapsed().as_secs_f64(),
                        one_line(&e.to_string())
                    )));
                }
            }
        }
        let _ = socket.close(None);
        Ok(())
    }
}
