//! Benchmarks of the placement planner (issue 3): Algorithm 2 on the paper's scenes and
//! resting poses on a plane.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::math::{Isometry3, Point3};
use pickplace_geometry::mesh::{MassProperties, TriMesh};
use pickplace_geometry::shapes;
use pickplace_placement::{
    EnvironmentModel, ObjectModel, PlacementOptions, RestingOptions, candidates, resting_poses,
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
    let can = shapes::can_builder().build().expect("can");
    let mug = shapes::mug_builder().build().expect("mug");
    let pallet = shapes::pallet_builder().build().expect("pallet");
    let table = shapes::table_builder().build().expect("table");
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

criterion_group!(benches, placement);
criterion_main!(benches);
