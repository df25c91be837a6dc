//! URDF import of serial chains (through `urdf-rs`).

use crate::error::one_line;
use std::collections::{BTreeMap, BTreeSet};

use nalgebra::{Isometry3, Unit, Vector3};

use super::LinkInertial;

use super::toml_format::xyz_rpy;
use super::{
    BodyShape, Convention, Joint, JointGeometry, JointKind, Limits, LinkBody, MimicJoint, ModelError, Robot, RobotSpec,
};
use crate::tolerance::AXIS_MIN_NORM;

/// Which serial chain of a URDF tree to import.
///
/// With both names `None`, the file must be a single unbranched chain; its root link is the
/// base and its only leaf the tip.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UrdfChain {
    /// Name of the base link (default: the tree's root link).
    pub base: Option<String>,
    /// Name of the tip link (default: the only leaf below the base).
    pub tip: Option<String>,
}

/// How [`Robot::from_urdf_str_with`] builds the robot's collision body from `<collision>`.
#[derive(Default)]
pub struct UrdfBodyOptions<'a> {
    /// Positions of movable joints off the chain (a gripper's fingers), by joint name: radians
    /// or metres. A joint not named sits at 0 clamped into its limits; a mimic joint follows
    /// its master's value.
    pub locked: &'a [(String, f64)],
    /// Reads a collision mesh file, given its `filename` as the URDF writes it
    /// (`package://…`, relative, `file://`): `None` when the file is not available, and the
    /// link carries a [`BodyShape::Missing`] solid (kinematics work; collision checks refuse),
    /// `Some(Err(reason))` when it cannot be read (an error). No reader: no mesh is available.
    #[allow(clippy::type_complexity)]
    pub meshes: Option<&'a dyn Fn(&str) -> Option<Result<Vec<u8>, String>>>,
}

impl Robot {
    /// [`Robot::from_urdf_str`] with the collision body's options: the positions of joints
    /// off the chain and a reader of collision mesh files.
    ///
    /// Every link below the chain's base becomes a [`LinkBody`] carrying its `<collision>`
    /// elements (each with its `<origin>`): box, cylinder, sphere, capsule, and meshes (STL,
    /// OBJ; checked as their convex hulls, [`BodyShape::ConvexMesh`]) scaled by their
    /// `scale`. A link rides on the chain frame of the last movable chain joint above it,
    /// placed through the fixed joints and the locked joints off the chain between them.
    ///
    /// # Errors
    /// As [`Robot::from_urdf_str`]; [`ModelError::Urdf`] naming the link and file when a mesh
    /// cannot be read or parsed ([`super::mesh_vertices`]), or a locked joint does not exist.
    pub fn from_urdf_str_with(text: &str, chain: &UrdfChain, options: &UrdfBodyOptions) -> Result<Robot, ModelError> {
        let robot = Robot::from_urdf_str(text, chain)?;
        let urdf = urdf_rs::read_from_string(text).map_err(|e| ModelError::Urdf(one_line(&e.to_string())))?;
        let (base, _, path) = chain_path(&urdf, chain)?;
        let mut spec = robot.spec().clone();
        spec.bodies = collision_bodies(&urdf, base, &path, options)?;
        Robot::new(spec)
    }

