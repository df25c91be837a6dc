//! RERR 6R arms whose axes 2, 3 and 4 are parallel: seed 003's vector method
//! (Knapczyk & Kisiel 1987, notes 003 §3), generalised to the whole UR-type family.
//!
//! # The family
//!
//! Six revolute joints in a standard DH table with
//!
//! * α1 = ±90° (axis 2 perpendicular to the column axis 1),
//! * α2, α3 ∈ {0°, 180°} (axes 2, 3, 4 parallel: the planar pair "E" of the paper),
//! * α4 = ±90°, α5 = ±90° (axis 5 perpendicular to axes 4 and 6),
//! * a5 = 0 (axes 5 and 6 meet at the wrist point C), a2 ≠ 0, a3 ≠ 0,
//!
//! and any d1, a1, d2, d3, d4, a4, d5, d6, a6, α6, joint offsets and flipped joints. The
//! lateral offset of the arm plane, `D = d2 + d3·cos α2 + d4·cos α2·cos α3`, may be non-zero.
//! Seed 003's welding robot (`welder6r`: α = (90, 0, 180, −90, 90, 90)°) and the UR5
//! (α = (90, 0, 0, 90, −90, 0)°, a2, a3 < 0, D = d4) are both members; the PUMA 560
//! (α3 = −90°) and seed 001's `spbu6` are not.
//!
//! # The method (notes 003 §3.3–3.4, in the DH frames of the robot)
//!
//! In the paper's notation e_i = z_{i−1} is the axis of joint i and a_i = x_i the common
//! normal; the target gives `n = x6` and `l = z6` (the tool frame, after removing base and
//! tool transforms with `chain_target`).
//!
//! 1. e6 = z5 = sin α6·y6 + cos α6·z6 (eq. 6: `l × n` for α6 = 90°); the wrist point
//!    C = P − a6·n − d6·e6 (eq. 7).
//! 2. The arm-plane normal w = e2 = z1 = sin α1·(sin θ1, −cos θ1, 0) must satisfy
//!    C·w = D (all points O1…O4 lie in a plane offset D along w). With ρ, φ the polar
//!    coordinates of C this is `ρ·sin(θ1 − φ) = sin α1·D`: two roots, the paper's `w`
//!    (eq. 10; θ1 = φ when D = 0) and the shoulder flip `−w` (θ1 + 180°).
//! 3. e5 = z4 = ±(w × e6)/sin∠(w, e6) (eq. 11; the paper takes `+`, the wrist flip is `−`).
//! 4. B = C − d5·e5 (eq. 12), then the point behind the wrist-pitch link,
//!    O3 = B − d4·z3 − a4·x4, and the in-plane vector r2·e_r2 = O3 − O1 − d2·z1 − d3·z2 from
//!    the shoulder O1 = d1·k + a1·x1 (for the welder simply r2·e_r2 = B, eq. 13).
//! 5. Δ = (a2² + r2² − a3²)/(2|a2|·r2) = cos β (eq. 14); |Δ| > 1 is out of reach.
//! 6. The direction of link 2 from Chace's formula (eq. 4 with the corrected normalisation,
//!    notes 003 §3.2/§6.4; [`chace`]) with e_i = e_r2, e_j = w, c_ik = Δ, c_jk = 0:
//!    `a2 = e_r2·cos β ± (e_r2 × w)·sin β` (eqs. 17, 20); `+` is configuration "+β".
//! 7. a3 = (r2·e_r2 − l2·a2)/l3 (eq. 18), a4 = (z3 × e5)/sin α4, a5 = (e5 × e6)/sin α5
//!    (eq. 19; for the welder `w × e5` and `e5 × e6`), a6 = n.
//! 8. θ_{i+1} = atan2(e_{i+1}·(a_i × a_{i+1}), a_i·a_{i+1}) (eq. 21).
//!
//! # Branches
//!
//! Up to 8 solutions, labelled with the paper's names:
//!
//! * `shoulder` = `w` (the paper's normal `w = (e_r1 × k)/‖e_r1 × k‖`, i.e. z1·(C × k) > 0)
//!   or `−w` (θ1 + 180° when D = 0) — the paper fixes `w` silently (notes 003 §3.7);
//! * `config` = `+β` (the triple (a2, e_r2, w) is right-handed, w = z1 of that solution) or
//!   `−β` (left-handed) — the paper's two configurations (eq. 20, Fig. 3);
//! * `wrist` = `e5` (z4 = +(z1 × z5)/‖·‖, the paper's choice, θ5 ∈ [−180°, 0°] for the welder)
//!   or `−e5` (the wrist flip).
//!
//! # Singularities
//!
//! * **elbow**: |Δ| = 1 (links 2 and 3 collinear; for |a2| = |a3| also r2 = 0): "+β" and "−β"
//!   coincide (notes 003 §3.6). Flagged (and the two merged) when the cosine of the elbow
//!   angle is within [`BOUNDARY`] of ±1, i.e. |θ3| or |θ3 ∓ 180°| below ≈ 4.5e-5 rad.
//!   For r2 = 0, θ2 is undetermined and taken from the seed.
//! * **shoulder**: C on the column axis (ρ = 0, D = 0): θ1 is undetermined and taken from the
//!   seed (and seed + 180° for `−w`); with D ≠ 0, ρ = |D| where the two roots merge.
//! * **wrist**: e6 ∥ w (sin∠(w, e6) = 0): e5 is undetermined; θ6 is taken from the seed
//!   (`e5`) and seed + 180° (`−e5`), and θ2…θ5 follow.
//!
//! [`ParallelAxes::measures`] returns Δ and these singularity measures for a target without
//! solving, for path tracking (notes 003 §4 step 2: detect singular positions along a path);
//! [`PathMeasures`] are the ones path tracking scans ([`IkSolver::singularity_measures`]).
//!
//! # Tracking
//!
//! A path is tracked by default in the paper's two configurations, `shoulder=w config=+β
//! wrist=e5` (the default) and `shoulder=w config=−β wrist=e5`
//! ([`IkSolver::configurations`]); the labels name the branches
//! ([`IkSolver::enumerates_all_branches`]).
//!
//! # Failure reasons
//!
//! * ρ < |D| (C inside the cylinder the arm plane cannot reach):
//!   `Unreachable { distance: ρ, reach: |D| }`;
//! * |Δ| > 1 for every shoulder/wrist branch: `Unreachable { distance: r2, reach }` with
//!   `reach` = |a2| + |a3| or ||a2| − |a3|| (the branch closest to reachable is reported).
//!
//! # Position-only targets
//!
//! A 6R arm has a 3-parameter family of solutions for a position; this solver keeps the tool
//! orientation of `options.seed` (else of the home configuration) and solves that pose.

use nalgebra::{Isometry3, Rotation3, Vector3};
use serde::Serialize;

use super::spherical_wrist::{Dh6, revolute_dh6};
use super::{
    Branch, ChainFrame, FlagBits, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, LaneSolve, Raw6,
    Raw6Set, SingularityKind, SingularityMeasures, finish_into, solve_at, solved,
};
use crate::angle::{atan2, atan2_each, sin_cos};
use crate::kinematics::check_q;
use crate::model::Robot;
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, IK_PARALLEL_SINE, STRUCTURE_ANGLE, STRUCTURE_LENGTH};

