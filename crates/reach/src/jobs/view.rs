//! The `view` workflow: everything the 3-D viewer draws, precomputed, so the viewer (three.js,
//! `web/`) does no kinematics of its own (except that urdf-loader places a URDF robot's
//! meshes from its document's joints at each state's joint values, [`ViewUrdf`]).
//!
//! A view holds the robot's states — one configuration, or the samples of a motion (a sampled
//! motion such as `reach move --json`'s, or every motion of a task file planned here) — each
//! with the world pose of every link frame and of the tool, and the world axis of every joint;
//! the capsule radius of every link segment; the scene's obstacles and tool zone as plain
//! shapes; the events of the motion for the timeline; and, for an IK target, one "ghost" state
//! per IK solution.
//!
//! # Sizes
//! At most [`MAX_VIEW_INPUT_SAMPLES`] samples are accepted; at most [`MAX_VIEW_SAMPLES`] are
//! shipped: a longer motion is thinned to evenly spaced samples that keep the first and the last
//! (`samples_total` tells how many there were). Events beyond [`MAX_VIEW_EVENTS`] are dropped
//! (the count is in `events_total`). The visual meshes of a URDF robot are inlined up to
//! [`MAX_VIEW_MESH_BYTES`] in all.

use nalgebra::{IsometryMatrix3, UnitQuaternion, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::ik::{IkRequest, ik};
use super::input::{Joints, MotionSample, Pose, q_display, quat_wxyz, samples_si};
use super::motion::{MoveEvent, MoveInterval, MoveReport, PlanRequest, plan};
use super::world::check::verdict_text;
use super::world::{CspaceRequest, SweptPathReport, cspace_with_grid, parse_scene};
use crate::Robot;
use crate::error::{Error, Result};
use crate::model::{UrdfChain, urdf_chain_links, urdf_visual_meshes};
use crate::world::cspace::GridCounts;
use crate::world::distance::point_segment_sq;
use crate::world::sweep::SweepOptions;
use crate::world::{CollisionChecker, PathSweep, Scene, Shape, SweptPair, Verdict};

/// Most motion samples a view request accepts.
pub const MAX_VIEW_INPUT_SAMPLES: usize = 1_000_000;
/// Most states a view report ships (a longer motion is thinned evenly, first and last kept).
pub const MAX_VIEW_SAMPLES: usize = 2_000;
/// Most timeline events a view report ships.
pub const MAX_VIEW_EVENTS: usize = 1_000;
/// Most grid nodes of a view's C-space section.
pub const MAX_VIEW_CSPACE_NODES: usize = 250_000;
/// Most bytes of mesh files a view inlines (their sum, before base64): 64 MiB.
pub const MAX_VIEW_MESH_BYTES: usize = 64 << 20;

/// What to show.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ViewRequest {
    /// The configuration shown when there is no motion (default: home).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q: Option<Joints>,
    /// A sampled motion (`reach move --json`'s `samples`), every sample within the limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Vec<MotionSample>>,
    /// Events to mark on the timeline of `samples` (e.g. from the move report,
    /// [`ViewEvent::of_move`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub events: Vec<ViewEvent>,
    /// Instead of `samples`: the text of a task file (TOML), planned here; its motions are
    /// shown one after the other, their events and infeasible intervals on the timeline.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub task: Option<String>,
    /// The text of a scene file (TOML): its obstacles and tool zone are drawn.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scene: Option<String>,
    /// An IK target: every solution is shown as a ghost arm.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ik_target: Option<Pose>,
    /// For a robot read from a URDF document: the document and its meshes, drawn instead of
    /// the link capsules ([`ViewUrdf::read`]). Its chain must have the robot's joints.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<ViewUrdf>,
    /// A two-joint section of the configuration space over `scene` (seed 004's forbidden
    /// cells), drawn beside the 3-D view with the motion's path in it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cspace: Option<ViewCspaceRequest>,
}

fn default_cspace_step_deg() -> f64 {
    5.0
}

/// Which C-space section to draw.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ViewCspaceRequest {
    /// The two swept joints, 1-based (`[2, 3]`); the others are fixed at the first state's
    /// values.
    pub joints: [usize; 2],
    /// Grid step, degrees (default 5; prismatic joints: the same number converted like an
    /// angle, as `reach cspace` does).
    #[serde(default = "default_cspace_step_deg")]
    pub step_deg: f64,
}

/// A two-joint section of the configuration space: the scene's grid classification
/// ([`crate::jobs::world::cspace_with_grid`], as `reach cspace`) with every joint but two
/// fixed at the first state's values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewCspace {
    /// The two swept joints, 1-based, ascending: the panel's horizontal and vertical axes.
    pub joints: [usize; 2],
    /// Grid step, degrees.
    pub step_deg: f64,
    /// The grid values of the two joints (revolute degrees, prismatic metres).
    pub axes_deg: [Vec<f64>; 2],
    /// The configuration the section goes through (the first state's): the other joints
    /// are fixed at its values.
    pub through_q_deg: Vec<f64>,
    /// Class of every node, the first joint's index varying slowest (`classes[i·n₂ + k]` at
    /// `axes_deg[0][i]`, `axes_deg[1][k]`): 0 allowed, 1 outside the joint limits, 2 tool
    /// outside the zone, 3 self-collision, 4 obstacle collision.
    pub classes: Vec<u8>,
    /// Counts per class.
    pub counts: GridCounts,
    /// Largest departure of the other joints from the section over the states (revolute
    /// degrees, prismatic metres): 0 when the whole motion lies in the section.
    pub off_section_deg: f64,
}

