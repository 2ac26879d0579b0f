//! The SVG floor plan, parsed back with roxmltree.

use roxmltree::{Document, Node};
use vpmap_render::{FloorPlanStyle, floor_plan_svg};

use crate::{awkward_map, default_map, map_with, save_for_review};

fn by_id<'a>(doc: &'a Document, id: &str) -> Node<'a, 'a> {
    doc.descendants()
        .find(|n| n.attribute("id") == Some(id))
        .unwrap_or_else(|| panic!("no element with id {id}"))
}

fn texts(doc: &Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or_default().to_owned())
        .collect()
}

fn num(n: Node, attr: &str) -> f64 {
    n.attribute(attr).unwrap().parse().unwrap()
}

/// Pixel y of every vertex of a path's `d` ("M x y L x y ... Z").
fn path_ys(d: &str) -> Vec<f64> {
    d.split(['M', 'L', 'Z'])
        .filter_map(|s| s.split_whitespace().nth(1).map(|y| y.parse().unwrap()))
        .collect()
}

#[test]
fn default_plan_is_xml_with_every_part() {
    let map = default_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    save_for_review("render-check.svg", svg.as_bytes());
    let doc = Document::parse(&svg).unwrap();
    let root = doc.root_element();
    assert_eq!(root.attribute("width"), Some("1000"));
    let height = num(root, "height");
    assert_eq!(
        root.attribute("viewBox").unwrap(),
        format!("0 0 1000 {height:.0}")
    );
    assert_eq!(
        root.attribute("font-family"),
        Some("DejaVu Sans, sans-serif")
    );
    for id in [
        "free-space",
        "field-of-view",
        "grid",
        "floor",
        "objects",
        "labels",
        "station-point",
        "axes",
        "title",
        "scale-bar",
        "legend",
    ] {
        by_id(&doc, id);
    }
    let free = by_id(&doc, "free-space");
    assert!(
        free.descendants()
            .any(|n| n.attribute("fill-rule") == Some("evenodd"))
    );
    let all_text = texts(&doc).join("\n");
    for o in &map.objects {
        assert!(all_text.contains(&o.name), "label of {}", o.name);
    }
    assert!(all_text.contains("units: metres"));
    if map.fit.is_some() {
        // The default method is the fit: error bars after the values, the height on a line
        // of its own.
        assert!(all_text.contains("pitch 20.0 ± "), "{all_text}");
        assert!(
            all_text.contains(" ± ") && all_text.contains("\nh "),
            "box sizes ± and height"
        );
        by_id(&doc, "uncertainty");
    } else {
        assert!(all_text.contains("pitch 20.0°"), "{all_text}");
        assert!(all_text.contains(" m, h "), "box sizes with height");
    }
    let scale_bar_text: Vec<&str> = by_id(&doc, "scale-bar")
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    assert_eq!(scale_bar_text.len(), 2);
    assert_eq!(scale_bar_text[0], "0");
    assert!(scale_bar_text[1].ends_with(" m"), "{scale_bar_text:?}");
}

#[test]
fn forward_points_up_the_page() {
    let map = default_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let doc = Document::parse(&svg).unwrap();
    let station = by_id(&doc, "station-point")
        .descendants()
        .find(|n| n.has_tag_name("circle"))
        .unwrap();
    let station_y = num(station, "cy");
    // Every object is in front of the camera, so above the station point on the page.
    for (i, o) in map.objects.iter().enumerate() {
        assert!(o.footprint.iter().all(|p| p[1] > 0.0));
        let path = by_id(&doc, &format!("object-{i}"));
        for y in path_ys(path.attribute("d").unwrap()) {
            assert!(
                y < station_y,
                "{}: {y} below the station at {station_y}",
                o.name
            );
        }
    }
    // And the farthest object is highest.
    let far = (0..map.objects.len())
        .max_by(|&a, &b| map.objects[a].centroid[1].total_cmp(&map.objects[b].centroid[1]))
        .unwrap();
    let near = (0..map.objects.len())
        .min_by(|&a, &b| map.objects[a].centroid[1].total_cmp(&map.objects[b].centroid[1]))
        .unwrap();
    let mean = |i: usize| {
        let ys = path_ys(by_id(&doc, &format!("object-{i}")).attribute("d").unwrap());
        ys.iter().sum::<f64>() / ys.len() as f64
    };
    assert!(mean(far) < mean(near));
}

