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

use std::time::{Duration, Instant};

use nalgebra::{DMatrix, IsometryMatrix3, Matrix3, Matrix6, Vector3, Vector6};

use super::solution::finish_within;
use super::{Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind};
use crate::angle::{fit_into_limits, wrap};
use crate::kinematics::{Jacobian, check_q};
use crate::model::{JointKind, Robot};
use crate::rng::SplitMix64;
use crate::tolerance::{
    BOUNDARY, IK_NUMERIC_DISTINCT, IK_NUMERIC_POSITION, IK_NUMERIC_SINGULAR, IK_ORIENTATION, IK_POSITION, LIMIT_SLACK,
};

/// Damping floor `w̄` of Sugihara's `λ = E + w̄` (dimensionless rows). Sugihara recommends
/// 1e-3 for unit-scale arms; it keeps `J Jᵀ + λ I` well conditioned at singular configurations
/// while costing little speed near regular solutions (rate `λ / (σ² + λ)`).
const DAMPING_FLOOR: f64 = 1e-3;
/// Bounds of the adaptive damping multiplier `μ`.
const MU_MIN: f64 = 1e-6;
const MU_MAX: f64 = 1e8;
/// Factor applied to `μ` after a rejected (grow) or accepted (shrink) step.
const MU_GROW: f64 = 8.0;
const MU_SHRINK: f64 = 0.5;
/// A start is abandoned after this many consecutive accepted steps that each reduce `E` by
/// less than `STALL_RELATIVE` of its value (a local minimum or a least-squares optimum).
/// (Measured on the random-start protocol: 4 steps below 1e-3 abandon a local minimum early
/// enough that the start's remaining budget finds a solution from a fresh configuration.)
const STALL_STEPS: usize = 4;

const STALL_RELATIVE: f64 = 1e-3;
/// Fixed seed of the start generator: the same problem always gets the same starts.
const START_SEED: u64 = 0x5EED_1C0D_2024_0001;
/// Fixed seed of the re-seeding generator (fresh configurations after a local minimum).
const RESEED_SEED: u64 = 0x5EED_1C0D_2024_0002;
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
            let failure = IkFailure::Unreachable { distance, reach: self.reach };
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

/// When a descent stops and what it accepts.
struct Criteria {
    stop_position: f64,
    stop_orientation: f64,
    accept_position: f64,
    accept_orientation: f64,
    deadline: Option<Instant>,
    /// Set: stop as if the deadline had passed.
    cancel: crate::Cancel,
}

impl Criteria {
    fn acceptance(&self) -> (f64, f64) {
        (self.accept_position, self.accept_orientation)
    }
}

/// The orientation part of a goal.
enum Orientation {
    /// Position only.
    None,
    /// The full target rotation matrix.
    Full(Matrix3<f64>),
    /// The target's z axis (approach direction).
    Approach(Vector3<f64>),
}

/// The target in the form the iteration uses.
struct Goal {
    position: Vector3<f64>,
    orientation: Orientation,
    /// `1/L`: weight of the position rows.
    scale: f64,
}

impl Goal {
    fn new(target: &IkTarget, axes: TaskAxes, length_scale: f64) -> Goal {
        let scale = 1.0 / length_scale;
        let position = target.position().coords;
        let orientation = match (target, axes) {
            (IkTarget::Position(_), _) | (_, TaskAxes::Position) => Orientation::None,
            (IkTarget::Pose(pose), TaskAxes::Pose) => Orientation::Full(*pose.rotation.to_rotation_matrix().matrix()),
            (IkTarget::Pose(pose), TaskAxes::PositionApproach) => {
                Orientation::Approach(pose.rotation.to_rotation_matrix().matrix().column(2).into_owned())
            }
        };
        Goal { position, orientation, scale }
    }

