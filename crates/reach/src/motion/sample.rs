//! Sampled motions: the plain values other stages consume.
//!
//! * [`ToolPath`] — a tool path as a list of [`PathSample`]s: time `t` (s), arc length `s`
//!   of the tool point from the start (m), rotation angle done so far (rad) and the pose
//!   (world ← tool). Produced by [`ToolMotion::sample_time`](super::ToolMotion::sample_time)
//!   and [`ToolMotion::sample_length`](super::ToolMotion::sample_length); any other producer
//!   may fill one directly (the fields are public). Samples are in time order, the first at
//!   the start of the motion and the last exactly at its end.
//! * [`JointTrajectory`] — a joint motion as a list of [`JointSample`]s: time and joint
//!   vector, with a flag when a sample is outside the joint limits. Produced by
//!   [`JointMotion::sample`](super::JointMotion::sample), [`JointPath::sample`](super::JointPath::sample)
//!   and [`ToolPath::to_joints`]; consumed by the effort functionals
//!   ([`effort::j2`](crate::effort::j2) takes [`JointTrajectory::rows`]).
//!
//! [`ToolPath::to_joints`] is the simple per-sample IK of seed 001 (notes 001 §4.4): every
//! sample is solved (with the solver [`ik::solve`] would pick, detected once) and the feasible solution closest to the previous sample is taken (the
//! previous sample also seeds the solver, so singular wrists keep their roll). It does not
//! split paths at singularities or keep a branch on purpose — that is path tracking's job.
//!
//! Sampling grids ([`sample_times`]) include both end points exactly; a step that does not
//! divide the interval leaves a shorter last step (notes 001 §9 "a non-integer sample count").

use nalgebra::Isometry3;
use serde::Serialize;

use super::{MotionError, check_number};
use crate::ik::{self, IkFailure, IkOptions, IkSolution, IkTarget};
use crate::model::Robot;
use crate::tolerance::{LIMIT_SLACK, SAMPLE_GRID};

/// One sample of a tool path: the samples of a [`ToolPath`] and the input of path tracking
/// ([`TrackedPath`](super::tracking::TrackedPath)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PathSample {
    /// Time, seconds.
    pub t: f64,
    /// Path parameter: the arc length of the tool point from the start of the path, metres.
    /// Path tracking accepts any strictly increasing parameter here.
    pub s: f64,
    /// Rotation angle of the tool from its start orientation, radians (about the path's axis).
    /// Path tracking does not read it.
    pub angle: f64,
    /// Tool pose in the world frame.
    pub pose: Isometry3<f64>,
}

/// A sampled tool path (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToolPath {
    /// The samples in time order; the first at the start, the last at the end of the motion.
    pub samples: Vec<PathSample>,
    /// Total length of the tool point's path, metres.
    pub length: f64,
    /// Total rotation angle of the tool, radians.
    pub angle: f64,
}

/// One sample of a joint motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointSample {
    /// Time, seconds.
    pub t: f64,
    /// Joint values (radians / metres).
    pub q: Vec<f64>,
    /// Whether every joint is within its limits (always `true` for joint motions built without
    /// a robot).
    pub within_limits: bool,
}

impl JointSample {
    /// A sample of `robot` at time `t` with joint values `q` (SI), flagged against the joints'
    /// position limits.
    #[must_use]
    pub fn of(robot: &Robot, t: f64, q: Vec<f64>) -> Self {
        let within_limits = robot.first_joint_outside_limits(&q, LIMIT_SLACK).is_none();
        JointSample { t, q, within_limits }
    }
}

/// A sampled joint motion (see the module docs).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectory {
    /// The samples in time order.
    pub samples: Vec<JointSample>,
}

impl JointTrajectory {
    /// The joint vectors, one row per sample (for [`effort::j2`](crate::effort::j2)).
    #[must_use]
    pub fn rows(&self) -> Vec<&[f64]> {
        self.samples.iter().map(|s| s.q.as_slice()).collect()
    }

    /// The sample times.
    #[must_use]
    pub fn times(&self) -> Vec<f64> {
        self.samples.iter().map(|s| s.t).collect()
    }

    /// Number of samples outside the joint limits.
    #[must_use]
    pub fn outside_limits(&self) -> usize {
        self.samples.iter().filter(|s| !s.within_limits).count()
    }
}

