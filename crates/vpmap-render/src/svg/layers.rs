//! The drawing, back to front: header and patterns, free space, field of view, hidden floor,
//! grid, floor outline, objects, path, station point, frame and axes, scale bar, legend.

use std::fmt::Write as _;

use vpmap_metrology::map::{FloorMap, MapPoint};
use vpmap_metrology::reconstruct::ObjectKind;

use super::labels::fmt_sd;
use super::layout::{Layout, polygon_path, ring_path};
use super::legend::{Swatch, UnitNames, has_ellipses};
use super::numbers::{fmt_num, grid_indices};
use super::style::{
    FONT_FAMILY, FloorPlanStyle, HIDDEN_PATTERN_FILL, HIDDEN_PATTERN_ID, MAX_PX, colour,
};
use super::xml::{SVG_FROM_MAP_ATTRIBUTE, escape_xml, matrix_text};
use crate::geometry::is_finite;

/// The XML declaration, the root element, title, description, clip path and patterns, and the paper.
pub(super) fn header(out: &mut String, style: &FloorPlanStyle, l: &Layout, u: &UnitNames) {
    let (width, height, f, frame) = (l.width, l.height, l.f, &l.frame);
    let hidden_paths = &l.hidden_paths;
    let title = style.title.as_deref().unwrap_or("Floor map");
    let _ = writeln!(out, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0}" height="{height:.0}" viewBox="0 0 {width:.0} {height:.0}" font-family="{FONT_FAMILY}" fill="{}" {SVG_FROM_MAP_ATTRIBUTE}="{}">"#,
        colour::TEXT,
        matrix_text(frame.svg_from_map())
    );
    let _ = writeln!(out, "<title>{}</title>", escape_xml(title));
    let _ = writeln!(
        out,
        "<desc>Floor plan drawn by vpmap-render: +y forward points up, +x right, units {}.</desc>",
        u.long
    );
    let _ = write!(
        out,
        r#"<defs><clipPath id="plot-clip"><rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}"/></clipPath>"#,
        frame.left, frame.top, frame.width, frame.height
    );
    if !hidden_paths.is_empty() {
        // Thin grey lines at 45° on a light grey ground, in page pixels (the same spacing in
        // the plot and in the legend swatch).
        let tile = 7.0 * f;
        let _ = write!(
            out,
            r#"<pattern id="{HIDDEN_PATTERN_ID}" patternUnits="userSpaceOnUse" x="0" y="0" width="{tile:.2}" height="{tile:.2}" patternTransform="rotate(45)"><rect x="0" y="0" width="{tile:.2}" height="{tile:.2}" fill="{}"/><line x1="{:.2}" y1="0" x2="{:.2}" y2="{tile:.2}" stroke="{}" stroke-width="{:.2}"/></pattern>"#,
            colour::HIDDEN_FILL,
            tile / 2.0,
            tile / 2.0,
            colour::HIDDEN_HATCH,
            1.1 * f
        );
    }
    let _ = writeln!(out, "</defs>");
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{width:.0}" height="{height:.0}" fill="{}"/>"#,
        colour::PAPER
    );
}

