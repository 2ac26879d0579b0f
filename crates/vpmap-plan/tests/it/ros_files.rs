//! ROS map_server files: round trips and hand-written variants.

use std::path::Path;

use proptest::prelude::*;
use vpmap_plan::ros::parse_ros_map;
use vpmap_plan::{
    CellXy, Occupancy, OccupancyGrid, PlanError, encode_ros_map, read_ros_map, write_ros_map,
};

use crate::grids::small_grid;

const F: Occupancy = Occupancy::Free;
const O: Occupancy = Occupancy::Occupied;
const U: Occupancy = Occupancy::Unknown;

fn write(dir: &Path, name: &str, bytes: &[u8]) {
    std::fs::write(dir.join(name), bytes).unwrap();
}

fn yaml_with(image: &str, extra: &str) -> String {
    format!("image: {image}\nresolution: 0.1\norigin: [-1.0, 2.0, 0.0]\n{extra}")
}

fn grey_png(width: u32, height: u32, color: png::ColorType, data: &[u8]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(color);
    encoder.set_depth(png::BitDepth::Eight);
    let mut writer = encoder.write_header().unwrap();
    writer.write_image_data(data).unwrap();
    writer.finish().unwrap();
    out
}

#[test]
fn round_trip_keeps_cells_resolution_and_origin_of_a_non_square_grid() {
    let dir = tempfile::tempdir().unwrap();
    let mut grid = OccupancyGrid::new(7, 3, 0.025, [-12.3, 4.05], Occupancy::Free).unwrap();
    grid.set(6, 2, Occupancy::Unknown).unwrap();
    grid.set(3, 1, Occupancy::Occupied).unwrap();
    grid.set(0, 2, Occupancy::Occupied).unwrap();
    let yaml_path = dir.path().join("room.yaml");
    write_ros_map(&grid, &yaml_path).unwrap();
    let back = read_ros_map(&yaml_path).unwrap();
    assert_eq!(back, grid);
    assert_eq!((back.width(), back.height()), (7, 3));
    assert_eq!(back.resolution_m(), 0.025);
    assert_eq!(back.origin_m(), [-12.3, 4.05]);
    // No temporary file is left behind.
    let mut names: Vec<_> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    names.sort();
    assert_eq!(names, ["room.pgm", "room.yaml"]);
}

#[test]
fn top_left_cell_stays_top_left_at_the_highest_world_y() {
    let dir = tempfile::tempdir().unwrap();
    let mut grid = OccupancyGrid::new(5, 4, 0.5, [1.0, -2.0], Occupancy::Free).unwrap();
    grid.set(0, 0, Occupancy::Occupied).unwrap();
    let (yaml, pgm) = encode_ros_map(&grid, "m.pgm");
    // The PGM's first pixel (top-left) is the occupied one.
    let header = b"P5\n5 4\n255\n";
    assert_eq!(&pgm[..header.len()], header);
    assert_eq!(pgm[header.len()], 0);
    assert!(pgm[header.len() + 1..].iter().all(|&v| v == 254));
    write(dir.path(), "m.yaml", yaml.as_bytes());
    write(dir.path(), "m.pgm", &pgm);
    let back = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(back.get(0, 0), Some(Occupancy::Occupied));
    assert_eq!(back.counts(), (19, 1, 0));
    // Its centre: half a cell right of the origin, 3.5 cells above it.
    assert_eq!(back.world_from_cell(0, 0), [1.25, -0.25]);
    assert_eq!(back.cell_from_world([1.1, -0.1]), Some(CellXy::new(0, 0)));
    assert_eq!(back.cell_from_world([1.1, -1.9]), Some(CellXy::new(0, 3)));
}

#[test]
fn negate_inverts_pixel_meaning() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.pgm", b"P5\n3 1\n255\n\x00\xff\x80");
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.pgm", "negate: 1\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[F, O, U]);
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.pgm", "negate: 0\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F, U]);
}

