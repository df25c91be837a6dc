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
//! to convergence or failure; the distinct converged configurations are returned, so a 6R arm
//! typically yields several of its (up to eight) branches and a redundant arm several points of
//! its self-motion.
//!
//! **Stopping:** a start converges when the position error is below
//! [`IK_NUMERIC_POSITION`] and the orientation error below [`IK_NUMERIC_ORIENTATION`] (1000×
//! tighter than the acceptance tolerances, a step or two more than needed). It is abandoned
//! after `options.max_iterations` tried steps (a rejected step counts), when the damping
//! multiplier exceeds 1e8 (no descent direction), or after 8 consecutive steps that each
//! reduce `E` by less than 1e-4 of its value (a local minimum; for an under-actuated arm, the
//! least-squares optimum). An abandoned start whose errors are below half the acceptance
//! tolerances still counts as converged.
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

use nalgebra::{IsometryMatrix3, Matrix3, Matrix6, Vector3, Vector6};

use super::{
    Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, finish,
};
use crate::angle::{fit_into_limits, wrap};
use crate::kinematics::{Jacobian, JacobianAxes, Manipulability, check_q};
use crate::model::{JointKind, Robot};
use crate::tolerance::{
    BOUNDARY, IK_NUMERIC_DISTINCT, IK_NUMERIC_ORIENTATION, IK_NUMERIC_POSITION, IK_NUMERIC_SINGULAR, IK_ORIENTATION,
    IK_POSITION, LIMIT_SLACK,
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
const STALL_STEPS: usize = 8;
const STALL_RELATIVE: f64 = 1e-4;
/// Fixed seed of the start generator: the same problem always gets the same starts.
const START_SEED: u64 = 0x5EED_1C0D_2024_0001;

/// General numeric IK solver (damped least squares with adaptive damping and multiple starts)
/// for any serial chain: any number of joints, revolute or prismatic, DH, MDH or URDF.
///
/// Handles full-pose and position-only targets, redundant arms (n > 6, e.g. `panda`) and
/// under-actuated arms (n < 6: the pose error is minimised in least squares; a target whose
/// position is reachable but whose orientation is not is reported as
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

    /// Every distinct solution found from the seed (or home) and the pseudo-random starts.
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] for a non-finite target, a robot with another number of joints
    /// than the one the solver was built for, or `max_iterations` / `restarts` equal to 0;
    /// [`IkError::Kinematics`] for a seed of the wrong length or with non-finite values.
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
        if let Some(seed) = &options.seed {
            check_q(robot.dof(), seed)?;
        }

        let distance = (target.position().coords - self.anchor).norm();
        if distance > self.reach * (1.0 + BOUNDARY) + IK_POSITION {
            let failure = IkFailure::Unreachable { distance, reach: self.reach };
            return finish(robot, target, Vec::new(), self.name(), failure);
        }

        let goal = Goal::new(target, self.length_scale);
        let mut work = Work::new(robot);
        let mut starts = Starts::new(robot, options.seed.as_deref(), self.length_scale);
        let mut found: Vec<(Vec<f64>, Start)> = Vec::new();
        let mut iterations = 0;
        let mut best_residual = f64::INFINITY;
        for k in 0..options.restarts {
            let start = starts.next_into(k, &mut work.q);
            let run = work.descend(robot, &goal, options.max_iterations)?;
            iterations += run.iterations;
            best_residual = best_residual.min(run.position_error + run.orientation_error);
            if run.converged && !found.iter().any(|(q, _)| same_configuration(robot, q, &work.q)) {
                found.push((work.q.clone(), start));
            }
        }

        let axes = if goal.rotation.is_some() { JacobianAxes::All } else { JacobianAxes::Translation };
        let mut candidates = Vec::with_capacity(found.len());
        for (q, start) in found {
            robot.jacobian_into(&q, &mut work.jac)?;
            let m = Manipulability::of(&work.jac, axes);
            let branch = label(robot, &q, start);
            let mut c = Candidate::new(q, branch);
            if m.sigma_min <= IK_NUMERIC_SINGULAR * m.sigma_max {
                c.singularities.push(SingularityKind::Jacobian);
            }
            candidates.push(c);
        }

        // Only an under-actuated arm has orientations it cannot reach at a reachable position
        // in general; for n ≥ 6 a failed pose solve is reported as what it is, no convergence.
        let failure = if candidates.is_empty()
            && goal.rotation.is_some()
            && self.dof < 6
            && self.position_reachable(robot, target, options, &mut work)?
        {
            IkFailure::OrientationUnreachable
        } else {
            IkFailure::NoConvergence { iterations, residual: best_residual }
        };
        finish(robot, target, candidates, self.name(), failure)
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
        work: &mut Work,
    ) -> Result<bool, IkError> {
        let goal = Goal::new(&IkTarget::Position(target.position()), self.length_scale);
        let mut starts = Starts::new(robot, options.seed.as_deref(), self.length_scale);
        for k in 0..options.restarts {
            starts.next_into(k, &mut work.q);
            if work.descend(robot, &goal, options.max_iterations)?.converged {
                return Ok(true);
            }
        }
        Ok(false)
    }
}

