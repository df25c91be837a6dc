//! Errors: [`ServeError`] for starting the service and its state, [`ApiError`] for one HTTP
//! request (a status and `{"error": "..."}`).

use std::path::Path;

use axum::Json;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};

/// Why the service cannot start or its state cannot be written.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The robot or a request of the library is wrong.
    #[error(transparent)]
    Reach(#[from] reach::Error),
    /// The state directory holds another robot.
    #[error(
        "the state directory `{dir}` belongs to {stored}, but this start gives {given}; start with the same robot or use another --state directory"
    )]
    RobotMismatch {
        /// The state directory.
        dir: String,
        /// The robot stored there, in words.
        stored: String,
        /// The robot given now, in words.
        given: String,
    },
    /// The database was written by a newer version.
    #[error("`{path}` has schema version {found}; this build reads version {expected}")]
    Schema {
        /// The database file.
        path: String,
        /// Its `user_version`.
        found: i64,
        /// The version this build writes.
        expected: i64,
    },
    /// The database failed.
    #[error("state database: {0}")]
    Db(#[from] rusqlite::Error),
    /// A file or socket failed.
    #[error("{0}")]
    Io(String),
    /// A bad option.
    #[error("{0}")]
    Config(String),
}

impl ServeError {
    /// An I/O error on `path`.
    #[must_use]
    pub fn io(path: &Path, e: &std::io::Error) -> Self {
        ServeError::Io(format!("{}: {e}", path.display()))
    }
}

/// An HTTP error: status and message, sent as `{"error": message}`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ApiError {
    /// 400, 401, 404, 409, 413 or 500.
    pub status: StatusCode,
    /// One line.
    pub message: String,
}

impl ApiError {
    /// 400 with `message`.
    #[must_use]
    pub fn bad_request(message: impl Into<String>) -> Self {
        ApiError { status: StatusCode::BAD_REQUEST, message: reach::one_line(&message.into()) }
    }

    /// 404 with `message`.
    #[must_use]
    pub fn not_found(message: impl Into<String>) -> Self {
        ApiError { status: StatusCode::NOT_FOUND, message: message.into() }
    }

    /// 409 with `message`.
    #[must_use]
    pub fn conflict(message: impl Into<String>) -> Self {
        ApiError { status: StatusCode::CONFLICT, message: message.into() }
    }

    /// 500 with `message` on one line (the service's own failure, not the request's).
    #[must_use]
    pub fn internal(message: impl Into<String>) -> Self {
        ApiError { status: StatusCode::INTERNAL_SERVER_ERROR, message: reach::one_line(&message.into()) }
    }

    /// 401: the token is missing or wrong.
    #[must_use]
    pub fn unauthorized() -> Self {
        ApiError {
            status: StatusCode::UNAUTHORIZED,
            message: "this service listens beyond loopback: send `Authorization: Bearer TOKEN` with the token \
                      from the state directory's `token` file"
                .into(),
        }
    }
}

impl From<ServeError> for ApiError {
    fn from(e: ServeError) -> Self {
        ApiError::internal(e.to_string())
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.status, Json(serde_json::json!({ "error": self.message }))).into_response()
    }
}
