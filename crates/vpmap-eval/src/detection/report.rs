//! The figures of `vpmap eval-detect`, as a table, Markdown and JSON.
//!
//! * within x degrees: the fraction of labelled vanishing points whose detected direction is at
//!   most x degrees off (misses count as off);
//! * AUC@L: the area under that accuracy curve from 0 to L degrees, divided by L (as Lu et al.
//!   report), computed exactly: the mean over vanishing points of `max(0, 1 - error / L)`;
//! * focal error: `|f - f_true| / f_true` when estimated (a refused photo counts as infinite);
//! * horizon error: of the scene file written, in image heights ([`super::horizon`]), its median
//!   and the area under its cumulative curve from 0 to [`HORIZON_AUC_LIMIT`] image heights,
//!   divided by that limit (Lezama et al. 2014); a photo with no scene counts as infinite;
//! * time: wall time of `detect` per call (both runs of every photo that could be read);
//! * the same angular figures ([`Accuracy`]) for each direction's own least-squares point, and,
//!   where the labels hold orthogonalised directions, for the frame and the own points against
//!   those, and for those against the labels (the same in both runs).

use std::fmt::Write as _;

use crate::error::{Result, ResultExt as _};
use crate::stats::{auc, fraction_at_most, quantile_of};
use serde_json::json;

use super::horizon::HORIZON_AUC_LIMIT;
use super::results::{ImageResult, Intrinsics};

/// Thresholds of the "within" rows, degrees.
pub const WITHIN_DEG: [f64; 4] = [1.0, 3.0, 5.0, 10.0];
/// Limits of the AUC rows, degrees.
pub const AUC_DEG: [f64; 3] = [3.0, 5.0, 10.0];
/// A focal length within this relative error counts as right.
pub const FOCAL_TOLERANCE: f64 = 0.05;

/// The reference: Lu et al.'s public implementation on York Urban.
pub const REFERENCE: &str = "Lu et al. (2-line exhaustive search, WACV 2017), public implementation, on York Urban: 95 % of vanishing points within 3 deg and AUC@10 87 % with the true intrinsics, about 43 ms per 640 x 480 photo; AUC@10 47 % when it must guess the intrinsics";

/// What the run was over.
pub struct Context {
    /// The folder, as given.
    pub dir: String,
    /// Labelled photos in it (before `--limit`).
    pub available: usize,
    /// The detector's `--max-side`.
    pub max_side: u32,
    /// Whether the estimated run took each photo's EXIF focal length as a prior (`--exif`).
    pub exif: bool,
}

/// The angular figures of one set of directions against one set of labels.
#[derive(Clone, Debug, PartialEq)]
pub struct Accuracy {
    /// Labelled vanishing points (3 per photo).
    pub vanishing_points: usize,
    /// Of them, not detected (refused photo or missing point).
    pub missed: usize,
    /// `(threshold, fraction within)`, [`WITHIN_DEG`].
    pub within: Vec<(f64, f64)>,
    /// `(limit, area)`, [`AUC_DEG`].
    pub auc: Vec<(f64, f64)>,
    /// Median error of the vertical vanishing points, degrees (infinite when most missed).
    pub median_vertical_deg: f64,
    /// Median error of the horizontal vanishing points, degrees.
    pub median_horizontal_deg: f64,
}

/// The figures of `photos`' errors: each photo's three errors in label order (`None`: a
/// miss) and which is vertical.
#[must_use]
pub fn accuracy(photos: &[([Option<f64>; 3], usize)]) -> Accuracy {
    let mut errors = Vec::new();
    let mut vertical = Vec::new();
    let mut horizontal = Vec::new();
    for (photo_errors, v) in photos {
        for (i, e) in photo_errors.iter().enumerate() {
            let e = e.unwrap_or(f64::INFINITY);
            errors.push(e);
            if i == *v {
                vertical.push(e);
            } else {
                horizontal.push(e);
            }
        }
    }
    Accuracy {
        vanishing_points: errors.len(),
        missed: errors.iter().filter(|e| e.is_infinite()).count(),
        within: WITHIN_DEG
            .iter()
            .map(|&t| (t, fraction_at_most(&errors, t)))
            .collect(),
        auc: AUC_DEG.iter().map(|&l| (l, auc(&errors, l))).collect(),
        median_vertical_deg: quantile_of(&vertical, 0.5).unwrap_or(f64::INFINITY),
        median_horizontal_deg: quantile_of(&horizontal, 0.5).unwrap_or(f64::INFINITY),
    }
}

