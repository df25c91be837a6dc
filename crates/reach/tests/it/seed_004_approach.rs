//! Seed 004 (notes 004 §4 E, §8 "Performance and integration"): motion synthesis of the
//! `varan4` arm next to the forbidden zones of the ceiling (Fig. 1c) and two-plane (Fig. 1d)
//! scenes — 1 000 random reachable position goals per scene, every sample checked against
//! the original (not grown) arm: allowed and at least the safe distance from the obstacle.

use nalgebra::Point3;
use reach::ik::IkTarget;
use reach::model::presets;
use reach::world::approach::{ApproachGoal, ApproachOptions, FastRegion, Outcome, approach, grown_robot};
use reach::world::sweep::SweepOptions;
use reach::world::{CollisionChecker, Goal, PlanOptions, Scene};
use std::time::Duration;

use crate::common::Rng;

const SAFE: f64 = 0.05;
const GOALS: usize = 1000;

fn scene(name: &str) -> Scene {
    let path = format!("{}/../../examples/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::from_toml_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn deg(v: [f64; 4]) -> Vec<f64> {
    v.iter().map(|x| x.to_radians()).collect()
}

/// Random goal configurations (q1 = 0) that keep the safe distance, with their tool points.
fn goals(robot: &reach::Robot, scene: &Scene, seed: u64) -> Vec<(Vec<f64>, Point3<f64>)> {
    let grown = grown_robot(robot, SAFE).unwrap();
    let mut checker = CollisionChecker::new(&grown, scene);
    let mut rng = Rng::new(seed);
    let mut out = Vec::new();
    while out.len() < GOALS {
        let q = deg([0.0, rng.uniform(0.0, 120.0), rng.uniform(-120.0, 120.0), rng.uniform(-120.0, 120.0)]);
        if checker.check(&q).unwrap().is_free() {
            let p = Point3::from(robot.fk(&q).unwrap().translation.vector);
            out.push((q, p));
        }
    }
    out
}

/// Shares of the outcomes over the goals (reached, deadlock, unreachable, deadlocks the
/// planner then solved), asserting the safety of every sample.
fn run(scene_name: &str, fast: bool) -> [usize; 4] {
    let robot = presets::get("varan4").unwrap();
    let scene = scene(scene_name);
    let start = deg([0.0, 30.0, 0.0, 0.0]);
    let region = fast.then(|| FastRegion::fit(&robot, &scene, SAFE, &[(0, 0.0)], 15f64.to_radians(), 2.0).unwrap());
    let mut exact = CollisionChecker::new(&robot, &scene);
    let options = ApproachOptions { safe_distance: SAFE, ..ApproachOptions::default() };
    let grown = grown_robot(&robot, SAFE).unwrap();
    let mut grown_checker = CollisionChecker::new(&grown, &scene);
    let mut counts = [0; 4];
    let (mut candidates, mut rejected, mut sweeps) = (0, 0, 0);
    let (mut planner_checks, mut planner_rejected) = (0, 0);
    for (k, (_, p)) in goals(&robot, &scene, 4004).iter().enumerate() {
        let goal = ApproachGoal::Target(IkTarget::Position(*p));
        let a = approach(&robot, &scene, &start, &goal, &options, region.as_ref()).unwrap();
        candidates += a.stats.candidates;
        rejected += a.stats.fast_rejected;
        sweeps += a.stats.exact_sweeps;
        assert!(a.min_margin > 0.0, "goal {k}: margin {}", a.min_margin);
        for q in &a.samples {
            let r = exact.report(q).unwrap();
            assert!(r.verdict.is_free(), "goal {k}: {q:?} {:?}", r.verdict);
            let c = r.min_obstacle_clearance_m.unwrap();
            assert!(c >= SAFE, "goal {k}: clearance {c} below the safe distance at {q:?}");
        }
        match a.outcome {
            Outcome::Reached => {
                let end = a.samples.last().unwrap();
                let at = Point3::from(robot.fk(end).unwrap().translation.vector);
                assert!((at - p).norm() <= options.tolerance, "goal {k}: {at} vs {p}");
                counts[0] += 1;
            }
            Outcome::Deadlock => {
                counts[1] += 1;
                if k < 3 || counts[1] == 1 {
                    println!("deadlock: goal {k} at {:?}: {:?}", p.coords.as_slice(), a.reason);
                }
                // The hand-over: the planner (links grown by the safe distance) from the
                // deadlock configuration; its edges are proven clear by the swept check.
                let from = a.samples.last().unwrap();
                let options = PlanOptions {
                    max_time: Some(Duration::from_millis(500)),
                    first_test: region.clone(),
                    ..PlanOptions::default()
                };
                if let Ok(plan) =
                    reach::world::plan(&grown, &scene, from, &Goal::Target(IkTarget::Position(*p)), &options)
                {
                    planner_checks += plan.stats.checks;
                    planner_rejected += plan.stats.first_test_rejections;
                    let swept = grown_checker.swept_path(&plan.waypoints, &SweepOptions::default()).unwrap();
                    assert!(swept.is_none_or(|s| s.clear), "goal {k}: planner path not clear");
                    counts[3] += 1;
                }
            }
            Outcome::Unreachable => counts[2] += 1,
        }
    }
    println!(
        "{scene_name} (fast region {fast}): reached {}, deadlock {} (planner then found a path for {}), unreachable {} of {GOALS}; candidates {candidates}, fast-rejected {rejected}, exact sweeps {sweeps}; planner: {planner_checks} exact checks, {planner_rejected} rejected by the first test",
        counts[0], counts[1], counts[3], counts[2]
    );
    counts
}

#[test]
fn ceiling_every_sample_keeps_the_safe_distance() {
    let counts = run("seed004_ceiling", false);
    assert_eq!(counts[..3].iter().sum::<usize>(), GOALS);
    assert!(counts[0] > GOALS / 2, "{counts:?}");
}

#[test]
fn two_planes_every_sample_keeps_the_safe_distance() {
    let counts = run("seed004_two_planes", false);
    assert_eq!(counts[..3].iter().sum::<usize>(), GOALS);
    assert!(counts[0] > GOALS / 2, "{counts:?}");
}

#[test]
fn the_fitted_region_as_first_test_keeps_every_sample_safe() {
    for scene in ["seed004_ceiling", "seed004_two_planes"] {
        let counts = run(scene, true);
        assert_eq!(counts[..3].iter().sum::<usize>(), GOALS);
        assert!(counts[0] > GOALS / 2, "{scene}: {counts:?}");
    }
}

/// Every sample of `a` is allowed for the original arm and keeps the safe distance.
fn assert_safe(robot: &reach::Robot, scene: &Scene, samples: &[Vec<f64>], safe: f64) {
    let mut exact = CollisionChecker::new(robot, scene);
    for q in samples {
        let r = exact.report(q).unwrap();
        assert!(r.verdict.is_free(), "{q:?} {:?}", r.verdict);
        assert!(r.min_obstacle_clearance_m.unwrap() >= safe, "{q:?}: {:?}", r.min_obstacle_clearance_m);
    }
}

#[test]
fn redundant_arms_resolve_the_redundancy_past_an_obstacle() {
    use nalgebra::{Isometry3, Vector3};
    use reach::world::Shape;
    // planar3 (position goal in its plane: 3 joints, 2 task rows): a ball beside the straight
    // way from the start to the goal.
    let robot = presets::get("planar3").unwrap();
    let ball = Shape::Sphere { center: Vector3::new(1.2, 0.5, 0.0), radius: 0.15 };
    let scene = Scene::new().with_obstacle("ball", ball).unwrap();
    let start = deg([60.0, -40.0, -30.0, 0.0])[..3].to_vec();
    let target = Point3::new(2.4, 0.2, 0.0);
    let a = approach(
        &robot,
        &scene,
        &start,
        &ApproachGoal::Target(IkTarget::Position(target)),
        &ApproachOptions { safe_distance: 0.1, ..ApproachOptions::default() },
        None,
    )
    .unwrap();
    assert_eq!(a.outcome, Outcome::Reached, "{:?}", a.reason);
    let end = Point3::from(robot.fk(a.samples.last().unwrap()).unwrap().translation.vector);
    assert!((end - target).norm() <= 1e-4);
    assert_safe(&robot, &scene, &a.samples, 0.1);
    // Panda (a full pose: 7 joints, 6 task rows) past a box, 5 cm away.
    let robot = presets::get("panda").unwrap();
    let block = Shape::Box {
        center: Vector3::new(0.45, 0.25, 0.3),
        half_extents: Vector3::new(0.05, 0.05, 0.3),
        rotation: nalgebra::Matrix3::identity(),
    };
    // The safe distance grows every link, so non-adjacent links are kept 2·d apart too; the
    // Panda's body has links closer than 10 cm at every configuration (the shoulder's
    // housings): this test is about the obstacle, so every pair of links is exempt.
    let names: Vec<String> = robot.bodies().iter().map(|b| b.name.clone()).collect();
    let scene = names.iter().enumerate().fold(Scene::new().with_obstacle("block", block).unwrap(), |s, (i, a)| {
        names[i + 1..].iter().fold(s, |s, b| s.with_allowed_self_collision(a, b))
    });
    let start = vec![0.0, -0.3, 0.0, -1.2, 0.0, 1.5, 0.8];
    let mut goal_q = start.clone();
    goal_q[0] = 0.9;
    let goal: Isometry3<f64> = robot.fk(&goal_q).unwrap();
    let a = approach(
        &robot,
        &scene,
        &start,
        &ApproachGoal::Target(IkTarget::Pose(goal)),
        &ApproachOptions::default(),
        None,
    )
    .unwrap();
    assert_safe(&robot, &scene, &a.samples, 0.05);
    assert_eq!(a.outcome, Outcome::Reached, "{:?}", a.reason);
    let end = robot.fk(a.samples.last().unwrap()).unwrap();
    assert!((end.translation.vector - goal.translation.vector).norm() <= 1e-4);
    assert!(end.rotation.angle_to(&goal.rotation) <= 1e-3);
}
