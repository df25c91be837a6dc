//! Named numeric tolerances, in one place.
//!
//! Every tolerance used by the library is a named constant here, with the reason for its value.

/// Largest deviation from orthonormality accepted for a rotation matrix given by a user
/// (`‖RᵀR − I‖∞`). Hand-typed matrices with 6–7 significant digits (e.g. `0.7071068`) stay
/// below it; anything larger is a mistake rather than rounding.
pub const ROTATION_ORTHONORMALITY: f64 = 1e-6;

/// Smallest accepted norm of a joint axis vector before normalisation (URDF `<axis xyz>`).
/// An axis shorter than this carries no direction.
pub const AXIS_MIN_NORM: f64 = 1e-9;

/// Relative threshold under which a singular value of the Jacobian counts as zero when the
/// rank is reported; `σ_i / σ_max` below this is numerically singular for f64 Jacobians
/// whose entries are O(1) metres or radians.
pub const SINGULAR_VALUE_RELATIVE: f64 = 1e-9;
