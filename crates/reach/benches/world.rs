//! World queries: one collision check of a 6-link arm against 20 primitives (target ≤ 1 µs),
//! the 1° C-space grid of `varan4` (≈ 7 million nodes, target ≤ 1 s on 2 cores), and seed
//! 004's R-function membership test (the region fitted to the scene's 15° grid) against the
//! direct link–zone intersection, on the same 1000 configurations.
//!
//! The real bodies on MotionBenchMaker's first bookshelf problem (`tests/data/mbm`): one
//! check and one certified swept edge (start → goal, stopped at the first contact or proven
//! clear) of the Panda as VAMP's 59 spheres, as the `panda` preset's 11 capsules and as its
//! collision meshes (convex hulls), with the SRDF's exempt pairs.
//!
//! Run with `cargo bench -p reach --bench world` (add `--no-default-features` for the
//! single-threaded grid).

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use reach::model::{LinkGeometry, Robot, RobotSpec, presets};
use reach::world::cspace::{GridSpec, classify_grid};
use reach::world::fit::{FitOptions, fit_region};
use reach::world::{CollisionChecker, Scene};

/// UR5 with 3 cm capsules and a scene of 20 primitives around it, none touching at `Q`.
const Q: [f64; 6] = [0.3, -1.2, 1.5, -0.9, 0.7, 0.4];

fn ur5_with_capsules() -> Robot {
    let ur5 = presets::get("ur5").unwrap();
    let spec = RobotSpec {
        links: vec![LinkGeometry { radius: 0.03 }; 6],
        bodies: Vec::new(),
        disabled_collisions: Vec::new(),
        ..ur5.spec().clone()
    };
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

fn membership(c: &mut Criterion) {
    // 1000 configurations on a pseudo-random spread over the box (degrees).
    let mut s = 7_u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let qs: Vec<[f64; 3]> =
        (0..1000).map(|_| [120.0 * next(), 240.0 * next() - 120.0, 240.0 * next() - 120.0]).collect();
    let varan = presets::get("varan4").unwrap();
    for (name, text) in [
        ("ceiling", include_str!("../../../examples/seed004_ceiling.toml")),
        ("two_planes", include_str!("../../../examples/seed004_two_planes.toml")),
    ] {
        let scene = Scene::from_toml_str(text).unwrap();
        // The region fitted to the scene's 15° grid (reach::world::fit): box, Ω1–Ω4, Ω5 (, Ω6).
        let grid = classify_grid(&varan, &scene, &GridSpec::new(4, 15f64.to_radians()).fix(0, 0.0)).unwrap();
        let region = fit_region(&grid, &FitOptions::default()).unwrap().region;
        let compiled = region.compile();
        let mut checker = CollisionChecker::new(&varan, &scene);
        let direct = |checker: &mut CollisionChecker<'_>, q: &[f64; 3]| {
            let r = [0.0, q[0].to_radians(), q[1].to_radians(), q[2].to_radians()];
            checker.check(&r).unwrap().is_free()
        };
        let agree = qs.iter().filter(|q| compiled.contains(**q) == direct(&mut checker, q)).count();
        assert_eq!(qs.iter().filter(|q| compiled.contains(**q) != region.contains(**q)).count(), 0);
        eprintln!(
            "seed004 {name}: fitted region with {} primitives agrees with the direct check on {agree} of 1000",
            region.primitives.len()
        );
        let mut group = c.benchmark_group(format!("seed004_{name}_1000_configurations"));
        // The region compiled (`Region::compile`): every primitive's sign in one flat pass.
        // (`black_box` of the reference: a black-boxed array value is stored and reloaded,
        // a store-forwarding stall of about the membership test's own cost.)
        group.bench_function("fitted_rfunction_membership", |b| {
            b.iter(|| qs.iter().filter(|q| compiled.contains(*black_box(*q))).count())
        });
        // The same test of the 1000 configurations as one batch (`contains_into`): blocks of
        // configurations in structure-of-arrays lanes, the answers stored, then counted.
        let mut inside = Vec::with_capacity(qs.len());
        compiled.contains_into(&qs, &mut inside);
        assert!(inside.iter().zip(&qs).all(|(b, q)| *b == compiled.contains(*q)));
        group.bench_function("fitted_rfunction_membership_batch", |b| {
            b.iter(|| {
                compiled.contains_into(black_box(&qs), &mut inside);
                inside.iter().filter(|x| **x).count()
            })
        });
        // The composed F(q) ≥ 0 of the primitives as fitted (left-nested R-conjunctions).
        group.bench_function("fitted_rfunction_value_composed", |b| {
            b.iter(|| qs.iter().filter(|q| region.value(*black_box(*q)) >= 0.0).count())
        });
        group.bench_function("direct_fk_and_link_zone_intersection", |b| {
            b.iter(|| qs.iter().filter(|q| direct(&mut checker, black_box(q))).count())
        });
        group.finish();
    }
}

