//! Following one configuration from sample to sample: the anchor solution, the lock on its
//! branch, the nearest solution of the same branch at the next sample (unwrapped to it), and
//! the wrap-safe rates of the steps.

use nalgebra::{Isometry3, Point3};
use serde::Serialize;

use super::TrackingError;
use super::path::validate_samples;
use crate::angle::{nearest_equivalent, wrap};
use crate::ik::{Branch, IkError, IkOptions, IkSolutions, IkSolver, IkTarget};
use crate::model::{JointKind, Robot};
use crate::motion::sample::PathSample;
use crate::tolerance::{IK_ORIENTATION, IK_POSITION};

/// Whether `label` carries every pair of `filter`.
pub(super) fn matches(label: &Branch, filter: &Branch) -> bool {
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
pub(super) fn unwrap_to(robot: &Robot, q: &[f64], reference: &[f64]) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .zip(q.iter().zip(reference))
        .map(|(j, (v, r))| if j.kind == JointKind::Revolute { nearest_equivalent(*v, *r) } else { *v })
        .collect()
}

/// How a followed configuration is recognised at the next sample.
#[derive(Debug, Clone)]
pub(super) enum Lock {
    /// The full label of the anchor solution (a solver whose labels name branches,
    /// [`IkSolver::enumerates_all_branches`]).
    Label(Branch),
    /// The configuration's filter only (any other solver: the nearest solution is followed).
    Filter(Branch),
}

/// The solver and the way targets are built.
pub(super) struct Solving<'a> {
    pub(super) robot: &'a Robot,
    pub(super) solver: Box<dyn IkSolver>,
    pub(super) position_only: bool,
}

/// The IK target of a path pose: the position only, or the whole pose.
pub(super) fn ik_target(pose: &Isometry3<f64>, position_only: bool) -> IkTarget {
    if position_only { IkTarget::Position(Point3::from(pose.translation.vector)) } else { IkTarget::Pose(*pose) }
}

/// The IK options of one tracking solve: seeded from `seed` when given; a seeded solve of a
/// solver that does not enumerate every branch (`by_label` false: a search) makes one start
/// only and does not re-seed — it follows the seed instead of searching afresh.
pub(super) fn seeded_options(by_label: bool, seed: Option<&[f64]>) -> IkOptions {
    let mut options = IkOptions { seed: seed.map(<[f64]>::to_vec), ..IkOptions::default() };
    if !by_label && seed.is_some() {
        options.restarts = 1;
        options.numeric.reseed = false;
    }
    options
}

impl Solving<'_> {
    fn target(&self, pose: &Isometry3<f64>) -> IkTarget {
        ik_target(pose, self.position_only)
    }

    /// Whether configurations are followed by their full labels
    /// ([`IkSolver::enumerates_all_branches`]).
    pub(super) fn by_label(&self) -> bool {
        self.solver.enumerates_all_branches()
    }

    fn options(&self, seed: Option<&[f64]>) -> IkOptions {
        seeded_options(self.by_label(), seed)
    }

    pub(super) fn solve(&self, pose: &Isometry3<f64>, seed: Option<&[f64]>) -> Result<IkSolutions, TrackingError> {
        Ok(self.solver.solve(self.robot, &self.target(pose), &self.options(seed))?)
    }

    /// The locked branch at `pose`, seeded with and next to `reference` ([`follow`]).
    pub(super) fn follow(
        &self,
        pose: &Isometry3<f64>,
        lock: &Lock,
        reference: &[f64],
    ) -> Result<Option<Vec<f64>>, TrackingError> {
        let options = self.options(Some(reference));
        Ok(follow(self.robot, self.solver.as_ref(), &self.target(pose), lock, reference, &options)?)
    }
}

/// Where the arm is at the path's first sample ([`super::TrackingOptions::start`]): the
/// configuration it is in and the lock on its branch. The first interval is followed from it.
#[derive(Debug, Clone)]
pub(super) struct Start {
    /// Index into the tracked configurations.
    pub(super) configuration: usize,
    /// The joint vector itself (SI), the first point of the trajectory.
    pub(super) q: Vec<f64>,
    /// Its branch: the label of the solution it is (a solver whose labels name branches), else
    /// the configuration's filter.
    pub(super) lock: Lock,
}

