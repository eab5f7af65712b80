//! The scene format's unit tests.

use super::*;

const MINIMAL: &str = r#"
[robot]
urdf = "robot.urdf"
srdf = "robot.srdf"
gripper = "gripper.toml"
[object]
mesh = "can.stl"
start_pose = { position = [0.4, -0.2, 0.0] }
[[environment]]
name = "pallet"
mesh = "/abs/pallet.stl"
[target]
point = [0.45, 0.1, 0.02]
"#;

fn parse(text: &str) -> Result<Scene, SceneError> {
    Scene::parse(text, Path::new("scene.toml"), Path::new("/scenes"))
}

#[test]
fn minimal_scene_gets_defaults_and_resolved_paths() {
    let s = parse(MINIMAL).expect("valid");
    assert_eq!(s.robots[0].urdf, PathBuf::from("/scenes/robot.urdf"));
    assert_eq!(s.robots.len(), 1);
    assert!(s.robot.is_none());
    assert_eq!(
        s.environment[0].mesh,
        Some(PathBuf::from("/abs/pallet.stl"))
    );
    assert_eq!(s.planner, PlannerOptions::default());
    assert_eq!(s.object.start_pose.orientation, [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(s.target.tolerance, None);
    assert_eq!(s.target.tolerance(), DEFAULT_TARGET_TOLERANCE);
    let s = parse(&MINIMAL.replace("[target]", "[target]\ntolerance = 0.01")).expect("valid");
    assert_eq!(s.target.tolerance(), 0.01);
}

#[test]
fn fixed_length_arrays_are_exact() {
    for (from, to, expected) in [
        (
            "[0.4, -0.2, 0.0] }",
            "[0.4, -0.2, 0.0, 9.0] }",
            "position: expected exactly 3 numbers [x, y, z], got 4",
        ),
        (
            "[0.4, -0.2, 0.0] }",
            "[0.4, -0.2] }",
            "expected exactly 3 numbers [x, y, z], got 2",
        ),
        (
            "[0.4, -0.2, 0.0] }",
            "[0.4, -0.2, 0.0], orientation = [0, 0, 0, 1, 0, 0] }",
            "orientation: expected exactly 4 numbers [x, y, z, w], got 6",
        ),
        (
            "[0.4, -0.2, 0.0] }",
            "[0.4, -0.2, 0.0], orientation = [0, 0, 1] }",
            "expected exactly 4 numbers [x, y, z, w], got 3",
        ),
        (
            "point = [0.45, 0.1, 0.02]",
            "point = [0.45, 0.1, 0.02, 0.0]",
            "got 4",
        ),
        ("point = [0.45, 0.1, 0.02]", "point = []", "got 0"),
        (
            "mesh = \"can.stl\"",
            "mesh = \"can.stl\"\ncenter_of_gravity = [0, 0, 0.1, 0]",
            "got 4",
        ),
    ] {
        let text = MINIMAL.replace(from, to);
        assert_ne!(text, MINIMAL, "{to}");
        let err = parse(&text).expect_err(to).to_string();
        assert!(err.starts_with("scene.toml: "), "{err}");
        assert!(err.contains(expected), "{to}: {err}");
    }
    let s = parse(&MINIMAL.replace(
        "mesh = \"can.stl\"",
        "mesh = \"can.stl\"\ncenter_of_gravity = [0, 0, 0.1]",
    ))
    .expect("three numbers");
    assert_eq!(s.object.center_of_gravity, Some([0.0, 0.0, 0.1]));
}

#[test]
fn unknown_fields_and_bad_values_are_named() {
    let err = parse(&MINIMAL.replace("[target]", "[target]\nradius = 3")).unwrap_err();
    assert!(err.to_string().contains("unknown field `radius`"), "{err}");
    let err = parse(&MINIMAL.replace(
        "[0.4, -0.2, 0.0] }",
        "[0.4, -0.2, 0.0], orientation = [0,0,0,0] }",
    ))
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("object.start_pose: orientation quaternion is zero"),
        "{err}"
    );
    let err = parse(&MINIMAL.replace("[target]", "[target]\ntolerance = -0.01")).unwrap_err();
    assert!(err.to_string().contains("target.tolerance"), "{err}");
    let err = parse(&format!("{MINIMAL}\n[planner]\nh_max_finger = -1")).unwrap_err();
    assert!(err.to_string().contains("planner.h_max_finger"), "{err}");
    let err = parse("[robot").unwrap_err();
    assert!(err.to_string().starts_with("scene.toml: "), "{err}");
}

#[test]
fn names_and_paths_over_their_limits_are_refused() {
    let long = "n".repeat(1025);
    let err =
        parse(&MINIMAL.replace("name = \"pallet\"", &format!("name = \"{long}\""))).unwrap_err();
    assert_eq!(
        err.to_string(),
        "scene.toml: environment[0].name: the name is 1025 bytes, over the limit of 1024"
    );
    let err = parse(&MINIMAL.replace(
        "[object]",
        &format!("start_state = {{ {long} = 1.0 }}\n[object]"),
    ))
    .unwrap_err();
    assert!(
        err.to_string()
            .contains("robot.start_state: the name is 1025 bytes"),
        "{err}"
    );
    let err = parse(&MINIMAL.replace("can.stl", &"p".repeat(5000))).unwrap_err();
    assert!(
        err.to_string()
            .contains("object.mesh: the path is 5000 bytes, over the limit of 4096"),
        "{err}"
    );
    assert!(parse(&MINIMAL.replace("pallet\"", &format!("{}\"", "n".repeat(1018)))).is_ok());
}

#[test]
fn syntax_errors_give_line_and_column_without_quoting_the_file() {
    // Regression (issue 18): `gripper = "/etc/passwd"` printed the file's first line.
    let err = parse("root:x:0:0:root:/root:/bin/bash\n").unwrap_err();
    let message = err.to_string();
    assert!(message.starts_with("scene.toml: "), "{message}");
    assert!(
        message.contains("line 1, column 32: key with no value"),
        "{message}"
    );
    assert!(!message.contains("/bin/bash"), "{message}");
    assert!(!message.contains('|'), "{message}");
}
