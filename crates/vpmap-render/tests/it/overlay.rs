//! The detection overlay through a lens: the horizon a pinhole camera's geometry gives is drawn
//! where the distorted photo shows it, checked by taking the drawn pixels back through the
//! division model's definition (written out here, not the library's `undistort`) onto the
//! horizon of an independently built camera.

use image::{DynamicImage, Rgb, RgbImage};
use nalgebra::{Vector2, Vector3};
use vpmap_metrology::scene::DivisionModel;
use vpmap_render::overlay::detection_overlay_png;
use vpmap_vision::distortion::LensEstimate;
use vpmap_vision::scene::detected_scene;
use vpmap_vision::{Detection, Intrinsics, Perspective, VanishingPoint};

const W: u32 = 1600;
const H: u32 = 1200;
const FOCAL_PX: f64 = 800.0;
const PITCH_DEG: f64 = 20.0;

/// A camera pitched down by [`PITCH_DEG`], no roll, the room turned 30 degrees: its three
/// directions in the camera frame (x right, y down, z forward), vertical last, each with z >= 0.
fn directions() -> [Vector3<f64>; 3] {
    let t = PITCH_DEG.to_radians();
    // World up is (0, -cos t, -sin t) in the camera frame; its opposite has z >= 0.
    let vertical = Vector3::new(0.0, t.cos(), t.sin());
    let forward = Vector3::new(0.0, -t.sin(), t.cos());
    let side = Vector3::new(1.0, 0.0, 0.0);
    let a = 30f64.to_radians();
    let signed = |d: Vector3<f64>| if d.z < 0.0 { -d } else { d };
    [
        signed(side * a.cos() + forward * a.sin()),
        signed(-side * a.sin() + forward * a.cos()),
        vertical,
    ]
}

/// The photo pixel `p` taken to the pinhole image by the division model with `k`, centre the
/// image centre, radius in half-diagonals: `c + (p - c) / (1 + k r^2)`.
fn undistorted_by_definition(k: f64, p: [f64; 2]) -> [f64; 2] {
    let c = [f64::from(W) / 2.0, f64::from(H) / 2.0];
    let unit = f64::from(W).hypot(f64::from(H)) / 2.0;
    let d = [p[0] - c[0], p[1] - c[1]];
    let r2 = (d[0] * d[0] + d[1] * d[1]) / (unit * unit);
    [c[0] + d[0] / (1.0 + k * r2), c[1] + d[1] / (1.0 + k * r2)]
}

/// The photo pixel of pinhole pixel `u`: the definition above solved for the photo pixel by
/// fixed-point iteration (`p = c + (u - c) (1 + k r(p)^2)`).
fn distorted_by_definition(k: f64, u: [f64; 2]) -> [f64; 2] {
    let c = [f64::from(W) / 2.0, f64::from(H) / 2.0];
    let unit = f64::from(W).hypot(f64::from(H)) / 2.0;
    let mut p = u;
    for _ in 0..200 {
        let r2 = ((p[0] - c[0]).powi(2) + (p[1] - c[1]).powi(2)) / (unit * unit);
        p = [
            c[0] + (u[0] - c[0]) * (1.0 + k * r2),
            c[1] + (u[1] - c[1]) * (1.0 + k * r2),
        ];
    }
    p
}

fn detection(k: f64) -> Detection {
    let c = [f64::from(W) / 2.0, f64::from(H) / 2.0];
    let dirs = directions();
    let vanishing_points = dirs
        .iter()
        .enumerate()
        .map(|(i, d)| VanishingPoint {
            point_px: Some([FOCAL_PX * d.x / d.z + c[0], FOCAL_PX * d.y / d.z + c[1]]),
            direction_camera: [d.x, d.y, d.z],
            segments: Vec::new(),
            vertical: i == 2,
            own_point: None,
        })
        .collect();
    let model = DivisionModel {
        k,
        centre_px: Vector2::new(c[0], c[1]),
        radius_unit_px: f64::from(W).hypot(f64::from(H)) / 2.0,
    };
    Detection {
        image_size_px: [W, H],
        segments: Vec::new(),
        vanishing_points,
        intrinsics: Intrinsics {
            focal_px: FOCAL_PX,
            principal_point_px: c,
        },
        focal_estimated: false,
        principal_point_estimated: false,
        principal_point_off_centre: false,
        principal_point_given: true,
        focal_prior: None,
        perspective: Perspective::ThreePoint,
        vertical_tilt_deg: 90.0 - PITCH_DEG,
        lens: Some(LensEstimate {
            model,
            estimated_k: k,
            k_sd: 0.005,
            segments_k_sd: None,
            segments: 0,
        }),
    }
}

/// For every 40th column, the rows of the photo (not the legend) drawn in the horizon's
/// yellow (antialiased over the grey photo).
fn yellow_rows(png: &[u8]) -> Vec<(u32, Vec<u32>)> {
    let img = image::load_from_memory(png).unwrap().to_rgb8();
    (20..W)
        .step_by(40)
        .map(|x| {
            let rows = (0..H)
                .filter(|&y| {
                    let Rgb([r, g, b]) = *img.get_pixel(x, y);
                    // Yellow over the grey photo, antialiased: at least 40 % yellow.
                    i32::from(r) - i32::from(b) > 100 && i32::from(g) - i32::from(b) > 70
                })
                .collect();
            (x, rows)
        })
        .collect()
}

#[test]
fn through_a_lens_the_horizon_is_drawn_where_the_distorted_photo_shows_it() {
    // The pinhole horizon of this camera: the row cy - f tan(pitch), straight across.
    let horizon_row = f64::from(H) / 2.0 - FOCAL_PX * PITCH_DEG.to_radians().tan();
    let photo = DynamicImage::ImageRgb8(RgbImage::from_pixel(W, H, Rgb([128, 128, 128])));
    for k in [-0.12, -0.06, 0.0] {
        let det = detection(k);
        let scene = detected_scene(&det).unwrap();
        let png = detection_overlay_png(&photo, &det, &scene).unwrap();
        crate::save_for_review(&format!("overlay-lens-{k}.png"), &png);
        // The vanishing points' discs are drawn over the horizon: their columns are left out.
        let discs: Vec<f64> = det
            .vanishing_points
            .iter()
            .filter_map(|v| v.point_px)
            .map(|u| distorted_by_definition(k, u)[0])
            .collect();
        let columns = yellow_rows(&png);
        let mut worst: f64 = 0.0;
        let mut looked_at = 0;
        for (x, rows) in &columns {
            if discs.iter().any(|d| (d - f64::from(*x)).abs() < 20.0) {
                continue;
            }
            looked_at += 1;
            // Of the yellow rows (the horizon and its thin 95 % band), those nearest the
            // horizon once taken back through the lens: the thick line itself.
            let nearest = rows
                .iter()
                .map(|&y| {
                    (undistorted_by_definition(k, [f64::from(*x), f64::from(y)])[1] - horizon_row)
                        .abs()
                })
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(nearest);
        }
        assert!(
            looked_at >= 35,
            "k = {k}: only {looked_at} columns looked at"
        );
        // Pixel centres and the line's 3 px width: within 1.5 px of the pinhole horizon in
        // every column. Drawn straight (as before the lens was drawn through), some column's
        // nearest yellow pixel lies 11.4 px off at k = -0.12.
        assert!(
            worst <= 1.5,
            "k = {k}: a column's horizon pixels lie {worst:.1} px from the true horizon once undistorted"
        );
    }
}
