//! Tracking a tool path through inverse kinematics: branch continuity, wrap-safe joint rates,
//! singular positions, per-interval feasibility and the choice of configuration — seed 003's
//! "universal algorithm" (Knapczyk & Kisiel 1987, notes 003 §3.5–3.7 and §4, Fig. 6),
//! generalised to any robot the [`ik`](crate::ik) module solves.
//!
//! # The input
//!
//! A path is a list of [`PathSample`](super::PathSample)s — path parameter `s` (arc length of
//! the tool point in the paper; any strictly increasing parameter here), time `t` (strictly
//! increasing) and tool pose, e.g. the samples of a [`ToolPath`](super::ToolPath) — wrapped in
//! a [`TrackedPath`]. Singular positions and limit crossings are refined between samples by
//! bisection, so the path must be evaluable between samples: either give
//! a closure `Fn(f64) -> Isometry3<f64>` over `s` ([`TrackedPath::with_evaluator`]) or let the
//! path interpolate its samples (straight-line position, slerped orientation;
//! [`TrackedPath::sampled`]). Time between samples is interpolated linearly in `s`.
//!
//! # Configurations and continuity
//!
//! A *configuration* is a [`Branch`] filter: the `key=value` pairs a solution's label must
//! carry (e.g. seed 003's `config=+β`, a PUMA's `elbow=up`; the empty filter matches every
//! solution). The caller names them ([`TrackingOptions::configurations`]) or the solver does
//! ([`IkSolver::configurations`](crate::ik::IkSolver::configurations), in its default order).
//! Tracking knows no particular solver: what it needs from one is asked through the
//! [`IkSolver`](crate::ik::IkSolver) trait.
//!
//! Along an interval, a configuration is followed from an anchor sample (the first
//! where a non-singular solution of the filter exists): at every sample the solver is called
//! with the previous joint vector as seed, and the solution **with the same full branch
//! label** nearest to the previous joint vector is taken, its revolute angles unwrapped
//! ([`crate::angle::nearest_equivalent`]) so that the joint trajectory is continuous. Only at a
//! sample where the label is missing and a solution flagged singular exists (branches merge
//! there) is the nearest singular solution taken. A label that disappears otherwise is
//! reported ([`ViolationKind::BranchLost`]), never replaced silently. This holds for solvers
//! whose labels name branches
//! ([`IkSolver::enumerates_all_branches`](crate::ik::IkSolver::enumerates_all_branches));
//! the labels of a search (the numeric solver: the start that found a solution) or of a
//! sampled self-motion (the sampled parameter) do not, so with them the filter alone is kept
//! and continuity comes from nearness (the solver is seeded with the previous joint vector).
//!
//! # Rates
//!
//! The paper differentiates numerically: the rate of a step is the angle increment divided by
//! the step time (notes 003 §3.5). The increment of a revolute joint is taken on the unwrapped
//! trajectory, i.e. the shortest rotation ([`crate::angle::shortest_difference`]), so a ±180°
//! crossing creates no spike ([`step_rates`]; the naive difference of wrapped angles gives
//! the notes' spurious −6.34 rev/min on the weld, §5.4).
//!
//! # Singular positions (notes 003 §3.6, §4 steps 2–3)
//!
//! When the solver computes singularity measures in closed form
//! ([`IkSolver::singularity_measures`](crate::ik::IkSolver::singularity_measures); seed 003's
//! arm: `√(1 − |cos θ_elbow|)`, 0 where |Δ| = 1, `sin∠(w, e6)` for the wrist and
//! `(ρ − |D|)/L` for the shoulder, [`PathMeasures`](crate::ik::parallel_axes::PathMeasures)),
//! those are scanned along the samples of a full-pose path. Otherwise the relative smallest
//! singular value `σ_min/σ_max` of the Jacobian is scanned, minimised over the solutions of the
//! configurations (the translational rows for position-only tracking). Every local minimum of
//! a measure is refined by golden-section search on `s`; a refined minimum at or below
//! [`TRACKING_SINGULAR`](crate::tolerance::TRACKING_SINGULAR) is a singular position.
//! Points where the path leaves or enters the reachable set (no solution of any configuration)
//! are refined by bisection. The path is split into intervals at all of them.
//!
//! # Feasibility and choice (notes 003 §4 step 4)
//!
//! In each interval every configuration is tracked and checked against the joint ranges and
//! speed limits; each violation names the joint, the limit, and where it starts and ends, the
//! crossings refined by bisection to [`TRACKING_PARAMETER`]. A revolute joint whose range is
//! narrower than a full turn is out of range where *no* representative `q + 2πk` lies in it
//! (as the paper checks wrapped angles; for such a range a continuous motion can only pass
//! from one representative to another through the gap, so this is also the check of the
//! continuous motion); a wider range is checked on the unwrapped, continuous trajectory.
//! The interval is realised in the default configuration when it is feasible and no
//! criterion is given, in the only feasible one, or in the feasible one with the lowest
//! score of a user [`ConfigurationCriterion`]; when the criterion scores none, the default is kept (K14).
//! Intervals are separated by singular positions, so the configuration changes only there.
//!
//! The decisions are logged as [`TrackingEvent`]s equivalent to the paper's operator
//! messages K1–K14 ([`EventCode`]). An event carries its data in SI units and radians
//! ([`EventDetail`]); [`describe`] makes the operator's text, in degrees or radians.
//!
//! # Files
//!
//! `path` (the [`TrackedPath`]), `branch` (following one configuration, [`step_rates`]),
//! `singular` (the scan for split points), `checks` (limit violations), `intervals` (the
//! per-interval tracking and choice, [`ConfigurationCriterion`]), `events` (the K1–K14 events, their data
//! and [`describe`], the one text renderer) and `log` (the log the tracker writes).

