//! A room of several photos: the room file (`{"version": 1, "photos": [SCENE, ...]}`), read
//! into its first photo's [`Scene`] with the others in [`Scene::other_photos`], and the checks
//! that tie the photos into one room (each object one kind, every photo tied to the first
//! through objects named in both).

use serde::{Deserialize, Serialize};

use super::types::{ObjectShape, Scene};
use crate::error::{MetrologyError, Result};

/// Most photos a room file may have: the joint fit's camera block grows with them.
pub const MAX_PHOTOS: usize = 16;

/// A room file as it is written.
#[derive(Debug, Deserialize, Serialize)]
pub(super) struct RoomFile {
    /// Format version; must be 1.
    pub version: u64,
    /// The photos, each a single-photo scene.
    pub photos: Vec<Scene>,
}

impl RoomFile {
    /// The room as one scene: the first photo with the others in `other_photos`.
    pub(super) fn into_scene(self) -> Result<Scene> {
        if self.version != 1 {
            return Err(MetrologyError::UnsupportedVersion {
                file: "room",
                version: self.version,
            });
        }
        let mut photos = self.photos.into_iter();
        let Some(mut first) = photos.next() else {
            return Err(MetrologyError::InvalidField {
                field: "photos".to_owned(),
                reason: "is empty: a room file needs at least one photo".to_owned(),
            });
        };
        first.other_photos = photos.collect();
        Ok(first)
    }
}

/// Whether a JSON object is a room file (it has `photos`) rather than a single-photo scene.
pub(super) fn is_room_value(value: &serde_json::Value) -> bool {
    value.get("photos").is_some()
}

/// An object's kind in one photo, for the message naming a mismatch.
fn kind_name(scene: &Scene, index: usize) -> &'static str {
    match scene.objects[index].shape(index) {
        Ok(ObjectShape::Box { .. }) => "a box",
        Ok(ObjectShape::Footprint { .. }) => "a footprint",
        Err(_) => "invalid",
    }
}

impl Scene {
    /// Every photo of the room, the first (this scene) first; one photo for a single-photo
    /// scene.
    pub fn photos(&self) -> impl Iterator<Item = &Scene> {
        std::iter::once(self).chain(self.other_photos.iter())
    }

    /// Photo `n` of the room (0 is this scene itself, as in [`Scene::photos`]), to change;
    /// `None` beyond the last.
    pub fn photo_mut(&mut self, n: usize) -> Option<&mut Scene> {
        match n {
            0 => Some(self),
            _ => self.other_photos.get_mut(n - 1),
        }
    }

    /// Number of photos: 1 for a single-photo scene.
    #[must_use]
    pub fn photo_count(&self) -> usize {
        1 + self.other_photos.len()
    }

    /// The room as a room file's JSON value (`{"version": 1, "photos": [...]}`).
    pub(super) fn room_file(&self) -> RoomFile {
        RoomFile {
            version: 1,
            photos: self
                .photos()
                .map(|p| Scene {
                    other_photos: Vec::new(),
                    ..p.clone()
                })
                .collect(),
        }
    }

