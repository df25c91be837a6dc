//! Obstacle and zone shapes, SI units, world frame.

use nalgebra::{Matrix3, Vector3};
use serde::Serialize;

use super::distance::{point_box_sdf, point_segment_sq, segment_box_clip, segment_box_sdf, segment_segment_sq};
use super::gjk::{self, Convex};
use crate::tolerance::CONTACT;

/// A solid (or a point) in the world frame, metres.
///
/// Every shape has a signed distance function (negative inside) and a
/// [`Shape::segment_sdf`], the minimum of that function over a segment: exact for points,
/// spheres, boxes, capsules and half-spaces; for cylinders and meshes a certified lower bound
/// of the distance when apart (GJK), exact for a point against a cylinder.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "shape", rename_all = "snake_case")]
#[non_exhaustive]
pub enum Shape {
    /// A single point (e.g. seed 000's sensed obstacle `H`).
    Point {
        /// Position.
        at: Vector3<f64>,
    },
    /// A ball.
    Sphere {
        /// Centre.
        center: Vector3<f64>,
        /// Radius (> 0).
        radius: f64,
    },
    /// A box, axis-aligned (`rotation` identity) or oriented; a planar rectangle is a box with
    /// a zero half-extent along its local z.
    Box {
        /// Centre.
        center: Vector3<f64>,
        /// Half-extents along the box's local axes (≥ 0; only a rectangle has a zero one).
        half_extents: Vector3<f64>,
        /// World ← box rotation (columns: the box axes in the world frame).
        rotation: Matrix3<f64>,
    },
    /// All points within `radius` of segment `ab`.
    Capsule {
        /// First end of the axis.
        a: Vector3<f64>,
        /// Second end of the axis.
        b: Vector3<f64>,
        /// Radius (> 0).
        radius: f64,
    },
    /// A solid cylinder.
    Cylinder {
        /// Centre (the middle of the axis).
        center: Vector3<f64>,
        /// World ← cylinder rotation: the axis is its third column.
        rotation: Matrix3<f64>,
        /// Radius (> 0).
        radius: f64,
        /// Half the length along the axis (> 0).
        half_length: f64,
    },
    /// The convex hull of a set of points (a mesh obstacle is checked as its hull, which
    /// encloses it).
    ConvexMesh {
        /// The hull's vertices (distinct points), world frame.
        vertices: Vec<Vector3<f64>>,
    },
    /// The half-space `{p : n·p ≤ offset}`; `n` is the unit **outward** normal (pointing to
    /// the free side).
    HalfSpace {
        /// Unit outward normal.
        normal: Vector3<f64>,
        /// `n·p` on the boundary plane.
        offset: f64,
    },
}