mod branch;
mod checks;
mod events;
mod intervals;
mod log;
mod path;
mod singular;

use std::cell::Cell;

use serde::Serialize;
use thiserror::Error;

use crate::ik::{Branch, IkError, SingularityMeasures, SolverKind};
use crate::model::Robot;
use crate::tolerance::TRACKING_PARAMETER;

pub use branch::{BranchTrack, step_rates, track_configuration};
use branch::{Solving, Start};
pub use checks::{Violation, ViolationKind, WrapCrossing};
pub use events::{EventCode, EventDetail, TrackingEvent, describe};
pub use intervals::{ConfigurationCriterion, ConfigurationTrack, Decision, IntervalReport, TrajectoryPoint};
use log::EventLog;
pub use path::TrackedPath;
pub use singular::{SingularityDetection, SplitKind, SplitPoint};

/// Why a tracking problem was rejected.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum TrackingError {
    /// A path needs at least two samples.
    #[error("a path needs at least 2 samples, got {found}")]
    TooFewSamples {
        /// Number of samples given.
        found: usize,
    },
    /// A sample has a NaN or infinite value.
    #[error("path sample {index}: `{field}` must be finite")]
    NonFinite {
        /// 0-based sample index.
        index: usize,
        /// Which field (`s`, `t`, `pose`).
        field: &'static str,
    },
    /// `s` or `t` does not increase strictly.
    #[error("path sample {index}: `{field}` must increase strictly ({previous} then {value})")]
    NotIncreasing {
        /// 0-based sample index.
        index: usize,
        /// `s` or `t`.
        field: &'static str,
        /// The previous sample's value.
        previous: f64,
        /// This sample's value.
        value: f64,
    },
    /// The path evaluator returned a non-finite pose.
    #[error("the path evaluator returned a non-finite pose at s = {s}")]
    Evaluator {
        /// Path parameter of the bad pose.
        s: f64,
    },
    /// An option is out of its domain.
    #[error("tracking option `{option}`: {reason}")]
    InvalidOption {
        /// Option name.
        option: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The joint vectors and times of [`step_rates`] do not fit together.
    #[error("rates: {reason}")]
    Shape {
        /// What does not fit.
        reason: String,
    },
    /// The IK solver rejected a target or does not fit the robot.
    #[error(transparent)]
    Ik(#[from] IkError),
    /// The tracking was stopped through [`TrackingOptions::cancel`].
    #[error("tracking cancelled")]
    Cancelled,
}

/// Everything [`track`] found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackingReport {
    /// The IK solver used.
    pub solver: &'static str,
    /// The configurations considered (index 0 is the default unless the options say otherwise).
    pub configurations: Vec<Branch>,
    /// Index of the default configuration.
    pub default_configuration: usize,
    /// Singular positions and reachability changes, in path order.
    pub split_points: Vec<SplitPoint>,
    /// The intervals between them.
    pub intervals: Vec<IntervalReport>,
    /// The event log (K1–K14).
    pub events: Vec<TrackingEvent>,
    /// The realised joint trajectory over the realisable intervals (batch output).
    pub trajectory: Vec<TrajectoryPoint>,
    /// Whether every interval is realised.
    pub feasible: bool,
}

