//! The fields of a scene or room file that vpmap does not read ([`unknown_fields`]): `vpmap
//! build` warns of each one, so that a typo does not pass unnoticed.

use super::BoxCorner;

/// The fields of a scene file that vpmap does not read (often typos such as `scael`), as
/// paths like `"scael"`, `objects[0]."heigth"` or `scale."meter"`; empty when `value` is not
/// an object.
///
/// # Example
/// ```
/// use vpmap_metrology::scene::unknown_fields;
/// let v = serde_json::json!({"version": 1, "scael": {}, "objects": [{"name": "a", "heigth": 2}]});
/// assert_eq!(unknown_fields(&v), ["\"scael\"", "objects[0].\"heigth\""]);
/// ```
#[must_use]
pub fn unknown_fields(value: &serde_json::Value) -> Vec<String> {
    if super::room::is_room_value(value) {
        let Some(top) = value.as_object() else {
            return Vec::new();
        };
        let mut out: Vec<String> = top
            .keys()
            .filter(|k| !["version", "photos"].contains(&k.as_str()))
            .map(|k| format!("{k:?}"))
            .collect();
        if let Some(photos) = top.get("photos").and_then(serde_json::Value::as_array) {
            for (k, p) in photos.iter().enumerate() {
                out.extend(
                    photo_unknown_fields(p)
                        .into_iter()
                        .map(|f| format!("photos[{k}].{f}")),
                );
            }
        }
        return out;
    }
    photo_unknown_fields(value)
}

/// [`unknown_fields`] of one photo's scene.
fn photo_unknown_fields(value: &serde_json::Value) -> Vec<String> {
    const TOP: [&str; 14] = [
        "click_covariances_px2",
        "placement_turn_deg",
        "lens_distortion",
        "focal_sd_px",
        "principal_point_sd_px",
        "version",
        "image",
        "vanishing_points",
        "principal_point",
        "focal_px",
        "objects",
        "floor",
        "scale",
        "perspective",
    ];
    const OBJECT: [&str; 5] = ["name", "base", "footprint", "top", "own_yaw"];
    const SCALE: [&str; 6] = [
        "camera_height_m",
        "object",
        "dimension",
        "edge",
        "meters",
        "floor_distance",
    ];
    let Some(top) = value.as_object() else {
        return Vec::new();
    };
    let mut out: Vec<String> = top
        .keys()
        .filter(|k| !TOP.contains(&k.as_str()))
        .map(|k| format!("{k:?}"))
        .collect();
    if let Some(objects) = top.get("objects").and_then(serde_json::Value::as_array) {
        for (i, o) in objects.iter().enumerate() {
            if let Some(o) = o.as_object() {
                out.extend(
                    o.keys()
                        .filter(|k| !OBJECT.contains(&k.as_str()))
                        .map(|k| format!("objects[{i}].{k:?}")),
                );
                for (part, extra) in [("base", &[][..]), ("top", &["above", "point"][..])] {
                    if let Some(corners) = o.get(part).and_then(serde_json::Value::as_object) {
                        out.extend(
                            corners
                                .keys()
                                .filter(|k| {
                                    !BoxCorner::ALL.iter().any(|c| c.name() == k.as_str())
                                        && !extra.contains(&k.as_str())
                                })
                                .map(|k| format!("objects[{i}].{part}.{k:?}")),
                        );
                    }
                }
            }
        }
    }
    if let Some(scale) = top.get("scale").and_then(serde_json::Value::as_object) {
        out.extend(
            scale
                .keys()
                .filter(|k| !SCALE.contains(&k.as_str()))
                .map(|k| format!("scale.{k:?}")),
        );
    }
    out
}
