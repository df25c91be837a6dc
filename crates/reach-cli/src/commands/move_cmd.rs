//! `reach move` — one motion between two joint vectors or two tool poses, in joint space or in
//! tool space (`reach plan`, in `plan.rs`, computes every motion of a task file). Thin: argv →
//! [`MoveRequest`] → `reach::jobs::motion::move_motion` → render (`move_render.rs`: text, CSV,
//! drawings). `--json` prints the report (docs/schemas/move.report.schema.json).
//!
//! Units on the command line (`crate::pose_arg`): joint values in degrees (radians with
//! `--rad`; prismatic in metres); poses `--from-xyz`/`--to-xyz` in metres with `--…-rpy` (degrees,
//! radians with `--rad`, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`) or `--…-quat`, or `--…-matrix`.
//!
//! Progress: a tool-space motion of at least [`PROGRESS_MIN_SAMPLES`] samples shows a progress
//! bar of its tracking on stderr, only when stdout and stderr are terminals and not with
//! `--json` (`crate::plot::progress`).
//!
//! Exit status: 0 feasible; 3 infeasible (a joint outside its limits or above its speed limit,
//! an unrealisable interval, a collision in `--scene`) after printing the report, with one
//! line on stderr, and without writing `--csv` (a sample table could be driven); 2 for bad
//! input.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use reach::jobs::motion::{ChoiceSpec, End, IntervalChoice, MoveRequest};

use crate::commands::check::read_valid_scene;
use crate::commands::move_render::{infeasible, move_drawing, write_csv, write_report};
use crate::error::CliError;
use crate::numbers::{parse_finite, parse_list};
use crate::output::{verdict_exit, write_json};
use crate::plot::progress::Progress;
use crate::pose_arg::{FromPoseArgs, PoseFlags, ToPoseArgs, flag_table, joints_arg};
use crate::robot_arg::RobotArgs;

pub use reach::jobs::motion::ProfileName;

/// Where the motion is interpolated (`reach::jobs::motion::Space`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SpaceArg {
    /// `q(t) = q0 + λ(τ)·(q1 − q0)`.
    Joint,
    /// Straight tool line, rotation about one fixed axis, IK per sample.
    Tool,
}

/// The time law λ(τ) (`reach::jobs::motion::ProfileName`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ProfileArg {
    /// Seed 001's λ = τ − sin(2πτ)/(2π).
    Cycloidal,
    /// Trapezoidal velocity (a third of the time accelerating, a third decelerating).
    Trapezoid,
    /// Quintic: zero velocity and acceleration at both ends.
    Quintic,
    /// Constant speed.
    Linear,
}

/// Arguments of `reach move`.
#[derive(Debug, Clone, Args)]
pub struct MoveArgs {
    /// The robot.
    #[command(flatten)]
    pub robot: RobotArgs,

    /// Start joint values q1,..,qn (degrees, radians with --rad; prismatic in metres).
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub from: Option<String>,

    /// Target joint values q1,..,qn.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true)]
    pub to: Option<String>,

    /// Start pose (instead of --from).
    #[command(flatten)]
    pub from_pose: FromPoseArgs,

    /// Target pose (instead of --to).
    #[command(flatten)]
    pub to_pose: ToPoseArgs,

    /// Joint values and roll, pitch, yaw are in radians instead of degrees.
    #[arg(long)]
    pub rad: bool,

    /// Interpolate in joint space or in tool space.
    #[arg(long, value_enum, default_value = "joint")]
    pub space: SpaceArg,

    /// Time law (default: cycloidal; linear with --speed).
    #[arg(long, value_enum)]
    pub profile: Option<ProfileArg>,

    /// Duration in seconds (joint space default: the fastest synchronised move within the
    /// robot's speed limits).
    #[arg(long, value_name = "S", allow_hyphen_values = true, conflicts_with = "speed")]
    pub duration: Option<String>,

    /// Tool speed in m/s (tool space only): duration = path length / speed.
    #[arg(long, value_name = "M/S", allow_hyphen_values = true)]
    pub speed: Option<String>,

    /// Sampling step in seconds (default: duration / 100).
    #[arg(long, value_name = "S", allow_hyphen_values = true)]
    pub dt: Option<String>,

    /// Joint weights w1,..,wn of J1/J2 (default: seed 001's for 6 joints, else all 1).
    #[arg(long, value_name = "W1,..,WN", allow_hyphen_values = true)]
    pub joint_weights: Option<String>,

