//! Seeded random meshes for the property tests.

use pickplace_geometry::math::{Point3, Real};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::shapes::MeshBuilder;

/// SplitMix64: a tiny seeded generator (same seed, same sequence).
#[derive(Debug, Clone)]
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: Real, hi: Real) -> Real {
        lo + (hi - lo) * ((self.next_u64() >> 11) as Real / (1u64 << 53) as Real)
    }
}

/// A box with every face split into an `n × n` grid, vertices moved along the face normal by
/// up to `noise` (m).
pub fn subdivided_box(half: [Real; 3], n: usize, noise: Real, rng: &mut Rng) -> TriMesh {
    let mut b = MeshBuilder::default();
    // (normal axis, sign): each face spanned by the two other axes, counter-clockwise outside.
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let (ua, va) = ((axis + 1) % 3, (axis + 2) % 3);
            let mut ids = vec![vec![0u32; n + 1]; n + 1];
            for (i, row) in ids.iter_mut().enumerate() {
                for (j, id) in row.iter_mut().enumerate() {
                    let mut p = [0.0; 3];
                    p[axis] = sign * half[axis];
                    p[ua] = half[ua] * (2.0 * i as Real / n as Real - 1.0);
                    p[va] = half[va] * (2.0 * j as Real / n as Real - 1.0);
                    let interior = i > 0 && i < n && j > 0 && j < n;
                    if interior {
                        p[axis] += rng.range(-noise, noise);
                    }
                    *id = b.vertex(Point3::new(p[0], p[1], p[2]));
                }
            }
            for i in 0..n {
                for j in 0..n {
                    let (a, bb, c, d) =
                        (ids[i][j], ids[i + 1][j], ids[i + 1][j + 1], ids[i][j + 1]);
                    if sign > 0.0 {
                        b.quad(a, bb, c, d)
                    } else {
                        b.quad(a, d, c, bb)
                    }
                }
            }
        }
    }
    b.build().expect("valid box")
}

/// A height field `z = f(x, y)` over `[0, size]²` with `n × n` cells: a few random waves plus
/// noise. Open mesh (it has a boundary).
pub fn height_field(n: usize, size: Real, amplitude: Real, rng: &mut Rng) -> TriMesh {
    let waves: Vec<(Real, Real, Real, Real)> = (0..3)
        .map(|_| {
            (
                rng.range(0.5, 4.0),
                rng.range(0.5, 4.0),
                rng.range(0.0, 6.3),
                rng.range(0.0, amplitude),
            )
        })
        .collect();
    let noise = amplitude * 0.05;
    let mut b = MeshBuilder::default();
    let mut ids = vec![vec![0u32; n + 1]; n + 1];
    for (i, row) in ids.iter_mut().enumerate() {
        for (j, id) in row.iter_mut().enumerate() {
            let (x, y) = (size * i as Real / n as Real, size * j as Real / n as Real);
            let mut z = rng.range(-noise, noise);
            for &(fx, fy, ph, a) in &waves {
                z += a * (fx * x / size * 6.3 + ph).sin() * (fy * y / size * 6.3).cos();
            }
            *id = b.vertex(Point3::new(x, y, z));
        }
    }
    for i in 0..n {
        for j in 0..n {
            b.quad(ids[i][j], ids[i + 1][j], ids[i + 1][j + 1], ids[i][j + 1]);
        }
    }
    b.build().expect("valid height field")
}
