//! Writing a `map_server` map: both files or neither, never over what is not a regular file.

use std::path::{Path, PathBuf};

use super::encode_ros_map;
use crate::error::{PlanError, Result};
use crate::grid::OccupancyGrid;

/// The I/O error of `action` on `path`.
fn io_error(action: &'static str, path: &Path) -> impl FnOnce(std::io::Error) -> PlanError {
    let path = path.to_path_buf();
    move |source| PlanError::Io {
        action,
        path,
        source,
    }
}

/// A hidden file beside `path` for this process: `.<name>.<pid>.<what>`.
fn beside(path: &Path, what: &str) -> Result<PathBuf> {
    let name = path.file_name().ok_or_else(|| PlanError::Io {
        action: "write",
        path: path.to_path_buf(),
        source: std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the path has no file name",
        ),
    })?;
    let mut hidden = std::ffi::OsString::from(".");
    hidden.push(name);
    hidden.push(format!(".{}.{what}", std::process::id()));
    Ok(path.with_file_name(hidden))
}

/// Write `files` (path, bytes) all or nothing: every one to a temporary file beside it, then
/// the old ones moved aside, the new ones renamed into place, the old ones removed. On any
/// failure the temporary files are removed and every old file is put back, so the folder is
/// as it was.
pub(super) fn write_all_or_nothing(files: &[(&Path, &[u8])]) -> Result<()> {
    let mut temps: Vec<PathBuf> = Vec::with_capacity(files.len());
    let cleanup = |temps: &[PathBuf]| {
        for t in temps {
            let _ = std::fs::remove_file(t);
        }
    };
    for (path, bytes) in files {
        let tmp = beside(path, "tmp").inspect_err(|_| cleanup(&temps))?;
        if let Err(e) = std::fs::write(&tmp, bytes) {
            let _ = std::fs::remove_file(&tmp);
            cleanup(&temps);
            return Err(io_error("write", &tmp)(e));
        }
        temps.push(tmp);
    }
    // (path, its old file moved aside, whether the new one is in place)
    let mut moved: Vec<(&Path, Option<PathBuf>, bool)> = Vec::with_capacity(files.len());
    let undo = |moved: &[(&Path, Option<PathBuf>, bool)]| {
        for (path, old, placed) in moved.iter().rev() {
            if *placed {
                let _ = std::fs::remove_file(path);
            }
            if let Some(old) = old {
                let _ = std::fs::rename(old, path);
            }
        }
    };
    for ((path, _), tmp) in files.iter().zip(&temps) {
        let old = if path.exists() {
            let backup = match beside(path, "old") {
                Ok(b) => b,
                Err(e) => {
                    undo(&moved);
                    cleanup(&temps);
                    return Err(e);
                }
            };
            if let Err(e) = std::fs::rename(path, &backup) {
                undo(&moved);
                cleanup(&temps);
                return Err(io_error("move aside", path)(e));
            }
            Some(backup)
        } else {
            None
        };
        moved.push((path, old, false));
        if let Err(e) = std::fs::rename(tmp, path) {
            undo(&moved);
            cleanup(&temps);
            return Err(io_error("rename to", path)(e));
        }
        if let Some(last) = moved.last_mut() {
            last.2 = true;
        }
    }
    for (_, old, _) in &moved {
        if let Some(old) = old {
            let _ = std::fs::remove_file(old);
        }
    }
    Ok(())
}

/// Write a grid as `map_server` files: the YAML at `yaml_path` and the PGM image beside it,
/// named after it with the extension `pgm`. Returns the image's path.
///
/// Both files are written or neither: a failure leaves the folder as it was (the previous map's
/// files kept). An existing path that is not a regular file (a folder, a device, a FIFO) is
/// refused and left untouched.
///
/// # Errors
/// [`PlanError::Io`] naming the file that could not be written, or `yaml_path` when it
/// ends in `.pgm`; [`PlanError::File`] for a path that is not a regular file.
///
/// # Example
/// ```
/// use vpmap_plan::{read_ros_map, write_ros_map, Occupancy, OccupancyGrid};
/// let dir = tempfile::tempdir().unwrap();
/// let grid = OccupancyGrid::new(4, 2, 0.1, [0.0, -0.2], Occupancy::Unknown).unwrap();
/// let image = write_ros_map(&grid, &dir.path().join("room.yaml")).unwrap();
/// assert_eq!(image, dir.path().join("room.pgm"));
/// assert_eq!(read_ros_map(&dir.path().join("room.yaml")).unwrap(), grid);
/// ```
pub fn write_ros_map(grid: &OccupancyGrid, yaml_path: &Path) -> Result<PathBuf> {
    let image_path = yaml_path.with_extension("pgm");
    if image_path == yaml_path {
        return Err(PlanError::Io {
            action: "write",
            path: yaml_path.to_path_buf(),
            source: std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "the map YAML file must not have the image's extension `.pgm`",
            ),
        });
    }
    let image_name = image_path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    // Regular files or new paths only (never a device, FIFO or folder), both or neither.
    vpmap_files::check_output_path(&image_path)?;
    vpmap_files::check_output_path(yaml_path)?;
    let (yaml, pgm) = encode_ros_map(grid, &image_name);
    write_all_or_nothing(&[(&image_path, &pgm), (yaml_path, yaml.as_bytes())])?;
    Ok(image_path)
}
