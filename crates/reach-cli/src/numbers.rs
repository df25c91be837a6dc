//! Numbers given on the command line: parsing, finiteness, joint units.
//!
//! Joint values are typed in **degrees** for revolute joints by default (radians with
//! `--rad`) and always in **metres** for prismatic joints; inside the program they are SI
//! (radians, metres). Every value must be a finite number: `nan`, `inf` and overflowing
//! literals such as `1e400` are rejected with a message naming the joint.

use clap::Args;
use reach::Robot;
pub use reach::jobs::input::{AngleUnit, from_si, joints_outside_limits, q_display};
use reach::model::JointKind;

use crate::error::CliError;

/// Joint-value arguments (flatten into a command): `Q…` and `--rad`.
///
/// Values may be negative without `--`: `reach fk ur5 -90 -45.5 0 0 0 0`. Like every joint
/// vector of the command line they take commas and/or blanks, so one argument may hold
/// several values: `reach fk ur5 10,-80,100,-110,10,0` and `reach fk ur5 "10 -80 100 -110 10 0"`
/// mean the same as six separate arguments.
#[derive(Debug, Clone, Args)]
pub struct JointArgs {
    /// Joint values, base to tip: degrees for revolute joints (radians with --rad), metres
    /// for prismatic joints; separate arguments or one list with commas/blanks
    /// (`0,-90,90,0,0,0`). Negative values need no `--`.
    #[arg(value_name = "Q")]
    pub q: Vec<String>,

    /// Revolute joint values are in radians instead of degrees.
    #[arg(long)]
    pub rad: bool,
}

impl JointArgs {
    /// The values as typed, in the unit of `--rad`, each checked to be a finite number (the
    /// count is checked against the robot by the library). Each argument is split at commas
    /// and blanks ([`split_joint_args`]).
    ///
    /// # Errors
    /// [`CliError::BadInput`] naming the 1-based joint: `joint 3: expected a number, got "abc"`.
    pub fn joints(&self) -> Result<reach::jobs::Joints, CliError> {
        let values = split_joint_args(&self.q)?;
        Ok(if self.rad { reach::jobs::Joints::Rad(values) } else { reach::jobs::Joints::Deg(values) })
    }
}

/// The one rule for joint values given as positional arguments: each argument holds one or
/// more values separated by commas and/or blanks, numbered base to tip across arguments. An
/// argument with no value at all (`""`, `","`) is an error naming the joint it would have
/// been.
///
/// # Errors
/// [`CliError::BadInput`]: `joint 3: expected a number, got "abc"`.
pub fn split_joint_args(args: &[String]) -> Result<Vec<f64>, CliError> {
    let mut values = Vec::new();
    for arg in args {
        let label = |values: &Vec<f64>| format!("joint {}", values.len() + 1);
        let items = list_items(arg);
        if items.is_empty() {
            return Err(CliError::bad_input(format!("{}: expected a number, got {arg:?}", label(&values))));
        }
        for item in items {
            let value = parse_finite(&label(&values), item)?;
            values.push(value);
        }
    }
    Ok(values)
}

/// Parses one number; `label` names it in the error (`joint 3`, `--speed`).
///
/// Surrounding blanks are ignored. Accepts what Rust's `f64` parser accepts (`-1.5`, `2e-3`,
/// `.5`) except non-finite values.
///
/// # Errors
/// [`CliError::BadInput`]: `joint 3: expected a number, got "abc"` or
/// `joint 3: expected a finite number, got "inf"`.
pub fn parse_finite(label: &str, text: &str) -> Result<f64, CliError> {
    let value: f64 =
        text.trim().parse().map_err(|_| CliError::bad_input(format!("{label}: expected a number, got {text:?}")))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(CliError::bad_input(format!("{label}: expected a finite number, got {text:?}")))
    }
}

