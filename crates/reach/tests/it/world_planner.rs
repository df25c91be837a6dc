//! RRT-Connect planner (`reach::world::planner`): success rate and timing over 100 seeded
//! queries on a UR5 with 3 cm capsules among boxes and spheres, every path re-checked by an
//! independent interpolation written here (no arm point moves more than 1 mm between checks),
//! typed failures and reproducibility.
//!
//! Timing is printed with `cargo test -p reach --test world_planner -- --nocapture`.

use reach::ik::IkTarget;
use reach::model::Robot;
use reach::world::planner::{Blocked, Goal, PlanError, PlanOptions, plan};
use reach::world::{CollisionChecker, Scene};

use crate::common::ur5_with_capsules as ur5;

/// Largest arm-point motion between two checks of the independent re-check, metres.
const CHECK_STEP: f64 = 0.001;

fn scene() -> Scene {
    Scene::from_toml_str(
        r#"
length_unit = "m"
angle_unit = "deg"

[[obstacles]]
name = "ball_a"
shape = "sphere"
center = [0.5, 0.3, 0.4]
radius = 0.1

[[obstacles]]
name = "ball_b"
shape = "sphere"
center = [-0.4, -0.4, 0.6]
radius = 0.12

[[obstacles]]
name = "ball_c"
shape = "sphere"
center = [0.0, 0.55, 0.1]
radius = 0.08

[[obstacles]]
name = "table"
shape = "aabb"
min = [0.35, -0.6, -0.1]
max = [0.8, -0.2, 0.15]

[[obstacles]]
name = "pillar"
shape = "aabb"
min = [-0.6, 0.25, -0.2]
max = [-0.45, 0.4, 0.9]

[[obstacles]]
name = "shelf"
shape = "box"
center = [0.0, -0.5, 0.75]
half_extents = [0.3, 0.05, 0.02]
rpy = [0, 0, 30]
"#,
    )
    .unwrap()
}

/// A plain 64-bit LCG (Knuth's MMIX constants), independent of the planner's generator.
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random collision-free configuration with every joint in [−π, π].
fn random_free(rng: &mut Lcg, checker: &mut CollisionChecker) -> Vec<f64> {
    loop {
        let q: Vec<f64> = (0..6).map(|_| (2.0 * rng.unit() - 1.0) * std::f64::consts::PI).collect();
        if checker.check(&q).unwrap().is_free() {
            return q;
        }
    }
}

