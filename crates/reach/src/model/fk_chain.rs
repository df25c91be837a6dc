//! The form of the chain that forward kinematics and the Jacobian run on
//! ([`Robot::fk_matrix`](crate::model::Robot::fk_matrix),
//! [`Robot::jacobian_into`](crate::model::Robot::jacobian_into) and their batch kernels).
//!
//! It is the compiled [`Chain`](super::chain::Chain) `T(q) = F0 · M1(q1) · F1 ⋯ Mn(qn) · Fn` with each motion frame
//! moved along and turned about its own axis where that makes the constant after it a
//! standard-DH step, the way the DH convention chooses frames:
//!
//! ```text
//! Mi · Fi = Mi · Ci · (Ci⁻¹ · Fi · Ci+1) · Ci+1⁻¹,   Ci = Rz(φi)·Tz(δi)
//! ```
//!
//! `Ci` commutes with the motion `Mi` (a rotation about or translation along z), so the product
//! is unchanged; `Ci+1` is chosen so that `Ci⁻¹ · Fi · Ci+1 = Rz(θi)·Tz(di)·Tx(ai)·Rx(αi)`: its
//! x axis on the common normal of the two joint axes, its origin where that normal meets the
//! next axis. `Rz(θi)` joins the joint's motion as an offset on its angle, the rest is a
//! [`DhStep`]: 18 products instead of a general constant's 36. A step is taken in this form only
//! when it equals the exact product to rounding ([`REFRAME_TOLERANCE`], checked when the chain
//! is built) and the next frame slides along its axis by no more than the step's own length
//! times `REFRAME_TOLERANCE / ε` (a longer slide rounds the product by more than the tolerance:
//! nearly parallel skew axes meet their common normal far away); otherwise the link keeps the
//! general constant and the next frame is not moved.
//! Standard-DH robots are in this form already (their steps are taken as they are, bit for
//! bit); modified DH and URDF chains are rewritten. The last constant (the tool included)
//! has no next motion frame to move: it becomes `Rz(θ)·`step when it is of that form as it
//! stands (a tool turned about or set along the last axis), to the same tolerance. Chains with mimic joints, and prismatic
//! joints (whose motion cannot take an angle offset), keep their constants.
//!
//! Every scalar product of the chain takes one walk ([`walk`], visitor [`Stop`]): forward
//! kinematics, the link frames and the Jacobian on this form, joint axes and dynamics on the
//! compiled [`Chain`](super::chain::Chain) as it stands ([`WalkLink`]). Its running frame
//! [`FkFrame`] is one lane of the batch kernels' [`FrameLanes`]: the elementary steps (turn
//! and slide along z, DH step, general constant, mimic motion) exist once. The walk evaluates
//! the sines and cosines of pairs of joints together
//! ([`sin_cos_lanes`](crate::angle::sin_cos_lanes), bit for bit the scalar ones). (Skipping a
//! step's zero terms was tried and measured slower: the branches cost more than the products.)

use nalgebra::{IsometryMatrix3, Matrix3, Rotation3, Translation3, Vector3};

use super::chain::{ChainLink, MimicStep};
use super::frame_lanes::FrameLanes;
use crate::angle::sin_cos_lanes;
use crate::simd::{self, Level};

/// Largest gap (rotation entries; translation entries relative to `1 + |translation|`) between
/// a rewritten DH step and the exact product it replaces: a few units of rounding. A slide of
/// the next frame along its axis by `δ` is allowed while `ε·|δ|` stays within this tolerance
/// relative to the step's length ([`dh_reframe`]).
pub(crate) const REFRAME_TOLERANCE: f64 = 8.0 * f64::EPSILON;

/// The constant `Tz(d)·Tx(a)·Rx(α)` after a joint's motion (12 + 6 products).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct DhStep {
    /// Length along the common normal (x), metres.
    pub a: f64,
    /// Offset along the joint axis (z), metres.
    pub d: f64,
    /// `cos α`.
    pub cos_alpha: f64,
    /// `sin α`.
    pub sin_alpha: f64,
}

