//! MoveIt's formats: a planning scene (`moveit_msgs/PlanningScene` as YAML, what MoveIt and
//! MotionBenchMaker write) and a motion-plan request's start state and joint goal
//! (`moveit_msgs/MotionPlanRequest` as YAML).
//!
//! # Planning scene
//! `world.collision_objects[]`: each object has an `id`, an optional object `pose` (the
//! primitives' and meshes' poses are relative to it), `primitives[]` with `type` and
//! `dimensions` — `box` `[x, y, z]` (full side lengths), `sphere` `[radius]`, `cylinder`
//! `[height, radius]` along its local z — and one `primitive_poses[]` entry each; `meshes[]`
//! (`vertices[]`, `triangles[].vertex_indices`) with `mesh_poses[]`, checked as their convex
//! hulls; `planes[]` (`coef: [a, b, c, d]`, the solid `a·x + b·y + c·z + d ≤ 0`). Positions are
//! `[x, y, z]` or `{x, y, z}`, orientations `[x, y, z, w]` or `{x, y, z, w}` (quaternions, as
//! ROS writes them). Everything is in the planning frame, which is taken as the world frame
//! of `reach` (the robot's base frame unless the robot has a base transform). An object of
//! several solids becomes one obstacle per solid, named `id`, `id[2]`, ….
//! `allowed_collision_matrix` (`entry_names`, `entry_values`): every pair marked `true`
//! becomes an allowed self-collision pair (entries naming the world's objects are ignored:
//! an obstacle is never allowed to touch the robot). `robot_state` and the other fields are
//! not read.

use std::collections::BTreeMap;

use nalgebra::{Isometry3, Quaternion, Translation3, UnitQuaternion, Vector3};
use serde::Deserialize;

use super::{Obstacle, Scene, Shape, WorldError};
use crate::model::MAX_MESH_TRIANGLES;

/// A position as ROS YAML writes it: a sequence or a map.
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum Xyz {
    Seq([f64; 3]),
    Map { x: f64, y: f64, z: f64 },
}

/// A quaternion as ROS YAML writes it (`x, y, z, w`).
#[derive(Deserialize, Clone, Copy)]
#[serde(untagged)]
enum Xyzw {
    Seq([f64; 4]),
    Map { x: f64, y: f64, z: f64, w: f64 },
}

#[derive(Deserialize, Clone, Copy)]
struct PoseField {
    position: Option<Xyz>,
    orientation: Option<Xyzw>,
}

#[derive(Deserialize)]
struct PrimitiveField {
    #[serde(rename = "type")]
    kind: String,
    #[serde(default)]
    dimensions: Vec<f64>,
}

#[derive(Deserialize)]
struct TriangleField {
    vertex_indices: Vec<usize>,
}

#[derive(Deserialize)]
struct MeshField {
    #[serde(default)]
    triangles: Vec<TriangleField>,
    #[serde(default)]
    vertices: Vec<Xyz>,
}

#[derive(Deserialize)]
struct PlaneField {
    coef: [f64; 4],
}

#[derive(Deserialize)]
struct ObjectField {
    id: String,
    pose: Option<PoseField>,
    #[serde(default)]
    primitives: Vec<PrimitiveField>,
    #[serde(default)]
    primitive_poses: Vec<PoseField>,
    #[serde(default)]
    meshes: Vec<MeshField>,
    #[serde(default)]
    mesh_poses: Vec<PoseField>,
    #[serde(default)]
    planes: Vec<PlaneField>,
    operation: Option<serde_norway::Value>,
}

#[derive(Deserialize, Default)]
struct WorldField {
    #[serde(default)]
    collision_objects: Vec<ObjectField>,
}

#[derive(Deserialize)]
struct AcmField {
    #[serde(default)]
    entry_names: Vec<String>,
    #[serde(default)]
    entry_values: Vec<Vec<bool>>,
}

#[derive(Deserialize)]
struct SceneField {
    #[serde(default)]
    world: WorldField,
    allowed_collision_matrix: Option<AcmField>,
}