/// The summary of one kind of run over every photo.
#[derive(Clone, Debug, PartialEq)]
pub struct Summary {
    /// Which run.
    pub which: Intrinsics,
    /// Photos.
    pub images: usize,
    /// Photos the detector refused (or that could not be read).
    pub failed: usize,
    /// The detected frame's directions against the labels (a refused photo or a missing
    /// point is a miss).
    pub frame: Accuracy,
    /// Focal error median, p90 and fraction within [`FOCAL_TOLERANCE`] (estimated runs only).
    pub focal: Option<(f64, f64, f64)>,
    /// Median horizon error, image heights (infinite when most photos give no scene).
    pub median_horizon: f64,
    /// Area under the horizon error curve up to [`HORIZON_AUC_LIMIT`], normalised to 1.
    pub horizon_auc: f64,
    /// The same area against the horizon through the labelled horizontal vanishing points.
    pub horizon_auc_of_horizontals: f64,
    /// Time per call, median and p90, milliseconds.
    pub time_ms: Option<(f64, f64)>,
    /// Of the labelled directions the written scenes give a point for, the share inside that
    /// point's 95 % ellipse, and how many there were.
    pub ellipse_coverage: (f64, usize),
    /// Of the photos whose scene gives a camera, the share whose labelled focal length lies
    /// inside its 95 % interval, and how many there were (estimated runs only).
    pub focal_coverage: Option<(f64, usize)>,
    /// Of the photos whose scene gives a camera, the share whose labelled camera lies within
    /// the estimate's 95 % intervals ([`CameraCoverage`]).
    pub camera_coverage: Option<CameraCoverage>,
    /// The lens estimates' consistency over the photos (one camera, one `k`;
    /// [`super::coverage::lens_consistency`]), and their median `k`.
    pub lens: Option<(super::coverage::LensConsistency, f64)>,
    /// Each direction's own least-squares point against the labels (a missing own point is a
    /// miss).
    pub own: Accuracy,
    /// Over the photos whose labels hold orthogonalised directions (`None`: none do): the
    /// frame against them, the own points against them, and they against the labels.
    pub orthogonal: Option<[Accuracy; 3]>,
}

/// Where the labelled cameras lie in the written scenes' camera estimates: the share within
/// `±1.96 sd` ([`super::coverage::CameraZ`]), against each labelled horizon (the vertical's,
/// the horizontals').
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraCoverage {
    /// Photos counted.
    pub photos: usize,
    /// Pitch, against each labelled horizon.
    pub pitch: [f64; 2],
    /// Roll.
    pub roll: [f64; 2],
    /// The horizon's offset at the principal point (the overlay's band).
    pub horizon: [f64; 2],
    /// The principal point `[x, y]` and the photos where the fit placed it.
    pub principal_point: Option<([f64; 2], usize)>,
}

/// The shares of [`CameraCoverage`] over `zs` (`None` for none).
fn camera_coverage(zs: &[super::coverage::CameraZ]) -> Option<CameraCoverage> {
    if zs.is_empty() {
        return None;
    }
    let inside = |f: &dyn Fn(&super::coverage::CameraZ) -> f64| {
        let v: Vec<f64> = zs.iter().map(|z| f(z).abs()).collect();
        fraction_at_most(&v, super::coverage::Z_95)
    };
    let pp: Vec<[f64; 2]> = zs.iter().filter_map(|z| z.principal_point).collect();
    let pp_inside = |i: usize| {
        let v: Vec<f64> = pp.iter().map(|z| z[i].abs()).collect();
        fraction_at_most(&v, super::coverage::Z_95)
    };
    Some(CameraCoverage {
        photos: zs.len(),
        pitch: [0, 1].map(|k| inside(&|z| z.pitch[k])),
        roll: [0, 1].map(|k| inside(&|z| z.roll[k])),
        horizon: [0, 1].map(|k| inside(&|z| z.horizon[k])),
        principal_point: (!pp.is_empty()).then(|| ([pp_inside(0), pp_inside(1)], pp.len())),
    })
}

