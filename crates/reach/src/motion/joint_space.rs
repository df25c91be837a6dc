//! Joint-space motion: `q(t) = q0 + λ(τ)·Δq` (seed 001 §3.6, "acceleration–deceleration
//! mode", with any [`Profile`]).
//!
//! # The joint difference `Δq`
//!
//! `Δqᵢ` is the crate's one joint-difference rule, [`Joint::difference`](crate::model::Joint::difference):
//! the shortest signed angle for a revolute joint without limits, the literal difference for
//! every other joint — so that a joint whose range does not contain the short way round (e.g.
//! seed 001's q1 ∈ [0°, 360°] going from 350° to 10°) stays inside its limits: a motion between
//! two configurations within limits is within limits at every instant, since each joint moves
//! monotonically between its end values.
//!
//! [`JointMotion::new`] (no robot) always uses the literal difference.
//!
//! # Between poses
//!
//! [`JointMotion::between_poses`] solves IK at both ends ([`ik::solve`]) and picks, among the
//! solutions within limits, the one with the smallest weighted change
//! ([`IkSolutions::closest_to`](crate::ik::IkSolutions::closest_to)): the start closest to a
//! reference configuration (default: home), the end closest to the chosen start. The default
//! weights are seed 001's [`DEFAULT_SIX_JOINT_WEIGHTS`](crate::effort::DEFAULT_SIX_JOINT_WEIGHTS).

use nalgebra::Isometry3;

use super::sample::{JointSample, JointTrajectory, sample_times};
use super::timing::{JointRates, Timing};
use super::{MotionError, Profile, check_number, check_vector};
use crate::ik::{self, IkFailure, IkOptions, IkTarget};
use crate::model::Robot;
use crate::tolerance::LIMIT_SLACK;

/// A point-to-point joint motion `q(t) = q0 + λ((t − t0)/T)·Δq`.
///
/// # Example
/// Seed 001's joint-space motion (notes 001 §3.6, §5.2): from home to (90°, 0, 0, 90°, 0, 0)
/// in 10 s; at t = 5 s every joint is half-way.
/// ```
/// use reach::motion::{JointMotion, Profile};
/// use std::f64::consts::FRAC_PI_2;
/// let spbu6 = reach::model::presets::get("spbu6").unwrap();
/// let q1 = [FRAC_PI_2, 0.0, 0.0, FRAC_PI_2, 0.0, 0.0];
/// let m = JointMotion::for_robot(&spbu6, &[0.0; 6], &q1, 0.0, 10.0, Profile::Cycloidal).unwrap();
/// assert!((m.position(5.0)[0] - FRAC_PI_2 / 2.0).abs() < 1e-15);
/// assert!((m.position(1.0)[3] - 0.006451 * FRAC_PI_2).abs() < 1e-6);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct JointMotion {
    q0: Vec<f64>,
    delta: Vec<f64>,
    limits_checked: bool,
    within_limits: bool,
    t0: f64,
    duration: f64,
    profile: Profile,
}

/// How [`JointMotion::between_poses`] picks the IK solutions at the two ends.
#[derive(Debug, Clone, PartialEq)]
pub struct EndChoice {
    /// Weights of `Σ wᵢ |Δqᵢ|`; missing entries count as 1. Default: seed 001's.
    pub weights: Vec<f64>,
    /// The start solution is the one closest to this (default: the robot's home).
    pub reference: Option<Vec<f64>>,
    /// Options for the IK solver (the seed is set to the reference / the start).
    pub ik: IkOptions,
}

impl Default for EndChoice {
    fn default() -> Self {
        EndChoice {
            weights: crate::effort::DEFAULT_SIX_JOINT_WEIGHTS.to_vec(),
            reference: None,
            ik: IkOptions::default(),
        }
    }
}