/// A YAML error as a [`WorldError::Parse`] with its line and column.
fn parse_error(e: &serde_norway::Error) -> WorldError {
    let (line, column) = e.location().map_or((1, 1), |l| (l.line(), l.column()));
    WorldError::Parse { line, column, message: e.to_string() }
}

fn object_error(object: &str, message: impl Into<String>) -> WorldError {
    WorldError::Input(format!("collision object `{object}`: {}", message.into()))
}

impl PoseField {
    /// The pose; `object` and `what` name it in messages.
    fn to_isometry(self, object: &str, what: &str) -> Result<Isometry3<f64>, WorldError> {
        let p = match self.position {
            None => [0.0; 3],
            Some(Xyz::Seq(v)) => v,
            Some(Xyz::Map { x, y, z }) => [x, y, z],
        };
        let q = match self.orientation {
            None => [0.0, 0.0, 0.0, 1.0],
            Some(Xyzw::Seq(v)) => v,
            Some(Xyzw::Map { x, y, z, w }) => [x, y, z, w],
        };
        if !p.iter().chain(&q).all(|v| v.is_finite()) {
            return Err(object_error(object, format!("{what}: the position and orientation must be finite")));
        }
        let quat = Quaternion::new(q[3], q[0], q[1], q[2]);
        let norm = quat.norm();
        if norm < 1e-6 {
            return Err(object_error(object, format!("{what}: the orientation quaternion is zero")));
        }
        Ok(Isometry3::from_parts(Translation3::new(p[0], p[1], p[2]), UnitQuaternion::from_quaternion(quat / norm)))
    }
}

