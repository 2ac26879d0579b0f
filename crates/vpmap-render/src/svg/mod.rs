//! Floor plans as SVG.
//!
//! The picture is north-up in the camera's sense: `+y` (forward) points up the page, `+x` to the
//! right, so the station point sits near the bottom with the room in front of it. One map unit
//! is the same number of pixels along both axes. Points that are NaN or infinite are left out
//! (a broken map gives a partial picture, never a panic).
//!
//! The SVG is written by hand with `write!`: it is a few dozen elements, and doing it ourselves
//! keeps the dependency tree small, the number formatting under control (two decimals of a
//! pixel) and the output byte-for-byte deterministic, which snapshot tests need. The `svg`
//! crate would add a dependency without removing any of the layout work.

//! The module is split by concern, bottom-up (each file uses only those before it): `style`
//! (the options, font, colours and limits), `xml` (escaping, the map-to-picture transform),
//! `numbers` (grid steps and number formats), `legend` (unit names and the legend's entries),
//! `layout` (where everything goes: the plot frame, the title band, the footer), `labels`
//! (object labels and their placement, the title), `layers` (the drawing, back to front);
//! this file puts them together.

use vpmap_metrology::map::FloorMap;

mod labels;
mod layers;
mod layout;
mod legend;
mod numbers;
mod style;
mod xml;

pub(crate) use numbers::{decimals_for, fmt_num, grid_indices, grid_step};
pub use style::{FONT_FAMILY, FloorPlanStyle};
pub use xml::{SVG_FROM_MAP_ATTRIBUTE, escape_xml, matrix_text};

///
/// Shows the free space (shaded, holes cut with `fill-rule="evenodd"`), the parts of it hidden
/// from the camera behind objects (hatched with thin grey diagonal lines on light grey, legend
/// entry "hidden from the camera"; only when the map has some), the floor outline, each
/// object as a filled polygon labelled with its name and sizes (a box's length × breadth and
/// height; a footprint's area and height), the station point, the camera's horizontal field
/// of view, a grid with labelled axes, a scale bar, a legend and a title with the camera's
/// pitch, roll and height. A map with error bars (method `fit`) also gets each object's 95 %
/// centroid ellipse (dashed, translucent, with its centre), `± 1 sigma` after the sizes and
/// heights in the labels and after the camera's pitch, roll and height, and a third title line
/// with the focal length, the click noise and the fit's RMS residual; a map without them is
/// drawn exactly as before. `+y` (forward) points up the page. Labels are moved apart when
/// they would overlap, with a leader line back to their object. Object names are
/// XML-escaped. Non-finite points are skipped.
///
/// # Example
/// ```
/// use vpmap_metrology::map::{build_map, BuildOptions};
/// use vpmap_metrology::synth::{synthesize, SynthOptions};
/// use vpmap_render::{floor_plan_svg, FloorPlanStyle};
/// let (scene, _) = synthesize(&SynthOptions::default()).unwrap();
/// let map = build_map(&scene, &BuildOptions::default()).unwrap();
/// let svg = floor_plan_svg(&map, &FloorPlanStyle::default());
/// assert!(svg.starts_with("<?xml") && svg.contains(r#"width="1000""#));
/// assert!(svg.contains(&map.objects[0].name));
/// ```
///
/// # Complexity
/// `O(n + k²)` for `n` polygon corners and `k` objects (label placement).
#[must_use]
pub fn floor_plan_svg(map: &FloorMap, style: &FloorPlanStyle) -> String {
    let u = legend::unit_names(map.units);
    let l = layout::layout(map, style, &u);
    let mut out = String::with_capacity(16 * 1024);
    layers::header(&mut out, style, &l, &u);
    layers::plot_background(&mut out, &l);
    layers::field_of_view(&mut out, map, style, &l, layers::FovPart::Fill);
    layers::free_space(&mut out, map, &l);
    layers::hidden(&mut out, &l);
    layers::field_of_view(&mut out, map, style, &l, layers::FovPart::Outline);
    layers::grid(&mut out, style, &l);
    layers::floor_and_objects(&mut out, map, &l);
    layers::uncertainty(&mut out, map, &l);
    layers::path(&mut out, style, &l);
    if style.show_labels {
        labels::object_labels(&mut out, map, &l, &u);
    }
    layers::other_cameras(&mut out, map, &l);
    layers::station_point(&mut out, map, &l);
    layers::axes(&mut out, &l, &u);
    labels::title(&mut out, map, style, &l, &u);
    layers::scale_bar(&mut out, &l);
    layers::legend(&mut out, &l);
    out.push_str("</svg>\n");
    out
}

