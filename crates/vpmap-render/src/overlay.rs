//! The detection overlay (`vpmap detect --overlay`): the photo with what was detected drawn
//! on it, as PNG ([`detection_overlay_png`]).
//!
//! The photo is half desaturated so that the drawing stands out. Segments supporting the first
//! horizontal vanishing point are red, the second green, the vertical blue, each drawn
//! `thickness` pixels wide (about 1/500 of the longer side); unassigned segments are thin and
//! grey. The horizon (the image of the plane orthogonal to the vertical direction) is yellow;
//! vanishing points inside the photo are filled circles in their colour; the principal point
//! is a magenta cross in a circle. Thin yellow lines either side of the horizon are its 95 %
//! band (the scene's camera before any click). A legend strip under the photo names each
//! colour and symbol, with each direction's ± at 95 % (the major semi-axis of its written
//! ellipse) and the band's half-width (the photo's own pixels keep their coordinates).
//!
//! When the detection applied a lens (its division model's `k` is not 0), the vanishing points,
//! the horizon and its band are pinhole geometry: they are drawn where the photo shows them,
//! through the lens. A straight pinhole line is then a curve in the photo, drawn as a polyline of
//! [`LENS_CURVE_SAMPLES`] points; the segments are the photo's own and are drawn as found.

use std::fmt::Write as _;
use std::io::Cursor;

use image::{DynamicImage, ImageFormat, Rgb, RgbImage};
use imageproc::drawing::{
    draw_antialiased_line_segment_mut, draw_filled_circle_mut, draw_hollow_circle_mut,
};
use imageproc::pixelops::interpolate;
use vpmap_metrology::fit::CHI2_2DOF_95;
use vpmap_metrology::scene::DivisionModel;
use vpmap_vision::Detection;
use vpmap_vision::scene::{DetectedScene, VP_NAMES};

use crate::error::RenderError;
use crate::raster::svg_to_png;
use crate::svg::{FONT_FAMILY, escape_xml};

/// Colours of the two horizontal and the vertical vanishing point.
pub const VP_COLOURS: [Rgb<u8>; 3] = [Rgb([235, 45, 45]), Rgb([40, 205, 60]), Rgb([40, 120, 255])];
/// Colour names for the summary, in [`VP_COLOURS`] order.
pub const VP_COLOUR_NAMES: [&str; 3] = ["red", "green", "blue"];
const UNASSIGNED: Rgb<u8> = Rgb([165, 165, 165]);
const HORIZON: Rgb<u8> = Rgb([255, 215, 0]);
const PRINCIPAL_POINT: Rgb<u8> = Rgb([255, 0, 255]);
const OUTLINE: Rgb<u8> = Rgb([255, 255, 255]);
/// The normal quantile at 97.5 % (a two-sided 95 % interval).
const Z_95: f64 = 1.959_963_984_540_054;
/// Points of the polyline a pinhole line is drawn as through a lens: at most about 8 px apart
/// on a 2000 px photo, where a phone's lens bends a line by well under a pixel between them.
pub const LENS_CURVE_SAMPLES: usize = 256;

/// An error's message followed by its sources', joined by `: `.
fn chain_text(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}