impl JointMotion {
    /// A motion between two joint vectors with the literal difference `q1 − q0` (no robot,
    /// no wrapping, no limit check).
    ///
    /// # Errors
    /// [`MotionError`] when the vectors differ in length or hold NaN/infinity, `t0` is not
    /// finite, or `duration` is not a positive finite number.
    pub fn new(q0: &[f64], q1: &[f64], t0: f64, duration: f64, profile: Profile) -> Result<Self, MotionError> {
        check_vector("q0", q0, q0.len())?;
        check_vector("q1", q1, q0.len())?;
        check_time(t0, duration)?;
        let delta = q0.iter().zip(q1).map(|(a, b)| b - a).collect();
        Ok(JointMotion { q0: q0.to_vec(), delta, limits_checked: false, within_limits: true, t0, duration, profile })
    }

    /// A motion between two joint vectors of `robot`, with the wrap policy of the module docs.
    /// The motion is flagged ([`JointMotion::within_limits`]) when either end is outside the
    /// joint limits.
    ///
    /// # Errors
    /// As [`JointMotion::new`], and a length error when a vector does not have one value per joint.
    pub fn for_robot(
        robot: &Robot,
        q0: &[f64],
        q1: &[f64],
        t0: f64,
        duration: f64,
        profile: Profile,
    ) -> Result<Self, MotionError> {
        check_vector("q0", q0, robot.dof())?;
        check_vector("q1", q1, robot.dof())?;
        check_time(t0, duration)?;
        let delta = robot.joints().iter().zip(q0.iter().zip(q1)).map(|(j, (a, b))| j.difference(*a, *b)).collect();
        let inside = |q: &[f64]| robot.first_joint_outside_limits(q, LIMIT_SLACK).is_none();
        Ok(JointMotion {
            q0: q0.to_vec(),
            delta,
            limits_checked: true,
            within_limits: inside(q0) && inside(q1),
            t0,
            duration,
            profile,
        })
    }

    /// The fastest synchronised motion of `robot` from `q0` to `q1` with `profile` within
    /// `rates` ([`Timing::synchronised`]; for a trapezoid the acceleration fraction is chosen
    /// too, [`Timing::synchronised_trapezoid`]). Returns the motion and its timing.
    ///
    /// # Errors
    /// As [`JointMotion::for_robot`]; [`MotionError::InvalidInput`] when no joint moves (a
    /// zero duration) or a trapezoid is asked for without acceleration limits.
    pub fn synchronised(
        robot: &Robot,
        q0: &[f64],
        q1: &[f64],
        t0: f64,
        rates: &JointRates,
        profile: Profile,
    ) -> Result<(Self, Timing), MotionError> {
        let mut motion = JointMotion::for_robot(robot, q0, q1, t0, 1.0, profile)?;
        let timing = match profile {
            Profile::Trapezoidal { .. } => Timing::synchronised_trapezoid(&motion.delta, rates)?,
            _ => Timing::synchronised(&motion.delta, rates, profile)?,
        };
        if timing.duration <= 0.0 {
            return Err(MotionError::InvalidInput {
                field: "q1".into(),
                reason: "equals q0: no joint moves, nothing to time".into(),
            });
        }
        motion.duration = timing.duration;
        motion.profile = timing.profile;
        Ok((motion, timing))
    }

