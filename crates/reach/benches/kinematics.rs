//! Per-call cost of forward kinematics and the Jacobian for Puma 560, UR5 (6 joints, standard
//! DH) and Panda (7 joints, modified DH, with a tool).
//!
//! Run with `cargo bench -p reach --bench kinematics`. Targets for a 6-joint arm:
//! FK ≤ 150 ns, Jacobian ≤ 250 ns per call.
//!
//! The batch groups (`fk_many`, `jacobian_many`) time 10 000 joint vectors per call on a pool
//! of one thread (the per-core figure) and of two; criterion reports them as poses per second.
//! `rows_one_at_a_time` is the same work as a plain loop over the one-row functions. The
//! batch kernels (and `fk_matrix`) run compiled for the widest vector level the processor has;
//! `REACH_SIMD=baseline|avx2|avx512` caps it, and the batch ids name the level that ran, so
//! runs at each level keep their own criterion history (poses per second per core at each
//! level: the one-thread ids).

use std::hint::black_box;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
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

/// Rows per batch call.
const BATCH: usize = 10_000;

/// `BATCH` joint vectors spread over ±1.5 rad (prismatic joints: ±1.5 m), deterministic.
fn batch_q(dof: usize) -> Vec<f64> {
    (0..BATCH * dof).map(|k| (k as f64 * 0.37).sin() * 1.5).collect()
}

/// Times `f` (a batch call over `BATCH` rows of `name`'s joint vectors) on pools of one and
/// two threads.
fn batch_group(c: &mut Criterion, group: &str, f: fn(&reach::Robot, &[f64]) -> reach::Result<Vec<f64>>) {
    let mut group = c.benchmark_group(group);
    group.throughput(Throughput::Elements(BATCH as u64));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        for &(name, _) in CASES {
            let robot = presets::get(name).unwrap();
            let q = batch_q(robot.dof());
            let id = format!("{threads} thread(s), {}", reach::simd::level().name());
            group.bench_function(BenchmarkId::new(name, id), |b| {
                b.iter(|| pool.install(|| f(black_box(&robot), black_box(&q)).unwrap()))
            });
        }
    }
    group.finish();
}

/// The reference for the batch groups: the same rows one call at a time on this thread, into
/// one preallocated buffer (`fk_matrix`, `jacobian_into`).
fn row_loops(c: &mut Criterion) {
    let mut group = c.benchmark_group("rows_one_at_a_time");
    group.throughput(Throughput::Elements(BATCH as u64));
    for &(name, _) in CASES {
        let robot = presets::get(name).unwrap();
        let dof = robot.dof();
        let q = batch_q(dof);
        let mut poses = vec![0.0; BATCH * 16];
        group.bench_function(BenchmarkId::new("fk_matrix", name), |b| {
            b.iter(|| {
                for (row, out) in black_box(&q).chunks_exact(dof).zip(poses.chunks_exact_mut(16)) {
                    let t = robot.fk_matrix(row).unwrap().to_homogeneous();
                    out.iter_mut().enumerate().for_each(|(k, v)| *v = t[(k / 4, k % 4)]);
                }
                black_box(&poses);
            })
        });
        let mut jacobians = vec![0.0; BATCH * 6 * dof];
        let mut j = Jacobian::zeros(dof);
        group.bench_function(BenchmarkId::new("jacobian_into", name), |b| {
            b.iter(|| {
                for (row, out) in black_box(&q).chunks_exact(dof).zip(jacobians.chunks_exact_mut(6 * dof)) {
                    robot.jacobian_into(row, &mut j).unwrap();
                    out.iter_mut().enumerate().for_each(|(k, v)| *v = j[(k / dof, k % dof)]);
                }
                black_box(&jacobians);
            })
        });
    }
    group.finish();
}

fn batches(c: &mut Criterion) {
    batch_group(c, "fk_many", reach::batch::fk_many);
    batch_group(c, "jacobian_many", reach::batch::jacobian_many);
    row_loops(c);
}

criterion_group!(benches, forward_kinematics, jacobian, batches);
criterion_main!(benches);
