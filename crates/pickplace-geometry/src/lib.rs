//! Geometry for pick-and-place planning: meshes, surface clustering (Harada et al., §III-A,
//! Algorithm 1), cluster geometry and the cluster database.
//!
//! This crate knows no robot and no planner.
#![warn(missing_docs)]

pub mod cluster;
pub mod codec;
pub mod db;
pub mod error;
pub mod export;
pub mod hash;
pub mod json;
pub mod math;
pub mod mesh;
pub mod parry;
pub mod polygon;
pub mod shapes;

pub use error::{Error, Result};
