//! A scene file, as `vpmap build` reads it: UTF-8 text, an optional byte-order mark, a JSON
//! object, its unknown fields, the scene's parsing and validation, then the build with every
//! method (fit, sideview, projective): floor map, 3D model, occupancy grid and its ROS files,
//! floor-plan SVG. The grid is kept small: at most `MAX_CELLS` cells, a coarser resolution
//! when the map is too large for the default one.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::{Scene, unknown_fields};
use vpmap_pipeline::{MapOptions, PipelineError, RESOLUTION_RANGE_M};

/// Most grid cells built per method.
const MAX_CELLS: f64 = 20_000.0;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if !text.trim_start().starts_with('{') {
        return;
    }
    let value = serde_json::from_str(text).unwrap_or(serde_json::Value::Null);
    let _ = unknown_fields(&value);
    let Ok(scene) = Scene::from_json_str(text) else {
        return;
    };
    // Round trip: what vpmap writes back must read back.
    let again = scene.to_json_string();
    if let Err(e) = Scene::from_json_str(&again) {
        panic!("a parsed scene does not read back: {e}\n{again}");
    }
    for method in [Method::Fit, Method::Sideview, Method::Projective] {
        let options = MapOptions {
            method,
            max_grid_cells: Some(MAX_CELLS),
            // A little variety from the input's length, not from its content.
            hidden_free: data.len() % 2 == 1,
            grow_confidence: (method == Method::Fit && data.len() % 3 == 0).then_some(0.9),
            ..MapOptions::default()
        };
        match vpmap_pipeline::build(&scene, &options) {
            Err(PipelineError::GridTooLarge { span_x, span_y, .. }) => {
                // The same map on a grid of about 100 cells a side.
                let resolution_m = ((span_x.max(span_y) + 1.0) / 100.0)
                    .clamp(*RESOLUTION_RANGE_M.start(), *RESOLUTION_RANGE_M.end());
                if resolution_m.is_finite() {
                    let _ = vpmap_pipeline::map_and_grid(
                        &scene,
                        &MapOptions {
                            resolution_m,
                            ..options
                        },
                    );
                }
            }
            Ok(built) => {
                if let Err(e) =
                    vpmap_metrology::map::FloorMap::from_json_str(&built.map.to_json_string())
                {
                    panic!("a built map.json does not read back: {e}");
                }
            }
            Err(_) => {}
        }
    }
});
