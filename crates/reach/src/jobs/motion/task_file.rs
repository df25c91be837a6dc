//! Task files (docs/task-format.md): one robot, an optional description, defaults, and one
//! or more `[[motion]]` tables, each a [`MoveRequest`] in the file's own key names.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::compute::move_motion_with_progress;
use super::report::PlanReport;
use super::request::{ChoiceSpec, End, IntervalChoice, MoveRequest, ProfileName, Space};
use crate::Robot;
use crate::error::{Error, Result};
use crate::jobs::input::{Joints, Pose};

/// Every motion of a task file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanRequest {
    /// The task file's text (TOML, docs/task-format.md). Its `robot` key is for front ends
    /// that load the robot from it; the robot given beside the request is the one planned for.
    pub task: String,
    /// The text of a scene file every motion is checked against continuously (as
    /// [`MoveRequest::scene`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
}

/// A parsed task file.
#[derive(Debug, Clone, PartialEq)]
pub struct Task {
    /// The `robot` key: a preset name or a robot file path, as written.
    pub robot: String,
    /// The description (empty when not given).
    pub description: String,
    /// One request per `[[motion]]`, defaults applied, named (`motion N` by default).
    pub motions: Vec<MoveRequest>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct TaskFile {
    robot: String,
    #[serde(default)]
    description: String,
    #[serde(default)]
    defaults: MotionTable,
    #[serde(rename = "motion", default)]
    motions: Vec<MotionTable>,
    choose: Option<ChoiceSpec>,
}

#[derive(Debug, Default, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionTable {
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
    choices: Option<Vec<IntervalChoice>>,
}

/// A task-file error: `line L, column C: message`.
fn file_error(e: &toml::de::Error, text: &str) -> Error {
    let message = e.message().trim().to_string();
    let message = match e.span() {
        Some(span) => {
            let before = &text[..span.start.min(text.len())];
            let line = before.matches('\n').count() + 1;
            let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
            format!("line {line}, column {column}: {message}")
        }
        None => message,
    };
    Error::File { what: "task file", message }
}

/// One end from the file's `from`/`from_pose` (or `to`/`to_pose`) keys.
fn end(joints: Option<Vec<f64>>, pose: Option<Vec<f64>>, key: &str, motion: &str) -> Result<End> {
    let field = |k: &str| format!("motion `{motion}`: {k}");
    match (joints, pose) {
        (Some(v), None) => Ok(End::Joints(Joints::Deg(v))),
        (None, Some(v)) => {
            let [x, y, z, roll, pitch, yaw]: [f64; 6] = v.as_slice().try_into().map_err(|_| {
                Error::request(
                    field(&format!("{key}_pose")),
                    format!("needs 6 numbers x,y,z,roll,pitch,yaw, got {}", v.len()),
                )
            })?;
            Ok(End::Pose(Pose::xyz_rpy_deg([x, y, z], [roll, pitch, yaw])))
        }
        _ => Err(Error::request(field(key), format!("give exactly one of `{key}` and `{key}_pose`"))),
    }
}

impl Task {
    /// Parses a task file's text.
    ///
    /// # Errors
    /// [`Error::File`] for malformed TOML or unknown keys (with line and column);
    /// [`Error::Request`] naming the motion for missing or contradicting ends, a pose that is
    /// not 6 numbers, no `[[motion]]`.
    pub fn parse(text: &str) -> Result<Task> {
        let file: TaskFile = toml::from_str(text).map_err(|e| file_error(&e, text))?;
        if file.motions.is_empty() {
            return Err(Error::File { what: "task file", message: "no [[motion]]".into() });
        }
        let d = file.defaults;
        let mut motions = Vec::with_capacity(file.motions.len());
        for (k, m) in file.motions.into_iter().enumerate() {
            let name = m.name.unwrap_or_else(|| format!("motion {}", k + 1));
            let from = end(m.from.or(d.from.clone()), m.from_pose.or(d.from_pose.clone()), "from", &name)?;
            let to = end(m.to.or(d.to.clone()), m.to_pose.or(d.to_pose.clone()), "to", &name)?;
            let space = m.space.or(d.space).unwrap_or_default();
            motions.push(MoveRequest {
                from,
                to,
                space,
                profile: m.profile.or(d.profile),
                duration_s: m.duration.or(d.duration),
                speed_m_s: m.speed.or(d.speed),
                dt_s: m.dt.or(d.dt),
                joint_weights: m.weights.or(d.weights.clone()),
                // `[choose]` applies to every tool-space motion of the file.
                choose: if space == Space::Tool { file.choose.clone() } else { None },
                scene: None,
                choices: m.choices.or(d.choices.clone()).unwrap_or_default(),
                name,
            });
        }
        Ok(Task { robot: file.robot, description: file.description, motions })
    }
}

/// A motion's error in the file's key names, prefixed with the motion's name.
fn in_motion(name: &str, e: Error) -> Error {
    let key = |field: &str| -> String {
        let (head, rest) = field.find(['.', ':', '[']).map_or((field, ""), |i| field.split_at(i));
        let head = match head {
            "duration_s" => "duration",
            "speed_m_s" => "speed",
            "dt_s" => "dt",
            "joint_weights" => "weights",
            other => other,
        };
        format!("motion `{name}`: {head}{rest}")
    };
    match e {
        Error::Request { field, reason } => Error::Request { field: key(&field), reason },
        other => Error::request(format!("motion `{name}`"), other.to_string()),
    }
}

/// Computes every motion of a task file on `robot`.
///
/// # Errors
/// As [`Task::parse`], and as [`super::move_motion`] for each motion with the field named in
/// the file's keys and prefixed with the motion's name (`motion `weld`: duration: …`).
pub fn plan(robot: &Robot, request: &PlanRequest) -> Result<PlanReport> {
    plan_with_progress(robot, request, &mut |_, _, _| {}, &crate::Cancel::default())
}

/// [`plan`] that reports each tool-space motion's tracking progress as
/// `progress(motion name, samples done, samples in all)` and stops once `cancel` is set.
///
/// # Errors
/// As [`plan`] and [`super::move_motion_with_progress`].
pub fn plan_with_progress(
    robot: &Robot,
    request: &PlanRequest,
    progress: &mut dyn FnMut(&str, usize, usize),
    cancel: &crate::Cancel,
) -> Result<PlanReport> {
    let task = Task::parse(&request.task)?;
    if let Some(scene) = &request.scene {
        crate::jobs::world::parse_scene(scene)?;
    }
    let motions = task
        .motions
        .iter()
        .map(|m| {
            let m = MoveRequest { scene: request.scene.clone(), ..m.clone() };
            move_motion_with_progress(robot, &m, &mut |done, total| progress(&m.name, done, total), cancel)
                .map_err(|e| in_motion(&m.name, e))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(PlanReport { robot: robot.name().to_string(), description: task.description, motions })
}
