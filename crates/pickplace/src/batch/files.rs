//! The batch's files: each scene's plan file name, the output folder, what may be at a plan's
//! path (never an input of the scene) and the removal of an earlier run's stale plan.

use super::{BatchError, SUMMARY_FILE, SceneSummary};
use crate::scene::Scene;
use std::path::{Path, PathBuf};

/// Each scene's plan file name, `<stem>.json`.
///
/// # Errors
/// [`BatchError::NoFileName`] for a path without a file name, [`BatchError::SameName`] for
/// two scenes with the same stem (compared ignoring case).
pub fn plan_file_names(scenes: &[PathBuf]) -> Result<Vec<String>, BatchError> {
    let mut names: Vec<String> = Vec::with_capacity(scenes.len());
    for (i, scene) in scenes.iter().enumerate() {
        let stem = scene
            .file_name()
            .and_then(|_| scene.file_stem())
            .ok_or_else(|| BatchError::NoFileName {
                scene: scene.clone(),
            })?;
        let name = format!("{}.json", stem.to_string_lossy());
        if let Some(j) = names
            .iter()
            .position(|n| n.to_lowercase() == name.to_lowercase())
        {
            return Err(BatchError::SameName {
                first: scenes[j].clone(),
                second: scenes[i].clone(),
                file: name,
            });
        }
        names.push(name);
    }
    Ok(names)
}

/// Creates the output folder when missing and checks it and the summary's path; returns the
/// summary's path.
pub(super) fn prepare_out_dir(dir: &Path) -> Result<PathBuf, BatchError> {
    let out = |reason: String| BatchError::Output {
        path: dir.to_path_buf(),
        reason,
    };
    if let Ok(meta) = std::fs::metadata(dir)
        && !meta.is_dir()
    {
        return Err(out(
            "is not a folder; give a folder (created if missing)".to_owned()
        ));
    }
    std::fs::create_dir_all(dir).map_err(|e| out(format!("cannot create the folder: {e}")))?;
    let summary = dir.join(SUMMARY_FILE);
    if let Err(reason) = check_regular_or_absent(&summary) {
        return Err(BatchError::Output {
            path: summary,
            reason: reason.to_string(),
        });
    }
    Ok(summary)
}

/// Why a batch output cannot be written where it goes (the sentence follows its path).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(super) enum UnusableOutput {
    /// A symbolic link is there.
    #[error(
        "is a symbolic link; batch outputs replace what is at their path, so remove it or give another output folder"
    )]
    SymbolicLink,
    /// A folder is there.
    #[error("is a folder where the batch writes a file")]
    Folder,
    /// A device, FIFO or socket is there.
    #[error("is a device, FIFO or socket, not a regular file; outputs are regular files only")]
    Special,
    /// The path is (or is a link to) an input of the scene.
    #[error("is {}, an input of the scene; it would be overwritten", .0.display())]
    AnInput(PathBuf),
}

/// `Ok` when nothing is at `path` or a regular file is; else what is there.
fn check_regular_or_absent(path: &Path) -> Result<(), UnusableOutput> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    let kind = meta.file_type();
    if kind.is_symlink() {
        Err(UnusableOutput::SymbolicLink)
    } else if kind.is_dir() {
        Err(UnusableOutput::Folder)
    } else if !kind.is_file() {
        Err(UnusableOutput::Special)
    } else {
        Ok(())
    }
}

/// The files a scene names, which a plan file must never replace: the scene, each robot's
/// URDF, SRDF and gripper file, the object and environment meshes.
pub(super) fn scene_inputs(scene_path: &Path, scene: &Scene) -> Vec<PathBuf> {
    let mut inputs = vec![scene_path.to_path_buf()];
    for robot in &scene.robots {
        inputs.push(robot.urdf.clone());
        inputs.extend(robot.srdf.iter().cloned());
        inputs.extend(robot.gripper.iter().cloned());
    }
    inputs.push(scene.object.mesh.clone());
    inputs.extend(scene.environment.iter().filter_map(|e| e.mesh.clone()));
    inputs
}

/// `Ok` when a plan may be written at `plan_path`: nothing there, or a regular file that is
/// none of `inputs` (compared by identity: another path or a hard link to an input counts).
pub(super) fn check_plan_path(plan_path: &Path, inputs: &[PathBuf]) -> Result<(), UnusableOutput> {
    check_regular_or_absent(plan_path)?;
    if let Some(input) = inputs.iter().find(|i| same_file(plan_path, i)) {
        return Err(UnusableOutput::AnInput(input.clone()));
    }
    Ok(())
}

/// True when `a` and `b` are the same existing file.
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        match (std::fs::metadata(a), std::fs::metadata(b)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
            (Ok(a), Ok(b)) => a == b,
            _ => false,
        }
    }
}

/// Removes the plan file an earlier run left at `plan_path` for a scene that has no plan now:
/// only a regular file that is none of `inputs`. A failure is a warning of the line.
pub(super) fn remove_stale(plan_path: &Path, inputs: &[PathBuf], s: &mut SceneSummary) {
    let regular = std::fs::symlink_metadata(plan_path).is_ok_and(|m| m.file_type().is_file());
    if !regular || inputs.iter().any(|i| same_file(plan_path, i)) {
        return;
    }
    if let Err(e) = std::fs::remove_file(plan_path) {
        s.warnings.push(format!(
            "{}: the plan file of an earlier run cannot be removed ({e})",
            plan_path.display()
        ));
    }
}