#[cfg(test)]
mod tests {
    use super::labels::{fit_text, fmt_sd, place_label};
    use super::layout::{Frame, Rect};
    use super::numbers::nice_at_most;
    use super::style::MIN_FONT_PX;
    use super::*;
    use crate::metrics::text_width_px;
    use approx::assert_relative_eq;

    #[test]
    fn escape_covers_xml_specials_and_controls() {
        assert_eq!(escape_xml(r#"a<b>&"c'"#), "a&lt;b&gt;&amp;&quot;c&apos;");
        assert_eq!(escape_xml("x\u{1}y\nz"), "x\u{fffd}y z");
    }

    #[test]
    fn grid_step_prefers_whole_units_then_1_2_5() {
        assert_relative_eq!(grid_step(8.0), 1.0);
        assert_relative_eq!(grid_step(20.0), 1.0);
        assert_relative_eq!(grid_step(3.0), 0.2);
        assert_relative_eq!(grid_step(0.004), 0.0005, max_relative = 1e-9);
        assert_relative_eq!(grid_step(180.0), 20.0);
        assert_relative_eq!(grid_step(f64::NAN), 1.0);
        for span in [0.013, 0.7, 2.2, 4.9, 21.0, 47.0, 333.0, 1.0e5] {
            let n = span / grid_step(span);
            assert!((4.0..=21.0).contains(&n), "{span}: {n} lines");
        }
    }

    #[test]
    fn nice_at_most_is_a_1_2_5_value_not_above_the_limit() {
        assert_relative_eq!(nice_at_most(2.3), 2.0);
        assert_relative_eq!(nice_at_most(0.99), 0.5);
        assert_relative_eq!(nice_at_most(7.0), 5.0);
        assert_relative_eq!(nice_at_most(10.0), 10.0);
    }

    #[test]
    fn numbers_have_step_decimals_and_no_negative_zero() {
        assert_eq!(decimals_for(1.0), 0);
        assert_eq!(decimals_for(0.1), 1);
        assert_eq!(decimals_for(0.05), 2);
        assert_eq!(decimals_for(20.0), 0);
        assert_eq!(fmt_num(-0.0001, 2), "0.00");
        assert_eq!(fmt_num(-1.234, 1), "-1.2");
    }

    #[test]
    fn small_error_bars_are_not_shown_as_zero() {
        assert_eq!(fmt_sd(0.0349, 2), "0.03");
        assert_eq!(fmt_sd(0.004, 2), "<0.01");
        assert_eq!(fmt_sd(0.004, 1), "<0.1");
        assert_eq!(fmt_sd(0.0, 2), "0.00");
    }

    #[test]
    fn long_text_is_shrunk_then_cut() {
        let (t, px) = fit_text("short", 20.0, 500.0, false);
        assert_eq!((t.as_str(), px), ("short", 20.0));
        let long = "x".repeat(400);
        let (t, px) = fit_text(&long, 20.0, 300.0, false);
        assert!(px >= MIN_FONT_PX);
        assert!(text_width_px(&t, px, false) <= 300.0 + 1e-9);
        assert!(t.ends_with('…'));
    }

    #[test]
    fn labels_are_moved_off_each_other_and_kept_in_the_plot() {
        let frame = Frame {
            x_min: 0.0,
            y_max: 10.0,
            px_per_unit: 50.0,
            left: 0.0,
            top: 0.0,
            width: 500.0,
            height: 500.0,
        };
        let a = Rect {
            x: 200.0,
            y: 200.0,
            w: 100.0,
            h: 30.0,
        };
        let b = place_label(a, None, &[], &[a], &frame);
        assert!(!b.overlaps(&a));
        let corner = Rect {
            x: 480.0,
            y: -10.0,
            ..a
        };
        let c = place_label(corner, None, &[], &[], &frame);
        assert!(frame.contains(&c));
        // A small object under the label: the label moves off it.
        let small = vec![
            (240.0, 210.0),
            (260.0, 210.0),
            (260.0, 220.0),
            (240.0, 220.0),
        ];
        let d = place_label(a, Some(0), std::slice::from_ref(&small), &[], &frame);
        assert!(!d.hits(&small));
        // A big object: the label stays centred inside it.
        let big = vec![
            (100.0, 100.0),
            (400.0, 100.0),
            (400.0, 400.0),
            (100.0, 400.0),
        ];
        let e = place_label(a, Some(0), &[big], &[], &frame);
        assert!((e.x - a.x).abs() < 1e-9 && (e.y - a.y).abs() < 1e-9);
    }
}
