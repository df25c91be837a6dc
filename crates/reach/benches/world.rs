//! World queries: one collision check of a 6-link arm against 20 primitives (target ≤ 1 µs),
//! the 1° C-space grid of `varan4` (≈ 7 million nodes, target ≤ 2 s on 2 cores), and seed
//! 004's R-function membership test against the direct link–zone intersection.
//!
//! Run with `cargo bench -p reach --bench world` (add `--no-default-features` for the
//! single-threaded grid).

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::model::{LinkGeometry, Robot, RobotSpec, presets};
use reach::world::cspace::{GridSpec, classify_grid};
use reach::world::rfunction::{Parabola, Primitive, Region};
use reach::world::{CollisionChecker, Scene};

/// UR5 with 3 cm capsules and a scene of 20 primitives around it, none touching at `Q`.
const Q: [f64; 6] = [0.3, -1.2, 1.5, -0.9, 0.7, 0.4];

fn ur5_with_capsules() -> Robot {
    let ur5 = presets::get("ur5").unwrap();
    let spec = RobotSpec { links: vec![LinkGeometry { radius: 0.03 }; 6], ..ur5.spec().clone() };
    Robot::new(spec).unwrap()
}

fn twenty_primitives() -> Scene {
    let mut t = String::from("length_unit = \"m\"\nangle_unit = \"deg\"\n");
    for i in 0..5 {
        let a = i as f64 * 72.0_f64.to_radians();
        t += &format!(
            "[[obstacles]]\nshape = \"sphere\"\ncenter = [{}, {}, 0.4]\nradius = 0.1\n",
            1.3 * a.cos(),
            1.3 * a.sin()
        );
        t += &format!(
            "[[obstacles]]\nshape = \"aabb\"\nmin = [{}, {}, 0.0]\nmax = [{}, {}, 0.3]\n",
            1.5 * a.cos() - 0.1,
            1.5 * a.sin() - 0.1,
            1.5 * a.cos() + 0.1,
            1.5 * a.sin() + 0.1
        );
    }
    for i in 0..4 {
        let a = (36.0 + i as f64 * 90.0_f64).to_radians();
        t += &format!(
            "[[obstacles]]\nshape = \"box\"\ncenter = [{}, {}, 0.8]\nhalf_extents = [0.1, 0.2, 0.05]\nrpy = [10, 20, {}]\n",
            1.2 * a.cos(),
            1.2 * a.sin(),
            30 * i
        );
    }
    for i in 0..3 {
        let a = (10.0 + i as f64 * 120.0_f64).to_radians();
        t += &format!(
            "[[obstacles]]\nshape = \"capsule\"\na = [{x}, {y}, 0.0]\nb = [{x}, {y}, 1.5]\nradius = 0.04\n",
            x = 1.1 * a.cos(),
            y = 1.1 * a.sin()
        );
    }
    t += "[[obstacles]]\nshape = \"halfspace\"\npoint = [0, 0, -0.3]\noutward_normal = [0, 0, 1]\n";
    t += "[[obstacles]]\nshape = \"halfspace\"\npoint = [0, 0, 2.0]\noutward_normal = [0, 0, -1]\n";
    t += "[[obstacles]]\nshape = \"rectangle\"\ncenter = [0, -1.4, 1.0]\nhalf_extents = [0.5, 0.3]\nrpy = [90, 0, 0]\n";
    let scene = Scene::from_toml_str(&t).unwrap();
    assert_eq!(scene.obstacles.len(), 20);
    scene
}

fn collision(c: &mut Criterion) {
    let robot = ur5_with_capsules();
    let scene = twenty_primitives();
    let mut checker = CollisionChecker::new(&robot, &scene);
    // The benchmark configuration is free: every pair is tested (the worst case).
    assert!(checker.check(&Q).unwrap().is_free(), "{:?}", checker.report(&Q).unwrap());
    c.bench_function("collision_check/ur5_capsules_20_primitives", |b| {
        b.iter(|| checker.check(black_box(&Q)).unwrap())
    });
    c.bench_function("clearance_report/ur5_capsules_20_primitives", |b| {
        b.iter(|| checker.report(black_box(&Q)).unwrap())
    });
}

fn cspace(c: &mut Criterion) {
    let varan = presets::get("varan4").unwrap();
    let scene = Scene::from_toml_str(include_str!("../../../examples/seed004_two_planes.toml")).unwrap();
    let spec = GridSpec::new(4, 1f64.to_radians()).fix(0, 0.0);
    let mut group = c.benchmark_group("cspace");
    group.sample_size(10).measurement_time(Duration::from_secs(20));
    group.bench_function("varan4_1deg_two_planes", |b| {
        b.iter(|| {
            let g = classify_grid(&varan, &scene, black_box(&spec)).unwrap();
            assert_eq!(g.counts.nodes, 121 * 241 * 241);
            g.counts.allowed
        })
    });
    group.finish();
}

/// An R-function region with the structure of the paper's tunnel case (eq. 8): the box,
/// elliptic cylinder Ω1, three planes, cylinder Ω5 and parabolic cylinder Ω6. The paper
/// prints no coefficients; the cost does not depend on their values.
fn tunnel_region() -> Region {
    Region {
        limits: [[0.0, 120.0], [-120.0, 120.0], [-120.0, 120.0]],
        primitives: vec![
            Primitive::EllipticCylinder { phi_deg: 30.0, a: 60.0, b: 35.0, centre: [-0.5, 10.0, 0.1, -20.0] },
            Primitive::HalfSpace { d: [1.0, 0.5, 0.2], b: -150.0 },
            Primitive::HalfSpace { d: [-0.3, 1.0, 0.4], b: -200.0 },
            Primitive::HalfSpace { d: [0.2, -0.7, 1.0], b: -210.0 },
            Primitive::EllipticCylinder { phi_deg: 110.0, a: 50.0, b: 20.0, centre: [-1.5, 90.0, -0.1, 0.0] },
            Primitive::ParabolicCylinder {
                phi_deg: 15.0,
                vertex: [100.0, -60.0],
                p: 8.0,
                variant: Parabola::SquareFirst,
            },
        ],
    }
}

fn membership(c: &mut Criterion) {
    // 1000 configurations on a pseudo-random spread over the box (degrees).
    let mut s = 7_u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let qs: Vec<[f64; 3]> =
        (0..1000).map(|_| [120.0 * next(), 240.0 * next() - 120.0, 240.0 * next() - 120.0]).collect();
    let region = tunnel_region();
    let varan = presets::get("varan4").unwrap();
    let scene = Scene::from_toml_str(include_str!("../../../examples/seed004_ceiling.toml")).unwrap();
    let mut checker = CollisionChecker::new(&varan, &scene);
    let mut group = c.benchmark_group("seed004_1000_configurations");
    group.bench_function("rfunction_membership", |b| {
        b.iter(|| qs.iter().filter(|q| region.contains(black_box(**q))).count())
    });
    group.bench_function("direct_fk_and_link_zone_intersection", |b| {
        b.iter(|| {
            qs.iter()
                .filter(|q| {
                    let r = [0.0, q[0].to_radians(), q[1].to_radians(), q[2].to_radians()];
                    checker.check(black_box(&r)).unwrap().is_free()
                })
                .count()
        })
    });
    group.finish();
}

criterion_group!(benches, collision, cspace, membership);
criterion_main!(benches);
