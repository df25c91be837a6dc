//! Tests of the planar solver, its geometry, the thesis's scan and its incremental rows.
use std::f64::consts::PI;

use super::geometry::*;
use super::scan::*;
use super::scan_kernel::*;
use super::*;
use crate::ik::SingularityKind;
use crate::model::presets;
use crate::simd;
use crate::tolerance::{LIMIT_SLACK, SCAN_GRID};

#[test]
fn triangle_angle_pair_is_two_triangle_angles_bit_for_bit() {
    // A deterministic spread of side triples: generic, isoceles, degenerate, invalid.
    let mut sides = vec![[1.0, 1.0, 1.0], [1.0, 1.0, 2.0], [1.0, 2.0, 3.5], [0.5, 1.0, 1.5], [2.0, 1.0, 1.0]];
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..2000 {
        let mut side = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            0.01 + 3.0 * (state >> 11) as f64 / (1u64 << 53) as f64
        };
        sides.push([side(), side(), side()]);
    }
    let mut valid = 0;
    for [a, b, c] in sides {
        let expected = triangle_angle(c, b, a).zip(triangle_angle(a, b, c));
        let got = triangle_angle_pair(a, b, c);
        assert_eq!(
            got.map(|(x, y)| (x.to_bits(), y.to_bits())),
            expected.map(|(x, y)| (x.to_bits(), y.to_bits())),
            "sides {a} {b} {c}"
        );
        valid += usize::from(got.is_some());
    }
    assert!(valid > 500 && valid < 2000, "{valid} valid triangles: the sample misses a case");
}

#[test]
fn rotation_steps_stay_within_a_few_ulps_of_fresh_trigonometry() {
    // Angle addition from each anchor: no error accumulates over the table's rows.
    let mut worst = 0.0f64;
    for step_deg in [0.01f64, 0.001, 0.37, 1.0] {
        let step = step_deg.to_radians();
        let steps = RotationSteps::new(step, SCAN_ANCHOR_ROWS);
        for start in [0.3, 1.2, 2.0, 3.0] {
            for a in [0, 7, 1000] {
                let anchor = start + (a as f64) * step;
                let trig = anchor.sin_cos();
                for j in 0..SCAN_ANCHOR_ROWS {
                    let (s, c) = steps.turn(trig, j);
                    let exact = (start + ((a + j) as f64) * step).sin_cos();
                    worst = worst.max((s - exact.0).abs()).max((c - exact.1).abs());
                }
            }
        }
    }
    // A few units in the last place of the angles (up to ≈ 20 rad here: ulp 3.6e-15),
    // whatever the distance from the anchor; the scan needs 1e-12.
    assert!(worst < 1e-14, "drift {worst:e}");
}

#[test]
fn atan_small_is_atan() {
    for k in -1000..=1000 {
        let t = SCAN_MAX_TAN * f64::from(k) / 1000.0;
        let (got, exact) = (atan_small(t), t.atan());
        // Rounding (2 ulp) and the truncation bound |t|⁹/9.
        let bound = 2.0 * f64::EPSILON * exact.abs() + t.abs().powi(9) / 9.0;
        assert!((got - exact).abs() <= bound, "{t}: {got} vs {exact}");
    }
}