/// A count typed for `option` (`--max`, `--restarts`, `--max-nodes`): a whole number; the
/// library checks its range and names the field.
///
/// # Errors
/// [`CliError::BadInput`] naming `option` for text that is not a whole number.
pub fn parse_count(option: &str, text: &str) -> Result<usize, CliError> {
    text.trim()
        .parse::<usize>()
        .map_err(|_| CliError::bad_input(format!("{option}: expected a whole number ≥ 1, got {text:?}")))
}

/// Parses a list of finite numbers for `option`: separated by commas and/or blanks
/// (`0,-90,90`, `"0 -90 90"`, `0, -90, 90`), negative values welcome. The one list parser of
/// the command line.
///
/// # Errors
/// [`CliError::BadInput`]: `--from value 2: expected a number, got "x"`, or an empty list.
pub fn parse_list(option: &str, text: &str) -> Result<Vec<f64>, CliError> {
    parse_items(option, text, "value")
}

/// [`parse_list`] for joint values: messages name the joint (`--from joint 2: …`).
///
/// # Errors
/// As [`parse_list`].
pub fn parse_joint_list(option: &str, text: &str) -> Result<Vec<f64>, CliError> {
    parse_items(option, text, "joint")
}

/// The items of a number list: the non-empty pieces between commas and blanks.
fn list_items(text: &str) -> Vec<&str> {
    text.split([',', ' ', '\t', '\n']).filter(|s| !s.trim().is_empty()).collect()
}

fn parse_items(option: &str, text: &str, noun: &str) -> Result<Vec<f64>, CliError> {
    let values: Vec<f64> = list_items(text)
        .into_iter()
        .enumerate()
        .map(|(i, s)| parse_finite(&format!("{option} {noun} {}", i + 1), s))
        .collect::<Result<_, _>>()?;
    if values.is_empty() {
        return Err(CliError::bad_input(format!("{option}: expected numbers, got {text:?}")));
    }
    Ok(values)
}

/// [`parse_list`] with exactly `count` values; `what` says what they are (`x,y,z in metres`).
///
/// # Errors
/// As [`parse_list`], and [`CliError::BadInput`] for another count.
pub fn parse_exact(option: &str, text: &str, count: usize, what: &str) -> Result<Vec<f64>, CliError> {
    let values = parse_list(option, text)?;
    if values.len() != count {
        return Err(CliError::bad_input(format!("{option}: expected {count} numbers ({what}), got {}", values.len())));
    }
    Ok(values)
}

/// The unit name of a joint's display value: `deg` or `m`.
#[must_use]
pub fn display_unit(kind: JointKind) -> &'static str {
    reach::jobs::input::unit_name(kind, AngleUnit::Deg)
}

/// A joint vector in display units (see [`display_unit`]) for people: `0 -90 45 [deg]`
/// when all joints share a unit, else `90 deg, 0.25 m`.
#[must_use]
pub fn q_text(robot: &Robot, shown: &[f64]) -> String {
    let units: Vec<&str> = robot.joints().iter().map(|j| display_unit(j.kind)).collect();
    if units.windows(2).all(|w| w[0] == w[1]) {
        format!("{} [{}]", crate::output::nums(shown), units.first().copied().unwrap_or(""))
    } else {
        shown.iter().zip(units).map(|(v, u)| format!("{} {u}", crate::output::num(*v))).collect::<Vec<_>>().join(", ")
    }
}

/// One line saying whether `q` (SI) respects the joint limits, naming the offenders.
#[must_use]
pub fn limits_text(robot: &Robot, q: &[f64]) -> String {
    let outside = joints_outside_limits(robot, q);
    if outside.is_empty() {
        return "all joints within limits".into();
    }
    let parts: Vec<String> = outside
        .iter()
        .map(|&n| {
            let j = &robot.joints()[n - 1];
            let lo = from_si(j.kind, j.limits.lower, AngleUnit::Deg);
            let hi = from_si(j.kind, j.limits.upper, AngleUnit::Deg);
            format!(
                "joint {n} ({}) outside {} .. {} {}",
                j.name,
                crate::output::num(lo),
                crate::output::num(hi),
                display_unit(j.kind)
            )
        })
        .collect();
    parts.join("; ")
}
