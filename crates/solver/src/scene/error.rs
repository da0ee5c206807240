//! Errors of scene files: each names the file and the key path at fault.

use std::path::PathBuf;

/// Everything that can be wrong with a scene file, alone or against a mesh.
///
/// `key` is the path of the offending value in the JSON document, written as
/// in `loads[1].force` or `materials.pile.nu` (`.` for the whole document).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A file could not be read (the scene, or the `.geo` it names).
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The JSON is malformed, or a value has the wrong type or shape, or a
    /// key is unknown or missing.
    #[error("{path}: {key}: {message} (line {line}, column {column})")]
    Parse {
        /// The scene file.
        path: PathBuf,
        /// Key path of the value being read.
        key: String,
        /// What is wrong (serde's message, without its location).
        message: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
    },
    /// A value is well-formed but not allowed (E <= 0, nu >= 0.5, a face that
    /// is not flat, ...).
    #[error("{path}: {key}: {message}")]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// Key path of the value.
        key: String,
        /// What is wrong and what is allowed.
        message: String,
    },
    /// A physical name that the mesh does not have.
    #[error("{path}: {key}: the mesh has no physical {what} named '{name}' (it has: {known})")]
    UnknownName {
        /// The scene file.
        path: PathBuf,
        /// Key path of the name.
        key: String,
        /// `surface`, `curve`, `point` or `curve or point`.
        what: &'static str,
        /// The name asked for.
        name: String,
        /// The names of that kind the mesh has, comma separated.
        known: String,
    },
}

impl SceneError {
    /// The same error with a key of `loads` read as one of load case `k`
    /// (`loads[i]...` -> `load_cases[k].loads[i]...`).
    pub fn in_case(mut self, k: usize) -> SceneError {
        if let SceneError::Parse { key, .. }
        | SceneError::Invalid { key, .. }
        | SceneError::UnknownName { key, .. } = &mut self
        {
            if key.starts_with("loads") {
                *key = format!("load_cases[{k}].{key}");
            }
        }
        self
    }

    /// The key path the error is about, if any.
    pub fn key(&self) -> Option<&str> {
        match self {
            SceneError::Io { .. } => None,
            SceneError::Parse { key, .. }
            | SceneError::Invalid { key, .. }
            | SceneError::UnknownName { key, .. } => Some(key),
        }
    }
}
