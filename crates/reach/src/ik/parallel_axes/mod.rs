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

mod labels;
mod measures;
mod solve;
#[cfg(test)]
mod tests;

use labels::KEYS;
pub use labels::{Config, Shoulder, Wrist};
pub use measures::{ArmMeasures, PathMeasures, TargetMeasures};
pub use solve::chace;
use solve::frame_of;

use nalgebra::Isometry3;

use super::spherical_wrist::{Dh6, revolute_dh6};
use super::{
    Branch, ChainFrame, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, LaneSolve, Raw6Set,
    SingularityKind, SingularityMeasures, finish_into, solve_at, solved,
};
use crate::kinematics::check_q;
use crate::model::Robot;
use crate::tolerance::{BOUNDARY, STRUCTURE_ANGLE, STRUCTURE_LENGTH};

const NAME: &str = "parallel-axes";

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
