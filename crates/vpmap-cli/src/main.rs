//! The `vpmap` command: one photo's annotations to a metric floor map.
//!
//! Flags, progress and printing only; the work is in the library crates. Modules, bottom-up
//! (each uses only those before it): `output` (files written all or nothing, the command
//! line as typed), `progress` (the bar), `memory` (the counting allocator), then one module
//! per command: `synth`, `build` (and `demo`), `plan`, `navigate` (uses `plan`'s map loading
//! and flag helpers), `eval`, `bench`, `detect` (inside: `options`, `eval` for
//! `eval-detect`, then its `mod.rs`), `serve`, `snap`, `eval_clicks`; this file parses the command line and
//! dispatches.

mod bench;
mod build;
mod detect;
mod eval;
mod eval_clicks;
mod memory;
mod navigate;
mod output;
mod plan;
mod progress;
mod serve;
mod snap;
mod synth;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use vpmap_metrology::reconstruct::Method;

/// One ordinary photo of a room in, a metric floor map a robot can use out.
#[derive(Parser)]
#[command(name = "vpmap", version, about, long_about = None, allow_negative_numbers = true)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build a floor map, picture, 3D model and occupancy grid from a scene file.
    Build {
        /// The scene file (JSON, version 1; see docs/scene-format.md).
        scene: PathBuf,
        #[command(flatten)]
        args: build::BuildArgs,
    },
    /// Build the bundled example end to end and compare it with its known truth.
    Demo {
        /// Output folder.
        #[arg(long, short, default_value = "out/demo")]
        out: PathBuf,
        /// Reconstruction method: fit, sideview or projective.
        #[arg(long, default_value = "fit", value_parser = build::parse_method)]
        method: Method,
    },
    /// Write a random synthetic scene (and its truth) from the built-in pinhole camera.
    Synth(synth::SynthArgs),
    /// Plan a path across a Moving AI map, a ROS map or a vpmap map.json.
    Plan(plan::PlanArgs),
    /// Drive a robot across a believed map, sensing the true one and re-planning.
    Navigate(navigate::NavigateArgs),
    /// Measure map accuracy under annotation noise on synthetic scenes (the thesis's 6.1).
    Eval(eval::EvalArgs),
    /// Compare planners on benchmark maps (the thesis's 6.2).
    Bench(bench::BenchArgs),
    /// Find line segments, vanishing points and the camera in a photo; write a scene file.
    Detect(detect::DetectArgs),
    /// Measure vanishing-point detection on a folder of labelled photos (York Urban format).
    EvalDetect(detect::EvalDetectArgs),
    /// Serve the local web page (annotate a photo, see its map, 3D model and path).
    Serve(serve::ServeArgs),
    /// Measure snapping against raw clicks on rendered photos (and the box proposals).
    EvalClicks(eval_clicks::EvalClicksArgs),
    /// Snap a scene's clicks to the photo's corners; write the scene with their covariances.
    Snap(snap::SnapArgs),
}

/// Parse the command line; usage errors become one line (`error: ...`) and exit code 2.
fn parse_cli() -> Result<Cli, ExitCode> {
    match Cli::try_parse() {
        Ok(cli) => Ok(cli),
        Err(e) => {
            use clap::error::ErrorKind;
            if matches!(
                e.kind(),
                ErrorKind::DisplayHelp
                    | ErrorKind::DisplayVersion
                    | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
            ) {
                let _ = e.print();
                return Err(if e.use_stderr() {
                    ExitCode::from(2)
                } else {
                    ExitCode::SUCCESS
                });
            }
            let text = e.to_string();
            let first = text
                .lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("invalid arguments")
                .trim_start_matches("error: ");
            eprintln!("error: {first} (see vpmap --help)");
            Err(ExitCode::from(2))
        }
    }
}

fn main() -> ExitCode {
    let cli = match parse_cli() {
        Ok(cli) => cli,
        Err(code) => return code,
    };
    let result = match cli.command {
        Command::Build { scene, args } => build::run_build(&scene, &args),
        Command::Demo { out, method } => build::run_demo(&out, method),
        Command::Synth(args) => synth::run(&args),
        Command::Plan(args) => plan::run(&args),
        Command::Navigate(args) => navigate::run(&args),
        Command::Eval(args) => eval::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Detect(args) => detect::run_detect(&args),
        Command::EvalDetect(args) => detect::run_eval_detect(&args),
        Command::Serve(args) => serve::run(&args),
        Command::Snap(args) => snap::run(&args),
        Command::EvalClicks(args) => eval_clicks::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("error: {err:#}");
            ExitCode::FAILURE
        }
    }
}
