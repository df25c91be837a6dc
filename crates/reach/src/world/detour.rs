//! Seed 000: the planar obstacle test and detour (notes 000 §3.3–3.4, §4.3–4.4).
//!
//! A point obstacle `H` (from sensors) is tested against the area swept by the last link
//! `AK` between the current pose and the target pose — the quadrilateral `A K K1 A1` with the
//! arcs replaced by chords — and, here, also against the middle link's `B A A1 B1` and the
//! first link's `O B B1`. When it is inside, the gripper goes around it through two
//! waypoints `K2`, `K3` on a circle of radius `L/7` about `H`: `K → K2 → K3 → K1`, each leg
//! with the thesis's minimum-change IK, each leg re-checked.
//!
//! Corrections (notes 000 §6.1):
//! * D6/D7 — the printed test (eqs. 24–36) uses `k < 1` instead of `|k| < 1`, a fixed vertex
//!   order and slopes that divide by zero on vertical/horizontal lines. The default test is
//!   an orientation-free point-in-polygon (even–odd crossings with cross products; no slope,
//!   no division by a possibly-zero difference). The literal test is kept as
//!   [`SweepTest::PaperLiteral`] for comparison only.
//! * D5 — the printed `K2`/`K3` formulas (Table 6) are not perpendicular to `KH`; the default
//!   [`WaypointRule::Perpendicular`] puts `K2 = H ± (L/7)·R(90°)(K − H)/|K − H|` on the
//!   perpendicular at `H`, on the base side (the candidate nearer `O`).

use serde::Serialize;

use super::WorldError;
use super::distance::point_segment_sq;
use super::sweep::{Clearances, Sweep, SweepOptions, segment_rate, sweep};
use crate::ik::planar::PlanarRedundant;
use crate::model::planar_angles::InteriorAngles;
use crate::tolerance::CONTACT;

/// A point of the arm's plane, metres (plane coordinates of [`PlanarRedundant`]).
pub type P2 = [f64; 2];

/// Which swept-area test decides whether an obstacle blocks a move.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum SweepTest {
    /// The continuous check of the joint-interpolated motion of all three links
    /// ([`leg_sweep`]): blocked unless a positive clearance is proven over the whole move.
    #[default]
    Robust,
    /// The thesis's eqs. (24)–(36) for the last link only, as printed (`k < 1`, fixed
    /// order, strict inequalities; NaN from a zero division makes a test false).
    PaperLiteral,
}

/// How the two waypoints are placed on the `L/7` circle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub enum WaypointRule {
    /// On the perpendicular to `KH` (`K1H`) at `H`, base side (notes 000 D5).
    #[default]
    Perpendicular,
    /// On the same perpendicular, the other side (away from the base): the alternative detour
    /// that [`crate::decide::detour_choice`] ranks against the base-side one.
    PerpendicularFar,
    /// The printed Table 6 formulas: `H + (L/7)·(−dx, dy)/|d|`.
    PaperPrinted,
}

/// Options of [`plan_detour`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DetourOptions {
    /// IK scan step `Δα`, radians (thesis: 0.01°).
    pub step: f64,
    /// Swept-area test.
    pub sweep_test: SweepTest,
    /// Waypoint construction.
    pub waypoints: WaypointRule,
    /// Radius of the waypoint circle, metres (thesis: `L/7`; `None` = mean link length / 7).
    pub radius: Option<f64>,
    /// Radius every point obstacle is grown by, metres (0: the thesis's points). A sensed
    /// obstacle grows by its uncertainty radius ([`super::sense`]), so a detour that clears
    /// the disc clears the true obstacle wherever it lies in it. The swept checks and the
    /// reported clearances are to the discs, and the waypoint circle's radius grows by it
    /// (`L/7` beyond the disc). The literal test ([`SweepTest::PaperLiteral`]) takes points only.
    pub obstacle_radius: f64,
}

impl Default for DetourOptions {
    fn default() -> Self {
        DetourOptions {
            step: 0.01f64.to_radians(),
            sweep_test: SweepTest::Robust,
            waypoints: WaypointRule::Perpendicular,
            radius: None,
            obstacle_radius: 0.0,
        }
    }
}

impl DetourOptions {
    /// The waypoint circle's radius for `arm`, metres: [`DetourOptions::radius`], or the mean
    /// link length / 7 (the thesis's `L/7`).
    #[must_use]
    pub fn circle_radius(&self, arm: &PlanarRedundant) -> f64 {
        let l = arm.lengths();
        self.radius.unwrap_or((l[0] + l[1] + l[2]) / 21.0)
    }
}

