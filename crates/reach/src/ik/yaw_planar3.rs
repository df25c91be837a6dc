//! Seed 004: a base yaw plus a planar three-link arm in a vertical plane (`varan4`).
//!
//! # The arm
//!
//! Joint 1 turns about z of the chain frame; joints 2, 3 and 4 have parallel horizontal axes
//! (perpendicular to joint 1's) and move the links in the *arm plane*, which turns with
//! joint 1 (notes 004 §2.2: `q1` azimuth, `q2` absolute angle of the first link from the
//! horizontal, `q3`, `q4` relative angles). The structure is read from the compiled chain, with
//! the same freedoms as [`super::yaw_two_link`]: shoulder offsets in the arm plane, a sideways
//! offset of the plane from the yaw axis, any description convention.
//!
//! # Solutions
//!
//! A position leaves one redundant degree of freedom, exposed as `φ`, the absolute angle of the
//! last link in the arm plane measured from the outward horizontal towards the vertical (for
//! `varan4`: `φ = q2 + q3 + q4`). For each base branch (`base=front|back`, see
//! [`super::yaw_two_link`]) and each `φ`, the wrist point is fixed and a two-link IK gives
//! `elbow=up|down`.
//!
//! * [`IkTarget::Position`] with [`IkOptions::free_parameter`] `= Some(φ)`: up to four
//!   solutions; without it, the self-motion sampled at [`IkOptions::redundancy_step`] over its
//!   feasible intervals ([`YawPlanar3::feasible_intervals`]), labelled `phi_deg=…`.
//! * [`IkTarget::Pose`]: the orientation fixes `φ` (and the base angle on the yaw axis): up to
//!   four solutions; an orientation the arm cannot take gives `OrientationUnreachable`.
//!
//! Singularities: `shoulder` (target on the yaw axis; base angle from the orientation, the
//! seed, or 0), `elbow` (links 2 and 3 aligned: the ends of the feasible `φ` intervals).
//! Failure reasons: `Unreachable` (distance from the shoulder against the annulus
//! `max(0, l_max − others) … l2 + l3 + l4`), `OrientationUnreachable` (reachable, but not with
//! the requested `φ` or orientation), `OutsideLimits`.

use nalgebra::Point3;

use super::planar::{
    PhiInterval, PlanarChain, TwoLink, check_options, check_step, elbow_label, phi_intervals, phi_label,
    sample_intervals, two_link,
};
use super::yaw_two_link::{YawBranch, YawFrame, read_yaw_arm, yaw_configurations};
use super::{
    Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, finish,
};
use crate::model::Robot;
use crate::tolerance::BOUNDARY;

const NAME: &str = "yaw-planar3";

/// Closed-form IK of a base yaw plus a planar three-link arm (seed 004, `varan4`), with the
/// redundancy parameterised by the absolute angle of the last link. See the
/// [module docs](self).
#[derive(Debug, Clone)]
pub struct YawPlanar3 {
    yaw: YawFrame,
    chain: PlanarChain<3>,
}

