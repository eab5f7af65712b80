//! The batch functions behind `pickplace.batch` and `pickplace.ray` (pure Python, in
//! `python/pickplace/`): many scenes planned in parallel with the code of `pickplace batch`
//! (`pickplace::batch`), and its pieces for callers that spread the scenes themselves.
//! Summaries cross the boundary as the JSON lines of `summary.jsonl`.

use crate::errors::{input, input_msg};
use crate::scene::cache_folder;
use pickplace::batch::{self, BatchEvent, BatchOptions, SceneSummary};
use pickplace::planner::PlanOverrides;
use pyo3::prelude::*;
use std::path::{Path, PathBuf};

/// The options of a batch but its folder and threads, as [`_batch_options`] makes them: what
/// the batch functions take.
#[pyclass(frozen, module = "pickplace", name = "_BatchOptions")]
#[derive(Debug)]
pub struct Options {
    /// The options, with a placeholder folder and thread count (see [`Options::batch`]).
    inner: BatchOptions,
}

/// A batch's options from the keywords `pickplace.batch.plan_many` and `pickplace.ray.plan_many`
/// share, spelled once here for the batch functions below; `cache_dir` `None` is the default
/// cache folder (as the CLI's), unless `use_cache` is false. The strategy is checked and the
/// cache folder chosen here: a Ray task makes its own options, so that the default cache
/// folder is its node's.
///
/// Raises InputError for a strategy that is not one of the CLI's names.
#[pyfunction]
#[pyo3(signature = (*, seed=None, strategy=None, time_budget=None, velocity_scaling=None, acceleration_scaling=None, sample_period=None, timings=false, resume=false, cache_dir=None, use_cache=true, package_dirs=Vec::new()))]
#[allow(clippy::too_many_arguments)]
pub fn _batch_options(
    seed: Option<u64>,
    strategy: Option<&str>,
    time_budget: Option<f64>,
    velocity_scaling: Option<f64>,
    acceleration_scaling: Option<f64>,
    sample_period: Option<f64>,
    timings: bool,
    resume: bool,
    cache_dir: Option<PathBuf>,
    use_cache: bool,
    package_dirs: Vec<PathBuf>,
) -> PyResult<Options> {
    let inner = BatchOptions {
        plan: PlanOverrides {
            seed,
            strategy: strategy.map(crate::plan::strategy).transpose()?,
            time_budget,
            velocity_scaling,
            acceleration_scaling,
            sample_period,
            timings: Some(timings),
        },
        resume,
        cache_dir: cache_folder(cache_dir, use_cache).0,
        package_dirs,
        ..BatchOptions::new(PathBuf::new())
    };
    Ok(Options { inner })
}

impl Options {
    /// These options writing into `out_dir` on `jobs` threads.
    fn batch(&self, out_dir: PathBuf, jobs: usize) -> BatchOptions {
        BatchOptions {
            out_dir,
            jobs,
            ..self.inner.clone()
        }
    }
}

/// A batch-level error as the package's InputError (what stops the whole batch is the
/// caller's input: names, options, the output folder), with the CLI's message.
fn batch_error(e: &batch::BatchError) -> PyErr {
    match e {
        batch::BatchError::Threads { .. } => {
            pyo3::exceptions::PyRuntimeError::new_err(crate::errors::message(e))
        }
        _ => input(e),
    }
}

/// Plans `scenes` into `out_dir` on `workers` threads (`pickplace batch`) with `options`;
/// returns the summary's lines (JSON), one per scene in the order given. `progress(line)` is
/// called as each scene ends, from the worker threads (with the GIL); an exception it raises
/// is printed and ignored.
#[pyfunction]
#[pyo3(signature = (scenes, out_dir, options, *, workers=None, progress=None))]
pub fn _batch_plan_many(
    py: Python<'_>,
    scenes: Vec<PathBuf>,
    out_dir: PathBuf,
    options: &Bound<'_, Options>,
    workers: Option<usize>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Vec<String>> {
    let options = options
        .get()
        .batch(out_dir, workers.unwrap_or_else(batch::default_jobs));
    let report = py
        .detach(|| {
            batch::plan_many(&scenes, &options, &|event| {
                if let (BatchEvent::Finished { summary, .. }, Some(callback)) = (event, &progress) {
                    let line = summary.to_json_line();
                    Python::attach(|py| {
                        if let Err(e) = callback.call1(py, (line,)) {
                            e.print(py);
                        }
                    });
                }
            })
        })
        .map_err(|e| batch_error(&e))?;
    Ok(report
        .summaries
        .iter()
        .map(SceneSummary::to_json_line)
        .collect())
}

/// What a batch does before planning (`pickplace::batch::prepare`): checks `options` and
/// the scenes' names, creates `out_dir`; returns each scene's plan file.
#[pyfunction]
pub fn _batch_prepare(
    scenes: Vec<PathBuf>,
    out_dir: PathBuf,
    options: &Bound<'_, Options>,
) -> PyResult<Vec<PathBuf>> {
    let options = options.get().batch(out_dir, 1);
    batch::prepare(&scenes, &options).map_err(|e| batch_error(&e))
}

/// One scene of a batch planned into `plan_path` (`pickplace::batch::plan_scene`) with
/// `options`, on a pool of `threads` threads (default: rayon's global pool,
/// `RAYON_NUM_THREADS`); its summary line, with `scene` shown as `display` when given.
#[pyfunction]
#[pyo3(signature = (scene, plan_path, options, *, display=None, threads=None))]
pub fn _batch_plan_one(
    py: Python<'_>,
    scene: PathBuf,
    plan_path: PathBuf,
    options: &Bound<'_, Options>,
    display: Option<String>,
    threads: Option<usize>,
) -> PyResult<String> {
    let out_dir = plan_path
        .parent()
        .map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    let options = options
        .get()
        .batch(out_dir, threads.unwrap_or_else(batch::default_jobs));
    if threads == Some(0) {
        return Err(input_msg("threads: 0 threads: give at least 1"));
    }
    let mut summary = py.detach(|| -> PyResult<SceneSummary> {
        match threads {
            Some(n) => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
                Ok(pool.install(|| batch::plan_scene(&scene, &plan_path, &options)))
            }
            None => Ok(batch::plan_scene(&scene, &plan_path, &options)),
        }
    })?;
    if let Some(name) = display {
        summary.scene = name;
    }
    Ok(summary.to_json_line())
}

/// Writes summary lines (JSON, as the functions above return them) to `path` atomically,
/// in the order given.
#[pyfunction]
pub fn _batch_write_summary(path: PathBuf, lines: Vec<String>) -> PyResult<()> {
    let summaries = lines
        .iter()
        .enumerate()
        .map(|(i, line)| {
            serde_json::from_str::<SceneSummary>(line)
                .map_err(|e| input_msg(format!("summary line {i}: {e}")))
        })
        .collect::<PyResult<Vec<_>>>()?;
    batch::write_summary(&path, &summaries).map_err(|e| batch_error(&e))
}
