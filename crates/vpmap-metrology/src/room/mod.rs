//! The whole room from a few photos: one joint fit of every photo's camera and every
//! object, with error bars across the photos.
//!
//! Model (`room/model.rs`): each photo's camera as in [`crate::fit`] (focal length, pitch,
//! roll, room yaw, the principal point where its vanishing points fix it), and for photos
//! after the first its station point and height on the floor of the first photo's map frame;
//! the heading follows from the shared room directions and a quarter turn. Each object once,
//! in that frame, fitted to its clicks in every photo that shows it. Objective: the sum of
//! squared reprojection errors of every click and vanishing-point segment of every photo,
//! the maximum-likelihood estimate under independent Gaussian click noise; minimised by the
//! same sparse Levenberg-Marquardt (the cameras are one block, each object another).
//!
//! Start (`room/hypotheses.rs`, `room/align.rs`): each photo fitted alone; every whole-room
//! hypothesis (a quarter turn per photo) scored by one linear least-squares placement of every
//! shared corner and height, independent of the photos' order; the joint fit started from the
//! best few, the most likely kept. Ties between hypotheses that fit about equally are broken by
//! physical checks (`room/checks.rs`), and said (a warning, `alternatives`) when they remain;
//! placements that fit exactly as well (to the costs' numerical noise) by a key of the
//! placement that no order of photos 2..n changes (`room/canonical.rs`);
//! a room whose joint fit is far worse than its photos alone is refused
//! (`room/consistency.rs`). Error bars (`room/uncertainty.rs`): the covariance of the whole
//! fit, propagated as for one photo.
//!
//! Lens distortion (`room/lens.rs`): the joint fit again with one photo's clicks undistorted
//! by another `k`, the chosen placement held, for the map's error bars to carry each photo's
//! `k_sd` as a consider parameter (as [`crate::map::build_map`] does for one photo).
//!
//! Files: `model`, then `canonical`, `align` and `hypotheses`, then `fit` (with `choose`,
//! which uses `checks` and `consistency`), then `uncertainty` and `lens`.

mod align;
mod canonical;
mod checks;
mod choose;
mod consistency;
mod fit;
mod hypotheses;
mod lens;
mod model;
mod prior;
mod uncertainty;

pub use consistency::LEVEL as CONSISTENCY_LEVEL;
pub use fit::{
    FittedPhoto, MAX_ROOM_SIGHTINGS, RoomAlternative, RoomFitted, fit_room, fit_room_until,
};
pub use uncertainty::{PhotoUncertainty, RoomUncertainty};
