//! Rigid-body dynamics of the arm: joint torques by recursive Newton–Euler, gravity torques,
//! the joint-space mass matrix, kinetic and potential energy, and the mechanical energy of a
//! sampled joint trajectory.
//!
//! # Model
//!
//! Each link is one rigid body with the [`LinkInertial`] of the robot description (mass,
//! centre of mass, inertia about the centre of mass, in the link frame; see [`LinkInertial`]
//! for the frame of each convention). Joints are ideal: no friction, no motor (rotor) inertia,
//! no gear losses, no elasticity. Gravity is the robot's [`Robot::gravity`] (default
//! 9.80665 m/s² along −z of the world frame); the base does not move. A flipped joint
//! (`flip = true`) reports torque and takes rates in the user's direction.
//!
//! [`inverse_dynamics`] runs the recursive Newton–Euler algorithm (RNEA; Luh, Walker & Paul
//! 1980, as in Craig ch. 6 and Corke's `rne`) with all vectors in world coordinates on the
//! compiled chain `F0·M1(q1)·F1 ⋯` of [`crate::kinematics`]: the link inertials are moved once
//! into the frame right after each joint motion, whose z axis is the joint axis. Gravity enters
//! as an upward acceleration `−g` of the base. Outward pass: angular velocity and acceleration
//! and the acceleration of each joint origin and centre of mass; inward pass: the force `f` and
//! moment `n` (about the joint origin) that link *i−1* exerts on link *i*; `τᵢ = zᵢ·nᵢ`
//! (revolute, N·m) or `τᵢ = zᵢ·fᵢ` (prismatic, N).
//!
//! [`kinetic_energy`] and [`potential_energy`] are computed independently of the recursion,
//! from the link frames of [`Robot::frames`] and the geometric Jacobian columns of each centre
//! of mass, with the inertials as written in the description; the tests use them to check the
//! power balance `Σ τᵢ·q̇ᵢ = d/dt (T + V)`.
//!
//! # Mechanical energy of a motion
//!
//! [`mechanical_energy`] is `E = ∫ Σᵢ |τᵢ(t)·q̇ᵢ(t)| dt` (joules) by the trapezoid rule over the
//! samples: the energy the joint drives deliver, counting braking (negative power) as spent,
//! since drives without regeneration do not recover it. [`trajectory_energy`] takes only times
//! and joint positions and estimates the rates by finite differences (see [`joint_rates`]);
//! [`trajectory_energy_with_rates`] takes the rates the samples carry and differentiates only
//! them for the accelerations.
//!
//! # Example
//! ```
//! use reach::effort::dynamics::{gravity_torques, inverse_dynamics};
//! use reach::model::presets;
//! let puma = presets::get("puma560").unwrap();
//! let q = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
//! let g = gravity_torques(&puma, &q).unwrap();
//! let tau = inverse_dynamics(&puma, &q, &[0.0; 6], &[0.0; 6]).unwrap();
//! assert_eq!(g, tau);
//! assert!(g[1] > 30.0); // the shoulder holds the outstretched upper arm
//! ```

use nalgebra::{DMatrix, Matrix3, Vector3};
use thiserror::Error;

use super::Differences;
use crate::model::fk_chain::Stop;
use crate::model::{JointKind, LinkInertial, Robot};

/// Why a dynamics quantity could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum DynamicsError {
    /// The robot description gives no link masses.
    #[error(
        "robot `{robot}` has no inertial data: give `[joints.inertial]` for every joint, or `<inertial>` in the URDF"
    )]
    NoInertialData {
        /// Robot name.
        robot: String,
    },
    /// A vector does not have one entry per joint (or per sample).
    #[error("`{field}` has {found} values, expected {expected}")]
    Length {
        /// The offending field (`q`, `qd`, `qdd`, `tau`, `sample 3`, …).
        field: String,
        /// Needed length.
        expected: usize,
        /// Given length.
        found: usize,
    },
    /// A value is NaN or infinite.
    #[error("`{field}` must be a finite number, got {value}")]
    NonFinite {
        /// The offending field and index (`qd[2]`, `times[4]`).
        field: String,
        /// The value.
        value: f64,
    },
    /// Sample times are not strictly increasing.
    #[error("sample times must increase strictly: times[{index}] = {value} s follows {previous} s")]
    Times {
        /// 0-based index of the offending sample.
        index: usize,
        /// Its time, s.
        value: f64,
        /// The time before it, s.
        previous: f64,
    },
}

