//! The TOML robot description format (documented in `docs/robot-format.md`).

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use serde::Deserialize;

use super::{
    BodyShape, Convention, DhParams, Joint, JointDrive, JointGeometry, JointKind, Limits, LinkBody, LinkGeometry,
    LinkInertial, ModelError, Robot, RobotSpec, STANDARD_GRAVITY, StepMode, Wiring,
};

/// Length unit of a description file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
pub enum LengthUnit {
    /// Metres.
    #[serde(rename = "m")]
    Metre,
    /// Millimetres.
    #[serde(rename = "mm")]
    Millimetre,
}

impl LengthUnit {
    /// Metres per unit.
    #[must_use]
    pub fn to_si(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Millimetre => 1e-3,
        }
    }

    /// `m` or `mm`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Millimetre => "mm",
        }
    }
}

/// Angle unit of a description file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, serde::Serialize)]
pub enum AngleUnit {
    /// Degrees.
    #[serde(rename = "deg")]
    Degree,
    /// Radians.
    #[serde(rename = "rad")]
    Radian,
}

impl AngleUnit {
    /// Radians per unit.
    #[must_use]
    pub fn to_si(self) -> f64 {
        match self {
            AngleUnit::Degree => std::f64::consts::PI / 180.0,
            AngleUnit::Radian => 1.0,
        }
    }

    /// `deg` or `rad`.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            AngleUnit::Degree => "deg",
            AngleUnit::Radian => "rad",
        }
    }
}

/// The units a robot was written in, kept so that tools can print it back the same way.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileUnits {
    /// Length unit.
    pub length: LengthUnit,
    /// Angle unit.
    pub angle: AngleUnit,
}

