//! The robot's collision body: solids fixed to the chain's frames (URDF `<collision>`, the
//! robot TOML's `[[bodies]]`), and the link pairs that never need a check (MoveIt's SRDF
//! `disable_collisions`).
//!
//! Every solid is given in the frame of the link that carries it: frame 0 is the base (fixed
//! in the world at [`super::Robot::base`]), frame `k ≥ 1` the frame after joint `k` (1-based),
//! the one [`super::Robot::frames_into`] returns at index `k − 1`. Lengths in metres.

use nalgebra::{Isometry3, Point3, Vector3};
use serde::Serialize;

use super::ModelError;

/// The most triangles one collision mesh may have (a cap on what a file can make the checker
/// hold). Collision meshes are simplified hulls of a few hundred to a few thousand triangles;
/// 200 000 admits fine scans and refuses a visual mesh given by mistake.
pub const MAX_MESH_TRIANGLES: usize = 200_000;

/// One solid of a link's collision body, in the link's frame, metres.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
#[non_exhaustive]
pub enum BodyShape {
    /// A ball.
    Sphere {
        /// Centre.
        center: Vector3<f64>,
        /// Radius (> 0).
        radius: f64,
    },
    /// All points within `radius` of segment `ab`.
    Capsule {
        /// First end of the axis.
        a: Vector3<f64>,
        /// Second end of the axis.
        b: Vector3<f64>,
        /// Radius (≥ 0).
        radius: f64,
    },
    /// A box centred at `pose`'s origin, its sides along `pose`'s axes.
    Box {
        /// Link ← box transform.
        pose: Isometry3<f64>,
        /// Half side lengths (> 0).
        half_extents: Vector3<f64>,
    },
    /// A solid cylinder centred at `pose`'s origin, its axis along `pose`'s z.
    Cylinder {
        /// Link ← cylinder transform.
        pose: Isometry3<f64>,
        /// Radius (> 0).
        radius: f64,
        /// Half the length along the axis (> 0).
        half_length: f64,
    },
    /// The convex hull of a mesh's vertices (the mesh's file, scaled and placed in the link
    /// frame). A collision mesh that is not convex is checked as its hull, which encloses it.
    ConvexMesh {
        /// Where the vertices came from (the URDF `filename`, or a TOML file name).
        source: String,
        /// The distinct vertices, link frame.
        vertices: Vec<Vector3<f64>>,
    },
    /// A solid the description has but the model could not load or place (a collision mesh
    /// whose file was not read, a link that follows a moving mimic joint). Kinematics work;
    /// the collision checker refuses the robot, naming it — a verdict about a body with a
    /// part missing would not be about the real body.
    Missing {
        /// What is missing and why.
        what: String,
    },
}

