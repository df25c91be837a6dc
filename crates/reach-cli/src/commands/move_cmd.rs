//! `reach move` — one motion between two joint vectors or two tool poses, in joint space
//! (`q(t) = q0 + λ(τ)·Δq`) or in tool space (straight line, rotation about one fixed axis,
//! tracked through IK with branch continuity); and `reach plan` — the same from a task file
//! (docs/task-format.md) that may list several motions.
//!
//! Units on the command line: joint values in degrees (prismatic in metres), poses
//! `x,y,z,roll,pitch,yaw` in metres and degrees with `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
//!
//! Output: samples (t, q, q̇, tool pose), per-interval status, events (tool space: the
//! K1–K14 log of the tracking), J1 and J2 (seed 001's weights for 6-joint robots, else 1; the
//! wrap policy of `reach::effort::Differences::for_robot`), the mechanical energy
//! `∫ Σ|τᵢ·q̇ᵢ| dt` when the robot file gives link masses (Newton–Euler torques,
//! `reach::effort::dynamics::trajectory_energy_with_rates`; otherwise `null` with the reason in
//! `energy_note`), and a feasibility summary.
//!
//! Progress: a tool-space motion of at least [`PROGRESS_MIN_SAMPLES`] samples shows a progress
//! bar of its tracking on stderr (`reach::motion::tracking::track_with_progress`), only when
//! stdout and stderr are terminals and not with `--json` (`crate::plot::progress`).
//!
//! Exit status: 0 feasible; 3 infeasible (a joint outside its limits, an unrealisable
//! interval) after printing the report, with one line on stderr; 2 for bad input.

use std::io::Write;
use std::path::PathBuf;

use clap::{Args, ValueEnum};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use reach::Robot;
use reach::effort::dynamics::trajectory_energy_with_rates;
use reach::effort::{Differences, j1, j2};
use reach::motion::joint_space::EndChoice;
use reach::motion::sample::PerSampleIk;
use reach::motion::tracking::{TrackedPath, TrackingOptions, describe, track_with_progress};
use reach::motion::{JointMotion, JointRates, Profile, ToolMotion};
use serde::{Deserialize, Serialize};

use crate::error::{CliError, one_line};
use crate::numbers::{display_unit, from_si, joints_outside_limits, q_to_display, to_si};
use crate::output::{fixed, fixeds, rpy_deg, write_json};
use crate::plot::progress::Progress;
use crate::robot_arg::{RobotArgs, load_robot};
use reach::model::UrdfChain;

/// Where the motion is interpolated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Space {
    /// `q(t) = q0 + λ(τ)·(q1 − q0)`.
    Joint,
    /// Straight tool line, rotation about one fixed axis, IK per sample.
    Tool,
}

/// The time law λ(τ).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum ProfileName {
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

    /// Start joint values q1,..,qn (degrees; prismatic in metres).
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true, conflicts_with = "from_pose")]
    pub from: Option<String>,

    /// Target joint values q1,..,qn.
    #[arg(long, value_name = "Q1,..,QN", allow_hyphen_values = true, conflicts_with = "to_pose")]
    pub to: Option<String>,

    /// Start pose x,y,z,roll,pitch,yaw (metres, degrees).
    #[arg(long, value_name = "X,Y,Z,R,P,Y", allow_hyphen_values = true)]
    pub from_pose: Option<String>,

    /// Target pose x,y,z,roll,pitch,yaw (metres, degrees).
    #[arg(long, value_name = "X,Y,Z,R,P,Y", allow_hyphen_values = true)]
    pub to_pose: Option<String>,

    /// Interpolate in joint space or in tool space.
    #[arg(long, value_enum, default_value = "joint")]
    pub space: Space,

    /// Time law (default: cycloidal; linear with --speed).
    #[arg(long, value_enum)]
    pub profile: Option<ProfileName>,

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

    /// With --choose: one weight per criterion, >= 0, not all 0 (default equal). Joint weights
    /// of J1/J2 are --joint-weights.
    #[arg(long, value_name = "W1,..,WK", allow_hyphen_values = true, requires = "choose")]
    pub weights: Option<String>,

    /// Also write the samples as CSV to FILE.
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,

    /// Print JSON: {"robot", "space", "samples": [{"t_s", "q_deg", "qd_deg_s", "xyz_m",
    /// "rpy_deg"}], "intervals", "events", "effort": {"j1", "j2", "energy_j", "energy_note"},
    /// "feasible", "reasons"} (energy_j is null, with the reason in energy_note, when the robot
    /// has no link masses).
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg FILE, --png FILE, --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

/// One end of a motion.
#[derive(Debug, Clone, PartialEq)]
pub enum End {
    /// Joint values in display units (degrees / metres).
    Joints(Vec<f64>),
    /// `[x, y, z, roll, pitch, yaw]` in metres and degrees.
    Pose([f64; 6]),
}

/// Everything one motion needs (from the command line or a task file).
#[derive(Debug, Clone, PartialEq)]
pub struct MoveSpec {
    /// Label (task files).
    pub name: String,
    /// Start.
    pub from: End,
    /// Target.
    pub to: End,
    /// Joint or tool space.
    pub space: Space,
    /// Time law.
    pub profile: Option<ProfileName>,
    /// Seconds.
    pub duration: Option<f64>,
    /// Tool speed in m/s.
    pub speed: Option<f64>,
    /// Sampling step in seconds.
    pub dt: Option<f64>,
    /// J1/J2 weights.
    pub weights: Option<Vec<f64>>,
    /// Per-interval configuration choice in tool space (task files' `[choose]`).
    pub choose: Option<PlanChoice>,
}

