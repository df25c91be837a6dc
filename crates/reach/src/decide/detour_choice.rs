//! Choosing among seed 000's detours around a point obstacle.
//!
//! When the direct move is blocked, seed 000 goes around the obstacle `H` through two
//! waypoints on a circle about it. The perpendicular construction has two sides: the base
//! side ([`WaypointRule::Perpendicular`], the thesis's choice) and the far side
//! ([`WaypointRule::PerpendicularFar`]). [`choose_detour`] plans both with
//! [`plan_detour`] and ranks the ones that succeed by [`DetourCriterion`]s.
//!
//! The IK of each leg is the thesis's minimum-change row of the self-motion scan, so each side
//! yields one configuration sequence: the alternatives are the two sides, no more. When the
//! move is direct, or only one side succeeds, there is genuinely one candidate and the result
//! says so ([`DetourChoice::alternatives`]) rather than inventing a choice.

use serde::Serialize;

use super::DecideError;
use super::mcdm::{Criterion, DecisionMatrix, Direction, Method, Ranking, normalise_weights, rank};
use crate::ik::planar::PlanarRedundant;
use crate::world::detour::{DetourOptions, DetourOutcome, DetourPlan, P2, WaypointRule, arm_points, plan_detour};

/// A criterion evaluated on one detour plan.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DetourCriterion {
    /// Seed 000's `S`, summed over the legs (`Σ |Δα| + |Δβ| + |Δγ|`). Unit `rad`; less is better.
    TotalChange,
    /// Smallest link–obstacle distance along the legs (joint-interpolated). Unit `m`; more is
    /// better.
    Clearance,
    /// Length of the gripper's polyline start → waypoints → target. Unit `m`; less is better.
    PathLength,
}

impl DetourCriterion {
    /// Every detour criterion, in a stable order.
    pub const ALL: [DetourCriterion; 3] =
        [DetourCriterion::TotalChange, DetourCriterion::Clearance, DetourCriterion::PathLength];

    /// Parses `s` (or `change`), `clearance`, `path_length`.
    #[must_use]
    pub fn parse(name: &str) -> Option<DetourCriterion> {
        match name.trim().to_ascii_lowercase().replace('-', "_").as_str() {
            "s" | "change" => Some(DetourCriterion::TotalChange),
            "clearance" => Some(DetourCriterion::Clearance),
            "path_length" => Some(DetourCriterion::PathLength),
            _ => None,
        }
    }

    /// Name, unit, direction.
    #[must_use]
    pub fn describe(self) -> Criterion {
        match self {
            DetourCriterion::TotalChange => Criterion::new("s", "rad", Direction::LessIsBetter),
            DetourCriterion::Clearance => Criterion::new("clearance", "m", Direction::MoreIsBetter),
            DetourCriterion::PathLength => Criterion::new("path_length", "m", Direction::LessIsBetter),
        }
    }

    fn evaluate(self, arm: &PlanarRedundant, start: &[f64; 3], plan: &DetourPlan) -> f64 {
        match self {
            DetourCriterion::TotalChange => plan.leg_s.iter().sum(),
            // No obstacles: nothing to clear; every candidate scores the same.
            DetourCriterion::Clearance => plan.min_clearance.unwrap_or(0.0),
            DetourCriterion::PathLength => {
                let mut prev: P2 = arm_points(arm, start)[3];
                plan.waypoints
                    .iter()
                    .map(|p| {
                        let d = (p[0] - prev[0]).hypot(p[1] - prev[1]);
                        prev = *p;
                        d
                    })
                    .sum()
            }
        }
    }
}

/// One detour alternative.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetourCandidate {
    /// `base_side` or `far_side` (`direct` when the move is not blocked).
    pub side: &'static str,
    /// The plan.
    pub plan: DetourPlan,
    /// Criterion values, in the order of the criteria (empty when the plan failed).
    pub values: Vec<f64>,
}

/// The result of [`choose_detour`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetourChoice {
    /// Every side planned (one when the move is direct or the target unreachable).
    pub candidates: Vec<DetourCandidate>,
    /// Number of successful alternatives (1: no real choice; 0: no plan succeeded).
    pub alternatives: usize,
    /// Ranking of the successful candidates (indices into `successful`) when there are two.
    pub ranking: Option<Ranking>,
    /// Indices into `candidates` of the successful ones (the ranking's rows).
    pub successful: Vec<usize>,
    /// Index into `candidates` of the chosen plan (`None` when none succeeded).
    pub chosen: Option<usize>,
}

/// How detours are ranked: criteria, one weight per criterion, method.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DetourRanking<'a> {
    /// The criteria (at least one).
    pub criteria: &'a [DetourCriterion],
    /// One weight per criterion, `>= 0`, not all zero.
    pub weights: &'a [f64],
    /// The ranking method.
    pub method: Method,
}

/// Plans the direct move or both detour sides and ranks the successful ones (module docs).
///
/// `options.waypoints` is ignored for the two sides (they are the perpendicular construction);
/// everything else is passed to [`plan_detour`].
///
/// # Errors
/// [`DecideError::NoCriteria`], weight errors of [`rank`], and [`DecideError::Criterion`]
/// wrapping a [`plan_detour`] error.
pub fn choose_detour(
    arm: &PlanarRedundant,
    start: &[f64; 3],
    target: P2,
    obstacles: &[P2],
    options: &DetourOptions,
    ranking: &DetourRanking<'_>,
) -> Result<DetourChoice, DecideError> {
    let DetourRanking { criteria, weights, method } = *ranking;
    if criteria.is_empty() {
        return Err(DecideError::NoCriteria);
    }
    let describe: Vec<Criterion> = criteria.iter().map(|c| c.describe()).collect();
    // Check the weights before planning.
    let names: Vec<&str> = describe.iter().map(|c| c.name.as_str()).collect();
    normalise_weights(&names, weights)?;
    let plan = |rule: WaypointRule| {
        plan_detour(arm, start, target, obstacles, &DetourOptions { waypoints: rule, ..*options })
            .map_err(|e| DecideError::Criterion { criterion: "detour".into(), reason: e.to_string() })
    };
    let base = plan(WaypointRule::Perpendicular)?;
    let mut candidates = Vec::new();
    let values = |p: &DetourPlan| criteria.iter().map(|c| c.evaluate(arm, start, p)).collect::<Vec<f64>>();
    let ok = |p: &DetourPlan| matches!(p.outcome, DetourOutcome::Direct | DetourOutcome::Detour { .. });
    if base.blocked {
        for (side, p) in [("base_side", base), ("far_side", plan(WaypointRule::PerpendicularFar)?)] {
            let v = if ok(&p) { values(&p) } else { Vec::new() };
            candidates.push(DetourCandidate { side, plan: p, values: v });
        }
    } else {
        let v = if ok(&base) { values(&base) } else { Vec::new() };
        candidates.push(DetourCandidate { side: "direct", plan: base, values: v });
    }
    let successful: Vec<usize> = (0..candidates.len()).filter(|&i| ok(&candidates[i].plan)).collect();
    let (ranking, chosen) = match successful.len() {
        0 => (None, None),
        1 => (None, Some(successful[0])),
        _ => {
            let rows = successful.iter().map(|&i| candidates[i].values.clone()).collect();
            let r = rank(&DecisionMatrix::new(describe, rows)?, weights, method)?;
            let best = successful[r.best()];
            (Some(r), Some(best))
        }
    };
    Ok(DetourChoice { alternatives: successful.len(), candidates, ranking, successful, chosen })
}
