//! The forward-kinematics check that turns candidates into verified solutions (scalar and in lanes).

use std::sync::Arc;

use nalgebra::{Point3, Rotation3, Vector3};

use crate::kinematics::{FrameLanes, Lanes, check_q};
use crate::model::{JointKind, Robot};
use crate::tolerance::{IK_ORIENTATION, IK_POSITION, LIMIT_SLACK};

use super::candidate::{same_q, surely_distinct};
use super::*;
use crate::ik::{IkError, IkTarget};

/// The target of the FK check, prepared once per solve (the target rotation as a transposed
/// matrix instead of a quaternion converted for each candidate).
pub(super) enum Check {
    /// Flange position and `R_targetᵀ`.
    Pose(Vector3<f64>, Rotation3<f64>),
    /// Tool point only.
    Position(Point3<f64>),
}

/// Joint count up to which candidates are verified in lanes ([`Robot::fk_lanes`], joint values
/// on the stack); longer chains take the scalar forward kinematics one candidate at a time.
pub(super) const LANE_DOF: usize = 8;

/// Candidates verified together: the 8 solutions of a 6R closed form in one pass.
pub(super) const VERIFY_LANES: usize = 8;

impl Check {
    pub(super) fn new(target: &IkTarget) -> Self {
        match target {
            IkTarget::Pose(pose) => Check::Pose(pose.translation.vector, pose.rotation.to_rotation_matrix().inverse()),
            IkTarget::Position(p) => Check::Position(*p),
        }
    }

    /// Pose errors of the tool poses `t`, lane by lane: the position error (metres) and the
    /// orientation error's `(sin, cos)` (the angle is `atan2` of them, [`Check::angle`]; both 0
    /// for a position target).
    ///
    /// The angle of `R_targetᵀ·R` is not `acos((tr − 1)/2)`: that is NaN when rounding puts the
    /// trace above 3 (an exact solution), and imprecise near 0. `atan2(½‖vee(R − Rᵀ)‖, (tr − 1)/2)`
    /// is neither. Each lane is the scalar formula with nalgebra's order of operations.
    #[inline(always)]
    pub(super) fn errors<const L: usize>(&self, t: &FrameLanes<L>) -> (Lanes<L>, Lanes<L>, Lanes<L>) {
        let norm = |x: f64, y: f64, z: f64| (x * x + y * y + z * z).sqrt();
        match self {
            Check::Pose(p, r_inv) => {
                let k = r_inv.matrix();
                let position = std::array::from_fn(|l| norm(t.p[0][l] - p.x, t.p[1][l] - p.y, t.p[2][l] - p.z));
                // Entry (i, j) of R_targetᵀ·R.
                let m = |i: usize, j: usize, l: usize| {
                    k[(i, 0)] * t.r[0][j][l] + k[(i, 1)] * t.r[1][j][l] + k[(i, 2)] * t.r[2][j][l]
                };
                let mut sin = [0.0; L];
                let mut cos = [0.0; L];
                for l in 0..L {
                    sin[l] = 0.5 * norm(m(2, 1, l) - m(1, 2, l), m(0, 2, l) - m(2, 0, l), m(1, 0, l) - m(0, 1, l));
                    cos[l] = 0.5 * (m(0, 0, l) + m(1, 1, l) + m(2, 2, l) - 1.0);
                }
                (position, sin, cos)
            }
            Check::Position(p) => {
                let position = std::array::from_fn(|l| norm(t.p[0][l] - p.x, t.p[1][l] - p.y, t.p[2][l] - p.z));
                (position, [0.0; L], [1.0; L])
            }
        }
    }

    /// The orientation errors (radians) of [`Check::errors`]' `(sin, cos)`, lane by lane
    /// ([`atan2_each`](crate::angle::atan2_each): the lanes together when `WIDE`, bit for bit
    /// `atan2` either way): 0 for a position target.
    #[inline(always)]
    pub(super) fn angles<const WIDE: bool, const L: usize>(&self, sin: &Lanes<L>, cos: &Lanes<L>) -> Lanes<L> {
        match self {
            Check::Pose(..) => crate::angle::atan2_each::<WIDE, L>(sin, cos),
            Check::Position(_) => [0.0; L],
        }
    }
}

