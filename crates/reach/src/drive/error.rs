use thiserror::Error;

use crate::KinematicsError;

/// Why a step schedule or a drive output could not be made.
///
/// Joint numbers are 1-based; times are seconds on the plan's time axis.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DriveError {
    /// The robot description gives no `[joints.drive]` for this joint.
    #[error(
        "joint {joint} ({name}) has no drive data: add a `[joints.drive]` table (steps_per_rev, max_step_rate, wiring, …) to the robot file"
    )]
    MissingDrive {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
    },
    /// The trajectory or move is malformed (too few samples, wrong length, NaN, time order).
    #[error("trajectory: {0}")]
    Trajectory(String),
    /// The plan asks a motor for more than its maximum step rate.
    #[error(
        "joint {joint} ({name}): step rate {rate:.1} Hz at t = {time:.4} s exceeds the motor's {limit} Hz; \
         a slower plan lasting at least {suggested:.4} s (now {duration:.4} s) stays within every motor's limits"
    )]
    RateLimit {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// Time of the first violation, s.
        time: f64,
        /// Step rate asked for, Hz.
        rate: f64,
        /// The motor's maximum step rate, Hz.
        limit: f64,
        /// Duration of the plan, s.
        duration: f64,
        /// Shortest duration of the same path, uniformly slowed, that respects all limits, s.
        suggested: f64,
    },
    /// The plan asks a motor for more than its maximum step acceleration.
    #[error(
        "joint {joint} ({name}): step acceleration {acceleration:.1} steps/s² at t = {time:.4} s exceeds the motor's \
         {limit} steps/s²; a slower plan lasting at least {suggested:.4} s (now {duration:.4} s) stays within every \
         motor's limits"
    )]
    AccelerationLimit {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// Time of the first violation, s.
        time: f64,
        /// Acceleration asked for, steps/s².
        acceleration: f64,
        /// The motor's limit, steps/s².
        limit: f64,
        /// Duration of the plan, s.
        duration: f64,
        /// Shortest duration of the same path, uniformly slowed, that respects all limits, s.
        suggested: f64,
    },
    /// A point-to-point duration shorter than the motors allow.
    #[error(
        "a duration of {duration:.4} s is too short: joint {joint} ({name}) needs at least {needed:.4} s \
         within its rate and acceleration limits"
    )]
    DurationTooShort {
        /// The duration asked for, s.
        duration: f64,
        /// The shortest feasible duration, s.
        needed: f64,
        /// 1-based number of the limiting joint.
        joint: usize,
        /// Its name.
        name: String,
    },
    /// Coil states were asked for a joint whose driver microsteps (no coil table).
    #[error(
        "joint {joint} ({name}): microstepping {microstepping} has no coil table (coil sequences exist for 1 and 2 \
         pulses per full step); use the step/direction or G-code output"
    )]
    NoCoilTable {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// The joint's microstepping.
        microstepping: u32,
    },
    /// A motion of a task file is infeasible (beyond a joint's range or speed), so there is
    /// nothing to drive.
    #[error("motion `{motion}` is infeasible: {reason}")]
    InfeasibleMotion {
        /// The motion's name in the task file.
        motion: String,
        /// The first reason `reach plan` gives.
        reason: String,
    },
    /// A plan whose schedule would hold more steps than a joint may have.
    #[error(
        "joint {joint} ({name}): the motion takes {steps:.0} motor steps, more than the {limit} one schedule may hold; \
         split the motion or check its joint values"
    )]
    TooManySteps {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// Steps the motion takes (path length in steps).
        steps: f64,
        /// [`super::MAX_STEPS_PER_JOINT`].
        limit: u64,
    },
    /// G-code has axis letters for six joints only.
    #[error("G-code maps joints to the axis letters X Y Z A B C; the robot has {0} joints")]
    TooManyAxes(usize),
    /// Forward kinematics failed while comparing in tool space.
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
}
