//! Seed 000 (thesis §II.3.2, P2011): stepper coil sequences and synchronised pulse trains.
//!
//! Notes `000.md` §4.6 (pulse sequences), §5 Tables 1 and 2, §6.6 (stepper vectors) and
//! §3.5 / D8 (the P2011 linear program: equal products φ·ω do not synchronise; the intended
//! rule makes the durations φ/ω equal).

use reach::drive::coils::{CoilSequence, CoilState};
use reach::drive::{axes, point_to_point};
use reach::model::{StepMode, Wiring, presets};

fn labels(states: impl IntoIterator<Item = CoilState>) -> Vec<String> {
    states.into_iter().map(|s| s.label()).collect()
}

/// The lines as the tables print them: "+" per pulsed winding, columns a1 b1 a2 b2.
fn plus_row(state: &CoilState) -> [&'static str; 4] {
    state.lines.map(|on| if on { "+" } else { "" })
}

#[test]
fn table_1_unipolar_full_step_is_reproduced_exactly() {
    // Notes §5, Table 1 (the seed's "full step": one winding at a time = wave drive).
    let expected = [["+", "", "", ""], ["", "+", "", ""], ["", "", "+", ""], ["", "", "", "+"]];
    let table = CoilSequence::new(Wiring::Unipolar, StepMode::Wave).table();
    let rows: Vec<[&str; 4]> = table.iter().map(plus_row).collect();
    assert_eq!(rows, expected);
}

#[test]
fn table_2_bipolar_two_windings_is_reproduced_exactly() {
    // Notes §5, Table 2.
    let expected = [["+", "", "+", ""], ["", "+", "+", ""], ["", "+", "", "+"], ["+", "", "", "+"]];
    let table = CoilSequence::new(Wiring::Bipolar, StepMode::Full).table();
    let rows: Vec<[&str; 4]> = table.iter().map(plus_row).collect();
    assert_eq!(rows, expected);
    // Phase currents: winding A (a1–b1) and B (a2–b2) reverse polarity in quadrature.
    let phases: Vec<(i8, i8)> = table.iter().map(|s| s.phases).collect();
    assert_eq!(phases, [(1, 1), (-1, 1), (-1, -1), (1, -1)]);
}

#[test]
fn section_6_6_vectors() {
    let t1 = CoilSequence::new(Wiring::Unipolar, StepMode::Wave);
    // Table 1 forward, 6 steps: [a1], [b1], [a2], [b2], [a1], [b1].
    assert_eq!(labels(t1.pulses(0, false).take(6)), ["a1", "b1", "a2", "b2", "a1", "b1"]);
    // Reverse, starting from phase 4: [b2], [a2], [b1], [a1].
    assert_eq!(labels(t1.pulses(3, true).take(4)), ["b2", "a2", "b1", "a1"]);
    // Table 2 forward: {a1, a2}, {b1, a2}, {b1, b2}, {a1, b2}, then repeat.
    let t2 = CoilSequence::new(Wiring::Bipolar, StepMode::Full);
    assert_eq!(labels(t2.pulses(0, false).take(5)), ["a1 a2", "b1 a2", "b1 b2", "a1 b2", "a1 a2"]);
}

#[test]
fn forward_then_reverse_returns_every_sequence_to_its_start_state() {
    for wiring in [Wiring::Unipolar, Wiring::Bipolar] {
        for mode in [StepMode::Wave, StepMode::Full, StepMode::Half] {
            let seq = CoilSequence::new(wiring, mode);
            for start in [-7_i64, 0, 3, 1001] {
                for n in [1usize, 5, 37] {
                    let mut fwd = seq.pulses(start, false);
                    let forward: Vec<CoilState> = fwd.by_ref().take(n + 1).collect();
                    // The last forward pulse was at start + n; reverse from there.
                    let back: Vec<CoilState> = seq.pulses(start + n as i64, true).take(n + 1).collect();
                    let mut reversed = back.clone();
                    reversed.reverse();
                    assert_eq!(forward, reversed, "{wiring:?} {mode:?} start {start} n {n}");
                    assert_eq!(back.last(), Some(&seq.state_at(start)));
                }
            }
        }
    }
}

