//! Decisions: criteria, multi-criteria methods (weighted sum, TOPSIS, VIKOR, Pareto filter)
//! and task sequencing.
//!
//! - [`mcdm`]: a [`DecisionMatrix`] of candidates × [`Criterion`]s ranked by
//!   [`Method::WeightedSum`], [`Method::Topsis`] or [`Method::Vikor`], plus a Pareto filter.
//! - [`ik_criteria`]: criteria computed for a set of IK solutions and [`choose`] among them.
//! - [`motion_criteria`]: criteria of whole motions (J1, J2, duration, peak rates, limits,
//!   manipulability, clearance, tool path length), [`choose_motion`], and [`TrackChooser`]
//!   for path tracking's per-interval choice of configuration.
//! - [`detour_choice`]: seed 000's detour around a point obstacle, both sides planned and
//!   ranked ([`detour_choice::choose_detour`]).
//! - [`sequence`]: ordering of targets ("visiting") and pick-and-place trips ("collection")
//!   on a cost matrix, exact (Held–Karp) for small sets and heuristic beyond (seed 001 §8–9).

pub mod detour_choice;
pub mod ik_criteria;
pub mod mcdm;
pub mod motion_criteria;
pub mod sequence;

pub use ik_criteria::{IkCriterion, choose, ik_matrix};
pub use mcdm::{Criterion, DecisionMatrix, Direction, Method, RankedCandidate, Ranking, VikorAcceptance, rank};
pub use motion_criteria::{MotionCriterion, SampledMotion, TrackChooser, choose_motion, motion_matrix};

use crate::kinematics::KinematicsError;

/// Errors of the decision module.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DecideError {
    /// A decision matrix needs at least one criterion.
    #[error("no criteria given")]
    NoCriteria,
    /// A decision needs at least one candidate.
    #[error("no candidates to choose from (empty candidate set)")]
    NoCandidates,
    /// A row of the decision matrix has the wrong number of values.
    #[error("candidate {candidate}: expected {expected} criterion values, got {found}")]
    RowLength {
        /// Candidate index.
        candidate: usize,
        /// Number of criteria.
        expected: usize,
        /// Values given.
        found: usize,
    },
    /// A matrix value is NaN or infinite.
    #[error("candidate {candidate}, criterion '{criterion}': value {value} is not finite")]
    NonFiniteValue {
        /// Candidate index.
        candidate: usize,
        /// Criterion name.
        criterion: String,
        /// The value.
        value: f64,
    },
    /// The number of weights differs from the number of criteria.
    #[error("expected {expected} weights (one per criterion), got {found}")]
    WeightCount {
        /// Number of criteria.
        expected: usize,
        /// Weights given.
        found: usize,
    },
    /// A weight is negative, NaN or infinite.
    #[error("weight of criterion '{criterion}' is {value}; weights must be finite and >= 0")]
    InvalidWeight {
        /// Criterion name.
        criterion: String,
        /// The weight.
        value: f64,
    },
    /// Every weight is zero.
    #[error("all weights are zero")]
    ZeroWeights,
    /// A reference configuration or joint-weight vector has the wrong length or bad values.
    #[error("{what}: {reason}")]
    BadVector {
        /// Which input.
        what: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A kinematics computation failed (wrong joint count, non-finite joint value).
    #[error("kinematics: {0}")]
    Kinematics(#[from] KinematicsError),
    /// A cost matrix is not square or does not match the number of targets.
    #[error("cost matrix '{what}': {reason}")]
    CostShape {
        /// Which matrix.
        what: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// A cost or duration is negative or NaN (infinite means "impossible" and is allowed).
    #[error("cost matrix '{what}' entry ({from}, {to}) is {value}; costs must be >= 0 (or +inf)")]
    InvalidCost {
        /// Which matrix.
        what: &'static str,
        /// Row.
        from: usize,
        /// Column.
        to: usize,
        /// The value.
        value: f64,
    },
    /// A criterion is zero for every candidate, so it cannot discriminate.
    #[error("criterion '{criterion}' is 0 for every candidate (all-zero column); it cannot discriminate, drop it")]
    ZeroColumn {
        /// Criterion name.
        criterion: String,
    },
    /// A criterion name is not known.
    #[error("unknown criterion '{name}' (known: {known})")]
    UnknownCriterion {
        /// The name given.
        name: String,
        /// The known names, comma-separated.
        known: String,
    },
    /// A criterion cannot be set up or evaluated (missing speed limits, no scene, bad motion).
    #[error("criterion '{criterion}': {reason}")]
    Criterion {
        /// Criterion name.
        criterion: String,
        /// What is wrong.
        reason: String,
    },
    /// A time budget is negative or NaN.
    #[error("time budget {0} s must be finite and >= 0")]
    InvalidBudget(f64),
    /// A dynamics quantity (mechanical energy of a leg) could not be computed, e.g. the robot
    /// has no link masses.
    #[error("dynamics: {0}")]
    Dynamics(#[from] crate::effort::dynamics::DynamicsError),
}
