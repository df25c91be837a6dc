//! FK∘IK round trips for every closed-form solver, on 10 000 seeded random joint vectors each.
//!
//! For every joint vector `q` inside the limits: target = FK(q); the solver's set must contain
//! `q` (to 1e-9 rad, modulo 2π) — unless the configuration is singular, in which case the
//! solver flags a singularity, picks the undetermined angle itself and must still reproduce the
//! pose (those cases are counted and must be rare) — and every returned solution must
//! reproduce the target to 1e-9 m / 1e-9 rad (1e-6, the library's acceptance tolerance, for a
//! solution flagged singular, whose `acos` argument was clamped at ±1), checked here with the library's forward
//! kinematics. Then unreachable targets (just beyond the outer reach, inside the inner hole)
//! and NaN give the typed reason, never NaN or a panic.
//!
//! Targets: planar3 — full pose (the in-plane heading fixes the redundancy); log-loader,
//! spbu6, puma560, welder6r, ur5 — full pose; varan4 — position with `free_parameter` = the
//! true absolute angle of the last link.

use std::f64::consts::TAU;

use nalgebra::{Isometry3, Point3};
use reach::Robot;
use reach::angle::wrap;
use reach::ik::yaw_planar3::YawPlanar3;
use reach::ik::{IkError, IkFailure, IkOptions, IkSolutions, IkTarget, SolverKind};
use reach::model::presets;

const CASES: usize = 10_000;

/// SplitMix64, the test's own generator.
struct Rng(u64);

impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random joint vector inside the limits (every preset joint here is revolute and bounded;
/// ranges wider than 2π are cut to one turn, the rest of the range being the same angles).
fn random_q(robot: &Robot, rng: &mut Rng) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .map(|j| {
            let lo = j.limits.lower;
            let hi = j.limits.upper.min(lo + TAU);
            lo + (hi - lo) * rng.uniform()
        })
        .collect()
}

/// Position (m) and orientation (rad) error of `q` against `target`; the orientation error
/// as atan2(‖vee(R − Rᵀ)‖/2, (tr R − 1)/2) of `R = R_targetᵀ·R(q)`, accurate near 0.
fn errors(robot: &Robot, q: &[f64], target: &IkTarget) -> (f64, f64) {
    let t = robot.fk(q).unwrap();
    match target {
        IkTarget::Pose(p) => {
            let dp = (t.translation.vector - p.translation.vector).norm();
            let r = (p.rotation.inverse() * t.rotation).to_rotation_matrix();
            let m = r.matrix();
            let vee = nalgebra::Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]);
            (dp, (0.5 * vee.norm()).atan2(0.5 * (m.trace() - 1.0)))
        }
        IkTarget::Position(p) => ((t.translation.vector - p.coords).norm(), 0.0),
    }
}

fn same_angles(a: &[f64], b: &[f64], tolerance: f64) -> bool {
    a.iter().zip(b).all(|(x, y)| wrap(x - y).abs() <= tolerance)
}

/// Tallies of one round-trip run.
#[derive(Debug, Default)]
struct Tally {
    found: usize,
    singular: usize,
    solutions: usize,
    /// Largest pose error (m or rad) of a solution flagged singular.
    worst_singular: f64,
}

