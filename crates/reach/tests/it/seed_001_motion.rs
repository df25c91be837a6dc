//! Seed 001 (Vodolaga 2021): joint-space and tool-space motion between T0 and T1 over
//! t ∈ [0, 10] with step 0.1, and the energy functionals J1/J2 (notes 001 §3.6–3.8, §4.3–4.4,
//! §5.1–5.2, §6).
//!
//! # What is asserted
//!
//! * the tool-space path: `e = (1, −1, 1)/√3` in the T0 tool frame, `φ1 = 120°`,
//!   `ρ(t1) = (0, −3, −3)`, `T(5)` exactly as the notes' rationals, `T(t1) = T1`, the tool
//!   point on the straight segment at every sample, and every sample equal to an independent
//!   Rodrigues evaluation written out in this file;
//! * the joint-space table (notes §5.2): `q = (Λ, 0, 0, Λ, 0, 0)`, `Λ = λ(t)·π/2`, and its pole;
//! * the tool-space table of the thesis's IK branch (`wrist=noflip`, the notes' "correct
//!   order" table) at t = 1…9 to the printed 4 decimals;
//! * J values with correct IK, checked against an independent computation in this file.
//!
//! # Why the paper's J = 0.6981 / 1.3307 are not asserted (notes 001 §6, §6.1 items 1, 13, 14)
//!
//! The thesis's appendix IK multiplies `inv(A1)·inv(A2)·inv(A3)·T` (wrong order): its joint
//! values do not reproduce the poses (FK∘IK ≠ id on 2000 of 2000 random poses), the J code is
//! not listed, and no choice of weights, dropped joint or step reproduces both printed values
//! (the notes tried them). With the correct IK:
//!
//! * `J1 = (1/3)·π/2 + (1/18)·π/2 = 7π/36 = 0.6109` for the joint-space motion (q1 and q4 each
//!   turn 90°); the sampled joint motion is monotone, so `J2 = J1` for it;
//! * `J2` of the tool-space motion, sampled at dt = 0.1 (101 samples), differences wrapped
//!   into (−π, π] ("wrap-safe"), the IK solution at each sample the one closest to the
//!   previous sample (weights ω), the wrist's undetermined roll q6 kept from the previous
//!   sample at the singular ends: **J2 = 0.876425** — the smooth `wrist=flip` branch all the
//!   way. It leaves seed 001's q6 limit of ±90° from t = 7.3 s on (q6 → 99.8° at t1): within
//!   the limits the tool-space motion is infeasible for this arm; the thesis only prints
//!   "ошибка" and goes on, which is what `allow_outside_limits` does;
//! * the thesis's own branch (`wrist=noflip`: sin q5 ≥ 0, notes §3.4 upper signs) gives the
//!   table of notes §5.2 and, wrap-safe, **J2 = 1.187423** (computed below): it starts with a
//!   ±170° jump of q4 and q6 at the first step (the home pose is a wrist singularity). The
//!   notes' 1.4533 for this branch differs in the last sample only: there the thesis's exact
//!   `switch r33` misses the singularity and returns rounding noise (q4, q6) = (−0.2691, −π)
//!   (notes §6.1 item 13), while here the singular end keeps q6 from the previous sample.
//!
//! Both J2 values exceed J1, the thesis's qualitative claim.

// The notes' tables print π/4, π/2 and π rounded to 4 decimals; they are data, not constants.
#![allow(clippy::approx_constant)]

use std::f64::consts::{FRAC_PI_2, PI};

use crate::common::{SPBU6_T0 as T0, SPBU6_T1 as T1, pose_from_rows as pose};
use nalgebra::{Isometry3, Matrix3, Matrix4, Vector3};
use reach::Robot;
use reach::angle::wrap;
use reach::effort::{DEFAULT_SIX_JOINT_WEIGHTS, Differences, j1, j1_of_delta, j2};
use reach::ik::{self, IkOptions, IkTarget};
use reach::model::presets;
use reach::motion::joint_space::EndChoice;
use reach::motion::sample::PerSampleIk;
use reach::motion::{JointMotion, Profile, ToolMotion, ToolPath};

fn spbu6() -> Robot {
    presets::get("spbu6").unwrap()
}

