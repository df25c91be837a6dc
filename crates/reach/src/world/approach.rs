//! Seed 004: motion synthesis next to forbidden zones — joint increments that reach a goal
//! while the arm keeps a safe distance from the obstacles, with deadlocks detected and
//! handed to the planner (notes 004 §4 E, §8 "Performance and integration").
//!
//! The paper leaves the velocity law to \[5\] and only says that the increment vector is
//! computed "taking into account a given safe distance" and that analysing motions against
//! the allowed region "allows predicting deadlocks". This module fills that gap.
//!
//! # Method
//! Each iteration makes one increment `Δq` from the current configuration `q`:
//!
//! 1. **Task step.** The task error `e` (joint goal: `q_goal − q`; position goal: the tool
//!    point's error; pose goal: position and rotation-vector error) and the task Jacobian `J`
//!    (identity, the 3 position rows, or all 6 rows of the geometric Jacobian) give the damped
//!    least-squares step `J⁺e`.
//! 2. **Redundancy.** For a redundant task (more joints than task rows: `planar3` and
//!    `varan4` for a position, Panda for a pose) the null-space projector `N = I − J⁺J` adds
//!    `N·z`, where `z` pushes away from the nearby clearances (the gradient of a repulsive
//!    barrier): self-motion that does not disturb the task.
//! 3. **Barrier.** Every clearance `h_i(q)` of the arm — each link against each obstacle,
//!    the tool point inside each tool-zone entry, non-adjacent links — is measured with the
//!    links grown by the safe distance (so `h_i` is the margin *beyond* the safe distance,
//!    the signed clearance of the paper's allowed region). The increment is projected onto
//!    `∇h_i·Δq ≥ −γ·h_i` for the clearances within [`ApproachOptions::influence`]
//!    (Hildreth's dual coordinate ascent, the least change of the step), a first-order
//!    control-barrier condition: a clearance may shrink by at most the share `γ` of itself
//!    per step.
//! 4. **Candidates, fast first test, exact proof.** The increment scaled by 1, ½, ¼, ⅛, 1/16,
//!    each also tilted both ways along the null space, are candidates in that order, clamped
//!    to the joint limits. With a [`FastRegion`] a candidate whose end lies clearly outside
//!    the fitted R-function region (`F_Λ < −band`) is dropped without the exact test. The
//!    first remaining candidate whose straight motion the swept check
//!    ([`super::CollisionChecker::swept`], conservative advancement with certified rates)
//!    proves clear is taken.
//! 5. **Deadlock.** No candidate proven clear, an increment the barrier cancels, or no
//!    progress (the task error not 0.5 % below its best for [`ApproachOptions::stall_window`]
//!    samples) is a deadlock: the goal direction and the barrier oppose. The caller hands over
//!    to the planner ([`super::planner`]).
//!
//! # Safety argument
//! Every increment is a straight joint-space motion accepted only when the swept check proves
//! every clearance of the grown links above [`super::sweep::SWEEP_FLOOR`] over the **whole**
//! motion, not at its ends: between two evaluated points a clearance `d` with rate bound `B`
//! (the fastest any point of the bodies can move per unit of the motion) is at least
//! `(d(s) + d(s') − B·|s' − s|)/2`. A link grown by the safe distance `d_s` with a positive
//! clearance is an original link with a clearance above `d_s`, so the motion keeps the safe
//! distance from every obstacle everywhere between the samples. The tool point stays strictly
//! inside every tool-zone entry. Non-adjacent links, both grown, stay `2·d_s` apart
//! (conservative). Joint limits: both ends are clamped into the limit box, which is convex,
//! so the straight motion between them stays inside. [`Approach::min_margin`] is the smallest
//! certified lower bound over all increments.
//!
//! The fitted region is **only** a first test: it may drop a candidate (the region is an
//! approximation and can wrongly call an allowed configuration forbidden, which costs only
//! completeness), but it never lets one through — every accepted increment is proven by the
//! exact swept check.

use nalgebra::{DMatrix, DVector, Vector3};
use serde::Serialize;

