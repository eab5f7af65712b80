//! Parametric meshes: the primitives (boxes, cylinders, solids of revolution, tubes along a
//! path, ellipsoids) that the library's obstacles and views, tests, benchmarks and the test
//! objects are built from.
//!
//! Every builder is deterministic and returns a closed, outward-wound, welded [`TriMesh`].
//!
//! The catalogue of test objects made from these primitives (the paper's can, mug, pallet and
//! table, the scene suite's objects and supports, the shipped meshes of `meshes/`) is the
//! crate `pickplace-objects`.

use crate::math::{Point3, Real, Vector3};
use crate::mesh::{MeshOptions, TriMesh, TriangleSource};
use std::f64::consts::{PI, TAU};

/// Positions and triangles of a mesh under construction.
#[derive(Debug, Clone, Default)]
pub struct MeshBuilder {
    /// Vertex positions.
    pub positions: Vec<Point3>,
    /// Index triples, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleSource for MeshBuilder {
    fn soup_positions(&self) -> &[Point3] {
        &self.positions
    }
    fn soup_triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }
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

    /// Moves every vertex by `offset`.
    pub fn translate(&mut self, offset: Vector3) {
        for p in &mut self.positions {
            *p += offset;
        }
    }

    /// A copy moved by `offset`.
    pub fn translated(mut self, offset: Vector3) -> Self {
        self.translate(offset);
        self
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

/// A solid of revolution about the z axis: the closed polyline `profile` of `(r, z)` points
/// swept through `segments` angular steps. Points with `r == 0` lie on the axis (one vertex,
/// a triangle fan). The profile must run so that the solid is on its right when `r` points
/// right and `z` up (for a solid cylinder: `(0, 0)`, `(R, 0)`, `(R, H)`, `(0, H)`); consecutive
/// points must differ.
pub fn revolve_builder(profile: &[[Real; 2]], segments: usize) -> MeshBuilder {
    let segments = segments.max(3);
    let mut b = MeshBuilder::default();
    // One vertex on the axis, or a ring of `segments` vertices, per profile point.
    let rings: Vec<Vec<u32>> = profile
        .iter()
        .map(|&[r, z]| {
            if r == 0.0 {
                vec![b.vertex(Point3::new(0.0, 0.0, z))]
            } else {
                (0..segments)
                    .map(|i| {
                        let a = TAU * i as Real / segments as Real;
                        b.vertex(Point3::new(r * a.cos(), r * a.sin(), z))
                    })
                    .collect()
            }
        })
        .collect();
    for pair in rings.windows(2) {
        let (p, q) = (&pair[0], &pair[1]);
        for i in 0..segments {
            let j = (i + 1) % segments;
            match (p.len(), q.len()) {
                (1, 1) => {}
                (1, _) => b.triangle(p[0], q[j], q[i]),
                (_, 1) => b.triangle(p[i], p[j], q[0]),
                _ => b.quad(p[i], p[j], q[j], q[i]),
            }
        }
    }
    b
}

/// A closed tube of circular cross-section (`radius`, `sides` facets around) swept along a
/// path in the xz plane given by its centre points and tangents (`(point, tangent)`, at least
/// two samples), with flat caps at both ends.
pub fn tube_builder(path: &[(Point3, Vector3)], radius: Real, sides: usize) -> MeshBuilder {
    let sides = sides.max(3);
    let mut b = MeshBuilder::default();
    let binormal = Vector3::y();
    let rings: Vec<Vec<u32>> = path
        .iter()
        .map(|(centre, tangent)| {
            // Right-handed frame (normal, binormal, tangent) with the binormal normal to the
            // path's plane.
            let normal = binormal.cross(tangent).normalize();
            (0..sides)
                .map(|k| {
                    let a = TAU * k as Real / sides as Real;
                    b.vertex(centre + radius * (a.cos() * normal + a.sin() * binormal))
                })
                .collect()
        })
        .collect();
    for pair in rings.windows(2) {
        for k in 0..sides {
            let l = (k + 1) % sides;
            b.quad(pair[0][k], pair[0][l], pair[1][l], pair[1][k]);
        }
    }
    if let (Some(first), Some(last)) = (path.first(), path.last()) {
        let start = b.vertex(first.0);
        let end = b.vertex(last.0);
        let (r0, r1) = (&rings[0], &rings[rings.len() - 1]);
        for k in 0..sides {
            let l = (k + 1) % sides;
            b.triangle(start, r0[l], r0[k]);
            b.triangle(end, r1[k], r1[l]);
        }
    }
    b
}

/// Scales every vertex by `factors` along x, y and z (all positive: the winding is kept).
pub fn scaled(mut builder: MeshBuilder, factors: [Real; 3]) -> MeshBuilder {
    for p in &mut builder.positions {
        *p = Point3::new(p.x * factors[0], p.y * factors[1], p.z * factors[2]);
    }
    builder
}

/// An ellipsoid of semi-axes `semi` centred at `(0, 0, semi[2])`, cut flat at height `cut`
/// above its lowest point (0 for none), `rings` latitude bands and `segments` facets around;
/// base at `z = 0` (the cut disc, or the lowest point).
pub fn ellipsoid_builder(semi: [Real; 3], cut: Real, rings: usize, segments: usize) -> MeshBuilder {
    let rings = rings.max(2);
    // A unit sphere's profile from the (cut) bottom to the top pole, then scaled.
    let c = semi[2];
    let start = if cut > 0.0 {
        (1.0 - cut / c).clamp(-1.0, 1.0).acos()
    } else {
        0.0
    };
    let mut profile = vec![[0.0, 0.0]];
    for k in 0..rings {
        // polar angle from the bottom pole
        let t = start + (PI - start) * k as Real / rings as Real;
        let (r, z) = (t.sin(), 1.0 - t.cos());
        if r > 1e-12 {
            profile.push([r, z]);
        }
    }
    profile.push([0.0, 2.0]);
    if cut > 0.0 {
        profile[0] = [0.0, 1.0 - start.cos()];
    }
    let b = revolve_builder(&profile, segments);
    let mut b = scaled(b, [semi[0], semi[1], c]);
    let lowest = b
        .positions
        .iter()
        .map(|p| p.z)
        .fold(Real::INFINITY, Real::min);
    b.translate(Vector3::new(0.0, 0.0, -lowest));
    b
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
