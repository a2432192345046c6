//! Typed errors of the core.
use thiserror::Error;

/// An invalid scene value: names the field, the value given and what is allowed.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("invalid scene value for `{field}`: {value} (allowed: {allowed})")]
pub struct SceneError {
    /// Dotted path of the field, e.g. `material.poisson`.
    pub field: String,
    /// The value that was given, as written.
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl SceneError {
    /// Build an error for `field` with `value` and the `allowed` range.
    pub fn new(field: impl Into<String>, value: impl ToString, allowed: impl Into<String>) -> Self {
        Self {
            field: field.into(),
            value: readable(value.to_string()),
            allowed: allowed.into(),
        }
    }
}

/// A number too long to read as written (`1e300` prints 301 digits) in scientific form.
fn readable(value: String) -> String {
    if value.len() > 16 && !value.contains('e') {
        if let Ok(v) = value.parse::<f64>() {
            return format!("{v:e}");
        }
    }
    value
}

/// Errors of the core library.
#[derive(Debug, Error)]
pub enum CoreError {
    /// A scene value is out of range.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// The scene file could not be parsed.
    #[error("scene file {path}: {message}")]
    Parse {
        /// File path.
        path: String,
        /// Parser message (names the unknown or malformed field).
        message: String,
    },
    /// The scene file could not be read.
    #[error("cannot read scene file {path}")]
    Io {
        /// File path.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// A run split across ranks could not be set up or failed on a rank.
    #[error(transparent)]
    Comm(#[from] crate::comm::CommError),
    /// A run was stopped by the stability guard.
    #[error(transparent)]
    Blowup(#[from] crate::method::Blowup),
    /// The requested combination is not available for this method.
    #[error("{method}: {message}")]
    Unsupported {
        /// Method name.
        method: String,
        /// What is not supported.
        message: String,
    },
}
