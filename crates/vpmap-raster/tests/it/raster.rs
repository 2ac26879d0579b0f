//! Floor map rasterization against geo's predicates.

use geo::{
    Area, Contains, Coord, Distance, Euclidean, Intersects, LineString, Point, Polygon, Rect,
};
use proptest::prelude::*;
use vpmap_metrology::map::{BuildOptions, FloorMap, MapObject, PolygonWithHoles, build_map};
use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_plan::{CellXy, Occupancy, OccupancyGrid, PlanError};
use vpmap_raster::{RasterError, RasterOptions, rasterize_map};

fn ring(points: &[[f64; 2]]) -> LineString<f64> {
    LineString::from(
        points
            .iter()
            .map(|p| Coord { x: p[0], y: p[1] })
            .collect::<Vec<_>>(),
    )
}

fn free_polygons(map: &FloorMap) -> Vec<Polygon<f64>> {
    map.free_space
        .iter()
        .map(|p| Polygon::new(ring(&p.exterior), p.holes.iter().map(|h| ring(h)).collect()))
        .collect()
}

fn hidden_polygons(map: &FloorMap) -> Vec<Polygon<f64>> {
    map.hidden
        .iter()
        .map(|p| Polygon::new(ring(&p.exterior), p.holes.iter().map(|h| ring(h)).collect()))
        .collect()
}

fn footprints(map: &FloorMap) -> Vec<Polygon<f64>> {
    map.objects
        .iter()
        .map(|o| Polygon::new(ring(&o.footprint), vec![]))
        .collect()
}

fn cell_rect(grid: &OccupancyGrid, x: usize, y: usize) -> Rect<f64> {
    let c = grid.world_from_cell(x, y);
    let h = grid.resolution_m() / 2.0;
    Rect::new(
        Coord {
            x: c[0] - h,
            y: c[1] - h,
        },
        Coord {
            x: c[0] + h,
            y: c[1] + h,
        },
    )
}

/// The rasterization rule, cell by cell, with geo's predicates.
fn reference_cell(
    grid: &OccupancyGrid,
    x: usize,
    y: usize,
    free: &[Polygon<f64>],
    hidden: &[Polygon<f64>],
    obstacles: &[Polygon<f64>],
) -> Occupancy {
    let rect = cell_rect(grid, x, y);
    if obstacles.iter().any(|o| o.intersects(&rect)) {
        return Occupancy::Occupied;
    }
    let c = grid.world_from_cell(x, y);
    let centre = Point::new(c[0], c[1]);
    if free.iter().any(|p| p.contains(&centre)) && !hidden.iter().any(|p| p.contains(&centre)) {
        Occupancy::Free
    } else {
        Occupancy::Unknown
    }
}

fn synthetic_map(seed: u64) -> FloorMap {
    let (scene, _) = synthesize(&SynthOptions {
        seed,
        ..SynthOptions::default()
    })
    .unwrap();
    build_map(&scene, &BuildOptions::default()).unwrap()
}

#[test]
fn synthetic_map_objects_are_occupied_and_open_floor_is_free() {
    let map = synthetic_map(0);
    // Hidden floor is checked cell by cell below; here all seen-or-not floor counts.
    let opts = RasterOptions {
        hidden_free: true,
        ..RasterOptions::default()
    };
    let grid = rasterize_map(&map, &opts).unwrap();
    for object in &map.objects {
        let CellXy { x, y } = grid.cell_from_world(object.centroid).unwrap();
        assert_eq!(grid.get(x, y), Some(Occupancy::Occupied), "{}", object.name);
    }
    // The grid covers the bounds plus the margin.
    let (lo, hi) = map.bounds();
    let o = grid.origin_m();
    let r = grid.resolution_m();
    assert!(o[0] <= lo[0] - opts.margin_m && o[0] > lo[0] - opts.margin_m - r);
    assert!(o[1] <= lo[1] - opts.margin_m && o[1] > lo[1] - opts.margin_m - r);
    let top_right = [
        o[0] + grid.width() as f64 * r,
        o[1] + grid.height() as f64 * r,
    ];
    assert!(top_right[0] >= hi[0] + opts.margin_m && top_right[0] < hi[0] + opts.margin_m + r);
    assert!(top_right[1] >= hi[1] + opts.margin_m && top_right[1] < hi[1] + opts.margin_m + r);
    // A floor point far from every object is free.
    let floor = Polygon::new(ring(&map.floor), vec![]);
    let obstacles = footprints(&map);
    let mut found = 0;
    for y in 0..grid.height() {
        for x in 0..grid.width() {
            let c = grid.world_from_cell(x, y);
            let p = Point::new(c[0], c[1]);
            let far = obstacles.iter().all(|o| Euclidean.distance(&p, o) > 0.3);
            if floor.contains(&p) && far && Euclidean.distance(&p, floor.exterior()) > 0.1 {
                assert_eq!(grid.get(x, y), Some(Occupancy::Free), "({x}, {y}) at {c:?}");
                found += 1;
            }
            if !floor.contains(&p) && Euclidean.distance(&p, floor.exterior()) > 0.1 {
                assert_ne!(grid.get(x, y), Some(Occupancy::Free), "({x}, {y}) at {c:?}");
            }
        }
    }
    assert!(found > 1000, "only {found} open floor cells");
    // The station point is behind the floor the camera sees: unknown.
    assert!(!floor.contains(&Point::new(0.0, 0.0)));
    let CellXy { x, y } = grid.cell_from_world([0.0, 0.0]).unwrap();
    assert_eq!(grid.get(x, y), Some(Occupancy::Unknown));
    assert_eq!(grid.get(0, 0), Some(Occupancy::Unknown));
}

