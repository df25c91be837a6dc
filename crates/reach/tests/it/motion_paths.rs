//! Joint-space and tool-space motions: the wrap policy, IK at the ends, waypoints, the
//! rotation axis at φ1 ≈ 0 and φ1 ≈ π, constant-speed paths (seed 003 §5), arc-length
//! sampling, and the per-sample IK.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};
use reach::Robot;
use reach::model::{Convention, Joint, RobotSpec, presets};
use reach::motion::joint_space::EndChoice;
use reach::motion::sample::PerSampleIk;
use reach::motion::{JointMotion, JointPath, MotionError, Profile, ToolMotion};

/// Two revolute joints: joint 1 continuous, joint 2 limited to [0, 2π].
fn two_joint_robot() -> Robot {
    let spec = RobotSpec::new(
        "two",
        Convention::Dh,
        vec![Joint::revolute(1.0, 0.0, 0.0, 0.0), Joint::revolute(1.0, 0.0, 0.0, 0.0).with_limits(0.0, TAU)],
    );
    Robot::new(spec).unwrap()
}

/// Continuous joints take the short way; limited ones the literal way, staying in range.
#[test]
fn wrap_policy_short_way_only_for_continuous_joints() {
    let robot = two_joint_robot();
    let m = JointMotion::for_robot(&robot, &[3.0, 6.0], &[-3.0, 0.2], 0.0, 1.0, Profile::Cycloidal).unwrap();
    assert!((m.delta()[0] - (TAU - 6.0)).abs() < 1e-12); // 3 → −3 through π: +0.283 rad
    assert!((m.delta()[1] + 5.8).abs() < 1e-12); // 6 → 0.2 the long way, inside [0, 2π]
    let traj = m.sample(0.01).unwrap();
    assert!(traj.samples.iter().all(|s| s.q[1] >= 0.2 - 1e-12 && s.q[1] <= 6.0 + 1e-12));
    assert!(traj.samples.iter().all(|s| s.within_limits));
    let end = m.end();
    assert!((end[0] - (3.0 + TAU - 6.0)).abs() < 1e-12 && (end[1] - 0.2).abs() < 1e-12);
    // The plain constructor is literal for every joint.
    let plain = JointMotion::new(&[3.0, 6.0], &[-3.0, 0.2], 0.0, 1.0, Profile::Cycloidal).unwrap();
    assert!((plain.delta()[0] + 6.0).abs() < 1e-12);
    // An end outside the limits is flagged.
    let out = JointMotion::for_robot(&robot, &[0.0, 1.0], &[0.0, 7.0], 0.0, 1.0, Profile::Linear).unwrap();
    assert!(!out.within_limits());
}

/// q̇ and q̈ are the derivatives of q (central differences), with t0 ≠ 0.
#[test]
fn joint_velocity_and_acceleration_are_derivatives() {
    for profile in [Profile::Cycloidal, Profile::Quintic, Profile::Trapezoidal { accel_fraction: 0.3 }] {
        let m = JointMotion::new(&[0.1, -0.4, 2.0], &[1.1, 0.6, -1.0], 2.0, 3.0, profile).unwrap();
        assert_eq!(m.position(2.0), vec![0.1, -0.4, 2.0]);
        assert_eq!(m.position(1.0), vec![0.1, -0.4, 2.0]); // rests before t0
        assert!(m.position(5.0).iter().zip([1.1, 0.6, -1.0]).all(|(a, b)| (a - b).abs() < 1e-15));
        assert!(m.velocity(2.0).iter().chain(&m.velocity(5.0)).all(|v| v.abs() < 1e-12));
        let h = 1e-5;
        for t in [2.37, 3.1, 3.77, 4.52] {
            let (qp, qm) = (m.position(t + h), m.position(t - h));
            let (vp, vm) = (m.velocity(t + h), m.velocity(t - h));
            for i in 0..3 {
                assert!((m.velocity(t)[i] - (qp[i] - qm[i]) / (2.0 * h)).abs() < 1e-7, "{profile:?} t={t}");
                assert!((m.acceleration(t)[i] - (vp[i] - vm[i]) / (2.0 * h)).abs() < 1e-5, "{profile:?} t={t}");
            }
        }
    }
}

