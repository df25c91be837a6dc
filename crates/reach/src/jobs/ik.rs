//! The `ik` workflow: every solution for a tool pose (or position), the one closest to the
//! current configuration or the one a multi-criteria method ranks first; and, for seed 000's
//! planar arm, the thesis's table of configurations ([`ik_scan`]).
//!
//! "No solution" is an answer, not an error: the report's `status` is a stable code
//! (`ok`, `unreachable`, `singular`, `outside_limits`, `orientation_unreachable`,
//! `branch_absent`, `no_convergence`) and `reason` says it in words.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::{Joints, Pose, q_display, rpy_deg};
use crate::decide::ik_criteria::DEFAULT_JOINT_RESOLUTION;
use crate::decide::{Criterion, DecideError, Direction, IkCriterion, Method, ik_matrix, rank};
use crate::error::{Error, Result};
use crate::ik::numeric::MAX_UNTIMED_ITERATIONS;
use crate::ik::planar::{PaperScan, PlanarRedundant, ScanRow};
use crate::ik::{IkFailure, IkOptions, IkSolution, IkSolutions, IkTarget, SolverKind};
use crate::model::planar_angles::InteriorAngles;
use crate::tolerance::IK_POSITION;
use crate::{Cancel, Robot};

/// Parses a solver name as written on the command line: `auto` (`None`: the first closed
/// form that fits the robot, else the numeric solver, [`SolverKind::detect`]) or a
/// [`SolverKind`] name (`spherical-wrist`, …).
///
/// # Errors
/// [`Error::Request`] naming `field` for an unknown name, listing the known ones.
pub fn parse_solver(field: &str, name: &str) -> Result<Option<SolverKind>> {
    if name == "auto" {
        return Ok(None);
    }
    SolverKind::parse(name).map(Some).ok_or_else(|| {
        let known: Vec<&str> = std::iter::once("auto").chain(SolverKind::ALL.iter().map(|k| k.as_str())).collect();
        Error::request(field, format!("unknown solver `{name}` (known: {})", known.join(", ")))
    })
}

/// A multi-criteria method choosing among the solutions within limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum IkChoiceMethod {
    /// TOPSIS: closeness to the ideal.
    Topsis,
    /// VIKOR: compromise index Q, with its acceptance conditions.
    Vikor,
    /// Weighted sum of min-max scores.
    WeightedSum,
    /// The non-dominated solutions, least joint change first (no weights).
    Pareto,
}

impl IkChoiceMethod {
    /// Parses a method name (case-insensitive).
    ///
    /// # Errors
    /// [`Error::Request`] naming `field` for an unknown name, listing the known ones.
    pub fn parse(field: &str, name: &str) -> Result<Self> {
        match name.trim().to_ascii_lowercase().as_str() {
            "pareto" => Ok(IkChoiceMethod::Pareto),
            m => match Method::parse(m) {
                Some(Method::Topsis) => Ok(IkChoiceMethod::Topsis),
                Some(Method::Vikor) => Ok(IkChoiceMethod::Vikor),
                Some(Method::WeightedSum) => Ok(IkChoiceMethod::WeightedSum),
                None => Err(Error::request(
                    field,
                    format!("unknown method `{name}` (known: topsis, vikor, weighted-sum, pareto)"),
                )),
            },
        }
    }

    /// The ranking method, `None` for the Pareto filter.
    fn method(self) -> Option<Method> {
        match self {
            IkChoiceMethod::Topsis => Some(Method::Topsis),
            IkChoiceMethod::Vikor => Some(Method::Vikor),
            IkChoiceMethod::WeightedSum => Some(Method::WeightedSum),
            IkChoiceMethod::Pareto => None,
        }
    }
}

/// A criterion of the IK choice.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum IkCriterionName {
    /// `Σ wᵢ·|Δqᵢ|` from `from` (radians, metres; the robot's joint-difference rule), less is
    /// better.
    Change,
    /// Smallest normalised distance to a joint limit, more is better.
    Limits,
    /// Yoshikawa's manipulability, more is better.
    Manipulability,
    /// Smallest singular value of the Jacobian, more is better.
    SigmaMin,
    /// Seed 003's stiffness: `σ_min/σ_max` of the position Jacobian (isotropy of the tool's
    /// stiffness), more is better.
    Stiffness,
    /// Seed 003's accuracy: `σ_max` of the position Jacobian times a joint resolution of 0.01°,
    /// metres, less is better.
    Accuracy,
}

impl IkCriterionName {
    /// Every criterion, in the order of the documentation.
    pub const ALL: [IkCriterionName; 6] = [
        IkCriterionName::Change,
        IkCriterionName::Limits,
        IkCriterionName::Manipulability,
        IkCriterionName::SigmaMin,
        IkCriterionName::Stiffness,
        IkCriterionName::Accuracy,
    ];

    /// The name (`change`, `limits`, `manipulability`, `sigma_min`, `stiffness`, `accuracy`).
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            IkCriterionName::Change => "change",
            IkCriterionName::Limits => "limits",
            IkCriterionName::Manipulability => "manipulability",
            IkCriterionName::SigmaMin => "sigma_min",
            IkCriterionName::Stiffness => "stiffness",
            IkCriterionName::Accuracy => "accuracy",
        }
    }

    /// Parses a name (case-insensitive, `-` for `_`).
    ///
    /// # Errors
    /// [`Error::Request`] naming `field` for an unknown name, listing the known ones.
    pub fn parse(field: &str, name: &str) -> Result<Self> {
        let key = name.trim().to_ascii_lowercase().replace('-', "_");
        IkCriterionName::ALL.into_iter().find(|c| c.as_str() == key).ok_or_else(|| {
            let known: Vec<&str> = IkCriterionName::ALL.iter().map(|c| c.as_str()).collect();
            Error::request(field, format!("unknown criterion `{name}` (known: {})", known.join(", ")))
        })
    }
}