impl DhStep {
    /// The step `[a, d, cos α, sin α]`.
    fn new(a: f64, d: f64, cos_alpha: f64, sin_alpha: f64) -> DhStep {
        DhStep { a, d, cos_alpha, sin_alpha }
    }

    /// The step when `after` is exactly `Tz(d)·Tx(a)·Rx(α)`.
    fn of(after: &IsometryMatrix3<f64>) -> Option<DhStep> {
        let r = after.rotation.matrix();
        let t = after.translation.vector;
        let x_fixed = r[(0, 0)] == 1.0 && r[(0, 1)] == 0.0 && r[(0, 2)] == 0.0 && r[(1, 0)] == 0.0 && r[(2, 0)] == 0.0;
        let rx = r[(2, 2)] == r[(1, 1)] && r[(1, 2)] == -r[(2, 1)];
        (x_fixed && rx && t.y == 0.0).then(|| DhStep::new(t.x, t.z, r[(1, 1)], r[(2, 1)]))
    }

    /// The step as an isometry.
    fn isometry(&self) -> IsometryMatrix3<f64> {
        let (c, s) = (self.cos_alpha, self.sin_alpha);
        #[rustfmt::skip]
        let r = Matrix3::new(
            1.0, 0.0, 0.0,
            0.0, c,   -s,
            0.0, s,   c,
        );
        IsometryMatrix3::from_parts(Translation3::new(self.a, 0.0, self.d), Rotation3::from_matrix_unchecked(r))
    }
}

/// The constant after a joint's motion.
#[derive(Debug, Clone, Copy)]
pub(crate) enum FkStep {
    /// A standard-DH step.
    Dh(DhStep),
    /// Any rigid transform.
    General(IsometryMatrix3<f64>),
}

/// A rigid transform: the running product of every scalar walk ([`walk`]), held as one lane
/// of [`FrameLanes`], so one joint vector and `L` of them (batch FK, the IK check) run the
/// same elementary steps. Each step is written entry by entry in the order of operations of
/// nalgebra's products of `IsometryMatrix3`, so the results are theirs bit for bit.
/// (Measured against the plain column arrays it replaced, same walk, callgrind instructions
/// per call, Puma 560: `fk_matrix` 1071 vs 1057, `jacobian_into` 1504 vs 1629; the columns
/// before the walk was shared: 1147 and 1554.)
#[derive(Debug, Clone, Copy)]
pub(crate) struct FkFrame(FrameLanes<1>);

impl FkFrame {
    /// The frame of `t`.
    #[inline(always)]
    pub fn of(t: &IsometryMatrix3<f64>) -> FkFrame {
        FkFrame(FrameLanes::splat(t))
    }

    /// The frame as an isometry.
    #[inline(always)]
    pub fn isometry(&self) -> IsometryMatrix3<f64> {
        IsometryMatrix3::from_parts(
            Translation3::from(self.translation()),
            Rotation3::from_matrix_unchecked(self.rotation()),
        )
    }

    /// The translation.
    #[inline(always)]
    pub fn translation(&self) -> Vector3<f64> {
        let p = &self.0.p;
        Vector3::new(p[0][0], p[1][0], p[2][0])
    }

    /// The z axis.
    #[inline(always)]
    pub fn z_axis(&self) -> Vector3<f64> {
        let r = &self.0.r;
        Vector3::new(r[0][2][0], r[1][2][0], r[2][2][0])
    }

    /// The rotation.
    #[inline(always)]
    pub fn rotation(&self) -> Matrix3<f64> {
        let r = &self.0.r;
        Matrix3::from_fn(|i, j| r[i][j][0])
    }

    /// Right-multiplies by `Rz(v)` given as `(sin v, cos v)`.
    #[inline(always)]
    pub fn rotate_z(&mut self, s: f64, c: f64) {
        self.0.rotate_z(&[s], &[c]);
    }

    /// Right-multiplies by `Tz(v)`.
    #[inline(always)]
    pub fn slide_z(&mut self, v: f64) {
        self.0.slide_z(&[v]);
    }

