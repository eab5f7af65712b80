//! `cargo xtask pytest [PYTEST_ARGS…]` (also the last step of `cargo xtask test`): builds the
//! Python package `pickplace` (crates/pickplace-py) in release with maturin into a wheel,
//! installs the wheel into a virtual environment (as `pip install` of a user would), and runs
//! its pytest suite against the release CLI, Ray's tests on a local Ray cluster and the browser
//! view's in headless Chromium (Debian's `chromium`; skipped with a message when it is
//! missing, unless `PICKPLACE_REQUIRE_WEB=1`, which `.ci/run` sets) included. The browser
//! view's two-robot test gets `PICKPLACE_ROBOTS_PACKAGES` as the Rust robot tests do (given,
//! else example-robot-data installed by [`crate::test::install_robots`]).
//!
//! The environment is `$PICKPLACE_PY_VENV`, else `target/py-venv`; it is created with
//! `$PYTHON` (else `python3`) and the pinned tools below when it lacks them, and kept between
//! runs (a fresh clone starts with a fresh one). `maturin build --release` builds into the
//! workspace's `target/`, so the crates below the bindings are compiled once per feature set,
//! not per run; the wheel goes to `target/wheels/`.

use anyhow::{Context, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// What the environment needs, pinned: the build backend, the test runner, numpy, Ray (the
/// `[ray]` extra of the package, for `pickplace.ray`'s tests), viser (the `[web]` extra, for
/// the browser view) and Playwright (which drives the system's Chromium in its tests; no
/// browser of its own is downloaded).
pub const PY_TOOLS: [&str; 6] = [
    "maturin==1.16.0",
    "pytest==9.2.0",
    "numpy==2.4.6",
    "ray==2.60.0",
    "viser==1.1.1",
    "playwright==1.65.2",
];

/// Builds the package into its environment and runs `pytest` on its tests, with the
/// arguments given after the task; fails when a test fails.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let venv = std::env::var_os("PICKPLACE_PY_VENV")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target/py-venv"));
    ensure_venv(&venv)?;
    let robots = match std::env::var_os("PICKPLACE_ROBOTS_PACKAGES") {
        Some(dir) => PathBuf::from(dir),
        None => crate::test::install_robots(root)?,
    };
    let crate_dir = root.join("crates/pickplace-py");
    let wheels = root.join("target/wheels");
    eprintln!(
        "xtask pytest: maturin build --release (into {})",
        wheels.display()
    );
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut paths = vec![venv.join("bin")];
    paths.extend(std::env::split_paths(&path));
    // Old wheels out of the way: the one built now is the one installed.
    if let Ok(entries) = std::fs::read_dir(&wheels) {
        for e in entries.flatten() {
            if is_our_wheel(&e.path()) {
                std::fs::remove_file(e.path())
                    .with_context(|| format!("cannot remove {}", e.path().display()))?;
            }
        }
    }
    let status = Command::new(venv.join("bin/maturin"))
        .current_dir(&crate_dir)
        .args(["build", "--release", "--quiet", "--out"])
        .arg(&wheels)
        .env("PATH", std::env::join_paths(paths)?)
        .status()
        .context("cannot run maturin")?;
    if !status.success() {
        bail!("maturin build --release failed ({status})");
    }
    let wheel = std::fs::read_dir(&wheels)
        .with_context(|| format!("cannot read {}", wheels.display()))?
        .flatten()
        .map(|e| e.path())
        .find(|p| is_our_wheel(p))
        .with_context(|| format!("maturin wrote no pickplace wheel into {}", wheels.display()))?;
    eprintln!("xtask pytest: pip install {}", wheel.display());
    let status = Command::new(venv.join("bin/pip"))
        .args([
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--force-reinstall",
            "--no-deps",
        ])
        .arg(&wheel)
        .status()
        .context("cannot run pip")?;
    if !status.success() {
        bail!("pip install {} failed ({status})", wheel.display());
    }
    let cli = root.join("target/release/pickplace");
    if !cli.is_file() {
        eprintln!("xtask pytest: cargo build --release -p pickplace-cli");
        let status = Command::new(std::env::var("CARGO").unwrap_or_else(|_| "cargo".into()))
            .current_dir(root)
            .args(["build", "--release", "--quiet", "-p", "pickplace-cli"])
            .status()
            .context("cannot run cargo build")?;
        if !status.success() {
            bail!("cargo build --release -p pickplace-cli failed ({status})");
        }
    }
    let chromium = std::env::var_os("PICKPLACE_CHROMIUM")
        .map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    if !chromium.is_file() {
        eprintln!(
            "xtask pytest: no Chromium at {} (Debian: apt-get install chromium; or set \
             PICKPLACE_CHROMIUM): the browser view's tests are skipped{}",
            chromium.display(),
            if std::env::var_os("PICKPLACE_REQUIRE_WEB").is_some_and(|v| v == "1") {
                ", and fail as PICKPLACE_REQUIRE_WEB=1 asks"
            } else {
                ""
            }
        );
    }
    eprintln!("xtask pytest: pytest crates/pickplace-py/tests");
    let status = Command::new(venv.join("bin/python"))
        .current_dir(&crate_dir)
        .args(["-m", "pytest", "-q", "tests"])
        .args(args)
        .env("PICKPLACE_CLI", &cli)
        .env("PICKPLACE_ROBOTS_PACKAGES", &robots)
        .env("PICKPLACE_REQUIRE_RAY", "1")
        .status()
        .context("cannot run pytest")?;
    if !status.success() {
        bail!("pytest of crates/pickplace-py failed ({status})");
    }
    Ok(())
}

/// Whether `path` is a wheel of the package (`pickplace-<version>-….whl`).
fn is_our_wheel(path: &Path) -> bool {
    path.file_name()
        .and_then(|n| n.to_str())
        .is_some_and(|n| n.starts_with("pickplace-") && n.ends_with(".whl"))
}

/// Creates the environment and installs [`PY_TOOLS`] when it does not have them yet.
fn ensure_venv(venv: &Path) -> anyhow::Result<()> {
    let ready = venv.join("bin/maturin").is_file()
        && Command::new(venv.join("bin/python"))
            .args(["-c", "import numpy, pytest, ray, viser, playwright"])
            .status()
            .is_ok_and(|s| s.success());
    if ready {
        return Ok(());
    }
    if !venv.join("bin/python").is_file() {
        if let Some(parent) = venv.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("cannot create {}", parent.display()))?;
        }
        let python = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        eprintln!("xtask pytest: creating {} with {python}", venv.display());
        let status = Command::new(&python)
            .args(["-m", "venv"])
            .arg(venv)
            .status()
            .with_context(|| {
                format!("cannot run {python} (set PYTHON to a Python 3.10+ interpreter)")
            })?;
        if !status.success() {
            bail!("{python} -m venv {} failed ({status})", venv.display());
        }
    }
    eprintln!("xtask pytest: pip install {}", PY_TOOLS.join(" "));
    let status = Command::new(venv.join("bin/pip"))
        .args(["install", "--quiet", "--disable-pip-version-check"])
        .args(PY_TOOLS)
        .status()
        .context("cannot run pip")?;
    if !status.success() {
        bail!("pip install {} failed ({status})", PY_TOOLS.join(" "));
    }
    Ok(())
}
