//! Integration tests of vpmap-vision (one test binary, see STYLE.md).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod bad_input;
mod real_photos;
mod rendered_rooms;
mod snap_lens;
mod snapping;
mod synthetic_scenes;