impl Scene {
    /// Reads a MoveIt planning scene from YAML (the format in the module docs of
    /// [`crate::world::moveit`]).
    ///
    /// # Errors
    /// [`WorldError::Parse`] with line and column for YAML that does not follow the message's
    /// layout; [`WorldError::Input`] naming the object and field for an unknown or unsupported
    /// primitive type (`cone`), dimensions of the wrong count or not positive, a primitive or
    /// mesh without its pose, a NaN, a mesh over [`MAX_MESH_TRIANGLES`] triangles or indexing
    /// a vertex it does not have, an object removed by its `operation`, or an allowed-collision
    /// matrix whose rows do not match its names.
    pub fn from_moveit_yaml(text: &str) -> Result<Scene, WorldError> {
        let file: SceneField = serde_norway::from_str(text).map_err(|e| parse_error(&e))?;
        let mut scene = Scene::new();
        let mut objects: BTreeMap<&str, ()> = BTreeMap::new();
        for o in &file.world.collision_objects {
            let id = o.id.as_str();
            if let Some(op) = &o.operation {
                // moveit_msgs/CollisionObject: ADD = 0 (the default), REMOVE = 1, APPEND = 2, MOVE = 3.
                let op = op.as_u64().or_else(|| op.as_str().and_then(|s| s.parse().ok()));
                if !matches!(op, Some(0 | 2)) {
                    return Err(object_error(id, "only objects added to the scene (operation 0 or 2) can be read"));
                }
            }
            objects.insert(id, ());
            let frame = o.pose.map_or(Ok(Isometry3::identity()), |p| p.to_isometry(id, "pose"))?;
            if o.primitive_poses.len() != o.primitives.len() {
                return Err(object_error(
                    id,
                    format!(
                        "{} primitives but {} primitive_poses (each needs its pose)",
                        o.primitives.len(),
                        o.primitive_poses.len()
                    ),
                ));
            }
            if o.mesh_poses.len() != o.meshes.len() {
                return Err(object_error(
                    id,
                    format!("{} meshes but {} mesh_poses (each needs its pose)", o.meshes.len(), o.mesh_poses.len()),
                ));
            }
            let mut shapes: Vec<Shape> = Vec::new();
            for (k, (prim, pose)) in o.primitives.iter().zip(&o.primitive_poses).enumerate() {
                let what = format!("primitive {}", k + 1);
                let pose = frame * pose.to_isometry(id, &what)?;
                let dims = &prim.dimensions;
                let need = |n: usize| -> Result<(), WorldError> {
                    if dims.len() != n {
                        return Err(object_error(
                            id,
                            format!("{what} ({}): `dimensions` needs {n} values, got {}", prim.kind, dims.len()),
                        ));
                    }
                    if let Some(d) = dims.iter().find(|d| !(d.is_finite() && **d > 0.0)) {
                        return Err(object_error(
                            id,
                            format!("{what} ({}): `dimensions` must be positive numbers (m), got {d}", prim.kind),
                        ));
                    }
                    Ok(())
                };
                let rotation = *pose.rotation.to_rotation_matrix().matrix();
                let center = pose.translation.vector;
                shapes.push(match prim.kind.to_ascii_lowercase().as_str() {
                    "box" | "1" => {
                        need(3)?;
                        Shape::Box { center, half_extents: Vector3::new(dims[0], dims[1], dims[2]) * 0.5, rotation }
                    }
                    "sphere" | "2" => {
                        need(1)?;
                        Shape::Sphere { center, radius: dims[0] }
                    }
                    "cylinder" | "3" => {
                        need(2)?;
                        Shape::Cylinder { center, rotation, radius: dims[1], half_length: dims[0] * 0.5 }
                    }
                    other => {
                        return Err(object_error(
                            id,
                            format!("{what}: primitive type `{other}` is not supported (box, sphere, cylinder)"),
                        ));
                    }
                });
            }
            for (k, (mesh, pose)) in o.meshes.iter().zip(&o.mesh_poses).enumerate() {
                let what = format!("mesh {}", k + 1);
                let pose = frame * pose.to_isometry(id, &what)?;
                if mesh.triangles.len() > MAX_MESH_TRIANGLES {
                    return Err(object_error(
                        id,
                        format!(
                            "{what}: {} triangles, more than the cap of {MAX_MESH_TRIANGLES}",
                            mesh.triangles.len()
                        ),
                    ));
                }
                let n = mesh.vertices.len();
                if let Some(i) = mesh.triangles.iter().flat_map(|t| &t.vertex_indices).find(|i| **i >= n) {
                    return Err(object_error(id, format!("{what}: a triangle names vertex {i}, the mesh has {n}")));
                }
                let vertices: Vec<Vector3<f64>> = mesh
                    .vertices
                    .iter()
                    .map(|v| {
                        let v = match *v {
                            Xyz::Seq(v) => v,
                            Xyz::Map { x, y, z } => [x, y, z],
                        };
                        (pose * nalgebra::Point3::from(v)).coords
                    })
                    .collect();
                shapes.push(Shape::ConvexMesh { vertices });
            }
            for (k, plane) in o.planes.iter().enumerate() {
                let [a, b, c, d] = plane.coef;
                let n = Vector3::new(a, b, c);
                let norm = n.norm();
                if !(norm.is_finite() && norm > 1e-9 && d.is_finite()) {
                    return Err(object_error(id, format!("plane {}: `coef` needs a finite non-zero normal", k + 1)));
                }
                // The solid a·x + b·y + c·z + d ≤ 0: its outward normal (toward free space) is n.
                let (n, offset) = (frame.rotation * (n / norm), -d / norm);
                shapes.push(Shape::HalfSpace { normal: n, offset: offset + n.dot(&frame.translation.vector) });
            }
            let several = shapes.len() > 1;
            for (k, shape) in shapes.into_iter().enumerate() {
                let name = if several && k > 0 { format!("{id}[{}]", k + 1) } else { id.to_string() };
                super::scene::validate("obstacle", &name, &shape)?;
                scene.obstacles.push(Obstacle { name, shape, velocity: Vector3::zeros() });
            }
        }
        if let Some(acm) = &file.allowed_collision_matrix {
            let n = acm.entry_names.len();
            if acm.entry_values.len() != n || acm.entry_values.iter().any(|r| r.len() != n) {
                return Err(WorldError::Input(format!(
                    "allowed_collision_matrix: {n} entry_names need {n} rows of {n} values"
                )));
            }
            for i in 0..n {
                for j in i + 1..n {
                    let (a, b) = (&acm.entry_names[i], &acm.entry_names[j]);
                    if (acm.entry_values[i][j] || acm.entry_values[j][i])
                        && !objects.contains_key(a.as_str())
                        && !objects.contains_key(b.as_str())
                    {
                        scene.allowed_self_collisions.push([a.clone(), b.clone()]);
                    }
                }
            }
        }
        Ok(scene)
    }
}

