//! A room of several photos against its truth: the joint map beside the map of its first photo
//! alone, and each shared object beside the maps of every photo that shows it alone.
//!
//! One trial draws a room ([`synthesize_room`], seed [`room_scene_seed`]), adds Gaussian click
//! noise of `sigma` pixels to every photo and writes its vanishing points as the box edges
//! through the noisy corners ([`noisy_scene`], as the single-photo evaluation; each photo its
//! own noise seed), then builds
//!
//! * the **joint** map of the room ([`build_map`] on the room: the lead's joint fit), and
//! * each photo's map **alone** ([`build_map`] on that photo's scene). Photos after the first
//!   carry no scale in the room; alone each is given its *true* camera height as the scale, so
//!   every map is in metres and a photo alone is compared at its best (its only scale error is
//!   none).
//!
//! and measures, all in metres against the truth in the map's own frame (the first photo's
//! plan frame for the joint map and the first photo alone, photo `k`'s plan frame for photo `k`
//! alone):
//!
//! * per object: the **position error** (distance from the map's footprint centroid to the true
//!   one), the **size errors** (the map's longer and shorter side against the truth's longer
//!   and shorter side, the height against the true height; absolute), and whether the true
//!   centroid lies inside the reported **95 % ellipse** (squared Mahalanobis distance at most
//!   [`CHI2_2DOF_95`]; only with noise: exact clicks have no error bars);
//! * the **share of the room's floor known**: the area of the true room rectangle inside the
//!   map's free space or an object's footprint and outside its hidden regions, over the room's
//!   area, beside the share the true cameras see ([`visible_floor_share`], the ceiling);
//! * per **shared object** (listed by two photos or more): whether its joint position error is
//!   below the smaller of its position errors in the maps of the photos that list it, each
//!   alone (photos whose map alone was refused are left out of that minimum). The photos alone
//!   know their true camera heights, which the joint map (the first photo's scale only) does
//!   not; so the room is also mapped jointly **with the same information**, every photo
//!   carrying its true camera height (which then holds each camera's height in the fit), and
//!   that map's error is compared both ways: in the first photo's frame against the smaller
//!   single-photo error, and in each listing photo's own frame (the joint map's object seen
//!   from its fitted camera against the truth seen from the true one) against that photo's
//!   map alone.

use geo::{Area, BooleanOps, Centroid, Coord, LineString, MultiPolygon, Polygon};
use serde::Serialize;

use super::coverage::CHI2_2DOF_95;
use super::room_visibility::visible_floor_share;
use super::trial::{Failure, failure_category, noise_seed, noisy_scene};
use crate::map::{BuildOptions, FloorMap, MapPoint, build_map};
use crate::scene::{ScaleSpec, Scene};
use crate::synth::{RoomSynthOptions, RoomTruth, synthesize_room};

/// SplitMix64's finaliser (as the single-photo evaluation's seeds).
fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The seed of one room trial: a function of the run's seed, the number of photos and the
/// trial number only.
#[must_use]
pub fn room_scene_seed(seed: u64, photos: usize, trial: u64) -> u64 {
    splitmix(splitmix(seed ^ splitmix(photos as u64 + 0x524F_4F4D)) ^ splitmix(trial))
}

/// Options of [`run_room_trial`].
#[derive(Debug, Clone, PartialEq)]
pub struct RoomTrialOptions {
    /// Photos of each room, 1 to [`crate::synth::MAX_ROOM_PHOTOS`].
    pub photos: usize,
    /// Boxes in each room.
    pub boxes: usize,
    /// Noise levels, pixels.
    pub sigmas_px: Vec<f64>,
}