fn default_criteria() -> Vec<IkCriterionName> {
    vec![IkCriterionName::Change, IkCriterionName::Limits, IkCriterionName::Manipulability]
}

/// A multi-criteria choice among the solutions within limits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IkChoice {
    /// The method.
    pub method: IkChoiceMethod,
    /// The criteria, in column order (default `change, limits, manipulability`).
    #[serde(default = "default_criteria")]
    pub criteria: Vec<IkCriterionName>,
    /// One weight per criterion, ≥ 0, not all 0 (normalised to sum 1); not for `pareto`.
    /// Default: equal weights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<Vec<f64>>,
}

/// Names of the three parts of an [`IkChoice`] in messages: method, criteria, weights.
pub const CHOICE_FIELDS: [&str; 3] = ["choose.method", "choose.criteria", "choose.weights"];

impl IkChoice {
    /// Checks the choice and returns the weights to use (equal weights by default).
    ///
    /// # Errors
    /// [`Error::Request`] naming the field of `fields` (method, criteria, weights; weights as
    /// `weights[i] (criterion)`): no criteria, a criterion given twice, weights for `pareto`, a
    /// wrong weight count, a negative or non-finite weight, all weights zero.
    pub fn check(&self, fields: [&str; 3]) -> Result<Vec<f64>> {
        let [_, criteria_field, weights_field] = fields;
        if self.criteria.is_empty() {
            return Err(Error::request(criteria_field, "no criteria given"));
        }
        for (k, c) in self.criteria.iter().enumerate() {
            if self.criteria[..k].contains(c) {
                return Err(Error::request(criteria_field, format!("`{}` is given twice", c.as_str())));
            }
        }
        let names: Vec<&str> = self.criteria.iter().map(|c| c.as_str()).collect();
        match (&self.weights, self.method) {
            (Some(_), IkChoiceMethod::Pareto) => {
                Err(Error::request(weights_field, "the pareto filter takes no weights"))
            }
            (Some(w), _) => {
                crate::decide::mcdm::normalise_weights(&names, w).map_err(|e| match e {
                    DecideError::WeightCount { expected, found } => Error::request(
                        weights_field,
                        format!("expected {expected} weights, one per criterion ({}), got {found}", names.join(",")),
                    ),
                    DecideError::InvalidWeight { criterion, value } => {
                        let i = names.iter().position(|n| *n == criterion).map_or(0, |i| i + 1);
                        Error::request(
                            format!("{weights_field}[{i}] ({criterion})"),
                            format!("must be finite and not negative, got {value}"),
                        )
                    }
                    DecideError::ZeroWeights => Error::request(weights_field, "all weights are zero"),
                    e => Error::request(weights_field, e.to_string()),
                })?;
                Ok(w.clone())
            }
            (None, _) => Ok(vec![1.0; self.criteria.len()]),
        }
    }

