//! Hostile and careless use (issue 18): closed pipes, `--out` destinations that must not be
//! written, validate on plans edited by hand.

use crate::root;
use crate::support::stderr;
use std::path::Path;
use std::process::{Command, Output, Stdio};

/// `pickplace ARGS…` from the repository's root, with the cache of the plan tests.
fn command(args: &[&std::ffi::OsStr]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pickplace"));
    c.args(args).current_dir(root()).env(
        "PICKPLACE_CACHE",
        Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache"),
    );
    c
}

/// Runs `pickplace ARGS…` with standard output a pipe whose reading end is closed at once.
fn with_closed_stdout(args: &[&std::ffi::OsStr]) -> Output {
    let mut child = command(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the pickplace binary runs");
    drop(child.stdout.take());
    child.wait_with_output().expect("pickplace ends")
}

#[test]
fn a_closed_standard_output_ends_quietly() {
    let urdf = root().join("robots/nx-hiro/nx-hiro.urdf");
    let scene = root().join("scenes/fig9-near.toml");
    let cases: [&[&std::ffi::OsStr]; 7] = [
        crate::args!["plan", scene],
        crate::args!["robot", "check", urdf],
        crate::args!["robot", "check", urdf, "--json"],
        crate::args!["placements", "meshes/can.stl", "--on", "meshes/pallet.stl"],
        crate::args!["placements", "meshes/can.stl", "--json"],
        crate::args!["clusters", "meshes/can.stl"],
        crate::args!["mesh-info", "meshes/can.stl"],
    ];
    for args in cases {
        let o = with_closed_stdout(args);
        let err = stderr(&o);
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains("error:"), "{args:?}: {err}");
        assert_eq!(o.status.code(), Some(0), "{args:?}: {err}");
    }
}

#[test]
fn a_run_with_open_standard_output_still_prints_everything() {
    let o = command(crate::args![
        "robot",
        "check",
        root().join("robots/nx-hiro/nx-hiro.urdf")
    ])
    .output()
    .expect("runs");
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.starts_with("robot \"nx-hiro\""), "{out}");
    assert!(
        out.trim_end()
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("warnings: ")),
        "{out}"
    );
}
