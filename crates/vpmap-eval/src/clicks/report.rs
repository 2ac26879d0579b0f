//! The report of `vpmap eval-clicks`: Markdown tables per noise level, and the section of
//! `docs/results.md`.

use std::fmt::Write as _;
use std::time::Duration;

use vpmap_vision::synthetic::photo::CornerKind;

use super::{Config, EdgeQuality, Results, inside_by_quarter};
use crate::stats::{median, quantile_of};

/// The name of the section `--publish` writes.
pub const CLICKS_SECTION: &str = "eval-clicks";

/// The name of the section `--cluttered --publish` writes.
pub const CLUTTERED_SECTION: &str = "eval-clicks-cluttered";

fn pct(part: usize, whole: usize) -> String {
    if whole == 0 {
        "-".to_owned()
    } else {
        format!("{:.1} %", 100.0 * part as f64 / whole as f64)
    }
}

fn num(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_owned(), |v| format!("{v:.digits$}"))
}

/// The report's tables (no title).
#[must_use]
pub fn summary_markdown(config: &Config, results: &Results) -> String {
    let mut s = String::new();
    let trials = &results.trials;
    let detected = trials.iter().filter(|t| t.detected).count();
    let failed: Vec<&str> = trials.iter().filter_map(|t| t.error.as_deref()).collect();
    let _ = writeln!(
        s,
        "{} rooms (1600 x 1200 px, focal length 1100 px, pitch 10/20/30 degrees, four boxes and a pentagonal prism each), rendered with shaded textured faces, {}; vanishing points detected in {detected} photos (the true ones otherwise){}. Click noise: Gaussian, `sigma` px per coordinate; search radius `2.45 sigma` (3 to 16 px).\n",
        trials.len(),
        if config.cluttered {
            "0.7 px blur growing to 1.4 px at the photo's corners, noise of 2 grey levels, three clutter strokes near every corner, two occluding bars, barrel distortion k = -0.06 (the fits are told it, as a calibrated lens) and JPEG at quality 85"
        } else {
            "0.7 px blur, noise of 2 grey levels and JPEG at quality 90"
        },
        if failed.is_empty() {
            String::new()
        } else {
            format!("; {} rooms could not be drawn", failed.len())
        }
    );
    // Corners.
    let _ = writeln!(
        s,
        "### Corners\n\nSnapped error: the distance of a snapped point from the true corner, over the points that snapped. Raw error: the click's distance, over the same kind of click.\n"
    );
    let _ = writeln!(
        s,
        "| click noise | kind of click | visible | snapped | snapped error median | p95 | raw error median | covariance: inside 95 % ellipse |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    for &sigma in &config.sigmas_px {
        for kind in [
            CornerKind::BoxCorner,
            CornerKind::RoomCorner,
            CornerKind::FootprintCorner,
            CornerKind::NoCorner,
        ] {
            let rows: Vec<_> = trials
                .iter()
                .flat_map(|t| &t.clicks)
                .filter(|c| c.sigma_px.to_bits() == sigma.to_bits() && c.kind == kind && c.visible)
                .collect();
            let snapped: Vec<f64> = rows
                .iter()
                .filter(|c| c.snapped)
                .map(|c| c.error_px)
                .collect();
            let raw: Vec<f64> = rows.iter().map(|c| c.raw_error_px).collect();
            let chi: Vec<f64> = rows.iter().filter_map(|c| c.chi2).collect();
            let inside = chi.iter().filter(|&&m| m <= 5.991).count();
            let _ = writeln!(
                s,
                "| {sigma} px | {} | {} | {} | {} px | {} px | {} px | {} |",
                kind.name(),
                rows.len(),
                pct(snapped.len(), rows.len()),
                num(median(&snapped), 3),
                num(quantile_of(&snapped, 0.95), 3),
                num(median(&raw), 2),
                pct(inside, chi.len())
            );
        }
    }
    // Coverage by how clear the edges are (every noise level's snapped box corners).
    let quality: Vec<(EdgeQuality, bool)> = trials
        .iter()
        .flat_map(|t| &t.clicks)
        .filter(|c| c.kind == CornerKind::BoxCorner && c.visible)
        .filter_map(|c| Some((c.edge_quality?, c.chi2? <= 5.991)))
        .collect();
    let _ = writeln!(
        s,
        "\nSnapped box corners (every noise level) inside their 95 % ellipse, in four groups of about equal size by the weaker edge's mean gradient across (grey levels per pixel, weakest first): {}; by the rougher edge's residual RMS (pixels, smoothest first): {}.",
        inside_by_quarter(
            quality
                .iter()
                .map(|(q, i)| (q.weaker_gradient, *i))
                .collect()
        ),
        inside_by_quarter(
            quality
                .iter()
                .map(|(q, i)| (q.rougher_rms_px, *i))
                .collect()
        ),
    );
    // Fits.
    let _ = writeln!(
        s,
        "\n### Boxes\n\nSize error: `|modelled - true| / true` of every box's length, breadth and height, at the true scale (the camera height). Coverage: the share of boxes whose true centroid lies in the fit's 95 % ellipse, and of sizes within `+-2 sd`. Raw fits are told the true click noise. `snapped, covariances` weighs each click by its own covariance (`click_covariances_px2`: a snapped point's, `sigma^2 I` for a click that stayed; the vanishing-point segments, through the snapped corners, as 1 px clicks). With one sigma for every click instead, `snapped` estimates it from the residuals (too small for the clicks that stayed) and `snapped, sigma given` is told the raw clicks' noise (too large for the snapped ones).\n"
    );
    let _ = writeln!(
        s,
        "| click noise | clicks | builds refused | size error median | p95 | centroid in 95 % ellipse | sizes within 2 sd |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for &sigma in &config.sigmas_px {
        for variant in [
            "raw",
            "snapped, covariances",
            "snapped",
            "snapped, sigma given",
        ] {
            let fits: Vec<_> = trials
                .iter()
                .flat_map(|t| &t.fits)
                .filter(|f| f.sigma_px.to_bits() == sigma.to_bits() && f.variant == variant)
                .collect();
            let refused = fits.iter().filter(|f| f.refused.is_some()).count();
            let errors: Vec<f64> = fits
                .iter()
                .flat_map(|f| f.size_errors_pct.iter().copied())
                .collect();
            let ellipse: Vec<bool> = fits
                .iter()
                .flat_map(|f| f.ellipse_within.iter().copied())
                .collect();
            let sizes: Vec<bool> = fits
                .iter()
                .flat_map(|f| f.size_within.iter().copied())
                .collect();
            let _ = writeln!(
                s,
                "| {sigma} px | {variant} | {refused} of {} | {} % | {} % | {} | {} |",
                fits.len(),
                num(median(&errors), 2),
                num(quantile_of(&errors, 0.95), 2),
                pct(ellipse.iter().filter(|&&w| w).count(), ellipse.len()),
                pct(sizes.iter().filter(|&&w| w).count(), sizes.len()),
            );
        }
    }
    // Proposals.
    let (mut proposals, mut correct, mut visible, mut found) = (0, 0, 0, 0);
    for t in trials {
        proposals += t.proposals.proposals;
        correct += t.proposals.correct;
        visible += t.proposals.visible_boxes;
        found += t.proposals.found;
    }
    let _ = writeln!(
        s,
        "\n### Box proposals\n\nA proposal matches a box when at least three of the box's clicked corners (base near, right, left; top near, left) are among its corners of the same name, all within {} px. Recall: the boxes whose clicked corners are all visible that some proposal matches; precision: the proposals that match a box.\n",
        super::trial::PROPOSAL_MATCH_PX
    );
    let _ = writeln!(
        s,
        "| fully visible boxes | found (recall) | proposals | correct (precision) |"
    );
    let _ = writeln!(s, "|---|---|---|---|");
    let _ = writeln!(
        s,
        "| {visible} | {found} ({}) | {proposals} | {correct} ({}) |",
        pct(found, visible),
        pct(correct, proposals)
    );
    s
}