/// Summarise one kind of run.
#[must_use]
pub fn summarise(results: &[ImageResult], which: Intrinsics) -> Summary {
    let slot = usize::from(which == Intrinsics::Estimated);
    let mut frame = Vec::new();
    let mut own = Vec::new();
    let mut orthogonal: [Vec<([Option<f64>; 3], usize)>; 3] = Default::default();
    let mut focal = Vec::new();
    let mut horizon = Vec::new();
    let mut horizon_of_horizontals = Vec::new();
    let mut times = Vec::new();
    let mut failed = 0;
    let mut d2s = Vec::new();
    let mut zs = Vec::new();
    let mut lenses = Vec::new();
    let mut cameras = Vec::new();
    for r in results {
        if let Ok(ok) = &r.runs[slot].outcome {
            d2s.extend(ok.ellipse_d2.iter().flatten().copied());
            zs.extend(ok.focal_z);
            cameras.extend(ok.camera_z);
            lenses.extend(ok.lens);
        }
        let run = &r.runs[slot];
        if let Some(t) = run.time_ms {
            times.push(t);
        }
        if run.outcome.is_err() {
            failed += 1;
        }
        let ok = run.outcome.as_ref().ok();
        let (focal_error, horizon_error) =
            ok.map_or((None, None), |ok| (ok.focal_error, ok.horizon_error));
        let [h, hh] = horizon_error.unwrap_or([f64::INFINITY; 2]);
        horizon.push(h);
        horizon_of_horizontals.push(hh);
        frame.push((ok.map_or([None; 3], |ok| ok.errors_deg), r.vertical));
        own.push((ok.map_or([None; 3], |ok| ok.own_errors_deg), r.vertical));
        if let Some(labels) = r.orthogonal_label_errors_deg {
            let [f, o] = ok
                .and_then(|ok| ok.against_orthogonal_deg)
                .unwrap_or([[None; 3]; 2]);
            orthogonal[0].push((f, r.vertical));
            orthogonal[1].push((o, r.vertical));
            orthogonal[2].push((labels.map(Some), r.vertical));
        }
        focal.push(focal_error.unwrap_or(f64::INFINITY));
    }
    let focal = (which == Intrinsics::Estimated && !focal.is_empty()).then(|| {
        (
            quantile_of(&focal, 0.5).unwrap_or(f64::INFINITY),
            quantile_of(&focal, 0.9).unwrap_or(f64::INFINITY),
            fraction_at_most(&focal, FOCAL_TOLERANCE),
        )
    });
    Summary {
        which,
        images: results.len(),
        failed,
        frame: accuracy(&frame),
        focal,
        median_horizon: quantile_of(&horizon, 0.5).unwrap_or(f64::INFINITY),
        horizon_auc: crate::stats::auc(&horizon, HORIZON_AUC_LIMIT),
        horizon_auc_of_horizontals: crate::stats::auc(&horizon_of_horizontals, HORIZON_AUC_LIMIT),
        time_ms: quantile_of(&times, 0.5).zip(quantile_of(&times, 0.9)),
        ellipse_coverage: (
            fraction_at_most(&d2s, super::coverage::CHI2_2DOF_95),
            d2s.len(),
        ),
        focal_coverage: (which == Intrinsics::Estimated && !zs.is_empty())
            .then(|| (fraction_at_most(&zs, super::coverage::Z_95), zs.len())),
        camera_coverage: camera_coverage(&cameras),
        lens: super::coverage::lens_consistency(&lenses).map(|c| {
            let ks: Vec<f64> = lenses.iter().map(|l| l[0]).collect();
            (c, quantile_of(&ks, 0.5).unwrap_or(f64::NAN))
        }),
        own: accuracy(&own),
        orthogonal: (!orthogonal[0].is_empty()).then(|| orthogonal.map(|o| accuracy(&o))),
    }
}

/// The rows of the camera estimates' coverage ([`CameraCoverage`]).
fn camera_rows(rows: &mut Vec<(String, [String; 2], String)>, summaries: &[Summary; 2]) {
    let cells = |f: &dyn Fn(&CameraCoverage) -> String| {
        summaries
            .each_ref()
            .map(|s| s.camera_coverage.as_ref().map_or_else(|| "-".to_owned(), f))
    };
    for (name, pick) in [
        (
            "pitch",
            (|c: &CameraCoverage| c.pitch) as fn(&CameraCoverage) -> [f64; 2],
        ),
        ("roll", |c| c.roll),
        ("horizon (the overlay's band)", |c| c.horizon),
    ] {
        rows.push((
            format!("labelled {name} inside the 95 % interval (vertical's horizon / horizontals')"),
            cells(&|c| {
                let [a, b] = pick(c);
                format!("{} / {} of {}", pct(a), pct(b), c.photos)
            }),
            "target 90-98 %".to_owned(),
        ));
    }
    rows.push((
        "labelled principal point inside the 95 % interval (x / y)".to_owned(),
        cells(&|c| {
            c.principal_point.map_or_else(
                || "(given)".to_owned(),
                |([x, y], n)| format!("{} / {} of {n}", pct(x), pct(y)),
            )
        }),
        "target 90-98 %".to_owned(),
    ));
}

/// A short name of a run for messages.
#[must_use]
pub fn label_of(which: Intrinsics) -> &'static str {
    match which {
        Intrinsics::Given => "true intrinsics given",
        Intrinsics::Estimated => "intrinsics estimated",
    }
}

fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{:.1} %", 100.0 * v)
    } else {
        "-".to_owned()
    }
}

fn deg(v: f64) -> String {
    if v.is_finite() {
        format!("{v:.2}")
    } else {
        "miss".to_owned()
    }
}

