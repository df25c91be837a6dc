//! `IkSolver::solve_into` (the lean path, into a reused `IkSolutions`) against
//! `IkSolver::solve`: for every solver (the closed forms, which implement `solve` by
//! `solve_into`, and the others, which fall back to `solve`), one buffer is reused over a
//! sequence of targets whose results differ in every part — the number of solutions (8, fewer
//! at singular poses, none out of reach), limit violations, singularity flags, failure reasons
//! (`OutsideLimits`, `Unreachable`, none) and the target kind — and after each solve the buffer
//! must equal a fresh `solve` exactly (same joint values bit for bit, labels, errors, flags,
//! failure) and serialise to the same JSON.

use std::collections::BTreeSet;
use std::f64::consts::PI;

use crate::common::Rng;
use nalgebra::{Isometry3, Point3, Translation3};
use reach::Robot;
use reach::ik::{IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SolverKind};
use reach::model::presets;

/// The targets of one robot: random joint vectors over full turns (many outside the limits),
/// some singular (wrist axes aligned: q5 = 0), some far out of reach, every fifth a position
/// target and every seventh with a seed.
fn problems(robot: &Robot, n: usize, seed: u64) -> Vec<(IkTarget, IkOptions)> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|i| {
            let mut q: Vec<f64> = (0..robot.dof()).map(|_| rng.uniform(-PI, PI)).collect();
            if i % 6 == 3 && robot.dof() >= 5 {
                q[4] = 0.0;
            }
            let mut pose = robot.fk(&q).unwrap();
            if i % 11 == 5 {
                pose = Isometry3::from_parts(Translation3::new(50.0, -40.0, 30.0), pose.rotation);
            }
            let target = if i % 5 == 1 {
                IkTarget::Position(Point3::from(pose.translation.vector))
            } else {
                IkTarget::Pose(pose)
            };
            let mut options = IkOptions::default();
            if i % 7 == 2 {
                options.seed = Some(rng.joints(robot));
            }
            (target, options)
        })
        .collect()
}

/// What a sequence covered, so that the test cannot pass on uniform results.
#[derive(Default)]
struct Coverage {
    counts: BTreeSet<usize>,
    violations: usize,
    singular: usize,
    outside_limits: usize,
    unreachable: usize,
}

/// Solves `problems` in order into one reused buffer and checks each result against `solve`.
fn check_sequence(robot: &Robot, solver: &dyn IkSolver, problems: &[(IkTarget, IkOptions)]) -> Coverage {
    let mut out = IkSolutions::default();
    let mut seen = Coverage::default();
    for (k, (target, options)) in problems.iter().enumerate() {
        let fresh = solver.solve(robot, target, options).unwrap();
        solver.solve_into(robot, target, options, &mut out).unwrap();
        assert_eq!(out, fresh, "{} ({}), problem {k}", robot.name(), solver.name());
        assert_eq!(
            serde_json::to_string(&out).unwrap(),
            serde_json::to_string(&fresh).unwrap(),
            "{} ({}), problem {k}",
            robot.name(),
            solver.name()
        );
        // The choice of a solution sees the same joint rule.
        let from = vec![0.1; robot.dof()];
        assert_eq!(out.closest_index(&from, &[]), fresh.closest_index(&from, &[]));
        seen.counts.insert(fresh.solutions.len());
        seen.violations += fresh.solutions.iter().map(|s| s.violations.len()).sum::<usize>();
        seen.singular += fresh.solutions.iter().filter(|s| !s.singularities.is_empty()).count();
        match fresh.failure {
            Some(IkFailure::OutsideLimits { .. }) => seen.outside_limits += 1,
            Some(IkFailure::Unreachable { .. }) => seen.unreachable += 1,
            _ => {}
        }
    }
    seen
}

#[test]
fn solve_into_a_reused_buffer_equals_solve() {
    let mut six_r = Coverage::default();
    for (name, kind, n) in [
        ("puma560", SolverKind::SphericalWrist, 300),
        ("spbu6", SolverKind::TwoLinkWrist, 300),
        ("welder6r", SolverKind::ParallelAxes, 300),
        ("ur5", SolverKind::ParallelAxes, 300),
        ("log-loader", SolverKind::YawTwoLink, 100),
        ("varan4", SolverKind::YawPlanar3, 30),
        ("planar3", SolverKind::Planar, 30),
        ("ur5", SolverKind::Numeric, 6),
    ] {
        let robot = presets::get(name).unwrap();
        let solver = kind.build(&robot).unwrap();
        let problems = problems(&robot, n, 0x501e_0000 + n as u64);
        let seen = check_sequence(&robot, solver.as_ref(), &problems);
        // The same problems backwards: every transition the other way round.
        let backwards: Vec<_> = problems.iter().rev().cloned().collect();
        check_sequence(&robot, solver.as_ref(), &backwards);
        if matches!(kind, SolverKind::SphericalWrist | SolverKind::TwoLinkWrist | SolverKind::ParallelAxes) {
            assert!(seen.counts.len() >= 2 && seen.counts.contains(&0), "{name}: solution counts {:?}", seen.counts);
            six_r.counts.extend(seen.counts);
            six_r.violations += seen.violations;
            six_r.singular += seen.singular;
            six_r.outside_limits += seen.outside_limits;
            six_r.unreachable += seen.unreachable;
        }
    }
    // The closed forms' sequences covered every kind of difference between results.
    assert!(six_r.counts.len() >= 4, "solution counts {:?}", six_r.counts);
    assert!(six_r.violations > 0 && six_r.singular > 0, "no violation or no singular solution");
    assert!(six_r.outside_limits > 0 && six_r.unreachable > 0, "failure reasons not covered");
}

#[test]
fn solve_into_keeps_the_buffers_of_a_closed_form() {
    // Once the buffer has served a solve with as many solutions, another solve reuses the
    // solution vector and each solution's joint vector (the same heap blocks): nothing is
    // allocated for them.
    let puma = presets::get("puma560").unwrap();
    let solver = SolverKind::SphericalWrist.build(&puma).unwrap();
    let options = IkOptions::default();
    let target = |q: [f64; 6]| IkTarget::Pose(puma.fk(&q).unwrap());
    let mut out = IkSolutions::default();
    solver.solve_into(&puma, &target([0.3, 0.5, -0.4, 0.7, 0.9, -0.2]), &options, &mut out).unwrap();
    assert_eq!(out.solutions.len(), 8);
    let blocks = |out: &IkSolutions| -> (usize, Vec<usize>) {
        (out.solutions.as_ptr() as usize, out.solutions.iter().map(|s| s.q.as_ptr() as usize).collect())
    };
    let before = blocks(&out);
    // Out of reach (no solution), then another generic pose: the 8 solutions come back from
    // the spares with their buffers.
    let far = IkTarget::Pose(Isometry3::translation(9.0, 9.0, 9.0));
    solver.solve_into(&puma, &far, &options, &mut out).unwrap();
    assert!(out.solutions.is_empty());
    solver.solve_into(&puma, &target([-1.1, 0.2, 0.4, -0.5, 1.2, 2.0]), &options, &mut out).unwrap();
    assert_eq!(out.solutions.len(), 8);
    assert_eq!(blocks(&out), before);
}
