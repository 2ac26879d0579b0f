//! All-or-nothing output (temporary files renamed into place): the measurement library's
//! [`vpmap_eval::output`], shared so that every command writes its files the same way; and
//! the command line as typed, which the reports quote.

use std::path::Path;

pub use vpmap_eval::output::OutputSet;

/// Write one file atomically (temporary file in the same folder, then rename).
pub fn write_file(path: &Path, bytes: impl Into<Vec<u8>>) -> anyhow::Result<()> {
    Ok(vpmap_eval::output::write_file(path, bytes)?)
}

/// The command line as typed, `vpmap` for the program, arguments quoted for a POSIX shell
/// where needed (for the reports' "measured with").
#[must_use]
pub fn command_line() -> String {
    let args: Vec<String> = std::iter::once("vpmap".to_owned())
        .chain(std::env::args().skip(1))
        .collect();
    shell_words::join(args)
}
