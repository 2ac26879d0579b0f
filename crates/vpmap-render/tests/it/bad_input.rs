//! Broken and empty maps: an error or a sensible picture, never a panic.

use vpmap_metrology::map::FloorMap;
use vpmap_render::{FloorPlanStyle, RenderError, floor_plan_svg, model_glb, svg_to_png};

use crate::default_map;

/// The SVG parses and rasterises.
fn draws(map: &FloorMap) {
    let svg = floor_plan_svg(map, &FloorPlanStyle::default());
    if let Some(dir) = std::env::var_os("VPMAP_RENDER_DEBUG_DIR") {
        std::fs::write(std::path::Path::new(&dir).join("bad.svg"), &svg).unwrap();
    }
    roxmltree::Document::parse(&svg).unwrap();
    assert!(!svg.contains("NaN\"") && !svg.contains("inf\""), "{svg}");
    let png = svg_to_png(&svg).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
}

fn empty_map() -> FloorMap {
    let mut map = default_map();
    map.objects.clear();
    map.floor.clear();
    map.free_space.clear();
    map.warnings.clear();
    map
}

#[test]
fn nan_footprint_corner_is_skipped_in_pictures_and_named_in_model_errors() {
    let mut map = default_map();
    map.objects[2].footprint[1][0] = f64::NAN;
    map.objects[2].centroid = [f64::NAN; 2];
    draws(&map);
    let err = model_glb(&map).unwrap_err();
    assert!(
        matches!(&err, RenderError::NonFinite { field, value }
            if field == "objects[2].footprint[1][0]" && value.is_nan()),
        "{err}"
    );
    assert!(err.to_string().contains("objects[2].footprint[1][0]"));
}

#[test]
fn infinite_floor_and_camera_values() {
    let mut map = default_map();
    map.floor[0] = [f64::INFINITY, f64::NEG_INFINITY];
    map.camera.pitch_deg = f64::NAN;
    map.camera.horizontal_fov_deg = [f64::NAN, 30.0];
    draws(&map);
    assert!(matches!(
        model_glb(&map),
        Err(RenderError::NonFinite { field, .. }) if field == "floor[0][0]"
    ));
    let mut map = default_map();
    map.camera.height = f64::NAN;
    draws(&map);
    assert!(matches!(
        model_glb(&map),
        Err(RenderError::NonFinite { field, .. }) if field == "camera.height"
    ));
}

#[test]
fn empty_map_gives_a_plan_and_a_floor_rectangle() {
    let map = empty_map();
    draws(&map);
    let glb = model_glb(&map).unwrap();
    let gltf = gltf::Gltf::from_slice(&glb).unwrap();
    let names: Vec<&str> = gltf.nodes().filter_map(|n| n.name()).collect();
    assert_eq!(names, ["floor (bounding rectangle)", "camera"]);
}

#[test]
fn degenerate_footprint_is_an_error_for_the_model_only() {
    let mut map = default_map();
    map.objects[0].footprint = vec![[1.0, 2.0]; 4];
    draws(&map);
    assert!(matches!(
        model_glb(&map),
        Err(RenderError::DegenerateFootprint { corners: 1, .. })
    ));
    map.objects[0].footprint = vec![[1.0, 2.0], [2.0, 2.0], [3.0, 2.0]];
    assert!(matches!(
        model_glb(&map),
        Err(RenderError::DegenerateFootprint { corners: 3, .. })
    ));
}

#[test]
fn huge_and_tiny_maps() {
    let mut map = default_map();
    map.objects[0].footprint[0] = [1e300, 5.0];
    draws(&map);
    assert!(matches!(
        model_glb(&map),
        Err(RenderError::OutOfRange { .. })
    ));
    let mut map = default_map();
    for o in &mut map.objects {
        o.footprint.iter_mut().flatten().for_each(|v| *v *= 1e-9);
        o.height = o.height.map(|h| h * 1e-9);
    }
    map.floor.iter_mut().flatten().for_each(|v| *v *= 1e-9);
    map.free_space.clear();
    map.camera.height *= 1e-9;
    draws(&map);
    model_glb(&map).unwrap();
}

#[test]
fn zero_width_and_garbage_svg() {
    let style = FloorPlanStyle {
        width_px: 0,
        margin_frac: f64::NAN,
        ..FloorPlanStyle::default()
    };
    let svg = floor_plan_svg(&empty_map(), &style);
    assert!(svg.contains(r#"width="200""#));
    assert!(matches!(svg_to_png("<svg"), Err(RenderError::Svg(_))));
    assert!(matches!(
        svg_to_png(r#"<svg xmlns="http://www.w3.org/2000/svg" width="1000000" height="1000000"/>"#),
        Err(RenderError::ImageSize { .. })
    ));
}