impl BodyShape {
    /// The short kind name (`sphere`, `capsule`, `box`, `cylinder`, `mesh`).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            BodyShape::Sphere { .. } => "sphere",
            BodyShape::Capsule { .. } => "capsule",
            BodyShape::Box { .. } => "box",
            BodyShape::Cylinder { .. } => "cylinder",
            BodyShape::ConvexMesh { .. } => "mesh",
            BodyShape::Missing { .. } => "missing",
        }
    }

    /// The largest distance of a point of the solid from `p` (link frame), metres: what
    /// bounds how fast the solid's points move when the frame turns about an axis through `p`.
    #[must_use]
    pub fn farthest_from(&self, p: &Vector3<f64>) -> f64 {
        match self {
            BodyShape::Sphere { center, radius } => (center - p).norm() + radius,
            BodyShape::Capsule { a, b, radius } => (a - p).norm().max((b - p).norm()) + radius,
            BodyShape::Box { pose, half_extents } => {
                let mut far: f64 = 0.0;
                for i in 0..8 {
                    let s = |bit: usize| if i & bit == 0 { -1.0 } else { 1.0 };
                    let c = Vector3::new(s(1) * half_extents.x, s(2) * half_extents.y, s(4) * half_extents.z);
                    far = far.max((pose * Point3::from(c)).coords.metric_distance(p));
                }
                far
            }
            BodyShape::Cylinder { pose, radius, half_length } => {
                // The farthest point is on a rim: the rim's centre plus the radius bounds it.
                let axis = pose.rotation * Vector3::z();
                let c = pose.translation.vector;
                [c + axis * *half_length, c - axis * *half_length]
                    .iter()
                    .map(|e| {
                        let d = e - p;
                        let along = d.dot(&axis);
                        let across = (d - axis * along).norm();
                        (along * along + (across + radius) * (across + radius)).sqrt()
                    })
                    .fold(0.0, f64::max)
            }
            BodyShape::ConvexMesh { vertices, .. } => vertices.iter().map(|v| (v - p).norm()).fold(0.0, f64::max),
            BodyShape::Missing { .. } => f64::INFINITY,
        }
    }

    /// Checks every number (finite, radii and extents positive, a mesh with vertices).
    ///
    /// # Errors
    /// A message naming the field.
    fn validate(&self) -> Result<(), String> {
        let finite = |name: &str, v: &[f64]| {
            if v.iter().all(|x| x.is_finite()) { Ok(()) } else { Err(format!("`{name}` must be finite, got {v:?}")) }
        };
        let positive = |name: &str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(format!("`{name}` must be a finite number > 0, got {v}"))
            }
        };
        let pose_ok = |pose: &Isometry3<f64>| {
            finite("pose", pose.translation.vector.as_slice())?;
            finite("pose", pose.rotation.coords.as_slice())
        };
        match self {
            BodyShape::Sphere { center, radius } => {
                finite("center", center.as_slice())?;
                positive("radius", *radius)
            }
            BodyShape::Capsule { a, b, radius } => {
                finite("a", a.as_slice())?;
                finite("b", b.as_slice())?;
                if radius.is_finite() && *radius >= 0.0 {
                    Ok(())
                } else {
                    Err(format!("`radius` must be a finite number ≥ 0, got {radius}"))
                }
            }
            BodyShape::Box { pose, half_extents } => {
                pose_ok(pose)?;
                for v in half_extents.iter() {
                    positive("size", *v)?;
                }
                Ok(())
            }
            BodyShape::Cylinder { pose, radius, half_length } => {
                pose_ok(pose)?;
                positive("radius", *radius)?;
                positive("length", *half_length)
            }
            BodyShape::ConvexMesh { source, vertices } => {
                if vertices.is_empty() {
                    return Err(format!("mesh `{source}` has no vertices"));
                }
                if let Some(v) = vertices.iter().find(|v| !v.iter().all(|x| x.is_finite())) {
                    return Err(format!("mesh `{source}` has a vertex that is not finite: {v:?}"));
                }
                Ok(())
            }
            BodyShape::Missing { .. } => Ok(()),
        }
    }
}

/// The solids of one link, fixed to one frame of the chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LinkBody {
    /// The link's name (URDF `<link name>`, or the TOML entry's `name`): what reports and
    /// SRDF pairs call it.
    pub name: String,
    /// The chain frame the solids are fixed to: 0 the base, `k` the frame after joint `k`.
    pub frame: usize,
    /// The link's parent link (index into the robot's bodies), `None` for the base link or a
    /// link whose parent is not a body: parent and child are adjacent, never checked against
    /// each other (they touch at their joint).
    pub parent: Option<usize>,
    /// The solids, in frame `frame`'s coordinates.
    pub shapes: Vec<BodyShape>,
    /// Every point within this distance of the solids belongs to the body too, metres (≥ 0;
    /// MoveIt's link padding): a clearance of the padded body is a clearance above the
    /// padding of the solids.
    pub padding: f64,
}

