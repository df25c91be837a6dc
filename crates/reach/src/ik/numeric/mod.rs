//! General numeric inverse kinematics for any serial chain: damped least squares
//! (Levenberg–Marquardt) with adaptive damping, joint limits inside the iteration, and
//! deterministic multiple starts.
//!
//! # Method
//!
//! The error of a configuration `q` against a pose target `(R*, p*)` is the 6-vector
//!
//! ```text
//! e(q) = [ p* − p(q) ;  log(R*·R(q)ᵀ) ]        (metres; rotation vector, radians)
//! ```
//!
//! in the world frame, so that to first order `e(q + δq) = e(q) − J(q)·δq` with the geometric
//! Jacobian `J` of [`Robot::jacobian_into`] (rows `vx vy vz ωx ωy ωz`). A position-only target
//! uses the three translational rows only. The position rows are divided by the chain's
//! length scale `L` (the sum of its link lengths) so that every row is dimensionless and a
//! 1 m arm and a 10 cm arm iterate alike.
//!
//! Each step solves the damped normal equations in task space (6×6, fixed size, Cholesky):
//!
//! ```text
//! δq = Jᵀ (J Jᵀ + λ I)⁻¹ e,      λ = μ · (E + w̄),   E = ½ eᵀe
//! ```
//!
//! which is the Levenberg–Marquardt step `(JᵀJ + λI)⁻¹Jᵀe` for any number of joints (push-through
//! identity) and the damped minimum-norm step for redundant arms. The damping follows
//! Sugihara (2011, "Solvability-unconcerned inverse kinematics by the Levenberg–Marquardt
//! method"): `λ` proportional to the current error plus a small floor `w̄`, so that the solver
//! takes cautious gradient-like steps far from the target and Gauss–Newton steps close to it;
//! the multiplier `μ` adapts as in a trust region (grown when a step does not reduce `E`, and
//! the step retried; shrunk after a successful step).
//!
//! **Joint limits** are enforced inside each step: a bounded joint whose step would leave its
//! range is moved exactly onto the limit and removed from the system, and the step is
//! recomputed for the remaining joints with the residual the fixed joint leaves
//! (an active-set projection; at most one pass per joint). Unbounded revolute joints are
//! wrapped into (−π, π] after every step.
//!
//! **Starts:** the first start is `options.seed` (moved into the limits), else the robot's home
//! configuration; the others are deterministic pseudo-random configurations inside the limits
//! (SplitMix64, fixed seed: the same problem always gives the same answer). Every start runs
//! to convergence or failure. **Re-seeding** ([`NumericOptions::reseed`], on by default): a
//! descent that ends in a local minimum before its start's iteration budget is spent continues
//! from a fresh pseudo-random configuration, within the same budget (as TRAC-IK's KDL loop
//! does). The failures of a single descent are local minima, not slow steps: on random
//! reachable poses from a random start, 12 % (UR5) to 50 % (Panda) of descents end at a
//! configuration with joints pinned at their limits or at a stretched elbow, and neither the
//! damping law (floor, growth and shrink factors) nor more iterations move these shares by more
//! than a point; spending the budget on new descents does (`examples/ik_protocol.rs`); the distinct converged configurations are returned, so a 6R arm
//! typically yields several of its (up to eight) branches and a redundant arm several points of
//! its self-motion.
//!
//! **Options** ([`NumericOptions`], the field `numeric` of [`IkOptions`]): which pose
//! components count ([`TaskAxes`]: full pose, position + approach axis (tool z, the roll about
//! it free), position only), the acceptance tolerances in metres and radians, a wall-time
//! budget, and the search mode ([`SearchMode`]): every distinct solution from all starts, or
//! the first converged one starting from the seed (the fast mode for tracking). The iteration
//! budget is `max_iterations` tried steps per start times `restarts` starts.
//!
//! **Stopping:** a start converges when the position error is below the position tolerance and
//! the orientation error below the orientation tolerance, both times 1e-3 (a step or two more
//! than needed; with the defaults 1e-9 m and 1e-9 rad, [`IK_NUMERIC_POSITION`]). It is
//! abandoned after `options.max_iterations` tried steps (a rejected step counts), when the
//! damping multiplier exceeds 1e8 (no descent direction), when the time budget is spent, or
//! after 4 consecutive steps that each reduce `E` by less than 1e-3 of its value (a local
//! minimum; for an under-actuated arm, the least-squares optimum). An abandoned start whose
//! errors are within the tolerances still counts as converged.
//!
//! **Failure reasons:** `Unreachable` when the target is farther from the first joint axis
//! than the sum of the link lengths (a cheap upper bound on the reach); for a pose target of
//! an under-actuated arm (n < 6) that no start reaches, `OrientationUnreachable` when a
//! position-only solve converges; otherwise `NoConvergence` with the iterations spent over
//! all starts and the best residual (`position error + orientation error`, metres + radians).
//!
//! **Branches:** each solution is labelled with the start that found it and the signs of its
//! joint values, e.g. `start=random-3 signs=+-+--+`; solutions closer than
//! [`IK_NUMERIC_DISTINCT`] in every joint are one. A solution whose Jacobian (the rows the
//! target uses) has `σ_min ≤` [`IK_NUMERIC_SINGULAR`]`·σ_max` is flagged
//! [`SingularityKind::Jacobian`].
//!
//! **Cost:** no allocation inside the iteration (buffers are allocated once per solve); one
//! forward kinematics per tried step and one Jacobian per accepted step.