/// What the planner decided.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum DetourOutcome {
    /// No obstacle in the way: move directly.
    Direct,
    /// Detour through `K2`, `K3` around obstacle `obstacle` (0-based).
    Detour {
        /// The obstacle that blocked the direct move.
        obstacle: usize,
    },
    /// The target fails the workspace test (thesis: `L < r < 3L`, strict).
    TargetUnreachable,
    /// The direct move is blocked and the obstacle lies within the circle radius of the
    /// target (or of the start): there is no room for a detour.
    ObstacleTooClose {
        /// The obstacle.
        obstacle: usize,
    },
    /// A waypoint (2 for `K2`, 3 for `K3`) fails the workspace test.
    WaypointUnreachable {
        /// 2 or 3.
        waypoint: usize,
        /// The obstacle detoured around.
        obstacle: usize,
    },
    /// A leg of the detour is itself blocked (several obstacles, or the arm's own sweep).
    LegBlocked {
        /// 1 = K→K2, 2 = K2→K3, 3 = K3→K1.
        leg: usize,
        /// The blocking obstacle.
        obstacle: usize,
    },
}

/// The result of [`plan_detour`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DetourPlan {
    /// Decision.
    pub outcome: DetourOutcome,
    /// Whether the direct move was blocked.
    pub blocked: bool,
    /// Gripper waypoints after the start: `[K1]` (direct) or `[K2, K3, K1]` (detour); the
    /// computed waypoints also when a later step failed; empty when the target is unreachable.
    pub waypoints: Vec<P2>,
    /// Joint values at each reached waypoint (radians), in order.
    pub configurations: Vec<[f64; 3]>,
    /// The thesis's angles `(α, β, γ)` at each reached waypoint.
    #[serde(skip)]
    pub paper_angles: Vec<InteriorAngles>,
    /// `S = Σ|Δangle|` of each leg, radians.
    pub leg_s: Vec<f64>,
    /// Smallest distance between any link and any obstacle along the planned legs (joint
    /// values interpolated linearly), metres; `None` without obstacles or legs.
    pub min_clearance: Option<f64>,
    /// Where that smallest distance occurs, with its certified lower bound.
    pub closest: Option<Closest>,
}

/// Where the arm comes closest to an obstacle along the planned legs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Closest {
    /// 1-based leg (1 for the direct move).
    pub leg: usize,
    /// Fraction `s ∈ [0, 1]` of the leg's joint-interpolated motion.
    pub at: f64,
    /// 1-based link: 1 = OB, 2 = BA, 3 = AK.
    pub link: usize,
    /// 0-based obstacle.
    pub obstacle: usize,
    /// The distance there, metres.
    pub clearance_m: f64,
    /// Certified lower bound of the distance over all legs, metres.
    pub lower_bound_m: f64,
}

/// Cross product of `b − a` and `c − a`.
#[inline]
fn cross(a: P2, b: P2, c: P2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

fn seg_dist(h: P2, a: P2, b: P2) -> f64 {
    let v = |p: P2| nalgebra::Vector3::new(p[0], p[1], 0.0);
    point_segment_sq(&v(h), &v(a), &v(b)).sqrt()
}

/// Whether `h` lies in the polygon `poly` (any vertex order, convex or not; a
/// self-intersecting quadrilateral counts by the even–odd rule), boundary included (within
/// [`CONTACT`]).
///
/// # Example
/// ```
/// use reach::world::detour::in_polygon;
/// let square = [[0.0, 0.0], [0.0, 1.0], [1.0, 1.0], [1.0, 0.0]]; // clockwise
/// assert!(in_polygon([0.5, 0.5], &square));
/// assert!(!in_polygon([1.5, 0.5], &square));
/// ```
#[must_use]
pub fn in_polygon(h: P2, poly: &[P2]) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        if seg_dist(h, a, b) <= CONTACT {
            return true;
        }
        if (a[1] > h[1]) != (b[1] > h[1]) {
            // The edge straddles the horizontal through h, so b[1] ≠ a[1]; h is left of the
            // crossing when the cross product has the edge's upward/downward sign.
            let c = cross(a, b, h);
            if (c > 0.0) == (b[1] > a[1]) {
                inside = !inside;
            }
        }
    }
    inside
}

