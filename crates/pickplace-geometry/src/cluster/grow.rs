//! The clustering engine: Algorithm 1 (Steps 1 and 2) of Harada et al., §III-A.
//!
//! A cluster keeps its area moments (area, first moment, second moment, summed scaled
//! normals), so merging two clusters and refitting the regression plane `P` costs a 3×3
//! eigenproblem, independent of the cluster sizes. The thickness `h` of a merged cluster along
//! the new normal is first bounded from stored extents (exact for the directions they were
//! measured along, widened by `|n' - n_ref| · R` for a new direction `n'`); only when the bound
//! cannot decide is the merged cluster's vertex set scanned. Every accepted cluster therefore
//! satisfies `h ≤ h_max` exactly as measured from its own vertices.

use crate::math::{Matrix3, Point3, Real, Vector3};
use crate::mesh::TriMesh;

/// Area moments of a set of triangles, relative to the engine's origin.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Moments {
    pub area: Real,
    /// ∫ x dA.
    pub first: Vector3,
    /// ∫ x xᵀ dA.
    pub second: Matrix3,
    /// Σ area-weighted unit normals (= Σ scaled normals / 2).
    pub normal_sum: Vector3,
}

impl Moments {
    pub fn triangle(a: &Vector3, b: &Vector3, c: &Vector3) -> Self {
        let scaled = (b - a).cross(&(c - a));
        let area = 0.5 * scaled.norm();
        let s = a + b + c;
        let second =
            (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose())
                * (area / 12.0);
        Self {
            area,
            first: s * (area / 3.0),
            second,
            normal_sum: scaled * 0.5,
        }
    }

    pub fn add(&self, o: &Self) -> Self {
        Self {
            area: self.area + o.area,
            first: self.first + o.first,
            second: self.second + o.second,
            normal_sum: self.normal_sum + o.normal_sum,
        }
    }

    /// The regression plane `P`: area-weighted least-squares plane of the triangles' surface
    /// (normal = eigenvector of the smallest eigenvalue of the area covariance), oriented to
    /// agree with the triangles' outward normals. Returns (unit normal, centroid).
    ///
    /// A fit whose normal turns more than [`MAX_FIT_DEVIATION`] away from the area-weighted
    /// normal of the triangles is ill-conditioned (a strip of triangles nearly one-dimensional,
    /// whose plane may turn freely about the strip): the area-weighted normal is used instead,
    /// so a cluster's normal always agrees with its own triangles (issue 17).
    pub fn plane(&self) -> (Vector3, Vector3) {
        let c = self.first / self.area;
        let cov = self.second / self.area - c * c.transpose();
        let mean = self.normal_sum.try_normalize(0.0);
        let fitted = smallest_eigenvector(&cov, &self.normal_sum);
        let n = match (fitted, mean) {
            (Some(n), Some(mean)) => {
                let n = if n.dot(&mean) < 0.0 { -n } else { n };
                if angle(&n, &mean) > MAX_FIT_DEVIATION {
                    mean
                } else {
                    n
                }
            }
            (Some(n), None) => n,
            (None, Some(mean)) => mean,
            (None, None) => Vector3::z(),
        };
        (n, c)
    }
}

/// Largest angle between a cluster's fitted normal (`Cluster::normal`) and the area-weighted normal of its
/// triangles (rad): 20°. Beyond it the fit is ill-conditioned and the area-weighted normal is
/// used ([`Moments::plane`]).
pub const MAX_FIT_DEVIATION: Real = 20.0 * std::f64::consts::PI / 180.0;

