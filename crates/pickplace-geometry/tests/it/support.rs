//! Seeded random meshes for the property tests.

use pickplace_geometry::math::{Point3, Real};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::shapes::MeshBuilder;
use pickplace_objects::SplitMix64;

/// The workspace's SplitMix64 with a uniform range (same seed, same sequence).
#[derive(Debug, Clone)]
pub struct Rng(SplitMix64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(SplitMix64::new(seed))
    }

    pub fn next_u64(&mut self) -> u64 {
        self.0.next_u64()
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

/// A UV ellipsoid with semi-axes `radii`, `rings` latitude bands and `segments` longitudes,
/// vertices moved radially by up to `noise` (m, poles excepted): a fruit, a duck's body, a
/// scanned-looking blob. Closed, outward wound.
pub fn ellipsoid(
    radii: [Real; 3],
    rings: usize,
    segments: usize,
    noise: Real,
    rng: &mut Rng,
) -> TriMesh {
    ellipsoid_builder(radii, rings, segments, noise, rng)
        .build()
        .expect("valid ellipsoid")
}

/// The builder of [`ellipsoid`].
pub fn ellipsoid_builder(
    radii: [Real; 3],
    rings: usize,
    segments: usize,
    noise: Real,
    rng: &mut Rng,
) -> MeshBuilder {
    use std::f64::consts::{PI, TAU};
    let mut b = MeshBuilder::default();
    let south = b.vertex(Point3::new(0.0, 0.0, -radii[2]));
    let mut bands = Vec::new();
    for i in 1..rings {
        let theta = PI * i as Real / rings as Real;
        let band: Vec<u32> = (0..segments)
            .map(|j| {
                let phi = TAU * j as Real / segments as Real;
                let s = 1.0 + rng.range(-noise, noise) / radii[0].min(radii[1]).min(radii[2]);
                b.vertex(Point3::new(
                    s * radii[0] * theta.sin() * phi.cos(),
                    s * radii[1] * theta.sin() * phi.sin(),
                    -s * radii[2] * theta.cos(),
                ))
            })
            .collect();
        bands.push(band);
    }
    let north = b.vertex(Point3::new(0.0, 0.0, radii[2]));
    for j in 0..segments {
        let k = (j + 1) % segments;
        b.triangle(south, bands[0][k], bands[0][j]);
        for w in bands.windows(2) {
            b.quad(w[0][j], w[0][k], w[1][k], w[1][j]);
        }
        let last = &bands[bands.len() - 1];
        b.triangle(last[j], last[k], north);
    }
    b
}

/// A closed cylinder (axis z, base at 0) with `rings` bands along its height, vertices of the
/// side moved radially by up to `noise` (m).
pub fn noisy_cylinder(
    radius: Real,
    height: Real,
    segments: usize,
    rings: usize,
    noise: Real,
    rng: &mut Rng,
) -> TriMesh {
    let mut b = MeshBuilder::default();
    let mut bands = Vec::new();
    for i in 0..=rings {
        let z = height * i as Real / rings as Real;
        let band: Vec<u32> = (0..segments)
            .map(|j| {
                let a = std::f64::consts::TAU * j as Real / segments as Real;
                let r = radius + rng.range(-noise, noise);
                b.vertex(Point3::new(r * a.cos(), r * a.sin(), z))
            })
            .collect();
        bands.push(band);
    }
    let bottom = b.vertex(Point3::new(0.0, 0.0, 0.0));
    let top = b.vertex(Point3::new(0.0, 0.0, height));
    for j in 0..segments {
        let k = (j + 1) % segments;
        for w in bands.windows(2) {
            b.quad(w[0][j], w[0][k], w[1][k], w[1][j]);
        }
        b.triangle(bottom, bands[0][k], bands[0][j]);
        b.triangle(bands[rings][j], bands[rings][k], top);
    }
    b.build().expect("valid cylinder")
}
