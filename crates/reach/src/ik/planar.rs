//! Seed 000: the planar redundant three-link arm (`planar3`) — its self-motion in closed form
//! and the thesis's α-scan.
//!
//! # The arm
//!
//! Three revolute joints whose axes are parallel (and point the same way); the tool point
//! moves in a plane normal to them. The structure is read from the compiled chain, so any
//! description fits: standard or modified DH, URDF, base and tool transforms, angle offsets,
//! flipped joints, and arbitrary link lengths `l1, l2, l3` (the thesis has three equal links).
//! The *plane frame* is the frame in which joint 1 turns about z (the base frame for the
//! `planar3` preset); the *absolute link angles* `φ1, φ2, φ3` are the directions of the links
//! (joint 1 → joint 2, joint 2 → joint 3, joint 3 → tool point) from its x axis. For `planar3`
//! `φ1 = q1`, `φ2 = q1 + q2`, `φ3 = q1 + q2 + q3`.
//!
//! # The redundancy
//!
//! A position target leaves one degree of freedom. It is parameterised by `φ = φ3`, the
//! absolute angle of the last link: for each `φ` the wrist point `W = p − l3·(cos φ, sin φ)` is
//! fixed and a two-link IK gives two elbow branches. `W` is reachable when
//! `|l1 − l2| ≤ |W| ≤ l1 + l2`; with `|W|² = r² + l3² − 2·r·l3·cos(φ − ψ)` (`r, ψ` the polar
//! coordinates of the target) this is `c_lo ≤ cos(φ − ψ) ≤ c_hi`, so the feasible `φ` form at
//! most two intervals symmetric about `ψ` ([`PlanarRedundant::feasible_intervals`]). At their
//! ends the elbow is stretched or folded (a singularity). The workspace is the annulus
//! `max(0, l_max − (sum of the other two)) ≤ r ≤ l1 + l2 + l3`.
//!
//! # The thesis's method
//!
//! [`PlanarRedundant::paper_scan`] reproduces the thesis's enumeration (notes 000 §3.1, §4.1):
//! the interior angle `α` at joint A is stepped from `α_min` (eq. 3) to 180°, and `γ`, `β`
//! follow from the law-of-cosines formulas (6)–(14) with the corrected `γ2 = atan2(y, x)`
//! (notes 000 §6.1, D1). [`PaperScan::select_min_s`] picks the row of least total joint change
//! `S` (notes 000 §6.3). The paper's angle convention is [`InteriorAngles`].

use std::f64::consts::{PI, TAU};

use nalgebra::{IsometryMatrix3, Point3, Rotation3, Vector3};

use super::solution::fit_revolute;
use super::{
    Branch, Candidate, IkError, IkFailure, IkOptions, IkSolutions, IkSolver, IkTarget, SingularityKind, finish,
};
use crate::kinematics::KinematicsError;
use crate::model::chain::ChainLink;
use crate::model::planar_angles::InteriorAngles;
use crate::model::{Limits, Robot};
use crate::simd;
use crate::tolerance::{
    BOUNDARY, IK_AXIS_DISTANCE, IK_DUPLICATE, IK_POSITION, LIMIT_SLACK, SCAN_GRID, STRUCTURE_ANGLE, STRUCTURE_LENGTH,
};

const NAME: &str = "planar";

/// Most rows [`PlanarRedundant::paper_scan`] builds (≈ 64 MB of rows): a step of 0.0001°
/// (ten times finer than the finest step of the thesis) still fits.
pub const MAX_SCAN_ROWS: usize = 1_000_000;

/// Most self-motion samples per full turn of the redundancy parameter (a step of at least
/// 0.1°). Every sample yields up to two (four with a base yaw) candidates, and the solution
/// set is de-duplicated pairwise, so the cost grows with the square of this number.
pub const MAX_SELF_MOTION_SAMPLES: usize = 3600;

// ---------------------------------------------------------------------------------------------
// Shared planar machinery (also used by the yaw solvers).
// ---------------------------------------------------------------------------------------------

/// One link of a chain of joints whose axes are parallel to z of the frame they start in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlanarLink {
    /// Distance from this joint's axis to the next joint's axis (or to the tool point).
    pub length: f64,
    /// Direction of the link in the frame turned by the joint (DH: 0; MDH/URDF offsets).
    pub delta: f64,
    /// Rotation about z from the frame turned by the joint to the next joint's motion frame.
    pub psi: f64,
    /// −1 for a flipped joint, +1 otherwise: the physical angle is `sign·q`.
    pub sign: f64,
}

/// A chain of `N` revolute joints with parallel axes, read from the compiled chain.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PlanarChain<const N: usize> {
    pub links: [PlanarLink; N],
    /// Offset of the tool point along the common axis (sum of the offsets along z).
    pub height: f64,
    /// Rotation of the last fixed transform (tool included), after the last joint's motion.
    pub last_rotation: Rotation3<f64>,
}

impl<const N: usize> PlanarChain<N> {
    /// Reads `links` (the compiled chain's joints `first_joint ..= first_joint + N − 1`,
    /// 1-based numbers for messages). Fails with the violated condition.
    pub fn from_chain(links: &[ChainLink], first_joint: usize) -> Result<Self, String> {
        if links.len() != N {
            return Err(format!("expected {N} planar joints, got {}", links.len()));
        }
        let mut out = [PlanarLink { length: 0.0, delta: 0.0, psi: 0.0, sign: 1.0 }; N];
        let mut height = 0.0;
        let mut last_rotation = Rotation3::identity();
        for (i, link) in links.iter().enumerate() {
            let number = first_joint + i;
            if link.prismatic {
                return Err(format!("joint {number} is prismatic (a revolute joint is needed)"));
            }
            let r = link.after.rotation;
            let p = link.after.translation.vector;
            let length = p.x.hypot(p.y);
            out[i] = PlanarLink {
                length,
                delta: if length > STRUCTURE_LENGTH { p.y.atan2(p.x) } else { 0.0 },
                psi: 0.0,
                sign: link.sign,
            };
            height += p.z;
            if i + 1 < N {
                let z = r * Vector3::z();
                if (z - Vector3::z()).norm() > STRUCTURE_ANGLE {
                    let angle = z.z.clamp(-1.0, 1.0).acos().to_degrees();
                    return Err(if (z + Vector3::z()).norm() <= STRUCTURE_ANGLE {
                        format!("joint {} axis is antiparallel to joint {number} axis (not supported)", number + 1)
                    } else {
                        format!("joint {} axis is not parallel to joint {number} axis (angle {angle:.6}°)", number + 1)
                    });
                }
                out[i].psi = r[(1, 0)].atan2(r[(0, 0)]);
            } else {
                last_rotation = r;
            }
        }
        Ok(PlanarChain { links: out, height, last_rotation })
    }

    /// Link lengths.
    pub fn lengths(&self) -> [f64; N] {
        self.links.map(|l| l.length)
    }

    /// Absolute link angles `φ` (in the frame the first joint turns in) of joint values `q`.
    pub fn link_angles(&self, q: &[f64]) -> [f64; N] {
        let mut phi = [0.0; N];
        let mut acc = 0.0;
        for (i, (link, &v)) in self.links.iter().zip(q).enumerate() {
            let theta = link.sign * v;
            phi[i] = acc + theta + link.delta;
            acc += theta + link.psi;
        }
        phi
    }

    /// Joint values (unwrapped) that give the absolute link angles `phi`.
    pub fn joints(&self, phi: &[f64; N]) -> [f64; N] {
        let mut q = [0.0; N];
        let mut acc = 0.0;
        for (i, link) in self.links.iter().enumerate() {
            let theta = phi[i] - link.delta - acc;
            q[i] = link.sign * theta;
            acc += theta + link.psi;
        }
        q
    }

    /// Absolute angle of the last link when the last joint's frame is turned by `heading`
    /// about z (`φ_N = Θ + δ_N`).
    pub fn heading_to_last_angle(&self, heading: f64) -> f64 {
        heading + self.links[N - 1].delta
    }
}

/// One solution of a planar two-link problem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Elbow {
    /// Absolute angles of the two links.
    pub phi: [f64; 2],
    /// Relative angle of link 2 to link 1 (`φ2 − φ1`), in [−π, π].
    pub bend: f64,
    /// Singularity of this solution (stretched/folded elbow, or wrist on the shoulder axis).
    pub singular: Option<SingularityKind>,
}

/// Result of a planar two-link IK.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum TwoLink {
    /// The point is outside the annulus `|l1 − l2| ≤ r ≤ l1 + l2`.
    Out { distance: f64, reach: f64 },
    /// One (singular) or two solutions.
    In([Option<Elbow>; 2]),
}

/// The angle between sides `a` and `b` of a triangle whose third side is `c` (law of
/// cosines), `None` when the sides violate the triangle inequality by more than [`BOUNDARY`]
/// (relative). Evaluated as `atan2(4·area, a² + b² − c²)` with Kahan's stable Heron formula,
/// so that angles near 0 and π keep full precision (`acos` loses half the digits there).
///
/// The plain single-angle form, kept as the reference that [`triangle_angle_pair`] (used by
/// the scan) must reproduce bit for bit.
#[cfg(test)]
fn triangle_angle(a: f64, b: f64, c: f64) -> Option<f64> {
    let slack = BOUNDARY * (a + b + c);
    if c > a + b + slack || c < (a - b).abs() - slack {
        return None;
    }
    let mut s = [a, b, c];
    s.sort_by(|x, y| y.total_cmp(x));
    let [x, y, z] = s;
    // Kahan: 16·area² = (x+(y+z))(z−(x−y))(z+(x−y))(x+(y−z)), x ≥ y ≥ z.
    let f = (x + (y + z)) * (z - (x - y)).max(0.0) * (z + (x - y)) * (x + (y - z));
    Some(f.max(0.0).sqrt().atan2(a * a + b * b - c * c))
}

/// `4·area` of the triangle with sides `a, b, c` (Kahan's stable Heron formula; 0 for a
/// degenerate one). Symmetric in its arguments, bit for bit (the sides are sorted first).
fn four_area(a: f64, b: f64, c: f64) -> f64 {
    // The three sides in decreasing order (a sorting network: no slice sort per call).
    let (hi, lo) = if a >= b { (a, b) } else { (b, a) };
    let (x, rest) = if hi >= c { (hi, c) } else { (c, hi) };
    let (y, z) = if lo >= rest { (lo, rest) } else { (rest, lo) };
    // Kahan: 16·area² = (x+(y+z))(z−(x−y))(z+(x−y))(x+(y−z)), x ≥ y ≥ z.
    let f = (x + (y + z)) * (z - (x - y)).max(0.0) * (z + (x - y)) * (x + (y - z));
    f.max(0.0).sqrt()
}