const NAME: &str = "parallel-axes";

/// Chace's solution of the vector tetrahedron (seed 003, eq. 4): the unit vectors `e_k` with
/// `e_i·e_k = c_ik` and `e_j·e_k = c_jk`, for known unit vectors `e_i`, `e_j`.
///
/// `e_k = [(c_ik − c_ij·c_jk)·e_i + (c_jk − c_ij·c_ik)·e_j ± √D·(e_i × e_j)] / s_ij²` with
/// `D = 1 − c_ij² − c_ik² − c_jk² + 2·c_ij·c_ik·c_jk` and `s_ij = sin∠(e_i, e_j)`.
/// This is the corrected normalisation (notes 003 §3.2 and §6.4: the paper prints no
/// division of the first two terms and `/s_ij` on the last, right only when `s_ij = 1`).
///
/// # Returns
/// `[plus, minus]`: `plus` makes `(e_i, e_j, e_k)` right-handed (`(e_i × e_j)·e_k ≥ 0`), the
/// paper's "+" root; `None` when `e_i ∥ e_j` (`s_ij` below [`IK_PARALLEL_SINE`]) or
/// `D < −2·BOUNDARY` (no such vector; `D` is clamped to 0 inside that tolerance, the
/// tolerance of cosines within `BOUNDARY` of ±1).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use reach::ik::parallel_axes::chace;
/// let (ei, ej) = (Vector3::x(), Vector3::new(0.6, 0.8, 0.0)); // 53.13° apart
/// let [plus, minus] = chace(&ei, &ej, 0.5, 0.3).unwrap();
/// for ek in [plus, minus] {
///     approx::assert_relative_eq!(ek.norm(), 1.0, epsilon = 1e-12);
///     approx::assert_relative_eq!(ek.dot(&ei), 0.5, epsilon = 1e-12);
///     approx::assert_relative_eq!(ek.dot(&ej), 0.3, epsilon = 1e-12);
/// }
/// assert!(ei.cross(&ej).dot(&plus) > 0.0 && ei.cross(&ej).dot(&minus) < 0.0);
/// ```
#[must_use]
#[inline(always)]
pub fn chace(e_i: &Vector3<f64>, e_j: &Vector3<f64>, c_ik: f64, c_jk: f64) -> Option<[Vector3<f64>; 2]> {
    let c_ij = e_i.dot(e_j);
    let n = e_i.cross(e_j);
    let s2 = n.norm_squared();
    if !s2.is_finite() || s2 <= IK_PARALLEL_SINE * IK_PARALLEL_SINE {
        return None;
    }
    let d = 1.0 - c_ij * c_ij - c_ik * c_ik - c_jk * c_jk + 2.0 * c_ij * c_ik * c_jk;
    if !d.is_finite() || d < -2.0 * BOUNDARY {
        return None;
    }
    let base = e_i * (c_ik - c_ij * c_jk) + e_j * (c_jk - c_ij * c_ik);
    let side = n * d.max(0.0).sqrt();
    Some([(base + side) / s2, (base - side) / s2])
}

/// Shoulder branch: the sign of the arm-plane normal w = e2 = z1 (notes 003 §3.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Shoulder {
    /// The paper's `w = (e_r1 × k)/‖e_r1 × k‖` (z1·(C × k) > 0).
    W,
    /// The opposite normal: θ1 + 180° when the arm plane has no lateral offset.
    MinusW,
}

impl Shoulder {
    /// The branch label: `w` or `−w`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Shoulder::W => "w",
            Shoulder::MinusW => "−w",
        }
    }
}

/// Wrist branch: the sign of e5 = z4 (notes 003 §3.7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Wrist {
    /// The paper's `e5 = (w × e6)/‖w × e6‖` (eq. 11).
    E5,
    /// The wrist flip, `−e5`.
    MinusE5,
}

impl Wrist {
    /// The branch label: `e5` or `−e5`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Wrist::E5 => "e5",
            Wrist::MinusE5 => "−e5",
        }
    }

    fn sign(self) -> f64 {
        match self {
            Wrist::E5 => 1.0,
            Wrist::MinusE5 => -1.0,
        }
    }
}

/// The paper's configuration of links 2 and 3 (eq. 20, Fig. 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Config {
    /// ξ = +1: (a2, e_r2, w) right-handed.
    PlusBeta,
    /// ξ = −1: (a2, e_r2, w) left-handed.
    MinusBeta,
}

impl Config {
    /// The branch label: `+β` or `−β`.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Config::PlusBeta => "+β",
            Config::MinusBeta => "−β",
        }
    }
}

/// Seed 003's quantities of one target for one shoulder and wrist branch (notes 003 §3.3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ArmMeasures {
    /// Shoulder branch.
    pub shoulder: Shoulder,
    /// Wrist branch.
    pub wrist: Wrist,
    /// `r2`: length of the in-plane vector from the shoulder to the elbow-triangle apex
    /// (|OB| for the welder), metres.
    pub r2: f64,
    /// The paper's `Δ = (l2² + r2² − l3²)/(2·l2·r2) = cos β` (eq. 14, l = |a|). |Δ| ≤ 1 is
    /// reachable, |Δ| = 1 an elbow singularity. For r2 = 0 it is computed with r2 =
    /// `f64::MIN_POSITIVE` (huge, or 0 when l2 = l3 — see [`ArmMeasures::elbow_margin`]).
    pub delta: f64,
    /// Cosine of the angle between links 2 and 3 (`(r2² − a2² − a3²)/(2·a2·a3)`): ±1 at the
    /// elbow singularity, also for l2 = l3 where Δ misses the folded arm.
    pub cos_elbow: f64,
    /// `sin∠(w, e6) = ‖z1 × z5‖`: 0 at the wrist singularity.
    pub wrist_sine: f64,
}

impl ArmMeasures {
    /// β = arccos Δ (radians) when |Δ| ≤ 1 (within [`BOUNDARY`]), else `None`.
    #[must_use]
    pub fn beta(&self) -> Option<f64> {
        (self.delta.abs() <= 1.0 + BOUNDARY).then(|| self.delta.clamp(-1.0, 1.0).acos())
    }

    /// `1 − |cos_elbow|`: positive inside the workspace, 0 at the elbow singularity
    /// (|Δ| = 1), negative when the target is out of reach on this branch.
    #[must_use]
    pub fn elbow_margin(&self) -> f64 {
        1.0 - self.cos_elbow.abs()
    }
}

/// Δ and the singularity measures of a target (see [`ParallelAxes::measures`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TargetMeasures {
    /// Horizontal distance ρ of the wrist point C from the column axis, metres.
    pub column_distance: f64,
    /// |D| = |d2 + d3·cos α2 + d4·cos α2·cos α3|, metres: the shoulder is singular at
    /// ρ = |D| (0 for the welder: C on the column axis).
    pub lateral_offset: f64,
    /// Per branch, in the order (w, e5), (w, −e5), (−w, e5), (−w, −e5); `None` when the
    /// shoulder equation has no root (ρ < |D|).
    pub arms: [Option<ArmMeasures>; 4],
}

