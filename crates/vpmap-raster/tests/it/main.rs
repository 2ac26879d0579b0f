//! Integration tests of vpmap-raster: the rasterisation of floor maps against geo's
//! predicates, cell by cell, on synthetic maps and random polygons.
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::float_cmp)]

mod raster;
