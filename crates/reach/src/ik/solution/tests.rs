use nalgebra::{Point3, Vector3};

use super::candidate::*;
use super::check::*;
use super::*;
use crate::ik::IkTarget;
use crate::kinematics::Lanes;
use crate::model::Robot;
use crate::tolerance::IK_DUPLICATE;

#[test]
fn joint_wraps_match_the_robot_rule_with_and_without_the_mask() {
    // A bounded yaw takes literal differences (the one rule, `Joint::difference`)…
    assert_eq!(JointWraps::for_robot(&yaw_slide()), JointWraps::Mask(0));
    // …a continuous one wraps.
    let robot = Robot::from_toml_str(
        "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
         [[joints]]\nname = \"yaw\"\nalpha = -90\n\
         [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
    )
    .unwrap();
    let wraps = JointWraps::for_robot(&robot);
    assert_eq!(wraps, JointWraps::Mask(0b01));
    let rule = crate::effort::Differences::for_robot(&robot);
    for (i, (a, b)) in [(0, (3.0, -3.0)), (1, (3.0, -3.0)), (0, (0.1, 0.4)), (1, (-9.0, 9.0))] {
        assert_eq!(wraps.diff(i, a, b), rule.diff(i, a, b), "joint {i}");
    }
    // Joints beyond the mask are literal, never a shift overflow.
    assert_eq!(wraps.diff(64, 3.0, -3.0), -6.0);
    assert_eq!(wraps.diff(200, 3.0, -3.0), -6.0);
    let wide = JointWraps::Wide(vec![false, true]);
    assert_eq!(wide.diff(0, 3.0, -3.0), -6.0);
    assert!((wide.diff(1, 3.0, -3.0) - (2.0 * std::f64::consts::PI - 6.0)).abs() < 1e-12);
    assert_eq!(wide.diff(2, 3.0, -3.0), -6.0);
}

/// Base yaw about z, then a 10 m prismatic slide perpendicular to it (DH α₁ = −90°): the
/// tool is at `d·(−sin θ, cos θ, 0)`, so `(0, d)` and `(π, −d)` reach the same point.
fn yaw_slide() -> Robot {
    Robot::from_toml_str(
        "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
         [[joints]]\nname = \"yaw\"\nalpha = -90\nlimits = [-180, 180]\n\
         [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
    )
    .unwrap()
}

#[test]
fn closest_to_takes_prismatic_changes_literally() {
    let robot = yaw_slide();
    let pi = std::f64::consts::PI;
    let target = IkTarget::Position(robot.fk(&[0.0, 4.0]).unwrap().translation.vector.into());
    let mut candidates = vec![
        Candidate::new(vec![0.0, 4.0], Branch::new([("side", "front")])),
        Candidate::new(vec![pi, -4.0], Branch::new([("side", "back")])),
    ];
    let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
    assert_eq!(all.solutions.len(), 2, "{all:?}");
    // From (0, −4): "front" moves the slide 8 m (cost 8), "back" turns the base by π (cost π).
    // Wrapping the slide's 8 m as an angle (8 − 2π ≈ 1.72) would wrongly prefer "front".
    let chosen = all.closest_to(&[0.0, -4.0], &[]).unwrap();
    assert_eq!(chosen.branch.get("side"), Some("back"), "{chosen:?}");
    // And from (0, 3.9) the slide change is small and "front" wins.
    let chosen = all.closest_to(&[0.0, 3.9], &[]).unwrap();
    assert_eq!(chosen.branch.get("side"), Some("front"), "{chosen:?}");
}

#[test]
fn prismatic_values_a_turn_apart_are_distinct_solutions() {
    // Two collinear slides along z: (0, 2π) and (2π, 0) reach the same point but are
    // different configurations (a revolute pair 2π apart would be one).
    let robot = Robot::from_toml_str(
        "name = \"double-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
         [[joints]]\nname = \"s1\"\nkind = \"prismatic\"\nlimits = [0, 10]\n\
         [[joints]]\nname = \"s2\"\nkind = \"prismatic\"\nlimits = [0, 10]\n",
    )
    .unwrap();
    let tau = std::f64::consts::TAU;
    let target = IkTarget::Position(robot.fk(&[0.0, tau]).unwrap().translation.vector.into());
    let mut candidates = vec![
        Candidate::new(vec![0.0, tau], Branch::new([("slide", "2")])),
        Candidate::new(vec![tau, 0.0], Branch::new([("slide", "1")])),
    ];
    let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
    assert_eq!(all.solutions.len(), 2, "{all:?}");
}