impl TrackingReport {
    /// The events with a given code.
    pub fn events_with(&self, code: EventCode) -> impl Iterator<Item = &TrackingEvent> {
        self.events.iter().filter(move |e| e.code == code)
    }
}

/// Options of [`track`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackingOptions {
    /// The IK solver; `None`: [`SolverKind::detect`].
    pub solver: Option<SolverKind>,
    /// The configurations to consider (branch filters). Empty: the solver's
    /// ([`IkSolver::configurations`](crate::ik::IkSolver::configurations), e.g. seed 003's
    /// two, `config=+β` first; any solution for the numeric solver), those of them with a
    /// solution at the first reachable sample.
    pub configurations: Vec<Branch>,
    /// Index of the default configuration (0: the first, e.g. the paper's `config=+β`).
    pub default_configuration: usize,
    /// Track the tool position only.
    pub position_only: bool,
    /// How singular positions are found.
    pub detection: SingularityDetection,
    /// Skip the speed-limit check (the paper's "diagnostic" mode checks nothing; angles are
    /// always reported).
    pub ignore_velocity: bool,
    /// Stops the tracking between two samples ([`TrackingError::Cancelled`]); a front end
    /// sets it on Ctrl-C ([`crate::Cancel`]).
    pub cancel: crate::Cancel,
    /// The operator's choices (seed 003's dialogue): interval (1-based) → configuration label
    /// ([`Branch`]'s text, as [`TrackingReport::configurations`] shows it). The named
    /// configuration must be feasible in its interval ([`Decision::Operator`]); the
    /// criterion and the default decide the other intervals.
    pub choices: std::collections::BTreeMap<usize, String>,
    /// Where the arm is at the path's first sample (joint vector, rad and m), e.g. a tool-space
    /// move's `from` joints. The first interval is then realised from exactly this joint vector,
    /// in its configuration and on its branch ([`Decision::Start`]; not realisable when that
    /// configuration breaks a limit there, however the others fare), so the arm does not jump
    /// to the same pose on another branch (MoveIt's `computeCartesianPath` starts from the
    /// robot state likewise). Its pose must be the path's first pose within the IK tolerances.
    /// `None`: the first interval is chosen as every other.
    pub start: Option<Vec<f64>>,
}

/// Counts the work of [`track_with_progress`] and calls its hook once per chunk.
struct Meter<'a> {
    hook: &'a dyn Fn(usize, usize),
    total: usize,
    done: Cell<usize>,
    reported: Cell<usize>,
}

impl Meter<'_> {
    /// Adds `n` units; reports when a chunk has accumulated (never `total` itself: that is
    /// [`Meter::finish`]'s).
    fn advance(&self, n: usize) {
        let done = (self.done.get() + n).min(self.total);
        self.done.set(done);
        if done < self.total && done - self.reported.get() >= TRACKING_PROGRESS_CHUNK {
            self.reported.set(done);
            (self.hook)(done, self.total);
        }
    }

    /// The single report of `total`.
    fn finish(&self) {
        debug_assert_eq!(self.done.get(), self.total, "the phases add up to the total");
        self.done.set(self.total);
        self.reported.set(self.total);
        (self.hook)(self.total, self.total);
    }
}

struct Tracker<'a> {
    meter: Meter<'a>,
    cancel: crate::Cancel,
    solving: Solving<'a>,
    path: &'a TrackedPath<'a>,
    configurations: Vec<Branch>,
    /// The solver's closed-form singularity measures, else the Jacobian's is scanned.
    closed_form: Option<Box<dyn SingularityMeasures>>,
    tolerance: f64,
    check_velocity: bool,
    choices: std::collections::BTreeMap<usize, String>,
    /// Where the arm is at the first sample ([`TrackingOptions::start`]).
    start: Option<Start>,
}

/// Tracks `path` through IK in every configuration, finds its singular positions, splits it
/// into intervals, checks each configuration in each interval and chooses one (see the
/// module docs; notes 003 §4).
///
/// # Arguments
/// * `criterion` — chooses among feasible configurations (lowest score); `None`: the default.
///
/// # Returns
/// The split points, per-interval reports with reasons, the event log and the realised joint
/// trajectory. An unreachable stretch or an infeasible interval is an answer in the report,
/// not an error.
///
/// # Errors
/// [`TrackingError`] for bad options, a non-finite pose from the evaluator, or a solver that
/// rejects the robot.
pub fn track(
    robot: &Robot,
    path: &TrackedPath<'_>,
    options: &TrackingOptions,
    criterion: Option<&dyn ConfigurationCriterion>,
) -> Result<TrackingReport, TrackingError> {
    track_with_progress(robot, path, options, criterion, &|_, _| {})
}

