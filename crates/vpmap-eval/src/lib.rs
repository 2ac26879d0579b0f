//! vpmap's measurements, as a library: what `vpmap eval`, `vpmap bench` and
//! `vpmap eval-detect` run, callable from a test, a notebook or the web page.
//!
//! - [`accuracy`]: map accuracy under annotation noise on synthetic pinhole scenes, the
//!   thesis's section 6.1 (figures 6.8-6.13 and 6.18-6.23): per object and noise level, the six
//!   metrics of section 6.1.1, summarised per perspective and set-up, with box plots.
//! - [`bench`](mod@bench): planners compared on benchmark maps (Moving AI maps and scenarios, maps built
//!   from synthetic rooms), the thesis's section 6.2 (figures 6.25 and 6.26): runtime, path
//!   length, excess over the exact any-angle optimum, peak heap, every path checked by the
//!   independent validator and every "no path" against breadth-first connectivity.
//! - [`navigate`](mod@navigate): the unknown-terrain navigation benchmark: a robot starting
//!   with an empty belief on Moving AI maps, every online planner on the same episodes.
//! - [`detection`]: vanishing-point detection on labelled photos in the York Urban format:
//!   angular error per vanishing point (the one York Urban scorer, [`detection::match_errors`]),
//!   fractions within 1-10 degrees, area under the error curve, focal error and time.
//! - [`clicks`]: snapping clicks on rendered photos (`vpmap eval-clicks`, plain or
//!   `--cluttered`): the snapped corners' error and share per kind of click, box size errors
//!   and error-bar coverage with snapped against raw clicks, and the box proposals' recall and
//!   precision; on real photos ([`clicks::yud`], `--yud DIR`): York Urban's labelled corners,
//!   with the labels' own error measured and allowed for.
//! - [`smooth`]: the smooth planner against its Hybrid-A* reference (`vpmap bench --smooth`),
//!   side by side on Nav2-kind maps, maps built from scenes and Moving AI rooms and cities.
//! - [`room`]: rooms of several photos: the joint map against the map of the first photo
//!   alone and each shared object against the photos that show it alone (issue 29's targets).
//! - [`stats`]: every quantile, median, mean and box-plot figure the reports print (type 7
//!   quantiles, Hyndman and Fan 1996).
//! - [`publish`]: a report's section of a Markdown file such as `docs/results.md`, and the
//!   description of the machine that measured it.
//!
//! # Modules
//! Bottom-up, each using only those before it (inside a folder, the files before its
//! `mod.rs`): `error`, [`progress`], [`stats`], [`output`], [`publish`];
//! [`accuracy`] (`config`, `collect`, `files`, `report`, `plot`); [`bench`](mod@bench) (`maps`,
//! `measure`, `results`, `summary`, `plots`, `report`); [`navigate`](mod@navigate) (`eval`); [`smooth`];
//! [`detection`] (`geom`, `horizon`, `results`, `report`); [`clicks`] (`trial`, `report`, `yud`).
//!
//! Each measurement is a function with an options struct; it returns its results and the files
//! of its report and writes them all or nothing ([`output::OutputSet`]). Nothing here prints:
//! progress goes through [`progress::Progress`], which the command line draws as a bar.

#![deny(missing_docs)]

pub mod accuracy;
pub mod bench;
pub mod clicks;
pub mod detection;
mod error;
pub mod navigate;
pub mod output;
pub mod progress;
pub mod publish;
pub mod room;
pub mod smooth;
pub mod stats;

pub use error::{EvalError, Result};
pub use progress::{Progress, Silent};

/// The README's example, compiled and run as a doc test.
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;
