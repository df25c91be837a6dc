//! The one solution type shared by every IK solver.

use std::borrow::Cow;
use std::fmt;
use std::sync::Arc;

use nalgebra::{Isometry3, Point3, Rotation3, Vector3};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use smallvec::SmallVec;

use crate::angle::fit_into_limits;
use crate::kinematics::{FrameLanes, Lanes, check_q};
use crate::model::{JointKind, Robot};
use crate::tolerance::{DH_EQUIVALENT_EXACT, IK_DUPLICATE, IK_ORIENTATION, IK_POSITION, LIMIT_SLACK};

use super::{IkError, IkTarget};

/// Kinds of singular configuration an IK solver reports.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
pub enum SingularityKind {
    /// Wrist axes aligned (e.g. θ5 = 0 in a spherical wrist): roll angles not separable.
    Wrist,
    /// Elbow fully stretched or folded (workspace boundary).
    Elbow,
    /// Wrist centre (or tool point) on the first joint axis: base angle undetermined.
    Shoulder,
    /// The Jacobian lost rank for another reason (numeric detection).
    Jacobian,
}

impl SingularityKind {
    /// Lower-case name.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            SingularityKind::Wrist => "wrist",
            SingularityKind::Elbow => "elbow",
            SingularityKind::Shoulder => "shoulder",
            SingularityKind::Jacobian => "jacobian",
        }
    }
}

/// One key or value of a [`Branch`] label: a static string (no allocation — the closed-form
/// solvers' fixed names) or an owned one (labels built at run time).
#[derive(Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize, JsonSchema)]
#[serde(transparent)]
pub struct Label(Cow<'static, str>);

impl Label {
    /// The text.
    #[must_use]
    pub fn as_str(&self) -> &str {
        &self.0
    }

    /// Whether this label holds the static string `s` itself (the same address and length; a
    /// cheap sufficient test of equality, `false` for an owned copy of the same text).
    fn is(&self, s: &'static str) -> bool {
        matches!(&self.0, Cow::Borrowed(b) if std::ptr::eq(*b, s))
    }
}

impl std::ops::Deref for Label {
    type Target = str;
    fn deref(&self) -> &str {
        &self.0
    }
}

impl From<&'static str> for Label {
    fn from(s: &'static str) -> Self {
        Label(Cow::Borrowed(s))
    }
}

impl From<String> for Label {
    fn from(s: String) -> Self {
        Label(Cow::Owned(s))
    }
}

impl fmt::Debug for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Debug::fmt(self.as_str(), f)
    }
}

impl fmt::Display for Label {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A readable branch label: ordered `key=value` pairs, e.g. `shoulder=left elbow=up wrist=flip`
/// or the paper's own names such as `config=+β`. In JSON: the pairs in order,
/// `[["shoulder", "left"], ["elbow", "up"]]`.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default, Serialize, Deserialize, JsonSchema)]
pub struct Branch(pub Vec<(Label, Label)>);

impl Branch {
    /// A label from pairs (static strings are kept without copying).
    #[must_use]
    pub fn new<K: Into<Label>, V: Into<Label>>(pairs: impl IntoIterator<Item = (K, V)>) -> Self {
        Branch(pairs.into_iter().map(|(k, v)| (k.into(), v.into())).collect())
    }

    /// The value of `key`, if present.
    #[must_use]
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0.iter().find(|(k, _)| k.as_str() == key).map(|(_, v)| v.as_str())
    }
}

impl fmt::Display for Branch {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, (k, v)) in self.0.iter().enumerate() {
            if i > 0 {
                f.write_str(" ")?;
            }
            write!(f, "{k}={v}")?;
        }
        Ok(())
    }
}

/// A joint outside its limits.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitViolation {
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name, shared with the robot ([`Robot::joint_name`]: no allocation per
    /// violation); a JSON string.
    #[serde(serialize_with = "serialize_str")]
    pub name: Arc<str>,
    /// The value (radians / metres).
    pub value: f64,
    /// Lower limit.
    pub lower: f64,
    /// Upper limit.
    pub upper: f64,
}

/// Serialises a shared string as a plain string.
fn serialize_str<S: serde::Serializer>(s: &Arc<str>, serializer: S) -> Result<S::Ok, S::Error> {
    serializer.serialize_str(s)
}

/// One IK solution, verified by forward kinematics.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct IkSolution {
    /// Joint values (radians / metres); revolute angles wrapped into (−π, π] or moved by whole
    /// turns into the joint range.
    pub q: Vec<f64>,
    /// Which branch (configuration) this is.
    pub branch: Branch,
    /// ‖p(q) − p_target‖, metres.
    pub position_error: f64,
    /// Angle of `R_targetᵀ·R(q)`, radians (0 for position-only targets).
    pub orientation_error: f64,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
    /// Every joint outside its limits.
    pub violations: Vec<LimitViolation>,
    /// Singular configurations this solution sits at.
    pub singularities: Vec<SingularityKind>,
}

/// Why an IK problem has no solution within limits.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
#[non_exhaustive]
pub enum IkFailure {
    /// The target position is outside the workspace: `distance` is the relevant distance of
    /// the target (e.g. from the shoulder), `reach` the bound it violates (maximum or minimum reach).
    Unreachable {
        /// Distance of the target (metres).
        distance: f64,
        /// The violated bound (metres).
        reach: f64,
    },
    /// The position is reachable but not with the requested orientation.
    OrientationUnreachable,
    /// The target is a singular configuration the solver cannot resolve.
    Singular {
        /// Which singularity.
        kind: SingularityKind,
    },
    /// Solutions exist, but every one violates a joint limit (the first violated joint of the
    /// first solution is named).
    OutsideLimits {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
    },
    /// Other branches solve the target but the requested one does not
    /// ([`IkSolver::solve_branch`](super::IkSolver::solve_branch)): it merged with another
    /// branch at a singular configuration, or its formula has no root or fails the FK check here.
    BranchAbsent {
        /// The requested branch label (`shoulder=left elbow=up wrist=flip`).
        branch: String,
    },
    /// The numeric solver did not converge.
    NoConvergence {
        /// Iterations spent (over all restarts).
        iterations: usize,
        /// Best residual reached (metres + radians).
        residual: f64,
    },
}

impl fmt::Display for IkFailure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            IkFailure::Unreachable { distance, reach } => {
                write!(f, "target out of reach: distance {distance:.6} m, workspace bound {reach:.6} m")
            }
            IkFailure::OrientationUnreachable => f.write_str("position reachable, orientation not"),
            IkFailure::Singular { kind } => write!(f, "target is a {} singularity", kind.as_str()),
            IkFailure::OutsideLimits { joint, name } => {
                write!(f, "every solution violates a joint limit (first: joint {joint} ({name}))")
            }
            IkFailure::BranchAbsent { branch } => write!(f, "no solution on branch `{branch}` (other branches exist)"),
            IkFailure::NoConvergence { iterations, residual } => {
                write!(f, "numeric IK did not converge ({iterations} iterations, residual {residual:.3e})")
            }
        }
    }
}

/// All solutions of one IK problem, and the reason when none is within limits.
///
/// Also the workspace of [`IkSolver::solve_into`](super::IkSolver::solve_into): a solve into a
/// reused `IkSolutions` overwrites it in place and keeps its buffers (the solutions' vectors,
/// and spare solutions of an earlier solve that had more), so that a closed form's solve
/// allocates nothing once the buffers are large enough. `IkSolutions::default()` is an empty
/// one (no solver, no solutions).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct IkSolutions {
    /// Name of the solver that produced them.
    pub solver: &'static str,
    /// Every branch found, verified by FK (within-limits and outside-limits ones alike).
    pub solutions: Vec<IkSolution>,
    /// Set when no solution is within limits.
    pub failure: Option<IkFailure>,
    /// How joint changes are measured by [`IkSolutions::closest_to`]: the robot's own rule
    /// ([`Differences::for_robot`](crate::effort::Differences::for_robot): revolute wrapped,
    /// prismatic literal).
    #[serde(skip)]
    differences: JointWraps,
    /// Solutions of an earlier solve beyond the current count, kept for their buffers.
    #[serde(skip)]
    spare: Spare,
}

/// Spare [`IkSolution`]s of a reused [`IkSolutions`]: buffers only, not part of the value (equal
/// to any other, cloned empty).
#[derive(Default)]
struct Spare(Vec<IkSolution>);

impl Clone for Spare {
    fn clone(&self) -> Self {
        Spare::default()
    }
}

impl PartialEq for Spare {
    fn eq(&self, _: &Spare) -> bool {
        true
    }
}

impl fmt::Debug for Spare {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} spare", self.0.len())
    }
}

