//! All-or-nothing output: every file is rendered in memory first, then written to temporary
//! files in the target folder and renamed into place, so a failure never leaves half a file
//! (or half a set of files) behind.

use std::path::{Path, PathBuf};

use crate::error::{Result, ResultExt as _, bail};

/// Fail early (before minutes of work) when the output folder `dir` cannot be created or
/// written: its nearest existing ancestor must be a folder that accepts a file. Leaves
/// nothing behind.
///
/// # Errors
/// `cannot create output folder DIR: ANCESTOR is not a folder`, or `cannot write into output
/// folder DIR` with the system's reason.
pub fn check_writable_folder(dir: &Path) -> Result<()> {
    let existing = dir
        .ancestors()
        .find(|a| a.as_os_str().is_empty() || a.exists())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let existing = if existing.as_os_str().is_empty() {
        PathBuf::from(".")
    } else {
        existing
    };
    if !existing.is_dir() {
        bail!(
            "cannot create output folder {}: {} is not a folder",
            dir.display(),
            existing.display()
        );
    }
    tempfile::tempfile_in(&existing)
        .with_context(|| format!("cannot write into output folder {}", dir.display()))?;
    Ok(())
}

/// Files to write into one folder, all or nothing.
#[derive(Default)]
pub struct OutputSet {
    /// (file name, contents), in the order added.
    files: Vec<(String, Vec<u8>)>,
}

impl OutputSet {
    /// Queue a file.
    pub fn add(&mut self, name: &str, bytes: impl Into<Vec<u8>>) {
        self.files.push((name.to_owned(), bytes.into()));
    }

    /// Write every file into `dir` (created if missing). Returns the paths written.
    ///
    /// # Errors
    /// When the folder cannot be created or a file cannot be written (nothing is left behind).
    pub fn write_all(&self, dir: &Path) -> Result<Vec<PathBuf>> {
        refuse_dangling_link(dir)?;
        // The folders this call creates, deepest last, to remove again on failure.
        let mut created: Vec<PathBuf> = dir
            .ancestors()
            .take_while(|a| !a.as_os_str().is_empty() && !a.exists())
            .map(Path::to_path_buf)
            .collect();
        created.reverse();
        let result = std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create output folder {}", dir.display()))
            .and_then(|()| {
                // Refuse before touching anything if an output name is taken by a folder, so
                // a failed run leaves an earlier run's files intact.
                for (name, _) in &self.files {
                    let target = dir.join(name);
                    if target.is_dir() {
                        bail!("cannot write {}: it is a folder", target.display());
                    }
                }
                write_files(dir, &self.files)
            });
        if result.is_err() {
            // Remove the (empty) folders we created; ignore failures.
            for d in created.iter().rev() {
                let _ = std::fs::remove_dir(d);
            }
        }
        result
    }
}

/// The nearest ancestor of `dir` that is there (as a name) must not be a symbolic link to
/// nothing: creating the folder would fail with a bare "File exists".
fn refuse_dangling_link(dir: &Path) -> Result<()> {
    for a in dir.ancestors().take_while(|a| !a.as_os_str().is_empty()) {
        let Ok(meta) = std::fs::symlink_metadata(a) else {
            continue;
        };
        if meta.file_type().is_symlink() && !a.exists() {
            let target = std::fs::read_link(a).unwrap_or_default();
            bail!(
                "cannot create output folder {}: {} is a symbolic link to {}, which does not exist; create that folder or choose another output",
                dir.display(),
                a.display(),
                target.display()
            );
        }
        break;
    }
    Ok(())
}

fn write_files(dir: &Path, files: &[(String, Vec<u8>)]) -> Result<Vec<PathBuf>> {
    use std::io::Write;
    let mut staged = Vec::with_capacity(files.len());
    for (name, bytes) in files {
        let mut tmp = tempfile::Builder::new()
            .prefix(&format!(".{name}."))
            .suffix(".tmp")
            .tempfile_in(dir)
            .with_context(|| format!("cannot write into output folder {}", dir.display()))?;
        tmp.write_all(bytes)
            .and_then(|()| tmp.flush())
            .with_context(|| format!("cannot write {}", dir.join(name).display()))?;
        // Temporary files are created private (0600); outputs are ordinary files (0644), so that
        // a ROS node or web server running as another user can read them.
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            std::fs::set_permissions(tmp.path(), std::fs::Permissions::from_mode(0o644))
                .with_context(|| format!("cannot write {}", dir.join(name).display()))?;
        }
        staged.push((tmp, dir.join(name)));
    }
    let mut done: Vec<PathBuf> = Vec::with_capacity(staged.len());
    for (tmp, target) in staged {
        if let Err(e) = tmp.persist(&target) {
            for p in &done {
                let _ = std::fs::remove_file(p);
            }
            return Err(e.error).with_context(|| format!("cannot write {}", target.display()));
        }
        done.push(target);
    }
    Ok(done)
}

/// Write one file atomically (temporary file in the same folder, then rename).
///
/// # Errors
/// When `path` names no file or the file cannot be written.
pub fn write_file(path: &Path, bytes: impl Into<Vec<u8>>) -> Result<()> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let Some(name) = path.file_name() else {
        bail!("{} is not a file path", path.display());
    };
    let name = name.to_string_lossy().into_owned();
    let mut set = OutputSet::default();
    set.add(&name, bytes);
    set.write_all(&dir).map(|_| ())
}
