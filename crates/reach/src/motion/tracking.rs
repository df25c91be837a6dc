//! Tracking a tool path through inverse kinematics: branch continuity, wrap-safe joint rates,
//! singular positions, per-interval feasibility and the choice of configuration — seed 003's
//! "universal algorithm" (Knapczyk & Kisiel 1987, notes 003 §3.5–3.7 and §4, Fig. 6),
//! generalised to any robot the [`ik`](crate::ik) module solves.
//!
//! # The input
//!
//! A path is a list of [`PathSample`]s — path parameter `s` (arc length of the tool point in
//! the paper; any strictly increasing parameter here), time `t` (strictly increasing) and
//! tool pose, e.g. the samples of a [`ToolPath`](super::ToolPath) — wrapped in a [`TrackedPath`]. Singular positions and limit crossings are refined
//! between samples by bisection, so the path must be evaluable between samples: either give
//! a closure `Fn(f64) -> Isometry3<f64>` over `s` ([`TrackedPath::with_evaluator`]) or let the
//! path interpolate its samples (straight-line position, slerped orientation;
//! [`TrackedPath::sampled`]). Time between samples is interpolated linearly in `s`.
//!
//! # Configurations and continuity
//!
//! A *configuration* is a [`Branch`] filter: the `key=value` pairs a solution's label must
//! carry (the welder's `config=+β`, a PUMA's `elbow=up`; the empty filter matches every
//! solution). Along an interval, a configuration is followed from an anchor sample (the first
//! where a non-singular solution of the filter exists): at every sample the solver is called
//! with the previous joint vector as seed, and the solution **with the same full branch
//! label** nearest to the previous joint vector is taken, its revolute angles unwrapped
//! ([`crate::angle::nearest_equivalent`]) so that the joint trajectory is continuous. Only at a
//! sample where the label is missing and a solution flagged singular exists (branches merge
//! there) is the nearest singular solution taken. A label that disappears otherwise is
//! reported ([`ViolationKind::BranchLost`]), never replaced silently. The numeric solver's
//! labels name the start that found a solution, not a geometric branch, so with it the
//! filter alone is kept and continuity comes from nearness (it is seeded with the previous
//! joint vector).
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
//! For robots the seed-003 closed form fits ([`ParallelAxes`]), the closed-form measures are
//! scanned along the samples: `√(1 − |cos θ_elbow|)` (0 where |Δ| = 1), `sin∠(w, e6)` (wrist)
//! and `(ρ − |D|)/L` (shoulder), for each shoulder/wrist branch the configurations use. For
//! every other robot the relative smallest singular value `σ_min/σ_max` of the Jacobian is
//! scanned, minimised over the solutions of the configurations (the translational rows for
//! position-only tracking). Every local minimum of a measure is refined by golden-section
//! search on `s`; a refined minimum at or below [`TRACKING_SINGULAR`] is a singular position.
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
//! score of a user [`Criterion`]; when the criterion scores none, the default is kept (K14).
//! Intervals are separated by singular positions, so the configuration changes only there.
//!
//! The decisions are logged as [`TrackingEvent`]s equivalent to the paper's operator
//! messages K1–K14 ([`EventCode`]).

use std::borrow::Cow;
use std::cell::Cell;
use std::f64::consts::{PI, TAU};
use std::fmt;

use nalgebra::{Isometry3, Point3, Translation3};
use serde::Serialize;
use thiserror::Error;

use super::sample::PathSample;
use crate::angle::{nearest_equivalent, shortest_difference, wrap};
use crate::ik::parallel_axes::{ParallelAxes, Shoulder, Wrist};
use crate::ik::{Branch, IkError, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use crate::kinematics::{JacobianAxes, Manipulability};
use crate::model::{Joint, JointKind, Robot};
use crate::tolerance::{LIMIT_SLACK, TRACKING_PARAMETER, TRACKING_RATE_STEP, TRACKING_SINGULAR};

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
}

/// A path: its samples and a way to evaluate it between them.
pub struct TrackedPath<'a> {
    samples: &'a [PathSample],
    evaluator: Option<&'a dyn Fn(f64) -> Isometry3<f64>>,
}

impl fmt::Debug for TrackedPath<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TrackedPath")
            .field("samples", &self.samples.len())
            .field("evaluator", &self.evaluator.is_some())
            .finish()
    }
}

impl<'a> TrackedPath<'a> {
    /// A path known only at its samples: poses between samples are interpolated (position
    /// linearly, orientation by slerp).
    ///
    /// # Errors
    /// [`TrackingError`] for fewer than 2 samples, non-finite values, or `s`/`t` not
    /// strictly increasing.
    pub fn sampled(samples: &'a [PathSample]) -> Result<Self, TrackingError> {
        validate_samples(samples)?;
        Ok(TrackedPath { samples, evaluator: None })
    }

    /// A path with an exact evaluator `pose(s)` used between samples (for bisection).
    ///
    /// # Errors
    /// As [`TrackedPath::sampled`].
    pub fn with_evaluator(
        samples: &'a [PathSample],
        evaluator: &'a dyn Fn(f64) -> Isometry3<f64>,
    ) -> Result<Self, TrackingError> {
        validate_samples(samples)?;
        Ok(TrackedPath { samples, evaluator: Some(evaluator) })
    }

    /// The samples.
    #[must_use]
    pub fn samples(&self) -> &[PathSample] {
        self.samples
    }

    /// The segment `k` with `s_k ≤ s ≤ s_{k+1}` (clamped to the path).
    fn segment(&self, s: f64) -> usize {
        let n = self.samples.len();
        let k = self.samples.partition_point(|p| p.s <= s);
        k.saturating_sub(1).min(n - 2)
    }

    /// The pose at `s` (evaluator, else interpolation between samples).
    ///
    /// # Errors
    /// [`TrackingError::Evaluator`] when the evaluator returns a non-finite pose.
    pub fn pose_at(&self, s: f64) -> Result<Isometry3<f64>, TrackingError> {
        let pose = match self.evaluator {
            Some(f) => f(s),
            None => {
                let k = self.segment(s);
                let (a, b) = (&self.samples[k], &self.samples[k + 1]);
                let u = ((s - a.s) / (b.s - a.s)).clamp(0.0, 1.0);
                let p = a.pose.translation.vector.lerp(&b.pose.translation.vector, u);
                let r = a.pose.rotation.try_slerp(&b.pose.rotation, u, 1e-12).unwrap_or(a.pose.rotation);
                Isometry3::from_parts(Translation3::from(p), r)
            }
        };
        if pose.translation.vector.iter().chain(pose.rotation.coords.iter()).any(|v| !v.is_finite()) {
            return Err(TrackingError::Evaluator { s });
        }
        Ok(pose)
    }

    /// The time at `s`, interpolated linearly between samples.
    #[must_use]
    pub fn time_at(&self, s: f64) -> f64 {
        let k = self.segment(s);
        let (a, b) = (&self.samples[k], &self.samples[k + 1]);
        a.t + (b.t - a.t) * (s - a.s) / (b.s - a.s)
    }

    fn start(&self) -> f64 {
        self.samples[0].s
    }

    fn end(&self) -> f64 {
        self.samples[self.samples.len() - 1].s
    }
}