    /// Imports the serial chain from `chain.base` to `chain.tip` of a URDF document.
    ///
    /// Revolute, continuous and prismatic joints become joints (continuous ones unlimited);
    /// fixed joints fold into the next joint's origin, or into the tool transform after the
    /// last movable joint. The base link frame is the world frame.
    ///
    /// A joint with `<mimic joint=".." multiplier=".." offset="..">` (defaults 1 and 0) is not a
    /// joint of the robot: when its master is on the chain it becomes a [`MimicJoint`] that
    /// follows the master (`q = multiplier·q_master + offset`, its own `<limit>` ignored); when
    /// its master is elsewhere in the tree it is fixed at `offset`, and the robot's
    /// description says so. A chain with moving mimic joints has no dynamics (the description
    /// says so when the links have mass).
    ///
    /// The whole tree is checked: every joint's parent and child link must be declared, and
    /// the links must form a tree (no cycle). Joints of the chosen chain must be revolute,
    /// continuous, prismatic or fixed (floating, planar and spherical joints are refused) with
    /// a non-zero axis; joints off the chain are not looked at further.
    ///
    /// Each link's `<inertial>` (mass, origin, inertia about the centre of mass in the origin's
    /// axes) becomes the [`LinkInertial`] of the movable joint whose child it is, expressed in
    /// that child link frame; links hanging below it on the chain by fixed joints are folded in
    /// (parallel-axis theorem), links before the first movable joint are fixed to the base and
    /// ignored. Links on side branches of the tree are not part of the chain and carry no mass
    /// in the model. When every link of the chain is massless and inertia-free, the robot has
    /// no dynamics (empty [`RobotSpec::inertials`]). Gravity is the default `(0, 0, −9.80665)`.
    ///
    /// # Errors
    /// [`ModelError::Urdf`] for XML errors, unknown link names, a joint whose parent or child
    /// link is not declared, a link with two parent joints, a cycle, a branched tree without a
    /// chosen tip, a tip not below the base, a floating/planar/spherical joint on the chain, a
    /// zero axis, a mimic joint whose master does not exist, is fixed or is itself a mimic
    /// joint — each naming the joint; plus the validation errors of [`Robot::new`].
    pub fn from_urdf_str(text: &str, chain: &UrdfChain) -> Result<Robot, ModelError> {
        let urdf = urdf_rs::read_from_string(text).map_err(|e| ModelError::Urdf(one_line(&e.to_string())))?;
        let (base, tip, path) = chain_path(&urdf, chain)?;

        let link_inertial = |name: &str| -> LinkInertial {
            urdf.links.iter().find(|l| l.name == name).map_or_else(LinkInertial::zero, |l| {
                let b = &l.inertial;
                let i = &b.inertia;
                LinkInertial::new(b.mass.value, Vector3::zeros(), [i.ixx, i.iyy, i.izz, i.ixy, i.ixz, i.iyz])
                    .transformed(&xyz_rpy(b.origin.xyz.0, b.origin.rpy.0, 1.0, 1.0))
            })
        };
        // The independent movable joints of the chain, by name: the masters mimic joints may follow.
        let independent: BTreeMap<&str, usize> = path
            .iter()
            .filter(|j| movable(j) && j.mimic.is_none())
            .enumerate()
            .map(|(i, j)| (j.name.as_str(), i))
            .collect();
        let chain_has_mass = path.iter().any(|j| {
            let b = link_inertial(&j.child.link);
            b.mass != 0.0 || b.inertia.amax() != 0.0
        });
        let mut notes: Vec<String> = Vec::new();
        let mut joints = Vec::new();
        let mut mimics: Vec<MimicJoint> = Vec::new();
        let mut inertials: Vec<LinkInertial> = Vec::new();
        let mut pending = Isometry3::identity();
        for j in &path {
            let mut origin = pending * xyz_rpy(j.origin.xyz.0, j.origin.rpy.0, 1.0, 1.0);
            let kind = match j.joint_type {
                urdf_rs::JointType::Fixed => None,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => Some(JointKind::Revolute),
                urdf_rs::JointType::Prismatic => Some(JointKind::Prismatic),
                ref other => {
                    return Err(ModelError::Urdf(format!(
                        "joint `{}` is a {} joint; only revolute, continuous, prismatic and fixed joints form a serial chain",
                        j.name,
                        format!("{other:?}").to_lowercase()
                    )));
                }
            };
            let axis = Vector3::from(j.axis.xyz.0);
            let norm = axis.norm();
            if kind.is_some() && (!norm.is_finite() || norm <= AXIS_MIN_NORM) {
                return Err(ModelError::Urdf(format!("joint `{}`: axis {:?} has no direction", j.name, j.axis.xyz.0)));
            }
            let axis = Unit::new_normalize(axis);
            let kind = match (kind, &j.mimic) {
                (None, _) => None,
                (Some(kind), None) => Some(kind),
                (Some(kind), Some(mimic)) => {
                    let multiplier = mimic.multiplier.unwrap_or(1.0);
                    let offset = mimic.offset.unwrap_or(0.0);
                    check_master(&urdf, j, &mimic.joint)?;
                    if let Some(&master) = independent.get(mimic.joint.as_str()) {
                        mimics.push(MimicJoint {
                            name: j.name.clone(),
                            kind,
                            position: joints.len(),
                            origin,
                            axis,
                            master,
                            multiplier,
                            offset,
                        });
                        pending = Isometry3::identity();
                        continue;
                    }
                    let unit = if kind == JointKind::Revolute { "rad" } else { "m" };
                    notes.push(format!(
                        "joint `{}` mimics `{}`, which is off the chain: fixed at its offset {offset} {unit}",
                        j.name, mimic.joint
                    ));
                    origin *= match kind {
                        JointKind::Revolute => Isometry3::rotation(axis.into_inner() * offset),
                        JointKind::Prismatic => {
                            Isometry3::translation(axis.x * offset, axis.y * offset, axis.z * offset)
                        }
                    };
                    None
                }
            };
            let Some(kind) = kind else {
                // `origin` places the fixed child in the last movable joint's child frame.
                if let Some(last) = inertials.last_mut() {
                    *last = last.combined(&link_inertial(&j.child.link).transformed(&origin));
                }
                pending = origin;
                continue;
            };
            let limits = if j.joint_type == urdf_rs::JointType::Continuous {
                Limits::UNLIMITED
            } else if j.limit.lower == 0.0 && j.limit.upper == 0.0 {
                // URDF 1.0 requires <limit> on revolute and prismatic joints; urdf-rs reads a
                // missing one as [0, 0], which would otherwise surface as an ordering error.
                return Err(ModelError::Urdf(format!(
                    "joint `{}`: a {:?} joint needs <limit lower=.. upper=..> (or type=\"continuous\")",
                    j.name, j.joint_type
                )));
            } else {
                Limits::new(j.limit.lower, j.limit.upper)
            };
            let max_velocity = (j.limit.velocity.is_finite() && j.limit.velocity > 0.0).then_some(j.limit.velocity);
            joints.push(Joint {
                name: j.name.clone(),
                kind,
                geometry: JointGeometry::Axis { origin, axis },
                limits,
                max_velocity,
                max_acceleration: None,
                max_jerk: None,
                drive: None,
                home: limits.default_home(),
                flip: false,
            });
            inertials.push(link_inertial(&j.child.link));
            pending = Isometry3::identity();
        }
        let massless = inertials.iter().all(|b| b.mass == 0.0 && b.inertia.amax() == 0.0);
        if !mimics.is_empty() && chain_has_mass {
            notes.push("no dynamics: the dynamics model does not support mimic joints".into());
        }
        let mut description = format!("imported from URDF, chain {base} → {tip}");
        for note in &notes {
            description.push_str("; ");
            description.push_str(note);
        }
        let spec = RobotSpec {
            name: urdf.name.clone(),
            description,
            convention: Convention::Urdf,
            joints,
            base: Isometry3::identity(),
            tool: pending,
            links: Vec::new(),
            bodies: collision_bodies(&urdf, base, &path, &UrdfBodyOptions::default())?,
            inertials: if massless || !mimics.is_empty() { Vec::new() } else { inertials },
            mimics,
            ..RobotSpec::new("", Convention::Urdf, Vec::new())
        };
        Robot::new(spec)
    }
}

