//! Multi-criteria methods: textbook examples, invariance, Pareto filter, bad input.

use proptest::prelude::*;
use reach::decide::DecideError;
use reach::decide::mcdm::{Criterion, DecisionMatrix, Direction, Method, normalise_weights, rank};

use Direction::{LessIsBetter as Less, MoreIsBetter as More};

/// Hwang & Yoon (1981), "Multiple Attribute Decision Making", the fighter-aircraft example:
/// maximum speed (Mach), ferry range (NM), maximum payload (lb), purchase cost ($10⁶, less is
/// better), reliability and manoeuvrability (interval scale 1–9).
fn fighters() -> DecisionMatrix {
    let c = |n: &str, u: &str, d| Criterion::new(n, u, d);
    DecisionMatrix::new(
        vec![
            c("speed", "Mach", More),
            c("range", "NM", More),
            c("payload", "lb", More),
            c("cost", "M$", Less),
            c("reliability", "1", More),
            c("manoeuvrability", "1", More),
        ],
        vec![
            vec![2.0, 1500.0, 20000.0, 5.5, 5.0, 9.0],
            vec![2.5, 2700.0, 18000.0, 6.5, 3.0, 5.0],
            vec![1.8, 2000.0, 21000.0, 4.5, 7.0, 7.0],
            vec![2.2, 1800.0, 20000.0, 5.0, 5.0, 5.0],
        ],
    )
    .unwrap()
}
const FIGHTER_W: [f64; 6] = [0.2, 0.1, 0.1, 0.1, 0.2, 0.3];

#[test]
fn topsis_hwang_yoon_fighter_aircraft() {
    let r = rank(&fighters(), &FIGHTER_W, Method::Topsis).unwrap();
    // The book's closeness coefficients (3 decimals): A1 0.643, A2 0.268, A3 0.614, A4 0.312;
    // order A1 > A3 > A4 > A2. Recomputed independently (plain script, vector normalisation):
    // 0.643277, 0.268384, 0.613542, 0.312291.
    let expected = [0.643277, 0.268384, 0.613542, 0.312291];
    for (i, e) in expected.iter().enumerate() {
        let c = r.candidate(i).unwrap();
        assert!((c.score - e).abs() < 1e-6, "A{}: {} vs {e}", i + 1, c.score);
    }
    assert_eq!(r.order(), vec![0, 2, 3, 1]);
    // Distances for A1 (same script): d+ = 0.054557, d- = 0.098383.
    let a1 = r.candidate(0).unwrap();
    assert!((a1.distance_ideal.unwrap() - 0.054557).abs() < 1e-6);
    assert!((a1.distance_anti_ideal.unwrap() - 0.098383).abs() < 1e-6);
    // Vector normalisation: speed column norm = sqrt(4 + 6.25 + 3.24 + 4.84) = sqrt(18.33).
    assert!((a1.normalised[0] - 2.0 / 18.33f64.sqrt()).abs() < 1e-12);
}

#[test]
fn vikor_on_fighter_aircraft_by_hand() {
    // VIKOR (Opricovic & Tzeng 2004, v = 0.5) on the same data, regrets by hand:
    // A2 is best on speed and range and worst on the other four criteria:
    //   S = 0.1 + 0.1 + 0.2 + 0.3 = 0.7, R = 0.3.
    // A1: speed 0.2·0.5/0.7, range 0.1·1200/1200, payload 0.1·1000/3000, cost 0.1·1/2,
    //     reliability 0.2·2/4, manoeuvrability 0 → S = 1/7 + 0.1 + 1/30 + 0.05 + 0.1, R = 1/7.
    // A3: speed 0.2, range 0.1·700/1200, payload 0, cost 0, reliability 0, manoeuvr. 0.3·2/4
    //     → S = 0.2 + 7/120 + 0.15, R = 0.2.
    // A4: speed 0.2·0.3/0.7, range 0.1·900/1200, payload 0.1/3, cost 0.1·0.5/2, reliab. 0.1,
    //     manoeuvr. 0.3 → S = 0.6/7 + 0.075 + 1/30 + 0.025 + 0.1 + 0.3, R = 0.3.
    let s = [
        1.0 / 7.0 + 0.1 + 1.0 / 30.0 + 0.05 + 0.1,
        0.7,
        0.2 + 7.0 / 120.0 + 0.15,
        0.6 / 7.0 + 0.075 + 1.0 / 30.0 + 0.025 + 0.1 + 0.3,
    ];
    let rr = [1.0 / 7.0, 0.3, 0.2, 0.3];
    let (s_lo, s_hi) = (s[2], s[1]);
    let (r_lo, r_hi) = (rr[0], 0.3);
    let r = rank(&fighters(), &FIGHTER_W, Method::Vikor).unwrap();
    for i in 0..4 {
        let c = r.candidate(i).unwrap();
        let q = 0.5 * (s[i] - s_lo) / (s_hi - s_lo) + 0.5 * (rr[i] - r_lo) / (r_hi - r_lo);
        assert!((c.vikor_s.unwrap() - s[i]).abs() < 1e-12, "S of A{}", i + 1);
        assert!((c.vikor_r.unwrap() - rr[i]).abs() < 1e-12, "R of A{}", i + 1);
        assert!((c.score - q).abs() < 1e-12, "Q of A{}", i + 1);
    }
    // Q: A1 0.0306, A3 0.1818, A4 0.8612, A2 1.
    assert_eq!(r.order(), vec![0, 2, 3, 1]);
    assert!((r.candidate(0).unwrap().score - 0.030612).abs() < 1e-6);
    // Acceptance (Opricovic & Tzeng 2004 §3 step 5), m = 4 so DQ = 1/3:
    // C1 fails: Q(A3) − Q(A1) = 0.1818 − 0.0306 = 0.151 < 1/3;
    // C2 holds: A1 is best by R (1/7 < 0.2 of A3), though not by S (A3's 0.4083 < A1's 0.4262).
    // Compromise set: Q − Q(A1) < 1/3 → A1 and A3 (A4 is 0.831 behind).
    let acceptance = r.vikor.as_ref().unwrap();
    assert!((acceptance.dq - 1.0 / 3.0).abs() < 1e-15);
    assert!(!acceptance.acceptable_advantage);
    assert!(acceptance.acceptable_stability);
    assert!(!acceptance.accepted());
    assert_eq!(acceptance.compromise, vec![0, 2]);
}

