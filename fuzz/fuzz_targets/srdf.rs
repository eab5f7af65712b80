//! The SRDF parser on arbitrary text (lossy UTF-8), then its resolution against NX-HIRO's model
//! (groups, end effectors, states, collision pairs), loaded once from `robots/nx-hiro`.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pickplace_robot::{LoadOptions, RobotModel, Semantics, Srdf};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

fn model() -> &'static RobotModel {
    static MODEL: OnceLock<RobotModel> = OnceLock::new();
    MODEL.get_or_init(|| {
        let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../robots/nx-hiro/nx-hiro.urdf");
        RobotModel::from_urdf_file(&path, &LoadOptions::default()).expect("the shipped URDF loads")
    })
}

fuzz_target!(|data: &[u8]| {
    let text = String::from_utf8_lossy(data);
    if let Ok(srdf) = Srdf::from_xml_str(&text) {
        let _ = srdf.to_xml();
        if let Ok(semantics) = Semantics::resolve(model(), &srdf, Path::new("fuzz.srdf")) {
            let mut q = vec![0.0; model().variable_count()];
            for group in semantics.groups() {
                let _ = semantics.chain(model(), &group.name);
            }
            for state in &srdf.group_states {
                let _ = semantics.apply_state(model(), &state.name, &mut q);
            }
        }
    }
});
