//! Criteria for whole motions (a sampled joint trajectory), and [`choose_motion`].
//!
//! A candidate motion is a [`SampledMotion`]: sample times (s) and joint vectors (rad / m),
//! e.g. a [`JointTrajectory`] or one configuration's track over a path interval
//! ([`ConfigurationTrack`]). Each [`MotionCriterion`] turns one motion into one number with a
//! unit and a preferred direction; [`motion_matrix`] builds the [`DecisionMatrix`] of several
//! candidates and [`choose_motion`] ranks them with any [`Method`].
//!
//! [`TrackChooser`] plugs these criteria into path tracking's per-interval choice of
//! configuration ([`tracking::ConfigurationCriterion`]; seed 003's user criterion, notes 003 §7 item 5).
//!
//! **Physical energy** (`energy`) needs link masses in the robot model: it is the mechanical
//! work `∫ Σ|τᵢ q̇ᵢ| dt` of [`effort::dynamics::trajectory_energy`] (Newton–Euler torques with
//! gravity, rates from the samples).

use serde::Serialize;

use super::DecideError;
use super::ik_criteria::{DEFAULT_JOINT_RESOLUTION, IkCriterion};
use super::mcdm::{Criterion, DecisionMatrix, Direction, Method, Ranking, normalise_weights, rank};
use crate::effort::{self, Differences};
use crate::model::{JointKind, Robot};
use crate::motion::sample::JointTrajectory;
use crate::motion::tracking::{self, ConfigurationTrack};
use crate::motion::{JointRates, Profile, Timing};
use crate::world::{CollisionChecker, Scene};

/// A sampled motion: strictly increasing times (s) and one joint vector (rad / m) per time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledMotion<'a> {
    /// Sample times, seconds.
    pub t: &'a [f64],
    /// Joint vectors, one per time.
    pub q: &'a [Vec<f64>],
}

impl<'a> SampledMotion<'a> {
    /// A motion from times and joint vectors.
    #[must_use]
    pub fn new(t: &'a [f64], q: &'a [Vec<f64>]) -> Self {
        SampledMotion { t, q }
    }

    /// The samples of one configuration's track over a path interval.
    #[must_use]
    pub fn of_track(track: &'a ConfigurationTrack) -> Self {
        SampledMotion { t: &track.t, q: &track.q }
    }
}

/// Times and joint vectors of a [`JointTrajectory`], owned (borrow them with
/// [`SampledMotion::new`]).
#[must_use]
pub fn trajectory_samples(trajectory: &JointTrajectory) -> (Vec<f64>, Vec<Vec<f64>>) {
    (trajectory.times(), trajectory.samples.iter().map(|s| s.q.clone()).collect())
}

