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

/// More objects named as placed poorly than this, and [`printed_warnings`] names them in one
/// line instead of one each.
pub const GROUPED_PLACE_WARNINGS: usize = 3;

/// The map's warnings as `vpmap build` prints them: each as it is, except the objects a warning
/// names as placed poorly ("its place is uncertain", "its outline is uncertain";
/// [`FloorMap::warns_uncertain`]) when there are more than [`GROUPED_PLACE_WARNINGS`]: those
/// become one line, after the others, naming each object with its standard deviation in the
/// order of the map ("box4 +-0.15 m", "box10 +-0.08 m at a corner"). `map.json` keeps every
/// warning whole, with each one's direction.
#[must_use]
pub fn printed_warnings(map: &FloorMap) -> Vec<String> {
    // (name, the warning's "+-S m" and whether it is a corner's), in the map's order.
    let placed: Vec<(usize, &str, String, bool)> = map
        .objects
        .iter()
        .filter_map(|o| {
            let prefix = format!("object {:?}: its ", o.name);
            map.warnings.iter().enumerate().find_map(|(i, w)| {
                let rest = w.strip_prefix(&prefix)?;
                let (corner, rest) = if let Some(r) = rest.strip_prefix("outline is uncertain by ")
                {
                    (true, r)
                } else {
                    (false, rest.strip_prefix("place is uncertain by ")?)
                };
                let sd = rest.split(" m").next()?.to_owned();
                Some((i, o.name.as_str(), sd, corner))
            })
        })
        .collect();
    if placed.len() <= GROUPED_PLACE_WARNINGS {
        return map.warnings.clone();
    }
    let grouped: Vec<usize> = placed.iter().map(|p| p.0).collect();
    let mut out: Vec<String> = map
        .warnings
        .iter()
        .enumerate()
        .filter(|(i, _)| !grouped.contains(i))
        .map(|(_, w)| w.clone())
        .collect();
    let names: Vec<String> = placed
        .iter()
        .map(|(_, name, sd, corner)| {
            format!("{name} {sd} m{}", if *corner { " at a corner" } else { "" })
        })
        .collect();
    let sigma = map.fit.as_ref().map_or_else(String::new, |f| {
        format!(", for {:.2} px clicks", f.click_sigma_px)
    });
    let every_photo = if map.cameras.len() > 1 {
        " in every photo that shows them"
    } else {
        ""
    };
    out.push(format!(
        "{} of {} objects may lie more than {} m off (1 sigma along each one's least certain direction{sigma}): {}; snap their corners and click all they show{every_photo}, or add a photo that sees them from nearer (map.json's warnings give each one's direction)",
        placed.len(),
        map.objects.len(),
        vpmap_metrology::map::WARN_POSITION_M,
        names.join(", ")
    ));
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use vpmap_metrology::synth::{SynthOptions, synthesize};

    /// A built map of `boxes` boxes whose warnings are `warnings(names)`.
    fn map_warning(boxes: usize, warnings: impl Fn(&[String]) -> Vec<String>) -> FloorMap {
        let (scene, _) = synthesize(&SynthOptions {
            boxes,
            ..SynthOptions::default()
        })
        .unwrap();
        let mut map = crate::build(&scene, &crate::MapOptions::default())
            .unwrap()
            .map;
        let names: Vec<String> = map.objects.iter().map(|o| o.name.clone()).collect();
        map.warnings = warnings(&names);
        map
    }

    fn place(name: &str, sd: &str) -> String {
        format!(
            "object {name:?}: its place is uncertain by +-{sd} m (1 sigma along its least certain direction, 90 degrees from +x, for 2.00 px clicks), so it may lie more than 0.25 m off; snap its corners"
        )
    }

    #[test]
    fn a_few_objects_placed_poorly_are_named_one_by_one() {
        let map = map_warning(4, |n| vec![place(&n[0], "0.12"), "other".to_owned()]);
        assert_eq!(printed_warnings(&map), map.warnings);
    }

    #[test]
    fn many_objects_placed_poorly_are_named_in_one_line() {
        let map = map_warning(5, |n| {
            vec![
                place(&n[3], "0.20"),
                "a vanishing point disagrees".to_owned(),
                place(&n[0], "0.12"),
                format!(
                    "object {:?}: its outline is uncertain by +-0.09 m at its least certain corner (...)",
                    n[1]
                ),
                place(&n[4], "0.30"),
            ]
        });
        let names: Vec<&str> = map.objects.iter().map(|o| o.name.as_str()).collect();
        let printed = printed_warnings(&map);
        assert_eq!(printed.len(), 2, "{printed:?}");
        assert_eq!(printed[0], "a vanishing point disagrees");
        let expected = format!(
            "4 of {} objects may lie more than 0.25 m off",
            map.objects.len()
        );
        assert!(printed[1].starts_with(&expected), "{}", printed[1]);
        // In the map's order, the corner said.
        let listed = format!(
            ": {} +-0.12 m, {} +-0.09 m at a corner, {} +-0.20 m, {} +-0.30 m; snap",
            names[0], names[1], names[3], names[4]
        );
        assert!(printed[1].contains(&listed), "{}", printed[1]);
    }
}