mod descent;
mod goal;
mod starts;
#[cfg(test)]
mod tests;

use std::time::{Duration, Instant};

use nalgebra::{DMatrix, Vector3};

use self::descent::{Criteria, Work};
use self::goal::Goal;
pub(crate) use self::goal::rotation_log;
use self::starts::{Start, Starts, label, same_configuration};
use super::solution::finish_within;
use super::{Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind};
use crate::kinematics::check_q;
use crate::model::{JointKind, Robot};
use crate::tolerance::{BOUNDARY, IK_NUMERIC_POSITION, IK_NUMERIC_SINGULAR, IK_ORIENTATION, IK_POSITION};

/// The iteration stops at this fraction of the acceptance tolerances (1e-3: the ratio of
/// [`IK_NUMERIC_POSITION`] to [`IK_POSITION`]); near a regular solution the convergence is
/// about quadratic, so the extra digits cost about one iteration and no accepted solution sits
/// on the edge of the tolerance.
const STOP_FRACTION: f64 = IK_NUMERIC_POSITION / IK_POSITION;

/// Which components of the tool pose the numeric solver matches.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum TaskAxes {
    /// Position and full orientation (6 equations). A position target
    /// ([`IkTarget::Position`]) always uses [`TaskAxes::Position`].
    #[default]
    Pose,
    /// Position and the direction of the tool z axis (the approach axis, 5 equations); the
    /// roll about that axis is free (e.g. a drill or a welding torch). The reported
    /// `orientation_error` is then the angle between the tool's and the target's z axes.
    PositionApproach,
    /// Position only (3 equations); `orientation_error` is reported as 0.
    Position,
}

/// How many solutions the numeric solver looks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum SearchMode {
    /// Run every start and return every distinct converged configuration (several branches
    /// of a 6R arm, several points of a redundant arm's self-motion).
    #[default]
    AllDistinct,
    /// Start from the seed (or home) and stop at the first start that converges: from a seed
    /// near a solution this is the solution closest to the seed. The fast mode for tracking.
    FirstFound,
}

/// Largest iteration budget (`restarts × max_iterations` tried steps) of one solve without a
/// wall-time budget: a few seconds of work for a 7-joint arm. A request asking for more
/// without a time budget is refused before the solve (the job layer's
/// `numeric.restarts`); with a time budget the budget ends the solve.
pub const MAX_UNTIMED_ITERATIONS: usize = 1_000_000;

/// Options of the numeric solver only (the field [`IkOptions::numeric`]); the iteration budget
/// per start and the number of starts are [`IkOptions::max_iterations`] and
/// [`IkOptions::restarts`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NumericOptions {
    /// Which pose components to match. Default [`TaskAxes::Pose`].
    pub axes: TaskAxes,
    /// Largest accepted position error, metres (> 0). Default [`IK_POSITION`] (1e-6 m).
    pub position_tolerance: f64,
    /// Largest accepted orientation error, radians (> 0). Default [`IK_ORIENTATION`] (1e-6 rad).
    pub orientation_tolerance: f64,
    /// Wall-time budget of one solve, checked before every step (the solve may overrun it by
    /// one step). `None`: no limit. Default `None`.
    pub time_budget: Option<Duration>,
    /// All distinct solutions or the first found. Default [`SearchMode::AllDistinct`].
    pub mode: SearchMode,
    /// Whether a start whose descent ends in a local minimum spends the rest of its iteration
    /// budget on descents from fresh pseudo-random configurations (TRAC-IK's KDL loop does the
    /// same). Default `true`; path tracking turns it off so that a seeded solve stays near
    /// its seed or fails.
    pub reseed: bool,
}