/// λ(t) written as the thesis's code does for t0 = 0 (notes §4.3 step 2.1).
fn lambda(t: f64) -> f64 {
    t / 10.0 - (PI * t / (10.0 / 2.0)).sin() / (2.0 * PI)
}

fn tool_motion() -> ToolMotion {
    ToolMotion::new(pose(T0), pose(T1), 0.0, 10.0, Profile::Cycloidal).unwrap()
}

/// Seed 001's velocity profile written as the thesis does, `(2/T)·sin²(πτ)` in `1/s`
/// (notes 001 §3.6): it should equal `λ'(τ)/T` of [`Profile::Cycloidal`].
fn thesis_velocity(tau: f64, duration: f64) -> f64 {
    let s = (PI * tau.clamp(0.0, 1.0)).sin();
    2.0 / duration * s * s
}

/// Notes §3.6: λ at t = 0..10.
#[test]
fn cycloidal_lambda_matches_the_notes() {
    let printed = [0.0, 0.006451, 0.048635, 0.148635, 0.306451, 0.5, 0.693549, 0.851365, 0.951365, 0.993549, 1.0];
    for (k, &want) in printed.iter().enumerate() {
        let t = k as f64;
        assert!((Profile::Cycloidal.position(t / 10.0) - want).abs() < 5e-7, "t = {t}");
        assert!((lambda(t) - want).abs() < 5e-7);
        // The thesis's velocity profile (2/T)·sin²(πτ) is λ'/T.
        let v = Profile::Cycloidal.eval(t / 10.0).velocity / 10.0;
        assert!((v - thesis_velocity(t / 10.0, 10.0)).abs() < 1e-15);
    }
}

/// Notes §5.2: `e`, `φ1`, `ρ(t1)`, `T(5)` and `T(t1)`.
#[test]
fn tool_space_axis_angle_and_midpoint() {
    let m = tool_motion();
    let k = 1.0 / 3f64.sqrt();
    assert!((m.axis().into_inner() - Vector3::new(k, -k, k)).norm() < 1e-12);
    assert!((m.axis().x - 0.5774).abs() < 5e-5); // the thesis's printed e
    assert!((m.angle() - 2.0 * PI / 3.0).abs() < 1e-12);
    assert!((m.displacement() - Vector3::new(0.0, -3.0, -3.0)).norm() < 1e-12);
    // In the base frame the axis is R0·e = (1, 1, 1)/√3.
    assert!((m.axis_world().into_inner() - Vector3::new(k, k, k)).norm() < 1e-12);
    #[rustfmt::skip]
    let t5 = Matrix4::new(2.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0, 1.5,
                          -1.0 / 3.0, -2.0 / 3.0, 2.0 / 3.0, 1.5,
                          2.0 / 3.0, -2.0 / 3.0, -1.0 / 3.0, 5.0,
                          0.0, 0.0, 0.0, 1.0);
    assert!((m.pose_at(5.0).to_homogeneous() - t5).amax() < 1e-12);
    assert!((m.pose_at(10.0).to_homogeneous() - pose(T1).to_homogeneous()).amax() < 1e-15);
}

/// Notes §3.7: every sample is `T0·[Rodrigues(e, λφ1), λρ1]` — evaluated here from the
/// thesis's formula `R = cos φ·E + (1 − cos φ)·eeᵀ + sin φ·Λ(e)` — and the tool point lies on
/// the straight segment p0 → p1.
#[test]
fn tool_space_samples_follow_rodrigues_and_a_straight_line() {
    let path = tool_motion().sample_time(0.1).unwrap();
    assert_eq!(path.samples.len(), 101);
    assert!((path.length - 18f64.sqrt()).abs() < 1e-12); // 3√2
    let t0 = pose(T0).to_homogeneous();
    let k = 1.0 / 3f64.sqrt();
    let e = Vector3::new(k, -k, k);
    let skew = Matrix3::new(0.0, -e.z, e.y, e.z, 0.0, -e.x, -e.y, e.x, 0.0);
    let (p0, p1) = (Vector3::new(3.0, 0.0, 5.0), Vector3::new(0.0, 3.0, 5.0));
    for (i, s) in path.samples.iter().enumerate() {
        let t = i as f64 * 0.1;
        assert!((s.t - t).abs() < 1e-12);
        let l = lambda(t);
        let phi = l * 2.0 * PI / 3.0;
        let r = Matrix3::identity() * phi.cos() + e * e.transpose() * (1.0 - phi.cos()) + skew * phi.sin();
        let mut a = Matrix4::identity();
        a.fixed_view_mut::<3, 3>(0, 0).copy_from(&r);
        a.fixed_view_mut::<3, 1>(0, 3).copy_from(&(Vector3::new(0.0, -3.0, -3.0) * l));
        let want = t0 * a;
        assert!((s.pose.to_homogeneous() - want).amax() < 1e-12, "t = {t}");
        let p = s.pose.translation.vector;
        assert!((p - (p0 + (p1 - p0) * l)).norm() < 1e-12, "t = {t}");
        assert!((s.s - l * 18f64.sqrt()).abs() < 1e-12);
        assert!((s.angle - phi).abs() < 1e-12);
    }
    // The pole table of notes §5.2 (tool space): (2.9806, 0.0194, 5) at t = 1, (1.5, 1.5, 5) at t = 5.
    let p = path.samples[10].pose.translation.vector;
    assert!((p - Vector3::new(2.9806, 0.0194, 5.0)).amax() < 5e-5);
}

