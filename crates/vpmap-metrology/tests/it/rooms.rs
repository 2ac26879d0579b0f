//! Rooms of several photos: the joint fit against the independent simulator's rooms
//! (`../shared/data/multiview-scenes`), and bad room files.

use std::path::PathBuf;

use serde::Deserialize;
use vpmap_metrology::map::{BuildOptions, FloorMap, build_map};
use vpmap_metrology::scene::Scene;

#[derive(Clone, Deserialize)]
pub(crate) struct RoomTruth {
    pub(crate) objects: Vec<TruthObject>,
    pub(crate) cameras: Vec<TruthCamera>,
    /// The room's rectangle, its sides along the room's axes (metres, photo 1's plan frame).
    pub(crate) room: Vec<[f64; 2]>,
}

#[derive(Clone, Deserialize)]
pub(crate) struct TruthObject {
    pub(crate) name: String,
    pub(crate) footprint: Vec<[f64; 2]>,
    height: f64,
}

#[derive(Clone, Deserialize)]
pub(crate) struct TruthCamera {
    pub(crate) position: [f64; 2],
    pub(crate) height: f64,
    pub(crate) focal_px: f64,
    pub(crate) pitch_deg: f64,
    pub(crate) roll_deg: f64,
    /// Clockwise from `+y` (the map's heading turns counter-clockwise).
    pub(crate) yaw_deg_in_frame: f64,
}

pub(crate) fn shared(sub: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/data")
        .join(sub);
    assert!(
        dir.is_dir(),
        "shared data {} is absent (expected beside the project)",
        dir.display()
    );
    dir
}

/// Shared room `mv0{r}` of `dir` (`shared("multiview-scenes")`): its file and its truth.
pub(crate) fn shared_room(dir: &std::path::Path, r: usize) -> (serde_json::Value, RoomTruth) {
    let path = dir.join(format!("mv0{r}.json"));
    let room = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let truth =
        serde_json::from_str(&std::fs::read_to_string(path.with_extension("truth.json")).unwrap())
            .unwrap();
    (room, truth)
}

/// The squared Mahalanobis distance of the offset `d` in the covariance `c` (written out
/// here, not taken from the library, so that the tests judge its error bars independently).
pub(crate) fn mahalanobis_sq(d: [f64; 2], c: [[f64; 2]; 2]) -> f64 {
    let det = c[0][0] * c[1][1] - c[0][1] * c[1][0];
    (c[1][1] * d[0] * d[0] - 2.0 * c[0][1] * d[0] * d[1] + c[0][0] * d[1] * d[1]) / det
}

