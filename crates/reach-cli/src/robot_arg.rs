//! The `<ROBOT>` argument: a preset name or a path to a `.toml` or `.urdf` description file.
//!
//! Every command that takes a robot flattens [`RobotArgs`] into its arguments and calls
//! [`RobotArgs::load`]. Resolution order:
//!
//! 1. a preset name (`reach robots` lists them) — presets win over files of the same name;
//!    write `./ur5` to force a file;
//! 2. otherwise a file path. The format follows the extension (`.toml`; `.urdf` or `.xml`);
//!    any other extension is sniffed (a document starting with `<` is URDF, else TOML);
//! 3. a name that is neither a preset nor an existing file, and does not look like a path,
//!    is reported as an unknown preset with the list of known names.
//!
//! `--base LINK` / `--tip LINK` choose the chain of a URDF tree and are rejected for TOML
//! robots.

use std::fmt;
use std::path::{Path, PathBuf};

use clap::Args;
use reach::Robot;
use reach::jobs::RobotInput;
use reach::model::{FileUnits, UrdfChain, mesh_file_path, presets};

use crate::error::{CliError, one_line};

/// Arguments that name a robot (flatten into a command with `#[command(flatten)]`).
#[derive(Debug, Clone, Args)]
pub struct RobotArgs {
    /// Preset name (see `reach robots`) or path to a `.toml` or `.urdf` robot file.
    #[arg(value_name = "ROBOT")]
    pub robot: String,

    /// URDF only: the link the chain starts at (default: the tree's root link).
    #[arg(long, value_name = "LINK")]
    pub base: Option<String>,

    /// URDF only: the link the chain ends at (default: the only leaf below the base).
    #[arg(long, value_name = "LINK")]
    pub tip: Option<String>,

    /// URDF only: a MoveIt SRDF whose `disable_collisions` link pairs are never checked
    /// against each other (TOML robots list them as `disabled_collisions`).
    #[arg(long, value_name = "FILE")]
    pub srdf: Option<PathBuf>,

    /// URDF only: a MoveIt `joint_limits.yaml` whose velocity, acceleration and jerk limits
    /// override the URDF's (TOML robots give `max_acceleration` and `max_jerk` per joint).
    #[arg(long, value_name = "FILE")]
    pub joint_limits: Option<PathBuf>,
}

/// Which description format a robot file is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FileFormat {
    /// `reach`'s TOML robot format (`docs/robot-format.md`).
    Toml,
    /// URDF (XML).
    Urdf,
}

/// Where a robot came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RobotSource {
    /// A preset embedded in the binary.
    Preset(String),
    /// A description file.
    File {
        /// The path as given.
        path: PathBuf,
        /// Its format.
        format: FileFormat,
    },
}

impl fmt::Display for RobotSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            RobotSource::Preset(name) => write!(f, "preset `{name}`"),
            RobotSource::File { path, format } => {
                let kind = match format {
                    FileFormat::Toml => "TOML",
                    FileFormat::Urdf => "URDF",
                };
                write!(f, "{kind} file `{}`", path.display())
            }
        }
    }
}

/// A robot together with where it came from and the units its file was written in.
#[derive(Debug, Clone)]
pub struct LoadedRobot {
    /// The validated model (SI units, radians).
    pub robot: Robot,
    /// Preset or file.
    pub source: RobotSource,
    /// Units of the TOML description (`None` for URDF, which is always metres and radians).
    pub units: Option<FileUnits>,
    /// What the robot was read from (a file's text as read, once).
    pub input: RobotInput,
}

impl RobotArgs {
    /// Resolves the argument to a robot (see the module docs for the rules).
    ///
    /// # Errors
    /// [`CliError::BadInput`] for an unknown preset, an unreadable or malformed file, or
    /// `--base`/`--tip` given for a TOML robot.
    pub fn load(&self) -> Result<LoadedRobot, CliError> {
        let read = |path: &Option<PathBuf>, what: &str| -> Result<Option<String>, CliError> {
            path.as_ref()
                .map(|p| {
                    std::fs::read_to_string(p).map_err(|e| {
                        CliError::bad_input(format!(
                            "cannot read {what} `{}`: {}",
                            p.display(),
                            one_line(&e.to_string())
                        ))
                    })
                })
                .transpose()
        };
        let extras = UrdfExtras {
            srdf: read(&self.srdf, "SRDF file")?,
            joint_limits: read(&self.joint_limits, "joint limits file")?,
        };
        let loaded = load_robot_with(&self.robot, &self.urdf_chain(), extras)?;
        let urdf_only = [
            ("--base", self.base.is_some()),
            ("--tip", self.tip.is_some()),
            ("--srdf", self.srdf.is_some()),
            ("--joint-limits", self.joint_limits.is_some()),
        ];
        if let (Some(_), Some((flag, _))) = (&loaded.units, urdf_only.iter().find(|(_, given)| *given)) {
            return Err(CliError::bad_input(format!(
                "{flag} applies to URDF robots only, but `{}` is a {}",
                self.robot,
                match loaded.source {
                    RobotSource::Preset(_) => "preset",
                    RobotSource::File { .. } => "TOML file",
                }
            )));
        }
        Ok(loaded)
    }