/// Unit eigenvector of the smallest eigenvalue of a symmetric positive semi-definite 3×3
/// matrix `m` (an area covariance).
///
/// Power iteration on the adjugate, started from `guess` (the area-weighted normal, close to
/// the answer): with `m`'s eigenvalues λ₁ ≤ λ₂ ≤ λ₃, adj(m) has the same eigenvectors with
/// eigenvalues λ₂λ₃ ≥ λ₁λ₃ ≥ λ₁λ₂, so its dominant eigenvector is the one wanted, and each
/// step shrinks the error by λ₁/λ₂. A flat cluster (λ₁ = 0) is exact after one step, a
/// gently curved one after two or three. When the iteration does not settle (λ₁ ≈ λ₂) a
/// full symmetric eigen-decomposition decides. Both are deterministic.
fn smallest_eigenvector(m: &Matrix3, guess: &Vector3) -> Option<Vector3> {
    let adj = Matrix3::new(
        m[(1, 1)] * m[(2, 2)] - m[(1, 2)] * m[(2, 1)],
        m[(0, 2)] * m[(2, 1)] - m[(0, 1)] * m[(2, 2)],
        m[(0, 1)] * m[(1, 2)] - m[(0, 2)] * m[(1, 1)],
        m[(1, 2)] * m[(2, 0)] - m[(1, 0)] * m[(2, 2)],
        m[(0, 0)] * m[(2, 2)] - m[(0, 2)] * m[(2, 0)],
        m[(0, 2)] * m[(1, 0)] - m[(0, 0)] * m[(1, 2)],
        m[(1, 0)] * m[(2, 1)] - m[(1, 1)] * m[(2, 0)],
        m[(0, 1)] * m[(2, 0)] - m[(0, 0)] * m[(2, 1)],
        m[(0, 0)] * m[(1, 1)] - m[(0, 1)] * m[(1, 0)],
    );
    if let Some(mut v) = guess.try_normalize(0.0) {
        for _ in 0..24 {
            let w = adj * v;
            let norm = w.norm();
            if !(norm.is_finite() && norm > 0.0) {
                break;
            }
            let w = w / norm;
            let settled = (w - v).norm_squared() < 1e-26;
            v = w;
            if settled {
                return Some(v);
            }
        }
    }
    smallest_eigenvector_full(m)
}

/// [`smallest_eigenvector`] by a full symmetric eigen-decomposition.
fn smallest_eigenvector_full(m: &Matrix3) -> Option<Vector3> {
    let eig = nalgebra::SymmetricEigen::new(*m);
    let mut k = 0;
    for i in 1..3 {
        if eig.eigenvalues[i] < eig.eigenvalues[k] {
            k = i;
        }
    }
    let v: Vector3 = eig.eigenvectors.column(k).into_owned();
    let norm = v.norm();
    (norm.is_finite() && norm > 0.5).then(|| v / norm)
}

/// Angle between two unit vectors, accurate near 0 and π.
#[inline]
pub(crate) fn angle(a: &Vector3, b: &Vector3) -> Real {
    2.0 * (0.5 * (a - b).norm()).min(1.0).asin()
}

/// Outer bounds of a cluster's vertices measured along a reference direction.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Extent {
    /// Reference direction (unit).
    dir: Vector3,
    /// Every vertex `p` has `lo ≤ dir·p ≤ hi`.
    lo: Real,
    hi: Real,
    /// Reference centre.
    center: Vector3,
    /// Every vertex is within `radius` of `center`.
    radius: Real,
    /// Every triangle normal is within `spread` (rad) of `dir`.
    spread: Real,
    /// A few of the cluster's vertices, the most extreme ones along the normal found so far
    /// (`NO_VERTEX` for empty slots): the union's thickness along any direction is at least
    /// theirs, which rejects most merges without scanning the cluster.
    pub(super) witnesses: [u32; WITNESSES],
}

/// Number of witness vertices an [`Extent`] keeps.
const WITNESSES: usize = 6;
/// An empty witness slot.
const NO_VERTEX: u32 = u32::MAX;
/// Supports of at most this many vertices are kept as they are.
const SMALL_SUPPORT: usize = 64;
/// A support is cut to its convex hull only past this many distinct vertices, and four times
/// the size of its last cut (a hull costs far more than a scan of a small set).
const HULL_SUPPORT: usize = 512;

/// One cluster under construction.
#[derive(Debug, Clone)]
pub(crate) struct Work {
    pub alive: bool,
    pub closed: bool,
    pub triangles: Vec<u32>,
    pub moments: Moments,
    pub normal: Vector3,
    pub centroid: Vector3,
    pub(super) extent: Extent,
    /// Vertices holding every vertex of the cluster's convex hull (repeats allowed): the
    /// extremes along any direction and the farthest vertex from any point are among them.
    pub(super) support: Vec<u32>,
    /// Size of `support` when it was last pruned, and when it was last cut to its hull.
    pruned: usize,
    hulled: usize,
}