/// A capsule that contains every point of `points` (and so their convex hull): its axis
/// along the points' principal direction (the covariance's largest eigenvector), its radius
/// the largest distance of a point from that axis, its ends pulled in as far as the
/// hemispherical caps still cover every point. `None` for no point or a non-finite one.
///
/// The fit is tight for elongated links (an arm's tube) and loose for flat or L-shaped
/// ones; [`BodyShape::farthest_from`] and a test against the points prove what it encloses.
#[must_use]
pub fn enclosing_capsule(points: &[Vector3<f64>]) -> Option<BodyShape> {
    if points.is_empty() || !points.iter().all(|p| p.iter().all(|x| x.is_finite())) {
        return None;
    }
    let n = points.len() as f64;
    let c = points.iter().sum::<Vector3<f64>>() / n;
    let cov = points.iter().fold(nalgebra::Matrix3::zeros(), |m, p| m + (p - c) * (p - c).transpose()) / n;
    let eigen = nalgebra::SymmetricEigen::new(cov);
    let (k, _) =
        eigen.eigenvalues.iter().enumerate().fold((0, f64::MIN), |b, (i, v)| if *v > b.1 { (i, *v) } else { b });
    let pca = eigen.eigenvectors.column(k).into_owned().try_normalize(1e-300).unwrap_or_else(Vector3::z);
    // The axis passes through the centre of the smallest circle around the points projected
    // on the plane across it (the smallest radius for that direction); the direction starts
    // at the principal one (which tilts with uneven sampling) and turns while that radius
    // shrinks.
    let across = |u: &Vector3<f64>| {
        let e1 = u.cross(&if u.x.abs() < 0.9 { Vector3::x() } else { Vector3::y() }).normalize();
        let e2 = u.cross(&e1);
        let flat: Vec<[f64; 2]> = points.iter().map(|p| [(p - c).dot(&e1), (p - c).dot(&e2)]).collect();
        let ([x, y], r) = smallest_circle(&flat);
        (r, c + e1 * x + e2 * y, e1, e2)
    };
    let (mut u, mut best) = (pca, across(&pca));
    let mut step = 0.05;
    while step > 1e-4 {
        let (_, _, e1, e2) = best;
        let tries = [u + e1 * step, u - e1 * step, u + e2 * step, u - e2 * step].map(|v| v.normalize());
        match tries.iter().map(|v| (*v, across(v))).min_by(|a, b| a.1.0.total_cmp(&b.1.0)) {
            Some((v, fit)) if fit.0 < best.0 => (u, best) = (v, fit),
            _ => step *= 0.5,
        }
    }
    let c = best.1;
    let split = |p: &Vector3<f64>| {
        let t = (p - c).dot(&u);
        (t, (p - c - u * t).norm())
    };
    // A rounding margin: every point stays inside after the arithmetic below.
    let radius = points.iter().map(|p| split(p).1).fold(0.0, f64::max) * (1.0 + 1e-9) + 1e-9;
    let reach = |d: f64| (radius * radius - d * d).max(0.0).sqrt();
    let hi = points
        .iter()
        .map(|p| {
            let (t, d) = split(p);
            t - reach(d)
        })
        .fold(f64::MIN, f64::max);
    let lo = points
        .iter()
        .map(|p| {
            let (t, d) = split(p);
            t + reach(d)
        })
        .fold(f64::MAX, f64::min);
    if lo <= hi {
        return Some(BodyShape::Capsule { a: c + u * lo, b: c + u * hi, radius });
    }
    // Every point is within the radius of the axis and the caps overlap: one ball around the
    // middle of the overlap holds them all.
    let m = c + u * (0.5 * (lo + hi));
    let r = points.iter().map(|p| (p - m).norm()).fold(0.0, f64::max) * (1.0 + 1e-9) + 1e-9;
    Some(BodyShape::Sphere { center: m, radius: r })
}

/// The smallest circle containing `points` (centre, radius): Welzl's algorithm, iterative, over
/// the points in a fixed pseudo-random order (expected linear time).
fn smallest_circle(points: &[[f64; 2]]) -> ([f64; 2], f64) {
    let mut p = points.to_vec();
    let mut rng = crate::rng::SplitMix64(0x5EED);
    for i in (1..p.len()).rev() {
        let j = (rng.next_f64() * (i + 1) as f64) as usize;
        p.swap(i, j.min(i));
    }
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let inside = |c: ([f64; 2], f64), q: [f64; 2]| d(c.0, q) <= c.1 * (1.0 + 1e-12) + 1e-15;
    let two = |a: [f64; 2], b: [f64; 2]| ([(a[0] + b[0]) * 0.5, (a[1] + b[1]) * 0.5], d(a, b) * 0.5);
    let three = |a: [f64; 2], b: [f64; 2], q: [f64; 2]| {
        let (bx, by, cx, cy) = (b[0] - a[0], b[1] - a[1], q[0] - a[0], q[1] - a[1]);
        let den = 2.0 * (bx * cy - by * cx);
        if den.abs() < 1e-300 {
            // Collinear: the circle on the two farthest apart.
            let (ab, aq, bq) = (two(a, b), two(a, q), two(b, q));
            return [ab, aq, bq].into_iter().fold(ab, |m, x| if x.1 > m.1 { x } else { m });
        }
        let (b2, c2) = (bx * bx + by * by, cx * cx + cy * cy);
        let o = [(cy * b2 - by * c2) / den, (bx * c2 - cx * b2) / den];
        ([a[0] + o[0], a[1] + o[1]], o[0].hypot(o[1]))
    };
    let mut circle = (p[0], 0.0);
    for i in 1..p.len() {
        if inside(circle, p[i]) {
            continue;
        }
        circle = (p[i], 0.0);
        for j in 0..i {
            if inside(circle, p[j]) {
                continue;
            }
            circle = two(p[i], p[j]);
            for k in 0..j {
                if !inside(circle, p[k]) {
                    circle = three(p[i], p[j], p[k]);
                }
            }
        }
    }
    circle
}

