//! Moving AI grid benchmark files: `.map` grids and `.scen` problem lists.
//!
//! Format of Sturtevant's benchmarks (<https://movingai.com/benchmarks/formats.html>):
//!
//! ```text
//! type octile
//! height 4
//! width 6
//! map
//! ......
//! .@@...
//! .@T..S
//! ......
//! ```
//!
//! - **Header**: the lines `type octile`, `height H` and `width W`, in any order (keys in any
//!   case, separated from their value by spaces or tabs), then a line `map`. Blank lines in
//!   the header are skipped; an unknown key, a repeated key, a missing key or a type other
//!   than `octile` is an error.
//! - **Rows**: `H` rows of exactly `W` terrain characters; row 0 is the top row and the
//!   character at column `x` of row `y` is cell `(x, y)`, as in [`OccupancyGrid`].
//!   Trailing spaces, tabs and `\r` are ignored (so CRLF files read like LF files), and so
//!   are blank lines after the last row and a missing final newline.
//! - **Terrain**, as the benchmark's octile-movement problems use it: `.` (ground), `G`
//!   (ground) and `S` (swamp, passable) are [`Occupancy::Free`]; `@` and `O` (out of bounds), `T`
//!   (trees) and `W` (water) are [`Occupancy::Occupied`]. Any other character is an error. No
//!   cell is [`Occupancy::Unknown`].
//! - The grid has resolution 1 and origin `[0, 0]`: lengths are in cells.
//!
//! A `.scen` file starts with `version 1` (or `version 1.0`), then has one problem a line
//! with nine fields separated by tabs or spaces: bucket, map, map width, map height, start
//! x, start y, goal x, goal y, optimal length. Coordinates use the map's convention (x =
//! column, y = row from the top). Map names may include folders (`maps/dao/arena2.map`)
//! or not (`arena2.map`); [`Scenario::map_file_name`] gives the bare name to match files
//! by. The optimal length is for 8-connected moves costing 1 and `sqrt 2`, diagonal steps
//! needing both orthogonal neighbours free (see [`crate::astar`](mod@crate::astar)).
//!
//! # References
//! N. Sturtevant, "Benchmarks for Grid-Based Pathfinding", IEEE Transactions on
//! Computational Intelligence and AI in Games 4(2), 2012.

use std::path::Path;

use crate::error::{PlanError, Result};
use crate::grid::{CellXy, Occupancy, OccupancyGrid, checked_cell_count};

/// One problem of a Moving AI `.scen` file.
#[derive(Clone, PartialEq, Debug)]
pub struct Scenario {
    /// Bucket number (problems of similar length share one).
    pub bucket: u32,
    /// The map's name as written in the file, possibly with folders.
    pub map: String,
    /// Width of the map, cells.
    pub width: usize,
    /// Height of the map, cells.
    pub height: usize,
    /// Start cell `(x, y)`: column, row from the top.
    pub start: CellXy,
    /// Goal cell `(x, y)`: column, row from the top.
    pub goal: CellXy,
    /// Length of a shortest octile path (no corner cutting), cells, as printed in the file.
    pub optimal_length_cells: f64,
}

impl Scenario {
    /// The map's file name without folders (`arena2.map` for `maps/dao/arena2.map`).
    ///
    /// # Example
    /// ```
    /// use vpmap_plan::movingai::parse_scen;
    /// let scen = parse_scen("version 1\n0\tmaps/dao/arena2.map\t281\t209\t1\t2\t3\t4\t2.82843\n").unwrap();
    /// assert_eq!(scen[0].map_file_name(), "arena2.map");
    /// ```
    #[must_use]
    pub fn map_file_name(&self) -> &str {
        self.map.rsplit(['/', '\\']).next().unwrap_or(&self.map)
    }
}

/// The terrain characters of a `.map` file and the cell each becomes.
fn terrain(c: char) -> Option<Occupancy> {
    match c {
        '.' | 'G' | 'S' => Some(Occupancy::Free),
        '@' | 'O' | 'T' | 'W' => Some(Occupancy::Occupied),
        _ => None,
    }
}

