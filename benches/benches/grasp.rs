//! Benchmarks of grasp planning (Harada et al. §III-B.1): the mug's grasp set with the NX-HIRO
//! gripper. Finger clustering and the collision mesh are built once, outside the timed loop.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
use pickplace_objects as objects;
use std::hint::black_box;
use std::path::Path;

fn gripper() -> GripperParams {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../crates/pickplace-grasp/tests/data/gripper.toml");
    GripperParams::load(&path).expect("valid gripper fixture")
}

fn grasps(c: &mut Criterion) {
    let gripper = gripper();
    let options = GraspOptions::default();
    let mut group = c.benchmark_group("grasps");
    for (name, builder) in [
        ("mug", objects::mug_builder()),
        ("can", objects::can_builder()),
    ] {
        let mesh = builder.build().expect("valid mesh");
        let clustering = cluster_surface(&mesh, &ClusterParams::finger()).expect("valid params");
        let planner = GraspPlanner::new(&mesh).expect("valid mesh");
        let set = planner
            .plan(&clustering, &gripper, &options)
            .expect("valid input");
        assert!(
            name != "mug" || set.candidates >= 500,
            "{} candidates",
            set.candidates
        );
        group.throughput(Throughput::Elements(set.candidates as u64));
        group.bench_function(format!("plan/{name}"), |b| {
            b.iter(|| {
                planner
                    .plan(black_box(&clustering), &gripper, &options)
                    .map(|s| s.grasps.len())
            })
        });
        group.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        group.bench_function(format!("prepare/{name}"), |b| {
            b.iter(|| GraspPlanner::new(black_box(&mesh)).map(|p| p.center_of_mass()))
        });
    }
    group.finish();
}

criterion_group!(benches, grasps);
criterion_main!(benches);
