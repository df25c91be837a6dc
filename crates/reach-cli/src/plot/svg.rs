//! A small hand-written SVG builder: a document with a style sheet, elements in pixel
//! coordinates, and [`Panel`]s that map data coordinates to pixels and draw axes with ticks,
//! labels, clipped polylines, shaded bands and legends.
//!
//! Colours and line styles live in one CSS style sheet ([`STYLE`]); elements refer to them by
//! class, so a drawing is small and every element kind can be found by its class (the tests
//! look for `panel`, `limit-band`, …).

use std::fmt::Write as _;

/// The style sheet of every drawing: one class per kind of mark.
pub const STYLE: &str = "\
text{font-family:'DejaVu Sans',Arial,Helvetica,sans-serif;fill:#222}\
.title{font-size:16px;font-weight:bold}.label{font-size:12px}.tick{font-size:10px;fill:#444}\
.frame{fill:none;stroke:#444;stroke-width:1}.grid{stroke:#ddd;stroke-width:0.6}\
.curve{fill:none;stroke:#1f5fbf;stroke-width:1.6}.curve2{fill:none;stroke:#c0392b;stroke-width:1.6}\
.limit-band{fill:#2e9e4f;fill-opacity:0.12;stroke:none}\
.limit-line{stroke:#2e9e4f;stroke-width:1;stroke-dasharray:5 3}\
.obstacle{fill:#d35400;fill-opacity:0.35;stroke:#a04000;stroke-width:1}\
.obstacle-point{fill:#a04000;stroke:none}\
.sweep{fill:#f1c40f;fill-opacity:0.25;stroke:#b7950b;stroke-width:0.6}\
.circle{fill:none;stroke:#8e44ad;stroke-width:1.2;stroke-dasharray:4 3}\
.arm{fill:none;stroke:#1f5fbf;stroke-width:3;stroke-linecap:round;stroke-linejoin:round}\
.arm-ghost{fill:none;stroke:#7f8c8d;stroke-width:1;stroke-opacity:0.45}\
.joint{fill:#fff;stroke:#222;stroke-width:1}.base{fill:#222}\
.waypoint{fill:#8e44ad;stroke:none}.start{fill:#27ae60}.end{fill:#c0392b}\
.route{fill:none;stroke:#555;stroke-width:1.2;stroke-dasharray:6 3}\
.c-allowed{fill:#2ecc71}.c-limits{fill:#bdc3c7}.c-zone{fill:#ecf0f1}\
.cspace rect{shape-rendering:crispEdges}.c-self{fill:#9b59b6}.c-obstacle{fill:#e74c3c}.legend-box{stroke:#444;stroke-width:0.6}";

/// Escapes `&`, `<`, `>` and `"` for text and attribute values.
#[must_use]
pub fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// Formats a pixel coordinate (two decimals, no trailing zeros needed).
fn px(v: f64) -> String {
    let r = (v * 100.0).round() / 100.0;
    if r == 0.0 { "0".into() } else { format!("{r}") }
}

/// Whether every value is finite (marks with a NaN coordinate, e.g. a sample without an IK
/// solution, are left out instead of writing an invalid SVG).
fn finite(values: &[f64]) -> bool {
    values.iter().all(|v| v.is_finite())
}

/// Text alignment relative to the anchor point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    /// The text starts at the point.
    Start,
    /// The text is centred on the point.
    Middle,
    /// The text ends at the point.
    End,
}

impl Anchor {
    fn name(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }
}

/// An SVG document under construction; coordinates are pixels, y pointing down.
#[derive(Debug, Clone)]
pub struct Svg {
    width: f64,
    height: f64,
    body: String,
    clip_ids: usize,
}

