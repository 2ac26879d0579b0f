//! Integration tests of vpmap-render: SVG, PNG and GLB outputs read back with independent
//! parsers (roxmltree, png, gltf) and checked against the map they were made from.
// Exact float equality is what several checks assert (accessor bounds, f32 coordinates).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod bad_input;
mod glb;
mod overlay;
mod png_output;
mod snapshots;
mod svg_output;

use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::synth::{SynthOptions, synthesize};

/// The default synthetic room: four boxes and one pentagonal prism, in metres.
pub(crate) fn default_map() -> FloorMap {
    map_with(&SynthOptions::default())
}

/// A synthetic map with the given options.
pub(crate) fn map_with(options: &SynthOptions) -> FloorMap {
    let (scene, _) = synthesize(options).unwrap();
    build_map(&scene, &BuildOptions::default()).unwrap()
}

/// The default map with an awkward name (`<&>` and quotes) and one object without a height.
pub(crate) fn awkward_map() -> FloorMap {
    let mut map = default_map();
    r#"desk <A&B> "left""#.clone_into(&mut map.objects[0].name);
    map.objects[1].height = None;
    map
}

/// Write an output for a person to look at when `VPMAP_RENDER_CHECK_DIR` is set.
pub(crate) fn save_for_review(file_name: &str, bytes: &[u8]) {
    if let Some(dir) = std::env::var_os("VPMAP_RENDER_CHECK_DIR") {
        std::fs::write(std::path::Path::new(&dir).join(file_name), bytes).unwrap();
    }
}
