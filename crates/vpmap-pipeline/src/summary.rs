//! The text summary of a built map, as `vpmap build` and `vpmap demo` print it: each camera
//! (a room's photos each) with its error bars, each object with its size, height and where it
//! lies, the floor, and the occupancy grid. The warnings are the map's own
//! ([`FloorMap::warnings`]); the command line prints them on stderr.

use std::fmt::Write as _;

use vpmap_metrology::map::{CameraReport, FloorMap, Units};
use vpmap_plan::OccupancyGrid;

/// A map's unit in a sentence: `m` or `camera heights`.
fn unit_words(units: Units) -> &'static str {
    match units {
        Units::Meters => "m",
        Units::CameraHeights => "camera heights",
    }
}

/// The summary of `map` and its occupancy `grid`: one line per camera (and its error bars),
/// one per object, the floor and the grid, each ending in a newline.
///
/// # Example
/// ```
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_pipeline::{build, map_summary, MapOptions};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let built = build(&scene, &MapOptions::default()).unwrap();
/// let text = map_summary(&built.map, &built.grid);
/// assert!(text.starts_with("camera: "));
/// assert!(text.contains("occupancy grid "));
/// ```
#[must_use]
pub fn map_summary(map: &FloorMap, grid: &OccupancyGrid) -> String {
    let mut out = String::new();
    if map.cameras.is_empty() {
        camera_lines(&mut out, map, &map.camera, "camera");
    } else {
        for (k, c) in map.cameras.iter().enumerate() {
            camera_lines(&mut out, map, c, &format!("photo {}", k + 1));
        }
    }
    object_and_floor_lines(&mut out, map);
    let (free, occupied, unknown) = grid.counts();
    let total = (free + occupied + unknown).max(1) as f64;
    let _ = writeln!(
        out,
        "occupancy grid {} x {} cells at {} {}: {:.0} % free, {:.0} % occupied, {:.0} % unknown",
        grid.width(),
        grid.height(),
        grid.resolution_m(),
        unit_words(map.units),
        100.0 * free as f64 / total,
        100.0 * occupied as f64 / total,
        100.0 * unknown as f64 / total,
    );
    out
}

/// One camera's line and its error bars; a room's cameras also say where they stood.
fn camera_lines(out: &mut String, map: &FloorMap, c: &CameraReport, label: &str) {
    let u = unit_words(map.units);
    let placed = c.heading_deg.map_or_else(String::new, |h| {
        let sd = c
            .uncertainty
            .as_ref()
            .and_then(|e| e.position_sd.zip(e.heading_deg_sd));
        format!(
            ", at ({:.3}, {:.3}) {u} heading {h:.1} deg{}",
            c.position[0],
            c.position[1],
            sd.map_or_else(String::new, |([sx, sy], sh)| format!(
                " (+- {sx:.3}, {sy:.3} {u}, {sh:.2} deg)"
            ))
        )
    });
    let _ = writeln!(
        out,
        "{label}: {} perspective, focal {:.1} px, principal point ({:.1}, {:.1}), pitch {:.2} deg, roll {:.2} deg, height {:.3} {u}{placed}",
        c.perspective.words(),
        c.focal_px,
        c.principal_point[0],
        c.principal_point[1],
        c.pitch_deg,
        c.roll_deg,
        c.height
    );
    if let (Some(e), Some(f)) = (&c.uncertainty, &map.fit) {
        let pp = e
            .principal_point_px_sd
            .map(|[x, y]| format!(", principal point ({x:.1}, {y:.1}) px"));
        let _ = writeln!(
            out,
            "  +- (1 sigma): focal {:.1} px{}, pitch {:.2} deg, roll {:.2} deg, height {:.3} {u}; for {:.2} px clicks ({}), reprojection RMS {:.2} px{}",
            e.focal_px_sd,
            pp.unwrap_or_default(),
            e.pitch_deg_sd,
            e.roll_deg_sd,
            e.height_sd,
            f.click_sigma_px,
            match f.click_sigma_source.as_str() {
                "given" => "given",
                "residuals" => "estimated from the residuals",
                "covariances" => "the clicks without their own covariance; the others by it",
                _ => "default",
            },
            f.rms_residual_px,
            f.rms_normalised
                .map(|n| format!(" ({n:.2} sigma normalised by each click's covariance)"))
                .unwrap_or_default()
        );
    }
}

/// The objects and the floor.
fn object_and_floor_lines(out: &mut String, map: &FloorMap) {
    let u = unit_words(map.units);
    for o in &map.objects {
        let pm = |sd: Option<f64>| sd.map_or_else(String::new, |s| format!(" +- {s:.3}"));
        let (u_len, u_br, u_h) = o.uncertainty.as_ref().map_or((None, None, None), |e| {
            (e.length_sd, e.breadth_sd, e.height_sd)
        });
        let size = o.size.map_or_else(
            || format!("area {:.3} {u}^2", o.area),
            |s| {
                format!(
                    "{:.3}{} x {:.3}{} {u}",
                    s.length,
                    pm(u_len),
                    s.breadth,
                    pm(u_br)
                )
            },
        );
        let height = o.height.map_or_else(
            || "height unknown".to_owned(),
            |h| format!("height {h:.3}{} {u}", pm(u_h)),
        );
        let place = o.uncertainty.as_ref().map_or_else(String::new, |e| {
            format!(
                " (95 % within {:.3} x {:.3} {u})",
                e.centroid_ellipse_95.semi_axes[0], e.centroid_ellipse_95.semi_axes[1]
            )
        });
        let _ = writeln!(
            out,
            "  {:<12} at ({:.3}, {:.3}) {u}{place}: {size}, {height}",
            o.name, o.centroid[0], o.centroid[1]
        );
    }
    let _ = writeln!(
        out,
        "floor: {} corners, free space {:.2} {u}^2 in {} region(s)",
        map.floor.len(),
        map.free_area(),
        map.free_space.len()
    );
}
