//! Convex hull of a 3D point set, for the minimum-width plane of a cluster (§III-A: a cluster is
//! a set of triangles that fits in a slab of thickness `h_max`; the thinnest slab of a point set
//! is set by its convex hull, see [`super::width`]).
//!
//! Incremental construction in the manner of quickhull: a first tetrahedron from extreme points;
//! every other point is listed outside one face; repeatedly the farthest point outside a face
//! is added, the faces it sees (found by a walk over face neighbours) are removed and the
//! horizon is joined to it. Points within a tolerance of a face count as inside. A point whose
//! visible region does not end in a single horizon loop (rounding on nearly coplanar faces) is
//! left out; the hull is then a little too small there. The callers only take *directions* from
//! the hull and measure every width on the full point set, so such a point can cost a candidate
//! direction, never a wrong width. Deterministic: no randomness, no hash-map iteration.

use crate::math::{Real, Vector3};
use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

/// A hasher for edge keys (two `u32`s): a multiply-xor mix, much cheaper than SipHash. Only
/// looked up, never iterated, so the order it gives does not matter.
#[derive(Debug, Default)]
struct EdgeHasher(u64);

impl Hasher for EdgeHasher {
    fn finish(&self) -> u64 {
        self.0
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }

    fn write_u32(&mut self, value: u32) {
        self.write_u64(u64::from(value));
    }

