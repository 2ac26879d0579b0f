//! The plots of `vpmap bench`, after the thesis's figures 6.25 (mean runtime per map, MBPP
//! against A* PS) and 6.26 (mean path length per map), with every planner run, plus the mean
//! excess over the exact optimum. Grouped horizontal bars, one group per map (so that map
//! names read horizontally), drawn with plotters' SVG backend.

use plotters::coord::Shift;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use vpmap_plan::planner::PlannerKind;

use super::results::Results;
use super::summary::{PlannerStats, Summary, planner_label};
use crate::error::{EvalError, Result};

/// One plot, named without its extension.
pub struct Plot {
    /// File name without extension.
    pub name: &'static str,
    /// The SVG text.
    pub svg: String,
}

/// Picture width, pixels.
const WIDTH: u32 = 960;
/// Height of one planner's bar, pixels.
const BAR_PX: u32 = 7;
/// Space above and below each map's group of bars, pixels.
const GROUP_PAD_PX: u32 = 5;
/// Title, legend and axis, pixels.
const FRAME_PX: u32 = 150;
/// Label font size, pixels.
const LABEL_FONT: f64 = 13.0;
/// Approximate width of one label character, pixels (DejaVu Sans at [`LABEL_FONT`]).
const CHAR_PX: f64 = 7.5;

/// A fixed colour per planner.
fn colour(kind: PlannerKind) -> RGBColor {
    match kind {
        PlannerKind::Mbpp => RGBColor(214, 39, 40),
        PlannerKind::MbppCloser => RGBColor(255, 127, 14),
        PlannerKind::AstarPs => RGBColor(31, 119, 180),
        PlannerKind::ThetaStar => RGBColor(44, 160, 44),
        PlannerKind::Astar => RGBColor(148, 148, 148),
        PlannerKind::Optimal => RGBColor(40, 40, 40),
    }
}

/// A linear axis with the tick marks given (plotters' own `with_key_points` cannot take a
/// label formatter on `f64` axes).
struct KeyedAxis {
    from: f64,
    to: f64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl Ranged for KeyedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let span = self.to - self.from;
        let t = if span > 0.0 {
            (value - self.from) / span
        } else {
            0.0
        };
        limit.0 + (t * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.from..self.to
    }
}

/// What a bar chart shows.
struct Bars<'a> {
    title: String,
    axis: &'a str,
    /// Logarithmic value axis.
    log: bool,
    /// One label per map, top to bottom.
    labels: Vec<String>,
    planners: &'a [PlannerKind],
    /// `values[map][planner]`.
    values: Vec<Vec<Option<f64>>>,
}

fn drawing_error<E: std::fmt::Debug>(e: E) -> EvalError {
    EvalError::Invalid(format!("drawing a plot: {e:?}"))
}

/// The runtime, length and (when `optimal` ran) excess plots.
///
/// # Errors
/// When drawing fails.
pub fn plots(results: &Results, summary: &Summary) -> Result<Vec<Plot>> {
    let labels: Vec<String> = results
        .maps
        .iter()
        .map(|m| format!("{} ({})", m.map.name, m.map.category))
        .collect();
    let column = |f: &dyn Fn(&PlannerStats) -> Option<f64>| -> Vec<Vec<Option<f64>>> {
        summary
            .maps
            .iter()
            .map(|g| g.planners.iter().map(f).collect())
            .collect()
    };
    let mut out = vec![
        Plot {
            name: "runtime",
            svg: bar_chart(&Bars {
                title: "Mean runtime per query (cf. thesis Fig. 6.25)".to_owned(),
                axis: "time per query, ms (log scale; median of the timed runs)",
                log: true,
                labels: labels.clone(),
                planners: &results.planners,
                values: column(&|s| s.mean_time_s.map(|t| t * 1e3)),
            })?,
        },
        Plot {
            name: "length",
            svg: bar_chart(&Bars {
                title: "Mean path length, solvable queries (cf. thesis Fig. 6.26)".to_owned(),
                axis: "path length, cells",
                log: false,
                labels: labels.clone(),
                planners: &results.planners,
                values: column(&|s| s.mean_length_cells),
            })?,
        },
    ];
    if has_excess_plot(&results.planners) {
        // The optimum's own excess is zero by definition: left out.
        let kept: Vec<usize> = (0..results.planners.len())
            .filter(|&p| results.planners[p] != PlannerKind::Optimal)
            .collect();
        let planners: Vec<PlannerKind> = kept.iter().map(|&p| results.planners[p]).collect();
        let values = column(&|s| s.mean_excess.map(|e| 100.0 * e))
            .into_iter()
            .map(|row| kept.iter().map(|&p| row[p]).collect())
            .collect();
        let labels = results
            .maps
            .iter()
            .zip(labels)
            .map(|(m, l)| {
                if m.optimal_skipped.is_some() {
                    format!("{l}: no optimum")
                } else {
                    l
                }
            })
            .collect();
        out.push(Plot {
            name: "excess",
            svg: bar_chart(&Bars {
                title: "Mean excess of the path length over the exact optimum".to_owned(),
                axis: "length / optimal - 1, %",
                log: false,
                labels,
                planners: &planners,
                values,
            })?,
        });
    }
    Ok(out)
}