/// Less-is-better rows whose columns already run from 0 to 1, so the regrets are the values.
fn unit_regrets(rows: Vec<Vec<f64>>) -> DecisionMatrix {
    let criteria = (0..rows[0].len()).map(|j| Criterion::new(format!("c{j}"), "1", Less)).collect();
    DecisionMatrix::new(criteria, rows).unwrap()
}

#[test]
fn vikor_acceptable_advantage_without_stability_gives_the_first_two() {
    // Hand-computed from the definitions (Opricovic & Tzeng 2004, v = 0.5), equal weights 1/3,
    // candidates X = (0, 0, 1), Y = (0.9, 0.9, 0.9), Z = (0.91, 0.1, 0), W = (1, 1, 1):
    //   S: X 1/3, Y 0.9, Z 1.01/3, W 1;   R: X 1/3, Y 0.3, Z 0.91/3, W 1/3.
    //   (S − 1/3)/(2/3): X 0, Y 0.85, Z 0.005, W 1;   (R − 0.3)/(1/30): X 1, Y 0, Z 0.1, W 1.
    //   Q: X 0.5, Y 0.425, Z 0.0525, W 1 → order Z, Y, X, W.
    // C1 holds: 0.425 − 0.0525 = 0.3725 ≥ DQ = 1/3. C2 fails: Z is neither best by S (X) nor
    // by R (Y). Compromise set: Z and Y.
    let m = unit_regrets(vec![vec![0.0, 0.0, 1.0], vec![0.9, 0.9, 0.9], vec![0.91, 0.1, 0.0], vec![1.0, 1.0, 1.0]]);
    let r = rank(&m, &[1.0, 1.0, 1.0], Method::Vikor).unwrap();
    assert_eq!(r.order(), vec![2, 1, 0, 3]);
    for (i, q) in [0.5, 0.425, 0.0525, 1.0].into_iter().enumerate() {
        assert!((r.candidate(i).unwrap().score - q).abs() < 1e-12, "Q of {i}");
    }
    let acceptance = r.vikor.as_ref().unwrap();
    assert!(acceptance.acceptable_advantage);
    assert!(!acceptance.acceptable_stability);
    assert_eq!(acceptance.compromise, vec![2, 1]);
}

#[test]
fn vikor_accepts_a_candidate_best_on_everything() {
    // A0 = (0, 0) is best on both criteria: S = R = Q = 0; A1 = (1, 0.5) and A2 = (0.5, 1) have
    // S = 0.75, R = 0.5, Q = 1. C1: 1 − 0 ≥ DQ = 1/2; C2: A0 best by S and R. Compromise: A0.
    let m = unit_regrets(vec![vec![0.0, 0.0], vec![1.0, 0.5], vec![0.5, 1.0]]);
    let r = rank(&m, &[1.0, 1.0], Method::Vikor).unwrap();
    let acceptance = r.vikor.as_ref().unwrap();
    assert!(acceptance.accepted());
    assert_eq!((acceptance.dq, acceptance.compromise.clone()), (0.5, vec![0]));
    // Only VIKOR reports the acceptance test.
    for method in [Method::WeightedSum, Method::Topsis] {
        assert!(rank(&m, &[1.0, 1.0], method).unwrap().vikor.is_none());
    }
}

