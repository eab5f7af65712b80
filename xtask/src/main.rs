//! cargo xtask: project automation (matklad's cargo-xtask pattern).

mod acm;
mod bench;
mod clusters;
mod fuzz;
mod gen_meshes;
mod mbm;
mod precompute;
mod python;
mod roadmaps;
mod scanned;
mod stability;
mod suite;
mod suite_run;
mod test;
mod torture;
mod venv;

use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let task = std::env::args().nth(1);
    match task.as_deref() {
        Some("gen-meshes") => gen_meshes::run(&repo_root().join("meshes")),
        Some("acm") => acm::run(&repo_root().join("robots/nx-hiro")),
        Some("bench") => bench::run(&repo_root(), &rest_args()),
        Some("fuzz") => fuzz::run(&repo_root(), &rest_args()),
        Some("fuzz-seeds") => fuzz::write_seeds(&repo_root()),
        Some("suite") => suite::run(&repo_root(), &rest_args()),
        Some("test") => test::run(&repo_root(), &rest_args()),
        Some("pytest") => python::run(&repo_root(), &rest_args()),
        Some("torture") => torture::run(&repo_root(), &rest_args()),
        Some("stability") => stability::run(&repo_root(), &rest_args()),
        Some("clusters") => clusters::run(&repo_root(), &rest_args()),
        Some("mbm") => mbm::run(&repo_root(), &rest_args()),
        Some("precompute") => {
            let force = std::env::args().skip(2).any(|a| a == "--force");
            precompute::run(&repo_root(), force)
        }
        Some("--help" | "-h" | "help") => {
            println!("{USAGE}");
            Ok(())
        }
        _ => {
            eprintln!("{USAGE}");
            std::process::exit(2);
        }
    }
}

/// `cargo xtask --help`: every task and its arguments.
const USAGE: &str = "usage: cargo xtask <task>\n\ntasks:\n  gen-meshes   write the shipped meshes \
     (meshes/*.stl) from pickplace_objects\n  \
     acm          regenerate disable_collisions of robots/nx-hiro/nx-hiro.srdf\n  \
     precompute   [--force]: cluster every mesh in meshes/ (env and finger) into the \
     cache and a PRM roadmap per arm group of NX-HIRO into the cache \
     ($PICKPLACE_CACHE or target/pickplace-cache, not the CLI's per-user \
     default); --force rebuilds\n  \
     bench        [--quick] [--no-run | --text-only] [-- FILTER…]: run the criterion \
     benches and write docs/benchmarks.md from their results and \
     benches/targets.toml; --no-run uses the results on disk, --text-only keeps \
     the figures of the document and rewrites its text\n  \
     fuzz         --seconds N [TARGET…]: run each cargo-fuzz target N seconds \
     (needs nightly and cargo-fuzz); exit 1 on a crash\n  \
     fuzz-seeds   write the generated seed corpora under fuzz/seeds/\n  \
     suite        gen | run [--seeds 1,2,3] [--scenes GLOB] [--write-doc]: write the \
     scene suite (scenes/suite, meshes/suite), or plan and validate every scene of it with \
     the release CLI and check each expectation (docs/suite.md)\n  \
     test         [CARGO_TEST_ARGS…]: install what the tests need (example-robot-data \
     from PyPI into target/robots-venv, once), run cargo test --workspace, then cargo \
     xtask suite run, torture, the toppra comparison and pytest\n  \
     pytest       [PYTEST_ARGS…]: build the Python package (crates/pickplace-py) into a \
     wheel with maturin build --release, install it into $PICKPLACE_PY_VENV or \
     target/py-venv (created with maturin, pytest, numpy, ray, viser and playwright when \
     missing) and run its pytest suite (Ray's tests on a local 2-CPU Ray cluster, the \
     browser view's in headless Chromium)\n  \
     torture      hostile and careless use of the release CLI (FIFOs, devices, huge, \
     truncated, NaN and nested inputs, kill -9 during writes, concurrent runs on one cache, \
     unusable cache folders, closed pipes): every case's exit status, message and files \
     left; target/torture/report.txt\n  \
     stability    [--objects GLOB] [--drops N] [--random N] [--write-doc]: check \
     pickplace_placement::resting_poses on ~150 objects (pybullet_data's, fetched pinned into \
     target/objects, and generated scanned-like meshes): rapier drop test of every offered \
     pose, recall against pybullet drops and trimesh's stable poses; \
     target/objects/report.json, docs/stability.md; exit 1 when a goal is missed\n  \
     clusters     [--objects GLOB] [--random N]: cluster robosuite 1.5.1's object meshes \
     (fetched pinned into target/objects), the stability set and the suite's scans in both \
     modes and count the adjacent cluster pairs that could still be merged; exit 1 when any \
     is left (docs/clustering.md)\n  \
     mbm          [--sample N] [--scenarios GLOB] [--seed S] [--write]: MotionBenchMaker's \
     problems, the Panda's 700 and Baxter's 1 800 (vamp-planner 0.6.4's source archive, \
     fetched pinned into target/mbm) planned by pickplace_prm::rrt_connect with the exact checker, every path \
     checked again at 1°; --write records the figures in benches/mbm.json and \
     docs/benchmarks.md; exit 1 when a path collides";

/// The arguments after the task name.
fn rest_args() -> Vec<String> {
    std::env::args().skip(2).collect()
}

/// The repository root, found from this crate's manifest directory.
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}

#[cfg(test)]
mod tests {
    use super::USAGE;

    /// Every task `main` dispatches is described in the usage text.
    #[test]
    fn every_task_is_in_the_help() {
        let main = include_str!("main.rs");
        let tasks: Vec<&str> = main
            .lines()
            .filter_map(|l| l.trim().strip_prefix("Some(\""))
            .filter_map(|l| l.split('"').next())
            .filter(|t| !t.starts_with('-') && *t != "help")
            .collect();
        assert_eq!(tasks.len(), 13, "{tasks:?}");
        for task in tasks {
            assert!(
                USAGE.contains(&format!("\n  {task} ")),
                "{task} is not in the help"
            );
        }
    }
}
