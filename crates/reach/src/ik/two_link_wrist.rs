//! Two-link arm on a ball-joint shoulder with a spherical wrist: seed 001's closed form
//! (Vodolaga 2021, notes 001 §3.3–3.4), corrected and extended to all 8 solutions.
//!
//! # The family
//!
//! Six revolute joints in a standard DH table that chain
//!
//! * a ball-joint shoulder: axes 1 and 2 meet (a1 = 0, d2 = 0) at right angles (α1 = ±90°);
//!   d1 (the height of the shoulder centre) is free;
//! * link 1 of length l1 = a2 ≠ 0 between the parallel axes 2 and 3 (α2 = 0, d3 = 0);
//! * link 2 of length l2 = d4 ≠ 0 along the wrist-roll axis 4 (a3 = 0, α3 = ±90°);
//! * a spherical wrist at the end of link 2 (a4 = a5 = a6 = 0, d5 = 0, α4 = ±90°, α5 = ±90°,
//!   α6 = 0), with the flange d6 along the approach vector (the thesis has d6 = 0: the tool
//!   point is the wrist centre).
//!
//! Joint offsets and flipped joints are free. Seed 001's `spbu6` (l1 = 5, l2 = 3,
//! α = −90, 0, −90, −90, 90, 0°, θ2 offset −90°; notes 001 §2.4) is the model. The
//! `puma560` (lateral offset d3, forearm offset a3) is not: see
//! [`spherical_wrist`](super::spherical_wrist).
//!
//! # The method (notes 001 §3.3–3.4, in the DH frames of the robot)
//!
//! With `p` the wrist centre relative to the shoulder centre (0, 0, d1), `ρ = √(p1² + p2²)`
//! and `r = |p|`:
//!
//! 1. Workspace: `|l1 − l2| ≤ r ≤ l1 + l2`. The thesis states only the outer sphere (its code
//!    even tests `r² ≤ l1² + l2²`, notes 001 §2.6 discrepancies 1–2); the inner bound is
//!    needed because `asin` below leaves its domain.
//! 2. `q1 = atan2(p2, p1)` (front shoulder, the thesis's) or `q1 + π` (back).
//! 3. The elbow from the law of cosines, `|p|² = l1² + l2² + 2·l1·l2·sgn(α3)·sin θ3`:
//!    `θ3 = asin(S)` (the thesis's, cos θ3 ≥ 0) or `π − asin(S)`, with
//!    `S = sgn(α3)·(r² − l1² − l2²)/(2·l1·l2)` — for `spbu6` the thesis's
//!    `q3 = asin((l1² + l2² − r²)/(2·l1·l2))`.
//! 4. The shoulder tilt: `θ2 = atan2(v, u) − atan2(Y, X)`, where `(u, v)` is the wrist centre
//!    in the arm plane of frame 1 and `(X, Y) = (l1 + sgn(α3)·l2·sin θ3, −sgn(α3)·l2·cos θ3)`
//!    the same point in frame 2. For `spbu6` this is the thesis's
//!    `q2 = atan2(ρ, p3) − acos((l1² + r² − l2²)/(2·l1·r))` (polar angle of the wrist centre
//!    minus the shoulder angle of the triangle), without the `acos`.
//! 5. The orientation: `R̃ = (A1·A2·A3)⁻¹·T6 = A3⁻¹·A2⁻¹·A1⁻¹·T6` — the text's order; the
//!    appendix code's `inv(A1)·inv(A2)·inv(A3)·T` is wrong (notes 001 §6.1 item 1). With
//!    α5 = −α4 its rotation is `Rz(θ4)·Ry(−sgn(α4)·θ5)·Rz(θ6)`, a ZYZ Euler rotation
//!    (`spbu6`: `Rz(q4)·Ry(q5)·Rz(q6)`); for α5 = α4 the constant `Rx(180°)` between
//!    frames 5 and 6 is removed first and θ6 changes sign. Then (r_ij of R̃, notes 001 §3.4):
//!    * `r33 ≠ ±1`: `ψ = atan2(±√(r13² + r23²), r33)`, `q4 = atan2(±r23, ±r13)`,
//!      `q6 = atan2(±r32, ∓r31)` (upper signs: the thesis's branch; computed from the residual
//!      rotation `Ry(ψ)ᵀ·Rz(q4)ᵀ·R̃ = Rz(q6)`, the same for exact data but exact also near
//!      the singularity);
//!    * `r33 = ±1` (wrist singularity, detected with the tolerance [`IK_PARALLEL_SINE`] on
//!      `√(r13² + r23²)` rather than the code's exact `switch`, notes 001 §6.1 item 13):
//!      `q6` is kept from `options.seed` (else 0, the thesis's choice) and
//!      `q4 = atan2(r21, r11) − q6` (r33 = 1) or `q4 = atan2(−r12, −r11) + q6` (r33 = −1).
//!
//! The joint range of `spbu6`'s q1 is [0°, 360°]; the solution set moves angles by whole
//! turns into a joint's range, so `q1 = atan2(p2, p1) < 0` is reported as `q1 + 360°`
//! (notes 001 §2.6 discrepancy 3: the thesis flags every target with p2 < 0).
//!
//! # Branches
//!
//! Up to 8 solutions, labelled `shoulder` = `front` / `back`, `elbow` = `up` / `down`,
//! `wrist` = `noflip` / `flip` with the geometric meaning of the
//! [`spherical_wrist`](super::spherical_wrist) docs (`noflip`: DH θ5 ∈ (0, π)). The thesis's
//! single solution (q1 = atan2(p2, p1), cos θ3 ≥ 0, sin q5 > 0) is
//! `shoulder=front elbow=up wrist=noflip` for `spbu6`: at home the elbow (0, 0, 5) lies above
//! the line from the shoulder to the wrist centre (3, 0, 5) (test `thesis_branch_is_front_up_noflip`
//! in `tests/seed_001_ik.rs`).
//!
//! # Singularities
//!
//! * **wrist**: r33 = ±1 (q5 = 0 or 180°), handled as above; one wrist solution per arm branch.
//! * **shoulder**: the wrist centre on the base axis (ρ < [`IK_AXIS_DISTANCE`]): q1 is kept
//!   from the seed (else 0); the front and back shoulders coincide.
//! * **elbow**: `|S|` within [`BOUNDARY`] of 1 (arm stretched or folded).
//!
//! # Failure reasons
//!
//! `Unreachable { distance: r, reach }` with `reach = l1 + l2` (outside the sphere) or
//! `|l1 − l2|` (inside the inner sphere).
//!
//! # Position-only targets
//!
//! The tool orientation of `options.seed` (else of the home configuration) is kept and that
//! pose is solved (for `spbu6` the tool point is the wrist centre, so the arm angles do not
//! depend on that choice).

