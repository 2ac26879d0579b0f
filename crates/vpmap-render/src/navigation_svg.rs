//! A drive of a robot that senses and re-plans, drawn over its true map: the picture
//! `vpmap navigate` writes (navigate.svg).

use std::fmt::Write as _;

use vpmap_plan::grid::{CellXy, Occupancy, OccupancyGrid};
use vpmap_plan::navigate::{Navigation, OnlinePlanner};

/// The animation's speed, cells a second, and its duration's bounds, seconds.
pub const ANIMATION_CELLS_PER_S: f64 = 40.0;
/// See [`ANIMATION_CELLS_PER_S`].
const MIN_ANIMATION_S: f64 = 4.0;
/// See [`ANIMATION_CELLS_PER_S`].
const MAX_ANIMATION_S: f64 = 30.0;

/// The narrowest picture, pixels.
const MIN_WIDTH_PX: f64 = 560.0;

/// The legend: colour and label of everything drawn.
const LEGEND: [(&str, &str); 8] = [
    ("#222222", "obstacle (true map)"),
    ("#cfe8ff", "sensed free floor"),
    ("#ff9896", "obstacle on the believed map"),
    ("#d62728", "driven track"),
    ("#ff7f0e", "re-planning point (appears when reached)"),
    ("#7f0000", "robot and track driven (animated in a browser)"),
    ("#2ca02c", "start"),
    ("#1f77b4", "goal"),
];

/// For each waypoint, the fraction of the track's length driven when the robot reaches it
/// (0 at the start, 1 at the end; all 0 for a track of no length).
fn track_fractions(waypoints: &[CellXy]) -> Vec<f64> {
    let mut cumulative = Vec::with_capacity(waypoints.len());
    let mut length = 0.0;
    for (i, c) in waypoints.iter().enumerate() {
        if let Some(p) = i.checked_sub(1).and_then(|j| waypoints.get(j)) {
            length += (c.x as f64 - p.x as f64).hypot(c.y as f64 - p.y as f64);
        }
        cumulative.push(length);
    }
    if length > 0.0 {
        for v in &mut cumulative {
            *v /= length;
        }
    }
    cumulative
}

