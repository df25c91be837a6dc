//! # reach — plan and check the motions of robot manipulators
//!
//! `reach` takes a robot (a Denavit–Hartenberg table or a URDF chain), computes its forward
//! kinematics and Jacobian, and — in later modules — its inverse kinematics, motions, motor
//! commands and reports. The method follows five research papers ("seeds"); where a paper's
//! formula is wrong, the corrected one is implemented and recorded in
//! `docs/seeds-and-corrections.md`.
//!
//! This crate is pure computation: no file, terminal or network I/O. The `reach` command
//! line (crate `reach-cli`) reads files and prints results.
//!
//! ## Conventions (stated once)
//!
//! * **Units:** SI throughout — metres, seconds, kilograms — and **radians**. Degrees and
//!   millimetres exist only at the edges (description files, CLI), where field names carry
//!   the unit (`q_deg`, `xyz_m`).
//! * **Numbers:** `f64` everywhere. NaN and infinity are rejected at every entry point.
//! * **Frames:** right-handed. Poses are `nalgebra::Isometry3<f64>` (world ← frame); the
//!   matrix form `IsometryMatrix3<f64>` is offered on hot paths. A 4×4 matrix is printed
//!   row-major.
//! * **Joints:** the joint vector `q` has one value per movable joint, base to tip: radians
//!   for revolute joints, metres for prismatic joints. Joint numbers in messages are 1-based.
//! * **DH:** standard (distal) DH is the default, `Aᵢ = Rz(θᵢ)·Tz(dᵢ)·Tx(aᵢ)·Rx(αᵢ)` with
//!   `θᵢ = qᵢ + offsetᵢ`; modified (proximal, Craig) DH is explicit,
//!   `Aᵢ = Rx(αᵢ₋₁)·Tx(aᵢ₋₁)·Rz(θᵢ)·Tz(dᵢ)`. The chain is `T = base · A₁ ⋯ Aₙ · tool`.
//! * **Orientation triples:** `rpy` is roll–pitch–yaw about fixed axes X, Y, Z, i.e.
//!   `R = Rz(yaw)·Ry(pitch)·Rx(roll)` (URDF's convention). Quaternions are `w, x, y, z`.
//! * **Jacobian:** geometric, 6×n, in the world frame, rows `vx vy vz ωx ωy ωz`, for the
//!   tool point.
//! * **Angles** are wrapped into (−π, π] by [`angle::wrap`] only.
//! * **Tolerances** are named constants in [`tolerance`].
//!
//! ## Module map
//!
//! * [`model`] — `Robot`, joints, limits, TOML and URDF parsing, presets.
//! * [`kinematics`] — forward kinematics, Jacobian, manipulability.
//! * [`ik`] — inverse kinematics: closed forms with all branches, numeric solver.
//! * [`decide`] — criteria (IK solutions, whole motions, detours), multi-criteria choice
//!   (weighted sum, TOPSIS, VIKOR, Pareto), path tracking's per-interval choice, task sequencing.
//! * [`motion`] — time profiles, joint/tool-space motion, path tracking, events.
//! * [`effort`] — J1/J2/S functionals, dynamics and energy.
//! * [`world`] — scenes, collision, detours, configuration space.
//! * [`drive`] — stepper sequences, step schedules, G-code.
//! * [`batch`] — FK, Jacobian and all-branch IK over many inputs at once, split over threads
//!   (the Python package's numpy calls).
//! * [`jobs`] — the application layer: one serde request and one report per workflow, and
//!   a pure `run`; every front end (CLI, service, Python, viewer) is a thin adapter over it.
//! * [`Error`] — the one error type, with stable failure codes.
//! * [`angle`] — wrapping and angle differences.
//! * [`tolerance`] — the numeric tolerances.
//! * [`simd`] — the run-time choice of vector instructions (SSE2, AVX2, AVX-512) for the
//!   batch kernels; results are bit for bit the same at every level.
//! * [`Cancel`] — a flag a front end sets to stop long work (Ctrl-C).
//!
//! ## Bounded resources
//!
//! Every size a request sets is computed and checked against a cap before anything is
//! allocated or run; an input over a cap is an [`Error::Request`] naming the field, the size
//! and the cap. The caps:
//!
//! | size | cap | raised by |
//! | --- | --- | --- |
//! | configuration-space grid nodes | [`world::cspace::DEFAULT_MAX_NODES`] (20 million) | `max_nodes` (CLI `--max-nodes`), up to [`world::cspace::MAX_NODES`] (200 million) |
//! | numeric IK `restarts × max_iterations` without a time budget | [`ik::numeric::MAX_UNTIMED_ITERATIONS`] (1 million) | a time budget (`numeric.time_budget_s`, CLI `--time-budget`) |
//! | motion duration (a move's `duration_s`, a drive's motion) | [`motion::sample::MAX_DURATION_S`] (one day) | — |
//! | motion samples (`duration / dt`, tool-path arc-length grids) | [`motion::sample::MAX_SAMPLES`] (10 million) | — |
//! | seed-000 IK scan rows (`scan`, `step_deg`) | [`ik::planar::MAX_SCAN_ROWS`] (1 million) | — |
//! | self-motion samples per turn | [`ik::planar::MAX_SELF_MOTION_SAMPLES`] (3600) | — |
//! | path planner iterations (two trees, one node each at most) | [`world::planner::PlanOptions::max_iterations`] (20 000) and its time budget | — |
//! | stepper steps per joint (`drive`) | [`drive::MAX_STEPS_PER_JOINT`] (2 million) | — |
//! | rows of one batch call ([`batch`]) | [`batch::MAX_BATCH`] (10 million) | — |
//! | wall-time budgets | [`jobs::input::MAX_TIME_BUDGET_S`] (one day) | — |
//!
//! ## Example
//!
//! ```
//! use reach::model::presets;
//! let puma = presets::get("puma560").unwrap();
//! let pose = puma.fk(&[0.0; 6]).unwrap();
//! let j = puma.jacobian(&[0.1, 0.2, 0.3, 0.4, 0.5, 0.6]).unwrap();
//! assert_eq!(j.shape(), (6, 6));
//! assert!(pose.translation.vector.norm() > 0.5);
//! ```

#![warn(missing_docs)]

pub mod angle;
pub mod batch;
mod cancel;
pub mod decide;
pub mod drive;
pub mod effort;
mod error;
pub mod ik;
pub mod jobs;
pub mod kinematics;
pub mod model;
pub mod motion;
mod rng;
pub mod simd;
pub mod tolerance;
pub mod world;

pub use cancel::Cancel;
pub use error::{Error, Result, one_line};
pub use kinematics::{Jacobian, KinematicsError, Manipulability};
pub use model::{ModelError, Robot, RobotSpec};