/// Largest distance from a truth corner to the nearest corner of the map's object.
pub(crate) fn footprint_error(map: &[[f64; 2]], truth: &[[f64; 2]]) -> f64 {
    truth
        .iter()
        .map(|t| {
            map.iter()
                .map(|m| (m[0] - t[0]).hypot(m[1] - t[1]))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// The worst error in metres (positions, sizes, heights) and degrees/pixels of the cameras.
fn errors(map: &FloorMap, truth: &RoomTruth) -> (f64, f64) {
    let mut metres = 0.0f64;
    assert_eq!(map.objects.len(), truth.objects.len());
    for t in &truth.objects {
        let m = map
            .objects
            .iter()
            .find(|o| o.name == t.name)
            .unwrap_or_else(|| panic!("object {} missing", t.name));
        metres = metres.max(footprint_error(&m.footprint, &t.footprint));
        metres = metres.max((m.height.unwrap() - t.height).abs());
    }
    let mut camera = 0.0f64;
    assert_eq!(map.cameras.len(), truth.cameras.len());
    for (m, t) in map.cameras.iter().zip(&truth.cameras) {
        metres = metres
            .max((m.position[0] - t.position[0]).abs())
            .max((m.position[1] - t.position[1]).abs())
            .max((m.height - t.height).abs());
        // The simulator turns its yaw clockwise (from +y towards +x); the map's heading turns
        // counter-clockwise.
        let heading = m.heading_deg.unwrap();
        let d = (heading + t.yaw_deg_in_frame + 540.0).rem_euclid(360.0) - 180.0;
        camera = camera
            .max((m.focal_px - t.focal_px).abs())
            .max((m.pitch_deg - t.pitch_deg).abs())
            .max((m.roll_deg - t.roll_deg).abs())
            .max(d.abs());
    }
    (metres, camera)
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_rooms_from_exact_clicks_reproduce_the_truth_to_1e_9_m() {
    let dir = shared("multiview-scenes");
    let mut paths: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.extension().is_some_and(|e| e == "json")
                && !p.to_string_lossy().ends_with(".truth.json")
        })
        .collect();
    paths.sort();
    assert!(
        paths.len() >= 8,
        "expected the eight rooms in {}",
        dir.display()
    );
    for path in paths {
        let scene = Scene::from_json_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let truth: RoomTruth = serde_json::from_str(
            &std::fs::read_to_string(path.with_extension("truth.json")).unwrap(),
        )
        .unwrap();
        let map = build_map(&scene, &BuildOptions::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let (metres, camera) = errors(&map, &truth);
        println!(
            "{}: {} photos, worst {metres:.2e} m, cameras {camera:.2e} (px/deg); warnings {:?}",
            path.display(),
            scene.photo_count(),
            map.warnings
        );
        assert!(metres < 1e-9, "{}: {metres} m", path.display());
        assert!(camera < 1e-7, "{}: {camera}", path.display());
    }
}

const FIXTURE: &str = include_str!("../fixtures/room-mv00.json");
const FIXTURE_TRUTH: &str = include_str!("../fixtures/room-mv00.truth.json");

fn fixture() -> serde_json::Value {
    serde_json::from_str(FIXTURE).unwrap()
}

fn build_value(v: &serde_json::Value) -> Result<FloorMap, String> {
    let scene = Scene::from_json_str(&v.to_string()).map_err(|e| e.to_string())?;
    build_map(&scene, &BuildOptions::default()).map_err(|e| e.to_string())
}

#[test]
fn a_room_of_two_photos_reproduces_the_independent_truth() {
    let map = build_value(&fixture()).unwrap();
    let truth: RoomTruth = serde_json::from_str(FIXTURE_TRUTH).unwrap();
    let (metres, camera) = errors(&map, &truth);
    assert!(metres < 1e-9, "{metres} m");
    assert!(camera < 1e-7, "{camera} px or deg");
    // One map of the room: photo 2 shows box0, which photo 1 does not.
    assert_eq!(map.objects.len(), 4);
    assert_eq!(map.cameras.len(), 2);
    assert_eq!(map.camera, map.cameras[0]);
}

#[test]
fn a_room_file_of_one_photo_gives_that_photo_s_map() {
    let v = fixture();
    let photo = v["photos"][0].clone();
    let room = serde_json::json!({"version": 1, "photos": [photo.clone()]});
    let a = build_value(&photo).unwrap();
    let b = build_value(&room).unwrap();
    assert_eq!(a.to_json_string(), b.to_json_string());
    assert!(a.cameras.is_empty());
}

/// The product of the semi-axes of object `name`'s 95 % centroid ellipse (its area over pi).
fn ellipse_area(map: &FloorMap, name: &str) -> f64 {
    let e = map.objects.iter().find(|o| o.name == name).unwrap();
    let a = e
        .uncertainty
        .as_ref()
        .unwrap()
        .centroid_ellipse_95
        .semi_axes;
    a[0] * a[1]
}

#[test]
fn an_object_seen_twice_is_placed_more_surely_than_from_one_photo() {
    // The same noise-free room with the click noise given as 1 px: the error bars of a box
    // seen in both photos are smaller than photo 1's alone.
    let options = BuildOptions {
        click_sigma_px: Some(1.0),
        ..BuildOptions::default()
    };
    let v = fixture();
    let room = build_map(&Scene::from_json_str(&v.to_string()).unwrap(), &options).unwrap();
    let alone = build_map(
        &Scene::from_json_str(&v["photos"][0].to_string()).unwrap(),
        &options,
    )
    .unwrap();
    for name in ["box2", "box3"] {
        let area = |m: &FloorMap| ellipse_area(m, name);
        assert!(
            area(&room) < area(&alone),
            "{name}: {} vs {}",
            area(&room),
            area(&alone)
        );
    }
}

#[test]
fn a_photo_no_shared_object_ties_is_refused_naming_it() {
    let mut v = fixture();
    for o in v["photos"][1]["objects"].as_array_mut().unwrap() {
        let name = o["name"].as_str().unwrap().to_owned();
        o["name"] = serde_json::Value::String(format!("{name}-b"));
    }
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("photos[1]") && e.contains("photo 2 is not tied to photo 1"),
        "{e}"
    );
    assert!(e.contains("box0-b"), "names an object to add in both: {e}");
}

#[test]
fn a_box_in_one_photo_and_a_footprint_in_another_is_refused() {
    let mut v = fixture();
    let o = &mut v["photos"][1]["objects"][1];
    let base = o["base"].clone();
    let pts: Vec<serde_json::Value> = ["near", "right", "left"]
        .iter()
        .map(|c| base[*c].clone())
        .collect();
    *o = serde_json::json!({"name": o["name"].clone(), "footprint": pts});
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("photos[1].objects[1]")
            && e.contains("a box in photo 1 and a footprint in photo 2"),
        "{e}"
    );
}

#[test]
fn a_name_used_twice_in_one_photo_names_the_photo() {
    let mut v = fixture();
    let first = v["photos"][1]["objects"][0]["name"].clone();
    v["photos"][1]["objects"][1]["name"] = first;
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("photos[1] (photo 2)") && e.contains("objects[1].name"),
        "{e}"
    );
}

