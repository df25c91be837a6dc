//! PUMA-type 6R arms with a spherical wrist: seed 002's geometric method (Khudoliy et al.,
//! notes 002 §3–4), corrected, generalised and extended to all 8 solutions.
//!
//! # The family
//!
//! Six revolute joints in a standard DH table with
//!
//! * a spherical wrist: a4 = a5 = a6 = 0 and d5 = 0 (axes 4, 5, 6 meet at the wrist centre,
//!   the origin of frames 4 and 5), α6 = 0 (the flange is d6 along the approach vector);
//! * α1 = ±90° (shoulder axis 2 perpendicular to the base axis 1), α2 = 0 (axes 2 and 3
//!   parallel), α3 = ±90°, α4 = ±90°, α5 = ±90°;
//! * a2 ≠ 0 and L2 = √(a3² + d4²) ≠ 0 (the elbow triangle of eqs. 10–16).
//!
//! d1, a1, d6, the joint offsets and flipped joints are free. The paper's formulas also need
//! d2 = d3 = 0 (notes 002 §2.2 item 4); this solver drops that condition and handles the
//! lateral (shoulder) offset `d = d2 + d3` of the classic PUMA 560 (`puma560`: d3 = 0.15005 m).
//! The α-sign conventions of notes 002 §4.3 are read from the table, so the paper's reference
//! table (α = 90, 0, −90, 90, −90, 0°), Corke's `puma560` and seed 001's `spbu6`
//! (α = −90, 0, −90, −90, 90, 0°) all fit; the UR5 (d5 ≠ 0, α3 = 0) does not.
//!
//! # The method (notes 002 §4.2, order θ1 → θ2 → θ3 → θ5 → θ4 → θ6)
//!
//! The target (base and tool removed with `chain_target`) gives n = x6, a = z6 and p.
//!
//! 1. Wrist centre `w = p − d6·a` (eq. 2).
//! 2. θ1 (eq. 4, generalised): in frame 1 the wrist centre has the out-of-plane coordinate
//!    `d = d2 + d3`, so its horizontal base coordinates are `Rz(θ1)·(h, −sgn(α1)·d)` with
//!    `h = ±√(wx² + wy² − d²)`: `θ1 = atan2(wy, wx) − atan2(−sgn(α1)·d, h)`, two shoulder
//!    solutions (for d = 0 the paper's `atan2(wy, wx)` and its back-shoulder twin θ1 + π).
//! 3. `P11 = A1⁻¹·w = (u, v, d)` (eq. 9), `R = √(u² + v²)` (eq. 12), `L2 = √(a3² + d4²)`
//!    (eq. 13), `β = atan2(u, v)` (eq. 7), `φ = acos((a2² + L2² − R²)/(2·a2·L2))` (eq. 16),
//!    `γ = acos((a2² + R² − L2²)/(2·a2·R))` (eq. 11; evaluated as
//!    `atan2(L2·sin φ, a2 − L2·cos φ)`, the same angle of the same triangle, which stays
//!    consistent with φ near the stretched elbow), `α = atan2(d4, a3)` (eq. 15 corrected).
//! 4. `θ2 = π/2 − β − s·γ`, `θ3 = s·(π − φ) + sgn(α3)·α` for s = ±1 (eqs. 5, 14 corrected and
//!    generalised, notes 002 §4.3).
//! 5. `T03 = A1·A2·A3`; `z4' = z3 × a` (eq. 26) has length |sin θ5| and
//!    `θ5 = atan2(±|z4'|, −sgn(α4)·sgn(α5)·(a·z3))` (eq. 22: `acos(a·z3)` for the paper's
//!    α5 = −α4, written with atan2 to stay accurate near 0 and π).
//! 6. `θ4 = atan2(g·(z4'·x3), g·(z4'·(−y3)))` with `g = −sgn(α5)·sgn(sin θ5)` (eqs. 23–25
//!    with the arguments in the corrected order; g = 1 for the paper's wrist).
//! 7. `T05 = T03·A4·A5`; `θ6 = atan2(n·y5, n·x5)` (eqs. 31–37 with x6 = n and the arguments
//!    in the corrected order).
//!
//! # Corrections of the paper (notes 002 §6)
//!
//! * eq. 15: denominator `2·a3·L2`, not `2·a2·L2` (item 1), i.e. `α = atan2(d4, a3)`;
//! * eq. 14: the second elbow branch is `−(π − φ + α)` (item 2, for α3 = −90°);
//! * eq. 23: `atan2(sq_x, sq_y)`, not `atan2(sq_y, sq_x)` (item 3);
//! * eq. 31: `atan2(cq_y, cq_x)`, not `atan2(cq_x, cq_y)` (item 4);
//! * eq. 34: `x6 = n6` (the normal), not the approach vector a6 (item 5).
//!
//! # Branches
//!
//! Up to 8 solutions: 2 shoulder × 2 elbow × 2 wrist, labelled
//!
//! * `shoulder`: with a lateral offset `right` / `left` — the arm plane lies to the right /
//!   left of the base axis, seen from +z0 looking from the base axis towards the wrist centre
//!   (`sgn(α1)·d·h > 0` is right); without one `front` (h > 0: the upper arm reaches towards
//!   the wrist centre) / `back` (reaching over backwards, θ1 + π);
//! * `elbow`: `up` / `down` — the elbow (the joint-3 axis) above / below the line from the
//!   shoulder (joint-2 axis) to the wrist centre, in the vertical arm plane seen with the
//!   reach direction to the right;
//! * `wrist`: `noflip` (DH θ5 ∈ (0, π), the paper's `acos` branch) / `flip`
//!   (θ4 + π, −θ5, θ6 + π).
//!
//! The paper's elbow branch "A" (s = +1) is `elbow=down` for α1 = +90° (notes 002 §3).
//!
//! # Singularities (flags on the solutions)
//!
//! * **wrist**: |sin θ5| < [`IK_PARALLEL_SINE`] (axes 4 and 6 aligned): θ4 is kept from
//!   `options.seed` (else q4 = 0), θ6 absorbs the rest; one wrist solution per arm branch.
//! * **shoulder**: the wrist centre on the base axis (d = 0) or on the cylinder of radius |d|
//!   around it (h = 0), within [`IK_AXIS_DISTANCE`]: the two shoulder roots merge; for d = 0,
//!   θ1 is undetermined and kept from the seed (else q1 = 0).
//! * **elbow**: `|cos φ|` within [`BOUNDARY`] of 1 (arm stretched or folded): the elbow
//!   branches merge. When the wrist centre lies on axis 2 (R = 0, only if a2 = L2), θ2 is
//!   undetermined and kept from the seed.
//!
//! # Failure reasons
//!
//! * `wx² + wy² < d²`: `Unreachable { distance: √(wx² + wy²), reach: |d| }` (inside the
//!   cylinder the offset arm plane cannot enter);
//! * R outside `[||a2| − L2|, |a2| + L2]` on every shoulder branch:
//!   `Unreachable { distance: R, reach: the violated bound }`.
//!
//! # Position-only targets
//!
//! The tool orientation of `options.seed` (else of the home configuration) is kept and that
//! pose is solved.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{Isometry3, IsometryMatrix3, Matrix3, Point3, Translation3, Vector3};

