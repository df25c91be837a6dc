//! The `check` workflow: collisions and clearances of one configuration in a scene, and the
//! swept (continuous) check of a motion from it: the straight joint motion to a second
//! configuration, or a sampled motion (the piecewise-linear joint path through its samples,
//! the path a drive schedule follows).

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use super::parse_scene;
use crate::Robot;
use crate::error::Error;
use crate::error::Result;
use crate::jobs::input::{Joints, MotionSample, positive, samples_si};
use crate::motion::PiecewiseCubic;
use crate::motion::sample::JointSample;
use crate::world::sweep::{JointCurve, Sweep, SweepOptions};
use crate::world::{CollisionChecker, Contact, LinkClearance, PathSweep, Scene, SelfClearance, SweptPair, Verdict};

/// One configuration checked against a scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CheckRequest {
    /// The text of the scene file (TOML: obstacles, tool zone, touching policy).
    pub scene: String,
    /// The joint values.
    pub q: Joints,
    /// With a target: the straight joint-space motion from `q` to `to` is checked
    /// continuously ([`CollisionChecker::swept`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<Joints>,
    /// With `to`: the motion's duration, seconds, the joints moving linearly in time from `q`
    /// (at time 0) to `to`. Needed when the scene has a moving obstacle (the check is then in
    /// time, [`CollisionChecker::swept_timed`]); with fixed obstacles it changes nothing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration_s: Option<f64>,
    /// Instead of `to`: a sampled motion (`reach move --json`'s `samples`, every sample within
    /// the joints' limits). The piecewise-linear joint path from `q` through the samples is
    /// checked continuously in time ([`CollisionChecker::swept_path_timed`]; `q` is at the first
    /// sample's time, and moving obstacles are at their scene position at that time); `q` is
    /// usually the first sample.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Vec<MotionSample>>,
}

/// A swept (continuous) check in a report ([`CollisionChecker::swept`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SweptReport {
    /// Whether the whole motion is proven clear (every clearance above 1 µm).
    pub clear: bool,
    /// Certified lower bound of the clearance over the motion (up to where the check stopped
    /// when not clear), metres; `null` when nothing is checked (no obstacle, zone or pair).
    pub lower_bound_m: Option<f64>,
    /// The smallest clearance found, metres (`null` as above).
    pub min_clearance_m: Option<f64>,
    /// Where, as the fraction of the motion (where it stopped when not clear).
    pub at: f64,
    /// A timed check (a duration or sample times): the instant of `at`, seconds from the
    /// start of the motion (moving obstacles are where they are at that time).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub t_s: Option<f64>,
    /// What that clearance measures (`null` as above).
    pub pair: Option<SweptPair>,
    /// The same in words, with the names of the obstacle or zone.
    pub pair_text: Option<String>,
    /// Clearance evaluations made.
    pub evaluations: usize,
}

impl SweptReport {
    /// The report of a sweep in `scene`; `span`: the motion's time interval, seconds, when
    /// timed.
    #[must_use]
    pub fn of(sweep: &Sweep, pair: SweptPair, checker: &CollisionChecker, span: Option<[f64; 2]>) -> Self {
        let checked = sweep.evaluations > 0 && sweep.min_clearance.is_finite();
        SweptReport {
            clear: sweep.clear,
            lower_bound_m: checked.then_some(sweep.lower_bound),
            min_clearance_m: checked.then_some(sweep.min_clearance),
            at: sweep.at,
            t_s: span.map(|[a, b]| a + sweep.at * (b - a)),
            pair: checked.then_some(pair),
            pair_text: checked.then(|| swept_pair_text(&pair, checker)),
            evaluations: sweep.evaluations,
        }
    }
}

/// The swept check of a piecewise-straight joint path ([`CollisionChecker::swept_path`]):
/// the verdict over the whole path and the segment where it comes closest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct SweptPathReport {
    /// 1-based segment (between points `segment` and `segment + 1` of the path) where the
    /// path comes closest, or the first segment not proven clear; `at` is the fraction of that
    /// segment.
    pub segment: usize,
    /// The check: `clear`, `lower_bound_m` and `evaluations` over the whole path (up to the
    /// first segment not proven clear), the rest of the closest segment.
    #[serde(flatten)]
    pub swept: SweptReport,
}

impl SweptPathReport {
    /// The swept check of the path through `points` in `scene` (`None` for fewer than two
    /// points), in time when the points' `times` (seconds from the start of the motion) are
    /// given ([`CollisionChecker::swept_path_timed`]: moving obstacles are checked where they
    /// are at each instant; fixed obstacles give the same verdict as without times).
    ///
    /// # Errors
    /// As [`CollisionChecker::swept_path`] (without times a scene with a moving obstacle is
    /// refused) and [`CollisionChecker::swept_path_timed`].
    pub fn check(robot: &Robot, scene: &Scene, points: &[Vec<f64>], times: Option<&[f64]>) -> Result<Option<Self>> {
        let mut checker = CollisionChecker::new(robot, scene);
        let options = SweepOptions::default();
        let path = match times {
            Some(times) => checker.swept_path_timed(points, times, &options)?,
            None => checker.swept_path(points, &options)?,
        };
        Ok(path.map(|p| Self::of(&p, &checker)))
    }