/// A motion-plan request's start and joint goal, by joint name (radians or metres).
#[derive(Debug, Clone, PartialEq)]
pub struct PlanRequest {
    /// `start_state.joint_state`: every joint named, in the file's order.
    pub start: Vec<(String, f64)>,
    /// `goal_constraints[0].joint_constraints`: the goal of each constrained joint.
    pub goal: Vec<(String, f64)>,
}

#[derive(Deserialize)]
struct JointStateField {
    #[serde(default)]
    name: Vec<String>,
    #[serde(default)]
    position: Vec<f64>,
}

#[derive(Deserialize)]
struct StartField {
    joint_state: JointStateField,
}

#[derive(Deserialize)]
struct JointConstraintField {
    joint_name: String,
    position: f64,
}

#[derive(Deserialize)]
struct GoalField {
    #[serde(default)]
    joint_constraints: Vec<JointConstraintField>,
}

#[derive(Deserialize)]
struct RequestField {
    start_state: StartField,
    #[serde(default)]
    goal_constraints: Vec<GoalField>,
}

impl PlanRequest {
    /// Reads a MoveIt motion-plan request from YAML.
    ///
    /// # Errors
    /// [`WorldError::Parse`] for YAML that does not follow the message; [`WorldError::Input`]
    /// for a start state whose names and positions differ in number, a NaN, or no joint goal.
    pub fn from_moveit_yaml(text: &str) -> Result<PlanRequest, WorldError> {
        let file: RequestField = serde_norway::from_str(text).map_err(|e| parse_error(&e))?;
        let js = &file.start_state.joint_state;
        if js.name.len() != js.position.len() {
            return Err(WorldError::Input(format!(
                "start_state.joint_state: {} names but {} positions",
                js.name.len(),
                js.position.len()
            )));
        }
        let start: Vec<(String, f64)> = js.name.iter().cloned().zip(js.position.iter().copied()).collect();
        let goal: Vec<(String, f64)> = file
            .goal_constraints
            .first()
            .map(|g| g.joint_constraints.iter().map(|c| (c.joint_name.clone(), c.position)).collect())
            .unwrap_or_default();
        if goal.is_empty() {
            return Err(WorldError::Input(
                "goal_constraints[0].joint_constraints: the request has no joint goal".into(),
            ));
        }
        if let Some((n, v)) = start.iter().chain(&goal).find(|(_, v)| !v.is_finite()) {
            return Err(WorldError::Input(format!("joint `{n}`: position must be finite, got {v}")));
        }
        Ok(PlanRequest { start, goal })
    }

    /// The start and goal as joint vectors of `names` (the robot's joints in order; a joint
    /// the goal does not constrain keeps its start value).
    ///
    /// # Errors
    /// [`WorldError::Input`] naming a joint of `names` that the start state lacks.
    pub fn joint_vectors(&self, names: &[&str]) -> Result<(Vec<f64>, Vec<f64>), WorldError> {
        let mut start = Vec::with_capacity(names.len());
        let mut goal = Vec::with_capacity(names.len());
        for n in names {
            let s = self
                .start
                .iter()
                .find(|(j, _)| j == n)
                .map(|(_, v)| *v)
                .ok_or_else(|| WorldError::Input(format!("the request's start state has no joint `{n}`")))?;
            start.push(s);
            goal.push(self.goal.iter().find(|(j, _)| j == n).map_or(s, |(_, v)| *v));
        }
        Ok((start, goal))
    }
}