impl TargetMeasures {
    /// ρ − |D|: 0 at the shoulder singularity, negative when out of reach.
    #[must_use]
    pub fn shoulder_margin(&self) -> f64 {
        self.column_distance - self.lateral_offset
    }

    /// The measures of one branch.
    #[must_use]
    pub fn arm(&self, shoulder: Shoulder, wrist: Wrist) -> Option<&ArmMeasures> {
        let i = match (shoulder, wrist) {
            (Shoulder::W, Wrist::E5) => 0,
            (Shoulder::W, Wrist::MinusE5) => 1,
            (Shoulder::MinusW, Wrist::E5) => 2,
            (Shoulder::MinusW, Wrist::MinusE5) => 3,
        };
        self.arms[i].as_ref()
    }

    /// The branch the paper uses (shoulder `w`, wrist `e5`): its Δ is the paper's Δ.
    #[must_use]
    pub fn paper(&self) -> Option<&ArmMeasures> {
        self.arm(Shoulder::W, Wrist::E5)
    }
}

/// Closed-form IK for RERR 6R arms with axes 2, 3, 4 parallel (seed 003; see the module docs).
#[derive(Debug, Clone)]
pub struct ParallelAxes {
    /// a_i, d_i (metres).
    a: [f64; 6],
    d: [f64; 6],
    /// sin α1, sin α4, sin α5 (each ±1), cos α2, cos α3 (each ±1), sin/cos α6.
    s_alpha1: f64,
    c_alpha2: f64,
    c_alpha3: f64,
    s_alpha4: f64,
    s_alpha5: f64,
    s_alpha6: f64,
    c_alpha6: f64,
    /// Lateral offset D of the arm plane along z1.
    lateral: f64,
    /// θ offsets and joint signs (−1 for flipped joints): θ = sign·q + offset.
    offset: [f64; 6],
    sign: [f64; 6],
    /// The DH chain relative to the robot's base and tool.
    frame: ChainFrame,
}

/// A root of the shoulder equation.
#[derive(Debug, Clone, Copy)]
struct ShoulderRoot {
    theta1: f64,
    label: Shoulder,
    singular: bool,
}

/// One shoulder root's frames up to the wrist, shared by its two wrists: the wrist `−e5`
/// negates z4, x4 and x5 exactly (eq. 11), and with them θ5 (eq. 21: both `z4` and the
/// cross product's factors change sign, so only the `atan2`'s first argument does).
#[derive(Debug, Clone, Copy)]
struct ShoulderArm {
    x1: Vector3<f64>,
    z1: Vector3<f64>,
    z3: Vector3<f64>,
    /// z4 = e5, x4 and x5 of the wrist `e5`.
    z4: Vector3<f64>,
    x4: Vector3<f64>,
    x5: Vector3<f64>,
    wrist_sine: f64,
    wrist_singular: bool,
}

/// Everything of one (shoulder, wrist) branch before the elbow configuration is chosen.
#[derive(Debug, Clone, Copy)]
struct Arm {
    x1: Vector3<f64>,
    z1: Vector3<f64>,
    x4: Vector3<f64>,
    /// In-plane vector r2·e_r2 (perpendicular to z1).
    v: Vector3<f64>,
    r2: f64,
}

/// The directions `[x2, x3]` of links 2 and 3 of one arm and configuration.
type Links = [Vector3<f64>; 2];

/// The `atan2` arguments `(y, x)` of one solve's angles (eq. 21), evaluated together in lanes
/// ([`atan2_each`]): per branch `b = 4·shoulder + 2·wrist + config` θ2, θ3, θ4 at `b`,
/// `BRANCHES + b`, `2·BRANCHES + b`; per shoulder `s` θ1, θ5 (wrist `e5`), θ6 (`e5`) and θ6
/// (`−e5`) at [`SHOULDER_LANES`] `+ s`, `+ 2 + s`, `+ 4 + s`, `+ 6 + s`. Unused lanes hold
/// `(1, 1)`.
const BRANCHES: usize = 8;
/// The first lane of the shoulders' angles (see [`BRANCHES`]).
const SHOULDER_LANES: usize = 3 * BRANCHES;
/// All lanes of a solve's angles (see [`BRANCHES`]).
const ANGLE_LANES: usize = SHOULDER_LANES + 8;

/// The chain-frame target: tool point and axes.
#[derive(Debug, Clone, Copy)]
struct Frame {
    p: Vector3<f64>,
    x6: Vector3<f64>,
    y6: Vector3<f64>,
    z6: Vector3<f64>,
}

/// θ1…θ6 of one branch from its shoulder's angles `[θ1, θ5, θ6 (e5), θ6 (−e5)]`
/// ([`ParallelAxes::shoulder_args`]) and its arm's `[θ2, θ3, θ4]`
/// ([`ParallelAxes::link_args`]): the wrist `−e5` negates θ5 and takes its own θ6 (eq. 21).
#[inline(always)]
fn branch_theta(shoulder: [f64; 4], link: [f64; 3], wrist: Wrist) -> [f64; 6] {
    let [theta1, theta5, theta6_e5, theta6_minus_e5] = shoulder;
    let (theta5, theta6) = match wrist {
        Wrist::E5 => (theta5, theta6_e5),
        Wrist::MinusE5 => (-theta5, theta6_minus_e5),
    };
    [theta1, link[0], link[1], link[2], theta5, theta6]
}

/// `(axis·(from × to), from·to)`: the `atan2` arguments of the angle from `from` to `to`
/// about `axis` (eq. 21).
#[inline(always)]
fn angle_args(axis: &Vector3<f64>, from: &Vector3<f64>, to: &Vector3<f64>) -> (f64, f64) {
    (axis.dot(&from.cross(to)), from.dot(to))
}

fn is_angle(value: f64, target: f64) -> bool {
    crate::angle::wrap(value - target).abs() <= STRUCTURE_ANGLE
}

