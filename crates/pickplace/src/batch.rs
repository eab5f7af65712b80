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

use crate::error::Error;
use crate::plan::Plan;
use crate::planner::{Outcome, PlanOptions};
use crate::scene::{Scene, StrategyChoice};
use crate::setup::{Setup, SetupOptions};
use crate::strategy::Strategy;
use pickplace_geometry::export::write_atomic;
use pickplace_geometry::io::{FileKind, read_text};
use pickplace_geometry::math::Real;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

/// The `format` of every summary line.
pub const SUMMARY_FORMAT: &str = "pickplace.batch/1";

/// The summary's file name in the output folder.
pub const SUMMARY_FILE: &str = "summary.jsonl";

/// Options of [`plan_many`]. The planning options left at `None` are the scene's, as for
/// `pickplace plan`.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchOptions {
    /// The folder the plans and the summary go to (created when missing).
    pub out_dir: PathBuf,
    /// Threads in all, at least 1 (default: the machine's available parallelism).
    pub jobs: usize,
    /// Seed of every scene's random choices (default: each scene's `planner.seed`).
    pub seed: Option<u64>,
    /// Strategy of every scene (default: each scene's `planner.strategy`).
    pub strategy: Option<StrategyChoice>,
    /// Wall-clock budget of each scene's plan (s), in [`crate::ranges::TIME_BUDGET`] (default: each scene's
    /// `planner.time_budget`).
    pub time_budget: Option<Real>,
    /// Velocity scaling factor in [`crate::ranges::SCALING`] (default: each scene's, see
    /// [`PlanOptions::velocity_scaling`]).
    pub velocity_scaling: Option<Real>,
    /// Acceleration scaling factor in [`crate::ranges::SCALING`] (default: each scene's).
    pub acceleration_scaling: Option<Real>,
    /// Trajectory sampling period (s), in [`crate::ranges::SAMPLE_PERIOD`] (default: [`PlanOptions::sample_period`]'s).
    pub sample_period: Option<Real>,
    /// Record stage timings in the plans, and each scene's time in the summary (default:
    /// true). Without them, the plan files and the summary are the same bytes on every run.
    pub timings: bool,
    /// Keep the valid plans already in the folder (see the module doc; default: false).
    pub resume: bool,
    /// Folder of cluster databases and roadmaps, shared by the scenes (default: none, built
    /// in memory for each scene).
    pub cache_dir: Option<PathBuf>,
    /// Folders searched for `package://` paths after each scene's own (default: none).
    pub package_dirs: Vec<PathBuf>,
}

impl BatchOptions {
    /// The defaults, writing into `out_dir`.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            jobs: default_jobs(),
            seed: None,
            strategy: None,
            time_budget: None,
            velocity_scaling: None,
            acceleration_scaling: None,
            sample_period: None,
            timings: true,
            resume: false,
            cache_dir: None,
            package_dirs: Vec::new(),
        }
    }

    /// Refuses values out of range, before any work.
    fn check(&self) -> Result<(), BatchError> {
        let invalid = |option: &'static str, reason: String| BatchError::Option { option, reason };
        crate::ranges::THREADS
            .check_count(self.jobs)
            .map_err(|e| invalid("jobs", e.to_string()))?;
        let range = |option: &'static str, value: Option<Real>, range: crate::ranges::Range| {
            value.map_or(Ok(()), |v| {
                range.check(v).map_err(|e| invalid(option, e.to_string()))
            })
        };
        range("time_budget", self.time_budget, crate::ranges::TIME_BUDGET)?;
        range(
            "velocity_scaling",
            self.velocity_scaling,
            crate::ranges::SCALING,
        )?;
        range(
            "acceleration_scaling",
            self.acceleration_scaling,
            crate::ranges::SCALING,
        )?;
        range(
            "sample_period",
            self.sample_period,
            crate::ranges::SAMPLE_PERIOD,
        )?;
        Ok(())
    }

    /// The planner's options for a scene: its own, with this batch's overrides.
    pub fn plan_options(&self, setup: &Setup) -> PlanOptions {
        let mut options = PlanOptions::for_setup(setup);
        if let Some(seed) = self.seed {
            options.seed = seed;
        }
        if let Some(strategy) = self.strategy {
            options.strategy = strategy;
        }
        if let Some(budget) = self.time_budget {
            options.time_budget = budget;
        }
        if let Some(f) = self.velocity_scaling {
            options.velocity_scaling = f;
        }
        if let Some(f) = self.acceleration_scaling {
            options.acceleration_scaling = f;
        }
        if let Some(p) = self.sample_period {
            options.sample_period = p;
        }
        options.timings = self.timings;
        options
    }
}

