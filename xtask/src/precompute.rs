//! `cargo xtask precompute`: clusters every mesh in `meshes/` (both contact modes, the paper's
//! h_max) in parallel and writes the cluster databases into the cache folder where the planner
//! and `pickplace precompute` look for them: `$PICKPLACE_CACHE`, else `<repo>/target/pickplace-cache`.
//! A database already valid for its mesh and parameters is kept unless `--force` is given.
//! Then every shipped scene is set up once, which caches the PRM roadmap of each arm (see
//! `roadmaps`).

use anyhow::{Context, Result};
use pickplace_geometry::cluster::ClusterParams;
use pickplace_geometry::db::{CacheStatus, ClusterDatabase, cache_path};
use pickplace_geometry::mesh::{self, MeshOptions};
use rayon::prelude::*;
use std::path::{Path, PathBuf};

/// Runs the task from the repository root `root`.
pub fn run(root: &Path, force: bool) -> Result<()> {
    let meshes_dir = root.join("meshes");
    let out = std::env::var_os("PICKPLACE_CACHE")
        .filter(|v| !v.is_empty())
        .map_or_else(
            || root.join("target").join("pickplace-cache"),
            PathBuf::from,
        );
    std::fs::create_dir_all(&out).with_context(|| format!("creating {}", out.display()))?;
    let mut meshes: Vec<PathBuf> = std::fs::read_dir(&meshes_dir)
        .with_context(|| format!("reading {}", meshes_dir.display()))?
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
    let jobs: Vec<(PathBuf, ClusterParams)> = meshes
        .iter()
        .flat_map(|m| {
            [
                (m.clone(), ClusterParams::environment()),
                (m.clone(), ClusterParams::finger()),
            ]
        })
        .collect();
    let bar = indicatif::ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("precompute {bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let results: Vec<Result<String>> = jobs
        .par_iter()
        .map(|(path, params)| {
            let start = std::time::Instant::now();
            let mesh = mesh::load(path, &MeshOptions::default())?;
            let db_path = cache_path(&out, path, params);
            let status = if force {
                ClusterDatabase::build(&mesh, params)?.save(&db_path)?;
                CacheStatus::Built {
                    reason: Some("--force".into()),
                }
            } else {
                ClusterDatabase::load_or_build(&db_path, &mesh, params)?.1
            };
            bar.inc(1);
            let rel = db_path
                .strip_prefix(root)
                .unwrap_or(&db_path)
                .display()
                .to_string();
            Ok(format!(
                "{:<24} {:<6} {} in {:.2} ms -> {rel}",
                path.file_name()
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default(),
                params.mode.name(),
                match status {
                    CacheStatus::Loaded => "loaded from cache",
                    _ => "built",
                },
                start.elapsed().as_secs_f64() * 1e3
            ))
        })
        .collect();
    bar.finish_and_clear();
    let mut failed = 0;
    for r in results {
        match r {
            Ok(line) => eprintln!("{line}"),
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