/// Units of work ((sample, configuration) visits) between two calls of the progress hook of
/// [`track_with_progress`] (one chunk).
pub const TRACKING_PROGRESS_CHUNK: usize = 256;

/// [`track`] that reports its progress: `progress(done, total)` is called after every chunk of
/// [`TRACKING_PROGRESS_CHUNK`] units of work, with `done` increasing, and exactly once with
/// `done == total`, as the last call, when the report is complete. The hook does not change
/// the report.
///
/// The work is counted in (sample, configuration) visits: with `n` samples and `m`
/// configurations, `total = 2·n·m`, two phases of `n·m` each —
/// 1. the scan of every sample (IK and the singularity measures of every configuration's
///    solutions: `m` units a sample; the refinement of the split points by bisection is counted
///    with the scan's last sample);
/// 2. the tracking of each configuration over every sample, interval by interval (an interval
///    owns the samples up to its end; the limit checks of a configuration are counted with its
///    last sample in the interval; an unreachable interval's samples are counted at once).
///
/// Choosing the default configurations (before the scan, stopping at the first reachable
/// sample) is not counted.
///
/// # Errors
/// As [`track`].
///
/// # Example
/// ```
/// use std::cell::Cell;
/// use nalgebra::{Isometry3, Translation3};
/// use reach::motion::PathSample;
/// use reach::motion::tracking::{TrackedPath, TrackingOptions, track_with_progress};
/// let robot = reach::model::presets::get("welder6r").unwrap();
/// let pose0 = robot.fk(&[0.1, 0.2, 0.3, 0.1, 0.5, 0.2]).unwrap();
/// // A 10 mm line along y, 101 samples.
/// let samples: Vec<PathSample> = (0..=100)
///     .map(|k| {
///         let s = f64::from(k) * 1e-4;
///         let at = Translation3::new(0.0, s, 0.0) * pose0.translation;
///         PathSample { s, t: s * 10.0, angle: 0.0, pose: Isometry3::from_parts(at, pose0.rotation) }
///     })
///     .collect();
/// let path = TrackedPath::sampled(&samples).unwrap();
/// let last = Cell::new((0, 0));
/// let report = track_with_progress(&robot, &path, &TrackingOptions::default(), None, &|done, total| {
///     assert!(done >= last.get().0);
///     last.set((done, total));
/// })
/// .unwrap();
/// // The paper's two configurations: 101 samples scanned for both, then tracked in both.
/// assert_eq!(last.get(), (2 * 101 * 2, 2 * 101 * 2));
/// assert!(!report.intervals.is_empty());
/// ```
pub fn track_with_progress(
    robot: &Robot,
    path: &TrackedPath<'_>,
    options: &TrackingOptions,
    criterion: Option<&dyn ConfigurationCriterion>,
    progress: &dyn Fn(usize, usize),
) -> Result<TrackingReport, TrackingError> {
    let kind = options.solver.unwrap_or_else(|| SolverKind::detect(robot));
    let solving = Solving { robot, solver: kind.build(robot)?, position_only: options.position_only };
    let mut configurations = if options.configurations.is_empty() {
        default_configurations(&solving, path)?
    } else {
        options.configurations.clone()
    };
    let mut default = options.default_configuration;
    if configurations.is_empty() {
        // The solver lists none: one "any solution" configuration.
        configurations.push(Branch::default());
        default = 0;
    }
    if default >= configurations.len() {
        return Err(TrackingError::InvalidOption {
            option: "default_configuration",
            reason: format!("index {default} but only {} configurations", configurations.len()),
        });
    }
    // Where the arm is: its configuration is tracked too (added when the solver's list lacks it).
    let start = match &options.start {
        Some(q) => Some(solving.start(
            q,
            &path.pose_at(path.start())?,
            &mut configurations,
            options.configurations.is_empty(),
        )?),
        None => None,
    };
    // A solver's closed-form measures are of full poses.
    let measures = match options.detection {
        SingularityDetection::Auto if !options.position_only => {
            solving.solver.singularity_measures(robot, &configurations)
        }
        _ => None,
    };
    let mut tracker = Tracker::new(solving, path, configurations, measures, options, progress);
    tracker.start = start;
    track_with(tracker, default, criterion)
}