/// The machine's available parallelism (1 when it cannot be known).
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}

/// How a scene ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SceneStatus {
    /// Planned, and the plan written.
    Planned,
    /// No strategy found a plan, or the scene is infeasible (a start state in collision, the
    /// object not resting, the target on no usable surface): `pickplace plan`'s exit status 1.
    NoPlan,
    /// The scene or a file it names is bad input (`pickplace plan`'s exit status 2).
    BadInput,
    /// Resumed: the plan file already there is valid and was kept.
    Skipped,
    /// The plan could not be written (or its path is not a regular file, or is an input of
    /// the scene), or a defect of the planner (a panic included).
    Error,
}

impl SceneStatus {
    /// Every status, in the order a report lists them.
    pub const ALL: [SceneStatus; 5] = [
        SceneStatus::Planned,
        SceneStatus::Skipped,
        SceneStatus::NoPlan,
        SceneStatus::BadInput,
        SceneStatus::Error,
    ];

    /// The word of the summary (`planned`, `no-plan`, `bad-input`, `skipped`, `error`).
    pub fn name(self) -> &'static str {
        match self {
            SceneStatus::Planned => "planned",
            SceneStatus::NoPlan => "no-plan",
            SceneStatus::BadInput => "bad-input",
            SceneStatus::Skipped => "skipped",
            SceneStatus::Error => "error",
        }
    }
}

impl std::fmt::Display for SceneStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One line of `summary.jsonl`: every field is always there (`null` or `[]` when it does
/// not apply), in this order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSummary {
    /// [`SUMMARY_FORMAT`].
    pub format: String,
    /// The scene file, as given.
    pub scene: String,
    /// How it ended.
    pub status: SceneStatus,
    /// The plan file (planned or skipped), else `None`.
    pub plan: Option<String>,
    /// The strategy of the plan.
    pub strategy: Option<Strategy>,
    /// The seed used (the plan's when skipped), once the scene was read.
    pub seed: Option<u64>,
    /// The plan's duration of motion (s).
    pub duration: Option<Real>,
    /// Wall-clock time spent on the scene (s): loading, planning and writing, or checking
    /// the plan kept; `None` without [`BatchOptions::timings`].
    pub time: Option<Real>,
    /// Why there is no plan: per strategy, the counts per stage and the most frequent
    /// rejections ([`crate::planner::Failure::reasons`]), or the infeasible scene's message.
    pub reasons: Vec<String>,
    /// The message of a bad input or an error, as `pickplace plan` prints it.
    pub error: Option<String>,
    /// Why a plan file found by a resumed run was not kept (it is planned again).
    pub replanned: Option<String>,
    /// The cache's warning, if any (the scene was set up in memory).
    pub warnings: Vec<String>,
}

impl SceneSummary {
    /// A line for `scene` with nothing known yet (status [`SceneStatus::Error`]).
    fn new(scene: &Path) -> Self {
        Self {
            format: SUMMARY_FORMAT.to_owned(),
            scene: scene.to_string_lossy().into_owned(),
            status: SceneStatus::Error,
            plan: None,
            strategy: None,
            seed: None,
            duration: None,
            time: None,
            reasons: Vec::new(),
            error: None,
            replanned: None,
            warnings: Vec::new(),
        }
    }

    /// The line as one line of JSON (no newline).
    pub fn to_json_line(&self) -> String {
        // Strings, numbers and enums only: serialising cannot fail.
        serde_json::to_string(self).unwrap_or_default()
    }

    /// This line with its status and message for a failure.
    fn fail(&mut self, status: SceneStatus, message: String) {
        self.status = status;
        self.error = Some(message);
    }
}

/// Progress of [`plan_many`], reported from the worker threads as scenes start and end.
#[derive(Debug, Clone, Copy)]
#[non_exhaustive]
pub enum BatchEvent<'a> {
    /// A worker started on a scene.
    Started {
        /// Its index in the scenes given.
        index: usize,
        /// The scene file.
        scene: &'a Path,
    },
    /// A scene is done.
    Finished {
        /// Its index in the scenes given.
        index: usize,
        /// Its summary line.
        summary: &'a SceneSummary,
        /// Wall-clock time it took (also without timings).
        elapsed: Duration,
    },
}

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

