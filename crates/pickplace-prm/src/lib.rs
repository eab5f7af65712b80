//! Motion planning in joint space for pick-and-place (Harada et al., "Pick and Place Planning
//! for Dual-Arm Manipulators", §III-C: collision-free motions between key poses by a PRM).
//!
//! The crate knows nothing of meshes, URDF or robots: a [`JointSpace`] (bounds and distance
//! weights) and a [`ValidityChecker`] (a trait, implemented for closures) are all it sees.
//!
//! - [`Roadmap`]: seeded PRM construction, parallel with rayon and identical for any thread count;
//!   [`Roadmap::build_lazy`] builds one roadmap without obstacles for many environments.
//! - [`PrmPlanner`]: lazy PRM queries (shortest paths by LPA*, nodes and edges checked only when a
//!   candidate path uses them, statuses cached), growth of the roadmap when start and goal are not
//!   joined, failures with their reason.
//! - [`rrt_connect`]: a single-query bidirectional RRT-Connect baseline.
//! - [`shortcut()`]: seeded random shortcutting that never lengthens a path.
//! - [`time_parameterize`]: synchronised trapezoidal profiles within per-joint velocity and
//!   acceleration limits, sampled as [`TrajectoryPoint`]s.
//! - [`codec`]: the versioned binary format of roadmaps.
//!
//! # Example
//! ```
//! use pickplace_prm::{
//!     JointSpace, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, ShortcutOptions,
//!     TimingOptions, shortcut, time_parameterize,
//! };
//!
//! // Two joints in [0, 1] with a wall at q0 = 0.5 open above q1 = 0.8.
//! let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2])?;
//! let free = |q: &[f64]| !((0.45..0.55).contains(&q[0]) && q[1] < 0.8);
//! // One roadmap without obstacles, for every environment.
//! let options = RoadmapOptions { node_count: 300, resolution: 0.01, ..RoadmapOptions::default() };
//! let roadmap = Roadmap::build_lazy(&space, &options)?;
//! let mut planner = PrmPlanner::new(&roadmap, &free, QueryOptions::default());
//! let path = planner.query(&[0.1, 0.1], &[0.9, 0.1])?;
//! let path = shortcut(&space, &free, &path, &ShortcutOptions { resolution: 0.01, ..ShortcutOptions::default() })?;
//! assert!(path.waypoints().any(|q| q[1] >= 0.8));
//! let limits = TimingOptions {
//!     max_velocities: vec![1.0, 1.0],
//!     max_accelerations: vec![2.0, 2.0],
//!     sample_period: 0.01,
//! };
//! let trajectory = time_parameterize(&path, &limits)?;
//! assert!(trajectory.duration() > 0.0);
//! # Ok::<(), pickplace_prm::Error>(())
//! ```
//!
//! # What a returned path guarantees
//! Every waypoint of a path returned by [`rrt_connect`], [`PrmPlanner::query`] or [`shortcut()`]
//! was accepted by the checker's [`ValidityChecker::is_state_valid`], every straight segment
//! between consecutive waypoints by its [`ValidityChecker::is_motion_valid`] at the options'
//! `resolution`. The default motion test ([`motion_valid_by_interpolation`]) checks states at
//! most `resolution` apart both in the weighted distance and in every joint (max-norm); the
//! default `resolution` of every options struct is [`DEFAULT_MAX_JOINT_STEP`] (1°), the
//! validator's joint step (`pickplace::validate::MAX_JOINT_STEP`). Nothing is claimed between
//! checked states: a caller choosing a coarser resolution (faster) should give its checker a
//! margin of half the resolution, and Cartesian spacing (the validator's 1 cm) is the checker's
//! concern.
//!
//! # Limitations
//! - Local paths are straight lines in joint space, checked by sampling at a resolution (a
//!   checker may override [`ValidityChecker::is_motion_valid`] with a continuous test).
//! - At most 16 joints (the k-d tree's dimension is instantiated at compile time).
//! - Timed trajectories stop at every waypoint (no blending).
#![warn(missing_docs)]
pub mod codec;
pub mod error;
pub(crate) mod lpa;
pub(crate) mod nn;
pub mod path;
pub mod planner;
pub mod rng;
pub mod roadmap;
pub mod rrt;
pub mod shortcut;
pub mod space;
pub mod timing;
pub mod toppra;
pub mod validity;
pub use error::{Error, Result};
pub use nn::MAX_DIMENSION;
pub use path::Path;
pub use planner::{PrmPlanner, QueryOptions, QueryStats};
pub use roadmap::{ALGORITHM_VERSION, Roadmap, RoadmapOptions, Validation};
pub use rrt::{RrtOptions, rrt_connect};
pub use shortcut::{ShortcutOptions, shortcut};
pub use space::JointSpace;
pub use timing::{
    MAX_TRAJECTORY_SAMPLES, TimingOptions, Trajectory, TrajectoryPoint, time_parameterize,
};
pub use validity::{
    AlwaysValid, DEFAULT_MAX_JOINT_STEP, ValidityChecker, motion_valid_by_interpolation,
};