use smallvec::SmallVec;

use super::{
    Branch, ChainFrame, FlagBits, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, LaneSolve, Raw6,
    Raw6Set, SingularityKind, finish_into, solve_at, solved,
};
use crate::angle::{atan2_each, sin_cos, sin_cos_lanes, wrap};
use crate::kinematics::{FrameLanes, Lanes, check_q};
use crate::model::fk_chain::DhStep;
use crate::model::{Convention, JointKind, Robot};
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, IK_PARALLEL_SINE, STRUCTURE_ANGLE, STRUCTURE_LENGTH};

const NAME: &str = "spherical-wrist";

// ---------------------------------------------------------------------------------------------
// Shared with `two_link_wrist` (seed 001's arm is the special case a3 = d2 = d3 = 0 of this
// family): DH joint data, structure checks, the seed and the chain-frame target.
// ---------------------------------------------------------------------------------------------

/// One revolute standard-DH joint as the closed forms use it: `θ = sign·q + offset`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DhJoint {
    pub a: f64,
    pub alpha: f64,
    pub d: f64,
    pub offset: f64,
    /// −1 for a flipped joint.
    pub sign: f64,
    /// sin α and cos α, computed once.
    pub sin_cos_alpha: (f64, f64),
}

impl DhJoint {
    /// The DH angle θ of joint value `q`.
    #[inline]
    pub fn theta(&self, q: f64) -> f64 {
        self.sign * q + self.offset
    }

    /// The joint value `q` of DH angle `theta`.
    #[inline]
    pub fn q(&self, theta: f64) -> f64 {
        self.sign * (theta - self.offset)
    }

    /// `A = Rz(θ)·Tz(d)·Tx(a)·Rx(α)` (the solvers use its rotation, [`DhJoint::rotation`]).
    #[cfg(test)]
    pub fn transform(&self, theta: f64) -> IsometryMatrix3<f64> {
        let (st, ct) = sin_cos(theta);
        IsometryMatrix3::from_parts(
            Translation3::new(self.a * ct, self.a * st, self.d),
            nalgebra::Rotation3::from_matrix_unchecked(self.rotation((st, ct))),
        )
    }

    /// The rotation `Rz(θ)·Rx(α)` of `A`, from `(sin θ, cos θ)` (computed once where the
    /// solver knows them).
    #[inline]
    pub fn rotation(&self, (st, ct): (f64, f64)) -> Matrix3<f64> {
        let (sa, ca) = self.sin_cos_alpha;
        #[rustfmt::skip]
        let r = Matrix3::new(
            ct, -st * ca, st * sa,
            st, ct * ca, -ct * sa,
            0.0, sa, ca,
        );
        r
    }
}

/// The `Unsupported` error of `solver` for `robot`.
pub(crate) fn unsupported(solver: &'static str, robot: &Robot, reason: String) -> IkError {
    IkError::Unsupported { solver, robot: robot.name().to_string(), reason }
}

/// The DH table a closed form of 6R arms reads: six revolute joints and where their chain
/// sits relative to the robot's base and tool.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Dh6 {
    pub joints: [DhJoint; 6],
    pub frame: ChainFrame,
}

impl Dh6 {
    /// `error` (a structure condition that failed on this table) with a note that the table is
    /// the standard-DH equivalent when the robot is not described in standard DH.
    pub fn explain(&self, error: IkError) -> IkError {
        match error {
            IkError::Unsupported { solver, robot, reason } if !self.frame.is_own() => IkError::Unsupported {
                solver,
                robot,
                reason: format!("{reason} (in the standard-DH equivalent derived from the joint axes)"),
            },
            other => other,
        }
    }
}

/// The six joints of a 6R robot as a standard-DH table, or why the robot is not one: a robot
/// described in standard DH gives its own table; any other its standard-DH equivalent derived
/// from the joint axes ([`Robot::dh_equivalent`], with the robot's own joint values: flipped
/// joints and θ offsets), whose base and tool relative to the robot's are in the returned
/// [`ChainFrame`].
pub(crate) fn revolute_dh6(robot: &Robot, solver: &'static str) -> Result<Dh6, IkError> {
    if robot.dof() != 6 {
        return Err(unsupported(solver, robot, format!("needs 6 joints, the robot has {}", robot.dof())));
    }
    let derived;
    let (table, frame) = if robot.convention() == Convention::Dh {
        (robot, ChainFrame::default())
    } else {
        derived = robot.dh_equivalent_and_gap().map_err(|e| {
            unsupported(solver, robot, format!("the robot is described in `{}` and {e}", robot.convention().as_str()))
        })?;
        (&derived.0, ChainFrame::between(robot, &derived.0, derived.1))
    };
    let mut out = [DhJoint { a: 0.0, alpha: 0.0, d: 0.0, offset: 0.0, sign: 1.0, sin_cos_alpha: (0.0, 1.0) }; 6];
    for (i, (joint, slot)) in table.joints().iter().zip(out.iter_mut()).enumerate() {
        if joint.kind != JointKind::Revolute {
            return Err(unsupported(solver, robot, format!("joint {} ({}) is not revolute", i + 1, joint.name)));
        }
        let Some(p) = joint.dh() else {
            return Err(unsupported(solver, robot, format!("joint {} ({}) has no DH parameters", i + 1, joint.name)));
        };
        *slot = DhJoint {
            a: p.a,
            alpha: p.alpha,
            sin_cos_alpha: p.alpha.sin_cos(),
            d: p.d,
            offset: p.theta_offset,
            sign: if joint.flip { -1.0 } else { 1.0 },
        };
    }
    Ok(Dh6 { joints: out, frame })
}

/// Checks that axes 4, 5 and 6 meet in one point: a4 = d5 = a5 = a6 = 0.
pub(crate) fn require_spherical_wrist(
    robot: &Robot,
    solver: &'static str,
    joints: &[DhJoint; 6],
) -> Result<(), IkError> {
    for (name, value) in [("a4", joints[3].a), ("d5", joints[4].d), ("a5", joints[4].a), ("a6", joints[5].a)] {
        if !is_zero_length(value) {
            return Err(unsupported(
                solver,
                robot,
                format!("{name} = {value} m ≠ 0: axes 4, 5 and 6 do not meet in one point (not a spherical wrist)"),
            ));
        }
    }
    Ok(())
}