fn validate_samples(samples: &[PathSample]) -> Result<(), TrackingError> {
    if samples.len() < 2 {
        return Err(TrackingError::TooFewSamples { found: samples.len() });
    }
    for (index, p) in samples.iter().enumerate() {
        if !p.s.is_finite() {
            return Err(TrackingError::NonFinite { index, field: "s" });
        }
        if !p.t.is_finite() {
            return Err(TrackingError::NonFinite { index, field: "t" });
        }
        if p.pose.translation.vector.iter().chain(p.pose.rotation.coords.iter()).any(|v| !v.is_finite()) {
            return Err(TrackingError::NonFinite { index, field: "pose" });
        }
        if index > 0 {
            let q = &samples[index - 1];
            if p.s <= q.s {
                return Err(TrackingError::NotIncreasing { index, field: "s", previous: q.s, value: p.s });
            }
            if p.t <= q.t {
                return Err(TrackingError::NotIncreasing { index, field: "t", previous: q.t, value: p.t });
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Branch continuity
// ---------------------------------------------------------------------------------------------

/// Whether `label` carries every pair of `filter`.
fn matches(label: &Branch, filter: &Branch) -> bool {
    filter.0.iter().all(|(k, v)| label.get(k) == Some(v.as_str()))
}

/// Joint-space distance with revolute differences wrapped.
fn distance(robot: &Robot, a: &[f64], b: &[f64]) -> f64 {
    robot
        .joints()
        .iter()
        .zip(a.iter().zip(b))
        .map(|(j, (x, y))| if j.kind == JointKind::Revolute { wrap(x - y).abs() } else { (x - y).abs() })
        .sum()
}

/// `q` with each revolute angle moved by whole turns next to `reference`.
fn unwrap_to(robot: &Robot, q: &[f64], reference: &[f64]) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .zip(q.iter().zip(reference))
        .map(|(j, (v, r))| if j.kind == JointKind::Revolute { nearest_equivalent(*v, *r) } else { *v })
        .collect()
}

/// How a followed configuration is recognised at the next sample.
#[derive(Debug, Clone)]
enum Lock {
    /// The full label of the anchor solution (closed forms).
    Label(Branch),
    /// The user's filter only (numeric solver).
    Filter(Branch),
}

/// The solver and the way targets are built.
struct Solving<'a> {
    robot: &'a Robot,
    solver: Box<dyn IkSolver>,
    position_only: bool,
    numeric: bool,
}

/// True for the numeric solver (the one way tracking tells it from the closed forms).
fn is_numeric(solver: &dyn IkSolver) -> bool {
    solver.name() == SolverKind::Numeric.as_str()
}

/// The IK target of a path pose: the position only, or the whole pose.
fn ik_target(pose: &Isometry3<f64>, position_only: bool) -> IkTarget {
    if position_only { IkTarget::Position(Point3::from(pose.translation.vector)) } else { IkTarget::Pose(*pose) }
}

/// The IK options of one tracking solve: seeded from `seed` when given; a seeded numeric solve
/// makes one restart only (it follows the seed instead of searching afresh).
fn seeded_options(numeric: bool, seed: Option<&[f64]>) -> IkOptions {
    let mut options = IkOptions { seed: seed.map(<[f64]>::to_vec), ..IkOptions::default() };
    if numeric && seed.is_some() {
        options.restarts = 1;
    }
    options
}

impl Solving<'_> {
    fn target(&self, pose: &Isometry3<f64>) -> IkTarget {
        ik_target(pose, self.position_only)
    }

    fn options(&self, seed: Option<&[f64]>) -> IkOptions {
        seeded_options(self.numeric, seed)
    }

    fn solve(&self, pose: &Isometry3<f64>, seed: Option<&[f64]>) -> Result<IkSolutions, TrackingError> {
        Ok(self.solver.solve(self.robot, &self.target(pose), &self.options(seed))?)
    }

    /// The locked branch at `pose`, seeded with and next to `reference` ([`follow`]).
    fn follow(&self, pose: &Isometry3<f64>, lock: &Lock, reference: &[f64]) -> Result<Option<Vec<f64>>, TrackingError> {
        let options = self.options(Some(reference));
        Ok(follow(self.robot, self.solver.as_ref(), &self.target(pose), lock, reference, &options)?)
    }
}

/// The anchor: the solution of `filter` to follow (non-singular first, then within limits,
/// then the solver's order), and the lock it defines.
fn anchor(sols: &IkSolutions, filter: &Branch, numeric: bool) -> Option<(Vec<f64>, Lock)> {
    let best = sols
        .solutions
        .iter()
        .filter(|s| matches(&s.branch, filter))
        .min_by_key(|s| (!s.singularities.is_empty(), !s.within_limits))?;
    let lock = if numeric { Lock::Filter(filter.clone()) } else { Lock::Label(best.branch.clone()) };
    Some((best.q.clone(), lock))
}

/// The solution of the locked branch nearest to `reference`, unwrapped next to it; at a
/// singular position, where branches merge, the nearest solution flagged singular.
fn pick(robot: &Robot, sols: &IkSolutions, lock: &Lock, reference: &[f64]) -> Option<Vec<f64>> {
    let nearest = |pred: &dyn Fn(&crate::ik::IkSolution) -> bool| {
        sols.solutions
            .iter()
            .filter(|s| pred(s))
            .min_by(|a, b| distance(robot, &a.q, reference).total_cmp(&distance(robot, &b.q, reference)))
    };
    let found = match lock {
        Lock::Label(label) => nearest(&|s| s.branch == *label),
        Lock::Filter(filter) => nearest(&|s| matches(&s.branch, filter)),
    }
    .or_else(|| nearest(&|s| !s.singularities.is_empty()))?;
    Some(unwrap_to(robot, &found.q, reference))
}

/// [`pick`] on the solutions at `target`: for a label lock (closed forms) only the locked
/// branch is solved ([`IkSolver::solve_branch`]), and every branch only when it has no solution
/// there — the singular fallback of [`pick`] needs them. The result is that of `pick` on the
/// full solve: `solve_branch` returns exactly the solutions the label filter of `pick` keeps.
fn follow(
    robot: &Robot,
    solver: &dyn IkSolver,
    target: &IkTarget,
    lock: &Lock,
    reference: &[f64],
    options: &IkOptions,
) -> Result<Option<Vec<f64>>, IkError> {
    if let Lock::Label(label) = lock {
        let own = solver.solve_branch(robot, target, label, options)?;
        if !own.solutions.is_empty() {
            return Ok(pick(robot, &own, lock, reference));
        }
    }
    Ok(pick(robot, &solver.solve(robot, target, options)?, lock, reference))
}

/// One configuration followed along a list of samples ([`track_configuration`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BranchTrack {
    /// The full label followed (the anchor solution's), `None` if the filter never matched.
    pub branch: Option<Branch>,
    /// Joint vectors per sample, revolute angles unwrapped (continuous); `None` where the
    /// branch has no solution.
    pub q: Vec<Option<Vec<f64>>>,
}

