//! Seed 000: the planar redundant three-link arm (`planar3`) — its self-motion in closed form
//! and the thesis's α-scan.
//!
//! # The arm
//!
//! Three revolute joints whose axes are parallel (and point the same way); the tool point
//! moves in a plane normal to them. The structure is read from the compiled chain, so any
//! description fits: standard or modified DH, URDF, base and tool transforms, angle offsets,
//! flipped joints, and arbitrary link lengths `l1, l2, l3` (the thesis has three equal links).
//! The *plane frame* is the frame in which joint 1 turns about z (the base frame for the
//! `planar3` preset); the *absolute link angles* `φ1, φ2, φ3` are the directions of the links
//! (joint 1 → joint 2, joint 2 → joint 3, joint 3 → tool point) from its x axis. For `planar3`
//! `φ1 = q1`, `φ2 = q1 + q2`, `φ3 = q1 + q2 + q3`.
//!
//! # The redundancy
//!
//! A position target leaves one degree of freedom. It is parameterised by `φ = φ3`, the
//! absolute angle of the last link: for each `φ` the wrist point `W = p − l3·(cos φ, sin φ)` is
//! fixed and a two-link IK gives two elbow branches. `W` is reachable when
//! `|l1 − l2| ≤ |W| ≤ l1 + l2`; with `|W|² = r² + l3² − 2·r·l3·cos(φ − ψ)` (`r, ψ` the polar
//! coordinates of the target) this is `c_lo ≤ cos(φ − ψ) ≤ c_hi`, so the feasible `φ` form at
//! most two intervals symmetric about `ψ` ([`PlanarRedundant::feasible_intervals`]). At their
//! ends the elbow is stretched or folded (a singularity). The workspace is the annulus
//! `max(0, l_max − (sum of the other two)) ≤ r ≤ l1 + l2 + l3`.
//!
//! # The thesis's method
//!
//! [`PlanarRedundant::paper_scan`] reproduces the thesis's enumeration (notes 000 §3.1, §4.1):
//! the interior angle `α` at joint A is stepped from `α_min` (eq. 3) to 180°, and `γ`, `β`
//! follow from the law-of-cosines formulas (6)–(14) with the corrected `γ2 = atan2(y, x)`
//! (notes 000 §6.1, D1). [`PaperScan::select_min_s`] picks the row of least total joint change
//! `S` (notes 000 §6.3). The paper's angle convention is [`InteriorAngles`].

mod geometry;
mod labels;
mod scan;
mod scan_kernel;
#[cfg(test)]
mod tests;

pub use geometry::PhiInterval;
pub(crate) use geometry::{Elbow, PlanarChain, TwoLink, phi_intervals, sample_intervals, two_link};
pub(crate) use labels::{elbow_label, phi_label};
pub use scan::{PaperScan, ScanRow};
use std::f64::consts::TAU;

use nalgebra::{IsometryMatrix3, Point3};

use super::{Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, finish};
use crate::kinematics::KinematicsError;
use crate::model::{Limits, Robot};
use crate::tolerance::{BOUNDARY, IK_POSITION, STRUCTURE_LENGTH};

const NAME: &str = "planar";

/// Most rows [`PlanarRedundant::paper_scan`] builds (≈ 64 MB of rows): a step of 0.0001°
/// (ten times finer than the finest step of the thesis) still fits.
pub const MAX_SCAN_ROWS: usize = 1_000_000;

/// Most self-motion samples per full turn of the redundancy parameter (a step of at least
/// 0.1°). Every sample yields up to two (four with a base yaw) candidates, and the solution
/// set is de-duplicated pairwise, so the cost grows with the square of this number.
pub const MAX_SELF_MOTION_SAMPLES: usize = 3600;

/// Validates the options shared by the planar and yaw solvers.
pub(crate) fn check_options(robot: &Robot, options: &IkOptions) -> Result<(), IkError> {
    if let Some(seed) = &options.seed {
        if seed.len() != robot.dof() {
            return Err(KinematicsError::JointCount { expected: robot.dof(), found: seed.len() }.into());
        }
        if let Some((i, &v)) = seed.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { joint: i + 1, value: v }.into());
        }
    }
    if let Some(phi) = options.free_parameter
        && !phi.is_finite()
    {
        return Err(IkError::InvalidInput(format!("free_parameter must be finite, got {phi}")));
    }
    Ok(())
}