/// The twist signs `[sgn α1, sgn α3, sgn α4, sgn α5]` of a 6R arm with a spherical wrist whose
/// twists are α1, α3, α4, α5 = ±90° and α2 = α6 = 0 (the families of [`SphericalWrist`] and
/// [`TwoLinkWrist`](super::two_link_wrist::TwoLinkWrist)), or the `Unsupported` error naming
/// the first twist that differs. `why1` and `why3` say what α1 and α3 = ±90° mean for `solver`.
pub(crate) fn wrist_arm_twists(
    robot: &Robot,
    solver: &'static str,
    joints: &[DhJoint; 6],
    (why1, why3): (&str, &str),
) -> Result<[f64; 4], IkError> {
    let deg = |i: usize| joints[i].alpha.to_degrees();
    let pm90 = |i: usize, why: &str| -> Result<f64, IkError> {
        quarter_turn(joints[i].alpha)
            .ok_or_else(|| unsupported(solver, robot, format!("α{} = {:.6}° (needs ±90°: {why})", i + 1, deg(i))))
    };
    let zero = |i: usize, why: &str| -> Result<(), IkError> {
        if is_zero_angle(joints[i].alpha) {
            Ok(())
        } else {
            Err(unsupported(solver, robot, format!("α{} = {:.6}° (needs 0°: {why})", i + 1, deg(i))))
        }
    };
    let s1 = pm90(0, why1)?;
    zero(1, "axes 2 and 3 parallel")?;
    let s3 = pm90(2, why3)?;
    let s4 = pm90(3, "axis 5 perpendicular to axis 4")?;
    let s5 = pm90(4, "axis 6 perpendicular to axis 5")?;
    zero(5, "the flange on the approach axis")?;
    Ok([s1, s3, s4, s5])
}

/// `sgn(α)` when α = ±90° (within [`STRUCTURE_ANGLE`]).
pub(crate) fn quarter_turn(alpha: f64) -> Option<f64> {
    if wrap(alpha - FRAC_PI_2).abs() <= STRUCTURE_ANGLE {
        Some(1.0)
    } else if wrap(alpha + FRAC_PI_2).abs() <= STRUCTURE_ANGLE {
        Some(-1.0)
    } else {
        None
    }
}

/// Whether α = 0 (within [`STRUCTURE_ANGLE`]).
pub(crate) fn is_zero_angle(alpha: f64) -> bool {
    wrap(alpha).abs() <= STRUCTURE_ANGLE
}

/// Whether a DH length is zero (within [`STRUCTURE_LENGTH`]).
pub(crate) fn is_zero_length(value: f64) -> bool {
    value.abs() <= STRUCTURE_LENGTH
}

/// The seed of `options` as DH angles, checked (length, finiteness).
pub(crate) fn seed_thetas(joints: &[DhJoint; 6], options: &IkOptions) -> Result<Option<[f64; 6]>, IkError> {
    let Some(seed) = options.seed.as_deref() else {
        return Ok(None);
    };
    check_q(6, seed)?;
    let mut out = [0.0; 6];
    for ((t, j), &q) in out.iter_mut().zip(joints).zip(seed) {
        *t = j.theta(q);
    }
    Ok(Some(out))
}

/// The DH angle of joint `i` to use where it is undetermined: the seed's, else that of q = 0.
pub(crate) fn free_theta(joints: &[DhJoint; 6], seed: Option<&[f64; 6]>, i: usize) -> f64 {
    seed.map_or(joints[i].offset, |s| s[i])
}

/// The flange pose to solve, in the chain frame: the pose target with base and tool removed
/// (and the DH chain's own base and tool, `frame`);
/// for a position target, the tool orientation of the seed (else of the home configuration)
/// at the target position.
pub(crate) fn flange_goal(
    robot: &Robot,
    frame: &ChainFrame,
    target: &IkTarget,
    options: &IkOptions,
) -> Result<IsometryMatrix3<f64>, IkError> {
    let pose = match target {
        IkTarget::Pose(pose) => *pose,
        IkTarget::Position(p) => {
            let q = options.seed.clone().unwrap_or_else(|| robot.home());
            let current = robot.fk(&q)?;
            Isometry3::from_parts(Translation3::from(p.coords), current.rotation)
        }
    };
    let t = frame.target(robot, &pose);
    Ok(IsometryMatrix3::from_parts(t.translation, t.rotation.to_rotation_matrix()))
}

/// The wrist centre `p − d6·a` of a flange pose (seed 002 eq. 2).
pub(crate) fn wrist_centre(flange: &IsometryMatrix3<f64>, d6: f64) -> Point3<f64> {
    let a = flange.rotation.matrix().column(2).into_owned();
    Point3::from(flange.translation.vector - a * d6)
}

/// The elbow label of an arm solution (see the module docs).
///
/// `(u, v)` is the wrist centre and `e` the elbow (joint-3 axis) in the x1–y1 plane of frame 1,
/// both relative to the joint-2 axis; y1 = sgn(α1)·z0 is "up" and the reach direction is
/// `sgn(h)·x1`.
pub(crate) fn elbow_label(s_alpha1: f64, h: f64, u: f64, v: f64, e: (f64, f64)) -> &'static str {
    let forward = if h < 0.0 { -1.0 } else { 1.0 };
    if forward * s_alpha1 * (u * e.1 - v * e.0) > 0.0 { "up" } else { "down" }
}

/// `noflip` when DH θ5 ∈ [0, π], else `flip`.
pub(crate) fn wrist_label(theta5: f64) -> &'static str {
    if sin_cos(theta5).0 >= 0.0 { "noflip" } else { "flip" }
}

/// `θ + π` wrapped into (−π, π] for θ in (−π, π] (the flipped wrist's θ4 and θ6), without the
/// remainder of [`wrap`].
#[inline]
pub(crate) fn half_turn(theta: f64) -> f64 {
    if theta > 0.0 { theta - PI } else { theta + PI }
}

/// The user's joint values of DH angles.
pub(crate) fn joint_values(joints: &[DhJoint; 6], theta: &[f64; 6]) -> [f64; 6] {
    std::array::from_fn(|i| joints[i].q(theta[i]))
}

/// The keys of an arm-then-wrist closed form's branch labels.
pub(crate) const ARM_KEYS: [&str; 3] = ["shoulder", "elbow", "wrist"];

/// The arm solutions of one target: at most 2 shoulders × 2 elbows, on the stack.
pub(crate) type Arms = SmallVec<[Arm; 4]>;

/// The arm angles θ1…θ3 of one shoulder/elbow branch.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Arm {
    pub theta: [f64; 3],
    /// `(sin θi, cos θi)` of the three, as the arm solution computed them.
    pub sin_cos: [(f64, f64); 3],
    pub shoulder: &'static str,
    pub elbow: &'static str,
    pub shoulder_singular: bool,
    pub elbow_singular: bool,
}

