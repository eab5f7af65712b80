//! Hardening, round three (issue 33): every number a scene, a flag or a file gives is
//! range-checked with a message naming the field (and the file and line where there is one);
//! paths say what they are; numbers print compactly.

use crate::support::run_at_root as run;
use crate::support::{Scratch, stderr};
use crate::{args, root};
use std::path::PathBuf;
use std::process::Output;

/// `scenes/fig9-near.toml` with absolute paths, `replace` applied, `extra` appended.
fn near(dir: &Scratch, name: &str, replace: &[(&str, &str)], extra: &str) -> PathBuf {
    let mut text = std::fs::read_to_string(root().join("scenes/fig9-near.toml"))
        .expect("scene")
        .replace("\"../", &format!("\"{}/", root().display()));
    for (from, to) in replace {
        assert!(text.contains(from), "{from:?} not in the scene");
        text = text.replacen(from, to, 1);
    }
    dir.file(name, format!("{text}\n{extra}").as_bytes())
}

/// Exit status `code`, no panic, every needle on stderr.
fn exits_with(o: &Output, code: i32, needles: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(code), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for n in needles {
        assert!(err.contains(n), "{n:?} not in {err}");
    }
}

#[test]
fn a_time_budget_no_duration_holds_is_refused_naming_the_field() {
    // Was a panic: "cannot convert float seconds to Duration" (exit 101).
    let dir = Scratch::new("numbers-budget");
    let s = near(
        &dir,
        "huge.toml",
        &[("seed = 1", "seed = 1\ntime_budget = 1e300")],
        "",
    );
    exits_with(
        &run(args!["plan", s]),
        2,
        &["planner.time_budget: 1e300 is not in [0, 604800] s"],
    );
    let out = dir.join("plans");
    exits_with(
        &run(args!["batch", s, "--out", out, "--time-budget", "1e300"]),
        2,
        &["--time-budget", "1e300 is not in"],
    );
}

#[test]
fn a_denormal_time_budget_prints_compactly() {
    let dir = Scratch::new("numbers-denormal");
    let s = near(
        &dir,
        "tiny.toml",
        &[("seed = 1", "seed = 1\ntime_budget = 5e-320")],
        "",
    );
    let o = run(args!["plan", s]);
    exits_with(&o, 1, &["the time budget of 5e-320 s is spent"]);
    assert!(!stderr(&o).contains("0.0000000000"), "{}", stderr(&o));
}

/// A scene case: replacements in the shipped scene, text appended, the message's needle.
type SceneCase<'a> = (&'a [(&'a str, &'a str)], &'a str, &'a str);

#[test]
fn scene_numbers_out_of_range_name_their_field() {
    let dir = Scratch::new("numbers-scene");
    let cases: [SceneCase<'_>; 6] = [
        (
            &[("[0.42, -0.04, 0.72]", "[1e300, -0.04, 0.72]")],
            "",
            "object.start_pose.position: 1e300 is not in",
        ),
        (
            &[],
            "[trajectory]\nvelocity_scaling = 1e-9",
            "trajectory.velocity_scaling",
        ),
        (
            &[],
            "[trajectory]\nmax_acceleration = 1e300",
            "trajectory.max_acceleration",
        ),
        (
            &[("seed = 1", "seed = 1\nh_max_finger = 1e-300")],
            "",
            "planner.h_max_finger: 1e-300 is not in",
        ),
        (
            &[("mesh = \"", "scale = 1e300\nmesh = \"")],
            "",
            "object.scale: 1e300 is not in",
        ),
        (
            &[],
            "[collision_matrix]\nsamples = 0",
            "collision_matrix.samples: 0 is not in",
        ),
    ];
    for (i, (replace, extra, needle)) in cases.into_iter().enumerate() {
        let s = near(&dir, &format!("s{i}.toml"), replace, extra);
        exits_with(&run(args!["plan", s]), 2, &[needle]);
    }
}