use super::cspace::{GridSpec, classify_grid, grid_node_count};
use super::fit::{FitOptions, MAX_FIT_NODES, fit_region};
use super::rfunction::CompiledRegion;
use super::sweep::SweepOptions;
use super::{CollisionChecker, Scene, SweptPair, WorldError};
use crate::ik::{self, IkOptions, IkTarget};
use crate::model::{LinkGeometry, Robot, RobotSpec};

/// The most samples (configurations, start included) one approach may make: the resource cap
/// of [`ApproachOptions::max_samples`].
pub const MAX_SAMPLES: usize = 100_000;

/// Evaluations one increment's swept check may make; an increment that needs more is not
/// taken (safe: a smaller candidate is tried).
const STEP_SWEEP_EVALUATIONS: usize = 2_000;

/// Damping of the task pseudo-inverse (`Jᵀ(JJᵀ + λ²I)⁻¹`), in the task's units: keeps the
/// step bounded near singular configurations and changes it by less than 1e-6 relative
/// elsewhere (the arms' singular values are 0.1–2).
const DAMPING: f64 = 1e-3;

/// Finite-difference step of the barrier gradients, radians / metres.
const GRADIENT_STEP: f64 = 1e-6;

/// Share `γ` of a clearance that one increment may consume (barrier condition).
const BARRIER_RATE: f64 = 0.5;

/// Least share of the barrier's push that must lie in the null space to be followed.
const NULL_SPACE_SHARE: f64 = 1e-3;

/// An increment shorter than this (joint-space norm) makes no motion: deadlock.
const NO_MOTION: f64 = 1e-9;

/// Relative decrease of the task error that counts as progress within the stall window.
const PROGRESS: f64 = 0.005;

/// What the approach should reach: the planner's goal (a joint vector, or a tool pose or a
/// tool position only, the task of `varan4` and `planar3`), so that a deadlock hands the same
/// goal over to the planner.
pub type ApproachGoal = crate::world::planner::Goal;

/// Settings of [`approach`]. `Default` gives the documented defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct ApproachOptions {
    /// Safe distance from every obstacle, metres (≥ 0). Default 0.05.
    pub safe_distance: f64,
    /// Largest increment, joint-space Euclidean norm (radians / metres). Default 0.05
    /// (about 2.9°).
    pub max_step: f64,
    /// The goal is reached when the tool point is this close (metres), or every joint this
    /// close (radians / metres) for a joint goal. Default 1e-4.
    pub tolerance: f64,
    /// Orientation tolerance of a pose goal, radians. Default 1e-3.
    pub orientation_tolerance: f64,
    /// Most samples, start included (at most [`MAX_SAMPLES`]). Default 3000.
    pub max_samples: usize,
    /// Margin beyond the safe distance within which a clearance acts as a barrier, metres.
    /// Default 0.1.
    pub influence: f64,
    /// Samples without progress after which the approach is a deadlock. Default 40.
    pub stall_window: usize,
}

impl Default for ApproachOptions {
    fn default() -> Self {
        ApproachOptions {
            safe_distance: 0.05,
            max_step: 0.05,
            tolerance: 1e-4,
            orientation_tolerance: 1e-3,
            max_samples: 3000,
            influence: 0.1,
            stall_window: 40,
        }
    }
}

/// How the approach ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The goal is reached within the tolerance.
    Reached,
    /// The goal direction and the barrier oppose (or no progress): hand over to the planner.
    Deadlock,
    /// The goal itself violates the limits or the safe distance, or has no IK solution.
    Unreachable,
}

/// Counts of the candidate tests.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct ApproachStats {
    /// Candidate increments considered.
    pub candidates: usize,
    /// Candidates the fitted region dropped without the exact test.
    pub fast_rejected: usize,
    /// Exact swept checks of candidates.
    pub exact_sweeps: usize,
    /// Clearance evaluations of those swept checks.
    pub sweep_evaluations: usize,
}

