//! The URDF loader on arbitrary text (lossy UTF-8). Relative mesh paths resolve against an
//! empty directory, so a mesh reference is an error, never a file read from the repository.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_robot::{LoadOptions, RobotModel};
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    let options = LoadOptions::default();
    if let Ok(model) =
        RobotModel::from_urdf_str(&text, Path::new("/nonexistent-fuzz-dir"), &options)
    {
        // Forward kinematics of the zero configuration must not panic on any accepted model.
        let q = vec![0.0; model.variable_count()];
        let mut poses = vec![pickplace_geometry::math::Isometry3::identity(); model.links().len()];
        let _ = model.forward_kinematics(&q, &mut poses);
    }
});