/// Limits a merge must respect.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Limits {
    pub h_max: Real,
    pub max_facet_angle: Real,
}

/// Clustering state over one mesh.
#[derive(Debug)]
pub(crate) struct Engine<'a> {
    pub mesh: &'a TriMesh,
    /// Vertex positions relative to `origin` (better conditioned moments).
    pub points: Vec<Vector3>,
    pub origin: Point3,
    pub tri_normals: Vec<Vector3>,
    /// Each triangle's vertices rotated to start at its lexicographically smallest position
    /// (same winding): moments and normals do not depend on the vertex rotation of the input.
    pub(super) tris: Vec<[u32; 3]>,
    /// Canonical rank of each triangle (see [`canonical_ranks`]).
    pub rank: Vec<u32>,
    pub cluster_of: Vec<u32>,
    pub clusters: Vec<Work>,
    pub(super) limits: Limits,
    stamp: Vec<u32>,
    generation: u32,
    /// `seen[v] == seen_generation`: vertex `v` met in the current pass over a support.
    seen: Vec<u32>,
    seen_generation: u32,
    /// Bounding-volume hierarchy of the triangles (their boxes, engine coordinates), built on
    /// the first ray query ([`Engine::exit_hits`]).
    pub(super) bvh: std::sync::OnceLock<parry3d_f64::partitioning::Bvh>,
}

/// A proposed merge.
pub(crate) struct Merged {
    pub(super) moments: Moments,
    pub(super) normal: Vector3,
    pub(super) centroid: Vector3,
    pub(super) extent: Extent,
}

