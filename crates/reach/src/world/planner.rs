//! Collision-free joint-space motion for any arm: bidirectional RRT-Connect (Kuffner &
//! LaValle 2000) with random shortcutting, seeded and reproducible.
//!
//! * The goal is a joint vector or a tool pose ([`Goal`]); a pose is turned into every
//!   feasible IK solution ([`crate::ik::solve`]), the collision-free ones become the roots of
//!   the goal tree, nearest to the start first (so the nearest reachable one wins ties).
//! * Samples are uniform within the joint limits; unbounded revolute joints are sampled in
//!   `[−π, π]`.
//! * Edges are straight lines in joint space, accepted only when the swept check
//!   ([`CollisionChecker::swept`], conservative advancement with certified rates) proves a
//!   positive clearance over the whole edge: no obstacle thinner than a sampling step can be
//!   tunnelled through.
//! * Randomness comes from a private SplitMix64 generator seeded by [`PlanOptions::seed`]:
//!   the same problem and seed give the same path, unless the wall-time budget cuts the search.

use std::time::{Duration, Instant};

use serde::Serialize;
use thiserror::Error;

use super::collision::link_label;
use super::sweep::SweepOptions;
use super::{CollisionChecker, Scene, Verdict, WorldError};
use crate::ik::{self, IkError, IkOptions, IkTarget};
use crate::model::{JointKind, Robot};
use crate::rng::SplitMix64;

/// What the motion should reach.
#[derive(Debug, Clone, PartialEq)]
pub enum Goal {
    /// A joint vector (radians / metres), within limits.
    Joints(Vec<f64>),
    /// A tool pose or position: every feasible, collision-free IK solution is a goal.
    Target(IkTarget),
}

/// Planner settings. `Default` gives the documented defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Seed of the random generator. Default 1.
    pub seed: u64,
    /// Largest number of RRT-Connect iterations (one random sample each). Default 20 000.
    pub max_iterations: usize,
    /// Wall-time budget of the search (IK and shortcutting excluded). Default 1 s.
    pub max_time: Option<Duration>,
    /// Largest tree extension, Euclidean norm in joint space (radians / metres). Default 0.5.
    pub step: f64,
    /// Random shortcut attempts on the found path. Default 100.
    pub shortcut_attempts: usize,
    /// Options for the IK of a [`Goal::Target`].
    pub ik: IkOptions,
    /// Seed 004's fitted region as a fast first test: a configuration clearly outside it is
    /// rejected without the exact check (only rejected: every edge kept is still proven by
    /// the swept check). Default none.
    pub first_test: Option<super::approach::FastRegion>,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            seed: 1,
            max_iterations: 20_000,
            max_time: Some(Duration::from_secs(1)),
            step: 0.5,
            shortcut_attempts: 100,
            ik: IkOptions::default(),
            first_test: None,
        }
    }
}

/// Search statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlanStats {
    /// RRT-Connect iterations (0 when the straight edge from start to goal was free).
    pub iterations: usize,
    /// Tree nodes over both trees (roots included).
    pub nodes: usize,
    /// Collision checks of single configurations.
    pub checks: usize,
    /// Configurations the first test ([`PlanOptions::first_test`]) rejected without a check.
    pub first_test_rejections: usize,
    /// Waypoints of the raw path, before shortcutting.
    pub raw_waypoints: usize,
    /// Length of the raw path before shortcutting, [`path_length`] (rad / m).
    pub raw_length: f64,
    /// Wall time of the whole call (IK, search, shortcutting), seconds.
    pub time_s: f64,
}

/// A collision-free path.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Plan {
    /// Joint vectors from the start to the goal (both included); consecutive ones are joined
    /// by straight, collision-free joint-space edges.
    pub waypoints: Vec<Vec<f64>>,
    /// Index into the feasible, collision-free IK solutions (sorted nearest to the start
    /// first) of the goal reached; 0 for a joint goal.
    pub goal_index: usize,
    /// How the search went.
    pub stats: PlanStats,
}

/// What blocks a configuration, with names.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Blocked {
    /// A link hits an obstacle.
    Obstacle {
        /// 1-based link number (`dof + 1` is the tool segment).
        link: usize,
        /// The link's name ([`CollisionChecker::link_name`]).
        link_name: String,
        /// Obstacle name.
        obstacle: String,
    },
    /// Two non-adjacent links collide.
    SelfCollision {
        /// 1-based link number.
        link_a: usize,
        /// 1-based link number.
        link_b: usize,
        /// Name of `link_a`.
        name_a: String,
        /// Name of `link_b`.
        name_b: String,
    },
    /// The tool point is outside a tool-zone entry.
    OutsideZone {
        /// Zone name.
        zone: String,
    },
}

