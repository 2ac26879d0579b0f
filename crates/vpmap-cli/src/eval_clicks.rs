//! `vpmap eval-clicks`: snapped against raw clicks on rendered photos
//! ([`vpmap_eval::clicks`]); `--publish` writes its section of `docs/results.md`.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use vpmap_eval::clicks::{
    CLICKS_SECTION, CLUTTERED_SECTION, Config, example_files, published_section, summary_markdown,
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
    /// Replace the `eval-clicks` section of this Markdown file (e.g. docs/results.md); with
    /// `--yud`, the `eval-clicks-yud` section.
    #[arg(long)]
    pub publish: Option<PathBuf>,
    /// Measure on real photos instead: the labelled corners of the York Urban photos in this
    /// folder (`<name>.jpg` + `<name>.json`), clicked `--yud-sigma` px off; writes yud.md.
    #[arg(long)]
    pub yud: Option<PathBuf>,
    /// Render the rooms as real photos look: clutter near the corners, occluding bars, blur
    /// growing off-centre, JPEG at quality 85, barrel distortion (section
    /// `eval-clicks-cluttered` with --publish).
    #[arg(long)]
    pub cluttered: bool,
    /// The click noise of `--yud`, pixels (1 sigma per coordinate).
    #[arg(long, default_value_t = 2.0)]
    pub yud_sigma: f64,
}

/// Run `vpmap eval-clicks --yud DIR`.
fn run_yud(args: &EvalClicksArgs, dir: &std::path::Path) -> Result<()> {
    use vpmap_eval::clicks::yud::{
        YUD_SECTION, YudConfig, run_yud, yud_markdown, yud_published_section,
    };
    if !(args.yud_sigma.is_finite() && args.yud_sigma > 0.0 && args.yud_sigma <= 10.0) {
        bail!("--yud-sigma {} must lie in (0, 10] pixels", args.yud_sigma);
    }
    let config = YudConfig {
        sigma_px: args.yud_sigma,
        seed: args.seed,
        ..YudConfig::default()
    };
    vpmap_eval::output::check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        if path.is_dir() {
            bail!(
                "--publish {} is a folder; give a Markdown file",
                path.display()
            );
        }
        vpmap_eval::publish::check_section(path, YUD_SECTION)?;
    }
    let started = std::time::Instant::now();
    let bar = crate::progress::Bar::new("{elapsed_precise} [{bar}] {pos}/{len} photos", "40");
    let results = run_yud(dir, &config, &bar)?;
    let elapsed = started.elapsed();
    let command = crate::output::command_line();
    let md = format!(
        "# Snapping clicks on real photos\n\n{}\nMeasured with `{command}`.\n",
        yud_markdown(&config, &results)
    );
    let mut files = vpmap_eval::output::OutputSet::default();
    files.add("yud.md", md.clone());
    files.write_all(&args.out)?;
    if let Some(path) = &args.publish {
        let section = yud_published_section(&config, &results, elapsed, &command);
        vpmap_eval::publish::replace_section(path, YUD_SECTION, &section)?;
    }
    print!("{md}");
    println!("wrote yud.md in {}", args.out.display());
    if let Some(path) = &args.publish {
        println!("published the {YUD_SECTION} section of {}", path.display());
    }
    Ok(())
}

/// Run `vpmap eval-clicks`.
pub fn run(args: &EvalClicksArgs) -> Result<()> {
    if let Some(dir) = &args.yud {
        return run_yud(args, dir);
    }
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
        cluttered: args.cluttered,
        ..Config::default()
    };
    let section_name = if args.cluttered {
        CLUTTERED_SECTION
    } else {
        CLICKS_SECTION
    };
    vpmap_eval::output::check_writable_folder(&args.out)?;
    if let Some(path) = &args.publish {
        if path.is_dir() {
            bail!(
                "--publish {} is a folder; give a Markdown file",
                path.display()
            );
        }
        vpmap_eval::publish::check_section(path, section_name)?;
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
        vpmap_eval::publish::replace_section(path, section_name, &section)?;
    }
    print!("{md}");
    println!(
        "wrote summary.md, example.jpg, example-scene.json, example-truth.json in {} (try: vpmap snap {0}/example.jpg {0}/example-scene.json -o {0}/snapped.json)",
        args.out.display()
    );
    if let Some(path) = &args.publish {
        println!("published the {section_name} section of {}", path.display());
    }
    Ok(())
}
