//! The vector method of the parallel-axes solver (notes 003 §3.3–3.4): Chace's formula, the
//! shoulder roots, the frames up to the wrist, the links of the elbow triangle and the
//! enumeration of the (up to 8) branches, with their `atan2` in lanes.

use nalgebra::{Isometry3, Rotation3, Vector3};

use super::*;
use crate::angle::{atan2, atan2_each, sin_cos};
use crate::ik::{FlagBits, Raw6};
use crate::tolerance::{IK_AXIS_DISTANCE, IK_PARALLEL_SINE};

/// Chace's solution of the vector tetrahedron (seed 003, eq. 4): the unit vectors `e_k` with
/// `e_i·e_k = c_ik` and `e_j·e_k = c_jk`, for known unit vectors `e_i`, `e_j`.
///
/// `e_k = [(c_ik − c_ij·c_jk)·e_i + (c_jk − c_ij·c_ik)·e_j ± √D·(e_i × e_j)] / s_ij²` with
/// `D = 1 − c_ij² − c_ik² − c_jk² + 2·c_ij·c_ik·c_jk` and `s_ij = sin∠(e_i, e_j)`.
/// This is the corrected normalisation (notes 003 §3.2 and §6.4: the paper prints no
/// division of the first two terms and `/s_ij` on the last, right only when `s_ij = 1`).
///
/// # Returns
/// `[plus, minus]`: `plus` makes `(e_i, e_j, e_k)` right-handed (`(e_i × e_j)·e_k ≥ 0`), the
/// paper's "+" root; `None` when `e_i ∥ e_j` (`s_ij` below [`IK_PARALLEL_SINE`]) or
/// `D < −2·BOUNDARY` (no such vector; `D` is clamped to 0 inside that tolerance, the
/// tolerance of cosines within `BOUNDARY` of ±1).
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use reach::ik::parallel_axes::chace;
/// let (ei, ej) = (Vector3::x(), Vector3::new(0.6, 0.8, 0.0)); // 53.13° apart
/// let [plus, minus] = chace(&ei, &ej, 0.5, 0.3).unwrap();
/// for ek in [plus, minus] {
///     approx::assert_relative_eq!(ek.norm(), 1.0, epsilon = 1e-12);
///     approx::assert_relative_eq!(ek.dot(&ei), 0.5, epsilon = 1e-12);
///     approx::assert_relative_eq!(ek.dot(&ej), 0.3, epsilon = 1e-12);
/// }
/// assert!(ei.cross(&ej).dot(&plus) > 0.0 && ei.cross(&ej).dot(&minus) < 0.0);
/// ```
#[must_use]
#[inline(always)]
pub fn chace(e_i: &Vector3<f64>, e_j: &Vector3<f64>, c_ik: f64, c_jk: f64) -> Option<[Vector3<f64>; 2]> {
    let c_ij = e_i.dot(e_j);
    let n = e_i.cross(e_j);
    let s2 = n.norm_squared();
    if !s2.is_finite() || s2 <= IK_PARALLEL_SINE * IK_PARALLEL_SINE {
        return None;
    }
    let d = 1.0 - c_ij * c_ij - c_ik * c_ik - c_jk * c_jk + 2.0 * c_ij * c_ik * c_jk;
    if !d.is_finite() || d < -2.0 * BOUNDARY {
        return None;
    }
    let base = e_i * (c_ik - c_ij * c_jk) + e_j * (c_jk - c_ij * c_ik);
    let side = n * d.max(0.0).sqrt();
    Some([(base + side) / s2, (base - side) / s2])
}

/// A root of the shoulder equation.
#[derive(Debug, Clone, Copy)]
pub(super) struct ShoulderRoot {
    theta1: f64,
    pub(super) label: Shoulder,
    singular: bool,
}

