//! The gripper configuration file.

use pickplace_grasp::{Error, GripperParams};
use std::path::Path;

#[test]
fn fixture_parses_with_the_nx_hiro_values() {
    let g = super::support::gripper();
    assert_eq!((g.opening_min, g.opening_max), (0.0, 0.08));
    assert_eq!(
        (
            g.pad_width,
            g.pad_depth,
            g.finger_length,
            g.finger_thickness
        ),
        (0.02, 0.025, 0.06, 0.01)
    );
    assert_eq!(g.palm.min.coords.as_slice(), &[-0.094, -0.055, -0.2245]);
}

#[test]
fn shipped_robot_files_parse_and_match_the_fixture() {
    // The one reader of `gripper.toml` (the robot crate has none): every shipped robot's file.
    let robots = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots");
    let mut read = 0;
    for entry in std::fs::read_dir(&robots).expect("robots/") {
        let file = entry.expect("entry").path().join("gripper.toml");
        if file.exists() {
            let g = GripperParams::load(&file).expect("shipped gripper file is valid");
            assert!(g.opening_max > g.opening_min, "{}", file.display());
            read += 1;
        }
    }
    assert!(read >= 1);
    let nx = GripperParams::load(&robots.join("nx-hiro/gripper.toml")).expect("nx-hiro");
    assert_eq!(nx, super::support::gripper());
}

#[test]
fn missing_file_and_missing_key_name_the_file() {
    let e = GripperParams::load(Path::new("/nonexistent/gripper.toml")).expect_err("missing");
    assert!(matches!(e, Error::Io { .. }));
    assert!(e.to_string().contains("/nonexistent/gripper.toml"), "{e}");
    let text = include_str!("../data/gripper.toml").replace("pad_width = 0.02\n", "");
    let e = GripperParams::from_toml_str(&text, Path::new("robots/x/gripper.toml"))
        .expect_err("missing key");
    let mut message = e.to_string();
    let mut source = std::error::Error::source(&e);
    while let Some(inner) = source {
        message = format!("{message}: {inner}");
        source = inner.source();
    }
    assert!(
        message.starts_with("robots/x/gripper.toml:") && message.contains("pad_width"),
        "{message}"
    );
}
