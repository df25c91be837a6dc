//! The world workflows: a configuration checked against a scene (`check`), seed 000's planar
//! detour (`avoid`), seed 004's configuration-space grid and its fitted region (`cspace`),
//! seed 004's motion synthesis next to forbidden zones (`approach`),
//! a collision-free, timed joint-space path through a scene (`path`), and seed 000's obstacle
//! located from ultrasonic range readings (`sense`).
//!
//! Requests that need a scene carry the **text** of the scene file (`scene`, TOML,
//! docs/scene-format.md); it is parsed here ([`parse_scene`]), so a front end only reads the
//! file.

pub mod approach;
pub mod avoid;
pub mod check;
pub mod cspace;
pub mod path;
pub mod sense;
pub mod timed;

pub use approach::{
    ApproachReport, ApproachRequest, FastRegionRequest, HandoverReport, approach, approach_with_cancel,
};
pub use avoid::{AvoidChoice, AvoidReport, AvoidRequest, AvoidRun, AvoidSide, avoid, avoid_run};
pub use check::{CheckReport, CheckRequest, MotionCheckReport, SweptPathReport, SweptReport, check, motion_times};
pub use cspace::{
    CspaceReport, CspaceRequest, CspaceSection, FitPrimitive, FitReport, cspace, cspace_axes, cspace_with_cancel,
    cspace_with_grid,
};
pub use path::{
    PathReport, PathRequest, PathRun, PathStatsReport, PathTiming, TimedPath, path, path_run, path_run_with_cancel,
};
pub use sense::{SenseReport, SenseRequest, SensorReading, sense};

use crate::Robot;
use crate::error::{Error, Result};
use crate::world::Scene;

/// Refuses a non-finite value of the list `field`, naming it by its 1-based index
/// (`to_xy_m[2]: expected a finite number, got NaN`).
///
/// # Errors
/// [`crate::Error::Request`].
pub(crate) fn finite(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => {
            Err(Error::request(format!("{field}[{}]", i + 1), format!("expected a finite number, got {}", values[i])))
        }
        None => Ok(()),
    }
}

/// A request's start (`from`) and goal (`to` or `to_pose`, exactly one) in SI, joint vectors
/// within the limits (the `path` and `approach` workflows).
///
/// # Errors
/// [`Error::Request`] naming `from`, `to` or `to_pose` for bad values, a joint outside its
/// limits, or both or neither goal.
fn start_and_goal(
    robot: &crate::Robot,
    from: &crate::jobs::input::Joints,
    to: Option<&crate::jobs::input::Joints>,
    to_pose: Option<&crate::jobs::input::Pose>,
) -> Result<(Vec<f64>, crate::world::planner::Goal)> {
    use crate::jobs::input::require_within_limits;
    use crate::world::planner::Goal;
    let start = from.si(robot, "from")?;
    require_within_limits(robot, &start, from.unit(), "from")?;
    let goal = match (to, to_pose) {
        (Some(q), None) => {
            let goal = q.si(robot, "to")?;
            require_within_limits(robot, &goal, q.unit(), "to")?;
            Goal::Joints(goal)
        }
        (None, Some(p)) => Goal::Target(p.target("to_pose")?),
        _ => return Err(Error::request("to", "give exactly one of `to` and `to_pose`")),
    };
    Ok((start, goal))
}

/// Parses a request's scene text: a MoveIt planning scene (YAML, [`Scene::from_moveit_yaml`])
/// when a line starts with one of the message's top-level keys (`world:`, `robot_state:`,
/// `name:`, …; a TOML file writes `key = value`), else the TOML scene format.
///
/// # Errors
/// [`crate::Error::World`]: [`crate::world::WorldError::Parse`] with the line and column of
/// malformed TOML or YAML, or the shape, object or entry that is invalid.
pub fn parse_scene(text: &str) -> Result<Scene> {
    if is_moveit_scene(text) { Ok(Scene::from_moveit_yaml(text)?) } else { Ok(Scene::from_toml_str(text)?) }
}

/// How far from a robot's base a workcell may reach: this many times the robot's reach
/// bound ([`workcell_radius_m`]).
pub const WORKCELL_REACH_FACTOR: f64 = 10.0;

/// The radius, metres, of the ball about the robot's first joint within which a scene kept
/// for it must lie ([`require_workcell`]): [`WORKCELL_REACH_FACTOR`] times its reach bound
/// (the numeric IK's, [`crate::ik::numeric::Numeric::reach_bound`]), at least 1 m and at most
/// 1 km (a robot with an unbounded prismatic joint).
#[must_use]
pub fn workcell_radius_m(robot: &Robot) -> f64 {
    let reach = crate::ik::numeric::Numeric::from_robot(robot).map_or(f64::INFINITY, |n| n.reach_bound());
    (WORKCELL_REACH_FACTOR * reach).clamp(1.0, 1000.0)
}

/// Refuses a scene with an obstacle or tool-zone entry beyond the robot's workcell
/// ([`workcell_radius_m`] about its first joint): what a service that keeps a scene for a
/// robot checks before storing one.
///
/// # Errors
/// [`crate::Error::World`] naming the entry and how far it reaches.
pub fn require_workcell(robot: &Robot, scene: &Scene) -> Result<()> {
    let radius = workcell_radius_m(robot);
    let what = format!("{WORKCELL_REACH_FACTOR} × the reach of {}", robot.name());
    Ok(scene.require_within(&robot.chain.first.translation.vector, radius, &what)?)
}