/// Checks a robot's bodies and disabled pairs against its number of joints.
///
/// # Errors
/// [`ModelError::Links`] naming the link and field.
pub(crate) fn validate_bodies(bodies: &[LinkBody], disabled: &[[String; 2]], dof: usize) -> Result<(), ModelError> {
    for (i, b) in bodies.iter().enumerate() {
        if b.frame > dof {
            return Err(ModelError::Links(format!(
                "body `{}`: frame {} does not exist (0 is the base, 1..{dof} the joints' frames)",
                b.name, b.frame
            )));
        }
        if bodies[..i].iter().any(|o| o.name == b.name) {
            return Err(ModelError::Links(format!("two bodies are named `{}`", b.name)));
        }
        if !(b.padding.is_finite() && b.padding >= 0.0) {
            return Err(ModelError::Links(format!(
                "body `{}`: `padding` must be a finite number ≥ 0, got {}",
                b.name, b.padding
            )));
        }
        if let Some(p) = b.parent
            && p >= bodies.len()
        {
            return Err(ModelError::Links(format!("body `{}`: parent index {p} does not exist", b.name)));
        }
        for (s, shape) in b.shapes.iter().enumerate() {
            shape.validate().map_err(|m| {
                ModelError::Links(format!("body `{}`, shape {} ({}): {m}", b.name, s + 1, shape.kind()))
            })?;
        }
    }
    for [a, b] in disabled {
        for name in [a, b] {
            if !bodies.iter().any(|x| &x.name == name) {
                let names: Vec<&str> = bodies.iter().map(|x| x.name.as_str()).collect();
                return Err(ModelError::Links(format!(
                    "disabled collision pair [`{a}`, `{b}`]: no link named `{name}` (links with bodies: {})",
                    if names.is_empty() { "none".to_string() } else { names.join(", ") }
                )));
            }
        }
    }
    Ok(())
}

/// The link pairs an SRDF document's `<disable_collisions link1=".." link2=".."/>` elements
/// name, in document order.
///
/// # Errors
/// [`ModelError::Urdf`] (prefixed `SRDF`) for XML errors or an element without both links.
pub fn srdf_disabled_pairs(text: &str) -> Result<Vec<[String; 2]>, ModelError> {
    let doc = roxmltree::Document::parse(text).map_err(|e| ModelError::Urdf(format!("SRDF: {e}")))?;
    let mut pairs = Vec::new();
    for node in doc.descendants().filter(|n| n.has_tag_name("disable_collisions")) {
        let pos = doc.text_pos_at(node.range().start);
        match (node.attribute("link1"), node.attribute("link2")) {
            (Some(a), Some(b)) => pairs.push([a.to_string(), b.to_string()]),
            _ => {
                return Err(ModelError::Urdf(format!(
                    "SRDF, line {}: <disable_collisions> needs both `link1` and `link2`",
                    pos.row
                )));
            }
        }
    }
    Ok(pairs)
}