/// How [`ToolPath::to_joints`] picks a solution at each sample.
#[derive(Debug, Clone, PartialEq)]
pub struct PerSampleIk {
    /// Weights of the joint-change cost `Σ wᵢ |Δqᵢ|` (wrapped angle differences) used to pick
    /// the solution closest to the previous sample; missing entries count as 1.
    pub weights: Vec<f64>,
    /// Configuration the first sample should be closest to (default: the robot's home).
    pub start: Option<Vec<f64>>,
    /// When no solution is within limits: `true` takes the closest solution outside limits and
    /// flags the sample (the thesis warns and continues, notes 001 §4.2 step 8); `false`
    /// stops with [`MotionError::NoIkSolution`].
    pub allow_outside_limits: bool,
    /// Options passed to the IK solver (`seed` is overwritten with the previous sample).
    pub ik: IkOptions,
}

impl Default for PerSampleIk {
    /// Seed 001's weights, start at home, strict limits, default IK options.
    fn default() -> Self {
        PerSampleIk {
            weights: crate::effort::DEFAULT_SIX_JOINT_WEIGHTS.to_vec(),
            start: None,
            allow_outside_limits: false,
            ik: IkOptions::default(),
        }
    }
}

impl ToolPath {
    /// Solves IK at every sample, taking the solution closest to the previous one (see the
    /// module docs and [`PerSampleIk`]).
    ///
    /// # Errors
    /// [`MotionError::NoIkSolution`] naming the first sample without a (feasible, unless
    /// allowed otherwise) solution; [`MotionError::Ik`] for solver errors; a length error when
    /// `start` does not fit the robot.
    ///
    /// # Example
    /// ```
    /// use reach::motion::{Profile, ToolMotion, sample::PerSampleIk};
    /// let puma = reach::model::presets::get("puma560").unwrap();
    /// let q0 = [0.0, 0.6, -0.3, 0.2, 0.5, 0.1];
    /// let start = puma.fk(&q0).unwrap();
    /// let end = nalgebra::Translation3::new(0.0, 0.0, -0.1) * start;
    /// let path = ToolMotion::new(start, end, 0.0, 1.0, Profile::Quintic).unwrap().sample_time(0.1).unwrap();
    /// let options = PerSampleIk { start: Some(q0.to_vec()), ..PerSampleIk::default() };
    /// let joints = path.to_joints(&puma, &options).unwrap();
    /// assert_eq!(joints.samples.len(), 11);
    /// assert!(joints.samples[0].q.iter().zip(&q0).all(|(a, b)| (a - b).abs() < 1e-9));
    /// ```
    pub fn to_joints(&self, robot: &Robot, options: &PerSampleIk) -> Result<JointTrajectory, MotionError> {
        let mut previous = match &options.start {
            Some(q) => {
                super::check_vector("start", q, robot.dof())?;
                q.clone()
            }
            None => robot.home(),
        };
        let mut ik_options = options.ik.clone();
        // `ik::solve` would detect the solver at every sample; detect it once.
        let solver = ik::SolverKind::detect(robot).build(robot)?;
        let mut samples = Vec::with_capacity(self.samples.len());
        for (k, sample) in self.samples.iter().enumerate() {
            ik_options.seed = Some(previous.clone());
            let mut all = solver.solve(robot, &IkTarget::Pose(sample.pose), &ik_options)?;
            all.express_near(robot, &previous);
            let chosen: Option<&IkSolution> = match all.closest_to(&previous, &options.weights) {
                Some(s) => Some(s),
                None if options.allow_outside_limits => closest_any(&all.solutions, &previous, &options.weights),
                None => None,
            };
            let Some(chosen) = chosen else {
                let failure = all.failure.clone().unwrap_or(IkFailure::OrientationUnreachable);
                return Err(MotionError::NoIkSolution { which: format!("sample {k} (t = {} s)", sample.t), failure });
            };
            samples.push(JointSample { t: sample.t, q: chosen.q.clone(), within_limits: chosen.within_limits });
            previous.clone_from(&chosen.q);
        }
        Ok(JointTrajectory { samples })
    }
}

/// The solution (feasible or not) with the smallest weighted wrapped change from `from`.
fn closest_any<'a>(solutions: &'a [IkSolution], from: &[f64], weights: &[f64]) -> Option<&'a IkSolution> {
    let cost = |s: &IkSolution| -> f64 {
        s.q.iter()
            .zip(from)
            .enumerate()
            .map(|(i, (a, b))| weights.get(i).copied().unwrap_or(1.0) * crate::angle::wrap(a - b).abs())
            .sum()
    };
    solutions.iter().min_by(|a, b| cost(a).total_cmp(&cost(b)))
}

/// Largest number of steps of one sampling grid (time or arc length): `duration / dt`
/// above this is refused before the grid is built (every sample of a motion holds a joint
/// vector, its rates and a tool pose, and is printed).
pub const MAX_SAMPLES: f64 = 1e7;

/// The longest motion a request may describe, seconds (one day): a typo such as `1e308`
/// is refused before anything is planned or driven (a drive holds its queue for the motion's
/// whole duration).
pub const MAX_DURATION_S: f64 = 86_400.0;

