//! Task sequencing (seed 001 §8 "visiting"/"collection"): exact vs brute force, heuristic gap,
//! large instances, unreachable targets, the heuristic on asymmetric costs, and mechanical-energy
//! leg costs (asymmetric because of gravity).

use proptest::prelude::*;
use reach::decide::DecideError;
use reach::decide::sequence::{
    EnergyKind, collection, collection_within_budget, energy_costs, joint_change_costs, leg_durations, leg_energy,
    visiting, visiting_heuristic, visiting_within_budget,
};
use reach::effort::dynamics::{potential_energy, trajectory_energy};
use reach::ik::{IkOptions, IkTarget, solve};
use reach::model::presets;
use reach::motion::{JointMotion, JointRates, Profile};

fn path(c: &[Vec<f64>], order: &[usize]) -> f64 {
    let mut prev = 0;
    let mut s = 0.0;
    for &j in order {
        s += c[prev][j];
        prev = j;
    }
    s
}

fn permutations(items: &[usize]) -> Vec<Vec<usize>> {
    if items.is_empty() {
        return vec![vec![]];
    }
    let mut out = Vec::new();
    for k in 0..items.len() {
        let mut rest = items.to_vec();
        let x = rest.remove(k);
        for mut p in permutations(&rest) {
            p.insert(0, x);
            out.push(p);
        }
    }
    out
}

fn square(n: usize) -> impl Strategy<Value = Vec<Vec<f64>>> {
    prop::collection::vec(prop::collection::vec(0.0f64..10.0, n..=n), n..=n)
}

fn instance() -> impl Strategy<Value = Vec<Vec<f64>>> {
    (1usize..=8).prop_flat_map(square) // 0..=7 targets
}

/// Deterministic pseudo-random points in a 6-D joint space, J1-like weighted L1 costs.
fn joint_space_instance(n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut s = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    let mut rnd = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64)
    };
    let w = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0]; // seed 001 §3.8
    let pts: Vec<Vec<f64>> = (0..=n).map(|_| (0..6).map(|_| 4.0 * rnd() - 2.0).collect()).collect();
    pts.iter().map(|a| pts.iter().map(|b| (0..6).map(|i| w[i] * (a[i] - b[i]).abs()).sum()).collect()).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(96))]

    #[test]
    fn visiting_exact_matches_brute_force(c in instance()) {
        let n = c.len() - 1;
        let s = visiting(&c).unwrap();
        prop_assert!(s.exact);
        let mut sorted = s.order.clone();
        sorted.sort();
        prop_assert_eq!(sorted, (1..=n).collect::<Vec<_>>());
        let brute = permutations(&(1..=n).collect::<Vec<_>>()).iter().map(|p| path(&c, p)).fold(f64::INFINITY, f64::min);
        let brute = if n == 0 { 0.0 } else { brute };
        prop_assert!((s.cost - brute).abs() < 1e-9, "dp {} brute {}", s.cost, brute);
        prop_assert!((s.cost - path(&c, &s.order)).abs() < 1e-12);
    }

    #[test]
    fn visiting_budget_matches_brute_force(c in (1usize..=7).prop_flat_map(square), d in square(7), budget in 0.0f64..25.0) {
        let k = c.len();
        let d: Vec<Vec<f64>> = d[..k].iter().map(|r| r[..k].to_vec()).collect();
        let n = k - 1;
        let s = visiting_within_budget(&c, &d, budget).unwrap();
        // Brute force: every subset, every order.
        let mut best = (0usize, 0.0f64);
        for mask in 1u32..(1 << n) {
            let items: Vec<usize> = (1..=n).filter(|j| mask & (1 << (j - 1)) != 0).collect();
            for p in permutations(&items) {
                let t = path(&d, &p);
                if t <= budget && (p.len() > best.0 || (p.len() == best.0 && t < best.1)) {
                    best = (p.len(), t);
                }
            }
        }
        prop_assert_eq!(s.order.len(), best.0);
        prop_assert!((s.duration.unwrap() - best.1).abs() < 1e-9);
        prop_assert!(s.duration.unwrap() <= budget);
    }

    #[test]
    fn collection_energy_is_order_free_and_budget_optimal(c in (1usize..=7).prop_flat_map(square), d in square(7), budget in 0.0f64..40.0) {
        let k = c.len();
        let d: Vec<Vec<f64>> = d[..k].iter().map(|r| r[..k].to_vec()).collect();
        let n = k - 1;
        let s = collection(&c).unwrap();
        let total: f64 = (1..=n).map(|j| c[0][j] + c[j][0]).sum();
        prop_assert!((s.cost - total).abs() < 1e-9);
        prop_assert!(s.legs.windows(2).all(|w| w[0] <= w[1]));
        let b = collection_within_budget(&c, &d, budget).unwrap();
        let most = (0u32..(1 << n))
            .filter(|mask| (1..=n).filter(|j| mask & (1 << (j - 1)) != 0).map(|j| d[0][j] + d[j][0]).sum::<f64>() <= budget)
            .map(|m| m.count_ones() as usize)
            .max()
            .unwrap_or(0);
        prop_assert_eq!(b.order.len(), most);
        prop_assert!(b.duration.unwrap() <= budget);
    }
}