impl Default for FileUnits {
    fn default() -> Self {
        FileUnits { length: LengthUnit::Metre, angle: AngleUnit::Degree }
    }
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum FileConvention {
    Dh,
    Mdh,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RobotFile {
    name: String,
    #[serde(default)]
    description: String,
    #[serde(default = "default_convention")]
    convention: FileConvention,
    length_unit: LengthUnit,
    angle_unit: AngleUnit,
    base: Option<TransformField>,
    tool: Option<TransformField>,
    joints: Vec<JointField>,
    #[serde(default)]
    links: Vec<LinkField>,
    #[serde(default)]
    bodies: Vec<BodyField>,
    #[serde(default)]
    disabled_collisions: Vec<[String; 2]>,
    /// Gravitational acceleration in the world frame, m/s² (not scaled by `length_unit`).
    gravity: Option<[f64; 3]>,
}

fn default_convention() -> FileConvention {
    FileConvention::Dh
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TransformField {
    #[serde(default)]
    xyz: [f64; 3],
    #[serde(default)]
    rpy: [f64; 3],
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct JointField {
    name: Option<String>,
    #[serde(default = "default_kind")]
    kind: JointKind,
    #[serde(default)]
    a: f64,
    #[serde(default)]
    alpha: f64,
    #[serde(default)]
    d: f64,
    #[serde(default)]
    theta: f64,
    limits: Option<[f64; 2]>,
    max_velocity: Option<f64>,
    max_velocity_rpm: Option<f64>,
    max_acceleration: Option<f64>,
    max_jerk: Option<f64>,
    home: Option<f64>,
    #[serde(default)]
    flip: bool,
    drive: Option<DriveField>,
    inertial: Option<InertialField>,
}

/// `[joints.inertial]`: mass properties of the link the joint moves, in that link's frame
/// (see `docs/robot-format.md`); `com` in the file length unit, `inertia` in kg·(length unit)².
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct InertialField {
    mass: f64,
    #[serde(default)]
    com: [f64; 3],
    /// `[ixx, iyy, izz, ixy, ixz, iyz]` about the centre of mass.
    #[serde(default)]
    inertia: [f64; 6],
}

/// `[joints.drive]`: the stepper drive of one joint (see `docs/robot-format.md`).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DriveField {
    steps_per_rev: u32,
    #[serde(default = "default_microstepping")]
    microstepping: u32,
    #[serde(default = "default_gear_ratio")]
    gear_ratio: f64,
    lead: Option<f64>,
    #[serde(default = "default_direction")]
    direction: i32,
    max_step_rate: f64,
    max_acceleration: Option<f64>,
    wiring: Wiring,
    mode: Option<StepMode>,
    #[serde(default)]
    home_steps: i64,
}

fn default_microstepping() -> u32 {
    1
}

fn default_gear_ratio() -> f64 {
    1.0
}

fn default_direction() -> i32 {
    1
}

fn default_kind() -> JointKind {
    JointKind::Revolute
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LinkField {
    radius: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyField {
    name: String,
    frame: usize,
    parent: Option<String>,
    shapes: Vec<BodyShapeField>,
    #[serde(default)]
    padding: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct BodyShapeField {
    shape: String,
    center: Option<[f64; 3]>,
    radius: Option<f64>,
    a: Option<[f64; 3]>,
    b: Option<[f64; 3]>,
    size: Option<[f64; 3]>,
    length: Option<f64>,
    #[serde(default)]
    rpy: [f64; 3],
}

impl BodyShapeField {
    /// The solid in SI units; `ls`, `an`: the file's length and angle scales.
    fn to_shape(&self, body: &str, index: usize, ls: f64, an: f64) -> Result<BodyShape, ModelError> {
        let fail = |m: String| ModelError::Links(format!("body `{body}`, shape {index} ({}): {m}", self.shape));
        let need3 =
            |v: Option<[f64; 3]>, f: &str| v.map(|v| Vector3::from(v) * ls).ok_or_else(|| fail(format!("needs `{f}`")));
        let need = |v: Option<f64>, f: &str| v.map(|v| v * ls).ok_or_else(|| fail(format!("needs `{f}`")));
        let allowed: &[&str] = match self.shape.as_str() {
            "sphere" => &["center", "radius"],
            "capsule" => &["a", "b", "radius"],
            "box" => &["center", "size", "rpy"],
            "cylinder" => &["center", "radius", "length", "rpy"],
            other => {
                return Err(fail(format!(
                    "unknown shape `{other}` (expected sphere, capsule, box or cylinder; meshes come from URDF <collision>)"
                )));
            }
        };
        let given = [
            ("center", self.center.is_some()),
            ("radius", self.radius.is_some()),
            ("a", self.a.is_some()),
            ("b", self.b.is_some()),
            ("size", self.size.is_some()),
            ("length", self.length.is_some()),
            ("rpy", self.rpy != [0.0; 3]),
        ];
        if let Some((f, _)) = given.iter().find(|(f, g)| *g && !allowed.contains(f)) {
            return Err(fail(format!("field `{f}` does not belong to a {}", self.shape)));
        }
        let pose = |c: Vector3<f64>| Isometry3::from_parts(c.into(), xyz_rpy([0.0; 3], self.rpy, 1.0, an).rotation);
        Ok(match self.shape.as_str() {
            "sphere" => {
                BodyShape::Sphere { center: need3(self.center, "center")?, radius: need(self.radius, "radius")? }
            }
            "capsule" => BodyShape::Capsule {
                a: need3(self.a, "a")?,
                b: need3(self.b, "b")?,
                radius: need(self.radius, "radius")?,
            },
            "box" => BodyShape::Box {
                pose: pose(need3(self.center, "center")?),
                half_extents: need3(self.size, "size")? * 0.5,
            },
            _ => BodyShape::Cylinder {
                pose: pose(need3(self.center, "center")?),
                radius: need(self.radius, "radius")?,
                half_length: need(self.length, "length")? * 0.5,
            },
        })
    }
}

/// The `[[bodies]]` of a robot file in SI units: each body's parent is the one named, or else
/// the body on the nearest lower frame (the link before it in the chain).
fn bodies_of(fields: &[BodyField], ls: f64, an: f64) -> Result<Vec<LinkBody>, ModelError> {
    let mut bodies = Vec::with_capacity(fields.len());
    for b in fields {
        let shapes =
            b.shapes.iter().enumerate().map(|(i, s)| s.to_shape(&b.name, i + 1, ls, an)).collect::<Result<_, _>>()?;
        let parent = match &b.parent {
            Some(p) => Some(fields.iter().position(|o| &o.name == p).ok_or_else(|| {
                ModelError::Links(format!("body `{}`: parent `{p}` is not a body of this file", b.name))
            })?),
            None => fields
                .iter()
                .enumerate()
                .filter(|(_, o)| o.frame < b.frame)
                .max_by_key(|(_, o)| o.frame)
                .map(|(i, _)| i),
        };
        bodies.push(LinkBody { name: b.name.clone(), frame: b.frame, parent, shapes, padding: b.padding * ls });
    }
    Ok(bodies)
}

/// Converts an `xyz` (file length unit) + `rpy` (file angle unit, fixed axes X then Y then Z,
/// i.e. `R = Rz(yaw)·Ry(pitch)·Rx(roll)` as in URDF) pair to an isometry in SI units.
pub(crate) fn xyz_rpy(xyz: [f64; 3], rpy: [f64; 3], length: f64, angle: f64) -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(xyz[0] * length, xyz[1] * length, xyz[2] * length),
        UnitQuaternion::from_euler_angles(rpy[0] * angle, rpy[1] * angle, rpy[2] * angle),
    )
}

/// 1-based line and column of a byte offset.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.chars().count(), |nl| before[nl + 1..].chars().count()) + 1;
    (line, column)
}

impl Robot {
    /// Parses a TOML robot description (format in `docs/robot-format.md`).
    ///
    /// # Errors
    /// [`ModelError::Parse`] with line and column for syntax errors, unknown fields, missing
    /// fields and wrong types; the validation errors of [`Robot::new`] for bad values.
    pub fn from_toml_str(text: &str) -> Result<Robot, ModelError> {
        Self::from_toml_str_with_units(text).map(|(robot, _)| robot)
    }

    /// Like [`Robot::from_toml_str`], also returning the units the file was written in.
    ///
    /// # Errors
    /// See [`Robot::from_toml_str`].
    pub fn from_toml_str_with_units(text: &str) -> Result<(Robot, FileUnits), ModelError> {
        let file: RobotFile = toml::from_str(text).map_err(|e| {
            let (line, column) = e.span().map_or((1, 1), |s| line_column(text, s.start));
            ModelError::Parse { line, column, message: e.message().trim().to_string() }
        })?;
        let units = FileUnits { length: file.length_unit, angle: file.angle_unit };
        let (ls, an) = (units.length.to_si(), units.angle.to_si());
        let convention = match file.convention {
            FileConvention::Dh => Convention::Dh,
            FileConvention::Mdh => Convention::Mdh,
        };
        let mut joints = Vec::with_capacity(file.joints.len());
        let mut inertials = Vec::with_capacity(file.joints.len());
        let with_inertial = file.joints.iter().filter(|j| j.inertial.is_some()).count();
        for (i, j) in file.joints.into_iter().enumerate() {
            match j.inertial {
                Some(b) => {
                    inertials.push(LinkInertial::new(b.mass, Vector3::from(b.com) * ls, b.inertia.map(|v| v * ls * ls)))
                }
                None if with_inertial > 0 => {
                    let name = j.name.unwrap_or_else(|| format!("joint{}", i + 1));
                    let message = "no `[joints.inertial]`: give one for every joint or for none (a massless link \
                                   is `mass = 0`)"
                        .into();
                    return Err(ModelError::Joint { joint: i + 1, name, message });
                }
                None => {}
            }
            let drive = j.drive.map(|d| JointDrive {
                steps_per_rev: d.steps_per_rev,
                microstepping: d.microstepping,
                gear_ratio: d.gear_ratio,
                lead: d.lead.map(|l| l * ls),
                direction: d.direction,
                max_step_rate: d.max_step_rate,
                max_acceleration: d.max_acceleration,
                wiring: d.wiring,
                mode: d.mode,
                home_steps: d.home_steps,
            });
            let name = j.name.unwrap_or_else(|| format!("joint{}", i + 1));
            let var_scale = match j.kind {
                JointKind::Revolute => an,
                JointKind::Prismatic => ls,
            };
            let max_velocity = match (j.max_velocity, j.max_velocity_rpm, j.kind) {
                (Some(_), Some(_), _) => {
                    let message = "give `max_velocity` or `max_velocity_rpm`, not both".into();
                    return Err(ModelError::Joint { joint: i + 1, name, message });
                }
                (_, Some(_), JointKind::Prismatic) => {
                    let message = "`max_velocity_rpm` applies to revolute joints only".into();
                    return Err(ModelError::Joint { joint: i + 1, name, message });
                }
                (Some(v), None, _) => Some(v * var_scale),
                (None, Some(rpm), _) => Some(rpm * std::f64::consts::TAU / 60.0),
                (None, None, _) => None,
            };
            let limits = j.limits.map_or(Limits::UNLIMITED, |[lo, hi]| Limits::new(lo * var_scale, hi * var_scale));
            let home = j.home.map_or_else(|| limits.default_home(), |h| h * var_scale);
            joints.push(Joint {
                name,
                home,
                kind: j.kind,
                geometry: JointGeometry::Dh(DhParams {
                    a: j.a * ls,
                    alpha: j.alpha * an,
                    d: j.d * ls,
                    theta_offset: j.theta * an,
                }),
                limits,
                max_velocity,
                max_acceleration: j.max_acceleration.map(|v| v * var_scale),
                max_jerk: j.max_jerk.map(|v| v * var_scale),
                drive,
                flip: j.flip,
            });
        }
        let transform =
            |t: Option<TransformField>| t.map_or_else(Isometry3::identity, |t| xyz_rpy(t.xyz, t.rpy, ls, an));
        let spec = RobotSpec {
            name: file.name,
            description: file.description,
            convention,
            joints,
            base: transform(file.base),
            tool: transform(file.tool),
            links: file.links.into_iter().map(|l| LinkGeometry { radius: l.radius * ls }).collect(),
            inertials,
            gravity: file.gravity.map_or(Vector3::new(0.0, 0.0, -STANDARD_GRAVITY), Vector3::from),
            mimics: Vec::new(),
            bodies: bodies_of(&file.bodies, ls, an)?,
            disabled_collisions: file.disabled_collisions,
        };
        Ok((Robot::new(spec)?, units))
    }
}