    /// A motion between two tool poses: IK at both ends, solutions chosen as in the module docs.
    ///
    /// # Errors
    /// [`MotionError::NoIkSolution`] when an end has no solution within limits (naming it and
    /// the solver's reason); [`MotionError::Ik`] for invalid poses; as [`JointMotion::new`].
    ///
    /// # Example
    /// Seed 001's example (notes 001 §5.1–5.2): T0 is home, T1 gives (90°, 0, 0, 90°, 0, 0).
    /// ```
    /// use reach::motion::{JointMotion, Profile, joint_space::EndChoice};
    /// let spbu6 = reach::model::presets::get("spbu6").unwrap();
    /// let t0 = spbu6.fk(&[0.0; 6]).unwrap();
    /// let t1 = spbu6.fk(&[1.5707963267948966, 0.0, 0.0, 1.5707963267948966, 0.0, 0.0]).unwrap();
    /// let m = JointMotion::between_poses(&spbu6, &t0, &t1, 0.0, 10.0, Profile::Cycloidal, &EndChoice::default()).unwrap();
    /// assert!(m.start().iter().all(|v| v.abs() < 1e-9));
    /// assert!((m.end()[0] - 1.5707963267948966).abs() < 1e-9);
    /// ```
    pub fn between_poses(
        robot: &Robot,
        start: &Isometry3<f64>,
        end: &Isometry3<f64>,
        t0: f64,
        duration: f64,
        profile: Profile,
        choice: &EndChoice,
    ) -> Result<Self, MotionError> {
        check_time(t0, duration)?;
        let reference = match &choice.reference {
            Some(q) => {
                check_vector("reference", q, robot.dof())?;
                q.clone()
            }
            None => robot.home(),
        };
        let q0 = solve_end(robot, start, &reference, choice, "start pose")?;
        let q1 = solve_end(robot, end, &q0, choice, "end pose")?;
        JointMotion::for_robot(robot, &q0, &q1, t0, duration, profile)
    }

    /// Start configuration.
    #[must_use]
    pub fn start(&self) -> &[f64] {
        &self.q0
    }

    /// End configuration, `q0 + Δq` (for an unlimited revolute joint this may differ from the
    /// given `q1` by whole turns).
    #[must_use]
    pub fn end(&self) -> Vec<f64> {
        self.q0.iter().zip(&self.delta).map(|(a, d)| a + d).collect()
    }

    /// The joint differences `Δq`.
    #[must_use]
    pub fn delta(&self) -> &[f64] {
        &self.delta
    }

    /// Start time, seconds.
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.t0
    }

    /// Duration, seconds.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// End time, seconds.
    #[must_use]
    pub fn t1(&self) -> f64 {
        self.t0 + self.duration
    }

    /// The time law.
    #[must_use]
    pub fn profile(&self) -> Profile {
        self.profile
    }

    /// Whether both ends are within the joint limits (always `true` for [`JointMotion::new`]);
    /// then, each joint being monotone, every instant is.
    #[must_use]
    pub fn within_limits(&self) -> bool {
        !self.limits_checked || self.within_limits
    }

    /// Normalised time `τ = (t − t0)/T`, clamped into `[0, 1]`.
    #[must_use]
    #[inline]
    pub fn tau(&self, t: f64) -> f64 {
        ((t - self.t0) / self.duration).clamp(0.0, 1.0)
    }

    /// `q(t)`, written into `out` (one value per joint).
    ///
    /// # Errors
    /// [`MotionError`] when `t` is not finite or `out` has the wrong length.
    pub fn position_into(&self, t: f64, out: &mut [f64]) -> Result<(), MotionError> {
        check_number("t", t, false)?;
        if out.len() != self.q0.len() {
            return Err(MotionError::Length { field: "out".into(), expected: self.q0.len(), found: out.len() });
        }
        let lambda = self.profile.position(self.tau(t));
        for ((o, a), d) in out.iter_mut().zip(&self.q0).zip(&self.delta) {
            *o = a + lambda * d;
        }
        Ok(())
    }

    /// `q(t)`; `t` outside `[t0, t1]` gives the end values (NaN gives NaN).
    #[must_use]
    pub fn position(&self, t: f64) -> Vec<f64> {
        let lambda = self.profile.position(self.tau_or_nan(t));
        self.q0.iter().zip(&self.delta).map(|(a, d)| a + lambda * d).collect()
    }

    /// `q̇(t) = λ'(τ)·Δq/T`.
    #[must_use]
    pub fn velocity(&self, t: f64) -> Vec<f64> {
        let v = self.profile.eval(self.tau_or_nan(t)).velocity / self.duration;
        self.delta.iter().map(|d| v * d).collect()
    }

    /// `q̈(t) = λ''(τ)·Δq/T²`.
    #[must_use]
    pub fn acceleration(&self, t: f64) -> Vec<f64> {
        let a = self.profile.eval(self.tau_or_nan(t)).acceleration / (self.duration * self.duration);
        self.delta.iter().map(|d| a * d).collect()
    }

    fn tau_or_nan(&self, t: f64) -> f64 {
        if t.is_nan() { f64::NAN } else { self.tau(t) }
    }

    /// Samples the motion every `dt` seconds, both ends included ([`sample_times`]).
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for a bad `dt`.
    pub fn sample(&self, dt: f64) -> Result<JointTrajectory, MotionError> {
        let times = sample_times(self.t0, self.duration, dt)?;
        let within_limits = self.within_limits();
        Ok(JointTrajectory {
            samples: times.into_iter().map(|t| JointSample { t, q: self.position(t), within_limits }).collect(),
        })
    }
}