/// The incremental scan gives the direct formulas' rows (same α, same set) with every
/// angle within 1e-12 rad, on the thesis's arm and an unequal one, for targets across the
/// workspace (near both circles, every quadrant) and several steps; most rows incremental.
#[test]
fn incremental_scan_rows_are_the_direct_rows() {
    let (equal, unequal) = equal_and_unequal_arms();
    let mut worst = 0.0f64;
    for (arm, targets) in [
        (&equal, [[2.0, 1.0], [2.4, 0.2], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4]]),
        (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [2.6, 0.1], [0.7, 0.0]]),
    ] {
        for target in targets {
            for step_deg in [0.01, 0.003, 0.1, 1.0] {
                let step = f64::to_radians(step_deg);
                let scan = arm.paper_scan(target, step).unwrap();
                let Some(alpha_min) = scan.alpha_min else { continue };
                let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                let [x, y] = target;
                let (r, gamma2) = ((x * x + y * y).sqrt(), y.atan2(x));
                let direct: Vec<ScanRow> =
                    (0..count).filter_map(|i| arm.paper_row_at(r, gamma2, alpha_min + (i as f64) * step)).collect();
                assert_eq!(scan.rows.len(), direct.len(), "{target:?} at {step_deg}°");
                for (a, b) in scan.rows.iter().zip(&direct) {
                    assert_eq!(a.paper.alpha.to_bits(), b.paper.alpha.to_bits());
                    assert_eq!(a.within_limits, b.within_limits, "{target:?} at {step_deg}°");
                    let d = [a.paper.beta - b.paper.beta, a.paper.gamma - b.paper.gamma]
                        .into_iter()
                        .chain(a.q.iter().zip(&b.q).map(|(u, v)| u - v))
                        .fold(0.0f64, |m, d| m.max(d.abs()));
                    assert!(d <= 1e-12, "{target:?} at {step_deg}° row α {}: {d:e}", a.paper.alpha);
                    worst = worst.max(d);
                }
            }
        }
    }
    assert!(worst > 0.0, "no row was incremental");
    // At 0.01° nearly every row is incremental (an anchor every SCAN_ANCHOR_ROWS).
    let (_, arm) = arm();
    let scan = arm.paper_scan([2.0, 1.0], 0.01f64.to_radians()).unwrap();
    let alpha_min = scan.alpha_min.unwrap();
    let frame = ScanFrame::new(arm.lengths(), [2.0, 1.0]);
    let (rows, direct) = arm.scan_rows(&frame, alpha_min, 0.01f64.to_radians(), scan.rows.len());
    assert_eq!(rows.len(), 9001);
    eprintln!("incremental scan: largest difference {worst:e} rad; at 0.01° {direct} of 9001 rows direct");
    assert!(direct <= 9001 / SCAN_ANCHOR_ROWS + 5, "{direct} rows computed directly");
}

/// The segment kernel ([`ScanSegment`], pass by pass) gives the row-by-row increments'
/// rows bit for bit, anchors and segment edges included: targets whose scans leave
/// segments early (ill-conditioned triangles near the inner circle, large turns at coarse
/// steps, β near 180°) and ones that never do, on equal and unequal arms.
#[test]
fn segment_kernel_is_the_row_by_row_increments() {
    let (equal, unequal) = equal_and_unequal_arms();
    let mut cut_short = 0;
    for (arm, targets) in [
        (&equal, [[2.0, 1.0], [2.4, 0.2], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4], [1e-3, 1.0]]),
        (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [2.6, 0.1], [0.7, 0.0], [0.5, 0.4]]),
    ] {
        for target in targets {
            for step_deg in [0.01, 0.003, 0.1, 0.7, 1.0, 3.0] {
                let step = f64::to_radians(step_deg);
                let Some(alpha_min) = arm.paper_scan(target, step).unwrap().alpha_min else { continue };
                let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                let frame = ScanFrame::new(arm.lengths(), target);
                let (rows, direct) = arm.scan_rows(&frame, alpha_min, step, count);
                let reference = arm.scan_rows_one_by_one(&frame, alpha_min, step, count);
                assert_eq!(rows.len(), reference.len(), "{target:?} at {step_deg}°");
                for (a, b) in rows.iter().zip(&reference) {
                    assert_eq!(row_bits(a), row_bits(b), "{target:?} at {step_deg}° row α {}", a.paper.alpha);
                }
                // Anchors beyond one per full segment: segments cut short.
                cut_short += usize::from(direct > count.div_ceil(SCAN_ANCHOR_ROWS));
            }
        }
    }
    assert!(cut_short > 0, "no scan left a segment early");
}

/// The scan's kernel ([`ScanKernel`]) gives the same rows, bit for bit, and the same count
/// of rows computed directly, at every vector-instruction level the processor has: scans
/// with and without segments cut short, rows bent back and rows outside the limits.
#[test]
fn scan_rows_are_the_same_bits_at_every_simd_level() {
    let (equal, unequal) = equal_and_unequal_arms();
    let mut rows_compared = 0;
    for (arm, targets) in [
        (&equal, [[2.0, 1.0], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4], [1e-3, 1.0]]),
        (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [0.7, 0.0], [0.5, 0.4]]),
    ] {
        for target in targets {
            for step_deg in [0.01, 0.003, 0.1, 0.7, 3.0] {
                let step = f64::to_radians(step_deg);
                let Some(alpha_min) = arm.paper_scan(target, step).unwrap().alpha_min else { continue };
                let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                let frame = ScanFrame::new(arm.lengths(), target);
                let (reference, direct) = arm.scan_rows_at(simd::Level::Baseline, &frame, alpha_min, step, count);
                for level in simd::levels() {
                    let (rows, level_direct) = arm.scan_rows_at(level, &frame, alpha_min, step, count);
                    let at = format!("{target:?} at {step_deg}°, level {}", level.name());
                    assert_eq!((rows.len(), level_direct), (reference.len(), direct), "{at}");
                    for (a, b) in rows.iter().zip(&reference) {
                        assert_eq!(row_bits(a), row_bits(b), "{at} row α {}", a.paper.alpha);
                    }
                    rows_compared += rows.len();
                }
            }
        }
    }
    assert!(rows_compared > 100_000, "{rows_compared} rows compared");
}

