//! The room synthesizer ([`vpmap_metrology::synth::synthesize_room`]) against the joint fit:
//! every room file validates, every photo alone builds and matches its own truth, and the
//! joint fit of the room reproduces the truth from exact clicks (an independent check of the
//! lead's fit: the synthesizer shares only the scene types with it).

use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::{ScaleSpec, Scene};
use vpmap_metrology::synth::{RoomSynthOptions, RoomTruth, synthesize_room};

use crate::{assert_camera_matches, max_relative_error};

/// Largest distance from a true corner to the nearest corner of the map's object, and the
/// height error, metres (the map names a box's corners as the first photo that shows it).
pub fn room_error(map: &FloorMap, truth: &RoomTruth) -> f64 {
    assert_eq!(map.objects.len(), truth.objects.len());
    let mut worst = 0.0f64;
    for t in &truth.objects {
        let m = map
            .objects
            .iter()
            .find(|o| o.name == t.name)
            .unwrap_or_else(|| panic!("object {} missing", t.name));
        for c in &t.footprint {
            let d = m
                .footprint
                .iter()
                .map(|p| (p[0] - c[0]).hypot(p[1] - c[1]))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        worst = worst.max((m.height.unwrap() - t.height).abs());
    }
    assert_eq!(map.cameras.len(), truth.cameras.len());
    for (m, t) in map.cameras.iter().zip(&truth.cameras) {
        worst = worst
            .max((m.position[0] - t.position[0]).abs())
            .max((m.position[1] - t.position[1]).abs())
            .max((m.height - t.height).abs());
        let turn = (m.heading_deg.unwrap() - t.heading_deg + 540.0).rem_euclid(360.0) - 180.0;
        assert!(turn.abs() < 1e-7, "heading {turn} deg off");
    }
    worst
}

/// Photo `k` of a room as a single-photo scene, with its true camera height as its scale.
fn photo_alone(scene: &Scene, truth: &RoomTruth, k: usize) -> Scene {
    let mut p = scene.photos().nth(k).unwrap().clone();
    p.other_photos.clear();
    p.scale = Some(ScaleSpec {
        camera_height_m: Some(truth.cameras[k].height),
        ..ScaleSpec::default()
    });
    p
}

#[test]
fn synthetic_rooms_from_exact_clicks_reproduce_the_truth_to_1e_9_m() {
    for photos in 2..=4 {
        for seed in 0..4 {
            let context = format!("{photos} photos, seed {seed}");
            let (scene, truth) = synthesize_room(&RoomSynthOptions {
                seed,
                photos,
                ..RoomSynthOptions::default()
            })
            .unwrap();
            // The room file validates and reads back as the same room.
            let read = Scene::from_json_str(&scene.to_json_string())
                .unwrap_or_else(|e| panic!("{context}: {e}"));
            assert_eq!(read.photo_count(), photos, "{context}");
            // (serde_json reads floats back to within an ulp, not always exactly.)
            let names = |s: &Scene| -> Vec<Vec<String>> {
                s.photos()
                    .map(|p| p.objects.iter().map(|o| o.name.clone()).collect())
                    .collect()
            };
            assert_eq!(names(&read), names(&scene), "{context}");
            // Only the first photo carries the scale.
            assert!(read.scale.is_some(), "{context}");
            assert!(
                read.other_photos.iter().all(|p| p.scale.is_none()),
                "{context}"
            );
            // Each photo alone builds and matches its own truth.
            for k in 0..photos {
                let alone = photo_alone(&read, &truth, k);
                let map = build_map(&alone, &BuildOptions::default())
                    .unwrap_or_else(|e| panic!("{context}, photo {k} alone: {e}"));
                let e = max_relative_error(&map, &truth.photos[k]);
                assert!(e < 1e-9, "{context}, photo {k} alone: {e}");
                assert_camera_matches(&map, &truth.photos[k], &context);
            }
            // The joint fit.
            let map = build_map(&read, &BuildOptions::default())
                .unwrap_or_else(|e| panic!("{context}: {e}"));
            let e = room_error(&map, &truth);
            assert!(
                e < 1e-9,
                "{context}: worst {e:e} m; warnings {:?}",
                map.warnings
            );
        }
    }
}

#[test]
fn synthetic_rooms_tie_every_photo_to_the_ones_before() {
    for photos in 1..=4 {
        for seed in 0..8 {
            let (scene, truth) = synthesize_room(&RoomSynthOptions {
                seed,
                photos,
                ..RoomSynthOptions::default()
            })
            .unwrap();
            let names: Vec<Vec<&str>> = scene
                .photos()
                .map(|p| p.objects.iter().map(|o| o.name.as_str()).collect())
                .collect();
            assert!(names[0].len() >= 2);
            for k in 1..photos {
                let shared = names[k]
                    .iter()
                    .filter(|n| names[..k].iter().any(|e| e.contains(n)))
                    .count();
                assert!(shared >= 2, "seed {seed}, photo {k}: {shared} shared");
            }
            for o in &truth.objects {
                let listed: Vec<usize> = (0..photos)
                    .filter(|&k| names[k].contains(&o.name.as_str()))
                    .collect();
                assert_eq!(listed, o.photos, "seed {seed}, {}", o.name);
            }
            // Every clicked base corner inside the image.
            for p in scene.photos() {
                for o in &p.objects {
                    for (_, c) in o.base.as_ref().unwrap().given() {
                        assert!((0.0..=1600.0).contains(&c[0]) && (0.0..=1200.0).contains(&c[1]));
                    }
                }
            }
        }
    }
}

#[test]
fn synthetic_rooms_are_pure_functions_of_their_options() {
    let opts = RoomSynthOptions {
        seed: 7,
        noise_px: 1.0,
        ..RoomSynthOptions::default()
    };
    let a = synthesize_room(&opts).unwrap();
    assert_eq!(a, synthesize_room(&opts).unwrap());
    let exact = synthesize_room(&RoomSynthOptions {
        noise_px: 0.0,
        ..opts.clone()
    })
    .unwrap();
    // Noise moves the clicks, not the room.
    assert_eq!(a.1, exact.1);
    assert_ne!(a.0, exact.0);
    assert!(
        synthesize_room(&RoomSynthOptions {
            photos: vpmap_metrology::synth::MAX_ROOM_PHOTOS + 1,
            ..opts.clone()
        })
        .is_err()
    );
    assert!(synthesize_room(&RoomSynthOptions { photos: 0, ..opts }).is_err());
}

#[test]
fn the_bundled_room_example_builds_and_matches_its_truth() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let scene =
        Scene::from_json_str(&std::fs::read_to_string(dir.join("room.json")).unwrap()).unwrap();
    let truth: RoomTruth =
        serde_json::from_str(&std::fs::read_to_string(dir.join("room.truth.json")).unwrap())
            .unwrap();
    assert_eq!(scene.photo_count(), 3);
    let map = build_map(&scene, &BuildOptions::default()).unwrap();
    // Its clicks are exact.
    let e = room_error(&map, &truth);
    assert!(e < 1e-9, "worst {e:e} m");
    // It is what `vpmap synth --photos 3 --seed 4` draws.
    let (_, drawn) = synthesize_room(&RoomSynthOptions {
        seed: 4,
        photos: 3,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    assert_eq!(drawn.objects.len(), truth.objects.len());
    for (a, b) in drawn.objects.iter().zip(&truth.objects) {
        assert_eq!(a.name, b.name);
        for (p, q) in a.footprint.iter().zip(&b.footprint) {
            assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
        }
    }
}

#[test]
fn known_camera_heights_are_held_when_the_clicks_agree_and_not_when_they_contradict() {
    let options = BuildOptions {
        click_sigma_px: Some(1.0),
        ..BuildOptions::default()
    };
    let (mut held_true, mut held_wrong, mut rooms) = (0, 0, 0);
    for seed in 0..12 {
        let (scene, truth) = synthesize_room(&RoomSynthOptions {
            photos: 3,
            seed,
            noise_px: 1.0,
            scale_every_photo: true,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        let Ok(map) = build_map(&scene, &options) else {
            continue;
        };
        rooms += 1;
        // Held: the camera stands exactly as high as its photo says, with no error bar.
        let held = |m: &FloorMap, k: usize, h: f64| {
            (m.cameras[k].height - h).abs() < 1e-9
                && m.cameras[k].uncertainty.as_ref().unwrap().height_sd < 1e-9
        };
        held_true += usize::from((1..3).all(|k| held(&map, k, truth.cameras[k].height)));
        // Photo 3 says its camera is 25 % higher than it is.
        let mut wrong = scene.clone();
        let h = truth.cameras[2].height * 1.25;
        wrong.other_photos[1].scale = Some(ScaleSpec {
            camera_height_m: Some(h),
            ..ScaleSpec::default()
        });
        let map = build_map(&wrong, &options).unwrap();
        held_wrong += usize::from(held(&map, 2, h));
        assert!(
            map.warnings
                .iter()
                .any(|w| w.contains("disagree") && w.contains("photo 3's camera height")),
            "seed {seed}: {:?}",
            map.warnings
        );
    }
    assert!(rooms >= 10, "{rooms} rooms built");
    // A likelihood-ratio test at 1 %: the true heights are held in (nearly) every room.
    assert!(
        held_true + 1 >= rooms,
        "true heights held in {held_true} of {rooms}"
    );
    assert_eq!(held_wrong, 0, "a wrong height was held");
}

#[test]
fn synthetic_rooms_give_the_same_map_for_every_order_of_photos_2_to_n() {
    use crate::rooms::{map_difference, permutations};
    for photos in 3..=4 {
        for seed in 0..3 {
            let (scene, truth) = synthesize_room(&RoomSynthOptions {
                seed,
                photos,
                ..RoomSynthOptions::default()
            })
            .unwrap();
            let reference = build_map(&scene, &BuildOptions::default()).unwrap();
            let rest: Vec<usize> = (0..photos - 1).collect();
            for order in permutations(&rest) {
                let mut s = scene.clone();
                s.other_photos = order
                    .iter()
                    .map(|&k| scene.other_photos[k].clone())
                    .collect();
                let context = format!("{photos} photos, seed {seed}, order {order:?}");
                let map = build_map(&s, &BuildOptions::default())
                    .unwrap_or_else(|e| panic!("{context}: {e}"));
                let d = map_difference(&map, &reference);
                assert!(d < 1e-9, "{context}: {d} m from the synthesizer's order");
                // Each the truth too (room_error needs the cameras in the truth's order).
                let mut t = truth.clone();
                t.cameras = std::iter::once(truth.cameras[0].clone())
                    .chain(order.iter().map(|&k| truth.cameras[k + 1].clone()))
                    .collect();
                let e = room_error(&map, &t);
                assert!(e < 1e-9, "{context}: {e} m from the truth");
            }
        }
    }
}

#[test]
fn a_photo_tied_to_the_first_by_one_box_is_placed_by_its_ties_to_the_others_in_every_order() {
    // Issue 39: photo k tied to photo 1 by one box only (a box fits as well turned by half a
    // turn about its centre), but to the other photos by boxes of their own: the whole room
    // decides its turn, whatever the order the photos are listed in.
    use crate::rooms::{map_difference, permutations};
    let mut cases = 0;
    for seed in 0..1 {
        let (scene, truth) = synthesize_room(&RoomSynthOptions {
            seed,
            photos: 4,
            boxes: 8,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        let names =
            |s: &Scene| -> Vec<String> { s.objects.iter().map(|o| o.name.clone()).collect() };
        let first = names(&scene);
        for k in 0..3 {
            let photo = &scene.other_photos[k];
            let with_first: Vec<String> = names(photo)
                .into_iter()
                .filter(|n| first.contains(n))
                .collect();
            for keep in &with_first {
                let mut s = scene.clone();
                for o in &mut s.other_photos[k].objects {
                    if first.contains(&o.name) && &o.name != keep {
                        o.name = format!("{} (only in photo {})", o.name, k + 2);
                    }
                }
                // Still tied to another photo by a box of its own.
                let others: Vec<String> = (0..3)
                    .filter(|&j| j != k)
                    .flat_map(|j| names(&s.other_photos[j]))
                    .collect();
                let own_ties = names(&s.other_photos[k])
                    .iter()
                    .filter(|n| *n != keep && others.contains(n))
                    .count();
                if own_ties == 0 {
                    continue;
                }
                cases += 1;
                let reference = build_map(&s, &BuildOptions::default())
                    .unwrap_or_else(|e| panic!("seed {seed} photo {} by {keep}: {e}", k + 2));
                for order in permutations(&[0usize, 1, 2]) {
                    let mut o = s.clone();
                    o.other_photos = order.iter().map(|&j| s.other_photos[j].clone()).collect();
                    let map = build_map(&o, &BuildOptions::default()).unwrap();
                    let context = format!(
                        "seed {seed}, photo {} tied to photo 1 by {keep}, order {order:?}",
                        k + 2
                    );
                    let d = map_difference(&map, &reference);
                    assert!(d < 1e-9, "{context}: {d} m from the first order");
                    let i = order.iter().position(|&j| j == k).unwrap();
                    let (p, t) = (map.cameras[i + 1].position, truth.cameras[k + 1].position);
                    let off = (p[0] - t[0]).hypot(p[1] - t[1]);
                    assert!(off < 1e-9, "{context}: camera {off} m off");
                }
            }
        }
    }
    println!("{cases} rooms with a photo tied to the first by one box");
    assert!(cases >= 5, "{cases}");
}

/// Synthetic room `seed` of four photos with photo `k + 2` (`other_photos[k]`) tied to photo 1
/// by box `keep` alone: its other objects dropped, and no photo's floor outline, so that no
/// wall, overlap or camera can tell its two half turns apart about `keep`'s centre, each of
/// which reproduces its exact clicks exactly.
fn exact_symmetric_tie(seed: u64, k: usize, keep: &str) -> (Scene, RoomTruth) {
    let (mut scene, truth) = synthesize_room(&RoomSynthOptions {
        seed,
        photos: 4,
        boxes: 8,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    // One other box of the photo's is seen by it alone (taken out of the other photos).
    let own = scene.other_photos[k]
        .objects
        .iter()
        .map(|o| o.name.clone())
        .find(|n| n != keep)
        .unwrap();
    scene.objects.retain(|o| o.name != own);
    for (j, p) in scene.other_photos.iter_mut().enumerate() {
        if j != k {
            p.objects.retain(|o| o.name != own);
        }
    }
    let photo = &mut scene.other_photos[k];
    photo.objects.retain(|o| o.name == keep || o.name == own);
    photo.click_covariances_px2.clear();
    scene.floor.clear();
    for p in &mut scene.other_photos {
        p.floor.clear();
    }
    (scene, truth)
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn an_exact_symmetric_tie_is_chosen_and_said_alike_for_every_order_of_photos_2_to_n() {
    // Issue 39: two placements that reproduce the exact clicks exactly (photo k + 2 tied by
    // one box, either half turn about the box's centre) have costs float noise apart, and the
    // noise follows the order the photos are listed in. The map and its alternative must not:
    // every order of photos 2..4 gives the same boxes and cameras to 1e-9 m and names the same
    // photo and turn as the alternative. Checked against the synthesizer's truth: the tied
    // photo's camera and its own box are either true or turned by a half turn about the
    // shared box's true centre, and the firmly tied photos are true.
    use crate::rooms::{map_difference, permutations};
    for (seed, k, keep) in [(3, 1, "box6"), (4, 0, "box6"), (3, 0, "box3")] {
        let (scene, truth) = exact_symmetric_tie(seed, k, keep);
        let own = scene.other_photos[k]
            .objects
            .iter()
            .find(|o| o.name != keep)
            .unwrap()
            .name
            .clone();
        let centre = |name: &str| {
            let o = truth.objects.iter().find(|o| o.name == name).unwrap();
            let n = o.footprint.len() as f64;
            [
                o.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
                o.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
            ]
        };
        let c = centre(keep);
        let turned = |p: [f64; 2]| [2.0 * c[0] - p[0], 2.0 * c[1] - p[1]];
        let mut first: Option<(FloorMap, [f64; 2], i32)> = None;
        for order in permutations(&[0usize, 1, 2]) {
            let context = format!(
                "seed {seed}, photo {} tied by {keep}, order {order:?}",
                k + 2
            );
            let mut s = scene.clone();
            s.other_photos = order
                .iter()
                .map(|&j| scene.other_photos[j].clone())
                .collect();
            let map = build_map(&s, &BuildOptions::default())
                .unwrap_or_else(|e| panic!("{context}: {e}"));
            // The tied photo, where this order lists it.
            let i = order.iter().position(|&j| j == k).unwrap() + 1;
            let here = [map.cameras[i].position[0], map.cameras[i].position[1]];
            let t = truth.cameras[k + 1].position;
            assert!(
                distance(here, t) < 1e-9 || distance(here, turned(t)) < 1e-9,
                "{context}: camera at {here:?}, neither {t:?} nor {:?}",
                turned(t)
            );
            let o = map.objects.iter().find(|o| o.name == own).unwrap();
            let (at, true_at) = ([o.centroid[0], o.centroid[1]], centre(&own));
            assert!(
                distance(at, true_at) < 1e-9 || distance(at, turned(true_at)) < 1e-9,
                "{context}: {own} at {at:?}"
            );
            for (m, &j) in order.iter().enumerate().filter(|&(_, &j)| j != k) {
                let p = [
                    map.cameras[m + 1].position[0],
                    map.cameras[m + 1].position[1],
                ];
                let t = truth.cameras[j + 1].position;
                assert!(distance(p, t) < 1e-9, "{context}: photo {} at {p:?}", j + 2);
            }
            // The other half turn is said, for the tied photo.
            assert_eq!(map.alternatives.len(), 1, "{context}: {:?}", map.warnings);
            let alt = &map.alternatives[0];
            assert_eq!((alt.photo, alt.turn_deg), (i + 1, 180), "{context}");
            match &first {
                None => first = Some((map.clone(), here, alt.placement_turn_deg)),
                Some((reference, camera, placement_turn_deg)) => {
                    let d = map_difference(&map, reference);
                    assert!(d < 1e-9, "{context}: boxes {d} m from the first order's");
                    let d = distance(here, *camera);
                    assert!(
                        d < 1e-9,
                        "{context}: tied camera {d} m from the first order's"
                    );
                    assert_eq!(
                        alt.placement_turn_deg, *placement_turn_deg,
                        "{context}: another alternative than the first order's"
                    );
                }
            }
        }
    }
}

#[test]
#[ignore = "a measurement, 618 builds (minutes in debug): cargo test -p vpmap-metrology --release --test it experiment_exact_one_box_ties -- --ignored --nocapture"]
fn experiment_exact_one_box_ties_are_chosen_alike_in_every_order_of_photos_2_to_n() {
    // Every one-box tie of six synthetic rooms of four photos (each photo after the first tied
    // to photo 1 by each box it shares with it, as `exact_symmetric_tie` makes it), every
    // order of photos 2..4: the same boxes and tied camera to 1e-9 m and the same alternatives
    // (photo and `placement_turn_deg`, the photo named as in the first order) as the first
    // order. Measured 2026-11-29: 103 rooms (86 with a tie left open), 0 differ; before the
    // canonical choice (`room/canonical.rs`) 51 differed in some order.
    use crate::rooms::{map_difference, permutations};
    let (mut cases, mut open, mut differ) = (0, 0, Vec::new());
    for seed in 0..6 {
        let (scene, _) = synthesize_room(&RoomSynthOptions {
            seed,
            photos: 4,
            boxes: 8,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        let first: Vec<String> = scene.objects.iter().map(|o| o.name.clone()).collect();
        for k in 0..3 {
            let shared: Vec<String> = scene.other_photos[k]
                .objects
                .iter()
                .map(|o| o.name.clone())
                .filter(|n| first.contains(n))
                .collect();
            for keep in &shared {
                let context = format!("seed {seed}, photo {} tied by {keep}", k + 2);
                let (s, _) = exact_symmetric_tie(seed, k, keep);
                let reference = build_map(&s, &BuildOptions::default())
                    .unwrap_or_else(|e| panic!("{context}: {e}"));
                cases += 1;
                open += usize::from(!reference.alternatives.is_empty());
                let said = |m: &FloorMap, order: &[usize]| -> Vec<(usize, i32)> {
                    m.alternatives
                        .iter()
                        .map(|a| (order[a.photo - 2] + 2, a.placement_turn_deg))
                        .collect()
                };
                let first_said = said(&reference, &[0, 1, 2]);
                for order in permutations(&[0usize, 1, 2]) {
                    let mut o = s.clone();
                    o.other_photos = order.iter().map(|&j| s.other_photos[j].clone()).collect();
                    let map = build_map(&o, &BuildOptions::default())
                        .unwrap_or_else(|e| panic!("{context}, order {order:?}: {e}"));
                    let i = order.iter().position(|&j| j == k).unwrap() + 1;
                    let (p, q) = (map.cameras[i].position, reference.cameras[k + 1].position);
                    let d = map_difference(&map, &reference).max((p[0] - q[0]).hypot(p[1] - q[1]));
                    if d > 1e-9 || said(&map, &order) != first_said {
                        differ.push(format!("{context}, order {order:?}: {d} m"));
                    }
                }
            }
        }
    }
    println!(
        "{cases} rooms with a one-box tie ({open} left open), {} orders differ from the first: {differ:#?}",
        differ.len()
    );
    assert!(cases >= 100, "{cases}");
    assert!(differ.is_empty());
}

/// Synthetic room `seed` of four photos in which each photo after the first is tied to photo 1
/// by one box alone (a box of its own choosing, `None` when the room has too few) and sees one
/// more box nobody else sees; no floor outlines. Each of the three photos fits its exact
/// clicks exactly at either half turn about its box's centre: `2^3 = 8` whole-room placements
/// tie, more than the joint fit starts from.
fn three_one_box_ties(seed: u64) -> Option<Scene> {
    let (mut scene, _) = synthesize_room(&RoomSynthOptions {
        seed,
        photos: 4,
        boxes: 8,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    let names = |s: &Scene| -> Vec<String> { s.objects.iter().map(|o| o.name.clone()).collect() };
    let first = names(&scene);
    let mut used: Vec<String> = Vec::new();
    let mut picks = Vec::new();
    for k in 0..3 {
        let mine = names(&scene.other_photos[k]);
        let keep = mine
            .iter()
            .find(|n| first.contains(n) && !used.contains(n))?
            .clone();
        used.push(keep.clone());
        let own = mine.iter().find(|n| !used.contains(n))?.clone();
        used.push(own.clone());
        picks.push((keep, own));
    }
    let owns: Vec<&String> = picks.iter().map(|(_, own)| own).collect();
    scene.objects.retain(|o| !owns.contains(&&o.name));
    scene.floor.clear();
    for (k, p) in scene.other_photos.iter_mut().enumerate() {
        let (keep, own) = &picks[k];
        p.objects.retain(|o| &o.name == keep || &o.name == own);
        p.click_covariances_px2.clear();
        p.floor.clear();
    }
    Some(scene)
}

/// Synthetic room `seed` of four photos tied in a chain by one box a link: photo 2 to photo 1
/// by box A, photo 3 to photo 2 by box B, photo 4 to photo 3 by box D (B and D unseen by
/// photo 1, so their place among the room's objects follows the order the photos are listed
/// in), photo 4 with a box of its own; no floor outlines. Each link fits the exact clicks
/// exactly at either half turn: `2^3 = 8` whole-room placements tie. `None` when the room
/// has no such chain.
fn chain_of_one_box_ties(seed: u64) -> Option<Scene> {
    chain_of_ties(seed, 4, 8)
}

/// As [`chain_of_one_box_ties`] for a room of `photos` photos and `boxes` boxes: photo
/// `k + 1` tied to photo `k` by one box a link, the last photo with a box of its own;
/// `2^(photos - 1)` whole-room placements tie.
fn chain_of_ties(seed: u64, photos: usize, boxes: usize) -> Option<Scene> {
    let (mut scene, _) = synthesize_room(&RoomSynthOptions {
        seed,
        photos,
        boxes,
        ..RoomSynthOptions::default()
    })
    .unwrap();
    let names = |s: &Scene| -> Vec<String> { s.objects.iter().map(|o| o.name.clone()).collect() };
    let seen: Vec<Vec<String>> = std::iter::once(names(&scene))
        .chain(scene.other_photos.iter().map(names))
        .collect();
    let mut links: Vec<String> = Vec::new();
    for k in 0..photos - 1 {
        let link = seen[k + 1]
            .iter()
            .find(|n| seen[k].contains(n) && !links.contains(n))?
            .clone();
        links.push(link);
    }
    let own = seen[photos - 1]
        .iter()
        .find(|n| !links.contains(n))?
        .clone();
    scene
        .objects
        .retain(|o| !links[1..].contains(&o.name) && o.name != own);
    scene.floor.clear();
    for (k, p) in scene.other_photos.iter_mut().enumerate() {
        // Photo k + 2 keeps its links to photos k + 1 and k + 3 (and the last its own box).
        let keep: Vec<&String> = [
            links.get(k),
            links.get(k + 1),
            (k + 2 == photos).then_some(&own),
        ]
        .into_iter()
        .flatten()
        .collect();
        p.objects.retain(|o| keep.contains(&&o.name));
        p.click_covariances_px2.clear();
        p.floor.clear();
    }
    Some(scene)
}

/// The map's alternatives as (the photo's place in `scene_order`'s listing, counted from 2,
/// its `placement_turn_deg`), sorted; `order[i]` is the listing place of the map's photo
/// `i + 2`.
fn alternatives_said(map: &FloorMap, order: &[usize]) -> Vec<(usize, i32)> {
    let mut said: Vec<(usize, i32)> = map
        .alternatives
        .iter()
        .map(|a| (order[a.photo - 2] + 2, a.placement_turn_deg))
        .collect();
    said.sort_unstable();
    said
}

/// Over every order of photos 2..4 of `scene`, the orders whose map differs from the first
/// order's (boxes or cameras beyond 1e-9 m, or other alternatives said); also whether the
/// first order's map left a tie open.
fn orders_that_differ(scene: &Scene, context: &str) -> (Vec<String>, bool) {
    use crate::rooms::permutations;
    let orders = permutations(&(0..scene.other_photos.len()).collect::<Vec<usize>>());
    orders_of_that_differ(scene, &orders, context)
}

/// Some orders of `m` photos after the first: the file's first, then reversed, every
/// rotation, evens before odds and the two halves exchanged (`m + 2` or fewer, each once).
fn sampled_orders(m: usize) -> Vec<Vec<usize>> {
    let first: Vec<usize> = (0..m).collect();
    let mut orders = vec![first.clone(), first.iter().rev().copied().collect()];
    for r in 1..m {
        let mut o = first.clone();
        o.rotate_left(r);
        orders.push(o);
    }
    orders.push((0..m).step_by(2).chain((1..m).step_by(2)).collect());
    orders.push((m / 2..m).chain(0..m / 2).collect());
    let mut unique: Vec<Vec<usize>> = Vec::new();
    for o in orders {
        if !unique.contains(&o) {
            unique.push(o);
        }
    }
    unique
}

/// As [`orders_that_differ`] over `orders` of photos 2..n (each a permutation of `0..n - 1`,
/// the first compared with).
fn orders_of_that_differ(
    scene: &Scene,
    orders: &[Vec<usize>],
    context: &str,
) -> (Vec<String>, bool) {
    use crate::rooms::map_difference;
    let reorder = |order: &[usize]| {
        let mut s = scene.clone();
        s.other_photos = order
            .iter()
            .map(|&j| scene.other_photos[j].clone())
            .collect();
        s
    };
    let (first, rest) = orders.split_first().expect("at least one order");
    let reference = build_map(&reorder(first), &BuildOptions::default())
        .unwrap_or_else(|e| panic!("{context}, order {first:?}: {e}"));
    let first_said = alternatives_said(&reference, first);
    // Where photo j of the scene stands in the first order.
    let mut first_place = vec![0; first.len()];
    for (i, &j) in first.iter().enumerate() {
        first_place[j] = i;
    }
    let mut differ = Vec::new();
    for order in rest {
        let map = build_map(&reorder(order), &BuildOptions::default())
            .unwrap_or_else(|e| panic!("{context}, order {order:?}: {e}"));
        let mut d = map_difference(&map, &reference);
        for (i, &j) in order.iter().enumerate() {
            let (p, q) = (
                map.cameras[i + 1].position,
                reference.cameras[first_place[j] + 1].position,
            );
            d = d.max(distance([p[0], p[1]], [q[0], q[1]]));
        }
        let said = alternatives_said(&map, order);
        if d > 1e-9 || said != first_said {
            differ.push(format!(
                "{context}, order {order:?}: {d} m, alternatives {said:?} vs {first_said:?}"
            ));
        }
    }
    (differ, !reference.alternatives.is_empty())
}

#[test]
fn more_tied_placements_than_starts_give_the_same_map_for_every_order_of_photos_2_to_n() {
    // Issue 39: photos 2, 3 and 4 each tied by one box, to photo 1 or in a chain: eight
    // whole-room placements fit the exact clicks exactly, their placement scores float noise
    // apart, and the joint fit starts from four of them. Which four, and so the map and the
    // alternatives it says, must not follow the order photos 2..4 are listed in (in a chain,
    // the boxes photo 1 does not see are summed in listing order, and so is the noise).
    let mut cases = 0;
    let mut differ = Vec::new();
    for seed in 0..3 {
        for (kind, scene) in [
            ("three ties to photo 1", three_one_box_ties(seed)),
            ("a chain of ties", chain_of_one_box_ties(seed)),
        ] {
            let Some(scene) = scene else { continue };
            cases += 1;
            let (d, _) = orders_that_differ(&scene, &format!("seed {seed}, {kind}"));
            differ.extend(d);
        }
    }
    assert!(cases >= 4, "{cases}");
    assert!(differ.is_empty(), "{differ:#?}");
}

#[test]
#[ignore = "a measurement, 6 builds a room: cargo test -p vpmap-metrology --release --test it experiment_more_tied_placements -- --ignored --nocapture"]
fn experiment_more_tied_placements_than_starts_give_the_same_map_in_every_order() {
    // As the test above over twenty synthetic rooms. Measured 2026-11-29: 39 rooms (every tie
    // left open), 0 orders differ; before the beam's order was a function of the room
    // (`Search::rank`), 20 of the 195 orders other than the first did (8 of the 20 chains).
    let (mut cases, mut open, mut differ) = (0, 0, Vec::new());
    for seed in 0..20 {
        for (kind, scene) in [
            ("three ties to photo 1", three_one_box_ties(seed)),
            ("a chain of ties", chain_of_one_box_ties(seed)),
        ] {
            let Some(scene) = scene else { continue };
            let (d, o) = orders_that_differ(&scene, &format!("seed {seed}, {kind}"));
            cases += 1;
            open += usize::from(o);
            differ.extend(d);
        }
    }
    println!(
        "{cases} rooms with three one-box ties to photo 1 or in a chain ({open} left open), {} orders differ from the first: {differ:#?}",
        differ.len()
    );
    assert!(differ.is_empty());
}

#[test]
fn rooms_of_more_than_four_photos_give_the_same_map_in_sampled_orders_of_photos_2_to_n() {
    // Issue 39 beyond four photos, where the beam keeps 64 of the partial hypotheses: six
    // photos (every photo after the first tied to the others by two boxes or more, as the
    // synthesizer draws them) and a chain of five one-box ties (32 whole-room placements fit
    // the exact clicks exactly). Each in eight orders of photos 2..6: the same map.
    let mut cases = 0;
    let mut differ = Vec::new();
    for seed in 0..2 {
        let (plain, _) = synthesize_room(&RoomSynthOptions {
            seed,
            photos: 6,
            boxes: 10,
            ..RoomSynthOptions::default()
        })
        .unwrap();
        for (kind, scene) in [
            ("six photos", Some(plain)),
            ("a chain of five ties", chain_of_ties(seed, 6, 10)),
        ] {
            let Some(scene) = scene else { continue };
            cases += 1;
            let (d, _) = orders_of_that_differ(
                &scene,
                &sampled_orders(scene.other_photos.len()),
                &format!("seed {seed}, {kind}"),
            );
            differ.extend(d);
        }
    }
    assert!(cases >= 3, "{cases}");
    assert!(differ.is_empty(), "{differ:#?}");
}

#[test]
#[ignore = "a measurement, about 10 builds a room of 5-8 photos: cargo test -p vpmap-metrology --release --test it experiment_rooms_of_more -- --ignored --nocapture"]
fn experiment_rooms_of_more_than_four_photos_give_the_same_map_in_sampled_orders() {
    // As the test above for 5 to 8 photos (a chain of 7 ties: 128 tied placements, twice the
    // beam's 64), ten seeds each.
    let (mut cases, mut open, mut differ) = (0, 0, Vec::new());
    for photos in 5..=vpmap_metrology::synth::MAX_ROOM_PHOTOS {
        for seed in 0..10 {
            let plain = synthesize_room(&RoomSynthOptions {
                seed,
                photos,
                boxes: 12,
                ..RoomSynthOptions::default()
            })
            .ok()
            .map(|(s, _)| s);
            for (kind, scene) in [
                ("plain", plain),
                ("a chain of ties", chain_of_ties(seed, photos, 12)),
            ] {
                let Some(scene) = scene else { continue };
                let (d, o) = orders_of_that_differ(
                    &scene,
                    &sampled_orders(scene.other_photos.len()),
                    &format!("{photos} photos, seed {seed}, {kind}"),
                );
                cases += 1;
                open += usize::from(o);
                differ.extend(d);
            }
        }
    }
    println!(
        "{cases} rooms of 5-8 photos ({open} with a tie left open), {} orders differ from the first: {differ:#?}",
        differ.len()
    );
    assert!(differ.is_empty());
}
