//! Audit of a clustering (issue 31): adjacent cluster pairs that could still be one cluster of
//! Algorithm 1 (§III-A), measured independently of the growth.
//!
//! A set of triangles can be a cluster when its vertices fit in a slab of thickness `h_max`
//! (§III-A, Fig. 2) along *some* plane. The clustering fits one plane per cluster; this audit
//! looks for the best plane of every adjacent pair's union instead, among these directions:
//! - the union's regression plane ([`super::fit_plane`]), its area-weighted normal, and the two
//!   clusters' normals;
//! - every face normal of the union's convex hull, and (when no face is thin enough) every
//!   direction perpendicular to two hull edges that support parallel planes
//!   ([`super::width`]): the minimum width of a point set is attained at one of them, so
//!   "thickness only" is decided exactly;
//! - when the pair is thin along some direction but none of the above satisfies the angle
//!   limits: 256 directions spread over the admissible cap (within [`MAX_FIT_DEVIATION`] of
//!   the area-weighted normal) and a compass search from the best of them. This brute force
//!   shares no code with the clustering's own search ([`super::slab`]).
//!
//! Three counts, each a subset of the one before:
//! - **thickness only**: the union's width along some direction is at most `h_max`;
//! - **thickness and facet angle**: along such a direction `n` (turned to agree with the
//!   union's area-weighted normal) every triangle is also within `max_facet_angle` of `n`;
//! - **mergeable** (thickness and both angles): `n` is also within [`MAX_FIT_DEVIATION`] of
//!   the area-weighted normal, the rule every cluster's normal obeys. Such a union is a
//!   cluster: this is the count the final merge pass ([`super::merge`]) brings to zero.
//!
//! "Thickness only" is exact. The other two are exact when a candidate direction satisfies
//! the angles, and lower bounds otherwise (the brute force samples the cap). Every test keeps
//! a margin against rounding: widths below `h_max` by [`AUDIT_MARGIN`], angles below their
//! limits by 1e-6 rad.

use super::geometry::tangent_pair;
use super::grow::Moments;
use super::hull::convex_hull;
use super::width::{edge_pair_directions, extent_along, face_directions};
use super::{Clustering, MAX_FIT_DEVIATION};
use crate::math::{Point3, Real, Vector3};
use crate::mesh::TriMesh;
use std::collections::BTreeSet;

/// A union counts as thin when its width is at most `h_max` minus this (m): 1 nm.
pub const AUDIT_MARGIN: Real = 1e-9;

/// Margin on the angle limits (rad).
const ANGLE_MARGIN: Real = 1e-6;

/// Two adjacent clusters whose union could be one cluster.
#[derive(Debug, Clone, PartialEq)]
pub struct MergeablePair {
    /// The lower cluster id.
    pub first: u32,
    /// The higher cluster id.
    pub second: u32,
    /// The union's width along [`MergeablePair::normal`] (m), at most `h_max`.
    pub width: Real,
    /// The direction found (unit, agreeing with the union's area-weighted normal).
    pub normal: Vector3,
    /// The union's width along its regression plane's normal ([`super::fit_plane`]) (m): what
    /// the growth's first test measures.
    pub fitted_width: Real,
}

/// What [`audit_adjacent_pairs`] found.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MergeAudit {
    /// Pairs of clusters that share a mesh edge, each once.
    pub adjacent_pairs: usize,
    /// Adjacent pairs whose union fits in `h_max` along some direction, whatever the angles.
    pub thickness_only: Vec<MergeablePair>,
    /// Adjacent pairs whose union fits in `h_max` along a direction that keeps every
    /// triangle within `max_facet_angle`, whatever its angle to the union's normals.
    pub thickness_and_facet_angle: Vec<MergeablePair>,
    /// Adjacent pairs whose union fits in `h_max` along a direction that keeps every
    /// triangle within `max_facet_angle` and is within [`MAX_FIT_DEVIATION`] of the union's
    /// area-weighted normal: pairs whose union is a cluster, which should have been merged.
    pub mergeable: Vec<MergeablePair>,
}

