//! `IkSolver::solve_branch` (one branch, verified by FK) against `IkSolver::solve` (all
//! branches): for every closed form that overrides it — `spherical-wrist` (`puma560`, the
//! seed-002 reference arm without lateral offset), `two-link-wrist` (`spbu6`) and
//! `parallel-axes` (`welder6r`, `ur5`) — and every branch label, `solve_branch(b)` must equal
//! `solve().restricted_to(b)` exactly (same joint values bit for bit, labels, errors, limit and
//! singularity flags, failure reason):
//!
//! * on 2 000 seeded random joint vectors per robot (pose targets, half of them with a random
//!   seed, every tenth a position target);
//! * on families of poses at and near the wrist, elbow and shoulder singularities, where
//!   branches merge (offsets from 0 to 1e-4 around the singular value, on both sides).
//!
//! Then path tracking: `track_configuration` (which follows the locked branch with
//! `solve_branch`) gives the same joint vectors as the all-branch rule written out here —
//! the nearest solution with the locked label, else (branches merged at a singular sample)
//! the nearest solution flagged singular — on paths through an elbow singularity.

use std::f64::consts::{FRAC_PI_2, PI};

use crate::common::{Rng, seed002_reference};
use nalgebra::{Isometry3, Point3, Rotation3, Translation3, UnitQuaternion, Vector3};
use reach::Robot;
use reach::angle::{nearest_equivalent, wrap};
use reach::ik::spherical_wrist::SphericalWrist;
use reach::ik::{Branch, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, SolverKind};
use reach::model::presets;
use reach::motion::PathSample;
use reach::motion::tracking::track_configuration;

const CASES: usize = 2000;

/// The robots, each with its solver kind and every label its solver can give.
fn cases() -> Vec<(Robot, SolverKind, Vec<Branch>)> {
    let arm_labels = || {
        let mut out = Vec::new();
        for s in ["front", "back", "left", "right"] {
            for e in ["up", "down"] {
                for w in ["noflip", "flip"] {
                    out.push(Branch::new([("shoulder", s), ("elbow", e), ("wrist", w)]));
                }
            }
        }
        out
    };
    let parallel_labels = || {
        let mut out = Vec::new();
        for s in ["w", "−w"] {
            for c in ["+β", "−β"] {
                for w in ["e5", "−e5"] {
                    out.push(Branch::new([("shoulder", s), ("config", c), ("wrist", w)]));
                }
            }
        }
        out
    };
    vec![
        (presets::get("puma560").unwrap(), SolverKind::SphericalWrist, arm_labels()),
        (seed002_reference(), SolverKind::SphericalWrist, arm_labels()),
        (presets::get("spbu6").unwrap(), SolverKind::TwoLinkWrist, arm_labels()),
        (presets::get("welder6r").unwrap(), SolverKind::ParallelAxes, parallel_labels()),
        (presets::get("ur5").unwrap(), SolverKind::ParallelAxes, parallel_labels()),
    ]
}

/// Labels that are no branch of these solvers: a partial label, the empty one, a foreign one.
fn foreign_labels() -> Vec<Branch> {
    vec![
        Branch::default(),
        Branch::new([("elbow", "up")]),
        Branch::new([("config", "+β")]),
        Branch::new([("shoulder", "w"), ("config", "+β"), ("wrist", "e5"), ("extra", "x")]),
    ]
}

/// Checks `solve_branch(b) == solve().restricted_to(b)` for every label; returns how many
/// labels had a solution.
fn check(
    robot: &Robot,
    solver: &dyn IkSolver,
    labels: &[Branch],
    target: &IkTarget,
    options: &IkOptions,
    what: &str,
) -> usize {
    let all = solver.solve(robot, target, options).unwrap();
    let mut found = 0;
    for b in labels.iter().chain(&foreign_labels()) {
        let one = solver.solve_branch(robot, target, b, options).unwrap();
        let want = all.clone().restricted_to(b);
        assert_eq!(one, want, "{} {what}: branch `{b}`", robot.name());
        found += usize::from(!one.solutions.is_empty());
    }
    // Every solution of the full solve is found on its own branch.
    for s in &all.solutions {
        let one = solver.solve_branch(robot, target, &s.branch, options).unwrap();
        assert_eq!(one.solutions, vec![s.clone()], "{} {what}: branch `{}`", robot.name(), s.branch);
    }
    found
}

