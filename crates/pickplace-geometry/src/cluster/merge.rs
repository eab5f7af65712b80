//! The final merge pass after Step 2 of Algorithm 1 (§III-A; issues 17 and 31).
//!
//! Step 2 grows one cluster at a time, so a neighbour refused early in a growth, or grown later
//! from its own seed, can leave two adjacent clusters whose union is still a cluster. The pass
//! merges them until no adjacent pair can be merged. A union is a cluster when some plane
//! holds it: its vertices within `h_max` along the plane's normal, every triangle within
//! `max_facet_angle` of it, and the normal within [`MAX_FIT_DEVIATION`] of the union's
//! area-weighted normal. The regression plane is tried first (the growth's own test); when it
//! does not fit, [`super::slab`] searches every other admissible plane (issue 31: on robosuite's
//! can, noisy scans and rims of edge-on triangles the regression plane is neither the thinnest
//! plane nor the one that keeps every triangle within the facet angle).
//!
//! Widths are measured on each cluster's *support* (`grow.rs`): a set of its vertices that
//! holds every vertex of its convex hull, so a merge into a large cluster costs the size of its
//! hull, not of its vertex set.

use super::MAX_FIT_DEVIATION;
use super::grow::{Engine, Merged, angle};
use super::slab::{SlabProblem, find_slab_normal};
use crate::math::{Real, Vector3};

/// Buffers and supports of the pass.
#[derive(Debug, Default)]
struct Scratch {
    /// `seen[v] == generation` when vertex `v` is already in `points`.
    seen: Vec<u32>,
    generation: u32,
    points: Vec<Vector3>,
    ids: Vec<u32>,
    normals: Vec<Vector3>,
}

impl Scratch {
    /// Starts a new set of distinct vertices.
    fn next_generation(&mut self) {
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            self.seen.fill(0);
            self.generation = 1;
        }
    }
}

impl Engine<'_> {
    /// The final pass: every pass lists the adjacent pairs of live clusters by decreasing
    /// normal agreement (ties by ids) and merges each pair whose union is a cluster (the
    /// regression plane first, then any admissible plane, see the module documentation);
    /// passes repeat until one merges nothing, so no mergeable adjacent pair is left. A pair
    /// neither of whose clusters changed in the last pass was tried then and failed: only
    /// pairs with a changed cluster are listed and tried again (all in the first pass).
    pub fn merge_adjacent(&mut self) {
        let adjacency = self.mesh.adjacency();
        let mut scratch = Scratch {
            seen: vec![0; self.points.len()],
            ..Scratch::default()
        };
        let mut changed = vec![true; self.clusters.len()];
        loop {
            let mut pairs: Vec<(Real, u32, u32)> = Vec::new();
            for (x, cx) in self.clusters.iter().enumerate() {
                if !(changed[x] && cx.alive) {
                    continue;
                }
                for &t in &cx.triangles {
                    for &nb in adjacency.neighbours(t as usize) {
                        let y = self.cluster_of[nb as usize];
                        if y != x as u32 && y != u32::MAX {
                            let (a, b) = ((x as u32).min(y), (x as u32).max(y));
                            let dot = cx.normal.dot(&self.clusters[y as usize].normal);
                            pairs.push((dot, a, b));
                        }
                    }
                }
            }
            pairs.sort_unstable_by_key(|p| (p.1, p.2));
            pairs.dedup_by(|p, q| (p.1, p.2) == (q.1, q.2));
            pairs.sort_by(|p, q| q.0.total_cmp(&p.0).then((p.1, p.2).cmp(&(q.1, q.2))));
            let mut merged = false;
            changed.fill(false);
            for &(_, a, b) in &pairs {
                if !(self.clusters[a as usize].alive && self.clusters[b as usize].alive) {
                    continue;
                }
                let found = match self.try_merge(a, b, None) {
                    Some(m) => Some(m),
                    None => self.try_merge_any_plane(a, b, &mut scratch),
                };
                if let Some(m) = found {
                    self.absorb(a, b, m);
                    changed[a as usize] = true;
                    merged = true;
                }
            }
            if !merged {
                break;
            }
        }
    }

    /// Merging `b` into `a` along any admissible plane ([`find_slab_normal`]), when the
    /// regression plane did not fit; the merged cluster's normal is the plane found.
    fn try_merge_any_plane(&self, a: u32, b: u32, scratch: &mut Scratch) -> Option<Merged> {
        let (ca, cb) = (&self.clusters[a as usize], &self.clusters[b as usize]);
        let moments = ca.moments.add(&cb.moments);
        let mean = moments.normal_sum.try_normalize(0.0)?;
        if moments.area.is_nan() || moments.area <= 0.0 {
            return None;
        }
        let centroid = moments.first / moments.area;
        let limits = self.limits;
        scratch.next_generation();
        scratch.points.clear();
        scratch.ids.clear();
        for &v in ca.support.iter().chain(&cb.support) {
            if scratch.seen[v as usize] != scratch.generation {
                scratch.seen[v as usize] = scratch.generation;
                scratch.points.push(self.points[v as usize]);
                scratch.ids.push(v);
            }
        }
        let mut problem = SlabProblem {
            points: &scratch.points,
            normals: &[],
            mean,
            h_max: limits.h_max,
            max_facet_angle: limits.max_facet_angle,
            max_deviation: MAX_FIT_DEVIATION,
        };
        // The slab alone first (most refusals end here, without a pass over the triangles).
        let thin = find_slab_normal(&problem)?;
        // A normal within max_facet_angle − MAX_FIT_DEVIATION of the mean is within the facet
        // angle of every admissible direction: it cannot bind.
        let free = limits.max_facet_angle - MAX_FIT_DEVIATION;
        let risky = if free > 0.0 {
            free.cos()
        } else {
            Real::INFINITY
        };
        scratch.normals.clear();
        for &t in ca.triangles.iter().chain(&cb.triangles) {
            let n = self.tri_normals[t as usize];
            if n.dot(&mean) < risky {
                scratch.normals.push(n);
            }
        }
        let cos_facet = limits.max_facet_angle.cos();
        let normal = if scratch.normals.iter().all(|n| n.dot(&thin) > cos_facet) {
            thin
        } else {
            problem.normals = &scratch.normals;
            find_slab_normal(&problem)?
        };
        // The decision is the exact one, from the union's hull vertices and every triangle.
        let mut exact = self.support_extent(
            scratch.ids.iter(),
            ca.triangles.iter().chain(&cb.triangles),
            normal,
            centroid,
        );
        if !self.accepts(&exact) || angle(&normal, &mean) > MAX_FIT_DEVIATION {
            return None;
        }
        let found = [exact.witnesses[0], exact.witnesses[1]];
        exact.witnesses = self.pick_witnesses(
            found
                .iter()
                .chain(&ca.extent.witnesses)
                .chain(&cb.extent.witnesses),
            &normal,
        );
        Some(Merged {
            moments,
            normal,
            centroid,
            extent: exact,
        })
    }
}
