//! The event log the tracker writes as it decides (notes 003 §4, Fig. 6): one method per
//! message, each event with its data ([`EventDetail`]).

use super::checks::{Violation, ViolationKind};
use super::events::{EventCode, EventDetail, TrackingEvent};
use super::path::TrackedPath;
use super::singular::{SplitKind, SplitPoint};
use crate::ik::Branch;

/// The event log of one tracking run, in the order of the decisions.
pub(super) struct EventLog<'a> {
    path: &'a TrackedPath<'a>,
    configurations: &'a [Branch],
    events: Vec<TrackingEvent>,
}

impl<'a> EventLog<'a> {
    pub(super) fn new(path: &'a TrackedPath<'a>, configurations: &'a [Branch]) -> Self {
        EventLog { path, configurations, events: Vec::new() }
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
        detail: EventDetail,
    ) {
        let t = self.path.time_at(s);
        self.events.push(TrackingEvent { code, s, t, interval, configuration, detail });
    }

    fn branch(&self, c: usize) -> Branch {
        self.configurations[c].clone()
    }

    /// K2 at a singular position, K1/K3 where the path leaves/enters the reachable set.
    pub(super) fn split(&mut self, p: &SplitPoint) {
        let (code, detail) = match p.kind {
            SplitKind::Singular(kind) => (EventCode::K2, EventDetail::Singular { kind, measure: p.measure }),
            SplitKind::Leaves => (EventCode::K1, EventDetail::Leaves),
            SplitKind::Enters => (EventCode::K3, EventDetail::Enters),
        };
        self.push(code, p.s, None, None, detail);
    }

    /// K1: interval `index` lies outside the reachable set.
    pub(super) fn outside(&mut self, index: usize, a: f64, b: f64) {
        self.push(EventCode::K1, a, Some(index), None, EventDetail::Outside { s_start: a, s_end: b });
    }

    /// K3: interval `index` lies in the reachable set.
    pub(super) fn inside(&mut self, index: usize, a: f64, b: f64) {
        self.push(EventCode::K3, a, Some(index), None, EventDetail::Inside { s_start: a, s_end: b });
    }

    /// K8: no configuration realises interval `index`.
    pub(super) fn not_realizable(&mut self, s: f64, index: usize) {
        self.push(EventCode::K8, s, Some(index), None, EventDetail::NotRealizable);
    }

    /// K4/K5 (the default configuration, `next` the one tried next) or K7/K12 (another one):
    /// configuration `c` breaks a limit or loses its branch.
    pub(super) fn violation(&mut self, index: usize, c: usize, v: &Violation, is_default: bool, next: Option<usize>) {
        let configuration = self.branch(c);
        let next = if is_default { next.map(|n| self.branch(n)) } else { None };
        let (s_start, s_end) = (v.s_start, v.s_end);
        let joint = v.joint.map_or(0, |j| j - 1);
        let (code, detail) = match v.kind {
            ViolationKind::Position => (
                if is_default { EventCode::K4 } else { EventCode::K7 },
                EventDetail::JointLimit {
                    configuration,
                    joint,
                    value: v.worst,
                    lower: v.lower,
                    upper: v.upper,
                    s_start,
                    s_end,
                    next,
                },
            ),
            ViolationKind::Velocity => (
                if is_default { EventCode::K5 } else { EventCode::K12 },
                EventDetail::Velocity { configuration, joint, value: v.worst, limit: v.upper, s_start, s_end, next },
            ),
            ViolationKind::BranchLost => (
                if is_default { EventCode::K4 } else { EventCode::K7 },
                EventDetail::BranchLost { configuration, s_start, s_end },
            ),
        };
        self.push(code, v.s_start, Some(index), Some(c), detail);
    }

    /// K6: the default configuration `c` is realisable (`others`: there are others to check).
    pub(super) fn realizable(&mut self, s: f64, index: usize, c: usize, others: bool) {
        let detail = EventDetail::Realizable { configuration: self.branch(c), others };
        self.push(EventCode::K6, s, Some(index), Some(c), detail);
    }

    /// K13: several configurations are realisable.
    pub(super) fn several_realizable(&mut self, s: f64, index: usize, feasible: &[usize]) {
        let detail =
            EventDetail::SeveralRealizable { configurations: feasible.iter().map(|&c| self.branch(c)).collect() };
        self.push(EventCode::K13, s, Some(index), None, detail);
    }

    /// K14: the criterion scores none; configuration `c` is realised.
    pub(super) fn criterion_rejected(&mut self, s: f64, index: usize, c: usize) {
        let detail = EventDetail::CriterionRejected { configuration: self.branch(c) };
        self.push(EventCode::K14, s, Some(index), Some(c), detail);
    }

    /// K9: configuration `c` realises interval `index`.
    pub(super) fn realized(&mut self, s: f64, index: usize, c: usize) {
        let detail = EventDetail::Chosen { configuration: self.branch(c) };
        self.push(EventCode::K9, s, Some(index), Some(c), detail);
    }

    /// K10: from interval `index` to the next.
    pub(super) fn next_interval(&mut self, s: f64, index: usize) {
        self.push(EventCode::K10, s, Some(index), None, EventDetail::NextInterval);
    }

    /// K11: the end of the path, in interval `index`.
    pub(super) fn end(&mut self, s: f64, index: usize) {
        self.push(EventCode::K11, s, Some(index), None, EventDetail::End);
    }
}
