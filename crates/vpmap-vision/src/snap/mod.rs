//! Snapping a click to the image corner it means.
//!
//! A person clicks a box corner a few pixels off. [`snap_click`] looks at the photo around
//! the click for the corner where straight edges meet, and returns it to a fraction of a
//! pixel with its 2 x 2 covariance, or leaves the click where it is and says why.
//!
//! # Method
//! 1. **Patch**: the grey levels ([`SnapImage`]) in a square of
//!    `search_radius_px + edge_length_px` around the click, Gaussian-smoothed
//!    ([`SnapOptions::smoothing_sigma_px`]); the gradient by central differences.
//! 2. **Directions**: the lines through the click towards each vanishing point (a two-point
//!    scene's vertical is perpendicular to the horizon), and with
//!    [`SnapOptions::free_directions`] up to two more directions that dominate the gradient's
//!    orientation histogram near the click but run to no vanishing point (a footprint
//!    object's sides, a box turned by its own yaw).
//! 3. **Candidate edges**: per direction, every pixel whose gradient is strong
//!    ([`SnapOptions::min_contrast`]) and perpendicular to the direction (within
//!    [`SnapOptions::angle_tolerance_deg`]) votes, with its gradient, for the line of the
//!    direction's pencil through it (by its signed offset from the click, 0.5 px bins, the two
//!    polarities apart); offsets within the search radius with the most votes are candidates.
//! 4. **Sub-pixel lines**: along each candidate, every pixel a profile across the line finds
//!    the gradient's maximum (of the candidate's polarity, still perpendicular) and places it
//!    by a parabola through it and its neighbours (0.5 px samples); the points are fitted by
//!    weighted least squares (weights: the squared gradient, Huber-reweighted), then sampled
//!    again in a narrow profile around the fitted line and refitted. Runs of points without
//!    gaps longer than 4 px (up to three points in a row missing: a stroke or a pipe across an
//!    edge), at least [`SnapOptions::min_support_px`] long, are edge pieces.
//!    The fitted line's direction is free: the vanishing point only chooses the candidates,
//!    so a vanishing point a little off does not pull the corner.
//! 5. **Corner**: every pair of pieces along different directions whose lines meet within
//!    the search radius, where at least one of them ends (not a crossing), scores the geometric mean of their gradients near the meeting point times a
//!    Gaussian prior on the distance from the click (`sigma = radius / 2.5`), times 0.2 for a T
//!    junction (one edge passes on: mostly an edge in front hiding one behind; but a box's top
//!    corner on the horizon, its two top edges on one image line, is one too). The best pair is
//!    refitted leaving out the points within [`SnapOptions::corner_gap_px`] of the corner
//!    (the blur rounds a corner) and beyond [`SnapOptions::edge_length_px`], twice.
//! 6. **Covariance**: each line fit's parameter covariance (`sigma^2 (A^T W A)^-1`, `sigma^2`
//!    from the weighted residuals), times [`SnapOptions::covariance_scale`] (neighbouring
//!    profile points share pixels through the smoothing and the blur, so they are not
//!    independent), propagated to the intersection to first order (numerical Jacobian), plus
//!    [`SnapOptions::covariance_floor_px`] squared on each axis (what no residual shows:
//!    JPEG blocks, the renderer's anti-aliasing), plus
//!    [`SnapOptions::unseen_sd_per_px`] squared times the squared length of each edge not seen
//!    next to the corner beyond two edge widths (the width: the standard deviation of a
//!    Gaussian through the gradient's peak across the edge; blur alone hides about two next to
//!    a corner, and a junction's own structure, a frame or a moulding, can hide more, over
//!    which the corner is only extrapolated), plus an ambiguity term: the strongest rival
//!    corner more than 1 px away, as the other component of a two-point mixture weighted by
//!    the scores `s1`, `s2`, adds `p d d^T` (`d` the rival's offset, `p = s2 / (s1 + s2)`).
//!
//! The click stays where it is ([`SnapOutcome::Kept`]) when no edge is found, when the edges
//! found all run one way (a click on a single edge), or when edges of two directions meet
//! farther than the search radius from the click: a click on a flat wall never jumps to a far
//! corner. A snapped point is never farther than [`SnapOptions::search_radius_px`] from the
//! click. It also stays, unsure ([`KeptReason::Unsure`], naming the [`Doubt`]), when the
//! corner found is a T junction (one edge passes on), when an edge is seen along less than
//! [`SnapOptions::min_edge_px`] or is not straight ([`SnapOptions::max_edge_rms_px`]), when an
//! edge chosen towards a vanishing point runs off it by more than three standard deviations of
//! the fit's and the vanishing point's ([`SnapOptions::vp_direction_sd_deg`]) uncertainty, or
//! when a rival corner is nearly as strong ([`SnapOptions::max_rival_ratio`]).
//!
//! # References
//! - Canny, "A computational approach to edge detection", IEEE PAMI 8(6), 1986 (gradient
//!   maxima across an edge, sub-pixel by interpolation).
//! - Förstner and Gülch, "A fast operator for detection and precise location of distinct
//!   points, corners and centres of circular features", 1987 (corners as the intersection of
//!   edge lines, with their covariance).
//! - Hartley and Zisserman, *Multiple View Geometry*, 2nd ed., 5.2 (first-order propagation
//!   of covariance).