/// The lane part of [`verify_block`]: the tool poses of `L` candidates (`q[j][l]`, the first
/// `shared` joints shared by groups of `L / H` lanes when `shared > 0`,
/// [`Robot::fk_lanes_shared`]) and their errors against the target — position (metres) and
/// orientation (radians). Inlined, so that it is compiled for the SIMD level of the closed
/// form's kernel ([`SolveKernel`]); every level, and `WIDE` or not ([`Check::angles`]), gives
/// the same bits.
#[inline(always)]
pub(super) fn lane_errors<const WIDE: bool, const L: usize, const H: usize>(
    robot: &Robot,
    check: &Check,
    q: &[Lanes<L>],
    shared: usize,
) -> (Lanes<L>, Lanes<L>) {
    let t = if shared == 0 {
        robot.fk_lanes(q)
    } else {
        // Lane `g · L/H` of each shared joint (a loop: `array::from_fn` stayed an out-of-line
        // call here).
        let group = L / H;
        let shared = shared.min(LANE_DOF).min(q.len());
        let mut prefix = [[0.0; H]; LANE_DOF];
        for j in 0..shared {
            for g in 0..H {
                prefix[j][g] = q[j][g * group];
            }
        }
        robot.fk_lanes_shared(&prefix[..shared], q)
    };
    let (position, sin, cos) = check.errors(&t);
    (position, check.angles::<WIDE, L>(&sin, &cos))
}

/// A solver whose [`IkSolver::solve_into`](super::IkSolver::solve_into) runs as a
/// [`crate::simd::Kernel`] ([`SolveKernel`]): its lane work — the FK check of the candidates in
/// [`finish_into`], and the solver's own lanes — compiled for the SIMD level
/// [`crate::simd::run`] picks ([`solve_at`]).
pub(crate) trait LaneSolve {
    /// The solve (what `solve_into` does), with its hot inner functions inlined
    /// (`#[inline(always)]`). `WIDE`: whether its lane work is compiled for a level of four
    /// lanes or more, where the branch-free lane forms pay ([`crate::angle::atan2_each`]); the
    /// result is the same bit for bit.
    fn solve_lanes<const WIDE: bool>(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &crate::ik::IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError>;
}

/// [`LaneSolve::solve_lanes`] as a [`crate::simd::Kernel`].
pub(crate) struct SolveKernel<'a, S, const WIDE: bool> {
    pub solver: &'a S,
    pub robot: &'a Robot,
    pub target: &'a IkTarget,
    pub options: &'a crate::ik::IkOptions,
    pub out: &'a mut IkSolutions,
}

impl<S: LaneSolve, const WIDE: bool> crate::simd::Kernel for SolveKernel<'_, S, WIDE> {
    type Output = Result<(), IkError>;

    #[inline(always)]
    fn run(self) -> Result<(), IkError> {
        self.solver.solve_lanes::<WIDE>(self.robot, self.target, self.options, self.out)
    }
}

/// The solve of a closed form ([`LaneSolve`], its `solve_into`) at SIMD level `level`
/// ([`crate::simd::level`] in `solve_into`): at the baseline level (two lanes per instruction)
/// the scalar-per-lane kernel, run directly; above, the wide one through
/// [`crate::simd::run_at`]. Every level gives the same bits.
pub(crate) fn solve_at<S: LaneSolve>(
    level: crate::simd::Level,
    solver: &S,
    robot: &Robot,
    target: &IkTarget,
    options: &crate::ik::IkOptions,
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    use crate::simd::Kernel;
    if level == crate::simd::Level::Baseline {
        SolveKernel::<S, false> { solver, robot, target, options, out }.run()
    } else {
        crate::simd::run_at(level, SolveKernel::<S, true> { solver, robot, target, options, out })
    }
}

/// Verifies, normalises and de-duplicates candidates, and states the failure reason.
///
/// * revolute angles are wrapped (or moved by whole turns into the joint range);
/// * candidates whose FK misses the target by more than `IK_POSITION` / `IK_ORIENTATION`
///   are dropped (a closed form evaluated outside its domain);
/// * candidates equal within `IK_DUPLICATE` are merged (their singularity flags united);
/// * `if_empty` is the reason reported when no candidate survives; when some survive but all
///   violate limits the reason is [`IkFailure::OutsideLimits`].
///
/// Every candidate's tool pose is its full forward kinematics: for chains of up to
/// [`LANE_DOF`] joints, [`VERIFY_LANES`] candidates at a time through [`Robot::fk_lanes`] (each
/// lane [`Robot::fk_matrix`] of its candidate), longer chains one at a time through
/// [`Robot::fk_matrix`].
pub(crate) fn finish(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut [Candidate],
    solver: &'static str,
    if_empty: IkFailure,
) -> Result<IkSolutions, IkError> {
    solved(|out| finish_into::<false, _>(robot, target, candidates, solver, if_empty, out))
}

