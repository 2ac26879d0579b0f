//! Snapped against raw clicks on rendered photos (`vpmap eval-clicks`); on real photos, see
//! [`yud`] (`vpmap eval-clicks --yud DIR`).
//!
//! With [`Config::cluttered`] the photos are rendered with
//! [`vpmap_vision::synthetic::photo::PhotoOptions::cluttered`] (clutter near the corners,
//! occluding bars, blur growing off-centre, JPEG at quality 85, barrel distortion): the clicks
//! are then jittered about the true points as the distorted photo shows them, and both fits
//! take them there (a pinhole fit of a distorted photo).
//!
//! Each trial draws a random room from `vpmap_metrology::synth` (1600 x 1200 px, focal length
//! 1100 px, camera 1.5 m high, pitch 10, 20 or 30 degrees by turn, 3 degrees of roll, four
//! boxes and a pentagonal prism, the thesis's annotation), renders its photo
//! ([`vpmap_vision::synthetic::photo`]: shaded textured faces, blur, noise, JPEG at quality
//! 90) and finds its vanishing points with [`vpmap_vision::detect`] (as a user would, from
//! `vpmap detect`; the true ones when detection fails). Then, per click noise level:
//!
//! * **raw clicks**: every clicked point of the exact scene jittered by Gaussian noise of
//!   `sigma` px per coordinate ([`vpmap_metrology::eval::noise_seed`]), the vanishing points
//!   written as the box edges through the noisy corners (as `vpmap eval` does);
//! * **snapped clicks**: the same noisy clicks snapped ([`vpmap_vision::snap::snap_click`]
//!   with [`vpmap_vision::snap::SnapOptions::for_click_sigma`] and the detected vanishing points), the vanishing
//!   points written as the box edges through the snapped corners;
//!
//! and both are built with the joint fit and compared with the truth
//! ([`vpmap_metrology::eval::evaluate_map`]). The raw fit is told the true click noise. The
//! snapped clicks are fitted three ways: each click weighed by its own covariance
//! (`click_covariances_px2`: a snapped point's, `sigma^2 I` for a click that stayed; the
//! vanishing-point segments count as 1 px clicks), and with one sigma for every click,
//! estimated from the residuals or told the raw clicks' noise.
//!
//! Measured: per kind of click ([`vpmap_vision::synthetic::photo::CornerKind`]) the share snapped and the snapped points'
//! error against the true corner; per box the size errors (length, breadth and height, in %
//! of the true ones) and whether the truth lies in the fit's error bars (the centroid's 95 %
//! ellipse, `+-2 sd` on the sizes); the box proposals' recall and precision against the boxes
//! whose every corner is visible.

mod report;
mod trial;
pub mod yud;
mod yud_labels;
mod yud_unseen;

use rayon::prelude::*;

pub use report::{CLICKS_SECTION, CLUTTERED_SECTION, published_section, summary_markdown};
pub use trial::{
    ClickRecord, EdgeQuality, FitRecord, ProposalRecord, TrialResult, run_clicks_trial,
};

use crate::progress::Progress;

/// Options of [`run`].
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Rooms drawn.
    pub trials: u64,
    /// Click noise levels, pixels (1 sigma per coordinate).
    pub sigmas_px: Vec<f64>,
    /// Seed of the rooms, photos and noise.
    pub seed: u64,
    /// Also fit the snapped clicks with each click's own covariance
    /// (`click_covariances_px2`: a snapped point's, `sigma^2 I` for a click that stayed).
    pub per_click_covariance: bool,
    /// Render the photos with what real photos have
    /// ([`vpmap_vision::synthetic::photo::PhotoOptions::cluttered`]: clutter near the corners,
    /// occluding bars, blur growing off-centre, JPEG at quality 85, barrel distortion).
    pub cluttered: bool,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            trials: 60,
            sigmas_px: vec![1.0, 2.0, 3.0],
            seed: 1,
            per_click_covariance: true,
            cluttered: false,
        }
    }
}

/// Every trial of a run, in trial order.
#[derive(Debug, Clone)]
pub struct Results {
    /// One per room.
    pub trials: Vec<TrialResult>,
}

/// Run every trial, in parallel (rayon); one [`Progress::step`] per trial.
#[must_use]
pub fn run(config: &Config, progress: &dyn Progress) -> Results {
    progress.start(config.trials);
    let mut trials: Vec<TrialResult> = (0..config.trials)
        .into_par_iter()
        .map(|t| {
            let r = run_clicks_trial(config, t);
            progress.step();
            r
        })
        .collect();
    progress.finish();
    trials.sort_by_key(|t| t.trial);
    Results { trials }
}