fn check_time(t0: f64, duration: f64) -> Result<(), MotionError> {
    check_number("t0", t0, false)?;
    check_number("duration", duration, true)
}

fn solve_end(
    robot: &Robot,
    pose: &Isometry3<f64>,
    reference: &[f64],
    choice: &EndChoice,
    which: &str,
) -> Result<Vec<f64>, MotionError> {
    let options = IkOptions { seed: Some(reference.to_vec()), ..choice.ik.clone() };
    let mut all = ik::solve(robot, &IkTarget::Pose(*pose), &options)?;
    all.express_near(robot, reference);
    match all.closest_to(reference, &choice.weights) {
        Some(s) => Ok(s.q.clone()),
        None => Err(MotionError::NoIkSolution {
            which: which.into(),
            failure: all.failure.clone().unwrap_or(IkFailure::OrientationUnreachable),
        }),
    }
}

/// A motion through several joint-space waypoints: one [`JointMotion`] per segment, each
/// with its own duration, resting at every waypoint (each segment starts and stops at rest
/// with a rest-to-rest profile).
///
/// # Example
/// ```
/// use reach::motion::{JointPath, Profile};
/// let planar3 = reach::model::presets::get("planar3").unwrap();
/// let waypoints = [vec![0.0, 0.0, 0.0], vec![0.5, 0.2, 0.0], vec![0.5, -0.2, 0.3]];
/// let path = JointPath::through(&planar3, &waypoints, &[1.0, 2.0], 0.0, Profile::Quintic).unwrap();
/// assert_eq!(path.duration(), 3.0);
/// assert!((path.position(1.0)[1] - 0.2).abs() < 1e-12);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct JointPath {
    segments: Vec<JointMotion>,
}

impl JointPath {
    /// Segments between consecutive `waypoints`, `durations[k]` for segment `k`, starting at `t0`.
    ///
    /// # Errors
    /// [`MotionError`] when fewer than two waypoints are given, `durations` does not have one
    /// value per segment, or a value is invalid (as [`JointMotion::for_robot`]).
    pub fn through(
        robot: &Robot,
        waypoints: &[Vec<f64>],
        durations: &[f64],
        t0: f64,
        profile: Profile,
    ) -> Result<Self, MotionError> {
        if waypoints.len() < 2 {
            return Err(MotionError::InvalidInput {
                field: "waypoints".into(),
                reason: format!("needs at least 2, got {}", waypoints.len()),
            });
        }
        if durations.len() != waypoints.len() - 1 {
            return Err(MotionError::Length {
                field: "durations".into(),
                expected: waypoints.len() - 1,
                found: durations.len(),
            });
        }
        let mut segments = Vec::with_capacity(durations.len());
        let mut t = t0;
        let mut from = waypoints[0].clone();
        for (k, (to, &d)) in waypoints[1..].iter().zip(durations).enumerate() {
            check_number(&format!("durations[{}]", k + 1), d, true)?;
            let segment = JointMotion::for_robot(robot, &from, to, t, d, profile)?;
            from = segment.end(); // whole turns taken by a continuous joint carry on
            t = segment.t1();
            segments.push(segment);
        }
        Ok(JointPath { segments })
    }