/// The rows of the comparison: label, one cell per run, the reference.
fn rows(summaries: &[Summary; 2]) -> Vec<(String, [String; 2], String)> {
    let cells = |f: &dyn Fn(&Summary) -> String| [f(&summaries[0]), f(&summaries[1])];
    let mut rows = vec![(
        "photos refused".to_owned(),
        cells(&|s| format!("{} of {}", s.failed, s.images)),
        String::new(),
    )];
    accuracy_rows(
        &mut rows,
        summaries,
        &|s| &s.frame,
        "vanishing points missed",
        "",
        true,
    );
    own_rows(&mut rows, summaries);
    rows.push((
        "horizon error, median (image heights)".to_owned(),
        cells(&|s| {
            if s.median_horizon.is_finite() {
                format!("{:.4}", s.median_horizon)
            } else {
                "miss".to_owned()
            }
        }),
        String::new(),
    ));
    rows.push((
        format!("horizon AUC@{HORIZON_AUC_LIMIT}"),
        cells(&|s| pct(s.horizon_auc)),
        String::new(),
    ));
    rows.push((
        "labelled direction inside the 95 % ellipse".to_owned(),
        cells(&|s| format!("{} of {}", pct(s.ellipse_coverage.0), s.ellipse_coverage.1)),
        "target 90-98 %".to_owned(),
    ));
    rows.push((
        "true focal inside the 95 % interval".to_owned(),
        cells(&|s| {
            s.focal_coverage.map_or_else(
                || "(given)".to_owned(),
                |(c, n)| format!("{} of {n}", pct(c)),
            )
        }),
        "target 90-98 %".to_owned(),
    ));
    camera_rows(&mut rows, summaries);
    rows.push((
        "lens k (division model), median".to_owned(),
        cells(&|s| {
            s.lens
                .map_or_else(|| "-".to_owned(), |(_, k)| format!("{k:.4}"))
        }),
        String::new(),
    ));
    rows.push((
        "k inside its 95 % interval of the others' mean".to_owned(),
        cells(&|s| {
            s.lens.map_or_else(
                || "-".to_owned(),
                |(c, _)| format!("{} of {} (rms z {:.2})", pct(c.inside), c.photos, c.rms_z),
            )
        }),
        "one camera: target 90-98 %".to_owned(),
    ));
    rows.push((
        format!("horizon AUC@{HORIZON_AUC_LIMIT}, labelled horizontal VPs"),
        cells(&|s| pct(s.horizon_auc_of_horizontals)),
        String::new(),
    ));
    rows.push((
        "focal error, median".to_owned(),
        cells(&|s| s.focal.map_or_else(|| "(given)".to_owned(), |f| pct(f.0))),
        String::new(),
    ));
    rows.push((
        "focal error, p90".to_owned(),
        cells(&|s| s.focal.map_or_else(|| "(given)".to_owned(), |f| pct(f.1))),
        String::new(),
    ));
    rows.push((
        format!("focal within {:.0} %", 100.0 * FOCAL_TOLERANCE),
        cells(&|s| s.focal.map_or_else(|| "(given)".to_owned(), |f| pct(f.2))),
        String::new(),
    ));
    rows.push((
        "time per photo, median (ms)".to_owned(),
        cells(&|s| {
            s.time_ms
                .map_or_else(|| "-".to_owned(), |t| format!("{:.1}", t.0))
        }),
        "about 43".to_owned(),
    ));
    rows.push((
        "time per photo, p90 (ms)".to_owned(),
        cells(&|s| {
            s.time_ms
                .map_or_else(|| "-".to_owned(), |t| format!("{:.1}", t.1))
        }),
        String::new(),
    ));
    rows
}

/// The rows of one set of directions' [`Accuracy`] (`pick` from each run's summary), their
/// labels after `prefix`; with `references`, the reference's figures beside the frame's.
fn accuracy_rows(
    rows: &mut Vec<(String, [String; 2], String)>,
    summaries: &[Summary; 2],
    pick: &dyn Fn(&Summary) -> &Accuracy,
    missed_label: &str,
    prefix: &str,
    references: bool,
) {
    let cells = |f: &dyn Fn(&Accuracy) -> String| [f(pick(&summaries[0])), f(pick(&summaries[1]))];
    let reference = |shown: bool, text: &str| {
        if references && shown {
            text.to_owned()
        } else {
            String::new()
        }
    };
    rows.push((
        missed_label.to_owned(),
        cells(&|a| format!("{} of {}", a.missed, a.vanishing_points)),
        String::new(),
    ));
    for (i, t) in WITHIN_DEG.iter().enumerate() {
        rows.push((
            format!("{prefix}within {t} deg"),
            cells(&|a| pct(a.within[i].1)),
            reference((*t - 3.0).abs() < 1e-9, "95 % / -"),
        ));
    }
    for (i, l) in AUC_DEG.iter().enumerate() {
        rows.push((
            format!("{prefix}AUC@{l} deg"),
            cells(&|a| pct(a.auc[i].1)),
            reference((*l - 10.0).abs() < 1e-9, "87 % / 47 %"),
        ));
    }
    rows.push((
        format!("{prefix}median error, vertical (deg)"),
        cells(&|a| deg(a.median_vertical_deg)),
        String::new(),
    ));
    rows.push((
        format!("{prefix}median error, horizontal (deg)"),
        cells(&|a| deg(a.median_horizontal_deg)),
        String::new(),
    ));
}