/// The overlay of a detection on its photo, as PNG bytes: the photo half desaturated, the
/// segments coloured by vanishing point ([`VP_COLOURS`]; unassigned ones thin and grey), the
/// horizon, the vanishing points inside the photo and the principal point, and a legend strip
/// under the photo (whose pixels keep their coordinates).
///
/// # Errors
/// [`RenderError::Overlay`] when the legend cannot be drawn or the PNG encoded.
pub fn detection_overlay_png(
    photo: &DynamicImage,
    det: &Detection,
    scene: &DetectedScene,
) -> Result<Vec<u8>, RenderError> {
    let mut canvas = desaturated(photo);
    let (w, h) = canvas.dimensions();
    let thickness = (w.max(h) / 500).clamp(2, 12);

    let mut role_of = vec![None; det.segments.len()];
    for (role, &vp) in scene.roles.iter().enumerate() {
        let Some(point) = det.vanishing_points.get(vp) else {
            continue;
        };
        for &s in &point.segments {
            if let Some(slot) = role_of.get_mut(s) {
                *slot = Some(role);
            }
        }
    }
    for (seg, role) in det.segments.iter().zip(&role_of) {
        if role.is_none() {
            draw_thick_segment(&mut canvas, seg.start_px, seg.end_px, 1, UNASSIGNED);
        }
    }
    for (seg, role) in det.segments.iter().zip(&role_of) {
        if let Some(&colour) = role.and_then(|r| VP_COLOURS.get(r)) {
            draw_thick_segment(&mut canvas, seg.start_px, seg.end_px, thickness, colour);
        }
    }

    // The lens the detection applied: the pinhole geometry below is drawn through it.
    let lens = det
        .lens
        .as_ref()
        .map(|l| l.model)
        .filter(|m| m.k != 0.0 && m.k.is_finite());
    // The horizon: l = K^-T v, scaled by f.
    let f = det.intrinsics.focal_px;
    let c = det.intrinsics.principal_point_px;
    let v = scene.directions[2];
    let line = [v[0], v[1], f * v[2] - c[0] * v[0] - c[1] * v[1]];
    draw_pinhole_line(&mut canvas, line, lens.as_ref(), thickness, HORIZON);
    // Its 95 % band: the horizon moved by 1.96 sd either way (the scene's camera before any
    // click), thin lines.
    let horizon_95_px = scene
        .camera_estimate()
        .map(|e| Z_95 * e.horizon_sd_px)
        .filter(|d| d.is_finite() && *d > 0.0);
    let norm = line[0].hypot(line[1]);
    if let Some(d) = horizon_95_px
        && norm > 0.0
    {
        for side in [-1.0, 1.0] {
            let moved = [line[0], line[1], line[2] + side * d * norm];
            draw_pinhole_line(&mut canvas, moved, lens.as_ref(), 1, HORIZON);
        }
    }

    let radius = 2 * thickness as i32 + 2;
    for (p, &colour) in scene.points_px.iter().zip(&VP_COLOURS) {
        let p = match (p, lens.as_ref()) {
            (Some(p), Some(model)) => model.distort(*p),
            (p, None) => *p,
            (None, Some(_)) => None,
        };
        if let Some(p) = p
            && inside(p, w, h)
        {
            let centre = (p[0].round() as i32, p[1].round() as i32);
            draw_filled_circle_mut(&mut canvas, centre, radius + 1, OUTLINE);
            draw_filled_circle_mut(&mut canvas, centre, radius, colour);
        }
    }
    if inside(c, w, h) {
        let arm = 6.0 * f64::from(thickness);
        draw_thick_segment(
            &mut canvas,
            [c[0] - arm, c[1]],
            [c[0] + arm, c[1]],
            thickness,
            PRINCIPAL_POINT,
        );
        draw_thick_segment(
            &mut canvas,
            [c[0], c[1] - arm],
            [c[0], c[1] + arm],
            thickness,
            PRINCIPAL_POINT,
        );
        let centre = (c[0].round() as i32, c[1].round() as i32);
        for k in 0..thickness as i32 {
            draw_hollow_circle_mut(
                &mut canvas,
                centre,
                4 * thickness as i32 + k,
                PRINCIPAL_POINT,
            );
        }
    }

    // Each direction's 95 % spread (the ellipse's major semi-axis) in the legend.
    let spread: [Option<f64>; 3] = std::array::from_fn(|role| {
        scene
            .covariances
            .get(role)
            .copied()
            .flatten()
            .map(|c| c.major_sd_deg() * CHI2_2DOF_95.sqrt())
    });
    let canvas = with_legend(&canvas, thickness, spread, horizon_95_px)?;
    let mut bytes = Vec::new();
    DynamicImage::ImageRgb8(canvas)
        .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
        .map_err(|e| RenderError::Overlay {
            step: "encoding the overlay as PNG",
            reason: chain_text(&e),
        })?;
    Ok(bytes)
}

/// `#rrggbb` of a colour.
fn hex(c: Rgb<u8>) -> String {
    format!("#{:02x}{:02x}{:02x}", c.0[0], c.0[1], c.0[2])
}

/// What a legend entry's symbol is.
enum Symbol {
    /// A line this many photo pixels wide.
    Line(Rgb<u8>, u32),
    /// A vanishing point's filled circle.
    Dot,
    /// The principal point's cross in a circle.
    Cross,
}