    /// Right-multiplies by the joint motion `Rz(v)` (radians) or `Tz(v)` (metres).
    #[inline(always)]
    pub fn motion(&mut self, prismatic: bool, v: f64) {
        self.0.motion(prismatic, &[v]);
    }

    /// Right-multiplies by the constant `m`.
    #[inline(always)]
    pub fn mul_const(&mut self, m: &IsometryMatrix3<f64>) {
        self.0.mul_const(m);
    }

    /// Right-multiplies by the constant `step`.
    #[inline(always)]
    pub fn mul_step(&mut self, step: &FkStep) {
        self.0.mul_step(step);
    }

    /// Right-multiplies by the mimic motions `steps` (joint values `q`), calling `visit` with
    /// each one and the frame just before it.
    #[inline(always)]
    pub fn mimics<'a>(&mut self, steps: &'a [MimicStep], q: &[f64], visit: &mut impl FnMut(Stop<'a>, &FkFrame)) {
        for m in steps {
            visit(Stop::Mimic(m), self);
            self.motion(m.prismatic, m.value(q));
            self.mul_const(&m.after);
        }
    }
}

/// Where a walk along a chain product ([`FkChain::walk`], [`Chain::walk`](super::chain::Chain::walk))
/// shows its visitor the running frame.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Stop<'a> {
    /// Just before independent joint `i`'s motion (0-based): the frame's z axis is the joint
    /// axis.
    Joint(usize),
    /// Just after joint `i`'s motion, before the constant that follows it.
    Moved(usize),
    /// Just before a mimic joint's motion.
    Mimic(&'a MimicStep),
}

/// An independent joint of a chain product: the motion, the constant after it and the mimic
/// motions that follow. [`FkLink`] (the forward-kinematics form) and
/// [`ChainLink`] (the compiled chain as it stands, whose frames dynamics and
/// [`Robot::joint_axes`](crate::model::Robot::joint_axes) report) are both walked by
/// [`walk`], step for step the same operations.
pub(crate) trait WalkLink {
    /// Translation along z instead of rotation about z.
    fn prismatic(&self) -> bool;
    /// The motion value (radians or metres) for joint value `q`.
    fn value(&self, q: f64) -> f64;
    /// Right-multiplies `t` by the constant after the motion.
    fn mul_after(&self, t: &mut FkFrame);
    /// Mimic-joint motions between this joint and the next.
    fn mimics(&self) -> &[MimicStep];
}

/// One joint of an [`FkChain`]: motion `Rz(sign·q + offset)` (or `Tz`), then `after`, then
/// the mimic motions that follow it.
#[derive(Debug, Clone)]
pub(crate) struct FkLink {
    /// Translation along z instead of rotation about z.
    pub prismatic: bool,
    /// −1 for a flipped joint, +1 otherwise.
    pub sign: f64,
    /// Added to `sign·q` (radians; 0 for prismatic joints).
    pub offset: f64,
    /// Constant from the frame after the motion to the reported link frame
    /// ([`ChainLink::to_frame`] with the motion frame's move undone).
    pub to_frame: IsometryMatrix3<f64>,
    /// The constant after the motion (for the last joint, the tool included).
    pub after: FkStep,
    /// Mimic-joint motions between this joint and the next (empty for most robots).
    pub mimics: Vec<MimicStep>,
}

impl FkLink {
    /// The motion value for joint value `q`.
    #[inline(always)]
    pub fn value(&self, q: f64) -> f64 {
        self.sign * q + self.offset
    }
}

impl WalkLink for FkLink {
    #[inline(always)]
    fn prismatic(&self) -> bool {
        self.prismatic
    }

    #[inline(always)]
    fn value(&self, q: f64) -> f64 {
        FkLink::value(self, q)
    }

    #[inline(always)]
    fn mul_after(&self, t: &mut FkFrame) {
        t.mul_step(&self.after);
    }

    #[inline(always)]
    fn mimics(&self) -> &[MimicStep] {
        &self.mimics
    }
}