/// The solver's configurations ([`IkSolver::configurations`], in its order) that have a
/// solution at the first sample where the path is reachable (all of them when none has, or
/// when the path is nowhere reachable). A single configuration is kept as it is.
fn default_configurations(solving: &Solving<'_>, path: &TrackedPath<'_>) -> Result<Vec<Branch>, TrackingError> {
    let listed = solving.solver.configurations(solving.robot);
    if listed.len() <= 1 {
        return Ok(listed);
    }
    for p in path.samples() {
        let sols = solving.solve(&p.pose, None)?;
        if !sols.solutions.is_empty() {
            let present: Vec<Branch> = listed
                .iter()
                .filter(|c| sols.solutions.iter().any(|s| branch::matches(&s.branch, c)))
                .cloned()
                .collect();
            return Ok(if present.is_empty() { listed } else { present });
        }
    }
    Ok(listed)
}

impl<'a> Tracker<'a> {
    fn new(
        solving: Solving<'a>,
        path: &'a TrackedPath<'a>,
        configurations: Vec<Branch>,
        closed_form: Option<Box<dyn SingularityMeasures>>,
        options: &TrackingOptions,
        progress: &'a dyn Fn(usize, usize),
    ) -> Self {
        let tolerance = TRACKING_PARAMETER * (path.end() - path.start()).abs().max(f64::MIN_POSITIVE);
        let meter = Meter {
            hook: progress,
            total: 2 * path.samples().len() * configurations.len(),
            done: Cell::new(0),
            reported: Cell::new(0),
        };
        Tracker {
            meter,
            cancel: options.cancel.clone(),
            solving,
            path,
            configurations,
            closed_form,
            tolerance,
            check_velocity: !options.ignore_velocity,
            choices: options.choices.clone(),
            start: None,
        }
    }

    fn robot(&self) -> &Robot {
        self.solving.robot
    }

    /// [`TrackingError::Cancelled`] once the options' cancel flag is set: called once per
    /// sample solved or followed.
    fn check_cancel(&self) -> Result<(), TrackingError> {
        if self.cancel.is_cancelled() { Err(TrackingError::Cancelled) } else { Ok(()) }
    }
}

fn track_with(
    tracker: Tracker<'_>,
    default: usize,
    criterion: Option<&dyn ConfigurationCriterion>,
) -> Result<TrackingReport, TrackingError> {
    let path = tracker.path;
    let scan = tracker.split_points()?;
    let bounds = tracker.bounds(&scan.points);
    let mut log = EventLog::new(path, &tracker.configurations);
    for p in scan.points.iter().filter(|p| p.s <= path.start() + tracker.tolerance) {
        log.split(p);
    }
    let count = bounds.len() - 1;
    if let Some(bad) = tracker.choices.keys().find(|&&i| i == 0 || i > count) {
        return Err(TrackingError::InvalidOption {
            option: "choices",
            reason: format!("interval {bad} does not exist: the path has intervals 1 to {count}"),
        });
    }
    let mut intervals = Vec::with_capacity(count);
    // Progress: interval i owns the samples from the previous interval's end up to its end.
    let mut owned_until = 0;
    for i in 0..count {
        let (a, b) = (bounds[i], bounds[i + 1]);
        let index = i + 1;
        let samples = path.samples();
        let until = if index == count { samples.len() } else { samples.partition_point(|p| p.s < b.0) };
        let budget = until - owned_until;
        owned_until = until;
        let report = tracker.interval(index, (a, b), &scan, budget, (default, criterion), &mut log)?;
        for p in scan.points.iter().filter(|p| p.s > a.0 + tracker.tolerance && p.s <= b.0 + tracker.tolerance) {
            log.split(p);
        }
        if index < count {
            log.next_interval(b.0, index);
        } else {
            log.end(b.0, index);
        }
        intervals.push(report);
    }
    let trajectory = tracker.realised(&intervals);
    let feasible = intervals.iter().all(|i| i.chosen.is_some());
    tracker.meter.finish();
    Ok(TrackingReport {
        solver: tracker.solving.solver.name(),
        configurations: tracker.configurations.clone(),
        default_configuration: default,
        split_points: scan.points,
        intervals,
        events: log.into_events(),
        trajectory,
        feasible,
    })
}
