//! Stable placements of an object on an environment: the object pose planner of Harada et al.,
//! §III-B.2 (Algorithm 2, the stability test of Fig. 7), and resting poses on a plane.
//!
//! This crate knows no kinematics and no robot.
#![warn(missing_docs)]

pub mod candidates;
pub mod collide;
pub mod error;
pub mod json;
pub mod region;
pub mod resting;
pub mod stability;

pub use candidates::{
    ContactKind, EnvironmentModel, ObjectModel, Placement, PlacementOptions, PlacementSet,
    Rejections, TargetError, candidates, default_target, include_bounding_box, select_target,
};
pub use error::{Error, Result};
pub use region::Region;
pub use resting::{RestingOptions, RestingPose, resting_poses};