/// One object of a map against its truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomObjectErrors {
    /// Name.
    pub name: String,
    /// How many photos of the room list it.
    pub photos: usize,
    /// Distance from the map's centroid to the true centroid, metres.
    pub position_error_m: f64,
    /// `|L_m - L_a|` of the longer sides, metres.
    pub length_error_m: f64,
    /// `|B_m - B_a|` of the shorter sides, metres.
    pub breadth_error_m: f64,
    /// `|h_m - h_a|`, metres.
    pub height_error_m: f64,
    /// Whether the true centroid lies inside the map's 95 % ellipse (`None` without error bars
    /// or without noise).
    pub in_ellipse_95: Option<bool>,
    /// The squared Mahalanobis distance of the true centroid from the map's, in the map's
    /// centroid covariance (`None` without error bars or without noise).
    pub mahalanobis_sq: Option<f64>,
    /// The largest distance from a true footprint corner to the nearest of the map's, metres.
    pub corner_error_m: f64,
    /// Whether a warning of the map says the object's place or a size of it is uncertain
    /// ([`FloorMap::warns_uncertain`]).
    pub uncertainty_said: bool,
}

/// A map of the room (joint or one photo alone) against its truth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomMapErrors {
    /// Every object the map shows.
    pub objects: Vec<RoomObjectErrors>,
    /// Share of the true room's floor some photo of the map shows (its free space or a
    /// footprint, hidden or not), 0 to 1.
    pub floor_in_view: f64,
    /// Share of the true room's floor the map knows (free or occupied, not hidden), 0 to 1.
    pub floor_known: f64,
}

/// A shared object's joint position error beside its errors in each photo alone.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SharedObject {
    /// Name.
    pub name: String,
    /// Position error in the joint map, metres.
    pub joint_error_m: f64,
    /// Position error in each listing photo's map alone, metres (`None`: that map refused).
    pub single_errors_m: Vec<Option<f64>>,
    /// Position error in the joint map given every photo's true camera height (the photos
    /// alone have them), metres (`None`: that map refused).
    pub equal_information_error_m: Option<f64>,
    /// That map's position error in each listing photo's own frame, metres (in the order of
    /// `single_errors_m`).
    pub equal_information_in_frames_m: Vec<Option<f64>>,
}

impl SharedObject {
    /// The smaller of the single-photo errors (`None` when every single-photo map refused).
    #[must_use]
    pub fn best_single_m(&self) -> Option<f64> {
        self.single_errors_m
            .iter()
            .flatten()
            .copied()
            .reduce(f64::min)
    }

    /// Whether the joint error is below the best single-photo error.
    #[must_use]
    pub fn joint_better(&self) -> Option<bool> {
        self.best_single_m().map(|b| self.joint_error_m < b)
    }

    /// Whether the joint error with the same information (every camera height) is below the
    /// best single-photo error.
    #[must_use]
    pub fn equal_information_better(&self) -> Option<bool> {
        Some(self.equal_information_error_m? < self.best_single_m()?)
    }

    /// Per listing photo whose map alone and the equal-information joint map both show the
    /// object: whether the joint map's error in that photo's frame is below that photo's own.
    pub fn better_in_frames(&self) -> impl Iterator<Item = bool> + '_ {
        self.single_errors_m
            .iter()
            .zip(&self.equal_information_in_frames_m)
            .filter_map(|(s, j)| Some(j.as_ref()? < s.as_ref()?))
    }
}

/// One room at one noise level.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomEvaluation {
    /// The joint map of every photo.
    pub joint: RoomMapErrors,
    /// The map of the first photo alone (in the same frame, against the same room).
    pub first_photo: Result<RoomMapErrors, Failure>,
    /// Objects listed by two photos or more.
    pub shared: Vec<SharedObject>,
    /// Share of the room's floor under a box or seen past every box by some true camera
    /// ([`visible_floor_share`]): the most of the floor a map of these photos can know.
    pub floor_visible: f64,
    /// The same for the first camera alone.
    pub first_floor_visible: f64,
    /// The order the joint map was given the photos in (from 0; photo 0 first, the others
    /// shuffled, seeded by the room and the noise level).
    pub order: Vec<usize>,
    /// Whether the joint map says its placement is open: `alternatives` in the map, or a
    /// warning of a photo that fits about as well turned.
    pub tie_said: bool,
}

