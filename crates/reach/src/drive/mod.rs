//! Motor drives: stepper coil sequences, step schedules, simulation back to angles, and
//! schedule outputs (CSV, JSON rows, step/direction events, G-code text).
//!
//! Seed 000 drives every joint of its arm with a stepper motor through a reduction gear. The
//! controller turns joint-angle changes into pulse counts `φᵢ` (pulses per degree × |Δangle|),
//! chooses the rotation direction by the order of the coil pulses (thesis §II.3.2, Tables 1
//! and 2) and picks pulse frequencies `ωᵢ ≤ 500 Hz` so that all motors start and stop together
//! (P2011). The paper's linear program makes `φᵢ·ωᵢ` equal, which does not synchronise the
//! motors; the intended rule, implemented here, makes the durations `φᵢ/ωᵢ` equal (notes 000,
//! D8): `ωᵢ = f_max·φᵢ / max φ`. Seed 002 stresses arms without position feedback: the step
//! count *is* the position, so quantisation never loses or adds a step.
//!
//! ## Pieces
//!
//! * [`coils`] — the coil sequences (wave, full, half step; unipolar and bipolar), the seed's
//!   tables as data, and a per-step coil-state iterator.
//! * [`Axis`] — one joint's conversion between joint values and motor steps, from the robot's
//!   drive data ([`crate::model::JointDrive`], `[joints.drive]` in the robot file).
//! * [`schedule_trajectory`] — a sampled joint trajectory ([`crate::motion::JointSample`]s) → per-joint step timestamps, with
//!   rounding that never drifts, checked against each motor's rate and acceleration limits.
//! * [`point_to_point`] — a synchronised move with a common trapezoidal step-rate ramp.
//! * [`simulate`], [`verify`], [`grid_error`] — integrate a schedule back into joint angles and compare it
//!   with the plan in joint and tool space.
//! * [`simulated`], [`with_simulated_drives`] — default motors for simulating robots without
//!   drive data (the control service).
//! * [`output`] — rows for CSV/JSON, step/direction events, coil tables and G-code.
//!
//! ## Conventions
//!
//! * A **step** is one driver pulse (a microstep when the driver microsteps). The motor step
//!   counter of joint *i* at joint value `q` is `s(q) = home_steps + direction·k·(q − home)`
//!   with `k` steps per radian (or per metre) — see [`Axis::exact_steps`].
//! * A sampled trajectory is quantised by rounding: the counter is `⌊s(q(t)) + ½⌋` at every
//!   instant of the piecewise-linear plan, so a step is taken when the plan crosses a
//!   half-step boundary. The counter is a function of the plan position, never of the path
//!   history, so no rounding error accumulates (zero drift). Where the plan turns back within
//!   one step period, the step and its immediate undo are both dropped (no chatter), so the
//!   counter stays within one step of the plan.
//! * A point-to-point move snaps both ends to the step grid, then takes step `k` at the instant
//!   the common ramp reaches `k` steps: every joint's last step falls exactly at the end time.
//! * Times are seconds from the start of the plan's time axis; joint numbers in messages and
//!   outputs are 1-based.

pub mod coils;
pub mod output;

mod axis;
mod error;
mod schedule;
mod simulated;
mod verify;

pub use axis::{Axis, axes};
pub use coils::{CoilSequence, CoilState};
pub use error::DriveError;
pub use schedule::{
    JointSchedule, MAX_STEPS_PER_JOINT, PointToPoint, Step, StepSchedule, point_to_point, schedule_trajectory,
};
pub use simulated::{simulated, with_simulated_drives};
pub use verify::{GridError, Verification, grid_error, simulate, verify};