/// `T(q) = first · Π(first_mimics) · Π (M(sign·qi + offset_i) · after_i · Π(mimics_i))`.
#[derive(Debug, Clone)]
pub(crate) struct FkChain {
    /// The frame of the first motion.
    pub first: IsometryMatrix3<f64>,
    /// Mimic motions before the first joint (empty for most robots).
    pub first_mimics: Vec<MimicStep>,
    /// One per independent joint.
    pub links: Vec<FkLink>,
}

impl FkChain {
    /// The forward-kinematics form of the compiled chain `first · Π(first_mimics) · Π links`
    /// (see the module documentation).
    pub fn new(first: &IsometryMatrix3<f64>, first_mimics: &[MimicStep], chain: &[ChainLink]) -> FkChain {
        let reframe = first_mimics.is_empty() && chain.iter().all(|l| l.mimics.is_empty());
        let n = chain.len();
        let mut links = Vec::with_capacity(n);
        // C_k⁻¹: the move of the current motion frame, undone on the left of its constant.
        let mut undo = IsometryMatrix3::identity();
        for (k, link) in chain.iter().enumerate() {
            let g = undo * link.after;
            let to_frame = undo * link.to_frame;
            undo = IsometryMatrix3::identity();
            let (offset, after) = if let Some(dh) = DhStep::of(&g) {
                (0.0, FkStep::Dh(dh))
            } else if let Some((c, theta, dh)) =
                (reframe && !link.prismatic && k + 1 < n).then(|| dh_reframe(&g)).flatten()
            {
                undo = c.inverse();
                (theta, FkStep::Dh(dh))
            } else if let Some((theta, dh)) =
                (reframe && !link.prismatic && k + 1 == n).then(|| dh_turned(&g, g.translation.vector.norm())).flatten()
            {
                // The last constant (tool included) is a turned DH step as it stands: the
                // tool frame stays where it is.
                (theta, FkStep::Dh(dh))
            } else {
                (0.0, FkStep::General(g))
            };
            // The motion turns `offset` further: undo that too before the link frame.
            let unturn = Rotation3::from_axis_angle(&Vector3::z_axis(), -offset);
            let to_frame = IsometryMatrix3::from_parts(Translation3::identity(), unturn) * to_frame;
            links.push(FkLink {
                prismatic: link.prismatic,
                sign: link.sign,
                offset,
                to_frame,
                after,
                mimics: link.mimics.clone(),
            });
        }
        FkChain { first: *first, first_mimics: first_mimics.to_vec(), links }
    }
}

/// `C = Rz(φ)·Tz(δ)`, `θ` and the DH step with `g · C = Rz(θ) · step` to
/// [`REFRAME_TOLERANCE`]: the next motion frame moved onto the common normal of the two joint
/// axes (z of the frame `g` starts from, z of the frame it leads to). `None` when no such `C`
/// gives the step to rounding (axes nearly but not exactly parallel).
fn dh_reframe(g: &IsometryMatrix3<f64>) -> Option<(IsometryMatrix3<f64>, f64, DhStep)> {
    let r = g.rotation.matrix();
    let (gx, gy, gz) = (r.column(0).into_owned(), r.column(1).into_owned(), r.column(2).into_owned());
    let p = g.translation.vector;
    // The common normal's direction: z × z' for skew (or meeting) axes; for parallel axes the
    // perpendicular from this axis towards the next one's origin (or the next x axis when
    // the axes coincide).
    let normal = Vector3::new(-gz.y, gz.x, 0.0);
    let skew = normal.norm() > 1e-12;
    let target = if skew {
        normal
    } else if p.x.hypot(p.y) > 0.0 {
        Vector3::new(p.x, p.y, 0.0)
    } else {
        gx
    };
    // φ: the next x axis turned about the next z onto the normal (projected into its plane).
    let (c, s) = (target.dot(&gx), target.dot(&gy));
    let h = c.hypot(s);
    if h == 0.0 || h.is_nan() {
        return None;
    }
    let (c, s) = (c / h, s / h);
    let x = gx * c + gy * s;
    // δ: the next origin slid along the next axis to where the normal meets it.
    let delta = if skew {
        let w = Vector3::new(-x.y, x.x, 0.0);
        -p.dot(&w) / gz.dot(&w)
    } else {
        0.0
    };
    // The slide rounds the product by about ε·|δ| (the next constant, the link frames and the
    // running frame go out along the axis and back), which the step's check below does not
    // see: it is taken only when that is within the tolerance relative to the step's own
    // length. Nearly parallel skew axes, whose common normal lies far along them (the AL5D's
    // axes 5.9e-10 rad off antiparallel: δ ≈ 2.5e8 m), keep the general constant.
    if delta.abs() * f64::EPSILON > REFRAME_TOLERANCE * p.norm() {
        return None;
    }
    #[rustfmt::skip]
    let rz = Matrix3::new(
        c,   -s,  0.0,
        s,   c,   0.0,
        0.0, 0.0, 1.0,
    );
    let move_next =
        IsometryMatrix3::from_parts(Translation3::new(0.0, 0.0, delta), Rotation3::from_matrix_unchecked(rz));
    let exact = g * move_next;
    dh_turned(&exact, p.norm()).map(|(theta, step)| (move_next, theta, step))
}

