//! Line of sight (`los`, an integer walk) against the validator (`validate`, the separating
//! axis theorem per cell): two independent implementations of one rule must agree exactly.

use std::collections::BTreeSet;

use proptest::prelude::*;
use rand::RngExt;
use vpmap_plan::los::{PassableGrid, visit_swept_cells};
use vpmap_plan::validate::swept_square_overlaps_cell;
use vpmap_plan::{
    LosCounter, Occupancy, OccupancyGrid, Passable, Traversable, line_of_sight,
    line_of_sight_counted, validate_path,
};

use crate::grids::{random_grid, small_grid};
use crate::rng;

/// A map from cells to cells (a mirror or a transposition).
type CellMap<'a> = dyn Fn(usize, usize) -> (usize, usize) + 'a;

fn grid_from_rows(rows: &[&str]) -> OccupancyGrid {
    let cells = rows
        .iter()
        .flat_map(|r| r.chars())
        .map(|c| match c {
            '#' => Occupancy::Occupied,
            '?' => Occupancy::Unknown,
            _ => Occupancy::Free,
        })
        .collect();
    OccupancyGrid::from_cells(rows[0].len(), rows.len(), 1.0, [0.0; 2], cells).unwrap()
}

fn clear_both_ways(grid: &OccupancyGrid, a: (usize, usize), b: (usize, usize)) -> bool {
    let forward = line_of_sight(grid, a, b);
    assert_eq!(forward, line_of_sight(grid, b, a), "{a:?} {b:?}");
    assert_eq!(
        forward,
        validate_path(grid, &[a.into(), b.into()], false).is_ok(),
        "los and validator disagree on {a:?} -> {b:?}"
    );
    forward
}

#[test]
fn swept_cells_equal_the_cells_the_validator_finds_overlapped() {
    let mut rng = rng(11);
    for _ in 0..4000 {
        let side = if rng.random_bool(0.5) { 6 } else { 40 };
        let a = (rng.random_range(0..side), rng.random_range(0..side));
        let b = (rng.random_range(0..side), rng.random_range(0..side));
        let mut walked = Vec::new();
        visit_swept_cells(a, b, |x, y| {
            walked.push((x, y));
            true
        });
        let walked_set: BTreeSet<_> = walked.iter().copied().collect();
        assert_eq!(
            walked_set.len(),
            walked.len(),
            "{a:?} -> {b:?} repeats a cell"
        );
        let (a, b) = ((a.0 as i64, a.1 as i64), (b.0 as i64, b.1 as i64));
        let mut overlapped = BTreeSet::new();
        for y in a.1.min(b.1) - 2..=a.1.max(b.1) + 2 {
            for x in a.0.min(b.0) - 2..=a.0.max(b.0) + 2 {
                if swept_square_overlaps_cell(a, b, (x, y)) {
                    overlapped.insert((x, y));
                }
            }
        }
        assert_eq!(walked_set, overlapped, "{a:?} -> {b:?}");
    }
}

#[test]
fn los_and_validator_agree_on_random_grids() {
    let mut rng = rng(7);
    let (mut clear, mut blocked) = (0, 0);
    for _ in 0..300 {
        let (w, h) = (rng.random_range(1..=24), rng.random_range(1..=24));
        let occupied = rng.random_range(0.0..0.35);
        let grid = random_grid(&mut rng, w, h, occupied, 0.05);
        for _ in 0..60 {
            let a = (rng.random_range(0..w), rng.random_range(0..h));
            let b = (rng.random_range(0..w), rng.random_range(0..h));
            for unknown_passable in [false, true] {
                let map = Traversable::new(&grid, unknown_passable);
                let los = line_of_sight(&map, a, b);
                let valid = validate_path(&grid, &[a.into(), b.into()], unknown_passable);
                assert_eq!(los, valid.is_ok(), "{a:?} -> {b:?}: {valid:?}\n{grid:?}");
                if los {
                    clear += 1;
                } else {
                    blocked += 1;
                }
            }
        }
    }
    println!("los/validator agreement: {clear} clear, {blocked} blocked segments");
    assert!(
        clear > 5000 && blocked > 5000,
        "{clear} clear, {blocked} blocked"
    );
}

