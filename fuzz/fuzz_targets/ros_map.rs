//! A ROS `map_server` map: the YAML text, a NUL byte, then the image's bytes (PGM or PNG), read
//! by `vpmap_plan::ros::parse_ros_map` as `vpmap plan map.yaml` reads the two files; then
//! inflation and connected components. Images declaring more than `MAX_PIXELS` pixels are
//! skipped before decoding, to keep every run short (the size limits themselves are tested in
//! the crate).
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use vpmap_plan::reach::Components;
use vpmap_plan::ros::parse_ros_map;

/// Largest image decoded, pixels.
const MAX_PIXELS: u64 = 512 * 512;

/// The image's declared size, when its header says it (PNG's IHDR, PGM's first numbers).
fn declared_pixels(image: &[u8]) -> Option<u64> {
    if image.starts_with(b"\x89PNG\r\n\x1a\n") {
        let w = u32::from_be_bytes(image.get(16..20)?.try_into().ok()?);
        let h = u32::from_be_bytes(image.get(20..24)?.try_into().ok()?);
        return Some(u64::from(w) * u64::from(h));
    }
    if !(image.starts_with(b"P2") || image.starts_with(b"P5")) {
        return None;
    }
    // Width and height: the first two numbers after the magic, comments skipped.
    let mut numbers = Vec::new();
    let mut rest = image.get(2..)?;
    while numbers.len() < 2 {
        match rest.first()? {
            b'#' => {
                let end = rest.iter().position(|&c| c == b'\n' || c == b'\r')?;
                rest = rest.get(end..)?;
            }
            c if c.is_ascii_whitespace() => rest = rest.get(1..)?,
            c if c.is_ascii_digit() => {
                let end = rest
                    .iter()
                    .position(|c| !c.is_ascii_digit())
                    .unwrap_or(rest.len());
                let digits = std::str::from_utf8(rest.get(..end)?).ok()?;
                numbers.push(digits.parse::<u64>().unwrap_or(u64::MAX));
                rest = rest.get(end..)?;
            }
            _ => return None,
        }
    }
    Some(numbers[0].saturating_mul(numbers[1]))
}

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == 0).unwrap_or(data.len());
    let (yaml, image) = (&data[..split], data.get(split + 1..).unwrap_or_default());
    let Ok(yaml) = std::str::from_utf8(yaml) else {
        return;
    };
    if declared_pixels(image).is_some_and(|n| n > MAX_PIXELS) {
        return;
    }
    let Ok(grid) = parse_ros_map(yaml, Path::new("fuzz/map.yaml"), image) else {
        return;
    };
    if let Ok(inflated) = grid.inflate(grid.resolution_m() * 1.5) {
        let _ = Components::label(&inflated, data.len() % 2 == 1);
    }
});
