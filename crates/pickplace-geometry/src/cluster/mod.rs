//! Surface clustering: Harada et al., §III-A, Algorithm 1.
//!
//! The surface is cut into clusters of edge-connected triangles whose vertices lie within a
//! slab of thickness `h ≤ h_max` along the cluster's contact-plane normal: a gripper pad or a
//! support surface covered by a flexible sheet of depth `h_max` touches the whole cluster.
//!
//! For each cluster: the regression plane `P` (area-weighted least squares), the contact plane
//! `S` parallel to `P` touching the surface from outside, its outer normal `n`, the thickness
//! `h`, a 2D frame on `S`, the outer boundary and the holes as polygons, the 2D convex hull, the
//! minimum-area bounding rectangle and the area ([`Cluster`]).
//!
//! Two modes ([`ContactMode`]):
//! - **environment** (§III-A.2): Step 1, then Step 2 from every Step-1 cluster in turn;
//! - **finger** (§III-A.1, after the paper's ref. \[15\]): from a seed cluster grow `C_x`, cast a
//!   ray from its centroid through the object along `-n_x`, grow the cluster at the antipode
//!   keeping its normal opposite to `n_x`; every Step-1 cluster not yet used becomes a seed in
//!   turn. Once the clusters are final, every cluster casts its ray and pairs
//!   ([`ClusterPair`]) with the opposite clusters it meets, with the distance between the
//!   planes and the overlap of the two regions.
//!
//! After growth a final pass merges adjacent clusters while the union is still a cluster along
//! its regression plane or, failing that, along any admissible plane (issue 31: `merge.rs`,
//! `slab.rs`), until no adjacent pair can be merged; [`audit_adjacent_pairs`] counts, for any
//! clustering, the adjacent pairs that could still be merged. In finger mode every final cluster then casts
//! its own ray and pairs with every opposite cluster where the ray leaves the object more than
//! [`MIN_WALL_THICKNESS`] away (so the outer walls of an open, thin-walled mesh pair across the object).
//!
//! Everything is deterministic and independent of the input's triangle order and of the
//! vertex rotation within triangles: triangles are visited in a canonical order of their
//! vertex positions, seeds are the Step-1 clusters in that order, neighbours by decreasing
//! normal agreement then canonical rank. A fitted plane whose normal turns more than
//! [`MAX_FIT_DEVIATION`] from the area-weighted normal of the cluster's triangles is
//! ill-conditioned and replaced by that normal.
//!
//! # Example
//! ```
//! use pickplace_geometry::cluster::{cluster_surface, ClusterParams};
//! use pickplace_geometry::shapes::box_mesh;
//!
//! let mesh = box_mesh([0.05, 0.03, 0.02]);
//! let clustering = cluster_surface(&mesh, &ClusterParams::finger())?;
//! assert_eq!(clustering.clusters.len(), 6);
//! assert_eq!(clustering.pairs.len(), 3);
//! # Ok::<(), pickplace_geometry::Error>(())
//! ```

mod audit;
mod geometry;
mod grow;
mod hull;
mod json;
mod merge;
mod pairs;
mod rays;
mod slab;
mod width;

pub use audit::{AUDIT_MARGIN, MergeAudit, MergeablePair, audit_adjacent_pairs};
pub use geometry::PlaneFrame;
pub use grow::MAX_FIT_DEVIATION;
pub use json::{CLUSTERS_JSON_FORMAT, ClusterJson, ClusterPairJson, ClustersJson};
pub use pairs::MIN_WALL_THICKNESS;

use crate::error::{Error, Result};
use crate::math::{Point2, Point3, Real, Vector3};
use crate::mesh::TriMesh;
use crate::polygon::{Polygon, Rect2};
use grow::{Engine, Limits};

/// Version of what [`cluster_surface`] computes. Bump it whenever the clusters or pairs of
/// some mesh change (a new rule in the growth, the merge pass, the pairing, the plane fit):
/// it is part of every cluster database's name ([`crate::db::cache_path`]) and header, so a
/// newer build never reuses the clusters an older algorithm computed (2: triangles stored twice
/// are welded when a mesh is built, issue 31, so a mesh's triangle indices can change; 3: the
/// final merge pass merges along any admissible plane, issue 31).
pub const ALGORITHM_VERSION: u32 = 3;