/// Follows one configuration along `samples` with branch continuity (see the module docs):
/// the IK of every sample, seeded with the previous joint vector, and the solution of the
/// same branch nearest to it.
///
/// # Arguments
/// * `solver` — e.g. `SolverKind::detect(robot).build(robot)?`;
/// * `filter` — the configuration (`Branch::default()` follows the first solution found);
/// * `position_only` — solve for the tool position only.
///
/// # Performance
/// Until the branch is locked, one IK solve per sample; then one single-branch solve per
/// sample ([`IkSolver::solve_branch`], the full solve only where the branch has no
/// solution) and a nearest search over its solutions; no other work.
///
/// # Errors
/// [`TrackingError`] for a bad path or when the solver rejects a target.
///
/// # Example
/// ```
/// use reach::ik::{Branch, SolverKind};
/// use reach::motion::PathSample;
/// use reach::motion::tracking::track_configuration;
/// let puma = reach::model::presets::get("puma560").unwrap();
/// let solver = SolverKind::detect(&puma).build(&puma).unwrap();
/// let start = puma.fk(&[0.0, 0.5, -0.4, 0.3, 0.6, 3.1]).unwrap();
/// let samples: Vec<PathSample> = (0..=10)
///     .map(|k| {
///         let q = [0.1 * k as f64, 0.5, -0.4, 0.3, 0.6, 3.1 + 0.01 * k as f64];
///         let pose = puma.fk(&q).unwrap();
///         PathSample { t: k as f64, s: k as f64, angle: start.rotation.angle_to(&pose.rotation), pose }
///     })
///     .collect();
/// let track = track_configuration(&puma, solver.as_ref(), &samples, &Branch::default(), false).unwrap();
/// // q6 passes π: the tracked angle keeps increasing instead of jumping to −π.
/// let q6: Vec<f64> = track.q.iter().map(|q| q.as_ref().unwrap()[5]).collect();
/// assert!(q6.windows(2).all(|w| (w[1] - w[0]).abs() < 0.1));
/// ```
pub fn track_configuration(
    robot: &Robot,
    solver: &dyn IkSolver,
    samples: &[PathSample],
    filter: &Branch,
    position_only: bool,
) -> Result<BranchTrack, TrackingError> {
    validate_samples(samples)?;
    let numeric = is_numeric(solver);
    let mut out = BranchTrack { branch: None, q: Vec::with_capacity(samples.len()) };
    let mut lock: Option<Lock> = None;
    let mut previous: Option<Vec<f64>> = None;
    let target = |pose: &Isometry3<f64>| ik_target(pose, position_only);
    for p in samples {
        let options = seeded_options(numeric, previous.as_deref());
        let q = match (&lock, &previous) {
            (Some(l), Some(prev)) => follow(robot, solver, &target(&p.pose), l, prev, &options)?,
            _ => anchor(&solver.solve(robot, &target(&p.pose), &options)?, filter, numeric).map(|(q, l)| {
                if let Lock::Label(b) = &l {
                    out.branch = Some(b.clone());
                } else {
                    out.branch = Some(filter.clone());
                }
                lock = Some(l);
                q
            }),
        };
        if q.is_some() {
            previous.clone_from(&q);
        }
        out.q.push(q);
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// Rates
// ---------------------------------------------------------------------------------------------

/// Joint rates of the steps between consecutive samples (notes 003 §3.5): `Δq/Δt`, with the
/// increment of a revolute joint taken as the shortest rotation, so a ±180° crossing of a
/// wrapped angle gives no spike. `q` may be wrapped or unwrapped.
///
/// # Returns
/// `q.len() − 1` rate vectors (rad/s, m/s); step `k` (0-based) goes from sample `k` to `k + 1`.
///
/// # Errors
/// [`TrackingError::Shape`] when `t` and `q` differ in length, a vector has the wrong length,
/// or the times do not increase.
///
/// # Example
/// ```
/// use reach::motion::tracking::step_rates;
/// let robot = reach::model::presets::get("log-loader").unwrap();
/// let d = 179f64.to_radians();
/// let q = vec![vec![d, 0.0, 0.0], vec![-d, 0.0, 0.0]]; // 2° through ±180°
/// let r = step_rates(&robot, &[0.0, 1.0], &q).unwrap();
/// approx::assert_relative_eq!(r[0][0], 2f64.to_radians(), epsilon = 1e-12);
/// ```
pub fn step_rates(robot: &Robot, t: &[f64], q: &[Vec<f64>]) -> Result<Vec<Vec<f64>>, TrackingError> {
    if t.len() != q.len() {
        return Err(TrackingError::Shape { reason: format!("{} times for {} joint vectors", t.len(), q.len()) });
    }
    if let Some(i) = q.iter().position(|v| v.len() != robot.dof()) {
        return Err(TrackingError::Shape {
            reason: format!("joint vector {i} has {} values, the robot {} joints", q[i].len(), robot.dof()),
        });
    }
    let mut out = Vec::with_capacity(q.len().saturating_sub(1));
    for k in 1..q.len() {
        let dt = t[k] - t[k - 1];
        if dt.is_nan() || dt <= 0.0 {
            return Err(TrackingError::Shape { reason: format!("time does not increase at sample {k}") });
        }
        out.push(
            robot
                .joints()
                .iter()
                .zip(q[k - 1].iter().zip(&q[k]))
                .map(|(j, (a, b))| {
                    let d = if j.kind == JointKind::Revolute { shortest_difference(*a, *b) } else { b - a };
                    d / dt
                })
                .collect(),
        );
    }
    Ok(out)
}

// ---------------------------------------------------------------------------------------------
// Reports and events
// ---------------------------------------------------------------------------------------------

/// What kind of point splits the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitKind {
    /// A singular position (|Δ| = 1, wrist, shoulder, or a Jacobian rank drop).
    Singular(SingularityKind),
    /// The path leaves the reachable set of the configurations (Fig. 4 case 7).
    Leaves,
    /// The path enters it (Fig. 4 case 1).
    Enters,
}

/// A point where the path is split into intervals.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SplitPoint {
    /// Path parameter, refined by bisection / golden-section search.
    pub s: f64,
    /// Time.
    pub t: f64,
    /// What happens there.
    pub kind: SplitKind,
    /// The refined value of the measure that found it (0 for reachability changes).
    pub measure: f64,
}

/// Which limit a violation concerns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViolationKind {
    /// Joint position outside its range (case c of the paper).
    Position,
    /// Joint speed above its limit (case d).
    Velocity,
    /// The followed branch has no solution (a branch lost without a singular position).
    BranchLost,
}

/// A stretch of the path where a configuration breaks a limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Violation {
    /// Which limit.
    pub kind: ViolationKind,
    /// 1-based joint number (`None` for [`ViolationKind::BranchLost`]).
    pub joint: Option<usize>,
    /// Joint name (empty for a lost branch).
    pub name: String,
    /// Where it starts (path parameter; refined by bisection unless it starts with the interval).
    pub s_start: f64,
    /// Where it ends (the interval's end when it lasts to there).
    pub s_end: f64,
    /// Time at `s_start`.
    pub t_start: f64,
    /// Time at `s_end`.
    pub t_end: f64,
    /// The worst sampled value: the position (wrapped into (−π, π] for a range narrower than a
    /// turn) or the rate.
    pub worst: f64,
    /// Lower limit (position) or `−max_velocity`.
    pub lower: f64,
    /// Upper limit (position) or `max_velocity`.
    pub upper: f64,
}

