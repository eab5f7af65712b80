//! Gripper files that broke an invariant of the `gripper` fuzz target (see docs/fuzzing.md),
//! kept under `tests/fuzz-regressions/gripper/`: an accepted gripper has unit, finite axes.

use pickplace_grasp::{Error, GripperParams};
use std::path::Path;

#[test]
fn an_axis_whose_length_overflows_is_refused() {
    // approach_axis = [0, 0, 1e308]: its norm overflows to infinity, so it normalised to the
    // zero vector, and the zero axis passed the orthogonality check (its dot product is 0).
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz-regressions/gripper/huge-approach-axis.toml");
    match GripperParams::load(&path) {
        Err(Error::InvalidGripper {
            path: p,
            field,
            reason,
        }) => {
            assert_eq!(p, path);
            assert_eq!(field, "approach_axis");
            assert!(reason.contains("overflows"), "{reason}");
        }
        other => panic!("expected InvalidGripper for approach_axis, got {other:?}"),
    }
}
