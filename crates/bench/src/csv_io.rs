//! Rows of the bench's CSV files, written atomically and read back.

use anyhow::{Context, Result};
use serde::{de::DeserializeOwned, Serialize};
use std::path::Path;

/// Writes `rows` as CSV to `path` atomically (a temporary file beside it,
/// renamed).
pub fn write_rows<T: Serialize>(path: &Path, rows: &[T]) -> Result<()> {
    axijoint_mesh::atomic::write(path, |out| {
        let mut w = csv::Writer::from_writer(out);
        for r in rows {
            w.serialize(r)?;
        }
        w.flush()
    })
    .with_context(|| format!("cannot write {}", path.display()))
}

/// Reads rows written by [`write_rows`].
pub fn read_rows<T: DeserializeOwned>(path: &Path) -> Result<Vec<T>> {
    let mut r = csv::Reader::from_path(path).with_context(|| format!("cannot read {}", path.display()))?;
    r.deserialize()
        .enumerate()
        .map(|(i, row)| row.with_context(|| format!("{}: row {}", path.display(), i + 1)))
        .collect()
}