/// Validates [`IkOptions::redundancy_step`] before the self-motion is sampled.
pub(crate) fn check_step(options: &IkOptions) -> Result<(), IkError> {
    let step = options.redundancy_step;
    let min_step = TAU / MAX_SELF_MOTION_SAMPLES as f64;
    if !(step.is_finite() && step >= min_step * (1.0 - BOUNDARY)) {
        return Err(IkError::InvalidInput(format!(
            "redundancy_step must be a finite angle of at least {:.3}° ({MAX_SELF_MOTION_SAMPLES} samples per turn), got {step} rad",
            min_step.to_degrees()
        )));
    }
    Ok(())
}

/// Closed-form IK of a planar arm of three parallel revolute joints (seed 000, `planar3`),
/// with its self-motion parameterised by the absolute angle of the last link.
///
/// * [`IkTarget::Pose`]: position in the arm's plane and the in-plane heading of the tool
///   (the target orientation must be the tool's orientation turned about the plane normal):
///   up to two solutions, `elbow=up` / `elbow=down`.
/// * [`IkTarget::Position`]: with [`IkOptions::free_parameter`] `= Some(φ)` the (up to two)
///   solutions whose last link points at `φ`; otherwise the self-motion sampled at
///   [`IkOptions::redundancy_step`] over its feasible intervals, both branches, each labelled
///   `phi_deg=… elbow=…`.
///
/// Failure reasons: `Unreachable` (outside the annulus, with the violated radius; or off the
/// arm's plane, with `distance` = the offset and `reach` = 0), `OrientationUnreachable` (the
/// position is reachable but not with the requested heading or `φ`), `OutsideLimits`.
/// Singular flags: `elbow` (links 1 and 2 within `acos(1 − BOUNDARY)` ≈ 2.6e-3° of aligned,
/// e.g. at the ends of the feasible `φ` intervals: exactly there one solution labelled
/// `elbow=stretched` or `elbow=folded`, near there both exact branches), `shoulder` (wrist on
/// the joint-1 axis with `l1 = l2`: φ1 is free and taken from the seed, else 0).
///
/// Sampled self-motions contain every sample, within limits or not (flagged by
/// [`IkSolution::within_limits`](super::IkSolution::within_limits)); the step must allow at
/// most [`MAX_SELF_MOTION_SAMPLES`] samples per turn.
#[derive(Debug, Clone)]
pub struct PlanarRedundant {
    chain: PlanarChain<3>,
    first: IsometryMatrix3<f64>,
    limits: [Limits; 3],
}

