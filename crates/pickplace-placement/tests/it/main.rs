//! Integration tests of pickplace-placement.
//!
//! The drop tests need the crate's `physics` feature (`cargo test --workspace` enables it
//! through xtask's dependency; alone: `cargo test -p pickplace-placement --features physics`).

#[cfg(not(feature = "physics"))]
compile_error!(
    "the integration tests need the `physics` feature: \
     cargo test -p pickplace-placement --features physics (cargo test --workspace enables it)"
);

mod candidates;
mod rest;
mod resting;
mod simulate;
mod suite;
