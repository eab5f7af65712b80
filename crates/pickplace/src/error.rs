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
    #[error("{}: {source}", path.display())]
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
    /// A cached file (cluster database, roadmap) could not be written.
    #[error("{}: cannot write the cache: {source}", path.display())]
    Cache {
        /// The file.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A plan file is malformed or does not fit the scene's robot.
    #[error("{}: {reason}", path.display())]
    BadPlan {
        /// The plan file.
        path: PathBuf,
        /// What is wrong.
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
