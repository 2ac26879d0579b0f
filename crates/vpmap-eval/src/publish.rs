//! Publishing results: a command's generated section of `docs/results.md`, and a one-line
//! description of the machine that measured it.

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};
use std::time::Duration;

use crate::error::{Result, ResultExt as _, bail};
use crate::output::write_file;

/// Replace the section `name` of the Markdown file at `path` — the lines between
/// `<!-- name:begin -->` and `<!-- name:end -->` — with `content`, keeping everything else;
/// the markers are appended at the end when the file lacks them, and the file is created when
/// missing. Written atomically (temporary file, then rename).
///
/// # Errors
/// When the file cannot be read or written, or holds only one of the two markers.
pub fn replace_section(path: &Path, name: &str, content: &str) -> Result<()> {
    let (old, found) = read_section(path, name)?;
    let (begin, end) = markers(name);
    let body = content.trim_end();
    let new = if let Some((b, e)) = found {
        format!(
            "{}{begin}\n{body}\n{}",
            old.get(..b).unwrap_or_default(),
            old.get(e..).unwrap_or_default()
        )
    } else {
        let mut text = old;
        if !text.is_empty() && !text.ends_with("\n\n") {
            text.push_str(if text.ends_with('\n') { "\n" } else { "\n\n" });
        }
        let _ = write!(text, "{begin}\n{body}\n{end}\n");
        text
    };
    write_file(path, new)
}

/// Check, before a long run, that [`replace_section`] will accept `path` and `name`: the file
/// is absent, or readable with both markers in order or neither.
///
/// # Errors
/// When the file cannot be read or holds only one of the markers, or them out of order.
pub fn check_section(path: &Path, name: &str) -> Result<()> {
    read_section(path, name).map(|_| ())
}

/// The begin and end markers of section `name`.
fn markers(name: &str) -> (String, String) {
    (
        format!("<!-- {name}:begin -->"),
        format!("<!-- {name}:end -->"),
    )
}

/// The file's text (empty when absent) and where section `name` begins and ends in it (the
/// begin marker's and the end marker's byte offsets), `None` when it has no such section.
fn read_section(path: &Path, name: &str) -> Result<(String, Option<(usize, usize)>)> {
    let (begin, end) = markers(name);
    let text = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => String::new(),
        Err(e) => return Err(e).with_context(|| format!("cannot read {}", path.display())),
    };
    let found = match (text.find(&begin), text.find(&end)) {
        (Some(b), Some(e)) if b < e => Some((b, e)),
        (None, None) => None,
        _ => bail!(
            "{} has a broken `{name}` section: it needs `{begin}` before `{end}`",
            path.display()
        ),
    };
    Ok((text, found))
}