#[test]
fn custom_thresholds_are_applied() {
    let dir = tempfile::tempdir().unwrap();
    // p = 0.8, 0.5, 0.2 for the three pixels.
    write(dir.path(), "m.pgm", b"P2 3 1 10 2 5 8");
    let extra = "occupied_thresh: 0.4\nfree_thresh: 0.3\n";
    write(dir.path(), "m.yaml", yaml_with("m.pgm", extra).as_bytes());
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, O, F]);
}

#[test]
fn ascii_pgm_with_comments_and_small_maxval() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "m.pgm",
        b"P2\n# CREATOR: by hand\n4 2\n# maxval next\n15\n0 15 15 10\n 15  0\n15 15\n",
    );
    write(dir.path(), "m.yaml", yaml_with("m.pgm", "").as_bytes());
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    // 10 of 15: p = 1/3, between the default thresholds.
    assert_eq!(grid.cells(), &[O, F, F, U, F, O, F, F]);
    assert_eq!(grid.origin_m(), [-1.0, 2.0]);
    assert_eq!(grid.resolution_m(), 0.1);
}

#[test]
fn scale_mode_reads_alpha_as_unknown() {
    let dir = tempfile::tempdir().unwrap();
    let png = grey_png(
        3,
        1,
        png::ColorType::GrayscaleAlpha,
        &[0, 255, 254, 255, 0, 0],
    );
    write(dir.path(), "m.png", &png);
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.png", "mode: scale\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F, U]);
    // Trinary ignores alpha.
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.png", "mode: trinary\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F, O]);
    // With a PGM (no alpha) scale reads like trinary.
    write(dir.path(), "m.pgm", b"P5 3 1 255\n\x00\xfe\xcd");
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.pgm", "mode: scale\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F, U]);
}

#[test]
fn raw_mode_reads_percentages() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.pgm", b"P2 4 1 255 0 100 50 255");
    write(
        dir.path(),
        "m.yaml",
        yaml_with("m.pgm", "mode: raw\n").as_bytes(),
    );
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[F, O, U, U]);
}

#[test]
fn grey_and_rgb_png_images_are_read() {
    let dir = tempfile::tempdir().unwrap();
    let png = grey_png(2, 2, png::ColorType::Grayscale, &[0, 254, 205, 254]);
    write(dir.path(), "m.png", &png);
    write(dir.path(), "m.yaml", yaml_with("m.png", "").as_bytes());
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F, U, F]);
    let png = grey_png(2, 1, png::ColorType::Rgb, &[0, 0, 0, 255, 250, 254]);
    write(dir.path(), "m.png", &png);
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O, F]);
}

#[test]
fn nav2_map_saver_file_is_read() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::create_dir(dir.path().join("maps")).unwrap();
    write(dir.path(), "maps/office.pgm", b"P5\n2 1\n255\n\xfe\x00");
    let yaml = "image: office.pgm\nmode: trinary\nresolution: 0.05\norigin: [-10, -10.5, 0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.25\n";
    write(dir.path(), "maps/office.yaml", yaml.as_bytes());
    let grid = read_ros_map(&dir.path().join("maps/office.yaml")).unwrap();
    assert_eq!(grid.cells(), &[F, O]);
    assert_eq!(grid.origin_m(), [-10.0, -10.5]);
    assert_eq!(grid.resolution_m(), 0.05);
}

#[test]
fn absolute_image_paths_are_used_as_is() {
    let dir = tempfile::tempdir().unwrap();
    let other = tempfile::tempdir().unwrap();
    let image = other.path().join("m.pgm");
    std::fs::write(&image, b"P5 1 1 255\n\x00").unwrap();
    let yaml = yaml_with(&format!("\"{}\"", image.display()), "");
    write(dir.path(), "m.yaml", yaml.as_bytes());
    let grid = read_ros_map(&dir.path().join("m.yaml")).unwrap();
    assert_eq!(grid.cells(), &[O]);
}

