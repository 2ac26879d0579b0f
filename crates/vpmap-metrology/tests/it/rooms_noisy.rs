//! Rooms of several photos with noisy clicks: the shared rooms
//! (`../shared/data/multiview-scenes`) at 0.5, 1 and 2 px on every click, in random photo
//! orders, with their vanishing points three ways (issue 39).

use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::scene::Scene;

use crate::rooms::{
    TruthCamera, footprint_error, mahalanobis_sq, permutations, shared, shared_room,
};

/// How the noisy trials of the shared rooms give each photo its vanishing points.
#[derive(Debug, Clone, Copy, PartialEq)]
enum VpSource {
    /// The file's points as they are: bare points, facts (the simulator's exact points),
    /// which the fit holds to `GIVEN_POINT_SD_DEG`.
    FilePoints,
    /// Each photo's boxes' edges through the noisy corners, as the evaluations do.
    Edges,
}

/// Room `v` with Gaussian noise of `sigma_px` on every click of every photo (box and
/// footprint corners, floor corners), seeded; its vanishing points from `vps`.
fn noisy_room(v: &serde_json::Value, sigma_px: f64, seed: u64, vps: VpSource) -> Scene {
    use rand::SeedableRng;
    let edges = vps == VpSource::Edges;
    let mut scene = Scene::from_json_str(&v.to_string()).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    vpmap_metrology::synth::add_noise(&mut scene, sigma_px, &mut rng);
    for p in &mut scene.other_photos {
        vpmap_metrology::synth::add_noise(p, sigma_px, &mut rng);
    }
    if edges {
        vpmap_metrology::synth::vanishing_points_as_lines(&mut scene);
        for p in &mut scene.other_photos {
            vpmap_metrology::synth::vanishing_points_as_lines(p);
        }
    }
    scene
}

/// The median of `v` (NaN for none).
fn median(v: &[f64]) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => f64::midpoint(v[n / 2 - 1], v[n / 2]),
    }
}

/// The chi-square quantile of 95 % with 2 degrees of freedom: a 95 % ellipse's squared
/// Mahalanobis radius.
const CHI2_2_95: f64 = 5.991_464_547_107_979;

/// A box wrong with nothing said: where, how far off, and its Mahalanobis distance squared.
#[derive(Debug)]
struct SilentBox {
    trial: String,
    error_m: f64,
    d2: f64,
}

/// How the noisy trials of the shared rooms came out.
#[derive(Debug, Default)]
struct NoisyCount {
    trials: usize,
    refused: Vec<String>,
    /// Boxes more than 0.25 m off or at d^2 > 30 in maps that say no tie and no warning of
    /// which names the box as uncertain (issue 39's "silent wrong").
    silent_wrong: Vec<SilentBox>,
    /// Maps with a box more than 0.25 m off inside its error bars (d^2 <= 30): for each, the
    /// worst such box, its error, d^2, the 95 % ellipse's major semi-axis and whether a
    /// warning names it.
    beyond_quarter_metre: Vec<String>,
    worst_m: f64,
    worst_d2: f64,
    /// Objects of the maps built, and of them those whose true centroid lies inside the map's
    /// 95 % ellipse (d^2 at most 5.991, chi-square with 2 degrees of freedom).
    objects: usize,
    inside: usize,
    /// Objects a warning names as placed no better than a quarter metre.
    place_warned: usize,
    /// Objects a warning names for their outline (a corner) alone.
    outline_warned: usize,
    /// Every object's centroid error, m.
    centroid_errors_m: Vec<f64>,
    /// Every object's 95 % ellipse's major semi-axis, m.
    major_95_m: Vec<f64>,
    /// The cameras' error bars: per quantity of [`CAMERA_QUANTITIES`], how many had one and
    /// how many held the truth within `±2 sd`.
    camera_counted: [usize; 8],
    camera_within: [usize; 8],
}