    /// The swept check of the untimed path `path` in `scene` — its straight pieces and the
    /// quadratic arcs that blend them ([`PiecewiseCubic::control_points`],
    /// [`CollisionChecker::swept_curves`]); `segment` numbers the pieces. `None` when nothing
    /// is checked.
    ///
    /// # Errors
    /// As [`CollisionChecker::swept_curves`]; [`Error::Request`] for a path with a cubic piece.
    pub fn check_pieces(robot: &Robot, scene: &Scene, path: &PiecewiseCubic) -> Result<Option<Self>> {
        let pieces = path.control_points().map_err(crate::jobs::retime::request_error)?;
        let curves = pieces
            .iter()
            .enumerate()
            .map(|(k, p)| match p.as_slice() {
                [a, b] => Ok(JointCurve::Line(a, b)),
                [a, b, c] => Ok(JointCurve::Quadratic(a, b, c)),
                _ => Err(Error::request("path", format!("piece {} has {} control points, not 2 or 3", k + 1, p.len()))),
            })
            .collect::<Result<Vec<_>>>()?;
        let mut checker = CollisionChecker::new(robot, scene);
        let path = checker.swept_curves(&curves, &SweepOptions::default())?;
        Ok(path.map(|p| Self::of(&p, &checker)))
    }

    /// The report of a path sweep by `checker`.
    #[must_use]
    pub fn of(path: &PathSweep, checker: &CollisionChecker) -> Self {
        let mut swept = SweptReport::of(&path.closest, path.pair, checker, None);
        swept.t_s = path.t_s;
        swept.clear = path.clear;
        if swept.lower_bound_m.is_some() {
            swept.lower_bound_m = Some(path.lower_bound);
        }
        swept.evaluations = path.evaluations;
        SweptPathReport { segment: path.segment + 1, swept }
    }
}

/// The swept check of the motion `q → to`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MotionCheckReport {
    /// Target joint values: revolute joints in degrees, prismatic joints in metres.
    pub to_deg: Vec<f64>,
    /// The check.
    #[serde(flatten)]
    pub swept: SweptReport,
}

/// Collisions and clearances of one configuration (`reach check --json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct CheckReport {
    /// Robot name.
    pub robot: String,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
    /// The first failed check (or free).
    pub verdict: Verdict,
    /// The verdict in words, with the names of the obstacle or zone.
    pub verdict_text: String,
    /// Every (link, obstacle) pair.
    pub links: Vec<LinkClearance>,
    /// Every pair of non-adjacent links.
    pub self_pairs: Vec<SelfClearance>,
    /// The tool point against every zone entry.
    pub tool_zone: Vec<Contact>,
    /// Smallest link–obstacle clearance (`null` without obstacles), metres.
    pub min_obstacle_clearance_m: Option<f64>,
    /// Smallest link–link clearance of the checked pairs (`null` without one; exempt pairs left out), metres.
    pub min_self_clearance_m: Option<f64>,
    /// With a target: the swept check of the motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<MotionCheckReport>,
    /// With samples: the swept check of the sampled motion (segment 1 runs from `q` to the
    /// first sample).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<SweptPathReport>,
}

impl CheckReport {
    /// Whether the whole check holds: the configuration is free and the swept check of its
    /// motion (`motion` or `samples`), when there is one, is proven clear. The verdict a
    /// front end reports as its outcome (`reach check` exits with status 3 when it is false).
    #[must_use]
    pub fn is_clear(&self) -> bool {
        self.verdict.is_free()
            && self.motion.as_ref().is_none_or(|m| m.swept.clear)
            && self.samples.as_ref().is_none_or(|p| p.swept.clear)
    }
}

/// The verdict of `checker` in words, naming the links (number and name), obstacle or zone.
#[must_use]
pub fn verdict_text(verdict: &Verdict, checker: &CollisionChecker) -> String {
    let scene = checker.scene();
    let link = |k: &usize| checker.link_label(*k);
    match verdict {
        Verdict::Free => "free".into(),
        Verdict::OutsideZone { zone } => format!("tool outside zone `{}`", scene.tool_zone[*zone].name),
        Verdict::SelfCollision { link_a, link_b } => format!("self-collision: {} and {}", link(link_a), link(link_b)),
        Verdict::Obstacle { link: k, obstacle } => {
            format!("collision: {} with `{}`", link(k), scene.obstacles[*obstacle].name)
        }
    }
}

