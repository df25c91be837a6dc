//! Poses and joint vectors typed on the command line, the same way in every command.
//!
//! * A joint vector is one argument, `Q1,..,QN` (commas and/or blanks, negative values
//!   welcome): degrees for revolute joints, radians with `--rad`, metres for prismatic joints.
//! * A pose is `--xyz X,Y,Z` (metres) with at most one of `--rpy R,P,Y` (degrees, radians
//!   with `--rad`; `R = Rz(yaw)·Ry(pitch)·Rx(roll)`) and `--quat W,X,Y,Z`, or `--matrix` (16
//!   numbers, row-major). A command taking two poses prefixes them: `--from-xyz`, `--to-rpy`, …

use clap::Args;
use reach::jobs::{Joints, Pose};

use crate::error::CliError;
use crate::numbers::{parse_exact, parse_joint_list};

/// Joint values typed for `option` (`--from`), in radians when `rad`.
///
/// # Errors
/// [`CliError::BadInput`] naming `option` and the joint (`--from joint 2: expected a number`).
pub fn joints_arg(option: &str, text: &str, rad: bool) -> Result<Joints, CliError> {
    let values = parse_joint_list(option, text)?;
    Ok(if rad { Joints::Rad(values) } else { Joints::Deg(values) })
}

/// The flags of one pose as typed, named with `prefix` (`""` → `--xyz`, `"to-"` → `--to-xyz`).
#[derive(Debug, Clone, Copy)]
pub struct PoseFlags<'a> {
    /// Flag prefix: `""`, `"from-"` or `"to-"`.
    pub prefix: &'static str,
    /// `--xyz`.
    pub xyz: Option<&'a str>,
    /// `--rpy`.
    pub rpy: Option<&'a str>,
    /// `--quat`.
    pub quat: Option<&'a str>,
    /// `--matrix`.
    pub matrix: Option<&'a str>,
}

impl PoseFlags<'_> {
    /// Whether any of the pose's flags was given.
    #[must_use]
    pub fn given(&self) -> bool {
        self.xyz.is_some() || self.rpy.is_some() || self.quat.is_some() || self.matrix.is_some()
    }

    fn flag(&self, name: &str) -> String {
        format!("--{}{name}", self.prefix)
    }

    /// The pose (`rad`: `--rpy` in radians). Which combinations are allowed is the library's
    /// rule ([`Pose::target`]); here only the numbers are read.
    ///
    /// # Errors
    /// [`CliError::BadInput`] naming the flag for a wrong count or a bad number, or when
    /// neither `--xyz` nor `--matrix` is given.
    pub fn pose(&self, rad: bool) -> Result<Pose, CliError> {
        let mut pose = Pose::default();
        if let Some(text) = self.matrix {
            let m = parse_exact(&self.flag("matrix"), text, 16, "a 4x4 matrix, row-major")?;
            pose.matrix = Some(std::array::from_fn(|r| std::array::from_fn(|c| m[4 * r + c])));
        }
        if let Some(text) = self.xyz {
            let p = parse_exact(&self.flag("xyz"), text, 3, "x,y,z in metres")?;
            pose.xyz_m = Some([p[0], p[1], p[2]]);
        } else if pose.matrix.is_none() {
            return Err(CliError::bad_input(format!(
                "give the pose with {} (and {} or {}) or {}",
                self.flag("xyz"),
                self.flag("rpy"),
                self.flag("quat"),
                self.flag("matrix")
            )));
        }
        if let Some(text) = self.rpy {
            let unit = if rad { "radians" } else { "degrees" };
            let a = parse_exact(&self.flag("rpy"), text, 3, &format!("roll,pitch,yaw in {unit}"))?;
            let a = [a[0], a[1], a[2]];
            if rad {
                pose.rpy_rad = Some(a);
            } else {
                pose.rpy_deg = Some(a);
            }
        }
        if let Some(text) = self.quat {
            let q = parse_exact(&self.flag("quat"), text, 4, "w,x,y,z")?;
            pose.quat_wxyz = Some([q[0], q[1], q[2], q[3]]);
        }
        Ok(pose)
    }

    /// How the library's pose fields under `field` (`to.pose`, `target`) map to these flags,
    /// for [`crate::error::flagged`].
    #[must_use]
    pub fn field_flags(&self, field: &str) -> Vec<(String, String)> {
        [("xyz_m", "xyz"), ("rpy_deg", "rpy"), ("rpy_rad", "rpy"), ("quat_wxyz", "quat"), ("matrix", "matrix")]
            .iter()
            .map(|(f, flag)| (format!("{field}.{f}"), self.flag(flag)))
            .collect()
    }
}

