//! Snapshots of the pictures a person reads (the bundled example's floor plan, a plan with
//! MBPP's bugs), and the `data-svg-from-map` transform checked against what is drawn.

use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::Scene;
use vpmap_plan::grid::{Occupancy, OccupancyGrid};
use vpmap_plan::navigate::{NavigateOptions, OnlinePlanner, navigate};
use vpmap_plan::{Planned, Planner, PlannerKind};
use vpmap_render::{FloorPlanStyle, GridCoordinates, floor_plan_svg, navigation_svg, plan_svg};

const OFFICE: &str = include_str!("../../../../examples/office.json");

/// The office with the thesis's side-view method (pinned, so that the snapshot keeps showing a
/// map without error bars whatever the default method).
fn office_map() -> FloorMap {
    let scene = Scene::from_json_str(OFFICE).unwrap();
    let options = BuildOptions {
        method: Method::Sideview,
        ..BuildOptions::default()
    };
    build_map(&scene, &options).unwrap()
}

/// The office by the joint fit, with error bars for a click noise of 1 px.
fn office_fit_map() -> FloorMap {
    let scene = Scene::from_json_str(OFFICE).unwrap();
    let options = BuildOptions {
        method: Method::Fit,
        click_sigma_px: Some(1.0),
    };
    build_map(&scene, &options).unwrap()
}

/// The six numbers of the root element's `data-svg-from-map`.
fn svg_from_map(svg: &str) -> [f64; 6] {
    let doc = roxmltree::Document::parse(svg).unwrap();
    let text = doc.root_element().attribute("data-svg-from-map").unwrap();
    let numbers: Vec<f64> = text.split(' ').map(|v| v.parse().unwrap()).collect();
    numbers.try_into().unwrap()
}

fn apply(m: [f64; 6], [x, y]: [f64; 2]) -> (f64, f64) {
    (m[0] * x + m[2] * y + m[4], m[1] * x + m[3] * y + m[5])
}

/// A 12 x 9 grid with two walls across the straight line from (0, 4) to (11, 4), MBPP with
/// its bug tracks.
fn two_walls() -> (OccupancyGrid, Planned) {
    let mut grid = OccupancyGrid::new(12, 9, 0.25, [-1.0, 2.0], Occupancy::Free).unwrap();
    for y in 1..7 {
        grid.set(3, y, Occupancy::Occupied).unwrap();
    }
    for y in 3..9 {
        grid.set(7, y, Occupancy::Occupied).unwrap();
    }
    let planned = PlannerKind::Mbpp
        .planner(false)
        .with_tracks(true)
        .plan(&grid, (0, 4).into(), (11, 4).into())
        .unwrap();
    (grid, planned)
}

#[test]
fn office_floor_plan() {
    insta::assert_snapshot!(floor_plan_svg(&office_map(), &FloorPlanStyle::default()));
}

#[test]
fn office_floor_plan_with_error_bars() {
    insta::assert_snapshot!(floor_plan_svg(
        &office_fit_map(),
        &FloorPlanStyle::default()
    ));
}

#[test]
fn error_ellipses_are_drawn_where_the_map_puts_them() {
    let map = office_fit_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let m = svg_from_map(&svg);
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let ellipses: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("ellipse") && n.attribute("class") == Some("centroid-ellipse"))
        .collect();
    assert_eq!(ellipses.len(), map.objects.len());
    for (i, o) in map.objects.iter().enumerate() {
        let e = o.uncertainty.as_ref().unwrap().centroid_ellipse_95;
        let node = ellipses[i];
        assert_eq!(node.attribute("id"), Some(format!("ellipse-{i}").as_str()));
        let at = |name| node.attribute(name).unwrap().parse::<f64>().unwrap();
        let (x, y) = apply(m, e.centre);
        assert!((at("cx") - x).abs() <= 0.005 && (at("cy") - y).abs() <= 0.005);
        assert!((at("rx") - e.semi_axes[0] * m[0]).abs() <= 0.005);
        assert!((at("ry") - e.semi_axes[1] * m[0]).abs() <= 0.005);
        // Counter-clockwise on the map is clockwise on the page (y down).
        let rotate = format!("rotate({:.2} ", -e.angle_deg + 0.0);
        assert!(node.attribute("transform").unwrap().starts_with(&rotate));
    }
    // Every label of a box shows its sizes and height with their error bars.
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .collect();
    for o in map.objects.iter().filter(|o| o.size.is_some()) {
        let s = o.size.unwrap();
        let want = format!("{:.2} ± ", s.length);
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with(&want) && t.contains(" × ")),
            "{}: no \"{want}...\" among {texts:?}",
            o.name
        );
    }
    assert!(texts.iter().any(|t| t.starts_with("joint fit: focal ")));
    // The map without error bars has none of this.
    let plain = floor_plan_svg(&office_map(), &FloorPlanStyle::default());
    assert!(!plain.contains("ellipse") && !plain.contains('±') && !plain.contains("joint fit"));
}

