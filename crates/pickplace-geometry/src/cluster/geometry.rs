//! Per-cluster geometry: contact plane, 2D frame, boundaries, hull, bounding rectangle.

use super::Cluster;
use super::grow::Engine;
use crate::math::{Point2, Point3, Real, Vector3};
use crate::polygon::{self, Polygon, Rect2};

/// A right-handed 2D frame on a plane: `u × v = normal`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PlaneFrame {
    /// Origin, on the plane (m).
    pub origin: Point3,
    /// First in-plane axis (unit).
    pub u: Vector3,
    /// Second in-plane axis (unit).
    pub v: Vector3,
}

/// Two unit vectors completing the unit `normal` to a right-handed orthonormal frame
/// (`u × v = normal`): `u` is the normal crossed with the world axis least aligned with it,
/// so the frame is deterministic.
pub(crate) fn tangent_pair(normal: &Vector3) -> (Vector3, Vector3) {
    let a = normal.abs();
    let e = if a.x <= a.y && a.x <= a.z {
        Vector3::x()
    } else if a.y <= a.z {
        Vector3::y()
    } else {
        Vector3::z()
    };
    let u = normal.cross(&e).normalize();
    (u, normal.cross(&u))
}

impl PlaneFrame {
    /// A frame on the plane through `origin` with unit normal `normal`. The first axis is the
    /// normal crossed with the world axis least aligned with it, so frames are deterministic.
    pub fn new(origin: Point3, normal: &Vector3) -> Self {
        let (u, v) = tangent_pair(normal);
        Self { origin, u, v }
    }

    /// The plane's unit normal `u × v`.
    pub fn normal(&self) -> Vector3 {
        self.u.cross(&self.v)
    }

    /// Orthogonal projection of a 3D point into the frame.
    pub fn to_2d(&self, p: &Point3) -> Point2 {
        let d = p - self.origin;
        Point2::new(d.dot(&self.u), d.dot(&self.v))
    }

    /// The 3D point of the plane at frame coordinates `q`.
    pub fn to_3d(&self, q: &Point2) -> Point3 {
        self.origin + self.u * q.x + self.v * q.y
    }
}

/// Builds the public [`Cluster`] of engine cluster `old` with id `id`.
pub(super) fn finish_cluster(engine: &Engine<'_>, old: u32, id: u32) -> Cluster {
    let w = &engine.clusters[old as usize];
    let mesh = engine.mesh;
    let n = w.normal;
    let (mut lo, mut hi) = (Real::INFINITY, Real::NEG_INFINITY);
    for &t in &w.triangles {
        for &v in &mesh.triangles()[t as usize] {
            let d = n.dot(&engine.points[v as usize]);
            lo = lo.min(d);
            hi = hi.max(d);
        }
    }
    let centroid_rel = w.centroid;
    let point_rel = centroid_rel + n * (hi - n.dot(&centroid_rel));
    let centroid = engine.origin + centroid_rel;
    let point = engine.origin + point_rel;
    let frame = PlaneFrame::new(point, &n);
    let loops = boundary_loops(engine, old, &w.triangles);
    let mut rings: Vec<Vec<Point2>> = loops
        .iter()
        .map(|l| {
            l.iter()
                .map(|&v| frame.to_2d(&mesh.vertices()[v as usize]))
                .collect::<Vec<_>>()
        })
        .filter(|r: &Vec<Point2>| r.len() >= 3)
        .collect();
    // The loop enclosing the largest area is the outer boundary; the others are holes.
    let outer_index = (0..rings.len())
        .max_by(|&a, &b| {
            polygon::signed_area(&rings[a])
                .abs()
                .total_cmp(&polygon::signed_area(&rings[b]).abs())
                .then(b.cmp(&a))
        })
        .unwrap_or(0);
    let mut region = Polygon::default();
    for (i, mut r) in rings.drain(..).enumerate() {
        let ccw = polygon::signed_area(&r) > 0.0;
        if i == outer_index {
            if !ccw {
                r.reverse();
            }
            region.outer = r;
        } else {
            if ccw {
                r.reverse();
            }
            region.holes.push(r);
        }
    }
    // A closed cluster (no boundary) cannot occur under the facet-angle limit; fall back to
    // the projected vertices for the hull all the same.
    let hull_input: Vec<Point2> = if region.outer.is_empty() {
        w.triangles
            .iter()
            .flat_map(|&t| mesh.triangles()[t as usize])
            .map(|v| frame.to_2d(&mesh.vertices()[v as usize]))
            .collect()
    } else {
        // Holes lie inside the outer boundary on a consistent mesh; on a folded triangle soup
        // one may stick out, and the hull (hence the rectangle) still covers it.
        region.points().copied().collect()
    };
    let hull = polygon::convex_hull(&hull_input);
    let bounding_rect = polygon::min_area_rect(&hull).unwrap_or(Rect2 {
        center: Point2::origin(),
        axis: crate::math::Vector2::x(),
        half_extents: crate::math::Vector2::zeros(),
    });
    Cluster {
        id,
        triangles: w.triangles.clone(),
        normal: n,
        centroid,
        point,
        h: hi - lo,
        area: w.moments.area,
        frame,
        region,
        hull,
        bounding_rect,
    }
}

/// Boundary loops of a cluster as vertex-index cycles, following the triangles' winding
/// (counter-clockwise seen from outside for the outer loop). A directed edge `a → b` of a
/// cluster triangle is on the boundary when no triangle of the same cluster has the edge
/// `b → a`. Loops are chained from the smallest unused edge; at a vertex with several
/// outgoing boundary edges the smallest unused one is taken.
fn boundary_loops(engine: &Engine<'_>, cluster: u32, triangles: &[u32]) -> Vec<Vec<u32>> {
    let mesh = engine.mesh;
    let tris = mesh.triangles();
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for &t in triangles {
        let tri = tris[t as usize];
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let twin = mesh.adjacency().neighbours(t as usize).iter().any(|&o| {
                engine.cluster_of[o as usize] == cluster && {
                    let ot = tris[o as usize];
                    (0..3).any(|j| ot[j] == b && ot[(j + 1) % 3] == a)
                }
            });
            if !twin {
                edges.push((a, b));
            }
        }
    }
    edges.sort_unstable();
    let mut used = vec![false; edges.len()];
    let mut loops = Vec::new();
    for start in 0..edges.len() {
        if used[start] {
            continue;
        }
        used[start] = true;
        let (first, mut cur) = edges[start];
        let mut ring = vec![first];
        while cur != first {
            ring.push(cur);
            let from = edges.partition_point(|e| e.0 < cur);
            let next = (from..edges.len())
                .take_while(|&i| edges[i].0 == cur)
                .find(|&i| !used[i]);
            match next {
                Some(i) => {
                    used[i] = true;
                    cur = edges[i].1;
                }
                // An open chain (inconsistent winding): keep what was found.
                None => break,
            }
        }
        loops.push(ring);
    }
    loops
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_is_right_handed_and_round_trips() {
        let n = Vector3::new(0.3, -0.5, 0.8).normalize();
        let f = PlaneFrame::new(Point3::new(1.0, 2.0, 3.0), &n);
        assert!((f.normal() - n).norm() < 1e-12);
        let q = Point2::new(0.25, -0.75);
        assert!((f.to_2d(&f.to_3d(&q)) - q).norm() < 1e-12);
    }
}
