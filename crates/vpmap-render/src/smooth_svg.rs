//! The picture of a smooth path ([`smooth_svg`]): the grid as [`crate::plan_svg()`] draws
//! it, the path as a polyline through its poses, and its tightest turn marked by the arc's
//! whole turning circle (dashed) and a ring where the turn is; each cusp (where the robot
//! changes between forward and reverse) marked by a square.

use std::fmt::Write as _;

use vpmap_plan::Planned;
use vpmap_plan::grid::{CellXy, OccupancyGrid};
use vpmap_plan::plan::Plan;
use vpmap_plan::smooth::{Gear, SmoothPlan};

use crate::plan_svg::{GridCoordinates, plan_svg};

/// Colour of the smooth path (the planners' path colour).
const PATH_COLOUR: &str = "#d62728";
/// Colour of the tightest turn's marks.
const TURN_COLOUR: &str = "#ff7f0e";
/// Colour of the cusp marks.
const CUSP_COLOUR: &str = "#9467bd";

/// The grid, start and goal as [`plan_svg()`] draws them (its subtitle giving the path's
/// length), with `plan`'s curve through its poses (one SVG unit per cell, cell `(x, y)`
/// spanning `x..x + 1`), its tightest turn's circle and a square at each cusp; `plan: None`
/// draws "no path".
#[must_use]
pub fn smooth_svg(
    grid: &OccupancyGrid,
    plan: Option<&SmoothPlan>,
    start: CellXy,
    goal: CellXy,
    coordinates: GridCoordinates,
    title: &str,
) -> String {
    // plan_svg draws the frame, the cells, the markers, the axes, the title and the legend;
    // a one-point "polyline" at the start stands for the path in its legend and subtitle.
    let planned = Planned {
        best: plan.map(|p| Plan {
            waypoints: vec![start],
            length_cells: p.length_cells,
            stats: vpmap_plan::plan::PlanStats::default(),
        }),
        ..Planned::default()
    };
    let mut out = plan_svg(grid, &planned, start, goal, coordinates, title);
    let Some(p) = plan else {
        return out;
    };
    let px = (900.0 / grid.width().max(grid.height()) as f64).clamp(0.5, 24.0);
    let stroke = (2.0 / px).max(0.15);
    let mut drawn = String::new();
    let points: Vec<String> = p
        .poses
        .iter()
        .map(|q| format!("{:.3},{:.3}", q.x + 0.5, q.y + 0.5))
        .collect();
    let _ = writeln!(
        drawn,
        r#"<polyline class="smooth-path" points="{}" fill="none" stroke="{PATH_COLOUR}" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"#,
        points.join(" ")
    );
    if let Some(seg) = p
        .curve
        .tightest_turn()
        .and_then(|i| p.curve.segments.get(i))
        && let (Some(c), Some(r)) = (seg.centre(), seg.radius())
    {
        let mid = seg.pose_at(seg.length / 2.0);
        let _ = writeln!(
            drawn,
            r#"<g class="tightest-turn" fill="none" stroke="{TURN_COLOUR}" stroke-width="{:.3}"><circle cx="{:.3}" cy="{:.3}" r="{r:.3}" stroke-dasharray="{:.3} {:.3}"/><circle cx="{:.3}" cy="{:.3}" r="{:.3}"/><title>tightest turn: radius {r:.3} cells</title></g>"#,
            stroke * 0.7,
            c[0] + 0.5,
            c[1] + 0.5,
            stroke * 3.0,
            stroke * 2.0,
            mid.x + 0.5,
            mid.y + 0.5,
            (6.0 / px).max(0.6),
        );
    }
    let half = (4.0 / px).max(0.4);
    for w in p.curve.segments.windows(2) {
        if let [a, b] = w
            && a.gear != b.gear
        {
            let _ = writeln!(
                drawn,
                r#"<rect class="cusp" x="{:.3}" y="{:.3}" width="{:.3}" height="{:.3}" fill="{CUSP_COLOUR}"><title>cusp: from {} to {} at ({:.2}, {:.2})</title></rect>"#,
                b.start.x + 0.5 - half,
                b.start.y + 0.5 - half,
                2.0 * half,
                2.0 * half,
                gear_name(a.gear),
                gear_name(b.gear),
                b.start.x,
                b.start.y,
            );
        }
    }
    if let Some(at) = out.find(r#"<circle class="start""#) {
        out.insert_str(at, &drawn);
    }
    out
}

fn gear_name(g: Gear) -> &'static str {
    match g {
        Gear::Forward => "forward",
        Gear::Reverse => "reverse",
    }
}
