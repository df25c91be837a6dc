use nalgebra::{Isometry3, Unit, Vector3};
use serde::{Deserialize, Serialize};

/// How the joint frames of a chain are described.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
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
        value >= self.lower - tolerance && value <= self.upper + tolerance
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
    /// Home (rest) position, radians or metres; inside the limits.
    pub home: f64,
    /// Reverse the joint direction: the model uses `−q` where the user gives `q`
    /// (like the `flip` attribute of the Robotics Toolbox). Limits apply to the user's `q`.
    pub flip: bool,
}

impl Joint {
    /// A revolute standard/modified DH joint with no limits; adjust the fields as needed.
    #[must_use]
    pub fn revolute(a: f64, alpha: f64, d: f64, theta_offset: f64) -> Self {
        Joint {
            name: String::new(),
            kind: JointKind::Revolute,
            geometry: JointGeometry::Dh(DhParams { a, alpha, d, theta_offset }),
            limits: Limits::UNLIMITED,
            max_velocity: None,
            home: 0.0,
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
