//! pickplace: pick-and-place planning for dual-arm robots after Harada et al., "Pick and Place
//! Planning for Dual-Arm Manipulators". This crate is the façade and API boundary: it reads
//! scenes, runs the online pipeline of the paper's Fig. 8 and re-exports the layers below.
//!
//! # Quick start
//! Load a scene (robot, object, environment and the target point; `docs/scene-format.md`),
//! plan, and re-check the plan independently:
//! ```
//! use pickplace::planner::Outcome;
//! use pickplace::{PlanOptions, Setup, SetupOptions};
//! use std::path::Path;
//!
//! let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! // Cluster databases and arm roadmaps are cached; the first setup builds them.
//! let options = SetupOptions {
//!     cache_dir: Some(root.join("target/pickplace-cache")),
//!     ..SetupOptions::default()
//! };
//! let setup = Setup::load(&root.join("scenes/fig9-near.toml"), &options)?;
//! let plan = match pickplace::plan(&setup, &PlanOptions::for_setup(&setup))? {
//!     Outcome::Planned(plan) => plan,
//!     Outcome::NoPlan(failure) => panic!("no plan: {:?}", failure.reasons),
//! };
//! println!("{} in {:.1} s of motion", plan.strategy, plan.stats.duration);
//! let report = pickplace::validate::validate(&setup, &plan, Path::new("plan.json"))?;
//! assert!(report.problems.is_empty());
//! std::fs::write(std::env::temp_dir().join("plan.json"), plan.to_json())?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//! A scene that cannot be planned is not an error: [`Outcome::NoPlan`] carries the reasons
//! per strategy and stage ([`planner::Stage`], [`planner::Rejection`]). Errors ([`Error`]) are
//! bad input (naming the file and what is wrong) or a defect of a lower layer.
//!
//! # Layers
//! Each stage is a crate of its own, usable alone and re-exported here: [`geometry`] (meshes,
//! surface clustering, §III-A), [`placement`] (stable placements, §III-B.2), [`grasp`]
//! (parallel-gripper grasps, §III-B.1), [`robot`] (URDF/SRDF, kinematics, collision) and
//! [`prm`] (motion planning, §III-C). `docs/ARCHITECTURE.md` maps every section of the paper
//! to its function.
#![warn(missing_docs)]

pub mod batch;
pub mod contact;
pub mod error;
pub mod motion;
pub mod plan;
pub mod planner;
pub mod ranges;
pub mod rules;
pub mod scene;
pub mod self_check;
pub mod setup;
pub mod strategy;
pub mod validate;

// The modules of the stages, under the paths they had before the façade was arranged by
// stage (issue 34).
pub use plan::export;
pub(crate) use planner::{start, timing};
pub use setup::{
    cache, checker, joint_limits, mesh_warning, obstacle, precompute, reach, roadmaps, robot_setup,
    tool_frame,
};
pub(crate) use setup::{collision_matrix, hand_fit};

#[cfg(test)]
mod testing;

pub use error::{Error, Result};
pub use pickplace_geometry as geometry;
pub use pickplace_grasp as grasp;
pub use pickplace_placement as placement;
pub use pickplace_prm as prm;
pub use pickplace_robot as robot;
pub use plan::{PLAN_FORMAT, Plan};
pub use planner::{Outcome, PlanOptions};
pub use robot_setup::RobotSetup;
pub use scene::{Scene, SceneError};
pub use self_check::plan;
pub use setup::{ProgressFn, Setup, SetupOptions, SetupProgress};
pub use start::check_start;
pub use strategy::{Arm, Strategy, StrategyChoice};
