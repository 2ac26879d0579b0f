//! ROS `map_server` map files: a YAML description beside a greyscale image.
//!
//! Writing ([`encode_ros_map`], [`write_ros_map`]) produces a binary PGM (`P5`, maxval 255)
//! with free cells 254, occupied cells 0 and unknown cells 205, and a YAML file with
//! `negate: 0`, `occupied_thresh: 0.65`, `free_thresh: 0.196` and `mode: trinary`, the
//! values `map_saver` writes. Image row 0 is the grid's row 0: the top, highest world `y`.
//!
//! Reading ([`read_ros_map`]) follows `map_server` (ROS 2 `nav2_map_server`):
//! - YAML fields: `image` (a path relative to the YAML file's folder, or absolute),
//!   `resolution` and `origin: [x, y, yaw]` are required; `negate` (0/1 or a boolean,
//!   default 0), `occupied_thresh` (default 0.65), `free_thresh` (default 0.196) and `mode`
//!   (`trinary`, `scale` or `raw`, default `trinary`) are optional. Other keys are ignored.
//!   A non-zero yaw is refused: the grid is axis-aligned.
//! - Images: PGM (`P5` binary and `P2` ASCII, maxval up to 255) and PNG (8-bit or less grey,
//!   grey with alpha, RGB and RGBA; 16-bit samples are reduced to 8 bits; colour is the mean
//!   of the red, green and blue channels, as ROS 1 `map_server`).
//! - A pixel of value `v` with maximum `m` has the occupancy `p = (m - v) / m`, or `v / m`
//!   with `negate`. `trinary`: occupied if `p > occupied_thresh`, free if
//!   `p < free_thresh`, else unknown. `scale`: the same, except that a pixel that is not
//!   fully opaque is unknown; the intermediate probabilities that `map_server` keeps are
//!   unknown here, since the grid has three states. `raw`: the pixel value (scaled to
//!   0-255, `negate` ignored as in `nav2_map_server`) is the occupancy in percent;
//!   values above 100 are unknown, others are thresholded as `p = value / 100`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::error::{PlanError, Result};
use crate::grid::{Occupancy, OccupancyGrid};
use vpmap_files::num;

mod image;
mod write;

use image::decode_image;
pub use write::write_ros_map;

/// Smallest `resolution` a map YAML may give: 10 micrometres a cell.
pub const MIN_RESOLUTION_M: f64 = 1e-5;

/// Largest `resolution` a map YAML may give: 10 km a cell.
pub const MAX_RESOLUTION_M: f64 = 1e4;

/// Largest distance of a map YAML's `origin` from zero along x or y: 10,000 km.
pub const MAX_ORIGIN_M: f64 = 1e7;

/// Pixel value written for a free cell.
pub const FREE_PIXEL: u8 = 254;
/// Pixel value written for an occupied cell.
pub const OCCUPIED_PIXEL: u8 = 0;
/// Pixel value written for an unknown cell.
pub const UNKNOWN_PIXEL: u8 = 205;
/// `occupied_thresh` written, and the default when a YAML file has none.
pub const OCCUPIED_THRESH: f64 = 0.65;
/// `free_thresh` written, and the default when a YAML file has none.
pub const FREE_THRESH: f64 = 0.196;

/// A float as YAML text that reads back to the same value, with a `.` so that YAML 1.1
/// readers see a float.
fn yaml_float(value: f64) -> String {
    let s = format!("{value}");
    if s.contains(['.', 'e', 'E', 'i', 'N']) {
        s
    } else {
        s + ".0"
    }
}

