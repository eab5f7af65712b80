//! `pickplace plan SCENE` and `pickplace validate SCENE PLAN`.

use crate::output::note;
use pickplace::StrategyChoice;
use pickplace::planner::{Outcome, PlanOptions, PlanOverrides};
use pickplace::{Plan, Setup, SetupOptions};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// `--strategy`'s values: the façade's names ([`StrategyChoice`]), each with its summary in
/// `--help`.
pub fn strategy_parser() -> impl clap::builder::TypedValueParser<Value = StrategyChoice> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(
        StrategyChoice::all().map(|c| PossibleValue::new(c.name()).help(c.summary())),
    )
    .try_map(|name| name.parse::<StrategyChoice>())
}

/// Arguments of `pickplace plan`.
#[derive(Debug, clap::Args)]
pub struct PlanArgs {
    /// Scene file (TOML, docs/scene-format.md).
    pub scene: PathBuf,
    /// Where to write the plan (JSON, docs/plan-format.md); default: print it on stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Seed of every random choice (default: the scene's planner.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Manipulation strategy (default: the scene's planner.strategy).
    #[arg(long, value_parser = strategy_parser())]
    pub strategy: Option<StrategyChoice>,
    /// Leave the stage timings out of the plan, so that the same seed gives the same bytes.
    #[arg(long)]
    pub no_timings: bool,
    #[command(flatten)]
    pub timing: crate::args::TimingArgs,
    #[command(flatten)]
    pub folders: crate::args::SceneFolders,
}

/// A scaling factor in [`pickplace::ranges::SCALING`].
pub fn scaling_factor(text: &str) -> Result<f64, pickplace::ranges::FlagError> {
    pickplace::ranges::parse_flag(text, pickplace::ranges::SCALING)
}

/// A sample period in [`pickplace::ranges::SAMPLE_PERIOD`] (finer would make huge files,
/// coarser would hide motion).
pub fn sample_period(text: &str) -> Result<f64, pickplace::ranges::FlagError> {
    pickplace::ranges::parse_flag(text, pickplace::ranges::SAMPLE_PERIOD)
}

/// Which cache folder a command's setup uses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CacheChoice {
    /// The per-user folder ([`pickplace::cache::default_dir`]).
    Default,
    /// The folder given (`--cache DIR`).
    Folder(PathBuf),
    /// No cache (`--no-cache`).
    Off,
}

impl CacheChoice {
    /// The choice of `--cache DIR` and `--no-cache` (clap makes them exclusive).
    pub fn from_args(cache: Option<&Path>, no_cache: bool) -> Self {
        match (cache, no_cache) {
            (_, true) => Self::Off,
            (Some(dir), false) => Self::Folder(dir.to_path_buf()),
            (None, false) => Self::Default,
        }
    }

    /// The folder chosen, if any: the per-user folder when it can be found (else a warning on
    /// stderr and none).
    pub fn folder(self) -> Option<PathBuf> {
        match self {
            Self::Folder(dir) => Some(dir),
            Self::Off => None,
            Self::Default => match pickplace::cache::default_dir() {
                Ok(dir) => Some(dir),
                Err(warning) => {
                    note!("warning: {warning}");
                    None
                }
            },
        }
    }
}

/// The setup options of a command's `--cache`/`--no-cache` choice and `--package-dir`
/// folders, with progress on stderr.
pub fn setup_options(cache: CacheChoice, package_dirs: &[PathBuf]) -> SetupOptions {
    SetupOptions {
        cache_dir: cache.folder(),
        package_dirs: package_dirs.to_vec(),
        progress: crate::progress::receiver(),
    }
}

/// Loads a scene with its log, the cache's warning (if any) and progress on stderr.
pub fn setup(scene: &Path, cache: CacheChoice, package_dirs: &[PathBuf]) -> anyhow::Result<Setup> {
    setup_with(scene, cache, package_dirs, |options| {
        Setup::load(scene, options)
    })
}

/// [`setup`] by another loader: `plan` sets up the scene it has parsed, `validate` only what
/// the validator reads (issue 33).
fn setup_with(
    scene: &Path,
    cache: CacheChoice,
    package_dirs: &[PathBuf],
    load: impl FnOnce(&SetupOptions) -> Result<Setup, pickplace::Error>,
) -> anyhow::Result<Setup> {
    let t = Instant::now();
    let options = setup_options(cache, package_dirs);
    let setup = load(&options)?;
    for warning in &setup.warnings {
        note!("warning: {warning}");
    }
    for warning in &setup.mesh_warnings {
        note!("warning: {warning}");
    }
    for line in &setup.log {
        note!("  {line}");
    }
    note!(
        "  scene {} set up in {:.0} ms",
        scene.display(),
        t.elapsed().as_secs_f64() * 1e3
    );
    Ok(setup)
}

