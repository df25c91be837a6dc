//! Inverse kinematics: every closed form of the seeds with all branches, and a numeric solver.
//!
//! Every solver returns the same [`IkSolutions`]: all branches found, each verified by
//! forward kinematics, labelled ([`Branch`]), flagged for limits and singularities, and a
//! typed [`IkFailure`] when none is within limits. "No solution" is an answer, not an error;
//! [`IkError`] is for bad input (NaN, wrong length) and for asking a closed form to solve a
//! robot it does not fit.
//!
//! | solver | robots | seed |
//! |---|---|---|
//! | [`planar::PlanarRedundant`] | three parallel revolute axes in a plane (`planar3`) | 000 |
//! | [`yaw_two_link::YawTwoLink`] | base yaw + two links in a vertical plane (`log-loader`) | 000 appendix |
//! | [`yaw_planar3::YawPlanar3`] | base yaw + three links in a vertical plane (`varan4`) | 004 |
//! | [`two_link_wrist::TwoLinkWrist`] | two-link arm + spherical wrist, no offsets (`spbu6`) | 001 |
//! | [`spherical_wrist::SphericalWrist`] | PUMA-type 6R with spherical wrist (`puma560`) | 002 |
//! | [`parallel_axes::ParallelAxes`] | RERR 6R, axes 2-3-4 parallel (`welder6r`) | 003 |
//! | [`numeric::Numeric`] | any chain | — |
//!
//! [`solve`] picks a solver from the robot's structure ([`SolverKind::detect`]) or uses the
//! one named; a robot with no closed form falls back to the numeric solver.
//!
//! # Closed forms from the geometry
//!
//! The 6R closed forms ([`two_link_wrist`], [`spherical_wrist`], [`parallel_axes`]) read a
//! standard DH table. A robot described otherwise (URDF with any joint origins, rpy and axis
//! signs; MDH) is read through its standard-DH equivalent ([`Robot::dh_equivalent`]: the table
//! of the common normals of its joint axes at q = 0, with a base and a tool transform, θ
//! offsets and flipped joints, checked by forward kinematics to
//! [`DH_EQUIVALENT`](crate::tolerance::DH_EQUIVALENT)), so a solver fits whatever file the
//! robot came from when its axes fit. The joint values are the robot's own (the equivalent's
//! joints are the robot's, flipped and offset), and every solution is verified against the
//! robot itself by the same FK check as any other (`finish`), with its limits. A robot in
//! standard DH is read by its own table. Limits: revolute chains without mimic joints; a
//! chain whose equivalent does not fit (or does not exist) gets the numeric solver, and
//! [`SolverKind::build`]'s error names the failed condition "in the standard-DH equivalent".
//!
//! Path tracking ([`crate::motion::tracking`]) asks a solver, through [`IkSolver`], what it
//! needs to know of it: the configurations to track ([`IkSolver::configurations`]), whether
//! labels name branches ([`IkSolver::enumerates_all_branches`]) and any closed-form
//! singularity measures ([`IkSolver::singularity_measures`]).

mod solution;

pub mod numeric;
pub mod parallel_axes;
pub mod planar;
pub mod planar_scan;
pub mod spherical_wrist;
pub mod two_link_wrist;
pub mod yaw_planar3;
pub mod yaw_two_link;

pub use solution::{Branch, IkFailure, IkSolution, IkSolutions, Label, LimitViolation, SingularityKind};
pub(crate) use solution::{
    Candidate, ChainFrame, FlagBits, LaneSolve, Raw6, Raw6Set, finish, finish_into, solve_at, solved,
};

use nalgebra::{Isometry3, Point3};
use thiserror::Error;

use crate::kinematics::KinematicsError;
use crate::model::Robot;

/// What the tool should reach.
#[derive(Debug, Clone, PartialEq)]
pub enum IkTarget {
    /// Full pose of the tool in the world frame.
    Pose(Isometry3<f64>),
    /// Tool position only (arms that cannot set orientation, e.g. seed 000's planar arm).
    Position(Point3<f64>),
}

impl IkTarget {
    /// The target position.
    #[must_use]
    pub fn position(&self) -> Point3<f64> {
        match self {
            IkTarget::Pose(p) => Point3::from(p.translation.vector),
            IkTarget::Position(p) => *p,
        }
    }