use std::f64::consts::PI;

use nalgebra::{IsometryMatrix3, Point3, Rotation3};

use super::spherical_wrist::{
    ARM_KEYS, Arm, Arms, Dh6, DhJoint, arm_branch, arm_configurations, elbow_label, fallback_failure, flange_goal,
    free_theta, is_zero_length, joint_values, require_spherical_wrist, revolute_dh6, seed_thetas, unsupported,
    wrist_arm_twists, wrist_centre, wrist_label,
};
use super::{
    Branch, ChainFrame, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, LaneSolve, Raw6, Raw6Set,
    SingularityKind, finish_into, solve_at, solved,
};
use crate::angle::{atan2, sin_cos};
use crate::model::Robot;
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, IK_PARALLEL_SINE};

const NAME: &str = "two-link-wrist";

/// Closed-form IK for a two-link arm with a ball-joint shoulder and a spherical wrist
/// (seed 001; see the module docs).
///
/// # Example
/// ```
/// use reach::ik::{IkOptions, IkSolver, IkTarget, two_link_wrist::TwoLinkWrist};
/// let spbu6 = reach::model::presets::get("spbu6").unwrap();
/// let solver = TwoLinkWrist::from_robot(&spbu6).unwrap();
/// assert_eq!((solver.l1(), solver.l2()), (5.0, 3.0));
/// let q = [1.0, 0.5, -0.3, 0.4, 0.8, -0.6]; // notes 001 §5.2
/// let target = IkTarget::Pose(spbu6.fk(&q).unwrap());
/// let all = solver.solve(&spbu6, &target, &IkOptions::default()).unwrap();
/// assert_eq!(all.solutions.len(), 8);
/// assert!(all.solutions.iter().any(|s| s.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9)));
/// ```
#[derive(Debug, Clone)]
pub struct TwoLinkWrist {
    joints: [DhJoint; 6],
    /// The DH chain relative to the robot's base and tool.
    frame: ChainFrame,
    /// sgn α1, sgn α3, sgn α4.
    s1: f64,
    s3: f64,
    s4: f64,
    /// +1 when α5 = −α4 (R̃ is a plain ZYZ rotation), −1 when α5 = α4 (θ6 reversed).
    s6: f64,
}

