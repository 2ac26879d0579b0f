//! Integration tests of vpmap-eval (one test binary, see STYLE.md).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod snapshots;
mod yud;