/// A revolute joint of a tracked configuration crossing ±180° (its wrapped angle jumps by a
/// turn while the motion is continuous; notes 003 §5.5's θ4 at s = 842.12 mm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrapCrossing {
    /// 1-based joint number.
    pub joint: usize,
    /// Path parameter, refined by bisection.
    pub s: f64,
    /// Time.
    pub t: f64,
}

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

/// How an interval's configuration was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Decision {
    /// The default configuration (feasible, no criterion given).
    Default,
    /// The only feasible configuration.
    OnlyFeasible,
    /// Several were feasible but not the default, and no criterion was given: the first
    /// feasible one in the list.
    FirstFeasible,
    /// Several were feasible; the criterion chose.
    Criterion,
    /// Several were feasible and the criterion scored none: the default was kept (K14).
    CriterionRejected,
    /// Outside the reachable set, or no configuration feasible (K8).
    NotRealizable,
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
    /// Index (into [`TrackingReport::configurations`]) of the configuration realised.
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

/// A user criterion for choosing among feasible configurations (notes 003 §7 item 5: smaller
/// accelerations, energy, stiffness, …): lower scores are better; `None` means the
/// configuration does not satisfy the criterion.
pub trait Criterion {
    /// The score of one configuration's trajectory over an interval.
    fn score(&self, track: &ConfigurationTrack) -> Option<f64>;

    /// Index (into `feasible`) of the configuration to realise, or `None` when none satisfies
    /// the criterion. Default: the lowest finite [`score`](Criterion::score) (first on a tie);
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

impl<F: Fn(&ConfigurationTrack) -> Option<f64>> Criterion for F {
    fn score(&self, track: &ConfigurationTrack) -> Option<f64> {
        self(track)
    }
}

/// How singular positions are detected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SingularityDetection {
    /// The seed-003 closed-form measures when [`ParallelAxes`] is the solver, else the Jacobian.
    #[default]
    Auto,
    /// The Jacobian's relative smallest singular value, for every robot.
    Jacobian,
}

/// Options of [`track`].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TrackingOptions {
    /// The IK solver; `None`: [`SolverKind::detect`].
    pub solver: Option<SolverKind>,
    /// The configurations to consider (branch filters). Empty: for [`ParallelAxes`] the paper's
    /// two, `shoulder=w config=+β wrist=e5` and `shoulder=w config=−β wrist=e5`; for the
    /// numeric solver one (follow the nearest solution); for other closed forms every branch
    /// label found at the first reachable sample.
    pub configurations: Vec<Branch>,
    /// Index of the default configuration (the paper's "+β"; 0).
    pub default_configuration: usize,
    /// Track the tool position only.
    pub position_only: bool,
    /// How singular positions are found.
    pub detection: SingularityDetection,
    /// Skip the speed-limit check (the paper's "diagnostic" mode checks nothing; angles are
    /// always reported).
    pub ignore_velocity: bool,
}

// ---------------------------------------------------------------------------------------------
// The algorithm
// ---------------------------------------------------------------------------------------------

/// A scanned singularity measure.
#[derive(Debug, Clone, Copy)]
enum Measure {
    /// `sign·√|1 − |cos θ_elbow||` of one arm of the closed form.
    Elbow(Shoulder, Wrist),
    /// `sin∠(w, e6)` of one arm.
    Wrist(Shoulder, Wrist),
    /// `(ρ − |D|)/L`.
    Shoulder,
    /// `σ_min/σ_max`, minimised over the configurations' solutions.
    Jacobian,
}

impl Measure {
    fn kind(self) -> SingularityKind {
        match self {
            Measure::Elbow(..) => SingularityKind::Elbow,
            Measure::Wrist(..) => SingularityKind::Wrist,
            Measure::Shoulder => SingularityKind::Shoulder,
            Measure::Jacobian => SingularityKind::Jacobian,
        }
    }
}

/// The scan of the samples ([`Tracker::split_points`]).
struct Scan {
    /// Singular positions and reachability changes, by `s`.
    points: Vec<SplitPoint>,
    /// Whether any configuration has a solution, per sample.
    reach: Vec<bool>,
    /// The unseeded solutions of every sample.
    solutions: Vec<IkSolutions>,
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
    solving: Solving<'a>,
    path: &'a TrackedPath<'a>,
    configurations: Vec<Branch>,
    closed_form: Option<ParallelAxes>,
    measures: Vec<Measure>,
    length_scale: f64,
    tolerance: f64,
    check_velocity: bool,
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
    criterion: Option<&dyn Criterion>,
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
    criterion: Option<&dyn Criterion>,
    progress: &dyn Fn(usize, usize),
) -> Result<TrackingReport, TrackingError> {
    let kind = options.solver.unwrap_or_else(|| SolverKind::detect(robot));
    let solver = kind.build(robot)?;
    let numeric = is_numeric(solver.as_ref());
    let solving = Solving { robot, solver, position_only: options.position_only, numeric };
    let closed_form = if kind == SolverKind::ParallelAxes && !options.position_only {
        ParallelAxes::from_robot(robot).ok()
    } else {
        None
    };
    let configurations = if options.configurations.is_empty() {
        default_configurations(&solving, path, closed_form.is_some())?
    } else {
        options.configurations.clone()
    };
    if configurations.is_empty() {
        // No reachable sample to read labels from: one "any solution" configuration.
        let tracker = Tracker::new(solving, path, vec![Branch::default()], closed_form, options, progress);
        return track_with(tracker, 0, criterion);
    }
    if options.default_configuration >= configurations.len() {
        return Err(TrackingError::InvalidOption {
            option: "default_configuration",
            reason: format!("index {} but only {} configurations", options.default_configuration, configurations.len()),
        });
    }
    let closed_form = if options.detection == SingularityDetection::Jacobian { None } else { closed_form };
    track_with(
        Tracker::new(solving, path, configurations, closed_form, options, progress),
        options.default_configuration,
        criterion,
    )
}

fn default_configurations(
    solving: &Solving<'_>,
    path: &TrackedPath<'_>,
    paper: bool,
) -> Result<Vec<Branch>, TrackingError> {
    if paper {
        return Ok(["+β", "−β"]
            .into_iter()
            .map(|c| Branch::new([("shoulder", "w"), ("config", c), ("wrist", "e5")]))
            .collect());
    }
    if solving.numeric {
        return Ok(vec![Branch::default()]);
    }
    for p in path.samples() {
        let sols = solving.solve(&p.pose, None)?;
        if !sols.solutions.is_empty() {
            let mut labels: Vec<Branch> = Vec::new();
            for s in &sols.solutions {
                if !labels.contains(&s.branch) {
                    labels.push(s.branch.clone());
                }
            }
            return Ok(labels);
        }
    }
    Ok(Vec::new())
}

