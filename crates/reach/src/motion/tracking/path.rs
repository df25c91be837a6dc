//! The tracked path: samples, their validation, and the pose and time between samples.

use std::fmt;

use nalgebra::{Isometry3, Translation3};

use super::TrackingError;
use crate::motion::sample::PathSample;

/// A path: its samples and a way to evaluate it between them.
pub struct TrackedPath<'a> {
    samples: &'a [PathSample],
    evaluator: Option<&'a dyn Fn(f64) -> Isometry3<f64>>,
}

impl fmt::Debug for TrackedPath<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("TrackedPath")
            .field("samples", &self.samples.len())
            .field("evaluator", &self.evaluator.is_some())
            .finish()
    }
}

impl<'a> TrackedPath<'a> {
    /// A path known only at its samples: poses between samples are interpolated (position
    /// linearly, orientation by slerp).
    ///
    /// # Errors
    /// [`TrackingError`] for fewer than 2 samples, non-finite values, or `s`/`t` not
    /// strictly increasing.
    pub fn sampled(samples: &'a [PathSample]) -> Result<Self, TrackingError> {
        validate_samples(samples)?;
        Ok(TrackedPath { samples, evaluator: None })
    }

    /// A path with an exact evaluator `pose(s)` used between samples (for bisection).
    ///
    /// # Errors
    /// As [`TrackedPath::sampled`].
    pub fn with_evaluator(
        samples: &'a [PathSample],
        evaluator: &'a dyn Fn(f64) -> Isometry3<f64>,
    ) -> Result<Self, TrackingError> {
        validate_samples(samples)?;
        Ok(TrackedPath { samples, evaluator: Some(evaluator) })
    }

    /// The samples.
    #[must_use]
    pub fn samples(&self) -> &[PathSample] {
        self.samples
    }

    /// The segment `k` with `s_k ≤ s ≤ s_{k+1}` (clamped to the path).
    pub(super) fn segment(&self, s: f64) -> usize {
        let n = self.samples.len();
        let k = self.samples.partition_point(|p| p.s <= s);
        k.saturating_sub(1).min(n - 2)
    }

    /// The pose at `s` (evaluator, else interpolation between samples).
    ///
    /// # Errors
    /// [`TrackingError::Evaluator`] when the evaluator returns a non-finite pose.
    pub fn pose_at(&self, s: f64) -> Result<Isometry3<f64>, TrackingError> {
        let pose = match self.evaluator {
            Some(f) => f(s),
            None => {
                let k = self.segment(s);
                let (a, b) = (&self.samples[k], &self.samples[k + 1]);
                let u = ((s - a.s) / (b.s - a.s)).clamp(0.0, 1.0);
                let p = a.pose.translation.vector.lerp(&b.pose.translation.vector, u);
                let r = a.pose.rotation.try_slerp(&b.pose.rotation, u, 1e-12).unwrap_or(a.pose.rotation);
                Isometry3::from_parts(Translation3::from(p), r)
            }
        };
        if pose.translation.vector.iter().chain(pose.rotation.coords.iter()).any(|v| !v.is_finite()) {
            return Err(TrackingError::Evaluator { s });
        }
        Ok(pose)
    }

    /// The time at `s`, interpolated linearly between samples.
    #[must_use]
    pub fn time_at(&self, s: f64) -> f64 {
        let k = self.segment(s);
        let (a, b) = (&self.samples[k], &self.samples[k + 1]);
        a.t + (b.t - a.t) * (s - a.s) / (b.s - a.s)
    }

    pub(super) fn start(&self) -> f64 {
        self.samples[0].s
    }

    pub(super) fn end(&self) -> f64 {
        self.samples[self.samples.len() - 1].s
    }
}

pub(super) fn validate_samples(samples: &[PathSample]) -> Result<(), TrackingError> {
    if samples.len() < 2 {
        return Err(TrackingError::TooFewSamples { found: samples.len() });
    }
    for (index, p) in samples.iter().enumerate() {
        if !p.s.is_finite() {
            return Err(TrackingError::NonFinite { index, field: "s" });
        }
        if !p.t.is_finite() {
            return Err(TrackingError::NonFinite { index, field: "t" });
        }
        if p.pose.translation.vector.iter().chain(p.pose.rotation.coords.iter()).any(|v| !v.is_finite()) {
            return Err(TrackingError::NonFinite { index, field: "pose" });
        }
        if index > 0 {
            let q = &samples[index - 1];
            if p.s <= q.s {
                return Err(TrackingError::NotIncreasing { index, field: "s", previous: q.s, value: p.s });
            }
            if p.t <= q.t {
                return Err(TrackingError::NotIncreasing { index, field: "t", previous: q.t, value: p.t });
            }
        }
    }
    Ok(())
}
