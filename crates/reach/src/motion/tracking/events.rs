//! The event log: the paper's operator messages K1–K14 (notes 003 §4, Fig. 6).
//!
//! An event carries what it says as data ([`EventDetail`]: path parameters, joint values and
//! limits in SI units and radians, joint indices 0-based, configurations as [`Branch`]
//! labels); [`describe`] makes the text an operator reads, in degrees or radians.

use std::f64::consts::PI;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::ik::{Branch, SingularityKind};
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

/// What an event says, in SI units (metres, seconds) and radians; joint indices are 0-based.
/// Path parameters are those of the [`TrackedPath`](super::TrackedPath).
///
/// In JSON (the `move` and `plan` reports' events): internally tagged by `type`
/// (`{"type": "joint_limit", "configuration": [["elbow", "up"]], "joint": 3, …}`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(tag = "type", rename_all = "snake_case")]
#[non_exhaustive]
pub enum EventDetail {
    /// K2: the gripper at a singular position.
    Singular {
        /// Which singularity.
        kind: SingularityKind,
        /// The refined value of the measure that found it ([`SplitPoint::measure`](super::SplitPoint::measure)).
        measure: f64,
    },
    /// K1: the path leaves the reachable set here.
    Leaves,
    /// K3: the path enters the reachable set here.
    Enters,
    /// K1: the interval lies outside the reachable set.
    Outside {
        /// Start of the interval (path parameter).
        s_start: f64,
        /// End of the interval.
        s_end: f64,
    },
    /// K3: the interval lies in the reachable set.
    Inside {
        /// Start of the interval (path parameter).
        s_start: f64,
        /// End of the interval.
        s_end: f64,
    },
    /// K4 (the default configuration) or K7 (another one): a joint leaves its range.
    JointLimit {
        /// The configuration.
        configuration: Branch,
        /// 0-based joint index.
        joint: usize,
        /// The worst value reached (radians or metres; wrapped into (−π, π] for a revolute
        /// range narrower than a turn).
        value: f64,
        /// Lower limit (radians or metres).
        lower: f64,
        /// Upper limit.
        upper: f64,
        /// Where the violation starts (path parameter).
        s_start: f64,
        /// Where it ends.
        s_end: f64,
        /// K4: the configuration tried next, if any.
        next: Option<Branch>,
    },
    /// K5 (the default configuration) or K12 (another one): a joint faster than its limit.
    Velocity {
        /// The configuration.
        configuration: Branch,
        /// 0-based joint index.
        joint: usize,
        /// The worst rate reached (rad/s or m/s, signed).
        value: f64,
        /// The speed limit (rad/s or m/s): `|q̇| ≤ limit`.
        limit: f64,
        /// Where the violation starts (path parameter).
        s_start: f64,
        /// Where it ends.
        s_end: f64,
        /// K5: the configuration tried next, if any.
        next: Option<Branch>,
    },
    /// K4 (the default configuration) or K7 (another one): the configuration's branch has no
    /// solution, without a singular position to pass it on.
    BranchLost {
        /// The configuration.
        configuration: Branch,
        /// Where the branch is lost (path parameter).
        s_start: f64,
        /// Until where.
        s_end: f64,
    },
    /// K6: the default configuration is realisable.
    Realizable {
        /// The configuration.
        configuration: Branch,
        /// Whether other configurations are checked next.
        others: bool,
    },
    /// K13: several configurations are realisable.
    SeveralRealizable {
        /// The realisable configurations, the default first when it is one.
        configurations: Vec<Branch>,
    },
    /// K14: the criterion scores no configuration; this one is realised.
    CriterionRejected {
        /// The configuration realised.
        configuration: Branch,
    },
    /// K9: the configuration realised in the interval.
    Chosen {
        /// The configuration.
        configuration: Branch,
    },
    /// K8: no configuration realises the interval.
    NotRealizable,
    /// K10: on to the next interval.
    NextInterval,
    /// K11: the end of the path.
    End,
}