/// A criterion evaluated on a whole motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MotionCriterion {
    /// Seed 001's J1 between the first and last sample, `Σ wᵢ |Δqᵢ|` (revolute differences
    /// wrapped, [`Differences::for_robot`]). Unit `rad`; less is better.
    J1 {
        /// Joint weights, one per joint, `>= 0`.
        weights: Vec<f64>,
    },
    /// Seed 001's J2, the weighted total variation over the samples ([`effort::j2`]). Unit
    /// `rad`; less is better.
    J2 {
        /// Joint weights, one per joint, `>= 0`.
        weights: Vec<f64>,
    },
    /// Shortest time to follow the sampled joint path within the speed limits: for every step
    /// the synchronised duration with the linear profile ([`Timing::synchronised`]; the
    /// slowest joint at its limit), summed. Accelerations are not limited; for a two-sample
    /// (point-to-point) motion use [`point_to_point_duration`] to add a profile. Unit `s`;
    /// less is better.
    Duration {
        /// Speed limits per joint.
        rates: JointRates,
    },
    /// Largest joint speed over the motion, `maxₖ maxᵢ |Δqᵢ/Δt|` over the steps (revolute
    /// differences shortest, [`tracking::step_rates`]). Unit `rad/s` (m/s for prismatic
    /// joints); less is better.
    PeakVelocity,
    /// Largest joint acceleration, from differences of consecutive step rates over the
    /// distance between step mid-times. Unit `rad/s^2`; less is better. Zero for fewer than
    /// three samples.
    PeakAcceleration,
    /// Smallest normalised distance to a joint limit over the samples
    /// ([`IkCriterion::LimitMargin`]; revolute angles wrapped to (−π, π] first when the range
    /// is narrower than a turn). Dimensionless in \[0, 0.5\]; more is better.
    LimitMargin,
    /// Smallest Yoshikawa manipulability over the samples. Unit `1`; more is better.
    MinManipulability,
    /// Smallest singular value of the Jacobian over the samples (distance from a singularity).
    /// Unit `1`; more is better.
    MinSigma,
    /// Seed 003's stiffness, the worst over the samples: the smallest
    /// [`IkCriterion::Stiffness`] (`σ_min/σ_max` of the position Jacobian). Unit `1`; more is
    /// better.
    MinStiffness,
    /// Seed 003's accuracy, the worst over the samples: the largest [`IkCriterion::Accuracy`]
    /// (`σ_max(J_p)·δq`, `δq` = [`DEFAULT_JOINT_RESOLUTION`]). Unit `m`; less is better.
    MaxErrorAmplification,
    /// Smallest link–obstacle clearance over the samples
    /// ([`crate::world::Report::min_obstacle_clearance_m`]; negative: penetration). Unit `m`;
    /// more is better.
    Clearance {
        /// The obstacles (at least one).
        scene: Scene,
    },
    /// Length of the tool point's path through the sampled configurations (forward
    /// kinematics, straight segments between samples). Unit `m`; less is better.
    ToolPathLength,
    /// Mechanical energy `∫ Σ|τᵢ q̇ᵢ| dt` ([`effort::dynamics::trajectory_energy`]: recursive
    /// Newton–Euler with gravity, joint rates by central differences of the samples, braking
    /// counted as spent). Needs link masses in the robot model. Unit `J`; less is better.
    Energy,
}

/// Names accepted by [`MotionCriterion::parse`], in a stable order.
pub const MOTION_CRITERIA: [&str; 13] = [
    "j1",
    "j2",
    "duration",
    "peak_velocity",
    "peak_acceleration",
    "limits",
    "manipulability",
    "sigma_min",
    "stiffness",
    "accuracy",
    "clearance",
    "path_length",
    "energy",
];

