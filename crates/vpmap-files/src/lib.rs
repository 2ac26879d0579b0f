//! Bounded reading of the files vpmap is given: every reader of a scene, a map, a grid or a photo
//! goes through [`read_bytes`] or [`read_text`], so no input path can make it read without end.
//! And the one rule for the paths it writes: [`check_output_path`].
//!
//! * Only **regular files** are read: a FIFO, a character or block device (`/dev/zero`,
//!   `/dev/urandom`), a socket or a directory is refused by name before anything is read (a FIFO
//!   would block for ever, a device would fill the memory).
//! * Each format has a **size limit** ([`Format::max_bytes`]); a larger file is refused with its
//!   size and the limit before it is read, and the read itself stops one byte past the limit, in
//!   case the file grows meanwhile (or reports no size, as files under `/proc` do).
//! * Outputs go only to **regular files or new paths** ([`check_output_path`]): a FIFO, a
//!   device (`-o /dev/null`), a socket or a directory is refused by name and left as it is
//!   (outputs are written to a temporary file renamed over the path, which would replace a
//!   device node or a FIFO with a regular file).
//!
//! A small crate of its own because every other crate reads files (the plan crate its grids, the
//! command line scenes, maps and photos) and none of them is the natural home of the others'
//! reading rules.
//!
//! # Example
//! ```
//! use vpmap_files::{Format, read_text};
//! let e = read_text(std::path::Path::new("/dev/zero"), Format::Scene).unwrap_err();
//! assert!(e.to_string().contains("character device"));
//! ```
#![deny(missing_docs)]

use std::io::Read;
use std::path::{Path, PathBuf};

use thiserror::Error;

/// What a file holds; each has its own size limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A scene file (JSON).
    Scene,
    /// A floor map (`map.json`).
    Map,
    /// A Moving AI `.map` grid.
    MovingAiMap,
    /// A Moving AI `.scen` scenario list.
    MovingAiScenarios,
    /// A ROS map YAML file.
    RosYaml,
    /// A ROS map image (PGM or PNG).
    RosImage,
    /// A photo (JPEG or PNG).
    Photo,
}

const MIB: u64 = 1024 * 1024;

impl Format {
    /// The largest file accepted, bytes. Generous for real inputs (the largest Moving AI maps
    /// are a few megabytes, a 50-megapixel JPEG about 30 MB), finite for hostile ones.
    #[must_use]
    pub fn max_bytes(self) -> u64 {
        match self {
            Self::Scene => 16 * MIB,
            Self::Map | Self::MovingAiMap | Self::RosImage => 256 * MIB,
            Self::MovingAiScenarios | Self::Photo => 64 * MIB,
            Self::RosYaml => MIB,
        }
    }

    /// The format's name in messages.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Scene => "scene file",
            Self::Map => "map file",
            Self::MovingAiMap => "Moving AI map",
            Self::MovingAiScenarios => "Moving AI scenario file",
            Self::RosYaml => "ROS map YAML",
            Self::RosImage => "ROS map image",
            Self::Photo => "photo",
        }
    }
}

/// Why a file was not read.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum FileError {
    /// The operating system refused (missing file, no permission, ...).
    #[error("cannot read {what} {}: {error}", path.display())]
    Io {
        /// What the file was to hold.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// The operating system's error, in the message (not also passed on as the cause, so
        /// that a chain of causes does not say it twice).
        error: std::io::Error,
    },
    /// The path is not a regular file.
    #[error("{what} {} is a {kind}, not a regular file; give a file", path.display())]
    NotRegular {
        /// What the file was to hold.
        what: &'static str,
        /// The path.
        path: PathBuf,
        /// "directory", "FIFO", "character device", "block device" or "socket".
        kind: &'static str,
    },
    /// The file is larger than its format's limit.
    #[error("{what} {} is {size} bytes, more than the {limit} bytes vpmap reads for a {what}", path.display())]
    TooLarge {
        /// What the file was to hold.
        what: &'static str,
        /// The file.
        path: PathBuf,
        /// Its size, bytes (at least; the read stops past the limit).
        size: u64,
        /// The limit, bytes.
        limit: u64,
    },
    /// An output path names something other than a regular file.
    #[error("cannot write {}: it is a {kind}, not a regular file; give a file name (outputs replace only regular files)", path.display())]
    NotRegularOutput {
        /// The path.
        path: PathBuf,
        /// "folder", "FIFO", "character device", "block device" or "socket".
        kind: &'static str,
    },
    /// A text file is not UTF-8.
    #[error("{what} {} is not UTF-8 text", path.display())]
    NotText {
        /// What the file was to hold.
        what: &'static str,
        /// The file.
        path: PathBuf,
    },
}

