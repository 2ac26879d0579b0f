//! Dead-end pruning (Polyanya's, Cui et al. 2017 section 5): the table of the rectangles
//! through which a search would enter a region whose only way out is the row line it came in
//! by (built once per grid with the free space, [`super::space`]), and the test the search
//! asks before entering a rectangle.

/// [`dead_ends`]' "not a dead end".
pub(super) const NOT_DEAD: i32 = i32::MIN;

/// Per strip and rectangle, `[up, down]`: the last row of the dead end entered through the
/// rectangle upwards (downwards), or [`NOT_DEAD`]. Upwards, rectangle `[a, b]` of strip `s`
/// is a dead end when the run of row `s + 1` over it is exactly `[a, b]` (no way sideways)
/// and strip `s + 1` has no rectangle over it (the dead end ends at row `s + 1`) or exactly
/// one, itself a dead end upwards (the dead end ends where that one's does). Downwards the
/// same, mirrored.
pub(super) fn dead_ends(
    runs: &[Vec<(i32, i32)>],
    strips: &[Vec<(i32, i32)>],
) -> Vec<Vec<[i32; 2]>> {
    let mut dead: Vec<Vec<[i32; 2]>> = strips
        .iter()
        .map(|rects| vec![[NOT_DEAD; 2]; rects.len()])
        .collect();
    let over = |strip: usize, a: i32, b: i32| -> Option<std::ops::Range<usize>> {
        let rects = strips.get(strip)?;
        let first = rects.partition_point(|&(_, rb)| rb < a);
        let end = rects.partition_point(|&(ra, _)| ra <= b);
        Some(first..end.max(first))
    };
    let exact_run = |row: usize, a: i32, b: i32| {
        runs.get(row)
            .is_some_and(|r| r.get(r.partition_point(|&(_, rb)| rb < a)) == Some(&(a, b)))
    };
    let n = strips.len();
    for (side, order) in [(0, true), (1, false)] {
        for k in 0..n {
            // Upwards from the top strip down; downwards from the bottom strip up.
            let s = if order { n - 1 - k } else { k };
            let (far_row, next) = if side == 0 {
                (s + 1, s.checked_add(1).filter(|&t| t < n))
            } else {
                (s, s.checked_sub(1))
            };
            let Some(rects) = strips.get(s) else { continue };
            for (i, &(a, b)) in rects.iter().enumerate() {
                if !exact_run(far_row, a, b) {
                    continue;
                }
                let until = match next.and_then(|t| Some((t, over(t, a, b)?))) {
                    None => Some(far_row as i32),
                    Some((_, range)) if range.is_empty() => Some(far_row as i32),
                    Some((t, range)) if range.len() == 1 => dead
                        .get(t)
                        .and_then(|d| d.get(range.start))
                        .map(|d| d[side])
                        .filter(|&u| u != NOT_DEAD),
                    Some(_) => None,
                };
                if let Some(until) = until
                    && let Some(slot) = dead.get_mut(s).and_then(|d| d.get_mut(i))
                {
                    slot[side] = until;
                }
            }
        }
    }
    dead
}

/// Whether entering rectangle `index` of strip `strip` (of `strips`, with the table `dead`
/// of [`dead_ends`]) in direction `dir` leads into a dead end that does not hold `goal`: a
/// region of the free space whose only way out is the row line the rectangle was entered
/// from. A path that crosses that row line into the region and comes back crosses it twice,
/// at `p` and `q`, and the segment `pq` along the (free, convex) crossing is no longer, so a
/// shortest path to a goal outside never enters (Polyanya's dead-end pruning, Cui et al.
/// 2017 section 5). The region lies in the rectangle's columns, so that is where the goal is
/// looked for.
pub(super) fn enters_dead_end(
    strips: &[Vec<(i32, i32)>],
    dead: &[Vec<[i32; 2]>],
    strip: i32,
    index: usize,
    dir: i32,
    goal: (i32, i32),
) -> bool {
    let Some(s) = usize::try_from(strip).ok() else {
        return false;
    };
    let (Some(&(a, b)), Some(&[up, down])) = (
        strips.get(s).and_then(|r| r.get(index)),
        dead.get(s).and_then(|d| d.get(index)),
    ) else {
        return false;
    };
    let (gx, gy) = goal;
    let in_columns = a <= gx && gx <= b;
    if dir > 0 {
        up != NOT_DEAD && !(in_columns && strip < gy && gy <= up)
    } else {
        down != NOT_DEAD && !(in_columns && down <= gy && gy <= strip)
    }
}
