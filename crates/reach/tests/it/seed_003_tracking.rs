//! Seed 003 (Knapczyk & Kisiel 1987): tracking the weld through IK — the "universal
//! algorithm" of notes 003 §4 on the example of §5, against the test vectors of notes 003
//! §5.4 (angle and rate tables, forward-difference rates) and the events of §5.5.
//!
//! The weld: the tool point moves on the straight line P = (50, 740, 70) mm → M = (500, 200,
//! 700) mm at 1 mm/s with the constant orientation n = (M − P)/|MP| (tool x axis),
//! e6 = (y1 − y2, x2 − x1, 0)/|M1P1| (tool y axis), l = n × e6 (tool z axis; the printed
//! `l_x = n_z e_6y` lacks its minus, notes 003 §6.4). The robot is `welder6r` in the paper's
//! sign convention (notes 003 §2.6, α3 = 180°).
//!
//! The paper prints no numbers (Fig. 8 is lost); the values asserted are the notes'
//! reconstruction [C], which reproduces the paper's qualitative claims: "+β" feasible, "−β"
//! infeasible because θ4 leaves its range near the end, and no θ̇4 spike at the jump.

use std::f64::consts::TAU;
use std::sync::OnceLock;

use crate::common::weld_pose;
use reach::Robot;
use reach::ik::parallel_axes::ParallelAxes;
use reach::ik::{Branch, SolverKind};
use reach::model::presets;
use reach::motion::PathSample;
use reach::motion::tracking::{
    ConfigurationTrack, Decision, EventCode, EventDetail, TrackedPath, TrackingEvent, TrackingOptions, TrackingReport,
    ViolationKind, describe, step_rates, track, track_configuration,
};

/// |MP| = √891000 mm (notes 003 §5.2).
const LENGTH_MM: f64 = 943.927_962_802_4;
/// rad/s → rev/min.
const RPM: f64 = 60.0 / TAU;

fn welder() -> Robot {
    presets::get("welder6r").unwrap()
}

/// Samples at the given arc lengths (mm) at 1 mm/s: t [s] = s [mm].
fn samples(s_mm: impl IntoIterator<Item = f64>) -> Vec<PathSample> {
    s_mm.into_iter().map(|s| PathSample { t: s, s: s / 1000.0, angle: 0.0, pose: weld_pose(s / 1000.0) }).collect()
}

/// Every millimetre from P, and M.
fn mm_grid() -> Vec<PathSample> {
    samples((0..=943).map(f64::from).chain([LENGTH_MM]))
}

/// The paper's n = 100 steps (notes 003 §5.4, forward differences).
fn hundred_steps() -> Vec<PathSample> {
    samples((0..=100).map(|k| LENGTH_MM * f64::from(k) / 100.0))
}

/// The tracking of the weld on the millimetre grid (computed once for all tests).
fn report() -> &'static TrackingReport {
    static REPORT: OnceLock<TrackingReport> = OnceLock::new();
    REPORT.get_or_init(|| {
        let grid = mm_grid();
        let eval = |s: f64| weld_pose(s);
        let path = TrackedPath::with_evaluator(&grid, &eval).unwrap();
        track(&welder(), &path, &TrackingOptions::default(), None).unwrap()
    })
}

/// An event as the CLI prints it, the text in degrees.
fn line(e: &TrackingEvent) -> String {
    format!("{} [s = {:.6}, t = {:.3} s] {}", e.code.as_str(), e.s, e.t, describe(e, &welder(), true))
}

fn config<'a>(r: &'a TrackingReport, label: &str) -> &'a ConfigurationTrack {
    let i = r.configurations.iter().position(|b| b.get("config") == Some(label)).unwrap();
    &r.intervals[0].configurations[i]
}

/// Index of the tracked sample at `s_mm`.
fn at(track: &ConfigurationTrack, s_mm: f64) -> usize {
    track.s.iter().position(|s| (s * 1000.0 - s_mm).abs() < 1e-6).unwrap_or_else(|| panic!("no sample at {s_mm}"))
}

#[test]
fn no_singular_position_one_interval() {
    // Notes 003 §5.5: Δ ∈ [0.699046, 0.948761], so no singular position and one interval.
    let r = report();
    assert_eq!(r.solver, "parallel-axes");
    assert!(r.split_points.is_empty(), "{:?}", r.split_points);
    assert_eq!(r.intervals.len(), 1);
    assert!(r.events_with(EventCode::K2).next().is_none());
    // The paper's Δ along the grid, from the closed form's measures.
    let robot = welder();
    let solver = ParallelAxes::from_robot(&robot).unwrap();
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in mm_grid() {
        let d = solver.measures(&robot, &p.pose, &Default::default()).unwrap().paper().unwrap().delta;
        lo = lo.min(d);
        hi = hi.max(d);
    }
    assert!((lo - 0.699046).abs() < 2e-6, "Δ_min {lo}"); // sampled min within 0.25 mm of s = 536.245
    assert!((hi - 0.948761).abs() < 1e-6, "Δ_max {hi}");
}