/// Counts the adjacent cluster pairs of `clustering` (computed on `mesh` with its
/// `params`) whose union could still be one cluster (see the module documentation for the
/// directions tried and the counts).
///
/// # Performance
/// Per adjacent pair: a convex hull of the union's vertices and its face directions
/// (`O(F·V)`); edge pairs (`O(E²)`, mostly one dot product each) only when no face is thin
/// enough; a search of the admissible cap only when the candidates fail but the pair is thin
/// enough along some direction. Meant for tests and `cargo xtask clusters`, not for the
/// planner.
pub fn audit_adjacent_pairs(mesh: &TriMesh, clustering: &Clustering) -> MergeAudit {
    let owner = clustering.cluster_of_triangles(mesh.triangle_count());
    let mut adjacent = BTreeSet::new();
    for t in 0..mesh.triangle_count() {
        for &nb in mesh.adjacency().neighbours(t) {
            if let (Some(a), Some(b)) = (owner[t], owner.get(nb as usize).copied().flatten())
                && a < b
            {
                adjacent.insert((a, b));
            }
        }
    }
    let mut audit = MergeAudit {
        adjacent_pairs: adjacent.len(),
        ..MergeAudit::default()
    };
    let (lo, hi) = mesh.aabb();
    let origin = Point3::from((lo.coords + hi.coords) * 0.5);
    let limits = Limits::new(clustering);
    let summaries: Vec<Summary> = clustering
        .clusters
        .iter()
        .map(|c| Summary::new(mesh, &origin, &c.triangles))
        .collect();
    for (a, b) in adjacent {
        let (Some(ca), Some(cb)) = (
            clustering.clusters.get(a as usize),
            clustering.clusters.get(b as usize),
        ) else {
            continue;
        };
        let union = Union::new(&summaries[a as usize], &summaries[b as usize]);
        let Some(mean) = union.mean_normal else {
            continue;
        };
        let fitted = union.fitted;
        let fitted_width = union.width(&fitted);
        let pair = |(width, normal): (Real, Vector3)| MergeablePair {
            first: a,
            second: b,
            width,
            normal,
            fitted_width,
        };
        let verdict = union.judge(&limits, mean, [ca.normal, cb.normal, fitted]);
        if let Some(found) = verdict.thin {
            audit.thickness_only.push(pair(found));
        }
        if let Some(found) = verdict.facet {
            audit.thickness_and_facet_angle.push(pair(found));
        }
        if let Some(found) = verdict.mergeable {
            audit.mergeable.push(pair(found));
        }
    }
    audit
}

/// What the audit keeps of one cluster: every width of a union and every facet angle is
/// decided by the extreme points of its vertices and of its triangle normals, and its
/// regression plane by its moments.
struct Summary {
    /// The cluster's vertices on their convex hull (relative to the mesh's box centre).
    points: Vec<Vector3>,
    /// The triangle normals on their convex hull: `min n·d` over the normals is attained
    /// there.
    normals: Vec<Vector3>,
    moments: Moments,
}

impl Summary {
    fn new(mesh: &TriMesh, origin: &Point3, triangles: &[u32]) -> Self {
        // A clustering of another mesh may name triangles this one does not have.
        let triangles: Vec<u32> = triangles
            .iter()
            .copied()
            .filter(|&t| (t as usize) < mesh.triangle_count())
            .collect();
        let triangles = triangles.as_slice();
        let mut ids: Vec<u32> = triangles
            .iter()
            .flat_map(|&t| mesh.triangles()[t as usize])
            .collect();
        ids.sort_unstable();
        ids.dedup();
        let points: Vec<Vector3> = ids
            .iter()
            .map(|&v| mesh.vertices()[v as usize] - origin)
            .collect();
        let normals: Vec<Vector3> = triangles
            .iter()
            .map(|&t| mesh.triangle_normal(t as usize))
            .collect();
        let mut moments =
            Moments::triangle(&Vector3::zeros(), &Vector3::zeros(), &Vector3::zeros());
        for &t in triangles {
            let [a, b, c] =
                mesh.triangles()[t as usize].map(|v| mesh.vertices()[v as usize] - origin);
            moments = moments.add(&Moments::triangle(&a, &b, &c));
        }
        Self {
            points: extreme_points(&points),
            normals: extreme_points(&normals),
            moments,
        }
    }
}