#[test]
fn closest_index_counts_every_solution_and_skips_infeasible_ones() {
    // The yaw-slide robot with the yaw limited to [−90°, 90°]: "back" (yaw ±π) is outside.
    let robot = Robot::from_toml_str(
        "name = \"yaw-slide\"\nlength_unit = \"m\"\nangle_unit = \"deg\"\n\
         [[joints]]\nname = \"yaw\"\nalpha = -90\nlimits = [-90, 90]\n\
         [[joints]]\nname = \"slide\"\nkind = \"prismatic\"\nlimits = [-10, 10]\n",
    )
    .unwrap();
    let pi = std::f64::consts::PI;
    let target = IkTarget::Position(robot.fk(&[0.0, 4.0]).unwrap().translation.vector.into());
    let mut candidates = vec![
        Candidate::new(vec![pi, -4.0], Branch::new([("side", "back")])),
        Candidate::new(vec![0.0, 4.0], Branch::new([("side", "front")])),
    ];
    let all = finish(&robot, &target, &mut candidates, "test", IkFailure::OrientationUnreachable).unwrap();
    assert_eq!(all.solutions.len(), 2, "{all:?}");
    let back = all.solutions.iter().position(|s| s.branch.get("side") == Some("back")).unwrap();
    assert!(!all.solutions[back].within_limits, "{all:?}");
    // From (π, −4) "back" costs nothing but is outside the limits: "front" is chosen, and its
    // index counts the infeasible solution too.
    let front = all.solutions.iter().position(|s| s.branch.get("side") == Some("front")).unwrap();
    assert_eq!(all.closest_index(&[pi, -4.0], &[]), Some(front));
    let chosen = all.closest_to(&[pi, -4.0], &[]).unwrap();
    assert!(std::ptr::eq(&all.solutions[front], chosen));
    // No feasible solution: no index.
    let none = all.restricted_to(&Branch::new([("side", "back")]));
    assert_eq!(none.closest_index(&[0.0, 0.0], &[]), None);
}

/// The pose errors as the scalar check computed them before the lanes (nalgebra's
/// products, one tool pose at a time).
fn scalar_errors(target: &IkTarget, t: &nalgebra::IsometryMatrix3<f64>) -> (f64, f64) {
    match target {
        IkTarget::Pose(pose) => {
            let r_inv = pose.rotation.to_rotation_matrix().inverse();
            let dp = (t.translation.vector - pose.translation.vector).norm();
            let m = (r_inv * t.rotation).into_inner();
            let vee = Vector3::new(m[(2, 1)] - m[(1, 2)], m[(0, 2)] - m[(2, 0)], m[(1, 0)] - m[(0, 1)]);
            (dp, crate::angle::atan2(0.5 * vee.norm(), 0.5 * (m.trace() - 1.0)))
        }
        IkTarget::Position(p) => ((Point3::from(t.translation.vector) - p).norm(), 0.0),
    }
}

