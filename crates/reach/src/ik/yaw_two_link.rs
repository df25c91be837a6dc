//! Seed 000 appendix (P2011): a base yaw plus a two-link arm in a vertical plane
//! (`log-loader`).
//!
//! # The arm
//!
//! Joint 1 turns about z of the chain frame (the "vertical"); joint 2's axis is perpendicular
//! to it ("horizontal"), and joint 3's axis is parallel to joint 2's. The links of joints 2 and
//! 3 move in a plane normal to the horizontal axis — the *arm plane*, which turns with joint 1.
//! The structure is read from the compiled chain, so DH/MDH/URDF, base and tool transforms,
//! offsets and flipped joints all fit. Allowed offsets: the shoulder (joint 2's axis) may sit
//! anywhere in the arm plane (height and radial offset), and the arm plane may be offset
//! sideways from the yaw axis by `d` (then the base angle has the two "shoulder" solutions of a
//! PUMA, `atan2(y, x) ∓ atan2(d, ±√(ρ² − d²))`).
//!
//! # Solutions
//!
//! Up to four: the base pointing at the target (`base=front`) or away from it with the arm
//! reaching back over the top (`base=back`, yaw + 180° and the shoulder beyond the vertical),
//! each with both elbows (`elbow=up`: the elbow above the shoulder–wrist line when the arm
//! reaches outwards; for the `log-loader` preset this is the paper's `q3 = β − 180° ≤ 0`).
//! The base angle is the corrected quadrant table of P2011 ([`base_angle`], notes 000 §3.5,
//! D9), which is `atan2`.
//!
//! Singularities: `shoulder` — the target on the yaw axis (the base angle is free: it is taken
//! from the target orientation for pose targets, else from the seed, else 0); `elbow` — the
//! arm fully stretched or folded (one elbow solution).
//!
//! Failure reasons: `Unreachable` (distance from the shoulder against `l2 + l3` or
//! `|l2 − l3|`; or, with a sideways offset, the horizontal distance against `d`),
//! `OrientationUnreachable` for a pose target whose orientation no solution matches (the arm
//! has three joints; only orientations the position leaves possible are reached),
//! `OutsideLimits`.

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::{IsometryMatrix3, Point3, Rotation3, Vector3};

use super::planar::{PlanarChain, TwoLink, check_options, elbow_label, two_link};
use super::{
    Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, finish,
};
use crate::model::Robot;
use crate::model::chain::ChainLink;
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, STRUCTURE_ANGLE, STRUCTURE_LENGTH};

const NAME: &str = "yaw-two-link";

/// The base angle of a point `(x, y)`: P2011's quadrant table (notes 000 §3.5), corrected,
/// in (−180°, 180°]; `None` at the origin (undefined).
///
/// The printed cell for `x < 0, y > 0`, `atan(y/|x|) + 90°`, is wrong except at `|x| = y`;
/// the correct cell is `atan(|x|/y) + 90°` (notes 000 §6.1, D9). With that fix the table is
/// `atan2(y, x)`.
///
/// # Example
/// ```
/// use reach::ik::yaw_two_link::base_angle;
/// // D9: (−1, 2) is at 116.565051°, not the printed 153.434949°.
/// approx::assert_relative_eq!(base_angle(-1.0, 2.0).unwrap().to_degrees(), 116.565051, epsilon = 1e-6);
/// assert_eq!(base_angle(0.0, 0.0), None);
/// ```
#[must_use]
pub fn base_angle(x: f64, y: f64) -> Option<f64> {
    if !(x.is_finite() && y.is_finite()) {
        return None;
    }
    Some(if x > 0.0 {
        (y / x).atan()
    } else if x < 0.0 {
        if y < 0.0 {
            (y / x).atan() - PI
        } else if y == 0.0 {
            PI
        } else {
            // Corrected cell (D9): atan(|x|/y) + 90°, printed as atan(y/|x|) + 90°.
            (x.abs() / y).atan() + FRAC_PI_2
        }
    } else if y > 0.0 {
        FRAC_PI_2
    } else if y < 0.0 {
        -FRAC_PI_2
    } else {
        return None;
    })
}

/// The shortest base rotation from angle `from` to angle `to`, in (−π, π] (P2011's "a",
/// notes 000 §3.5): positive counter-clockwise.
///
/// The paper's rule `a = −(360° − |a2 − a1|)` for `|a2 − a1| ≥ 180°` has the wrong sign when
/// `a2 − a1 < −180°`; the corrected rule is `a = (a2 − a1) − 360°·sign(a2 − a1)` (notes 000
/// §6.1, D10), i.e. [`crate::angle::shortest_difference`]. At exactly 180° both directions
/// are shortest; +180° is returned.
///
/// # Example
/// ```
/// use reach::ik::yaw_two_link::shortest_base_rotation;
/// // D10: from 170° to −170° is +20° (the paper gives −20°).
/// let a = shortest_base_rotation(170f64.to_radians(), (-170f64).to_radians());
/// approx::assert_relative_eq!(a.to_degrees(), 20.0, epsilon = 1e-9);
/// ```
#[must_use]
#[inline]
pub fn shortest_base_rotation(from: f64, to: f64) -> f64 {
    crate::angle::shortest_difference(from, to)
}