/// The distinct vertices of a mesh file's triangles: binary or ASCII STL, or Wavefront OBJ
/// (its `v` lines), told apart by content; `name` names the file in messages.
///
/// # Errors
/// A message naming the file: an empty or truncated file, a number that does not parse or is
/// not finite, no vertex at all, more than [`MAX_MESH_TRIANGLES`] triangles, or a Collada
/// document (not read for collision: convert it to STL or OBJ).
pub fn mesh_vertices(name: &str, bytes: &[u8]) -> Result<Vec<Vector3<f64>>, String> {
    if bytes.is_empty() {
        return Err(format!("mesh `{name}` is empty"));
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(512)]).to_ascii_lowercase();
    let raw = if head.contains("<collada") {
        return Err(format!("mesh `{name}`: Collada (.dae) collision meshes are not read; convert it to STL or OBJ"));
    } else if head.trim_start().starts_with("solid") && !binary_stl_fits(bytes) {
        ascii_stl(name, bytes)?
    } else if binary_stl_fits(bytes) {
        binary_stl(name, bytes)?
    } else {
        obj(name, bytes)?
    };
    if raw.is_empty() {
        return Err(format!("mesh `{name}` has no vertices"));
    }
    if let Some(v) = raw.iter().find(|v| !v.iter().all(|x| x.is_finite())) {
        return Err(format!("mesh `{name}` has a vertex that is not finite: {v:?}"));
    }
    let mut seen = std::collections::HashSet::with_capacity(raw.len());
    Ok(raw.into_iter().filter(|v| seen.insert([v.x.to_bits(), v.y.to_bits(), v.z.to_bits()])).collect())
}

/// Whether `bytes` has exactly the length a binary STL's triangle count says.
fn binary_stl_fits(bytes: &[u8]) -> bool {
    bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        n.checked_mul(50).and_then(|b| b.checked_add(84)) == Some(bytes.len())
    }
}

fn too_many(name: &str, n: usize) -> String {
    format!("mesh `{name}` has {n} triangles, more than the cap of {MAX_MESH_TRIANGLES}")
}

fn binary_stl(name: &str, bytes: &[u8]) -> Result<Vec<Vector3<f64>>, String> {
    let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
    if n > MAX_MESH_TRIANGLES {
        return Err(too_many(name, n));
    }
    let f = |o: usize| f64::from(f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]));
    let mut out = Vec::with_capacity(3 * n);
    for t in 0..n {
        let base = 84 + 50 * t + 12;
        for v in 0..3 {
            let o = base + 12 * v;
            out.push(Vector3::new(f(o), f(o + 4), f(o + 8)));
        }
    }
    Ok(out)
}

fn ascii_stl(name: &str, bytes: &[u8]) -> Result<Vec<Vector3<f64>>, String> {
    let text = std::str::from_utf8(bytes).map_err(|_| format!("mesh `{name}`: an ASCII STL that is not UTF-8"))?;
    let mut out = Vec::new();
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        if words.next() != Some("vertex") {
            continue;
        }
        if out.len() >= 3 * MAX_MESH_TRIANGLES {
            return Err(too_many(name, out.len() / 3 + 1));
        }
        out.push(three(name, line_no + 1, words)?);
    }
    Ok(out)
}

fn obj(name: &str, bytes: &[u8]) -> Result<Vec<Vector3<f64>>, String> {
    let text = std::str::from_utf8(bytes)
        .map_err(|_| format!("mesh `{name}`: neither a binary STL (length does not match) nor a text OBJ/STL"))?;
    let mut out = Vec::new();
    let mut faces = 0_usize;
    for (line_no, line) in text.lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => out.push(three(name, line_no + 1, words)?),
            Some("f") => faces += line.split_whitespace().count().saturating_sub(3),
            _ => {}
        }
        if faces > MAX_MESH_TRIANGLES {
            return Err(too_many(name, faces));
        }
    }
    Ok(out)
}