/// The points of `points` on their convex hull (all of them when there are few); for a flat
/// set, those on its convex outline in its plane; for a collinear one, the two ends.
fn extreme_points(points: &[Vector3]) -> Vec<Vector3> {
    if points.len() <= 8 {
        return points.to_vec();
    }
    if let Some(hull) = convex_hull(points) {
        return hull
            .vertices()
            .iter()
            .map(|&v| points[v as usize])
            .collect();
    }
    let far = |from: &Vector3, key: &dyn Fn(&Vector3) -> Real| {
        points
            .iter()
            .copied()
            .max_by(|p, q| key(p).total_cmp(&key(q)))
            .unwrap_or(*from)
    };
    let p0 = points[0];
    let p1 = far(&p0, &|p| (p - p0).norm_squared());
    let p2 = far(&p1, &|p| (p - p1).norm_squared());
    let Some(axis) = (p2 - p1).try_normalize(0.0) else {
        return vec![p0];
    };
    let p3 = far(&p1, &|p| {
        (p - p1 - axis * axis.dot(&(p - p1))).norm_squared()
    });
    let Some(normal) = axis.cross(&(p3 - p1)).try_normalize(1e-12) else {
        return vec![p1, p2];
    };
    let side = normal.cross(&axis);
    // Andrew's monotone chain on the plane coordinates.
    let mut order: Vec<(Real, Real, usize)> = points
        .iter()
        .enumerate()
        .map(|(i, p)| (axis.dot(p), side.dot(p), i))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let turn = |o: &(Real, Real, usize), a: &(Real, Real, usize), b: &(Real, Real, usize)| {
        (a.0 - o.0) * (b.1 - o.1) - (a.1 - o.1) * (b.0 - o.0)
    };
    let mut chain: Vec<(Real, Real, usize)> = Vec::new();
    for pass in 0..2 {
        let start = chain.len();
        let iter: Box<dyn Iterator<Item = &(Real, Real, usize)>> = if pass == 0 {
            Box::new(order.iter())
        } else {
            Box::new(order.iter().rev())
        };
        for q in iter {
            while chain.len() >= start + 2
                && turn(&chain[chain.len() - 2], &chain[chain.len() - 1], q) <= 0.0
            {
                chain.pop();
            }
            chain.push(*q);
        }
    }
    let mut ids: Vec<usize> = chain.iter().map(|q| q.2).collect();
    ids.sort_unstable();
    ids.dedup();
    ids.into_iter().map(|i| points[i]).collect()
}

/// The limits of a cluster, with the audit's margins.
struct Limits {
    /// `h_max` − [`AUDIT_MARGIN`].
    h: Real,
    /// Cosine of `max_facet_angle` − [`ANGLE_MARGIN`].
    cos_facet: Real,
    /// Cosine of [`MAX_FIT_DEVIATION`] − [`ANGLE_MARGIN`].
    cos_deviation: Real,
    /// A triangle normal within this cosine of the mean normal is within the facet angle of
    /// every admissible direction (`max_facet_angle − MAX_FIT_DEVIATION`).
    cos_free: Real,
    /// A triangle normal beyond this cosine of the mean normal is outside the facet angle of
    /// every admissible direction (`max_facet_angle + MAX_FIT_DEVIATION`).
    cos_hopeless: Real,
    /// Angular radius of the admissible cap (rad).
    deviation: Real,
}

impl Limits {
    fn new(clustering: &Clustering) -> Self {
        let p = &clustering.params;
        let free = p.max_facet_angle - MAX_FIT_DEVIATION;
        Self {
            h: p.h_max - AUDIT_MARGIN,
            cos_facet: (p.max_facet_angle - ANGLE_MARGIN).cos(),
            cos_deviation: (MAX_FIT_DEVIATION - ANGLE_MARGIN).cos(),
            cos_free: if free > 0.0 {
                free.cos()
            } else {
                Real::INFINITY
            },
            cos_hopeless: (p.max_facet_angle + MAX_FIT_DEVIATION)
                .min(std::f64::consts::PI)
                .cos(),
            deviation: MAX_FIT_DEVIATION - ANGLE_MARGIN,
        }
    }
}

/// What one pair's union admits: a direction and the width along it, per count.
#[derive(Default)]
struct Verdict {
    thin: Option<(Real, Vector3)>,
    facet: Option<(Real, Vector3)>,
    mergeable: Option<(Real, Vector3)>,
}

/// The extreme points and normals of a union of two clusters, with its planes.
struct Union {
    /// Vertices (relative to the mesh's box centre): the two clusters' extreme ones.
    points: Vec<Vector3>,
    /// Triangle normals: the two clusters' extreme ones.
    normals: Vec<Vector3>,
    /// Area-weighted normal (unit), `None` when the areas cancel.
    mean_normal: Option<Vector3>,
    /// The regression plane's normal (as [`super::fit_plane`] gives it).
    fitted: Vector3,
}

impl Union {
    fn new(a: &Summary, b: &Summary) -> Self {
        let moments = a.moments.add(&b.moments);
        Self {
            points: a.points.iter().chain(&b.points).copied().collect(),
            normals: a.normals.iter().chain(&b.normals).copied().collect(),
            mean_normal: moments.normal_sum.try_normalize(0.0),
            fitted: moments.plane().0,
        }
    }