/// Units of work [`cluster_surface_with_progress`] reports: `done` runs from 0 to this total.
pub const PROGRESS_TOTAL: usize = 1000;

/// Which contact the clusters are made for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactMode {
    /// Object-environment contact (§III-A.2): clusters only.
    Environment,
    /// Finger-object contact (§III-A.1): clusters and pairs of opposite parallel clusters.
    Finger,
}

impl ContactMode {
    /// Short name: "env" or "finger".
    pub fn name(self) -> &'static str {
        match self {
            Self::Environment => "env",
            Self::Finger => "finger",
        }
    }
}

/// Clustering parameters.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClusterParams {
    /// Contact mode (default: [`ContactMode::Environment`]).
    pub mode: ContactMode,
    /// Maximum thickness `h_max` of a cluster along its normal, i.e. the depth of the flexible
    /// sheet (m) (default: 0.001 for environment contact, 0.005 for finger contact, the
    /// paper's values).
    pub h_max: Real,
    /// No triangle of a cluster may turn more than this angle away from the cluster normal
    /// (rad). Keeps the two sides of a wall thinner than `h_max` apart (default: 80°).
    pub max_facet_angle: Real,
    /// Two contact planes are "opposite" when their normals' dot product is at most this
    /// value (default: -0.95, about 18°).
    pub opposite_dot: Real,
}

impl Default for ClusterParams {
    fn default() -> Self {
        Self::environment()
    }
}

impl ClusterParams {
    /// The paper's environment-contact parameters (`h_max` = 0.001 m).
    pub fn environment() -> Self {
        Self {
            mode: ContactMode::Environment,
            h_max: 0.001,
            max_facet_angle: 80f64.to_radians(),
            opposite_dot: -0.95,
        }
    }

    /// The paper's finger-contact parameters (`h_max` = 0.005 m).
    pub fn finger() -> Self {
        Self {
            mode: ContactMode::Finger,
            h_max: 0.005,
            ..Self::environment()
        }
    }

    /// Checks every value.
    ///
    /// # Errors
    /// [`Error::InvalidParameter`] naming the first bad value.
    pub fn validate(&self) -> Result<()> {
        let check = |name: &'static str, value: Real, ok: bool, reason: &'static str| {
            if ok {
                Ok(())
            } else {
                Err(Error::InvalidParameter {
                    name,
                    value,
                    reason,
                })
            }
        };
        check(
            "h_max",
            self.h_max,
            self.h_max.is_finite() && self.h_max >= 0.0,
            "must be finite and non-negative",
        )?;
        check(
            "max_facet_angle",
            self.max_facet_angle,
            self.max_facet_angle > 0.0 && self.max_facet_angle <= std::f64::consts::FRAC_PI_2,
            "must be in (0, π/2] rad",
        )?;
        check(
            "opposite_dot",
            self.opposite_dot,
            (-1.0..=0.0).contains(&self.opposite_dot),
            "must be in [-1, 0]",
        )
    }
}

/// One cluster: a planar contact region of the surface.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Cluster {
    /// Index in [`Clustering::clusters`].
    pub id: u32,
    /// Triangles of the welded mesh (indices into [`TriMesh::triangles`]), increasing.
    pub triangles: Vec<u32>,
    /// Unit outer normal `n` of the contact plane `S`.
    pub normal: Vector3,
    /// Area centroid of the triangles (on the surface side of `S`).
    pub centroid: Point3,
    /// The centroid projected onto `S`: a point of the contact plane (m).
    pub point: Point3,
    /// Thickness of the cluster's vertices along `n` (m); `S` touches the outermost ones.
    pub h: Real,
    /// Surface area of the triangles (m²).
    pub area: Real,
    /// 2D frame on `S` (origin at [`Cluster::point`]).
    pub frame: PlaneFrame,
    /// Outer boundary and holes projected onto `S`, in [`Cluster::frame`].
    pub region: Polygon,
    /// 2D convex hull of the region (counter-clockwise).
    pub hull: Vec<Point2>,
    /// Minimum-area bounding rectangle of the region (the paper's 2D bounding box).
    pub bounding_rect: Rect2,
}

