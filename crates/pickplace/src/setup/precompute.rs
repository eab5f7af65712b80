//! The offline phase's cluster databases (Harada et al. §III-A): every mesh clustered once per
//! contact mode and kept in a cache folder, where [`crate::Setup`] finds them.
//!
//! One loop serves `pickplace precompute` and `cargo xtask precompute`: [`precompute`] runs the
//! jobs one after the other, [`precompute_parallel`] on rayon's pool. Each job loads the
//! database a previous run left in the cache when it is valid for its mesh and parameters, and
//! builds and saves it otherwise (or always, with [`Rebuild::Always`]). Callers show their own
//! progress through a [`Progress`].
//!
//! # Example
//! ```
//! use pickplace::geometry::cluster::ClusterParams;
//! use pickplace::geometry::shapes;
//! use pickplace::precompute::{Job, PrecomputeOptions, precompute};
//! use std::path::Path;
//!
//! let cache = std::env::temp_dir().join(format!("pickplace-precompute-doc-{}", std::process::id()));
//! std::fs::create_dir_all(&cache)?;
//! // A drink can: radius 3.3 cm, height 12 cm, 64 facets around.
//! let can = shapes::cylinder(0.033, 0.12, 64);
//! let params = [ClusterParams::environment(), ClusterParams::finger()];
//! let jobs = Job::each_mode(Path::new("can.stl"), &can, &params);
//! let reports = precompute(&jobs, &cache, &PrecomputeOptions::default(), &())?;
//! assert_eq!(reports.len(), 2);
//! assert!(reports.iter().all(|r| r.status != pickplace::geometry::db::CacheStatus::Loaded));
//! // A second run finds both databases in the cache.
//! let again = precompute(&jobs, &cache, &PrecomputeOptions::default(), &())?;
//! assert!(again.iter().all(|r| r.status == pickplace::geometry::db::CacheStatus::Loaded));
//! # std::fs::remove_dir_all(&cache)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use pickplace_geometry::Result;
use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::db::{CacheStatus, ClusterDatabase, cache_path};
use pickplace_geometry::mesh::TriMesh;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

pub use crate::cache::CACHE_ENV;

/// The cache folder under a base folder when [`CACHE_ENV`] is not set, for the xtask
/// commands' own runs ([`cache_dir`]). The `pickplace` command's default is per user
/// ([`crate::cache::default_dir`]).
pub const DEFAULT_CACHE_DIR: &str = "target/pickplace-cache";

/// The cache folder of the xtask commands: `$PICKPLACE_CACHE` when set and not empty, else
/// `base/`[`DEFAULT_CACHE_DIR`] (the repository's target folder).
pub fn cache_dir(base: &Path) -> PathBuf {
    std::env::var_os(CACHE_ENV)
        .filter(|v| !v.is_empty())
        .map_or_else(|| base.join(DEFAULT_CACHE_DIR), PathBuf::from)
}

/// What to do with a database the cache already holds.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Rebuild {
    /// Keep a database valid for its mesh and parameters; build the others (default).
    #[default]
    WhenInvalid,
    /// Build and save every database, valid or not (`--force`).
    Always,
}

/// Options of [`precompute`] and [`precompute_parallel`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PrecomputeOptions {
    /// When cached databases are rebuilt (default: [`Rebuild::WhenInvalid`]).
    pub rebuild: Rebuild,
}

/// The reason recorded in [`CacheStatus::Built`] when [`Rebuild::Always`] rebuilt a database.
pub const FORCED_REASON: &str = "--force";

/// One database to make: a loaded mesh, the file it came from (which names the database, see
/// [`cache_path`]) and the clustering parameters.
#[derive(Debug, Clone, Copy)]
pub struct Job<'a> {
    /// The mesh's file.
    pub mesh_path: &'a Path,
    /// The mesh, as loaded from `mesh_path`.
    pub mesh: &'a TriMesh,
    /// Clustering parameters (contact mode and `h_max`).
    pub params: ClusterParams,
}

impl<'a> Job<'a> {
    /// One job per parameter set for the same mesh, in the order of `params`.
    pub fn each_mode(
        mesh_path: &'a Path,
        mesh: &'a TriMesh,
        params: &[ClusterParams],
    ) -> Vec<Self> {
        params
            .iter()
            .map(|&params| Job {
                mesh_path,
                mesh,
                params,
            })
            .collect()
    }
}

