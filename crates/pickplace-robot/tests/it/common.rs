//! Shared fixtures: the shipped NX-HIRO model.

use pickplace_robot::{LoadOptions, RobotModel, Semantics};
use std::path::PathBuf;
use std::sync::OnceLock;

pub fn robot_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro")
}

pub fn nx() -> &'static (RobotModel, Semantics) {
    static NX: OnceLock<(RobotModel, Semantics)> = OnceLock::new();
    NX.get_or_init(|| {
        let model =
            RobotModel::from_urdf_file(&robot_dir().join("nx-hiro.urdf"), &LoadOptions::default())
                .expect("shipped URDF loads");
        let semantics = Semantics::from_file(&model, &robot_dir().join("nx-hiro.srdf"))
            .expect("shipped SRDF resolves");
        (model, semantics)
    })
}

/// A configuration with every variable drawn uniformly within its limits.
pub fn random_configuration(model: &RobotModel, rng: &mut pickplace_robot::rng::Rng) -> Vec<f64> {
    model
        .variable_limits()
        .map(|l| rng.uniform(l.lower, l.upper))
        .collect()
}