/// The camera quantities whose error bars `map.json` reports (`cameras[].uncertainty`), in
/// the order of [`NoisyCount::camera_within`]: every photo's focal length, pitch and roll;
/// photos 2..n's height, station point (x, y) and heading; every photo's room yaw.
const CAMERA_QUANTITIES: [&str; 8] = [
    "focal", "pitch", "roll", "height", "x", "y", "heading", "room yaw",
];

impl NoisyCount {
    /// Count where the true camera `t` lies in the error bars of the map's camera `m`.
    fn count_camera(
        &mut self,
        m: &vpmap_metrology::map::CameraReport,
        t: &TruthCamera,
        room_axis_deg: f64,
    ) {
        let u = m.uncertainty.as_ref().unwrap();
        // The simulator turns its yaw clockwise from +y; the map's heading turns
        // counter-clockwise.
        let heading = m
            .heading_deg
            .map(|h| (h + t.yaw_deg_in_frame + 540.0).rem_euclid(360.0) - 180.0);
        let position = u.position_sd;
        let errors = [
            Some((m.focal_px - t.focal_px, u.focal_px_sd)),
            Some((m.pitch_deg - t.pitch_deg, u.pitch_deg_sd)),
            Some((m.roll_deg - t.roll_deg, u.roll_deg_sd)),
            Some((m.height - t.height, u.height_sd)),
            position.map(|sd| (m.position[0] - t.position[0], sd[0])),
            position.map(|sd| (m.position[1] - t.position[1], sd[1])),
            heading.zip(u.heading_deg_sd),
            // The room's yaw, in the photo's own plan frame (counter-clockwise from its +x),
            // against the truth's room sides seen from the true camera (the room's frame turned
            // by minus its true heading, counter-clockwise: minus the simulator's yaw), modulo
            // a quarter turn (either side may be VP1's).
            Some((
                (m.room_yaw_deg - (room_axis_deg + t.yaw_deg_in_frame) + 45.0).rem_euclid(90.0)
                    - 45.0,
                u.room_yaw_deg_sd,
            )),
        ];
        for (k, e) in errors.into_iter().enumerate() {
            // A value the fit holds (sd 0: a two-point photo's pitch, the first photo's height
            // and place) has no error bar.
            if let Some((e, sd)) = e.filter(|(_, sd)| *sd > 0.0) {
                self.camera_counted[k] += 1;
                self.camera_within[k] += usize::from(e.abs() <= 2.0 * sd);
            }
        }
    }
}

