//! XML text: escaping, and the map-to-picture transform every picture carries on its root
//! element ([`SVG_FROM_MAP_ATTRIBUTE`]).

/// The root element's attribute holding the transform from map coordinates (`+x` right,
/// `+y` up, map units) to the SVG's user units, as six numbers `a b c d e f` in SVG
/// `matrix()` order: `x_svg = a x + c y + e`, `y_svg = b x + d y + f`. Written on every
/// floor plan ([`floor_plan_svg`](crate::floor_plan_svg)) and plan picture ([`crate::plan_svg()`]), so that a reader
/// (the web page) places map points on the picture without fitting it.
pub const SVG_FROM_MAP_ATTRIBUTE: &str = "data-svg-from-map";

/// Six numbers separated by spaces, each in Rust's shortest round-trip form (`{}`), with no
/// negative zero.
#[must_use]
pub fn matrix_text(m: [f64; 6]) -> String {
    m.map(|v| format!("{}", v + 0.0)).join(" ")
}

/// Escape the five XML special characters and drop characters XML 1.0 forbids.
#[must_use]
pub fn escape_xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(' '),
            c if u32::from(c) < 0x20 || c == '\u{fffe}' || c == '\u{ffff}' => out.push('\u{fffd}'),
            c => out.push(c),
        }
    }
    out
}