#[test]
fn heuristic_gap_on_ten_targets() {
    let mut worst: f64 = 0.0;
    let mut sum = 0.0;
    let runs = 100;
    for seed in 0..runs {
        let c = joint_space_instance(10, seed);
        let exact = visiting(&c).unwrap();
        assert!(exact.exact);
        let h = visiting_heuristic(&c).unwrap();
        assert!(h.cost >= exact.cost - 1e-12);
        let gap = h.cost / exact.cost - 1.0;
        worst = worst.max(gap);
        sum += gap;
    }
    eprintln!(
        "NN+2-opt gap over {runs} ten-target instances: mean {:.4}%, max {:.4}%",
        100.0 * sum / runs as f64,
        100.0 * worst
    );
    assert!(sum / (runs as f64) < 0.03, "mean gap {}", sum / runs as f64);
    assert!(worst < 0.15, "max gap {worst}");
}

#[test]
fn two_hundred_targets_finish() {
    let c = joint_space_instance(200, 7);
    let t = std::time::Instant::now();
    let s = visiting(&c).unwrap();
    let dt = t.elapsed().as_secs_f64();
    assert!(!s.exact);
    assert_eq!(s.order.len(), 200);
    // 2-opt cannot be worse than its nearest-neighbour start.
    let mut nn = vec![];
    let mut left: Vec<usize> = (1..=200).collect();
    let mut cur = 0;
    while !left.is_empty() {
        let k = (0..left.len()).fold(0, |b, k| if c[cur][left[k]] < c[cur][left[b]] { k } else { b });
        cur = left.remove(k);
        nn.push(cur);
    }
    assert!(s.cost <= path(&c, &nn) + 1e-9);
    eprintln!("200 targets: {dt:.3} s, cost {:.3} (NN {:.3})", s.cost, path(&c, &nn));
    assert!(dt < 5.0, "took {dt} s (target 1 s; generous bound for a loaded machine)");
}

#[test]
fn unreachable_targets_are_skipped() {
    let puma = presets::get("puma560").unwrap();
    let start = [0.0, 0.5, -0.5, 0.0, 0.3, 0.0];
    let q_a = [0.3, 0.6, -0.9, 0.4, 0.7, -0.2];
    let q_b = [-0.4, 0.4, -0.6, 0.1, 0.5, 0.3];
    let far = IkTarget::Position(nalgebra::Point3::new(5.0, 0.0, 0.0));
    let opts = IkOptions::default();
    let targets = vec![
        solve(&puma, &IkTarget::Pose(puma.fk(&q_a).unwrap()), &opts).unwrap(),
        solve(&puma, &far, &opts).unwrap(),
        solve(&puma, &IkTarget::Pose(puma.fk(&q_b).unwrap()), &opts).unwrap(),
    ];
    let w = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0];
    let cc = joint_change_costs(&puma, &start, &targets, &w).unwrap();
    assert!(cc.configs[2].is_none());
    assert!(cc.costs[0][2].is_infinite());
    let s = visiting(&cc.costs).unwrap();
    assert_eq!(s.skipped, vec![2]);
    assert_eq!(s.order.len(), 2);
    let c = collection(&cc.costs).unwrap();
    assert_eq!(c.skipped, vec![2]);
    // J1 by hand for start → the configuration chosen for target 1.
    let q1 = cc.configs[1].as_ref().unwrap();
    let j1: f64 = (0..6).map(|i| w[i] * puma.joint_difference(i, start[i], q1[i]).abs()).sum();
    assert!((cc.costs[0][1] - j1).abs() < 1e-12);
}