#[test]
fn one_branch_equals_the_branch_of_all_solutions_on_random_poses() {
    for (robot, kind, labels) in cases() {
        let solver = kind.build(&robot).unwrap();
        let mut rng = Rng::new(0x5eed_b7a9 ^ robot.dof() as u64 ^ robot.name().len() as u64);
        let mut found = 0;
        let mut per_label = vec![0usize; labels.len()];
        for case in 0..CASES {
            let q = rng.joints(&robot);
            let pose = robot.fk(&q).unwrap();
            let seed = (case % 2 == 1).then(|| rng.joints(&robot));
            let options = IkOptions { seed, ..IkOptions::default() };
            let target = if case % 10 == 3 {
                IkTarget::Position(Point3::from(pose.translation.vector))
            } else {
                IkTarget::Pose(pose)
            };
            found += check(&robot, solver.as_ref(), &labels, &target, &options, &format!("case {case}"));
            let all = solver.solve(&robot, &target, &options).unwrap();
            for (count, b) in per_label.iter_mut().zip(&labels) {
                *count += usize::from(all.solutions.iter().any(|s| s.branch == *b));
            }
        }
        // Not vacuous: most poses have 8 solutions, every label of the family occurs.
        assert!(found > 5 * CASES, "{}: only {found} branch solutions", robot.name());
        let used: Vec<&Branch> = labels.iter().zip(&per_label).filter(|(_, n)| **n > 0).map(|(b, _)| b).collect();
        assert_eq!(used.len(), 8, "{}: labels seen {used:?}", robot.name());
    }
}

/// The DH angle of joint `i` as a joint value.
fn q_of(robot: &Robot, i: usize, theta: f64) -> f64 {
    let j = &robot.joints()[i];
    let offset = j.dh().unwrap().theta_offset;
    if j.flip { -(theta - offset) } else { theta - offset }
}

/// Offsets around a singular value, both sides, from exact to well outside the tolerances.
const NEAR: [f64; 13] = [0.0, 1e-15, 1e-12, -1e-12, 1e-10, -1e-10, 1e-9, -1e-9, 1e-8, -1e-8, 1e-7, 1e-5, -1e-4];

/// The singular DH angles θ3 (elbow stretched or folded) of each robot.
fn elbow_singular_theta3(robot: &Robot, kind: SolverKind) -> Vec<f64> {
    match kind {
        SolverKind::SphericalWrist => {
            // θ3 = s·(π − φ) + sgn(α3)·α with φ = π (stretched) or 0 (folded).
            let alpha = SphericalWrist::from_robot(robot).unwrap().elbow_alpha();
            let s3 = robot.joints()[2].dh().unwrap().alpha.signum();
            vec![s3 * alpha, s3 * alpha + PI, s3 * alpha - PI]
        }
        SolverKind::TwoLinkWrist => vec![FRAC_PI_2, -FRAC_PI_2],
        _ => vec![0.0, PI],
    }
}