impl TwoLinkWrist {
    /// Checks that `robot` belongs to the family of the module docs and extracts l1, l2 and
    /// the sign conventions.
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition (convention, joint count or kind,
    /// non-spherical wrist, a twist that is not 0°/±90°, a shoulder or forearm offset, a zero
    /// link).
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
            ("ball-joint axes 1 and 2 perpendicular", "link 2 perpendicular to the elbow axis 3"),
        )?;
        for (name, value, why) in [
            ("a1", joints[0].a, "axes 1 and 2 do not meet (no ball-joint shoulder)"),
            ("d2", joints[1].d, "lateral shoulder offset"),
            ("d3", joints[2].d, "lateral shoulder offset"),
            ("a3", joints[2].a, "forearm offset: link 2 is not along the wrist axis 4"),
        ] {
            if !is_zero_length(value) {
                return fail(format!("{name} = {value} m ≠ 0: {why}"));
            }
        }
        if is_zero_length(joints[1].a) {
            return fail("a2 = 0: no link 1".into());
        }
        if is_zero_length(joints[3].d) {
            return fail("d4 = 0: no link 2".into());
        }
        Ok(TwoLinkWrist { joints, frame: table.frame, s1, s3, s4, s6: if s5 == -s4 { 1.0 } else { -1.0 } })
    }

    /// Length of link 1 (`a2`), metres.
    #[must_use]
    pub fn l1(&self) -> f64 {
        self.joints[1].a
    }

    /// Length of link 2 (`d4`), metres.
    #[must_use]
    pub fn l2(&self) -> f64 {
        self.joints[3].d
    }

    /// The arm solutions for the wrist centre `w` (steps 1–4 of the module docs).
    fn arms(&self, w: &Point3<f64>, seed: Option<&[f64; 6]>) -> Result<Arms, IkFailure> {
        let (l1, l2) = (self.l1(), self.l2());
        let p = w.coords - nalgebra::Vector3::new(0.0, 0.0, self.joints[0].d);
        let r = p.norm();
        let (outer, inner) = (l1.abs() + l2.abs(), (l1.abs() - l2.abs()).abs());
        if r > outer * (1.0 + BOUNDARY) {
            return Err(IkFailure::Unreachable {
                distance: r,
                reach: outer,
                point: "the wrist centre",
                from: "the shoulder",
            });
        }
        if r < inner * (1.0 - BOUNDARY) {
            return Err(IkFailure::Unreachable {
                distance: r,
                reach: inner,
                point: "the wrist centre",
                from: "the shoulder",
            });
        }
        let rho = p.x.hypot(p.y);
        let shoulder_singular = rho < IK_AXIS_DISTANCE;
        // (θ1, u): the thesis's q1 = atan2(p2, p1) with u = ρ, and the back shoulder; on the
        // base axis θ1 is undetermined (kept from the seed) and both coincide.
        let q1 = atan2(p.y, p.x);
        let shoulders: &[(f64, f64, &str)] = if shoulder_singular {
            &[(free_theta(&self.joints, seed, 0), 0.0, "front")]
        } else {
            &[(q1, rho, "front"), (q1 + PI, -rho, "back")]
        };
        let v = self.s1 * p.z;
        let sin3 = (self.s3 * (r * r - l1 * l1 - l2 * l2) / (2.0 * l1 * l2)).clamp(-1.0, 1.0);
        let elbow_singular = 1.0 - sin3.abs() <= BOUNDARY || r <= IK_AXIS_DISTANCE;
        let t3 = sin3.asin();
        let mut arms = Arms::new();
        for &(theta1, u, shoulder) in shoulders {
            for theta3 in [t3, PI - t3] {
                let (s, c) = sin_cos(theta3);
                let (x, y) = (l1 + self.s3 * l2 * s, -self.s3 * l2 * c);
                let theta2 = if r > IK_AXIS_DISTANCE {
                    atan2(v, u) - atan2(y, x)
                } else {
                    // Folded onto the shoulder centre (l1 = l2): θ2 undetermined.
                    free_theta(&self.joints, seed, 1)
                };
                let (s2, c2) = sin_cos(theta2);
                let e = (l1 * c2, l1 * s2);
                arms.push(Arm {
                    theta: [theta1, theta2, theta3],
                    sin_cos: [sin_cos(theta1), (s2, c2), (s, c)],
                    shoulder,
                    elbow: elbow_label(self.s1, u, u, v, e),
                    shoulder_singular,
                    elbow_singular,
                });
            }
        }
        Ok(arms)
    }

    /// The wrist solutions of one arm branch (step 5), appended to `out`.
    fn wrists(&self, arm: &Arm, flange: &IsometryMatrix3<f64>, seed: Option<&[f64; 6]>, out: &mut Raw6Set) {
        let [t1, t2, t3] = arm.theta;
        // R̃ = (A1·A2·A3)⁻¹·T6, the correct order (notes 001 §6.1 item 1).
        let mut m = Rotation3::from_matrix_unchecked(arm.r03(&self.joints).transpose()) * flange.rotation;
        if self.s6 < 0.0 {
            // α5 = α4: remove the constant Rx(180°) (negate columns y and z).
            let mm = m.matrix_mut_unchecked();
            for r in 0..3 {
                mm[(r, 1)] = -mm[(r, 1)];
                mm[(r, 2)] = -mm[(r, 2)];
            }
        }
        let m = m.matrix();
        let hyp = m[(0, 2)].hypot(m[(1, 2)]);
        let mut push = |euler: [f64; 3], singular: bool| {
            let [phi, psi, chi] = euler;
            let theta5 = -self.s4 * psi;
            let theta = [t1, t2, t3, phi, theta5, self.s6 * chi];
            let wrist = if singular { "noflip" } else { wrist_label(theta5) };
            let flags = arm.flags().with(SingularityKind::Wrist, singular);
            out.push(Raw6 { q: joint_values(&self.joints, &theta), values: [arm.shoulder, arm.elbow, wrist], flags });
        };
        if hyp < IK_PARALLEL_SINE {
            // r33 = ±1: only q4 ± q6 is determined; keep q6 (seed, else 0 — the thesis's rule).
            let chi = self.s6 * free_theta(&self.joints, seed, 5);
            if m[(2, 2)] > 0.0 {
                push([atan2(m[(1, 0)], m[(0, 0)]) - chi, 0.0, chi], true);
            } else {
                push([atan2(-m[(0, 1)], -m[(0, 0)]) + chi, PI, chi], true);
            }
            return;
        }
        for k in [1.0, -1.0] {
            let psi = atan2(k * hyp, m[(2, 2)]);
            let phi = atan2(k * m[(1, 2)], k * m[(0, 2)]);
            // The thesis's q6 = atan2(±r32, ∓r31), taken from the residual rotation
            // Ry(ψ)ᵀ·Rz(φ)ᵀ·R̃ = Rz(χ) instead: identical for exact data, and it absorbs the
            // round-off of φ near the singularity (≈ 1e-16/sin ψ), keeping the pose exact.
            let (sp, cp) = sin_cos(phi);
            let (ss, cs) = sin_cos(psi);
            let p00 = cp * m[(0, 0)] + sp * m[(1, 0)];
            let p10 = -sp * m[(0, 0)] + cp * m[(1, 0)];
            let chi = atan2(p10, cs * p00 - ss * m[(2, 0)]);
            debug_assert!(
                crate::angle::wrap(chi - (k * m[(2, 1)]).atan2(-k * m[(2, 0)])).abs() < 1e-6 || hyp < 1e-6,
                "residual χ agrees with the thesis's formula"
            );
            push([phi, psi, chi], false);
        }
    }
}

