//! The random test grids every test module draws from, seeded: proptest strategies
//! ([`small_grid`]), uniform random grids ([`random_grid`]) and grids of seven kinds (open,
//! cluttered, rooms, maze, u-trap, spiral, diagonal walls with gaps: [`generate`]), with
//! their traversable cells.

use proptest::prelude::*;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;
use vpmap_plan::{Occupancy, OccupancyGrid, Passable, Traversable};

/// Any cell state.
pub(crate) fn any_cell() -> impl Strategy<Value = Occupancy> {
    prop_oneof![
        Just(Occupancy::Free),
        Just(Occupancy::Occupied),
        Just(Occupancy::Unknown)
    ]
}

/// Small random grids with random frames.
pub(crate) fn small_grid(max_side: usize) -> impl Strategy<Value = OccupancyGrid> {
    (1..=max_side, 1..=max_side).prop_flat_map(|(w, h)| {
        (
            proptest::collection::vec(any_cell(), w * h),
            0.001f64..10.0,
            -100.0f64..100.0,
            -100.0f64..100.0,
        )
            .prop_map(move |(cells, res, ox, oy)| {
                OccupancyGrid::from_cells(w, h, res, [ox, oy], cells).unwrap()
            })
    })
}

/// A `width x height` grid, resolution 1, each cell occupied with probability `occupied`,
/// else unknown with probability `unknown`, else free.
pub(crate) fn random_grid(
    rng: &mut ChaCha8Rng,
    width: usize,
    height: usize,
    occupied: f64,
    unknown: f64,
) -> OccupancyGrid {
    let cells = (0..width * height)
        .map(|_| {
            let r: f64 = rng.random();
            if r < occupied {
                Occupancy::Occupied
            } else if r < occupied + unknown {
                Occupancy::Unknown
            } else {
                Occupancy::Free
            }
        })
        .collect();
    OccupancyGrid::from_cells(width, height, 1.0, [0.0; 2], cells).unwrap()
}

/// The kinds of generated grids.
pub(crate) const KINDS: [&str; 7] = [
    "open",
    "cluttered",
    "rooms",
    "maze",
    "u-trap",
    "spiral",
    "diagonal-gaps",
];

pub(crate) fn grid_of(width: usize, height: usize, cell: Occupancy) -> OccupancyGrid {
    OccupancyGrid::new(width, height, 1.0, [0.0; 2], cell).unwrap()
}

fn block(grid: &mut OccupancyGrid, x: i64, y: i64) {
    if let (Ok(x), Ok(y)) = (usize::try_from(x), usize::try_from(y)) {
        let _ = grid.set(x, y, Occupancy::Occupied);
    }
}

fn clear(grid: &mut OccupancyGrid, x: i64, y: i64) {
    if let (Ok(x), Ok(y)) = (usize::try_from(x), usize::try_from(y)) {
        let _ = grid.set(x, y, Occupancy::Free);
    }
}