    /// Rejects NaN and infinity.
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] naming the component.
    pub fn validate(&self) -> Result<(), IkError> {
        let p = self.position();
        for (name, v) in [("x", p.x), ("y", p.y), ("z", p.z)] {
            if !v.is_finite() {
                return Err(IkError::InvalidInput(format!("target {name} must be finite, got {v}")));
            }
        }
        if let IkTarget::Pose(pose) = self
            && pose.rotation.coords.iter().any(|v| !v.is_finite())
        {
            return Err(IkError::InvalidInput("target orientation contains NaN or infinity".into()));
        }
        Ok(())
    }
}

/// Options shared by the solvers. `Default` gives the documented defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct IkOptions {
    /// The current (previous) configuration: kept for undetermined angles at singularities
    /// (e.g. the wrist roll when θ5 = 0) and used as the numeric solver's first guess.
    pub seed: Option<Vec<f64>>,
    /// Value of the redundancy parameter for redundant arms (radians; e.g. the absolute angle
    /// of the last link of a planar 3-link arm). `None`: sample the self-motion.
    pub free_parameter: Option<f64>,
    /// Step for sampling a self-motion manifold (radians). Default 1°.
    pub redundancy_step: f64,
    /// Numeric solver: iterations per start. Default 200.
    pub max_iterations: usize,
    /// Numeric solver: number of starts (the seed, then deterministic pseudo-random ones). Default 16.
    pub restarts: usize,
    /// Numeric solver: which task axes count, acceptance tolerances, wall-time budget and
    /// search mode ([`numeric::NumericOptions`]). Default: full pose (position only for a
    /// position target), 1e-6 m / 1e-6 rad, no time limit, every distinct solution found.
    pub numeric: numeric::NumericOptions,
    /// Stops the numeric solver early, as if its time budget were spent ([`crate::Cancel`]).
    /// Default: never.
    pub cancel: crate::Cancel,
}

impl Default for IkOptions {
    fn default() -> Self {
        IkOptions {
            seed: None,
            free_parameter: None,
            redundancy_step: 1f64.to_radians(),
            max_iterations: 200,
            restarts: 16,
            numeric: numeric::NumericOptions::default(),
            cancel: crate::Cancel::default(),
        }
    }
}

/// Bad input or a solver that does not fit the robot.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum IkError {
    /// The target or an option is NaN, infinite or out of its domain.
    #[error("invalid IK input: {0}")]
    InvalidInput(String),
    /// The named closed-form solver does not fit this robot's structure.
    #[error("solver `{solver}` does not fit robot `{robot}`: {reason}")]
    Unsupported {
        /// Solver name.
        solver: &'static str,
        /// Robot name.
        robot: String,
        /// Which structural condition failed.
        reason: String,
    },
    /// The seed configuration (or a kinematics call) was rejected.
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}

/// A solver for one family of robots.
pub trait IkSolver {
    /// Short name (`spherical-wrist`).
    fn name(&self) -> &'static str;
    /// Every solution for `target`.
    ///
    /// # Errors
    /// [`IkError`] for invalid input.
    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError>;