mod corner;
mod edges;
mod patch;
pub mod scene;

pub use corner::Doubt;
pub use edges::EdgeDirection;
pub use patch::SnapImage;

use corner::{CornerSearch, NoCorner, find_corner};
use edges::{EdgeSearch, Pencil, free_pencils, pieces};
use patch::Patch;

use crate::error::{Result, VisionError};

/// Options of [`snap_click`]. `Default` suits clicks about 2 px off on a photo's own scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapOptions {
    /// The largest distance a click moves, pixels: the corner must lie this close.
    pub search_radius_px: f64,
    /// How far along each edge from the corner its points are fitted, pixels.
    pub edge_length_px: f64,
    /// Gaussian smoothing before the gradient, pixels.
    pub smoothing_sigma_px: f64,
    /// Largest angle between an edge and its direction, degrees.
    pub angle_tolerance_deg: f64,
    /// Smallest brightness step across an edge, grey levels (0 to 255).
    pub min_contrast: f64,
    /// Shortest edge piece, pixels.
    pub min_support_px: f64,
    /// Edge points this close to the corner are left out of the fit, pixels.
    pub corner_gap_px: f64,
    /// Also look for edges along directions that run to no vanishing point.
    pub free_directions: bool,
    /// Multiplier of the line fits' covariance (see the module doc, step 6).
    pub covariance_scale: f64,
    /// Standard deviation added on each axis of the snapped point's covariance, pixels.
    pub covariance_floor_px: f64,
    /// Standard deviation added to the snapped point, on each axis, per pixel of either edge
    /// not seen next to the corner beyond what the blur hides (two edge widths, the width
    /// measured across the edge): the corner is carried along the lines over that stretch,
    /// where a junction's own structure can sit. 0.3 is measured on York Urban: its snapped
    /// points whose edges stop 4.7-6.3 px short of the corner held their labelled corner in
    /// the 95 % ellipse 74 % of the time without it, 90 % with it (`docs/snapping.md`).
    pub unseen_sd_per_px: f64,
    /// The least support of each edge beside the corner (points from
    /// [`SnapOptions::corner_gap_px`] to [`SnapOptions::edge_length_px`] from it, one a
    /// pixel: at most 14 with the defaults) for a snap, pixels. 10 (the edge seen along
    /// three quarters of the fit) is the one threshold chosen on York Urban: 8, 10 and 12 made
    /// 3.6 %, 2.8 % and 1.8 % of 2 px clicks worse by more than 1 px and snapped 40 %, 35 %
    /// and 26 % (`docs/snapping.md`).
    pub min_edge_px: f64,
    /// The largest root-mean-square distance of an edge's points from its fitted line for a
    /// snap, pixels.
    pub max_edge_rms_px: f64,
    /// One standard deviation of the image direction of a line towards a vanishing point,
    /// degrees: how far an edge may run off its vanishing point (3 sd, with the fit's own
    /// uncertainty) before the snap is doubted. 1 degree is the floor of a detected vanishing
    /// point ([`crate::uncertainty::VP_FLOOR_SD_DEG`]).
    pub vp_direction_sd_deg: f64,
    /// A rival corner (more than 2 px from the chosen one, within the search radius) whose
    /// score is more than this share of the chosen one's makes the snap unsure.
    pub max_rival_ratio: f64,
}