/// Why a batch could not run (a scene's own failure is a [`SceneSummary`] instead).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// Two scenes would write the same plan file.
    #[error(
        "{} and {}: both would be planned into {file}; scenes of one batch need distinct file names (rename one, or plan them into two folders)",
        first.display(),
        second.display()
    )]
    SameName {
        /// The first scene given.
        first: PathBuf,
        /// The later scene.
        second: PathBuf,
        /// The plan file's name.
        file: String,
    },
    /// A scene path has no file name to name its plan after.
    #[error("{}: not a scene file name", scene.display())]
    NoFileName {
        /// The path given.
        scene: PathBuf,
    },
    /// An option is out of range.
    #[error("batch option {option}: {reason}")]
    Option {
        /// The option ([`BatchOptions`]'s field).
        option: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The output folder, or the summary's path in it, cannot be used.
    #[error("{}: {reason}", path.display())]
    Output {
        /// The folder or file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A worker thread or its pool could not be started.
    #[error("cannot start the batch's threads: {reason}")]
    Threads {
        /// What the system said.
        reason: String,
    },
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
/// use std::path::Path;
///
/// let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
/// let out = std::env::temp_dir().join(format!("pickplace-batch-doc-{}", std::process::id()));
/// let options = BatchOptions {
///     jobs: 2,
///     timings: false,
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

/// Writes the summary lines, one JSON object per line in the order given, atomically.
///
/// # Errors
/// [`BatchError::Output`] when the file cannot be written.
pub fn write_summary(path: &Path, summaries: &[SceneSummary]) -> Result<(), BatchError> {
    let mut text = String::new();
    for s in summaries {
        text.push_str(&s.to_json_line());
        text.push('\n');
    }
    write_atomic(path, text.as_bytes()).map_err(|e| BatchError::Output {
        path: path.to_path_buf(),
        reason: format!("cannot write the summary: {}", error_message(&e)),
    })
}

/// Each scene's plan file name, `<stem>.json`.
///
/// # Errors
/// [`BatchError::NoFileName`] for a path without a file name, [`BatchError::SameName`] for
/// two scenes with the same stem (compared ignoring case).
pub fn plan_file_names(scenes: &[PathBuf]) -> Result<Vec<String>, BatchError> {
    let mut names: Vec<String> = Vec::with_capacity(scenes.len());
    for (i, scene) in scenes.iter().enumerate() {
        let stem = scene
            .file_name()
            .and_then(|_| scene.file_stem())
            .ok_or_else(|| BatchError::NoFileName {
                scene: scene.clone(),
            })?;
        let name = format!("{}.json", stem.to_string_lossy());
        if let Some(j) = names
            .iter()
            .position(|n| n.to_lowercase() == name.to_lowercase())
        {
            return Err(BatchError::SameName {
                first: scenes[j].clone(),
                second: scenes[i].clone(),
                file: name,
            });
        }
        names.push(name);
    }
    Ok(names)
}

/// Creates the output folder when missing and checks it and the summary's path; returns the
/// summary's path.
fn prepare_out_dir(dir: &Path) -> Result<PathBuf, BatchError> {
    let out = |reason: String| BatchError::Output {
        path: dir.to_path_buf(),
        reason,
    };
    if let Ok(meta) = std::fs::metadata(dir)
        && !meta.is_dir()
    {
        return Err(out(
            "is not a folder; give a folder (created if missing)".to_owned()
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| out(format!("cannot create the folder: {e}")))?;
    let summary = dir.join(SUMMARY_FILE);
    if let Err(reason) = check_regular_or_absent(&summary) {
        return Err(BatchError::Output {
            path: summary,
            reason,
        });
    }
    Ok(summary)
}

/// `Ok` when nothing is at `path` or a regular file is; else what is there, in words.
fn check_regular_or_absent(path: &Path) -> Result<(), String> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    let kind = meta.file_type();
    if kind.is_symlink() {
        Err("is a symbolic link; batch outputs replace what is at their path, so remove it or give another output folder".to_owned())
    } else if kind.is_dir() {
        Err("is a folder where the batch writes a file".to_owned())
    } else if !kind.is_file() {
        Err(
            "is a device, FIFO or socket, not a regular file; outputs are regular files only"
                .to_owned(),
        )
    } else {
        Ok(())
    }
}

/// The workers and the threads of each one's pool: `jobs` workers (one per scene at most),
/// each with a pool of `jobs` threads. While every worker plans, their pools share the
/// cores as the OS schedules them (one scene's parallel loops cannot run another scene, so
/// a scene's time budget counts its own work only); when the last scenes are left, they
/// get every core: with one thread per worker, the batch's tail (its last, longest scene)
/// ran on one core (24 suite scenes on 2 cores: 1.77 times one core's throughput with one
/// thread per worker, 1.85 with this; docs/batch.md).
fn worker_threads(jobs: usize, scenes: usize) -> Vec<usize> {
    let jobs = jobs.max(1);
    let workers = jobs.min(scenes).max(1);
    vec![jobs; workers]
}

/// Runs every scene on the workers; the lines in the scenes' order.
fn run_workers(
    scenes: &[PathBuf],
    plan_paths: &[PathBuf],
    options: &BatchOptions,
    progress: &(dyn Fn(BatchEvent<'_>) + Sync),
) -> Result<Vec<SceneSummary>, BatchError> {
    let n = scenes.len();
    if n == 0 {
        return Ok(Vec::new());
    }
    let threads = |e: &dyn std::fmt::Display| BatchError::Threads {
        reason: e.to_string(),
    };
    let pools = worker_threads(options.jobs, n)
        .into_iter()
        .enumerate()
        .map(|(w, threads)| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .thread_name(move |i| format!("pickplace-batch-{w}-{i}"))
                .build()
        })
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| threads(&e))?;
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<Option<SceneSummary>>> = Mutex::new(vec![None; n]);
    let work = |pool: &rayon::ThreadPool| {
        loop {
            let i = next.fetch_add(1, Ordering::Relaxed);
            let (Some(scene), Some(plan_path)) = (scenes.get(i), plan_paths.get(i)) else {
                break;
            };
            progress(BatchEvent::Started { index: i, scene });
            let t = Instant::now();
            let summary = pool.install(|| guarded_plan_one(scene, plan_path, options));
            progress(BatchEvent::Finished {
                index: i,
                summary: &summary,
                elapsed: t.elapsed(),
            });
            done.lock().unwrap_or_else(PoisonError::into_inner)[i] = Some(summary);
        }
    };
    let spawned = std::thread::scope(|scope| {
        let mut spawned = Vec::new();
        for (w, pool) in pools.iter().enumerate() {
            let work = &work;
            spawned.push(
                std::thread::Builder::new()
                    .name(format!("pickplace-batch-{w}"))
                    .spawn_scoped(scope, move || work(pool)),
            );
        }
        // A worker that did start takes every scene left, so one is enough.
        let mut first_error = None;
        let mut any = false;
        for handle in spawned {
            match handle {
                Ok(handle) => {
                    // A worker's panic (from `progress`) is the caller's: passed on.
                    if let Err(panic) = handle.join() {
                        std::panic::resume_unwind(panic);
                    }
                    any = true;
                }
                Err(e) => first_error = Some(e),
            }
        }
        match (any, first_error) {
            (false, Some(e)) => Err(e),
            _ => Ok(()),
        }
    });
    spawned.map_err(|e| threads(&e))?;
    let done = done.into_inner().unwrap_or_else(PoisonError::into_inner);
    Ok(done
        .into_iter()
        .zip(scenes)
        .map(|(line, scene)| {
            line.unwrap_or_else(|| {
                let mut s = SceneSummary::new(scene);
                s.fail(SceneStatus::Error, "internal error: not planned".to_owned());
                s
            })
        })
        .collect())
}

/// [`plan_one`], with a panic of the planner turned into a line with status `error`.
fn guarded_plan_one(scene: &Path, plan_path: &Path, options: &BatchOptions) -> SceneSummary {
    let t = Instant::now();
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        plan_one(scene, plan_path, options)
    }))
    .unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".to_owned());
        let mut s = SceneSummary::new(scene);
        s.fail(
            SceneStatus::Error,
            format!("internal error: the planner panicked on this scene: {what}"),
        );
        if options.timings {
            s.time = Some(t.elapsed().as_secs_f64());
        }
        s
    })
}