/// `θ` and the DH step with `g = Rz(θ) · step` to [`REFRAME_TOLERANCE`] (translation gaps
/// relative to `1 + scale`), or `None` when `g` is not of that form to rounding.
fn dh_turned(g: &IsometryMatrix3<f64>, scale: f64) -> Option<(f64, DhStep)> {
    let m = g.rotation.matrix();
    let o = g.translation.vector;
    let theta = m[(1, 0)].atan2(m[(0, 0)]);
    let alpha = m[(2, 1)].atan2(m[(2, 2)]);
    let (sin_alpha, cos_alpha) = crate::angle::sin_cos(alpha);
    let (sin_theta, cos_theta) = crate::angle::sin_cos(theta);
    let step = DhStep::new(o.x * cos_theta + o.y * sin_theta, o.z, cos_alpha, sin_alpha);
    #[rustfmt::skip]
    let rz_theta = Matrix3::new(
        cos_theta, -sin_theta, 0.0,
        sin_theta, cos_theta,  0.0,
        0.0,       0.0,        1.0,
    );
    let model = IsometryMatrix3::from_parts(Translation3::identity(), Rotation3::from_matrix_unchecked(rz_theta))
        * step.isometry();
    let rotation_gap = (model.rotation.matrix() - m).amax();
    let translation_gap = (model.translation.vector - o).amax() / (1.0 + scale);
    (rotation_gap <= REFRAME_TOLERANCE && translation_gap <= REFRAME_TOLERANCE).then_some((theta, step))
}

/// Joints whose sines and cosines [`walk`] evaluates together (a pair; [`FkChain::product_at`]
/// takes more: [`BASELINE_TRIG_LANES`] at the baseline level, 4 or 8 at the wider ones).
const TRIG_LANES: usize = 2;

/// Joints whose sines and cosines [`FkChain::product_at`] evaluates together at the baseline
/// level (two lanes per vector: SSE2, NEON) for a chain of up to that many joints: the whole
/// of a 6-joint arm in one [`walk_by`] block (three vectors, every lane used). Measured
/// 2026-12-03, callgrind instructions per call, Puma 560, baseline level: `fk_matrix` 1 513 with
/// [`walk`]'s pairs (inlined there, the pair's two lanes were evaluated one after the other),
/// 1 168 with this block; the walk alone (start, walk, isometry) in blocks of 3, 4, 6 and 8:
/// 1 117, 1 154, 1 018 and 1 115.
const BASELINE_TRIG_LANES: usize = 6;

