//! End-to-end tests of the `pickplace` binary.

mod bad_input;
mod clusters;
mod precompute;
mod support;
