//! The `sense` workflow: seed 000's obstacle located from two or more ultrasonic range
//! readings ([`crate::world::sense`]); `avoid` takes the same request to detour around the
//! sensed obstacle grown by its uncertainty radius.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::Robot;
use crate::error::{Error, Result};
use crate::jobs::input::number_text;
use crate::jobs::world::finite;
use crate::world::sense::{
    Ambiguity, CONFIDENCE, MAX_LENGTH_M, MAX_SENSORS, MIN_SIGMA_M, RangeReading, SenseEstimate, locate,
};

/// Default standard deviation of a range reading, metres: a hobby ultrasonic ranger's
/// centimetre.
pub const DEFAULT_SIGMA_M: f64 = 0.01;

/// Default full opening angle of a beam, degrees (a common ultrasonic ranger's 30°).
pub const DEFAULT_CONE_DEG: f64 = 30.0;

fn default_sigma_m() -> f64 {
    DEFAULT_SIGMA_M
}

fn default_cone_deg() -> f64 {
    DEFAULT_CONE_DEG
}

/// One sensor's pose in the arm's plane and its reading.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorReading {
    /// Sensor position `x, y` in the arm's plane (the base frame's x–y), metres.
    pub xy_m: [f64; 2],
    /// Beam axis direction from +x, degrees.
    pub dir_deg: f64,
    /// Measured distance to the obstacle, metres, > 0.
    pub range_m: f64,
    /// Full opening angle of the beam cone, degrees, in (0, 180) (default 30); the echo comes
    /// from within half of it on either side of the axis.
    #[serde(default = "default_cone_deg")]
    pub cone_deg: f64,
    /// This reading's standard deviation, metres (default: the request's `sigma_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma_m: Option<f64>,
}

/// Range readings from two or more sensors at known poses.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SenseRequest {
    /// The readings: at least 2, at most 32.
    pub sensors: Vec<SensorReading>,
    /// Standard deviation of the readings that give none, metres (default 0.01), in
    /// [1e-9, 1e6]; coordinates and ranges are at most 1e6 m.
    #[serde(default = "default_sigma_m")]
    pub sigma_m: f64,
}

/// The located obstacle (`reach sense --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SenseReport {
    /// Robot name (the readings are in its base frame's x–y plane).
    pub robot: String,
    /// Estimated obstacle position `x, y`, metres (weighted least squares).
    pub obstacle_m: [f64; 2],
    /// Radius of the circle about `obstacle_m` that holds the obstacle with probability
    /// `confidence`, metres; `null` when the geometry leaves a direction undetermined.
    pub uncertainty_m: Option<f64>,
    /// Probability of `uncertainty_m` (0.9973, the one-dimensional 3σ probability).
    pub confidence: f64,
    /// Root mean square of the range residuals at the estimate, metres (0 for two readings
    /// that meet).
    pub residual_m: f64,
    /// Each reading's residual `|x − p| − range`, metres.
    pub residuals_m: Vec<f64>,
    /// Whether the geometry cannot separate solutions; the estimate is then not to be trusted.
    pub ambiguous: bool,
    /// Why: `alternatives` (another position fits, e.g. both intersections of two range
    /// circles inside both cones) or `ill_conditioned` (sensors near-collinear with the
    /// obstacle).
    pub ambiguity: Option<Ambiguity>,
    /// The other positions that fit, metres.
    pub alternatives_m: Vec<[f64; 2]>,
    /// Covariance of `obstacle_m`, m², row-major; `null` when singular.
    pub covariance_m2: Option<[[f64; 2]; 2]>,
}

/// A length `> 0` (at least `min`) and at most [`MAX_LENGTH_M`].
fn length(field: &str, value: f64, min: f64) -> Result<()> {
    if !(value.is_finite() && value > 0.0) {
        Err(Error::request(field, format!("must be > 0 m, got {}", number_text(value))))
    } else if value > MAX_LENGTH_M {
        Err(Error::request(field, format!("must be at most {MAX_LENGTH_M:e} m, got {value:e}")))
    } else if value < min {
        Err(Error::request(field, format!("must be at least {min:e} m, got {value:e}")))
    } else {
        Ok(())
    }
}