impl Cluster {
    /// Signed distance of a point to the contact plane (positive outside).
    pub fn plane_distance(&self, p: &Point3) -> Real {
        self.normal.dot(&(p - self.point))
    }

    /// The outer boundary as 3D points on `S`.
    pub fn outer_boundary_3d(&self) -> Vec<Point3> {
        self.region
            .outer
            .iter()
            .map(|q| self.frame.to_3d(q))
            .collect()
    }

    /// The holes as 3D loops on `S`.
    pub fn holes_3d(&self) -> Vec<Vec<Point3>> {
        self.region
            .holes
            .iter()
            .map(|h| h.iter().map(|q| self.frame.to_3d(q)).collect())
            .collect()
    }
}

/// Two clusters with parallel, opposite contact planes: where a parallel gripper can close.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ClusterPair {
    /// The lower of the two cluster ids.
    pub first: u32,
    /// The higher of the two cluster ids.
    pub second: u32,
    /// Distance between the two contact planes (m), measured along their mean normal.
    pub width: Real,
    /// The second region projected onto the first's contact plane, intersected with the first
    /// region, in the first cluster's frame.
    pub overlap: Vec<Polygon>,
    /// Area of the overlap (m²).
    pub overlap_area: Real,
    /// Centre of the overlap on the mid-plane between the two contact planes (m).
    pub center: Point3,
    /// Unit closing axis: the first cluster's normal.
    pub axis: Vector3,
}

/// The result of clustering a mesh.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Clustering {
    /// Parameters used.
    pub params: ClusterParams,
    /// Clusters, ordered by the canonical rank of their first triangle (see the module
    /// documentation: by vertex positions, not by triangle index).
    pub clusters: Vec<Cluster>,
    /// Opposite cluster pairs (finger mode only), each once, ordered by `(first, second)`.
    pub pairs: Vec<ClusterPair>,
}

impl Clustering {
    /// For every triangle of the welded mesh, the id of its cluster.
    pub fn cluster_of_triangles(&self, triangle_count: usize) -> Vec<Option<u32>> {
        let mut out = vec![None; triangle_count];
        for c in &self.clusters {
            for &t in &c.triangles {
                if let Some(slot) = out.get_mut(t as usize) {
                    *slot = Some(c.id);
                }
            }
        }
        out
    }
}

/// The contact plane a cluster made of `triangles` of `mesh` would have: its unit outer
/// normal `n` (the regression plane of §III-A, or the area-weighted normal of the triangles
/// when the fit is ill-conditioned, see [`MAX_FIT_DEVIATION`]) and its area centroid. The
/// growth accepts a set of triangles exactly when their vertices lie within `h_max` along this
/// normal and every triangle is within `max_facet_angle` of it; the final merge pass tries
/// this plane first and, when it does not hold two adjacent clusters, any plane within
/// [`MAX_FIT_DEVIATION`] of their area-weighted normal (the merged cluster's normal is then
/// that plane's, not this one).
///
/// Returns `None` when `triangles` is empty or names a triangle `mesh` does not have.
pub fn fit_plane(mesh: &TriMesh, triangles: &[u32]) -> Option<(Vector3, Point3)> {
    let (lo, hi) = mesh.aabb();
    fit_plane_about(
        mesh,
        &Point3::from((lo.coords + hi.coords) * 0.5),
        triangles,
    )
}

/// [`fit_plane`] with the moments taken about `origin` (the clustering takes them about the
/// mesh's box centre): the same plane, without a pass over the mesh's vertices.
pub(crate) fn fit_plane_about(
    mesh: &TriMesh,
    origin: &Point3,
    triangles: &[u32],
) -> Option<(Vector3, Point3)> {
    let mut moments: Option<grow::Moments> = None;
    for &t in triangles {
        let tri = mesh.triangles().get(t as usize)?;
        let [a, b, c] = tri.map(|v| mesh.vertices()[v as usize] - origin);
        let m = grow::Moments::triangle(&a, &b, &c);
        moments = Some(match moments {
            Some(acc) => acc.add(&m),
            None => m,
        });
    }
    let (n, c) = moments?.plane();
    Some((n, origin + c))
}

