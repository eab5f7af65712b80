//! `cargo xtask precompute`: clusters every mesh in `meshes/` (both contact modes, the paper's
//! h_max) in parallel and writes the cluster databases into xtask's cache folder:
//! `$PICKPLACE_CACHE`, else `<repo>/target/pickplace-cache` (the `pickplace` command's own
//! default is per user, `~/.cache/pickplace`: give it this folder with `--cache` or
//! `PICKPLACE_CACHE`).
//! A database already valid for its mesh and parameters is kept unless `--force` is given.
//! The loop is the façade's ([`pickplace::precompute`]); this task lists the meshes and shows
//! the progress. Then every shipped scene is set up once, which caches the PRM roadmap of each
//! arm (see `roadmaps`).

use anyhow::{Context, Result};
use pickplace::precompute::{
    self, DatabaseReport, Job, PrecomputeOptions, Rebuild, precompute_parallel,
};
use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::db::CacheStatus;
use pickplace_geometry::mesh::{self, MeshOptions, TriMesh};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Advances the progress bar as each database is done.
struct Bar(indicatif::ProgressBar);

impl precompute::Progress for Bar {
    fn finished(&self, _job: &Job<'_>, outcome: &pickplace_geometry::Result<DatabaseReport>) {
        if outcome.is_ok() {
            self.0.inc(1);
        }
    }
}

/// The mesh files of `dir` (`.stl`, `.obj`, `.ply`, any case), sorted.
fn mesh_files(dir: &Path) -> Result<Vec<PathBuf>> {
    let mut meshes: Vec<PathBuf> = std::fs::read_dir(dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            matches!(
                p.extension()
                    .and_then(|e| e.to_str())
                    .map(str::to_ascii_lowercase)
                    .as_deref(),
                Some("stl" | "obj" | "ply")
            )
        })
        .collect();
    meshes.sort();
    Ok(meshes)
}

/// One line of the log: mesh, mode, loaded or built, time, database path relative to `root`.
fn report_line(root: &Path, report: &DatabaseReport) -> String {
    let rel = report
        .db_path
        .strip_prefix(root)
        .unwrap_or(&report.db_path)
        .display()
        .to_string();
    format!(
        "{:<24} {:<6} {} in {:.2} ms -> {rel}",
        report
            .mesh_path
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default(),
        report.params.mode.name(),
        match report.status {
            CacheStatus::Loaded => "loaded from cache",
            _ => "built",
        },
        report.elapsed.as_secs_f64() * 1e3
    )
}

/// Runs the task from the repository root `root`.
pub fn run(root: &Path, force: bool) -> Result<()> {
    let out = precompute::cache_dir(root);
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let paths = mesh_files(&root.join("meshes"))?;
    let params = [ClusterParams::environment(), ClusterParams::finger()];
    let bar = indicatif::ProgressBar::new((paths.len() * params.len()) as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("precompute {bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let loaded: Vec<(&PathBuf, pickplace_geometry::Result<TriMesh>)> = paths
        .par_iter()
        .map(|path| (path, mesh::load(path, &MeshOptions::default())))
        .collect();
    let mut failed = 0;
    let mut jobs = Vec::new();
    for (path, mesh) in &loaded {
        match mesh {
            Ok(mesh) => jobs.extend(Job::each_mode(path, mesh, &params)),
            Err(e) => {
                failed += 1;
                bar.suspend(|| eprintln!("error: {e:#}"));
            }
        }
    }
    let options = PrecomputeOptions {
        rebuild: if force {
            Rebuild::Always
        } else {
            Rebuild::WhenInvalid
        },
    };
    let bar = Bar(bar);
    let outcomes = precompute_parallel(&jobs, &out, &options, &bar);
    bar.0.finish_and_clear();
    for outcome in outcomes {
        match outcome {
            Ok(report) => eprintln!("{}", report_line(root, &report)),
            Err(e) => {
                failed += 1;
                eprintln!("error: {e:#}");
            }
        }
    }
    anyhow::ensure!(failed == 0, "{failed} mesh(es) failed");
    // PRM roadmaps of the shipped robot's arm groups (§III-C).
    crate::roadmaps::run(root, &out, force)
}
