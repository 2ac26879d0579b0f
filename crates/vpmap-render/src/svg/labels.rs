//! Words on the picture: object labels and where they go (moved apart, with leader lines),
//! and the title.

use std::fmt::Write as _;

use vpmap_metrology::map::{FloorMap, MapObject, MapPoint};
use vpmap_metrology::reconstruct::ObjectKind;

use super::layout::{Frame, Layout, Rect};
use super::legend::UnitNames;
use super::numbers::fmt_num;
use super::style::{FloorPlanStyle, MAX_NAME_CHARS, MIN_FONT_PX, colour};
use super::xml::escape_xml;
use crate::geometry::is_finite;
use crate::metrics::text_width_px;

/// `text` cut to at most `max_chars` characters, ending in an ellipsis when cut.
fn truncate(text: &str, max_chars: usize) -> String {
    if text.chars().count() <= max_chars {
        return text.to_owned();
    }
    let mut out: String = text.chars().take(max_chars.saturating_sub(1)).collect();
    out.push('…');
    out
}

/// A font size at most `font_px` at which `text` fits in `max_width_px`, and the text, cut if
/// even [`MIN_FONT_PX`] is too large.
pub(super) fn fit_text(text: &str, font_px: f64, max_width_px: f64, bold: bool) -> (String, f64) {
    let width = text_width_px(text, font_px, bold);
    if width <= max_width_px {
        return (text.to_owned(), font_px);
    }
    let size = (font_px * max_width_px / width).max(MIN_FONT_PX);
    let mut chars = text.chars().count();
    let mut cut = text.to_owned();
    while chars > 1 && text_width_px(&cut, size, bold) > max_width_px {
        chars -= 1;
        cut = truncate(text, chars);
    }
    (cut, size)
}

/// A standard deviation with `decimals` decimals, or `<0.01` (one unit of the last decimal)
/// when it rounds to zero, so that a small but non-zero error bar is not shown as exactly 0.
pub(super) fn fmt_sd(sd: f64, decimals: usize) -> String {
    let text = fmt_num(sd, decimals);
    if sd > 0.0 && text.parse::<f64>().is_ok_and(|v| v == 0.0) {
        let unit = 10f64.powi(-i32::try_from(decimals).unwrap_or(12));
        format!("<{}", fmt_num(unit, decimals))
    } else {
        text
    }
}

/// `v`, followed by `± sd` when the standard deviation is known and finite.
fn with_sd(v: f64, sd: Option<f64>, decimals: usize) -> String {
    match sd {
        Some(sd) if sd.is_finite() && sd >= 0.0 => {
            format!("{} ± {}", fmt_num(v, decimals), fmt_sd(sd, decimals))
        }
        _ => fmt_num(v, decimals),
    }
}

/// The label of an object: its name line and the lines under it. Without error bars one line,
/// "L × B m, h H m" (a footprint: "area A m², h H m"); with them (method `fit`) the sizes and
/// the height each get `± sd` (1 sigma) and a line of their own.
fn object_label(o: &MapObject, u: &UnitNames, decimals: usize) -> (String, Vec<String>) {
    let name = truncate(o.name.trim(), MAX_NAME_CHARS);
    let name = if name.is_empty() {
        "(unnamed)".to_owned()
    } else {
        name
    };
    if let Some(unc) = &o.uncertainty {
        let height = match o.height {
            Some(h) => format!("h {} {}", with_sd(h, unc.height_sd, decimals), u.short),
            None => "h unknown".to_owned(),
        };
        let sizes = match (o.kind, o.size) {
            (ObjectKind::Box, Some(s)) => format!(
                "{} × {} {}",
                with_sd(s.length, unc.length_sd, decimals),
                with_sd(s.breadth, unc.breadth_sd, decimals),
                u.short
            ),
            _ => format!("area {} {}", fmt_num(o.area, decimals), u.area),
        };
        return (name, vec![sizes, height]);
    }
    let height = match o.height {
        Some(h) => format!("h {} {}", fmt_num(h, decimals), u.short),
        None => "h unknown".to_owned(),
    };
    let sizes = match (o.kind, o.size) {
        (ObjectKind::Box, Some(s)) => format!(
            "{} × {} {}, {height}",
            fmt_num(s.length, decimals),
            fmt_num(s.breadth, decimals),
            u.short
        ),
        _ => format!("area {} {}, {height}", fmt_num(o.area, decimals), u.area),
    };
    (name, vec![sizes])
}