/// What a swept clearance of `checker` measures, in words, naming the links, obstacle or zone.
#[must_use]
pub fn swept_pair_text(pair: &SweptPair, checker: &CollisionChecker) -> String {
    let scene = checker.scene();
    let link = |k: &usize| checker.link_label(*k);
    match pair {
        SweptPair::ToolZone { zone } => {
            format!("tool point and the boundary of zone `{}`", scene.tool_zone[*zone].name)
        }
        SweptPair::Obstacle { link: k, obstacle } => format!("{} and `{}`", link(k), scene.obstacles[*obstacle].name),
        SweptPair::SelfPair { link_a, link_b } => format!("{} and {}", link(link_a), link(link_b)),
    }
}

/// The times of a sampled motion from its start (the first sample at 0 s), seconds: where
/// moving obstacles are when the motion reaches each sample.
///
/// # Errors
/// [`Error::Request`] naming `field` and the sample when a time is not finite or decreases.
pub fn motion_times(samples: &[JointSample], field: &str) -> Result<Vec<f64>> {
    let t0 = samples.first().map_or(0.0, |s| s.t);
    let mut times: Vec<f64> = Vec::with_capacity(samples.len());
    for (k, s) in samples.iter().enumerate() {
        let t = s.t - t0;
        if !(t.is_finite() && times.last().is_none_or(|last| t >= *last)) {
            return Err(Error::request(
                format!("{field}: sample {k}"),
                format!("`t_s` must be finite and not decrease, got {} s", s.t),
            ));
        }
        times.push(t);
    }
    Ok(times)
}

/// Checks the configuration: whatever the verdict, it is in the report.
///
/// # Errors
/// [`crate::Error::World`] for a malformed scene (line and column); [`crate::Error::Request`]
/// for a wrong joint count or a non-finite value (field `q`, `to`, `samples`), a sample
/// outside the joints' limits, both `to` and `samples`, sample times that decrease, a
/// `duration_s` that is not a positive number or comes without `to`, or a scene with a moving
/// obstacle and `to` without `duration_s` (the check needs the motion's timing).
pub fn check(robot: &Robot, request: &CheckRequest) -> Result<CheckReport> {
    let scene = parse_scene(&request.scene)?;
    let q = request.q.si(robot, "q")?;
    if positive("duration_s", request.duration_s)?.is_some() && request.to.is_none() {
        return Err(Error::request("duration_s", "a duration needs a motion `to`"));
    }
    let mut checker = CollisionChecker::new(robot, &scene);
    let motion = match &request.to {
        None => None,
        Some(to) => {
            let target = to.si(robot, "to")?;
            let span = match (request.duration_s, scene.moving_obstacle()) {
                (Some(d), _) => Some([0.0, d]),
                (None, Some(o)) => {
                    return Err(Error::request(
                        "duration_s",
                        format!(
                            "obstacle `{}` moves: the motion is checked against it in time, which needs the motion's duration",
                            o.name
                        ),
                    ));
                }
                (None, None) => None,
            };
            let options = SweepOptions::default();
            let (swept, pair) = match span {
                Some(span) => checker.swept_timed(&q, &target, span, &options)?,
                None => checker.swept(&q, &target, &options)?,
            };
            Some(MotionCheckReport { to_deg: to.display(robot), swept: SweptReport::of(&swept, pair, &checker, span) })
        }
    };
    let samples = match (&request.samples, &request.to) {
        (None, _) => None,
        (Some(_), Some(_)) => return Err(Error::request("samples", "give `to` or `samples`, not both")),
        (Some(samples), None) if samples.is_empty() => {
            return Err(Error::request("samples", "give at least one sample"));
        }
        (Some(samples), None) => {
            let samples = samples_si(robot, samples, "samples")?;
            // `q` at the first sample's time, the start of the motion.
            let times: Vec<f64> = std::iter::once(0.0).chain(motion_times(&samples, "samples")?).collect();
            let path: Vec<Vec<f64>> = std::iter::once(q.clone()).chain(samples.into_iter().map(|s| s.q)).collect();
            SweptPathReport::check(robot, &scene, &path, Some(&times))?
        }
    };
    let report = checker.report(&q)?;
    Ok(CheckReport {
        robot: robot.name().to_string(),
        q_deg: request.q.display(robot),
        verdict_text: verdict_text(&report.verdict, &checker),
        verdict: report.verdict,
        links: report.links,
        self_pairs: report.self_pairs,
        tool_zone: report.tool_zone,
        min_obstacle_clearance_m: report.min_obstacle_clearance_m,
        min_self_clearance_m: report.min_self_clearance_m,
        motion,
        samples,
    })
}