/// One shoulder root's frames up to the wrist, shared by its two wrists: the wrist `−e5`
/// negates z4, x4 and x5 exactly (eq. 11), and with them θ5 (eq. 21: both `z4` and the
/// cross product's factors change sign, so only the `atan2`'s first argument does).
#[derive(Debug, Clone, Copy)]
pub(super) struct ShoulderArm {
    x1: Vector3<f64>,
    z1: Vector3<f64>,
    z3: Vector3<f64>,
    /// z4 = e5, x4 and x5 of the wrist `e5`.
    z4: Vector3<f64>,
    x4: Vector3<f64>,
    x5: Vector3<f64>,
    pub(super) wrist_sine: f64,
    wrist_singular: bool,
}

/// Everything of one (shoulder, wrist) branch before the elbow configuration is chosen.
#[derive(Debug, Clone, Copy)]
pub(super) struct Arm {
    x1: Vector3<f64>,
    z1: Vector3<f64>,
    x4: Vector3<f64>,
    /// In-plane vector r2·e_r2 (perpendicular to z1).
    v: Vector3<f64>,
    pub(super) r2: f64,
}

/// The directions `[x2, x3]` of links 2 and 3 of one arm and configuration.
type Links = [Vector3<f64>; 2];

/// The `atan2` arguments `(y, x)` of one solve's angles (eq. 21), evaluated together in lanes
/// ([`atan2_each`]): per branch `b = 4·shoulder + 2·wrist + config` θ2, θ3, θ4 at `b`,
/// `BRANCHES + b`, `2·BRANCHES + b`; per shoulder `s` θ1, θ5 (wrist `e5`), θ6 (`e5`) and θ6
/// (`−e5`) at [`SHOULDER_LANES`] `+ s`, `+ 2 + s`, `+ 4 + s`, `+ 6 + s`. Unused lanes hold
/// `(1, 1)`.
const BRANCHES: usize = 8;
/// The first lane of the shoulders' angles (see [`BRANCHES`]).
const SHOULDER_LANES: usize = 3 * BRANCHES;
/// All lanes of a solve's angles (see [`BRANCHES`]).
const ANGLE_LANES: usize = SHOULDER_LANES + 8;

/// The chain-frame target: tool point and axes.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    p: Vector3<f64>,
    x6: Vector3<f64>,
    y6: Vector3<f64>,
    z6: Vector3<f64>,
}

/// θ1…θ6 of one branch from its shoulder's angles `[θ1, θ5, θ6 (e5), θ6 (−e5)]`
/// ([`ParallelAxes::shoulder_args`]) and its arm's `[θ2, θ3, θ4]`
/// ([`ParallelAxes::link_args`]): the wrist `−e5` negates θ5 and takes its own θ6 (eq. 21).
#[inline(always)]
fn branch_theta(shoulder: [f64; 4], link: [f64; 3], wrist: Wrist) -> [f64; 6] {
    let [theta1, theta5, theta6_e5, theta6_minus_e5] = shoulder;
    let (theta5, theta6) = match wrist {
        Wrist::E5 => (theta5, theta6_e5),
        Wrist::MinusE5 => (-theta5, theta6_minus_e5),
    };
    [theta1, link[0], link[1], link[2], theta5, theta6]
}

/// `(axis·(from × to), from·to)`: the `atan2` arguments of the angle from `from` to `to`
/// about `axis` (eq. 21).
#[inline(always)]
fn angle_args(axis: &Vector3<f64>, from: &Vector3<f64>, to: &Vector3<f64>) -> (f64, f64) {
    (axis.dot(&from.cross(to)), from.dot(to))
}

pub(super) fn frame_of(t: &Isometry3<f64>) -> Frame {
    let r: Rotation3<f64> = t.rotation.to_rotation_matrix();
    let m = r.matrix();
    Frame {
        p: t.translation.vector,
        x6: m.column(0).into_owned(),
        y6: m.column(1).into_owned(),
        z6: m.column(2).into_owned(),
    }
}