#[test]
fn weighted_sum_min_max_by_hand() {
    // Two criteria: cost (less better) and quality (more better), weights 1 and 3 (→ 0.25, 0.75).
    let m = DecisionMatrix::new(
        vec![Criterion::new("cost", "J", Less), Criterion::new("quality", "1", More)],
        vec![vec![10.0, 1.0], vec![20.0, 5.0], vec![15.0, 3.0]],
    )
    .unwrap();
    let r = rank(&m, &[1.0, 3.0], Method::WeightedSum).unwrap();
    // normalised: A0 (1, 0) → 0.25; A1 (0, 1) → 0.75; A2 (0.5, 0.5) → 0.5.
    assert_eq!(r.order(), vec![1, 2, 0]);
    assert!((r.candidate(0).unwrap().score - 0.25).abs() < 1e-15);
    assert!((r.candidate(2).unwrap().score - 0.5).abs() < 1e-15);
    assert_eq!(r.candidate(2).unwrap().normalised, vec![0.5, 0.5]);
    assert_eq!(r.weights, vec![0.25, 0.75]);
}

#[test]
fn ties_broken_by_index_and_constant_column_neutral() {
    // Column 1 is constant: it cannot discriminate and must not change the order given by column 0.
    let m = DecisionMatrix::new(
        vec![Criterion::new("a", "1", More), Criterion::new("flat", "1", More)],
        vec![vec![1.0, 7.0], vec![3.0, 7.0], vec![3.0, 7.0], vec![2.0, 7.0]],
    )
    .unwrap();
    for method in [Method::WeightedSum, Method::Topsis, Method::Vikor] {
        let r = rank(&m, &[0.5, 0.5], method).unwrap();
        assert_eq!(r.order(), vec![1, 2, 3, 0], "{method:?}");
        assert_eq!(r.ranked[0].score, r.ranked[1].score);
    }
    // All-zero column under TOPSIS (norm 0): normalised 0, no division by zero.
    let z = DecisionMatrix::new(
        vec![Criterion::new("a", "1", Less), Criterion::new("zero", "1", More)],
        vec![vec![1.0, 0.0], vec![2.0, 0.0]],
    )
    .unwrap();
    let r = rank(&z, &[1.0, 1.0], Method::Topsis).unwrap();
    assert_eq!(r.order(), vec![0, 1]);
    assert!(r.ranked.iter().all(|c| c.score.is_finite() && c.normalised[1] == 0.0));
    // Single candidate: ranks first with a finite score under every method.
    let one = DecisionMatrix::new(vec![Criterion::new("a", "1", More)], vec![vec![4.0]]).unwrap();
    for method in [Method::WeightedSum, Method::Topsis, Method::Vikor] {
        let r = rank(&one, &[1.0], method).unwrap();
        assert_eq!(r.best(), 0);
        assert!(r.ranked[0].score.is_finite());
    }
}

#[test]
fn bad_input_is_rejected() {
    let m = fighters();
    assert!(matches!(rank(&m, &[1.0; 5], Method::Topsis), Err(DecideError::WeightCount { expected: 6, found: 5 })));
    assert!(matches!(
        rank(&m, &[1.0, -0.1, 1.0, 1.0, 1.0, 1.0], Method::Topsis),
        Err(DecideError::InvalidWeight { ref criterion, .. }) if criterion == "range"
    ));
    assert!(matches!(rank(&m, &[0.0; 6], Method::Vikor), Err(DecideError::ZeroWeights)));
    assert!(matches!(
        rank(&m, &[f64::NAN, 1.0, 1.0, 1.0, 1.0, 1.0], Method::WeightedSum),
        Err(DecideError::InvalidWeight { .. })
    ));
    let c = vec![Criterion::new("a", "1", More)];
    assert_eq!(DecisionMatrix::new(c.clone(), vec![]), Err(DecideError::NoCandidates));
    assert_eq!(DecisionMatrix::new(vec![], vec![vec![]]), Err(DecideError::NoCriteria));
    assert!(matches!(
        DecisionMatrix::new(c.clone(), vec![vec![1.0], vec![f64::NAN]]),
        Err(DecideError::NonFiniteValue { candidate: 1, .. })
    ));
    assert!(matches!(
        DecisionMatrix::new(c, vec![vec![1.0, 2.0]]),
        Err(DecideError::RowLength { candidate: 0, expected: 1, found: 2 })
    ));
    let msg = rank(&m, &[1.0; 5], Method::Topsis).unwrap_err().to_string();
    assert!(msg.contains("6 weights"), "{msg}");
}

