//! The cluster database: clusters computed offline once per mesh and parameter set (§III-A:
//! "the information on each cluster is described in a parameter file ... read when executing
//! the online planner").
//!
//! A database is keyed by the mesh's content hash ([`crate::hash::mesh_hash`]: the welded
//! mesh's canonical bytes) and by every clustering parameter; loading one built for another
//! mesh, another format version or other parameters is an [`Error::Database`], never a silent
//! reuse. Files are written atomically (temporary file, then rename). The byte format is in
//! [`crate::codec`].

use crate::cluster::{ClusterParams, Clustering, ClustersJson, cluster_surface};
use crate::codec;
use crate::error::{Error, Result};
use crate::export::write_atomic;
use crate::hash::ContentHasher;
use crate::hash::mesh_hash;
use crate::mesh::TriMesh;
use std::path::{Path, PathBuf};

/// File extension of cluster databases.
pub const DATABASE_EXTENSION: &str = "ppdb";

/// Where the database of the mesh file `mesh_path` built with `params` lives in the cache
/// folder `dir`: `<dir>/<file stem>.<mode>.<parameter hash>.ppdb`, e.g.
/// `target/pickplace-cache/can.finger.1f0c…e2.ppdb`.
///
/// The name carries the mesh file's stem and a hash of every parameter, so each mesh and
/// parameter set gets its own file. The mesh's content is not in the name: it is checked
/// when the file is read ([`ClusterDatabase::load`]), so an edited mesh (or two meshes with
/// the same stem in different folders) makes [`ClusterDatabase::load_or_build`] rebuild the
/// file, never reuse it.
pub fn cache_path(dir: &Path, mesh_path: &Path, params: &ClusterParams) -> PathBuf {
    let stem = mesh_path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "mesh".to_owned());
    let mut h = ContentHasher::default();
    h.bytes(params.mode.name().as_bytes());
    h.word(params.h_max.to_bits());
    h.word(params.max_facet_angle.to_bits());
    h.word(params.opposite_dot.to_bits());
    dir.join(format!(
        "{stem}.{}.{:016x}.{DATABASE_EXTENSION}",
        params.mode.name(),
        h.finish()
    ))
}

/// Clusters of one mesh, with what they were built from.
#[derive(Debug, Clone, PartialEq)]
pub struct ClusterDatabase {
    /// [`mesh_hash`] of the mesh.
    pub mesh_hash: u64,
    /// Triangles of the welded mesh.
    pub triangle_count: usize,
    /// The clusters (and pairs in finger mode), with the parameters used.
    pub clustering: Clustering,
}

/// Whether [`ClusterDatabase::load_or_build`] read the file or rebuilt it.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CacheStatus {
    /// The file was valid for this mesh and these parameters.
    Loaded,
    /// The file was missing or unusable (the reason is kept) and was rebuilt and saved.
    Built {
        /// Why the file could not be used (`None` when it did not exist).
        reason: Option<String>,
    },
}

impl ClusterDatabase {
    /// Clusters `mesh` with `params`.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters.
    pub fn build(mesh: &TriMesh, params: &ClusterParams) -> Result<Self> {
        Ok(Self {
            mesh_hash: mesh_hash(mesh),
            triangle_count: mesh.triangle_count(),
            clustering: cluster_surface(mesh, params)?,
        })
    }

    /// The database as bytes (see [`crate::codec`]).
    pub fn to_bytes(&self) -> Vec<u8> {
        codec::encode(self)
    }

    /// Writes the database atomically.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be written.
    pub fn save(&self, path: &Path) -> Result<()> {
        write_atomic(path, &self.to_bytes())
    }

    /// Reads a database built for the mesh with hash `expected_hash` (see
    /// [`crate::hash::mesh_hash`]) and the parameters `params`.
    ///
    /// # Errors
    /// [`Error::Io`] when the file cannot be read, is not a regular file or is larger than
    /// [`crate::io::MAX_CACHE_ENTRY_BYTES`]; [`Error::Database`] when it is not a
    /// database, has another format version, was built for another mesh or other parameters,
    /// or is corrupt.
    pub fn load(path: &Path, expected_hash: u64, params: &ClusterParams) -> Result<Self> {
        let bytes =
            crate::io::read_bytes(path, crate::io::FileKind::CacheEntry).map_err(|source| {
                Error::Io {
                    path: path.to_path_buf(),
                    source,
                }
            })?;
        codec::decode(&bytes, expected_hash, params).map_err(|kind| Error::Database {
            path: path.to_path_buf(),
            kind,
        })
    }

    /// Loads the database at `path` if it was built for `mesh` and `params`; otherwise builds
    /// it and saves it there.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] for invalid parameters, [`Error::Io`] when the file exists
    /// but cannot be read, or cannot be written. A path that is not a regular file (a FIFO, a
    /// device) or a file over [`crate::io::MAX_CACHE_ENTRY_BYTES`] is a damaged entry: rebuilt.
    pub fn load_or_build(
        path: &Path,
        mesh: &TriMesh,
        params: &ClusterParams,
    ) -> Result<(Self, CacheStatus)> {
        params.validate()?;
        let reason = match Self::load(path, mesh_hash(mesh), params) {
            Ok(db) => return Ok((db, CacheStatus::Loaded)),
            Err(Error::Io { source, .. }) if source.kind() == std::io::ErrorKind::NotFound => None,
            Err(e @ Error::Database { .. }) => Some(e.to_string()),
            // Not a regular file, or too large: a damaged entry, rebuilt.
            Err(e) if matches!(&e, Error::Io { source, .. } if crate::io::is_refused(source)) => {
                Some(e.to_string())
            }
            Err(e) => return Err(e),
        };
        let db = Self::build(mesh, params)?;
        db.save(path)?;
        Ok((db, CacheStatus::Built { reason }))
    }

    /// The "clusters" JSON document (see [`ClustersJson`]); `mesh` must be the mesh the
    /// database was built for.
    pub fn to_json(&self, mesh: &TriMesh, mesh_path: &str) -> ClustersJson {
        ClustersJson::new(&self.clustering, mesh, mesh_path)
    }
}
