//! The error type of the geometry crate.

use std::path::PathBuf;

/// Errors of `pickplace-geometry`. Each names the file (or `<memory>`) and what is wrong.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A mesh is malformed.
    #[error("{}: {kind}", path.display())]
    Mesh {
        /// The mesh file, or `<memory>` for meshes built in code.
        path: PathBuf,
        /// What is wrong.
        kind: MeshErrorKind,
    },
    /// A parameter is outside its valid range.
    #[error("invalid parameter {name} = {}: {reason}", crate::io::fmt_real(*.value))]
    InvalidParameter {
        /// Parameter name.
        name: &'static str,
        /// The value given.
        value: f64,
        /// Why it is invalid.
        reason: &'static str,
    },
    /// A cluster database is unreadable or was built for other inputs.
    #[error("{}: {kind}", path.display())]
    Database {
        /// The database file.
        path: PathBuf,
        /// What is wrong.
        kind: DatabaseErrorKind,
    },
}

/// What is wrong with a mesh.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshErrorKind {
    /// The file extension is not one we read.
    #[error("unsupported mesh format {extension:?} (expected .stl, .obj, .ply or .dae)")]
    UnsupportedFormat {
        /// The extension found.
        extension: String,
    },
    /// The file does not follow its format.
    #[error("malformed {format} file: {detail}")]
    Malformed {
        /// "STL", "OBJ", "PLY" or "COLLADA".
        format: &'static str,
        /// What the parser reported.
        detail: String,
    },
    /// The file has no triangles.
    #[error("the mesh has no triangles")]
    Empty,
    /// A coordinate is NaN or infinite.
    #[error("vertex {vertex} has a non-finite coordinate")]
    NonFiniteCoordinate {
        /// Index of the vertex in the file.
        vertex: usize,
    },
    /// A face refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {index}, but the mesh has {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the triangle in the file.
        triangle: usize,
        /// The vertex index found.
        index: u64,
        /// Number of vertices in the file.
        vertex_count: usize,
    },
    /// Every triangle is degenerate (zero area).
    #[error("all {triangles} triangles are degenerate (zero area)")]
    ZeroArea {
        /// Number of triangles in the file.
        triangles: usize,
    },
    /// The scale factor is not a positive finite number.
    #[error("scale {} must be positive and finite", crate::io::fmt_real(*.scale))]
    InvalidScale {
        /// The scale given.
        scale: f64,
    },
    /// The file holds (or its header declares) more of something than a mesh may have
    /// ([`crate::mesh::MAX_MESH_TRIANGLES`], [`crate::mesh::MAX_MESH_VERTICES`]); refused
    /// before the memory for it is allocated.
    #[error("{count} {what}, over the limit of {limit}")]
    OverLimit {
        /// What was counted: "triangles", "vertices", "triangles declared in the header", ….
        what: &'static str,
        /// How many the file holds or declares.
        count: u64,
        /// The limit.
        limit: u64,
    },
    /// A per-axis scale has a zero or non-finite component (negative ones mirror).
    #[error(
        "scale [{}, {}, {}] has a zero or non-finite component",
        crate::io::fmt_real(.scale[0]),
        crate::io::fmt_real(.scale[1]),
        crate::io::fmt_real(.scale[2])
    )]
    InvalidScaleVector {
        /// The scale given, per axis.
        scale: [f64; 3],
    },
}

/// What is wrong with a cluster database.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DatabaseErrorKind {
    /// The file does not start with the database magic bytes.
    #[error("not a pickplace cluster database (bad magic)")]
    BadMagic,
    /// The database was written by another format version.
    #[error(
        "database format version {found}, this build reads version {expected}; rebuild it with `pickplace precompute`"
    )]
    Version {
        /// Version in the file.
        found: u32,
        /// Version this build reads.
        expected: u32,
    },
    /// The database was built for another mesh or other parameters.
    #[error(
        "database was built for {what} {found}, expected {expected}; rebuild it with `pickplace precompute`"
    )]
    Mismatch {
        /// What differs ("mesh hash", "h_max", "mode", ...).
        what: &'static str,
        /// Value in the file.
        found: String,
        /// Value expected.
        expected: String,
    },
    /// The payload could not be decoded.
    #[error("corrupt database: {detail}")]
    Corrupt {
        /// What the decoder reported.
        detail: String,
    },
}

impl From<pickplace_base::io::WriteError> for Error {
    fn from(e: pickplace_base::io::WriteError) -> Self {
        Error::Io {
            path: e.path,
            source: e.source,
        }
    }
}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;

pub(crate) fn memory_path() -> PathBuf {
    PathBuf::from("<memory>")
}