impl Shape {
    /// The short kind name used in files and messages (`point`, `sphere`, `box`, …).
    #[must_use]
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Point { .. } => "point",
            Shape::Sphere { .. } => "sphere",
            Shape::Box { half_extents, .. } if half_extents.z == 0.0 => "rectangle",
            Shape::Box { .. } => "box",
            Shape::Capsule { .. } => "capsule",
            Shape::Cylinder { .. } => "cylinder",
            Shape::ConvexMesh { .. } => "mesh",
            Shape::HalfSpace { .. } => "halfspace",
        }
    }

    /// A sphere `(centre, radius)` containing the shape; `None` for a half-space.
    #[must_use]
    pub fn bounding_sphere(&self) -> Option<(Vector3<f64>, f64)> {
        match self {
            Shape::Point { at } => Some((*at, 0.0)),
            Shape::Sphere { center, radius } => Some((*center, *radius)),
            Shape::Box { center, half_extents, .. } => Some((*center, half_extents.norm())),
            Shape::Capsule { a, b, radius } => Some(((a + b) * 0.5, (b - a).norm() * 0.5 + radius)),
            Shape::Cylinder { center, radius, half_length, .. } => Some((*center, radius.hypot(*half_length))),
            Shape::ConvexMesh { vertices } => {
                let (mut lo, mut hi) = (vertices[0], vertices[0]);
                for v in vertices.iter() {
                    lo = lo.inf(v);
                    hi = hi.sup(v);
                }
                let c = (lo + hi) * 0.5;
                Some((c, vertices.iter().map(|v| (v - c).norm()).fold(0.0, f64::max)))
            }
            Shape::HalfSpace { .. } => None,
        }
    }

    /// Signed distance from point `p` to the shape (negative inside).
    #[must_use]
    pub fn point_sdf(&self, p: &Vector3<f64>) -> f64 {
        match self {
            Shape::Point { at } => (p - at).norm(),
            Shape::Sphere { center, radius } => (p - center).norm() - radius,
            Shape::Box { center, half_extents, rotation } => {
                point_box_sdf(&(rotation.transpose() * (p - center)), half_extents)
            }
            Shape::Capsule { a, b, radius } => point_segment_sq(p, a, b).sqrt() - radius,
            Shape::Cylinder { center, rotation, radius, half_length } => {
                let l = rotation.transpose() * (p - center);
                let (dr, dz) = (l.xy().norm() - radius, l.z.abs() - half_length);
                if dr <= 0.0 && dz <= 0.0 { dr.max(dz) } else { dr.max(0.0).hypot(dz.max(0.0)) }
            }
            Shape::ConvexMesh { .. } => self.convex_distance(&Convex::Point(*p)),
            Shape::HalfSpace { normal, offset } => normal.dot(p) - offset,
        }
    }

    /// The shape as a support-mapped convex solid and the radius it is inflated by (`None`
    /// for a half-space).
    pub(crate) fn convex(&self) -> Option<(Convex<'_>, f64)> {
        Some(match self {
            Shape::Point { at } => (Convex::Point(*at), 0.0),
            Shape::Sphere { center, radius } => (Convex::Point(*center), *radius),
            Shape::Box { center, half_extents, rotation } => (Convex::Box(*center, *rotation, *half_extents), 0.0),
            Shape::Capsule { a, b, radius } => (Convex::Segment(*a, *b), *radius),
            Shape::Cylinder { center, rotation, radius, half_length } => {
                (Convex::Cylinder(*center, rotation.column(2).into_owned(), *radius, *half_length), 0.0)
            }
            Shape::ConvexMesh { vertices } => (Convex::Hull(Matrix3::identity(), Vector3::zeros(), vertices), 0.0),
            Shape::HalfSpace { .. } => return None,
        })
    }

    /// A lower bound of the signed distance between the shape and the convex solid `other`
    /// (GJK, [`super::gjk`]): their distance when apart (certified lower bound), and when they
    /// overlap `−2·CONTACT` less the shape's radius — the depth is not measured, and this
    /// value collides under either touching policy. A half-space is exact: the support point
    /// of `other` deepest along its normal.
    #[must_use]
    pub(crate) fn convex_distance(&self, other: &Convex) -> f64 {
        match self.convex() {
            None => {
                let Shape::HalfSpace { normal, offset } = self else {
                    unreachable!("only a half-space has no support")
                };
                normal.dot(&other.support(&-normal)) - offset
            }
            Some((c, r)) => {
                let d = gjk::distance(&c, other);
                if d > 0.0 { d - r } else { -2.0 * CONTACT - r }
            }
        }
    }

    /// The minimum of the shape's signed distance over segment `ab`: the distance between
    /// segment and shape when apart (≥ 0), the negated deepest penetration otherwise.
    ///
    /// # Performance
    /// Closed form for points, spheres, capsules and half-spaces (one segment–point or
    /// segment–segment distance); boxes take up to 14 point/edge distances when apart.
    #[must_use]
    #[inline]
    pub fn segment_sdf(&self, a: &Vector3<f64>, b: &Vector3<f64>) -> f64 {
        match self {
            Shape::Point { at } => point_segment_sq(at, a, b).sqrt(),
            Shape::Sphere { center, radius } => point_segment_sq(center, a, b).sqrt() - radius,
            Shape::Box { center, half_extents, rotation } => {
                let rt = rotation.transpose();
                segment_box_sdf(&(rt * (a - center)), &(rt * (b - center)), half_extents)
            }
            Shape::Capsule { a: c, b: d, radius } => segment_segment_sq(a, b, c, d).sqrt() - radius,
            Shape::Cylinder { .. } if a == b => self.point_sdf(a),
            Shape::Cylinder { .. } | Shape::ConvexMesh { .. } => self.convex_distance(&Convex::Segment(*a, *b)),
            Shape::HalfSpace { normal, offset } => normal.dot(a).min(normal.dot(b)) - offset,
        }
    }

    /// Whether segment `ab` swept by `radius` comes within `margin` of the shape, i.e.
    /// `segment_sdf(a, b) − radius ≤ margin` — with cheap early answers (bounding sphere, then
    /// the box inflated by `radius + margin`) before the exact distance.
    #[must_use]
    #[inline]
    pub fn segment_within(&self, a: &Vector3<f64>, b: &Vector3<f64>, radius: f64, margin: f64) -> bool {
        let reach = radius + margin;
        match self {
            Shape::Box { center, half_extents, rotation } => {
                let bound = half_extents.norm();
                let r2 = bound + reach;
                if r2 >= 0.0 && point_segment_sq(center, a, b) > r2 * r2 {
                    return false;
                }
                let rt = rotation.transpose();
                let (la, lb) = (rt * (a - center), rt * (b - center));
                if reach >= 0.0 && segment_box_clip(&la, &lb, half_extents).is_some() {
                    return true;
                }
                let grown = half_extents.add_scalar(reach.max(0.0));
                if segment_box_clip(&la, &lb, &grown).is_none() {
                    return false;
                }
                segment_box_sdf(&la, &lb, half_extents) <= reach
            }
            _ => self.segment_sdf(a, b) <= reach,
        }
    }
}