impl Default for SnapOptions {
    fn default() -> Self {
        Self {
            search_radius_px: 8.0,
            edge_length_px: 16.0,
            smoothing_sigma_px: 1.0,
            angle_tolerance_deg: 8.0,
            min_contrast: 6.0,
            min_support_px: 5.0,
            corner_gap_px: 3.0,
            free_directions: true,
            covariance_scale: 2.0,
            covariance_floor_px: 0.4,
            unseen_sd_per_px: 0.3,
            min_edge_px: 10.0,
            max_edge_rms_px: 0.5,
            vp_direction_sd_deg: crate::uncertainty::VP_FLOOR_SD_DEG,
            max_rival_ratio: 0.5,
        }
    }
}

/// The search radius in click sigmas: `sqrt(chi2_2(0.95))`, the 95 % circle of a 2-D
/// Gaussian click.
pub const CLICK_RADIUS_SIGMAS: f64 = 2.447_746_830_680_816;

impl SnapOptions {
    /// The default options with the search radius for clicks of `sigma_px` pixels of noise
    /// (1 sigma per coordinate): `2.45 sigma`, at least 3 and at most 16 pixels. A 2-D
    /// Gaussian click lies within `2.45 sigma` of its corner 95 % of the time
    /// (`sqrt(chi2_2(0.95))`): a corner farther from the click is not the one clicked at 95 %,
    /// and on real photos it is more often another structure's corner (York Urban: a radius of
    /// `3.5 sigma` made 5.4 % of 2 px clicks worse by more than 1 px, `2.45 sigma` 3.6 %;
    /// `docs/snapping.md`).
    #[must_use]
    pub fn for_click_sigma(sigma_px: f64) -> Self {
        Self {
            search_radius_px: (CLICK_RADIUS_SIGMAS * sigma_px).clamp(3.0, 16.0),
            ..Self::default()
        }
    }

    fn check(&self) -> Result<()> {
        let checks: [(&'static str, f64, f64, f64); 13] = [
            ("search_radius_px", self.search_radius_px, 0.5, 64.0),
            ("edge_length_px", self.edge_length_px, 3.0, 128.0),
            ("smoothing_sigma_px", self.smoothing_sigma_px, 0.0, 8.0),
            ("angle_tolerance_deg", self.angle_tolerance_deg, 0.5, 30.0),
            ("min_contrast", self.min_contrast, 0.0, 255.0),
            ("min_support_px", self.min_support_px, 3.0, 128.0),
            ("corner_gap_px", self.corner_gap_px, 0.0, 16.0),
            ("covariance_scale", self.covariance_scale, 0.0, 1e6),
            ("unseen_sd_per_px", self.unseen_sd_per_px, 0.0, 10.0),
            ("min_edge_px", self.min_edge_px, 0.0, 128.0),
            ("max_edge_rms_px", self.max_edge_rms_px, 0.0, 1e6),
            ("vp_direction_sd_deg", self.vp_direction_sd_deg, 0.0, 90.0),
            ("max_rival_ratio", self.max_rival_ratio, 0.0, 1e6),
        ];
        for (field, value, lo, hi) in checks {
            if !(value.is_finite() && value >= lo && value <= hi) {
                return Err(VisionError::InvalidParameter {
                    field,
                    value,
                    requirement: "is out of range (see SnapOptions)",
                });
            }
        }
        if !(self.covariance_floor_px.is_finite() && self.covariance_floor_px >= 0.0) {
            return Err(VisionError::InvalidParameter {
                field: "covariance_floor_px",
                value: self.covariance_floor_px,
                requirement: "must be a non-negative number",
            });
        }
        Ok(())
    }
}

/// One edge that fixed a snapped corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapEdge {
    /// Where its direction comes from.
    pub direction: EdgeDirection,
    /// The fitted line's point nearest the corner, pixels.
    pub point_px: [f64; 2],
    /// The fitted line's unit direction.
    pub direction_px: [f64; 2],
    /// Edge points used in the fit (one a pixel of its length).
    pub support_px: f64,
    /// Mean gradient across it, grey levels per pixel.
    pub gradient: f64,
    /// Root-mean-square distance of its points from the fitted line, pixels.
    pub rms_px: f64,
    /// The distance from the corner to the nearest point where the edge was seen, pixels:
    /// how far its line is carried to the corner unseen (blur rounds every corner by a pixel
    /// or two; a junction's own structure can hide more).
    pub gap_px: f64,
    /// The part of [`SnapEdge::gap_px`] beyond what the blur hides (two edge widths and the
    /// points' 1 px spacing), pixels: what the covariance's unseen term counts
    /// ([`SnapOptions::unseen_sd_per_px`] squared times its square, on each axis).
    pub unseen_px: f64,
}