/// The rows of the own points ([`Summary::own`]) and of the orthogonalised labels
/// ([`Summary::orthogonal`]).
fn own_rows(rows: &mut Vec<(String, [String; 2], String)>, summaries: &[Summary; 2]) {
    accuracy_rows(
        rows,
        summaries,
        &|s| &s.own,
        "own points: missed",
        "own points: ",
        false,
    );
    let triple = |a: &Accuracy| {
        let [x, y, z] = [0, 1, 2].map(|i| a.auc.get(i).map_or(f64::NAN, |v| v.1));
        format!("{:.1} / {:.1} / {:.1} %", 100.0 * x, 100.0 * y, 100.0 * z)
    };
    let quadruple = |a: &Accuracy| {
        let w: Vec<String> = a
            .within
            .iter()
            .map(|v| format!("{:.1}", 100.0 * v.1))
            .collect();
        format!("{} %", w.join(" / "))
    };
    let limits = |v: &[f64]| {
        v.iter()
            .map(ToString::to_string)
            .collect::<Vec<_>>()
            .join("/")
    };
    let against = [
        "frame vs orthogonal labels",
        "own vs orthogonal labels",
        "orthogonal labels vs labels",
    ];
    for (k, what) in against.iter().enumerate() {
        let cell = |f: &dyn Fn(&Accuracy) -> String| {
            summaries.each_ref().map(|s| {
                s.orthogonal
                    .as_ref()
                    .map_or_else(|| "-".to_owned(), |o| f(&o[k]))
            })
        };
        rows.push((
            format!("{what}: within {} deg", limits(&WITHIN_DEG)),
            cell(&quadruple),
            String::new(),
        ));
        rows.push((
            format!("{what}: AUC@{} deg", limits(&AUC_DEG)),
            cell(&triple),
            String::new(),
        ));
    }
}

const HEADERS: [&str; 4] = [
    "",
    "true K given",
    "K estimated",
    "Lu et al. (given / estimated)",
];

/// The table printed on stdout.
#[must_use]
pub fn table(ctx: &Context, summaries: &[Summary; 2]) -> String {
    let rows = rows(summaries);
    let w0 = rows
        .iter()
        .map(|r| r.0.len())
        .max()
        .unwrap_or(0)
        .max(HEADERS[0].len());
    let w1 = rows
        .iter()
        .map(|r| r.1[0].len())
        .max()
        .unwrap_or(0)
        .max(HEADERS[1].len());
    let w2 = rows
        .iter()
        .map(|r| r.1[1].len())
        .max()
        .unwrap_or(0)
        .max(HEADERS[2].len());
    let mut out = format!(
        "vanishing points on {} labelled photos in {}{} (3 each), detector at --max-side {}{}, one photo at a time\n",
        summaries[0].images,
        ctx.dir,
        if summaries[0].images < ctx.available {
            format!(" (first {} of {})", summaries[0].images, ctx.available)
        } else {
            String::new()
        },
        ctx.max_side,
        if ctx.exif {
            ", the EXIF focal length as a prior when estimated"
        } else {
            ""
        }
    );
    let _ = writeln!(
        out,
        "{:<w0$}  {:>w1$}  {:>w2$}  {}",
        HEADERS[0], HEADERS[1], HEADERS[2], HEADERS[3]
    );
    for (label, cells, reference) in &rows {
        let _ = writeln!(
            out,
            "{label:<w0$}  {:>w1$}  {:>w2$}  {reference}",
            cells[0], cells[1]
        );
    }
    let _ = write!(out, "reference: {REFERENCE}");
    out
}

