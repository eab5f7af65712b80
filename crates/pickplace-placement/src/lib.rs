//! Stable placements of an object on an environment: the object pose planner of Harada et al.,
//! §III-B.2 (Algorithm 2, the stability test of Fig. 7), and resting poses on a plane.
//!
//! This crate knows no kinematics and no robot.
//!
//! # Example
//! Place the can on the pallet (the paper's Fig. 10), at the default target:
//! ```
//! use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
//! use pickplace_geometry::math::Isometry3;
//! use pickplace_geometry::mesh::{self, MassProperties, MeshOptions};
//! use pickplace_placement::{
//!     EnvironmentModel, ObjectModel, PlacementOptions, candidates, default_target,
//! };
//! use std::path::Path;
//!
//! let meshes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../meshes");
//! let can = mesh::load(&meshes.join("can.stl"), &MeshOptions::default())?;
//! let pallet = mesh::load(&meshes.join("pallet.stl"), &MeshOptions::default())?;
//! let params = ClusterParams::environment();
//! let cog = MassProperties::of(&can).center_of_mass;
//! let object = ObjectModel::new(&can, &cluster_surface(&can, &params)?, cog)?;
//! let env = EnvironmentModel::new(&pallet, &cluster_surface(&pallet, &params)?, &Isometry3::identity())?;
//! let options = PlacementOptions::default();
//! let target = default_target(&env, &options).expect("the pallet's top faces up");
//! let set = candidates(&object, &env, &target, &options).expect("the target is on the pallet");
//! assert!(!set.placements.is_empty());
//! assert!(set.placements[0].stability_margin >= options.min_margin);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![warn(missing_docs)]

pub mod candidates;
pub mod collide;
pub mod error;
pub mod json;
pub mod region;
pub mod rest;
pub mod resting;
#[cfg(feature = "physics")]
pub mod simulate;
pub mod stability;

pub use candidates::{
    ContactKind, DEFAULT_MIN_MARGIN, DEFAULT_MIN_TIPPING_ANGLE, EnvironmentModel, ObjectModel,
    Placement, PlacementOptions, PlacementSet, Rejections, TargetError, candidates, default_target,
    diversify, horizontal_distance, include_bounding_box, intermediate_placements, select_target,
};
pub use error::{Error, Result};
pub use region::Region;
pub use rest::{
    RestOptions, RestState, TargetSurface, TargetSurfaceError, rest_state, target_surface,
};
pub use resting::{RestingOptions, RestingPose, resting_poses};