/// A flag table for [`crate::error::flagged`]: `fixed` field → flag pairs, and for each pose
/// its library field (`to.pose`) mapped to its flags (`--to-xyz`, …).
#[must_use]
pub fn flag_table(fixed: &[(&str, &str)], poses: &[(PoseFlags<'_>, &str)]) -> Vec<(String, String)> {
    let mut table: Vec<(String, String)> = fixed.iter().map(|(k, f)| (k.to_string(), f.to_string())).collect();
    for (pose, field) in poses {
        table.extend(pose.field_flags(field));
    }
    table
}

/// The start pose of a motion: `--from-xyz` with `--from-rpy` or `--from-quat`, or
/// `--from-matrix` (instead of the joint values `--from`).
#[derive(Debug, Clone, Default, Args)]
pub struct FromPoseArgs {
    /// Start tool position x,y,z in metres (a pose instead of --from).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, conflicts_with = "from")]
    pub from_xyz: Option<String>,
    /// Start orientation roll,pitch,yaw in degrees (radians with --rad).
    #[arg(long, value_name = "R,P,Y", allow_hyphen_values = true, requires = "from_xyz")]
    pub from_rpy: Option<String>,
    /// Start orientation as a unit quaternion w,x,y,z.
    #[arg(
        long,
        value_name = "W,X,Y,Z",
        allow_hyphen_values = true,
        requires = "from_xyz",
        conflicts_with = "from_rpy"
    )]
    pub from_quat: Option<String>,
    /// Start pose as a 4x4 homogeneous matrix, 16 numbers row-major (metres).
    #[arg(long, value_name = "M11,..,M44", allow_hyphen_values = true, conflicts_with_all = ["from", "from_xyz"])]
    pub from_matrix: Option<String>,
}

impl FromPoseArgs {
    /// The flags as typed.
    #[must_use]
    pub fn flags(&self) -> PoseFlags<'_> {
        PoseFlags {
            prefix: "from-",
            xyz: self.from_xyz.as_deref(),
            rpy: self.from_rpy.as_deref(),
            quat: self.from_quat.as_deref(),
            matrix: self.from_matrix.as_deref(),
        }
    }
}

/// The target pose of a motion: `--to-xyz` with `--to-rpy` or `--to-quat`, or `--to-matrix`
/// (instead of the joint values `--to`).
#[derive(Debug, Clone, Default, Args)]
pub struct ToPoseArgs {
    /// Target tool position x,y,z in metres (a pose instead of --to).
    #[arg(long, value_name = "X,Y,Z", allow_hyphen_values = true, conflicts_with = "to")]
    pub to_xyz: Option<String>,
    /// Target orientation roll,pitch,yaw in degrees (radians with --rad).
    #[arg(long, value_name = "R,P,Y", allow_hyphen_values = true, requires = "to_xyz")]
    pub to_rpy: Option<String>,
    /// Target orientation as a unit quaternion w,x,y,z.
    #[arg(long, value_name = "W,X,Y,Z", allow_hyphen_values = true, requires = "to_xyz", conflicts_with = "to_rpy")]
    pub to_quat: Option<String>,
    /// Target pose as a 4x4 homogeneous matrix, 16 numbers row-major (metres).
    #[arg(long, value_name = "M11,..,M44", allow_hyphen_values = true, conflicts_with_all = ["to", "to_xyz"])]
    pub to_matrix: Option<String>,
}

impl ToPoseArgs {
    /// The flags as typed.
    #[must_use]
    pub fn flags(&self) -> PoseFlags<'_> {
        PoseFlags {
            prefix: "to-",
            xyz: self.to_xyz.as_deref(),
            rpy: self.to_rpy.as_deref(),
            quat: self.to_quat.as_deref(),
            matrix: self.to_matrix.as_deref(),
        }
    }
}
