//! The `check` workflow: collisions and clearances of one configuration in a scene.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::parse_scene;
use crate::Robot;
use crate::error::Result;
use crate::jobs::input::Joints;
use crate::world::{CollisionChecker, Contact, LinkClearance, Scene, SelfClearance, Verdict};

/// One configuration checked against a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckRequest {
    /// The text of the scene file (TOML: obstacles, tool zone, touching policy).
    pub scene: String,
    /// The joint values.
    pub q: Joints,
}

/// Collisions and clearances of one configuration (`reach check --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CheckReport {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// The first failed check (or free).
    pub verdict: Verdict,
    /// The verdict in words, with the names of the obstacle or zone.
    pub verdict_text: String,
    /// Every (link, obstacle) pair.
    pub links: Vec<LinkClearance>,
    /// Every pair of non-adjacent links.
    pub self_pairs: Vec<SelfClearance>,
    /// The tool point against every zone entry.
    pub tool_zone: Vec<Contact>,
    /// Smallest link–obstacle clearance (`null` without obstacles), metres.
    pub min_obstacle_clearance_m: Option<f64>,
    /// Smallest link–link clearance (`null` without non-adjacent pairs), metres.
    pub min_self_clearance_m: Option<f64>,
}

/// The verdict in words, naming the obstacle or zone.
#[must_use]
pub fn verdict_text(verdict: &Verdict, scene: &Scene) -> String {
    match verdict {
        Verdict::Free => "free".into(),
        Verdict::OutsideZone { zone } => format!("tool outside zone `{}`", scene.tool_zone[*zone].name),
        Verdict::SelfCollision { link_a, link_b } => format!("self-collision: links {link_a} and {link_b}"),
        Verdict::Obstacle { link, obstacle } => {
            format!("collision: link {link} with `{}`", scene.obstacles[*obstacle].name)
        }
    }
}

/// Checks the configuration: whatever the verdict, it is in the report.
///
/// # Errors
/// [`crate::Error::World`] for a malformed scene (line and column); [`crate::Error::Request`]
/// for a wrong joint count or a non-finite value (field `q`).
pub fn check(robot: &Robot, request: &CheckRequest) -> Result<CheckReport> {
    let scene = parse_scene(&request.scene)?;
    let q = request.q.si(robot, "q")?;
    let report = CollisionChecker::new(robot, &scene).report(&q)?;
    Ok(CheckReport {
        robot: robot.name().to_string(),
        q_deg: request.q.display(robot),
        verdict_text: verdict_text(&report.verdict, &scene),
        verdict: report.verdict,
        links: report.links,
        self_pairs: report.self_pairs,
        tool_zone: report.tool_zone,
        min_obstacle_clearance_m: report.min_obstacle_clearance_m,
        min_self_clearance_m: report.min_self_clearance_m,
    })
}