#[test]
fn plus_beta_is_feasible_and_chosen() {
    let r = report();
    let plus = config(r, "+β");
    assert!(plus.feasible, "{:?}", plus.violations);
    assert_eq!(plus.branch.as_ref().unwrap().to_string(), "shoulder=w config=+β wrist=e5");
    let interval = &r.intervals[0];
    assert_eq!(interval.chosen, Some(0));
    assert_eq!(interval.decision, Decision::Default);
    assert!(r.feasible);
    // The realised trajectory is "+β" over the whole weld.
    assert_eq!(r.trajectory.len(), plus.q.len());
    assert!(r.trajectory.iter().all(|p| p.configuration == 0));
    // K6 ("+β" realizable), K7 (θ4 of "−β"), K9 ("+β" realized), K11; no K13 (only one feasible).
    let codes: Vec<EventCode> = r.events.iter().map(|e| e.code).collect();
    assert_eq!(codes, [EventCode::K3, EventCode::K6, EventCode::K7, EventCode::K9, EventCode::K11]);
    let k9 = line(r.events_with(EventCode::K9).next().unwrap());
    assert_eq!(
        k9,
        "K9 [s = 0.000000, t = 0.000 s] in interval P1 I realize configuration \"shoulder=w config=+β wrist=e5\""
    );
    let k7 = r.events_with(EventCode::K7).next().unwrap();
    assert_eq!(k7.joint(), Some(3)); // θ4, 0-based in the data
    let text = line(k7);
    assert!(text.starts_with("K7 [s = 0.618"), "{text}");
    assert!(text.contains("θ4 (wrist-pitch)") && text.contains("−β"), "{text}");
    // The range as operators read it: welder6r's θ4 limits −175° … 150°, in degrees.
    assert!(text.contains("[-175.00, 150.00] deg"), "{text}");
    // The data: SI and radians; the same text in radians.
    let EventDetail::JointLimit { lower, upper, value, s_start, .. } = k7.detail else { panic!("{:?}", k7.detail) };
    assert_eq!((lower, upper), ((-175f64).to_radians(), 150f64.to_radians()));
    assert_eq!(s_start, k7.s);
    assert!(value > upper && value <= std::f64::consts::PI, "worst θ4 {value} rad");
    let text = describe(k7, &welder(), false);
    assert!(text.contains("θ4 (wrist-pitch)") && text.contains("[-3.0543, 2.6180] rad"), "{text}");
}

#[test]
fn minus_beta_breaks_the_theta4_range_on_618_to_882_mm() {
    // Notes 003 §5.5: θ4 > 150° from s = 618.10 mm, below −175° until s = 882.21 mm.
    let minus = config(report(), "−β");
    assert!(!minus.feasible);
    assert_eq!(minus.violations.len(), 1, "{:?}", minus.violations);
    let v = &minus.violations[0];
    assert_eq!(v.kind, ViolationKind::Position);
    assert_eq!(v.joint, Some(4));
    assert!((v.upper.to_degrees() - 150.0).abs() < 1e-9 && (v.lower.to_degrees() + 175.0).abs() < 1e-9);
    assert!((v.s_start * 1000.0 - 618.10).abs() < 0.01, "enters at {} mm", v.s_start * 1000.0);
    assert!((v.s_end * 1000.0 - 882.21).abs() < 0.01, "leaves at {} mm", v.s_end * 1000.0);
    assert!((v.t_start - 618.10).abs() < 0.01 && (v.t_end - 882.21).abs() < 0.01);
    // The worst value is the one deepest in the range's gap (150°, 185°): its middle, 167.5°
    // (θ4 moves ~0.13°/mm, so the 1 mm grid meets it within 0.07°).
    assert!((v.worst.to_degrees() - 167.5).abs() < 0.07, "{}", v.worst.to_degrees());
}

