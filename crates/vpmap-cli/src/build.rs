//! `vpmap build` and `vpmap demo`.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use vpmap_metrology::map::FloorMap;
use vpmap_metrology::reconstruct::Method;
use vpmap_metrology::scene::Scene;
use vpmap_metrology::synth::Truth;
use vpmap_pipeline::demo::{EXAMPLE_SCENE, EXAMPLE_TRUTH};
use vpmap_pipeline::{MapOptions, PipelineError, TruthErrors, errors_against_truth};
use vpmap_plan::grid::OccupancyGrid;
use vpmap_render::{FloorPlanStyle, floor_plan_svg, svg_to_png};

use crate::output::OutputSet;
use vpmap_pipeline::num;

/// The scene file at `path`, read by the pipeline's one scene reader; unknown fields are
/// warned about on stderr.
fn read_scene(path: &Path) -> Result<Scene> {
    let text = vpmap_files::read_text(path, vpmap_files::Format::Scene)?;
    // Editors on Windows may start the file with a byte-order mark; it is not JSON.
    let text = text.strip_prefix('\u{feff}').unwrap_or(&text);
    let (scene, warnings) = match vpmap_pipeline::parse_scene(text) {
        Ok(parsed) => (Ok(parsed.scene), parsed.warnings),
        Err(PipelineError::SceneNotAnObject) => bail!(
            "{}: scene file is malformed: it must be a JSON object ({{ ... }})",
            path.display()
        ),
        Err(PipelineError::SceneJson(e)) => {
            bail!("{}: scene file is malformed: {e}", path.display())
        }
        Err(PipelineError::InvalidScene { error, warnings }) => (Err(error), warnings),
        Err(other) => return Err(other.into()),
    };
    for w in warnings {
        eprintln!("warning: {}: {w}", path.display());
    }
    scene.with_context(|| format!("{}", path.display()))
}

/// Options shared by `build` and `demo`.
#[derive(clap::Args, Clone)]
pub struct BuildArgs {
    /// Output folder (created if missing).
    #[arg(long, short)]
    pub out: PathBuf,
    /// Reconstruction method: `fit`, the joint maximum-likelihood fit of the camera and every
    /// object to all clicks, with error bars; `sideview`, the thesis's method; `projective`,
    /// the camera-matrix form (see docs/method.md).
    #[arg(long, default_value = "fit", value_parser = parse_method)]
    pub method: Method,
    /// Click noise the fit's error bars are computed for, pixels (1 sigma per coordinate;
    /// default: estimated from the residuals when the clicks over-determine the model, else 1).
    #[arg(long, allow_negative_numbers = true)]
    pub click_sigma: Option<f64>,
    /// Grow each obstacle in the occupancy grid by its uncertainty at this confidence (e.g.
    /// 0.95), so a robot keeps clear of what is not known well (method fit).
    #[arg(long, allow_negative_numbers = true)]
    pub grow_confidence: Option<f64>,
    /// Occupancy-grid cell size, metres (map units when the scene has no scale).
    #[arg(long, default_value_t = vpmap_pipeline::DEFAULT_RESOLUTION_M, allow_negative_numbers = true)]
    pub resolution: f64,
    /// Robot radius: obstacles in the occupancy grid are inflated by it, metres (0 for a
    /// grid of the bare obstacles).
    #[arg(long, default_value_t = vpmap_pipeline::DEFAULT_ROBOT_RADIUS_M, allow_negative_numbers = true)]
    pub robot_radius: f64,
    /// Mark floor hidden behind objects as free in the occupancy grid (default: unknown).
    #[arg(long)]
    pub hidden_free: bool,
}

/// `--method`: a reconstruction method by its name.
pub fn parse_method(s: &str) -> Result<Method, String> {
    s.parse()
}

/// Everything `build` writes, rendered in memory.
struct Built {
    map: FloorMap,
    grid: OccupancyGrid,
    files: OutputSet,
}

/// The pipeline's options from the command line's.
fn map_options(args: &BuildArgs) -> MapOptions {
    MapOptions {
        method: args.method,
        resolution_m: args.resolution,
        robot_radius_m: args.robot_radius,
        hidden_free: args.hidden_free,
        max_grid_cells: Some(vpmap_plan::MAX_CELLS as f64),
        click_sigma_px: args.click_sigma,
        grow_confidence: args.grow_confidence,
    }
}