    fn width(&self, d: &Vector3) -> Real {
        let (lo, hi) = extent_along(&self.points, d);
        hi - lo
    }

    /// Whether every triangle is within the facet angle of `d`.
    fn facets_fit(&self, limits: &Limits, d: &Vector3) -> bool {
        self.normals.iter().all(|n| n.dot(d) >= limits.cos_facet)
    }

    /// Updates `verdict` with the thin ones of `candidates` (width, direction), thinnest
    /// first, each width checked on all points.
    fn consider(
        &self,
        mut candidates: Vec<(Real, Vector3)>,
        limits: &Limits,
        mean: &Vector3,
        verdict: &mut Verdict,
    ) {
        candidates.retain(|c| c.0 <= limits.h);
        candidates.sort_by(|p, q| {
            p.0.total_cmp(&q.0)
                .then(p.1.x.total_cmp(&q.1.x))
                .then(p.1.y.total_cmp(&q.1.y))
                .then(p.1.z.total_cmp(&q.1.z))
        });
        for (_, d) in candidates {
            if verdict.mergeable.is_some() {
                return;
            }
            // The hull may miss a point it left out: the width is checked on all of them.
            let width = self.width(&d);
            if width > limits.h {
                continue;
            }
            verdict.thin.get_or_insert((width, d));
            if verdict.facet.is_none() && self.facets_fit(limits, &d) {
                verdict.facet = Some((width, d));
            }
            if d.dot(mean) >= limits.cos_deviation && self.facets_fit(limits, &d) {
                verdict.mergeable = Some((width, d));
            }
        }
    }

    /// The three counts' directions for this union (module documentation).
    fn judge(&self, limits: &Limits, mean: Vector3, extra: [Vector3; 3]) -> Verdict {
        let orient = |d: Vector3| if d.dot(&mean) < 0.0 { -d } else { d };
        let mut verdict = Verdict::default();
        // A union narrower than h_max in every direction (twice its radius about its mean
        // point) is thin along any plane: only the angles decide, exactly, as an intersection
        // of spherical caps.
        let centre = self.points.iter().sum::<Vector3>() / self.points.len().max(1) as Real;
        let radius = self
            .points
            .iter()
            .map(|p| (p - centre).norm())
            .fold(0.0, Real::max);
        if 2.0 * radius <= limits.h {
            let width = |d: &Vector3| self.width(d);
            verdict.thin = Some((width(&mean), mean));
            let facets: Vec<(Vector3, Real)> = self
                .normals
                .iter()
                .map(|n| (*n, limits.cos_facet))
                .collect();
            verdict.facet = caps_meet(&facets, &mean).map(|d| (width(&d), d));
            let mut all = facets;
            all.push((mean, limits.cos_deviation));
            verdict.mergeable = caps_meet(&all, &mean).map(|d| (width(&d), d));
            return verdict;
        }
        // The named directions first, their widths exact on all points.
        let named: Vec<(Real, Vector3)> = std::iter::once(mean)
            .chain(extra)
            .map(|d| (self.width(&d), orient(d)))
            .collect();
        self.consider(named, limits, &mean, &mut verdict);
        // No admissible direction is within the facet angle of a normal this far from the
        // mean: the pair cannot be a cluster.
        let possible = self
            .normals
            .iter()
            .all(|n| n.dot(&mean) > limits.cos_hopeless);
        // The hull's directions: for the exact thickness when no named direction is thin, and
        // as candidates when the pair may be a cluster.
        let hull = if verdict.thin.is_none() || (possible && verdict.mergeable.is_none()) {
            convex_hull(&self.points)
        } else {
            None
        };
        if let Some(hull) = &hull {
            let mut candidates: Vec<(Real, Vector3)> = face_directions(&self.points, hull)
                .into_iter()
                .map(|(d, w)| (w, orient(d)))
                .collect();
            if verdict.thin.is_none() && candidates.iter().all(|c| c.0 > limits.h) {
                candidates.extend(
                    edge_pair_directions(&self.points, hull)
                        .into_iter()
                        .map(|(d, w)| (w, orient(d))),
                );
            }
            self.consider(candidates, limits, &mean, &mut verdict);
        }
        if verdict.mergeable.is_none() && verdict.thin.is_some() && possible {
            let support: Vec<Vector3> = match &hull {
                Some(hull) => hull
                    .vertices()
                    .iter()
                    .map(|&v| self.points[v as usize])
                    .collect(),
                None => self.points.clone(),
            };
            let risky: Vec<Vector3> = self
                .normals
                .iter()
                .filter(|n| n.dot(&mean) < limits.cos_free)
                .copied()
                .collect();
            if let Some(d) = search_cap(&support, &risky, limits, &mean) {
                let width = self.width(&d);
                if width <= limits.h && self.facets_fit(limits, &d) {
                    verdict.facet.get_or_insert((width, d));
                    verdict.mergeable = Some((width, d));
                }
            }
        }
        verdict
    }
}

