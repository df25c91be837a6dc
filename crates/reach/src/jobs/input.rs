//! What every request shares: the robot, joint vectors in the user's units, poses, and the
//! conversions between the user's units and SI.
//!
//! # Units in requests and reports
//!
//! * Joint vectors are typed by unit: `{"deg": [0, -90, 90]}` or `{"rad": [0, -1.57, 1.57]}`
//!   ([`Joints`]); revolute joints take the named unit, **prismatic joints always metres**.
//!   Messages about a request quote joint values in the unit it was typed in ([`AngleUnit`]).
//! * Reports give joint values in display units under names that carry them: `q_deg`
//!   (revolute degrees, prismatic metres), and SI under `q_si` where both are useful.
//! * Poses ([`Pose`]): `xyz_m` with one of `rpy_deg`, `rpy_rad`, `quat_wxyz`, or a row-major
//!   4×4 `matrix` alone; `xyz_m` alone is a position-only target.

use nalgebra::{Isometry3, Matrix3, Matrix4, Point3, Rotation3, Translation3, UnitQuaternion};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result, one_line};
use crate::ik::IkTarget;
use std::collections::BTreeMap;

use crate::model::{FileUnits, JointKind, Robot, UrdfBodyOptions, UrdfChain, presets};
use crate::motion::JointSample;
use crate::tolerance::{LIMIT_SLACK, ROTATION_ORTHONORMALITY};

/// Where a request's robot comes from: a preset name, or the text of a description file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum RobotInput {
    /// A preset by name (`reach robots` lists them).
    Preset(String),
    /// The text of a TOML robot description (docs/robot-format.md).
    Toml {
        /// The file's text.
        text: String,
    },
    /// The text of a URDF document and the chain to take from its tree.
    Urdf {
        /// The document's text.
        text: String,
        /// The link the chain starts at (default: the tree's root).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        base: Option<String>,
        /// The link the chain ends at (default: the only leaf below the base).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        tip: Option<String>,
        /// The collision mesh files, by their `filename` as the document writes it: the
        /// file's bytes, base64 (standard alphabet). A mesh not given leaves its link's body
        /// incomplete: kinematics work, collision checks are refused naming the file.
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        meshes: BTreeMap<String, String>,
        /// The text of a MoveIt SRDF whose `disable_collisions` pairs are never checked.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        srdf: Option<String>,
        /// The text of a MoveIt `joint_limits.yaml` whose velocity, acceleration and jerk
        /// limits override the URDF's ([`Robot::with_moveit_joint_limits`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        joint_limits: Option<String>,
        /// Positions of movable joints off the chain (a gripper's fingers), radians or metres.
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        locked: BTreeMap<String, f64>,
    },
}

/// A robot with the units its description was written in.
#[derive(Debug, Clone)]
pub struct LoadedRobot {
    /// The validated model (SI units, radians).
    pub robot: Robot,
    /// Units of the TOML description (`None` for URDF: always metres and radians).
    pub units: Option<FileUnits>,
}

impl RobotInput {
    /// A URDF robot's input with its collision meshes: `read` gives a mesh file's bytes by
    /// its `filename` as the document writes it (`None`: not available, the body stays
    /// incomplete; see [`RobotInput::Urdf`]).
    ///
    /// # Errors
    /// A reason naming the file that `read` could not read; the document itself is checked
    /// by [`RobotInput::load`].
    pub fn urdf(
        text: String,
        chain: &UrdfChain,
        read: impl Fn(&str) -> Option<std::result::Result<Vec<u8>, String>>,
    ) -> std::result::Result<RobotInput, String> {
        use base64::Engine as _;
        let mut meshes = BTreeMap::new();
        // A document that does not parse is reported when the robot is loaded.
        for filename in crate::model::urdf_collision_meshes(&text).unwrap_or_default() {
            if let Some(bytes) = read(&filename) {
                let bytes = bytes.map_err(|e| format!("collision mesh `{filename}`: {e}"))?;
                meshes.insert(filename, base64::engine::general_purpose::STANDARD.encode(bytes));
            }
        }
        Ok(RobotInput::Urdf {
            text,
            base: chain.base.clone(),
            tip: chain.tip.clone(),
            meshes,
            srdf: None,
            joint_limits: None,
            locked: BTreeMap::new(),
        })
    }

    /// Parses the robot.
    ///
    /// # Errors
    /// [`Error::Model`]: an unknown preset (naming the known ones), a malformed description.
    pub fn load(&self) -> Result<LoadedRobot> {
        match self {
            RobotInput::Preset(name) => {
                let text = presets::source(name).ok_or_else(|| crate::model::ModelError::UnknownPreset {
                    name: name.clone(),
                    known: presets::names().join(", "),
                })?;
                let (robot, units) = Robot::from_toml_str_with_units(text)?;
                Ok(LoadedRobot { robot, units: Some(units) })
            }
            RobotInput::Toml { text } => {
                let (robot, units) = Robot::from_toml_str_with_units(text)?;
                Ok(LoadedRobot { robot, units: Some(units) })
            }
            RobotInput::Urdf { text, base, tip, meshes, srdf, joint_limits, locked } => {
                use base64::Engine as _;
                let chain = UrdfChain { base: base.clone(), tip: tip.clone() };
                let read = |file: &str| -> Option<std::result::Result<Vec<u8>, String>> {
                    meshes.get(file).map(|b| {
                        base64::engine::general_purpose::STANDARD.decode(b).map_err(|e| format!("not base64: {e}"))
                    })
                };
                let locked: Vec<(String, f64)> = locked.iter().map(|(k, v)| (k.clone(), *v)).collect();
                let options = UrdfBodyOptions { locked: &locked, meshes: Some(&read) };
                let mut robot = Robot::from_urdf_str_with(text, &chain, &options)?;
                if let Some(srdf) = srdf {
                    robot = robot.with_disabled_collisions(&crate::model::srdf_disabled_pairs(srdf)?)?;
                }
                if let Some(limits) = joint_limits {
                    robot = robot.with_moveit_joint_limits(limits)?;
                }
                Ok(LoadedRobot { robot, units: None })
            }
        }
    }
}