/// Where an object's label is anchored: its centroid when that is in the plot, else the mean
/// of its finite corners.
fn label_anchor(o: &MapObject, frame: &Frame) -> Option<MapPoint> {
    if is_finite(o.centroid) && frame.shows(o.centroid) {
        return Some(o.centroid);
    }
    let pts: Vec<&MapPoint> = o.footprint.iter().filter(|p| is_finite(**p)).collect();
    if pts.is_empty() {
        return None;
    }
    let n = pts.len() as f64;
    Some([
        pts.iter().map(|p| p[0]).sum::<f64>() / n,
        pts.iter().map(|p| p[1]).sum::<f64>() / n,
    ])
}

/// The object labels (`<g id="labels">`), placed off each other and off the station point's
/// marker and label.
pub(super) fn object_labels(out: &mut String, map: &FloorMap, l: &Layout, u: &UnitNames) {
    let (f, frame, station, label_px, size_decimals) =
        (l.f, &l.frame, l.station, l.label_px, l.size_decimals);
    // Station point: marker with an arrow along +y, label to its right.
    let mut placed: Vec<Rect> = Vec::new();
    let r = l.station_r;
    let station_label = "camera";
    let station_rect = Rect {
        x: station.0 - r - 2.0,
        y: station.1 - 2.6 * r,
        w: 2.0 * r + 6.0 * f + text_width_px(station_label, label_px, false) + 4.0,
        h: 3.8 * r,
    };
    placed.push(station_rect);
    // The path's start and goal stay visible: labels keep off their markers.
    let end_r = l.path_end_r + 3.0 * f;
    for &(x, y) in &l.path_ends {
        placed.push(Rect {
            x: x - end_r,
            y: y - end_r,
            w: 2.0 * end_r,
            h: 2.0 * end_r,
        });
    }

    {
        let name_px = 14.0 * f;
        let size_px = 13.0 * f;
        let line_gap = 1.25 * name_px;
        let size_line_gap = 1.25 * size_px;
        let _ = writeln!(out, r#"<g id="labels" text-anchor="middle">"#);
        let object_px: Vec<PixelPolygon> = map
            .objects
            .iter()
            .map(|o| {
                o.footprint
                    .iter()
                    .filter(|p| is_finite(**p))
                    .map(|p| frame.px(*p))
                    .collect()
            })
            .collect();
        for (i, o) in map.objects.iter().enumerate() {
            let Some(anchor) = label_anchor(o, frame) else {
                continue;
            };
            let anchor_px = frame.px(anchor);
            let (name, lines) = object_label(o, u, size_decimals);
            let w = lines
                .iter()
                .map(|t| text_width_px(t, size_px, false))
                .fold(text_width_px(&name, name_px, true), f64::max)
                + 6.0 * f;
            let extra_lines = lines.len().saturating_sub(1) as f64;
            let h = line_gap + extra_lines * size_line_gap + size_px * 1.4 + 2.0 * f;
            let centred = Rect {
                x: anchor_px.0 - w / 2.0,
                y: anchor_px.1 - h / 2.0,
                w,
                h,
            };
            let rect = place_label(centred, Some(i), &object_px, &placed, frame);
            placed.push(rect);
            if rect.distance_to(anchor_px) > 1.0 {
                let (tx, ty) = (
                    anchor_px.0.clamp(rect.x, rect.x + rect.w),
                    anchor_px.1.clamp(rect.y, rect.y + rect.h),
                );
                let _ = writeln!(
                    out,
                    r#"<line x1="{:.2}" y1="{:.2}" x2="{tx:.2}" y2="{ty:.2}" stroke="{}" stroke-width="{:.2}"/><circle cx="{:.2}" cy="{:.2}" r="{:.2}" fill="{}" stroke="none"/>"#,
                    anchor_px.0,
                    anchor_px.1,
                    colour::MUTED,
                    0.8 * f,
                    anchor_px.0,
                    anchor_px.1,
                    1.8 * f,
                    colour::MUTED
                );
            }
            let _ = writeln!(
                out,
                r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" rx="{:.1}" fill="{}" fill-opacity="0.85" stroke="{}" stroke-width="{:.2}" stroke-opacity="0.5"/>"#,
                rect.x,
                rect.y,
                rect.w,
                rect.h,
                3.0 * f,
                colour::PAPER,
                colour::MUTED,
                0.6 * f
            );
            let cx = rect.x + rect.w / 2.0;
            let name_base = rect.y + name_px + 1.5 * f;
            let _ = writeln!(
                out,
                r#"<text x="{cx:.2}" y="{name_base:.2}" font-size="{name_px:.1}" font-weight="bold">{}</text>"#,
                escape_xml(&name)
            );
            for (k, line) in lines.iter().enumerate() {
                let _ = writeln!(
                    out,
                    r#"<text x="{cx:.2}" y="{:.2}" font-size="{size_px:.1}">{}</text>"#,
                    name_base + line_gap + k as f64 * size_line_gap,
                    escape_xml(line)
                );
            }
        }
        let _ = writeln!(out, "</g>");
    }
}

/// The title and the camera line under it.
pub(super) fn title(
    out: &mut String,
    map: &FloorMap,
    style: &FloorPlanStyle,
    l: &Layout,
    u: &UnitNames,
) {
    let (width, pad, title_px, sub_px, title_base, sub_base, size_decimals) = (
        l.width,
        l.pad,
        l.title_px,
        l.sub_px,
        l.title_base,
        l.sub_base,
        l.size_decimals,
    );
    let title = style.title.as_deref().unwrap_or("Floor map");
    // Title.
    let text_room = width - 2.0 * pad;
    let count = map.objects.len();
    let first = format!(
        "{title} — {count} object{}",
        if count == 1 { "" } else { "s" }
    );
    let (first, first_px) = fit_text(&first, title_px, text_room, true);
    let c = &map.camera;
    let second = if let Some(cu) = &c.uncertainty {
        // With error bars (method fit): ± 1 sigma; the height has none when the scale is the
        // camera height itself.
        let height = if cu.height_sd > 0.0 {
            with_sd(c.height, Some(cu.height_sd), size_decimals)
        } else {
            fmt_num(c.height, size_decimals)
        };
        format!(
            "camera: pitch {:.1} ± {}°, roll {:.1} ± {}°, height {height} {} · {} · method {} · units: {}",
            c.pitch_deg,
            fmt_sd(cu.pitch_deg_sd, 1),
            c.roll_deg,
            fmt_sd(cu.roll_deg_sd, 1),
            u.short,
            map.camera.perspective.name(),
            map.method,
            u.long
        )
    } else {
        format!(
            "camera: pitch {:.1}°, roll {:.1}°, height {} {} · {} · method {} · units: {}",
            c.pitch_deg,
            c.roll_deg,
            fmt_num(c.height, size_decimals),
            u.short,
            map.camera.perspective.name(),
            map.method,
            u.long
        )
    };
    // A room: how many photos, and that the camera line is the first photo's.
    let second = if map.cameras.len() > 1 {
        format!(
            "{} photos · {}",
            map.cameras.len(),
            second.replacen("camera:", "photo 1:", 1)
        )
    } else {
        second
    };
    let (second, second_px) = fit_text(&second, sub_px, text_room, false);
    let _ = writeln!(out, r#"<g id="title">"#);
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{title_base:.2}" font-size="{first_px:.1}" font-weight="bold">{}</text>"#,
        escape_xml(&first)
    );
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{sub_base:.2}" font-size="{second_px:.1}" fill="{}">{}</text>"#,
        colour::MUTED,
        escape_xml(&second)
    );
    if let (Some(fit), Some(fit_base)) = (&map.fit, l.fit_base) {
        let focal = c.uncertainty.map_or_else(String::new, |cu| {
            format!(
                "focal {} px · ",
                with_sd(c.focal_px, Some(cu.focal_px_sd), 1)
            )
        });
        let third = format!(
            "joint fit: {focal}click noise σ {} px ({}) · RMS residual {} px · ± are 1σ, ellipses 95 % of each centroid",
            fmt_num(fit.click_sigma_px, 2),
            fit_source_text(&fit.click_sigma_source),
            fmt_num(fit.rms_residual_px, 2),
        );
        let (third, third_px) = fit_text(&third, sub_px, text_room, false);
        let _ = writeln!(
            out,
            r#"<text id="fit-report" x="{pad:.2}" y="{fit_base:.2}" font-size="{third_px:.1}" fill="{}">{}</text>"#,
            colour::MUTED,
            escape_xml(&third)
        );
    }
    let _ = writeln!(out, "</g>");
}