impl PlanarRedundant {
    /// Reads the arm from `robot`: three revolute joints, axes 2 and 3 parallel to axis 1 and
    /// pointing the same way, links 1 and 2 of non-zero length (link 3 may be zero).
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let unsupported =
            |reason: String| IkError::Unsupported { solver: NAME, robot: robot.name().to_string(), reason };
        if robot.dof() != 3 {
            return Err(unsupported(format!("needs exactly 3 joints, the robot has {}", robot.dof())));
        }
        if robot.chain.has_mimics() {
            return Err(unsupported("the chain has mimic joints".into()));
        }
        let chain = PlanarChain::<3>::from_chain(&robot.chain.links, 1).map_err(unsupported)?;
        for (i, l) in chain.links.iter().take(2).enumerate() {
            if l.length <= STRUCTURE_LENGTH {
                return Err(unsupported(format!("link {} has zero length in the plane", i + 1)));
            }
        }
        let j = robot.joints();
        Ok(PlanarRedundant { chain, first: robot.chain.first, limits: [j[0].limits, j[1].limits, j[2].limits] })
    }

    /// Link lengths `[l1, l2, l3]` (metres).
    #[must_use]
    pub fn lengths(&self) -> [f64; 3] {
        self.chain.lengths()
    }

    /// Inner and outer radius of the workspace annulus: `max(0, l_max − (sum of the others))`
    /// and `l1 + l2 + l3` (joint limits ignored).
    #[must_use]
    pub fn workspace(&self) -> (f64, f64) {
        let l = self.lengths();
        let sum = l[0] + l[1] + l[2];
        let max = l[0].max(l[1]).max(l[2]);
        ((2.0 * max - sum).max(0.0), sum)
    }

    /// Coordinates of a world point in the plane frame: `(x, y, offset)`, the offset being the
    /// signed distance from the arm's plane.
    #[must_use]
    pub fn plane_coordinates(&self, world: &Point3<f64>) -> (f64, f64, f64) {
        let p = self.first.inverse_transform_point(world);
        (p.x, p.y, p.z - self.chain.height)
    }

    /// Absolute link angles `[φ1, φ2, φ3]` (plane frame) of joint values `q` (3 values).
    #[must_use]
    pub fn link_angles(&self, q: &[f64; 3]) -> [f64; 3] {
        self.chain.link_angles(q)
    }

    /// Joint values (not wrapped) giving the absolute link angles `phi`.
    #[must_use]
    pub fn joints_from_link_angles(&self, phi: &[f64; 3]) -> [f64; 3] {
        self.chain.joints(phi)
    }

    /// The feasible intervals of `φ` (absolute angle of the last link) for a target given in
    /// plane coordinates, joint limits ignored: empty outside the workspace annulus, one full
    /// turn when every `φ` works, else one or two intervals symmetric about the target's
    /// direction. At interval ends the elbow is stretched or folded.
    #[must_use]
    pub fn feasible_intervals(&self, target_xy: [f64; 2]) -> Vec<PhiInterval> {
        let [l1, l2, l3] = self.lengths();
        phi_intervals(l1, l2, l3, target_xy)
    }

    fn unreachable(&self, p: [f64; 2]) -> Option<IkFailure> {
        let r = p[0].hypot(p[1]);
        let (inner, outer) = self.workspace();
        if r > outer * (1.0 + BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: outer, point: "the target", from: "joint 1" })
        } else if r < inner * (1.0 - BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: inner, point: "the target", from: "joint 1" })
        } else {
            None
        }
    }

    /// The (≤ 2) candidates whose last link points at `phi`.
    fn at_phi(&self, p: [f64; 2], phi: f64, seed_phi1: f64, label_phi: bool, out: &mut Vec<Candidate>) {
        let [l1, l2, l3] = self.lengths();
        let w = [p[0] - l3 * phi.cos(), p[1] - l3 * phi.sin()];
        let TwoLink::In(sols) = two_link(l1, l2, w, seed_phi1) else { return };
        for e in sols.into_iter().flatten() {
            let q = self.chain.joints(&[e.phi[0], e.phi[1], phi]);
            let mut pairs = Vec::with_capacity(2);
            if label_phi {
                pairs.push(("phi_deg", phi_label(phi)));
            }
            pairs.push(("elbow", elbow_label(&e, 1.0).to_string()));
            let mut c = Candidate::new(q.to_vec(), Branch::new(pairs));
            if let Some(k) = e.singular {
                c.singularities.push(k);
            }
            out.push(c);
        }
    }
}
impl IkSolver for PlanarRedundant {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
        target.validate()?;
        check_options(robot, options)?;
        let (x, y, offset) = self.plane_coordinates(&target.position());
        if offset.abs() > IK_POSITION {
            let failure = IkFailure::Unreachable {
                distance: offset.abs(),
                reach: 0.0,
                point: "the target",
                from: "the arm's plane",
            };
            return finish(robot, target, &mut [], NAME, failure);
        }
        let p = [x, y];
        let seed_phi1 = options.seed.as_ref().map_or(0.0, |s| self.chain.link_angles(s)[0]);
        let mut candidates = Vec::new();
        match target {
            IkTarget::Pose(pose) => {
                // Rz(Θ)·R_last = R_local, with Θ the rotation of the last joint's frame.
                let r_local = self.first.rotation.inverse() * pose.rotation.to_rotation_matrix();
                let m = r_local * self.chain.last_rotation.inverse();
                let phi = self.chain.heading_to_last_angle(m[(1, 0)].atan2(m[(0, 0)]));
                self.at_phi(p, phi, seed_phi1, false, &mut candidates);
            }
            IkTarget::Position(_) => match options.free_parameter {
                Some(phi) => self.at_phi(p, phi, seed_phi1, true, &mut candidates),
                None => {
                    check_step(options)?;
                    for phi in sample_intervals(&self.feasible_intervals(p), options.redundancy_step) {
                        self.at_phi(p, phi, seed_phi1, true, &mut candidates);
                    }
                }
            },
        }
        let if_empty = self.unreachable(p).unwrap_or(IkFailure::OrientationUnreachable);
        finish(robot, target, &mut candidates, NAME, if_empty)
    }

    /// The two elbows, `elbow=up` first (the bend `−e` of `two_link`, the order of
    /// [`IkSolver::solve`]). With a position target the labels also carry the sampled
    /// redundancy parameter (`phi_deg=…`), which these filters leave free.
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        ["up", "down"].into_iter().map(|e| Branch::new([("elbow", e)])).collect()
    }

    /// `false`: the labels of a position target carry the sampled redundancy parameter, which
    /// changes from one target to the next, so a path is followed by nearness.
    fn enumerates_all_branches(&self) -> bool {
        false
    }
}