/// `(triangle_angle(c, b, a), triangle_angle(a, b, c))`: the angles at the two ends of side `b`
/// (opposite `a` and `c`), both or neither, sharing one area evaluation.
fn triangle_angle_pair(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
    let slack_cba = BOUNDARY * (c + b + a);
    if a > c + b + slack_cba || a < (c - b).abs() - slack_cba {
        return None;
    }
    let slack_abc = BOUNDARY * (a + b + c);
    if c > a + b + slack_abc || c < (a - b).abs() - slack_abc {
        return None;
    }
    let area = four_area(a, b, c);
    Some((area.atan2(c * c + b * b - a * a), area.atan2(a * a + b * b - c * c)))
}

/// Rows of [`PlanarRedundant::paper_scan`] from one directly computed *anchor* row to the
/// next (the others are incremental).
const SCAN_ANCHOR_ROWS: usize = 128;

/// A row's triangles are used incrementally only where `4·area` of triangle OBK and `KB` (in
/// squared units) exceed this fraction of `r² + l1² + l2² + l3²`: there an error `δ` in
/// `cos α` moves `γ1` and `β` by at most about `δ / SCAN_MIN_CONDITION` (the angles' condition
/// number), so the increments' few units in the last place stay below 1e-13 rad.
const SCAN_MIN_CONDITION: f64 = 1e-2;

/// Whether an incremental row's chain bends back at B (`β > π·(1 + BOUNDARY)`) is decided from
/// the anchor only when `β` is farther than this (radians) from that limit; nearer, the row is
/// computed directly (the increments' error is below 1e-12 rad).
const SCAN_DECISION_MARGIN: f64 = 1e-10;

/// Largest turn (as `|tan|`) of a triangle's direction vector from one row to the next that
/// is evaluated by [`atan_small`]; beyond, the row is computed directly.
const SCAN_MAX_TAN: f64 = 1.0 / 64.0;

/// `atan t` for `|t| ≤` [`SCAN_MAX_TAN`]: the Taylor series to `t⁷/7` (alternating: the
/// truncation error is below `|t|⁹/9` ≤ 6.2e-18 rad).
#[inline(always)]
fn atan_small(t: f64) -> f64 {
    let t2 = t * t;
    t * (1.0 + t2 * (-1.0 / 3.0 + t2 * (1.0 / 5.0 - t2 * (1.0 / 7.0))))
}

/// Slots of a segment's arrays ([`ScanSegment`], [`RotationSteps`]): the anchor (slot 0) and
/// [`SCAN_ANCHOR_ROWS`] more, one beyond the segment's last row, so that the passes over the
/// rows run over a whole number of vectors at every level (no scalar remainder); the values
/// of slots past a segment's rows are computed and never used.
const SEGMENT_SLOTS: usize = SCAN_ANCHOR_ROWS + 1;

/// `(sin, cos)` of `α_anchor + j·Δ` for `j` below [`SCAN_ANCHOR_ROWS`] by angle addition from
/// the anchor's exact `(sin, cos)` and a table of `(sin jΔ, cos jΔ)`: no error accumulates
/// from row to row (each value is a 2-term product of correctly evaluated factors, within a
/// few units in the last place of the exact one).
#[derive(Debug, Clone)]
struct RotationSteps {
    /// `sin jΔ` and `cos jΔ` per slot `j` (`0` and `1` beyond the rows asked for).
    sin: [f64; SEGMENT_SLOTS],
    cos: [f64; SEGMENT_SLOTS],
}

impl RotationSteps {
    /// The rotations by `0, Δ, …, (rows − 1)·Δ` (at least; [`crate::angle::sin_cos`] of each,
    /// evaluated 8 at a time by [`crate::angle::sin_cos_lanes`], the same bits).
    fn new(step: f64, rows: usize) -> Self {
        const LANES: usize = 8;
        let mut steps = RotationSteps { sin: [0.0; SEGMENT_SLOTS], cos: [1.0; SEGMENT_SLOTS] };
        for start in (0..rows.min(SEGMENT_SLOTS)).step_by(LANES) {
            let angles: [f64; LANES] = std::array::from_fn(|l| (start + l) as f64 * step);
            let (s, c) = crate::angle::sin_cos_lanes(&angles);
            let len = LANES.min(SEGMENT_SLOTS - start);
            steps.sin[start..start + len].copy_from_slice(&s[..len]);
            steps.cos[start..start + len].copy_from_slice(&c[..len]);
        }
        steps
    }

    /// `(sin, cos)` of the anchor's angle turned by `j` steps (`j <` [`SEGMENT_SLOTS`]).
    #[inline(always)]
    fn turn(&self, (s, c): (f64, f64), j: usize) -> (f64, f64) {
        let (sj, cj) = (self.sin[j], self.cos[j]);
        (s * cj + c * sj, c * cj - s * sj)
    }
}

/// What one incremental row of the scan gives.
#[cfg(test)]
enum Incremental {
    /// The row's `γ1` and `β` (not clamped).
    Angles(f64, f64),
    /// Not decidable from the track: the row is computed directly.
    Direct,
}

/// The incremental rows' state: the anchor's `(sin α, cos α)` (the last row computed
/// directly) and the angles and direction vectors of the previous row.
#[derive(Debug, Clone, Copy)]
struct Track {
    trig: (f64, f64),
    /// `γ1` and its direction vector `(r² + l1² − KB², 4·area)` of triangle OBK.
    gamma1: f64,
    g: [f64; 2],
    /// `β = β1 + β2` (before the clamp to π) and its direction vector.
    beta: f64,
    b: [f64; 2],
}

/// The per-scan constants of the incremental rows.
struct ScanFrame {
    lengths: [f64; 3],
    /// Target distance `r` and direction `γ2`.
    r: f64,
    gamma2: f64,
    /// A triangle is used incrementally only when `(4·area)²` and `KB²` (scaled by the sum of
    /// the squared lengths) exceed these: there the angles are well conditioned (module
    /// `paper_scan` docs).
    min_area2: f64,
    min_kb2: f64,
}

impl ScanFrame {
    /// The constants of a scan of an arm of `lengths` to `target_xy` (plane coordinates).
    fn new(lengths: [f64; 3], [x, y]: [f64; 2]) -> Self {
        // The same r and γ2 as `paper_row` computes for each row (r there is not `hypot`).
        let r = (x * x + y * y).sqrt();
        let squares = r * r + lengths.iter().map(|l| l * l).sum::<f64>();
        ScanFrame {
            lengths,
            r,
            gamma2: y.atan2(x),
            min_area2: (SCAN_MIN_CONDITION * squares).powi(2),
            min_kb2: SCAN_MIN_CONDITION * squares,
        }
    }

    /// `KB²` and the direction vectors of `γ1` and `β` at `(sin α, cos α)`, or `None` for an
    /// ill-conditioned (nearly degenerate) triangle.
    #[inline]
    fn vectors(&self, trig: (f64, f64)) -> Option<([f64; 2], [f64; 2])> {
        let (conditioned, g, b) = self.vectors_unchecked(trig);
        conditioned.then_some((g, b))
    }

    /// The direction vectors of [`Self::vectors`] and whether the triangles are well
    /// conditioned (branch-free: the vectors are computed either way, NaN-free or not).
    #[inline(always)]
    fn vectors_unchecked(&self, (sin_alpha, cos_alpha): (f64, f64)) -> (bool, [f64; 2], [f64; 2]) {
        let [l1, l2, l3] = self.lengths;
        let r = self.r;
        let kb2 = l2 * l2 + l3 * l3 - 2.0 * l2 * l3 * cos_alpha;
        // Triangle OBK: 4·area = √((2·r·l1)² − (r² + l1² − KB²)²), the difference factored.
        let n_gamma = r * r + l1 * l1 - kb2;
        let two_rl = 2.0 * r * l1;
        let area2 = (two_rl - n_gamma) * (two_rl + n_gamma);
        // Both conditions false for NaN.
        let conditioned = (area2 >= self.min_area2) & (kb2 >= self.min_kb2);
        let area = area2.sqrt();
        let n_beta = kb2 + l1 * l1 - r * r;
        // β = β1 + β2: the product of their direction vectors (β2 of triangle ABK).
        let (x2, y2) = (l2 - l3 * cos_alpha, l3 * sin_alpha);
        (conditioned, [n_gamma, area], [n_beta * x2 - area * y2, n_beta * y2 + area * x2])
    }
}

/// Whether the turn `(cross, dot)` of a direction vector from one row to the next is small
/// enough for [`atan_small`]: `|tan| ≤` [`SCAN_MAX_TAN`], forward (`dot > 0`); false for NaN.
#[inline(always)]
fn small_turn(cross: f64, dot: f64) -> bool {
    (dot > 0.0) & (cross.abs() <= SCAN_MAX_TAN * dot)
}

/// One anchor's segment of the scan (up to [`SCAN_ANCHOR_ROWS`] rows) in
/// structure-of-arrays form: pass by pass over the rows, each pass free of row-to-row
/// dependencies except the final running sums, so the rows' square roots, divisions and
/// polynomials overlap (and pair up in vector instructions) instead of waiting on each other.
struct ScanSegment {
    /// Direction vectors of `γ1` and `β` per row (components as separate arrays).
    g: [[f64; SEGMENT_SLOTS]; 2],
    b: [[f64; SEGMENT_SLOTS]; 2],
    /// Per row: the turns of `γ1` and `β` from the previous row (NaN where the row is not
    /// decidable incrementally), then the angles themselves.
    gamma1: [f64; SEGMENT_SLOTS],
    beta: [f64; SEGMENT_SLOTS],
    /// The finished rows ([`Self::finish`]).
    rows: SegmentRows,
}