impl ParallelAxes {
    /// Checks that `robot` is a 6R standard-DH arm with axes 2, 3, 4 parallel as described in
    /// the module docs, and extracts its parameters.
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let table = revolute_dh6(robot, NAME)?;
        Self::from_table(robot, &table).map_err(|e| table.explain(e))
    }

    fn from_table(robot: &Robot, table: &Dh6) -> Result<Self, IkError> {
        let unsupported =
            |reason: String| IkError::Unsupported { solver: NAME, robot: robot.name().to_string(), reason };
        let a = table.joints.map(|j| j.a);
        let d = table.joints.map(|j| j.d);
        let alpha = table.joints.map(|j| j.alpha);
        let offset = table.joints.map(|j| j.offset);
        let sign = table.joints.map(|j| j.sign);
        let deg = |i: usize| alpha[i].to_degrees();
        let right = std::f64::consts::FRAC_PI_2;
        let pm90 = |i: usize, what: &str| -> Result<f64, IkError> {
            if is_angle(alpha[i], right) {
                Ok(1.0)
            } else if is_angle(alpha[i], -right) {
                Ok(-1.0)
            } else {
                Err(unsupported(format!("α{} = {:.6}° (needs ±90°: {what})", i + 1, deg(i))))
            }
        };
        let parallel = |i: usize| -> Result<f64, IkError> {
            if is_angle(alpha[i], 0.0) {
                Ok(1.0)
            } else if is_angle(alpha[i], std::f64::consts::PI) {
                Ok(-1.0)
            } else {
                Err(unsupported(format!(
                    "α{} = {:.6}° (needs 0° or 180°: axes 2, 3 and 4 must be parallel)",
                    i + 1,
                    deg(i)
                )))
            }
        };
        let s_alpha1 = pm90(0, "axis 2 perpendicular to the column axis 1")?;
        let c_alpha2 = parallel(1)?;
        let c_alpha3 = parallel(2)?;
        let s_alpha4 = pm90(3, "axis 5 perpendicular to the parallel axes")?;
        let s_alpha5 = pm90(4, "axis 6 perpendicular to axis 5")?;
        if a[4].abs() > STRUCTURE_LENGTH {
            return Err(unsupported(format!(
                "a5 = {} m ≠ 0: axes 5 and 6 do not meet, so the wrist point C is not fixed by the pose",
                a[4]
            )));
        }
        for i in [1, 2] {
            if a[i].abs() <= STRUCTURE_LENGTH {
                return Err(unsupported(format!(
                    "a{} = 0: the arm plane has no link {} (no elbow triangle)",
                    i + 1,
                    i + 1
                )));
            }
        }
        let (s_alpha6, c_alpha6) = alpha[5].sin_cos();
        Ok(ParallelAxes {
            a,
            d,
            s_alpha1,
            c_alpha2,
            c_alpha3,
            s_alpha4,
            s_alpha5,
            s_alpha6,
            c_alpha6,
            lateral: d[1] + d[2] * c_alpha2 + d[3] * c_alpha2 * c_alpha3,
            offset,
            sign,
            frame: table.frame,
        })
    }

    /// Δ (cos β) and the singularity measures of `target` without solving (notes 003 §3.3,
    /// §3.6), for every shoulder and wrist branch: the motion module tracks these along a
    /// path to find the singular positions (|Δ| = 1, ρ = |D|, sin∠(w, e6) = 0).
    ///
    /// # Arguments
    /// * `target` — tool pose in the world frame;
    /// * `options` — only `seed` is used, for the undetermined angles at singularities
    ///   (θ1 when C is on the column axis, θ6 when e6 ∥ w).
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] for a non-finite target, [`IkError::Kinematics`] for a bad seed.
    ///
    /// # Example
    /// ```
    /// use reach::ik::parallel_axes::ParallelAxes;
    /// let welder = reach::model::presets::get("welder6r").unwrap();
    /// let solver = ParallelAxes::from_robot(&welder).unwrap();
    /// let pose = welder.fk(&[0.3, 0.2, 0.9, -1.0, -0.8, 0.4]).unwrap();
    /// let m = solver.measures(&welder, &pose, &Default::default()).unwrap();
    /// let paper = m.paper().unwrap();
    /// assert!(paper.delta.abs() < 1.0 && paper.elbow_margin() > 0.0);
    /// ```
    pub fn measures(
        &self,
        robot: &Robot,
        target: &Isometry3<f64>,
        options: &IkOptions,
    ) -> Result<TargetMeasures, IkError> {
        IkTarget::Pose(*target).validate()?;
        let seed = self.seed_theta(robot, options)?;
        let frame = frame_of(&self.frame.target(robot, target));
        let (z5, c) = self.wrist_point(&frame);
        let rho = c.x.hypot(c.y);
        let mut out = TargetMeasures { column_distance: rho, lateral_offset: self.lateral.abs(), arms: [None; 4] };
        if let Ok(roots) = self.shoulder_roots(&c, seed[0]) {
            for root in &roots {
                let shared = self.shoulder_arm(&frame, &z5, root, seed[5]);
                for (j, wrist) in [Wrist::E5, Wrist::MinusE5].into_iter().enumerate() {
                    let arm = self.arm(&shared, &c, wrist);
                    let (l2, l3) = (self.a[1], self.a[2]);
                    let delta =
                        (l2 * l2 + arm.r2 * arm.r2 - l3 * l3) / (2.0 * l2.abs() * arm.r2.max(f64::MIN_POSITIVE));
                    let cos_elbow = (arm.r2 * arm.r2 - l2 * l2 - l3 * l3) / (2.0 * l2 * l3);
                    let slot = match root.label {
                        Shoulder::W => j,
                        Shoulder::MinusW => 2 + j,
                    };
                    out.arms[slot] = Some(ArmMeasures {
                        shoulder: root.label,
                        wrist,
                        r2: arm.r2,
                        delta,
                        cos_elbow,
                        wrist_sine: shared.wrist_sine,
                    });
                }
            }
        }
        Ok(out)
    }

    /// The seed as DH angles θ = sign·q + offset (zeros when there is no seed).
    fn seed_theta(&self, robot: &Robot, options: &IkOptions) -> Result<[f64; 6], IkError> {
        let mut theta = self.offset;
        if let Some(seed) = &options.seed {
            check_q(robot.dof(), seed)?;
            for i in 0..6 {
                theta[i] = self.sign[i] * seed[i] + self.offset[i];
            }
        }
        Ok(theta)
    }

    /// e6 = z5 and the wrist point C (eqs. 6, 7).
    fn wrist_point(&self, f: &Frame) -> (Vector3<f64>, Vector3<f64>) {
        let z5 = f.y6 * self.s_alpha6 + f.z6 * self.c_alpha6;
        let c = f.p - f.x6 * self.a[5] - z5 * self.d[5];
        (z5, c)
    }

    /// The two roots of `C·z1(θ1) = D` (eq. 10 generalised), labelled; `Err` = unreachable.
    fn shoulder_roots(&self, c: &Vector3<f64>, seed_theta1: f64) -> Result<[ShoulderRoot; 2], IkFailure> {
        let rho = c.x.hypot(c.y);
        let lateral = self.lateral;
        if rho <= IK_AXIS_DISTANCE && lateral.abs() <= IK_AXIS_DISTANCE {
            // C on the column axis: w undetermined; keep the seed's θ1 (notes 003 §3.6, [R]).
            let t = seed_theta1;
            return Ok([
                ShoulderRoot { theta1: t, label: Shoulder::W, singular: true },
                ShoulderRoot { theta1: t + std::f64::consts::PI, label: Shoulder::MinusW, singular: true },
            ]);
        }
        let ratio = self.s_alpha1 * lateral / rho;
        if ratio.is_nan() || ratio.abs() > 1.0 + BOUNDARY {
            return Err(IkFailure::Unreachable {
                distance: rho,
                reach: lateral.abs(),
                point: "the wrist point",
                from: "joint 1's axis",
            });
        }
        let singular = ratio.abs() >= 1.0 - BOUNDARY;
        let gamma = ratio.clamp(-1.0, 1.0).asin();
        let phi = atan2(c.y, c.x);
        let near = phi + gamma; // z1·(C × k) = sin α1·ρ·cos γ: the paper's `w` when sin α1 > 0
        let far = phi + std::f64::consts::PI - gamma;
        let (w, minus_w) = if self.s_alpha1 > 0.0 { (near, far) } else { (far, near) };
        Ok([
            ShoulderRoot { theta1: w, label: Shoulder::W, singular },
            ShoulderRoot { theta1: minus_w, label: Shoulder::MinusW, singular },
        ])
    }

    /// Steps 3–4 of the method for one shoulder root, up to the wrist sign: the frames both
    /// wrists share ([`ShoulderArm`]).
    #[inline(always)]
    fn shoulder_arm(&self, f: &Frame, z5: &Vector3<f64>, root: &ShoulderRoot, seed_theta6: f64) -> ShoulderArm {
        let (s1, c1) = sin_cos(root.theta1);
        let x1 = Vector3::new(c1, s1, 0.0);
        let z1 = Vector3::new(s1, -c1, 0.0) * self.s_alpha1;
        let z3 = z1 * self.c_alpha2 * self.c_alpha3;
        // e5 = (w × e6)/sin∠(w, e6)  (eq. 11; the wrist flip is its negation).
        let u = z1.cross(z5);
        let wrist_sine = u.norm();
        let wrist_singular = wrist_sine <= IK_PARALLEL_SINE;
        let z4 = if wrist_singular {
            // e6 ∥ w: e5 is any vector ⟂ w; the seed's θ6 fixes frame 5 and with it
            // e5 = sin α5·y5 (z_{i−1} = sin α_i·y_i + cos α_i·z_i, α5 = ±90°).
            let (s6, c6) = sin_cos(seed_theta6);
            let x5 = f.x6 * c6 - (f.y6 * self.c_alpha6 - f.z6 * self.s_alpha6) * s6;
            let y5 = z5.cross(&x5);
            let e5 = y5 * self.s_alpha5;
            (e5 - z1 * e5.dot(&z1)).normalize()
        } else {
            u * (1.0 / wrist_sine)
        };
        let x4 = z3.cross(&z4) * self.s_alpha4;
        let x5 = z4.cross(z5) * self.s_alpha5;
        let x5 = x5 / x5.norm();
        ShoulderArm { x1, z1, z3, z4, x4, x5, wrist_sine, wrist_singular }
    }

    /// Step 4 for one wrist sign: B = C − d5·e5 (eq. 12), then back along the wrist-pitch link
    /// and the lateral offsets to the in-plane vector r2·e_r2.
    #[inline(always)]
    fn arm(&self, shared: &ShoulderArm, c: &Vector3<f64>, wrist: Wrist) -> Arm {
        let ShoulderArm { x1, z1, z3, .. } = *shared;
        let z2 = z1 * self.c_alpha2;
        let (z4, x4) = (shared.z4 * wrist.sign(), shared.x4 * wrist.sign());
        let o4 = c - z4 * self.d[4];
        let o3 = o4 - z3 * self.d[3] - x4 * self.a[3];
        let o1 = Vector3::new(0.0, 0.0, self.d[0]) + x1 * self.a[0];
        let v = o3 - o1 - z1 * self.d[1] - z2 * self.d[2];
        let v = v - z1 * v.dot(&z1); // exact in-plane part (the residue is round-off or ≤ ρ at the shoulder singularity)
        Arm { x1, z1, x4, v, r2: v.norm() }
    }

    /// The `atan2` arguments of θ1, θ5 (wrist `e5`; `−e5`: −θ5) and θ6 (`e5`, `−e5`) of one
    /// shoulder (eq. 21).
    #[inline(always)]
    fn shoulder_args(shared: &ShoulderArm, f: &Frame, z5: &Vector3<f64>) -> [(f64, f64); 4] {
        [
            angle_args(&Vector3::z(), &Vector3::x(), &shared.x1),
            angle_args(&shared.z4, &shared.x4, &shared.x5),
            angle_args(z5, &shared.x5, &f.x6),
            angle_args(z5, &-shared.x5, &f.x6),
        ]
    }

    /// Steps 5–7 for one arm: the directions x2, x3 of links 2 and 3 of the configurations
    /// `[+β, −β]` (equal at r2 = 0, from the seed's θ2), whether the elbow is singular, or
    /// `Err` = out of reach.
    #[inline(always)]
    fn links(&self, arm: &Arm, seed_theta2: f64) -> Result<([Links; 2], bool), IkFailure> {
        let (l2, l3) = (self.a[1].abs(), self.a[2].abs());
        let z1 = arm.z1;
        // Direction of link 2 (from the shoulder towards the elbow), a2 of the paper.
        let (link2, elbow_singular) = if arm.r2 <= IK_AXIS_DISTANCE {
            // r2 = 0: only possible for l2 = l3 (else |Δ| = ∞): the folded arm, θ2 free.
            if (l2 - l3).abs() > IK_AXIS_DISTANCE {
                return Err(IkFailure::Unreachable {
                    distance: arm.r2,
                    reach: (l2 - l3).abs(),
                    point: "the wrist point",
                    from: "joint 2",
                });
            }
            let (s2, c2) = sin_cos(seed_theta2);
            let x2 = arm.x1 * c2 + z1.cross(&arm.x1) * s2;
            let link2 = x2 * self.a[1].signum();
            ([link2, link2], true)
        } else {
            // Reachability and the elbow singularity are decided on the cosine of the elbow
            // angle, c3 = (r2² − a2² − a3²)/(2·a2·a3), which is ±1 exactly when |Δ| = 1 and
            // is what `ArmMeasures::elbow_margin` reports, so both agree.
            let c3 = (arm.r2 * arm.r2 - l2 * l2 - l3 * l3) / (2.0 * self.a[1] * self.a[2]);
            if c3.is_nan() || c3.abs() > 1.0 + BOUNDARY {
                let reach = if arm.r2 > l2 + l3 { l2 + l3 } else { (l2 - l3).abs() };
                return Err(IkFailure::Unreachable {
                    distance: arm.r2,
                    reach,
                    point: "the wrist point",
                    from: "joint 2",
                });
            }
            let singular = c3.abs() >= 1.0 - BOUNDARY;
            // Δ = cos β (eq. 14); ±1 at the singularity (β = 0, or 180° when folded with l2 < l3).
            let delta = ((l2 * l2 + arm.r2 * arm.r2 - l3 * l3) / (2.0 * l2 * arm.r2)).clamp(-1.0, 1.0);
            let delta = if singular { delta.signum() } else { delta };
            let e_r2 = arm.v / arm.r2;
            // a2 = e_r2·cos β ± (e_r2 × w)·sin β  (eqs. 17, 20 via Chace's formula, eq. 4):
            // e_i = e_r2 ⟂ e_j = w, c_ik = Δ, c_jk = 0; the "+" root makes (e_r2, w, a2) and
            // hence (a2, e_r2, w) right-handed: configuration "+β".
            let Some([plus, minus]) = chace(&e_r2, &z1, delta, 0.0) else {
                return Err(IkFailure::Singular { kind: SingularityKind::Elbow });
            };
            ([plus.normalize(), minus.normalize()], singular)
        };
        Ok((
            link2.map(|link2| {
                let x2 = link2 * self.a[1].signum();
                // a3 = (r2·e_r2 − l2·a2)/l3  (eq. 18), with signed DH lengths.
                let x3 = ((arm.v - x2 * self.a[1]) / self.a[2]).normalize();
                [x2, x3]
            }),
            elbow_singular,
        ))
    }

    /// The `atan2` arguments of θ2, θ3 and θ4 (eq. 21) of one arm and configuration from its
    /// links `[x2, x3]` ([`ParallelAxes::links`]).
    #[inline(always)]
    fn link_args(&self, arm: &Arm, [x2, x3]: &Links) -> [(f64, f64); 3] {
        let z2 = arm.z1 * self.c_alpha2;
        let z3 = z2 * self.c_alpha3;
        [angle_args(&arm.z1, &arm.x1, x2), angle_args(&z2, x2, x3), angle_args(&z3, x3, &arm.x4)]
    }

    /// Every candidate (up to 8) for a chain-frame target, and the failure reason if none.
    ///
    /// The two shoulders' frames are shared by their wrists ([`ShoulderArm`]), the two
    /// configurations of an arm by one Chace solve ([`ParallelAxes::links`]), and the angles
    /// of all branches go through their `atan2` together ([`atan2_each`]: in lanes when
    /// `WIDE`, bit for bit [`atan2`] either way; see [`BRANCHES`]).
    #[inline(always)]
    fn candidates<const WIDE: bool>(&self, frame: &Frame, seed: &[f64; 6]) -> (Raw6Set, Option<IkFailure>) {
        let mut out = Raw6Set::new(KEYS);
        let (z5, c) = self.wrist_point(frame);
        let roots = match self.shoulder_roots(&c, seed[0]) {
            Ok(r) => r,
            Err(failure) => return (out, Some(failure)),
        };
        let mut failure: Option<(f64, IkFailure)> = None;
        let (mut y, mut x) = ([1.0; ANGLE_LANES], [1.0; ANGLE_LANES]);
        let mut branches = [None; BRANCHES];
        let mut wrist_singular = [false; 2];
        for (s, root) in roots.iter().enumerate() {
            let shared = self.shoulder_arm(frame, &z5, root, seed[5]);
            wrist_singular[s] = shared.wrist_singular;
            for (i, (ys, xs)) in Self::shoulder_args(&shared, frame, &z5).into_iter().enumerate() {
                (y[SHOULDER_LANES + 2 * i + s], x[SHOULDER_LANES + 2 * i + s]) = (ys, xs);
            }
            for (w, wrist) in [Wrist::E5, Wrist::MinusE5].into_iter().enumerate() {
                let arm = self.arm(&shared, &c, wrist);
                match self.links(&arm, seed[1]) {
                    Ok((links, elbow_singular)) => {
                        for (k, links) in links.iter().enumerate() {
                            let b = 4 * s + 2 * w + k;
                            for (i, (ys, xs)) in self.link_args(&arm, links).into_iter().enumerate() {
                                (y[i * BRANCHES + b], x[i * BRANCHES + b]) = (ys, xs);
                            }
                            branches[b] = Some(elbow_singular);
                        }
                    }
                    Err(f) => {
                        let excess = match &f {
                            IkFailure::Unreachable { distance, reach, .. } => (distance - reach).abs(),
                            _ => f64::INFINITY,
                        };
                        if failure.as_ref().is_none_or(|(e, _)| excess < *e) {
                            failure = Some((excess, f));
                        }
                    }
                }
            }
        }
        let angles = atan2_each::<WIDE, ANGLE_LANES>(&y, &x);
        for (b, elbow_singular) in branches.into_iter().enumerate() {
            let Some(elbow_singular) = elbow_singular else { continue };
            let (s, w, k) = (b / 4, (b / 2) % 2, b % 2);
            let (config, wrist) = ([Config::PlusBeta, Config::MinusBeta][k], [Wrist::E5, Wrist::MinusE5][w]);
            let theta = branch_theta(
                std::array::from_fn(|i| angles[SHOULDER_LANES + 2 * i + s]),
                std::array::from_fn(|i| angles[i * BRANCHES + b]),
                wrist,
            );
            out.push(self.candidate(&theta, &roots[s], config, wrist, wrist_singular[s], elbow_singular));
        }
        (out, failure.map(|(_, f)| f))
    }

    /// The candidate of one branch, `None` when the branch has no root here: the steps of
    /// [`ParallelAxes::candidates`] for that branch alone, each `atan2` by [`atan2`] (the same
    /// bits as the lanes').
    fn branch_candidate(
        &self,
        frame: &Frame,
        seed: &[f64; 6],
        shoulder: Shoulder,
        config: Config,
        wrist: Wrist,
    ) -> Option<Raw6> {
        let (z5, c) = self.wrist_point(frame);
        let roots = self.shoulder_roots(&c, seed[0]).ok()?;
        let root = roots.iter().find(|r| r.label == shoulder)?;
        let shared = self.shoulder_arm(frame, &z5, root, seed[5]);
        let arm = self.arm(&shared, &c, wrist);
        let (links, elbow_singular) = self.links(&arm, seed[1]).ok()?;
        let k = match config {
            Config::PlusBeta => 0,
            Config::MinusBeta => 1,
        };
        let angle = |(y, x): (f64, f64)| atan2(y, x);
        let theta = branch_theta(
            Self::shoulder_args(&shared, frame, &z5).map(angle),
            self.link_args(&arm, &links[k]).map(angle),
            wrist,
        );
        Some(self.candidate(&theta, root, config, wrist, shared.wrist_singular, elbow_singular))
    }

    /// The labelled, flagged candidate of DH angles `theta`.
    #[inline(always)]
    fn candidate(
        &self,
        theta: &[f64; 6],
        root: &ShoulderRoot,
        config: Config,
        wrist: Wrist,
        wrist_singular: bool,
        elbow_singular: bool,
    ) -> Raw6 {
        let q: [f64; 6] = std::array::from_fn(|i| self.sign[i] * (theta[i] - self.offset[i]));
        let flags = FlagBits::default()
            .with(SingularityKind::Shoulder, root.singular)
            .with(SingularityKind::Elbow, elbow_singular)
            .with(SingularityKind::Wrist, wrist_singular);
        Raw6 { q, values: [root.label.label(), config.label(), wrist.label()], flags }
    }

    /// The flange pose to solve: the pose target, or the target position with the tool
    /// orientation of the seed (else of the home configuration).
    fn pose_of(robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<Isometry3<f64>, IkError> {
        Ok(match target {
            IkTarget::Pose(p) => *p,
            IkTarget::Position(p) => {
                let q = options.seed.clone().unwrap_or_else(|| robot.home());
                let current = robot.fk(&q)?;
                Isometry3::from_parts(nalgebra::Translation3::from(p.coords), current.rotation)
            }
        })
    }
}