fn noisy_shared_rooms(sigma_px: f64, trials: u64, vps: VpSource) -> NoisyCount {
    let dir = shared("multiview-scenes");
    let mut count = NoisyCount::default();
    for r in 0..8 {
        let (room, truth) = shared_room(&dir, r);
        for t in 0..trials {
            count.trials += 1;
            let mut scene = noisy_room(&room, sigma_px, 1000 * r as u64 + t, vps);
            // Photos 2..n in an order of the trial's own.
            let orders = permutations(&scene.other_photos);
            let order = (t as usize * 7 + r) % orders.len();
            scene.other_photos.clone_from(&orders[order]);
            // Which photo of the file each of the map's cameras is.
            let photos: Vec<usize> = std::iter::once(0)
                .chain(
                    permutations(&(1..=scene.other_photos.len()).collect::<Vec<_>>())[order]
                        .iter()
                        .copied(),
                )
                .collect();
            match build_map(&scene, &BuildOptions::default()) {
                Err(e) => count.refused.push(format!("mv0{r} trial {t}: {e}")),
                Ok(map) => {
                    let mut worst = 0.0f64;
                    let mut worst_d2 = 0.0f64;
                    let mut worst_said = String::new();
                    // Boxes wrong (more than 0.25 m off, or d^2 > 30) that no warning names as
                    // uncertain.
                    let mut unsaid = Vec::new();
                    for o in &truth.objects {
                        let m = map.objects.iter().find(|m| m.name == o.name).unwrap();
                        let e = footprint_error(&m.footprint, &o.footprint);
                        let c = o
                            .footprint
                            .iter()
                            .fold([0.0, 0.0], |a, p| [a[0] + p[0] / 4.0, a[1] + p[1] / 4.0]);
                        let d = [m.centroid[0] - c[0], m.centroid[1] - c[1]];
                        let u = m.uncertainty.as_ref().unwrap();
                        let d2 = mahalanobis_sq(d, u.centroid_covariance);
                        let major_95 = u.centroid_ellipse_95.semi_axes[0];
                        let named = map.warns_uncertain(&o.name);
                        worst_d2 = worst_d2.max(d2);
                        if e > worst {
                            worst = e;
                            worst_said = format!(
                                "mv0{r} trial {t}: {} {e:.2} m off, d^2 {d2:.1}, 95 % semi-axis {major_95:.2} m, named uncertain in a warning: {named}",
                                o.name
                            );
                        }
                        if (e > 0.25 || d2 > 30.0) && !named {
                            unsaid.push((o.name.clone(), e, d2));
                        }
                        count.place_warned += usize::from(map.warnings.iter().any(|w| {
                            w.starts_with(&format!("object {:?}: its place is uncertain", o.name))
                        }));
                        count.outline_warned += usize::from(map.warnings.iter().any(|w| {
                            w.starts_with(&format!("object {:?}: its outline is uncertain", o.name))
                        }));
                        count.objects += 1;
                        count.centroid_errors_m.push(d[0].hypot(d[1]));
                        count.major_95_m.push(major_95);
                        count.inside += usize::from(d2 <= CHI2_2_95);
                    }
                    let [a, b] = [truth.room[0], truth.room[1]];
                    let room_axis_deg = (b[1] - a[1]).atan2(b[0] - a[0]).to_degrees();
                    for (m, &k) in map.cameras.iter().zip(&photos) {
                        count.count_camera(m, &truth.cameras[k], room_axis_deg);
                    }
                    count.worst_m = count.worst_m.max(worst);
                    count.worst_d2 = count.worst_d2.max(worst_d2);
                    let said = map.warnings.iter().any(|w| w.contains("turned by"));
                    if worst > 0.25 && worst_d2 <= 30.0 {
                        count.beyond_quarter_metre.push(worst_said);
                    }
                    if !said {
                        for (name, e, d2) in unsaid {
                            count.silent_wrong.push(SilentBox {
                                trial: format!("mv0{r} trial {t}: {name}"),
                                error_m: e,
                                d2,
                            });
                        }
                    }
                }
            }
        }
    }
    count
}

