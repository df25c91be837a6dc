//! Time-optimal motion through a polyline of proven-clear joint-space edges — what the `path`
//! and `approach` workflows time: the corners cut by parabolic blends within a tolerance
//! ([`PiecewiseCubic::blended`]), tightened until the blended path itself is proven clear
//! ([`SweptPathReport::check_pieces`]), then timed by TOPP-RA under the joints' limits
//! ([`PathLimits::from_robot`]: their own and their stepper drives').

use super::check::SweptPathReport;
use crate::Robot;
use crate::error::Result;
use crate::jobs::input::{MotionSample, q_display};
use crate::jobs::retime::request_error;
use crate::motion::{OptimalMotion, PathLimits, PiecewiseCubic, time_optimal};
use crate::world::Scene;

/// How many times a blend tolerance whose blended path is not proven clear is halved before
/// the motion rests at the waypoints (whose straight edges were proven clear).
pub const BLEND_TIGHTENINGS: usize = 6;

/// Whether a swept check proves the motion clear (`None`: nothing to check against).
#[must_use]
pub(crate) fn proven_clear(swept: Option<&SweptPathReport>) -> bool {
    swept.is_none_or(|s| s.swept.clear)
}

/// The blend a polyline is timed with: its tolerance and the swept check of the blended path.
pub(crate) struct ClearBlend {
    /// The tolerance, rad and m (0: the polyline, resting at every waypoint).
    pub tolerance: f64,
    /// The swept check of the blended path (`None`: nothing to check against).
    pub swept: Option<SweptPathReport>,
}

/// The widest blend of `waypoints` proven clear of `scene` for `body`: `requested`, halved up
/// to [`BLEND_TIGHTENINGS`] times, at last 0 (the polyline, returned with its own check
/// whatever it says).
///
/// # Errors
/// [`crate::Error::Request`] for a bad tolerance or waypoints; the swept check's errors.
pub(crate) fn clear_blend(body: &Robot, scene: &Scene, waypoints: &[Vec<f64>], requested: f64) -> Result<ClearBlend> {
    let mut tries: Vec<f64> = (0..=BLEND_TIGHTENINGS as i32).map(|k| requested / 2f64.powi(k)).chain([0.0]).collect();
    tries.dedup();
    let mut blend = ClearBlend { tolerance: 0.0, swept: None };
    for tolerance in tries {
        let path = PiecewiseCubic::blended(waypoints, tolerance).map_err(request_error)?;
        blend = ClearBlend { tolerance, swept: SweptPathReport::check_pieces(body, scene, &path)? };
        if proven_clear(blend.swept.as_ref()) {
            break;
        }
    }
    Ok(blend)
}

/// The time-optimal motion along `waypoints` blended with `tolerance`, under the robot's
/// limits times their scales.
///
/// # Errors
/// [`crate::Error::Request`] for a joint without limits, a scale outside (0, 1], bad
/// waypoints or a path the limits cannot time.
pub(crate) fn optimal_motion(
    robot: &Robot,
    waypoints: &[Vec<f64>],
    tolerance: f64,
    velocity_scale: f64,
    acceleration_scale: f64,
) -> Result<OptimalMotion> {
    let path = PiecewiseCubic::blended(waypoints, tolerance).map_err(request_error)?;
    let limits = PathLimits::from_robot(robot, velocity_scale, acceleration_scale).map_err(request_error)?;
    time_optimal(&path, &limits, 0).map_err(request_error)
}

/// The motion's positions every `dt_s` seconds from 0, and at the end, as a drive follows
/// them (revolute degrees, prismatic metres).
///
/// # Errors
/// [`crate::Error::Request`] for a `dt_s` that is not positive or gives too many samples.
pub(crate) fn motion_samples(robot: &Robot, motion: &OptimalMotion, dt_s: f64) -> Result<Vec<MotionSample>> {
    Ok(motion
        .samples(dt_s)
        .map_err(request_error)?
        .into_iter()
        .map(|s| MotionSample { t_s: s.t, q_deg: q_display(robot, &s.q) })
        .collect())
}
