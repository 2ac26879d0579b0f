//! Whole-room placement hypotheses, independent of the order the photos are given in.
//!
//! A hypothesis is one quarter turn for every photo after the first (photo 1 sets the room
//! frame). Given the turns, every photo's heading is known, and placing the photos is a
//! linear least-squares problem: each photo's scale `s_k` and station point `t_k` (photo 1:
//! `1` and the origin) and each shared point's room position `P_j` minimise
//! `sum w_kj |s_k R_k p_kj + t_k - P_j|^2` over every shared floor corner `p_kj` (a box's
//! four corners, labelled by where they lie along the room's two directions, so the turn
//! decides which corner is which; a footprint's vertices in the cyclic order that fits the
//! photo that placed it best) and `sum w_ko (s_k h_ko - H_o)^2` over shared heights. The
//! points are eliminated in closed form (each is the weighted mean of its sightings), which
//! leaves a `3 (n - 1)` system. Its minimum is the hypothesis's score: every tie of every
//! photo counts at once, so a photo tied weakly to one photo is held by the others.
//!
//! Weights are the inverse variance of a floor point clicked with one pixel of noise:
//! `f^2 / (d^2 (1 + d^2) + 1)` for a point `d` camera heights from its camera (depth error
//! grows as `d^2`), `f^2 / (d^2 + 1)` for a height; the score is thus in squared pixels of
//! the clicks, roughly.
//!
//! Search: photos are joined strongest tie first (most shared corners with the photos
//! already joined; equal ties by their objects' names, then their content, so the order of
//! the file does not matter), keeping the best [`BEAM`] partial hypotheses at each step (every one of them
//! for rooms of up to four photos; best by score, scores within their numerical noise of each
//! other by the placement key of `room/canonical.rs`, so that which are kept and which the
//! joint fit starts from do not follow the file's order either) among those scoring within
//! the bound a greedy pass sets
//! (a photo joining never lowers a score, so a partial hypothesis above `2 S +
//! NEAR_SCORE_PX2`, `S` the greedy hypothesis's score, can never be started from). A photo
//! whose room file pins its turn (`placement_turn_deg`) is tried at that turn only.

use nalgebra::{DMatrix, DVector, Vector2};

use super::align::{PhotoFit, footprint_map, own_corners, room_axes};
use super::canonical::{PhotoKeys, same_score};
use crate::fit::model::{BoxAxes, Part};

/// Partial hypotheses kept at each step of the search (`4^3`: every hypothesis of a room of
/// four photos).
pub(crate) const BEAM: usize = 64;

/// Smallest ratio of the placement system's Cholesky diagonal to its largest (the square
/// root of its condition number's inverse) for the system to place its photos.
const SINGULAR_RATIO: f64 = 1e-7;

/// One whole-room hypothesis: each photo's quarter turn and its placement.
#[derive(Debug, Clone)]
pub(crate) struct Hypothesis {
    /// Each photo's quarter turn (`None`: not tied to the room).
    pub quarters: Vec<Option<u8>>,
    /// Each photo's scale and station point (photo 1: `1` and the origin).
    pub placements: Vec<Option<(f64, Vector2<f64>)>>,
    /// The weighted least-squares misfit of every shared corner and height, roughly squared
    /// pixels of click noise.
    pub score: f64,
}

/// One shared point seen by one photo: which room point, its own-frame position turned by
/// the photo's heading (or a height), its weight.
#[derive(Debug, Clone, Copy)]
struct Obs {
    photo: usize,
    /// The tied object's index and the point's label on it (`usize::MAX`: its height).
    key: (usize, usize),
    /// Turned own-frame floor point; for a height, `(h, 0)`.
    at: Vector2<f64>,
    height: bool,
    weight: f64,
}

/// The photos' shared objects: for each object name seen by two or more photos, each photo's
/// object index.
pub(crate) struct Ties {
    names: Vec<String>,
    /// Per name, `(photo, object index)`.
    seen: Vec<Vec<(usize, usize)>>,
}

impl Ties {
    pub fn new(fits: &[PhotoFit]) -> Self {
        let mut names: Vec<String> = Vec::new();
        let mut seen: Vec<Vec<(usize, usize)>> = Vec::new();
        for (k, f) in fits.iter().enumerate() {
            for (i, o) in f.objects.iter().enumerate() {
                if let Some(n) = names.iter().position(|n| n == &o.name) {
                    if let Some(s) = seen.get_mut(n) {
                        s.push((k, i));
                    }
                } else {
                    names.push(o.name.clone());
                    seen.push(vec![(k, i)]);
                }
            }
        }
        let keep: Vec<bool> = seen.iter().map(|s| s.len() > 1).collect();
        let mut it = keep.iter();
        names.retain(|_| *it.next().unwrap_or(&false));
        seen.retain(|s| s.len() > 1);
        Self { names, seen }
    }

