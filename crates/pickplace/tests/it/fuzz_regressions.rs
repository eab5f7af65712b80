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