/// Notes §5.2, joint-space table: q = (Λ, 0, 0, Λ, 0, 0), Λ = λ·π/2, and the pole on the
/// arc of radius 3 at z = 5.
#[test]
fn joint_space_table() {
    let robot = spbu6();
    let m =
        JointMotion::between_poses(&robot, &pose(T0), &pose(T1), 0.0, 10.0, Profile::Cycloidal, &EndChoice::default())
            .unwrap();
    let printed = [0.0101, 0.0764, 0.2335, 0.4814, 0.7854, 1.0894, 1.3373, 1.4944, 1.5607, 1.5708];
    let traj = m.sample(0.1).unwrap();
    assert_eq!(traj.samples.len(), 101);
    for (k, &big_lambda) in printed.iter().enumerate() {
        let q = &traj.samples[10 * (k + 1)].q;
        let exact = lambda((k + 1) as f64) * FRAC_PI_2;
        for (i, want) in [exact, 0.0, 0.0, exact, 0.0, 0.0].iter().enumerate() {
            assert!((q[i] - want).abs() < 1e-12, "t = {}, q{}", k + 1, i + 1);
        }
        assert!((q[0] - big_lambda).abs() < 5e-5);
        let pole = robot.fk(q).unwrap().translation.vector;
        assert!((pole - Vector3::new(3.0 * exact.cos(), 3.0 * exact.sin(), 5.0)).norm() < 1e-12);
    }
    let pole5 = robot.fk(&traj.samples[50].q).unwrap().translation.vector;
    assert!((pole5 - Vector3::new(2.1213, 2.1213, 5.0)).amax() < 5e-5);
    assert!(traj.samples.iter().all(|s| s.within_limits));
}

/// Notes §5.2, tool-space table with the correct IK order: the thesis's branch is
/// `shoulder=front elbow=up wrist=noflip`; at t = 1…9 the library's solution of that branch
/// equals the printed values (4 decimals; q4 at t = 5 is ±π, compared modulo 2π).
#[test]
fn tool_space_table_of_the_thesis_branch() {
    #[rustfmt::skip]
    let printed: [[f64; 6]; 9] = [
        [0.0065, -0.0039, 0.0038, -2.9713, 0.0079, 2.9791],
        [0.0511, -0.0284, 0.0278, -2.9786, 0.0585, 3.0389],
        [0.1728, -0.0815, 0.0760, -3.0011, 0.1687, -3.0873],
        [0.4161, -0.1455, 0.1279, -3.0531, 0.3019, -2.7903],
        [0.7854, -0.1764, 0.1506, -3.1416, 0.3657, -2.3562],
        [1.1547, -0.1455, 0.1279, 3.0531, 0.3019, -1.9221],
        [1.3980, -0.0815, 0.0760, 3.0011, 0.1687, -1.6251],
        [1.5197, -0.0284, 0.0278, 2.9786, 0.0585, -1.4681],
        [1.5643, -0.0039, 0.0038, 2.9713, 0.0079, -1.4083],
    ];
    let robot = spbu6();
    let path = tool_motion().sample_time(0.1).unwrap();
    let thesis = thesis_branch(&robot, &path);
    for (k, row) in printed.iter().enumerate() {
        let q = &thesis[10 * (k + 1)];
        for i in 0..6 {
            assert!(wrap(q[i] - row[i]).abs() < 1e-4, "t = {}, q{}: {} vs {}", k + 1, i + 1, q[i], row[i]);
        }
    }
}