impl Arm {
    /// `R03 = R1·R2·R3` of the arm's joints (`joints`: the DH table).
    pub fn r03(&self, joints: &[DhJoint; 6]) -> Matrix3<f64> {
        joints[0].rotation(self.sin_cos[0]) * joints[1].rotation(self.sin_cos[1]) * joints[2].rotation(self.sin_cos[2])
    }

    /// The singularity flags of the arm.
    pub fn flags(&self) -> FlagBits {
        FlagBits::default()
            .with(SingularityKind::Shoulder, self.shoulder_singular)
            .with(SingularityKind::Elbow, self.elbow_singular)
    }
}

/// The reason reported when every candidate fails the FK check. The closed form is exact, so
/// this only happens through round-off at a singular configuration the target sits on.
pub(crate) fn fallback_failure(arms: &[Arm]) -> IkFailure {
    let kind = if arms.iter().any(|a| a.elbow_singular) {
        SingularityKind::Elbow
    } else if arms.iter().any(|a| a.shoulder_singular) {
        SingularityKind::Shoulder
    } else {
        SingularityKind::Wrist
    };
    IkFailure::Singular { kind }
}

/// The one branch `branch` of an arm-then-wrist closed form ([`IkSolver::solve_branch`]):
/// the wrist solutions of the only arm labelled with the branch's shoulder and elbow,
/// restricted to its wrist label and verified by [`finish`].
///
/// This equals `solve(…).restricted_to(branch)` because [`finish`] can merge two candidates
/// only when all their joint values agree within `IK_DUPLICATE`: the two wrist solutions of
/// one arm differ by π in θ4, so a merge needs another arm with the same θ1…θ3. `None` (the
/// caller falls back to the full solve) when such an arm exists within twice that tolerance,
/// when no or several arms carry the labels, or when the branch has no verified solution.
pub(crate) fn arm_branch(
    robot: &Robot,
    frame: &ChainFrame,
    target: &IkTarget,
    branch: &Branch,
    solver: &'static str,
    arms: &[Arm],
    wrists: impl FnOnce(&Arm, &mut Raw6Set),
) -> Result<Option<IkSolutions>, IkError> {
    let (Some(shoulder), Some(elbow)) = (branch.get("shoulder"), branch.get("elbow")) else {
        return Ok(None);
    };
    let mut labelled = arms.iter().filter(|a| a.shoulder == shoulder && a.elbow == elbow);
    let (Some(arm), None) = (labelled.next(), labelled.next()) else {
        return Ok(None);
    };
    let close = |other: &Arm| {
        other.theta.iter().zip(&arm.theta).all(|(a, b)| wrap(a - b).abs() <= 2.0 * crate::tolerance::IK_DUPLICATE)
    };
    if arms.iter().any(|other| !std::ptr::eq(other, arm) && close(other)) {
        return Ok(None);
    }
    let mut candidates = Raw6Set::new(ARM_KEYS);
    wrists(arm, &mut candidates);
    candidates.retain_branch(branch);
    if candidates.is_empty() {
        return Ok(None);
    }
    frame.refine(robot, target, &mut candidates);
    let sols =
        solved(|out| finish_into::<false, _>(robot, target, &mut candidates, solver, fallback_failure(arms), out))?;
    Ok((!sols.solutions.is_empty()).then_some(sols))
}

// ---------------------------------------------------------------------------------------------

/// Closed-form IK for PUMA-type 6R arms with a spherical wrist (seed 002; see the module docs).
///
/// # Example
/// ```
/// use reach::ik::{IkOptions, IkSolver, IkTarget, spherical_wrist::SphericalWrist};
/// let puma = reach::model::presets::get("puma560").unwrap();
/// let solver = SphericalWrist::from_robot(&puma).unwrap();
/// let q = [0.3, 0.5, -0.4, 0.7, 0.9, -0.2];
/// let target = IkTarget::Pose(puma.fk(&q).unwrap());
/// let all = solver.solve(&puma, &target, &IkOptions::default()).unwrap();
/// assert_eq!(all.solutions.len(), 8);
/// assert!(all.solutions.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// ```
#[derive(Debug, Clone)]
pub struct SphericalWrist {
    joints: [DhJoint; 6],
    /// The DH chain relative to the robot's base and tool.
    frame: ChainFrame,
    /// sgn α1, sgn α3, sgn α4, sgn α5.
    s1: f64,
    s3: f64,
    s4: f64,
    s5: f64,
    /// Lateral offset d = d2 + d3 (out-of-plane coordinate of the wrist centre in frame 1).
    lateral: f64,
    /// L2 = √(a3² + d4²) (eq. 13).
    l2: f64,
    /// α = atan2(d4, a3) (eq. 15, corrected).
    alpha: f64,
}

impl SphericalWrist {
    /// Checks that `robot` belongs to the family of the module docs and extracts its parameters.
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition (convention, joint count or kind,
    /// non-spherical wrist, a twist that is not 0°/±90°, a2 = 0 or L2 = 0).
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let table = revolute_dh6(robot, NAME)?;
        Self::from_table(robot, &table).map_err(|e| table.explain(e))
    }

    fn from_table(robot: &Robot, table: &Dh6) -> Result<Self, IkError> {
        let joints = table.joints;
        let fail = |reason: String| Err(unsupported(NAME, robot, reason));
        require_spherical_wrist(robot, NAME, &joints)?;
        let [s1, s3, s4, s5] = wrist_arm_twists(
            robot,
            NAME,
            &joints,
            ("shoulder axis 2 perpendicular to the base axis 1", "wrist axis 4 perpendicular to the elbow axis 3"),
        )?;
        if is_zero_length(joints[1].a) {
            return fail("a2 = 0: no upper arm (the elbow triangle of eqs. 10–16 degenerates)".into());
        }
        let (a3, d4) = (joints[2].a, joints[3].d);
        let l2 = a3.hypot(d4);
        if is_zero_length(l2) {
            return fail("a3 = d4 = 0: no forearm (the wrist centre is on the elbow axis)".into());
        }
        Ok(SphericalWrist {
            joints,
            frame: table.frame,
            s1,
            s3,
            s4,
            s5,
            lateral: joints[1].d + joints[2].d,
            l2,
            alpha: d4.atan2(a3),
        })
    }

    /// The lateral (shoulder) offset d = d2 + d3, metres.
    #[must_use]
    pub fn lateral_offset(&self) -> f64 {
        self.lateral
    }

    /// The forearm length L2 = √(a3² + d4²) (eq. 13), metres.
    #[must_use]
    pub fn forearm(&self) -> f64 {
        self.l2
    }

    /// The paper's constant α at joint 3 between x3 and the forearm line, radians:
    /// `acos((a3² + L2² − d4²)/(2·a3·L2)) = atan2(d4, a3)` (eq. 15 with the corrected
    /// denominator `2·a3·L2`, notes 002 §6 item 1; the printed `2·a2·L2` is wrong).
    #[must_use]
    pub fn elbow_alpha(&self) -> f64 {
        self.alpha
    }