    /// [`IkSolver::solve`] into a reused `out`, for real-time loops: the result is exactly
    /// `solve`'s whatever `out` held before, but `out`'s buffers are kept (overwritten in
    /// place; see [`IkSolutions`]), so that the closed forms allocate nothing per solve once
    /// `out` has served a solve with as many solutions and limit violations. On error `out`
    /// holds no meaningful result (its buffers are kept).
    ///
    /// The closed forms implement `solve` by this lean path (one code path for both); the
    /// default implementation, for solvers without one (the numeric solver), is
    /// `*out = self.solve(..)?`.
    ///
    /// # Errors
    /// [`IkError`] for invalid input, as [`IkSolver::solve`].
    ///
    /// # Example
    /// ```
    /// use reach::ik::{IkOptions, IkSolutions, IkSolver, IkTarget, SolverKind};
    /// let puma = reach::model::presets::get("puma560").unwrap();
    /// let solver = SolverKind::SphericalWrist.build(&puma).unwrap();
    /// let options = IkOptions::default();
    /// let mut out = IkSolutions::default();
    /// for q in [[0.3, 0.5, -0.4, 0.7, 0.9, -0.2], [0.1, -0.2, 0.3, -0.4, 0.5, -0.6]] {
    ///     let target = IkTarget::Pose(puma.fk(&q).unwrap());
    ///     solver.solve_into(&puma, &target, &options, &mut out).unwrap();
    ///     assert_eq!(out, solver.solve(&puma, &target, &options).unwrap());
    /// }
    /// ```
    fn solve_into(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError> {
        *out = self.solve(robot, target, options)?;
        Ok(())
    }

    /// The solutions of one branch: `solve(robot, target, options)?.restricted_to(branch)`
    /// ([`IkSolutions::restricted_to`]) — the solutions labelled exactly `branch`, verified,
    /// wrapped into limits and flagged as by [`IkSolver::solve`], and the failure restated for
    /// them ([`IkFailure::BranchAbsent`] when other branches solve the target but this one does
    /// not). The default implementation is exactly that; the closed forms of 6R arms
    /// ([`spherical_wrist`], [`two_link_wrist`], [`parallel_axes`]) override it to compute and
    /// FK-verify only the requested branch (path tracking follows one branch per sample),
    /// falling back to the full solve where branches may merge (singular configurations).
    ///
    /// # Errors
    /// [`IkError`] for invalid input, as [`IkSolver::solve`].
    ///
    /// # Example
    /// ```
    /// use reach::ik::{IkOptions, IkSolver, IkTarget, SolverKind};
    /// let puma = reach::model::presets::get("puma560").unwrap();
    /// let solver = SolverKind::detect(&puma).build(&puma).unwrap();
    /// let target = IkTarget::Pose(puma.fk(&[0.3, 0.5, -0.4, 0.7, 0.9, -0.2]).unwrap());
    /// let all = solver.solve(&puma, &target, &IkOptions::default()).unwrap();
    /// let branch = &all.solutions[5].branch;
    /// let one = solver.solve_branch(&puma, &target, branch, &IkOptions::default()).unwrap();
    /// assert_eq!(one.solutions, vec![all.solutions[5].clone()]);
    /// ```
    fn solve_branch(
        &self,
        robot: &Robot,
        target: &IkTarget,
        branch: &Branch,
        options: &IkOptions,
    ) -> Result<IkSolutions, IkError> {
        Ok(self.solve(robot, target, options)?.restricted_to(branch))
    }

    /// The configurations a path is tracked in when the caller names none
    /// ([`crate::motion::tracking`]), in the default order: the first is the default
    /// configuration. Each is a branch filter — the `key=value` pairs a solution's label must
    /// carry ([`Branch`]); the empty filter matches every solution.
    ///
    /// The default implementation is one empty filter: any solution, followed by nearness
    /// (what a search such as the numeric solver can offer). The closed forms list their
    /// branches in the order [`IkSolver::solve`] returns them (seed 003's arm lists the paper's
    /// two configurations, `config=+β` first).
    ///
    /// # Example
    /// ```
    /// use reach::ik::{IkSolver, SolverKind};
    /// let welder = reach::model::presets::get("welder6r").unwrap();
    /// let solver = SolverKind::detect(&welder).build(&welder).unwrap();
    /// let labels: Vec<String> = solver.configurations(&welder).iter().map(ToString::to_string).collect();
    /// assert_eq!(labels, ["shoulder=w config=+β wrist=e5", "shoulder=w config=−β wrist=e5"]);
    /// ```
    fn configurations(&self, robot: &Robot) -> Vec<Branch> {
        let _ = robot;
        vec![Branch::default()]
    }

    /// Whether [`IkSolver::solve`] returns every solution of a target, each labelled with the
    /// name of its branch, so that a label names the same continuous branch at neighbouring
    /// targets (the closed forms of non-redundant arms). Path tracking then follows a
    /// configuration by the full label of its first solution ([`IkSolver::solve_branch`]).
    ///
    /// `false` (the default) for a search, whose labels name the start that found a solution
    /// (the numeric solver), and for a sampled self-motion, whose labels carry the sampled
    /// parameter (the redundant planar arms): tracking keeps the configuration's filter and
    /// follows the solution nearest to the previous joint vector, passed as the seed; a seeded
    /// solve then makes one start only ([`IkOptions::restarts`]): it follows the seed instead of
    /// searching afresh.
    fn enumerates_all_branches(&self) -> bool {
        false
    }

    /// Closed-form singularity measures of full-pose targets for the given configurations, to
    /// be scanned along a path (notes 003 §3.6, §4 steps 2–3), or `None` (the default): path
    /// tracking then scans the relative smallest singular value of the Jacobian.
    fn singularity_measures(&self, robot: &Robot, configurations: &[Branch]) -> Option<Box<dyn SingularityMeasures>> {
        let _ = (robot, configurations);
        None
    }
}

/// Singularity measures a solver computes in closed form for path tracking
/// ([`IkSolver::singularity_measures`]), each for one kind of singular position.
pub trait SingularityMeasures {
    /// What each measure detects, in the order of the values of [`SingularityMeasures::at`].
    fn kinds(&self) -> &[SingularityKind];