/// The synthesised motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Approach {
    /// How it ended.
    pub outcome: Outcome,
    /// Why, for a deadlock or an unreachable goal.
    pub reason: Option<String>,
    /// The configurations, start first; consecutive ones are joined by straight joint-space
    /// increments proven to keep the safe distance.
    pub samples: Vec<Vec<f64>>,
    /// Certified lower bound, over the whole motion, of the margin beyond the safe distance
    /// (see the module's safety argument), metres; `+∞` without motion or constraints.
    pub min_margin: f64,
    /// Which clearance comes closest (of the increment that gives `min_margin`).
    pub closest: Option<SweptPair>,
    /// Task error at the end: tool-point distance (metres), or the largest joint error for a
    /// joint goal.
    pub error: f64,
    /// Orientation error at the end for a pose goal, radians (0 otherwise).
    pub orientation_error: f64,
    /// The goal configurations (a joint goal, or the IK solutions that keep the safe
    /// distance, nearest to the start first): what a planner takes over.
    pub goals: Vec<Vec<f64>>,
    /// Candidate tests.
    pub stats: ApproachStats,
}

/// A fitted seed-004 R-function region used as a fast first test of candidates.
#[derive(Debug, Clone, PartialEq)]
pub struct FastRegion {
    /// The region over three joints, degrees, compiled (its source:
    /// [`CompiledRegion::region`]).
    pub region: CompiledRegion,
    /// 0-based joints that are the region's coordinates.
    pub joints: [usize; 3],
    /// The other joints and the values (radians / metres) they had in the fitting grid; the
    /// region says nothing where they differ.
    pub fixed: Vec<(usize, f64)>,
    /// `F_Λ` below `−band` is "clearly outside" (the region's own units, degrees).
    pub band: f64,
}

/// A fixed joint counts as at its grid value within this (radians / metres).
const FIXED_MATCH: f64 = 1e-9;

impl FastRegion {
    /// Fits the region to the grid of `robot` in `scene` with the links grown by
    /// `safe_distance` (so the region approximates the allowed set *with* the safe distance),
    /// the joints in `fixed` held at their values, the others swept at `step` (radians).
    ///
    /// # Errors
    /// [`WorldError::Input`] unless exactly three joints are swept, for a grid of more than
    /// [`MAX_FIT_NODES`] nodes, or for a negative safe distance; as [`classify_grid`] and
    /// [`fit_region`].
    pub fn fit(
        robot: &Robot,
        scene: &Scene,
        safe_distance: f64,
        fixed: &[(usize, f64)],
        step: f64,
        band: f64,
    ) -> Result<FastRegion, WorldError> {
        let grown = grown_robot(robot, safe_distance)?;
        let mut spec = GridSpec::new(robot.dof(), step);
        for &(j, v) in fixed {
            spec = spec.fix(j, v);
        }
        let nodes = grid_node_count(robot, &spec)?;
        if nodes > MAX_FIT_NODES {
            return Err(WorldError::Input(format!(
                "the fitting grid would have {nodes} nodes, more than {MAX_FIT_NODES}: use a coarser step"
            )));
        }
        let grid = classify_grid(&grown, scene, &spec)?;
        let fit = fit_region(&grid, &FitOptions::default())?;
        Ok(FastRegion { region: fit.region.compile(), joints: fit.joints, fixed: fixed.to_vec(), band })
    }

    /// Whether the region speaks about `q` (the fixed joints at their values).
    #[must_use]
    pub fn applies(&self, q: &[f64]) -> bool {
        self.fixed.iter().all(|&(j, v)| q.get(j).is_some_and(|x| (x - v).abs() <= FIXED_MATCH))
    }

    /// `F_Λ(q)`, the region's value at `q` (degrees), or `None` where it does not apply.
    #[must_use]
    pub fn value(&self, q: &[f64]) -> Option<f64> {
        if !self.applies(q) || self.joints.iter().any(|&j| j >= q.len()) {
            return None;
        }
        Some(self.region.value(self.joints.map(|j| q[j].to_degrees())))
    }

    /// Whether `q` lies clearly outside the region (`F_Λ < −band`): the first test drops it.
    #[must_use]
    pub fn rejects(&self, q: &[f64]) -> bool {
        self.value(q).is_some_and(|f| f < -self.band)
    }
}

