//! Parametric meshes: primitives used by tests, benchmarks and the shipped-mesh generator.
//!
//! Every builder is deterministic and returns a closed, outward-wound, welded [`TriMesh`].
//!
//! The meshes of the paper's scenes (Harada et al., §IV, Figs. 9-10: a drink can placed into
//! the dents of a pallet, a mug placed on a table among obstacles) are here as builders
//! ([`can_builder`], [`mug_builder`], [`object_box_builder`], [`pallet_builder`],
//! [`table_builder`]); `cargo xtask gen-meshes` writes them to `meshes/` as binary STL
//! ([`shipped_meshes`]).

use crate::error::Error;
use crate::math::{Point3, Real, Vector3};
use crate::mesh::{MeshOptions, TriMesh};
use std::f64::consts::{PI, TAU};

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

/// Drink-can radius (m).
pub const CAN_RADIUS: Real = 0.033;
/// Drink-can height (m).
pub const CAN_HEIGHT: Real = 0.12;

/// The drink can of the paper's Figs. 3 and 9: a closed cylinder of radius [`CAN_RADIUS`] and
/// height [`CAN_HEIGHT`], 64 facets around, axis z, base at `z = 0`.
pub fn can_builder() -> MeshBuilder {
    cylinder_builder(CAN_RADIUS, CAN_HEIGHT, 64)
}

/// Mug outer radius (m).
pub const MUG_RADIUS: Real = 0.04;
/// Mug wall thickness (m).
pub const MUG_WALL: Real = 0.005;
/// Mug height (m).
pub const MUG_HEIGHT: Real = 0.095;
/// Mug bottom thickness (m).
pub const MUG_BOTTOM: Real = 0.005;

/// The mug of the paper's Figs. 4 and 10(b), axis z, base at `z = 0`, handle on the +x side.
///
/// Two closed shells: the body, a solid of revolution (64 facets around) with outer radius
/// [`MUG_RADIUS`], wall [`MUG_WALL`], height [`MUG_HEIGHT`], bottom [`MUG_BOTTOM`] and an open
/// top with a flat rim annulus; and the handle, a tube of radius 6 mm (16 facets around, 40
/// steps) swept along a half ellipse in the xz plane (3.5 cm out from its ends, 5.6 cm tall,
/// centred at `z = 0.05`) whose capped ends sit 3 mm deep inside the wall. The shells overlap
/// there, so the volume of [`MassProperties`](crate::mesh::MassProperties) counts that overlap
/// (about 0.7 cm³ of 142 cm³) twice. 1824 triangles.
pub fn mug_builder() -> MeshBuilder {
    let (r, w, h, f) = (MUG_RADIUS, MUG_WALL, MUG_HEIGHT, MUG_BOTTOM);
    let profile = [
        [0.0, 0.0],
        [r, 0.0],
        [r, h],
        [r - w, h],
        [r - w, f],
        [0.0, f],
    ];
    let mut b = revolve_builder(&profile, 64);
    let (x0, reach, zc, half_height, steps) = (r - 0.003, 0.035, 0.05, 0.028, 40);
    let path: Vec<(Point3, Vector3)> = (0..=steps)
        .map(|s| {
            let t = PI * s as Real / steps as Real;
            let centre = Point3::new(x0 + reach * t.sin(), 0.0, zc + half_height * t.cos());
            let tangent = Vector3::new(reach * t.cos(), 0.0, -half_height * t.sin());
            (centre, tangent)
        })
        .collect();
    b.append(&tube_builder(&path, 0.006, 16));
    b
}

/// Half extents of the box object (m): 0.06 x 0.04 x 0.10.
pub const OBJECT_BOX_HALF_EXTENTS: [Real; 3] = [0.03, 0.02, 0.05];

/// A box object 0.06 x 0.04 x 0.10 m, centred on the z axis, base at `z = 0`.
pub fn object_box_builder() -> MeshBuilder {
    let [_, _, z] = OBJECT_BOX_HALF_EXTENTS;
    box_builder(OBJECT_BOX_HALF_EXTENTS).translated(Vector3::new(0.0, 0.0, z))
}

/// A rectangular dent in the top of a slab.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dent {
    /// Centre `(x, y)` of the dent (m).
    pub center: [Real; 2],
    /// Size along x and y (m).
    pub size: [Real; 2],
    /// Depth below the top (m), less than the slab's thickness.
    pub depth: Real,
}

