//! A room file (`{"version": 1, "photos": [SCENE, ...]}`) as `vpmap build` and `vpmap snap`
//! read it, without the fit: the checks of `room_check.rs` (reading, validation, round trip,
//! `vpmap snap`'s writing), thousands of executions a second where the `room` target, which
//! also fits small rooms, makes a few hundred.
#![no_main]

#[path = "room_check.rs"]
mod room_check;

use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let _ = room_check::check_room_file(data);
});
