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

/// Height of the table top in the WAIST frame: the facts sheet puts WAIST 0.97 m above the
/// floor; the table is 0.72 m high, 6 cm below the fingers of the home state on the pallet.
pub const TABLE_TOP_Z: f64 = 0.72 - 0.97;

/// The pallet scene: a table top (a box) in front of the robot and `meshes/pallet.stl` on it
/// at x = 0.45 m. Returns the world and the environment indices (table, pallet).
pub fn pallet_world(
    model: &RobotModel,
    semantics: &Semantics,
) -> pickplace_robot::collision::CollisionWorld {
    use pickplace_geometry::math::{Isometry3, Vector3};
    use pickplace_robot::collision::{AllowedCollisionMatrix, CollisionShape, CollisionWorld};
    let mut world = CollisionWorld::new(model, AllowedCollisionMatrix::from_srdf(semantics.srdf()))
        .expect("robot shapes are valid");
    let table = CollisionShape::cuboid(Vector3::new(0.3, 0.5, 0.015)).expect("valid box");
    world.add_environment(
        "table",
        table,
        &Isometry3::translation(0.55, 0.0, TABLE_TOP_Z - 0.015),
    );
    let pallet = CollisionShape::mesh_file(
        &PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../meshes/pallet.stl"),
        &pickplace_geometry::mesh::MeshOptions::default(),
    )
    .expect("shipped pallet loads");
    world.add_environment(
        "pallet",
        pallet,
        &Isometry3::translation(0.45, 0.0, TABLE_TOP_Z),
    );
    world
}

/// The home configuration of the SRDF.
pub fn home(model: &RobotModel, semantics: &Semantics) -> Vec<f64> {
    let mut q = model.zero_configuration();
    semantics
        .apply_state(model, "home", &mut q)
        .expect("home state exists");
    q
}
