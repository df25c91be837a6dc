//! A timed motion as the ROS 2 message `trajectory_msgs/msg/JointTrajectory` (`reach retime
//! --ros FILE`): the same field names and nesting, so its YAML is what `ros2 topic pub` takes
//! and its JSON what a rosbridge client sends.
//!
//! ROS's units are SI (rad, m, s; REP 103), as are a [`RetimeReport`]'s samples: values are
//! copied unchanged. Times are `builtin_interfaces` whole seconds and nanoseconds, rounded to
//! the nearest nanosecond with `0 ≤ nanosec < 10⁹`.

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::retime::RetimeReport;
use crate::error::{Error, Result};

/// Nanoseconds per second.
const NANOS_PER_SECOND: i64 = 1_000_000_000;

/// `builtin_interfaces/msg/Duration`: `sec + nanosec · 10⁻⁹` seconds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub struct Duration {
    /// Whole seconds (floor of the time, so negative for a negative time).
    pub sec: i32,
    /// Nanoseconds past `sec`, in `[0, 10⁹)`.
    pub nanosec: u32,
}

impl Duration {
    /// `seconds` rounded to the nearest nanosecond (halves away from zero), split into whole
    /// seconds and nanoseconds: 1.9999999999 s is `{sec: 2, nanosec: 0}`, −0.25 s is
    /// `{sec: -1, nanosec: 750000000}`. `None` for a non-finite time or one whose seconds do
    /// not fit an `i32` (about 68 years).
    #[must_use]
    pub fn from_seconds(seconds: f64) -> Option<Duration> {
        let nanos = (seconds * 1e9).round();
        // ±2³¹ s in nanoseconds is far inside i64; beyond it (or NaN) the time is refused
        // before the conversion could saturate.
        let bound = (f64::from(i32::MAX) + 1.0) * 1e9;
        if !nanos.is_finite() || nanos >= bound || nanos < -bound {
            return None;
        }
        #[allow(clippy::cast_possible_truncation, reason = "finite and within ±2⁶² by the check above")]
        let nanos = nanos as i64;
        let sec = i32::try_from(nanos.div_euclid(NANOS_PER_SECOND)).ok()?;
        let nanosec = u32::try_from(nanos.rem_euclid(NANOS_PER_SECOND)).ok()?;
        Some(Duration { sec, nanosec })
    }

    /// The duration in seconds.
    #[must_use]
    pub fn seconds(&self) -> f64 {
        f64::from(self.sec) + f64::from(self.nanosec) * 1e-9
    }
}

/// `builtin_interfaces/msg/Time`: a time stamp, `sec + nanosec · 10⁻⁹` seconds since the
/// epoch.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub struct Time {
    /// Whole seconds.
    pub sec: i32,
    /// Nanoseconds past `sec`, in `[0, 10⁹)`.
    pub nanosec: u32,
}

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
pub struct Header {
    /// When the trajectory starts; zero (as written here) means "now" to a ROS controller.
    pub stamp: Time,
    /// The frame of the data: empty, joint values have none.
    pub frame_id: String,
}

/// `trajectory_msgs/msg/JointTrajectoryPoint`: one sample, SI (rad, rad/s, rad/s²; m, m/s,
/// m/s² for prismatic joints), in the order of [`JointTrajectory::joint_names`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct JointTrajectoryPoint {
    /// Joint values.
    pub positions: Vec<f64>,
    /// Joint speeds.
    pub velocities: Vec<f64>,
    /// Joint accelerations.
    pub accelerations: Vec<f64>,
    /// Joint efforts: empty (not given).
    pub effort: Vec<f64>,
    /// The time of the sample from the start of the trajectory.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/JointTrajectory` (`reach retime --ros FILE`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct JointTrajectory {
    /// Zero stamp, empty frame.
    pub header: Header,
    /// The joints' names, base to tip.
    pub joint_names: Vec<String>,
    /// The samples, in time order.
    pub points: Vec<JointTrajectoryPoint>,
}

impl JointTrajectory {
    /// The message of a retimed motion: one point per sample, the joints named `joint_names`
    /// (the robot's, `robot.joints()[i].name`), values unchanged (both SI), `time_from_start`
    /// the sample's `t_s` to the nearest nanosecond.
    ///
    /// # Errors
    /// [`Error::Request`] (field `joint_names`) when the number of names is not the number of
    /// joints of the samples; (field `t_s`) when a sample's time is not finite or too large
    /// for a ROS duration, or when two samples round to the same nanosecond.
    pub fn from_retime(report: &RetimeReport, joint_names: Vec<String>) -> Result<JointTrajectory> {
        let mut points = Vec::with_capacity(report.samples.len());
        for (i, s) in report.samples.iter().enumerate() {
            if [&s.q, &s.qd, &s.qdd].iter().any(|v| v.len() != joint_names.len()) {
                return Err(Error::request(
                    "joint_names",
                    format!("{} names for samples of {} joints", joint_names.len(), s.q.len()),
                ));
            }
            let time_from_start = Duration::from_seconds(s.t_s)
                .ok_or_else(|| Error::request("t_s", format!("sample {}: {} s is not a ROS duration", i + 1, s.t_s)))?;
            if let Some(previous) = points.last().map(|p: &JointTrajectoryPoint| p.time_from_start)
                && (previous.sec, previous.nanosec) >= (time_from_start.sec, time_from_start.nanosec)
            {
                return Err(Error::request(
                    "t_s",
                    format!("samples {i} and {} are not 1 ns apart: use a larger dt", i + 1),
                ));
            }
            points.push(JointTrajectoryPoint {
                positions: s.q.clone(),
                velocities: s.qd.clone(),
                accelerations: s.qdd.clone(),
                effort: Vec::new(),
                time_from_start,
            });
        }
        Ok(JointTrajectory { header: Header::default(), joint_names, points })
    }