/// Refuses a motion duration above [`MAX_DURATION_S`] (`field` names it in the message).
///
/// # Errors
/// [`MotionError::InvalidInput`] naming `field`.
pub fn check_duration(field: &str, duration: f64) -> Result<(), MotionError> {
    if duration > MAX_DURATION_S {
        return Err(MotionError::InvalidInput {
            field: field.into(),
            reason: format!("at most {MAX_DURATION_S} s (one day), got {duration:?} s"),
        });
    }
    Ok(())
}

/// Sample times `t0, t0 + dt, …, t0 + duration` (see the module docs).
///
/// The end is always included exactly; a grid point within [`SAMPLE_GRID`]·`dt` of the end
/// is replaced by it (so `10 / 0.1` gives 101 samples, not 102).
///
/// # Errors
/// [`MotionError::InvalidInput`] when a number is not finite, `duration` is negative, `dt` is
/// not positive, `duration` exceeds [`MAX_DURATION_S`] (one day), or the grid would exceed
/// [`MAX_SAMPLES`] (10 million) samples.
///
/// # Example
/// ```
/// let t = reach::motion::sample::sample_times(0.0, 10.0, 0.1).unwrap();
/// assert_eq!(t.len(), 101);
/// assert_eq!(t[100], 10.0);
/// let t = reach::motion::sample::sample_times(0.0, 1.0, 0.3).unwrap();
/// assert_eq!(t.len(), 5); // 0, 0.3, 0.6, 0.9, 1.0
/// ```
pub fn sample_times(t0: f64, duration: f64, dt: f64) -> Result<Vec<f64>, MotionError> {
    check_duration("duration", duration)?;
    grid(t0, duration, dt, "duration", "dt")
}

/// `start, start + step, …, start + span` with the end exact (shared by time and arc-length grids).
pub(crate) fn grid(
    start: f64,
    span: f64,
    step: f64,
    span_name: &str,
    step_name: &str,
) -> Result<Vec<f64>, MotionError> {
    check_number("t0", start, false)?;
    check_number(span_name, span, false)?;
    check_number(step_name, step, true)?;
    if span < 0.0 {
        return Err(MotionError::InvalidInput {
            field: span_name.into(), reason: format!("must be ≥ 0, got {span}")
        });
    }
    let steps = span / step;
    if steps > MAX_SAMPLES {
        return Err(MotionError::InvalidInput {
            field: step_name.into(),
            reason: format!("{step} gives {steps:.0} samples over {span} (more than 10 million)"),
        });
    }
    let mut n = steps.floor() as usize; // whole steps
    if steps - (n as f64) > 1.0 - SAMPLE_GRID {
        n += 1;
    }
    let mut out: Vec<f64> = (0..=n).map(|k| start + k as f64 * step).collect();
    let end = start + span;
    let last = out.len() - 1;
    if (out[last] - end).abs() <= SAMPLE_GRID * step || out[last] > end {
        out[last] = end;
    } else {
        out.push(end);
    }
    if out.len() >= 2 && out[out.len() - 2] >= out[out.len() - 1] {
        out.remove(out.len() - 2); // span = 0 or rounding put two points on the end
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_motion_longer_than_a_day_is_refused() {
        assert_eq!(sample_times(0.0, MAX_DURATION_S, 864.0).unwrap().len(), 101);
        for duration in [MAX_DURATION_S * (1.0 + 1e-12), 1e308] {
            let e = sample_times(0.0, duration, duration / 100.0).unwrap_err().to_string();
            assert!(e.contains("duration") && e.contains("86400"), "{e}");
        }
    }

    #[test]
    fn grids_include_both_ends() {
        assert_eq!(sample_times(0.0, 10.0, 0.1).unwrap().len(), 101);
        assert_eq!(sample_times(2.0, 1.0, 0.25).unwrap(), vec![2.0, 2.25, 2.5, 2.75, 3.0]);
        let t = sample_times(0.0, 1.0, 0.3).unwrap();
        assert_eq!(t.len(), 5);
        assert!((t[3] - 0.9).abs() < 1e-15 && t[4] == 1.0);
        assert_eq!(sample_times(1.0, 0.0, 0.1).unwrap(), vec![1.0]);
        assert_eq!(sample_times(0.0, 0.05, 0.1).unwrap(), vec![0.0, 0.05]);
        assert!(sample_times(0.0, 1.0, 0.0).is_err());
        assert!(sample_times(0.0, -1.0, 0.1).is_err());
        assert!(sample_times(f64::NAN, 1.0, 0.1).is_err());
        assert!(sample_times(0.0, 1.0, 1e-9).is_err());
    }
}
