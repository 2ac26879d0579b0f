//! Why clicks on York Urban's labelled corners stay (issue 38): for the clicks that stayed with
//! "no meeting within the radius" or "an edge too short", which single change of the snapping
//! would have snapped them onto the labelled corner, and enlarged crops of a sample of them to
//! look at.
//!
//! ```sh
//! cargo run --release -p vpmap-eval --example snap_misses -- ../shared/data/yud-train /tmp/snap-misses
//! ```
//!
//! Prints, per reason, how many of the clicks each variant snaps within 1.5 px of the labelled
//! corner (each variant alone; the click and everything else as `eval-clicks --yud` has them),
//! and writes `sheet-<reason>-<k>.png`: 8 crops each (41 x 41 px around the labelled corner,
//! enlarged 8 times; green: the labelled segments and corner; red: the click; blue: the edge
//! pieces snapping found towards a vanishing point, cyan: along a free direction; magenta: the
//! meeting point it rejected), with one line per crop (the photo, the corner, the click, the
//! variants that snap it, why it stayed, the pieces found) in `sheets.txt`; and the number of
//! clicks of each outcome by the angle between the two labelled lines. With a third argument
//! `summary` it prints only the `eval-clicks --yud` table's first rows and the reasons.
#![allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use image::{Rgb, RgbImage};
use vpmap_eval::clicks::yud::{YudConfig, run_yud};
use vpmap_eval::detection::find_pairs;
use vpmap_vision::photo::{PhotoLimits, decode_photo};
use vpmap_vision::snap::{
    EdgeDirection, KeptReason, SnapImage, SnapOptions, SnapOutcome, edges_near_click, snap_click,
};
use vpmap_vision::{DetectOptions, detect};

const SCALE: u32 = 8;
const HALF: i64 = 20;
const SAMPLE: usize = 40;
const GOOD_PX: f64 = 1.5;

