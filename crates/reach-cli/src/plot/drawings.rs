//! The drawings of the commands, built with [`super::svg`].
//!
//! Units on the axes: time in s, revolute joints in degrees (rates deg/s), prismatic joints in
//! metres (m/s), positions in metres.

use reach::Robot;
use reach::ik::planar::PlanarRedundant;
use reach::model::JointKind;
use reach::world::Obstacle;
use reach::world::Shape;
use reach::world::cspace::NodeClass;
use reach::world::detour::{DetourOutcome, DetourPlan, P2, arm_points};

use super::svg::{Anchor, Panel, Svg, padded_range};
use crate::error::CliError;
use crate::numbers::{display_unit, q_display};

/// Drawing width, pixels.
const WIDTH: f64 = 1000.0;
/// Left margin (room for tick labels and the vertical axis label).
const LEFT: f64 = 70.0;

/// One joint's curves in display units (degrees or metres; rates per second).
#[derive(Debug, Clone, PartialEq)]
pub struct JointSeries {
    /// Axis label, e.g. `q2 (shoulder)`.
    pub label: String,
    /// `deg` or `m`.
    pub unit: &'static str,
    /// Positions, one per time.
    pub q: Vec<f64>,
    /// Rates, one per time.
    pub qd: Vec<f64>,
    /// Position limits `(lower, upper)` when both are finite.
    pub limits: Option<(f64, f64)>,
    /// Speed limit `|q̇| ≤ max_rate` when known.
    pub max_rate: Option<f64>,
}

/// Per-joint series of a robot from positions and rates already in display units (one row
/// per time, one column per joint).
#[must_use]
pub fn joint_series(robot: &Robot, q_display: &[Vec<f64>], qd_display: &[Vec<f64>]) -> Vec<JointSeries> {
    robot
        .joints()
        .iter()
        .enumerate()
        .map(|(i, joint)| {
            let shown = |v: f64| if joint.kind == JointKind::Revolute { v.to_degrees() } else { v };
            let (lo, hi) = (joint.limits.lower, joint.limits.upper);
            JointSeries {
                label: if joint.name.is_empty() || joint.name == format!("q{}", i + 1) {
                    format!("q{}", i + 1)
                } else {
                    format!("q{} ({})", i + 1, joint.name)
                },
                unit: display_unit(joint.kind),
                q: q_display.iter().map(|row| row.get(i).copied().unwrap_or(f64::NAN)).collect(),
                qd: qd_display.iter().map(|row| row.get(i).copied().unwrap_or(f64::NAN)).collect(),
                limits: (lo.is_finite() && hi.is_finite()).then(|| (shown(lo), shown(hi))),
                max_rate: joint.max_velocity.filter(|v| v.is_finite() && *v > 0.0).map(shown),
            }
        })
        .collect()
}

/// Everything a joint-curve drawing shows.
#[derive(Debug, Clone)]
pub struct TrajectoryDrawing<'a> {
    /// Title (robot, profile, …).
    pub title: String,
    /// Sample times, s.
    pub times: Vec<f64>,
    /// One entry per joint.
    pub joints: Vec<JointSeries>,
    /// Tool positions (m), one per time.
    pub tool: Vec<[f64; 3]>,
    /// Tool positions at the planner's waypoints (m), marked on the tool path.
    pub tool_waypoints: Vec<[f64; 3]>,
    /// Obstacles projected onto the tool-path panels.
    pub obstacles: &'a [Obstacle],
}

/// A y range showing the data and any limit that is near it (within half the data span).
fn range_with_limits(data: &[f64], limits: Option<(f64, f64)>) -> (f64, f64) {
    let (mut lo, mut hi) = padded_range(data.iter().copied());
    let span = hi - lo;
    if let Some((a, b)) = limits {
        if a >= lo - 0.5 * span {
            lo = lo.min(a - 0.05 * span);
        }
        if b <= hi + 0.5 * span {
            hi = hi.max(b + 0.05 * span);
        }
    }
    (lo, hi)
}

