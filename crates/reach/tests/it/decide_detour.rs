//! Choosing among seed 000's detours (`decide::detour_choice`): both sides of the obstacle are
//! planned, the successful ones ranked by total change S, clearance and gripper path length;
//! a direct move is one candidate, not a choice.

use reach::decide::detour_choice::{DetourCriterion, DetourRanking, choose_detour};
use reach::decide::{DecideError, Method};
use reach::ik::planar::PlanarRedundant;
use reach::model::planar_angles::InteriorAngles;
use reach::model::presets;
use reach::world::detour::{DetourOptions, DetourOutcome, WaypointRule, plan_detour};

fn arm() -> PlanarRedundant {
    PlanarRedundant::from_robot(&presets::get("planar3").unwrap()).unwrap()
}

fn start() -> [f64; 3] {
    let d = f64::to_radians;
    InteriorAngles { alpha: d(150.0), beta: d(140.0), gamma: d(60.0) }.to_joints()
}

/// A coarser IK scan than the thesis's 0.01° keeps the test fast; the choice logic is the same.
fn options() -> DetourOptions {
    DetourOptions { step: 0.1f64.to_radians(), ..DetourOptions::default() }
}

#[test]
fn both_sides_are_planned_and_the_only_feasible_one_is_reported_as_such() {
    let (arm, h) = (arm(), [2.0, 0.7]);
    let all = DetourCriterion::ALL;
    let choice = choose_detour(
        &arm,
        &start(),
        [2.4, 0.2],
        &[h],
        &options(),
        &DetourRanking { criteria: &all, weights: &[1.0, 1.0, 1.0], method: Method::Topsis },
    )
    .unwrap();
    assert_eq!(choice.candidates.len(), 2);
    assert_eq!(choice.candidates[0].side, "base_side");
    assert_eq!(choice.candidates[1].side, "far_side");
    // The base side is the thesis's plan, unchanged.
    let thesis = plan_detour(&arm, &start(), [2.4, 0.2], &[h], &options()).unwrap();
    assert_eq!(choice.candidates[0].plan, thesis);
    assert!(matches!(thesis.outcome, DetourOutcome::Detour { obstacle: 0 }));
    let c = &choice.candidates[0];
    assert!((c.values[0] - c.plan.leg_s.iter().sum::<f64>()).abs() < 1e-12);
    assert_eq!(c.values[1], c.plan.min_clearance.unwrap());
    // The far side mirrors the waypoints about the line K–H; with the minimum-change IK per
    // leg the links sweep over H on the way there, so the first leg is blocked by the very
    // obstacle: one real candidate, no ranking invented.
    let far = plan_detour(
        &arm,
        &start(),
        [2.4, 0.2],
        &[h],
        &DetourOptions { waypoints: WaypointRule::PerpendicularFar, ..options() },
    )
    .unwrap();
    assert_eq!(choice.candidates[1].plan, far);
    assert_ne!(thesis.waypoints[0], far.waypoints[0]);
    assert_eq!(far.outcome, DetourOutcome::LegBlocked { leg: 1, obstacle: 0 });
    assert!(choice.candidates[1].values.is_empty());
    assert_eq!((choice.alternatives, choice.chosen), (1, Some(0)));
    assert!(choice.ranking.is_none());
}

#[test]
fn a_direct_move_is_one_candidate_not_a_choice() {
    let choice = choose_detour(
        &arm(),
        &start(),
        [2.4, 0.2],
        &[],
        &options(),
        &DetourRanking { criteria: &[DetourCriterion::TotalChange], weights: &[1.0], method: Method::Topsis },
    )
    .unwrap();
    assert_eq!((choice.candidates.len(), choice.alternatives, choice.chosen), (1, 1, Some(0)));
    assert_eq!(choice.candidates[0].side, "direct");
    assert!(choice.ranking.is_none());
}

#[test]
fn bad_weights_and_names() {
    let (arm, h) = (arm(), [2.0, 0.7]);
    let crit = [DetourCriterion::TotalChange, DetourCriterion::Clearance];
    let r = choose_detour(
        &arm,
        &start(),
        [2.4, 0.2],
        &[h],
        &options(),
        &DetourRanking { criteria: &crit, weights: &[1.0], method: Method::Topsis },
    );
    assert!(matches!(r, Err(DecideError::WeightCount { expected: 2, found: 1 })));
    let r = choose_detour(
        &arm,
        &start(),
        [2.4, 0.2],
        &[h],
        &options(),
        &DetourRanking { criteria: &crit, weights: &[1.0, -1.0], method: Method::Topsis },
    );
    assert!(matches!(r, Err(DecideError::InvalidWeight { .. })));
    let r = choose_detour(
        &arm,
        &start(),
        [2.4, 0.2],
        &[h],
        &options(),
        &DetourRanking { criteria: &[], weights: &[], method: Method::Topsis },
    );
    assert!(matches!(r, Err(DecideError::NoCriteria)));
    assert_eq!(DetourCriterion::parse("path-length"), Some(DetourCriterion::PathLength));
    assert_eq!(DetourCriterion::parse("stiffness"), None);
}
