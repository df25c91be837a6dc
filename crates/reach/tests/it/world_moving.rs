//! Obstacles that move at a known, constant velocity (seed 000 §8 future work; issue 17 item
//! 4): the swept check in time against references computed here from the geometry alone —
//! distance over closing speed for an arm at rest, the first root of the exact
//! point-to-segment distance for an arm and an obstacle crossing each other, dense sampling of
//! that distance for random cases — and a fixed obstacle (`v = 0`) giving exactly the untimed
//! check's verdicts on seed 000's post scene.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Vector3;
use proptest::prelude::*;
use reach::ik::planar::PlanarRedundant;
use reach::model::presets;
use reach::world::detour::{P2, arm_points};
use reach::world::sweep::{SWEEP_FLOOR, SweepOptions};
use reach::world::{CollisionChecker, Scene, Shape, SweptPair, Verdict, WorldError};

use crate::common::Rng;

fn planar3() -> reach::Robot {
    presets::get("planar3").unwrap()
}

fn sphere(x: f64, y: f64, r: f64) -> Shape {
    Shape::Sphere { center: Vector3::new(x, y, 0.0), radius: r }
}

/// A scene with one sphere of radius `r` at `(x, y, 0)` at time 0, moving at `v` m/s.
fn moving_ball(x: f64, y: f64, r: f64, v: [f64; 2]) -> Scene {
    Scene::new().with_moving_obstacle("ball", sphere(x, y, r), Vector3::new(v[0], v[1], 0.0)).unwrap()
}