impl YawPlanar3 {
    /// Reads the arm from `robot`: four revolute joints, joint 2's axis perpendicular to
    /// joint 1's, joints 3 and 4 parallel to joint 2 (same direction), links 2 and 3 of
    /// non-zero length in the arm plane (link 4 may be zero).
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let (yaw, chain) = read_yaw_arm::<3>(robot, NAME, 2)?;
        Ok(YawPlanar3 { yaw, chain })
    }

    /// Lengths of the three arm links (joint 2 → 3, 3 → 4, 4 → tool point), metres.
    #[must_use]
    pub fn lengths(&self) -> [f64; 3] {
        self.chain.lengths()
    }

    /// The redundancy parameter `φ` of joint values `q` (4 values): the absolute angle of the
    /// last link in the arm plane, from the outward horizontal towards the vertical.
    #[must_use]
    pub fn last_link_angle(&self, q: &[f64; 4]) -> f64 {
        self.chain.link_angles(&q[1..])[2] + self.yaw.kappa
    }

    /// The feasible intervals of `φ` for a world target, joint limits ignored: `[front, back]`
    /// (the back branch is empty on the yaw axis, where there is one base branch; both are
    /// empty when the target is out of reach).
    #[must_use]
    pub fn feasible_intervals(&self, world: &Point3<f64>) -> [Vec<PhiInterval>; 2] {
        let t = self.yaw.local(world);
        let mut out = [Vec::new(), Vec::new()];
        if let Ok(branches) = self.yaw.branches(&t, 0.0) {
            for (slot, b) in out.iter_mut().zip(branches) {
                if let Some(b) = b {
                    *slot = self.intervals(&b, &t);
                }
            }
        }
        out
    }

    fn intervals(&self, b: &YawBranch, t: &Point3<f64>) -> Vec<PhiInterval> {
        let [l2, l3, l4] = self.lengths();
        phi_intervals(l2, l3, l4, self.yaw.in_plane(b, t))
    }

    /// Candidates of base branch `b` whose last link points at `phi` (arm-plane angle).
    fn at_phi(&self, b: &YawBranch, t: &Point3<f64>, phi: f64, seed_phi: f64, out: &mut Vec<Candidate>) {
        let [l2, l3, l4] = self.lengths();
        let p = self.yaw.in_plane(b, t);
        let w = [p[0] - l4 * phi.cos(), p[1] - l4 * phi.sin()];
        let TwoLink::In(sols) = two_link(l2, l3, w, seed_phi) else { return };
        let (base, reach_sign) = b.label();
        let k = self.yaw.kappa;
        for e in sols.into_iter().flatten() {
            let qp = self.chain.joints(&[e.phi[0] - k, e.phi[1] - k, phi - k]);
            let q = vec![self.yaw.yaw_sign * b.theta1, qp[0], qp[1], qp[2]];
            let label = Branch::new([
                ("base", base.to_string()),
                ("phi_deg", phi_label(phi)),
                ("elbow", elbow_label(&e, reach_sign).to_string()),
            ]);
            let mut c = Candidate::new(q, label);
            if b.singular {
                c.singularities.push(SingularityKind::Shoulder);
            }
            if let Some(s) = e.singular
                && !c.singularities.contains(&s)
            {
                c.singularities.push(s);
            }
            out.push(c);
        }
    }

    /// Why a target with base branch `b` is out of reach (annulus of the planar part).
    fn unreachable(&self, b: &YawBranch, t: &Point3<f64>) -> Option<IkFailure> {
        let l = self.lengths();
        let p = self.yaw.in_plane(b, t);
        let r = p[0].hypot(p[1]);
        let outer = l[0] + l[1] + l[2];
        let inner = (2.0 * l[0].max(l[1]).max(l[2]) - outer).max(0.0);
        if r > outer * (1.0 + BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: outer, point: "the target", from: "joint 2" })
        } else if r < inner * (1.0 - BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: inner, point: "the target", from: "joint 2" })
        } else {
            None
        }
    }
}