impl<'a> Tracker<'a> {
    fn new(
        solving: Solving<'a>,
        path: &'a TrackedPath<'a>,
        configurations: Vec<Branch>,
        closed_form: Option<ParallelAxes>,
        options: &TrackingOptions,
        progress: &'a dyn Fn(usize, usize),
    ) -> Self {
        let robot = solving.robot;
        let length_scale =
            robot.joints().iter().filter_map(Joint::dh).map(|p| p.a.abs() + p.d.abs()).sum::<f64>().max(1e-3);
        let measures = match &closed_form {
            Some(_) => {
                let mut m = Vec::new();
                for shoulder in [Shoulder::W, Shoulder::MinusW] {
                    for wrist in [Wrist::E5, Wrist::MinusE5] {
                        let used = configurations.iter().any(|c| {
                            c.get("shoulder").is_none_or(|v| v == shoulder.label())
                                && c.get("wrist").is_none_or(|v| v == wrist.label())
                        });
                        if used {
                            m.push(Measure::Elbow(shoulder, wrist));
                            m.push(Measure::Wrist(shoulder, wrist));
                        }
                    }
                }
                m.push(Measure::Shoulder);
                m
            }
            None => vec![Measure::Jacobian],
        };
        let tolerance = TRACKING_PARAMETER * (path.end() - path.start()).abs().max(f64::MIN_POSITIVE);
        let meter = Meter {
            hook: progress,
            total: 2 * path.samples().len() * configurations.len(),
            done: Cell::new(0),
            reported: Cell::new(0),
        };
        Tracker {
            meter,
            solving,
            path,
            configurations,
            closed_form,
            measures,
            length_scale,
            tolerance,
            check_velocity: !options.ignore_velocity,
        }
    }

    fn robot(&self) -> &Robot {
        self.solving.robot
    }

    /// Whether any configuration has a solution.
    fn reachable(&self, sols: &IkSolutions) -> bool {
        sols.solutions.iter().any(|s| self.configurations.iter().any(|c| matches(&s.branch, c)))
    }

    fn reachable_at(&self, s: f64) -> Result<bool, TrackingError> {
        let sols = self.solving.solve(&self.path.pose_at(s)?, None)?;
        Ok(self.reachable(&sols))
    }

    /// Every measure at `s` (`None` where undefined, e.g. unreachable).
    fn measures_at(
        &self,
        pose: &Isometry3<f64>,
        sols: Option<&IkSolutions>,
    ) -> Result<Vec<Option<f64>>, TrackingError> {
        let robot = self.robot();
        let mut out = Vec::with_capacity(self.measures.len());
        if let Some(cf) = &self.closed_form {
            let m = cf.measures(robot, pose, &IkOptions::default())?;
            for measure in &self.measures {
                out.push(match *measure {
                    Measure::Elbow(sh, wr) => m.arm(sh, wr).map(|a| {
                        let e = a.elbow_margin();
                        e.signum() * e.abs().sqrt()
                    }),
                    Measure::Wrist(sh, wr) => m.arm(sh, wr).map(|a| a.wrist_sine),
                    Measure::Shoulder => Some(m.shoulder_margin() / self.length_scale),
                    Measure::Jacobian => None,
                });
            }
            return Ok(out);
        }
        let owned;
        let sols = match sols {
            Some(s) => s,
            None => {
                owned = self.solving.solve(pose, None)?;
                &owned
            }
        };
        let axes = if self.solving.position_only { JacobianAxes::Translation } else { JacobianAxes::All };
        let mut best: Option<f64> = None;
        for s in sols.solutions.iter().filter(|s| self.configurations.iter().any(|c| matches(&s.branch, c))) {
            let m = Manipulability::of(&robot.jacobian(&s.q).map_err(IkError::from)?, axes);
            let v = if m.sigma_max > 0.0 { m.sigma_min / m.sigma_max } else { 0.0 };
            best = Some(best.map_or(v, |b: f64| b.min(v)));
        }
        out.push(best);
        Ok(out)
    }

    /// Bisection between `a` (predicate `pa`) and `b` (the opposite) to the path tolerance.
    fn bisect(
        &self,
        mut a: f64,
        mut b: f64,
        pa: bool,
        mut pred: impl FnMut(f64) -> Result<bool, TrackingError>,
    ) -> Result<f64, TrackingError> {
        for _ in 0..200 {
            if (b - a).abs() <= self.tolerance {
                break;
            }
            let m = 0.5 * (a + b);
            if pred(m)? == pa {
                a = m;
            } else {
                b = m;
            }
        }
        Ok(0.5 * (a + b))
    }

