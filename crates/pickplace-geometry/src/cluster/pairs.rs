//! Finger-contact mode (§III-A.1, after ref. \[15\]): pairs of opposite parallel clusters.

use super::grow::Engine;
use super::{Cluster, ClusterPair};
use crate::math::Real;
use crate::polygon::{self, Polygon};

/// Thinnest wall whose two sides pair (m): 2 mm. Two opposite surfaces closer than this are
/// the two sides of one sheet, not two sides of an object a parallel gripper closes across.
pub const MIN_WALL_THICKNESS: Real = 0.002;

/// Grows clusters seed by seed, each seed's antipode towards the opposite normal (§III-A.1).
///
/// For each seed (an open Step-1 cluster, in canonical order): grow it with Step 2
/// into `C_x`; cast a ray from its centroid along `-n_x` and take the first triangle where the
/// ray leaves the object. If that triangle's cluster is still open and faces opposite
/// (`n·n_x ≤ opposite_dot`), grow it towards `-n_x` keeping its normal opposite; otherwise
/// grow it as an ordinary cluster. The pairs are found afterwards by [`find_pairs`], once the
/// clusters are final. `seed_done(seeds done, seeds)` is told after each seed.
pub(super) fn grow_finger(
    engine: &mut Engine<'_>,
    opposite_dot: Real,
    seed_done: &mut dyn FnMut(usize, usize),
) {
    let seeds = engine.seed_order();
    for (i, &x) in seeds.iter().enumerate() {
        seed_done(i, seeds.len());
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
                engine.grow(y, None);
                continue;
            }
            engine.grow(y, Some((-nx, -opposite_dot)));
        }
    }
}

/// Pairs of opposite clusters (§III-A.1), found from every final cluster in turn (issue 17:
/// a cluster grown as another's antipode looks for its own opposite too).
///
/// From the centroid of every live cluster `x` a ray is cast through the object along
/// `-n_x`; every triangle where it leaves the object belongs to a candidate `y`. `y` pairs with
/// `x` when it faces the other way (`n_y·n_x ≤ opposite_dot`) and lies more than
/// [`MIN_WALL_THICKNESS`] behind `x`'s centroid: the two sides of a sheet (a 1 mm wall of
/// cardboard or plastic) are not a grip, and a ray that crosses such a wall goes on to the far
/// side of the object, so the outer walls of a hollow or open mesh pair with each other. Returns engine id pairs
/// `(lower, higher)`, each once, sorted.
pub(super) fn find_pairs(engine: &Engine<'_>, opposite_dot: Real) -> Vec<(u32, u32)> {
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    for (x, cx) in engine.clusters.iter().enumerate() {
        if !cx.alive {
            continue;
        }
        let x = x as u32;
        for (hit, distance) in engine.exit_hits(&cx.centroid, &-cx.normal, x) {
            let y = engine.cluster_of[hit as usize];
            if distance <= MIN_WALL_THICKNESS
                || engine.clusters[y as usize].normal.dot(&cx.normal) > opposite_dot
            {
                continue;
            }
            pairs.push((x.min(y), x.max(y)));
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
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
