//! The thesis's box plots (figures 6.8-6.13 and 6.18-6.23): one plot per metric, one box per
//! experiment set-up and method, 2PP and 3PP side by side, at one noise level.
//!
//! A box spans the first to the third quartile, a line marks the median, and the whiskers end
//! at the 5th and 95th percentiles (capped); nothing beyond them is drawn. Both panels share
//! the y range, so the perspectives compare at a glance.

use plotters::prelude::*;
use rayon::prelude::*;
use vpmap_metrology::calibration::Perspective;
use vpmap_render::RenderError;

use super::collect::{Collected, DESCRIBED, Described, Group};
use super::config::Config;
use crate::error::{EvalError, Result};
use crate::stats::Summary;

/// One plot, rendered.
pub struct Plot {
    /// The metric plotted.
    pub metric: &'static str,
    /// File name without extension.
    pub stem: String,
    /// The SVG text.
    pub svg: String,
    /// The PNG bytes (`None` when the system has no fonts to draw the text with).
    pub png: Option<Vec<u8>>,
}

const WIDTH: u32 = 1400;
const HEIGHT: u32 = 560;

/// Colours of the methods, in the order given.
const COLOURS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
];

/// The boxes of one panel: per set-up, per method.
struct Panel {
    title: String,
    names: Vec<&'static str>,
    boxes: Vec<Vec<Option<Summary>>>,
}

/// Render every plot (SVG, and PNG when fonts allow).
///
/// # Errors
/// When the plot's noise level is not among the run's, or drawing or rendering fails.
pub fn box_plots(config: &Config, c: &Collected) -> Result<Vec<Plot>> {
    let Some(sigma) = config
        .sigmas
        .iter()
        .position(|s| (s - config.plot_sigma).abs() <= 1e-12)
    else {
        return Err(EvalError::Invalid(format!(
            "the plot's noise level {} is not among the noise levels",
            config.plot_sigma
        )));
    };
    DESCRIBED
        .par_iter()
        .enumerate()
        .map(|(k, d)| {
            let panels: Vec<Panel> = [Perspective::TwoPoint, Perspective::ThreePoint]
                .into_iter()
                .filter_map(|p| panel(config, c, sigma, k, d, p))
                .collect();
            let svg = draw(config, d, &panels)
                .map_err(|e| EvalError::Invalid(format!("drawing the {} plot: {e}", d.name)))?;
            let png = match vpmap_render::svg_to_png(&svg) {
                Ok(png) => Some(png),
                Err(RenderError::NoFonts) => None,
                Err(e) => {
                    return Err(EvalError::Context {
                        context: format!("rendering the {} plot", d.name),
                        source: Box::new(e.into()),
                    });
                }
            };
            Ok(Plot {
                metric: d.name,
                stem: format!("box_{}", d.name),
                svg,
                png,
            })
        })
        .collect()
}

fn panel(
    config: &Config,
    c: &Collected,
    sigma: usize,
    metric: usize,
    d: &Described,
    perspective: Perspective,
) -> Option<Panel> {
    let members: Vec<usize> = (0..config.setups.len())
        .filter(|&e| config.setups[e].perspective == perspective)
        .collect();
    if members.is_empty() {
        return None;
    }
    let (label, figure) = match perspective {
        Perspective::TwoPoint => ("2PP", d.figures[0]),
        Perspective::ThreePoint => ("3PP", d.figures[1]),
    };
    Some(Panel {
        title: if figure == "-" {
            label.to_owned()
        } else {
            format!("{label} (thesis fig. {figure})")
        },
        names: members.iter().map(|&e| config.setups[e].name).collect(),
        boxes: members
            .iter()
            .map(|&e| {
                (0..config.methods.len())
                    .map(|m| c.summary(config, m, sigma, Group::Experiment(e), metric))
                    .collect()
            })
            .collect(),
    })
}

/// The y range: every box's whiskers and the perfect value, padded by 5 %.
fn y_range(panels: &[Panel], perfect: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (perfect, perfect);
    for s in panels
        .iter()
        .flat_map(|p| p.boxes.iter().flatten().flatten())
    {
        lo = lo.min(s.p5);
        hi = hi.max(s.p95);
    }
    let span = hi - lo;
    if span <= 1e-9 * (1.0 + perfect.abs()) {
        return (perfect - 1.0, perfect + 1.0);
    }
    (lo - 0.05 * span, hi + 0.05 * span)
}