impl ParallelAxes {
    /// e6 = z5 and the wrist point C (eqs. 6, 7).
    pub(super) fn wrist_point(&self, f: &Frame) -> (Vector3<f64>, Vector3<f64>) {
        let z5 = f.y6 * self.s_alpha6 + f.z6 * self.c_alpha6;
        let c = f.p - f.x6 * self.a[5] - z5 * self.d[5];
        (z5, c)
    }

    /// The two roots of `C·z1(θ1) = D` (eq. 10 generalised), labelled; `Err` = unreachable.
    pub(super) fn shoulder_roots(&self, c: &Vector3<f64>, seed_theta1: f64) -> Result<[ShoulderRoot; 2], IkFailure> {
        let rho = c.x.hypot(c.y);
        let lateral = self.lateral;
        if rho <= IK_AXIS_DISTANCE && lateral.abs() <= IK_AXIS_DISTANCE {
            // C on the column axis: w undetermined; keep the seed's θ1 (notes 003 §3.6, [R]).
            let t = seed_theta1;
            return Ok([
                ShoulderRoot { theta1: t, label: Shoulder::W, singular: true },
                ShoulderRoot { theta1: t + std::f64::consts::PI, label: Shoulder::MinusW, singular: true },
            ]);
        }
        let ratio = self.s_alpha1 * lateral / rho;
        if ratio.is_nan() || ratio.abs() > 1.0 + BOUNDARY {
            return Err(IkFailure::Unreachable {
                distance: rho,
                reach: lateral.abs(),
                point: "the wrist point",
                from: "joint 1's axis",
            });
        }
        let singular = ratio.abs() >= 1.0 - BOUNDARY;
        let gamma = ratio.clamp(-1.0, 1.0).asin();
        let phi = atan2(c.y, c.x);
        let near = phi + gamma; // z1·(C × k) = sin α1·ρ·cos γ: the paper's `w` when sin α1 > 0
        let far = phi + std::f64::consts::PI - gamma;
        let (w, minus_w) = if self.s_alpha1 > 0.0 { (near, far) } else { (far, near) };
        Ok([
            ShoulderRoot { theta1: w, label: Shoulder::W, singular },
            ShoulderRoot { theta1: minus_w, label: Shoulder::MinusW, singular },
        ])
    }

    /// Steps 3–4 of the method for one shoulder root, up to the wrist sign: the frames both
    /// wrists share ([`ShoulderArm`]).
    #[inline(always)]
    pub(super) fn shoulder_arm(
        &self,
        f: &Frame,
        z5: &Vector3<f64>,
        root: &ShoulderRoot,
        seed_theta6: f64,
    ) -> ShoulderArm {
        let (s1, c1) = sin_cos(root.theta1);
        let x1 = Vector3::new(c1, s1, 0.0);
        let z1 = Vector3::new(s1, -c1, 0.0) * self.s_alpha1;
        let z3 = z1 * self.c_alpha2 * self.c_alpha3;
        // e5 = (w × e6)/sin∠(w, e6)  (eq. 11; the wrist flip is its negation).
        let u = z1.cross(z5);
        let wrist_sine = u.norm();
        let wrist_singular = wrist_sine <= IK_PARALLEL_SINE;
        let z4 = if wrist_singular {
            // e6 ∥ w: e5 is any vector ⟂ w; the seed's θ6 fixes frame 5 and with it
            // e5 = sin α5·y5 (z_{i−1} = sin α_i·y_i + cos α_i·z_i, α5 = ±90°).
            let (s6, c6) = sin_cos(seed_theta6);
            let x5 = f.x6 * c6 - (f.y6 * self.c_alpha6 - f.z6 * self.s_alpha6) * s6;
            let y5 = z5.cross(&x5);
            let e5 = y5 * self.s_alpha5;
            (e5 - z1 * e5.dot(&z1)).normalize()
        } else {
            u * (1.0 / wrist_sine)
        };
        let x4 = z3.cross(&z4) * self.s_alpha4;
        let x5 = z4.cross(z5) * self.s_alpha5;
        let x5 = x5 / x5.norm();
        ShoulderArm { x1, z1, z3, z4, x4, x5, wrist_sine, wrist_singular }
    }

