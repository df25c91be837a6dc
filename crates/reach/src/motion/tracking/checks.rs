//! The limit checks of a tracked configuration: joint ranges and speed limits, each broken
//! stretch refined by bisection, and the ±180° crossings of the wrapped angles.

use std::f64::consts::{PI, TAU};

use serde::Serialize;

use super::branch::Lock;
use super::intervals::ConfigurationTrack;
use super::{Tracker, TrackingError};
use crate::angle::wrap;
use crate::model::{Joint, JointKind};
use crate::tolerance::{LIMIT_SLACK, TRACKING_RATE_STEP};

/// Which limit a violation concerns.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ViolationKind {
    /// Joint position outside its range (case c of the paper).
    Position,
    /// Joint speed above its limit (case d).
    Velocity,
    /// The followed branch has no solution (a branch lost without a singular position).
    BranchLost,
}

/// A stretch of the path where a configuration breaks a limit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Violation {
    /// Which limit.
    pub kind: ViolationKind,
    /// 1-based joint number (`None` for [`ViolationKind::BranchLost`]).
    pub joint: Option<usize>,
    /// Joint name (empty for a lost branch).
    pub name: String,
    /// Where it starts (path parameter; refined by bisection unless it starts with the interval).
    pub s_start: f64,
    /// Where it ends (the interval's end when it lasts to there).
    pub s_end: f64,
    /// Time at `s_start`.
    pub t_start: f64,
    /// Time at `s_end`.
    pub t_end: f64,
    /// The worst sampled value: the position (wrapped into (−π, π] for a range narrower than a
    /// turn) or the rate.
    pub worst: f64,
    /// Lower limit (position) or `−max_velocity`.
    pub lower: f64,
    /// Upper limit (position) or `max_velocity`.
    pub upper: f64,
}

/// A revolute joint of a tracked configuration crossing ±180° (its wrapped angle jumps by a
/// turn while the motion is continuous; notes 003 §5.5's θ4 at s = 842.12 mm).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WrapCrossing {
    /// 1-based joint number.
    pub joint: usize,
    /// Path parameter, refined by bisection.
    pub s: f64,
    /// Time.
    pub t: f64,
}

impl Tracker<'_> {
    /// The joint vector of the locked branch at `s`, next to `reference`.
    pub(super) fn q_at(&self, s: f64, lock: &Lock, reference: &[f64]) -> Result<Option<Vec<f64>>, TrackingError> {
        self.solving.follow(&self.path.pose_at(s)?, lock, reference)
    }

    /// A limit violation of joint `j` (0-based) over `s ∈ [s_start, s_end]`, with the worst
    /// sampled value and the limits `(lower, upper)` it broke.
    fn joint_violation(
        &self,
        kind: ViolationKind,
        j: usize,
        (s_start, s_end): (f64, f64),
        worst: f64,
        (lower, upper): (f64, f64),
    ) -> Violation {
        Violation {
            kind,
            joint: Some(j + 1),
            name: self.robot().joints()[j].name.clone(),
            s_start,
            s_end,
            t_start: self.path.time_at(s_start),
            t_end: self.path.time_at(s_end),
            worst,
            lower,
            upper,
        }
    }

    pub(super) fn lost(&self, a: f64, b: f64) -> Violation {
        Violation {
            kind: ViolationKind::BranchLost,
            joint: None,
            name: String::new(),
            s_start: a,
            s_end: b,
            t_start: self.path.time_at(a),
            t_end: self.path.time_at(b),
            worst: f64::NAN,
            lower: f64::NAN,
            upper: f64::NAN,
        }
    }

    /// Position violations, crossings refined by bisection.
    pub(super) fn check_positions(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        for (j, joint) in robot.joints().iter().enumerate() {
            let inside = |v: f64| position_margin(joint, v) >= -LIMIT_SLACK;
            let n = track.q.len();
            for (first, last) in failing_runs(n, |k| inside(track.q[k][j])) {
                let s_start = if first == 0 {
                    track.s[0]
                } else {
                    let reference = track.q[first - 1].clone();
                    self.bisect(track.s[first - 1], track.s[first], true, |s| {
                        Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| inside(q[j])))
                    })?
                };
                let s_end = if last == n - 1 {
                    track.s[n - 1]
                } else {
                    let reference = track.q[last].clone();
                    self.bisect(track.s[last], track.s[last + 1], false, |s| {
                        Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| inside(q[j])))
                    })?
                };
                let worst = (first..=last)
                    .map(|i| track.q[i][j])
                    .min_by(|a, b| position_margin(joint, *a).total_cmp(&position_margin(joint, *b)))
                    .unwrap_or(f64::NAN);
                let worst =
                    if joint.kind == JointKind::Revolute && joint.limits.span() < TAU { wrap(worst) } else { worst };
                let limits = (joint.limits.lower, joint.limits.upper);
                let violation = self.joint_violation(ViolationKind::Position, j, (s_start, s_end), worst, limits);
                track.violations.push(violation);
            }
        }
        Ok(())
    }

    /// The instantaneous rate of joint `j` at `s` (central difference through IK).
    pub(super) fn rate_at(
        &self,
        s: f64,
        j: usize,
        lock: &Lock,
        reference: &[f64],
    ) -> Result<Option<f64>, TrackingError> {
        let h = TRACKING_RATE_STEP * (self.path.end() - self.path.start());
        let (a, b) = ((s - h).max(self.path.start()), (s + h).min(self.path.end()));
        let (Some(qa), Some(qb)) = (self.q_at(a, lock, reference)?, self.q_at(b, lock, reference)?) else {
            return Ok(None);
        };
        let dt = self.path.time_at(b) - self.path.time_at(a);
        Ok(Some((qb[j] - qa[j]) / dt))
    }

    /// Speed violations over runs of steps; where the rate changes smoothly the crossing is
    /// refined by bisection on the instantaneous rate, else the step's end is reported.
    pub(super) fn check_velocities(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        let steps = track.step_rates.len();
        for (j, joint) in robot.joints().iter().enumerate() {
            let Some(vmax) = joint.max_velocity else { continue };
            let ok = |r: f64| r.abs() <= vmax * (1.0 + LIMIT_SLACK);
            for (first, last) in failing_runs(steps, |k| ok(track.step_rates[k][j])) {
                let mid = |i: usize| 0.5 * (track.s[i] + track.s[i + 1]);
                let inside_rate = |s: f64, reference: &[f64]| -> Result<bool, TrackingError> {
                    Ok(self.rate_at(s, j, lock, reference)?.is_none_or(ok))
                };
                let s_start = if first == 0 {
                    track.s[0]
                } else {
                    let reference = track.q[first].clone();
                    let (a, b) = (mid(first - 1), mid(first));
                    if inside_rate(a, &reference)? && !inside_rate(b, &reference)? {
                        self.bisect(a, b, true, |s| inside_rate(s, &reference))?
                    } else {
                        track.s[first]
                    }
                };
                let s_end = if last == steps - 1 {
                    track.s[steps]
                } else {
                    let reference = track.q[last + 1].clone();
                    let (a, b) = (mid(last), mid(last + 1));
                    if !inside_rate(a, &reference)? && inside_rate(b, &reference)? {
                        self.bisect(a, b, false, |s| inside_rate(s, &reference))?
                    } else {
                        track.s[last + 1]
                    }
                };
                let worst = (first..=last)
                    .map(|i| track.step_rates[i][j])
                    .max_by(|a, b| a.abs().total_cmp(&b.abs()))
                    .unwrap_or(f64::NAN);
                let violation =
                    self.joint_violation(ViolationKind::Velocity, j, (s_start, s_end), worst, (-vmax, vmax));
                track.violations.push(violation);
            }
        }
        Ok(())
    }

    /// ±180° crossings of the wrapped angles, refined by bisection.
    pub(super) fn find_wraps(&self, track: &mut ConfigurationTrack, lock: &Lock) -> Result<(), TrackingError> {
        let robot = self.robot();
        let turn = |v: f64| ((v + PI) / TAU).floor();
        for (j, joint) in robot.joints().iter().enumerate() {
            if joint.kind != JointKind::Revolute {
                continue;
            }
            for k in 1..track.q.len() {
                let (a, b) = (track.q[k - 1][j], track.q[k][j]);
                if turn(a) == turn(b) {
                    continue;
                }
                let reference = track.q[k - 1].clone();
                let side = turn(a);
                let s = self.bisect(track.s[k - 1], track.s[k], true, |s| {
                    Ok(self.q_at(s, lock, &reference)?.is_some_and(|q| turn(q[j]) == side))
                })?;
                track.wraps.push(WrapCrossing { joint: j + 1, s, t: self.path.time_at(s) });
            }
        }
        Ok(())
    }
}