impl MotionCriterion {
    /// The criterion named `name` (one of [`MOTION_CRITERIA`]; `-` and `_` are the same) for
    /// `robot`: J1/J2 take `weights` (default: seed 001's for six joints, else 1), duration the
    /// robot's `max_velocity` limits, clearance `scene`.
    ///
    /// # Errors
    /// [`DecideError::UnknownCriterion`] for an unknown name; [`DecideError::Criterion`] when
    /// the robot has no speed limits (duration), no scene with obstacles is given
    /// (clearance), the scene's allowed-collision list names a link the robot does not have
    /// (clearance, naming the link) or the robot has no link masses (energy); [`DecideError::BadVector`] for weights that do not fit the robot.
    pub fn parse(
        name: &str,
        robot: &Robot,
        weights: Option<&[f64]>,
        scene: Option<&Scene>,
    ) -> Result<MotionCriterion, DecideError> {
        let key = name.trim().to_ascii_lowercase().replace('-', "_");
        let joint_weights = || -> Result<Vec<f64>, DecideError> {
            effort::joint_weights(robot, weights).map_err(|e| DecideError::BadVector {
                what: "joint weights",
                reason: format!("expected {} finite values >= 0: {e}", robot.dof()),
            })
        };
        Ok(match key.as_str() {
            "j1" => MotionCriterion::J1 { weights: joint_weights()? },
            "j2" => MotionCriterion::J2 { weights: joint_weights()? },
            "duration" => MotionCriterion::Duration {
                rates: JointRates::from_robot(robot, None)
                    .map_err(|e| DecideError::Criterion { criterion: "duration".into(), reason: e.to_string() })?,
            },
            "peak_velocity" => MotionCriterion::PeakVelocity,
            "peak_acceleration" => MotionCriterion::PeakAcceleration,
            "limits" => MotionCriterion::LimitMargin,
            "manipulability" => MotionCriterion::MinManipulability,
            "sigma_min" => MotionCriterion::MinSigma,
            "stiffness" => MotionCriterion::MinStiffness,
            "accuracy" => MotionCriterion::MaxErrorAmplification,
            "clearance" => match scene {
                Some(s) if !s.obstacles.is_empty() => {
                    CollisionChecker::try_new(robot, s)
                        .map_err(|e| DecideError::Criterion { criterion: "clearance".into(), reason: e.to_string() })?;
                    MotionCriterion::Clearance { scene: s.clone() }
                }
                _ => {
                    return Err(DecideError::Criterion {
                        criterion: "clearance".into(),
                        reason: "needs a scene with at least one obstacle".into(),
                    });
                }
            },
            "path_length" => MotionCriterion::ToolPathLength,
            "energy" if robot.has_dynamics() => MotionCriterion::Energy,
            "energy" => {
                return Err(DecideError::Criterion {
                    criterion: "energy".into(),
                    reason: format!("robot `{}` has no link masses (docs/robot-format.md, inertial)", robot.name()),
                });
            }
            _ => {
                return Err(DecideError::UnknownCriterion {
                    name: name.to_string(),
                    known: MOTION_CRITERIA.join(", "),
                });
            }
        })
    }

    /// The criterion's name, unit and direction.
    #[must_use]
    pub fn describe(&self) -> Criterion {
        use Direction::{LessIsBetter as Less, MoreIsBetter as More};
        let (name, unit, direction) = match self {
            MotionCriterion::J1 { .. } => ("j1", "rad", Less),
            MotionCriterion::J2 { .. } => ("j2", "rad", Less),
            MotionCriterion::Duration { .. } => ("duration", "s", Less),
            MotionCriterion::PeakVelocity => ("peak_velocity", "rad/s", Less),
            MotionCriterion::PeakAcceleration => ("peak_acceleration", "rad/s^2", Less),
            MotionCriterion::LimitMargin => ("limits", "1", More),
            MotionCriterion::MinManipulability => ("manipulability", "1", More),
            MotionCriterion::MinSigma => ("sigma_min", "1", More),
            MotionCriterion::MinStiffness => ("stiffness", "1", More),
            MotionCriterion::MaxErrorAmplification => ("accuracy", "m", Less),
            MotionCriterion::Clearance { .. } => ("clearance", "m", More),
            MotionCriterion::ToolPathLength => ("path_length", "m", Less),
            MotionCriterion::Energy => ("energy", "J", Less),
        };
        Criterion::new(name, unit, direction)
    }

