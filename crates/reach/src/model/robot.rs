use std::sync::Arc;

use nalgebra::{Isometry3, Vector3};

use super::chain::Chain;
use super::{
    Convention, Joint, JointDrive, JointGeometry, JointKind, LinkBody, LinkGeometry, LinkInertial, MimicJoint,
    ModelError, STANDARD_GRAVITY, StepMode,
};

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
    /// Optional mass properties, one entry per joint's link (frames: see [`LinkInertial`]),
    /// or empty when the description gives no dynamics.
    pub inertials: Vec<LinkInertial>,
    /// Gravitational acceleration in the world frame, m/s² (default `(0, 0, −9.80665)`).
    pub gravity: Vector3<f64>,
    /// Joints that follow another joint (URDF `<mimic>`), in chain order; empty for most
    /// robots. Only in the URDF convention, and not together with mass properties.
    pub mimics: Vec<MimicJoint>,
    /// The collision body: solids fixed to the chain's frames (URDF `<collision>`, TOML
    /// `[[bodies]]`). Empty: the robot is checked as its stick figure, the segments between
    /// frame origins swept by [`RobotSpec::links`]' radii.
    pub bodies: Vec<LinkBody>,
    /// Pairs of bodies (by name) never checked against each other (SRDF
    /// `disable_collisions`, TOML `disabled_collisions`).
    pub disabled_collisions: Vec<[String; 2]>,
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
            inertials: Vec::new(),
            gravity: Vector3::new(0.0, 0.0, -STANDARD_GRAVITY),
            mimics: Vec::new(),
            bodies: Vec::new(),
            disabled_collisions: Vec::new(),
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
    /// The joint names, shared: reports that name a joint (an IK solution's limit
    /// violations) clone an `Arc` instead of allocating a `String`.
    names: Arc<[Arc<str>]>,
}

impl Robot {
    /// Validates `spec` and prepares it for kinematics.
    ///
    /// # Errors
    /// [`ModelError`] naming the joint and field when a number is NaN or infinite, limits are
    /// not ordered, a velocity limit is not positive, a joint is not in the robot's convention,
    /// a transform is not finite, link geometry does not match the joints, or there are no joints;
    /// [`ModelError::Joint`] naming the `inertial.…` field for a bad mass, centre of mass or
    /// inertia; [`ModelError::Dynamics`] for a non-finite gravity or a wrong number of
    /// inertial entries; [`ModelError::Mimic`] for a mimic joint outside the URDF convention,
    /// with a master that does not exist, a non-finite number, mimic joints out of chain
    /// order, or mimic joints together with mass properties.
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
        check_inertials(&spec)?;
        check_mimics(&spec)?;
        super::body::validate_bodies(&spec.bodies, &spec.disabled_collisions, spec.joints.len())?;
        let chain = Chain::compile(&spec);
        let names = spec.joints.iter().map(|j| Arc::from(j.name.as_str())).collect();
        Ok(Robot { spec, chain, names })
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