/// Geometry of a base yaw joint followed by an arm whose joint axes are horizontal (shared
/// with [`super::yaw_planar3`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct YawFrame {
    /// The chain frame (base included): joint 1 turns about its z axis.
    pub first: IsometryMatrix3<f64>,
    /// −1 when joint 1 is flipped.
    pub yaw_sign: f64,
    /// Direction of the arm plane's outward horizontal axis `n`, in the frame turned by joint 1.
    pub nu: f64,
    /// Direction of the horizontal joint axis `e` (joint 2), in the frame turned by joint 1.
    pub axis_angle: f64,
    /// Sideways offset of the arm plane from the yaw axis, along `e`.
    pub lateral: f64,
    /// Shoulder (joint 2 axis) in arm-plane coordinates `(u, v)`: outward, up.
    pub shoulder: [f64; 2],
    /// Angle from `n` to the x axis of joint 2's motion frame, in the arm plane (`(u, v)`
    /// angle = planar-chain angle + κ).
    pub kappa: f64,
    /// Rotation from the frame turned by joint 1 to joint 2's motion frame.
    pub r1: Rotation3<f64>,
}

/// One base-angle solution: physical yaw `θ1`, the outward coordinate `u` of the target in the
/// arm plane, and whether the target is on the yaw axis (`u = 0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct YawBranch {
    pub theta1: f64,
    pub u: f64,
    pub singular: bool,
}

impl YawBranch {
    /// `front`/`back` label and the reach direction sign for the elbow label (the one branch
    /// on the yaw axis is `front`).
    pub fn label(&self) -> (&'static str, f64) {
        if self.u < 0.0 && !self.singular { ("back", -1.0) } else { ("front", 1.0) }
    }
}

impl YawFrame {
    /// Reads joint 1 (`link`) and the plane's offset along the horizontal axis (`height`, the
    /// sum of the following joints' offsets along their axes).
    pub fn from_chain(link: &ChainLink, first: IsometryMatrix3<f64>, height: f64) -> Result<Self, String> {
        if link.prismatic {
            return Err("joint 1 is prismatic (a revolute base joint is needed)".into());
        }
        let r1 = link.after.rotation;
        let e = r1 * Vector3::z();
        if e.z.abs() > STRUCTURE_ANGLE {
            return Err(format!(
                "joint 2 axis is not perpendicular to joint 1 axis (angle {:.6}°)",
                e.z.clamp(-1.0, 1.0).acos().to_degrees()
            ));
        }
        let e = Vector3::new(e.x, e.y, 0.0).normalize();
        let n = Vector3::z().cross(&e);
        let p1 = link.after.translation.vector;
        let e1 = r1 * Vector3::x();
        Ok(YawFrame {
            first,
            yaw_sign: link.sign,
            nu: n.y.atan2(n.x),
            axis_angle: e.y.atan2(e.x),
            lateral: p1.dot(&e) + height,
            shoulder: [p1.dot(&n), p1.z],
            kappa: e1.z.atan2(e1.dot(&n)),
            r1,
        })
    }

    /// A world point in the chain frame.
    pub fn local(&self, world: &Point3<f64>) -> Point3<f64> {
        self.first.inverse_transform_point(world)
    }

    /// The base angles that put the arm plane through `t` (chain frame): two (front, back), or
    /// one on the yaw axis, where `fallback` is used when the angle is free.
    pub fn branches(&self, t: &Point3<f64>, fallback: f64) -> Result<[Option<YawBranch>; 2], IkFailure> {
        let rho = t.x.hypot(t.y);
        let lat = self.lateral;
        if rho < lat.abs() * (1.0 - BOUNDARY) - IK_AXIS_DISTANCE {
            return Err(IkFailure::Unreachable {
                distance: rho,
                reach: lat.abs(),
                point: "the target",
                from: "joint 1's axis",
            });
        }
        let u0 = (rho * rho - lat * lat).max(0.0).sqrt();
        let direction = t.y.atan2(t.x) - self.nu;
        if u0 <= IK_AXIS_DISTANCE {
            let theta1 = if rho <= IK_AXIS_DISTANCE { fallback } else { direction - (-lat).atan2(0.0) };
            // The target's (tiny) component along the arm plane's outward axis for this base
            // angle: keeps the in-plane point exact when the arm is also folded near the axis.
            let u = t.x * (theta1 + self.nu).cos() + t.y * (theta1 + self.nu).sin();
            return Ok([Some(YawBranch { theta1, u, singular: true }), None]);
        }
        let branch = |u: f64| YawBranch { theta1: direction - (-lat).atan2(u), u, singular: false };
        Ok([Some(branch(u0)), Some(branch(-u0))])
    }

