//! Scene description: obstacles and the tool's allowed zone, parsed from TOML.

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

use super::{Shape, WorldError};
use crate::model::{AngleUnit, LengthUnit};

/// Whether an obstacle touched by a link (clearance within [`crate::tolerance::CONTACT`] of
/// zero) counts as a collision.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Touching {
    /// Obstacles are closed sets: touching is a collision (the default; the safe reading).
    #[default]
    Closed,
    /// Obstacles are open sets: touching is allowed, only penetration collides.
    Open,
}

/// A named obstacle (forbidden zone), fixed or moving at a known constant velocity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Obstacle {
    /// Name from the file (or `obstacle{i}`).
    pub name: String,
    /// The solid, SI units, where it is at time 0 (the start of the motion checked).
    pub shape: Shape,
    /// Constant velocity, m/s: at time `t` (seconds from the start of the motion checked) the
    /// solid is `shape` translated by `velocity·t`. Zero for a fixed obstacle and for every
    /// tool-zone entry.
    #[serde(rename = "velocity_m_s")]
    pub velocity: Vector3<f64>,
}

impl Obstacle {
    /// Whether the obstacle moves (a non-zero velocity).
    #[must_use]
    pub fn moves(&self) -> bool {
        self.velocity != Vector3::zeros()
    }

    /// How far the obstacle has moved at time `t` (seconds from the start of the motion),
    /// metres: `velocity·t`.
    #[must_use]
    pub fn displacement(&self, t: f64) -> Vector3<f64> {
        self.velocity * t
    }
}

/// Obstacles, the tool's allowed zone and the touching policy.
///
/// # File format (TOML)
/// ```toml
/// length_unit = "mm"          # "m" or "mm"
/// angle_unit = "deg"          # "deg" or "rad" (for `rpy`)
/// touching = "closed"         # or "open" (optional, default closed)
///
/// [[obstacles]]
/// name = "ceiling"
/// shape = "halfspace"         # the solid {p : n·(p − point) ≤ 0}
/// point = [0, 0, 1200]
/// outward_normal = [0, 0, -1] # points to the free side
///
/// [[tool_zone]]               # the tool point must be strictly inside every entry
/// name = "x > 500"
/// shape = "halfspace"
/// point = [500, 0, 0]
/// outward_normal = [-1, 0, 0]
/// ```
/// An obstacle may move: `velocity = [vx, vy, vz]` (in `length_unit` per second; constant,
/// the shape's fields give its place at time 0, the start of the motion checked).
/// Shapes and their fields: `point` (`at`), `sphere` (`center`, `radius`), `aabb` (`min`,
/// `max`), `box` (`center`, `half_extents`, optional `rpy`), `capsule` (`a`, `b`, `radius`),
/// `cylinder` (`center`, `radius`, `length`, optional `rpy`; the axis is the rotated z),
/// `halfspace` (`point`, `outward_normal`), `rectangle` (`center`, `half_extents = [hx, hy]`,
/// optional `rpy`; the rectangle lies in its local x–y plane).
/// `allowed_self_collisions = [["wrist_1", "wrist_3"]]` (optional) exempts link pairs from
/// the self-collision check.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Scene {
    /// Forbidden zones.
    pub obstacles: Vec<Obstacle>,
    /// The tool point must lie strictly inside each of these (their intersection); empty
    /// means anywhere.
    pub tool_zone: Vec<Obstacle>,
    /// Touching policy for obstacles.
    pub touching: Touching,
    /// Pairs of links exempt from the self-collision check (an allowed-collision list, like
    /// MoveIt's allowed-collision matrix), by link name: a joint name of the robot (link `k`
    /// is the segment ending at joint `k`'s frame), `link<k>` (1-based) or `tool`. Names are
    /// resolved against the robot by [`super::CollisionChecker::try_new`].
    pub allowed_self_collisions: Vec<[String; 2]>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    length_unit: LengthUnit,
    #[serde(default = "default_angle")]
    angle_unit: AngleUnit,
    #[serde(default)]
    touching: Touching,
    #[serde(default)]
    obstacles: Vec<ShapeField>,
    #[serde(default)]
    tool_zone: Vec<ShapeField>,
    #[serde(default)]
    allowed_self_collisions: Vec<Vec<String>>,
}

fn default_angle() -> AngleUnit {
    AngleUnit::Degree
}