/// `path` made absolute and with `.` and `..` removed lexically (symbolic links are not
/// resolved).
fn normalized(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut out = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The relative path from folder `from` to `to`, with `/` separators (for a Markdown link);
/// `.` when they are the same folder.
///
/// # Example
/// ```
/// use std::path::{Component, Path, PathBuf};
/// use vpmap_eval::publish::relative_link;
/// assert_eq!(relative_link(Path::new("/a/docs"), Path::new("/a/bench-out")), "../bench-out");
/// ```
#[must_use]
pub fn relative_link(from: &Path, to: &Path) -> String {
    let (from, to) = (normalized(from), normalized(to));
    let a: Vec<Component> = from.components().collect();
    let b: Vec<Component> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut parts: Vec<String> = vec!["..".to_owned(); a.len() - common];
    parts.extend(
        b.iter()
            .skip(common)
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    if parts.is_empty() {
        ".".to_owned()
    } else {
        parts.join("/")
    }
}

/// Now, UTC, as `YYYY-MM-DD HH:MM UTC`.
#[must_use]
pub fn utc_now() -> String {
    chrono::Utc::now().format("%Y-%m-%d %H:%M UTC").to_string()
}

/// Today's date, UTC, as `YYYY-MM-DD`.
#[must_use]
pub fn utc_date() -> String {
    chrono::Utc::now().format("%Y-%m-%d").to_string()
}

/// The machine, for a results table: CPU model, logical cores, memory, OS.
#[must_use]
pub fn machine_description() -> String {
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    let model = cpuinfo
        .lines()
        .find_map(|l| l.strip_prefix("model name"))
        .and_then(|l| l.split(':').nth(1))
        .map_or_else(|| "unknown CPU".to_owned(), |m| m.trim().to_owned());
    let cores = std::thread::available_parallelism().map_or(1, std::num::NonZero::get);
    let meminfo = std::fs::read_to_string("/proc/meminfo").unwrap_or_default();
    let memory_gib = meminfo
        .lines()
        .find_map(|l| l.strip_prefix("MemTotal:"))
        .and_then(|l| l.split_whitespace().next())
        .and_then(|kb| kb.parse::<f64>().ok())
        .map(|kb| kb / 1024.0 / 1024.0);
    let memory = memory_gib.map_or_else(String::new, |g| format!(", {g:.0} GiB"));
    format!(
        "{model}, {cores} logical cores{memory}, {} {}",
        std::env::consts::OS,
        std::env::consts::ARCH
    )
}

/// The command that regenerates a published section, as a fenced `sh` block that
/// `.ci/doc-blocks.py` leaves unrun (measurements take minutes to hours), with a blank line
/// after it.
#[must_use]
pub fn command_block(command: &str) -> String {
    format!(
        "<!-- not run in CI: minutes to hours of measurement (the times are given with each result) -->\n```sh\n{command}\n```\n"
    )
}

/// A published section titled `title`: where, when and how it was measured (`elapsed`,
/// `command`), then `body`.
#[must_use]
pub fn published(title: &str, body: &str, elapsed: Duration, command: &str) -> String {
    format!(
        "## {title}\n\nMeasured on {}, {} (UTC), in {:.1} s, with\n\n{}\n{body}",
        machine_description(),
        utc_date(),
        elapsed.as_secs_f64(),
        command_block(command)
    )
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn links() {
        assert_eq!(
            relative_link(Path::new("/a/docs"), Path::new("/a/bench-out")),
            "../bench-out"
        );
        assert_eq!(relative_link(Path::new("/a"), Path::new("/a/b/c")), "b/c");
        assert_eq!(relative_link(Path::new("/a/b"), Path::new("/a/b")), ".");
        assert_eq!(
            relative_link(Path::new("/a/./b/../c"), Path::new("/a/d")),
            "../d"
        );
    }

    #[test]
    fn sections_are_replaced_appended_and_checked() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("results.md");
        replace_section(&path, "bench", "first").unwrap();
        std::fs::write(
            &path,
            format!(
                "# Results\n\nintro\n\n{}",
                std::fs::read_to_string(&path).unwrap()
            ),
        )
        .unwrap();
        replace_section(&path, "eval", "E1").unwrap();
        replace_section(&path, "bench", "second\nrun").unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            text,
            "# Results\n\nintro\n\n<!-- bench:begin -->\nsecond\nrun\n<!-- bench:end -->\n\n\
             <!-- eval:begin -->\nE1\n<!-- eval:end -->\n"
        );
        std::fs::write(&path, "<!-- eval:end -->\n<!-- eval:begin -->\n").unwrap();
        assert!(replace_section(&path, "eval", "x").is_err());
        assert!(check_section(&path, "eval").is_err());
        assert!(check_section(&path, "bench").is_ok());
        assert!(check_section(&dir.path().join("absent.md"), "eval").is_ok());
        assert!(machine_description().contains("logical cores"));
        let (date, now) = (utc_date(), utc_now());
        assert_eq!(date.len(), 10);
        assert!(
            now.starts_with(&date[..7]) && now.ends_with(" UTC"),
            "{now}"
        );
    }
}