/// One message of the event log.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackingEvent {
    /// Which message.
    pub code: EventCode,
    /// Path parameter it refers to.
    pub s: f64,
    /// Time, seconds.
    pub t: f64,
    /// 1-based interval number (the paper's P_t), when it concerns an interval.
    pub interval: Option<usize>,
    /// Index (into [`TrackingReport::configurations`](super::TrackingReport::configurations))
    /// of the configuration concerned.
    pub configuration: Option<usize>,
    /// What it says ([`describe`] makes the text).
    pub detail: EventDetail,
}

impl TrackingEvent {
    /// The 0-based index of the joint concerned (limit and speed events).
    #[must_use]
    pub fn joint(&self) -> Option<usize> {
        match self.detail {
            EventDetail::JointLimit { joint, .. } | EventDetail::Velocity { joint, .. } => Some(joint),
            _ => None,
        }
    }
}

/// The text of an event as operators read it, the paper's messages K1–K14: angles and
/// angular rates in degrees (`deg`, `deg/s`) when `degrees`, else in radians (`rad`,
/// `rad/s`); lengths in metres; joints numbered from 1 and named from `robot`.
///
/// # Arguments
/// * `robot` — the robot tracked (joint names and kinds; a joint it does not have is shown
///   by number, as revolute).
///
/// # Example
/// ```
/// use reach::ik::Branch;
/// use reach::motion::tracking::{EventCode, EventDetail, TrackingEvent, describe};
/// let welder = reach::model::presets::get("welder6r").unwrap();
/// let detail = EventDetail::JointLimit {
///     configuration: Branch::new([("config", "−β")]),
///     joint: 3,
///     value: 2.9,
///     lower: (-175f64).to_radians(),
///     upper: 150f64.to_radians(),
///     s_start: 0.618103,
///     s_end: 0.882211,
///     next: None,
/// };
/// let (s, t) = (0.618103, 618.103);
/// let event = TrackingEvent { code: EventCode::K7, s, t, interval: Some(1), configuration: Some(1), detail };
/// assert_eq!(
///     describe(&event, &welder, true),
///     "computed angle θ4 (wrist-pitch) not in the interval of possible values [-175.00, 150.00] deg \
///      on s ∈ (0.618103, 0.882211); configuration \"config=−β\" not realizable"
/// );
/// assert!(describe(&event, &welder, false).contains("[-3.0543, 2.6180] rad"));
/// ```
#[must_use]
pub fn describe(event: &TrackingEvent, robot: &Robot, degrees: bool) -> String {
    let interval = event.interval.map_or_else(|| "?".to_string(), |i| i.to_string());
    let limit = |joint: usize, lower: f64, upper: f64, rate: bool| {
        let kind = robot.joints().get(joint).map_or(JointKind::Revolute, |j| j.kind);
        let (scale, unit, digits) = match (kind, rate, degrees) {
            (JointKind::Revolute, false, true) => (180.0 / PI, "deg", 2),
            (JointKind::Revolute, true, true) => (180.0 / PI, "deg/s", 2),
            (JointKind::Revolute, false, false) => (1.0, "rad", 4),
            (JointKind::Revolute, true, false) => (1.0, "rad/s", 4),
            (JointKind::Prismatic, false, _) => (1.0, "m", 2),
            (JointKind::Prismatic, true, _) => (1.0, "m/s", 2),
        };
        format!("[{:.digits$}, {:.digits$}] {unit}", lower * scale, upper * scale)
    };
    let switching = |next: &Option<Branch>| {
        next.as_ref().map(|n| format!("; switching to configuration {}", name(n))).unwrap_or_default()
    };
    match &event.detail {
        EventDetail::Singular { kind, .. } => format!("gripper at a singular point ({} singularity)", kind.as_str()),
        EventDetail::Leaves => "gripper leaves the manipulation space".to_string(),
        EventDetail::Enters => "gripper enters the manipulation space".to_string(),
        EventDetail::Outside { s_start, s_end } => {
            format!("gripper outside the manipulation space on s ∈ ({s_start:.6}, {s_end:.6})")
        }
        EventDetail::Inside { s_start, s_end } => {
            format!("gripper in the manipulation space on interval P{interval}, s ∈ [{s_start:.6}, {s_end:.6}]")
        }
        EventDetail::JointLimit { configuration, joint, lower, upper, s_start, s_end, next, .. } => {
            let (joint, range) = (joint_symbol(robot, *joint), limit(*joint, *lower, *upper, false));
            if event.code == EventCode::K4 {
                format!(
                    "angle {joint} not in the interval of possible values {range} on s ∈ ({s_start:.6}, {s_end:.6}){}",
                    switching(next)
                )
            } else {
                format!(
                    "computed angle {joint} not in the interval of possible values {range} on s ∈ ({s_start:.6}, {s_end:.6}); configuration {} not realizable",
                    name(configuration)
                )
            }
        }
        EventDetail::Velocity { configuration, joint, limit: vmax, s_start, s_end, next, .. } => {
            let (joint, range) = (joint_symbol(robot, *joint), limit(*joint, -vmax, *vmax, true));
            if event.code == EventCode::K5 {
                format!(
                    "angular velocity of {joint} not in {range} on s ∈ ({s_start:.6}, {s_end:.6}){}; configuration {} not realizable",
                    switching(next),
                    name(configuration)
                )
            } else {
                format!(
                    "computed angular velocity of {joint} not in {range} on s ∈ ({s_start:.6}, {s_end:.6}); configuration {} not realizable",
                    name(configuration)
                )
            }
        }
        EventDetail::BranchLost { configuration, s_start, s_end } => format!(
            "configuration {} has no solution on s ∈ ({s_start:.6}, {s_end:.6}); not realizable",
            name(configuration)
        ),
        EventDetail::Realizable { configuration, others } => {
            let rest = if *others { "; checking the other configurations" } else { "" };
            format!("configuration {} realizable{rest}", name(configuration))
        }
        EventDetail::SeveralRealizable { configurations } => {
            let names: Vec<String> = configurations.iter().map(name).collect();
            format!("configurations {} realizable", names.join(", "))
        }
        EventDetail::CriterionRejected { configuration } => {
            format!("criterion cannot be satisfied; rejecting it, configuration {} is realized", name(configuration))
        }
        EventDetail::Chosen { configuration } => {
            format!("in interval P{interval} I realize configuration {}", name(configuration))
        }
        EventDetail::NotRealizable => {
            format!("trajectory interval P{interval} not realizable; checking the next interval")
        }
        EventDetail::NextInterval => {
            let next = event.interval.map_or_else(|| "?".to_string(), |i| (i + 1).to_string());
            format!("moving to the next trajectory interval P{next}")
        }
        EventDetail::End => "end of trajectory".to_string(),
    }
}