#[test]
fn a_second_known_camera_height_holds_that_camera_and_narrows_the_error_bars() {
    let options = BuildOptions {
        click_sigma_px: Some(1.0),
        ..BuildOptions::default()
    };
    let truth: RoomTruth = serde_json::from_str(FIXTURE_TRUTH).unwrap();
    let one = fixture();
    let mut both = fixture();
    both["photos"][1]["scale"] = serde_json::json!({"camera_height_m": truth.cameras[1].height});
    let build = |v: &serde_json::Value| {
        build_map(&Scene::from_json_str(&v.to_string()).unwrap(), &options).unwrap()
    };
    let (one, both) = (build(&one), build(&both));
    // The independent truth, still to 1e-9 m.
    let (metres, camera) = errors(&both, &truth);
    assert!(metres < 1e-9 && camera < 1e-9, "{metres} m, {camera}");
    // Photo 2's height is held at what it says, no longer fitted.
    let sd = |m: &FloorMap| m.cameras[1].uncertainty.as_ref().unwrap().height_sd;
    assert!(sd(&one) > 1e-4, "fitted: {}", sd(&one));
    assert!(sd(&both) < 1e-12, "held: {}", sd(&both));
    // Every object known at least as well, and some better.
    let mut narrower = 0;
    for o in &one.objects {
        let (a, b) = (ellipse_area(&one, &o.name), ellipse_area(&both, &o.name));
        assert!(b <= a * (1.0 + 1e-9), "{}: {b} vs {a}", o.name);
        narrower += usize::from(b < 0.9 * a);
    }
    assert!(narrower > 0, "a known height adds information");
}

#[test]
fn scales_that_disagree_are_both_named() {
    let mut v = fixture();
    // Photo 2's camera is 1.3105 m high (the truth); say 1.6 m.
    v["photos"][1]["scale"] = serde_json::json!({"camera_height_m": 1.6});
    v["photos"][0]["scale"] =
        serde_json::json!({"object": "box2", "dimension": "height", "meters": 0.5});
    let map = build_value(&v).unwrap();
    let w = map.warnings.join("\n");
    assert!(
        w.contains("disagree")
            && w.contains("photo 2's camera height 1.6 m")
            && w.contains("photo 1's height of \"box2\""),
        "{w}"
    );
}

