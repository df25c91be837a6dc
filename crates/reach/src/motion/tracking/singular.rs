//! The scan of the samples for singular positions and reachability changes (notes 003 §3.6,
//! §4 steps 2–3), refined by golden-section search and bisection.

use nalgebra::Isometry3;
use serde::Serialize;

use super::branch::matches;
use super::{Tracker, TrackingError};
use crate::ik::parallel_axes::{Shoulder, Wrist};
use crate::ik::{IkError, IkOptions, IkSolutions, SingularityKind};
use crate::kinematics::{JacobianAxes, Manipulability};
use crate::tolerance::TRACKING_SINGULAR;

/// What kind of point splits the path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SplitKind {
    /// A singular position (|Δ| = 1, wrist, shoulder, or a Jacobian rank drop).
    Singular(SingularityKind),
    /// The path leaves the reachable set of the configurations (Fig. 4 case 7).
    Leaves,
    /// The path enters it (Fig. 4 case 1).
    Enters,
}

/// A point where the path is split into intervals.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SplitPoint {
    /// Path parameter, refined by bisection / golden-section search.
    pub s: f64,
    /// Time.
    pub t: f64,
    /// What happens there.
    pub kind: SplitKind,
    /// The refined value of the measure that found it (0 for reachability changes).
    pub measure: f64,
}

/// How singular positions are detected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SingularityDetection {
    /// The seed-003 closed-form measures when [`ParallelAxes`] is the solver, else the Jacobian.
    #[default]
    Auto,
    /// The Jacobian's relative smallest singular value, for every robot.
    Jacobian,
}

/// A scanned singularity measure.
#[derive(Debug, Clone, Copy)]
pub(super) enum Measure {
    /// `sign·√|1 − |cos θ_elbow||` of one arm of the closed form.
    Elbow(Shoulder, Wrist),
    /// `sin∠(w, e6)` of one arm.
    Wrist(Shoulder, Wrist),
    /// `(ρ − |D|)/L`.
    Shoulder,
    /// `σ_min/σ_max`, minimised over the configurations' solutions.
    Jacobian,
}

impl Measure {
    fn kind(self) -> SingularityKind {
        match self {
            Measure::Elbow(..) => SingularityKind::Elbow,
            Measure::Wrist(..) => SingularityKind::Wrist,
            Measure::Shoulder => SingularityKind::Shoulder,
            Measure::Jacobian => SingularityKind::Jacobian,
        }
    }
}

/// The scan of the samples ([`Tracker::split_points`]).
pub(super) struct Scan {
    /// Singular positions and reachability changes, by `s`.
    pub(super) points: Vec<SplitPoint>,
    /// Whether any configuration has a solution, per sample.
    pub(super) reach: Vec<bool>,
    /// The unseeded solutions of every sample.
    pub(super) solutions: Vec<IkSolutions>,
}

