//! The seeded generator of IK restarts and collision-matrix sampling: the workspace's one
//! generator, [`pickplace_base::rng::Rng`] (xoshiro256++ seeded through SplitMix64), re-exported
//! so that `pickplace_robot::rng::Rng` keeps working.

pub use pickplace_base::rng::Rng;