    /// The segments in order.
    #[must_use]
    pub fn segments(&self) -> &[JointMotion] {
        &self.segments
    }

    /// Start time.
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.segments[0].t0()
    }

    /// Total duration.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.segments.iter().map(JointMotion::duration).sum()
    }

    /// The segment active at `t` (the first one before the start, the last after the end).
    #[must_use]
    pub fn segment_at(&self, t: f64) -> &JointMotion {
        self.segments.iter().find(|s| t <= s.t1()).unwrap_or(&self.segments[self.segments.len() - 1])
    }

    /// `q(t)`.
    #[must_use]
    pub fn position(&self, t: f64) -> Vec<f64> {
        self.segment_at(t).position(t)
    }

    /// `q̇(t)`.
    #[must_use]
    pub fn velocity(&self, t: f64) -> Vec<f64> {
        self.segment_at(t).velocity(t)
    }

    /// Whether every waypoint is within the joint limits.
    #[must_use]
    pub fn within_limits(&self) -> bool {
        self.segments.iter().all(JointMotion::within_limits)
    }

    /// Samples the whole path every `dt` seconds, both ends included.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for a bad `dt`.
    pub fn sample(&self, dt: f64) -> Result<JointTrajectory, MotionError> {
        let t0 = self.t0();
        let times = sample_times(t0, self.duration(), dt)?;
        let within_limits = self.within_limits();
        Ok(JointTrajectory {
            samples: times.into_iter().map(|t| JointSample { t, q: self.position(t), within_limits }).collect(),
        })
    }
}

/// A smooth motion through several joint-space waypoints without stopping at the interior
/// ones: per joint a monotone piecewise-cubic Hermite interpolant (PCHIP, Fritsch–Carlson with
/// the weighted harmonic mean of the neighbouring slopes), at rest at the first and last
/// waypoint.
///
/// # Behavior
/// * positions pass through every waypoint at the summed durations; velocities are continuous
///   (C¹), accelerations jump at the waypoints;
/// * where a joint reverses at a waypoint (or stays) its velocity there is 0, and each cubic
///   is monotone between its two waypoints — so a joint never overshoots its waypoints, and a
///   path whose waypoints are within the limits is within them throughout;
/// * the joint differences follow the wrap policy of the module docs, waypoint to waypoint.
///
/// # Example
/// ```
/// use reach::motion::joint_space::SmoothJointPath;
/// let planar3 = reach::model::presets::get("planar3").unwrap();
/// let w = [vec![0.0, 0.0, 0.0], vec![0.5, 0.2, 0.0], vec![1.0, -0.2, 0.3]];
/// let path = SmoothJointPath::through(&planar3, &w, &[1.0, 1.0], 0.0).unwrap();
/// assert!((path.position(1.0)[0] - 0.5).abs() < 1e-12);
/// assert!((path.velocity(1.0)[0] - 0.5).abs() < 1e-12); // keeps moving through the waypoint
/// assert!(path.velocity(1.0)[1].abs() < 1e-12); // joint 2 reverses there: it stops
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SmoothJointPath {
    /// Knot times.
    times: Vec<f64>,
    /// Waypoints with the wrap policy applied (continuous joints may exceed (−π, π]).
    points: Vec<Vec<f64>>,
    /// Velocity of every joint at every knot.
    slopes: Vec<Vec<f64>>,
    /// Whether every waypoint is within the joint limits.
    within_limits: bool,
}