/// A pipeline failure, in the command line's words (flags, the file that failed).
fn pipeline_error(e: PipelineError) -> anyhow::Error {
    match e {
        PipelineError::OptionOutOfRange { option, value } => anyhow::anyhow!(
            "{} must be {}, got {}",
            option.flag(),
            option.requirement(),
            num(value)
        ),
        PipelineError::Model(e) => anyhow::Error::new(e).context("building model.glb"),
        PipelineError::Grid(e) => anyhow::Error::new(e).context("rasterising the occupancy grid"),
        e => anyhow::Error::new(e),
    }
}

fn build_outputs(scene: &Scene, args: &BuildArgs) -> Result<Built> {
    let built = vpmap_pipeline::build(scene, &map_options(args)).map_err(pipeline_error)?;
    let mut files = OutputSet::default();
    files.add("map.json", built.map.to_json_string());
    files.add("model.glb", built.model_glb);
    files.add("occupancy.yaml", built.occupancy_yaml);
    files.add("occupancy.pgm", built.occupancy_pgm);
    Ok(Built {
        map: built.map,
        grid: built.grid,
        files,
    })
}

/// Render the floor plan (`map.svg`, `map.png`) into the output set: the last step, so that a
/// caller can add a planned path to the style first.
fn add_pictures(built: &mut Built, style: &FloorPlanStyle) -> Result<()> {
    let svg = floor_plan_svg(&built.map, style);
    built
        .files
        .add("map.png", svg_to_png(&svg).context("rendering map.png")?);
    built.files.add("map.svg", svg);
    Ok(())
}

/// What `build` and `demo` print of the map ([`vpmap_pipeline::map_summary`]), and its
/// warnings on stderr (many objects placed poorly in one line:
/// [`vpmap_pipeline::printed_warnings`]).
fn print_summary(built: &Built) {
    print!("{}", vpmap_pipeline::map_summary(&built.map, &built.grid));
    for w in vpmap_pipeline::printed_warnings(&built.map) {
        eprintln!("warning: {w}");
    }
}

fn report_written(paths: &[PathBuf]) {
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            p.file_name()
                .map_or_else(String::new, |n| n.to_string_lossy().into_owned())
        })
        .collect();
    if let Some(dir) = paths.first().and_then(|p| p.parent()) {
        println!("wrote {} in {}", names.join(", "), dir.display());
    }
}

/// `vpmap build SCENE --out DIR`.
pub fn run_build(scene_path: &Path, args: &BuildArgs) -> Result<()> {
    let scene = read_scene(scene_path)?;
    let built = build_outputs(&scene, args)
        .and_then(|mut b| add_pictures(&mut b, &FloorPlanStyle::default()).map(|()| b))
        .with_context(|| format!("building {}", scene_path.display()))?;
    let paths = built.files.write_all(&args.out)?;
    print_summary(&built);
    report_written(&paths);
    Ok(())
}

/// `vpmap demo`: the bundled example, end to end.
pub fn run_demo(out: &Path, method: Method) -> Result<()> {
    let scene = Scene::from_json_str(EXAMPLE_SCENE).context("the bundled example scene")?;
    let truth: Truth =
        serde_json::from_str(EXAMPLE_TRUTH).context("the bundled example's truth")?;
    println!(
        "vpmap demo: examples/office.json, a synthetic office photographed from {:.2} m at {:.0} deg pitch and {:.0} deg roll",
        truth.camera.height, truth.camera.pitch_deg, truth.camera.roll_deg
    );
    let args = BuildArgs {
        out: out.to_path_buf(),
        method,
        resolution: vpmap_pipeline::DEFAULT_RESOLUTION_M,
        robot_radius: vpmap_pipeline::DEFAULT_ROBOT_RADIUS_M,
        hidden_free: false,
        click_sigma: None,
        grow_confidence: None,
    };
    let mut built = build_outputs(&scene, &args)?;
    let route = vpmap_pipeline::demo_path(&built.map, &built.grid)?;
    let (path_line, style) = vpmap_pipeline::demo_path_text(&route, out);
    add_pictures(&mut built, &style)?;
    let paths = built.files.write_all(out)?;
    print_summary(&built);
    println!("{path_line}");
    let TruthErrors {
        position: pos,
        height,
    } = errors_against_truth(&built.map, &truth);
    let c = &built.map.camera;
    println!(
        "error against the known truth ({method}): corners and floor {pos:.2e} m, heights {height:.2e} m, pitch {:.2e} deg, focal {:.2e} px",
        (c.pitch_deg - truth.camera.pitch_deg).abs(),
        (c.focal_px - truth.camera.focal_px).abs()
    );
    report_written(&paths);
    Ok(())
}