/// The collision bodies of every link below `base` (see [`Robot::from_urdf_str_with`]).
fn collision_bodies(
    urdf: &urdf_rs::Robot,
    base: &str,
    path: &[&urdf_rs::Joint],
    options: &UrdfBodyOptions,
) -> Result<Vec<LinkBody>, ModelError> {
    for (name, value) in options.locked {
        match urdf.joints.iter().find(|j| &j.name == name) {
            None => return Err(ModelError::Urdf(format!("locked joint `{name}` does not exist"))),
            Some(_) if !value.is_finite() => {
                return Err(ModelError::Urdf(format!("locked joint `{name}`: position must be finite, got {value}")));
            }
            Some(_) => {}
        }
    }
    // The chain's frames: the independent movable joints on the path, 1-based.
    let frames: BTreeMap<&str, usize> = path
        .iter()
        .filter(|j| movable(j) && j.mimic.is_none())
        .enumerate()
        .map(|(i, j)| (j.name.as_str(), i + 1))
        .collect();
    let value_of = |j: &urdf_rs::Joint| -> f64 {
        let own = |j: &urdf_rs::Joint| {
            options.locked.iter().find(|(n, _)| n == &j.name).map_or_else(
                || {
                    if j.joint_type == urdf_rs::JointType::Continuous {
                        0.0
                    } else {
                        0.0_f64.clamp(j.limit.lower.min(j.limit.upper), j.limit.upper.max(j.limit.lower))
                    }
                },
                |(_, v)| *v,
            )
        };
        match &j.mimic {
            Some(m) => {
                let master = urdf.joints.iter().find(|x| x.name == m.joint).map_or(0.0, own);
                m.multiplier.unwrap_or(1.0) * master + m.offset.unwrap_or(0.0)
            }
            None => own(j),
        }
    };
    struct Place {
        frame: usize,
        pose: Isometry3<f64>,
        /// Why the link cannot be placed on a chain frame (below a moving mimic joint).
        lost: Option<String>,
    }
    let mut bodies: Vec<LinkBody> = Vec::new();
    let mut queue: Vec<(&str, Place, Option<usize>)> =
        vec![(base, Place { frame: 0, pose: Isometry3::identity(), lost: None }, None)];
    while let Some((name, place, parent)) = queue.pop() {
        let link = urdf.links.iter().find(|l| l.name == name);
        let mut shapes = Vec::new();
        for c in link.map_or(&[][..], |l| &l.collision) {
            if let Some(why) = &place.lost {
                shapes.push(BodyShape::Missing { what: format!("link `{name}`: {why}") });
                continue;
            }
            let pose = place.pose * xyz_rpy(c.origin.xyz.0, c.origin.rpy.0, 1.0, 1.0);
            let shape = match &c.geometry {
                urdf_rs::Geometry::Sphere { radius } => {
                    BodyShape::Sphere { center: pose.translation.vector, radius: *radius }
                }
                urdf_rs::Geometry::Box { size } => BodyShape::Box { pose, half_extents: Vector3::from(size.0) * 0.5 },
                urdf_rs::Geometry::Cylinder { radius, length } => {
                    BodyShape::Cylinder { pose, radius: *radius, half_length: length * 0.5 }
                }
                urdf_rs::Geometry::Capsule { radius, length } => {
                    let half = pose.rotation * Vector3::new(0.0, 0.0, length * 0.5);
                    let c = pose.translation.vector;
                    BodyShape::Capsule { a: c - half, b: c + half, radius: *radius }
                }
                urdf_rs::Geometry::Mesh { filename, scale } => match options.meshes.and_then(|read| read(filename)) {
                    None => BodyShape::Missing {
                        what: format!(
                            "link `{name}`: collision mesh `{filename}` is not loaded (read the URDF from its file)"
                        ),
                    },
                    Some(bytes) => {
                        let bytes = bytes.map_err(|e| {
                            ModelError::Urdf(format!("link `{name}`: collision mesh `{filename}`: {e}"))
                        })?;
                        let vertices = super::mesh_vertices(filename, &bytes)
                            .map_err(|e| ModelError::Urdf(format!("link `{name}`: {e}")))?;
                        let k = scale.map_or(Vector3::repeat(1.0), |s| Vector3::from(s.0));
                        let vertices = vertices
                            .iter()
                            .map(|v| (pose * nalgebra::Point3::from(v.component_mul(&k))).coords)
                            .collect();
                        BodyShape::ConvexMesh { source: filename.clone(), vertices }
                    }
                },
            };
            shapes.push(shape);
        }
        let index = bodies.len();
        bodies.push(LinkBody { name: name.to_string(), frame: place.frame, parent, shapes, padding: 0.0 });
        for j in urdf.joints.iter().filter(|j| j.parent.link == name) {
            let child = if let Some(&frame) = frames.get(j.name.as_str()) {
                Place { frame, pose: Isometry3::identity(), lost: place.lost.clone() }
            } else {
                let moving_mimic =
                    movable(j) && j.mimic.as_ref().is_some_and(|m| frames.contains_key(m.joint.as_str()));
                let lost = place.lost.clone().or_else(|| {
                    moving_mimic.then(|| format!("it follows the moving mimic joint `{}`, not a chain frame", j.name))
                });
                let mut pose = place.pose * xyz_rpy(j.origin.xyz.0, j.origin.rpy.0, 1.0, 1.0);
                if movable(j) && lost.is_none() {
                    let axis = Vector3::from(j.axis.xyz.0).try_normalize(AXIS_MIN_NORM).unwrap_or_else(Vector3::z);
                    let v = value_of(j);
                    pose *= if j.joint_type == urdf_rs::JointType::Prismatic {
                        Isometry3::translation(axis.x * v, axis.y * v, axis.z * v)
                    } else {
                        Isometry3::rotation(axis * v)
                    };
                }
                Place { frame: place.frame, pose, lost }
            };
            queue.push((j.child.link.as_str(), child, Some(index)));
        }
    }
    // Links without solids stay: they carry the adjacency between their parent and children.
    Ok(bodies)
}