/// `summary.md`.
#[must_use]
pub fn markdown(ctx: &Context, results: &[ImageResult], summaries: &[Summary; 2]) -> String {
    let mut out = String::from("# Vanishing-point detection (`vpmap eval-detect`)\n\n");
    let _ = writeln!(
        out,
        "{} labelled photos from `{}`{}, 3 vanishing points each; detector at `--max-side {}`, one photo at a time on one core, each detected twice: with the true intrinsics given and with them estimated{}.\n",
        summaries[0].images,
        ctx.dir,
        if summaries[0].images < ctx.available {
            format!(" (the first {} of {})", summaries[0].images, ctx.available)
        } else {
            String::new()
        },
        ctx.max_side,
        if ctx.exif {
            " (with each photo's EXIF focal length as a prior, `--exif`)"
        } else {
            ""
        }
    );
    let _ = writeln!(
        out,
        "| | {} | {} | {} |\n|---|---:|---:|---|",
        HEADERS[1], HEADERS[2], HEADERS[3]
    );
    for (label, cells, reference) in rows(summaries) {
        let _ = writeln!(
            out,
            "| {label} | {} | {} | {reference} |",
            cells[0], cells[1]
        );
    }
    let _ = writeln!(
        out,
        "\nError: the angle between the detected and the labelled vanishing direction (`vp_dirs_camera_yup`), sign-free; vertical matched to vertical, horizontals by the better assignment; with estimated intrinsics the detected points are turned into directions with the estimated K. A refused photo or a missing vanishing point counts as a miss in every figure. AUC@L is the area under the curve \"fraction of vanishing points with error <= x\" for x from 0 to L, divided by L. Horizon error (Barinova et al. 2010, Lezama et al. 2014): the largest vertical distance, over the image's width, between the horizon of the scene file `vpmap detect` writes (the line through its two horizontal vanishing points) and the true one (`K^-T v`, v the labelled vertical), divided by the image height; horizon AUC@{HORIZON_AUC_LIMIT}: the area under the curve \"fraction of photos with horizon error <= x\" for x from 0 to {HORIZON_AUC_LIMIT}, divided by {HORIZON_AUC_LIMIT}; a refused photo is a miss. The row \"horizon AUC@{HORIZON_AUC_LIMIT}, labelled horizontal VPs\" measures the same against the line through the two labelled horizontal vanishing points instead, which differs because the labelled directions are not exactly orthogonal. Own points: each direction's own least-squares point of its supporting segments, not held orthogonal to the others (`VanishingPoint::own_point`; `vpmap detect` writes the frame's points, not these), scored the same way with the same intrinsics. Orthogonal labels: the dataset's `vp_orthogonal_dirs_camera_yup`, the labels made exactly orthogonal; the frame and the own points (\"own\") against them (same matching), and they against the labels (the dataset's own orthogonal fit to its labels: about the best an exactly orthogonal frame does against them; the same in both runs). Time: wall time of `detect` only.\n\nReference: {REFERENCE}.\n"
    );
    let refused: Vec<String> = results
        .iter()
        .flat_map(|r| {
            Intrinsics::BOTH
                .iter()
                .zip(&r.runs)
                .filter_map(move |(w, run)| {
                    run.outcome
                        .as_ref()
                        .err()
                        .map(|e| format!("- `{}` ({}): {e}", r.name, label_of(*w)))
                })
        })
        .collect();
    if !refused.is_empty() {
        let _ = writeln!(out, "## Refused\n\n{}\n", refused.join("\n"));
    }
    out
}

fn finite(v: f64) -> serde_json::Value {
    if v.is_finite() {
        json!(v)
    } else {
        serde_json::Value::Null
    }
}

fn accuracy_json(a: &Accuracy) -> serde_json::Value {
    json!({
        "vanishing_points": a.vanishing_points,
        "missed": a.missed,
        "within_deg": a.within.iter().map(|(t, f)| json!({"deg": t, "fraction": f})).collect::<Vec<_>>(),
        "auc": a.auc.iter().map(|(l, v)| json!({"deg": l, "area": v})).collect::<Vec<_>>(),
        "median_error_vertical_deg": finite(a.median_vertical_deg),
        "median_error_horizontal_deg": finite(a.median_horizontal_deg),
    })
}