#[test]
fn bad_joint_input_is_an_error() {
    let robot = two_joint_robot();
    assert!(matches!(
        JointMotion::for_robot(&robot, &[0.0], &[0.0, 1.0], 0.0, 1.0, Profile::Linear),
        Err(MotionError::Length { .. })
    ));
    let e = JointMotion::new(&[0.0, f64::NAN], &[0.0, 1.0], 0.0, 1.0, Profile::Linear).unwrap_err();
    assert!(e.to_string().contains("q0[2]"), "{e}");
    assert!(JointMotion::new(&[0.0], &[1.0], 0.0, 0.0, Profile::Linear).is_err());
    assert!(JointMotion::new(&[0.0], &[1.0], f64::INFINITY, 1.0, Profile::Linear).is_err());
    let m = JointMotion::new(&[0.0], &[1.0], 0.0, 1.0, Profile::Linear).unwrap();
    assert!(m.sample(0.0).is_err());
    let mut out = [0.0; 2];
    assert!(m.position_into(0.5, &mut out).is_err());
}

/// Between two poses of the PUMA: the ends reproduce the poses and, with the start's own
/// configuration as reference, the start is that configuration.
#[test]
fn between_poses_solves_both_ends() {
    let puma = presets::get("puma560").unwrap();
    let qa = [0.2, 0.5, -0.4, 0.3, 0.6, -0.2];
    let qb = [0.7, 0.3, -0.1, -0.4, 0.9, 0.5];
    let (pa, pb) = (puma.fk(&qa).unwrap(), puma.fk(&qb).unwrap());
    let choice = EndChoice { reference: Some(qa.to_vec()), ..EndChoice::default() };
    let m = JointMotion::between_poses(&puma, &pa, &pb, 1.0, 2.0, Profile::Quintic, &choice).unwrap();
    assert!(m.start().iter().zip(&qa).all(|(a, b)| (a - b).abs() < 1e-9));
    // The end is the solution closest to the start: qb itself (the others flip a branch).
    assert!(m.end().iter().zip(&qb).all(|(a, b)| (a - b).abs() < 1e-9), "{:?}", m.end());
    let end_pose = puma.fk(&m.position(3.0)).unwrap();
    assert!((end_pose.to_homogeneous() - pb.to_homogeneous()).amax() < 1e-9);
    // Unreachable end: a typed error naming it.
    let far = Isometry3::translation(5.0, 0.0, 0.0);
    match JointMotion::between_poses(&puma, &pa, &far, 0.0, 1.0, Profile::Quintic, &choice) {
        Err(MotionError::NoIkSolution { which, .. }) => assert_eq!(which, "end pose"),
        other => panic!("{other:?}"),
    }
}

/// Waypoints: each segment starts and ends at its waypoints, at rest, at the summed times.
#[test]
fn waypoints_are_reached_at_rest() {
    let planar3 = presets::get("planar3").unwrap();
    let w = vec![vec![0.0, 0.0, 0.0], vec![0.5, 0.2, -0.1], vec![0.5, -0.2, 0.3], vec![-0.3, 0.1, 0.0]];
    let durations = [1.0, 2.0, 0.5];
    let path = JointPath::through(&planar3, &w, &durations, 1.0, Profile::Cycloidal).unwrap();
    assert_eq!(path.segments().len(), 3);
    assert!((path.duration() - 3.5).abs() < 1e-15);
    let mut t = 1.0;
    for (k, d) in durations.iter().enumerate() {
        let q = path.position(t);
        assert!(q.iter().zip(&w[k]).all(|(a, b)| (a - b).abs() < 1e-12), "waypoint {k} at t = {t}");
        assert!(path.velocity(t).iter().all(|v| v.abs() < 1e-12));
        t += d;
    }
    assert!(path.position(t).iter().zip(&w[3]).all(|(a, b)| (a - b).abs() < 1e-12));
    let traj = path.sample(0.25).unwrap();
    assert_eq!(traj.samples.len(), 15);
    assert!(JointPath::through(&planar3, &w, &[1.0], 0.0, Profile::Linear).is_err());
    assert!(JointPath::through(&planar3, &w[..1], &[], 0.0, Profile::Linear).is_err());
    assert!(JointPath::through(&planar3, &w, &[1.0, -1.0, 1.0], 0.0, Profile::Linear).is_err());
}