/// The keys of the branch labels.
const KEYS: [&str; 3] = ["shoulder", "config", "wrist"];

fn frame_of(t: &Isometry3<f64>) -> Frame {
    let r: Rotation3<f64> = t.rotation.to_rotation_matrix();
    let m = r.matrix();
    Frame {
        p: t.translation.vector,
        x6: m.column(0).into_owned(),
        y6: m.column(1).into_owned(),
        z6: m.column(2).into_owned(),
    }
}

impl LaneSolve for ParallelAxes {
    #[inline(always)]
    fn solve_lanes<const WIDE: bool>(
        &self,
        robot: &Robot,
        target: &IkTarget,
        options: &IkOptions,
        out: &mut IkSolutions,
    ) -> Result<(), IkError> {
        target.validate()?;
        let seed = self.seed_theta(robot, options)?;
        let frame = frame_of(&self.frame.target(robot, &Self::pose_of(robot, target, options)?));
        let (mut candidates, failure) = self.candidates::<WIDE>(&frame, &seed);
        self.frame.refine(robot, target, &mut candidates);
        let if_empty = failure.unwrap_or_else(|| {
            let kind = candidates.iter().find_map(|c| c.flags.first()).unwrap_or(SingularityKind::Jacobian);
            IkFailure::Singular { kind }
        });
        finish_into::<WIDE, _>(robot, target, &mut candidates, NAME, if_empty, out)
    }
}