/// The time axis of the joint panels, s: from the first to the last sample time. A motion
/// without duration (one sample, or all times equal) gets a span of one second (more for a
/// large start time, so that the end stays distinct from the start in floating point) instead
/// of an empty range, which would map every mark to NaN.
fn time_range(times: &[f64]) -> (f64, f64) {
    let (lo, hi) = padded_range(times.iter().copied());
    let t0 = times.first().copied().filter(|t| t.is_finite()).unwrap_or(lo);
    let t1 = times.last().copied().filter(|t| t.is_finite()).unwrap_or(hi);
    if t1 > t0 { (t0, t1) } else { (t0, t0 + 1.0f64.max(t0.abs() * 0.1)) }
}

/// Joint curves — one row per joint with a q(t) panel and a q̇(t) panel, the allowed range
/// (position limits, speed limits) shaded — and the tool path in xy and xz projections with
/// the obstacles.
#[must_use]
pub fn trajectory(d: &TrajectoryDrawing<'_>) -> Svg {
    let row_h = 150.0;
    let top = 60.0;
    let n = d.joints.len();
    let tool_h = 380.0;
    let height = top + n as f64 * row_h + tool_h + 20.0;
    let mut svg = Svg::new(WIDTH, height);
    svg.text(WIDTH / 2.0, 26.0, &d.title, "title", Anchor::Middle);
    svg.legend(LEFT, 34.0, &[("limit-band", "allowed range (position and speed limits)")][..]);
    let (t0, t1) = time_range(&d.times);
    let panel_w = (WIDTH - LEFT - 110.0) / 2.0;
    for (i, j) in d.joints.iter().enumerate() {
        let y = top + i as f64 * row_h + 10.0;
        let h = row_h - 50.0;
        let q: Vec<(f64, f64)> = d.times.iter().copied().zip(j.q.iter().copied()).collect();
        let qd: Vec<(f64, f64)> = d.times.iter().copied().zip(j.qd.iter().copied()).collect();
        let rate_limits = j.max_rate.map(|v| (-v, v));
        let pq = Panel::new(LEFT, y, panel_w, h, (t0, t1), range_with_limits(&j.q, j.limits));
        pq.begin(&mut svg, "joint-position", &format!("{} [{}]", j.label, j.unit), "t [s]", j.unit);
        if let Some((lo, hi)) = j.limits {
            pq.hband(&mut svg, lo, hi, "limit-band");
        }
        pq.polyline(&mut svg, &q, "curve");
        pq.end(&mut svg);
        let rate_unit = format!("{}/s", j.unit);
        let pv = Panel::new(LEFT + panel_w + 90.0, y, panel_w, h, (t0, t1), range_with_limits(&j.qd, rate_limits));
        pv.begin(&mut svg, "joint-rate", &format!("rate of {} [{rate_unit}]", j.label), "t [s]", &rate_unit);
        if let Some((lo, hi)) = rate_limits {
            pv.hband(&mut svg, lo, hi, "limit-band");
        }
        pv.polyline(&mut svg, &qd, "curve2");
        pv.end(&mut svg);
    }
    let y = top + n as f64 * row_h + 20.0;
    tool_panels(&mut svg, d, y, tool_h - 60.0);
    svg
}