/// Plans one scene into `plan_path` (or keeps the plan there) and says how it went.
fn plan_one(scene_path: &Path, plan_path: &Path, options: &BatchOptions) -> SceneSummary {
    let t = Instant::now();
    let mut s = SceneSummary::new(scene_path);
    plan_into(scene_path, plan_path, options, &mut s);
    if options.timings {
        s.time = Some(t.elapsed().as_secs_f64());
    }
    s
}

/// The work of [`plan_one`], filling `s`.
fn plan_into(scene_path: &Path, plan_path: &Path, options: &BatchOptions, s: &mut SceneSummary) {
    let scene = match Scene::load(scene_path) {
        Ok(scene) => scene,
        Err(e) => {
            s.fail(SceneStatus::BadInput, error_message(&e));
            remove_stale(plan_path, &[scene_path.to_path_buf()], s);
            return;
        }
    };
    let inputs = scene_inputs(scene_path, &scene);
    if let Err(reason) = check_plan_path(plan_path, &inputs) {
        s.fail(
            SceneStatus::Error,
            format!("{}: {reason}", plan_path.display()),
        );
        return;
    }
    s.seed = Some(options.seed.unwrap_or(scene.planner.seed));
    let setup_options = SetupOptions {
        cache_dir: options.cache_dir.clone(),
        package_dirs: options.package_dirs.clone(),
        progress: None,
    };
    let setup = match Setup::new(scene, scene_path, &setup_options) {
        Ok(setup) => setup,
        Err(e) => {
            fail_with(s, &e);
            remove_stale(plan_path, &inputs, s);
            return;
        }
    };
    s.warnings = setup
        .warnings
        .iter()
        .map(ToString::to_string)
        .chain(setup.mesh_warnings.iter().map(ToString::to_string))
        .collect();
    let plan_options = options.plan_options(&setup);
    if options.resume {
        match kept_plan(&setup, &plan_options, plan_path) {
            Kept::Valid(plan) => {
                s.status = SceneStatus::Skipped;
                s.plan = Some(plan_path.to_string_lossy().into_owned());
                s.strategy = Some(plan.strategy);
                s.seed = Some(plan.seed);
                s.duration = Some(plan.stats.duration);
                return;
            }
            Kept::Invalid(reason) => s.replanned = Some(reason),
            Kept::Absent => {}
        }
    }
    match crate::plan(&setup, &plan_options) {
        Ok(Outcome::Planned(plan)) => {
            if let Err(e) = write_atomic(plan_path, plan.to_json().as_bytes()) {
                s.fail(
                    SceneStatus::Error,
                    format!(
                        "{}: cannot write the plan: {}",
                        plan_path.display(),
                        error_message(&e)
                    ),
                );
                remove_stale(plan_path, &inputs, s);
                return;
            }
            s.status = SceneStatus::Planned;
            s.plan = Some(plan_path.to_string_lossy().into_owned());
            s.strategy = Some(plan.strategy);
            s.duration = Some(plan.stats.duration);
        }
        Ok(Outcome::NoPlan(failure)) => {
            s.status = SceneStatus::NoPlan;
            s.reasons = failure.reasons;
            remove_stale(plan_path, &inputs, s);
        }
        Err(e) => {
            fail_with(s, &e);
            remove_stale(plan_path, &inputs, s);
        }
    }
}