    /// Ranks the solutions within limits of `all`; indices in the ranking refer to
    /// `all.solutions`. `from` and `joint_weights` (SI, one per joint) define the `change`
    /// criterion and Pareto's tie-break.
    ///
    /// # Errors
    /// As [`IkChoice::check`]; [`Error::Request`] naming `field` when the criteria cannot be
    /// evaluated or cannot discriminate (an all-zero column).
    pub fn rank(
        &self,
        robot: &Robot,
        all: &IkSolutions,
        from: &[f64],
        joint_weights: &[f64],
        fields: [&str; 3],
        field: &str,
    ) -> Result<IkRanking> {
        let weights = self.check(fields)?;
        let change = IkCriterion::JointChange { reference: from.to_vec(), weights: joint_weights.to_vec() };
        let criteria: Vec<IkCriterion> = self
            .criteria
            .iter()
            .map(|c| match c {
                IkCriterionName::Change => change.clone(),
                IkCriterionName::Limits => IkCriterion::LimitMargin,
                IkCriterionName::Manipulability => IkCriterion::Manipulability,
                IkCriterionName::SigmaMin => IkCriterion::SigmaMin,
                IkCriterionName::Stiffness => IkCriterion::Stiffness,
                IkCriterionName::Accuracy => IkCriterion::Accuracy { resolution: DEFAULT_JOINT_RESOLUTION },
            })
            .collect();
        let candidates: Vec<usize> = (0..all.solutions.len()).filter(|&i| all.solutions[i].within_limits).collect();
        let solutions: Vec<IkSolution> = candidates.iter().map(|&i| all.solutions[i].clone()).collect();
        let decide = |e: DecideError| Error::request(field, e.to_string());
        let matrix = ik_matrix(robot, &solutions, &criteria).map_err(decide)?;
        matrix.reject_zero_columns().map_err(decide)?;
        let describe = |weight: Option<f64>, c: &Criterion| IkCriterionReport {
            name: c.name.clone(),
            unit: c.unit.clone(),
            direction: match c.direction {
                Direction::MoreIsBetter => CriterionDirection::MoreIsBetter,
                Direction::LessIsBetter => CriterionDirection::LessIsBetter,
            },
            weight,
        };
        if let Some(method) = self.method.method() {
            let ranking = rank(&matrix, &weights, method).map_err(decide)?;
            return Ok(IkRanking {
                method: self.method,
                criteria: ranking.criteria.iter().zip(&ranking.weights).map(|(c, w)| describe(Some(*w), c)).collect(),
                score: match method {
                    Method::WeightedSum => "weighted sum of min-max scores (1 = best), higher is better",
                    Method::Topsis => "closeness C = d-/(d+ + d-) to the ideal, higher is better",
                    Method::Vikor => "compromise index Q (v = 0.5), lower is better",
                }
                .into(),
                ranked: ranking
                    .ranked
                    .iter()
                    .map(|e| IkRankedReport {
                        solution: candidates[e.index],
                        rank: e.rank,
                        score: Some(e.score),
                        values: matrix.rows()[e.index].clone(),
                        normalised: Some(e.normalised.clone()),
                        pareto_optimal: e.pareto_optimal,
                    })
                    .collect(),
                vikor: ranking.vikor.map(|v| IkVikorReport {
                    dq: v.dq,
                    acceptable_advantage: v.acceptable_advantage,
                    acceptable_stability: v.acceptable_stability,
                    compromise: v.compromise.iter().map(|&i| candidates[i]).collect(),
                }),
            });
        }
        // Pareto: the non-dominated ones first, least weighted joint change first (the seeds'
        // rule), then the dominated ones in the same order.
        let front = matrix.pareto();
        let cost: Vec<f64> =
            solutions.iter().map(|s| change.evaluate(robot, &s.q)).collect::<Result<_, _>>().map_err(decide)?;
        let mut order: Vec<usize> = (0..solutions.len()).collect();
        order.sort_by(|&a, &b| {
            (!front.contains(&a)).cmp(&!front.contains(&b)).then(cost[a].total_cmp(&cost[b])).then(a.cmp(&b))
        });
        Ok(IkRanking {
            method: IkChoiceMethod::Pareto,
            criteria: matrix.criteria().iter().map(|c| describe(None, c)).collect(),
            score: "none: non-dominated first, then least joint change from --from".into(),
            ranked: order
                .iter()
                .enumerate()
                .map(|(k, &i)| IkRankedReport {
                    solution: candidates[i],
                    rank: k + 1,
                    score: None,
                    values: matrix.rows()[i].clone(),
                    normalised: None,
                    pareto_optimal: front.contains(&i),
                })
                .collect(),
            vikor: None,
        })
    }
}

/// Options of the numeric solver (ignored by the closed forms).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IkNumericRequest {
    /// Number of starts, ≥ 1 (default 16). Without `time_budget_s`, `restarts ×
    /// max_iterations` is at most [`MAX_UNTIMED_ITERATIONS`]; with it, the budget ends the
    /// solve.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub restarts: Option<usize>,
    /// Iterations per start, ≥ 1 (default 200).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_iterations: Option<usize>,
    /// Wall-time budget of the solve, seconds (> 0; default: none). A budget makes the result
    /// depend on the machine's speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_budget_s: Option<f64>,
    /// Largest accepted position error, metres (> 0; default 1e-6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position_tolerance_m: Option<f64>,
    /// Largest accepted orientation error, radians (> 0; default 1e-6).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orientation_tolerance_rad: Option<f64>,
}

/// Inverse kinematics of one target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IkRequest {
    /// The target: a full pose, or a position alone (orientation free).
    pub target: Pose,
    /// The solver (default: the first closed form that fits the robot, else the numeric
    /// solver, [`SolverKind::detect`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SolverKind>,
    /// List every solution, within the joint limits or not (otherwise only the chosen one,
    /// or every one when none is within limits).
    #[serde(default)]
    pub all: bool,
    /// The current configuration (default: home): the closest solution is chosen, the
    /// numeric solver starts there, and undetermined angles at singularities keep its values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<Joints>,
    /// Weights `wᵢ ≥ 0` of the joint changes `Σ wᵢ·|Δqᵢ|`, one per joint (default all 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub joint_weights: Option<Vec<f64>>,
    /// Choose by several criteria instead of the least joint change (`solutions` then lists
    /// every solution and `ranking` explains the choice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub choose: Option<IkChoice>,
    /// With `all`: list at most this many solutions (≥ 1), evenly spaced in the solver's order
    /// (a sampled self-motion's parameter) and always with the chosen one; `found` still counts
    /// them all. Default: every one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_solutions: Option<usize>,
    /// Redundant arms: the free parameter, degrees (planar3: absolute angle of the last link).
    /// Default: sample the self-motion with `step_deg`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub free_angle_deg: Option<f64>,
    /// Redundant arms: sampling step of the self-motion, degrees (> 0; default 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub step_deg: Option<f64>,
    /// Numeric solver options.
    #[serde(default)]
    pub numeric: IkNumericRequest,
}

impl IkRequest {
    /// A request for `target` with every option at its default.
    #[must_use]
    pub fn new(target: Pose) -> Self {
        IkRequest {
            target,
            solver: None,
            all: false,
            from: None,
            joint_weights: None,
            choose: None,
            max_solutions: None,
            free_angle_deg: None,
            step_deg: None,
            numeric: IkNumericRequest::default(),
        }
    }
}