/// The section of `docs/results.md`.
#[must_use]
pub fn published_section(
    config: &Config,
    results: &Results,
    elapsed: Duration,
    command: &str,
) -> String {
    crate::publish::published(
        if config.cluttered {
            "Snapping clicks on cluttered renders (`vpmap eval-clicks --cluttered`)"
        } else {
            "Snapping clicks to the photo (`vpmap eval-clicks`)"
        },
        &summary_markdown(config, results),
        elapsed,
        command,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::clicks::{ClickRecord, FitRecord, ProposalRecord, TrialResult};

    #[test]
    fn the_tables_count_what_the_trials_hold() {
        let click = |snapped: bool, error_px: f64| ClickRecord {
            sigma_px: 2.0,
            kind: CornerKind::BoxCorner,
            visible: true,
            snapped,
            raw_error_px: 2.0,
            error_px,
            chi2: snapped.then_some(1.0),
            edge_quality: None,
        };
        let trial = TrialResult {
            trial: 0,
            detected: true,
            clicks: vec![click(true, 0.1), click(true, 0.3), click(false, 2.0)],
            fits: vec![FitRecord {
                sigma_px: 2.0,
                variant: "raw",
                size_errors_pct: vec![1.0, 3.0],
                ellipse_within: vec![true, false],
                size_within: vec![true],
                refused: None,
            }],
            proposals: ProposalRecord {
                proposals: 4,
                correct: 3,
                visible_boxes: 2,
                found: 1,
            },
            error: None,
        };
        let config = Config {
            sigmas_px: vec![2.0],
            ..Config::default()
        };
        let md = summary_markdown(
            &config,
            &Results {
                trials: vec![trial],
            },
        );
        assert!(
            md.contains(
                "| 2 px | box corner | 3 | 66.7 % | 0.200 px | 0.290 px | 2.00 px | 100.0 % |"
            ),
            "{md}"
        );
        assert!(
            md.contains("| 2 px | raw | 0 of 1 | 2.00 % | 2.90 % | 50.0 % | 100.0 % |"),
            "{md}"
        );
        assert!(md.contains("| 2 | 1 (50.0 %) | 4 | 3 (75.0 %) |"), "{md}");
    }
}