    /// The names photo `k` shares with any other photo.
    pub fn shared_by(&self, k: usize) -> Vec<String> {
        self.names
            .iter()
            .zip(&self.seen)
            .filter(|(_, s)| s.iter().any(|(p, _)| *p == k))
            .map(|(n, _)| n.clone())
            .collect()
    }
}

/// Points one object gives a tie: a box's 4 corners (and its height when both photos see its
/// top), a footprint's vertices.
fn tie_points(fits: &[PhotoFit], a: (usize, usize)) -> usize {
    let Some(o) = fits.get(a.0).and_then(|f| f.objects.get(a.1)) else {
        return 0;
    };
    match &o.part {
        Part::Box { .. } => 4,
        Part::Footprint { vertices, .. } => vertices.len(),
        Part::FloorPoint { .. } => 1,
    }
}

/// The order photos are joined in: photo 1 first, then repeatedly the photo with the most
/// shared points with the photos joined (ties by its sorted object names, then by its content,
/// `photos`: never by where the file lists it). Photos that share nothing with the joined
/// ones are left out.
pub(crate) fn join_order(fits: &[PhotoFit], ties: &Ties, photos: &PhotoKeys) -> Vec<usize> {
    let n = fits.len();
    let keys: Vec<(Vec<&str>, &str)> = fits
        .iter()
        .enumerate()
        .map(|(k, f)| {
            let mut v: Vec<&str> = f.objects.iter().map(|o| o.name.as_str()).collect();
            v.sort_unstable();
            (v, photos.photo(k))
        })
        .collect();
    let mut order = vec![0];
    let mut joined = vec![false; n];
    if let Some(j) = joined.first_mut() {
        *j = true;
    }
    loop {
        let mut best: Option<(usize, usize)> = None;
        for k in (0..n).filter(|&k| !joined[k]) {
            let strength: usize = ties
                .seen
                .iter()
                .filter_map(|s| {
                    let mine = s.iter().find(|(p, _)| *p == k)?;
                    s.iter()
                        .any(|(p, _)| joined[*p])
                        .then(|| tie_points(fits, *mine))
                })
                .sum();
            if strength == 0 {
                continue;
            }
            let better =
                best.is_none_or(|(b, bs)| strength > bs || (strength == bs && keys[k] < keys[b]));
            if better {
                best = Some((k, strength));
            }
        }
        let Some((k, _)) = best else { break };
        joined[k] = true;
        order.push(k);
    }
    order
}

/// Label of a box's corner `(i, j)` in the room: bit 0 whether it is the far one along the
/// room's first direction, bit 1 along the second.
fn corner_label(axes: BoxAxes, i: u8, j: u8) -> usize {
    // Quarter turns of the box's two axes in the room (0: +first, 1: +second, 2: -first,
    // 3: -second), as `align::quarters`.
    let q = |k: usize, sign: f64| (k + if sign < 0.0 { 2 } else { 0 }) % 4;
    let (q1, q2) = (q(axes.first, axes.sign1), q(1 - axes.first, axes.sign2));
    let mut label = 0;
    for (qa, v) in [(q1, i), (q2, j)] {
        let far = match qa {
            0 | 1 => v == 1,
            _ => v == 0,
        };
        if far {
            label |= 1 << (qa % 2);
        }
    }
    label
}

/// Floor-point weight: inverse variance of a point `d` camera heights away clicked with one
/// pixel of noise by a camera of focal length `f` pixels.
fn point_weight(focal_px: f64, d: f64) -> f64 {
    focal_px * focal_px / (d * d * (1.0 + d * d) + 1.0)
}

fn height_weight(focal_px: f64, d: f64) -> f64 {
    focal_px * focal_px / (d * d + 1.0)
}

/// An object's floor corners in its photo's own frame and its height.
type OwnObject = (Vec<Vector2<f64>>, Option<f64>);

/// The search's fixed data: each photo's shared objects' corners in its own frame.
pub(crate) struct Search<'a> {
    fits: &'a [PhotoFit],
    ties: &'a Ties,
    /// Per photo, its room yaw.
    yaws: Vec<f64>,
    focals: Vec<f64>,
    /// Per tied object and sighting (as `ties.seen`), its floor corners in its photo's own
    /// frame and its height.
    own: Vec<Vec<OwnObject>>,
    /// Per photo, its pinned quarter turn (the room file's `placement_turn_deg`), `None`
    /// where every turn is tried.
    pins: Vec<Option<u8>>,
    /// Per photo, its rank among the photos' content keys ([`PhotoKeys::ranks`]).
    ranks: Vec<usize>,
}