/// The target as solved: position, and orientation unless free.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkTargetReport {
    /// Position, metres.
    pub xyz_m: [f64; 3],
    /// Roll, pitch, yaw in degrees, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`; `null`: orientation free.
    pub rpy_deg: Option<[f64; 3]>,
}

/// A joint outside its limits, in display units (revolute degrees, prismatic metres).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkViolationReport {
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// The value.
    pub value_deg: f64,
    /// Lower limit (`null` when unbounded).
    pub lower_deg: Option<f64>,
    /// Upper limit (`null` when unbounded).
    pub upper_deg: Option<f64>,
}

/// One solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkSolutionReport {
    /// Joint values: revolute in degrees, prismatic in metres.
    pub q_deg: Vec<f64>,
    /// Branch label, e.g. `shoulder=left elbow=up wrist=noflip`.
    pub branch: String,
    /// Tool position error, metres.
    pub position_error_m: f64,
    /// Tool orientation error, radians.
    pub orientation_error_rad: f64,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
    /// The joints outside their limits.
    pub violations: Vec<IkViolationReport>,
    /// Singular configurations the solution sits at: `wrist`, `elbow`, `shoulder`, `jacobian`.
    pub singular: Vec<String>,
}

/// Whether larger or smaller values of a criterion are preferred.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CriterionDirection {
    /// Larger is better.
    MoreIsBetter,
    /// Smaller is better.
    LessIsBetter,
}

/// One criterion of a ranking.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkCriterionReport {
    /// Name.
    pub name: String,
    /// Unit of the raw values.
    pub unit: String,
    /// Preferred direction.
    pub direction: CriterionDirection,
    /// Weight, normalised to sum 1 (`null` for pareto).
    pub weight: Option<f64>,
}

/// One ranked solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkRankedReport {
    /// Index into `solutions`.
    pub solution: usize,
    /// 1-based rank (pareto: 1 for the chosen, then the other non-dominated, then the rest).
    pub rank: usize,
    /// The method's score (`null` for pareto).
    pub score: Option<f64>,
    /// Raw criterion values, in the criteria's units.
    pub values: Vec<f64>,
    /// Normalised values as the method uses them (`null` for pareto).
    pub normalised: Option<Vec<f64>>,
    /// Whether no other candidate is better or equal on every criterion and better on one.
    pub pareto_optimal: bool,
}

/// VIKOR's acceptance of its Q-best solution (conditions C1 and C2) and the compromise set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkVikorReport {
    /// `DQ = 1/(m − 1)` for `m` candidates (0 with one).
    pub dq: f64,
    /// C1: `Q(a″) − Q(a′) ≥ DQ`.
    pub acceptable_advantage: bool,
    /// C2: a′ is also best by S or by R.
    pub acceptable_stability: bool,
    /// The compromise set, indices into `solutions`, best first.
    pub compromise: Vec<usize>,
}

impl IkVikorReport {
    /// Whether the Q-best solution alone is the compromise (C1 and C2 hold).
    #[must_use]
    pub fn accepted(&self) -> bool {
        self.acceptable_advantage && self.acceptable_stability
    }
}

/// The ranking of a multi-criteria choice.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkRanking {
    /// The method.
    pub method: IkChoiceMethod,
    /// The criteria, in column order, with the normalised weights.
    pub criteria: Vec<IkCriterionReport>,
    /// Meaning of `score`.
    pub score: String,
    /// The candidates, best first.
    pub ranked: Vec<IkRankedReport>,
    /// VIKOR only: acceptance conditions C1/C2 and the compromise set.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vikor: Option<IkVikorReport>,
}

/// The solutions of one target and the choice among them (`reach ik --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkReport {
    /// Robot name.
    pub robot: String,
    /// Name of the solver used.
    pub solver: String,
    /// `ok`, or why no solution is within limits: `unreachable`, `singular`,
    /// `outside_limits`, `orientation_unreachable`, `branch_absent`, `no_convergence`.
    pub status: String,
    /// The reason in words (`null` when the status is `ok`).
    pub reason: Option<String>,
    /// The target as solved.
    pub target: IkTargetReport,
    /// The configuration the choice is measured from (display units).
    pub from_q_deg: Vec<f64>,
    /// The joint weights of `Σ wᵢ·|Δqᵢ|`.
    pub joint_weights: Vec<f64>,
    /// How many solutions the solver found.
    pub found: usize,
    /// How many of them are within the joint limits.
    pub within_limits: usize,
    /// With `all` or `choose`, or when none is within limits: every solution found;
    /// otherwise the chosen one only.
    pub solutions: Vec<IkSolutionReport>,
    /// Index of the chosen solution in `solutions` (`null` when none is within limits).
    pub chosen: Option<usize>,
    /// With `choose`: the ranking of the solutions within limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranking: Option<IkRanking>,
}

/// The stable code of a failure (`unreachable`, `outside_limits`, …).
#[must_use]
pub fn failure_code(failure: &IkFailure) -> &'static str {
    match failure {
        IkFailure::Unreachable { .. } => "unreachable",
        IkFailure::OrientationUnreachable => "orientation_unreachable",
        IkFailure::Singular { .. } => "singular",
        IkFailure::OutsideLimits { .. } => "outside_limits",
        IkFailure::BranchAbsent { .. } => "branch_absent",
        IkFailure::NoConvergence { .. } => "no_convergence",
    }
}

