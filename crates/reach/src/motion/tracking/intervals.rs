//! The intervals between split points: every configuration tracked over each, the choice of
//! one (notes 003 §4 step 4) and the realised trajectory.

use std::borrow::Cow;
use std::cell::Cell;

use serde::Serialize;

use super::branch::{Lock, anchor, pick, step_rates, unwrap_to};
use super::checks::{Violation, WrapCrossing};
use super::log::EventLog;
use super::singular::{Scan, SplitKind, SplitPoint};
use super::{Tracker, TrackingError};
use crate::ik::{Branch, IkSolutions};

/// One configuration tracked over one interval.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConfigurationTrack {
    /// The configuration (filter) as given.
    pub configuration: Branch,
    /// The full branch label followed (`None` when no solution of the filter exists).
    pub branch: Option<Branch>,
    /// Path parameter per tracked sample (the interval's ends and the samples inside).
    pub s: Vec<f64>,
    /// Time per tracked sample.
    pub t: Vec<f64>,
    /// Joint vector per tracked sample, continuous (revolute angles unwrapped).
    pub q: Vec<Vec<f64>>,
    /// Rates of the steps between tracked samples ([`step_rates`]).
    pub step_rates: Vec<Vec<f64>>,
    /// Whether every joint stays within its range and speed limit.
    pub feasible: bool,
    /// Every limit broken, with where.
    pub violations: Vec<Violation>,
    /// ±180° crossings of the wrapped angles.
    pub wraps: Vec<WrapCrossing>,
}

impl ConfigurationTrack {
    /// Rates at the tracked samples: the mean of the adjacent step rates weighted by the
    /// other step's duration (the central difference on a uniform grid), one-sided at the ends.
    #[must_use]
    pub fn sample_rates(&self) -> Vec<Vec<f64>> {
        let n = self.q.len();
        if n < 2 {
            return vec![vec![0.0; self.q.first().map_or(0, Vec::len)]; n];
        }
        (0..n)
            .map(|k| {
                if k == 0 {
                    self.step_rates[0].clone()
                } else if k == n - 1 {
                    self.step_rates[n - 2].clone()
                } else {
                    let (h1, h2) = (self.t[k] - self.t[k - 1], self.t[k + 1] - self.t[k]);
                    self.step_rates[k - 1]
                        .iter()
                        .zip(&self.step_rates[k])
                        .map(|(a, b)| (a * h2 + b * h1) / (h1 + h2))
                        .collect()
                }
            })
            .collect()
    }
}

/// How an interval's configuration was chosen (reported as is by the `move` and `plan`
/// jobs, snake_case in JSON).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// The default configuration (feasible, no criterion given).
    Default,
    /// The only feasible configuration.
    OnlyFeasible,
    /// Several were feasible but not the default, and no criterion was given: the first
    /// feasible one in the list.
    FirstFeasible,
    /// Several were feasible; the criterion chose (the `move`/`plan` request's `choose`).
    Criterion,
    /// Several were feasible and the criterion scored none: the default was kept (K14).
    CriterionRejected,
    /// Outside the reachable set, or no configuration feasible (K8).
    NotRealizable,
    /// The operator chose among the feasible configurations ([`super::TrackingOptions::choices`]).
    Operator,
    /// The first interval, from where the arm is ([`super::TrackingOptions::start`]): in the
    /// start's configuration, feasible there.
    Start,
}

/// One interval between consecutive split points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntervalReport {
    /// 1-based number (the paper's P_t).
    pub index: usize,
    /// Start (path parameter).
    pub s_start: f64,
    /// End.
    pub s_end: f64,
    /// Time at the start.
    pub t_start: f64,
    /// Time at the end.
    pub t_end: f64,
    /// Whether the interval lies in the reachable set (the paper's manipulation space).
    pub reachable: bool,
    /// Every configuration tracked over the interval (empty when unreachable).
    pub configurations: Vec<ConfigurationTrack>,
    /// Index (into [`TrackingReport::configurations`](super::TrackingReport::configurations)) of
    /// the configuration realised.
    pub chosen: Option<usize>,
    /// Why.
    pub decision: Decision,
}

/// One point of the realised joint trajectory.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrajectoryPoint {
    /// Path parameter.
    pub s: f64,
    /// Time.
    pub t: f64,
    /// Joint vector (continuous over the whole trajectory).
    pub q: Vec<f64>,
    /// Index of the configuration.
    pub configuration: usize,
}

/// A user criterion for choosing among feasible configurations (notes 003 §7 item 5: smaller
/// accelerations, energy, stiffness, …): lower scores are better; `None` means the
/// configuration does not satisfy the criterion.
pub trait ConfigurationCriterion {
    /// The score of one configuration's trajectory over an interval.
    fn score(&self, track: &ConfigurationTrack) -> Option<f64>;