/// The C-space section of `request` through the first of `states`.
fn view_cspace(
    robot: &Robot,
    scene: Option<&str>,
    request: &ViewCspaceRequest,
    states: &[ViewState],
) -> Result<ViewCspace> {
    let scene = scene.ok_or_else(|| Error::request("cspace", "needs a scene"))?;
    let [a, b] = request.joints;
    let dof = robot.dof();
    if a == b || !(1..=dof).contains(&a) || !(1..=dof).contains(&b) {
        return Err(Error::request("cspace", format!("joints {a} and {b}: two different joints of 1..{dof}")));
    }
    let joints = [a.min(b), a.max(b)];
    let through = states.first().map(|s| s.q_deg.clone()).ok_or_else(|| Error::request("cspace", "no state"))?;
    let fix = (1..=dof).filter(|j| !joints.contains(j)).map(|j| (format!("q{j}"), through[j - 1])).collect();
    let grid_request = CspaceRequest {
        scene: scene.to_string(),
        step_deg: request.step_deg,
        fix,
        fit: false,
        max_nodes: Some(MAX_VIEW_CSPACE_NODES),
    };
    let (report, grid) = cspace_with_grid(robot, &grid_request, &|_, _| {}).map_err(|e| match e {
        Error::Request { field, reason } => Error::request(format!("cspace.{field}"), reason),
        e => e,
    })?;
    let display = |j: usize, v: &f64| match robot.joints()[j].kind {
        crate::model::JointKind::Revolute => v.to_degrees(),
        crate::model::JointKind::Prismatic => *v,
    };
    let axis = |j: usize| grid.axes[j - 1].iter().map(|v| display(j - 1, v)).collect::<Vec<_>>();
    let off_section_deg = states
        .iter()
        .flat_map(|s| (1..=dof).filter(|j| !joints.contains(j)).map(|j| (s.q_deg[j - 1] - through[j - 1]).abs()))
        .fold(0.0, f64::max);
    Ok(ViewCspace {
        joints,
        step_deg: request.step_deg,
        axes_deg: [axis(joints[0]), axis(joints[1])],
        through_q_deg: through,
        classes: grid.classes.iter().map(|c| *c as u8).collect(),
        counts: report.counts,
        off_section_deg,
    })
}

/// A URDF robot as its own description draws it: the document and its visual meshes, from
/// which the viewer builds the robot (with the `urdf-loader` package of three.js) and poses it
/// by joint name at every state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ViewUrdf {
    /// The URDF document's text.
    pub text: String,
    /// The chain's base link: its frame is the robot's base frame (the report's `base`).
    pub base_link: String,
    /// The chain's tip link: its origin is the tool point.
    pub tip_link: String,
    /// Every visual mesh of the document (STL or Collada), each once.
    pub meshes: Vec<ViewMesh>,
}

/// A mesh file, inlined.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ViewMesh {
    /// The `filename` attribute as the URDF document writes it (`package://…`, relative, …).
    pub filename: String,
    /// The file's bytes, base64 (standard alphabet, padded).
    pub base64: String,
}

impl ViewUrdf {
    /// The document `text`, the chain `chain` selects in it and every visual mesh it
    /// references: `read(filename)` gives a mesh file's bytes (the caller resolves the address
    /// as written — `package://NAME/…`, relative, `file://` — and reads the file).
    ///
    /// # Errors
    /// The document's and the chain's errors ([`crate::model::urdf_chain_links`]); a mesh
    /// that is neither STL nor Collada (`.dae`) ([`Error::File`] naming it); the errors of
    /// `read`; meshes of more than [`MAX_VIEW_MESH_BYTES`] in all ([`Error::Request`], field
    /// `urdf`).
    pub fn read(text: &str, chain: &UrdfChain, mut read: impl FnMut(&str) -> Result<Vec<u8>>) -> Result<ViewUrdf> {
        use base64::Engine as _;
        let (base_link, tip_link) = urdf_chain_links(text, chain)?;
        let mut total = 0usize;
        let mut meshes = Vec::new();
        for filename in urdf_visual_meshes(text)? {
            let ext = filename.rsplit_once('.').map(|(_, e)| e.to_ascii_lowercase());
            if !matches!(ext.as_deref(), Some("stl" | "dae")) {
                return Err(Error::File {
                    what: "mesh file",
                    message: format!("`{filename}`: only STL and Collada (.dae) meshes can be shown"),
                });
            }
            let bytes = read(&filename)?;
            total += bytes.len();
            if total > MAX_VIEW_MESH_BYTES {
                return Err(Error::request(
                    "urdf",
                    format!("the meshes exceed the {} MiB a view inlines (at `{filename}`)", MAX_VIEW_MESH_BYTES >> 20),
                ));
            }
            meshes.push(ViewMesh { base64: base64::engine::general_purpose::STANDARD.encode(&bytes), filename });
        }
        Ok(ViewUrdf { text: text.to_string(), base_link, tip_link, meshes })
    }

