//! The bundled example (`examples/office.json` and its known truth) and what `vpmap demo`
//! computes on it besides the build: a path across the built grid ([`demo_path`]) and the
//! map's largest errors against the truth ([`errors_against_truth`]).

use std::path::Path;

use vpmap_metrology::map::FloorMap;
use vpmap_metrology::synth::Truth;
use vpmap_plan::grid::{Occupancy, OccupancyGrid};
use vpmap_plan::mbpp::{MbppOptions, mbpp};
use vpmap_plan::reach::Components;
use vpmap_render::FloorPlanStyle;

use crate::error::PipelineError;

/// The bundled example: a synthetic office seen at 25 degrees pitch (`examples/office.json`;
/// `data/` in this crate links to it, so that the crate's package holds it).
pub const EXAMPLE_SCENE: &str = include_str!("../data/office.json");
/// The bundled example's truth (`examples/office.truth.json`).
pub const EXAMPLE_TRUTH: &str = include_str!("../data/office.truth.json");

/// How far into the seen floor the demo's path starts, in front of the camera, map units.
const START_INTO_FLOOR: f64 = 0.5;

/// The path `vpmap demo` draws.
#[derive(Debug, Clone, PartialEq)]
pub struct DemoRoute {
    /// The path's corners, map coordinates, start first.
    pub waypoints: Vec<[f64; 2]>,
    /// Its first point.
    pub from: [f64; 2],
    /// Its last point.
    pub to: [f64; 2],
    /// Its length, map units.
    pub length: f64,
    /// MBPP's bugs.
    pub bugs: usize,
    /// MBPP's alternative paths.
    pub alternatives: usize,
}

/// What [`demo_path`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum DemoPath {
    /// The grid has no free cell.
    NoFreeFloor,
    /// MBPP found no path.
    NoPath,
    /// The path.
    Found(DemoRoute),
}

/// The demo's path: from the free cell nearest a point half a metre into the seen floor in
/// front of the camera to the reachable free cell deepest into the room (largest map y, the
/// leftmost on a tie), by the thesis's Multi-Bug Path Planning with its default options.
///
/// # Errors
/// [`PipelineError::Plan`] when MBPP refuses the grid or runs out of its budget.
pub fn demo_path(map: &FloorMap, grid: &OccupancyGrid) -> Result<DemoPath, PipelineError> {
    let near_y = map.floor.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    let target = [0.0, near_y + START_INTO_FLOOR];
    let free: Vec<(usize, usize)> = (0..grid.height())
        .flat_map(|y| (0..grid.width()).map(move |x| (x, y)))
        .filter(|&(x, y)| grid.get(x, y) == Some(Occupancy::Free))
        .collect();
    let dist = |c: (usize, usize)| {
        let w = grid.world_from_cell(c.0, c.1);
        (w[0] - target[0]).hypot(w[1] - target[1])
    };
    let Some(start) = free
        .iter()
        .copied()
        .min_by(|a, b| dist(*a).total_cmp(&dist(*b)))
    else {
        return Ok(DemoPath::NoFreeFloor);
    };
    let goal = deepest_reachable(grid, start);
    let result = mbpp(grid, start, goal, &MbppOptions::default()).map_err(PipelineError::Plan)?;
    let Some(plan) = result.best else {
        return Ok(DemoPath::NoPath);
    };
    let waypoints: Vec<[f64; 2]> = plan
        .waypoints
        .iter()
        .map(|c| grid.world_from_cell(c.x, c.y))
        .collect();
    let (Some(&from), Some(&to)) = (waypoints.first(), waypoints.last()) else {
        return Ok(DemoPath::NoPath);
    };
    Ok(DemoPath::Found(DemoRoute {
        from,
        to,
        length: plan.length_cells * grid.resolution_m(),
        bugs: result.mbpp_stats.bugs,
        alternatives: result.alternatives.len(),
        waypoints,
    }))
}

/// The free cell reachable from `start` with the largest world y (the far side of the room),
/// the leftmost of them on a tie.
fn deepest_reachable(grid: &OccupancyGrid, start: (usize, usize)) -> (usize, usize) {
    let components = Components::label(grid, false);
    let Some(label) = components.of(start) else {
        return start;
    };
    // Row 0 is the top, the largest world y: the first cell of the component in row-major
    // order.
    components
        .labels()
        .iter()
        .position(|&l| l == label)
        .map_or(start, |i| components.cell_at(i).into())
}