/// The tool path projected on xy and xz, equal aspect, with the base and the obstacles.
fn tool_panels(svg: &mut Svg, d: &TrajectoryDrawing<'_>, y: f64, h: f64) {
    let panel_w = (WIDTH - LEFT - 110.0) / 2.0;
    for (k, (a, b, name)) in [(0usize, 1usize, "xy"), (0, 2, "xz")].into_iter().enumerate() {
        let pts: Vec<(f64, f64)> = d.tool.iter().map(|p| (p[a], p[b])).collect();
        let xr = padded_range(pts.iter().map(|p| p.0).chain([0.0]));
        let yr = padded_range(pts.iter().map(|p| p.1).chain([0.0]));
        let grow = |r: (f64, f64)| {
            let s = (r.1 - r.0) * 0.1;
            (r.0 - s, r.1 + s)
        };
        let x = LEFT + k as f64 * (panel_w + 90.0);
        let panel = Panel::equal_aspect(x, y, panel_w, h, grow(xr), grow(yr));
        let (la, lb) = (&name[0..1], &name[1..2]);
        panel.begin(
            svg,
            "tool-path",
            &format!("tool path, {name} projection [m]"),
            &format!("{la} [m]"),
            &format!("{lb} [m]"),
        );
        for o in d.obstacles {
            match project(&o.shape, a, b, [panel.xr.0, panel.xr.1, panel.yr.0, panel.yr.1]) {
                Projection::Polygon(poly) => panel.polygon(svg, &poly, "obstacle"),
                Projection::Point(p) => panel.dot(svg, p, 4.0, "obstacle-point"),
                Projection::Everywhere => {}
            }
        }
        panel.dot(svg, (0.0, 0.0), 5.0, "base");
        panel.polyline(svg, &pts, "curve");
        for w in &d.tool_waypoints {
            panel.dot(svg, (w[a], w[b]), 3.5, "waypoint");
        }
        if let (Some(s), Some(e)) = (pts.first(), pts.last()) {
            panel.dot(svg, *s, 4.5, "start");
            panel.dot(svg, *e, 4.5, "end");
        }
        panel.end(svg);
    }
    let legend_y = y + h + 34.0;
    svg.legend(LEFT, legend_y, &[("start", "start"), ("end", "end")][..]);
    svg.legend(LEFT + 110.0, legend_y, &[("base", "robot base"), ("obstacle", "obstacle (projection)")][..]);
    if !d.tool_waypoints.is_empty() {
        svg.legend(LEFT + 330.0, legend_y, &[("waypoint", "planner waypoints")][..]);
    }
}

/// An obstacle seen in a projection.
#[derive(Debug, Clone, PartialEq)]
enum Projection {
    /// The outline of the projected solid (convex).
    Polygon(Vec<(f64, f64)>),
    /// A point obstacle.
    Point((f64, f64)),
    /// The solid covers the whole projection plane (a half-space not parallel to the view
    /// direction): nothing useful to draw.
    Everywhere,
}

