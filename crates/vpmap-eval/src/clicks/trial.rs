//! One trial of `vpmap eval-clicks`: a room, its photo, and per noise level the raw and the
//! snapped clicks, their fits and the box proposals.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use vpmap_metrology::eval::{evaluate_map, noise_seed};
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::reconstruct::{Method, ObjectKind};
use vpmap_metrology::scene::{DivisionModel, ImageSize, LensDistortion, Scene};
use vpmap_metrology::synth::{
    SynthOptions, Truth, add_noise, synthesize, vanishing_points_as_lines,
};
use vpmap_vision::clicks::{ClickPlace, set_scene_click};
use vpmap_vision::proposals::{ProposalOptions, propose_boxes};
use vpmap_vision::snap::scene::{scene_vanishing_points, vanishing_points_at};
use vpmap_vision::snap::{SnapImage, SnapOptions, snap_click};
use vpmap_vision::synthetic::photo::{CornerKind, PhotoOptions, TrueCorner, render_photo};
use vpmap_vision::{DetectOptions, detect};

use super::Config;

/// One click at one noise level.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClickRecord {
    /// The click noise, pixels.
    pub sigma_px: f64,
    /// What kind of image point it is.
    pub kind: CornerKind,
    /// Whether the camera sees the true point.
    pub visible: bool,
    /// Whether it moved to a corner.
    pub snapped: bool,
    /// Distance of the raw click from the true point, pixels.
    pub raw_error_px: f64,
    /// Distance of the point after snapping (the click when kept) from the true point.
    pub error_px: f64,
    /// Squared Mahalanobis distance of a snapped point's error under its covariance.
    pub chi2: Option<f64>,
    /// A snapped point's weaker edge: its mean gradient across, grey levels per pixel
    /// (`SnapEdge::gradient`), and the rougher edge's residual RMS, pixels.
    pub edge_quality: Option<EdgeQuality>,
}

/// How clear a snapped point's two edges are: the weaker one's gradient and the rougher one's
/// residual RMS.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeQuality {
    /// The smaller mean gradient across the two edges, grey levels per pixel.
    pub weaker_gradient: f64,
    /// The larger residual RMS of the two edges' points about their lines, pixels.
    pub rougher_rms_px: f64,
}

impl EdgeQuality {
    /// Of a snap's edges; `None` without any.
    #[must_use]
    pub fn of(edges: &[vpmap_vision::snap::SnapEdge]) -> Option<Self> {
        (!edges.is_empty()).then(|| EdgeQuality {
            weaker_gradient: edges
                .iter()
                .map(|e| e.gradient)
                .fold(f64::INFINITY, f64::min),
            rougher_rms_px: edges.iter().map(|e| e.rms_px).fold(0.0, f64::max),
        })
    }
}

/// One fit of one trial and noise level.
#[derive(Debug, Clone, PartialEq)]
pub struct FitRecord {
    /// The click noise, pixels.
    pub sigma_px: f64,
    /// `raw`, `snapped, covariances` (each click weighed by its own covariance: a snapped
    /// point's, the raw noise for a click that stayed), `snapped` (one click sigma estimated
    /// from the residuals) or `snapped, sigma given` (the raw clicks' sigma for every click).
    pub variant: &'static str,
    /// Per box: absolute errors of length, breadth and height, % of the true ones.
    pub size_errors_pct: Vec<f64>,
    /// Per box: the true centroid lies in the 95 % ellipse.
    pub ellipse_within: Vec<bool>,
    /// Per box size (length, breadth, height): the truth lies within `+-2 sd`.
    pub size_within: Vec<bool>,
    /// Why the build or its evaluation failed.
    pub refused: Option<String>,
}

/// The box proposals of one photo against its boxes.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ProposalRecord {
    /// Proposals made.
    pub proposals: usize,
    /// Proposals that match a true box.
    pub correct: usize,
    /// True boxes whose every clicked corner is visible.
    pub visible_boxes: usize,
    /// Of those, the ones some proposal matches.
    pub found: usize,
}

/// One trial's records.
#[derive(Debug, Clone, PartialEq)]
pub struct TrialResult {
    /// Trial number.
    pub trial: u64,
    /// Whether the vanishing points came from detection (else the true ones).
    pub detected: bool,
    /// Every click at every noise level.
    pub clicks: Vec<ClickRecord>,
    /// Every fit.
    pub fits: Vec<FitRecord>,
    /// The box proposals.
    pub proposals: ProposalRecord,
    /// Why the trial could not run (no scene, no photo).
    pub error: Option<String>,
}