/// A copy of `robot` whose link capsules and bodies ([`crate::model::LinkBody::padding`]) are
/// grown by `safe_distance`: a positive clearance of the grown links is a clearance above the
/// safe distance of the original ones.
///
/// # Errors
/// [`WorldError::Input`] for a negative or non-finite distance.
pub fn grown_robot(robot: &Robot, safe_distance: f64) -> Result<Robot, WorldError> {
    if !(safe_distance.is_finite() && safe_distance >= 0.0) {
        return Err(WorldError::Input(format!("the safe distance must be ≥ 0 metres, got {safe_distance}")));
    }
    let links: Vec<LinkGeometry> = (0..robot.dof())
        .map(|k| LinkGeometry { radius: robot.links().get(k).map_or(0.0, |l| l.radius) + safe_distance })
        .collect();
    let mut bodies = robot.bodies().to_vec();
    for b in &mut bodies {
        b.padding += safe_distance;
    }
    Robot::new(RobotSpec { links, bodies, ..robot.spec().clone() }).map_err(|e| WorldError::Input(e.to_string()))
}

/// The task: error and Jacobian rows.
enum Task {
    Joints(Vec<f64>),
    Position(Vector3<f64>),
    Pose(nalgebra::Isometry3<f64>),
}

impl Task {
    /// Error vector, task Jacobian, error measure (m or rad) and orientation error (rad).
    fn at(&self, robot: &Robot, q: &[f64]) -> Result<(DVector<f64>, DMatrix<f64>, f64, f64), WorldError> {
        let n = q.len();
        Ok(match self {
            Task::Joints(goal) => {
                let e = DVector::from_iterator(n, goal.iter().zip(q).map(|(g, x)| g - x));
                let m = e.amax();
                (e, DMatrix::identity(n, n), m, 0.0)
            }
            Task::Position(p) => {
                let t = robot.fk(q)?;
                let dp = p - t.translation.vector;
                let jac = robot.jacobian(q)?;
                let j = DMatrix::from_fn(3, n, |r, c| jac[(r, c)]);
                (DVector::from_column_slice(dp.as_slice()), j, dp.norm(), 0.0)
            }
            Task::Pose(goal) => {
                let t = robot.fk(q)?;
                let dp = goal.translation.vector - t.translation.vector;
                let r =
                    goal.rotation.to_rotation_matrix().matrix() * t.rotation.to_rotation_matrix().matrix().transpose();
                let (w, angle) = crate::ik::numeric::rotation_log(&r);
                let jac = robot.jacobian(q)?;
                let j = DMatrix::from_fn(6, n, |r, c| jac[(r, c)]);
                let e = DVector::from_vec(vec![dp.x, dp.y, dp.z, w.x, w.y, w.z]);
                (e, j, dp.norm(), angle)
            }
        })
    }
}

/// The damped pseudo-inverse `Jᵀ(JJᵀ + λ²I)⁻¹`.
fn pseudo_inverse(j: &DMatrix<f64>) -> DMatrix<f64> {
    let m = j.nrows();
    let a = j * j.transpose() + DMatrix::identity(m, m) * (DAMPING * DAMPING);
    match a.cholesky() {
        Some(c) => j.transpose() * c.inverse(),
        None => DMatrix::zeros(j.ncols(), m),
    }
}

/// The approach's working state: the grown checker and its clearance buffers.
struct Barrier<'a> {
    checker: CollisionChecker<'a>,
    h: Vec<f64>,
    shifted: Vec<f64>,
}

impl Barrier<'_> {
    /// Clearances within `influence` and their gradients (finite differences).
    fn active(&mut self, q: &[f64], influence: f64) -> Result<Vec<(f64, DVector<f64>)>, WorldError> {
        use super::sweep::Clearances;
        let rates = self.checker.prepare(&[q], &vec![0.0; q.len()])?;
        self.h.resize(rates.len(), 0.0);
        self.shifted.resize(rates.len(), 0.0);
        self.checker.evaluate(0.0, q, &mut self.h)?;
        let near: Vec<usize> = (0..self.h.len()).filter(|&i| self.h[i] < influence).collect();
        if near.is_empty() {
            return Ok(Vec::new());
        }
        let n = q.len();
        let mut grads = vec![DVector::zeros(n); near.len()];
        let mut x = q.to_vec();
        for j in 0..n {
            x[j] = q[j] + GRADIENT_STEP;
            self.checker.evaluate(0.0, &x, &mut self.shifted)?;
            let plus: Vec<f64> = near.iter().map(|&i| self.shifted[i]).collect();
            x[j] = q[j] - GRADIENT_STEP;
            self.checker.evaluate(0.0, &x, &mut self.shifted)?;
            for (k, &i) in near.iter().enumerate() {
                grads[k][j] = (plus[k] - self.shifted[i]) / (2.0 * GRADIENT_STEP);
            }
            x[j] = q[j];
        }
        Ok(near.iter().map(|&i| self.h[i]).zip(grads).collect())
    }
}