/// Why a click stayed where it was.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum KeptReason {
    /// No straight edge near the click (a flat wall, floor or face).
    NoEdge,
    /// Straight edges near the click, but all in one direction (a click on an edge, not a
    /// corner).
    OneDirection(EdgeDirection),
    /// Edges of two directions that meet too far from the click, or not where one ends.
    TooFar {
        /// Where the nearest pair meets, pixels (if any pair meets).
        corner_px: Option<[f64; 2]>,
        /// Its distance from the click, pixels.
        distance_px: Option<f64>,
        /// The search radius, pixels.
        radius_px: f64,
    },
    /// A corner within the search radius, but the edges do not support it well enough.
    Unsure {
        /// The corner, pixels.
        corner_px: [f64; 2],
        /// What is wrong with it.
        doubt: Doubt,
    },
}

impl std::fmt::Display for KeptReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NoEdge => write!(f, "no straight edge near the click"),
            Self::OneDirection(d) => write!(
                f,
                "edges near the click run one way only ({d}): on an edge, not a corner"
            ),
            Self::TooFar {
                corner_px: Some(c),
                distance_px: Some(d),
                radius_px,
            } => write!(
                f,
                "the nearest edges meet at ({:.1}, {:.1}), {d:.1} px away, beyond the {radius_px:.1} px search radius",
                c[0], c[1]
            ),
            Self::TooFar { radius_px, .. } => write!(
                f,
                "no two edges meet within the {radius_px:.1} px search radius"
            ),
            Self::Unsure { corner_px, doubt } => {
                write!(
                    f,
                    "unsure of the corner at ({:.1}, {:.1}): ",
                    corner_px[0], corner_px[1]
                )?;
                match doubt {
                    Doubt::TJunction => write!(
                        f,
                        "a T junction (one edge passes on: an edge in front of another)"
                    ),
                    Doubt::ShortEdge {
                        support_px,
                        required_px,
                    } => write!(
                        f,
                        "an edge only {support_px:.0} px long beside it (at least {required_px:.0} px needed)"
                    ),
                    Doubt::RoughEdge { rms_px, allowed_px } => write!(
                        f,
                        "an edge is not straight ({rms_px:.2} px from its line, at most {allowed_px:.2} px)"
                    ),
                    Doubt::OffVanishingPoint {
                        angle_deg,
                        allowed_deg,
                    } => write!(
                        f,
                        "an edge runs {angle_deg:.1} deg off its vanishing point (at most {allowed_deg:.1} deg)"
                    ),
                    Doubt::Rival { other_px, ratio } => write!(
                        f,
                        "another corner at ({:.1}, {:.1}) is nearly as strong ({:.0} %)",
                        other_px[0],
                        other_px[1],
                        100.0 * ratio
                    ),
                }
            }
        }
    }
}