/// Which joints of the solved robot wrap ([`Joint::wraps`](crate::model::Joint::wraps), the
/// crate's one joint-difference rule), without allocating for robots of up to 64 joints: bit
/// `i` of a mask. Robots of more joints (rare) fall back to one flag per joint in a vector.
#[derive(Debug, Clone, PartialEq)]
enum JointWraps {
    /// Bit `i` set: joint `i` (0-based) wraps.
    Mask(u64),
    /// More than 64 joints: `true` for a revolute joint.
    Wide(Vec<bool>),
}

impl Default for JointWraps {
    fn default() -> Self {
        JointWraps::Mask(0)
    }
}

impl JointWraps {
    /// Becomes [`JointWraps::for_robot`], reusing the vector of a wide robot's flags.
    fn set_for_robot(&mut self, robot: &Robot) {
        match self {
            JointWraps::Wide(v) if robot.dof() > 64 => {
                v.clear();
                v.extend(robot.joints().iter().map(crate::model::Joint::wraps));
            }
            _ => *self = JointWraps::for_robot(robot),
        }
    }

    fn for_robot(robot: &Robot) -> Self {
        let wraps = robot.joints().iter().map(crate::model::Joint::wraps);
        if robot.dof() <= 64 {
            JointWraps::Mask(wraps.enumerate().fold(0, |m, (i, r)| if r { m | (1 << i) } else { m }))
        } else {
            JointWraps::Wide(wraps.collect())
        }
    }

    /// The change from `a` to `b` of joint `i`, as [`Joint::difference`](crate::model::Joint::difference)
    /// (literal for an index beyond the robot's joints).
    fn diff(&self, i: usize, a: f64, b: f64) -> f64 {
        let wraps = match self {
            JointWraps::Mask(m) => {
                u32::try_from(i).ok().and_then(|s| m.checked_shr(s)).is_some_and(|bits| bits & 1 == 1)
            }
            JointWraps::Wide(v) => v.get(i).copied().unwrap_or(false),
        };
        if wraps { crate::angle::wrap(b - a) } else { b - a }
    }
}

impl IkSolutions {
    /// The solutions within joint limits.
    pub fn feasible(&self) -> impl Iterator<Item = &IkSolution> {
        self.solutions.iter().filter(|s| s.within_limits)
    }

    /// Whether there is no solution within limits.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.feasible().next().is_none()
    }

    /// The feasible solution with the smallest weighted joint change from `from`
    /// (`Σ wᵢ |Δqᵢ|`, radians and metres; seed 000's and 001's rule), each `Δqᵢ` the distance
    /// joint `i` travels ([`Joint::difference`](crate::model::Joint::difference) of the solved
    /// robot).
    /// `weights` shorter than the joint vector count as 1 for the missing joints.
    #[must_use]
    pub fn closest_to(&self, from: &[f64], weights: &[f64]) -> Option<&IkSolution> {
        let cost = |s: &IkSolution| -> f64 {
            s.q.iter()
                .zip(from)
                .enumerate()
                .map(|(i, (a, b))| weights.get(i).copied().unwrap_or(1.0) * self.differences.diff(i, *b, *a).abs())
                .sum()
        };
        self.feasible().min_by(|a, b| cost(a).total_cmp(&cost(b)))
    }

    /// The solutions labelled exactly `branch`, in the same order, with the failure restated
    /// for them: none when one is within limits, [`IkFailure::OutsideLimits`] (the first
    /// violated joint of the first) when all violate limits. When none is labelled `branch`,
    /// the failure of the whole problem if it has no solution at all, else
    /// [`IkFailure::BranchAbsent`]. This defines [`IkSolver::solve_branch`](super::IkSolver::solve_branch).
    #[must_use]
    pub fn restricted_to(self, branch: &Branch) -> IkSolutions {
        let IkSolutions { solver, solutions, failure, differences, spare } = self;
        let any = !solutions.is_empty();
        let solutions: Vec<IkSolution> = solutions.into_iter().filter(|s| s.branch == *branch).collect();
        let failure = match limits_failure(&solutions, None) {
            Some(f) => Some(f),
            None if solutions.is_empty() && any => Some(IkFailure::BranchAbsent { branch: branch.to_string() }),
            None if solutions.is_empty() => failure,
            None => None,
        };
        IkSolutions { solver, solutions, failure, differences, spare }
    }

    /// Re-expresses each solution's revolute values by the representative `qᵢ + 2πk` nearest to
    /// `from` that stays within the joint's limits. A joint whose range is wider than a turn (a
    /// UR5's ±360°) has two representatives of most angles; the solver reports the one in
    /// (−π, π], and this picks the one a joint-space motion from `from` reaches by turning least —
    /// what [`IkSolutions::closest_to`] then measures with the robot's one joint-difference rule
    /// ([`Joint::difference`](crate::model::Joint::difference)). Joints of a narrower range (one
    /// representative within limits), prismatic joints and values with no representative within
    /// limits are unchanged; `from` shorter than the joint vector leaves the rest unchanged.
    pub fn express_near(&mut self, robot: &Robot, from: &[f64]) {
        for solution in &mut self.solutions {
            for ((v, joint), &reference) in solution.q.iter_mut().zip(robot.joints()).zip(from) {
                if joint.kind == JointKind::Revolute && reference.is_finite() {
                    let near = crate::angle::nearest_equivalent(*v, reference);
                    if joint.limits.contains(near, LIMIT_SLACK) {
                        *v = near;
                    }
                }
            }
        }
    }

    /// The index in [`IkSolutions::solutions`] of [`IkSolutions::closest_to`]'s choice (same
    /// rule, same arguments), for callers that keep indices (rankings, reports).
    #[must_use]
    pub fn closest_index(&self, from: &[f64], weights: &[f64]) -> Option<usize> {
        let chosen = self.closest_to(from, weights)?;
        self.solutions.iter().position(|s| std::ptr::eq(s, chosen))
    }
}

/// [`IkFailure::OutsideLimits`] when `solutions` is not empty and every one violates a limit
/// (the first violated joint of the first solution is named); `None` otherwise. The name is
/// written into `buffer` when one is given (a reused solve's previous failure name).
fn limits_failure(solutions: &[IkSolution], buffer: Option<String>) -> Option<IkFailure> {
    if !solutions.is_empty() && solutions.iter().all(|s| !s.within_limits) {
        let v = &solutions[0].violations[0];
        let mut name = buffer.unwrap_or_default();
        name.clear();
        name.push_str(&v.name);
        Some(IkFailure::OutsideLimits { joint: v.joint, name })
    } else {
        None
    }
}

/// Joint values of a [`Candidate`]: inline up to 8 joints (every closed form), on the heap
/// beyond (long chains, numeric solver only).
pub(crate) type JointValues = SmallVec<[f64; 8]>;

/// The `key=value` pairs of a [`Candidate`]'s branch label, inline up to 3 pairs; a [`Branch`]
/// once the candidate is verified (the 6R closed forms use the compact [`Raw6`] instead).
pub(crate) type Labels = SmallVec<[(Label, Label); 3]>;

/// The singularity flags of a [`Candidate`], inline (there are four kinds).
pub(crate) type Flags = SmallVec<[SingularityKind; 4]>;

/// A raw solver output before verification.
#[derive(Debug, Clone)]
pub(crate) struct Candidate {
    pub q: JointValues,
    pub branch: Labels,
    pub singularities: Flags,
}

impl Candidate {
    pub fn new(q: Vec<f64>, branch: Branch) -> Self {
        Candidate { q: SmallVec::from_vec(q), branch: SmallVec::from_vec(branch.0), singularities: Flags::new() }
    }
}

/// The singularity kinds of a [`Raw6`] as bits, reported in one fixed order — shoulder, elbow,
/// wrist, Jacobian — the order in which every 6R closed form flags them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct FlagBits(u8);

impl FlagBits {
    /// The kinds in the order of their bits.
    const ORDER: [SingularityKind; 4] =
        [SingularityKind::Shoulder, SingularityKind::Elbow, SingularityKind::Wrist, SingularityKind::Jacobian];

    /// These flags with `kind` added when `on`.
    #[must_use]
    pub fn with(self, kind: SingularityKind, on: bool) -> Self {
        let bit = Self::ORDER.iter().position(|k| *k == kind).map_or(0, |i| 1 << i);
        if on { FlagBits(self.0 | bit) } else { self }
    }

    /// The kinds set, in the fixed order (lowest bit first; nothing to visit when none is set).
    pub fn iter(self) -> impl Iterator<Item = SingularityKind> {
        let mut bits = self.0;
        std::iter::from_fn(move || {
            let i = bits.trailing_zeros() as usize;
            bits &= bits.wrapping_sub(1);
            Self::ORDER.get(i).copied()
        })
    }