    /// Checks that the chain `base_link` → `tip_link` of the document moves the joints of
    /// `robot`, in its order (the viewer poses the document's joints by these names).
    fn check(&self, robot: &Robot) -> Result<()> {
        let chain = UrdfChain { base: Some(self.base_link.clone()), tip: Some(self.tip_link.clone()) };
        let own = Robot::from_urdf_str(&self.text, &chain)?;
        let names = |r: &Robot| r.joints().iter().map(|j| j.name.clone()).collect::<Vec<_>>();
        if names(&own) != names(robot) {
            return Err(Error::request(
                "urdf",
                format!(
                    "the chain {} → {} moves joints [{}], the robot has [{}]",
                    self.base_link,
                    self.tip_link,
                    names(&own).join(", "),
                    names(robot).join(", ")
                ),
            ));
        }
        Ok(())
    }
}

/// The viewer bundle built from `web/src` (`npm run build` in `web/`), committed (so that
/// building needs no npm; CI checks it matches its sources).
pub const VIEWER_JS: &str = include_str!("../../../../web/dist/viewer.js");

/// A self-contained HTML page showing a view report (its JSON, `report_json`) with the viewer
/// bundle inlined: it opens offline. `live`: the page also follows the service that serves it
/// (`reach serve`'s `GET /`: joint states over its WebSocket, the operator's questions).
/// Every `<` of the JSON (only inside its strings) is written `\u003c`, the same string to a
/// JSON parser, so the data can neither close its script element nor open a comment.
#[must_use]
pub fn page(title: &str, report_json: &str, live: bool) -> String {
    let data = report_json.replace('<', "\\u003c");
    let title = title.replace('&', "&amp;").replace('<', "&lt;").replace('>', "&gt;");
    let live = if live { " data-live=\"1\"" } else { "" };
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>reach view: {title}</title>\n\
         </head>\n<body>\n<script id=\"reach-view-data\" type=\"application/json\"{live}>{data}</script>\n\
         <script>{VIEWER_JS}</script>\n</body>\n</html>\n"
    )
}

/// A pose in the world frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewFrame {
    /// Origin, metres.
    pub xyz_m: [f64; 3],
    /// Orientation, unit quaternion `[w, x, y, z]`.
    pub quat_wxyz: [f64; 4],
}

impl ViewFrame {
    fn of(t: &IsometryMatrix3<f64>) -> Self {
        let v = t.translation.vector;
        ViewFrame { xyz_m: [v.x, v.y, v.z], quat_wxyz: quat_wxyz(&UnitQuaternion::from_rotation_matrix(&t.rotation)) }
    }
}

/// A joint axis in the world frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewAxis {
    /// A point on the axis (the joint's frame origin before its motion), metres.
    pub point_m: [f64; 3],
    /// Unit direction, signed as the joint value turns or slides.
    pub direction: [f64; 3],
}

/// The robot at one configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewState {
    /// Time, seconds (0 for a single configuration).
    pub t_s: f64,
    /// Joint values: revolute in degrees, prismatic in metres.
    pub q_deg: Vec<f64>,
    /// World pose of every link frame (`Robot::frames`), one per joint.
    pub frames: Vec<ViewFrame>,
    /// World pose of the tool.
    pub tool: ViewFrame,
    /// World axis of every joint.
    pub axes: Vec<ViewAxis>,
}

/// One mark on the timeline.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ViewEvent {
    /// Start, seconds.
    pub t_s: f64,
    /// End of an interval, seconds (`null` for an instant).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_s: Option<f64>,
    /// Short code: `K1` … `K14` for tracking events, `infeasible` for an infeasible
    /// interval, `motion` for the start of a task's motion.
    pub code: String,
    /// The text.
    pub message: String,
}

impl ViewEvent {
    /// The events and infeasible intervals of a move report, shifted by `offset_s` seconds.
    #[must_use]
    pub fn of_move(report: &MoveReport, offset_s: f64) -> Vec<ViewEvent> {
        Self::of_log(&report.events, &report.intervals, offset_s)
    }

    /// Tracking events and the infeasible ones of `intervals`, shifted by `offset_s` seconds.
    #[must_use]
    pub fn of_log(events: &[MoveEvent], intervals: &[MoveInterval], offset_s: f64) -> Vec<ViewEvent> {
        let events = events.iter().map(|e| ViewEvent {
            t_s: e.t_s + offset_s,
            end_s: None,
            code: e.code.clone(),
            message: e.message.clone(),
        });
        let intervals = intervals.iter().filter(|i| !i.feasible).map(|i| ViewEvent {
            t_s: i.start_s + offset_s,
            end_s: Some(i.end_s + offset_s),
            code: "infeasible".into(),
            message: i.reasons.join("; "),
        });
        events.chain(intervals).collect()
    }
}

/// The timeline marks of a motion file (`reach move --json`'s `events` and infeasible
/// `intervals`); none when the file has neither (e.g. samples only, or a motion CSV: text
/// that does not start with `{`).
///
/// # Errors
/// [`Error::File`] for JSON that is malformed or whose `events`/`intervals` are.
pub fn parse_motion_events(text: &str) -> Result<Vec<ViewEvent>> {
    if !text.trim_start().starts_with('{') {
        return Ok(Vec::new());
    }
    #[derive(Deserialize)]
    struct MotionLog {
        #[serde(default)]
        events: Vec<MoveEvent>,
        #[serde(default)]
        intervals: Vec<MoveInterval>,
    }
    serde_json::from_str::<MotionLog>(text)
        .map(|log| ViewEvent::of_log(&log.events, &log.intervals, 0.0))
        .map_err(|e| Error::File { what: "motion file", message: crate::one_line(&e.to_string()) })
}

