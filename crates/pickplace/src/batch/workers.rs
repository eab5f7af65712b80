//! The worker threads, each with a rayon pool of its own, taking the scenes in turn, and the
//! progress events they report ([`BatchEvent`]).

use super::run::guarded_plan_one;
use super::{BatchError, BatchOptions, SceneStatus, SceneSummary};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Progress of [`plan_many`](super::plan_many), reported from the worker threads as scenes
/// start and end.
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
pub(super) fn run_workers(
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn threads_are_shared_out_between_the_workers() {
        assert_eq!(worker_threads(2, 4), [2, 2]);
        assert_eq!(worker_threads(2, 1), [2]);
        assert_eq!(worker_threads(5, 2), [5, 5]);
        assert_eq!(worker_threads(1, 0), [1]);
        assert_eq!(worker_threads(0, 3), [1]);
    }
}
