//! Path tracking through IK (`motion::tracking`): singular positions split the path, the
//! configuration changes only there, an unreachable stretch is reported (not a panic), and
//! bad input is rejected.
//!
//! The arm is the `log-loader` (base yaw + two 1 m links in a vertical plane, position
//! targets), so every expected value follows from plane trigonometry written out here: for a
//! target at distance R from the shoulder and elevation e in the arm plane, the half-angle
//! of the elbow triangle is β = acos(R/2), the elbow-up solution has q2 = e + β, q3 = −2β and
//! the elbow-down one q2 = e − β, q3 = 2β. R = 2 is the stretched arm (|Δ| = 1).

use std::cell::RefCell;
use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use reach::Robot;
use reach::ik::{Branch, SingularityKind};
use reach::model::presets;
use reach::motion::PathSample;
use reach::motion::tracking::{
    ConfigurationTrack, Decision, EventCode, SingularityDetection, SplitKind, TRACKING_PROGRESS_CHUNK, TrackedPath,
    TrackingError, TrackingOptions, TrackingReport, ViolationKind, describe, track, track_with_progress,
};

const YAW_DEG: f64 = 30.0;

fn loader(upper_a_deg: f64) -> Robot {
    let mut spec = presets::get("log-loader").unwrap().spec().clone();
    spec.joints[1].limits.upper = upper_a_deg.to_radians();
    Robot::new(spec).unwrap()
}

/// A point at distance `r` and elevation `e` (radians) in the arm plane at yaw 30°.
fn point(r: f64, e: f64) -> Isometry3<f64> {
    let (sy, cy) = YAW_DEG.to_radians().sin_cos();
    let dir = Vector3::new(cy * e.cos(), sy * e.cos(), e.sin());
    Isometry3::from_parts(Translation3::from(dir * r), UnitQuaternion::identity())
}

/// Touch path: R(s) = 2 − (s − 1)²/2 reaches the stretched arm at s = 1 only; the elevation
/// rises from 15° to 80°.
fn touch_r(s: f64) -> f64 {
    2.0 - 0.5 * (s - 1.0) * (s - 1.0)
}
fn touch_e(s: f64) -> f64 {
    (15.0 + 32.5 * s).to_radians()
}
fn touch_pose(s: f64) -> Isometry3<f64> {
    point(touch_r(s), touch_e(s))
}

fn grid(f: impl Fn(f64) -> Isometry3<f64>, end: f64, steps: u32) -> Vec<PathSample> {
    (0..=steps)
        .map(|k| {
            let s = end * f64::from(k) / f64::from(steps);
            PathSample { t: 2.0 * s, s, angle: 0.0, pose: f(s) }
        })
        .collect()
}

fn configurations() -> Vec<Branch> {
    vec![Branch::new([("base", "front"), ("elbow", "up")]), Branch::new([("base", "front"), ("elbow", "down")])]
}

fn options(detection: SingularityDetection) -> TrackingOptions {
    TrackingOptions { configurations: configurations(), position_only: true, detection, ..Default::default() }
}

fn run(robot: &Robot, criterion: Option<&dyn reach::motion::tracking::ConfigurationCriterion>) -> TrackingReport {
    let samples = grid(touch_pose, 2.0, 149); // s = 1 is not a sample
    let eval = |s: f64| touch_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    track(robot, &path, &options(SingularityDetection::Auto), criterion).unwrap()
}

