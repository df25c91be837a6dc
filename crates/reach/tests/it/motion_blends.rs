//! Blended paths (issue 33): ten waypoints on the Panda and the UR5 timed with blends against
//! the stop-and-go timing, within every limit (exact ratios and an independent dense
//! sampling), and the blended path — lines and arcs — proven clear by the swept check; the
//! path workflow blends its corners and proves what it times.

use reach::jobs::Joints;
use reach::jobs::world::{PathRequest, PathTiming, SweptPathReport, path_run};
use reach::model::presets;
use reach::motion::{PathLimits, PiecewiseCubic, time_optimal};
use reach::world::Scene;

/// Ten waypoints on a closed loop in joint space about `centre`, `amplitude` rad per joint.
fn loop_waypoints(centre: &[f64], amplitude: f64) -> Vec<Vec<f64>> {
    (0..10)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 10.0;
            centre.iter().enumerate().map(|(j, c)| c + amplitude * (a + 0.7 * j as f64).sin()).collect()
        })
        .collect()
}

#[test]
fn ten_blended_waypoints_are_several_times_faster_than_stop_and_go_within_limits_and_proven_clear() {
    // A 5 cm ball in front of each arm, and the arm's own links (self-collision).
    for (name, centre, ball) in [
        ("panda", vec![0.0, -0.3, 0.0, -2.2, 0.0, 2.0, 0.8], [0.6, 0.0, 0.2]),
        ("ur5", vec![0.0, -1.2, 1.2, -1.5, -1.57, 0.0], [0.5, 0.3, 0.2]),
    ] {
        let scene = Scene::from_toml_str(&format!(
            "length_unit = \"m\"\nangle_unit = \"deg\"\n[[obstacles]]\nname = \"ball\"\nshape = \"sphere\"\ncenter = {ball:?}\nradius = 0.05\n"
        ))
        .unwrap();
        let robot = presets::get(name).unwrap();
        let limits = PathLimits::from_robot(&robot, 1.0, 1.0).unwrap();
        let w = loop_waypoints(&centre, 0.3);
        let stop = time_optimal(&PiecewiseCubic::polyline(&w).unwrap(), &limits, 0).unwrap();
        let path = PiecewiseCubic::blended(&w, 0.1).unwrap();
        let blended = time_optimal(&path, &limits, 0).unwrap();
        let ratio = stop.duration() / blended.duration();
        eprintln!("{name}: stop-and-go {:.3} s, blended {:.3} s ({ratio:.2}×)", stop.duration(), blended.duration());
        assert!(ratio >= 1.8, "{name}: blends only {ratio:.2}× faster");
        let r = blended.worst_ratios();
        for j in 0..robot.dof() {
            assert!(r.velocity[j] <= 1.0 && r.acceleration[j] <= 1.0, "{name}: {r:?}");
        }
        for s in blended.samples(blended.duration() / 20_000.0).unwrap() {
            for j in 0..robot.dof() {
                assert!(s.qd[j].abs() <= limits.velocity[j] * (1.0 + 1e-9), "{name} joint {j}: {s:?}");
                assert!(s.qdd[j].abs() <= limits.acceleration[j] * (1.0 + 1e-9), "{name} joint {j}: {s:?}");
            }
        }
        let swept = SweptPathReport::check_pieces(&robot, &scene, &path).unwrap().unwrap();
        assert!(swept.swept.clear && swept.swept.lower_bound_m.unwrap() > 0.0, "{name}: {swept:?}");
    }
}

#[test]
fn the_path_workflow_blends_its_corners_and_proves_the_blended_path() {
    let robot = presets::get("ur5").unwrap();
    let request = |blend: Option<f64>| PathRequest {
        scene: std::fs::read_to_string("../../examples/ur5_ball.toml").unwrap(),
        from: Joints::Deg(vec![-60.0, -90.0, 0.0, -90.0, 0.0, 0.0]),
        to: Some(Joints::Deg(vec![60.0, -90.0, 0.0, -90.0, 0.0, 0.0])),
        to_pose: None,
        seed: 1,
        time_budget_s: 5.0,
        duration_s: None,
        timing: None,
        max_velocity_scale: 1.0,
        max_acceleration_scale: 1.0,
        blend_tolerance: blend,
    };
    let blended = path_run(&robot, &request(None)).unwrap().report;
    let stop = path_run(&robot, &request(Some(0.0))).unwrap().report;
    assert!(blended.found && blended.timing == PathTiming::Optimal, "{blended:?}");
    assert_eq!(blended.waypoints_deg, stop.waypoints_deg, "the same plan for the same seed");
    assert!(blended.waypoints_deg.len() >= 3, "the ball forces a corner: {:?}", blended.waypoints_deg);
    assert_eq!(stop.blend_tolerance, Some(0.0));
    let tolerance = blended.blend_tolerance.unwrap();
    assert!(tolerance > 0.0 && tolerance <= 0.1, "{tolerance}");
    assert_eq!(blended.collision_free, Some(true));
    let swept = blended.swept.as_ref().unwrap();
    assert!(swept.swept.clear && swept.swept.lower_bound_m.unwrap() > 0.0, "{swept:?}");
    assert!(
        blended.duration_s.unwrap() < stop.duration_s.unwrap(),
        "{:?} vs {:?}",
        blended.duration_s,
        stop.duration_s
    );
    assert_eq!(blended.segment_durations_s.len(), blended.waypoints_deg.len() - 1);
    for ratio in blended.worst_velocity_ratio.iter().chain(&blended.worst_acceleration_ratio).flatten() {
        assert!(*ratio <= 1.0, "{ratio}");
    }
    // Refused: a negative tolerance, or one with cycloidal timing.
    assert!(path_run(&robot, &request(Some(-0.1))).unwrap_err().to_string().contains("blend_tolerance"));
    let cycloidal = PathRequest { timing: Some(PathTiming::Cycloidal), ..request(Some(0.1)) };
    assert!(path_run(&robot, &cycloidal).unwrap_err().to_string().contains("optimal timing only"));
}
