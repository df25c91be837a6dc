//! Raw solver candidates before verification: joint values, labels, flags, and the duplicate rules.

use smallvec::SmallVec;

use crate::angle::fit_into_limits;
use crate::model::{JointKind, Robot};
use crate::tolerance::{IK_DUPLICATE, LIMIT_SLACK};

use super::*;

/// Joint values of a [`Candidate`]: inline up to 8 joints (every closed form), on the heap
/// beyond (long chains, numeric solver only).
pub(crate) type JointValues = SmallVec<[f64; 8]>;

/// The `key=value` pairs of a [`Candidate`]'s branch label, inline up to 3 pairs; a [`Branch`]
/// once the candidate is verified (the 6R closed forms use the compact [`Raw6`] instead).
pub(crate) type Labels = SmallVec<[(Label, Label); 3]>;

/// The singularity flags of a [`Candidate`], inline (there are four kinds).
pub(crate) type Flags = SmallVec<[SingularityKind; 4]>;

/// A raw solver output before verification.
#[derive(Debug, Clone)]
pub(crate) struct Candidate {
    pub q: JointValues,
    pub branch: Labels,
    pub singularities: Flags,
}

impl Candidate {
    pub fn new(q: Vec<f64>, branch: Branch) -> Self {
        Candidate { q: SmallVec::from_vec(q), branch: SmallVec::from_vec(branch.0), singularities: Flags::new() }
    }
}

/// The singularity kinds of a [`Raw6`] as bits, reported in one fixed order — shoulder, elbow,
/// wrist, Jacobian — the order in which every 6R closed form flags them.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct FlagBits(u8);

impl FlagBits {
    /// The kinds in the order of their bits.
    const ORDER: [SingularityKind; 4] =
        [SingularityKind::Shoulder, SingularityKind::Elbow, SingularityKind::Wrist, SingularityKind::Jacobian];

    /// These flags with `kind` added when `on`.
    #[must_use]
    pub fn with(self, kind: SingularityKind, on: bool) -> Self {
        let bit = Self::ORDER.iter().position(|k| *k == kind).map_or(0, |i| 1 << i);
        if on { FlagBits(self.0 | bit) } else { self }
    }

    /// The kinds set, in the fixed order (lowest bit first; nothing to visit when none is set).
    pub fn iter(self) -> impl Iterator<Item = SingularityKind> {
        let mut bits = self.0;
        std::iter::from_fn(move || {
            let i = bits.trailing_zeros() as usize;
            bits &= bits.wrapping_sub(1);
            Self::ORDER.get(i).copied()
        })
    }

    /// The first kind set, if any.
    #[must_use]
    pub fn first(self) -> Option<SingularityKind> {
        self.iter().next()
    }

    /// Whether no kind is set.
    #[must_use]
    pub fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// A raw solution of a 6R closed form (spherical wrist, two-link wrist, parallel axes): the
/// six joint values, the values of its three-part branch label (the keys are the set's,
/// [`Raw6Set`]) and its singularity flags — about 100 bytes, no vector. The public
/// [`IkSolution`] is built only for the verified ones.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Raw6 {
    pub q: [f64; 6],
    pub values: [&'static str; 3],
    pub flags: FlagBits,
}

/// The raw solutions of one 6R closed-form solve: a fixed-capacity set of up to 8 on the stack
/// (every such arm has at most 8 solutions), labelled with the same three keys.
#[derive(Debug, Clone)]
pub(crate) struct Raw6Set {
    keys: [&'static str; 3],
    items: SmallVec<[Raw6; 8]>,
}

impl Raw6Set {
    /// An empty set whose labels have the keys `keys`.
    #[must_use]
    pub fn new(keys: [&'static str; 3]) -> Self {
        Raw6Set { keys, items: SmallVec::new() }
    }

    /// Adds a solution.
    pub fn push(&mut self, raw: Raw6) {
        self.items.push(raw);
    }

    /// The solutions, in the order pushed.
    pub fn iter(&self) -> impl Iterator<Item = &Raw6> {
        self.items.iter()
    }

    /// Whether the set is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Keeps only the solutions labelled exactly `branch`.
    pub fn retain_branch(&mut self, branch: &Branch) {
        let keys = self.keys;
        self.items.retain(|r| {
            branch.0.len() == 3
                && branch
                    .0
                    .iter()
                    .zip(keys.iter().zip(&r.values))
                    .all(|((k, v), (rk, rv))| k.as_str() == *rk && v.as_str() == *rv)
        });
    }
}

/// The candidates a verification ([`finish_within_into`]) reads: the general [`Candidate`]s
/// (any joint count, owned labels) or a closed form's compact [`Raw6Set`].
pub(crate) trait CandidateList {
    /// Number of candidates.
    fn count(&self) -> usize;
    /// Joint values of candidate `i`.
    fn joints(&self, i: usize) -> &[f64];
    /// Joint values of candidate `i`, to normalise in place.
    fn joints_mut(&mut self, i: usize) -> &mut [f64];
    /// Singularity flags of candidate `i`, in order.
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_;
    /// Makes `out` (a reused solution's label) candidate `i`'s branch label (moving it out:
    /// called once, for a kept candidate).
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>);
}

impl CandidateList for [Candidate] {
    fn count(&self) -> usize {
        self.len()
    }
    fn joints(&self, i: usize) -> &[f64] {
        &self[i].q
    }
    fn joints_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self[i].q
    }
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_ {
        self[i].singularities.iter().copied()
    }
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>) {
        out.clear();
        out.extend(self[i].branch.drain(..));
    }
}

