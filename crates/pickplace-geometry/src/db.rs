//! The cluster database: clusters computed offline once per mesh and parameter set (§III-A:
//! "the information on each cluster is described in a parameter file ... read when executing
//! the online planner").
//!
//! A database is keyed by the mesh's content hash ([`crate::hash::mesh_hash`]: the welded
//! mesh's canonical bytes), by every clustering parameter and by the clustering algorithm's
//! version ([`crate::cluster::ALGORITHM_VERSION`]); loading one built for another mesh,
//! another format or algorithm version or other parameters is an [`Error::Database`], never
//! a silent reuse. Files are written atomically (temporary file, then rename). The byte format is in
//! [`crate::codec`].

use crate::cluster::{
    ALGORITHM_VERSION, ClusterParams, Clustering, ClustersJson, cluster_surface_with_progress,
};
use crate::codec;
use crate::error::{Error, Result};
use crate::hash::ContentHasher;
use crate::hash::mesh_hash;
use crate::mesh::TriMesh;
use pickplace_base::io::write_atomic;
use std::path::{Path, PathBuf};

/// File extension of cluster databases.
pub const DATABASE_EXTENSION: &str = "ppdb";

/// Where the database of the mesh file `mesh_path` built with `params` lives in the cache
/// folder `dir`: `<dir>/<file stem>.<mode>.<key>.ppdb`, e.g.
/// `~/.cache/pickplace/can.finger.1f0c…e2.ppdb`.
///
/// The name carries the mesh file's stem and a hash of every parameter and of the clustering
/// algorithm's version ([`ALGORITHM_VERSION`]), so each mesh, parameter set and algorithm
/// gets its own file: a newer build never even opens an older algorithm's database. The mesh's content is not in the name: it is checked
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
    h.word(u64::from(ALGORITHM_VERSION));
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
        Self::build_with_progress(mesh, params, &|_, _| {})
    }

    /// [`ClusterDatabase::build`], telling `progress(done, total)` how far the clustering got
    /// (see [`crate::cluster::cluster_surface_with_progress`]).
    ///
    /// # Errors
    /// As [`ClusterDatabase::build`].
    pub fn build_with_progress(
        mesh: &TriMesh,
        params: &ClusterParams,
        progress: &dyn Fn(usize, usize),
    ) -> Result<Self> {
        Ok(Self {
            mesh_hash: mesh_hash(mesh),
            triangle_count: mesh.triangle_count(),
            clustering: cluster_surface_with_progress(mesh, params, progress)?,
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
        Ok(write_atomic(path, &self.to_bytes())?)
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
            crate::io::read_bytes(path, crate::io::CACHE_ENTRY).map_err(|source| Error::Io {
                path: path.to_path_buf(),
                source,
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
            Err(e) => Self::rebuild_reason(e)?,
        };
        let db = Self::build(mesh, params)?;
        db.save(path)?;
        Ok((db, CacheStatus::Built { reason }))
    }

    /// Why a cached database that [`ClusterDatabase::load`] refused is rebuilt, or the error
    /// that stops [`ClusterDatabase::load_or_build`]: `Ok(None)` for a missing file,
    /// `Ok(Some(reason))` for a damaged entry (another mesh, parameters, format or algorithm
    /// version, corrupt bytes, not a regular file, too large), rebuilt over.
    ///
    /// # Errors
    /// `error` itself when the file exists and cannot be read (permission denied, an I/O
    /// error): a cache that is not a requirement reports it and builds in memory.
    pub fn rebuild_reason(error: Error) -> Result<Option<String>> {
        match error {
            Error::Io { source, .. } if source.kind() == std::io::ErrorKind::NotFound => Ok(None),
            e @ Error::Database { .. } => Ok(Some(e.to_string())),
            // Not a regular file, or too large: a damaged entry, rebuilt.
            e if matches!(&e, Error::Io { source, .. } if crate::io::is_refused(source)) => {
                Ok(Some(e.to_string()))
            }
            e => Err(e),
        }
    }

    /// The "clusters" JSON document (see [`ClustersJson`]); `mesh` must be the mesh the
    /// database was built for.
    pub fn to_json(&self, mesh: &TriMesh, mesh_path: &str) -> ClustersJson {
        ClustersJson::new(&self.clustering, mesh, mesh_path)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::box_mesh;

    #[test]
    fn a_cached_database_equals_a_freshly_built_one() {
        let dir = std::env::temp_dir().join(format!("pickplace-db-fresh-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("cache folder");
        let mesh = box_mesh([0.05, 0.03, 0.02]);
        let params = ClusterParams::finger();
        let path = cache_path(&dir, Path::new("box.stl"), &params);
        let (first, status) = ClusterDatabase::load_or_build(&path, &mesh, &params).expect("built");
        assert_eq!(status, CacheStatus::Built { reason: None });
        let (second, status) =
            ClusterDatabase::load_or_build(&path, &mesh, &params).expect("loaded");
        assert_eq!(status, CacheStatus::Loaded);
        let fresh = ClusterDatabase::build(&mesh, &params).expect("fresh");
        assert_eq!(second, fresh);
        assert_eq!(first, fresh);
        std::fs::remove_dir_all(&dir).expect("cleanup");
    }

    #[test]
    fn progress_reaches_its_total_once_and_never_goes_back() {
        let mesh = box_mesh([0.05, 0.03, 0.02]);
        for params in [ClusterParams::environment(), ClusterParams::finger()] {
            let calls = std::cell::RefCell::new(Vec::new());
            let with = ClusterDatabase::build_with_progress(&mesh, &params, &|done, total| {
                calls.borrow_mut().push((done, total));
            })
            .expect("clusters");
            let calls = calls.into_inner();
            let total = crate::cluster::PROGRESS_TOTAL;
            assert_eq!(calls.first(), Some(&(0, total)), "{calls:?}");
            assert_eq!(calls.last(), Some(&(total, total)), "{calls:?}");
            assert_eq!(
                calls.iter().filter(|c| c.0 == total).count(),
                1,
                "{calls:?}"
            );
            assert!(calls.windows(2).all(|w| w[0].0 <= w[1].0), "{calls:?}");
            assert!(calls.len() <= 102, "{calls:?}");
            // Reporting does not change the clusters.
            assert_eq!(with, ClusterDatabase::build(&mesh, &params).expect("again"));
        }
    }

    #[test]
    fn rebuild_reasons_missing_damaged_and_unreadable() {
        let missing = Error::Io {
            path: "x".into(),
            source: std::io::Error::from(std::io::ErrorKind::NotFound),
        };
        assert_eq!(
            ClusterDatabase::rebuild_reason(missing).expect("missing"),
            None
        );
        let denied = Error::Io {
            path: "x".into(),
            source: std::io::Error::from(std::io::ErrorKind::PermissionDenied),
        };
        assert!(ClusterDatabase::rebuild_reason(denied).is_err());
    }
}
