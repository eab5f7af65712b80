//! pickplace: pick-and-place planning for dual-arm robots after Harada et al., "Pick and Place
//! Planning for Dual-Arm Manipulators". This crate is the façade and API boundary: it reads
//! scenes and re-exports the layers below.
#![warn(missing_docs)]

pub mod scene;

pub use pickplace_geometry as geometry;
pub use pickplace_placement as placement;
pub use scene::{Scene, SceneError};