/// Regression: error bars below the last decimal are written `<0.01`, which must be escaped
/// in the ellipses' titles too (the page refused the floor plan as invalid SVG).
#[test]
fn tiny_error_bars_give_valid_svg() {
    let scene = Scene::from_json_str(OFFICE).unwrap();
    let options = BuildOptions {
        method: Method::Fit,
        click_sigma_px: Some(1e-6),
    };
    let svg = floor_plan_svg(
        &build_map(&scene, &options).unwrap(),
        &FloorPlanStyle::default(),
    );
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let titles: Vec<&str> = doc
        .descendants()
        .filter(|n| n.has_tag_name("title"))
        .filter_map(|n| n.text())
        .collect();
    assert!(
        titles
            .iter()
            .any(|t| t.ends_with("95 % ellipse <0.01 × <0.01")),
        "{titles:?}"
    );
}

#[test]
fn mbpp_plan_with_bugs() {
    let (grid, planned) = two_walls();
    assert!(planned.bugs.len() >= 2 && !planned.alternatives.is_empty());
    let svg = plan_svg(
        &grid,
        &planned,
        (0, 4),
        (11, 4),
        GridCoordinates::World,
        "MBPP on two walls",
    );
    insta::assert_snapshot!(svg);
}

/// A D* Lite drive across a 12 x 8 room knowing nothing: a wall with a gap, met as the robot
/// senses it (range 3 cells).
#[test]
fn navigation_drive_over_a_wall() {
    let mut truth = OccupancyGrid::new(12, 8, 0.1, [0.0; 2], Occupancy::Free).unwrap();
    for y in 0..6 {
        truth.set(6, y, Occupancy::Occupied).unwrap();
    }
    let believed = OccupancyGrid::new(12, 8, 0.1, [0.0; 2], Occupancy::Unknown).unwrap();
    let opts = NavigateOptions {
        planner: OnlinePlanner::DStarLite,
        sensor_range_cells: 3.0,
        ..NavigateOptions::default()
    };
    let (start, goal) = ((1, 1).into(), (10, 1).into());
    let run = navigate(&believed, &truth, start, goal, &opts).unwrap();
    assert!(run.events.len() >= 2, "the wall makes it re-plan");
    let svg = navigation_svg(&truth, &believed, &run, start, goal, opts.planner);
    // The robot's animation starts at the start and ends at the goal's centre.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let robot = doc
        .descendants()
        .find(|n| n.attribute("class") == Some("robot"))
        .unwrap();
    let values = |name: &str| -> Vec<String> {
        let a = robot
            .children()
            .find(|c| c.attribute("attributeName") == Some(name))
            .unwrap();
        a.attribute("values")
            .unwrap()
            .split(';')
            .map(str::to_owned)
            .collect()
    };
    assert_eq!(values("cx").first().map(String::as_str), Some("1.5"));
    assert_eq!(values("cx").last().map(String::as_str), Some("10.5"));
    assert_eq!(values("cy").last().map(String::as_str), Some("1.5"));
    insta::assert_snapshot!(svg);
}

#[test]
fn floor_plan_transform_puts_the_station_point_and_the_objects_where_they_are_drawn() {
    let map = office_map();
    let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
    let m = svg_from_map(&svg);
    assert!(
        m[1] == 0.0 && m[2] == 0.0 && m[0] > 0.0 && m[3] == -m[0],
        "{m:?}"
    );
    let doc = roxmltree::Document::parse(&svg).unwrap();
    // The station point (0, 0) is the centre of the camera marker.
    let marker = doc
        .descendants()
        .find(|n| {
            n.has_tag_name("circle")
                && n.ancestors()
                    .any(|a| a.attribute("id") == Some("station-point"))
        })
        .unwrap();
    let (x, y) = apply(m, [0.0, 0.0]);
    let at = |name| marker.attribute(name).unwrap().parse::<f64>().unwrap();
    assert!((at("cx") - x).abs() <= 0.005 && (at("cy") - y).abs() <= 0.005);
    // Each object's first corner is the first point of its path.
    for (i, o) in map.objects.iter().enumerate() {
        let id = format!("object-{i}");
        let d = doc
            .descendants()
            .find(|n| n.attribute("id") == Some(id.as_str()))
            .and_then(|n| n.attribute("d"))
            .unwrap();
        let first: Vec<f64> = d[1..]
            .split(' ')
            .take(2)
            .map(|v| v.parse().unwrap())
            .collect();
        let (x, y) = apply(m, o.footprint[0]);
        assert!(
            (first[0] - x).abs() <= 0.005 && (first[1] - y).abs() <= 0.005,
            "{id}: {first:?} vs ({x}, {y})"
        );
    }
}

#[test]
fn plan_transform_puts_cell_centres_at_their_picture_cells() {
    let (grid, planned) = two_walls();
    for (coordinates, centre) in [
        (GridCoordinates::World, grid.world_from_cell(11, 4)),
        (GridCoordinates::Cells, [11.0, 4.0]),
    ] {
        let svg = plan_svg(&grid, &planned, (0, 4), (11, 4), coordinates, "two walls");
        assert_eq!(
            apply(svg_from_map(&svg), centre),
            (11.5, 4.5),
            "{coordinates:?}"
        );
    }
}