    /// Weighted error vector, position error (m) and orientation error (rad) of the pose `t`.
    #[inline]
    fn error(&self, t: &IsometryMatrix3<f64>) -> (Vector6<f64>, f64, f64) {
        let dp = self.position - t.translation.vector;
        let (w, angle) = match &self.orientation {
            Orientation::Full(r) => rotation_log(&(r * t.rotation.matrix().transpose())),
            Orientation::Approach(z) => tilt(t.rotation.matrix(), z),
            Orientation::None => (Vector3::zeros(), 0.0),
        };
        let s = self.scale;
        (Vector6::new(dp.x * s, dp.y * s, dp.z * s, w.x, w.y, w.z), dp.norm(), angle)
    }

    /// Turns the geometric Jacobian at the pose `t` into the Jacobian of [`Goal::error`]
    /// (up to sign): position rows scaled by `1/L`; rotation rows kept (full pose), projected
    /// across the current approach axis (approach), or zeroed (position only).
    #[inline]
    fn weigh(&self, jac: &mut Jacobian, t: &IsometryMatrix3<f64>) {
        for r in 0..3 {
            jac.row_mut(r).scale_mut(self.scale);
        }
        match &self.orientation {
            Orientation::Full(_) => {}
            Orientation::None => {
                for r in 3..6 {
                    jac.row_mut(r).fill(0.0);
                }
            }
            Orientation::Approach(_) => {
                // Only rotations across the current z axis tilt it: ω ↦ (I − z zᵀ) ω.
                let z: Vector3<f64> = t.rotation.matrix().column(2).into_owned();
                for c in 0..jac.ncols() {
                    let w = Vector3::new(jac[(3, c)], jac[(4, c)], jac[(5, c)]);
                    let p = w - z * z.dot(&w);
                    jac[(3, c)] = p.x;
                    jac[(4, c)] = p.y;
                    jac[(5, c)] = p.z;
                }
            }
        }
    }
}

/// Rotation vector (across the current z axis) that turns the z axis of `r` onto `target_z`,
/// and its angle.
fn tilt(r: &Matrix3<f64>, target_z: &Vector3<f64>) -> (Vector3<f64>, f64) {
    let z = r.column(2).into_owned();
    let cross = z.cross(target_z);
    let sin = cross.norm();
    let angle = sin.atan2(z.dot(target_z));
    if angle < 1e-6 {
        // θ / sin θ = 1 + θ²/6 + …
        return (cross * (1.0 + angle * angle / 6.0), angle);
    }
    if sin > 1e-12 {
        return (cross * (angle / sin), angle);
    }
    // Opposite axes: any axis across z will do; take the current x axis.
    (r.column(0).into_owned() * angle, angle)
}

/// Rotation vector (axis · angle, angle in [0, π]) of a rotation matrix, and the angle;
/// accurate near 0 and near π.
pub(crate) fn rotation_log(r: &Matrix3<f64>) -> (Vector3<f64>, f64) {
    let cos = ((r.trace() - 1.0) * 0.5).clamp(-1.0, 1.0);
    // vee(R − Rᵀ) = 2 sin θ · axis
    let vee = Vector3::new(r[(2, 1)] - r[(1, 2)], r[(0, 2)] - r[(2, 0)], r[(1, 0)] - r[(0, 1)]);
    let sin = 0.5 * vee.norm();
    let angle = sin.atan2(cos);
    if cos > -0.5 {
        // θ < 120°: θ / (2 sin θ) is well conditioned (series near 0).
        let k = if angle < 1e-6 { 0.5 + angle * angle / 12.0 } else { 0.5 * angle / sin };
        return (vee * k, angle);
    }
    // Near π the antisymmetric part vanishes; take the axis from the symmetric part
    // (R + Rᵀ)/2 − cos θ·I = (1 − cos θ)·axis·axisᵀ, column of the largest diagonal entry.
    let b = (r + r.transpose()) * 0.5 - Matrix3::identity() * cos;
    let i = (0..3).max_by(|&a, &c| b[(a, a)].total_cmp(&b[(c, c)])).unwrap_or(0);
    let col = b.column(i).into_owned();
    let norm = col.norm();
    if norm <= 0.0 {
        return (Vector3::zeros(), angle);
    }
    let mut axis = col / norm;
    if axis.dot(&vee) < 0.0 {
        axis = -axis;
    }
    (axis * angle, angle)
}