    /// Every arm solution (θ1, θ2, θ3) for the wrist centre `w`, or why there is none.
    ///
    /// The two shoulders' and four arms' angles go through their `atan2` and sines and cosines
    /// together, in lanes ([`atan2_each`], [`sin_cos_lanes`]: bit for bit [`atan2`](crate::angle::atan2) and
    /// [`sin_cos`]).
    #[inline(always)]
    fn arms<const WIDE: bool>(&self, w: &Point3<f64>, seed: Option<&[f64; 6]>) -> Result<Arms, IkFailure> {
        let [j1, j2, ..] = &self.joints;
        let d = self.lateral;
        let rho2 = w.x * w.x + w.y * w.y;
        let mut h2 = rho2 - d * d;
        if h2 < 0.0 {
            if h2 < -BOUNDARY * d * d {
                return Err(IkFailure::Unreachable {
                    distance: rho2.sqrt(),
                    reach: d.abs(),
                    point: "the wrist centre",
                    from: "joint 1's axis",
                });
            }
            h2 = 0.0;
        }
        let h = h2.sqrt();
        let shoulder_singular = h < IK_AXIS_DISTANCE;
        let (sides, roots) = if shoulder_singular { (1, [0.0, 0.0]) } else { (2, [1.0, -1.0]) };
        let hs = roots.map(|side| side * h);
        let (a2, l2) = (j2.a, self.l2);
        // θ1 (eq. 4, generalised to the lateral offset d) of both shoulders: the azimuth of the
        // wrist centre less the offset's angle. With d = 0 on the base axis the angle is
        // undetermined: keep the seed's.
        let [azimuth, offset0, offset1] =
            atan2_each::<WIDE, 3>(&[w.y, -self.s1 * d, -self.s1 * d], &[w.x, hs[0], hs[1]]);
        let theta1 = if shoulder_singular && is_zero_length(d) {
            [free_theta(&self.joints, seed, 0); 2]
        } else {
            [azimuth - offset0, azimuth - offset1]
        };
        let (sin1, cos1) = sin_cos_lanes(&theta1);
        // Per shoulder: the elbow triangle, or the failure of an unreachable one.
        let mut failure = None;
        let mut reachable = [false; 2];
        let (mut u, mut v, mut phi, mut cos_phi, mut r) = ([0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
        for i in 0..sides {
            // P11 = A1⁻¹·P_m (eq. 9): (u, v) in the arm plane, the third component is d.
            let (s1, c1) = (sin1[i], cos1[i]);
            let p11 = j1.rotation((s1, c1)).tr_mul(&(w.coords - Vector3::new(j1.a * c1, j1.a * s1, j1.d)));
            (u[i], v[i]) = (p11.x, p11.y);
            r[i] = (u[i] * u[i] + v[i] * v[i]).sqrt(); // |T̄24| (eq. 12)
            // cos φ (eq. 16): |cos φ| ≤ 1 ⇔ ||a2| − L2| ≤ R ≤ |a2| + L2.
            cos_phi[i] = (a2 * a2 + l2 * l2 - r[i] * r[i]) / (2.0 * a2 * l2);
            if cos_phi[i].abs() > 1.0 + BOUNDARY {
                let outer = a2.abs() + l2;
                let reach = if r[i] > outer { outer } else { (a2.abs() - l2).abs() };
                failure.get_or_insert(IkFailure::Unreachable {
                    distance: r[i],
                    reach,
                    point: "the wrist centre",
                    from: "joint 2",
                });
                continue;
            }
            reachable[i] = true;
            phi[i] = cos_phi[i].clamp(-1.0, 1.0).acos();
        }
        // β (eq. 7, x first) and γ (eq. 11) of both shoulders. γ is taken from the same
        // triangle as φ — cos γ = (a2 − L2·cos φ)/R = (a2² + R² − L2²)/(2·a2·R),
        // sin γ = L2·sin φ/R — so that the two angles stay consistent near the stretched or
        // folded elbow, where two independent `acos` disagree by ~1e-8 rad (√ of the round-off).
        let (sin_phi, cos_phi_of) = sin_cos_lanes(&phi);
        let [beta0, gamma0, beta1, gamma1] = atan2_each::<WIDE, 4>(
            &[u[0], l2 * sin_phi[0], u[1], l2 * sin_phi[1]],
            &[v[0], a2 - l2 * cos_phi_of[0], v[1], a2 - l2 * cos_phi_of[1]],
        );
        // θ2 and θ3 of the (up to) four arms, shoulder by shoulder, the triangle root s = +1
        // first: eq. 5 and eq. 14 with the corrected branch B `−(π − φ + α)` and the α3-sign
        // generalisation (notes 002 §4.3, §6 item 2).
        let mut theta23 = [0.0; 8];
        let mut count = 0;
        for i in (0..sides).filter(|&i| reachable[i]) {
            let (beta, gamma) = if r[i] > IK_AXIS_DISTANCE {
                if i == 0 { (beta0, gamma0) } else { (beta1, gamma1) }
            } else {
                // Wrist centre on axis 2 (a2 = L2, folded): θ2 undetermined, keep the seed's.
                (FRAC_PI_2 - free_theta(&self.joints, seed, 1), 0.0)
            };
            for s in [1.0, -1.0] {
                theta23[count] = wrap(FRAC_PI_2 - beta - s * gamma);
                theta23[4 + count] = wrap(s * (PI - phi[i]) + self.s3 * self.alpha);
                count += 1;
            }
        }
        let (sin23, cos23) = sin_cos_lanes(&theta23);
        let mut arms = Arms::new();
        for i in (0..sides).filter(|&i| reachable[i]) {
            let elbow_singular = 1.0 - cos_phi[i].abs() <= BOUNDARY || r[i] <= IK_AXIS_DISTANCE;
            let shoulder = if is_zero_length(d) {
                if hs[i] < 0.0 { "back" } else { "front" }
            } else if self.s1 * d * hs[i] >= 0.0 {
                "right"
            } else {
                "left"
            };
            for _ in 0..2 {
                let k = arms.len();
                let (s2, c2) = (sin23[k], cos23[k]);
                let e = (a2 * c2, a2 * s2);
                arms.push(Arm {
                    theta: [theta1[i], theta23[k], theta23[4 + k]],
                    sin_cos: [(sin1[i], cos1[i]), (s2, c2), (sin23[4 + k], cos23[4 + k])],
                    shoulder,
                    elbow: elbow_label(self.s1, hs[i], u[i], v[i], e),
                    shoulder_singular,
                    elbow_singular,
                });
            }
        }
        if arms.is_empty() {
            return Err(failure.unwrap_or(IkFailure::Unreachable {
                distance: 0.0,
                reach: 0.0,
                point: "the wrist centre",
                from: "joint 2",
            }));
        }
        Ok(arms)
    }

    /// The wrists of up to [`ARMS`] arm branches up to their three `atan2` (θ5, θ4, θ6) each,
    /// in lanes (lane `k`: arm `k`; lanes beyond `arms` repeat arm 0, unused): the arguments
    /// `(y, x)` of the twelve `atan2` in groups of [`ARMS`] lanes — θ5's, θ4's, θ6's — and per
    /// arm at a wrist singularity its `(θ4, θ5)` ([`WristLanes`]). The caller evaluates the `atan2` for all arms
    /// at once ([`atan2_each`]) and hands them to [`SphericalWrist::push_wrists`].
    ///
    /// `R03 = R1·R2·R3` as the forward kinematics' lanes build a chain
    /// ([`FrameLanes::rotate_z`], [`FrameLanes::mul_dh`]); `z4' = z3 × a` (eq. 26) has the length
    /// sin θ5 and θ5 ∈ (0, π) (the `acos` branch) has `cos θ5 = −sgn(α4)·sgn(α5)·(a·z3)`
    /// (eq. 22, generalised sign); eq. 23 with the arguments in the corrected order (notes 002
    /// §6 item 3), generalised to the α4/α5 signs: `θ4 = atan2(g·(z4'·x3), −g·(z4'·y3))`,
    /// g = −sgn(α5). The arguments of both are the sines and cosines (θ5: |z3 × a|² + (a·z3)² = 1;
    /// θ4: z4' ⊥ z3 has the length sin θ5 in the x3–y3 plane), normalised for θ6: `(n·y5, n·x5)`
    /// (eqs. 31–37, corrected: x6 = n, arguments swapped), the first two components of
    /// `R05ᵀ·n = R5ᵀ·R4ᵀ·R03ᵀ·n` — matrix-vector products instead of the matrix products of
    /// `T05`. At a wrist singularity (sin θ5 < [`IK_PARALLEL_SINE`]) θ4 is kept from the seed,
    /// θ5 is 0 or π and θ6 takes the rest (only θ6's arguments are used; θ5's and θ4's are
    /// placeholders).
    #[inline(always)]
    fn wrist_lanes(&self, arms: &[Arm], flange: &IsometryMatrix3<f64>, seed: Option<&[f64; 6]>) -> WristLanes {
        debug_assert!(!arms.is_empty() && arms.len() <= ARMS);
        let arm = |k: usize| if k < arms.len() { &arms[k] } else { &arms[0] };
        let mut r03 = FrameLanes::<ARMS>::splat(&IsometryMatrix3::identity());
        for (i, joint) in self.joints[..3].iter().enumerate() {
            let s: Lanes<ARMS> = std::array::from_fn(|k| arm(k).sin_cos[i].0);
            let c: Lanes<ARMS> = std::array::from_fn(|k| arm(k).sin_cos[i].1);
            r03.rotate_z(&s, &c);
            let (sin_alpha, cos_alpha) = joint.sin_cos_alpha;
            r03.mul_dh(&DhStep { a: 0.0, d: 0.0, cos_alpha, sin_alpha });
        }
        let m = &r03.r;
        let r = flange.rotation.matrix();
        let (n, a) = (r.column(0), r.column(2));
        let (g, sign5) = (-self.s5, -self.s4 * self.s5);
        let (mut y, mut x) = ([1.0; 3 * ARMS], [1.0; 3 * ARMS]);
        let (mut sc4, mut sc5) = (([0.0; ARMS], [0.0; ARMS]), ([0.0; ARMS], [0.0; ARMS]));
        let mut singular = false;
        for k in 0..ARMS {
            let (x3, y3, z3) = (
                [m[0][0][k], m[1][0][k], m[2][0][k]],
                [m[0][1][k], m[1][1][k], m[2][1][k]],
                [m[0][2][k], m[1][2][k], m[2][2][k]],
            );
            // eq. 26: sin θ5 times the joint-5 axis (up to sign)
            let z4 = [z3[1] * a[2] - z3[2] * a[1], z3[2] * a[0] - z3[0] * a[2], z3[0] * a[1] - z3[1] * a[0]];
            let sin5 = (z4[0] * z4[0] + z4[1] * z4[1] + z4[2] * z4[2]).sqrt();
            let cos5 = sign5 * (a[0] * z3[0] + a[1] * z3[1] + a[2] * z3[2]);
            let dot = |u: [f64; 3], v: [f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
            let (y4, x4) = (g * dot(z4, x3), -g * dot(z4, y3)); // eqs. 23–25
            let norm4 = (x4 * x4 + y4 * y4).sqrt();
            (y[k], x[k]) = (sin5, cos5);
            (y[ARMS + k], x[ARMS + k]) = (y4, x4);
            (sc4.0[k], sc4.1[k]) = (y4 / norm4, x4 / norm4);
            (sc5.0[k], sc5.1[k]) = (sin5, cos5);
            singular |= sin5 < IK_PARALLEL_SINE;
        }
        let mut singular_wrists = [None; ARMS];
        if singular {
            for k in 0..ARMS {
                if y[k] < IK_PARALLEL_SINE {
                    let (theta5, cos5) = if x[k] >= 0.0 { (0.0, 1.0) } else { (PI, -1.0) };
                    let theta4 = free_theta(&self.joints, seed, 3);
                    singular_wrists[k] = Some((theta4, theta5));
                    (sc4.0[k], sc4.1[k]) = sin_cos(theta4);
                    (sc5.0[k], sc5.1[k]) = (0.0, cos5);
                    (y[k], x[k], y[ARMS + k], x[ARMS + k]) = (1.0, 1.0, 1.0, 1.0);
                }
            }
        }
        // θ6's arguments: R03ᵀ·n, then (Rz(θ4)·Rx(α4))ᵀ, then (Rz(θ5)·Rx(α5))ᵀ (x and y only).
        let (sa4, ca4) = self.joints[3].sin_cos_alpha;
        let (sa5, ca5) = self.joints[4].sin_cos_alpha;
        for k in 0..ARMS {
            let v: [f64; 3] = std::array::from_fn(|j| m[0][j][k] * n[0] + m[1][j][k] * n[1] + m[2][j][k] * n[2]);
            let (s4, c4) = (sc4.0[k], sc4.1[k]);
            let w = [c4 * v[0] + s4 * v[1], c4 * v[1] - s4 * v[0], v[2]];
            let v = [w[0], ca4 * w[1] + sa4 * w[2], ca4 * w[2] - sa4 * w[1]];
            let (s5, c5) = (sc5.0[k], sc5.1[k]);
            let w = [c5 * v[0] + s5 * v[1], c5 * v[1] - s5 * v[0], v[2]];
            (y[2 * ARMS + k], x[2 * ARMS + k]) = (ca5 * w[1] + sa5 * w[2], w[0]);
        }
        WristLanes { y, x, singular: singular_wrists }
    }

    /// The wrist solutions of one arm branch (only the one labelled `wrist` when given) from its
    /// angles `[θ5, θ4, θ6]` ([`SphericalWrist::wrist_lanes`]' arguments' `atan2`; at a wrist
    /// singularity θ4 and θ5 are `singular`'s), appended to `out`. The flipped wrist is
    /// `(θ4 + π, −θ5, θ6 + π)` of the other (eqs. 22–37 with sin θ5 negated: both arguments of
    /// θ4's and of θ6's atan2 change sign), so θ4, θ5 and θ6 are computed once per arm. At a
    /// wrist singularity, one solution (`noflip`).
    fn push_wrists(
        &self,
        arm: &Arm,
        singular: Option<(f64, f64)>,
        angles: [f64; 3],
        wrist: Option<&str>,
        out: &mut Raw6Set,
    ) {
        let wanted = |label: &str| wrist.is_none_or(|w| w == label);
        let [t1, t2, t3] = arm.theta;
        let push = |out: &mut Raw6Set, theta: [f64; 6], label: &'static str, wrist_singular: bool| {
            let flags = arm.flags().with(SingularityKind::Wrist, wrist_singular);
            out.push(Raw6 { q: joint_values(&self.joints, &theta), values: [arm.shoulder, arm.elbow, label], flags });
        };
        let [theta5, theta4, theta6] = angles;
        if let Some((theta4, theta5)) = singular {
            if wanted("noflip") {
                push(out, [t1, t2, t3, theta4, theta5, theta6], "noflip", true);
            }
            return;
        }
        for (label, theta) in [
            ("noflip", [t1, t2, t3, theta4, theta5, theta6]),
            ("flip", [t1, t2, t3, half_turn(theta4), -theta5, half_turn(theta6)]),
        ] {
            if wanted(label) {
                push(out, theta, label, false);
            }
        }
    }

    /// The wrist solutions of every arm branch (only those labelled `wrist` when given),
    /// appended to `out` in the order of `arms`: up to four arms' wrists in lanes
    /// ([`SphericalWrist::wrist_lanes`]), their twelve `atan2` in lanes ([`atan2_each`]:
    /// together when `WIDE`, bit for bit [`atan2`](crate::angle::atan2) either way), then the solutions.
    #[inline(always)]
    fn wrists<const WIDE: bool>(
        &self,
        arms: &[Arm],
        flange: &IsometryMatrix3<f64>,
        seed: Option<&[f64; 6]>,
        wrist: Option<&str>,
        out: &mut Raw6Set,
    ) {
        for group in arms.chunks(ARMS) {
            let WristLanes { y, x, singular } = self.wrist_lanes(group, flange, seed);
            let angles = atan2_each::<WIDE, { 3 * ARMS }>(&y, &x);
            for (k, arm) in group.iter().enumerate() {
                let arm_angles = [angles[k], angles[ARMS + k], angles[2 * ARMS + k]];
                self.push_wrists(arm, singular[k], arm_angles, wrist, out);
            }
        }
    }
}

/// Arm branches whose wrists are solved together in lanes ([`SphericalWrist::wrist_lanes`]):
/// all four of a solve.
const ARMS: usize = 4;

/// The wrists of [`ARMS`] arm branches before their angles ([`SphericalWrist::wrist_lanes`]).
struct WristLanes {
    /// `(y, x)` of the `atan2` of θ5 (lanes `0..ARMS`), θ4 (`ARMS..2·ARMS`) and θ6.
    y: [f64; 3 * ARMS],
    x: [f64; 3 * ARMS],
    /// Per arm at a wrist singularity: θ4 (the seed's) and θ5 (0 or π).
    singular: [Option<(f64, f64)>; ARMS],
}

impl LaneSolve for SphericalWrist {
    #[inline(always)]
    fn solve_lanes<const WIDE: bool>(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError> {
        target.validate()?;
        let seed = seed_thetas(&self.joints, options)?;
        let flange = flange_goal(robot, &self.frame, target, options)?;
        let w = wrist_centre(&flange, self.joints[5].d);
        let arms = match self.arms::<WIDE>(&w, seed.as_ref()) {
            Ok(arms) => arms,
            Err(failure) => {
                return finish_into::<WIDE, _>(robot, target, &mut Raw6Set::new(ARM_KEYS), NAME, failure, out);
            }
        };
        let mut candidates = Raw6Set::new(ARM_KEYS);
        self.wrists::<WIDE>(&arms, &flange, seed.as_ref(), None, &mut candidates);
        self.frame.refine(robot, target, &mut candidates);
        finish_into::<WIDE, _>(robot, target, &mut candidates, NAME, fallback_failure(&arms), out)
    }
}

impl IkSolver for SphericalWrist {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
        solved(|out| self.solve_into(robot, target, options, out))
    }

    fn solve_into(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError> {
        solve_at(crate::simd::level(), self, robot, target, options, out)
    }

    /// Only the requested branch's arm and wrist are computed and verified (see
    /// [`IkSolver::solve_branch`]); the full solve where branches may merge.
    fn solve_branch(
        &self,
        robot: &Robot,
        target: &IkTarget,
        branch: &Branch,
        options: &IkOptions,
    ) -> Result<IkSolutions, IkError> {
        target.validate()?;
        let seed = seed_thetas(&self.joints, options)?;
        let flange = flange_goal(robot, &self.frame, target, options)?;
        let w = wrist_centre(&flange, self.joints[5].d);
        if let Ok(arms) = self.arms::<false>(&w, seed.as_ref())
            && let Some(sols) = arm_branch(robot, &self.frame, target, branch, NAME, &arms, |arm, out| {
                self.wrists::<false>(std::slice::from_ref(arm), &flange, seed.as_ref(), branch.get("wrist"), out);
            })?
        {
            return Ok(sols);
        }
        Ok(self.solve(robot, target, options)?.restricted_to(branch))
    }

    /// The eight branches in the order [`IkSolver::solve`] returns them: the shoulder of the
    /// positive root of `h` first (`front` without a lateral offset `d`, else the side
    /// `sgn(α1)·d` points to, `right` when positive), then the other; per shoulder the elbow of
    /// the triangle root `s = +1` first (`up` when `sgn(h)·sgn(α1)·a2 < 0`), then the other;
    /// per elbow `noflip` (the `acos` branch) first.
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        let d = self.lateral;
        let shoulders = if is_zero_length(d) {
            ["front", "back"]
        } else if self.s1 * d >= 0.0 {
            ["right", "left"]
        } else {
            ["left", "right"]
        };
        let a2 = self.joints[1].a;
        arm_configurations(shoulders, [self.s1 * a2 < 0.0, -self.s1 * a2 < 0.0], true)
    }

    fn enumerates_all_branches(&self) -> bool {
        true
    }
}

/// The eight labels `shoulder × elbow × wrist` of a 6R arm with a spherical wrist, in the
/// order of its solve: per shoulder (in the order given) both elbows, `up` first where
/// `up_first` says so, and per elbow both wrists, `noflip` first when `noflip_first`.
pub(crate) fn arm_configurations(shoulders: [&'static str; 2], up_first: [bool; 2], noflip_first: bool) -> Vec<Branch> {
    let ordered = |first: bool, a: &'static str, b: &'static str| if first { [a, b] } else { [b, a] };
    let mut out = Vec::with_capacity(8);
    for (shoulder, up) in shoulders.into_iter().zip(up_first) {
        for elbow in ordered(up, "up", "down") {
            for wrist in ordered(noflip_first, "noflip", "flip") {
                out.push(Branch::new([("shoulder", shoulder), ("elbow", elbow), ("wrist", wrist)]));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ik::SolverKind;
    use crate::model::{Joint, RobotSpec, presets};

    /// Notes 002 §2.3: the paper's structure (no lateral offset) with PUMA lengths.
    fn reference() -> Robot {
        let r = |a: f64, alpha_deg: f64, d: f64| Joint::revolute(a, alpha_deg.to_radians(), d, 0.0);
        Robot::new(RobotSpec::new(
            "seed002-reference",
            Convention::Dh,
            vec![
                r(0.0, 90.0, 0.3),
                r(0.4318, 0.0, 0.0),
                r(0.0203, -90.0, 0.0),
                r(0.0, 90.0, 0.4318),
                r(0.0, -90.0, 0.0),
                r(0.0, 0.0, 0.05625),
            ],
        ))
        .unwrap()
    }

    #[test]
    fn corrected_eq15_alpha_is_atan2_d4_a3() {
        // Notes 002 §5: α = 87.308364° with the corrected denominator 2·a3·L2; the printed
        // 2·a2·L2 gives 89.873506°.
        let s = SphericalWrist::from_robot(&reference()).unwrap();
        assert!((s.elbow_alpha().to_degrees() - 87.308364).abs() < 1e-6);
        let (a2, a3, d4) = (0.4318_f64, 0.0203_f64, 0.4318_f64);
        let l2 = a3.hypot(d4);
        let by_cosines = ((a3 * a3 + l2 * l2 - d4 * d4) / (2.0 * a3 * l2)).acos();
        assert!((by_cosines - s.elbow_alpha()).abs() < 1e-12);
        let typo = ((a3 * a3 + l2 * l2 - d4 * d4) / (2.0 * a2 * l2)).acos();
        assert!((typo.to_degrees() - 89.873506).abs() < 1e-6);
    }

    #[test]
    fn reads_the_puma_offsets() {
        let puma = presets::get("puma560").unwrap();
        let s = SphericalWrist::from_robot(&puma).unwrap();
        assert!((s.lateral_offset() - 0.15005).abs() < 1e-12);
        assert!((s.forearm() - 0.0203f64.hypot(0.4318)).abs() < 1e-12);
        assert_eq!((s.s1, s.s3, s.s4, s.s5), (1.0, -1.0, 1.0, -1.0));
    }

    #[test]
    fn rejects_robots_outside_the_family() {
        for (name, needle) in [("ur5", "d5"), ("panda", "7"), ("planar3", "6 joints")] {
            let robot = presets::get(name).unwrap();
            let err = SphericalWrist::from_robot(&robot).unwrap_err().to_string();
            assert!(err.contains(needle), "{name}: {err}");
        }
        // A twisted forearm: α3 = 45°.
        let mut spec = reference().spec().clone();
        spec.joints[2] = Joint::revolute(0.0203, 45f64.to_radians(), 0.0, 0.0);
        let err = SphericalWrist::from_robot(&Robot::new(spec).unwrap()).unwrap_err().to_string();
        assert!(err.contains("α3"), "{err}");
    }

    #[test]
    fn name_matches_the_cli_name() {
        let s = SphericalWrist::from_robot(&reference()).unwrap();
        assert_eq!(s.name(), SolverKind::SphericalWrist.as_str());
    }

    #[test]
    fn dh_transform_matches_forward_kinematics() {
        let robot = reference();
        let s = SphericalWrist::from_robot(&robot).unwrap();
        let q = [0.1, -0.7, 1.3, 0.4, -2.0, 2.9];
        let mut t = IsometryMatrix3::identity();
        for (j, &v) in s.joints.iter().zip(&q) {
            t *= j.transform(j.theta(v));
        }
        let fk = robot.fk_matrix(&q).unwrap();
        assert!((t.to_homogeneous() - fk.to_homogeneous()).abs().max() < 1e-14);
    }

    #[test]
    fn configurations_are_the_eight_branches_in_the_order_of_the_solve() {
        use crate::ik::configuration_order::{check, labels};
        let puma = presets::get("puma560").unwrap();
        let s = SphericalWrist::from_robot(&puma).unwrap();
        assert!(s.enumerates_all_branches());
        let expected: Vec<String> = [("right", "down"), ("right", "up"), ("left", "up"), ("left", "down")]
            .into_iter()
            .flat_map(|(sh, el)| ["noflip", "flip"].map(|w| format!("shoulder={sh} elbow={el} wrist={w}")))
            .collect();
        assert_eq!(labels(&s, &puma), expected);
        assert_eq!(check(&s, &puma, 200), 200, "puma560: every pose has all eight branches");
        // The order follows the signs of α1, a2 and the lateral offset d.
        let arm = |alpha1_deg: f64, a2: f64, d2: f64| {
            let r = |a: f64, alpha_deg: f64, d: f64| Joint::revolute(a, alpha_deg.to_radians(), d, 0.0);
            Robot::new(RobotSpec::new(
                "arm",
                Convention::Dh,
                vec![
                    r(0.0, alpha1_deg, 0.3),
                    r(a2, 0.0, d2),
                    r(0.0203, -90.0, 0.0),
                    r(0.0, 90.0, 0.4318),
                    r(0.0, -90.0, 0.0),
                    r(0.0, 0.0, 0.05625),
                ],
            ))
            .unwrap()
        };
        for (alpha1, a2, d2, first) in [
            (90.0, 0.4318, 0.0, "shoulder=front elbow=down wrist=noflip"),
            (-90.0, 0.4318, 0.0, "shoulder=front elbow=up wrist=noflip"),
            (90.0, -0.4318, 0.0, "shoulder=front elbow=up wrist=noflip"),
            (90.0, 0.4318, -0.15, "shoulder=left elbow=down wrist=noflip"),
            (-90.0, 0.4318, 0.15, "shoulder=left elbow=up wrist=noflip"),
        ] {
            let robot = arm(alpha1, a2, d2);
            let s = SphericalWrist::from_robot(&robot).unwrap();
            assert_eq!(labels(&s, &robot)[0], first, "α1 = {alpha1}°, a2 = {a2}, d2 = {d2}");
            assert!(check(&s, &robot, 100) > 50, "α1 = {alpha1}°, a2 = {a2}, d2 = {d2}");
        }
    }
}