/// Whether a shape is an obstacle or an entry of the tool's allowed zone.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ViewRole {
    /// A forbidden zone.
    Obstacle,
    /// The tool point must stay inside.
    ToolZone,
}

/// A scene shape, SI units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "shape", rename_all = "snake_case")]
pub enum ViewShapeKind {
    /// A point.
    Point {
        /// Position, metres.
        at_m: [f64; 3],
    },
    /// A ball.
    Sphere {
        /// Centre, metres.
        center_m: [f64; 3],
        /// Radius, metres.
        radius_m: f64,
    },
    /// An oriented box (a rectangle has a zero half-extent).
    Box {
        /// Centre, metres.
        center_m: [f64; 3],
        /// Half-extents along the box axes, metres.
        half_extents_m: [f64; 3],
        /// World ← box rotation, `[w, x, y, z]`.
        quat_wxyz: [f64; 4],
    },
    /// Points within `radius_m` of segment `a`–`b`.
    Capsule {
        /// First end, metres.
        a_m: [f64; 3],
        /// Second end, metres.
        b_m: [f64; 3],
        /// Radius, metres.
        radius_m: f64,
    },
    /// A solid cylinder.
    Cylinder {
        /// Centre (middle of the axis), metres.
        center_m: [f64; 3],
        /// World ← cylinder rotation, `[w, x, y, z]`; the axis is the rotated z.
        quat_wxyz: [f64; 4],
        /// Radius, metres.
        radius_m: f64,
        /// Length along the axis, metres.
        length_m: f64,
    },
    /// The convex hull of these points (a mesh obstacle as it is checked).
    ConvexMesh {
        /// The vertices, metres.
        vertices_m: Vec<[f64; 3]>,
    },
    /// `{p : normal·p ≤ offset_m}`; `normal` points to the free side.
    HalfSpace {
        /// Unit outward normal.
        normal: [f64; 3],
        /// `normal·p` on the boundary plane, metres.
        offset_m: f64,
    },
}

/// A named scene shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewShape {
    /// Name from the scene file.
    pub name: String,
    /// Obstacle or tool zone.
    pub role: ViewRole,
    /// The solid.
    #[serde(flatten)]
    pub kind: ViewShapeKind,
}

fn xyz(v: &Vector3<f64>) -> [f64; 3] {
    [v.x, v.y, v.z]
}

impl ViewShapeKind {
    fn of(shape: &Shape) -> Self {
        match shape {
            Shape::Point { at } => ViewShapeKind::Point { at_m: xyz(at) },
            Shape::Sphere { center, radius } => ViewShapeKind::Sphere { center_m: xyz(center), radius_m: *radius },
            Shape::Box { center, half_extents, rotation } => ViewShapeKind::Box {
                center_m: xyz(center),
                half_extents_m: xyz(half_extents),
                quat_wxyz: quat_wxyz(&UnitQuaternion::from_matrix(rotation)),
            },
            Shape::Capsule { a, b, radius } => ViewShapeKind::Capsule { a_m: xyz(a), b_m: xyz(b), radius_m: *radius },
            Shape::Cylinder { center, rotation, radius, half_length } => ViewShapeKind::Cylinder {
                center_m: xyz(center),
                quat_wxyz: quat_wxyz(&UnitQuaternion::from_matrix(rotation)),
                radius_m: *radius,
                length_m: 2.0 * half_length,
            },
            Shape::ConvexMesh { vertices } => {
                ViewShapeKind::ConvexMesh { vertices_m: vertices.iter().map(xyz).collect() }
            }
            Shape::HalfSpace { normal, offset } => ViewShapeKind::HalfSpace { normal: xyz(normal), offset_m: *offset },
        }
    }
}

/// One IK solution drawn as a ghost arm.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewGhost {
    /// Branch label.
    pub branch: String,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
    /// Whether it is the solution IK chooses.
    pub chosen: bool,
    /// The arm at the solution.
    pub state: ViewState,
    /// With a scene: the solution checked in it (the library's collision check, as
    /// `reach check`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub check: Option<ViewGhostCheck>,
}

/// One configuration checked in the view's scene ([`CollisionChecker::report`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewGhostCheck {
    /// Whether the configuration is free (no collision, tool inside its zone).
    pub free: bool,
    /// The first failed check (or free), as `reach check` reports it.
    pub verdict: Verdict,
    /// The verdict in words, naming the link and the obstacle or zone (as `reach check`).
    pub verdict_text: String,
    /// Smallest link–obstacle clearance (`null` without obstacles), metres.
    pub min_obstacle_clearance_m: Option<f64>,
}

/// Where a motion shown with a scene is not proven clear: the library's swept check of the
/// piecewise-linear joint path through the motion's samples (as `reach check --samples`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewContact {
    /// The first instant the swept check cannot prove clear (the clearance there is at most
    /// the contact tolerance), seconds on the motion's clock (as `states[].t_s`).
    pub t_s: f64,
    /// The last such instant (the same check run from the end of the path backwards),
    /// seconds; `null` when the scene has a moving obstacle (its check runs forward in time
    /// only). The arm is in contact at `t_s` and at `end_s`, and may be free in between.
    pub end_s: Option<f64>,
    /// What touches: a link and an obstacle, two links, or the tool point and a zone's boundary.
    pub pair: SweptPair,
    /// The same in words, with the link's and the obstacle's or zone's names.
    pub pair_text: String,
    /// The link's name (the first link of a pair of links), `null` for the tool point.
    pub link_name: Option<String>,
    /// Where the marker is drawn, world, metres, in the configuration at `t_s`: for an
    /// obstacle, the point of its boundary nearest to the link's stick segment (the segment
    /// through the link's frame origin); for two links, the point of the first link's segment
    /// nearest to the other's; for a zone, the tool point. A place to look, not a verdict.
    pub xyz_m: [f64; 3],
    /// The arm at `t_s`.
    pub state: ViewState,
}

