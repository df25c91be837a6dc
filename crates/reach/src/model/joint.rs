use nalgebra::{Isometry3, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// How the joint frames of a chain are described.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Convention {
    /// Standard (distal) Denavit–Hartenberg: `A_i = Rz(θ_i)·Tz(d_i)·Tx(a_i)·Rx(α_i)`; frame *i*
    /// sits at the far end of link *i* and joint *i* turns about `z_{i−1}`.
    Dh,
    /// Modified (proximal, Craig) Denavit–Hartenberg: `A_i = Rx(α_{i−1})·Tx(a_{i−1})·Rz(θ_i)·Tz(d_i)`,
    /// written per row as `(a, alpha)` of the *preceding* link; joint *i* turns about `z_i`.
    Mdh,
    /// URDF style: each joint is a fixed origin transform followed by a motion about (or
    /// along) a unit axis given in the joint frame.
    Urdf,
}

impl Convention {
    /// The name used in files and output: `dh`, `mdh` or `urdf`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Convention::Dh => "dh",
            Convention::Mdh => "mdh",
            Convention::Urdf => "urdf",
        }
    }
}

/// Revolute (angle, radians) or prismatic (length, metres).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum JointKind {
    /// Rotation about the joint axis; the joint variable is an angle in radians.
    Revolute,
    /// Translation along the joint axis; the joint variable is a length in metres.
    Prismatic,
}

impl JointKind {
    /// `revolute` or `prismatic`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            JointKind::Revolute => "revolute",
            JointKind::Prismatic => "prismatic",
        }
    }
}

/// Closed position interval `[lower, upper]` of a joint (radians or metres).
///
/// Infinite bounds mean "unlimited" (a continuous joint); NaN is never valid.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Limits {
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
}

impl Limits {
    /// An unlimited (continuous) joint.
    pub const UNLIMITED: Limits = Limits { lower: f64::NEG_INFINITY, upper: f64::INFINITY };

    /// `[lower, upper]`.
    #[must_use]
    pub const fn new(lower: f64, upper: f64) -> Self {
        Limits { lower, upper }
    }

    /// Whether both bounds are finite.
    #[must_use]
    pub fn is_bounded(&self) -> bool {
        self.lower.is_finite() && self.upper.is_finite()
    }

    /// Whether `value` lies in the closed interval, allowing `tolerance` on either side.
    #[must_use]
    #[inline]
    pub fn contains(&self, value: f64, tolerance: f64) -> bool {
        // `&`, not `&&`: both tests are cheap and pure, and branch-free code vectorises over
        // lanes of values (the IK's limit screen).
        (value >= self.lower - tolerance) & (value <= self.upper + tolerance)
    }

    /// The home position used when a description gives none: 0 when inside the limits, else
    /// the middle of a bounded range, else the finite bound nearest to 0 (for a range open on
    /// one side, whose middle would be infinite).
    #[must_use]
    pub(crate) fn default_home(&self) -> f64 {
        if self.contains(0.0, 0.0) {
            0.0
        } else if self.is_bounded() {
            0.5 * (self.lower + self.upper)
        } else if self.lower > 0.0 {
            self.lower
        } else if self.upper < 0.0 {
            self.upper
        } else {
            0.0 // NaN limits: rejected by validation
        }
    }

    /// Width of the interval (infinite for unlimited joints).
    #[must_use]
    pub fn span(&self) -> f64 {
        self.upper - self.lower
    }
}

/// Denavit–Hartenberg parameters of one joint, SI units and radians.
///
/// For [`Convention::Dh`] `a` and `alpha` belong to link *i* (after the joint); for
/// [`Convention::Mdh`] they belong to link *i−1* (before the joint), as in Craig's book.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DhParams {
    /// Link length along x, metres.
    pub a: f64,
    /// Link twist about x, radians.
    pub alpha: f64,
    /// Link offset along z, metres (for a prismatic joint: the offset added to the variable).
    pub d: f64,
    /// Joint angle offset about z, radians (for a prismatic joint: the fixed angle).
    pub theta_offset: f64,
}

/// The fixed geometry of one joint, in the robot's [`Convention`].
#[derive(Debug, Clone, PartialEq)]
pub enum JointGeometry {
    /// DH or MDH parameters (the robot's convention says which).
    Dh(DhParams),
    /// URDF joint: origin of the joint frame in the parent frame, then the motion axis
    /// (unit vector in the joint frame).
    Axis {
        /// Joint frame relative to the previous joint frame (fixed joints in between folded in).
        origin: Isometry3<f64>,
        /// Unit axis of rotation or translation in the joint frame.
        axis: Unit<Vector3<f64>>,
    },
}