#[test]
fn one_branch_equals_the_branch_of_all_solutions_at_wrist_and_elbow_singularities() {
    for (robot, kind, labels) in cases() {
        let solver = kind.build(&robot).unwrap();
        let mut rng = Rng::new(0xe1b0_u64 + robot.name().len() as u64);
        let (mut wrist_seen, mut elbow_seen) = (0, 0);
        for case in 0..40 {
            let base = rng.joints(&robot);
            let seed = (case % 2 == 0).then(|| rng.joints(&robot));
            let options = IkOptions { seed, ..IkOptions::default() };
            // Wrist: DH θ5 at 0 and π (axes 4 and 6, or for the parallel-axes arms e6 and w,
            // aligned; the counts below check that these are flagged singular).
            let mut family = Vec::new();
            for t5 in [0.0, PI] {
                for e in NEAR {
                    let mut q = base.clone();
                    q[4] = q_of(&robot, 4, t5 + e);
                    family.push(q);
                }
            }
            for t3 in elbow_singular_theta3(&robot, kind) {
                for e in NEAR {
                    let mut q = base.clone();
                    q[2] = q_of(&robot, 2, t3 + e);
                    family.push(q);
                }
            }
            for q in family {
                let target = IkTarget::Pose(robot.fk(&q).unwrap());
                check(&robot, solver.as_ref(), &labels, &target, &options, &format!("near-singular q {q:?}"));
                let all = solver.solve(&robot, &target, &options).unwrap();
                let flagged = |k| all.solutions.iter().any(|s| s.singularities.contains(&k));
                wrist_seen += usize::from(flagged(SingularityKind::Wrist));
                elbow_seen += usize::from(flagged(SingularityKind::Elbow));
            }
        }
        assert!(wrist_seen > 100 && elbow_seen > 100, "{}: {wrist_seen} wrist, {elbow_seen} elbow", robot.name());
    }
}

/// The world pose whose wrist point (spherical wrist centre, or seed 003's point C) is `c` in
/// the chain frame, with flange orientation `r`: p = c + a6·x6 + d6·z5,
/// z5 = sin α6·y6 + cos α6·z6.
fn pose_with_wrist_point(robot: &Robot, c: Vector3<f64>, r: Rotation3<f64>) -> Isometry3<f64> {
    let j6 = robot.joints()[5].dh().unwrap();
    let m = r.matrix();
    let z5 = m.column(1) * j6.alpha.sin() + m.column(2) * j6.alpha.cos();
    let p = c + m.column(0) * j6.a + z5 * j6.d;
    let flange = Isometry3::from_parts(Translation3::from(p), UnitQuaternion::from_rotation_matrix(&r));
    robot.base() * flange * robot.tool()
}

#[test]
fn one_branch_equals_the_branch_of_all_solutions_at_shoulder_singularities() {
    for (robot, kind, labels) in cases() {
        let solver = kind.build(&robot).unwrap();
        // The radius of the shoulder singularity: the lateral offset of the arm plane.
        let lateral = match kind {
            SolverKind::SphericalWrist => SphericalWrist::from_robot(&robot).unwrap().lateral_offset().abs(),
            SolverKind::ParallelAxes => {
                let pa = reach::ik::parallel_axes::ParallelAxes::from_robot(&robot).unwrap();
                let m = pa.measures(&robot, &robot.fk(&robot.home()).unwrap(), &IkOptions::default()).unwrap();
                m.lateral_offset
            }
            _ => 0.0,
        };
        let d1 = robot.joints()[0].dh().unwrap().d;
        // Arm size (upper arm and forearm), to place the wrist point within reach.
        let dh = |i: usize| *robot.joints()[i].dh().unwrap();
        let arm = dh(1).a.abs() + dh(2).a.abs() + dh(3).d.abs();
        let mut rng = Rng::new(0x5401_u64 + robot.name().len() as u64);
        let (mut solved, mut shoulder_seen) = (0, 0);
        for case in 0..60 {
            let r = Rotation3::from_euler_angles(rng.uniform(-PI, PI), rng.uniform(-1.5, 1.5), rng.uniform(-PI, PI));
            let heading = rng.uniform(-PI, PI);
            let height = d1 + rng.uniform(0.4, 0.9) * arm * if case % 3 == 0 { -1.0 } else { 1.0 };
            let seed = (case % 2 == 0).then(|| rng.joints(&robot));
            let options = IkOptions { seed, ..IkOptions::default() };
            for e in NEAR {
                let rho = (lateral + e).abs();
                let c = Vector3::new(rho * heading.cos(), rho * heading.sin(), height);
                let target = IkTarget::Pose(pose_with_wrist_point(&robot, c, r));
                solved += check(&robot, solver.as_ref(), &labels, &target, &options, &format!("ρ = |D| + {e}"));
                let all = solver.solve(&robot, &target, &options).unwrap();
                shoulder_seen +=
                    usize::from(all.solutions.iter().any(|s| s.singularities.contains(&SingularityKind::Shoulder)));
            }
        }
        assert!(solved > 200 && shoulder_seen > 20, "{}: {solved} solutions, {shoulder_seen} shoulder", robot.name());
    }
}