fn summary_json(s: &Summary) -> serde_json::Value {
    let mut out = accuracy_json(&s.frame);
    let rest = json!({
        "images": s.images,
        "refused": s.failed,
        "focal_error": s.focal.map(|(m, p, w)| json!({
            "median": finite(m), "p90": finite(p), "within_fraction": w, "tolerance": FOCAL_TOLERANCE,
        })),
        "horizon_error": json!({
            "median": finite(s.median_horizon),
            "auc": s.horizon_auc,
            "auc_limit": HORIZON_AUC_LIMIT,
            "auc_against_labelled_horizontal_vps": s.horizon_auc_of_horizontals,
        }),
        "time_ms": s.time_ms.map(|(m, p)| json!({"median": m, "p90": p})),
        "camera_inside_95": s.camera_coverage.map(|c| json!({
            "photos": c.photos,
            "pitch_against_vertical_and_horizontals": c.pitch,
            "roll_against_vertical_and_horizontals": c.roll,
            "horizon_against_vertical_and_horizontals": c.horizon,
            "principal_point_xy": c.principal_point.map(|(p, _)| p),
            "principal_point_photos": c.principal_point.map(|(_, n)| n),
        })),
        "lens": s.lens.map(|(c, median)| json!({
            "median_k": median,
            "mean_k": c.mean_k,
            "photos": c.photos,
            "inside_95_of_the_others_mean": c.inside,
            "rms_z": c.rms_z,
        })),
        "own_points": accuracy_json(&s.own),
        "against_orthogonal_labels": s.orthogonal.as_ref().map(|[f, o, l]| json!({
            "frame": accuracy_json(f),
            "own_points": accuracy_json(o),
            "orthogonal_labels_against_labels": accuracy_json(l),
        })),
    });
    // The frame's figures at the top level, beside the run's own.
    if let (Some(out), serde_json::Value::Object(rest)) = (out.as_object_mut(), rest) {
        out.extend(rest);
    }
    out
}