/// The unit revolute joint values (and angle messages) are written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum AngleUnit {
    /// Degrees (the default of the command line).
    #[default]
    Deg,
    /// Radians.
    Rad,
}

impl AngleUnit {
    /// A revolute value typed in this unit, in radians.
    #[must_use]
    pub fn to_rad(self, value: f64) -> f64 {
        match self {
            AngleUnit::Deg => value.to_radians(),
            AngleUnit::Rad => value,
        }
    }

    /// A value in radians, in this unit.
    #[must_use]
    pub fn from_rad(self, value: f64) -> f64 {
        match self {
            AngleUnit::Deg => value.to_degrees(),
            AngleUnit::Rad => value,
        }
    }

    /// `deg` or `rad`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            AngleUnit::Deg => "deg",
            AngleUnit::Rad => "rad",
        }
    }
}

/// Joint values as typed: revolute joints in degrees or radians, prismatic joints in metres.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Joints {
    /// Revolute joints in degrees, prismatic in metres.
    Deg(Vec<f64>),
    /// Revolute joints in radians, prismatic in metres.
    Rad(Vec<f64>),
}

impl Joints {
    /// The unit the revolute values are typed in.
    #[must_use]
    pub fn unit(&self) -> AngleUnit {
        match self {
            Joints::Deg(_) => AngleUnit::Deg,
            Joints::Rad(_) => AngleUnit::Rad,
        }
    }

    /// The values as typed.
    #[must_use]
    pub fn values(&self) -> &[f64] {
        match self {
            Joints::Deg(v) | Joints::Rad(v) => v,
        }
    }

    /// The values in SI (radians, metres) for `robot`, checked: one finite value per joint.
    ///
    /// # Errors
    /// [`Error::Request`] naming `field` (and the 1-based joint for a non-finite value).
    pub fn si(&self, robot: &Robot, field: &str) -> Result<Vec<f64>> {
        let values = self.values();
        if values.len() != robot.dof() {
            return Err(Error::request(
                field,
                format!(
                    "robot `{}` has {} joints, got {} joint value{}",
                    robot.name(),
                    robot.dof(),
                    values.len(),
                    if values.len() == 1 { "" } else { "s" }
                ),
            ));
        }
        let unit = self.unit();
        robot
            .joints()
            .iter()
            .zip(values)
            .enumerate()
            .map(|(i, (j, &v))| {
                if v.is_finite() {
                    Ok(to_si(j.kind, v, unit))
                } else {
                    Err(Error::request(
                        format!("{field}: joint {}", i + 1),
                        format!("expected a finite number, got {v}"),
                    ))
                }
            })
            .collect()
    }

    /// The values in display units (revolute degrees, prismatic metres); degrees are kept
    /// exactly as typed (no round trip through radians).
    #[must_use]
    pub fn display(&self, robot: &Robot) -> Vec<f64> {
        match self {
            Joints::Deg(v) => v.clone(),
            Joints::Rad(v) => q_display(robot, v),
        }
    }
}

/// A joint value typed in `unit`, in SI (revolute radians, prismatic metres as given).
#[must_use]
pub fn to_si(kind: JointKind, value: f64, unit: AngleUnit) -> f64 {
    match kind {
        JointKind::Revolute => unit.to_rad(value),
        JointKind::Prismatic => value,
    }
}

/// An SI joint value in `unit` (inverse of [`to_si`]).
#[must_use]
pub fn from_si(kind: JointKind, value: f64, unit: AngleUnit) -> f64 {
    match kind {
        JointKind::Revolute => unit.from_rad(value),
        JointKind::Prismatic => value,
    }
}

/// The joint vector (SI) in display units: revolute joints in degrees, prismatic in metres —
/// what report fields named `q_deg` hold.
#[must_use]
pub fn q_display(robot: &Robot, q: &[f64]) -> Vec<f64> {
    robot.joints().iter().zip(q).map(|(j, &v)| from_si(j.kind, v, AngleUnit::Deg)).collect()
}

/// The unit name of a joint value in `unit`: `deg`/`rad` for revolute joints, `m` for
/// prismatic ones.
#[must_use]
pub fn unit_name(kind: JointKind, unit: AngleUnit) -> &'static str {
    match kind {
        JointKind::Revolute => unit.as_str(),
        JointKind::Prismatic => "m",
    }
}

