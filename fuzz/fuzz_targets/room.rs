//! A room file (`{"version": 1, "photos": [SCENE, ...]}`): the checks of `room_check.rs`
//! (reading, validation, round trip, `vpmap snap`'s writing), then the joint fit's floor map
//! for small rooms. The fit makes an execution slow (about 200 a second): the `room_file`
//! target runs the same checks without it, for many more executions.
#![no_main]

#[path = "room_check.rs"]
mod room_check;

use libfuzzer_sys::fuzz_target;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_vision::clicks::scene_clicks;

/// Most photos and clicks of a room whose map is built: the joint fit's time grows with both
/// (bounded by the room's own limits, issue 40), and each execution is kept short.
const MAX_BUILT_PHOTOS: usize = 3;
const MAX_BUILT_CLICKS: usize = 60;

fuzz_target!(|data: &[u8]| {
    let Some(room) = room_check::check_room_file(data) else {
        return;
    };
    let clicks: usize = room.photos().map(|p| scene_clicks(p).len()).sum();
    if room.photo_count() > MAX_BUILT_PHOTOS || clicks > MAX_BUILT_CLICKS {
        return;
    }
    if let Ok(map) = build_map(&room, &BuildOptions::default()) {
        if let Some(fit) = &map.fit
            && !(fit.rms_residual_px.is_finite() && fit.rms_residual_px >= 0.0)
        {
            panic!("a room's RMS residual is {} px", fit.rms_residual_px);
        }
        if let Err(e) = vpmap_metrology::map::FloorMap::from_json_str(&map.to_json_string()) {
            panic!("a built room's map.json does not read back: {e}");
        }
    }
});