    /// The base angle that turns the horizontal joint axis to where a pose target's
    /// orientation puts it (`R·R_lastᵀ·z = Rz(θ1)·e`); `None` when that axis is not horizontal
    /// enough to define it.
    pub fn theta1_from_orientation(&self, r_local: &Rotation3<f64>, last_rotation: &Rotation3<f64>) -> Option<f64> {
        let a = r_local * last_rotation.inverse() * Vector3::z();
        (a.x.hypot(a.y) > 0.5).then(|| a.y.atan2(a.x) - self.axis_angle)
    }

    /// Rotation angle Θ of the last planar joint's frame (planar-chain coordinates) that a
    /// pose target's orientation asks for, given the base angle `theta1`.
    pub fn planar_heading(&self, theta1: f64, r_local: &Rotation3<f64>, last_rotation: &Rotation3<f64>) -> f64 {
        let yaw = Rotation3::from_axis_angle(&Vector3::z_axis(), -theta1);
        let m = self.r1.inverse() * yaw * r_local * last_rotation.inverse();
        m[(1, 0)].atan2(m[(0, 0)])
    }

    /// Target in arm-plane coordinates relative to the shoulder, for a base branch.
    pub fn in_plane(&self, branch: &YawBranch, t: &Point3<f64>) -> [f64; 2] {
        [branch.u - self.shoulder[0], t.z - self.shoulder[1]]
    }
}

/// Reads a base yaw plus an `N`-link arm in a vertical plane from `robot` (`N + 1` joints; the
/// families of [`YawTwoLink`] and [`YawPlanar3`](super::yaw_planar3::YawPlanar3)): the yaw
/// frame and the planar chain, the first `nonzero` links of non-zero length in the arm plane.
/// Errors are `solver`'s [`IkError::Unsupported`] naming the failed condition.
pub(crate) fn read_yaw_arm<const N: usize>(
    robot: &Robot,
    solver: &'static str,
    nonzero: usize,
) -> Result<(YawFrame, PlanarChain<N>), IkError> {
    let unsupported = |reason: String| IkError::Unsupported { solver, robot: robot.name().to_string(), reason };
    if robot.dof() != N + 1 {
        return Err(unsupported(format!("needs exactly {} joints, the robot has {}", N + 1, robot.dof())));
    }
    if robot.chain.has_mimics() {
        return Err(unsupported("the chain has mimic joints".into()));
    }
    let links = &robot.chain.links;
    let chain = PlanarChain::<N>::from_chain(&links[1..], 2).map_err(unsupported)?;
    let yaw = YawFrame::from_chain(&links[0], robot.chain.first, chain.height).map_err(unsupported)?;
    for (i, l) in chain.links.iter().take(nonzero).enumerate() {
        if l.length <= STRUCTURE_LENGTH {
            return Err(unsupported(format!("link {} has zero length in the arm plane", i + 2)));
        }
    }
    Ok((yaw, chain))
}

/// Closed-form IK of a base yaw plus a two-link arm in a vertical plane (seed 000 appendix,
/// `log-loader`): position targets, up to four solutions (`base=front|back`,
/// `elbow=up|down`). See the [module docs](self).
#[derive(Debug, Clone)]
pub struct YawTwoLink {
    yaw: YawFrame,
    chain: PlanarChain<2>,
}

impl YawTwoLink {
    /// Reads the arm from `robot`: three revolute joints, joint 2's axis perpendicular to
    /// joint 1's, joint 3's parallel to joint 2's (same direction), both links of non-zero
    /// length in the arm plane.
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let (yaw, chain) = read_yaw_arm::<2>(robot, NAME, 2)?;
        Ok(YawTwoLink { yaw, chain })
    }

    /// Lengths of the two arm links (joint 2 → joint 3, joint 3 → tool point), metres.
    #[must_use]
    pub fn lengths(&self) -> [f64; 2] {
        self.chain.lengths()
    }
}

/// The base and elbow branches of an arm on a yaw joint, in the order of its solve:
/// `base=front` (the base towards the target) then `base=back`; the elbow of the bend `−e`
/// of [`two_link`] first, which is `up` reaching forwards and `down` reaching back.
pub(crate) fn yaw_configurations() -> Vec<Branch> {
    [("front", "up"), ("front", "down"), ("back", "down"), ("back", "up")]
        .into_iter()
        .map(|(base, elbow)| Branch::new([("base", base), ("elbow", elbow)]))
        .collect()
}

