use serde::Serialize;

use super::DriveError;
use super::coils::CoilSequence;
use crate::Robot;
use crate::model::{JointDrive, JointKind};

/// One driven joint: the conversion between its joint value (radians or metres) and its
/// motor step counter, and the motor's limits.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Axis {
    /// 1-based joint number.
    pub joint: usize,
    /// Joint name.
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Steps per radian (revolute) or per metre (prismatic), always positive.
    pub steps_per_unit: f64,
    /// +1 or −1: the motor direction of a positive joint motion.
    pub direction: i32,
    /// Joint value at which the counter reads `home_steps`, SI.
    pub home: f64,
    /// Step counter at `home`.
    pub home_steps: i64,
    /// Maximum step rate, Hz.
    pub max_step_rate: f64,
    /// Maximum step acceleration, steps/s² (`None` = unlimited).
    pub max_acceleration: Option<f64>,
    /// Pulses per full step (for messages and coil tables).
    pub microstepping: u32,
    /// The coil sequence, when the controller switches the coils itself.
    pub coils: Option<CoilSequence>,
}

impl Axis {
    /// The axis of joint `index` (0-based) with `drive`.
    ///
    /// # Errors
    /// [`DriveError::MissingDrive`] when `drive` has no step scale for this joint kind
    /// (a prismatic joint without `lead`; the robot's validation already rejects that).
    pub fn new(robot: &Robot, index: usize, drive: &JointDrive) -> Result<Axis, DriveError> {
        let joint = &robot.joints()[index];
        let missing = || DriveError::MissingDrive { joint: index + 1, name: joint.name.clone() };
        let steps_per_unit = drive.steps_per_unit(joint.kind).ok_or_else(missing)?;
        Ok(Axis {
            joint: index + 1,
            name: joint.name.clone(),
            kind: joint.kind,
            steps_per_unit,
            direction: drive.direction,
            home: joint.home,
            home_steps: drive.home_steps,
            max_step_rate: drive.max_step_rate,
            max_acceleration: drive.max_acceleration,
            microstepping: drive.microstepping,
            coils: drive.coil_mode().map(|mode| CoilSequence::new(drive.wiring, mode)),
        })
    }

    /// The exact (unrounded) motor step counter at joint value `q` (SI):
    /// `home_steps + direction · steps_per_unit · (q − home)`.
    #[must_use]
    #[inline]
    pub fn exact_steps(&self, q: f64) -> f64 {
        self.home_steps as f64 + f64::from(self.direction) * self.steps_per_unit * (q - self.home)
    }

    /// The step counter the motor holds for joint value `q`: `⌊exact + ½⌋`.
    #[must_use]
    #[inline]
    pub fn quantise(&self, q: f64) -> i64 {
        (self.exact_steps(q) + 0.5).floor() as i64
    }

    /// The joint value (SI) of step counter `position` (inverse of [`Axis::exact_steps`]).
    #[must_use]
    #[inline]
    pub fn joint_value(&self, position: i64) -> f64 {
        self.home + (position - self.home_steps) as f64 / (f64::from(self.direction) * self.steps_per_unit)
    }

    /// One step in joint units (radians or metres).
    #[must_use]
    pub fn step_size(&self) -> f64 {
        1.0 / self.steps_per_unit
    }
}

/// The axes of every joint of `robot`.
///
/// # Errors
/// [`DriveError::MissingDrive`] naming the first joint without drive data.
pub fn axes(robot: &Robot) -> Result<Vec<Axis>, DriveError> {
    robot
        .drives()
        .iter()
        .enumerate()
        .map(|(i, drive)| match drive {
            Some(d) => Axis::new(robot, i, d),
            None => Err(DriveError::MissingDrive { joint: i + 1, name: robot.joints()[i].name.clone() }),
        })
        .collect()
}
