//! A few representative scenes of the scene suite (`scenes/suite`, issue 17), end to end in
//! debug: one single-arm scene, one handover, and infeasible scenes refused with the stage and
//! the reason their scene file's header states. The whole suite, every scene with seeds 1 to
//! 3, runs in release through `cargo xtask suite run` (docs/suite.md).

use crate::root;
use crate::support::Scratch;
use crate::support::run_at_root as run;
use std::path::PathBuf;
use std::process::Output;

fn scene(name: &str) -> PathBuf {
    root().join("scenes/suite").join(format!("{name}.toml"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The expectation a suite scene's header states: `None` for a feasible scene, else the stage
/// and the reason `pickplace plan` must print.
fn expectation(name: &str) -> Option<(String, String)> {
    let text = std::fs::read_to_string(scene(name)).expect("suite scene");
    let line = text
        .lines()
        .find(|l| l.starts_with("# Expected:"))
        .expect("an expectation line");
    if line.contains("feasible.") && !line.contains("no solution") {
        return None;
    }
    let quoted: Vec<&str> = line.split('"').skip(1).step_by(2).collect();
    assert_eq!(quoted.len(), 2, "{line}");
    Some((quoted[0].to_owned(), quoted[1].to_owned()))
}

/// Plans a feasible suite scene and validates the plan; returns the plan.
fn plans_and_validates(name: &str) -> serde_json::Value {
    assert_eq!(expectation(name), None, "{name} is a feasible scene");
    let dir = Scratch::new(&format!("suite-{name}"));
    let out = dir.join("plan.json");
    let o = run(crate::args![
        "plan",
        scene(name),
        "--out",
        out,
        "--no-timings"
    ]);
    assert_eq!(o.status.code(), Some(0), "plan {name}: {}", stderr(&o));
    let v = run(crate::args!["validate", scene(name), out]);
    assert_eq!(v.status.code(), Some(0), "validate {name}: {}", stderr(&v));
    serde_json::from_slice(&std::fs::read(&out).expect("plan written")).expect("plan JSON")
}

/// Plans an infeasible suite scene: exit 1, no plan, the stage and the reason on stderr.
fn is_refused_as_stated(name: &str) {
    let (stage, reason) = expectation(name).expect("an infeasible scene");
    let dir = Scratch::new(&format!("suite-{name}"));
    let out = dir.join("plan.json");
    let o = run(crate::args!["plan", scene(name), "--out", out]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{name}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    let low = err.to_lowercase();
    assert!(low.contains(&stage), "{name}: {stage:?} not in {err}");
    assert!(low.contains(&reason), "{name}: {reason:?} not in {err}");
    assert!(!out.exists(), "no plan file on failure");
}

#[test]
fn suite_single_arm_scene_plans_and_validates() {
    let plan = plans_and_validates("can-right");
    assert_eq!(plan["strategy"], "right-right");
    assert_eq!(plan["placement"]["environment"], "table");
}

#[test]
fn suite_handover_scene_plans_with_both_hands() {
    let plan = plans_and_validates("can-handover-left-to-right");
    let strategy = plan["strategy"].as_str().expect("strategy");
    assert!(
        strategy == "left-right" || strategy == "right-left",
        "{strategy}"
    );
    assert_eq!(plan["grasps"].as_array().expect("grasps").len(), 2);
}

#[test]
fn suite_start_in_collision_is_refused_for_that_reason() {
    is_refused_as_stated("start-in-collision");
}

#[test]
fn suite_target_out_of_reach_is_refused_for_that_reason() {
    is_refused_as_stated("target-out-of-reach");
}

/// The expectation lines the tests above read are the generator's (a change of wording there
/// must show here).
#[test]
fn suite_scene_headers_state_their_expectation() {
    assert_eq!(expectation("can-right"), None);
    assert_eq!(
        expectation("start-in-collision"),
        Some(("start state".to_owned(), "in collision".to_owned()))
    );
}
