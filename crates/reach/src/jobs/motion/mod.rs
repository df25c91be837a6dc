//! The `move` and `plan` workflows: one motion between two joint vectors or two tool poses,
//! in joint space (`q(t) = q0 + λ(τ)·Δq`) or in tool space (straight line, rotation about one
//! fixed axis, tracked through IK with branch continuity); and a task file
//! (docs/task-format.md) that lists several motions.
//!
//! * [`MoveRequest`] → [`move_motion`] → [`MoveReport`]: samples (t, q, q̇, tool pose),
//!   per-interval status, events (tool space: the K1–K14 log of the tracking), J1 and J2
//!   (seed 001's weights for 6-joint robots, else 1), the mechanical energy `∫ Σ|τᵢ·q̇ᵢ| dt`
//!   when the robot gives link masses, and a feasibility summary.
//! * [`PlanRequest`] (the task file's text) → [`plan`] → [`PlanReport`], one [`MoveReport`]
//!   per `[[motion]]`. [`Task::parse`] reads the file alone (front ends use its `robot` key to
//!   load the robot; the library never reads files).
//! * Joint differences (J1, J2, rates of tracked samples) follow the crate's one rule,
//!   [`crate::Robot::joint_difference`]: wrapped only for revolute joints without limits, literal
//!   otherwise — what a joint-space motion travels.
//! * Infeasibility (a joint outside its range or above its speed limit, an interval no
//!   configuration realises) is in the report (`feasible`, `reasons`), not an error.

mod compute;
mod report;
mod request;
mod task_file;

pub use compute::{move_motion, move_motion_with_progress};
pub use report::{MoveEffort, MoveEvent, MoveInterval, MoveReport, MoveSample, PlanReport};
pub use request::{ChoiceSpec, End, IntervalChoice, MoveRequest, ProfileName, Space};
pub use task_file::{PlanRequest, Task, plan, plan_with_progress};

#[cfg(test)]
mod tests;