    /// The criterion's value for `motion` of `robot`.
    ///
    /// # Errors
    /// [`DecideError::BadVector`] for an empty motion, a joint vector of the wrong length or
    /// with non-finite values, or times that do not match or do not increase;
    /// [`DecideError::Criterion`] when a computation fails (wrong weights, a scene without
    /// obstacles).
    pub fn evaluate(&self, robot: &Robot, motion: &SampledMotion<'_>) -> Result<f64, DecideError> {
        check_motion(robot, motion)?;
        let name = || self.describe().name;
        let failed = |e: &dyn std::fmt::Display| DecideError::Criterion { criterion: name(), reason: e.to_string() };
        let q = motion.q;
        let differences = Differences::for_robot(robot);
        let rates = || tracking::step_rates(robot, motion.t, q).map_err(|e| failed(&e));
        let max_abs = |rows: &[Vec<f64>]| rows.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        let min_over = |c: &IkCriterion| -> Result<f64, DecideError> {
            q.iter().try_fold(f64::INFINITY, |m, qk| Ok(m.min(c.evaluate(robot, &wrapped_into_range(robot, qk))?)))
        };
        match self {
            MotionCriterion::J1 { weights } => {
                effort::j1(&q[0], &q[q.len() - 1], weights, &differences).map_err(|e| failed(&e))
            }
            MotionCriterion::J2 { weights } => effort::j2(q, weights, &differences).map_err(|e| failed(&e)),
            MotionCriterion::Duration { rates } => {
                let mut total = 0.0;
                for pair in q.windows(2) {
                    let delta: Vec<f64> =
                        (0..robot.dof()).map(|i| differences.diff(i, pair[0][i], pair[1][i])).collect();
                    total += Timing::synchronised(&delta, rates, Profile::Linear).map_err(|e| failed(&e))?.duration;
                }
                Ok(total)
            }
            MotionCriterion::PeakVelocity => Ok(max_abs(&rates()?)),
            MotionCriterion::PeakAcceleration => {
                // Interior samples: the difference of the neighbouring step rates over half the
                // sum of the two step durations; the end rows copy their neighbours, so they do
                // not change the peak.
                let (_, qdd) = effort::dynamics::joint_rates(robot, motion.t, q).map_err(|e| failed(&e))?;
                Ok(max_abs(&qdd))
            }
            MotionCriterion::LimitMargin => min_over(&IkCriterion::LimitMargin),
            MotionCriterion::MinManipulability => min_over(&IkCriterion::Manipulability),
            MotionCriterion::MinSigma => min_over(&IkCriterion::SigmaMin),
            MotionCriterion::MinStiffness => min_over(&IkCriterion::Stiffness),
            MotionCriterion::MaxErrorAmplification => {
                let accuracy = IkCriterion::Accuracy { resolution: DEFAULT_JOINT_RESOLUTION };
                q.iter().try_fold(0.0_f64, |m, qk| Ok(m.max(accuracy.evaluate(robot, &wrapped_into_range(robot, qk))?)))
            }
            MotionCriterion::Clearance { scene } => {
                let mut checker = CollisionChecker::new(robot, scene);
                let mut least = f64::INFINITY;
                for qk in q {
                    let report = checker.report(qk).map_err(|e| failed(&e))?;
                    let c = report.min_obstacle_clearance_m.ok_or_else(|| failed(&"the scene has no obstacles"))?;
                    least = least.min(c);
                }
                Ok(least)
            }
            MotionCriterion::ToolPathLength => {
                let mut length = 0.0;
                let mut previous = robot.fk(&q[0])?.translation.vector;
                for qk in &q[1..] {
                    let p = robot.fk(qk)?.translation.vector;
                    length += (p - previous).norm();
                    previous = p;
                }
                Ok(length)
            }
            MotionCriterion::Energy => effort::dynamics::trajectory_energy(robot, motion.t, q).map_err(|e| failed(&e)),
        }
    }
}

/// Duration (s) of a point-to-point move by `delta` (rad / m) synchronised within `rates` with
/// the time law `profile` ([`Timing::synchronised`]); the cost the `Duration` criterion uses
/// when the profile matters (task sequencing legs).
///
/// # Errors
/// [`DecideError::Criterion`] when `delta` does not fit `rates` or holds non-finite values.
pub fn point_to_point_duration(delta: &[f64], rates: &JointRates, profile: Profile) -> Result<f64, DecideError> {
    Timing::synchronised(delta, rates, profile)
        .map(|t| t.duration)
        .map_err(|e| DecideError::Criterion { criterion: "duration".into(), reason: e.to_string() })
}

