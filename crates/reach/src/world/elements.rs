//! The robot's body as the collision checker tests it: a list of elements, each a solid fixed
//! to one chain frame (a body's sphere, capsule, box, cylinder or convex mesh), or — for a
//! robot without bodies — the stick figure's segments between consecutive frame origins,
//! swept by the links' radii. Placed in the world once per configuration, allocation-free.

use nalgebra::{IsometryMatrix3, Matrix3, Point3, Vector3};

use super::WorldError;
use super::gjk::{self, Convex};
use super::shape::Shape;
use super::sweep::segment_rate;
use crate::model::{BodyShape, Robot};
use crate::tolerance::CONTACT;

/// An element's solid in its frame's coordinates.
#[derive(Debug, Clone, Copy)]
enum Local<'a> {
    /// Stick segment `k`: chain points `k` and `k + 1` (not fixed to one frame).
    Segment(usize),
    /// A capsule's axis (a sphere: both ends equal).
    Capsule(Vector3<f64>, Vector3<f64>),
    /// Box centre, frame ← box rotation, half-extents.
    Box(Vector3<f64>, Matrix3<f64>, Vector3<f64>),
    /// Cylinder centre, unit axis, radius, half-length.
    Cylinder(Vector3<f64>, Vector3<f64>, f64, f64),
    /// Convex hull of these vertices.
    Hull(&'a [Vector3<f64>]),
}

/// One element: its solid, what it belongs to, and its bounds.
#[derive(Debug, Clone)]
pub(crate) struct Element<'a> {
    local: Local<'a>,
    /// 0-based link: the stick segment's number, or the index into [`Robot::bodies`].
    pub(crate) link: usize,
    /// The chain frame the solid is fixed to (0 base, `k` after joint `k`); for stick segment
    /// `k`, `k + 1` (its far end's frame).
    frame: usize,
    /// The radius the core solid is swept by (capsule radius plus the body's padding).
    pub(crate) radius: f64,
    /// Bounding sphere of the core solid in frame coordinates: centre and radius.
    bound: (Vector3<f64>, f64),
    /// The farthest point of the element (radius included) from its frame's origin.
    reach: f64,
}

/// An element placed in the world.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Placed<'a> {
    /// A segment (a point when both ends are equal).
    Capsule(Vector3<f64>, Vector3<f64>),
    /// A convex solid.
    Convex(Convex<'a>),
}

impl Placed<'_> {
    fn convex(&self) -> Convex<'_> {
        match *self {
            Placed::Capsule(a, b) if a == b => Convex::Point(a),
            Placed::Capsule(a, b) => Convex::Segment(a, b),
            Placed::Convex(c) => c,
        }
    }
}

/// The elements of one robot and where they are.
#[derive(Debug, Clone)]
pub(crate) struct Elements<'a> {
    pub(crate) list: Vec<Element<'a>>,
    /// World placement of each element (the last configuration placed).
    pub(crate) placed: Vec<Placed<'a>>,
    /// World bounding sphere of each element, radius included.
    pub(crate) spheres: Vec<(Vector3<f64>, f64)>,
    /// Whether these are the stick figure's segments (no bodies).
    pub(crate) stick: bool,
    /// Name of each 0-based link.
    pub(crate) names: Vec<String>,
    /// Per 0-based link: the nearest ancestor link that has solids (bodies only).
    parents: Vec<Option<usize>>,
}