/// Whether the excess plot is drawn: `optimal` ran, and some other planner did.
#[must_use]
pub fn has_excess_plot(planners: &[PlannerKind]) -> bool {
    planners.contains(&PlannerKind::Optimal) && planners.len() > 1
}

/// Value-axis range and ticks: `(from, to, bold ticks, light ticks)` in axis coordinates
/// (log10 of the value on a log axis).
fn value_axis(values: &[f64], log: bool) -> (f64, f64, Vec<f64>, Vec<f64>) {
    if log {
        let positive: Vec<f64> = values.iter().copied().filter(|v| *v > 0.0).collect();
        let lo = positive.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = positive.iter().copied().fold(0.0, f64::max);
        let (lo, hi) = if positive.is_empty() {
            (0.0, 1.0)
        } else {
            (
                lo.log10().floor(),
                hi.log10().ceil().max(lo.log10().floor() + 1.0),
            )
        };
        let bold: Vec<f64> = (lo as i32..=hi as i32).map(f64::from).collect();
        let light = (lo as i32..hi as i32)
            .flat_map(|k| [2.0f64, 5.0].map(move |m| f64::from(k) + m.log10()))
            .collect();
        (lo, hi, bold, light)
    } else {
        let hi = values.iter().copied().fold(0.0, f64::max);
        let hi = if hi > 0.0 { hi * 1.05 } else { 1.0 };
        let step = nice_step(hi / 6.0);
        let ticks = (hi / step + 1e-9).floor() as i32;
        let bold = (0..=ticks).map(|k| f64::from(k) * step).collect();
        (0.0, hi, bold, Vec::new())
    }
}

/// 1, 2 or 5 times a power of ten, at least `raw`.
fn nice_step(raw: f64) -> f64 {
    let p = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * p)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * p)
}

/// A tick label: a power of ten on a log axis, else a plain number.
fn tick_text(v: f64, log: bool) -> String {
    if log {
        let value = 10f64.powf(v);
        if value >= 1.0 {
            format!("{value:.0}")
        } else {
            let decimals = (-v).round().max(0.0) as usize;
            format!("{value:.decimals$}")
        }
    } else if v.fract().abs() < 1e-9 {
        format!("{v:.0}")
    } else {
        format!("{v}")
    }
}

fn bar_chart(bars: &Bars) -> Result<String> {
    let n = bars.labels.len();
    let np = bars.planners.len();
    let group_px = np as u32 * BAR_PX + 2 * GROUP_PAD_PX;
    let height = FRAME_PX + n as u32 * group_px;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing_error)?;
        let root = root
            .titled(&bars.title, ("sans-serif", 20))
            .map_err(drawing_error)?;
        let (legend, plot) = root.split_vertically(30);
        draw_legend(&legend, bars.planners)?;
        draw_bars(&plot, bars)?;
        root.present().map_err(drawing_error)?;
    }
    Ok(svg)
}

