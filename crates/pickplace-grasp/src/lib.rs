//! Parallel-gripper grasp planning: Harada et al., §III-B.1 ("Grasp Planner"), after their
//! ref. \[15\] (grasp planning for parallel grippers with a flexible sheet on the fingers).
//!
//! Input: the object mesh, its finger-contact clustering (§III-A.1: pairs of opposite parallel
//! clusters, `pickplace_geometry::cluster`) and the gripper as plain parameters
//! ([`GripperParams`], read from the robot's `gripper.toml`). Output: grasps as
//! `object_from_tcp` poses with their width and score, ranked, and counts of rejected
//! candidates per reason ([`GraspSet`]).
//!
//! This crate knows no kinematics and no robot beyond the gripper's shape.
//!
//! # Example
//! ```
//! use pickplace_geometry::cluster::{cluster_surface, ClusterParams};
//! use pickplace_geometry::shapes;
//! use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
//!
//! let gripper = GripperParams::from_toml_str(
//!     include_str!("../tests/data/gripper.toml"),
//!     std::path::Path::new("gripper.toml"),
//! )?;
//! // A drink can: radius 3.3 cm, height 12 cm, 64 facets around.
//! let can = shapes::cylinder(0.033, 0.12, 64);
//! let clustering = cluster_surface(&can, &ClusterParams::finger())?;
//! let set = GraspPlanner::new(&can)?.plan(&clustering, &gripper, &GraspOptions::default())?;
//! assert!(!set.grasps.is_empty());
//! assert!(set.grasps[0].width < gripper.opening_max);
//! # Ok::<(), pickplace_grasp::Error>(())
//! ```
//!
//! # Limitations
//! - The object is checked against the gripper at the grasp only, not along the approach
//!   motion, and not against the environment (the planner's key poses do that).
//! - Finger and palm shapes are boxes.
//! - The score is geometric (contact area, torque arm, boundary margin); friction and forces
//!   are not modelled.
#![warn(missing_docs)]

pub mod collide;
pub mod db;
pub mod error;
pub mod gripper;
pub mod json;
pub mod planner;
pub mod quality;

pub use error::{Error, Result};
pub use gripper::{GripperBox, GripperFile, GripperParams, PalmBox};
pub use planner::{Grasp, GraspOptions, GraspPlanner, GraspSet, RejectionCounts};
pub use quality::GraspQuality;