impl IkSolver for YawTwoLink {
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
        let branches = match self.yaw.branches(&t, fallback) {
            Ok(b) => b,
            Err(failure) => return finish(robot, target, &mut [], NAME, failure),
        };
        let [la, lb] = self.lengths();
        let mut candidates = Vec::with_capacity(4);
        let mut failure = None;
        for b in branches.into_iter().flatten() {
            let (base, reach_sign) = b.label();
            // Folded onto the shoulder axis (l2 = l3) link 2's angle is free; a pose target's
            // orientation fixes the last link, hence link 2 = last − 180°.
            let seed_phi = r_local.as_ref().map_or(seed_phi, |r| {
                let heading = self.yaw.planar_heading(b.theta1, r, &self.chain.last_rotation);
                self.chain.heading_to_last_angle(heading) + self.yaw.kappa - PI
            });
            let sols = match two_link(la, lb, self.yaw.in_plane(&b, &t), seed_phi) {
                TwoLink::Out { distance, reach } => {
                    failure.get_or_insert(IkFailure::Unreachable {
                        distance,
                        reach,
                        point: "the target",
                        from: "joint 2",
                    });
                    continue;
                }
                TwoLink::In(sols) => sols,
            };
            for e in sols.into_iter().flatten() {
                let k = self.yaw.kappa;
                let qp = self.chain.joints(&[e.phi[0] - k, e.phi[1] - k]);
                let q = vec![self.yaw.yaw_sign * b.theta1, qp[0], qp[1]];
                let mut c = Candidate::new(q, Branch::new([("base", base), ("elbow", elbow_label(&e, reach_sign))]));
                if b.singular {
                    c.singularities.push(SingularityKind::Shoulder);
                }
                if let Some(s) = e.singular
                    && !c.singularities.contains(&s)
                {
                    c.singularities.push(s);
                }
                candidates.push(c);
            }
        }
        // No candidate: the position is out of reach; candidates that `finish` drops miss the
        // orientation of a pose target.
        let if_empty = match failure {
            Some(f) if candidates.is_empty() => f,
            _ => IkFailure::OrientationUnreachable,
        };
        finish(robot, target, &mut candidates, NAME, if_empty)
    }

    /// The four branches in the order [`IkSolver::solve`] returns them (`yaw_configurations`).
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        yaw_configurations()
    }

    fn enumerates_all_branches(&self) -> bool {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn reads_the_preset() {
        let robot = presets::get("log-loader").unwrap();
        let s = YawTwoLink::from_robot(&robot).unwrap();
        assert_eq!(s.lengths(), [1.0, 1.0]);
        assert!(s.yaw.lateral.abs() < 1e-15 && s.yaw.nu.abs() < 1e-15 && s.yaw.kappa.abs() < 1e-15);
        assert!(s.yaw.shoulder.iter().all(|v| v.abs() < 1e-15));
    }

    #[test]
    fn rejects_other_structures() {
        for name in ["planar3", "varan4", "puma560", "spbu6", "ur5", "panda", "welder6r"] {
            let robot = presets::get(name).unwrap();
            let err = YawTwoLink::from_robot(&robot).unwrap_err();
            assert!(matches!(err, IkError::Unsupported { .. }), "{name}: {err}");
        }
        let err = YawTwoLink::from_robot(&presets::get("planar3").unwrap()).unwrap_err();
        assert!(err.to_string().contains("not perpendicular"), "{err}");
    }

    #[test]
    fn base_angle_is_atan2() {
        for i in -20..=20 {
            for j in -20..=20 {
                let (x, y) = (f64::from(i) * 0.37, f64::from(j) * 0.29);
                match base_angle(x, y) {
                    None => assert!(i == 0 && j == 0),
                    Some(a) => assert!((a - y.atan2(x)).abs() < 1e-12, "({x}, {y}): {a}"),
                }
            }
        }
    }

    #[test]
    fn configurations_are_the_four_branches_in_the_order_of_the_solve() {
        use crate::ik::configuration_order::{check_with, labels};
        let robot = presets::get("log-loader").unwrap();
        let s = YawTwoLink::from_robot(&robot).unwrap();
        assert!(s.enumerates_all_branches());
        assert_eq!(
            labels(&s, &robot),
            ["base=front elbow=up", "base=front elbow=down", "base=back elbow=down", "base=back elbow=up"]
        );
        // A pose of a 3-joint arm fixes the branch: check positions.
        let complete = check_with(&s, &robot, 200, true, &IkOptions::default());
        assert!(complete > 100, "{complete}");
    }
}