#[test]
fn synthetic_map_matches_geo_predicates_cell_by_cell() {
    for seed in [0, 1, 2] {
        let map = synthetic_map(seed);
        let grid = rasterize_map(
            &map,
            &RasterOptions {
                resolution_m: 0.04,
                ..RasterOptions::default()
            },
        )
        .unwrap();
        let free = free_polygons(&map);
        let hidden = hidden_polygons(&map);
        let obstacles = footprints(&map);
        for y in 0..grid.height() {
            for x in 0..grid.width() {
                let expected = reference_cell(&grid, x, y, &free, &hidden, &obstacles);
                assert_eq!(grid.get(x, y), Some(expected), "seed {seed} ({x}, {y})");
            }
        }
    }
}

#[test]
fn free_area_matches_the_free_space_polygons() {
    let map = synthetic_map(3);
    let free = free_polygons(&map);
    let area: f64 = free.iter().map(Area::unsigned_area).sum();
    let perimeter: f64 = map
        .free_space
        .iter()
        .flat_map(|p| std::iter::once(&p.exterior).chain(&p.holes))
        .map(|r| {
            (0..r.len())
                .map(|i| {
                    let (a, b) = (r[i], r[(i + 1) % r.len()]);
                    (b[0] - a[0]).hypot(b[1] - a[1])
                })
                .sum::<f64>()
        })
        .sum();
    for resolution_m in [0.1, 0.05, 0.02] {
        let grid = rasterize_map(
            &map,
            &RasterOptions {
                resolution_m,
                hidden_free: true,
                ..RasterOptions::default()
            },
        )
        .unwrap();
        let free_area = grid.counts().0 as f64 * resolution_m * resolution_m;
        // Centre sampling errs by about half a cell along the boundary; conservative
        // obstacles take up to about one more cell along the holes.
        let tolerance = 2.0 * perimeter * resolution_m;
        assert!(
            (free_area - area).abs() < tolerance,
            "res {resolution_m}: {free_area} vs {area} (tolerance {tolerance})"
        );
    }
}

#[test]
fn robot_radius_inflates_the_rasterized_obstacles() {
    let map = synthetic_map(0);
    let bare = rasterize_map(&map, &RasterOptions::default()).unwrap();
    let opts = RasterOptions {
        robot_radius_m: 0.25,
        ..RasterOptions::default()
    };
    let inflated = rasterize_map(&map, &opts).unwrap();
    assert_eq!(inflated, bare.inflate(0.25).unwrap());
    assert!(inflated.counts().1 > bare.counts().1);
}

#[test]
fn degenerate_footprints_block_the_cells_they_touch() {
    let mut map = synthetic_map(0);
    map.objects.truncate(1);
    let mut post = map.objects[0].clone();
    post.name = "post".to_owned();
    post.footprint = vec![[0.5, 2.0]];
    let mut wall = post.clone();
    wall.name = "wall".to_owned();
    wall.footprint = vec![[-1.0, 4.0], [1.0, 4.0]];
    map.objects.push(post);
    map.objects.push(wall);
    let grid = rasterize_map(&map, &RasterOptions::default()).unwrap();
    let CellXy { x, y } = grid.cell_from_world([0.5, 2.0]).unwrap();
    assert_eq!(grid.get(x, y), Some(Occupancy::Occupied));
    for i in 0..=20 {
        let p = [-1.0 + 0.1 * f64::from(i), 4.0];
        let CellXy { x, y } = grid.cell_from_world(p).unwrap();
        assert_eq!(grid.get(x, y), Some(Occupancy::Occupied), "{p:?}");
    }
}