impl ScanSegment {
    fn new() -> Box<Self> {
        Box::new(ScanSegment {
            g: [[0.0; SEGMENT_SLOTS]; 2],
            b: [[0.0; SEGMENT_SLOTS]; 2],
            gamma1: [0.0; SEGMENT_SLOTS],
            beta: [0.0; SEGMENT_SLOTS],
            rows: SegmentRows {
                alpha: [0.0; SEGMENT_SLOTS],
                beta: [0.0; SEGMENT_SLOTS],
                gamma: [0.0; SEGMENT_SLOTS],
                q: [[0.0; SEGMENT_SLOTS]; 3],
                as_is: [false; SEGMENT_SLOTS],
                index: std::array::from_fn(|j| j as f64),
                block: [ScanRow {
                    paper: InteriorAngles { alpha: 0.0, beta: 0.0, gamma: 0.0 },
                    q: [0.0; 3],
                    within_limits: false,
                }; SCAN_ANCHOR_ROWS],
            },
        })
    }

    /// Rows `1 .. n` after the anchor `track` (`n ≤` [`SCAN_ANCHOR_ROWS`]): fills `γ1` and
    /// `β` of rows `1 .. m` and returns `m`, the first row that is not decidable
    /// incrementally (`n` when all are). Every value is the one [`PlanarRedundant`]'s
    /// row-by-row increments give (the same expressions in the same order, bit for bit).
    #[allow(
        clippy::needless_range_loop,
        reason = "the passes index several arrays by the same row: the form that vectorises"
    )]
    #[inline(always)]
    fn fill(&mut self, frame: &ScanFrame, steps: &RotationSteps, track: &Track, n: usize) -> usize {
        let (g, b) = (&mut self.g, &mut self.b);
        [g[0][0], g[1][0], b[0][0], b[1][0]] = [track.g[0], track.g[1], track.b[0], track.b[1]];
        // Pass 1: each row's direction vectors (NaN where ill conditioned).
        for j in 1..SEGMENT_SLOTS {
            let (conditioned, gj, bj) = frame.vectors_unchecked(steps.turn(track.trig, j));
            let keep = |v: f64| if conditioned { v } else { f64::NAN };
            [g[0][j], g[1][j], b[0][j], b[1][j]] = [keep(gj[0]), keep(gj[1]), keep(bj[0]), keep(bj[1])];
        }
        // Pass 2: each row's turns from the previous row (NaN `β` turn where not small).
        for j in 1..SEGMENT_SLOTS {
            let (cross_g, dot_g) = cross_dot([g[0][j - 1], g[1][j - 1]], [g[0][j], g[1][j]]);
            let (cross_b, dot_b) = cross_dot([b[0][j - 1], b[1][j - 1]], [b[0][j], b[1][j]]);
            // One division for both tangents.
            let inverse = 1.0 / (dot_g * dot_b);
            self.gamma1[j] = atan_small(cross_g * dot_b * inverse);
            let turn = atan_small(cross_b * dot_g * inverse);
            self.beta[j] = if small_turn(cross_g, dot_g) & small_turn(cross_b, dot_b) { turn } else { f64::NAN };
        }
        // Pass 3: the running sums, in row order (rows after the first one not decidable
        // here get sums too; they are not used).
        let (mut gamma1, mut beta) = (track.gamma1, track.beta);
        for j in 1..n {
            gamma1 += self.gamma1[j];
            beta += self.beta[j];
            self.gamma1[j] = gamma1;
            self.beta[j] = beta;
        }
        // The first row not decidable here (branch-free, so that it vectorises): whether the
        // chain bends back at B (β > 180°) is decided only with a margin far above the
        // increments' error; near the limit (or NaN) the row is computed directly.
        let mut first = n;
        for j in 1..SEGMENT_SLOTS {
            let decidable = (self.beta[j] - PI * (1.0 + BOUNDARY)).abs() > SCAN_DECISION_MARGIN;
            first = first.min(if decidable | (j >= n) { n } else { j });
        }
        first
    }
}

/// The rows `1 .. n` of a segment, finished: [`PlanarRedundant::finish_row`]'s rows, bit for
/// bit, in structure-of-arrays passes (the joint values and the test that their fit into the
/// limits leaves them as they are, for all rows; [`PlanarRedundant::fit_row`] only for the
/// rows that test fails), written with one `extend`.
struct SegmentRows {
    /// Per row: `α`, `β` clamped to 180°, `γ`, and the joint values before the fit.
    alpha: [f64; SEGMENT_SLOTS],
    beta: [f64; SEGMENT_SLOTS],
    gamma: [f64; SEGMENT_SLOTS],
    q: [[f64; SEGMENT_SLOTS]; 3],
    /// Whether the row's joint values are within the limits as they are.
    as_is: [bool; SEGMENT_SLOTS],
    /// `j as f64` per row `j` (loaded with the other arrays instead of converted per row).
    index: [f64; SEGMENT_SLOTS],
    /// The rows themselves, appended to the scan's with one copy.
    block: [ScanRow; SCAN_ANCHOR_ROWS],
}

impl ScanSegment {
    /// Appends rows `1 .. n` of the segment (`n` returned by [`Self::fill`]) to `rows`: the
    /// rows `arm.finish_row(α_min + (i + j)·Δ, β_j, γ1_j + γ2)` gives, bit for bit, for
    /// `[α_min, i, Δ] = alpha_grid` (`i` as a float: `i + j` is exact).
    #[allow(
        clippy::needless_range_loop,
        reason = "the passes index several arrays by the same row: the form that vectorises"
    )]
    #[inline(always)]
    fn finish(&mut self, arm: &PlanarRedundant, gamma2: f64, alpha_grid: [f64; 3], n: usize, rows: &mut Vec<ScanRow>) {
        let [alpha_min, first, step] = alpha_grid;
        let out = &mut self.rows;
        // Pass 4: each row's angles, joint values and whether they fit as they are; whether
        // any row bends back at B (`finish_row` gives no row there).
        let mut bent_back = false;
        for j in 1..SEGMENT_SLOTS {
            let alpha = alpha_min + (first + out.index[j]) * step;
            let beta = self.beta[j];
            bent_back |= (beta > PI * (1.0 + BOUNDARY)) & (j < n);
            let beta = beta.min(PI);
            let gamma = self.gamma1[j] + gamma2;
            let q = arm.row_joints(alpha, beta, gamma);
            [out.alpha[j], out.beta[j], out.gamma[j]] = [alpha, beta, gamma];
            [out.q[0][j], out.q[1][j], out.q[2][j]] = q;
            out.as_is[j] = arm.fits_as_is(&q);
        }
        // The rows, the fit into the limits taken only where the values do not fit as they are
        // (slot `k` of the block is row `k + 1`).
        let out = &mut self.rows;
        let m = n - 1;
        let fields = (&out.alpha[1..n], &out.beta[1..n], &out.gamma[1..n], &out.as_is[1..n]);
        let q = [&out.q[0][1..n], &out.q[1][1..n], &out.q[2][1..n]];
        for (k, row) in out.block[..m].iter_mut().enumerate() {
            let raw = [q[0][k], q[1][k], q[2][k]];
            let (q, within_limits) = if fields.3[k] { (raw, true) } else { arm.fit_row(raw) };
            *row = ScanRow {
                paper: InteriorAngles { alpha: fields.0[k], beta: fields.1[k], gamma: fields.2[k] },
                q,
                within_limits,
            };
        }
        let block = &out.block[..m];
        if bent_back {
            // The rows `finish_row` keeps (`β` of a decided row is not NaN).
            let keep = |(_, beta): &(&ScanRow, &f64)| **beta <= PI * (1.0 + BOUNDARY);
            rows.extend(block.iter().zip(&self.beta[1..n]).filter(keep).map(|(row, _)| *row));
        } else {
            rows.extend_from_slice(block);
        }
    }
}

/// `cross(a, b)` and `dot(a, b)` of two plane vectors.
#[inline(always)]
fn cross_dot(a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    (a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1])
}

/// Planar two-link IK: links `l1, l2` from the origin to the point `w`. `seed_phi1` is the
/// first link's angle used when it is undetermined (`w` on the shoulder axis, `l1 = l2`).
pub(crate) fn two_link(l1: f64, l2: f64, w: [f64; 2], seed_phi1: f64) -> TwoLink {
    let r2 = w[0] * w[0] + w[1] * w[1];
    let r = r2.sqrt();
    let c = (r2 - l1 * l1 - l2 * l2) / (2.0 * l1 * l2);
    if c > 1.0 + BOUNDARY {
        return TwoLink::Out { distance: r, reach: l1 + l2 };
    }
    if c < -1.0 - BOUNDARY {
        return TwoLink::Out { distance: r, reach: (l1 - l2).abs() };
    }
    if r <= IK_AXIS_DISTANCE {
        // Folded with l1 = l2: the wrist is on the shoulder axis and φ1 is free.
        let e = Elbow { phi: [seed_phi1, seed_phi1 + PI], bend: PI, singular: Some(SingularityKind::Shoulder) };
        return TwoLink::In([Some(e), None]);
    }
    let base = w[1].atan2(w[0]);
    let solve = |bend: f64, singular: Option<SingularityKind>| {
        let phi1 = base - (l2 * bend.sin()).atan2(l1 + l2 * bend.cos());
        Elbow { phi: [phi1, phi1 + bend], bend, singular }
    };
    // Bend angle by the half-angle form tan²(e/2) = ((l1+l2)² − r²)/(r² − (l1−l2)²): full
    // precision near 0 and π, where acos(c) keeps only half the digits (an exactly stretched
    // or folded arm gives e = 0 or π and one solution).
    let (sum, diff) = (l1 + l2, (l1 - l2).abs());
    let e = 2.0 * ((sum - r) * (sum + r)).max(0.0).sqrt().atan2(((r - diff) * (r + diff)).max(0.0).sqrt());
    let singular = (c.abs() >= 1.0 - BOUNDARY).then_some(SingularityKind::Elbow);
    // Branches closer than IK_DUPLICATE are one solution (`finish` would merge them): report
    // it exactly stretched or folded. (Not for a folded equal-link arm: there the snap would
    // move the wrist by |w| onto the shoulder axis.)
    if e <= IK_DUPLICATE / 2.0 {
        return TwoLink::In([Some(solve(0.0, singular)), None]);
    }
    if PI - e <= IK_DUPLICATE / 2.0 && diff > STRUCTURE_LENGTH {
        return TwoLink::In([Some(solve(PI, singular)), None]);
    }
    TwoLink::In([Some(solve(-e, singular)), Some(solve(e, singular))])
}

