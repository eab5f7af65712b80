//! `pickplace plan` and `pickplace validate` on the shipped scenes (the paper's Figs. 9 and 10).

use crate::root;
use crate::support::run_at_root as run;
use crate::support::{Scratch, stdout};
use std::path::{Path, PathBuf};
use std::process::Output;

fn scene(name: &str) -> PathBuf {
    root().join("scenes").join(name)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Plans `scene` into `out` and validates it; returns the plan.
fn plan_and_validate(scene: &Path, out: &Path) -> serde_json::Value {
    let o = run(crate::args!["plan", scene, "--out", out, "--no-timings"]);
    assert_eq!(
        o.status.code(),
        Some(0),
        "plan {}: {}",
        scene.display(),
        stderr(&o)
    );
    let v = run(crate::args!["validate", scene, out]);
    assert_eq!(
        v.status.code(),
        Some(0),
        "validate {}: {}",
        scene.display(),
        stderr(&v)
    );
    assert!(stderr(&v).contains("valid"), "{}", stderr(&v));
    serde_json::from_slice(&std::fs::read(out).expect("plan written")).expect("plan JSON")
}

#[test]
fn near_start_is_planned_with_one_hand_and_validates() {
    let dir = Scratch::new("plan-near");
    let plan = plan_and_validate(&scene("fig9-near.toml"), &dir.join("plan.json"));
    assert_eq!(plan["format"], "pickplace.plan/2");
    assert_eq!(plan["strategy"], "right-right");
    assert_eq!(plan["placement"]["contact"], "face-face");
    assert_eq!(plan["placement"]["environment"], "pallet");
    let events = plan["events"].as_array().expect("events");
    let kinds: Vec<&str> = events
        .iter()
        .map(|e| e["kind"].as_str().expect("kind"))
        .collect();
    assert_eq!(kinds, ["grasp", "release"]);
    // Every actuated joint is a column, every sample has one value per joint.
    let n = plan["joint_names"].as_array().expect("names").len();
    assert_eq!(n, 17);
    for p in plan["trajectory"].as_array().expect("trajectory") {
        assert_eq!(p["positions"].as_array().expect("positions").len(), n);
    }
    let names: Vec<&str> = plan["key_poses"]
        .as_array()
        .expect("key poses")
        .iter()
        .map(|k| k["name"].as_str().expect("name"))
        .collect();
    for key in [
        "pre-grasp",
        "grasp",
        "lift",
        "pre-place",
        "place",
        "release",
        "retreat",
    ] {
        assert!(names.contains(&key), "{key} missing from {names:?}");
    }
}

#[test]
fn far_left_start_needs_a_handover() {
    let dir = Scratch::new("plan-far");
    let plan = plan_and_validate(&scene("fig9-far-left.toml"), &dir.join("plan.json"));
    let strategy = plan["strategy"].as_str().expect("strategy");
    assert!(
        strategy == "left-right" || strategy == "right-left",
        "{strategy}"
    );
    let events: Vec<(String, String)> = plan["events"]
        .as_array()
        .expect("events")
        .iter()
        .map(|e| {
            (
                e["kind"].as_str().unwrap().to_owned(),
                e["arm"].as_str().unwrap().to_owned(),
            )
        })
        .collect();
    // Grasp by the first hand, regrasp by the second, release by the first, then by the second.
    assert_eq!(events.len(), 4, "{events:?}");
    assert_eq!(events[0].0, "grasp");
    assert_eq!(events[1].0, "grasp");
    assert_ne!(events[0].1, events[1].1);
    assert_eq!(plan["grasps"].as_array().expect("grasps").len(), 2);
    // The single-arm strategies were tried and failed, with reasons.
    let tried = plan["stats"]["strategies"].as_array().expect("strategies");
    assert!(
        tried.last().expect("one")["success"]
            .as_bool()
            .expect("bool")
    );
}

#[test]
fn small_dent_gives_an_edge_face_placement() {
    let dir = Scratch::new("plan-edge");
    let plan = plan_and_validate(&scene("fig10a-edge.toml"), &dir.join("plan.json"));
    assert_eq!(plan["placement"]["contact"], "edge-face");
}

#[test]
fn mug_is_placed_on_the_table_among_obstacles() {
    let dir = Scratch::new("plan-mug");
    let plan = plan_and_validate(&scene("fig10b-mug.toml"), &dir.join("plan.json"));
    assert_eq!(plan["placement"]["environment"], "table");
}

#[test]
fn same_seed_gives_identical_bytes() {
    let dir = Scratch::new("plan-seed");
    let mut outputs = Vec::new();
    for (i, seed) in ["7", "7"].iter().enumerate() {
        let out = dir.join(&format!("plan-{i}.json"));
        let o = run(crate::args![
            "plan",
            scene("fig9-near.toml"),
            "--out",
            out,
            "--seed",
            seed,
            "--no-timings"
        ]);
        assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
        outputs.push(std::fs::read(&out).expect("written"));
    }
    assert_eq!(outputs[0], outputs[1]);
    // Without --out the plan goes to stdout, the same bytes.
    let o = run(crate::args![
        "plan",
        scene("fig9-near.toml"),
        "--seed",
        "7",
        "--no-timings"
    ]);
    assert_eq!(stdout(&o).as_bytes(), &outputs[0][..]);
}

#[test]
fn unreachable_target_exits_1_with_reasons() {
    let dir = Scratch::new("plan-unreachable");
    // The pallet a metre and a half in front of the robot: placements exist, no hand reaches.
    let text = std::fs::read_to_string(scene("fig9-near.toml"))
        .expect("scene")
        .replace("../", &format!("{}/", root().display()))
        .replace(
            "pose = { position = [0.50, -0.25, 0.72] }",
            "pose = { position = [1.50, -0.25, 0.72] }",
        )
        .replace(
            "point = [0.40, -0.20, 0.745]",
            "point = [1.40, -0.20, 0.745]",
        );
    let path = dir.file("far.toml", text.as_bytes());
    let out = dir.join("plan.json");
    let o = run(crate::args!["plan", path, "--out", out]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("no plan"), "{err}");
    assert!(err.contains("out of reach"), "{err}");
    for s in ["right-right", "left-left", "right-left", "left-right"] {
        assert!(err.contains(s), "{s} not reported: {err}");
    }
    assert!(!out.exists(), "no plan file on failure");
}

#[test]
fn malformed_scenes_exit_2_naming_the_file() {
    let dir = Scratch::new("plan-malformed");
    let good = std::fs::read_to_string(scene("fig9-near.toml"))
        .expect("scene")
        .replace("../", &format!("{}/", root().display()));
    let cases = [
        ("syntax.toml", "[robot\n".to_owned(), "syntax.toml"),
        (
            "unknown.toml",
            good.replace("[planner]", "[planner]\nspeed = 3"),
            "unknown field `speed`",
        ),
        (
            "mesh.toml",
            good.replace("meshes/can.stl", "meshes/nothing.stl"),
            "nothing.stl",
        ),
        (
            "joint.toml",
            good.replace(
                "[object]",
                "[robot.start_state]\nNO_SUCH_JOINT = 0.1\n\n[object]",
            ),
            "NO_SUCH_JOINT",
        ),
    ];
    for (name, text, expected) in cases {
        let path = dir.file(name, text.as_bytes());
        let out = dir.join("plan.json");
        let o = run(crate::args!["plan", path, "--out", out]);
        assert_eq!(o.status.code(), Some(2), "{name}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains(expected), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(!out.exists(), "{name}: no plan file");
    }
    // A target in the air is an infeasible scene, refused before any search.
    let path = dir.file(
        "target.toml",
        good.replace("point = [0.40, -0.20, 0.745]", "point = [0.40, -0.20, 1.5]")
            .as_bytes(),
    );
    let out = dir.join("plan.json");
    let o = run(crate::args!["plan", path, "--out", out]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("target: the target is not on any surface"),
        "{}",
        stderr(&o)
    );
    assert!(!out.exists(), "no plan file");
}

#[test]
fn validate_finds_a_tampered_plan() {
    let dir = Scratch::new("plan-tampered");
    let scene_path = scene("fig9-near.toml");
    let good = dir.join("plan.json");
    let o = run(crate::args![
        "plan",
        scene_path,
        "--out",
        good,
        "--no-timings"
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut plan: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&good).expect("plan")).expect("json");
    // Drive the right elbow through the table in the middle of the motion.
    let names: Vec<String> = plan["joint_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_owned())
        .collect();
    let j1 = names
        .iter()
        .position(|n| n == "RARM_JOINT1")
        .expect("joint");
    let traj = plan["trajectory"].as_array_mut().unwrap();
    let mid = traj.len() / 2;
    traj[mid]["positions"][j1] = serde_json::json!(0.9);
    let bad = dir.file("bad.json", serde_json::to_string(&plan).unwrap().as_bytes());
    let v = run(crate::args!["validate", scene_path, bad]);
    assert_eq!(v.status.code(), Some(1), "{}", stderr(&v));
    assert!(stderr(&v).contains("t = "), "{}", stderr(&v));
    // A plan for another robot is bad input.
    plan["joint_names"][0] = serde_json::json!("SOMETHING_ELSE");
    let other = dir.file(
        "other.json",
        serde_json::to_string(&plan).unwrap().as_bytes(),
    );
    let v = run(crate::args!["validate", scene_path, other]);
    assert_eq!(v.status.code(), Some(2), "{}", stderr(&v));
    assert!(stderr(&v).contains("joint_names"), "{}", stderr(&v));
}

#[test]
fn a_spent_time_budget_is_a_reason_not_a_hang() {
    let dir = Scratch::new("plan-budget");
    let text = std::fs::read_to_string(scene("fig9-far-left.toml"))
        .expect("scene")
        .replace("../", &format!("{}/", root().display()))
        .replace("seed = 1", "seed = 1\ntime_budget = 1e-9");
    let path = dir.file("budget.toml", text.as_bytes());
    let o = run(crate::args!["plan", path]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(stderr(&o).contains("time budget"), "{}", stderr(&o));
}
