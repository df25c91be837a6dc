//! Criteria of whole motions (`decide::motion_criteria`) against values computed by hand or by
//! the functions they stand on, and the per-interval configuration choice in path tracking
//! (`TrackChooser`).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use reach::decide::motion_criteria::{MOTION_CRITERIA, Requirement, point_to_point_duration};
use reach::decide::{DecideError, Direction, Method, MotionCriterion, SampledMotion, TrackChooser, choose_motion};
use reach::effort::{DEFAULT_SIX_JOINT_WEIGHTS, Differences, j1};
use reach::ik::Branch;
use reach::model::presets;
use reach::motion::PathSample;
use reach::motion::tracking::{Decision, EventCode, TrackedPath, TrackingOptions, track};
use reach::motion::{JointRates, Profile};
use reach::world::{Scene, Shape};

fn c(name: &str, robot: &reach::Robot) -> MotionCriterion {
    MotionCriterion::parse(name, robot, None, None).unwrap()
}

#[test]
fn values_match_hand_computations() {
    let robot = presets::get("spbu6").unwrap();
    // q(t) = (t², 0, 0, t, 0, 0) at t = 0, 0.5, 1, 1.5 (radians).
    let t = [0.0, 0.5, 1.0, 1.5];
    let q: Vec<Vec<f64>> = t.iter().map(|&s| vec![s * s, 0.0, 0.0, s, 0.0, 0.0]).collect();
    let m = SampledMotion::new(&t, &q);
    let v = |name: &str| c(name, &robot).evaluate(&robot, &m).unwrap();
    let expected_j1 = j1(&q[0], &q[3], &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::Literal).unwrap();
    assert!((v("j1") - expected_j1).abs() < 1e-12);
    // Monotone motion: J2 = J1.
    assert!((v("j2") - expected_j1).abs() < 1e-12);
    // Step rates of q1: 0.5, 1.5, 2.5 rad/s; q4: 1 rad/s. Peak 2.5.
    assert!((v("peak_velocity") - 2.5).abs() < 1e-12);
    // Rate differences 1.0 over 0.5 s mid-time spacing: 2 rad/s².
    assert!((v("peak_acceleration") - 2.0).abs() < 1e-12);
    // Tool path length: sum of FK chord lengths.
    let fk = |k: usize| robot.fk(&q[k]).unwrap().translation.vector;
    let chords: f64 = (1..4).map(|k| (fk(k) - fk(k - 1)).norm()).sum();
    assert!((v("path-length") - chords).abs() < 1e-12);
    // Manipulability: the minimum over the samples.
    let least = q.iter().map(|qk| robot.manipulability(qk).unwrap().yoshikawa).fold(f64::INFINITY, f64::min);
    assert!((v("manipulability") - least).abs() < 1e-12);
    for name in MOTION_CRITERIA.iter().filter(|n| !["clearance", "duration", "energy"].contains(n)) {
        let d = c(name, &robot).describe();
        assert_eq!(&d.name, name);
        assert!(!d.unit.is_empty());
    }
    assert_eq!(c("limits", &robot).describe().direction, Direction::MoreIsBetter);
    assert_eq!(c("j2", &robot).describe().direction, Direction::LessIsBetter);
}

#[test]
fn energy_is_the_mechanical_work_of_the_dynamics_model() {
    // puma560 carries link masses: lifting the upper arm costs at least the potential energy
    // gained, and the criterion is the dynamics module's number.
    let puma = presets::get("puma560").unwrap();
    let t: Vec<f64> = (0..=50).map(|k| f64::from(k) * 0.02).collect();
    let q: Vec<Vec<f64>> = t.iter().map(|&s| vec![0.0, 0.4 * s, -0.2 * s, 0.0, 0.0, 0.0]).collect();
    let e = c("energy", &puma).evaluate(&puma, &SampledMotion::new(&t, &q)).unwrap();
    let expected = reach::effort::dynamics::trajectory_energy(&puma, &t, &q).unwrap();
    assert!((e - expected).abs() < 1e-12 * expected.max(1.0), "{e} vs {expected}");
    let gained = reach::effort::dynamics::potential_energy(&puma, &q[50]).unwrap()
        - reach::effort::dynamics::potential_energy(&puma, &q[0]).unwrap();
    assert!(gained > 0.0 && e >= gained - 1e-9, "energy {e} J < potential energy gained {gained} J");
    let d = c("energy", &puma).describe();
    assert_eq!((d.name.as_str(), d.unit.as_str(), d.direction), ("energy", "J", Direction::LessIsBetter));
    // spbu6 has no masses: a named error, not a made-up value.
    let spbu6 = presets::get("spbu6").unwrap();
    let err = MotionCriterion::parse("energy", &spbu6, None, None).unwrap_err().to_string();
    assert!(err.contains("energy") && err.contains("spbu6"), "{err}");
}