/// SplitMix64's finaliser.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The pitch of trial `t`, degrees.
#[must_use]
pub fn pitch_deg(trial: u64) -> f64 {
    [10.0, 20.0, 30.0][(trial % 3) as usize]
}

/// The room and photo options of trial `t`.
#[must_use]
pub fn synth_options(config: &Config, trial: u64) -> SynthOptions {
    SynthOptions {
        seed: mix(config.seed ^ mix(trial)),
        image: ImageSize {
            width: 1600,
            height: 1200,
        },
        focal_px: 1100.0,
        pitch_deg: pitch_deg(trial),
        ..SynthOptions::default()
    }
}

/// Run one trial.
#[must_use]
pub fn run_clicks_trial(config: &Config, trial: u64) -> TrialResult {
    let mut out = TrialResult {
        trial,
        detected: false,
        clicks: Vec::new(),
        fits: Vec::new(),
        proposals: ProposalRecord::default(),
        error: None,
    };
    let synth = synth_options(config, trial);
    let (scene, truth) = match synthesize(&synth) {
        Ok(s) => s,
        Err(e) => {
            out.error = Some(e.to_string());
            return out;
        }
    };
    let photo_options = if config.cluttered {
        PhotoOptions::cluttered(synth.seed)
    } else {
        PhotoOptions {
            seed: synth.seed,
            ..PhotoOptions::default()
        }
    };
    let photo = match render_photo(&scene, &truth, &photo_options) {
        Ok(p) => p,
        Err(e) => {
            out.error = Some(e.to_string());
            return out;
        }
    };
    let image = SnapImage::new(&photo.image);
    let detection = detect(&photo.image, &DetectOptions::default()).ok();
    // The vanishing points and the lens they are the pinhole camera's for: detect's applied
    // lens with its points, the renderer's with the scene's; snapping looks through it
    // (`vanishing_points_at`), as `vpmap snap` does with the scene detect writes.
    let (vps, lens): (Vec<[f64; 3]>, Option<DivisionModel>) = match &detection {
        Some(d) if d.vanishing_points.len() >= 2 => {
            out.detected = true;
            (
                d.vanishing_points
                    .iter()
                    .filter_map(|v| v.point_px.map(|p| [p[0], p[1], 1.0]))
                    .collect(),
                d.lens.map(|l| l.model),
            )
        }
        _ => (
            scene_vanishing_points(&scene).unwrap_or_default(),
            Some(DivisionModel::new(
                photo.distortion_k,
                scene.image,
                scene.principal_point,
            )),
        ),
    };
    if let Some(d) = &detection {
        out.proposals =
            proposal_record(&photo.image, &image, d, &vps, lens.as_ref(), &photo.corners);
    }
    for &sigma in &config.sigmas_px {
        let mut noisy = scene.clone();
        let mut rng = ChaCha8Rng::seed_from_u64(noise_seed(synth.seed, sigma));
        add_noise(&mut noisy, sigma, &mut rng);
        let mut snapped = noisy.clone();
        let mut raw_scene = noisy.clone();
        let clicks = vpmap_vision::clicks::scene_clicks(&noisy);
        let exact = vpmap_vision::clicks::scene_clicks(&scene);
        let mut snapped_points: Vec<[f64; 2]> = Vec::new();
        let mut covariances = std::collections::BTreeMap::new();
        let opts = SnapOptions::for_click_sigma(sigma);
        for ((c, t), e) in clicks.iter().zip(&photo.corners).zip(&exact) {
            // The click: the true point in the photo (distorted by the lens, if any) plus the
            // click's noise; both fits get it where the photo shows it.
            let click_px = if photo.distortion_k == 0.0 {
                c.point_px
            } else {
                let p = [
                    t.point_px[0] + c.point_px[0] - e.point_px[0],
                    t.point_px[1] + c.point_px[1] - e.point_px[1],
                ];
                set_scene_click(&mut raw_scene, c.place, p);
                set_scene_click(&mut snapped, c.place, p);
                p
            };
            let raw_error = dist(click_px, t.point_px);
            let here = vanishing_points_at(&vps, lens.as_ref(), click_px);
            let snap = snap_click(&image, &here, click_px, &opts).ok();
            let (point, snapped_here, chi2) = match &snap {
                Some(s) if s.snapped() => (
                    s.point_px,
                    true,
                    s.covariance_px2
                        .map(|cov| mahalanobis_sq(s.point_px, t.point_px, cov)),
                ),
                _ => (click_px, false, None),
            };
            if snapped_here {
                set_scene_click(&mut snapped, c.place, point);
                snapped_points.push(point);
            }
            // The fit weighs object clicks only; a click that stayed carries the raw noise.
            if !matches!(c.place, ClickPlace::Floor { .. }) {
                let cov = snap
                    .as_ref()
                    .filter(|s| s.snapped())
                    .and_then(|s| s.covariance_px2)
                    .unwrap_or([[sigma * sigma, 0.0], [0.0, sigma * sigma]]);
                covariances.insert(c.place.field(), cov);
            }
            out.clicks.push(ClickRecord {
                sigma_px: sigma,
                kind: t.kind,
                visible: t.visible,
                snapped: snapped_here,
                raw_error_px: raw_error,
                error_px: dist(point, t.point_px),
                chi2,
                edge_quality: snap
                    .as_ref()
                    .filter(|_| snapped_here)
                    .and_then(|s| EdgeQuality::of(&s.edges)),
            });
        }
        // The clicks are where the photo shows them: through its lens, which the fits are
        // told (as a calibrated lens: known `k`).
        if photo.distortion_k != 0.0 {
            let lens = Some(LensDistortion {
                k: photo.distortion_k,
                k_sd: None,
            });
            raw_scene.lens_distortion = lens;
            snapped.lens_distortion = lens;
        }
        let mut noisy = raw_scene;
        vanishing_points_as_lines(&mut noisy);
        vanishing_points_as_lines(&mut snapped);
        keep_snapped_lines(&mut snapped, &snapped_points);
        out.fits
            .push(fit_record(&noisy, &truth, sigma, "raw", Some(sigma)));
        out.fits
            .push(fit_record(&snapped, &truth, sigma, "snapped", None));
        out.fits.push(fit_record(
            &snapped,
            &truth,
            sigma,
            "snapped, sigma given",
            Some(sigma),
        ));
        if config.per_click_covariance {
            let mut weighted = snapped.clone();
            weighted.click_covariances_px2 = covariances;
            out.fits.push(fit_record(
                &weighted,
                &truth,
                sigma,
                "snapped, covariances",
                None,
            ));
        }
    }
    out
}

