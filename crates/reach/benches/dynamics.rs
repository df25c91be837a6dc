//! Per-call cost of the Puma 560 dynamics: recursive Newton–Euler torques (workspace form, no
//! allocation), gravity torques, the mass matrix (6 Newton–Euler passes) and the mechanical
//! energy of a 201-sample joint motion (rates by finite differences).
//!
//! Run with `cargo bench -p reach --bench dynamics`.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::DMatrix;
use reach::effort::dynamics::{Dynamics, trajectory_energy};
use reach::model::presets;

const Q: [f64; 6] = [0.3, -0.5, 0.8, -1.1, 0.7, 0.4];
const QD: [f64; 6] = [0.5, -0.3, 0.9, 1.2, -0.8, 0.6];
const QDD: [f64; 6] = [1.0, 2.0, -1.5, 0.5, 3.0, -2.0];

fn dynamics(c: &mut Criterion) {
    let puma = presets::get("puma560").unwrap();
    let mut ws = Dynamics::new(&puma).unwrap();
    let mut tau = [0.0; 6];
    c.bench_function("rnea/puma560", |b| {
        b.iter(|| ws.inverse_dynamics_into(black_box(&Q), black_box(&QD), black_box(&QDD), &mut tau).unwrap())
    });
    c.bench_function("gravity/puma560", |b| b.iter(|| ws.gravity_torques_into(black_box(&Q), &mut tau).unwrap()));
    let mut m = DMatrix::zeros(6, 6);
    c.bench_function("mass_matrix/puma560", |b| b.iter(|| ws.mass_matrix_into(black_box(&Q), &mut m).unwrap()));
    let times: Vec<f64> = (0..=200).map(|k| k as f64 * 0.01).collect();
    let q: Vec<Vec<f64>> = times.iter().map(|t| Q.iter().map(|q0| q0 + 0.5 * (2.0 * t).sin()).collect()).collect();
    c.bench_function("trajectory_energy/puma560_201_samples", |b| {
        b.iter(|| trajectory_energy(black_box(&puma), black_box(&times), black_box(&q)).unwrap())
    });
}

criterion_group!(benches, dynamics);
criterion_main!(benches);
