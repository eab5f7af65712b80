//! `pickplace batch SCENE… --out DIR`: many scenes planned in parallel through
//! [`pickplace::batch::plan_many`], with a progress bar on stderr and a table on stdout.
//!
//! Exit status: 0 when every scene was planned (or skipped by `--resume`); 1 when some scene
//! has no plan (and none is bad input); 2 for bad usage (refused before any work: the output
//! folder, two scenes with the same file name, an option) or when some scene was bad input or
//! ended in an error. Each scene's outcome is in `DIR/summary.jsonl` (docs/batch.md).

use crate::output::{note, outln};
use crate::plan::{CacheChoice, strategy_parser};
use pickplace::StrategyChoice;
use pickplace::batch::{BatchEvent, BatchOptions, BatchReport, SceneStatus, plan_many};
use pickplace::planner::PlanOverrides;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::Duration;

/// Arguments of `pickplace batch`.
#[derive(Debug, clap::Args)]
pub struct BatchArgs {
    /// Scene files (TOML, docs/scene-format.md); each plan is written to DIR/<file stem>.json,
    /// so the file names must differ.
    #[arg(required = true, value_name = "SCENE")]
    pub scenes: Vec<PathBuf>,
    /// Folder of the plans and of summary.jsonl (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Threads in all (default: the machine's available parallelism).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=4096))]
    pub jobs: Option<u32>,
    /// Seed of every scene's random choices (default: each scene's planner.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// Manipulation strategy of every scene (default: each scene's planner.strategy).
    #[arg(long, value_parser = strategy_parser())]
    pub strategy: Option<StrategyChoice>,
    /// Wall-clock budget of each scene's plan, seconds, 0 or more (default: each scene's
    /// planner.time_budget).
    #[arg(long, value_name = "SECONDS", value_parser = time_budget)]
    pub time_budget: Option<f64>,
    #[command(flatten)]
    pub timing: crate::args::TimingArgs,
    /// Keep the plans already in DIR that are valid for their scene and this batch's seed
    /// (their line says "skipped"); any other plan file is planned again.
    #[arg(long)]
    pub resume: bool,
    /// Leave the stage timings out of the plans and the times out of the summary, so that
    /// the same scenes and seed give the same bytes.
    #[arg(long)]
    pub no_timings: bool,
    /// No progress bar, no table, no warnings: the files and the exit status tell.
    #[arg(long)]
    pub quiet: bool,
    #[command(flatten)]
    pub folders: crate::args::SceneFolders,
}

/// A time budget in [`pickplace::ranges::TIME_BUDGET`].
fn time_budget(text: &str) -> Result<f64, pickplace::ranges::FlagError> {
    pickplace::ranges::parse_flag(text, pickplace::ranges::TIME_BUDGET)
}

/// How progress is shown on stderr: `PICKPLACE_PROGRESS` as for the other commands
/// ([`crate::progress::PROGRESS_ENV`]), nothing with `--quiet`.
enum BatchProgress {
    /// Nothing.
    Hidden,
    /// A line per finished scene (`PICKPLACE_PROGRESS=always`).
    Lines,
    /// An `indicatif` bar (stderr is a terminal).
    Bar(indicatif::ProgressBar),
}

impl BatchProgress {
    fn new(quiet: bool, scenes: usize) -> Self {
        use std::io::IsTerminal as _;
        if quiet {
            return Self::Hidden;
        }
        match std::env::var(crate::progress::PROGRESS_ENV)
            .unwrap_or_default()
            .as_str()
        {
            "never" => Self::Hidden,
            "always" => Self::Lines,
            _ if std::io::stderr().is_terminal() => {
                let bar = indicatif::ProgressBar::with_draw_target(
                    Some(scenes as u64),
                    indicatif::ProgressDrawTarget::stderr(),
                );
                bar.set_style(
                    indicatif::ProgressStyle::with_template(
                        "batch {bar:30} {pos}/{len} scenes, {elapsed} {msg}",
                    )
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
                );
                bar.enable_steady_tick(Duration::from_millis(250));
                Self::Bar(bar)
            }
            _ => Self::Hidden,
        }
    }

    /// A scene is done: `done` of `total`.
    fn finished(&self, done: usize, total: usize, scene: &str, status: SceneStatus) {
        match self {
            Self::Hidden => {}
            Self::Lines => note!("batch {done}/{total}: {scene}: {status}"),
            Self::Bar(bar) => {
                bar.set_message(format!("({scene}: {status})"));
                bar.inc(1);
            }
        }
    }

