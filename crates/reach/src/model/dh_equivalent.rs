//! The standard-DH description of a revolute chain, derived from its geometry: the one place
//! where a robot described otherwise (URDF joint origins with any rpy and axis signs, an MDH
//! table) gets the DH table the closed-form IK solvers read ([`Robot::dh_equivalent`]).
//!
//! The derivation and its limits are documented on [`Robot::dh_equivalent`].

use nalgebra::{Isometry3, IsometryMatrix3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

use super::{Convention, DhParams, Joint, JointGeometry, JointKind, ModelError, Robot, RobotSpec};
use crate::tolerance::DH_EQUIVALENT;

/// One axis line: a point on it and its unit direction.
#[derive(Debug, Clone, Copy)]
struct Line {
    point: Vector3<f64>,
    dir: Vector3<f64>,
}

/// `v` made exactly 0 when within [`DH_EQUIVALENT`] of it.
fn snap_length(v: f64) -> f64 {
    if v.abs() <= DH_EQUIVALENT { 0.0 } else { v }
}

/// `angle` made an exact multiple of 90° when within [`DH_EQUIVALENT`] of one.
fn snap_angle(angle: f64) -> f64 {
    let quarter = std::f64::consts::FRAC_PI_2;
    let k = (angle / quarter).round();
    if (angle - k * quarter).abs() <= DH_EQUIVALENT { crate::angle::wrap(k * quarter) } else { angle }
}

/// The angle from `from` to `to` about `axis` (both perpendicular to it).
fn angle_about(axis: &Vector3<f64>, from: &Vector3<f64>, to: &Vector3<f64>) -> f64 {
    axis.dot(&from.cross(to)).atan2(from.dot(to))
}

/// A unit vector perpendicular to the unit vector `z`.
fn perpendicular(z: &Vector3<f64>) -> Vector3<f64> {
    let helper = if z.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() };
    let v = helper - z * z.dot(&helper);
    v.normalize()
}

/// A frame from its x and z axes (orthonormal) and origin.
fn frame(x: &Vector3<f64>, z: &Vector3<f64>, origin: &Vector3<f64>) -> IsometryMatrix3<f64> {
    let y = z.cross(x);
    IsometryMatrix3::from_parts(
        Translation3::from(*origin),
        Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[*x, y, *z])),
    )
}

/// The joint vectors of the equivalence check besides q = 0: deterministic, spread over
/// (−1.5, 1.5) rad with no two joints alike.
fn check_vectors(n: usize) -> impl Iterator<Item = Vec<f64>> {
    (1..=4).map(move |k| (0..n).map(|j| ((k * 7 + j * 3) as f64 * 0.37).sin() * 1.5).collect())
}