impl std::fmt::Display for Blocked {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Blocked::Obstacle { link, link_name, obstacle } => {
                write!(f, "{} collides with obstacle `{obstacle}`", link_label(*link, link_name))
            }
            Blocked::SelfCollision { link_a, link_b, name_a, name_b } => {
                write!(f, "{} and {} collide", link_label(*link_a, name_a), link_label(*link_b, name_b))
            }
            Blocked::OutsideZone { zone } => write!(f, "tool point outside tool zone `{zone}`"),
        }
    }
}

impl Blocked {
    fn from_verdict(v: Verdict, checker: &CollisionChecker) -> Option<Blocked> {
        let scene = checker.scene();
        let name = |k: usize| checker.link_name(k).to_string();
        match v {
            Verdict::Free => None,
            Verdict::Obstacle { link, obstacle } => Some(Blocked::Obstacle {
                link,
                link_name: name(link),
                obstacle: scene.obstacles[obstacle].name.clone(),
            }),
            Verdict::SelfCollision { link_a, link_b } => {
                Some(Blocked::SelfCollision { link_a, link_b, name_a: name(link_a), name_b: name(link_b) })
            }
            Verdict::OutsideZone { zone } => Some(Blocked::OutsideZone { zone: scene.tool_zone[zone].name.clone() }),
        }
    }
}

