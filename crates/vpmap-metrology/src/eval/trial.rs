//! Running one trial: its seeds, the noisy scene each noise level annotates (the vanishing
//! points fitted to the objects' edges or to long room lines), a map built with every method
//! and evaluated, and why a build was refused.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde::Serialize;

use super::evaluate::{MapEvaluation, evaluate_map};
use super::setups::Setup;
use crate::error::{MetrologyError, Result};
use crate::map::{BuildOptions, build_map};
use crate::reconstruct::Method;
use crate::scene::Scene;
use crate::synth::{LongEdgeOptions, Truth, add_noise, long_edges, synthesize};

/// SplitMix64's finaliser: a bijective mix of 64 bits.
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn combine(a: u64, b: u64) -> u64 {
    splitmix(a ^ splitmix(b))
}

/// 64-bit FNV-1a of a name (stable across runs and platforms).
fn name_hash(name: &str) -> u64 {
    name.bytes().fold(0xCBF2_9CE4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01B3)
    })
}

/// The seed of one trial's scene: a function of the run's seed, the set-up's name and the
/// trial number only, so a trial draws the same scene whatever else runs (other set-ups,
/// other noise levels, thread scheduling).
#[must_use]
pub fn scene_seed(seed: u64, setup: &Setup, trial: u64) -> u64 {
    combine(combine(seed, name_hash(setup.name)), trial)
}

/// The seed of the noise added to a scene at one noise level.
#[must_use]
pub fn noise_seed(scene_seed: u64, sigma_px: f64) -> u64 {
    combine(scene_seed, sigma_px.to_bits())
}

/// The scene as a user would annotate it with `sigma_px` pixels of Gaussian noise on every
/// clicked point: [`add_noise`] on every corner, top, footprint vertex and floor corner, then
/// the vanishing points replaced by the box edges through the noisy corners (two or more per
/// vanishing point), to be re-estimated by least squares. With `sigma_px = 0` only the second
/// step applies.
#[must_use]
pub fn noisy_scene(scene: &Scene, sigma_px: f64, seed: u64) -> Scene {
    let mut noisy = scene.clone();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    add_noise(&mut noisy, sigma_px, &mut rng);
    crate::synth::vanishing_points_as_lines(&mut noisy);
    noisy
}

/// The seed of the long vanishing-point edges placed in one trial's scene
/// ([`VpEdges::Long`]): a function of the scene's seed only, so every noise level and method
/// sees the same edges.
#[must_use]
pub fn long_edge_seed(scene_seed: u64) -> u64 {
    combine(scene_seed, name_hash("long vanishing-point edges"))
}

/// Which edges the vanishing points are fitted to in an experiment.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum VpEdges {
    /// The objects' own box edges through their noisy corners ([`noisy_scene`]): short
    /// edges, the default and the published results.
    #[default]
    Objects,
    /// Long straight room lines drawn through the true camera ([`with_long_edges`]), their
    /// end points clicked with the same noise as the objects' points.
    Long(LongEdgeOptions),
}

/// Options of [`run_trial_with`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TrialOptions {
    /// The edges the vanishing points are fitted to.
    pub vp_edges: VpEdges,
}

/// The scene with its vanishing points replaced by long straight edges that run to them
/// ([`crate::synth::long_edges`] through the truth's camera, seeded by `seed`), exact: the
/// noise comes later ([`add_noise`] jitters their end points after the objects' points, so
/// the objects get the same noise as with [`noisy_scene`]).
///
/// The vanishing directions are the scene's vanishing points pulled back through the true
/// camera, so the edges' lines pass through those points to rounding.
///
/// # Errors
/// [`MetrologyError::InvalidField`] when a vanishing point is not given as a point or the
/// options are out of range; [`MetrologyError::Degenerate`] when edges of that length do not
/// fit in the image.
pub fn with_long_edges(
    scene: &Scene,
    truth: &Truth,
    options: &LongEdgeOptions,
    seed: u64,
) -> Result<Scene> {
    let camera = truth.camera.pinhole(scene.image);
    let (right, down, forward) = camera.axes();
    let mut directions = Vec::with_capacity(scene.vanishing_points.len());
    for (i, vp) in scene.vanishing_points.iter().enumerate() {
        let Some(p) = vp.point else {
            return Err(MetrologyError::InvalidField {
                field: format!("vanishing_points[{i}].point"),
                reason:
                    "long edges are drawn towards the exact vanishing point; give it as a point"
                        .to_owned(),
            });
        };
        let q = (nalgebra::Vector2::new(p[0], p[1]) - camera.principal_point_px) / camera.focal_px;
        directions.push(right * q.x + down * q.y + forward);
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let edges = long_edges(&camera, &directions, options, &mut rng)?;
    let mut out = scene.clone();
    for (vp, lines) in out.vanishing_points.iter_mut().zip(edges) {
        vp.point = None;
        vp.lines = lines;
    }
    Ok(out)
}

/// A short, stable name for why a builder refused a scene (`failures.csv`, the summaries).
#[must_use]
pub fn failure_category(error: &MetrologyError) -> &'static str {
    match error {
        MetrologyError::InPhoto { error, .. } => failure_category(error),
        MetrologyError::NotBelowHorizon { .. } => "point_not_below_horizon",
        MetrologyError::NoRealFocalLength(_) => "no_real_focal_length",
        MetrologyError::ParallelLines { .. } => "parallel_edges",
        MetrologyError::CoincidentVanishingPoints { .. } => "coincident_vanishing_points",
        MetrologyError::Degenerate { reason, .. } => {
            if reason.contains("negative height") {
                "negative_height"
            } else if reason.contains("behind the camera") {
                "behind_camera"
            } else if reason.contains("too close to the horizon") {
                "near_horizon"
            } else if reason.contains("zero area") || reason.contains("no length") {
                "zero_area"
            } else {
                "degenerate"
            }
        }
        MetrologyError::InvalidField { .. } => "invalid_field",
        MetrologyError::InconsistentRoom { .. } => "inconsistent_room",
        MetrologyError::Interrupted { .. } => "interrupted",
        MetrologyError::Json(_)
        | MetrologyError::UnsupportedVersion { .. }
        | MetrologyError::NonFinite { .. }
        | MetrologyError::VanishingPointCount(_)
        | MetrologyError::UnknownScaleObject { .. } => "invalid_scene",
    }
}