#[test]
fn invalid_options_and_maps_are_refused() {
    let map = synthetic_map(0);
    let err = rasterize_map(
        &map,
        &RasterOptions {
            resolution_m: 0.0,
            ..RasterOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        err.to_string().contains("RasterOptions.resolution_m` is 0"),
        "{err}"
    );
    let err = rasterize_map(
        &map,
        &RasterOptions {
            robot_radius_m: -0.2,
            ..RasterOptions::default()
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("robot_radius_m` is -0.2"), "{err}");
    let err = rasterize_map(
        &map,
        &RasterOptions {
            resolution_m: 1e-6,
            ..RasterOptions::default()
        },
    )
    .unwrap_err();
    assert!(
        matches!(err, RasterError::Plan(PlanError::GridTooLarge { .. })),
        "{err}"
    );
    let mut bad = map.clone();
    bad.objects[1].footprint[2][1] = f64::NAN;
    let err = rasterize_map(&bad, &RasterOptions::default()).unwrap_err();
    assert!(
        err.to_string().contains("objects[1].footprint[2][1]"),
        "{err}"
    );
}

fn map_with(free: Vec<PolygonWithHoles>, objects: Vec<Vec<[f64; 2]>>) -> FloorMap {
    let mut map = synthetic_map(0);
    map.floor = free.first().map(|p| p.exterior.clone()).unwrap_or_default();
    map.free_space = free;
    map.hidden = Vec::new();
    let template: MapObject = map.objects[0].clone();
    map.objects = objects
        .into_iter()
        .enumerate()
        .map(|(i, footprint)| MapObject {
            name: format!("o{i}"),
            footprint,
            ..template.clone()
        })
        .collect();
    map
}

/// A star-shaped polygon around `centre`: vertices at increasing angles, radii in
/// `[r_min, r_max)`, so that it never self-intersects.
fn star(
    centre: [f64; 2],
    r_min: f64,
    r_max: f64,
    vertices: std::ops::Range<usize>,
) -> impl Strategy<Value = Vec<[f64; 2]>> {
    proptest::collection::vec((0.0f64..1.0, r_min..r_max), vertices).prop_map(move |parts| {
        let n = parts.len() as f64;
        parts
            .iter()
            .enumerate()
            .map(|(k, (jitter, r))| {
                let a = (k as f64 + 0.8 * jitter) * std::f64::consts::TAU / n;
                [centre[0] + r * a.cos(), centre[1] + r * a.sin()]
            })
            .collect()
    })
}

fn obstacle() -> impl Strategy<Value = Vec<[f64; 2]>> {
    ([-3.0f64..3.0, -3.0f64..3.0]).prop_flat_map(|c| star(c, 0.05, 1.0, 3..7))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// Random free space (a star-shaped exterior with a hole) and obstacles, against geo's
    /// Intersects on each cell's rectangle and Contains on its centre.
    #[test]
    fn random_polygons_match_geo_predicates(
        exterior in star([0.3, -0.2], 1.5, 3.0, 3..12),
        hole in star([0.3, -0.2], 0.1, 1.4, 3..8),
        objects in proptest::collection::vec(obstacle(), 0..4),
        resolution_m in 0.07f64..0.4,
    ) {
        let map = map_with(
            vec![PolygonWithHoles { exterior, holes: vec![hole] }],
            objects,
        );
        let grid = rasterize_map(&map, &RasterOptions { resolution_m, ..RasterOptions::default() }).unwrap();
        let free = free_polygons(&map);
        let hidden = hidden_polygons(&map);
        let obstacles = footprints(&map);
        for y in 0..grid.height() {
            for x in 0..grid.width() {
                let expected = reference_cell(&grid, x, y, &free, &hidden, &obstacles);
                prop_assert_eq!(grid.get(x, y), Some(expected), "({}, {})", x, y);
            }
        }
    }
}

#[test]
fn floor_hidden_behind_objects_is_unknown_unless_asked() {
    let map = synthetic_map(1);
    assert!(
        !map.hidden.is_empty(),
        "the synthetic room must hide some floor"
    );
    let hidden = hidden_polygons(&map);
    let seen = rasterize_map(&map, &RasterOptions::default()).unwrap();
    let all = rasterize_map(
        &map,
        &RasterOptions {
            hidden_free: true,
            ..RasterOptions::default()
        },
    )
    .unwrap();
    let mut hidden_cells = 0;
    for y in 0..seen.height() {
        for x in 0..seen.width() {
            let c = seen.world_from_cell(x, y);
            if all.get(x, y) == Some(Occupancy::Free)
                && hidden.iter().any(|p| p.contains(&Point::new(c[0], c[1])))
            {
                assert_eq!(seen.get(x, y), Some(Occupancy::Unknown), "({x}, {y})");
                hidden_cells += 1;
            } else {
                assert_eq!(seen.get(x, y), all.get(x, y), "({x}, {y})");
            }
        }
    }
    assert!(hidden_cells > 10, "only {hidden_cells} hidden cells");
}