impl<'a> Elements<'a> {
    /// The elements of `robot`: its bodies' solids, or the stick figure without bodies.
    ///
    /// # Errors
    /// [`WorldError::Input`] naming the link when a body has a [`BodyShape::Missing`] solid.
    pub(crate) fn of(robot: &'a Robot) -> Result<Self, WorldError> {
        let n = robot.dof();
        let bodies = robot.bodies();
        let mut list = Vec::new();
        if bodies.is_empty() {
            let radii = robot.segment_radii();
            for (k, &radius) in radii.iter().enumerate() {
                list.push(Element {
                    local: Local::Segment(k),
                    link: k,
                    frame: k + 1,
                    radius,
                    bound: (Vector3::zeros(), 0.0),
                    reach: 0.0,
                });
            }
            let names = (0..=n).map(|k| robot.joints().get(k).map_or_else(|| "tool".to_string(), |j| j.name.clone()));
            let count = list.len();
            return Ok(Elements {
                list,
                placed: vec![Placed::Capsule(Vector3::zeros(), Vector3::zeros()); count],
                spheres: vec![(Vector3::zeros(), 0.0); count],
                stick: true,
                names: names.collect(),
                parents: Vec::new(),
            });
        }
        for (link, body) in bodies.iter().enumerate() {
            for shape in &body.shapes {
                let origin = Vector3::zeros();
                let (local, radius, bound) = match shape {
                    BodyShape::Sphere { center, radius } => (Local::Capsule(*center, *center), *radius, (*center, 0.0)),
                    BodyShape::Capsule { a, b, radius } => {
                        (Local::Capsule(*a, *b), *radius, ((a + b) * 0.5, (b - a).norm() * 0.5))
                    }
                    BodyShape::Box { pose, half_extents } => {
                        let c = pose.translation.vector;
                        (
                            Local::Box(c, *pose.rotation.to_rotation_matrix().matrix(), *half_extents),
                            0.0,
                            (c, half_extents.norm()),
                        )
                    }
                    BodyShape::Cylinder { pose, radius, half_length } => {
                        let c = pose.translation.vector;
                        let u = pose.rotation * Vector3::z();
                        (Local::Cylinder(c, u, *radius, *half_length), 0.0, (c, radius.hypot(*half_length)))
                    }
                    BodyShape::ConvexMesh { vertices, .. } => {
                        let (mut lo, mut hi) = (vertices[0], vertices[0]);
                        for v in vertices {
                            lo = lo.inf(v);
                            hi = hi.sup(v);
                        }
                        let c = (lo + hi) * 0.5;
                        let r = vertices.iter().map(|v| (v - c).norm()).fold(0.0, f64::max);
                        (Local::Hull(vertices), 0.0, (c, r))
                    }
                    BodyShape::Missing { what } => {
                        return Err(WorldError::Input(format!(
                            "robot `{}` has no complete collision body: {what}",
                            robot.name()
                        )));
                    }
                };
                let radius = radius + body.padding;
                list.push(Element {
                    local,
                    link,
                    frame: body.frame,
                    radius,
                    bound: (bound.0, bound.1 + radius),
                    reach: shape.farthest_from(&origin) + body.padding,
                });
            }
        }
        let parents = (0..bodies.len())
            .map(|l| {
                let mut p = bodies[l].parent;
                while let Some(i) = p {
                    if !bodies[i].shapes.is_empty() {
                        return Some(i);
                    }
                    p = bodies[i].parent;
                }
                None
            })
            .collect();
        let count = list.len();
        Ok(Elements {
            list,
            placed: vec![Placed::Capsule(Vector3::zeros(), Vector3::zeros()); count],
            spheres: vec![(Vector3::zeros(), 0.0); count],
            stick: false,
            names: bodies.iter().map(|b| b.name.clone()).collect(),
            parents,
        })
    }

    /// No elements (the stand-in for a body that could not be built; every check refuses it).
    pub(crate) fn of_nothing() -> Self {
        Elements {
            list: Vec::new(),
            placed: Vec::new(),
            spheres: Vec::new(),
            stick: false,
            names: Vec::new(),
            parents: Vec::new(),
        }
    }

    /// Whether two different body links are adjacent (one is the other's nearest ancestor
    /// with solids): they touch at their joint and are never checked against each other.
    pub(crate) fn adjacent(&self, a: usize, b: usize) -> bool {
        self.parents.get(a).copied().flatten() == Some(b) || self.parents.get(b).copied().flatten() == Some(a)
    }

    /// Places every element: `frames[k − 1]` is frame `k`, `base` frame 0, `points` the
    /// chain points (base origin, frame origins, tool point).
    pub(crate) fn place(
        &mut self,
        base: &IsometryMatrix3<f64>,
        frames: &[IsometryMatrix3<f64>],
        points: &[Vector3<f64>],
    ) {
        for ((e, placed), sphere) in self.list.iter().zip(&mut self.placed).zip(&mut self.spheres) {
            let f = if e.frame == 0 { base } else { &frames[(e.frame - 1).min(frames.len() - 1)] };
            let at = |v: &Vector3<f64>| (f * Point3::from(*v)).coords;
            *placed = match e.local {
                Local::Segment(k) => Placed::Capsule(points[k], points[k + 1]),
                Local::Capsule(a, b) => Placed::Capsule(at(&a), at(&b)),
                Local::Box(c, r, h) => Placed::Convex(Convex::Box(at(&c), f.rotation.matrix() * r, h)),
                Local::Cylinder(c, u, r, h) => Placed::Convex(Convex::Cylinder(at(&c), f.rotation * u, r, h)),
                Local::Hull(v) => Placed::Convex(Convex::Hull(*f.rotation.matrix(), f.translation.vector, v)),
            };
            *sphere = match *placed {
                Placed::Capsule(a, b) => ((a + b) * 0.5, (b - a).norm() * 0.5 + e.radius),
                Placed::Convex(_) => (at(&e.bound.0), e.bound.1),
            };
        }
    }