/// The outcome of one descent.
struct Run {
    converged: bool,
    timed_out: bool,
    iterations: usize,
    position_error: f64,
    orientation_error: f64,
}

/// Buffers of one solve, allocated once; the iteration itself does not allocate.
struct Work {
    n: usize,
    q: Vec<f64>,
    trial: Vec<f64>,
    dq: Vec<f64>,
    free: Vec<bool>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    wraps: Vec<bool>,
    ranges: Vec<(f64, f64)>,
    rng: SplitMix64,
    jac: Jacobian,
}

impl Work {
    fn new(robot: &Robot, length_scale: f64) -> Work {
        let n = robot.dof();
        let joints = robot.joints();
        Work {
            n,
            q: vec![0.0; n],
            trial: vec![0.0; n],
            dq: vec![0.0; n],
            free: vec![true; n],
            lower: joints.iter().map(|j| j.limits.lower).collect(),
            upper: joints.iter().map(|j| j.limits.upper).collect(),
            wraps: joints
                .iter()
                .map(|j| j.kind == JointKind::Revolute && !j.limits.lower.is_finite() && !j.limits.upper.is_finite())
                .collect(),
            ranges: sampling_ranges(robot, length_scale),
            rng: SplitMix64(RESEED_SEED),
            jac: Jacobian::zeros(n),
        }
    }

    /// Descent from `self.q` within `max_iterations` tried steps. When a Levenberg–Marquardt
    /// descent ends in a local minimum (stalled or no descent direction) with iterations left
    /// and `reseed` is set, the descent starts again from a fresh pseudo-random configuration
    /// inside the limits ([`Work::reseed`]); the reported errors are those of the best descent.
    fn descend(
        &mut self,
        robot: &Robot,
        goal: &Goal,
        max_iterations: usize,
        criteria: &Criteria,
        reseed: bool,
    ) -> Result<Run, IkError> {
        let mut iterations = 0;
        let mut best = (f64::INFINITY, f64::INFINITY);
        loop {
            let mut run = self.descend_once(robot, goal, max_iterations - iterations, criteria)?;
            iterations += run.iterations;
            run.iterations = iterations;
            if run.position_error + run.orientation_error < best.0 + best.1 {
                best = (run.position_error, run.orientation_error);
            }
            if run.converged || run.timed_out || iterations >= max_iterations || !reseed {
                if !run.converged {
                    (run.position_error, run.orientation_error) = best;
                }
                return Ok(run);
            }
            self.reseed();
        }
    }

    /// Moves `self.q` to a pseudo-random configuration inside the limits (the next of this
    /// solve's own SplitMix64 sequence, independent of the starts).
    fn reseed(&mut self) {
        for (v, &(lo, hi)) in self.q.iter_mut().zip(&self.ranges) {
            *v = lo + (hi - lo) * self.rng.next_f64();
        }
    }

    /// Levenberg–Marquardt descent from `self.q` (left at the last accepted configuration).
    fn descend_once(
        &mut self,
        robot: &Robot,
        goal: &Goal,
        max_iterations: usize,
        criteria: &Criteria,
    ) -> Result<Run, IkError> {
        let mut t = robot.fk_matrix(&self.q)?;
        let (mut e, mut pe, mut oe) = goal.error(&t);
        let mut energy = 0.5 * e.norm_squared();
        let mut mu = 1.0;
        let mut stall = 0;
        let mut iterations = 0;
        let mut timed_out = false;
        loop {
            if pe <= criteria.stop_position && oe <= criteria.stop_orientation {
                return Ok(Run { converged: true, timed_out, iterations, position_error: pe, orientation_error: oe });
            }
            if iterations >= max_iterations || stall >= STALL_STEPS {
                break;
            }
            if criteria.deadline.is_some_and(|d| Instant::now() >= d) || criteria.cancel.is_cancelled() {
                timed_out = true;
                break;
            }
            robot.jacobian_into(&self.q, &mut self.jac)?;
            goal.weigh(&mut self.jac, &t);
            let mut accepted = false;
            while iterations < max_iterations && mu <= MU_MAX {
                iterations += 1;
                let lambda = mu * (energy + DAMPING_FLOOR);
                if !self.step(&e, lambda) {
                    mu *= MU_GROW;
                    continue;
                }
                let t2 = robot.fk_matrix(&self.trial)?;
                let (e2, pe2, oe2) = goal.error(&t2);
                let energy2 = 0.5 * e2.norm_squared();
                if energy2 < energy {
                    stall = if energy - energy2 < STALL_RELATIVE * energy { stall + 1 } else { 0 };
                    std::mem::swap(&mut self.q, &mut self.trial);
                    (t, e, pe, oe, energy) = (t2, e2, pe2, oe2, energy2);
                    mu = (mu * MU_SHRINK).max(MU_MIN);
                    accepted = true;
                    break;
                }
                mu *= MU_GROW;
            }
            if !accepted {
                break;
            }
        }
        // Stopped short of the internal threshold (iteration budget, stall, time or no further
        // decrease): still a solution if within the acceptance tolerances.
        let converged = pe <= criteria.accept_position && oe <= criteria.accept_orientation;
        Ok(Run { converged, timed_out, iterations, position_error: pe, orientation_error: oe })
    }