/// A row's values as bits, to compare rows bit for bit.
fn row_bits(r: &ScanRow) -> ([u64; 6], bool) {
    let p = [r.paper.alpha, r.paper.beta, r.paper.gamma, r.q[0], r.q[1], r.q[2]];
    (p.map(f64::to_bits), r.within_limits)
}

/// planar3's arm and one with unequal links (1.3, 0.8, 0.6) and planar3's limits.
fn equal_and_unequal_arms() -> (PlanarRedundant, PlanarRedundant) {
    let (_, equal) = arm();
    let mut unequal = equal.clone();
    for (link, l) in unequal.chain.links.iter_mut().zip([1.3, 0.8, 0.6]) {
        link.length = l;
    }
    (equal, unequal)
}

/// Where the scan's branch-free test says a row's values fit as they are, the fit into the
/// limits gives them back bit for bit, within the limits: at and around (−π, π]'s ends, the
/// limits with their slack, whole turns away and NaN, on planar3's limits and others.
#[test]
fn fits_as_is_is_the_fit_leaving_the_values() {
    let (_, planar3) = arm();
    let mut other = planar3.clone();
    other.limits = [Limits::new(-3.5, 3.5), Limits::new(0.0, 6.0), Limits::UNLIMITED];
    let mut values = vec![f64::NAN, f64::INFINITY, -f64::INFINITY];
    for base in [0.0, PI, -PI, 3.5, -3.5, 6.0, PI + LIMIT_SLACK, -PI - LIMIT_SLACK, TAU, -TAU] {
        for k in -3i64..=3 {
            let v = base + k as f64 * 0.25;
            values.extend([v, v.next_up(), v.next_down(), v - LIMIT_SLACK, v + LIMIT_SLACK]);
        }
    }
    let (mut as_is, mut fitted) = (0, 0);
    for arm in [&planar3, &other] {
        for &a in &values {
            for &b in &values {
                for c in [0.5, -0.5, a] {
                    let raw = [a, b, c];
                    if arm.fits_as_is(&raw) {
                        as_is += 1;
                        let (q, within) = arm.fit_row(raw);
                        assert_eq!(q.map(f64::to_bits), raw.map(f64::to_bits), "{raw:?}");
                        assert!(within, "{raw:?}");
                    } else {
                        fitted += 1;
                    }
                }
            }
        }
    }
    assert!(as_is > 1000 && fitted > 1000, "{as_is} as is, {fitted} fitted: the sample misses a case");
}

fn arm() -> (Robot, PlanarRedundant) {
    let robot = presets::get("planar3").unwrap();
    let arm = PlanarRedundant::from_robot(&robot).unwrap();
    (robot, arm)
}

#[test]
fn reads_the_preset() {
    let (_, arm) = arm();
    assert_eq!(arm.lengths(), [1.0, 1.0, 1.0]);
    assert_eq!(arm.workspace(), (0.0, 3.0));
    let q = [0.3, -0.4, 0.5];
    let phi = arm.link_angles(&q);
    assert!((phi[0] - 0.3).abs() < 1e-15 && (phi[1] + 0.1).abs() < 1e-15 && (phi[2] - 0.4).abs() < 1e-15);
    let back = arm.joints_from_link_angles(&phi);
    assert!(back.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-15));
}

#[test]
fn rejects_other_structures() {
    for name in ["log-loader", "varan4", "puma560", "spbu6", "ur5", "panda", "welder6r"] {
        let robot = presets::get(name).unwrap();
        let err = PlanarRedundant::from_robot(&robot).unwrap_err();
        assert!(matches!(err, IkError::Unsupported { .. }), "{name}: {err}");
    }
    let err = PlanarRedundant::from_robot(&presets::get("log-loader").unwrap()).unwrap_err();
    assert!(err.to_string().contains("not parallel"), "{err}");
}