impl Default for NumericOptions {
    fn default() -> Self {
        NumericOptions {
            axes: TaskAxes::Pose,
            position_tolerance: IK_POSITION,
            orientation_tolerance: IK_ORIENTATION,
            time_budget: None,
            mode: SearchMode::AllDistinct,
            reseed: true,
        }
    }
}

impl NumericOptions {
    /// Rejects tolerances that are not finite and positive.
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] naming the field.
    pub fn validate(&self) -> Result<(), IkError> {
        for (name, v) in [
            ("numeric.position_tolerance", self.position_tolerance),
            ("numeric.orientation_tolerance", self.orientation_tolerance),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(IkError::InvalidInput(format!("options.{name} must be a finite number > 0, got {v}")));
            }
        }
        Ok(())
    }
}

/// General numeric IK solver (damped least squares with adaptive damping and multiple starts)
/// for any serial chain: any number of joints, revolute or prismatic, DH, MDH or URDF.
///
/// Handles full-pose, position + approach-axis and position-only targets, redundant arms
/// (n > 6, e.g. `panda`) and under-actuated arms (n < 6: the pose error is minimised in least
/// squares; a target whose position is reachable but whose orientation is not is reported as
/// [`IkFailure::OrientationUnreachable`]). See the [module documentation](self) for the method.
///
/// # Example
/// ```
/// use reach::ik::{IkOptions, IkSolver, IkTarget, numeric::Numeric};
/// let panda = reach::model::presets::get("panda").unwrap();
/// let q = [0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.5];
/// let target = IkTarget::Pose(panda.fk(&q).unwrap());
/// let solver = Numeric::from_robot(&panda).unwrap();
/// let all = solver.solve(&panda, &target, &IkOptions::default()).unwrap();
/// assert!(all.failure.is_none());
/// assert!(all.feasible().all(|s| s.position_error < 1e-6 && s.orientation_error < 1e-6));
/// ```
#[derive(Debug, Clone)]
pub struct Numeric {
    dof: usize,
    /// World position of a point on the first joint axis (the chain's first motion frame).
    anchor: Vector3<f64>,
    /// Upper bound on the distance from `anchor` to the tool point (may be infinite).
    reach: f64,
    /// Length scale dividing the position rows (metres, > 0).
    length_scale: f64,
}

impl Numeric {
    /// Prepares the solver for `robot`. Always succeeds: any valid chain fits.
    ///
    /// Computes the reach bound: the sum, over the joints, of the distance between consecutive
    /// joint-axis reference points (constant under rotation of a revolute joint) plus, for a
    /// prismatic joint, its largest travel, and the tool offset.
    ///
    /// # Errors
    /// None at present; the `Result` matches the other solvers' constructors.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let mut reach = 0.0;
        let mut fixed = 0.0;
        for (link, joint) in robot.chain.links.iter().zip(robot.joints()) {
            let offset = link.after.translation.vector.norm();
            fixed += offset;
            reach += offset;
            if joint.kind == JointKind::Prismatic {
                reach += joint.limits.lower.abs().max(joint.limits.upper.abs());
            }
        }
        // Mimic joints: their constant offsets, and a prismatic one's travel bounded through
        // its master's limits.
        for m in robot.chain.first_mimics.iter().chain(robot.chain.links.iter().flat_map(|l| &l.mimics)) {
            let offset = m.after.translation.vector.norm();
            fixed += offset;
            reach += offset;
            if m.prismatic {
                let master = robot.joints()[m.master].limits;
                reach += m.multiplier.abs() * master.lower.abs().max(master.upper.abs()) + m.offset.abs();
            }
        }
        let length_scale = if reach.is_finite() && reach > 1e-6 {
            reach
        } else if fixed > 1e-6 {
            fixed
        } else {
            1.0
        };
        Ok(Numeric { dof: robot.dof(), anchor: robot.chain.first.translation.vector, reach, length_scale })
    }

    /// Upper bound on the distance (metres) from the first joint axis's reference point to the
    /// tool point over all configurations (infinite when a prismatic joint is unbounded).
    #[must_use]
    pub fn reach_bound(&self) -> f64 {
        self.reach
    }
}