/// One link's mass properties in the frame right after its joint motion (z = joint axis).
#[derive(Debug, Clone, Copy)]
struct Body {
    mass: f64,
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
}

/// A reusable inverse-dynamics workspace for one robot: no allocation per call.
///
/// ```
/// use reach::effort::dynamics::Dynamics;
/// use reach::model::presets;
/// let puma = presets::get("puma560").unwrap();
/// let mut dynamics = Dynamics::new(&puma).unwrap();
/// let mut tau = [0.0; 6];
/// dynamics.inverse_dynamics_into(&[0.1; 6], &[0.5; 6], &[1.0; 6], &mut tau).unwrap();
/// assert!(tau.iter().all(|t| t.is_finite()));
/// ```
#[derive(Debug, Clone)]
pub struct Dynamics<'r> {
    robot: &'r Robot,
    bodies: Vec<Body>,
    axis: Vec<Vector3<f64>>,
    origin: Vec<Vector3<f64>>,
    rotation: Vec<Matrix3<f64>>,
    com: Vec<Vector3<f64>>,
    force: Vec<Vector3<f64>>,
    moment: Vec<Vector3<f64>>,
    zeros: Vec<f64>,
    unit: Vec<f64>,
    column: Vec<f64>,
}

impl<'r> Dynamics<'r> {
    /// Prepares the workspace (moves the link inertials into the joint-motion frames).
    ///
    /// # Errors
    /// [`DynamicsError::NoInertialData`] when the robot has no mass properties.
    pub fn new(robot: &'r Robot) -> Result<Self, DynamicsError> {
        if !robot.has_dynamics() {
            return Err(DynamicsError::NoInertialData { robot: robot.name().to_string() });
        }
        let bodies = robot
            .chain
            .links
            .iter()
            .zip(robot.inertials())
            .map(|(link, b): (_, &LinkInertial)| {
                // The description's link frame is (motion frame)·to_frame.
                let moved = b.transformed(&link.to_frame);
                Body { mass: moved.mass, com: moved.com, inertia: moved.inertia }
            })
            .collect();
        let n = robot.dof();
        let v = vec![Vector3::zeros(); n];
        Ok(Dynamics {
            robot,
            bodies,
            axis: v.clone(),
            origin: v.clone(),
            rotation: vec![Matrix3::zeros(); n],
            com: v.clone(),
            force: v.clone(),
            moment: v,
            zeros: vec![0.0; n],
            unit: vec![0.0; n],
            column: vec![0.0; n],
        })
    }

