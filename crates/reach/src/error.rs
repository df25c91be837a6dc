//! The crate's one error type: every module's typed error under one enum, plus the errors of
//! the application layer's requests ([`crate::jobs`]).
//!
//! Callers match on variants, never on message text. [`Error::code`] gives a stable string per
//! kind of failure for JSON (`{"error": …, "code": …}`), unchanged when messages are reworded.

use thiserror::Error as ThisError;

use crate::decide::DecideError;
use crate::drive::DriveError;
use crate::effort::EffortError;
use crate::effort::dynamics::DynamicsError;
use crate::ik::IkError;
use crate::kinematics::KinematicsError;
use crate::model::ModelError;
use crate::motion::MotionError;
use crate::motion::tracking::TrackingError;
use crate::world::{PlanError, WorldError};

/// Any failure of the library: bad input named by field, joint or shape.
///
/// "No solution" and "infeasible" are not errors: they are answers, carried in the reports.
#[derive(Debug, Clone, PartialEq, ThisError)]
#[non_exhaustive]
pub enum Error {
    /// A robot description is invalid or could not be parsed.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// Kinematics was given a wrong joint vector.
    #[error(transparent)]
    Kinematics(#[from] KinematicsError),
    /// Inverse kinematics was given a bad target or options.
    #[error(transparent)]
    Ik(#[from] IkError),
    /// A motion could not be built.
    #[error(transparent)]
    Motion(#[from] MotionError),
    /// A path could not be tracked.
    #[error(transparent)]
    Tracking(#[from] TrackingError),
    /// An effort functional was given bad input.
    #[error(transparent)]
    Effort(#[from] EffortError),
    /// Dynamics was given bad input or a robot without masses.
    #[error(transparent)]
    Dynamics(#[from] DynamicsError),
    /// A scene, grid or collision query is invalid.
    #[error(transparent)]
    World(#[from] WorldError),
    /// A planning query is invalid.
    #[error(transparent)]
    Plan(#[from] PlanError),
    /// A criterion, method or task set is invalid.
    #[error(transparent)]
    Decide(#[from] DecideError),
    /// A drive schedule could not be made.
    #[error(transparent)]
    Drive(#[from] DriveError),
    /// A request's field is missing, malformed, out of range or contradicts another field.
    /// `field` names it as the user wrote it (a JSON field, or the CLI flag it came from).
    #[error("{field}: {reason}")]
    Request {
        /// The offending field.
        field: String,
        /// What is wrong, in the units the user typed.
        reason: String,
    },
    /// A task or scene file could not be parsed.
    #[error("{what}: {message}")]
    File {
        /// Which file (`task file`, `scene file`).
        what: &'static str,
        /// The parser's message, with line and column where known.
        message: String,
    },
}

impl Error {
    /// A [`Error::Request`] error naming `field`.
    #[must_use]
    pub fn request(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::Request { field: field.into(), reason: reason.into() }
    }

    /// A stable code for the kind of failure (`"model"`, `"request"`, …), for JSON reports and
    /// programs that react to failures; it does not change when messages are reworded.
    #[must_use]
    pub fn code(&self) -> &'static str {
        match self {
            Error::Model(_) => "model",
            Error::Kinematics(_) => "kinematics",
            Error::Ik(_) => "ik",
            Error::Motion(_) => "motion",
            Error::Tracking(_) => "tracking",
            Error::Effort(_) => "effort",
            Error::Dynamics(_) => "dynamics",
            Error::World(_) => "world",
            Error::Plan(_) => "plan",
            Error::Decide(_) => "decide",
            Error::Drive(_) => "drive",
            Error::Request { .. } => "request",
            Error::File { .. } => "file",
        }
    }
}

/// Collapses a message to a single line: parser messages (TOML, XML, JSON) may contain line
/// breaks, and front ends promise one line per error.
#[must_use]
pub fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The crate's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_stable_and_messages_name_the_field() {
        let e = Error::request("duration_s", "must be > 0, got -1");
        assert_eq!(e.code(), "request");
        assert_eq!(e.to_string(), "duration_s: must be > 0, got -1");
        let m: Error = ModelError::NoJoints.into();
        assert_eq!(m.code(), "model");
        assert!(m.to_string().contains("no joints"));
    }
}