    /// The first kind set, if any.
    #[must_use]
    pub fn first(self) -> Option<SingularityKind> {
        self.iter().next()
    }

    /// Whether no kind is set.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// A raw solution of a 6R closed form (spherical wrist, two-link wrist, parallel axes): the
/// six joint values, the values of its three-part branch label (the keys are the set's,
/// [`Raw6Set`]) and its singularity flags — about 100 bytes, no vector. The public
/// [`IkSolution`] is built only for the verified ones.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Raw6 {
    pub q: [f64; 6],
    pub values: [&'static str; 3],
    pub flags: FlagBits,
}

/// The raw solutions of one 6R closed-form solve: a fixed-capacity set of up to 8 on the stack
/// (every such arm has at most 8 solutions), labelled with the same three keys.
#[derive(Debug, Clone)]
pub(crate) struct Raw6Set {
    keys: [&'static str; 3],
    items: SmallVec<[Raw6; 8]>,
}

impl Raw6Set {
    /// An empty set whose labels have the keys `keys`.
    #[must_use]
    pub fn new(keys: [&'static str; 3]) -> Self {
        Raw6Set { keys, items: SmallVec::new() }
    }

    /// Adds a solution.
    pub fn push(&mut self, raw: Raw6) {
        self.items.push(raw);
    }

    /// The solutions, in the order pushed.
    pub fn iter(&self) -> impl Iterator<Item = &Raw6> {
        self.items.iter()
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Keeps only the solutions labelled exactly `branch`.
    pub fn retain_branch(&mut self, branch: &Branch) {
        let keys = self.keys;
        self.items.retain(|r| {
            branch.0.len() == 3
                && branch
                    .0
                    .iter()
                    .zip(keys.iter().zip(&r.values))
                    .all(|((k, v), (rk, rv))| k.as_str() == *rk && v.as_str() == *rv)
        });
    }
}

/// The candidates a verification ([`finish_within_into`]) reads: the general [`Candidate`]s
/// (any joint count, owned labels) or a closed form's compact [`Raw6Set`].
pub(crate) trait CandidateList {
    /// Number of candidates.
    fn count(&self) -> usize;
    /// Joint values of candidate `i`.
    fn joints(&self, i: usize) -> &[f64];
    /// Joint values of candidate `i`, to normalise in place.
    fn joints_mut(&mut self, i: usize) -> &mut [f64];
    /// Singularity flags of candidate `i`, in order.
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_;
    /// Makes `out` (a reused solution's label) candidate `i`'s branch label (moving it out:
    /// called once, for a kept candidate).
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>);
}

impl CandidateList for [Candidate] {
    fn count(&self) -> usize {
        self.len()
    }
    fn joints(&self, i: usize) -> &[f64] {
        &self[i].q
    }
    fn joints_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self[i].q
    }
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_ {
        self[i].singularities.iter().copied()
    }
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>) {
        out.clear();
        out.extend(self[i].branch.drain(..));
    }
}

impl CandidateList for Raw6Set {
    fn count(&self) -> usize {
        self.items.len()
    }
    fn joints(&self, i: usize) -> &[f64] {
        &self.items[i].q
    }
    fn joints_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self.items[i].q
    }
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_ {
        self.items[i].flags.iter()
    }
    /// A reused solution that holds the same static strings already (the usual case: a solve
    /// into a reused [`IkSolutions`] returns the branches in the same order) keeps its label.
    #[inline]
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>) {
        let values = self.items[i].values;
        let pairs = self.keys.iter().zip(values);
        if out.len() == self.keys.len() && out.iter().zip(pairs.clone()).all(|((k, v), (rk, rv))| k.is(rk) && v.is(rv))
        {
            return;
        }
        out.clear();
        out.extend(pairs.map(|(k, v)| (Label::from(*k), Label::from(v))));
    }
}

/// [`fit_into_limits`] with the IK slack: revolute values as the solvers report them
/// (wrapped into (−π, π], or moved by whole turns into the joint range). An angle already in
/// (−π, π] and within the limits costs two comparisons ([`crate::angle::wrap`]'s fast path).
#[inline]
pub(crate) fn fit_revolute(angle: f64, limits: &crate::model::Limits) -> f64 {
    fit_into_limits(angle, limits, LIMIT_SLACK)
}

/// Whether two joint values are equal within `IK_DUPLICATE` modulo whole turns
/// (`wrap(a − b).abs() < IK_DUPLICATE`), skipping the `fmod` when the plain difference decides.
#[inline]
fn same_angle(a: f64, b: f64) -> bool {
    use std::f64::consts::{PI, TAU};
    let d = (a - b).abs();
    // |d| < IK_DUPLICATE (< π) wraps to itself; |d| in [IK_DUPLICATE, π] also wraps to itself
    // and fails the test; only larger differences can wrap back near 0.
    if d < IK_DUPLICATE {
        true
    } else if d <= PI {
        false
    } else if d < TAU {
        // `wrap(a − b)` is `a − b ∓ 2π` here, exactly (Sterbenz: 2π lies within [d, 2d]), of
        // magnitude `2π − d`, also exact: the same value without the remainder (the two
        // wrist solutions of an arm differ by about π in θ4 and θ6).
        TAU - d < IK_DUPLICATE
    } else {
        crate::angle::wrap(a - b).abs() < IK_DUPLICATE
    }
}

/// Whether two joint values are different by [`same_angle`] *and* by the prismatic rule of
/// [`same_q`], whatever the joint's kind: `true` proves that two joint vectors differing so at
/// one joint are different solutions; `false` proves nothing (`NaN` gives `false`). The lane
/// screen of [`verify_block`], branch-free.
#[inline(always)]
fn surely_distinct(a: f64, b: f64) -> bool {
    use std::f64::consts::TAU;
    let d = (a - b).abs();
    let e = TAU - d;
    // Revolute, d < 2π: for d ≤ π, e ≥ π > IK_DUPLICATE and the test is d ≥ IK_DUPLICATE
    // (at d = π the minimum is e = π), where `same_angle` is false; for d in (π, 2π),
    // e < π < d and the test is 2π − d ≥ IK_DUPLICATE, `same_angle`'s own (exact) term.
    // Prismatic: either way d ≥ IK_DUPLICATE. d ≥ 2π proves nothing here.
    (d < TAU) & ((if d < e { d } else { e }) >= IK_DUPLICATE)
}

/// Whether two joint vectors are the same solution: revolute values by [`same_angle`], prismatic
/// ones literally (`|a − b| < IK_DUPLICATE` metres — 0 m and 2π m are different).
/// Compared from the last joint: branches of an arm share their first joints (the two wrist
/// solutions of one arm differ first in the wrist), so distinct ones part at once.
fn same_q(robot: &Robot, a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).zip(robot.joints()).rev().all(|((a, b), j)| match j.kind {
        JointKind::Revolute => same_angle(*a, *b),
        JointKind::Prismatic => (a - b).abs() < IK_DUPLICATE,
    })
}

/// The target of the FK check, prepared once per solve (the target rotation as a transposed
/// matrix instead of a quaternion converted for each candidate).
enum Check {
    /// Flange position and `R_targetᵀ`.
    Pose(Vector3<f64>, Rotation3<f64>),
    /// Tool point only.
    Position(Point3<f64>),
}

/// Joint count up to which candidates are verified in lanes ([`Robot::fk_lanes`], joint values
/// on the stack); longer chains take the scalar forward kinematics one candidate at a time.
const LANE_DOF: usize = 8;

/// Candidates verified together: the 8 solutions of a 6R closed form in one pass.
const VERIFY_LANES: usize = 8;

impl Check {
    fn new(target: &IkTarget) -> Self {
        match target {
            IkTarget::Pose(pose) => Check::Pose(pose.translation.vector, pose.rotation.to_rotation_matrix().inverse()),
            IkTarget::Position(p) => Check::Position(*p),
        }
    }