/// One noise level of a room trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomOutcome {
    /// Noise, pixels.
    pub sigma_px: f64,
    /// The evaluation, or why the joint map was refused.
    pub result: Result<RoomEvaluation, Failure>,
}

/// One room trial.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RoomTrial {
    /// Trial number.
    pub trial: u64,
    /// The room's seed ([`room_scene_seed`]).
    pub scene_seed: u64,
    /// Photos of the room.
    pub photos: usize,
    /// One outcome per noise level (empty when the room could not be drawn: see `draw`).
    pub outcomes: Vec<RoomOutcome>,
    /// Why the room could not be drawn, if so.
    pub draw: Option<Failure>,
}

/// Run one room trial (see the module's documentation).
#[must_use]
pub fn run_room_trial(seed: u64, trial: u64, options: &RoomTrialOptions) -> RoomTrial {
    let scene_seed = room_scene_seed(seed, options.photos, trial);
    let drawn = synthesize_room(&RoomSynthOptions {
        seed: scene_seed,
        photos: options.photos,
        boxes: options.boxes,
        ..RoomSynthOptions::default()
    });
    let (scene, truth) = match drawn {
        Ok(d) => d,
        Err(e) => {
            return RoomTrial {
                trial,
                scene_seed,
                photos: options.photos,
                outcomes: Vec::new(),
                draw: Some(Failure {
                    category: "scene_draw",
                    message: e.to_string(),
                }),
            };
        }
    };
    let images: Vec<_> = scene.photos().map(|p| p.image).collect();
    let all: Vec<usize> = (0..images.len()).collect();
    let visible = [
        visible_floor_share(&truth, &images, &all),
        visible_floor_share(&truth, &images, &[0]),
    ];
    let outcomes = options
        .sigmas_px
        .iter()
        .map(|&sigma_px| RoomOutcome {
            sigma_px,
            result: evaluate_noisy(&scene, &truth, sigma_px, scene_seed, visible),
        })
        .collect();
    RoomTrial {
        trial,
        scene_seed,
        photos: options.photos,
        outcomes,
        draw: None,
    }
}

fn failure(e: &crate::error::MetrologyError) -> Failure {
    Failure {
        category: failure_category(e),
        message: e.to_string(),
    }
}