    /// Step 4 for one wrist sign: B = C − d5·e5 (eq. 12), then back along the wrist-pitch link
    /// and the lateral offsets to the in-plane vector r2·e_r2.
    #[inline(always)]
    pub(super) fn arm(&self, shared: &ShoulderArm, c: &Vector3<f64>, wrist: Wrist) -> Arm {
        let ShoulderArm { x1, z1, z3, .. } = *shared;
        let z2 = z1 * self.c_alpha2;
        let (z4, x4) = (shared.z4 * wrist.sign(), shared.x4 * wrist.sign());
        let o4 = c - z4 * self.d[4];
        let o3 = o4 - z3 * self.d[3] - x4 * self.a[3];
        let o1 = Vector3::new(0.0, 0.0, self.d[0]) + x1 * self.a[0];
        let v = o3 - o1 - z1 * self.d[1] - z2 * self.d[2];
        let v = v - z1 * v.dot(&z1); // exact in-plane part (the residue is round-off or ≤ ρ at the shoulder singularity)
        Arm { x1, z1, x4, v, r2: v.norm() }
    }

    /// The `atan2` arguments of θ1, θ5 (wrist `e5`; `−e5`: −θ5) and θ6 (`e5`, `−e5`) of one
    /// shoulder (eq. 21).
    #[inline(always)]
    fn shoulder_args(shared: &ShoulderArm, f: &Frame, z5: &Vector3<f64>) -> [(f64, f64); 4] {
        [
            angle_args(&Vector3::z(), &Vector3::x(), &shared.x1),
            angle_args(&shared.z4, &shared.x4, &shared.x5),
            angle_args(z5, &shared.x5, &f.x6),
            angle_args(z5, &-shared.x5, &f.x6),
        ]
    }

    /// Steps 5–7 for one arm: the directions x2, x3 of links 2 and 3 of the configurations
    /// `[+β, −β]` (equal at r2 = 0, from the seed's θ2), whether the elbow is singular, or
    /// `Err` = out of reach.
    #[inline(always)]
    fn links(&self, arm: &Arm, seed_theta2: f64) -> Result<([Links; 2], bool), IkFailure> {
        let (l2, l3) = (self.a[1].abs(), self.a[2].abs());
        let z1 = arm.z1;
        // Direction of link 2 (from the shoulder towards the elbow), a2 of the paper.
        let (link2, elbow_singular) = if arm.r2 <= IK_AXIS_DISTANCE {
            // r2 = 0: only possible for l2 = l3 (else |Δ| = ∞): the folded arm, θ2 free.
            if (l2 - l3).abs() > IK_AXIS_DISTANCE {
                return Err(IkFailure::Unreachable {
                    distance: arm.r2,
                    reach: (l2 - l3).abs(),
                    point: "the wrist point",
                    from: "joint 2",
                });
            }
            let (s2, c2) = sin_cos(seed_theta2);
            let x2 = arm.x1 * c2 + z1.cross(&arm.x1) * s2;
            let link2 = x2 * self.a[1].signum();
            ([link2, link2], true)
        } else {
            // Reachability and the elbow singularity are decided on the cosine of the elbow
            // angle, c3 = (r2² − a2² − a3²)/(2·a2·a3), which is ±1 exactly when |Δ| = 1 and
            // is what `ArmMeasures::elbow_margin` reports, so both agree.
            let c3 = (arm.r2 * arm.r2 - l2 * l2 - l3 * l3) / (2.0 * self.a[1] * self.a[2]);
            if c3.is_nan() || c3.abs() > 1.0 + BOUNDARY {
                let reach = if arm.r2 > l2 + l3 { l2 + l3 } else { (l2 - l3).abs() };
                return Err(IkFailure::Unreachable {
                    distance: arm.r2,
                    reach,
                    point: "the wrist point",
                    from: "joint 2",
                });
            }
            let singular = c3.abs() >= 1.0 - BOUNDARY;
            // Δ = cos β (eq. 14); ±1 at the singularity (β = 0, or 180° when folded with l2 < l3).
            let delta = ((l2 * l2 + arm.r2 * arm.r2 - l3 * l3) / (2.0 * l2 * arm.r2)).clamp(-1.0, 1.0);
            let delta = if singular { delta.signum() } else { delta };
            let e_r2 = arm.v / arm.r2;
            // a2 = e_r2·cos β ± (e_r2 × w)·sin β  (eqs. 17, 20 via Chace's formula, eq. 4):
            // e_i = e_r2 ⟂ e_j = w, c_ik = Δ, c_jk = 0; the "+" root makes (e_r2, w, a2) and
            // hence (a2, e_r2, w) right-handed: configuration "+β".
            let Some([plus, minus]) = chace(&e_r2, &z1, delta, 0.0) else {
                return Err(IkFailure::Singular { kind: SingularityKind::Elbow });
            };
            ([plus.normalize(), minus.normalize()], singular)
        };
        Ok((
            link2.map(|link2| {
                let x2 = link2 * self.a[1].signum();
                // a3 = (r2·e_r2 − l2·a2)/l3  (eq. 18), with signed DH lengths.
                let x3 = ((arm.v - x2 * self.a[1]) / self.a[2]).normalize();
                [x2, x3]
            }),
            elbow_singular,
        ))
    }