fn map_error(line: usize, reason: String) -> PlanError {
    PlanError::MovingAi {
        kind: "map",
        file: None,
        line,
        reason,
    }
}

fn scen_error(line: usize, reason: String) -> PlanError {
    PlanError::MovingAi {
        kind: "scenario",
        file: None,
        line,
        reason,
    }
}

/// Attach the file path to a format error.
fn in_file(err: PlanError, path: &Path) -> PlanError {
    match err {
        PlanError::MovingAi {
            kind, line, reason, ..
        } => PlanError::MovingAi {
            kind,
            file: Some(path.to_path_buf()),
            line,
            reason,
        },
        other => other,
    }
}

fn read_text(path: &Path, format: vpmap_files::Format) -> Result<String> {
    Ok(vpmap_files::read_text(path, format)?)
}

/// Lines numbered from 1, with trailing whitespace (including `\r`) removed.
fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines()
        .enumerate()
        .map(|(i, line)| (i + 1, line.trim_end()))
}

/// A header value: a positive cell count.
fn parse_side(line: usize, key: &str, value: &str) -> Result<usize> {
    match value.parse::<usize>() {
        Ok(n) if n > 0 => Ok(n),
        Ok(_) => Err(map_error(
            line,
            format!("`{key}` is 0; the map needs at least one row and column"),
        )),
        Err(_) => Err(map_error(
            line,
            format!("`{key}` is `{value}`; expected a positive whole number of cells"),
        )),
    }
}

/// Read a Moving AI `.map` grid from its text (see the [module docs](self)).
///
/// # Errors
/// [`PlanError::MovingAi`] naming the line and the value for a malformed header (unknown,
/// repeated or missing key, a type other than `octile`, a side that is not a positive whole
/// number), a row of the wrong length, an unknown terrain character, too few or too many
/// rows; [`PlanError::GridTooLarge`] above [`crate::MAX_CELLS`] cells.
///
/// # Example
/// ```
/// use vpmap_plan::{Occupancy, movingai::parse_movingai_map};
/// let grid = parse_movingai_map("type octile\r\nheight 2\r\nwidth\t3\r\nmap\r\n.@.\r\nT.S").unwrap();
/// assert_eq!((grid.width(), grid.height()), (3, 2));
/// assert_eq!(grid.get(1, 0), Some(Occupancy::Occupied));
/// assert_eq!(grid.get(2, 1), Some(Occupancy::Free));
/// assert!(parse_movingai_map("type octile\nheight 1\nwidth 2\nmap\n.x\n").is_err());
/// ```
pub fn parse_movingai_map(text: &str) -> Result<OccupancyGrid> {
    let mut lines = numbered_lines(text);
    let mut kind: Option<(usize, String)> = None;
    let mut height: Option<(usize, usize)> = None;
    let mut width: Option<(usize, usize)> = None;
    let mut map_line = None;
    for (n, line) in lines.by_ref() {
        let mut words = line.split_whitespace();
        let Some(key) = words.next() else {
            continue;
        };
        let value = words.next();
        if let Some(extra) = words.next() {
            return Err(map_error(
                n,
                format!("unexpected `{extra}` after `{key}` in the header line `{line}`"),
            ));
        }
        let key_lower = key.to_ascii_lowercase();
        if key_lower == "map" {
            if let Some(v) = value {
                return Err(map_error(n, format!("unexpected `{v}` after `map`")));
            }
            map_line = Some(n);
            break;
        }
        let Some(value) = value else {
            return Err(map_error(n, format!("header key `{key}` has no value")));
        };
        let previous = match key_lower.as_str() {
            "type" => kind.replace((n, value.to_owned())).map(|p| p.0),
            "height" => height
                .replace((n, parse_side(n, "height", value)?))
                .map(|p| p.0),
            "width" => width
                .replace((n, parse_side(n, "width", value)?))
                .map(|p| p.0),
            _ => {
                return Err(map_error(
                    n,
                    format!(
                        "unknown header line `{line}`; expected `type octile`, `height H`, `width W` or `map`"
                    ),
                ));
            }
        };
        if let Some(first) = previous {
            return Err(map_error(
                n,
                format!("header key `{key}` repeats the one on line {first}"),
            ));
        }
    }
    let end = text.lines().count() + 1;
    let Some(map_line) = map_line else {
        return Err(map_error(
            end,
            "the text ends before the `map` line that starts the rows".to_owned(),
        ));
    };
    match &kind {
        Some((_, t)) if t.eq_ignore_ascii_case("octile") => {}
        Some((n, t)) => {
            return Err(map_error(
                *n,
                format!("map type is `{t}`; only `octile` is supported"),
            ));
        }
        None => {
            return Err(map_error(
                map_line,
                "no `type octile` line before `map`".into(),
            ));
        }
    }
    let Some((_, height)) = height else {
        return Err(map_error(
            map_line,
            "no `height H` line before `map`".into(),
        ));
    };
    let Some((_, width)) = width else {
        return Err(map_error(map_line, "no `width W` line before `map`".into()));
    };
    let mut cells = Vec::with_capacity(checked_cell_count(width, height)?);
    let mut rows = 0;
    for (n, line) in lines {
        if rows == height {
            if line.is_empty() {
                continue;
            }
            return Err(map_error(
                n,
                format!(
                    "too many rows: the header (height {height}) ends the map at line {}",
                    map_line + height
                ),
            ));
        }
        let found = line.chars().count();
        if found != width {
            return Err(map_error(
                n,
                format!("row {rows} has {found} characters; the header says width {width}"),
            ));
        }
        for (x, c) in line.chars().enumerate() {
            let cell = terrain(c).ok_or_else(|| {
                map_error(
                    n,
                    format!(
                        "unknown terrain character {c:?} at column {} (cell ({x}, {rows})); expected one of . G S @ O T W",
                        x + 1
                    ),
                )
            })?;
            cells.push(cell);
        }
        rows += 1;
    }
    if rows < height {
        return Err(map_error(
            end,
            format!("too few rows: the header says height {height}, the text has {rows}"),
        ));
    }
    OccupancyGrid::from_cells(width, height, 1.0, [0.0, 0.0], cells)
}

