//! Criteria for choosing among inverse-kinematics solutions, and [`choose`].
//!
//! Each [`IkCriterion`] turns one [`IkSolution`] into a number with a unit and a preferred
//! direction; [`ik_matrix`] builds the [`DecisionMatrix`] and [`choose`] ranks it.

use serde::Serialize;

use super::DecideError;
use super::mcdm::{Criterion, DecisionMatrix, Direction, Method, Ranking, rank};
use crate::ik::IkSolution;
use crate::kinematics::Manipulability;
use crate::model::Robot;

/// Joint resolution `δq` of the [`IkCriterion::Accuracy`] criterion by default: 0.01° (in
/// radians; the same number in metres for prismatic joints) — seed 000's angle step `Δα`, the
/// finest joint increment any seed computes with. The criterion scales linearly with it, so
/// it changes no ranking, only the value a requirement is compared with.
pub const DEFAULT_JOINT_RESOLUTION: f64 = 0.01 * std::f64::consts::PI / 180.0;

/// A criterion evaluated on one IK solution.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IkCriterion {
    /// Weighted joint change from a reference configuration (seeds 000/001):
    /// `Σ wᵢ |Δqᵢ|`, each `Δqᵢ` by [`Joint::difference`](crate::model::Joint::difference) (wrapped
    /// only for revolute joints without limits). Unit `rad` (mixed with
    /// metres for prismatic joints); less is better.
    JointChange {
        /// Reference configuration (e.g. the current one).
        reference: Vec<f64>,
        /// Per-joint weights (non-negative, one per joint).
        weights: Vec<f64>,
    },
    /// Smallest normalised distance to a joint limit: `minᵢ min(qᵢ − loᵢ, hiᵢ − qᵢ)/(hiᵢ − loᵢ)`,
    /// in \[0, 0.5\] (0.5 = every joint mid-range). Joints without finite limits count 0.5.
    /// Dimensionless; more is better.
    LimitMargin,
    /// Yoshikawa manipulability `√det(J Jᵀ)` over the six Jacobian rows. Unit `1` (mixed
    /// metres and radians, as Yoshikawa's measure); more is better.
    Manipulability,
    /// Smallest singular value of the six-row Jacobian (distance from a singularity). Unit
    /// `1` (mixed); more is better.
    SigmaMin,
    /// Seed 003's stiffness criterion (notes 003 §4 step 4, Conclusion 5), as the **isotropy of
    /// the tool's translational stiffness**: `σ_min/σ_max = 1/κ(J_p)` of the position Jacobian
    /// ([`Manipulability::position`]; 2-D for planar arms). With equal joint stiffnesses `k`
    /// the tool's stiffness matrix is `K = k·(J_p J_pᵀ)⁻¹`, whose eigenvalues are `k/σᵢ²`: the
    /// stiffest direction resists `κ²` times more than the most compliant one. In `[0, 1]`, 1
    /// for an arm that is equally stiff in every direction, 0 at a singularity. Unit `1`; more
    /// is better.
    Stiffness,
    /// Seed 003's accuracy criterion, as the **position-error amplification**: `σ_max(J_p)·δq`,
    /// the largest tool displacement caused by a joint error vector of Euclidean norm `δq`
    /// (`resolution`). Unit `m`; less is better.
    Accuracy {
        /// The joint resolution `δq`, radians (metres for prismatic joints), > 0; default
        /// [`DEFAULT_JOINT_RESOLUTION`].
        resolution: f64,
    },
}

impl IkCriterion {
    /// The criterion's name, unit and direction.
    pub fn describe(&self) -> Criterion {
        match self {
            IkCriterion::JointChange { .. } => Criterion::new("change", "rad", Direction::LessIsBetter),
            IkCriterion::LimitMargin => Criterion::new("limits", "1", Direction::MoreIsBetter),
            IkCriterion::Manipulability => Criterion::new("manipulability", "1", Direction::MoreIsBetter),
            IkCriterion::SigmaMin => Criterion::new("sigma_min", "1", Direction::MoreIsBetter),
            IkCriterion::Stiffness => Criterion::new("stiffness", "1", Direction::MoreIsBetter),
            IkCriterion::Accuracy { .. } => Criterion::new("accuracy", "m", Direction::LessIsBetter),
        }
    }

