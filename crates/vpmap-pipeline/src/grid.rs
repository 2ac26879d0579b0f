//! Floor map to planning grid: [`occupancy_grid`], the one rasterisation of a floor map that
//! every command and endpoint plans on, and the growing of obstacles by their uncertainty.

use nalgebra::Vector2;
use vpmap_metrology::map::{FloorMap, ObjectUncertainty};
use vpmap_plan::OccupancyGrid;
use vpmap_raster::{RasterOptions, rasterize_map};

use crate::error::PipelineError;
use crate::options::{GRID_MARGIN_M, MapOptions};
use crate::text::units_name;

/// Radius by which an obstacle is grown at confidence `p`, `k = sqrt(-2 ln(1 - p))` sigmas
/// (the chi-square quantile with 2 degrees of freedom): the larger of
///
/// * the centroid's confidence circle of its larger standard deviation plus half its larger
///   side's standard deviation, both at `k` sigmas, and
/// * the least certain footprint corner's confidence circle, `k` times
///   [`ObjectUncertainty::corner_sd`] (its standard deviation along its least certain
///   direction): the circle contains that corner's confidence ellipse, and every corner's, and
///   a point of an edge between two corners is no less certain than the less certain of them,
///   so the grown outline holds each point of the true one at `p`. This is what the first
///   misses: a box's yaw turns its far corners, and a footprint's vertices are fitted one by
///   one.
///
/// Conservative: each circle contains its ellipse.
#[must_use]
pub fn uncertainty_margin(u: &ObjectUncertainty, p: f64) -> f64 {
    let k = (-2.0 * (1.0 - p).ln()).sqrt();
    let c = u.centroid_covariance;
    let mean = 0.5 * (c[0][0] + c[1][1]);
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    let largest = mean + (mean * mean - det).max(0.0).sqrt();
    let side = u.length_sd.unwrap_or(0.0).max(u.breadth_sd.unwrap_or(0.0));
    let centre = k * (largest.max(0.0).sqrt() + 0.5 * side);
    let corner = k * u.corner_sd.filter(|s| s.is_finite()).unwrap_or(0.0);
    centre.max(corner)
}

/// The map with each obstacle grown by [`uncertainty_margin`] at confidence `p` and the free
/// space recomputed; objects without error bars stay as they are.
#[must_use]
pub fn grown_by_uncertainty(map: &FloorMap, p: f64) -> FloorMap {
    use geo::{Buffer, LineString, Polygon};
    let mut out = map.clone();
    for o in &mut out.objects {
        let Some(u) = &o.uncertainty else { continue };
        let r = uncertainty_margin(u, p);
        if !(r.is_finite() && r > 0.0) || o.footprint.len() < 3 {
            continue;
        }
        let poly = Polygon::new(
            LineString::from(o.footprint.iter().map(|q| (q[0], q[1])).collect::<Vec<_>>()),
            vec![],
        );
        let grown = poly.buffer(r);
        if let Some(largest) = grown
            .0
            .iter()
            .max_by(|a, b| geo::Area::unsigned_area(*a).total_cmp(&geo::Area::unsigned_area(*b)))
        {
            let mut ring: Vec<[f64; 2]> = largest.exterior().coords().map(|c| [c.x, c.y]).collect();
            if ring.len() > 1 && ring.first() == ring.last() {
                ring.pop();
            }
            o.footprint = ring;
        }
    }
    let floor: Vec<Vector2<f64>> = out.floor.iter().map(|p| Vector2::new(p[0], p[1])).collect();
    let footprints: Vec<Vec<Vector2<f64>>> = out
        .objects
        .iter()
        .map(|o| {
            o.footprint
                .iter()
                .map(|p| Vector2::new(p[0], p[1]))
                .collect()
        })
        .collect();
    out.free_space =
        vpmap_metrology::map::to_polygons(&vpmap_metrology::map::free_space(&floor, &footprints));
    out
}