/// A task file's `[choose]`: rank the feasible configurations of each tool-space interval by
/// motion criteria (`reach::decide::TrackChooser`; docs/task-format.md).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlanChoice {
    /// `topsis`, `vikor` or `weighted-sum`.
    pub method: String,
    /// Motion criterion names (`reach::decide::motion_criteria::MOTION_CRITERIA`).
    pub criteria: Vec<String>,
    /// One weight per criterion (default equal).
    pub weights: Option<Vec<f64>>,
    /// Hard bounds `criterion = bound` on listed criteria (a maximum for less-is-better, a
    /// minimum for more-is-better ones): a configuration breaking one does not satisfy the
    /// choice; none satisfying it realises the default (K14).
    #[serde(default)]
    pub require: std::collections::BTreeMap<String, f64>,
    /// Given by `reach move --choose/--criteria/--weights` rather than a task file (error
    /// messages then name the flags).
    #[serde(skip)]
    pub from_flags: bool,
}

impl PlanChoice {
    /// The chooser for `robot` (J1/J2 criteria use the motion's `joint_weights`).
    fn chooser<'r>(
        &self,
        robot: &'r Robot,
        joint_weights: Option<&[f64]>,
    ) -> Result<reach::decide::TrackChooser<'r>, CliError> {
        let label = if self.from_flags { "--choose" } else { "[choose]" };
        let bad = |e: reach::decide::DecideError| CliError::bad_input(format!("{label}: {}", one_line(&e.to_string())));
        let method = reach::decide::Method::parse(&self.method).ok_or_else(|| {
            CliError::bad_input(format!(
                "{label} method: unknown `{}` (known: topsis, vikor, weighted-sum)",
                self.method
            ))
        })?;
        let criteria = self
            .criteria
            .iter()
            .map(|n| reach::decide::MotionCriterion::parse(n, robot, joint_weights, None))
            .collect::<Result<Vec<_>, _>>()
            .map_err(bad)?;
        let weights = self.weights.clone().unwrap_or_else(|| vec![1.0; criteria.len()]);
        let mut requirements = Vec::with_capacity(self.require.len());
        for (name, &bound) in &self.require {
            let key = name.replace('-', "_");
            let Some(criterion) = criteria.iter().position(|c| c.describe().name == key) else {
                return Err(CliError::bad_input(format!(
                    "[choose] require: `{name}` is not one of the criteria ({})",
                    self.criteria.join(", ")
                )));
            };
            requirements.push(reach::decide::motion_criteria::Requirement { criterion, bound });
        }
        reach::decide::TrackChooser::new(robot, criteria, weights, method)
            .and_then(|c| c.with_requirements(requirements))
            .map_err(bad)
    }
}

/// One sample of the JSON output (what `reach drive` reads: `t_s`, `q_deg`).
#[derive(Debug, Clone, Serialize)]
pub struct SampleJson {
    /// Time.
    pub t_s: f64,
    /// Joint values (degrees; prismatic metres).
    pub q_deg: Vec<f64>,
    /// Joint rates (degrees/s; prismatic m/s).
    pub qd_deg_s: Vec<f64>,
    /// Tool position.
    pub xyz_m: [f64; 3],
    /// Tool orientation.
    pub rpy_deg: [f64; 3],
}

/// One interval of the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct IntervalJson {
    /// Start time.
    pub start_s: f64,
    /// End time.
    pub end_s: f64,
    /// Configuration realised (`joint` for a joint-space move, a branch label in tool space,
    /// `null` when none is feasible).
    pub configuration: Option<String>,
    /// Whether the interval is realised within every limit.
    pub feasible: bool,
    /// Every limit broken (by any configuration tracked), with where.
    pub reasons: Vec<String>,
    /// How the configuration was chosen (tool space): `default`, `only_feasible`,
    /// `first_feasible`, `criterion` (`[choose]`), `criterion_rejected` (K14), `not_realizable`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub decision: Option<reach::motion::tracking::Decision>,
}

/// One event of the JSON output.
#[derive(Debug, Clone, Serialize)]
pub struct EventJson {
    /// Time.
    pub t_s: f64,
    /// `K1` … `K14`.
    pub code: String,
    /// The text as operators read it (angles in degrees; `reach::motion::tracking::describe`).
    pub message: String,
}

/// Effort functionals.
#[derive(Debug, Clone, Serialize)]
pub struct EffortJson {
    /// `Σ wᵢ|qᵢ(t1) − qᵢ(t0)|` (radians).
    pub j1: f64,
    /// `Σ wᵢ·(total variation of qᵢ over the samples)` (radians).
    pub j2: f64,
    /// Mechanical energy `∫ Σ|τᵢ·q̇ᵢ| dt`, joules (rigid links, no friction); `null` when it
    /// cannot be computed (see `energy_note`).
    pub energy_j: Option<f64>,
    /// Why `energy_j` is `null` (e.g. no link masses in the robot file); `null` otherwise.
    pub energy_note: Option<String>,
    /// The weights used.
    pub weights: Vec<f64>,
}

/// The JSON output of one motion.
#[derive(Debug, Clone, Serialize)]
pub struct MoveJson {
    /// Task label (empty on the command line).
    pub name: String,
    /// Robot name.
    pub robot: String,
    /// `joint` or `tool`.
    pub space: Space,
    /// Duration in seconds.
    pub duration_s: f64,
    /// The samples.
    pub samples: Vec<SampleJson>,
    /// Per-interval status.
    pub intervals: Vec<IntervalJson>,
    /// Event log (tool space: K1–K14).
    pub events: Vec<EventJson>,
    /// J1, J2, energy.
    pub effort: EffortJson,
    /// Whether the whole motion respects every limit.
    pub feasible: bool,
    /// Why not, one line each.
    pub reasons: Vec<String>,
}

