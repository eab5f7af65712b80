//! The two readers of gripper files on arbitrary text (lossy UTF-8):
//! - the robot's `gripper.toml` (`pickplace_grasp::GripperParams::from_toml_str`, read by
//!   `pickplace grasps`): an accepted gripper must have unit, orthogonal, finite axes and
//!   finite finger and palm boxes;
//! - a scene's `robot.gripper` overrides file (`pickplace::robot_setup::GripperOverrides::load`,
//!   which reads a path only, so the text is written to one temporary file per process first):
//!   an accepted file must have axes that are the tool frame's (`approach_axis` along +z,
//!   `closing_axis` along +y), and is then resolved against NX-HIRO's right arm as
//!   `RobotSetup` does: the overrides become `GripperOptions` for `Gripper::derive`, and the
//!   measured gripper with the overrides becomes the grasp planner's `GripperParams`, which
//!   must pass `validate` or be an error (never a panic).
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::grasp::GripperParams;
use pickplace::robot_setup::{GripperOverrides, grasp_model};
use pickplace_geometry::math::Vector3;
use pickplace_robot::gripper::Gripper;
use pickplace_robot::{LoadOptions, RobotModel, Semantics, Srdf};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

/// NX-HIRO's model and its right arm's variables, loaded once.
fn nx_hiro() -> &'static (RobotModel, Vec<usize>) {
    static MODEL: OnceLock<(RobotModel, Vec<usize>)> = OnceLock::new();
    MODEL.get_or_init(|| {
        let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../robots/nx-hiro");
        let model = RobotModel::from_urdf_file(&dir.join("nx-hiro.urdf"), &LoadOptions::default())
            .expect("the shipped URDF loads");
        let text = std::fs::read_to_string(dir.join("nx-hiro.srdf")).expect("the shipped SRDF");
        let srdf = Srdf::from_xml_str(&text).expect("the shipped SRDF parses");
        let semantics =
            Semantics::resolve(&model, &srdf, Path::new("nx-hiro.srdf")).expect("resolves");
        let arm = semantics
            .group("right_arm")
            .expect("right_arm")
            .variables
            .clone();
        (model, arm)
    })
}

fn overrides_path() -> &'static Path {
    static PATH: OnceLock<PathBuf> = OnceLock::new();
    PATH.get_or_init(|| {
        std::env::temp_dir().join(format!(
            "pickplace-fuzz-gripper-{}.toml",
            std::process::id()
        ))
    })
}

fn check_params(params: &GripperParams) {
    let (a, c, l) = (params.approach(), params.closing(), params.lateral());
    for (name, v) in [("approach", a), ("closing", c), ("lateral", l)] {
        assert!(
            v.iter().all(|x| x.is_finite()) && (v.norm() - 1.0).abs() < 1e-9,
            "{name} axis {v:?} of an accepted gripper {params:?}"
        );
    }
    assert!(a.dot(&c).abs() < 1e-6, "axes not orthogonal: {params:?}");
    for opening in [params.opening_min, params.opening_max] {
        for finger in params.fingers(opening) {
            assert!(finger.center.iter().all(|x| x.is_finite()), "{params:?}");
            assert!(
                finger
                    .half_extents
                    .iter()
                    .all(|x| x.is_finite() && *x > 0.0),
                "{params:?}"
            );
        }
    }
    let palm = params.palm_box();
    assert!(
        palm.half_extents.iter().all(|x| x.is_finite() && *x > 0.0),
        "{params:?}"
    );
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(params) = GripperParams::from_toml_str(&text, Path::new("fuzz.toml")) {
        check_params(&params);
    }

    if std::fs::write(overrides_path(), text.as_bytes()).is_err() {
        return;
    }
    let Ok(o) = GripperOverrides::load(overrides_path()) else {
        return;
    };
    for (name, given, want) in [
        ("approach_axis", o.approach_axis, Vector3::z()),
        ("closing_axis", o.closing_axis, Vector3::y()),
    ] {
        if let Some(axis) = given {
            let axis = Vector3::from(axis).normalize();
            assert!(
                (axis - want).norm() <= 1e-9,
                "{name} {given:?} accepted; it must be along {want:?}"
            );
        }
    }
    let (model, arm) = nx_hiro();
    let Ok(gripper) = Gripper::derive(model, arm, &o.options()) else {
        return;
    };
    let Ok(params) = grasp_model(&gripper, &o, Path::new("fuzz-overrides.toml")) else {
        return;
    };
    check_params(&params);
    // The closing command of every width the grasp planner may ask for stays a finite
    // parameter in [0, 1].
    let mut q = vec![0.0; model.variable_count()];
    for width in [params.opening_min, params.opening_max] {
        gripper.set_grasp(&mut q, width);
        let s = gripper.parameter_of(&q);
        assert!(
            s.is_finite() && (-1e-9..=1.0 + 1e-9).contains(&s),
            "s = {s} for {width}"
        );
    }
});