#[test]
fn theta4_wrap_at_842_mm_gives_no_rate_spike() {
    // Notes 003 §5.5: in "−β" θ4 reaches ±180° at s = 842.12 mm; §3.5: no θ̇4 spike.
    let minus = config(report(), "−β");
    assert_eq!(minus.wraps.len(), 1, "{:?}", minus.wraps);
    assert_eq!(minus.wraps[0].joint, 4);
    assert!((minus.wraps[0].s * 1000.0 - 842.12).abs() < 0.01, "{}", minus.wraps[0].s * 1000.0);
    // The tracked θ4 is continuous (unwrapped past 180°) and its rates stay tiny.
    let k = at(minus, 900.0);
    assert!((minus.q[k][3].to_degrees() - (360.0 - 172.775)).abs() < 1e-3);
    let max = minus.step_rates.iter().map(|r| (r[3] * RPM).abs()).fold(0.0, f64::max);
    assert!(max < 0.03, "largest |θ̇4| {max} rev/min");
    // Velocity limits are never approached (largest |θ̇| 0.0622 rev/min, θ̇3).
    for track in &report().intervals[0].configurations {
        let max = track.step_rates.iter().flatten().map(|r| (r * RPM).abs()).fold(0.0, f64::max);
        assert!(max < 0.0625 && max > 0.059, "{max}");
    }
}

#[test]
fn naive_difference_gives_the_spurious_spike_at_step_90() {
    // Notes 003 §5.4: with n = 100 and a naive difference of wrapped angles, "−β" step 90
    // gives θ̇4 = −6.3356 rev/min (beyond the ±6 limit). Tracking keeps each joint continuous
    // (`nearest_equivalent` along the path), so the rates of the tracked series — taken with the
    // one joint-difference rule, literal for the bounded θ4 — show no spike; re-wrapping the
    // series is what makes the spike, and the literal difference then reproduces the paper's.
    let robot = welder();
    let solver = SolverKind::ParallelAxes.build(&robot).unwrap();
    let grid = hundred_steps();
    let filter = Branch::new([("shoulder", "w"), ("config", "−β"), ("wrist", "e5")]);
    let tracked = track_configuration(&robot, solver.as_ref(), &grid, &filter, false).unwrap();
    let q: Vec<Vec<f64>> = tracked.q.into_iter().map(Option::unwrap).collect();
    let t: Vec<f64> = grid.iter().map(|p| p.t).collect();
    let wrapped: Vec<Vec<f64>> = q.iter().map(|v| v.iter().map(|a| reach::angle::wrap(*a)).collect()).collect();
    // Naive: (θ(k) − θ(k−1))/Δt on the wrapped angles, written out plainly.
    let naive4 = (wrapped[90][3] - wrapped[89][3]) / (t[90] - t[89]) * RPM;
    assert!((naive4 + 6.3356).abs() < 1e-4, "naive {naive4}");
    let r = step_rates(&robot, &t, &q).unwrap()[89][3] * RPM;
    assert!(r.abs() < 0.03 && r > 0.0, "tracked step 90: {r}");
    assert!(robot.joints()[3].limits.is_bounded(), "θ4 is bounded: literal differences");
    let spike = step_rates(&robot, &t, &wrapped).unwrap()[89][3] * RPM;
    assert!((spike - naive4).abs() < 1e-9, "re-wrapped series: {spike} vs naive {naive4}");
    // Steps 1 and 100 of both configurations (notes 003 §5.4, forward differences, rev/min).
    let rates = step_rates(&robot, &t, &q).unwrap();
    let check = |got: &[f64], want: [f64; 6]| {
        for (g, w) in got.iter().zip(want) {
            assert!((g * RPM - w).abs() < 1e-6, "{} vs {w}", g * RPM);
        }
    };
    check(&rates[0], [-0.004733, 0.031976, -0.059795, -0.027819, 0.004733, 0.0]);
    check(&rates[99], [-0.022055, -0.011122, 0.032767, 0.021645, 0.022055, 0.0]);
    let plus = Branch::new([("shoulder", "w"), ("config", "+β"), ("wrist", "e5")]);
    let tracked = track_configuration(&robot, solver.as_ref(), &grid, &plus, false).unwrap();
    let q: Vec<Vec<f64>> = tracked.q.into_iter().map(Option::unwrap).collect();
    let rates = step_rates(&robot, &t, &q).unwrap();
    check(&rates[0], [-0.004733, -0.017842, 0.059795, 0.041952, 0.004733, 0.0]);
    check(&rates[99], [-0.022055, 0.013983, -0.032767, -0.018785, 0.022055, 0.0]);
}

