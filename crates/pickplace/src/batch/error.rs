//! What stops a whole batch ([`BatchError`]), and an error's message as `pickplace` prints it
//! ([`error_message`]).

use std::path::PathBuf;

/// Why a batch could not run (a scene's own failure is a [`SceneSummary`](super::SceneSummary)
/// instead).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum BatchError {
    /// Two scenes would write the same plan file.
    #[error(
        "{} and {}: both would be planned into {file}; scenes of one batch need distinct file names (rename one, or plan them into two folders)",
        first.display(),
        second.display()
    )]
    SameName {
        /// The first scene given.
        first: PathBuf,
        /// The later scene.
        second: PathBuf,
        /// The plan file's name.
        file: String,
    },
    /// A scene path has no file name to name its plan after.
    #[error("{}: not a scene file name", scene.display())]
    NoFileName {
        /// The path given.
        scene: PathBuf,
    },
    /// An option is out of range.
    #[error("batch option {option}: {reason}")]
    Option {
        /// The option ([`BatchOptions`](super::BatchOptions)'s field).
        option: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The output folder, or the summary's path in it, cannot be used.
    #[error("{}: {reason}", path.display())]
    Output {
        /// The folder or file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// A worker thread or its pool could not be started.
    #[error("cannot start the batch's threads: {reason}")]
    Threads {
        /// What the system said.
        reason: String,
    },
}