/// The thesis's obstacle test as printed (eqs. 24–36 and the `k ≥ 1` branch of §4.3), with
/// `A = (x3, y3)`, `K = (x1, y1)`, `A1 = (x4, y4)`, `K1 = (x2, y2)`: literal `k < 1`, the
/// figure's vertex order, strict inequalities. Kept for comparison (notes 000 D6, D7); it
/// misses obstacles that are inside for other layouts (vector OB-G3).
#[must_use]
pub fn paper_literal_in_sweep(a: P2, k: P2, a1: P2, k1: P2, h: P2) -> bool {
    let ([x1, y1], [x2, y2], [x3, y3], [x4, y4], [xh, yh]) = (k, k1, a, a1, h);
    let slope = (y1 - y3) / (x1 - x3);
    if slope < 1.0 {
        let f1 = y3 + (y1 - y3) / (x1 - x3) * (xh - x3);
        let f2 = y4 + (y2 - y4) / (x2 - x4) * (xh - x4);
        if !(f2 < yh && yh < f1) {
            return false;
        }
        let xh3 = (yh - y3) * (x3 - x4) / (y3 - y4) + x3;
        let xh4 = (yh - y1) * (x1 - x2) / (y1 - y2) + x1;
        xh3 < xh && xh < xh4
    } else {
        let xh1 = (yh - y3) * (x1 - x3) / (y1 - y3) + x3;
        let xh2 = (yh - y4) * (x2 - x4) / (y2 - y4) + x4;
        if !(xh1 < xh && xh < xh2) {
            return false;
        }
        let f3 = y3 + (y3 - y4) / (x3 - x4) * (xh - x3);
        let f4 = y1 + (y1 - y2) / (x1 - x2) * (xh - x1);
        f3 < yh && yh < f4
    }
}

/// The waypoint for the source point `s` (`K` or `K1`) around `h` on a circle of `radius`;
/// `None` when `s` coincides with `h`.
#[must_use]
pub fn waypoint(h: P2, s: P2, radius: f64, rule: WaypointRule) -> Option<P2> {
    let d = [s[0] - h[0], s[1] - h[1]];
    let len = d[0].hypot(d[1]);
    if len <= CONTACT {
        return None;
    }
    let u = [d[0] / len, d[1] / len];
    Some(match rule {
        // Table 6 as printed (D5): (−dx, +dy).
        WaypointRule::PaperPrinted => [h[0] - radius * u[0], h[1] + radius * u[1]],
        WaypointRule::Perpendicular | WaypointRule::PerpendicularFar => {
            let c1 = [h[0] - radius * u[1], h[1] + radius * u[0]];
            let c2 = [h[0] + radius * u[1], h[1] - radius * u[0]];
            // Base side: the candidate nearer the base O (the thesis's "side of the
            // mounting axis"); a tie keeps the counter-clockwise one. Far side: the other.
            let c2_nearer = c2[0].hypot(c2[1]) < c1[0].hypot(c1[1]);
            if c2_nearer == (rule == WaypointRule::Perpendicular) { c2 } else { c1 }
        }
    })
}

/// The arm's points `[O, B, A, K]` in plane coordinates for joint values `q`.
#[must_use]
pub fn arm_points(arm: &PlanarRedundant, q: &[f64; 3]) -> [P2; 4] {
    let phi = arm.link_angles(q);
    let l = arm.lengths();
    let mut pts = [[0.0; 2]; 4];
    for i in 0..3 {
        pts[i + 1] = [pts[i][0] + l[i] * phi[i].cos(), pts[i][1] + l[i] * phi[i].sin()];
    }
    pts
}

/// The clearances of the three links of a planar arm to point obstacles grown into discs of
/// `radius`, for [`sweep`]: constraint `3·o + i` is link `i` (0-based: OB, BA, AK) against
/// obstacle `o`.
pub struct PlanarClearances<'a> {
    /// The arm.
    pub arm: &'a PlanarRedundant,
    /// The obstacles' centres.
    pub obstacles: &'a [P2],
    /// The obstacles' radius, metres (0 for points).
    pub radius: f64,
}

impl Clearances for PlanarClearances<'_> {
    fn prepare(&mut self, _hull: &[&[f64]], speed: &[f64]) -> Result<Vec<f64>, WorldError> {
        let lengths = self.arm.lengths();
        Ok((0..3 * self.obstacles.len()).map(|c| segment_rate(&lengths, &[true; 3], speed, 0, c % 3, 0.0)).collect())
    }

    fn evaluate(&mut self, _s: f64, q: &[f64], out: &mut [f64]) -> Result<(), WorldError> {
        let p = arm_points(self.arm, &[q[0], q[1], q[2]]);
        for (o, h) in self.obstacles.iter().enumerate() {
            for i in 0..3 {
                out[3 * o + i] = seg_dist(*h, p[i], p[i + 1]) - self.radius;
            }
        }
        Ok(())
    }
}