impl CandidateList for Raw6Set {
    fn count(&self) -> usize {
        self.items.len()
    }
    fn joints(&self, i: usize) -> &[f64] {
        &self.items[i].q
    }
    fn joints_mut(&mut self, i: usize) -> &mut [f64] {
        &mut self.items[i].q
    }
    fn flags(&self, i: usize) -> impl Iterator<Item = SingularityKind> + '_ {
        self.items[i].flags.iter()
    }
    /// A reused solution that holds the same static strings already (the usual case: a solve
    /// into a reused [`IkSolutions`] returns the branches in the same order) keeps its label.
    #[inline]
    fn take_label(&mut self, i: usize, out: &mut Vec<(Label, Label)>) {
        let values = self.items[i].values;
        let pairs = self.keys.iter().zip(values);
        if out.len() == self.keys.len() && out.iter().zip(pairs.clone()).all(|((k, v), (rk, rv))| k.is(rk) && v.is(rv))
        {
            return;
        }
        out.clear();
        out.extend(pairs.map(|(k, v)| (Label::from(*k), Label::from(v))));
    }
}

/// [`fit_into_limits`] with the IK slack: revolute values as the solvers report them
/// (wrapped into (−π, π], or moved by whole turns into the joint range). An angle already in
/// (−π, π] and within the limits costs two comparisons ([`crate::angle::wrap`]'s fast path).
#[inline]
pub(crate) fn fit_revolute(angle: f64, limits: &crate::model::Limits) -> f64 {
    fit_into_limits(angle, limits, LIMIT_SLACK)
}

/// Whether two joint values are equal within `IK_DUPLICATE` modulo whole turns
/// (`wrap(a − b).abs() < IK_DUPLICATE`), skipping the `fmod` when the plain difference decides.
#[inline]
pub(super) fn same_angle(a: f64, b: f64) -> bool {
    use std::f64::consts::{PI, TAU};
    let d = (a - b).abs();
    // |d| < IK_DUPLICATE (< π) wraps to itself; |d| in [IK_DUPLICATE, π] also wraps to itself
    // and fails the test; only larger differences can wrap back near 0.
    if d < IK_DUPLICATE {
        true
    } else if d <= PI {
        false
    } else if d < TAU {
        // `wrap(a − b)` is `a − b ∓ 2π` here, exactly (Sterbenz: 2π lies within [d, 2d]), of
        // magnitude `2π − d`, also exact: the same value without the remainder (the two
        // wrist solutions of an arm differ by about π in θ4 and θ6).
        TAU - d < IK_DUPLICATE
    } else {
        crate::angle::wrap(a - b).abs() < IK_DUPLICATE
    }
}

/// Whether two joint values are different by [`same_angle`] *and* by the prismatic rule of
/// [`same_q`], whatever the joint's kind: `true` proves that two joint vectors differing so at
/// one joint are different solutions; `false` proves nothing (`NaN` gives `false`). The lane
/// screen of [`verify_block`], branch-free.
#[inline(always)]
pub(super) fn surely_distinct(a: f64, b: f64) -> bool {
    use std::f64::consts::TAU;
    let d = (a - b).abs();
    let e = TAU - d;
    // Revolute, d < 2π: for d ≤ π, e ≥ π > IK_DUPLICATE and the test is d ≥ IK_DUPLICATE
    // (at d = π the minimum is e = π), where `same_angle` is false; for d in (π, 2π),
    // e < π < d and the test is 2π − d ≥ IK_DUPLICATE, `same_angle`'s own (exact) term.
    // Prismatic: either way d ≥ IK_DUPLICATE. d ≥ 2π proves nothing here.
    (d < TAU) & ((if d < e { d } else { e }) >= IK_DUPLICATE)
}

/// Whether two joint vectors are the same solution: revolute values by [`same_angle`], prismatic
/// ones literally (`|a − b| < IK_DUPLICATE` metres — 0 m and 2π m are different).
/// Compared from the last joint: branches of an arm share their first joints (the two wrist
/// solutions of one arm differ first in the wrist), so distinct ones part at once.
pub(super) fn same_q(robot: &Robot, a: &[f64], b: &[f64]) -> bool {
    a.iter().zip(b).zip(robot.joints()).rev().all(|((a, b), j)| match j.kind {
        JointKind::Revolute => same_angle(*a, *b),
        JointKind::Prismatic => (a - b).abs() < IK_DUPLICATE,
    })
}
