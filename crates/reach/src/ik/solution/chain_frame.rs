//! Where a closed form's DH chain sits relative to the robot's own base and tool.

use nalgebra::Isometry3;

use crate::model::Robot;
use crate::tolerance::DH_EQUIVALENT_EXACT;

use super::*;
use crate::ik::IkTarget;

/// The flange pose in the chain's own frame: `base⁻¹ · target · tool⁻¹`.
#[must_use]
pub(crate) fn chain_target(robot: &Robot, target: &Isometry3<f64>) -> Isometry3<f64> {
    robot.base().inverse() * target * robot.tool().inverse()
}

/// Where the DH chain a closed form solves sits relative to the robot's own base and tool:
/// nothing between them for a robot described in standard DH (the solver reads its table);
/// for any other robot the base and tool of its standard-DH equivalent
/// ([`Robot::dh_equivalent`]) relative to the robot's own, `B_rel = base⁻¹·B_dh` and
/// `T_rel = T_dh·tool⁻¹`. The robot's own base and tool still apply at solve time, as for a DH
/// robot, so a solver built for a robot also solves a copy with another tool
/// ([`Robot::with_tool`]).
///
/// When the equivalent's forward kinematics deviate from the robot's by more than rounding
/// ([`DH_EQUIVALENT_EXACT`]: twists or lengths were made exact), [`ChainFrame::refine`] moves
/// the closed form's candidates onto the robot's own pose by Newton steps.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct ChainFrame {
    /// `(B_rel⁻¹, T_rel⁻¹)`; `None` when both are the identity.
    relative: Option<(Isometry3<f64>, Isometry3<f64>)>,
    /// Whether the candidates need refining on the robot itself.
    refine: bool,
}

impl ChainFrame {
    /// The frame of `equivalent` (the standard-DH equivalent of `robot`, whose forward
    /// kinematics deviate from the robot's by up to `gap`) relative to `robot`.
    #[must_use]
    pub fn between(robot: &Robot, equivalent: &Robot, gap: f64) -> Self {
        let base = robot.base().inverse() * equivalent.base();
        let tool = equivalent.tool() * robot.tool().inverse();
        ChainFrame { relative: Some((base.inverse(), tool.inverse())), refine: gap > DH_EQUIVALENT_EXACT }
    }

    /// For an equivalent that is not exact, up to two Newton steps per candidate on `robot`
    /// itself towards a pose target (`Δq = J⁻¹·e`, the 6×6 geometric Jacobian; a step is kept
    /// only when it reduces the error, so a singular candidate stays as computed). Nothing for
    /// an exact equivalent, the robot's own table, or a position target (whose solutions keep
    /// an orientation of the solver's choosing). [`finish`] verifies the result as always.
    pub fn refine<C: CandidateList + ?Sized>(&self, robot: &Robot, target: &IkTarget, candidates: &mut C) {
        let (true, IkTarget::Pose(pose), 6) = (self.refine, target, robot.dof()) else {
            return;
        };
        let goal = nalgebra::IsometryMatrix3::from_parts(pose.translation, pose.rotation.to_rotation_matrix());
        let error = |q: &[f64]| -> Option<(nalgebra::Vector6<f64>, f64)> {
            let t = robot.fk_matrix(q).ok()?;
            let dp = goal.translation.vector - t.translation.vector;
            let (w, angle) =
                crate::ik::numeric::rotation_log(&(goal.rotation.matrix() * t.rotation.matrix().transpose()));
            Some((nalgebra::Vector6::new(dp.x, dp.y, dp.z, w.x, w.y, w.z), dp.norm().max(angle)))
        };
        for i in 0..candidates.count() {
            let q = candidates.joints_mut(i);
            for _ in 0..2 {
                let Some((e, size)) = error(q) else { break };
                let Ok(jac) = robot.jacobian(q) else { break };
                let Some(dq) = nalgebra::Matrix6::from_iterator(jac.iter().copied()).lu().solve(&e) else { break };
                let trial: JointValues = q.iter().zip(dq.iter()).map(|(q, d)| q + d).collect();
                match error(&trial) {
                    Some((_, smaller)) if smaller < size => q.copy_from_slice(&trial),
                    _ => break,
                }
            }
        }
    }

    /// Whether the chain is the robot's own DH table.
    #[must_use]
    pub fn is_own(&self) -> bool {
        self.relative.is_none()
    }

    /// The flange pose of the DH chain for the world pose `target` of `robot`'s tool:
    /// [`chain_target`], then `B_rel⁻¹ · … · T_rel⁻¹`.
    #[must_use]
    pub fn target(&self, robot: &Robot, target: &Isometry3<f64>) -> Isometry3<f64> {
        let t = chain_target(robot, target);
        match &self.relative {
            None => t,
            Some((base, tool)) => base * t * tool,
        }
    }
}
