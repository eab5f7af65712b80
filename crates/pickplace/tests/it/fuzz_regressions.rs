//! Scene files that broke an invariant of the `scene` fuzz target (see docs/fuzzing.md), kept
//! under `tests/fuzz-regressions/scene/`: a scene that parses holds only usable poses.

use pickplace::Scene;
use std::path::Path;

#[test]
fn huge_quaternion_gives_a_unit_rotation() {
    // orientation = [1e200, 0, 0, 1e200]: its norm overflows to infinity, and normalising by it
    // gave the zero quaternion, accepted as a "unit" rotation.
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz-regressions/scene/huge-quaternion.toml");
    let text = std::fs::read_to_string(&path).expect("input");
    let scene = Scene::parse(&text, &path, Path::new("/scene")).expect("a valid scene");
    let rotation = scene
        .object
        .start_pose
        .to_isometry()
        .expect("a pose")
        .rotation;
    let q = rotation.quaternion();
    assert!((q.norm() - 1.0).abs() < 1e-12, "{q:?}");
    // The direction is kept: a quarter turn about x, the same as [1, 0, 0, 1] normalised.
    let expected = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (q.i - expected).abs() < 1e-12 && (q.w - expected).abs() < 1e-12,
        "{q:?}"
    );
}

/// Gripper overrides files (a scene's `robot.gripper`) that broke an invariant of the
/// `gripper` fuzz target, kept under `tests/fuzz-regressions/gripper/`: an accepted file's
/// axes are the tool frame's.
mod gripper_overrides {
    use pickplace::Error;
    use pickplace::robot_setup::GripperOverrides;
    use std::path::{Path, PathBuf};

    fn input(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/fuzz-regressions/gripper")
            .join(name)
    }

    #[test]
    fn a_zero_approach_axis_is_refused() {
        // approach_axis = [0, 0, 0] normalised to NaN, and `NaN > 1e-9` is false: accepted.
        let path = input("zero-approach-axis.toml");
        match GripperOverrides::load(&path) {
            Err(Error::Invalid { path: p, field, .. }) => {
                assert_eq!(p, path);
                assert_eq!(field, "approach_axis");
            }
            other => panic!("expected Invalid for approach_axis, got {other:?}"),
        }
    }

    #[test]
    fn huge_axes_along_the_tool_frame_are_accepted() {
        // [0, 0, 1e308] is along +z: scaled before normalising, it is not refused as NaN.
        let o = GripperOverrides::load(&input("huge-axes-along-the-tool-frame.toml"))
            .expect("axes along the tool frame");
        assert_eq!(o.approach_axis, Some([0.0, 0.0, 1e308]));
        assert_eq!(o.closing_axis, Some([0.0, 1e308, 0.0]));
    }
}