/// What one job did.
#[derive(Debug, Clone)]
pub struct DatabaseReport {
    /// The mesh's file.
    pub mesh_path: PathBuf,
    /// Clustering parameters.
    pub params: ClusterParams,
    /// Where the database is in the cache.
    pub db_path: PathBuf,
    /// The database (loaded or built).
    pub database: ClusterDatabase,
    /// Loaded from the cache, or built (with the reason the cached file was not used).
    pub status: CacheStatus,
    /// Wall time of the job.
    pub elapsed: Duration,
}

/// Progress of a precompute run, for a progress bar or a log. Both methods do nothing by
/// default; `()` reports nothing. With [`precompute_parallel`] they are called from rayon's
/// worker threads, in the order the jobs run.
pub trait Progress: Sync {
    /// A job starts.
    fn started(&self, job: &Job<'_>) {
        let _ = job;
    }
    /// A job ended, with its report or its error.
    fn finished(&self, job: &Job<'_>, outcome: &Result<DatabaseReport>) {
        let _ = (job, outcome);
    }
}

impl Progress for () {}

/// Loads or builds one job's database in `cache_dir` (which must exist).
///
/// # Errors
/// The geometry crate's error when the mesh cannot be clustered with these parameters or the
/// database cannot be written.
pub fn precompute_one(
    job: &Job<'_>,
    cache_dir: &Path,
    options: &PrecomputeOptions,
) -> Result<DatabaseReport> {
    let start = Instant::now();
    let db_path = cache_path(cache_dir, job.mesh_path, &job.params);
    let (database, status) = match options.rebuild {
        Rebuild::Always => {
            let database = ClusterDatabase::build(job.mesh, &job.params)?;
            database.save(&db_path)?;
            let reason = Some(FORCED_REASON.to_owned());
            (database, CacheStatus::Built { reason })
        }
        Rebuild::WhenInvalid => ClusterDatabase::load_or_build(&db_path, job.mesh, &job.params)?,
    };
    Ok(DatabaseReport {
        mesh_path: job.mesh_path.to_path_buf(),
        params: job.params,
        db_path,
        database,
        status,
        elapsed: start.elapsed(),
    })
}