impl Robot {
    /// The standard-DH robot with the same kinematics as this one: same joints (names, kinds,
    /// limits, home, speed limits, drives), joint values taken as this robot takes them, and
    /// the same tool pose for every joint vector (to [`DH_EQUIVALENT`]), with a DH table
    /// derived from the joint axes as described below — for a robot described by URDF or MDH,
    /// so that the closed-form IK solvers, which read a DH table, solve it. A robot in standard DH gets the table derived afresh from its geometry (it
    /// may differ from its own table by the free choices of the convention).
    ///
    /// # Derivation
    ///
    /// The joint axes are taken as lines in the base (world) frame at q = 0, each signed as its
    /// joint value turns ([`Robot::joint_axes`]), and the tool pose at q = 0 ([`Robot::fk_matrix`]).
    /// Frame *k* of the DH chain has its z axis on the axis of joint *k + 1*; joint *k* turns about
    /// `z_{k−1}`, as standard DH wants ([`Convention::Dh`]):
    ///
    /// * **directions**: `z_{k−1} = σ_k·u_k` with `u_k` the joint's own axis direction and
    ///   `σ_k = ±1`: an axis parallel to the previous one takes its direction (so that parallel
    ///   axes have α = 0°, as the closed forms of PUMA- and UR-type arms expect, never 180°); the
    ///   first axis points up (non-negative world z) where it can; every other axis keeps its own
    ///   direction. `σ_k = −1` makes the DH joint *flipped* ([`Joint::flip`]: the model turns by
    ///   `−q` where the user gives `q`), so the equivalent takes the robot's own joint values;
    /// * **common normals**: `x_k` is the common normal from axis *k* to axis *k + 1*, pointing
    ///   from the one to the other (a_k ≥ 0, so that a shoulder `front` label means the arm
    ///   reaches towards the target): `±z_{k−1} × z_k` normalised for skew axes, `z_{k−1} × z_k`
    ///   for axes that meet, the perpendicular from the previous origin `O_{k−1}` to the next axis
    ///   for parallel axes (so d_k = 0 there, the usual choice; the UR5 gets its published table
    ///   up to the signs of a2, a3), and `x_{k−1}` for coincident axes; `O_k` is where the normal
    ///   meets axis *k + 1*;
    /// * **parameters**: `d_k = (foot on axis k − O_{k−1})·z_{k−1}`, `a_k = (O_k − foot)·x_k`,
    ///   `α_k` the angle from `z_{k−1}` to `z_k` about `x_k`, and the θ offset the angle from
    ///   `x_{k−1}` to `x_k` about `z_{k−1}` at q = 0;
    /// * **ends**: frame 0 sits on the first axis at the foot of the perpendicular from the base
    ///   origin, with `x_0 = x_1` (θ1 offset 0); the last frame continues the last axis
    ///   (`a_n = 0`, `α_n = 0`, `x_n = x_{n−1}`) to the foot of the perpendicular from the tool
    ///   point, so that a spherical wrist has `a_n = 0`, `α_n = 0`; the **base** transform is
    ///   frame 0 in the world and the **tool** transform the original tool pose in frame *n*.
    ///
    /// Twists within [`DH_EQUIVALENT`] of a multiple of 90° and lengths within it of zero are
    /// made exact (URDF files print π/2 with 7 to 10 digits: `1.570796325` is 1.8e-9 rad off),
    /// then the equivalent is **checked**: its forward kinematics must agree with the robot's to
    /// [`DH_EQUIVALENT`] (every entry of the homogeneous transforms, metres and cosines) at q = 0
    /// and at four more joint vectors. A chain that fails, or has a prismatic or mimic joint, has
    /// no equivalent.
    ///
    /// # Limits
    ///
    /// Revolute joints only (a prismatic joint's DH `d` would carry its variable, which this
    /// derivation does not place); no mimic joints (their motion is not a DH row); the
    /// equivalent describes kinematics only (no mass properties: the DH link frames differ from
    /// the description's).
    ///
    /// # Errors
    /// [`ModelError::NoDhEquivalent`] naming the reason: a prismatic or mimic joint, or forward
    /// kinematics that disagree (by more than [`DH_EQUIVALENT`]) at a checked joint vector.
    ///
    /// # Example
    /// ```
    /// use reach::model::{Convention, Robot, UrdfChain};
    /// let urdf = std::fs::read_to_string(concat!(
    ///    env!("CARGO_MANIFEST_DIR"),
    ///    "/../../examples/urdf/kuka_kr16_support/urdf/kr16_2.urdf"
    /// ))
    /// .unwrap();
    /// let chain = UrdfChain { base: None, tip: Some("tool0".into()) };
    /// let kr16 = Robot::from_urdf_str(&urdf, &chain).unwrap();
    /// let dh = kr16.dh_equivalent().unwrap();
    /// assert_eq!(dh.convention(), Convention::Dh);
    /// let q = [0.3, -0.5, 0.4, 1.1, -0.7, 0.2];
    /// let (a, b) = (kr16.fk_matrix(&q).unwrap(), dh.fk_matrix(&q).unwrap());
    /// assert!((a.to_homogeneous() - b.to_homogeneous()).abs().max() < 1e-9);
    /// // Axes 2 and 3 are parallel (α2 = 0), the wrist is spherical (a4 = a5 = d5 = 0).
    /// let p = |i: usize| *dh.joints()[i].dh().unwrap();
    /// assert_eq!((p(1).alpha, p(3).a, p(4).a, p(4).d), (0.0, 0.0, 0.0, 0.0));
    /// ```
    ///
    /// [`DH_EQUIVALENT`]: crate::tolerance::DH_EQUIVALENT
    pub fn dh_equivalent(&self) -> Result<Robot, ModelError> {
        self.dh_equivalent_and_gap().map(|(robot, _)| robot)
    }

