//! Hostile and careless use (issue 18): closed pipes, `--out` destinations that must not be
//! written, validate on plans edited by hand.

use crate::root;
use crate::support::{Scratch, stderr};
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

/// A real plan of `fig9-near` (planned once per test run into `dir`), as JSON.
fn near_plan(dir: &Scratch) -> serde_json::Value {
    let out = dir.join("near.json");
    let o = command(crate::args![
        "plan",
        root().join("scenes/fig9-near.toml"),
        "--out",
        out,
        "--no-timings"
    ])
    .output()
    .expect("runs");
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    serde_json::from_slice(&std::fs::read(&out).expect("plan written")).expect("plan JSON")
}

/// Validates `plan` (written into `dir` as `name`) against `fig9-near`.
fn validate(dir: &Scratch, name: &str, plan: &serde_json::Value) -> Output {
    let path = dir.file(name, plan.to_string().as_bytes());
    command(crate::args![
        "validate",
        root().join("scenes/fig9-near.toml"),
        path
    ])
    .output()
    .expect("runs")
}

#[test]
fn validate_checks_values_times_and_poses_before_interpolating() {
    let dir = Scratch::new("hardening-validate");
    let plan = near_plan(&dir);
    // A joint value far outside its limits: reported at once (it used to hang).
    for value in [1e4, 1e300, -1e12] {
        let mut far = plan.clone();
        far["trajectory"][10]["positions"][3] = serde_json::json!(value);
        let started = std::time::Instant::now();
        let o = validate(&dir, "far.json", &far);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert!(
            err.contains("LARM_JOINT0 = ")
                && err.contains("is outside its limits [-1.5359, 1.5359] (trajectory[10]"),
            "{err}"
        );
        assert!(err.contains("checked 0 states"), "{err}");
        assert!(!err.contains("0000000000"), "a long number: {err}");
        assert!(started.elapsed().as_secs() < 30, "{:?}", started.elapsed());
    }
    // A negative time, a zero or non-finite quaternion in a key pose: the plan is malformed.
    let mut negative = plan.clone();
    negative["trajectory"][0]["time_from_start"] = serde_json::json!(-1.0);
    let mut zero = plan.clone();
    zero["key_poses"][2]["world_from_tcp"]["orientation"] = serde_json::json!([0, 0, 0, 0]);
    let mut huge = plan.clone();
    huge["key_poses"][0]["world_from_object"]["orientation"] =
        serde_json::json!([1e308, 1e308, 1e308, 1e308]);
    let mut backwards = plan.clone();
    backwards["trajectory"][5]["time_from_start"] =
        plan["trajectory"][3]["time_from_start"].clone();
    for (name, faulty, expected) in [
        (
            "negative.json",
            &negative,
            "trajectory[0]: time_from_start -1 s is negative",
        ),
        (
            "zero.json",
            &zero,
            "key_poses[2].world_from_tcp: orientation quaternion is zero",
        ),
        (
            "backwards.json",
            &backwards,
            "trajectory[5] goes back in time",
        ),
    ] {
        let o = validate(&dir, name, faulty);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        let last = err.trim_end().lines().last().unwrap_or_default();
        assert!(last.starts_with("error: "), "{err}");
        assert!(last.contains(name) && last.contains(expected), "{err}");
    }
    // Huge but finite components are a valid (normalised) quaternion.
    let o = validate(&dir, "huge.json", &huge);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}
