//! Link hulls with few vertices. A query's convex–convex test (GJK) costs one scan of a
//! hull's vertices per support point, so a link mesh of a few hundred vertices (TALOS's arm
//! links have 150–950, all on their hull) makes every state check slow. A hull with more than
//! [`MAX_HULL_VERTICES`] vertices is replaced by the hull of a subset of them, rounded by the
//! largest distance of a dropped vertex from it: the rounded shape contains the exact hull,
//! so the check stays conservative, by at most [`MAX_INFLATION`].

use parry3d_f64::math::Vector;
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::{ConvexPolyhedron, SharedShape};
use parry3d_f64::transformation::convex_hull;
use pickplace_geometry::math::Real;

/// Hulls with more vertices than this are simplified.
pub(super) const MAX_HULL_VERTICES: usize = 128;

/// The largest rounding (m) a simplified hull may have; a hull that needs more stays exact.
pub(super) const MAX_INFLATION: Real = 0.002;

/// Vertices within this distance (m) outside the subset's hull are not added to it.
const TOLERANCE: Real = 0.0005;

/// The convex hull of `points`, simplified when it has more than [`MAX_HULL_VERTICES`]
/// vertices (module doc); `None` when the points span no volume.
pub(super) fn link_hull(points: &[Vector]) -> Option<SharedShape> {
    let (hull, _) = convex_hull(points);
    if hull.len() <= MAX_HULL_VERTICES {
        return SharedShape::convex_hull(&hull);
    }
    simplified(&hull).or_else(|| SharedShape::convex_hull(&hull))
}

/// The rounded hull of a subset of the hull's vertices `hull`, or `None` when no subset of
/// [`MAX_HULL_VERTICES`] vertices is within [`MAX_INFLATION`] of every vertex.
fn simplified(hull: &[Vector]) -> Option<SharedShape> {
    // Start from the extreme vertices along the axes and the diagonals.
    let mut chosen: Vec<usize> = Vec::new();
    for d in [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, 1.0],
        [-1.0, 1.0, 1.0],
    ] {
        let d = Vector::new(d[0], d[1], d[2]);
        for sign in [1.0, -1.0] {
            let best = (0..hull.len()).max_by(|&a, &b| {
                (hull[a].dot(d) * sign)
                    .total_cmp(&(hull[b].dot(d) * sign))
                    .then(b.cmp(&a))
            })?;
            if !chosen.contains(&best) {
                chosen.push(best);
            }
        }
    }
    // Quickhull's step, bounded: each face of the subset's hull takes the vertex farthest
    // outside it, farthest first, until every vertex is within the tolerance or the subset
    // is full.
    loop {
        let points: Vec<Vector> = chosen.iter().map(|&i| hull[i]).collect();
        let (vertices, faces) = convex_hull(&points);
        if vertices.len() < 4 {
            return None;
        }
        let centre = vertices.iter().fold(Vector::ZERO, |s, &v| s + v) / vertices.len() as Real;
        let planes: Vec<(Vector, Real)> = faces
            .iter()
            .filter_map(|f| {
                let [a, b, c] = f.map(|i| vertices[i as usize]);
                let n = (b - a).cross(c - a).try_normalize()?;
                let n = if n.dot(centre - a) > 0.0 { -n } else { n };
                Some((n, n.dot(a)))
            })
            .collect();
        let mut farthest: Vec<Option<(Real, usize)>> = vec![None; planes.len()];
        for (i, p) in hull.iter().enumerate() {
            let Some((face, d)) = planes
                .iter()
                .enumerate()
                .map(|(f, (n, o))| (f, n.dot(*p) - o))
                .max_by(|a, b| a.1.total_cmp(&b.1))
            else {
                continue;
            };
            if d > TOLERANCE && farthest[face].is_none_or(|(best, _)| d > best) {
                farthest[face] = Some((d, i));
            }
        }
        let mut add: Vec<(Real, usize)> = farthest.into_iter().flatten().collect();
        add.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        add.dedup_by_key(|a| a.1);
        let room = MAX_HULL_VERTICES.saturating_sub(chosen.len());
        if add.is_empty() || room == 0 {
            break;
        }
        chosen.extend(
            add.iter()
                .take(room)
                .map(|&(_, i)| i)
                .filter(|i| !chosen.contains(i))
                .collect::<Vec<_>>(),
        );
    }
    let points: Vec<Vector> = chosen.iter().map(|&i| hull[i]).collect();
    let reduced = ConvexPolyhedron::from_convex_hull(&points)?;
    let inflation = hull
        .iter()
        .map(|&p| reduced.distance_to_local_point(p, true))
        .fold(0.0, Real::max);
    if inflation > MAX_INFLATION {
        return None;
    }
    if inflation == 0.0 {
        SharedShape::convex_hull(&points)
    } else {
        SharedShape::round_convex_hull(&points, inflation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on a sphere of radius `r` (a golden-angle spiral).
    fn sphere(n: usize, r: Real) -> Vec<Vector> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as Real + 0.5) / n as Real;
                let rho = (1.0 - z * z).sqrt();
                let phi = i as Real * 2.399_963_229_728_653;
                Vector::new(rho * phi.cos(), rho * phi.sin(), z) * r
            })
            .collect()
    }

    #[test]
    fn a_small_hull_stays_exact() {
        let cube: Vec<Vector> = (0..8)
            .map(|i| Vector::new((i & 1) as Real, (i >> 1 & 1) as Real, (i >> 2) as Real))
            .collect();
        let shape = link_hull(&cube).expect("a volume");
        assert!(shape.as_convex_polyhedron().is_some());
        assert_eq!(
            shape.as_convex_polyhedron().map(|c| c.points().len()),
            Some(8)
        );
    }

    #[test]
    fn a_dense_hull_gets_few_vertices_and_still_contains_every_vertex() {
        // 600 vertices on a 2 cm sphere: few enough of them are within 2 mm.
        let points = sphere(600, 0.02);
        let shape = link_hull(&points).expect("a volume");
        let round = shape.as_round_convex_polyhedron().expect("simplified");
        assert!(round.inner_shape.points().len() <= MAX_HULL_VERTICES);
        assert!(round.border_radius <= MAX_INFLATION);
        for p in &points {
            assert!(shape.contains_local_point(*p * (1.0 - 1e-9)), "{p:?}");
        }
    }

    #[test]
    fn a_hull_too_large_to_simplify_within_the_bound_stays_exact() {
        // A 1 m sphere of 2 000 vertices: 64 of them leave more than 2 mm out.
        let points = sphere(2000, 1.0);
        let shape = link_hull(&points).expect("a volume");
        assert!(shape.as_convex_polyhedron().is_some());
    }
}