/// Projects `dq` onto `{Δ : aᵢ·Δ ≥ −γ·hᵢ}` (Hildreth's method: the nearest point for the
/// Euclidean norm).
fn project(dq: &mut DVector<f64>, constraints: &[(f64, DVector<f64>)]) {
    let mut lambda = vec![0.0; constraints.len()];
    for _ in 0..100 {
        let mut change: f64 = 0.0;
        for ((h, a), l) in constraints.iter().zip(&mut lambda) {
            let aa = a.norm_squared();
            if aa <= f64::EPSILON {
                continue;
            }
            let r = (-BARRIER_RATE * h - a.dot(dq)) / aa;
            let delta = r.max(-*l);
            *l += delta;
            dq.axpy(delta, a, 1.0);
            change = change.max(delta.abs() * aa.sqrt());
        }
        if change < 1e-12 {
            break;
        }
    }
}

fn check_options(options: &ApproachOptions) -> Result<(), WorldError> {
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(WorldError::Input(format!("{name} must be positive, got {v}")))
        }
    };
    positive("the largest increment", options.max_step)?;
    positive("the tolerance", options.tolerance)?;
    positive("the orientation tolerance", options.orientation_tolerance)?;
    positive("the barrier's influence distance", options.influence)?;
    if !(2..=MAX_SAMPLES).contains(&options.max_samples) {
        return Err(WorldError::Input(format!(
            "the number of samples must be between 2 and {MAX_SAMPLES}, got {}",
            options.max_samples
        )));
    }
    if options.stall_window == 0 {
        return Err(WorldError::Input("the stall window must be at least one sample".into()));
    }
    Ok(())
}

/// The first (0-based) joint of `q` outside its limits.
fn outside_limits(robot: &Robot, q: &[f64]) -> Option<usize> {
    robot.joints().iter().zip(q).position(|(j, v)| !j.limits.contains(*v, crate::tolerance::LIMIT_SLACK))
}

/// Clamps `q` into the joint limits.
fn clamp(robot: &Robot, q: &mut [f64]) {
    for (v, j) in q.iter_mut().zip(robot.joints()) {
        *v = v.clamp(j.limits.lower, j.limits.upper);
    }
}