#[derive(Deserialize, Default)]
#[serde(deny_unknown_fields)]
struct ShapeField {
    name: Option<String>,
    shape: String,
    at: Option<[f64; 3]>,
    center: Option<[f64; 3]>,
    radius: Option<f64>,
    min: Option<[f64; 3]>,
    max: Option<[f64; 3]>,
    half_extents: Option<Vec<f64>>,
    rpy: Option<[f64; 3]>,
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
    point: Option<[f64; 3]>,
    outward_normal: Option<[f64; 3]>,
    length: Option<f64>,
    velocity: Option<[f64; 3]>,
}

impl ShapeField {
    fn present(&self) -> Vec<&'static str> {
        let mut v = Vec::new();
        let fields: [(&'static str, bool); 12] = [
            ("length", self.length.is_some()),
            ("at", self.at.is_some()),
            ("center", self.center.is_some()),
            ("radius", self.radius.is_some()),
            ("min", self.min.is_some()),
            ("max", self.max.is_some()),
            ("half_extents", self.half_extents.is_some()),
            ("rpy", self.rpy.is_some()),
            ("a", self.a.is_some()),
            ("b", self.b.is_some()),
            ("point", self.point.is_some()),
            ("outward_normal", self.outward_normal.is_some()),
        ];
        for (name, p) in fields {
            if p {
                v.push(name);
            }
        }
        v
    }
}

fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.chars().count(), |nl| before[nl + 1..].chars().count()) + 1;
    (line, column)
}

impl Scene {
    /// An empty scene (no obstacle, tool anywhere, closed obstacles).
    #[must_use]
    pub fn new() -> Self {
        Scene::default()
    }