/// A string as a YAML scalar: plain when unambiguous, else double-quoted.
fn yaml_string(value: &str) -> String {
    const RESERVED: [&str; 11] = [
        "true", "false", "yes", "no", "on", "off", "null", "y", "n", "inf", "nan",
    ];
    let plain = value
        .chars()
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_' || c == '/')
        && value
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '/' | '-'))
        && !RESERVED.contains(&value.to_ascii_lowercase().as_str());
    if plain {
        return value.to_owned();
    }
    let mut out = String::from("\"");
    for c in value.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => {
                let _ = write!(out, "\\u{:04X}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// The `map_server` YAML text and the binary PGM image of a grid.
///
/// `image_file_name` is written as the YAML's `image` field: store the image under that
/// name in the YAML file's folder (or use [`write_ros_map`], which does).
///
/// # Example
/// ```
/// use vpmap_plan::{encode_ros_map, Occupancy, OccupancyGrid};
/// let mut grid = OccupancyGrid::new(3, 2, 0.05, [-1.0, 0.5], Occupancy::Free).unwrap();
/// grid.set(0, 0, Occupancy::Occupied).unwrap();
/// grid.set(2, 1, Occupancy::Unknown).unwrap();
/// let (yaml, pgm) = encode_ros_map(&grid, "room.pgm");
/// assert!(yaml.contains("image: room.pgm\n"));
/// assert!(yaml.contains("origin: [-1.0, 0.5, 0.0]\n"));
/// let header = b"P5\n3 2\n255\n";
/// assert_eq!(&pgm[..header.len()], header);
/// assert_eq!(&pgm[header.len()..], &[0, 254, 254, 254, 254, 205]);
/// ```
#[must_use]
pub fn encode_ros_map(grid: &OccupancyGrid, image_file_name: &str) -> (String, Vec<u8>) {
    let [ox, oy] = grid.origin_m();
    let yaml = format!(
        "image: {}\nresolution: {}\norigin: [{}, {}, 0.0]\nnegate: 0\noccupied_thresh: {}\nfree_thresh: {}\nmode: trinary\n",
        yaml_string(image_file_name),
        yaml_float(grid.resolution_m()),
        yaml_float(ox),
        yaml_float(oy),
        yaml_float(OCCUPIED_THRESH),
        yaml_float(FREE_THRESH),
    );
    let header = format!("P5\n{} {}\n255\n", grid.width(), grid.height());
    let mut pgm = Vec::with_capacity(header.len() + grid.cells().len());
    pgm.extend_from_slice(header.as_bytes());
    pgm.extend(grid.cells().iter().map(|c| match c {
        Occupancy::Free => FREE_PIXEL,
        Occupancy::Occupied => OCCUPIED_PIXEL,
        Occupancy::Unknown => UNKNOWN_PIXEL,
    }));
    (yaml, pgm)
}

/// How pixel values map to occupancy (`mode` of the YAML file).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum MapMode {
    Trinary,
    Scale,
    Raw,
}

/// `negate` as `map_server` accepts it: an integer (non-zero is true) or a boolean.
struct Negate(bool);

impl<'de> Deserialize<'de> for Negate {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        /// Reads a boolean or an integer, and names both when it finds anything else.
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Negate;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("0, 1, true or false")
            }
            fn visit_bool<E: serde::de::Error>(self, v: bool) -> std::result::Result<Negate, E> {
                Ok(Negate(v))
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> std::result::Result<Negate, E> {
                Ok(Negate(v != 0))
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> std::result::Result<Negate, E> {
                Ok(Negate(v != 0))
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// The YAML file as written; every field optional so that a missing one is reported by name.
#[derive(Deserialize)]
struct RawMapYaml {
    image: Option<String>,
    resolution: Option<f64>,
    origin: Option<Vec<f64>>,
    negate: Option<Negate>,
    occupied_thresh: Option<f64>,
    free_thresh: Option<f64>,
    mode: Option<String>,
}

/// A validated map YAML file.
#[derive(Debug, Clone, PartialEq)]
struct MapYaml {
    image: PathBuf,
    resolution_m: f64,
    origin_m: [f64; 2],
    negate: bool,
    occupied_thresh: f64,
    free_thresh: f64,
    mode: MapMode,
}

fn parse_map_yaml(text: &str, yaml_path: &Path) -> Result<MapYaml> {
    let raw: Option<RawMapYaml> = serde_saphyr::from_str(text).map_err(|e| PlanError::Yaml {
        path: yaml_path.to_path_buf(),
        message: e.to_string(),
    })?;
    let raw = raw.ok_or_else(|| PlanError::MissingField {
        path: yaml_path.to_path_buf(),
        field: "image",
    })?;
    let missing = |field| PlanError::MissingField {
        path: yaml_path.to_path_buf(),
        field,
    };
    let invalid = |field, value: String, reason: &str| PlanError::InvalidField {
        path: yaml_path.to_path_buf(),
        field,
        value,
        reason: reason.to_owned(),
    };
    let image = raw.image.ok_or_else(|| missing("image"))?;
    if image.is_empty() {
        return Err(invalid(
            "image",
            "\"\"".to_owned(),
            "it must name the image file",
        ));
    }
    let resolution_m = raw.resolution.ok_or_else(|| missing("resolution"))?;
    if !(MIN_RESOLUTION_M..=MAX_RESOLUTION_M).contains(&resolution_m) {
        return Err(invalid(
            "resolution",
            num(resolution_m),
            &format!(
                "it must be from {} to {} metres a cell",
                num(MIN_RESOLUTION_M),
                num(MAX_RESOLUTION_M)
            ),
        ));
    }
    let origin = raw.origin.ok_or_else(|| missing("origin"))?;
    let shown = || {
        format!(
            "[{}]",
            origin
                .iter()
                .map(|v| num(*v))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let &[ox, oy, yaw] = origin.as_slice() else {
        return Err(invalid(
            "origin",
            shown(),
            "it must have 3 elements [x, y, yaw]",
        ));
    };
    if !(ox.is_finite() && oy.is_finite() && yaw.is_finite()) {
        return Err(invalid("origin", shown(), "its elements must be finite"));
    }
    if ox.abs().max(oy.abs()) > MAX_ORIGIN_M {
        return Err(invalid(
            "origin",
            shown(),
            &format!("its x and y must be within ±{} metres", num(MAX_ORIGIN_M)),
        ));
    }
    if yaw != 0.0 {
        return Err(invalid(
            "origin",
            shown(),
            "rotated maps are not supported: the yaw (third element) must be 0",
        ));
    }
    let negate = raw.negate.is_some_and(|n| n.0);
    let occupied_thresh = raw.occupied_thresh.unwrap_or(OCCUPIED_THRESH);
    let free_thresh = raw.free_thresh.unwrap_or(FREE_THRESH);
    for (field, value) in [
        ("occupied_thresh", occupied_thresh),
        ("free_thresh", free_thresh),
    ] {
        if !(0.0..=1.0).contains(&value) {
            return Err(invalid(field, num(value), "it must be in [0, 1]"));
        }
    }
    if free_thresh > occupied_thresh {
        return Err(invalid(
            "free_thresh",
            num(free_thresh),
            &format!(
                "it must not exceed occupied_thresh ({})",
                num(occupied_thresh)
            ),
        ));
    }
    let mode = match raw.mode.as_deref() {
        None | Some("trinary") => MapMode::Trinary,
        Some("scale") => MapMode::Scale,
        Some("raw") => MapMode::Raw,
        Some(other) => {
            return Err(invalid(
                "mode",
                format!("\"{other}\""),
                "it must be \"trinary\", \"scale\" or \"raw\"",
            ));
        }
    };
    let image = Path::new(&image);
    let image = if image.is_absolute() {
        image.to_path_buf()
    } else {
        yaml_path
            .parent()
            .unwrap_or_else(|| Path::new(""))
            .join(image)
    };
    Ok(MapYaml {
        image,
        resolution_m,
        origin_m: [ox, oy],
        negate,
        occupied_thresh,
        free_thresh,
        mode,
    })
}

/// The cell of an occupancy probability `p`.
fn threshold(p: f64, meta: &MapYaml) -> Occupancy {
    if p > meta.occupied_thresh {
        Occupancy::Occupied
    } else if p < meta.free_thresh {
        Occupancy::Free
    } else {
        Occupancy::Unknown
    }
}

/// The cell of a pixel (rules in the [module docs](self)).
fn cell_from_pixel(value: u8, alpha: u8, max_value: u8, meta: &MapYaml) -> Occupancy {
    let m = f64::from(max_value);
    let v = f64::from(value);
    match meta.mode {
        MapMode::Raw => {
            let percent = (v * 255.0 / m).round();
            if percent <= 100.0 {
                threshold(percent / 100.0, meta)
            } else {
                Occupancy::Unknown
            }
        }
        MapMode::Scale if alpha < u8::MAX => Occupancy::Unknown,
        MapMode::Trinary | MapMode::Scale => {
            let p = if meta.negate { v / m } else { (m - v) / m };
            threshold(p, meta)
        }
    }
}

/// Read a `map_server` map: the YAML file and the image it names (rules in the
/// [module docs](self)).
///
/// # Errors
/// [`PlanError::File`] naming a file that cannot be read (the YAML or its image: missing, not a
/// regular file such as `/dev/zero`, or over its size limit, [`vpmap_files::Format`]),
/// [`PlanError::Yaml`] for malformed YAML, [`PlanError::MissingField`] and
/// [`PlanError::InvalidField`] naming the field, [`PlanError::MalformedImage`] and
/// [`PlanError::UnsupportedImage`] for the image, [`PlanError::GridTooLarge`] above
/// [`MAX_CELLS`](crate::grid::MAX_CELLS) pixels.
///
/// # Example
/// ```
/// use vpmap_plan::{read_ros_map, Occupancy};
/// let dir = tempfile::tempdir().unwrap();
/// std::fs::write(dir.path().join("m.pgm"), b"P2 2 1 255\n0 254\n").unwrap();
/// std::fs::write(dir.path().join("m.yaml"), "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n").unwrap();
/// let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
/// assert_eq!(grid.cells(), &[Occupancy::Occupied, Occupancy::Free]);
/// ```
pub fn read_ros_map(yaml_path: &Path) -> Result<OccupancyGrid> {
    let text = vpmap_files::read_text(yaml_path, vpmap_files::Format::RosYaml)?;
    let meta = parse_map_yaml(&text, yaml_path)?;
    let bytes = vpmap_files::read_bytes(&meta.image, vpmap_files::Format::RosImage)?;
    grid_from_image(&meta, &bytes)
}

/// A `map_server` map from its YAML text and the bytes of the image it names, as
/// [`read_ros_map`] reads them from files but with no file opened (the image named by the
/// YAML's `image:` is not read: `image_bytes` stand for it). `yaml_path` only names the files
/// in messages.
///
/// # Errors
/// As [`read_ros_map`], without [`PlanError::File`].
///
/// # Example
/// ```
/// use std::path::Path;
/// use vpmap_plan::{Occupancy, ros::parse_ros_map};
/// let yaml = "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\n";
/// let grid = parse_ros_map(yaml, Path::new("m.yaml"), b"P2 2 1 255\n0 254\n").unwrap();
/// assert_eq!(grid.cells(), &[Occupancy::Occupied, Occupancy::Free]);
/// ```
pub fn parse_ros_map(
    yaml_text: &str,
    yaml_path: &Path,
    image_bytes: &[u8],
) -> Result<OccupancyGrid> {
    let meta = parse_map_yaml(yaml_text, yaml_path)?;
    grid_from_image(&meta, image_bytes)
}

/// The grid of a decoded YAML file and its image's bytes.
fn grid_from_image(meta: &MapYaml, bytes: &[u8]) -> Result<OccupancyGrid> {
    let image = decode_image(bytes, &meta.image)?;
    let cells = match &image.alpha {
        Some(alpha) => image
            .grey
            .iter()
            .zip(alpha)
            .map(|(&v, &a)| cell_from_pixel(v, a, image.max_value, meta))
            .collect(),
        None => image
            .grey
            .iter()
            .map(|&v| cell_from_pixel(v, u8::MAX, image.max_value, meta))
            .collect(),
    };
    OccupancyGrid::from_cells(
        image.width,
        image.height,
        meta.resolution_m,
        meta.origin_m,
        cells,
    )
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::float_cmp)]
mod tests {
    use super::image::decode_pgm;
    use super::write::write_all_or_nothing;
    use super::*;

    fn meta(mode: MapMode, negate: bool) -> MapYaml {
        MapYaml {
            image: PathBuf::from("m.pgm"),
            resolution_m: 0.05,
            origin_m: [0.0; 2],
            negate,
            occupied_thresh: OCCUPIED_THRESH,
            free_thresh: FREE_THRESH,
            mode,
        }
    }

    #[test]
    fn written_pixel_values_read_back_as_their_cells() {
        let m = meta(MapMode::Trinary, false);
        assert_eq!(cell_from_pixel(FREE_PIXEL, 255, 255, &m), Occupancy::Free);
        assert_eq!(
            cell_from_pixel(OCCUPIED_PIXEL, 255, 255, &m),
            Occupancy::Occupied
        );
        assert_eq!(
            cell_from_pixel(UNKNOWN_PIXEL, 255, 255, &m),
            Occupancy::Unknown
        );
    }

    #[test]
    fn negate_swaps_black_and_white() {
        let m = meta(MapMode::Trinary, true);
        assert_eq!(cell_from_pixel(0, 255, 255, &m), Occupancy::Free);
        assert_eq!(cell_from_pixel(255, 255, 255, &m), Occupancy::Occupied);
    }

    #[test]
    fn scale_mode_makes_transparent_pixels_unknown() {
        let m = meta(MapMode::Scale, false);
        assert_eq!(cell_from_pixel(0, 254, 255, &m), Occupancy::Unknown);
        assert_eq!(cell_from_pixel(0, 255, 255, &m), Occupancy::Occupied);
        let t = meta(MapMode::Trinary, false);
        assert_eq!(cell_from_pixel(0, 0, 255, &t), Occupancy::Occupied);
    }

    #[test]
    fn raw_mode_reads_percentages() {
        let m = meta(MapMode::Raw, false);
        assert_eq!(cell_from_pixel(0, 255, 255, &m), Occupancy::Free);
        assert_eq!(cell_from_pixel(100, 255, 255, &m), Occupancy::Occupied);
        assert_eq!(cell_from_pixel(50, 255, 255, &m), Occupancy::Unknown);
        assert_eq!(cell_from_pixel(101, 255, 255, &m), Occupancy::Unknown);
        assert_eq!(cell_from_pixel(255, 255, 255, &m), Occupancy::Unknown);
    }

    #[test]
    fn smaller_maxval_scales_values() {
        let m = meta(MapMode::Trinary, false);
        assert_eq!(cell_from_pixel(1, 255, 1, &m), Occupancy::Free);
        assert_eq!(cell_from_pixel(0, 255, 1, &m), Occupancy::Occupied);
    }

    #[test]
    fn pgm_header_comments_and_ascii_raster() {
        let p = Path::new("x.pgm");
        let img = decode_pgm(b"P2\n# made by hand\n3 # width\n1\n9\n0 9\n5\n", p).unwrap();
        assert_eq!((img.width, img.height, img.max_value), (3, 1, 9));
        assert_eq!(img.grey, vec![0, 9, 5]);
        let img = decode_pgm(b"P5 2 1 255\n\x00\x0a", p).unwrap();
        assert_eq!(img.grey, vec![0, 10]);
    }

    #[test]
    fn malformed_pgm_is_reported() {
        let p = Path::new("x.pgm");
        let e = decode_pgm(b"P5 2 2 255\n\x00\x00", p).unwrap_err();
        assert!(e.to_string().contains("raster has 2 bytes"), "{e}");
        let e = decode_pgm(b"P2 2 1 9\n0 10\n", p).unwrap_err();
        assert!(e.to_string().contains("exceeds maxval 9"), "{e}");
        let e = decode_pgm(b"P5 2 1 65535\n", p).unwrap_err();
        assert!(matches!(e, PlanError::UnsupportedImage { .. }), "{e}");
        let e = decode_pgm(b"P5 2 2\n", p).unwrap_err();
        assert!(e.to_string().contains("no maxval"), "{e}");
        let e = decode_pgm(b"P5 100000 100000 255\n", p).unwrap_err();
        assert!(matches!(e, PlanError::GridTooLarge { .. }), "{e}");
        let e = decode_image(b"P6 1 1 255\n\0\0\0", p).unwrap_err();
        assert!(e.to_string().contains("PPM"), "{e}");
    }

    #[test]
    fn yaml_scalars_are_quoted_when_needed() {
        assert_eq!(yaml_string("map.pgm"), "map.pgm");
        assert_eq!(yaml_string("yes"), "\"yes\"");
        assert_eq!(yaml_string("my map: 1.pgm"), "\"my map: 1.pgm\"");
        assert_eq!(yaml_string("a\"b"), "\"a\\\"b\"");
        assert_eq!(yaml_float(2.0), "2.0");
        assert_eq!(yaml_float(-0.05), "-0.05");
        assert_eq!(yaml_float(1e-7).parse::<f64>().unwrap(), 1e-7);
    }

    #[test]
    fn yaml_defaults_and_errors() {
        let p = Path::new("/maps/room.yaml");
        let m = parse_map_yaml("image: a.pgm\nresolution: 0.1\norigin: [1, 2, 0]\n", p).unwrap();
        assert_eq!(
            m,
            MapYaml {
                image: PathBuf::from("/maps/a.pgm"),
                resolution_m: 0.1,
                origin_m: [1.0, 2.0],
                negate: false,
                occupied_thresh: OCCUPIED_THRESH,
                free_thresh: FREE_THRESH,
                mode: MapMode::Trinary,
            }
        );
        let m = parse_map_yaml(
            "image: /abs/a.pgm\nresolution: 0.1\norigin: [1, 2, 0.0]\nnegate: true\nmode: raw\n",
            p,
        )
        .unwrap();
        assert_eq!(m.image, PathBuf::from("/abs/a.pgm"));
        assert!(m.negate);
        assert_eq!(m.mode, MapMode::Raw);
        let e =
            parse_map_yaml("image: a.pgm\nresolution: 0.1\norigin: [1, 2, 0.5]\n", p).unwrap_err();
        assert!(e.to_string().contains("yaw"), "{e}");
        let e = parse_map_yaml("image: a.pgm\nresolution: 0.1\norigin: [1, 2]\n", p).unwrap_err();
        assert!(e.to_string().contains("3 elements"), "{e}");
        let e = parse_map_yaml(
            "image: a.pgm\nresolution: 0.1\norigin: [1, 2, 0]\nmode: fancy\n",
            p,
        )
        .unwrap_err();
        assert!(e.to_string().contains("fancy"), "{e}");
        let e = parse_map_yaml(
            "image: a.pgm\nresolution: 0.1\norigin: [1, 2, 0]\nfree_thresh: 0.9\n",
            p,
        )
        .unwrap_err();
        assert!(e.to_string().contains("free_thresh"), "{e}");
        let e = parse_map_yaml("image: a.pgm\nresolution: -1\norigin: [1, 2, 0]\n", p).unwrap_err();
        assert!(e.to_string().contains("`resolution` is -1"), "{e}");
        let e =
            parse_map_yaml("image: a.pgm\nresolution: fine\norigin: [1, 2, 0]\n", p).unwrap_err();
        assert!(matches!(e, PlanError::Yaml { .. }), "{e}");
        let e = parse_map_yaml("", p).unwrap_err();
        assert!(e.to_string().contains("image"), "{e}");
    }

    #[test]
    fn a_file_that_cannot_be_written_leaves_the_others_as_they_were() {
        let dir = tempfile::tempdir().unwrap();
        let first = dir.path().join("a.pgm");
        std::fs::write(&first, b"old").unwrap();
        let second = dir.path().join("missing/b.yaml");
        let e = write_all_or_nothing(&[(&first, b"new"), (&second, b"new")]).unwrap_err();
        assert!(e.to_string().contains("b.yaml"), "{e}");
        assert_eq!(std::fs::read(&first).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }
}