fn parse_list(option: &str, text: &str) -> Result<Vec<f64>, CliError> {
    text.split([',', ' '])
        .filter(|s| !s.trim().is_empty())
        .enumerate()
        .map(|(i, s)| {
            let v: f64 = s
                .trim()
                .parse()
                .map_err(|_| CliError::bad_input(format!("{option}: value {}: expected a number, got {s:?}", i + 1)))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(CliError::bad_input(format!("{option}: value {}: expected a finite number, got {s:?}", i + 1)))
            }
        })
        .collect()
}

fn parse_number(option: &str, text: &str) -> Result<f64, CliError> {
    let v = parse_list(option, text)?;
    match v.as_slice() {
        [x] => Ok(*x),
        _ => Err(CliError::bad_input(format!("{option}: expected one number, got {text:?}"))),
    }
}

/// Parses `x,y,z,roll,pitch,yaw` (metres, degrees) into [`End::Pose`].
pub(crate) fn pose_end(option: &str, text: &str) -> Result<End, CliError> {
    let v = parse_list(option, text)?;
    let a: [f64; 6] = v.as_slice().try_into().map_err(|_| {
        CliError::bad_input(format!("{option}: expected x,y,z,roll,pitch,yaw (6 numbers), got {}", v.len()))
    })?;
    Ok(End::Pose(a))
}

impl MoveArgs {
    fn spec(&self) -> Result<MoveSpec, CliError> {
        let end = |joints: &Option<String>, pose: &Option<String>, j: &str, p: &str| -> Result<End, CliError> {
            match (joints, pose) {
                (Some(t), None) => Ok(End::Joints(parse_list(j, t)?)),
                (None, Some(t)) => pose_end(p, t),
                _ => Err(CliError::bad_input(format!("give exactly one of {j} and {p}"))),
            }
        };
        Ok(MoveSpec {
            name: String::new(),
            from: end(&self.from, &self.from_pose, "--from", "--from-pose")?,
            to: end(&self.to, &self.to_pose, "--to", "--to-pose")?,
            space: self.space,
            profile: self.profile,
            duration: self.duration.as_deref().map(|t| parse_number("--duration", t)).transpose()?,
            speed: self.speed.as_deref().map(|t| parse_number("--speed", t)).transpose()?,
            dt: self.dt.as_deref().map(|t| parse_number("--dt", t)).transpose()?,
            weights: self.joint_weights.as_deref().map(|t| parse_list("--joint-weights", t)).transpose()?,
            choose: match (&self.choose, self.space) {
                (None, _) => None,
                (Some(_), Space::Joint) => {
                    return Err(CliError::bad_input(
                        "--choose: a joint-space move has no configuration to choose; use --space tool",
                    ));
                }
                (Some(method), Space::Tool) => Some(PlanChoice {
                    method: method.clone(),
                    criteria: self.criteria.iter().flat_map(|c| c.split(',')).map(|c| c.trim().to_string()).collect(),
                    weights: self.weights.as_deref().map(|t| parse_list("--weights", t)).transpose()?,
                    require: Default::default(),
                    from_flags: true,
                }),
            },
        })
    }
}

/// The pose of `[x, y, z, roll, pitch, yaw]` (metres, degrees).
pub(crate) fn pose_of(v: &[f64; 6]) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(v[0], v[1], v[2]),
        UnitQuaternion::from_euler_angles(v[3].to_radians(), v[4].to_radians(), v[5].to_radians()),
    )
}

fn joints_si(robot: &Robot, option: &str, values: &[f64]) -> Result<Vec<f64>, CliError> {
    if values.len() != robot.dof() {
        return Err(CliError::bad_input(format!(
            "{option}: {} values, expected {} (one per joint of {})",
            values.len(),
            robot.dof(),
            robot.name()
        )));
    }
    Ok(robot.joints().iter().zip(values).map(|(j, v)| to_si(j.kind, *v, crate::numbers::AngleInput::Degrees)).collect())
}

fn motion_error(e: impl std::fmt::Display) -> CliError {
    CliError::bad_input(one_line(&e.to_string()))
}

pub(crate) fn profile_of(name: Option<ProfileName>, default: ProfileName) -> Result<Profile, CliError> {
    Ok(match name.unwrap_or(default) {
        ProfileName::Cycloidal => Profile::Cycloidal,
        ProfileName::Quintic => Profile::Quintic,
        ProfileName::Linear => Profile::Linear,
        ProfileName::Trapezoid => Profile::trapezoidal(1.0 / 3.0).map_err(motion_error)?,
    })
}

fn check_positive(name: &str, v: Option<f64>) -> Result<(), CliError> {
    match v {
        Some(x) if x <= 0.0 => Err(CliError::bad_input(format!("{name} must be > 0, got {x}"))),
        _ => Ok(()),
    }
}

/// Tool-space motions with at least this many samples show a progress bar while they are
/// tracked (shorter ones finish before a bar would be read; the default `dt` gives 101).
pub const PROGRESS_MIN_SAMPLES: usize = 1000;