/// Signed distance of `v` inside the joint's range (negative outside): for a revolute joint
/// with a range narrower than a turn, of the best representative `v + 2πk`.
pub(super) fn position_margin(joint: &Joint, v: f64) -> f64 {
    let (lo, hi) = (joint.limits.lower, joint.limits.upper);
    if joint.kind == JointKind::Revolute && joint.limits.span() < TAU {
        let w = wrap(v);
        [w - TAU, w, w + TAU].into_iter().map(|x| (x - lo).min(hi - x)).fold(f64::NEG_INFINITY, f64::max)
    } else {
        (v - lo).min(hi - v)
    }
}

/// The maximal runs `(first, last)` (inclusive) of indices `0..n` where `ok` is false, in order.
pub(super) fn failing_runs(n: usize, ok: impl Fn(usize) -> bool) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut k = 0;
    while k < n {
        if ok(k) {
            k += 1;
            continue;
        }
        let first = k;
        while k < n && !ok(k) {
            k += 1;
        }
        runs.push((first, k - 1));
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn position_margin_is_modular_for_ranges_narrower_than_a_turn() {
        let welder = presets::get("welder6r").unwrap();
        let j4 = &welder.joints()[3]; // [−175°, 150°]
        let m = |deg: f64| position_margin(j4, deg.to_radians()).to_degrees();
        assert!((m(0.0) - 150.0).abs() < 1e-9);
        assert!((m(140.0) - 10.0).abs() < 1e-9);
        // 190° is −170° (inside, 5° from −175°); 167.5° is the middle of the gap (150°, 185°).
        assert!((m(190.0) - 5.0).abs() < 1e-9);
        assert!((m(167.5) + 17.5).abs() < 1e-9);
        // An unlimited joint is never outside; a wide range is checked on the value itself.
        let mut j = j4.clone();
        j.limits = crate::model::Limits::new(-3.0 * PI, 3.0 * PI);
        assert!(position_margin(&j, 3.5 * PI) < 0.0 && position_margin(&j, 2.5 * PI) > 0.0);
        j.limits = crate::model::Limits::UNLIMITED;
        assert!(position_margin(&j, 1e6) > 0.0);
    }
}
