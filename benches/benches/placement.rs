//! Benchmarks of the placement planner (issue 3): Algorithm 2 on the paper's scenes and
//! resting poses on a plane.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::math::{Isometry3, Point3};
use pickplace_geometry::mesh::{MassProperties, TriMesh};
use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
use pickplace_objects as objects;
use pickplace_placement::{
    EnvironmentModel, ObjectModel, PlacementOptions, RestingOptions, candidates, default_target,
    resting_poses,
};
use std::hint::black_box;

fn models(object: &TriMesh, env: &TriMesh) -> (ObjectModel, EnvironmentModel) {
    let params = ClusterParams::environment();
    let oc = cluster_surface(object, &params).expect("object clusters");
    let ec = cluster_surface(env, &params).expect("env clusters");
    let cog = MassProperties::of(object).center_of_mass;
    (
        ObjectModel::new(object, &oc, cog).expect("object"),
        EnvironmentModel::new(env, &ec, &Isometry3::identity()).expect("env"),
    )
}

fn placement(c: &mut Criterion) {
    let can = objects::can_builder().build().expect("can");
    let mug = objects::mug_builder().build().expect("mug");
    let pallet = objects::pallet_builder().build().expect("pallet");
    let table = objects::table_builder().build().expect("table");
    let options = PlacementOptions::default();

    // Fig. 9: the can into the large dent (face-face), cluster databases precomputed.
    let (object, env) = models(&can, &pallet);
    let dent = Point3::new(-0.10, 0.05, 0.025);
    c.bench_function("placement/can_on_pallet_large_dent", |b| {
        b.iter(|| candidates(black_box(&object), &env, &dent, &options).expect("placements"))
    });
    // Fig. 10(a): the can on the narrow groove (edge-face).
    let groove = Point3::new(-0.08, -0.09, 0.028);
    c.bench_function("placement/can_on_pallet_groove_edge_face", |b| {
        b.iter(|| candidates(black_box(&object), &env, &groove, &options).expect("placements"))
    });
    // Fig. 10(b): the mug on the table among obstacles.
    let (mug_object, table_env) = models(&mug, &table);
    let near_obstacle = Point3::new(-0.25, 0.19, 0.70);
    c.bench_function("placement/mug_on_table_near_obstacle", |b| {
        b.iter(|| {
            candidates(black_box(&mug_object), &table_env, &near_obstacle, &options)
                .expect("placements")
        })
    });

    // Resting poses on a plane: the shipped mug (1824 triangles).
    let cog = MassProperties::of(&mug).center_of_mass;
    c.bench_function("placement/mug_resting_poses", |b| {
        b.iter(|| resting_poses(black_box(&mug), &cog, &RestingOptions::default()).expect("poses"))
    });
}

/// Issue 31: a scanned-like box (10 x 6 x 5 cm, 16 428 triangles, every vertex moved by up to
/// 0.5 mm) on the table: its first setup (environment and finger clusters, grasp set, placement
/// model), its resting poses and its placements.
fn scanned(c: &mut Criterion) {
    let scan = objects::jittered(
        objects::subdivided_box_builder([0.1, 0.06, 0.05], 37),
        0.0005,
        31,
    )
    .build()
    .expect("scanned box");
    assert_eq!(scan.triangle_count(), 16_428);
    let table = objects::table_builder().build().expect("table");
    let gripper = GripperParams::load(
        &std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../robots/nx-hiro/gripper.toml"),
    )
    .expect("the NX-HIRO gripper");
    let cog = MassProperties::of(&scan).center_of_mass;
    let options = PlacementOptions::default();
    let mut group = c.benchmark_group("scanned_16k");
    group.sample_size(10);
    group.bench_function("first_setup", |b| {
        b.iter(|| {
            let env = cluster_surface(black_box(&scan), &ClusterParams::environment())
                .expect("env clusters");
            let finger = cluster_surface(&scan, &ClusterParams::finger()).expect("finger clusters");
            let grasps = GraspPlanner::new(&scan)
                .expect("planner")
                .plan(&finger, &gripper, &GraspOptions::default())
                .expect("grasps");
            let object = ObjectModel::new(&scan, &env, cog).expect("object");
            (grasps.grasps.len(), object.regions.len())
        })
    });
    group.bench_function("resting_poses", |b| {
        b.iter(|| resting_poses(black_box(&scan), &cog, &RestingOptions::default()).expect("poses"))
    });
    let (object, env) = models(&scan, &table);
    let top = default_target(&env, &options).expect("the table's top");
    group.bench_function("placements_on_table", |b| {
        b.iter(|| candidates(black_box(&object), &env, &top, &options).expect("placements"))
    });
    group.finish();
}

criterion_group!(benches, placement, scanned);
criterion_main!(benches);