impl<'a> Search<'a> {
    pub fn new(fits: &'a [PhotoFit], ties: &'a Ties, photos: &PhotoKeys) -> Self {
        let cams: Vec<_> = fits.iter().map(PhotoFit::camera).collect();
        let own = ties
            .seen
            .iter()
            .map(|s| {
                s.iter()
                    .map(|&(p, i)| {
                        match (cams.get(p), fits.get(p).and_then(|f| f.objects.get(i))) {
                            (Some(cam), Some(o)) => own_corners(cam, o),
                            _ => (Vec::new(), None),
                        }
                    })
                    .collect()
            })
            .collect();
        Self {
            fits,
            ties,
            yaws: cams.iter().map(|c| c.room_yaw_rad).collect(),
            focals: cams.iter().map(|c| c.focal_px).collect(),
            own,
            pins: Vec::new(),
            ranks: photos.ranks(),
        }
    }

    /// The search with photos pinned to quarter turns (`pins[k]`, `None`: every turn tried).
    pub fn with_pins(mut self, pins: Vec<Option<u8>>) -> Self {
        self.pins = pins;
        self
    }

    fn heading(&self, k: usize, quarter: u8) -> f64 {
        self.yaws.first().copied().unwrap_or(0.0) + f64::from(quarter) * std::f64::consts::FRAC_PI_2
            - self.yaws.get(k).copied().unwrap_or(0.0)
    }

    /// The observations of a (partial) hypothesis.
    fn observations(&self, quarters: &[Option<u8>], order: &[usize]) -> Vec<Obs> {
        let rank = |k: usize| order.iter().position(|&o| o == k).unwrap_or(usize::MAX);
        let mut out = Vec::new();
        for (object, s) in self.ties.seen.iter().enumerate() {
            let mut joined: Vec<(usize, usize, u8, usize)> = s
                .iter()
                .enumerate()
                .filter_map(|(n, &(p, i))| Some((p, i, quarters.get(p).copied().flatten()?, n)))
                .collect();
            if joined.len() < 2 {
                continue;
            }
            // A footprint's vertices are matched to those of the first photo joined that
            // shows it.
            joined.sort_by_key(|(p, _, _, _)| rank(*p));
            let mut reference: Option<Vec<Vector2<f64>>> = None;
            for &(p, i, q, n) in &joined {
                let Some(f) = self.fits.get(p) else { continue };
                let Some(o) = f.objects.get(i) else { continue };
                let Some((corners, h)) = self.own.get(object).and_then(|v| v.get(n)) else {
                    continue;
                };
                let h = *h;
                let (sn, cs) = self.heading(p, q).sin_cos();
                let turn = |v: Vector2<f64>| Vector2::new(cs * v.x - sn * v.y, sn * v.x + cs * v.y);
                let focal = self.focals.get(p).copied().unwrap_or(1000.0);
                let centre = corners.iter().sum::<Vector2<f64>>() / corners.len().max(1) as f64;
                let labels: Vec<usize> = match &o.part {
                    Part::Box { axes, .. } => {
                        let turned = room_axes(*axes, q);
                        [(0u8, 0u8), (1, 0), (1, 1), (0, 1)]
                            .iter()
                            .map(|&(i, j)| corner_label(turned, i, j))
                            .collect()
                    }
                    Part::Footprint { .. } => {
                        let turned: Vec<Vector2<f64>> = corners.iter().map(|c| turn(*c)).collect();
                        if let Some(r) = &reference {
                            match footprint_map(&turned, r, 0.0) {
                                Some((m, _)) => m,
                                None => continue,
                            }
                        } else {
                            reference = Some(turned);
                            (0..corners.len()).collect()
                        }
                    }
                    Part::FloorPoint { .. } => continue,
                };
                for (c, label) in corners.iter().zip(labels) {
                    out.push(Obs {
                        photo: p,
                        key: (object, label),
                        at: turn(*c),
                        height: false,
                        weight: point_weight(focal, c.norm()),
                    });
                }
                if let Some(h) = h {
                    out.push(Obs {
                        photo: p,
                        key: (object, usize::MAX),
                        at: Vector2::new(h, 0.0),
                        height: true,
                        weight: height_weight(focal, centre.norm()),
                    });
                }
            }
        }
        out
    }

