//! Benchmarks of pickplace-geometry.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_geometry::math::Point3;
use pickplace_geometry::mesh::{MeshOptions, TriMesh};

fn weld(c: &mut Criterion) {
    let n = 100usize;
    let mut p = Vec::new();
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let (x, y) = (i as f64, j as f64);
            let b = p.len() as u32;
            p.extend([
                Point3::new(x, y, 0.0),
                Point3::new(x + 1.0, y, 0.0),
                Point3::new(x + 1.0, y + 1.0, 0.0),
            ]);
            t.push([b, b + 1, b + 2]);
        }
    }
    c.bench_function("mesh/weld_10k_soup", |b| {
        b.iter(|| TriMesh::from_soup(&p, &t, &MeshOptions::default()).map(|m| m.triangle_count()))
    });
}

criterion_group!(benches, weld);
criterion_main!(benches);