#[test]
fn missing_fields_are_named() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.pgm", b"P5 1 1 255\n\x00");
    for (yaml, field) in [
        ("resolution: 0.1\norigin: [0, 0, 0]\n", "image"),
        ("image: m.pgm\norigin: [0, 0, 0]\n", "resolution"),
        ("image: m.pgm\nresolution: 0.1\n", "origin"),
    ] {
        write(dir.path(), "m.yaml", yaml.as_bytes());
        let err = read_ros_map(&dir.path().join("m.yaml")).unwrap_err();
        assert!(
            matches!(&err, PlanError::MissingField { field: f, .. } if *f == field),
            "{err}"
        );
        let msg = err.to_string();
        assert!(msg.contains(&format!("`{field}`")), "{msg}");
        assert!(msg.contains("m.yaml"), "{msg}");
    }
}

#[test]
fn missing_image_is_named() {
    let dir = tempfile::tempdir().unwrap();
    write(
        dir.path(),
        "m.yaml",
        yaml_with("nowhere.pgm", "").as_bytes(),
    );
    let err = read_ros_map(&dir.path().join("m.yaml")).unwrap_err();
    assert!(
        matches!(err, PlanError::File(vpmap_files::FileError::Io { .. })),
        "{err}"
    );
    let msg = err.to_string();
    assert!(
        msg.contains(&dir.path().join("nowhere.pgm").display().to_string()),
        "{msg}"
    );
    let err = read_ros_map(&dir.path().join("absent.yaml")).unwrap_err();
    assert!(err.to_string().contains("absent.yaml"), "{err}");
}

#[test]
fn invalid_fields_are_named_with_their_values() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.pgm", b"P5 1 1 255\n\x00");
    for (yaml, needle) in [
        (
            "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 1.57]\n",
            "`origin` is [0, 0, 1.57]",
        ),
        (
            "image: m.pgm\nresolution: 0\norigin: [0, 0, 0]\n",
            "`resolution` is 0",
        ),
        (
            "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\nmode: bright\n",
            "`mode` is \"bright\"",
        ),
        (
            "image: m.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 1.5\n",
            "`occupied_thresh` is 1.5",
        ),
        (
            "image: m.pgm\nresolution: [1]\norigin: [0, 0, 0]\n",
            "malformed",
        ),
        ("- not\n- a map\n", "malformed"),
    ] {
        write(dir.path(), "m.yaml", yaml.as_bytes());
        let err = read_ros_map(&dir.path().join("m.yaml")).unwrap_err();
        assert!(err.to_string().contains(needle), "{err}");
    }
}

#[test]
fn unsupported_images_are_refused_clearly() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "m.yaml", yaml_with("m.jpg", "").as_bytes());
    write(dir.path(), "m.jpg", b"\xff\xd8\xff\xe0 jpeg");
    let err = read_ros_map(&dir.path().join("m.yaml")).unwrap_err();
    assert!(matches!(err, PlanError::UnsupportedImage { .. }), "{err}");
    assert!(err.to_string().contains("m.jpg"), "{err}");
    write(dir.path(), "m.yaml", yaml_with("m.pgm", "").as_bytes());
    write(dir.path(), "m.pgm", b"P5 4 4 255\n\x00\x00");
    let err = read_ros_map(&dir.path().join("m.yaml")).unwrap_err();
    assert!(matches!(err, PlanError::MalformedImage { .. }), "{err}");
}

#[test]
fn image_names_that_need_quoting_round_trip() {
    let dir = tempfile::tempdir().unwrap();
    let grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Occupied).unwrap();
    let (yaml, pgm) = encode_ros_map(&grid, "my map: #1.pgm");
    write(dir.path(), "my map: #1.pgm", &pgm);
    write(dir.path(), "m.yaml", yaml.as_bytes());
    assert_eq!(read_ros_map(&dir.path().join("m.yaml")).unwrap(), grid);
}

#[test]
fn write_errors_name_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let yaml_path = dir.path().join("absent/room.yaml");
    let err = write_ros_map(&grid, &yaml_path).unwrap_err();
    assert!(err.to_string().contains("absent"), "{err}");
    let err = write_ros_map(&grid, &dir.path().join("room.pgm")).unwrap_err();
    assert!(err.to_string().contains("room.pgm"), "{err}");
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
}

