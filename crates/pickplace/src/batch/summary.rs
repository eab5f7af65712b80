//! A scene's line of `summary.jsonl` ([`SceneSummary`], its [`SceneStatus`]) and the summary
//! file written from the lines.

use super::{BatchError, error_message};
use crate::strategy::Strategy;
use pickplace_geometry::export::write_atomic;
use pickplace_geometry::math::Real;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The `format` of every summary line.
pub const SUMMARY_FORMAT: &str = "pickplace.batch/1";

/// The summary's file name in the output folder.
pub const SUMMARY_FILE: &str = "summary.jsonl";

/// How a scene ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SceneStatus {
    /// Planned, and the plan written.
    Planned,
    /// No strategy found a plan, or the scene is infeasible (a start state in collision, the
    /// object not resting, the target on no usable surface): `pickplace plan`'s exit status 1.
    NoPlan,
    /// The scene or a file it names is bad input (`pickplace plan`'s exit status 2).
    BadInput,
    /// Resumed: the plan file already there is valid and was kept.
    Skipped,
    /// The plan could not be written (or its path is not a regular file, or is an input of
    /// the scene), or a defect of the planner (a panic included).
    Error,
}

impl SceneStatus {
    /// Every status, in the order a report lists them.
    pub const ALL: [SceneStatus; 5] = [
        SceneStatus::Planned,
        SceneStatus::Skipped,
        SceneStatus::NoPlan,
        SceneStatus::BadInput,
        SceneStatus::Error,
    ];

    /// The word of the summary (`planned`, `no-plan`, `bad-input`, `skipped`, `error`).
    pub fn name(self) -> &'static str {
        match self {
            SceneStatus::Planned => "planned",
            SceneStatus::NoPlan => "no-plan",
            SceneStatus::BadInput => "bad-input",
            SceneStatus::Skipped => "skipped",
            SceneStatus::Error => "error",
        }
    }
}

impl std::fmt::Display for SceneStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// One line of `summary.jsonl`: every field is always there (`null` or `[]` when it does
/// not apply), in this order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSummary {
    /// [`SUMMARY_FORMAT`].
    pub format: String,
    /// The scene file, as given.
    pub scene: String,
    /// How it ended.
    pub status: SceneStatus,
    /// The plan file (planned or skipped), else `None`.
    pub plan: Option<String>,
    /// The strategy of the plan.
    pub strategy: Option<Strategy>,
    /// The seed used (the plan's when skipped), once the scene was read.
    pub seed: Option<u64>,
    /// The plan's duration of motion (s).
    pub duration: Option<Real>,
    /// Wall-clock time spent on the scene (s): loading, planning and writing, or checking
    /// the plan kept; `None` without
    /// [`BatchOptions::timings`](super::BatchOptions::timings).
    pub time: Option<Real>,
    /// Why there is no plan: per strategy, the counts per stage and the most frequent
    /// rejections ([`crate::planner::Failure::reasons`]), or the infeasible scene's message.
    pub reasons: Vec<String>,
    /// The message of a bad input or an error, as `pickplace plan` prints it.
    pub error: Option<String>,
    /// Why a plan file found by a resumed run was not kept (it is planned again).
    pub replanned: Option<String>,
    /// The cache's warning, if any (the scene was set up in memory).
    pub warnings: Vec<String>,
}

impl SceneSummary {
    /// A line for `scene` with nothing known yet (status [`SceneStatus::Error`]).
    pub(super) fn new(scene: &Path) -> Self {
        Self {
            format: SUMMARY_FORMAT.to_owned(),
            scene: scene.to_string_lossy().into_owned(),
            status: SceneStatus::Error,
            plan: None,
            strategy: None,
            seed: None,
            duration: None,
            time: None,
            reasons: Vec::new(),
            error: None,
            replanned: None,
            warnings: Vec::new(),
        }
    }

    /// The line as one line of JSON (no newline).
    pub fn to_json_line(&self) -> String {
        // Strings, numbers and enums only: serialising cannot fail.
        serde_json::to_string(self).unwrap_or_default()
    }

    /// This line with its status and message for a failure.
    pub(super) fn fail(&mut self, status: SceneStatus, message: String) {
        self.status = status;
        self.error = Some(message);
    }
}

/// Writes the summary lines, one JSON object per line in the order given, atomically.
///
/// # Errors
/// [`BatchError::Output`] when the file cannot be written.
pub fn write_summary(path: &Path, summaries: &[SceneSummary]) -> Result<(), BatchError> {
    let mut text = String::new();
    for s in summaries {
        text.push_str(&s.to_json_line());
        text.push('\n');
    }
    write_atomic(path, text.as_bytes()).map_err(|e| BatchError::Output {
        path: path.to_path_buf(),
        reason: format!("cannot write the summary: {}", error_message(&e)),
    })
}