fn rot(axis: [f64; 3], angle: f64) -> UnitQuaternion<f64> {
    UnitQuaternion::from_axis_angle(&Unit::new_normalize(Vector3::new(axis[0], axis[1], axis[2])), angle)
}

/// φ1 = 0: a pure translation; the orientation never changes.
#[test]
fn tool_motion_without_rotation() {
    let r = rot([0.3, -0.2, 0.9], 0.7);
    let a = Isometry3::from_parts(Translation3::new(0.1, 0.2, 0.3), r);
    let b = Isometry3::from_parts(Translation3::new(0.4, -0.2, 0.3), r);
    let m = ToolMotion::new(a, b, 0.0, 2.0, Profile::Quintic).unwrap();
    assert_eq!(m.angle(), 0.0);
    for k in 0..=10 {
        let p = m.pose_at(0.2 * f64::from(k));
        assert!(p.rotation.angle_to(&r) < 1e-12);
    }
    // Identical poses: a motion that rests.
    let still = ToolMotion::new(a, a, 0.0, 1.0, Profile::Cycloidal).unwrap();
    assert_eq!((still.angle(), still.length()), (0.0, 0.0));
    assert!((still.pose_at(0.5).to_homogeneous() - a.to_homogeneous()).amax() < 1e-15);
    assert!(still.sample_length(0.01).is_err());
}

/// φ1 = π and φ1 = π − 1e-10: the end pose is reached, and half-way the tool has turned by
/// φ1/2 about the rotation axis (either sign of the axis is a valid half-turn at exactly π).
#[test]
fn tool_motion_near_a_half_turn() {
    let start = Isometry3::from_parts(Translation3::new(0.5, 0.0, 0.2), rot([0.1, 0.2, 0.3], 0.4));
    let axis = [1.0, -2.0, 0.5];
    for angle in [PI, PI - 1e-10, PI - 1e-6] {
        let end = Isometry3::from_parts(Translation3::new(0.5, 0.0, 0.2), start.rotation * rot(axis, angle));
        let m = ToolMotion::new(start, end, 0.0, 1.0, Profile::Cycloidal).unwrap();
        assert!((m.angle() - angle).abs() < 1e-9, "{angle}");
        let e = Unit::new_normalize(Vector3::new(axis[0], axis[1], axis[2]));
        let dot = m.axis().dot(&e);
        assert!((dot.abs() - 1.0).abs() < 1e-9, "{angle}: {dot}");
        if angle < PI {
            assert!(dot > 0.0, "the axis keeps its sign below π");
        }
        assert!((m.pose_at(1.0).to_homogeneous() - end.to_homogeneous()).amax() < 1e-12);
        let half = start.rotation * UnitQuaternion::from_axis_angle(&m.axis(), angle / 2.0);
        assert!(m.pose_at(0.5).rotation.angle_to(&half) < 1e-9);
        // Sampling never produces NaN.
        let path = m.sample_time(0.05).unwrap();
        assert!(path.samples.iter().all(|s| s.pose.rotation.coords.iter().all(|v| v.is_finite())));
    }
}

