//! A faster support function for the link hulls. Parry's convex polyhedron finds a support
//! point by scanning every vertex; a self-collision query's GJK asks for a few dozen support
//! points, and TALOS's torso against its shoulder (341 × 128 vertices) is tested in nearly
//! every arm state. Climbing the hull's vertex graph from a vertex extreme in the direction's
//! octant visits a handful of vertices instead.
//!
//! On a convex polytope a vertex that no neighbour improves on is a global maximum of a linear
//! function (the polytope lies in the cone its edges span at that vertex), so the climb finds
//! the same support value as the scan: the queries answer as parry's own, exactly. A hull whose
//! climb disagrees with the scan on a set of test directions (a numerically degenerate hull)
//! keeps parry's scan.

use parry3d_f64::math::Vector;
use parry3d_f64::shape::{SharedShape, SupportMap};
use parry3d_f64::transformation::convex_hull;
use pickplace_geometry::math::Real;

/// A convex hull's vertices with their adjacency (the hull's triangulated edges), and the
/// border radius of a rounded hull.
#[derive(Debug, Clone)]
pub(super) struct ClimbingHull {
    points: Vec<Vector>,
    /// `neighbours[offsets[i]..offsets[i + 1]]` are the vertices joined to vertex `i`.
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// Where a climb starts: the vertex extreme along the centre direction of each cell of
    /// a cube map ([`cell`]).
    starts: Vec<u32>,
    border: Real,
}

/// Directions on which a new hull's climb is compared with the scan.
const TEST_DIRECTIONS: usize = 256;

impl ClimbingHull {
    /// The climbing hull of a convex polyhedron, rounded or not, with more than a few
    /// vertices; `None` for any other shape (parry's support function is as good), or when
    /// the climb disagrees with the scan.
    pub(super) fn of(shape: &SharedShape) -> Option<Self> {
        let (points, border) = if let Some(c) = shape.as_convex_polyhedron() {
            (c.points(), 0.0)
        } else if let Some(r) = shape.as_round_convex_polyhedron() {
            (r.inner_shape.points(), r.border_radius)
        } else {
            return None;
        };
        if points.len() < 16 {
            return None;
        }
        let (vertices, triangles) = convex_hull(points);
        if vertices.len() < 4 || vertices.len() >= u32::MAX as usize {
            return None;
        }
        let mut pairs: Vec<(u32, u32)> = Vec::with_capacity(triangles.len() * 6);
        for t in &triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                pairs.push((a, b));
                pairs.push((b, a));
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        let mut offsets = vec![0u32; vertices.len() + 1];
        for &(a, _) in &pairs {
            offsets[a as usize + 1] += 1;
        }
        for i in 0..vertices.len() {
            offsets[i + 1] += offsets[i];
        }
        let neighbours = pairs.iter().map(|&(_, b)| b).collect();
        let joined = |i: usize| offsets[i + 1] > offsets[i];
        let mut starts = vec![0u32; 6 * CELLS * CELLS];
        for (c, start) in starts.iter_mut().enumerate() {
            let d = cell_centre(c);
            *start = (0..vertices.len())
                .filter(|&i| joined(i))
                .max_by(|&a, &b| {
                    vertices[a]
                        .dot(d)
                        .total_cmp(&vertices[b].dot(d))
                        .then(b.cmp(&a))
                })? as u32;
        }
        let hull = Self {
            points: vertices,
            offsets,
            neighbours,
            starts,
            border,
        };
        hull.agrees_with_scan(points).then_some(hull)
    }

    /// Whether the climb reaches the scan's support value over `points` on the test
    /// directions (a golden-angle spiral), up to rounding.
    fn agrees_with_scan(&self, points: &[Vector]) -> bool {
        let scale = points.iter().map(|p| p.length()).fold(0.0, Real::max);
        (0..TEST_DIRECTIONS).all(|i| {
            let z = 1.0 - 2.0 * (i as Real + 0.5) / TEST_DIRECTIONS as Real;
            let rho = (1.0 - z * z).sqrt();
            let phi = i as Real * 2.399_963_229_728_653;
            let d = Vector::new(rho * phi.cos(), rho * phi.sin(), z);
            let scan = points.iter().map(|p| p.dot(d)).fold(Real::MIN, Real::max);
            let climb = self.points[self.climb(d)].dot(d);
            climb >= scan - 1e-12 * scale.max(1.0)
        })
    }

    /// The vertex of largest `dir` component, found by climbing the vertex graph.
    #[inline]
    fn climb(&self, dir: Vector) -> usize {
        let mut current = self.starts[cell(dir)] as usize;
        let mut best = self.points[current].dot(dir);
        loop {
            let from = current;
            let (lo, hi) = (self.offsets[from] as usize, self.offsets[from + 1] as usize);
            for &n in &self.neighbours[lo..hi] {
                let n = n as usize;
                let value = self.points[n].dot(dir);
                if value > best {
                    best = value;
                    current = n;
                }
            }
            if current == from {
                return current;
            }
        }
    }
}