/// [`finish`] into a reused `out` (see [`finish_within_into`]), for any [`CandidateList`]: the
/// 6R closed forms' compact [`Raw6Set`] as well as [`Candidate`]s. `WIDE` as in
/// [`LaneSolve::solve_lanes`] (`false` outside a [`SolveKernel`]).
#[inline(always)]
pub(crate) fn finish_into<const WIDE: bool, C: CandidateList + ?Sized>(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut C,
    solver: &'static str,
    if_empty: IkFailure,
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    finish_within_into::<WIDE, C>(robot, target, candidates, solver, if_empty, (IK_POSITION, IK_ORIENTATION), out)
}

/// The result of a lean solve (`f`, an [`IkSolver::solve_into`](super::IkSolver::solve_into))
/// in a new [`IkSolutions`]: how the closed forms implement [`IkSolver::solve`](super::IkSolver::solve).
pub(crate) fn solved(f: impl FnOnce(&mut IkSolutions) -> Result<(), IkError>) -> Result<IkSolutions, IkError> {
    let mut out = IkSolutions::default();
    f(&mut out)?;
    Ok(out)
}

/// [`finish`] with the acceptance tolerances `(metres, radians)` given instead of
/// `IK_POSITION` / `IK_ORIENTATION` (the numeric solver's user-set tolerances).
pub(crate) fn finish_within(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut [Candidate],
    solver: &'static str,
    if_empty: IkFailure,
    tolerances: (f64, f64),
) -> Result<IkSolutions, IkError> {
    solved(|out| finish_within_into::<false, _>(robot, target, candidates, solver, if_empty, tolerances, out))
}

/// The revolute values of `q` fitted into their limits ([`fit_revolute`]), in place; `false`
/// (and `q` untouched) when a value is not finite (the candidate is dropped).
#[inline]
pub(super) fn normalise(robot: &Robot, q: &mut [f64]) -> bool {
    if q.iter().any(|v| !v.is_finite()) {
        return false;
    }
    for (v, joint) in q.iter_mut().zip(robot.joints()) {
        if joint.kind == JointKind::Revolute {
            *v = fit_revolute(*v, &joint.limits);
        }
    }
    true
}

/// [`finish_within`] writing into `out` ([`IkSolver::solve_into`](super::IkSolver::solve_into)):
/// `out`'s solutions are overwritten in place (their vectors cleared and refilled, keeping
/// their capacity), solutions beyond the new count are kept aside as spares and taken back
/// before any new one is made. The result equals [`finish_within`]'s whatever `out` held.
///
/// Inlined, as the lane kernel it calls, so that a closed form's [`SolveKernel`] compiles it
/// for its SIMD level (`WIDE` as in [`LaneSolve::solve_lanes`]).
#[inline(always)]
pub(crate) fn finish_within_into<const WIDE: bool, C: CandidateList + ?Sized>(
    robot: &Robot,
    target: &IkTarget,
    candidates: &mut C,
    solver: &'static str,
    if_empty: IkFailure,
    tolerances: (f64, f64),
    out: &mut IkSolutions,
) -> Result<(), IkError> {
    let check = Check::new(target);
    // The solutions of `out` are overwritten in order, then spares (taken back last first),
    // then new ones: the result does not depend on what `out` held, only the buffers are
    // reused.
    let mut kept = Kept { robot, tolerances, len: 0, block: 0, solutions: &mut out.solutions, spare: &mut out.spare.0 };
    let n = candidates.count();
    kept.solutions.reserve(n.saturating_sub(kept.solutions.len()));
    let dof = robot.dof();
    if dof <= LANE_DOF {
        // Blocks of 8, the rest in the narrowest block that holds it (one candidate of
        // `solve_branch` takes the one-lane kernel, not an eight-lane one).
        let mut start = 0;
        while start < n {
            start += match n - start {
                5.. => {
                    verify_block::<WIDE, VERIFY_LANES, { VERIFY_LANES / 2 }, C>(&mut kept, &check, candidates, start)?
                }
                3..=4 => verify_block::<WIDE, 4, 2, C>(&mut kept, &check, candidates, start)?,
                2 => verify_block::<WIDE, 2, 1, C>(&mut kept, &check, candidates, start)?,
                _ => verify_block::<WIDE, 1, 1, C>(&mut kept, &check, candidates, start)?,
            };
        }
    } else {
        for i in 0..n {
            if !normalise(robot, candidates.joints_mut(i)) {
                continue;
            }
            let t = robot.fk_matrix(candidates.joints(i))?;
            let m = t.rotation.matrix();
            let t = FrameLanes::<1> {
                r: std::array::from_fn(|r| std::array::from_fn(|c| [m[(r, c)]])),
                p: std::array::from_fn(|k| [t.translation.vector[k]]),
            };
            let (position, sin, cos) = check.errors(&t);
            kept.offer(candidates, i, position[0], check.angles::<false, 1>(&sin, &cos)[0], Screen::default());
        }
    }
    let len = kept.len;
    out.spare.0.extend(out.solutions.drain(len..).rev());
    let recycled = match out.failure.take() {
        Some(IkFailure::OutsideLimits { name, .. }) => Some(name),
        _ => None,
    };
    out.failure = if out.solutions.is_empty() { Some(if_empty) } else { limits_failure(&out.solutions, recycled) };
    out.solver = solver;
    out.differences.set_for_robot(robot);
    Ok(())
}