#[test]
fn half_step_interleaves_wave_and_full_step_states() {
    for wiring in [Wiring::Unipolar, Wiring::Bipolar] {
        let half = CoilSequence::new(wiring, StepMode::Half).table();
        let wave = CoilSequence::new(wiring, StepMode::Wave).table();
        let full = CoilSequence::new(wiring, StepMode::Full).table();
        assert_eq!(half.len(), 8);
        for k in 0..4 {
            assert_eq!(half[2 * k], wave[k]);
            assert_eq!(half[2 * k + 1], full[k]);
        }
    }
    // Unipolar half step as lines: a1, a1 b1, b1, b1 a2, a2, a2 b2, b2, b2 a1.
    let half = CoilSequence::new(Wiring::Unipolar, StepMode::Half).table();
    assert_eq!(labels(half), ["a1", "a1 b1", "b1", "b1 a2", "a2", "a2 b2", "b2", "a1 b2"]);
}

#[test]
fn d8_synchronised_rates_125_500_250_hz_for_0_8_s() {
    // planar3: 200 steps/rev, 50:1 gear => 27.78 steps/deg, 500 Hz, no ramp. Moves of 3.6°,
    // 14.4° and 7.2° are φ = (100, 400, 200) pulses (notes 000, D8).
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let to = [3.6_f64.to_radians(), (-14.4_f64).to_radians(), (-7.2_f64).to_radians()];
    let plan = point_to_point(&axes, &[0.0; 3], &to, None, 0.0).unwrap();
    let phi: Vec<i64> = plan.from_steps.iter().zip(&plan.to_steps).map(|(a, b)| (b - a).abs()).collect();
    assert_eq!(phi, [100, 400, 200]);
    assert!((plan.duration - 0.8).abs() < 1e-12, "t = {}", plan.duration);
    // Corrected rule: ω_i = 500·φ_i / max φ = (125, 500, 250) Hz: constant step periods.
    for (joint, omega) in plan.schedule.joints.iter().zip([125.0, 500.0, 250.0]) {
        let steps = &joint.steps;
        for w in steps.windows(2) {
            assert!((w[1].t - w[0].t - 1.0 / omega).abs() < 1e-12);
        }
        assert!((steps[0].t - 1.0 / omega).abs() < 1e-12);
        assert!((steps.last().unwrap().t - 0.8).abs() < 1e-12, "all joints stop together at 0.8 s");
    }
    // The paper's literal LP (equal φ·ω, ω ≤ 500) gives ω = (500, 125, 250): durations
    // (0.2, 3.2, 0.8) s — not synchronous, which is why D8 corrects it.
    let literal: Vec<f64> = [100.0, 400.0, 200.0].iter().map(|p| p / (500.0 * 100.0 / p)).collect();
    assert_eq!(literal, [0.2, 3.2, 0.8]);
    // Joint B moves negatively: its motor steps backwards.
    assert!(plan.schedule.joints[1].steps.iter().all(|s| s.dir == -1));
}

#[test]
fn d8_a_motor_that_does_not_move_does_not_break_the_synchronisation() {
    // The literal LP collapses (c = 0) when a motor does not move (D8); the corrected rule
    // simply gives that motor no pulses.
    let robot = presets::get("planar3").unwrap();
    let axes = axes(&robot).unwrap();
    let to = [3.6_f64.to_radians(), 0.0, (-7.2_f64).to_radians()];
    let plan = point_to_point(&axes, &[0.0; 3], &to, None, 0.0).unwrap();
    assert!((plan.duration - 0.4).abs() < 1e-12); // 200 pulses at 500 Hz
    assert!(plan.schedule.joints[1].steps.is_empty());
    assert_eq!(plan.schedule.joints[0].steps.len(), 100);
}