    /// The criterion's value for configuration `q` of `robot`.
    ///
    /// # Errors
    /// [`DecideError::BadVector`] when the reference or weights do not match the robot;
    /// [`DecideError::Kinematics`] for a `q` of the wrong length or with non-finite values.
    pub fn evaluate(&self, robot: &Robot, q: &[f64]) -> Result<f64, DecideError> {
        let dof = robot.dof();
        if q.len() != dof || q.iter().any(|v| !v.is_finite()) {
            return Err(DecideError::BadVector {
                what: "solution q",
                reason: format!("expected {dof} finite joint values, got {:?}", q),
            });
        }
        match self {
            IkCriterion::JointChange { reference, weights } => {
                check_vector("reference", reference, dof, false)?;
                check_vector("joint weights", weights, dof, true)?;
                // The one joint-difference rule (`Joint::difference`), as `IkSolutions::closest_to`.
                Ok((0..dof).map(|i| weights[i] * robot.joint_difference(i, reference[i], q[i]).abs()).sum())
            }
            IkCriterion::LimitMargin => Ok(robot
                .joints()
                .iter()
                .zip(q)
                .map(|(j, &v)| {
                    if j.limits.is_bounded() && j.limits.span() > 0.0 {
                        ((v - j.limits.lower).min(j.limits.upper - v) / j.limits.span()).max(0.0)
                    } else {
                        0.5
                    }
                })
                .fold(0.5, f64::min)),
            IkCriterion::Manipulability => Ok(robot.manipulability(q)?.yoshikawa),
            IkCriterion::SigmaMin => Ok(robot.manipulability(q)?.sigma_min),
            IkCriterion::Stiffness => {
                let m = Manipulability::position(&robot.jacobian(q)?);
                Ok(if m.sigma_max > 0.0 { m.sigma_min / m.sigma_max } else { 0.0 })
            }
            IkCriterion::Accuracy { resolution } => {
                if !(resolution.is_finite() && *resolution > 0.0) {
                    return Err(DecideError::BadVector {
                        what: "joint resolution",
                        reason: format!("must be a finite number > 0, got {resolution}"),
                    });
                }
                Ok(Manipulability::position(&robot.jacobian(q)?).sigma_max * resolution)
            }
        }
    }
}

fn check_vector(what: &'static str, v: &[f64], dof: usize, weights: bool) -> Result<(), DecideError> {
    if v.len() != dof {
        return Err(DecideError::BadVector { what, reason: format!("expected {dof} values, got {}", v.len()) });
    }
    if let Some(i) = v.iter().position(|x| !x.is_finite() || (weights && *x < 0.0)) {
        return Err(DecideError::BadVector {
            what,
            reason: format!("value {} at joint {i} must be finite{}", v[i], if weights { " and >= 0" } else { "" }),
        });
    }
    Ok(())
}

/// The decision matrix of `solutions` (rows, in the given order) × `criteria` (columns).
///
/// # Errors
/// [`DecideError::NoCandidates`] for an empty set, [`DecideError::NoCriteria`], and the
/// errors of [`IkCriterion::evaluate`].
pub fn ik_matrix(
    robot: &Robot,
    solutions: &[IkSolution],
    criteria: &[IkCriterion],
) -> Result<DecisionMatrix, DecideError> {
    if solutions.is_empty() {
        return Err(DecideError::NoCandidates);
    }
    let rows = solutions
        .iter()
        .map(|s| criteria.iter().map(|c| c.evaluate(robot, &s.q)).collect::<Result<Vec<f64>, _>>())
        .collect::<Result<Vec<_>, _>>()?;
    DecisionMatrix::new(criteria.iter().map(IkCriterion::describe).collect(), rows)
}

/// Ranks `solutions` by `criteria` with `weights` (one per criterion) and `method`; the
/// ranking's indices refer to `solutions`.
///
/// # Errors
/// See [`ik_matrix`] and [`rank`].
pub fn choose(
    robot: &Robot,
    solutions: &[IkSolution],
    criteria: &[IkCriterion],
    weights: &[f64],
    method: Method,
) -> Result<Ranking, DecideError> {
    let m = ik_matrix(robot, solutions, criteria)?;
    rank(&m, weights, method)
}
