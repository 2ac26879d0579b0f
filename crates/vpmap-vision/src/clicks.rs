//! Every clicked point of a scene, named by its field path.
//!
//! A scene's clicks are the box corners (`objects[i].base.<corner>`, `objects[i].top.<corner>`),
//! footprint vertices (`objects[i].footprint[k]`), footprint tops (`objects[i].top.point`) and
//! floor corners (`floor[k]`), the paths the scene reader's error messages use and the keys of
//! the scene's `click_covariances_px2` table (`docs/scene-format.md`). Vanishing-point segments
//! are not clicks here: they are not corners.

use vpmap_metrology::scene::{BoxCorner, PixelPoint, Scene};

/// Where a clicked point sits in a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClickPlace {
    /// A box corner: object index, which vertical edge, at the top (else at the base).
    BoxCorner {
        /// Index into `objects`.
        object: usize,
        /// Which vertical edge of the box.
        corner: BoxCorner,
        /// At the top of the edge (else at its floor end).
        top: bool,
    },
    /// A footprint object's base vertex.
    FootprintVertex {
        /// Index into `objects`.
        object: usize,
        /// Index into its `footprint`.
        vertex: usize,
    },
    /// A footprint object's top point (`top.point`, above vertex `above`).
    FootprintTop {
        /// Index into `objects`.
        object: usize,
        /// The footprint vertex below it.
        above: usize,
    },
    /// A floor outline corner.
    Floor {
        /// Index into `floor`.
        index: usize,
    },
}

impl ClickPlace {
    /// The field path, e.g. `objects[0].base.near`, `floor[3]`.
    #[must_use]
    pub fn field(&self) -> String {
        match *self {
            Self::BoxCorner {
                object,
                corner,
                top,
            } => format!(
                "objects[{object}].{}.{}",
                if top { "top" } else { "base" },
                corner.name()
            ),
            Self::FootprintVertex { object, vertex } => {
                format!("objects[{object}].footprint[{vertex}]")
            }
            Self::FootprintTop { object, .. } => format!("objects[{object}].top.point"),
            Self::Floor { index } => format!("floor[{index}]"),
        }
    }

    /// The same place's point in a scene's JSON value, mutably (`None` when the value does
    /// not hold it).
    pub fn point_in_json<'a>(
        &self,
        scene: &'a mut serde_json::Value,
    ) -> Option<&'a mut serde_json::Value> {
        match *self {
            Self::BoxCorner {
                object,
                corner,
                top,
            } => scene
                .get_mut("objects")?
                .get_mut(object)?
                .get_mut(if top { "top" } else { "base" })?
                .get_mut(corner.name()),
            Self::FootprintVertex { object, vertex } => scene
                .get_mut("objects")?
                .get_mut(object)?
                .get_mut("footprint")?
                .get_mut(vertex),
            Self::FootprintTop { object, .. } => scene
                .get_mut("objects")?
                .get_mut(object)?
                .get_mut("top")?
                .get_mut("point"),
            Self::Floor { index } => scene.get_mut("floor")?.get_mut(index),
        }
    }
}

/// One clicked point of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneClick {
    /// Where it sits.
    pub place: ClickPlace,
    /// The point, pixels.
    pub point_px: PixelPoint,
}

impl SceneClick {
    /// The field path ([`ClickPlace::field`]).
    #[must_use]
    pub fn field(&self) -> String {
        self.place.field()
    }
}

/// Every clicked point of a scene in file order: per object its base corners, top corners
/// (both in [`BoxCorner::ALL`] order), footprint vertices and top point; then the floor.
#[must_use]
pub fn scene_clicks(scene: &Scene) -> Vec<SceneClick> {
    let mut out = Vec::new();
    for (object, o) in scene.objects.iter().enumerate() {
        if let Some(base) = &o.base {
            for (corner, p) in base.given() {
                out.push(SceneClick {
                    place: ClickPlace::BoxCorner {
                        object,
                        corner,
                        top: false,
                    },
                    point_px: p,
                });
            }
        }
        if let Some(top) = &o.top {
            for (corner, p) in top.corners.given() {
                out.push(SceneClick {
                    place: ClickPlace::BoxCorner {
                        object,
                        corner,
                        top: true,
                    },
                    point_px: p,
                });
            }
        }
        if let Some(fp) = &o.footprint {
            for (vertex, p) in fp.iter().enumerate() {
                out.push(SceneClick {
                    place: ClickPlace::FootprintVertex { object, vertex },
                    point_px: *p,
                });
            }
        }
        if let Some(top) = &o.top
            && let Some(p) = top.point
        {
            out.push(SceneClick {
                place: ClickPlace::FootprintTop {
                    object,
                    above: top.above.unwrap_or(0),
                },
                point_px: p,
            });
        }
    }
    for (index, p) in scene.floor.iter().enumerate() {
        out.push(SceneClick {
            place: ClickPlace::Floor { index },
            point_px: *p,
        });
    }
    out
}

/// Move one click of a scene (the typed scene, as [`scene_clicks`] names it). Returns whether
/// the scene holds that click.
pub fn set_scene_click(scene: &mut Scene, place: ClickPlace, point_px: PixelPoint) -> bool {
    let slot: Option<&mut PixelPoint> = match place {
        ClickPlace::BoxCorner {
            object,
            corner,
            top,
        } => scene.objects.get_mut(object).and_then(|o| {
            if top {
                o.top
                    .as_mut()
                    .and_then(|t| t.corners.get_mut(corner).as_mut())
            } else {
                o.base.as_mut().and_then(|b| b.get_mut(corner).as_mut())
            }
        }),
        ClickPlace::FootprintVertex { object, vertex } => scene
            .objects
            .get_mut(object)
            .and_then(|o| o.footprint.as_mut())
            .and_then(|f| f.get_mut(vertex)),
        ClickPlace::FootprintTop { object, .. } => scene
            .objects
            .get_mut(object)
            .and_then(|o| o.top.as_mut())
            .and_then(|t| t.point.as_mut()),
        ClickPlace::Floor { index } => scene.floor.get_mut(index),
    };
    match slot {
        Some(p) => {
            *p = point_px;
            true
        }
        None => false,
    }
}

#[cfg(test)]
#[allow(clippy::float_cmp)]
mod tests {
    use super::*;
    use vpmap_metrology::synth::{SynthOptions, synthesize};

    #[test]
    fn every_click_is_named_and_found_in_the_json() {
        let Ok((scene, _)) = synthesize(&SynthOptions::default()) else {
            panic!("synthesize failed");
        };
        let clicks = scene_clicks(&scene);
        // 4 boxes x (3 base + 2 top) + 5 footprint vertices + 1 top + the floor.
        assert_eq!(clicks.len(), 4 * 5 + 5 + 1 + scene.floor.len());
        assert_eq!(clicks[0].field(), "objects[0].base.near");
        let mut value = serde_json::to_value(&scene).unwrap_or_default();
        for c in &clicks {
            let found = c.place.point_in_json(&mut value).cloned();
            let expected = serde_json::json!(c.point_px);
            assert_eq!(found, Some(expected), "{}", c.field());
        }
        let mut moved = scene.clone();
        for c in &clicks {
            assert!(set_scene_click(&mut moved, c.place, [1.0, 2.0]));
        }
        assert!(
            scene_clicks(&moved)
                .iter()
                .all(|c| c.point_px == [1.0, 2.0])
        );
    }
}