    /// The `atan2` arguments of θ2, θ3 and θ4 (eq. 21) of one arm and configuration from its
    /// links `[x2, x3]` ([`ParallelAxes::links`]).
    #[inline(always)]
    fn link_args(&self, arm: &Arm, [x2, x3]: &Links) -> [(f64, f64); 3] {
        let z2 = arm.z1 * self.c_alpha2;
        let z3 = z2 * self.c_alpha3;
        [angle_args(&arm.z1, &arm.x1, x2), angle_args(&z2, x2, x3), angle_args(&z3, x3, &arm.x4)]
    }

    /// Every candidate (up to 8) for a chain-frame target, and the failure reason if none.
    ///
    /// The two shoulders' frames are shared by their wrists ([`ShoulderArm`]), the two
    /// configurations of an arm by one Chace solve ([`ParallelAxes::links`]), and the angles
    /// of all branches go through their `atan2` together ([`atan2_each`]: in lanes when
    /// `WIDE`, bit for bit [`atan2`] either way; see [`BRANCHES`]).
    #[inline(always)]
    pub(super) fn candidates<const WIDE: bool>(&self, frame: &Frame, seed: &[f64; 6]) -> (Raw6Set, Option<IkFailure>) {
        let mut out = Raw6Set::new(KEYS);
        let (z5, c) = self.wrist_point(frame);
        let roots = match self.shoulder_roots(&c, seed[0]) {
            Ok(r) => r,
            Err(failure) => return (out, Some(failure)),
        };
        let mut failure: Option<(f64, IkFailure)> = None;
        let (mut y, mut x) = ([1.0; ANGLE_LANES], [1.0; ANGLE_LANES]);
        let mut branches = [None; BRANCHES];
        let mut wrist_singular = [false; 2];
        for (s, root) in roots.iter().enumerate() {
            let shared = self.shoulder_arm(frame, &z5, root, seed[5]);
            wrist_singular[s] = shared.wrist_singular;
            for (i, (ys, xs)) in Self::shoulder_args(&shared, frame, &z5).into_iter().enumerate() {
                (y[SHOULDER_LANES + 2 * i + s], x[SHOULDER_LANES + 2 * i + s]) = (ys, xs);
            }
            for (w, wrist) in [Wrist::E5, Wrist::MinusE5].into_iter().enumerate() {
                let arm = self.arm(&shared, &c, wrist);
                match self.links(&arm, seed[1]) {
                    Ok((links, elbow_singular)) => {
                        for (k, links) in links.iter().enumerate() {
                            let b = 4 * s + 2 * w + k;
                            for (i, (ys, xs)) in self.link_args(&arm, links).into_iter().enumerate() {
                                (y[i * BRANCHES + b], x[i * BRANCHES + b]) = (ys, xs);
                            }
                            branches[b] = Some(elbow_singular);
                        }
                    }
                    Err(f) => {
                        let excess = match &f {
                            IkFailure::Unreachable { distance, reach, .. } => (distance - reach).abs(),
                            _ => f64::INFINITY,
                        };
                        if failure.as_ref().is_none_or(|(e, _)| excess < *e) {
                            failure = Some((excess, f));
                        }
                    }
                }
            }
        }
        let angles = atan2_each::<WIDE, ANGLE_LANES>(&y, &x);
        for (b, elbow_singular) in branches.into_iter().enumerate() {
            let Some(elbow_singular) = elbow_singular else { continue };
            let (s, w, k) = (b / 4, (b / 2) % 2, b % 2);
            let (config, wrist) = ([Config::PlusBeta, Config::MinusBeta][k], [Wrist::E5, Wrist::MinusE5][w]);
            let theta = branch_theta(
                std::array::from_fn(|i| angles[SHOULDER_LANES + 2 * i + s]),
                std::array::from_fn(|i| angles[i * BRANCHES + b]),
                wrist,
            );
            out.push(self.candidate(&theta, &roots[s], config, wrist, wrist_singular[s], elbow_singular));
        }
        (out, failure.map(|(_, f)| f))
    }