/// The round trip on `CASES` joint vectors; `target_of` builds the target and options from `q`.
fn round_trip(
    name: &str,
    kind: SolverKind,
    rng_seed: u64,
    target_of: impl Fn(&Robot, &[f64]) -> (IkTarget, IkOptions),
) -> Tally {
    let robot = presets::get(name).unwrap();
    let solver = kind.build(&robot).unwrap();
    let mut rng = Rng(rng_seed);
    let mut tally = Tally::default();
    for _ in 0..CASES {
        let q = random_q(&robot, &mut rng);
        let (target, options) = target_of(&robot, &q);
        let all: IkSolutions = solver.solve(&robot, &target, &options).unwrap();
        tally.solutions += all.solutions.len();
        for s in &all.solutions {
            assert!(s.q.iter().all(|v| v.is_finite()), "{name}: NaN in {:?}", s.q);
            let (pe, oe) = errors(&robot, &s.q, &target);
            // A regular solution is exact to 1e-9. At a flagged singularity the closed forms
            // clamp `acos`/`asin` arguments within `BOUNDARY` of ±1 and pick undetermined
            // angles, which may cost up to the library's acceptance tolerance (1e-6).
            let tolerance = if s.singularities.is_empty() { 1e-9 } else { 1e-6 };
            assert!(
                pe <= tolerance && oe <= tolerance,
                "{name}: q = {q:?}: solution {:?} ({:?}) misses by {pe:e} m, {oe:e} rad",
                s.q,
                s.singularities
            );
            if !s.singularities.is_empty() {
                tally.worst_singular = tally.worst_singular.max(pe).max(oe);
            }
        }
        if all.solutions.iter().any(|s| same_angles(&s.q, &q, 1e-9)) {
            tally.found += 1;
        } else {
            // Only a singular configuration may lose the original (its undetermined angle is
            // chosen by the solver); the pose is still reproduced (checked above).
            assert!(
                !all.solutions.is_empty() && all.solutions.iter().any(|s| !s.singularities.is_empty()),
                "{name}: original {q:?} not among {:?} (failure {:?})",
                all.solutions.iter().map(|s| (&s.q, &s.singularities)).collect::<Vec<_>>(),
                all.failure
            );
            tally.singular += 1;
        }
    }
    eprintln!("{name}: {tally:?} over {CASES}");
    // Singular configurations have measure zero: at most 0.5 % of random draws come within
    // the closed forms' singularity thresholds.
    assert!(tally.singular * 200 <= CASES, "{name}: {} singular cases", tally.singular);
    assert_eq!(tally.found + tally.singular, CASES);
    tally
}

fn pose_target(robot: &Robot, q: &[f64]) -> (IkTarget, IkOptions) {
    (IkTarget::Pose(robot.fk(q).unwrap()), IkOptions::default())
}

#[test]
fn planar3_pose_targets() {
    round_trip("planar3", SolverKind::Planar, 1, pose_target);
}

#[test]
fn log_loader_pose_targets() {
    round_trip("log-loader", SolverKind::YawTwoLink, 2, pose_target);
}

#[test]
fn varan4_position_with_the_true_last_link_angle() {
    let robot = presets::get("varan4").unwrap();
    let solver = YawPlanar3::from_robot(&robot).unwrap();
    round_trip("varan4", SolverKind::YawPlanar3, 3, |robot, q| {
        let q4: [f64; 4] = q.try_into().unwrap();
        let phi = solver.last_link_angle(&q4);
        let target = IkTarget::Position(Point3::from(robot.fk(q).unwrap().translation.vector));
        (target, IkOptions { free_parameter: Some(phi), ..IkOptions::default() })
    });
}

#[test]
fn spbu6_pose_targets() {
    round_trip("spbu6", SolverKind::TwoLinkWrist, 4, pose_target);
}

#[test]
fn puma560_pose_targets() {
    round_trip("puma560", SolverKind::SphericalWrist, 5, pose_target);
}

#[test]
fn welder6r_pose_targets() {
    round_trip("welder6r", SolverKind::ParallelAxes, 6, pose_target);
}

#[test]
fn ur5_pose_targets() {
    round_trip("ur5", SolverKind::ParallelAxes, 7, pose_target);
}

/// Solves and checks that nothing is NaN and no solution is returned.
fn solve_empty(name: &str, robot: &Robot, kind: SolverKind, target: &IkTarget) -> IkFailure {
    let all = kind.build(robot).unwrap().solve(robot, target, &IkOptions::default()).unwrap();
    assert!(all.solutions.is_empty(), "{name}: {:?}", all.solutions);
    all.failure.unwrap_or_else(|| panic!("{name}: no failure reason"))
}