/// The serial chain `chain` selects in a parsed URDF tree: its base link, its tip link and the
/// joints from base to tip (the errors of [`Robot::from_urdf_str`] about the tree and the chain).
fn chain_path<'a>(
    urdf: &'a urdf_rs::Robot,
    chain: &'a UrdfChain,
) -> Result<(&'a str, &'a str, Vec<&'a urdf_rs::Joint>), ModelError> {
    let links: BTreeSet<&str> = urdf.links.iter().map(|l| l.name.as_str()).collect();
    let mut parent_joint: BTreeMap<&str, &urdf_rs::Joint> = BTreeMap::new();
    let mut children: BTreeMap<&str, Vec<&str>> = BTreeMap::new();
    for j in &urdf.joints {
        for (role, link) in [("parent", &j.parent.link), ("child", &j.child.link)] {
            if !links.contains(link.as_str()) {
                return Err(ModelError::Urdf(format!(
                    "joint `{}`: its {role} link `{link}` is not declared (no <link name=\"{link}\">)",
                    j.name
                )));
            }
        }
        if parent_joint.insert(j.child.link.as_str(), j).is_some() {
            return Err(ModelError::Urdf(format!("link `{}` has two parent joints", j.child.link)));
        }
        children.entry(j.parent.link.as_str()).or_default().push(j.child.link.as_str());
    }
    check_acyclic(&links, &parent_joint)?;
    let known = |name: &str| -> Result<(), ModelError> {
        if links.contains(name) {
            Ok(())
        } else {
            let list: Vec<&str> = links.iter().copied().collect();
            Err(ModelError::Urdf(format!("no link named `{name}` (links: {})", list.join(", "))))
        }
    };
    let base: &str = match &chain.base {
        Some(b) => {
            known(b)?;
            b
        }
        None => {
            let roots: Vec<&str> = links.iter().copied().filter(|l| !parent_joint.contains_key(l)).collect();
            match roots.as_slice() {
                [root] => root,
                [] => {
                    return Err(ModelError::Urdf("the link tree has no root (a cycle?)".into()));
                }
                many => {
                    return Err(ModelError::Urdf(format!(
                        "several root links ({}); choose the base link",
                        many.join(", ")
                    )));
                }
            }
        }
    };
    let tip: &str = match &chain.tip {
        Some(t) => {
            known(t)?;
            t
        }
        None => {
            // Walk down from the base while the chain does not branch. A path visits each
            // joint at most once, so more steps than joints means a cycle.
            let mut link = base;
            let mut steps = 0;
            loop {
                match children.get(link).map(Vec::as_slice) {
                    None | Some([]) => break link,
                    Some([_]) if steps > urdf.joints.len() => return Err(cycle(link)),
                    Some([only]) => {
                        link = only;
                        steps += 1;
                    }
                    Some(many) => {
                        return Err(ModelError::Urdf(format!(
                            "the tree branches at link `{link}` (children: {}); choose the tip link",
                            many.join(", ")
                        )));
                    }
                }
            }
        }
    };
    // Walk up from the tip to the base.
    let mut path: Vec<&urdf_rs::Joint> = Vec::new();
    let mut link = tip;
    while link != base {
        match parent_joint.get(link) {
            Some(_) if path.len() > urdf.joints.len() => return Err(cycle(link)),
            Some(j) => {
                path.push(j);
                link = j.parent.link.as_str();
            }
            None => {
                return Err(ModelError::Urdf(format!("link `{tip}` is not below link `{base}`")));
            }
        }
    }
    path.reverse();
    Ok((base, tip, path))
}

