//! The event log: the paper's operator messages K1–K14 (notes 003 §4, Fig. 6).

use std::fmt;

use serde::Serialize;

use super::checks::{Violation, ViolationKind};
use super::path::TrackedPath;
use super::singular::{SplitKind, SplitPoint};
use crate::ik::Branch;
use crate::model::{JointKind, Robot};

/// The paper's operator messages (notes 003 §4, Fig. 6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum EventCode {
    /// Gripper outside the manipulation space.
    K1,
    /// Gripper at a singular point.
    K2,
    /// Gripper in the manipulation space.
    K3,
    /// The default configuration breaks an angle range; switching to the next.
    K4,
    /// The default configuration breaks a speed limit; switching to the next.
    K5,
    /// The default configuration is realisable; checking the others.
    K6,
    /// Another configuration breaks an angle range.
    K7,
    /// Interval not realisable; checking the next.
    K8,
    /// Realising a configuration in the interval.
    K9,
    /// Moving to the next interval.
    K10,
    /// End of trajectory.
    K11,
    /// Another configuration breaks a speed limit.
    K12,
    /// Several configurations realisable.
    K13,
    /// Criterion cannot be satisfied; the default configuration is realised.
    K14,
}

impl EventCode {
    /// `K1` … `K14`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            EventCode::K1 => "K1",
            EventCode::K2 => "K2",
            EventCode::K3 => "K3",
            EventCode::K4 => "K4",
            EventCode::K5 => "K5",
            EventCode::K6 => "K6",
            EventCode::K7 => "K7",
            EventCode::K8 => "K8",
            EventCode::K9 => "K9",
            EventCode::K10 => "K10",
            EventCode::K11 => "K11",
            EventCode::K12 => "K12",
            EventCode::K13 => "K13",
            EventCode::K14 => "K14",
        }
    }
}

/// One message of the event log.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackingEvent {
    /// Which message.
    pub code: EventCode,
    /// Path parameter it refers to.
    pub s: f64,
    /// Time.
    pub t: f64,
    /// 1-based interval number, when it concerns an interval.
    pub interval: Option<usize>,
    /// Index of the configuration concerned.
    pub configuration: Option<usize>,
    /// 1-based joint concerned.
    pub joint: Option<usize>,
    /// The text.
    pub message: String,
}

impl fmt::Display for TrackingEvent {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} [s = {:.6}, t = {:.3} s] {}", self.code.as_str(), self.s, self.t, self.message)
    }
}

fn joint_symbol(robot: &Robot, j: usize) -> String {
    let kind = robot.joints()[j - 1].kind;
    let name = &robot.joints()[j - 1].name;
    let sym = if kind == JointKind::Revolute { "θ" } else { "d" };
    if name.is_empty() { format!("{sym}{j}") } else { format!("{sym}{j} ({name})") }
}

/// A violated limit as operators read it: `[lower, upper]` in degrees (deg/s) for a revolute
/// joint, metres (m/s) for a prismatic one.
fn limit_range(robot: &Robot, v: &Violation) -> String {
    let kind = v.joint.map_or(JointKind::Revolute, |j| robot.joints()[j - 1].kind);
    let rate = v.kind == ViolationKind::Velocity;
    let (scale, unit) = match (kind, rate) {
        (JointKind::Revolute, false) => (180.0 / std::f64::consts::PI, "deg"),
        (JointKind::Revolute, true) => (180.0 / std::f64::consts::PI, "deg/s"),
        (JointKind::Prismatic, false) => (1.0, "m"),
        (JointKind::Prismatic, true) => (1.0, "m/s"),
    };
    format!("[{:.2}, {:.2}] {unit}", v.lower * scale, v.upper * scale)
}

/// The event log of one tracking run, in the order of the decisions.
pub(super) struct EventLog<'a> {
    robot: &'a Robot,
    path: &'a TrackedPath<'a>,
    /// The configurations' labels (`any` for the empty filter, else quoted).
    names: Vec<String>,
    events: Vec<TrackingEvent>,
}

impl<'a> EventLog<'a> {
    pub(super) fn new(robot: &'a Robot, path: &'a TrackedPath<'a>, configurations: &[Branch]) -> Self {
        let names = configurations
            .iter()
            .map(|c| if c.0.is_empty() { "any".to_string() } else { format!("\"{c}\"") })
            .collect();
        EventLog { robot, path, names, events: Vec::new() }
    }

    pub(super) fn into_events(self) -> Vec<TrackingEvent> {
        self.events
    }

    fn push(
        &mut self,
        code: EventCode,
        s: f64,
        interval: Option<usize>,
        configuration: Option<usize>,
        joint: Option<usize>,
        message: String,
    ) {
        let t = self.path.time_at(s);
        self.events.push(TrackingEvent { code, s, t, interval, configuration, joint, message });
    }

    /// K2 at a singular position, K1/K3 where the path leaves/enters the reachable set.
    pub(super) fn split(&mut self, p: &SplitPoint) {
        let (code, message) = match p.kind {
            SplitKind::Singular(kind) => {
                (EventCode::K2, format!("gripper at a singular point ({} singularity)", kind.as_str()))
            }
            SplitKind::Leaves => (EventCode::K1, "gripper leaves the manipulation space".to_string()),
            SplitKind::Enters => (EventCode::K3, "gripper enters the manipulation space".to_string()),
        };
        self.push(code, p.s, None, None, None, message);
    }

