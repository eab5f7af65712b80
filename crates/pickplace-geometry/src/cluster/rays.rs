//! Rays through the object for finger mode (§III-A.1, after ref. \[15\]): where a ray from a
//! cluster's centroid along its inner normal leaves the object, found through a bounding-volume
//! hierarchy of the triangles.

use super::grow::Engine;
use crate::math::{Real, Vector3};

impl Engine<'_> {
    /// First surface crossing of the ray `origin + t·dir` (t > 0) where the ray leaves the
    /// object (triangle normal along `dir`), skipping the triangles of cluster `skip`.
    /// Coordinates relative to the engine origin. Returns the triangle and its distance.
    pub fn exit_hit(&self, origin: &Vector3, dir: &Vector3, skip: u32) -> Option<(u32, Real)> {
        self.exit_hits(origin, dir, skip).into_iter().next()
    }

    /// Every surface crossing of the ray `origin + t·dir` (t > 0) where the ray leaves the
    /// object, skipping the triangles of cluster `skip`, by increasing distance (ties by
    /// canonical rank). Returns triangles and distances.
    pub fn exit_hits(&self, origin: &Vector3, dir: &Vector3, skip: u32) -> Vec<(u32, Real)> {
        // Only the triangles whose (slightly inflated) boxes the ray meets can be hit: the same
        // hits as a scan of every triangle, in the same order (sorted below).
        let bvh = self.bvh.get_or_init(|| {
            let boxes: Vec<parry3d_f64::bounding_volume::Aabb> = self
                .tris
                .iter()
                .map(|tri| {
                    let [a, b, c] = tri.map(|v| self.points[v as usize]);
                    let lo = a.inf(&b).inf(&c);
                    let hi = a.sup(&b).sup(&c);
                    let pad = 1e-9 * (1.0 + lo.abs().max().max(hi.abs().max()));
                    parry3d_f64::bounding_volume::Aabb::new(
                        crate::parry::vector(&lo.add_scalar(-pad)),
                        crate::parry::vector(&hi.add_scalar(pad)),
                    )
                })
                .collect();
            parry3d_f64::partitioning::Bvh::from_leaves(
                parry3d_f64::partitioning::BvhBuildStrategy::Binned,
                &boxes,
            )
        });
        let inverse = dir.map(|c| 1.0 / c);
        let meets = |node: &parry3d_f64::partitioning::BvhNode| {
            let aabb = node.aabb();
            let (lo, hi) = (
                crate::parry::to_vector(aabb.mins),
                crate::parry::to_vector(aabb.maxs),
            );
            ray_meets_box(origin, &inverse, &lo, &hi)
        };
        let mut hits = Vec::new();
        for t in bvh.leaves(meets) {
            let t = t as usize;
            if self.cluster_of[t] == skip || self.tri_normals[t].dot(dir) <= 0.0 {
                continue;
            }
            let [a, b, c] = self.tris[t].map(|v| self.points[v as usize]);
            if let Some(d) = ray_triangle(origin, dir, &a, &b, &c)
                && d > 1e-12
            {
                hits.push((t as u32, d));
            }
        }
        hits.sort_by(|p, q| {
            p.1.total_cmp(&q.1)
                .then(self.rank[p.0 as usize].cmp(&self.rank[q.0 as usize]))
        });
        hits
    }
}

/// Whether the ray from `origin` with direction components inverted in `inverse` meets the
/// box `[lo, hi]` for some t ≥ 0 (slab test; an axis-parallel ray has infinite inverses).
fn ray_meets_box(origin: &Vector3, inverse: &Vector3, lo: &Vector3, hi: &Vector3) -> bool {
    let (mut near, mut far) = (0.0, Real::INFINITY);
    for k in 0..3 {
        let (a, b) = (
            (lo[k] - origin[k]) * inverse[k],
            (hi[k] - origin[k]) * inverse[k],
        );
        // 0 × ∞ (the origin on a slab's plane, parallel ray) is NaN: that slab does not cut.
        let (a, b) = if a.is_nan() || b.is_nan() {
            if origin[k] < lo[k] || origin[k] > hi[k] {
                return false;
            }
            (Real::NEG_INFINITY, Real::INFINITY)
        } else {
            (a.min(b), a.max(b))
        };
        near = Real::max(near, a);
        far = Real::min(far, b);
        if near > far {
            return false;
        }
    }
    true
}

/// The ray parameter where the ray from `o` along `d` crosses triangle `abc` (either side)
/// ([`crate::math::line_triangle`], edge tolerance 1e-12).
fn ray_triangle(o: &Vector3, d: &Vector3, a: &Vector3, b: &Vector3, c: &Vector3) -> Option<Real> {
    let p = |v: &Vector3| crate::math::Point3::from(*v);
    crate::math::line_triangle(&p(o), d, [&p(a), &p(b), &p(c)], 1e-12)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_hits_inside_the_triangle_only() {
        let (a, b, c) = (Vector3::zeros(), Vector3::x(), Vector3::y());
        let o = Vector3::new(0.2, 0.2, 1.0);
        assert!((ray_triangle(&o, &-Vector3::z(), &a, &b, &c).expect("hit") - 1.0).abs() < 1e-12);
        assert!(ray_triangle(&Vector3::new(0.8, 0.8, 1.0), &-Vector3::z(), &a, &b, &c).is_none());
    }
}