#[test]
fn just_beyond_the_outer_reach_is_unreachable() {
    // Arms whose reach from the shoulder is the sum of the link lengths (the shoulder is the
    // world origin in these presets): planar3 3 m, log-loader 2 m, varan4 2.1 m.
    for (name, kind, reach, target) in [
        ("planar3", SolverKind::Planar, 3.0, IkTarget::Position(Point3::new(3.0 + 1e-6, 0.0, 0.0))),
        ("log-loader", SolverKind::YawTwoLink, 2.0, IkTarget::Position(Point3::new(0.0, 0.0, 2.0 + 1e-6))),
        ("varan4", SolverKind::YawPlanar3, 2.1, IkTarget::Position(Point3::new(0.0, 2.1 + 1e-6, 0.0))),
    ] {
        let robot = presets::get(name).unwrap();
        match solve_empty(name, &robot, kind, &target) {
            IkFailure::Unreachable { distance, reach: bound, .. } => {
                assert!((distance - (reach + 1e-6)).abs() < 1e-9, "{name}: distance {distance}");
                assert!((bound - reach).abs() < 1e-9, "{name}: reach {bound}");
            }
            other => panic!("{name}: expected Unreachable, got {other:?}"),
        }
    }
    // 6R arms: 5 cm beyond the stretched arm (a point farther from the base than the sum of
    // every link offset can never be reached).
    for (name, kind) in [
        ("spbu6", SolverKind::TwoLinkWrist),
        ("puma560", SolverKind::SphericalWrist),
        ("welder6r", SolverKind::ParallelAxes),
        ("ur5", SolverKind::ParallelAxes),
    ] {
        let robot = presets::get(name).unwrap();
        let bound: f64 = robot
            .joints()
            .iter()
            .map(|j| match &j.geometry {
                reach::model::JointGeometry::Dh(p) => p.a.hypot(p.d),
                other => panic!("{name}: DH preset expected, got {other:?}"),
            })
            .sum();
        let target = IkTarget::Pose(Isometry3::translation(bound + 0.05, 0.0, 0.0));
        let failure = solve_empty(name, &robot, kind, &target);
        assert!(matches!(failure, IkFailure::Unreachable { .. }), "{name}: {failure:?}");
    }
}

#[test]
fn inside_the_inner_hole_is_unreachable() {
    // Same structures with unequal links, so that a hole exists around the shoulder.
    let planar = Robot::from_toml_str(
        "name = \"p\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\na = 2.0\n[[joints]]\na = 0.5\n[[joints]]\na = 0.5\n",
    )
    .unwrap();
    // Links 2, 0.5, 0.5: the tip stays at least 2 − 1 = 1 m from the shoulder.
    match solve_empty("planar hole", &planar, SolverKind::Planar, &IkTarget::Position(Point3::new(0.3, 0.4, 0.0))) {
        IkFailure::Unreachable { distance, reach, .. } => {
            assert!((distance - 0.5).abs() < 1e-12 && (reach - 1.0).abs() < 1e-12, "{distance} {reach}");
        }
        other => panic!("expected Unreachable, got {other:?}"),
    }
    let yaw = Robot::from_toml_str(
        "name = \"y\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n[[joints]]\nalpha = 90\n[[joints]]\na = 1.0\n[[joints]]\na = 0.4\n",
    )
    .unwrap();
    // Links 1 and 0.4: the tip stays at least 0.6 m from the shoulder (the origin).
    match solve_empty("yaw hole", &yaw, SolverKind::YawTwoLink, &IkTarget::Position(Point3::new(0.2, 0.1, 0.2))) {
        IkFailure::Unreachable { distance, reach, .. } => {
            assert!((distance - 0.3).abs() < 1e-12 && (reach - 0.6).abs() < 1e-12, "{distance} {reach}");
        }
        other => panic!("expected Unreachable, got {other:?}"),
    }
}

#[test]
fn nan_targets_are_input_errors_for_every_solver() {
    for (name, kind) in [
        ("planar3", SolverKind::Planar),
        ("log-loader", SolverKind::YawTwoLink),
        ("varan4", SolverKind::YawPlanar3),
        ("spbu6", SolverKind::TwoLinkWrist),
        ("puma560", SolverKind::SphericalWrist),
        ("welder6r", SolverKind::ParallelAxes),
        ("ur5", SolverKind::ParallelAxes),
    ] {
        let robot = presets::get(name).unwrap();
        let solver = kind.build(&robot).unwrap();
        for target in [
            IkTarget::Position(Point3::new(f64::NAN, 0.0, 0.5)),
            IkTarget::Pose(Isometry3::translation(0.3, f64::NAN, 0.4)),
            IkTarget::Pose(Isometry3::translation(0.3, 0.1, f64::INFINITY)),
        ] {
            let result = solver.solve(&robot, &target, &IkOptions::default());
            assert!(matches!(result, Err(IkError::InvalidInput(_))), "{name}: {result:?}");
        }
    }
}