    /// Index (into `feasible`) of the configuration to realise, or `None` when none satisfies
    /// the criterion. Default: the lowest finite [`score`](ConfigurationCriterion::score) (first on a tie);
    /// criteria that compare the candidates with each other (multi-criteria rankings,
    /// [`crate::decide::TrackChooser`]) override it.
    fn choose(&self, feasible: &[&ConfigurationTrack]) -> Option<usize> {
        feasible
            .iter()
            .enumerate()
            .filter_map(|(k, t)| self.score(t).filter(|v| v.is_finite()).map(|v| (k, v)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .map(|(k, _)| k)
    }
}

impl<F: Fn(&ConfigurationTrack) -> Option<f64>> ConfigurationCriterion for F {
    fn score(&self, track: &ConfigurationTrack) -> Option<f64> {
        self(track)
    }
}

impl Tracker<'_> {
    /// Tracks configuration `c` over `points` (s values of one interval), given the unseeded
    /// solutions `sols` at those points (shared by the configurations); advances the meter by
    /// `budget` units, in proportion to the points followed.
    pub(super) fn track_interval(
        &self,
        c: usize,
        points: &[f64],
        sols: &[Cow<'_, IkSolutions>],
        ends_at_boundary: (bool, bool),
        budget: usize,
    ) -> Result<ConfigurationTrack, TrackingError> {
        let given = Cell::new(0);
        let followed = Cell::new(0);
        let give = |target: usize| {
            self.meter.advance(target - given.get());
            given.set(target);
        };
        let track = self.track_interval_counted(c, points, sols, ends_at_boundary, &|| {
            followed.set(followed.get() + 1);
            give(budget * followed.get() / points.len());
        })?;
        give(budget);
        Ok(track)
    }

    /// [`Tracker::track_interval`]; `tick` is called after each point followed.
    pub(super) fn track_interval_counted(
        &self,
        c: usize,
        points: &[f64],
        sols: &[Cow<'_, IkSolutions>],
        ends_at_boundary: (bool, bool),
        tick: &dyn Fn(),
    ) -> Result<ConfigurationTrack, TrackingError> {
        let robot = self.robot();
        let filter = &self.configurations[c];
        // From where the arm is, in the first interval's start configuration; else from the
        // first non-singular anchor.
        let anchor = match &self.start {
            Some(start) if start.configuration == c && points[0] <= self.path.start() + self.tolerance => {
                Some((0, (start.q.clone(), start.lock.clone())))
            }
            _ => (0..points.len())
                .filter_map(|k| anchor(&sols[k], filter, self.solving.by_label()).map(|a| (k, a)))
                .min_by_key(|(k, (q, _))| {
                    let singular = sols[*k].solutions.iter().any(|x| x.q == *q && !x.singularities.is_empty());
                    (singular, *k)
                }),
        };
        let mut track = ConfigurationTrack {
            configuration: filter.clone(),
            branch: None,
            s: Vec::new(),
            t: Vec::new(),
            q: Vec::new(),
            step_rates: Vec::new(),
            feasible: false,
            violations: Vec::new(),
            wraps: Vec::new(),
        };
        let Some((k0, (q0, lock))) = anchor else {
            track.violations.push(self.lost(points[0], points[points.len() - 1]));
            return Ok(track);
        };
        track.branch = Some(match &lock {
            Lock::Label(b) => b.clone(),
            Lock::Filter(f) => f.clone(),
        });
        let mut q: Vec<Option<Vec<f64>>> = vec![None; points.len()];
        q[k0] = Some(q0);
        let mut lost: Option<(f64, f64)> = None;
        let follow = |k: usize, from: usize, q: &mut Vec<Option<Vec<f64>>>| -> Result<bool, TrackingError> {
            self.check_cancel()?;
            let reference = q[from].clone().expect("followed from a tracked sample");
            let found = self
                .solving
                .follow(&self.path.pose_at(points[k])?, &lock, &reference)?
                .or_else(|| pick(self.solving.robot, &sols[k], &lock, &reference));
            let ok = found.is_some();
            q[k] = found;
            tick();
            Ok(ok)
        };
        for k in k0 + 1..points.len() {
            if !follow(k, k - 1, &mut q)? {
                let at_boundary = k == points.len() - 1 && ends_at_boundary.1;
                if !at_boundary {
                    lost = Some((points[k - 1], points[points.len() - 1]));
                }
                break;
            }
        }
        for k in (0..k0).rev() {
            if !follow(k, k + 1, &mut q)? {
                let at_boundary = k == 0 && ends_at_boundary.0;
                if !at_boundary {
                    let end = lost.map_or(points[k + 1], |l| l.1);
                    lost = Some((points[0], end.max(points[k + 1])));
                }
                break;
            }
        }
        for (k, v) in q.into_iter().enumerate() {
            if let Some(v) = v {
                track.s.push(points[k]);
                track.t.push(self.path.time_at(points[k]));
                track.q.push(v);
            }
        }
        // Keep the trajectory continuous across gaps left by a lost branch.
        for k in 1..track.q.len() {
            let prev = track.q[k - 1].clone();
            track.q[k] = unwrap_to(robot, &track.q[k], &prev);
        }
        if let Some((a, b)) = lost {
            track.violations.push(self.lost(a, b));
        }
        if track.q.len() >= 2 {
            track.step_rates = step_rates(robot, &track.t, &track.q)?;
        }
        self.check_positions(&mut track, &lock)?;
        if self.check_velocity {
            self.check_velocities(&mut track, &lock)?;
        }
        self.find_wraps(&mut track, &lock)?;
        track.feasible = track.violations.is_empty();
        Ok(track)
    }
}

/// One end of an interval: its path parameter and what splits the path there (`None` at the
/// path's ends).
type Bound = (f64, Option<SplitKind>);

impl Tracker<'_> {
    /// The interval ends: the path's ends and the split points strictly inside.
    pub(super) fn bounds(&self, split_points: &[SplitPoint]) -> Vec<Bound> {
        let path = self.path;
        let mut bounds = vec![(path.start(), None)];
        for p in split_points {
            if p.s > path.start() + self.tolerance && p.s < path.end() - self.tolerance {
                bounds.push((p.s, Some(p.kind)));
            }
        }
        bounds.push((path.end(), None));
        bounds
    }

    /// Interval `index` (1-based) between `a` and `b`: every configuration tracked and checked,
    /// one chosen (notes 003 §4 step 4), the events logged; advances the meter by `budget`
    /// units per configuration.
    pub(super) fn interval(
        &self,
        index: usize,
        ((a, ka), (b, kb)): (Bound, Bound),
        scan: &Scan,
        budget: usize,
        (default, criterion): (usize, Option<&dyn ConfigurationCriterion>),
        log: &mut EventLog<'_>,
    ) -> Result<IntervalReport, TrackingError> {
        let path = self.path;
        let samples = path.samples();
        let mut points = vec![a];
        // The samples strictly inside (a, b), a tolerance away from both ends: a range, since
        // the samples' s increase strictly (validated by TrackedPath).
        let first = samples.partition_point(|p| p.s <= a + self.tolerance);
        let interior = first..samples.partition_point(|p| p.s < b - self.tolerance).max(first);
        points.extend(samples[interior.clone()].iter().map(|p| p.s));
        points.push(b);
        let reachable =
            if interior.is_empty() { self.reachable_at(0.5 * (a + b))? } else { scan.reach[interior.start] };
        let mut report = IntervalReport {
            index,
            s_start: a,
            s_end: b,
            t_start: path.time_at(a),
            t_end: path.time_at(b),
            reachable,
            configurations: Vec::new(),
            chosen: None,
            decision: Decision::NotRealizable,
        };
        if !reachable {
            self.meter.advance(budget * self.configurations.len());
            log.outside(index, a, b);
            log.not_realizable(a, index);
            return Ok(report);
        }
        log.inside(index, a, b);
        // The first interval starts where the arm is: its configuration is the start's.
        let pinned = self.start.as_ref().filter(|_| index == 1).map(|s| s.configuration);
        let default = pinned.unwrap_or(default);
        let boundary = |k: Option<SplitKind>| matches!(k, Some(SplitKind::Leaves | SplitKind::Enters));
        let order: Vec<usize> =
            std::iter::once(default).chain((0..self.configurations.len()).filter(|&c| c != default)).collect();
        let mut tracks: Vec<Option<ConfigurationTrack>> = vec![None; self.configurations.len()];
        // The unseeded solutions at the interval's points, once for every configuration:
        // a sample's from the scan when the path gives the sample's own pose there.
        let mut sols: Vec<Cow<'_, IkSolutions>> = Vec::with_capacity(points.len());
        for (j, &s) in points.iter().enumerate() {
            let pose = path.pose_at(s)?;
            let k = j.checked_sub(1).map(|j| interior.start + j).filter(|k| interior.contains(k));
            sols.push(match k {
                Some(k) if samples[k].pose == pose => Cow::Borrowed(&scan.solutions[k]),
                _ => Cow::Owned(self.solving.solve(&pose, None)?),
            });
        }
        for (rank, &c) in order.iter().enumerate() {
            let t = self.track_interval(c, &points, &sols, (boundary(ka), boundary(kb)), budget)?;
            let is_default = rank == 0;
            for v in &t.violations {
                log.violation(index, c, v, is_default, order.get(1).copied());
            }
            if is_default && t.feasible {
                log.realizable(a, index, c, order.len() > 1);
            }
            tracks[c] = Some(t);
        }
        let tracks: Vec<ConfigurationTrack> =
            tracks.into_iter().map(|t| t.expect("every configuration tracked")).collect();
        let feasible: Vec<usize> = order.iter().copied().filter(|&c| tracks[c].feasible).collect();
        let (chosen, decision) = match (self.choices.get(&index), pinned) {
            (Some(label), Some(c)) if *label != self.configurations[c].to_string() => {
                return Err(TrackingError::InvalidOption {
                    option: "choices",
                    reason: format!(
                        "interval 1 starts where the arm is, in configuration `{}`; `{label}` cannot be chosen there",
                        self.configurations[c]
                    ),
                });
            }
            (_, Some(c)) if feasible.contains(&c) => (Some(c), Decision::Start),
            (_, Some(_)) => (None, Decision::NotRealizable),
            (Some(label), None) => (Some(self.operator_choice(index, label, &feasible)?), Decision::Operator),
            (None, None) => choose(&tracks, &feasible, default, criterion),
        };
        if feasible.len() > 1 {
            log.several_realizable(a, index, &feasible);
        }
        if let (Some(c), Decision::CriterionRejected) = (chosen, decision) {
            log.criterion_rejected(a, index, c);
        }
        match chosen {
            Some(c) => log.realized(a, index, c),
            None => log.not_realizable(a, index),
        }
        report.configurations = tracks;
        report.chosen = chosen;
        report.decision = decision;
        Ok(report)
    }

    /// The configuration the operator named for interval `index` (its label), which must be one
    /// of the `feasible` ones there.
    fn operator_choice(&self, index: usize, label: &str, feasible: &[usize]) -> Result<usize, TrackingError> {
        let labels: Vec<String> = self.configurations.iter().map(ToString::to_string).collect();
        let named = |cs: &mut dyn Iterator<Item = usize>| cs.map(|c| format!("`{}`", labels[c])).collect::<Vec<_>>();
        let reason = match labels.iter().position(|l| l == label) {
            Some(c) if feasible.contains(&c) => return Ok(c),
            Some(_) if feasible.is_empty() => format!("interval {index}: no configuration is feasible there"),
            Some(_) => format!(
                "interval {index}: configuration `{label}` is not feasible there; feasible: {}",
                named(&mut feasible.iter().copied()).join(", ")
            ),
            None => format!(
                "interval {index}: no configuration `{label}`; the configurations are {}",
                named(&mut (0..labels.len())).join(", ")
            ),
        };
        Err(TrackingError::InvalidOption { option: "choices", reason })
    }

    /// The realised joint trajectory: the chosen configuration of every realised interval,
    /// continuous across the interval ends.
    pub(super) fn realised(&self, intervals: &[IntervalReport]) -> Vec<TrajectoryPoint> {
        let mut trajectory: Vec<TrajectoryPoint> = Vec::new();
        for interval in intervals {
            let Some(c) = interval.chosen else { continue };
            let t = &interval.configurations[c];
            for k in 0..t.q.len() {
                let q = match trajectory.last() {
                    Some(last) if (last.s - t.s[k]).abs() <= self.tolerance => continue,
                    Some(last) => unwrap_to(self.robot(), &t.q[k], &last.q),
                    None => t.q[k].clone(),
                };
                trajectory.push(TrajectoryPoint { s: t.s[k], t: t.t[k], q, configuration: c });
            }
        }
        trajectory
    }
}

/// The choice among the `feasible` configurations (indices into `tracks`, the default first
/// when feasible, then in the order tried): the only one; else the criterion's choice; else
/// the default, or the first feasible when the default is not (notes 003 §4 step 4, K13/K14).
fn choose(
    tracks: &[ConfigurationTrack],
    feasible: &[usize],
    default: usize,
    criterion: Option<&dyn ConfigurationCriterion>,
) -> (Option<usize>, Decision) {
    match feasible {
        [] => (None, Decision::NotRealizable),
        [only] => (Some(*only), if *only == default { Decision::Default } else { Decision::OnlyFeasible }),
        _ => {
            let fallback = if feasible.contains(&default) { default } else { feasible[0] };
            match criterion {
                None if fallback == default => (Some(fallback), Decision::Default),
                None => (Some(fallback), Decision::FirstFeasible),
                Some(cr) => {
                    let candidates: Vec<&ConfigurationTrack> = feasible.iter().map(|&c| &tracks[c]).collect();
                    match cr.choose(&candidates).and_then(|k| feasible.get(k).copied()) {
                        Some(c) => (Some(c), Decision::Criterion),
                        None => (Some(fallback), Decision::CriterionRejected),
                    }
                }
            }
        }
    }
}