#[test]
#[ignore = "needs ../shared/data/multiview-scenes (absent from a fresh clone): cargo test -- --ignored shared_data"]
fn shared_data_rooms_with_noisy_clicks_are_mapped_not_refused() {
    // VPMAP_ROOM_TRIALS=50 for the figures of docs/method.md.
    let trials = std::env::var("VPMAP_ROOM_TRIALS")
        .ok()
        .and_then(|t| t.parse().ok())
        .unwrap_or(8);
    let mut counts = Vec::new();
    let mut cases = Vec::new();
    for vps in [VpSource::FilePoints, VpSource::Edges] {
        for sigma in [0.5, 1.0, 2.0] {
            cases.push((sigma, vps));
        }
    }
    for (sigma, edges) in cases {
        let c = noisy_shared_rooms(sigma, trials, edges);
        println!(
            "{sigma} px, vanishing points {edges:?}: {} trials, {} refused, {} boxes wrong with nothing said, {} a box > 0.25 m inside its error bars, worst box {:.3} m, worst d^2 {:.1}, truth inside the 95 % ellipse {} of {} ({:.1} %), {} placed uncertain by a warning, {} more for their outline\n{:#?}\n{:#?}",
            c.trials,
            c.refused.len(),
            c.silent_wrong.len(),
            c.beyond_quarter_metre.len(),
            c.worst_m,
            c.worst_d2,
            c.inside,
            c.objects,
            100.0 * c.inside as f64 / c.objects.max(1) as f64,
            c.place_warned,
            c.outline_warned,
            c.refused,
            c.silent_wrong
        );
        println!(
            "  median centroid error {:.4} m, median 95 % major semi-axis {:.4} m",
            median(&c.centroid_errors_m),
            median(&c.major_95_m)
        );
        let cameras: Vec<String> = CAMERA_QUANTITIES
            .iter()
            .zip(c.camera_within.iter().zip(&c.camera_counted))
            .map(|(q, (w, n))| format!("{q} {w} of {n}"))
            .collect();
        println!(
            "  the cameras' error bars, the truth within +-2 sd: {}",
            cameras.join(", ")
        );
        for b in &c.beyond_quarter_metre {
            println!("  a box > 0.25 m: {b}");
        }
        counts.push((sigma, edges, c));
    }
    for (sigma, edges, c) in counts {
        // Issue 39's "silent wrong": a box more than 0.25 m off or at d^2 > 30 with nothing
        // said. A box whose place the error bars leave uncertain beyond a quarter metre (3
        // sigma along its least certain direction) is named by a warning
        // (`WARN_POSITION_M`), so a box wrong with nothing said must lie beyond its error bars
        // (3 sigma: d^2 > 9), and none beyond d^2 = 30. (Calibrated error bars leave such a
        // tail: over 50 trials a room one box of 1,700 at 1 px with the boxes' edges, mv03
        // trial 17's box3, 0.251 m off at d^2 12.9; docs/results.md.)
        for b in &c.silent_wrong {
            assert!(
                b.d2 > 9.0 && b.d2 <= 30.0,
                "{sigma} px, {edges:?}: {} is {:.3} m off at d^2 {:.1} with nothing said",
                b.trial,
                b.error_m,
                b.d2
            );
        }
        // Issue 39's target: at most 1 % of the rooms refused (none of 64 in 8 trials a
        // room). Until a room's photos had their boxes made positive without mirroring them
        // (`room/align.rs`, `PhotoFit::new`), a photo whose fit ended with a negative side put
        // that box on the wrong side of its edge: 5 of 2,400 trials of 50 a room were refused
        // (mv06 trial 2 among the first 8 with vanishing points from the boxes' edges at
        // 2 px); now 1 (mv01 trial 32 at 2 px: its photo 3 alone does not converge).
        // The 95 % ellipses: in the 92-98 % band of issue 39 over 50 trials a room (1,700
        // objects a level; 94.1-94.2 % with the boxes' edges, 93.5-94.1 % with the files'
        // points); over CI's 8 (272 objects, about 1.3 points of binomial sd, and the objects
        // of one trial share its cameras) asked within 90-98.5 %. Until the files' bare points
        // were held as facts (`GIVEN_POINT_SD_DEG`) they weighed as one click each and their
        // ellipses held 99.2 %.
        let coverage = c.inside as f64 / c.objects.max(1) as f64;
        let band = 0.90..=0.985;
        assert!(
            band.contains(&coverage),
            "{sigma} px, {edges:?}: the truth inside the 95 % ellipse for {} of {} objects",
            c.inside,
            c.objects
        );
        // The cameras' error bars, pooled over the quantities (about 1,100 values a level
        // over CI's 8 trials: 0.7 points of binomial sd), in the band where the boxes' edges
        // give the vanishing points (95.1-95.9 % over 50 trials a room). With the files'
        // exact points the fitted cameras are exact and every value lies inside.
        if edges == VpSource::Edges {
            let within: usize = c.camera_within.iter().sum();
            let counted: usize = c.camera_counted.iter().sum();
            let share = within as f64 / counted.max(1) as f64;
            assert!(
                (0.92..=0.985).contains(&share),
                "{sigma} px: the cameras' error bars hold the truth for {within} of {counted}"
            );
        }
        assert!(
            c.refused.len() * 100 <= c.trials,
            "{sigma} px, {edges:?}: {} of {} refused: {:?}",
            c.refused.len(),
            c.trials,
            c.refused
        );
    }
}
