//! Distances between convex solids given by their support functions (Gilbert–Johnson–Keerthi),
//! as **certified lower bounds**: what a proof of clearance needs.
//!
//! For convex sets `A`, `B` and their Minkowski difference `D = A − B`, any unit direction `u`
//! gives `dist(A, B) ≥ min_{x∈D} u·x = u·s_D(−u)`, where `s_D(−u) = s_A(−u) − s_B(u)` is a
//! support point. GJK drives `u` toward the direction of the closest point of `D`; every
//! iterate's bound is valid, so the returned value is a lower bound whatever the iteration
//! count, and within a relative `1e-9` of the distance when GJK converges (it does on these
//! shapes in a few iterations). Overlapping sets give 0.

use nalgebra::{Matrix3, Vector3};

/// A convex solid in the world frame, by its support function.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Convex<'a> {
    /// A point.
    Point(Vector3<f64>),
    /// A segment.
    Segment(Vector3<f64>, Vector3<f64>),
    /// A box: centre, world ← box rotation, half-extents.
    Box(Vector3<f64>, Matrix3<f64>, Vector3<f64>),
    /// A cylinder: centre, unit axis, radius, half-length.
    Cylinder(Vector3<f64>, Vector3<f64>, f64, f64),
    /// The convex hull of `vertices` (in a local frame) placed by `rotation`, `translation`.
    Hull(Matrix3<f64>, Vector3<f64>, &'a [Vector3<f64>]),
}

impl Convex<'_> {
    /// A point of the solid farthest along `d`.
    #[inline]
    pub(crate) fn support(&self, d: &Vector3<f64>) -> Vector3<f64> {
        match *self {
            Convex::Point(p) => p,
            Convex::Segment(a, b) => {
                if d.dot(&a) >= d.dot(&b) {
                    a
                } else {
                    b
                }
            }
            Convex::Box(c, r, h) => {
                let l = r.transpose() * d;
                let s = Vector3::new(h.x.copysign(l.x), h.y.copysign(l.y), h.z.copysign(l.z));
                c + r * s
            }
            Convex::Cylinder(c, u, r, h) => {
                let along = d.dot(&u);
                let across = d - u * along;
                let n = across.norm();
                let rim = if n > 1e-300 { across * (r / n) } else { Vector3::zeros() };
                c + u * h.copysign(along) + rim
            }
            Convex::Hull(r, t, vertices) => {
                let l = r.transpose() * d;
                let mut best = vertices[0];
                let mut score = l.dot(&best);
                for v in &vertices[1..] {
                    let s = l.dot(v);
                    if s > score {
                        score = s;
                        best = *v;
                    }
                }
                t + r * best
            }
        }
    }

    /// A point inside the solid (the start of the search).
    fn inner(&self) -> Vector3<f64> {
        match *self {
            Convex::Point(p) => p,
            Convex::Segment(a, b) => (a + b) * 0.5,
            Convex::Box(c, ..) | Convex::Cylinder(c, ..) => c,
            Convex::Hull(r, t, vertices) => t + r * vertices[0],
        }
    }
}

/// Most GJK iterations (each adds one support point); the bound is valid at any stop.
const MAX_ITERATIONS: usize = 64;

/// Relative gap `(|v|² − v·w)/|v|²` at which the distance is taken as found.
const RELATIVE_GAP: f64 = 1e-9;

/// A certified lower bound of the distance between `a` and `b` (0 when they overlap), metres.
#[must_use]
pub(crate) fn distance(a: &Convex, b: &Convex) -> f64 {
    let mut v = a.inner() - b.inner();
    if v.norm_squared() < 1e-300 {
        v = Vector3::x();
    }
    let mut simplex: [Vector3<f64>; 4] = [Vector3::zeros(); 4];
    let mut n = 0;
    let mut lower: f64 = 0.0;
    for _ in 0..MAX_ITERATIONS {
        let w = a.support(&-v) - b.support(&v);
        let vv = v.norm_squared();
        let vw = v.dot(&w);
        lower = lower.max(vw / vv.sqrt());
        if vv - vw <= RELATIVE_GAP * vv {
            break;
        }
        if simplex[..n].iter().any(|p| (p - w).norm_squared() <= 1e-24 * vv.max(1e-300)) {
            break;
        }
        simplex[n] = w;
        n += 1;
        let (closest, kept) = closest_on_simplex(&mut simplex, n);
        n = kept;
        if n == 4 || closest.norm_squared() <= 1e-28 {
            return 0.0;
        }
        v = closest;
    }
    lower.max(0.0)
}