/// The occupancy grid of a floor map: the one rasterisation every planning grid comes from
/// (`vpmap build`'s occupancy grid, the page's `/api/build` and `/api/plan` through
/// [`crate::map_and_grid`], and `vpmap plan` and `vpmap navigate` on a `map.json` through
/// [`crate::planning::read_planning_map`]). Obstacles are grown by their uncertainty first
/// when [`MapOptions::grow_confidence`] is set; the map is rasterised at
/// [`MapOptions::resolution_m`] with [`GRID_MARGIN_M`] of unknown border, floor hidden behind
/// objects unknown unless [`MapOptions::hidden_free`], and obstacles inflated by
/// [`MapOptions::robot_radius_m`] ([`vpmap_raster::rasterize_map`]). Refused beyond
/// [`MapOptions::max_grid_cells`] before any cell is made.
///
/// The options are not range-checked here beyond what rasterising needs
/// ([`vpmap_raster::RasterOptions::validate`]): [`crate::map_and_grid`] and [`crate::build`]
/// check them all with [`MapOptions::validate`] first.
///
/// # Errors
/// [`PipelineError::GridTooLarge`] beyond [`MapOptions::max_grid_cells`], and
/// [`PipelineError::Grid`] for a resolution or radius rasterising refuses, a map it cannot
/// read, or a grid beyond [`vpmap_plan::MAX_CELLS`].
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions};
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_pipeline::{map_and_grid, occupancy_grid, MapOptions};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let options = MapOptions::default();
/// let from_scene = map_and_grid(&scene, &options).unwrap();
/// assert_eq!(occupancy_grid(&from_scene.map, &options).unwrap(), from_scene.grid);
/// ```
pub fn occupancy_grid(
    map: &FloorMap,
    options: &MapOptions,
) -> Result<OccupancyGrid, PipelineError> {
    let grown;
    let map = match options.grow_confidence {
        Some(p) => {
            grown = grown_by_uncertainty(map, p);
            &grown
        }
        None => map,
    };
    if let Some(limit) = options.max_grid_cells {
        let (mut lo, mut hi) = map.bounds();
        for p in map.free_space.iter().flat_map(|p| &p.exterior) {
            for axis in 0..2 {
                lo[axis] = lo[axis].min(p[axis]);
                hi[axis] = hi[axis].max(p[axis]);
            }
        }
        let cells_along = |axis: usize| {
            ((hi[axis] - lo[axis] + 2.0 * GRID_MARGIN_M) / options.resolution_m).ceil() + 1.0
        };
        let (width, height) = (cells_along(0), cells_along(1));
        let cells = width * height;
        if cells.is_nan() || cells > limit {
            return Err(PipelineError::GridTooLarge {
                resolution: options.resolution_m,
                width,
                height,
                span_x: hi[0] - lo[0],
                span_y: hi[1] - lo[1],
                units: units_name(map.units),
                limit,
            });
        }
    }
    rasterize_map(
        map,
        &RasterOptions {
            resolution_m: options.resolution_m,
            robot_radius_m: options.robot_radius_m,
            hidden_free: options.hidden_free,
            margin_m: GRID_MARGIN_M,
        },
    )
    .map_err(PipelineError::Grid)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::fit::ellipse_95;

    /// Error bars with centroid covariance `c` (metres squared), a side's sd and a corner's.
    fn bars(c: [[f64; 2]; 2], side: Option<f64>, corner: Option<f64>) -> ObjectUncertainty {
        ObjectUncertainty {
            centroid_covariance: c,
            centroid_ellipse_95: ellipse_95([0.0, 0.0], c),
            corner_sd: corner,
            length_sd: side,
            breadth_sd: side,
            height_sd: None,
            yaw_deg: None,
            yaw_sd_deg: None,
        }
    }

    #[test]
    fn the_margin_holds_the_centroid_the_sides_and_the_least_certain_corner() {
        // k at 95 %: sqrt(5.991) = 2.448.
        let k = 5.991_464_547_107_979_f64.sqrt();
        // Centroid sd 0.02 m (the larger axis), sides 0.01 m: 0.025 m at one sigma.
        let c = [[0.02 * 0.02, 0.0], [0.0, 0.01 * 0.01]];
        let m = uncertainty_margin(&bars(c, Some(0.01), None), 0.95);
        assert!((m - k * 0.025).abs() < 1e-12, "{m}");
        // A corner known worse than that (a yaw turning a long box's far corner) decides.
        let m = uncertainty_margin(&bars(c, Some(0.01), Some(0.05)), 0.95);
        assert!((m - k * 0.05).abs() < 1e-12, "{m}");
        // A corner known better changes nothing; one not known at all is left to the rest.
        let m = uncertainty_margin(&bars(c, Some(0.01), Some(0.001)), 0.95);
        assert!((m - k * 0.025).abs() < 1e-12, "{m}");
        let m = uncertainty_margin(&bars(c, Some(0.01), Some(f64::NAN)), 0.95);
        assert!((m - k * 0.025).abs() < 1e-12, "{m}");
        // A footprint (no sides): its vertices' own uncertainty.
        let m = uncertainty_margin(&bars([[1e-6, 0.0], [0.0, 1e-6]], None, Some(0.03)), 0.95);
        assert!((m - k * 0.03).abs() < 1e-12, "{m}");
    }
}