/// A closed interval of the redundancy parameter `φ` (radians, `start ≤ end`; the values are
/// not wrapped, an interval may cross ±π).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhiInterval {
    /// Lower end.
    pub start: f64,
    /// Upper end.
    pub end: f64,
}

impl PhiInterval {
    /// Width, radians.
    #[must_use]
    pub fn width(&self) -> f64 {
        self.end - self.start
    }
}

/// The angles `φ` of the last link (length `l3`) for which a two-link arm `l1, l2` at the
/// origin reaches the wrist `p − l3·(cos φ, sin φ)`: at most two intervals, or one full turn.
pub(crate) fn phi_intervals(l1: f64, l2: f64, l3: f64, p: [f64; 2]) -> Vec<PhiInterval> {
    let r = p[0].hypot(p[1]);
    let (outer, inner) = (l1 + l2, (l1 - l2).abs());
    let inside = |d: f64| d <= outer * (1.0 + BOUNDARY) && d >= inner * (1.0 - BOUNDARY);
    let psi = p[1].atan2(p[0]);
    let full = vec![PhiInterval { start: psi - PI, end: psi + PI }];
    if l3 <= STRUCTURE_LENGTH {
        return if inside(r) { full } else { Vec::new() };
    }
    if r <= IK_AXIS_DISTANCE {
        return if inside(l3) { full } else { Vec::new() };
    }
    // |W|² = r² + l3² − 2·r·l3·cos ω, ω = φ − ψ; inner² ≤ |W|² ≤ outer².
    let c_lo = (r * r + l3 * l3 - outer * outer) / (2.0 * r * l3);
    let c_hi = (r * r + l3 * l3 - inner * inner) / (2.0 * r * l3);
    if c_lo > 1.0 + BOUNDARY || c_hi < -1.0 - BOUNDARY {
        return Vec::new();
    }
    let w_max = c_lo.clamp(-1.0, 1.0).acos();
    let w_min = c_hi.clamp(-1.0, 1.0).acos();
    if w_min > w_max {
        return Vec::new();
    }
    match (w_min <= 0.0, w_max >= PI) {
        (true, true) => full,
        (true, false) => vec![PhiInterval { start: psi - w_max, end: psi + w_max }],
        (false, true) => vec![PhiInterval { start: psi + w_min, end: psi + TAU - w_min }],
        (false, false) => vec![
            PhiInterval { start: psi - w_max, end: psi - w_min },
            PhiInterval { start: psi + w_min, end: psi + w_max },
        ],
    }
}

/// Sample values of `intervals`, spaced at most `step`, both ends included (a full turn
/// without repeating its end).
pub(crate) fn sample_intervals(intervals: &[PhiInterval], step: f64) -> Vec<f64> {
    let mut out = Vec::new();
    for iv in intervals {
        let width = iv.width();
        let full_turn = width >= TAU * (1.0 - BOUNDARY);
        // Bounded by MAX_SELF_MOTION_SAMPLES through `check_options`.
        let n = (width / step).ceil().max(0.0) as usize;
        if n == 0 {
            out.push(iv.start);
            continue;
        }
        let last = if full_turn { n - 1 } else { n };
        out.extend((0..=last).map(|k| iv.start + width * (k as f64) / (n as f64)));
    }
    out
}

/// Validates the options shared by the planar and yaw solvers.
pub(crate) fn check_options(robot: &Robot, options: &IkOptions) -> Result<(), IkError> {
    if let Some(seed) = &options.seed {
        if seed.len() != robot.dof() {
            return Err(KinematicsError::JointCount { expected: robot.dof(), found: seed.len() }.into());
        }
        if let Some((i, &v)) = seed.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(KinematicsError::NonFinite { joint: i + 1, value: v }.into());
        }
    }
    if let Some(phi) = options.free_parameter
        && !phi.is_finite()
    {
        return Err(IkError::InvalidInput(format!("free_parameter must be finite, got {phi}")));
    }
    Ok(())
}

/// Validates [`IkOptions::redundancy_step`] before the self-motion is sampled.
pub(crate) fn check_step(options: &IkOptions) -> Result<(), IkError> {
    let step = options.redundancy_step;
    let min_step = TAU / MAX_SELF_MOTION_SAMPLES as f64;
    if !(step.is_finite() && step >= min_step * (1.0 - BOUNDARY)) {
        return Err(IkError::InvalidInput(format!(
            "redundancy_step must be a finite angle of at least {:.3}° ({MAX_SELF_MOTION_SAMPLES} samples per turn), got {step} rad",
            min_step.to_degrees()
        )));
    }
    Ok(())
}

/// Label value of the elbow: `up` when link 2 turns clockwise from link 1 as seen with the arm
/// reaching to the right (`reach_sign` = −1 mirrors it), `down` otherwise, `stretched` /
/// `folded` for the single solution at the workspace boundary.
pub(crate) fn elbow_label(e: &Elbow, reach_sign: f64) -> &'static str {
    if e.bend == 0.0 {
        "stretched"
    } else if e.bend.abs() == PI {
        "folded"
    } else if reach_sign * e.bend < 0.0 {
        "up"
    } else {
        "down"
    }
}

/// Label value of the redundancy parameter, degrees.
pub(crate) fn phi_label(phi: f64) -> String {
    format!("{:.4}", crate::angle::wrap(phi).to_degrees())
}

// ---------------------------------------------------------------------------------------------
// The planar solver.
// ---------------------------------------------------------------------------------------------

/// Closed-form IK of a planar arm of three parallel revolute joints (seed 000, `planar3`),
/// with its self-motion parameterised by the absolute angle of the last link.
///
/// * [`IkTarget::Pose`]: position in the arm's plane and the in-plane heading of the tool
///   (the target orientation must be the tool's orientation turned about the plane normal):
///   up to two solutions, `elbow=up` / `elbow=down`.
/// * [`IkTarget::Position`]: with [`IkOptions::free_parameter`] `= Some(φ)` the (up to two)
///   solutions whose last link points at `φ`; otherwise the self-motion sampled at
///   [`IkOptions::redundancy_step`] over its feasible intervals, both branches, each labelled
///   `phi_deg=… elbow=…`.
///
/// Failure reasons: `Unreachable` (outside the annulus, with the violated radius; or off the
/// arm's plane, with `distance` = the offset and `reach` = 0), `OrientationUnreachable` (the
/// position is reachable but not with the requested heading or `φ`), `OutsideLimits`.
/// Singular flags: `elbow` (links 1 and 2 within `acos(1 − BOUNDARY)` ≈ 2.6e-3° of aligned,
/// e.g. at the ends of the feasible `φ` intervals: exactly there one solution labelled
/// `elbow=stretched` or `elbow=folded`, near there both exact branches), `shoulder` (wrist on
/// the joint-1 axis with `l1 = l2`: φ1 is free and taken from the seed, else 0).
///
/// Sampled self-motions contain every sample, within limits or not (flagged by
/// [`IkSolution::within_limits`](super::IkSolution::within_limits)); the step must allow at
/// most [`MAX_SELF_MOTION_SAMPLES`] samples per turn.
#[derive(Debug, Clone)]
pub struct PlanarRedundant {
    chain: PlanarChain<3>,
    first: IsometryMatrix3<f64>,
    limits: [Limits; 3],
}

impl PlanarRedundant {
    /// Reads the arm from `robot`: three revolute joints, axes 2 and 3 parallel to axis 1 and
    /// pointing the same way, links 1 and 2 of non-zero length (link 3 may be zero).
    ///
    /// # Errors
    /// [`IkError::Unsupported`] naming the failed condition.
    pub fn from_robot(robot: &Robot) -> Result<Self, IkError> {
        let unsupported =
            |reason: String| IkError::Unsupported { solver: NAME, robot: robot.name().to_string(), reason };
        if robot.dof() != 3 {
            return Err(unsupported(format!("needs exactly 3 joints, the robot has {}", robot.dof())));
        }
        if robot.chain.has_mimics() {
            return Err(unsupported("the chain has mimic joints".into()));
        }
        let chain = PlanarChain::<3>::from_chain(&robot.chain.links, 1).map_err(unsupported)?;
        for (i, l) in chain.links.iter().take(2).enumerate() {
            if l.length <= STRUCTURE_LENGTH {
                return Err(unsupported(format!("link {} has zero length in the plane", i + 1)));
            }
        }
        let j = robot.joints();
        Ok(PlanarRedundant { chain, first: robot.chain.first, limits: [j[0].limits, j[1].limits, j[2].limits] })
    }

    /// Link lengths `[l1, l2, l3]` (metres).
    #[must_use]
    pub fn lengths(&self) -> [f64; 3] {
        self.chain.lengths()
    }

    /// Inner and outer radius of the workspace annulus: `max(0, l_max − (sum of the others))`
    /// and `l1 + l2 + l3` (joint limits ignored).
    #[must_use]
    pub fn workspace(&self) -> (f64, f64) {
        let l = self.lengths();
        let sum = l[0] + l[1] + l[2];
        let max = l[0].max(l[1]).max(l[2]);
        ((2.0 * max - sum).max(0.0), sum)
    }

    /// Coordinates of a world point in the plane frame: `(x, y, offset)`, the offset being the
    /// signed distance from the arm's plane.
    #[must_use]
    pub fn plane_coordinates(&self, world: &Point3<f64>) -> (f64, f64, f64) {
        let p = self.first.inverse_transform_point(world);
        (p.x, p.y, p.z - self.chain.height)
    }

    /// Absolute link angles `[φ1, φ2, φ3]` (plane frame) of joint values `q` (3 values).
    #[must_use]
    pub fn link_angles(&self, q: &[f64; 3]) -> [f64; 3] {
        self.chain.link_angles(q)
    }

    /// Joint values (not wrapped) giving the absolute link angles `phi`.
    #[must_use]
    pub fn joints_from_link_angles(&self, phi: &[f64; 3]) -> [f64; 3] {
        self.chain.joints(phi)
    }

    /// The feasible intervals of `φ` (absolute angle of the last link) for a target given in
    /// plane coordinates, joint limits ignored: empty outside the workspace annulus, one full
    /// turn when every `φ` works, else one or two intervals symmetric about the target's
    /// direction. At interval ends the elbow is stretched or folded.
    #[must_use]
    pub fn feasible_intervals(&self, target_xy: [f64; 2]) -> Vec<PhiInterval> {
        let [l1, l2, l3] = self.lengths();
        phi_intervals(l1, l2, l3, target_xy)
    }