#[test]
fn single_steps_follow_the_no_corner_cutting_rule_exhaustively() {
    // Every free/occupied pattern of the 8 neighbours of a free centre cell.
    const MOVES: [(i64, i64); 8] = [
        (1, 0),
        (1, 1),
        (0, 1),
        (-1, 1),
        (-1, 0),
        (-1, -1),
        (0, -1),
        (1, -1),
    ];
    for pattern in 0u32..256 {
        let mut grid = OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        let blocked = |dx: i64, dy: i64| {
            let i = MOVES.iter().position(|&m| m == (dx, dy)).unwrap();
            pattern & (1 << i) != 0
        };
        for &(dx, dy) in &MOVES {
            if blocked(dx, dy) {
                grid.set((1 + dx) as usize, (1 + dy) as usize, Occupancy::Occupied)
                    .unwrap();
            }
        }
        for &(dx, dy) in &MOVES {
            let expected =
                !blocked(dx, dy) && (dx == 0 || dy == 0 || (!blocked(dx, 0) && !blocked(0, dy)));
            let target = ((1 + dx) as usize, (1 + dy) as usize);
            assert_eq!(
                clear_both_ways(&grid, (1, 1), target),
                expected,
                "pattern {pattern:08b}, move ({dx}, {dy})"
            );
        }
    }
}

#[test]
fn diagonal_squeeze_between_two_blocked_cells_is_blocked() {
    let grid = grid_from_rows(&[".#", "#."]);
    assert!(!clear_both_ways(&grid, (0, 0), (1, 1)));
    let grid = grid_from_rows(&["..", ".."]);
    assert!(clear_both_ways(&grid, (0, 0), (1, 1)));
    assert!(clear_both_ways(&grid, (1, 0), (0, 1)));
    let grid = grid_from_rows(&["#.", ".#"]);
    assert!(!clear_both_ways(&grid, (1, 0), (0, 1)));
    // One blocked orthogonal neighbour is enough to block a diagonal step.
    let grid = grid_from_rows(&["..", "#."]);
    assert!(!clear_both_ways(&grid, (0, 0), (1, 1)));
}

