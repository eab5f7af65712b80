//! The catalogue of test objects: everyday objects and supports made from the mesh primitives
//! of [`pickplace_geometry::shapes`], every builder deterministic (the seeded ones through
//! [`SplitMix64`]).
//!
//! - The meshes of the paper's scenes (Harada et al., §IV, Figs. 9-10: a drink can placed into
//!   the dents of a pallet, a mug placed on a table among obstacles) as builders
//!   ([`can_builder`], [`mug_builder`], [`object_box_builder`], [`pallet_builder`],
//!   [`table_builder`]); `cargo xtask gen-meshes` writes them to `meshes/` as binary STL
//!   ([`shipped_meshes`]).
//! - The objects and supports of the scene suite (issue 17, `cargo xtask suite gen`): boxes,
//!   a milk carton, a bottle, an L block, a hollow brick, a fruit, a duck, a "scanned" box
//!   ([`jittered`]), a plain table and a shelf.
//!
//! Every builder returns a [`MeshBuilder`] whose [`build`](MeshBuilder::build) gives a closed,
//! outward-wound, welded mesh with its base on `z = 0`.
//!
//! This crate is for tests, benchmarks, the demo and the xtask generators: the library crates
//! take it as a dev-dependency only, and their docs use the primitives.
#![warn(missing_docs)]

use pickplace_geometry::Error;
use pickplace_geometry::math::{Point3, Real, Vector3};
use pickplace_geometry::shapes::{
    MeshBuilder, box_builder, cylinder_builder, revolve_builder, tube_builder,
};
use std::f64::consts::PI;

mod suite;

pub use suite::*;

#[cfg(test)]
mod tests;

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
/// there, so the volume of [`MassProperties`](pickplace_geometry::mesh::MassProperties) counts that overlap
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
) -> pickplace_geometry::Result<MeshBuilder> {
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
