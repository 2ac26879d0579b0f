//! The page's requests, through the checks its endpoints make (`vpmap_web::fuzzing`): the
//! input's first line is the request line's path and query (`/api/build?method=fit`,
//! `/api/plan`, `/api/navigate`, `/api/detect?focal_px=900`), the rest is the body.
//! `/api/build`, `/api/plan` and `/api/navigate` go through the options, the scene, the map
//! and a grid of at most `MAX_CELLS` cells (for a plan, its start and goal; for a drive, also
//! its planner, sensor range and the true office on the grid); `/api/detect` through its query, checked
//! against the size of the photo in the body as its header declares it.
#![no_main]

use std::io::Cursor;

use libfuzzer_sys::fuzz_target;
use vpmap_web::fuzzing::{build_request, detect_query, navigate_request, plan_request};

/// Most grid cells built.
const MAX_CELLS: f64 = 20_000.0;

fuzz_target!(|data: &[u8]| {
    let split = data.iter().position(|&b| b == b'\n').unwrap_or(data.len());
    let (line, body) = (&data[..split], data.get(split + 1..).unwrap_or_default());
    let Ok(line) = std::str::from_utf8(line) else {
        return;
    };
    let (path, query) = match line.split_once('?') {
        Some((p, q)) => (p, Some(q)),
        None => (line, None),
    };
    let result = match path {
        "/api/build" => build_request(query, body, MAX_CELLS),
        "/api/plan" => plan_request(body, MAX_CELLS),
        "/api/navigate" => navigate_request(body, MAX_CELLS),
        "/api/detect" => {
            let Ok(reader) = image::ImageReader::new(Cursor::new(body)).with_guessed_format()
            else {
                return;
            };
            let Ok((width, height)) = reader.into_dimensions() else {
                return;
            };
            detect_query(query, width, height)
        }
        _ => return,
    };
    if let Err(e) = result {
        assert!(!e.message.is_empty(), "an error without a message");
    }
});