/// The legend's SVG for a photo `width` pixels wide, and its height in pixels: one row per
/// fitting run of entries, text about 1/70 of the width (11 to 28 px).
fn legend_svg(
    width: u32,
    thickness: u32,
    spread_deg: [Option<f64>; 3],
    horizon_95_px: Option<f64>,
) -> (String, u32) {
    let names = VP_NAMES;
    let vp = |role: usize| {
        let within = spread_deg[role]
            .map(|d| format!(" (±{d:.1}° at 95 %)"))
            .unwrap_or_default();
        format!("segments of the {}{within}", names[role])
    };
    let entries: [(Symbol, String); 7] = [
        (Symbol::Line(VP_COLOURS[0], thickness), vp(0)),
        (Symbol::Line(VP_COLOURS[1], thickness), vp(1)),
        (Symbol::Line(VP_COLOURS[2], thickness), vp(2)),
        (
            Symbol::Line(UNASSIGNED, 1),
            "unassigned segments".to_owned(),
        ),
        (
            Symbol::Line(HORIZON, thickness),
            horizon_95_px.map_or_else(
                || "horizon".to_owned(),
                |d| format!("horizon, thin lines its 95 % band (±{d:.1} px)"),
            ),
        ),
        (
            Symbol::Dot,
            "vanishing point (when inside the photo)".to_owned(),
        ),
        (Symbol::Cross, "principal point".to_owned()),
    ];
    let w = f64::from(width);
    let font = (w / 70.0).clamp(11.0, 28.0);
    let (pad, symbol, gap, row_h) = (0.8 * font, 2.2 * font, 0.5 * font, 1.7 * font);
    // DejaVu Sans averages about 0.6 em per character in these words; 0.62 errs wide.
    let text_w = |s: &str| 0.62 * font * s.chars().count() as f64;
    let mut placed = Vec::with_capacity(entries.len());
    let (mut x, mut row) = (pad, 0u32);
    for (sym, label) in entries {
        let entry_w = symbol + gap + text_w(&label);
        if x > pad && x + entry_w > w - pad {
            x = pad;
            row += 1;
        }
        placed.push((sym, label, x, row));
        x += entry_w + 2.0 * font;
    }
    let height = (2.0 * pad + f64::from(row + 1) * row_h).ceil() as u32;
    let t = f64::from(thickness);
    let mut svg = format!(
        r##"<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="{FONT_FAMILY}" font-size="{font:.1}"><rect width="{width}" height="{height}" fill="#ffffff"/>"##
    );
    for (sym, label, x, row) in placed {
        let y = pad + (f64::from(row) + 0.5) * row_h;
        let xm = x + symbol / 2.0;
        let _ = match sym {
            Symbol::Line(colour, width) => write!(
                svg,
                r#"<line x1="{x:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}" stroke="{}" stroke-width="{}"/>"#,
                x + symbol,
                hex(colour),
                width.max(1)
            ),
            Symbol::Dot => {
                let r = (2.0 * t + 2.0).min(0.45 * row_h);
                write!(
                    svg,
                    r##"<circle cx="{:.1}" cy="{y:.1}" r="{r:.1}" fill="{}" stroke="#888888"/><circle cx="{:.1}" cy="{y:.1}" r="{r:.1}" fill="{}" stroke="#888888"/>"##,
                    xm - 0.6 * r,
                    hex(VP_COLOURS[0]),
                    xm + 0.6 * r,
                    hex(VP_COLOURS[1]),
                )
            }
            Symbol::Cross => {
                let arm = (6.0 * t).min(0.5 * row_h);
                let c = hex(PRINCIPAL_POINT);
                write!(
                    svg,
                    r#"<g stroke="{c}" stroke-width="{t}" fill="none"><line x1="{:.1}" y1="{y:.1}" x2="{:.1}" y2="{y:.1}"/><line x1="{xm:.1}" y1="{:.1}" x2="{xm:.1}" y2="{:.1}"/><circle cx="{xm:.1}" cy="{y:.1}" r="{:.1}"/></g>"#,
                    xm - arm,
                    xm + arm,
                    y - arm,
                    y + arm,
                    0.66 * arm
                )
            }
        };
        let _ = write!(
            svg,
            r##"<text x="{:.1}" y="{:.1}" fill="#1a1a1a">{}</text>"##,
            x + symbol + gap,
            y + 0.35 * font,
            escape_xml(&label)
        );
    }
    svg.push_str("</svg>\n");
    (svg, height)
}