pub(crate) fn status(failure: Option<&IkFailure>) -> (String, Option<String>) {
    match failure {
        None => ("ok".into(), None),
        Some(f) => (failure_code(f).into(), Some(f.to_string())),
    }
}

/// `joint_weights`: one finite, non-negative weight per joint (default all 1).
fn joint_weights(robot: &Robot, weights: Option<&[f64]>) -> Result<Vec<f64>> {
    let Some(w) = weights else { return Ok(vec![1.0; robot.dof()]) };
    if w.len() != robot.dof() {
        return Err(Error::request(
            "joint_weights",
            format!("robot `{}` has {} joints, got {} weights", robot.name(), robot.dof(), w.len()),
        ));
    }
    if let Some(i) = w.iter().position(|v| !v.is_finite() || *v < 0.0) {
        return Err(Error::request(
            format!("joint_weights[{}]", i + 1),
            format!("must be finite and not negative, got {}", w[i]),
        ));
    }
    Ok(w.to_vec())
}

/// The solver options of a request, starting from `from`: `free_angle_deg`, `step_deg` and
/// `numeric` validated (whole numbers ≥ 1, the [`MAX_UNTIMED_ITERATIONS`] cap without a time
/// budget, positive tolerances). Front ends that solve many targets with one request's
/// options ([`crate::batch::ik_many`]) take them from here.
///
/// # Errors
/// [`Error::Request`] naming the field (`numeric.restarts`, `step_deg`, …).
pub fn solver_options(request: &IkRequest, from: &[f64]) -> Result<IkOptions> {
    let mut options = IkOptions { seed: Some(from.to_vec()), ..IkOptions::default() };
    if let Some(a) = request.free_angle_deg {
        if !a.is_finite() {
            return Err(Error::request("free_angle_deg", format!("expected a finite number, got {a}")));
        }
        options.free_parameter = Some(a.to_radians());
    }
    if let Some(step) = request.step_deg {
        if !(step.is_finite() && step > 0.0) {
            return Err(Error::request("step_deg", format!("must be a positive angle in degrees, got {step}")));
        }
        options.redundancy_step = step.to_radians();
    }
    let n = &request.numeric;
    let whole = |field: &str, v: Option<usize>| match v {
        Some(0) => Err(Error::request(field, "expected a whole number ≥ 1, got 0")),
        other => Ok(other),
    };
    if let Some(r) = whole("numeric.restarts", n.restarts)? {
        options.restarts = r;
    }
    if let Some(m) = whole("numeric.max_iterations", n.max_iterations)? {
        options.max_iterations = m;
    }
    if let Some(t) = super::input::time_budget("numeric.time_budget_s", n.time_budget_s)? {
        options.numeric.time_budget = Some(t);
    }
    let budget = options.restarts.saturating_mul(options.max_iterations);
    if options.numeric.time_budget.is_none() && budget > MAX_UNTIMED_ITERATIONS {
        let field = if n.restarts.is_some() { "numeric.restarts" } else { "numeric.max_iterations" };
        return Err(Error::request(
            field,
            format!(
                "{} starts × {} iterations is {:.3e} solver iterations, more than the cap of {MAX_UNTIMED_ITERATIONS} \
                 without a time budget (use fewer starts or iterations, or give a time budget)",
                options.restarts,
                options.max_iterations,
                options.restarts as f64 * options.max_iterations as f64
            ),
        ));
    }
    if let Some(t) = super::input::positive("numeric.position_tolerance_m", n.position_tolerance_m)? {
        options.numeric.position_tolerance = t;
    }
    if let Some(t) = super::input::positive("numeric.orientation_tolerance_rad", n.orientation_tolerance_rad)? {
        options.numeric.orientation_tolerance = t;
    }
    Ok(options)
}

/// One solution in display units.
#[must_use]
pub fn solution_report(robot: &Robot, s: &IkSolution) -> IkSolutionReport {
    let display =
        |joint: usize, v: f64| super::input::from_si(robot.joints()[joint - 1].kind, v, super::input::AngleUnit::Deg);
    let bound = |joint: usize, v: f64| v.is_finite().then(|| display(joint, v));
    IkSolutionReport {
        // `+ 0.0` turns −0 into 0.
        q_deg: q_display(robot, &s.q).into_iter().map(|v| v + 0.0).collect(),
        branch: s.branch.to_string(),
        position_error_m: s.position_error,
        orientation_error_rad: s.orientation_error,
        within_limits: s.within_limits,
        violations: s
            .violations
            .iter()
            .map(|v| IkViolationReport {
                joint: v.joint,
                name: v.name.to_string(),
                value_deg: display(v.joint, v.value),
                lower_deg: bound(v.joint, v.lower),
                upper_deg: bound(v.joint, v.upper),
            })
            .collect(),
        singular: s.singularities.iter().map(|k| k.as_str().to_string()).collect(),
    }
}

/// Solves the target and chooses a solution.
///
/// The default choice is the solution within limits with the least `Σ wᵢ·|Δqᵢ|` from `from`
/// ([`IkSolutions::closest_index`], each `Δqᵢ` by the robot's one joint-difference rule
/// [`crate::model::Joint::difference`]); with `choose`, the method's rank 1.
///
/// # Errors
/// [`Error::Request`] naming the field (`target.matrix`, `from`, `joint_weights[6]`,
/// `choose.weights`, `numeric.restarts`, …); [`Error::Ik`] for a solver that does not fit the
/// robot. No solution within limits is not an error: see the report's `status`.
pub fn ik(robot: &Robot, request: &IkRequest) -> Result<IkReport> {
    ik_with_cancel(robot, request, &Cancel::default())
}

