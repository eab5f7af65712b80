//! PRM placeholder during bring-up.
#![warn(missing_docs)]
pub mod error;
pub(crate) mod nn;
pub mod path;
pub mod planner;
pub(crate) mod rng;
pub mod roadmap;
pub mod space;
pub mod validity;
pub use error::{Error, Result};
pub use path::Path;
pub use planner::{PrmPlanner, QueryOptions, QueryStats};
pub use roadmap::{Roadmap, RoadmapOptions, Validation};
pub use space::JointSpace;
pub use validity::{AlwaysValid, ValidityChecker, motion_valid_by_interpolation};
