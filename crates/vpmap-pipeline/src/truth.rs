//! A synthetic scene's truth as an occupancy grid, for driving a robot against what a room
//! really is (`vpmap navigate`, the page's drive on the bundled example).

use vpmap_metrology::synth::Truth;
use vpmap_plan::grid::{Occupancy, OccupancyGrid};

use crate::error::PipelineError;

/// `truth` rasterised into `frame`'s grid (its size, resolution and origin; the truth's
/// coordinates are map metres, the frame of a map built from the truth's scene): a cell is
/// free when its centre lies on the floor outline and in no object's footprint (even-odd
/// rule), occupied otherwise; then inflated by `radius_m` like every planning grid.
///
/// # Errors
/// [`PipelineError::Grid`] when the inflation radius is invalid.
///
/// # Example
/// ```
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_pipeline::{map_and_grid, truth_grid, MapOptions};
/// let (scene, truth) = synthesize(&SynthOptions::default()).unwrap();
/// let belief = map_and_grid(&scene, &MapOptions::default()).unwrap().grid;
/// let true_grid = truth_grid(&truth, &belief, 0.2).unwrap();
/// assert_eq!((true_grid.width(), true_grid.height()), (belief.width(), belief.height()));
/// ```
pub fn truth_grid(
    truth: &Truth,
    frame: &OccupancyGrid,
    radius_m: f64,
) -> Result<OccupancyGrid, PipelineError> {
    let mut grid = OccupancyGrid::new(
        frame.width(),
        frame.height(),
        frame.resolution_m(),
        frame.origin_m(),
        Occupancy::Occupied,
    )
    .map_err(PipelineError::Grid)?;
    for y in 0..grid.height() {
        for x in 0..grid.width() {
            let p = grid.world_from_cell(x, y);
            let on_floor = inside(&truth.floor, p);
            let in_object = truth.objects.iter().any(|o| inside(&o.footprint, p));
            if on_floor && !in_object {
                grid.set(x, y, Occupancy::Free)
                    .map_err(PipelineError::Grid)?;
            }
        }
    }
    grid.inflate(radius_m).map_err(PipelineError::Grid)
}

/// Even-odd point-in-polygon test.
fn inside(polygon: &[[f64; 2]], p: [f64; 2]) -> bool {
    let mut odd = false;
    let n = polygon.len();
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                odd = !odd;
            }
        }
    }
    odd
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::synth::{TruthCamera, TruthObject};

    #[test]
    fn a_square_room_with_a_box_in_it() {
        // An independent count: a 4 x 4 m floor and a 1 x 1 m box, 0.5 m cells centred on
        // the quarter metres, no inflation.
        let truth = Truth {
            camera: TruthCamera {
                focal_px: 1000.0,
                principal_point: None,
                pitch_deg: 20.0,
                roll_deg: 0.0,
                height: 1.5,
            },
            objects: vec![TruthObject {
                name: "box".to_owned(),
                footprint: vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]],
                height: 1.0,
            }],
            floor: vec![[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]],
        };
        let frame = OccupancyGrid::new(10, 10, 0.5, [-0.5, -0.5], Occupancy::Unknown).unwrap();
        let grid = truth_grid(&truth, &frame, 0.0).unwrap();
        let free = grid
            .cells()
            .iter()
            .filter(|&&c| c == Occupancy::Free)
            .count();
        // 8 x 8 cells on the floor, 2 x 2 of them in the box.
        assert_eq!(free, 64 - 4);
    }
}