impl SmoothJointPath {
    /// The path through `waypoints`, segment `k` lasting `durations[k]`, starting at `t0`.
    ///
    /// # Errors
    /// As [`JointPath::through`].
    pub fn through(robot: &Robot, waypoints: &[Vec<f64>], durations: &[f64], t0: f64) -> Result<Self, MotionError> {
        // Validates every number and applies the wrap policy.
        let segments = JointPath::through(robot, waypoints, durations, t0, Profile::Linear)?;
        let mut times = vec![t0];
        let mut points = vec![segments.segments[0].start().to_vec()];
        for s in &segments.segments {
            times.push(s.t1());
            points.push(s.end());
        }
        let n = robot.dof();
        let m = points.len();
        let secant = |k: usize, j: usize| (points[k + 1][j] - points[k][j]) / (times[k + 1] - times[k]);
        let mut slopes = vec![vec![0.0; n]; m];
        for k in 1..m - 1 {
            let (h0, h1) = (times[k] - times[k - 1], times[k + 1] - times[k]);
            for (j, slope) in slopes[k].iter_mut().enumerate() {
                let (d0, d1) = (secant(k - 1, j), secant(k, j));
                if d0 * d1 > 0.0 {
                    let (w1, w2) = (2.0 * h1 + h0, h1 + 2.0 * h0);
                    *slope = (w1 + w2) / (w1 / d0 + w2 / d1);
                }
            }
        }
        Ok(SmoothJointPath { times, points, slopes, within_limits: segments.within_limits() })
    }

    /// Start time.
    #[must_use]
    pub fn t0(&self) -> f64 {
        self.times[0]
    }

    /// Whether every waypoint (hence, the interpolant being monotone between them, every
    /// instant) is within the joint limits.
    #[must_use]
    pub fn within_limits(&self) -> bool {
        self.within_limits
    }

    /// Total duration.
    #[must_use]
    pub fn duration(&self) -> f64 {
        self.times[self.times.len() - 1] - self.times[0]
    }

    /// Segment index and `(s, h)`: normalised time in the segment and its length.
    fn locate(&self, t: f64) -> (usize, f64, f64) {
        let last = self.times.len() - 2;
        let k = self.times[1..].iter().position(|&end| t <= end).unwrap_or(last).min(last);
        let h = self.times[k + 1] - self.times[k];
        (k, ((t - self.times[k]) / h).clamp(0.0, 1.0), h)
    }

    /// `q(t)` (the end values outside the interval).
    #[must_use]
    pub fn position(&self, t: f64) -> Vec<f64> {
        let (k, s, h) = self.locate(t);
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (2.0 * s3 - 3.0 * s2 + 1.0, s3 - 2.0 * s2 + s, -2.0 * s3 + 3.0 * s2, s3 - s2);
        (0..self.points[0].len())
            .map(|j| {
                h00 * self.points[k][j]
                    + h10 * h * self.slopes[k][j]
                    + h01 * self.points[k + 1][j]
                    + h11 * h * self.slopes[k + 1][j]
            })
            .collect()
    }

    /// `q̇(t)` (0 outside the interval).
    #[must_use]
    pub fn velocity(&self, t: f64) -> Vec<f64> {
        if t < self.times[0] || t > self.times[self.times.len() - 1] {
            return vec![0.0; self.points[0].len()];
        }
        let (k, s, h) = self.locate(t);
        let s2 = s * s;
        let (d00, d10, d01, d11) =
            (6.0 * s2 - 6.0 * s, 3.0 * s2 - 4.0 * s + 1.0, -6.0 * s2 + 6.0 * s, 3.0 * s2 - 2.0 * s);
        (0..self.points[0].len())
            .map(|j| {
                (d00 * self.points[k][j] + d01 * self.points[k + 1][j]) / h
                    + d10 * self.slopes[k][j]
                    + d11 * self.slopes[k + 1][j]
            })
            .collect()
    }

    /// Samples the path every `dt` seconds, both ends included.
    ///
    /// # Errors
    /// [`MotionError::InvalidInput`] for a bad `dt`.
    pub fn sample(&self, dt: f64) -> Result<JointTrajectory, MotionError> {
        let times = sample_times(self.t0(), self.duration(), dt)?;
        let within_limits = self.within_limits;
        Ok(JointTrajectory {
            samples: times.into_iter().map(|t| JointSample { t, q: self.position(t), within_limits }).collect(),
        })
    }
}