/// Revolute angles with a range narrower than a turn wrapped to (−π, π] (tracked motions are
/// unwrapped, the limits are not).
fn wrapped_into_range(robot: &Robot, q: &[f64]) -> Vec<f64> {
    robot
        .joints()
        .iter()
        .zip(q)
        .map(|(j, &v)| {
            let narrow = j.limits.is_bounded() && j.limits.span() < std::f64::consts::TAU;
            if j.kind == JointKind::Revolute && narrow { crate::angle::wrap(v) } else { v }
        })
        .collect()
}

fn check_motion(robot: &Robot, motion: &SampledMotion<'_>) -> Result<(), DecideError> {
    let bad = |reason: String| DecideError::BadVector { what: "motion", reason };
    if motion.q.is_empty() {
        return Err(bad("no samples".into()));
    }
    if motion.t.len() != motion.q.len() {
        return Err(bad(format!("{} times for {} joint vectors", motion.t.len(), motion.q.len())));
    }
    for (k, qk) in motion.q.iter().enumerate() {
        if qk.len() != robot.dof() || qk.iter().any(|v| !v.is_finite()) {
            return Err(bad(format!("sample {k}: expected {} finite joint values, got {qk:?}", robot.dof())));
        }
    }
    if let Some(k) = (1..motion.t.len()).find(|&k| motion.t[k].is_nan() || motion.t[k] <= motion.t[k - 1]) {
        return Err(bad(format!("time does not increase at sample {k}")));
    }
    Ok(())
}