/// `eval-detect.json`: the summary and one row per photo.
///
/// # Errors
/// When serialising fails.
pub fn json(ctx: &Context, results: &[ImageResult], summaries: &[Summary; 2]) -> Result<String> {
    let rows: Vec<serde_json::Value> = results
        .iter()
        .map(|r| {
            let mut row = json!({
                "name": r.name,
                "size_px": r.size_px,
                "vertical_index": r.vertical,
                "orthogonal_label_errors_deg": r.orthogonal_label_errors_deg,
            });
            for (which, run) in Intrinsics::BOTH.iter().zip(&r.runs) {
                row[which.key()] = match &run.outcome {
                    Ok(ok) => json!({
                        "time_ms": run.time_ms,
                        "errors_deg": ok.errors_deg.map(|e| e.and_then(|e| e.is_finite().then_some(e))),
                        "own_errors_deg": ok.own_errors_deg.map(|e| e.and_then(|e| e.is_finite().then_some(e))),
                        "errors_deg_against_orthogonal_labels": ok.against_orthogonal_deg.map(|[f, _]| f),
                        "own_errors_deg_against_orthogonal_labels": ok.against_orthogonal_deg.map(|[_, o]| o),
                        "focal_px": ok.focal_px,
                        "focal_error": ok.focal_error,
                        "principal_point_px": ok.principal_point_px,
                        "perspective": ok.perspective,
                        "segments": ok.segments,
                        "horizon_error": ok.horizon_error.map(|e| e[0]).filter(|e| e.is_finite()),
                        "horizon_error_against_labelled_horizontal_vps": ok.horizon_error.map(|e| e[1]).filter(|e| e.is_finite()),
                        "lens_k": ok.lens.map(|l| l[0]),
                        "lens_k_sd": ok.lens.map(|l| l[1]),
                        "lens_k_sd_segments": ok.lens_segments_sd,
                        "camera_z": ok.camera_z.map(|z| json!({
                            "pitch_against_vertical_and_horizontals": z.pitch,
                            "roll_against_vertical_and_horizontals": z.roll,
                            "horizon_against_vertical_and_horizontals": z.horizon,
                            "principal_point_xy": z.principal_point,
                        })),
                    }),
                    Err(e) => json!({"time_ms": run.time_ms, "refused": e}),
                };
            }
            row
        })
        .collect();
    let mut summary = serde_json::Map::new();
    for s in summaries {
        summary.insert(s.which.key().to_owned(), summary_json(s));
    }
    let doc = json!({
        "dataset": ctx.dir,
        "labelled_photos": ctx.available,
        "max_side_px": ctx.max_side,
        "exif_focal_prior": ctx.exif,
        "error": "angle between detected and labelled (vp_dirs_camera_yup) vanishing directions, degrees, sign-free; null: missed",
        "horizon_error": "largest vertical distance over the image width between the written scene's horizon and K^-T v (v the labelled vertical), image heights; null: missed",
        "reference": REFERENCE,
        "summary": summary,
        "photos": rows,
    });
    let mut text = serde_json::to_string_pretty(&doc).context("serialising eval-detect.json")?;
    text.push('\n');
    Ok(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::detection::{Run, RunOk};

    #[test]
    fn coverage_counts_what_the_ellipses_and_intervals_hold() {
        // Per photo one direction inside 5.991, one outside, one not written; focal z of
        // 10 x the focal error: 0.1 -> 1.0 (inside 1.96), 0.3 -> 3.0 (outside).
        let results = [
            result([Some(1.0), Some(1.0), Some(1.0)], 0.1),
            result([Some(1.0), Some(1.0), Some(1.0)], 0.3),
        ];
        let s = summarise(&results, Intrinsics::Estimated);
        assert_eq!(s.ellipse_coverage, (0.5, 4));
        assert_eq!(s.focal_coverage, Some((0.5, 2)));
        assert_eq!(summarise(&results, Intrinsics::Given).focal_coverage, None);
    }

    fn result(errors: [Option<f64>; 3], focal_error: f64) -> ImageResult {
        let ok = |which| Run {
            time_ms: Some(10.0),
            outcome: Ok(RunOk {
                errors_deg: errors,
                own_errors_deg: errors.map(|e| e.map(|e| 0.5 * e)),
                against_orthogonal_deg: Some([errors, [Some(0.1), None, Some(0.2)]]),
                ellipse_d2: [Some(1.0), Some(7.0), None],
                focal_z: (which == Intrinsics::Estimated).then_some(10.0 * focal_error),
                camera_z: None,
                focal_px: 500.0,
                focal_error: (which == Intrinsics::Estimated).then_some(focal_error),
                principal_point_px: [1.0, 2.0],
                perspective: "3pp",
                segments: 9,
                horizon_error: Some([0.05, 0.3]),
                lens: None,
                lens_segments_sd: None,
            }),
        };
        ImageResult {
            name: "x".to_owned(),
            size_px: Some([640, 480]),
            vertical: 1,
            orthogonal_label_errors_deg: Some([0.5, 1.0, 4.0]),
            runs: [ok(Intrinsics::Given), ok(Intrinsics::Estimated)],
        }
    }

    #[test]
    fn auc_and_fractions_count_misses() {
        let refused = ImageResult {
            runs: [
                Run {
                    time_ms: Some(5.0),
                    outcome: Err("no".to_owned()),
                },
                Run {
                    time_ms: Some(5.0),
                    outcome: Err("no".to_owned()),
                },
            ],
            ..result([None; 3], 0.0)
        };
        let results = [result([Some(0.5), Some(2.0), None], 0.01), refused];
        let s = summarise(&results, Intrinsics::Estimated);
        assert_eq!(
            (s.images, s.failed, s.frame.vanishing_points, s.frame.missed),
            (2, 1, 6, 4)
        );
        assert!((s.frame.within[0].1 - 1.0 / 6.0).abs() < 1e-12);
        assert!((s.frame.within[1].1 - 2.0 / 6.0).abs() < 1e-12);
        // AUC@10: (0.95 + 0.8) / 6.
        assert!(
            (s.frame.auc[2].1 - 1.75 / 6.0).abs() < 1e-12,
            "{:?}",
            s.frame.auc
        );
        let (median, _, within) = s.focal.unwrap_or_default();
        assert!(median.is_infinite() || (median - 0.01).abs() < 1e-12);
        assert!((within - 0.5).abs() < 1e-12);
        assert!(s.frame.median_vertical_deg.is_infinite());
        assert!(summarise(&results, Intrinsics::Given).focal.is_none());
        // Horizon: 0.05 and a miss; AUC@0.25 = (1 - 0.05 / 0.25) / 2 = 0.4.
        assert!((s.horizon_auc - 0.4).abs() < 1e-12, "{}", s.horizon_auc);
        assert!(s.horizon_auc_of_horizontals.abs() < 1e-12);
        // Own points: 0.25, 1.0 and a miss, then the refused photo's three misses.
        assert_eq!((s.own.vanishing_points, s.own.missed), (6, 4));
        assert!((s.own.within[0].1 - 2.0 / 6.0).abs() < 1e-12);
        // AUC@3 of the own points: (1 - 0.25 / 3 + 1 - 1 / 3) / 6.
        assert!((s.own.auc[0].1 - (2.0 - 1.25 / 3.0) / 6.0).abs() < 1e-12);
        // Against the orthogonalised labels: both photos have them; the refused one misses.
        let Some([frame, own, labels]) = &s.orthogonal else {
            panic!("no orthogonal figures: {s:?}")
        };
        assert_eq!((frame.missed, own.missed, labels.missed), (4, 4, 0));
        assert!((frame.within[0].1 - 1.0 / 6.0).abs() < 1e-12);
        assert!((own.within[0].1 - 2.0 / 6.0).abs() < 1e-12);
        // The labels' own figures count every photo, refused or not: 0.5, 1.0, 4.0 twice.
        assert!((labels.within[1].1 - 4.0 / 6.0).abs() < 1e-12);
        assert!((labels.within[2].1 - 1.0).abs() < 1e-12);
        // A photo without orthogonalised labels adds nothing to those figures.
        let mut plain = result([Some(0.5), Some(2.0), None], 0.01);
        plain.orthogonal_label_errors_deg = None;
        assert!(summarise(&[plain], Intrinsics::Given).orthogonal.is_none());
    }
}