    /// The robot this workspace computes for.
    #[must_use]
    pub fn robot(&self) -> &'r Robot {
        self.robot
    }

    /// Joint torques (N·m, revolute) and forces (N, prismatic) `τ = M(q)·q̈ + C(q, q̇)·q̇ + g(q)`
    /// for positions `q` (rad / m), rates `qd` (rad/s / m/s) and accelerations `qdd`
    /// (rad/s² / m/s²), written into `tau`. No allocation.
    ///
    /// # Errors
    /// [`DynamicsError::Length`] or [`DynamicsError::NonFinite`] naming `q`, `qd`, `qdd` or `tau`.
    pub fn inverse_dynamics_into(
        &mut self,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        tau: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let n = self.robot.dof();
        check_vector("q", q, n)?;
        check_vector("qd", qd, n)?;
        check_vector("qdd", qdd, n)?;
        check_length("tau", tau.len(), n)?;
        let g = *self.robot.gravity();
        self.rnea(q, qd, qdd, &g, tau);
        Ok(())
    }

    /// Gravity torques `g(q)` (the torques that hold the arm still), written into `tau`.
    ///
    /// # Errors
    /// As [`Dynamics::inverse_dynamics_into`].
    pub fn gravity_torques_into(&mut self, q: &[f64], tau: &mut [f64]) -> Result<(), DynamicsError> {
        let n = self.robot.dof();
        check_vector("q", q, n)?;
        check_length("tau", tau.len(), n)?;
        let zeros = std::mem::take(&mut self.zeros);
        let g = *self.robot.gravity();
        self.rnea(q, &zeros, &zeros, &g, tau);
        self.zeros = zeros;
        Ok(())
    }

    /// The joint-space mass (inertia) matrix `M(q)` (kg·m², kg·m, kg by joint kinds), column
    /// *j* from one Newton–Euler pass with `q̇ = 0`, `q̈ = eⱼ` and no gravity. Symmetric and
    /// positive definite when every joint moves some mass.
    ///
    /// # Errors
    /// [`DynamicsError`] for a bad `q` or when `out` is not n×n (`field = "mass matrix"`).
    pub fn mass_matrix_into(&mut self, q: &[f64], out: &mut DMatrix<f64>) -> Result<(), DynamicsError> {
        let n = self.robot.dof();
        check_vector("q", q, n)?;
        check_length("mass matrix", out.nrows().min(out.ncols()), n)?;
        check_length("mass matrix", out.nrows().max(out.ncols()), n)?;
        let zeros = std::mem::take(&mut self.zeros);
        let mut unit = std::mem::take(&mut self.unit);
        let mut column = std::mem::take(&mut self.column);
        for j in 0..n {
            unit.iter_mut().enumerate().for_each(|(i, u)| *u = if i == j { 1.0 } else { 0.0 });
            self.rnea(q, &zeros, &unit, &Vector3::zeros(), &mut column);
            out.column_mut(j).copy_from_slice(&column);
        }
        // Symmetric by theory; average away the rounding so that callers get an exact one.
        let sym = (&*out + out.transpose()) * 0.5;
        out.copy_from(&sym);
        self.zeros = zeros;
        self.unit = unit;
        self.column = column;
        Ok(())
    }

    /// Recursive Newton–Euler on checked input (module docs), gravity `g` (m/s², world).
    fn rnea(&mut self, q: &[f64], qd: &[f64], qdd: &[f64], g: &Vector3<f64>, tau: &mut [f64]) {
        let chain = &self.robot.chain;
        // The frames: each joint's axis (before its motion), and the frame after the motion.
        chain.product(q, |stop, t| match stop {
            Stop::Joint(i) => self.axis[i] = t.z_axis(),
            Stop::Moved(i) => {
                self.origin[i] = t.translation();
                self.rotation[i] = t.rotation();
            }
            // A chain with mimic joints has no dynamics (`Robot::new` rejects mass properties
            // with mimic joints).
            Stop::Mimic(_) => {}
        });
        let mut prev_origin = chain.first.translation.vector;
        let mut w = Vector3::zeros();
        let mut wd = Vector3::zeros();
        // A uniform gravity field is the same as an upward acceleration of the base.
        let mut acc = -g;
        for (i, link) in chain.links.iter().enumerate() {
            let (z, o, rot) = (self.axis[i], self.origin[i], &self.rotation[i]);
            let (vd, vdd) = (link.sign * qd[i], link.sign * qdd[i]);
            let r = o - prev_origin;
            // Acceleration of the point o as a point of link i−1.
            let mut a = acc + wd.cross(&r) + w.cross(&w.cross(&r));
            if link.prismatic {
                a += w.cross(&z) * (2.0 * vd) + z * vdd;
            } else {
                wd += z * vdd + w.cross(&z) * vd;
                w += z * vd;
            }
            let body = &self.bodies[i];
            let c = rot * body.com;
            let a_com = a + wd.cross(&c) + w.cross(&w.cross(&c));
            // Euler's equation in the link's axes (cheaper than rotating the tensor).
            let (w_local, wd_local) = (rot.tr_mul(&w), rot.tr_mul(&wd));
            let iw = body.inertia * w_local;
            self.com[i] = c;
            self.force[i] = a_com * body.mass;
            self.moment[i] = rot * (body.inertia * wd_local + w_local.cross(&iw));
            prev_origin = o;
            acc = a;
        }
        let mut f = Vector3::zeros();
        let mut n = Vector3::zeros();
        let mut next_origin = Vector3::zeros();
        for i in (0..chain.links.len()).rev() {
            let o = self.origin[i];
            n = self.moment[i] + self.com[i].cross(&self.force[i]) + n + (next_origin - o).cross(&f);
            f += self.force[i];
            let link = &chain.links[i];
            let along = if link.prismatic { self.axis[i].dot(&f) } else { self.axis[i].dot(&n) };
            tau[i] = link.sign * along;
            next_origin = o;
        }
    }
}

fn check_length(field: &str, found: usize, expected: usize) -> Result<(), DynamicsError> {
    if found == expected { Ok(()) } else { Err(DynamicsError::Length { field: field.to_string(), expected, found }) }
}