impl IkSolver for Numeric {
    fn name(&self) -> &'static str {
        "numeric"
    }

    /// The distinct solutions found from the seed (or home) and the pseudo-random starts, or
    /// the first one ([`SearchMode::FirstFound`]).
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] for a non-finite target, a robot with another number of joints
    /// than the one the solver was built for, `max_iterations` / `restarts` equal to 0 or a
    /// tolerance that is not finite and positive; [`IkError::Kinematics`] for a seed of the
    /// wrong length or with non-finite values.
    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
        target.validate()?;
        if robot.dof() != self.dof {
            return Err(IkError::InvalidInput(format!(
                "numeric solver was built for {} joints, robot `{}` has {}",
                self.dof,
                robot.name(),
                robot.dof()
            )));
        }
        if options.max_iterations == 0 {
            return Err(IkError::InvalidInput("options.max_iterations must be at least 1, got 0".into()));
        }
        if options.restarts == 0 {
            return Err(IkError::InvalidInput("options.restarts must be at least 1, got 0".into()));
        }
        let opts = &options.numeric;
        opts.validate()?;
        if let Some(seed) = &options.seed {
            check_q(robot.dof(), seed)?;
        }
        let started = Instant::now();
        let criteria = Criteria {
            stop_position: opts.position_tolerance * STOP_FRACTION,
            stop_orientation: opts.orientation_tolerance * STOP_FRACTION,
            accept_position: opts.position_tolerance,
            accept_orientation: opts.orientation_tolerance,
            deadline: opts.time_budget.and_then(|b| started.checked_add(b)),
            cancel: options.cancel.clone(),
        };
        let axes = match target {
            IkTarget::Position(_) => TaskAxes::Position,
            IkTarget::Pose(_) => opts.axes,
        };

        let distance = (target.position().coords - self.anchor).norm();
        if distance > self.reach * (1.0 + BOUNDARY) + opts.position_tolerance {
            let failure = IkFailure::Unreachable {
                distance,
                reach: self.reach,
                point: "the tool point",
                from: "joint 1's origin",
            };
            return finish_within(robot, target, &mut [], self.name(), failure, criteria.acceptance());
        }

        let goal = Goal::new(target, axes, self.length_scale);
        let mut work = Work::new(robot, self.length_scale);
        let mut starts = Starts::new(robot, options.seed.as_deref(), self.length_scale);
        let mut found: Vec<(Vec<f64>, Start)> = Vec::new();
        let mut iterations = 0;
        let mut best_residual = f64::INFINITY;
        let mut timed_out = false;
        for k in 0..options.restarts {
            let start = starts.next_into(k, &mut work.q);
            let run = work.descend(robot, &goal, options.max_iterations, &criteria, opts.reseed)?;
            iterations += run.iterations;
            best_residual = best_residual.min(run.position_error + run.orientation_error);
            if run.converged && !found.iter().any(|(q, _)| same_configuration(robot, q, &work.q)) {
                found.push((work.q.clone(), start));
            }
            timed_out = run.timed_out;
            if timed_out || (opts.mode == SearchMode::FirstFound && !found.is_empty()) {
                break;
            }
        }

        let mut candidates = Vec::with_capacity(found.len());
        for (q, start) in found {
            let branch = label(robot, &q, start);
            let mut c = Candidate::new(q, branch);
            if is_singular(robot, &c.q, axes, &mut work)? {
                c.singularities.push(SingularityKind::Jacobian);
            }
            candidates.push(c);
        }

        // Only an under-actuated arm has orientations it cannot reach at a reachable position
        // in general; for n ≥ 6 a failed pose solve is reported as what it is, no convergence.
        let failure = if candidates.is_empty()
            && !timed_out
            && axes != TaskAxes::Position
            && self.dof < 6
            && self.position_reachable(robot, target, options, &criteria, &mut work)?
        {
            IkFailure::OrientationUnreachable
        } else {
            IkFailure::NoConvergence { iterations, residual: best_residual }
        };
        match axes {
            TaskAxes::Pose => {
                finish_within(robot, target, &mut candidates, self.name(), failure, criteria.acceptance())
            }
            TaskAxes::Position => {
                let target = IkTarget::Position(target.position());
                finish_within(robot, &target, &mut candidates, self.name(), failure, criteria.acceptance())
            }
            TaskAxes::PositionApproach => {
                // `finish` checks the position; the approach axis is checked here.
                let mut approach_errors = Vec::with_capacity(candidates.len());
                for c in &candidates {
                    let (_, _, angle) = goal.error(&robot.fk_matrix(&c.q)?);
                    approach_errors.push((c.q.clone(), angle));
                }
                let mut kept: Vec<Candidate> = candidates
                    .into_iter()
                    .zip(&approach_errors)
                    .filter(|(_, (_, angle))| *angle <= criteria.accept_orientation)
                    .map(|(c, _)| c)
                    .collect();
                let position = IkTarget::Position(target.position());
                let mut out = finish_within(robot, &position, &mut kept, self.name(), failure, criteria.acceptance())?;
                for s in &mut out.solutions {
                    // `finish` may have moved revolute angles by whole turns: same pose.
                    s.orientation_error = approach_errors
                        .iter()
                        .find(|(q, _)| same_configuration(robot, q, &s.q))
                        .map_or(goal.error(&robot.fk_matrix(&s.q)?).2, |(_, a)| *a);
                }
                Ok(out)
            }
        }
    }

    /// One configuration, any solution: the labels name the start that found a solution, not
    /// a geometric branch, so a path is followed by nearness to the previous joint vector.
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        vec![Branch::default()]
    }

    /// `false`: a search finds some of the solutions, labelled by their start.
    fn enumerates_all_branches(&self) -> bool {
        false
    }
}

