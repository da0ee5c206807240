//! Errors of the mesh crate: each names the file, line or entity at fault.

use std::path::PathBuf;

/// Everything that can go wrong between a `.geo`/`.msh` file and a mesh.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// The file could not be read.
    #[error("{path}: cannot read: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The `.msh` text or binary is malformed.
    #[error("{path}:{line}: {message}")]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line (for binary sections: the line of the section header).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// gmsh is not installed.
    #[error("gmsh not found on PATH (needed to mesh {path}); install it with: sudo apt-get install -y gmsh")]
    GmshMissing {
        /// The `.geo` file.
        path: PathBuf,
    },
    /// gmsh ran and failed (non-zero exit or `Error` lines, e.g. a `.geo`
    /// it rejects), or could not be started.
    #[error("{path}: gmsh failed ({status}):\n{output}")]
    GmshFailed {
        /// The `.geo` file.
        path: PathBuf,
        /// Exit status.
        status: String,
        /// gmsh's own error text.
        output: String,
    },
    /// The mesh is well-formed but not usable.
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong and where (entity, element tag, physical name).
        message: String,
    },
    /// A physical name asked for does not exist.
    #[error("{path}: no physical {what} named '{name}' (the file has: {known})")]
    UnknownName {
        /// The file.
        path: PathBuf,
        /// "curve", "surface" or "point".
        what: &'static str,
        /// The missing name.
        name: String,
        /// Names that do exist, comma separated.
        known: String,
    },
}
