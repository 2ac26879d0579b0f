//! Scenes from request bodies, and the map, grid and pictures built from them (as
//! `vpmap build` does: `crates/vpmap-cli/src/build.rs`).

use vpmap_metrology::map::{BuildOptions, FloorMap, Units, build_map};
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::Scene;
use vpmap_plan::grid::OccupancyGrid;
use vpmap_plan::raster::{RasterOptions, rasterize_map};

use crate::ApiError;
use crate::params::Query;

/// Most objects in a scene.
pub const MAX_OBJECTS: usize = 500;
/// Most points in one footprint, in the floor outline, and segments per vanishing point.
pub const MAX_POINTS: usize = 1000;
/// Most cells in an occupancy grid (2000 x 2000).
pub const MAX_GRID_CELLS: f64 = 4e6;
/// Accepted resolutions, map units per cell.
const RESOLUTION_RANGE: std::ops::RangeInclusive<f64> = 0.001..=100.0;
/// Largest robot radius, map units.
const MAX_ROBOT_RADIUS: f64 = 1000.0;
/// Unknown border around the map in the grid, map units (as `vpmap build`).
const GRID_MARGIN: f64 = 0.5;

/// A scene and the notes about it (unknown fields).
pub struct ParsedScene {
    /// The scene, validated.
    pub scene: Scene,
    /// One line per unknown field.
    pub warnings: Vec<String>,
}

/// How to build: the query parameters of `/api/build`, the fields of `/api/plan`.
#[derive(Clone, Copy, Debug)]
pub struct BuildParams {
    /// Reconstruction method.
    pub method: Method,
    /// Grid cell side, map units.
    pub resolution: f64,
    /// Obstacle inflation, map units.
    pub robot_radius: f64,
    /// Floor hidden behind objects is free (default unknown).
    pub hidden_free: bool,
}

impl Default for BuildParams {
    fn default() -> Self {
        Self {
            method: Method::Sideview,
            resolution: 0.05,
            robot_radius: 0.2,
            hidden_free: false,
        }
    }
}

/// The query parameters `/api/build` reads.
pub const BUILD_QUERY: [&str; 4] = ["method", "resolution", "robot_radius", "hidden_free"];

impl BuildParams {
    /// From `/api/build`'s query string.
    ///
    /// # Errors
    /// An unknown or repeated parameter, or a value out of range.
    pub fn from_query(raw: Option<&str>) -> Result<Self, ApiError> {
        let q = Query::parse(raw, &BUILD_QUERY)?;
        let d = Self::default();
        Self::checked(
            q.get("method"),
            q.number("resolution", d.resolution)?,
            q.number("robot_radius", d.robot_radius)?,
            q.flag("hidden_free", d.hidden_free)?,
        )
    }

    /// From values given (defaults already applied).
    ///
    /// # Errors
    /// A value out of range.
    pub fn checked(
        method: Option<&str>,
        resolution: f64,
        robot_radius: f64,
        hidden_free: bool,
    ) -> Result<Self, ApiError> {
        let method = match method {
            None => Method::Sideview,
            Some(m) => m.parse().map_err(|_| {
                ApiError::bad_request(format!("method is {m:?}; use sideview or projective"))
            })?,
        };
        if !(resolution.is_finite() && RESOLUTION_RANGE.contains(&resolution)) {
            return Err(ApiError::bad_request(format!(
                "resolution is {resolution}; it must be from {} to {} (metres per cell)",
                RESOLUTION_RANGE.start(),
                RESOLUTION_RANGE.end()
            )));
        }
        if !(robot_radius.is_finite() && (0.0..=MAX_ROBOT_RADIUS).contains(&robot_radius)) {
            return Err(ApiError::bad_request(format!(
                "robot_radius is {robot_radius}; it must be from 0 to {MAX_ROBOT_RADIUS} (metres)"
            )));
        }
        Ok(Self {
            method,
            resolution,
            robot_radius,
            hidden_free,
        })
    }
}

/// Fields of a scene that vpmap does not read (often typos such as `scael`), as warnings.
fn unknown_fields(value: &serde_json::Value) -> Vec<String> {
    vpmap_metrology::scene::unknown_fields(value)
        .into_iter()
        .map(|field| format!("unknown field {field} is ignored (see docs/scene-format.md)"))
        .collect()
}

/// Refuse scenes too large to build quickly.
fn check_size(scene: &Scene) -> Result<(), ApiError> {
    let too_many = |what: String, n: usize, max: usize| {
        ApiError::bad_request(format!(
            "{what} has {n} entries; the web API accepts at most {max}"
        ))
    };
    if scene.objects.len() > MAX_OBJECTS {
        return Err(too_many(
            "scene field `objects`".to_owned(),
            scene.objects.len(),
            MAX_OBJECTS,
        ));
    }
    if scene.floor.len() > MAX_POINTS {
        return Err(too_many(
            "scene field `floor`".to_owned(),
            scene.floor.len(),
            MAX_POINTS,
        ));
    }
    for (i, o) in scene.objects.iter().enumerate() {
        if let Some(fp) = &o.footprint
            && fp.len() > MAX_POINTS
        {
            return Err(too_many(
                format!("scene field `objects[{i}].footprint`"),
                fp.len(),
                MAX_POINTS,
            ));
        }
    }
    for (i, v) in scene.vanishing_points.iter().enumerate() {
        if v.lines.len() > MAX_POINTS {
            return Err(too_many(
                format!("scene field `vanishing_points[{i}].lines`"),
                v.lines.len(),
                MAX_POINTS,
            ));
        }
    }
    Ok(())
}