/// The base and tip links of the chain `chain` selects in a URDF document (the defaults
/// resolved as [`Robot::from_urdf_str`] resolves them).
///
/// # Errors
/// As [`Robot::from_urdf_str`] for the document and the chain.
pub fn urdf_chain_links(text: &str, chain: &UrdfChain) -> Result<(String, String), ModelError> {
    let urdf = urdf_rs::read_from_string(text).map_err(|e| ModelError::Urdf(one_line(&e.to_string())))?;
    let (base, tip, _) = chain_path(&urdf, chain)?;
    Ok((base.to_string(), tip.to_string()))
}

/// The `filename` of every `<visual>` mesh of a URDF document (every link, in document order,
/// each once), as written (`package://…`, relative or `file://` addresses).
///
/// # Errors
/// [`ModelError::Urdf`] for XML errors.
pub fn urdf_visual_meshes(text: &str) -> Result<Vec<String>, ModelError> {
    mesh_files(text, |l| l.visual.iter().map(|v| &v.geometry).collect())
}

/// The `filename` of every `<collision>` mesh of a URDF document, as
/// [`urdf_visual_meshes`] lists the visual ones.
///
/// # Errors
/// [`ModelError::Urdf`] for XML errors.
pub fn urdf_collision_meshes(text: &str) -> Result<Vec<String>, ModelError> {
    mesh_files(text, |l| l.collision.iter().map(|c| &c.geometry).collect())
}