    /// [`Robot::dh_equivalent`] and the largest gap its check found between the two forward
    /// kinematics (every entry of the homogeneous transforms, metres and cosines): rounding
    /// (~1e-16) for a file whose axes are exactly perpendicular and parallel, more where twists
    /// or lengths were made exact.
    pub(crate) fn dh_equivalent_and_gap(&self) -> Result<(Robot, f64), ModelError> {
        let fail = |reason: String| ModelError::NoDhEquivalent { robot: self.name().to_string(), reason };
        if let Some(m) = self.mimics().first() {
            return Err(fail(format!("mimic joint `{}` is not a row of a DH table", m.name)));
        }
        if let Some((i, j)) = self.joints().iter().enumerate().find(|(_, j)| j.kind != JointKind::Revolute) {
            return Err(fail(format!("joint {} ({}) is prismatic; only revolute chains are derived", i + 1, j.name)));
        }
        let n = self.dof();
        let zero = vec![0.0; n];
        let kinematics = |e: crate::kinematics::KinematicsError| fail(e.to_string());
        let axes = self.joint_axes(&zero).map_err(kinematics)?;
        let flange = self.fk_matrix(&zero).map_err(kinematics)?;

        // Directions σ_k·u_k.
        let mut lines: Vec<Line> = Vec::with_capacity(n);
        let mut signs: Vec<f64> = Vec::with_capacity(n);
        for (point, dir) in &axes {
            let u = dir.normalize();
            let sign = match lines.last() {
                None if u.z < -DH_EQUIVALENT => -1.0,
                Some(prev) if prev.dir.cross(&u).norm() <= DH_EQUIVALENT && prev.dir.dot(&u) < 0.0 => -1.0,
                _ => 1.0,
            };
            signs.push(sign);
            lines.push(Line { point: *point, dir: u * sign });
        }

        // Frames 1 … n−1 from the common normals, frame n continuing the last axis.
        let base_origin = self.base().translation.vector;
        let first = &lines[0];
        let mut origins: Vec<Vector3<f64>> = Vec::with_capacity(n + 1);
        let mut xs: Vec<Vector3<f64>> = Vec::with_capacity(n + 1);
        origins.push(first.point + first.dir * first.dir.dot(&(base_origin - first.point)));
        xs.push(Vector3::zeros()); // set below, once x_1 is known
        let mut params: Vec<DhParams> = Vec::with_capacity(n);
        for k in 0..n {
            let (a_line, prev_origin) = (lines[k], origins[k]);
            let (foot, x, next_origin) = if let Some(b_line) = lines.get(k + 1) {
                let c = a_line.dir.cross(&b_line.dir);
                if c.norm() > DH_EQUIVALENT {
                    // Skew or meeting axes: the unique common normal.
                    let w0 = a_line.point - b_line.point;
                    let b = a_line.dir.dot(&b_line.dir);
                    let (d, e) = (a_line.dir.dot(&w0), b_line.dir.dot(&w0));
                    let denom = 1.0 - b * b;
                    let s = (b * e - d) / denom;
                    let t = (e - b * d) / denom;
                    let (foot, next) = (a_line.point + a_line.dir * s, b_line.point + b_line.dir * t);
                    // Pointing from axis k to axis k + 1 (a_k ≥ 0), so that the closed forms'
                    // labels (`front`: the arm reaches towards the target) mean what they say.
                    let x = c.normalize();
                    let x = if (next - foot).dot(&x) < -DH_EQUIVALENT { -x } else { x };
                    (foot, x, next)
                } else {
                    // Parallel axes: the perpendicular from the previous origin (d = 0).
                    let foot = prev_origin;
                    let on_b = b_line.point + b_line.dir * b_line.dir.dot(&(foot - b_line.point));
                    let v = on_b - foot;
                    // Coincident axes: keep the previous normal (any perpendicular for the first).
                    let x = if v.norm() > DH_EQUIVALENT {
                        v.normalize()
                    } else if k == 0 {
                        perpendicular(&a_line.dir)
                    } else {
                        xs[k]
                    };
                    (foot, x, on_b)
                }
            } else {
                // The last frame: along the last axis to the foot of the tool point.
                let t = a_line.dir.dot(&(flange.translation.vector - prev_origin));
                let foot = prev_origin + a_line.dir * t;
                (foot, xs[k], foot)
            };
            if k == 0 {
                // Frame 0 takes x_1 (θ1 offset 0); a single joint takes any perpendicular.
                xs[0] = if n > 1 { x } else { perpendicular(&a_line.dir) };
            }
            let x = if k + 1 == n { xs[k] } else { x };
            let z_next = lines.get(k + 1).map_or(a_line.dir, |l| l.dir);
            params.push(DhParams {
                a: snap_length((next_origin - foot).dot(&x)),
                alpha: snap_angle(angle_about(&x, &a_line.dir, &z_next)),
                d: snap_length((foot - prev_origin).dot(&a_line.dir)),
                theta_offset: snap_angle(angle_about(&a_line.dir, &xs[k], &x)),
            });
            xs.push(x);
            origins.push(next_origin);
        }

        let base_frame = frame(&xs[0], &lines[0].dir, &origins[0]);
        let joints: Vec<Joint> = self
            .joints()
            .iter()
            .zip(&params)
            .zip(&signs)
            .map(|((j, p), &sign)| Joint { geometry: JointGeometry::Dh(*p), flip: sign < 0.0, ..j.clone() })
            .collect();
        let iso = |m: &IsometryMatrix3<f64>| {
            Isometry3::from_parts(m.translation, UnitQuaternion::from_rotation_matrix(&m.rotation))
        };
        let mut spec = RobotSpec {
            name: self.name().to_string(),
            description: format!("standard-DH equivalent of `{}`, derived from its joint axes", self.name()),
            convention: Convention::Dh,
            joints,
            base: iso(&base_frame),
            tool: Isometry3::identity(),
            links: self.links().to_vec(),
            inertials: Vec::new(),
            gravity: *self.gravity(),
            mimics: Vec::new(),
            // The bodies are fixed to the robot's own frames, not to the equivalent's.
            bodies: Vec::new(),
            disabled_collisions: Vec::new(),
        };
        // The tool: the robot's tool pose in the equivalent's last frame at q = 0.
        let last = Robot::new(spec.clone())?.fk_matrix(&zero).map_err(kinematics)?;
        spec.tool = iso(&(last.inverse() * flange));
        let equivalent = Robot::new(spec)?;
        let mut largest = 0.0_f64;
        for q in std::iter::once(zero).chain(check_vectors(n)) {
            let (mine, theirs) =
                (self.fk_matrix(&q).map_err(kinematics)?, equivalent.fk_matrix(&q).map_err(kinematics)?);
            let gap = (mine.to_homogeneous() - theirs.to_homogeneous()).abs().max();
            if gap.is_nan() || gap > DH_EQUIVALENT {
                return Err(fail(format!(
                    "the derived DH chain's forward kinematics differ by {gap:.3e} at q = {q:?} (more than {DH_EQUIVALENT:e})"
                )));
            }
            largest = largest.max(gap);
        }
        Ok((equivalent, largest))
    }
}
