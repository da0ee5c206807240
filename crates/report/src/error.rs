//! Errors of the report crate, and the check that refuses non-finite
//! values.

use std::path::{Path, PathBuf};

/// A report output that could not be made.
#[derive(Debug, thiserror::Error)]
pub enum ReportError {
    /// Writing a file failed.
    #[error("{path}: {message}")]
    Write {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// A value to write is not finite (never written as NaN).
    #[error("{path}: {what} is not finite; the file was not written")]
    NotFinite {
        /// The file.
        path: PathBuf,
        /// Which value.
        what: String,
    },
    /// The solution does not contain what the report needs.
    #[error("{0}")]
    Input(String),
}

impl ReportError {
    pub(crate) fn write(path: &Path, e: impl std::fmt::Display) -> Self {
        ReportError::Write {
            path: path.to_path_buf(),
            message: e.to_string(),
        }
    }
}

/// Fails with [`ReportError::NotFinite`] unless every value is finite.
pub(crate) fn check_finite(
    path: &Path,
    values: &[f64],
    what: impl FnOnce() -> String,
) -> Result<(), ReportError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(ReportError::NotFinite {
            path: path.to_path_buf(),
            what: what(),
        })
    }
}
