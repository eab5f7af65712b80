//! The pre-search checks on the shipped scenes (`scenes/*.toml`, their poses copied here): each
//! start pose rests on the table, each target is on a surface the object fits.

use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::math::nalgebra::Quaternion;
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion};
use pickplace_geometry::mesh::{self, MassProperties, MeshOptions, TriMesh};
use pickplace_placement::{
    ContactKind, EnvironmentModel, ObjectModel, PlacementOptions, RestOptions, RestState,
    rest_state, target_surface,
};
use std::f64::consts::FRAC_1_SQRT_2;
use std::path::Path;

fn load(name: &str) -> TriMesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name);
    mesh::load(&path, &MeshOptions::default()).expect("shipped mesh")
}

/// A pose from a scene: position and quaternion (x, y, z, w).
fn pose(p: [Real; 3], q: [Real; 4]) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(p[0], p[1], p[2]),
        UnitQuaternion::from_quaternion(Quaternion::new(q[3], q[0], q[1], q[2]).normalize()),
    )
}

const IDENTITY: [Real; 4] = [0.0, 0.0, 0.0, 1.0];
const TABLE_TURN: [Real; 4] = [0.0, 0.0, -FRAC_1_SQRT_2, FRAC_1_SQRT_2];

fn environment(parts: &[(&str, [Real; 3], [Real; 4])]) -> EnvironmentModel {
    let params = ClusterParams::environment();
    let meshes: Vec<(TriMesh, Isometry3)> = parts
        .iter()
        .map(|(name, p, q)| (load(name), pose(*p, *q)))
        .collect();
    let clusters: Vec<_> = meshes
        .iter()
        .map(|(m, _)| cluster_surface(m, &params).expect("clusters"))
        .collect();
    let refs: Vec<_> = meshes
        .iter()
        .zip(&clusters)
        .map(|((m, pose), c)| (m, c, *pose))
        .collect();
    EnvironmentModel::from_parts(&refs).expect("environment")
}

fn object(name: &str) -> ObjectModel {
    let mesh = load(name);
    let clusters = cluster_surface(&mesh, &ClusterParams::environment()).expect("clusters");
    ObjectModel::new(&mesh, &clusters, MassProperties::of(&mesh).center_of_mass).expect("object")
}

#[test]
fn shipped_scenes_start_resting_and_aim_at_surfaces_that_fit() {
    let table = ("table.stl", [0.55, 0.0, 0.02], TABLE_TURN);
    let pallet = ("pallet.stl", [0.50, -0.25, 0.72], IDENTITY);
    let can = object("can.stl");
    let env = environment(&[table, pallet]);
    let options = PlacementOptions::default();
    // fig9-near and fig10a-edge start, fig9-far-left start.
    for start in [[0.42, -0.04, 0.72], [0.48, 0.30, 0.72]] {
        let state = rest_state(&can, &env, &pose(start, IDENTITY), &RestOptions::default());
        let RestState::Resting { margin, .. } = state else {
            panic!("{start:?}: {state}");
        };
        assert!((margin - 0.033).abs() < 1e-3, "{margin}");
        // Lifted 1 cm it floats; sunk 5 mm it penetrates.
        let lifted = pose([start[0], start[1], start[2] + 0.01], IDENTITY);
        assert!(matches!(
            rest_state(&can, &env, &lifted, &RestOptions::default()),
            RestState::Floating { .. }
        ));
        let sunk = pose([start[0], start[1], start[2] - 0.005], IDENTITY);
        assert!(matches!(
            rest_state(&can, &env, &sunk, &RestOptions::default()),
            RestState::Penetrating { .. }
        ));
    }
    // fig9: the large dent, face-face; fig10a: the groove, edge-face only.
    let dent = target_surface(&can, &env, &Point3::new(0.40, -0.20, 0.745), &options)
        .expect("the large dent");
    assert!(dent.fits.iter().any(|(_, k)| *k == ContactKind::FaceFace));
    let groove =
        target_surface(&can, &env, &Point3::new(0.42, -0.34, 0.748), &options).expect("the groove");
    assert!(groove.fits.iter().all(|(_, k)| *k == ContactKind::EdgeFace));
    assert!(!groove.fits.is_empty());

    // fig10b: the mug on the table among three boxes.
    let mug = object("mug.stl");
    let env = environment(&[
        table,
        ("box.stl", [0.34, -0.28, 0.72], IDENTITY),
        (
            "box.stl",
            [0.52, -0.26, 0.72],
            [0.0, 0.0, 0.382_683_43, 0.923_879_53],
        ),
        (
            "box.stl",
            [0.44, -0.12, 0.72],
            [0.0, 0.0, FRAC_1_SQRT_2, FRAC_1_SQRT_2],
        ),
    ]);
    let state = rest_state(
        &mug,
        &env,
        &pose([0.40, 0.02, 0.72], IDENTITY),
        &RestOptions::default(),
    );
    assert!(state.is_resting(), "{state}");
    target_surface(&mug, &env, &Point3::new(0.43, -0.25, 0.72), &options).expect("the table");
}