/// Checks sample `k` of the rows named `name` (`q[k]`, `q[k][i]` in errors); the field name is
/// formatted only on error.
fn check_row(name: &str, k: usize, values: &[f64], n: usize) -> Result<(), DynamicsError> {
    if values.len() != n {
        return Err(DynamicsError::Length { field: format!("{name}[{k}]"), expected: n, found: values.len() });
    }
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(DynamicsError::NonFinite { field: format!("{name}[{k}][{i}]"), value: values[i] }),
        None => Ok(()),
    }
}

/// Checks that `found` samples match the `m` times (`{name} samples` in errors).
fn check_sample_count(name: &str, found: usize, m: usize) -> Result<(), DynamicsError> {
    if found == m {
        Ok(())
    } else {
        Err(DynamicsError::Length { field: format!("{name} samples"), expected: m, found })
    }
}

fn check_vector(field: &str, values: &[f64], n: usize) -> Result<(), DynamicsError> {
    check_length(field, values.len(), n)?;
    match values.iter().position(|v| !v.is_finite()) {
        Some(i) => Err(DynamicsError::NonFinite { field: format!("{field}[{i}]"), value: values[i] }),
        None => Ok(()),
    }
}

/// Joint torques/forces `τ` (N·m / N) for `q`, `q̇`, `q̈` (see [`Dynamics::inverse_dynamics_into`]).
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data or a vector is bad.
pub fn inverse_dynamics(robot: &Robot, q: &[f64], qd: &[f64], qdd: &[f64]) -> Result<Vec<f64>, DynamicsError> {
    let mut tau = vec![0.0; robot.dof()];
    Dynamics::new(robot)?.inverse_dynamics_into(q, qd, qdd, &mut tau)?;
    Ok(tau)
}

/// Gravity torques/forces `g(q)` (N·m / N): what the joints exert to hold the arm at rest.
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data or `q` is bad.
pub fn gravity_torques(robot: &Robot, q: &[f64]) -> Result<Vec<f64>, DynamicsError> {
    let mut tau = vec![0.0; robot.dof()];
    Dynamics::new(robot)?.gravity_torques_into(q, &mut tau)?;
    Ok(tau)
}

/// The joint-space mass matrix `M(q)` (see [`Dynamics::mass_matrix_into`]).
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data or `q` is bad.
pub fn mass_matrix(robot: &Robot, q: &[f64]) -> Result<DMatrix<f64>, DynamicsError> {
    let mut m = DMatrix::zeros(robot.dof(), robot.dof());
    Dynamics::new(robot)?.mass_matrix_into(q, &mut m)?;
    Ok(m)
}

/// World-frame centre of mass, angular velocity and centre-of-mass velocity of every link, from
/// the link frames and the Jacobian columns `zⱼ × (c − oⱼ)` (independent of the recursion).
fn link_states(robot: &Robot, q: &[f64], qd: &[f64]) -> Result<Vec<LinkState>, DynamicsError> {
    if !robot.has_dynamics() {
        return Err(DynamicsError::NoInertialData { robot: robot.name().to_string() });
    }
    let n = robot.dof();
    check_vector("q", q, n)?;
    check_vector("qd", qd, n)?;
    // `q` is checked, so forward kinematics cannot fail; its error is passed on regardless.
    let frames =
        robot.frames(q).map_err(|e| DynamicsError::NonFinite { field: format!("q ({e})"), value: f64::NAN })?;
    // Joint axis z and a point o on it: the motion frame is (link frame)·to_frame⁻¹.
    let axes: Vec<(Vector3<f64>, Vector3<f64>)> = frames
        .iter()
        .zip(&robot.chain.links)
        .map(|(f, link)| {
            let m = f * link.to_frame.inverse();
            (m.rotation.matrix().column(2).into_owned(), m.translation.vector)
        })
        .collect();
    let mut out = Vec::with_capacity(n);
    for (i, (frame, b)) in frames.iter().zip(robot.inertials()).enumerate() {
        let world = b.transformed(frame);
        let c = world.com;
        let mut w = Vector3::zeros();
        let mut v = Vector3::zeros();
        for (j, (z, o)) in axes.iter().take(i + 1).enumerate() {
            let link = &robot.chain.links[j];
            let rate = link.sign * qd[j];
            if robot.joints()[j].kind == JointKind::Prismatic {
                v += z * rate;
            } else {
                w += z * rate;
                v += z.cross(&(c - o)) * rate;
            }
        }
        out.push(LinkState { com: c, w, v, inertia: world.inertia, mass: world.mass });
    }
    Ok(out)
}