/// Runs every job in order, stopping at the first error.
///
/// # Arguments
/// * `jobs` – the databases to make ([`Job::each_mode`] builds them per mesh).
/// * `cache_dir` – the cache folder; it must exist.
/// * `options` – when cached databases are rebuilt.
/// * `progress` – told when each job starts and ends.
///
/// # Returns
/// One report per job, in the order of `jobs`.
///
/// # Errors
/// The first job's error, as [`precompute_one`].
pub fn precompute(
    jobs: &[Job<'_>],
    cache_dir: &Path,
    options: &PrecomputeOptions,
    progress: &dyn Progress,
) -> Result<Vec<DatabaseReport>> {
    jobs.iter()
        .map(|job| run_job(job, cache_dir, options, progress))
        .collect()
}

/// Runs every job on rayon's pool; one job's error does not stop the others.
///
/// # Returns
/// One outcome per job, in the order of `jobs` (whatever order they ran in).
///
/// # Performance
/// Jobs are independent (each writes its own file); clustering a mesh is single-threaded, so
/// the speed-up grows with the number of jobs up to the pool's threads.
pub fn precompute_parallel(
    jobs: &[Job<'_>],
    cache_dir: &Path,
    options: &PrecomputeOptions,
    progress: &dyn Progress,
) -> Vec<Result<DatabaseReport>> {
    jobs.par_iter()
        .map(|job| run_job(job, cache_dir, options, progress))
        .collect()
}

fn run_job(
    job: &Job<'_>,
    cache_dir: &Path,
    options: &PrecomputeOptions,
    progress: &dyn Progress,
) -> Result<DatabaseReport> {
    progress.started(job);
    let outcome = precompute_one(job, cache_dir, options);
    progress.finished(job, &outcome);
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::cluster::ContactMode;
    use pickplace_objects as objects;
    use std::sync::Mutex;

    /// An empty cache folder for one test (removed by the test when it passes).
    fn empty_cache(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!(
            "pickplace-precompute-{name}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("cache folder");
        dir
    }

    /// Records the calls, as a progress bar would see them.
    #[derive(Default)]
    struct Log(Mutex<Vec<String>>);

    impl Progress for Log {
        fn started(&self, job: &Job<'_>) {
            self.0
                .lock()
                .expect("log")
                .push(format!("start {}", job.params.mode.name()));
        }
        fn finished(&self, job: &Job<'_>, outcome: &Result<DatabaseReport>) {
            let what = if outcome.is_ok() { "ok" } else { "error" };
            self.0
                .lock()
                .expect("log")
                .push(format!("end {} {what}", job.params.mode.name()));
        }
    }

    fn modes() -> [ClusterParams; 2] {
        [ClusterParams::environment(), ClusterParams::finger()]
    }

    #[test]
    fn builds_then_loads_then_forced_rebuild() {
        let dir = empty_cache("cycle");
        let can = objects::can_builder().build().expect("can");
        let jobs = Job::each_mode(Path::new("meshes/can.stl"), &can, &modes());
        let log = Log::default();
        let first = precompute(&jobs, &dir, &PrecomputeOptions::default(), &log).expect("first");
        assert_eq!(
            *log.0.lock().expect("log"),
            ["start env", "end env ok", "start finger", "end finger ok"]
        );
        assert_eq!(first.len(), 2);
        for (report, params) in first.iter().zip(modes()) {
            assert_eq!(report.status, CacheStatus::Built { reason: None });
            assert_eq!(report.params, params);
            assert_eq!(
                report.db_path,
                cache_path(&dir, Path::new("can.stl"), &params)
            );
            assert!(report.db_path.is_file());
            assert_eq!(report.mesh_path, Path::new("meshes/can.stl"));
        }
        assert_eq!(
            first[1].database.clustering.params.mode,
            ContactMode::Finger
        );

        let second = precompute(&jobs, &dir, &PrecomputeOptions::default(), &()).expect("second");
        assert!(second.iter().all(|r| r.status == CacheStatus::Loaded));
        for (a, b) in first.iter().zip(&second) {
            assert_eq!(
                a.database.clustering.clusters.len(),
                b.database.clustering.clusters.len()
            );
        }

        let forced = PrecomputeOptions {
            rebuild: Rebuild::Always,
        };
        let third = precompute(&jobs[..1], &dir, &forced, &()).expect("forced");
        assert_eq!(
            third[0].status,
            CacheStatus::Built {
                reason: Some(FORCED_REASON.to_owned())
            }
        );
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn parallel_keeps_the_job_order_and_goes_on_after_an_error() {
        let dir = empty_cache("parallel");
        let can = objects::can_builder().build().expect("can");
        let bad = ClusterParams {
            h_max: -1.0,
            ..ClusterParams::environment()
        };
        let params = [ClusterParams::finger(), bad, ClusterParams::environment()];
        let jobs = Job::each_mode(Path::new("can.stl"), &can, &params);
        let log = Log::default();
        let outcomes = precompute_parallel(&jobs, &dir, &PrecomputeOptions::default(), &log);
        assert_eq!(outcomes.len(), 3);
        assert_eq!(
            outcomes[0].as_ref().expect("finger").params.mode,
            ContactMode::Finger
        );
        assert!(outcomes[1].is_err(), "negative h_max");
        assert_eq!(
            outcomes[2].as_ref().expect("env").params.mode,
            ContactMode::Environment
        );
        assert_eq!(log.0.lock().expect("log").len(), 6);
        // In order, the same invalid job stops the run before the third.
        let log = Log::default();
        assert!(precompute(&jobs, &dir, &PrecomputeOptions::default(), &log).is_err());
        assert_eq!(log.0.lock().expect("log").len(), 4);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn cache_dir_under_the_base_or_from_the_environment() {
        // The variable is read, not written, here: tests run in parallel threads.
        match std::env::var_os(CACHE_ENV).filter(|v| !v.is_empty()) {
            Some(set) => assert_eq!(cache_dir(Path::new("/repo")), PathBuf::from(set)),
            None => {
                assert_eq!(
                    cache_dir(Path::new("/repo")),
                    Path::new("/repo/target/pickplace-cache")
                );
            }
        }
    }
}