    /// Pose errors of the tool poses `t`, lane by lane: the position error (metres) and the
    /// orientation error's `(sin, cos)` (the angle is `atan2` of them, [`Check::angle`]; both 0
    /// for a position target).
    ///
    /// The angle of `R_targetᵀ·R` is not `acos((tr − 1)/2)`: that is NaN when rounding puts the
    /// trace above 3 (an exact solution), and imprecise near 0. `atan2(½‖vee(R − Rᵀ)‖, (tr − 1)/2)`
    /// is neither. Each lane is the scalar formula with nalgebra's order of operations.
    #[inline(always)]
    fn errors<const L: usize>(&self, t: &FrameLanes<L>) -> (Lanes<L>, Lanes<L>, Lanes<L>) {
        let norm = |x: f64, y: f64, z: f64| (x * x + y * y + z * z).sqrt();
        match self {
            Check::Pose(p, r_inv) => {
                let k = r_inv.matrix();
                let position = std::array::from_fn(|l| norm(t.p[0][l] - p.x, t.p[1][l] - p.y, t.p[2][l] - p.z));
                // Entry (i, j) of R_targetᵀ·R.
                let m = |i: usize, j: usize, l: usize| {
                    k[(i, 0)] * t.r[0][j][l] + k[(i, 1)] * t.r[1][j][l] + k[(i, 2)] * t.r[2][j][l]
                };
                let mut sin = [0.0; L];
                let mut cos = [0.0; L];
                for l in 0..L {
                    sin[l] = 0.5 * norm(m(2, 1, l) - m(1, 2, l), m(0, 2, l) - m(2, 0, l), m(1, 0, l) - m(0, 1, l));
                    cos[l] = 0.5 * (m(0, 0, l) + m(1, 1, l) + m(2, 2, l) - 1.0);
                }
                (position, sin, cos)
            }
            Check::Position(p) => {
                let position = std::array::from_fn(|l| norm(t.p[0][l] - p.x, t.p[1][l] - p.y, t.p[2][l] - p.z));
                (position, [0.0; L], [1.0; L])
            }
        }
    }

    /// The orientation errors (radians) of [`Check::errors`]' `(sin, cos)`, lane by lane
    /// ([`atan2_each`](crate::angle::atan2_each): the lanes together when `WIDE`, bit for bit
    /// `atan2` either way): 0 for a position target.
    #[inline(always)]
    fn angles<const WIDE: bool, const L: usize>(&self, sin: &Lanes<L>, cos: &Lanes<L>) -> Lanes<L> {
        match self {
            Check::Pose(..) => crate::angle::atan2_each::<WIDE, L>(sin, cos),
            Check::Position(_) => [0.0; L],
        }
    }
}

/// The lane part of [`verify_block`]: the tool poses of `L` candidates (`q[j][l]`, the first
/// `shared` joints shared by groups of `L / H` lanes when `shared > 0`,
/// [`Robot::fk_lanes_shared`]) and their errors against the target — position (metres) and
/// orientation (radians). Inlined, so that it is compiled for the SIMD level of the closed
/// form's kernel ([`SolveKernel`]); every level, and `WIDE` or not ([`Check::angles`]), gives
/// the same bits.
#[inline(always)]
fn lane_errors<const WIDE: bool, const L: usize, const H: usize>(
    robot: &Robot,
    check: &Check,
    q: &[Lanes<L>],
    shared: usize,
) -> (Lanes<L>, Lanes<L>) {
    let t = if shared == 0 {
        robot.fk_lanes(q)
    } else {
        // Lane `g · L/H` of each shared joint (a loop: `array::from_fn` stayed an out-of-line
        // call here).
        let group = L / H;
        let shared = shared.min(LANE_DOF).min(q.len());
        let mut prefix = [[0.0; H]; LANE_DOF];
        for j in 0..shared {
            for g in 0..H {
                prefix[j][g] = q[j][g * group];
            }
        }
        robot.fk_lanes_shared(&prefix[..shared], q)
    };
    let (position, sin, cos) = check.errors(&t);
    (position, check.angles::<WIDE, L>(&sin, &cos))
}

/// A solver whose [`IkSolver::solve_into`](super::IkSolver::solve_into) runs as a
/// [`crate::simd::Kernel`] ([`SolveKernel`]): its lane work — the FK check of the candidates in
/// [`finish_into`], and the solver's own lanes — compiled for the SIMD level
/// [`crate::simd::run`] picks ([`solve_at`]).
pub(crate) trait LaneSolve {
    /// The solve (what `solve_into` does), with its hot inner functions inlined
    /// (`#[inline(always)]`). `WIDE`: whether its lane work is compiled for a level of four
    /// lanes or more, where the branch-free lane forms pay ([`crate::angle::atan2_each`]); the
    /// result is the same bit for bit.
    fn solve_lanes<const WIDE: bool>(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &super::IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError>;
}

/// [`LaneSolve::solve_lanes`] as a [`crate::simd::Kernel`].
pub(crate) struct SolveKernel<'a, S, const WIDE: bool> {
    pub solver: &'a S,
    pub robot: &'a Robot,
    pub target: &'a IkTarget,
    pub options: &'a super::IkOptions,
    pub out: &'a mut IkSolutions,
}

impl<S: LaneSolve, const WIDE: bool> crate::simd::Kernel for SolveKernel<'_, S, WIDE> {
    type Output = Result<(), IkError>;

    #[inline(always)]
    fn run(self) -> Result<(), IkError> {
        self.solver.solve_lanes::<WIDE>(self.robot, self.target, self.options, self.out)
    }
}

/// The solve of a closed form ([`LaneSolve`], its `solve_into`) at SIMD level `level`
/// ([`crate::simd::level`] in `solve_into`): at the baseline level (two lanes per instruction)
/// the scalar-per-lane kernel, run directly; above, the wide one through
/// [`crate::simd::run_at`]. Every level gives the same bits.
pub(crate) fn solve_at<S: LaneSolve>(
    level: crate::simd::Level,
    solver: &S,
    robot: &Robot,
    target: &IkTarget,
    options: &super::IkOptions,
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    use crate::simd::Kernel;
    if level == crate::simd::Level::Baseline {
        SolveKernel::<S, false> { solver, robot, target, options, out }.run()
    } else {
        crate::simd::run_at(level, SolveKernel::<S, true> { solver, robot, target, options, out })
    }
}

/// Verifies, normalises and de-duplicates candidates, and states the failure reason.
///
/// * revolute angles are wrapped (or moved by whole turns into the joint range);
/// * candidates whose FK misses the target by more than `IK_POSITION` / `IK_ORIENTATION`
///   are dropped (a closed form evaluated outside its domain);
/// * candidates equal within `IK_DUPLICATE` are merged (their singularity flags united);
/// * `if_empty` is the reason reported when no candidate survives; when some survive but all
///   violate limits the reason is [`IkFailure::OutsideLimits`].
///
/// Every candidate's tool pose is its full forward kinematics: for chains of up to
/// [`LANE_DOF`] joints, [`VERIFY_LANES`] candidates at a time through [`Robot::fk_lanes`] (each
/// lane [`Robot::fk_matrix`] of its candidate), longer chains one at a time through
/// [`Robot::fk_matrix`].
pub(crate) fn finish(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut [Candidate],
    solver: &'static str,
    if_empty: IkFailure,
) -> Result<IkSolutions, IkError> {
    solved(|out| finish_into::<false, _>(robot, target, candidates, solver, if_empty, out))
}

/// [`finish`] into a reused `out` (see [`finish_within_into`]), for any [`CandidateList`]: the
/// 6R closed forms' compact [`Raw6Set`] as well as [`Candidate`]s. `WIDE` as in
/// [`LaneSolve::solve_lanes`] (`false` outside a [`SolveKernel`]).
#[inline(always)]
pub(crate) fn finish_into<const WIDE: bool, C: CandidateList + ?Sized>(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut C,
    solver: &'static str,
    if_empty: IkFailure,
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    finish_within_into::<WIDE, C>(robot, target, candidates, solver, if_empty, (IK_POSITION, IK_ORIENTATION), out)
}

/// The result of a lean solve (`f`, an [`IkSolver::solve_into`](super::IkSolver::solve_into))
/// in a new [`IkSolutions`]: how the closed forms implement [`IkSolver::solve`](super::IkSolver::solve).
pub(crate) fn solved(f: impl FnOnce(&mut IkSolutions) -> Result<(), IkError>) -> Result<IkSolutions, IkError> {
    let mut out = IkSolutions::default();
    f(&mut out)?;
    Ok(out)
}

/// [`finish`] with the acceptance tolerances `(metres, radians)` given instead of
/// `IK_POSITION` / `IK_ORIENTATION` (the numeric solver's user-set tolerances).
pub(crate) fn finish_within(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut [Candidate],
    solver: &'static str,
    if_empty: IkFailure,
    tolerances: (f64, f64),
) -> Result<IkSolutions, IkError> {
    solved(|out| finish_within_into::<false, _>(robot, target, candidates, solver, if_empty, tolerances, out))
}

/// The revolute values of `q` fitted into their limits ([`fit_revolute`]), in place; `false`
/// (and `q` untouched) when a value is not finite (the candidate is dropped).
#[inline]
fn normalise(robot: &Robot, q: &mut [f64]) -> bool {
    if q.iter().any(|v| !v.is_finite()) {
        return false;
    }
    for (v, joint) in q.iter_mut().zip(robot.joints()) {
        if joint.kind == JointKind::Revolute {
            *v = fit_revolute(*v, &joint.limits);
        }
    }
    true
}