/// The line of a façade error: an infeasible scene has no plan (its message is the reason),
/// a defect is an error, anything else bad input.
fn fail_with(s: &mut SceneSummary, e: &Error) {
    let message = error_message(e);
    if e.is_infeasible() {
        s.status = SceneStatus::NoPlan;
        s.reasons = vec![message];
    } else if matches!(e, Error::Internal { .. }) {
        s.fail(SceneStatus::Error, message);
    } else {
        s.fail(SceneStatus::BadInput, message);
    }
}

/// What a resumed run found at a scene's plan path.
enum Kept {
    /// Nothing.
    Absent,
    /// A plan to keep.
    Valid(Box<Plan>),
    /// A file not to keep, and why.
    Invalid(String),
}

/// Reads and checks the plan file a previous run left at `plan_path`.
fn kept_plan(setup: &Setup, plan_options: &PlanOptions, plan_path: &Path) -> Kept {
    if std::fs::symlink_metadata(plan_path).is_err() {
        return Kept::Absent;
    }
    let shown = plan_path.display();
    let text = match read_text(plan_path, FileKind::Plan) {
        Ok(text) => text,
        Err(e) => return Kept::Invalid(format!("{shown}: cannot be read ({e})")),
    };
    let plan = match Plan::from_json(&text) {
        Ok(plan) => plan,
        Err(reason) => return Kept::Invalid(format!("{shown}: not a plan: {reason}")),
    };
    if let Some(reason) = other_options(&plan, plan_options) {
        return Kept::Invalid(format!("{shown}: {reason}"));
    }
    match crate::validate::validate(setup, &plan, plan_path) {
        Ok(report) if report.problems.is_empty() => Kept::Valid(Box::new(plan)),
        Ok(report) => Kept::Invalid(format!(
            "{shown}: fails validation ({} problem(s)), first: {}",
            report.problems.len(),
            report.problems.first().map_or("", String::as_str)
        )),
        Err(e) => Kept::Invalid(error_message(&e)),
    }
}