#[test]
fn bad_matrices_rejected() {
    use reach::decide::DecideError;
    assert!(matches!(visiting(&[]), Err(DecideError::CostShape { .. })));
    assert!(matches!(visiting(&[vec![0.0, 1.0], vec![1.0]]), Err(DecideError::CostShape { .. })));
    assert!(matches!(
        visiting(&[vec![0.0, -1.0], vec![1.0, 0.0]]),
        Err(DecideError::InvalidCost { from: 0, to: 1, .. })
    ));
    assert!(matches!(collection(&[vec![0.0, f64::NAN], vec![1.0, 0.0]]), Err(DecideError::InvalidCost { .. })));
    let c = vec![vec![0.0, 1.0], vec![1.0, 0.0]];
    assert!(matches!(visiting_within_budget(&c, &c, f64::NAN), Err(DecideError::InvalidBudget(_))));
    assert!(matches!(collection_within_budget(&c, &[vec![0.0]], 1.0), Err(DecideError::CostShape { .. })));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Random matrices are asymmetric (`c[i][j] != c[j][i]`): the heuristic must still return a
    /// permutation whose reported cost is the recomputed sum, no better than brute force, and a
    /// true 2-opt local optimum — no segment reversal, evaluated here by recomputing the whole
    /// reversed path, lowers the cost (this checks 2-opt's O(1) asymmetric evaluation).
    #[test]
    fn heuristic_on_asymmetric_costs_is_a_valid_two_opt_optimum(c in instance()) {
        let n = c.len() - 1;
        let s = visiting_heuristic(&c).unwrap();
        prop_assert!(!s.exact);
        let mut sorted = s.order.clone();
        sorted.sort();
        prop_assert_eq!(sorted, (1..=n).collect::<Vec<_>>());
        let recomputed = path(&c, &s.order);
        prop_assert!((s.cost - recomputed).abs() < 1e-12, "reported {} recomputed {}", s.cost, recomputed);
        prop_assert!((s.legs.iter().sum::<f64>() - recomputed).abs() < 1e-12);
        let brute = permutations(&(1..=n).collect::<Vec<_>>()).iter().map(|p| path(&c, p)).fold(f64::INFINITY, f64::min);
        let brute = if n == 0 { 0.0 } else { brute };
        prop_assert!(s.cost >= brute - 1e-9);
        for i in 0..n {
            for j in i + 1..n {
                let mut r = s.order.clone();
                r[i..=j].reverse();
                let reversed = path(&c, &r);
                prop_assert!(reversed >= s.cost - 1e-9 * (1.0 + s.cost), "reversing {i}..={j}: {reversed} < {}", s.cost);
            }
        }
    }
}

/// PUMA 560 configurations: tool high (arm stretched up) and tool low (shoulder and elbow bent).
fn puma_high_low() -> (reach::Robot, Vec<f64>, Vec<f64>) {
    let puma = presets::get("puma560").unwrap();
    let high = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let low = vec![0.3, -0.9, 0.6, 0.2, -0.4, 0.1];
    (puma, high, low)
}

fn puma_rates() -> JointRates {
    JointRates::new(vec![1.0, 1.0, 1.0, 2.0, 2.0, 2.0], None).unwrap()
}

