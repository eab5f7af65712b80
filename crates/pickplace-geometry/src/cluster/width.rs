//! The thinnest slab of a point set: candidate directions for a cluster's contact plane
//! (§III-A: the vertices of a cluster must fit between two parallel planes `h_max` apart).
//!
//! The width of a point set along a unit direction `d` is `max d·p − min d·p`. Its minimum over
//! all directions is attained where two parallel planes touch the convex hull in one of two
//! ways (Houle and Toussaint's antipodal pairs): a hull face and a vertex (the direction is the
//! face's normal), or two hull edges (the direction is perpendicular to both, and lies in the
//! normal cone of one edge while its opposite lies in the other's). [`face_directions`] and
//! [`edge_pair_directions`] list both kinds, so the least width among them is the minimum width of the set, exactly
//! (up to the hull's tolerance, see [`super::hull`]).

use super::hull::Hull;
use crate::math::{Real, Vector3};

/// `(min, max)` of `d·p` over `points`.
pub(crate) fn extent_along<'a>(
    points: impl IntoIterator<Item = &'a Vector3>,
    d: &Vector3,
) -> (Real, Real) {
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for p in points {
        let x = d.dot(p);
        lo = lo.min(x);
        hi = hi.max(x);
    }
    (lo, hi)
}

/// An edge of the hull, ready for the edge-edge test.
struct Edge {
    /// One end point.
    a: Vector3,
    /// Unit direction.
    t: Vector3,
    /// Outward normals of the two faces on either side.
    n1: Vector3,
    n2: Vector3,
    /// `n1 × n2` (along `±t`); zero for an edge between coplanar faces.
    c: Vector3,
    /// The middle of the arc from `n1` to `n2` on the unit sphere (the edge's normal cone),
    /// and the cosine of its half length: a quick test of whether two cones can meet.
    mid: Vector3,
    half: Real,
}

impl Edge {
    /// Whether unit `d` (perpendicular to the edge) lies in the edge's normal cone, i.e. a
    /// plane with outer normal `d` through the edge supports the hull: `d = α n1 + β n2`
    /// with `α, β ≥ 0`.
    fn supports(&self, d: &Vector3) -> bool {
        let tol = -1e-12 * self.c.norm_squared();
        d.cross(&self.n2).dot(&self.c) >= tol && self.n1.cross(d).dot(&self.c) >= tol
    }
}

/// Every face normal of `hull` (the hull of `points`) with the width of the hull's vertices
/// along it: the face-vertex antipodal pairs.
///
/// # Performance
/// `O(F·V)` for `F` faces and `V` vertices of the hull.
pub(crate) fn face_directions(points: &[Vector3], hull: &Hull) -> Vec<(Vector3, Real)> {
    let vertices: Vec<Vector3> = hull
        .vertices()
        .iter()
        .map(|&v| points[v as usize])
        .collect();
    hull.faces
        .iter()
        .zip(&hull.normals)
        .map(|(tri, n)| {
            let top = n.dot(&points[tri[0] as usize]);
            let (lo, _) = extent_along(&vertices, n);
            (*n, top - lo)
        })
        .collect()
}

/// Every direction perpendicular to two edges of `hull` (the hull of `points`) that support
/// parallel planes on opposite sides, with the hull's width along it: the edge-edge antipodal
/// pairs. Each direction is the outward normal at the first edge.
///
/// # Performance
/// `O(E²)` for `E` edges, a dot product for most pairs (their normal cones are far apart).
pub(crate) fn edge_pair_directions(points: &[Vector3], hull: &Hull) -> Vec<(Vector3, Real)> {
    let edges: Vec<Edge> = hull
        .edges()
        .into_iter()
        .filter_map(|(a, b, f, g)| {
            let (pa, pb) = (points[a as usize], points[b as usize]);
            let t = (pb - pa).try_normalize(0.0)?;
            let (n1, n2) = (hull.normals[f as usize], hull.normals[g as usize]);
            let c = n1.cross(&n2);
            // Between coplanar faces the cone is the face normal alone: a face candidate.
            if c.norm_squared() <= 1e-20 {
                return None;
            }
            let mid = (n1 + n2).try_normalize(1e-12)?;
            Some(Edge {
                a: pa,
                t,
                n1,
                n2,
                c,
                mid,
                half: mid.dot(&n1),
            })
        })
        .collect();
    let mut out = Vec::new();
    for (i, e) in edges.iter().enumerate() {
        for f in &edges[i + 1..] {
            // The cones (arcs of half angles acos(half)) can only meet with opposite
            // orientation when -mid_f is within the sum of the half angles of mid_e.
            let cos_sum = e.half * f.half
                - (1.0 - e.half * e.half).max(0.0).sqrt() * (1.0 - f.half * f.half).max(0.0).sqrt();
            if -e.mid.dot(&f.mid) < cos_sum - 1e-9 {
                continue;
            }
            let Some(d) = e.t.cross(&f.t).try_normalize(1e-9) else {
                continue;
            };
            let d = if e.supports(&d) {
                d
            } else if e.supports(&-d) {
                -d
            } else {
                continue;
            };
            if f.supports(&-d) {
                out.push((d, d.dot(&(e.a - f.a))));
            }
        }
    }
    out
}

