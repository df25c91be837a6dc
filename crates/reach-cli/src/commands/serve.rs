//! `reach serve` — the control service (crate `reach-serve`): parses the options and runs it.

use std::io::Write;
use std::net::SocketAddr;
use std::path::PathBuf;

use clap::Args;

use crate::error::{CliError, one_line};
use crate::robot_arg::{RobotArgs, robot_input};

/// Arguments of `reach serve`.
#[derive(Debug, Clone, Args)]
pub struct ServeArgs {
    /// The robot (preset name or robot file; `--base`/`--tip` for URDF).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// A scene file (TOML): every job's motion must be proven clear of it.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<PathBuf>,

    /// The state directory (database, token); made on the first start.
    #[arg(long, value_name = "DIR", default_value = "reach-state")]
    pub state: PathBuf,

    /// The address to listen on. Beyond loopback every request needs the token in DIR/token.
    #[arg(long, value_name = "ADDR", default_value = "127.0.0.1:7878")]
    pub listen: String,

    /// Simulation speed: 1 = real time, 10 = ten times faster.
    #[arg(long, value_name = "FACTOR", default_value_t = 1.0)]
    pub speed: f64,

    /// A browser origin allowed to call the API (CORS), e.g. http://localhost:5173.
    #[arg(long, value_name = "ORIGIN")]
    pub cors: Option<String>,

    /// Seconds a job waits for the operator's choice of configuration (POST /jobs/ID/choose)
    /// before --operator-choose answers (without it: the default configuration).
    #[arg(long, value_name = "S", default_value_t = reach_serve::service::DEFAULT_OPERATOR_TIMEOUT_S)]
    pub operator_timeout: f64,

    /// What answers when the operator does not: topsis, vikor or weighted-sum over
    /// --operator-criteria (docs/choosing.md).
    #[arg(long, value_name = "METHOD", requires = "operator_criteria")]
    pub operator_choose: Option<String>,

    /// With --operator-choose: the motion criteria, comma-separated.
    #[arg(long, value_name = "C1,..,CK", requires = "operator_choose")]
    pub operator_criteria: Option<String>,

    /// With --operator-choose: one weight per criterion (default equal).
    #[arg(long, value_name = "W1,..,WK", requires = "operator_choose")]
    pub operator_weights: Option<String>,
}

/// Runs the service until Ctrl-C.
///
/// # Errors
/// [`CliError::BadInput`] for a bad robot, scene, address or speed, or a state directory that
/// belongs to another robot; [`CliError::Internal`] when the server fails.
pub fn run(args: &ServeArgs, _out: &mut dyn Write) -> Result<(), CliError> {
    let (robot, _) = robot_input(&args.robot.robot, &args.robot.urdf_chain())?;
    let listen: SocketAddr = args.listen.parse().map_err(|e| {
        CliError::bad_input(format!("--listen `{}`: {e} (write IP:PORT, e.g. 127.0.0.1:7878)", args.listen))
    })?;
    let scene = match &args.scene {
        Some(path) => Some(std::fs::read_to_string(path).map_err(|e| {
            CliError::bad_input(format!("cannot read scene file `{}`: {}", path.display(), one_line(&e.to_string())))
        })?),
        None => None,
    };
    let mut config = reach_serve::Config::new(robot);
    config.scene = scene;
    config.state_dir.clone_from(&args.state);
    config.listen = listen;
    config.speed = args.speed;
    config.cors.clone_from(&args.cors);
    config.operator_timeout_s = args.operator_timeout;
    config.operator_criterion = crate::commands::move_cmd::choice_spec(
        args.operator_choose.as_deref(),
        args.operator_criteria.as_deref(),
        args.operator_weights.as_deref(),
        "--operator-weights",
    )?;
    let cancel = crate::interrupt::cancel().clone();
    let stop = async move {
        while !cancel.is_cancelled() {
            tokio::time::sleep(std::time::Duration::from_millis(100)).await;
        }
    };
    reach_serve::serve(&config, stop).map_err(|e| match e {
        reach_serve::ServeError::Io(m) => CliError::internal(m),
        other => CliError::bad_input(one_line(&other.to_string())),
    })
}