/// Whether a click moved.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SnapOutcome {
    /// Moved to the corner of two (or more) edges.
    Snapped,
    /// Left where it was, for this reason.
    Kept(KeptReason),
}

/// The result of snapping one click.
#[derive(Clone, Debug, PartialEq)]
pub struct Snap {
    /// The click, pixels.
    pub click_px: [f64; 2],
    /// The snapped point (the click when kept), pixels.
    pub point_px: [f64; 2],
    /// The snapped point's covariance, pixels squared (`None` when kept).
    pub covariance_px2: Option<[[f64; 2]; 2]>,
    /// The edges that fixed it (empty when kept).
    pub edges: Vec<SnapEdge>,
    /// Moved, or kept and why.
    pub outcome: SnapOutcome,
}

impl Snap {
    /// How far the click moved, pixels.
    #[must_use]
    pub fn moved_px(&self) -> f64 {
        (self.point_px[0] - self.click_px[0]).hypot(self.point_px[1] - self.click_px[1])
    }

    /// Whether it moved to a corner.
    #[must_use]
    pub fn snapped(&self) -> bool {
        self.outcome == SnapOutcome::Snapped
    }
}

/// The directions snapping looks along: one per vanishing point, plus a two-point scene's
/// vertical (perpendicular to the line through its two vanishing points).
fn pencils(vanishing_points: &[[f64; 3]]) -> Vec<Pencil> {
    let mut out: Vec<Pencil> = vanishing_points
        .iter()
        .enumerate()
        .filter_map(|(i, v)| Pencil::new(EdgeDirection::VanishingPoint(i), *v))
        .collect();
    if let [a, b] = vanishing_points
        && let Some(v) = two_point_vertical(*a, *b)
        && let Some(p) = Pencil::new(EdgeDirection::VanishingPoint(2), v)
    {
        out.push(p);
    }
    out
}

