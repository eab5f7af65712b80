//! `cargo xtask test [-- CARGO_TEST_ARGS…]`: every test of the workspace, with what the tests
//! need installed first, then the scene suite in release (`cargo xtask suite run`, seeds 1 to
//! 3: every feasible scene plans and validates, every infeasible one is refused for its
//! reason), then the torture suite (`cargo xtask torture`: hostile and careless input, kills,
//! concurrent runs, unusable cache folders, closed pipes), the comparison with toppra, and
//! the Python package's pytest suite (`cargo xtask pytest`, built with maturin into
//! `target/py-venv` or `$PICKPLACE_PY_VENV`).
//!
//! The robots-as-shipped tests plan with PR2, Baxter, TALOS and two Pandas from the public
//! PyPI package `example-robot-data` (version pinned below). It is installed with a plain
//! `pip install` into a virtual environment of its own, `target/robots-venv` or
//! `$PICKPLACE_ROBOTS_VENV` (kept between runs: a second run installs nothing), and the tests
//! find its files through
//! `PICKPLACE_ROBOTS_PACKAGES` (the folder that holds `example-robot-data/`).

use anyhow::{Context, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The pinned release of `example-robot-data` on PyPI.
pub const EXAMPLE_ROBOT_DATA: &str = "example-robot-data==6.0.0";

/// Runs the workspace tests with the robot package installed.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let packages = install_robots(root)?;
    eprintln!("xtask test: robots from {}", packages.display());
    let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
        .current_dir(root)
        .args(["test", "--workspace"])
        .args(args)
        .env("PICKPLACE_ROBOTS_PACKAGES", &packages)
        .status()
        .context("cannot run cargo test")?;
    if !status.success() {
        bail!("cargo test failed ({status})");
    }
    // The scene suite of issue 17 in release, every scene with seeds 1 to 3 (docs/suite.md).
    eprintln!("xtask test: cargo xtask suite run");
    crate::suite_run::run(root, &[])?;
    // Hostile and careless use of the release CLI (issue 18; docs/torture.md).
    eprintln!("xtask test: cargo xtask torture");
    crate::torture::run(root, &[])?;
    // Our motion durations against the toppra package on the shipped scenes (issue 19).
    toppra_compare(root)?;
    // The Python package, built into its virtual environment, and its pytest suite (issue 20).
    eprintln!("xtask test: cargo xtask pytest");
    crate::python::run(root, &[])
}

/// The pinned release of `toppra` on PyPI (the reference of issue 19; numpy and scipy come
/// with it). Not a dependency of any crate.
pub const TOPPRA: &str = "toppra==0.6.10";

/// Most a motion of a shipped scene may take over toppra's time on the same path (issue 19).
const MAX_TOPPRA_RATIO: &str = "1.05";

/// Runs `benches/toppra_plans.py` on the shipped scenes with the release CLI (built by the
/// suite), in a virtual environment with `toppra` (`$PICKPLACE_TOPPRA_VENV`, else
/// `target/toppra-venv`; created when missing); fails when a motion is more than
/// [`MAX_TOPPRA_RATIO`] times toppra's.
fn toppra_compare(root: &Path) -> anyhow::Result<()> {
    let venv = std::env::var_os("PICKPLACE_TOPPRA_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/toppra-venv"));
    let python = crate::venv::ensure(&venv, "import toppra", &[TOPPRA], "xtask test")?;
    let mut scenes: Vec<PathBuf> = std::fs::read_dir(root.join("scenes"))
        .context("cannot list scenes/")?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    scenes.sort();
    eprintln!(
        "xtask test: benches/toppra_plans.py on {} shipped scenes",
        scenes.len()
    );
    let status = Command::new(&python)
        .current_dir(root)
        .arg("benches/toppra_plans.py")
        .args(["--max-ratio", MAX_TOPPRA_RATIO])
        .arg(root.join("target/release/pickplace"))
        .args(&scenes)
        .status()
        .context("cannot run benches/toppra_plans.py")?;
    if !status.success() {
        bail!("benches/toppra_plans.py failed ({status})");
    }
    Ok(())
}

/// Installs `example-robot-data` into its virtual environment when it is not there yet, and
/// returns the folder that holds `example-robot-data/`. The environment is
/// `$PICKPLACE_ROBOTS_VENV` when set (CI keeps it between runs), else `target/robots-venv`.
pub fn install_robots(root: &Path) -> anyhow::Result<PathBuf> {
    let venv = std::env::var_os("PICKPLACE_ROBOTS_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/robots-venv"));
    if let Some(share) = find_share(&venv) {
        return Ok(share);
    }
    if let Some(parent) = venv.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
    eprintln!("xtask test: creating {} with {python}", venv.display());
    let status = Command::new(&python)
        .args(["-m", "venv"])
        .arg(&venv)
        .status()
        .with_context(|| format!("cannot run {python} (set PYTHON to a Python 3 interpreter)"))?;
    if !status.success() {
        bail!("{python} -m venv {} failed ({status})", venv.display());
    }
    let pip = venv.join("bin/pip");
    eprintln!("xtask test: pip install {EXAMPLE_ROBOT_DATA}");
    let status = Command::new(&pip)
        .args([
            "install",
            "--quiet",
            "--disable-pip-version-check",
            EXAMPLE_ROBOT_DATA,
        ])
        .status()
        .with_context(|| format!("cannot run {}", pip.display()))?;
    if !status.success() {
        bail!("pip install {EXAMPLE_ROBOT_DATA} failed ({status})");
    }
    find_share(&venv).with_context(|| {
        format!(
            "{EXAMPLE_ROBOT_DATA} installed, but no cmeel.prefix/share/example-robot-data under {}",
            venv.display()
        )
    })
}

/// `VENV/lib/pythonX.Y/site-packages/cmeel.prefix/share` when it holds the robots.
fn find_share(venv: &Path) -> Option<PathBuf> {
    let lib = std::fs::read_dir(venv.join("lib")).ok()?;
    let mut found: Vec<PathBuf> = lib
        .filter_map(|e| e.ok())
        .map(|e| e.path().join("site-packages/cmeel.prefix/share"))
        .filter(|p| p.join("example-robot-data/robots").is_dir())
        .collect();
    found.sort();
    found.pop()
}