    fn unreachable(&self, p: [f64; 2]) -> Option<IkFailure> {
        let r = p[0].hypot(p[1]);
        let (inner, outer) = self.workspace();
        if r > outer * (1.0 + BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: outer, point: "the target", from: "joint 1" })
        } else if r < inner * (1.0 - BOUNDARY) {
            Some(IkFailure::Unreachable { distance: r, reach: inner, point: "the target", from: "joint 1" })
        } else {
            None
        }
    }

    /// The (≤ 2) candidates whose last link points at `phi`.
    fn at_phi(&self, p: [f64; 2], phi: f64, seed_phi1: f64, label_phi: bool, out: &mut Vec<Candidate>) {
        let [l1, l2, l3] = self.lengths();
        let w = [p[0] - l3 * phi.cos(), p[1] - l3 * phi.sin()];
        let TwoLink::In(sols) = two_link(l1, l2, w, seed_phi1) else { return };
        for e in sols.into_iter().flatten() {
            let q = self.chain.joints(&[e.phi[0], e.phi[1], phi]);
            let mut pairs = Vec::with_capacity(2);
            if label_phi {
                pairs.push(("phi_deg", phi_label(phi)));
            }
            pairs.push(("elbow", elbow_label(&e, 1.0).to_string()));
            let mut c = Candidate::new(q.to_vec(), Branch::new(pairs));
            if let Some(k) = e.singular {
                c.singularities.push(k);
            }
            out.push(c);
        }
    }

    /// One row of the thesis's table (notes 000 §3.1, eqs. 6–14, generalised to unequal
    /// lengths) for the interior angle `alpha` at joint A; `None` where a triangle of the
    /// construction does not exist or the chain would bend counter-clockwise at B (β > 180°).
    ///
    /// `target_xy` is in plane coordinates. The row's `q` are this robot's joint values,
    /// wrapped (or moved by whole turns) into the joint ranges when possible.
    #[must_use]
    pub fn paper_row(&self, target_xy: [f64; 2], alpha: f64) -> Option<ScanRow> {
        let [x, y] = target_xy;
        let r = (x * x + y * y).sqrt();
        // Eqs. (7)–(8), corrected (notes 000 §6.1 D1): γ2 = atan2(y, x), not atan(x/y).
        self.paper_row_at(r, y.atan2(x), alpha)
    }

    /// [`Self::paper_row`] with the target's per-scan quantities precomputed: its distance `r`
    /// from the base and its direction `γ2 = atan2(y, x)`.
    fn paper_row_at(&self, r: f64, gamma2: f64, alpha: f64) -> Option<ScanRow> {
        self.paper_row_angles(r, alpha, alpha.sin_cos())
            .and_then(|(gamma1, beta)| self.finish_row(alpha, beta, gamma1 + gamma2))
    }

    /// The row's `γ1` (angle KOB) and `β = β1 + β2` (not clamped) at `α`, given `(sin α, cos α)`.
    fn paper_row_angles(&self, r: f64, alpha: f64, (sin_alpha, cos_alpha): (f64, f64)) -> Option<(f64, f64)> {
        let [l1, l2, l3] = self.lengths();
        if !(alpha.is_finite() && r > IK_AXIS_DISTANCE) || l3 <= STRUCTURE_LENGTH {
            return None;
        }
        // Eq. (4): KB² in triangle ABK (AB = l2, AK = l3, angle α at A).
        let kb2 = l2 * l2 + l3 * l3 - 2.0 * l2 * l3 * cos_alpha;
        let kb = kb2.sqrt();
        if kb <= IK_AXIS_DISTANCE {
            return None;
        }
        // The law-of-cosines angles are evaluated in a stable form (`triangle_angle`): the
        // same values as the printed acos expressions, without their loss of precision near
        // 0° and 180° (β1 → 180° at α_min, β2 → 0° at α = 180°).
        // Eqs. (5)–(6): γ1 = angle KOB in triangle OBK (sides OK = r, OB = l1, KB), i.e.
        // triangle_angle(r, l1, kb); eqs. (11)–(12): β1 = angle OBK (sides BK, BO = l1,
        // opposite OK = r), i.e. triangle_angle(kb, l1, r). One call gives both.
        let (gamma1, beta1) = triangle_angle_pair(kb, l1, r)?;
        // Eq. (13): β2 = angle ABK; (180° − α)/2 for l2 = l3, in general
        // atan2(l3·sin α, l2 − l3·cos α).
        let beta2 = (l3 * sin_alpha).atan2(l2 - l3 * cos_alpha);
        Some((gamma1, beta1 + beta2))
    }

    /// The row of angles `α`, `β` (before the clamp; `None` above 180°) and `γ`.
    #[inline(always)]
    fn finish_row(&self, alpha: f64, beta: f64, gamma: f64) -> Option<ScanRow> {
        if beta > PI * (1.0 + BOUNDARY) {
            return None;
        }
        let beta = beta.min(PI);
        let (q, within_limits) = self.fit_row(self.row_joints(alpha, beta, gamma));
        Some(ScanRow { paper: InteriorAngles { alpha, beta, gamma }, q, within_limits })
    }

    /// The joint values (not fitted into the limits) of the row `α`, `β` (clamped to 180°), `γ`.
    #[inline(always)]
    fn row_joints(&self, alpha: f64, beta: f64, gamma: f64) -> [f64; 3] {
        let phi1 = gamma;
        let phi2 = phi1 + beta - PI;
        let phi3 = phi2 + alpha - PI;
        self.chain.joints(&[phi1, phi2, phi3])
    }

    /// A row's joint values fitted into the limits ([`fit_revolute`]) and whether they are
    /// within them.
    #[inline(always)]
    fn fit_row(&self, raw: [f64; 3]) -> ([f64; 3], bool) {
        let mut q = [0.0; 3];
        let mut within_limits = true;
        for i in 0..3 {
            q[i] = fit_revolute(raw[i], &self.limits[i]);
            within_limits &= self.limits[i].contains(q[i], LIMIT_SLACK);
        }
        (q, within_limits)
    }

    /// Whether [`Self::fit_row`] gives `(raw, true)`: every value in (−π, π]
    /// ([`crate::angle::is_wrapped`]: `wrap`, the first step of [`fit_revolute`], leaves it as it is) and within its limits (which
    /// [`fit_revolute`] then returns). Branch-free, for the scan's row passes.
    #[inline(always)]
    fn fits_as_is(&self, raw: &[f64; 3]) -> bool {
        raw.iter()
            .zip(&self.limits)
            .fold(true, |all, (&v, limits)| all & crate::angle::is_wrapped(v) & limits.contains(v, LIMIT_SLACK))
    }

    /// Row `index` computed directly, and the track it starts (when its triangles are well
    /// conditioned).
    fn direct_row(&self, frame: &ScanFrame, alpha: f64) -> (Option<ScanRow>, Option<Track>) {
        let trig = alpha.sin_cos();
        let Some((gamma1, beta)) = self.paper_row_angles(frame.r, alpha, trig) else { return (None, None) };
        let row = self.finish_row(alpha, beta, gamma1 + frame.gamma2);
        let track = frame.vectors(trig).map(|(g, b)| Track { trig, gamma1, g, beta, b });
        (row, track)
    }

    #[cfg(test)]
    /// `γ1` and `β` of the row `j` rows after the track's anchor, the track moved to it.
    #[inline]
    fn incremental_row(frame: &ScanFrame, steps: &RotationSteps, track: &mut Track, j: usize) -> Incremental {
        let Some((g, b)) = frame.vectors(steps.turn(track.trig, j)) else { return Incremental::Direct };
        let (cross_g, dot_g) = cross_dot(track.g, g);
        let (cross_b, dot_b) = cross_dot(track.b, b);
        // Both turns from the previous row small: |tan| ≤ SCAN_MAX_TAN, forward (dot > 0).
        if !(small_turn(cross_g, dot_g) && small_turn(cross_b, dot_b)) {
            return Incremental::Direct;
        }
        // One division for both tangents.
        let inverse = 1.0 / (dot_g * dot_b);
        let gamma1 = track.gamma1 + atan_small(cross_g * dot_b * inverse);
        let beta = track.beta + atan_small(cross_b * dot_g * inverse);
        // Whether the chain bends back at B (β > 180°) is decided only with a margin far above
        // the increments' error; near the limit the row is computed directly.
        if (beta - PI * (1.0 + BOUNDARY)).abs() <= SCAN_DECISION_MARGIN {
            return Incremental::Direct;
        }
        *track = Track { gamma1, g, beta, b, ..*track };
        Incremental::Angles(gamma1, beta)
    }

    /// The thesis's IK by enumeration (notes 000 §4.1): `α = α_min + i·step`, `i = 0, 1, …`
    /// while `α ≤ 180°`, with `γ`, `β` per row from the corrected formulas.
    ///
    /// # Behavior
    /// * Workspace test as in the thesis, strict: `|l1 + l2 − l3| < r < l1 + l2 + l3` (for three
    ///   equal links `L < r < 3L`). A target outside gives an empty table and
    ///   `failure = Unreachable` with the violated bound (the thesis "waits for new input").
    /// * `α_min` is eq. (3), generalised: `acos(((l1 + l2)² + l3² − r²) / (2·(l1 + l2)·l3))`,
    ///   where `β = 180°`.
    /// * The last row is the largest grid value not above 180° (within [`SCAN_GRID`] of a
    ///   step), so the thesis's last row (α = 180°, notes 000 §5 Table 3, D3) is included
    ///   when the grid hits it.
    /// * Rows are not filtered by joint limits (the thesis does not, notes 000 §6.1 D11); each
    ///   row says whether it is within them. For unequal lengths rows where a triangle of the
    ///   construction does not exist are left out.
    /// * Most rows are evaluated incrementally from an exactly computed row a few steps back
    ///   (angle addition instead of fresh trigonometry); the rows are the direct formulas'
    ///   rows, each angle within 1e-12 rad of [`Self::paper_row`]'s.
    ///
    /// # Arguments
    /// * `target_xy` — target in plane coordinates (metres);
    /// * `step` — `Δα` in radians (thesis: 0.01°, P2012: 0.001°).
    ///
    /// # Errors
    /// [`IkError::InvalidInput`] for a non-finite target, a step that is not positive, or more
    /// than [`MAX_SCAN_ROWS`] rows.
    ///
    /// # Example
    /// ```
    /// use reach::ik::planar::PlanarRedundant;
    /// let arm = PlanarRedundant::from_robot(&reach::model::presets::get("planar3").unwrap()).unwrap();
    /// let scan = arm.paper_scan([2.0, 1.0], 0.01f64.to_radians()).unwrap();
    /// assert_eq!(scan.rows.len(), 9001); // α from 90° to 180°
    /// approx::assert_relative_eq!(scan.rows[9000].paper.gamma.to_degrees(), 90.0, epsilon = 1e-9);
    /// ```
    pub fn paper_scan(&self, target_xy: [f64; 2], step: f64) -> Result<PaperScan, IkError> {
        for (name, v) in [("x", target_xy[0]), ("y", target_xy[1])] {
            if !v.is_finite() {
                return Err(IkError::InvalidInput(format!("target {name} must be finite, got {v}")));
            }
        }
        if !(step.is_finite() && step > 0.0) {
            return Err(IkError::InvalidInput(format!("scan step must be a positive angle, got {step} rad")));
        }
        let [l1, l2, l3] = self.lengths();
        let r = target_xy[0].hypot(target_xy[1]);
        let (outer, inner) = (l1 + l2 + l3, (l1 + l2 - l3).abs());
        // Thesis §4.1 step 2: 3L > KO > L, strict.
        let failure = if r >= outer {
            Some(IkFailure::Unreachable { distance: r, reach: outer, point: "the target", from: "joint 1" })
        } else if r <= inner || l3 <= STRUCTURE_LENGTH {
            Some(IkFailure::Unreachable { distance: r, reach: inner, point: "the target", from: "joint 1" })
        } else {
            None
        };
        if let Some(failure) = failure {
            return Ok(PaperScan { alpha_min: None, rows: Vec::new(), failure: Some(failure) });
        }
        // Eq. (3), generalised to l1 + l2 ≠ 2·l3.
        let s = l1 + l2;
        let alpha_min = ((s * s + l3 * l3 - r * r) / (2.0 * s * l3)).clamp(-1.0, 1.0).acos();
        let count = ((PI - alpha_min) / step + SCAN_GRID).floor() + 1.0;
        if count > MAX_SCAN_ROWS as f64 {
            return Err(IkError::InvalidInput(format!(
                "scan step {step} rad gives {count} rows, more than {MAX_SCAN_ROWS}"
            )));
        }
        let count = count as usize;
        let frame = ScanFrame::new(self.lengths(), target_xy);
        let rows = self.scan_rows(&frame, alpha_min, step, count).0;
        Ok(PaperScan { alpha_min: Some(alpha_min), rows, failure: None })
    }

    /// The rows of [`Self::paper_scan`], and how many were computed directly (anchors and
    /// rows not decidable incrementally).
    ///
    /// A row computed directly (fresh `sin_cos` and `atan2`) is an *anchor*; the next rows,
    /// up to [`SCAN_ANCHOR_ROWS`] − 1 of them, are incremental:
    /// * `(sin α, cos α)` by angle addition from the anchor's and a table of `(sin jΔ, cos jΔ)`
    ///   ([`RotationSteps`]): no error carries from row to row;
    /// * the direction vectors of `γ1` (triangle OBK) and of `β = β1 + β2` from those
    ///   (one square root, no trigonometry);
    /// * `γ1` and `β` as the previous row's plus the turn of their direction vectors, `atan`
    ///   of a cross over a dot product ([`atan_small`]; one division for both).
    ///
    /// Drift bound: the vectors' own errors telescope (each row's turn is measured between
    /// two computed vectors, so the sum of the turns since the anchor is the last vector's
    /// direction minus the anchor's, up to the per-row rounding); what accumulates is, per
    /// row, the rounding of one addition (≤ ½ ulp of a value below 2π, 4.4e-16) and of the
    /// `atan` (truncation ≤ 6.2e-18, rounding ≤ 2 ulp of a turn below 1/64): at most
    /// 128 × 5e-16 ≈ 6.4e-14 rad before the next anchor, plus the last vector's direction
    /// error (ill-conditioned triangles are computed directly, [`SCAN_MIN_CONDITION`]) — well
    /// within 1e-12 rad (the tests measure it). A row whose triangles are ill conditioned,
    /// whose turn exceeds [`SCAN_MAX_TAN`] or whose `β` lies within [`SCAN_DECISION_MARGIN`]
    /// of the 180° limit is computed directly and becomes the next anchor, so the set of rows
    /// is the direct computation's.
    fn scan_rows(&self, frame: &ScanFrame, alpha_min: f64, step: f64, count: usize) -> (Vec<ScanRow>, usize) {
        self.scan_rows_at(simd::level(), frame, alpha_min, step, count)
    }

    /// [`Self::scan_rows`] compiled for the vector-instruction `level` (the same rows, bit for
    /// bit, at every level).
    fn scan_rows_at(
        &self,
        level: simd::Level,
        frame: &ScanFrame,
        alpha_min: f64,
        step: f64,
        count: usize,
    ) -> (Vec<ScanRow>, usize) {
        simd::run_at(level, ScanKernel { arm: self, frame, alpha_min, step, count })
    }

    /// The body of [`Self::scan_rows`], inlined into each level's [`ScanKernel`].
    #[inline(always)]
    fn scan_rows_inline(&self, frame: &ScanFrame, alpha_min: f64, step: f64, count: usize) -> (Vec<ScanRow>, usize) {
        let mut rows = Vec::with_capacity(count);
        let mut direct = 0;
        let steps = RotationSteps::new(step, count.min(SCAN_ANCHOR_ROWS));
        let mut segment = ScanSegment::new();
        // A local copy of the arm: its limits and link constants stay in registers (the
        // rows' stores cannot alias a local whose address does not escape).
        let arm = self.clone();
        // α_i = α_min + i·Δα (no accumulated sum; notes 000 §6).
        let alpha = |i: usize| alpha_min + (i as f64) * step;
        let mut i = 0;
        while i < count {
            // An anchor, then the rows its segment decides incrementally ([`ScanSegment`]);
            // the first row it does not decide is the next anchor.
            let (row, track) = self.direct_row(frame, alpha(i));
            direct += 1;
            rows.extend(row);
            let Some(track) = track else {
                i += 1;
                continue;
            };
            let decided = segment.fill(frame, &steps, &track, (count - i).min(SCAN_ANCHOR_ROWS));
            segment.finish(&arm, frame.gamma2, [alpha_min, i as f64, step], decided, &mut rows);
            i += decided;
        }
        (rows, direct)
    }

    /// The row-by-row form of [`Self::scan_rows`] (each incremental row waits for the
    /// previous one): the reference that [`ScanSegment`] reproduces bit for bit.
    #[cfg(test)]
    fn scan_rows_one_by_one(&self, frame: &ScanFrame, alpha_min: f64, step: f64, count: usize) -> Vec<ScanRow> {
        let mut rows = Vec::with_capacity(count);
        let steps = RotationSteps::new(step, count.min(SCAN_ANCHOR_ROWS));
        // The track and its anchor's row.
        let mut track: Option<(Track, usize)> = None;
        for i in 0..count {
            let alpha = alpha_min + (i as f64) * step;
            let next = match track.as_mut().filter(|(_, anchor)| i - *anchor < SCAN_ANCHOR_ROWS) {
                Some((t, anchor)) => Self::incremental_row(frame, &steps, t, i - *anchor),
                None => Incremental::Direct,
            };
            let row = match next {
                Incremental::Angles(gamma1, beta) => self.finish_row(alpha, beta, gamma1 + frame.gamma2),
                Incremental::Direct => {
                    let (row, next) = self.direct_row(frame, alpha);
                    track = next.map(|t| (t, i));
                    row
                }
            };
            rows.extend(row);
        }
        rows
    }
}