#[test]
fn lane_verification_is_the_scalar_check_bit_for_bit() {
    // Every preset the lanes verify: the tool poses of `fk_lanes` and the errors of
    // `Check::errors` are those of `fk_matrix` and the scalar formula, bit for bit, so the
    // accepted solutions and their reported errors do not depend on the lanes.
    let mut rng = crate::rng::SplitMix64(16);
    for name in crate::model::presets::names() {
        let robot = crate::model::presets::get(name).unwrap();
        let dof = robot.dof();
        if dof > LANE_DOF {
            continue;
        }
        for _ in 0..8 {
            let qs: Vec<Vec<f64>> =
                (0..VERIFY_LANES).map(|_| (0..dof).map(|_| (2.0 * rng.next_f64() - 1.0) * 4.0).collect()).collect();
            let mut lanes = [[0.0; VERIFY_LANES]; LANE_DOF];
            for (l, q) in qs.iter().enumerate() {
                for (j, v) in q.iter().enumerate() {
                    lanes[j][l] = *v;
                }
            }
            let t = robot.fk_lanes(&lanes[..dof]);
            let near = robot.fk(&qs[0]).unwrap();
            for target in [IkTarget::Pose(near), IkTarget::Position(near.translation.vector.into())] {
                let check = Check::new(&target);
                let (position, sin, cos) = check.errors(&t);
                for (l, q) in qs.iter().enumerate() {
                    let scalar = robot.fk_matrix(q).unwrap();
                    let m = scalar.rotation.matrix();
                    for i in 0..3 {
                        assert_eq!(t.p[i][l].to_bits(), scalar.translation.vector[i].to_bits(), "{name} {q:?}");
                        for j in 0..3 {
                            assert_eq!(t.r[i][j][l].to_bits(), m[(i, j)].to_bits(), "{name} {q:?}");
                        }
                    }
                    // One lane alone (the kernel of a single candidate) gives the same bits.
                    let one: Vec<Lanes<1>> = q.iter().map(|v| [*v]).collect();
                    assert_eq!(robot.fk_lanes(&one).p[0][0].to_bits(), t.p[0][l].to_bits(), "{name} {q:?}");
                    let (p, o) = scalar_errors(&target, &scalar);
                    assert_eq!(position[l].to_bits(), p.to_bits(), "{name} {q:?}");
                    assert_eq!(
                        check.angles::<true, VERIFY_LANES>(&sin, &cos)[l].to_bits(),
                        o.to_bits(),
                        "{name} {q:?}"
                    );
                    assert_eq!(
                        check.angles::<false, VERIFY_LANES>(&sin, &cos)[l].to_bits(),
                        o.to_bits(),
                        "{name} {q:?}"
                    );
                }
            }
        }
    }
}

/// The solves of `solver` for `target` at SIMD level `level`: that of `solve_into` at this
/// level ([`solve_at`]), and both kernel variants ([`SolveKernel`], `WIDE` or not) run at it.
fn solves_at<S: LaneSolve>(
    level: crate::simd::Level,
    solver: &S,
    robot: &Robot,
    target: &IkTarget,
) -> [IkSolutions; 3] {
    let options = super::super::IkOptions::default();
    let (mut chosen, mut wide, mut narrow) = (IkSolutions::default(), IkSolutions::default(), IkSolutions::default());
    solve_at(level, solver, robot, target, &options, &mut chosen).unwrap();
    crate::simd::run_at(level, SolveKernel::<S, true> { solver, robot, target, options: &options, out: &mut wide })
        .unwrap();
    crate::simd::run_at(level, SolveKernel::<S, false> { solver, robot, target, options: &options, out: &mut narrow })
        .unwrap();
    [chosen, wide, narrow]
}

/// Every solve of [`solves_at`] at every level has the bits of `solve_into` at the
/// baseline level.
fn assert_same_bits_at_every_level<S: LaneSolve>(solver: &S, robot: &Robot, target: &IkTarget, what: &str) {
    let options = super::super::IkOptions::default();
    let mut base = IkSolutions::default();
    solve_at(crate::simd::Level::Baseline, solver, robot, target, &options, &mut base).unwrap();
    for level in crate::simd::levels() {
        for (variant, solved) in
            ["solve_into", "wide kernel", "narrow kernel"].iter().zip(solves_at(level, solver, robot, target))
        {
            assert_same_bits(&solved, &base, &format!("{what} at {}, {variant}", level.name()));
        }
    }
}

/// `a` and `b` with the same solutions, labels and flags, and the same bits in every
/// joint value and error.
fn assert_same_bits(a: &IkSolutions, b: &IkSolutions, what: &str) {
    assert_eq!(a, b, "{what}");
    for (x, y) in a.solutions.iter().zip(&b.solutions) {
        let bits = |s: &IkSolution| -> Vec<u64> {
            s.q.iter().chain([&s.position_error, &s.orientation_error]).map(|v| v.to_bits()).collect()
        };
        assert_eq!(bits(x), bits(y), "{what}");
    }
}