impl IkSolver for ParallelAxes {
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

    /// Only the requested branch is computed and verified (see [`IkSolver::solve_branch`]).
    /// Two branches can merge (the FK check de-duplicates equal joint vectors) only at a
    /// flagged singularity: the wrist twins differ in the sign of e5 = z4; the two shoulder
    /// roots differ in θ1 by π − 2·asin(sin α1·D/ρ) (or by π on the column axis), below
    /// `IK_DUPLICATE` only far inside the `BOUNDARY` band of the shoulder singularity ρ = |D|;
    /// the configurations ±β differ in θ2, θ3 by about 2β, likewise only inside the band of
    /// the elbow singularity. A singular candidate, or a branch without a verified solution,
    /// falls back to the full solve.
    fn solve_branch(
        &self,
        robot: &Robot,
        target: &IkTarget,
        branch: &Branch,
        options: &IkOptions,
    ) -> Result<IkSolutions, IkError> {
        target.validate()?;
        let seed = self.seed_theta(robot, options)?;
        let labels = (branch.get("shoulder"), branch.get("config"), branch.get("wrist"), branch.0.len());
        let parsed = match labels {
            (Some(s), Some(c), Some(w), 3) => {
                let shoulder = [Shoulder::W, Shoulder::MinusW].into_iter().find(|x| x.label() == s);
                let config = [Config::PlusBeta, Config::MinusBeta].into_iter().find(|x| x.label() == c);
                let wrist = [Wrist::E5, Wrist::MinusE5].into_iter().find(|x| x.label() == w);
                shoulder.zip(config).zip(wrist)
            }
            _ => None,
        };
        if let Some(((shoulder, config), wrist)) = parsed {
            let frame = frame_of(&self.frame.target(robot, &Self::pose_of(robot, target, options)?));
            if let Some(cand) = self.branch_candidate(&frame, &seed, shoulder, config, wrist)
                && cand.flags.is_empty()
            {
                let if_empty = IkFailure::Singular { kind: SingularityKind::Jacobian };
                let mut candidates = Raw6Set::new(KEYS);
                candidates.push(cand);
                self.frame.refine(robot, target, &mut candidates);
                let sols = solved(|out| finish_into::<false, _>(robot, target, &mut candidates, NAME, if_empty, out))?;
                if !sols.solutions.is_empty() {
                    return Ok(sols);
                }
            }
        }
        Ok(self.solve(robot, target, options)?.restricted_to(branch))
    }