struct LinkState {
    com: Vector3<f64>,
    w: Vector3<f64>,
    v: Vector3<f64>,
    inertia: Matrix3<f64>,
    mass: f64,
}

/// Kinetic energy of the arm `T = Σ ½·mᵢ·|vᵢ|² + ½·ωᵢᵀ·Iᵢ·ωᵢ` (joules) at `q`, `q̇`, from the
/// link velocities (not from the mass matrix or the recursion).
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data or a vector is bad.
pub fn kinetic_energy(robot: &Robot, q: &[f64], qd: &[f64]) -> Result<f64, DynamicsError> {
    let states = link_states(robot, q, qd)?;
    Ok(states.iter().map(|s| 0.5 * s.mass * s.v.norm_squared() + 0.5 * s.w.dot(&(s.inertia * s.w))).sum())
}

/// Potential energy of the arm in the gravity field `V = −Σ mᵢ·g·cᵢ` (joules, zero at the world
/// origin), where `cᵢ` is the world centre of mass of link *i*.
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data or `q` is bad.
pub fn potential_energy(robot: &Robot, q: &[f64]) -> Result<f64, DynamicsError> {
    let states = link_states(robot, q, &vec![0.0; robot.dof()])?;
    Ok(-states.iter().map(|s| s.mass * robot.gravity().dot(&s.com)).sum::<f64>())
}

/// `E = ∫ Σᵢ |τᵢ·q̇ᵢ| dt` (joules) over samples with known rates, trapezoid rule; `tau`
/// from [`inverse_dynamics`] at each sample. One sample gives 0.
///
/// # Errors
/// [`DynamicsError`] when the robot has no inertial data, the four slices differ in length,
/// a sample has the wrong length or a non-finite value (named `q[k]`, `qd[k]`, `qdd[k]`),
/// or the times are not finite and strictly increasing.
pub fn mechanical_energy<Q: AsRef<[f64]>>(
    robot: &Robot,
    times: &[f64],
    q: &[Q],
    qd: &[Q],
    qdd: &[Q],
) -> Result<f64, DynamicsError> {
    integrate_power(robot, times, q, qd, qdd, f64::abs)
}

/// `W⁺ = ∫ Σᵢ max(τᵢ·q̇ᵢ, 0) dt` (joules): the work the joint drives put in, braking (negative
/// power) costing nothing, as for drives that dissipate braking energy for free; samples,
/// torques and rule as [`mechanical_energy`]. Unlike that energy it depends on the direction of
/// a move: since `|P| = max(P, 0) + max(−P, 0)` and the reverse of a rest-to-rest move negates
/// every joint power, `W⁺(move) − W⁺(reverse) = ΔV` (the potential energy gained) and
/// `W⁺(move) + W⁺(reverse) = E(move)`.
///
/// # Errors
/// As [`mechanical_energy`].
pub fn positive_work<Q: AsRef<[f64]>>(
    robot: &Robot,
    times: &[f64],
    q: &[Q],
    qd: &[Q],
    qdd: &[Q],
) -> Result<f64, DynamicsError> {
    integrate_power(robot, times, q, qd, qdd, |p| p.max(0.0))
}

/// `∫ Σᵢ f(τᵢ·q̇ᵢ) dt` by the trapezoid rule over the samples.
fn integrate_power<Q: AsRef<[f64]>>(
    robot: &Robot,
    times: &[f64],
    q: &[Q],
    qd: &[Q],
    qdd: &[Q],
    joint_power: fn(f64) -> f64,
) -> Result<f64, DynamicsError> {
    let mut dynamics = Dynamics::new(robot)?;
    check_times(times)?;
    for (field, rows) in [("q", q), ("qd", qd), ("qdd", qdd)] {
        check_sample_count(field, rows.len(), times.len())?;
    }
    let n = robot.dof();
    for k in 0..times.len() {
        check_row("q", k, q[k].as_ref(), n)?;
        check_row("qd", k, qd[k].as_ref(), n)?;
        check_row("qdd", k, qdd[k].as_ref(), n)?;
    }
    Ok(energy_unchecked(&mut dynamics, times, q, qd, qdd, joint_power))
}