/// A map's largest errors against its truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TruthErrors {
    /// Largest distance of an object's footprint corner or a floor corner from its true
    /// place, map units.
    pub position: f64,
    /// Largest error of an object's height, map units.
    pub height: f64,
}

/// Largest errors of a map against its truth, corners and heights paired in order (objects,
/// their footprint corners, the floor's corners).
#[must_use]
pub fn errors_against_truth(map: &FloorMap, truth: &Truth) -> TruthErrors {
    let mut position = 0.0f64;
    let mut height = 0.0f64;
    for (m, t) in map.objects.iter().zip(&truth.objects) {
        for (a, b) in m.footprint.iter().zip(&t.footprint) {
            position = position.max((a[0] - b[0]).hypot(a[1] - b[1]));
        }
        if let Some(h) = m.height {
            height = height.max((h - t.height).abs());
        }
    }
    for (a, b) in map.floor.iter().zip(&truth.floor) {
        position = position.max((a[0] - b[0]).hypot(a[1] - b[1]));
    }
    TruthErrors { position, height }
}

/// What `vpmap demo` says about its path, and the floor-plan style that draws it: the line
/// names the `vpmap plan` command that draws the bugs and the alternatives too (into `out`).
///
/// # Example
/// ```
/// use vpmap_pipeline::{demo_path_text, DemoPath};
/// let (line, style) = demo_path_text(&DemoPath::NoPath, std::path::Path::new("out"));
/// assert_eq!(line, "path: no path found");
/// assert!(style.path.is_empty());
/// ```
#[must_use]
pub fn demo_path_text(path: &DemoPath, out: &Path) -> (String, FloorPlanStyle) {
    let route = match path {
        DemoPath::Found(route) => route,
        DemoPath::NoFreeFloor => {
            return (
                "path: the map has no free floor to plan on".to_owned(),
                FloorPlanStyle::default(),
            );
        }
        DemoPath::NoPath => return ("path: no path found".to_owned(), FloorPlanStyle::default()),
    };
    let length = route.length;
    let style = FloorPlanStyle {
        path: route.waypoints.clone(),
        path_label: format!("path (MBPP, {length:.2} m)"),
        ..FloorPlanStyle::default()
    };
    let (a, b) = (route.from, route.to);
    let line = format!(
        "path: MBPP from ({:.2}, {:.2}) to ({:.2}, {:.2}) m around the objects (robot radius {} m): {length:.2} m, {} bugs, {} alternatives; the path is drawn in map.svg and map.png, and\n  vpmap plan {} --from={:.2},{:.2} --to={:.2},{:.2} --planner mbpp --svg {}\ndraws it with every bug's track and the alternatives",
        a[0],
        a[1],
        b[0],
        b[1],
        crate::options::DEFAULT_ROBOT_RADIUS_M,
        route.bugs,
        route.alternatives,
        out.join("map.json").display(),
        a[0],
        a[1],
        b[0],
        b[1],
        out.join("plan.svg").display(),
    );
    (line, style)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::map_and_grid;
    use crate::options::MapOptions;
    use vpmap_metrology::scene::Scene;

    #[test]
    fn the_demo_path_crosses_the_office_and_the_fit_meets_the_truth() {
        let scene = Scene::from_json_str(EXAMPLE_SCENE).unwrap();
        let truth: Truth = serde_json::from_str(EXAMPLE_TRUTH).unwrap();
        let built = map_and_grid(&scene, &MapOptions::default()).unwrap();
        let DemoPath::Found(route) = demo_path(&built.map, &built.grid).unwrap() else {
            panic!("no demo path");
        };
        assert!(route.to[1] > route.from[1] + 5.0, "{route:?}");
        assert_eq!(route.waypoints.first(), Some(&route.from));
        let e = errors_against_truth(&built.map, &truth);
        assert!(e.position < 1e-9 && e.height < 1e-9, "{e:?}");
    }
}
