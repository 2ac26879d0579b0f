//! York Urban's snapped points grouped by how much of their edges the photo does not show
//! next to the corner: the evidence behind the covariance's unseen term
//! ([`vpmap_vision::snap::SnapOptions::unseen_sd_per_px`]), with and without it.

use std::fmt::Write as _;

use super::yud::{YudClick, inside_95};
use crate::stats::median;

/// Groups of about equal size, by the larger unseen stretch of a snapped point's two edges.
const GROUPS: usize = 6;

/// The Markdown paragraph and table: per group, the range of the larger of the two edges'
/// gaps to the corner ([`vpmap_vision::snap::SnapEdge::gap_px`]), the snapped points' median
/// distance to the labelled corner, and the share whose labelled corner lies in their 95 %
/// ellipse (the labels' error of `label_sd_px` per line added) with the covariance as
/// reported and with its unseen term (`unseen_sd_per_px` squared times the edges' squared
/// [`vpmap_vision::snap::SnapEdge::unseen_px`], on each axis) taken out. Empty without
/// snapped points.
pub(super) fn by_unseen_stretch(
    snapped: &[&YudClick],
    label_sd_px: f64,
    unseen_sd_per_px: f64,
) -> String {
    let mut rows: Vec<(f64, &YudClick)> = snapped
        .iter()
        .filter_map(|c| {
            let gap = c.edges.iter().map(|e| e.gap_px).fold(0.0, f64::max);
            c.covariance_px2.map(|_| (gap, *c))
        })
        .collect();
    if rows.is_empty() {
        return String::new();
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut s = String::new();
    let _ = writeln!(
        s,
        "\nThe snapped points in {GROUPS} groups of about equal size by the larger of their two edges' gaps to the corner (the distance from the corner to the nearest point where the edge was seen); the corner inside the 95 % ellipse (labels' error added) as reported, and with the covariance's unseen term ({unseen_sd_per_px} px a pixel of edge the blur does not explain) taken out:\n"
    );
    let _ = writeln!(
        s,
        "| gap to the corner | snapped points | median distance to the corner | in the 95 % ellipse | without the unseen term |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|");
    let size = rows.len().div_ceil(GROUPS);
    for group in rows.chunks(size) {
        let (Some(first), Some(last)) = (group.first(), group.last()) else {
            continue;
        };
        let inside = |take_out: bool| {
            let count = group
                .iter()
                .filter(|(_, c)| {
                    let term = if take_out {
                        unseen_sd_per_px.powi(2)
                            * c.edges.iter().map(|e| e.unseen_px.powi(2)).sum::<f64>()
                    } else {
                        0.0
                    };
                    inside_95(c, label_sd_px, -term) == Some(true)
                })
                .count();
            format!("{:.1} %", 100.0 * count as f64 / group.len() as f64)
        };
        let distances: Vec<f64> = group.iter().map(|(_, c)| c.error_px).collect();
        let _ = writeln!(
            s,
            "| {:.1}-{:.1} px | {} | {} | {} | {} |",
            first.0,
            last.0,
            group.len(),
            median(&distances).map_or_else(|| "-".to_owned(), |m| format!("{m:.2} px")),
            inside(false),
            inside(true),
        );
    }
    s
}

#[cfg(test)]
#[allow(clippy::unwrap_used, clippy::indexing_slicing)]
mod tests {
    use vpmap_vision::snap::{EdgeDirection, SnapEdge};

    use super::*;
    use crate::clicks::yud::test_click;

    /// A snapped click 2 px off its labelled corner whose edges stop `unseen_px` beyond the
    /// blur, its covariance a 0.4 px floor plus the unseen term.
    fn click(unseen_px: f64, kappa: f64) -> YudClick {
        let edge = |direction_px| SnapEdge {
            direction: EdgeDirection::VanishingPoint(0),
            point_px: [10.0, 10.0],
            direction_px,
            support_px: 12.0,
            gradient: 20.0,
            rms_px: 0.1,
            gap_px: unseen_px + 3.0,
            unseen_px,
        };
        let variance = 0.16 + 2.0 * (kappa * unseen_px).powi(2);
        YudClick {
            raw_error_px: 2.5,
            error_px: 2.0,
            snapped: true,
            sd_px: Some(variance.sqrt()),
            covariance_px2: Some([[variance, 0.0], [0.0, variance]]),
            error_vec_px: [2.0, 0.0],
            label_offsets_px: [Some(0.0); 2],
            edges: vec![edge([1.0, 0.0]), edge([0.0, 1.0])],
            ..test_click()
        }
    }

    #[test]
    fn the_unseen_term_is_taken_out_exactly_where_the_edges_were_not_seen() {
        // Seen to the corner: 2 px off a 0.4 px floor and 0.1 px labels is far outside, with
        // or without the term (there is none). 4 px unseen at 0.3 px a pixel: inside as
        // reported (sd 1.7 px), outside once the term is taken out.
        let (seen, unseen) = (click(0.0, 0.3), click(4.0, 0.3));
        let table = by_unseen_stretch(&[&seen, &unseen], 0.1, 0.3);
        let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| 3.0")).collect();
        assert_eq!(
            rows,
            ["| 3.0-3.0 px | 1 | 2.00 px | 0.0 % | 0.0 % |"],
            "{table}"
        );
        let rows: Vec<&str> = table.lines().filter(|l| l.starts_with("| 7.0")).collect();
        assert_eq!(
            rows,
            ["| 7.0-7.0 px | 1 | 2.00 px | 100.0 % | 0.0 % |"],
            "{table}"
        );
        assert_eq!(by_unseen_stretch(&[], 0.1, 0.3), "");
    }
}