/// Convex hull (Andrew's monotone chain), counter-clockwise.
fn convex_hull(mut pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    pts.sort_by(|p, q| p.0.total_cmp(&q.0).then(p.1.total_cmp(&q.1)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: (f64, f64), a: (f64, f64), b: (f64, f64)| (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0);
    let mut hull: Vec<(f64, f64)> = Vec::with_capacity(pts.len() * 2);
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &(f64, f64)>> =
            if pass == 0 { Box::new(pts.iter()) } else { Box::new(pts.iter().rev()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0.0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// Projection of a shape onto the plane of world axes `a`, `b` (0 = x, 1 = y, 2 = z), within
/// the view `[xmin, xmax, ymin, ymax]` (used for half-spaces).
fn project(shape: &Shape, a: usize, b: usize, view: [f64; 4]) -> Projection {
    let circle_pts = |c: &nalgebra::Vector3<f64>, r: f64, out: &mut Vec<(f64, f64)>| {
        for k in 0..32 {
            let t = k as f64 * std::f64::consts::TAU / 32.0;
            out.push((c[a] + r * t.cos(), c[b] + r * t.sin()));
        }
    };
    match shape {
        Shape::Point { at } => Projection::Point((at[a], at[b])),
        Shape::Sphere { center, radius } => {
            let mut pts = Vec::new();
            circle_pts(center, *radius, &mut pts);
            Projection::Polygon(pts)
        }
        Shape::Capsule { a: p, b: q, radius } => {
            let mut pts = Vec::new();
            circle_pts(p, *radius, &mut pts);
            circle_pts(q, *radius, &mut pts);
            Projection::Polygon(convex_hull(pts))
        }
        Shape::Box { center, half_extents, rotation } => {
            let mut pts = Vec::new();
            for s in 0..8 {
                let sign = |bit: usize| if s & (1 << bit) == 0 { -1.0 } else { 1.0 };
                let local = nalgebra::Vector3::new(
                    sign(0) * half_extents.x,
                    sign(1) * half_extents.y,
                    sign(2) * half_extents.z,
                );
                let p = center + rotation * local;
                pts.push((p[a], p[b]));
            }
            Projection::Polygon(convex_hull(pts))
        }
        Shape::HalfSpace { normal, offset } => {
            let c = 3 - a - b;
            if normal[c].abs() > 1e-9 {
                return Projection::Everywhere;
            }
            // The solid {n·p ≤ offset} clipped to the view rectangle (one Sutherland–Hodgman pass).
            let [x0, x1, y0, y1] = view;
            let rect = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)];
            let f = |p: (f64, f64)| normal[a] * p.0 + normal[b] * p.1 - offset;
            let mut out = Vec::new();
            for k in 0..4 {
                let (p, q) = (rect[k], rect[(k + 1) % 4]);
                let (fp, fq) = (f(p), f(q));
                if fp <= 0.0 {
                    out.push(p);
                }
                if (fp < 0.0) != (fq < 0.0) && fp != fq {
                    let t = fp / (fp - fq);
                    out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
                }
            }
            Projection::Polygon(out)
        }
        _ => Projection::Everywhere,
    }
}

/// Seed 000's detour: the planar arm at the start, at the waypoints `K2`, `K3` and at the
/// target, intermediate poses of each leg (joints interpolated linearly, as the plan checks
/// them), the area swept by the links in the direct move, the obstacles and the waypoint
/// circles of radius `radius` (metres, the thesis's `L/7`, plus `disc`); obstacles grown into
/// discs of radius `disc` (a sensed obstacle's uncertainty; 0 for points) are drawn filled.
#[must_use]
pub fn detour(
    title: &str,
    arm: &PlanarRedundant,
    start: &[f64; 3],
    plan: &DetourPlan,
    obstacles: &[P2],
    radius: f64,
    disc: f64,
) -> Svg {
    let mut poses: Vec<[f64; 3]> = vec![*start];
    poses.extend(plan.configurations.iter().copied());
    let reach: f64 = arm.lengths().iter().sum();
    let mut xs = vec![0.0, reach * 0.2];
    let mut ys = vec![0.0];
    for q in &poses {
        for p in arm_points(arm, q) {
            xs.push(p[0]);
            ys.push(p[1]);
        }
    }
    for h in obstacles.iter().chain(&plan.waypoints) {
        xs.extend([h[0] - radius, h[0] + radius]);
        ys.extend([h[1] - radius, h[1] + radius]);
    }
    let (width, height) = (WIDTH, 760.0);
    let mut svg = Svg::new(width, height);
    svg.text(width / 2.0, 26.0, title, "title", Anchor::Middle);
    let panel =
        Panel::equal_aspect(LEFT, 50.0, width - LEFT - 250.0, height - 110.0, padded_range(xs), padded_range(ys));
    panel.begin(&mut svg, "detour", "", "x [m]", "y [m]");
    // Area swept by the links in the direct move (the polygons of the robust test).
    let target_q = match plan.outcome {
        DetourOutcome::Direct | DetourOutcome::Detour { .. } => plan.configurations.last().copied(),
        _ => None,
    };
    if let Some(tq) = target_q {
        let [o, b, a, k] = arm_points(arm, start);
        let [_, b1, a1, k1] = arm_points(arm, &tq);
        let t = |p: P2| (p[0], p[1]);
        for poly in [vec![t(a), t(k), t(k1), t(a1)], vec![t(b), t(a), t(a1), t(b1)], vec![t(o), t(b), t(b1)]] {
            panel.polygon(&mut svg, &poly, "sweep");
        }
    }
    // Ghost poses along each leg.
    for leg in poses.windows(2) {
        for s in 1..10 {
            let f = s as f64 / 10.0;
            let q = [0, 1, 2].map(|i| leg[0][i] + f * (leg[1][i] - leg[0][i]));
            let pts: Vec<(f64, f64)> = arm_points(arm, &q).iter().map(|p| (p[0], p[1])).collect();
            panel.polyline(&mut svg, &pts, "arm-ghost");
        }
    }
    for h in obstacles {
        panel.circle(&mut svg, (h[0], h[1]), radius, "circle");
        if disc > 0.0 {
            panel.circle(&mut svg, (h[0], h[1]), disc, "obstacle");
        }
    }
    let names: Vec<&str> = if plan.waypoints.len() == 3 { vec!["K2", "K3", "K1"] } else { vec!["K1"] };
    let mut route = vec![arm_points(arm, start)[3]];
    route.extend(plan.waypoints.iter().copied());
    panel.polyline(&mut svg, &route.iter().map(|p| (p[0], p[1])).collect::<Vec<_>>(), "route");
    for (i, q) in poses.iter().enumerate() {
        let pts: Vec<(f64, f64)> = arm_points(arm, q).iter().map(|p| (p[0], p[1])).collect();
        panel.polyline(&mut svg, &pts, "arm");
        for p in &pts[1..3] {
            panel.dot(&mut svg, *p, 3.0, "joint");
        }
        let class = if i == 0 {
            "start"
        } else if i + 1 == poses.len() && target_q.is_some() {
            "end"
        } else {
            "waypoint"
        };
        panel.dot(&mut svg, pts[3], 4.5, class);
    }
    for (w, name) in plan.waypoints.iter().zip(&names) {
        panel.label(&mut svg, (w[0], w[1]), (7.0, -7.0), name);
    }
    let k = arm_points(arm, start)[3];
    panel.label(&mut svg, (k[0], k[1]), (7.0, -7.0), "K (start)");
    for (i, h) in obstacles.iter().enumerate() {
        panel.dot(&mut svg, (h[0], h[1]), 4.0, "obstacle-point");
        panel.label(&mut svg, (h[0], h[1]), (7.0, 12.0), &format!("H{}", i + 1));
    }
    panel.dot(&mut svg, (0.0, 0.0), 5.0, "base");
    panel.end(&mut svg);
    let circle = if disc > 0.0 {
        format!("circle L/7 + {disc:.4} = {radius:.4} m")
    } else {
        format!("circle L/7 = {radius:.4} m")
    };
    let grown = format!("sensed H grown by {disc:.4} m");
    // The last entry, the grown disc, only when there is one.
    let disc_legend = if disc > 0.0 { 9 } else { 8 };
    svg.legend(
        width - 230.0,
        70.0,
        &[
            ("start", "start pose K"),
            ("waypoint", "waypoints K2, K3"),
            ("end", "target K1"),
            ("arm-ghost", "intermediate poses"),
            ("sweep", "swept area, direct move"),
            ("obstacle-point", "obstacle H"),
            ("circle", &circle),
            ("base", "base O"),
            ("obstacle", &grown),
        ][..disc_legend],
    );
    svg
}

/// The colour class and legend label of a node class.
#[must_use]
pub fn class_style(c: NodeClass) -> (&'static str, &'static str) {
    match c {
        NodeClass::Allowed => ("c-allowed", "allowed"),
        NodeClass::OutsideLimits => ("c-limits", "outside joint limits"),
        NodeClass::OutsideZone => ("c-zone", "tool outside zone"),
        NodeClass::SelfCollision => ("c-self", "self-collision"),
        NodeClass::ObstacleCollision => ("c-obstacle", "obstacle collision"),
    }
}

/// Cell edges around grid values: midpoints between neighbours, half a gap beyond the ends.
fn cell_edges(values: &[f64]) -> Vec<f64> {
    let n = values.len();
    if n == 1 {
        return vec![values[0] - 0.5, values[0] + 0.5];
    }
    let mut e = Vec::with_capacity(n + 1);
    e.push(values[0] - (values[1] - values[0]) / 2.0);
    for w in values.windows(2) {
        e.push((w[0] + w[1]) / 2.0);
    }
    e.push(values[n - 1] + (values[n - 1] - values[n - 2]) / 2.0);
    e
}

/// One C-space section: an image over two swept joints (`x_values` horizontally, `y_values`
/// vertically, display units) coloured by node class, with a legend giving the count of each
/// class in the section. `class_at(ix, iy)` is the class of the node at those indices.
#[must_use]
pub fn cspace_section(
    title: &str,
    (x_label, x_values): (&str, &[f64]),
    (y_label, y_values): (&str, &[f64]),
    class_at: &dyn Fn(usize, usize) -> NodeClass,
) -> Svg {
    let (width, height) = (920.0, 700.0);
    let mut svg = Svg::new(width, height);
    svg.text(width / 2.0, 26.0, title, "title", Anchor::Middle);
    let (xe, ye) = (cell_edges(x_values), cell_edges(y_values));
    let xr = (xe[0], xe[xe.len() - 1]);
    let yr = (ye[0], ye[ye.len() - 1]);
    let side = 600.0;
    let panel = Panel::new(LEFT, 50.0, side, side, xr, yr);
    panel.begin(&mut svg, "cspace", "", x_label, y_label);
    let all = [
        NodeClass::Allowed,
        NodeClass::OutsideLimits,
        NodeClass::OutsideZone,
        NodeClass::SelfCollision,
        NodeClass::ObstacleCollision,
    ];
    let mut counts = [0usize; 5];
    for iy in 0..y_values.len() {
        // Runs of one class along x become one rectangle.
        let mut ix = 0;
        while ix < x_values.len() {
            let c = class_at(ix, iy);
            let mut end = ix + 1;
            while end < x_values.len() && class_at(end, iy) == c {
                end += 1;
            }
            counts[c as usize] += end - ix;
            let (x0, x1) = (panel.px(xe[ix]), panel.px(xe[end]));
            let (y0, y1) = (panel.py(ye[iy + 1]), panel.py(ye[iy]));
            // Overlap by a fraction of a pixel so the rasteriser leaves no seams.
            svg.rect(x0, y0, x1 - x0 + 0.3, y1 - y0 + 0.3, class_style(c).0);
            ix = end;
        }
    }
    panel.end(&mut svg);
    let labels: Vec<String> = all.iter().map(|c| format!("{} ({})", class_style(*c).1, counts[*c as usize])).collect();
    let items: Vec<(&str, &str)> = all.iter().zip(&labels).map(|(c, l)| (class_style(*c).0, l.as_str())).collect();
    svg.legend(LEFT + side + 20.0, 60.0, &items);
    svg
}

/// How a tour leaves its start node (`reach tasks`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Route {
    /// Visiting: one open path start → first point → … → last point.
    Open,
    /// Collection: a round trip start → point → start for every point in the order.
    Trips,
}

/// A top view (xy, metres) of a tour: the robot base at `base`, the start node at `start.0`
/// (labelled `start.1`: the start tool position or the container), the `points` visited in
/// `order` (indices into `points`) along `route`, each point numbered by its place in the
/// order (its number in the task file in brackets), points not in the order in grey
/// (unreachable or beyond the budget).
///
/// # Errors
/// [`CliError::BadInput`] for an index out of range or a non-finite coordinate.
pub fn tour_top_view(
    title: &str,
    base: [f64; 2],
    start: ([f64; 2], &str),
    points: &[[f64; 2]],
    order: &[usize],
    route: Route,
) -> Result<Svg, CliError> {
    if let Some(&i) = order.iter().find(|&&i| i >= points.len()) {
        return Err(CliError::bad_input(format!(
            "tour: point index {i} out of range (there are {} points)",
            points.len()
        )));
    }
    let all = || points.iter().chain([&base, &start.0]);
    if let Some(i) = all().position(|p| !p.iter().all(|v| v.is_finite())) {
        return Err(CliError::bad_input(format!("tour: point {} has a non-finite coordinate", i + 1)));
    }
    let (width, height) = (820.0, 760.0);
    let mut svg = Svg::new(width, height);
    svg.text(width / 2.0, 26.0, title, "title", Anchor::Middle);
    let xr = padded_range(all().map(|p| p[0]));
    let yr = padded_range(all().map(|p| p[1]));
    let grow = |r: (f64, f64)| {
        let s = (r.1 - r.0) * 0.08;
        (r.0 - s, r.1 + s)
    };
    let panel = Panel::equal_aspect(LEFT, 50.0, width - LEFT - 40.0, height - 150.0, grow(xr), grow(yr));
    panel.begin(&mut svg, "tour", "", "x [m]", "y [m]");
    let at = |i: usize| (points[i][0], points[i][1]);
    let home = (start.0[0], start.0[1]);
    match route {
        Route::Open => {
            let path: Vec<(f64, f64)> = std::iter::once(home).chain(order.iter().map(|&i| at(i))).collect();
            panel.polyline(&mut svg, &path, "route");
        }
        Route::Trips => {
            for &i in order {
                panel.polyline(&mut svg, &[home, at(i), home], "route");
            }
        }
    }
    for (i, p) in points.iter().enumerate() {
        if !order.contains(&i) {
            panel.dot(&mut svg, (p[0], p[1]), 4.0, "c-limits");
            panel.label(&mut svg, (p[0], p[1]), (6.0, -6.0), &format!("({})", i + 1));
        }
    }
    for (rank, &i) in order.iter().enumerate() {
        let class = if rank + 1 == order.len() && route == Route::Open { "end" } else { "waypoint" };
        panel.dot(&mut svg, at(i), 4.5, class);
        panel.label(&mut svg, at(i), (6.0, -6.0), &format!("{} ({})", rank + 1, i + 1));
    }
    panel.dot(&mut svg, home, 5.5, "start");
    panel.label(&mut svg, home, (8.0, -8.0), start.1);
    panel.dot(&mut svg, (base[0], base[1]), 6.0, "base");
    panel.label(&mut svg, (base[0], base[1]), (8.0, 14.0), "base");
    panel.end(&mut svg);
    let order_text = match route {
        Route::Open => "visiting order: rank (point number)",
        Route::Trips => "trips in order: rank (object number)",
    };
    svg.legend(LEFT, height - 60.0, &[("start", start.1), ("waypoint", "point"), ("route", order_text)][..]);
    Ok(svg)
}

/// A [`TrajectoryDrawing`] title for a robot: `name — what`.
#[must_use]
pub fn title(robot: &Robot, what: &str) -> String {
    format!("{} — {what}", robot.name())
}

/// Joint series from SI samples (positions and rates in rad, m), for callers holding SI data.
#[must_use]
pub fn joint_series_si(robot: &Robot, q_si: &[Vec<f64>], qd_si: &[Vec<f64>]) -> Vec<JointSeries> {
    let q: Vec<Vec<f64>> = q_si.iter().map(|q| q_display(robot, q)).collect();
    let qd: Vec<Vec<f64>> = qd_si.iter().map(|q| q_display(robot, q)).collect();
    joint_series(robot, &q, &qd)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_of_a_square_with_an_inner_point() {
        let h = convex_hull(vec![(0.0, 0.0), (1.0, 0.0), (0.5, 0.5), (1.0, 1.0), (0.0, 1.0)]);
        assert_eq!(h, vec![(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
    }

    #[test]
    fn a_ceiling_projects_to_a_band_in_xz_and_everywhere_in_xy() {
        let ceiling = Shape::HalfSpace { normal: nalgebra::Vector3::new(0.0, 0.0, -1.0), offset: -1.2 };
        assert_eq!(project(&ceiling, 0, 1, [0.0, 2.0, 0.0, 2.0]), Projection::Everywhere);
        let Projection::Polygon(p) = project(&ceiling, 0, 2, [0.0, 2.0, 0.0, 2.0]) else { panic!("no polygon") };
        assert!(p.iter().all(|q| q.1 >= 1.2 - 1e-12), "{p:?}");
        assert!(p.contains(&(2.0, 2.0)) && p.contains(&(0.0, 2.0)));
    }

    #[test]
    fn cell_edges_split_uneven_grids_halfway() {
        assert_eq!(cell_edges(&[0.0, 10.0, 15.0]), vec![-5.0, 5.0, 12.5, 17.5]);
        assert_eq!(cell_edges(&[3.0]), vec![2.5, 3.5]);
    }

    #[test]
    fn the_time_axis_runs_from_the_first_to_the_last_sample() {
        assert_eq!(time_range(&[0.0, 0.2, 0.5]), (0.0, 0.5));
        assert_eq!(time_range(&[0.0]), (0.0, 1.0));
        assert_eq!(time_range(&[3.0, 3.0]), (3.0, 4.0));
        let (t0, t1) = time_range(&[1e20]);
        assert!(t0 == 1e20 && t1 > t0, "({t0}, {t1})");
    }

    /// Regression: a one-sample motion used to get the x range (t, t), so every time tick and
    /// the sample itself mapped to NaN pixels and the panels were drawn without a time axis.
    #[test]
    fn a_one_sample_motion_draws_a_time_axis() {
        let joint = JointSeries {
            label: "q1".into(),
            unit: "deg",
            q: vec![10.0],
            qd: vec![0.0],
            limits: Some((-90.0, 90.0)),
            max_rate: Some(30.0),
        };
        let drawing = TrajectoryDrawing {
            title: "one sample".into(),
            times: vec![0.0],
            joints: vec![joint],
            tool: vec![[0.5, 0.0, 0.3]],
            tool_waypoints: vec![],
            obstacles: &[],
        };
        let text = trajectory(&drawing).finish();
        assert!(!text.contains("NaN"), "{text}");
        // Vertical grid lines (one per time tick) in the two joint panels, which come before
        // the tool-path panels.
        let joint_panels = text.split("<g class=\"panel tool-path\"").next().unwrap_or_default();
        let time_grid = joint_panels
            .lines()
            .filter(|l| l.starts_with("<line class=\"grid\""))
            .filter(|l| {
                let attr = |name: &str| l.split(&format!(" {name}=\"")).nth(1).and_then(|r| r.split('"').next());
                attr("x1") == attr("x2")
            })
            .count();
        assert!(time_grid >= 2, "{text}");
    }

    #[test]
    fn tour_rejects_bad_indices() {
        let start = ([0.5, 0.5], "start");
        assert!(tour_top_view("t", [0.0, 0.0], start, &[[1.0, 0.0]], &[1], Route::Open).is_err());
        assert!(tour_top_view("t", [f64::NAN, 0.0], start, &[[1.0, 0.0]], &[0], Route::Open).is_err());
        let open = tour_top_view("t", [0.0, 0.0], start, &[[1.0, 0.0], [0.0, 1.0]], &[1, 0], Route::Open).unwrap();
        assert_eq!(open.finish().matches("<polyline class=\"route\"").count(), 1);
        let trips = tour_top_view("t", [0.0, 0.0], start, &[[1.0, 0.0], [0.0, 1.0]], &[1, 0], Route::Trips).unwrap();
        assert_eq!(trips.finish().matches("<polyline class=\"route\"").count(), 2);
    }
}