    /// Tool space: choose the configuration of each path interval by motion criteria, as a
    /// task file's `[choose]` (docs/choosing.md): topsis, vikor or weighted-sum.
    #[arg(long, value_name = "METHOD", requires = "criteria")]
    pub choose: Option<String>,

    /// With --choose: the motion criteria, comma-separated (docs/choosing.md).
    #[arg(long, value_name = "C1,..,CK", requires = "choose")]
    pub criteria: Option<String>,

    /// Tool space: the configuration of one path interval, INTERVAL=CONFIGURATION with a label
    /// of the report's `alternatives` (repeat for several intervals; docs/choosing.md).
    #[arg(long, value_name = "INTERVAL=CONFIGURATION")]
    pub choice: Vec<String>,

    /// With --choose: one weight per criterion, >= 0, not all 0 (default equal). Joint weights
    /// of J1/J2 are --joint-weights.
    #[arg(long, value_name = "W1,..,WK", allow_hyphen_values = true, requires = "choose")]
    pub weights: Option<String>,

    /// Scene file (TOML: obstacles, tool zone): the motion is checked continuously against it
    /// (the joint path through the samples, as `reach drive` steps it); a motion not proven
    /// clear is infeasible.
    #[arg(long, value_name = "SCENE")]
    pub scene: Option<String>,