    /// One damped least-squares step with the limits enforced: writes `self.trial`.
    /// Returns `false` when the damped system cannot be factorised.
    fn step(&mut self, e: &Vector6<f64>, lambda: f64) -> bool {
        self.free.fill(true);
        self.dq.fill(0.0);
        for _ in 0..=self.n {
            let mut a = Matrix6::from_diagonal_element(lambda);
            let mut r = *e;
            for j in 0..self.n {
                let c = self.jac.fixed_view::<6, 1>(0, j);
                if self.free[j] {
                    a.ger(1.0, &c, &c, 1.0);
                } else {
                    r.axpy(-self.dq[j], &c, 1.0);
                }
            }
            let Some(chol) = a.cholesky() else {
                return false;
            };
            let y = chol.solve(&r);
            let mut clamped = false;
            for j in 0..self.n {
                if !self.free[j] {
                    continue;
                }
                let d = self.jac.fixed_view::<6, 1>(0, j).dot(&y);
                let v = self.q[j] + d;
                if v < self.lower[j] {
                    self.dq[j] = self.lower[j] - self.q[j];
                    self.free[j] = false;
                    clamped = true;
                } else if v > self.upper[j] {
                    self.dq[j] = self.upper[j] - self.q[j];
                    self.free[j] = false;
                    clamped = true;
                } else {
                    self.dq[j] = d;
                }
            }
            if !clamped {
                break;
            }
        }
        for j in 0..self.n {
            let v = self.q[j] + self.dq[j];
            self.trial[j] = if self.wraps[j] { wrap(v) } else { v };
        }
        self.dq.iter().all(|v| v.is_finite())
    }
}

/// Where a start came from.
#[derive(Debug, Clone, Copy)]
enum Start {
    Seed,
    Home,
    Random(usize),
}

/// Deterministic start configurations: the seed (or home), then pseudo-random ones.
struct Starts {
    first: Vec<f64>,
    from_seed: bool,
    /// Sampling interval per joint.
    ranges: Vec<(f64, f64)>,
    rng: SplitMix64,
}

impl Starts {
    fn new(robot: &Robot, seed: Option<&[f64]>, length_scale: f64) -> Starts {
        let joints = robot.joints();
        let first: Vec<f64> = match seed {
            Some(s) => s
                .iter()
                .zip(joints)
                .map(|(&v, j)| {
                    let v = if j.kind == JointKind::Revolute { fit_into_limits(v, &j.limits, 0.0) } else { v };
                    v.clamp(j.limits.lower, j.limits.upper)
                })
                .collect(),
            None => robot.home(),
        };
        let ranges = sampling_ranges(robot, length_scale);
        Starts { first, from_seed: seed.is_some(), ranges, rng: SplitMix64(START_SEED) }
    }

