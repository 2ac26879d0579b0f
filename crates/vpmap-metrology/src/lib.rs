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
//! # Module order
//! Modules import one way: each uses only the modules listed before it, bottom-up. Inside a
//! directory module the files do the same, in the order given; its `mod.rs` declares and
//! re-exports them (`fit/mod.rs` also drives the fit), and no file imports from its `mod.rs`.
//!
//! 1. [`error`] (the error type, which every later module may use), [`linalg`]
//!    (decompositions that cannot panic) and [`interrupt`] (stopping long work early): they
//!    import nothing from the crate but `interrupt`'s reasons, which `error` names.
//! 2. [`scene`]: the scene file (uses `linalg`). `types`, then `validate` and `vanishing`.
//! 3. [`calibration`]: the camera from the vanishing points (uses `scene`).
//! 4. `camera` (private; re-exported from [`map`]): the map frame's point, the rotation from
//!    camera to map, a scene's calibrated camera, the room's yaw (uses `calibration`, `scene`).
//! 5. `uncertainty` (private; re-exported from [`map`]): the error-bar types the fit computes
//!    and the map carries (uses `camera`).
//! 6. [`reconstruct`]: methods, reconstructed objects, the floor-projection trait (uses
//!    `calibration`, `scene`).
//! 7. [`sideview`] and [`projective`]: the two reference methods (use `reconstruct`,
//!    `calibration`, `scene`).
//! 8. [`fit`]: the joint fit (uses `camera`, `uncertainty`, `reconstruct`, `calibration`,
//!    `scene`, `linalg`). `model`, `solve`, `fitted`, then `init` and `uncertainty`.
//! 9. [`room`]: the joint fit of a room's several photos (uses `fit`, `uncertainty`,
//!    `reconstruct`, `calibration`, `scene`). `model`, `align`, `fit`, then `uncertainty`.
//! 10. [`synth`]: synthetic scenes from an independent pinhole camera (uses `scene` only).
//!     `camera`, `truth`, `noise`, `annotate`, `vp_edges`, then `random_scene`.
//! 11. [`map`]: the floor map (uses `room`, `fit`, `sideview`, `projective`, `reconstruct`,
//!     `uncertainty`, `camera`, `calibration`, `scene`; its tests also `synth`). `types`, then
//!     `reconstruction`, `regions` and `warnings`, then `build`.
//! 12. [`eval`]: map accuracy against a synthetic truth (uses `map`, `synth`, `reconstruct`,
//!     `calibration`, `scene`). `metrics`, `coverage`, `evaluate`, `setups`, then `trial`.
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
pub mod interrupt;
pub mod linalg;
pub mod map;
pub mod projective;
pub mod reconstruct;
pub mod room;
pub mod scene;
pub mod sideview;
pub mod synth;
mod uncertainty;

pub use error::{MetrologyError, Result};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
