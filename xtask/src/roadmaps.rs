//! Roadmaps of `cargo xtask precompute` (paper §III-C): every shipped scene in `scenes/` is set
//! up once through the façade, which builds the PRM roadmap of each arm (prefiltered by
//! self-collision, one roadmap serving every scene) and its cluster databases, and caches them
//! in xtask's folder (file names keyed by the robot files, the options and the algorithm
//! versions). A cache that cannot be written is an error here, not a warning.

use anyhow::{Context, Result};
use pickplace::roadmaps::ROADMAP_EXTENSION;
use pickplace::{Setup, SetupOptions};
use std::path::Path;

/// Sets up every scene of `<root>/scenes` with the cache `out`; with `force`, the cached
/// roadmaps are removed first so that they are rebuilt.
pub fn run(root: &Path, out: &Path, force: bool) -> Result<()> {
    if force {
        for entry in std::fs::read_dir(out).with_context(|| format!("reading {}", out.display()))? {
            let path = entry?.path();
            if path.extension().and_then(|e| e.to_str()) == Some(ROADMAP_EXTENSION) {
                std::fs::remove_file(&path)
                    .with_context(|| format!("removing {}", path.display()))?;
            }
        }
    }
    let dir = root.join("scenes");
    let mut scenes: Vec<_> = std::fs::read_dir(&dir)
        .with_context(|| format!("reading {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().and_then(|e| e.to_str()) == Some("toml"))
        .collect();
    scenes.sort();
    let options = SetupOptions {
        cache_dir: Some(out.to_path_buf()),
        ..SetupOptions::default()
    };
    for scene in scenes {
        let start = std::time::Instant::now();
        let setup = Setup::load(&scene, &options)?;
        // Writing the cache is this task's whole job: a warning is an error here.
        if let Some(warning) = setup.warnings.first() {
            anyhow::bail!("{}: {warning}", scene.display());
        }
        eprintln!(
            "{}: set up in {:.2} s",
            scene.display(),
            start.elapsed().as_secs_f64()
        );
        for line in &setup.log {
            eprintln!("  {line}");
        }
    }
    Ok(())
}