/// Verifies up to `L` candidates from `start` together ([`Robot::fk_lanes`], [`Check::errors`])
/// and offers each finite one to `kept`, in order; returns how many it took.
///
/// When consecutive pairs of candidates share their first joint values (the two wrist
/// solutions of each arm of a 6R closed form share θ1…θ3), the chain up to the last shared
/// joint is walked once per pair, on `H = L / 2` lanes ([`Robot::fk_lanes_shared`], bit for
/// bit the same poses); `H = L` walks every lane alone.
#[inline(always)]
pub(super) fn verify_block<const WIDE: bool, const L: usize, const H: usize, C: CandidateList + ?Sized>(
    kept: &mut Kept<'_>,
    check: &Check,
    candidates: &mut C,
    start: usize,
) -> Result<usize, IkError> {
    let (robot, dof) = (kept.robot, kept.robot.dof());
    let len = (candidates.count() - start).min(L);
    // Lanes of dropped candidates (and beyond `len`) compute the pose of zeros or of another
    // lane's values ([`shared_prefix`]), unused.
    let mut q = [[0.0; L]; LANE_DOF];
    let mut finite = [false; L];
    for l in 0..len {
        let v = candidates.joints_mut(start + l);
        if normalise(robot, v) {
            if v.len() != dof {
                check_q(dof, v)?;
            }
            finite[l] = true;
            for (lanes, x) in q.iter_mut().zip(v.iter()) {
                lanes[l] = *x;
            }
        }
    }
    let shared = shared_prefix::<L, H>(robot, &mut q[..dof], &finite, len);
    let (position, orientation) = lane_errors::<WIDE, L, H>(robot, check, &q[..dof], shared);
    let screens = screen::<L>(robot, &q[..dof]);
    kept.block = kept.len;
    for l in 0..len {
        if finite[l] {
            kept.offer(candidates, start + l, position[l], orientation[l], screens[l]);
        }
    }
    Ok(len)
}

/// What the lanes of one block prove about each candidate before it is offered to [`Kept`],
/// so that the usual case skips the per-joint loops. The default proves nothing.
#[derive(Clone, Copy, Default)]
pub(super) struct Screen {
    /// Every joint within its limits ([`Limits::contains`](crate::model::Limits::contains)
    /// with [`LIMIT_SLACK`], the test of the violation list): no violation to look for.
    within: bool,
    /// The last joint's value is [`surely_distinct`] from that of every earlier lane of the
    /// block: no solution kept from this block can be the same.
    distinct: bool,
}

/// The [`Screen`] of each lane of `q` (`q[j][l]`, `q.len()` joints ≥ 1). Lanes without a
/// verified candidate hold zeros or another lane's values (see [`shared_prefix`]); they can
/// only clear a later lane's `distinct`, so a screen never claims more than holds.
#[inline(always)]
pub(super) fn screen<const L: usize>(robot: &Robot, q: &[Lanes<L>]) -> [Screen; L] {
    let mut within = [true; L];
    for (joint, lanes) in robot.joints().iter().zip(q) {
        for l in 0..L {
            within[l] &= joint.limits.contains(lanes[l], LIMIT_SLACK);
        }
    }
    let last = &q[q.len() - 1];
    let mut distinct = [true; L];
    // Each lane against every other, masked to the earlier ones: whole vectors, no triangle.
    for (m, &earlier) in last.iter().enumerate() {
        for l in 0..L {
            distinct[l] &= (l <= m) | surely_distinct(last[l], earlier);
        }
    }
    let mut screens = [Screen::default(); L];
    for l in 0..L {
        screens[l] = Screen { within: within[l], distinct: distinct[l] };
    }
    screens
}