    /// Signed clearance of element `e` to `shape` moved by `-shift`, metres (a certified lower
    /// bound for solids GJK measures; see [`Shape::convex_distance`]).
    #[inline]
    pub(crate) fn obstacle_clearance(&self, e: usize, shape: &Shape, shift: &Vector3<f64>) -> f64 {
        let r = self.list[e].radius;
        match self.placed[e] {
            Placed::Capsule(a, b) => shape.segment_sdf(&(a - shift), &(b - shift)) - r,
            Placed::Convex(c) => shape.convex_distance(&shifted(c, shift)) - r,
        }
    }

    /// Whether element `e` comes within `margin` of `shape` moved by `-shift` (early outs for
    /// capsules against boxes, [`Shape::segment_within`]).
    #[inline]
    pub(crate) fn obstacle_within(&self, e: usize, shape: &Shape, shift: &Vector3<f64>, margin: f64) -> bool {
        let r = self.list[e].radius;
        match self.placed[e] {
            Placed::Capsule(a, b) => shape.segment_within(&(a - shift), &(b - shift), r, margin),
            Placed::Convex(c) => shape.convex_distance(&shifted(c, shift)) - r <= margin,
        }
    }

    /// Signed clearance between elements `i` and `j`, metres (exact for capsules, a certified
    /// lower bound by GJK otherwise; overlapping convex cores give `−2·CONTACT` less both radii).
    #[inline]
    pub(crate) fn pair_clearance(&self, i: usize, j: usize) -> f64 {
        let r = self.list[i].radius + self.list[j].radius;
        match (self.placed[i], self.placed[j]) {
            (Placed::Capsule(a, b), Placed::Capsule(c, d)) => {
                super::distance::segment_segment_sq(&a, &b, &c, &d).sqrt() - r
            }
            (x, y) => {
                let d = gjk::distance(&x.convex(), &y.convex());
                if d > 0.0 { d - r } else { -2.0 * CONTACT - r }
            }
        }
    }

    /// Rate bound of element `e`'s points along the straight motion with joint changes
    /// `delta` ([`segment_rate`]; `lengths` bound the chain segments over the motion),
    /// relative to the frames the joints before `first` (0-based) move rigidly with it.
    pub(crate) fn rate(&self, e: usize, lengths: &[f64], revolute: &[bool], delta: &[f64], first: usize) -> f64 {
        let el = &self.list[e];
        match el.local {
            Local::Segment(k) => segment_rate(lengths, revolute, delta, first, k, el.radius),
            _ if el.frame == 0 => 0.0,
            // Within `reach` of frame `f`'s origin, the end of chain segment `f − 1`.
            _ => segment_rate(lengths, revolute, delta, first, el.frame - 1, el.reach),
        }
    }

    /// Rate bound of the clearance between elements `i` and `j` along the motion: only the
    /// joints between their frames move one relative to the other.
    pub(crate) fn pair_rate(&self, i: usize, j: usize, lengths: &[f64], revolute: &[bool], delta: &[f64]) -> f64 {
        let (a, b) = (&self.list[i], &self.list[j]);
        let (near, far) = if a.frame <= b.frame { (i, j) } else { (j, i) };
        if self.stick {
            // Segment i is moved by joints 0..=i, not rigidly with one frame: from joint i on.
            return self.rate(far, lengths, revolute, delta, self.list[near].link);
        }
        self.rate(far, lengths, revolute, delta, self.list[near].frame)
    }
}

/// A convex solid moved by `-shift`.
fn shifted<'c>(c: Convex<'c>, shift: &Vector3<f64>) -> Convex<'c> {
    match c {
        Convex::Point(p) => Convex::Point(p - shift),
        Convex::Segment(a, b) => Convex::Segment(a - shift, b - shift),
        Convex::Box(p, r, h) => Convex::Box(p - shift, r, h),
        Convex::Cylinder(p, u, r, h) => Convex::Cylinder(p - shift, u, r, h),
        Convex::Hull(r, t, v) => Convex::Hull(r, t - shift, v),
    }
}