/// Time reversal: the reverse of a rest-to-rest move with a symmetric profile is `q(T − t)`,
/// with the same torques at mirrored instants and negated rates, so `∫ Σ|τᵢ·q̇ᵢ| dt` is the same
/// both ways — lifting and lowering cost the same under this functional (braking counted as
/// spent), while both cover the potential energy gained when lifting.
#[test]
fn energy_of_a_leg_equals_its_reverse_and_covers_the_potential_energy_gained() {
    let (puma, high, low) = puma_high_low();
    let configs = vec![Some(low.clone()), Some(high.clone()), None];
    let d = leg_durations(&puma, &configs, &puma_rates(), Profile::Cycloidal).unwrap();
    assert!((d[0][1] - d[1][0]).abs() < 1e-12, "same joint distance, same duration");
    assert!(d[0][2].is_infinite() && d[2][1].is_infinite() && d[2][2].is_infinite());
    let e = energy_costs(&puma, &configs, &d, Profile::Cycloidal, EnergyKind::Absolute).unwrap();
    let (up, down) = (e[0][1], e[1][0]);
    let gained = potential_energy(&puma, &high).unwrap() - potential_energy(&puma, &low).unwrap();
    assert!(gained > 5.0, "the tool-high configuration is higher: ΔV = {gained} J");
    // Rest to rest: ∫Σ|τq̇| ≥ ∫Στq̇ = ΔV (the trapezoid rule on 65 samples is within 1 %).
    assert!(up >= 0.99 * gained, "lifting {up} J < ΔV {gained} J");
    assert!((up - down).abs() < 1e-9 * up, "lifting {up} J vs lowering {down} J");
    // A slower move spends less on accelerating, never less than ΔV.
    let slow = leg_energy(&puma, &low, &high, 3.0 * d[0][1], Profile::Cycloidal, EnergyKind::Absolute).unwrap();
    assert!(slow < up && slow >= 0.99 * gained, "slow {slow} J, fast {up} J, ΔV {gained} J");
    assert_eq!(e[0][0], 0.0);
    assert!(e[0][2].is_infinite() && e[2][0].is_infinite());
}

/// Positive work (braking free) is direction-dependent: lifting costs lowering plus the potential
/// energy gained, and the two add up to the braking-counted energy; the asymmetric matrix goes
/// through the exact solver, which takes the cheap direction.
#[test]
fn positive_work_of_lifting_exceeds_lowering_by_the_potential_energy_gained() {
    let (puma, high, low) = puma_high_low();
    let configs = vec![Some(low.clone()), Some(high.clone())];
    let d = leg_durations(&puma, &configs, &puma_rates(), Profile::Cycloidal).unwrap();
    let w = energy_costs(&puma, &configs, &d, Profile::Cycloidal, EnergyKind::PositiveWork).unwrap();
    let e = energy_costs(&puma, &configs, &d, Profile::Cycloidal, EnergyKind::Absolute).unwrap();
    let (up, down) = (w[0][1], w[1][0]);
    let gained = potential_energy(&puma, &high).unwrap() - potential_energy(&puma, &low).unwrap();
    assert!((up - down - gained).abs() < 0.01 * gained, "W⁺ up {up} J, down {down} J, ΔV {gained} J");
    assert!((up + down - e[0][1]).abs() < 1e-9 * e[0][1], "W⁺ up + down = E: {up} + {down} vs {}", e[0][1]);
    assert!(down > 0.0, "lowering still accelerates the arm");
    // Visiting the other node from either end: from `high` (node 0 swapped) is cheaper.
    let from_high = vec![vec![0.0, w[1][0]], vec![w[0][1], 0.0]];
    assert!((visiting(&w).unwrap().cost - up).abs() < 1e-12);
    assert!((visiting(&from_high).unwrap().cost - down).abs() < 1e-12);
}