#[test]
fn absent_branches_and_failures_are_restated_for_the_branch() {
    let puma = presets::get("puma560").unwrap();
    let solver = SolverKind::SphericalWrist.build(&puma).unwrap();
    let options = IkOptions::default();
    // Out of reach: no branch has a solution, the reason of the whole problem is kept.
    let far = IkTarget::Pose(Isometry3::translation(3.0, 0.0, 0.5));
    let flip = Branch::new([("shoulder", "left"), ("elbow", "up"), ("wrist", "flip")]);
    let one = solver.solve_branch(&puma, &far, &flip, &options).unwrap();
    assert!(one.solutions.is_empty());
    assert!(matches!(one.failure, Some(IkFailure::Unreachable { .. })), "{:?}", one.failure);
    // Wrist singularity (θ5 = 0): one wrist solution per arm, labelled `noflip`; `flip` is absent.
    let q = [0.2, 0.4, -0.3, 0.5, q_of(&puma, 4, 0.0), 0.1];
    let target = IkTarget::Pose(puma.fk(&q).unwrap());
    let all = solver.solve(&puma, &target, &options).unwrap();
    let arm = all.solutions[0].branch.clone();
    let value = |k: &str| arm.get(k).unwrap().to_string();
    let flipped =
        Branch::new([("shoulder", value("shoulder")), ("elbow", value("elbow")), ("wrist", "flip".to_string())]);
    let one = solver.solve_branch(&puma, &target, &flipped, &options).unwrap();
    assert!(one.solutions.is_empty());
    assert!(matches!(&one.failure, Some(IkFailure::BranchAbsent { branch }) if branch.contains("wrist=flip")));
    assert!(one.failure.unwrap().to_string().contains("other branches exist"));
    // Limits: a branch whose only solution violates a limit names that solution's joint, even
    // when other branches are within limits.
    let mut found = false;
    let mut rng = Rng::new(7);
    for _ in 0..200 {
        let target = IkTarget::Pose(puma.fk(&rng.joints(&puma)).unwrap());
        let all = solver.solve(&puma, &target, &options).unwrap();
        if all.failure.is_some() {
            continue;
        }
        if let Some(out) = all.solutions.iter().find(|s| !s.within_limits) {
            let one = solver.solve_branch(&puma, &target, &out.branch, &options).unwrap();
            let v = &out.violations[0];
            assert_eq!(one.failure, Some(IkFailure::OutsideLimits { joint: v.joint, name: v.name.to_string() }));
            found = true;
            break;
        }
    }
    assert!(found, "no pose with a branch outside the limits");
    // Bad input is still an error, not a failure.
    let nan = IkTarget::Position(Point3::new(f64::NAN, 0.0, 0.0));
    assert!(solver.solve_branch(&puma, &nan, &flip, &options).is_err());
    let short_seed = IkOptions { seed: Some(vec![0.0; 3]), ..IkOptions::default() };
    assert!(solver.solve_branch(&puma, &target, &flip, &short_seed).is_err());
}