/// Computes one motion (no output but the progress bar). Bad input is an error; infeasibility
/// is in the result.
///
/// # Arguments
/// * `progress` — whether a progress bar may be shown (false in JSON mode); it is shown only
///   for tool-space motions of at least [`PROGRESS_MIN_SAMPLES`] samples and when stdout and
///   stderr are terminals.
///
/// # Errors
/// [`CliError::BadInput`] for wrong counts, non-positive durations, unreachable end poses.
pub fn compute(robot: &Robot, spec: &MoveSpec, progress: bool) -> Result<MoveJson, CliError> {
    check_positive("duration", spec.duration)?;
    check_positive("speed", spec.speed)?;
    check_positive("dt", spec.dt)?;
    let weights = reach::effort::joint_weights(robot, spec.weights.as_deref())
        .map_err(|e| CliError::bad_input(format!("weights: {e}")))?;
    let (times, q, qd, intervals, events) = match spec.space {
        Space::Joint => joint_space(robot, spec)?,
        Space::Tool => tool_space(robot, spec, progress)?,
    };
    let differences = Differences::for_robot(robot);
    let (j1v, j2v) = match (q.first(), q.last()) {
        (Some(a), Some(b)) => (
            j1(a, b, &weights, &differences).map_err(motion_error)?,
            j2(&q, &weights, &differences).map_err(motion_error)?,
        ),
        _ => (0.0, 0.0),
    };
    let (energy_j, energy_note) = match trajectory_energy_with_rates(robot, &times, &q, &qd) {
        Ok(e) => (Some(e), None),
        Err(e) => (None, Some(e.to_string())),
    };
    let mut samples = Vec::with_capacity(q.len());
    for ((t, qk), qdk) in times.iter().zip(&q).zip(&qd) {
        let pose = robot.fk(qk).map_err(motion_error)?;
        let v = pose.translation.vector;
        samples.push(SampleJson {
            t_s: *t,
            q_deg: q_to_display(robot, qk),
            qd_deg_s: q_to_display(robot, qdk),
            xyz_m: [v.x, v.y, v.z],
            rpy_deg: rpy_deg(&pose.rotation),
        });
    }
    let reasons: Vec<String> =
        intervals.iter().filter(|i| !i.feasible).flat_map(|i| i.reasons.iter().cloned()).collect();
    let feasible = intervals.iter().all(|i| i.feasible) && !samples.is_empty();
    Ok(MoveJson {
        name: spec.name.clone(),
        robot: robot.name().to_string(),
        space: spec.space,
        duration_s: times.last().copied().unwrap_or(0.0) - times.first().copied().unwrap_or(0.0),
        samples,
        intervals,
        events,
        effort: EffortJson { j1: j1v, j2: j2v, energy_j, energy_note, weights },
        feasible,
        reasons,
    })
}

type Computed = (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<IntervalJson>, Vec<EventJson>);

fn joint_space(robot: &Robot, spec: &MoveSpec) -> Result<Computed, CliError> {
    if spec.speed.is_some() {
        return Err(CliError::bad_input("--speed (a tool speed) needs --space tool; use --duration"));
    }
    let profile = profile_of(spec.profile, ProfileName::Cycloidal)?;
    let motion = match (&spec.from, &spec.to) {
        (End::Joints(a), End::Joints(b)) => {
            let (q0, q1) = (joints_si(robot, "from", a)?, joints_si(robot, "to", b)?);
            match spec.duration {
                Some(d) => JointMotion::for_robot(robot, &q0, &q1, 0.0, d, profile).map_err(motion_error)?,
                None => {
                    let rates = JointRates::from_robot(robot, None)
                        .map_err(|e| CliError::bad_input(format!("give --duration: {}", one_line(&e.to_string()))))?;
                    JointMotion::synchronised(robot, &q0, &q1, 0.0, &rates, profile).map_err(motion_error)?.0
                }
            }
        }
        (End::Pose(a), End::Pose(b)) => {
            let d = spec.duration.ok_or_else(|| CliError::bad_input("a move between poses needs --duration"))?;
            JointMotion::between_poses(robot, &pose_of(a), &pose_of(b), 0.0, d, profile, &EndChoice::default())
                .map_err(motion_error)?
        }
        _ => return Err(CliError::bad_input("give both ends as joint values or both as poses")),
    };
    let dt = spec.dt.unwrap_or(motion.duration() / 100.0);
    let traj = motion.sample(dt).map_err(motion_error)?;
    let times = traj.times();
    let q: Vec<Vec<f64>> = traj.samples.iter().map(|s| s.q.clone()).collect();
    let qd: Vec<Vec<f64>> = times.iter().map(|t| motion.velocity(*t)).collect();
    let reasons = limit_reasons(robot, &times, &q, &qd);
    let interval = IntervalJson {
        start_s: motion.t0(),
        end_s: motion.t1(),
        configuration: Some("joint".into()),
        feasible: reasons.is_empty(),
        reasons,
        decision: None,
    };
    Ok((times, q, qd, vec![interval], Vec::new()))
}

/// Stretches of samples where a joint is outside its range or above its speed limit.
fn limit_reasons(robot: &Robot, times: &[f64], q: &[Vec<f64>], qd: &[Vec<f64>]) -> Vec<String> {
    let mut out = Vec::new();
    for (i, joint) in robot.joints().iter().enumerate() {
        let unit = display_unit(joint.kind);
        let shown = |v: f64| from_si(joint.kind, v, crate::numbers::AngleInput::Degrees);
        let position = |k: usize| !joints_outside_limits(robot, &q[k]).contains(&(i + 1));
        let speed = |k: usize| joint.max_velocity.is_none_or(|m| qd[k][i].abs() <= m * (1.0 + 1e-9));
        for (what, ok, text) in [
            (
                "position",
                &position as &dyn Fn(usize) -> bool,
                format!(
                    "outside {} .. {} {unit}",
                    fixed(shown(joint.limits.lower), 3),
                    fixed(shown(joint.limits.upper), 3)
                ),
            ),
            ("speed", &speed, format!("above {} {unit}/s", joint.max_velocity.map_or(0.0, shown))),
        ] {
            let mut k = 0;
            while k < times.len() {
                if ok(k) {
                    k += 1;
                    continue;
                }
                let start = k;
                while k < times.len() && !ok(k) {
                    k += 1;
                }
                out.push(format!(
                    "joint {} ({}) {what} {text} from t = {} s to t = {} s",
                    i + 1,
                    joint.name,
                    fixed(times[start], 3),
                    fixed(times[k - 1], 3)
                ));
            }
        }
    }
    out
}