/// [`ik`] whose numeric solver stops when `cancel` is set (the report then holds what was
/// found so far, like a spent time budget).
///
/// # Errors
/// As [`ik`].
pub fn ik_with_cancel(robot: &Robot, request: &IkRequest, cancel: &Cancel) -> Result<IkReport> {
    let target = request.target.target("target")?;
    let from = match &request.from {
        Some(q) => q.si(robot, "from")?,
        None => robot.home(),
    };
    let weights = joint_weights(robot, request.joint_weights.as_deref())?;
    if let Some(choice) = &request.choose {
        choice.check(CHOICE_FIELDS)?;
    }
    match request.max_solutions {
        Some(0) => return Err(Error::request("max_solutions", "must be at least 1")),
        Some(_) if !request.all => return Err(Error::request("max_solutions", "thins the list of `all`; set `all`")),
        Some(_) if request.choose.is_some() => {
            return Err(Error::request("max_solutions", "with `choose` every ranked solution is listed"));
        }
        _ => {}
    }
    let options = IkOptions { cancel: cancel.clone(), ..solver_options(request, &from)? };
    let kind = request.solver.unwrap_or_else(|| SolverKind::detect(robot));
    let mut all = kind.build(robot)?.solve(robot, &target, &options)?;
    all.express_near(robot, &from);
    let closest = all.closest_index(&from, &weights);
    let ranking = match &request.choose {
        Some(choice) if closest.is_some() => {
            Some(choice.rank(robot, &all, &from, &weights, CHOICE_FIELDS, "choose")?)
        }
        _ => None,
    };
    let chosen = ranking.as_ref().map_or(closest, |r| r.ranked.first().map(|e| e.solution));
    let shown: Vec<usize> = match (chosen, request.max_solutions) {
        (Some(i), _) if !request.all && ranking.is_none() => vec![i],
        (_, Some(max)) => thinned(all.solutions.len(), max, chosen),
        (_, None) => (0..all.solutions.len()).collect(),
    };
    let (status, reason) = status(all.failure.as_ref());
    let p = target.position();
    Ok(IkReport {
        robot: robot.name().to_string(),
        solver: all.solver.to_string(),
        status,
        reason,
        target: IkTargetReport {
            xyz_m: [p.x, p.y, p.z],
            rpy_deg: match &target {
                IkTarget::Pose(pose) => Some(rpy_deg(&pose.rotation)),
                IkTarget::Position(_) => None,
            },
        },
        from_q_deg: q_display(robot, &from),
        joint_weights: weights,
        found: all.solutions.len(),
        within_limits: all.feasible().count(),
        solutions: shown.iter().map(|&i| solution_report(robot, &all.solutions[i])).collect(),
        chosen: chosen.and_then(|c| shown.iter().position(|&i| i == c)),
        ranking,
    })
}

/// At most `max` of the indices `0..n`, evenly spaced (the first and the last among them),
/// with `keep` in place of the nearest when it is not one of them; ascending.
fn thinned(n: usize, max: usize, keep: Option<usize>) -> Vec<usize> {
    if n <= max {
        return (0..n).collect();
    }
    let mut shown: Vec<usize> = if max == 1 {
        vec![keep.unwrap_or(0)]
    } else {
        (0..max).map(|k| (k * (n - 1) + (max - 1) / 2) / (max - 1)).collect()
    };
    if let Some(keep) = keep.filter(|k| !shown.contains(k)) {
        let nearest = (0..shown.len()).min_by_key(|&k| shown[k].abs_diff(keep)).expect("max ≥ 1");
        shown[nearest] = keep;
        shown.sort_unstable();
    }
    shown
}

// ---------------------------------------------------------------------------------------------
// The planar scan: seed 000's table of configurations.
// ---------------------------------------------------------------------------------------------

/// Seed 000's table of configurations of a planar 3-link arm for one position (notes 000
/// §4.1): α from α_min to 180° in steps, and the row with the least
/// `S = |α − α0| + |β − β0| + |γ − γ0|` from the current configuration.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IkScanRequest {
    /// The tool position, metres (in the arm's plane).
    pub xyz_m: [f64; 3],
    /// The step of α, degrees (> 0).
    pub step_deg: f64,
    /// The current configuration (default: home).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<Joints>,
}

/// The interior angles α, β, γ of seed 000's convention ([`InteriorAngles`]), degrees.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct InteriorAnglesReport {
    /// Interior angle at joint A, degrees.
    pub alpha_deg: f64,
    /// Interior angle at joint B, degrees.
    pub beta_deg: f64,
    /// Absolute angle of the first link, degrees.
    pub gamma_deg: f64,
}

