//! `retime`: the time-optimal motion through joint waypoints under the robot's velocity and
//! acceleration limits ([`crate::motion::optimal`]), proven within them between samples.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::input::{Joints, from_si, full_scale, number_text, unit_name};
use crate::Robot;
use crate::error::{Error, Result};
use crate::motion::{MotionError, PathLimits, PiecewiseCubic, time_optimal};

/// How the waypoints are joined.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// The not-a-knot cubic spline at uniform parameter (toppra's `SplineInterpolator`):
    /// passes every waypoint without stopping.
    #[default]
    Spline,
    /// Straight segments; the motion rests at every corner.
    Linear,
    /// Straight segments with every corner cut by a parabolic blend within
    /// `blend_tolerance` of the corner ([`PiecewiseCubic::blended`]): the motion does not stop.
    Blend,
}

/// Largest joint-space distance (rad; m for prismatic joints) by which a blend may pass a
/// corner when the request does not say: MoveIt's default `path_tolerance` for its
/// time-optimal parameterisation (TOTG).
pub const DEFAULT_BLEND_TOLERANCE: f64 = 0.1;

/// Time a path of joint waypoints.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RetimeRequest {
    /// The waypoints, base to tip joint order, at least two.
    pub waypoints: Vec<Joints>,
    /// How they are joined (default `spline`).
    #[serde(default)]
    pub interpolation: Interpolation,
    /// `blend` interpolation: how far (joint-space Euclidean distance, rad and m) the path may
    /// pass from each corner (default [`DEFAULT_BLEND_TOLERANCE`]); 0 rests at every corner.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend_tolerance: Option<f64>,
    /// Sample step of the report, s (default 0.01).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Multiplies every joint's `max_velocity`, in (0, 1] (MoveIt's scaling factor; default 1).
    #[serde(default = "full_scale")]
    pub max_velocity_scale: f64,
    /// Multiplies every joint's `max_acceleration`, in (0, 1] (default 1).
    #[serde(default = "full_scale")]
    pub max_acceleration_scale: f64,
    /// Grid intervals per path piece (default 64, fewer on long paths: about 4096 grid
    /// intervals in all, at least 8 per piece). More brings the duration closer to the
    /// time-optimal one; the limits hold at any value.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub points_per_piece: Option<usize>,
}

/// One sample of the timed motion, SI: rad, rad/s, rad/s² (prismatic joints m, m/s, m/s²).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct RetimeSample {
    /// Time, s.
    pub t_s: f64,
    /// Joint values.
    pub q: Vec<f64>,
    /// Joint speeds.
    pub qd: Vec<f64>,
    /// Joint accelerations.
    pub qdd: Vec<f64>,
}

/// The timed motion (`reach retime --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct RetimeReport {
    /// Robot name.
    pub robot: String,
    /// How the waypoints were joined.
    pub interpolation: Interpolation,
    /// `blend` interpolation: the tolerance used (rad and m); `null` otherwise.
    pub blend_tolerance: Option<f64>,
    /// The time at which the motion passes each waypoint (a blended corner: the middle of its
    /// blend), s.
    pub waypoint_times_s: Vec<f64>,
    /// Number of waypoints.
    pub waypoints: usize,
    /// Duration, s, rest to rest.
    pub duration_s: f64,
    /// Grid points of the parameterisation.
    pub grid_points: usize,
    /// The uniform slow-down applied so the limits hold between grid points (1 = none).
    pub slowdown: f64,
    /// The speed limits used (after scaling), SI.
    pub velocity_limits: Vec<f64>,
    /// The acceleration limits used (after scaling), SI.
    pub acceleration_limits: Vec<f64>,
    /// Per joint, the exact largest `|q̇| / limit` over the whole motion (≤ 1).
    pub worst_velocity_ratio: Vec<f64>,
    /// Per joint, the exact largest `|q̈| / limit` over the whole motion (≤ 1).
    pub worst_acceleration_ratio: Vec<f64>,
    /// Samples every `dt` from 0, and the end.
    pub samples: Vec<RetimeSample>,
}

/// A bad number of the request (a scale, `dt`, `points_per_piece`, a missing limit) as the
/// request error naming its field.
pub(crate) fn request_error(e: MotionError) -> Error {
    match e {
        MotionError::InvalidInput { field, reason } => Error::request(field, reason),
        other => other.into(),
    }
}