/// The drawing with the legend strip under it: the photo's pixels keep their coordinates.
fn with_legend(
    drawing: &RgbImage,
    thickness: u32,
    spread_deg: [Option<f64>; 3],
    horizon_95_px: Option<f64>,
) -> Result<RgbImage, RenderError> {
    let (w, h) = drawing.dimensions();
    let (svg, strip_h) = legend_svg(w, thickness, spread_deg, horizon_95_px);
    let png = svg_to_png(&svg).map_err(|e| RenderError::Overlay {
        step: "drawing the overlay's legend",
        reason: chain_text(&e),
    })?;
    let strip = image::load_from_memory_with_format(&png, ImageFormat::Png)
        .map_err(|e| RenderError::Overlay {
            step: "reading the overlay's legend",
            reason: chain_text(&e),
        })?
        .to_rgb8();
    let mut out = RgbImage::from_pixel(w, h + strip_h, OUTLINE);
    image::imageops::replace(&mut out, drawing, 0, 0);
    image::imageops::replace(&mut out, &strip, 0, i64::from(h));
    Ok(out)
}

/// The photo as RGB, half way to grey.
fn desaturated(photo: &DynamicImage) -> RgbImage {
    let mut rgb = photo.to_rgb8();
    for p in rgb.pixels_mut() {
        let [r, g, b] = p.0.map(f32::from);
        let grey = 0.299 * r + 0.587 * g + 0.114 * b;
        p.0 = [r, g, b].map(|v| (0.5 * v + 0.5 * grey).round().clamp(0.0, 255.0) as u8);
    }
    rgb
}

fn inside(p: [f64; 2], w: u32, h: u32) -> bool {
    p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= f64::from(w) && p[1] <= f64::from(h)
}

/// A segment `thickness` pixels wide: parallel antialiased lines one pixel apart, clipped to
/// the canvas first (the line drawer walks every pixel between its ends).
fn draw_thick_segment(
    canvas: &mut RgbImage,
    a: [f64; 2],
    b: [f64; 2],
    thickness: u32,
    colour: Rgb<u8>,
) {
    let (w, h) = canvas.dimensions();
    let Some((a, b)) = clip_segment(a, b, w, h) else {
        return;
    };
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    if len < 1.0 {
        return;
    }
    let normal = [-(b[1] - a[1]) / len, (b[0] - a[0]) / len];
    for k in 0..thickness {
        let off = f64::from(k) - f64::from(thickness - 1) / 2.0;
        let shift = |p: [f64; 2]| {
            (
                (p[0] + off * normal[0]).round() as i32,
                (p[1] + off * normal[1]).round() as i32,
            )
        };
        let (s, e) = (shift(a), shift(b));
        if s != e {
            draw_antialiased_line_segment_mut(canvas, s, e, colour, interpolate);
        }
    }
}

/// Liang-Barsky: the part of segment `a`-`b` inside `[0, w - 1] x [0, h - 1]`.
fn clip_segment(a: [f64; 2], b: [f64; 2], w: u32, h: u32) -> Option<([f64; 2], [f64; 2])> {
    if !(a.iter().chain(&b).all(|v| v.is_finite())) {
        return None;
    }
    let (xmax, ymax) = (f64::from(w.max(1) - 1), f64::from(h.max(1) - 1));
    let d = [b[0] - a[0], b[1] - a[1]];
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d[0], a[0]),
        (d[0], xmax - a[0]),
        (-d[1], a[1]),
        (d[1], ymax - a[1]),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    (t0 <= t1).then(|| {
        (
            [a[0] + t0 * d[0], a[1] + t0 * d[1]],
            [a[0] + t1 * d[0], a[1] + t1 * d[1]],
        )
    })
}