/// Everything the viewer draws.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct ViewReport {
    /// Robot name.
    pub robot: String,
    /// Joint names.
    pub joint_names: Vec<String>,
    /// Per joint: whether it is prismatic (its `q_deg` entry is in metres).
    pub prismatic: Vec<bool>,
    /// World pose of the base.
    pub base: ViewFrame,
    /// Capsule radius of every link segment, metres (`dof + 1` entries: base → frame 1, …,
    /// last frame → tool point; 0 when the robot file gives no `[[links]]`).
    pub link_radii_m: Vec<f64>,
    /// The states in time order: one for a single configuration, else the motion's samples
    /// (at most [`MAX_VIEW_SAMPLES`]).
    pub states: Vec<ViewState>,
    /// How many samples the motion had before thinning.
    pub samples_total: usize,
    /// Duration of the motion, seconds (0 for a single configuration).
    pub duration_s: f64,
    /// Timeline marks (at most [`MAX_VIEW_EVENTS`]).
    pub events: Vec<ViewEvent>,
    /// How many events there were before the cap.
    pub events_total: usize,
    /// Obstacles and tool-zone entries.
    pub shapes: Vec<ViewShape>,
    /// The IK target, when given.
    pub ik_target: Option<ViewFrame>,
    /// IK status (`ok`, `unreachable`, …) when a target is given.
    pub ik_status: Option<String>,
    /// One ghost arm per IK solution.
    pub ghosts: Vec<ViewGhost>,
    /// A URDF robot's document and meshes (drawn instead of the link capsules), when given.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub urdf: Option<ViewUrdf>,
    /// The C-space section, when asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cspace: Option<ViewCspace>,
    /// A motion (two or more samples) with a scene: the swept check of the path through all
    /// its samples (before thinning), as `reach check --samples` reports it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub swept: Option<Box<SweptPathReport>>,
    /// Where that check is not proven clear, when it is not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact: Option<Box<ViewContact>>,
}

/// The point of segment `a`–`b` where the convex function `f` (a signed distance along the
/// segment) is smallest: a ternary search over the segment's parameter.
fn nearest_on_segment(a: &Vector3<f64>, b: &Vector3<f64>, f: impl Fn(&Vector3<f64>) -> f64) -> Vector3<f64> {
    let at = |s: f64| a + (b - a) * s;
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let (m1, m2) = (lo + (hi - lo) / 3.0, hi - (hi - lo) / 3.0);
        if f(&at(m1)) <= f(&at(m2)) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    at(0.5 * (lo + hi))
}

/// The stick segments that may carry 1-based checker link `link` in `state`, from the
/// polyline base, frame origins, tool: for a robot without bodies, segment `link − 1`; for a
/// link with solids fixed to frame `k`, the segments on either side of frame `k`'s origin.
fn link_segments(robot: &Robot, base: &ViewFrame, state: &ViewState, link: usize) -> Vec<(Vector3<f64>, Vector3<f64>)> {
    let points: Vec<Vector3<f64>> = std::iter::once(base.xyz_m)
        .chain(state.frames.iter().map(|f| f.xyz_m))
        .chain(std::iter::once(state.tool.xyz_m))
        .map(Vector3::from)
        .collect();
    let last = points.len() - 2;
    let ks = match robot.bodies().get(link.saturating_sub(1)) {
        Some(body) => vec![body.frame.saturating_sub(1), body.frame.min(last)],
        None => vec![link.saturating_sub(1).min(last)],
    };
    ks.into_iter().map(|k| (points[k], points[k + 1])).collect()
}

/// Of the segments, the point where the convex function `f` is smallest.
fn nearest_on_segments(segments: &[(Vector3<f64>, Vector3<f64>)], f: impl Fn(&Vector3<f64>) -> f64) -> Vector3<f64> {
    segments
        .iter()
        .map(|(a, b)| nearest_on_segment(a, b, &f))
        .min_by(|p, q| f(p).total_cmp(&f(q)))
        .unwrap_or_else(Vector3::zeros)
}

/// The point of the boundary of a convex `shape` nearest to `p`: `p` moved by its signed
/// distance against the distance's gradient (central differences).
fn onto_boundary(shape: &Shape, p: &Vector3<f64>) -> Vector3<f64> {
    let h = 1e-7 * (1.0 + p.norm());
    let grad = Vector3::from_fn(|i, _| {
        let e = Vector3::from_fn(|j, _| if i == j { h } else { 0.0 });
        (shape.point_sdf(&(p + e)) - shape.point_sdf(&(p - e))) / (2.0 * h)
    });
    match grad.try_normalize(1e-12) {
        Some(n) => p - n * shape.point_sdf(p),
        None => *p,
    }
}

/// A motion's swept check in a scene and where it is not proven clear (the report's `swept`
/// and `contact`).
type MotionCheck = (Option<Box<SweptPathReport>>, Option<Box<ViewContact>>);

