//! Python virtual environments of the comparisons with other tools (toppra, OMPL), made
//! once with pinned packages from PyPI.

use anyhow::{Context, bail};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The Python of the virtual environment `venv`, created with `$PYTHON` (else `python3`) and
/// `packages` installed when `probe` (Python code, `import toppra`) fails in it. `who` names
/// the command in the messages.
///
/// # Errors
/// A Python, `venv` or `pip` that cannot run or fails, named.
pub fn ensure(venv: &Path, probe: &str, packages: &[&str], who: &str) -> anyhow::Result<PathBuf> {
    let python = venv.join("bin/python");
    let ready = Command::new(&python)
        .args(["-c", probe])
        .status()
        .is_ok_and(|s| s.success());
    if ready {
        return Ok(python);
    }
    if let Some(parent) = venv.parent() {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    if !python.is_file() {
        let system = std::env::var("PYTHON").unwrap_or_else(|_| "python3".into());
        eprintln!("{who}: creating {} with {system}", venv.display());
        let status = Command::new(&system)
            .args(["-m", "venv"])
            .arg(venv)
            .status()
            .with_context(|| format!("cannot run {system}"))?;
        if !status.success() {
            bail!("{system} -m venv {} failed ({status})", venv.display());
        }
    }
    eprintln!("{who}: pip install {}", packages.join(" "));
    let status = Command::new(venv.join("bin/pip"))
        .args(["install", "--quiet", "--disable-pip-version-check"])
        .args(packages)
        .status()
        .context("cannot run pip")?;
    if !status.success() {
        bail!("pip install {} failed ({status})", packages.join(" "));
    }
    Ok(python)
}