/// The CSV column names of one joint quantity, with their units: `q1_deg … q6_deg` (a
/// prismatic joint `q3_m`), `qd1_deg_s` with `per = "_s"`, `qdd1_deg_s2` with `per = "_s2"`.
/// What `reach move --csv` and `reach retime --csv` write and [`parse_motion_csv`] and
/// [`parse_path_file`] read back.
pub fn joint_columns<'a>(
    robot: &'a Robot,
    unit: AngleUnit,
    quantity: &'a str,
    per: &'a str,
) -> impl Iterator<Item = String> + 'a {
    robot.joints().iter().enumerate().map(move |(i, j)| format!("{quantity}{}_{}{per}", i + 1, unit_name(j.kind, unit)))
}

/// A CSV header's time and joint-position columns (0-based): `t_s`, and `q1 … qn`, each
/// named `qN` or `qN_deg`, `qN_rad`, `qN_m` ([`joint_columns`]); `None` when the row names no
/// joint column. The unit is that of the revolute columns (`None`: none says; all that say
/// must agree).
struct CsvColumns {
    time: Option<usize>,
    joints: Vec<usize>,
    unit: Option<AngleUnit>,
}

fn csv_columns(cells: &[&str]) -> std::result::Result<Option<CsvColumns>, String> {
    let mut time = None;
    let mut joints: Vec<(usize, usize)> = Vec::new();
    let mut unit: Option<AngleUnit> = None;
    for (column, cell) in cells.iter().enumerate() {
        let name = cell.trim();
        if name == "t_s" {
            time = Some(column);
            continue;
        }
        let Some(rest) = name.strip_prefix('q') else { continue };
        let (number, suffix) = rest.split_once('_').unwrap_or((rest, ""));
        let Ok(index) = number.parse::<usize>() else { continue };
        let said = match suffix {
            "" | "m" => None,
            "deg" => Some(AngleUnit::Deg),
            "rad" => Some(AngleUnit::Rad),
            _ => continue,
        };
        if let Some(u) = said {
            if unit.is_some_and(|prev| prev != u) {
                return Err(format!("column `{name}`: the joint columns mix degrees and radians"));
            }
            unit = Some(u);
        }
        joints.push((index, column));
    }
    if joints.is_empty() {
        return Ok(None);
    }
    joints.sort_unstable();
    for (k, (index, _)) in joints.iter().enumerate() {
        if *index != k + 1 {
            return Err(format!("the joint columns are not q1 … q{}: q{} is missing or repeated", joints.len(), k + 1));
        }
    }
    Ok(Some(CsvColumns { time, joints: joints.into_iter().map(|(_, c)| c).collect(), unit }))
}

/// A CSV's header cells (if any) and its rows of numbers with their 1-based line numbers.
type CsvTable = (Option<Vec<String>>, Vec<(usize, Vec<f64>)>);

/// The rows of a CSV (values separated by commas and/or blanks; blank lines and `#` comments
/// skipped) after an optional header row of names, as numbers: the header's cells and the
/// rows, each row as long as the first. Errors name the line (1-based) and the column.
fn csv_rows(text: &str) -> std::result::Result<CsvTable, String> {
    let mut header = None;
    let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
    for (line_index, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let cells: Vec<&str> = line.split([',', ' ', '\t', ';']).filter(|c| !c.trim().is_empty()).collect();
        let parsed: Vec<Option<f64>> = cells.iter().map(|c| c.trim().parse::<f64>().ok()).collect();
        if rows.is_empty() && header.is_none() && parsed.iter().all(Option::is_none) {
            header = Some(cells.iter().map(|c| c.trim().to_string()).collect());
            continue;
        }
        let mut row = Vec::with_capacity(cells.len());
        for (column, (cell, value)) in cells.iter().zip(&parsed).enumerate() {
            match value {
                Some(v) if v.is_finite() => row.push(*v),
                _ => {
                    return Err(format!(
                        "line {}, column {}: expected a finite number, got {cell:?}",
                        line_index + 1,
                        column + 1
                    ));
                }
            }
        }
        if let Some((_, first)) = rows.first()
            && first.len() != row.len()
        {
            return Err(format!(
                "line {}: {} values, but the first row has {}",
                line_index + 1,
                row.len(),
                first.len()
            ));
        }
        rows.push((line_index + 1, row));
    }
    Ok((header, rows))
}

/// The header's columns, checked against the rows' width.
fn header_columns(header: Option<&Vec<String>>, width: usize) -> std::result::Result<Option<CsvColumns>, String> {
    let Some(header) = header else { return Ok(None) };
    let cells: Vec<&str> = header.iter().map(String::as_str).collect();
    let columns = csv_columns(&cells)?;
    if let Some(c) = &columns
        && let Some(&beyond) = c.time.iter().chain(&c.joints).find(|&&k| k >= width)
    {
        return Err(format!("column `{}` has no values: the rows have {width}", header[beyond]));
    }
    Ok(columns)
}

/// 1-based numbers of the joints whose value (SI) lies outside their limits (with the crate's
/// [`LIMIT_SLACK`]).
#[must_use]
pub fn joints_outside_limits(robot: &Robot, q: &[f64]) -> Vec<usize> {
    robot
        .joints()
        .iter()
        .zip(q)
        .enumerate()
        .filter(|(_, (j, v))| !j.limits.contains(**v, LIMIT_SLACK))
        .map(|(i, _)| i + 1)
        .collect()
}

