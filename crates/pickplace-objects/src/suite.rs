//! Objects and environment parts of the scene suite (issue 17, `cargo xtask suite gen`).
//!
//! The paper's method (Harada et al., §III: clustering into planar contact regions, stable
//! placements by Algorithm 2, parallel-gripper grasps on opposite clusters) is meant for
//! everyday objects; these builders make the kinds of objects and supports it meets on a real
//! table. Every builder is deterministic (the seeded ones through [`SplitMix64`]).

use crate::{CAN_HEIGHT, CAN_RADIUS, OBJECT_BOX_HALF_EXTENTS};
use pickplace_geometry::math::{Point3, Real, Vector3};
use pickplace_geometry::shapes::{MeshBuilder, box_builder, ellipsoid_builder, revolve_builder};

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
