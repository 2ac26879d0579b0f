//! Single-view metrology from vanishing points: one annotated photo to a metric floor map.
//!
//! This crate implements the map-building half of the thesis shipped in
//! `../shared/thesis/thesis.md` ("side view geometry", chapters 2-4, Appendix B), read with the
//! sign rules of `../shared/thesis/errata.md`, and an independent projective form.
//!
//! | step | module | method |
//! |---|---|---|
//! | scene file (JSON, version 1) | [`scene`] | parse, validate, least-squares vanishing points from clicked segments |
//! | calibration | [`calibration`] | 2PP: vanishing circle (App. B); 3PP: orthocentre, `d = sqrt(OG OC)`, pitch (eqs. 4.1-4.4); roll from the horizon |
//! | side-view reconstruction | [`sideview`] | offset distances, station point, top views, floor corners, heights (eqs. 3.1-3.10, 4.5-4.31) |
//! | projective reconstruction | [`projective`] | camera matrix `K`, floor normal `K^T l_horizon`, ray-plane intersection |
//! | floor map | [`map`] | scale from one known length, free space = floor minus footprints (`geo` boolean ops) |
//! | synthetic scenes | [`synth`] | an independent pinhole camera: the test oracle |
//! | map accuracy | [`eval`] | the thesis's scale factor `S_k` (eq. 6.1), six error metrics (6.1.1), experiment set-ups |
//!
//! # Example
//! ```
//! use vpmap_metrology::{map::{build_map, BuildOptions}, synth::{synthesize, SynthOptions}};
//! let (scene, truth) = synthesize(&SynthOptions::default()).unwrap();
//! let map = build_map(&scene, &BuildOptions::default()).unwrap();
//! let err = (map.objects[0].height.unwrap() - truth.objects[0].height).abs();
//! assert!(err < 1e-9);
//! ```
//!
//! # References
//! - The thesis, chapters 2-4 and Appendix B; `../shared/thesis/errata.md`.
//! - R. Hartley, A. Zisserman, *Multiple View Geometry*, 2nd ed., section 8.6 (vanishing points
//!   and the image of the absolute conic) for the projective form.
#![deny(missing_docs)]

pub mod calibration;
mod camera;
pub mod error;
pub mod eval;
pub mod fit;
pub mod linalg;
pub mod map;
pub mod projective;
pub mod reconstruct;
pub mod scene;
pub mod sideview;
pub mod synth;
mod uncertainty;

pub use error::{MetrologyError, Result};