#[test]
fn duration_is_the_speed_limited_traversal() {
    let robot = presets::get("puma560").unwrap();
    let rates = JointRates::new(vec![1.0, 2.0, 1.0, 4.0, 4.0, 4.0], None).unwrap();
    let d = MotionCriterion::Duration { rates: rates.clone() };
    // Two steps: joint 1 moves 0.5 then joint 2 moves 1.0 → 0.5 s + 0.5 s.
    let t = [0.0, 1.0, 2.0];
    let q = vec![vec![0.0; 6], vec![0.5, 0.0, 0.0, 0.0, 0.0, 0.0], vec![0.5, 1.0, 0.0, 0.0, 0.0, 0.0]];
    assert!((d.evaluate(&robot, &SampledMotion::new(&t, &q)).unwrap() - 1.0).abs() < 1e-12);
    // Point to point with a cycloidal profile: peak normalised speed 2 → 2·|Δ|/v.
    let p2p = point_to_point_duration(&[0.5, 1.0, 0.0, 0.0, 0.0, 0.0], &rates, Profile::Cycloidal).unwrap();
    assert!((p2p - 1.0).abs() < 1e-12, "{p2p}");
}

#[test]
fn clearance_is_the_smallest_over_the_motion() {
    let robot = presets::get("puma560").unwrap();
    let scene = Scene::new()
        .with_obstacle("ball", Shape::Sphere { center: Vector3::new(0.6, 0.0, 0.4), radius: 0.05 })
        .unwrap();
    let crit = MotionCriterion::parse("clearance", &robot, None, Some(&scene)).unwrap();
    let t = [0.0, 1.0, 2.0];
    let q: Vec<Vec<f64>> = [0.0, 0.3, 0.6].iter().map(|&a| vec![a, -0.5, 0.5, 0.0, 0.5, 0.0]).collect();
    let value = crit.evaluate(&robot, &SampledMotion::new(&t, &q)).unwrap();
    let mut checker = reach::world::CollisionChecker::new(&robot, &scene);
    let least =
        q.iter().map(|qk| checker.report(qk).unwrap().min_obstacle_clearance_m.unwrap()).fold(f64::INFINITY, f64::min);
    assert_eq!(value, least);
    // Without a scene, clearance is refused rather than invented.
    assert!(matches!(MotionCriterion::parse("clearance", &robot, None, None), Err(DecideError::Criterion { .. })));
}

#[test]
fn clearance_rejects_a_bad_allowed_collision_list_at_parse() {
    // Regression: a bad list used to be kept and surfaced only as an evaluation error, which a
    // TrackChooser read as "no value" and silently fell back to another choice.
    let robot = presets::get("puma560").unwrap();
    let scene = Scene::new()
        .with_obstacle("ball", Shape::Sphere { center: Vector3::new(0.6, 0.0, 0.4), radius: 0.05 })
        .unwrap()
        .with_allowed_self_collision("link1", "no_such_link");
    match MotionCriterion::parse("clearance", &robot, None, Some(&scene)) {
        Err(DecideError::Criterion { criterion, reason }) => {
            assert_eq!(criterion, "clearance");
            assert!(reason.contains("no_such_link"), "{reason}");
        }
        other => panic!("expected a clearance error, got {other:?}"),
    }
    // A good list is accepted.
    let good = Scene::new()
        .with_obstacle("ball", Shape::Sphere { center: Vector3::new(0.6, 0.0, 0.4), radius: 0.05 })
        .unwrap()
        .with_allowed_self_collision("link1", "link3");
    assert!(MotionCriterion::parse("clearance", &robot, None, Some(&good)).is_ok());
}

#[test]
fn bad_motions_and_names_are_rejected() {
    let robot = presets::get("puma560").unwrap();
    let err = MotionCriterion::parse("rigidity", &robot, None, None).unwrap_err();
    assert!(err.to_string().contains("unknown criterion 'rigidity'"), "{err}");
    assert!(MotionCriterion::parse("j1", &robot, Some(&[1.0, -1.0, 1.0, 1.0, 1.0, 1.0]), None).is_err());
    let j2 = c("j2", &robot);
    let t = [0.0, 1.0];
    let short = vec![vec![0.0; 6], vec![0.0; 5]];
    assert!(matches!(j2.evaluate(&robot, &SampledMotion::new(&t, &short)), Err(DecideError::BadVector { .. })));
    let nan = vec![vec![0.0; 6], vec![f64::NAN; 6]];
    assert!(j2.evaluate(&robot, &SampledMotion::new(&t, &nan)).is_err());
    let backwards = [1.0, 0.0];
    let ok = vec![vec![0.0; 6], vec![0.1; 6]];
    assert!(j2.evaluate(&robot, &SampledMotion::new(&backwards, &ok)).is_err());
    assert!(matches!(
        choose_motion(&robot, &[], std::slice::from_ref(&j2), &[1.0], Method::Topsis),
        Err(DecideError::NoCandidates)
    ));
    let m = SampledMotion::new(&t, &ok);
    assert!(matches!(
        choose_motion(&robot, &[m], &[j2], &[1.0, 2.0], Method::Topsis),
        Err(DecideError::WeightCount { .. })
    ));
}