/// The all-branch tracking rule, written out: anchor = the first sample's solution of
/// `filter` (non-singular first, then within limits); then at every sample the full solve
/// seeded with the last tracked joint vector, the nearest solution with the anchor's label, else
/// the nearest one flagged singular, unwrapped next to the last tracked joint vector.
fn reference_track(
    robot: &Robot,
    solver: &dyn IkSolver,
    samples: &[PathSample],
    filter: &Branch,
) -> Vec<Option<Vec<f64>>> {
    let dist = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| wrap(x - y).abs()).sum::<f64>();
    let first = solver.solve(robot, &IkTarget::Pose(samples[0].pose), &IkOptions::default()).unwrap();
    let anchor = first
        .solutions
        .iter()
        .filter(|s| filter.0.iter().all(|(k, v)| s.branch.get(k) == Some(v.as_str())))
        .min_by_key(|s| (!s.singularities.is_empty(), !s.within_limits))
        .expect("the filter is a label of the first sample");
    let label = anchor.branch.clone();
    let mut prev = anchor.q.clone();
    let mut out = vec![Some(anchor.q.clone())];
    for p in &samples[1..] {
        let options = IkOptions { seed: Some(prev.clone()), ..IkOptions::default() };
        let sols: IkSolutions = solver.solve(robot, &IkTarget::Pose(p.pose), &options).unwrap();
        let nearest = |pred: &dyn Fn(&reach::ik::IkSolution) -> bool| {
            sols.solutions.iter().filter(|s| pred(s)).min_by(|a, b| dist(&a.q, &prev).total_cmp(&dist(&b.q, &prev)))
        };
        let found = nearest(&|s| s.branch == label)
            .or_else(|| nearest(&|s| !s.singularities.is_empty()))
            .map(|s| s.q.iter().zip(&prev).map(|(v, r)| nearest_equivalent(*v, *r)).collect::<Vec<f64>>());
        if let Some(q) = &found {
            prev.clone_from(q);
        }
        out.push(found);
    }
    out
}

#[test]
fn tracking_through_an_elbow_singularity_matches_the_all_branch_rule() {
    for (robot, kind, _) in cases() {
        let solver = kind.build(&robot).unwrap();
        let t3 = elbow_singular_theta3(&robot, kind)[0];
        // θ3 sweeps through the stretched elbow, exactly singular at sample 50.
        let q = |k: usize| {
            let u = k as f64 - 50.0;
            let mut q = vec![0.3 + 0.002 * u, 0.4 - 0.001 * u, 0.0, 0.6, 0.8 + 0.001 * u, -0.2];
            q[2] = q_of(&robot, 2, t3 + 0.002 * u);
            q
        };
        let start = robot.fk(&q(0)).unwrap();
        let samples: Vec<PathSample> = (0..=100)
            .map(|k| {
                let pose = robot.fk(&q(k)).unwrap();
                PathSample { t: k as f64, s: k as f64, angle: start.rotation.angle_to(&pose.rotation), pose }
            })
            .collect();
        let first = solver.solve(&robot, &IkTarget::Pose(samples[0].pose), &IkOptions::default()).unwrap();
        let mut fallbacks = 0;
        for start in &first.solutions {
            // Follow each branch of the first sample, by its full label and by its shoulder
            // and wrist only (the anchor then picks the elbow).
            let partial = Branch(
                start.branch.0.iter().filter(|(k, _)| !matches!(k.as_str(), "elbow" | "config")).cloned().collect(),
            );
            for filter in [start.branch.clone(), partial] {
                let tracked = track_configuration(&robot, solver.as_ref(), &samples, &filter, false).unwrap();
                let want = reference_track(&robot, solver.as_ref(), &samples, &filter);
                assert_eq!(tracked.q, want, "{} filter `{filter}`", robot.name());
                // Count the samples where the locked label was missing (the singular fallback).
                let locked = tracked.branch.unwrap();
                let mut prev = tracked.q[0].clone().unwrap();
                for (k, p) in samples.iter().enumerate().skip(1) {
                    let options = IkOptions { seed: Some(prev.clone()), ..IkOptions::default() };
                    let all = solver.solve(&robot, &IkTarget::Pose(p.pose), &options).unwrap();
                    fallbacks += usize::from(!all.solutions.iter().any(|s| s.branch == locked));
                    if let Some(q) = &tracked.q[k] {
                        prev.clone_from(q);
                    }
                }
            }
        }
        assert!(fallbacks > 0, "{}: the singular fallback was never exercised", robot.name());
    }
}
