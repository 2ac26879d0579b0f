//! The maps and queries of `vpmap bench`: the Moving AI benchmark maps of the thesis's
//! categories, occupancy grids built by vpmap from synthetic room scenes, generated grids
//! when the benchmark data is absent, and the maps and scenario files a user names.
//!
//! Connectivity: a diagonal step needs both orthogonal neighbours free (no corner cutting),
//! so it can always be replaced by two straight steps, and the components of the 8-connected
//! movement graph are exactly the 4-connected components of the free cells.
//! [`vpmap_plan::reach::Components`] labels them by breadth-first search; it is the reference
//! for "is there a path".

use std::path::{Path, PathBuf};

use crate::error::{EvalError, Result, ResultExt as _, bail};
use crate::progress::Progress;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use vpmap_metrology::map::{BuildOptions, build_map};
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::{SynthOptions, synthesize};
use vpmap_plan::movingai::{Scenario, read_movingai_map, read_scen};
use vpmap_plan::reach::Components;
use vpmap_plan::{Occupancy, OccupancyGrid};
use vpmap_raster::{RasterOptions, rasterize_map};

/// A cell `(x, y)`: column, row from the top.
pub use vpmap_plan::CellXy;

/// Where the benchmark data lives by default, relative to the workspace root.
pub const MOVINGAI_RELATIVE: &str = "../shared/data/movingai";

/// Environment variable that names the Moving AI folder instead.
pub const MOVINGAI_ENV: &str = "VPMAP_MOVINGAI";

/// Unsolvable queries added to each map with more than one connected component: one from
/// the largest component to another, one the other way round.
pub const UNSOLVABLE_PER_MAP: usize = 2;

/// Candidate pairs drawn per wanted query when sampling a `.map`; the queries are spread
/// evenly over the candidates sorted by straight-line distance.
const CANDIDATES_PER_QUERY: usize = 20;

/// The default benchmark: `(category, map under maps/, scenario file under scen/)`.
///
/// `crates/vpmap-plan/benches/planners.rs` has a similar table (`MAPS`, four of these maps)
/// on purpose: they answer different questions. This one is the thesis's comparison (section
/// 6.2), one to three maps in each of its kinds of environment, so that every category row of
/// `vpmap bench`'s report and `docs/results.md` has maps behind it; the criterion bench keeps
/// four mid-sized maps so that its per-commit timings of the planners' inner loops (our A*
/// against `pathfinding::astar`) stay short and comparable across runs. Changing one must not
/// change the other, and the plan crate cannot depend on this one.
const DEFAULT_MAPS: [(&str, &str, &str); 18] = [
    (
        "free",
        "mapf/empty-48-48.map",
        "mapf/empty-48-48-random-1.scen",
    ),
    (
        "home-office",
        "rooms/8room_000.map",
        "rooms/8room_000.map.scen",
    ),
    (
        "home-office",
        "rooms/32room_000.map",
        "rooms/32room_000.map.scen",
    ),
    (
        "home-office",
        "mapf/room-64-64-8.map",
        "mapf/room-64-64-8-random-1.scen",
    ),
    (
        "home-office",
        "da2/ht_chantry.map",
        "da2/ht_chantry.map.scen",
    ),
    ("game", "dao/den520d.map", "dao/den520d.map.scen"),
    ("game", "dao/brc202d.map", "dao/brc202d.map.scen"),
    ("game", "dao/arena2.map", "dao/arena2.map.scen"),
    ("game", "bg512/AR0500SR.map", "bg512/AR0500SR.map.scen"),
    ("game", "sc1/Aftershock.map", "sc1/Aftershock.map.scen"),
    (
        "maze",
        "mazes/maze512-32-0.map",
        "mazes/maze512-32-0.map.scen",
    ),
    (
        "maze",
        "mazes/maze512-2-5.map",
        "mazes/maze512-2-5.map.scen",
    ),
    (
        "maze",
        "mapf/maze-128-128-2.map",
        "mapf/maze-128-128-2-random-1.scen",
    ),
    (
        "random",
        "mapf/random-64-64-20.map",
        "mapf/random-64-64-20-random-1.scen",
    ),
    (
        "random",
        "random/random512-10-0.map",
        "random/random512-10-0.map.scen",
    ),
    (
        "random",
        "random/random512-20-0.map",
        "random/random512-20-0.map.scen",
    ),
    (
        "city",
        "cities/Berlin_0_256.map",
        "cities/Berlin_0_256.map.scen",
    ),
    (
        "city",
        "cities/Milan_1_1024.map",
        "cities/Milan_1_1024.map.scen",
    ),
];