/// Re-checks every edge with straight joint-space interpolation such that no arm point moves
/// more than `CHECK_STEP` between checks: bound `R · Σ|Δq|`, `R` = the sum of the
/// distances between consecutive link points at home plus the link radius (all joints revolute).
fn assert_path_free(checker: &mut CollisionChecker, robot: &Robot, path: &[Vec<f64>]) {
    checker.check(&robot.home()).unwrap();
    let pts = checker.points().to_vec();
    let r: f64 = pts.windows(2).map(|w| (w[1] - w[0]).norm()).sum::<f64>() + 0.03;
    for (e, w) in path.windows(2).enumerate() {
        let l1: f64 = w[0].iter().zip(&w[1]).map(|(a, b)| (a - b).abs()).sum();
        let n = (r * l1 / CHECK_STEP).ceil().max(1.0) as usize;
        for k in 0..=n {
            let t = k as f64 / n as f64;
            let q: Vec<f64> = w[0].iter().zip(&w[1]).map(|(a, b)| a + t * (b - a)).collect();
            let v = checker.check(&q).unwrap();
            assert!(v.is_free(), "edge {e} at t = {t}: {v:?}");
        }
    }
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

#[test]
fn hundred_seeded_queries_succeed_and_paths_are_free_when_rechecked() {
    let robot = ur5();
    let scene = scene();
    let mut checker = CollisionChecker::new(&robot, &scene);
    let mut rng = Lcg(2026);
    let options = PlanOptions::default();
    let (mut ok, mut times, mut direct) = (0, Vec::new(), 0);
    for i in 0..100u64 {
        let start = random_free(&mut rng, &mut checker);
        let goal = random_free(&mut rng, &mut checker);
        let result =
            plan(&robot, &scene, &start, &Goal::Joints(goal.clone()), &PlanOptions { seed: i, ..options.clone() });
        match result {
            Ok(p) => {
                ok += 1;
                times.push(p.stats.time_s);
                direct += usize::from(p.stats.iterations == 0);
                assert_eq!(p.waypoints.first().unwrap(), &start);
                assert_eq!(p.waypoints.last().unwrap(), &goal);
                assert!(p.waypoints.len() <= p.stats.raw_waypoints);
                assert_path_free(&mut checker, &robot, &p.waypoints);
            }
            Err(PlanError::BudgetExhausted { .. }) => {}
            Err(e) => panic!("query {i}: unexpected error {e}"),
        }
    }
    times.sort_by(f64::total_cmp);
    println!(
        "planner: {ok}/100 solved ({direct} by the straight edge), median {:.2} ms, p95 {:.2} ms",
        1e3 * percentile(&times, 0.5),
        1e3 * percentile(&times, 0.95)
    );
    assert!(ok >= 90, "success rate {ok}/100");
    // The scene must make the problem non-trivial: some queries need the search.
    assert!(direct < ok, "every query was solved by a straight edge");
}

#[test]
fn same_seed_gives_the_same_path() {
    let robot = ur5();
    let scene = scene();
    let mut checker = CollisionChecker::new(&robot, &scene);
    let mut rng = Lcg(7);
    // A query whose straight edge is blocked, so the random search runs.
    let (start, goal) = loop {
        let s = random_free(&mut rng, &mut checker);
        let g = random_free(&mut rng, &mut checker);
        let p = plan(&robot, &scene, &s, &Goal::Joints(g.clone()), &PlanOptions::default()).unwrap();
        if p.stats.iterations > 0 {
            break (s, g);
        }
    };
    let options = PlanOptions { seed: 42, ..PlanOptions::default() };
    let a = plan(&robot, &scene, &start, &Goal::Joints(goal.clone()), &options).unwrap();
    let b = plan(&robot, &scene, &start, &Goal::Joints(goal.clone()), &options).unwrap();
    assert_eq!(a.waypoints, b.waypoints);
    assert_eq!(a.stats.iterations, b.stats.iterations);
    assert_eq!(a.stats.nodes, b.stats.nodes);

    // The same query without any iteration left: the budget error.
    let none = PlanOptions { max_iterations: 0, ..PlanOptions::default() };
    match plan(&robot, &scene, &start, &Goal::Joints(goal), &none) {
        Err(PlanError::BudgetExhausted { iterations: 0, nodes: 2, .. }) => {}
        other => panic!("expected budget exhausted, got {other:?}"),
    }
}

#[test]
fn start_or_goal_in_collision_names_link_and_obstacle() {
    let robot = ur5();
    // A ball around the wrist centre (frame 5 origin) of q0 hits link 5 or 6 of the arm.
    let q0 = [0.3, -1.2, 1.5, -0.9, 0.7, 0.4];
    let wrist = robot.frames(&q0).unwrap()[4].translation.vector;
    let toml = format!(
        "length_unit = \"m\"\n[[obstacles]]\nname = \"wrist_ball\"\nshape = \"sphere\"\ncenter = [{}, {}, {}]\nradius = 0.05\n",
        wrist.x, wrist.y, wrist.z
    );
    let scene = Scene::from_toml_str(&toml).unwrap();
    let free = [-2.5, -1.0, 1.0, -1.0, 1.0, 0.0];
    assert!(CollisionChecker::new(&robot, &scene).check(&free).unwrap().is_free());

    match plan(&robot, &scene, &q0, &Goal::Joints(free.to_vec()), &PlanOptions::default()) {
        Err(e @ PlanError::StartInCollision(Blocked::Obstacle { .. })) => {
            let PlanError::StartInCollision(Blocked::Obstacle { link, link_name, obstacle }) = &e else {
                unreachable!()
            };
            assert_eq!(obstacle, "wrist_ball");
            assert!((4..=7).contains(link), "link {link}");
            // The message names the link by its number and its name (issue 35, point 8).
            assert_eq!(link_name, CollisionChecker::new(&robot, &scene).link_name(*link));
            assert!(e.to_string().contains(&format!("link {link} (`{link_name}`) collides")), "{e}");
        }
        other => panic!("expected start in collision, got {other:?}"),
    }
    let err = plan(&robot, &scene, &free, &Goal::Joints(q0.to_vec()), &PlanOptions::default()).unwrap_err();
    assert!(
        matches!(err, PlanError::GoalInCollision(Blocked::Obstacle { ref obstacle, .. }) if obstacle == "wrist_ball")
    );
    assert!(err.to_string().contains("wrist_ball"), "{err}");
    let pose = robot.fk(&q0).unwrap();
    let r = plan(&robot, &scene, &free, &Goal::Target(IkTarget::Pose(pose)), &PlanOptions::default());
    // Every IK solution puts the wrist centre at the same point (the ball), so all collide.
    assert!(matches!(r, Err(PlanError::GoalInCollision(_))), "{r:?}");
}

#[test]
fn pose_goal_reaches_the_pose_through_a_free_path() {
    let robot = ur5();
    let scene = scene();
    let mut checker = CollisionChecker::new(&robot, &scene);
    let mut rng = Lcg(99);
    for _ in 0..5 {
        let start = random_free(&mut rng, &mut checker);
        let target_q = random_free(&mut rng, &mut checker);
        let pose = robot.fk(&target_q).unwrap();
        let p = plan(&robot, &scene, &start, &Goal::Target(IkTarget::Pose(pose)), &PlanOptions::default()).unwrap();
        let end = robot.fk(p.waypoints.last().unwrap()).unwrap();
        assert!((end.translation.vector - pose.translation.vector).norm() < 1e-6);
        assert!(end.rotation.angle_to(&pose.rotation) < 1e-6);
        assert_path_free(&mut checker, &robot, &p.waypoints);
    }
}

#[test]
fn bad_input_is_rejected() {
    let robot = ur5();
    let scene = scene();
    let q = [0.0; 6];
    let short = plan(&robot, &scene, &q[..5], &Goal::Joints(q.to_vec()), &PlanOptions::default());
    assert!(matches!(short, Err(PlanError::Input(ref m)) if m.contains("5 joint values")), "{short:?}");
    let mut nan = q.to_vec();
    nan[2] = f64::NAN;
    let r = plan(&robot, &scene, &q, &Goal::Joints(nan), &PlanOptions::default());
    assert!(matches!(r, Err(PlanError::Input(ref m)) if m.contains("goal joint 3")), "{r:?}");
    let r = plan(&robot, &scene, &q, &Goal::Joints(q.to_vec()), &PlanOptions { step: 0.0, ..PlanOptions::default() });
    assert!(matches!(r, Err(PlanError::Input(_))), "{r:?}");
}
