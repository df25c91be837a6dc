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

/// Largest tool-position error (metres) for which an inverse-kinematics candidate still counts
/// as a solution when it is checked by forward kinematics. Closed forms reach ~1e-12 m; the
/// margin covers `acos`/`asin` arguments clamped at the workspace boundary and the numeric
/// solver's convergence threshold.
pub const IK_POSITION: f64 = 1e-6;

/// Largest tool-orientation error (radians, angle of `R_targetᵀ·R`) for an IK solution.
pub const IK_ORIENTATION: f64 = 1e-6;

/// Two IK solutions closer than this in every joint (radians / metres) are the same solution
/// (branches coincide at singular configurations).
pub const IK_DUPLICATE: f64 = 1e-7;

/// Tolerance on joint limits when IK flags a solution as within limits (radians / metres):
/// a solution computed as exactly on a limit must not be rejected by rounding.
pub const LIMIT_SLACK: f64 = 1e-9;

/// Tolerance for arguments of `acos`/`asin` and for reach tests: a value within this of the
/// boundary (|x| ≤ 1 + ε, relative) is clamped rather than declared unreachable.
pub const BOUNDARY: f64 = 1e-9;

/// Internal stopping threshold of the numeric IK solver, metres: 1000× below [`IK_POSITION`]
/// so that the forward-kinematics check of every solution never rejects a converged one.
/// Levenberg–Marquardt converges about quadratically near a regular solution, so the extra
/// digits cost about one iteration.
pub const IK_NUMERIC_POSITION: f64 = 1e-9;

/// Internal stopping threshold of the numeric IK solver, radians (see [`IK_NUMERIC_POSITION`]).
pub const IK_NUMERIC_ORIENTATION: f64 = 1e-9;

/// Two numeric IK solutions closer than this in every joint (radians / metres) are the same:
/// starts that converge to one branch agree to ~1e-8 (the stopping threshold divided by the
/// smallest singular value), much finer than any two genuinely different branches.
pub const IK_NUMERIC_DISTINCT: f64 = 1e-4;

/// A numeric IK solution is flagged singular when the smallest singular value of the relevant
/// Jacobian rows is below this fraction of the largest: an iterative solution sits only within
/// ~1e-9 of a singular configuration, so the exact-rank threshold [`SINGULAR_VALUE_RELATIVE`]
/// would miss it.
pub const IK_NUMERIC_SINGULAR: f64 = 1e-6;

/// Distance (metres) under which a point counts as lying on a joint axis in a closed-form IK
/// (seed 003: the wrist point C on the column axis, shoulder singularity; the elbow point on
/// the shoulder axis of an arm with equal links). The undetermined angle is then taken from
/// the seed; that moves the tool by at most this distance, far below [`IK_POSITION`]. Just
/// above it the direct formula's round-off (`atan2` of coordinates ~1e-9 m: ~1e-7 rad) is
/// still below [`IK_ORIENTATION`].
pub const IK_AXIS_DISTANCE: f64 = 1e-9;

/// Sine of the angle under which two joint axes count as parallel in a closed-form IK
/// (seed 003's wrist singularity: axis 6 parallel to axes 2–4, `sin∠(w, e6) = 0`). Below it
/// the normal `w × e6` is round-off and the undetermined angle is taken from the seed (error
/// ≤ this sine, in radians); just above it normalising `w × e6` loses ~1e-16/1e-9 = 1e-7 rad.
/// Both stay below [`IK_ORIENTATION`].
pub const IK_PARALLEL_SINE: f64 = 1e-9;

/// Tolerance (radians) when a closed-form solver checks a DH twist or angle against the
/// value its structure needs (0°, ±90°, 180°): tables typed in degrees convert with ~1e-16
/// error, while a real design deviation is many orders larger.
pub const STRUCTURE_ANGLE: f64 = 1e-9;

/// Tolerance (metres) when a closed-form solver checks that a DH length is zero.
pub const STRUCTURE_LENGTH: f64 = 1e-9;

/// Fraction of a step by which the last value of a scanned grid may overshoot the end of
/// the scanned range and still count (seed 000's α scan, `α_min + i·Δα ≤ 180°`): absorbs the
/// rounding of `i·Δα` so that an exact end value (e.g. 90° + 9000 · 0.01° = 180°) is kept.
pub const SCAN_GRID: f64 = 1e-9;
