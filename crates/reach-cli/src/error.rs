//! Errors of the command line and the exit codes they map to.
//!
//! | exit status | meaning |
//! |---|---|
//! | 0 | success (also when the reader of stdout went away: `reach robots \| head -1`) |
//! | 1 | internal error (a bug, or stdout could not be written) |
//! | 2 | bad input: arguments, numbers, robot names, robot files (also clap's usage errors) |
//! | 3 | no solution / infeasible / not clear: the report is printed, then one line on stderr (`crate::output::verdict_exit`) |
//! | 130 | interrupted by Ctrl-C (`error: interrupted`) |
//!
//! Every error is reported as **one line** on stderr, `error: <message>`, and nothing is
//! printed on stdout: commands check and compute everything before they write.

use std::fmt;
use std::io;

/// Exit status: success.
pub const EXIT_OK: i32 = 0;
/// Exit status: internal error (a bug, or output could not be written).
pub const EXIT_INTERNAL: i32 = 1;
/// Exit status: bad input (arguments, numbers, robot names or files). Clap uses it too.
pub const EXIT_BAD_INPUT: i32 = 2;
/// Exit status: the input is valid but has no solution / is infeasible / is not clear.
pub const EXIT_NO_SOLUTION: i32 = 3;
/// Exit status: interrupted by Ctrl-C (128 + SIGINT, the shells' convention).
pub const EXIT_INTERRUPTED: i32 = 130;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// The user's input is wrong (exit status 2). The message names the argument or field.
    BadInput(String),
    /// The input is valid but the task has no solution (exit status 3).
    NoSolution(String),
    /// Something that should not happen (exit status 1).
    Internal(String),
    /// The user pressed Ctrl-C (exit status 130).
    Interrupted,
    /// Writing the output failed (a broken pipe is not reported, see [`CliError::exit_code`]).
    Output(io::Error),
}

impl CliError {
    /// A bad-input error with this message.
    pub fn bad_input(message: impl Into<String>) -> Self {
        CliError::BadInput(message.into())
    }

    /// An internal error with this message.
    pub fn internal(message: impl Into<String>) -> Self {
        CliError::Internal(message.into())
    }

    /// Whether the error is the reader of stdout having gone away (`| head -1`): not an
    /// error for a command-line tool, so nothing is printed and the exit status is 0.
    #[must_use]
    pub fn is_broken_pipe(&self) -> bool {
        matches!(self, CliError::Output(e) if e.kind() == io::ErrorKind::BrokenPipe)
    }

    /// The process exit status for this error.
    #[must_use]
    pub fn exit_code(&self) -> i32 {
        match self {
            CliError::BadInput(_) => EXIT_BAD_INPUT,
            CliError::NoSolution(_) => EXIT_NO_SOLUTION,
            CliError::Internal(_) => EXIT_INTERNAL,
            CliError::Interrupted => EXIT_INTERRUPTED,
            CliError::Output(_) if self.is_broken_pipe() => EXIT_OK,
            CliError::Output(_) => EXIT_INTERNAL,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::BadInput(m) | CliError::NoSolution(m) => f.write_str(m),
            CliError::Internal(m) => write!(f, "internal error: {m}"),
            CliError::Interrupted => f.write_str("interrupted"),
            CliError::Output(e) => write!(f, "cannot write the output: {e}"),
        }
    }
}

impl std::error::Error for CliError {}

impl From<io::Error> for CliError {
    fn from(e: io::Error) -> Self {
        CliError::Output(e)
    }
}

impl From<serde_json::Error> for CliError {
    fn from(e: serde_json::Error) -> Self {
        if e.is_io() {
            CliError::Output(io::Error::from(e))
        } else {
            CliError::Internal(format!("JSON encoding failed: {e}"))
        }
    }
}

pub use reach::one_line;

impl From<reach::Error> for CliError {
    /// The library's errors are about the user's input (a request field, a file, a joint).
    fn from(e: reach::Error) -> Self {
        CliError::BadInput(one_line(&e.to_string()))
    }
}

/// The library's error with its request field named by the command-line flag it came from:
/// `flags` maps field prefixes to flags (the longest matching prefix wins; `duration_s` →
/// `--duration`), an index becomes ` value i` (`target.xyz_m[2]` → `--xyz value 2`) and a
/// sub-field is dropped (`choose.method` → `--choose`). Other errors convert unchanged.
pub fn flagged<K: AsRef<str>, F: AsRef<str>>(e: reach::Error, flags: &[(K, F)]) -> CliError {
    let reach::Error::Request { field, reason } = &e else { return e.into() };
    let hit = flags
        .iter()
        .filter(|(key, _)| {
            field
                .strip_prefix(key.as_ref())
                .is_some_and(|rest| rest.is_empty() || rest.starts_with(['[', ' ', ':', '.']))
        })
        .max_by_key(|(key, _)| key.as_ref().len());
    let Some((key, flag)) = hit else { return e.into() };
    let (key, flag) = (key.as_ref(), flag.as_ref());
    let rest = &field[key.len()..];
    let rest = match rest.strip_prefix('[').and_then(|r| r.split_once(']')) {
        Some((index, tail)) => format!(" value {index}{tail}"),
        None if rest.starts_with('.') => String::new(),
        None => rest.to_string(),
    };
    CliError::bad_input(format!("{flag}{rest}: {reason}"))
}

impl From<reach::KinematicsError> for CliError {
    /// Wrong joint vectors are the user's input; anything else is a bug in the caller.
    fn from(e: reach::KinematicsError) -> Self {
        match e {
            reach::KinematicsError::JointCount { .. } | reach::KinematicsError::NonFinite { .. } => {
                CliError::BadInput(one_line(&e.to_string()))
            }
            _ => CliError::Internal(one_line(&e.to_string())),
        }
    }
}
