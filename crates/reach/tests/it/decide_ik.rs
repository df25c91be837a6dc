//! Criteria on IK solutions and `choose`: different criteria pick different puma560 solutions.

use reach::decide::{DecideError, IkCriterion, Method, choose, ik_matrix};
use reach::ik::{IkOptions, IkTarget, solve};
use reach::model::presets;

#[test]
fn criteria_choose_different_puma_solutions() {
    let puma = presets::get("puma560").unwrap();
    let q0 = [0.3, 0.6, -0.9, 0.4, 0.7, -0.2];
    let target = IkTarget::Pose(puma.fk(&q0).unwrap());
    let sols = solve(&puma, &target, &IkOptions::default()).unwrap();
    let feasible: Vec<_> = sols.feasible().cloned().collect();
    assert!(feasible.len() >= 2, "need several branches within limits; got {}", feasible.len());

    let change = IkCriterion::JointChange { reference: q0.to_vec(), weights: vec![1.0; 6] };
    let crits = [change.clone(), IkCriterion::LimitMargin, IkCriterion::Manipulability, IkCriterion::SigmaMin];
    let m = ik_matrix(&puma, &feasible, &crits).unwrap();

    // Independent checks of each column.
    for (i, s) in feasible.iter().enumerate() {
        let man = puma.manipulability(&s.q).unwrap();
        assert_eq!(m.rows()[i][2], man.yoshikawa);
        assert_eq!(m.rows()[i][3], man.sigma_min);
        let margin = puma
            .joints()
            .iter()
            .zip(&s.q)
            .map(|(j, &v)| ((v - j.limits.lower).min(j.limits.upper - v)) / (j.limits.upper - j.limits.lower))
            .fold(0.5f64, f64::min);
        assert!((m.rows()[i][1] - margin).abs() < 1e-12);
    }

    // Joint change alone picks the solution that reproduces q0 (change ≈ 0).
    let by_change = choose(&puma, &feasible, std::slice::from_ref(&change), &[1.0], Method::Topsis).unwrap();
    let best = &feasible[by_change.best()];
    assert!(best.q.iter().zip(&q0).all(|(a, b)| reach::angle::wrap(a - b).abs() < 1e-6), "{:?}", best.q);
    assert_eq!(m.rows()[by_change.best()][0], m.rows().iter().map(|r| r[0]).fold(f64::INFINITY, f64::min));

    // Manipulability alone picks the solution with the largest Yoshikawa measure, which here is
    // a different branch; the limit margin picks yet another (or at least not the change one).
    let by_man = choose(&puma, &feasible, &[IkCriterion::Manipulability], &[1.0], Method::WeightedSum).unwrap();
    let max_man = m.rows().iter().map(|r| r[2]).fold(0.0, f64::max);
    assert_eq!(m.rows()[by_man.best()][2], max_man);
    let by_margin = choose(&puma, &feasible, &[IkCriterion::LimitMargin], &[1.0], Method::Vikor).unwrap();
    let bests = [by_change.best(), by_man.best(), by_margin.best()];
    let distinct = {
        let mut b = bests.to_vec();
        b.sort();
        b.dedup();
        b.len()
    };
    assert!(distinct >= 2, "criteria should disagree: {bests:?}, matrix {:?}", m.rows());

    // The combined ranking explains itself.
    let all = choose(&puma, &feasible, &crits, &[0.5, 0.2, 0.2, 0.1], Method::Topsis).unwrap();
    assert_eq!(all.ranked.len(), feasible.len());
    assert!(all.ranked.iter().all(|c| c.normalised.len() == 4 && c.distance_ideal.is_some()));
    let json = serde_json::to_string(&all).unwrap();
    assert!(json.contains("\"manipulability\"") && json.contains("\"more_is_better\""));
}

#[test]
fn ik_criteria_bad_input() {
    let puma = presets::get("puma560").unwrap();
    assert!(matches!(ik_matrix(&puma, &[], &[IkCriterion::LimitMargin]), Err(DecideError::NoCandidates)));
    let sols = solve(&puma, &IkTarget::Pose(puma.fk(&[0.1; 6]).unwrap()), &IkOptions::default()).unwrap();
    let bad = IkCriterion::JointChange { reference: vec![0.0; 5], weights: vec![1.0; 6] };
    assert!(matches!(ik_matrix(&puma, &sols.solutions, &[bad]), Err(DecideError::BadVector { what: "reference", .. })));
    let neg = IkCriterion::JointChange { reference: vec![0.0; 6], weights: vec![1.0, -1.0, 1.0, 1.0, 1.0, 1.0] };
    assert!(matches!(ik_matrix(&puma, &sols.solutions, &[neg]), Err(DecideError::BadVector { .. })));
}