/// Cells along each side of a cube-map face.
const CELLS: usize = 8;

/// The cube-map cell of a direction: the face of its largest coordinate (axis and sign),
/// then the other two coordinates over the largest, in `CELLS` bins each. Any cell for a
/// zero or non-finite direction (the climb is right from any start).
#[inline]
fn cell(d: Vector) -> usize {
    let a = d.abs();
    let (axis, major, u, v) = if a.x >= a.y && a.x >= a.z {
        (0, d.x, d.y, d.z)
    } else if a.y >= a.z {
        (1, d.y, d.z, d.x)
    } else {
        (2, d.z, d.x, d.y)
    };
    let face = axis * 2 + usize::from(major < 0.0);
    let scale = CELLS as Real / (2.0 * major.abs());
    let bin = |t: Real| {
        // `as` saturates (NaN gives 0): always a valid bin.
        ((t * scale + CELLS as Real / 2.0) as usize).min(CELLS - 1)
    };
    (face * CELLS + bin(u)) * CELLS + bin(v)
}

/// The centre direction of cube-map cell `c` (the inverse of [`cell`]).
fn cell_centre(c: usize) -> Vector {
    let (face, rest) = (c / (CELLS * CELLS), c % (CELLS * CELLS));
    let centre = |i: usize| (i as Real + 0.5) * 2.0 / CELLS as Real - 1.0;
    let (u, v) = (centre(rest / CELLS), centre(rest % CELLS));
    let major = if face % 2 == 0 { 1.0 } else { -1.0 };
    match face / 2 {
        0 => Vector::new(major, u, v),
        1 => Vector::new(v, major, u),
        _ => Vector::new(u, v, major),
    }
}

impl SupportMap for ClimbingHull {
    /// As parry's convex polyhedron (a scan) and its rounded shape (the inner support point
    /// toward the normalized direction, pushed out by the border radius).
    fn local_support_point(&self, dir: Vector) -> Vector {
        if self.border > 0.0 {
            self.local_support_point_toward(dir.normalize())
        } else {
            self.points[self.climb(dir)]
        }
    }

    fn local_support_point_toward(&self, dir: Vector) -> Vector {
        if self.border > 0.0 {
            self.points[self.climb(dir)] + dir * self.border
        } else {
            self.points[self.climb(dir)]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a sphere of radius `r` (a golden-angle spiral), skewed into an ellipsoid.
    fn ellipsoid(n: usize) -> Vec<Vector> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as Real + 0.5) / n as Real;
                let rho = (1.0 - z * z).sqrt();
                let phi = i as Real * 2.399_963_229_728_653;
                Vector::new(0.3 * rho * phi.cos(), 0.1 * rho * phi.sin(), 0.05 * z)
            })
            .collect()
    }

    #[test]
    fn the_climb_finds_the_scans_support_point() {
        let points = ellipsoid(300);
        let shape = SharedShape::convex_hull(&points).expect("a volume");
        let hull = ClimbingHull::of(&shape).expect("a climbing hull");
        let parry = shape.as_convex_polyhedron().expect("a polyhedron");
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let d = Vector::new(next(), next(), next());
            let a = hull.local_support_point(d).dot(d);
            let b = parry.local_support_point(d).dot(d);
            assert!((a - b).abs() <= 1e-15, "{d:?}: {a} vs {b}");
        }
    }

    #[test]
    fn a_rounded_hull_adds_its_border_as_parry_does() {
        let points = ellipsoid(200);
        let shape = SharedShape::round_convex_hull(&points, 0.002).expect("a volume");
        let hull = ClimbingHull::of(&shape).expect("a climbing hull");
        let round = shape.as_round_convex_polyhedron().expect("rounded");
        for d in [
            Vector::new(1.0, 2.0, -3.0),
            Vector::new(-0.1, 0.0, 0.0),
            Vector::new(0.3, -0.7, 0.2),
        ] {
            let a = hull.local_support_point(d);
            let b = round.local_support_point(d);
            assert!((a - b).length() <= 1e-15, "{d:?}: {a:?} vs {b:?}");
        }
    }

    #[test]
    fn a_cell_centre_falls_in_its_cell() {
        for c in 0..6 * CELLS * CELLS {
            assert_eq!(cell(cell_centre(c)), c);
        }
        assert!(cell(Vector::ZERO) < 6 * CELLS * CELLS);
        assert!(cell(Vector::splat(Real::NAN)) < 6 * CELLS * CELLS);
    }

    #[test]
    fn small_hulls_and_other_shapes_keep_parrys_support() {
        assert!(ClimbingHull::of(&SharedShape::cuboid(0.1, 0.2, 0.3)).is_none());
        let cube: Vec<Vector> = (0..8)
            .map(|i| Vector::new((i & 1) as Real, (i >> 1 & 1) as Real, (i >> 2) as Real))
            .collect();
        let shape = SharedShape::convex_hull(&cube).expect("a volume");
        assert!(ClimbingHull::of(&shape).is_none());
    }
}
