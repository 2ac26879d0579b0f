//! What a detection evaluation measured: per photo ([`ImageResult`]), its two runs ([`Run`]),
//! one with the labelled intrinsics given and one with them estimated ([`Intrinsics`]).

/// With the true intrinsics given to the detector, or estimated by it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Intrinsics {
    /// `--focal-px` and `--principal-point` from the label's `K`.
    Given,
    /// Estimated from the photo.
    Estimated,
}

impl Intrinsics {
    /// Both, in report order.
    pub const BOTH: [Self; 2] = [Self::Given, Self::Estimated];

    /// Key in the JSON report.
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::Given => "given_intrinsics",
            Self::Estimated => "estimated_intrinsics",
        }
    }
}

/// One detection run on one photo.
#[derive(Clone, Debug)]
pub struct Run {
    /// Wall time of `detect`, milliseconds (`None` when the photo could not be read).
    pub time_ms: Option<f64>,
    /// What came out, or why nothing did.
    pub outcome: std::result::Result<RunOk, String>,
}

/// A successful run.
#[derive(Clone, Debug)]
pub struct RunOk {
    /// Error of each labelled vanishing point (label order), degrees; `None`: not detected.
    pub errors_deg: [Option<f64>; 3],
    /// The same for each direction's own least-squares point
    /// ([`vpmap_vision::VanishingPoint::own_point`]); `None`: no own point.
    pub own_errors_deg: [Option<f64>; 3],
    /// Against the dataset's orthogonalised labels instead ([`super::Label::orthogonalised`]):
    /// the frame's errors, then the own points'; `None` when the label file has none.
    pub against_orthogonal_deg: Option<[[Option<f64>; 3]; 2]>,
    /// Each labelled direction's Mahalanobis distance squared from the written scene's
    /// vanishing point, under its covariance (label order; `None`: not written)
    /// ([`super::coverage`]).
    pub ellipse_d2: [Option<f64>; 3],
    /// The labelled focal length's distance from the written scene's estimate, in its
    /// standard deviations (estimated runs only; [`super::coverage::focal_z`]).
    pub focal_z: Option<f64>,
    /// Where the labelled camera (pitch, roll, horizon, principal point) lies in the error
    /// bars of the written scene's camera ([`super::coverage::camera_z`]).
    pub camera_z: Option<super::coverage::CameraZ>,
    /// Focal length used, pixels.
    pub focal_px: f64,
    /// Relative focal error `|f - f_true| / f_true` (only when estimated).
    pub focal_error: Option<f64>,
    /// Principal point used, pixels.
    pub principal_point_px: [f64; 2],
    /// "2pp" or "3pp", as the detector judged it.
    pub perspective: &'static str,
    /// Segments found.
    pub segments: usize,
    /// The horizon error of the scene file written for the detection, image heights
    /// ([`horizon_error`](super::horizon::horizon_error)) against
    /// [`Label::horizon`](super::Label::horizon) and against
    /// [`Label::horizon_of_horizontals`](super::Label::horizon_of_horizontals); `None` when the detection gives no scene.
    pub horizon_error: Option<[f64; 2]>,
    /// The lens distortion the edges show: the division model's `k` (applied or not) and its
    /// sd (`None` with the lens taken as a pinhole's).
    pub lens: Option<[f64; 2]>,
    /// The segments' own part of that sd, before the floor and the prior (`None` when they do
    /// not fix `k`).
    pub lens_segments_sd: Option<f64>,
}

/// One photo's two runs.
#[derive(Clone, Debug)]
pub struct ImageResult {
    /// The file stem.
    pub name: String,
    /// `[width, height]`, pixels (`None` when unreadable).
    pub size_px: Option<[u32; 2]>,
    /// Which labelled vanishing point is the vertical one.
    pub vertical: usize,
    /// The dataset's orthogonalised directions' errors against its labels
    /// ([`super::Label::orthogonal_errors_deg`]); `None` when the label file has none.
    pub orthogonal_label_errors_deg: Option<[f64; 3]>,
    /// Runs in [`Intrinsics::BOTH`] order.
    pub runs: [Run; 2],
}