    /// Solve the placement of a (partial) hypothesis: `None` when the ties do not fix it.
    pub fn solve(&self, quarters: &[Option<u8>], order: &[usize]) -> Option<Hypothesis> {
        let n = quarters.len();
        // Unknown index of each posed photo.
        let mut slot = vec![None; n];
        let mut m = 0;
        for &k in order.iter().skip(1) {
            if quarters.get(k).copied().flatten().is_some() {
                slot[k] = Some(m);
                m += 1;
            }
        }
        let obs = self.observations(quarters, order);
        let dim = 3 * m;
        let mut hess = DMatrix::<f64>::zeros(dim, dim);
        let mut grad = DVector::<f64>::zeros(dim);
        let mut constant = 0.0;
        // Each observation as `a = J z + b` (2 rows for a floor point, 1 for a height), `J`
        // nonzero only in its photo's three columns.
        let row = |o: &Obs, r: usize| -> [f64; 3] {
            match (o.height, r) {
                (true, _) => [o.at.x, 0.0, 0.0],
                (false, 0) => [o.at.x, 1.0, 0.0],
                (false, _) => [o.at.y, 0.0, 1.0],
            }
        };
        let mut obs = obs;
        obs.sort_by_key(|o| o.key);
        for group in obs.chunk_by(|a, b| a.key == b.key) {
            if group.len() < 2 {
                continue;
            }
            let total: f64 = group.iter().map(|o| o.weight).sum();
            let len = if group.first().is_some_and(|o| o.height) {
                1
            } else {
                2
            };
            for r in 0..len {
                // Each sighting's row: coefficients on its photo's unknowns, and its constant
                // (photo 1's sighting is all constant).
                let lin: Vec<(Option<usize>, [f64; 3], f64, f64)> = group
                    .iter()
                    .map(|o| {
                        let coef = row(o, r);
                        match slot.get(o.photo).copied().flatten() {
                            Some(s) => (Some(s), coef, 0.0, o.weight),
                            // Photo 1: s = 1, t = 0.
                            None => (None, [0.0; 3], coef[0], o.weight),
                        }
                    })
                    .collect();
                // sum_k w_k a_k^2 - (sum_k w_k a_k)^2 / W, a_k = c_k . z_k + b_k.
                for (sa, ca, ba, wa) in &lin {
                    constant += wa * ba * ba;
                    if let Some(sa) = sa {
                        for u in 0..3 {
                            grad[3 * sa + u] += wa * ca[u] * ba;
                            for v in 0..3 {
                                hess[(3 * sa + u, 3 * sa + v)] += wa * ca[u] * ca[v];
                            }
                        }
                    }
                    for (sb, cb, bb, wb) in &lin {
                        let f = wa * wb / total;
                        constant -= f * ba * bb;
                        if let Some(sa) = sa {
                            for u in 0..3 {
                                grad[3 * sa + u] -= f * ca[u] * bb;
                            }
                        }
                        if let (Some(sa), Some(sb)) = (sa, sb) {
                            for u in 0..3 {
                                for v in 0..3 {
                                    hess[(3 * sa + u, 3 * sb + v)] -= f * ca[u] * cb[v];
                                }
                            }
                        }
                    }
                }
            }
        }
        // Each posed photo needs its three unknowns fixed.
        let z = if dim == 0 {
            DVector::zeros(0)
        } else {
            let chol = hess.clone().cholesky()?;
            // A nearly singular system (a photo tied by a single point) does not place it.
            let l = chol.l_dirty().diagonal();
            let (lo, hi) = l.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(*v), hi.max(*v))
            });
            if lo <= SINGULAR_RATIO * hi {
                return None;
            }
            chol.solve(&(-&grad))
        };
        let score = (constant + grad.dot(&z)).max(0.0);
        let mut placements = vec![None; n];
        if let Some(p) = placements.first_mut() {
            *p = Some((1.0, Vector2::zeros()));
        }
        for (k, s) in slot.iter().enumerate() {
            if let Some(s) = s {
                let scale = z[3 * s];
                if !(scale.is_finite() && scale > 0.0) {
                    return None;
                }
                placements[k] = Some((scale, Vector2::new(z[3 * s + 1], z[3 * s + 2])));
            }
        }
        Some(Hypothesis {
            quarters: quarters.to_vec(),
            placements,
            score,
        })
    }
}