/// The order categories are reported in; others follow alphabetically.
pub const CATEGORY_ORDER: [&str; 8] = [
    "free",
    "home-office",
    "game",
    "maze",
    "random",
    "city",
    "built",
    "generated",
];

/// The bundled example scene (`examples/office.json`).
const EXAMPLE_SCENE: &str = vpmap_pipeline::demo::EXAMPLE_SCENE;

/// Cell size of the built maps, metres.
pub const BUILT_RESOLUTION_M: f64 = 0.05;

/// Robot radius the built maps' obstacles are inflated by, metres.
pub const BUILT_ROBOT_RADIUS_M: f64 = 0.1;

/// The synthetic room scenes of the built maps: `(name, seed, boxes, prisms)`.
const BUILT_SYNTHETIC: [(&str, u64, usize, usize); 2] =
    [("built-office-2", 7, 6, 1), ("built-office-3", 11, 8, 2)];

/// Where a query comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Origin {
    /// A problem of a `.scen` file, with its bucket and the file's octile optimum.
    Scen {
        /// The problem's bucket.
        bucket: u32,
        /// The octile optimal length printed in the file, cells.
        octile_optimum_cells: f64,
    },
    /// A random pair of free cells in one connected component.
    Sampled,
    /// A random pair of free cells in different connected components.
    Unsolvable,
}

impl Origin {
    /// The name written into the results.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Scen { .. } => "scen",
            Self::Sampled => "sampled",
            Self::Unsolvable => "unsolvable",
        }
    }
}

/// One planning problem.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Query {
    /// Start cell.
    pub start: CellXy,
    /// Goal cell.
    pub goal: CellXy,
    /// Where it comes from.
    pub origin: Origin,
}

/// A map with its queries.
pub struct BenchMap {
    /// Short name (file stem or generated name), unique within a run.
    pub name: String,
    /// The thesis's kind of environment: free, home-office, game, maze, random, city, built,
    /// generated, or `user` for a map the category of which is not known.
    pub category: String,
    /// Where it came from: a file path or how it was made.
    pub source: String,
    /// The grid (no unknown cells are entered).
    pub grid: OccupancyGrid,
    /// Its connected components, the reference for solvability.
    pub components: Components,
    /// The queries, solvable ones first.
    pub queries: Vec<Query>,
}

/// The Moving AI folder: `$VPMAP_MOVINGAI` when set, else `../shared/data/movingai` next to
/// the current folder or one of its ancestors, else next to the workspace this binary was
/// built from.
///
/// # Errors
/// The text to print when it is absent.
pub fn movingai_dir() -> Result<PathBuf, String> {
    if let Some(dir) = std::env::var_os(MOVINGAI_ENV) {
        let dir = PathBuf::from(dir);
        return if dir.is_dir() {
            Ok(dir)
        } else {
            Err(format!("{MOVINGAI_ENV}={} not found", dir.display()))
        };
    }
    let tail = Path::new("shared/data/movingai");
    if let Ok(cwd) = std::env::current_dir() {
        // `../shared` of the workspace root is `shared` of one of the current folder's
        // ancestors (the root itself or any folder inside it).
        for ancestor in cwd.ancestors().skip(1) {
            let dir = ancestor.join(tail);
            if dir.is_dir() {
                return Ok(dir);
            }
        }
    }
    let built_from = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../..")
        .join(tail);
    if built_from.is_dir() {
        return Ok(built_from);
    }
    Err(format!("{MOVINGAI_RELATIVE} not found"))
}