fn tool_space(robot: &Robot, spec: &MoveSpec, progress: bool) -> Result<Computed, CliError> {
    let pose_end = |end: &End, which: &str| -> Result<Isometry3<f64>, CliError> {
        match end {
            End::Pose(p) => Ok(pose_of(p)),
            End::Joints(v) => robot.fk(&joints_si(robot, which, v)?).map_err(motion_error),
        }
    };
    let (start, end) = (pose_end(&spec.from, "from")?, pose_end(&spec.to, "to")?);
    let motion = match (spec.duration, spec.speed) {
        (Some(d), None) => ToolMotion::new(start, end, 0.0, d, profile_of(spec.profile, ProfileName::Cycloidal)?)
            .map_err(motion_error)?,
        (None, Some(v)) => {
            let length = (end.translation.vector - start.translation.vector).norm();
            if length <= 0.0 {
                return Err(CliError::bad_input("--speed: the tool point does not move; give --duration"));
            }
            ToolMotion::new(start, end, 0.0, length / v, profile_of(spec.profile, ProfileName::Linear)?)
                .map_err(motion_error)?
        }
        _ => return Err(CliError::bad_input("a tool-space move needs --duration or --speed")),
    };
    let dt = spec.dt.unwrap_or(motion.duration() / 100.0);
    let path = motion.sample_time(dt).map_err(motion_error)?;
    let tracked = TrackedPath::sampled(&path.samples).map_err(motion_error)?;
    let chooser = spec.choose.as_ref().map(|c| c.chooser(robot, spec.weights.as_deref())).transpose()?;
    let criterion = chooser.as_ref().map(|c| c as &dyn reach::motion::tracking::Criterion);
    // The bar is made at the first report, which carries the total.
    let bar: std::cell::OnceCell<Progress> = std::cell::OnceCell::new();
    let show = progress && path.samples.len() >= PROGRESS_MIN_SAMPLES;
    let message = if spec.name.is_empty() { "tracking".to_string() } else { format!("tracking {}", spec.name) };
    let report = track_with_progress(robot, &tracked, &TrackingOptions::default(), criterion, &|done, total| {
        if show {
            bar.get_or_init(|| Progress::new(total as u64, &message, false)).set(done as u64);
        }
    })
    .map_err(motion_error)?;
    drop(bar);
    // Samples: the realised trajectory when every interval is realised; otherwise the per-sample
    // IK nearest to the previous sample with the limits ignored (so that J1/J2 and the curves
    // are still reported next to the reasons), or the realised part when even that fails.
    let fallback = if report.feasible {
        None
    } else {
        path.to_joints(robot, &PerSampleIk { allow_outside_limits: true, ..PerSampleIk::default() }).ok()
    };
    let (times, q): (Vec<f64>, Vec<Vec<f64>>) = match fallback {
        Some(traj) => (traj.times(), traj.samples.into_iter().map(|s| s.q).collect()),
        None => {
            (report.trajectory.iter().map(|p| p.t).collect(), report.trajectory.iter().map(|p| p.q.clone()).collect())
        }
    };
    let qd = central_rates(robot, &times, &q);
    let intervals = report
        .intervals
        .iter()
        .map(|iv| {
            let mut reasons = Vec::new();
            if !iv.reachable {
                reasons.push(format!("outside the workspace from t = {} s to t = {} s", fixed(iv.t_start, 3), fixed(iv.t_end, 3)));
            }
            for (c, track) in iv.configurations.iter().enumerate() {
                for v in &track.violations {
                    let joint = v.joint.map_or_else(|| "branch lost".to_string(), |j| format!("joint {j} ({})", v.name));
                    let unit = v.joint.map_or("", |j| display_unit(robot.joints()[j - 1].kind));
                    let shown = |x: f64| {
                        v.joint.map_or(x, |j| from_si(robot.joints()[j - 1].kind, x, crate::numbers::AngleInput::Degrees))
                    };
                    reasons.push(format!(
                        "configuration {} ({}): {joint} {} limit {} .. {} {unit} broken (worst {}) from t = {} s to t = {} s",
                        c,
                        report.configurations.get(c).map(ToString::to_string).unwrap_or_default(),
                        format!("{:?}", v.kind).to_lowercase(),
                        fixed(shown(v.lower), 3),
                        fixed(shown(v.upper), 3),
                        fixed(shown(v.worst), 3),
                        fixed(v.t_start, 3),
                        fixed(v.t_end, 3)
                    ));
                }
            }
            IntervalJson {
                start_s: iv.t_start,
                end_s: iv.t_end,
                configuration: iv.chosen.and_then(|c| report.configurations.get(c)).map(ToString::to_string),
                feasible: iv.chosen.is_some(),
                reasons,
                decision: Some(iv.decision),
            }
        })
        .collect();
    let events = report
        .events
        .iter()
        .map(|e| EventJson { t_s: e.t, code: e.code.as_str().into(), message: describe(e, robot, true) })
        .collect();
    Ok((times, q, qd, intervals, events))
}