impl Tracker<'_> {
    /// Whether any configuration has a solution.
    pub(super) fn reachable(&self, sols: &IkSolutions) -> bool {
        sols.solutions.iter().any(|s| self.configurations.iter().any(|c| matches(&s.branch, c)))
    }

    pub(super) fn reachable_at(&self, s: f64) -> Result<bool, TrackingError> {
        let sols = self.solving.solve(&self.path.pose_at(s)?, None)?;
        Ok(self.reachable(&sols))
    }

    /// Every measure at `s` (`None` where undefined, e.g. unreachable).
    pub(super) fn measures_at(
        &self,
        pose: &Isometry3<f64>,
        sols: Option<&IkSolutions>,
    ) -> Result<Vec<Option<f64>>, TrackingError> {
        let robot = self.robot();
        let mut out = Vec::with_capacity(self.measures.len());
        if let Some(cf) = &self.closed_form {
            let m = cf.measures(robot, pose, &IkOptions::default())?;
            for measure in &self.measures {
                out.push(match *measure {
                    Measure::Elbow(sh, wr) => m.arm(sh, wr).map(|a| {
                        let e = a.elbow_margin();
                        e.signum() * e.abs().sqrt()
                    }),
                    Measure::Wrist(sh, wr) => m.arm(sh, wr).map(|a| a.wrist_sine),
                    Measure::Shoulder => Some(m.shoulder_margin() / self.length_scale),
                    Measure::Jacobian => None,
                });
            }
            return Ok(out);
        }
        let owned;
        let sols = match sols {
            Some(s) => s,
            None => {
                owned = self.solving.solve(pose, None)?;
                &owned
            }
        };
        let axes = if self.solving.position_only { JacobianAxes::Translation } else { JacobianAxes::All };
        let mut best: Option<f64> = None;
        for s in sols.solutions.iter().filter(|s| self.configurations.iter().any(|c| matches(&s.branch, c))) {
            let m = Manipulability::of(&robot.jacobian(&s.q).map_err(IkError::from)?, axes);
            let v = if m.sigma_max > 0.0 { m.sigma_min / m.sigma_max } else { 0.0 };
            best = Some(best.map_or(v, |b: f64| b.min(v)));
        }
        out.push(best);
        Ok(out)
    }

    /// Bisection between `a` (predicate `pa`) and `b` (the opposite) to the path tolerance.
    pub(super) fn bisect(
        &self,
        mut a: f64,
        mut b: f64,
        pa: bool,
        mut pred: impl FnMut(f64) -> Result<bool, TrackingError>,
    ) -> Result<f64, TrackingError> {
        for _ in 0..200 {
            if (b - a).abs() <= self.tolerance {
                break;
            }
            let m = 0.5 * (a + b);
            if pred(m)? == pa {
                a = m;
            } else {
                b = m;
            }
        }
        Ok(0.5 * (a + b))
    }

    /// Golden-section minimisation of measure `i` on `[a, b]`: (argmin, min).
    pub(super) fn minimise(&self, i: usize, mut a: f64, mut b: f64) -> Result<(f64, f64), TrackingError> {
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let eval = |s: f64| -> Result<f64, TrackingError> {
            Ok(self.measures_at(&self.path.pose_at(s)?, None)?[i].unwrap_or(f64::INFINITY))
        };
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let (mut fc, mut fd) = (eval(c)?, eval(d)?);
        for _ in 0..200 {
            if (b - a).abs() <= self.tolerance {
                break;
            }
            if fc <= fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = eval(c)?;
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = eval(d)?;
            }
        }
        Ok(if fc <= fd { (c, fc) } else { (d, fd) })
    }

    /// Step 2–3 of the algorithm: singular positions and reachability changes. Also returns
    /// the unseeded solutions of every sample (reused by [`Tracker::track_interval`]).
    pub(super) fn split_points(&self) -> Result<Scan, TrackingError> {
        let samples = self.path.samples();
        let mut reach = Vec::with_capacity(samples.len());
        let mut values: Vec<Vec<Option<f64>>> = Vec::with_capacity(samples.len());
        let mut all = Vec::with_capacity(samples.len());
        for p in samples {
            let sols = self.solving.solve(&p.pose, None)?;
            reach.push(self.reachable(&sols));
            values.push(self.measures_at(&p.pose, Some(&sols))?);
            all.push(sols);
            self.meter.advance(self.configurations.len());
        }
        let mut points = Vec::new();
        for k in 1..samples.len() {
            if reach[k] != reach[k - 1] {
                let s = self.bisect(samples[k - 1].s, samples[k].s, reach[k - 1], |s| self.reachable_at(s))?;
                let kind = if reach[k - 1] { SplitKind::Leaves } else { SplitKind::Enters };
                points.push(SplitPoint { s, t: self.path.time_at(s), kind, measure: 0.0 });
            }
        }
        let n = samples.len();
        for (i, measure) in self.measures.iter().enumerate() {
            let v = |k: usize| values[k][i].filter(|x| *x >= 0.0);
            for k in 0..n {
                let Some(vk) = v(k) else { continue };
                let left = if k > 0 { v(k - 1) } else { None };
                let right = if k + 1 < n { v(k + 1) } else { None };
                let (Some(l), Some(r)) = (left, right) else {
                    // An end sample (or next to an unreachable one): singular only if the sample is.
                    if vk <= TRACKING_SINGULAR && (k == 0 || k == n - 1) {
                        points.push(self.singular_point(samples[k].s, *measure, vk)?);
                    }
                    continue;
                };
                if vk <= l && vk <= r && !(vk == l && k > 1 && v(k - 2).is_some_and(|x| x == vk)) {
                    let (s, m) = self.minimise(i, samples[k - 1].s, samples[k + 1].s)?;
                    if m <= TRACKING_SINGULAR {
                        points.push(self.singular_point(s, *measure, m)?);
                    }
                }
            }
        }
        points.sort_by(|a, b| a.s.total_cmp(&b.s));
        let merge = 1e3 * self.tolerance;
        let mut merged: Vec<SplitPoint> = Vec::with_capacity(points.len());
        for p in points {
            match merged.last_mut() {
                Some(last) if (p.s - last.s).abs() <= merge => {
                    // Keep reachability changes over singular positions at the same place (the
                    // boundary of the manipulation space is itself singular, Fig. 4 cases 1, 7).
                    if matches!(p.kind, SplitKind::Leaves | SplitKind::Enters) {
                        *last = p;
                    }
                }
                _ => merged.push(p),
            }
        }
        Ok(Scan { points: merged, reach, solutions: all })
    }

    /// A singular position at `s`, its kind read from the solver's flags when it sets one.
    pub(super) fn singular_point(&self, s: f64, measure: Measure, value: f64) -> Result<SplitPoint, TrackingError> {
        let sols = self.solving.solve(&self.path.pose_at(s)?, None)?;
        let flagged = sols
            .solutions
            .iter()
            .filter(|x| self.configurations.iter().any(|c| matches(&x.branch, c)))
            .find_map(|x| x.singularities.first().copied());
        let kind = match measure {
            Measure::Jacobian => flagged.unwrap_or(SingularityKind::Jacobian),
            other => other.kind(),
        };
        Ok(SplitPoint { s, t: self.path.time_at(s), kind: SplitKind::Singular(kind), measure: value })
    }
}