/// The target in the form the iteration uses.
struct Goal {
    position: Vector3<f64>,
    /// `None` for a position-only target.
    rotation: Option<Matrix3<f64>>,
    /// Row weights: `1/L` on the position rows, 1 (pose) or 0 (position only) on the rotation rows.
    weights: Vector6<f64>,
}

impl Goal {
    fn new(target: &IkTarget, length_scale: f64) -> Goal {
        let s = 1.0 / length_scale;
        match target {
            IkTarget::Pose(pose) => Goal {
                position: pose.translation.vector,
                rotation: Some(*pose.rotation.to_rotation_matrix().matrix()),
                weights: Vector6::new(s, s, s, 1.0, 1.0, 1.0),
            },
            IkTarget::Position(p) => {
                Goal { position: p.coords, rotation: None, weights: Vector6::new(s, s, s, 0.0, 0.0, 0.0) }
            }
        }
    }

    /// Weighted error vector, position error (m) and orientation error (rad) of the pose `t`.
    #[inline]
    fn error(&self, t: &IsometryMatrix3<f64>) -> (Vector6<f64>, f64, f64) {
        let dp = self.position - t.translation.vector;
        let (w, angle) = match &self.rotation {
            Some(r) => rotation_log(&(r * t.rotation.matrix().transpose())),
            None => (Vector3::zeros(), 0.0),
        };
        let e = Vector6::new(dp.x, dp.y, dp.z, w.x, w.y, w.z).component_mul(&self.weights);
        (e, dp.norm(), angle)
    }
}

/// Rotation vector (axis · angle, angle in [0, π]) of a rotation matrix, and the angle;
/// accurate near 0 and near π.
fn rotation_log(r: &Matrix3<f64>) -> (Vector3<f64>, f64) {
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
    jac: Jacobian,
}

impl Work {
    fn new(robot: &Robot) -> Work {
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
            jac: Jacobian::zeros(n),
        }
    }

    /// Levenberg–Marquardt descent from `self.q` (left at the last accepted configuration).
    fn descend(&mut self, robot: &Robot, goal: &Goal, max_iterations: usize) -> Result<Run, IkError> {
        let t = robot.fk_matrix(&self.q)?;
        let (mut e, mut pe, mut oe) = goal.error(&t);
        let mut energy = 0.5 * e.norm_squared();
        let mut mu = 1.0;
        let mut stall = 0;
        let mut iterations = 0;
        loop {
            if pe <= IK_NUMERIC_POSITION && oe <= IK_NUMERIC_ORIENTATION {
                return Ok(Run { converged: true, iterations, position_error: pe, orientation_error: oe });
            }
            if iterations >= max_iterations || stall >= STALL_STEPS {
                break;
            }
            robot.jacobian_into(&self.q, &mut self.jac)?;
            for (r, w) in goal.weights.iter().enumerate() {
                self.jac.row_mut(r).scale_mut(*w);
            }
            let mut accepted = false;
            while iterations < max_iterations && mu <= MU_MAX {
                iterations += 1;
                let lambda = mu * (energy + DAMPING_FLOOR);
                if !self.step(&e, lambda) {
                    mu *= MU_GROW;
                    continue;
                }
                let t = robot.fk_matrix(&self.trial)?;
                let (e2, pe2, oe2) = goal.error(&t);
                let energy2 = 0.5 * e2.norm_squared();
                if energy2 < energy {
                    stall = if energy - energy2 < STALL_RELATIVE * energy { stall + 1 } else { 0 };
                    std::mem::swap(&mut self.q, &mut self.trial);
                    (e, pe, oe, energy) = (e2, pe2, oe2, energy2);
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
        // Stopped short of the internal threshold (iteration budget, stall or no further
        // decrease): still a solution if within half the acceptance tolerances.
        let converged = pe <= 0.5 * IK_POSITION && oe <= 0.5 * IK_ORIENTATION;
        Ok(Run { converged, iterations, position_error: pe, orientation_error: oe })
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
        use std::f64::consts::{PI, TAU};
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
        let ranges = joints
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
            .collect();
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

/// SplitMix64 (Steele, Lea & Flood 2014): a tiny, fast, well-mixed deterministic generator.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn next_f64(&mut self) -> f64 {
        // 53 random bits; both conversions are exact.
        let x = (self.next_u64() >> 11) as f64;
        x * (1.0 / (1u64 << 53) as f64)
    }
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
        let mut work = Work::new(&robot);
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
        let mut unconstrained = Work::new(&free);
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
}