/// The point of the simplex `s[..n]` closest to the origin, and the simplex reduced to the
/// smallest face that contains it (moved to the front of `s`).
fn closest_on_simplex(s: &mut [Vector3<f64>; 4], n: usize) -> (Vector3<f64>, usize) {
    match n {
        1 => (s[0], 1),
        2 => segment(s, 0, 1),
        3 => triangle(s, [0, 1, 2]),
        _ => tetrahedron(s),
    }
}

fn segment(s: &mut [Vector3<f64>; 4], i: usize, j: usize) -> (Vector3<f64>, usize) {
    let (a, b) = (s[i], s[j]);
    let ab = b - a;
    let t = -a.dot(&ab);
    let l = ab.norm_squared();
    if t <= 0.0 || l <= 0.0 {
        s[0] = a;
        (a, 1)
    } else if t >= l {
        s[0] = b;
        (b, 1)
    } else {
        s[0] = a;
        s[1] = b;
        (a + ab * (t / l), 2)
    }
}

/// Closest point of triangle `s[idx]` to the origin (Ericson, *Real-Time Collision Detection*,
/// §5.1.5), the simplex reduced to its supporting feature.
fn triangle(s: &mut [Vector3<f64>; 4], idx: [usize; 3]) -> (Vector3<f64>, usize) {
    let (a, b, c) = (s[idx[0]], s[idx[1]], s[idx[2]]);
    let (ab, ac, ap) = (b - a, c - a, -a);
    let (d1, d2) = (ab.dot(&ap), ac.dot(&ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        s[0] = a;
        return (a, 1);
    }
    let bp = -b;
    let (d3, d4) = (ab.dot(&bp), ac.dot(&bp));
    if d3 >= 0.0 && d4 <= d3 {
        s[0] = b;
        return (b, 1);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        s[0] = a;
        s[1] = b;
        return (a + ab * v, 2);
    }
    let cp = -c;
    let (d5, d6) = (ab.dot(&cp), ac.dot(&cp));
    if d6 >= 0.0 && d5 <= d6 {
        s[0] = c;
        return (c, 1);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        s[0] = a;
        s[1] = c;
        return (a + ac * w, 2);
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        s[0] = b;
        s[1] = c;
        return (b + (c - b) * w, 2);
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    s[0] = a;
    s[1] = b;
    s[2] = c;
    (a + ab * v + ac * w, 3)
}

/// A candidate face of [`tetrahedron`]: squared distance, closest point, the simplex kept and
/// its size.
type FaceCandidate = (f64, Vector3<f64>, [Vector3<f64>; 4], usize);

/// Closest point of the tetrahedron `s` to the origin: the origin inside gives 4 points kept.
fn tetrahedron(s: &mut [Vector3<f64>; 4]) -> (Vector3<f64>, usize) {
    let faces = [[0, 1, 2, 3], [0, 2, 3, 1], [0, 3, 1, 2], [1, 3, 2, 0]];
    let mut best: Option<FaceCandidate> = None;
    for [i, j, k, opposite] in faces {
        let (a, b, c, d) = (s[i], s[j], s[k], s[opposite]);
        let normal = (b - a).cross(&(c - a));
        let sign_origin = (-a).dot(&normal);
        let sign_d = (d - a).dot(&normal);
        // The origin on the far side of this face from the fourth point.
        if sign_origin * sign_d < 0.0 {
            let mut t = [a, b, c, Vector3::zeros()];
            let (p, kept) = triangle(&mut t, [0, 1, 2]);
            let dist = p.norm_squared();
            if best.as_ref().is_none_or(|(bd, ..)| dist < *bd) {
                best = Some((dist, p, t, kept));
            }
        }
    }
    match best {
        None => (Vector3::zeros(), 4),
        Some((_, p, t, kept)) => {
            s[..kept].copy_from_slice(&t[..kept]);
            (p, kept)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    #[test]
    fn exact_distances_of_known_pairs() {
        let id = Matrix3::identity();
        let unit = Convex::Box(Vector3::zeros(), id, Vector3::repeat(0.5));
        // A point 1 m beyond a face, beyond an edge, beyond a corner.
        for (p, d) in [
            (Vector3::new(1.5, 0.0, 0.0), 1.0),
            (Vector3::new(1.5, 1.5, 0.0), 2.0_f64.sqrt()),
            (Vector3::new(1.5, 1.5, 1.5), 3.0_f64.sqrt()),
        ] {
            let g = distance(&unit, &Convex::Point(p));
            assert!(g <= d + 1e-12 && g >= d * (1.0 - 1e-8), "{g} vs {d}");
        }
        // A segment crossing the box overlaps it; one passing 0.25 above does not.
        let cross = Convex::Segment(Vector3::new(-2.0, 0.1, 0.2), Vector3::new(2.0, -0.1, 0.1));
        assert_eq!(distance(&unit, &cross), 0.0);
        let above = Convex::Segment(Vector3::new(-2.0, 0.3, 0.75), Vector3::new(2.0, -0.1, 0.75));
        let g = distance(&unit, &above);
        assert!((g - 0.25).abs() < 1e-8, "{g}");
        // Cylinder (axis z, r 0.2, half-length 0.5) and a rotated box 0.3 beside its side.
        let cyl = Convex::Cylinder(Vector3::zeros(), Vector3::z(), 0.2, 0.5);
        let r = *Rotation3::from_euler_angles(0.0, 0.0, 0.7).matrix();
        let bx = Convex::Box(Vector3::new(0.5 + 0.1, 0.0, 0.0), r, Vector3::new(0.1, 0.1, 0.1));
        // The box's nearest point to the axis is its corner R·(−0.1, 0.1) from the centre.
        let (c, s) = (0.7_f64.cos(), 0.7_f64.sin());
        let near = (0.6 - 0.1 * (c + s)).hypot(0.1 * (c - s));
        let g = distance(&cyl, &bx);
        assert!((g - (near - 0.2)).abs() < 1e-8, "{g} vs {}", near - 0.2);
        // The hull of a tetrahedron against a point below its base.
        let v = [Vector3::zeros(), Vector3::x(), Vector3::y(), Vector3::z()];
        let hull = Convex::Hull(id, Vector3::new(0.0, 0.0, 1.0), &v);
        let g = distance(&hull, &Convex::Point(Vector3::new(0.2, 0.2, 0.0)));
        assert!((g - 1.0).abs() < 1e-9, "{g}");
        assert_eq!(distance(&hull, &Convex::Point(Vector3::new(0.1, 0.1, 1.1))), 0.0);
    }

    #[test]
    fn the_bound_never_exceeds_a_sampled_distance() {
        // Random boxes and cylinders: the GJK bound is at most the distance of any pair of
        // sampled surface points, and close to the smallest.
        let mut rng = crate::rng::SplitMix64(7);
        let mut u = || rng.next_f64() * 2.0 - 1.0;
        for _ in 0..200 {
            let r1 = *Rotation3::from_euler_angles(u() * 3.0, u() * 3.0, u() * 3.0).matrix();
            let r2 = *Rotation3::from_euler_angles(u() * 3.0, u() * 3.0, u() * 3.0).matrix();
            let h = Vector3::new(0.1 + u().abs() * 0.3, 0.1 + u().abs() * 0.3, 0.1 + u().abs() * 0.3);
            let c2 = Vector3::new(u(), u(), u()) * 1.5;
            let a = Convex::Box(Vector3::zeros(), r1, h);
            let axis = r2 * Vector3::z();
            let b = Convex::Cylinder(c2, axis, 0.15, 0.3);
            let g = distance(&a, &b);
            let mut sampled = f64::INFINITY;
            for _ in 0..400 {
                let d = Vector3::new(u(), u(), u());
                let pa = a.support(&d);
                for _ in 0..4 {
                    let e = Vector3::new(u(), u(), u());
                    sampled = sampled.min((pa - b.support(&e)).norm());
                }
            }
            assert!(g <= sampled + 1e-12, "bound {g} above a sampled distance {sampled}");
        }
    }
}