#[test]
fn two_link_branches_and_boundaries() {
    // l1 = 2, l2 = 1 to (2, 1): elbow angles ±acos((5 − 4 − 1)/4) = ±90°.
    let TwoLink::In([Some(a), Some(b)]) = two_link(2.0, 1.0, [2.0, 1.0], 0.0) else { panic!() };
    for e in [a, b] {
        let x = 2.0 * e.phi[0].cos() + e.phi[1].cos();
        let y = 2.0 * e.phi[0].sin() + e.phi[1].sin();
        assert!((x - 2.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12);
        assert!((e.bend.abs() - PI / 2.0).abs() < 1e-12);
    }
    assert_eq!(two_link(2.0, 1.0, [3.5, 0.0], 0.0), TwoLink::Out { distance: 3.5, reach: 3.0 });
    assert_eq!(two_link(2.0, 1.0, [0.5, 0.0], 0.0), TwoLink::Out { distance: 0.5, reach: 1.0 });
    let TwoLink::In([Some(s), None]) = two_link(2.0, 1.0, [0.0, 3.0], 0.0) else { panic!() };
    assert_eq!(s.singular, Some(SingularityKind::Elbow));
    assert!((s.phi[0] - PI / 2.0).abs() < 1e-12 && s.bend == 0.0);
    let TwoLink::In([Some(f), None]) = two_link(1.0, 1.0, [0.0, 0.0], 0.7) else { panic!() };
    assert_eq!(f.singular, Some(SingularityKind::Shoulder));
    assert_eq!(f.phi[0], 0.7);
}

#[test]
fn intervals_match_a_brute_force_scan() {
    for (l, p) in [
        ([1.0, 1.0, 1.0], [2.0, 1.0]),
        ([1.0, 1.0, 1.0], [0.3, 0.2]),
        ([2.0, 0.5, 1.0], [1.0, 0.4]),
        ([2.0, 0.5, 1.0], [3.2, -0.5]),
        ([0.5, 0.7, 2.0], [0.1, 0.0]),
        ([0.5, 0.7, 2.0], [2.9, 0.0]),
        ([1.0, 1.0, 3.0], [0.5, 0.5]),
    ] {
        let ivs = phi_intervals(l[0], l[1], l[2], p);
        for k in 0..3600 {
            let phi = -PI + (k as f64 + 0.5) * TAU / 3600.0;
            let w = [p[0] - l[2] * phi.cos(), p[1] - l[2] * phi.sin()];
            let d = w[0].hypot(w[1]);
            let feasible = d <= l[0] + l[1] && d >= (l[0] - l[1]).abs();
            let inside = ivs.iter().any(|iv| {
                let t = iv.start + (phi - iv.start).rem_euclid(TAU);
                t <= iv.end
            });
            assert_eq!(feasible, inside, "lengths {l:?} target {p:?} φ {phi}");
        }
    }
}

#[test]
fn pose_target_gives_both_elbows() {
    let (robot, arm) = arm();
    let q = [0.4, -0.9, -0.6];
    let target = IkTarget::Pose(robot.fk(&q).unwrap());
    let sols = arm.solve(&robot, &target, &IkOptions::default()).unwrap();
    assert_eq!(sols.solutions.len(), 2);
    let up = sols.solutions.iter().find(|s| s.branch.get("elbow") == Some("up")).unwrap();
    assert!(up.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9), "{:?}", up.q);
}

#[test]
fn bad_options_are_rejected() {
    let (robot, arm) = arm();
    let target = IkTarget::Position(Point3::new(2.0, 1.0, 0.0));
    let tiny = IkOptions { redundancy_step: 1e-6, ..IkOptions::default() };
    assert!(matches!(arm.solve(&robot, &target, &tiny), Err(IkError::InvalidInput(_))));
    // The step only matters when the self-motion is sampled.
    let fixed = IkOptions { free_parameter: Some(0.5), ..tiny };
    assert!(arm.solve(&robot, &target, &fixed).unwrap().solutions.len() == 2);
    let nan = IkOptions { free_parameter: Some(f64::NAN), ..IkOptions::default() };
    assert!(matches!(arm.solve(&robot, &target, &nan), Err(IkError::InvalidInput(_))));
    let seed = IkOptions { seed: Some(vec![0.0; 2]), ..IkOptions::default() };
    assert!(matches!(arm.solve(&robot, &target, &seed), Err(IkError::Kinematics(_))));
    assert!(matches!(arm.paper_scan([2.0, 1.0], 0.0), Err(IkError::InvalidInput(_))));
    assert!(matches!(arm.paper_scan([2.0, 1.0], 1e-9), Err(IkError::InvalidInput(_))));
}

#[test]
fn configurations_are_the_two_elbows_in_the_order_of_the_solve() {
    use crate::ik::configuration_order::{check, labels};
    let robot = presets::get("planar3").unwrap();
    let s = PlanarRedundant::from_robot(&robot).unwrap();
    assert_eq!(labels(&s, &robot), ["elbow=up", "elbow=down"]);
    assert!(check(&s, &robot, 200) > 100);
    // Position targets label the sampled redundancy parameter: not one label per branch.
    assert!(!s.enumerates_all_branches());
}
