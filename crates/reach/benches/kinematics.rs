//! Per-call cost of forward kinematics and the Jacobian for Puma 560, UR5 (6 joints, standard
//! DH) and Panda (7 joints, modified DH, with a tool).
//!
//! Run with `cargo bench -p reach --bench kinematics`. Targets for a 6-joint arm:
//! FK ≤ 150 ns, Jacobian ≤ 250 ns per call.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::Jacobian;
use reach::model::presets;

/// A fixed, generic (non-singular, all joints non-zero) configuration per robot.
const CASES: &[(&str, &[f64])] = &[
    ("puma560", &[0.3, -0.5, 0.8, -1.1, 0.7, 0.4]),
    ("ur5", &[0.3, -1.2, 1.5, -0.9, 0.7, 0.4]),
    ("panda", &[0.2, -0.4, 0.3, -2.1, 0.25, 1.9, 0.6]),
];

fn forward_kinematics(c: &mut Criterion) {
    let mut group = c.benchmark_group("fk_matrix");
    for &(name, q) in CASES {
        let robot = presets::get(name).unwrap();
        group.bench_function(name, |b| b.iter(|| black_box(&robot).fk_matrix(black_box(q)).unwrap()));
    }
    group.finish();

    let mut group = c.benchmark_group("fk");
    for &(name, q) in CASES {
        let robot = presets::get(name).unwrap();
        group.bench_function(name, |b| b.iter(|| black_box(&robot).fk(black_box(q)).unwrap()));
    }
    group.finish();
}

fn jacobian(c: &mut Criterion) {
    let mut group = c.benchmark_group("jacobian_into");
    for &(name, q) in CASES {
        let robot = presets::get(name).unwrap();
        let mut out = Jacobian::zeros(robot.dof());
        group.bench_function(name, |b| {
            b.iter(|| {
                black_box(&robot).jacobian_into(black_box(q), &mut out).unwrap();
                black_box(&out);
            })
        });
    }
    group.finish();
}

criterion_group!(benches, forward_kinematics, jacobian);
criterion_main!(benches);