/// Why a plan was made with other options than this batch's, as far as the plan records
/// them: the seed, the strategy when one is forced (by the batch or the scene), the scaling
/// factors.
fn other_options(plan: &Plan, plan_options: &PlanOptions) -> Option<String> {
    if plan.seed != plan_options.seed {
        return Some(format!(
            "planned with seed {}, this batch uses {}",
            plan.seed, plan_options.seed
        ));
    }
    if let Some(forced) = plan_options.strategy.strategy()
        && forced != plan.strategy
    {
        return Some(format!(
            "planned with strategy {}, this batch asks for {forced}",
            plan.strategy
        ));
    }
    if let Some(limits) = &plan.limits
        && (limits.velocity_scaling != plan_options.velocity_scaling
            || limits.acceleration_scaling != plan_options.acceleration_scaling)
    {
        return Some(format!(
            "planned with scaling factors {} (velocity) and {} (acceleration), this batch uses {} and {}",
            limits.velocity_scaling,
            limits.acceleration_scaling,
            plan_options.velocity_scaling,
            plan_options.acceleration_scaling
        ));
    }
    None
}

/// The files a scene names, which a plan file must never replace: the scene, each robot's
/// URDF, SRDF and gripper file, the object and environment meshes.
fn scene_inputs(scene_path: &Path, scene: &Scene) -> Vec<PathBuf> {
    let mut inputs = vec![scene_path.to_path_buf()];
    for robot in &scene.robots {
        inputs.push(robot.urdf.clone());
        inputs.extend(robot.srdf.iter().cloned());
        inputs.extend(robot.gripper.iter().cloned());
    }
    inputs.push(scene.object.mesh.clone());
    inputs.extend(scene.environment.iter().map(|e| e.mesh.clone()));
    inputs
}

/// `Ok` when a plan may be written at `plan_path`: nothing there, or a regular file that is
/// none of `inputs` (compared by identity: another path or a hard link to an input counts).
fn check_plan_path(plan_path: &Path, inputs: &[PathBuf]) -> Result<(), String> {
    check_regular_or_absent(plan_path)?;
    if let Some(input) = inputs.iter().find(|i| same_file(plan_path, i)) {
        return Err(format!(
            "is {}, an input of the scene; it would be overwritten",
            input.display()
        ));
    }
    Ok(())
}

/// True when `a` and `b` are the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }
}

/// Removes the plan file an earlier run left at `plan_path` for a scene that has no plan now:
/// only a regular file that is none of `inputs`. A failure is a warning of the line.
fn remove_stale(plan_path: &Path, inputs: &[PathBuf], s: &mut SceneSummary) {
    let regular = std::fs::symlink_metadata(plan_path).is_ok_and(|m| m.file_type().is_file());
    if !regular || inputs.iter().any(|i| same_file(plan_path, i)) {
        return;
    }
    if let Err(e) = std::fs::remove_file(plan_path) {
        s.warnings.push(format!(
            "{}: the plan file of an earlier run cannot be removed ({e})",
            plan_path.display()
        ));
    }
}