    fn write_u64(&mut self, value: u64) {
        self.0 = (self.0.rotate_left(26) ^ value).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// Directed edge → face.
type EdgeMap = HashMap<(u32, u32), u32, BuildHasherDefault<EdgeHasher>>;

/// A convex hull: triangles of indices into the input points, counter-clockwise seen from
/// outside, with their outward unit normals.
#[derive(Debug, Clone)]
pub(crate) struct Hull {
    /// The triangles (coplanar facets come as several triangles).
    pub faces: Vec<[u32; 3]>,
    /// Outward unit normal of each face.
    pub normals: Vec<Vector3>,
    /// Whether every input point is inside the hull (up to the tolerance): false when a
    /// point was left out (see the module documentation).
    pub complete: bool,
}

impl Hull {
    /// The input indices of the hull's vertices, increasing.
    pub fn vertices(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self.faces.iter().flatten().copied().collect();
        v.sort_unstable();
        v.dedup();
        v
    }

    /// Every edge once: its end points `(a, b)` with `a < b` and the faces on either side
    /// (the face holding the directed edge `a → b` first).
    pub fn edges(&self) -> Vec<(u32, u32, u32, u32)> {
        let mut directed: Vec<(u32, u32, u32)> = Vec::with_capacity(self.faces.len() * 3);
        for (f, tri) in self.faces.iter().enumerate() {
            for k in 0..3 {
                directed.push((tri[k], tri[(k + 1) % 3], f as u32));
            }
        }
        directed.sort_unstable();
        let find = |a: u32, b: u32| {
            directed
                .binary_search_by(|e| (e.0, e.1).cmp(&(a, b)))
                .ok()
                .map(|i| directed[i].2)
        };
        directed
            .iter()
            .filter(|e| e.0 < e.1)
            .filter_map(|&(a, b, f)| find(b, a).map(|g| (a, b, f, g)))
            .collect()
    }
}

/// One face under construction.
struct Face {
    v: [u32; 3],
    normal: Vector3,
    offset: Real,
    alive: bool,
    /// Points outside this face and assigned to it.
    outside: Vec<u32>,
}

/// The convex hull of `points`; `None` when they are fewer than four, or all (nearly) on one
/// plane or line, or not finite.
pub(crate) fn convex_hull(points: &[Vector3]) -> Option<Hull> {
    if points.len() < 4 || points.iter().any(|p| !p.iter().all(|c| c.is_finite())) {
        return None;
    }
    let (mut lo, mut hi) = (points[0], points[0]);
    for p in points {
        lo = lo.inf(p);
        hi = hi.sup(p);
    }
    let diag = (hi - lo).norm();
    if diag <= 0.0 {
        return None;
    }
    // Points closer than this to a face's plane are on it.
    let eps = 1e-13 * diag;
    let [i0, i1, i2, i3] = first_tetrahedron(points, diag)?;
    let mut faces: Vec<Face> = Vec::new();
    let mut edge_face = EdgeMap::default();
    let inner =
        (points[i0 as usize] + points[i1 as usize] + points[i2 as usize] + points[i3 as usize])
            / 4.0;
    for [a, b, c] in [[i0, i1, i2], [i0, i1, i3], [i0, i2, i3], [i1, i2, i3]] {
        let (pa, pb, pc) = (points[a as usize], points[b as usize], points[c as usize]);
        let n = (pb - pa).cross(&(pc - pa)).try_normalize(0.0)?;
        let tri = if n.dot(&(inner - pa)) > 0.0 {
            [a, c, b]
        } else {
            [a, b, c]
        };
        add_face(points, &mut faces, &mut edge_face, tri)?;
    }
    let first = [i0, i1, i2, i3];
    for (i, p) in points.iter().enumerate() {
        if first.contains(&(i as u32)) {
            continue;
        }
        if let Some(f) = faces.iter().position(|f| f.normal.dot(p) - f.offset > eps) {
            faces[f].outside.push(i as u32);
        }
    }
    let mut next_face = 0;
    let mut complete = true;
    while next_face < faces.len() {
        if !faces[next_face].alive || faces[next_face].outside.is_empty() {
            next_face += 1;
            continue;
        }
        let start = next_face as u32;
        // The farthest point outside the face (ties by index).
        let face = &faces[next_face];
        let Some((slot, &eye)) = face.outside.iter().enumerate().max_by(|a, b| {
            let da = face.normal.dot(&points[*a.1 as usize]);
            let db = face.normal.dot(&points[*b.1 as usize]);
            da.total_cmp(&db).then(b.1.cmp(a.1))
        }) else {
            next_face += 1;
            continue;
        };
        faces[next_face].outside.swap_remove(slot);
        let pe = points[eye as usize];
        let visible = visible_faces(&faces, &edge_face, start, &pe, eps);
        let Some(horizon) = horizon_loop(&faces, &edge_face, &visible) else {
            complete = false;
            continue;
        };
        // The new faces must be proper triangles; otherwise the eye is left out.
        if horizon.iter().any(|&(a, b)| {
            (points[b as usize] - points[a as usize])
                .cross(&(pe - points[a as usize]))
                .try_normalize(0.0)
                .is_none()
        }) {
            complete = false;
            continue;
        }
        let mut orphans = Vec::new();
        for &f in &visible {
            let face = &mut faces[f as usize];
            face.alive = false;
            orphans.append(&mut face.outside);
            let v = face.v;
            for k in 0..3 {
                edge_face.remove(&(v[k], v[(k + 1) % 3]));
            }
        }
        let new_from = faces.len();
        for &(a, b) in &horizon {
            add_face(points, &mut faces, &mut edge_face, [a, b, eye])?;
        }
        for q in orphans {
            let p = &points[q as usize];
            if let Some(f) =
                (new_from..faces.len()).find(|&f| faces[f].normal.dot(p) - faces[f].offset > eps)
            {
                faces[f].outside.push(q);
            }
        }
        // Earlier faces may have gained nothing, but the new ones are after `next_face`.
    }
    let alive: Vec<&Face> = faces.iter().filter(|f| f.alive).collect();
    Some(Hull {
        faces: alive.iter().map(|f| f.v).collect(),
        normals: alive.iter().map(|f| f.normal).collect(),
        complete,
    })
}

/// Four points spanning a proper tetrahedron: the lowest in x (ties by index), the farthest
/// from it, the farthest from their line, the farthest from their plane.
fn first_tetrahedron(points: &[Vector3], diag: Real) -> Option<[u32; 4]> {
    let argmax = |key: &dyn Fn(&Vector3) -> Real| -> (u32, Real) {
        let mut best = (0u32, Real::NEG_INFINITY);
        for (i, p) in points.iter().enumerate() {
            let k = key(p);
            if k > best.1 {
                best = (i as u32, k);
            }
        }
        best
    };
    let (i0, _) = argmax(&|p| -p.x);
    let p0 = points[i0 as usize];
    let (i1, d1) = argmax(&|p| (p - p0).norm());
    let p1 = points[i1 as usize];
    let axis = (p1 - p0) / d1;
    let (i2, d2) = argmax(&|p| {
        let r = p - p0;
        (r - axis * r.dot(&axis)).norm()
    });
    let tiny = 1e-9 * diag;
    if d1 <= tiny || d2 <= tiny {
        return None;
    }
    let normal = axis.cross(&(points[i2 as usize] - p0)).try_normalize(0.0)?;
    let (i3, d3) = argmax(&|p| normal.dot(&(p - p0)).abs());
    (d3 > tiny).then_some([i0, i1, i2, i3])
}

/// Appends the face `v` (counter-clockwise seen from outside) and registers its edges.
fn add_face(
    points: &[Vector3],
    faces: &mut Vec<Face>,
    edge_face: &mut EdgeMap,
    v: [u32; 3],
) -> Option<()> {
    let [a, b, c] = v.map(|i| points[i as usize]);
    let normal = (b - a).cross(&(c - a)).try_normalize(0.0)?;
    let id = faces.len() as u32;
    for k in 0..3 {
        edge_face.insert((v[k], v[(k + 1) % 3]), id);
    }
    faces.push(Face {
        v,
        normal,
        offset: normal.dot(&a),
        alive: true,
        outside: Vec::new(),
    });
    Some(())
}

/// The faces `eye` sees, found by a walk over neighbours from `start` (which it sees).
fn visible_faces(
    faces: &[Face],
    edge_face: &EdgeMap,
    start: u32,
    eye: &Vector3,
    eps: Real,
) -> Vec<u32> {
    let mut visible = vec![start];
    let mut i = 0;
    while i < visible.len() {
        let v = faces[visible[i] as usize].v;
        i += 1;
        for k in 0..3 {
            let Some(&g) = edge_face.get(&(v[(k + 1) % 3], v[k])) else {
                continue;
            };
            let face = &faces[g as usize];
            if face.alive && !visible.contains(&g) && face.normal.dot(eye) - face.offset > eps {
                visible.push(g);
            }
        }
    }
    visible
}

/// The horizon of a set of visible faces as one loop of directed edges `(a, b)` (each the
/// edge of a visible face whose other side is not visible), in order; `None` when the
/// boundary is not a single simple loop.
fn horizon_loop(faces: &[Face], edge_face: &EdgeMap, visible: &[u32]) -> Option<Vec<(u32, u32)>> {
    let mut edges: Vec<(u32, u32)> = Vec::new();
    for &f in visible {
        let v = faces[f as usize].v;
        for k in 0..3 {
            let (a, b) = (v[k], v[(k + 1) % 3]);
            let other = edge_face.get(&(b, a))?;
            if !visible.contains(other) {
                edges.push((a, b));
            }
        }
    }
    edges.sort_unstable();
    if edges.len() < 3 || edges.windows(2).any(|w| w[0].0 == w[1].0) {
        return None;
    }
    let mut ordered = Vec::with_capacity(edges.len());
    let mut at = edges[0];
    loop {
        ordered.push(at);
        if ordered.len() > edges.len() {
            return None;
        }
        let i = edges.binary_search_by(|e| e.0.cmp(&at.1)).ok()?;
        at = edges[i];
        if at == edges[0] {
            break;
        }
    }
    (ordered.len() == edges.len()).then_some(ordered)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn volume(points: &[Vector3], hull: &Hull) -> Real {
        hull.faces
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| points[i as usize]);
                a.dot(&b.cross(&c)) / 6.0
            })
            .sum()
    }

    fn lcg(state: &mut u64) -> Real {
        *state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (*state >> 11) as Real / (1u64 << 53) as Real - 0.5
    }

    #[test]
    fn a_cube_with_inner_points_has_the_cube_as_hull() {
        let mut pts: Vec<Vector3> = (0..8)
            .map(|i| {
                Vector3::new(
                    (i & 1) as Real,
                    ((i >> 1) & 1) as Real,
                    ((i >> 2) & 1) as Real,
                )
            })
            .collect();
        let mut s = 3;
        for _ in 0..200 {
            pts.push(Vector3::new(
                lcg(&mut s) + 0.5,
                lcg(&mut s) + 0.5,
                lcg(&mut s) + 0.5,
            ));
        }
        let hull = convex_hull(&pts).expect("a hull");
        assert_eq!(hull.vertices(), (0..8).collect::<Vec<u32>>());
        assert!((volume(&pts, &hull) - 1.0).abs() < 1e-12);
        assert_eq!(hull.edges().len() * 2, hull.faces.len() * 3);
    }

    #[test]
    fn every_point_is_inside_and_agrees_with_parry() {
        let mut s = 11;
        for case in 0..60 {
            let n = 4 + case * 7;
            // A thin noisy slab, as a cluster looks, or a ball.
            let flat = if case % 2 == 0 { 0.01 } else { 1.0 };
            let pts: Vec<Vector3> = (0..n)
                .map(|_| Vector3::new(lcg(&mut s), lcg(&mut s), lcg(&mut s) * flat))
                .collect();
            let hull = convex_hull(&pts).expect("a hull");
            for (f, t) in hull.faces.iter().enumerate() {
                let off = hull.normals[f].dot(&pts[t[0] as usize]);
                for p in &pts {
                    assert!(hull.normals[f].dot(p) - off < 1e-9, "case {case}");
                }
            }
            let parry_points: Vec<_> = pts.iter().map(crate::parry::vector).collect();
            let (hp, ht) =
                parry3d_f64::transformation::try_convex_hull(&parry_points).expect("parry hull");
            let reference: Real = ht
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| crate::parry::to_vector(hp[i as usize]));
                    a.dot(&b.cross(&c)) / 6.0
                })
                .sum();
            let ours = volume(&pts, &hull);
            assert!(
                (ours - reference).abs() <= 1e-9 * reference.abs().max(1e-12),
                "case {case}: {ours} vs {reference}"
            );
        }
    }

    #[test]
    fn flat_and_tiny_sets_have_no_hull() {
        let flat: Vec<Vector3> = (0..10)
            .map(|i| Vector3::new(i as Real, (i * i % 7) as Real, 0.0))
            .collect();
        assert!(convex_hull(&flat).is_none());
        assert!(convex_hull(&flat[..3]).is_none());
        let mut bad = flat.clone();
        bad.push(Vector3::new(Real::NAN, 0.0, 1.0));
        assert!(convex_hull(&bad).is_none());
    }
}