/// The trapezoid sum `∫ Σᵢ joint_power(τᵢ·q̇ᵢ) dt` of [`mechanical_energy`] (`f64::abs`) or
/// [`positive_work`] on inputs already checked: as many finite rows of `dof` values as `times`,
/// times strictly increasing.
fn energy_unchecked<Q: AsRef<[f64]>, D: AsRef<[f64]>, A: AsRef<[f64]>>(
    dynamics: &mut Dynamics<'_>,
    times: &[f64],
    q: &[Q],
    qd: &[D],
    qdd: &[A],
    joint_power: fn(f64) -> f64,
) -> f64 {
    let g = *dynamics.robot.gravity();
    let mut tau = vec![0.0; dynamics.robot.dof()];
    let mut previous: Option<(f64, f64)> = None;
    let mut energy = 0.0;
    for (k, &t) in times.iter().enumerate() {
        let (qk, qdk, qddk) = (q[k].as_ref(), qd[k].as_ref(), qdd[k].as_ref());
        dynamics.rnea(qk, qdk, qddk, &g, &mut tau);
        let power: f64 = tau.iter().zip(qdk).map(|(t, v)| joint_power(t * v)).sum();
        if let Some((t0, p0)) = previous {
            energy += 0.5 * (p0 + power) * (t - t0);
        }
        previous = Some((t, power));
    }
    energy
}

fn check_times(times: &[f64]) -> Result<(), DynamicsError> {
    for (k, &t) in times.iter().enumerate() {
        if !t.is_finite() {
            return Err(DynamicsError::NonFinite { field: format!("times[{k}]"), value: t });
        }
        if k > 0 && t <= times[k - 1] {
            return Err(DynamicsError::Times { index: k, value: t, previous: times[k - 1] });
        }
    }
    Ok(())
}

/// Joint rates `q̇` and accelerations `q̈` estimated from sampled positions.
///
/// Increments are wrap-safe for revolute joints (`wrap(qₖ₊₁ − qₖ)`, see
/// [`Differences::for_robot`]), so a joint reported as −179° after +179° moved 2°. With steps
/// `h₁ = tₖ − tₖ₋₁`, `h₂ = tₖ₊₁ − tₖ` and increments `d₁`, `d₂`, interior samples use the
/// three-point central differences for uneven steps (second order):
/// `q̇ₖ = (h₂·d₁/h₁ + h₁·d₂/h₂)/(h₁ + h₂)`, `q̈ₖ = 2·(d₂/h₂ − d₁/h₁)/(h₁ + h₂)`. The end samples
/// take the neighbour's `q̈` and `q̇₀ = d/h − q̈·h/2` (`q̇ₙ = d/h + q̈·h/2`), which is exact for
/// a quadratic. Two samples give a constant rate and zero acceleration; one sample gives zeros.
///
/// # Errors
/// [`DynamicsError`] when a sample has the wrong length or a non-finite value, the numbers of
/// times and samples differ, or the times are not strictly increasing.
#[allow(clippy::type_complexity)]
pub fn joint_rates<Q: AsRef<[f64]>>(
    robot: &Robot,
    times: &[f64],
    q: &[Q],
) -> Result<(Vec<Vec<f64>>, Vec<Vec<f64>>), DynamicsError> {
    derivatives(times, q, robot.dof(), "q", &Differences::for_robot(robot), true)
}