/// Central differences of the (continuous, unwrapped) tracked joint vectors.
fn central_rates(robot: &Robot, t: &[f64], q: &[Vec<f64>]) -> Vec<Vec<f64>> {
    let n = q.len();
    let differences = Differences::for_robot(robot);
    if n < 2 {
        return vec![vec![0.0; robot.dof()]; n];
    }
    (0..n)
        .map(|k| {
            let (a, b) = (k.saturating_sub(1), (k + 1).min(n - 1));
            let h = t[b] - t[a];
            // Wrap-safe differences: a ±180° crossing is no spike.
            (0..q[a].len()).map(|i| if h > 0.0 { differences.diff(i, q[a][i], q[b][i]) / h } else { 0.0 }).collect()
        })
        .collect()
}

fn write_csv(path: &PathBuf, m: &MoveJson) -> Result<(), CliError> {
    let dof = m.samples.first().map_or(0, |s| s.q_deg.len());
    let mut text = String::from("t_s");
    for i in 1..=dof {
        text.push_str(&format!(",q{i}"));
    }
    for i in 1..=dof {
        text.push_str(&format!(",qd{i}"));
    }
    text.push_str(",x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg\n");
    for s in &m.samples {
        let cells: Vec<String> = std::iter::once(s.t_s)
            .chain(s.q_deg.iter().copied())
            .chain(s.qd_deg_s.iter().copied())
            .chain(s.xyz_m)
            .chain(s.rpy_deg)
            .map(|v| format!("{v}"))
            .collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    std::fs::write(path, text).map_err(|e| CliError::bad_input(format!("--csv {}: {e}", path.display())))
}

/// Writes the human-readable report of one motion.
///
/// # Errors
/// Output errors.
pub fn write_report(out: &mut dyn Write, m: &MoveJson, every: usize) -> Result<(), CliError> {
    let title = if m.name.is_empty() { String::new() } else { format!("{}: ", m.name) };
    writeln!(
        out,
        "{title}{} move of {}, {} s, {} samples",
        match m.space {
            Space::Joint => "joint-space",
            Space::Tool => "tool-space",
        },
        m.robot,
        fixed(m.duration_s, 3),
        m.samples.len()
    )?;
    writeln!(out, "  t [s]      q [deg]                                    xyz [m]")?;
    let step = every.max(1);
    for (k, s) in m.samples.iter().enumerate() {
        if k % step == 0 || k + 1 == m.samples.len() {
            writeln!(out, "  {:<9}  {:<42} {}", fixed(s.t_s, 3), fixeds(&s.q_deg, 3), fixeds(&s.xyz_m, 4))?;
        }
    }
    for iv in &m.intervals {
        writeln!(
            out,
            "  interval {} .. {} s: {} ({}){}",
            fixed(iv.start_s, 3),
            fixed(iv.end_s, 3),
            if iv.feasible { "feasible" } else { "NOT feasible" },
            iv.configuration.as_deref().unwrap_or("no configuration"),
            match iv.decision {
                Some(reach::motion::tracking::Decision::Criterion) => ", chosen by the criteria",
                Some(reach::motion::tracking::Decision::CriterionRejected) => ", criteria not met: default kept (K14)",
                _ => "",
            }
        )?;
        for r in &iv.reasons {
            writeln!(out, "    {r}")?;
        }
    }
    for e in &m.events {
        writeln!(out, "  {} [t = {} s] {}", e.code, fixed(e.t_s, 3), e.message)?;
    }
    let energy = match (m.effort.energy_j, &m.effort.energy_note) {
        (Some(e), _) => format!("{} J", fixed(e, 3)),
        (None, note) => format!("n/a ({})", note.as_deref().unwrap_or("not computed")),
    };
    writeln!(out, "  J1 = {}  J2 = {}  energy: {energy}", fixed(m.effort.j1, 6), fixed(m.effort.j2, 6))?;
    writeln!(
        out,
        "  {}",
        if m.feasible { "feasible".to_string() } else { format!("INFEASIBLE: {} reason(s)", m.reasons.len()) }
    )?;
    Ok(())
}

fn infeasible(m: &MoveJson) -> CliError {
    CliError::NoSolution(format!(
        "motion{} infeasible: {}",
        if m.name.is_empty() { String::new() } else { format!(" `{}`", m.name) },
        m.reasons.first().cloned().unwrap_or_else(|| "no feasible samples".into())
    ))
}

/// Runs `reach move`.
///
/// # Errors
/// See the module docs.
pub fn run(args: &MoveArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let robot = args.robot.load()?.robot;
    let spec = args.spec()?;
    args.draw.check_files()?;
    let m = compute(&robot, &spec, !args.json)?;
    if args.draw.any() {
        args.draw.write(&move_drawing(&robot, &spec, &m))?;
    }
    if let Some(path) = &args.csv {
        write_csv(path, &m)?;
    }
    if args.json {
        write_json(out, &m)?;
    } else {
        write_report(out, &m, m.samples.len().div_ceil(20))?;
    }
    if m.feasible {
        Ok(())
    } else {
        out.flush()?;
        Err(infeasible(&m))
    }
}

// ---------------------------------------------------------------------------------------------
// reach plan
// ---------------------------------------------------------------------------------------------

/// Arguments of `reach plan`.
#[derive(Debug, Clone, Args)]
pub struct PlanArgs {
    /// Task file (TOML, docs/task-format.md).
    #[arg(value_name = "TASK")]
    pub task: PathBuf,

    /// Print JSON: {"task", "motions": [… as `reach move --json` …]}.
    #[arg(long)]
    pub json: bool,

    /// Drawings: --svg DIR, --png DIR (one file per motion), --png-width PX.
    #[command(flatten)]
    pub draw: crate::plot::DrawArgs,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TaskFile {
    robot: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    defaults: MotionFile,
    #[serde(rename = "motion")]
    motions: Vec<MotionFile>,
    choose: Option<PlanChoice>,
}

#[derive(Debug, Default, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionFile {
    name: Option<String>,
    from: Option<Vec<f64>>,
    to: Option<Vec<f64>>,
    from_pose: Option<Vec<f64>>,
    to_pose: Option<Vec<f64>>,
    space: Option<Space>,
    profile: Option<ProfileName>,
    duration: Option<f64>,
    speed: Option<f64>,
    dt: Option<f64>,
    weights: Option<Vec<f64>>,
}

/// The JSON output of `reach plan`.
#[derive(Debug, Serialize)]
pub struct PlanJson {
    /// Robot name.
    pub robot: String,
    /// The task's description.
    pub description: String,
    /// One report per motion.
    pub motions: Vec<MoveJson>,
}

fn file_end(joints: &Option<Vec<f64>>, pose: &Option<Vec<f64>>, j: &str, p: &str, name: &str) -> Result<End, CliError> {
    match (joints, pose) {
        (Some(v), None) => Ok(End::Joints(v.clone())),
        (None, Some(v)) => {
            let a: [f64; 6] = v.as_slice().try_into().map_err(|_| {
                CliError::bad_input(format!(
                    "motion `{name}`: {p} needs 6 numbers x,y,z,roll,pitch,yaw, got {}",
                    v.len()
                ))
            })?;
            Ok(End::Pose(a))
        }
        _ => Err(CliError::bad_input(format!("motion `{name}`: give exactly one of `{j}` and `{p}`"))),
    }
}

/// Reads a task file into its robot, description and motions.
///
/// # Errors
/// [`CliError::BadInput`] for an unreadable or malformed file.
pub fn load_task(text: &str, origin: &str) -> Result<(Robot, String, Vec<MoveSpec>), CliError> {
    let file: TaskFile =
        toml::from_str(text).map_err(|e| CliError::bad_input(format!("{origin}: {}", one_line(&e.to_string()))))?;
    let robot = load_robot(&file.robot, &UrdfChain { base: None, tip: None })?.robot;
    let d = &file.defaults;
    let mut specs = Vec::new();
    for (k, m) in file.motions.iter().enumerate() {
        let name = m.name.clone().unwrap_or_else(|| format!("motion {}", k + 1));
        let from = file_end(
            &m.from.clone().or(d.from.clone()),
            &m.from_pose.clone().or(d.from_pose.clone()),
            "from",
            "from_pose",
            &name,
        )?;
        let to =
            file_end(&m.to.clone().or(d.to.clone()), &m.to_pose.clone().or(d.to_pose.clone()), "to", "to_pose", &name)?;
        for v in [m.duration, m.speed, m.dt].into_iter().flatten() {
            if !v.is_finite() {
                return Err(CliError::bad_input(format!("motion `{name}`: non-finite number {v}")));
            }
        }
        specs.push(MoveSpec {
            name,
            from,
            to,
            space: m.space.or(d.space).unwrap_or(Space::Joint),
            profile: m.profile.or(d.profile),
            duration: m.duration.or(d.duration),
            speed: m.speed.or(d.speed),
            dt: m.dt.or(d.dt),
            weights: m.weights.clone().or(d.weights.clone()),
            choose: file.choose.clone(),
        });
    }
    if specs.is_empty() {
        return Err(CliError::bad_input(format!("{origin}: no [[motion]]")));
    }
    Ok((robot, file.description, specs))
}

/// Computes every motion of a task (no progress bar).
///
/// # Errors
/// As [`compute`]; the message names the motion.
pub fn plan(robot: &Robot, specs: &[MoveSpec]) -> Result<Vec<MoveJson>, CliError> {
    plan_with_progress(robot, specs, false)
}

/// [`plan`] that may show a progress bar for long tool-space motions (see [`compute`]).
///
/// # Errors
/// As [`plan`].
pub fn plan_with_progress(robot: &Robot, specs: &[MoveSpec], progress: bool) -> Result<Vec<MoveJson>, CliError> {
    specs
        .iter()
        .map(|s| {
            compute(robot, s, progress)
                .map_err(|e| CliError::bad_input(format!("motion `{}`: {}", s.name, one_line(&e.to_string()))))
        })
        .collect()
}

/// Runs `reach plan`.
///
/// # Errors
/// See the module docs.
pub fn run_plan(args: &PlanArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let text = std::fs::read_to_string(&args.task)
        .map_err(|e| CliError::bad_input(format!("{}: {e}", args.task.display())))?;
    let (robot, description, specs) = load_task(&text, &args.task.display().to_string())?;
    let motions = plan_with_progress(&robot, &specs, !args.json)?;
    write_plan_drawings(&args.draw, &robot, &specs, &motions)?;
    if args.json {
        write_json(
            out,
            &PlanJson { robot: robot.name().to_string(), description: description.clone(), motions: motions.clone() },
        )?;
    } else {
        if !description.is_empty() {
            writeln!(out, "{description}")?;
        }
        for m in &motions {
            write_report(out, m, m.samples.len().div_ceil(10))?;
        }
        write_comparison(out, &motions)?;
    }
    match motions.iter().find(|m| !m.feasible) {
        Some(m) => {
            out.flush()?;
            Err(infeasible(m))
        }
        None => Ok(()),
    }
}

/// A one-line-per-motion comparison table (J1, J2, feasibility).
///
/// # Errors
/// Output errors.
pub fn write_comparison(out: &mut dyn Write, motions: &[MoveJson]) -> Result<(), CliError> {
    writeln!(out, "comparison:")?;
    for m in motions {
        writeln!(
            out,
            "  {:<24} {:<5} J1 = {}  J2 = {}  {}",
            m.name,
            match m.space {
                Space::Joint => "joint",
                Space::Tool => "tool",
            },
            fixed(m.effort.j1, 6),
            fixed(m.effort.j2, 6),
            if m.feasible { "feasible".to_string() } else { format!("infeasible ({})", m.reasons.len()) }
        )?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Drawings (--svg / --png) of `reach move` and `reach plan`
// ---------------------------------------------------------------------------------------------

/// The joint curves and tool path of one computed motion.
fn move_drawing(robot: &Robot, spec: &MoveSpec, m: &MoveJson) -> crate::plot::Svg {
    use crate::plot::drawings::{TrajectoryDrawing, joint_series, title, trajectory};
    let default =
        if spec.space == Space::Tool && spec.speed.is_some() { ProfileName::Linear } else { ProfileName::Cycloidal };
    let profile = spec.profile.unwrap_or(default);
    let profile = profile.to_possible_value().map_or_else(String::new, |v| v.get_name().to_string());
    let space = match m.space {
        Space::Joint => "joint-space",
        Space::Tool => "tool-space",
    };
    let label = if m.name.is_empty() { String::new() } else { format!("{}: ", m.name) };
    let q: Vec<Vec<f64>> = m.samples.iter().map(|s| s.q_deg.clone()).collect();
    let qd: Vec<Vec<f64>> = m.samples.iter().map(|s| s.qd_deg_s.clone()).collect();
    trajectory(&TrajectoryDrawing {
        title: title(robot, &format!("{label}{space} move, {profile} profile, {} s", fixed(m.duration_s, 3))),
        times: m.samples.iter().map(|s| s.t_s).collect(),
        joints: joint_series(robot, &q, &qd),
        tool: m.samples.iter().map(|s| s.xyz_m).collect(),
        tool_waypoints: Vec::new(),
        obstacles: &[],
    })
}

/// `reach plan --svg DIR / --png DIR`: one drawing per motion, `DIR/motion-K.svg` (`.png`).
fn write_plan_drawings(
    draw: &crate::plot::DrawArgs,
    robot: &Robot,
    specs: &[MoveSpec],
    motions: &[MoveJson],
) -> Result<(), CliError> {
    for (option, dir) in [("--svg", &draw.svg), ("--png", &draw.png)] {
        if let Some(dir) = dir {
            crate::plot::ensure_dir(option, dir)?;
        }
    }
    for (k, (spec, m)) in specs.iter().zip(motions).enumerate() {
        let drawing = move_drawing(robot, spec, m);
        if let Some(dir) = &draw.svg {
            crate::plot::write_svg("--svg", &dir.join(format!("motion-{}.svg", k + 1)), &drawing)?;
        }
        if let Some(dir) = &draw.png {
            crate::plot::write_png("--png", &dir.join(format!("motion-{}.png", k + 1)), &drawing, draw.png_width)?;
        }
    }
    Ok(())
}

/// The seed examples, embedded so that `reach demo` runs from any directory.
const SEED001_TASK: &str = include_str!("../../../../examples/seed001_tool_vs_joint.toml");
const SEED003_TASK: &str = include_str!("../../../../examples/seed003_welding.toml");

/// `reach demo` section: seed 001, J1 and J2 of the joint-space and tool-space motions.
///
/// # Errors
/// Output errors; [`CliError::Internal`] if the embedded example breaks.
pub fn demo_seed001(out: &mut dyn Write) -> Result<(), CliError> {
    let (robot, description, specs) = load_task(SEED001_TASK, "examples/seed001_tool_vs_joint.toml")
        .map_err(|e| CliError::internal(e.to_string()))?;
    let motions = plan(&robot, &specs).map_err(|e| CliError::internal(e.to_string()))?;
    writeln!(out)?;
    writeln!(out, "{description} (reach plan examples/seed001_tool_vs_joint.toml)")?;
    write_comparison(out, &motions)?;
    writeln!(
        out,
        "  J_tool > J_joint, as the thesis claims; its printed 0.6981 / 1.3307 are not reproducible (notes 001 §6)."
    )?;
    if let Some(tool) = motions.iter().find(|m| m.space == Space::Tool) {
        for r in tool.reasons.iter().take(2) {
            writeln!(out, "  tool space: {r}")?;
        }
    }
    Ok(())
}

/// `reach demo` section: seed 003, per-configuration feasibility of the weld and the events.
///
/// # Errors
/// Output errors; [`CliError::Internal`] if the embedded example breaks.
pub fn demo_seed003(out: &mut dyn Write) -> Result<(), CliError> {
    let (robot, description, specs) =
        load_task(SEED003_TASK, "examples/seed003_welding.toml").map_err(|e| CliError::internal(e.to_string()))?;
    let motions = plan(&robot, &specs).map_err(|e| CliError::internal(e.to_string()))?;
    writeln!(out)?;
    writeln!(out, "{description} (reach plan examples/seed003_welding.toml)")?;
    for m in &motions {
        for iv in &m.intervals {
            writeln!(
                out,
                "  interval {} .. {} s: realised in {}",
                fixed(iv.start_s, 3),
                fixed(iv.end_s, 3),
                iv.configuration.as_deref().unwrap_or("no configuration")
            )?;
            for r in &iv.reasons {
                writeln!(out, "    {r}")?;
            }
        }
        writeln!(out, "  events:")?;
        for e in &m.events {
            writeln!(out, "    {} [t = {} s] {}", e.code, fixed(e.t_s, 3), e.message)?;
        }
    }
    write_comparison(out, &motions)
}