/// The distinct mesh file names of the geometries `of` picks from each link.
fn mesh_files(text: &str, of: impl Fn(&urdf_rs::Link) -> Vec<&urdf_rs::Geometry>) -> Result<Vec<String>, ModelError> {
    let urdf = urdf_rs::read_from_string(text).map_err(|e| ModelError::Urdf(one_line(&e.to_string())))?;
    let mut files: Vec<String> = Vec::new();
    for geometry in urdf.links.iter().flat_map(of) {
        if let urdf_rs::Geometry::Mesh { filename, .. } = geometry
            && !files.contains(filename)
        {
            files.push(filename.clone());
        }
    }
    Ok(files)
}

/// The file a URDF mesh address names, for the URDF file at `urdf` (an absolute path, for
/// `package://` to search its ancestors): `package://NAME/REST` is `REST` below the nearest
/// directory named `NAME` above the URDF file (the ROS package layout), or else below the
/// directory `NAME` beside the URDF file (MotionBenchMaker's layout; `is_dir` tells whether a
/// directory exists); `file:///PATH` is `/PATH`; an address without a scheme is relative to
/// the URDF file's directory.
///
/// # Errors
/// A reason for another scheme or a package with no such directory above or beside the file.
pub fn mesh_file_path(
    urdf: &std::path::Path,
    filename: &str,
    is_dir: &dyn Fn(&std::path::Path) -> bool,
) -> Result<std::path::PathBuf, String> {
    let dir = urdf.parent().unwrap_or(std::path::Path::new("."));
    if let Some(rest) = filename.strip_prefix("package://") {
        let (package, rest) = rest.split_once('/').ok_or("no file after the package name")?;
        return dir
            .ancestors()
            .find(|a| a.file_name().is_some_and(|n| n == package))
            .map(|root| root.join(rest))
            .or_else(|| Some(dir.join(package)).filter(|d| is_dir(d)).map(|d| d.join(rest)))
            .ok_or_else(|| format!("no directory `{package}` above or beside {}", urdf.display()));
    }
    if let Some(abs) = filename.strip_prefix("file://") {
        return Ok(std::path::PathBuf::from(abs));
    }
    if filename.contains("://") {
        return Err("only package://, file:// and relative addresses can be read".into());
    }
    Ok(dir.join(filename))
}

