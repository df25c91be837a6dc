//! Preset robots, shipped as description files under `robots/` and embedded at compile time.
//!
//! | name | DOF | source |
//! |---|---|---|
//! | `planar3` | 3 | seed 000: planar redundant arm, three 1 m links |
//! | `planar4` | 4 | seed 000's future work: planar redundant arm, four 1 m links |
//! | `log-loader` | 3 | seed 000 appendix: base yaw + two 1 m links in a vertical plane |
//! | `spbu6` | 6 | seed 001: two-link arm (l1 = 5, l2 = 3) with a spherical wrist |
//! | `puma560` | 6 | seed 002 structure, classic PUMA 560 numbers |
//! | `welder6r` | 6 | seed 003 Table 1, the paper's sign convention (α3 = 180°) |
//! | `varan4` | 4 | seed 004: base yaw + 900/700/500 mm planar arm |
//! | `ur5` | 6 | Universal Robots UR5, standard DH |
//! | `panda` | 7 | Franka Emika Panda, modified DH, with hand |

use super::{ModelError, Robot};

/// `(name, TOML source)` of every preset, in display order.
pub const PRESETS: &[(&str, &str)] = &[
    ("planar3", include_str!("../../robots/planar3.toml")),
    ("planar4", include_str!("../../robots/planar4.toml")),
    ("log-loader", include_str!("../../robots/log-loader.toml")),
    ("spbu6", include_str!("../../robots/spbu6.toml")),
    ("puma560", include_str!("../../robots/puma560.toml")),
    ("welder6r", include_str!("../../robots/welder6r.toml")),
    ("varan4", include_str!("../../robots/varan4.toml")),
    ("ur5", include_str!("../../robots/ur5.toml")),
    ("panda", include_str!("../../robots/panda.toml")),
];

/// Names of all presets.
#[must_use]
pub fn names() -> Vec<&'static str> {
    PRESETS.iter().map(|(n, _)| *n).collect()
}

/// The TOML source of a preset.
#[must_use]
pub fn source(name: &str) -> Option<&'static str> {
    PRESETS.iter().find(|(n, _)| *n == name).map(|(_, s)| *s)
}

/// Builds a preset robot by name.
///
/// # Errors
/// [`ModelError::UnknownPreset`] listing the known names.
///
/// # Example
/// ```
/// let puma = reach::model::presets::get("puma560").unwrap();
/// assert_eq!(puma.dof(), 6);
/// ```
pub fn get(name: &str) -> Result<Robot, ModelError> {
    let text =
        source(name).ok_or_else(|| ModelError::UnknownPreset { name: name.to_string(), known: names().join(", ") })?;
    Robot::from_toml_str(text)
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_preset_parses_and_has_its_name() {
        for (name, _) in super::PRESETS {
            let robot = super::get(name).unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(robot.name(), *name);
            assert!(!robot.description().is_empty(), "{name} needs a description");
        }
    }

    #[test]
    fn unknown_preset_lists_known_names() {
        let err = super::get("nope").unwrap_err().to_string();
        assert!(err.contains("nope") && err.contains("puma560"), "{err}");
    }
}