/// A URDF joint that follows another joint of the chain (`<mimic>`): its value is
/// `multiplier · q[master] + offset`, with `q[master]` the master's value as the user gives it.
///
/// A mimic joint is not a degree of freedom: it has no entry in the joint vector, no limits
/// (the URDF `<limit>` of a mimic joint is a consequence of its master's and is not checked)
/// and no reported link frame. It sits on the chain between the independent joints: the
/// geometry of whatever comes next on the chain (the next joint's `origin`, another mimic
/// joint's, or the tool transform) is given relative to its child frame.
#[derive(Debug, Clone, PartialEq)]
pub struct MimicJoint {
    /// Joint name (from the file).
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Where it sits on the chain: the number of independent joints before it (0 = before the
    /// first joint). Mimic joints are listed in chain order, so positions never decrease.
    pub position: usize,
    /// Joint frame relative to the previous movable joint's child frame (the base frame for
    /// the first one), fixed joints in between folded in.
    pub origin: Isometry3<f64>,
    /// Unit axis of rotation or translation in the joint frame.
    pub axis: Unit<Vector3<f64>>,
    /// 0-based index of the master among the robot's (independent) joints.
    pub master: usize,
    /// Factor on the master's value (URDF default 1).
    pub multiplier: f64,
    /// Added to the scaled value, radians or metres (URDF default 0).
    pub offset: f64,
}

/// One movable joint of a serial chain.
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    /// Joint name (from the file, or `joint{i}`).
    pub name: String,
    /// Revolute or prismatic.
    pub kind: JointKind,
    /// Fixed geometry (DH/MDH parameters or URDF origin and axis).
    pub geometry: JointGeometry,
    /// Position limits, radians or metres.
    pub limits: Limits,
    /// Optional speed limit, rad/s or m/s (symmetric: `|q̇| ≤ max_velocity`).
    pub max_velocity: Option<f64>,
    /// Optional acceleration limit, rad/s² or m/s² (symmetric: `|q̈| ≤ max_acceleration`).
    pub max_acceleration: Option<f64>,
    /// Optional jerk limit, rad/s³ or m/s³ (symmetric).
    pub max_jerk: Option<f64>,
    /// Home (rest) position, radians or metres; inside the limits.
    pub home: f64,
    /// Stepper drive (motor, gear, step limits), when the description gives one.
    pub drive: Option<JointDrive>,
    /// Reverse the joint direction: the model uses `−q` where the user gives `q`
    /// (like the `flip` attribute of the Robotics Toolbox). Limits apply to the user's `q`.
    pub flip: bool,
}

impl Joint {
    /// Whether differences of this joint wrap: a **revolute joint without limits**
    /// (continuous, both bounds infinite) may turn either way, so it takes the shortest signed
    /// difference. See [`Joint::difference`].
    #[must_use]
    #[inline]
    pub fn wraps(&self) -> bool {
        self.kind == JointKind::Revolute && !self.limits.lower.is_finite() && !self.limits.upper.is_finite()
    }

    /// The difference this joint travels from `from` to `to` — **the** joint-difference rule of
    /// the crate, used by joint-space motion, J1/J2, durations, rates, energy, IK choice,
    /// tracking and sequencing alike:
    ///
    /// * a revolute joint without limits ([`Joint::wraps`]) takes the shortest signed
    ///   difference `wrap(to − from) ∈ (−π, π]`: it may turn either way, the short way is the
    ///   cheaper one, and a joint-space motion travels exactly that;
    /// * every other joint — prismatic, or revolute with any finite bound, however wide
    ///   (±360° included) — takes the literal difference `to − from`: a bounded joint cannot
    ///   take the short way round through its limit, and a joint-space motion interpolates the
    ///   literal values, so that is what it travels (UR5 from 170° to −170° turns 340°).
    ///
    /// # Example
    /// ```
    /// use reach::model::Joint;
    /// let continuous = Joint::revolute(0.0, 0.0, 0.0, 0.0);
    /// let limited = Joint::revolute(0.0, 0.0, 0.0, 0.0).with_limits(0.0, 6.3);
    /// assert!((continuous.difference(6.0, 0.2) - (0.2 - 6.0 + std::f64::consts::TAU)).abs() < 1e-12);
    /// assert!((limited.difference(6.0, 0.2) + 5.8).abs() < 1e-12);
    /// ```
    #[must_use]
    #[inline]
    pub fn difference(&self, from: f64, to: f64) -> f64 {
        if self.wraps() { crate::angle::shortest_difference(from, to) } else { to - from }
    }

    /// The joint speed and acceleration its stepper drive allows, rad/s and rad/s² (m/s, m/s²
    /// for a prismatic joint): `max_step_rate` and the drive's `max_acceleration` divided by
    /// the steps per unit. `None` where the joint has no drive, the drive no ramp limit, or a
    /// prismatic drive no `lead`.
    #[must_use]
    pub fn drive_limits(&self) -> (Option<f64>, Option<f64>) {
        let Some((drive, per_unit)) = self.drive.as_ref().and_then(|d| Some((d, d.steps_per_unit(self.kind)?))) else {
            return (None, None);
        };
        (Some(drive.max_step_rate / per_unit), drive.max_acceleration.map(|a| a / per_unit))
    }

