//! Seed 000 (Šarpnickas 2013) §II, §4.5 step 6: "obstacle position comes from 2 or more
//! ultrasonic sensors" (notes 000 §2) — not analysed by the thesis. The obstacle is located
//! from the readings (`reach::world::sense`) and the detour is planned around it grown by its
//! uncertainty radius; the plan must clear the **true** obstacle. (The 10 000-trial coverage
//! test is a unit test of `world::sense`, which has the crate's seeded generator.)

use reach::jobs::Joints;
use reach::jobs::world::{AvoidRequest, SenseRequest, SensorReading, avoid_run, sense};
use reach::model::presets;
use reach::world::detour::{DetourOutcome, P2, leg_sweep};
use reach::world::sense::Ambiguity;

/// Notes 000 §6.3: the obstacle of the thesis's scenario.
const H: P2 = [2.0, 0.7];

/// A reading of `H` from `p`, the beam `off_deg` off the line of sight, the range off by `noise`.
fn reading(p: P2, off_deg: f64, noise: f64) -> SensorReading {
    let d = [H[0] - p[0], H[1] - p[1]];
    SensorReading {
        xy_m: p,
        dir_deg: d[1].atan2(d[0]).to_degrees() + off_deg,
        range_m: d[0].hypot(d[1]) + noise,
        cone_deg: 30.0,
        sigma_m: None,
    }
}

fn request(sense: SenseRequest) -> AvoidRequest {
    AvoidRequest {
        start: Some(Joints::Deg(vec![60.0, -40.0, -30.0])),
        from_xy_m: None,
        to_xy_m: [2.4, 0.2],
        obstacles_xy_m: vec![],
        step_deg: 0.01,
        literal_test: false,
        printed_waypoints: false,
        choose: None,
        sense: Some(sense),
    }
}

#[test]
fn the_detour_around_the_sensed_obstacle_clears_the_true_one() {
    let robot = presets::get("planar3").unwrap();
    // Range errors of ±2σ on each of two sensors below the work area, and none.
    for (e1, e2) in [(0.0, 0.0), (0.02, 0.02), (0.02, -0.02), (-0.02, 0.02), (-0.02, -0.02)] {
        let readings = SenseRequest {
            sensors: vec![reading([0.5, -0.5], 5.0, e1), reading([3.0, -0.5], -5.0, e2)],
            sigma_m: 0.01,
        };
        let run = avoid_run(&robot, &request(readings)).unwrap();
        let report = &run.report;
        let sensed = report.sensed.as_ref().unwrap();
        let radius = sensed.uncertainty_m.unwrap();
        let miss = (sensed.obstacle_m[0] - H[0]).hypot(sensed.obstacle_m[1] - H[1]);
        assert!(miss <= radius, "({e1}, {e2}): H is {miss} m from the estimate, radius {radius} m");
        assert!((0.02..0.06).contains(&radius), "{radius}");
        assert_eq!(run.obstacle_radius_m, radius);
        assert!(report.blocked, "({e1}, {e2}): the direct move passes H");
        assert!(matches!(report.outcome, DetourOutcome::Detour { obstacle: 0 }), "{:?}", report.outcome);
        // The report's swept check: proven clear of the disc over every leg.
        let closest = report.closest.unwrap();
        assert!(closest.lower_bound_m > 0.0, "{closest:?}");
        // Independently: every leg swept against the true point obstacle is proven clear, by at
        // least the disc's margin plus what the disc adds around H.
        let mut from = run.start;
        for (leg, to) in run.plan.configurations.iter().enumerate() {
            let swept = leg_sweep(&run.arm, &from, to, &[H]).unwrap();
            assert!(swept.clear, "({e1}, {e2}) leg {}: {swept:?}", leg + 1);
            assert!(swept.min_clearance >= closest.lower_bound_m + (radius - miss) - 1e-9, "{swept:?} {closest:?}");
            assert!(swept.lower_bound > 0.0);
            from = *to;
        }
    }
}

#[test]
fn ambiguous_or_mixed_input_is_refused_by_avoid_and_reported_by_sense() {
    let robot = presets::get("planar3").unwrap();
    // Two sensors facing each other along the x axis with 60° beams: (0.5, ±0.2) both fit.
    let face = |x: f64, dir: f64| SensorReading {
        xy_m: [x, 0.0],
        dir_deg: dir,
        range_m: 0.5f64.hypot(0.2),
        cone_deg: 60.0,
        sigma_m: None,
    };
    let symmetric = SenseRequest { sensors: vec![face(0.0, 0.0), face(1.0, 180.0)], sigma_m: 0.01 };
    let report = sense(&robot, &symmetric).unwrap();
    assert!(report.ambiguous);
    assert_eq!(report.ambiguity, Some(Ambiguity::Alternatives));
    let ys = [report.obstacle_m[1], report.alternatives_m[0][1]];
    assert!((ys[0] + ys[1]).abs() < 1e-9 && (ys[0].abs() - 0.2).abs() < 1e-9, "{ys:?}");
    let e = avoid_run(&robot, &request(symmetric)).unwrap_err().to_string();
    assert!(e.starts_with("sense: the readings do not locate the obstacle unambiguously"), "{e}");
    let mut both = request(SenseRequest {
        sensors: vec![reading([0.5, -0.5], 0.0, 0.0), reading([3.0, -0.5], 0.0, 0.0)],
        sigma_m: 0.01,
    });
    both.obstacles_xy_m = vec![H];
    assert!(avoid_run(&robot, &both).unwrap_err().to_string().contains("not both"));
    both.obstacles_xy_m.clear();
    both.literal_test = true;
    assert!(avoid_run(&robot, &both).unwrap_err().to_string().contains("literal test takes points only"));
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig { cases: 256, ..Default::default() })]

    /// Any finite readings give an estimate or a named error, never a panic; an estimate is
    /// finite, its radius finite and positive or absent (singular), its residuals match it.
    #[test]
    fn any_finite_readings_give_an_answer_or_a_named_error(
        sensors in proptest::collection::vec(
            (-3.0..3.0f64, -3.0..3.0f64, -360.0..360.0f64, 0.01..5.0f64, 1.0..179.0f64),
            2..6,
        ),
        sigma in 1e-4..0.2f64,
    ) {
        let robot = presets::get("planar3").unwrap();
        let request = SenseRequest {
            sensors: sensors
                .iter()
                .map(|&(x, y, dir_deg, range_m, cone_deg)| SensorReading { xy_m: [x, y], dir_deg, range_m, cone_deg, sigma_m: None })
                .collect(),
            sigma_m: sigma,
        };
        match sense(&robot, &request) {
            Ok(r) => {
                proptest::prop_assert!(r.obstacle_m.iter().all(|v| v.is_finite()));
                proptest::prop_assert!(r.uncertainty_m.is_none_or(|u| u.is_finite() && u > 0.0));
                for (s, e) in request.sensors.iter().zip(&r.residuals_m) {
                    let d = (r.obstacle_m[0] - s.xy_m[0]).hypot(r.obstacle_m[1] - s.xy_m[1]);
                    proptest::prop_assert!((d - s.range_m - e).abs() < 1e-9);
                }
            }
            Err(e) => proptest::prop_assert!(["world", "request"].contains(&e.code()), "{e}"),
        }
    }
}