/// Synthesises the motion from `start` to `goal` keeping the safe distance (see the module
/// docs), with an optional fitted region as a fast first test of the candidates.
///
/// # Returns
/// The motion and its outcome. An unreachable goal (outside the limits, closer than the safe
/// distance to an obstacle, no IK solution that keeps it) is an answer with one sample.
///
/// # Errors
/// [`WorldError::Input`] for bad options, a scene with a moving obstacle
/// ([`Scene::require_fixed`]), a start of the wrong length, non-finite, outside
/// the limits or closer than the safe distance; as [`CollisionChecker::try_new`] for a bad
/// allowed-collision list; [`WorldError::Ik`] when the IK of a target goal fails on its
/// input.
pub fn approach(
    robot: &Robot,
    scene: &Scene,
    start: &[f64],
    goal: &ApproachGoal,
    options: &ApproachOptions,
    fast: Option<&FastRegion>,
) -> Result<Approach, WorldError> {
    check_options(options)?;
    scene.require_fixed("the motion synthesis (its increments are untimed)")?;
    let grown = grown_robot(robot, options.safe_distance)?;
    let mut checker = CollisionChecker::try_new(&grown, scene)?;
    if start.len() != robot.dof() || start.iter().any(|v| !v.is_finite()) {
        return Err(WorldError::Input(format!("start: expected {} finite joint values, got {:?}", robot.dof(), start)));
    }
    if let Some(j) = outside_limits(robot, start) {
        return Err(WorldError::Input(format!("start: joint {} is outside its limits", j + 1)));
    }
    let verdict = checker.check(start)?;
    if !verdict.is_free() {
        return Err(WorldError::Input(format!(
            "start: not allowed with a safe distance of {} m ({verdict:?})",
            options.safe_distance
        )));
    }
    let mut result = Approach {
        outcome: Outcome::Unreachable,
        reason: None,
        samples: vec![start.to_vec()],
        min_margin: f64::INFINITY,
        closest: None,
        error: f64::INFINITY,
        orientation_error: 0.0,
        goals: Vec::new(),
        stats: ApproachStats::default(),
    };
    let task = match goal {
        ApproachGoal::Joints(q) => {
            if q.len() != robot.dof() || q.iter().any(|v| !v.is_finite()) {
                return Err(WorldError::Input(format!("goal: expected {} finite joint values", robot.dof())));
            }
            if outside_limits(robot, q).is_some() {
                result.reason = Some("the goal is outside the joint limits".into());
                return Ok(result);
            }
            let v = checker.check(q)?;
            if !v.is_free() {
                result.reason = Some(format!("the goal is not allowed with the safe distance ({v:?})"));
                return Ok(result);
            }
            result.goals.push(q.clone());
            Task::Joints(q.clone())
        }
        ApproachGoal::Target(target) => {
            let ik_options = IkOptions { seed: Some(start.to_vec()), ..IkOptions::default() };
            let sols = ik::solve(&grown, target, &ik_options)?;
            let mut free = Vec::new();
            for s in sols.feasible() {
                if checker.check(&s.q)?.is_free() {
                    free.push(s.q.clone());
                }
            }
            let distance = |q: &Vec<f64>| q.iter().zip(start).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
            free.sort_by(|a, b| distance(a).total_cmp(&distance(b)));
            result.goals = free;
            if result.goals.is_empty() {
                result.reason = Some(format!(
                    "no IK solution within the limits keeps the safe distance ({} solutions, {} within limits)",
                    sols.solutions.len(),
                    sols.feasible().count()
                ));
                return Ok(result);
            }
            match target {
                IkTarget::Position(p) => Task::Position(p.coords),
                IkTarget::Pose(p) => Task::Pose(*p),
            }
        }
    };
    let mut barrier = Barrier { checker, h: Vec::new(), shifted: Vec::new() };
    let n = robot.dof();
    let mut q = start.to_vec();
    let mut best = f64::INFINITY;
    let mut since_best = 0;
    let sweep_options = SweepOptions { closest: false, max_evaluations: STEP_SWEEP_EVALUATIONS };
    loop {
        let (e, j, error, angle) = task.at(robot, &q)?;
        result.error = error;
        result.orientation_error = angle;
        if error <= options.tolerance && angle <= options.orientation_tolerance {
            result.outcome = Outcome::Reached;
            return Ok(result);
        }
        let measure = error + angle;
        if measure < best * (1.0 - PROGRESS) {
            best = measure;
            since_best = 0;
        } else {
            since_best += 1;
            if since_best >= options.stall_window {
                return Ok(deadlock(result, "no progress: the barrier holds the arm against the goal direction"));
            }
        }
        if result.samples.len() >= options.max_samples {
            return Ok(deadlock(result, &format!("not reached within {} samples", options.max_samples)));
        }
        // 1. Task step.
        // A joint goal's Jacobian is the identity: its exact inverse lands on the goal.
        let pinv = if matches!(task, Task::Joints(_)) { j.clone() } else { pseudo_inverse(&j) };
        let mut dq = &pinv * &e;
        let norm = dq.norm();
        if norm > options.max_step {
            dq *= options.max_step / norm;
        }
        // 2. Barrier and redundancy.
        let constraints = barrier.active(&q, options.influence)?;
        let redundant = j.nrows() < n;
        let null = DMatrix::identity(n, n) - &pinv * &j;
        let mut tilt = DVector::zeros(n);
        if redundant && !constraints.is_empty() {
            let mut push = DVector::zeros(n);
            let mut weight: f64 = 0.0;
            for (h, a) in &constraints {
                let w = ((options.influence - h) / options.influence).clamp(0.0, 1.0);
                weight = weight.max(w);
                push.axpy(w, a, 1.0);
            }
            let z = &null * &push;
            // A push the task already controls (the tool point itself is the nearest point)
            // has no self-motion part: its null-space remainder is rounding, not a direction.
            if z.norm() > NULL_SPACE_SHARE * push.norm() {
                tilt = z.normalize();
                // Self-motion away from the nearest clearances, up to half the task step.
                dq.axpy(0.5 * weight * dq.norm().max(0.1 * options.max_step), &tilt, 1.0);
            }
        }
        // 3. Barrier condition.
        project(&mut dq, &constraints);
        let length = dq.norm();
        if length <= NO_MOTION {
            return Ok(deadlock(result, "the barrier cancels the increment towards the goal"));
        }
        if length > options.max_step {
            dq *= options.max_step / length;
        }
        // 4. Candidates: fast first test, exact swept proof.
        let mut taken = None;
        'scales: for scale in [1.0, 0.5, 0.25, 0.125, 0.0625] {
            let base = &dq * scale;
            let offsets: &[f64] = if tilt.norm() > 0.0 { &[0.0, 1.0, -1.0] } else { &[0.0] };
            for &t in offsets {
                let step = &base + &tilt * (t * 0.5 * base.norm());
                let mut next: Vec<f64> = q.iter().zip(step.iter()).map(|(a, d)| a + d).collect();
                clamp(robot, &mut next);
                result.stats.candidates += 1;
                if fast.is_some_and(|f| f.rejects(&next)) {
                    result.stats.fast_rejected += 1;
                    continue;
                }
                result.stats.exact_sweeps += 1;
                let (sweep, pair) = barrier.checker.swept(&q, &next, &sweep_options)?;
                result.stats.sweep_evaluations += sweep.evaluations;
                if sweep.clear && barrier.checker.check(&next)?.is_free() {
                    taken = Some((next, sweep.lower_bound, pair));
                    break 'scales;
                }
            }
        }
        let Some((next, bound, pair)) = taken else {
            return Ok(deadlock(result, "no increment towards the goal keeps the safe distance"));
        };
        if bound < result.min_margin {
            result.min_margin = bound;
            result.closest = Some(pair);
        }
        q = next;
        result.samples.push(q.clone());
    }
}

