//! Benchmarks of mesh files: reading the shipped mug (binary STL), encoding it, and its mass
//! properties.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::mesh::{MeshOptions, encode_stl_binary, read_stl};
use pickplace_objects::mug_builder;
use std::hint::black_box;
use std::path::Path;

fn mesh_io(c: &mut Criterion) {
    let mug = mug_builder();
    let bytes = encode_stl_binary(&mug).expect("the mug encodes");
    let path = Path::new("mug.stl");
    c.bench_function("mesh_io/read_stl_mug_1824", |b| {
        b.iter(|| {
            read_stl(black_box(&bytes), path, &MeshOptions::default()).map(|m| m.triangle_count())
        })
    });
    c.bench_function("mesh_io/encode_stl_mug_1824", |b| {
        b.iter(|| encode_stl_binary(black_box(&mug)).map(|v| v.len()))
    });
    let mesh = read_stl(&bytes, path, &MeshOptions::default()).expect("the mug reads");
    c.bench_function("mesh_io/mass_properties_mug_1824", |b| {
        b.iter(|| black_box(&mesh).mass_properties().volume)
    });
}

criterion_group!(benches, mesh_io);
criterion_main!(benches);