    /// Writes start `k` into `q`.
    fn next_into(&mut self, k: usize, q: &mut [f64]) -> Start {
        if k == 0 {
            q.copy_from_slice(&self.first);
            return if self.from_seed { Start::Seed } else { Start::Home };
        }
        for (v, &(lo, hi)) in q.iter_mut().zip(&self.ranges) {
            *v = lo + (hi - lo) * self.rng.next_f64();
        }
        Start::Random(k)
    }
}

/// Interval per joint that random starts are drawn from: revolute ranges of a full turn or
/// more cut to one turn, prismatic ranges to `length_scale` either side of the centre.
fn sampling_ranges(robot: &Robot, length_scale: f64) -> Vec<(f64, f64)> {
    use std::f64::consts::{PI, TAU};
    robot
        .joints()
        .iter()
        .map(|j| {
            let (lo, hi) = (j.limits.lower, j.limits.upper);
            match j.kind {
                JointKind::Revolute if j.limits.contains(-PI, 0.0) && j.limits.contains(PI, 0.0) => (-PI, PI),
                JointKind::Revolute if j.limits.span() >= TAU => {
                    let start = if lo.is_finite() { lo } else { hi - TAU };
                    (start, start + TAU)
                }
                JointKind::Revolute => (lo, hi),
                JointKind::Prismatic => {
                    let centre = if lo.is_finite() && hi.is_finite() { 0.5 * (lo + hi) } else { j.home };
                    (lo.max(centre - length_scale), hi.min(centre + length_scale))
                }
            }
        })
        .collect()
}

/// Whether two configurations are the same solution (revolute differences wrapped).
fn same_configuration(robot: &Robot, a: &[f64], b: &[f64]) -> bool {
    robot.joints().iter().zip(a.iter().zip(b)).all(|(j, (x, y))| {
        let d = if j.kind == JointKind::Revolute { wrap(x - y) } else { x - y };
        d.abs() < IK_NUMERIC_DISTINCT
    })
}