fn cycle(link: &str) -> ModelError {
    ModelError::Urdf(format!("the link tree has a cycle through link `{link}`"))
}

fn movable(j: &urdf_rs::Joint) -> bool {
    matches!(
        j.joint_type,
        urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous | urdf_rs::JointType::Prismatic
    )
}

/// Checks that the master of mimic joint `j` exists, moves and is not itself a mimic joint.
fn check_master(urdf: &urdf_rs::Robot, j: &urdf_rs::Joint, master: &str) -> Result<(), ModelError> {
    let fail = |why: &str| ModelError::Urdf(format!("joint `{}` mimics joint `{master}`, {why}", j.name));
    match urdf.joints.iter().find(|m| m.name == master) {
        None => Err(fail("which does not exist")),
        Some(m) if m.mimic.is_some() => Err(fail("which is itself a mimic joint")),
        Some(m) if !movable(m) => {
            Err(fail(&format!("which is a {} joint", format!("{:?}", m.joint_type).to_lowercase())))
        }
        Some(_) => Ok(()),
    }
}

/// Rejects a cycle of parent joints, naming a joint on it. Each link is walked up at most once.
fn check_acyclic(links: &BTreeSet<&str>, parent_joint: &BTreeMap<&str, &urdf_rs::Joint>) -> Result<(), ModelError> {
    // 1: on the current walk; 2: known to reach a root.
    let mut state: BTreeMap<&str, u8> = BTreeMap::new();
    for &start in links {
        let mut walk: Vec<&str> = Vec::new();
        let mut link = start;
        loop {
            match state.get(link) {
                Some(2) => break,
                Some(_) => {
                    let joint = &parent_joint[link].name;
                    return Err(ModelError::Urdf(format!(
                        "joint `{joint}` closes a cycle of links through link `{link}` (a URDF must be a tree)"
                    )));
                }
                None => {}
            }
            state.insert(link, 1);
            walk.push(link);
            match parent_joint.get(link) {
                Some(j) => link = j.parent.link.as_str(),
                None => break,
            }
        }
        for l in walk {
            state.insert(l, 2);
        }
    }
    Ok(())
}
