//! Exact distance kernels between points, segments and boxes (hand-written, allocation-free).
//!
//! Every function works on plain `Vector3<f64>` coordinates. The collision checker calls
//! exactly one of these per (link, shape) pair, so each query has one implementation.

use nalgebra::Vector3;

/// Below this squared length a segment is treated as a point (m²): far below any link.
const DEGENERATE_SQ: f64 = 1e-24;

/// Squared distance from point `p` to segment `ab`.
///
/// # Example
/// ```
/// use nalgebra::Vector3;
/// use reach::world::distance::point_segment_sq;
/// let d2 = point_segment_sq(&Vector3::new(0.5, 1.0, 0.0), &Vector3::zeros(), &Vector3::x());
/// assert_eq!(d2, 1.0);
/// ```
#[must_use]
#[inline]
pub fn point_segment_sq(p: &Vector3<f64>, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
    let ab = b - a;
    let ap = p - a;
    let len2 = ab.norm_squared();
    let t = if len2 > DEGENERATE_SQ { (ap.dot(&ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (ap - ab * t).norm_squared()
}

/// Squared distance between segments `p1q1` and `p2q2` (either may be a single point).
///
/// Closest points by the clamped-parameter method (Ericson, *Real-Time Collision Detection*,
/// §5.1.9): minimise over `s` for the line, clamp, re-solve `t`, clamp, re-solve `s`.
/// Parallel segments take `s = 0` and are still exact after the clamping passes.
#[must_use]
#[inline]
pub fn segment_segment_sq(p1: &Vector3<f64>, q1: &Vector3<f64>, p2: &Vector3<f64>, q2: &Vector3<f64>) -> f64 {
    let d1 = q1 - p1;
    let d2 = q2 - p2;
    let r = p1 - p2;
    let a = d1.norm_squared();
    let e = d2.norm_squared();
    let f = d2.dot(&r);
    let (s, t);
    if a <= DEGENERATE_SQ && e <= DEGENERATE_SQ {
        return r.norm_squared();
    }
    if a <= DEGENERATE_SQ {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e <= DEGENERATE_SQ {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s0 = if denom > 1e-12 * a * e { ((b * f - c * e) / denom).clamp(0.0, 1.0) } else { 0.0 };
            let mut t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t0 = 0.0;
                s0 = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t0 = 1.0;
                s0 = ((b - c) / a).clamp(0.0, 1.0);
            }
            s = s0;
            t = t0;
        }
    }
    let c1 = p1 + d1 * s;
    let c2 = p2 + d2 * t;
    (c1 - c2).norm_squared()
}

/// Signed distance from point `p` (box frame) to the box `[-h, h]` (negative inside).
#[must_use]
#[inline]
pub fn point_box_sdf(p: &Vector3<f64>, h: &Vector3<f64>) -> f64 {
    let q = p.abs() - h;
    let outside = Vector3::new(q.x.max(0.0), q.y.max(0.0), q.z.max(0.0)).norm();
    outside + q.x.max(q.y).max(q.z).min(0.0)
}

/// The parameter interval `[t0, t1] ⊂ [0, 1]` where segment `a + t(b − a)` lies in the box
/// `[-h, h]` (box frame), or `None` (slab clipping; no division by a zero direction).
#[must_use]
#[inline]
pub fn segment_box_clip(a: &Vector3<f64>, b: &Vector3<f64>, h: &Vector3<f64>) -> Option<(f64, f64)> {
    let d = b - a;
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for i in 0..3 {
        if d[i] == 0.0 {
            if a[i].abs() > h[i] {
                return None;
            }
        } else {
            let inv = 1.0 / d[i];
            let (mut u, mut v) = ((-h[i] - a[i]) * inv, (h[i] - a[i]) * inv);
            if u > v {
                std::mem::swap(&mut u, &mut v);
            }
            t0 = t0.max(u);
            t1 = t1.min(v);
            if t0 > t1 {
                return None;
            }
        }
    }
    Some((t0, t1))
}

/// The minimum over segment `ab` (box frame) of the box's signed distance function:
/// the Euclidean distance between segment and box when they are apart, minus the largest
/// depth of a segment point inside the box when they overlap.
///
/// # Behavior
/// * Apart: the closest pair lies at a segment end (point–box distance) or between the
///   segment and one of the 12 box edges (segment–segment distance); the minimum of those
///   14 distances is exact.
/// * Overlapping: the depth `min_i(h_i − |p_i|)` is concave and piecewise linear along the
///   clipped part of the segment, so its maximum is at a clip end, where a coordinate
///   crosses 0, or where two of the linear pieces cross; all these are evaluated.
/// * A box with a zero half-extent (a planar rectangle) works unchanged.
#[must_use]
pub fn segment_box_sdf(a: &Vector3<f64>, b: &Vector3<f64>, h: &Vector3<f64>) -> f64 {
    let d = b - a;
    if let Some((t0, t1)) = segment_box_clip(a, b, h) {
        let depth = |t: f64| {
            let p = a + d * t;
            (h.x - p.x.abs()).min(h.y - p.y.abs()).min(h.z - p.z.abs())
        };
        let mut best = depth(t0).max(depth(t1));
        let mut consider = |t: f64| {
            if t > t0 && t < t1 {
                best = best.max(depth(t));
            }
        };
        for i in 0..3 {
            if d[i] != 0.0 {
                consider(-a[i] / d[i]);
            }
            for j in (i + 1)..3 {
                for si in [-1.0, 1.0] {
                    for sj in [-1.0, 1.0] {
                        // h_i − s_i·p_i(t) = h_j − s_j·p_j(t)
                        let slope = -si * d[i] + sj * d[j];
                        if slope != 0.0 {
                            consider(-(h[i] - si * a[i] - h[j] + sj * a[j]) / slope);
                        }
                    }
                }
            }
        }
        return -best.max(0.0);
    }
    let mut best = point_box_sdf(a, h).min(point_box_sdf(b, h));
    // The 12 edges: for each axis i, the 4 edges parallel to it.
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        for sj in [-1.0, 1.0] {
            for sk in [-1.0, 1.0] {
                let mut e0 = Vector3::zeros();
                e0[i] = -h[i];
                e0[j] = sj * h[j];
                e0[k] = sk * h[k];
                let mut e1 = e0;
                e1[i] = h[i];
                best = best.min(segment_segment_sq(a, b, &e0, &e1).sqrt());
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: the minimum of the box SDF over 20 001 points of the segment.
    fn sampled(a: &Vector3<f64>, b: &Vector3<f64>, h: &Vector3<f64>) -> f64 {
        (0..=20_000).map(|i| point_box_sdf(&(a + (b - a) * (i as f64 / 20_000.0)), h)).fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn segment_box_matches_dense_sampling() {
        let h = Vector3::new(1.0, 0.5, 0.25);
        let mut seed = 12345_u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 6.0 - 3.0
        };
        for _ in 0..300 {
            let a = Vector3::new(rnd(), rnd(), rnd());
            let b = Vector3::new(rnd(), rnd(), rnd());
            let exact = segment_box_sdf(&a, &b, &h);
            let approx = sampled(&a, &b, &h);
            // Sampling overestimates the minimum by at most |b − a| / 20 000.
            assert!(exact <= approx + 1e-12, "{a:?} {b:?}: {exact} > {approx}");
            assert!(approx - exact <= (b - a).norm() / 20_000.0 + 1e-12, "{a:?} {b:?}: {exact} vs {approx}");
        }
    }

    #[test]
    fn segment_segment_hand_values() {
        let z = Vector3::zeros();
        // Crossing skew segments 1 apart in z.
        let d = segment_segment_sq(
            &Vector3::new(-1.0, 0.0, 0.0),
            &Vector3::new(1.0, 0.0, 0.0),
            &Vector3::new(0.0, -1.0, 1.0),
            &Vector3::new(0.0, 1.0, 1.0),
        );
        assert!((d - 1.0).abs() < 1e-15);
        // Parallel, overlapping in x, 2 apart.
        let d = segment_segment_sq(
            &z,
            &Vector3::new(2.0, 0.0, 0.0),
            &Vector3::new(1.0, 2.0, 0.0),
            &Vector3::new(3.0, 2.0, 0.0),
        );
        assert!((d - 4.0).abs() < 1e-15);
        // Collinear, gap of 1.
        let d = segment_segment_sq(&z, &Vector3::x(), &Vector3::new(2.0, 0.0, 0.0), &Vector3::new(3.0, 0.0, 0.0));
        assert!((d - 1.0).abs() < 1e-15);
        // Degenerate: point vs segment.
        let d = segment_segment_sq(&Vector3::new(0.5, 3.0, 0.0), &Vector3::new(0.5, 3.0, 0.0), &z, &Vector3::x());
        assert!((d - 9.0).abs() < 1e-15);
    }

    #[test]
    fn box_overlap_depth() {
        let h = Vector3::new(1.0, 1.0, 1.0);
        // Through the centre: deepest point is the centre, depth 1.
        let v = segment_box_sdf(&Vector3::new(-3.0, 0.0, 0.0), &Vector3::new(3.0, 0.0, 0.0), &h);
        assert!((v + 1.0).abs() < 1e-15);
        // Grazing a face at y = 1: touching, 0.
        let v = segment_box_sdf(&Vector3::new(-3.0, 1.0, 0.0), &Vector3::new(3.0, 1.0, 0.0), &h);
        assert!(v.abs() < 1e-15);
    }
}