/// A configuration as the messages name it: `any` for the empty filter, else quoted.
fn name(configuration: &Branch) -> String {
    if configuration.0.is_empty() { "any".to_string() } else { format!("\"{configuration}\"") }
}

/// `θ4 (name)` for the 0-based joint index 3 (`d4` for a prismatic joint; no name when the
/// joint has none or the robot does not have it).
fn joint_symbol(robot: &Robot, joint: usize) -> String {
    let number = joint + 1;
    match robot.joints().get(joint) {
        Some(j) => {
            let sym = if j.kind == JointKind::Revolute { "θ" } else { "d" };
            if j.name.is_empty() { format!("{sym}{number}") } else { format!("{sym}{number} ({})", j.name) }
        }
        None => format!("θ{number}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    fn event(code: EventCode, detail: EventDetail) -> TrackingEvent {
        TrackingEvent { code, s: 0.25, t: 1.5, interval: Some(2), configuration: Some(0), detail }
    }

    fn limit(next: Option<Branch>) -> EventDetail {
        EventDetail::JointLimit {
            configuration: Branch::new([("elbow", "up")]),
            joint: 3,
            value: 2.7,
            lower: (-175f64).to_radians(),
            upper: 150f64.to_radians(),
            s_start: 0.25,
            s_end: 0.5,
            next,
        }
    }

    #[test]
    fn a_limit_event_reads_in_degrees_or_radians() {
        let welder = presets::get("welder6r").unwrap();
        let k4 = event(EventCode::K4, limit(Some(Branch::new([("elbow", "down")]))));
        assert_eq!(
            describe(&k4, &welder, true),
            "angle θ4 (wrist-pitch) not in the interval of possible values [-175.00, 150.00] deg on s ∈ \
             (0.250000, 0.500000); switching to configuration \"elbow=down\""
        );
        assert_eq!(
            describe(&k4, &welder, false),
            "angle θ4 (wrist-pitch) not in the interval of possible values [-3.0543, 2.6180] rad on s ∈ \
             (0.250000, 0.500000); switching to configuration \"elbow=down\""
        );
        let k7 = event(EventCode::K7, limit(None));
        assert_eq!(
            describe(&k7, &welder, false),
            "computed angle θ4 (wrist-pitch) not in the interval of possible values [-3.0543, 2.6180] rad on s ∈ \
             (0.250000, 0.500000); configuration \"elbow=up\" not realizable"
        );
        assert_eq!(k7.joint(), Some(3));
    }

    #[test]
    fn a_speed_event_reads_in_degrees_or_radians_per_second() {
        let welder = presets::get("welder6r").unwrap();
        let detail = EventDetail::Velocity {
            configuration: Branch::default(),
            joint: 0,
            value: -0.9,
            limit: 30f64.to_radians(),
            s_start: 0.0,
            s_end: 0.125,
            next: None,
        };
        let k12 = event(EventCode::K12, detail);
        assert_eq!(
            describe(&k12, &welder, true),
            "computed angular velocity of θ1 (column) not in [-30.00, 30.00] deg/s on s ∈ (0.000000, 0.125000); \
             configuration any not realizable"
        );
        assert!(describe(&k12, &welder, false).contains("not in [-0.5236, 0.5236] rad/s on"));
        // A joint the robot does not have is shown by number, not a panic.
        let mut far = k12.clone();
        if let EventDetail::Velocity { joint, .. } = &mut far.detail {
            *joint = 9;
        }
        assert!(describe(&far, &welder, true).contains("of θ10 not in"));
    }

    #[test]
    fn interval_events_name_the_interval_and_the_configurations() {
        let robot = presets::get("log-loader").unwrap();
        let up = Branch::new([("base", "front"), ("elbow", "up")]);
        let down = Branch::new([("base", "front"), ("elbow", "down")]);
        let text = |code, detail| describe(&event(code, detail), &robot, true);
        assert_eq!(
            text(EventCode::K13, EventDetail::SeveralRealizable { configurations: vec![up.clone(), down] }),
            "configurations \"base=front elbow=up\", \"base=front elbow=down\" realizable"
        );
        assert_eq!(
            text(EventCode::K9, EventDetail::Chosen { configuration: up }),
            "in interval P2 I realize configuration \"base=front elbow=up\""
        );
        assert_eq!(text(EventCode::K10, EventDetail::NextInterval), "moving to the next trajectory interval P3");
        assert_eq!(
            text(EventCode::K2, EventDetail::Singular { kind: SingularityKind::Elbow, measure: 0.0 }),
            "gripper at a singular point (elbow singularity)"
        );
    }

    #[test]
    fn events_serialise_as_typed_data() {
        let k7 = event(EventCode::K7, limit(None));
        let json = serde_json::to_value(&k7).unwrap();
        assert_eq!(json["code"], "K7");
        assert_eq!(json["detail"]["type"], "joint_limit");
        assert_eq!(json["detail"]["joint"], 3);
        assert!((json["detail"]["upper"].as_f64().unwrap() - 150f64.to_radians()).abs() < 1e-15);
        assert_eq!(json["detail"]["configuration"], serde_json::json!([["elbow", "up"]]));
        assert!(json.get("message").is_none());
    }
}