/// log-loader (base yaw + two 1 m links), position-only path from (r, e) = (1.2, 60°)
/// to (1.8, 80°) at yaw 30°: no singular position, elbow-up and elbow-down both feasible.
fn loader_report(
    criterion: Option<&dyn reach::motion::tracking::ConfigurationCriterion>,
) -> reach::motion::tracking::TrackingReport {
    let robot = presets::get("log-loader").unwrap();
    let pose = |s: f64| {
        let (r, e) = (1.2 + 0.6 * s, (60.0 + 20.0 * s).to_radians());
        let (sy, cy) = 30f64.to_radians().sin_cos();
        Isometry3::from_parts(
            Translation3::from(Vector3::new(cy * e.cos(), sy * e.cos(), e.sin()) * r),
            UnitQuaternion::identity(),
        )
    };
    let samples: Vec<PathSample> = (0..=40)
        .map(|k| f64::from(k) / 40.0)
        .map(|s| PathSample { s, t: 4.0 * s, angle: 0.0, pose: pose(s) })
        .collect();
    let path = TrackedPath::sampled(&samples).unwrap();
    let options = TrackingOptions {
        configurations: vec![
            Branch::new([("base", "front"), ("elbow", "up")]),
            Branch::new([("base", "front"), ("elbow", "down")]),
        ],
        position_only: true,
        ..Default::default()
    };
    track(&robot, &path, &options, criterion).unwrap()
}

#[test]
fn track_chooser_realises_the_best_ranked_configuration() {
    let robot = presets::get("log-loader").unwrap();
    let plain = loader_report(None);
    assert_eq!(plain.intervals.len(), 1);
    let interval = &plain.intervals[0];
    assert!(interval.configurations.iter().all(|t| t.feasible));
    assert_eq!(interval.decision, Decision::Default);
    let motions: Vec<SampledMotion> = interval.configurations.iter().map(SampledMotion::of_track).collect();
    // A ball above the elbow-up elbow (in the arm plane at yaw 30°: 0.6 m behind the base
    // axis, 0.9 m up): clearance prefers elbow-down; the limit margin prefers elbow-up (q2 of
    // elbow-down starts 7° from its lower limit).
    let (sy, cy) = 30f64.to_radians().sin_cos();
    let ball = Shape::Sphere { center: Vector3::new(-0.6 * cy, -0.6 * sy, 0.9), radius: 0.1 };
    let scene = Scene::new().with_obstacle("ball", ball).unwrap();
    let cases: [(Vec<&str>, Vec<f64>, usize); 3] = [
        (vec!["limits"], vec![1.0], 0),
        (vec!["clearance"], vec![1.0], 1),
        (vec!["peak_velocity", "j2", "limits", "clearance"], vec![0.1, 0.2, 0.3, 0.4], 1),
    ];
    for (names, weights, want) in cases {
        let criteria: Vec<MotionCriterion> =
            names.iter().map(|n| MotionCriterion::parse(n, &robot, None, Some(&scene)).unwrap()).collect();
        let expected = choose_motion(&robot, &motions, &criteria, &weights, Method::Topsis).unwrap().best();
        assert_eq!(expected, want, "{names:?}");
        let chooser = TrackChooser::new(&robot, criteria, weights, Method::Topsis).unwrap();
        let r = loader_report(Some(&chooser));
        assert_eq!((r.intervals[0].chosen, r.intervals[0].decision), (Some(want), Decision::Criterion), "{names:?}");
    }
    // A requirement no configuration meets (limit margin ≥ 0.6 > 0.5): K14, default kept.
    let chooser = TrackChooser::new(&robot, vec![c("limits", &robot)], vec![1.0], Method::Vikor)
        .unwrap()
        .with_requirements(vec![Requirement { criterion: 0, bound: 0.6 }])
        .unwrap();
    let r = loader_report(Some(&chooser));
    assert_eq!((r.intervals[0].chosen, r.intervals[0].decision), (Some(0), Decision::CriterionRejected));
    assert_eq!(r.events_with(EventCode::K14).count(), 1);
    // Weight errors are caught when the chooser is built.
    assert!(TrackChooser::new(&robot, vec![c("j2", &robot)], vec![-1.0], Method::Topsis).is_err());
    assert!(TrackChooser::new(&robot, vec![c("j2", &robot)], vec![0.0], Method::Topsis).is_err());
}