/// A number for a message, in the user's units: at most 6 decimals, trailing zeros dropped
/// (`180`, not `179.99999999999997` after a round trip through radians); huge values in
/// exponent form (`1e308`).
#[must_use]
pub fn number_text(v: f64) -> String {
    if !v.is_finite() || v.abs() >= 1e9 {
        return format!("{v:e}");
    }
    let text = format!("{v:.6}");
    let text = if text.contains('.') { text.trim_end_matches('0').trim_end_matches('.') } else { &text };
    if text == "-0" { "0".to_string() } else { text.to_string() }
}

/// Refuses joint values (SI) outside their position limits, naming the first such joint, its
/// value and its limits in `unit` (prismatic joints in metres):
/// `to: joint 1 `q1` = 270 deg is outside its limits [-180, 180] deg`.
///
/// # Errors
/// [`Error::Request`] naming `field`.
pub fn require_within_limits(robot: &Robot, q: &[f64], unit: AngleUnit, field: &str) -> Result<()> {
    let Some(i) = robot.first_joint_outside_limits(q, LIMIT_SLACK) else {
        return Ok(());
    };
    let joint = &robot.joints()[i];
    let shown = |v: f64| number_text(from_si(joint.kind, v, unit));
    let name = unit_name(joint.kind, unit);
    Err(Error::request(
        field,
        format!(
            "joint {} `{}` = {} {name} is outside its limits [{}, {}] {name}",
            i + 1,
            joint.name,
            shown(q[i]),
            shown(joint.limits.lower),
            shown(joint.limits.upper)
        ),
    ))
}

/// A pose as typed: position in metres with one orientation, or a homogeneous matrix.
///
/// Exactly one of: `matrix`; or `xyz_m` with at most one of `rpy_deg`, `rpy_rad`, `quat_wxyz`
/// (none: a position-only target, for IK of arms that cannot set orientation). Roll, pitch,
/// yaw are about fixed axes, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`; quaternions `w, x, y, z`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Pose {
    /// Position, metres.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub xyz_m: Option<[f64; 3]>,
    /// Roll, pitch, yaw in degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy_deg: Option<[f64; 3]>,
    /// Roll, pitch, yaw in radians.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rpy_rad: Option<[f64; 3]>,
    /// Unit quaternion `w, x, y, z` (normalised here; must not be zero).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quat_wxyz: Option<[f64; 4]>,
    /// Homogeneous 4×4 matrix, row-major: last row `0 0 0 1`, rotation orthonormal.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub matrix: Option<[[f64; 4]; 4]>,
}

impl Pose {
    /// A pose from a position and roll, pitch, yaw in degrees.
    #[must_use]
    pub fn xyz_rpy_deg(xyz_m: [f64; 3], rpy_deg: [f64; 3]) -> Self {
        Pose { xyz_m: Some(xyz_m), rpy_deg: Some(rpy_deg), ..Pose::default() }
    }

    /// The IK target: a full pose, or a position when no orientation is given.
    ///
    /// # Errors
    /// [`Error::Request`] naming `field` (`field.matrix`, `field.quat_wxyz`, …): non-finite
    /// numbers, no or contradicting parts, a matrix whose last row is not `0 0 0 1`, whose
    /// rotation is not orthonormal (`max |RᵀR − I| > ROTATION_ORTHONORMALITY`) or is a
    /// reflection, a zero quaternion.
    pub fn target(&self, field: &str) -> Result<IkTarget> {
        let sub = |name: &str| format!("{field}.{name}");
        let finite = |name: &str, values: &[f64]| -> Result<()> {
            match values.iter().position(|v| !v.is_finite()) {
                Some(i) => Err(Error::request(
                    format!("{}[{}]", sub(name), i + 1),
                    format!("expected a finite number, got {}", values[i]),
                )),
                None => Ok(()),
            }
        };
        let orientations = [self.rpy_deg.is_some(), self.rpy_rad.is_some(), self.quat_wxyz.is_some()];
        let count = orientations.iter().filter(|&&b| b).count();
        if let Some(m) = &self.matrix {
            if self.xyz_m.is_some() || count > 0 {
                return Err(Error::request(field, "give either `matrix` or `xyz_m` with an orientation, not both"));
            }
            let flat: Vec<f64> = m.iter().flatten().copied().collect();
            finite("matrix", &flat)?;
            return Ok(IkTarget::Pose(pose_from_matrix(&sub("matrix"), &Matrix4::from_row_slice(&flat))?));
        }
        let Some(xyz) = self.xyz_m else {
            return Err(Error::request(field, "give `xyz_m` (with an orientation) or `matrix`"));
        };
        finite("xyz_m", &xyz)?;
        if count > 1 {
            return Err(Error::request(field, "give at most one of `rpy_deg`, `rpy_rad`, `quat_wxyz`"));
        }
        let point = Point3::from(xyz);
        let rotation = if let Some(a) = self.rpy_deg {
            finite("rpy_deg", &a)?;
            UnitQuaternion::from_euler_angles(a[0].to_radians(), a[1].to_radians(), a[2].to_radians())
        } else if let Some(a) = self.rpy_rad {
            finite("rpy_rad", &a)?;
            UnitQuaternion::from_euler_angles(a[0], a[1], a[2])
        } else if let Some(q) = self.quat_wxyz {
            finite("quat_wxyz", &q)?;
            let quaternion = nalgebra::Quaternion::new(q[0], q[1], q[2], q[3]);
            if quaternion.norm() < 1e-9 {
                return Err(Error::request(sub("quat_wxyz"), "a zero quaternion is not a rotation"));
            }
            UnitQuaternion::from_quaternion(quaternion)
        } else {
            return Ok(IkTarget::Position(point));
        };
        Ok(IkTarget::Pose(Isometry3::from_parts(Translation3::from(point.coords), rotation)))
    }

