//! Path-tracking benchmarks.
//!
//! Run with `cargo bench -p reach --bench tracking`.
//!
//! * `track_configuration/<robot>/line_1000`: one configuration followed along a
//!   1000-sample straight line with constant orientation — one closed-form IK solve per
//!   sample (seeded with the previous joint vector) and the nearest solution of the same
//!   branch. Target: ≤ 2 ms.
//! * `track/welder6r/weld_945`: the whole seed-003 analysis of the weld on a 1 mm grid
//!   (945 samples, both configurations, singular-position scan, limit checks with
//!   bisection, events).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use nalgebra::{Isometry3, Matrix3, Translation3, UnitQuaternion, Vector3};
use reach::ik::{Branch, SolverKind};
use reach::model::presets;
use reach::motion::PathSample;
use reach::motion::tracking::{TrackedPath, TrackingOptions, track, track_configuration};

/// A straight line of `n` samples between the tool poses of two configurations' positions,
/// keeping the first pose's orientation.
fn line(robot: &reach::Robot, qa: &[f64], qb: &[f64], n: u32) -> Vec<PathSample> {
    let a = robot.fk(qa).expect("fk");
    let b = robot.fk(qb).expect("fk");
    (0..n)
        .map(|k| {
            let u = f64::from(k) / f64::from(n - 1);
            let p = a.translation.vector.lerp(&b.translation.vector, u);
            PathSample { t: u, s: u, angle: 0.0, pose: Isometry3::from_parts(Translation3::from(p), a.rotation) }
        })
        .collect()
}

fn track_line(c: &mut Criterion) {
    let mut group = c.benchmark_group("track_configuration");
    let cases: [(&str, [f64; 6], [f64; 6]); 2] = [
        ("puma560", [0.2, 0.6, -0.8, 0.4, 0.7, -0.3], [0.7, 0.3, -0.4, 0.4, 0.7, -0.3]),
        ("ur5", [0.4, -1.1, 1.3, -0.6, 1.2, 0.3], [0.9, -1.4, 1.6, -0.6, 1.2, 0.3]),
    ];
    for (name, qa, qb) in cases {
        let robot = presets::get(name).expect("preset");
        let solver = SolverKind::detect(&robot).build(&robot).expect("solver");
        let samples = line(&robot, &qa, &qb, 1000);
        let first =
            solver.solve(&robot, &reach::ik::IkTarget::Pose(samples[0].pose), &Default::default()).expect("solve");
        // Follow the branch of the start configuration.
        let start = first
            .solutions
            .iter()
            .min_by(|x, y| {
                let d = |s: &reach::ik::IkSolution| s.q.iter().zip(&qa).map(|(a, b)| (a - b).abs()).sum::<f64>();
                d(x).total_cmp(&d(y))
            })
            .expect("a solution");
        let filter: Branch = start.branch.clone();
        let check = track_configuration(&robot, solver.as_ref(), &samples, &filter, false).expect("track");
        assert!(check.q.iter().all(Option::is_some), "{name}: branch lost on the line");
        group.bench_function(format!("{name}/line_1000"), |b| {
            b.iter(|| {
                track_configuration(black_box(&robot), solver.as_ref(), black_box(&samples), &filter, false)
                    .expect("track")
            });
        });
    }
    group.finish();
}

fn weld(c: &mut Criterion) {
    let robot = presets::get("welder6r").expect("preset");
    let p = Vector3::new(0.050, 0.740, 0.070);
    let m = Vector3::new(0.500, 0.200, 0.700);
    let n = (m - p).normalize();
    let e6 = Vector3::new(p.y - m.y, m.x - p.x, 0.0).normalize();
    let rot = UnitQuaternion::from_matrix(&Matrix3::from_columns(&[n, e6, n.cross(&e6)]));
    let pose = move |s: f64| Isometry3::from_parts(Translation3::from(p + n * s), rot);
    let length = (m - p).norm();
    let samples: Vec<PathSample> = (0..=943)
        .map(|k| f64::from(k) / 1000.0)
        .chain([length])
        .map(|s| PathSample { t: s * 1000.0, s, angle: 0.0, pose: pose(s) })
        .collect();
    let path = TrackedPath::with_evaluator(&samples, &pose).expect("path");
    let options = TrackingOptions::default();
    let mut group = c.benchmark_group("track");
    group.sample_size(20);
    group.bench_function("welder6r/weld_945", |b| {
        b.iter(|| track(black_box(&robot), &path, &options, None).expect("track"));
    });
    group.finish();
}

criterion_group!(benches, track_line, weld);
criterion_main!(benches);
