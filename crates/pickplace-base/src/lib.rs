//! The foundation below every pickplace crate: what all of them share and none of them owns.
//!
//! - [`math`]: the workspace's scalar and `nalgebra` aliases (`f64`, SI units), and the one
//!   line–triangle test.
//! - [`io`]: files read safely (regular files only, at most a limit per kind of file the
//!   reading crate declares), written atomically, temporaries of killed runs removed; names,
//!   paths and numbers of inputs checked and printed.
//! - [`rng`]: the workspace's one seeded generator ([`rng::Rng`], xoshiro256++ with derivable
//!   streams) and SplitMix64 ([`rng::SplitMix64`]), which seeds it and drives the seeded mesh
//!   builders.
//!
//! The crates above re-export these under their old paths (`pickplace_geometry::math`,
//! `pickplace_prm::rng`, `pickplace_robot::rng`), so a dependant needs no change; a crate that
//! needs only these (the robot crate's IK restarts and collision-matrix sampling) depends on
//! this crate instead of the planner's.

pub mod io;
pub mod math;
pub mod rng;