/// A photo and its clicked scene to try `vpmap snap` on: trial 0's room, rendered
/// (`example.jpg`, the photo after its JPEG round trip, saved at quality 98), its scene with
/// every click jittered by `sigma_px` (`example-scene.json`), and the exact scene
/// (`example-truth.json`).
///
/// # Errors
/// When the room cannot be drawn, rendered or encoded.
pub fn example_files(config: &Config, sigma_px: f64) -> crate::Result<crate::output::OutputSet> {
    use rand::SeedableRng as _;
    let synth = trial::synth_options(config, 0);
    let (scene, truth) = vpmap_metrology::synth::synthesize(&synth)?;
    let photo = vpmap_vision::synthetic::photo::render_photo(
        &scene,
        &truth,
        &vpmap_vision::synthetic::photo::PhotoOptions {
            seed: synth.seed,
            ..vpmap_vision::synthetic::photo::PhotoOptions::default()
        },
    )
    .map_err(|e| crate::EvalError::Invalid(e.to_string()))?;
    let mut jpeg = Vec::new();
    image::codecs::jpeg::JpegEncoder::new_with_quality(&mut jpeg, 98)
        .encode_image(&photo.image.to_rgb8())
        .map_err(|e| crate::EvalError::Invalid(format!("encoding the example photo: {e}")))?;
    let mut noisy = scene.clone();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(synth.seed ^ 0xC11C);
    vpmap_metrology::synth::add_noise(&mut noisy, sigma_px, &mut rng);
    let mut files = crate::output::OutputSet::default();
    files.add("example.jpg", jpeg);
    files.add(
        "example-scene.json",
        format!("{}\n", serde_json::to_string_pretty(&noisy)?),
    );
    files.add(
        "example-truth.json",
        format!("{}\n", serde_json::to_string_pretty(&scene)?),
    );
    Ok(files)
}

/// The share of `rows` inside (`true`) in four groups of about equal size by their key,
/// smallest key first, with each group's key range and how many of it are outside:
/// `50.0 / 100.0 % (1.000-2.000: 1 of 2 outside; 3.000-4.000: 0 of 2 outside)`; `-` for no
/// rows.
pub(crate) fn inside_by_quarter(mut rows: Vec<(f64, bool)>) -> String {
    if rows.is_empty() {
        return "-".to_owned();
    }
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let size = rows.len().div_ceil(4);
    let (mut shares, mut ranges) = (Vec::new(), Vec::new());
    for group in rows.chunks(size) {
        let inside = group.iter().filter(|r| r.1).count();
        shares.push(format!("{:.1}", 100.0 * inside as f64 / group.len() as f64));
        if let (Some(a), Some(b)) = (group.first(), group.last()) {
            ranges.push(format!(
                "{:.3}-{:.3}: {} of {} outside",
                a.0,
                b.0,
                group.len() - inside,
                group.len()
            ));
        }
    }
    format!("{} % ({})", shares.join(" / "), ranges.join("; "))
}

#[cfg(test)]
mod quarter_tests {
    use super::inside_by_quarter;

    #[test]
    fn the_quarters_are_sorted_by_key_and_count_their_own_rows() {
        // Keys given out of order: the smallest four are all outside, the next four half in.
        let rows = vec![
            (9.0, true),
            (1.0, false),
            (5.0, true),
            (2.0, false),
            (13.0, true),
            (6.0, false),
            (3.0, false),
            (10.0, true),
            (4.0, false),
            (7.0, true),
            (14.0, true),
            (8.0, false),
            (11.0, true),
            (15.0, true),
            (12.0, false),
            (16.0, true),
        ];
        assert_eq!(
            inside_by_quarter(rows),
            "0.0 / 50.0 / 75.0 / 100.0 % (1.000-4.000: 4 of 4 outside; 5.000-8.000: 2 of 4 outside; 9.000-12.000: 1 of 4 outside; 13.000-16.000: 0 of 4 outside)"
        );
        assert_eq!(inside_by_quarter(Vec::new()), "-");
        // Five rows: groups of two, two and one.
        let five = (1..=5).map(|k| (f64::from(k), k % 2 == 0)).collect();
        assert_eq!(
            inside_by_quarter(five),
            "50.0 / 50.0 / 0.0 % (1.000-2.000: 1 of 2 outside; 3.000-4.000: 1 of 2 outside; 5.000-5.000: 1 of 1 outside)"
        );
    }
}