fn kind_of(t: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_fifo() {
            return "FIFO";
        }
        if t.is_char_device() {
            return "character device";
        }
        if t.is_block_device() {
            return "block device";
        }
        if t.is_socket() {
            return "socket";
        }
    }
    if t.is_dir() {
        "directory"
    } else {
        "special file"
    }
}

/// Read a regular file of at most `limit` bytes.
///
/// # Errors
/// [`FileError`]: not a regular file, larger than `limit`, or an I/O error.
pub fn read_bytes_limited(
    path: &Path,
    what: &'static str,
    limit: u64,
) -> Result<Vec<u8>, FileError> {
    let io = |error| FileError::Io {
        what,
        path: path.to_path_buf(),
        error,
    };
    // Follows symbolic links: a link to a regular file is a regular file.
    let meta = std::fs::metadata(path).map_err(io)?;
    if !meta.file_type().is_file() {
        return Err(FileError::NotRegular {
            what,
            path: path.to_path_buf(),
            kind: kind_of(meta.file_type()),
        });
    }
    let too_large = |size| FileError::TooLarge {
        what,
        path: path.to_path_buf(),
        size,
        limit,
    };
    if meta.len() > limit {
        return Err(too_large(meta.len()));
    }
    let file = std::fs::File::open(path).map_err(io)?;
    let mut bytes = Vec::with_capacity(usize::try_from(meta.len()).unwrap_or(0));
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    let read = bytes.len() as u64;
    if read > limit {
        return Err(too_large(read));
    }
    Ok(bytes)
}

/// Check that `path` may be replaced by an output: it names nothing yet (a dangling symbolic
/// link counts as nothing: the rename replaces the link) or a regular file (following
/// symbolic links). Call it before writing the temporary file that is renamed over `path`.
///
/// # Errors
/// [`FileError::NotRegularOutput`] for a directory, FIFO, device or socket.
///
/// # Example
/// ```
/// use vpmap_files::check_output_path;
/// let e = check_output_path(std::path::Path::new("/dev/null")).unwrap_err();
/// assert!(e.to_string().contains("/dev/null: it is a character device"));
/// let dir = tempfile::tempdir().unwrap();
/// assert!(check_output_path(&dir.path().join("new.json")).is_ok());
/// ```
pub fn check_output_path(path: &Path) -> Result<(), FileError> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.file_type().is_file() => Ok(()),
        Ok(meta) => Err(FileError::NotRegularOutput {
            path: path.to_path_buf(),
            // The command line's word for a directory.
            kind: match kind_of(meta.file_type()) {
                "directory" => "folder",
                kind => kind,
            },
        }),
        // Nothing there (or nothing this process may examine: the write itself then fails
        // and says why).
        Err(_) => Ok(()),
    }
}

/// Read a regular file of `format`, within its size limit ([`Format::max_bytes`]).
///
/// # Errors
/// As [`read_bytes_limited`].
pub fn read_bytes(path: &Path, format: Format) -> Result<Vec<u8>, FileError> {
    read_bytes_limited(path, format.name(), format.max_bytes())
}

/// [`read_bytes`] for a text format.
///
/// # Errors
/// As [`read_bytes`], and [`FileError::NotText`] for bytes that are not UTF-8.
pub fn read_text(path: &Path, format: Format) -> Result<String, FileError> {
    let bytes = read_bytes(path, format)?;
    String::from_utf8(bytes).map_err(|_| FileError::NotText {
        what: format.name(),
        path: path.to_path_buf(),
    })
}