    /// The URDF chain selection given by `--base` and `--tip`.
    #[must_use]
    pub fn urdf_chain(&self) -> UrdfChain {
        UrdfChain { base: self.base.clone(), tip: self.tip.clone() }
    }
}

/// Resolves a preset name or file path to the library's [`RobotInput`] (a file is read here
/// and parsed by the library); `chain` selects the chain of a URDF file.
///
/// # Errors
/// [`CliError::BadInput`] for a file that cannot be read.
pub fn robot_input(arg: &str, chain: &UrdfChain) -> Result<(RobotInput, RobotSource), CliError> {
    let path = Path::new(arg);
    if presets::source(arg).is_some() || (!path.exists() && !looks_like_path(arg)) {
        // An unknown name is reported by the library with the list of presets.
        return Ok((RobotInput::Preset(arg.to_string()), RobotSource::Preset(arg.to_string())));
    }
    let text = std::fs::read_to_string(path)
        .map_err(|e| CliError::bad_input(format!("cannot read robot file `{arg}`: {}", one_line(&e.to_string()))))?;
    let format = file_format(path, &text);
    let input = match format {
        FileFormat::Toml => RobotInput::Toml { text },
        FileFormat::Urdf => RobotInput::urdf(text, chain, |filename| read_mesh(path, filename))
            .map_err(|e| CliError::bad_input(format!("{arg}: {e}")))?,
    };
    Ok((input, RobotSource::File { path: path.to_path_buf(), format }))
}

/// The bytes of the mesh file `filename` of the URDF file `urdf` ([`mesh_file_path`]):
/// `None` when there is no such file, an error naming the file when it cannot be read.
pub fn read_mesh(urdf: &Path, filename: &str) -> Option<Result<Vec<u8>, String>> {
    let canonical = std::fs::canonicalize(urdf).unwrap_or_else(|_| urdf.to_path_buf());
    let file = mesh_file_path(&canonical, filename, &|d: &Path| d.is_dir()).ok()?;
    file.exists().then(|| std::fs::read(&file).map_err(|e| format!("{}: {}", file.display(), one_line(&e.to_string()))))
}

/// Resolves a preset name or file path to a robot; `chain` selects the chain of a URDF file.
///
/// # Errors
/// [`CliError::BadInput`] for an unknown preset or an unreadable or malformed file.
pub fn load_robot(arg: &str, chain: &UrdfChain) -> Result<LoadedRobot, CliError> {
    load_robot_with(arg, chain, UrdfExtras::default())
}

/// The MoveIt files that complete a URDF robot: their texts.
#[derive(Debug, Clone, Default)]
pub struct UrdfExtras {
    /// An SRDF (`disable_collisions`).
    pub srdf: Option<String>,
    /// A `joint_limits.yaml` (velocity, acceleration, jerk limits).
    pub joint_limits: Option<String>,
}

/// [`load_robot`] with the MoveIt files of a URDF robot (ignored for other robots).
///
/// # Errors
/// As [`load_robot`].
pub fn load_robot_with(arg: &str, chain: &UrdfChain, extras: UrdfExtras) -> Result<LoadedRobot, CliError> {
    let (mut input, source) = robot_input(arg, chain)?;
    if let RobotInput::Urdf { srdf, joint_limits, .. } = &mut input {
        *srdf = extras.srdf;
        *joint_limits = extras.joint_limits;
    }
    let loaded = input.load().map_err(|e| match (&source, &e) {
        (RobotSource::Preset(_), reach::Error::Model(reach::ModelError::UnknownPreset { name, known })) => {
            CliError::bad_input(format!("unknown robot `{name}`: not a preset (known: {known}) and not a robot file"))
        }
        (RobotSource::Preset(name), _) => {
            CliError::internal(format!("preset `{name}` does not parse: {}", one_line(&e.to_string())))
        }
        (RobotSource::File { .. }, _) => CliError::bad_input(format!("{arg}: {}", one_line(&e.to_string()))),
    })?;
    Ok(LoadedRobot { robot: loaded.robot, source, units: loaded.units, input })
}

/// Loads a preset by name (with its file units).
///
/// # Errors
/// [`CliError::BadInput`] naming the unknown preset and listing the known ones.
pub fn load_preset(name: &str) -> Result<LoadedRobot, CliError> {
    load_robot(name, &UrdfChain::default())
}

/// Whether a robot argument is meant as a path rather than a preset name.
fn looks_like_path(arg: &str) -> bool {
    arg.contains('/') || arg.contains(std::path::MAIN_SEPARATOR) || Path::new(arg).extension().is_some()
}

/// The format of a robot file: by extension, else by its first non-blank character.
#[must_use]
pub fn file_format(path: &Path, text: &str) -> FileFormat {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("toml") => FileFormat::Toml,
        Some("urdf" | "xml") => FileFormat::Urdf,
        _ if text.trim_start().starts_with('<') => FileFormat::Urdf,
        _ => FileFormat::Toml,
    }
}
