//! `pickplace motion` (issue 35) on the shipped motion scene (NX-HIRO, a table box, the pallet
//! mesh, a post cylinder and a ball): a motion written atomically, the same bytes per seed,
//! a goal in collision exits 1 naming the pair, bad input exits 2 naming what is wrong, and
//! a pick-and-place scene with primitives plans and validates.

use crate::support::run_at_root as run;
use crate::support::{Scratch, ok, stderr};
use crate::{args, root};
use std::process::Output;

/// Bad input: exit status 2, nothing on stdout, no panic, the last line on stderr an `error:`
/// line with every string of `expected` (the lines before say what was set up).
fn fails_with(o: &Output, expected: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "stderr:\n{err}");
    assert!(o.stdout.is_empty());
    assert!(!err.contains("panicked"), "{err}");
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("error: "), "{err}");
    for e in expected {
        assert!(last.contains(e), "{e:?} not in {last:?}");
    }
}

const SCENE: &str = "scenes/motion/nx-hiro-table.toml";
const FROM: &str = "--from=-0.5,-0.3,-2.0,0.2,0.3,0.1";
const TO: &str = "0.2,-0.5,-1.5,0,0,0";

#[test]
fn a_motion_is_written_and_the_same_seed_gives_the_same_bytes() {
    let dir = Scratch::new("motion-out");
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    for out in [&a, &b] {
        let o = run(args![
            "motion",
            SCENE,
            "--group",
            "right_arm",
            FROM,
            "--to",
            TO,
            "--no-timings",
            "--out",
            out
        ]);
        ok(&o);
        assert!(
            stderr(&o).contains("motion of right_arm (6 joints)"),
            "{}",
            stderr(&o)
        );
    }
    let text = std::fs::read_to_string(&a).expect("written");
    assert_eq!(text, std::fs::read_to_string(&b).expect("written"));
    let motion: pickplace::motion::MotionPlan = serde_json::from_str(&text).expect("the format");
    assert_eq!(motion.format, pickplace::motion::MOTION_FORMAT);
    assert_eq!(motion.joint_names[0], "RARM_JOINT0");
    assert!(motion.trajectory.len() > 2);
    // Printed on stdout without --out.
    let printed = ok(&run(args![
        "motion",
        SCENE,
        "--group",
        "right_arm",
        FROM,
        "--to",
        TO,
        "--no-timings"
    ]));
    assert_eq!(printed, text);
}

#[test]
fn an_end_in_collision_exits_1_naming_the_pair() {
    let o = run(args![
        "motion",
        SCENE,
        "--group",
        "right_arm",
        FROM,
        "--to",
        "0.0,-0.6,-1.5,0,0,0"
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(o.stdout.is_empty());
    let err = stderr(&o);
    assert!(
        err.contains("no motion: the goal state is in collision"),
        "{err}"
    );
    assert!(err.contains("post"), "{err}");
}

#[test]
fn bad_queries_exit_2_naming_what_is_wrong() {
    fails_with(
        &run(args!["motion", SCENE, "--to", TO]),
        &["group: missing", "right_arm (6 joints)"],
    );
    fails_with(
        &run(args![
            "motion",
            SCENE,
            "--group",
            "right_arm",
            "--to",
            "1,2"
        ]),
        &["goal", "2 values for the 6 joints"],
    );
    fails_with(
        &run(args![
            "motion",
            SCENE,
            "--group",
            "right_arm",
            "--to",
            "dance"
        ]),
        &["goal", "no group_state \"dance\""],
    );
    fails_with(
        &run(args![
            "motion",
            SCENE,
            "--group",
            "right_arm",
            "--to",
            "RARM_JOINT0=x"
        ]),
        &["--to", "`x` is not a number"],
    );
    fails_with(
        &run(args![
            "motion",
            SCENE,
            "--group",
            "right_arm",
            "--to",
            TO,
            "--out",
            SCENE
        ]),
        &["--out", "an input of this command"],
    );
    let dir = Scratch::new("motion-bad-scene");
    let text = std::fs::read_to_string(root().join(SCENE)).expect("scene");
    let text = text.replace("\"../../", &format!("\"{}/", root().display()));
    let two = dir.file(
        "two.toml",
        text.replace(
            "sphere = { radius = 0.05 }",
            "sphere = { radius = 0.05 }\nbox = [1, 1, 1]",
        )
        .as_bytes(),
    );
    fails_with(
        &run(args!["motion", &two, "--group", "right_arm", "--to", TO]),
        &[
            "environment[3]",
            "exactly one of mesh, box, cylinder and sphere (given: box, sphere)",
        ],
    );
    let flat = dir.file(
        "flat.toml",
        text.replace("radius = 0.05", "radius = 0").as_bytes(),
    );
    fails_with(
        &run(args!["motion", &flat, "--group", "right_arm", "--to", TO]),
        &["environment[3].sphere.radius"],
    );
    // A motion scene is not a pick-and-place scene.
    fails_with(
        &run(args!["plan", SCENE]),
        &["object: missing: a pick-and-place scene needs [object]"],
    );
}

#[test]
fn a_pick_and_place_scene_of_primitives_plans_and_validates() {
    let dir = Scratch::new("motion-primitives-plan");
    let text = std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("scene");
    let text = text.replace("\"../", &format!("\"{}/", root().display()));
    let table =
        "mesh = \"".to_owned() + &root().join("meshes/table.stl").display().to_string() + "\"";
    assert!(text.contains(&table), "fig9-near's table");
    // The table's top as a box, and a post beside it.
    let text = text
        .replace(&table, "box = [0.6, 0.9, 0.04]")
        .replace(
            "pose = { position = [0.55, 0.0, 0.02], orientation = [0.0, 0.0, -0.70710678, 0.70710678] }",
            "pose = { position = [0.55, 0.0, 0.70] }\n\n[[environment]]\nname = \"post\"\ncylinder = { radius = 0.03, length = 0.4 }\npose = { position = [0.45, 0.25, 0.92] }",
        );
    let scene = dir.file("scene.toml", text.as_bytes());
    let plan = dir.join("plan.json");
    // `run` validates the written plan against the scene too.
    ok(&run(args!["plan", &scene, "--no-timings", "--out", &plan]));
    ok(&run(args![
        "view",
        "--scene",
        &scene,
        &plan,
        "--out",
        &dir.join("view")
    ]));
}
