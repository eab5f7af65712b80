//! Parametric meshes: primitives used by tests, benchmarks and the shipped-mesh generator.
//!
//! Every builder is deterministic and returns a closed, outward-wound, welded [`TriMesh`].

use crate::math::{Point3, Real};
use crate::mesh::{MeshOptions, TriMesh};

/// Positions and triangles of a mesh under construction.
#[derive(Debug, Clone, Default)]
pub struct MeshBuilder {
    /// Vertex positions.
    pub positions: Vec<Point3>,
    /// Index triples, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl MeshBuilder {
    /// Adds a vertex and returns its index.
    pub fn vertex(&mut self, p: Point3) -> u32 {
        self.positions.push(p);
        (self.positions.len() - 1) as u32
    }

    /// Adds a triangle.
    pub fn triangle(&mut self, a: u32, b: u32, c: u32) {
        self.triangles.push([a, b, c]);
    }

    /// Adds the quad `a b c d` (counter-clockwise) as two triangles.
    pub fn quad(&mut self, a: u32, b: u32, c: u32, d: u32) {
        self.triangles.push([a, b, c]);
        self.triangles.push([a, c, d]);
    }

    /// Appends another builder's geometry.
    pub fn append(&mut self, other: &MeshBuilder) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|v| v + base)));
    }

    /// Builds the mesh (welding coincident vertices).
    ///
    /// # Panics
    /// Never for the builders of this module; a hand-made builder with no valid triangle
    /// returns the error of [`TriMesh::from_soup`].
    pub fn build(&self) -> crate::Result<TriMesh> {
        TriMesh::from_soup(&self.positions, &self.triangles, &MeshOptions::default())
    }
}

/// An axis-aligned box centred at the origin, two triangles per face.
pub fn box_builder(half_extents: [Real; 3]) -> MeshBuilder {
    let [x, y, z] = half_extents;
    let mut b = MeshBuilder::default();
    let c: Vec<u32> = (0..8)
        .map(|i| {
            b.vertex(Point3::new(
                if i & 1 == 0 { -x } else { x },
                if i & 2 == 0 { -y } else { y },
                if i & 4 == 0 { -z } else { z },
            ))
        })
        .collect();
    b.quad(c[0], c[2], c[3], c[1]); // -z
    b.quad(c[4], c[5], c[7], c[6]); // +z
    b.quad(c[0], c[1], c[5], c[4]); // -y
    b.quad(c[2], c[6], c[7], c[3]); // +y
    b.quad(c[0], c[4], c[6], c[2]); // -x
    b.quad(c[1], c[3], c[7], c[5]); // +x
    b
}

/// An axis-aligned box centred at the origin.
pub fn box_mesh(half_extents: [Real; 3]) -> TriMesh {
    expect_valid(box_builder(half_extents).build())
}

/// A closed cylinder along z from `z = 0` to `z = height`, with `segments` facets around and
/// caps fanned from their centres.
pub fn cylinder_builder(radius: Real, height: Real, segments: usize) -> MeshBuilder {
    let segments = segments.max(3);
    let mut b = MeshBuilder::default();
    let ring = |b: &mut MeshBuilder, z: Real| -> Vec<u32> {
        (0..segments)
            .map(|i| {
                let a = std::f64::consts::TAU * i as Real / segments as Real;
                b.vertex(Point3::new(radius * a.cos(), radius * a.sin(), z))
            })
            .collect()
    };
    let bottom = ring(&mut b, 0.0);
    let top = ring(&mut b, height);
    let cb = b.vertex(Point3::new(0.0, 0.0, 0.0));
    let ct = b.vertex(Point3::new(0.0, 0.0, height));
    for i in 0..segments {
        let j = (i + 1) % segments;
        b.quad(bottom[i], bottom[j], top[j], top[i]);
        b.triangle(cb, bottom[j], bottom[i]);
        b.triangle(ct, top[i], top[j]);
    }
    b
}

/// A closed cylinder along z from `z = 0` to `z = height`.
pub fn cylinder(radius: Real, height: Real, segments: usize) -> TriMesh {
    expect_valid(cylinder_builder(radius, height, segments).build())
}

fn expect_valid(mesh: crate::Result<TriMesh>) -> TriMesh {
    match mesh {
        Ok(m) => m,
        // The primitives above always have positive-area triangles for positive sizes; a
        // non-positive size is a caller bug, reported loudly.
        Err(e) => panic!("primitive mesh with invalid size: {e}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_are_closed_with_the_right_area() {
        let b = box_mesh([0.5, 1.0, 1.5]);
        assert!(b.report().is_closed());
        assert_eq!(b.triangle_count(), 12);
        assert!((b.area() - 2.0 * (1.0 * 2.0 + 2.0 * 3.0 + 1.0 * 3.0)).abs() < 1e-12);
        let c = cylinder(1.0, 2.0, 64);
        assert!(c.report().is_closed());
        assert_eq!(c.triangle_count(), 64 * 4);
        for t in 0..b.triangle_count() {
            let centroid = b
                .triangle_points(t)
                .iter()
                .fold(Point3::origin(), |s, p| s + p.coords / 3.0);
            assert!(
                b.triangle_normal(t).dot(&centroid.coords) > 0.0,
                "outward winding"
            );
        }
    }
}