/// The thesis's branch at every sample (the library's `wrist=noflip` solution, the roll kept
/// from the previous sample at the singular ends).
fn thesis_branch(robot: &Robot, path: &ToolPath) -> Vec<Vec<f64>> {
    let mut previous = vec![0.0; 6];
    let mut out = Vec::new();
    for s in &path.samples {
        let options = IkOptions { seed: Some(previous.clone()), ..IkOptions::default() };
        let all = ik::solve(robot, &IkTarget::Pose(s.pose), &options).unwrap();
        let sol = all
            .solutions
            .iter()
            .find(|x| {
                x.branch.get("shoulder") == Some("front")
                    && x.branch.get("elbow") == Some("up")
                    && x.branch.get("wrist") == Some("noflip")
            })
            .unwrap();
        previous.clone_from(&sol.q);
        out.push(sol.q.clone());
    }
    out
}

/// Seed 001's IK written plainly from the notes (§3.3 arm, thesis branch; §3.4 ZYZ wrist with
/// the text's multiplication order, both signs), with the printed link matrices A1..A3
/// (§2.3, l1 = 5, l2 = 3). Returns the two wrist solutions; at the singularity
/// (√(r13² + r23²) < 1e-9) one solution, q6 = `q6_keep`, q4 = atan2(r21, r11) − q6.
fn plain_ik(t: &Isometry3<f64>, q6_keep: f64) -> Vec<[f64; 6]> {
    let (l1, l2) = (5.0_f64, 3.0_f64);
    let m = t.to_homogeneous();
    let (p1, p2, p3) = (m[(0, 3)], m[(1, 3)], m[(2, 3)]);
    let rho = p1.hypot(p2);
    let r2 = p1 * p1 + p2 * p2 + p3 * p3;
    let q1 = p2.atan2(p1);
    let q2 = rho.atan2(p3) - ((l1 * l1 + r2 - l2 * l2) / (2.0 * l1 * r2.sqrt())).clamp(-1.0, 1.0).acos();
    let q3 = ((l1 * l1 + l2 * l2 - r2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0).asin();
    let (c1, s1, c2, s2, c3, s3) = (q1.cos(), q1.sin(), q2.cos(), q2.sin(), q3.cos(), q3.sin());
    #[rustfmt::skip]
    let a1 = Matrix4::new(c1, 0.0, -s1, 0.0,  s1, 0.0, c1, 0.0,  0.0, -1.0, 0.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    #[rustfmt::skip]
    let a2 = Matrix4::new(s2, c2, 0.0, l1 * s2,  -c2, s2, 0.0, -l1 * c2,  0.0, 0.0, 1.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    #[rustfmt::skip]
    let a3 = Matrix4::new(c3, 0.0, -s3, -l2 * s3,  s3, 0.0, c3, l2 * c3,  0.0, -1.0, 0.0, 0.0,  0.0, 0.0, 0.0, 1.0);
    let r123 = (a1 * a2 * a3).fixed_view::<3, 3>(0, 0).into_owned();
    let r = r123.transpose() * m.fixed_view::<3, 3>(0, 0);
    let hyp = r[(0, 2)].hypot(r[(1, 2)]);
    if hyp < 1e-9 {
        return vec![[q1, q2, q3, r[(1, 0)].atan2(r[(0, 0)]) - q6_keep, 0.0, q6_keep]];
    }
    [1.0, -1.0]
        .iter()
        .map(|k| {
            [
                q1,
                q2,
                q3,
                (k * r[(1, 2)]).atan2(k * r[(0, 2)]),
                (k * hyp).atan2(r[(2, 2)]),
                (k * r[(2, 1)]).atan2(-k * r[(2, 0)]),
            ]
        })
        .collect()
}

/// The weighted wrapped change Σ ωᵢ |wrap(bᵢ − aᵢ)|, written out.
fn cost(a: &[f64], b: &[f64]) -> f64 {
    (0..6).map(|i| DEFAULT_SIX_JOINT_WEIGHTS[i] * wrap(b[i] - a[i]).abs()).sum()
}

/// J1 of the joint-space motion = 7π/36; the sampled motion is monotone, so J2 = J1.
#[test]
fn j1_of_the_joint_space_motion_is_7pi_over_36() {
    let robot = spbu6();
    let m =
        JointMotion::between_poses(&robot, &pose(T0), &pose(T1), 0.0, 10.0, Profile::Cycloidal, &EndChoice::default())
            .unwrap();
    let want = 7.0 * PI / 36.0;
    assert!((j1_of_delta(m.delta(), &DEFAULT_SIX_JOINT_WEIGHTS).unwrap() - want).abs() < 1e-12);
    assert!(
        (j1(m.start(), &m.end(), &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::for_robot(&robot)).unwrap() - want).abs()
            < 1e-12
    );
    let traj = m.sample(0.1).unwrap();
    assert!(
        (j2(&traj.rows(), &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::for_robot(&robot)).unwrap() - want).abs() < 1e-12
    );
    assert!((want - 0.6109).abs() < 5e-5);
}

/// J2 of the tool-space motion with the per-sample IK closest to the previous sample (see the
/// file docs): the library's samples equal the plain IK's choice at every sample, and J2 equals
/// the independently summed total variation, 0.876425.
#[test]
fn j2_of_the_tool_space_motion_closest_branch() {
    let robot = spbu6();
    let path = tool_motion().sample_time(0.1).unwrap();
    // Strictly within limits the motion is infeasible: q6 passes 90° at t = 7.3 s.
    let strict = path.to_joints(&robot, &PerSampleIk::default());
    match strict {
        Err(reach::motion::MotionError::NoIkSolution { which, .. }) => {
            assert!(which.starts_with("sample 73 "), "{which}")
        }
        other => panic!("expected a limit failure, got {other:?}"),
    }
    let options = PerSampleIk { allow_outside_limits: true, ..PerSampleIk::default() };
    let traj = path.to_joints(&robot, &options).unwrap();
    // Independent: the thesis's arm, the wrist solution closest to the previous sample.
    let mut previous = [0.0; 6];
    let mut independent = 0.0;
    for (k, s) in path.samples.iter().enumerate() {
        let candidates = plain_ik(&s.pose, previous[5]);
        let best =
            candidates.iter().min_by(|a, b| cost(&previous, &a[..]).total_cmp(&cost(&previous, &b[..]))).unwrap();
        for (i, (got, want)) in traj.samples[k].q.iter().zip(best).enumerate() {
            assert!(wrap(got - want).abs() < 1e-9, "sample {k}, q{}", i + 1);
        }
        independent += cost(&previous, best);
        previous = *best;
    }
    let got = j2(&traj.rows(), &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::for_robot(&robot)).unwrap();
    assert!((got - independent).abs() < 1e-9, "{got} vs {independent}");
    assert!((got - 0.876425).abs() < 1e-6, "{got}");
    assert!(got > 7.0 * PI / 36.0); // J_tool > J_joint, the thesis's claim
    // The samples from t = 7.3 s on are flagged outside the limits (q6 > 90°).
    assert_eq!(traj.outside_limits(), 28);
    assert!(traj.samples[72].within_limits && !traj.samples[73].within_limits);
}

/// J2 of the thesis's own branch (upper-sign wrist), wrap-safe: equals the plain IK's sum.
#[test]
fn j2_of_the_tool_space_motion_thesis_branch() {
    let robot = spbu6();
    let path = tool_motion().sample_time(0.1).unwrap();
    let thesis = thesis_branch(&robot, &path);
    let mut previous = [0.0; 6];
    let mut independent = 0.0;
    for (k, s) in path.samples.iter().enumerate() {
        let candidates = plain_ik(&s.pose, previous[5]);
        let upper = candidates[0];
        for i in 0..6 {
            assert!(wrap(thesis[k][i] - upper[i]).abs() < 1e-9, "sample {k}, q{}", i + 1);
        }
        independent += cost(&previous, &upper);
        previous = upper;
    }
    let got = j2(&thesis, &DEFAULT_SIX_JOINT_WEIGHTS, &Differences::Wrapped).unwrap();
    assert!((got - independent).abs() < 1e-9, "{got} vs {independent}");
    assert!((got - 1.187423).abs() < 1e-6, "{got}");
    // Not the paper's 1.3307 (notes §6).
    assert!((got - 1.3307).abs() > 0.1);
}