impl Search<'_> {
    /// A hypothesis's placement key: [`PhotoKeys::placement`] with the photos' ranks for their
    /// keys, a photo not yet joined at turn `u8::MAX` (every hypothesis of one step of the
    /// search joins the same photos: the join order is a function of the room).
    fn placement_key(&self, h: &Hypothesis) -> Vec<(usize, u8)> {
        let mut key: Vec<(usize, u8)> = h
            .quarters
            .iter()
            .enumerate()
            .skip(1)
            .map(|(k, q)| {
                let rank = self.ranks.get(k).copied().unwrap_or(usize::MAX);
                (rank, q.unwrap_or(u8::MAX))
            })
            .collect();
        key.sort_unstable();
        key
    }

    /// Order `hypotheses` best first as a function of the room, not of the order its photos
    /// are listed in: by score, but scores within their numerical noise of the least score
    /// not yet placed ([`same_score`]: the noise follows the order of the sums, which follows
    /// the listing) as one group, ordered by placement key. The beam's truncation and the
    /// starts ([`starts`]) then take the same hypotheses in every order.
    fn rank(&self, hypotheses: &mut Vec<Hypothesis>) {
        hypotheses.sort_by(|a, b| a.score.total_cmp(&b.score));
        let mut ranked = Vec::with_capacity(hypotheses.len());
        let mut rest = std::mem::take(hypotheses).into_iter().peekable();
        while let Some(first) = rest.next() {
            let mut group = vec![first];
            let least = group.first().map_or(0.0, |h| h.score);
            while let Some(h) = rest.next_if(|h| same_score(h.score, least)) {
                group.push(h);
            }
            group.sort_by_cached_key(|h| self.placement_key(h));
            ranked.append(&mut group);
        }
        *hypotheses = ranked;
    }
}

/// Most whole-room hypotheses the joint fit is started from.
pub(crate) const MAX_STARTS: usize = 4;

/// Score margin, squared pixels, within which a hypothesis is started as well as the best:
/// `score <= 2 best + NEAR_SCORE_PX2` (the factor 2 allows for the scores' rough weights).
pub(crate) const NEAR_SCORE_PX2: f64 = 25.0;

impl Search<'_> {
    /// Every whole-room hypothesis the beam keeps, best first (scores within their numerical
    /// noise by placement key, [`Self::rank`]); `Err(k)` names a photo that no hypothesis
    /// places.
    pub fn run(&self, order: &[usize]) -> std::result::Result<Vec<Hypothesis>, usize> {
        // A greedy pass bounds the search: a photo joining never lowers a hypothesis's score
        // (it adds residuals and unknowns of its own), so a partial hypothesis scoring above
        // `2 S + NEAR_SCORE_PX2`, `S` the greedy one's, can never be started from.
        let greedy = self.beam(order, 1, f64::INFINITY)?;
        let bound = greedy
            .first()
            .map_or(f64::INFINITY, |h| 2.0 * h.score + NEAR_SCORE_PX2);
        self.beam(order, BEAM, bound)
    }

    /// The beam search keeping `width` partial hypotheses scoring at most `bound`.
    fn beam(
        &self,
        order: &[usize],
        width: usize,
        bound: f64,
    ) -> std::result::Result<Vec<Hypothesis>, usize> {
        let n = self.fits.len();
        let mut start = vec![None; n];
        if let Some(s) = start.first_mut() {
            *s = Some(0);
        }
        let mut beam = vec![Hypothesis {
            quarters: start,
            placements: Vec::new(),
            score: 0.0,
        }];
        for (step, &k) in order.iter().enumerate().skip(1) {
            let mut next = Vec::with_capacity(4 * beam.len());
            for h in &beam {
                let pinned = self.pins.get(k).copied().flatten();
                for q in (0..4u8).filter(|&q| pinned.is_none_or(|p| p == q)) {
                    let mut quarters = h.quarters.clone();
                    if let Some(slot) = quarters.get_mut(k) {
                        *slot = Some(q);
                    }
                    if let Some(s) = self.solve(&quarters, &order[..=step])
                        && s.score <= bound
                    {
                        next.push(s);
                    }
                }
            }
            if next.is_empty() {
                return Err(k);
            }
            self.rank(&mut next);
            next.truncate(width);
            beam = next;
        }
        if beam.iter().all(|h| h.placements.is_empty()) {
            // Photo 1 alone.
            for h in &mut beam {
                h.placements = vec![None; n];
                if let Some(p) = h.placements.first_mut() {
                    *p = Some((1.0, Vector2::zeros()));
                }
            }
        }
        Ok(beam)
    }
}

/// The hypotheses the joint fit starts from: the best, and those near it
/// ([`NEAR_SCORE_PX2`]), at most [`MAX_STARTS`].
pub(crate) fn starts(all: &[Hypothesis]) -> Vec<&Hypothesis> {
    let best = all.first().map_or(0.0, |h| h.score);
    all.iter()
        .take_while(|h| h.score <= 2.0 * best + NEAR_SCORE_PX2)
        .take(MAX_STARTS)
        .collect()
}