#[test]
fn names_with_xml_specials_are_escaped() {
    let map = awkward_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    assert!(svg.contains("desk &lt;A&amp;B&gt; &quot;left&quot;"));
    assert!(!svg.contains("<A&B>"));
    let doc = Document::parse(&svg).unwrap();
    let all_text = texts(&doc).join("\n");
    assert!(all_text.contains(r#"desk <A&B> "left""#));
    assert!(all_text.contains("h unknown"));
    assert!(all_text.contains("height unknown"), "legend entry");
}

/// Absolute bounding boxes `(x0, y0, x1, y1)` and contents of every text of an SVG, laid out
/// by usvg with the system fonts (the glyph outlines resvg will paint).
fn text_boxes(svg: &str) -> Vec<(String, [f32; 4])> {
    use resvg::usvg::{self, fontdb};
    fn walk(group: &usvg::Group, out: &mut Vec<(String, [f32; 4])>) {
        for node in group.children() {
            match node {
                usvg::Node::Group(g) => walk(g, out),
                usvg::Node::Text(t) => {
                    let b = t.abs_bounding_box();
                    let text = t.chunks().iter().map(usvg::TextChunk::text).collect();
                    out.push((text, [b.left(), b.top(), b.right(), b.bottom()]));
                }
                _ => {}
            }
        }
    }
    let mut db = fontdb::Database::new();
    db.load_system_fonts();
    db.set_sans_serif_family("DejaVu Sans");
    let options = usvg::Options {
        fontdb: std::sync::Arc::new(db),
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options).unwrap();
    let mut out = Vec::new();
    walk(tree.root(), &mut out);
    out
}

#[test]
fn text_stays_inside_the_picture() {
    let mut map = awkward_map();
    map.objects[2].name = "a very long object name that goes on and on and on and on".repeat(3);
    for width_px in [320, 1000, 2400] {
        let style = FloorPlanStyle {
            width_px,
            title: Some("W".repeat(300)),
            ..FloorPlanStyle::default()
        };
        let svg = floor_plan_svg(&map, &style);
        let doc = Document::parse(&svg).unwrap();
        let root = doc.root_element();
        let (w, h) = (num(root, "width") as f32, num(root, "height") as f32);
        let boxes = text_boxes(&svg);
        assert!(boxes.len() > 20, "texts are laid out (fonts found)");
        for (text, [x0, y0, x1, y1]) in boxes {
            assert!(
                x0 >= 0.0 && y0 >= 0.0 && x1 <= w && y1 <= h,
                "{width_px}px: {text:?} at ({x0:.0}, {y0:.0})..({x1:.0}, {y1:.0}) outside {w}x{h}"
            );
        }
    }
}

#[test]
fn grid_step_follows_units_and_size() {
    // Camera heights: grid labelled in ch, title says so.
    let map = map_with(&vpmap_metrology::synth::SynthOptions {
        with_scale: false,
        ..vpmap_metrology::synth::SynthOptions::default()
    });
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let doc = Document::parse(&svg).unwrap();
    let all_text = texts(&doc).join("\n");
    assert!(all_text.contains("camera heights"));
    assert!(all_text.contains("x (ch)"));
    // Every map gets 4..=21 grid lines across its larger side.
    for scale in [1e-3, 1.0, 1e3] {
        let mut m = default_map();
        for o in &mut m.objects {
            o.footprint.iter_mut().flatten().for_each(|v| *v *= scale);
        }
        m.floor.iter_mut().flatten().for_each(|v| *v *= scale);
        m.free_space.clear();
        let svg = floor_plan_svg(&m, &FloorPlanStyle::default());
        let doc = Document::parse(&svg).unwrap();
        let grid = by_id(&doc, "grid");
        let (v, h): (Vec<Node>, Vec<Node>) = grid
            .children()
            .filter(|n| n.has_tag_name("line"))
            .partition(|n| n.attribute("x1") == n.attribute("x2"));
        let most = v.len().max(h.len());
        assert!((4..=22).contains(&most), "scale {scale}: {most} lines");
    }
}

/// A room where objects hide parts of the floor from the camera.
fn map_with_hidden_floor() -> vpmap_metrology::map::FloorMap {
    let map = map_with(&vpmap_metrology::synth::SynthOptions {
        seed: 10,
        pitch_deg: 25.0,
        roll_deg: 3.0,
        height_m: 1.6,
        ..vpmap_metrology::synth::SynthOptions::default()
    });
    assert!(map.hidden.len() >= 2, "the test needs hidden floor");
    map
}

/// Position of an element among all elements, in document order.
fn order(doc: &Document, id: &str) -> usize {
    doc.descendants()
        .filter(Node::is_element)
        .position(|n| n.attribute("id") == Some(id))
        .unwrap_or_else(|| panic!("no element with id {id}"))
}

#[test]
fn hidden_floor_is_hatched_between_free_space_and_objects() {
    let map = map_with_hidden_floor();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    save_for_review("render-check-hidden.svg", svg.as_bytes());
    let doc = Document::parse(&svg).unwrap();
    // The hatch: a pattern of thin grey diagonal lines on a light grey ground.
    let pattern = by_id(&doc, "hidden-hatch");
    assert!(pattern.has_tag_name("pattern"));
    assert!(pattern.ancestors().any(|n| n.has_tag_name("defs")));
    assert_eq!(pattern.attribute("patternUnits"), Some("userSpaceOnUse"));
    assert_eq!(pattern.attribute("patternTransform"), Some("rotate(45)"));
    let line = pattern
        .children()
        .find(|n| n.has_tag_name("line"))
        .expect("hatch line");
    assert!(num(line, "stroke-width") < 2.0, "thin lines");
    assert!(pattern.children().any(|n| n.has_tag_name("rect")));
    // One hatched path per hidden polygon.
    let hidden = by_id(&doc, "hidden");
    let paths: Vec<Node> = hidden
        .children()
        .filter(|n| n.has_tag_name("path"))
        .collect();
    assert_eq!(paths.len(), map.hidden.len());
    for p in &paths {
        assert_eq!(p.attribute("class"), Some("hidden"));
        assert_eq!(p.attribute("fill"), Some("url(#hidden-hatch)"));
        assert_eq!(p.attribute("fill-rule"), Some("evenodd"));
    }
    let hidden_rings: usize = map
        .hidden
        .iter()
        .map(|p| 1 + p.holes.iter().filter(|h| h.len() >= 3).count())
        .sum();
    let subpaths: usize = paths
        .iter()
        .map(|p| p.attribute("d").unwrap().matches('M').count())
        .sum();
    assert_eq!(subpaths, hidden_rings);
    assert_eq!(svg.matches(r#"class="hidden""#).count(), map.hidden.len());
    // Drawing order: on the free space, under the objects.
    assert!(order(&doc, "free-space") < order(&doc, "hidden"));
    assert!(order(&doc, "hidden") < order(&doc, "objects"));
    // Legend entry with a hatched swatch.
    let legend = by_id(&doc, "legend");
    assert!(
        legend
            .descendants()
            .any(|n| n.text() == Some("hidden from the camera"))
    );
    assert!(
        legend
            .descendants()
            .any(|n| n.has_tag_name("rect") && n.attribute("fill") == Some("url(#hidden-hatch)"))
    );
    // Labels are still drawn for every object.
    let all_text = texts(&doc).join("\n");
    for o in &map.objects {
        assert!(all_text.contains(&o.name), "label of {}", o.name);
    }
}

#[test]
fn no_hatch_or_legend_entry_without_hidden_floor() {
    let mut map = map_with_hidden_floor();
    map.hidden.clear();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    assert!(!svg.contains("<pattern"));
    assert!(!svg.contains("hidden-hatch"));
    assert!(!svg.contains("hidden from the camera"));
    assert!(!svg.contains(r#"class="hidden""#));
    let doc = Document::parse(&svg).unwrap();
    assert!(
        doc.descendants()
            .all(|n| n.attribute("id") != Some("hidden"))
    );
    by_id(&doc, "legend");
    // Without a legend the hidden floor is still hatched, with no legend text.
    let map = map_with_hidden_floor();
    let style = FloorPlanStyle {
        show_legend: false,
        ..FloorPlanStyle::default()
    };
    let svg = floor_plan_svg(&map, &style);
    assert!(svg.contains(r#"<pattern id="hidden-hatch""#));
    assert_eq!(svg.matches(r#"class="hidden""#).count(), map.hidden.len());
    assert!(!svg.contains("hidden from the camera"));
}

/// A path starting and ending on objects (where their labels would go): no label box covers
/// the start or the goal marker.
#[test]
fn labels_keep_off_the_path_start_and_goal() {
    let map = default_map();
    let style = FloorPlanStyle {
        path: vec![map.objects[0].centroid, map.objects[1].centroid],
        path_label: "path".to_owned(),
        ..FloorPlanStyle::default()
    };
    let svg = floor_plan_svg(&map, &style);
    let doc = Document::parse(&svg).unwrap();
    let markers: Vec<Node> = by_id(&doc, "path")
        .children()
        .filter(|n| n.has_tag_name("circle"))
        .collect();
    assert_eq!(markers.len(), 2);
    let boxes: Vec<Node> = by_id(&doc, "labels")
        .children()
        .filter(|n| n.has_tag_name("rect"))
        .collect();
    assert_eq!(boxes.len(), map.objects.len());
    for m in &markers {
        let (cx, cy, r) = (num(*m, "cx"), num(*m, "cy"), num(*m, "r"));
        for b in &boxes {
            let (x, y, w, h) = (
                num(*b, "x"),
                num(*b, "y"),
                num(*b, "width"),
                num(*b, "height"),
            );
            let apart = cx + r <= x || cx - r >= x + w || cy + r <= y || cy - r >= y + h;
            assert!(apart, "a label box covers the marker at ({cx}, {cy})");
        }
    }
}

/// `plan --svg`'s picture on a tiny and a large grid, in metres and in cells: its title,
/// ticks and legend lie inside the picture and off each other, and the legend's bug-track
/// symbol has exactly the colours of the drawn tracks.
#[test]
fn plan_picture_text_fits_and_the_track_swatch_has_the_track_colours() {
    use vpmap_plan::grid::{Occupancy, OccupancyGrid};
    use vpmap_plan::{Planner, PlannerKind};
    use vpmap_render::{GridCoordinates, plan_svg};
    for (w, h) in [(12, 9), (300, 180)] {
        let mut grid = OccupancyGrid::new(w, h, 0.05, [-1.0, 2.0], Occupancy::Free).unwrap();
        for y in 1..h - 2 {
            grid.set(w / 3, y, Occupancy::Occupied).unwrap();
        }
        for y in 2..h {
            grid.set(2 * w / 3, y, Occupancy::Unknown).unwrap();
        }
        let (start, goal) = ((0, h / 2), (w - 1, h / 2));
        let planned = PlannerKind::Mbpp
            .planner(true)
            .with_tracks(true)
            .plan(&grid, start.into(), goal.into())
            .unwrap();
        assert!(planned.bugs.len() >= 2, "{w} x {h}");
        for coordinates in [GridCoordinates::World, GridCoordinates::Cells] {
            let svg = plan_svg(
                &grid,
                &planned,
                start,
                goal,
                coordinates,
                "MBPP on a test grid",
            );
            let doc = Document::parse(&svg).unwrap();
            let root = doc.root_element();
            let (pw, ph) = (num(root, "width") as f32, num(root, "height") as f32);
            let boxes = text_boxes(&svg);
            let all: Vec<&str> = boxes.iter().map(|(t, _)| t.as_str()).collect();
            for needle in [
                "MBPP on a test grid",
                "start",
                "goal",
                "occupied cell",
                "unknown cell",
            ] {
                assert!(all.contains(&needle), "{needle:?} missing from {all:?}");
            }
            for (i, (text, [x0, y0, x1, y1])) in boxes.iter().enumerate() {
                assert!(
                    *x0 >= 0.0 && *y0 >= 0.0 && *x1 <= pw && *y1 <= ph,
                    "{w} x {h}: {text:?} at ({x0}, {y0})..({x1}, {y1}) outside {pw} x {ph}"
                );
                for (other, [a0, b0, a1, b1]) in &boxes[i + 1..] {
                    let apart = x1 <= a0 || a1 <= x0 || y1 <= b0 || b1 <= y0;
                    assert!(apart, "{w} x {h}: {text:?} overlaps {other:?}");
                }
            }
            let colours = |class: &str| -> std::collections::BTreeSet<String> {
                doc.descendants()
                    .filter(|n| n.attribute("class") == Some(class))
                    .map(|n| n.attribute("stroke").unwrap().to_owned())
                    .collect()
            };
            assert_eq!(colours("track-swatch"), colours("bug-track"));
        }
    }
}
