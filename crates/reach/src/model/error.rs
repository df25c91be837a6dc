use thiserror::Error;

/// Why a robot model could not be built or parsed.
///
/// Joint numbers in messages are 1-based, as robotics texts number them.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The chain has no movable joint.
    #[error("the robot has no joints (at least one revolute or prismatic joint is required)")]
    NoJoints,
    /// A joint parameter is NaN or infinite.
    #[error("joint {joint} ({name}): field `{field}` must be a finite number, got {value}")]
    NonFinite {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// Field name as in the description file.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// Lower limit not below upper limit, or a NaN limit.
    #[error("joint {joint} ({name}): limits must satisfy lower < upper, got [{lower}, {upper}]")]
    LimitsOrder {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// Lower limit (SI).
        lower: f64,
        /// Upper limit (SI).
        upper: f64,
    },
    /// A velocity limit that is not a positive finite number.
    #[error("joint {joint} ({name}): velocity limit must be positive and finite, got {value}")]
    VelocityLimit {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// The offending value (SI).
        value: f64,
    },
    /// A joint entry is inconsistent (e.g. two velocity limits given).
    #[error("joint {joint} ({name}): {message}")]
    Joint {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// The joint description does not match the robot's convention (e.g. a URDF joint in a DH robot).
    #[error("joint {joint} ({name}): its geometry is not described in the robot's convention `{convention}`")]
    MixedConvention {
        /// 1-based joint number.
        joint: usize,
        /// Joint name.
        name: String,
        /// The robot's convention.
        convention: &'static str,
    },
    /// A base or tool transform (or a URDF origin) has a non-finite or non-orthonormal part.
    #[error("`{which}` transform is invalid: {reason}")]
    Transform {
        /// Which transform (`base`, `tool`, or a URDF joint origin).
        which: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A mimic joint (URDF `<mimic>`) is inconsistent with the robot.
    #[error("mimic joint `{name}`: {message}")]
    Mimic {
        /// The mimic joint's name.
        name: String,
        /// What is wrong.
        message: String,
    },
    /// A link geometry entry is invalid or their number does not match the joints.
    #[error("links: {0}")]
    Links(String),
    /// The dynamics data as a whole is invalid (gravity not finite, wrong number of entries).
    #[error("dynamics: {0}")]
    Dynamics(String),
    /// The description file is not valid TOML or does not follow the format.
    #[error("robot file, line {line}, column {column}: {message}")]
    Parse {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What the parser expected.
        message: String,
    },
    /// A URDF file could not be read or does not describe a usable serial chain.
    #[error("URDF: {0}")]
    Urdf(String),
    /// A MoveIt `joint_limits.yaml` could not be read or gives a limit it does not hold.
    #[error("joint limits file: {0}")]
    JointLimits(String),
    /// The chain has no standard-DH equivalent ([`Robot::dh_equivalent`](super::Robot::dh_equivalent)).
    #[error("robot `{robot}` has no standard-DH equivalent: {reason}")]
    NoDhEquivalent {
        /// The robot's name.
        robot: String,
        /// Why (a prismatic or mimic joint, or forward kinematics that disagree).
        reason: String,
    },
    /// No preset robot has this name.
    #[error("unknown robot preset `{name}` (known: {known})")]
    UnknownPreset {
        /// The name asked for.
        name: String,
        /// Comma-separated list of preset names.
        known: String,
    },
}
