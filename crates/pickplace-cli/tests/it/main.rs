//! End-to-end tests of the `pickplace` command on the shipped meshes.

mod bad_input;
mod batch;
mod cache;
mod clusters;
mod demo;
mod export;
mod hardening;
mod limits;
mod motion;
mod numbers;
mod placements;
mod plan;
mod precompute;
mod robot;
mod robots;
mod suite;
mod support;
mod trajectory;
mod view;

use std::path::PathBuf;
use std::process::{Command, Output};

/// The repository's root.
pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `pickplace ARGS…` from the repository's root.
pub fn pickplace(args: &[&str]) -> Output {
    let o = Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run pickplace");
    let os: Vec<&std::ffi::OsStr> = args.iter().map(std::ffi::OsStr::new).collect();
    support::validate_written_plan(&root(), None, &os, &o);
    o
}