/// The swept check of the joint-interpolated move `from → to` against `obstacles` (see
/// [`super::sweep`]): proven clear, or the first obstacle and link it touches.
///
/// # Errors
/// [`WorldError::Input`] for non-finite joint values.
pub fn leg_sweep(arm: &PlanarRedundant, from: &[f64; 3], to: &[f64; 3], obstacles: &[P2]) -> Result<Sweep, WorldError> {
    leg_sweep_discs(arm, from, to, obstacles, 0.0)
}

/// [`leg_sweep`] against obstacles grown into discs of `radius` metres (clearances to the
/// discs).
///
/// # Errors
/// [`WorldError::Input`] for non-finite joint values.
pub fn leg_sweep_discs(
    arm: &PlanarRedundant,
    from: &[f64; 3],
    to: &[f64; 3],
    obstacles: &[P2],
    radius: f64,
) -> Result<Sweep, WorldError> {
    sweep(&mut PlanarClearances { arm, obstacles, radius }, from, to, &SweepOptions::default())
}

/// Whether the move `from → to` is blocked by obstacle `h` under `test`.
#[must_use]
pub fn move_blocked(arm: &PlanarRedundant, from: &[f64; 3], to: &[f64; 3], h: P2, test: SweepTest) -> bool {
    let [o, b, a, k] = arm_points(arm, from);
    let [_, b1, a1, k1] = arm_points(arm, to);
    match test {
        SweepTest::PaperLiteral => paper_literal_in_sweep(a, k, a1, k1, h),
        SweepTest::Robust => {
            in_polygon(h, &[a, k, k1, a1]) || in_polygon(h, &[b, a, a1, b1]) || in_polygon(h, &[o, b, b1])
        }
    }
}

/// The minimum-change configuration for `target` from `current` (thesis §4.1), or `None`
/// when the target fails the workspace test.
fn select(
    arm: &PlanarRedundant,
    current: &[f64; 3],
    target: P2,
    step: f64,
) -> Result<Option<([f64; 3], InteriorAngles, f64)>, WorldError> {
    let scan = arm.paper_scan(target, step)?;
    let now = InteriorAngles::from_link_angles(arm.link_angles(current));
    Ok(scan.select_min_s(&now).map(|(i, s)| (scan.rows[i].q, scan.rows[i].paper, s)))
}

