//! Inverse-kinematics benchmarks, one criterion group per solver.
//!
//! Run with `cargo bench -p reach --bench ik` (add `-- numeric` to run one group).
//! To add a solver: write a `fn <solver>(c: &mut Criterion)` that opens a group named after
//! the solver's CLI name and add it to `criterion_group!` at the bottom.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::Robot;
use reach::ik::numeric::Numeric;
use reach::ik::{IkOptions, IkSolver, IkTarget};
use reach::model::presets;

/// A generic (non-singular, within-limits) configuration per benchmarked robot.
fn generic_q(name: &str) -> Vec<f64> {
    match name {
        "ur5" => vec![0.4, -1.1, 1.3, -0.6, 1.2, 0.3],
        "panda" => vec![0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.5],
        "puma560" => vec![0.2, 0.6, -0.8, 0.4, 0.7, -0.3],
        other => panic!("no benchmark configuration for `{other}`"),
    }
}

/// `(robot, pose target of generic_q, generic_q)`.
fn problem(name: &str) -> (Robot, IkTarget, Vec<f64>) {
    let robot = presets::get(name).expect("preset");
    let q = generic_q(name);
    let target = IkTarget::Pose(robot.fk(&q).expect("fk"));
    (robot, target, q)
}

/// Numeric solver: one start from a seed 0.1 rad away from the solution in every joint (the
/// tracking case), and the full default multi-start (16 starts, all branches).
fn numeric(c: &mut Criterion) {
    let mut group = c.benchmark_group("numeric");
    for name in ["ur5", "panda"] {
        let (robot, target, q) = problem(name);
        let solver = Numeric::from_robot(&robot).expect("numeric fits every robot");
        let seed: Vec<f64> = q.iter().map(|v| v + 0.1).collect();
        let nearby = IkOptions { seed: Some(seed), restarts: 1, ..IkOptions::default() };
        group.bench_function(format!("{name}/single_start_nearby_seed"), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&nearby)).expect("solve"));
        });
        let full = IkOptions::default();
        group.bench_function(format!("{name}/multi_start_{}", full.restarts), |b| {
            b.iter(|| solver.solve(black_box(&robot), black_box(&target), black_box(&full)).expect("solve"));
        });
    }
    group.finish();
}

criterion_group!(benches, numeric);
criterion_main!(benches);