/// The room with noise on every photo, mapped jointly and photo by photo, against its truth.
fn evaluate_noisy(
    scene: &Scene,
    truth: &RoomTruth,
    sigma_px: f64,
    scene_seed: u64,
    [floor_visible, first_floor_visible]: [f64; 2],
) -> Result<RoomEvaluation, Failure> {
    let photos: Vec<Scene> = scene
        .photos()
        .enumerate()
        .map(|(k, p)| {
            let mut alone = p.clone();
            alone.other_photos.clear();
            let seed = noise_seed(scene_seed ^ splitmix(k as u64), sigma_px);
            noisy_scene(&alone, sigma_px, seed)
        })
        .collect();
    let options = BuildOptions {
        click_sigma_px: Some(sigma_px),
        ..BuildOptions::default()
    };
    let mut room = photos.first().cloned().ok_or_else(|| Failure {
        category: "scene_draw",
        message: "a room without photos".to_owned(),
    })?;
    room.other_photos = photos.iter().skip(1).cloned().collect();
    // The joint map from the photos in a shuffled order (photo 1 sets the frame): the map may
    // not depend on it.
    let order = shuffled_order(photos.len(), splitmix(scene_seed ^ sigma_px.to_bits()));
    let mut shuffled = room.clone();
    shuffled.other_photos = order
        .iter()
        .skip(1)
        .filter_map(|&k| photos.get(k).cloned())
        .collect();
    let joint_map = build_map(&shuffled, &options).map_err(|e| failure(&e))?;
    let tie_said = !joint_map.alternatives.is_empty()
        || joint_map
            .warnings
            .iter()
            .any(|w| w.contains("about as well with photo"));
    let joint = map_errors(&joint_map, truth, &truth_objects(truth, None), sigma_px);
    // The same clicks with every photo's true camera height: what the photos alone know.
    let true_height = |k: usize| {
        Some(ScaleSpec {
            camera_height_m: truth.cameras.get(k).map(|c| c.height),
            ..ScaleSpec::default()
        })
    };
    let mut every_height = room.clone();
    every_height.scale = true_height(0);
    for (k, p) in every_height.other_photos.iter_mut().enumerate() {
        p.scale = true_height(k + 1);
    }
    let equal_map = build_map(&every_height, &options).ok();
    // Each photo alone, with its true camera height.
    let mut singles: Vec<Option<FloorMap>> = Vec::with_capacity(photos.len());
    let mut first_photo = None;
    for (k, p) in photos.iter().enumerate() {
        let mut alone = p.clone();
        alone.scale = true_height(k);
        let built = build_map(&alone, &options);
        if k == 0 {
            first_photo = Some(
                built
                    .as_ref()
                    .map(|m| map_errors(m, truth, &truth_objects(truth, Some(0)), sigma_px))
                    .map_err(failure),
            );
        }
        singles.push(built.ok());
    }
    let shared = truth
        .objects
        .iter()
        .filter(|o| o.photos.len() >= 2)
        .filter_map(|o| {
            let joint_error_m = joint
                .objects
                .iter()
                .find(|e| e.name == o.name)?
                .position_error_m;
            let single_errors_m = o
                .photos
                .iter()
                .map(|&k| {
                    let map = singles.get(k)?.as_ref()?;
                    let m = map.objects.iter().find(|m| m.name == o.name)?;
                    Some(distance(
                        centroid(&m.footprint)?,
                        true_centroid_seen_from(truth, k, &o.name)?,
                    ))
                })
                .collect();
            let equal_information_error_m = equal_map.as_ref().and_then(|m| {
                let e = m.objects.iter().find(|e| e.name == o.name)?;
                Some(distance(centroid(&e.footprint)?, centroid(&o.footprint)?))
            });
            let equal_information_in_frames_m = o
                .photos
                .iter()
                .map(|&k| {
                    let seen = seen_from(equal_map.as_ref()?, k, &o.name)?;
                    Some(distance(seen, true_centroid_seen_from(truth, k, &o.name)?))
                })
                .collect();
            Some(SharedObject {
                name: o.name.clone(),
                joint_error_m,
                single_errors_m,
                equal_information_error_m,
                equal_information_in_frames_m,
            })
        })
        .collect();
    Ok(RoomEvaluation {
        joint,
        first_photo: first_photo.unwrap_or_else(|| {
            Err(Failure {
                category: "scene_draw",
                message: "a room without photos".to_owned(),
            })
        }),
        shared,
        floor_visible,
        first_floor_visible,
        order,
        tie_said,
    })
}

/// `0, 1, ..., n - 1` with `1..n` shuffled (Fisher-Yates on SplitMix64 draws from `seed`).
fn shuffled_order(n: usize, seed: u64) -> Vec<usize> {
    let mut order: Vec<usize> = (0..n).collect();
    let mut state = seed;
    for i in (2..n).rev() {
        state = splitmix(state);
        let j = 1 + (state % i as u64) as usize;
        order.swap(i, j);
    }
    order
}

/// Object `name`'s true footprint centroid in photo `k`'s own plan frame.
fn true_centroid_seen_from(truth: &RoomTruth, k: usize, name: &str) -> Option<[f64; 2]> {
    let t = truth
        .photos
        .get(k)?
        .objects
        .iter()
        .find(|t| t.name == name)?;
    centroid(&t.footprint)
}

