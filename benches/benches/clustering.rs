//! Benchmarks of surface clustering (Algorithm 1) and of the cluster database.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::db::ClusterDatabase;
use pickplace_geometry::hash::mesh_hash;
use pickplace_geometry::math::{Point3, Real};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::shapes::{MeshBuilder, cylinder, cylinder_builder};
use std::f64::consts::TAU;
use std::hint::black_box;

/// Stand-in for the shipped mug until meshes/mug.stl lands: a cup (outer wall, rim, inner
/// wall, inner floor, base) with a torus-segment handle, about 3k triangles.
fn mug() -> TriMesh {
    let (r_out, r_in, height, floor, seg) = (0.04, 0.036, 0.1, 0.006, 96usize);
    let mut b = MeshBuilder::default();
    let ring = |b: &mut MeshBuilder, r: Real, z: Real| -> Vec<u32> {
        (0..seg).map(|i| b.vertex(Point3::new(r * (TAU * i as Real / seg as Real).cos(), r * (TAU * i as Real / seg as Real).sin(), z))).collect()
    };
    let levels = 8;
    let outer: Vec<Vec<u32>> = (0..=levels).map(|k| ring(&mut b, r_out, height * k as Real / levels as Real)).collect();
    let inner: Vec<Vec<u32>> = (0..=levels).map(|k| ring(&mut b, r_in, floor + (height - floor) * k as Real / levels as Real)).collect();
    let bottom = b.vertex(Point3::new(0.0, 0.0, 0.0));
    let inner_floor = b.vertex(Point3::new(0.0, 0.0, floor));
    for i in 0..seg {
        let j = (i + 1) % seg;
        for k in 0..levels {
            b.quad(outer[k][i], outer[k][j], outer[k + 1][j], outer[k + 1][i]);
            b.quad(inner[k][j], inner[k][i], inner[k + 1][i], inner[k + 1][j]);
        }
        b.quad(outer[levels][i], outer[levels][j], inner[levels][j], inner[levels][i]);
        b.triangle(bottom, outer[0][j], outer[0][i]);
        b.triangle(inner_floor, inner[0][i], inner[0][j]);
    }
    // Handle: half a torus on the +x side (tube radius 6 mm), closed by the wall in reality;
    // here a separate open tube, enough for clustering cost.
    let (major, minor, around, along) = (0.03, 0.006, 16usize, 24usize);
    let mut ids = vec![vec![0u32; around]; along + 1];
    for (a, row) in ids.iter_mut().enumerate() {
        let phi = -TAU / 4.0 + (TAU / 2.0) * a as Real / along as Real;
        let centre = Point3::new(r_out + major * phi.cos() * 0.5, 0.0, height / 2.0 + major * phi.sin());
        for (k, id) in row.iter_mut().enumerate() {
            let t = TAU * k as Real / around as Real;
            let radial = pickplace_geometry::math::Vector3::new(phi.cos(), 0.0, phi.sin());
            *id = b.vertex(centre + radial * (minor * t.cos()) + pickplace_geometry::math::Vector3::y() * (minor * t.sin()));
        }
    }
    for a in 0..along {
        for k in 0..around {
            let l = (k + 1) % around;
            b.quad(ids[a][k], ids[a + 1][k], ids[a + 1][l], ids[a][l]);
        }
    }
    b.build().expect("valid mug")
}

/// A UV sphere of radius 0.1 m with about 100k triangles.
fn sphere_100k() -> TriMesh {
    let (rings, seg) = (160usize, 316usize);
    let mut b = MeshBuilder::default();
    let r = 0.1;
    let mut ids = vec![vec![0u32; seg]; rings + 1];
    for (i, row) in ids.iter_mut().enumerate() {
        let theta = std::f64::consts::PI * i as Real / rings as Real;
        for (j, id) in row.iter_mut().enumerate() {
            let phi = TAU * j as Real / seg as Real;
            *id = b.vertex(Point3::new(r * theta.sin() * phi.cos(), r * theta.sin() * phi.sin(), r * theta.cos()));
        }
    }
    for i in 0..rings {
        for j in 0..seg {
            let k = (j + 1) % seg;
            b.quad(ids[i][j], ids[i + 1][j], ids[i + 1][k], ids[i][k]);
        }
    }
    // The poles' zero-area triangles are dropped on construction.
    b.build().expect("valid sphere")
}

fn clustering(c: &mut Criterion) {
    let _ = cylinder_builder;
    let meshes = [("can", cylinder(0.033, 0.12, 64)), ("mug", mug()), ("sphere_100k", sphere_100k())];
    let mut group = c.benchmark_group("clustering");
    for (name, mesh) in &meshes {
        group.throughput(Throughput::Elements(mesh.triangle_count() as u64));
        group.bench_function(format!("env/{name}"), |b| {
            b.iter(|| cluster_surface(black_box(mesh), &ClusterParams::environment()).map(|c| c.clusters.len()))
        });
        if *name != "sphere_100k" {
            group.bench_function(format!("finger/{name}"), |b| {
                b.iter(|| cluster_surface(black_box(mesh), &ClusterParams::finger()).map(|c| c.pairs.len()))
            });
        }
    }
    group.finish();
}

fn database(c: &mut Criterion) {
    let can = cylinder(0.033, 0.12, 64);
    let dir = std::env::temp_dir().join(format!("pickplace-bench-db-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let hash = mesh_hash(&can);
    for params in [ClusterParams::environment(), ClusterParams::finger()] {
        let path = dir.join(format!("can-{}.ppdb", params.mode.name()));
        ClusterDatabase::build(&can, &params).expect("valid").save(&path).expect("written");
        c.bench_function(&format!("database/load_can_{}", params.mode.name()), |b| {
            b.iter(|| ClusterDatabase::load(black_box(&path), hash, &params).map(|d| d.clustering.clusters.len()))
        });
    }
    c.bench_function("database/mesh_hash_can", |b| b.iter(|| mesh_hash(black_box(&can))));
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, clustering, database);
criterion_main!(benches);