/// The candidate directions of the thinnest slab of `points`, whose convex hull is `hull`:
/// [`face_directions`] and [`edge_pair_directions`], each with the width of the hull's
/// vertices along it; the least of these widths is the minimum width of the points.
#[cfg(test)]
pub(crate) fn critical_directions(points: &[Vector3], hull: &Hull) -> Vec<(Vector3, Real)> {
    let mut out = face_directions(points, hull);
    out.extend(edge_pair_directions(points, hull));
    out
}

/// The least width of `points` over [`critical_directions`] and its direction; `None` when
/// the points have no proper hull (fewer than four, or flat: width 0 along their plane).
#[cfg(test)]
pub(crate) fn min_width(points: &[Vector3]) -> Option<(Vector3, Real)> {
    let hull = super::hull::convex_hull(points)?;
    critical_directions(points, &hull)
        .into_iter()
        .min_by(|a, b| a.1.total_cmp(&b.1))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lcg(state: &mut u64) -> Real {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as Real / (1u64 << 53) as Real - 0.5
    }

    #[test]
    fn a_regular_tetrahedron_is_thinnest_across_opposite_edges() {
        // Edge length 2√2: the height over a face is 4/√3 ≈ 2.31, the distance between two
        // opposite edges 2, the least width.
        let pts = [
            Vector3::new(1.0, 1.0, 1.0),
            Vector3::new(1.0, -1.0, -1.0),
            Vector3::new(-1.0, 1.0, -1.0),
            Vector3::new(-1.0, -1.0, 1.0),
        ];
        let (d, w) = min_width(&pts).expect("a hull");
        assert!((w - 2.0).abs() < 1e-12, "{w}");
        let (lo, hi) = extent_along(&pts, &d);
        assert!((hi - lo - w).abs() < 1e-12);
        // Faces alone would give the height 4/√3 ≈ 2.31.
        let hull = super::super::hull::convex_hull(&pts).expect("a hull");
        let faces = hull.normals.iter().map(|n| {
            let (lo, hi) = extent_along(&pts, n);
            hi - lo
        });
        assert!(faces.fold(Real::INFINITY, Real::min) > 2.3);
    }

    #[test]
    fn no_sampled_direction_is_thinner_than_the_minimum() {
        let mut s = 5;
        for case in 0..40 {
            let n = 5 + case;
            let pts: Vec<Vector3> = (0..n)
                .map(|_| Vector3::new(lcg(&mut s), lcg(&mut s) * 0.6, lcg(&mut s) * 0.2))
                .collect();
            let (d, w) = min_width(&pts).expect("a hull");
            let (lo, hi) = extent_along(&pts, &d);
            assert!((hi - lo - w).abs() < 1e-12, "case {case}");
            // A dense sample of the sphere finds nothing thinner.
            for i in 0..4000 {
                let z = 1.0 - (i as Real + 0.5) / 2000.0;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let a = i as Real * 2.399_963_229_728_653;
                let dir = Vector3::new(r * a.cos(), r * a.sin(), z);
                let (lo, hi) = extent_along(&pts, &dir);
                assert!(hi - lo >= w - 1e-12, "case {case}: {} < {w}", hi - lo);
            }
        }
    }
}