/// A two-point scene's vertical, for horizontal vanishing points `a` and `b` (homogeneous):
/// the direction at infinity `(l0, l1, 0)` perpendicular to the horizon `l = a x b`; `None`
/// when the two points give no horizon.
pub(crate) fn two_point_vertical(a: [f64; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let l = [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ];
    (l[0].hypot(l[1]) > 0.0).then_some([l[0], l[1], 0.0])
}

/// Snap one click to the image corner it means (see the [module docs](self)).
///
/// `vanishing_points` are homogeneous pixel coordinates `(x, y, w)`: a point `(x, y, 1)`, a
/// direction `(dx, dy, 0)` (as [`vpmap_metrology::scene::Scene::resolve_vanishing_points`]
/// gives them); two (a level camera: the vertical is added) or three.
///
/// # Errors
/// [`VisionError::ClickOutsidePhoto`] for a click outside the photo or not finite,
/// [`VisionError::InvalidParameter`] for options out of range.
///
/// # Example
/// ```
/// use image::{DynamicImage, GrayImage, Luma};
/// use vpmap_vision::snap::{snap_click, SnapImage, SnapOptions};
/// // A dark square whose top-left corner is at (30, 20).
/// let img = GrayImage::from_fn(100, 80, |x, y| {
///     Luma([if x >= 30 && y >= 20 && x < 70 && y < 60 { 40 } else { 200 }])
/// });
/// let photo = SnapImage::new(&DynamicImage::ImageLuma8(img));
/// // Vanishing points at infinity along x and y.
/// let vps = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let snap = snap_click(&photo, &vps, [32.0, 18.5], &SnapOptions::default())?;
/// assert!(snap.snapped());
/// assert!((snap.point_px[0] - 30.0).abs() < 0.2 && (snap.point_px[1] - 20.0).abs() < 0.2);
/// # Ok::<(), vpmap_vision::VisionError>(())
/// ```
///
/// # Complexity
/// `O((search_radius_px + edge_length_px)^2)` per direction: the patch around the click only.
pub fn snap_click(
    image: &SnapImage,
    vanishing_points: &[[f64; 3]],
    click_px: [f64; 2],
    opts: &SnapOptions,
) -> Result<Snap> {
    opts.check()?;
    check_click(image, click_px)?;
    let found = find_pieces(image, vanishing_points, click_px, opts);
    let corner = find_corner(
        &found,
        &CornerSearch {
            click: click_px,
            radius: opts.search_radius_px,
            gap: opts.corner_gap_px,
            length: opts.edge_length_px,
            min_points: min_points(opts),
            covariance_scale: opts.covariance_scale,
            covariance_floor: opts.covariance_floor_px,
            unseen_sd_per_px: opts.unseen_sd_per_px,
            min_edge_px: opts.min_edge_px,
            max_rms_px: opts.max_edge_rms_px,
            vp_direction_sd: opts.vp_direction_sd_deg.to_radians(),
            max_rival_ratio: opts.max_rival_ratio,
        },
    );
    Ok(match corner {
        Ok(c) => Snap {
            click_px,
            point_px: c.point,
            covariance_px2: Some(c.cov),
            edges: c
                .edges
                .iter()
                .map(|e| SnapEdge {
                    direction: e.kind,
                    point_px: e.point,
                    direction_px: e.direction,
                    support_px: e.support_px,
                    gradient: e.strength,
                    rms_px: e.rms_px,
                    gap_px: e.gap_px,
                    unseen_px: e.unseen_px,
                })
                .collect(),
            outcome: SnapOutcome::Snapped,
        },
        Err(why) => Snap {
            click_px,
            point_px: click_px,
            covariance_px2: None,
            edges: Vec::new(),
            outcome: SnapOutcome::Kept(match why {
                NoCorner::NoEdge => KeptReason::NoEdge,
                NoCorner::OneDirection(d) => KeptReason::OneDirection(d),
                NoCorner::NoMeeting(m) => KeptReason::TooFar {
                    corner_px: m.map(|m| m.0),
                    distance_px: m.map(|m| m.1),
                    radius_px: opts.search_radius_px,
                },
                NoCorner::Unsure(corner_px, doubt) => KeptReason::Unsure { corner_px, doubt },
            }),
        },
    })
}

/// The edge pieces found near a click (steps 1 to 4 of the [module docs](self)); `opts` is
/// checked by the caller.
fn find_pieces(
    image: &SnapImage,
    vanishing_points: &[[f64; 3]],
    click_px: [f64; 2],
    opts: &SnapOptions,
) -> Vec<edges::Piece> {
    let reach = opts.search_radius_px + opts.edge_length_px;
    let half = (reach + 3.0).ceil() as usize;
    let patch = Patch::new(image, click_px, half, opts.smoothing_sigma_px);
    let sigma_total = opts.smoothing_sigma_px.hypot(0.8);
    let min_gradient = opts.min_contrast / (sigma_total * (2.0 * std::f64::consts::PI).sqrt());
    let search = EdgeSearch {
        click: click_px,
        radius: opts.search_radius_px,
        reach,
        min_gradient,
        tan_tolerance: opts.angle_tolerance_deg.to_radians().tan(),
        min_points: min_points(opts),
        min_vote: 0.5 * opts.min_contrast * opts.min_support_px,
    };
    let mut all = pencils(vanishing_points);
    // A vanishing point inside the patch: its pencil's direction changes too fast to vote.
    all.retain(|p| p.distance_from(click_px) > 2.0 * reach);
    if opts.free_directions {
        let free = free_pencils(&patch, &search, &all);
        all.extend(free);
    }
    all.iter()
        .flat_map(|p| pieces(&patch, &search, p))
        .collect()
}

/// One straight edge piece found near a click, as snapping saw it (before any corner is
/// chosen): for looking at why a click stayed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoundEdge {
    /// Where its direction comes from.
    pub direction: EdgeDirection,
    /// Its first and last points on its fitted line, pixels.
    pub ends_px: [[f64; 2]; 2],
    /// Points seen along it (one a pixel).
    pub support_px: f64,
    /// Mean gradient across it, grey levels per pixel.
    pub gradient: f64,
}

