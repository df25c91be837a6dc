//! Robot models: joints, DH/MDH/URDF geometry, limits, validation, description files.
//!
//! A [`Robot`] is a serial chain of revolute and prismatic joints between a base transform
//! and a tool transform. It is built from a [`RobotSpec`] (plain data, all SI units and
//! radians) by [`Robot::new`], which validates every number and names the offending joint
//! and field on failure. Description files are parsed from strings by
//! [`Robot::from_toml_str`] and [`Robot::from_urdf_str`]; the shipped presets are in
//! [`presets`].

mod body;
mod dh_equivalent;
mod error;
mod inertia;
mod joint;
mod joint_limits;
mod robot;
mod toml_format;
mod urdf;

pub(crate) mod chain;
pub(crate) mod fk_chain;
pub(crate) mod frame_lanes;
pub mod planar_angles;
pub mod presets;

pub use body::{BodyShape, LinkBody, MAX_MESH_TRIANGLES, enclosing_capsule, mesh_vertices, srdf_disabled_pairs};
pub use error::ModelError;
pub use inertia::{LinkInertial, STANDARD_GRAVITY};
pub use joint::{
    Convention, DhParams, Joint, JointDrive, JointGeometry, JointKind, Limits, LinkGeometry, MimicJoint, StepMode,
    Wiring,
};
pub use robot::{Robot, RobotSpec};
pub use toml_format::{AngleUnit, FileUnits, LengthUnit};
pub use urdf::{
    UrdfBodyOptions, UrdfChain, mesh_file_path, urdf_chain_links, urdf_collision_meshes, urdf_visual_meshes,
};