    /// The name of joint `i` (0-based), shared ([`Joint::name`] in an `Arc`: cloning it does
    /// not allocate). `None` beyond the joints.
    #[must_use]
    pub fn joint_name(&self, i: usize) -> Option<&Arc<str>> {
        self.names.get(i)
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

    /// The collision body, one entry per link that has solids (empty: the stick figure; see
    /// [`RobotSpec::bodies`]).
    #[must_use]
    pub fn bodies(&self) -> &[LinkBody] {
        &self.spec.bodies
    }

    /// The body pairs (by name) never checked against each other.
    #[must_use]
    pub fn disabled_collisions(&self) -> &[[String; 2]] {
        &self.spec.disabled_collisions
    }

    /// This robot with `pairs` added to its disabled collision pairs (an SRDF's
    /// `disable_collisions`, [`super::srdf_disabled_pairs`]).
    ///
    /// # Errors
    /// [`ModelError::Links`] when a pair names a link that has no body.
    pub fn with_disabled_collisions(&self, pairs: &[[String; 2]]) -> Result<Robot, ModelError> {
        let mut spec = self.spec.clone();
        for p in pairs {
            if !spec.disabled_collisions.contains(p) {
                spec.disabled_collisions.push(p.clone());
            }
        }
        Robot::new(spec)
    }

    /// Capsule radius of each of the `dof + 1` segments of [`Robot::joint_positions`]'s
    /// polyline, metres: segment `k` (0-based) is link `k + 1`; the last one (last frame →
    /// tool point) takes the last link's radius; 0 when the description gives no `[[links]]`.
    #[must_use]
    pub fn segment_radii(&self) -> Vec<f64> {
        let n = self.dof();
        let links = self.links();
        (0..=n).map(|k| links.get(k.min(n.saturating_sub(1))).map_or(0.0, |l| l.radius)).collect()
    }

    /// Mass properties per link (empty when the description gives none; see [`LinkInertial`]
    /// for the frames).
    #[must_use]
    pub fn inertials(&self) -> &[LinkInertial] {
        &self.spec.inertials
    }

    /// Whether the description gives mass properties, so that dynamics can be computed.
    #[must_use]
    pub fn has_dynamics(&self) -> bool {
        !self.spec.inertials.is_empty()
    }

    /// Gravitational acceleration in the world frame, m/s².
    #[must_use]
    pub fn gravity(&self) -> &Vector3<f64> {
        &self.spec.gravity
    }

    /// A copy of this robot with mass properties, one entry per joint (frames: see
    /// [`LinkInertial`]), or none (empty vector).
    ///
    /// # Errors
    /// As [`Robot::new`]: the number of entries, or a mass, centre of mass or inertia that is
    /// not valid (the error names the joint and the `inertial.…` field).
    pub fn with_inertials(&self, inertials: Vec<LinkInertial>) -> Result<Robot, ModelError> {
        Robot::new(RobotSpec { inertials, ..self.spec.clone() })
    }

    /// Joints that follow another joint (URDF `<mimic>`); they are not degrees of freedom.
    #[must_use]
    pub fn mimics(&self) -> &[MimicJoint] {
        &self.spec.mimics
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

    /// The stepper drive of each joint (`None` where the description gives none); one entry
    /// per joint.
    #[must_use]
    pub fn drives(&self) -> Vec<Option<&JointDrive>> {
        self.spec.joints.iter().map(|j| j.drive.as_ref()).collect()
    }

    /// A copy of this robot with stepper drive data, one entry per joint (`None` = no drive).
    ///
    /// # Errors
    /// [`ModelError::Joint`] naming the joint and the `drive.…` field when a count is zero, the
    /// gear ratio, lead, rate or acceleration is not a positive finite number, the direction is
    /// not ±1, a prismatic joint has no `lead` (or a revolute joint has one), or the coil
    /// sequence does not match the microstepping; [`ModelError::Joint`] on joint 0 when the
    /// number of entries differs from the number of joints.
    pub fn with_drives(&self, drives: Vec<Option<JointDrive>>) -> Result<Robot, ModelError> {
        if drives.len() != self.dof() {
            return Err(ModelError::Joint {
                joint: 0,
                name: String::new(),
                message: format!("{} drive entries for {} joints (give one per joint)", drives.len(), self.dof()),
            });
        }
        let mut spec = self.spec.clone();
        for (joint, drive) in spec.joints.iter_mut().zip(drives) {
            joint.drive = drive;
        }
        Robot::new(spec)
    }

    /// The distance joint `i` (0-based) travels from `from` to `to`: the crate's one
    /// joint-difference rule, [`Joint::difference`] (wrapped for a revolute joint without
    /// limits, literal otherwise). An index beyond the joints takes the literal difference.
    #[must_use]
    #[inline]
    pub fn joint_difference(&self, i: usize, from: f64, to: f64) -> f64 {
        self.spec.joints.get(i).map_or(to - from, |j| j.difference(from, to))
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
    for (field, value) in [("max_acceleration", joint.max_acceleration), ("max_jerk", joint.max_jerk)] {
        if let Some(v) = value
            && !(v.is_finite() && v > 0.0)
        {
            let message = format!("`{field}` must be a finite number > 0, got {v}");
            return Err(ModelError::Joint { joint: number, name: joint.name.clone(), message });
        }
    }
    if let Some(drive) = &joint.drive {
        validate_drive(number, joint, drive)?;
    }
    Ok(())
}

fn check_inertials(spec: &RobotSpec) -> Result<(), ModelError> {
    if let Some(v) = spec.gravity.iter().find(|v| !v.is_finite()) {
        return Err(ModelError::Dynamics(format!("`gravity` must be finite, got {v}")));
    }
    if spec.inertials.is_empty() {
        return Ok(());
    }
    if spec.inertials.len() != spec.joints.len() {
        return Err(ModelError::Dynamics(format!(
            "{} inertial entries for {} joints (give one per joint, or none)",
            spec.inertials.len(),
            spec.joints.len()
        )));
    }
    for (i, (joint, inertial)) in spec.joints.iter().zip(&spec.inertials).enumerate() {
        inertial.check().map_err(|(field, message)| ModelError::Joint {
            joint: i + 1,
            name: joint.name.clone(),
            message: format!("`{field}` {message}"),
        })?;
    }
    Ok(())
}

fn check_mimics(spec: &RobotSpec) -> Result<(), ModelError> {
    let mut previous = 0;
    for m in &spec.mimics {
        let fail = |message: String| ModelError::Mimic { name: m.name.clone(), message };
        if spec.convention != Convention::Urdf {
            return Err(fail(format!(
                "mimic joints exist only in the `urdf` convention, the robot is `{}`",
                spec.convention.as_str()
            )));
        }
        if m.master >= spec.joints.len() {
            return Err(fail(format!(
                "master joint {} does not exist (the robot has {})",
                m.master + 1,
                spec.joints.len()
            )));
        }
        for (field, value) in [("multiplier", m.multiplier), ("offset", m.offset)] {
            if !value.is_finite() {
                return Err(fail(format!("`{field}` must be a finite number, got {value}")));
            }
        }
        for (field, value) in [("axis.x", m.axis.x), ("axis.y", m.axis.y), ("axis.z", m.axis.z)] {
            if !value.is_finite() {
                return Err(fail(format!("`{field}` must be a finite number, got {value}")));
            }
        }
        check_transform(&format!("mimic joint {} origin", m.name), &m.origin)?;
        if m.position > spec.joints.len() || m.position < previous {
            return Err(fail(format!(
                "position {} is out of chain order (after {previous}, at most {})",
                m.position,
                spec.joints.len()
            )));
        }
        previous = m.position;
        if !spec.inertials.is_empty() {
            return Err(fail("the dynamics model does not support mimic joints; give no mass properties".into()));
        }
    }
    Ok(())
}

fn validate_drive(number: usize, joint: &Joint, drive: &JointDrive) -> Result<(), ModelError> {
    let fail = |message: String| ModelError::Joint { joint: number, name: joint.name.clone(), message };
    let positive = |field: &str, value: f64| {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(fail(format!("`drive.{field}` must be a positive finite number, got {value}")))
        }
    };
    if drive.steps_per_rev == 0 {
        return Err(fail("`drive.steps_per_rev` must be at least 1, got 0".into()));
    }
    if !(1..=256).contains(&drive.microstepping) {
        return Err(fail(format!("`drive.microstepping` must be 1 to 256, got {}", drive.microstepping)));
    }
    positive("gear_ratio", drive.gear_ratio)?;
    positive("max_step_rate", drive.max_step_rate)?;
    if let Some(a) = drive.max_acceleration {
        positive("max_acceleration", a)?;
    }
    if drive.direction != 1 && drive.direction != -1 {
        return Err(fail(format!("`drive.direction` must be 1 or -1, got {}", drive.direction)));
    }
    match (joint.kind, drive.lead) {
        (JointKind::Prismatic, None) => {
            return Err(fail("`drive.lead` (travel per screw revolution) is required for a prismatic joint".into()));
        }
        (JointKind::Revolute, Some(_)) => {
            return Err(fail("`drive.lead` applies to prismatic joints only".into()));
        }
        (JointKind::Prismatic, Some(lead)) => positive("lead", lead)?,
        (JointKind::Revolute, None) => {}
    }
    if let Some(mode) = drive.mode {
        let needed = if mode == StepMode::Half { 2 } else { 1 };
        if drive.microstepping != needed {
            return Err(fail(format!(
                "`drive.mode = \"{}\"` needs `drive.microstepping = {needed}`, got {}",
                match mode {
                    StepMode::Wave => "wave",
                    StepMode::Full => "full",
                    StepMode::Half => "half",
                },
                drive.microstepping
            )));
        }
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
