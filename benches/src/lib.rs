//! Shared helpers of the criterion benchmarks (scene generators): the repository's files, the
//! shipped robot and the pallet scene of the robot and PRM benches.

use pickplace::geometry::math::{Isometry3, Vector3};
use pickplace::robot::collision::{CollisionShape, CollisionWorld};
use pickplace::robot::{LoadOptions, RobotModel, Semantics};
use std::path::PathBuf;

/// Height of the table top in the WAIST frame (m): WAIST is 0.97 m above the floor (facts
/// sheet), the table top 0.72 m.
pub const TABLE_TOP_Z: f64 = 0.72 - 0.97;

/// The repository root, found from this crate's manifest directory.
pub fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}

/// NX-HIRO as shipped: `robots/nx-hiro/nx-hiro.urdf` and its SRDF.
///
/// # Panics
/// When the shipped files do not load (a broken checkout).
pub fn nx_hiro() -> (RobotModel, Semantics) {
    let model = RobotModel::from_urdf_file(
        &repo().join("robots/nx-hiro/nx-hiro.urdf"),
        &LoadOptions::default(),
    )
    .expect("shipped URDF loads");
    let semantics = Semantics::from_file(&model, &repo().join("robots/nx-hiro/nx-hiro.srdf"))
        .expect("shipped SRDF resolves");
    (model, semantics)
}

/// Adds the pallet scene to `world`: a 0.6 × 1.0 × 0.03 m table top and `meshes/pallet.stl` on
/// it, in front of the robot.
///
/// # Panics
/// When the shipped pallet does not load.
pub fn add_pallet_scene(world: &mut CollisionWorld) {
    world.add_environment(
        "table",
        CollisionShape::cuboid(Vector3::new(0.3, 0.5, 0.015)).expect("valid box"),
        &Isometry3::translation(0.55, 0.0, TABLE_TOP_Z - 0.015),
    );
    world.add_environment(
        "pallet",
        CollisionShape::mesh_file(&repo().join("meshes/pallet.stl"), &Default::default())
            .expect("shipped pallet loads"),
        &Isometry3::translation(0.45, 0.0, TABLE_TOP_Z),
    );
}
