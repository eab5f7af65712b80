//! The plan reader of `pickplace validate` and `pickplace view` (`pickplace::Plan::from_json`)
//! on arbitrary text (lossy UTF-8). A plan that is accepted must write back (`to_json`) to
//! text that reads back to an equal plan, and the validator's structural helpers must not
//! panic on it: its holds (grasp/release pairing) and its joint columns against NX-HIRO's
//! actuated joints (the model loaded once from `robots/nx-hiro`), its motions
//! (`Plan::motions`) and its ROS 2 export (`pickplace::export`). The whole validator
//! (`pickplace::validate::validate`) is not run: it interpolates and collision-checks up to
//! its state limit, seconds per plan.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace::Plan;
use pickplace_robot::{LoadOptions, RobotModel};
use std::path::PathBuf;
use std::sync::OnceLock;

fn joint_names() -> &'static [String] {
    static NAMES: OnceLock<Vec<String>> = OnceLock::new();
    NAMES.get_or_init(|| {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../robots/nx-hiro/nx-hiro.urdf");
        let model = RobotModel::from_urdf_file(&path, &LoadOptions::default())
            .expect("the shipped URDF loads");
        model.variable_names().map(str::to_owned).collect()
    })
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(plan) = Plan::from_json(&text) {
        let written = plan.to_json();
        let back = Plan::from_json(&written)
            .unwrap_or_else(|e| panic!("an accepted plan does not read back: {e}\n{written}"));
        assert_eq!(back, plan, "the plan changed on a write and read");
        assert_eq!(
            back.to_json(),
            written,
            "the second write differs from the first"
        );
        if let Ok(holds) = plan.holds() {
            for h in &holds {
                assert!(h.link_from_object.rotation.quaternion().norm().is_finite());
            }
        }
        let motions = plan.motions();
        for m in &motions {
            assert!(m.first < m.last && m.last < plan.trajectory.len());
        }
        if let Ok(messages) = pickplace::export::joint_trajectories(&plan) {
            for t in &messages {
                let _ = pickplace::export::to_yaml(&t.message);
            }
        }
        let _ = pickplace::export::display_trajectory(&plan, "robot");
        let names: Vec<&str> = joint_names().iter().map(String::as_str).collect();
        if let Ok(columns) = plan.columns(&names) {
            assert_eq!(columns.len(), names.len());
            for p in &plan.trajectory {
                for &c in &columns {
                    assert!(p.positions[c].is_finite());
                }
            }
        }
    }
});
