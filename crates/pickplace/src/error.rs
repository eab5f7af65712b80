//! Errors of the façade: bad input (exit status 2 in the CLI), never "no plan" (that is a
//! [`crate::planner::Outcome`]).

use crate::scene::SceneError;
use std::path::PathBuf;

/// Why a scene could not be set up or a plan could not be computed or checked.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// The scene file is unreadable or invalid.
    #[error(transparent)]
    Scene(#[from] Box<SceneError>),
    /// A mesh (object or environment) could not be read or clustered.
    #[error("{what}: {source}")]
    Mesh {
        /// Which mesh of the scene (`object.mesh`, `environment[1] "pallet"`).
        what: String,
        /// The cause (names the file).
        #[source]
        source: Box<pickplace_geometry::Error>,
    },
    /// The robot (URDF, SRDF) could not be read or is not what the planner needs.
    #[error("{}", robot_message(path, source))]
    Robot {
        /// The URDF or SRDF file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: Box<pickplace_robot::Error>,
    },
    /// The gripper file could not be read.
    #[error("{source}")]
    Gripper {
        /// The cause (names the file).
        #[source]
        source: Box<pickplace_grasp::Error>,
    },
    /// A value of the scene does not fit the robot or the meshes.
    #[error("{}: {field}: {reason}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// The field, as a TOML path.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// The target point is on no environment surface the object could rest on.
    #[error("{}: target.point: {source}", path.display())]
    Target {
        /// The scene file.
        path: PathBuf,
        /// Which cluster is nearest, and how far.
        #[source]
        source: Box<pickplace_placement::TargetError>,
    },
    /// A plan file is malformed or does not fit the scene's robot.
    #[error("{}: {reason}", path.display())]
    BadPlan {
        /// The plan file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
    /// No sampled state of an arm is free of self-collision: its roadmap would be empty.
    #[error(
        "the roadmap of {group} is empty: every sample collides; most rejected samples: {first} ~ {second} ({rejections})"
    )]
    EmptyRoadmap {
        /// The arm's SRDF group.
        group: String,
        /// First body of the pair that rejected most samples.
        first: String,
        /// Second body.
        second: String,
        /// How many sampled states it rejected.
        rejections: usize,
    },
    /// The start state collides: robot with itself, with the environment or with the object
    /// at its start pose. An infeasible scene (exit status 1 in the CLI), not bad input.
    #[error("start state in collision: {first} and {second} ({})", depth_words(*.distance))]
    StartInCollision {
        /// First body's name.
        first: String,
        /// Second body's name.
        second: String,
        /// Their signed distance (m): negative inside each other (the penetration depth),
        /// 0 touching.
        distance: f64,
    },
    /// The object is not resting where the scene says it starts: floating, penetrating the
    /// environment, or unable to stand there. An infeasible scene (exit status 1).
    #[error("object: not resting where the scene puts it: {state}")]
    ObjectNotResting {
        /// How it is (`floating 50.0 mm above the nearest support`, …).
        state: String,
    },
    /// The target is on no surface the object can stand on. An infeasible scene (exit
    /// status 1).
    #[error("target: {reason}")]
    TargetUnusable {
        /// Why (`the target is not on any surface: …`, too steep, too small).
        reason: String,
    },
    /// The timed trajectory would exceed a limit (a joint velocity limit so small that the
    /// motion would take millions of samples): bad input in the robot's files, exit status 2.
    #[error("trajectory: {reason}")]
    TrajectoryLimit {
        /// The time parameterization's message (the limit, the duration, the joint).
        reason: String,
    },
    /// A lower layer failed on input the façade had checked: a bug, reported with its cause.
    #[error("internal error in {stage}: {reason}")]
    Internal {
        /// The stage.
        stage: &'static str,
        /// The lower layer's message.
        reason: String,
    },
}

impl Error {
    /// True for a well-formed scene that has no solution (a start state in collision): the
    /// CLI's exit status 1 (the start state in collision, the object not resting, the target
    /// on no usable surface); every other error is bad input or a defect (exit status 2).
    pub fn is_infeasible(&self) -> bool {
        matches!(
            self,
            Self::StartInCollision { .. }
                | Self::ObjectNotResting { .. }
                | Self::TargetUnusable { .. }
        )
    }
}

/// `penetration 3.2 mm`, or `touching` within 0.05 mm.
fn depth_words(distance: f64) -> String {
    if distance < -5e-5 {
        format!("penetration {:.1} mm", -distance * 1e3)
    } else {
        "touching".to_owned()
    }
}

/// Result alias of the façade.
pub type Result<T, E = Error> = std::result::Result<T, E>;

pub(crate) fn internal<E: std::fmt::Display>(stage: &'static str) -> impl FnOnce(E) -> Error {
    move |e| Error::Internal {
        stage,
        reason: e.to_string(),
    }
}

impl From<SceneError> for Error {
    fn from(e: SceneError) -> Self {
        Error::Scene(Box::new(e))
    }
}

/// An error and its causes on one line, each cause once, as the `pickplace` command prints
/// it after `error: `, a batch's summary and Python's exceptions carry it (the façade's errors already quote their source in their message, so a
/// cause whose text the previous message contains is skipped).
pub fn message(e: &(dyn std::error::Error + 'static)) -> String {
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

/// `path: source`, or `source` alone when it starts with that file already.
fn robot_message(path: &std::path::Path, source: &pickplace_robot::Error) -> String {
    match source.file() {
        Some(file) if file == path => source.to_string(),
        _ => format!("{}: {source}", path.display()),
    }
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
        assert_eq!(message(&e), "a.toml: bad: x: y");
    }
}