/// Seed 003 §5.1–5.2: the weld from P = (50, 740, 70) mm to M = (500, 200, 700) mm at
/// 1 mm/s: |MP| = 943.927963 mm, so 943.928 s; sampled every 100 mm of seam, each sample is
/// at `t = s / v` and on the line.
#[test]
fn seed003_weld_at_one_millimetre_per_second() {
    let p = Vector3::new(0.050, 0.740, 0.070);
    let q = Vector3::new(0.500, 0.200, 0.700);
    let a = Isometry3::from_parts(Translation3::from(p), UnitQuaternion::identity());
    let b = Isometry3::from_parts(Translation3::from(q), UnitQuaternion::identity());
    let m = ToolMotion::at_speed(a, b, 0.0, 0.001).unwrap();
    assert!((m.length() - 0.943_927_963).abs() < 1e-9);
    assert!((m.duration() - 943.927_963).abs() < 1e-6);
    let path = m.sample_length(0.1).unwrap();
    assert_eq!(path.samples.len(), 11); // 0, 0.1, …, 0.9, 0.9439
    let n = (q - p).normalize();
    for (k, s) in path.samples.iter().enumerate() {
        let want_s = if k == 10 { m.length() } else { 0.1 * k as f64 };
        assert!((s.s - want_s).abs() < 1e-12);
        assert!((s.t - s.s / 0.001).abs() < 1e-9);
        assert!((s.pose.translation.vector - (p + n * s.s)).norm() < 1e-12);
        assert!((m.pose_at_length(s.s).to_homogeneous() - s.pose.to_homogeneous()).amax() < 1e-12);
    }
    // Constant speed: 1 mm/s everywhere.
    let (v, w) = m.velocity_at(100.0);
    assert!((v.norm() - 0.001).abs() < 1e-15 && w.norm() == 0.0);
    assert!(ToolMotion::at_speed(a, a, 0.0, 0.001).is_err());
    assert!(ToolMotion::at_speed(a, b, 0.0, 0.0).is_err());
}

/// Arc-length sampling of a non-linear profile inverts λ: λ((t − t0)/T)·L = s at every sample.
#[test]
fn arc_length_sampling_inverts_the_profile() {
    let a = Isometry3::from_parts(Translation3::new(0.0, 0.0, 0.0), rot([0.0, 0.0, 1.0], 0.0));
    let b = Isometry3::from_parts(Translation3::new(1.0, 1.0, 0.0), rot([0.0, 0.0, 1.0], FRAC_PI_2));
    let m = ToolMotion::new(a, b, 3.0, 4.0, Profile::Cycloidal).unwrap();
    let path = m.sample_length(0.05).unwrap();
    assert_eq!(path.samples.len(), 30); // √2 / 0.05 = 28.28 → 29 steps + the end
    for s in &path.samples {
        let lambda = Profile::Cycloidal.position((s.t - 3.0) / 4.0);
        assert!((lambda * m.length() - s.s).abs() < 1e-9, "t = {}", s.t);
        assert!((s.angle - lambda * FRAC_PI_2).abs() < 1e-9);
    }
    assert_eq!(path.samples.last().unwrap().t, 7.0);
}