/// [`finish_within`] writing into `out` ([`IkSolver::solve_into`](super::IkSolver::solve_into)):
/// `out`'s solutions are overwritten in place (their vectors cleared and refilled, keeping
/// their capacity), solutions beyond the new count are kept aside as spares and taken back
/// before any new one is made. The result equals [`finish_within`]'s whatever `out` held.
///
/// Inlined, as the lane kernel it calls, so that a closed form's [`SolveKernel`] compiles it
/// for its SIMD level (`WIDE` as in [`LaneSolve::solve_lanes`]).
#[inline(always)]
pub(crate) fn finish_within_into<const WIDE: bool, C: CandidateList + ?Sized>(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut C,
    solver: &'static str,
    if_empty: IkFailure,
    tolerances: (f64, f64),
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    let check = Check::new(target);
    // The solutions of `out` are overwritten in order, then spares (taken back last first),
    // then new ones: the result does not depend on what `out` held, only the buffers are
    // reused.
    let mut kept = Kept { robot, tolerances, len: 0, block: 0, solutions: &mut out.solutions, spare: &mut out.spare.0 };
    let n = candidates.count();
    kept.solutions.reserve(n.saturating_sub(kept.solutions.len()));
    let dof = robot.dof();
    if dof <= LANE_DOF {
        // Blocks of 8, the rest in the narrowest block that holds it (one candidate of
        // `solve_branch` takes the one-lane kernel, not an eight-lane one).
        let mut start = 0;
        while start < n {
            start += match n - start {
                5.. => {
                    verify_block::<WIDE, VERIFY_LANES, { VERIFY_LANES / 2 }, C>(&mut kept, &check, candidates, start)?
                }
                3..=4 => verify_block::<WIDE, 4, 2, C>(&mut kept, &check, candidates, start)?,
                2 => verify_block::<WIDE, 2, 1, C>(&mut kept, &check, candidates, start)?,
                _ => verify_block::<WIDE, 1, 1, C>(&mut kept, &check, candidates, start)?,
            };
        }
    } else {
        for i in 0..n {
            if !normalise(robot, candidates.joints_mut(i)) {
                continue;
            }
            let t = robot.fk_matrix(candidates.joints(i))?;
            let m = t.rotation.matrix();
            let t = FrameLanes::<1> {
                r: std::array::from_fn(|r| std::array::from_fn(|c| [m[(r, c)]])),
                p: std::array::from_fn(|k| [t.translation.vector[k]]),
            };
            let (position, sin, cos) = check.errors(&t);
            kept.offer(candidates, i, position[0], check.angles::<false, 1>(&sin, &cos)[0], Screen::default());
        }
    }
    let len = kept.len;
    out.spare.0.extend(out.solutions.drain(len..).rev());
    let recycled = match out.failure.take() {
        Some(IkFailure::OutsideLimits { name, .. }) => Some(name),
        _ => None,
    };
    out.failure = if out.solutions.is_empty() { Some(if_empty) } else { limits_failure(&out.solutions, recycled) };
    out.solver = solver;
    out.differences.set_for_robot(robot);
    Ok(())
}

/// Verifies up to `L` candidates from `start` together ([`Robot::fk_lanes`], [`Check::errors`])
/// and offers each finite one to `kept`, in order; returns how many it took.
///
/// When consecutive pairs of candidates share their first joint values (the two wrist
/// solutions of each arm of a 6R closed form share θ1…θ3), the chain up to the last shared
/// joint is walked once per pair, on `H = L / 2` lanes ([`Robot::fk_lanes_shared`], bit for
/// bit the same poses); `H = L` walks every lane alone.
#[inline(always)]
fn verify_block<const WIDE: bool, const L: usize, const H: usize, C: CandidateList + ?Sized>(
    kept: &mut Kept<'_>,
    check: &Check,
    candidates: &mut C,
    start: usize,
) -> Result<usize, IkError> {
    let (robot, dof) = (kept.robot, kept.robot.dof());
    let len = (candidates.count() - start).min(L);
    // Lanes of dropped candidates (and beyond `len`) compute the pose of zeros or of another
    // lane's values ([`shared_prefix`]), unused.
    let mut q = [[0.0; L]; LANE_DOF];
    let mut finite = [false; L];
    for l in 0..len {
        let v = candidates.joints_mut(start + l);
        if normalise(robot, v) {
            if v.len() != dof {
                check_q(dof, v)?;
            }
            finite[l] = true;
            for (lanes, x) in q.iter_mut().zip(v.iter()) {
                lanes[l] = *x;
            }
        }
    }
    let shared = shared_prefix::<L, H>(robot, &mut q[..dof], &finite, len);
    let (position, orientation) = lane_errors::<WIDE, L, H>(robot, check, &q[..dof], shared);
    let screens = screen::<L>(robot, &q[..dof]);
    kept.block = kept.len;
    for l in 0..len {
        if finite[l] {
            kept.offer(candidates, start + l, position[l], orientation[l], screens[l]);
        }
    }
    Ok(len)
}

/// What the lanes of one block prove about each candidate before it is offered to [`Kept`],
/// so that the usual case skips the per-joint loops. The default proves nothing.
#[derive(Clone, Copy, Default)]
struct Screen {
    /// Every joint within its limits ([`Limits::contains`](crate::model::Limits::contains)
    /// with [`LIMIT_SLACK`], the test of the violation list): no violation to look for.
    within: bool,
    /// The last joint's value is [`surely_distinct`] from that of every earlier lane of the
    /// block: no solution kept from this block can be the same.
    distinct: bool,
}

/// The [`Screen`] of each lane of `q` (`q[j][l]`, `q.len()` joints ≥ 1). Lanes without a
/// verified candidate hold zeros or another lane's values (see [`shared_prefix`]); they can
/// only clear a later lane's `distinct`, so a screen never claims more than holds.
#[inline(always)]
fn screen<const L: usize>(robot: &Robot, q: &[Lanes<L>]) -> [Screen; L] {
    let mut within = [true; L];
    for (joint, lanes) in robot.joints().iter().zip(q) {
        for l in 0..L {
            within[l] &= joint.limits.contains(lanes[l], LIMIT_SLACK);
        }
    }
    let last = &q[q.len() - 1];
    let mut distinct = [true; L];
    // Each lane against every other, masked to the earlier ones: whole vectors, no triangle.
    for (m, &earlier) in last.iter().enumerate() {
        for l in 0..L {
            distinct[l] &= (l <= m) | surely_distinct(last[l], earlier);
        }
    }
    let mut screens = [Screen::default(); L];
    for l in 0..L {
        screens[l] = Screen { within: within[l], distinct: distinct[l] };
    }
    screens
}

/// How many leading joints every group of `L / H` consecutive lanes of `q` (`q[j][l]`) shares,
/// bit for bit, when the chain up to them has no mimic joint (else 0, as for `H = L`). Lanes
/// not verified (beyond `len`, or not `finite`) take their group's first verified lane's values
/// first: their poses are not read, so they need not part a group.
fn shared_prefix<const L: usize, const H: usize>(
    robot: &Robot,
    q: &mut [Lanes<L>],
    finite: &[bool; L],
    len: usize,
) -> usize {
    if H == L {
        return 0;
    }
    let group = L / H;
    for g in 0..H {
        let lanes = g * group..(g + 1) * group;
        let Some(first) = lanes.clone().find(|&l| l < len && finite[l]) else { continue };
        for l in lanes {
            if l >= len || !finite[l] {
                for joint in q.iter_mut() {
                    joint[l] = joint[first];
                }
            }
        }
    }
    let k = q.iter().take_while(|joint| (0..L).all(|l| joint[l].to_bits() == joint[l - l % group].to_bits())).count();
    if robot.prefix_without_mimics(k) { k } else { 0 }
}

/// The solutions a verification keeps, in order, with the buffers it reuses.
struct Kept<'a> {
    robot: &'a Robot,
    tolerances: (f64, f64),
    /// Number of solutions kept so far: the first `len` of `solutions` (those beyond are
    /// buffers of an earlier solve, overwritten next).
    len: usize,
    /// Number of solutions kept before the current block of [`verify_block`]: a candidate
    /// screened [`Screen::distinct`] is compared with these only (unused on the scalar path,
    /// whose candidates are never screened distinct).
    block: usize,
    solutions: &'a mut Vec<IkSolution>,
    spare: &'a mut Vec<IkSolution>,
}

