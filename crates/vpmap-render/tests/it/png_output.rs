//! The PNG, decoded with the png crate.

use vpmap_render::{FloorPlanStyle, floor_plan_svg, svg_to_png};

use crate::{awkward_map, default_map, save_for_review};

/// Width, height and RGBA pixels of a PNG.
fn decode(bytes: &[u8]) -> (u32, u32, Vec<[u8; 4]>) {
    let mut decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    assert_eq!(info.bit_depth, png::BitDepth::Eight);
    let pixels = buf[..info.buffer_size()]
        .chunks_exact(4)
        .map(|c| [c[0], c[1], c[2], c[3]])
        .collect();
    (info.width, info.height, pixels)
}

fn dark(p: [u8; 4]) -> bool {
    p[3] > 200 && p[0] < 90 && p[1] < 90 && p[2] < 90
}

#[test]
fn plan_png_has_the_svg_size_and_visible_text() {
    let map = default_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let bytes = svg_to_png(&svg).unwrap();
    save_for_review("render-check.png", &bytes);
    let (w, h, pixels) = decode(&bytes);
    assert_eq!(w, 1000);
    let svg_height: f64 = roxmltree::Document::parse(&svg)
        .unwrap()
        .root_element()
        .attribute("height")
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(f64::from(h), svg_height);
    let distinct: std::collections::BTreeSet<[u8; 4]> = pixels.iter().copied().collect();
    assert!(distinct.len() > 50, "only {} colours", distinct.len());
    // The title band (top 40 px, left half) holds only text: it must have dark pixels.
    let title_dark = (0..40)
        .flat_map(|y| (0..500).map(move |x| (x, y)))
        .filter(|&(x, y)| dark(pixels[(y * w + x) as usize]))
        .count();
    assert!(title_dark > 300, "{title_dark} dark pixels in the title");
    // Object labels are drawn too: dark pixels near the first object's centroid label.
    assert!(pixels.iter().filter(|p| dark(**p)).count() > 3000);
}

#[test]
fn small_and_awkward_plan_rasterises() {
    let style = FloorPlanStyle {
        width_px: 320,
        ..FloorPlanStyle::default()
    };
    let bytes = svg_to_png(&floor_plan_svg(&awkward_map(), &style)).unwrap();
    let (w, _, pixels) = decode(&bytes);
    assert_eq!(w, 320);
    assert!(pixels.iter().any(|p| dark(*p)));
}

/// Neutral grey pixels (the hatch and its ground), opaque.
fn neutral_grey(p: [u8; 4]) -> bool {
    p[3] == 255 && p[0] == p[1] && p[1] == p[2] && (100..=235).contains(&p[0])
}

#[test]
fn hidden_floor_hatch_is_rasterised() {
    let mut map = crate::map_with(&vpmap_metrology::synth::SynthOptions {
        seed: 10,
        pitch_deg: 25.0,
        roll_deg: 3.0,
        height_m: 1.6,
        ..vpmap_metrology::synth::SynthOptions::default()
    });
    assert!(!map.hidden.is_empty());
    let bytes = svg_to_png(&floor_plan_svg(&map, &FloorPlanStyle::default())).unwrap();
    save_for_review("render-check-hidden.png", &bytes);
    let (_, _, pixels) = decode(&bytes);
    let with = pixels.iter().filter(|p| neutral_grey(**p)).count();
    // The hatch lines are darker than their ground: both colours are painted.
    let lines = pixels
        .iter()
        .filter(|p| neutral_grey(**p) && p[0] < 180)
        .count();
    map.hidden.clear();
    let bytes = svg_to_png(&floor_plan_svg(&map, &FloorPlanStyle::default())).unwrap();
    let (_, _, pixels) = decode(&bytes);
    let without = pixels.iter().filter(|p| neutral_grey(**p)).count();
    let lines_without = pixels
        .iter()
        .filter(|p| neutral_grey(**p) && p[0] < 180)
        .count();
    assert!(with > without + 20_000, "{with} vs {without} grey pixels");
    assert!(
        lines > lines_without + 2_000,
        "{lines} vs {lines_without} line pixels"
    );
}

/// The legend's swatches of the free space and of the floor in view show the colours those
/// areas have in the picture: many plot pixels have exactly the swatch's colour.
#[test]
fn free_space_and_floor_in_view_swatches_match_the_plot() {
    let map = default_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let (w, _, pixels) = decode(&svg_to_png(&svg).unwrap());
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let num = |n: roxmltree::Node, a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
    let clip = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("plot-clip"))
        .and_then(|n| n.first_element_child())
        .unwrap();
    let (px0, py0) = (num(clip, "x").ceil() as u32, num(clip, "y").ceil() as u32);
    let (px1, py1) = (
        (num(clip, "x") + num(clip, "width")).floor() as u32,
        (num(clip, "y") + num(clip, "height")).floor() as u32,
    );
    let legend = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("legend"))
        .unwrap();
    for label in ["free space", "floor in view"] {
        let text = legend
            .children()
            .find(|n| n.text().is_some_and(|t| t.starts_with(label)))
            .unwrap_or_else(|| panic!("no legend entry {label:?}"));
        let swatch = text.prev_sibling_element().unwrap();
        assert!(swatch.has_tag_name("rect"), "{label}: {swatch:?}");
        let (cx, cy) = (
            (num(swatch, "x") + num(swatch, "width") / 2.0) as u32,
            (num(swatch, "y") + num(swatch, "height") / 2.0) as u32,
        );
        let colour = pixels[(cy * w + cx) as usize];
        let same = (py0..py1)
            .flat_map(|y| (px0..px1).map(move |x| (x, y)))
            .filter(|&(x, y)| pixels[(y * w + x) as usize] == colour)
            .count();
        assert!(
            same > 2000,
            "{label}: only {same} plot pixels have the swatch's colour {colour:?}"
        );
    }
}