/// First and, when `second`, second derivatives of sampled vectors (the scheme of
/// [`joint_rates`]); without `second` the second vector is empty (the first derivative's end
/// rows still use the neighbouring second derivatives, computed where needed only).
#[allow(clippy::type_complexity)]
fn derivatives<Q: AsRef<[f64]>>(
    times: &[f64],
    q: &[Q],
    n: usize,
    field: &str,
    diffs: &Differences,
    second: bool,
) -> Result<(Vec<Vec<f64>>, Vec<Vec<f64>>), DynamicsError> {
    check_times(times)?;
    check_sample_count(field, q.len(), times.len())?;
    for (k, row) in q.iter().enumerate() {
        check_row(field, k, row.as_ref(), n)?;
    }
    let m = times.len();
    let mut qd = vec![vec![0.0; n]; m];
    let mut qdd = if second { vec![vec![0.0; n]; m] } else { Vec::new() };
    if m < 2 {
        return Ok((qd, qdd));
    }
    // Slopes of the segments.
    let slope = |k: usize, i: usize| diffs.diff(i, q[k].as_ref()[i], q[k + 1].as_ref()[i]) / (times[k + 1] - times[k]);
    if m == 2 {
        let rate: Vec<f64> = (0..n).map(|i| slope(0, i)).collect();
        return Ok((vec![rate.clone(), rate], qdd));
    }
    // Second derivative at interior sample k.
    let accel = |k: usize, i: usize| {
        let (h1, h2) = (times[k] - times[k - 1], times[k + 1] - times[k]);
        2.0 * (slope(k, i) - slope(k - 1, i)) / (h1 + h2)
    };
    for k in 1..m - 1 {
        let (h1, h2) = (times[k] - times[k - 1], times[k + 1] - times[k]);
        for i in 0..n {
            let (s1, s2) = (slope(k - 1, i), slope(k, i));
            qd[k][i] = (h2 * s1 + h1 * s2) / (h1 + h2);
            if second {
                qdd[k][i] = accel(k, i);
            }
        }
    }
    let (h0, hn) = (times[1] - times[0], times[m - 1] - times[m - 2]);
    for i in 0..n {
        let (a0, an) = (accel(1, i), accel(m - 2, i));
        qd[0][i] = slope(0, i) - a0 * h0 / 2.0;
        qd[m - 1][i] = slope(m - 2, i) + an * hn / 2.0;
        if second {
            qdd[0][i] = a0;
            qdd[m - 1][i] = an;
        }
    }
    Ok((qd, qdd))
}

/// Mechanical energy `∫ Σᵢ |τᵢ·q̇ᵢ| dt` (joules) of samples that carry positions (rad / m) and
/// rates (rad/s / m/s), as the motion planners' output does: `q̈` is the derivative of the
/// given `q̇` by the central differences of [`joint_rates`] (literal increments), torques from
/// [`inverse_dynamics`], trapezoid rule ([`mechanical_energy`]).
///
/// # Errors
/// As [`trajectory_energy`], with `qd` samples named too.
pub fn trajectory_energy_with_rates<Q: AsRef<[f64]>>(
    robot: &Robot,
    times: &[f64],
    q: &[Q],
    qd: &[Q],
) -> Result<f64, DynamicsError> {
    let mut dynamics = Dynamics::new(robot)?;
    let n = robot.dof();
    // Checks the times and the rates.
    let (qdd, _) = derivatives(times, qd, n, "qd", &Differences::Literal, false)?;
    check_sample_count("q", q.len(), times.len())?;
    for (k, (qk, qddk)) in q.iter().zip(&qdd).enumerate() {
        check_row("q", k, qk.as_ref(), n)?;
        check_row("qdd", k, qddk, n)?;
    }
    Ok(energy_unchecked(&mut dynamics, times, q, qd, &qdd, f64::abs))
}

/// Mechanical energy `∫ Σᵢ |τᵢ·q̇ᵢ| dt` (joules) of a motion given only by sample times (s)
/// and joint positions (rad / m): rates from [`joint_rates`], torques from
/// [`inverse_dynamics`], trapezoid rule ([`mechanical_energy`]).
///
/// # Errors
/// As [`joint_rates`] and [`mechanical_energy`]; [`DynamicsError::NoInertialData`] first when the
/// robot has no masses.
///
/// # Example
/// ```
/// use reach::effort::dynamics::trajectory_energy;
/// use reach::model::presets;
/// let puma = presets::get("puma560").unwrap();
/// // Lift the upper arm by 0.5 rad in 1 s: at least the potential energy it gains.
/// let times: Vec<f64> = (0..=100).map(|k| k as f64 * 0.01).collect();
/// let q: Vec<Vec<f64>> = times.iter().map(|t| vec![0.0, -0.5 * t, 0.0, 0.0, 0.0, 0.0]).collect();
/// let e = trajectory_energy(&puma, &times, &q).unwrap();
/// assert!(e > 0.0);
/// ```
pub fn trajectory_energy<Q: AsRef<[f64]>>(robot: &Robot, times: &[f64], q: &[Q]) -> Result<f64, DynamicsError> {
    let mut dynamics = Dynamics::new(robot)?;
    // Checks the times and the positions; the derived rates are checked for overflow only.
    let (qd, qdd) = joint_rates(robot, times, q)?;
    let n = robot.dof();
    for (k, (qdk, qddk)) in qd.iter().zip(&qdd).enumerate() {
        check_row("qd", k, qdk, n)?;
        check_row("qdd", k, qddk, n)?;
    }
    Ok(energy_unchecked(&mut dynamics, times, q, &qd, &qdd, f64::abs))
}
