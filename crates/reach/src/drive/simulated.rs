//! Default stepper data for simulating robots whose description gives none.
//!
//! The control service (`reach serve`) plays every job on simulated stepper motors, so every
//! joint needs drive data. A robot file's `[joints.drive]` always wins; a joint without one
//! gets [`simulated`]: a fine, fast motor that never limits a plan the joints' own speed
//! limits allow, and a finite acceleration so that a controlled stop has a ramp.
//!
//! | joint | resolution | max rate | max acceleration |
//! |---|---|---|---|
//! | revolute | 200 steps × 16 microsteps × 10:1 gear = 32 000 steps/rev (0.01125°) | 200 kHz (2250°/s) | 50 rad/s² (≈ 2865°/s²) |
//! | prismatic | 200 × 16 per revolution of a 10 mm lead screw = 320 000 steps/m (3.125 µm) | 200 kHz (0.625 m/s) | 5 m/s² |

use crate::Robot;
use crate::model::{JointDrive, JointKind, ModelError, StepMode, Wiring};

/// Simulated motor: full steps per revolution.
const STEPS_PER_REV: u32 = 200;
/// Simulated driver: microsteps per full step.
const MICROSTEPPING: u32 = 16;
/// Simulated gear: motor revolutions per joint (or lead-screw) revolution.
const GEAR_RATIO: f64 = 10.0;
/// Simulated lead screw of prismatic joints, metres per revolution.
const LEAD_M: f64 = 0.01;
/// Simulated maximum pulse rate, Hz.
const MAX_STEP_RATE_HZ: f64 = 200_000.0;
/// Simulated acceleration limit of revolute joints, rad/s².
const MAX_ACCELERATION_RAD_S2: f64 = 50.0;
/// Simulated acceleration limit of prismatic joints, m/s².
const MAX_ACCELERATION_M_S2: f64 = 5.0;

/// The default drive of a simulated joint of `kind` (see the module docs for the values).
///
/// # Example
/// ```
/// use reach::drive::simulated;
/// use reach::model::JointKind;
/// let d = simulated(JointKind::Revolute);
/// let per_rev = d.steps_per_unit(JointKind::Revolute).unwrap() * std::f64::consts::TAU;
/// assert!((per_rev - 32_000.0).abs() < 1e-9);
/// ```
#[must_use]
pub fn simulated(kind: JointKind) -> JointDrive {
    let (lead, acceleration) = match kind {
        JointKind::Revolute => (None, MAX_ACCELERATION_RAD_S2),
        JointKind::Prismatic => (Some(LEAD_M), MAX_ACCELERATION_M_S2),
    };
    let mut drive = JointDrive {
        steps_per_rev: STEPS_PER_REV,
        microstepping: MICROSTEPPING,
        gear_ratio: GEAR_RATIO,
        lead,
        direction: 1,
        max_step_rate: MAX_STEP_RATE_HZ,
        max_acceleration: None,
        wiring: Wiring::Bipolar,
        mode: None::<StepMode>,
        home_steps: 0,
    };
    // Acceleration in steps/s²: the joint's limit times its steps per radian (metre).
    drive.max_acceleration = drive.steps_per_unit(kind).map(|k| k * acceleration);
    drive
}

/// `robot` with [`simulated`] drive data on every joint that has none, and which joints got
/// it (0-based).
///
/// # Errors
/// [`ModelError`] if the completed robot does not validate (it always does for the defaults).
pub fn with_simulated_drives(robot: &Robot) -> Result<(Robot, Vec<usize>), ModelError> {
    let missing: Vec<usize> = robot.drives().iter().enumerate().filter(|(_, d)| d.is_none()).map(|(i, _)| i).collect();
    if missing.is_empty() {
        return Ok((robot.clone(), missing));
    }
    let drives = robot
        .joints()
        .iter()
        .zip(robot.drives())
        .map(|(joint, drive)| Some(drive.copied().unwrap_or_else(|| simulated(joint.kind))))
        .collect();
    Ok((robot.with_drives(drives)?, missing))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::axes;
    use crate::model::presets;

    #[test]
    fn a_robot_without_drives_gets_simulated_ones_and_keeps_its_own() {
        let ur5 = presets::get("ur5").unwrap();
        assert!(axes(&ur5).is_err(), "ur5 has no drive data");
        let (sim, missing) = with_simulated_drives(&ur5).unwrap();
        assert_eq!(missing, vec![0, 1, 2, 3, 4, 5]);
        let a = axes(&sim).unwrap();
        // 32 000 steps per revolution: 90° is 8 000 steps.
        assert_eq!(a[1].quantise(a[1].home + std::f64::consts::FRAC_PI_2) - a[1].quantise(a[1].home), 8000);
        let planar = presets::get("planar3").unwrap();
        let (same, missing) = with_simulated_drives(&planar).unwrap();
        assert!(missing.is_empty());
        assert_eq!(same.drives(), planar.drives());
    }
}
