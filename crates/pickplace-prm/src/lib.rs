//! PRM placeholder during bring-up.
#![warn(missing_docs)]
pub mod error;
pub(crate) mod nn;
pub(crate) mod rng;
pub mod space;
pub mod validity;