    /// The measures of a tool pose, in the order of [`SingularityMeasures::kinds`]: each
    /// dimensionless, non-negative where it applies and 0 at a singular position of its kind;
    /// `None` or negative where it does not apply (e.g. the target is out of reach of the
    /// branch it measures).
    ///
    /// # Errors
    /// [`IkError`] for a non-finite pose.
    fn at(&self, robot: &Robot, pose: &Isometry3<f64>) -> Result<Vec<Option<f64>>, IkError>;
}

/// The solvers, by name. In JSON (requests and reports) a solver is its
/// [`as_str`](SolverKind::as_str) name, e.g. `"spherical-wrist"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum SolverKind {
    /// Planar redundant 3-link arm ([`planar::PlanarRedundant`]).
    Planar,
    /// Base yaw and a planar two-link arm ([`yaw_two_link::YawTwoLink`]).
    YawTwoLink,
    /// Base yaw and a planar three-link arm ([`yaw_planar3::YawPlanar3`]).
    YawPlanar3,
    /// Two links and a wrist ([`two_link_wrist::TwoLinkWrist`]).
    TwoLinkWrist,
    /// 6R arm with a spherical wrist ([`spherical_wrist::SphericalWrist`]).
    SphericalWrist,
    /// 6R arm with three parallel axes ([`parallel_axes::ParallelAxes`]).
    ParallelAxes,
    /// Damped least squares with restarts, any serial chain ([`numeric::Numeric`]).
    Numeric,
}

impl SolverKind {
    /// Every solver, in the order [`SolverKind::detect`] tries them.
    pub const ALL: [SolverKind; 7] = [
        SolverKind::Planar,
        SolverKind::YawTwoLink,
        SolverKind::YawPlanar3,
        SolverKind::TwoLinkWrist,
        SolverKind::SphericalWrist,
        SolverKind::ParallelAxes,
        SolverKind::Numeric,
    ];

    /// Name used on the command line.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            SolverKind::Planar => "planar",
            SolverKind::YawTwoLink => "yaw-two-link",
            SolverKind::YawPlanar3 => "yaw-planar3",
            SolverKind::TwoLinkWrist => "two-link-wrist",
            SolverKind::SphericalWrist => "spherical-wrist",
            SolverKind::ParallelAxes => "parallel-axes",
            SolverKind::Numeric => "numeric",
        }
    }

    /// Parses a name as printed by [`SolverKind::as_str`].
    #[must_use]
    pub fn parse(name: &str) -> Option<SolverKind> {
        SolverKind::ALL.into_iter().find(|k| k.as_str() == name)
    }

    /// Builds this solver for `robot`.
    ///
    /// # Errors
    /// [`IkError::Unsupported`] when the robot's structure does not fit the closed form.
    pub fn build(self, robot: &Robot) -> Result<Box<dyn IkSolver>, IkError> {
        Ok(match self {
            SolverKind::Planar => Box::new(planar::PlanarRedundant::from_robot(robot)?),
            SolverKind::YawTwoLink => Box::new(yaw_two_link::YawTwoLink::from_robot(robot)?),
            SolverKind::YawPlanar3 => Box::new(yaw_planar3::YawPlanar3::from_robot(robot)?),
            SolverKind::TwoLinkWrist => Box::new(two_link_wrist::TwoLinkWrist::from_robot(robot)?),
            SolverKind::SphericalWrist => Box::new(spherical_wrist::SphericalWrist::from_robot(robot)?),
            SolverKind::ParallelAxes => Box::new(parallel_axes::ParallelAxes::from_robot(robot)?),
            SolverKind::Numeric => Box::new(numeric::Numeric::from_robot(robot)?),
        })
    }

    /// The first closed form that fits `robot`, or [`SolverKind::Numeric`].
    #[must_use]
    pub fn detect(robot: &Robot) -> SolverKind {
        SolverKind::ALL.into_iter().find(|k| k.build(robot).is_ok()).unwrap_or(SolverKind::Numeric)
    }
}