    fn finish(&self) {
        if let Self::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}

/// Runs `pickplace batch`.
pub fn run(args: &BatchArgs) -> anyhow::Result<ExitCode> {
    let inputs: Vec<crate::args::Input<'_>> = args
        .scenes
        .iter()
        .map(|s| ("a scene", s.as_path()))
        .collect();
    crate::args::check_output_dir(&args.out, "--out", &inputs)?;
    // Before anything is printed: two scenes with one file name are bad usage.
    pickplace::batch::plan_file_names(&args.scenes)?;
    let cache_dir = match args.folders.cache_choice() {
        CacheChoice::Folder(dir) => Some(dir),
        CacheChoice::Off => None,
        CacheChoice::Default => match pickplace::cache::default_dir() {
            Ok(dir) => Some(dir),
            Err(warning) => {
                if !args.quiet {
                    note!("warning: {warning}");
                }
                None
            }
        },
    };
    let options = BatchOptions {
        jobs: args
            .jobs
            .map_or_else(pickplace::batch::default_jobs, |j| j as usize),
        plan: PlanOverrides {
            seed: args.seed,
            strategy: args.strategy,
            time_budget: args.time_budget,
            timings: Some(!args.no_timings),
            ..args.timing.overrides()
        },
        resume: args.resume,
        cache_dir,
        package_dirs: args.folders.package_dirs.clone(),
        ..BatchOptions::new(&args.out)
    };
    let total = args.scenes.len();
    if !args.quiet {
        note!(
            "pickplace batch: {total} scene(s) into {}, {} thread(s){}",
            args.out.display(),
            options.jobs,
            if args.resume { ", resuming" } else { "" }
        );
    }
    let display = BatchProgress::new(args.quiet, total);
    let done = AtomicUsize::new(0);
    let elapsed = Mutex::new(vec![Duration::ZERO; total]);
    let result = plan_many(&args.scenes, &options, &|event| {
        if let BatchEvent::Finished {
            index,
            summary,
            elapsed: took,
        } = event
        {
            if let Some(slot) = elapsed
                .lock()
                .unwrap_or_else(PoisonError::into_inner)
                .get_mut(index)
            {
                *slot = took;
            }
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            display.finished(n, total, &summary.scene, summary.status);
        }
    });
    display.finish();
    let report = result?;
    if !args.quiet {
        let mut warnings: Vec<&String> =
            report.summaries.iter().flat_map(|s| &s.warnings).collect();
        warnings.sort();
        warnings.dedup();
        for w in warnings {
            note!("warning: {w}");
        }
        let elapsed = elapsed.into_inner().unwrap_or_else(PoisonError::into_inner);
        crate::output::print(&table(&report, &elapsed, options.jobs))?;
    }
    Ok(ExitCode::from(exit_status(&report)))
}

/// 2 when some scene was bad input or an error, else 1 when some scene has no plan, else 0.
fn exit_status(report: &BatchReport) -> u8 {
    if report.count(SceneStatus::BadInput) + report.count(SceneStatus::Error) > 0 {
        2
    } else if report.count(SceneStatus::NoPlan) > 0 {
        1
    } else {
        0
    }
}

/// The table printed at the end: a row per scene (status, strategy, time, scene), the reasons
/// or the error under the rows that have one, and the counts.
fn table(report: &BatchReport, elapsed: &[Duration], jobs: usize) -> String {
    let mut out = String::new();
    let width = report
        .summaries
        .iter()
        .filter_map(|s| s.strategy.map(|st| st.name().len()))
        .max()
        .unwrap_or(0)
        .max("strategy".len());
    outln!(
        out,
        "{:<9}  {:<width$}  {:>8}  scene",
        "status",
        "strategy",
        "time"
    );
    for (i, s) in report.summaries.iter().enumerate() {
        let time = elapsed.get(i).copied().unwrap_or_default().as_secs_f64();
        outln!(
            out,
            "{:<9}  {:<width$}  {:>6.2} s  {}",
            s.status.name(),
            s.strategy.map_or("-", |st| st.name()),
            time,
            s.scene
        );
        if let Some(why) = &s.replanned {
            outln!(out, "{:11}re-planned: {why}", "");
        }
        if let Some(e) = &s.error {
            outln!(out, "{:11}error: {e}", "");
        }
        for r in &s.reasons {
            outln!(out, "{:11}{r}", "");
        }
    }
    outln!(
        out,
        "{} scene(s) in {:.2} s on {jobs} thread(s): {}; summary {}",
        report.summaries.len(),
        report.elapsed.as_secs_f64(),
        SceneStatus::ALL
            .iter()
            .map(|&st| format!("{} {st}", report.count(st)))
            .collect::<Vec<_>>()
            .join(", "),
        report.summary_path.display()
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace::batch::SceneSummary;

    fn line(scene: &str, status: &str, extra: &str) -> SceneSummary {
        serde_json::from_str(&format!(
            r#"{{"format":"pickplace.batch/1","scene":"{scene}","status":"{status}","plan":null,"strategy":null,"seed":1,"duration":null,"time":null,"reasons":[],"error":null,"replanned":null,"warnings":[]{extra}}}"#
        ))
        .expect("a summary line")
    }

    #[test]
    fn the_worst_scene_gives_the_exit_status_and_the_table_lists_every_scene() {
        let mut report = BatchReport {
            summaries: vec![line("a.toml", "planned", ""), line("b.toml", "skipped", "")],
            summary_path: PathBuf::from("out/summary.jsonl"),
            elapsed: Duration::from_millis(1500),
        };
        report.summaries[0].strategy = Some(pickplace::Strategy::RightLeft);
        assert_eq!(exit_status(&report), 0);
        let mut no_plan = line("c.toml", "no-plan", "");
        no_plan.reasons = vec!["right-right: pick 0/3 passed".to_owned()];
        report.summaries.push(no_plan);
        assert_eq!(exit_status(&report), 1);
        let mut bad = line("d.toml", "bad-input", "");
        bad.error = Some("d.toml: missing field `robot`".to_owned());
        report.summaries.push(bad);
        assert_eq!(exit_status(&report), 2);
        let text = table(&report, &[Duration::from_millis(250)], 2);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], "status     strategy        time  scene");
        assert_eq!(lines[1], "planned    right-left    0.25 s  a.toml");
        assert_eq!(lines[2], "skipped    -             0.00 s  b.toml");
        assert_eq!(lines[4], "           right-right: pick 0/3 passed");
        assert_eq!(lines[6], "           error: d.toml: missing field `robot`");
        assert_eq!(
            lines[7],
            "4 scene(s) in 1.50 s on 2 thread(s): 1 planned, 1 skipped, 1 no-plan, 1 bad-input, 0 error; summary out/summary.jsonl"
        );
        assert!(
            time_budget("-1").is_err()
                && time_budget("inf").is_err()
                && time_budget("1e300").is_err()
        );
        assert_eq!(time_budget("2.5"), Ok(2.5));
    }
}
