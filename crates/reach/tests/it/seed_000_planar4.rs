//! Seed 000's future work (notes 000 §8: "a 4-link manipulator"): the table scan and the
//! minimum-change choice for planar arms of n ≥ 3 links (`ik::planar_scan`, preset `planar4`).
//! Checked against the thesis's own three-link scan (a different construction: the law-of-
//! cosines formulas of notes 000 §3.1) and, for four links, against a brute force written here
//! from the DH table alone.

use std::f64::consts::PI;

use nalgebra::Point3;
use reach::ik::IkFailure;
use reach::ik::planar_scan::ScanOutcome::{Chosen, NoSolution};
use reach::ik::planar_scan::{MAX_SCAN_NODES, ScanChoice, scan_min_change};
use reach::model::presets;

fn d(v: f64) -> f64 {
    v.to_radians()
}

fn chosen(robot: &str, target: [f64; 2], current: &[f64], step_deg: f64) -> ScanChoice {
    let r = presets::get(robot).unwrap();
    match scan_min_change(&r, &Point3::new(target[0], target[1], 0.0), current, d(step_deg)).unwrap() {
        Chosen(c) => c,
        NoSolution(f) => panic!("{robot} {target:?}: {f:?}"),
    }
}

#[test]
fn three_links_reproduce_the_thesis_choice() {
    // Notes 000 §6.3: start (α, β, γ) = (150, 140, 60) → q = (60, −40, −30)°, target (2.4, 0.2).
    // The thesis's scan at 0.001° chooses α = 149.999959, β = 121.045829, γ = 55.198996 with
    // S = 23.755217°; the minimum is at α = 150° (no change of α), which the grid from −180°
    // in steps of 0.01° hits exactly.
    let c = chosen("planar3", [2.4, 0.2], &[d(60.0), d(-40.0), d(-30.0)], 0.01);
    let deg: Vec<f64> = c.q.iter().map(|v| v.to_degrees()).collect();
    let thesis = [55.198996, 121.045829 - 180.0, 149.999959 - 180.0];
    for (a, b) in deg.iter().zip(thesis) {
        assert!((a - b).abs() < 2e-4, "{deg:?} vs {thesis:?}");
    }
    assert!((c.s.to_degrees() - 23.755217).abs() < 2e-4, "{}", c.s.to_degrees());
    assert_eq!(c.nodes, 18001);
    // The thesis's own table, independently: paper_scan + select_min_s at 0.01° (its grid
    // starts at α_min and misses 150° by 0.003°, so its S is 0.0014° larger).
    let arm = reach::ik::planar::PlanarRedundant::from_robot(&presets::get("planar3").unwrap()).unwrap();
    let scan = arm.paper_scan([2.4, 0.2], d(0.01)).unwrap();
    let start = reach::model::planar_angles::InteriorAngles { alpha: d(150.0), beta: d(140.0), gamma: d(60.0) };
    let (_, s) = scan.select_min_s(&start).unwrap();
    assert!(c.s <= s && s - c.s < d(0.002), "{} vs {}", c.s.to_degrees(), s.to_degrees());
}

/// The four-link choice by brute force from the DH table (a = 1 m, no offsets): for every grid
/// node (q3, q4) the tail from joint 2 is v = (1, 0) + u(q3) + u(q3 + q4) in link 2's frame;
/// joints 1 and 2 follow from the law of cosines.
fn brute_force(target: [f64; 2], current: &[f64; 4], step: f64) -> (f64, [f64; 4]) {
    let wrap = |a: f64| {
        let w = (a + PI).rem_euclid(2.0 * PI) - PI;
        if w <= -PI { w + 2.0 * PI } else { w }
    };
    let r2 = target[0] * target[0] + target[1] * target[1];
    let mut best = (f64::INFINITY, [0.0; 4]);
    let n = (PI / step + 1e-9).floor() as usize + 1;
    for i in 0..n {
        let q3 = -PI + i as f64 * step;
        for j in 0..n {
            let q4 = -PI + j as f64 * step;
            let v = [1.0 + q3.cos() + (q3 + q4).cos(), q3.sin() + (q3 + q4).sin()];
            let (dv, b0) = (v[0].hypot(v[1]), v[1].atan2(v[0]));
            let c = (r2 - 1.0 - dv * dv) / (2.0 * dv);
            if c.abs() > 1.0 {
                continue;
            }
            for e in [c.acos(), -c.acos()] {
                let q1 = wrap(target[1].atan2(target[0]) - (dv * e.sin()).atan2(1.0 + dv * e.cos()));
                let q2 = wrap(e - b0);
                if !(-1e-9..=PI + 1e-9).contains(&q1) || !(-PI - 1e-9..=1e-9).contains(&q2) {
                    continue;
                }
                let q = [q1, q2, q3, q4];
                let s: f64 = q.iter().zip(current).map(|(a, b)| (a - b).abs()).sum();
                if s < best.0 {
                    best = (s, q);
                }
            }
        }
    }
    best
}

