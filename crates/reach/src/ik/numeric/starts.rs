//! Deterministic starts (the seed or home, then pseudo-random configurations inside the
//! limits), when two solutions are one, and the branch label naming the start.

use super::Branch;
use crate::angle::{fit_into_limits, wrap};
use crate::model::{JointKind, Robot};
use crate::rng::SplitMix64;
use crate::tolerance::{IK_NUMERIC_DISTINCT, LIMIT_SLACK};

/// Fixed seed of the start generator: the same problem always gets the same starts.
pub(super) const START_SEED: u64 = 0x5EED_1C0D_2024_0001;

/// Where a start came from.
#[derive(Debug, Clone, Copy)]
pub(super) enum Start {
    Seed,
    Home,
    Random(usize),
}

/// Deterministic start configurations: the seed (or home), then pseudo-random ones.
pub(super) struct Starts {
    pub(super) first: Vec<f64>,
    pub(super) from_seed: bool,
    /// Sampling interval per joint.
    pub(super) ranges: Vec<(f64, f64)>,
    pub(super) rng: SplitMix64,
}

impl Starts {
    pub(super) fn new(robot: &Robot, seed: Option<&[f64]>, length_scale: f64) -> Starts {
        let joints = robot.joints();
        let first: Vec<f64> = match seed {
            Some(s) => s
                .iter()
                .zip(joints)
                .map(|(&v, j)| {
                    let v = if j.kind == JointKind::Revolute { fit_into_limits(v, &j.limits, 0.0) } else { v };
                    v.clamp(j.limits.lower, j.limits.upper)
                })
                .collect(),
            None => robot.home(),
        };
        let ranges = sampling_ranges(robot, length_scale);
        Starts { first, from_seed: seed.is_some(), ranges, rng: SplitMix64(START_SEED) }
    }

    /// Writes start `k` into `q`.
    pub(super) fn next_into(&mut self, k: usize, q: &mut [f64]) -> Start {
        if k == 0 {
            q.copy_from_slice(&self.first);
            return if self.from_seed { Start::Seed } else { Start::Home };
        }
        for (v, &(lo, hi)) in q.iter_mut().zip(&self.ranges) {
            *v = lo + (hi - lo) * self.rng.next_f64();
        }
        Start::Random(k)
    }
}

/// Interval per joint that random starts are drawn from: revolute ranges of a full turn or
/// more cut to one turn, prismatic ranges to `length_scale` either side of the centre.
pub(super) fn sampling_ranges(robot: &Robot, length_scale: f64) -> Vec<(f64, f64)> {
    use std::f64::consts::{PI, TAU};
    robot
        .joints()
        .iter()
        .map(|j| {
            let (lo, hi) = (j.limits.lower, j.limits.upper);
            match j.kind {
                JointKind::Revolute if j.limits.contains(-PI, 0.0) && j.limits.contains(PI, 0.0) => (-PI, PI),
                JointKind::Revolute if j.limits.span() >= TAU => {
                    let start = if lo.is_finite() { lo } else { hi - TAU };
                    (start, start + TAU)
                }
                JointKind::Revolute => (lo, hi),
                JointKind::Prismatic => {
                    let centre = if lo.is_finite() && hi.is_finite() { 0.5 * (lo + hi) } else { j.home };
                    (lo.max(centre - length_scale), hi.min(centre + length_scale))
                }
            }
        })
        .collect()
}

/// Whether two configurations are the same solution (revolute differences wrapped).
pub(super) fn same_configuration(robot: &Robot, a: &[f64], b: &[f64]) -> bool {
    robot.joints().iter().zip(a.iter().zip(b)).all(|(j, (x, y))| {
        let d = if j.kind == JointKind::Revolute { wrap(x - y) } else { x - y };
        d.abs() < IK_NUMERIC_DISTINCT
    })
}

/// Branch label: which start found the solution and the sign of each joint value as it is
/// reported (e.g. `start=random-3 signs=+-+--+`).
pub(super) fn label(robot: &Robot, q: &[f64], start: Start) -> Branch {
    let start = match start {
        Start::Seed => "seed".to_string(),
        Start::Home => "home".to_string(),
        Start::Random(k) => format!("random-{k}"),
    };
    let mut signs = String::with_capacity(q.len());
    for (j, &v) in robot.joints().iter().zip(q) {
        let v = if j.kind == JointKind::Revolute { fit_into_limits(v, &j.limits, LIMIT_SLACK) } else { v };
        signs.push(if v < 0.0 { '-' } else { '+' });
    }
    Branch::new([("start", start), ("signs", signs)])
}
