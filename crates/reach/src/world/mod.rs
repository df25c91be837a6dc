//! World: scenes, shapes, collision and clearance, the seed-000 detour, configuration-space
//! maps and R-function regions.
//!
//! * [`Scene`] — obstacles (forbidden zones) and the allowed zone of the tool, parsed from
//!   TOML by [`Scene::from_toml_str`] (lengths and angles in the file's units, SI inside).
//! * [`Shape`] — points, spheres, axis-aligned and oriented boxes, capsules, half-spaces and
//!   planar rectangles, with exact distance queries against link segments ([`distance`]).
//! * [`CollisionChecker`] — collision yes/no and signed clearances of a robot's links
//!   (segments swept by a radius, [`crate::model::LinkGeometry`]) against a scene, and
//!   self-collision between non-adjacent links; allocation-free after construction.
//! * [`detour`] — seed 000: the swept-area test of the last (and middle) link and the detour
//!   through two waypoints on the `L/7` circle.
//! * [`cspace`] — seed 004: joint-grid enumeration and classification of every node.
//! * [`approach`] — seed 004: motion synthesis next to forbidden zones (safe distance as a
//!   barrier, redundancy in the null space, deadlocks, the fitted region as a first test).
//! * [`rfunction`] — seed 004: Rvachev's R-conjunction and the region primitives.
//! * [`fit`] — seed 004: fitting those primitives to a classified grid; confusion counts.
//! * [`sense`] — seed 000: an obstacle located from ultrasonic range readings (least squares,
//!   beam cones, uncertainty radius, ambiguity).
//! * [`planner`] — collision-free joint-space motion between joint vectors or to a pose:
//!   seeded bidirectional RRT-Connect with shortcutting.
//!
//! ## Touching policy
//!
//! Obstacles are **closed** sets by default: a link that touches an obstacle (clearance within
//! [`crate::tolerance::CONTACT`] of zero) collides. With [`Touching::Open`] a link may touch;
//! it collides only when it penetrates deeper than the tolerance. The tool's allowed zone is
//! **open** (seed 004's `x > 500 mm, z > 0` are strict): the tool point must lie inside every
//! zone shape by more than the tolerance.

pub mod approach;
mod collision;
pub mod cspace;
pub mod detour;
pub mod distance;
mod elements;
pub mod fit;
mod gjk;
pub mod moveit;
pub mod planner;
pub mod rfunction;
mod scene;
pub mod sense;
mod shape;
pub mod sweep;

pub use collision::{
    CollisionChecker, Contact, LinkClearance, PairSurvey, PathSweep, Report, SelfClearance, SweptPair, Verdict,
    link_label,
};
pub use moveit::PlanRequest;
pub use planner::{Blocked, Goal, Plan, PlanError, PlanOptions, PlanStats, plan};
pub use scene::{Obstacle, Scene, Touching};
pub use shape::Shape;

use thiserror::Error;

/// Why a scene or a world query was rejected.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum WorldError {
    /// A scene file that is not valid TOML or does not follow the format.
    #[error("scene file, line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A shape with a bad value (degenerate, NaN, wrong fields).
    #[error("{what} `{name}` ({shape}): {message}")]
    Shape {
        /// `obstacle` or `tool zone`.
        what: &'static str,
        /// The shape's name (from the file, or `#i`).
        name: String,
        /// The shape kind (`sphere`, `box`, …).
        shape: String,
        /// What is wrong.
        message: String,
    },
    /// A bad argument to a query (joint vector, grid, detour input).
    #[error("{0}")]
    Input(String),
    /// A grid without any allowed node: there is no region to fit
    /// ([`fit::fit_region`]). The input is valid; the answer is empty.
    #[error("the grid has no allowed node to fit a region to")]
    NoAllowedNode,
    /// The computation was stopped through its [`crate::Cancel`] flag.
    #[error("interrupted")]
    Cancelled,
    /// A kinematics error from the robot model.
    #[error(transparent)]
    Kinematics(#[from] crate::kinematics::KinematicsError),
    /// An inverse-kinematics error.
    #[error(transparent)]
    Ik(#[from] crate::ik::IkError),
}
