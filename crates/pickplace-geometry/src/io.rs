//! Reading input files safely ([`pickplace_base::io`], re-exported here under its old path),
//! and the kinds of file this crate reads: meshes and cache entries.

pub use pickplace_base::io::*;

/// Default limit of a mesh file (STL, OBJ, PLY, COLLADA): 1 GiB.
pub const MAX_MESH_BYTES: u64 = 1024 * MIB;
/// Default limit of a cache entry (cluster database, roadmap, grasp set): 1 GiB.
pub const MAX_CACHE_ENTRY_BYTES: u64 = 1024 * MIB;

/// A mesh file (STL, OBJ, PLY, COLLADA).
pub const MESH: FileKind = FileKind::new("a mesh", MAX_MESH_BYTES);
/// A cache entry (cluster database, roadmap, grasp set).
pub const CACHE_ENTRY: FileKind = FileKind::new("a cache entry", MAX_CACHE_ENTRY_BYTES);
