//! One scene reader: scene JSON text to a validated [`Scene`], with a warning for every field
//! vpmap does not read (often a typo such as `scael`). `vpmap build` reads its scene file
//! through it and `/api/build` its request body; each caller reads its input within its own
//! size limit first (the command line's scene file limit, the page's body limit) and words the
//! errors its own way.

use vpmap_metrology::scene::Scene;

use crate::error::PipelineError;

/// A scene and the notes about it.
#[derive(Debug, Clone)]
pub struct ParsedScene {
    /// The scene, validated.
    pub scene: Scene,
    /// One line per unknown field: `unknown field "scael" is ignored (see
    /// docs/scene-format.md)`.
    pub warnings: Vec<String>,
}

/// Fields of a scene that vpmap does not read, one warning line each (see
/// [`ParsedScene::warnings`]).
#[must_use]
pub fn unknown_field_warnings(value: &serde_json::Value) -> Vec<String> {
    vpmap_metrology::scene::unknown_fields(value)
        .into_iter()
        .map(|field| format!("unknown field {field} is ignored (see docs/scene-format.md)"))
        .collect()
}

/// A scene from JSON text: it must start as a JSON object, parse as a JSON value (so that a
/// text nested deeper than serde_json's 128 levels is refused rather than read without
/// warnings), and be a valid scene.
///
/// # Errors
/// [`PipelineError::SceneNotAnObject`], [`PipelineError::SceneJson`] (with line and column),
/// or [`PipelineError::InvalidScene`] naming the field and value, with the unknown fields'
/// warnings.
///
/// # Example
/// ```
/// use vpmap_pipeline::scene::parse_scene;
/// let text = r#"{"version": 1, "scael": 2}"#;
/// let e = parse_scene(text).unwrap_err();
/// let vpmap_pipeline::PipelineError::InvalidScene { warnings, .. } = e else { panic!() };
/// assert_eq!(warnings, ["unknown field \"scael\" is ignored (see docs/scene-format.md)"]);
/// assert!(parse_scene("[1]").is_err());
/// ```
pub fn parse_scene(text: &str) -> Result<ParsedScene, PipelineError> {
    if !text.trim_start().starts_with('{') {
        return Err(PipelineError::SceneNotAnObject);
    }
    let value: serde_json::Value = serde_json::from_str(text).map_err(PipelineError::SceneJson)?;
    let warnings = unknown_field_warnings(&value);
    match Scene::from_json_str(text) {
        Ok(scene) => Ok(ParsedScene { scene, warnings }),
        Err(error) => Err(PipelineError::InvalidScene { error, warnings }),
    }
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
        let w = unknown_field_warnings(&v);
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[0].contains("\"scael\""));
        assert!(w[1].contains("objects[0].\"heigth\""));
        assert!(w[2].contains("scale.\"meter\""));
    }

    #[test]
    fn texts_that_are_not_scenes_say_at_which_stage() {
        assert!(matches!(
            parse_scene(" [1]"),
            Err(PipelineError::SceneNotAnObject)
        ));
        assert!(matches!(
            parse_scene("{\"version\": "),
            Err(PipelineError::SceneJson(_))
        ));
        let office = include_str!("../../../examples/office.json");
        let parsed = parse_scene(office).unwrap();
        assert!(parsed.warnings.is_empty() && !parsed.scene.objects.is_empty());
    }
}
