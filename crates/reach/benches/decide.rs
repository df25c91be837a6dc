//! Decision benchmarks: task sequencing and multi-criteria ranking.
//!
//! Run with `cargo bench -p reach --bench decide`.
//!
//! * `visiting_exact_12` — Held–Karp on 12 targets;
//! * `visiting_heuristic_200` — nearest neighbour + 2-opt on 200 targets (target ≤ 1 s);
//! * `topsis_8x4` — TOPSIS on 8 candidates × 4 criteria;
//! * `choose_motion_8x101` — six motion criteria (J2, peak velocity and acceleration, limit
//!   margin, smallest manipulability, tool path length) on 8 PUMA 560 trajectories of 101
//!   samples each, ranked by TOPSIS.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::decide::mcdm::{Criterion as Crit, DecisionMatrix, Direction, Method, rank};
use reach::decide::sequence::visiting;
use reach::decide::{MotionCriterion, SampledMotion, choose_motion};

/// Deterministic pseudo-random points in a 6-D joint space with seed 001's J1 weights.
fn instance(n: usize, seed: u64) -> Vec<Vec<f64>> {
    let mut s = seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut rnd = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((s >> 11) as f64) / ((1u64 << 53) as f64)
    };
    let w = [1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0, 1.0 / 18.0, 1.0 / 18.0, 1.0 / 18.0];
    let pts: Vec<Vec<f64>> = (0..=n).map(|_| (0..6).map(|_| 4.0 * rnd() - 2.0).collect()).collect();
    pts.iter().map(|a| pts.iter().map(|b| (0..6).map(|i| w[i] * (a[i] - b[i]).abs()).sum()).collect()).collect()
}

fn bench(c: &mut Criterion) {
    let small = instance(12, 1);
    c.bench_function("visiting_exact_12", |b| b.iter(|| visiting(black_box(&small)).unwrap()));
    let large = instance(200, 2);
    c.bench_function("visiting_heuristic_200", |b| b.iter(|| visiting(black_box(&large)).unwrap()));
    let crits = (0..4)
        .map(|j| {
            Crit::new(format!("c{j}"), "1", if j % 2 == 0 { Direction::MoreIsBetter } else { Direction::LessIsBetter })
        })
        .collect();
    let rows = instance(7, 3).into_iter().map(|r| r[..4].to_vec()).collect();
    let m = DecisionMatrix::new(crits, rows).unwrap();
    c.bench_function("topsis_8x4", |b| b.iter(|| rank(black_box(&m), &[0.4, 0.3, 0.2, 0.1], Method::Topsis).unwrap()));
    let puma = reach::model::presets::get("puma560").unwrap();
    let t: Vec<f64> = (0..=100).map(|k| f64::from(k) * 0.02).collect();
    let tracks: Vec<Vec<Vec<f64>>> = (0..8)
        .map(|c| {
            let a = 0.1 * f64::from(c);
            t.iter().map(|&s| vec![a + 0.3 * s, -0.4 + 0.2 * s * s, 0.3 - a * s, 0.1, 0.5 + 0.1 * s, a]).collect()
        })
        .collect();
    let motions: Vec<SampledMotion> = tracks.iter().map(|q| SampledMotion::new(&t, q)).collect();
    let criteria: Vec<MotionCriterion> =
        ["j2", "peak_velocity", "peak_acceleration", "limits", "manipulability", "path_length"]
            .iter()
            .map(|n| MotionCriterion::parse(n, &puma, None, None).unwrap())
            .collect();
    c.bench_function("choose_motion_8x101", |b| {
        b.iter(|| choose_motion(&puma, black_box(&motions), &criteria, &[1.0; 6], Method::Topsis).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