    /// Parses a TOML scene (format in the type's documentation).
    ///
    /// # Errors
    /// [`WorldError::Parse`] with line and column for syntax errors, unknown fields and wrong
    /// types; [`WorldError::Shape`] naming the shape for an unknown kind, a missing or foreign
    /// field, NaN/infinity, a radius ≤ 0, an inverted or flat box, a zero normal, or a
    /// rotation that is not finite; [`WorldError::Input`] for an `allowed_self_collisions`
    /// entry that is not a pair of names.
    pub fn from_toml_str(text: &str) -> Result<Scene, WorldError> {
        let file: SceneFile = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((1, 1), |s| line_column(text, s.start));
            WorldError::Parse { line, column, message: e.message().trim().to_string() }
        })?;
        let (ls, an) = (file.length_unit.to_si(), file.angle_unit.to_si());
        let mut scene = Scene { touching: file.touching, ..Scene::default() };
        for (i, pair) in file.allowed_self_collisions.into_iter().enumerate() {
            let [a, b]: [String; 2] = pair.try_into().map_err(|p: Vec<String>| {
                WorldError::Input(format!(
                    "allowed_self_collisions entry {}: needs two link names, got {}",
                    i + 1,
                    p.len()
                ))
            })?;
            scene.allowed_self_collisions.push([a, b]);
        }
        for (i, f) in file.obstacles.into_iter().enumerate() {
            let name = f.name.clone().unwrap_or_else(|| format!("obstacle{}", i + 1));
            let shape = build_shape("obstacle", &name, &f, ls, an)?;
            let velocity = match f.velocity {
                None => Vector3::zeros(),
                Some(v) if v.iter().all(|x| x.is_finite()) => Vector3::from(v) * ls,
                Some(v) => {
                    return Err(shape_error(
                        "obstacle",
                        &name,
                        &f.shape,
                        format!("`velocity` must be finite numbers, got {v:?}"),
                    ));
                }
            };
            scene.obstacles.push(Obstacle { name, shape, velocity });
        }
        for (i, f) in file.tool_zone.into_iter().enumerate() {
            let name = f.name.clone().unwrap_or_else(|| format!("zone{}", i + 1));
            let shape = build_shape("tool zone", &name, &f, ls, an)?;
            if f.velocity.is_some() {
                return Err(shape_error(
                    "tool zone",
                    &name,
                    &f.shape,
                    "`velocity` applies to obstacles only; the tool zone is fixed",
                ));
            }
            if matches!(shape, Shape::Point { .. }) {
                return Err(WorldError::Shape {
                    what: "tool zone",
                    name,
                    shape: "point".into(),
                    message: "a point has no inside; use a solid shape".into(),
                });
            }
            scene.tool_zone.push(Obstacle { name, shape, velocity: Vector3::zeros() });
        }
        Ok(scene)
    }

    /// Adds an obstacle after checking its numbers (builder style).
    ///
    /// # Errors
    /// [`WorldError::Shape`] for NaN/infinity or a degenerate shape.
    pub fn with_obstacle(mut self, name: impl Into<String>, shape: Shape) -> Result<Self, WorldError> {
        let name = name.into();
        validate("obstacle", &name, &shape)?;
        self.obstacles.push(Obstacle { name, shape, velocity: Vector3::zeros() });
        Ok(self)
    }

    /// Adds an obstacle moving at the constant `velocity` (m/s; `shape` is its place at time
    /// 0) after checking its numbers (builder style).
    ///
    /// # Errors
    /// [`WorldError::Shape`] for NaN/infinity (in the shape or the velocity) or a degenerate
    /// shape.
    pub fn with_moving_obstacle(
        mut self,
        name: impl Into<String>,
        shape: Shape,
        velocity: Vector3<f64>,
    ) -> Result<Self, WorldError> {
        let name = name.into();
        validate("obstacle", &name, &shape)?;
        if !velocity.iter().all(|x| x.is_finite()) {
            return Err(shape_error(
                "obstacle",
                &name,
                shape.kind(),
                format!("`velocity` must be finite numbers, got {:?} m/s", velocity.as_slice()),
            ));
        }
        self.obstacles.push(Obstacle { name, shape, velocity });
        Ok(self)
    }

    /// The first obstacle that moves, if any.
    #[must_use]
    pub fn moving_obstacle(&self) -> Option<&Obstacle> {
        self.obstacles.iter().find(|o| o.moves())
    }

    /// Refuses a scene with a moving obstacle for a computation that treats obstacles as
    /// fixed (`what`: the computation, e.g. "the planner"), rather than silently taking the
    /// obstacle where it is at time 0.
    ///
    /// # Errors
    /// [`WorldError::Input`] naming the first moving obstacle and its velocity.
    pub fn require_fixed(&self, what: &str) -> Result<(), WorldError> {
        match self.moving_obstacle() {
            None => Ok(()),
            Some(o) => Err(WorldError::Input(format!(
                "obstacle `{}` moves (velocity [{}, {}, {}] m/s), but {what} treats obstacles as fixed; \
                 check a timed motion against moving obstacles instead (`reach check --to … --duration`, \
                 `reach check --motion`, `reach move --scene`)",
                o.name, o.velocity.x, o.velocity.y, o.velocity.z
            ))),
        }
    }

    /// Refuses a scene with an obstacle or tool-zone entry that reaches beyond `radius` metres
    /// of `centre` (a solid's bounding sphere must lie within that ball; a half-space's
    /// boundary plane must pass within it). `what` says whose bound it is, for the message.
    /// A solid far outside any motion is harmless to a check but is almost always a typo (a
    /// radius of `1e308`, a centre in millimetres in a scene in metres), and huge numbers are
    /// where distances lose their digits.
    ///
    /// # Errors
    /// [`WorldError::Input`] naming the first entry beyond the bound and how far it reaches.
    pub fn require_within(&self, centre: &Vector3<f64>, radius: f64, what: &str) -> Result<(), WorldError> {
        let entries =
            self.obstacles.iter().map(|o| ("obstacle", o)).chain(self.tool_zone.iter().map(|o| ("tool zone", o)));
        for (kind, o) in entries {
            let reach = match (&o.shape, o.shape.bounding_sphere()) {
                (_, Some((c, r))) => (c - centre).norm() + r,
                (Shape::HalfSpace { normal, offset }, None) => (normal.dot(centre) - offset).abs(),
                (_, None) => continue,
            };
            if reach.is_nan() || reach > radius {
                return Err(WorldError::Input(format!(
                    "{kind} `{}` ({}) reaches {reach:.6e} m from the robot's base, beyond {what} ({radius:.3} m); \
                     check its numbers and the scene's length unit",
                    o.name,
                    o.shape.kind()
                )));
            }
        }
        Ok(())
    }

    /// Exempts the link pair `(a, b)` from the self-collision check (builder style); names as
    /// in [`Scene::allowed_self_collisions`], checked when a collision checker is built.
    #[must_use]
    pub fn with_allowed_self_collision(mut self, a: impl Into<String>, b: impl Into<String>) -> Self {
        self.allowed_self_collisions.push([a.into(), b.into()]);
        self
    }

    /// Adds a tool-zone shape after checking its numbers (builder style).
    ///
    /// # Errors
    /// [`WorldError::Shape`] for NaN/infinity or a degenerate shape.
    pub fn with_tool_zone(mut self, name: impl Into<String>, shape: Shape) -> Result<Self, WorldError> {
        let name = name.into();
        validate("tool zone", &name, &shape)?;
        self.tool_zone.push(Obstacle { name, shape, velocity: Vector3::zeros() });
        Ok(self)
    }
}

