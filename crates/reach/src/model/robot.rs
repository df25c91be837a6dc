use nalgebra::Isometry3;

use super::{Convention, Joint, JointGeometry, LinkGeometry, ModelError};
use crate::kinematics::chain::Chain;

/// Plain-data description of a robot, SI units and radians, before validation.
#[derive(Debug, Clone, PartialEq)]
pub struct RobotSpec {
    /// Short name (`puma560`).
    pub name: String,
    /// One-line description.
    pub description: String,
    /// How the joints' geometry is written.
    pub convention: Convention,
    /// The movable joints from base to tip.
    pub joints: Vec<Joint>,
    /// Pose of the chain's first frame in the world frame.
    pub base: Isometry3<f64>,
    /// Pose of the tool point (TCP) in the last joint frame.
    pub tool: Isometry3<f64>,
    /// Optional collision geometry, one entry per joint's link, or empty.
    pub links: Vec<LinkGeometry>,
}

impl RobotSpec {
    /// A spec with identity base and tool and no link geometry.
    #[must_use]
    pub fn new(name: impl Into<String>, convention: Convention, joints: Vec<Joint>) -> Self {
        RobotSpec {
            name: name.into(),
            description: String::new(),
            convention,
            joints,
            base: Isometry3::identity(),
            tool: Isometry3::identity(),
            links: Vec::new(),
        }
    }
}

/// A validated serial manipulator, ready for kinematics.
///
/// Built with [`Robot::new`] from a [`RobotSpec`], or parsed from a description file.
/// The joint variable vector `q` has one entry per joint: radians for revolute joints,
/// metres for prismatic joints.
///
/// # Example
/// ```
/// use reach::model::{Convention, Joint, Robot, RobotSpec};
/// use std::f64::consts::FRAC_PI_2;
/// // A planar two-link arm, 1 m links.
/// let spec = RobotSpec::new("two-link", Convention::Dh, vec![
///     Joint::revolute(1.0, 0.0, 0.0, 0.0),
///     Joint::revolute(1.0, 0.0, 0.0, 0.0),
/// ]);
/// let robot = Robot::new(spec).unwrap();
/// let pose = robot.fk(&[FRAC_PI_2, -FRAC_PI_2]).unwrap();
/// approx::assert_relative_eq!(pose.translation.vector.x, 1.0, epsilon = 1e-12);
/// approx::assert_relative_eq!(pose.translation.vector.y, 1.0, epsilon = 1e-12);
/// ```
#[derive(Debug, Clone)]
pub struct Robot {
    spec: RobotSpec,
    pub(crate) chain: Chain,
}

impl Robot {
    /// Validates `spec` and prepares it for kinematics.
    ///
    /// # Errors
    /// [`ModelError`] naming the joint and field when a number is NaN or infinite, limits are
    /// not ordered, a velocity limit is not positive, a joint is not in the robot's convention,
    /// a transform is not finite, link geometry does not match the joints, or there are no joints.
    pub fn new(mut spec: RobotSpec) -> Result<Self, ModelError> {
        if spec.joints.is_empty() {
            return Err(ModelError::NoJoints);
        }
        for (i, joint) in spec.joints.iter_mut().enumerate() {
            if joint.name.is_empty() {
                joint.name = format!("joint{}", i + 1);
            }
            validate_joint(i + 1, joint, spec.convention)?;
        }
        check_transform("base", &spec.base)?;
        check_transform("tool", &spec.tool)?;
        if !spec.links.is_empty() && spec.links.len() != spec.joints.len() {
            return Err(ModelError::Links(format!(
                "{} link entries for {} joints (give one per joint, or none)",
                spec.links.len(),
                spec.joints.len()
            )));
        }
        for (i, link) in spec.links.iter().enumerate() {
            if !link.radius.is_finite() || link.radius < 0.0 {
                return Err(ModelError::Links(format!(
                    "link {}: `radius` must be a finite number ≥ 0, got {}",
                    i + 1,
                    link.radius
                )));
            }
        }
        let chain = Chain::compile(&spec);
        Ok(Robot { spec, chain })
    }