    /// Golden-section minimisation of measure `i` on `[a, b]`: (argmin, min).
    fn minimise(&self, i: usize, mut a: f64, mut b: f64) -> Result<(f64, f64), TrackingError> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let eval = |s: f64| -> Result<f64, TrackingError> {
            Ok(self.measures_at(&self.path.pose_at(s)?, None)?[i].unwrap_or(f64::INFINITY))
        };
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (eval(c)?, eval(d)?);
        for _ in 0..200 {
            if (b - a).abs() <= self.tolerance {
                break;
            }
            if fc <= fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = eval(c)?;
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = eval(d)?;
            }
        }
        Ok(if fc <= fd { (c, fc) } else { (d, fd) })
    }

    /// Step 2–3 of the algorithm: singular positions and reachability changes. Also returns
    /// the unseeded solutions of every sample (reused by [`Tracker::track_interval`]).
    fn split_points(&self) -> Result<Scan, TrackingError> {
        let samples = self.path.samples();
        let mut reach = Vec::with_capacity(samples.len());
        let mut values: Vec<Vec<Option<f64>>> = Vec::with_capacity(samples.len());
        let mut all = Vec::with_capacity(samples.len());
        for p in samples {
            let sols = self.solving.solve(&p.pose, None)?;
            reach.push(self.reachable(&sols));
            values.push(self.measures_at(&p.pose, Some(&sols))?);
            all.push(sols);
            self.meter.advance(self.configurations.len());
        }
        let mut points = Vec::new();
        for k in 1..samples.len() {
            if reach[k] != reach[k - 1] {
                let s = self.bisect(samples[k - 1].s, samples[k].s, reach[k - 1], |s| self.reachable_at(s))?;
                let kind = if reach[k - 1] { SplitKind::Leaves } else { SplitKind::Enters };
                points.push(SplitPoint { s, t: self.path.time_at(s), kind, measure: 0.0 });
            }
        }
        let n = samples.len();
        for (i, measure) in self.measures.iter().enumerate() {
            let v = |k: usize| values[k][i].filter(|x| *x >= 0.0);
            for k in 0..n {
                let Some(vk) = v(k) else { continue };
                let left = if k > 0 { v(k - 1) } else { None };
                let right = if k + 1 < n { v(k + 1) } else { None };
                let (Some(l), Some(r)) = (left, right) else {
                    // An end sample (or next to an unreachable one): singular only if the sample is.
                    if vk <= TRACKING_SINGULAR && (k == 0 || k == n - 1) {
                        points.push(self.singular_point(samples[k].s, *measure, vk)?);
                    }
                    continue;
                };
                if vk <= l && vk <= r && !(vk == l && k > 1 && v(k - 2).is_some_and(|x| x == vk)) {
                    let (s, m) = self.minimise(i, samples[k - 1].s, samples[k + 1].s)?;
                    if m <= TRACKING_SINGULAR {
                        points.push(self.singular_point(s, *measure, m)?);
                    }
                }
            }
        }
        points.sort_by(|a, b| a.s.total_cmp(&b.s));
        let merge = 1e3 * self.tolerance;
        let mut merged: Vec<SplitPoint> = Vec::with_capacity(points.len());
        for p in points {
            match merged.last_mut() {
                Some(last) if (p.s - last.s).abs() <= merge => {
                    // Keep reachability changes over singular positions at the same place (the
                    // boundary of the manipulation space is itself singular, Fig. 4 cases 1, 7).
                    if matches!(p.kind, SplitKind::Leaves | SplitKind::Enters) {
                        *last = p;
                    }
                }
                _ => merged.push(p),
            }
        }
        Ok(Scan { points: merged, reach, solutions: all })
    }

    /// A singular position at `s`, its kind read from the solver's flags when it sets one.
    fn singular_point(&self, s: f64, measure: Measure, value: f64) -> Result<SplitPoint, TrackingError> {
        let sols = self.solving.solve(&self.path.pose_at(s)?, None)?;
        let flagged = sols
            .solutions
            .iter()
            .filter(|x| self.configurations.iter().any(|c| matches(&x.branch, c)))
            .find_map(|x| x.singularities.first().copied());
        let kind = match measure {
            Measure::Jacobian => flagged.unwrap_or(SingularityKind::Jacobian),
            other => other.kind(),
        };
        Ok(SplitPoint { s, t: self.path.time_at(s), kind: SplitKind::Singular(kind), measure: value })
    }

    /// The joint vector of the locked branch at `s`, next to `reference`.
    fn q_at(&self, s: f64, lock: &Lock, reference: &[f64]) -> Result<Option<Vec<f64>>, TrackingError> {
        self.solving.follow(&self.path.pose_at(s)?, lock, reference)
    }

    /// Tracks configuration `c` over `points` (s values of one interval), given the unseeded
    /// solutions `sols` at those points (shared by the configurations); advances the meter by
    /// `budget` units, in proportion to the points followed.
    fn track_interval(
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
    fn track_interval_counted(
        &self,
        c: usize,
        points: &[f64],
        sols: &[Cow<'_, IkSolutions>],
        ends_at_boundary: (bool, bool),
        tick: &dyn Fn(),
    ) -> Result<ConfigurationTrack, TrackingError> {
        let robot = self.robot();
        let filter = &self.configurations[c];
        let anchor = (0..points.len())
            .filter_map(|k| anchor(&sols[k], filter, self.solving.numeric).map(|a| (k, a)))
            .min_by_key(|(k, (q, _))| {
                let singular = sols[*k].solutions.iter().any(|x| x.q == *q && !x.singularities.is_empty());
                (singular, *k)
            });
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

    fn lost(&self, a: f64, b: f64) -> Violation {
        Violation {
            kind: ViolationKind::BranchLost,
            joint: None,
            name: String::new(),
            s_start: a,
            s_end: b,
            t_start: self.path.time_at(a),
            t_end: self.path.time_at(b),
            worst: f64::NAN,
            lower: f64::NAN,
            upper: f64::NAN,
        }
    }

    /// Position violations, crossings refined by bisection.
    fn check_positions(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        for (j, joint) in robot.joints().iter().enumerate() {
            let inside = |v: f64| position_margin(joint, v) >= -LIMIT_SLACK;
            let n = track.q.len();
            for (first, last) in failing_runs(n, |k| inside(track.q[k][j])) {
                let s_start = if first == 0 {
                    track.s[0]
                } else {
                    let reference = track.q[first - 1].clone();
                    self.bisect(track.s[first - 1], track.s[first], true, |s| {
                        Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| inside(q[j])))
                    })?
                };
                let s_end = if last == n - 1 {
                    track.s[n - 1]
                } else {
                    let reference = track.q[last].clone();
                    self.bisect(track.s[last], track.s[last + 1], false, |s| {
                        Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| inside(q[j])))
                    })?
                };
                let worst = (first..=last)
                    .map(|i| track.q[i][j])
                    .min_by(|a, b| position_margin(joint, *a).total_cmp(&position_margin(joint, *b)))
                    .unwrap_or(f64::NAN);
                let worst =
                    if joint.kind == JointKind::Revolute && joint.limits.span() < TAU { wrap(worst) } else { worst };
                track.violations.push(Violation {
                    kind: ViolationKind::Position,
                    joint: Some(j + 1),
                    name: joint.name.clone(),
                    s_start,
                    s_end,
                    t_start: self.path.time_at(s_start),
                    t_end: self.path.time_at(s_end),
                    worst,
                    lower: joint.limits.lower,
                    upper: joint.limits.upper,
                });
            }
        }
        Ok(())
    }

    /// The instantaneous rate of joint `j` at `s` (central difference through IK).
    fn rate_at(&self, s: f64, j: usize, lock: &Lock, reference: &[f64]) -> Result<Option<f64>, TrackingError> {
        let h = TRACKING_RATE_STEP * (self.path.end() - self.path.start());
        let (a, b) = ((s - h).max(self.path.start()), (s + h).min(self.path.end()));
        let (Some(qa), Some(qb)) = (self.q_at(a, lock, reference)?, self.q_at(b, lock, reference)?) else {
            return Ok(None);
        };
        let dt = self.path.time_at(b) - self.path.time_at(a);
        Ok(Some((qb[j] - qa[j]) / dt))
    }

    /// Speed violations over runs of steps; where the rate changes smoothly the crossing is
    /// refined by bisection on the instantaneous rate, else the step's end is reported.
    fn check_velocities(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        let steps = track.step_rates.len();
        for (j, joint) in robot.joints().iter().enumerate() {
            let Some(vmax) = joint.max_velocity else { continue };
            let ok = |r: f64| r.abs() <= vmax * (1.0 + LIMIT_SLACK);
            for (first, last) in failing_runs(steps, |k| ok(track.step_rates[k][j])) {
                let mid = |i: usize| 0.5 * (track.s[i] + track.s[i + 1]);
                let inside_rate = |s: f64, reference: &[f64]| -> Result<bool, TrackingError> {
                    Ok(self.rate_at(s, j, lock, reference)?.is_none_or(ok))
                };
                let s_start = if first == 0 {
                    track.s[0]
                } else {
                    let reference = track.q[first].clone();
                    let (a, b) = (mid(first - 1), mid(first));
                    if inside_rate(a, &reference)? && !inside_rate(b, &reference)? {
                        self.bisect(a, b, true, |s| inside_rate(s, &reference))?
                    } else {
                        track.s[first]
                    }
                };
                let s_end = if last == steps - 1 {
                    track.s[steps]
                } else {
                    let reference = track.q[last + 1].clone();
                    let (a, b) = (mid(last), mid(last + 1));
                    if !inside_rate(a, &reference)? && inside_rate(b, &reference)? {
                        self.bisect(a, b, false, |s| inside_rate(s, &reference))?
                    } else {
                        track.s[last + 1]
                    }
                };
                let worst = (first..=last)
                    .map(|i| track.step_rates[i][j])
                    .max_by(|a, b| a.abs().total_cmp(&b.abs()))
                    .unwrap_or(f64::NAN);
                track.violations.push(Violation {
                    kind: ViolationKind::Velocity,
                    joint: Some(j + 1),
                    name: joint.name.clone(),
                    s_start,
                    s_end,
                    t_start: self.path.time_at(s_start),
                    t_end: self.path.time_at(s_end),
                    worst,
                    lower: -vmax,
                    upper: vmax,
                });
            }
        }
        Ok(())
    }

    /// ±180° crossings of the wrapped angles, refined by bisection.
    fn find_wraps(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        let turn = |v: f64| ((v + PI) / TAU).floor();
        for (j, joint) in robot.joints().iter().enumerate() {
            if joint.kind != JointKind::Revolute {
                continue;
            }
            for k in 1..track.q.len() {
                let (a, b) = (track.q[k - 1][j], track.q[k][j]);
                if turn(a) == turn(b) {
                    continue;
                }
                let reference = track.q[k - 1].clone();
                let side = turn(a);
                let s = self.bisect(track.s[k - 1], track.s[k], true, |s| {
                    Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| turn(q[j]) == side))
                })?;
                track.wraps.push(WrapCrossing { joint: j + 1, s, t: self.path.time_at(s) });
            }
        }
        Ok(())
    }
}