impl Kept<'_> {
    /// Candidate `i` of `candidates` (normalised, its tool pose `position_error` metres and
    /// `orientation_error` radians away from the target, `screen` what its block proved):
    /// dropped when outside the tolerances, merged into an equal kept solution (flags
    /// united), else kept.
    fn offer<C: CandidateList + ?Sized>(
        &mut self,
        candidates: &mut C,
        i: usize,
        position_error: f64,
        orientation_error: f64,
        screen: Screen,
    ) {
        let (position_tolerance, orientation_tolerance) = self.tolerances;
        if position_error > position_tolerance || orientation_error > orientation_tolerance {
            return;
        }
        let robot = self.robot;
        let q = candidates.joints(i);
        let compared = if screen.distinct { self.block } else { self.len };
        if let Some(existing) = self.solutions[..compared].iter_mut().find(|s| same_q(robot, &s.q, q)) {
            for k in candidates.flags(i) {
                if !existing.singularities.contains(&k) {
                    existing.singularities.push(k);
                }
            }
            return;
        }
        if self.len == self.solutions.len() {
            self.solutions.push(self.spare.pop().unwrap_or_default());
        }
        let s = &mut self.solutions[self.len];
        self.len += 1;
        s.q.clear();
        s.q.extend_from_slice(q);
        s.position_error = position_error;
        s.orientation_error = orientation_error;
        s.violations.clear();
        let joints = if screen.within { &[][..] } else { robot.joints() };
        for (i, (j, v)) in joints.iter().zip(q).enumerate() {
            if !j.limits.contains(*v, LIMIT_SLACK) {
                s.violations.push(LimitViolation {
                    joint: i + 1,
                    name: robot.joint_name(i).map_or_else(|| Arc::from(j.name.as_str()), Arc::clone),
                    value: *v,
                    lower: j.limits.lower,
                    upper: j.limits.upper,
                });
            }
        }
        s.within_limits = s.violations.is_empty();
        s.singularities.clear();
        s.singularities.extend(candidates.flags(i));
        candidates.take_label(i, &mut s.branch.0);
    }
}

/// The flange pose in the chain's own frame: `base⁻¹ · target · tool⁻¹`.
#[must_use]
pub(crate) fn chain_target(robot: &Robot, target: &Isometry3<f64>) -> Isometry3<f64> {
    robot.base().inverse() * target * robot.tool().inverse()
}

/// Where the DH chain a closed form solves sits relative to the robot's own base and tool:
/// nothing between them for a robot described in standard DH (the solver reads its table);
/// for any other robot the base and tool of its standard-DH equivalent
/// ([`Robot::dh_equivalent`]) relative to the robot's own, `B_rel = base⁻¹·B_dh` and
/// `T_rel = T_dh·tool⁻¹`. The robot's own base and tool still apply at solve time, as for a DH
/// robot, so a solver built for a robot also solves a copy with another tool
/// ([`Robot::with_tool`]).
///
/// When the equivalent's forward kinematics deviate from the robot's by more than rounding
/// ([`DH_EQUIVALENT_EXACT`]: twists or lengths were made exact), [`ChainFrame::refine`] moves
/// the closed form's candidates onto the robot's own pose by Newton steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct ChainFrame {
    /// `(B_rel⁻¹, T_rel⁻¹)`; `None` when both are the identity.
    relative: Option<(Isometry3<f64>, Isometry3<f64>)>,
    /// Whether the candidates need refining on the robot itself.
    refine: bool,
}

impl ChainFrame {
    /// The frame of `equivalent` (the standard-DH equivalent of `robot`, whose forward
    /// kinematics deviate from the robot's by up to `gap`) relative to `robot`.
    #[must_use]
    pub fn between(robot: &Robot, equivalent: &Robot, gap: f64) -> Self {
        let base = robot.base().inverse() * equivalent.base();
        let tool = equivalent.tool() * robot.tool().inverse();
        ChainFrame { relative: Some((base.inverse(), tool.inverse())), refine: gap > DH_EQUIVALENT_EXACT }
    }

    /// For an equivalent that is not exact, up to two Newton steps per candidate on `robot`
    /// itself towards a pose target (`Δq = J⁻¹·e`, the 6×6 geometric Jacobian; a step is kept
    /// only when it reduces the error, so a singular candidate stays as computed). Nothing for
    /// an exact equivalent, the robot's own table, or a position target (whose solutions keep
    /// an orientation of the solver's choosing). [`finish`] verifies the result as always.
    pub fn refine<C: CandidateList + ?Sized>(&self, robot: &Robot, target: &IkTarget, candidates: &mut C) {
        let (true, IkTarget::Pose(pose), 6) = (self.refine, target, robot.dof()) else {
            return;
        };
        let goal = nalgebra::IsometryMatrix3::from_parts(pose.translation, pose.rotation.to_rotation_matrix());
        let error = |q: &[f64]| -> Option<(nalgebra::Vector6<f64>, f64)> {
            let t = robot.fk_matrix(q).ok()?;
            let dp = goal.translation.vector - t.translation.vector;
            let (w, angle) = super::numeric::rotation_log(&(goal.rotation.matrix() * t.rotation.matrix().transpose()));
            Some((nalgebra::Vector6::new(dp.x, dp.y, dp.z, w.x, w.y, w.z), dp.norm().max(angle)))
        };
        for i in 0..candidates.count() {
            let q = candidates.joints_mut(i);
            for _ in 0..2 {
                let Some((e, size)) = error(q) else { break };
                let Ok(jac) = robot.jacobian(q) else { break };
                let Some(dq) = nalgebra::Matrix6::from_iterator(jac.iter().copied()).lu().solve(&e) else { break };
                let trial: JointValues = q.iter().zip(dq.iter()).map(|(q, d)| q + d).collect();
                match error(&trial) {
                    Some((_, smaller)) if smaller < size => q.copy_from_slice(&trial),
                    _ => break,
                }
            }
        }
    }

    /// Whether the chain is the robot's own DH table.
    #[must_use]
    pub fn is_own(&self) -> bool {
        self.relative.is_none()
    }

