//! The error type of the grasp crate.

use pickplace_geometry::math::Real;
use std::path::PathBuf;

/// Errors of `pickplace-grasp`. Each names the file (or `<memory>`) and what is wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A gripper configuration file could not be read.
    #[error("{}: cannot read the gripper configuration", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A gripper configuration is not valid TOML or does not have the expected fields.
    #[error("{}: invalid gripper configuration: {message}", path.display())]
    GripperSyntax {
        /// The file, or `<memory>`.
        path: PathBuf,
        /// What the TOML reader reported, with line and column, without quoting the file
        /// (`pickplace_geometry::io::parse_error`).
        message: String,
    },
    /// A gripper parameter is outside its valid range.
    #[error("{}: gripper parameter `{field}` {reason}", path.display())]
    InvalidGripper {
        /// The file, or `<memory>`.
        path: PathBuf,
        /// The parameter (TOML key).
        field: &'static str,
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A planning option is outside its valid range.
    #[error("invalid grasp option {name} = {value}: {reason}")]
    InvalidOption {
        /// Option name.
        name: &'static str,
        /// The value given.
        value: Real,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// A cluster pair refers to a cluster the clustering does not have.
    #[error(
        "cluster pair {pair} refers to cluster {cluster}, but the clustering has {count} clusters"
    )]
    MissingCluster {
        /// Index of the pair.
        pair: usize,
        /// The missing cluster id.
        cluster: u32,
        /// Number of clusters.
        count: usize,
    },
    /// A cluster names a triangle the planner's mesh does not have: the clustering was made on
    /// another mesh.
    #[error(
        "cluster {cluster} refers to triangle {triangle}, but the object mesh has {count} triangles"
    )]
    ForeignClustering {
        /// The cluster id.
        cluster: u32,
        /// The triangle index.
        triangle: u32,
        /// Number of triangles of the planner's mesh.
        count: usize,
    },
    /// A pair's overlap region is too large for the grid spacing.
    #[error(
        "grid_step = {grid_step} m is too fine for cluster pair {pair}: more than {limit} grid nodes"
    )]
    GridTooFine {
        /// Index of the pair.
        pair: usize,
        /// The grid spacing (m).
        grid_step: Real,
        /// The limit on grid nodes per pair.
        limit: u64,
    },
    /// The object mesh could not be turned into a collision mesh.
    #[error("the object mesh cannot be used for collision tests")]
    CollisionMesh {
        /// What parry reported.
        #[source]
        source: parry3d_f64::shape::TriMeshBuilderError,
    },
    /// An error of the geometry layer (mesh, clusters).
    #[error(transparent)]
    Geometry(#[from] pickplace_geometry::Error),
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
