//! pickplace: pick-and-place planning for dual-arm robots after Harada et al., "Pick and Place
//! Planning for Dual-Arm Manipulators". This crate is the façade and API boundary: it reads
//! scenes, runs the online pipeline of the paper's Fig. 8 and re-exports the layers below.
#![warn(missing_docs)]

pub mod plan;
pub mod scene;
pub mod strategy;

pub use pickplace_geometry as geometry;
pub use pickplace_placement as placement;
pub use plan::{PLAN_FORMAT, Plan};
pub use scene::{Scene, SceneError};
pub use strategy::{Arm, Strategy};