/// Plans the move of the gripper from the pose `start` to `target` past point obstacles
/// (thesis §4.5; notes 000 §9 item 10 for the cases the thesis leaves open).
///
/// # Behavior
/// 1. Target: minimum-change IK row ([`PlanarRedundant::paper_scan`] +
///    [`select_min_s`](crate::ik::planar::PaperScan::select_min_s)); outside `L < r < 3L`:
///    [`DetourOutcome::TargetUnreachable`].
/// 2. The direct move is blocked by the first obstacle the joint-interpolated motion cannot be
///    proven to clear ([`leg_sweep`]; with [`SweepTest::PaperLiteral`], the thesis's printed
///    test). Not blocked: [`DetourOutcome::Direct`].
/// 3. Blocked by `H`: if `H` is within the circle radius of `K1` or `K`, no detour fits
///    ([`DetourOutcome::ObstacleTooClose`]). Otherwise `K2`, `K3` by the waypoint rule; a
///    waypoint outside the workspace gives [`DetourOutcome::WaypointUnreachable`].
/// 4. Each leg `K → K2 → K3 → K1` takes the minimum-change row from the previous leg's
///    configuration and is re-checked against **every** obstacle;
///    a blocked leg gives [`DetourOutcome::LegBlocked`] (no detour exists by this method).
///
/// # Errors
/// [`WorldError::Input`] for NaN coordinates, a bad step or sample count;
/// [`WorldError::Ik`] from the scan.
pub fn plan_detour(
    arm: &PlanarRedundant,
    start: &[f64; 3],
    target: P2,
    obstacles: &[P2],
    options: &DetourOptions,
) -> Result<DetourPlan, WorldError> {
    let finite = |p: &P2| p.iter().all(|v| v.is_finite());
    if !start.iter().all(|v| v.is_finite()) || !finite(&target) || !obstacles.iter().all(finite) {
        return Err(WorldError::Input("detour: start, target and obstacles must be finite numbers".into()));
    }
    let grown = options.obstacle_radius;
    if !(grown.is_finite() && grown >= 0.0) {
        return Err(WorldError::Input(format!("detour: obstacle radius must be ≥ 0, got {grown} m")));
    }
    if grown > 0.0 && options.sweep_test == SweepTest::PaperLiteral {
        return Err(WorldError::Input("detour: the thesis's literal test takes point obstacles only".into()));
    }
    let radius = options.circle_radius(arm) + grown;
    if !(radius.is_finite() && radius > 0.0) {
        return Err(WorldError::Input(format!("detour: circle radius must be positive, got {radius} m")));
    }
    let mut plan = DetourPlan {
        outcome: DetourOutcome::TargetUnreachable,
        blocked: false,
        waypoints: Vec::new(),
        configurations: Vec::new(),
        paper_angles: Vec::new(),
        leg_s: Vec::new(),
        min_clearance: None,
        closest: None,
    };
    let Some((q1, p1, s1)) = select(arm, start, target, options.step)? else { return Ok(plan) };
    // The first obstacle the move runs into (the swept check), or the literal test's first.
    let blocker = |from: &[f64; 3], to: &[f64; 3]| -> Result<Option<usize>, WorldError> {
        Ok(match options.sweep_test {
            SweepTest::Robust => {
                let swept = leg_sweep_discs(arm, from, to, obstacles, grown)?;
                (!swept.clear).then_some(swept.constraint / 3)
            }
            SweepTest::PaperLiteral => {
                obstacles.iter().position(|h| move_blocked(arm, from, to, *h, SweepTest::PaperLiteral))
            }
        })
    };
    let Some(hit) = blocker(start, &q1)? else {
        plan.outcome = DetourOutcome::Direct;
        plan.waypoints = vec![target];
        plan.configurations = vec![q1];
        plan.paper_angles = vec![p1];
        plan.leg_s = vec![s1];
        plan.closest = closest(arm, start, &plan.configurations, obstacles, grown)?;
        plan.min_clearance = plan.closest.map(|c| c.clearance_m);
        return Ok(plan);
    };
    plan.blocked = true;
    let h = obstacles[hit];
    let k = arm_points(arm, start)[3];
    let near = |p: P2| (p[0] - h[0]).hypot(p[1] - h[1]) <= radius;
    let (Some(k2), Some(k3)) =
        (waypoint(h, k, radius, options.waypoints), waypoint(h, target, radius, options.waypoints))
    else {
        plan.outcome = DetourOutcome::ObstacleTooClose { obstacle: hit };
        return Ok(plan);
    };
    if near(target) || near(k) {
        plan.outcome = DetourOutcome::ObstacleTooClose { obstacle: hit };
        return Ok(plan);
    }
    plan.waypoints = vec![k2, k3, target];
    let mut current = *start;
    for (leg, point) in [k2, k3, target].into_iter().enumerate() {
        let Some((q, p, s)) = select(arm, &current, point, options.step)? else {
            plan.outcome = DetourOutcome::WaypointUnreachable { waypoint: leg + 2, obstacle: hit };
            return Ok(plan);
        };
        if let Some(o) = blocker(&current, &q)? {
            plan.outcome = DetourOutcome::LegBlocked { leg: leg + 1, obstacle: o };
            return Ok(plan);
        }
        plan.configurations.push(q);
        plan.paper_angles.push(p);
        plan.leg_s.push(s);
        current = q;
    }
    plan.outcome = DetourOutcome::Detour { obstacle: hit };
    plan.closest = closest(arm, start, &plan.configurations, obstacles, grown)?;
    plan.min_clearance = plan.closest.map(|c| c.clearance_m);
    Ok(plan)
}

/// The closest approach over the legs `start → legs[0] → legs[1] …` (`None` without
/// obstacles or legs).
fn closest(
    arm: &PlanarRedundant,
    start: &[f64; 3],
    legs: &[[f64; 3]],
    obstacles: &[P2],
    radius: f64,
) -> Result<Option<Closest>, WorldError> {
    let mut best: Option<Closest> = None;
    let mut from = *start;
    for (leg, to) in legs.iter().enumerate() {
        let swept = leg_sweep_discs(arm, &from, to, obstacles, radius)?;
        if swept.evaluations > 0 && best.is_none_or(|b| swept.min_clearance < b.clearance_m) {
            best = Some(Closest {
                leg: leg + 1,
                at: swept.at,
                link: swept.constraint % 3 + 1,
                obstacle: swept.constraint / 3,
                clearance_m: swept.min_clearance,
                lower_bound_m: swept.lower_bound.min(best.map_or(f64::INFINITY, |b| b.lower_bound_m)),
            });
        } else if let Some(b) = &mut best {
            b.lower_bound_m = b.lower_bound_m.min(swept.lower_bound);
        }
        from = *to;
    }
    Ok(best)
}
