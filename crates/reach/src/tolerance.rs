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
/// The solver stops at the same fraction of every tolerance (position and orientation).
/// Levenberg–Marquardt converges about quadratically near a regular solution, so the extra
/// digits cost about one iteration.
pub const IK_NUMERIC_POSITION: f64 = 1e-9;

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

/// Tolerance of the standard-DH equivalent of a chain ([`Robot::dh_equivalent`](crate::model::Robot::dh_equivalent)):
/// derived twists within this (radians) of a multiple of 90° and lengths within this (metres)
/// of zero are made exact, and the equivalent's forward kinematics must agree with the
/// robot's to this (every entry of the homogeneous transform, metres and cosines). URDF files
/// print π/2 with 7 to 10 digits (`1.570796325` is 1.8e-9 rad off, a few 1e-9 m at the tool
/// of a 1 m arm); a real design deviation is many orders larger.
pub const DH_EQUIVALENT: f64 = 1e-8;

/// A standard-DH equivalent whose forward kinematics agree with the robot's to this (metres
/// and cosines; rounding is ~1e-16) is exact. Above it (twists or lengths made exact, up to
/// [`DH_EQUIVALENT`]) the closed-form solutions computed on it are refined by Newton steps on
/// the robot itself, so that they meet a pose target to rounding, not to the equivalent's gap.
pub const DH_EQUIVALENT_EXACT: f64 = 1e-12;

/// Fraction of a step by which the last value of a scanned grid may overshoot the end of
/// the scanned range and still count (seed 000's α scan, `α_min + i·Δα ≤ 180°`): absorbs the
/// rounding of `i·Δα` so that an exact end value (e.g. 90° + 9000 · 0.01° = 180°) is kept.
pub const SCAN_GRID: f64 = 1e-9;

/// Contact tolerance of the world module (metres): a link whose clearance to an obstacle is
/// within this of zero touches it (a collision for closed obstacles, allowed for open ones),
/// and the tool point must be inside its allowed zone by more than this. 1 nm = 1e-6 mm is
/// the value seed 004's reference counts use (notes 004 §5.4): grid nodes that lie on a zone
/// boundary analytically land within ~1e-13 m of it in floating point.
pub const CONTACT: f64 = 1e-9;

/// Fraction of a step by which a sampling grid's last point may fall short of the end of the
/// interval and still count as the end (motion sampling, `t0 + k·dt`): absorbs the rounding of
/// `duration / dt` (e.g. `10 / 0.1`), so an exact multiple gives one sample at the end, not two
/// a rounding error apart.
pub const SAMPLE_GRID: f64 = 1e-9;

/// Rotation angle (radians) below which a tool motion counts as a pure translation and its
/// rotation axis is undefined (seed 001's `e = vee(Rf − Rfᵀ)/(2 sin φ1)` divides by ~0): the
/// axis is then taken as z. Rotating by less than this about any axis moves orientations by
/// less than [`IK_ORIENTATION`] / 1000.
pub const ROTATION_ANGLE_ZERO: f64 = 1e-9;

/// Path tracking: bisection and golden-section searches on the path parameter stop when the
/// bracket is narrower than this fraction of the path's parameter range (for seed 003's
/// 0.944 m weld, 1e-9 m). Far below any position tolerance a user can see, and reached in
/// ~30 halvings.
pub const TRACKING_PARAMETER: f64 = 1e-9;

/// Path tracking: a refined local minimum of a singularity measure at or below this is a
/// singular position. The measures vanish linearly at a singularity (`σ_min/σ_max`,
/// `sin∠(w, e6)`, `√(1 − |cos θ_elbow|)` ≈ |θ_elbow|/√2, `(ρ − |D|)/L`), so after the search
/// to [`TRACKING_PARAMETER`] an exact crossing or touch leaves ~1e-9, while a path that
/// misses the singularity by more than ~1e-6 (radians, or the same fraction of the arm's
/// length) is not split there.
pub const TRACKING_SINGULAR: f64 = 1e-6;

/// Path tracking: half-width, as a fraction of the path's parameter range, of the central
/// difference that estimates an instantaneous joint rate when a speed-limit crossing is
/// refined. Truncation error ~h², round-off ~1e-16/h: 1e-6 balances both near 1e-10 relative.
pub const TRACKING_RATE_STEP: f64 = 1e-6;

/// Drives: relative slack when a step rate or acceleration is compared with a motor's limit
/// (and a point-to-point duration with the shortest feasible one). A plan computed to run a
/// motor exactly at its limit reaches it up to f64 round-off (~1e-15 relative); 1e-9 keeps
/// such plans feasible while any real excess (a fraction of a hertz at 500 Hz) is caught.
pub const DRIVE_LIMIT_SLACK: f64 = 1e-9;

/// Drives: fraction by which a point-to-point ramp plans below each motor's acceleration
/// limit. Steps are discrete, so the acceleration measured from three consecutive step times
/// (rate change between intervals over their mean length) can exceed the continuous ramp's by
/// up to ~0.6 % at the second step of a ramp from rest; planning 2 % below the limit keeps
/// the measured value under it (checked in `tests/it/drive_schedule.rs`).
pub const DRIVE_RAMP_MARGIN: f64 = 0.02;