    /// The robot's name.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.spec.name
    }

    /// One-line description.
    #[must_use]
    pub fn description(&self) -> &str {
        &self.spec.description
    }

    /// How the joint geometry is written.
    #[must_use]
    pub fn convention(&self) -> Convention {
        self.spec.convention
    }

    /// The joints from base to tip.
    #[must_use]
    pub fn joints(&self) -> &[Joint] {
        &self.spec.joints
    }

    /// Number of joints (degrees of freedom).
    #[must_use]
    #[inline]
    pub fn dof(&self) -> usize {
        self.spec.joints.len()
    }

    /// Base transform (world ← first frame).
    #[must_use]
    pub fn base(&self) -> &Isometry3<f64> {
        &self.spec.base
    }

    /// Tool transform (last joint frame ← tool point).
    #[must_use]
    pub fn tool(&self) -> &Isometry3<f64> {
        &self.spec.tool
    }

    /// Collision geometry per link (empty when the description gives none).
    #[must_use]
    pub fn links(&self) -> &[LinkGeometry] {
        &self.spec.links
    }

    /// The validated plain data.
    #[must_use]
    pub fn spec(&self) -> &RobotSpec {
        &self.spec
    }

    /// A copy of this robot with another tool transform.
    ///
    /// # Errors
    /// [`ModelError::Transform`] when `tool` is not finite.
    pub fn with_tool(&self, tool: Isometry3<f64>) -> Result<Robot, ModelError> {
        Robot::new(RobotSpec { tool, ..self.spec.clone() })
    }

    /// A copy of this robot with another base transform.
    ///
    /// # Errors
    /// [`ModelError::Transform`] when `base` is not finite.
    pub fn with_base(&self, base: Isometry3<f64>) -> Result<Robot, ModelError> {
        Robot::new(RobotSpec { base, ..self.spec.clone() })
    }

    /// The home (rest) configuration: each joint's `home` value.
    #[must_use]
    pub fn home(&self) -> Vec<f64> {
        self.spec.joints.iter().map(|j| j.home).collect()
    }

    /// Whether every joint value lies within its limits (with `tolerance`, SI units).
    ///
    /// Returns the 0-based index of the first joint outside its limits, or `None`.
    #[must_use]
    pub fn first_joint_outside_limits(&self, q: &[f64], tolerance: f64) -> Option<usize> {
        self.spec.joints.iter().zip(q).position(|(j, &v)| !j.limits.contains(v, tolerance))
    }
}

fn validate_joint(number: usize, joint: &Joint, convention: Convention) -> Result<(), ModelError> {
    let non_finite = |field: &'static str, value: f64| ModelError::NonFinite {
        joint: number,
        name: joint.name.clone(),
        field,
        value,
    };
    match (&joint.geometry, convention) {
        (JointGeometry::Dh(p), Convention::Dh | Convention::Mdh) => {
            for (field, value) in [("a", p.a), ("alpha", p.alpha), ("d", p.d), ("theta", p.theta_offset)] {
                if !value.is_finite() {
                    return Err(non_finite(field, value));
                }
            }
        }
        (JointGeometry::Axis { origin, axis }, Convention::Urdf) => {
            check_transform(&format!("joint {number} ({}) origin", joint.name), origin)?;
            for (field, value) in [("axis.x", axis.x), ("axis.y", axis.y), ("axis.z", axis.z)] {
                if !value.is_finite() {
                    return Err(non_finite(field, value));
                }
            }
        }
        _ => {
            return Err(ModelError::MixedConvention {
                joint: number,
                name: joint.name.clone(),
                convention: convention.as_str(),
            });
        }
    }
    let limits = joint.limits;
    if limits.lower.is_nan() || limits.upper.is_nan() || limits.lower >= limits.upper {
        return Err(ModelError::LimitsOrder {
            joint: number,
            name: joint.name.clone(),
            lower: limits.lower,
            upper: limits.upper,
        });
    }
    if !joint.home.is_finite() {
        return Err(non_finite("home", joint.home));
    }
    if !limits.contains(joint.home, 0.0) {
        return Err(ModelError::Joint {
            joint: number,
            name: joint.name.clone(),
            message: format!("home position {} is outside the limits [{}, {}]", joint.home, limits.lower, limits.upper),
        });
    }
    if let Some(v) = joint.max_velocity
        && !(v.is_finite() && v > 0.0)
    {
        return Err(ModelError::VelocityLimit { joint: number, name: joint.name.clone(), value: v });
    }
    Ok(())
}

fn check_transform(which: &str, t: &Isometry3<f64>) -> Result<(), ModelError> {
    let finite = t.translation.vector.iter().all(|v| v.is_finite()) && t.rotation.coords.iter().all(|v| v.is_finite());
    if finite {
        Ok(())
    } else {
        Err(ModelError::Transform { which: which.to_string(), reason: "contains NaN or infinity".into() })
    }
}