impl Solving<'_> {
    /// The [`Start`] of joint vector `q` at `pose` (the path's first pose): `q` must have the
    /// robot's joint count, be finite, and put the tool at `pose` within the IK tolerances
    /// ([`IK_POSITION`], [`IK_ORIENTATION`]; the position only when tracking positions). Its
    /// branch is that of the solution nearest to it (the solver seeded with it), and its
    /// configuration the first of `configurations` whose filter that label carries; when none
    /// does, that label is appended as a configuration if `extend` (the solver's default list,
    /// e.g. seed 003's two of the UR5's eight), else it is an error (the caller's list).
    pub(super) fn start(
        &self,
        q: &[f64],
        pose: &Isometry3<f64>,
        configurations: &mut Vec<Branch>,
        extend: bool,
    ) -> Result<Start, TrackingError> {
        let invalid = |reason: String| TrackingError::InvalidOption { option: "start", reason };
        let dof = self.robot.dof();
        if q.len() != dof {
            return Err(invalid(format!("{} joint values for a robot with {dof} joints", q.len())));
        }
        if let Some(j) = q.iter().position(|v| !v.is_finite()) {
            return Err(invalid(format!("joint {} must be finite", j + 1)));
        }
        let at = self.robot.fk(q).map_err(|e| invalid(e.to_string()))?;
        let off = (at.translation.vector - pose.translation.vector).norm();
        let turned = at.rotation.angle_to(&pose.rotation);
        if off > IK_POSITION || (!self.position_only && turned > IK_ORIENTATION) {
            return Err(invalid(format!(
                "the joint vector puts the tool {off:.3e} m and {turned:.3e} rad from the path's first pose"
            )));
        }
        let sols = self.solve(pose, Some(q))?;
        let nearest = sols
            .solutions
            .iter()
            .min_by(|a, b| distance(self.robot, &a.q, q).total_cmp(&distance(self.robot, &b.q, q)))
            .ok_or_else(|| invalid("the solver finds no solution at the path's first pose".into()))?;
        let found = configurations.iter().position(|c| matches(&nearest.branch, c));
        let configuration = match found {
            Some(c) => c,
            None if extend => {
                configurations.push(nearest.branch.clone());
                configurations.len() - 1
            }
            None => {
                let listed: Vec<String> = configurations.iter().map(|c| format!("`{c}`")).collect();
                return Err(invalid(format!(
                    "the joint vector is in configuration `{}`, not among the tracked ones ({})",
                    nearest.branch,
                    listed.join(", ")
                )));
            }
        };
        let lock = if self.by_label() {
            Lock::Label(nearest.branch.clone())
        } else {
            Lock::Filter(configurations[configuration].clone())
        };
        Ok(Start { configuration, q: q.to_vec(), lock })
    }
}

/// The anchor: the solution of `filter` to follow (non-singular first, then within limits,
/// then the solver's order), and the lock it defines (its full label when `by_label`, else the
/// filter).
pub(super) fn anchor(sols: &IkSolutions, filter: &Branch, by_label: bool) -> Option<(Vec<f64>, Lock)> {
    let best = sols
        .solutions
        .iter()
        .filter(|s| matches(&s.branch, filter))
        .min_by_key(|s| (!s.singularities.is_empty(), !s.within_limits))?;
    let lock = if by_label { Lock::Label(best.branch.clone()) } else { Lock::Filter(filter.clone()) };
    Some((best.q.clone(), lock))
}

/// The solution of the locked branch nearest to `reference`, unwrapped next to it; at a
/// singular position, where branches merge, the nearest solution flagged singular.
pub(super) fn pick(robot: &Robot, sols: &IkSolutions, lock: &Lock, reference: &[f64]) -> Option<Vec<f64>> {
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

/// [`pick`] on the solutions at `target`: for a label lock only the locked
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
    let by_label = solver.enumerates_all_branches();
    let mut out = BranchTrack { branch: None, q: Vec::with_capacity(samples.len()) };
    let mut lock: Option<Lock> = None;
    let mut previous: Option<Vec<f64>> = None;
    let target = |pose: &Isometry3<f64>| ik_target(pose, position_only);
    for p in samples {
        let options = seeded_options(by_label, previous.as_deref());
        let q = match (&lock, &previous) {
            (Some(l), Some(prev)) => follow(robot, solver, &target(&p.pose), l, prev, &options)?,
            _ => anchor(&solver.solve(robot, &target(&p.pose), &options)?, filter, by_label).map(|(q, l)| {
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
/// // A bounded joint from +179° to −179° turns 358° (the one rule, `Joint::difference`).
/// let q = vec![vec![d, 0.0, 0.0], vec![-d, 0.0, 0.0]];
/// let r = step_rates(&robot, &[0.0, 1.0], &q).unwrap();
/// approx::assert_relative_eq!(r[0][0], -358f64.to_radians(), epsilon = 1e-12);
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
                .map(|(j, (a, b))| j.difference(*a, *b) / dt)
                .collect(),
        );
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_match_subsets_of_labels() {
        let label = Branch::new([("a", "1"), ("b", "2"), ("c", "3")]);
        assert!(matches(&label, &Branch::new([("b", "2")])));
        assert!(matches(&label, &Branch::new([("c", "3"), ("a", "1")])));
        assert!(matches(&label, &Branch::default()));
        assert!(!matches(&label, &Branch::new([("b", "1")])));
        assert!(!matches(&label, &Branch::new([("d", "2")])));
    }
}
