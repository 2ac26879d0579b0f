//! Scenes from request bodies, and the build options of a request; the map, grid and
//! pictures are built by `vpmap_pipeline`, as `vpmap build` builds them.

use vpmap_metrology::reconstruct::Method;
use vpmap_pipeline::{MapOptions, ParsedScene, PipelineError};

use crate::error::ApiError;
use crate::params::{Query, parse_number};

/// Most cells in an occupancy grid (2000 x 2000).
pub const MAX_GRID_CELLS: f64 = 4e6;

/// The query parameters `/api/build` reads.
pub const BUILD_QUERY: [&str; 5] = [
    "method",
    "resolution",
    "robot_radius",
    "hidden_free",
    "click_sigma",
];

/// Largest click noise the web API accepts, pixels (1 sigma per coordinate); the smallest is
/// anything above 0.
pub const MAX_CLICK_SIGMA_PX: f64 = 100.0;

/// A click noise in pixels, checked: `0 < sigma <= MAX_CLICK_SIGMA_PX`.
///
/// # Errors
/// A value out of that range (NaN included).
pub fn click_sigma(sigma: f64) -> Result<f64, ApiError> {
    if sigma > 0.0 && sigma <= MAX_CLICK_SIGMA_PX {
        Ok(sigma)
    } else {
        Err(ApiError::bad_request(format!(
            "click_sigma is {sigma}; give the noise of the clicked points in pixels (1 sigma), more than 0 and at most {MAX_CLICK_SIGMA_PX}, or leave it out to estimate it from the fit"
        )))
    }
}

/// Build options from a request's values, `None` where the request gives none (the
/// pipeline's default), with the web API's grid limit ([`MAX_GRID_CELLS`]), checked.
/// `click_sigma` is the click noise of the fit's error bars, pixels (method `fit` only;
/// `None`: estimated from the residuals, else 1 px).
///
/// # Errors
/// An unknown method, or a value out of range ([`MapOptions::validate`], [`click_sigma`]).
pub fn map_options(
    method: Option<&str>,
    resolution: Option<f64>,
    robot_radius: Option<f64>,
    hidden_free: Option<bool>,
    click_sigma_px: Option<f64>,
) -> Result<MapOptions, ApiError> {
    let d = MapOptions::default();
    let method = match method {
        None => d.method,
        Some(m) => m.parse::<Method>().map_err(|_| {
            ApiError::bad_request(format!("method is {m:?}; use fit, sideview or projective"))
        })?,
    };
    let options = MapOptions {
        method,
        resolution_m: resolution.unwrap_or(d.resolution_m),
        robot_radius_m: robot_radius.unwrap_or(d.robot_radius_m),
        hidden_free: hidden_free.unwrap_or(d.hidden_free),
        max_grid_cells: Some(MAX_GRID_CELLS),
        click_sigma_px: match click_sigma_px {
            Some(s) => Some(click_sigma(s)?),
            None => d.click_sigma_px,
        },
        grow_confidence: d.grow_confidence,
    };
    options.validate().map_err(pipeline_error)?;
    Ok(options)
}

/// Build options from `/api/build`'s query string.
///
/// # Errors
/// An unknown or repeated parameter, or a value out of range.
pub fn map_options_from_query(raw: Option<&str>) -> Result<MapOptions, ApiError> {
    let q = Query::parse(raw, &BUILD_QUERY)?;
    let d = MapOptions::default();
    map_options(
        q.get("method"),
        Some(q.number("resolution", d.resolution_m)?),
        Some(q.number("robot_radius", d.robot_radius_m)?),
        Some(q.flag("hidden_free", d.hidden_free)?),
        q.get("click_sigma")
            .map(|v| parse_number("click_sigma", v))
            .transpose()?,
    )
}

/// A pipeline failure as a 400 answer, saying which stage failed.
pub fn pipeline_error(e: PipelineError) -> ApiError {
    match e {
        PipelineError::Map(e) => ApiError::bad_request(format!("scene: {e}")),
        PipelineError::Model(e) => ApiError::bad_request(format!("cannot build the 3D model: {e}")),
        PipelineError::Grid(e) => ApiError::bad_request(format!("occupancy grid: {e}")),
        e => ApiError::bad_request(e.to_string()),
    }
}

/// A scene from JSON text (the body of `/api/build`), read by the pipeline's one scene
/// reader ([`vpmap_pipeline::parse_scene`]) in the page's words.
///
/// # Errors
/// Not a JSON object, malformed (with line and column), or an invalid scene (naming the field
/// and value).
pub fn scene_from_text(text: &str) -> Result<ParsedScene, ApiError> {
    vpmap_pipeline::parse_scene(text).map_err(|e| match e {
        PipelineError::SceneNotAnObject => ApiError::bad_request(
            "the body is not a scene: it must be a JSON object ({ ... }), see docs/scene-format.md",
        ),
        PipelineError::SceneJson(e) => {
            ApiError::bad_request(format!("the body is not valid JSON: {e}"))
        }
        PipelineError::InvalidScene { error, .. } => {
            ApiError::bad_request(format!("scene: {error}"))
        }
        other => pipeline_error(other),
    })
}

/// A scene from a JSON value (the `scene` field of `/api/plan`): a single-photo scene or a
/// room file.
///
/// # Errors
/// As [`scene_from_text`].
pub fn scene_from_value(value: &serde_json::Value) -> Result<ParsedScene, ApiError> {
    if !value.is_object() {
        return Err(ApiError::bad_request(
            "field `scene` must be a scene JSON object ({ ... }), see docs/scene-format.md",
        ));
    }
    // Through the one scene reader, so that a room file is read as `/api/build` reads it.
    scene_from_text(&value.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parameters_are_range_checked() {
        let ok = map_options(Some("sideview"), Some(0.05), None, None, None);
        assert!(ok.is_ok_and(
            |o| o.robot_radius_m.to_bits() == 0.2f64.to_bits() && o.max_grid_cells.is_some()
        ));
        assert!(map_options(Some("side"), None, None, None, None).is_err());
        let e = map_options(None, Some(0.0), None, None, None).err();
        assert!(e.is_some_and(|e| e.message.starts_with("resolution is 0;")));
        let e = map_options(None, None, Some(-1.0), None, None).err();
        assert!(e.is_some_and(|e| e.message.starts_with("robot_radius is -1;")));
        let fit = map_options(Some("fit"), None, None, None, Some(1.5));
        assert!(fit.is_ok_and(|o| o.method == Method::Fit && o.click_sigma_px == Some(1.5)));
        assert!(map_options(None, None, None, None, Some(100.0)).is_ok());
        for bad in [0.0, -1.0, 100.5, f64::NAN] {
            let e = map_options(None, None, None, None, Some(bad)).err();
            assert!(
                e.is_some_and(|e| e.message.starts_with("click_sigma is ")
                    && e.message.contains("at most 100")),
                "{bad}"
            );
        }
        let q = map_options_from_query(Some("click_sigma=2&method=fit"));
        assert!(q.is_ok_and(|o| o.click_sigma_px == Some(2.0)));
        let e = map_options_from_query(Some("click_sigma=px")).err();
        assert!(e.is_some_and(|e| e.message.contains("not a finite number")));
    }
}