/// Keep, per vanishing point, only the box edges whose both ends snapped, when at least two
/// are left (a click that stayed is a few pixels off: its edges would bend the vanishing
/// point the snapped ones fix well).
fn keep_snapped_lines(scene: &mut Scene, snapped: &[[f64; 2]]) {
    let is_snapped = |x: f64, y: f64| {
        snapped
            .iter()
            .any(|p| (p[0] - x).abs() < 1e-9 && (p[1] - y).abs() < 1e-9)
    };
    for vp in &mut scene.vanishing_points {
        let kept: Vec<[f64; 4]> = vp
            .lines
            .iter()
            .copied()
            .filter(|l| is_snapped(l[0], l[1]) && is_snapped(l[2], l[3]))
            .collect();
        if kept.len() >= 2 {
            vp.lines = kept;
        }
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn mahalanobis_sq(p: [f64; 2], truth: [f64; 2], cov: [[f64; 2]; 2]) -> f64 {
    let e = [p[0] - truth[0], p[1] - truth[1]];
    let det = cov[0][0] * cov[1][1] - cov[0][1] * cov[1][0];
    if det <= 0.0 {
        return f64::INFINITY;
    }
    (e[0] * e[0] * cov[1][1] - 2.0 * e[0] * e[1] * cov[0][1] + e[1] * e[1] * cov[0][0]) / det
}

/// Build with the joint fit and compare the boxes with the truth.
fn fit_record(
    scene: &Scene,
    truth: &Truth,
    sigma: f64,
    variant: &'static str,
    click_sigma_px: Option<f64>,
) -> FitRecord {
    let mut record = FitRecord {
        sigma_px: sigma,
        variant,
        size_errors_pct: Vec::new(),
        ellipse_within: Vec::new(),
        size_within: Vec::new(),
        refused: None,
    };
    let built = build_map(
        scene,
        &BuildOptions {
            method: Method::Fit,
            click_sigma_px,
        },
    )
    .and_then(|map| evaluate_map(&map, truth).map(|ev| (map, ev)));
    let (map, ev) = match built {
        Ok(x) => x,
        Err(e) => {
            record.refused = Some(e.to_string());
            return record;
        }
    };
    for ((m, t), e) in map.objects.iter().zip(&truth.objects).zip(&ev.objects) {
        if m.kind != ObjectKind::Box {
            continue;
        }
        let side = |f: &[[f64; 2]], k: usize| -> Option<f64> {
            let (a, b) = (f.first()?, f.get(k)?);
            Some((b[0] - a[0]).hypot(b[1] - a[1]))
        };
        for k in [1, 3] {
            if let (Some(ms), Some(ts)) = (side(&m.footprint, k), side(&t.footprint, k)) {
                record.size_errors_pct.push(100.0 * (ms - ts).abs() / ts);
            }
        }
        if let Some(h) = m.height {
            record
                .size_errors_pct
                .push(100.0 * (h - t.height).abs() / t.height);
        }
        if let Some(c) = &e.coverage {
            let within = c.within();
            if let Some(Some(w)) = within.first() {
                record.ellipse_within.push(*w);
            }
            record
                .size_within
                .extend(within.iter().skip(1).filter_map(|w| *w));
        }
    }
    record
}

/// Pixels within which a proposed corner matches a true one.
pub const PROPOSAL_MATCH_PX: f64 = 5.0;

/// The proposals of a photo against its true boxes: a proposal matches a box when at least
/// three of the box's clicked corners are among the proposal's corners of the same name and
/// all of those lie within [`PROPOSAL_MATCH_PX`] of the truth.
fn proposal_record(
    photo: &image::DynamicImage,
    image: &SnapImage,
    detection: &vpmap_vision::Detection,
    vps: &[[f64; 3]],
    lens: Option<&DivisionModel>,
    corners: &[TrueCorner],
) -> ProposalRecord {
    // The segments at the photo's full size (the detector works on a smaller copy).
    let full = vpmap_vision::DetectOptions {
        max_side_px: image.width().max(image.height()),
        ..vpmap_vision::DetectOptions::default()
    };
    let segments = vpmap_vision::detect_segments(photo, &full).unwrap_or_default();
    let _ = detection;
    let options = ProposalOptions {
        lens: lens.copied(),
        ..ProposalOptions::default()
    };
    let proposals = propose_boxes(image, &segments, vps, &options).unwrap_or_default();
    let objects: Vec<usize> = {
        let mut o: Vec<usize> = corners
            .iter()
            .filter_map(|c| match c.place {
                ClickPlace::BoxCorner { object, .. } => Some(object),
                _ => None,
            })
            .collect();
        o.dedup();
        o
    };
    let box_corners = |object: usize| -> Vec<&TrueCorner> {
        corners
            .iter()
            .filter(|c| matches!(c.place, ClickPlace::BoxCorner { object: o, .. } if o == object))
            .collect()
    };
    let matches = |p: &vpmap_vision::proposals::BoxProposal, object: usize| -> bool {
        let mut shared = 0;
        for c in box_corners(object) {
            let ClickPlace::BoxCorner { corner, top, .. } = c.place else {
                continue;
            };
            let proposed = if top {
                p.top.get(corner)
            } else {
                p.base.get(corner)
            };
            if let Some(q) = proposed {
                if dist(q, c.point_px) > PROPOSAL_MATCH_PX {
                    return false;
                }
                shared += 1;
            }
        }
        shared >= 3
    };
    let visible: Vec<usize> = objects
        .iter()
        .copied()
        .filter(|&o| box_corners(o).iter().all(|c| c.visible))
        .collect();
    ProposalRecord {
        proposals: proposals.len(),
        correct: proposals
            .iter()
            .filter(|p| objects.iter().any(|&o| matches(p, o)))
            .count(),
        visible_boxes: visible.len(),
        found: visible
            .iter()
            .filter(|&&o| proposals.iter().any(|p| matches(p, o)))
            .count(),
    }
}
