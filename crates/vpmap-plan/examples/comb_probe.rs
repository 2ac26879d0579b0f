//! Throwaway probe: MBPP on the 300 x 300 comb.
#![allow(missing_docs, clippy::unwrap_used)]
use std::time::Instant;
use vpmap_plan::mbpp::{LeaveRule, MbppOptions, mbpp};
use vpmap_plan::{Occupancy, OccupancyGrid};

fn main() {
    let (w, h) = (300usize, 300usize);
    let mut grid = OccupancyGrid::new(w, h, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    for (k, y) in (2..h - 2).step_by(3).enumerate() {
        for x in 0..w {
            let gap = if k % 2 == 0 { x == w - 2 } else { x == 1 };
            if !gap {
                grid.set(x, y, Occupancy::Occupied).unwrap();
            }
        }
    }
    for leave in [LeaveRule::MLine, LeaveRule::Closer] {
        let opts = MbppOptions { leave, max_sight_cells: usize::MAX, max_bug_steps: usize::MAX, ..MbppOptions::default() };
        let t = Instant::now();
        let r = mbpp(&grid, (150, 0), (150, 299), &opts);
        let dt = t.elapsed();
        match r {
            Ok(p) => {
                let best = p.best.as_ref().unwrap();
                println!("{leave:?} {:.2}s {:?} len {} wps {} alts {}", dt.as_secs_f64(), p.mbpp_stats, best.length_cells, best.waypoints.len(), p.alternatives.len());
            }
            Err(e) => println!("{leave:?} {:.2}s {e}", dt.as_secs_f64()),
        }
    }
}