/// [`PlanarRedundant::scan_rows`] as a [`simd::Kernel`]: the segment passes compiled for each
/// vector-instruction level, dispatched once per scan.
struct ScanKernel<'a> {
    arm: &'a PlanarRedundant,
    frame: &'a ScanFrame,
    alpha_min: f64,
    step: f64,
    count: usize,
}

impl simd::Kernel for ScanKernel<'_> {
    type Output = (Vec<ScanRow>, usize);

    #[inline(always)]
    fn run(self) -> Self::Output {
        self.arm.scan_rows_inline(self.frame, self.alpha_min, self.step, self.count)
    }
}

/// One row of the thesis's configuration table (notes 000 §5 Table 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScanRow {
    /// The thesis's angles `α, β, γ` (radians; `γ` not wrapped, it may leave [0, π], D11).
    pub paper: InteriorAngles,
    /// The robot's joint values for this row.
    pub q: [f64; 3],
    /// Whether `q` is within the robot's joint limits.
    pub within_limits: bool,
}

/// The thesis's configuration table for one target.
#[derive(Debug, Clone, PartialEq)]
pub struct PaperScan {
    /// `α_min` (radians), where `β = 180°`; `None` when the target failed the workspace test.
    pub alpha_min: Option<f64>,
    /// The rows, `α` increasing.
    pub rows: Vec<ScanRow>,
    /// Why the table is empty.
    pub failure: Option<IkFailure>,
}

impl PaperScan {
    /// The row with the least total joint change from `current` (notes 000 §4.1 step 5, §6.3):
    /// `S = |α − α0| + |β − β0| + |γ − γ0|` (radians, no wrapping, as in the thesis); the first
    /// minimum wins. Returns the row index and `S`.
    #[must_use]
    pub fn select_min_s(&self, current: &InteriorAngles) -> Option<(usize, f64)> {
        let mut best: Option<(usize, f64)> = None;
        for (i, row) in self.rows.iter().enumerate() {
            let p = &row.paper;
            let s = (p.alpha - current.alpha).abs() + (p.beta - current.beta).abs() + (p.gamma - current.gamma).abs();
            if best.is_none_or(|(_, b)| s < b) {
                best = Some((i, s));
            }
        }
        best
    }
}