/// Why a trial produced no evaluation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Failure {
    /// [`failure_category`], `scene_draw` when the set-up could not place its objects, or
    /// `vp_edges` when long vanishing-point edges did not fit in the image ([`VpEdges::Long`]).
    pub category: &'static str,
    /// The error message.
    pub message: String,
}

/// One method at one noise level on one trial's scene.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrialOutcome {
    /// Noise, pixels.
    pub sigma_px: f64,
    /// The reconstruction method.
    pub method: Method,
    /// The evaluation, or why the builder refused the scene.
    pub result: std::result::Result<MapEvaluation, Failure>,
}

/// Every outcome of one trial of one set-up.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Trial {
    /// Trial number.
    pub trial: u64,
    /// The seed its scene was drawn with ([`scene_seed`]).
    pub scene_seed: u64,
    /// Per noise level (outer) and method (inner), in the order given.
    pub outcomes: Vec<TrialOutcome>,
}

/// Run one trial: draw the set-up's scene for `(seed, trial)`, then for every noise level
/// add noise ([`noisy_scene`]), build the map with every method ([`build_map`]) and compare it
/// with the truth ([`evaluate_map`]). A scene a builder refuses is an outcome with a
/// [`Failure`], not an error. [`run_trial_with`] with the default [`TrialOptions`].
#[must_use]
pub fn run_trial(
    setup: &Setup,
    seed: u64,
    trial: u64,
    sigmas_px: &[f64],
    methods: &[Method],
) -> Trial {
    run_trial_with(
        setup,
        seed,
        trial,
        sigmas_px,
        methods,
        &TrialOptions::default(),
    )
}

/// [`run_trial`] with a choice of the edges the vanishing points are fitted to
/// ([`TrialOptions::vp_edges`]). With [`VpEdges::Long`] the edges are placed once per scene
/// ([`with_long_edges`], [`long_edge_seed`]); a scene they do not fit in is a [`Failure`] of
/// category `vp_edges` at every noise level. At zero noise the objects carry no
/// [`Coverage`](crate::eval::Coverage) (their error bars are zero).
#[must_use]
pub fn run_trial_with(
    setup: &Setup,
    seed: u64,
    trial: u64,
    sigmas_px: &[f64],
    methods: &[Method],
    options: &TrialOptions,
) -> Trial {
    let scene_seed = scene_seed(seed, setup, trial);
    let drawn = synthesize(&setup.synth_options(scene_seed)).map_err(|e| Failure {
        category: "scene_draw",
        message: e.to_string(),
    });
    let drawn = match (drawn, options.vp_edges) {
        (Ok((scene, truth)), VpEdges::Long(long)) => {
            with_long_edges(&scene, &truth, &long, long_edge_seed(scene_seed))
                .map(|scene| (scene, truth))
                .map_err(|e| Failure {
                    category: "vp_edges",
                    message: e.to_string(),
                })
        }
        (drawn, _) => drawn,
    };
    let mut outcomes = Vec::with_capacity(sigmas_px.len() * methods.len());
    for &sigma_px in sigmas_px {
        for &method in methods {
            let result = match &drawn {
                Ok((scene, truth)) => {
                    let noise = noise_seed(scene_seed, sigma_px);
                    let noisy = match options.vp_edges {
                        VpEdges::Objects => noisy_scene(scene, sigma_px, noise),
                        VpEdges::Long(_) => {
                            let mut noisy = scene.clone();
                            add_noise(&mut noisy, sigma_px, &mut ChaCha8Rng::seed_from_u64(noise));
                            noisy
                        }
                    };
                    build_map(
                        &noisy,
                        &BuildOptions {
                            method,
                            click_sigma_px: Some(sigma_px),
                        },
                    )
                    .and_then(|map| evaluate_map(&map, truth))
                    .map(|mut ev| {
                        // Error bars for exact clicks are zero: nothing to cover.
                        if sigma_px <= 0.0 {
                            for o in &mut ev.objects {
                                o.coverage = None;
                            }
                        }
                        ev
                    })
                    .map_err(|e| Failure {
                        category: failure_category(&e),
                        message: e.to_string(),
                    })
                }
                Err(failure) => Err(failure.clone()),
            };
            outcomes.push(TrialOutcome {
                sigma_px,
                method,
                result,
            });
        }
    }
    Trial {
        trial,
        scene_seed,
        outcomes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::eval::setups::SETUPS;

    #[test]
    fn seeds_depend_on_every_input() {
        let (a, b) = (&SETUPS[0], &SETUPS[1]);
        let s = scene_seed(1, a, 0);
        assert_eq!(s, scene_seed(1, a, 0));
        assert_ne!(s, scene_seed(2, a, 0));
        assert_ne!(s, scene_seed(1, b, 0));
        assert_ne!(s, scene_seed(1, a, 1));
        assert_ne!(noise_seed(s, 1.0), noise_seed(s, 2.0));
    }
}
