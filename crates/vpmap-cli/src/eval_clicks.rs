//! `vpmap eval-clicks`: snapped against raw clicks on rendered photos
//! ([`vpmap_eval::clicks`]); `--publish` writes its section of `docs/results.md`.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use vpmap_eval::clicks::{
    CLICKS_SECTION, Config, example_files, published_section, summary_markdown,
};

/// Arguments of `vpmap eval-clicks`.
#[derive(clap::Args)]
pub struct EvalClicksArgs {
    /// Output folder: summary.md, and example.jpg with its clicked scene to try `vpmap snap` on.
    #[arg(long, short, default_value = "out/clicks")]
    pub out: PathBuf,
    /// Rooms drawn (each rendered once, clicked at every noise level).
    #[arg(long, default_value_t = Config::default().trials)]
    pub trials: u64,
    /// Click noise levels, pixels (1 sigma per coordinate), comma-separated.
    #[arg(long, default_value = "1,2,3")]
    pub sigma: String,
    /// Seed of the rooms, photos and noise.
    #[arg(long, default_value_t = Config::default().seed)]
    pub seed: u64,
    /// Replace the `eval-clicks` section of this Markdown file (e.g. docs/results.md).
    #[arg(long)]
    pub publish: Option<PathBuf>,
}

/// Run `vpmap eval-clicks`.
pub fn run(args: &EvalClicksArgs) -> Result<()> {
    let mut sigmas = Vec::new();
    for part in args.sigma.split(',') {
        let v: f64 = part
            .trim()
            .parse()
            .with_context(|| format!("--sigma {:?}: {part:?} is not a number", args.sigma))?;
        if !(v.is_finite() && v > 0.0 && v <= 10.0) {
            bail!("--sigma {:?}: {v} must lie in (0, 10] pixels", args.sigma);
        }
        sigmas.push(v);
    }
    if !(1..=10_000).contains(&args.trials) {
        bail!("--trials {} must be from 1 to 10000", args.trials);
    }
    let config = Config {
        trials: args.trials,
        sigmas_px: sigmas,
        seed: args.seed,
        ..Config::default()
    };
    vpmap_eval::output::check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        if path.is_dir() {
            bail!(
                "--publish {} is a folder; give a Markdown file",
                path.display()
            );
        }
        vpmap_eval::publish::check_section(path, CLICKS_SECTION)?;
    }
    let started = std::time::Instant::now();
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} rooms", "40");
    let results = vpmap_eval::clicks::run(&config, &bar);
    let elapsed = started.elapsed();
    let command = crate::output::command_line();
    let body = summary_markdown(&config, &results);
    let md = format!("# Snapping clicks to the photo\n\n{body}\nMeasured with `{command}`.\n");
    let mut files = example_files(&config, 2.0)?;
    files.add("summary.md", md.clone());
    files.write_all(&args.out)?;
    if let Some(path) = &args.publish {
        let section = published_section(&config, &results, elapsed, &command);
        vpmap_eval::publish::replace_section(path, CLICKS_SECTION, &section)?;
    }
    print!("{md}");
    println!(
        "wrote summary.md, example.jpg, example-scene.json, example-truth.json in {} (try: vpmap snap {0}/example.jpg {0}/example-scene.json -o {0}/snapped.json)",
        args.out.display()
    );
    if let Some(path) = &args.publish {
        println!(
            "published the {CLICKS_SECTION} section of {}",
            path.display()
        );
    }
    Ok(())
}