/// A slab `size[0] x size[1]` centred on the z axis, from `z = 0` to `z = thickness`, with
/// rectangular dents in its top.
///
/// The top is split into a grid by every slab and dent edge coordinate; a cell whose centre
/// is in a dent drops to the deepest such dent's floor. Walls stand on grid edges between
/// cells of different levels, and each wall carries a vertex at every level met at its end
/// columns, so the mesh has no T-junction and is closed and outward-wound. Dents may touch or
/// overlap (the deepest wins), but four cells meeting at one grid vertex in a checkerboard of
/// levels make that vertex's column non-manifold.
///
/// # Errors
/// [`Error::InvalidParameter`] for a non-positive size or thickness, a dent of non-positive
/// size, a depth outside `(0, thickness)`, or a dent reaching outside the slab.
pub fn dented_slab_builder(
    size: [Real; 2],
    thickness: Real,
    dents: &[Dent],
) -> crate::Result<MeshBuilder> {
    let invalid = |name, value, reason| Error::InvalidParameter {
        name,
        value,
        reason,
    };
    for v in size {
        if !(v > 0.0 && v.is_finite()) {
            return Err(invalid("size", v, "must be positive and finite"));
        }
    }
    if !(thickness > 0.0 && thickness.is_finite()) {
        return Err(invalid(
            "thickness",
            thickness,
            "must be positive and finite",
        ));
    }
    let half = [size[0] / 2.0, size[1] / 2.0];
    let mut xs = vec![-half[0], half[0]];
    let mut ys = vec![-half[1], half[1]];
    for d in dents {
        if !(d.depth > 0.0 && d.depth < thickness) {
            return Err(invalid("dent.depth", d.depth, "must be in (0, thickness)"));
        }
        for (axis, half_size) in half.into_iter().enumerate() {
            let (lo, hi) = (
                d.center[axis] - d.size[axis] / 2.0,
                d.center[axis] + d.size[axis] / 2.0,
            );
            if !(d.size[axis] > 0.0 && d.size[axis].is_finite()) {
                return Err(invalid(
                    "dent.size",
                    d.size[axis],
                    "must be positive and finite",
                ));
            }
            if !(lo >= -half_size && hi <= half_size) {
                return Err(invalid(
                    "dent.center",
                    d.center[axis],
                    "the dent reaches outside the slab",
                ));
            }
            let list = if axis == 0 { &mut xs } else { &mut ys };
            list.push(lo);
            list.push(hi);
        }
    }
    for list in [&mut xs, &mut ys] {
        list.sort_by(Real::total_cmp);
        list.dedup();
    }
    let (nx, ny) = (xs.len() - 1, ys.len() - 1);
    let level: Vec<Vec<Real>> = (0..nx)
        .map(|i| {
            (0..ny)
                .map(|j| {
                    let c = [(xs[i] + xs[i + 1]) / 2.0, (ys[j] + ys[j + 1]) / 2.0];
                    dents
                        .iter()
                        .filter(|d| (0..2).all(|a| (c[a] - d.center[a]).abs() < d.size[a] / 2.0))
                        .map(|d| thickness - d.depth)
                        .fold(thickness, Real::min)
                })
                .collect()
        })
        .collect();
    // Levels of the cells around grid vertex (i, j).
    let column = |i: usize, j: usize| -> Vec<Real> {
        level[i.saturating_sub(1)..(i + 1).min(nx)]
            .iter()
            .flat_map(|cells| cells[j.saturating_sub(1)..(j + 1).min(ny)].iter().copied())
            .collect()
    };
    let mut b = MeshBuilder::default();
    for i in 0..nx {
        for j in 0..ny {
            let (x0, x1, y0, y1, z) = (xs[i], xs[i + 1], ys[j], ys[j + 1], level[i][j]);
            let v = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
                .map(|(x, y)| b.vertex(Point3::new(x, y, z)));
            b.quad(v[0], v[1], v[2], v[3]);
            let v = [(x0, y0), (x0, y1), (x1, y1), (x1, y0)]
                .map(|(x, y)| b.vertex(Point3::new(x, y, 0.0)));
            b.quad(v[0], v[1], v[2], v[3]);
        }
    }
    // A wall from grid vertex p to grid vertex q (outward normal along (q - p) x z) between
    // heights lo and hi.
    let wall = |b: &mut MeshBuilder, p: (usize, usize), q: (usize, usize), lo: Real, hi: Real| {
        let mut heights = |(i, j): (usize, usize)| -> Vec<u32> {
            let mut zs: Vec<Real> = column(i, j)
                .into_iter()
                .filter(|&z| z > lo && z < hi)
                .collect();
            zs.push(lo);
            zs.push(hi);
            zs.sort_by(Real::total_cmp);
            zs.dedup();
            zs.into_iter()
                .map(|z| b.vertex(Point3::new(xs[i], ys[j], z)))
                .collect()
        };
        let (ps, qs) = (heights(p), heights(q));
        let (mut a, mut c) = (0, 0);
        // Zip up the two vertical edges, lowest next vertex first.
        while a + 1 < ps.len() || c + 1 < qs.len() {
            let next_p = ps.get(a + 1).map(|&v| b.positions[v as usize].z);
            let next_q = qs.get(c + 1).map(|&v| b.positions[v as usize].z);
            let advance_p = match (next_p, next_q) {
                (Some(zp), Some(zq)) => zp <= zq,
                (Some(_), None) => true,
                _ => false,
            };
            if advance_p {
                b.triangle(ps[a], qs[c], ps[a + 1]);
                a += 1;
            } else {
                b.triangle(ps[a], qs[c], qs[c + 1]);
                c += 1;
            }
        }
    };
    for (i, cells) in level.iter().enumerate() {
        wall(&mut b, (i, 0), (i + 1, 0), 0.0, cells[0]);
        wall(&mut b, (i + 1, ny), (i, ny), 0.0, cells[ny - 1]);
    }
    for (j, (&first, &last)) in level[0].iter().zip(&level[nx - 1]).enumerate() {
        wall(&mut b, (0, j + 1), (0, j), 0.0, first);
        wall(&mut b, (nx, j), (nx, j + 1), 0.0, last);
    }
    for (column_pair, i) in level.windows(2).zip(1..) {
        for (j, (&left, &right)) in column_pair[0].iter().zip(&column_pair[1]).enumerate() {
            if left > right {
                wall(&mut b, (i, j), (i, j + 1), right, left);
            } else if right > left {
                wall(&mut b, (i, j + 1), (i, j), left, right);
            }
        }
    }
    for (i, cells) in level.iter().enumerate() {
        for (pair, j) in cells.windows(2).zip(1..) {
            let (front, back) = (pair[0], pair[1]);
            if front > back {
                wall(&mut b, (i + 1, j), (i, j), back, front);
            } else if back > front {
                wall(&mut b, (i, j), (i + 1, j), front, back);
            }
        }
    }
    Ok(b)
}