impl<'a> Engine<'a> {
    pub fn new(mesh: &'a TriMesh, limits: Limits) -> Self {
        let (lo, hi) = mesh.aabb();
        let origin = Point3::from((lo.coords + hi.coords) * 0.5);
        let points: Vec<Vector3> = mesh.vertices().iter().map(|p| p - origin).collect();
        let vertices = mesh.vertices();
        let tris: Vec<[u32; 3]> = mesh
            .triangles()
            .iter()
            .map(|&t| {
                let k = (0..3)
                    .min_by(|&a, &b| {
                        lex(&vertices[t[a] as usize], &vertices[t[b] as usize]).then(a.cmp(&b))
                    })
                    .unwrap_or(0);
                [t[k], t[(k + 1) % 3], t[(k + 2) % 3]]
            })
            .collect();
        let tri_normals = tris
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|v| points[v as usize]);
                (b - a)
                    .cross(&(c - a))
                    .try_normalize(0.0)
                    .unwrap_or_else(Vector3::z)
            })
            .collect();
        let rank = canonical_ranks(mesh);
        Self {
            mesh,
            points,
            origin,
            tri_normals,
            tris,
            rank,
            cluster_of: vec![u32::MAX; mesh.triangle_count()],
            clusters: Vec::new(),
            limits,
            stamp: Vec::new(),
            generation: 0,
            seen: vec![0; mesh.vertices().len()],
            seen_generation: 0,
            bvh: std::sync::OnceLock::new(),
        }
    }

    fn tri_moments(&self, t: u32) -> Moments {
        let [a, b, c] = self.tris[t as usize].map(|v| self.points[v as usize]);
        Moments::triangle(&a, &b, &c)
    }

    /// Exact extent of a set of triangles along `dir` around `center`.
    pub(super) fn exact_extent<'b>(
        &self,
        tris: impl Iterator<Item = &'b u32>,
        dir: Vector3,
        center: Vector3,
    ) -> Extent {
        let (mut lo, mut hi, mut r2, mut min_dot) =
            (Real::INFINITY, Real::NEG_INFINITY, 0.0 as Real, 1.0 as Real);
        let (mut lo_v, mut hi_v) = (NO_VERTEX, NO_VERTEX);
        let tris_idx = &self.tris;
        for &t in tris {
            min_dot = min_dot.min(self.tri_normals[t as usize].dot(&dir));
            for &v in &tris_idx[t as usize] {
                let p = &self.points[v as usize];
                let d = dir.dot(p);
                if d < lo {
                    lo = d;
                    lo_v = v;
                }
                if d > hi {
                    hi = d;
                    hi_v = v;
                }
                r2 = r2.max((p - center).norm_squared());
            }
        }
        let mut witnesses = [NO_VERTEX; WITNESSES];
        witnesses[0] = lo_v;
        witnesses[1] = hi_v;
        Extent {
            dir,
            lo,
            hi,
            center,
            radius: r2.sqrt(),
            spread: min_dot.clamp(-1.0, 1.0).acos(),
            witnesses,
        }
    }

    /// [`Engine::exact_extent`] from a subset of the vertices that holds every vertex of the
    /// triangles' convex hull (`support`): the extremes along any direction and the farthest
    /// vertex from any point are hull vertices, so the extent is the same; the facet spread
    /// still scans every triangle's normal.
    pub(super) fn support_extent<'b>(
        &self,
        support: impl Iterator<Item = &'b u32>,
        tris: impl Iterator<Item = &'b u32>,
        dir: Vector3,
        center: Vector3,
    ) -> Extent {
        let (mut lo, mut hi, mut r2) = (Real::INFINITY, Real::NEG_INFINITY, 0.0 as Real);
        let (mut lo_v, mut hi_v) = (NO_VERTEX, NO_VERTEX);
        for &v in support {
            let p = &self.points[v as usize];
            let d = dir.dot(p);
            if d < lo {
                lo = d;
                lo_v = v;
            }
            if d > hi {
                hi = d;
                hi_v = v;
            }
            r2 = r2.max((p - center).norm_squared());
        }
        let mut min_dot: Real = 1.0;
        for &t in tris {
            min_dot = min_dot.min(self.tri_normals[t as usize].dot(&dir));
        }
        let mut witnesses = [NO_VERTEX; WITNESSES];
        witnesses[0] = lo_v;
        witnesses[1] = hi_v;
        Extent {
            dir,
            lo,
            hi,
            center,
            radius: r2.sqrt(),
            spread: min_dot.clamp(-1.0, 1.0).acos(),
            witnesses,
        }
    }

    /// The `WITNESSES / 2` lowest and highest distinct vertices of `candidates` along `dir`.
    pub(super) fn pick_witnesses<'b>(
        &self,
        candidates: impl Iterator<Item = &'b u32>,
        dir: &Vector3,
    ) -> [u32; WITNESSES] {
        // At most two extents' witnesses and two scan results: no allocation.
        let mut buf = [(0.0, NO_VERTEX); 2 * WITNESSES + 2];
        let mut n = 0;
        for &v in candidates.filter(|&&v| v != NO_VERTEX).take(buf.len()) {
            buf[n] = (dir.dot(&self.points[v as usize]), v);
            n += 1;
        }
        let all = &mut buf[..n];
        all.sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        // Equal vertices have equal projections, so duplicates are adjacent after sorting.
        let mut unique = 0;
        for i in 0..all.len() {
            if unique == 0 || all[unique - 1].1 != all[i].1 {
                all[unique] = all[i];
                unique += 1;
            }
        }
        let all = &all[..unique];
        let mut out = [NO_VERTEX; WITNESSES];
        if all.len() <= WITNESSES {
            for (slot, e) in out.iter_mut().zip(all) {
                *slot = e.1;
            }
        } else {
            let half = WITNESSES / 2;
            for k in 0..half {
                out[k] = all[k].1;
                out[half + k] = all[all.len() - 1 - k].1;
            }
        }
        out
    }

    pub(super) fn accepts(&self, e: &Extent) -> bool {
        e.hi - e.lo <= self.limits.h_max && e.spread < self.limits.max_facet_angle
    }

    fn new_cluster(&mut self, tris: Vec<u32>) -> u32 {
        let id = self.clusters.len() as u32;
        let mut m = self.tri_moments(tris[0]);
        for &t in &tris[1..] {
            m = m.add(&self.tri_moments(t));
        }
        let (normal, centroid) = m.plane();
        let extent = self.exact_extent(tris.iter(), normal, centroid);
        for &t in &tris {
            self.cluster_of[t as usize] = id;
        }
        let support: Vec<u32> = tris.iter().flat_map(|&t| self.tris[t as usize]).collect();
        self.clusters.push(Work {
            alive: true,
            closed: false,
            triangles: tris,
            moments: m,
            normal,
            centroid,
            pruned: support.len(),
            hulled: support.len(),
            support,
            extent,
        });
        self.stamp.push(0);
        id
    }

    /// Step 1 of Algorithm 1: every triangle not yet clustered is paired with its free
    /// neighbour whose normal is closest to its own (`SelectNeighborTriangle`), provided the
    /// pair respects the limits; otherwise it starts a cluster alone. Triangles are visited in
    /// canonical order ([`canonical_ranks`]), neighbours by decreasing normal agreement then
    /// canonical rank, so the clusters do not depend on the input's triangle order.
    pub fn step1(&mut self) {
        let mut order: Vec<u32> = (0..self.mesh.triangle_count() as u32).collect();
        order.sort_unstable_by_key(|&t| self.rank[t as usize]);
        for j in order {
            let j = j as usize;
            if self.cluster_of[j] != u32::MAX {
                continue;
            }
            let nj = self.tri_normals[j];
            let mut cands: Vec<(Real, u32)> = self
                .mesh
                .adjacency()
                .neighbours(j)
                .iter()
                .filter(|&&t| self.cluster_of[t as usize] == u32::MAX)
                .map(|&t| (nj.dot(&self.tri_normals[t as usize]), t))
                .collect();
            cands.sort_by(|a, b| {
                b.0.total_cmp(&a.0)
                    .then(self.rank[a.1 as usize].cmp(&self.rank[b.1 as usize]))
            });
            let mut chosen = None;
            for &(_, t) in &cands {
                let m = self.tri_moments(j as u32).add(&self.tri_moments(t));
                let (n, c) = m.plane();
                if self.accepts(&self.exact_extent([j as u32, t].iter(), n, c)) {
                    chosen = Some(t);
                    break;
                }
            }
            match chosen {
                Some(t) => self.new_cluster(vec![j as u32, t]),
                None => self.new_cluster(vec![j as u32]),
            };
        }
    }

    /// Tries merging cluster `a` into `x`; `None` when the result would break the limits or
    /// the optional normal constraint `(target, min_dot)`.
    pub(super) fn try_merge(
        &self,
        x: u32,
        a: u32,
        constraint: Option<(Vector3, Real)>,
    ) -> Option<Merged> {
        let mut scan = |normal: Vector3, centroid: Vector3| {
            let (cx, ca) = (&self.clusters[x as usize], &self.clusters[a as usize]);
            self.support_extent(
                cx.support.iter().chain(&ca.support),
                cx.triangles.iter().chain(ca.triangles.iter()),
                normal,
                centroid,
            )
        };
        self.try_merge_with(x, a, constraint, &mut scan)
    }

    /// [`Engine::try_merge`], measuring the union's exact extent along a normal with `exact`
    /// (normal, centroid) when the stored bounds cannot decide.
    pub(super) fn try_merge_with(
        &self,
        x: u32,
        a: u32,
        constraint: Option<(Vector3, Real)>,
        exact: &mut dyn FnMut(Vector3, Vector3) -> Extent,
    ) -> Option<Merged> {
        let (cx, ca) = (&self.clusters[x as usize], &self.clusters[a as usize]);
        let moments = cx.moments.add(&ca.moments);
        let (normal, centroid) = moments.plane();
        if let Some((target, min_dot)) = constraint
            && normal.dot(&target) < min_dot
        {
            return None;
        }
        let (ex, ea) = (&cx.extent, &ca.extent);
        // Lower bound: the union is at least as thick along `normal` as its witness vertices.
        // When they already exceed h_max the exact scan below would reject the merge too.
        let (mut w_lo, mut w_hi) = (Real::INFINITY, Real::NEG_INFINITY);
        for &v in ex
            .witnesses
            .iter()
            .chain(ea.witnesses.iter())
            .filter(|&&v| v != NO_VERTEX)
        {
            let d = normal.dot(&self.points[v as usize]);
            w_lo = w_lo.min(d);
            w_hi = w_hi.max(d);
        }
        if w_hi - w_lo > self.limits.h_max {
            return None;
        }
        // Conservative extent of the union along x's reference direction.
        let e = (ex.dir - ea.dir).norm();
        let off_a = ex.dir.dot(&ea.center) - ea.dir.dot(&ea.center);
        let lo = ex.lo.min(ea.lo + off_a - e * ea.radius);
        let hi = ex.hi.max(ea.hi + off_a + e * ea.radius);
        let radius = ex.radius.max((ea.center - ex.center).norm() + ea.radius);
        let spread = ex.spread.max(ea.spread + angle(&ea.dir, &ex.dir));
        let witnesses = [NO_VERTEX; WITNESSES];
        let mut bound = Extent {
            dir: ex.dir,
            lo,
            hi,
            center: ex.center,
            radius,
            spread,
            witnesses,
        };
        // Along the new normal the thickness grows by at most 2·|n' - n_ref|·R.
        let e_new = (normal - ex.dir).norm();
        let h_bound = (hi - lo) + 2.0 * e_new * radius;
        let spread_bound = spread + angle(&normal, &ex.dir);
        if h_bound <= self.limits.h_max && spread_bound < self.limits.max_facet_angle {
            bound.witnesses =
                self.pick_witnesses(ex.witnesses.iter().chain(&ea.witnesses), &normal);
            return Some(Merged {
                moments,
                normal,
                centroid,
                extent: bound,
            });
        }
        let mut exact = exact(normal, centroid);
        if !self.accepts(&exact) {
            return None;
        }
        let found = [exact.witnesses[0], exact.witnesses[1]];
        exact.witnesses = self.pick_witnesses(
            found.iter().chain(&ex.witnesses).chain(&ea.witnesses),
            &normal,
        );
        Some(Merged {
            moments,
            normal,
            centroid,
            extent: exact,
        })
    }

    fn push_neighbours(&mut self, x: u32, tris_from: u32, frontier: &mut Vec<u32>) {
        let adjacency = self.mesh.adjacency();
        let gen_in = self.generation;
        for &t in &self.clusters[tris_from as usize].triangles {
            for &nb in adjacency.neighbours(t as usize) {
                let c = self.cluster_of[nb as usize];
                if c == x || c == u32::MAX {
                    continue;
                }
                let w = &self.clusters[c as usize];
                if !w.alive || w.closed || self.stamp[c as usize] == gen_in {
                    continue;
                }
                // Stamped: in the frontier or rejected during this growth.
                self.stamp[c as usize] = gen_in;
                frontier.push(c);
            }
        }
    }

    /// Step 2 of Algorithm 1 for the cluster `x`: repeatedly merge the open neighbouring
    /// cluster whose normal is closest to `n_x` (`SelectNeighborCluster`) among those whose
    /// merge keeps `h ≤ h_max`, until none is left. With a constraint `(target, min_dot)`, the
    /// neighbours are ranked by closeness to `target` and merges must keep `n·target ≥ min_dot`
    /// (finger mode's opposite cluster). A neighbour rejected once is not retried during this
    /// growth. `x` is closed afterwards: later growths do not absorb it.
    pub fn grow(&mut self, x: u32, constraint: Option<(Vector3, Real)>) {
        self.generation += 1;
        self.stamp[x as usize] = self.generation;
        let mut frontier = Vec::new();
        self.push_neighbours(x, x, &mut frontier);
        while !frontier.is_empty() {
            let dir = constraint.map_or(self.clusters[x as usize].normal, |c| c.0);
            let mut best = 0usize;
            let mut best_key = (Real::NEG_INFINITY, u32::MAX);
            for (i, &c) in frontier.iter().enumerate() {
                let key = (self.clusters[c as usize].normal.dot(&dir), c);
                if key.0 > best_key.0 || (key.0 == best_key.0 && key.1 < best_key.1) {
                    best_key = key;
                    best = i;
                }
            }
            let a = frontier.swap_remove(best);
            let Some(m) = self.try_merge(x, a, constraint) else {
                continue;
            };
            // Neighbours of the absorbed triangles join the frontier (`a` itself is stamped).
            self.push_neighbours(x, a, &mut frontier);
            self.absorb(x, a, m);
        }
        self.clusters[x as usize].closed = true;
    }

    /// Moves cluster `a` into `x`, whose new moments, plane and extent are `m`.
    pub(super) fn absorb(&mut self, x: u32, a: u32, m: Merged) {
        let moved = std::mem::take(&mut self.clusters[a as usize].triangles);
        for &t in &moved {
            self.cluster_of[t as usize] = x;
        }
        self.clusters[a as usize].alive = false;
        let support = std::mem::take(&mut self.clusters[a as usize].support);
        let cx = &mut self.clusters[x as usize];
        cx.triangles.extend_from_slice(&moved);
        cx.moments = m.moments;
        cx.normal = m.normal;
        cx.centroid = m.centroid;
        cx.extent = m.extent;
        cx.support.extend(support);
        if cx.support.len() > SMALL_SUPPORT.max(2 * cx.pruned) {
            self.prune_support(x);
        }
    }

    /// Reduces cluster `x`'s support to its distinct vertices, and to the vertices of their
    /// convex hull when there are many (see [`HULL_SUPPORT`]) and the hull holds every one of
    /// them (see [`super::hull`]).
    fn prune_support(&mut self, x: u32) {
        self.seen_generation = self.seen_generation.wrapping_add(1);
        if self.seen_generation == 0 {
            self.seen.fill(0);
            self.seen_generation = 1;
        }
        let mut support = std::mem::take(&mut self.clusters[x as usize].support);
        let (seen, generation) = (&mut self.seen, self.seen_generation);
        support.retain(|&v| {
            let fresh = seen[v as usize] != generation;
            seen[v as usize] = generation;
            fresh
        });
        let hulled = self.clusters[x as usize].hulled;
        if support.len() > HULL_SUPPORT && support.len() > 4 * hulled {
            let points: Vec<Vector3> = support.iter().map(|&v| self.points[v as usize]).collect();
            if let Some(hull) = super::hull::convex_hull(&points)
                && hull.complete
            {
                support = hull
                    .vertices()
                    .iter()
                    .map(|&i| support[i as usize])
                    .collect();
            }
        }
        let cx = &mut self.clusters[x as usize];
        if support.len() > HULL_SUPPORT && support.len() > 4 * hulled {
            cx.hulled = support.len();
        }
        cx.pruned = support.len();
        cx.support = support;
    }

    /// Step-1 clusters in seed order: canonical order of their first triangle, i.e. their ids.
    /// (Ordering by area was tried: equal-area facets then come in an order set by rounding
    /// noise, which fragments a tessellated cylinder into uneven strips.)
    pub fn seed_order(&self) -> Vec<u32> {
        (0..self.clusters.len() as u32).collect()
    }
}