/// A scene from JSON text (the body of `/api/build`).
///
/// # Errors
/// Not a JSON object, malformed (with line and column), or an invalid scene (naming the field
/// and value).
pub fn scene_from_text(text: &str) -> Result<ParsedScene, ApiError> {
    if !text.trim_start().starts_with('{') {
        return Err(ApiError::bad_request(
            "the body is not a scene: it must be a JSON object ({ ... }), see docs/scene-format.md",
        ));
    }
    let value: serde_json::Value = serde_json::from_str(text)
        .map_err(|e| ApiError::bad_request(format!("the body is not valid JSON: {e}")))?;
    let scene =
        Scene::from_json_str(text).map_err(|e| ApiError::bad_request(format!("scene: {e}")))?;
    check_size(&scene)?;
    Ok(ParsedScene {
        scene,
        warnings: unknown_fields(&value),
    })
}

/// A scene from a JSON value (the `scene` field of `/api/plan`).
///
/// # Errors
/// As [`scene_from_text`].
pub fn scene_from_value(value: &serde_json::Value) -> Result<ParsedScene, ApiError> {
    if !value.is_object() {
        return Err(ApiError::bad_request(
            "field `scene` must be a scene JSON object ({ ... }), see docs/scene-format.md",
        ));
    }
    let scene: Scene = serde_json::from_value(value.clone())
        .map_err(|e| ApiError::bad_request(format!("scene: {e}")))?;
    scene
        .validate()
        .map_err(|e| ApiError::bad_request(format!("scene: {e}")))?;
    check_size(&scene)?;
    Ok(ParsedScene {
        scene,
        warnings: unknown_fields(value),
    })
}

/// `"m"` or `"camera_heights"`.
pub fn units_name(units: Units) -> &'static str {
    match units {
        Units::Meters => "m",
        Units::CameraHeights => "camera_heights",
    }
}

/// The floor map of a scene.
///
/// # Errors
/// The scene's calibration, reconstruction or scale fails (naming the field and value).
pub fn map_of(scene: &Scene, params: &BuildParams) -> Result<FloorMap, ApiError> {
    build_map(
        scene,
        &BuildOptions {
            method: params.method,
        },
    )
    .map_err(|e| ApiError::bad_request(format!("scene: {e}")))
}

/// The occupancy grid of a map, as `vpmap build` rasterises it; refused beyond
/// [`MAX_GRID_CELLS`].
///
/// # Errors
/// The grid would be too large, or the map cannot be rasterised.
pub fn grid_of(map: &FloorMap, params: &BuildParams) -> Result<OccupancyGrid, ApiError> {
    let (mut lo, mut hi) = map.bounds();
    for p in map.free_space.iter().flat_map(|p| &p.exterior) {
        for axis in 0..2 {
            lo[axis] = lo[axis].min(p[axis]);
            hi[axis] = hi[axis].max(p[axis]);
        }
    }
    let cells_along =
        |axis: usize| ((hi[axis] - lo[axis] + 2.0 * GRID_MARGIN) / params.resolution).ceil() + 1.0;
    let (w, h) = (cells_along(0), cells_along(1));
    let cells = w * h;
    if cells.is_nan() || cells > MAX_GRID_CELLS {
        return Err(ApiError::bad_request(format!(
            "resolution {} gives an occupancy grid of about {w:.0} x {h:.0} cells for this map ({:.1} x {:.1} {}); the web API's limit is {MAX_GRID_CELLS:.0} cells: use a coarser resolution",
            params.resolution,
            hi[0] - lo[0],
            hi[1] - lo[1],
            units_name(map.units)
        )));
    }
    rasterize_map(
        map,
        &RasterOptions {
            resolution_m: params.resolution,
            robot_radius_m: params.robot_radius,
            hidden_free: params.hidden_free,
            margin_m: GRID_MARGIN,
        },
    )
    .map_err(|e| ApiError::bad_request(format!("occupancy grid: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_fields_are_named() {
        let v: serde_json::Value = serde_json::from_str(
            r#"{"version": 1, "scael": {}, "objects": [{"name": "a", "heigth": 2}], "scale": {"meter": 1}}"#,
        )
        .unwrap_or_default();
        let w = unknown_fields(&v);
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[0].contains("\"scael\""));
        assert!(w[1].contains("objects[0].\"heigth\""));
        assert!(w[2].contains("scale.\"meter\""));
    }

    #[test]
    fn parameters_are_range_checked() {
        assert!(BuildParams::checked(Some("sideview"), 0.05, 0.2, false).is_ok());
        assert!(BuildParams::checked(Some("side"), 0.05, 0.2, false).is_err());
        assert!(BuildParams::checked(None, 0.0, 0.2, false).is_err());
        assert!(BuildParams::checked(None, 0.05, -1.0, false).is_err());
    }
}