/// A random grid of `kind`, at most `max_side` cells a side (at least 3), and whether its
/// unknown cells are passable.
pub(crate) fn generate(rng: &mut ChaCha8Rng, kind: &str, max_side: usize) -> (OccupancyGrid, bool) {
    let min_side = if matches!(kind, "spiral" | "maze") {
        6
    } else {
        3
    };
    let w = rng.random_range(min_side..=max_side);
    let h = rng.random_range(min_side..=max_side);
    let (wi, hi) = (w as i64, h as i64);
    let mut unknown_passable = false;
    let grid = match kind {
        "open" => {
            let mut g = grid_of(w, h, Occupancy::Free);
            for _ in 0..rng.random_range(0..=2) {
                block(&mut g, rng.random_range(0..wi), rng.random_range(0..hi));
            }
            g
        }
        "cluttered" => {
            let occupied = rng.random_range(0.1..0.4);
            let unknown = rng.random_range(0.0..0.1);
            unknown_passable = rng.random_bool(0.5);
            random_grid(rng, w, h, occupied, unknown)
        }
        "rooms" => {
            let mut g = grid_of(w, h, Occupancy::Free);
            let k = rng.random_range(3..=5);
            for x in (k..wi).step_by(k as usize) {
                for y in 0..hi {
                    block(&mut g, x, y);
                }
            }
            for y in (k..hi).step_by(k as usize) {
                for x in 0..wi {
                    block(&mut g, x, y);
                }
            }
            // A door in each wall piece between junctions (sometimes none).
            for x in (k..wi).step_by(k as usize) {
                for y0 in (0..hi).step_by(k as usize) {
                    if rng.random_bool(0.85) {
                        let y = y0 + rng.random_range(0..k - 1).min(hi - 1 - y0);
                        clear(&mut g, x, y);
                    }
                }
            }
            for y in (k..hi).step_by(k as usize) {
                for x0 in (0..wi).step_by(k as usize) {
                    if rng.random_bool(0.85) {
                        let x = x0 + rng.random_range(0..k - 1).min(wi - 1 - x0);
                        clear(&mut g, x, y);
                    }
                }
            }
            g
        }
        "maze" => {
            // Recursive backtracker on the odd cells, sometimes with a few walls knocked out.
            let mut g = grid_of(w, h, Occupancy::Occupied);
            let (cw, ch) = ((wi - 1) / 2, (hi - 1) / 2);
            let mut seen = vec![false; (cw * ch) as usize];
            let mut stack = vec![(0i64, 0i64)];
            seen[0] = true;
            clear(&mut g, 1, 1);
            while let Some(&(cx, cy)) = stack.last() {
                let options: Vec<(i64, i64)> = [(1, 0), (-1, 0), (0, 1), (0, -1)]
                    .into_iter()
                    .map(|(dx, dy)| (cx + dx, cy + dy))
                    .filter(|&(nx, ny)| {
                        (0..cw).contains(&nx)
                            && (0..ch).contains(&ny)
                            && !seen[(ny * cw + nx) as usize]
                    })
                    .collect();
                if options.is_empty() {
                    stack.pop();
                    continue;
                }
                let (nx, ny) = options[rng.random_range(0..options.len())];
                seen[(ny * cw + nx) as usize] = true;
                clear(&mut g, 2 * nx + 1, 2 * ny + 1);
                clear(&mut g, cx + nx + 1, cy + ny + 1);
                stack.push((nx, ny));
            }
            for _ in 0..rng.random_range(0..=2) {
                clear(&mut g, rng.random_range(0..wi), rng.random_range(0..hi));
            }
            g
        }
        "u-trap" => {
            let mut g = grid_of(w, h, Occupancy::Free);
            for _ in 0..rng.random_range(1..=2) {
                let (x0, y0) = (rng.random_range(0..wi), rng.random_range(0..hi));
                let (x1, y1) = (
                    (x0 + rng.random_range(2..=5)).min(wi - 1),
                    (y0 + rng.random_range(2..=5)).min(hi - 1),
                );
                let open_side = rng.random_range(0..4);
                for x in x0..=x1 {
                    if open_side != 0 {
                        block(&mut g, x, y0);
                    }
                    if open_side != 1 {
                        block(&mut g, x, y1);
                    }
                }
                for y in y0..=y1 {
                    if open_side != 2 {
                        block(&mut g, x0, y);
                    }
                    if open_side != 3 {
                        block(&mut g, x1, y);
                    }
                }
            }
            g
        }
        "spiral" => {
            // Concentric square walls two cells apart, each with one gap on an alternating
            // side.
            let mut g = grid_of(w, h, Occupancy::Free);
            let mut ring = 1;
            while 2 * ring < wi.min(hi) - 1 {
                let (x0, y0, x1, y1) = (ring, ring, wi - 1 - ring, hi - 1 - ring);
                for x in x0..=x1 {
                    block(&mut g, x, y0);
                    block(&mut g, x, y1);
                }
                for y in y0..=y1 {
                    block(&mut g, x0, y);
                    block(&mut g, x1, y);
                }
                match ring % 4 {
                    0 => clear(&mut g, x0, y0.midpoint(y1)),
                    1 => clear(&mut g, x0.midpoint(x1), y0),
                    2 => clear(&mut g, x1, y0.midpoint(y1)),
                    _ => clear(&mut g, x0.midpoint(x1), y1),
                }
                ring += 2;
            }
            g
        }
        _ => {
            // Diagonal walls (impassable without corner cutting) with one-cell gaps and
            // cells touching at corners.
            let mut g = grid_of(w, h, Occupancy::Free);
            for _ in 0..rng.random_range(1..=3) {
                let c = rng.random_range(1..wi + hi - 2);
                let rising = rng.random_bool(0.5);
                let x_at = |y: i64| if rising { c - y } else { c + y - (hi - 1) };
                for y in 0..hi {
                    block(&mut g, x_at(y), y);
                }
                for _ in 0..rng.random_range(0..=2) {
                    let y = rng.random_range(0..hi);
                    clear(&mut g, x_at(y), y);
                }
            }
            for _ in 0..rng.random_range(0..=3) {
                block(&mut g, rng.random_range(0..wi), rng.random_range(0..hi));
            }
            g
        }
    };
    (grid, unknown_passable)
}

/// The traversable cells of a grid.
pub(crate) fn traversable_cells(
    grid: &OccupancyGrid,
    unknown_passable: bool,
) -> Vec<(usize, usize)> {
    let passable = Traversable::new(grid, unknown_passable);
    let mut cells = Vec::new();
    for y in 0..grid.height() {
        for x in 0..grid.width() {
            if passable.passable(x as i64, y as i64) {
                cells.push((x, y));
            }
        }
    }
    cells
}