/// A direction within the admissible cap around `mean` along which `points` fit in the slab
/// and every normal of `normals` is within the facet angle, by brute force: 256 directions
/// spread evenly over the cap, then a compass search (steps along two tangent directions,
/// halved when no step improves) from the best of them, on the largest relative violation.
/// Independent of the clustering's own search ([`super::slab`]). `None` when nothing is found.
fn search_cap(
    points: &[Vector3],
    normals: &[Vector3],
    limits: &Limits,
    mean: &Vector3,
) -> Option<Vector3> {
    let violation = |d: &Vector3| -> Real {
        let (lo, hi) = extent_along(points, d);
        let mut worst = (hi - lo - limits.h) / limits.h.max(1e-12);
        worst = worst.max(limits.cos_deviation - d.dot(mean));
        for n in normals {
            worst = worst.max(limits.cos_facet - n.dot(d));
        }
        worst
    };
    let (u, v) = tangent_pair(mean);
    let samples = 256;
    let mut best = (violation(mean), *mean);
    for i in 0..samples {
        let cos_polar = 1.0 - (1.0 - limits.deviation.cos()) * (i as Real + 0.5) / samples as Real;
        let sin_polar = (1.0 - cos_polar * cos_polar).max(0.0).sqrt();
        let azimuth = i as Real * 2.399_963_229_728_653;
        let d = mean * cos_polar + (u * azimuth.cos() + v * azimuth.sin()) * sin_polar;
        let value = violation(&d);
        if value < best.0 {
            best = (value, d);
        }
    }
    let mut step = 2.0 * limits.deviation / (samples as Real).sqrt();
    let mut evaluations = 0;
    while best.0 > 0.0 && step > 1e-7 && evaluations < 400 {
        let (tu, tv) = tangent_pair(&best.1);
        let mut improved = false;
        for t in [tu, -tu, tv, -tv] {
            let d = (best.1 + t * step).normalize();
            let value = violation(&d);
            evaluations += 1;
            if value < best.0 {
                best = (value, d);
                improved = true;
                break;
            }
        }
        if !improved {
            step *= 0.5;
        }
    }
    (best.0 <= 0.0).then_some(best.1)
}

/// A unit vector in every cap `(centre, cos radius)` of `caps` (each a closed spherical cap of
/// radius below 90°), or `None` when they do not meet. Exact up to rounding: the point of the
/// intersection closest to `toward` is `toward` itself, the point of one cap's rim closest to
/// `toward`, or a point where two rims cross; every such candidate is tried.
fn caps_meet(caps: &[(Vector3, Real)], toward: &Vector3) -> Option<Vector3> {
    let inside = |d: &Vector3| caps.iter().all(|(c, cos)| c.dot(d) >= *cos - 1e-12);
    if inside(toward) {
        return Some(*toward);
    }
    let mut candidates: Vec<Vector3> = Vec::new();
    for (c, cos) in caps {
        // The rim point on the great circle from the centre towards `toward`.
        if let Some(t) = (toward - c * c.dot(toward)).try_normalize(1e-12) {
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            candidates.push(c * *cos + t * sin);
        }
    }
    for (i, (ci, cos_i)) in caps.iter().enumerate() {
        for (cj, cos_j) in &caps[i + 1..] {
            let g = ci.dot(cj);
            let axis = ci.cross(cj);
            let det = 1.0 - g * g;
            if det <= 1e-15 {
                continue;
            }
            let a = (cos_i - g * cos_j) / det;
            let b = (cos_j - g * cos_i) / det;
            let rest = 1.0 - (a * a + b * b + 2.0 * a * b * g);
            if rest < 0.0 {
                continue;
            }
            let k = (rest / axis.norm_squared()).sqrt();
            let base = ci * a + cj * b;
            candidates.push(base + axis * k);
            candidates.push(base - axis * k);
        }
    }
    candidates
        .into_iter()
        .filter_map(|d| d.try_normalize(0.0))
        .find(|d| inside(d))
}