    /// K1: interval `index` lies outside the reachable set.
    pub(super) fn outside(&mut self, index: usize, a: f64, b: f64) {
        let message = format!("gripper outside the manipulation space on s ∈ ({a:.6}, {b:.6})");
        self.push(EventCode::K1, a, Some(index), None, None, message);
    }

    /// K3: interval `index` lies in the reachable set.
    pub(super) fn inside(&mut self, index: usize, a: f64, b: f64) {
        let message = format!("gripper in the manipulation space on interval P{index}, s ∈ [{a:.6}, {b:.6}]");
        self.push(EventCode::K3, a, Some(index), None, None, message);
    }

    /// K8: no configuration realises interval `index`.
    pub(super) fn not_realizable(&mut self, s: f64, index: usize) {
        let message = format!("trajectory interval P{index} not realizable; checking the next interval");
        self.push(EventCode::K8, s, Some(index), None, None, message);
    }

    /// K4/K5 (the default configuration, `next` the one tried next) or K7/K12 (another one):
    /// configuration `c` breaks a limit or loses its branch.
    pub(super) fn violation(&mut self, index: usize, c: usize, v: &Violation, is_default: bool, next: Option<usize>) {
        let robot = self.robot;
        let name = &self.names[c];
        let joint = v.joint.map(|j| joint_symbol(robot, j)).unwrap_or_default();
        let switching = next.map(|n| format!("; switching to configuration {}", self.names[n])).unwrap_or_default();
        let (code, text) = match (v.kind, is_default) {
            (ViolationKind::Position, true) => (
                EventCode::K4,
                format!(
                    "angle {joint} not in the interval of possible values {} on s ∈ ({:.6}, {:.6}){switching}",
                    limit_range(robot, v),
                    v.s_start,
                    v.s_end,
                ),
            ),
            (ViolationKind::Velocity, true) => (
                EventCode::K5,
                format!(
                    "angular velocity of {joint} not in {} on s ∈ ({:.6}, {:.6}){switching}; configuration {name} not realizable",
                    limit_range(robot, v),
                    v.s_start,
                    v.s_end,
                ),
            ),
            (ViolationKind::Position, false) => (
                EventCode::K7,
                format!(
                    "computed angle {joint} not in the interval of possible values {} on s ∈ ({:.6}, {:.6}); configuration {name} not realizable",
                    limit_range(robot, v),
                    v.s_start,
                    v.s_end,
                ),
            ),
            (ViolationKind::Velocity, false) => (
                EventCode::K12,
                format!(
                    "computed angular velocity of {joint} not in {} on s ∈ ({:.6}, {:.6}); configuration {name} not realizable",
                    limit_range(robot, v),
                    v.s_start,
                    v.s_end,
                ),
            ),
            (ViolationKind::BranchLost, d) => (
                if d { EventCode::K4 } else { EventCode::K7 },
                format!(
                    "configuration {name} has no solution on s ∈ ({:.6}, {:.6}); not realizable",
                    v.s_start, v.s_end
                ),
            ),
        };
        self.push(code, v.s_start, Some(index), Some(c), v.joint, text);
    }

    /// K6: the default configuration `c` is realisable (`others`: there are others to check).
    pub(super) fn realizable(&mut self, s: f64, index: usize, c: usize, others: bool) {
        let rest = if others { "; checking the other configurations" } else { "" };
        let message = format!("configuration {} realizable{rest}", self.names[c]);
        self.push(EventCode::K6, s, Some(index), Some(c), None, message);
    }

    /// K13: several configurations are realisable.
    pub(super) fn several_realizable(&mut self, s: f64, index: usize, feasible: &[usize]) {
        let names: Vec<&str> = feasible.iter().map(|&c| self.names[c].as_str()).collect();
        let message = format!("configurations {} realizable", names.join(", "));
        self.push(EventCode::K13, s, Some(index), None, None, message);
    }

    /// K14: the criterion scores none; configuration `c` is realised.
    pub(super) fn criterion_rejected(&mut self, s: f64, index: usize, c: usize) {
        let message =
            format!("criterion cannot be satisfied; rejecting it, configuration {} is realized", self.names[c]);
        self.push(EventCode::K14, s, Some(index), Some(c), None, message);
    }

    /// K9: configuration `c` realises interval `index`.
    pub(super) fn realized(&mut self, s: f64, index: usize, c: usize) {
        let message = format!("in interval P{index} I realize configuration {}", self.names[c]);
        self.push(EventCode::K9, s, Some(index), Some(c), None, message);
    }

    /// K10: from interval `index` to the next.
    pub(super) fn next_interval(&mut self, s: f64, index: usize) {
        let message = format!("moving to the next trajectory interval P{}", index + 1);
        self.push(EventCode::K10, s, Some(index), None, None, message);
    }

    /// K11: the end of the path, in interval `index`.
    pub(super) fn end(&mut self, s: f64, index: usize) {
        self.push(EventCode::K11, s, Some(index), None, None, "end of trajectory".into());
    }
}
