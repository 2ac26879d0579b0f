//! SVG to PNG with resvg (pure Rust: usvg parses, tiny-skia paints).
//!
//! Text needs fonts: the system font directories are scanned once per process and the generic
//! family `sans-serif` is mapped to "DejaVu Sans" (or, when that is missing, the first family
//! found), because resvg's built-in default ("Arial") is usually absent on Linux and text
//! would silently disappear. That family's faces are read into memory once (the drawing uses
//! no other family).

use std::sync::{Arc, OnceLock};

use resvg::tiny_skia::{Pixmap, Transform};
use resvg::usvg::{self, fontdb};

use crate::error::RenderError;

/// The family that `sans-serif` resolves to when it is installed.
pub const PREFERRED_SANS_FAMILY: &str = "DejaVu Sans";

/// Largest picture rasterised, pixels (a 1 GiB RGBA buffer).
pub const MAX_PIXELS: u64 = 1 << 28;

/// The system fonts, loaded on first use.
fn system_fonts() -> Arc<fontdb::Database> {
    static FONTS: OnceLock<Arc<fontdb::Database>> = OnceLock::new();
    Arc::clone(FONTS.get_or_init(|| {
        let mut db = fontdb::Database::new();
        db.load_system_fonts();
        let preferred = db
            .faces()
            .flat_map(|face| face.families.iter())
            .any(|(family, _)| family == PREFERRED_SANS_FAMILY);
        let sans = if preferred {
            Some(PREFERRED_SANS_FAMILY.to_owned())
        } else {
            db.faces()
                .flat_map(|face| face.families.iter())
                .map(|(family, _)| family.clone())
                .next()
        };
        let Some(family) = sans else {
            return Arc::new(db);
        };
        // Keep the chosen family's faces in memory: a database of file paths re-reads a
        // 0.7 MB font file for every glyph lookup, which dominated the run time of large maps.
        let mut in_memory = fontdb::Database::new();
        let mut loaded = std::collections::BTreeSet::new();
        for face in db.faces() {
            if !face.families.iter().any(|(f, _)| *f == family) {
                continue;
            }
            if let fontdb::Source::File(path) = &face.source
                && loaded.insert(path.clone())
                && let Ok(bytes) = std::fs::read(path)
            {
                in_memory.load_font_data(bytes);
            }
        }
        if in_memory.is_empty() {
            db.set_sans_serif_family(family);
            return Arc::new(db);
        }
        in_memory.set_sans_serif_family(family);
        Arc::new(in_memory)
    }))
}

/// Rasterise an SVG (e.g. from [`crate::floor_plan_svg`]) to PNG bytes at its own pixel size.
///
/// System fonts are loaded once per process; `sans-serif` maps to "DejaVu Sans" when it is
/// installed, else to the first family found.
///
/// # Errors
/// [`RenderError::Svg`] when the text is not an SVG resvg can read, [`RenderError::NoFonts`]
/// when the SVG has text but the system has no fonts, [`RenderError::ImageSize`] when the
/// picture is empty or larger than [`MAX_PIXELS`], [`RenderError::Rasterise`] when resvg fails
/// while painting, [`RenderError::Png`] when encoding fails.
///
/// # Example
/// ```
/// let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="20">
///   <rect width="40" height="20" fill="#fff"/><circle cx="10" cy="10" r="5"/></svg>"##;
/// let png = vpmap_render::svg_to_png(svg).unwrap();
/// assert_eq!(&png[1..4], b"PNG");
/// ```
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, RenderError> {
    let fonts = system_fonts();
    if fonts.is_empty() && svg.contains("<text") {
        return Err(RenderError::NoFonts);
    }
    let options = usvg::Options {
        font_family: PREFERRED_SANS_FAMILY.to_owned(),
        fontdb: fonts,
        ..usvg::Options::default()
    };
    let tree = usvg::Tree::from_str(svg, &options).map_err(|e| RenderError::Svg(e.to_string()))?;
    let size = tree.size().to_int_size();
    let too_large = RenderError::ImageSize {
        width: size.width(),
        height: size.height(),
    };
    if u64::from(size.width()) * u64::from(size.height()) > MAX_PIXELS {
        return Err(too_large);
    }
    let mut pixmap = Pixmap::new(size.width(), size.height()).ok_or(too_large)?;
    // resvg has arithmetic that overflows (a panic in debug builds) on coordinates beyond
    // `i32`; a foreign SVG must give an error, not bring the caller down.
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        resvg::render(&tree, Transform::identity(), &mut pixmap.as_mut());
    }))
    .map_err(|panic| {
        let reason = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        RenderError::Rasterise(reason)
    })?;
    pixmap
        .encode_png()
        .map_err(|e| RenderError::Png(e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn garbage_is_an_svg_error() {
        assert!(matches!(svg_to_png("not svg"), Err(RenderError::Svg(_))));
    }

    #[test]
    fn sans_serif_resolves_to_an_installed_family() {
        let db = system_fonts();
        if db.is_empty() {
            return;
        }
        let query = fontdb::Query {
            families: &[fontdb::Family::SansSerif],
            ..fontdb::Query::default()
        };
        assert!(db.query(&query).is_some());
    }
}
