//! Stepper coil sequences (seed 000, thesis §II.3.2, Tables 1 and 2).
//!
//! A controller without a step/direction driver switches the motor's windings itself, one
//! output line per winding end. The four lines are named as in the seed's tables, **a1, b1,
//! a2, b2**:
//!
//! * **Unipolar** (Table 1): each line energises one half-winding; a1 = phase A forward,
//!   b1 = phase B forward, a2 = phase A reversed, b2 = phase B reversed, so pulsing a1, b1,
//!   a2, b2 in turn rotates the field by a quarter cycle per pulse.
//! * **Bipolar** (Table 2): winding A lies between a1 and b1, winding B between a2 and b2. A
//!   "+" line receives the positive pulse; the winding's other end gets the negative pulse
//!   through the npn transistor the thesis describes. Current from a1 to b1 is phase A
//!   forward, from b1 to a1 phase A reversed; likewise a2/b2 for phase B.
//!
//! Every sequence is a cycle of phase-current pairs `(i_A, i_B) ∈ {−1, 0, 1}²`:
//!
//! | mode | states per cycle | cycle |
//! |---|---|---|
//! | wave (one phase on) | 4 | (+,0) (0,+) (−,0) (0,−) |
//! | full (two phases on) | 4 | (+,+) (−,+) (−,−) (+,−) |
//! | half | 8 | (+,0) (+,+) (0,+) (−,+) (−,0) (−,−) (0,−) (+,−) |
//!
//! Mapped to the lines, unipolar wave drive is exactly the seed's Table 1 and bipolar full step
//! exactly its Table 2. The opposite direction runs the cycle in reverse order ("the direction
//! of rotation depends on the order of the pulses"). The state for step counter `n` is entry
//! `n mod len` of the cycle, so a motor that steps forward and back is again in its start state.
//!
//! # Example
//! ```
//! use reach::drive::coils::{CoilSequence, CoilState};
//! use reach::model::{StepMode, Wiring};
//! let table2 = CoilSequence::new(Wiring::Bipolar, StepMode::Full);
//! let names: Vec<String> = table2.table().iter().map(CoilState::label).collect();
//! assert_eq!(names, ["a1 a2", "b1 a2", "b1 b2", "a1 b2"]);
//! ```

use serde::Serialize;

pub use crate::model::{StepMode, Wiring};

/// Names of the four output lines, in the column order of the seed's tables.
pub const LINE_NAMES: [&str; 4] = ["a1", "b1", "a2", "b2"];

const WAVE: [(i8, i8); 4] = [(1, 0), (0, 1), (-1, 0), (0, -1)];
const FULL: [(i8, i8); 4] = [(1, 1), (-1, 1), (-1, -1), (1, -1)];
const HALF: [(i8, i8); 8] = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)];

/// The state of the four output lines a1, b1, a2, b2 (`true` = pulsed, "+" in the tables),
/// together with the phase currents it produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct CoilState {
    /// Lines a1, b1, a2, b2.
    pub lines: [bool; 4],
    /// Phase currents `(i_A, i_B)`, each −1, 0 or +1.
    pub phases: (i8, i8),
}

impl CoilState {
    fn from_phases(wiring: Wiring, phases: (i8, i8)) -> Self {
        let (a, b) = phases;
        let lines = match wiring {
            // half-windings A+, B+, A−, B−
            Wiring::Unipolar => [a > 0, b > 0, a < 0, b < 0],
            // winding A between a1 and b1, winding B between a2 and b2
            Wiring::Bipolar => [a > 0, a < 0, b > 0, b < 0],
        };
        CoilState { lines, phases }
    }

    /// The pulsed lines separated by spaces, e.g. `a1 a2` (empty when all are off).
    #[must_use]
    pub fn label(&self) -> String {
        LINE_NAMES.iter().zip(self.lines).filter(|(_, on)| *on).map(|(n, _)| *n).collect::<Vec<_>>().join(" ")
    }

    /// The lines as four characters `0`/`1` in the order a1 b1 a2 b2, e.g. `1010`.
    #[must_use]
    pub fn bits(&self) -> String {
        self.lines.iter().map(|&on| if on { '1' } else { '0' }).collect()
    }
}

/// One coil sequence: a wiring and a step mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct CoilSequence {
    /// How the windings are wired.
    pub wiring: Wiring,
    /// Which cycle is used.
    pub mode: StepMode,
}

impl CoilSequence {
    /// The sequence for `wiring` and `mode`.
    #[must_use]
    pub const fn new(wiring: Wiring, mode: StepMode) -> Self {
        CoilSequence { wiring, mode }
    }

    fn cycle(&self) -> &'static [(i8, i8)] {
        match self.mode {
            StepMode::Wave => &WAVE,
            StepMode::Full => &FULL,
            StepMode::Half => &HALF,
        }
    }

    /// Number of states in one electrical cycle (4, or 8 for half step).
    #[must_use]
    pub fn len(&self) -> usize {
        self.cycle().len()
    }

    /// Always `false`: a cycle has at least four states.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The cycle in forward order, as the seed prints it (pulse 1 first).
    #[must_use]
    pub fn table(&self) -> Vec<CoilState> {
        self.cycle().iter().map(|&p| CoilState::from_phases(self.wiring, p)).collect()
    }

    /// The coil state at step counter `position` (entry `position mod len` of the cycle).
    #[must_use]
    #[inline]
    pub fn state_at(&self, position: i64) -> CoilState {
        let cycle = self.cycle();
        // rem_euclid of a positive length is in 0..len.
        let index = position.rem_euclid(cycle.len() as i64) as usize;
        CoilState::from_phases(self.wiring, cycle[index])
    }

    /// The states energised by successive pulses, starting with the state at `position` and
    /// moving forward (`reverse = false`) or backward through the cycle. Endless.
    #[must_use]
    pub fn pulses(&self, position: i64, reverse: bool) -> CoilSteps {
        CoilSteps { sequence: *self, next: position, step: if reverse { -1 } else { 1 } }
    }
}

/// Iterator over the coil states of successive pulses (see [`CoilSequence::pulses`]).
#[derive(Debug, Clone)]
pub struct CoilSteps {
    sequence: CoilSequence,
    next: i64,
    step: i64,
}

impl CoilSteps {
    /// The step counter of the next state to be yielded.
    #[must_use]
    pub fn position(&self) -> i64 {
        self.next
    }
}

impl Iterator for CoilSteps {
    type Item = CoilState;

    fn next(&mut self) -> Option<CoilState> {
        let state = self.sequence.state_at(self.next);
        self.next = self.next.wrapping_add(self.step);
        Some(state)
    }
}