/// An error and its causes on one line, each cause once, as the `pickplace` command prints
/// it after `error: ` (the façade's errors already quote their source in their message, so a
/// cause whose text the previous message contains is skipped).
pub fn error_message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut out = String::new();
    let mut previous = String::new();
    let mut cause = Some(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !previous.contains(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&text);
            previous = text;
        }
        cause = c.source();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
    }

    fn scene(name: &str) -> PathBuf {
        root().join("scenes").join(name)
    }

    /// A fresh folder under the system's temporary folder.
    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("pickplace-batch-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch");
        dir
    }

    fn options(out: &Path, jobs: usize) -> BatchOptions {
        BatchOptions {
            jobs,
            timings: false,
            cache_dir: Some(root().join("target/pickplace-test-cache")),
            ..BatchOptions::new(out)
        }
    }

    /// The plan `pickplace plan SCENE --no-timings` writes, made directly.
    fn direct_plan(name: &str) -> String {
        let setup = crate::testing::setup(name);
        let options = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        };
        match crate::plan(setup, &options).expect("plans") {
            Outcome::Planned(plan) => plan.to_json(),
            Outcome::NoPlan(f) => panic!("{name}: no plan: {:?}", f.reasons),
        }
    }

    fn read(p: &Path) -> String {
        std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
    }

    #[test]
    fn batch_plans_are_the_direct_plans_whatever_the_threads() {
        let scenes = [scene("fig9-far-left.toml"), scene("fig10b-mug.toml")];
        let expected = [
            direct_plan("fig9-far-left.toml"),
            direct_plan("fig10b-mug.toml"),
        ];
        // Two workers of one thread, one worker of one thread, and one scene alone on a
        // pool of two threads (the handover search runs in parallel there).
        for (jobs, scenes) in [(2, &scenes[..]), (1, &scenes[..]), (2, &scenes[..1])] {
            let out = scratch(&format!("threads-{jobs}-{}", scenes.len()));
            let events = Mutex::new(Vec::new());
            let report = plan_many(scenes, &options(&out, jobs), &|e| {
                if let BatchEvent::Finished { index, summary, .. } = e {
                    events.lock().expect("events").push((index, summary.status));
                }
            })
            .expect("batch runs");
            assert_eq!(report.count(SceneStatus::Planned), scenes.len());
            assert_eq!(events.into_inner().expect("events").len(), scenes.len());
            assert_eq!(
                read(&out.join("fig9-far-left.json")),
                expected[0],
                "jobs {jobs}"
            );
            if scenes.len() == 2 {
                assert_eq!(read(&out.join("fig10b-mug.json")), expected[1]);
            }
            let lines: Vec<SceneSummary> = read(&report.summary_path)
                .lines()
                .map(|l| serde_json::from_str(l).expect("a summary line"))
                .collect();
            assert_eq!(lines, report.summaries);
            assert!(lines[0].strategy.expect("planned").has_handover());
            assert_eq!(lines[0].time, None, "no timings, no times");
            let _ = std::fs::remove_dir_all(&out);
        }
    }

    #[test]
    fn threads_are_shared_out_between_the_workers() {
        assert_eq!(worker_threads(2, 4), [2, 2]);
        assert_eq!(worker_threads(2, 1), [2]);
        assert_eq!(worker_threads(5, 2), [5, 5]);
        assert_eq!(worker_threads(1, 0), [1]);
        assert_eq!(worker_threads(0, 3), [1]);
    }

    #[test]
    fn scenes_with_the_same_stem_are_refused_before_any_work() {
        let e = plan_file_names(&[
            PathBuf::from("a/scene.toml"),
            PathBuf::from("b.toml"),
            PathBuf::from("c/Scene.TOML"),
        ])
        .expect_err("same stem");
        assert_eq!(
            e.to_string(),
            "a/scene.toml and c/Scene.TOML: both would be planned into Scene.json; scenes of one batch need distinct file names (rename one, or plan them into two folders)"
        );
        assert!(matches!(
            plan_file_names(&[PathBuf::from("..")]),
            Err(BatchError::NoFileName { .. })
        ));
        assert_eq!(
            plan_file_names(&[PathBuf::from("x/a.toml"), PathBuf::from("b")]).expect("names"),
            ["a.json", "b.json"]
        );
        let out = scratch("refused");
        let e = plan_many(
            &[scene("fig9-near.toml"), scene("fig9-near.toml")],
            &options(&out, 1),
            &|_| {},
        )
        .expect_err("refused");
        assert!(matches!(e, BatchError::SameName { .. }));
        assert!(!out.join(SUMMARY_FILE).exists(), "nothing written");
        let e = plan_many(&[], &options(&out, 0), &|_| {}).expect_err("no threads");
        assert!(e.to_string().contains("jobs"), "{e}");
        let _ = std::fs::remove_dir_all(&out);
    }

    #[test]
    fn bad_input_is_a_line_and_resume_keeps_only_valid_plans() {
        let out = scratch("resume");
        let bad = out.join("bad.toml");
        std::fs::write(&bad, "robot = 3\n").expect("bad scene");
        let near = scene("fig9-near.toml");
        let scenes = [bad.clone(), near.clone()];
        // A plan file an earlier run left for the bad scene is removed.
        std::fs::write(out.join("bad.json"), "{}").expect("stale");
        let report = plan_many(&scenes, &options(&out, 2), &|_| {}).expect("runs");
        let [first, second] = &report.summaries[..] else {
            panic!("two lines")
        };
        assert_eq!(first.status, SceneStatus::BadInput);
        let message = first.error.as_deref().expect("message");
        assert!(message.starts_with(&bad.display().to_string()), "{message}");
        assert_eq!(
            message,
            error_message(&Scene::load(&bad).expect_err("bad")),
            "the message pickplace plan prints"
        );
        assert!(!out.join("bad.json").exists(), "stale plan removed");
        assert_eq!(second.status, SceneStatus::Planned);
        let plan_path = out.join("fig9-near.json");
        let planned = read(&plan_path);

        // Resumed: the valid plan is kept.
        let resume = BatchOptions {
            resume: true,
            ..options(&out, 1)
        };
        let again = plan_many(&scenes[1..], &resume, &|_| {}).expect("runs");
        assert_eq!(again.summaries[0].status, SceneStatus::Skipped);
        assert_eq!(again.summaries[0].strategy, second.strategy);
        assert_eq!(again.summaries[0].duration, second.duration);
        assert_eq!(again.summaries[0].replanned, None);

        // A corrupt file, a plan of another seed and an invalid plan are planned again.
        std::fs::write(&plan_path, &planned[..planned.len() / 2]).expect("cut");
        let s = &plan_many(&scenes[1..], &resume, &|_| {})
            .expect("runs")
            .summaries[0];
        assert_eq!(s.status, SceneStatus::Planned);
        assert!(
            s.replanned.as_deref().expect("why").contains("not a plan"),
            "{s:?}"
        );
        assert_eq!(read(&plan_path), planned);

        let seeded = BatchOptions {
            seed: Some(7),
            ..resume.clone()
        };
        let s = &plan_many(&scenes[1..], &seeded, &|_| {})
            .expect("runs")
            .summaries[0];
        assert!(
            s.replanned
                .as_deref()
                .expect("why")
                .contains("seed 1, this batch uses 7"),
            "{s:?}"
        );
        assert_eq!(s.seed, Some(7));

        let mut plan = Plan::from_json(&planned).expect("plan");
        plan.events[0].time = 0.0;
        std::fs::write(&plan_path, plan.to_json()).expect("invalid plan");
        let s = &plan_many(&scenes[1..], &resume, &|_| {})
            .expect("runs")
            .summaries[0];
        assert_eq!(s.status, SceneStatus::Planned);
        assert!(
            s.replanned
                .as_deref()
                .expect("why")
                .contains("fails validation"),
            "{s:?}"
        );
        assert_eq!(read(&plan_path), planned);
        let _ = std::fs::remove_dir_all(&out);
    }

    #[test]
    fn a_plan_made_with_other_options_is_not_kept() {
        let plan = Plan::from_json(&direct_plan("fig9-near.toml")).expect("plan");
        let setup = crate::testing::setup("fig9-near.toml");
        let same = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        };
        assert_eq!(other_options(&plan, &same), None);
        let forced = PlanOptions {
            strategy: StrategyChoice::LeftLeft,
            ..same.clone()
        };
        assert_eq!(
            other_options(&plan, &forced).as_deref(),
            Some("planned with strategy right-right, this batch asks for left-left")
        );
        let slower = PlanOptions {
            velocity_scaling: 0.5,
            ..same.clone()
        };
        let why = other_options(&plan, &slower).expect("another factor");
        assert!(why.contains("scaling factors 1 (velocity)"), "{why}");
    }

    #[test]
    fn an_infeasible_scene_has_no_plan_and_its_message_is_the_reason() {
        let out = scratch("infeasible");
        // The can 5 cm above the table: not resting where it starts.
        let text = read(&scene("fig9-near.toml"))
            .replace(
                "\"../",
                &format!("\"{}/../", root().join("scenes").display()),
            )
            .replace("[0.42, -0.04, 0.72]", "[0.42, -0.04, 0.77]");
        let floating = out.join("floating.toml");
        std::fs::write(&floating, text).expect("scene");
        let report = plan_many(
            std::slice::from_ref(&floating),
            &options(&out.join("plans"), 1),
            &|_| {},
        )
        .expect("runs");
        let s = &report.summaries[0];
        assert_eq!(s.status, SceneStatus::NoPlan, "{s:?}");
        assert!(s.reasons[0].contains("not resting"), "{s:?}");
        assert_eq!(s.error, None);
        assert_eq!(s.plan, None);
        let _ = std::fs::remove_dir_all(&out);
    }

    #[test]
    fn a_plan_path_that_is_an_input_is_never_written_nor_removed() {
        let out = scratch("input");
        // A scene file whose plan would replace it: `x.json` plans into `x.json`.
        let text = read(&scene("fig9-near.toml"));
        let base = root().join("scenes");
        let text = text.replace("\"../", &format!("\"{}/../", base.display()));
        let own = out.join("x.json");
        std::fs::write(&own, &text).expect("scene");
        let report =
            plan_many(std::slice::from_ref(&own), &options(&out, 1), &|_| {}).expect("runs");
        let s = &report.summaries[0];
        assert_eq!(s.status, SceneStatus::Error, "{s:?}");
        assert!(
            s.error
                .as_deref()
                .expect("message")
                .contains("an input of the scene"),
            "{s:?}"
        );
        assert_eq!(read(&own), text, "untouched");
        let _ = std::fs::remove_dir_all(&out);
    }

    #[test]
    fn messages_name_each_cause_once() {
        #[derive(Debug)]
        struct E(&'static str, Option<Box<E>>);
        impl std::fmt::Display for E {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.0)
            }
        }
        impl std::error::Error for E {
            fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
                self.1.as_deref().map(|e| e as _)
            }
        }
        let e = E(
            "a.toml: bad: x",
            Some(Box::new(E("x", Some(Box::new(E("y", None)))))),
        );
        assert_eq!(error_message(&e), "a.toml: bad: x: y");
    }
}