#[test]
fn the_reference_methods_refuse_a_room() {
    let scene = Scene::from_json_str(FIXTURE).unwrap();
    let e = build_map(
        &scene,
        &BuildOptions {
            method: vpmap_metrology::reconstruct::Method::Sideview,
            ..BuildOptions::default()
        },
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("joint fit") && e.contains("sideview"), "{e}");
}

#[test]
fn a_photo_tied_by_one_box_is_named_with_the_turn_that_fits_as_well() {
    // Photo 2 shares only box2 with photo 1: a box with unequal sides fits the same turned by
    // a half turn about its centre, so the data cannot say which way photo 2 faces.
    let mut v = fixture();
    for o in v["photos"][1]["objects"].as_array_mut().unwrap() {
        if o["name"] == "box3" {
            o["name"] = serde_json::Value::String("box3-seen-from-2".to_owned());
        }
    }
    let map = build_value(&v).unwrap();
    let w = map.warnings.join("\n");
    assert!(
        w.contains("photo 2 is tied to the room only by object \"box2\"")
            && w.contains("turned by 180 degrees")
            && w.contains("inside the walls"),
        "{w}"
    );
    // The floor outlines' walls choose the turn that keeps the cameras in the room: the true
    // one here.
    let truth: RoomTruth = serde_json::from_str(FIXTURE_TRUTH).unwrap();
    let (p, t) = (map.cameras[1].position, truth.cameras[1].position);
    assert!((p[0] - t[0]).hypot(p[1] - t[1]) < 1e-9, "{p:?} vs {t:?}");
    // With both shared boxes the data decide, and nothing is said.
    let map = build_value(&fixture()).unwrap();
    assert!(
        !map.warnings
            .iter()
            .any(|w| w.contains("tied to the room only"))
    );
}

/// A shared room with one photo tied to the others by one shared box only.
struct OneBoxTie {
    /// The room, `mv0{room}`.
    room: usize,
    /// The tied photo, from 0.
    photo: usize,
    /// The one box it still shares.
    keep: String,
    /// The room file, the photo's other shared boxes renamed.
    value: serde_json::Value,
    truth: RoomTruth,
}