#[test]
fn four_links_match_a_brute_force_from_the_dh_table() {
    let robot = presets::get("planar4").unwrap();
    for (target, current) in [
        ([2.4, 0.2], [d(60.0), d(-40.0), d(-30.0), d(-20.0)]),
        ([1.5, 1.5], [d(100.0), d(-60.0), d(-60.0), d(-40.0)]),
        ([-1.0, 2.0], [d(120.0), d(-30.0), d(-50.0), d(-70.0)]),
        ([3.2, 0.9], [d(30.0), d(-10.0), d(-20.0), d(-15.0)]),
    ] {
        let c = chosen("planar4", target, &current, 1.0);
        let (s, q) = brute_force(target, &current, d(1.0));
        assert!((c.s - s).abs() < 1e-9, "{target:?}: S {} vs {}", c.s.to_degrees(), s.to_degrees());
        for (a, b) in c.q.iter().zip(q) {
            assert!((a - b).abs() < 1e-9, "{target:?}: {:?} vs {q:?}", c.q);
        }
        let tool = robot.fk(&c.q).unwrap().translation.vector;
        assert!((tool.x - target[0]).abs() < 1e-9 && (tool.y - target[1]).abs() < 1e-9 && tool.z.abs() < 1e-12);
        assert_eq!(c.nodes, 181 * 181);
        assert!(c.within_limits > 0 && c.within_limits <= c.configurations);
    }
    // Where the tool already is, the current configuration (on the grid) is chosen, S = 0.
    let current = [d(70.0), d(-50.0), d(-40.0), d(-30.0)];
    let here = robot.fk(&current).unwrap().translation.vector;
    let c = chosen("planar4", [here.x, here.y], &current, 1.0);
    assert!(c.s < 1e-9, "{}", c.s);
}

#[test]
fn unreachable_targets_and_bad_input() {
    let robot = presets::get("planar4").unwrap();
    let q = [d(60.0), d(-40.0), d(-30.0), d(-20.0)];
    let at = |x: f64, y: f64, z: f64| Point3::new(x, y, z);
    match scan_min_change(&robot, &at(4.5, 0.0, 0.0), &q, d(1.0)).unwrap() {
        NoSolution(IkFailure::Unreachable { distance, reach, .. }) => {
            assert!((distance - 4.5).abs() < 1e-12 && (reach - 4.0).abs() < 1e-12, "{distance} {reach}");
        }
        other => panic!("{other:?}"),
    }
    // Out of the arm's plane.
    assert!(matches!(scan_min_change(&robot, &at(2.0, 0.0, 0.1), &q, d(1.0)).unwrap(), NoSolution(_)));
    assert!(scan_min_change(&robot, &at(2.0, 0.0, 0.0), &q, 0.0).unwrap_err().to_string().contains("positive"));
    let e = scan_min_change(&robot, &at(2.0, 0.0, 0.0), &q, d(0.01)).unwrap_err().to_string();
    assert!(e.contains(&MAX_SCAN_NODES.to_string()), "{e}");
    assert!(scan_min_change(&robot, &at(f64::NAN, 0.0, 0.0), &q, d(1.0)).is_err());
    assert!(scan_min_change(&robot, &at(2.0, 0.0, 0.0), &q[..3], d(1.0)).is_err());
    let ur5 = presets::get("ur5").unwrap();
    let e = scan_min_change(&ur5, &at(0.4, 0.0, 0.3), &[0.0; 6], d(10.0)).unwrap_err().to_string();
    assert!(e.contains("not parallel"), "{e}");
}