impl IkSolver for PlanarRedundant {
    fn name(&self) -> &'static str {
        NAME
    }

    fn solve(&self, robot: &Robot, target: &IkTarget, options: &IkOptions) -> Result<IkSolutions, IkError> {
        target.validate()?;
        check_options(robot, options)?;
        let (x, y, offset) = self.plane_coordinates(&target.position());
        if offset.abs() > IK_POSITION {
            let failure = IkFailure::Unreachable {
                distance: offset.abs(),
                reach: 0.0,
                point: "the target",
                from: "the arm's plane",
            };
            return finish(robot, target, &mut [], NAME, failure);
        }
        let p = [x, y];
        let seed_phi1 = options.seed.as_ref().map_or(0.0, |s| self.chain.link_angles(s)[0]);
        let mut candidates = Vec::new();
        match target {
            IkTarget::Pose(pose) => {
                // Rz(Θ)·R_last = R_local, with Θ the rotation of the last joint's frame.
                let r_local = self.first.rotation.inverse() * pose.rotation.to_rotation_matrix();
                let m = r_local * self.chain.last_rotation.inverse();
                let phi = self.chain.heading_to_last_angle(m[(1, 0)].atan2(m[(0, 0)]));
                self.at_phi(p, phi, seed_phi1, false, &mut candidates);
            }
            IkTarget::Position(_) => match options.free_parameter {
                Some(phi) => self.at_phi(p, phi, seed_phi1, true, &mut candidates),
                None => {
                    check_step(options)?;
                    for phi in sample_intervals(&self.feasible_intervals(p), options.redundancy_step) {
                        self.at_phi(p, phi, seed_phi1, true, &mut candidates);
                    }
                }
            },
        }
        let if_empty = self.unreachable(p).unwrap_or(IkFailure::OrientationUnreachable);
        finish(robot, target, &mut candidates, NAME, if_empty)
    }

    /// The two elbows, `elbow=up` first (the bend `−e` of `two_link`, the order of
    /// [`IkSolver::solve`]). With a position target the labels also carry the sampled
    /// redundancy parameter (`phi_deg=…`), which these filters leave free.
    fn configurations(&self, _robot: &Robot) -> Vec<Branch> {
        ["up", "down"].into_iter().map(|e| Branch::new([("elbow", e)])).collect()
    }

    /// `false`: the labels of a position target carry the sampled redundancy parameter, which
    /// changes from one target to the next, so a path is followed by nearness.
    fn enumerates_all_branches(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::presets;

    #[test]
    fn triangle_angle_pair_is_two_triangle_angles_bit_for_bit() {
        // A deterministic spread of side triples: generic, isoceles, degenerate, invalid.
        let mut sides = vec![[1.0, 1.0, 1.0], [1.0, 1.0, 2.0], [1.0, 2.0, 3.5], [0.5, 1.0, 1.5], [2.0, 1.0, 1.0]];
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        for _ in 0..2000 {
            let mut side = || {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                0.01 + 3.0 * (state >> 11) as f64 / (1u64 << 53) as f64
            };
            sides.push([side(), side(), side()]);
        }
        let mut valid = 0;
        for [a, b, c] in sides {
            let expected = triangle_angle(c, b, a).zip(triangle_angle(a, b, c));
            let got = triangle_angle_pair(a, b, c);
            assert_eq!(
                got.map(|(x, y)| (x.to_bits(), y.to_bits())),
                expected.map(|(x, y)| (x.to_bits(), y.to_bits())),
                "sides {a} {b} {c}"
            );
            valid += usize::from(got.is_some());
        }
        assert!(valid > 500 && valid < 2000, "{valid} valid triangles: the sample misses a case");
    }

    #[test]
    fn rotation_steps_stay_within_a_few_ulps_of_fresh_trigonometry() {
        // Angle addition from each anchor: no error accumulates over the table's rows.
        let mut worst = 0.0f64;
        for step_deg in [0.01f64, 0.001, 0.37, 1.0] {
            let step = step_deg.to_radians();
            let steps = RotationSteps::new(step, SCAN_ANCHOR_ROWS);
            for start in [0.3, 1.2, 2.0, 3.0] {
                for a in [0, 7, 1000] {
                    let anchor = start + (a as f64) * step;
                    let trig = anchor.sin_cos();
                    for j in 0..SCAN_ANCHOR_ROWS {
                        let (s, c) = steps.turn(trig, j);
                        let exact = (start + ((a + j) as f64) * step).sin_cos();
                        worst = worst.max((s - exact.0).abs()).max((c - exact.1).abs());
                    }
                }
            }
        }
        // A few units in the last place of the angles (up to ≈ 20 rad here: ulp 3.6e-15),
        // whatever the distance from the anchor; the scan needs 1e-12.
        assert!(worst < 1e-14, "drift {worst:e}");
    }

    #[test]
    fn atan_small_is_atan() {
        for k in -1000..=1000 {
            let t = SCAN_MAX_TAN * f64::from(k) / 1000.0;
            let (got, exact) = (atan_small(t), t.atan());
            // Rounding (2 ulp) and the truncation bound |t|⁹/9.
            let bound = 2.0 * f64::EPSILON * exact.abs() + t.abs().powi(9) / 9.0;
            assert!((got - exact).abs() <= bound, "{t}: {got} vs {exact}");
        }
    }

    /// The incremental scan gives the direct formulas' rows (same α, same set) with every
    /// angle within 1e-12 rad, on the thesis's arm and an unequal one, for targets across the
    /// workspace (near both circles, every quadrant) and several steps; most rows incremental.
    #[test]
    fn incremental_scan_rows_are_the_direct_rows() {
        let (equal, unequal) = equal_and_unequal_arms();
        let mut worst = 0.0f64;
        for (arm, targets) in [
            (&equal, [[2.0, 1.0], [2.4, 0.2], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4]]),
            (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [2.6, 0.1], [0.7, 0.0]]),
        ] {
            for target in targets {
                for step_deg in [0.01, 0.003, 0.1, 1.0] {
                    let step = f64::to_radians(step_deg);
                    let scan = arm.paper_scan(target, step).unwrap();
                    let Some(alpha_min) = scan.alpha_min else { continue };
                    let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                    let [x, y] = target;
                    let (r, gamma2) = ((x * x + y * y).sqrt(), y.atan2(x));
                    let direct: Vec<ScanRow> =
                        (0..count).filter_map(|i| arm.paper_row_at(r, gamma2, alpha_min + (i as f64) * step)).collect();
                    assert_eq!(scan.rows.len(), direct.len(), "{target:?} at {step_deg}°");
                    for (a, b) in scan.rows.iter().zip(&direct) {
                        assert_eq!(a.paper.alpha.to_bits(), b.paper.alpha.to_bits());
                        assert_eq!(a.within_limits, b.within_limits, "{target:?} at {step_deg}°");
                        let d = [a.paper.beta - b.paper.beta, a.paper.gamma - b.paper.gamma]
                            .into_iter()
                            .chain(a.q.iter().zip(&b.q).map(|(u, v)| u - v))
                            .fold(0.0f64, |m, d| m.max(d.abs()));
                        assert!(d <= 1e-12, "{target:?} at {step_deg}° row α {}: {d:e}", a.paper.alpha);
                        worst = worst.max(d);
                    }
                }
            }
        }
        assert!(worst > 0.0, "no row was incremental");
        // At 0.01° nearly every row is incremental (an anchor every SCAN_ANCHOR_ROWS).
        let (_, arm) = arm();
        let scan = arm.paper_scan([2.0, 1.0], 0.01f64.to_radians()).unwrap();
        let alpha_min = scan.alpha_min.unwrap();
        let frame = ScanFrame::new(arm.lengths(), [2.0, 1.0]);
        let (rows, direct) = arm.scan_rows(&frame, alpha_min, 0.01f64.to_radians(), scan.rows.len());
        assert_eq!(rows.len(), 9001);
        eprintln!("incremental scan: largest difference {worst:e} rad; at 0.01° {direct} of 9001 rows direct");
        assert!(direct <= 9001 / SCAN_ANCHOR_ROWS + 5, "{direct} rows computed directly");
    }

    /// The segment kernel ([`ScanSegment`], pass by pass) gives the row-by-row increments'
    /// rows bit for bit, anchors and segment edges included: targets whose scans leave
    /// segments early (ill-conditioned triangles near the inner circle, large turns at coarse
    /// steps, β near 180°) and ones that never do, on equal and unequal arms.
    #[test]
    fn segment_kernel_is_the_row_by_row_increments() {
        let (equal, unequal) = equal_and_unequal_arms();
        let mut cut_short = 0;
        for (arm, targets) in [
            (&equal, [[2.0, 1.0], [2.4, 0.2], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4], [1e-3, 1.0]]),
            (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [2.6, 0.1], [0.7, 0.0], [0.5, 0.4]]),
        ] {
            for target in targets {
                for step_deg in [0.01, 0.003, 0.1, 0.7, 1.0, 3.0] {
                    let step = f64::to_radians(step_deg);
                    let Some(alpha_min) = arm.paper_scan(target, step).unwrap().alpha_min else { continue };
                    let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                    let frame = ScanFrame::new(arm.lengths(), target);
                    let (rows, direct) = arm.scan_rows(&frame, alpha_min, step, count);
                    let reference = arm.scan_rows_one_by_one(&frame, alpha_min, step, count);
                    assert_eq!(rows.len(), reference.len(), "{target:?} at {step_deg}°");
                    for (a, b) in rows.iter().zip(&reference) {
                        assert_eq!(row_bits(a), row_bits(b), "{target:?} at {step_deg}° row α {}", a.paper.alpha);
                    }
                    // Anchors beyond one per full segment: segments cut short.
                    cut_short += usize::from(direct > count.div_ceil(SCAN_ANCHOR_ROWS));
                }
            }
        }
        assert!(cut_short > 0, "no scan left a segment early");
    }

    /// The scan's kernel ([`ScanKernel`]) gives the same rows, bit for bit, and the same count
    /// of rows computed directly, at every vector-instruction level the processor has: scans
    /// with and without segments cut short, rows bent back and rows outside the limits.
    #[test]
    fn scan_rows_are_the_same_bits_at_every_simd_level() {
        let (equal, unequal) = equal_and_unequal_arms();
        let mut rows_compared = 0;
        for (arm, targets) in [
            (&equal, [[2.0, 1.0], [1.0, 0.1], [2.95, 0.1], [-1.5, 1.5], [0.3, -1.4], [1e-3, 1.0]]),
            (&unequal, [[1.5, 0.5], [2.5, -0.3], [0.2, 0.6], [-1.0, -1.2], [0.7, 0.0], [0.5, 0.4]]),
        ] {
            for target in targets {
                for step_deg in [0.01, 0.003, 0.1, 0.7, 3.0] {
                    let step = f64::to_radians(step_deg);
                    let Some(alpha_min) = arm.paper_scan(target, step).unwrap().alpha_min else { continue };
                    let count = ((PI - alpha_min) / step + SCAN_GRID).floor() as usize + 1;
                    let frame = ScanFrame::new(arm.lengths(), target);
                    let (reference, direct) = arm.scan_rows_at(simd::Level::Baseline, &frame, alpha_min, step, count);
                    for level in simd::levels() {
                        let (rows, level_direct) = arm.scan_rows_at(level, &frame, alpha_min, step, count);
                        let at = format!("{target:?} at {step_deg}°, level {}", level.name());
                        assert_eq!((rows.len(), level_direct), (reference.len(), direct), "{at}");
                        for (a, b) in rows.iter().zip(&reference) {
                            assert_eq!(row_bits(a), row_bits(b), "{at} row α {}", a.paper.alpha);
                        }
                        rows_compared += rows.len();
                    }
                }
            }
        }
        assert!(rows_compared > 100_000, "{rows_compared} rows compared");
    }

    /// A row's values as bits, to compare rows bit for bit.
    fn row_bits(r: &ScanRow) -> ([u64; 6], bool) {
        let p = [r.paper.alpha, r.paper.beta, r.paper.gamma, r.q[0], r.q[1], r.q[2]];
        (p.map(f64::to_bits), r.within_limits)
    }

    /// planar3's arm and one with unequal links (1.3, 0.8, 0.6) and planar3's limits.
    fn equal_and_unequal_arms() -> (PlanarRedundant, PlanarRedundant) {
        let (_, equal) = arm();
        let mut unequal = equal.clone();
        for (link, l) in unequal.chain.links.iter_mut().zip([1.3, 0.8, 0.6]) {
            link.length = l;
        }
        (equal, unequal)
    }

    /// Where the scan's branch-free test says a row's values fit as they are, the fit into the
    /// limits gives them back bit for bit, within the limits: at and around (−π, π]'s ends, the
    /// limits with their slack, whole turns away and NaN, on planar3's limits and others.
    #[test]
    fn fits_as_is_is_the_fit_leaving_the_values() {
        let (_, planar3) = arm();
        let mut other = planar3.clone();
        other.limits = [Limits::new(-3.5, 3.5), Limits::new(0.0, 6.0), Limits::UNLIMITED];
        let mut values = vec![f64::NAN, f64::INFINITY, -f64::INFINITY];
        for base in [0.0, PI, -PI, 3.5, -3.5, 6.0, PI + LIMIT_SLACK, -PI - LIMIT_SLACK, TAU, -TAU] {
            for k in -3i64..=3 {
                let v = base + k as f64 * 0.25;
                values.extend([v, v.next_up(), v.next_down(), v - LIMIT_SLACK, v + LIMIT_SLACK]);
            }
        }
        let (mut as_is, mut fitted) = (0, 0);
        for arm in [&planar3, &other] {
            for &a in &values {
                for &b in &values {
                    for c in [0.5, -0.5, a] {
                        let raw = [a, b, c];
                        if arm.fits_as_is(&raw) {
                            as_is += 1;
                            let (q, within) = arm.fit_row(raw);
                            assert_eq!(q.map(f64::to_bits), raw.map(f64::to_bits), "{raw:?}");
                            assert!(within, "{raw:?}");
                        } else {
                            fitted += 1;
                        }
                    }
                }
            }
        }
        assert!(as_is > 1000 && fitted > 1000, "{as_is} as is, {fitted} fitted: the sample misses a case");
    }

    fn arm() -> (Robot, PlanarRedundant) {
        let robot = presets::get("planar3").unwrap();
        let arm = PlanarRedundant::from_robot(&robot).unwrap();
        (robot, arm)
    }

    #[test]
    fn reads_the_preset() {
        let (_, arm) = arm();
        assert_eq!(arm.lengths(), [1.0, 1.0, 1.0]);
        assert_eq!(arm.workspace(), (0.0, 3.0));
        let q = [0.3, -0.4, 0.5];
        let phi = arm.link_angles(&q);
        assert!((phi[0] - 0.3).abs() < 1e-15 && (phi[1] + 0.1).abs() < 1e-15 && (phi[2] - 0.4).abs() < 1e-15);
        let back = arm.joints_from_link_angles(&phi);
        assert!(back.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-15));
    }

    #[test]
    fn rejects_other_structures() {
        for name in ["log-loader", "varan4", "puma560", "spbu6", "ur5", "panda", "welder6r"] {
            let robot = presets::get(name).unwrap();
            let err = PlanarRedundant::from_robot(&robot).unwrap_err();
            assert!(matches!(err, IkError::Unsupported { .. }), "{name}: {err}");
        }
        let err = PlanarRedundant::from_robot(&presets::get("log-loader").unwrap()).unwrap_err();
        assert!(err.to_string().contains("not parallel"), "{err}");
    }

    #[test]
    fn two_link_branches_and_boundaries() {
        // l1 = 2, l2 = 1 to (2, 1): elbow angles ±acos((5 − 4 − 1)/4) = ±90°.
        let TwoLink::In([Some(a), Some(b)]) = two_link(2.0, 1.0, [2.0, 1.0], 0.0) else { panic!() };
        for e in [a, b] {
            let x = 2.0 * e.phi[0].cos() + e.phi[1].cos();
            let y = 2.0 * e.phi[0].sin() + e.phi[1].sin();
            assert!((x - 2.0).abs() < 1e-12 && (y - 1.0).abs() < 1e-12);
            assert!((e.bend.abs() - PI / 2.0).abs() < 1e-12);
        }
        assert_eq!(two_link(2.0, 1.0, [3.5, 0.0], 0.0), TwoLink::Out { distance: 3.5, reach: 3.0 });
        assert_eq!(two_link(2.0, 1.0, [0.5, 0.0], 0.0), TwoLink::Out { distance: 0.5, reach: 1.0 });
        let TwoLink::In([Some(s), None]) = two_link(2.0, 1.0, [0.0, 3.0], 0.0) else { panic!() };
        assert_eq!(s.singular, Some(SingularityKind::Elbow));
        assert!((s.phi[0] - PI / 2.0).abs() < 1e-12 && s.bend == 0.0);
        let TwoLink::In([Some(f), None]) = two_link(1.0, 1.0, [0.0, 0.0], 0.7) else { panic!() };
        assert_eq!(f.singular, Some(SingularityKind::Shoulder));
        assert_eq!(f.phi[0], 0.7);
    }

    #[test]
    fn intervals_match_a_brute_force_scan() {
        for (l, p) in [
            ([1.0, 1.0, 1.0], [2.0, 1.0]),
            ([1.0, 1.0, 1.0], [0.3, 0.2]),
            ([2.0, 0.5, 1.0], [1.0, 0.4]),
            ([2.0, 0.5, 1.0], [3.2, -0.5]),
            ([0.5, 0.7, 2.0], [0.1, 0.0]),
            ([0.5, 0.7, 2.0], [2.9, 0.0]),
            ([1.0, 1.0, 3.0], [0.5, 0.5]),
        ] {
            let ivs = phi_intervals(l[0], l[1], l[2], p);
            for k in 0..3600 {
                let phi = -PI + (k as f64 + 0.5) * TAU / 3600.0;
                let w = [p[0] - l[2] * phi.cos(), p[1] - l[2] * phi.sin()];
                let d = w[0].hypot(w[1]);
                let feasible = d <= l[0] + l[1] && d >= (l[0] - l[1]).abs();
                let inside = ivs.iter().any(|iv| {
                    let t = iv.start + (phi - iv.start).rem_euclid(TAU);
                    t <= iv.end
                });
                assert_eq!(feasible, inside, "lengths {l:?} target {p:?} φ {phi}");
            }
        }
    }

    #[test]
    fn pose_target_gives_both_elbows() {
        let (robot, arm) = arm();
        let q = [0.4, -0.9, -0.6];
        let target = IkTarget::Pose(robot.fk(&q).unwrap());
        let sols = arm.solve(&robot, &target, &IkOptions::default()).unwrap();
        assert_eq!(sols.solutions.len(), 2);
        let up = sols.solutions.iter().find(|s| s.branch.get("elbow") == Some("up")).unwrap();
        assert!(up.q.iter().zip(&q).all(|(a, b)| (a - b).abs() < 1e-9), "{:?}", up.q);
    }

    #[test]
    fn bad_options_are_rejected() {
        let (robot, arm) = arm();
        let target = IkTarget::Position(Point3::new(2.0, 1.0, 0.0));
        let tiny = IkOptions { redundancy_step: 1e-6, ..IkOptions::default() };
        assert!(matches!(arm.solve(&robot, &target, &tiny), Err(IkError::InvalidInput(_))));
        // The step only matters when the self-motion is sampled.
        let fixed = IkOptions { free_parameter: Some(0.5), ..tiny };
        assert!(arm.solve(&robot, &target, &fixed).unwrap().solutions.len() == 2);
        let nan = IkOptions { free_parameter: Some(f64::NAN), ..IkOptions::default() };
        assert!(matches!(arm.solve(&robot, &target, &nan), Err(IkError::InvalidInput(_))));
        let seed = IkOptions { seed: Some(vec![0.0; 2]), ..IkOptions::default() };
        assert!(matches!(arm.solve(&robot, &target, &seed), Err(IkError::Kinematics(_))));
        assert!(matches!(arm.paper_scan([2.0, 1.0], 0.0), Err(IkError::InvalidInput(_))));
        assert!(matches!(arm.paper_scan([2.0, 1.0], 1e-9), Err(IkError::InvalidInput(_))));
    }

    #[test]
    fn configurations_are_the_two_elbows_in_the_order_of_the_solve() {
        use crate::ik::configuration_order::{check, labels};
        let robot = presets::get("planar3").unwrap();
        let s = PlanarRedundant::from_robot(&robot).unwrap();
        assert_eq!(labels(&s, &robot), ["elbow=up", "elbow=down"]);
        assert!(check(&s, &robot, 200) > 100);
        // Position targets label the sampled redundancy parameter: not one label per branch.
        assert!(!s.enumerates_all_branches());
    }
}