impl IkSolver for YawPlanar3 {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
        target.validate()?;
        check_options(robot, options)?;
        let t = self.yaw.local(&target.position());
        let seed = options.seed.as_deref();
        let r_local = match target {
            IkTarget::Pose(pose) => Some(self.yaw.first.rotation.inverse() * pose.rotation.to_rotation_matrix()),
            IkTarget::Position(_) => None,
        };
        // On the yaw axis the base angle is free: from the orientation, else the seed, else 0.
        let fallback = r_local
            .as_ref()
            .and_then(|r| self.yaw.theta1_from_orientation(r, &self.chain.last_rotation))
            .unwrap_or_else(|| seed.map_or(0.0, |s| self.yaw.yaw_sign * s[0]));
        let seed_phi = seed.map_or(0.0, |s| self.chain.link_angles(&s[1..])[0] + self.yaw.kappa);
        if r_local.is_none() && options.free_parameter.is_none() {
            check_step(options)?;
        }
        let branches = match self.yaw.branches(&t, fallback) {
            Ok(b) => b,
            Err(failure) => return finish(robot, target, &mut [], NAME, failure),
        };
        let mut candidates = Vec::new();
        let mut failure = None;
        for b in branches.iter().flatten() {
            match (&r_local, options.free_parameter) {
                (Some(r), _) => {
                    let heading = self.yaw.planar_heading(b.theta1, r, &self.chain.last_rotation);
                    let phi = self.chain.heading_to_last_angle(heading) + self.yaw.kappa;
                    self.at_phi(b, &t, phi, seed_phi, &mut candidates);
                }
                (None, Some(phi)) => self.at_phi(b, &t, phi, seed_phi, &mut candidates),
                (None, None) => {
                    for phi in sample_intervals(&self.intervals(b, &t), options.redundancy_step) {
                        self.at_phi(b, &t, phi, seed_phi, &mut candidates);
                    }
                }
            }
            if failure.is_none() {
                failure = self.unreachable(b, &t);
            }
        }
        let reachable = branches.iter().flatten().any(|b| self.unreachable(b, &t).is_none());
        let if_empty = if reachable {
            IkFailure::OrientationUnreachable
        } else {
            failure.unwrap_or(IkFailure::OrientationUnreachable)
        };
        finish(robot, target, &mut candidates, NAME, if_empty)
    }

    /// The four base and elbow branches in the order [`IkSolver::solve`] returns them
    /// (`yaw_configurations`); the labels also carry the last link's angle (`phi_deg=…`,
    /// sampled for a position target), which these filters leave free.
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        yaw_configurations()
    }

    /// `false`: the labels of a position target carry the sampled redundancy parameter, which
    /// changes from one target to the next, so a path is followed by nearness.
    fn enumerates_all_branches(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn reads_the_preset() {
        let robot = presets::get("varan4").unwrap();
        let s = YawPlanar3::from_robot(&robot).unwrap();
        let l = s.lengths();
        assert!((l[0] - 0.9).abs() < 1e-12 && (l[1] - 0.7).abs() < 1e-12 && (l[2] - 0.5).abs() < 1e-12);
        let q = [0.1, 0.2, 0.3, -0.4];
        assert!((s.last_link_angle(&q) - 0.1).abs() < 1e-15);
    }

    #[test]
    fn rejects_other_structures() {
        for name in ["planar3", "log-loader", "puma560", "spbu6", "ur5", "panda", "welder6r"] {
            let robot = presets::get(name).unwrap();
            let err = YawPlanar3::from_robot(&robot).unwrap_err();
            assert!(matches!(err, IkError::Unsupported { .. }), "{name}: {err}");
        }
    }

    #[test]
    fn configurations_are_the_four_base_and_elbow_branches_in_the_order_of_the_solve() {
        use crate::ik::configuration_order::{check, check_with, labels};
        let robot = presets::get("varan4").unwrap();
        let s = YawPlanar3::from_robot(&robot).unwrap();
        assert_eq!(
            labels(&s, &robot),
            ["base=front elbow=up", "base=front elbow=down", "base=back elbow=down", "base=back elbow=up"]
        );
        // A pose fixes the base: two solutions, in order.
        assert_eq!(check(&s, &robot, 100), 0);
        // A position with the last link's angle given: all four, in order.
        let options = IkOptions { free_parameter: Some(-0.3), ..IkOptions::default() };
        let complete = check_with(&s, &robot, 200, true, &options);
        assert!(complete > 20, "{complete}");
        // The labels carry the last link's angle (`phi_deg`): not one label per branch.
        assert!(!s.enumerates_all_branches());
    }
}