/// Read a Moving AI `.map` file (see [`parse_movingai_map`]).
///
/// # Errors
/// [`PlanError::File`] when the file cannot be read (not a regular file, over its size limit,
/// not UTF-8), and the errors of
/// [`parse_movingai_map`], which then name the file.
pub fn read_movingai_map(path: impl AsRef<Path>) -> Result<OccupancyGrid> {
    let path = path.as_ref();
    parse_movingai_map(&read_text(path, vpmap_files::Format::MovingAiMap)?)
        .map_err(|e| in_file(e, path))
}

fn scen_field<T: std::str::FromStr>(line: usize, name: &str, value: &str) -> Result<T> {
    value.parse().map_err(|_| {
        scen_error(
            line,
            format!("{name} is `{value}`; expected a whole number"),
        )
    })
}

fn parse_scen_line(n: usize, line: &str) -> Result<Scenario> {
    let fields: Vec<&str> = line.split_whitespace().collect();
    let &[bucket, map, width, height, sx, sy, gx, gy, optimal] = fields.as_slice() else {
        return Err(scen_error(
            n,
            format!(
                "{} fields; expected 9 (bucket, map, width, height, start x, start y, goal x, goal y, optimal length)",
                fields.len()
            ),
        ));
    };
    let bucket = scen_field(n, "bucket", bucket)?;
    let width: usize = scen_field(n, "map width", width)?;
    let height: usize = scen_field(n, "map height", height)?;
    let start = (scen_field(n, "start x", sx)?, scen_field(n, "start y", sy)?);
    let goal = (scen_field(n, "goal x", gx)?, scen_field(n, "goal y", gy)?);
    for (name, (x, y)) in [("start", start), ("goal", goal)] {
        if x >= width || y >= height {
            return Err(scen_error(
                n,
                format!("{name} ({x}, {y}) is outside the {width} x {height} map"),
            ));
        }
    }
    let optimal_length: f64 = optimal.parse().map_err(|_| {
        scen_error(
            n,
            format!("optimal length is `{optimal}`; expected a number"),
        )
    })?;
    if !(optimal_length.is_finite() && optimal_length >= 0.0) {
        return Err(scen_error(
            n,
            format!("optimal length is {optimal_length}; it must be finite and non-negative"),
        ));
    }
    Ok(Scenario {
        bucket,
        map: map.to_owned(),
        width,
        height,
        start: start.into(),
        goal: goal.into(),
        optimal_length_cells: optimal_length,
    })
}

