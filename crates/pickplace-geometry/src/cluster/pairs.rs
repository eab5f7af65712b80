//! Finger-contact mode (§III-A.1, after ref. \[15\]): pairs of opposite parallel clusters.

use super::grow::Engine;
use super::{Cluster, ClusterPair};
use crate::math::Real;
use crate::polygon::{self, Polygon};

/// Grows clusters seed by seed and pairs each with the cluster grown at its antipode.
///
/// For each seed (an open Step-1 cluster, in mesh order): grow it with Step 2
/// into `C_x`; cast a ray from its centroid along `-n_x` and take the first triangle where the
/// ray leaves the object. If that triangle's cluster is still open and faces opposite
/// (`n·n_x ≤ opposite_dot`), grow it towards `-n_x` keeping its normal opposite; if it was
/// already grown, use it as is. The two form a pair when their normals are opposite.
/// Returns pairs of engine cluster ids.
pub(super) fn grow_pairs(engine: &mut Engine<'_>, opposite_dot: Real) -> Vec<(u32, u32)> {
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for x in engine.seed_order() {
        let cx = &engine.clusters[x as usize];
        if !cx.alive || cx.closed {
            continue;
        }
        engine.grow(x, None);
        let (nx, origin) = (
            engine.clusters[x as usize].normal,
            engine.clusters[x as usize].centroid,
        );
        let Some((hit, _)) = engine.exit_hit(&origin, &-nx, x) else {
            continue;
        };
        let y = engine.cluster_of[hit as usize];
        let cy = &engine.clusters[y as usize];
        if !cy.closed {
            if cy.normal.dot(&nx) > opposite_dot {
                // The antipode does not face the other way: an ordinary cluster, no pair.
                engine.grow(y, None);
                continue;
            }
            engine.grow(y, Some((-nx, -opposite_dot)));
        }
        let ny = engine.clusters[y as usize].normal;
        if ny.dot(&nx) <= opposite_dot
            && !pairs
                .iter()
                .any(|&(a, b)| (a, b) == (x, y) || (a, b) == (y, x))
        {
            pairs.push((x, y));
        }
    }
    pairs
}

/// Width, overlap and centre of a pair of final clusters; `None` when their regions do not
/// overlap once projected onto each other (no grasp fits between them).
pub(super) fn pair_geometry(first: &Cluster, second: &Cluster) -> Option<ClusterPair> {
    let mean = first.normal - second.normal;
    let mean = mean.try_normalize(1e-12)?;
    let width = mean.dot(&(first.point - second.point));
    let project = |ring: &Vec<crate::math::Point2>| -> Vec<crate::math::Point2> {
        ring.iter()
            .map(|q| first.frame.to_2d(&second.frame.to_3d(q)))
            .collect()
    };
    let mut projected = Polygon {
        outer: project(&second.region.outer),
        holes: second.region.holes.iter().map(project).collect(),
    };
    // Seen from the first plane the second region is mirrored: restore the orientations.
    if polygon::signed_area(&projected.outer) < 0.0 {
        projected.outer.reverse();
        for h in &mut projected.holes {
            h.reverse();
        }
    }
    let overlap = polygon::intersection(std::slice::from_ref(&first.region), &[projected]);
    let overlap_area = polygon::total_area(&overlap);
    if overlap_area <= 0.0 {
        return None;
    }
    let c2 = polygon::total_centroid(&overlap)?;
    let center = first.frame.to_3d(&c2) - first.normal * (0.5 * width);
    Some(ClusterPair {
        first: first.id,
        second: second.id,
        width,
        overlap,
        overlap_area,
        center,
        axis: first.normal,
    })
}