/// Right-multiplies `t` by the motion of `link` for joint value `q` (given the sine and cosine
/// of its angle, [`WalkLink::value`]; unused for a prismatic joint), the constant after it and
/// its mimic motions (joint values `all`), showing `visit` joint `i` before and after its
/// motion and each mimic motion.
#[inline(always)]
fn advance<'a, K: WalkLink>(
    link: &'a K,
    i: usize,
    t: &mut FkFrame,
    q: f64,
    (s, c): (f64, f64),
    all: &[f64],
    visit: &mut impl FnMut(Stop<'a>, &FkFrame),
) {
    visit(Stop::Joint(i), t);
    if link.prismatic() {
        t.slide_z(link.value(q));
    } else {
        t.rotate_z(s, c);
    }
    visit(Stop::Moved(i), t);
    link.mul_after(t);
    t.mimics(link.mimics(), all, visit);
}

/// The frame `first · Π(first_mimics)` a chain product starts from (joint values `q`),
/// showing `visit` each mimic motion.
#[inline(always)]
pub(crate) fn start<'a>(
    first: &IsometryMatrix3<f64>,
    first_mimics: &'a [MimicStep],
    q: &[f64],
    visit: &mut impl FnMut(Stop<'a>, &FkFrame),
) -> FkFrame {
    let mut t = FkFrame::of(first);
    t.mimics(first_mimics, q, visit);
    t
}

/// Right-multiplies `t` by the motions, constants and mimic motions of `links[joints]` (a
/// range of joint indices; `links` the whole chain) for joint values `q` (all of them, one per
/// joint), showing `visit` every [`Stop`] on the way. The one walk of every scalar chain
/// product: forward kinematics, link frames and the Jacobian on the [`FkChain`], joint axes
/// and dynamics on the compiled [`Chain`](super::chain::Chain). The sines and cosines of
/// pairs of joints are evaluated together; [`walk_by`] is the same walk with more joints
/// together, for kernels compiled for wider vectors.
#[inline(always)]
pub(crate) fn walk<'a, K: WalkLink>(
    links: &'a [K],
    t: &mut FkFrame,
    q: &[f64],
    joints: std::ops::Range<usize>,
    mut visit: impl FnMut(Stop<'a>, &FkFrame),
) {
    let from = joints.start;
    let values = &q[joints.clone()];
    let links = &links[joints];
    let mut i = from;
    let mut chunks = links.chunks_exact(TRIG_LANES);
    let mut value_chunks = values.chunks_exact(TRIG_LANES);
    for (ls, vs) in chunks.by_ref().zip(value_chunks.by_ref()) {
        let angles: [f64; TRIG_LANES] = std::array::from_fn(|k| trig_angle(&ls[k], vs[k]));
        let (s, c) = sin_cos_lanes(&angles);
        // Written out: a loop over the pair kept its counter in some callers (measured again
        // 2026-12-03 as `walk_by::<_, 2>`: `jacobian_into` +5.6 % instructions).
        advance(&ls[0], i, t, vs[0], (s[0], c[0]), q, &mut visit);
        advance(&ls[1], i + 1, t, vs[1], (s[1], c[1]), q, &mut visit);
        i += TRIG_LANES;
    }
    for (link, &v) in chunks.remainder().iter().zip(value_chunks.remainder()) {
        advance(link, i, t, v, crate::angle::sin_cos(trig_angle(link, v)), q, &mut visit);
        i += 1;
    }
}

/// The angle whose sine and cosine a walk ([`walk`], [`walk_by`]) evaluates for `link` at joint
/// value `v`: its motion's ([`WalkLink::value`]), 0 for a prismatic joint (unused).
#[inline(always)]
fn trig_angle<K: WalkLink>(link: &K, v: f64) -> f64 {
    if link.prismatic() { 0.0 } else { link.value(v) }
}