fn dirs() -> impl Strategy<Value = Vec<Direction>> {
    prop::collection::vec(prop::bool::ANY.prop_map(|b| if b { More } else { Less }), 1..5)
}

fn instance() -> impl Strategy<Value = (Vec<Direction>, Vec<Vec<f64>>, Vec<f64>)> {
    dirs().prop_flat_map(|d| {
        let m = d.len();
        (
            Just(d),
            prop::collection::vec(
                prop::collection::vec(0u8..6, m..=m).prop_map(|r| r.into_iter().map(f64::from).collect()),
                1..9,
            ),
            prop::collection::vec(0.05f64..1.0, m..=m),
        )
    })
}

fn matrix(d: &[Direction], rows: Vec<Vec<f64>>) -> DecisionMatrix {
    let c = d.iter().enumerate().map(|(j, &d)| Criterion::new(format!("c{j}"), "1", d)).collect();
    DecisionMatrix::new(c, rows).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn pareto_matches_brute_force((d, rows, _w) in instance()) {
        let m = matrix(&d, rows.clone());
        let front = m.pareto();
        // Brute force from the definition, written independently of `dominates`.
        let better_eq = |a: &[f64], b: &[f64]| d.iter().enumerate().all(|(j, d)| match d { More => a[j] >= b[j], Less => a[j] <= b[j] });
        for i in 0..rows.len() {
            let dominated = (0..rows.len()).any(|k| better_eq(&rows[k], &rows[i]) && rows[k] != rows[i]);
            prop_assert_eq!(front.contains(&i), !dominated, "candidate {}", i);
        }
        prop_assert!(!front.is_empty());
    }

    #[test]
    fn topsis_ranking_invariant_under_unit_scaling((d, rows, w) in instance(), scale in prop::collection::vec(0.001f64..1000.0, 4)) {
        let m = matrix(&d, rows.clone());
        let scaled: Vec<Vec<f64>> = rows.iter().map(|r| r.iter().enumerate().map(|(j, v)| v * scale[j % 4]).collect()).collect();
        let ms = matrix(&d, scaled);
        let a = rank(&m, &w, Method::Topsis).unwrap();
        let b = rank(&ms, &w, Method::Topsis).unwrap();
        for (x, y) in a.ranked.iter().zip(&b.ranked) {
            prop_assert!((x.score - y.score).abs() < 1e-9);
        }
        // Orders equal up to exact ties (whose order is by index in both).
        let ord_a = a.order();
        let ord_b = b.order();
        for k in 0..ord_a.len() {
            if ord_a[k] != ord_b[k] {
                prop_assert!((a.ranked[k].score - b.candidate(ord_a[k]).unwrap().score).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn dominated_candidate_never_first((d, rows, w) in instance()) {
        let m = matrix(&d, rows.clone());
        for method in [Method::WeightedSum, Method::Topsis, Method::Vikor] {
            let r = rank(&m, &w, method).unwrap();
            let best = r.best();
            prop_assert!(!(0..rows.len()).any(|k| m.dominates(k, best)), "{:?} chose dominated {}", method, best);
            prop_assert!(r.ranked[0].pareto_optimal);
        }
    }
}

#[test]
fn normalise_weights_checks_without_a_matrix_and_agrees_with_it() {
    let names = ["a", "b", "c"];
    let w = normalise_weights(&names, &[1.0, 1.0, 2.0]).unwrap();
    assert_eq!(w, vec![0.25, 0.25, 0.5]);
    let m =
        DecisionMatrix::new(names.iter().map(|n| Criterion::new(*n, "1", Less)).collect(), vec![vec![0.0; 3]]).unwrap();
    assert_eq!(m.normalised_weights(&[1.0, 1.0, 2.0]).unwrap(), w);
    assert!(matches!(normalise_weights(&names, &[1.0]), Err(DecideError::WeightCount { expected: 3, found: 1 })));
    match normalise_weights(&names, &[1.0, -1.0, 1.0]) {
        Err(DecideError::InvalidWeight { criterion, value }) => assert_eq!((criterion.as_str(), value), ("b", -1.0)),
        other => panic!("expected an invalid weight, got {other:?}"),
    }
    assert!(matches!(normalise_weights(&names, &[1.0, 1.0, f64::NAN]), Err(DecideError::InvalidWeight { .. })));
    assert!(matches!(normalise_weights(&names, &[0.0; 3]), Err(DecideError::ZeroWeights)));
    assert!(matches!(normalise_weights::<&str>(&[], &[]), Err(DecideError::NoCriteria)));
}