    /// The paper's two configurations, `shoulder=w config=+β wrist=e5` (the default) and
    /// `shoulder=w config=−β wrist=e5` (notes 003 §3.7, §4).
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        [Config::PlusBeta, Config::MinusBeta]
            .into_iter()
            .map(|c| {
                Branch::new([("shoulder", Shoulder::W.label()), ("config", c.label()), ("wrist", Wrist::E5.label())])
            })
            .collect()
    }

    fn enumerates_all_branches(&self) -> bool {
        true
    }

    /// Seed 003's measures ([`PathMeasures`]).
    fn singularity_measures(&self, _robot: &Robot, configurations: &[Branch]) -> Option<Box<dyn SingularityMeasures>> {
        Some(Box::new(PathMeasures::new(self.clone(), configurations)))
    }
}

/// Seed 003's closed-form singularity measures along a path (notes 003 §3.6), from
/// [`ParallelAxes::measures`]: for every shoulder/wrist branch the configurations use (a
/// configuration without a `shoulder` or `wrist` pair uses both of that pair), the elbow
/// measure `sign(m)·√|m|` with `m = 1 − |cos θ_elbow|` (0 where |Δ| = 1, negative out of
/// reach) and the wrist measure `sin∠(w, e6)`; then the shoulder measure `(ρ − |D|)/L`, `L`
/// the sum of the DH lengths `|a| + |d|` (at least 1 mm).
#[derive(Debug, Clone)]
pub struct PathMeasures {
    solver: ParallelAxes,
    arms: Vec<(Shoulder, Wrist)>,
    kinds: Vec<SingularityKind>,
    length_scale: f64,
}

impl PathMeasures {
    /// The measures of the shoulder/wrist branches `configurations` use.
    #[must_use]
    pub fn new(solver: ParallelAxes, configurations: &[Branch]) -> Self {
        let mut arms = Vec::new();
        let mut kinds = Vec::new();
        for shoulder in [Shoulder::W, Shoulder::MinusW] {
            for wrist in [Wrist::E5, Wrist::MinusE5] {
                let used = configurations.iter().any(|c| {
                    c.get("shoulder").is_none_or(|v| v == shoulder.label())
                        && c.get("wrist").is_none_or(|v| v == wrist.label())
                });
                if used {
                    arms.push((shoulder, wrist));
                    kinds.extend([SingularityKind::Elbow, SingularityKind::Wrist]);
                }
            }
        }
        kinds.push(SingularityKind::Shoulder);
        let length_scale = solver.a.iter().zip(&solver.d).map(|(a, d)| a.abs() + d.abs()).sum::<f64>().max(1e-3);
        PathMeasures { solver, arms, kinds, length_scale }
    }
}

impl SingularityMeasures for PathMeasures {
    fn kinds(&self) -> &[SingularityKind] {
        &self.kinds
    }