/// Plans a loaded scene and prints a summary on stderr; the outcome is returned.
pub fn plan_setup(setup: &Setup, args: &PlanArgs) -> anyhow::Result<Outcome> {
    let overrides = PlanOverrides {
        seed: args.seed,
        strategy: args.strategy,
        timings: Some(!args.no_timings),
        ..args.timing.overrides()
    };
    let options = PlanOptions::with_overrides(setup, &overrides);
    let t = Instant::now();
    let outcome = pickplace::plan(setup, &options)?;
    let elapsed = t.elapsed().as_secs_f64() * 1e3;
    match &outcome {
        Outcome::Planned(plan) => {
            for s in &plan.stats.strategies {
                note!(
                    "  {}: {}",
                    s.strategy,
                    if s.success { "planned" } else { "failed" }
                );
            }
            note!(
                "  plan: {} with a {} placement on {:?} (margin {:.1} mm), {} grasp(s), {} key poses, {:.2} s of motion, {} samples; planned in {elapsed:.1} ms",
                plan.strategy,
                plan.placement.contact,
                plan.placement.environment,
                plan.placement.stability_margin * 1e3,
                plan.grasps.len(),
                plan.key_poses.len(),
                plan.stats.duration,
                plan.trajectory.len()
            );
        }
        Outcome::NoPlan(failure) => {
            note!("  no plan ({elapsed:.1} ms):");
            for r in &failure.reasons {
                note!("    {r}");
            }
        }
    }
    Ok(outcome)
}

/// Runs `pickplace plan`.
pub fn run(args: &PlanArgs) -> anyhow::Result<ExitCode> {
    note!("pickplace plan {}", args.scene.display());
    // Parsed once: the output is checked against its inputs, then the scene is set up.
    let scene = pickplace::Scene::load(&args.scene)?;
    if let Some(out) = &args.out {
        // Before any work: the plan must not replace a link, a device or an input.
        let inputs = crate::args::scene_inputs(&args.scene, &scene);
        crate::args::check_output_file(out, "--out", &crate::args::as_inputs(&inputs))?;
    }
    let cache = args.folders.cache_choice();
    let setup = setup_with(&args.scene, cache, &args.folders.package_dirs, |options| {
        Setup::new(scene, &args.scene, options)
    })?;
    match plan_setup(&setup, args)? {
        Outcome::Planned(plan) => {
            crate::output::write_or_print(args.out.as_deref(), &plan.to_json(), "the plan")?;
            Ok(ExitCode::SUCCESS)
        }
        Outcome::NoPlan(_) => Ok(ExitCode::from(1)),
    }
}

/// Arguments of `pickplace validate`.
#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// Scene file the plan was made for.
    pub scene: PathBuf,
    /// Plan file.
    pub plan: PathBuf,
    /// Print the report as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub folders: crate::args::SceneFolders,
}

/// Runs `pickplace validate`: exit 0 when the plan passes, 1 when it does not.
pub fn run_validate(args: &ValidateArgs) -> anyhow::Result<ExitCode> {
    note!(
        "pickplace validate {} {}",
        args.scene.display(),
        args.plan.display()
    );
    let plan = Plan::load(&args.plan)?;
    let cache = args.folders.cache_choice();
    let setup = setup_with(&args.scene, cache, &args.folders.package_dirs, |options| {
        Setup::load_for_validation(&args.scene, options)
    })?;
    let t = Instant::now();
    let report = pickplace::validate::validate(&setup, &plan, &args.plan)?;
    note!(
        "  checked {} states over {:.2} s of motion in {:.0} ms",
        report.states_checked,
        report.duration,
        t.elapsed().as_secs_f64() * 1e3
    );
    if args.json {
        crate::output::print_json(&report)?;
    }
    if report.problems.is_empty() {
        note!("  valid");
        Ok(ExitCode::SUCCESS)
    } else {
        for p in report.problems.iter().take(20) {
            note!("  {p}");
        }
        if report.problems.len() > 20 {
            note!("  … {} problems in all", report.problems.len());
        }
        Ok(ExitCode::from(1))
    }
}