impl InteriorAnglesReport {
    fn of(p: &InteriorAngles) -> Self {
        InteriorAnglesReport {
            alpha_deg: p.alpha.to_degrees(),
            beta_deg: p.beta.to_degrees(),
            gamma_deg: p.gamma.to_degrees(),
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkScanRow {
    /// The thesis's angles.
    pub paper: InteriorAnglesReport,
    /// Joint values, degrees.
    pub q_deg: [f64; 3],
    /// `S` from the current configuration, degrees.
    pub s_deg: f64,
    /// Whether every joint is within its limits.
    pub within_limits: bool,
}

/// The table of configurations (`reach ik --scan --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct IkScanReport {
    /// Robot name.
    pub robot: String,
    /// The step of α, degrees.
    pub step_deg: f64,
    /// The target in the arm's plane, metres.
    pub plane_xy_m: [f64; 2],
    /// The smallest α of the table, degrees (`null` when the target is unreachable).
    pub alpha_min_deg: Option<f64>,
    /// The current configuration, joint values in degrees.
    pub from_q_deg: Vec<f64>,
    /// The current configuration, the thesis's angles.
    pub from_paper: InteriorAnglesReport,
    /// `ok`, or why there is no row: a code as in the `ik` report.
    pub status: String,
    /// The reason in words (`null` when the status is `ok`).
    pub reason: Option<String>,
    /// How many rows are within the joint limits.
    pub within_limits: usize,
    /// The rows, α ascending.
    pub rows: Vec<IkScanRow>,
    /// Index of the row with the least `S` (`null` without rows).
    pub chosen: Option<usize>,
}

/// `S` of a row against the start (notes 000 §6.3), radians.
fn s_of(row: &ScanRow, start: &InteriorAngles) -> f64 {
    let p = &row.paper;
    (p.alpha - start.alpha).abs() + (p.beta - start.beta).abs() + (p.gamma - start.gamma).abs()
}

/// Checks the inputs every planar scan shares — the grid step (`step_deg`, a positive angle in
/// degrees) and a finite target (`xyz_m`) — and returns the start (`from`, default home; SI).
///
/// # Errors
/// [`Error::Request`] naming `step_deg`, `xyz_m[i]` or `from`.
pub(crate) fn scan_input(robot: &Robot, step_deg: f64, xyz_m: &[f64; 3], from: Option<&Joints>) -> Result<Vec<f64>> {
    if !(step_deg.is_finite() && step_deg > 0.0) {
        return Err(Error::request(
            "step_deg",
            format!("the step must be a positive angle in degrees, got {step_deg}"),
        ));
    }
    if let Some(i) = xyz_m.iter().position(|v| !v.is_finite()) {
        return Err(Error::request(format!("xyz_m[{}]", i + 1), format!("expected a finite number, got {}", xyz_m[i])));
    }
    let from = match from {
        Some(q) => q.si(robot, "from")?,
        None => robot.home(),
    };
    Ok(from)
}

/// Builds seed 000's table of configurations.
///
/// # Errors
/// [`Error::Request`] for a non-finite position or a step that is not a positive angle
/// (`step_deg`), a bad `from`; [`Error::Ik`] when the robot is not a planar 3-link arm.
pub fn ik_scan(robot: &Robot, request: &IkScanRequest) -> Result<IkScanReport> {
    let arm = PlanarRedundant::from_robot(robot)?;
    let step = request.step_deg;
    let from = scan_input(robot, step, &request.xyz_m, request.from.as_ref())?;
    let (x, y, offset) = arm.plane_coordinates(&nalgebra::Point3::from(request.xyz_m));
    let scan = if offset.abs() > IK_POSITION {
        let failure =
            IkFailure::Unreachable { distance: offset.abs(), reach: 0.0, point: "the target", from: "the arm's plane" };
        PaperScan { alpha_min: None, rows: Vec::new(), failure: Some(failure) }
    } else {
        arm.paper_scan([x, y], step.to_radians())?
    };
    let start = InteriorAngles::from_link_angles(arm.link_angles(&[from[0], from[1], from[2]]));
    let (status, reason) = status(scan.failure.as_ref());
    Ok(IkScanReport {
        robot: robot.name().to_string(),
        step_deg: step,
        plane_xy_m: [x, y],
        alpha_min_deg: scan.alpha_min.map(f64::to_degrees),
        from_q_deg: q_display(robot, &from),
        from_paper: InteriorAnglesReport::of(&start),
        status,
        reason,
        within_limits: scan.rows.iter().filter(|r| r.within_limits).count(),
        rows: scan
            .rows
            .iter()
            .map(|row| IkScanRow {
                paper: InteriorAnglesReport::of(&row.paper),
                q_deg: row.q.map(f64::to_degrees),
                s_deg: s_of(row, &start).to_degrees(),
                within_limits: row.within_limits,
            })
            .collect(),
        chosen: scan.select_min_s(&start).map(|(i, _)| i),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    fn puma_request() -> IkRequest {
        IkRequest::new(Pose::xyz_rpy_deg([0.5, -0.2, 0.3], [180.0, 0.0, 0.0]))
    }

    #[test]
    fn max_solutions_thins_a_sampled_self_motion_and_keeps_the_chosen() {
        assert_eq!(thinned(5, 9, None), [0, 1, 2, 3, 4]);
        assert_eq!(thinned(11, 3, None), [0, 5, 10]);
        assert_eq!(thinned(11, 3, Some(7)), [0, 7, 10]);
        assert_eq!(thinned(11, 1, Some(7)), [7]);
        assert_eq!(thinned(720, 4, Some(719)), [0, 240, 479, 719]);
        // planar3's self-motion at 1°: hundreds of solutions (the feasible φ, both elbows).
        let robot = presets::get("planar3").unwrap();
        let mut request = IkRequest::new(Pose { xyz_m: Some([1.5, 1.0, 0.0]), ..Pose::default() });
        request.all = true;
        let every = ik(&robot, &request).unwrap();
        assert!(every.found > 300 && every.solutions.len() == every.found, "{}", every.found);
        request.max_solutions = Some(10);
        let few = ik(&robot, &request).unwrap();
        assert_eq!((few.found, few.solutions.len()), (every.found, 10));
        let chosen = few.chosen.expect("a solution within limits");
        assert_eq!(few.solutions[chosen], every.solutions[every.chosen.unwrap()]);
        assert!(few.solutions.iter().all(|s| every.solutions.contains(s)));
        for (max, all, message) in [(0, true, "at least 1"), (3, false, "set `all`")] {
            let mut bad = request.clone();
            (bad.max_solutions, bad.all) = (Some(max), all);
            let e = ik(&robot, &bad).unwrap_err().to_string();
            assert!(e.contains("max_solutions") && e.contains(message), "{e}");
        }
    }

    #[test]
    fn the_default_choice_is_the_closest_by_the_joint_difference_rule() {
        let robot = presets::get("puma560").unwrap();
        let mut request = puma_request();
        request.all = true;
        let report = ik(&robot, &request).unwrap();
        assert_eq!(report.status, "ok");
        assert_eq!(report.solutions.len(), report.found);
        let chosen = report.chosen.unwrap();
        // The chosen one has the least Σ |Δq| from home, each Δq by Joint::difference.
        let cost = |s: &IkSolutionReport| -> f64 {
            s.q_deg
                .iter()
                .enumerate()
                .map(|(i, q)| robot.joint_difference(i, robot.home()[i], q.to_radians()).abs())
                .sum()
        };
        let best = report.solutions.iter().filter(|s| s.within_limits).map(cost).fold(f64::INFINITY, f64::min);
        assert!((cost(&report.solutions[chosen]) - best).abs() < 1e-12);
        // Without `all`, only the chosen one is listed.
        let one = ik(&robot, &puma_request()).unwrap();
        assert_eq!(one.solutions, vec![report.solutions[chosen].clone()]);
        assert_eq!(one.chosen, Some(0));
    }

    #[test]
    fn choice_with_change_alone_agrees_with_the_closest() {
        let robot = presets::get("puma560").unwrap();
        let mut request = puma_request();
        request.choose =
            Some(IkChoice { method: IkChoiceMethod::Topsis, criteria: vec![IkCriterionName::Change], weights: None });
        let ranked = ik(&robot, &request).unwrap();
        let closest = ik(&robot, &puma_request()).unwrap();
        assert_eq!(ranked.solutions[ranked.chosen.unwrap()], closest.solutions[0]);
        assert_eq!(ranked.ranking.unwrap().ranked.len(), ranked.within_limits);
    }

    #[test]
    fn bad_fields_are_named() {
        let robot = presets::get("puma560").unwrap();
        let mut request = puma_request();
        request.joint_weights = Some(vec![1.0, 1.0, 1.0, 1.0, 1.0, -1.0]);
        assert!(ik(&robot, &request).unwrap_err().to_string().starts_with("joint_weights[6]: must be finite"));
        let mut request = puma_request();
        request.choose = Some(IkChoice {
            method: IkChoiceMethod::Pareto,
            criteria: default_criteria(),
            weights: Some(vec![1.0, 1.0, 1.0]),
        });
        assert_eq!(ik(&robot, &request).unwrap_err().to_string(), "choose.weights: the pareto filter takes no weights");
        let mut request = puma_request();
        request.numeric.restarts = Some(0);
        assert!(ik(&robot, &request).unwrap_err().to_string().starts_with("numeric.restarts:"));
        assert!(parse_solver("solver", "foo").unwrap_err().to_string().contains("spherical-wrist"));
        assert_eq!(parse_solver("solver", "yaw-planar3").unwrap(), Some(SolverKind::YawPlanar3));
        assert_eq!(parse_solver("solver", "auto").unwrap(), None);
        // A request's solver reads and writes the command-line names.
        for kind in SolverKind::ALL {
            assert_eq!(serde_json::to_value(kind).unwrap(), serde_json::json!(kind.as_str()));
        }
        let request: IkRequest = serde_json::from_value(serde_json::json!({
            "target": {"xyz_m": [0.5, 0.1, 0.2]},
            "solver": "spherical-wrist"
        }))
        .unwrap();
        assert_eq!(request.solver, Some(SolverKind::SphericalWrist));
        let json = serde_json::to_value(SolverKind::YawPlanar3).unwrap();
        assert_eq!(json, "yaw-planar3");
    }

    #[test]
    fn the_scan_of_planar3_chooses_the_least_s() {
        let robot = presets::get("planar3").unwrap();
        let request = IkScanRequest { xyz_m: [2.4, 0.2, 0.0], step_deg: 1.0, from: None };
        let report = ik_scan(&robot, &request).unwrap();
        assert_eq!(report.status, "ok");
        let chosen = report.chosen.unwrap();
        assert!(report.rows.iter().all(|r| r.s_deg >= report.rows[chosen].s_deg));
        let off_plane = IkScanRequest { xyz_m: [2.4, 0.2, 1.0], ..request };
        assert_eq!(ik_scan(&robot, &off_plane).unwrap().status, "unreachable");
    }
}