#[test]
fn from_bytes_reads_what_the_files_hold_and_names_the_image_in_errors() {
    let dir = tempfile::tempdir().unwrap();
    let mut grid = OccupancyGrid::new(4, 3, 0.05, [0.5, -1.0], Occupancy::Free).unwrap();
    grid.set(1, 2, Occupancy::Occupied).unwrap();
    grid.set(3, 0, Occupancy::Unknown).unwrap();
    let yaml_path = dir.path().join("room.yaml");
    write_ros_map(&grid, &yaml_path).unwrap();
    let yaml = std::fs::read_to_string(&yaml_path).unwrap();
    let pgm = std::fs::read(dir.path().join("room.pgm")).unwrap();
    let from_bytes = parse_ros_map(&yaml, &yaml_path, &pgm).unwrap();
    assert_eq!(from_bytes, read_ros_map(&yaml_path).unwrap());
    assert_eq!(from_bytes, grid);
    // The image named in the YAML is not opened: the bytes stand for it.
    let elsewhere = Path::new("/nonexistent/dir/room.yaml");
    assert_eq!(parse_ros_map(&yaml, elsewhere, &pgm).unwrap(), grid);
    let err = parse_ros_map(&yaml, elsewhere, b"P5 4 3 255\n\x00").unwrap_err();
    assert!(matches!(err, PlanError::MalformedImage { .. }), "{err}");
    assert!(err.to_string().contains("room.pgm"), "{err}");
    let err = parse_ros_map("image: room.pgm\n", elsewhere, &pgm).unwrap_err();
    assert!(err.to_string().contains("resolution"), "{err}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_grids_round_trip(grid in small_grid(24)) {
        let dir = tempfile::tempdir().unwrap();
        let yaml_path = dir.path().join("g.yaml");
        write_ros_map(&grid, &yaml_path).unwrap();
        prop_assert_eq!(read_ros_map(&yaml_path).unwrap(), grid);
    }
}

#[test]
fn a_failed_write_leaves_the_previous_map_and_nothing_else() {
    // The YAML's path is a folder: refused before anything is written, the previous image
    // byte for byte as it was, no temporary file left.
    let dir = tempfile::tempdir().unwrap();
    let old = OccupancyGrid::new(3, 2, 0.5, [0.0; 2], Occupancy::Occupied).unwrap();
    write_ros_map(&old, &dir.path().join("room.yaml")).unwrap();
    let image_before = std::fs::read(dir.path().join("room.pgm")).unwrap();
    std::fs::remove_file(dir.path().join("room.yaml")).unwrap();
    std::fs::create_dir(dir.path().join("room.yaml")).unwrap();
    let new = OccupancyGrid::new(5, 5, 0.1, [1.0; 2], Occupancy::Free).unwrap();
    let err = write_ros_map(&new, &dir.path().join("room.yaml")).unwrap_err();
    assert!(err.to_string().contains("room.yaml"), "{err}");
    assert_eq!(
        std::fs::read(dir.path().join("room.pgm")).unwrap(),
        image_before
    );
    let mut names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names, ["room.pgm", "room.yaml"]);
}

#[cfg(unix)]
#[test]
fn a_fifo_is_refused_and_left_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let fifo = dir.path().join("room.pgm");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if !made.is_ok_and(|s| s.success()) {
        eprintln!("SKIPPED: mkfifo is not available");
        return;
    }
    let grid = OccupancyGrid::new(2, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let err = write_ros_map(&grid, &dir.path().join("room.yaml")).unwrap_err();
    assert!(err.to_string().contains("room.pgm"), "{err}");
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    assert!(!dir.path().join("room.yaml").exists());
}

#[test]
fn writing_again_replaces_both_files() {
    let dir = tempfile::tempdir().unwrap();
    let yaml = dir.path().join("room.yaml");
    let first = OccupancyGrid::new(3, 2, 0.5, [0.0; 2], Occupancy::Occupied).unwrap();
    write_ros_map(&first, &yaml).unwrap();
    let second = OccupancyGrid::new(4, 4, 0.25, [1.0, 2.0], Occupancy::Free).unwrap();
    write_ros_map(&second, &yaml).unwrap();
    assert_eq!(read_ros_map(&yaml).unwrap(), second);
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
}