    /// Also write the samples as CSV to FILE (only for a feasible motion).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Print the report as JSON (docs/schemas/move.report.schema.json): samples (t_s, q_deg,
    /// qd_deg_s, xyz_m, rpy_deg), intervals, events, effort (j1, j2, energy_j, energy_note),
    /// feasible, reasons.
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

impl MoveArgs {
    /// The request of these arguments (numbers parsed, nothing computed).
    ///
    /// # Errors
    /// [`CliError::BadInput`] naming the flag.
    pub fn request(&self) -> Result<MoveRequest, CliError> {
        let end = |joints: &Option<String>, pose: PoseFlags, j: &str| -> Result<End, CliError> {
            match (joints, pose.given()) {
                (Some(t), false) => Ok(End::Joints(joints_arg(j, t, self.rad)?)),
                (None, true) => Ok(End::Pose(pose.pose(self.rad)?)),
                _ => Err(CliError::bad_input(format!(
                    "give exactly one of {j} and --{}xyz/--{}matrix",
                    pose.prefix, pose.prefix
                ))),
            }
        };
        let number = |option: &str, text: &Option<String>| text.as_deref().map(|t| parse_finite(option, t)).transpose();
        Ok(MoveRequest {
            name: String::new(),
            from: end(&self.from, self.from_pose.flags(), "--from")?,
            to: end(&self.to, self.to_pose.flags(), "--to")?,
            space: match self.space {
                SpaceArg::Joint => reach::jobs::motion::Space::Joint,
                SpaceArg::Tool => reach::jobs::motion::Space::Tool,
            },
            profile: self.profile.map(|p| match p {
                ProfileArg::Cycloidal => ProfileName::Cycloidal,
                ProfileArg::Trapezoid => ProfileName::Trapezoid,
                ProfileArg::Quintic => ProfileName::Quintic,
                ProfileArg::Linear => ProfileName::Linear,
            }),
            duration_s: number("--duration", &self.duration)?,
            speed_m_s: number("--speed", &self.speed)?,
            dt_s: number("--dt", &self.dt)?,
            joint_weights: self.joint_weights.as_deref().map(|t| parse_list("--joint-weights", t)).transpose()?,
            choose: choice_spec(
                self.choose.as_deref(),
                self.criteria.as_deref(),
                self.weights.as_deref(),
                "--weights",
            )?,
            scene: self.scene.as_deref().map(read_valid_scene).transpose()?,
            choices: self.choice.iter().map(|c| parse_choice(c)).collect::<Result<_, _>>()?,
        })
    }
}

/// One interval's configuration from `INTERVAL=CONFIGURATION` (`--choice`).
///
/// # Errors
/// [`CliError::BadInput`] naming the flag's text when it is not of that form.
pub fn parse_choice(text: &str) -> Result<IntervalChoice, CliError> {
    let bad = |why: String| CliError::bad_input(format!("--choice `{text}`: {why}"));
    let (interval, configuration) =
        text.split_once('=').ok_or_else(|| bad("write INTERVAL=CONFIGURATION, e.g. 1=config=-β".into()))?;
    let interval = interval.trim().parse::<usize>().ok().filter(|&i| i >= 1);
    let interval = interval.ok_or_else(|| bad("the interval must be a whole number ≥ 1".into()))?;
    Ok(IntervalChoice { interval, configuration: configuration.to_string() })
}

/// A tool-space motion's criterion from `--choose METHOD --criteria C1,..,CK [--weights
/// W1,..,WK]` (`weights_flag`: how the weights' flag is spelt, for errors); `None` without a
/// method.
///
/// # Errors
/// [`CliError::BadInput`] for weights that are not numbers.
pub fn choice_spec(
    method: Option<&str>,
    criteria: Option<&str>,
    weights: Option<&str>,
    weights_flag: &str,
) -> Result<Option<ChoiceSpec>, CliError> {
    let Some(method) = method else { return Ok(None) };
    Ok(Some(ChoiceSpec {
        method: method.to_string(),
        criteria: criteria.iter().flat_map(|c| c.split(',')).map(|c| c.trim().to_string()).collect(),
        weights: weights.map(|t| parse_list(weights_flag, t)).transpose()?,
        require: Default::default(),
    }))
}

/// The library's error with the request field named by its flag (`duration_s` → `--duration`,
/// `from.joints` → `--from`, `to.pose.rpy_deg` → `--to-rpy`, `choose.criteria` → `--criteria`).
fn flag_error(args: &MoveArgs, e: reach::Error) -> CliError {
    let fixed = [
        ("from.joints", "--from"),
        ("from", if args.from.is_some() { "--from" } else { "--from-xyz" }),
        ("to.joints", "--to"),
        ("to", if args.to.is_some() { "--to" } else { "--to-xyz" }),
        ("duration_s", "--duration"),
        ("speed_m_s", "--speed"),
        ("dt_s", "--dt"),
        ("joint_weights", "--joint-weights"),
        ("choose.criteria", "--criteria"),
        ("choose.weights", "--weights"),
        ("choose", "--choose"),
        ("choices", "--choice"),
    ];
    let flags = flag_table(&fixed, &[(args.from_pose.flags(), "from.pose"), (args.to_pose.flags(), "to.pose")]);
    crate::error::flagged(e, &flags)
}

/// Tool-space motions with at least this many samples show a progress bar while they are
/// tracked (shorter ones finish before a bar would be read; the default `dt` gives 101).
pub const PROGRESS_MIN_SAMPLES: usize = 1000;

/// A progress hook for the library: one bar per tracked motion of at least
/// [`PROGRESS_MIN_SAMPLES`] samples, made at its first report (which carries the total).
pub(crate) struct Bars {
    /// JSON mode: no bars.
    pub(crate) json: bool,
    /// The bar shown and the motion it is for.
    pub(crate) current: Option<(String, Progress)>,
}

impl Bars {
    /// Reports `done` of `total` samples of the motion `name`.
    pub(crate) fn report(&mut self, name: &str, done: usize, total: usize) {
        if self.json || total < PROGRESS_MIN_SAMPLES {
            return;
        }
        if self.current.as_ref().is_none_or(|(n, _)| n != name) {
            let message = if name.is_empty() { "tracking".to_string() } else { format!("tracking {name}") };
            self.current = Some((name.to_string(), Progress::new(total as u64, &message, false)));
        }
        if let Some((_, bar)) = &self.current {
            bar.set(done as u64);
        }
    }
}

/// Runs `reach move`.
///
/// # Errors
/// See the module docs.
pub fn run(args: &MoveArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = args.robot.load()?.robot;
    let request = args.request()?;
    args.draw.check_files()?;
    let mut bars = Bars { json: args.json, current: None };
    let m = reach::jobs::motion::move_motion_with_progress(
        &robot,
        &request,
        &mut |done, total| bars.report("", done, total),
        crate::interrupt::cancel(),
    )
    .map_err(|e| flag_error(args, e))?;
    drop(bars);
    if args.draw.any() {
        args.draw.write(&move_drawing(&robot, &request, &m))?;
    }
    // A sample table can be driven (`reach drive --motion`): an infeasible motion's is not
    // written. The report and drawings still show why it is infeasible.
    if let (Some(path), true) = (&args.csv, m.feasible) {
        write_csv(path, &robot, &m)?;
    }
    if args.json {
        write_json(out, &m)?;
    } else {
        write_report(out, &m, m.samples.len().div_ceil(20))?;
    }
    verdict_exit(out, (!m.feasible).then(|| infeasible(&m)))
}