#[test]
fn closed_form_solves_give_the_same_bits_at_every_simd_level() {
    use super::super::parallel_axes::ParallelAxes;
    use super::super::spherical_wrist::SphericalWrist;
    use super::super::two_link_wrist::TwoLinkWrist;
    let mut rng = crate::rng::SplitMix64(17);
    let mut solved_presets = 0;
    for name in crate::model::presets::names() {
        let robot = crate::model::presets::get(name).unwrap();
        if robot.dof() != 6 {
            continue;
        }
        let (sw, tw, pa) =
            (SphericalWrist::from_robot(&robot), TwoLinkWrist::from_robot(&robot), ParallelAxes::from_robot(&robot));
        if sw.is_err() && tw.is_err() && pa.is_err() {
            continue;
        }
        solved_presets += 1;
        for k in 0..40 {
            let q: Vec<f64> = robot
                .joints()
                .iter()
                .map(|j| {
                    let (lo, hi) = (j.limits.lower.max(-3.0), j.limits.upper.min(3.0));
                    lo + (hi - lo) * rng.next_f64()
                })
                .collect();
            // Generic poses, a wrist singularity (q5 = 0) and a position target.
            let mut q = q;
            if k == 0 {
                q[4] = 0.0;
            }
            let pose = robot.fk(&q).unwrap();
            let targets = [IkTarget::Pose(pose), IkTarget::Position(pose.translation.vector.into())];
            for target in &targets {
                let what = format!("{name} {q:?}");
                if let Ok(s) = &sw {
                    assert_same_bits_at_every_level(s, &robot, target, &what);
                }
                if let Ok(s) = &tw {
                    assert_same_bits_at_every_level(s, &robot, target, &what);
                }
                if let Ok(s) = &pa {
                    assert_same_bits_at_every_level(s, &robot, target, &what);
                }
            }
        }
    }
    assert!(solved_presets >= 4, "puma560, ur5, welder6r, spbu6 at least: {solved_presets}");
}

#[test]
fn shared_prefix_walk_is_the_lane_walk_bit_for_bit() {
    // Pairs of lanes sharing their first k joints (as the two wrists of an arm share θ1…θ3):
    // `shared_prefix` finds k, and the walk of the prefix on 4 lanes gives the poses of the
    // plain 8-lane walk, bit for bit, for every preset and every k.
    let mut rng = crate::rng::SplitMix64(42);
    for name in crate::model::presets::names() {
        let robot = crate::model::presets::get(name).unwrap();
        let dof = robot.dof();
        if dof > LANE_DOF {
            continue;
        }
        for k in 0..=dof {
            let mut q = [[0.0; VERIFY_LANES]; LANE_DOF];
            for (j, joint) in q.iter_mut().enumerate().take(dof) {
                for l in 0..VERIFY_LANES {
                    joint[l] = if j < k && l % 2 == 1 { joint[l - 1] } else { (2.0 * rng.next_f64() - 1.0) * 4.0 };
                }
            }
            let finite = [true; VERIFY_LANES];
            let found = shared_prefix::<VERIFY_LANES, 4>(&robot, &mut q[..dof], &finite, VERIFY_LANES);
            let expected = if robot.prefix_without_mimics(k) { k } else { 0 };
            assert_eq!(found, expected, "{name} k = {k}");
            let prefix: Vec<Lanes<4>> = q[..k].iter().map(|j| std::array::from_fn(|g| j[2 * g])).collect();
            if !robot.prefix_without_mimics(k) {
                continue;
            }
            let shared = robot.fk_lanes_shared(&prefix, &q[..dof]);
            let plain = robot.fk_lanes(&q[..dof]);
            for l in 0..VERIFY_LANES {
                for i in 0..3 {
                    assert_eq!(shared.p[i][l].to_bits(), plain.p[i][l].to_bits(), "{name} k = {k}");
                    for j in 0..3 {
                        assert_eq!(shared.r[i][j][l].to_bits(), plain.r[i][j][l].to_bits(), "{name} k = {k}");
                    }
                }
            }
        }
        // A lane not verified (beyond the count, or not finite) takes its partner's values
        // and does not part the pair.
        let mut q = [[0.0; VERIFY_LANES]; LANE_DOF];
        for joint in q.iter_mut().take(dof) {
            for l in 0..VERIFY_LANES {
                joint[l] = if l % 2 == 1 { joint[l - 1] } else { rng.next_f64() };
            }
            joint[3] = 9.0;
            joint[7] = -9.0;
        }
        let mut finite = [true; VERIFY_LANES];
        finite[3] = false;
        let found = shared_prefix::<VERIFY_LANES, 4>(&robot, &mut q[..dof], &finite, 7);
        assert_eq!(found, if robot.prefix_without_mimics(dof) { dof } else { 0 }, "{name}");
    }
}