/// Object `name`'s footprint centroid in photo `k`'s own plan frame (origin under its camera,
/// `+y` its viewing direction), from a room map's placed camera `k`.
fn seen_from(map: &FloorMap, k: usize, name: &str) -> Option<[f64; 2]> {
    let camera = map.cameras.get(k)?;
    let (s, c) = camera.heading_deg.unwrap_or(0.0).to_radians().sin_cos();
    let p = centroid(&map.objects.iter().find(|m| m.name == name)?.footprint)?;
    let d = [p[0] - camera.position[0], p[1] - camera.position[1]];
    // Rotate the room-frame offset by minus the heading (counter-clockwise from +y).
    Some([c * d[0] + s * d[1], -s * d[0] + c * d[1]])
}

/// The room's true objects a map should show: every one, or those photo `k` lists.
fn truth_objects(truth: &RoomTruth, photo: Option<usize>) -> Vec<&crate::synth::RoomTruthObject> {
    truth
        .objects
        .iter()
        .filter(|o| photo.is_none_or(|k| o.photos.contains(&k)))
        .collect()
}

fn ring(points: &[MapPoint]) -> LineString<f64> {
    LineString::from(
        points
            .iter()
            .map(|p| Coord { x: p[0], y: p[1] })
            .collect::<Vec<_>>(),
    )
}

fn polygon(points: &[MapPoint]) -> Polygon<f64> {
    Polygon::new(ring(points), vec![])
}

