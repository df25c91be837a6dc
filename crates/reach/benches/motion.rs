//! Motion benchmarks: run with `cargo bench -p reach --bench motion`.
//!
//! * `seed001` — seed 001's example (notes 001 §5.1): the tool-space path T0 → T1 sampled at
//!   dt = 0.1 (101 poses), the per-sample IK of those poses on `spbu6` (101 closed-form
//!   solves, closest to the previous sample), and J2 of the result;
//! * `joint_space` — sampling a 6-joint cycloidal motion at 1 ms over 10 s (10 001 samples).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::effort::{DEFAULT_SIX_JOINT_WEIGHTS, Differences, j2};
use reach::model::presets;
use reach::motion::sample::PerSampleIk;
use reach::motion::{JointMotion, Profile, ToolMotion};

fn seed001(c: &mut Criterion) {
    let spbu6 = presets::get("spbu6").unwrap();
    let t0 = spbu6.fk(&[0.0; 6]).unwrap();
    let t1 = spbu6.fk(&[std::f64::consts::FRAC_PI_2, 0.0, 0.0, std::f64::consts::FRAC_PI_2, 0.0, 0.0]).unwrap();
    let motion = ToolMotion::new(t0, t1, 0.0, 10.0, Profile::Cycloidal).unwrap();
    let options = PerSampleIk { allow_outside_limits: true, ..PerSampleIk::default() };
    let mut group = c.benchmark_group("seed001");
    group.bench_function("tool_path_101", |b| b.iter(|| black_box(&motion).sample_time(0.1).unwrap()));
    let path = motion.sample_time(0.1).unwrap();
    group.bench_function("per_sample_ik_101", |b| b.iter(|| black_box(&path).to_joints(&spbu6, &options).unwrap()));
    let traj = path.to_joints(&spbu6, &options).unwrap();
    let rows = traj.rows();
    group.bench_function("j2_101", |b| {
        b.iter(|| j2(black_box(&rows), &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::Wrapped).unwrap())
    });
    group.finish();
}

fn joint_space(c: &mut Criterion) {
    let m = JointMotion::new(&[0.0; 6], &[1.0, -0.5, 0.3, 2.0, -1.0, 0.7], 0.0, 10.0, Profile::Cycloidal).unwrap();
    c.bench_function("joint_space/sample_10001", |b| b.iter(|| black_box(&m).sample(0.001).unwrap()));
}

criterion_group!(benches, seed001, joint_space);
criterion_main!(benches);
