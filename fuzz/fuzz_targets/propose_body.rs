//! `/api/propose` request bodies (`vpmap_web::fuzzing::propose_body`): the JSON fields and
//! vanishing points, then the box proposals on a kept photo `p1` of 320 x 240 pixels (its
//! segments found once, the search bounded by `ProposalOptions`' caps).
#![no_main]

use libfuzzer_sys::fuzz_target;
use vpmap_web::fuzzing::propose_body;

fuzz_target!(|data: &[u8]| {
    if let Err(e) = propose_body(data) {
        assert!(!e.message.is_empty(), "an error without a message");
    }
});
