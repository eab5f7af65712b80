//! Trajectory limits from the command line, the scene and a MoveIt-shaped `joint_limits.yaml`
//! (issue 19): a slower limit makes a slower plan that still validates against the limits it
//! was timed with; bad tables and factors exit 2 naming the file, the line or the option.

use crate::support::run_at_root as run;
use crate::support::{Scratch, ok};
use crate::{args, root};
use std::path::{Path, PathBuf};
use std::process::Output;

/// fig9-near written into `dir` with `extra` appended and `robot_line` added to `[robot]`.
fn scene(dir: &Scratch, robot_line: &str, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("scene");
    let base = root().join("scenes");
    // Paths of the shipped scene are relative to scenes/: make them absolute.
    let text = text.replace("\"../", &format!("\"{}/../", base.display()));
    let text = text.replacen("[robot]\n", &format!("[robot]\n{robot_line}\n"), 1);
    dir.file("scene.toml", format!("{text}\n{extra}\n").as_bytes())
}

fn duration(plan: &Path) -> f64 {
    let plan =
        pickplace::Plan::from_json(&std::fs::read_to_string(plan).expect("plan")).expect("reads");
    plan.trajectory.last().expect("samples").time_from_start
}

#[test]
fn a_joint_limits_file_and_scaling_slow_the_plan_and_it_still_validates() {
    let dir = Scratch::new("trajectory-limits");
    let plain = scene(&dir, "", "");
    let fast = dir.join("fast.json");
    ok(&run(args!["plan", &plain, "--no-timings", "--out", &fast]));
    // Every right-arm joint at 1 rad/s²: the same paths take longer.
    let mut yaml =
        String::from("# MoveIt shape\ndefault_acceleration_scaling_factor: 0.5\njoint_limits:\n");
    for j in 0..6 {
        yaml.push_str(&format!(
            "  RARM_JOINT{j}:\n    has_acceleration_limits: true\n    max_acceleration: 2.0\n"
        ));
    }
    dir.file("limits.yaml", yaml.as_bytes());
    let limited = scene(&dir, "joint_limits = \"limits.yaml\"", "");
    let slow = dir.join("slow.json");
    ok(&run(args![
        "plan",
        &limited,
        "--no-timings",
        "--out",
        &slow
    ]));
    let (t_fast, t_slow) = (duration(&fast), duration(&slow));
    assert!(t_slow > 1.2 * t_fast, "{t_fast} s, then {t_slow} s");
    let plan =
        pickplace::Plan::from_json(&std::fs::read_to_string(&slow).expect("plan")).expect("reads");
    let limits = plan.limits.expect("format 2 has limits");
    assert_eq!(limits.acceleration_scaling, 0.5);
    let j = plan
        .joint_names
        .iter()
        .position(|n| n == "RARM_JOINT0")
        .expect("joint");
    assert_eq!(limits.accelerations[j], 1.0);
    ok(&run(args!["validate", &limited, &slow]));
    // The command line wins over the file's default factor.
    let scaled = dir.join("scaled.json");
    ok(&run(args![
        "plan",
        &limited,
        "--no-timings",
        "--acceleration-scaling",
        "1",
        "--out",
        &scaled
    ]));
    assert!(duration(&scaled) < t_slow);
    // Same input, same bytes.
    let again = dir.join("again.json");
    ok(&run(args![
        "plan",
        &limited,
        "--no-timings",
        "--out",
        &again
    ]));
    assert_eq!(
        std::fs::read(&slow).expect("a"),
        std::fs::read(&again).expect("b")
    );
}

/// Exit status 2, every word of `expected` in the error, no panic (the setup's first line
/// may come before the error).
fn fails_with(o: &Output, expected: &[&str]) {
    let err = crate::support::stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("error: "), "{err}");
    for e in expected {
        assert!(err.contains(e), "{e:?} not in {err:?}");
    }
}

#[test]
fn bad_tables_and_factors_exit_2_naming_what_is_wrong() {
    let dir = Scratch::new("trajectory-bad");
    dir.file(
        "flow.yaml",
        b"joint_limits: {RARM_JOINT0: {max_velocity: 1}}\n",
    );
    let s = scene(&dir, "joint_limits = \"flow.yaml\"", "");
    fails_with(&run(args!["plan", &s]), &["flow.yaml", "line 1:"]);
    dir.file(
        "unknown.yaml",
        b"joint_limits:\n  NO_SUCH_JOINT:\n    max_velocity: 1.0\n",
    );
    let s = scene(&dir, "joint_limits = \"unknown.yaml\"", "");
    fails_with(&run(args!["plan", &s]), &["unknown.yaml", "NO_SUCH_JOINT"]);
    let s = scene(
        &dir,
        "",
        "[trajectory.joint_limits.RARM_JOINT0]\nmax_acceleration = -1.0",
    );
    fails_with(
        &run(args!["plan", &s]),
        &[
            "trajectory.joint_limits.RARM_JOINT0",
            "max_acceleration: -1 is not in",
        ],
    );
    let s = scene(&dir, "", "[trajectory]\nvelocity_scaling = 2.0");
    fails_with(
        &run(args!["plan", &s]),
        &["trajectory.velocity_scaling", "[0.001, 1]"],
    );
    let plain = scene(&dir, "", "");
    for (flag, value, words) in [
        ("--velocity-scaling", "0", "[0.001, 1]"),
        ("--acceleration-scaling", "nan", "[0.001, 1]"),
        ("--sample-period", "1e-9", "[0.001, 1]"),
    ] {
        let o = run(args!["plan", &plain, flag, value]);
        let err = crate::support::stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(flag) && err.contains(words), "{err}");
    }
}