/// The swept check of the path through `times_q` (seconds, SI joint values) in `scene`, and
/// where it is not proven clear.
fn motion_contact(robot: &Robot, scene: &Scene, base: &ViewFrame, times_q: &[(f64, Vec<f64>)]) -> Result<MotionCheck> {
    let t0 = times_q.first().map_or(0.0, |p| p.0);
    let points: Vec<Vec<f64>> = times_q.iter().map(|p| p.1.clone()).collect();
    let times: Vec<f64> = times_q.iter().map(|p| p.0 - t0).collect();
    let options = SweepOptions::default();
    let mut checker = CollisionChecker::new(robot, scene);
    let Some(path) = checker.swept_path_timed(&points, &times, &options)? else {
        return Ok((None, None));
    };
    let report = Box::new(SweptPathReport::of(&path, &checker));
    if path.clear {
        return Ok((Some(report), None));
    }
    let along = |segment: usize, at: f64| -> (f64, Vec<f64>) {
        let (a, b) = (&times_q[segment], &times_q[segment + 1]);
        (a.0 + at * (b.0 - a.0), a.1.iter().zip(&b.1).map(|(x, y)| x + at * (y - x)).collect())
    };
    let (t_s, q) = along(path.segment, path.closest.at);
    // The last contact: the first one of the reversed path (fixed obstacles only).
    let end_s = if scene.moving_obstacle().is_none() {
        let reversed: Vec<Vec<f64>> = points.iter().rev().cloned().collect();
        let back: Option<PathSweep> = checker.swept_path(&reversed, &options)?;
        back.filter(|b| !b.clear).map(|b| along(points.len() - 2 - b.segment, 1.0 - b.closest.at).0)
    } else {
        None
    };
    let state = view_state(robot, t_s, &q)?;
    let (link_name, point) = match path.pair {
        SweptPair::ToolZone { .. } => (None, Vector3::from(state.tool.xyz_m)),
        SweptPair::Obstacle { link, obstacle } => {
            // The obstacle where it is at `t_s`, the boundary point nearest the link's segment.
            let o = &scene.obstacles[obstacle];
            let shift = o.displacement(t_s - t0);
            let segments = link_segments(robot, base, &state, link);
            let p = nearest_on_segments(&segments, |p| o.shape.point_sdf(&(p - shift)));
            (Some(checker.link_name(link).to_string()), onto_boundary(&o.shape, &(p - shift)) + shift)
        }
        SweptPair::SelfPair { link_a, link_b } => {
            let others = link_segments(robot, base, &state, link_b);
            let gap =
                |p: &Vector3<f64>| others.iter().map(|(c, d)| point_segment_sq(p, c, d)).fold(f64::INFINITY, f64::min);
            let segments = link_segments(robot, base, &state, link_a);
            (Some(checker.link_name(link_a).to_string()), nearest_on_segments(&segments, gap))
        }
    };
    let contact = ViewContact {
        t_s,
        end_s,
        pair: path.pair,
        pair_text: report.swept.pair_text.clone().unwrap_or_default(),
        link_name,
        xyz_m: xyz(&point),
        state,
    };
    Ok((Some(report), Some(Box::new(contact))))
}

/// The robot at `q` (SI) and time `t_s`.
///
/// # Errors
/// [`Error::Kinematics`] for a `q` of the wrong length or a non-finite value.
pub fn view_state(robot: &Robot, t_s: f64, q: &[f64]) -> Result<ViewState> {
    let mut frames = vec![IsometryMatrix3::identity(); robot.dof()];
    let tool = robot.frames_into(q, &mut frames)?;
    let axes = robot.joint_axes(q)?.iter().map(|(p, d)| ViewAxis { point_m: xyz(p), direction: xyz(d) }).collect();
    Ok(ViewState {
        t_s,
        q_deg: q_display(robot, q),
        frames: frames.iter().map(ViewFrame::of).collect(),
        tool: ViewFrame::of(&tool),
        axes,
    })
}

/// Indices of at most `cap` evenly spaced items out of `n`, first and last kept.
fn thinned(n: usize, cap: usize) -> Vec<usize> {
    if n <= cap {
        return (0..n).collect();
    }
    if cap < 2 {
        return vec![0];
    }
    let mut idx: Vec<usize> = (0..cap).map(|k| (k * (n - 1) + (cap - 1) / 2) / (cap - 1)).collect();
    idx.dedup();
    idx
}