/// Read the problems of a Moving AI `.scen` file from its text (see the
/// [module docs](self)). Blank lines are skipped.
///
/// # Errors
/// [`PlanError::MovingAi`] naming the line and the value when the first non-blank line is
/// not `version 1` / `version 1.0`, a line does not have nine fields, a number does not
/// parse, a start or goal lies outside the stated map size, or an optimal length is
/// negative or not finite.
///
/// # Example
/// ```
/// use vpmap_plan::movingai::parse_scen;
/// let text = "version 1.0\n3 maps/bg/AR0500SR.map 512 512 81 452 246 138 421.84";
/// let scen = parse_scen(text).unwrap();
/// assert_eq!((scen[0].start, scen[0].goal), ((81, 452).into(), (246, 138).into()));
/// assert_eq!(scen[0].optimal_length_cells, 421.84);
/// ```
pub fn parse_scen(text: &str) -> Result<Vec<Scenario>> {
    let mut lines = numbered_lines(text).filter(|(_, line)| !line.is_empty());
    let Some((n, first)) = lines.next() else {
        return Err(scen_error(
            1,
            "the text is empty; expected `version 1`".to_owned(),
        ));
    };
    let mut words = first.split_whitespace();
    let version_ok = words
        .next()
        .is_some_and(|w| w.eq_ignore_ascii_case("version"))
        && words.next().is_some_and(|v| v == "1" || v == "1.0")
        && words.next().is_none();
    if !version_ok {
        return Err(scen_error(
            n,
            format!("first line is `{first}`; expected `version 1` or `version 1.0`"),
        ));
    }
    lines.map(|(n, line)| parse_scen_line(n, line)).collect()
}

/// Read a Moving AI `.scen` file (see [`parse_scen`]).
///
/// # Errors
/// [`PlanError::File`] when the file cannot be read (not a regular file, over its size limit,
/// not UTF-8), and the errors of
/// [`parse_scen`], which then name the file.
pub fn read_scen(path: impl AsRef<Path>) -> Result<Vec<Scenario>> {
    let path = path.as_ref();
    parse_scen(&read_text(path, vpmap_files::Format::MovingAiScenarios)?)
        .map_err(|e| in_file(e, path))
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::*;

    #[test]
    fn header_in_any_order_with_tabs_and_blank_lines() {
        let grid =
            parse_movingai_map("width \t2\n\nTYPE octile  \nheight 1\nmap\n.W\n\n\n").unwrap();
        assert_eq!(grid.cells(), &[Occupancy::Free, Occupancy::Occupied]);
        assert_eq!(grid.resolution_m(), 1.0);
        assert_eq!(grid.origin_m(), [0.0, 0.0]);
    }

    #[test]
    fn file_errors_name_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.map");
        std::fs::write(&path, "type octile\nheight 1\nwidth 1\nmap\nx\n").unwrap();
        let e = read_movingai_map(&path).unwrap_err().to_string();
        assert!(e.contains("bad.map") && e.contains("line 5"), "{e}");
        let e = read_scen(dir.path().join("missing.scen")).unwrap_err();
        assert!(
            matches!(e, PlanError::File(vpmap_files::FileError::Io { .. })),
            "{e}"
        );
        assert!(e.to_string().contains("missing.scen"), "{e}");
    }
}