/// [`walk`] with the sines and cosines of `T` joints evaluated together
/// ([`sin_cos_lanes`](crate::angle::sin_cos_lanes), bit for bit the scalar ones, so `T` does
/// not change the result): blocks of `T` joints, then the last `joints.len() mod T` together
/// (their unused lanes at angle 0). A kernel compiled for wider vectors takes all of a 6- or
/// 7-joint arm in one block ([`FkChain::product_at`]).
#[inline(always)]
pub(crate) fn walk_by<'a, K: WalkLink, const T: usize>(
    links: &'a [K],
    t: &mut FkFrame,
    q: &[f64],
    joints: std::ops::Range<usize>,
    mut visit: impl FnMut(Stop<'a>, &FkFrame),
) {
    let from = joints.start;
    let values = &q[joints.clone()];
    let links = &links[joints];
    let mut i = from;
    let mut chunks = links.chunks_exact(T);
    let mut value_chunks = values.chunks_exact(T);
    for (ls, vs) in chunks.by_ref().zip(value_chunks.by_ref()) {
        // Loops over the block rather than `array::from_fn` with a closure: the closure was
        // left out of line in callers with several walks (the baseline level's `fk_matrix`).
        let mut angles = [0.0; T];
        for k in 0..T {
            angles[k] = trig_angle(&ls[k], vs[k]);
        }
        let (s, c) = sin_cos_lanes::<T>(&angles);
        for k in 0..T {
            advance(&ls[k], i + k, t, vs[k], (s[k], c[k]), q, &mut visit);
        }
        i += T;
    }
    let (ls, vs) = (chunks.remainder(), value_chunks.remainder());
    if !ls.is_empty() {
        let mut angles = [0.0; T];
        for (angle, (link, &v)) in angles.iter_mut().zip(ls.iter().zip(vs)) {
            *angle = trig_angle(link, v);
        }
        let (s, c) = sin_cos_lanes::<T>(&angles);
        for (k, (link, &v)) in ls.iter().zip(vs).enumerate() {
            advance(link, i + k, t, v, (s[k], c[k]), q, &mut visit);
        }
    }
}

impl FkChain {
    /// The frame `first · Π(first_mimics)` the product starts from (joint values `q`),
    /// showing `visit` each mimic motion.
    #[inline(always)]
    pub fn start<'a>(&'a self, q: &[f64], visit: &mut impl FnMut(Stop<'a>, &FkFrame)) -> FkFrame {
        start(&self.first, &self.first_mimics, q, visit)
    }

    /// Right-multiplies `t` by the motions and constants of joints `joints` (a range of
    /// joint indices) for joint values `q` (all of them, one per joint; mimic motions
    /// included), showing `visit` every [`Stop`] on the way.
    #[inline(always)]
    pub fn walk<'a>(
        &'a self,
        t: &mut FkFrame,
        q: &[f64],
        joints: std::ops::Range<usize>,
        visit: impl FnMut(Stop<'a>, &FkFrame),
    ) {
        walk(&self.links, t, q, joints, visit);
    }

    /// The tool pose for joint values `q`, the walk compiled for `level` with the sines and
    /// cosines of several joints together (4 with AVX2, 8 with AVX-512; at the baseline level
    /// all of a chain of up to [`BASELINE_TRIG_LANES`] joints, else 8): bit for bit
    /// [`FkChain::product`] at every level. What
    /// [`Robot::fk_matrix`](crate::model::Robot::fk_matrix) runs.
    #[inline]
    pub fn product_at(&self, q: &[f64], level: Level) -> FkFrame {
        simd::run_at(level, Product { chain: self, q, level })
    }

    /// The whole product for joint values `q` (the tool pose), showing `visit` every
    /// [`Stop`] on the way.
    #[inline(always)]
    pub fn product<'a>(&'a self, q: &[f64], mut visit: impl FnMut(Stop<'a>, &FkFrame)) -> FkFrame {
        let mut t = self.start(q, &mut visit);
        self.walk(&mut t, q, 0..self.links.len(), visit);
        t
    }
}

/// [`FkChain::product_at`] as a [`simd::Kernel`] (`level`: the level it runs at, which
/// chooses how many joints' sines and cosines go together).
struct Product<'a> {
    chain: &'a FkChain,
    q: &'a [f64],
    level: Level,
}