/// Distance from `h` to the segment `a b` (2-D).
fn point_segment(h: P2, a: P2, b: P2) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((h[0] - a[0]) * dx + (h[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (h[0] - a[0] - t * dx).hypot(h[1] - a[1] - t * dy)
}

/// Clearance of a ball (centre `h`, radius `r`) to the three links of planar3 at `q`, and the
/// 1-based link that is closest.
fn ball_clearance(arm: &PlanarRedundant, q: &[f64; 3], h: P2, r: f64) -> (f64, usize) {
    let p = arm_points(arm, q);
    (0..3)
        .map(|i| (point_segment(h, p[i], p[i + 1]) - r, i + 1))
        .fold((f64::INFINITY, 0), |m, c| if c.0 < m.0 { c } else { m })
}

fn lerp(a: &[f64; 3], b: &[f64; 3], s: f64) -> [f64; 3] {
    [0, 1, 2].map(|i| a[i] + s * (b[i] - a[i]))
}

/// The first instant in `[t0, t1]` where `f` reaches zero from above: bracketed on a grid of
/// 20 000 steps, then bisected to machine precision.
fn first_root(f: impl Fn(f64) -> f64, t0: f64, t1: f64) -> Option<f64> {
    let n = 20_000;
    let mut lo = t0;
    for k in 1..=n {
        let hi = t0 + (t1 - t0) * k as f64 / n as f64;
        if f(hi) <= 0.0 {
            let (mut a, mut b) = (lo, hi);
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if f(m) <= 0.0 { b = m } else { a = m }
            }
            return Some(b);
        }
        lo = hi;
    }
    None
}

/// planar3 at rest, stretched along x (tool at (3, 0)); a ball of radius 0.1 m at (3.5, 0)
/// moving at 0.2 m/s toward the tool. The gap is 3.5 − 0.1 − 3 = 0.4 m, so the ball touches
/// link 3 at 0.4 / 0.2 = 2 s. A motion that ends at 1.9 s is proven clear (clearance 0.02 m
/// at its end); one that lasts 2.5 s is not, stopping at 2 s on link 3 — where the checker
/// at that instant sees the contact. Moving away, or starting later, changes the answer as
/// the geometry says.
#[test]
fn a_ball_approaching_the_resting_arm_is_met_at_distance_over_speed() {
    let robot = planar3();
    let scene = moving_ball(3.5, 0.0, 0.1, [-0.2, 0.0]);
    let mut checker = CollisionChecker::new(&robot, &scene);
    let q = [0.0; 3];
    let options = SweepOptions::default();

    let (short, _) = checker.swept_timed(&q, &q, [0.0, 1.9], &options).unwrap();
    assert!(short.clear, "{short:?}");
    assert!((short.min_clearance - 0.02).abs() < 1e-9 && short.at == 1.0, "{short:?}");
    assert!(short.lower_bound > 0.0 && short.lower_bound <= short.min_clearance, "{short:?}");

    let (long, pair) = checker.swept_timed(&q, &q, [0.0, 2.5], &options).unwrap();
    assert!(!long.clear, "{long:?}");
    let t = 2.5 * long.at;
    assert!((2.0 - SWEEP_FLOOR / 0.2..=2.0 + 1e-12).contains(&t), "contact at t = {t} s, expected 2 s");
    assert_eq!(pair, SweptPair::Obstacle { link: 3, obstacle: 0 });
    assert_eq!(checker.check_at(&q, 2.0).unwrap(), Verdict::Obstacle { link: 3, obstacle: 0 });
    assert_eq!(checker.check_at(&q, 1.99).unwrap(), Verdict::Free);
    assert_eq!(checker.check(&q).unwrap(), Verdict::Free, "at time 0 the ball is 0.4 m away");
    let at_contact = checker.report_at(&q, t).unwrap();
    assert!(at_contact.min_obstacle_clearance_m.unwrap() <= SWEEP_FLOOR);

    // The same motion from 1 s to 2.2 s: the ball has already closed 0.2 m; contact still at 2 s.
    let (late, _) = checker.swept_timed(&q, &q, [1.0, 2.2], &options).unwrap();
    assert!(!late.clear);
    assert!((1.0 + 1.2 * late.at - 2.0).abs() <= SWEEP_FLOOR / 0.2, "{late:?}");

    // Moving away, or sideways past the tool (closest 0.5 − 0.1 = 0.4 m at time 0), is clear
    // for any duration.
    for v in [[0.2, 0.0], [0.0, 1.0]] {
        let scene = moving_ball(3.5, 0.0, 0.1, v);
        let (away, _) = CollisionChecker::new(&robot, &scene).swept_timed(&q, &q, [0.0, 100.0], &options).unwrap();
        assert!(away.clear, "{v:?}: {away:?}");
        assert!((away.min_clearance - 0.4).abs() < 1e-9 && away.at == 0.0, "{v:?}: {away:?}");
        assert!(away.lower_bound > 0.0 && away.lower_bound <= 0.4, "{away:?}");
    }
}

/// Crossing: the stretched arm swings about the base from 0° to 90° in 2 s while a ball of
/// radius 0.1 m starting at (2, 2) falls at 1 m/s across its path. The contact instant is the
/// first root of `|c(t) − rod(θ(t))| = 0.1` (computed here from the point-to-segment distance);
/// the check stops there (within the floor's time), on the link the reference names.
/// Taken as fixed where it is at time 0 the ball would be met later: the verdict depends on
/// the motion's timing.
#[test]
fn an_arm_and_a_ball_crossing_meet_at_the_computed_instant() {
    let robot = planar3();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    let (a, b) = ([0.0; 3], [FRAC_PI_2, 0.0, 0.0]);
    let (c0, v, r, duration) = ([2.0, 2.0], [0.0, -1.0], 0.1, 2.0);
    let centre = |t: f64| [c0[0] + v[0] * t, c0[1] + v[1] * t];
    let clearance = |t: f64| ball_clearance(&arm, &lerp(&a, &b, t / duration), centre(t), r);
    let t_star = first_root(|t| clearance(t).0, 0.0, duration).unwrap();
    let link = clearance(t_star).1;
    assert!((0.6..0.8).contains(&t_star), "reference contact at {t_star} s");

    let scene = moving_ball(c0[0], c0[1], r, v);
    let mut checker = CollisionChecker::new(&robot, &scene);
    let (swept, pair) = checker.swept_timed(&a, &b, [0.0, duration], &SweepOptions::default()).unwrap();
    assert!(!swept.clear, "{swept:?}");
    let t = duration * swept.at;
    assert!((t_star - 1e-5..=t_star + 1e-9).contains(&t), "stopped at {t} s, contact at {t_star} s");
    assert_eq!(pair, SweptPair::Obstacle { link, obstacle: 0 });
    assert!(clearance(t).0 <= SWEEP_FLOOR + 1e-9, "the reference clearance there: {}", clearance(t).0);

    // The ball fixed at (2, 2): the swing meets it only at the angle where the rod's distance to
    // (2, 2) is 0.1 m, θ = 45° − asin(0.1/√8), i.e. t = θ/(π/4) s — later than t*.
    let fixed = Scene::new().with_obstacle("ball", sphere(2.0, 2.0, r)).unwrap();
    let (still, _) = CollisionChecker::new(&robot, &fixed).swept(&a, &b, &SweepOptions::default()).unwrap();
    let theta = std::f64::consts::FRAC_PI_4 - (0.1 / 8f64.sqrt()).asin();
    assert!(!still.clear);
    assert!((duration * still.at - theta / std::f64::consts::FRAC_PI_4).abs() < 1e-5, "{still:?}");
    assert!(duration * still.at > t + 0.05);
}

/// Crossing clear: the ball (radius 0.1 m) starts at (2.5, 0.5), ahead of the swinging arm, and
/// leaves its disc upward at 3 m/s before the arm comes: proven clear, the certified bound below
/// the densely sampled exact clearance (200 001 instants) and the reported minimum within
/// 0.1 % of it. Slower (0.5 m/s) the arm catches it: not clear, at a real contact.
#[test]
fn a_ball_crossing_ahead_of_the_arm_is_proven_clear_and_a_slower_one_is_hit() {
    let robot = planar3();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    let (a, b, r, duration) = ([0.0; 3], [FRAC_PI_2, 0.0, 0.0], 0.1, 2.0);
    for (speed, clear) in [(3.0, true), (0.5, false)] {
        let centre = |t: f64| [2.5, 0.5 + speed * t];
        let clearance = |t: f64| ball_clearance(&arm, &lerp(&a, &b, t / duration), centre(t), r).0;
        let sampled =
            (0..=200_000).map(|k| clearance(duration * f64::from(k) / 200_000.0)).fold(f64::INFINITY, f64::min);
        let scene = moving_ball(2.5, 0.5, r, [0.0, speed]);
        let (swept, _) = CollisionChecker::new(&robot, &scene)
            .swept_timed(&a, &b, [0.0, duration], &SweepOptions::default())
            .unwrap();
        assert_eq!(swept.clear, clear, "speed {speed}: {swept:?}, sampled minimum {sampled}");
        if clear {
            assert!(sampled > 0.05, "the reference: {sampled}");
            assert!(swept.lower_bound > 0.0 && swept.lower_bound <= sampled + 1e-12, "{swept:?} vs {sampled}");
            assert!((swept.min_clearance - sampled).abs() <= 1e-3 * sampled, "{swept:?} vs {sampled}");
        } else {
            let t_star = first_root(clearance, 0.0, duration).unwrap();
            let t = duration * swept.at;
            assert!((t_star - 1e-5..=t_star + 1e-9).contains(&t), "stopped at {t} s, contact at {t_star} s");
        }
    }
}

/// The post scene of seed 000's planar arm (examples/path_planar3_post.toml).
fn post_scene_text() -> String {
    std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/path_planar3_post.toml")).unwrap()
}

/// A fixed obstacle is `v = 0`: on seed 000's post scene, 200 random motions (and the paths
/// through them) get exactly the untimed check's results from the timed check, whatever the
/// time span, also with `velocity = [0, 0, 0]` written in the file.
#[test]
fn a_fixed_obstacle_gives_exactly_the_untimed_verdicts() {
    let robot = planar3();
    let scene = Scene::from_toml_str(&post_scene_text()).unwrap();
    let written = Scene::from_toml_str(&format!("{}velocity = [0, 0, 0]\n", post_scene_text())).unwrap();
    assert!(scene.moving_obstacle().is_none() && written.moving_obstacle().is_none());
    let mut rng = Rng::new(17);
    let options = SweepOptions::default();
    let (mut untimed, mut timed, mut with_zero) = (
        CollisionChecker::new(&robot, &scene),
        CollisionChecker::new(&robot, &scene),
        CollisionChecker::new(&robot, &written),
    );
    let mut blocked = 0;
    let mut points = vec![rng.joints(&robot)];
    for _ in 0..200 {
        let (a, b) = (points[points.len() - 1].clone(), rng.joints(&robot));
        let span = [rng.uniform(0.0, 5.0), rng.uniform(5.0, 10.0)];
        let reference = untimed.swept(&a, &b, &options).unwrap();
        assert_eq!(timed.swept_timed(&a, &b, span, &options).unwrap(), reference);
        assert_eq!(with_zero.swept_timed(&a, &b, span, &options).unwrap(), reference);
        blocked += usize::from(!reference.0.clear);
        points.push(b);
    }
    assert!((20..180).contains(&blocked), "both verdicts occur: {blocked} of 200 blocked");
    let times: Vec<f64> = (0..points.len()).map(|k| 0.5 * k as f64).collect();
    let path = untimed.swept_path(&points, &options).unwrap().unwrap();
    let timed_path = timed.swept_path_timed(&points, &times, &options).unwrap().unwrap();
    assert_eq!((timed_path.clear, timed_path.segment, timed_path.closest), (path.clear, path.segment, path.closest));
    assert_eq!(timed_path.t_s, Some(times[path.segment] + path.closest.at * 0.5));
}

/// A path in time: the arm rests for 1 s, then swings 90° in 1 s; a ball at (1.5, 1.2) moving
/// at (0, −0.5) m/s. The ball is 1.1 m above the arm at rest and still 0.6 m at 1 s; during the
/// swing it is hit — the path's check names segment 2 and an instant in (1, 2) s where the
/// reference clearance is zero.
#[test]
fn a_timed_path_is_checked_segment_by_segment_at_each_instant() {
    let robot = planar3();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    let scene = moving_ball(1.5, 1.2, 0.1, [0.0, -0.5]);
    let points = vec![vec![0.0; 3], vec![0.0; 3], vec![FRAC_PI_2, 0.0, 0.0]];
    let times = [0.0, 1.0, 2.0];
    let path = CollisionChecker::new(&robot, &scene)
        .swept_path_timed(&points, &times, &SweepOptions::default())
        .unwrap()
        .unwrap();
    assert!(!path.clear);
    assert_eq!(path.segment, 1);
    let t = path.t_s.unwrap();
    let reference = |t: f64| {
        let s = (t - 1.0).max(0.0);
        ball_clearance(&arm, &[FRAC_PI_2 * s, 0.0, 0.0], [1.5, 1.2 - 0.5 * t], 0.1).0
    };
    let t_star = first_root(reference, 0.0, 2.0).unwrap();
    assert!(t > 1.0 && (t_star - 1e-5..=t_star + 1e-9).contains(&t), "stopped at {t} s, contact at {t_star} s");
    // Bad times are refused.
    let mut checker = CollisionChecker::new(&robot, &scene);
    for bad in [[0.0, 2.0, 1.0], [0.0, f64::NAN, 1.0]] {
        assert!(matches!(checker.swept_path_timed(&points, &bad, &SweepOptions::default()), Err(WorldError::Input(_))));
    }
    assert!(checker.swept_path_timed(&points, &[0.0, 1.0], &SweepOptions::default()).is_err());
}

/// A moving obstacle is refused wherever obstacles are taken as fixed — the untimed swept
/// check, the planner, the configuration-space grid, the motion synthesis — with its name; the
/// scene file gives the velocity in its length unit per second, finite, obstacles only.
#[test]
fn moving_obstacles_are_refused_where_time_is_unknown_and_parsed_in_file_units() {
    let robot = planar3();
    let scene = Scene::from_toml_str(
        "length_unit = \"mm\"\nangle_unit = \"deg\"\n[[obstacles]]\nname = \"cart\"\nshape = \"sphere\"\n\
         center = [3500, 0, 0]\nradius = 100\nvelocity = [-200, 0, 0]\n",
    )
    .unwrap();
    assert_eq!(scene.obstacles[0].velocity, Vector3::new(-0.2, 0.0, 0.0));
    let q = vec![0.0; 3];
    let mut checker = CollisionChecker::new(&robot, &scene);
    let untimed = checker.swept(&q, &q, &SweepOptions::default()).unwrap_err().to_string();
    assert!(untimed.contains("`cart` moves") && untimed.contains("-0.2"), "{untimed}");
    assert!(checker.swept_path(&[q.clone(), q.clone()], &SweepOptions::default()).is_err());
    let plan =
        reach::world::plan(&robot, &scene, &q, &reach::world::Goal::Joints(vec![0.5, 0.0, 0.0]), &Default::default());
    assert!(plan.unwrap_err().to_string().contains("the planner"));
    let spec = reach::world::cspace::GridSpec::new(3, 30f64.to_radians());
    let grid = reach::world::cspace::classify_grid(&robot, &scene, &spec).unwrap_err().to_string();
    assert!(grid.contains("`cart` moves"), "{grid}");
    let goal = reach::world::approach::ApproachGoal::Joints(vec![0.5, -0.5, -0.5]);
    let synth = reach::world::approach::approach(&robot, &scene, &[0.1, -0.1, -0.1], &goal, &Default::default(), None);
    assert!(synth.unwrap_err().to_string().contains("`cart` moves"));

    let bad = |extra: &str, zone: bool| {
        let table = if zone { "tool_zone" } else { "obstacles" };
        Scene::from_toml_str(&format!(
            "length_unit = \"m\"\nangle_unit = \"deg\"\n[[{table}]]\nname = \"x\"\nshape = \"sphere\"\n\
             center = [0, 0, 0]\nradius = 1\n{extra}\n"
        ))
        .unwrap_err()
        .to_string()
    };
    assert!(bad("velocity = [nan, 0, 0]", false).contains("`velocity` must be finite"));
    assert!(bad("velocity = [1, 0]", false).contains("line"), "a wrong length is a parse error");
    assert!(bad("velocity = [1, 0, 0]", true).contains("obstacles only"));
    let built = Scene::new().with_moving_obstacle("b", sphere(0.0, 0.0, 1.0), Vector3::new(f64::INFINITY, 0.0, 0.0));
    assert!(built.unwrap_err().to_string().contains("`velocity` must be finite"));
}

/// The `check` and `move` workflows: a straight motion against a moving obstacle needs its
/// duration (refused without, naming `duration_s`), then reports the instant; a `move` with a
/// scene is checked in time along its samples, and `check` of its samples agrees.
#[test]
fn the_check_and_move_workflows_check_moving_obstacles_in_time() {
    use reach::jobs::Joints;
    use reach::jobs::input::MotionSample;
    use reach::jobs::motion::{MoveRequest, move_motion};
    use reach::jobs::world::{CheckRequest, check};
    let robot = planar3();
    let scene = "length_unit = \"m\"\nangle_unit = \"deg\"\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\n\
                 center = [3.5, 0, 0]\nradius = 0.1\nvelocity = [-0.2, 0, 0]\n";
    let request = |duration_s: Option<f64>| CheckRequest {
        scene: scene.into(),
        q: Joints::Deg(vec![0.0, 0.0, 0.0]),
        to: Some(Joints::Deg(vec![0.0, 0.0, 0.0])),
        duration_s,
        samples: None,
    };
    let e = check(&robot, &request(None)).unwrap_err().to_string();
    assert!(e.contains("duration_s") && e.contains("`ball` moves"), "{e}");
    assert!(check(&robot, &request(Some(-1.0))).unwrap_err().to_string().contains("duration_s"));
    let clear = check(&robot, &request(Some(1.9))).unwrap().motion.unwrap();
    assert!(clear.swept.clear && clear.swept.t_s == Some(1.9), "{clear:?}");
    let hit = check(&robot, &request(Some(3.0))).unwrap().motion.unwrap();
    assert!(!hit.swept.clear);
    assert!((hit.swept.t_s.unwrap() - 2.0).abs() < 1e-5, "{hit:?}");
    assert_eq!(hit.swept.pair_text.as_deref(), Some("link 3 (`A`) and `ball`"));

    // A move of 5 s that folds link 3 by only 3°: the tool (within 0.003 m of x = 3 before
    // 2.1 s) meets the ball close to 2 s.
    let moved = move_motion(
        &robot,
        &MoveRequest {
            duration_s: Some(5.0),
            scene: Some(scene.into()),
            ..MoveRequest::joints(Joints::Deg(vec![0.0, 0.0, 0.0]), Joints::Deg(vec![0.0, 0.0, -3.0]))
        },
    )
    .unwrap();
    assert!(!moved.feasible);
    let swept = moved.swept.as_ref().unwrap();
    let t = swept.swept.t_s.unwrap();
    assert!(t > 1.98 && t < 2.02, "{swept:?}");
    assert!(moved.reasons.last().unwrap().contains("link 3 (`A`) and `ball` at t = "), "{:?}", moved.reasons);
    let samples: Vec<MotionSample> =
        moved.samples.iter().map(|s| MotionSample { t_s: s.t_s, q_deg: s.q_deg.clone() }).collect();
    let again = check(&robot, &CheckRequest { to: None, samples: Some(samples), duration_s: None, ..request(None) })
        .unwrap()
        .samples
        .unwrap();
    // Segment 1 of `check` runs from `q` to the first sample (no motion): one segment later.
    assert_eq!(again.segment, swept.segment + 1);
    assert!((again.swept.t_s.unwrap() - t).abs() < 1e-9, "{again:?} vs {swept:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// Random planar3 motions, balls and velocities (128 cases, about 15 % hit): a collision at any of 10 001 sampled
    /// instants means not clear; a clear verdict's bound is positive and below every sampled
    /// clearance; where the check stops the reference clearance is within the floor.
    #[test]
    fn a_moving_ball_is_never_called_clear_when_it_is_hit(
        q1 in prop::array::uniform2(-3.0f64..3.0),
        from in prop::array::uniform2(-1.5f64..1.5),
        to in prop::array::uniform2(-1.5f64..1.5),
        h in prop::array::uniform2(-2.5f64..2.5),
        v in prop::array::uniform2(-3.0f64..3.0),
        r in 0.05f64..0.5,
        t0 in 0.0f64..2.0,
        duration in 0.1f64..3.0,
    ) {
        // Bends within ±1.5 rad: links 1 and 3 never meet, every stop is the ball's.
        let (from, to) = ([q1[0], from[0], from[1]], [q1[1], to[0], to[1]]);
        let robot = planar3();
        let arm = PlanarRedundant::from_robot(&robot).unwrap();
        let scene = moving_ball(h[0], h[1], r, v);
        let at = |s: f64| {
            let t = t0 + s * duration;
            ball_clearance(&arm, &lerp(&from, &to, s), [h[0] + v[0] * t, h[1] + v[1] * t], r).0
        };
        let sampled = (0..=10_000).map(|k| at(f64::from(k) / 10_000.0)).fold(f64::INFINITY, f64::min);
        let (swept, pair) = CollisionChecker::new(&robot, &scene)
            .swept_timed(&from, &to, [t0, t0 + duration], &SweepOptions::default())
            .unwrap();
        if sampled <= 0.0 {
            prop_assert!(!swept.clear, "hit at a sample ({sampled}), yet clear: {swept:?}");
        }
        if swept.clear {
            prop_assert!(swept.lower_bound > 0.0 && swept.lower_bound <= sampled + 1e-12, "{swept:?} vs {sampled}");
        } else {
            prop_assert!(matches!(pair, SweptPair::Obstacle { .. }), "{pair:?}");
            prop_assert!(at(swept.at) <= SWEEP_FLOOR + 1e-9, "stopped at s = {} with clearance {}", swept.at, at(swept.at));
        }
    }
}