fn shape_error(what: &'static str, name: &str, shape: &str, message: impl Into<String>) -> WorldError {
    WorldError::Shape { what, name: name.to_string(), shape: shape.to_string(), message: message.into() }
}

fn build_shape(what: &'static str, name: &str, f: &ShapeField, ls: f64, an: f64) -> Result<Shape, WorldError> {
    let kind = f.shape.as_str();
    let (required, optional): (&[&str], &[&str]) = match kind {
        "point" => (&["at"], &[]),
        "sphere" => (&["center", "radius"], &[]),
        "aabb" => (&["min", "max"], &[]),
        "box" => (&["center", "half_extents"], &["rpy"]),
        "capsule" => (&["a", "b", "radius"], &[]),
        "halfspace" => (&["point", "outward_normal"], &[]),
        "rectangle" => (&["center", "half_extents"], &["rpy"]),
        "cylinder" => (&["center", "radius", "length"], &["rpy"]),
        other => {
            return Err(shape_error(
                what,
                name,
                other,
                "unknown shape (expected point, sphere, aabb, box, capsule, cylinder, halfspace or rectangle)",
            ));
        }
    };
    let present = f.present();
    for r in required {
        if !present.contains(r) {
            return Err(shape_error(what, name, kind, format!("missing field `{r}`")));
        }
    }
    for p in &present {
        if !required.contains(p) && !optional.contains(p) {
            return Err(shape_error(what, name, kind, format!("field `{p}` does not apply to this shape")));
        }
    }
    let v = |x: Option<[f64; 3]>| {
        let x = x.unwrap_or_default();
        Vector3::new(x[0] * ls, x[1] * ls, x[2] * ls)
    };
    let rotation = |rpy: Option<[f64; 3]>| {
        let r = rpy.unwrap_or_default();
        nalgebra::Rotation3::from_euler_angles(r[0] * an, r[1] * an, r[2] * an).into_inner()
    };
    let half = |n: usize| -> Result<Vector3<f64>, WorldError> {
        let h = f.half_extents.as_deref().unwrap_or_default();
        if h.len() != n {
            return Err(shape_error(what, name, kind, format!("`half_extents` needs {n} values, got {}", h.len())));
        }
        Ok(Vector3::new(h[0] * ls, h[1] * ls, if n == 3 { h[2] * ls } else { 0.0 }))
    };
    // Check raw numbers for NaN first so that the message names the field.
    for (field, vals) in [
        ("at", f.at),
        ("center", f.center),
        ("min", f.min),
        ("max", f.max),
        ("rpy", f.rpy),
        ("a", f.a),
        ("b", f.b),
        ("point", f.point),
        ("outward_normal", f.outward_normal),
    ] {
        if let Some(vals) = vals
            && vals.iter().any(|x| !x.is_finite())
        {
            return Err(shape_error(what, name, kind, format!("`{field}` must be finite numbers, got {vals:?}")));
        }
    }
    if let Some(h) = &f.half_extents
        && h.iter().any(|x| !x.is_finite())
    {
        return Err(shape_error(what, name, kind, format!("`half_extents` must be finite numbers, got {h:?}")));
    }
    for (field, x) in [("radius", f.radius), ("length", f.length)] {
        if let Some(x) = x
            && !x.is_finite()
        {
            return Err(shape_error(what, name, kind, format!("`{field}` must be a finite number, got {x}")));
        }
    }
    let shape = match kind {
        "point" => Shape::Point { at: v(f.at) },
        "sphere" => Shape::Sphere { center: v(f.center), radius: f.radius.unwrap_or_default() * ls },
        "aabb" => {
            let (lo, hi) = (v(f.min), v(f.max));
            for i in 0..3 {
                if lo[i] >= hi[i] {
                    return Err(shape_error(
                        what,
                        name,
                        kind,
                        format!(
                            "`min` must be below `max` on every axis; axis {} has {} ≥ {}",
                            ["x", "y", "z"][i],
                            f.min.unwrap_or_default()[i],
                            f.max.unwrap_or_default()[i]
                        ),
                    ));
                }
            }
            Shape::Box { center: (lo + hi) * 0.5, half_extents: (hi - lo) * 0.5, rotation: Matrix3::identity() }
        }
        "box" => Shape::Box { center: v(f.center), half_extents: half(3)?, rotation: rotation(f.rpy) },
        "rectangle" => Shape::Box { center: v(f.center), half_extents: half(2)?, rotation: rotation(f.rpy) },
        "capsule" => Shape::Capsule { a: v(f.a), b: v(f.b), radius: f.radius.unwrap_or_default() * ls },
        "cylinder" => Shape::Cylinder {
            center: v(f.center),
            rotation: rotation(f.rpy),
            radius: f.radius.unwrap_or_default() * ls,
            half_length: f.length.unwrap_or_default() * ls * 0.5,
        },
        _ => {
            let n = Vector3::from(f.outward_normal.unwrap_or_default());
            let norm = n.norm();
            if norm < crate::tolerance::AXIS_MIN_NORM {
                return Err(shape_error(what, name, kind, "`outward_normal` must not be zero"));
            }
            let n = n / norm;
            Shape::HalfSpace { normal: n, offset: n.dot(&v(f.point)) }
        }
    };
    validate(what, name, &shape)?;
    Ok(shape)
}

