//! pickplace: pick-and-place planning for dual-arm robots after Harada et al., "Pick and Place
//! Planning for Dual-Arm Manipulators". This crate is the façade and API boundary: it reads
//! scenes, runs the online pipeline of the paper's Fig. 8 and re-exports the layers below.
#![warn(missing_docs)]

pub mod checker;
pub mod error;
pub mod plan;
pub mod planner;
pub mod precompute;
pub mod roadmaps;
pub mod scene;
pub mod setup;
pub mod strategy;
pub mod validate;

pub use error::{Error, Result};
pub use pickplace_geometry as geometry;
pub use pickplace_grasp as grasp;
pub use pickplace_placement as placement;
pub use pickplace_prm as prm;
pub use pickplace_robot as robot;
pub use plan::{PLAN_FORMAT, Plan};
pub use planner::{Outcome, PlanOptions, plan};
pub use scene::{Scene, SceneError};
pub use setup::{Setup, SetupOptions};
pub use strategy::{Arm, Strategy};
