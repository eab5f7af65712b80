//! Benchmarks of surface clustering (Algorithm 1, paper §III-A) and of the cluster database.
//!
//! Meshes: the shipped can and mug (`meshes/*.stl`, read through the loader) and a UV sphere of
//! about 100k triangles (curved everywhere, so every cluster is small and Step 2 does the most
//! work per triangle). Targets (issue 2): at least one million triangles per second per core
//! in environment mode; loading the can's database in under 1 ms.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::db::ClusterDatabase;
use pickplace_geometry::hash::mesh_hash;
use pickplace_geometry::math::{Point3, Real};
use pickplace_geometry::mesh::{self, MeshOptions, TriMesh};
use pickplace_geometry::shapes::MeshBuilder;
use std::f64::consts::{PI, TAU};
use std::hint::black_box;
use std::path::Path;

/// A shipped mesh, read with the loader.
fn shipped(name: &str) -> TriMesh {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../meshes")
        .join(name);
    mesh::load(&path, &MeshOptions::default()).expect("shipped mesh loads")
}

/// A UV sphere of radius 0.1 m with 160 × 316 quads, about 100k triangles (the poles'
/// zero-area triangles are dropped on construction).
fn sphere_100k() -> TriMesh {
    let (rings, seg) = (160usize, 316usize);
    let r = 0.1;
    let mut b = MeshBuilder::default();
    let ids: Vec<Vec<u32>> = (0..=rings)
        .map(|i| {
            let theta = PI * i as Real / rings as Real;
            (0..seg)
                .map(|j| {
                    let phi = TAU * j as Real / seg as Real;
                    b.vertex(Point3::new(
                        r * theta.sin() * phi.cos(),
                        r * theta.sin() * phi.sin(),
                        r * theta.cos(),
                    ))
                })
                .collect()
        })
        .collect();
    for i in 0..rings {
        for j in 0..seg {
            let k = (j + 1) % seg;
            b.quad(ids[i][j], ids[i + 1][j], ids[i + 1][k], ids[i][k]);
        }
    }
    b.build().expect("valid sphere")
}

fn clustering(c: &mut Criterion) {
    let meshes = [
        ("can", shipped("can.stl")),
        ("mug", shipped("mug.stl")),
        ("sphere_100k", sphere_100k()),
    ];
    let mut group = c.benchmark_group("clustering");
    for (name, mesh) in &meshes {
        let n = mesh.triangle_count();
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(format!("env/{name}_{n}"), |b| {
            b.iter(|| {
                cluster_surface(black_box(mesh), &ClusterParams::environment())
                    .map(|c| c.clusters.len())
            })
        });
        if *name != "sphere_100k" {
            group.bench_function(format!("finger/{name}_{n}"), |b| {
                b.iter(|| {
                    cluster_surface(black_box(mesh), &ClusterParams::finger())
                        .map(|c| c.pairs.len())
                })
            });
        }
    }
    group.finish();
}

fn database(c: &mut Criterion) {
    let can = shipped("can.stl");
    let dir = std::env::temp_dir().join(format!("pickplace-bench-db-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let hash = mesh_hash(&can);
    for params in [ClusterParams::environment(), ClusterParams::finger()] {
        let path = dir.join(format!("can-{}.ppdb", params.mode.name()));
        ClusterDatabase::build(&can, &params)
            .expect("valid")
            .save(&path)
            .expect("written");
        c.bench_function(&format!("database/load_can_{}", params.mode.name()), |b| {
            b.iter(|| {
                ClusterDatabase::load(black_box(&path), hash, &params)
                    .map(|d| d.clustering.clusters.len())
            })
        });
    }
    // What a cache lookup costs on top of the load: hashing the loaded mesh.
    c.bench_function("database/mesh_hash_can", |b| {
        b.iter(|| mesh_hash(black_box(&can)))
    });
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, clustering, database);
criterion_main!(benches);