impl Numeric {
    /// Whether the position of a pose target is reachable: a position-only solve converges from
    /// one of the same starts.
    fn position_reachable(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &IkOptions,
        criteria: &Criteria,
        work: &mut Work,
    ) -> Result<bool, IkError> {
        let goal = Goal::new(target, TaskAxes::Position, self.length_scale);
        let mut starts = Starts::new(robot, options.seed.as_deref(), self.length_scale);
        for k in 0..options.restarts {
            starts.next_into(k, &mut work.q);
            let run = work.descend(robot, &goal, options.max_iterations, criteria, options.numeric.reseed)?;
            if run.converged {
                return Ok(true);
            }
            if run.timed_out {
                break;
            }
        }
        Ok(false)
    }
}

/// Whether the rows of the Jacobian that `axes` uses have `σ_min ≤ IK_NUMERIC_SINGULAR·σ_max`
/// at `q` (position rows; plus the two rotation rows across the approach axis, or all three).
fn is_singular(robot: &Robot, q: &[f64], axes: TaskAxes, work: &mut Work) -> Result<bool, IkError> {
    robot.jacobian_into(q, &mut work.jac)?;
    let jac = &work.jac;
    let n = jac.ncols();
    let rows = match axes {
        TaskAxes::Pose => DMatrix::from_fn(6, n, |r, c| jac[(r, c)]),
        TaskAxes::Position => DMatrix::from_fn(3, n, |r, c| jac[(r, c)]),
        TaskAxes::PositionApproach => {
            let t = robot.fk_matrix(q)?;
            let m = t.rotation.matrix();
            let (u, v) = (m.column(0).into_owned(), m.column(1).into_owned());
            DMatrix::from_fn(5, n, |r, c| {
                let w = Vector3::new(jac[(3, c)], jac[(4, c)], jac[(5, c)]);
                match r {
                    0..=2 => jac[(r, c)],
                    3 => u.dot(&w),
                    _ => v.dot(&w),
                }
            })
        }
    };
    let sv = rows.singular_values();
    let k = rows.nrows().min(n);
    let mut sorted: Vec<f64> = sv.iter().copied().collect();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let sigma_max = sorted.first().copied().unwrap_or(0.0);
    let sigma_min = sorted.get(k.saturating_sub(1)).copied().unwrap_or(0.0);
    Ok(sigma_min <= IK_NUMERIC_SINGULAR * sigma_max)
}