    /// The flange pose of the DH chain for the world pose `target` of `robot`'s tool:
    /// [`chain_target`], then `B_rel⁻¹ · … · T_rel⁻¹`.
    #[must_use]
    pub fn target(&self, robot: &Robot, target: &Isometry3<f64>) -> Isometry3<f64> {
        let t = chain_target(robot, target);
        match &self.relative {
            None => t,
            Some((base, tool)) => base * t * tool,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joint_wraps_match_the_robot_rule_with_and_without_the_mask() {
        // A bounded yaw takes literal differences (the one rule, `Joint::difference`)…
        assert_eq!(JointWraps::for_robot(&yaw_slide()), JointWraps::Mask(0));
        // …a continuous one wraps.
        let robot = Robot::from_toml_str(
            "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
             [[joints]]\nname = \"yaw\"\nalpha = -90\n\
             [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
        )
        .unwrap();
        let wraps = JointWraps::for_robot(&robot);
        assert_eq!(wraps, JointWraps::Mask(0b01));
        let rule = crate::effort::Differences::for_robot(&robot);
        for (i, (a, b)) in [(0, (3.0, -3.0)), (1, (3.0, -3.0)), (0, (0.1, 0.4)), (1, (-9.0, 9.0))] {
            assert_eq!(wraps.diff(i, a, b), rule.diff(i, a, b), "joint {i}");
        }
        // Joints beyond the mask are literal, never a shift overflow.
        assert_eq!(wraps.diff(64, 3.0, -3.0), -6.0);
        assert_eq!(wraps.diff(200, 3.0, -3.0), -6.0);
        let wide = JointWraps::Wide(vec![false, true]);
        assert_eq!(wide.diff(0, 3.0, -3.0), -6.0);
        assert!((wide.diff(1, 3.0, -3.0) - (2.0 * std::f64::consts::PI - 6.0)).abs() < 1e-12);
        assert_eq!(wide.diff(2, 3.0, -3.0), -6.0);
    }

    /// Base yaw about z, then a 10 m prismatic slide perpendicular to it (DH α₁ = −90°): the
    /// tool is at `d·(−sin θ, cos θ, 0)`, so `(0, d)` and `(π, −d)` reach the same point.
    fn yaw_slide() -> Robot {
        Robot::from_toml_str(
            "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
             [[joints]]\nname = \"yaw\"\nalpha = -90\nlimits = [-180, 180]\n\
             [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
        )
        .unwrap()
    }

    #[test]
    fn closest_to_takes_prismatic_changes_literally() {
        let robot = yaw_slide();
        let pi = std::f64::consts::PI;
        let target = IkTarget::Position(robot.fk(&[0.0, 4.0]).unwrap().translation.vector.into());
        let mut candidates = vec![
            Candidate::new(vec![0.0, 4.0], Branch::new([("side", "front")])),
            Candidate::new(vec![pi, -4.0], Branch::new([("side", "back")])),
        ];
        let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
        assert_eq!(all.solutions.len(), 2, "{all:?}");
        // From (0, −4): "front" moves the slide 8 m (cost 8), "back" turns the base by π (cost π).
        // Wrapping the slide's 8 m as an angle (8 − 2π ≈ 1.72) would wrongly prefer "front".
        let chosen = all.closest_to(&[0.0, -4.0], &[]).unwrap();
        assert_eq!(chosen.branch.get("side"), Some("back"), "{chosen:?}");
        // And from (0, 3.9) the slide change is small and "front" wins.
        let chosen = all.closest_to(&[0.0, 3.9], &[]).unwrap();
        assert_eq!(chosen.branch.get("side"), Some("front"), "{chosen:?}");
    }

    #[test]
    fn prismatic_values_a_turn_apart_are_distinct_solutions() {
        // Two collinear slides along z: (0, 2π) and (2π, 0) reach the same point but are
        // different configurations (a revolute pair 2π apart would be one).
        let robot = Robot::from_toml_str(
            "name = \"double-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
             [[joints]]\nname = \"s1\"\nkind = \"prismatic\"\nlimits = [0, 10]\n\
             [[joints]]\nname = \"s2\"\nkind = \"prismatic\"\nlimits = [0, 10]\n",
        )
        .unwrap();
        let tau = std::f64::consts::TAU;
        let target = IkTarget::Position(robot.fk(&[0.0, tau]).unwrap().translation.vector.into());
        let mut candidates = vec![
            Candidate::new(vec![0.0, tau], Branch::new([("slide", "2")])),
            Candidate::new(vec![tau, 0.0], Branch::new([("slide", "1")])),
        ];
        let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
        assert_eq!(all.solutions.len(), 2, "{all:?}");
    }

    #[test]
    fn closest_index_counts_every_solution_and_skips_infeasible_ones() {
        // The yaw-slide robot with the yaw limited to [−90°, 90°]: "back" (yaw ±π) is outside.
        let robot = Robot::from_toml_str(
            "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
             [[joints]]\nname = \"yaw\"\nalpha = -90\nlimits = [-90, 90]\n\
             [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
        )
        .unwrap();
        let pi = std::f64::consts::PI;
        let target = IkTarget::Position(robot.fk(&[0.0, 4.0]).unwrap().translation.vector.into());
        let mut candidates = vec![
            Candidate::new(vec![pi, -4.0], Branch::new([("side", "back")])),
            Candidate::new(vec![0.0, 4.0], Branch::new([("side", "front")])),
        ];
        let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
        assert_eq!(all.solutions.len(), 2, "{all:?}");
        let back = all.solutions.iter().position(|s| s.branch.get("side") == Some("back")).unwrap();
        assert!(!all.solutions[back].within_limits, "{all:?}");
        // From (π, −4) "back" costs nothing but is outside the limits: "front" is chosen, and its
        // index counts the infeasible solution too.
        let front = all.solutions.iter().position(|s| s.branch.get("side") == Some("front")).unwrap();
        assert_eq!(all.closest_index(&[pi, -4.0], &[]), Some(front));
        let chosen = all.closest_to(&[pi, -4.0], &[]).unwrap();
        assert!(std::ptr::eq(&all.solutions[front], chosen));
        // No feasible solution: no index.
        let none = all.restricted_to(&Branch::new([("side", "back")]));
        assert_eq!(none.closest_index(&[0.0, 0.0], &[]), None);
    }

    /// The pose errors as the scalar check computed them before the lanes (nalgebra's
    /// products, one tool pose at a time).
    fn scalar_errors(target: &IkTarget, t: &nalgebra::IsometryMatrix3<f64>) -> (f64, f64) {
        match target {
            IkTarget::Pose(pose) => {
                let r_inv = pose.rotation.to_rotation_matrix().inverse();
                let dp = (t.translation.vector - pose.translation.vector).norm();
                let m = (r_inv * t.rotation).into_inner();
                let vee = Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]);
                (dp, crate::angle::atan2(0.5 * vee.norm(), 0.5 * (m.trace() - 1.0)))
            }
            IkTarget::Position(p) => ((Point3::from(t.translation.vector) - p).norm(), 0.0),
        }
    }

    #[test]
    fn lane_verification_is_the_scalar_check_bit_for_bit() {
        // Every preset the lanes verify: the tool poses of `fk_lanes` and the errors of
        // `Check::errors` are those of `fk_matrix` and the scalar formula, bit for bit, so the
        // accepted solutions and their reported errors do not depend on the lanes.
        let mut rng = crate::rng::SplitMix64(16);
        for name in crate::model::presets::names() {
            let robot = crate::model::presets::get(name).unwrap();
            let dof = robot.dof();
            if dof > LANE_DOF {
                continue;
            }
            for _ in 0..8 {
                let qs: Vec<Vec<f64>> =
                    (0..VERIFY_LANES).map(|_| (0..dof).map(|_| (2.0 * rng.next_f64() - 1.0) * 4.0).collect()).collect();
                let mut lanes = [[0.0; VERIFY_LANES]; LANE_DOF];
                for (l, q) in qs.iter().enumerate() {
                    for (j, v) in q.iter().enumerate() {
                        lanes[j][l] = *v;
                    }
                }
                let t = robot.fk_lanes(&lanes[..dof]);
                let near = robot.fk(&qs[0]).unwrap();
                for target in [IkTarget::Pose(near), IkTarget::Position(near.translation.vector.into())] {
                    let check = Check::new(&target);
                    let (position, sin, cos) = check.errors(&t);
                    for (l, q) in qs.iter().enumerate() {
                        let scalar = robot.fk_matrix(q).unwrap();
                        let m = scalar.rotation.matrix();
                        for i in 0..3 {
                            assert_eq!(t.p[i][l].to_bits(), scalar.translation.vector[i].to_bits(), "{name} {q:?}");
                            for j in 0..3 {
                                assert_eq!(t.r[i][j][l].to_bits(), m[(i, j)].to_bits(), "{name} {q:?}");
                            }
                        }
                        // One lane alone (the kernel of a single candidate) gives the same bits.
                        let one: Vec<Lanes<1>> = q.iter().map(|v| [*v]).collect();
                        assert_eq!(robot.fk_lanes(&one).p[0][0].to_bits(), t.p[0][l].to_bits(), "{name} {q:?}");
                        let (p, o) = scalar_errors(&target, &scalar);
                        assert_eq!(position[l].to_bits(), p.to_bits(), "{name} {q:?}");
                        assert_eq!(
                            check.angles::<true, VERIFY_LANES>(&sin, &cos)[l].to_bits(),
                            o.to_bits(),
                            "{name} {q:?}"
                        );
                        assert_eq!(
                            check.angles::<false, VERIFY_LANES>(&sin, &cos)[l].to_bits(),
                            o.to_bits(),
                            "{name} {q:?}"
                        );
                    }
                }
            }
        }
    }

    /// The solves of `solver` for `target` at SIMD level `level`: that of `solve_into` at this
    /// level ([`solve_at`]), and both kernel variants ([`SolveKernel`], `WIDE` or not) run at it.
    fn solves_at<S: LaneSolve>(
        level: crate::simd::Level,
        solver: &S,
        robot: &Robot,
        target: &IkTarget,
    ) -> [IkSolutions; 3] {
        let options = super::super::IkOptions::default();
        let (mut chosen, mut wide, mut narrow) =
            (IkSolutions::default(), IkSolutions::default(), IkSolutions::default());
        solve_at(level, solver, robot, target, &options, &mut chosen).unwrap();
        crate::simd::run_at(level, SolveKernel::<S, true> { solver, robot, target, options: &options, out: &mut wide })
            .unwrap();
        crate::simd::run_at(
            level,
            SolveKernel::<S, false> { solver, robot, target, options: &options, out: &mut narrow },
        )
        .unwrap();
        [chosen, wide, narrow]
    }

    /// Every solve of [`solves_at`] at every level has the bits of `solve_into` at the
    /// baseline level.
    fn assert_same_bits_at_every_level<S: LaneSolve>(solver: &S, robot: &Robot, target: &IkTarget, what: &str) {
        let options = super::super::IkOptions::default();
        let mut base = IkSolutions::default();
        solve_at(crate::simd::Level::Baseline, solver, robot, target, &options, &mut base).unwrap();
        for level in crate::simd::levels() {
            for (variant, solved) in
                ["solve_into", "wide kernel", "narrow kernel"].iter().zip(solves_at(level, solver, robot, target))
            {
                assert_same_bits(&solved, &base, &format!("{what} at {}, {variant}", level.name()));
            }
        }
    }

