//! Drive benchmarks: step-schedule generation.
//!
//! Run with `cargo bench -p reach --bench drive`.
//!
//! * `schedule_trajectory/6x10000` — a 6-joint puma560 trajectory of 10 000 samples (10 s at
//!   1 kHz, every joint sweeping ±0.5 rad) quantised into step timestamps, with rate and
//!   acceleration checks; 200 steps/rev × 8 microsteps × 20:1 gear = 5093 steps/rad, about
//!   52 000 steps per joint. Target: ≤ 5 ms.
//! * `point_to_point/6` — a synchronised trapezoidal move of the same robot.

use std::f64::consts::TAU;
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::drive::{axes, point_to_point, schedule_trajectory};
use reach::model::{JointDrive, Wiring, presets};
use reach::motion::JointSample;

fn robot() -> reach::Robot {
    let puma = presets::get("puma560").unwrap();
    let drive = JointDrive {
        steps_per_rev: 200,
        microstepping: 8,
        gear_ratio: 20.0,
        lead: None,
        direction: 1,
        max_step_rate: 40_000.0,
        max_acceleration: Some(200_000.0),
        wiring: Wiring::Bipolar,
        mode: None,
        home_steps: 0,
    };
    puma.with_drives(vec![Some(drive); 6]).unwrap()
}

fn bench(c: &mut Criterion) {
    let robot = robot();
    let axes = axes(&robot).unwrap();
    let samples: Vec<JointSample> = (0..10_000)
        .map(|i| {
            let t = i as f64 * 1e-3;
            let q = (0..6).map(|j| 0.5 * (TAU * t / (2.0 + j as f64)).sin()).collect();
            JointSample::of(&robot, t, q)
        })
        .collect();
    let steps = schedule_trajectory(&axes, &samples).unwrap().step_count();
    assert!(steps > 100_000, "{steps} steps");
    c.bench_function("schedule_trajectory/6x10000", |b| {
        b.iter(|| schedule_trajectory(black_box(&axes), black_box(&samples)).unwrap())
    });
    let to = [0.5, -0.4, 0.3, 1.0, -0.8, 0.6];
    c.bench_function("point_to_point/6", |b| {
        b.iter(|| point_to_point(black_box(&axes), &[0.0; 6], black_box(&to), None, 0.0).unwrap())
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