#[test]
fn touching_a_corner_is_allowed_overlapping_is_not() {
    let grid = grid_from_rows(&["..#", "...", "#.."]);
    assert!(clear_both_ways(&grid, (0, 0), (2, 2)));
    let grid = grid_from_rows(&[".#.", "...", "..."]);
    assert!(!clear_both_ways(&grid, (0, 0), (2, 2)));
    // A knight's move sweeps the whole 3 x 2 block.
    for blocked in [(1, 0), (2, 0), (0, 1), (1, 1)] {
        let mut grid = OccupancyGrid::new(3, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
        grid.set(blocked.0, blocked.1, Occupancy::Occupied).unwrap();
        assert!(!clear_both_ways(&grid, (0, 0), (2, 1)), "{blocked:?}");
    }
}

#[test]
fn axis_aligned_segments_slide_along_blocked_neighbours() {
    let grid = grid_from_rows(&["##########", "..........", "##########"]);
    assert!(clear_both_ways(&grid, (0, 1), (9, 1)));
    let grid = grid_from_rows(&["#.#", "#.#", "#.#", "#.#"]);
    assert!(clear_both_ways(&grid, (1, 0), (1, 3)));
    let grid = grid_from_rows(&["....", "....", "..#.", "...."]);
    assert!(!clear_both_ways(&grid, (2, 0), (2, 3)));
}

#[test]
fn long_shallow_lines_are_exact_at_the_touching_corners() {
    // Segment from (0, 0) to (100, 2): the swept square leaves row 0 after column 50 and
    // enters row 2 from column 50; cells (49, 2) and (51, 0) are touched at a corner only.
    let free = OccupancyGrid::new(101, 3, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let with = |cells: &[(usize, usize)]| {
        let mut g = free.clone();
        for &(x, y) in cells {
            g.set(x, y, Occupancy::Occupied).unwrap();
        }
        g
    };
    assert!(clear_both_ways(&free, (0, 0), (100, 2)));
    assert!(clear_both_ways(
        &with(&[(49, 2), (51, 0)]),
        (0, 0),
        (100, 2)
    ));
    assert!(!clear_both_ways(&with(&[(50, 2)]), (0, 0), (100, 2)));
    assert!(!clear_both_ways(&with(&[(50, 0)]), (0, 0), (100, 2)));
    assert!(!clear_both_ways(&with(&[(0, 1)]), (0, 0), (100, 2)));
    // Slope 1/100: the square enters row 1 at once.
    assert!(!clear_both_ways(&with(&[(0, 1)]), (0, 0), (100, 1)));
    assert!(clear_both_ways(
        &with(&[(0, 2), (100, 2)]),
        (0, 0),
        (100, 1)
    ));
    // The same, steep and mirrored.
    let tall = OccupancyGrid::new(3, 101, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let mut g = tall.clone();
    g.set(0, 49, Occupancy::Occupied).unwrap();
    g.set(2, 51, Occupancy::Occupied).unwrap();
    assert!(clear_both_ways(&g, (2, 0), (0, 100)));
    g.set(2, 50, Occupancy::Occupied).unwrap();
    assert!(!clear_both_ways(&g, (2, 0), (0, 100)));
}

#[test]
fn blocked_unknown_and_outside_end_cells() {
    let grid = grid_from_rows(&[".?#", "..."]);
    assert!(line_of_sight(&grid, (0, 0), (0, 0)));
    assert!(!line_of_sight(&grid, (2, 0), (2, 0)));
    assert!(!line_of_sight(&grid, (0, 0), (1, 0)));
    assert!(line_of_sight(
        &Traversable::new(&grid, true),
        (0, 0),
        (1, 0)
    ));
    assert!(!line_of_sight(&grid, (0, 0), (3, 0)));
    assert!(!line_of_sight(&grid, (0, 0), (0, 2)));
    let mut counter = LosCounter::default();
    assert!(line_of_sight_counted(&grid, (0, 1), (2, 1), &mut counter));
    assert!(!line_of_sight_counted(&grid, (0, 1), (2, 0), &mut counter));
    assert_eq!(counter.checks, 2);
    assert!(counter.cells >= 4);
}

#[test]
fn los_is_invariant_under_mirroring_and_transposing_the_grid() {
    let mut rng = rng(3);
    for _ in 0..100 {
        let (w, h) = (rng.random_range(1..=16), rng.random_range(1..=16));
        let grid = random_grid(&mut rng, w, h, 0.2, 0.0);
        let transform = |f: &CellMap<'_>, tw: usize, th: usize| {
            let mut g = OccupancyGrid::new(tw, th, 1.0, [0.0; 2], Occupancy::Free).unwrap();
            for y in 0..h {
                for x in 0..w {
                    let (u, v) = f(x, y);
                    g.set(u, v, grid.get(x, y).unwrap()).unwrap();
                }
            }
            g
        };
        let mirror_x = |x: usize, y: usize| (w - 1 - x, y);
        let mirror_y = |x: usize, y: usize| (x, h - 1 - y);
        let transpose = |x: usize, y: usize| (y, x);
        let variants: [(&CellMap<'_>, usize, usize); 3] =
            [(&mirror_x, w, h), (&mirror_y, w, h), (&transpose, h, w)];
        for (f, tw, th) in variants {
            let g = transform(f, tw, th);
            for _ in 0..30 {
                let a = (rng.random_range(0..w), rng.random_range(0..h));
                let b = (rng.random_range(0..w), rng.random_range(0..h));
                assert_eq!(
                    line_of_sight(&grid, a, b),
                    line_of_sight(&g, f(a.0, a.1), f(b.0, b.1))
                );
            }
        }
    }
}

/// A cell of a `width x height` grid or up to `margin` cells outside it.
fn cell_around(width: usize, height: usize, margin: i64) -> impl Strategy<Value = (i64, i64)> {
    (
        -margin..width as i64 + margin,
        -margin..height as i64 + margin,
    )
}

/// A grid with two cells in or near it; near enough that most segments touch the border.
fn grid_and_segment() -> impl Strategy<Value = (OccupancyGrid, (i64, i64), (i64, i64), i64)> {
    (small_grid(24), 1..=3i64).prop_flat_map(|(grid, margin)| {
        let (w, h) = (grid.width(), grid.height());
        (
            Just(grid),
            cell_around(w, h, margin),
            cell_around(w, h, margin),
            Just(margin),
        )
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// The fast walk of `PassableGrid` against the reference `visit_swept_cells` asking a
    /// `Traversable`: same answer, same cells looked up in the same order (so the same
    /// counts), for unknown cells passable or not and for end cells outside the grid
    /// (the reference is translation invariant, so it walks the segment shifted into
    /// non-negative coordinates).
    #[test]
    fn passable_grid_walks_the_reference_cells((grid, a, b, margin) in grid_and_segment()) {
        for unknown_passable in [false, true] {
            let reference = Traversable::new(&grid, unknown_passable);
            let shift = |(x, y): (i64, i64)| ((x + margin) as usize, (y + margin) as usize);
            let mut expected = Vec::new();
            let expected_clear = visit_swept_cells(shift(a), shift(b), |x, y| {
                let cell = (x - margin, y - margin);
                expected.push(cell);
                reference.passable(cell.0, cell.1)
            });
            let view = PassableGrid::new(&grid, unknown_passable);
            let mut walked = Vec::new();
            let mut counter = LosCounter::default();
            let clear = view.sight_traced(a, b, &mut counter, |x, y| walked.push((x, y)));
            prop_assert_eq!(clear, expected_clear, "{:?} -> {:?}", a, b);
            prop_assert_eq!(&walked, &expected, "{:?} -> {:?}", a, b);
            prop_assert_eq!(counter, LosCounter { checks: 1, cells: expected.len() });
            let mut untraced = LosCounter::default();
            prop_assert_eq!(view.sight(a, b, &mut untraced), clear);
            prop_assert_eq!(untraced, counter);
            if a.0 >= 0 && a.1 >= 0 && b.0 >= 0 && b.1 >= 0 {
                let (ua, ub) = ((a.0 as usize, a.1 as usize), (b.0 as usize, b.1 as usize));
                let mut slow = LosCounter::default();
                prop_assert_eq!(line_of_sight_counted(&reference, ua, ub, &mut slow), clear);
                prop_assert_eq!(slow, counter);
                prop_assert_eq!(line_of_sight(&view, ua, ub), clear);
            }
            for x in -margin..grid.width() as i64 + margin {
                for y in -margin..grid.height() as i64 + margin {
                    prop_assert_eq!(view.passable(x, y), reference.passable(x, y));
                }
            }
        }
    }

    /// Single steps from a passable cell that `PassableGrid::step_clear` allows are
    /// exactly the one-cell segments in line of sight (the movement rule of A*, Theta* and
    /// MBPP's bugs agrees with the collision rule).
    #[test]
    fn step_clear_is_one_cell_line_of_sight(
        (grid, a, _, _) in grid_and_segment(),
        unknown_passable in any::<bool>(),
    ) {
        let view = PassableGrid::new(&grid, unknown_passable);
        for dx in -1..=1 {
            for dy in -1..=1 {
                let b = (a.0 + dx, a.1 + dy);
                let legal = view.passable(a.0, a.1) && view.step_clear(a, (dx, dy));
                let clear = view.sight(a, b, &mut LosCounter::default());
                prop_assert_eq!(legal, clear, "{:?} by {:?}", a, (dx, dy));
            }
        }
    }
}

/// The box index (`PassableGrid::index_boxes`) changes how a segment is checked, never the
/// answer: on seeded grids from nearly empty to half blocked, up to 90 cells a side (so that
/// boxes are proved free, halved and walked), every segment between random cells, the
/// border included, is clear with the index exactly when the reference walk says so, also
/// after `rebuild` on another grid, and when the index is built only once it pays. Open
/// space costs a few look-ups, not its length.
#[test]
fn the_box_index_gives_the_reference_answers() {
    let mut rng = rng(4040);
    let mut segments = 0;
    for (round, &occupied) in [0.0, 0.002, 0.01, 0.05, 0.2, 0.5]
        .iter()
        .cycle()
        .take(48)
        .enumerate()
    {
        let (w, h) = (rng.random_range(1..=90), rng.random_range(1..=90));
        let grid = random_grid(&mut rng, w, h, occupied, 0.05);
        let unknown_passable = round % 2 == 0;
        let reference = Traversable::new(&grid, unknown_passable);
        let mut boxed = PassableGrid::new(
            &OccupancyGrid::new(3, 3, 1.0, [0.0; 2], Occupancy::Occupied).unwrap(),
            false,
        );
        boxed.index_boxes();
        boxed.rebuild(&grid, unknown_passable);
        // Built once the walks have looked up as many cells as the grid has (a few
        // segments on these grids): the first answers walked, the later ones by boxes.
        let mut lazy = PassableGrid::new(&grid, unknown_passable);
        lazy.index_boxes_when_worth_it();
        for _ in 0..400 {
            let a = (
                rng.random_range(-1..=w as i64),
                rng.random_range(-1..=h as i64),
            );
            let b = (
                rng.random_range(-1..=w as i64),
                rng.random_range(-1..=h as i64),
            );
            let shift = |(x, y): (i64, i64)| ((x + 1) as usize, (y + 1) as usize);
            let expected =
                visit_swept_cells(shift(a), shift(b), |x, y| reference.passable(x - 1, y - 1));
            let mut counter = LosCounter::default();
            assert_eq!(
                boxed.sight(a, b, &mut counter),
                expected,
                "{w}x{h} at {occupied}: {a:?} -> {b:?}"
            );
            assert_eq!(counter.checks, 1);
            assert_eq!(lazy.sight(a, b, &mut LosCounter::default()), expected);
            segments += 1;
        }
    }
    assert_eq!(segments, 48 * 400);
    // An empty 1000-cell row: four look-ups instead of 1000.
    let open = OccupancyGrid::new(1000, 2, 1.0, [0.0; 2], Occupancy::Free).unwrap();
    let mut boxed = PassableGrid::new(&open, false);
    boxed.index_boxes();
    let mut counter = LosCounter::default();
    assert!(boxed.sight((0, 0), (999, 1), &mut counter));
    assert_eq!(counter.cells, 4);
}