/// Solves IK with the solver that fits the robot (see [`SolverKind::detect`]).
///
/// # Errors
/// [`IkError`] for invalid input.
///
/// # Example
/// ```
/// use reach::ik::{self, IkOptions, IkTarget};
/// let puma = reach::model::presets::get("puma560").unwrap();
/// let q = [0.1, 0.4, -0.3, 0.5, 0.6, 0.7];
/// let target = IkTarget::Pose(puma.fk(&q).unwrap());
/// let all = ik::solve(&puma, &target, &IkOptions::default()).unwrap();
/// assert!(all.solutions.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// ```
pub fn solve(robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
    SolverKind::detect(robot).build(robot)?.solve(robot, target, options)
}

/// Checks of [`IkSolver::configurations`] shared by the solvers' unit tests.
#[cfg(test)]
pub(crate) mod configuration_order {
    use std::f64::consts::PI;

    use nalgebra::Point3;

    use super::{Branch, IkOptions, IkSolver, IkTarget};
    use crate::model::Robot;
    use crate::rng::SplitMix64;

    /// The labels of `solver.configurations(robot)` as text.
    pub(crate) fn labels(solver: &dyn IkSolver, robot: &Robot) -> Vec<String> {
        solver.configurations(robot).iter().map(ToString::to_string).collect()
    }

    /// Solves the poses of `cases` random joint vectors (angles uniform in (−π, π]) and checks
    /// that the solutions come in the order of the configurations: each solution matches at
    /// most one configuration, and those matched increase strictly along the solutions (poses
    /// with a singular solution, where branches merge, are skipped). Returns how many poses had
    /// a solution of every configuration.
    pub(crate) fn check(solver: &dyn IkSolver, robot: &Robot, cases: usize) -> usize {
        check_with(solver, robot, cases, false, &IkOptions::default())
    }

    /// [`check`] with position targets when `position_only`, and the given options.
    pub(crate) fn check_with(
        solver: &dyn IkSolver,
        robot: &Robot,
        cases: usize,
        position_only: bool,
        options: &IkOptions,
    ) -> usize {
        let configurations = solver.configurations(robot);
        let matches = |label: &Branch, filter: &Branch| filter.0.iter().all(|(k, v)| label.get(k) == Some(v.as_str()));
        let mut rng = SplitMix64(0xc0f1_6000 ^ robot.dof() as u64);
        let mut complete = 0;
        for _ in 0..cases {
            let q: Vec<f64> = (0..robot.dof()).map(|_| (2.0 * rng.next_f64() - 1.0) * PI).collect();
            let pose = robot.fk(&q).unwrap();
            let target = if position_only {
                IkTarget::Position(Point3::from(pose.translation.vector))
            } else {
                IkTarget::Pose(pose)
            };
            let sols = solver.solve(robot, &target, options).unwrap();
            if sols.solutions.iter().any(|s| !s.singularities.is_empty()) {
                continue;
            }
            let mut order = Vec::new();
            for s in &sols.solutions {
                let found: Vec<usize> =
                    (0..configurations.len()).filter(|&c| matches(&s.branch, &configurations[c])).collect();
                assert!(found.len() <= 1, "{}: `{}` matches configurations {found:?}", robot.name(), s.branch);
                order.extend(found);
            }
            assert!(order.windows(2).all(|w| w[0] < w[1]), "{}: configurations {order:?} at q = {q:?}", robot.name());
            complete += usize::from(order.len() == configurations.len());
        }
        complete
    }
}
