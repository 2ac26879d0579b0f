//! All-or-nothing output (temporary files renamed into place): the measurement library's
//! [`vpmap_eval::output`], shared so that every command writes its files the same way.

use std::path::Path;

pub use vpmap_eval::output::OutputSet;

/// Write one file atomically (temporary file in the same folder, then rename).
pub fn write_file(path: &Path, bytes: impl Into<Vec<u8>>) -> anyhow::Result<()> {
    Ok(vpmap_eval::output::write_file(path, bytes)?)
}