#[test]
fn leg_energy_agrees_with_finely_sampled_finite_differences() {
    let (puma, high, low) = puma_high_low();
    let t = 2.5;
    let coarse = leg_energy(&puma, &low, &high, t, Profile::Cycloidal, EnergyKind::Absolute).unwrap();
    let motion = JointMotion::for_robot(&puma, &low, &high, 0.0, t, Profile::Cycloidal).unwrap();
    let times: Vec<f64> = (0..=4000).map(|k| t * f64::from(k) / 4000.0).collect();
    let q: Vec<Vec<f64>> = times.iter().map(|&x| motion.position(x)).collect();
    let fine = trajectory_energy(&puma, &times, &q).unwrap();
    assert!((coarse - fine).abs() < 0.01 * fine, "65 samples {coarse} J vs 4001 samples {fine} J");
    // No motion, no energy; bad durations rejected.
    assert_eq!(leg_energy(&puma, &low, &low, 0.0, Profile::Cycloidal, EnergyKind::Absolute).unwrap(), 0.0);
    for bad in [-1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            leg_energy(&puma, &low, &high, bad, Profile::Cycloidal, EnergyKind::Absolute),
            Err(DecideError::BadVector { what: "leg duration", .. })
        ));
    }
}

#[test]
fn energy_costs_need_link_masses_and_matching_shapes() {
    let spbu6 = presets::get("spbu6").unwrap();
    assert!(!spbu6.has_dynamics(), "this test needs a preset without masses");
    let q = vec![0.0; 6];
    let e = leg_energy(&spbu6, &q, &[0.1; 6], 1.0, Profile::Cycloidal, EnergyKind::PositiveWork).unwrap_err();
    assert!(e.to_string().contains("spbu6") && e.to_string().contains("inertial"), "{e}");
    let (puma, high, low) = puma_high_low();
    let configs = vec![Some(low), Some(high)];
    let wrong = vec![vec![0.0; 3]; 3];
    assert!(matches!(
        energy_costs(&puma, &configs, &wrong, Profile::Cycloidal, EnergyKind::Absolute),
        Err(DecideError::CostShape { what: "durations", .. })
    ));
    let missing = vec![None, configs[1].clone()];
    assert!(matches!(
        energy_costs(&puma, &missing, &[vec![0.0; 2], vec![0.0; 2]], Profile::Cycloidal, EnergyKind::Absolute),
        Err(DecideError::BadVector { what: "configurations", .. })
    ));
}

/// Regression: `reach tasks` costed a leg's J1 with the wrapped joint difference but timed it
/// (and its energy) with the literal one. On ur5 (joint 1 bounded to ±360°) a leg from +170°
/// to −170° travels 340° in joint space: J1, duration and the move itself must all agree.
#[test]
fn leg_j1_and_duration_use_the_same_joint_difference_across_180_deg() {
    let ur5 = presets::get("ur5").unwrap();
    let deg = |v: [f64; 6]| v.iter().map(|x| x.to_radians()).collect::<Vec<f64>>();
    let a = deg([170.0, -90.0, 90.0, 0.0, 90.0, 0.0]);
    let b = deg([-170.0, -90.0, 90.0, 0.0, 90.0, 0.0]);
    let w = vec![1.0; 6];
    let configs = vec![Some(a.clone()), Some(b.clone())];
    let costs = reach::decide::sequence::config_costs(&ur5, configs.clone(), &w).unwrap();
    let travelled = ur5.joint_difference(0, a[0], b[0]).abs();
    assert!((travelled - 340f64.to_radians()).abs() < 1e-12, "ur5 joint 1 is bounded: literal difference");
    assert!((costs.costs[0][1] - travelled).abs() < 1e-12, "J1 {} rad, travelled {travelled} rad", costs.costs[0][1]);
    assert!((costs.costs[1][0] - travelled).abs() < 1e-12);
    let rates = JointRates::from_robot(&ur5, None).unwrap();
    let d = leg_durations(&ur5, &configs, &rates, Profile::Cycloidal).unwrap();
    let motion = JointMotion::for_robot(&ur5, &a, &b, 0.0, d[0][1], Profile::Cycloidal).unwrap();
    let end = motion.position(d[0][1]);
    assert!((end[0] - b[0]).abs() < 1e-9 && (motion.position(d[0][1] / 2.0)[0]).abs() < 1e-9, "the move passes 0°");
    let fastest = reach::decide::motion_criteria::point_to_point_duration(
        &[travelled, 0.0, 0.0, 0.0, 0.0, 0.0],
        &rates,
        Profile::Cycloidal,
    )
    .unwrap();
    assert!((d[0][1] - fastest).abs() < 1e-12, "duration {} s times the same 340°", d[0][1]);
}