/// Clusters a mesh's surface (Algorithm 1) in the mode of `params`.
///
/// # Errors
/// [`Error::InvalidParameter`] when `params` is invalid.
///
/// # Performance
/// Linear in the triangle count for flat regions, plus a sort of the triangles for the
/// canonical order; a merge is checked against stored extents first and scans the cluster's
/// vertices only when those cannot decide. The final merge pass lists the adjacent pairs once
/// per pass. Finger mode adds one ray cast (linear in the triangle count) per seed and per
/// final cluster.
pub fn cluster_surface(mesh: &TriMesh, params: &ClusterParams) -> Result<Clustering> {
    cluster_surface_with_progress(mesh, params, &|_, _| {})
}

/// [`cluster_surface`], telling `progress(done, total)` how far it got: `total` is
/// [`PROGRESS_TOTAL`], `done` grows with the seeds grown (most of the work) and reaches
/// `total` once, at the end. Called at most about a hundred times; the clusters are the same
/// as [`cluster_surface`]'s.
///
/// # Errors
/// As [`cluster_surface`].
pub fn cluster_surface_with_progress(
    mesh: &TriMesh,
    params: &ClusterParams,
    progress: &dyn Fn(usize, usize),
) -> Result<Clustering> {
    params.validate()?;
    // Step 1 up to 10 %, the growth from the seeds up to 80 %, the merge pass up to 90 %,
    // pairs and the clusters' geometry up to 100 %.
    let mut last = usize::MAX;
    let mut report = |done: usize| {
        if done / 10 != last / 10 || done == PROGRESS_TOTAL {
            last = done;
            progress(done, PROGRESS_TOTAL);
        }
    };
    report(0);
    let mut engine = Engine::new(
        mesh,
        Limits {
            h_max: params.h_max,
            max_facet_angle: params.max_facet_angle,
        },
    );
    engine.step1();
    report(100);
    let mut seed_done = |seed: usize, seeds: usize| report(100 + 700 * seed / seeds.max(1));
    match params.mode {
        ContactMode::Environment => {
            let seeds = engine.seed_order();
            for (i, &x) in seeds.iter().enumerate() {
                if engine.clusters[x as usize].alive && !engine.clusters[x as usize].closed {
                    engine.grow(x, None);
                }
                seed_done(i + 1, seeds.len());
            }
        }
        ContactMode::Finger => {
            pairs::grow_finger(&mut engine, params.opposite_dot, &mut seed_done);
        }
    }
    report(800);
    engine.merge_adjacent();
    report(900);
    let raw_pairs = match params.mode {
        ContactMode::Environment => Vec::new(),
        ContactMode::Finger => pairs::find_pairs(&engine, params.opposite_dot),
    };
    // Final ids: live clusters ordered by the canonical rank of their first triangle, so they
    // do not depend on the input's triangle order.
    for c in engine.clusters.iter_mut().filter(|c| c.alive) {
        c.triangles.sort_unstable();
    }
    let mut alive: Vec<(u32, u32)> = engine
        .clusters
        .iter()
        .enumerate()
        .filter(|(_, c)| c.alive)
        .map(|(i, c)| {
            let first = c
                .triangles
                .iter()
                .map(|&t| engine.rank[t as usize])
                .min()
                .unwrap_or(u32::MAX);
            (first, i as u32)
        })
        .collect();
    alive.sort_unstable();
    let mut new_id = vec![u32::MAX; engine.clusters.len()];
    let mut clusters = Vec::with_capacity(alive.len());
    for (k, &(_, old)) in alive.iter().enumerate() {
        new_id[old as usize] = k as u32;
        clusters.push(geometry::finish_cluster(&engine, old, k as u32));
    }
    // Each pair once, the cluster with the lower final id first, ordered by ids.
    let mut ordered: Vec<(u32, u32)> = raw_pairs
        .into_iter()
        .map(|(a, b)| {
            let (a, b) = (new_id[a as usize], new_id[b as usize]);
            (a.min(b), a.max(b))
        })
        .collect();
    ordered.sort_unstable();
    ordered.dedup();
    let pairs = ordered
        .into_iter()
        .filter_map(|(a, b)| pairs::pair_geometry(&clusters[a as usize], &clusters[b as usize]))
        .collect();
    report(PROGRESS_TOTAL);
    Ok(Clustering {
        params: *params,
        clusters,
        pairs,
    })
}
