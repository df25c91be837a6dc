//! `reach sense` — seed 000's obstacle located from ultrasonic range readings
//! (`reach::jobs::world::sense`; `--json` prints its report). The `--sensor` parsing and its
//! error messages are shared with `reach avoid --sensor`.

use std::io::Write;

use clap::Args;
use reach::jobs::world::sense::{DEFAULT_CONE_DEG, DEFAULT_SIGMA_M};
use reach::jobs::world::{SenseReport, SenseRequest, SensorReading, sense};

use crate::error::CliError;
use crate::numbers::{parse_finite, parse_list};
use crate::output::{Table, fixed, write_json};
use crate::robot_arg::RobotArgs;

/// Arguments of `reach sense`.
#[derive(Debug, Clone, Args)]
pub struct SenseArgs {
    /// The robot whose base frame's x–y plane holds the sensors (e.g. `planar3`).
    #[command(flatten)]
    pub robot: RobotArgs,

    /// The readings (at least 2).
    #[command(flatten)]
    pub sensors: SensorArgs,

    /// Print the report as JSON (docs/schemas/sense.report.schema.json).
    #[arg(long)]
    pub json: bool,
}

/// The `--sensor` and `--sigma` arguments (`reach sense`, `reach avoid`).
#[derive(Debug, Clone, Args)]
pub struct SensorArgs {
    /// One sensor's pose and reading: position x,y [m], beam direction [deg from +x], measured
    /// range [m], and optionally the beam's full opening angle [deg, default 30] (repeatable).
    #[arg(long, value_name = "X,Y,DIR_DEG,RANGE[,CONE_DEG]", allow_hyphen_values = true)]
    pub sensor: Vec<String>,

    /// Standard deviation of every range reading [m] (default 0.01).
    #[arg(long, value_name = "M", requires = "sensor")]
    pub sigma: Option<String>,
}

impl SensorArgs {
    /// The library request, or `None` without `--sensor`.
    ///
    /// # Errors
    /// [`CliError::BadInput`] for a malformed reading (`--sensor 2: expected 4 or 5 numbers …`).
    pub fn request(&self) -> Result<Option<SenseRequest>, CliError> {
        if self.sensor.is_empty() {
            return Ok(None);
        }
        let sensors = self
            .sensor
            .iter()
            .enumerate()
            .map(|(i, text)| {
                let option = format!("--sensor {}", i + 1);
                let v = parse_list(&option, text)?;
                if !(4..=5).contains(&v.len()) {
                    return Err(CliError::bad_input(format!(
                        "{option}: expected 4 or 5 numbers (X,Y,DIR_DEG,RANGE[,CONE_DEG]), got {}",
                        v.len()
                    )));
                }
                Ok(SensorReading {
                    xy_m: [v[0], v[1]],
                    dir_deg: v[2],
                    range_m: v[3],
                    cone_deg: v.get(4).copied().unwrap_or(DEFAULT_CONE_DEG),
                    sigma_m: None,
                })
            })
            .collect::<Result<_, _>>()?;
        let sigma_m = self.sigma.as_deref().map(|t| parse_finite("--sigma", t)).transpose()?.unwrap_or(DEFAULT_SIGMA_M);
        Ok(Some(SenseRequest { sensors, sigma_m }))
    }
}

/// The library's error with the reading named as on the command line:
/// `sensors[2].range_m` → `--sensor 2 (RANGE)`, `sigma_m` → `--sigma`; other fields by `flags`
/// (as [`crate::error::flagged`]).
#[must_use]
pub fn sensor_error(e: reach::Error, flags: &[(&str, &str)]) -> CliError {
    if let reach::Error::Request { field, reason } = &e {
        let reading = field.strip_prefix("sensors[").and_then(|rest| rest.split_once(']'));
        if let Some((i, tail)) = reading {
            let what = match tail {
                t if t.starts_with(".xy_m") => " (X,Y)",
                ".dir_deg" => " (DIR_DEG)",
                ".range_m" => " (RANGE)",
                ".cone_deg" => " (CONE_DEG)",
                _ => "",
            };
            return CliError::bad_input(format!("--sensor {i}{what}: {reason}"));
        }
    }
    let mut all = vec![("sensors", "--sensor"), ("sigma_m", "--sigma")];
    all.extend_from_slice(flags);
    crate::error::flagged(e, &all)
}

/// Locates the obstacle and prints it.
///
/// # Errors
/// [`CliError::BadInput`] for bad readings (naming the sensor and the field) or readings no
/// position fits; [`CliError::Output`].
pub fn run(args: &SenseArgs, out: &mut dyn Write) -> Result<(), CliError> {
    let loaded = args.robot.load()?;
    let Some(request) = args.sensors.request()? else {
        return Err(CliError::bad_input("--sensor: give readings from at least 2 sensors"));
    };
    let report = sense(&loaded.robot, &request).map_err(|e| sensor_error(e, &[]))?;
    if args.json {
        return write_json(out, &report);
    }
    write_text(&report, out)
}

fn write_text(r: &SenseReport, out: &mut dyn Write) -> Result<(), CliError> {
    let xy = |p: &[f64; 2]| format!("({}, {}) m", fixed(p[0], 6), fixed(p[1], 6));
    let mut head = Table::key_value();
    head.pair("robot", r.robot.clone());
    head.pair("obstacle", xy(&r.obstacle_m));
    head.pair(
        "uncertainty",
        r.uncertainty_m.map_or("undetermined (singular geometry)".into(), |u| {
            format!("{} m radius ({} % confidence)", fixed(u, 6), fixed(100.0 * r.confidence, 2))
        }),
    );
    head.pair("residual (rms)", format!("{} m", fixed(r.residual_m, 6)));
    let verdict = match r.ambiguity {
        None => "no".to_string(),
        Some(reach::world::sense::Ambiguity::Alternatives) => {
            format!("yes: other positions fit: {}", r.alternatives_m.iter().map(xy).collect::<Vec<_>>().join(", "))
        }
        Some(reach::world::sense::Ambiguity::IllConditioned) => {
            "yes: the sensors are nearly in line with the obstacle".to_string()
        }
    };
    head.pair("ambiguous", verdict);
    head.write(out, "")
}