    /// The full pose.
    ///
    /// # Errors
    /// As [`Pose::target`], and [`Error::Request`] when no orientation is given.
    pub fn isometry(&self, field: &str) -> Result<Isometry3<f64>> {
        match self.target(field)? {
            IkTarget::Pose(p) => Ok(p),
            IkTarget::Position(_) => {
                Err(Error::request(field, "needs an orientation: `rpy_deg`, `rpy_rad` or `quat_wxyz` (or a `matrix`)"))
            }
        }
    }
}

/// A pose from a homogeneous matrix: the last row must be exactly `0 0 0 1` and the rotation
/// part orthonormal (`max |RᵀR − I| ≤ ROTATION_ORTHONORMALITY`) with determinant +1.
fn pose_from_matrix(field: &str, m: &Matrix4<f64>) -> Result<Isometry3<f64>> {
    let last = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]];
    if last != [0.0, 0.0, 0.0, 1.0] {
        return Err(Error::request(field, format!("the last row must be 0 0 0 1, got {last:?}")));
    }
    let r: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    let deviation = (r.transpose() * r - Matrix3::identity()).abs().max();
    if deviation > ROTATION_ORTHONORMALITY {
        return Err(Error::request(
            field,
            format!(
                "the rotation part (rows and columns 1-3) is not orthonormal: max |RᵀR − I| = {deviation:.3e}, \
                 more than {ROTATION_ORTHONORMALITY:e}"
            ),
        ));
    }
    if r.determinant() < 0.0 {
        return Err(Error::request(field, "the rotation part is a reflection (determinant −1), not a rotation"));
    }
    let translation = Translation3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]);
    // Closed form (Shepperd): `UnitQuaternion::from_matrix`'s iteration starts at the identity
    // and stalls on half-turns (diag(−1, 1, −1) came back as a 0.0155° roll).
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Isometry3::from_parts(translation, rotation))
}

/// The homogeneous matrix of a pose, row-major (`matrix[row][column]`).
#[must_use]
pub fn matrix_rows(pose: &Isometry3<f64>) -> [[f64; 4]; 4] {
    let m = pose.to_homogeneous();
    std::array::from_fn(|r| std::array::from_fn(|c| m[(r, c)]))
}

/// Any matrix as its rows (`rows[row][column]`), the layout of every matrix in a JSON report.
#[must_use]
pub fn dense_rows<R: nalgebra::Dim, C: nalgebra::Dim, S: nalgebra::RawStorage<f64, R, C>>(
    m: &nalgebra::Matrix<f64, R, C, S>,
) -> Vec<Vec<f64>> {
    m.row_iter().map(|row| row.iter().copied().collect()).collect()
}

/// A pose in a report: `{"matrix", "xyz_m", "rpy_deg", "quat_wxyz"}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct PoseReport {
    /// Homogeneous matrix, row-major.
    pub matrix: [[f64; 4]; 4],
    /// Position, metres.
    pub xyz_m: [f64; 3],
    /// Roll, pitch, yaw in degrees, `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
    pub rpy_deg: [f64; 3],
    /// Unit quaternion `w, x, y, z` with `w ≥ 0`.
    pub quat_wxyz: [f64; 4],
}

impl PoseReport {
    /// The report form of a pose.
    #[must_use]
    pub fn of(pose: &Isometry3<f64>) -> Self {
        PoseReport {
            matrix: matrix_rows(pose),
            xyz_m: pose.translation.vector.into(),
            rpy_deg: rpy_deg(&pose.rotation),
            quat_wxyz: quat_wxyz(&pose.rotation),
        }
    }
}

/// Roll, pitch, yaw in radians with `R = Rz(yaw)·Ry(pitch)·Rx(roll)`.
#[must_use]
pub fn rpy_rad(rotation: &UnitQuaternion<f64>) -> [f64; 3] {
    let (roll, pitch, yaw) = rotation.euler_angles();
    [roll, pitch, yaw]
}

/// Roll, pitch, yaw in degrees (see [`rpy_rad`]).
#[must_use]
pub fn rpy_deg(rotation: &UnitQuaternion<f64>) -> [f64; 3] {
    rpy_rad(rotation).map(f64::to_degrees)
}

/// The quaternion as `[w, x, y, z]` with `w ≥ 0`.
#[must_use]
pub fn quat_wxyz(rotation: &UnitQuaternion<f64>) -> [f64; 4] {
    let q = rotation.quaternion();
    let s = if q.w < 0.0 { -1.0 } else { 1.0 };
    [s * q.w, s * q.i, s * q.j, s * q.k]
}

/// A positive finite number from an optional request field.
///
/// # Errors
/// [`Error::Request`] naming `field` when the value is not finite or not `> 0`.
pub fn positive(field: &str, value: Option<f64>) -> Result<Option<f64>> {
    match value {
        Some(v) if !v.is_finite() => Err(Error::request(field, format!("expected a finite number, got {v}"))),
        Some(v) if v <= 0.0 => Err(Error::request(field, format!("must be > 0, got {v}"))),
        other => Ok(other),
    }
}

/// The longest wall-time budget a request may give, seconds (one day): a typo such as `1e300`
/// is refused instead of overflowing a timer.
pub const MAX_TIME_BUDGET_S: f64 = 86_400.0;