/// Open the plot group (map coordinates, clipped) with its background.
pub(super) fn plot_background(out: &mut String, l: &Layout) {
    let frame = &l.frame;
    // Everything in map coordinates, clipped to the plot.
    let _ = writeln!(out, r#"<g id="map" clip-path="url(#plot-clip)">"#);
    let _ = writeln!(
        out,
        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="{}"/>"#,
        frame.left,
        frame.top,
        frame.width,
        frame.height,
        colour::PLOT
    );
}

/// The free space, above the floor in view's fill.
pub(super) fn free_space(out: &mut String, map: &FloorMap, l: &Layout) {
    let (f, frame) = (l.f, &l.frame);
    let _ = writeln!(out, r#"<g id="free-space">"#);
    for d in map.free_space.iter().filter_map(|p| polygon_path(frame, p)) {
        let _ = writeln!(
            out,
            r#"<path d="{d}" fill="{}" fill-rule="evenodd" stroke="{}" stroke-width="{:.2}"/>"#,
            colour::FREE_FILL,
            colour::FREE_STROKE,
            0.8 * f
        );
    }
    let _ = writeln!(out, "</g>");
}

/// Which part of the field of view to draw: its fill goes under the free space, its dashed
/// outline over the free and hidden floor.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum FovPart {
    Fill,
    Outline,
}

/// The floor in view (or the field of view as a wedge when the map has no view polygon): its
/// opaque fill or its dashed outline.
pub(super) fn field_of_view(
    out: &mut String,
    map: &FloorMap,
    style: &FloorPlanStyle,
    l: &Layout,
    part: FovPart,
) {
    let (f, frame, station, span, fov_deg, fov_ok) =
        (l.f, &l.frame, l.station, l.span, l.fov_deg, l.fov_ok);
    let view: Vec<MapPoint> = map
        .camera
        .view_on_floor
        .iter()
        .copied()
        .filter(|p| p[0].is_finite() && p[1].is_finite())
        .collect();
    if style.show_field_of_view && map.cameras.len() > 1 {
        // A room: every photo's floor in view.
        let paths: Vec<String> = map
            .cameras
            .iter()
            .filter_map(|c| ring_path(frame, &c.view_on_floor))
            .collect();
        if part == FovPart::Fill {
            let _ = writeln!(out, r#"<g id="field-of-view">"#);
            for d in &paths {
                let _ = writeln!(
                    out,
                    r#"<path d="{d}" fill="{}" stroke="none"/>"#,
                    colour::FOV_FILL
                );
            }
        } else {
            let _ = writeln!(out, r#"<g id="field-of-view-outline">"#);
            for d in &paths {
                let _ = writeln!(
                    out,
                    r#"<path d="{d}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/>"#,
                    colour::FOV_RAY,
                    1.2 * f,
                    6.0 * f,
                    4.0 * f
                );
            }
        }
        let _ = writeln!(out, "</g>");
    } else if style.show_field_of_view && view.len() >= 3 {
        // The floor the photo shows: the image rectangle projected onto the floor.
        if let Some(d) = ring_path(frame, &view) {
            if part == FovPart::Fill {
                let _ = writeln!(
                    out,
                    r#"<g id="field-of-view"><path d="{d}" fill="{}" stroke="none"/></g>"#,
                    colour::FOV_FILL
                );
            } else {
                let _ = writeln!(
                    out,
                    r#"<g id="field-of-view-outline"><path d="{d}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/></g>"#,
                    colour::FOV_RAY,
                    1.2 * f,
                    6.0 * f,
                    4.0 * f
                );
            }
        }
    } else if style.show_field_of_view && fov_ok {
        let reach = 3.0 * span;
        let arc_steps = 32;
        let mut d = format!("M{:.2} {:.2} ", station.0, station.1);
        for i in 0..=arc_steps {
            let a = (fov_deg[0] + (fov_deg[1] - fov_deg[0]) * f64::from(i) / f64::from(arc_steps))
                .to_radians();
            let (x, y) = frame.px([reach * a.sin(), reach * a.cos()]);
            let _ = write!(d, "L{x:.2} {y:.2} ");
        }
        d.push('Z');
        if part == FovPart::Fill {
            let _ = writeln!(
                out,
                r#"<g id="field-of-view"><path d="{d}" fill="{}" stroke="none"/></g>"#,
                colour::FOV_FILL
            );
            return;
        }
        let _ = writeln!(out, r#"<g id="field-of-view-outline">"#);
        for a in fov_deg {
            let a = a.to_radians();
            let (x, y) = frame.px([reach * a.sin(), reach * a.cos()]);
            let _ = writeln!(
                out,
                r#"<line x1="{:.2}" y1="{:.2}" x2="{x:.2}" y2="{y:.2}" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/>"#,
                station.0,
                station.1,
                colour::FOV_RAY,
                1.2 * f,
                6.0 * f,
                4.0 * f
            );
        }
        let _ = writeln!(out, "</g>");
    }
}

/// The hidden floor, hatched.
pub(super) fn hidden(out: &mut String, l: &Layout) {
    let (f, hidden_paths) = (l.f, &l.hidden_paths);
    // Hidden floor: above the free space and the field of view (so its hatching is not tinted),
    // below the grid and the objects.
    if !hidden_paths.is_empty() {
        let _ = writeln!(out, r#"<g id="hidden">"#);
        for d in hidden_paths {
            let _ = writeln!(
                out,
                r#"<path class="hidden" d="{d}" fill="{HIDDEN_PATTERN_FILL}" fill-rule="evenodd" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round"/>"#,
                colour::HIDDEN_STROKE,
                0.6 * f
            );
        }
        let _ = writeln!(out, "</g>");
    }
}

/// The grid lines, when asked for.
pub(super) fn grid(out: &mut String, style: &FloorPlanStyle, l: &Layout) {
    let (f, frame, step, plot_bottom) = (l.f, &l.frame, l.step, l.plot_bottom);
    if style.show_grid {
        let _ = writeln!(
            out,
            r#"<g id="grid" stroke="{}" stroke-width="{:.2}" stroke-opacity="0.45">"#,
            colour::GRID,
            0.7 * f
        );
        for k in grid_indices(frame.x_min, frame.x_max(), step) {
            let (x, _) = frame.px([k * step, 0.0]);
            let _ = writeln!(
                out,
                r#"<line x1="{x:.2}" y1="{:.2}" x2="{x:.2}" y2="{plot_bottom:.2}"/>"#,
                frame.top
            );
        }
        for k in grid_indices(frame.y_min(), frame.y_max, step) {
            let (_, y) = frame.px([0.0, k * step]);
            let _ = writeln!(
                out,
                r#"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}"/>"#,
                frame.left,
                frame.left + frame.width
            );
        }
        let _ = writeln!(out, "</g>");
    }
}

/// The floor outline and the objects.
pub(super) fn floor_and_objects(out: &mut String, map: &FloorMap, l: &Layout) {
    let (f, frame) = (l.f, &l.frame);
    if let Some(d) = ring_path(frame, &map.floor) {
        let _ = writeln!(
            out,
            r#"<path id="floor" d="{d}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round"/>"#,
            colour::FLOOR,
            2.2 * f
        );
    }

    let _ = writeln!(out, r#"<g id="objects" stroke-linejoin="round">"#);
    for (i, o) in map.objects.iter().enumerate() {
        let Some(d) = ring_path(frame, &o.footprint) else {
            continue;
        };
        let (fill, stroke) = match o.kind {
            ObjectKind::Box => (colour::BOX_FILL, colour::BOX_STROKE),
            ObjectKind::Footprint => (colour::FOOTPRINT_FILL, colour::FOOTPRINT_STROKE),
        };
        let dash = if o.height.is_none() {
            format!(r#" stroke-dasharray="{:.1} {:.1}""#, 5.0 * f, 3.0 * f)
        } else {
            String::new()
        };
        let _ = writeln!(
            out,
            r#"<path id="object-{i}" class="object" d="{d}" fill="{fill}" fill-opacity="0.9" stroke="{stroke}" stroke-width="{:.2}"{dash}><title>{}</title></path>"#,
            1.5 * f,
            escape_xml(&o.name)
        );
    }
    let _ = writeln!(out, "</g>");
}

/// Each object's 95 % centroid ellipse and its centre (maps with error bars only): a
/// translucent ellipse with a dashed outline, above the objects so that it shows inside them.
pub(super) fn uncertainty(out: &mut String, map: &FloorMap, l: &Layout) {
    if !has_ellipses(map) {
        return;
    }
    let (f, frame) = (l.f, &l.frame);
    let _ = writeln!(out, r#"<g id="uncertainty">"#);
    for (i, o) in map.objects.iter().enumerate() {
        let Some(u) = &o.uncertainty else {
            continue;
        };
        let e = &u.centroid_ellipse_95;
        let [major, minor] = e.semi_axes;
        if !(is_finite(e.centre)
            && major.is_finite()
            && minor.is_finite()
            && e.angle_deg.is_finite())
        {
            continue;
        }
        let (cx, cy) = frame.px(e.centre);
        let rx = (major.abs() * frame.px_per_unit).min(MAX_PX);
        let ry = (minor.abs() * frame.px_per_unit).min(MAX_PX);
        // The map's angle is counter-clockwise with +y up; the picture's y runs down.
        let rotate = -e.angle_deg + 0.0;
        let _ = writeln!(
            out,
            r#"<ellipse id="ellipse-{i}" class="centroid-ellipse" cx="{cx:.2}" cy="{cy:.2}" rx="{rx:.2}" ry="{ry:.2}" transform="rotate({rotate:.2} {cx:.2} {cy:.2})" fill="{}" fill-opacity="0.18" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"><title>{}: centroid, 95 % ellipse {} × {}</title></ellipse><circle class="centroid" cx="{cx:.2}" cy="{cy:.2}" r="{:.2}" fill="{}" stroke="none"/>"#,
            colour::ELLIPSE,
            colour::ELLIPSE,
            1.2 * f,
            3.0 * f,
            2.0 * f,
            escape_xml(&o.name),
            escape_xml(&fmt_sd(major.abs(), l.size_decimals)),
            escape_xml(&fmt_sd(minor.abs(), l.size_decimals)),
            1.8 * f,
            colour::ELLIPSE
        );
    }
    let _ = writeln!(out, "</g>");
}

/// The planned path with its start and goal, when there is one.
pub(super) fn path(out: &mut String, style: &FloorPlanStyle, l: &Layout) {
    let (f, frame) = (l.f, &l.frame);
    let path_px: Vec<(f64, f64)> = style
        .path
        .iter()
        .filter(|p| is_finite(**p))
        .map(|p| frame.px(*p))
        .collect();
    if path_px.len() >= 2 {
        let points: Vec<String> = path_px
            .iter()
            .map(|(x, y)| format!("{x:.2},{y:.2}"))
            .collect();
        let _ = writeln!(out, r#"<g id="path">"#);
        let _ = writeln!(
            out,
            r#"<polyline points="{}" fill="none" stroke="{}" stroke-width="{:.2}" stroke-linejoin="round" stroke-linecap="round"/>"#,
            points.join(" "),
            colour::PATH,
            3.0 * f
        );
        // The start a ring, the goal a dot.
        for (i, (x, y)) in l.path_ends.iter().enumerate() {
            let _ = writeln!(out, "{}", path_end_marker(*x, *y, i == 0, l));
        }
        let _ = writeln!(out, "</g>");
    }
}

/// The path's start (a ring in the path's colour) or goal (a dot) at `(x, y)`, pixels.
pub(super) fn path_end_marker(x: f64, y: f64, start: bool, l: &Layout) -> String {
    let (r, f) = (l.path_end_r, l.f);
    if start {
        format!(
            r#"<circle class="path-start" cx="{x:.2}" cy="{y:.2}" r="{:.2}" fill="{}" stroke="{}" stroke-width="{:.2}"/>"#,
            r - 1.25 * f,
            colour::PAPER,
            colour::PATH,
            2.5 * f
        )
    } else {
        format!(
            r#"<circle class="path-goal" cx="{x:.2}" cy="{y:.2}" r="{r:.2}" fill="{}" stroke="{}" stroke-width="{:.2}"/>"#,
            colour::PATH,
            colour::PAPER,
            1.5 * f
        )
    }
}

/// A room's cameras after the first: each a marker with an arrow along its heading and its
/// photo's number.
pub(super) fn other_cameras(out: &mut String, map: &FloorMap, l: &Layout) {
    let (f, r, label_px) = (l.f, l.station_r, l.label_px);
    if map.cameras.len() < 2 {
        return;
    }
    let _ = writeln!(out, r#"<g id="cameras">"#);
    for (k, c) in map.cameras.iter().enumerate().skip(1) {
        let p = [c.position[0], c.position[1]];
        if !(p[0].is_finite() && p[1].is_finite()) {
            continue;
        }
        let (x, y) = l.frame.px(p);
        // The heading turns +y (up the page) counter-clockwise: on the page, left of up.
        let a = c.heading_deg.unwrap_or(0.0).to_radians();
        let (s, co) = a.sin_cos();
        let at = |along: f64, across: f64| {
            // Page coordinates: up is -y; the arrow points (-sin a, -cos a).
            (x - along * s + across * co, y - along * co - across * s)
        };
        let tip = at(2.4 * r, 0.0);
        let left = at(1.3 * r, -0.6 * r);
        let right = at(1.3 * r, 0.6 * r);
        let _ = writeln!(
            out,
            r#"<path d="M{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z" fill="{}" stroke="none"/>"#,
            tip.0,
            tip.1,
            left.0,
            left.1,
            right.0,
            right.1,
            colour::CAMERA
        );
        let _ = writeln!(
            out,
            r#"<circle cx="{x:.2}" cy="{y:.2}" r="{r:.2}" fill="{}" stroke="{}" stroke-width="{:.2}"/>"#,
            colour::CAMERA,
            colour::PAPER,
            1.5 * f
        );
        let _ = writeln!(
            out,
            r#"<text x="{:.2}" y="{:.2}" font-size="{label_px:.1}" stroke="{}" stroke-width="{:.2}" paint-order="stroke">photo {}</text>"#,
            x + r + 5.0 * f,
            y + 0.35 * label_px,
            colour::PAPER,
            3.0 * f,
            k + 1
        );
    }
    let _ = writeln!(out, "</g>");
}

/// The station point: marker with an arrow along +y, label to its right; closes the plot group.
pub(super) fn station_point(out: &mut String, map: &FloorMap, l: &Layout) {
    let (f, station, r, label_px) = (l.f, l.station, l.station_r, l.label_px);
    let station_label = if map.cameras.len() > 1 {
        "photo 1"
    } else {
        "camera"
    };
    let _ = writeln!(out, r#"<g id="station-point">"#);
    let _ = writeln!(
        out,
        r#"<path d="M{:.2} {:.2} L{:.2} {:.2} L{:.2} {:.2} Z" fill="{}" stroke="none"/>"#,
        station.0,
        station.1 - 2.4 * r,
        station.0 - 0.6 * r,
        station.1 - 1.3 * r,
        station.0 + 0.6 * r,
        station.1 - 1.3 * r,
        colour::CAMERA
    );
    let _ = writeln!(
        out,
        r#"<circle cx="{:.2}" cy="{:.2}" r="{r:.2}" fill="{}" stroke="{}" stroke-width="{:.2}"/>"#,
        station.0,
        station.1,
        colour::CAMERA,
        colour::PAPER,
        1.5 * f
    );
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="{:.2}" font-size="{label_px:.1}" stroke="{}" stroke-width="{:.2}" paint-order="stroke">{station_label}</text>"#,
        station.0 + r + 5.0 * f,
        station.1 + 0.35 * label_px,
        colour::PAPER,
        3.0 * f
    );
    let _ = writeln!(out, "</g>");
    let _ = writeln!(out, "</g>");
}

/// The plot's frame, ticks and axis titles.
pub(super) fn axes(out: &mut String, l: &Layout, u: &UnitNames) {
    let (f, frame, pad, step, tick_decimals, plot_bottom) =
        (l.f, &l.frame, l.pad, l.step, l.tick_decimals, l.plot_bottom);
    // Frame, ticks and axis titles.
    let _ = writeln!(
        out,
        r#"<rect x="{:.2}" y="{:.2}" width="{:.2}" height="{:.2}" fill="none" stroke="{}" stroke-width="{:.2}"/>"#,
        frame.left,
        frame.top,
        frame.width,
        frame.height,
        colour::FLOOR,
        f
    );
    let tick_px = 12.0 * f;
    let _ = writeln!(
        out,
        r#"<g id="axes" font-size="{tick_px:.1}" fill="{}">"#,
        colour::MUTED
    );
    for k in grid_indices(frame.x_min, frame.x_max(), step) {
        let (x, _) = frame.px([k * step, 0.0]);
        let _ = writeln!(
            out,
            r#"<line x1="{x:.2}" y1="{plot_bottom:.2}" x2="{x:.2}" y2="{:.2}" stroke="{}"/><text x="{x:.2}" y="{:.2}" text-anchor="middle">{}</text>"#,
            plot_bottom + 4.0 * f,
            colour::FLOOR,
            plot_bottom + 6.0 * f + tick_px,
            fmt_num(k * step, tick_decimals)
        );
    }
    for k in grid_indices(frame.y_min(), frame.y_max, step) {
        let (_, y) = frame.px([0.0, k * step]);
        let _ = writeln!(
            out,
            r#"<line x1="{:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{}"/><text x="{:.2}" y="{:.2}" text-anchor="end">{}</text>"#,
            frame.left - 4.0 * f,
            frame.left,
            colour::FLOOR,
            frame.left - 6.0 * f,
            y + 0.35 * tick_px,
            fmt_num(k * step, tick_decimals)
        );
    }
    let _ = writeln!(
        out,
        r#"<text x="{:.2}" y="{:.2}" text-anchor="middle" font-size="{:.1}" fill="{}">x ({}) → right</text>"#,
        frame.left + frame.width / 2.0,
        plot_bottom + 8.0 * f + 2.4 * tick_px,
        12.0 * f,
        colour::TEXT,
        u.short
    );
    let y_title_x = pad + 12.0 * f;
    let y_title_y = frame.top + frame.height / 2.0;
    let _ = writeln!(
        out,
        r#"<text x="{y_title_x:.2}" y="{y_title_y:.2}" text-anchor="middle" font-size="{:.1}" fill="{}" transform="rotate(-90 {y_title_x:.2} {y_title_y:.2})">y ({}) → forward</text>"#,
        12.0 * f,
        colour::TEXT,
        u.short
    );
    let _ = writeln!(out, "</g>");
}

/// The scale bar: "0", two alternating halves, then its length.
pub(super) fn scale_bar(out: &mut String, l: &Layout) {
    let (f, pad, footer_top, label_px, bar_px, bar_x) =
        (l.f, l.pad, l.footer_top, l.label_px, l.bar_px, l.bar_x);
    let bar_label = &l.bar_label;
    // Scale bar: "0", two alternating halves, then its length.
    let bar_h = 6.0 * f;
    let bar_y = footer_top - bar_h / 2.0;
    let half = bar_px / 2.0;
    let text_y = footer_top + 0.35 * label_px;
    let _ = writeln!(
        out,
        r#"<g id="scale-bar" font-size="{label_px:.1}" stroke="{}" stroke-width="{:.2}">"#,
        colour::TEXT,
        0.8 * f
    );
    let _ = writeln!(
        out,
        r#"<rect x="{bar_x:.2}" y="{bar_y:.2}" width="{half:.2}" height="{bar_h:.2}" fill="{}"/><rect x="{:.2}" y="{bar_y:.2}" width="{half:.2}" height="{bar_h:.2}" fill="{}"/>"#,
        colour::TEXT,
        bar_x + half,
        colour::PAPER
    );
    let _ = writeln!(
        out,
        r#"<text x="{pad:.2}" y="{text_y:.2}" stroke="none">0</text><text x="{:.2}" y="{text_y:.2}" stroke="none">{}</text>"#,
        bar_x + bar_px + 5.0 * f,
        escape_xml(bar_label)
    );
    let _ = writeln!(out, "</g>");
}

/// The legend, when it has entries.
pub(super) fn legend(out: &mut String, l: &Layout) {
    let (f, label_px, swatch_px) = (l.f, l.label_px, l.swatch_px);
    let (legend, legend_pos) = (&l.legend, &l.legend_pos);
    if !legend.is_empty() {
        let _ = writeln!(out, r#"<g id="legend" font-size="{label_px:.1}">"#);
        for ((swatch, text), (x, y)) in legend.iter().zip(legend_pos) {
            let sy = y - 0.4 * swatch_px;
            match swatch {
                Swatch::Fill {
                    fill,
                    stroke,
                    dashed,
                } => {
                    let dash = if *dashed {
                        format!(r#" stroke-dasharray="{:.1} {:.1}""#, 3.0 * f, 2.0 * f)
                    } else {
                        String::new()
                    };
                    let _ = write!(
                        out,
                        r#"<rect x="{x:.2}" y="{sy:.2}" width="{swatch_px:.2}" height="{:.2}" fill="{fill}" stroke="{stroke}" stroke-width="{:.2}"{dash}/>"#,
                        0.8 * swatch_px,
                        1.2 * f
                    );
                }
                Swatch::Line { stroke, dashed } => {
                    let dash = if *dashed {
                        format!(r#" stroke-dasharray="{:.1} {:.1}""#, 4.0 * f, 2.5 * f)
                    } else {
                        String::new()
                    };
                    let _ = write!(
                        out,
                        r#"<line x1="{x:.2}" y1="{y:.2}" x2="{:.2}" y2="{y:.2}" stroke="{stroke}" stroke-width="{:.2}"{dash}/>"#,
                        x + swatch_px,
                        2.0 * f
                    );
                }
                Swatch::Ellipse => {
                    let (cx, rx, ry) = (x + swatch_px / 2.0, 0.5 * swatch_px, 0.3 * swatch_px);
                    let _ = write!(
                        out,
                        r#"<ellipse cx="{cx:.2}" cy="{y:.2}" rx="{rx:.2}" ry="{ry:.2}" fill="{}" fill-opacity="0.18" stroke="{}" stroke-width="{:.2}" stroke-dasharray="{:.1} {:.1}"/><circle cx="{cx:.2}" cy="{y:.2}" r="{:.2}" fill="{}"/>"#,
                        colour::ELLIPSE,
                        colour::ELLIPSE,
                        1.2 * f,
                        3.0 * f,
                        2.0 * f,
                        1.8 * f,
                        colour::ELLIPSE
                    );
                }
                Swatch::PathEnd { start } => {
                    let _ = write!(
                        out,
                        "{}",
                        path_end_marker(x + swatch_px / 2.0, *y, *start, l)
                    );
                }
                Swatch::Dot => {
                    let _ = write!(
                        out,
                        r#"<circle cx="{:.2}" cy="{y:.2}" r="{:.2}" fill="{}"/>"#,
                        x + swatch_px / 2.0,
                        0.3 * swatch_px,
                        colour::CAMERA
                    );
                }
            }
            let _ = writeln!(
                out,
                r#"<text x="{:.2}" y="{:.2}">{}</text>"#,
                x + swatch_px + 6.0 * f,
                y + 0.35 * label_px,
                escape_xml(text)
            );
        }
        let _ = writeln!(out, "</g>");
    }
}