#[test]
fn flags_out_of_range_are_usage_errors() {
    let can = root().join("meshes/can.stl");
    let robot = root().join("robots/nx-hiro");
    let urdf = root().join("robots/nx-hiro/nx-hiro.urdf");
    let cases: [(&[&std::ffi::OsStr], &str); 5] = [
        (
            args!["grasps", can, "--robot", robot, "--grid-step", "1e-300"],
            "--grid-step",
        ),
        (
            args!["grasps", can, "--robot", robot, "--approaches", "1e12"],
            "--approaches",
        ),
        (args!["clusters", can, "--scale", "1e300"], "--scale"),
        (args!["clusters", can, "--h-max", "1e-300"], "--h-max"),
        (
            args!["robot", "check", urdf, "--min-collision-fraction", "5"],
            "--min-collision-fraction",
        ),
    ];
    for (a, flag) in cases {
        exits_with(&run(a), 2, &[flag, "is not in"]);
    }
}

#[test]
fn a_velocity_limit_far_too_small_is_refused_naming_the_joint_and_the_urdf() {
    // Was a plan (exit 0) of 0.22 s that validate refused: the limit's square underflowed,
    // the timing gave its stages no time, and the robot jumped along its path.
    let dir = Scratch::new("numbers-velocity");
    let urdf = std::fs::read_to_string(root().join("robots/nx-hiro/nx-hiro.urdf"))
        .expect("urdf")
        .replace(
            "<limit lower=\"-2.75762\" upper=\"0\" velocity=\"3.7525\"",
            "<limit lower=\"-2.75762\" upper=\"0\" velocity=\"1e-300\"",
        );
    assert!(urdf.contains("1e-300"));
    let urdf = dir.file("slow.urdf", urdf.as_bytes());
    let s = near(
        &dir,
        "slow.toml",
        &[(
            &format!("\"{}/robots/nx-hiro/nx-hiro.urdf\"", root().display()),
            &format!("{:?}", urdf.display().to_string()),
        )],
        "",
    );
    exits_with(
        &run(args!["plan", s]),
        2,
        &[
            "slow.urdf",
            "joint \"RARM_JOINT2\"",
            "velocity limit 1e-300 is not in",
        ],
    );
}

#[test]
fn a_bad_gripper_override_names_its_file_and_line() {
    let dir = Scratch::new("numbers-gripper");
    let cases = [
        ("pad_width = -0.01", "line 2: pad_width", "not -0.01"),
        ("pad_width = nan", "line 2: pad_width", "not NaN"),
        ("opening_max = 0.0", "line 2: opening_max", "not 0"),
        (
            "finger_length = 0.0",
            "line 2: finger_length",
            "0 is not in",
        ),
        (
            "opening_min = 0.05\nopening_max = 0.01",
            "line 2: opening_min",
            "not below opening_max",
        ),
    ];
    for (i, (text, field, reason)) in cases.into_iter().enumerate() {
        let g = dir.file(
            &format!("g{i}.toml"),
            format!("# overrides\n{text}\n").as_bytes(),
        );
        let s = near(
            &dir,
            &format!("g{i}-scene.toml"),
            &[(
                &format!("\"{}/robots/nx-hiro/gripper.toml\"", root().display()),
                &format!("{:?}", g.display().to_string()),
            )],
            "",
        );
        let o = run(args!["plan", s]);
        exits_with(&o, 2, &[&format!("g{i}.toml: {field}"), reason]);
        assert!(!stderr(&o).contains("planner.right_arm"), "{}", stderr(&o));
    }
}

#[test]
fn a_urdf_mesh_that_is_a_link_to_a_device_says_so() {
    let dir = Scratch::new("numbers-device-mesh");
    std::os::unix::fs::symlink("/dev/zero", dir.join("zero.stl")).expect("symlink");
    std::os::unix::fs::symlink(dir.join("gone.stl"), dir.join("dangling.stl")).expect("link");
    let urdf = dir.file(
        "r.urdf",
        br#"<robot name="r">
  <link name="a"><collision><geometry><mesh filename="zero.stl"/></geometry></collision></link>
  <link name="b"><collision><geometry><mesh filename="dangling.stl"/></geometry></collision></link>
  <joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>
</robot>"#,
    );
    let o = run(args!["robot", "check", urdf]);
    let err = format!("{}{}", stderr(&o), crate::support::stdout(&o));
    assert!(err.contains("zero.stl is a character device"), "{err}");
    assert!(
        err.contains("dangling.stl is a symbolic link to a missing file"),
        "{err}"
    );
    assert!(!err.contains("install the mesh package"), "{err}");
}