/// A seeded generator for one map: the same map name and seed give the same queries,
/// whatever else is in the run.
fn map_rng(seed: u64, name: &str) -> ChaCha8Rng {
    // FNV-1a of the name.
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    for b in name.bytes() {
        hash ^= u64::from(b);
        hash = hash.wrapping_mul(0x0100_0000_01b3);
    }
    ChaCha8Rng::seed_from_u64(seed ^ hash)
}

/// The category of a Moving AI map from its name and folder.
pub fn category_of(map_path: &Path) -> String {
    let stem = map_stem(map_path);
    if let Some((category, _, _)) = DEFAULT_MAPS
        .iter()
        .find(|(_, m, _)| map_stem(Path::new(m)) == stem)
    {
        return (*category).to_owned();
    }
    let folder = map_path
        .parent()
        .and_then(Path::file_name)
        .map(|f| f.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let by_folder = match folder.as_str() {
        "dao" | "da2" | "bg512" | "sc1" | "wc3maps512" | "dao-map" => Some("game"),
        "mazes" => Some("maze"),
        "random" => Some("random"),
        "rooms" => Some("home-office"),
        "cities" | "street" => Some("city"),
        _ => None,
    };
    let by_name = || {
        let s = stem.to_ascii_lowercase();
        if s.starts_with("empty") {
            Some("free")
        } else if s.starts_with("room") || s.contains("room_") {
            Some("home-office")
        } else if s.starts_with("maze") {
            Some("maze")
        } else if s.starts_with("random") {
            Some("random")
        } else {
            None
        }
    };
    by_folder.or_else(by_name).unwrap_or("user").to_owned()
}

fn map_stem(path: &Path) -> String {
    path.file_stem()
        .map_or_else(String::new, |s| s.to_string_lossy().into_owned())
}

/// Read a `.map` and sample its queries.
///
/// # Errors
/// When the file cannot be read or is not a Moving AI map.
pub fn load_map_file(path: &Path, per_map: usize, seed: u64) -> Result<BenchMap> {
    let grid = read_movingai_map(path)?;
    let name = map_stem(path);
    let components = Components::label(&grid, false);
    let mut rng = map_rng(seed, &name);
    let mut queries = sample_solvable(&components, per_map, &mut rng);
    queries.extend(sample_unsolvable(&components, &mut rng));
    Ok(BenchMap {
        category: category_of(path),
        source: path.display().to_string(),
        name,
        grid,
        components,
        queries,
    })
}

/// Read a `.scen` file and the maps it names; `per_map` problems per map, spread evenly
/// over the file's problems sorted by bucket. `extra_dirs` are searched for the maps too.
///
/// # Errors
/// When a file cannot be read or parsed, a map cannot be found, or a problem does not fit
/// its map.
pub fn load_scen_file(
    path: &Path,
    per_map: usize,
    seed: u64,
    extra_dirs: &[PathBuf],
) -> Result<Vec<BenchMap>> {
    let problems = read_scen(path)?;
    if problems.is_empty() {
        bail!("{}: the scenario file has no problems", path.display());
    }
    // Maps in order of first mention.
    let mut names: Vec<&str> = Vec::new();
    for p in &problems {
        if !names.contains(&p.map_file_name()) {
            names.push(p.map_file_name());
        }
    }
    let mut maps = Vec::with_capacity(names.len());
    for map_name in names {
        let map_path = find_scen_map(path, map_name, extra_dirs)?;
        let grid = read_movingai_map(&map_path)?;
        let mut mine: Vec<(usize, &Scenario)> = problems
            .iter()
            .enumerate()
            .filter(|(_, p)| p.map_file_name() == map_name)
            .collect();
        for &(i, p) in &mine {
            check_problem(path, i, p, &grid)?;
        }
        mine.sort_by_key(|(_, p)| p.bucket);
        let n = mine.len();
        let k = per_map.min(n);
        let mut queries: Vec<Query> = (0..k)
            .map(|i| {
                let p = mine[(2 * i + 1) * n / (2 * k)].1;
                Query {
                    start: p.start,
                    goal: p.goal,
                    origin: Origin::Scen {
                        bucket: p.bucket,
                        octile_optimum_cells: p.optimal_length_cells,
                    },
                }
            })
            .collect();
        let name = map_stem(&map_path);
        let components = Components::label(&grid, false);
        let mut rng = map_rng(seed, &name);
        queries.extend(sample_unsolvable(&components, &mut rng));
        maps.push(BenchMap {
            category: category_of(&map_path),
            source: format!("{} ({})", map_path.display(), path.display()),
            name,
            grid,
            components,
            queries,
        });
    }
    Ok(maps)
}

/// A scenario problem must fit its map and have its start and goal on free cells.
fn check_problem(scen: &Path, index: usize, p: &Scenario, grid: &OccupancyGrid) -> Result<()> {
    let (w, h) = (grid.width(), grid.height());
    if (p.width, p.height) != (w, h) {
        bail!(
            "{}: problem {} is for a {} x {} map, but {} is {w} x {h}",
            scen.display(),
            index + 1,
            p.width,
            p.height,
            p.map
        );
    }
    for (what, c) in [("start", p.start), ("goal", p.goal)] {
        if !grid.is_free(c.x, c.y) {
            bail!(
                "{}: problem {}: {what} ({}, {}) is not a free cell of {}",
                scen.display(),
                index + 1,
                c.x,
                c.y,
                p.map
            );
        }
    }
    Ok(())
}

/// Find the map a scenario file names: next to the file, in the Moving AI layout
/// (`scen/<set>/x.scen` beside `maps/<set>/x.map`), or in `extra_dirs`.
fn find_scen_map(scen: &Path, map_name: &str, extra_dirs: &[PathBuf]) -> Result<PathBuf> {
    let dir = scen
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let mut candidates = vec![dir.join(map_name)];
    if let Some(set) = dir.file_name() {
        candidates.push(dir.join("../../maps").join(set).join(map_name));
    }
    candidates.extend(extra_dirs.iter().map(|d| d.join(map_name)));
    candidates
        .iter()
        .find(|c| c.is_file())
        .cloned()
        .ok_or_else(|| {
            EvalError::Invalid(format!(
                "{}: cannot find its map {map_name} (looked in {})",
                scen.display(),
                candidates
                    .iter()
                    .filter_map(|c| c.parent())
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
}

/// `n` solvable queries: candidate pairs of distinct cells of one component (the start
/// uniform over the free cells of components with at least two cells, the goal uniform
/// over the start's component), sorted by straight-line distance and taken evenly spread.
pub fn sample_solvable(components: &Components, n: usize, rng: &mut ChaCha8Rng) -> Vec<Query> {
    let mut by_component: Vec<Vec<u32>> = vec![Vec::new(); components.count()];
    for (i, &l) in components.labels().iter().enumerate() {
        if l > 0 {
            by_component[l as usize - 1].push(i as u32);
        }
    }
    let eligible: Vec<u32> = by_component
        .iter()
        .filter(|c| c.len() >= 2)
        .flatten()
        .copied()
        .collect();
    if eligible.is_empty() || n == 0 {
        return Vec::new();
    }
    let mut candidates: Vec<(f64, CellXy, CellXy)> = (0..n * CANDIDATES_PER_QUERY)
        .map(|_| {
            let s = eligible[rng.random_range(0..eligible.len())] as usize;
            let cells = &by_component[components.labels()[s] as usize - 1];
            let g = loop {
                let g = cells[rng.random_range(0..cells.len())] as usize;
                if g != s {
                    break g;
                }
            };
            let (a, b) = (components.cell_at(s), components.cell_at(g));
            let d = (a.x.abs_diff(b.x) as f64).hypot(a.y.abs_diff(b.y) as f64);
            (d, a, b)
        })
        .collect();
    candidates.sort_by(|x, y| x.0.total_cmp(&y.0));
    let m = candidates.len();
    (0..n)
        .map(|i| {
            let (_, start, goal) = candidates[(2 * i + 1) * m / (2 * n)];
            Query {
                start,
                goal,
                origin: Origin::Sampled,
            }
        })
        .collect()
}

/// [`UNSOLVABLE_PER_MAP`] queries between different components when there are several:
/// from a cell of the largest component to a cell outside it, and back.
pub fn sample_unsolvable(components: &Components, rng: &mut ChaCha8Rng) -> Vec<Query> {
    if components.count() < 2 {
        return Vec::new();
    }
    let largest = (1..=components.count() as u32)
        .max_by_key(|&l| (components.size(l), std::cmp::Reverse(l)))
        .unwrap_or(1);
    let (inside, outside): (Vec<usize>, Vec<usize>) = components
        .labels()
        .iter()
        .enumerate()
        .filter(|(_, l)| **l > 0)
        .map(|(i, l)| (i, *l))
        .fold((Vec::new(), Vec::new()), |(mut a, mut b), (i, l)| {
            if l == largest {
                a.push(i);
            } else {
                b.push(i);
            }
            (a, b)
        });
    let pick = |cells: &[usize], rng: &mut ChaCha8Rng| {
        components.cell_at(cells[rng.random_range(0..cells.len())])
    };
    (0..UNSOLVABLE_PER_MAP)
        .map(|k| {
            let (a, b) = (pick(&inside, rng), pick(&outside, rng));
            let (start, goal) = if k % 2 == 0 { (a, b) } else { (b, a) };
            Query {
                start,
                goal,
                origin: Origin::Unsolvable,
            }
        })
        .collect()
}

/// A grid made in memory, with its name and category, before queries are sampled.
struct MadeGrid {
    name: String,
    category: &'static str,
    source: String,
    grid: OccupancyGrid,
}

fn with_sampled_queries(made: MadeGrid, per_map: usize, seed: u64) -> BenchMap {
    let components = Components::label(&made.grid, false);
    let mut rng = map_rng(seed, &made.name);
    let mut queries = sample_solvable(&components, per_map, &mut rng);
    queries.extend(sample_unsolvable(&components, &mut rng));
    BenchMap {
        name: made.name,
        category: made.category.to_owned(),
        source: made.source,
        grid: made.grid,
        components,
        queries,
    }
}

/// Occupancy grids built by vpmap from room scenes, like a robot would get from one photo:
/// the bundled example office and synthetic rooms, built by the side-view method and
/// rasterised at [`BUILT_RESOLUTION_M`] with obstacles grown by [`BUILT_ROBOT_RADIUS_M`];
/// floor hidden behind objects and the margin are unknown, which no planner enters.
///
/// # Errors
/// When a scene cannot be synthesised, built or rasterised.
pub fn built_maps(per_map: usize, seed: u64) -> Result<Vec<BenchMap>> {
    let raster = RasterOptions {
        resolution_m: BUILT_RESOLUTION_M,
        robot_radius_m: BUILT_ROBOT_RADIUS_M,
        ..RasterOptions::default()
    };
    let mut made = Vec::new();
    let scene = Scene::from_json_str(EXAMPLE_SCENE).context("the bundled example scene")?;
    let map = build_map(&scene, &BuildOptions::default()).context("building the example")?;
    made.push(MadeGrid {
        name: "built-office-1".to_owned(),
        category: "built",
        source: format!(
            "examples/office.json built by vpmap, {BUILT_RESOLUTION_M} m cells, robot radius {BUILT_ROBOT_RADIUS_M} m"
        ),
        grid: rasterize_map(&map, &raster).context("rasterising the example")?,
    });
    for (name, scene_seed, boxes, prisms) in BUILT_SYNTHETIC {
        let (scene, _) = synthesize(&SynthOptions {
            seed: scene_seed,
            boxes,
            prisms,
            ..SynthOptions::default()
        })
        .with_context(|| format!("synthesising the scene of {name}"))?;
        let map = build_map(&scene, &BuildOptions::default())
            .with_context(|| format!("building {name}"))?;
        made.push(MadeGrid {
            name: name.to_owned(),
            category: "built",
            source: format!(
                "synthetic room (seed {scene_seed}, {boxes} boxes, {prisms} prisms) built by vpmap, {BUILT_RESOLUTION_M} m cells, robot radius {BUILT_ROBOT_RADIUS_M} m"
            ),
            grid: rasterize_map(&map, &raster).with_context(|| format!("rasterising {name}"))?,
        });
    }
    Ok(made
        .into_iter()
        .map(|m| with_sampled_queries(m, per_map, seed))
        .collect())
}

/// Grids generated without the benchmark data: an empty room, rooms with doors (one room
/// closed, so that there is a second component) and random obstacles.
///
/// # Errors
/// When a grid cannot be made.
pub fn generated_maps(per_map: usize, seed: u64) -> Result<Vec<BenchMap>> {
    let mut made = vec![MadeGrid {
        name: "generated-empty-48".to_owned(),
        category: "free",
        source: "generated: 48 x 48, no obstacles".to_owned(),
        grid: OccupancyGrid::new(48, 48, 1.0, [0.0; 2], Occupancy::Free)?,
    }];
    made.push(MadeGrid {
        name: "generated-rooms-128".to_owned(),
        category: "home-office",
        source: "generated: 128 x 128, 8 x 8 rooms of 15 cells with doors, one room closed"
            .to_owned(),
        grid: rooms_grid(128, 16)?,
    });
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let cells = (0..128 * 128)
        .map(|_| {
            if rng.random_bool(0.2) {
                Occupancy::Occupied
            } else {
                Occupancy::Free
            }
        })
        .collect();
    made.push(MadeGrid {
        name: "generated-random-128".to_owned(),
        category: "random",
        source: format!("generated: 128 x 128, 20 % random obstacles (seed {seed})"),
        grid: OccupancyGrid::from_cells(128, 128, 1.0, [0.0; 2], cells)?,
    });
    Ok(made
        .into_iter()
        .map(|m| with_sampled_queries(m, per_map, seed))
        .collect())
}

/// A `side x side` grid of square rooms of `room` cells (walls one cell thick on the room
/// grid lines), each wall with a door of three cells in its middle, except the walls of the
/// second room of the first row, which is closed.
fn rooms_grid(side: usize, room: usize) -> Result<OccupancyGrid> {
    let mut grid = OccupancyGrid::new(side, side, 1.0, [0.0; 2], Occupancy::Free)?;
    let door = |i: usize| {
        let k = i % room;
        k + 1 >= room / 2 && k <= room / 2 + 1
    };
    for y in 0..side {
        for x in 0..side {
            let on_vertical = x % room == room - 1;
            let on_horizontal = y % room == room - 1;
            let wall = (on_vertical && !door(y)) || (on_horizontal && !door(x));
            let wall = wall || (on_vertical && on_horizontal);
            // The closed room: columns room..2 room, rows 0..room.
            let closed = (x + 1 == room || x + 1 == 2 * room) && y < room
                || y + 1 == room && (room - 1..2 * room).contains(&x);
            if wall || closed {
                grid.set(x, y, Occupancy::Occupied)?;
            }
        }
    }
    Ok(grid)
}

/// The default benchmark maps found under `dir` (with their scenario files when present);
/// missing files are left out with a warning through `progress`.
///
/// # Errors
/// When a map or scenario file that is present cannot be read.
pub fn default_movingai_maps(
    dir: &Path,
    per_map: usize,
    seed: u64,
    progress: &dyn Progress,
) -> Result<Vec<BenchMap>> {
    let mut maps = Vec::new();
    for (category, map, scen) in DEFAULT_MAPS {
        let map_path = dir.join("maps").join(map);
        let scen_path = dir.join("scen").join(scen);
        if !map_path.is_file() {
            progress.warn(&format!("{} not found; left out", map_path.display()));
            continue;
        }
        let mut loaded = if scen_path.is_file() {
            load_scen_file(
                &scen_path,
                per_map,
                seed,
                &[map_path
                    .parent()
                    .map_or_else(PathBuf::new, Path::to_path_buf)],
            )?
        } else {
            vec![load_map_file(&map_path, per_map, seed)?]
        };
        for m in &mut loaded {
            category.clone_into(&mut m.category);
        }
        maps.extend(loaded);
    }
    Ok(maps)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(rows: &[&str]) -> OccupancyGrid {
        let cells = rows
            .iter()
            .flat_map(|r| {
                r.chars().map(|c| {
                    if c == '@' {
                        Occupancy::Occupied
                    } else {
                        Occupancy::Free
                    }
                })
            })
            .collect();
        OccupancyGrid::from_cells(rows[0].len(), rows.len(), 1.0, [0.0; 2], cells)
            .unwrap_or_else(|e| panic!("bad test grid: {e}"))
    }

    #[test]
    fn diagonal_touching_cells_are_separate_components() {
        // The two free cells touch only at a corner: no corner cutting, no path.
        let g = grid(&[".@", "@.", "@@"]);
        let c = Components::label(&g, false);
        assert_eq!(c.count(), 2);
        assert!(!c.connected((0, 0), (1, 1)));
        assert!(c.connected((0, 0), (0, 0)));
        assert_eq!(c.of((0, 1)), None);
        assert_eq!(c.of((5, 0)), None);
    }

    #[test]
    fn sampled_queries_are_solvable_and_unsolvable_ones_are_not() {
        let g = grid(&["....@...", "....@...", "....@...", "....@..."]);
        let c = Components::label(&g, false);
        let mut rng = map_rng(1, "x");
        let solvable = sample_solvable(&c, 5, &mut rng);
        assert_eq!(solvable.len(), 5);
        assert!(
            solvable
                .iter()
                .all(|q| q.start != q.goal && c.connected(q.start, q.goal))
        );
        // Spread over lengths: sorted by distance.
        let d = |q: &Query| {
            (q.start.x.abs_diff(q.goal.x) as f64).hypot(q.start.y.abs_diff(q.goal.y) as f64)
        };
        assert!(solvable.windows(2).all(|w| d(&w[0]) <= d(&w[1])));
        let unsolvable = sample_unsolvable(&c, &mut rng);
        assert_eq!(unsolvable.len(), UNSOLVABLE_PER_MAP);
        assert!(unsolvable.iter().all(|q| !c.connected(q.start, q.goal)
            && c.of(q.start).is_some()
            && c.of(q.goal).is_some()));
        let one = Components::label(&grid(&["...", "..."]), false);
        assert!(sample_unsolvable(&one, &mut rng).is_empty());
    }

    #[test]
    fn the_rooms_grid_has_a_closed_room() {
        let g = rooms_grid(64, 16).unwrap_or_else(|e| panic!("{e}"));
        let c = Components::label(&g, false);
        assert_eq!(c.count(), 2);
        assert!(c.connected((0, 0), (62, 62)));
        assert!(!c.connected((0, 0), (20, 5)));
    }

    #[test]
    fn categories_come_from_names_and_folders() {
        assert_eq!(category_of(Path::new("x/dao/den520d.map")), "game");
        assert_eq!(category_of(Path::new("maps/mapf/empty-8-8.map")), "free");
        assert_eq!(category_of(Path::new("/t/dao/lak303d.map")), "game");
        assert_eq!(category_of(Path::new("a.map")), "user");
        assert_eq!(category_of(Path::new("room-32-32-4.map")), "home-office");
    }
}