impl LaneSolve for TwoLinkWrist {
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
        let arms = match self.arms(&w, seed.as_ref()) {
            Ok(arms) => arms,
            Err(failure) => {
                return finish_into::<WIDE, _>(robot, target, &mut Raw6Set::new(ARM_KEYS), NAME, failure, out);
            }
        };
        let mut candidates = Raw6Set::new(ARM_KEYS);
        for arm in &arms {
            self.wrists(arm, &flange, seed.as_ref(), &mut candidates);
        }
        self.frame.refine(robot, target, &mut candidates);
        finish_into::<WIDE, _>(robot, target, &mut candidates, NAME, fallback_failure(&arms), out)
    }
}

impl IkSolver for TwoLinkWrist {
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

    /// Only the requested branch's arm and wrist are verified (see
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
        if let Ok(arms) = self.arms(&w, seed.as_ref())
            && let Some(sols) = arm_branch(robot, &self.frame, target, branch, NAME, &arms, |arm, out| {
                self.wrists(arm, &flange, seed.as_ref(), out);
            })?
        {
            return Ok(sols);
        }
        Ok(self.solve(robot, target, options)?.restricted_to(branch))
    }

    /// The eight branches in the order [`IkSolver::solve`] returns them: `front`, then `back`;
    /// per shoulder the elbow of `θ3 = asin(…)` first (`up` when
    /// `sgn(u)·sgn(α1)·sgn(α3)·sgn(l1·l2) > 0`, `u` = ±ρ the shoulder's reach), then the other;
    /// per elbow the wrist of `ψ ∈ (0, π)` first (`noflip` when `sgn(α4) < 0`).
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        let sign = self.s1 * self.s3 * (self.l1() * self.l2()).signum();
        arm_configurations(["front", "back"], [sign > 0.0, sign < 0.0], self.s4 < 0.0)
    }

    fn enumerates_all_branches(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ik::SolverKind;
    use crate::model::presets;

    #[test]
    fn reads_spbu6() {
        let s = TwoLinkWrist::from_robot(&presets::get("spbu6").unwrap()).unwrap();
        assert_eq!((s.l1(), s.l2()), (5.0, 3.0));
        assert_eq!((s.s1, s.s3, s.s4, s.s6), (-1.0, -1.0, -1.0, 1.0));
        assert_eq!(s.name(), SolverKind::TwoLinkWrist.as_str());
    }

    #[test]
    fn rejects_offset_arms() {
        for (name, needle) in [("puma560", "d3"), ("ur5", "d5"), ("panda", "7"), ("log-loader", "6 joints")] {
            let err = TwoLinkWrist::from_robot(&presets::get(name).unwrap()).unwrap_err().to_string();
            assert!(err.contains(needle), "{name}: {err}");
        }
    }

    #[test]
    fn singular_wrist_keeps_the_seeds_q6() {
        let robot = presets::get("spbu6").unwrap();
        let s = TwoLinkWrist::from_robot(&robot).unwrap();
        let target = IkTarget::Pose(robot.fk(&[0.0; 6]).unwrap());
        let options = IkOptions { seed: Some(vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.4]), ..IkOptions::default() };
        let all = s.solve(&robot, &target, &options).unwrap();
        let sol = all.solutions.iter().find(|s| s.q[..3].iter().all(|v| v.abs() < 1e-12)).unwrap();
        assert!((sol.q[5] - 0.4).abs() < 1e-12 && (sol.q[3] + 0.4).abs() < 1e-12, "{:?}", sol.q);
        assert!(sol.singularities.contains(&SingularityKind::Wrist));
    }

    #[test]
    fn configurations_are_the_eight_branches_in_the_order_of_the_solve() {
        use crate::ik::configuration_order::{check, labels};
        use crate::model::{Convention, Joint, RobotSpec};
        let spbu6 = presets::get("spbu6").unwrap();
        let s = TwoLinkWrist::from_robot(&spbu6).unwrap();
        assert!(s.enumerates_all_branches());
        let expected: Vec<String> = [("front", "up"), ("front", "down"), ("back", "down"), ("back", "up")]
            .into_iter()
            .flat_map(|(sh, el)| ["noflip", "flip"].map(|w| format!("shoulder={sh} elbow={el} wrist={w}")))
            .collect();
        assert_eq!(labels(&s, &spbu6), expected);
        assert!(check(&s, &spbu6, 200) > 100);
        // The order follows the signs of α1, α3, α4 and the link lengths.
        let arm = |alpha1: f64, l1: f64, alpha3: f64, l2: f64, alpha4: f64| {
            let r = |a: f64, alpha_deg: f64, d: f64, theta_deg: f64| {
                Joint::revolute(a, alpha_deg.to_radians(), d, theta_deg.to_radians())
            };
            Robot::new(RobotSpec::new(
                "arm",
                Convention::Dh,
                vec![
                    r(0.0, alpha1, 0.0, 0.0),
                    r(l1, 0.0, 0.0, -90.0),
                    r(0.0, alpha3, 0.0, 0.0),
                    r(0.0, alpha4, l2, 0.0),
                    r(0.0, -alpha4, 0.0, 0.0),
                    r(0.0, 0.0, 0.0, 0.0),
                ],
            ))
            .unwrap()
        };
        for (alpha1, l1, alpha3, l2, alpha4, first) in [
            (-90.0, 5.0, -90.0, 3.0, -90.0, "shoulder=front elbow=up wrist=noflip"),
            (90.0, 5.0, -90.0, 3.0, -90.0, "shoulder=front elbow=down wrist=noflip"),
            (-90.0, 5.0, 90.0, 3.0, -90.0, "shoulder=front elbow=down wrist=noflip"),
            (-90.0, -5.0, -90.0, 3.0, 90.0, "shoulder=front elbow=down wrist=flip"),
            (-90.0, 5.0, -90.0, -3.0, 90.0, "shoulder=front elbow=down wrist=flip"),
        ] {
            let robot = arm(alpha1, l1, alpha3, l2, alpha4);
            let s = TwoLinkWrist::from_robot(&robot).unwrap();
            let what = format!("α1 = {alpha1}°, l1 = {l1}, α3 = {alpha3}°, l2 = {l2}, α4 = {alpha4}°");
            assert_eq!(labels(&s, &robot)[0], first, "{what}");
            assert!(check(&s, &robot, 100) > 30, "{what}");
        }
    }
}