/// Whether `text` is written as a MoveIt planning scene (see [`parse_scene`]).
#[must_use]
pub fn is_moveit_scene(text: &str) -> bool {
    const KEYS: [&str; 9] = [
        "world",
        "robot_state",
        "robot_model_name",
        "name",
        "fixed_frame_transforms",
        "allowed_collision_matrix",
        "link_padding",
        "link_scale",
        "is_diff",
    ];
    text.lines().any(|l| {
        l.split_once(':').is_some_and(|(key, _)| KEYS.contains(&key.trim_end()) && !key.starts_with([' ', '\t']))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::{Job, Report};
    use crate::world::WorldError;

    #[test]
    fn a_workcell_is_ten_reaches_about_the_first_joint() {
        let ur5 = crate::model::presets::get("ur5").unwrap();
        let radius = workcell_radius_m(&ur5);
        let reach = crate::ik::numeric::Numeric::from_robot(&ur5).unwrap().reach_bound();
        assert!((radius - 10.0 * reach).abs() < 1e-12 && (5.0..20.0).contains(&radius), "{radius}");
        let scene =
            |body: &str| parse_scene(&format!("length_unit = \"m\"\n[[obstacles]]\nname = \"o\"\n{body}")).unwrap();
        let inside = scene("shape = \"sphere\"\ncenter = [1, 0, 0]\nradius = 0.5\n");
        require_workcell(&ur5, &inside).unwrap();
        let floor = scene("shape = \"halfspace\"\npoint = [0, 0, -0.01]\noutward_normal = [0, 0, 1]\n");
        require_workcell(&ur5, &floor).unwrap();
        for body in [
            format!("shape = \"sphere\"\ncenter = [0, 0, 0]\nradius = {}\n", radius * 1.001),
            "shape = \"sphere\"\ncenter = [0, 0, 0]\nradius = 1e308\n".to_string(),
            "shape = \"sphere\"\ncenter = [1e308, 0, 0]\nradius = 1\n".to_string(),
            "shape = \"halfspace\"\npoint = [0, 0, -1e4]\noutward_normal = [0, 0, 1]\n".to_string(),
        ] {
            let e = require_workcell(&ur5, &scene(&body)).unwrap_err().to_string();
            assert!(e.contains("obstacle `o`") && e.contains("10 × the reach of ur5"), "{body}: {e}");
        }
    }

    #[test]
    fn moveit_scenes_and_toml_scenes_are_told_apart() {
        assert!(is_moveit_scene("world:\n  collision_objects: []\n"));
        assert!(!is_moveit_scene("length_unit = \"m\"\n[[obstacles]]\nname = \"world: x\"\n"));
        let scene = parse_scene("world:\n  collision_objects:\n    - id: b\n      primitives: [{type: sphere, dimensions: [0.1]}]\n      primitive_poses: [{position: [1, 0, 0]}]\n").unwrap();
        assert_eq!(scene.obstacles.len(), 1);
    }

    #[test]
    fn a_malformed_scene_is_a_world_error_with_line_and_column() {
        let e = parse_scene("[[obstacles]]\nshape = \"sphere\"\ncentre = [0, 0\n").unwrap_err();
        let crate::Error::World(WorldError::Parse { line, column, .. }) = e else { panic!("{e:?}") };
        assert!(line >= 3 && column >= 1, "{line}:{column}");
    }

    #[test]
    fn a_cspace_job_reads_fixes_by_joint_and_rejects_unknown_ones() {
        let scene = include_str!("../../../../../examples/seed004_ceiling.toml");
        let job: Job = serde_json::from_value(serde_json::json!({
            "robot": {"preset": "varan4"},
            "request": {"kind": "cspace", "scene": scene, "step_deg": 15, "fix": {"q1": 0}}
        }))
        .unwrap();
        let Report::Cspace(report) = job.run().unwrap() else { panic!("not a cspace report") };
        assert_eq!((report.counts.nodes, report.counts.allowed), (2601, 635));
        let mut bad = job.clone();
        if let crate::jobs::Request::Cspace(r) = &mut bad.request {
            r.fix = [("q9".to_string(), 0.0)].into();
        }
        let e = bad.run().unwrap_err();
        assert_eq!(e.code(), "request");
        assert!(e.to_string().starts_with("fix.q9: `q9` is not a joint q1..q4"), "{e}");
    }

    #[test]
    fn avoid_needs_exactly_one_start_and_a_positive_step() {
        let robot = crate::model::presets::get("planar3").unwrap();
        let mut request = AvoidRequest {
            start: None,
            from_xy_m: None,
            to_xy_m: [2.4, 0.2],
            obstacles_xy_m: vec![],
            step_deg: 0.01,
            literal_test: false,
            printed_waypoints: false,
            choose: None,
            sense: None,
        };
        assert!(avoid(&robot, &request).unwrap_err().to_string().contains("exactly one of `start` and `from_xy_m`"));
        request.start = Some(crate::jobs::Joints::Deg(vec![60.0, -40.0, -30.0]));
        request.step_deg = 0.0;
        assert!(avoid(&robot, &request).unwrap_err().to_string().starts_with("step_deg: must be positive"));
        request.step_deg = 0.01;
        let report = avoid(&robot, &request).unwrap();
        assert!(!report.failed() && !report.blocked);
    }
}