/// Size of the pallet (m): 0.40 x 0.30, thickness 0.04 (top at `z = 0.04`).
pub const PALLET_SIZE: [Real; 3] = [0.40, 0.30, 0.04];

/// The dents of the pallet of the paper's Figs. 9 and 10(a).
pub const PALLET_DENTS: [Dent; 4] = [
    // Larger than the can's base (diameter 0.066): the can stands in it (Fig. 9).
    Dent {
        center: [-0.10, 0.05],
        size: [0.09, 0.09],
        depth: 0.015,
    },
    // Smaller than the can's base: the can rests on its edge (Fig. 10(a)).
    Dent {
        center: [0.05, 0.06],
        size: [0.05, 0.05],
        depth: 0.01,
    },
    // A deep rectangular pocket, long along y.
    Dent {
        center: [0.13, -0.05],
        size: [0.075, 0.12],
        depth: 0.02,
    },
    // A shallow groove, long along x.
    Dent {
        center: [-0.08, -0.09],
        size: [0.16, 0.04],
        depth: 0.012,
    },
];

/// The pallet: a slab [`PALLET_SIZE`] centred on the z axis, base at `z = 0`, with the
/// [`PALLET_DENTS`]; see [`dented_slab_builder`].
pub fn pallet_builder() -> MeshBuilder {
    match dented_slab_builder(
        [PALLET_SIZE[0], PALLET_SIZE[1]],
        PALLET_SIZE[2],
        &PALLET_DENTS,
    ) {
        Ok(b) => b,
        // The constants above are valid; a test builds them.
        Err(e) => panic!("invalid pallet constants: {e}"),
    }
}

/// Height of the table's top surface (m).
pub const TABLE_HEIGHT: Real = 0.70;

/// The table of the paper's Fig. 10(b), in separate closed shells: a top 0.9 x 0.6 x 0.03 m
/// (top surface at `z = 0.70`) centred on the z axis, four legs 0.05 x 0.05 m standing on
/// `z = 0` under its corners, and three obstacles standing on the top near its corners,
/// leaving the middle (|x| < 0.25 m) free: a box 0.08 x 0.08 x 0.15 m at (0.33, 0.20), a box
/// 0.10 x 0.06 x 0.08 m at (-0.33, -0.20) and a cylinder of radius 0.04 m and height 0.18 m
/// (32 facets) at (-0.33, 0.19). Shells touch (legs under the top, obstacles on it) but share
/// no vertex.
pub fn table_builder() -> MeshBuilder {
    let (top_half, thickness) = ([0.45, 0.30], 0.03);
    let mut b = box_builder([top_half[0], top_half[1], thickness / 2.0]).translated(Vector3::new(
        0.0,
        0.0,
        TABLE_HEIGHT - thickness / 2.0,
    ));
    let leg_height = TABLE_HEIGHT - thickness;
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let leg = box_builder([0.025, 0.025, leg_height / 2.0]).translated(Vector3::new(
            sx * 0.40,
            sy * 0.25,
            leg_height / 2.0,
        ));
        b.append(&leg);
    }
    let boxes = [
        ([0.04, 0.04, 0.075], [0.33, 0.20]),
        ([0.05, 0.03, 0.04], [-0.33, -0.20]),
    ];
    for (half, [x, y]) in boxes {
        b.append(&box_builder(half).translated(Vector3::new(x, y, TABLE_HEIGHT + half[2])));
    }
    b.append(&cylinder_builder(0.04, 0.18, 32).translated(Vector3::new(-0.33, 0.19, TABLE_HEIGHT)));
    b
}

/// A mesh shipped in `meshes/`, generated by `cargo xtask gen-meshes`.
#[derive(Debug, Clone)]
pub struct ShippedMesh {
    /// File name inside `meshes/` (binary STL).
    pub file_name: &'static str,
    /// The geometry, written triangle by triangle in this order.
    pub builder: MeshBuilder,
}