impl Svg {
    /// An empty white drawing of `width` × `height` pixels.
    #[must_use]
    pub fn new(width: f64, height: f64) -> Self {
        let mut svg = Svg { width, height, body: String::new(), clip_ids: 0 };
        svg.raw(&format!("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"#fff\"/>", px(width), px(height)));
        svg
    }

    fn raw(&mut self, element: &str) {
        self.body.push_str(element);
        self.body.push('\n');
    }

    /// Opens a group `<g class=…>` (closed by [`Svg::close`]), optionally clipped to a rectangle.
    pub fn open(&mut self, class: &str, clip: Option<[f64; 4]>) {
        match clip {
            Some([x, y, w, h]) => {
                self.clip_ids += 1;
                let id = self.clip_ids;
                self.raw(&format!(
                    "<clipPath id=\"clip{id}\"><rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/></clipPath>",
                    px(x),
                    px(y),
                    px(w),
                    px(h)
                ));
                self.raw(&format!("<g class=\"{}\" clip-path=\"url(#clip{id})\">", escape(class)));
            }
            None => self.raw(&format!("<g class=\"{}\">", escape(class))),
        }
    }

    /// Closes the innermost group.
    pub fn close(&mut self) {
        self.raw("</g>");
    }

    /// A rectangle.
    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, class: &str) {
        if !finite(&[x, y, w, h]) {
            return;
        }
        self.raw(&format!(
            "<rect class=\"{class}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"/>",
            px(x),
            px(y),
            px(w.max(0.0)),
            px(h.max(0.0))
        ));
    }

    /// A straight line.
    pub fn line(&mut self, a: (f64, f64), b: (f64, f64), class: &str) {
        if !finite(&[a.0, a.1, b.0, b.1]) {
            return;
        }
        self.raw(&format!(
            "<line class=\"{class}\" x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\"/>",
            px(a.0),
            px(a.1),
            px(b.0),
            px(b.1)
        ));
    }

    fn points(points: &[(f64, f64)]) -> String {
        let mut s = String::with_capacity(points.len() * 12);
        for (i, (x, y)) in points.iter().enumerate() {
            if i > 0 {
                s.push(' ');
            }
            let _ = write!(s, "{},{}", px(*x), px(*y));
        }
        s
    }

    /// An open polyline (nothing for fewer than two points).
    pub fn polyline(&mut self, points: &[(f64, f64)], class: &str) {
        if points.len() >= 2 && points.iter().all(|p| finite(&[p.0, p.1])) {
            self.raw(&format!("<polyline class=\"{class}\" points=\"{}\"/>", Self::points(points)));
        }
    }

    /// A closed polygon (nothing for fewer than three points).
    pub fn polygon(&mut self, points: &[(f64, f64)], class: &str) {
        if points.len() >= 3 && points.iter().all(|p| finite(&[p.0, p.1])) {
            self.raw(&format!("<polygon class=\"{class}\" points=\"{}\"/>", Self::points(points)));
        }
    }

    /// A circle of radius `r` pixels.
    pub fn circle(&mut self, c: (f64, f64), r: f64, class: &str) {
        if !finite(&[c.0, c.1, r]) {
            return;
        }
        self.raw(&format!("<circle class=\"{class}\" cx=\"{}\" cy=\"{}\" r=\"{}\"/>", px(c.0), px(c.1), px(r)));
    }

    /// Text at `(x, y)` (baseline), escaped.
    pub fn text(&mut self, x: f64, y: f64, text: &str, class: &str, anchor: Anchor) {
        if !finite(&[x, y]) {
            return;
        }
        self.raw(&format!(
            "<text class=\"{class}\" x=\"{}\" y=\"{}\" text-anchor=\"{}\">{}</text>",
            px(x),
            px(y),
            anchor.name(),
            escape(text)
        ));
    }

    /// Text rotated by −90° (reading upwards), centred on `(x, y)`.
    pub fn vertical_text(&mut self, x: f64, y: f64, text: &str, class: &str) {
        self.raw(&format!(
            "<text class=\"{class}\" x=\"{}\" y=\"{}\" text-anchor=\"middle\" transform=\"rotate(-90 {} {})\">{}</text>",
            px(x),
            px(y),
            px(x),
            px(y),
            escape(text)
        ));
    }

    /// A legend: one swatch (a small rectangle of the item's class) and label per item, in a
    /// column starting at `(x, y)`.
    pub fn legend(&mut self, x: f64, y: f64, items: &[(&str, &str)]) {
        self.open("legend", None);
        for (i, (class, label)) in items.iter().enumerate() {
            let yy = y + i as f64 * 16.0;
            self.rect(x, yy, 14.0, 10.0, &format!("{class} legend-box"));
            self.text(x + 20.0, yy + 9.5, label, "label", Anchor::Start);
        }
        self.close();
    }

    /// The finished document.
    #[must_use]
    pub fn finish(&self) -> String {
        format!(
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" viewBox=\"0 0 {w} {h}\">\n<style>{STYLE}</style>\n{}</svg>\n",
            self.body,
            w = px(self.width),
            h = px(self.height)
        )
    }
}

/// "Nice" tick values (1, 2, 5 × 10ᵏ steps) within `[lo, hi]`, about `target` of them (at most
/// 1.5 × `target` + 1); returns the ticks and the step.
#[must_use]
pub fn nice_ticks(lo: f64, hi: f64, target: usize) -> (Vec<f64>, f64) {
    let span = hi - lo;
    if !(span.is_finite() && span > 0.0) {
        return (vec![lo], 1.0);
    }
    let raw = span / target.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    // The finest 1-2-5 step that gives at most half as many ticks again as asked for.
    let limit = 1.5 * target.max(1) as f64;
    let step = [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * mag).find(|s| span / s <= limit).unwrap_or(10.0 * mag);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    ((first..=last).map(|k| k as f64 * step).collect(), step)
}

/// A tick label with as many decimals as the step needs.
#[must_use]
pub fn tick_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 { 0 } else { (-step.log10()).ceil() as usize };
    let s = format!("{v:.decimals$}");
    if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') { s[1..].to_string() } else { s }
}