fn draw(config: &Config, d: &Described, panels: &[Panel]) -> Result<String, String> {
    let err = |e: &dyn std::fmt::Display| e.to_string();
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, HEIGHT)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (top, rest) = root.split_vertically(64);
        let (body, legend) = rest.split_vertically(HEIGHT - 64 - 40);
        let title = format!(
            "{} — {} ({}), σ = {} px, truth scaled by S_k (eq. 6.1)",
            d.name, d.title, d.unit, config.plot_sigma
        );
        top.draw_text(&title, &("sans-serif", 22).into_text_style(&top), (20, 12))
            .map_err(|e| err(&e))?;
        top.draw_text(
            &format!(
                "box: quartiles; line: median; whiskers: 5th and 95th percentiles; {} trials per experiment, every object",
                config.trials
            ),
            &("sans-serif", 15).into_text_style(&top),
            (20, 40),
        )
        .map_err(|e| err(&e))?;
        let (y0, y1) = y_range(panels, d.perfect);
        let areas = body.split_evenly((1, panels.len().max(1)));
        for (area, panel) in areas.iter().zip(panels) {
            draw_panel(area, panel, config.methods.len(), d, (y0, y1)).map_err(|e| err(&e))?;
        }
        let mut x = 80;
        for (m, method) in config.methods.iter().enumerate() {
            let colour = COLOURS[m % COLOURS.len()];
            legend
                .draw(&Rectangle::new(
                    [(x, 10), (x + 24, 26)],
                    colour.mix(0.35).filled(),
                ))
                .map_err(|e| err(&e))?;
            legend
                .draw(&Rectangle::new(
                    [(x, 10), (x + 24, 26)],
                    colour.stroke_width(2),
                ))
                .map_err(|e| err(&e))?;
            legend
                .draw_text(
                    &method.to_string(),
                    &("sans-serif", 16).into_text_style(&legend),
                    (x + 32, 10),
                )
                .map_err(|e| err(&e))?;
            x += 180;
        }
        root.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    panel: &Panel,
    methods: usize,
    d: &Described,
    (y0, y1): (f64, f64),
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let n = panel.names.len();
    let x_max = n as f64 - 0.5;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 18))
        .margin(12)
        .x_label_area_size(36)
        .y_label_area_size(64)
        .build_cartesian_2d(-0.5..x_max, y0..y1)?;
    let names = panel.names.clone();
    let label = move |x: &f64| {
        let i = x.round();
        if (x - i).abs() < 1e-6 && i >= 0.0 {
            names
                .get(i as usize)
                .map_or_else(String::new, |s| (*s).to_owned())
        } else {
            String::new()
        }
    };
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(n)
        .x_label_formatter(&label)
        .y_desc(format!("{} ({})", d.name, d.unit))
        .label_style(("sans-serif", 14))
        .axis_desc_style(("sans-serif", 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(210, 210, 210))
        .draw()?;
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(-0.5, d.perfect), (x_max, d.perfect)],
        BLACK.mix(0.5).stroke_width(1),
    )))?;
    let slot = 0.8 / methods.max(1) as f64;
    let half = slot * 0.38;
    for (e, per_method) in panel.boxes.iter().enumerate() {
        for (m, summary) in per_method.iter().enumerate() {
            let Some(s) = summary else { continue };
            let colour = COLOURS[m % COLOURS.len()];
            let x = e as f64 - 0.4 + slot * (m as f64 + 0.5);
            let line = colour.stroke_width(1);
            chart.draw_series([
                PathElement::new(vec![(x, s.p5), (x, s.q1)], line),
                PathElement::new(vec![(x, s.q3), (x, s.p95)], line),
                PathElement::new(vec![(x - half / 2.0, s.p5), (x + half / 2.0, s.p5)], line),
                PathElement::new(vec![(x - half / 2.0, s.p95), (x + half / 2.0, s.p95)], line),
            ])?;
            chart.draw_series([
                Rectangle::new(
                    [(x - half, s.q1), (x + half, s.q3)],
                    colour.mix(0.35).filled(),
                ),
                Rectangle::new([(x - half, s.q1), (x + half, s.q3)], colour.stroke_width(1)),
            ])?;
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(x - half, s.median), (x + half, s.median)],
                colour.stroke_width(3),
            )))?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_y_range_holds_every_whisker_and_the_perfect_value() {
        let s = Summary::of(&[1.0, 2.0, 3.0, 4.0, 50.0]).unwrap();
        let panel = Panel {
            title: String::new(),
            names: vec!["a"],
            boxes: vec![vec![Some(s)]],
        };
        let (lo, hi) = y_range(std::slice::from_ref(&panel), 0.0);
        assert!(lo < 0.0 && hi > s.p95 && hi < s.max, "{lo} {hi}");
        // All values at the perfect one: a unit band around it.
        let flat = Summary::of(&[100.0, 100.0]).unwrap();
        let panel = Panel {
            title: String::new(),
            names: vec!["a"],
            boxes: vec![vec![Some(flat)]],
        };
        assert_eq!(y_range(&[panel], 100.0), (99.0, 101.0));
    }
}