/// Every shipped mesh, in a fixed order: `can.stl`, `mug.stl`, `box.stl`, `pallet.stl`,
/// `table.stl`.
pub fn shipped_meshes() -> Vec<ShippedMesh> {
    [
        ("can.stl", can_builder()),
        ("mug.stl", mug_builder()),
        ("box.stl", object_box_builder()),
        ("pallet.stl", pallet_builder()),
        ("table.stl", table_builder()),
    ]
    .into_iter()
    .map(|(file_name, builder)| ShippedMesh { file_name, builder })
    .collect()
}

// ---------------------------------------------------------------------------------------------
// Objects and environment parts of the scene suite (issue 17, `cargo xtask suite gen`).
//
// The paper's method (Harada et al., §III: clustering into planar contact regions, stable
// placements by Algorithm 2, parallel-gripper grasps on opposite clusters) is meant for
// everyday objects; these builders make the kinds of objects and supports it meets on a real
// table. Every builder is deterministic (the seeded ones through [`SplitMix64`]).

/// The generator of the seeded builders ([`jittered`]): the workspace's SplitMix64.
pub use pickplace_base::rng::SplitMix64;

/// A box of full size `size`, centred on the z axis, base at `z = 0`.
pub fn box_on_base_builder(size: [Real; 3]) -> MeshBuilder {
    box_builder([size[0] / 2.0, size[1] / 2.0, size[2] / 2.0]).translated(Vector3::new(
        0.0,
        0.0,
        size[2] / 2.0,
    ))
}

/// A box of full size `size` whose six faces are each split into `divisions × divisions`
/// quads (two triangles each): `12 · divisions²` triangles, the same solid as
/// [`box_on_base_builder`]. Centred on the z axis, base at `z = 0`.
pub fn subdivided_box_builder(size: [Real; 3], divisions: usize) -> MeshBuilder {
    let n = divisions.max(1);
    let half = [size[0] / 2.0, size[1] / 2.0, size[2] / 2.0];
    let mut b = MeshBuilder::default();
    // Each face: its normal axis, sign, and two in-plane axes (u, v) with u × v = normal.
    for (axis, sign) in [
        (0, 1.0),
        (0, -1.0),
        (1, 1.0),
        (1, -1.0),
        (2, 1.0),
        (2, -1.0),
    ] {
        let (u, v) = if sign > 0.0 {
            ((axis + 1) % 3, (axis + 2) % 3)
        } else {
            ((axis + 2) % 3, (axis + 1) % 3)
        };
        let grid: Vec<Vec<u32>> = (0..=n)
            .map(|i| {
                (0..=n)
                    .map(|j| {
                        let mut p = [0.0; 3];
                        p[axis] = sign * half[axis];
                        p[u] = -half[u] + size[u] * i as Real / n as Real;
                        p[v] = -half[v] + size[v] * j as Real / n as Real;
                        b.vertex(Point3::new(p[0], p[1], p[2] + half[2]))
                    })
                    .collect()
            })
            .collect();
        for i in 0..n {
            for j in 0..n {
                b.quad(
                    grid[i][j],
                    grid[i + 1][j],
                    grid[i + 1][j + 1],
                    grid[i][j + 1],
                );
            }
        }
    }
    b
}

/// Moves every vertex by a seeded random offset of at most `amplitude` per coordinate, the
/// offset a function of the vertex's position (rounded to 1 µm) and `seed`: copies of one
/// point move together, so a welded, closed mesh stays closed. Makes a "scanned-looking"
/// surface out of a clean one; keep `amplitude` well under the edge lengths.
pub fn jittered(mut builder: MeshBuilder, amplitude: Real, seed: u64) -> MeshBuilder {
    for p in &mut builder.positions {
        let key = [p.x, p.y, p.z].iter().fold(seed, |h, c| {
            let q = (c * 1e6).round() as i64 as u64;
            SplitMix64::new(h ^ q.wrapping_mul(0x9E37_79B9_7F4A_7C15)).next_u64()
        });
        let mut rng = SplitMix64::new(key);
        *p += Vector3::new(rng.symmetric(), rng.symmetric(), rng.symmetric()) * amplitude;
    }
    builder
}

/// Scales every vertex by `factors` along x, y and z (all positive: the winding is kept).
pub fn scaled(mut builder: MeshBuilder, factors: [Real; 3]) -> MeshBuilder {
    for p in &mut builder.positions {
        *p = Point3::new(p.x * factors[0], p.y * factors[1], p.z * factors[2]);
    }
    builder
}

/// The cereal box of issue 17: 0.19 × 0.03 × 0.26 m (width, depth, height), base at `z = 0`.
/// Its 3 cm depth is the only dimension that fits a parallel gripper of 8 cm opening.
pub fn cereal_box_builder() -> MeshBuilder {
    box_on_base_builder([0.19, 0.03, 0.26])
}

