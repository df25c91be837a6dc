//! The scan of the samples for singular positions and reachability changes (notes 003 §3.6,
//! §4 steps 2–3), refined by golden-section search and bisection.

use nalgebra::Isometry3;
use serde::Serialize;

use super::branch::matches;
use super::{Tracker, TrackingError};
use crate::ik::{IkError, IkSolutions, SingularityKind};
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
    /// The solver's closed-form measures for full-pose tracking when it has them
    /// ([`IkSolver::singularity_measures`](crate::ik::IkSolver::singularity_measures), e.g.
    /// seed 003's), else the Jacobian.
    #[default]
    Auto,
    /// The Jacobian's relative smallest singular value, for every robot.
    Jacobian,
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

    /// How many measures are scanned: the solver's closed-form ones, else one, `σ_min/σ_max`
    /// of the Jacobian minimised over the configurations' solutions.
    fn measure_count(&self) -> usize {
        self.closed_form.as_ref().map_or(1, |m| m.kinds().len())
    }

    /// Every measure at `pose` (`None` where undefined, e.g. unreachable); `sols` are the
    /// unseeded solutions there when known.
    pub(super) fn measures_at(
        &self,
        pose: &Isometry3<f64>,
        sols: Option<&IkSolutions>,
    ) -> Result<Vec<Option<f64>>, TrackingError> {
        let robot = self.robot();
        if let Some(closed_form) = &self.closed_form {
            return Ok(closed_form.at(robot, pose)?);
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
        Ok(vec![best])
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
        // Per measure, its value at every sample.
        let mut values: Vec<Vec<Option<f64>>> = vec![Vec::with_capacity(samples.len()); self.measure_count()];
        let mut all = Vec::with_capacity(samples.len());
        for p in samples {
            self.check_cancel()?;
            let sols = self.solving.solve(&p.pose, None)?;
            reach.push(self.reachable(&sols));
            let at = self.measures_at(&p.pose, Some(&sols))?;
            debug_assert_eq!(at.len(), values.len(), "one value per measure");
            for (column, value) in values.iter_mut().zip(at) {
                column.push(value);
            }
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
        for (i, column) in values.iter().enumerate() {
            let v = |k: usize| column[k].filter(|x| *x >= 0.0);
            for k in 0..n {
                let Some(vk) = v(k) else { continue };
                let left = if k > 0 { v(k - 1) } else { None };
                let right = if k + 1 < n { v(k + 1) } else { None };
                let (Some(l), Some(r)) = (left, right) else {
                    // An end sample (or next to an unreachable one): singular only if the sample is.
                    if vk <= TRACKING_SINGULAR && (k == 0 || k == n - 1) {
                        points.push(self.singular_point(samples[k].s, i, vk)?);
                    }
                    continue;
                };
                if vk <= l && vk <= r && !(vk == l && k > 1 && v(k - 2).is_some_and(|x| x == vk)) {
                    let (s, m) = self.minimise(i, samples[k - 1].s, samples[k + 1].s)?;
                    if m <= TRACKING_SINGULAR {
                        points.push(self.singular_point(s, i, m)?);
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

    /// A singular position at `s` found by measure `i`: of the measure's kind, or for the
    /// Jacobian's of the kind the solver flags there, if it flags one.
    pub(super) fn singular_point(&self, s: f64, i: usize, value: f64) -> Result<SplitPoint, TrackingError> {
        let kind = match &self.closed_form {
            Some(closed_form) => closed_form.kinds()[i],
            None => {
                let sols = self.solving.solve(&self.path.pose_at(s)?, None)?;
                sols.solutions
                    .iter()
                    .filter(|x| self.configurations.iter().any(|c| matches(&x.branch, c)))
                    .find_map(|x| x.singularities.first().copied())
                    .unwrap_or(SingularityKind::Jacobian)
            }
        };
        Ok(SplitPoint { s, t: self.path.time_at(s), kind: SplitKind::Singular(kind), measure: value })
    }
}
