//! Many scenes planned in parallel into one folder: `pickplace batch SCENE… --out DIR`, and the
//! same call for the Python bindings ([`plan_many`]).
//!
//! Each scene's plan is written to `DIR/<stem>.json` (`<stem>`: the scene file's name without
//! its extension), byte for byte what `pickplace plan SCENE --out FILE` writes with the same
//! options; then one line per scene goes to `DIR/summary.jsonl` ([`SceneSummary`]), in the
//! order the scenes were given, written at the end in one atomic write.
//!
//! # Parallelism
//! [`BatchOptions::jobs`] threads in all. With at least as many scenes as jobs, `jobs` workers
//! each plan one scene at a time on a rayon pool of one thread; with fewer scenes, the threads
//! are shared out between the workers' pools, so one scene alone gets all of them. Each worker
//! has its own pool on purpose: on one shared pool, a thread waiting inside a scene's parallel
//! loop steals whatever is queued, a whole other scene included, and the first scene's clock
//! (its time budget, its `time`) would run while the other is planned. The planner gives the
//! same plan whatever its pool's thread count (its parallel loops are taken in rank order),
//! so a batch gives the plans `pickplace plan` gives, unless a scene's time budget runs out.
//!
//! # Files
//! Two scenes whose stems are equal (ignoring case, for file systems that do) are refused
//! before any work ([`BatchError::SameName`]): rename one, or plan them into two folders.
//! After a run, `DIR/<stem>.json` exists exactly for the scenes whose line says `planned` or
//! `skipped`: a plan file an earlier run left for a scene that now has none is removed (never
//! when the path is not a regular file, or is the scene or one of its inputs).
//!
//! # Resume
//! With [`BatchOptions::resume`], a scene whose plan file is there, reads as a plan, was made
//! with this batch's seed (and forced strategy and scaling factors, when the plan records
//! them) and passes [`crate::validate::validate`] against the scene is not planned again: its
//! line says `skipped`. Any other plan file is planned again, and the line says why
//! ([`SceneSummary::replanned`]).
//!
//! # Errors per scene
//! One scene's bad input never stops the others: it is a line with status `bad-input` and the
//! message `pickplace plan` prints for it ([`error_message`]).

mod error;
mod files;
mod options;
mod resume;
mod run;
mod summary;
mod workers;

#[cfg(test)]
mod tests;

pub use crate::error::message as error_message;
pub use error::BatchError;
pub use files::plan_file_names;
pub use options::{BatchOptions, default_jobs};
pub use summary::{SUMMARY_FILE, SUMMARY_FORMAT, SceneStatus, SceneSummary, write_summary};
pub use workers::BatchEvent;

use files::prepare_out_dir;
use run::guarded_plan_one;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};
use workers::run_workers;

/// What [`plan_many`] did.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchReport {
    /// One line per scene, in the order given.
    pub summaries: Vec<SceneSummary>,
    /// The summary file written.
    pub summary_path: PathBuf,
    /// Wall-clock time of the whole batch.
    pub elapsed: Duration,
}

impl BatchReport {
    /// How many scenes ended with `status`.
    pub fn count(&self, status: SceneStatus) -> usize {
        self.summaries.iter().filter(|s| s.status == status).count()
    }
}

/// Plans `scenes` into [`BatchOptions::out_dir`] (see the module doc) and writes the summary.
/// `progress` is called from the worker threads as each scene starts and ends.
///
/// # Errors
/// [`BatchError`] for what stops the whole batch, found before any scene is planned (names,
/// options, the output folder, the threads), or the summary that cannot be written at the
/// end. A scene that fails is a summary line, never an error.
///
/// # Example
/// ```
/// use pickplace::batch::{BatchOptions, SceneStatus, plan_many};
/// use pickplace::planner::PlanOverrides;
/// use std::path::Path;
///
/// let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
/// let out = std::env::temp_dir().join(format!("pickplace-batch-doc-{}", std::process::id()));
/// let options = BatchOptions {
///     jobs: 2,
///     plan: PlanOverrides {
///         timings: Some(false),
///         ..PlanOverrides::default()
///     },
///     cache_dir: Some(root.join("target/pickplace-cache")),
///     ..BatchOptions::new(&out)
/// };
/// let report = plan_many(&[root.join("scenes/fig10b-mug.toml")], &options, &|_| {})?;
/// assert_eq!(report.count(SceneStatus::Planned), 1);
/// assert!(out.join("fig10b-mug.json").is_file());
/// assert_eq!(report.summary_path, out.join("summary.jsonl"));
/// # std::fs::remove_dir_all(&out)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
///
/// # Performance
/// Each scene is loaded and set up by its worker (the cache makes the second scene of a
/// robot fast); the scenes are independent, so throughput grows with `jobs` up to the
/// machine's cores.
pub fn plan_many(
    scenes: &[PathBuf],
    options: &BatchOptions,
    progress: &(dyn Fn(BatchEvent<'_>) + Sync),
) -> Result<BatchReport, BatchError> {
    let started = Instant::now();
    let plan_paths = prepare(scenes, options)?;
    let summary_path = options.out_dir.join(SUMMARY_FILE);
    let summaries = run_workers(scenes, &plan_paths, options, progress)?;
    write_summary(&summary_path, &summaries)?;
    Ok(BatchReport {
        summaries,
        summary_path,
        elapsed: started.elapsed(),
    })
}

/// What [`plan_many`] does before planning: checks the options and the scenes' names,
/// creates the output folder and checks the summary's path in it; returns each scene's plan
/// file. For callers that spread a batch's scenes themselves ([`plan_scene`] per scene, then
/// [`write_summary`]), such as the Python package's Ray tasks.
///
/// # Errors
/// As [`plan_many`], before any scene is planned.
pub fn prepare(scenes: &[PathBuf], options: &BatchOptions) -> Result<Vec<PathBuf>, BatchError> {
    options.check()?;
    let names = plan_file_names(scenes)?;
    prepare_out_dir(&options.out_dir)?;
    Ok(names.iter().map(|n| options.out_dir.join(n)).collect())
}

/// One scene of a batch: planned into `plan_path` (or, with [`BatchOptions::resume`], its
/// valid plan there kept), on the current rayon pool, exactly as a worker of [`plan_many`]
/// does it; a panic of the planner becomes a line with status `error`.
pub fn plan_scene(scene: &Path, plan_path: &Path, options: &BatchOptions) -> SceneSummary {
    guarded_plan_one(scene, plan_path, options)
}