/// Why no path was returned.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum PlanError {
    /// A bad argument (joint vector length, NaN, limits, option value).
    #[error("{0}")]
    Input(String),
    /// The start configuration is not free.
    #[error("start configuration in collision: {0}")]
    StartInCollision(Blocked),
    /// The goal configuration (or every feasible IK solution of the goal pose) is not free;
    /// the nearest one's reason is given.
    #[error("goal configuration in collision: {0}")]
    GoalInCollision(Blocked),
    /// The goal pose has no IK solution within joint limits.
    #[error("no IK solution for the goal: {0}")]
    NoIkSolution(String),
    /// The iteration or time budget ran out before the trees met.
    #[error("planning budget exhausted after {iterations} iterations, {nodes} nodes, {time_s:.3} s")]
    BudgetExhausted {
        /// Iterations run.
        iterations: usize,
        /// Tree nodes over both trees.
        nodes: usize,
        /// Seconds spent.
        time_s: f64,
    },
    /// A collision-check error.
    #[error(transparent)]
    World(#[from] WorldError),
    /// An IK error.
    #[error(transparent)]
    Ik(#[from] IkError),
}

/// Length of a joint-space polyline: the sum of the Euclidean norms of the steps between
/// consecutive waypoints (radians and metres mixed, as the planner measures edges).
///
/// # Example
/// ```
/// use reach::world::planner::path_length;
/// assert_eq!(path_length(&[vec![0.0, 0.0], vec![3.0, 4.0], vec![3.0, 5.0]]), 6.0);
/// ```
#[must_use]
pub fn path_length(waypoints: &[Vec<f64>]) -> f64 {
    waypoints.windows(2).map(|w| w[0].iter().zip(&w[1]).map(|(a, b)| (b - a) * (b - a)).sum::<f64>().sqrt()).sum()
}

/// Clearance evaluations one edge may take before it is rejected (safe: the search then
/// goes around; an edge that hugs an obstacle for its whole length is not worth proving).
pub const EDGE_EVALUATIONS: usize = 300;

/// Configurations of an edge checked (cheaply, with the broad phase) before its swept proof:
/// the far end, then the midpoints of a coarse-to-fine grid of this many intervals. A blocked
/// edge is usually rejected here after a few checks.
const EDGE_PROBES: usize = 8;

/// Straight-line edge checker: cheap probes, then the swept check, counting evaluations.
struct EdgeChecker<'c, 'a> {
    checker: &'c mut CollisionChecker<'a>,
    checks: usize,
    buf: Vec<f64>,
    first_test: Option<&'c super::approach::FastRegion>,
    rejected: usize,
}

impl EdgeChecker<'_, '_> {
    /// Whether `q` is free (the first test, then one cheap check).
    fn is_free(&mut self, q: &[f64]) -> Result<bool, WorldError> {
        if self.first_test.is_some_and(|f| f.rejects(q)) {
            self.rejected += 1;
            return Ok(false);
        }
        self.checks += 1;
        Ok(self.checker.check(q)?.is_free())
    }

    /// Whether the edge `a → b` is proven free (`a` is assumed already checked).
    fn edge_free(&mut self, a: &[f64], b: &[f64]) -> Result<bool, WorldError> {
        if !self.is_free(b)? {
            return Ok(false);
        }
        let mut buf = std::mem::take(&mut self.buf);
        let mut stride = EDGE_PROBES / 2;
        while stride >= 1 {
            for k in (stride..EDGE_PROBES).step_by(2 * stride) {
                let t = k as f64 / EDGE_PROBES as f64;
                for ((o, x), y) in buf.iter_mut().zip(a).zip(b) {
                    *o = x + t * (y - x);
                }
                if !self.is_free(&buf)? {
                    self.buf = buf;
                    return Ok(false);
                }
            }
            stride /= 2;
        }
        self.buf = buf;
        let options = SweepOptions { closest: false, max_evaluations: EDGE_EVALUATIONS };
        let (swept, _) = self.checker.swept(a, b, &options)?;
        self.checks += swept.evaluations;
        Ok(swept.clear)
    }
}

/// One search tree: flat node storage and parent links (`usize::MAX` for a root).
struct Tree {
    dof: usize,
    q: Vec<f64>,
    parent: Vec<usize>,
}

impl Tree {
    fn new(dof: usize) -> Self {
        Tree { dof, q: Vec::new(), parent: Vec::new() }
    }

    fn len(&self) -> usize {
        self.parent.len()
    }

    fn node(&self, i: usize) -> &[f64] {
        &self.q[i * self.dof..(i + 1) * self.dof]
    }

    fn push(&mut self, q: &[f64], parent: usize) -> usize {
        self.q.extend_from_slice(q);
        self.parent.push(parent);
        self.parent.len() - 1
    }

    fn nearest(&self, q: &[f64]) -> usize {
        let mut best = (0, f64::INFINITY);
        for (i, node) in self.q.chunks_exact(self.dof).enumerate() {
            let d: f64 = node.iter().zip(q).map(|(a, b)| (a - b) * (a - b)).sum();
            if d < best.1 {
                best = (i, d);
            }
        }
        best.0
    }

    /// Node `i` and its ancestors up to the root, `i` first; also the root's index.
    fn branch(&self, mut i: usize) -> (Vec<Vec<f64>>, usize) {
        let mut out = vec![self.node(i).to_vec()];
        while self.parent[i] != usize::MAX {
            i = self.parent[i];
            out.push(self.node(i).to_vec());
        }
        (out, i)
    }
}

#[derive(PartialEq, Eq)]
enum Extend {
    Trapped,
    Advanced(usize),
    Reached(usize),
}

fn extend(tree: &mut Tree, target: &[f64], step: f64, edges: &mut EdgeChecker) -> Result<Extend, WorldError> {
    let near = tree.nearest(target);
    let from = tree.node(near).to_vec();
    let d = from.iter().zip(target).map(|(a, b)| (a - b) * (a - b)).sum::<f64>().sqrt();
    let (q_new, reached) = if d <= step {
        (target.to_vec(), true)
    } else {
        (from.iter().zip(target).map(|(a, b)| a + (b - a) * step / d).collect(), false)
    };
    if !edges.edge_free(&from, &q_new)? {
        return Ok(Extend::Trapped);
    }
    let i = tree.push(&q_new, near);
    Ok(if reached { Extend::Reached(i) } else { Extend::Advanced(i) })
}

fn check_joints(robot: &Robot, q: &[f64], what: &str) -> Result<(), PlanError> {
    if q.len() != robot.dof() {
        return Err(PlanError::Input(format!("{what} has {} joint values, the robot has {}", q.len(), robot.dof())));
    }
    for (i, (v, j)) in q.iter().zip(robot.joints()).enumerate() {
        if !v.is_finite() {
            return Err(PlanError::Input(format!("{what} joint {} ({}) must be finite, got {v}", i + 1, j.name)));
        }
        if !j.limits.contains(*v, crate::tolerance::LIMIT_SLACK) {
            return Err(PlanError::Input(format!(
                "{what} joint {} ({}) = {v} is outside its limits [{}, {}]",
                i + 1,
                j.name,
                j.limits.lower,
                j.limits.upper
            )));
        }
    }
    Ok(())
}

/// Sampling box of each joint (limits; `[−π, π]` for unbounded revolute sides).
fn sampling_ranges(robot: &Robot) -> Result<Vec<(f64, f64)>, PlanError> {
    robot
        .joints()
        .iter()
        .enumerate()
        .map(|(i, j)| {
            let (lo, hi) = match j.kind {
                JointKind::Revolute => (
                    if j.limits.lower.is_finite() { j.limits.lower } else { -std::f64::consts::PI },
                    if j.limits.upper.is_finite() { j.limits.upper } else { std::f64::consts::PI },
                ),
                JointKind::Prismatic => (j.limits.lower, j.limits.upper),
            };
            if !(lo.is_finite() && hi.is_finite()) || lo > hi {
                return Err(PlanError::Input(format!(
                    "joint {} ({}) has no finite sampling range: prismatic joints need both limits",
                    i + 1,
                    j.name
                )));
            }
            Ok((lo, hi))
        })
        .collect()
}

/// Plans a collision-free joint-space path of `robot` in `scene` from `start` to `goal`.
///
/// # Errors
/// [`PlanError::Input`] for a bad start/goal vector or option, [`PlanError::StartInCollision`]
/// / [`PlanError::GoalInCollision`] naming the link and obstacle, [`PlanError::NoIkSolution`]
/// when the goal pose has no solution within limits, [`PlanError::BudgetExhausted`] when the
/// trees do not meet within the iteration or time budget; [`PlanError::World`] for a scene
/// with a moving obstacle (the planner works in joint space, untimed:
/// [`Scene::require_fixed`]).
///
/// # Example
/// ```
/// use reach::model::{LinkGeometry, Robot, RobotSpec, presets};
/// use reach::world::{Scene, Shape};
/// use reach::world::planner::{Goal, PlanOptions, plan};
/// let ur5 = presets::get("ur5").unwrap();
/// let robot = Robot::new(RobotSpec { links: vec![LinkGeometry { radius: 0.03 }; 6], ..ur5.spec().clone() }).unwrap();
/// let scene = Scene::new()
///     .with_obstacle("ball", Shape::Sphere { center: nalgebra::Vector3::new(0.45, 0.0, 0.45), radius: 0.1 })
///     .unwrap();
/// let start = [0.8, -1.2, 1.2, -1.5, -1.5, 0.0];
/// let goal = Goal::Joints(vec![-0.8, -1.2, 1.2, -1.5, -1.5, 0.0]);
/// let path = plan(&robot, &scene, &start, &goal, &PlanOptions::default()).unwrap();
/// assert_eq!(path.waypoints.first().unwrap().as_slice(), &start);
/// ```
pub fn plan(
    robot: &Robot,
    scene: &Scene,
    start: &[f64],
    goal: &Goal,
    options: &PlanOptions,
) -> Result<Plan, PlanError> {
    let t0 = Instant::now();
    if !(options.step.is_finite() && options.step > 0.0) {
        return Err(PlanError::Input(format!("step must be positive, got {}", options.step)));
    }
    scene.require_fixed("the planner (it plans in joint space, not in time)")?;
    check_joints(robot, start, "start")?;
    let ranges = sampling_ranges(robot)?;
    let dof = robot.dof();
    let mut checker = CollisionChecker::new(robot, scene);
    if let Some(b) = Blocked::from_verdict(checker.check(start)?, &checker) {
        return Err(PlanError::StartInCollision(b));
    }

    // Goals: the joint vector, or the free feasible IK solutions nearest first.
    let goals: Vec<Vec<f64>> = match goal {
        Goal::Joints(q) => {
            check_joints(robot, q, "goal")?;
            if let Some(b) = Blocked::from_verdict(checker.check(q)?, &checker) {
                return Err(PlanError::GoalInCollision(b));
            }
            vec![q.clone()]
        }
        Goal::Target(target) => {
            let mut ik_options = options.ik.clone();
            if ik_options.seed.is_none() {
                ik_options.seed = Some(start.to_vec());
            }
            let sols = ik::solve(robot, target, &ik_options)?;
            let mut feasible: Vec<Vec<f64>> = sols.feasible().map(|s| s.q.clone()).collect();
            if feasible.is_empty() {
                let why = sols.failure.map_or_else(|| "no solution".to_string(), |f| f.to_string());
                return Err(PlanError::NoIkSolution(why));
            }
            let dist = |q: &Vec<f64>| q.iter().zip(start).map(|(a, b)| (a - b) * (a - b)).sum::<f64>();
            feasible.sort_by(|a, b| dist(a).total_cmp(&dist(b)));
            let mut free = Vec::new();
            let mut first_block = None;
            for q in feasible {
                match Blocked::from_verdict(checker.check(&q)?, &checker) {
                    None => free.push(q),
                    Some(b) => {
                        first_block.get_or_insert(b);
                    }
                }
            }
            match (free.is_empty(), first_block) {
                (true, Some(b)) => return Err(PlanError::GoalInCollision(b)),
                _ => free,
            }
        }
    };

    let mut edges = EdgeChecker {
        checker: &mut checker,
        checks: 0,
        buf: vec![0.0; dof],
        first_test: options.first_test.as_ref(),
        rejected: 0,
    };
    let mut rng = SplitMix64(options.seed);

    // The straight edge first, nearest goal first.
    let mut raw: Option<(Vec<Vec<f64>>, usize)> = None;
    for (gi, g) in goals.iter().enumerate() {
        if edges.edge_free(start, g)? {
            raw = Some((vec![start.to_vec(), g.clone()], gi));
            break;
        }
    }

    let mut iterations = 0;
    let mut start_tree = Tree::new(dof);
    start_tree.push(start, usize::MAX);
    let mut goal_tree = Tree::new(dof);
    for g in &goals {
        goal_tree.push(g, usize::MAX);
    }
    if raw.is_none() {
        let mut sample = vec![0.0; dof];
        let mut a_is_start = true;
        while raw.is_none() {
            let nodes = start_tree.len() + goal_tree.len();
            if iterations >= options.max_iterations
                || options.max_time.is_some_and(|t| t0.elapsed() > t)
                || options.ik.cancel.is_cancelled()
            {
                return Err(PlanError::BudgetExhausted { iterations, nodes, time_s: t0.elapsed().as_secs_f64() });
            }
            iterations += 1;
            for (s, &(lo, hi)) in sample.iter_mut().zip(&ranges) {
                *s = lo + (hi - lo) * rng.next_f64();
            }
            let (a, b) = if a_is_start { (&mut start_tree, &mut goal_tree) } else { (&mut goal_tree, &mut start_tree) };
            let new = match extend(a, &sample, options.step, &mut edges)? {
                Extend::Trapped => None,
                Extend::Advanced(i) | Extend::Reached(i) => Some(i),
            };
            if let Some(ia) = new {
                let q_a = a.node(ia).to_vec();
                loop {
                    match extend(b, &q_a, options.step, &mut edges)? {
                        Extend::Advanced(_) => continue,
                        Extend::Trapped => break,
                        Extend::Reached(ib) => {
                            let (ia, ib) = if a_is_start { (ia, ib) } else { (ib, ia) };
                            let (mut path, _) = start_tree.branch(ia);
                            path.reverse();
                            let (to_goal, root) = goal_tree.branch(ib);
                            // The meeting node is in both halves: drop the duplicate.
                            path.extend(to_goal.into_iter().skip(1));
                            raw = Some((path, root));
                            break;
                        }
                    }
                }
            }
            a_is_start = !a_is_start;
        }
    }
    let (mut path, goal_index) = raw.unwrap_or_default();
    let raw_waypoints = path.len();
    let raw_length = path_length(&path);

    // Random shortcutting: replace the section between two waypoints by a straight edge.
    for _ in 0..options.shortcut_attempts {
        if path.len() < 3 {
            break;
        }
        let i = rng.below(path.len() - 2);
        let j = i + 2 + rng.below(path.len() - i - 2);
        if edges.edge_free(&path[i], &path[j])? {
            path.drain(i + 1..j);
        }
    }

    Ok(Plan {
        waypoints: path,
        goal_index,
        stats: PlanStats {
            iterations,
            nodes: start_tree.len() + goal_tree.len(),
            checks: edges.checks,
            first_test_rejections: edges.rejected,
            raw_waypoints,
            raw_length,
            time_s: t0.elapsed().as_secs_f64(),
        },
    })
}