/// A wall-time budget in seconds from an optional request field: positive, finite and at most
/// [`MAX_TIME_BUDGET_S`].
///
/// # Errors
/// [`Error::Request`] naming `field`.
pub fn time_budget(field: &str, seconds: Option<f64>) -> Result<Option<std::time::Duration>> {
    match positive(field, seconds)? {
        Some(s) if s > MAX_TIME_BUDGET_S => {
            Err(Error::request(field, format!("at most {MAX_TIME_BUDGET_S} s (one day), got {s} s")))
        }
        other => Ok(other.map(std::time::Duration::from_secs_f64)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn motion_csv_columns_carry_their_units_and_read_back() {
        let robot = crate::model::presets::get("ur5").unwrap();
        let q: Vec<String> = joint_columns(&robot, AngleUnit::Deg, "q", "").collect();
        assert_eq!(q[0], "q1_deg");
        assert_eq!(joint_columns(&robot, AngleUnit::Rad, "qdd", "_s2").last().unwrap(), "qdd6_rad_s2");
        // What `reach move --csv` writes: t, q, q̇, the tool pose; only t and q are read.
        let text = "t_s,q1_deg,q2_deg,qd1_deg_s,qd2_deg_s,x_m\n0,10,20,0,0,0.5\n0.5,11,21,2,2,0.6\n";
        let samples = parse_motion_csv(text).unwrap();
        assert_eq!(
            samples,
            [MotionSample { t_s: 0.0, q_deg: vec![10.0, 20.0] }, MotionSample { t_s: 0.5, q_deg: vec![11.0, 21.0] }]
        );
        assert_eq!(parse_motion_file(text).unwrap(), samples);
        // Radians become degrees, metres stay; columns in any order; a bare `qN` is degrees.
        let rad = parse_motion_csv("q2_m,t_s,q1_rad\n0.25,1,3.141592653589793\n").unwrap();
        assert_eq!(rad, [MotionSample { t_s: 1.0, q_deg: vec![180.0, 0.25] }]);
        assert_eq!(parse_motion_csv("t_s,q1,q2\n0,1,2\n").unwrap()[0].q_deg, [1.0, 2.0]);
        // The path reader takes the joint columns only, in the header's unit.
        let path = parse_path_file(text, AngleUnit::Rad).unwrap();
        assert_eq!(path, [Joints::Deg(vec![10.0, 20.0]), Joints::Deg(vec![11.0, 21.0])]);
        let plain = parse_path_file("1 2\n3 4\n", AngleUnit::Rad).unwrap();
        assert_eq!(plain[1], Joints::Rad(vec![3.0, 4.0]));
        // Bad files, one clear message each.
        let message = |text: &str| parse_motion_csv(text).unwrap_err().to_string();
        assert!(message("0,1,2\n").contains("needs a header naming `t_s`"));
        assert!(message("t_s,x_m\n0,1\n").contains("needs a header"));
        assert!(message("t_s,q1_deg,q2_rad\n0,1,2\n").contains("mix degrees and radians"));
        assert!(message("t_s,q1_deg,q3_deg\n0,1,2\n").contains("q2 is missing"));
        assert!(message("t_s,q1_deg,q2_deg\n0,1\n").contains("column `q2_deg` has no values"));
        assert!(message("t_s,q1_deg\n0,NaN\n").contains("line 2, column 2"));
        assert!(message("t_s,q1_deg\n").contains("no sample"));
    }

    #[test]
    fn numbers_in_messages_are_short() {
        assert_eq!(number_text(std::f64::consts::PI.to_degrees()), "180");
        assert_eq!(number_text(-0.0), "0");
        assert_eq!(number_text(2.5e-7), "0");
        assert_eq!(number_text(-45.125), "-45.125");
        assert_eq!(number_text(1e308), "1e308");
        assert_eq!(number_text(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn rpy_follows_fixed_axis_convention() {
        // R = Rz(yaw)·Ry(pitch)·Rx(roll), built from elementary rotations.
        let (roll, pitch, yaw) = (0.3, -0.4, 1.1);
        let r = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), yaw)
            * UnitQuaternion::from_axis_angle(&nalgebra::Vector3::y_axis(), pitch)
            * UnitQuaternion::from_axis_angle(&nalgebra::Vector3::x_axis(), roll);
        let got = rpy_rad(&r);
        for (g, w) in got.iter().zip([roll, pitch, yaw]) {
            assert!((g - w).abs() < 1e-12, "{got:?}");
        }
    }

    #[test]
    fn quaternion_has_non_negative_w() {
        let r = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), 1.5 * std::f64::consts::PI);
        assert!(quat_wxyz(&r)[0] >= 0.0);
        let r = UnitQuaternion::from_axis_angle(&nalgebra::Vector3::z_axis(), std::f64::consts::FRAC_PI_2);
        let q = quat_wxyz(&r);
        assert!((q[0] - q[3]).abs() < 1e-15 && q[3] > 0.0);
    }

    #[test]
    fn half_turn_matrix_is_read_exactly() {
        let pose = Pose {
            matrix: Some([[-1.0, 0.0, 0.0, 0.4], [0.0, 1.0, 0.0, -0.2], [0.0, 0.0, -1.0, 0.3], [0.0, 0.0, 0.0, 1.0]]),
            ..Pose::default()
        };
        let p = pose.isometry("to").unwrap();
        // diag(−1, 1, −1) is a half turn about y, read exactly (not a small roll).
        assert!((p.rotation.angle() - std::f64::consts::PI).abs() < 1e-12, "{:?}", p.rotation.euler_angles());
        let axis = p.rotation.axis().unwrap();
        assert!((axis.y.abs() - 1.0).abs() < 1e-12, "{axis:?}");
    }

    #[test]
    fn contradicting_or_missing_parts_name_the_field() {
        let both = Pose { rpy_deg: Some([0.0; 3]), rpy_rad: Some([0.0; 3]), ..Pose::xyz_rpy_deg([0.0; 3], [0.0; 3]) };
        assert!(both.target("to").unwrap_err().to_string().starts_with("to: give at most one"));
        let nan = Pose::xyz_rpy_deg([0.0, f64::NAN, 0.0], [0.0; 3]);
        assert_eq!(nan.target("to").unwrap_err().to_string(), "to.xyz_m[2]: expected a finite number, got NaN");
        assert!(Pose::default().target("to").is_err());
        let position = Pose { xyz_m: Some([1.0, 2.0, 3.0]), ..Pose::default() };
        assert!(matches!(position.target("to").unwrap(), IkTarget::Position(_)));
        assert!(position.isometry("to").is_err());
    }

    #[test]
    fn joints_convert_by_their_unit_and_name_the_joint() {
        let robot = presets::get("ur5").unwrap();
        let deg = Joints::Deg(vec![90.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!((deg.si(&robot, "q").unwrap()[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        let rad = Joints::Rad(vec![std::f64::consts::FRAC_PI_2, 0.0, 0.0, 0.0, 0.0, 0.0]);
        assert!((rad.display(&robot)[0] - 90.0).abs() < 1e-12);
        let short = Joints::Deg(vec![0.0; 5]);
        assert_eq!(short.si(&robot, "q").unwrap_err().to_string(), "q: robot `ur5` has 6 joints, got 5 joint values");
        let inf = Joints::Deg(vec![0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(inf.si(&robot, "q").unwrap_err().to_string(), "q: joint 2: expected a finite number, got inf");
    }

    #[test]
    fn robots_load_from_presets_and_text() {
        assert_eq!(RobotInput::Preset("puma560".into()).load().unwrap().robot.dof(), 6);
        let e = RobotInput::Preset("nope".into()).load().unwrap_err();
        assert_eq!(e.code(), "model");
        let text = presets::source("planar3").unwrap().to_string();
        assert_eq!(RobotInput::Toml { text }.load().unwrap().robot.dof(), 3);
    }
}

/// One sample of a sampled motion (`reach move --json`'s `samples`), as a request gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct MotionSample {
    /// Time, seconds.
    pub t_s: f64,
    /// Joint values: revolute joints in degrees, prismatic joints in metres.
    pub q_deg: Vec<f64>,
}

/// A motion file's samples: the JSON `reach move --json` prints (`{"samples": [{"t_s",
/// "q_deg"}, ...]}`), or a `reach path --json` report (`{"waypoints_deg", "segment_durations_s"}`:
/// its waypoints are the samples, at the cumulative times of its segments from 0 s; the
/// timed path runs on the straight joint segments between them). Other fields are ignored.
///
/// # Errors
/// [`Error::File`] for text that is neither, or a path report whose segment durations do not
/// match its waypoints.
pub fn parse_motion_json(text: &str) -> Result<Vec<MotionSample>> {
    #[derive(Deserialize)]
    struct MotionFile {
        samples: Option<Vec<MotionSample>>,
        waypoints_deg: Option<Vec<Vec<f64>>>,
        segment_durations_s: Option<Vec<f64>>,
    }
    let bad = |message: String| Error::File { what: "motion file", message };
    let file = serde_json::from_str::<MotionFile>(text).map_err(|e| bad(one_line(&e.to_string())))?;
    match (file.samples, file.waypoints_deg, file.segment_durations_s) {
        (Some(samples), ..) => Ok(samples),
        (None, Some(waypoints), Some(durations)) => {
            if waypoints.is_empty() || durations.len() + 1 != waypoints.len() {
                return Err(bad(format!(
                    "a path report needs one segment duration fewer than waypoints, got {} waypoints and {} durations (a path that was not found has none)",
                    waypoints.len(),
                    durations.len()
                )));
            }
            let times = std::iter::once(0.0).chain(durations.iter().scan(0.0, |t, d| {
                *t += d;
                Some(*t)
            }));
            Ok(times.zip(waypoints).map(|(t_s, q_deg)| MotionSample { t_s, q_deg }).collect())
        }
        _ => Err(bad("missing field `samples` (or a path report's `waypoints_deg` and `segment_durations_s`)".into())),
    }
}

/// A sampled motion in SI, every sample within the joints' position limits.
///
/// # Errors
/// [`Error::Request`] naming `field` and the sample (0-based) for a wrong joint count, a
/// non-finite value or a joint outside its limits.
pub fn samples_si(robot: &Robot, samples: &[MotionSample], field: &str) -> Result<Vec<JointSample>> {
    samples
        .iter()
        .enumerate()
        .map(|(k, s)| {
            let field = format!("{field}: sample {k}");
            let q = Joints::Deg(s.q_deg.clone()).si(robot, &field)?;
            require_within_limits(robot, &q, AngleUnit::Deg, &field)?;
            Ok(JointSample::of(robot, s.t_s, q))
        })
        .collect()
}

/// The joint waypoints of a path file, in the unit of its revolute values: a CSV (one joint
/// vector per row, separated by commas and/or blanks; blank lines and `#` comments skipped;
/// revolute values in `csv_unit`, prismatic in metres; an optional header row of names —
/// when it names joint columns `q1 … qn` ([`joint_columns`], e.g. the CSV of `reach move`
/// or `reach retime`), only those are read, in the unit their names give)
/// or the JSON of `reach path` (`waypoints_deg`), `reach approach` (`motion_deg`) or
/// `reach move` (`samples[].q_deg`), always in degrees.
///
/// # Errors
/// [`Error::File`] naming the row (1-based line) and the column of a value that is not a
/// finite number, a row of another length than the first, JSON with none of those fields,
/// or a file with no waypoint.
pub fn parse_path_file(text: &str, csv_unit: AngleUnit) -> Result<Vec<Joints>> {
    let file_error = |message: String| Error::File { what: "path file", message };
    if text.trim_start().starts_with('{') {
        #[derive(Deserialize)]
        struct Sample {
            q_deg: Vec<f64>,
        }
        #[derive(Deserialize)]
        struct PathFile {
            waypoints_deg: Option<Vec<Vec<f64>>>,
            motion_deg: Option<Vec<Vec<f64>>>,
            samples: Option<Vec<Sample>>,
        }
        let file: PathFile = serde_json::from_str(text).map_err(|e| file_error(one_line(&e.to_string())))?;
        let rows = file
            .waypoints_deg
            .or(file.motion_deg)
            .or_else(|| file.samples.map(|s| s.into_iter().map(|s| s.q_deg).collect()))
            .ok_or_else(|| {
                file_error(
                    "JSON without `waypoints_deg` (reach path), `motion_deg` (reach approach) or `samples` \
                     (reach move)"
                        .into(),
                )
            })?;
        if rows.is_empty() {
            return Err(file_error("the path has no waypoint (was a path found?)".into()));
        }
        return Ok(rows.into_iter().map(Joints::Deg).collect());
    }
    let (header, rows) = csv_rows(text).map_err(file_error)?;
    if rows.is_empty() {
        return Err(file_error("no waypoint: expected one row of joint values per line".into()));
    }
    let columns = header_columns(header.as_ref(), rows[0].1.len()).map_err(file_error)?;
    let unit = columns.as_ref().and_then(|c| c.unit).unwrap_or(csv_unit);
    Ok(rows
        .into_iter()
        .map(|(_, r)| {
            let q = match &columns {
                Some(c) => c.joints.iter().map(|&k| r[k]).collect(),
                None => r,
            };
            match unit {
                AngleUnit::Deg => Joints::Deg(q),
                AngleUnit::Rad => Joints::Rad(q),
            }
        })
        .collect())
}

/// The samples of a motion CSV — the file `reach move --csv` or `reach retime --csv` writes: a
/// header naming the columns, `t_s` and the joint positions `q1_deg … qn_deg` (`qN_rad` in
/// radians, `qN_m` for a prismatic joint; a bare `qN`, as older files have, is degrees), other
/// columns ignored; then one row per sample.
///
/// # Errors
/// [`Error::File`] for a header without `t_s` or without `q1 … qn`, columns that mix degrees
/// and radians, a value that is not a finite number (its line and column), rows of unequal
/// length, no row.
pub fn parse_motion_csv(text: &str) -> Result<Vec<MotionSample>> {
    let bad = |message: String| Error::File { what: "motion file", message };
    let (header, rows) = csv_rows(text).map_err(bad)?;
    if header.is_some() && rows.is_empty() {
        return Err(bad("no sample: expected one row per sample after the header".into()));
    }
    let width = rows.first().map_or(0, |(_, r)| r.len());
    let columns = header_columns(header.as_ref(), width).map_err(bad)?;
    let (Some(columns), Some(time)) = (columns.as_ref(), columns.as_ref().and_then(|c| c.time)) else {
        return Err(bad(
            "a motion CSV needs a header naming `t_s` and the joint columns `q1_deg` … (as `reach move --csv` writes)"
                .into(),
        ));
    };
    let to_deg = match columns.unit {
        Some(AngleUnit::Rad) => f64::to_degrees,
        _ => |v: f64| v,
    };
    let names = header.as_deref().unwrap_or_default();
    Ok(rows
        .into_iter()
        .map(|(_, r)| MotionSample {
            t_s: r[time],
            // Metres stay metres; angles become degrees.
            q_deg: columns.joints.iter().map(|&k| if names[k].ends_with("_m") { r[k] } else { to_deg(r[k]) }).collect(),
        })
        .collect())
}

/// A motion file's samples, JSON ([`parse_motion_json`]) or CSV ([`parse_motion_csv`]),
/// told apart by the first character (`{`: JSON).
///
/// # Errors
/// As those two.
pub fn parse_motion_file(text: &str) -> Result<Vec<MotionSample>> {
    if text.trim_start().starts_with('{') { parse_motion_json(text) } else { parse_motion_csv(text) }
}

/// The default of a limit's scale (`max_velocity_scale`, `max_acceleration_scale`): 1, the
/// limits as given.
pub(crate) fn full_scale() -> f64 {
    1.0
}