/// Where the click noise of the error bars comes from, in words.
fn fit_source_text(source: &str) -> &str {
    match source {
        "given" => "given",
        "residuals" => "from the residuals",
        "default" => "default",
        other => other,
    }
}

/// Polygon in pixels.
pub(super) type PixelPolygon = Vec<(f64, f64)>;

/// Point in polygon by the even-odd ray test.
fn point_in_polygon((x, y): (f64, f64), poly: &[(f64, f64)]) -> bool {
    let mut inside = false;
    let next = poly.iter().cycle().skip(1);
    for (a, b) in poly.iter().zip(next) {
        if (a.1 > y) != (b.1 > y) && x < a.0 + (y - a.1) * (b.0 - a.0) / (b.1 - a.1) {
            inside = !inside;
        }
    }
    inside
}

/// Segments `p1 p2` and `q1 q2` cross (touching counts).
fn segments_cross(p1: (f64, f64), p2: (f64, f64), q1: (f64, f64), q2: (f64, f64)) -> bool {
    let orient = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
        (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
    };
    let (d1, d2) = (orient(q1, q2, p1), orient(q1, q2, p2));
    let (d3, d4) = (orient(p1, p2, q1), orient(p1, p2, q2));
    d1 * d2 <= 0.0 && d3 * d4 <= 0.0
}