/// A domino, 0.048 × 0.024 × 0.0075 m (a thin box), base at `z = 0`.
pub fn domino_builder() -> MeshBuilder {
    box_on_base_builder([0.048, 0.024, 0.0075])
}

/// A toy block, a 4 cm cube, base at `z = 0`.
pub fn toy_block_builder() -> MeshBuilder {
    box_on_base_builder([0.04, 0.04, 0.04])
}

/// A milk carton with a gable top: a 0.07 × 0.07 × 0.19 m body and a roof rising 0.03 m to
/// a ridge along x (total height 0.22 m), base at `z = 0`. Convex, 16 triangles.
pub fn milk_carton_builder() -> MeshBuilder {
    let (h, w, eave, ridge) = (0.035, 0.035, 0.19, 0.22);
    let mut b = MeshBuilder::default();
    // Bottom corners, eave corners, ridge ends.
    let v = |b: &mut MeshBuilder, x: Real, y: Real, z: Real| b.vertex(Point3::new(x, y, z));
    let b0 = v(&mut b, -h, -w, 0.0);
    let b1 = v(&mut b, h, -w, 0.0);
    let b2 = v(&mut b, h, w, 0.0);
    let b3 = v(&mut b, -h, w, 0.0);
    let e0 = v(&mut b, -h, -w, eave);
    let e1 = v(&mut b, h, -w, eave);
    let e2 = v(&mut b, h, w, eave);
    let e3 = v(&mut b, -h, w, eave);
    let r0 = v(&mut b, -h, 0.0, ridge);
    let r1 = v(&mut b, h, 0.0, ridge);
    b.quad(b0, b3, b2, b1); // bottom
    b.quad(b0, b1, e1, e0); // -y wall
    b.quad(b2, b3, e3, e2); // +y wall
    b.quad(e0, e1, r1, r0); // -y roof
    b.quad(e2, e3, r0, r1); // +y roof
    // -x gable end: b0 e0 r0 e3 b3 (outward -x).
    b.quad(b0, e0, e3, b3);
    b.triangle(e0, r0, e3);
    // +x gable end.
    b.quad(b1, b2, e2, e1);
    b.triangle(e1, e2, r1);
    b
}

/// A densely tessellated drink can: radius [`CAN_RADIUS`], height [`CAN_HEIGHT`], 256 facets
/// around and 12 bands up the side (6656 triangles), base at `z = 0`: "a mesh with thousands
/// of triangles" whose facets are long slivers, as exported by CAD tools.
pub fn dense_can_builder() -> MeshBuilder {
    let bands = 12;
    let mut profile = vec![[0.0, 0.0]];
    profile.extend((0..=bands).map(|k| [CAN_RADIUS, CAN_HEIGHT * k as Real / bands as Real]));
    profile.push([0.0, CAN_HEIGHT]);
    revolve_builder(&profile, 256)
}

/// A bottle with a recessed (punted) base and a neck, axis z, 64 facets around: body radius
/// 3.3 cm, a foot ring 1 cm wide on which it stands (`z = 0`), a punt rising 1.2 cm inside
/// it, a shoulder from 15 to 19 cm, a neck of radius 1.3 cm up to 24.5 cm and a lip. Height
/// 0.25 m.
pub fn punted_bottle_builder() -> MeshBuilder {
    let profile = [
        [0.0, 0.012],
        [0.012, 0.009],
        [0.020, 0.003],
        [0.023, 0.0],
        [0.030, 0.0],
        [0.033, 0.004],
        [0.033, 0.15],
        [0.028, 0.17],
        [0.018, 0.185],
        [0.013, 0.195],
        [0.013, 0.24],
        [0.015, 0.242],
        [0.015, 0.25],
        [0.0, 0.25],
    ];
    revolve_builder(&profile, 64)
}

