//! Stable placements of an object on an environment: the object pose planner of Harada et al.,
//! §III-B.2 (Algorithm 2, the stability test of Fig. 7), and resting poses on a plane.
//!
//! This crate knows no kinematics and no robot.
#![warn(missing_docs)]

pub mod collide;
pub mod error;
pub mod resting;

pub use error::{Error, Result};
pub use resting::{RestingOptions, RestingPose, resting_poses};