/// The picture of a drive (`vpmap navigate`'s navigate.svg): the true map, the believed
/// obstacles, the sensed area, the driven track, the re-planning points, start, goal and a
/// legend; one SVG unit per cell, row 0 at the top. Animated in a browser (SMIL): the robot
/// drives the track at constant speed ([`ANIMATION_CELLS_PER_S`], the whole drive in 4 to
/// 30 s, looping), the track darkens behind it, and each re-planning point appears when the
/// robot reaches it; a static renderer shows the whole drive with the robot at the start.
///
/// `truth` and `believed` are grids of the same size (as [`navigate`](vpmap_plan::navigate::navigate)
/// requires); `run` is the drive from `start` to `goal` by `planner`.
#[must_use]
pub fn navigation_svg(
    truth: &OccupancyGrid,
    believed: &OccupancyGrid,
    run: &Navigation,
    start: CellXy,
    goal: CellXy,
    planner: OnlinePlanner,
) -> String {
    let (w, h) = (truth.width(), truth.height());
    let px = (900.0 / w.max(h) as f64).clamp(0.5, 24.0);
    // The picture is at least MIN_WIDTH_PX wide (the grid at the left) so that the title
    // and the legend fit beside a small grid; the legend takes two columns from 700 px.
    let width = (w as f64).max(MIN_WIDTH_PX / px);
    let columns = if width * px >= 700.0 { 2 } else { 1 };
    let legend_rows = LEGEND.len().div_ceil(columns);
    let legend_h = (legend_rows as f64 + 1.0) * 16.0 / px;
    let title_h = 40.0 / px;
    let mut s = String::new();
    let _ = write!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{:.0}" height="{:.0}" viewBox="0 {:.3} {width:.3} {:.3}" font-family="sans-serif">"#,
        width * px,
        (h as f64 + title_h + legend_h) * px,
        -title_h,
        h as f64 + title_h + legend_h
    );
    let font = 12.0 / px;
    let _ = write!(
        s,
        r##"<text x="0" y="{:.3}" font-size="{:.3}" fill="#222">{} on {w} x {h} cells: {}, driven {} cells, {} re-plans</text>"##,
        -title_h * 0.35,
        font * 1.2,
        planner.name(),
        run.outcome.as_str(),
        (run.length_cells * 100.0).round() / 100.0,
        run.events.len().saturating_sub(1)
    );
    let _ = write!(
        s,
        r##"<rect x="0" y="0" width="{w}" height="{h}" fill="#ffffff"/>"##
    );
    // Run-length rectangles per row of cells matching `pick`.
    let rows = |s: &mut String, pick: &dyn Fn(usize, usize) -> bool, fill: &str, opacity: f64| {
        for y in 0..h {
            let mut x = 0;
            while x < w {
                if pick(x, y) {
                    let x0 = x;
                    while x < w && pick(x, y) {
                        x += 1;
                    }
                    let _ = write!(
                        s,
                        r#"<rect x="{x0}" y="{y}" width="{}" height="1" fill="{fill}" fill-opacity="{opacity}" shape-rendering="crispEdges"/>"#,
                        x - x0
                    );
                } else {
                    x += 1;
                }
            }
        }
    };
    let seen = |x: usize, y: usize| {
        truth
            .index(x, y)
            .and_then(|i| run.belief.seen.get(i).copied())
            .unwrap_or(false)
    };
    rows(
        &mut s,
        &|x, y| seen(x, y) && truth.is_free(x, y),
        "#cfe8ff",
        1.0,
    );
    rows(&mut s, &|x, y| !truth.is_free(x, y), "#222222", 1.0);
    rows(
        &mut s,
        &|x, y| believed.get(x, y) == Some(Occupancy::Occupied),
        "#ff9896",
        0.6,
    );
    // The grid's edge (unsensed floor is white like the margin).
    let _ = write!(
        s,
        r##"<rect x="0" y="0" width="{w}" height="{h}" fill="none" stroke="#888888" stroke-width="{:.3}"/>"##,
        1.0 / px
    );
    let points: Vec<String> = run
        .waypoints
        .iter()
        .map(|c| format!("{}.5,{}.5", c.x, c.y))
        .collect();
    let stroke = (2.0 / px).max(0.15);
    let _ = write!(
        s,
        r##"<polyline points="{}" fill="none" stroke="#d62728" stroke-width="{stroke:.3}" stroke-linejoin="round"/>"##,
        points.join(" ")
    );
    // The animation (SMIL, played by browsers; a static renderer shows the whole drive with
    // the robot at the start): the robot moves along the track at constant speed, the track darkens behind it, and each
    // re-planning point appears when the robot reaches it. All share one duration and loop.
    let along = track_fractions(&run.waypoints);
    let total = run.length_cells;
    let duration_s = (total / ANIMATION_CELLS_PER_S).clamp(MIN_ANIMATION_S, MAX_ANIMATION_S);
    if total > 0.0 {
        let _ = write!(
            s,
            r##"<polyline points="{}" fill="none" stroke="#7f0000" stroke-width="{:.3}" stroke-linejoin="round" stroke-dasharray="{total:.3} {total:.3}" stroke-dashoffset="{total:.3}"><animate attributeName="stroke-dashoffset" from="{total:.3}" to="0" dur="{duration_s:.2}s" repeatCount="indefinite"/></polyline>"##,
            points.join(" "),
            stroke * 1.2
        );
    }
    let r = (4.0 / px).max(0.4);
    let mut from = 0;
    for e in run.events.iter().skip(1) {
        // The event's cell is a waypoint of the track (re-planning cells are), at or after
        // the previous event's.
        let found = run.waypoints[from..]
            .iter()
            .position(|&c| c == e.cell)
            .map(|k| from + k);
        let fraction = found.map_or(0.0, |k| along[k]);
        from = found.unwrap_or(from);
        let _ = write!(
            s,
            r##"<circle cx="{}.5" cy="{}.5" r="{r:.3}" fill="none" stroke="#ff7f0e" stroke-width="{:.3}"><animate attributeName="opacity" values="0;1" keyTimes="0;{fraction:.5}" calcMode="discrete" dur="{duration_s:.2}s" repeatCount="indefinite"/></circle>"##,
            e.cell.x,
            e.cell.y,
            stroke * 0.7
        );
    }
    if let (Some(first), true) = (run.waypoints.first(), total > 0.0) {
        // The centre's coordinates animated through the waypoints, key times at their
        // fractions of the length (constant speed); repeated points (no length) left out.
        let (mut xs, mut ys, mut times) = (Vec::new(), Vec::new(), Vec::<String>::new());
        let mut last = f64::NEG_INFINITY;
        for (c, &f) in run.waypoints.iter().zip(&along) {
            if f > last {
                xs.push(format!("{}.5", c.x));
                ys.push(format!("{}.5", c.y));
                times.push(format!("{f:.5}"));
                last = f;
            }
        }
        if let Some(t) = times.last_mut() {
            // Exactly 1 however the fractions round.
            "1".clone_into(t);
        }
        let times = times.join(";");
        let _ = write!(
            s,
            r##"<circle class="robot" cx="{}.5" cy="{}.5" r="{:.3}" fill="#7f0000" stroke="#ffffff" stroke-width="{:.3}"><animate attributeName="cx" values="{}" keyTimes="{times}" dur="{duration_s:.2}s" repeatCount="indefinite"/><animate attributeName="cy" values="{}" keyTimes="{times}" dur="{duration_s:.2}s" repeatCount="indefinite"/></circle>"##,
            first.x,
            first.y,
            r * 1.1,
            stroke * 0.5,
            xs.join(";"),
            ys.join(";"),
        );
    }
    for (c, colour) in [(start, "#2ca02c"), (goal, "#1f77b4")] {
        let _ = write!(
            s,
            r#"<circle cx="{}.5" cy="{}.5" r="{:.3}" fill="{colour}"/>"#,
            c.x,
            c.y,
            r * 1.2
        );
    }
    let line = 16.0 / px;
    for (i, (colour, label)) in LEGEND.iter().enumerate() {
        let col = i % columns;
        let row = i / columns;
        let x = col as f64 * (width / 2.0);
        let y = h as f64 + line * (row as f64 + 0.8);
        let _ = write!(
            s,
            r##"<rect x="{x:.3}" y="{:.3}" width="{:.3}" height="{:.3}" fill="{colour}" stroke="#555" stroke-width="{:.3}"/><text x="{:.3}" y="{y:.3}" font-size="{font:.3}" fill="#222">{label}</text>"##,
            y - font * 0.8,
            font,
            font,
            stroke * 0.2,
            x + font * 1.5
        );
    }
    s.push_str("</svg>\n");
    s
}