/// Builds the view.
///
/// # Errors
/// [`Error::Request`] naming the field for bad joint values, samples outside the limits, too
/// many samples or both `samples` and `task`; the errors of [`plan`], [`parse_scene`] and
/// [`ik`].
pub fn view(robot: &Robot, request: &ViewRequest) -> Result<ViewReport> {
    if request.samples.is_some() && request.task.is_some() {
        return Err(Error::request("task", "give either samples or a task, not both"));
    }
    if let Some(urdf) = &request.urdf {
        urdf.check(robot)?;
    }
    let mut events = request.events.clone();
    let (times_q, samples_total) = if let Some(samples) = &request.samples {
        if samples.len() > MAX_VIEW_INPUT_SAMPLES {
            return Err(Error::request(
                "samples",
                format!("{} samples, more than the {MAX_VIEW_INPUT_SAMPLES} a view accepts", samples.len()),
            ));
        }
        if samples.is_empty() {
            return Err(Error::request("samples", "no sample"));
        }
        let si = samples_si(robot, samples, "samples")?;
        (si.into_iter().map(|s| (s.t, s.q)).collect::<Vec<_>>(), samples.len())
    } else if let Some(task) = &request.task {
        let report = plan(robot, &PlanRequest { task: task.clone(), scene: request.scene.clone() })?;
        let mut all = Vec::new();
        let mut offset = 0.0;
        for m in &report.motions {
            events.push(ViewEvent { t_s: offset, end_s: None, code: "motion".into(), message: m.name.clone() });
            events.extend(ViewEvent::of_move(m, offset));
            for s in &m.samples {
                let q = Joints::Deg(s.q_deg.clone()).si(robot, "task")?;
                all.push((offset + s.t_s, q));
            }
            offset += m.duration_s;
        }
        if all.is_empty() {
            return Err(Error::request("task", "the task has no motion"));
        }
        let n = all.len();
        (all, n)
    } else {
        let q = match &request.q {
            Some(q) => q.si(robot, "q")?,
            None => robot.home(),
        };
        (vec![(0.0, q)], 1)
    };
    let states = thinned(times_q.len(), MAX_VIEW_SAMPLES)
        .into_iter()
        .map(|k| view_state(robot, times_q[k].0, &times_q[k].1))
        .collect::<Result<Vec<_>>>()?;
    let duration_s = match (times_q.first(), times_q.last()) {
        (Some(a), Some(b)) => b.0 - a.0,
        _ => 0.0,
    };
    events.sort_by(|a, b| a.t_s.total_cmp(&b.t_s));
    let events_total = events.len();
    events.truncate(MAX_VIEW_EVENTS);

    let base = ViewFrame::of(&IsometryMatrix3::from_parts(
        robot.base().translation,
        robot.base().rotation.to_rotation_matrix(),
    ));
    let scene = request.scene.as_deref().map(parse_scene).transpose()?;
    let mut shapes = Vec::new();
    if let Some(scene) = &scene {
        let roles = [(ViewRole::Obstacle, &scene.obstacles), (ViewRole::ToolZone, &scene.tool_zone)];
        for (role, list) in roles {
            shapes.extend(list.iter().map(|o| ViewShape {
                name: o.name.clone(),
                role,
                kind: ViewShapeKind::of(&o.shape),
            }));
        }
    }

    let cspace =
        request.cspace.as_ref().map(|c| view_cspace(robot, request.scene.as_deref(), c, &states)).transpose()?;

    let (mut ik_target, mut ik_status, mut ghosts) = (None, None, Vec::new());
    if let Some(target) = &request.ik_target {
        let pose = target.isometry("ik_target")?;
        ik_target =
            Some(ViewFrame::of(&IsometryMatrix3::from_parts(pose.translation, pose.rotation.to_rotation_matrix())));
        let mut ik_request = IkRequest::new(target.clone());
        ik_request.all = true;
        let report = ik(robot, &ik_request)?;
        ik_status = Some(report.status.clone());
        let mut checker = scene.as_ref().map(|scene| CollisionChecker::new(robot, scene));
        for (k, s) in report.solutions.iter().enumerate() {
            let q = Joints::Deg(s.q_deg.clone()).si(robot, "ik_target")?;
            let check = match checker.as_mut() {
                Some(checker) => {
                    let r = checker.report(&q)?;
                    Some(ViewGhostCheck {
                        free: r.verdict.is_free(),
                        verdict: r.verdict,
                        verdict_text: verdict_text(&r.verdict, checker),
                        min_obstacle_clearance_m: r.min_obstacle_clearance_m,
                    })
                }
                None => None,
            };
            ghosts.push(ViewGhost {
                branch: s.branch.clone(),
                within_limits: s.within_limits,
                chosen: report.chosen == Some(k),
                state: view_state(robot, 0.0, &q)?,
                check,
            });
        }
    }

    let (swept, contact) = match &scene {
        Some(scene) if times_q.len() > 1 => motion_contact(robot, scene, &base, &times_q)?,
        _ => (None, None),
    };

    Ok(ViewReport {
        robot: robot.name().to_string(),
        joint_names: robot.joints().iter().map(|j| j.name.clone()).collect(),
        prismatic: robot.joints().iter().map(|j| j.kind == crate::model::JointKind::Prismatic).collect(),
        base,
        link_radii_m: robot.segment_radii(),
        states,
        samples_total,
        duration_s,
        events,
        events_total,
        shapes,
        ik_target,
        ik_status,
        ghosts,
        urdf: request.urdf.clone(),
        cspace,
        swept,
        contact,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn the_bundle_cannot_close_its_script_element() {
        assert!(!VIEWER_JS.to_ascii_lowercase().contains("</script"));
        let html = page("a<b", r#"{"name":"</script>"}"#, false);
        assert_eq!(html.matches("</script>").count(), 2);
        assert!(html.contains(r#"{"name":"\u003c/script>"}"#));
        assert!(html.contains("a&lt;b"));
        assert!(!html.contains("data-live"));
        assert!(page("x", "{}", true).contains(r#"type="application/json" data-live="1">{}"#));
    }

    #[test]
    fn thinning_keeps_first_and_last_and_the_cap() {
        assert_eq!(thinned(5, 10), vec![0, 1, 2, 3, 4]);
        let idx = thinned(10_001, 2_000);
        assert_eq!(idx.len(), 2_000);
        assert_eq!((idx[0], idx[1999]), (0, 10_000));
        assert!(idx.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(thinned(0, 10), Vec::<usize>::new());
    }

    #[test]
    fn a_state_holds_the_fk_frames_and_the_jacobian_axes() {
        let robot = presets::get("ur5").unwrap();
        let q = [0.3, -1.2, 1.1, -0.4, 1.3, 0.2];
        let state = view_state(&robot, 0.0, &q).unwrap();
        let tool = robot.fk(&q).unwrap();
        for i in 0..3 {
            assert!((state.tool.xyz_m[i] - tool.translation.vector[i]).abs() < 1e-12);
        }
        let j = robot.jacobian(&q).unwrap();
        for (i, axis) in state.axes.iter().enumerate() {
            for r in 0..3 {
                assert!((axis.direction[r] - j[(3 + r, i)]).abs() < 1e-12, "joint {i}");
            }
            // The linear column is z × (p − o) for a revolute joint.
            let o = Vector3::from(axis.point_m);
            let z = Vector3::from(axis.direction);
            let v = z.cross(&(tool.translation.vector - o));
            for r in 0..3 {
                assert!((v[r] - j[(r, i)]).abs() < 1e-12, "joint {i}");
            }
        }
        assert_eq!(state.frames.len(), 6);
    }

    const UR5_BALL: &str = "length_unit = \"m\"\nangle_unit = \"deg\"\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\ncenter = [0, -0.136, 0.3]\nradius = 0.02\n";

    /// The UR5 turning its base from +60° to −60° (upper arm upright), `n` samples over 2 s.
    fn turn(n: usize) -> Vec<MotionSample> {
        (0..n)
            .map(|k| {
                let f = k as f64 / (n - 1) as f64;
                MotionSample { t_s: 2.0 * f, q_deg: vec![60.0 - 120.0 * f, -90.0, 0.0, -90.0, 0.0, 0.0] }
            })
            .collect()
    }

    #[test]
    fn issue_35_point_10_a_colliding_motion_reports_its_contact() {
        let robot = presets::get("ur5").unwrap();
        let request = ViewRequest { samples: Some(turn(21)), scene: Some(UR5_BALL.into()), ..ViewRequest::default() };
        let report = view(&robot, &request).unwrap();
        let swept = report.swept.as_ref().unwrap();
        assert!(!swept.swept.clear);
        let contact = report.contact.as_ref().unwrap();
        assert_eq!(contact.pair, SweptPair::Obstacle { link: 3, obstacle: 0 });
        assert_eq!(contact.link_name.as_deref(), Some("upper_arm_link"));
        // The ball lies at q1 = 0 (t = 1 s): the contact spans it, nearly symmetric about it
        // (each end is where the conservative check first fails to prove clearance).
        let end = contact.end_s.unwrap();
        assert!(contact.t_s > 0.1 && contact.t_s < 1.0 && end > 1.0 && end < 1.9, "{} … {end}", contact.t_s);
        assert!((contact.t_s + end - 2.0).abs() < 0.02, "{} … {end}", contact.t_s);
        assert_eq!(Some(contact.t_s), swept.swept.t_s);
        // The marker is on the ball's surface; the state is the arm at the contact.
        let d = (Vector3::from(contact.xyz_m) - Vector3::new(0.0, -0.136, 0.3)).norm();
        assert!((d - 0.02).abs() < 1e-6, "{d}");
        assert!((contact.state.q_deg[0] - (60.0 - 60.0 * contact.t_s)).abs() < 1e-9);
        // Moved out of the way: proven clear, no contact.
        let away = UR5_BALL.replace("center = [0,", "center = [1.5,");
        let report = view(&robot, &ViewRequest { scene: Some(away), ..request }).unwrap();
        assert!(report.swept.unwrap().swept.clear);
        assert!(report.contact.is_none());
    }

    #[test]
    fn issue_35_point_10_ghosts_are_checked_in_the_scene() {
        let robot = presets::get("ur5").unwrap();
        let target = Pose { xyz_m: Some([0.4, 0.2, 0.3]), rpy_deg: Some([180.0, 0.0, 0.0]), ..Pose::default() };
        let plain = view(&robot, &ViewRequest { ik_target: Some(target.clone()), ..ViewRequest::default() }).unwrap();
        assert!(plain.ghosts.iter().all(|g| g.check.is_none()));
        let elbow = plain.ghosts[0].state.frames[2].xyz_m;
        let scene = format!(
            "length_unit = \"m\"\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = 0.05\n",
            elbow[0], elbow[1], elbow[2]
        );
        let parsed = parse_scene(&scene).unwrap();
        let report =
            view(&robot, &ViewRequest { ik_target: Some(target), scene: Some(scene), ..ViewRequest::default() })
                .unwrap();
        let mut checker = CollisionChecker::new(&robot, &parsed);
        for g in &report.ghosts {
            let q = Joints::Deg(g.state.q_deg.clone()).si(&robot, "q").unwrap();
            let check = g.check.as_ref().unwrap();
            assert_eq!(check.free, checker.check(&q).unwrap().is_free(), "{}", g.branch);
        }
        assert!(!report.ghosts[0].check.as_ref().unwrap().free);
        assert!(matches!(report.ghosts[0].check.as_ref().unwrap().verdict, Verdict::Obstacle { obstacle: 0, .. }));
        assert!(report.ghosts[0].check.as_ref().unwrap().verdict_text.contains("`ball`"));
        assert!(report.ghosts.iter().any(|g| g.check.as_ref().unwrap().free));
    }
}
