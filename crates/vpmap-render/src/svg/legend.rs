//! The legend's words: a map's unit names, and the legend's entries (what the picture shows,
//! each with its swatch).

use vpmap_metrology::map::{FloorMap, Units};
use vpmap_metrology::reconstruct::ObjectKind;

use super::numbers::fmt_num;
use super::style::{FloorPlanStyle, HIDDEN_LEGEND, HIDDEN_PATTERN_FILL, colour};
use crate::geometry::is_finite;

/// Unit words of a map.
pub(super) struct UnitNames {
    /// After a length: "m".
    pub(super) short: &'static str,
    /// After an area: "m²".
    pub(super) area: &'static str,
    /// In the title: "metres".
    pub(super) long: &'static str,
}

pub(super) fn unit_names(units: Units) -> UnitNames {
    match units {
        Units::Meters => UnitNames {
            short: "m",
            area: "m²",
            long: "metres",
        },
        Units::CameraHeights => UnitNames {
            short: "ch",
            area: "ch²",
            long: "camera heights (ch; the camera is 1 ch above the floor)",
        },
    }
}

/// One legend entry: its swatch and its text.
pub(super) enum Swatch {
    Fill {
        fill: &'static str,
        stroke: &'static str,
        dashed: bool,
    },
    Line {
        stroke: &'static str,
        dashed: bool,
    },
    Dot,
    /// The path's start (a ring) or goal (a dot).
    PathEnd {
        start: bool,
    },
    /// An error ellipse with its centre.
    Ellipse,
}

/// Some object of the map carries a finite centroid ellipse (method `fit`).
pub(super) fn has_ellipses(map: &FloorMap) -> bool {
    map.objects.iter().any(|o| {
        o.uncertainty.as_ref().is_some_and(|u| {
            let e = &u.centroid_ellipse_95;
            is_finite(e.centre) && e.semi_axes.iter().all(|a| a.is_finite())
        })
    })
}

/// The legend's entries, in drawing order: what the picture shows.
// The facts are computed once by the layout, which also places the entries.
#[allow(clippy::too_many_arguments)]
pub(super) fn legend_entries(
    map: &FloorMap,
    style: &FloorPlanStyle,
    u: &UnitNames,
    has_hidden: bool,
    fov_deg: [f64; 2],
    fov_ok: bool,
    step: f64,
    tick_decimals: usize,
) -> Vec<(Swatch, String)> {
    let mut legend: Vec<(Swatch, String)> = Vec::new();
    if style.show_legend {
        if !map.free_space.is_empty() {
            legend.push((
                Swatch::Fill {
                    fill: colour::FREE_FILL,
                    stroke: colour::FREE_STROKE,
                    dashed: false,
                },
                "free space".to_owned(),
            ));
        }
        if has_hidden {
            legend.push((
                Swatch::Fill {
                    fill: HIDDEN_PATTERN_FILL,
                    stroke: colour::HIDDEN_STROKE,
                    dashed: false,
                },
                if map.cameras.len() > 1 {
                    "hidden from every camera".to_owned()
                } else {
                    HIDDEN_LEGEND.to_owned()
                },
            ));
        }
        if map.floor.len() >= 3 {
            legend.push((
                Swatch::Line {
                    stroke: colour::FLOOR,
                    dashed: false,
                },
                "floor outline".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.kind == ObjectKind::Box) {
            legend.push((
                Swatch::Fill {
                    fill: colour::BOX_FILL,
                    stroke: colour::BOX_STROKE,
                    dashed: false,
                },
                "box".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.kind == ObjectKind::Footprint) {
            legend.push((
                Swatch::Fill {
                    fill: colour::FOOTPRINT_FILL,
                    stroke: colour::FOOTPRINT_STROKE,
                    dashed: false,
                },
                "footprint".to_owned(),
            ));
        }
        if map.objects.iter().any(|o| o.height.is_none()) {
            legend.push((
                Swatch::Fill {
                    fill: colour::PAPER,
                    stroke: colour::MUTED,
                    dashed: true,
                },
                "height unknown".to_owned(),
            ));
        }
        if has_ellipses(map) {
            legend.push((
                Swatch::Ellipse,
                "centroid, 95 % confidence ellipse".to_owned(),
            ));
        }
        legend.push((
            Swatch::Dot,
            if map.cameras.len() > 1 {
                "cameras (station points)".to_owned()
            } else {
                "camera (station point)".to_owned()
            },
        ));
        if style.path.len() >= 2 {
            legend.push((
                Swatch::Line {
                    stroke: colour::PATH,
                    dashed: false,
                },
                if style.path_label.is_empty() {
                    "planned path".to_owned()
                } else {
                    style.path_label.clone()
                },
            ));
            legend.push((Swatch::PathEnd { start: true }, "start".to_owned()));
            legend.push((Swatch::PathEnd { start: false }, "goal".to_owned()));
        }
        if style.show_field_of_view && fov_ok {
            legend.push((
                Swatch::Fill {
                    fill: colour::FOV_FILL,
                    stroke: colour::FOV_RAY,
                    dashed: true,
                },
                if map.cameras.len() > 1 {
                    "floor in view of each photo".to_owned()
                } else if map.camera.view_on_floor.len() >= 3 {
                    format!(
                        "floor in view (field of view {:.0}°)",
                        fov_deg[1] - fov_deg[0]
                    )
                } else {
                    format!("field of view {:.0}°", fov_deg[1] - fov_deg[0])
                },
            ));
        }
        if style.show_grid {
            legend.push((
                Swatch::Line {
                    stroke: colour::GRID,
                    dashed: false,
                },
                format!("grid {} {}", fmt_num(step, tick_decimals), u.short),
            ));
        }
    }
    legend
}