    /// `a` and `b` with the same solutions, labels and flags, and the same bits in every
    /// joint value and error.
    fn assert_same_bits(a: &IkSolutions, b: &IkSolutions, what: &str) {
        assert_eq!(a, b, "{what}");
        for (x, y) in a.solutions.iter().zip(&b.solutions) {
            let bits = |s: &IkSolution| -> Vec<u64> {
                s.q.iter().chain([&s.position_error, &s.orientation_error]).map(|v| v.to_bits()).collect()
            };
            assert_eq!(bits(x), bits(y), "{what}");
        }
    }

    #[test]
    fn closed_form_solves_give_the_same_bits_at_every_simd_level() {
        use super::super::parallel_axes::ParallelAxes;
        use super::super::spherical_wrist::SphericalWrist;
        use super::super::two_link_wrist::TwoLinkWrist;
        let mut rng = crate::rng::SplitMix64(17);
        let mut solved_presets = 0;
        for name in crate::model::presets::names() {
            let robot = crate::model::presets::get(name).unwrap();
            if robot.dof() != 6 {
                continue;
            }
            let (sw, tw, pa) = (
                SphericalWrist::from_robot(&robot),
                TwoLinkWrist::from_robot(&robot),
                ParallelAxes::from_robot(&robot),
            );
            if sw.is_err() && tw.is_err() && pa.is_err() {
                continue;
            }
            solved_presets += 1;
            for k in 0..40 {
                let q: Vec<f64> = robot
                    .joints()
                    .iter()
                    .map(|j| {
                        let (lo, hi) = (j.limits.lower.max(-3.0), j.limits.upper.min(3.0));
                        lo + (hi - lo) * rng.next_f64()
                    })
                    .collect();
                // Generic poses, a wrist singularity (q5 = 0) and a position target.
                let mut q = q;
                if k == 0 {
                    q[4] = 0.0;
                }
                let pose = robot.fk(&q).unwrap();
                let targets = [IkTarget::Pose(pose), IkTarget::Position(pose.translation.vector.into())];
                for target in &targets {
                    let what = format!("{name} {q:?}");
                    if let Ok(s) = &sw {
                        assert_same_bits_at_every_level(s, &robot, target, &what);
                    }
                    if let Ok(s) = &tw {
                        assert_same_bits_at_every_level(s, &robot, target, &what);
                    }
                    if let Ok(s) = &pa {
                        assert_same_bits_at_every_level(s, &robot, target, &what);
                    }
                }
            }
        }
        assert!(solved_presets >= 4, "puma560, ur5, welder6r, spbu6 at least: {solved_presets}");
    }

    #[test]
    fn shared_prefix_walk_is_the_lane_walk_bit_for_bit() {
        // Pairs of lanes sharing their first k joints (as the two wrists of an arm share θ1…θ3):
        // `shared_prefix` finds k, and the walk of the prefix on 4 lanes gives the poses of the
        // plain 8-lane walk, bit for bit, for every preset and every k.
        let mut rng = crate::rng::SplitMix64(42);
        for name in crate::model::presets::names() {
            let robot = crate::model::presets::get(name).unwrap();
            let dof = robot.dof();
            if dof > LANE_DOF {
                continue;
            }
            for k in 0..=dof {
                let mut q = [[0.0; VERIFY_LANES]; LANE_DOF];
                for (j, joint) in q.iter_mut().enumerate().take(dof) {
                    for l in 0..VERIFY_LANES {
                        joint[l] = if j < k && l % 2 == 1 { joint[l - 1] } else { (2.0 * rng.next_f64() - 1.0) * 4.0 };
                    }
                }
                let finite = [true; VERIFY_LANES];
                let found = shared_prefix::<VERIFY_LANES, 4>(&robot, &mut q[..dof], &finite, VERIFY_LANES);
                let expected = if robot.prefix_without_mimics(k) { k } else { 0 };
                assert_eq!(found, expected, "{name} k = {k}");
                let prefix: Vec<Lanes<4>> = q[..k].iter().map(|j| std::array::from_fn(|g| j[2 * g])).collect();
                if !robot.prefix_without_mimics(k) {
                    continue;
                }
                let shared = robot.fk_lanes_shared(&prefix, &q[..dof]);
                let plain = robot.fk_lanes(&q[..dof]);
                for l in 0..VERIFY_LANES {
                    for i in 0..3 {
                        assert_eq!(shared.p[i][l].to_bits(), plain.p[i][l].to_bits(), "{name} k = {k}");
                        for j in 0..3 {
                            assert_eq!(shared.r[i][j][l].to_bits(), plain.r[i][j][l].to_bits(), "{name} k = {k}");
                        }
                    }
                }
            }
            // A lane not verified (beyond the count, or not finite) takes its partner's values
            // and does not part the pair.
            let mut q = [[0.0; VERIFY_LANES]; LANE_DOF];
            for joint in q.iter_mut().take(dof) {
                for l in 0..VERIFY_LANES {
                    joint[l] = if l % 2 == 1 { joint[l - 1] } else { rng.next_f64() };
                }
                joint[3] = 9.0;
                joint[7] = -9.0;
            }
            let mut finite = [true; VERIFY_LANES];
            finite[3] = false;
            let found = shared_prefix::<VERIFY_LANES, 4>(&robot, &mut q[..dof], &finite, 7);
            assert_eq!(found, if robot.prefix_without_mimics(dof) { dof } else { 0 }, "{name}");
        }
    }

    #[test]
    fn same_angle_is_the_wrapped_difference_test() {
        use std::f64::consts::{PI, TAU};
        let wrapped = |a: f64, b: f64| crate::angle::wrap(a - b).abs() < IK_DUPLICATE;
        let mut rng = crate::rng::SplitMix64(3);
        let e = IK_DUPLICATE;
        let mut pairs = vec![
            (PI, -PI),
            (PI - e, -PI),
            (PI - 0.5 * e, -PI + 0.25 * e),
            (0.0, TAU),
            (0.0, TAU - e),
            (1.0, 1.0 + PI),
            (-3.0, 3.0),
        ];
        for _ in 0..20_000 {
            let a = (2.0 * rng.next_f64() - 1.0) * 10.0;
            let k = [0.0, PI, TAU, -TAU, 2.0 * TAU][rng.below(5)];
            pairs.push((a, a + k + (2.0 * rng.next_f64() - 1.0) * 3.0 * e));
        }
        for (a, b) in pairs {
            assert_eq!(same_angle(a, b), wrapped(a, b), "{a} {b}");
        }
    }

    #[test]
    fn surely_distinct_claims_only_what_both_rules_prove() {
        // `surely_distinct` ⇒ different by the revolute rule and by the prismatic one, on the
        // boundaries (IK_DUPLICATE, π, 2π, NaN) and on random pairs near them; and it does
        // prove the usual cases (distinct branches, the two wrists about π apart).
        use std::f64::consts::{PI, TAU};
        let e = IK_DUPLICATE;
        let mut rng = crate::rng::SplitMix64(5);
        let mut pairs = vec![(0.0, e), (0.0, 0.5 * e), (PI, -PI), (0.0, PI), (0.0, TAU - e), (0.0, TAU - 2.0 * e)];
        pairs.extend([(0.0, TAU), (0.0, TAU + e), (1.0, f64::NAN), (0.0, f64::INFINITY), (PI - 0.5 * e, -PI)]);
        for _ in 0..20_000 {
            let a = (2.0 * rng.next_f64() - 1.0) * 10.0;
            let k = [0.0, PI, TAU, -TAU, 2.0 * TAU][rng.below(5)];
            pairs.push((a, a + k + (2.0 * rng.next_f64() - 1.0) * 3.0 * e));
        }
        let mut proved = 0;
        for (a, b) in pairs {
            if surely_distinct(a, b) {
                proved += 1;
                assert!(!same_angle(a, b), "revolute {a} {b}");
                assert!((a - b).abs() >= IK_DUPLICATE, "prismatic {a} {b}");
            }
        }
        assert!(proved > 5_000, "{proved}");
        assert!(surely_distinct(0.3, 0.3 + PI) && surely_distinct(0.3, 0.3 - PI + 1e-12) && surely_distinct(-2.0, 1.0));
        assert!(!surely_distinct(1.0, 1.0) && !surely_distinct(1.0, 1.0 + TAU) && !surely_distinct(1.0, f64::NAN));
    }

    #[test]
    fn flag_bits_report_the_kinds_in_the_fixed_order() {
        let all = FlagBits::default()
            .with(SingularityKind::Wrist, true)
            .with(SingularityKind::Jacobian, false)
            .with(SingularityKind::Shoulder, true);
        assert_eq!(all.iter().collect::<Vec<_>>(), [SingularityKind::Shoulder, SingularityKind::Wrist]);
        assert_eq!(all.first(), Some(SingularityKind::Shoulder));
        assert!(FlagBits::default().is_empty() && FlagBits::default().first().is_none());
    }
}