/// Checks a shape's numbers (also for shapes built in code).
pub(super) fn validate(what: &'static str, name: &str, shape: &Shape) -> Result<(), WorldError> {
    let kind = shape.kind();
    let finite3 = |v: &Vector3<f64>| v.iter().all(|x| x.is_finite());
    let err = |m: String| Err(shape_error(what, name, kind, m));
    match shape {
        Shape::Point { at } if !finite3(at) => err(format!("`at` must be finite, got {at:?}")),
        Shape::Sphere { center, radius } | Shape::Capsule { a: center, radius, .. } => {
            if !finite3(center) {
                err("coordinates must be finite".into())
            } else if !(radius.is_finite() && *radius > 0.0) {
                err(format!("`radius` must be a positive number, got {radius} m"))
            } else if let Shape::Capsule { b, .. } = shape
                && !finite3(b)
            {
                err("`b` must be finite".into())
            } else {
                Ok(())
            }
        }
        Shape::Box { center, half_extents, rotation } => {
            if !finite3(center) || !rotation.iter().all(|x| x.is_finite()) {
                return err("centre and rotation must be finite".into());
            }
            let flat_ok = half_extents.z == 0.0 && half_extents.x > 0.0 && half_extents.y > 0.0;
            if !(half_extents.iter().all(|h| h.is_finite() && *h > 0.0) || flat_ok) {
                return err(format!(
                    "`half_extents` must be positive (a flat shape is a `rectangle` with two values), got {:?} m",
                    half_extents.as_slice()
                ));
            }
            if (rotation.transpose() * rotation - Matrix3::identity()).amax()
                > crate::tolerance::ROTATION_ORTHONORMALITY
            {
                return err("`rotation` is not orthonormal".into());
            }
            Ok(())
        }
        Shape::Cylinder { center, rotation, radius, half_length } => {
            if !finite3(center) || !rotation.iter().all(|x| x.is_finite()) {
                return err("centre and rotation must be finite".into());
            }
            if !(radius.is_finite() && *radius > 0.0 && half_length.is_finite() && *half_length > 0.0) {
                return err(format!(
                    "`radius` and `length` must be positive numbers, got {radius} m and {} m",
                    2.0 * half_length
                ));
            }
            if (rotation.transpose() * rotation - Matrix3::identity()).amax()
                > crate::tolerance::ROTATION_ORTHONORMALITY
            {
                return err("`rotation` is not orthonormal".into());
            }
            Ok(())
        }
        Shape::ConvexMesh { vertices } => {
            if vertices.is_empty() {
                err("a mesh needs at least one vertex".into())
            } else if vertices.len() > 3 * crate::model::MAX_MESH_TRIANGLES {
                err(format!(
                    "{} vertices, more than the cap of {}",
                    vertices.len(),
                    3 * crate::model::MAX_MESH_TRIANGLES
                ))
            } else if !vertices.iter().all(finite3) {
                err("every vertex must be finite".into())
            } else {
                Ok(())
            }
        }
        Shape::HalfSpace { normal, offset } => {
            if !finite3(normal) || !offset.is_finite() || (normal.norm() - 1.0).abs() > 1e-9 {
                err("the normal must be a finite unit vector and the offset finite".into())
            } else {
                Ok(())
            }
        }
        _ => Ok(()),
    }
}