/// The decision matrix of `motions` (rows, in order) × `criteria` (columns).
///
/// # Errors
/// [`DecideError::NoCandidates`] for no motions, [`DecideError::NoCriteria`], and the errors
/// of [`MotionCriterion::evaluate`].
pub fn motion_matrix(
    robot: &Robot,
    motions: &[SampledMotion<'_>],
    criteria: &[MotionCriterion],
) -> Result<DecisionMatrix, DecideError> {
    if motions.is_empty() {
        return Err(DecideError::NoCandidates);
    }
    let rows = motions
        .iter()
        .map(|m| criteria.iter().map(|c| c.evaluate(robot, m)).collect::<Result<Vec<f64>, _>>())
        .collect::<Result<Vec<_>, _>>()?;
    DecisionMatrix::new(criteria.iter().map(MotionCriterion::describe).collect(), rows)
}

/// Ranks `motions` by `criteria`, `weights` (one per criterion) and `method`; indices refer to
/// `motions`.
///
/// # Errors
/// See [`motion_matrix`] and [`rank`].
pub fn choose_motion(
    robot: &Robot,
    motions: &[SampledMotion<'_>],
    criteria: &[MotionCriterion],
    weights: &[f64],
    method: Method,
) -> Result<Ranking, DecideError> {
    rank(&motion_matrix(robot, motions, criteria)?, weights, method)
}

/// Per-interval configuration choice in path tracking by motion criteria
/// ([`tracking::ConfigurationCriterion`]).
///
/// Among the feasible configurations of an interval, their tracks are ranked like
/// [`choose_motion`] and the best is realised. A track on which a criterion cannot be evaluated
/// (no samples, times that do not increase, a joint vector that does not fit the robot), or
/// which breaks one of the [`Requirement`]s, does not satisfy the choice; when no track
/// satisfies it, tracking keeps the default configuration (the paper's K14).
///
/// # Example
/// ```
/// use reach::decide::{Method, MotionCriterion, TrackChooser};
/// let robot = reach::model::presets::get("log-loader").unwrap();
/// let limits = MotionCriterion::parse("limits", &robot, None, None).unwrap();
/// let j2 = MotionCriterion::parse("j2", &robot, None, None).unwrap();
/// let chooser = TrackChooser::new(&robot, vec![limits, j2], vec![0.7, 0.3], Method::Topsis).unwrap();
/// // Pass `Some(&chooser)` as the criterion of `reach::motion::tracking::track`.
/// assert_eq!(chooser.criteria().len(), 2);
/// ```
#[derive(Debug, Clone)]
pub struct TrackChooser<'r> {
    robot: &'r Robot,
    criteria: Vec<MotionCriterion>,
    weights: Vec<f64>,
    method: Method,
    requirements: Vec<Requirement>,
}

/// A hard bound on one criterion: a track whose value is on the wrong side does not satisfy
/// the choice (seed 003's "criterion cannot be met").
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Requirement {
    /// Index of the criterion in the chooser's list.
    pub criterion: usize,
    /// The bound, in the criterion's unit: a maximum for less-is-better criteria, a minimum
    /// for more-is-better ones.
    pub bound: f64,
}

impl<'r> TrackChooser<'r> {
    /// A chooser ranking with `method` over `criteria` weighted by `weights`.
    ///
    /// # Errors
    /// [`DecideError::NoCriteria`], and the weight errors of
    /// [`normalise_weights`] (checked now, not at the first interval).
    pub fn new(
        robot: &'r Robot,
        criteria: Vec<MotionCriterion>,
        weights: Vec<f64>,
        method: Method,
    ) -> Result<Self, DecideError> {
        let names: Vec<String> = criteria.iter().map(|c| c.describe().name).collect();
        normalise_weights(&names, &weights)?;
        Ok(TrackChooser { robot, criteria, weights, method, requirements: Vec::new() })
    }

    /// Adds hard bounds (see [`Requirement`]).
    ///
    /// # Errors
    /// [`DecideError::Criterion`] for an index out of range or a non-finite bound.
    pub fn with_requirements(mut self, requirements: Vec<Requirement>) -> Result<Self, DecideError> {
        for r in &requirements {
            if r.criterion >= self.criteria.len() || !r.bound.is_finite() {
                return Err(DecideError::Criterion {
                    criterion: format!("requirement {}", r.criterion),
                    reason: format!("needs a criterion index < {} and a finite bound", self.criteria.len()),
                });
            }
        }
        self.requirements = requirements;
        Ok(self)
    }

    /// The criteria.
    #[must_use]
    pub fn criteria(&self) -> &[MotionCriterion] {
        &self.criteria
    }

    /// The criterion values of one track, or `None` when it does not satisfy the choice.
    fn values(&self, track: &ConfigurationTrack) -> Option<Vec<f64>> {
        let motion = SampledMotion::of_track(track);
        let v: Vec<f64> = self.criteria.iter().map(|c| c.evaluate(self.robot, &motion).ok()).collect::<Option<_>>()?;
        let ok = self.requirements.iter().all(|r| match self.criteria[r.criterion].describe().direction {
            Direction::LessIsBetter => v[r.criterion] <= r.bound,
            Direction::MoreIsBetter => v[r.criterion] >= r.bound,
        });
        ok.then_some(v)
    }
}

impl tracking::ConfigurationCriterion for TrackChooser<'_> {
    /// A single track's score (lower is better): the value of the most heavily weighted
    /// criterion (the first on a tie), signed so that less is better; `None` when the track
    /// does not satisfy the choice. The choice between tracks ranks all criteria together
    /// ([`tracking::ConfigurationCriterion::choose`] below).
    fn score(&self, track: &ConfigurationTrack) -> Option<f64> {
        let v = self.values(track)?;
        let main = (0..self.weights.len()).fold(0, |b, j| if self.weights[j] > self.weights[b] { j } else { b });
        Some(-self.criteria[main].describe().direction.sign() * v[main])
    }

    fn choose(&self, feasible: &[&ConfigurationTrack]) -> Option<usize> {
        let satisfied: Vec<(usize, Vec<f64>)> =
            feasible.iter().enumerate().filter_map(|(k, t)| self.values(t).map(|v| (k, v))).collect();
        let rows = satisfied.iter().map(|(_, v)| v.clone()).collect();
        let matrix = DecisionMatrix::new(self.criteria.iter().map(MotionCriterion::describe).collect(), rows).ok()?;
        let ranking = rank(&matrix, &self.weights, self.method).ok()?;
        Some(satisfied[ranking.best()].0)
    }
}