    /// The message as YAML (the form of a message file, or of `ros2 topic pub`'s argument).
    ///
    /// # Errors
    /// [`Error::Request`] if the YAML writer fails (it does not for this type).
    pub fn to_yaml(&self) -> Result<String> {
        serde_norway::to_string(self).map_err(|e| Error::request("yaml", e.to_string()))
    }

    /// Reads the message back from YAML (as written by [`JointTrajectory::to_yaml`]).
    ///
    /// # Errors
    /// [`Error::Request`] (field `yaml`) for text that is not such a message.
    pub fn from_yaml(text: &str) -> Result<JointTrajectory> {
        serde_norway::from_str(text).map_err(|e| Error::request("yaml", e.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::jobs::retime::{Interpolation, RetimeSample};

    #[test]
    fn times_round_to_the_nearest_nanosecond_within_the_second() {
        let d = |t: f64| Duration::from_seconds(t).map(|d| (d.sec, d.nanosec));
        assert_eq!(d(1.999_999_999_9), Some((2, 0)));
        assert_eq!(d(0.0), Some((0, 0)));
        assert_eq!(d(0.01), Some((0, 10_000_000)));
        assert_eq!(d(2.999_999_999_4), Some((2, 999_999_999)));
        assert_eq!(d(1.5e-10), Some((0, 0)));
        assert_eq!(d(-0.25), Some((-1, 750_000_000)));
        assert_eq!(d(-1e-10), Some((0, 0)));
        assert_eq!(d(2_147_483_647.0), Some((i32::MAX, 0)));
        assert_eq!(d(2_147_483_648.0), None);
        assert_eq!(d(f64::NAN), None);
        assert_eq!(d(f64::INFINITY), None);
        for t in [0.0, 0.123_456_789, 7.25, 1_234.000_000_001] {
            let got = Duration::from_seconds(t).unwrap();
            assert!(got.nanosec < 1_000_000_000);
            assert!((got.seconds() - t).abs() <= 0.5e-9 + t * f64::EPSILON, "{t}: {got:?}");
        }
    }

    fn report(times: &[f64]) -> RetimeReport {
        RetimeReport {
            robot: "two".into(),
            interpolation: Interpolation::Linear,
            blend_tolerance: None,
            waypoint_times_s: vec![0.0, *times.last().unwrap()],
            waypoints: 2,
            duration_s: *times.last().unwrap(),
            grid_points: 2,
            slowdown: 1.0,
            velocity_limits: vec![1.0, 1.0],
            acceleration_limits: vec![1.0, 1.0],
            worst_velocity_ratio: vec![0.0, 0.0],
            worst_acceleration_ratio: vec![0.0, 0.0],
            samples: times
                .iter()
                .map(|&t| RetimeSample { t_s: t, q: vec![t, -t], qd: vec![1.0, -1.0], qdd: vec![0.0, 0.0] })
                .collect(),
        }
    }

    #[test]
    fn a_report_becomes_the_message_and_its_yaml_reads_back() {
        let names = vec!["a".to_string(), "b".to_string()];
        let msg = JointTrajectory::from_retime(&report(&[0.0, 0.5, 1.999_999_999_9]), names.clone()).unwrap();
        assert_eq!(msg.joint_names, names);
        assert_eq!(msg.header, Header::default());
        assert_eq!(msg.points.len(), 3);
        assert_eq!(msg.points[2].time_from_start, Duration { sec: 2, nanosec: 0 });
        assert_eq!(msg.points[1].positions, vec![0.5, -0.5]);
        assert!(msg.points.iter().all(|p| p.effort.is_empty()));
        let yaml = msg.to_yaml().unwrap();
        assert!(yaml.contains("time_from_start:") && yaml.contains("nanosec: 500000000"), "{yaml}");
        assert_eq!(JointTrajectory::from_yaml(&yaml).unwrap(), msg);
        let json = serde_json::to_value(&msg).unwrap();
        assert_eq!(json["header"]["stamp"], serde_json::json!({"sec": 0, "nanosec": 0}));
        assert_eq!(json["points"][1]["time_from_start"], serde_json::json!({"sec": 0, "nanosec": 500_000_000}));
    }

    #[test]
    fn bad_names_and_colliding_times_are_request_errors() {
        let wrong = JointTrajectory::from_retime(&report(&[0.0, 1.0]), vec!["a".into()]).unwrap_err();
        assert!(wrong.to_string().contains("joint_names"), "{wrong}");
        let close = JointTrajectory::from_retime(&report(&[0.0, 1e-10]), vec!["a".into(), "b".into()]).unwrap_err();
        assert!(close.to_string().contains("1 ns"), "{close}");
    }
}