/// Signed distance of `v` inside the joint's range (negative outside): for a revolute joint
/// with a range narrower than a turn, of the best representative `v + 2πk`.
fn position_margin(joint: &Joint, v: f64) -> f64 {
    let (lo, hi) = (joint.limits.lower, joint.limits.upper);
    if joint.kind == JointKind::Revolute && joint.limits.span() < TAU {
        let w = wrap(v);
        [w - TAU, w, w + TAU].into_iter().map(|x| (x - lo).min(hi - x)).fold(f64::NEG_INFINITY, f64::max)
    } else {
        (v - lo).min(hi - v)
    }
}

fn joint_symbol(robot: &Robot, j: usize) -> String {
    let kind = robot.joints()[j - 1].kind;
    let name = &robot.joints()[j - 1].name;
    let sym = if kind == JointKind::Revolute { "θ" } else { "d" };
    if name.is_empty() { format!("{sym}{j}") } else { format!("{sym}{j} ({name})") }
}

/// The maximal runs `(first, last)` (inclusive) of indices `0..n` where `ok` is false, in order.
fn failing_runs(n: usize, ok: impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut k = 0;
    while k < n {
        if ok(k) {
            k += 1;
            continue;
        }
        let first = k;
        while k < n && !ok(k) {
            k += 1;
        }
        runs.push((first, k - 1));
    }
    runs
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

fn track_with(
    tracker: Tracker<'_>,
    default: usize,
    criterion: Option<&dyn Criterion>,
) -> Result<TrackingReport, TrackingError> {
    let path = tracker.path;
    let robot = tracker.robot();
    let Scan { points: split_points, reach, solutions: sample_solutions } = tracker.split_points()?;
    let samples = path.samples();
    let mut bounds = vec![(path.start(), None::<SplitKind>)];
    for p in &split_points {
        if p.s > path.start() + tracker.tolerance && p.s < path.end() - tracker.tolerance {
            bounds.push((p.s, Some(p.kind)));
        }
    }
    bounds.push((path.end(), None));
    let names: Vec<String> = tracker.configurations.iter().map(ToString::to_string).collect();
    let name = |c: usize| if names[c].is_empty() { "any".to_string() } else { format!("\"{}\"", names[c]) };
    let mut events = Vec::new();
    let event = |events: &mut Vec<TrackingEvent>,
                 code: EventCode,
                 s: f64,
                 interval: Option<usize>,
                 configuration: Option<usize>,
                 joint: Option<usize>,
                 message: String| {
        events.push(TrackingEvent { code, s, t: path.time_at(s), interval, configuration, joint, message });
    };
    let split_event = |events: &mut Vec<TrackingEvent>, p: &SplitPoint| {
        let (code, message) = match p.kind {
            SplitKind::Singular(kind) => {
                (EventCode::K2, format!("gripper at a singular point ({} singularity)", kind.as_str()))
            }
            SplitKind::Leaves => (EventCode::K1, "gripper leaves the manipulation space".to_string()),
            SplitKind::Enters => (EventCode::K3, "gripper enters the manipulation space".to_string()),
        };
        event(events, code, p.s, None, None, None, message);
    };
    for p in split_points.iter().filter(|p| p.s <= path.start() + tracker.tolerance) {
        split_event(&mut events, p);
    }
    let mut intervals = Vec::with_capacity(bounds.len() - 1);
    let count = bounds.len() - 1;
    // Progress: interval i owns the samples from the previous interval's end up to its end.
    let mut owned_until = 0;
    for i in 0..count {
        let (a, ka) = bounds[i];
        let (b, kb) = bounds[i + 1];
        let index = i + 1;
        let until = if index == count { samples.len() } else { samples.partition_point(|p| p.s < b) };
        let budget = until - owned_until;
        owned_until = until;
        let mut points = vec![a];
        // The samples strictly inside (a, b), a tolerance away from both ends: a range, since
        // the samples' s increase strictly (validated by TrackedPath).
        let first = samples.partition_point(|p| p.s <= a + tracker.tolerance);
        let interior = first..samples.partition_point(|p| p.s < b - tracker.tolerance).max(first);
        points.extend(samples[interior.clone()].iter().map(|p| p.s));
        points.push(b);
        let reachable = if interior.is_empty() { tracker.reachable_at(0.5 * (a + b))? } else { reach[interior.start] };
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
            tracker.meter.advance(budget * tracker.configurations.len());
            event(
                &mut events,
                EventCode::K1,
                a,
                Some(index),
                None,
                None,
                format!("gripper outside the manipulation space on s ∈ ({a:.6}, {b:.6})"),
            );
            event(
                &mut events,
                EventCode::K8,
                a,
                Some(index),
                None,
                None,
                format!("trajectory interval P{index} not realizable; checking the next interval"),
            );
        } else {
            event(
                &mut events,
                EventCode::K3,
                a,
                Some(index),
                None,
                None,
                format!("gripper in the manipulation space on interval P{index}, s ∈ [{a:.6}, {b:.6}]"),
            );
            let boundary = |k: Option<SplitKind>| matches!(k, Some(SplitKind::Leaves | SplitKind::Enters));
            let order: Vec<usize> =
                std::iter::once(default).chain((0..tracker.configurations.len()).filter(|&c| c != default)).collect();
            let mut tracks: Vec<Option<ConfigurationTrack>> = vec![None; tracker.configurations.len()];
            // The unseeded solutions at the interval's points, once for every configuration:
            // a sample's from the scan when the path gives the sample's own pose there.
            let mut sols: Vec<Cow<'_, IkSolutions>> = Vec::with_capacity(points.len());
            for (j, &s) in points.iter().enumerate() {
                let pose = path.pose_at(s)?;
                let k = j.checked_sub(1).map(|j| interior.start + j).filter(|k| interior.contains(k));
                sols.push(match k {
                    Some(k) if samples[k].pose == pose => Cow::Borrowed(&sample_solutions[k]),
                    _ => Cow::Owned(tracker.solving.solve(&pose, None)?),
                });
            }
            for (rank, &c) in order.iter().enumerate() {
                let t = tracker.track_interval(c, &points, &sols, (boundary(ka), boundary(kb)), budget)?;
                let is_default = rank == 0;
                let next = order.get(1).map(|&n| name(n));
                for v in &t.violations {
                    let joint = v.joint.map(|j| joint_symbol(robot, j)).unwrap_or_default();
                    let (code, text) = match (v.kind, is_default) {
                        (ViolationKind::Position, true) => (
                            EventCode::K4,
                            format!(
                                "angle {joint} not in the interval of possible values {} on s ∈ ({:.6}, {:.6}){}",
                                limit_range(robot, v),
                                v.s_start,
                                v.s_end,
                                next.as_ref().map(|n| format!("; switching to configuration {n}")).unwrap_or_default()
                            ),
                        ),
                        (ViolationKind::Velocity, true) => (
                            EventCode::K5,
                            format!(
                                "angular velocity of {joint} not in {} on s ∈ ({:.6}, {:.6}){}; configuration {} not realizable",
                                limit_range(robot, v),
                                v.s_start,
                                v.s_end,
                                next.as_ref().map(|n| format!("; switching to configuration {n}")).unwrap_or_default(),
                                name(c)
                            ),
                        ),
                        (ViolationKind::Position, false) => (
                            EventCode::K7,
                            format!(
                                "computed angle {joint} not in the interval of possible values {} on s ∈ ({:.6}, {:.6}); configuration {} not realizable",
                                limit_range(robot, v),
                                v.s_start,
                                v.s_end,
                                name(c)
                            ),
                        ),
                        (ViolationKind::Velocity, false) => (
                            EventCode::K12,
                            format!(
                                "computed angular velocity of {joint} not in {} on s ∈ ({:.6}, {:.6}); configuration {} not realizable",
                                limit_range(robot, v),
                                v.s_start,
                                v.s_end,
                                name(c)
                            ),
                        ),
                        (ViolationKind::BranchLost, d) => (
                            if d { EventCode::K4 } else { EventCode::K7 },
                            format!(
                                "configuration {} has no solution on s ∈ ({:.6}, {:.6}); not realizable",
                                name(c),
                                v.s_start,
                                v.s_end
                            ),
                        ),
                    };
                    event(&mut events, code, v.s_start, Some(index), Some(c), v.joint, text);
                }
                if is_default && t.feasible {
                    let rest = if order.len() > 1 { "; checking the other configurations" } else { "" };
                    event(
                        &mut events,
                        EventCode::K6,
                        a,
                        Some(index),
                        Some(c),
                        None,
                        format!("configuration {} realizable{rest}", name(c)),
                    );
                }
                tracks[c] = Some(t);
            }
            let tracks: Vec<ConfigurationTrack> =
                tracks.into_iter().map(|t| t.expect("every configuration tracked")).collect();
            let feasible: Vec<usize> = order.iter().copied().filter(|&c| tracks[c].feasible).collect();
            let (chosen, decision) = match feasible.len() {
                0 => (None, Decision::NotRealizable),
                1 => {
                    (Some(feasible[0]), if feasible[0] == default { Decision::Default } else { Decision::OnlyFeasible })
                }
                _ => {
                    event(
                        &mut events,
                        EventCode::K13,
                        a,
                        Some(index),
                        None,
                        None,
                        format!(
                            "configurations {} realizable",
                            feasible.iter().map(|&c| name(c)).collect::<Vec<_>>().join(", ")
                        ),
                    );
                    let fallback = if feasible.contains(&default) { default } else { feasible[0] };
                    match criterion {
                        None if fallback == default => (Some(fallback), Decision::Default),
                        None => (Some(fallback), Decision::FirstFeasible),
                        Some(cr) => {
                            let candidates: Vec<&ConfigurationTrack> = feasible.iter().map(|&c| &tracks[c]).collect();
                            match cr.choose(&candidates).and_then(|k| feasible.get(k).copied()) {
                                Some(c) => (Some(c), Decision::Criterion),
                                None => {
                                    event(
                                        &mut events,
                                        EventCode::K14,
                                        a,
                                        Some(index),
                                        Some(fallback),
                                        None,
                                        format!(
                                            "criterion cannot be satisfied; rejecting it, configuration {} is realized",
                                            name(fallback)
                                        ),
                                    );
                                    (Some(fallback), Decision::CriterionRejected)
                                }
                            }
                        }
                    }
                }
            };
            match chosen {
                Some(c) => event(
                    &mut events,
                    EventCode::K9,
                    a,
                    Some(index),
                    Some(c),
                    None,
                    format!("in interval P{index} I realize configuration {}", name(c)),
                ),
                None => event(
                    &mut events,
                    EventCode::K8,
                    a,
                    Some(index),
                    None,
                    None,
                    format!("trajectory interval P{index} not realizable; checking the next interval"),
                ),
            }
            report.configurations = tracks;
            report.chosen = chosen;
            report.decision = decision;
        }
        for p in split_points.iter().filter(|p| p.s > a + tracker.tolerance && p.s <= b + tracker.tolerance) {
            split_event(&mut events, p);
        }
        if index < count {
            event(
                &mut events,
                EventCode::K10,
                b,
                Some(index),
                None,
                None,
                format!("moving to the next trajectory interval P{}", index + 1),
            );
        } else {
            event(&mut events, EventCode::K11, b, Some(index), None, None, "end of trajectory".into());
        }
        intervals.push(report);
    }
    let mut trajectory: Vec<TrajectoryPoint> = Vec::new();
    for interval in &intervals {
        let Some(c) = interval.chosen else { continue };
        let t = &interval.configurations[c];
        for k in 0..t.q.len() {
            let q = match trajectory.last() {
                Some(last) if (last.s - t.s[k]).abs() <= tracker.tolerance => continue,
                Some(last) => unwrap_to(robot, &t.q[k], &last.q),
                None => t.q[k].clone(),
            };
            trajectory.push(TrajectoryPoint { s: t.s[k], t: t.t[k], q, configuration: c });
        }
    }
    let feasible = intervals.iter().all(|i| i.chosen.is_some());
    tracker.meter.finish();
    Ok(TrackingReport {
        solver: tracker.solving.solver.name(),
        configurations: tracker.configurations.clone(),
        default_configuration: default,
        split_points,
        intervals,
        events,
        trajectory,
        feasible,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn position_margin_is_modular_for_ranges_narrower_than_a_turn() {
        let welder = presets::get("welder6r").unwrap();
        let j4 = &welder.joints()[3]; // [−175°, 150°]
        let m = |deg: f64| position_margin(j4, deg.to_radians()).to_degrees();
        assert!((m(0.0) - 150.0).abs() < 1e-9);
        assert!((m(140.0) - 10.0).abs() < 1e-9);
        // 190° is −170° (inside, 5° from −175°); 167.5° is the middle of the gap (150°, 185°).
        assert!((m(190.0) - 5.0).abs() < 1e-9);
        assert!((m(167.5) + 17.5).abs() < 1e-9);
        // An unlimited joint is never outside; a wide range is checked on the value itself.
        let mut j = j4.clone();
        j.limits = crate::model::Limits::new(-3.0 * PI, 3.0 * PI);
        assert!(position_margin(&j, 3.5 * PI) < 0.0 && position_margin(&j, 2.5 * PI) > 0.0);
        j.limits = crate::model::Limits::UNLIMITED;
        assert!(position_margin(&j, 1e6) > 0.0);
    }

    #[test]
    fn filters_match_subsets_of_labels() {
        let label = Branch::new([("shoulder", "w"), ("config", "+β"), ("wrist", "e5")]);
        assert!(matches(&label, &Branch::new([("config", "+β")])));
        assert!(matches(&label, &Branch::default()));
        assert!(!matches(&label, &Branch::new([("config", "−β")])));
        assert!(!matches(&label, &Branch::new([("elbow", "up")])));
    }
}
