//! RRT-Connect planner on the benchmark scene: a UR5 with 3 cm capsules among three spheres
//! and three boxes (the scene of `tests/world_planner.rs`). Two measurements: one query whose
//! straight edge is blocked (the random search runs; target ≤ 5 ms), and the first 20 random
//! collision-free queries in a row (straight-edge and searched ones mixed; divide by 20).
//!
//! Run with `cargo bench -p reach --bench planner`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::model::{LinkGeometry, Robot, RobotSpec, presets};
use reach::world::planner::{Goal, PlanOptions, plan};
use reach::world::{CollisionChecker, Scene};

fn ur5_with_capsules() -> Robot {
    let ur5 = presets::get("ur5").unwrap();
    Robot::new(RobotSpec {
        links: vec![LinkGeometry { radius: 0.03 }; 6],
        bodies: Vec::new(),
        disabled_collisions: Vec::new(),
        ..ur5.spec().clone()
    })
    .unwrap()
}

fn scene() -> Scene {
    let mut t = String::from("length_unit = \"m\"\nangle_unit = \"deg\"\n");
    for (c, r) in [([0.5, 0.3, 0.4], 0.1), ([-0.4, -0.4, 0.6], 0.12), ([0.0, 0.55, 0.1], 0.08)] {
        t += &format!("[[obstacles]]\nshape = \"sphere\"\ncenter = {c:?}\nradius = {r}\n");
    }
    for (lo, hi) in [([0.35, -0.6, -0.1], [0.8, -0.2, 0.15]), ([-0.6, 0.25, -0.2], [-0.45, 0.4, 0.9])] {
        t += &format!("[[obstacles]]\nshape = \"aabb\"\nmin = {lo:?}\nmax = {hi:?}\n");
    }
    t += "[[obstacles]]\nshape = \"box\"\ncenter = [0.0, -0.5, 0.75]\nhalf_extents = [0.3, 0.05, 0.02]\nrpy = [0, 0, 30]\n";
    Scene::from_toml_str(&t).unwrap()
}

/// The first `n` pairs of random collision-free configurations (joints in [−π, π]).
fn queries(robot: &Robot, scene: &Scene, n: usize) -> Vec<(Vec<f64>, Vec<f64>)> {
    let mut checker = CollisionChecker::new(robot, scene);
    let mut state = 2026u64;
    let mut free = || loop {
        let q: Vec<f64> = (0..6)
            .map(|_| {
                state = state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (2.0 * ((state >> 11) as f64 / (1u64 << 53) as f64) - 1.0) * std::f64::consts::PI
            })
            .collect();
        if checker.check(&q).unwrap().is_free() {
            return q;
        }
    };
    (0..n).map(|_| (free(), free())).collect()
}

fn planner(c: &mut Criterion) {
    let robot = ur5_with_capsules();
    let scene = scene();
    let options = PlanOptions::default();
    let all = queries(&robot, &scene, 20);
    let searched = all
        .iter()
        .find(|(s, g)| plan(&robot, &scene, s, &Goal::Joints(g.clone()), &options).unwrap().stats.iterations > 0)
        .expect("a query that needs the search")
        .clone();
    let mut group = c.benchmark_group("planner");
    group.sample_size(20).measurement_time(Duration::from_secs(5));
    group.bench_function("rrt_connect/ur5_6_obstacles/searched_query", |b| {
        let goal = Goal::Joints(searched.1.clone());
        b.iter(|| plan(&robot, &scene, black_box(&searched.0), &goal, &options).unwrap())
    });
    group.bench_function("rrt_connect/ur5_6_obstacles/20_random_queries", |b| {
        b.iter(|| {
            for (s, g) in &all {
                black_box(plan(&robot, &scene, s, &Goal::Joints(g.clone()), &options).unwrap());
            }
        })
    });
    group.finish();
}

criterion_group!(benches, planner);
criterion_main!(benches);