/// Every photo after the first of every shared room, tied by each of its shared boxes in turn
/// (the others renamed as not shared).
fn one_box_ties() -> Vec<OneBoxTie> {
    let dir = shared("multiview-scenes");
    let mut out = Vec::new();
    for r in 0..8 {
        let (room, truth) = shared_room(&dir, r);
        let photos = room["photos"].as_array().unwrap();
        let names = |p: &serde_json::Value| -> Vec<String> {
            p["objects"]
                .as_array()
                .unwrap()
                .iter()
                .map(|o| o["name"].as_str().unwrap().to_owned())
                .collect()
        };
        for k in 1..photos.len() {
            let others: Vec<String> = (0..photos.len())
                .filter(|&j| j != k)
                .flat_map(|j| names(&photos[j]))
                .collect();
            for keep in names(&photos[k]).into_iter().filter(|n| others.contains(n)) {
                let mut v = room.clone();
                for o in v["photos"][k]["objects"].as_array_mut().unwrap() {
                    let n = o["name"].as_str().unwrap().to_owned();
                    if others.contains(&n) && n != keep {
                        o["name"] = serde_json::Value::String(format!("{n} (not shared)"));
                    }
                }
                out.push(OneBoxTie {
                    room: r,
                    photo: k,
                    keep,
                    value: v,
                    truth: truth.clone(),
                });
            }
        }
    }
    out
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_rooms_tied_by_one_box_are_placed_by_their_walls_or_warned() {
    // Each photo after the first tied to the others by one shared box only (every shared box
    // in turn), exact clicks: the likelihood cannot tell a half turn; the walls choose, and the
    // build warns. A tie the walls decide (no alternative) must be right in at least 80 % of
    // cases; one they leave open is a coin toss the map names, so its alternative, pinned by its
    // `placement_turn_deg`, must be the truth when the map's placement is not. (Before issue
    // 39's canonical choice of exact ties this asserted 80 % right over every case, open ones
    // included, and passed with 31 of 37: three open ties were right by the float noise of the
    // file's order. Measured 2026-11-29: 27 decided, all right; 10 open, the map's placement
    // the truth in 1, the alternative in the other 9.)
    let (mut decided, mut right, mut open, mut open_right) = (0, 0, 0, 0);
    let distance = |p: [f64; 3], t: [f64; 2]| (p[0] - t[0]).hypot(p[1] - t[1]);
    for tie in one_box_ties() {
        let (r, k, keep) = (tie.room, tie.photo, &tie.keep);
        let context = format!("mv0{r} photo {} tied by {keep:?}", k + 1);
        let map = build_value(&tie.value).unwrap_or_else(|e| panic!("{context}: {e}"));
        let t = tie.truth.cameras[k].position;
        let here = distance(map.cameras[k].position, t) < 1e-6;
        if !here {
            assert!(
                map.warnings
                    .iter()
                    .any(|w| w.contains("tied to the room only")),
                "{context}: placed wrong without a warning"
            );
        }
        let Some(alt) = map.alternatives.iter().find(|a| a.photo == k + 1) else {
            decided += 1;
            right += usize::from(here);
            continue;
        };
        open += 1;
        open_right += usize::from(here);
        if !here {
            let mut pinned = tie.value.clone();
            pinned["photos"][k]["placement_turn_deg"] = serde_json::json!(alt.placement_turn_deg);
            let other = build_value(&pinned).unwrap_or_else(|e| panic!("{context}, pinned: {e}"));
            let d = distance(other.cameras[k].position, t);
            assert!(
                d < 1e-6,
                "{context}: neither placement is the truth ({d} m)"
            );
        }
    }
    println!(
        "tied by one box: {decided} decided by the walls, {right} of them right; {open} left open with the alternative named, the map's placement the truth in {open_right}, the alternative in the others"
    );
    assert!(decided + open >= 30, "{}", decided + open);
    assert!(right * 5 >= decided * 4, "{right} of {decided}");
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_ties_the_physical_checks_decide_are_resolved_right() {
    // Issue 39: "ties resolved right wherever the physical checks can tell (at least 95 % of
    // those)". Each photo after the first tied by one shared box (as above), with exact clicks
    // and with 1 px of noise on every click (two seeds). A tie the checks decide leaves no
    // alternative in the map; one they cannot decide lists the other turn. Among the decided,
    // the placement must be the true one (camera within 0.25 m) at least 95 % of the time; an
    // undecided one must name its alternative and may be either. (Measured 2026-11-29, each
    // tie judged against the placement with that photo alone turned: 92 of 93 decided right,
    // 18 left open; the wrong one, mv07's photo 4 tied by box1 at 1 px, seed 1, is named in the
    // tie warning: the true placement overlaps box0 with the same box under another name,
    // whose 1 px sides come out 11 % apart, over the 10 % the checks take for one box.)
    // VPMAP_TIE_SIGMA_PX=0.5 (or 2) for the noisy trials at another level (docs/results.md).
    use rand::SeedableRng;
    use vpmap_metrology::synth::add_noise;
    let noise: f64 = std::env::var("VPMAP_TIE_SIGMA_PX")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1.0);
    let (mut decided, mut right, mut said, mut refused) = (0, 0, 0, 0);
    let mut wrong_warned = 0;
    for tie in one_box_ties() {
        let (r, k, keep, truth) = (tie.room, tie.photo, &tie.keep, &tie.truth);
        let exact = Scene::from_json_str(&tie.value.to_string()).unwrap();
        for (sigma, seed) in [(0.0, 0_u64), (noise, 1), (noise, 2)] {
            let mut scene = exact.clone();
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(
                seed * 1000 + 100 * r as u64 + 10 * k as u64,
            );
            add_noise(&mut scene, sigma, &mut rng);
            for p in &mut scene.other_photos {
                add_noise(p, sigma, &mut rng);
            }
            let Ok(map) = build_map(&scene, &BuildOptions::default()) else {
                refused += 1;
                continue;
            };
            let (p, t) = (map.cameras[k].position, truth.cameras[k].position);
            let ok = (p[0] - t[0]).hypot(p[1] - t[1]) < 0.25;
            if map.alternatives.iter().any(|a| a.photo == k + 1) {
                said += 1;
            } else {
                decided += 1;
                right += usize::from(ok);
                if !ok {
                    let warned = map
                        .warnings
                        .iter()
                        .any(|w| w.contains(&format!("photo {} is tied", k + 1)));
                    wrong_warned += usize::from(warned);
                    println!(
                        "mv0{r} photo {} tied by {keep:?}, {sigma} px (seed {seed}): camera {:.2} m off, tie warning {warned}",
                        k + 1,
                        (p[0] - t[0]).hypot(p[1] - t[1])
                    );
                }
            }
        }
    }
    println!(
        "ties by one box, exact and {noise} px clicks: {decided} decided by the checks, {right} of them right ({wrong_warned} of the wrong ones with the tie warning); {said} left open with the alternative named; {refused} refused"
    );
    assert!(decided >= 30, "{decided}");
    assert!(right * 100 >= decided * 95, "{right} of {decided}");
    // A wrong choice is never silent: the tie is said in the warnings.
    assert_eq!(wrong_warned, decided - right);
}

/// Every order of `items` (Heap's algorithm).
pub fn permutations<T: Clone>(items: &[T]) -> Vec<Vec<T>> {
    if items.len() <= 1 {
        return vec![items.to_vec()];
    }
    let mut out = Vec::new();
    for i in 0..items.len() {
        let mut rest = items.to_vec();
        let first = rest.remove(i);
        for mut p in permutations(&rest) {
            p.insert(0, first.clone());
            out.push(p);
        }
    }
    out
}

/// Largest difference between two maps of one room: every object's footprint corners (the
/// nearest corner of the other map's object of the same name) and height, metres.
pub fn map_difference(a: &FloorMap, b: &FloorMap) -> f64 {
    assert_eq!(a.objects.len(), b.objects.len());
    let mut worst = 0.0f64;
    for o in &a.objects {
        let p = b
            .objects
            .iter()
            .find(|p| p.name == o.name)
            .unwrap_or_else(|| panic!("object {} missing", o.name));
        worst = worst.max(footprint_error(&p.footprint, &o.footprint));
        worst = worst.max(footprint_error(&o.footprint, &p.footprint));
        if let (Some(h), Some(g)) = (o.height, p.height) {
            worst = worst.max((h - g).abs());
        }
    }
    worst
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_rooms_give_the_same_map_for_every_order_of_photos_2_to_n() {
    let dir = shared("multiview-scenes");
    let mut orders = 0;
    for r in 0..8 {
        let (room, truth) = shared_room(&dir, r);
        let photos = room["photos"].as_array().unwrap().clone();
        let reference = build_value(&room).unwrap_or_else(|e| panic!("mv0{r}: {e}"));
        let rest: Vec<usize> = (1..photos.len()).collect();
        for order in permutations(&rest) {
            let mut v = room.clone();
            let mut reordered = vec![photos[0].clone()];
            reordered.extend(order.iter().map(|&k| photos[k].clone()));
            v["photos"] = serde_json::Value::Array(reordered);
            let map = build_value(&v).unwrap_or_else(|e| panic!("mv0{r} order {order:?}: {e}"));
            let d = map_difference(&map, &reference);
            assert!(
                d < 1e-9,
                "mv0{r} order {order:?}: {d} m from the file's order"
            );
            // And each is the truth.
            for t in &truth.objects {
                let m = map.objects.iter().find(|o| o.name == t.name).unwrap();
                let e = footprint_error(&m.footprint, &t.footprint);
                assert!(e < 1e-9, "mv0{r} order {order:?}: {} {e} m", t.name);
            }
            // The cameras follow their photos.
            for (i, &k) in order.iter().enumerate() {
                let (p, t) = (map.cameras[i + 1].position, truth.cameras[k].position);
                assert!(
                    (p[0] - t[0]).hypot(p[1] - t[1]) < 1e-9,
                    "mv0{r} order {order:?}: camera of photo {}",
                    k + 1
                );
            }
            orders += 1;
        }
    }
    println!("{orders} orders of 8 rooms: one map each");
    assert!(orders >= 8 + 6, "{orders}");
}

/// The fixture with photo 2 tied to photo 1 by box2 only (its box3 named apart) and no floor
/// outlines, so that no wall can tell which way photo 2 faces: box2 fits as well with photo 2
/// turned by a half turn about its centre.
fn tied_by_one_box_without_walls() -> serde_json::Value {
    let mut v = fixture();
    for o in v["photos"][1]["objects"].as_array_mut().unwrap() {
        if o["name"] == "box3" {
            o["name"] = serde_json::Value::String("box3-seen-from-2".to_owned());
        }
    }
    for p in v["photos"].as_array_mut().unwrap() {
        p["floor"] = serde_json::json!([]);
    }
    v
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn a_tie_no_check_decides_is_an_alternative_and_its_placement_turn_pins_it() {
    // Issue 39: the map names the other placement and the room file's `placement_turn_deg`
    // asks for it. Checked against the independent truth: photo 2's two placements are its
    // true camera and that camera turned by a half turn about box2's true centre.
    let v = tied_by_one_box_without_walls();
    let truth: RoomTruth = serde_json::from_str(FIXTURE_TRUTH).unwrap();
    let box2 = truth.objects.iter().find(|o| o.name == "box2").unwrap();
    let n = box2.footprint.len() as f64;
    let c = [
        box2.footprint.iter().map(|p| p[0]).sum::<f64>() / n,
        box2.footprint.iter().map(|p| p[1]).sum::<f64>() / n,
    ];
    let true_cam = truth.cameras[1].position;
    let turned_cam = [2.0 * c[0] - true_cam[0], 2.0 * c[1] - true_cam[1]];
    let map = build_value(&v).unwrap();
    assert_eq!(map.alternatives.len(), 1, "{:?}", map.warnings);
    let alt = &map.alternatives[0];
    assert_eq!((alt.photo, alt.turn_deg), (2, 180));
    assert!(
        [0, 90, 180, 270].contains(&alt.placement_turn_deg),
        "{alt:?}"
    );
    assert!((alt.cost_px2 - alt.chosen_cost_px2).abs() < 1e-6, "{alt:?}");
    let here = |m: &FloorMap| [m.cameras[1].position[0], m.cameras[1].position[1]];
    let (first, other) = if distance(here(&map), true_cam) < 1e-6 {
        (true_cam, turned_cam)
    } else {
        (turned_cam, true_cam)
    };
    assert!(distance(here(&map), first) < 1e-6, "{:?}", here(&map));
    // Pinned to the alternative: photo 2 is placed the other way, nothing else is tried for
    // it, and the map says it is pinned.
    let mut pinned = v.clone();
    pinned["photos"][1]["placement_turn_deg"] = serde_json::json!(alt.placement_turn_deg);
    // A field vpmap reads: no "unknown field" note about it.
    assert!(
        vpmap_metrology::scene::unknown_fields(&pinned).is_empty(),
        "{:?}",
        vpmap_metrology::scene::unknown_fields(&pinned)
    );
    let swapped = build_value(&pinned).unwrap();
    assert!(
        distance(here(&swapped), other) < 1e-6,
        "{:?} vs {other:?}",
        here(&swapped)
    );
    assert!(
        swapped.alternatives.is_empty(),
        "{:?}",
        swapped.alternatives
    );
    assert!(
        swapped.warnings.iter().any(|w| w.contains(&format!(
            "photo 2's placement is pinned by its `placement_turn_deg` ({} degrees)",
            alt.placement_turn_deg
        ))),
        "{:?}",
        swapped.warnings
    );
    // Photo 1 and the box both photos show stay where they were.
    let centroid = |m: &FloorMap, name: &str| {
        let o = m.objects.iter().find(|o| o.name == name).unwrap();
        [o.centroid[0], o.centroid[1]]
    };
    assert!(distance(centroid(&swapped, "box2"), c) < 1e-6);
    assert!(distance(centroid(&map, "box2"), c) < 1e-6);
    // Pinned back to the map's own turn: the first map again.
    pinned["photos"][1]["placement_turn_deg"] =
        serde_json::json!((alt.placement_turn_deg + 180) % 360);
    let back = build_value(&pinned).unwrap();
    assert!(distance(here(&back), first) < 1e-6, "{:?}", here(&back));
}

#[test]
fn placement_turns_that_are_not_quarter_turns_or_pin_photo_1_are_refused_by_name() {
    let mut v = tied_by_one_box_without_walls();
    v["photos"][1]["placement_turn_deg"] = serde_json::json!(45);
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("photos[1].placement_turn_deg")
            && e.contains("45 is not a quarter turn")
            && e.contains("0, 90, 180 or 270"),
        "{e}"
    );
    let mut v = tied_by_one_box_without_walls();
    v["photos"][0]["placement_turn_deg"] = serde_json::json!(90);
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("photos[0].placement_turn_deg") && e.contains("photo 1 sets the room's frame"),
        "{e}"
    );
    let mut photo = fixture()["photos"][0].clone();
    photo["placement_turn_deg"] = serde_json::json!(180);
    let e = build_value(&photo).unwrap_err();
    assert!(
        e.contains("placement_turn_deg") && e.contains("single-photo scene"),
        "{e}"
    );
    let mut v = tied_by_one_box_without_walls();
    v["photos"][1]["placement_turn_deg"] = serde_json::json!("half");
    let e = build_value(&v).unwrap_err();
    assert!(
        e.contains("placement_turn_deg") || e.contains("invalid type"),
        "{e}"
    );
}

#[test]
fn a_camera_the_map_puts_inside_an_object_is_said_by_name() {
    // Issue 39: a camera placed inside an object is never a silent map. The fixture's photo 2
    // twice: the copy shares box3 only (its other boxes named apart), so it fits as well
    // turned by a half turn about box3's centre, where (by the fixture's truth) each camera
    // lands inside a box of the other photo. The physical checks choose the copy's true place;
    // pinned the other way, the map says which camera stands inside which object.
    let photo = fixture()["photos"][1].clone();
    let mut copy = photo.clone();
    for o in copy["objects"].as_array_mut().unwrap() {
        if o["name"] != "box3" {
            let apart = format!("{} (copy)", o["name"].as_str().unwrap());
            o["name"] = serde_json::Value::String(apart);
        }
    }
    let mut room = serde_json::json!({"version": 1, "photos": [photo, copy]});
    let inside = |m: &FloorMap| -> Vec<String> {
        m.warnings
            .iter()
            .filter(|w| w.contains("camera stands inside object"))
            .cloned()
            .collect()
    };
    let free = build_value(&room).unwrap();
    assert!(inside(&free).is_empty(), "{:?}", free.warnings);
    // Photo 2's camera where photo 1's is (the copy's true place).
    let here = |m: &FloorMap| [m.cameras[1].position[0], m.cameras[1].position[1]];
    assert!(
        distance(here(&free), [0.0, 0.0]) < 1e-6,
        "{:?}",
        here(&free)
    );
    let box3 = free
        .objects
        .iter()
        .find(|o| o.name == "box3")
        .unwrap()
        .centroid;
    let turned = [2.0 * box3[0], 2.0 * box3[1]];
    let mut found = false;
    for turn in [0, 90, 180, 270] {
        room["photos"][1]["placement_turn_deg"] = serde_json::json!(turn);
        let Ok(map) = build_value(&room) else {
            continue;
        };
        if distance(here(&map), turned) > 1e-6 {
            continue;
        }
        found = true;
        let said = inside(&map).join("\n");
        assert!(
            said.contains("photo 2's camera stands inside object \"box0\"")
                && said.contains("photo 1's camera stands inside object \"box0 (copy)\"")
                && said.contains("`placement_turn_deg`"),
            "{:?}",
            map.warnings
        );
    }
    assert!(
        found,
        "no pinned turn puts photo 2 at its half turn about box3"
    );
}