/// Runs a [`RetimeRequest`].
///
/// # Errors
/// [`Error::Request`] for fewer than two waypoints, a waypoint of the wrong length or with a
/// NaN, a waypoint outside the joint limits, a spline that leaves the limits between
/// waypoints (naming the joint, the value reached and the segment), a joint without a
/// velocity or acceleration limit, a scale outside (0, 1], a bad `dt` or too many grid points
/// or samples.
pub fn retime(robot: &Robot, request: &RetimeRequest) -> Result<RetimeReport> {
    if request.waypoints.len() < 2 {
        return Err(Error::request("waypoints", format!("needs at least 2, got {}", request.waypoints.len())));
    }
    let mut waypoints = Vec::with_capacity(request.waypoints.len());
    for (i, w) in request.waypoints.iter().enumerate() {
        let field = format!("waypoint {}", i + 1);
        let q = w.si(robot, &field)?;
        super::input::require_within_limits(robot, &q, w.unit(), &field)?;
        waypoints.push(q);
    }
    let blend_tolerance = match (request.interpolation, request.blend_tolerance) {
        (Interpolation::Blend, t) => Some(t.unwrap_or(DEFAULT_BLEND_TOLERANCE)),
        (_, None) => None,
        (_, Some(_)) => {
            return Err(Error::request("blend_tolerance", "applies to blend interpolation only"));
        }
    };
    let path = match request.interpolation {
        Interpolation::Spline => PiecewiseCubic::spline(&waypoints)?,
        Interpolation::Linear => PiecewiseCubic::polyline(&waypoints)?,
        Interpolation::Blend => {
            PiecewiseCubic::blended(&waypoints, blend_tolerance.unwrap_or_default()).map_err(request_error)?
        }
    };
    let unit = request.waypoints[0].unit();
    for (j, joint) in robot.joints().iter().enumerate() {
        let ((low, low_at), (high, high_at)) = path.joint_range(j);
        for (value, at, bound, outside) in [
            (low, low_at, joint.limits.lower, low < joint.limits.lower),
            (high, high_at, joint.limits.upper, high > joint.limits.upper),
        ] {
            if outside && !joint.limits.contains(value, crate::tolerance::LIMIT_SLACK) {
                let shown = |v: f64| number_text(from_si(joint.kind, v, unit));
                return Err(Error::request(
                    "waypoints",
                    format!(
                        "the {} through them leaves joint {} ({})'s limit {} {} between waypoints {} and {}: it reaches {} {}; \
                         use linear interpolation or add waypoints",
                        match request.interpolation {
                            Interpolation::Spline => "spline",
                            Interpolation::Linear | Interpolation::Blend => "polyline",
                        },
                        j + 1,
                        joint.name,
                        shown(bound),
                        unit_name(joint.kind, unit),
                        path.waypoint_of_piece(at) + 1,
                        path.waypoint_of_piece(at) + 2,
                        shown(value),
                        unit_name(joint.kind, unit),
                    ),
                ));
            }
        }
    }
    let limits = PathLimits::from_robot(robot, request.max_velocity_scale, request.max_acceleration_scale)
        .map_err(request_error)?;
    let motion = time_optimal(&path, &limits, request.points_per_piece.unwrap_or(0)).map_err(request_error)?;
    let samples = motion
        .samples(request.dt.unwrap_or(0.01))
        .map_err(request_error)?
        .into_iter()
        .map(|s| RetimeSample { t_s: s.t, q: s.q, qd: s.qd, qdd: s.qdd })
        .collect();
    let ratios = motion.worst_ratios().clone();
    Ok(RetimeReport {
        robot: robot.name().to_string(),
        interpolation: request.interpolation,
        blend_tolerance,
        waypoint_times_s: motion.waypoint_times(),
        waypoints: waypoints.len(),
        duration_s: motion.duration(),
        grid_points: motion.grid_points(),
        slowdown: motion.slowdown(),
        velocity_limits: limits.velocity,
        acceleration_limits: limits.acceleration,
        worst_velocity_ratio: ratios.velocity,
        worst_acceleration_ratio: ratios.acceleration,
        samples,
    })
}