    /// The checks that tie several photos into one room, after each photo passed its own:
    /// at most [`MAX_PHOTOS`] photos, no photo inside a photo, an object the same kind (and a
    /// footprint the same number of vertices) in every photo that shows it, and every photo
    /// tied to the first through objects named in both (directly or through other photos).
    pub(super) fn validate_room(&self) -> Result<()> {
        let n = self.photo_count();
        if n > MAX_PHOTOS {
            return Err(MetrologyError::InvalidField {
                field: "photos".to_owned(),
                reason: format!("it has {n} entries; a room may have at most {MAX_PHOTOS}"),
            });
        }
        let photos: Vec<&Scene> = self.photos().collect();
        for (k, p) in photos.iter().enumerate().skip(1) {
            if !p.other_photos.is_empty() {
                return Err(MetrologyError::InvalidField {
                    field: format!("photos[{k}]"),
                    reason: "holds photos of its own; a room's photos are single-photo scenes"
                        .to_owned(),
                });
            }
        }
        self.validate_placement_pins()?;
        // Each name: its kind and vertex count where first seen.
        let mut first_seen: std::collections::BTreeMap<&str, (usize, usize)> =
            std::collections::BTreeMap::new();
        for (k, p) in photos.iter().enumerate() {
            for (i, o) in p.objects.iter().enumerate() {
                let Some(&(q, j)) = first_seen.get(o.name.as_str()) else {
                    first_seen.insert(o.name.as_str(), (k, i));
                    continue;
                };
                let (a, b) = (kind_name(photos[q], j), kind_name(p, i));
                if a != b {
                    return Err(MetrologyError::InvalidField {
                        field: format!("photos[{k}].objects[{i}]"),
                        reason: format!(
                            "object {:?} is {a} in photo {} and {b} in photo {}: an object seen in several photos must be annotated the same way in each (or named apart)",
                            o.name,
                            q + 1,
                            k + 1
                        ),
                    });
                }
                let vertices =
                    |s: &Scene, idx: usize| s.objects[idx].footprint.as_ref().map(Vec::len);
                if let (Some(va), Some(vb)) = (vertices(photos[q], j), vertices(p, i))
                    && va != vb
                {
                    return Err(MetrologyError::InvalidField {
                        field: format!("photos[{k}].objects[{i}].footprint"),
                        reason: format!(
                            "object {:?} has {va} vertices in photo {} and {vb} in photo {}: a footprint seen in several photos must be clicked at the same corners in each",
                            o.name,
                            q + 1,
                            k + 1
                        ),
                    });
                }
            }
        }
        let untied = untied_photos(&photos);
        if !untied.is_empty() {
            let list: Vec<String> = untied.iter().map(|k| format!("photo {}", k + 1)).collect();
            let tied: Vec<String> = (0..n)
                .filter(|k| !untied.contains(k))
                .map(|k| format!("photo {}", k + 1))
                .collect();
            let example = photos[untied[0]]
                .objects
                .first()
                .map_or_else(String::new, |o| format!(" (e.g. {:?})", o.name));
            return Err(MetrologyError::InvalidField {
                field: format!("photos[{}]", untied[0]),
                reason: format!(
                    "{} {} not tied to photo 1: no object is named the same in {} and in {}; annotate an object that both show in both, under one name{example}",
                    list.join(", "),
                    if untied.len() == 1 { "is" } else { "are" },
                    if untied.len() == 1 { "it" } else { "them" },
                    tied.join(" or ")
                ),
            });
        }
        Ok(())
    }
}

/// The placement turns a room's photos may be pinned to ([`Scene::placement_turn_deg`]).
pub const PLACEMENT_TURNS_DEG: [i64; 4] = [0, 90, 180, 270];

impl Scene {
    /// Each photo's `placement_turn_deg`: photos 2..n of a room only, one of
    /// [`PLACEMENT_TURNS_DEG`].
    pub(super) fn validate_placement_pins(&self) -> Result<()> {
        if self.other_photos.is_empty() {
            return match self.placement_turn_deg {
                Some(v) => Err(MetrologyError::InvalidField {
                    field: "placement_turn_deg".to_owned(),
                    reason: format!(
                        "{v} pins a photo of a room, but this is a single-photo scene: `placement_turn_deg` pins photos 2..n of a room file"
                    ),
                }),
                None => Ok(()),
            };
        }
        for (k, p) in self.photos().enumerate() {
            let Some(v) = p.placement_turn_deg else {
                continue;
            };
            if k == 0 {
                return Err(MetrologyError::InvalidField {
                    field: "photos[0].placement_turn_deg".to_owned(),
                    reason: format!(
                        "{v} pins photo 1, but photo 1 sets the room's frame and cannot be turned: pin photos 2..n only"
                    ),
                });
            }
            if !PLACEMENT_TURNS_DEG.contains(&v) {
                return Err(MetrologyError::InvalidField {
                    field: format!("photos[{k}].placement_turn_deg"),
                    reason: format!(
                        "{v} is not a quarter turn: photo {}'s placement turn must be 0, 90, 180 or 270 degrees (as the map's `alternatives` give it)",
                        k + 1
                    ),
                });
            }
        }
        Ok(())
    }

    /// Each photo's pinned quarter turn (`placement_turn_deg / 90`), `None` where the room fit
    /// chooses; photo 1 is never pinned.
    #[must_use]
    pub(crate) fn placement_pins(&self) -> Vec<Option<u8>> {
        self.photos()
            .enumerate()
            .map(|(k, p)| {
                p.placement_turn_deg
                    .filter(|_| k > 0)
                    .and_then(|v| u8::try_from(v.rem_euclid(360) / 90).ok())
            })
            .collect()
    }
}

/// The photos no chain of shared object names ties to the first, in order.
fn untied_photos(photos: &[&Scene]) -> Vec<usize> {
    let names = |s: &Scene| -> std::collections::BTreeSet<String> {
        s.objects.iter().map(|o| o.name.clone()).collect()
    };
    let sets: Vec<_> = photos.iter().map(|p| names(p)).collect();
    let mut tied = vec![false; photos.len()];
    let mut queue = vec![0];
    tied[0] = true;
    while let Some(a) = queue.pop() {
        for b in 0..photos.len() {
            if !tied[b] && !sets[a].is_disjoint(&sets[b]) {
                tied[b] = true;
                queue.push(b);
            }
        }
    }
    (0..photos.len()).filter(|&k| !tied[k]).collect()
}