    /// The candidate of one branch, `None` when the branch has no root here: the steps of
    /// [`ParallelAxes::candidates`] for that branch alone, each `atan2` by [`atan2`] (the same
    /// bits as the lanes').
    pub(super) fn branch_candidate(
        &self,
        frame: &Frame,
        seed: &[f64; 6],
        shoulder: Shoulder,
        config: Config,
        wrist: Wrist,
    ) -> Option<Raw6> {
        let (z5, c) = self.wrist_point(frame);
        let roots = self.shoulder_roots(&c, seed[0]).ok()?;
        let root = roots.iter().find(|r| r.label == shoulder)?;
        let shared = self.shoulder_arm(frame, &z5, root, seed[5]);
        let arm = self.arm(&shared, &c, wrist);
        let (links, elbow_singular) = self.links(&arm, seed[1]).ok()?;
        let k = match config {
            Config::PlusBeta => 0,
            Config::MinusBeta => 1,
        };
        let angle = |(y, x): (f64, f64)| atan2(y, x);
        let theta = branch_theta(
            Self::shoulder_args(&shared, frame, &z5).map(angle),
            self.link_args(&arm, &links[k]).map(angle),
            wrist,
        );
        Some(self.candidate(&theta, root, config, wrist, shared.wrist_singular, elbow_singular))
    }

    /// The labelled, flagged candidate of DH angles `theta`.
    #[inline(always)]
    fn candidate(
        &self,
        theta: &[f64; 6],
        root: &ShoulderRoot,
        config: Config,
        wrist: Wrist,
        wrist_singular: bool,
        elbow_singular: bool,
    ) -> Raw6 {
        let q: [f64; 6] = std::array::from_fn(|i| self.sign[i] * (theta[i] - self.offset[i]));
        let flags = FlagBits::default()
            .with(SingularityKind::Shoulder, root.singular)
            .with(SingularityKind::Elbow, elbow_singular)
            .with(SingularityKind::Wrist, wrist_singular);
        Raw6 { q, values: [root.label.label(), config.label(), wrist.label()], flags }
    }
}
