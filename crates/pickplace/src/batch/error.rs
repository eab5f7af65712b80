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

/// An error and its causes on one line, each cause once, as the `pickplace` command prints
/// it after `error: ` (the façade's errors already quote their source in their message, so a
/// cause whose text the previous message contains is skipped).
pub fn error_message(e: &(dyn std::error::Error + 'static)) -> String {
    let mut out = String::new();
    let mut previous = String::new();
    let mut cause = Some(e);
    while let Some(c) = cause {
        let text = c.to_string();
        if !previous.contains(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&text);
            previous = text;
        }
        cause = c.source();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_each_cause_once() {
        #[derive(Debug)]
        struct E(&'static str, Option<Box<E>>);
        impl std::fmt::Display for E {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str(self.0)
            }
        }
        impl std::error::Error for E {
            fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
                self.1.as_deref().map(|e| e as _)
            }
        }
        let e = E(
            "a.toml: bad: x",
            Some(Box::new(E("x", Some(Box::new(E("y", None)))))),
        );
        assert_eq!(error_message(&e), "a.toml: bad: x: y");
    }
}