impl simd::Kernel for Product<'_> {
    type Output = FkFrame;
    #[inline(always)]
    fn run(self) -> FkFrame {
        let (chain, q) = (self.chain, self.q);
        let mut t = chain.start(q, &mut |_, _| {});
        let all = 0..chain.links.len();
        match self.level {
            // Two lanes per vector: six joints in one block (three vectors, every lane
            // used), seven or more in blocks of eight.
            Level::Baseline if chain.links.len() <= BASELINE_TRIG_LANES => {
                walk_by::<_, BASELINE_TRIG_LANES>(&chain.links, &mut t, q, all, |_, _| {});
            }
            Level::Baseline => walk_by::<_, 8>(&chain.links, &mut t, q, all, |_, _| {}),
            Level::Avx2 => walk_by::<_, 4>(&chain.links, &mut t, q, all, |_, _| {}),
            Level::Avx512 => walk_by::<_, 8>(&chain.links, &mut t, q, all, |_, _| {}),
        }
        t
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Robot, UrdfChain, presets};
    use crate::rng::SplitMix64;

    /// Every preset, a URDF arm (reframed steps and a general constant: UR5), and the mimic
    /// arm.
    fn robots() -> Vec<Robot> {
        let urdf = |text: &str, base: Option<&str>, tip: &str| {
            let chain = UrdfChain { base: base.map(Into::into), tip: Some(tip.into()) };
            Robot::from_urdf_str(text, &chain).unwrap()
        };
        let ur5 = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../examples/urdf/ur_description/urdf/ur5.urdf"
        ))
        .unwrap();
        let mut robots: Vec<Robot> = presets::names().iter().map(|n| presets::get(n).unwrap()).collect();
        robots.push(urdf(&ur5, None, "ee_link"));
        robots.push(urdf(include_str!("../../tests/data/mimic_arm.urdf"), Some("base"), "tool"));
        robots
    }

    fn bits(t: &FkFrame) -> Vec<u64> {
        let (r, p) = (t.rotation(), t.translation());
        r.iter().chain(p.iter()).map(|v| v.to_bits()).collect()
    }

    #[test]
    fn the_product_is_the_same_bits_at_every_level_and_trig_width() {
        let mut rng = SplitMix64(31);
        for robot in robots() {
            let fk = &robot.chain.fk;
            let n = fk.links.len();
            for _ in 0..40 {
                // Some joint values beyond the fast range of `sin_cos` (its libm fallback).
                let q: Vec<f64> = (0..robot.dof())
                    .map(|_| (2.0 * rng.next_f64() - 1.0) * if rng.next_f64() < 0.1 { 300.0 } else { 4.0 })
                    .collect();
                let want = bits(&fk.product(&q, |_, _| {}));
                for level in simd::levels() {
                    assert_eq!(bits(&fk.product_at(&q, level)), want, "{} {}", robot.name(), level.name());
                }
                let by = |w: fn(&[FkLink], &mut FkFrame, &[f64])| {
                    let mut t = fk.start(&q, &mut |_, _| {});
                    w(&fk.links, &mut t, &q);
                    bits(&t)
                };
                assert_eq!(by(|l, t, q| walk_by::<_, 1>(l, t, q, 0..l.len(), |_, _| {})), want);
                assert_eq!(by(|l, t, q| walk_by::<_, 2>(l, t, q, 0..l.len(), |_, _| {})), want);
                assert_eq!(by(|l, t, q| walk_by::<_, 3>(l, t, q, 0..l.len(), |_, _| {})), want);
                assert_eq!(by(|l, t, q| walk_by::<_, 4>(l, t, q, 0..l.len(), |_, _| {})), want);
                assert_eq!(by(|l, t, q| walk_by::<_, 6>(l, t, q, 0..l.len(), |_, _| {})), want);
                assert_eq!(by(|l, t, q| walk_by::<_, 8>(l, t, q, 0..l.len(), |_, _| {})), want);
                // A walk in two parts is the whole walk.
                let mut t = fk.start(&q, &mut |_, _| {});
                walk_by::<_, 8>(&fk.links, &mut t, &q, 0..n / 2, |_, _| {});
                walk_by::<_, 8>(&fk.links, &mut t, &q, n / 2..n, |_, _| {});
                assert_eq!(bits(&t), want);
            }
        }
    }
}