    fn at(&self, robot: &Robot, pose: &Isometry3<f64>) -> Result<Vec<Option<f64>>, IkError> {
        let m = self.solver.measures(robot, pose, &IkOptions::default())?;
        let mut out = Vec::with_capacity(self.kinds.len());
        for &(shoulder, wrist) in &self.arms {
            let arm = m.arm(shoulder, wrist);
            out.push(arm.map(|a| {
                let e = a.elbow_margin();
                e.signum() * e.abs().sqrt()
            }));
            out.push(arm.map(|a| a.wrist_sine));
        }
        out.push(Some(m.shoulder_margin() / self.length_scale));
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;
    use crate::model::{Joint, JointKind};

    #[test]
    fn chace_solves_non_orthogonal_tetrahedra() {
        // Notes 003 §6.2 item 6: the corrected normalisation on non-orthogonal e_i, e_j.
        let cases = [
            (Vector3::new(1.0, 0.0, 0.0), Vector3::new(0.6, 0.8, 0.0), 0.5, 0.3),
            (Vector3::new(0.0, 0.0, 1.0), Vector3::new(0.0, 0.9, 0.19f64.sqrt()), -0.2, 0.7),
            (Vector3::new(0.3, -0.4, 0.866), Vector3::new(0.5, 0.1, 0.8), 0.5, 0.6),
        ];
        for (ei, ej, cik, cjk) in cases {
            let (ei, ej) = (ei.normalize(), ej.normalize());
            let [p, m] = chace(&ei, &ej, cik, cjk).expect("solvable");
            for ek in [p, m] {
                assert!((ek.norm() - 1.0).abs() < 1e-12, "{ek}");
                assert!((ek.dot(&ei) - cik).abs() < 1e-12);
                assert!((ek.dot(&ej) - cjk).abs() < 1e-12);
            }
            assert!(ei.cross(&ej).dot(&p) > 0.0 && ei.cross(&ej).dot(&m) < 0.0);
            // The literally printed form (no /s² on the first terms, /s on the last) is not unit.
            let c_ij = ei.dot(&ej);
            let s = ei.cross(&ej).norm();
            let d = 1.0 - c_ij * c_ij - cik * cik - cjk * cjk + 2.0 * c_ij * cik * cjk;
            let printed = ei * (cik - c_ij * cjk) + ej * (cjk - c_ij * cik) + ei.cross(&ej) * (d.sqrt() / s);
            assert!((printed.dot(&ei) - cik).abs() > 1e-2, "printed form should fail for s_ij ≠ 1");
        }
        // No solution: cosines incompatible with the angle between e_i and e_j.
        assert!(chace(&Vector3::x(), &Vector3::y(), 0.9, 0.9).is_none());
        // Parallel e_i, e_j.
        assert!(chace(&Vector3::x(), &Vector3::x(), 0.5, 0.5).is_none());
    }

    #[test]
    fn accepts_the_family_and_rejects_others() {
        for name in ["welder6r", "ur5"] {
            let robot = presets::get(name).unwrap();
            ParallelAxes::from_robot(&robot).unwrap_or_else(|e| panic!("{name}: {e}"));
        }
        for (name, needle) in [("puma560", "α3"), ("spbu6", "α3"), ("planar3", "6 joints"), ("panda", "7")] {
            let robot = presets::get(name).unwrap();
            let err = ParallelAxes::from_robot(&robot).unwrap_err().to_string();
            assert!(err.contains(needle), "{name}: {err}");
        }
    }

    fn welder_with(change: impl FnOnce(&mut Vec<Joint>)) -> Result<ParallelAxes, IkError> {
        let mut spec = presets::get("welder6r").unwrap().spec().clone();
        change(&mut spec.joints);
        ParallelAxes::from_robot(&Robot::new(spec).unwrap())
    }

    #[test]
    fn names_the_failed_condition() {
        let set = |i: usize, f: fn(&mut crate::model::DhParams)| {
            move |j: &mut Vec<Joint>| {
                if let crate::model::JointGeometry::Dh(p) = &mut j[i].geometry {
                    f(p);
                }
            }
        };
        let err = welder_with(set(4, |p| p.a = 0.01)).unwrap_err().to_string();
        assert!(err.contains("a5"), "{err}");
        let err = welder_with(set(1, |p| p.a = 0.0)).unwrap_err().to_string();
        assert!(err.contains("a2 = 0"), "{err}");
        let err = welder_with(set(0, |p| p.alpha = 0.0)).unwrap_err().to_string();
        assert!(err.contains("α1"), "{err}");
        let err = welder_with(set(1, |p| p.alpha = 0.3)).unwrap_err().to_string();
        assert!(err.contains("α2"), "{err}");
        let err = welder_with(set(3, |p| p.alpha = 1.0)).unwrap_err().to_string();
        assert!(err.contains("α4"), "{err}");
        let err = welder_with(set(4, |p| p.alpha = 0.0)).unwrap_err().to_string();
        assert!(err.contains("α5"), "{err}");
        let err = welder_with(|j| j[2].kind = JointKind::Prismatic).unwrap_err().to_string();
        assert!(err.contains("joint 3"), "{err}");
        // Offsets the method supports.
        welder_with(|j| {
            for (i, joint) in j.iter_mut().enumerate() {
                if let crate::model::JointGeometry::Dh(p) = &mut joint.geometry {
                    p.d += 0.01 * (i as f64 + 1.0);
                    p.theta_offset = 0.1 * i as f64;
                    if i != 4 {
                        p.a += 0.02;
                    }
                }
            }
        })
        .unwrap();
    }

    #[test]
    fn welder_start_point_plus_beta() {
        // Notes 003 §5.3, start P, configuration "+β".
        let robot = presets::get("welder6r").unwrap();
        let solver = ParallelAxes::from_robot(&robot).unwrap();
        let n = Vector3::new(450.0, -540.0, 630.0).normalize();
        let e6 = Vector3::new(540.0, 450.0, 0.0).normalize();
        let l = n.cross(&e6);
        let r = Rotation3::from_matrix_unchecked(nalgebra::Matrix3::from_columns(&[n, e6, l]));
        let pose = Isometry3::from_parts(nalgebra::Translation3::new(0.050, 0.740, 0.070), r.into());
        let all = solver.solve(&robot, &IkTarget::Pose(pose), &IkOptions::default()).unwrap();
        assert_eq!(all.solutions.len(), 8);
        let s = all
            .solutions
            .iter()
            .find(|s| {
                s.branch.get("config") == Some("+β")
                    && s.branch.get("shoulder") == Some("w")
                    && s.branch.get("wrist") == Some("e5")
            })
            .unwrap();
        let expected = [105.2482, -32.9417, 43.3392, -169.6025, -155.4427, 138.1315];
        for (q, e) in s.q.iter().zip(expected) {
            assert!((q.to_degrees() - e).abs() < 1e-4, "{} vs {e}", q.to_degrees());
        }
    }

    #[test]
    fn configurations_are_the_papers_two_and_the_measures_their_arm() {
        use crate::ik::configuration_order::{check, labels};
        for name in ["welder6r", "ur5"] {
            let robot = presets::get(name).unwrap();
            let s = ParallelAxes::from_robot(&robot).unwrap();
            assert!(s.enumerates_all_branches());
            assert_eq!(labels(&s, &robot), ["shoulder=w config=+β wrist=e5", "shoulder=w config=−β wrist=e5"]);
            assert!(check(&s, &robot, 200) > 50, "{name}");
            // The paper's configurations use one arm (w, e5): its elbow and wrist, and the shoulder.
            let m = s.singularity_measures(&robot, &s.configurations(&robot)).unwrap();
            assert_eq!(m.kinds(), [SingularityKind::Elbow, SingularityKind::Wrist, SingularityKind::Shoulder]);
            // Any solution: all four arms.
            let m = s.singularity_measures(&robot, &[Branch::default()]).unwrap();
            assert_eq!(m.kinds().len(), 9);
            // At a pose: the elbow measure is √(1 − |cos θ_elbow|) of the paper's arm.
            let pose = robot.fk(&[0.3, 0.2, 0.9, -1.0, -0.8, 0.4]).unwrap();
            let paper = *s.measures(&robot, &pose, &IkOptions::default()).unwrap().paper().unwrap();
            let values = s.singularity_measures(&robot, &s.configurations(&robot)).unwrap().at(&robot, &pose).unwrap();
            assert!((values[0].unwrap() - paper.elbow_margin().sqrt()).abs() < 1e-15, "{name}");
            assert_eq!(values[1], Some(paper.wrist_sine));
        }
    }
}
