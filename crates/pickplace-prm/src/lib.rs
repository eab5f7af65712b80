//! Motion planning in joint space for pick-and-place (Harada et al., "Pick and Place Planning
//! for Dual-Arm Manipulators", §III-C: collision-free motions between key poses by a PRM).
//!
//! The crate knows nothing of meshes, URDF or robots: a [`JointSpace`] (bounds and distance
//! weights) and a [`ValidityChecker`] (a trait, implemented for closures) are all it sees.
//!
//! - [`Roadmap`]: seeded PRM construction, parallel with rayon and identical for any thread count;
//!   [`Roadmap::build_lazy`] builds one roadmap without obstacles for many environments.
//! - [`PrmPlanner`]: lazy PRM queries (A*, edges checked only when used, statuses cached), growth of
//!   the roadmap when start and goal are not joined, failures with their reason.
//! - [`rrt_connect`]: a single-query bidirectional RRT-Connect baseline.
//! - [`shortcut()`]: seeded random shortcutting that never lengthens a path.
//! - [`time_parameterize`]: synchronised trapezoidal profiles within per-joint velocity and
//!   acceleration limits, sampled as [`TrajectoryPoint`]s.
//! - [`codec`]: the versioned binary format of roadmaps.
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
pub(crate) mod rng;
pub mod roadmap;
pub mod rrt;
pub mod shortcut;
pub mod space;
pub mod timing;
pub mod validity;
pub use error::{Error, Result};
pub use path::Path;
pub use planner::{PrmPlanner, QueryOptions, QueryStats};
pub use roadmap::{Roadmap, RoadmapOptions, Validation};
pub use rrt::{RrtOptions, rrt_connect};
pub use shortcut::{ShortcutOptions, shortcut};
pub use space::JointSpace;
pub use timing::{TimingOptions, Trajectory, TrajectoryPoint, time_parameterize};
pub use validity::{AlwaysValid, ValidityChecker, motion_valid_by_interpolation};