/// A number read from an input, as the messages about it print it: plain when it reads well,
/// in exponent form when it is very large or very small (`1e300`, not 301 digits; `1e-300`,
/// not 300 zeros).
///
/// # Example
/// ```
/// assert_eq!(vpmap_files::num(0.05), "0.05");
/// assert_eq!(vpmap_files::num(1e300), "1e300");
/// assert_eq!(vpmap_files::num(-2.5e-9), "-2.5e-9");
/// assert_eq!(vpmap_files::num(f64::NAN), "NaN");
/// ```
#[must_use]
pub fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A decoder's error message made readable: on one line, with the PNG decoder's internal
/// chunk descriptions (`ChunkType { type: IHDR, critical: true, … }`) reduced to the chunk's
/// name (`IHDR`).
///
/// # Example
/// ```
/// let raw = "CRC error: expected 0x0 have 0xe164e157 while decoding ChunkType { type: IHDR, \
///            critical: true, private: false, reserved: false, safecopy: false } chunk.";
/// assert_eq!(
///     vpmap_files::decoder_message(raw),
///     "CRC error: expected 0x0 have 0xe164e157 while decoding IHDR chunk."
/// );
/// ```
#[must_use]
pub fn decoder_message(message: &str) -> String {
    const CHUNK: &str = "ChunkType { type: ";
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    while let Some(at) = rest.find(CHUNK) {
        out.push_str(&rest[..at]);
        let after = &rest[at + CHUNK.len()..];
        let name_end = after.find([',', ' ', '}']).unwrap_or(after.len());
        out.push_str(&after[..name_end]);
        rest = after.find('}').map_or("", |close| &after[close + 1..]);
    }
    out.push_str(rest);
    out.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn devices_and_directories_are_refused_by_name() {
        for (path, kind) in [
            ("/dev/zero", "character device"),
            ("/dev/urandom", "character device"),
            ("/", "directory"),
        ] {
            let e = read_bytes(Path::new(path), Format::Photo)
                .unwrap_err()
                .to_string();
            assert!(e.contains(kind) && e.contains(path), "{e}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let status = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !status.is_ok_and(|s| s.success()) {
            eprintln!("SKIPPED: mkfifo is not available");
            return;
        }
        let e = read_text(&fifo, Format::Scene).unwrap_err().to_string();
        assert!(e.contains("FIFO") && e.contains("scene file"), "{e}");
    }

    #[test]
    fn outputs_refuse_devices_and_directories_and_accept_files_and_new_paths() {
        let dir = tempfile::tempdir().unwrap();
        for (path, kind) in [
            (Path::new("/dev/null"), "character device"),
            (dir.path(), "folder"),
        ] {
            let e = check_output_path(path).unwrap_err().to_string();
            assert!(
                e.contains(kind) && e.contains(&path.display().to_string()),
                "{e}"
            );
        }
        let file = dir.path().join("old.json");
        std::fs::write(&file, "{}").unwrap();
        assert!(check_output_path(&file).is_ok());
        assert!(check_output_path(&dir.path().join("new.json")).is_ok());
        #[cfg(unix)]
        {
            let link = dir.path().join("dangling");
            std::os::unix::fs::symlink(dir.path().join("nowhere"), &link).unwrap();
            assert!(check_output_path(&link).is_ok());
        }
    }

    #[test]
    fn a_file_over_the_limit_is_refused_with_both_sizes() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.json");
        std::fs::write(&path, vec![b' '; 101]).unwrap();
        let e = read_bytes_limited(&path, "scene file", 100)
            .unwrap_err()
            .to_string();
        assert!(e.contains("101 bytes") && e.contains("100 bytes"), "{e}");
        assert_eq!(
            read_bytes_limited(&path, "scene file", 101).unwrap().len(),
            101
        );
    }

    #[test]
    fn text_must_be_utf8_and_missing_files_name_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.json");
        std::fs::write(&path, [0xff, 0xfe, 0x00]).unwrap();
        assert!(
            read_text(&path, Format::Scene)
                .unwrap_err()
                .to_string()
                .contains("not UTF-8")
        );
        let e = read_text(&dir.path().join("missing.json"), Format::Scene)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("cannot read scene file") && e.contains("missing.json"),
            "{e}"
        );
    }
}

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
