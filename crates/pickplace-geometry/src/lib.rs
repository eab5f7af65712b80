//! Geometry for pick-and-place planning: meshes, surface clustering (Harada et al., §III-A,
//! Algorithm 1), cluster geometry and the cluster database.
//!
//! This crate knows no robot and no planner.
//!
//! # Example
//! Load the pallet of the paper's Fig. 9 and find its planar contact regions:
//! ```
//! use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
//! use pickplace_geometry::mesh::{self, MeshOptions};
//! use std::path::Path;
//!
//! let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes/pallet.stl");
//! let pallet = mesh::load(&file, &MeshOptions::default())?;
//! let clustering = cluster_surface(&pallet, &ClusterParams::environment())?;
//! // The largest region facing up is the pallet's top, 4 cm above its base.
//! let top = clustering
//!     .clusters
//!     .iter()
//!     .filter(|c| c.normal.z > 0.99)
//!     .max_by(|a, b| a.area.total_cmp(&b.area))
//!     .expect("a region faces up");
//! assert!((top.point.z - 0.04).abs() < 1e-6, "{}", top.point.z);
//! # Ok::<(), pickplace_geometry::Error>(())
//! ```
#![warn(missing_docs)]

pub mod cluster;
pub mod codec;
pub mod db;
pub mod error;
pub mod exact;
pub mod export;
pub mod hash;
pub mod io;
pub mod json;
pub use pickplace_base::math;
pub mod mesh;
pub mod obb;
pub mod parry;
pub mod polygon;
pub mod shapes;
/// Temporaries of atomic writes ([`pickplace_base::io::temp`]), under their old path.
pub use pickplace_base::io::temp;

pub use error::{Error, Result};
