//! The one solution type shared by every IK solver.

mod candidate;
mod chain_frame;
mod check;
#[cfg(test)]
mod tests;

pub(crate) use candidate::{Candidate, CandidateList, FlagBits, JointValues, Raw6, Raw6Set, fit_revolute};
pub(crate) use chain_frame::ChainFrame;
pub(crate) use check::{LaneSolve, finish, finish_into, finish_within, solve_at, solved};

use std::borrow::Cow;
use std::fmt;
use std::sync::Arc;

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::model::{JointKind, Robot};
use crate::tolerance::LIMIT_SLACK;

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
    /// The target position is outside the workspace: `distance` is the distance of `point`
    /// (the target, the wrist centre it implies, …) from `from` (a joint, its axis, the arm's
    /// plane), `reach` the bound it violates: the outer one when `distance > reach` (too far),
    /// the inner one otherwise (too close).
    Unreachable {
        /// Distance of `point` from `from` (metres).
        distance: f64,
        /// The violated bound (metres).
        reach: f64,
        /// What is measured: `the target`, `the wrist centre`, ….
        point: &'static str,
        /// From where: `joint 2`, `joint 1's axis`, `the arm's plane`, ….
        from: &'static str,
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
            IkFailure::Unreachable { distance, reach, point, from } if distance > reach => write!(
                f,
                "target out of reach (too far): {point} is {distance:.6} m from {from}, beyond the outer workspace bound {reach:.6} m"
            ),
            IkFailure::Unreachable { distance, reach, point, from } => write!(
                f,
                "target out of reach (too close): {point} is {distance:.6} m from {from}, inside the inner workspace bound {reach:.6} m"
            ),
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