/// `[min, max]` of the finite values, padded by 5 % (by 1 for a single value or none).
#[must_use]
pub fn padded_range(values: impl IntoIterator<Item = f64>) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values.into_iter().filter(|v| v.is_finite()) {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    if span <= 1e-12 * (1.0 + lo.abs()) {
        let pad = 1.0f64.max(lo.abs() * 0.1);
        return (lo - pad, hi + pad);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

/// A plotting area: a pixel rectangle and the data ranges it shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Panel {
    /// Left edge, pixels.
    pub x: f64,
    /// Top edge, pixels.
    pub y: f64,
    /// Width, pixels.
    pub w: f64,
    /// Height, pixels.
    pub h: f64,
    /// Data range shown horizontally.
    pub xr: (f64, f64),
    /// Data range shown vertically.
    pub yr: (f64, f64),
}

impl Panel {
    /// A panel at pixel rectangle `(x, y, w, h)` showing `xr` × `yr`.
    #[must_use]
    pub fn new(x: f64, y: f64, w: f64, h: f64, xr: (f64, f64), yr: (f64, f64)) -> Self {
        Panel { x, y, w, h, xr, yr }
    }

    /// Like [`Panel::new`], with the ranges widened so that one data unit has the same pixel
    /// length on both axes (for drawings of space).
    #[must_use]
    pub fn equal_aspect(x: f64, y: f64, w: f64, h: f64, xr: (f64, f64), yr: (f64, f64)) -> Self {
        let sx = w / (xr.1 - xr.0);
        let sy = h / (yr.1 - yr.0);
        let s = sx.min(sy);
        let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
        let (hw, hh) = (w / s / 2.0, h / s / 2.0);
        Panel { x, y, w, h, xr: (cx - hw, cx + hw), yr: (cy - hh, cy + hh) }
    }

    /// Pixel x of data x.
    #[must_use]
    pub fn px(&self, v: f64) -> f64 {
        self.x + (v - self.xr.0) / (self.xr.1 - self.xr.0) * self.w
    }

    /// Pixel y of data y (up is up).
    #[must_use]
    pub fn py(&self, v: f64) -> f64 {
        self.y + self.h - (v - self.yr.0) / (self.yr.1 - self.yr.0) * self.h
    }

    /// Pixel point of a data point.
    #[must_use]
    pub fn p(&self, (x, y): (f64, f64)) -> (f64, f64) {
        (self.px(x), self.py(y))
    }

    /// Pixels per data unit along x.
    #[must_use]
    pub fn scale_x(&self) -> f64 {
        self.w / (self.xr.1 - self.xr.0)
    }

    /// Opens the panel group (class `panel` plus `class`): the frame, grid lines, ticks, axis
    /// labels and title are drawn; the marks drawn until [`Panel::end`] are clipped to it.
    pub fn begin(&self, svg: &mut Svg, class: &str, title: &str, xlabel: &str, ylabel: &str) {
        svg.open(&format!("panel {class}"), None);
        let (xt, xs) = nice_ticks(self.xr.0, self.xr.1, (self.w / 70.0).max(3.0) as usize);
        let (yt, ys) = nice_ticks(self.yr.0, self.yr.1, (self.h / 30.0).max(3.0) as usize);
        for &t in &xt {
            let x = self.px(t);
            svg.line((x, self.y), (x, self.y + self.h), "grid");
            svg.text(x, self.y + self.h + 13.0, &tick_label(t, xs), "tick", Anchor::Middle);
        }
        for &t in &yt {
            let y = self.py(t);
            svg.line((self.x, y), (self.x + self.w, y), "grid");
            svg.text(self.x - 4.0, y + 3.5, &tick_label(t, ys), "tick", Anchor::End);
        }
        svg.text(self.x + self.w / 2.0, self.y + self.h + 27.0, xlabel, "label", Anchor::Middle);
        svg.vertical_text(self.x - 40.0, self.y + self.h / 2.0, ylabel, "label");
        if !title.is_empty() {
            svg.text(self.x, self.y - 5.0, title, "label", Anchor::Start);
        }
        svg.open("marks", Some([self.x, self.y, self.w, self.h]));
    }

    /// Closes the clipped marks and draws the frame on top.
    pub fn end(&self, svg: &mut Svg) {
        svg.close();
        svg.rect(self.x, self.y, self.w, self.h, "frame");
        svg.close();
    }

    /// A horizontal band `lo ≤ y ≤ hi` across the panel (clipped), with dashed edge lines.
    pub fn hband(&self, svg: &mut Svg, lo: f64, hi: f64, class: &str) {
        let clamp = |v: f64| v.clamp(self.yr.0 - (self.yr.1 - self.yr.0), self.yr.1 + (self.yr.1 - self.yr.0));
        let (top, bottom) = (self.py(clamp(hi)), self.py(clamp(lo)));
        svg.rect(self.x, top, self.w, bottom - top, class);
        for v in [lo, hi] {
            if v > self.yr.0 && v < self.yr.1 {
                svg.line((self.x, self.py(v)), (self.x + self.w, self.py(v)), "limit-line");
            }
        }
    }

    /// A polyline through data points; a point with a non-finite coordinate (a sample without
    /// a solution) breaks the line into pieces.
    pub fn polyline(&self, svg: &mut Svg, points: &[(f64, f64)], class: &str) {
        for piece in points.split(|p| !(p.0.is_finite() && p.1.is_finite())) {
            let pts: Vec<(f64, f64)> = piece.iter().map(|&p| self.p(p)).collect();
            svg.polyline(&pts, class);
        }
    }

    /// A polygon through data points.
    pub fn polygon(&self, svg: &mut Svg, points: &[(f64, f64)], class: &str) {
        let pts: Vec<(f64, f64)> = points.iter().map(|&p| self.p(p)).collect();
        svg.polygon(&pts, class);
    }

    /// A circle of data radius `r` (use with [`Panel::equal_aspect`]).
    pub fn circle(&self, svg: &mut Svg, c: (f64, f64), r: f64, class: &str) {
        svg.circle(self.p(c), r * self.scale_x(), class);
    }

    /// A marker of `r` pixels at a data point.
    pub fn dot(&self, svg: &mut Svg, c: (f64, f64), r: f64, class: &str) {
        svg.circle(self.p(c), r, class);
    }

    /// Text at a data point, offset by `(dx, dy)` pixels.
    pub fn label(&self, svg: &mut Svg, at: (f64, f64), (dx, dy): (f64, f64), text: &str) {
        let (x, y) = self.p(at);
        svg.text(x + dx, y + dy, text, "tick", Anchor::Start);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_and_cover_the_range() {
        let (t, s) = nice_ticks(-3.2, 97.0, 5);
        assert_eq!(s, 20.0);
        assert_eq!(t, vec![0.0, 20.0, 40.0, 60.0, 80.0]);
        let (t, s) = nice_ticks(0.0012, 0.0049, 4);
        assert_eq!(s, 0.001);
        assert_eq!(t.len(), 3);
        assert_eq!(tick_label(0.002, s), "0.002");
        assert_eq!(tick_label(-0.0, 1.0), "0");
    }

    #[test]
    fn text_is_escaped_and_panels_map_up() {
        let mut svg = Svg::new(100.0, 50.0);
        svg.text(1.0, 2.0, "a<b & \"c\"", "label", Anchor::Start);
        assert!(svg.finish().contains("a&lt;b &amp; &quot;c&quot;"));
        let p = Panel::new(10.0, 10.0, 80.0, 40.0, (0.0, 8.0), (0.0, 4.0));
        assert_eq!(p.p((0.0, 0.0)), (10.0, 50.0));
        assert_eq!(p.p((8.0, 4.0)), (90.0, 10.0));
        let e = Panel::equal_aspect(0.0, 0.0, 200.0, 100.0, (0.0, 1.0), (0.0, 1.0));
        assert!((e.scale_x() - 100.0).abs() < 1e-12 && (e.yr.1 - e.yr.0 - 1.0).abs() < 1e-12);
    }

    #[test]
    fn marks_with_non_finite_coordinates_are_left_out() {
        let mut svg = Svg::new(100.0, 50.0);
        let p = Panel::new(0.0, 0.0, 100.0, 50.0, (0.0, 4.0), (0.0, 4.0));
        p.polyline(&mut svg, &[(0.0, 0.0), (1.0, 1.0), (2.0, f64::NAN), (3.0, 3.0), (4.0, 4.0)], "curve");
        p.dot(&mut svg, (f64::NAN, 1.0), 2.0, "start");
        let text = svg.finish();
        assert_eq!(text.matches("<polyline").count(), 2);
        assert!(!text.contains("NaN") && !text.contains("<circle"));
    }

    #[test]
    fn ranges_are_padded_and_survive_constant_or_empty_data() {
        assert_eq!(padded_range([0.0, 10.0]), (-0.5, 10.5));
        assert_eq!(padded_range([2.0, 2.0]), (1.0, 3.0));
        assert_eq!(padded_range([f64::NAN]), (-1.0, 1.0));
    }
}