/// Per-sample IK along a PUMA tool path: every sample's FK is its pose, and consecutive
/// samples stay close (the closest solution is taken each time).
#[test]
fn per_sample_ik_follows_the_path() {
    let puma = presets::get("puma560").unwrap();
    let q0 = [0.1, 0.7, -0.5, 0.4, 0.8, -0.3];
    let start = puma.fk(&q0).unwrap();
    let end = Isometry3::from_parts(
        Translation3::from(start.translation.vector + Vector3::new(-0.1, 0.15, -0.05)),
        start.rotation * rot([0.2, 1.0, -0.3], 0.5),
    );
    let m = ToolMotion::new(start, end, 0.0, 2.0, Profile::Quintic).unwrap();
    let path = m.sample_time(0.02).unwrap();
    let options = PerSampleIk { start: Some(q0.to_vec()), ..PerSampleIk::default() };
    let traj = path.to_joints(&puma, &options).unwrap();
    assert_eq!(traj.samples.len(), path.samples.len());
    for (s, j) in path.samples.iter().zip(&traj.samples) {
        assert_eq!(s.t, j.t);
        assert!((puma.fk(&j.q).unwrap().to_homogeneous() - s.pose.to_homogeneous()).amax() < 1e-6);
    }
    for pair in traj.samples.windows(2) {
        let step = pair[0].q.iter().zip(&pair[1].q).map(|(a, b)| reach::angle::wrap(b - a).abs()).fold(0.0, f64::max);
        assert!(step < 0.1, "jump of {step} rad between t = {} and {}", pair[0].t, pair[1].t);
    }
    let bad = PerSampleIk { start: Some(vec![0.0; 5]), ..PerSampleIk::default() };
    assert!(matches!(path.to_joints(&puma, &bad), Err(MotionError::Length { .. })));
}

/// The smooth path: through every waypoint, C¹ (velocity continuous across waypoints), at rest
/// at both ends, and monotone between waypoints (no overshoot; a reversing joint stops).
#[test]
fn smooth_path_is_c1_and_does_not_overshoot() {
    use reach::motion::SmoothJointPath;
    let planar3 = presets::get("planar3").unwrap();
    let w = vec![vec![0.0, 0.0, 0.0], vec![0.5, 0.4, -0.1], vec![0.6, -0.2, 0.3], vec![1.2, 0.1, 0.3]];
    let durations = [1.0, 0.5, 2.0];
    let path = SmoothJointPath::through(&planar3, &w, &durations, 2.0).unwrap();
    assert!((path.duration() - 3.5).abs() < 1e-15);
    let knots = [2.0, 3.0, 3.5, 5.5];
    for (k, &t) in knots.iter().enumerate() {
        assert!(path.position(t).iter().zip(&w[k]).all(|(a, b)| (a - b).abs() < 1e-12), "waypoint {k}");
        let (before, after) = (path.velocity(t - 1e-9), path.velocity(t + 1e-9));
        if k > 0 && k < 3 {
            assert!(before.iter().zip(&after).all(|(a, b)| (a - b).abs() < 1e-6), "velocity jumps at {k}");
        }
    }
    assert!(path.velocity(2.0).iter().chain(&path.velocity(5.5)).all(|v| v.abs() < 1e-12));
    // Joint 1 keeps moving through waypoint 2 (0.5 → 0.6 → 1.2); joint 2 reverses (0.4 → −0.2) and stops.
    assert!(path.velocity(3.0)[0] > 0.1);
    assert!(path.velocity(3.0)[1].abs() < 1e-12);
    // Velocity is the derivative of position; no joint leaves the range of its two waypoints.
    let h = 1e-6;
    for i in 0..=700 {
        let t = 2.0 + 3.5 * f64::from(i) / 700.0;
        let q = path.position(t);
        let seg = knots.windows(2).position(|p| t <= p[1]).unwrap_or(2);
        for j in 0..3 {
            let (lo, hi) = (w[seg][j].min(w[seg + 1][j]), w[seg][j].max(w[seg + 1][j]));
            assert!(q[j] >= lo - 1e-12 && q[j] <= hi + 1e-12, "t = {t}, joint {j}: {} ∉ [{lo}, {hi}]", q[j]);
            if t > 2.0 + h && t < 5.5 - h && knots.iter().all(|k| (t - k).abs() > 2.0 * h) {
                let fd = (path.position(t + h)[j] - path.position(t - h)[j]) / (2.0 * h);
                assert!((path.velocity(t)[j] - fd).abs() < 1e-6, "t = {t}");
            }
        }
    }
    assert_eq!(path.sample(0.5).unwrap().samples.len(), 8);
    assert!(SmoothJointPath::through(&planar3, &w, &[1.0, 1.0], 0.0).is_err());
}