impl Rect {
    fn corners(&self) -> [(f64, f64); 4] {
        [
            (self.x, self.y),
            (self.x + self.w, self.y),
            (self.x + self.w, self.y + self.h),
            (self.x, self.y + self.h),
        ]
    }

    /// The rectangle and the polygon share any point.
    pub(super) fn hits(&self, poly: &[(f64, f64)]) -> bool {
        if poly.len() < 3 {
            return false;
        }
        let corners = self.corners();
        if corners.iter().any(|c| point_in_polygon(*c, poly)) {
            return true;
        }
        if poly.iter().any(|p| {
            p.0 >= self.x && p.0 <= self.x + self.w && p.1 >= self.y && p.1 <= self.y + self.h
        }) {
            return true;
        }
        let rect_edges = corners.iter().zip(corners.iter().cycle().skip(1));
        rect_edges.into_iter().any(|(a, b)| {
            poly.iter()
                .zip(poly.iter().cycle().skip(1))
                .any(|(p, q)| segments_cross(*a, *b, *p, *q))
        })
    }

    /// The rectangle lies inside the polygon (corners inside, no edge crossing).
    fn inside(&self, poly: &[(f64, f64)]) -> bool {
        let corners = self.corners();
        corners.iter().all(|c| point_in_polygon(*c, poly))
            && !corners
                .iter()
                .zip(corners.iter().cycle().skip(1))
                .any(|(a, b)| {
                    poly.iter()
                        .zip(poly.iter().cycle().skip(1))
                        .any(|(p, q)| segments_cross(*a, *b, *p, *q))
                })
    }
}

/// Where a label goes. In order of preference:
/// 1. centred on its object, when it fits inside the object's outline and touches no other
///    label or object;
/// 2. the nearest spot (rings of 8 directions around the object) that touches no other label
///    and no object, drawn with a leader line;
/// 3. the nearest spot that touches no other label;
/// 4. centred, clamped into the plot.
///
/// `own` is the index of the label's object in `objects`.
pub(super) fn place_label(
    centred: Rect,
    own: Option<usize>,
    objects: &[PixelPolygon],
    placed: &[Rect],
    frame: &Frame,
) -> Rect {
    let free_of_labels = |r: &Rect| frame.contains(r) && !placed.iter().any(|p| p.overlaps(r));
    let free_of_objects = |r: &Rect, skip: Option<usize>| {
        objects
            .iter()
            .enumerate()
            .all(|(i, poly)| Some(i) == skip || !r.hits(poly))
    };
    let own_poly = own.and_then(|i| objects.get(i));
    if own_poly.is_some_and(|poly| centred.inside(poly))
        && free_of_labels(&centred)
        && free_of_objects(&centred, own)
    {
        return centred;
    }
    let (sx, sy) = (0.5 * centred.w + 6.0, 0.5 * centred.h + 4.0);
    let mut candidates: Vec<Rect> = Vec::with_capacity(8 * 8);
    for ring in 1..=8 {
        let k = f64::from(ring);
        for (dx, dy) in [
            (0.0, -1.0),
            (0.0, 1.0),
            (1.0, 0.0),
            (-1.0, 0.0),
            (1.0, -1.0),
            (-1.0, -1.0),
            (1.0, 1.0),
            (-1.0, 1.0),
        ] {
            candidates.push(Rect {
                x: centred.x + dx * k * sx,
                y: centred.y + dy * k * sy,
                ..centred
            });
        }
    }
    let centre = (centred.x + centred.w / 2.0, centred.y + centred.h / 2.0);
    candidates.sort_by(|a, b| a.distance_to(centre).total_cmp(&b.distance_to(centre)));
    if let Some(r) = candidates
        .iter()
        .find(|r| free_of_labels(r) && free_of_objects(r, None))
    {
        return *r;
    }
    if free_of_labels(&centred) {
        return centred;
    }
    if let Some(r) = candidates.iter().find(|r| free_of_labels(r)) {
        return *r;
    }
    centred.clamped_into(frame)
}