impl SenseRequest {
    /// The readings in SI units, checked field by field (`sensors[2].range_m: …`, 1-based).
    ///
    /// # Errors
    /// [`Error::Request`] for fewer than 2 or more than 32 sensors, a non-finite position or
    /// direction, a range or sigma that is not > 0, a cone outside (0, 180) degrees.
    pub fn readings(&self) -> Result<Vec<RangeReading>> {
        let n = self.sensors.len();
        if n < 2 {
            return Err(Error::request("sensors", format!("need readings from at least 2 sensors, got {n}")));
        }
        if n > MAX_SENSORS {
            return Err(Error::request("sensors", format!("at most {MAX_SENSORS} sensors, got {n}")));
        }
        length("sigma_m", self.sigma_m, MIN_SIGMA_M)?;
        self.sensors
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let field = |name: &str| format!("sensors[{}].{name}", i + 1);
                finite(&field("xy_m"), &s.xy_m)?;
                if let Some(v) = s.xy_m.iter().find(|v| v.abs() > MAX_LENGTH_M) {
                    return Err(Error::request(
                        field("xy_m"),
                        format!("at most {MAX_LENGTH_M:e} m from the origin, got {v:e}"),
                    ));
                }
                if !s.dir_deg.is_finite() {
                    return Err(Error::request(
                        field("dir_deg"),
                        format!("expected a finite number, got {}", s.dir_deg),
                    ));
                }
                length(&field("range_m"), s.range_m, 0.0)?;
                if !(s.cone_deg > 0.0 && s.cone_deg < 180.0) {
                    return Err(Error::request(
                        field("cone_deg"),
                        format!("the full beam angle must be in (0, 180) deg, got {}", number_text(s.cone_deg)),
                    ));
                }
                if let Some(sigma) = s.sigma_m {
                    length(&field("sigma_m"), sigma, MIN_SIGMA_M)?;
                }
                Ok(RangeReading {
                    position: s.xy_m,
                    direction: s.dir_deg.to_radians(),
                    half_angle: (s.cone_deg / 2.0).to_radians(),
                    range: s.range_m,
                    sigma: s.sigma_m.unwrap_or(self.sigma_m),
                })
            })
            .collect()
    }

    /// Locates the obstacle.
    ///
    /// # Errors
    /// As [`SenseRequest::readings`]; [`Error::World`] for two sensors at one point or
    /// readings that no position fits inside every beam cone.
    pub fn locate(&self) -> Result<SenseEstimate> {
        Ok(locate(&self.readings()?)?)
    }
}

impl SenseReport {
    /// The report of an estimate.
    #[must_use]
    pub fn of(robot: &Robot, e: &SenseEstimate) -> Self {
        SenseReport {
            robot: robot.name().to_string(),
            obstacle_m: e.position,
            uncertainty_m: e.uncertainty,
            confidence: CONFIDENCE,
            residual_m: e.residual_rms,
            residuals_m: e.residuals.clone(),
            ambiguous: e.ambiguity.is_some(),
            ambiguity: e.ambiguity,
            alternatives_m: e.alternatives.clone(),
            covariance_m2: e.covariance,
        }
    }
}

/// Locates the obstacle from the readings (see [`crate::world::sense`]). An ambiguous geometry
/// is an answer (`ambiguous`), not an error.
///
/// # Errors
/// As [`SenseRequest::locate`].
pub fn sense(robot: &Robot, request: &SenseRequest) -> Result<SenseReport> {
    Ok(SenseReport::of(robot, &request.locate()?))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reading(xy_m: [f64; 2], dir_deg: f64, range_m: f64) -> SensorReading {
        SensorReading { xy_m, dir_deg, range_m, cone_deg: DEFAULT_CONE_DEG, sigma_m: None }
    }

    #[test]
    fn bad_readings_name_the_sensor_and_the_field() {
        let robot = crate::model::presets::get("planar3").unwrap();
        let good = SenseRequest {
            sensors: vec![reading([0.5, -0.5], 43.66, 1.920937), reading([3.0, -0.5], 129.81, 1.56205)],
            sigma_m: 0.01,
        };
        let report = sense(&robot, &good).unwrap();
        assert!((report.obstacle_m[0] - 2.0).abs() < 1e-5 && (report.obstacle_m[1] - 0.7).abs() < 1e-5);
        assert!(!report.ambiguous);
        let error = |f: &dyn Fn(&mut SenseRequest)| {
            let mut r = good.clone();
            f(&mut r);
            sense(&robot, &r).unwrap_err().to_string()
        };
        assert_eq!(error(&|r| r.sensors.truncate(1)), "sensors: need readings from at least 2 sensors, got 1");
        assert_eq!(error(&|r| r.sensors[1].range_m = f64::NAN), "sensors[2].range_m: must be > 0 m, got NaN");
        assert_eq!(error(&|r| r.sensors[0].range_m = -1.0), "sensors[1].range_m: must be > 0 m, got -1");
        assert_eq!(error(&|r| r.sigma_m = 0.0), "sigma_m: must be > 0 m, got 0");
        assert_eq!(error(&|r| r.sensors[1].sigma_m = Some(0.0)), "sensors[2].sigma_m: must be > 0 m, got 0");
        assert_eq!(
            error(&|r| r.sensors[0].xy_m[1] = f64::INFINITY),
            "sensors[1].xy_m[2]: expected a finite number, got inf"
        );
        assert!(error(&|r| r.sensors[0].cone_deg = 180.0).starts_with("sensors[1].cone_deg: the full beam angle"));
        assert_eq!(error(&|r| r.sigma_m = 1e-300), "sigma_m: must be at least 1e-9 m, got 1e-300");
        assert_eq!(error(&|r| r.sensors[0].range_m = 1e300), "sensors[1].range_m: must be at most 1e6 m, got 1e300");
        assert!(error(&|r| r.sensors[1].xy_m[0] = -2e6).starts_with("sensors[2].xy_m: at most 1e6 m"));
    }
}