/// How many leading joints every group of `L / H` consecutive lanes of `q` (`q[j][l]`) shares,
/// bit for bit, when the chain up to them has no mimic joint (else 0, as for `H = L`). Lanes
/// not verified (beyond `len`, or not `finite`) take their group's first verified lane's values
/// first: their poses are not read, so they need not part a group.
pub(super) fn shared_prefix<const L: usize, const H: usize>(
    robot: &Robot,
    q: &mut [Lanes<L>],
    finite: &[bool; L],
    len: usize,
) -> usize {
    if H == L {
        return 0;
    }
    let group = L / H;
    for g in 0..H {
        let lanes = g * group..(g + 1) * group;
        let Some(first) = lanes.clone().find(|&l| l < len && finite[l]) else { continue };
        for l in lanes {
            if l >= len || !finite[l] {
                for joint in q.iter_mut() {
                    joint[l] = joint[first];
                }
            }
        }
    }
    let k = q.iter().take_while(|joint| (0..L).all(|l| joint[l].to_bits() == joint[l - l % group].to_bits())).count();
    if robot.prefix_without_mimics(k) { k } else { 0 }
}

/// The solutions a verification keeps, in order, with the buffers it reuses.
pub(super) struct Kept<'a> {
    robot: &'a Robot,
    tolerances: (f64, f64),
    /// Number of solutions kept so far: the first `len` of `solutions` (those beyond are
    /// buffers of an earlier solve, overwritten next).
    len: usize,
    /// Number of solutions kept before the current block of [`verify_block`]: a candidate
    /// screened [`Screen::distinct`] is compared with these only (unused on the scalar path,
    /// whose candidates are never screened distinct).
    block: usize,
    solutions: &'a mut Vec<IkSolution>,
    spare: &'a mut Vec<IkSolution>,
}

impl Kept<'_> {
    /// Candidate `i` of `candidates` (normalised, its tool pose `position_error` metres and
    /// `orientation_error` radians away from the target, `screen` what its block proved):
    /// dropped when outside the tolerances, merged into an equal kept solution (flags
    /// united), else kept.
    fn offer<C: CandidateList + ?Sized>(
        &mut self,
        candidates: &mut C,
        i: usize,
        position_error: f64,
        orientation_error: f64,
        screen: Screen,
    ) {
        let (position_tolerance, orientation_tolerance) = self.tolerances;
        if position_error > position_tolerance || orientation_error > orientation_tolerance {
            return;
        }
        let robot = self.robot;
        let q = candidates.joints(i);
        let compared = if screen.distinct { self.block } else { self.len };
        if let Some(existing) = self.solutions[..compared].iter_mut().find(|s| same_q(robot, &s.q, q)) {
            for k in candidates.flags(i) {
                if !existing.singularities.contains(&k) {
                    existing.singularities.push(k);
                }
            }
            return;
        }
        if self.len == self.solutions.len() {
            self.solutions.push(self.spare.pop().unwrap_or_default());
        }
        let s = &mut self.solutions[self.len];
        self.len += 1;
        s.q.clear();
        s.q.extend_from_slice(q);
        s.position_error = position_error;
        s.orientation_error = orientation_error;
        s.violations.clear();
        let joints = if screen.within { &[][..] } else { robot.joints() };
        for (i, (j, v)) in joints.iter().zip(q).enumerate() {
            if !j.limits.contains(*v, LIMIT_SLACK) {
                s.violations.push(LimitViolation {
                    joint: i + 1,
                    name: robot.joint_name(i).map_or_else(|| Arc::from(j.name.as_str()), Arc::clone),
                    value: *v,
                    lower: j.limits.lower,
                    upper: j.limits.upper,
                });
            }
        }
        s.within_limits = s.violations.is_empty();
        s.singularities.clear();
        s.singularities.extend(candidates.flags(i));
        candidates.take_label(i, &mut s.branch.0);
    }
}
