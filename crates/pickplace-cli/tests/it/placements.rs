//! `pickplace placements`.

use crate::pickplace;
use serde_json::Value;

fn json(out: &std::process::Output) -> Value {
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

/// `pickplace placements` of the can on the pallet at `target`, with `extra` arguments.
fn can_on_pallet(target: &str, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "placements",
        "meshes/can.stl",
        "--on",
        "meshes/pallet.stl",
        "--target",
        target,
    ];
    args.extend_from_slice(extra);
    pickplace(&args)
}

/// The JSON document of the can's placements on the pallet at `target` (exit status 0).
fn can_on_pallet_json(target: &str) -> Value {
    let out = can_on_pallet(target, &["--json"]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    json(&out)
}

#[test]
fn can_into_the_large_dent() {
    let v = can_on_pallet_json("-0.1,0.05,0.025");
    assert_eq!(v["format"], "pickplace.placements/1");
    let first = &v["placements"][0];
    assert_eq!(first["contact"], "face-face");
    let z = first["pose"]["position"][2].as_f64().expect("z");
    assert!(
        (z - 0.025).abs() < 1e-9,
        "the can's base on the dent floor: {z}"
    );
    assert!(first["stability_margin"].as_f64().expect("margin") > 0.03);
}

#[test]
fn can_on_the_groove_is_edge_face() {
    let v = can_on_pallet_json("-0.08,-0.09,0.028");
    let placements = v["placements"].as_array().expect("array");
    assert!(!placements.is_empty());
    assert!(placements.iter().all(|p| p["contact"] == "edge-face"));
}

#[test]
fn environment_pose_moves_the_placements() {
    let out = pickplace(&[
        "placements",
        "meshes/can.stl",
        "--on",
        "meshes/pallet.stl",
        "--env-pose",
        "0.5,0,0.7",
        "--target",
        "0.4,0.05,0.725",
        "--json",
        "--max",
        "1",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let p = &json(&out)["placements"][0]["pose"]["position"];
    assert!((p[0].as_f64().expect("x") - 0.4).abs() < 1e-9);
    assert!((p[2].as_f64().expect("z") - 0.725).abs() < 1e-9);
}

/// The can on the pallet at `target`: the exit status and every `needle` on stderr.
fn check_can_on_pallet(target: &str, code: i32, needles: &[&str]) {
    let out = can_on_pallet(target, &[]);
    assert_eq!(out.status.code(), Some(code), "{target}");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(needles.iter().all(|n| err.contains(n)), "{target}: {err}");
}

#[test]
fn no_placement_exits_1_with_reasons() {
    check_can_on_pallet("0.05,0.06,0.03", 1, &["did not fit", "environment cluster"]);
}

#[test]
fn target_off_the_environment_exits_2_naming_the_nearest_cluster() {
    check_can_on_pallet("1,0,0.04", 2, &["nearest is cluster", "pallet.stl"]);
}

#[test]
fn resting_poses_without_environment() {
    let out = pickplace(&["placements", "meshes/can.stl", "--json"]);
    assert_eq!(out.status.code(), Some(0));
    // A cylinder rests on its two caps and rolls on its side.
    assert_eq!(json(&out)["placements"].as_array().expect("array").len(), 3);
}

#[test]
fn bad_input_exits_2_naming_the_file() {
    for (args, needle) in [
        (
            vec!["placements", "meshes/nothing.stl"],
            "meshes/nothing.stl",
        ),
        (
            vec![
                "placements",
                "meshes/can.stl",
                "--on",
                "meshes/pallet.stl",
                "--target",
                "a,b,c",
            ],
            "--target",
        ),
        (
            vec![
                "placements",
                "meshes/can.stl",
                "--on",
                "meshes/pallet.stl",
                "--env-pose",
                "0,0,0,0,0,0,0",
            ],
            "quaternion",
        ),
        (vec!["placements", "meshes/README.md"], "README.md"),
    ] {
        let out = pickplace(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

#[test]
fn same_input_same_bytes() {
    let args = [
        "placements",
        "meshes/mug.stl",
        "--on",
        "meshes/table.stl",
        "--target",
        "-0.25,0.19,0.7",
        "--json",
    ];
    let (a, b) = (pickplace(&args), pickplace(&args));
    assert_eq!(a.status.code(), Some(0));
    assert_eq!(a.stdout, b.stdout);
}