/// Lexicographic order of two points (x, then y, then z; total order on floats).
fn lex(a: &Point3, b: &Point3) -> std::cmp::Ordering {
    a.x.total_cmp(&b.x)
        .then(a.y.total_cmp(&b.y))
        .then(a.z.total_cmp(&b.z))
}

/// Canonical rank of every triangle: triangles sorted by their three vertex positions (each
/// triangle's positions sorted lexicographically, then compared lexicographically), ties
/// (coincident triangles) by index. Depends on the geometry only, not on the order of the
/// triangles or on the rotation of their vertices.
pub(crate) fn canonical_ranks(mesh: &TriMesh) -> Vec<u32> {
    let vertices = mesh.vertices();
    let keys: Vec<[Point3; 3]> = mesh
        .triangles()
        .iter()
        .map(|t| {
            let mut k = t.map(|v| vertices[v as usize]);
            k.sort_unstable_by(lex);
            k
        })
        .collect();
    let mut order: Vec<u32> = (0..keys.len() as u32).collect();
    order.sort_unstable_by(|&a, &b| {
        let (ka, kb) = (&keys[a as usize], &keys[b as usize]);
        lex(&ka[0], &kb[0])
            .then(lex(&ka[1], &kb[1]))
            .then(lex(&ka[2], &kb[2]))
            .then(a.cmp(&b))
    });
    let mut rank = vec![0u32; keys.len()];
    for (r, &t) in order.iter().enumerate() {
        rank[t as usize] = r as u32;
    }
    rank
}

#[cfg(test)]
mod tests;