fn draw_legend(area: &DrawingArea<SVGBackend, Shift>, planners: &[PlannerKind]) -> Result<()> {
    let mut x = 20i32;
    for &kind in planners {
        let name = planner_label(kind);
        area.draw(&Rectangle::new(
            [(x, 8), (x + 14, 20)],
            colour(kind).filled(),
        ))
        .map_err(drawing_error)?;
        area.draw(&Text::new(
            name,
            (x + 20, 14),
            ("sans-serif", LABEL_FONT)
                .into_font()
                .color(&BLACK)
                .pos(Pos::new(HPos::Left, VPos::Center)),
        ))
        .map_err(drawing_error)?;
        x += 20 + 22 + (name.len() as f64 * CHAR_PX) as i32;
    }
    Ok(())
}

fn draw_bars(area: &DrawingArea<SVGBackend, Shift>, bars: &Bars) -> Result<()> {
    let n = bars.labels.len();
    let np = bars.planners.len();
    let flat: Vec<f64> = bars.values.iter().flatten().flatten().copied().collect();
    let (lo, hi, bold, light) = value_axis(&flat, bars.log);
    let label_px = bars
        .labels
        .iter()
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0) as f64
        * CHAR_PX
        + 16.0;
    let keys: Vec<f64> = (0..n).map(|i| i as f64 + 0.5).collect();
    let labels = &bars.labels;
    let log = bars.log;
    let mut chart = ChartBuilder::on(area)
        .margin_right(30)
        .margin_bottom(10)
        .x_label_area_size(45)
        .y_label_area_size(label_px as u32)
        .build_cartesian_2d(
            KeyedAxis {
                from: lo,
                to: hi,
                bold,
                light,
            },
            KeyedAxis {
                from: 0.0,
                to: n.max(1) as f64,
                bold: keys,
                light: Vec::new(),
            },
        )
        .map_err(drawing_error)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc(bars.axis)
        .axis_desc_style(("sans-serif", LABEL_FONT))
        .label_style(("sans-serif", LABEL_FONT))
        .x_label_formatter(&|v| tick_text(*v, log))
        .y_label_formatter(&|y| {
            let i = n
                .saturating_sub(1)
                .saturating_sub(y.floor().max(0.0) as usize);
            labels.get(i).cloned().unwrap_or_default()
        })
        .draw()
        .map_err(drawing_error)?;
    let bar_h = 0.8 / np.max(1) as f64;
    let to_axis = |v: f64| if log { v.log10() } else { v };
    for (p, &kind) in bars.planners.iter().enumerate() {
        let rects: Vec<Rectangle<(f64, f64)>> = bars
            .values
            .iter()
            .enumerate()
            .filter_map(|(i, row)| {
                let v = row.get(p).copied().flatten()?;
                if log && v <= 0.0 {
                    return None;
                }
                let top = (n - i) as f64 - 0.1 - p as f64 * bar_h;
                Some(Rectangle::new(
                    [(lo, top - bar_h), (to_axis(v).max(lo), top)],
                    colour(kind).filled(),
                ))
            })
            .collect();
        chart.draw_series(rects).map_err(drawing_error)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_have_readable_ticks() {
        let (lo, hi, bold, light) = value_axis(&[0.02, 3.0, 450.0], true);
        assert!((lo + 2.0).abs() < 1e-12 && (hi - 3.0).abs() < 1e-12);
        assert_eq!(bold.len(), 6);
        assert_eq!(light.len(), 5 * 2);
        assert_eq!(tick_text(-2.0, true), "0.01");
        assert_eq!(tick_text(3.0, true), "1000");
        let (lo, hi, bold, _) = value_axis(&[0.0, 12.0], false);
        assert!(lo.abs() < 1e-12 && hi > 12.0);
        assert_eq!(bold, [0.0, 5.0, 10.0]);
        assert!((nice_step(0.7) - 1.0).abs() < 1e-12);
        assert!((nice_step(13.0) - 20.0).abs() < 1e-12);
    }
}