/// A polygon of the xz plane (counter-clockwise with x right and z up, so that its face at
/// `y = -depth / 2` faces −y) extruded along y from `-depth / 2` to `depth / 2`. The caps
/// are fans from vertex `apex`, which must see every edge (a convex polygon, or the reflex
/// corner of an L).
pub fn extruded_builder(polygon: &[[Real; 2]], apex: usize, depth: Real) -> MeshBuilder {
    let n = polygon.len();
    let mut b = MeshBuilder::default();
    let front: Vec<u32> = polygon
        .iter()
        .map(|&[x, z]| b.vertex(Point3::new(x, -depth / 2.0, z)))
        .collect();
    let back: Vec<u32> = polygon
        .iter()
        .map(|&[x, z]| b.vertex(Point3::new(x, depth / 2.0, z)))
        .collect();
    for k in 1..n.saturating_sub(1) {
        let (i, j) = ((apex + k) % n, (apex + k + 1) % n);
        b.triangle(front[apex % n], front[i], front[j]);
        b.triangle(back[apex % n], back[j], back[i]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        b.quad(front[i], back[i], back[j], front[j]);
    }
    b
}

/// An L-shaped block: a foot 0.12 m long and 0.03 m high and an upright 0.03 m thick and
/// 0.10 m high at its −x end, both 0.045 m deep (y); the corner of the L at the origin's −x
/// side, base at `z = 0`, centred in x and y on the foot.
pub fn l_shape_builder() -> MeshBuilder {
    let polygon = [
        [-0.06, 0.0],
        [0.06, 0.0],
        [0.06, 0.03],
        [-0.03, 0.03],
        [-0.03, 0.10],
        [-0.06, 0.10],
    ];
    extruded_builder(&polygon, 3, 0.045)
}

/// An open box (a "hollow brick"): outer size `size`, walls and floor `wall` thick, open at
/// the top, base at `z = 0`. One closed shell: outer faces, the rim, the inner walls and the
/// inner floor.
pub fn open_box_builder(size: [Real; 3], wall: Real) -> MeshBuilder {
    let [hx, hy, h] = [size[0] / 2.0, size[1] / 2.0, size[2]];
    let (ix, iy) = (hx - wall, hy - wall);
    let mut b = MeshBuilder::default();
    let rect = |b: &mut MeshBuilder, x: Real, y: Real, z: Real| -> [u32; 4] {
        [(-x, -y), (x, -y), (x, y), (-x, y)].map(|(px, py)| b.vertex(Point3::new(px, py, z)))
    };
    let ob = rect(&mut b, hx, hy, 0.0);
    let ot = rect(&mut b, hx, hy, h);
    let it = rect(&mut b, ix, iy, h);
    let ib = rect(&mut b, ix, iy, wall);
    b.quad(ob[0], ob[3], ob[2], ob[1]); // bottom, facing down
    b.quad(ib[0], ib[1], ib[2], ib[3]); // inner floor, facing up
    for i in 0..4 {
        let j = (i + 1) % 4;
        b.quad(ob[i], ob[j], ot[j], ot[i]); // outer wall
        b.quad(ot[i], ot[j], it[j], it[i]); // rim
        b.quad(it[i], it[j], ib[j], ib[i]); // inner wall, facing the cavity
    }
    b
}

/// The hollow brick of issue 17: an open box 0.06 × 0.05 × 0.04 m with 2 mm walls.
pub fn hollow_brick_builder() -> MeshBuilder {
    open_box_builder([0.06, 0.05, 0.04], 0.002)
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

/// A fruit (doubly curved): an ellipsoid 7 × 6.4 × 6 cm cut flat 6 mm above its lowest point,
/// 24 bands and 48 facets around.
pub fn fruit_builder() -> MeshBuilder {
    ellipsoid_builder([0.035, 0.032, 0.030], 0.006, 24, 48)
}

/// A rubber duck (doubly curved, two overlapping shells): a body ellipsoid 9 × 5.8 × 5 cm cut
/// flat 5 mm up, and a head sphere of radius 2 cm centred 2.5 cm forward (+x) and 5.5 cm up.
pub fn duck_builder() -> MeshBuilder {
    let mut b = ellipsoid_builder([0.045, 0.029, 0.025], 0.005, 20, 40);
    let head = ellipsoid_builder([0.02, 0.02, 0.02], 0.0, 16, 32)
        .translated(Vector3::new(0.025, 0.0, 0.035));
    b.append(&head);
    b
}

/// A "scanned" box: the shipped box object's size (0.06 × 0.04 × 0.10 m) with 16 × 16 quads
/// per face (3072 triangles), every vertex moved by up to 0.3 mm of seeded noise
/// ([`jittered`], seed 17); base near `z = 0`.
pub fn scanned_box_builder() -> MeshBuilder {
    let [x, y, z] = OBJECT_BOX_HALF_EXTENTS;
    jittered(
        subdivided_box_builder([2.0 * x, 2.0 * y, 2.0 * z], 16),
        0.0003,
        17,
    )
}

/// A table without obstacles: a top `size[0] × size[1] × 0.03` m with its upper surface at
/// `height`, centred on the z axis, and four 5 cm legs 5 cm in from the corners, standing on
/// `z = 0`.
pub fn plain_table_builder(size: [Real; 2], height: Real) -> MeshBuilder {
    let thickness = 0.03;
    let mut b = box_builder([size[0] / 2.0, size[1] / 2.0, thickness / 2.0])
        .translated(Vector3::new(0.0, 0.0, height - thickness / 2.0));
    let leg = height - thickness;
    let (lx, ly) = (size[0] / 2.0 - 0.05, size[1] / 2.0 - 0.05);
    for (sx, sy) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        b.append(
            &box_builder([0.025, 0.025, leg / 2.0]).translated(Vector3::new(
                sx * lx,
                sy * ly,
                leg / 2.0,
            )),
        );
    }
    b
}

/// A shelf standing on `z = 0`: a board `size[0] × size[1]` (x, y), 2 cm thick, with its top
/// at `height`, on two side panels 2 cm thick at its ±y ends (closed shells that touch), the board 1 cm shorter in x than the panels.
pub fn shelf_builder(size: [Real; 2], height: Real) -> MeshBuilder {
    let t = 0.02;
    // The board is 1 cm shorter in x than the panels: the shells touch, but share no vertex.
    let mut b = box_builder([size[0] / 2.0 - 0.005, size[1] / 2.0 - t, t / 2.0])
        .translated(Vector3::new(0.0, 0.0, height - t / 2.0));
    for s in [-1.0, 1.0] {
        b.append(
            &box_builder([size[0] / 2.0, t / 2.0, height / 2.0]).translated(Vector3::new(
                0.0,
                s * (size[1] / 2.0 - t / 2.0),
                height / 2.0,
            )),
        );
    }
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
    use crate::mesh::MassMethod;

    #[test]
    fn shipped_meshes_are_closed_and_outward() {
        for shipped in shipped_meshes() {
            let mesh = shipped.builder.build().expect("valid shipped mesh");
            let report = mesh.report();
            assert!(report.is_closed(), "{}: {report:?}", shipped.file_name);
            assert_eq!(report.degenerate_triangles, 0, "{}", shipped.file_name);
            let mass = mesh.mass_properties();
            assert_eq!(mass.method, MassMethod::Volume, "{}", shipped.file_name);
            assert!(!mass.inverted_winding, "{}", shipped.file_name);
            let (lo, _) = mesh.aabb();
            assert!(lo.z.abs() < 1e-12, "{}: base at z = 0", shipped.file_name);
        }
    }

    /// Every builder of the scene suite: closed, outward-wound, no degenerate triangle, base on
    /// `z = 0` (the jittered box within its noise).
    #[test]
    fn suite_builders_are_closed_and_outward() {
        let builders: Vec<(&str, MeshBuilder, Real)> = vec![
            ("cereal box", cereal_box_builder(), 0.0),
            ("domino", domino_builder(), 0.0),
            ("toy block", toy_block_builder(), 0.0),
            ("milk carton", milk_carton_builder(), 0.0),
            ("dense can", dense_can_builder(), 0.0),
            ("bottle", punted_bottle_builder(), 0.0),
            ("L", l_shape_builder(), 0.0),
            ("hollow brick", hollow_brick_builder(), 0.0),
            ("fruit", fruit_builder(), 0.0),
            ("duck", duck_builder(), 0.0),
            ("scanned box", scanned_box_builder(), 0.0003),
            ("table", plain_table_builder([0.6, 0.9], 0.7), 0.0),
            ("shelf", shelf_builder([0.2, 0.3], 0.15), 0.0),
            (
                "subdivided",
                subdivided_box_builder([0.1, 0.2, 0.3], 3),
                0.0,
            ),
        ];
        for (name, builder, noise) in builders {
            let mesh = builder.build().expect("valid");
            let report = mesh.report();
            assert!(report.is_closed(), "{name}: {report:?}");
            assert_eq!(report.degenerate_triangles, 0, "{name}");
            let mass = mesh.mass_properties();
            assert_eq!(mass.method, MassMethod::Volume, "{name}");
            assert!(!mass.inverted_winding, "{name}");
            assert!(mass.volume > 0.0, "{name}");
            let (lo, _) = mesh.aabb();
            assert!(lo.z.abs() <= noise + 1e-12, "{name}: base at z = {}", lo.z);
        }
    }

    #[test]
    fn suite_builders_have_their_volumes_and_sizes() {
        let vol = |b: MeshBuilder| b.build().expect("valid").mass_properties().volume;
        assert!((vol(cereal_box_builder()) - 0.19 * 0.03 * 0.26).abs() < 1e-12);
        let carton = 0.07 * 0.07 * 0.19 + 0.07 * 0.07 * 0.03 / 2.0;
        assert!((vol(milk_carton_builder()) - carton).abs() < 1e-12);
        let l = 0.12 * 0.03 * 0.045 + 0.03 * 0.07 * 0.045;
        assert!((vol(l_shape_builder()) - l).abs() < 1e-12);
        let brick = 0.06 * 0.05 * 0.04 - 0.056 * 0.046 * 0.038;
        assert!((vol(hollow_brick_builder()) - brick).abs() < 1e-12);
        let sub = vol(subdivided_box_builder([0.1, 0.2, 0.3], 5));
        assert!((sub - 0.006).abs() < 1e-12, "{sub}");
        // Thousands of triangles where the suite says so.
        assert_eq!(dense_can_builder().triangles.len(), 256 * 26);
        assert_eq!(scanned_box_builder().triangles.len(), 12 * 16 * 16);
        // The punt: the bottle's lowest points are a ring, its axis point is 12 mm up.
        let bottle = punted_bottle_builder().build().expect("valid");
        let (lo, hi) = bottle.aabb();
        assert!(lo.z.abs() < 1e-12 && (hi.z - 0.25).abs() < 1e-12);
        // The fruit's flat base and height.
        let (lo, hi) = fruit_builder().build().expect("valid").aabb();
        assert!((hi.z - lo.z - 0.054).abs() < 1e-9, "{}", hi.z - lo.z);
    }

    #[test]
    fn jitter_is_seeded_bounded_and_keeps_copies_together() {
        let clean = subdivided_box_builder([0.06, 0.04, 0.1], 4);
        let a = jittered(clean.clone(), 0.001, 5);
        let b = jittered(clean.clone(), 0.001, 5);
        let c = jittered(clean.clone(), 0.001, 6);
        assert_eq!(a.positions, b.positions, "same seed, same mesh");
        assert_ne!(a.positions, c.positions, "another seed, another mesh");
        for (p, q) in clean.positions.iter().zip(&a.positions) {
            assert!((p - q).amax() <= 0.001, "bounded");
            assert!(p != q, "every vertex moves");
        }
        // Copies of a corner (one per face) moved to one point: the mesh stays closed.
        assert!(a.build().expect("valid").report().is_closed());
        let mut rng = SplitMix64::new(0);
        // The reference sequence of SplitMix64 seeded with 0.
        assert_eq!(rng.next_u64(), 0xE220_A839_7B1D_CDAF);
    }

    #[test]
    fn mug_volume_is_the_body_plus_the_handle() {
        let mug = mug_builder().build().expect("valid");
        assert!(
            (1000..=3000).contains(&mug.triangle_count()),
            "{}",
            mug.triangle_count()
        );
        let m = mug.mass_properties();
        // Body: outer cylinder minus the cavity, for a 64-gon (area factor sin(2pi/n) n / 2pi).
        let k = (TAU / 64.0).sin() * 64.0 / TAU;
        let body = k
            * PI
            * (MUG_RADIUS.powi(2) * MUG_HEIGHT
                - (MUG_RADIUS - MUG_WALL).powi(2) * (MUG_HEIGHT - MUG_BOTTOM));
        // Handle: tube of radius 6 mm along a half ellipse of semi-axes 35 and 28 mm (length
        // ~ 99.9 mm by Ramanujan's perimeter / 2), 16-gon section.
        let (a, c) = (0.035, 0.028);
        let h = 3.0 * (a - c) * (a - c) / ((a + c) * (a + c));
        let length = PI * (a + c) * (1.0 + h / (10.0 + (4.0 - 3.0 * h).sqrt())) / 2.0;
        let handle = (TAU / 16.0).sin() * 16.0 / 2.0 * 0.006f64.powi(2) * length;
        assert!(
            (m.volume - body - handle).abs() < 0.03 * handle,
            "{} vs {}",
            m.volume,
            body + handle
        );
        assert!(m.center_of_mass.x > 0.0, "the handle pulls the CoG to +x");
    }

    #[test]
    fn pallet_has_its_dents_as_floors() {
        let pallet = pallet_builder().build().expect("valid");
        let mut floors: Vec<Real> = Vec::new();
        for t in 0..pallet.triangle_count() {
            let [a, b, c] = pallet.triangle_points(t);
            if pallet.triangle_normal(t).z > 0.999
                && a.z == b.z
                && b.z == c.z
                && !floors.contains(&a.z)
            {
                floors.push(a.z);
            }
        }
        floors.sort_by(Real::total_cmp);
        assert_eq!(floors, vec![0.02, 0.025, 0.028, 0.03, 0.04]);
        let [sx, sy, sz] = PALLET_SIZE;
        let dents: Real = PALLET_DENTS
            .iter()
            .map(|d| d.size[0] * d.size[1] * d.depth)
            .sum();
        let m = pallet.mass_properties();
        assert!(
            (m.volume - (sx * sy * sz - dents)).abs() < 1e-12,
            "{}",
            m.volume
        );
    }

    #[test]
    fn overlapping_dents_stay_closed() {
        let dents = [
            Dent {
                center: [0.0, 0.0],
                size: [0.2, 0.2],
                depth: 0.01,
            },
            Dent {
                center: [0.05, 0.05],
                size: [0.1, 0.06],
                depth: 0.02,
            },
            Dent {
                center: [-0.2, 0.0],
                size: [0.1, 0.1],
                depth: 0.005,
            },
        ];
        let slab = dented_slab_builder([0.5, 0.4], 0.05, &dents)
            .expect("valid")
            .build()
            .expect("valid");
        assert!(slab.report().is_closed(), "{:?}", slab.report());
        let expected = 0.5 * 0.4 * 0.05 - 0.2 * 0.2 * 0.01 - 0.1 * 0.06 * 0.01 - 0.1 * 0.1 * 0.005;
        assert!((slab.mass_properties().volume - expected).abs() < 1e-12);
        let err = dented_slab_builder(
            [0.5, 0.4],
            0.05,
            &[Dent {
                center: [0.3, 0.0],
                size: [0.1, 0.1],
                depth: 0.01,
            }],
        );
        assert!(err.is_err());
    }

    #[test]
    fn table_top_is_at_its_height() {
        let table = table_builder().build().expect("valid");
        let (lo, hi) = table.aabb();
        assert!((lo.z).abs() < 1e-12 && (hi.z - (TABLE_HEIGHT + 0.18)).abs() < 1e-12);
        assert!((hi.x - 0.45).abs() < 1e-12 && (lo.y + 0.30).abs() < 1e-12);
    }

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