fn centroid(points: &[MapPoint]) -> Option<[f64; 2]> {
    polygon(points).centroid().map(|c| [c.x(), c.y()])
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The longer and shorter of a quadrilateral's first two sides.
fn long_short(points: &[MapPoint]) -> Option<(f64, f64)> {
    let a = distance(*points.first()?, *points.get(1)?);
    let b = distance(*points.get(1)?, *points.get(2)?);
    Some((a.max(b), a.min(b)))
}

/// Share of the true room's floor a map knows: inside its free space or a footprint, outside
/// its hidden regions.
#[must_use]
pub fn floor_known_share(map: &FloorMap, room: &[MapPoint]) -> f64 {
    floor_shares(map, room).1
}

/// A map region as a polygon with its holes.
fn with_holes(p: &crate::map::PolygonWithHoles) -> Polygon<f64> {
    Polygon::new(ring(&p.exterior), p.holes.iter().map(|h| ring(h)).collect())
}

/// Shares of the true room's floor inside the map's free space or a footprint (the floor some
/// photo shows), and of that outside the hidden regions (the floor known).
fn floor_shares(map: &FloorMap, room: &[MapPoint]) -> (f64, f64) {
    let room = MultiPolygon::new(vec![polygon(room)]);
    let area = room.unsigned_area();
    if area <= 0.0 {
        return (0.0, 0.0);
    }
    let mut in_view: Vec<Polygon<f64>> = map.free_space.iter().map(with_holes).collect();
    in_view.extend(map.objects.iter().map(|o| polygon(&o.footprint)));
    let in_view = geo::unary_union(&in_view).intersection(&room);
    let hidden = MultiPolygon::new(map.hidden.iter().map(with_holes).collect());
    let known = in_view.difference(&hidden);
    (
        (in_view.unsigned_area() / area).clamp(0.0, 1.0),
        (known.unsigned_area() / area).clamp(0.0, 1.0),
    )
}

/// A map's objects (those of `expected` it shows) against the truth, in the first photo's
/// frame.
fn map_errors(
    map: &FloorMap,
    truth: &RoomTruth,
    expected: &[&crate::synth::RoomTruthObject],
    sigma_px: f64,
) -> RoomMapErrors {
    let objects = expected
        .iter()
        .filter_map(|t| {
            let m = map.objects.iter().find(|m| m.name == t.name)?;
            let (cm, ct) = (centroid(&m.footprint)?, centroid(&t.footprint)?);
            let (lm, bm) = long_short(&m.footprint)?;
            let (lt, bt) = long_short(&t.footprint)?;
            let mahalanobis_sq = m.uncertainty.as_ref().filter(|_| sigma_px > 0.0).map(|u| {
                let c = u.centroid_covariance;
                let d = [cm[0] - ct[0], cm[1] - ct[1]];
                let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
                if det > 0.0 {
                    (c[1][1] * d[0] * d[0] - 2.0 * c[0][1] * d[0] * d[1] + c[0][0] * d[1] * d[1])
                        / det
                } else {
                    f64::INFINITY
                }
            });
            let in_ellipse_95 = mahalanobis_sq.map(|m2| m2 <= CHI2_2DOF_95);
            let corner_error_m = t
                .footprint
                .iter()
                .map(|c| {
                    m.footprint
                        .iter()
                        .map(|p| distance(*p, *c))
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0, f64::max);
            Some(RoomObjectErrors {
                name: t.name.clone(),
                photos: t.photos.len(),
                position_error_m: distance(cm, ct),
                length_error_m: (lm - lt).abs(),
                breadth_error_m: (bm - bt).abs(),
                height_error_m: (m.height.unwrap_or(f64::NAN) - t.height).abs(),
                in_ellipse_95,
                mahalanobis_sq,
                corner_error_m,
                uncertainty_said: map.warns_uncertain(&t.name),
            })
        })
        .collect();
    let (floor_in_view, floor_known) = floor_shares(map, &truth.room);
    RoomMapErrors {
        objects,
        floor_in_view,
        floor_known,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_clicks_give_zero_errors_and_a_joint_map_that_knows_more_floor() {
        let trial = run_room_trial(
            3,
            0,
            &RoomTrialOptions {
                photos: 3,
                boxes: 6,
                sigmas_px: vec![0.0],
            },
        );
        assert!(trial.draw.is_none());
        let ev = trial.outcomes[0].result.as_ref().unwrap();
        assert!(!ev.joint.objects.is_empty());
        for o in &ev.joint.objects {
            assert!(o.position_error_m < 1e-6, "{o:?}");
            assert!(o.height_error_m < 1e-6, "{o:?}");
            assert_eq!(o.in_ellipse_95, None);
        }
        let first = ev.first_photo.as_ref().unwrap();
        assert!(ev.joint.floor_known > first.floor_known, "{ev:?}");
        assert!(ev.joint.floor_known <= 1.0 && first.floor_known > 0.0);
        assert!(!ev.shared.is_empty());
        // Every shared object seen from each listing camera of the map with every camera
        // height, against the truth in that photo's own frame.
        let mut in_frames = 0;
        for o in &ev.shared {
            assert!(
                o.equal_information_error_m.is_some_and(|e| e < 1e-6),
                "{o:?}"
            );
            for e in &o.equal_information_in_frames_m {
                assert!(e.is_some_and(|e| e < 1e-6), "{o:?}");
                in_frames += 1;
            }
        }
        assert!(in_frames >= 2 * ev.shared.len());
    }

    #[test]
    fn the_floor_known_is_the_room_inside_free_space_or_footprints_outside_hidden() {
        let (scene, truth) = synthesize_room(&RoomSynthOptions {
            photos: 1,
            seed: 2,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        let map = build_map(&scene, &BuildOptions::default()).unwrap();
        let share = floor_known_share(&map, &truth.room);
        // Independently: the free area inside the room, plus footprints, over the room.
        let room = polygon(&truth.room);
        let area_in_room = |regions: &[crate::map::PolygonWithHoles]| -> f64 {
            regions
                .iter()
                .map(|p| with_holes(p).intersection(&room).unsigned_area())
                .sum()
        };
        let (free, hidden) = (area_in_room(&map.free_space), area_in_room(&map.hidden));
        assert!(hidden > 0.0, "a box's shadow hides some floor");
        let feet: f64 = map
            .objects
            .iter()
            .map(|o| polygon(&o.footprint).intersection(&room).unsigned_area())
            .sum();
        // Footprints are cut out of the free space, and the hidden regions lie inside it.
        let expected = (free - hidden + feet) / room.unsigned_area();
        assert!((share - expected).abs() < 1e-6, "{share} vs {expected}");
        assert!(share > 0.1 && share < 1.0, "{share}");
    }
}