fn deadlock(mut result: Approach, reason: &str) -> Approach {
    result.outcome = Outcome::Deadlock;
    result.reason = Some(reason.to_string());
    result
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn hildreth_projection_meets_every_constraint_with_the_least_change() {
        // One constraint x ≥ −0.5·h with h = 0.2: x ≥ −0.1; the step (−1, 0) becomes (−0.1, 0).
        let mut dq = DVector::from_vec(vec![-1.0, 0.0]);
        project(&mut dq, &[(0.2, DVector::from_vec(vec![1.0, 0.0]))]);
        assert!((dq[0] + 0.1).abs() < 1e-12 && dq[1].abs() < 1e-12, "{dq}");
        // An inactive constraint changes nothing.
        let mut dq = DVector::from_vec(vec![0.3, 0.4]);
        project(&mut dq, &[(0.2, DVector::from_vec(vec![1.0, 0.0]))]);
        assert_eq!(dq, DVector::from_vec(vec![0.3, 0.4]));
    }

    #[test]
    fn grown_links_add_the_safe_distance_to_every_radius() {
        let robot = presets::get("varan4").unwrap();
        let grown = grown_robot(&robot, 0.05).unwrap();
        assert!(grown.segment_radii().iter().all(|r| (r - 0.05).abs() < 1e-15), "{:?}", grown.segment_radii());
        assert!(grown_robot(&robot, -1.0).is_err() && grown_robot(&robot, f64::NAN).is_err());
    }

    #[test]
    fn a_free_joint_goal_is_reached_in_straight_increments() {
        let robot = presets::get("planar3").unwrap();
        let scene = Scene::new();
        let start = [0.3, -0.2, -0.1];
        let goal = ApproachGoal::Joints(vec![0.5, -0.5, -0.3]);
        let a = approach(&robot, &scene, &start, &goal, &ApproachOptions::default(), None).unwrap();
        assert_eq!(a.outcome, Outcome::Reached, "{:?}", a.reason);
        assert_eq!(a.samples.last().unwrap(), &vec![0.5, -0.5, -0.3]);
        // √(0.2² + 0.3² + 0.2²) = 0.4123 rad of joint-space distance at 0.05 per increment: 9.
        assert_eq!(a.samples.len(), 10);
    }
}