/// Every straight edge piece [`snap_click`] finds near a click, whether or not two of them
/// make a corner: what a person (or a diagnosis) looks at when a click stays.
///
/// # Errors
/// As [`snap_click`].
pub fn edges_near_click(
    image: &SnapImage,
    vanishing_points: &[[f64; 3]],
    click_px: [f64; 2],
    opts: &SnapOptions,
) -> Result<Vec<FoundEdge>> {
    opts.check()?;
    check_click(image, click_px)?;
    Ok(find_pieces(image, vanishing_points, click_px, opts)
        .iter()
        .filter_map(|p| {
            let fit = edges::fit_line(&p.points, 0.05)?;
            let (point, d) = p.line(&fit);
            let (t0, t1) = p.range();
            let along = |t: f64| {
                // `t` runs along the piece's frame; its line's point nearest the frame's `t`.
                let q = [p.origin[0] + t * p.u[0], p.origin[1] + t * p.u[1]];
                let k = (q[0] - point[0]) * d[0] + (q[1] - point[1]) * d[1];
                [point[0] + k * d[0], point[1] + k * d[1]]
            };
            Some(FoundEdge {
                direction: p.kind,
                ends_px: [along(t0), along(t1)],
                support_px: p.points.len() as f64,
                gradient: p.points.iter().map(|q| q.weight).sum::<f64>()
                    / p.points.len().max(1) as f64,
            })
        })
        .collect())
}

/// The fewest points of an edge piece.
fn min_points(opts: &SnapOptions) -> usize {
    opts.min_support_px.round().max(3.0) as usize
}

/// A click outside the photo or not finite is refused.
fn check_click(image: &SnapImage, click_px: [f64; 2]) -> Result<()> {
    let (w, h) = (f64::from(image.width()), f64::from(image.height()));
    if click_px.iter().all(|v| v.is_finite())
        && (0.0..=w).contains(&click_px[0])
        && (0.0..=h).contains(&click_px[1])
    {
        return Ok(());
    }
    Err(VisionError::ClickOutsidePhoto {
        field: "click".to_owned(),
        x: click_px[0],
        y: click_px[1],
        width: image.width(),
        height: image.height(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use image::{DynamicImage, GrayImage, Luma};

    /// A dark square whose top-left corner is at (30, 20), its top edge crossed by a thin
    /// vertical stroke `stroke_px` wide starting `at_px` right of the corner.
    fn corner_with_stroke(at_px: u32, stroke_px: u32) -> SnapImage {
        let img = GrayImage::from_fn(100, 80, |x, y| {
            let inside = x >= 30 && y >= 20 && x < 70 && y < 60;
            let stroke = x >= 30 + at_px && x < 30 + at_px + stroke_px && (12..28).contains(&y);
            Luma([match (stroke, inside) {
                (true, _) => 120,
                (false, true) => 40,
                (false, false) => 200,
            }])
        });
        SnapImage::new(&DynamicImage::ImageLuma8(img))
    }

    #[test]
    fn an_edge_crossed_by_a_thin_stroke_is_one_piece() {
        // Regression (issue 38): a stroke across an edge turns the gradient over its width
        // and the blur's, so three points in a row are missing; pieces broke at gaps over
        // 2 px, and the edge next to the corner was lost.
        let vps = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        for at in [6, 8, 10] {
            let photo = corner_with_stroke(at, 3);
            let edges = match edges_near_click(
                &photo,
                &vps,
                [31.5, 21.0],
                &SnapOptions::for_click_sigma(2.0),
            ) {
                Ok(e) => e,
                Err(e) => panic!("{e}"),
            };
            let across = edges.iter().any(|e| {
                let (x0, x1) = (
                    e.ends_px[0][0].min(e.ends_px[1][0]),
                    e.ends_px[0][0].max(e.ends_px[1][0]),
                );
                (e.ends_px[0][1] - 20.0).abs() < 0.5
                    && x0 < f64::from(30 + at)
                    && x1 > f64::from(33 + at)
            });
            assert!(across, "stroke at {at} px: {edges:?}");
        }
    }
}
