//! `/api/snap` request bodies (`vpmap_web::fuzzing::snap_body`): the JSON fields, the
//! vanishing points, the click noise and radius, then the snap itself on a kept photo `p1`
//! of 320 x 240 pixels.
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_web::fuzzing::snap_body;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = snap_body(data) {
        assert!(!e.message.is_empty(), "an error without a message");
    }
});