fn three<'a>(name: &str, line: usize, mut words: impl Iterator<Item = &'a str>) -> Result<Vector3<f64>, String> {
    let mut v = [0.0; 3];
    for x in &mut v {
        let w = words.next().ok_or_else(|| format!("mesh `{name}`, line {line}: a vertex needs three numbers"))?;
        *x = w.parse().map_err(|_| format!("mesh `{name}`, line {line}: `{w}` is not a number"))?;
    }
    Ok(Vector3::from(v))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn meshes_parse_in_every_format_and_bad_ones_are_named() {
        let obj_text = "o cube\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 2 4\n";
        assert_eq!(mesh_vertices("a.obj", obj_text.as_bytes()).unwrap().len(), 4);
        let stl = "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n";
        assert_eq!(mesh_vertices("a.stl", stl.as_bytes()).unwrap().len(), 3);
        let mut bin = vec![0_u8; 80];
        bin.extend(1_u32.to_le_bytes());
        bin.extend([0_u8; 12]);
        for v in [[0.0_f32, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]] {
            for x in v {
                bin.extend(x.to_le_bytes());
            }
        }
        bin.extend([0_u8; 2]);
        let v = mesh_vertices("b.stl", &bin).unwrap();
        assert_eq!(v.len(), 3);
        assert_eq!(v[1], Vector3::new(2.0, 0.0, 0.0));
        assert!(mesh_vertices("e.stl", b"").unwrap_err().contains("empty"));
        assert!(mesh_vertices("x.obj", b"v 1 2\n").unwrap_err().contains("line 1"));
        assert!(mesh_vertices("x.obj", b"v 1 2 nan\n").unwrap_err().contains("not finite"));
        assert!(mesh_vertices("n.obj", b"# nothing\n").unwrap_err().contains("no vertices"));
        assert!(mesh_vertices("c.dae", b"<?xml?><COLLADA>").unwrap_err().contains("Collada"));
    }

    #[test]
    fn farthest_points_bound_every_solid() {
        let p = Vector3::new(0.1, -0.2, 0.3);
        let pose = Isometry3::new(Vector3::new(0.5, 0.0, 0.0), Vector3::new(0.3, 0.2, 0.1));
        let cyl = BodyShape::Cylinder { pose, radius: 0.1, half_length: 0.2 };
        let far = cyl.farthest_from(&p);
        // Points on the rims attain it; none is farther.
        let mut best: f64 = 0.0;
        for i in 0..360 {
            let a = f64::from(i).to_radians();
            for z in [-0.2, 0.2] {
                let q = pose * Point3::new(0.1 * a.cos(), 0.1 * a.sin(), z);
                best = best.max((q.coords - p).norm());
            }
        }
        assert!(far >= best - 1e-12 && far <= best + 1e-4, "{far} {best}");
        let bx = BodyShape::Box { pose, half_extents: Vector3::new(0.1, 0.2, 0.3) };
        assert!(bx.farthest_from(&p) >= (pose * Point3::new(0.1, 0.2, 0.3)).coords.metric_distance(&p));
    }

    #[test]
    fn an_enclosing_capsule_holds_every_point_and_is_tight_on_a_tube() {
        let mut rng = crate::rng::SplitMix64(3);
        // Points on a tube of radius 0.05 along a tilted axis, 0.4 long, with hemispherical ends.
        let axis = Vector3::new(1.0, 2.0, 0.5).normalize();
        let side = axis.cross(&Vector3::z()).normalize();
        let up = axis.cross(&side);
        let mut pts = Vec::new();
        for _ in 0..2000 {
            let (t, a) = (rng.next_f64() * 0.4, rng.next_f64() * std::f64::consts::TAU);
            pts.push(axis * t + (side * a.cos() + up * a.sin()) * 0.05 + Vector3::new(0.3, -0.1, 0.2));
        }
        let Some(BodyShape::Capsule { a, b, radius }) = enclosing_capsule(&pts) else { panic!() };
        for p in &pts {
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            assert!((p - (a + ab * t)).norm() <= radius, "a point outside");
        }
        assert!(radius < 0.0505 && (b - a).norm() <= 0.4 && (b - a).norm() > 0.3, "{radius} {}", (b - a).norm());
        assert!(enclosing_capsule(&[]).is_none());
        assert!(matches!(enclosing_capsule(&[Vector3::zeros()]), Some(BodyShape::Sphere { .. })));
    }

    #[test]
    fn srdf_pairs_are_read() {
        let text = r#"<robot name="r"><disable_collisions link1="a" link2="b" reason="Adjacent"/>
            <disable_collisions link1="c" link2="d" reason="Never"/></robot>"#;
        assert_eq!(srdf_disabled_pairs(text).unwrap(), vec![["a".to_string(), "b".into()], ["c".into(), "d".into()]]);
        assert!(
            srdf_disabled_pairs("<robot><disable_collisions link1=\"a\"/></robot>")
                .unwrap_err()
                .to_string()
                .contains("link2")
        );
        assert!(srdf_disabled_pairs("<robot>").is_err());
    }
}