/// The part of the line `l[0] x + l[1] y + l[2] = 0` inside the image.
/// The pinhole line `l` (homogeneous, pixels) as the photo shows it: straight and clipped to
/// the canvas without a lens; through `lens` a curve, the line's part inside the photo's
/// undistorted reach sampled at [`LENS_CURVE_SAMPLES`] points, each taken to its photo pixel
/// ([`DivisionModel::distort`]) and joined (each piece clipped to the canvas as it is drawn).
fn draw_pinhole_line(
    canvas: &mut RgbImage,
    l: [f64; 3],
    lens: Option<&DivisionModel>,
    thickness: u32,
    colour: Rgb<u8>,
) {
    let (w, h) = canvas.dimensions();
    let Some(model) = lens else {
        if let Some((a, b)) = clip_line(l, w, h) {
            draw_thick_segment(canvas, a, b, thickness, colour);
        }
        return;
    };
    let n = l[0].hypot(l[1]);
    if !(n.is_finite() && n > 0.0 && l[2].is_finite()) {
        return;
    }
    let c = [model.centre_px.x, model.centre_px.y];
    // How far from the centre the photo's pixels reach once undistorted: the largest over
    // its border (corners and 64 points a side; a division model's undistorted radius need
    // not grow with the photo's).
    let (wf, hf) = (f64::from(w), f64::from(h));
    let mut reach: f64 = 0.0;
    for i in 0..=64 {
        let t = f64::from(i) / 64.0;
        for p in [[t * wf, 0.0], [t * wf, hf], [0.0, t * hf], [wf, t * hf]] {
            let u = model.undistort(p);
            reach = reach.max((u[0] - c[0]).hypot(u[1] - c[1]));
        }
    }
    let reach = 1.01 * reach;
    let dist = (l[0] * c[0] + l[1] * c[1] + l[2]) / n;
    if !dist.is_finite() || dist.abs() >= reach {
        return;
    }
    let foot = [c[0] - dist * l[0] / n, c[1] - dist * l[1] / n];
    let dir = [-l[1] / n, l[0] / n];
    let half = (reach * reach - dist * dist).sqrt();
    let mut last: Option<[f64; 2]> = None;
    for i in 0..LENS_CURVE_SAMPLES {
        let t = -half + 2.0 * half * i as f64 / (LENS_CURVE_SAMPLES - 1) as f64;
        let here = model.distort([foot[0] + t * dir[0], foot[1] + t * dir[1]]);
        if let (Some(a), Some(b)) = (last, here) {
            draw_thick_segment(canvas, a, b, thickness, colour);
        }
        last = here;
    }
}

fn clip_line(l: [f64; 3], w: u32, h: u32) -> Option<([f64; 2], [f64; 2])> {
    let n = l[0].hypot(l[1]);
    if !(n.is_finite() && n > 0.0 && l[2].is_finite()) {
        return None;
    }
    let centre = [f64::from(w) / 2.0, f64::from(h) / 2.0];
    // The foot of the image centre on the line, and the line's direction.
    let dist = (l[0] * centre[0] + l[1] * centre[1] + l[2]) / n;
    let foot = [centre[0] - dist * l[0] / n, centre[1] - dist * l[1] / n];
    let dir = [-l[1] / n, l[0] / n];
    let reach = f64::from(w) + f64::from(h);
    if dist.abs() > reach {
        return None;
    }
    clip_segment(
        [foot[0] - reach * dir[0], foot[1] - reach * dir[1]],
        [foot[0] + reach * dir[0], foot[1] + reach * dir[1]],
        w,
        h,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clipping_keeps_the_inside_part() {
        let (a, b) = clip_segment([-10.0, 5.0], [200.0, 5.0], 100, 50).unwrap_or_default();
        assert!(a[0].abs() + (a[1] - 5.0).abs() + (b[0] - 99.0).abs() + (b[1] - 5.0).abs() < 1e-9);
        assert!(clip_segment([-10.0, -5.0], [200.0, -5.0], 100, 50).is_none());
        // The line y = x.
        let (a, b) = clip_line([1.0, -1.0, 0.0], 100, 50).unwrap_or_default();
        assert!((a[0] - a[1]).abs() < 1e-9 && (b[0] - b[1]).abs() < 1e-9);
        assert!(
            a[1].abs() < 1e-9 && (b[1] - 49.0).abs() < 1e-9,
            "{a:?} {b:?}"
        );
        assert!(clip_line([0.0, 1.0, -500.0], 100, 50).is_none());
    }
}
