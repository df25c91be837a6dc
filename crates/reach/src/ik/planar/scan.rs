//! The thesis's α-scan (notes 000 §3.1, §4.1): the law-of-cosines rows, the configuration
//! table and its least-change selection.

use std::f64::consts::PI;

use super::scan_kernel::*;
use super::*;
use crate::ik::solution::fit_revolute;
use crate::ik::{IkError, IkFailure};
use crate::model::planar_angles::InteriorAngles;
use crate::tolerance::{BOUNDARY, IK_AXIS_DISTANCE, LIMIT_SLACK, SCAN_GRID, STRUCTURE_LENGTH};

/// The angle between sides `a` and `b` of a triangle whose third side is `c` (law of
/// cosines), `None` when the sides violate the triangle inequality by more than [`BOUNDARY`]
/// (relative). Evaluated as `atan2(4·area, a² + b² − c²)` with Kahan's stable Heron formula,
/// so that angles near 0 and π keep full precision (`acos` loses half the digits there).
///
/// The plain single-angle form, kept as the reference that [`triangle_angle_pair`] (used by
/// the scan) must reproduce bit for bit.
#[cfg(test)]
pub(super) fn triangle_angle(a: f64, b: f64, c: f64) -> Option<f64> {
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
pub(super) fn triangle_angle_pair(a: f64, b: f64, c: f64) -> Option<(f64, f64)> {
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

impl PlanarRedundant {
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
    pub(super) fn paper_row_at(&self, r: f64, gamma2: f64, alpha: f64) -> Option<ScanRow> {
        self.paper_row_angles(r, alpha, alpha.sin_cos())
            .and_then(|(gamma1, beta)| self.finish_row(alpha, beta, gamma1 + gamma2))
    }

    /// The row's `γ1` (angle KOB) and `β = β1 + β2` (not clamped) at `α`, given `(sin α, cos α)`.
    pub(super) fn paper_row_angles(
        &self,
        r: f64,
        alpha: f64,
        (sin_alpha, cos_alpha): (f64, f64),
    ) -> Option<(f64, f64)> {
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
    pub(super) fn finish_row(&self, alpha: f64, beta: f64, gamma: f64) -> Option<ScanRow> {
        if beta > PI * (1.0 + BOUNDARY) {
            return None;
        }
        let beta = beta.min(PI);
        let (q, within_limits) = self.fit_row(self.row_joints(alpha, beta, gamma));
        Some(ScanRow { paper: InteriorAngles { alpha, beta, gamma }, q, within_limits })
    }

    /// The joint values (not fitted into the limits) of the row `α`, `β` (clamped to 180°), `γ`.
    #[inline(always)]
    pub(super) fn row_joints(&self, alpha: f64, beta: f64, gamma: f64) -> [f64; 3] {
        let phi1 = gamma;
        let phi2 = phi1 + beta - PI;
        let phi3 = phi2 + alpha - PI;
        self.chain.joints(&[phi1, phi2, phi3])
    }

    /// A row's joint values fitted into the limits ([`fit_revolute`]) and whether they are
    /// within them.
    #[inline(always)]
    pub(super) fn fit_row(&self, raw: [f64; 3]) -> ([f64; 3], bool) {
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
    pub(super) fn fits_as_is(&self, raw: &[f64; 3]) -> bool {
        raw.iter()
            .zip(&self.limits)
            .fold(true, |all, (&v, limits)| all & crate::angle::is_wrapped(v) & limits.contains(v, LIMIT_SLACK))
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
