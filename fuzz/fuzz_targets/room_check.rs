//! The checks of a room file that the `room` and `room_file` targets share: as `vpmap build`
//! and `vpmap snap` read it, UTF-8 text, an optional byte-order mark, a JSON object with
//! `photos`, its unknown fields (named per photo), the room's parsing and validation (each
//! photo's own checks, then what ties the photos into one room), the round trip of what vpmap
//! writes back, and `vpmap snap`'s writing of snapped clicks into each photo of the room's
//! JSON (never at the room's top level).

use vpmap_metrology::scene::{Scene, unknown_fields};
use vpmap_vision::clicks::scene_clicks;
use vpmap_vision::snap::scene::{SnappedClick, write_snapped};
use vpmap_vision::snap::{Snap, SnapOutcome};

/// The room `data` holds when it reads as one, after every check above (a failed check
/// panics: a finding).
pub fn check_room_file(data: &[u8]) -> Option<Scene> {
    let Ok(text) = std::str::from_utf8(data) else {
        return None;
    };
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    if !text.trim_start().starts_with('{') {
        return None;
    }
    let value: serde_json::Value = serde_json::from_str(text).unwrap_or(serde_json::Value::Null);
    let _ = unknown_fields(&value);
    let Ok(room) = Scene::from_json_str(text) else {
        return None;
    };
    // Round trip: what vpmap writes back must read back.
    let again = room.to_json_string();
    if let Err(e) = Scene::from_json_str(&again) {
        panic!("a parsed room does not read back: {e}\n{again}");
    }
    // `vpmap snap`'s writing: every click of each photo "snapped" where it is with a 1 px
    // covariance, written into that photo of the room's JSON (never at the room's top level).
    let mut json = value.clone();
    let is_room = json.get("photos").is_some();
    for (k, photo) in room.photos().enumerate() {
        let snapped: Vec<SnappedClick> = scene_clicks(photo)
            .into_iter()
            .map(|c| SnappedClick {
                place: c.place,
                snap: Snap {
                    click_px: c.point_px,
                    point_px: c.point_px,
                    covariance_px2: Some([[1.0, 0.0], [0.0, 1.0]]),
                    edges: Vec::new(),
                    outcome: SnapOutcome::Snapped,
                },
            })
            .collect();
        let target = if is_room {
            json.get_mut("photos").and_then(|p| p.get_mut(k))
        } else {
            Some(&mut json)
        };
        let Some(target) = target else {
            panic!("photo {k} of a parsed room is not in its JSON");
        };
        if let Err(e) = write_snapped(target, &snapped, Some(2.0)) {
            panic!("photo {k}: snapped clicks cannot be written: {e}");
        }
    }
    if is_room && json.get("click_covariances_px2").is_some() {
        panic!("covariances written at a room's top level");
    }
    Some(room)
}
