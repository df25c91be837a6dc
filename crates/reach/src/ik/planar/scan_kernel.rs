//! The scan's incremental rows: anchors, angle-addition steps and structure-of-arrays
//! segments dispatched per vector-instruction level.

use std::f64::consts::PI;

use super::scan::*;
use super::*;
use crate::model::planar_angles::InteriorAngles;
use crate::simd;
use crate::tolerance::BOUNDARY;

/// Rows of [`PlanarRedundant::paper_scan`] from one directly computed *anchor* row to the
/// next (the others are incremental).
pub(super) const SCAN_ANCHOR_ROWS: usize = 128;

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
pub(super) const SCAN_MAX_TAN: f64 = 1.0 / 64.0;

/// `atan t` for `|t| ≤` [`SCAN_MAX_TAN`]: the Taylor series to `t⁷/7` (alternating: the
/// truncation error is below `|t|⁹/9` ≤ 6.2e-18 rad).
#[inline(always)]
pub(super) fn atan_small(t: f64) -> f64 {
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
pub(super) struct RotationSteps {
    /// `sin jΔ` and `cos jΔ` per slot `j` (`0` and `1` beyond the rows asked for).
    sin: [f64; SEGMENT_SLOTS],
    cos: [f64; SEGMENT_SLOTS],
}

impl RotationSteps {
    /// The rotations by `0, Δ, …, (rows − 1)·Δ` (at least; [`crate::angle::sin_cos`] of each,
    /// evaluated 8 at a time by [`crate::angle::sin_cos_lanes`], the same bits).
    pub(super) fn new(step: f64, rows: usize) -> Self {
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
    pub(super) fn turn(&self, (s, c): (f64, f64), j: usize) -> (f64, f64) {
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
pub(super) struct ScanFrame {
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
    pub(super) fn new(lengths: [f64; 3], [x, y]: [f64; 2]) -> Self {
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

impl PlanarRedundant {
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
    pub(super) fn scan_rows(
        &self,
        frame: &ScanFrame,
        alpha_min: f64,
        step: f64,
        count: usize,
    ) -> (Vec<ScanRow>, usize) {
        self.scan_rows_at(simd::level(), frame, alpha_min, step, count)
    }

    /// [`Self::scan_rows`] compiled for the vector-instruction `level` (the same rows, bit for
    /// bit, at every level).
    pub(super) fn scan_rows_at(
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
    pub(super) fn scan_rows_one_by_one(
        &self,
        frame: &ScanFrame,
        alpha_min: f64,
        step: f64,
        count: usize,
    ) -> Vec<ScanRow> {
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
