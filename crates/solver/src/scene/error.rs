//! Errors of scene files: each names the file and the key path at fault.

use std::path::PathBuf;

/// Everything that can be wrong with a scene file, alone or against a mesh.
///
/// `key` is the path of the offending value in the JSON document, written as
/// in `loads[1].force` or `materials.pile.nu` (`.` for the whole document).
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A file could not be read (the scene, or the `.geo` it names).
    #[error("{path}: cannot read: {error}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error (in the message, not a source: said once).
        error: std::io::Error,
    },
    /// The JSON is malformed, or a value has the wrong type or shape, or a
    /// key is unknown or missing.
    #[error("{path}: {key}: {message} ({})", location(*.line, *.column, *.overridden))]
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
        /// The value is not in the file: an override set it (`line` and
        /// `column` then locate the file's value that holds it).
        overridden: bool,
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
    #[error(
        "{path}: {key}: the mesh has no physical {what} named '{name}'{} (it has: {known})",
        did_you_mean(.suggestion.as_deref())
    )]
    UnknownName {
        /// The scene file.
        path: PathBuf,
        /// Key path of the name.
        key: String,
        /// What kind of physical group.
        what: NameKind,
        /// The name asked for.
        name: String,
        /// The names of that kind the mesh has, comma separated.
        known: String,
        /// The nearest of them, when one is near ([`nearest`]).
        suggestion: Option<Box<str>>,
    },
}

/// Where a parse error is, in its message.
fn location(line: usize, column: usize, overridden: bool) -> String {
    if overridden {
        format!("a value an override set, within the value at line {line}, column {column}")
    } else {
        format!("line {line}, column {column}")
    }
}

impl SceneError {
    /// The same error with a key of `loads` read as one of stage `k`'s
    /// `field` (`loads[i]...` -> `stages[k].loads[i]...` or
    /// `stages[k].cyclic.loads[i]...`).
    pub fn in_stage(mut self, k: usize, field: &str) -> SceneError {
        if let SceneError::Parse { key, .. }
        | SceneError::Invalid { key, .. }
        | SceneError::UnknownName { key, .. } = &mut self
        {
            if let Some(rest) = key.strip_prefix("loads") {
                *key = format!("stages[{k}].{field}{rest}");
            }
        }
        self
    }

    /// The same error read from `text` changed by overrides, with the line
    /// and column of a parse error in `original` (the file's own text):
    /// where its key's value is there, else (the value an override added)
    /// where the nearest value holding it is. Other errors name no line.
    pub fn located_in(mut self, original: &str) -> SceneError {
        if let SceneError::Parse {
            key,
            line,
            column,
            overridden,
            ..
        } = &mut self
        {
            if let Some(((l, c), exact)) = super::locate::locate(original, key) {
                (*line, *column, *overridden) = (l, c, !exact);
            }
        }
        self
    }

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

/// `"; did you mean 'x'?"` for a suggestion, else nothing.
pub fn did_you_mean(suggestion: Option<&str>) -> String {
    suggestion.map_or_else(String::new, |s| format!("; did you mean '{s}'?"))
}

/// The name of `known` nearest to `name` when it is near: at most a quarter
/// of the longer name's characters edited (at least one; transpositions
/// count once), ties to the first.
pub fn nearest<'a>(name: &str, known: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    known
        .into_iter()
        .map(|k| (strsim::damerau_levenshtein(name, k), k))
        .filter(|&(d, k)| d > 0 && d <= (name.chars().count().max(k.chars().count()) / 4).max(1))
        .min_by_key(|&(d, _)| d)
        .map(|(_, k)| k)
}

/// The kind of physical group a name was looked up among.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NameKind {
    /// A physical surface (a body).
    Surface,
    /// A physical curve.
    Curve,
    /// A physical point.
    Point,
    /// A curve, else a point (a support).
    CurveOrPoint,
}

impl std::fmt::Display for NameKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            NameKind::Surface => "surface",
            NameKind::Curve => "curve",
            NameKind::Point => "point",
            NameKind::CurveOrPoint => "curve or point",
        })
    }
}