/// Plain bisection of a scalar function with a sign change on [a, b].
fn root(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    assert!(f(a).signum() != f(b).signum());
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if f(m).signum() == f(a).signum() {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

fn beta(s: f64) -> f64 {
    (touch_r(s) / 2.0).min(1.0).acos()
}

fn position_violation(track: &ConfigurationTrack, joint: usize) -> (f64, f64) {
    let v = track
        .violations
        .iter()
        .find(|v| v.kind == ViolationKind::Position && v.joint == Some(joint))
        .unwrap_or_else(|| panic!("no violation of joint {joint}: {:?}", track.violations));
    (v.s_start, v.s_end)
}

#[test]
fn elbow_touch_splits_the_path_and_the_configuration_switches_only_there() {
    // A range of 0…100° for joint 2 makes elbow-down infeasible before the touch (q2 = e − β < 0)
    // and elbow-up infeasible after it (q2 = e + β > 100°): the arm must switch at s = 1.
    let robot = loader(100.0);
    let r = run(&robot, None);
    assert_eq!(r.solver, "yaw-two-link");
    assert_eq!(r.split_points.len(), 1, "{:?}", r.split_points);
    let split = &r.split_points[0];
    assert!((split.s - 1.0).abs() < 1e-6, "split at {}", split.s);
    assert!((split.t - 2.0).abs() < 2e-6);
    assert_eq!(split.kind, SplitKind::Singular(SingularityKind::Elbow));
    assert_eq!(r.intervals.len(), 2);
    let (first, second) = (&r.intervals[0], &r.intervals[1]);
    assert_eq!((first.chosen, first.decision), (Some(0), Decision::Default));
    assert_eq!((second.chosen, second.decision), (Some(1), Decision::OnlyFeasible));
    assert!(r.feasible);

    // Where the losing configurations break joint 2, against the plain formulas.
    let down_until = root(|s| touch_e(s) - beta(s), 0.0, 1.0);
    let (a, b) = position_violation(&first.configurations[1], 2);
    assert!(a == 0.0 && (b - down_until).abs() < 1e-8, "down breaks q2 ≥ 0 on [{a}, {b}], expected until {down_until}");
    let up_from = root(|s| touch_e(s) + beta(s) - 100f64.to_radians(), 1.0, 2.0);
    let (a, b) = position_violation(&second.configurations[0], 2);
    assert!((a - up_from).abs() < 1e-8 && b == 2.0, "up breaks q2 ≤ 100° on [{a}, {b}], expected from {up_from}");

    // The realised trajectory follows the formulas and switches configuration only at s = 1.
    for p in &r.trajectory {
        let (e, b) = (touch_e(p.s), beta(p.s));
        let (q2, q3) = if p.configuration == 0 { (e + b, -2.0 * b) } else { (e - b, 2.0 * b) };
        assert!((p.q[0] - YAW_DEG.to_radians()).abs() < 1e-9);
        assert!((p.q[1] - q2).abs() < 1e-6 && (p.q[2] - q3).abs() < 1e-6, "s={} q={:?}", p.s, p.q);
        assert_eq!(p.configuration, usize::from(p.s > split.s), "s = {}", p.s);
    }
    // Continuous through the switch: both configurations meet at the stretched arm.
    let k = r.trajectory.iter().position(|p| p.configuration == 1).unwrap();
    let (before, after) = (&r.trajectory[k - 1], &r.trajectory[k]);
    assert!((before.s - split.s).abs() < 1e-6, "the last point of interval 1 is the split");
    for j in 0..3 {
        assert!((after.q[j] - before.q[j]).abs() < 0.05, "joint {} jumps at the switch", j + 1);
    }

    // The log: K2 at the singular position between the two intervals' decisions.
    let codes: Vec<EventCode> = r.events.iter().map(|e| e.code).collect();
    let k2 = codes.iter().position(|c| *c == EventCode::K2).unwrap();
    assert_eq!(codes[k2 + 1], EventCode::K10);
    assert!(codes[..k2].contains(&EventCode::K9) && codes[k2..].contains(&EventCode::K9));
    assert_eq!(codes.last(), Some(&EventCode::K11));
    let k4 = r.events_with(EventCode::K4).last().unwrap();
    assert_eq!((k4.interval, k4.joint()), (Some(2), Some(1))); // joint 2, 0-based in the data
    let text = describe(k4, &robot, true);
    assert!(text.contains("switching to configuration \"base=front elbow=down\""), "{text}");
}

#[test]
fn each_configuration_is_followed_continuously_in_its_interval() {
    // Within an interval a configuration is never swapped for another branch: its samples
    // follow one formula (elbow-up in both intervals: the arm bounces off the stretched pose).
    let robot = loader(180.0);
    let r = run(&robot, None);
    assert_eq!(r.split_points.len(), 1);
    for interval in &r.intervals {
        let up = &interval.configurations[0];
        for (s, q) in up.s.iter().zip(&up.q) {
            let b = beta(*s);
            assert!((q[1] - (touch_e(*s) + b)).abs() < 1e-6 && (q[2] + 2.0 * b).abs() < 1e-6, "s={s}");
        }
    }
    // Interval 2: both feasible (K13); no criterion, so the default (elbow-up) is kept.
    let second = &r.intervals[1];
    assert!(second.configurations.iter().all(|c| c.feasible));
    assert_eq!((second.chosen, second.decision), (Some(0), Decision::Default));
    assert_eq!(r.events_with(EventCode::K13).count(), 1);
}

#[test]
fn a_user_criterion_chooses_among_feasible_configurations() {
    let robot = loader(180.0);
    // Smallest peak |q2| (e.g. a lower shoulder): elbow-down in interval 2.
    let peak_q2 = |t: &ConfigurationTrack| t.q.iter().map(|q| q[1].abs()).reduce(f64::max);
    let r = run(&robot, Some(&peak_q2));
    assert_eq!((r.intervals[0].chosen, r.intervals[0].decision), (Some(0), Decision::Default));
    assert_eq!((r.intervals[1].chosen, r.intervals[1].decision), (Some(1), Decision::Criterion));
    // A criterion no configuration satisfies: K14, the default is realised.
    let never = |_: &ConfigurationTrack| None;
    let r = run(&robot, Some(&never));
    assert_eq!((r.intervals[1].chosen, r.intervals[1].decision), (Some(0), Decision::CriterionRejected));
    let k14 = r.events_with(EventCode::K14).next().unwrap();
    assert_eq!(k14.interval, Some(2));
}

#[test]
fn jacobian_detection_finds_the_same_singular_position_on_a_sampled_path() {
    // Without an evaluator the path is interpolated between samples (chords of the curve):
    // the touch of the chord polygon is at the sample nearest s = 1 only if it reaches R = 2,
    // so sample s = 1 exactly (odd number of steps would miss it).
    let robot = loader(100.0);
    let samples = grid(touch_pose, 2.0, 100);
    let path = TrackedPath::sampled(&samples).unwrap();
    let r = track(&robot, &path, &options(SingularityDetection::Jacobian), None).unwrap();
    assert_eq!(r.split_points.len(), 1, "{:?}", r.split_points);
    assert!((r.split_points[0].s - 1.0).abs() < 1e-6);
    assert_eq!(r.intervals.len(), 2);
}

/// Out-and-back path: R(s) = 1.6 + 0.8·sin(πs) exceeds the 2 m reach for s ∈ (1/6, 5/6).
fn bulge_pose(s: f64) -> Isometry3<f64> {
    point(1.6 + 0.8 * (PI * s).sin(), 40f64.to_radians())
}

#[test]
fn leaving_the_workspace_midway_is_reported_not_a_panic() {
    let robot = loader(180.0);
    let samples = grid(bulge_pose, 1.0, 60);
    let eval = |s: f64| bulge_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    let r = track(&robot, &path, &options(SingularityDetection::Auto), None).unwrap();
    assert!(!r.feasible);
    let kinds: Vec<SplitKind> = r.split_points.iter().map(|p| p.kind).collect();
    assert_eq!(kinds, [SplitKind::Leaves, SplitKind::Enters]);
    assert!((r.split_points[0].s - 1.0 / 6.0).abs() < 1e-8, "{}", r.split_points[0].s);
    assert!((r.split_points[1].s - 5.0 / 6.0).abs() < 1e-8, "{}", r.split_points[1].s);
    assert_eq!(r.intervals.len(), 3);
    let middle = &r.intervals[1];
    assert!(!middle.reachable && middle.chosen.is_none());
    assert_eq!(middle.decision, Decision::NotRealizable);
    assert!((middle.s_start - 1.0 / 6.0).abs() < 1e-8 && (middle.s_end - 5.0 / 6.0).abs() < 1e-8);
    for i in [0, 2] {
        assert!(r.intervals[i].reachable && r.intervals[i].chosen == Some(0), "interval {}", i + 1);
    }
    // K1 when leaving and for the unreachable interval, K8 for it, K3 when re-entering.
    let k8 = r.events_with(EventCode::K8).next().unwrap();
    assert_eq!(k8.interval, Some(2));
    assert!(
        r.events_with(EventCode::K1)
            .any(|e| e.interval == Some(2) && describe(e, &robot, true).contains("(0.166667, 0.833333)"))
    );
    assert!(r.events_with(EventCode::K3).any(|e| (e.s - 5.0 / 6.0).abs() < 1e-8));
    // The realised trajectory covers the two reachable intervals only.
    assert!(r.trajectory.iter().all(|p| p.s <= 1.0 / 6.0 + 1e-8 || p.s >= 5.0 / 6.0 - 1e-8));
}

#[test]
fn a_path_entirely_out_of_reach_is_one_unrealisable_interval() {
    let robot = loader(180.0);
    let far = |s: f64| point(3.0 + s, 0.3);
    let samples = grid(far, 1.0, 10);
    let path = TrackedPath::with_evaluator(&samples, &far).unwrap();
    let r = track(&robot, &path, &options(SingularityDetection::Auto), None).unwrap();
    assert_eq!(r.intervals.len(), 1);
    assert_eq!(r.intervals[0].decision, Decision::NotRealizable);
    assert!(r.trajectory.is_empty() && !r.feasible);
}

#[test]
fn bad_paths_are_rejected_with_the_field_named() {
    let robot = loader(180.0);
    let mut samples = grid(touch_pose, 2.0, 10);
    samples[3].s = f64::NAN;
    let err = TrackedPath::sampled(&samples).unwrap_err();
    assert_eq!(err, TrackingError::NonFinite { index: 3, field: "s" });
    let mut samples = grid(touch_pose, 2.0, 10);
    samples[5].t = samples[4].t;
    let err = TrackedPath::sampled(&samples).unwrap_err().to_string();
    assert!(err.contains("sample 5") && err.contains("`t`"), "{err}");
    assert!(matches!(TrackedPath::sampled(&samples[..1]), Err(TrackingError::TooFewSamples { found: 1 })));
    // An evaluator that returns NaN between samples: an error, not a panic.
    let samples = grid(touch_pose, 2.0, 149);
    let bad = |s: f64| if (s - 1.0).abs() < 0.05 { point(f64::NAN, 0.0) } else { touch_pose(s) };
    let path = TrackedPath::with_evaluator(&samples, &bad).unwrap();
    let err = track(&robot, &path, &options(SingularityDetection::Auto), None).unwrap_err();
    assert!(matches!(err, TrackingError::Evaluator { .. }), "{err}");
    // A default configuration index beyond the list.
    let path = TrackedPath::sampled(&samples).unwrap();
    let opts = TrackingOptions { default_configuration: 2, ..options(SingularityDetection::Auto) };
    assert!(matches!(track(&robot, &path, &opts, None), Err(TrackingError::InvalidOption { .. })));
}

#[test]
fn a_speed_limit_is_located_where_the_rate_crosses_it() {
    // q3 = ∓2β and t = 2s, so |q̇3| = |dβ/ds| = (|R'|/2)/√(1 − R²/4) with R' = −(s − 1):
    // 0.756 rad/s at s = 0 falling to 1/√2 at the touch. A 0.73 rad/s limit is broken from the
    // start to where |dβ/ds| = 0.73, in both configurations: interval 1 is not realizable.
    let mut spec = loader(180.0).spec().clone();
    spec.joints[2].max_velocity = Some(0.73);
    let robot = Robot::new(spec).unwrap();
    let r = run(&robot, None);
    let rate = |s: f64| {
        let (rr, dr) = (touch_r(s), -(s - 1.0));
        (dr.abs() / 2.0) / (1.0 - rr * rr / 4.0).sqrt()
    };
    let until = root(|s| rate(s) - 0.73, 0.0, 0.9);
    let first = &r.intervals[0];
    assert_eq!(first.decision, Decision::NotRealizable);
    for c in &first.configurations {
        let v = c.violations.iter().find(|v| v.kind == ViolationKind::Velocity).expect("speed violation");
        assert_eq!(v.joint, Some(3));
        assert_eq!(v.s_start, 0.0);
        assert!((v.s_end - until).abs() < 1e-6, "{} vs {until}", v.s_end);
        assert!((v.worst.abs() - rate(0.0)).abs() < 0.01, "worst {}", v.worst);
    }
    // Joint 3: index 2 in the data.
    assert!(r.events_with(EventCode::K5).any(|e| e.interval == Some(1) && e.joint() == Some(2)));
    assert!(r.events_with(EventCode::K12).any(|e| e.interval == Some(1) && e.joint() == Some(2)));
    assert!(r.events_with(EventCode::K8).any(|e| e.interval == Some(1)));
}

#[test]
fn the_numeric_solver_follows_a_redundant_arm_continuously() {
    // Panda (7 joints, no closed form): one configuration, followed by nearness with the
    // previous joint vector as seed. The realised trajectory reproduces every sampled pose and
    // moves each joint by small steps only.
    let panda = presets::get("panda").unwrap();
    let q0 = [0.3, -0.2, 0.1, -2.0, 0.2, 1.8, 0.5];
    let start = panda.fk(&q0).unwrap();
    let line = |s: f64| {
        Isometry3::from_parts(
            Translation3::from(start.translation.vector + Vector3::new(0.0, 0.1, 0.05) * s),
            start.rotation,
        )
    };
    let samples = grid(line, 1.0, 20);
    let path = TrackedPath::with_evaluator(&samples, &line).unwrap();
    let r = track(&panda, &path, &TrackingOptions::default(), None).unwrap();
    assert_eq!(r.solver, "numeric");
    assert!(r.feasible, "{:?}", r.intervals.iter().map(|i| i.decision).collect::<Vec<_>>());
    assert_eq!(r.trajectory.len(), samples.len());
    for (p, sample) in r.trajectory.iter().zip(&samples) {
        let pose = panda.fk(&p.q).unwrap();
        assert!((pose.translation.vector - sample.pose.translation.vector).norm() < 1e-6);
        assert!(pose.rotation.angle_to(&sample.pose.rotation) < 1e-6);
    }
    for w in r.trajectory.windows(2) {
        let step = w[0].q.iter().zip(&w[1].q).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
        assert!(step < 0.1, "joint step {step} at s = {}", w[1].s);
    }
}

/// Tracks `path` with and without the progress hook; checks the calls (one total, reached once
/// as the last call, `done` increasing, one call per chunk at most) and that the reports agree.
fn check_progress(robot: &Robot, path: &TrackedPath<'_>, options: &TrackingOptions) -> TrackingReport {
    let calls = RefCell::new(Vec::<(usize, usize)>::new());
    let hooked =
        track_with_progress(robot, path, options, None, &|done, total| calls.borrow_mut().push((done, total))).unwrap();
    let plain = track(robot, path, options, None).unwrap();
    assert_eq!(hooked, plain, "the hook changed the report");
    let calls = calls.into_inner();
    let n = path.samples().len();
    let total = 2 * n * hooked.configurations.len();
    assert!(calls.iter().all(|&(_, t)| t == total), "total is 2·n·m = {total}: {calls:?}");
    assert_eq!(calls.last(), Some(&(total, total)), "{calls:?}");
    assert_eq!(calls.iter().filter(|&&(d, _)| d == total).count(), 1, "total reached once: {calls:?}");
    assert!(calls.windows(2).all(|w| w[0].0 < w[1].0), "monotone: {calls:?}");
    assert!(
        calls.windows(2).all(|w| w[1].0 - w[0].0 >= TRACKING_PROGRESS_CHUNK || w[1].0 == total),
        "chunks: {calls:?}"
    );
    // The phases add up: the last report before the total is within a chunk of it.
    assert!(calls.len() >= 2 && total - calls[calls.len() - 2].0 < TRACKING_PROGRESS_CHUNK, "{calls:?}");
    // Per chunk, not per sample: several reports on a long path, but far fewer than samples.
    assert!(calls.len() >= total / TRACKING_PROGRESS_CHUNK / 2, "{} calls for {total} units", calls.len());
    assert!(calls.len() <= total / TRACKING_PROGRESS_CHUNK + 1, "{} calls for {total} units", calls.len());
    hooked
}

#[test]
fn progress_reaches_the_total_once_and_leaves_the_report_unchanged() {
    // Three intervals, the middle one out of reach (its samples are counted at once).
    let robot = loader(180.0);
    let samples = grid(bulge_pose, 1.0, 2999);
    let eval = |s: f64| bulge_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    let r = check_progress(&robot, &path, &options(SingularityDetection::Auto));
    assert_eq!(r.intervals.len(), 3);
    assert!(!r.intervals[1].reachable);
    // Two intervals split at a singular position, the configuration switching there.
    let robot = loader(100.0);
    let samples = grid(touch_pose, 2.0, 1999);
    let eval = |s: f64| touch_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    let r = check_progress(&robot, &path, &options(SingularityDetection::Auto));
    assert_eq!(r.intervals.len(), 2);
    // Default configurations (every label of the first reachable sample) and a short path:
    // a single report, the total.
    let samples = grid(touch_pose, 2.0, 20);
    let path = TrackedPath::sampled(&samples).unwrap();
    let calls = RefCell::new(Vec::new());
    let options = TrackingOptions { position_only: true, ..Default::default() };
    let r = track_with_progress(&robot, &path, &options, None, &|d, t| calls.borrow_mut().push((d, t))).unwrap();
    let total = 2 * 21 * r.configurations.len();
    assert_eq!(calls.into_inner(), [(total, total)]);
}

/// A set cancel flag stops the tracking between samples (Ctrl-C in the CLI): the tracker
/// returns `Cancelled`, and so does a tool-space move of the jobs layer given the flag.
#[test]
fn a_cancelled_tracking_stops() {
    let robot = loader(100.0);
    let samples = grid(touch_pose, 2.0, 149);
    let eval = |s: f64| touch_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    let cancel = reach::Cancel::new();
    let opts = TrackingOptions { cancel: cancel.clone(), ..options(SingularityDetection::Auto) };
    assert!(track(&robot, &path, &opts, None).is_ok(), "not cancelled yet");
    cancel.cancel();
    assert!(matches!(track(&robot, &path, &opts, None), Err(TrackingError::Cancelled)));

    use reach::jobs::motion::{End, MoveRequest, Space, move_motion_with_progress};
    use reach::jobs::{Joints, Pose};
    let weld = MoveRequest {
        from: End::Pose(Pose::xyz_rpy_deg([0.05, 0.74, 0.07], [0.0, -41.86854343693031, -50.19442890773481])),
        to: End::Pose(Pose::xyz_rpy_deg([0.5, 0.2, 0.7], [0.0, -41.86854343693031, -50.19442890773481])),
        space: Space::Tool,
        duration_s: Some(10.0),
        ..MoveRequest::joints(Joints::Deg(Vec::new()), Joints::Deg(Vec::new()))
    };
    let welder = presets::get("welder6r").unwrap();
    let e = move_motion_with_progress(&welder, &weld, &mut |_, _| {}, &cancel).unwrap_err();
    assert!(matches!(e, reach::Error::Tracking(TrackingError::Cancelled)), "{e}");
    assert!(move_motion_with_progress(&welder, &weld, &mut |_, _| {}, &reach::Cancel::default()).is_ok());
}

/// Seed 003's dialogue: where both configurations of the welder are feasible (the first
/// 300 mm of the weld, before −β's θ4 leaves its range at s = 618 mm), the report offers both
/// as alternatives and realises the default (+β); the operator's choice of the other one is
/// realised instead (decision `operator`), its samples reach the same tool poses in another
/// branch. A choice of a configuration that is not feasible, or of an interval that does not
/// exist, is refused with a message naming it.
#[test]
fn the_operator_chooses_a_feasible_configuration_per_interval() {
    use reach::jobs::motion::{End, IntervalChoice, MoveRequest, Space, move_motion};
    use reach::jobs::{Joints, Pose};
    use reach::motion::tracking::Decision;
    let rpy = [0.0, -41.86854343693031, -50.19442890773481];
    let (p, m) = (Vector3::new(0.05, 0.74, 0.07), Vector3::new(0.5, 0.2, 0.7));
    let at = |s: f64| p + (m - p).normalize() * s;
    let request = |to: Vector3<f64>, choices: Vec<IntervalChoice>| MoveRequest {
        from: End::Pose(Pose::xyz_rpy_deg(p.into(), rpy)),
        to: End::Pose(Pose::xyz_rpy_deg(to.into(), rpy)),
        space: Space::Tool,
        duration_s: Some(30.0),
        choices,
        ..MoveRequest::joints(Joints::Deg(Vec::new()), Joints::Deg(Vec::new()))
    };
    let welder = presets::get("welder6r").unwrap();
    let auto = move_motion(&welder, &request(at(0.3), Vec::new())).unwrap();
    assert!(auto.feasible);
    assert_eq!(auto.intervals.len(), 1);
    let interval = &auto.intervals[0];
    assert_eq!(interval.alternatives.len(), 2, "{interval:?}");
    assert_eq!(interval.decision, Some(Decision::Default));
    assert_eq!(interval.configuration.as_ref(), Some(&interval.alternatives[0]));
    let other = interval.alternatives[1].clone();
    let chosen =
        move_motion(&welder, &request(at(0.3), vec![IntervalChoice { interval: 1, configuration: other.clone() }]))
            .unwrap();
    assert!(chosen.feasible);
    assert_eq!(chosen.intervals[0].decision, Some(Decision::Operator));
    assert_eq!(chosen.intervals[0].configuration.as_ref(), Some(&other));
    // Same tool path, another branch: the joints differ, FK of each sample is the sample's pose.
    let (a, b) = (&auto.samples[10], &chosen.samples[10]);
    assert!(a.q_deg.iter().zip(&b.q_deg).any(|(x, y)| (x - y).abs() > 1.0), "{a:?} {b:?}");
    for s in [a, b] {
        let q: Vec<f64> = s.q_deg.iter().map(|d| d.to_radians()).collect();
        let t = welder.fk(&q).unwrap().translation.vector;
        assert!((t - Vector3::from(s.xyz_m)).norm() < 1e-9);
        assert!((t - Vector3::from(a.xyz_m)).norm() < 1e-6, "both branches put the tool at the same point");
    }
    // Over the whole weld −β is infeasible (θ4, notes 003 §5.2): choosing it is refused.
    let whole = request(m, vec![IntervalChoice { interval: 1, configuration: other.clone() }]);
    let e = move_motion(&welder, &whole).unwrap_err().to_string();
    assert!(e.contains("choices") && e.contains(&format!("`{other}` is not feasible")), "{e}");
    let e = move_motion(&welder, &request(at(0.3), vec![IntervalChoice { interval: 2, configuration: other }]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("interval 2 does not exist"), "{e}");
    let e = move_motion(
        &welder,
        &request(at(0.3), vec![IntervalChoice { interval: 1, configuration: "elbow sideways".into() }]),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("no configuration `elbow sideways`"), "{e}");
}

#[test]
fn a_start_joint_vector_pins_the_first_interval_to_its_branch() {
    // Where the arm is, at s = 0: elbow-down, which is not the default (elbow-up).
    let (e, b) = (touch_e(0.0), beta(0.0));
    let down = vec![YAW_DEG.to_radians(), e - b, 2.0 * b];
    let samples = grid(touch_pose, 2.0, 149);
    let eval = |s: f64| touch_pose(s);
    let path = TrackedPath::with_evaluator(&samples, &eval).unwrap();
    let with_start = |start: Vec<f64>| TrackingOptions { start: Some(start), ..options(SingularityDetection::Auto) };
    // Joint 2 from −90° to 180°: both configurations feasible in interval 1; the start's is
    // realised, from the start itself.
    let mut spec = loader(180.0).spec().clone();
    spec.joints[1].limits.lower = -FRAC_PI_2;
    let robot = Robot::new(spec).unwrap();
    let free = track(&robot, &path, &options(SingularityDetection::Auto), None).unwrap();
    assert_eq!((free.intervals[0].chosen, free.intervals[0].decision), (Some(0), Decision::Default));
    let r = track(&robot, &path, &with_start(down.clone()), None).unwrap();
    assert_eq!((r.intervals[0].chosen, r.intervals[0].decision), (Some(1), Decision::Start));
    assert_eq!(r.trajectory[0].q, down, "the trajectory starts where the arm is");
    for p in r.trajectory.iter().filter(|p| p.s < 1.0 - 1e-6) {
        let (e, b) = (touch_e(p.s), beta(p.s));
        assert!((p.q[1] - (e - b)).abs() < 1e-6 && (p.q[2] - 2.0 * b).abs() < 1e-6, "elbow-down at s = {}", p.s);
    }
    // Joint 2 from 0° to 100°: elbow-down breaks q2 ≥ 0 in interval 1. From an elbow-down start the
    // interval is not realisable — the arm does not jump to elbow-up, which is feasible there.
    let robot = loader(100.0);
    let r = track(&robot, &path, &with_start(down.clone()), None).unwrap();
    assert_eq!((r.intervals[0].chosen, r.intervals[0].decision), (None, Decision::NotRealizable));
    assert!(r.intervals[0].configurations[0].feasible && !r.intervals[0].configurations[1].feasible);
    assert!(!r.feasible);
    // Bad starts, the option named.
    let invalid = |start: Vec<f64>, configurations: Vec<Branch>| {
        let mut o = with_start(start);
        if !configurations.is_empty() {
            o.configurations = configurations;
        }
        match track(&robot, &path, &o, None) {
            Err(TrackingError::InvalidOption { option: "start", reason }) => reason,
            other => panic!("expected a `start` error, got {other:?}"),
        }
    };
    assert!(invalid(vec![0.0; 2], Vec::new()).contains("2 joint values for a robot with 3 joints"));
    assert!(invalid(vec![0.5, f64::NAN, 0.0], Vec::new()).contains("joint 2 must be finite"));
    assert!(invalid(vec![0.5, 0.2, 0.1], Vec::new()).contains("from the path's first pose"));
    let only_up = vec![configurations()[0].clone()];
    let reason = invalid(down.clone(), only_up);
    assert!(reason.contains("elbow=down") && reason.contains("not among the tracked ones"), "{reason}");
    // The operator cannot name another configuration for interval 1.
    let mut o = with_start(down);
    o.choices.insert(1, "base=front elbow=up".into());
    let robot = loader(180.0);
    assert!(matches!(track(&robot, &path, &o, None), Err(TrackingError::InvalidOption { option: "choices", .. })));
}