#[derive(serde::Deserialize)]
struct LabelFile {
    segments_xyxy: Vec<[f64; 4]>,
    vp_px: Vec<[f64; 2]>,
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let (Some(dir), Some(out)) = (args.get(1), args.get(2)) else {
        return Err("usage: snap_misses YUD_DIR OUT_DIR".into());
    };
    let (dir, out) = (Path::new(dir), Path::new(out));
    std::fs::create_dir_all(out)?;
    let config = YudConfig::default();
    let base = run_yud(dir, &config, &vpmap_eval::Silent)?;
    if args.get(3).is_some_and(|a| a == "summary") {
        let md = vpmap_eval::clicks::yud::yud_markdown(&config, &base);
        for l in md.lines().filter(|l| {
            l.starts_with("| every")
                || l.starts_with("| labels the photo does not")
                || l.starts_with("Clicks that")
        }) {
            println!("{l}");
        }
        return Ok(());
    }
    let opts = SnapOptions::for_click_sigma(config.sigma_px);
    let variants: Vec<(&str, SnapOptions, bool)> = vec![
        ("as is", opts, false),
        ("labelled vanishing points", opts, true),
        (
            "angle tolerance 15 deg",
            SnapOptions {
                angle_tolerance_deg: 15.0,
                ..opts
            },
            false,
        ),
        (
            "contrast 3 grey levels",
            SnapOptions {
                min_contrast: 3.0,
                ..opts
            },
            false,
        ),
        (
            "pieces from 3 px",
            SnapOptions {
                min_support_px: 3.0,
                ..opts
            },
            false,
        ),
        (
            "radius 7.3 px",
            SnapOptions {
                search_radius_px: 7.3,
                ..opts
            },
            false,
        ),
        (
            "corner gap 2 px",
            SnapOptions {
                corner_gap_px: 2.0,
                ..opts
            },
            false,
        ),
        (
            "edge length 8 px",
            SnapOptions {
                min_edge_px: 8.0,
                ..opts
            },
            false,
        ),
        (
            "edge length 6 px",
            SnapOptions {
                min_edge_px: 6.0,
                ..opts
            },
            false,
        ),
        (
            "smoothing 0.7 px",
            SnapOptions {
                smoothing_sigma_px: 0.7,
                ..opts
            },
            false,
        ),
    ];
    let reasons = ["no meeting within the radius", "unsure: an edge too short"];
    // counts[reason][variant] = clicks snapped within GOOD_PX of the label; [.. ][n] = total.
    let mut counts: BTreeMap<&str, Vec<usize>> = BTreeMap::new();
    let mut exact_counts: BTreeMap<&str, usize> = BTreeMap::new();
    let mut totals: BTreeMap<&str, usize> = BTreeMap::new();
    let mut sheet_log = String::new();
    let mut samples: BTreeMap<&str, Vec<RgbImage>> = BTreeMap::new();
    let mut seen: BTreeMap<&str, usize> = BTreeMap::new();
    for pair in find_pairs(dir)? {
        let label: LabelFile = serde_json::from_str(&std::fs::read_to_string(&pair.label)?)?;
        let photo = decode_photo(&std::fs::read(&pair.image)?, &PhotoLimits::default())?;
        let image = SnapImage::new(&photo.image);
        let rgb = photo.image.to_rgb8();
        let detected: Vec<[f64; 3]> = detect(&photo.image, &DetectOptions::default())
            .map(|d| {
                let (f, c) = (d.intrinsics.focal_px, d.intrinsics.principal_point_px);
                d.vanishing_points
                    .iter()
                    .map(|v| {
                        let k = v.direction_camera;
                        [f * k[0] + c[0] * k[2], f * k[1] + c[1] * k[2], k[2]]
                    })
                    .collect()
            })
            .unwrap_or_default();
        let labelled: Vec<[f64; 3]> = label.vp_px.iter().map(|p| [p[0], p[1], 1.0]).collect();
        let vps = if detected.len() >= 2 {
            detected
        } else {
            labelled.clone()
        };
        let segments: Vec<[f64; 4]> = label
            .segments_xyxy
            .iter()
            .map(|s| s.map(|v| v - config.label_shift_px))
            .collect();
        let clicks: Vec<_> = base
            .clicks
            .iter()
            .filter(|c| c.photo == pair.name)
            .collect();
        for c in clicks {
            let Some(reason) = c.kept.and_then(|k| reasons.iter().find(|r| **r == k)) else {
                continue;
            };
            let click = [
                c.corner.point_px[0] + c.error_vec_px[0],
                c.corner.point_px[1] + c.error_vec_px[1],
            ];
            *totals.entry(reason).or_default() += 1;
            let row = counts
                .entry(reason)
                .or_insert_with(|| vec![0; variants.len()]);
            let mut fixes = Vec::new();
            for (k, (name, o, use_labelled)) in variants.iter().enumerate() {
                let v = if *use_labelled { &labelled } else { &vps };
                let s = snap_click(&image, v, click, o)?;
                let e = (s.point_px[0] - c.corner.point_px[0])
                    .hypot(s.point_px[1] - c.corner.point_px[1]);
                if s.snapped() && e <= GOOD_PX {
                    row[k] += 1;
                    fixes.push(*name);
                }
            }
            let exact = snap_click(&image, &vps, c.corner.point_px, &opts)?;
            if exact.snapped() {
                *exact_counts.entry(reason).or_default() += 1;
            }
            // Every k-th click of the reason, for the sheets.
            let n = seen.entry(reason).or_default();
            *n += 1;
            let stride = match *reason {
                "no meeting within the radius" => 14,
                _ => 8,
            };
            if !(*n - 1).is_multiple_of(stride)
                || samples.get(reason).is_some_and(|v| v.len() >= SAMPLE)
            {
                continue;
            }
            let snap = snap_click(&image, &vps, click, &opts)?;
            let meeting = match snap.outcome {
                SnapOutcome::Kept(
                    KeptReason::TooFar {
                        corner_px: Some(p), ..
                    }
                    | KeptReason::Unsure { corner_px: p, .. },
                ) => Some(p),
                _ => None,
            };
            let edges = edges_near_click(&image, &vps, click, &opts)?;
            let segs: Vec<[f64; 4]> = c
                .corner
                .segments
                .iter()
                .filter_map(|&s| segments.get(s).copied())
                .collect();
            let crop = draw_crop(&rgb, c.corner.point_px, click, &segs, &edges, meeting);
            let list = samples.entry(reason).or_default();
            let index = list.len();
            let _ = writeln!(
                sheet_log,
                "{reason} #{index} (sheet {}, place {}): {} corner ({:.1}, {:.1}) click ({:.1}, {:.1}), {:.1} px off; fixed by: {}; kept: {}; edges: {}",
                index / 8,
                index % 8,
                pair.name,
                c.corner.point_px[0],
                c.corner.point_px[1],
                click[0],
                click[1],
                c.raw_error_px,
                fixes.join(", "),
                match snap.outcome {
                    SnapOutcome::Kept(r) => r.to_string(),
                    SnapOutcome::Snapped => "snapped".to_owned(),
                },
                edges
                    .iter()
                    .map(|e| format!(
                        "[{} {:.0} px g {:.0}]",
                        e.direction, e.support_px, e.gradient
                    ))
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            list.push(crop);
        }
    }
    // The angle between the two labelled lines, by outcome.
    let mut by_angle: BTreeMap<String, [usize; 6]> = BTreeMap::new();
    for c in &base.clicks {
        let [n1, n2] = c.corner.normals;
        let sine = (n1[0] * n2[1] - n1[1] * n2[0]).abs();
        let deg = sine.asin().to_degrees();
        let bin = match deg {
            d if d < 30.0 => 0,
            d if d < 45.0 => 1,
            d if d < 60.0 => 2,
            d if d < 75.0 => 3,
            d if d < 85.0 => 4,
            _ => 5,
        };
        let key = c.kept.unwrap_or("snapped").to_owned();
        by_angle.entry(key).or_default()[bin] += 1;
        by_angle.entry("every click".to_owned()).or_default()[bin] += 1;
    }
    println!("angle between the labelled lines: <30, 30-45, 45-60, 60-75, 75-85, 85-90 deg");
    for (k, v) in &by_angle {
        println!("  {k:40} {v:?}");
    }
    for (reason, row) in &counts {
        let total = totals.get(reason).copied().unwrap_or(0);
        println!(
            "{reason}: {total} clicks; a click on the labelled corner itself snaps for {}",
            exact_counts.get(reason).copied().unwrap_or(0)
        );
        for ((name, _, _), n) in variants.iter().zip(row) {
            println!("  {name:28} snapped within {GOOD_PX} px of the label: {n}");
        }
    }
    for (reason, crops) in &samples {
        let tag = if reason.starts_with("no meeting") {
            "nomeet"
        } else {
            "short"
        };
        for (k, chunk) in crops.chunks(8).enumerate() {
            let side = (2 * HALF as u32 + 1) * SCALE;
            let mut sheet =
                RgbImage::from_pixel(4 * (side + 6), 2 * (side + 6), Rgb([255, 255, 255]));
            for (i, crop) in chunk.iter().enumerate() {
                let (x, y) = ((i % 4) as u32 * (side + 6), (i / 4) as u32 * (side + 6));
                image::imageops::overlay(&mut sheet, crop, i64::from(x), i64::from(y));
            }
            sheet.save(out.join(format!("sheet-{tag}-{k}.png")))?;
        }
    }
    std::fs::write(out.join("sheets.txt"), sheet_log)?;
    Ok(())
}

/// The crop around `centre`, enlarged, with the labels, the click and the edges drawn.
fn draw_crop(
    rgb: &RgbImage,
    centre: [f64; 2],
    click: [f64; 2],
    segments: &[[f64; 4]],
    edges: &[vpmap_vision::snap::FoundEdge],
    meeting: Option<[f64; 2]>,
) -> RgbImage {
    let side = (2 * HALF + 1) as u32;
    let (x0, y0) = (
        centre[0].floor() as i64 - HALF,
        centre[1].floor() as i64 - HALF,
    );
    let mut img = RgbImage::from_fn(side * SCALE, side * SCALE, |x, y| {
        let (px, py) = (x0 + i64::from(x / SCALE), y0 + i64::from(y / SCALE));
        let (w, h) = (i64::from(rgb.width()), i64::from(rgb.height()));
        if px < 0 || py < 0 || px >= w || py >= h {
            Rgb([0, 0, 0])
        } else {
            *rgb.get_pixel(px as u32, py as u32)
        }
    });
    let to = |p: [f64; 2]| {
        [
            (p[0] - x0 as f64) * f64::from(SCALE),
            (p[1] - y0 as f64) * f64::from(SCALE),
        ]
    };
    for s in segments {
        line(
            &mut img,
            to([s[0], s[1]]),
            to([s[2], s[3]]),
            Rgb([0, 230, 0]),
        );
    }
    for e in edges {
        let colour = match e.direction {
            EdgeDirection::VanishingPoint(_) => Rgb([40, 90, 255]),
            EdgeDirection::Free(_) => Rgb([0, 230, 230]),
        };
        line(&mut img, to(e.ends_px[0]), to(e.ends_px[1]), colour);
    }
    dot(&mut img, to(centre), Rgb([0, 230, 0]));
    cross(&mut img, to(click), Rgb([255, 0, 0]));
    if let Some(m) = meeting {
        dot(&mut img, to(m), Rgb([255, 0, 255]));
    }
    // The search radius about the click.
    let r = 4.9 * f64::from(SCALE);
    let c = to(click);
    for k in 0..360 {
        let a = f64::from(k).to_radians();
        put(
            &mut img,
            [c[0] + r * a.cos(), c[1] + r * a.sin()],
            Rgb([255, 120, 0]),
        );
    }
    img
}

fn put(img: &mut RgbImage, p: [f64; 2], c: Rgb<u8>) {
    if p[0] >= 0.0 && p[1] >= 0.0 && (p[0] as u32) < img.width() && (p[1] as u32) < img.height() {
        img.put_pixel(p[0] as u32, p[1] as u32, c);
    }
}

fn line(img: &mut RgbImage, a: [f64; 2], b: [f64; 2], c: Rgb<u8>) {
    let n = ((b[0] - a[0]).hypot(b[1] - a[1]).ceil() as usize).max(1);
    for k in 0..=n {
        let t = k as f64 / n as f64;
        let p = [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])];
        put(img, p, c);
        put(img, [p[0] + 1.0, p[1]], c);
    }
}

fn dot(img: &mut RgbImage, p: [f64; 2], c: Rgb<u8>) {
    for dy in -4..=4 {
        for dx in -4..=4 {
            if dx * dx + dy * dy <= 16 {
                put(img, [p[0] + f64::from(dx), p[1] + f64::from(dy)], c);
            }
        }
    }
}

fn cross(img: &mut RgbImage, p: [f64; 2], c: Rgb<u8>) {
    for d in -8..=8 {
        let d = f64::from(d);
        put(img, [p[0] + d, p[1] + d], c);
        put(img, [p[0] + d, p[1] - d], c);
    }
}