/// Notes 003 §5.4, angles [deg]: (s mm, "+β" θ1…θ6, "−β" θ2…θ4).
const ANGLES: [(f64, [f64; 6], [f64; 3]); 5] = [
    (0.0, [105.248, -32.942, 43.339, -169.602, -155.443, 138.131], [3.900, -43.339, 140.561]),
    (250.0, [95.730, -39.051, 97.441, -121.610, -145.924, 138.131], [39.905, -97.441, 122.464]),
    (550.0, [71.857, -12.267, 118.045, -74.222, -122.051, 138.131], [79.007, -118.045, 140.962]),
    (850.0, [27.066, 18.251, 93.487, -68.261, -77.260, 138.131], [94.472, -93.487, -179.015]),
    (LENGTH_MM, [13.567, 25.845, 77.203, -76.952, -63.761, 138.131], [90.035, -77.203, -167.168]),
];

#[test]
fn angle_table_rows() {
    let r = report();
    let (plus, minus) = (config(r, "+β"), config(r, "−β"));
    for (s, p, m) in ANGLES {
        let (kp, km) = (at(plus, s), at(minus, s));
        for j in 0..6 {
            let got = reach::angle::wrap(plus.q[kp][j]).to_degrees();
            assert!((got - p[j]).abs() < 1e-3, "+β s={s} θ{}: {got} vs {}", j + 1, p[j]);
            // θ1, θ5, θ6 do not depend on the configuration.
            let want = if (1..4).contains(&j) { m[j - 1] } else { p[j] };
            let got = reach::angle::wrap(minus.q[km][j]).to_degrees();
            assert!((got - want).abs() < 1e-3, "−β s={s} θ{}: {got} vs {want}", j + 1);
        }
    }
}

/// Notes 003 §5.4, exact rates [rev/min] at 1 mm/s: (s mm, "+β" θ̇1…θ̇4, "−β" θ̇2…θ̇4).
const RATES: [(f64, [f64; 4], [f64; 3]); 4] = [
    (50.0, [-0.005229, -0.010364, 0.045120, 0.034755], [0.026298, -0.045120, -0.018822]),
    (500.0, [-0.017060, 0.019766, 0.003261, 0.023027], [0.021376, -0.003261, 0.018115]),
    (800.0, [-0.026936, 0.014103, -0.021340, -0.007237], [-0.000004, 0.021340, 0.021336]),
    (900.0, [-0.023889, 0.013367, -0.029039, -0.015672], [-0.008123, 0.029039, 0.020916]),
];

#[test]
fn rate_table_rows() {
    // Central differences over the 1 mm grid against the notes' exact derivatives; the
    // invariants θ̇5 = −θ̇1 and θ̇6 = 0 (notes 003 §5.5) hold at every sample.
    let r = report();
    let (plus, minus) = (config(r, "+β"), config(r, "−β"));
    let (rp, rm) = (plus.sample_rates(), minus.sample_rates());
    for (s, p, m) in RATES {
        let (kp, km) = (at(plus, s), at(minus, s));
        for j in 0..4 {
            assert!((rp[kp][j] * RPM - p[j]).abs() < 2e-6, "+β s={s} θ̇{}: {} vs {}", j + 1, rp[kp][j] * RPM, p[j]);
        }
        assert!((rm[km][0] * RPM - p[0]).abs() < 2e-6);
        for j in 1..4 {
            assert!(
                (rm[km][j] * RPM - m[j - 1]).abs() < 2e-6,
                "−β s={s} θ̇{}: {} vs {}",
                j + 1,
                rm[km][j] * RPM,
                m[j - 1]
            );
        }
    }
    for rates in [&rp, &rm] {
        for v in rates.iter() {
            assert!((v[4] + v[0]).abs() < 1e-9 && v[5].abs() < 1e-9);
        }
    }
}

#[test]
fn jacobian_detection_agrees_no_singular_position() {
    // The general detector (σ_min/σ_max of the Jacobian at both configurations' solutions)
    // finds no singular position either, and the same θ4 violation of "−β".
    let grid = samples((0..=94).map(|k| f64::from(k) * 10.0).chain([LENGTH_MM]));
    let eval = |s: f64| weld_pose(s);
    let path = TrackedPath::with_evaluator(&grid, &eval).unwrap();
    let options =
        TrackingOptions { detection: reach::motion::tracking::SingularityDetection::Jacobian, ..Default::default() };
    let r = track(&welder(), &path, &options, None).unwrap();
    assert!(r.split_points.is_empty(), "{:?}", r.split_points);
    let v = &config(&r, "−β").violations[0];
    assert!((v.s_start * 1000.0 - 618.10).abs() < 0.01 && (v.s_end * 1000.0 - 882.21).abs() < 0.01);
}