/// Seed 004's fitted region as a fast first test (`reach::world::approach::FastRegion`, links
/// grown by a 5 cm safe distance): a configuration clearly outside the region
/// (`F_Λ < −2`) is dropped, every other one still gets the exact verdict. On the same 1000
/// configurations as `membership`: the exact check alone against the first test plus the
/// exact check where it does not drop; and for candidate increments (3° away, in a random
/// direction) from the allowed ones of them the exact swept check alone against the first test at the increment's
/// end plus the swept check.
fn first_test(c: &mut Criterion) {
    use reach::world::approach::{FastRegion, grown_robot};
    use reach::world::sweep::SweepOptions;
    let mut s = 11_u64;
    let mut next = || {
        s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let qs: Vec<Vec<f64>> = (0..1000)
        .map(|_| {
            vec![
                0.0,
                (120.0 * next()).to_radians(),
                (240.0 * next() - 120.0).to_radians(),
                (240.0 * next() - 120.0).to_radians(),
            ]
        })
        .collect();
    let ends: Vec<Vec<f64>> = qs
        .iter()
        .map(|q| {
            let d: Vec<f64> = (0..3).map(|_| next() - 0.5).collect();
            let n = d.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-9);
            let mut e = q.clone();
            for k in 0..3 {
                e[k + 1] = (e[k + 1] + 3f64.to_radians() * d[k] / n)
                    .clamp(if k == 0 { 0.0 } else { -120f64.to_radians() }, 120f64.to_radians());
            }
            e
        })
        .collect();
    let varan = presets::get("varan4").unwrap();
    let grown = grown_robot(&varan, 0.05).unwrap();
    for (name, text) in [
        ("ceiling", include_str!("../../../examples/seed004_ceiling.toml")),
        ("two_planes", include_str!("../../../examples/seed004_two_planes.toml")),
    ] {
        let scene = Scene::from_toml_str(text).unwrap();
        let fast = FastRegion::fit(&varan, &scene, 0.05, &[(0, 0.0)], 15f64.to_radians(), 2.0).unwrap();
        let mut checker = CollisionChecker::new(&grown, &scene);
        let exact: Vec<bool> = qs.iter().map(|q| checker.check(q).unwrap().is_free()).collect();
        let dropped = qs.iter().filter(|q| fast.rejects(q)).count();
        let lost = qs.iter().zip(&exact).filter(|(q, free)| **free && fast.rejects(q)).count();
        eprintln!(
            "seed004 {name}: the first test drops {dropped} of 1000 configurations ({lost} of them allowed: lost candidates, never a wrong 'allowed'); {} allowed by the exact check",
            exact.iter().filter(|f| **f).count()
        );
        // Increments start from allowed configurations, as in the synthesis.
        let pairs: Vec<(&Vec<f64>, &Vec<f64>)> =
            qs.iter().zip(&ends).zip(&exact).filter(|(_, free)| **free).map(|(p, _)| p).collect();
        let options = SweepOptions { closest: false, max_evaluations: 2000 };
        let mut group = c.benchmark_group(format!("seed004_{name}_first_test"));
        group.bench_function("exact_check_only", |b| {
            b.iter(|| qs.iter().filter(|q| checker.check(black_box(q)).unwrap().is_free()).count())
        });
        group.bench_function("fitted_first_test_then_exact", |b| {
            b.iter(|| qs.iter().filter(|q| !fast.rejects(black_box(q)) && checker.check(q).unwrap().is_free()).count())
        });
        group.bench_function("exact_swept_increments_only", |b| {
            b.iter(|| {
                qs.iter().zip(&ends).filter(|(a, e)| checker.swept(black_box(a), e, &options).unwrap().0.clear).count()
            })
        });
        group.bench_function("fitted_first_test_then_swept_increments", |b| {
            b.iter(|| {
                pairs
                    .iter()
                    .filter(|(a, e)| !fast.rejects(black_box(e)) && checker.swept(a, e, &options).unwrap().0.clear)
                    .count()
            })
        });
        group.finish();
    }
}

fn mbm_bodies(c: &mut Criterion) {
    use reach::model::{UrdfBodyOptions, UrdfChain, srdf_disabled_pairs};
    use reach::world::PlanRequest;
    use reach::world::sweep::SweepOptions;
    const DATA: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/mbm");
    let read = |name: &str| std::fs::read_to_string(format!("{DATA}/{name}")).unwrap();
    let chain = UrdfChain { base: Some("panda_link0".into()), tip: Some("panda_hand".into()) };
    let srdf = srdf_disabled_pairs(&read("panda.srdf")).unwrap();
    let spheres =
        Robot::from_urdf_str(&read("panda_spherized.urdf"), &chain).unwrap().with_disabled_collisions(&srdf).unwrap();
    let reader = |f: &str| -> Option<Result<Vec<u8>, String>> {
        let rest = f.strip_prefix("package://")?;
        Some(std::fs::read(format!("{DATA}/{rest}")).map_err(|e| e.to_string()))
    };
    let options = UrdfBodyOptions { meshes: Some(&reader), ..Default::default() };
    let meshes = Robot::from_urdf_str_with(&read("panda.urdf"), &chain, &options)
        .unwrap()
        .with_disabled_collisions(&srdf)
        .unwrap();
    let capsules = presets::get("panda").unwrap();
    let scene = Scene::from_moveit_yaml(&read("problems/bookshelf_small_scene0001.yaml")).unwrap();
    let request = PlanRequest::from_moveit_yaml(&read("problems/bookshelf_small_request0001.yaml")).unwrap();
    let names: Vec<&str> = spheres.joints().iter().map(|j| j.name.as_str()).collect();
    let (start, goal) = request.joint_vectors(&names).unwrap();
    let mut group = c.benchmark_group("mbm_bookshelf_small_0001");
    for (name, robot) in [("spheres59", &spheres), ("preset_capsules", &capsules), ("meshes", &meshes)] {
        let mut checker = CollisionChecker::try_new(robot, &scene).unwrap();
        group.bench_function(format!("check/{name}"), |b| b.iter(|| checker.check(black_box(&start)).unwrap()));
        let sweep = SweepOptions { closest: false, ..SweepOptions::default() };
        group.bench_function(format!("swept_start_goal/{name}"), |b| {
            b.iter(|| checker.swept(black_box(&start), black_box(&goal), &sweep).unwrap().0.clear)
        });
    }
    group.finish();
}

criterion_group!(benches, collision, cspace, membership, first_test, mbm_bodies);
criterion_main!(benches);