    /// A revolute standard/modified DH joint with no limits; adjust the fields as needed.
    #[must_use]
    pub fn revolute(a: f64, alpha: f64, d: f64, theta_offset: f64) -> Self {
        Joint {
            name: String::new(),
            kind: JointKind::Revolute,
            geometry: JointGeometry::Dh(DhParams { a, alpha, d, theta_offset }),
            limits: Limits::UNLIMITED,
            max_velocity: None,
            max_acceleration: None,
            max_jerk: None,
            home: 0.0,
            drive: None,
            flip: false,
        }
    }

    /// A prismatic DH joint (variable along z, added to `d`) with no limits.
    #[must_use]
    pub fn prismatic(a: f64, alpha: f64, d: f64, theta_offset: f64) -> Self {
        Joint { kind: JointKind::Prismatic, ..Joint::revolute(a, alpha, d, theta_offset) }
    }

    /// Sets the position limits (builder style).
    #[must_use]
    pub fn with_limits(mut self, lower: f64, upper: f64) -> Self {
        self.limits = Limits::new(lower, upper);
        self
    }

    /// Sets the name (builder style).
    #[must_use]
    pub fn named(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// The DH parameters, if the joint is described by DH/MDH.
    #[must_use]
    pub fn dh(&self) -> Option<&DhParams> {
        match &self.geometry {
            JointGeometry::Dh(p) => Some(p),
            JointGeometry::Axis { .. } => None,
        }
    }
}

/// Collision geometry of one link (the body moved by the joint of the same index).
///
/// Links are modelled as segments between consecutive joint-frame origins, swept by a
/// sphere of `radius` (a capsule), as both seeds 000 and 004 model links as segments.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LinkGeometry {
    /// Capsule radius, metres (0 = bare segment).
    pub radius: f64,
}

/// How a stepper motor's windings are wired to its driver (seed 000, thesis §II.3.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Wiring {
    /// Centre-tapped windings, four switched half-windings (seed 000, Table 1).
    Unipolar,
    /// Two windings whose polarity the driver reverses (seed 000, Table 2).
    Bipolar,
}

/// The coil sequence a controller uses when it switches the windings itself.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StepMode {
    /// One phase on at a time, four states per electrical cycle ("wave drive"; seed 000's
    /// unipolar Table 1).
    Wave,
    /// Two phases on at a time, four states per cycle (seed 000's bipolar Table 2).
    Full,
    /// Alternately one and two phases on, eight states per cycle; one step is half a full step.
    Half,
}

/// How one joint is driven by a stepper motor (all counts in the driver's pulse unit).
///
/// The motor step counter is `home_steps + direction · steps_per_unit · (q − home)`, where
/// `steps_per_unit` is [`JointDrive::steps_per_unit`] (pulses per radian or per metre).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct JointDrive {
    /// Motor full steps per motor revolution (200 for a 1.8° hybrid stepper).
    pub steps_per_rev: u32,
    /// Pulses per full step: 1 = full step, 2 = half step, up to 256 (microstepping drivers).
    pub microstepping: u32,
    /// Motor revolutions per revolution of the joint (revolute) or of the lead screw (prismatic).
    pub gear_ratio: f64,
    /// Prismatic joints only: travel per lead-screw revolution, metres.
    pub lead: Option<f64>,
    /// +1 when a positive motor step moves the joint in its positive direction, −1 otherwise.
    pub direction: i32,
    /// Maximum pulse rate, steps per second (Hz).
    pub max_step_rate: f64,
    /// Maximum rate of change of the pulse rate, steps/s²; `None` = the motor may start and
    /// stop at any rate up to `max_step_rate` (seed 000's constant-rate pulse trains).
    pub max_acceleration: Option<f64>,
    /// Winding wiring.
    pub wiring: Wiring,
    /// Coil sequence when the controller switches the coils itself; `None` for a step/direction
    /// driver with `microstepping > 2`. See [`JointDrive::coil_mode`].
    pub mode: Option<StepMode>,
    /// Step counter value at the joint's home position.
    pub home_steps: i64,
}

impl JointDrive {
    /// Pulses per radian (revolute) or per metre (prismatic); `None` for a prismatic joint
    /// without a `lead`.
    #[must_use]
    pub fn steps_per_unit(&self, kind: JointKind) -> Option<f64> {
        let per_motor_rev = f64::from(self.steps_per_rev) * f64::from(self.microstepping) * self.gear_ratio;
        match kind {
            JointKind::Revolute => Some(per_motor_rev / std::f64::consts::TAU),
            JointKind::Prismatic => self.lead.map(|lead| per_motor_rev / lead),
        }
    }

    /// The coil sequence in use: the explicit `mode`, else the seed's pairing for one pulse per
    /// full step (unipolar → wave drive, Table 1; bipolar → two phases on, Table 2), half step
    /// for two pulses per full step, and `None` (step/direction driver only) above that.
    #[must_use]
    pub fn coil_mode(&self) -> Option<StepMode> {
        self.mode.or(match (self.microstepping, self.wiring) {
            (1, Wiring::Unipolar) => Some(StepMode::Wave),
            (1, Wiring::Bipolar) => Some(StepMode::Full),
            (2, _) => Some(StepMode::Half),
            _ => None,
        })
    }
}