#[test]
fn same_angle_is_the_wrapped_difference_test() {
    use std::f64::consts::{PI, TAU};
    let wrapped = |a: f64, b: f64| crate::angle::wrap(a - b).abs() < IK_DUPLICATE;
    let mut rng = crate::rng::SplitMix64(3);
    let e = IK_DUPLICATE;
    let mut pairs = vec![
        (PI, -PI),
        (PI - e, -PI),
        (PI - 0.5 * e, -PI + 0.25 * e),
        (0.0, TAU),
        (0.0, TAU - e),
        (1.0, 1.0 + PI),
        (-3.0, 3.0),
    ];
    for _ in 0..20_000 {
        let a = (2.0 * rng.next_f64() - 1.0) * 10.0;
        let k = [0.0, PI, TAU, -TAU, 2.0 * TAU][rng.below(5)];
        pairs.push((a, a + k + (2.0 * rng.next_f64() - 1.0) * 3.0 * e));
    }
    for (a, b) in pairs {
        assert_eq!(same_angle(a, b), wrapped(a, b), "{a} {b}");
    }
}

#[test]
fn surely_distinct_claims_only_what_both_rules_prove() {
    // `surely_distinct` ⇒ different by the revolute rule and by the prismatic one, on the
    // boundaries (IK_DUPLICATE, π, 2π, NaN) and on random pairs near them; and it does
    // prove the usual cases (distinct branches, the two wrists about π apart).
    use std::f64::consts::{PI, TAU};
    let e = IK_DUPLICATE;
    let mut rng = crate::rng::SplitMix64(5);
    let mut pairs = vec![(0.0, e), (0.0, 0.5 * e), (PI, -PI), (0.0, PI), (0.0, TAU - e), (0.0, TAU - 2.0 * e)];
    pairs.extend([(0.0, TAU), (0.0, TAU + e), (1.0, f64::NAN), (0.0, f64::INFINITY), (PI - 0.5 * e, -PI)]);
    for _ in 0..20_000 {
        let a = (2.0 * rng.next_f64() - 1.0) * 10.0;
        let k = [0.0, PI, TAU, -TAU, 2.0 * TAU][rng.below(5)];
        pairs.push((a, a + k + (2.0 * rng.next_f64() - 1.0) * 3.0 * e));
    }
    let mut proved = 0;
    for (a, b) in pairs {
        if surely_distinct(a, b) {
            proved += 1;
            assert!(!same_angle(a, b), "revolute {a} {b}");
            assert!((a - b).abs() >= IK_DUPLICATE, "prismatic {a} {b}");
        }
    }
    assert!(proved > 5_000, "{proved}");
    assert!(surely_distinct(0.3, 0.3 + PI) && surely_distinct(0.3, 0.3 - PI + 1e-12) && surely_distinct(-2.0, 1.0));
    assert!(!surely_distinct(1.0, 1.0) && !surely_distinct(1.0, 1.0 + TAU) && !surely_distinct(1.0, f64::NAN));
}

#[test]
fn flag_bits_report_the_kinds_in_the_fixed_order() {
    let all = FlagBits::default()
        .with(SingularityKind::Wrist, true)
        .with(SingularityKind::Jacobian, false)
        .with(SingularityKind::Shoulder, true);
    assert_eq!(all.iter().collect::<Vec<_>>(), [SingularityKind::Shoulder, SingularityKind::Wrist]);
    assert_eq!(all.first(), Some(SingularityKind::Shoulder));
    assert!(FlagBits::default().is_empty() && FlagBits::default().first().is_none());
}