/// Branch label: which start found the solution and the sign of each joint value as it is
/// reported (e.g. `start=random-3 signs=+-+--+`).
fn label(robot: &Robot, q: &[f64], start: Start) -> Branch {
    let start = match start {
        Start::Seed => "seed".to_string(),
        Start::Home => "home".to_string(),
        Start::Random(k) => format!("random-{k}"),
    };
    let mut signs = String::with_capacity(q.len());
    for (j, &v) in robot.joints().iter().zip(q) {
        let v = if j.kind == JointKind::Revolute { fit_into_limits(v, &j.limits, LIMIT_SLACK) } else { v };
        signs.push(if v < 0.0 { '-' } else { '+' });
    }
    Branch::new([("start", start), ("signs", signs)])
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use nalgebra::{Rotation3, Unit};

    use super::*;
    use crate::model::presets;

    #[test]
    fn rotation_log_inverts_the_exponential_everywhere() {
        let axes = [Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.3, -0.8, 0.5), Vector3::new(-0.2, 0.1, -0.9)];
        for axis in axes {
            let axis = Unit::new_normalize(axis);
            for angle in [0.0, 1e-12, 1e-7, 0.3, 2.0, 2.1, PI - 1e-3, PI - 1e-9] {
                let r = Rotation3::from_axis_angle(&axis, angle);
                let (w, a) = rotation_log(r.matrix());
                assert!((a - angle).abs() < 1e-9, "angle {angle}: {a}");
                assert!((w - axis.into_inner() * angle).norm() < 1e-8, "angle {angle}: {w:?}");
            }
            // Exactly π: the axis is defined up to sign.
            let (w, a) = rotation_log(Rotation3::from_axis_angle(&axis, PI).matrix());
            assert!((a - PI).abs() < 1e-12);
            assert!((w.norm() - PI).abs() < 1e-12 && w.normalize().dot(&axis).abs() > 1.0 - 1e-12);
        }
    }

    #[test]
    fn splitmix64_matches_the_reference_sequence() {
        // Reference outputs of SplitMix64 from state 0 (Vigna's splitmix64.c).
        let mut rng = SplitMix64(0);
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(rng.next_u64(), 0x6E78_9E6A_A1B9_65F4);
        let mut rng = SplitMix64(START_SEED);
        for _ in 0..1000 {
            let x = rng.next_f64();
            assert!((0.0..1.0).contains(&x));
        }
    }

    #[test]
    fn starts_lie_within_the_limits() {
        for name in presets::names() {
            let robot = presets::get(name).unwrap();
            let mut starts = Starts::new(&robot, None, 1.0);
            let mut q = vec![0.0; robot.dof()];
            for k in 0..50 {
                starts.next_into(k, &mut q);
                assert_eq!(robot.first_joint_outside_limits(&q, 0.0), None, "{name} start {k}: {q:?}");
            }
        }
        // A seed outside the limits is moved inside (by whole turns, else clamped).
        let puma = presets::get("puma560").unwrap();
        let seed = [3.0, 0.1 + 2.0 * PI, 0.0, 0.0, -2.5, 0.0];
        let mut starts = Starts::new(&puma, Some(&seed), 1.0);
        let mut q = vec![0.0; 6];
        assert!(matches!(starts.next_into(0, &mut q), Start::Seed));
        assert!((q[0] - 160f64.to_radians()).abs() < 1e-12);
        assert!((q[1] - 0.1).abs() < 1e-12);
        assert!((q[4] + 100f64.to_radians()).abs() < 1e-12);
    }

    #[test]
    fn a_step_never_leaves_the_limits() {
        // Two-link arm, 1 m links, q1 ∈ [0, 0.5]: pulling the tip far along −y pushes q1 below 0;
        // the step must stop joint 1 exactly at its limit and move joint 2 instead.
        let joints = vec![
            crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0).with_limits(0.0, 0.5),
            crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0),
        ];
        let robot = Robot::new(crate::model::RobotSpec::new("two", crate::model::Convention::Dh, joints)).unwrap();
        let mut work = Work::new(&robot, 1.0);
        work.q.copy_from_slice(&[0.1, 0.3]);
        robot.jacobian_into(&work.q, &mut work.jac).unwrap();
        let e = Vector6::new(0.0, -1.0, 0.0, 0.0, 0.0, 0.0);
        assert!(work.step(&e, 1e-6));
        assert_eq!(work.trial[0], 0.0);
        assert!(work.trial[1] < 0.3, "joint 2 takes over: {:?}", work.trial);
        // The unconstrained step would have moved joint 1 below its limit.
        let free = Robot::new(crate::model::RobotSpec::new(
            "free",
            crate::model::Convention::Dh,
            vec![crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0), crate::model::Joint::revolute(1.0, 0.0, 0.0, 0.0)],
        ))
        .unwrap();
        let mut unconstrained = Work::new(&free, 1.0);
        unconstrained.q.copy_from_slice(&[0.1, 0.3]);
        free.jacobian_into(&unconstrained.q, &mut unconstrained.jac).unwrap();
        assert!(unconstrained.step(&e, 1e-6));
        assert!(unconstrained.trial[0] < 0.0);
    }

    #[test]
    fn same_configuration_wraps_revolute_joints_only() {
        let rp = Robot::from_toml_str(
            "name = \"rp\"\nlength_unit = \"m\"\nangle_unit = \"rad\"\n[[joints]]\nalpha = 1.5\n[[joints]]\nkind = \"prismatic\"\n",
        )
        .unwrap();
        assert!(same_configuration(&rp, &[PI - 1e-6, 0.2], &[-PI + 1e-6, 0.2]));
        assert!(!same_configuration(&rp, &[0.0, 0.2], &[0.0, 0.2 + 2.0 * PI]));
        assert!(!same_configuration(&rp, &[0.0, 0.2], &[1e-3, 0.2]));
    }

    #[test]
    fn configurations_are_one_any_solution_followed_by_nearness() {
        let panda = presets::get("panda").unwrap();
        let s = Numeric::from_robot(&panda).unwrap();
        assert_eq!(s.configurations(&panda), [Branch::default()]);
        assert!(!s.enumerates_all_branches());
        assert!(s.singularity_measures(&panda, &[Branch::default()]).is_none());
    }
}
