//! Algorithm 2 of the paper (§III-B.2): object posture candidates on the environment cluster
//! the user points at, with the stability test of Fig. 7.
//!
//! For each object region C_j: if its 2D bounding box fits in the environment region's
//! (`includeBoundingBox`), search face-face contacts (`searchFaceFaceContact`): the two contact
//! planes coincide with opposite normals, and positions and yaw angles are searched inside the
//! environment region, nearest to the target first. Otherwise search edge-face contacts
//! (`searchEdgeFaceContact`): a segment of the 2D convex hull of C_j's boundary is laid on the
//! environment's contact plane and the object is rotated about it until a second contact
//! appears (bisection on the tilt angle).
//!
//! Every pose must pass the stability test (Fig. 7, [`crate::stability`]): for face-face
//! contacts the common area of the two outer boundaries minus both regions' holes, its convex
//! hull, and the vertical through the CoG must pass inside it; for edge-face contacts the hull
//! of the segment and the points where C_j meets the environment. And it must not penetrate
//! the environment (parry3d-f64, with a small clearance; a convex object is tested as its
//! convex hull against the environment mesh, others mesh against mesh).
//!
//! Improvements over the paper: yaw steps finer than the original 2 or 4, visited spread over
//! the turn; positions searched on a grid in order of distance to the target so the first
//! candidates are the best ranked; the stability test asks for a minimum margin and a minimum
//! tipping angle, both reported; the candidates are diversified over the object's resting faces
//! ([`diversify`]); every rejection is counted with its reason; object regions and hull segments
//! that cannot pass the stability test are rejected by cheap bounds before any collision test.

use crate::collide::CollisionMesh;
use crate::region::Region;
use crate::stability;
use pickplace_geometry::cluster::Clustering;
use pickplace_geometry::math::{Isometry3, Point2, Point3, Real};
use pickplace_geometry::mesh::TriMesh;
use pickplace_geometry::polygon::signed_margin;

mod search;

use search::{RegionPair, search_edge_face, search_face_face, stable};

/// Options of the placement search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlacementOptions {
    /// Number of yaw angles tried per position, evenly spaced over a full turn (default: 16).
    pub yaw_steps: usize,
    /// Spacing of candidate positions on the environment region (m) (default: 0.005).
    pub position_step: Real,
    /// Maximum number of candidates kept per (object region, environment region) pair
    /// (default: 16). The yaws at a position are visited spread over the turn (0°, 180°, 90°,
    /// 270°, 45°, …), so the first variants of a face differ most.
    pub max_per_pair: usize,
    /// Number of candidates returned (default: 96). A soft cap: the list is in the diversified
    /// order (every resting face before further variants of one, see [`candidates`]) and is
    /// never cut below one placement per (object cluster, contact kind), so no cap hides a
    /// resting face.
    pub max_candidates: usize,
    /// Gap (m) between object and environment in the penetration test: the object is lifted
    /// by this much along the contact normal before testing (default: 0.0005).
    pub clearance: Real,
    /// Minimum stability margin (m): distance from the CoG's vertical to the support hull's
    /// boundary (default: [`DEFAULT_MIN_MARGIN`], 2 mm; see docs/placement.md for the drop tests
    /// behind it). Applied to face-face and edge-face placements alike.
    pub min_margin: Real,
    /// Steepest environment region that can hold the object (rad from horizontal)
    /// (default: 20°).
    pub max_slope: Real,
    /// Other upward-facing environment regions within this distance of the target (m) are
    /// searched too. The paper searches only the cluster the user clicked (default: 0.0).
    pub search_radius: Real,
    /// Edge-face search: largest tilt tried (rad) (default: 60°).
    pub max_tilt: Real,
    /// Edge-face search: the tilt is found to within this angle (rad) (default: 1e-4).
    pub tilt_tolerance: Real,
    /// Edge-face search: step of the coarse scan for the first free tilt, before the
    /// bisection (rad) (default: 3°).
    pub tilt_scan_step: Real,
    /// Edge-face search: hull segments tried per object region, the longest first (default: 4).
    pub edge_segments: usize,
    /// Edge-face search: positions of the segment on the environment region, spread over the
    /// whole region on a grid, nearest to the target first (default: 64).
    pub edge_positions: usize,
    /// A target point this far (m) from a region's plane still selects it (default: 0.01).
    pub target_tolerance: Real,
    /// Minimum tipping angle (rad): the object must rotate at least this much about the
    /// nearest edge of its support before its CoG crosses it, `atan(margin / cog height)`.
    /// A margin alone favours tall objects; this is the paper's Fig. 7 test made scale-aware
    /// (default: [`DEFAULT_MIN_TIPPING_ANGLE`], 6°; see docs/placement.md for the drop tests
    /// behind it). Applied to face-face and edge-face placements alike.
    pub min_tipping_angle: Real,
    /// Positions farther than this (m, in the environment region's plane) from the target are
    /// not searched (default: unbounded). A planner that accepts placements only within a
    /// tolerance of the target sets it, so that a large region (a table top) is not gridded
    /// and sorted whole, and the edge-face positions are spread over the disc around the
    /// target instead of the whole region.
    pub max_distance: Real,
}

impl Default for PlacementOptions {
    fn default() -> Self {
        Self {
            yaw_steps: 16,
            position_step: 0.005,
            max_per_pair: 16,
            max_candidates: 96,
            clearance: 5e-4,
            min_margin: DEFAULT_MIN_MARGIN,
            max_slope: 20f64.to_radians(),
            search_radius: 0.0,
            max_tilt: 60f64.to_radians(),
            tilt_tolerance: 1e-4,
            tilt_scan_step: 3f64.to_radians(),
            edge_segments: 4,
            edge_positions: 64,
            target_tolerance: 0.01,
            min_tipping_angle: DEFAULT_MIN_TIPPING_ANGLE,
            max_distance: Real::INFINITY,
        }
    }
}

/// Default minimum stability margin (m) of placements and resting poses: 2 mm, twice the
/// clustering's h_max (1 mm), so that the support the margin is measured on can be off by a
/// cluster's thickness and the CoG still falls inside. The milk carton upside down on
/// its 1.6 mm sealing fin (margin 0.8 mm) is refused by it (and by the tipping angle); released
/// 1° off, it falls over in the drop test (docs/placement.md).
pub const DEFAULT_MIN_MARGIN: Real = 0.002;

/// Default minimum tipping angle (rad): 6°. In the suite's drop test with both minimums at zero
/// (docs/placement.md), 40 of 2 372 placements move or turn too much, every one with a tipping
/// angle of at most 4.1° (margins up to 6.7 mm: a margin alone does not separate them); with
/// the defaults all 1 748 hold. Columns released 3° off tip over at a tipping angle of 2°,
/// balance on their edge at 3° and settle back from 3.5° on.
pub const DEFAULT_MIN_TIPPING_ANGLE: Real = 6.0 * std::f64::consts::PI / 180.0;

/// How the object touches the environment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ContactKind {
    /// A face of the object lies on the environment's contact plane.
    FaceFace,
    /// The object rests on an edge of its contact region, tilted onto a second contact.
    EdgeFace,
}

/// A stable placement of the object.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Placement {
    /// Object pose in the world.
    pub world_from_object: Isometry3,
    /// Contact type.
    pub contact: ContactKind,
    /// Object cluster in contact.
    pub object_cluster: usize,
    /// Environment cluster in contact.
    pub env_cluster: usize,
    /// Distance from the CoG's vertical to the support hull's boundary (m) (Fig. 7).
    pub stability_margin: Real,
    /// Angle (rad) the object must turn about the nearest edge of its support before its CoG
    /// crosses it: `atan(stability_margin / h)`, `h` the CoG's height above the contact plane.
    pub tipping_angle: Real,
    /// Horizontal distance (m) from the target point to the vertical line through the placed
    /// object's CoG: `hypot(c.x - t.x, c.y - t.y)` with `c = world_from_object * cog` and `t`
    /// the target, world frame (gravity along −z). The validator measures the same.
    pub distance_to_target: Real,
    /// Tilt of the object's contact plane from the environment's (rad; 0 for face-face).
    pub tilt: Real,
}

/// The object as the placement planner sees it.
#[derive(Debug)]
pub struct ObjectModel {
    /// Contact regions (environment-contact clusters) in the object frame; a region the object
    /// can rest on lies on the plane of its resting facet, its support under the contact model
    /// ([`ObjectModel::new`]).
    pub regions: Vec<Region>,
    /// For each region, the object's tipping angle (rad) resting on it, as its convex hull
    /// decides it ([`stability::hull_tipping_angle`]): it caps the tipping angle of the
    /// stability test, which a tolerance support alone would overstate on a curved surface.
    pub tipping_limits: Vec<Real>,
    /// Centre of gravity (object frame).
    pub cog: Point3,
    /// Vertices of the object's convex hull (object frame).
    pub hull: Vec<Point3>,
    /// For each region, the rigid part of its support: the 2D hull (region plane coordinates)
    /// of the object's points within [`RIGID_TOLERANCE`] of its plane. An edge-face contact
    /// (Fig. 6(d)) lays an edge of it on the environment: an edge is rigid, a tolerance band
    /// of a curved surface is not.
    pub rigid_supports: Vec<Vec<Point2>>,
    /// Collision mesh (object frame).
    pub collision: CollisionMesh,
    /// For each region, whether it can touch a plane at all: no other region's boundary lies
    /// more than 2 mm beyond its plane (computed once, as the model is made).
    pub supporting: Vec<bool>,
}

/// The contact model's tolerance (m) for the object's supports:
/// [`stability::CONTACT_TOLERANCE`].
pub const CONTACT_TOLERANCE: Real = stability::CONTACT_TOLERANCE;

/// Points this close (m) to a plane lie on it rigidly: the edges of edge-face contacts and their
/// second contacts (0.1 mm).
pub const RIGID_TOLERANCE: Real = 1e-4;

/// A region whose plane is within this angle (rad) of a resting facet's is moved onto it
/// (10°, the resting poses' duplicate angle).
const SNAP_ANGLE: Real = 0.174_532_925_199_432_95;

impl ObjectModel {
    /// The object of `mesh` with its environment-contact clustering (paper §III-A, h_max
    /// 1 mm by default) and its centre of gravity, all in the object frame.
    ///
    /// The contact model (issue 31): an object on a plane touches it where its convex hull
    /// does. Each region within 10° of a facet the object rests on ([`crate::resting_poses`]
    /// with no minimums) is moved onto that facet's plane, and its support is the hull of the
    /// object's points within [`CONTACT_TOLERANCE`] of the plane; the stability minimums are
    /// applied by the searches.
    ///
    /// # Errors
    /// [`crate::Error::NonFiniteCog`] for a CoG that is not finite.
    pub fn new(mesh: &TriMesh, clustering: &Clustering, cog: Point3) -> crate::Result<Self> {
        if !cog.coords.iter().all(|c| c.is_finite()) {
            return Err(crate::Error::NonFiniteCog {
                x: cog.x,
                y: cog.y,
                z: cog.z,
            });
        }
        let identity = Isometry3::identity();
        let hull = crate::resting::hull_points(mesh.vertices()).unwrap_or_default();
        let rests = crate::resting_poses(
            mesh,
            &cog,
            &crate::RestingOptions {
                min_margin: 0.0,
                min_tipping_angle: 0.0,
                include_rolling: false,
                ..Default::default()
            },
        )
        .unwrap_or_default();
        // Each cluster's region and the resting facet it lies on, if any; of several regions on
        // one facet (the patches of a scanned base) the largest stands for it.
        let snapped: Vec<(Region, Option<usize>)> = clustering
            .clusters
            .iter()
            .filter_map(|c| Region::from_cluster_on_mesh(c, mesh, &identity, CONTACT_TOLERANCE))
            .map(|region| {
                let n = region.normal();
                let o = region.parent_from_plane.translation.vector;
                // A rest whose plane the region lies on (within twice the tolerance): not the
                // inside of a cup under its rim's plane.
                let rest = (0..rests.len())
                    .filter(|&r| rests[r].support_normal.dot(&n) > SNAP_ANGLE.cos())
                    .filter(|&r| {
                        let m = &rests[r].support_normal;
                        let offset = m.dot(&cog.coords) + rests[r].cog_height;
                        (m.dot(&o) - offset).abs() <= 2.0 * CONTACT_TOLERANCE
                    })
                    .max_by(|&a, &b| {
                        rests[a]
                            .support_normal
                            .dot(&n)
                            .total_cmp(&rests[b].support_normal.dot(&n))
                    });
                (region, rest)
            })
            .collect();
        let mut largest = std::collections::BTreeMap::<usize, usize>::new();
        for (i, (region, rest)) in snapped.iter().enumerate() {
            if let Some(r) = rest {
                let best = largest.entry(*r).or_insert(i);
                if region.area > snapped[*best].0.area {
                    *best = i;
                }
            }
        }
        let mut regions = Vec::new();
        let mut tipping_limits = Vec::new();
        let mut rigid_supports = Vec::new();
        for (i, (region, rest)) in snapped.into_iter().enumerate() {
            let region = match rest {
                Some(r) if largest.get(&r) != Some(&i) => continue,
                Some(r) if rests[r].support_normal.dot(&region.normal()) < 1.0 - 1e-12 => {
                    let rest = &rests[r];
                    let offset = rest.support_normal.dot(&cog.coords) + rest.cog_height;
                    region
                        .on_plane(&rest.support_normal, offset, &hull, CONTACT_TOLERANCE)
                        .unwrap_or(region)
                }
                _ => region,
            };
            // Only a plane that no hull point crosses by more than the tolerance can carry it.
            let n = region.normal();
            let offset = n.dot(&region.parent_from_plane.translation.vector);
            let supports = hull
                .iter()
                .all(|p| n.dot(&p.coords) - offset <= CONTACT_TOLERANCE);
            let rigid: Vec<Point2> = hull
                .iter()
                .filter(|p| offset - n.dot(&p.coords) <= RIGID_TOLERANCE)
                .map(|p| region.to_plane(p).0)
                .collect();
            rigid_supports.push(pickplace_geometry::polygon::convex_hull(&rigid));
            tipping_limits.push(if supports {
                stability::hull_tipping_angle(&hull, &cog, &n)
            } else {
                0.0
            });
            regions.push(region);
        }
        Ok(Self {
            supporting: supporting_regions(&regions),
            regions,
            tipping_limits,
            cog,
            hull,
            rigid_supports,
            collision: CollisionMesh::new(mesh)?,
        })
    }

    /// The stability margin (m) of a face-face contact on object region `index` with support
    /// `margin`, capped by the region's hull tipping angle at CoG height `height`.
    pub fn capped_margin(&self, index: usize, margin: Real, height: Real) -> Real {
        let limit = self.tipping_limits.get(index).copied().unwrap_or(0.0);
        margin.min(height.max(1e-9) * limit.tan())
    }
}

impl EnvironmentModel {
    /// The environment of `mesh` placed at `world_from_env`, with its environment-contact
    /// clustering (computed in the mesh frame, so a cached database serves every pose).
    ///
    /// # Errors
    /// Only on an internally inconsistent mesh (see [`CollisionMesh::new`]).
    pub fn new(
        mesh: &TriMesh,
        clustering: &Clustering,
        world_from_env: &Isometry3,
    ) -> crate::Result<Self> {
        Self::from_parts(&[(mesh, clustering, *world_from_env)])
    }

    /// Several environment meshes, each with its clustering and pose, seen as one environment.
    /// Region [`Region::cluster_id`]s are numbered across the meshes in order (the clusters of
    /// the second mesh follow those of the first).
    ///
    /// # Errors
    /// Only on an internally inconsistent mesh (see [`CollisionMesh::new`]).
    pub fn from_parts(parts: &[(&TriMesh, &Clustering, Isometry3)]) -> crate::Result<Self> {
        let mut regions = Vec::new();
        let mut offset = 0;
        for (_, clustering, pose) in parts {
            for c in &clustering.clusters {
                if let Some(mut r) = Region::from_cluster(c, pose) {
                    r.cluster_id += offset;
                    regions.push(r);
                }
            }
            offset += clustering.clusters.len();
        }
        let meshes: Vec<(&TriMesh, Isometry3)> =
            parts.iter().map(|(m, _, pose)| (*m, *pose)).collect();
        Ok(Self {
            regions,
            collision: CollisionMesh::from_meshes(&meshes)?,
        })
    }
}

/// The environment as the placement planner sees it.
#[derive(Debug)]
pub struct EnvironmentModel {
    /// Contact regions in the world frame.
    pub regions: Vec<Region>,
    /// Collision mesh in the world frame.
    pub collision: CollisionMesh,
}

/// Why candidates were rejected on one environment cluster.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct Rejections {
    /// Object regions whose bounding box did not fit and whose edge-face search found no pose.
    pub did_not_fit: usize,
    /// Poses whose CoG vertical missed the support hull (or came too close to its boundary).
    pub unstable: usize,
    /// Poses where the object penetrated the environment.
    pub penetrates: usize,
    /// Poses accepted.
    pub accepted: usize,
}

/// The result of a placement search.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct PlacementSet {
    /// Environment cluster the target selected.
    pub target_cluster: usize,
    /// Candidates in the diversified order ([`diversify`]): the best placement of every
    /// resting face (object cluster, contact kind) first, faces ordered by their best
    /// placement's rank (distance to the target, then stability margin), then the second best
    /// of every face, and so on.
    pub placements: Vec<Placement>,
    /// Rejection counts per environment cluster searched (cluster id, counts).
    pub rejections: Vec<(usize, Rejections)>,
}

/// The target point is on no environment cluster.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "target point ({:.4}, {:.4}, {:.4}) is on no upward-facing environment cluster; the nearest is cluster {nearest_cluster}, {distance:.4} m away",
    target.x, target.y, target.z
)]
pub struct TargetError {
    /// The target point.
    pub target: Point3,
    /// The nearest upward-facing cluster, if any.
    pub nearest_cluster: usize,
    /// Its distance to the target (m).
    pub distance: Real,
}

fn upward(region: &Region, options: &PlacementOptions) -> bool {
    region.normal().z >= options.max_slope.cos()
}

/// Distance from `p` to a region (m): height above its plane combined with the 2D distance
/// outside its polygon.
fn distance_to_region(region: &Region, p: &Point3) -> Real {
    let (q, h) = region.to_plane(p);
    let outside = if region.polygon.contains(&q) {
        0.0
    } else {
        (-signed_margin(&q, &region.polygon.outer)).max(0.0)
    };
    (h * h + outside * outside).sqrt()
}

/// A target for when the user gives none: the centre of the environment's largest
/// upward-facing region (ties: the lowest cluster id), world frame. The centroid of a region
/// with holes may fall in a hole; the centre of the region's bounding rectangle is taken then.
/// `None` when no region faces up (within [`PlacementOptions::max_slope`]).
pub fn default_target(env: &EnvironmentModel, options: &PlacementOptions) -> Option<Point3> {
    env.regions
        .iter()
        .filter(|r| upward(r, options))
        .max_by(|a, b| {
            a.area
                .total_cmp(&b.area)
                .then(b.cluster_id.cmp(&a.cluster_id))
        })
        .and_then(|r| {
            let c = r.polygon.centroid()?;
            let c = if r.polygon.contains(&c) {
                c
            } else {
                r.rect.center
            };
            Some(r.parent_from_plane * Point3::new(c.x, c.y, 0.0))
        })
}

/// The environment cluster the target selects (the paper's click): the upward-facing region
/// that contains the target's projection, nearest to its plane.
///
/// # Errors
/// [`TargetError`] naming the nearest upward-facing cluster and its distance.
pub fn select_target(
    env: &EnvironmentModel,
    target: &Point3,
    options: &PlacementOptions,
) -> Result<usize, TargetError> {
    let mut best: Option<(Real, usize)> = None;
    let mut nearest: Option<(Real, usize)> = None;
    for (i, r) in env
        .regions
        .iter()
        .enumerate()
        .filter(|(_, r)| upward(r, options))
    {
        let (q, h) = r.to_plane(target);
        if h.abs() <= options.target_tolerance
            && r.polygon.contains(&q)
            && best.is_none_or(|(d, _)| h.abs() < d)
        {
            best = Some((h.abs(), i));
        }
        let d = distance_to_region(r, target);
        if nearest.is_none_or(|(nd, _)| d < nd) {
            nearest = Some((d, i));
        }
    }
    match (best, nearest) {
        (Some((_, i)), _) => Ok(i),
        (None, Some((d, i))) => Err(TargetError {
            target: *target,
            nearest_cluster: env.regions[i].cluster_id,
            distance: d,
        }),
        (None, None) => Err(TargetError {
            target: *target,
            nearest_cluster: usize::MAX,
            distance: Real::INFINITY,
        }),
    }
}

/// Candidate placements of the object near `target` (Algorithm 2).
///
/// Every placement passes the stability test (Fig. 7) with [`PlacementOptions::min_margin`]
/// and [`PlacementOptions::min_tipping_angle`], face-face and edge-face alike. The placements
/// of each resting face (object cluster, contact kind) are ranked by distance to the target,
/// then by margin ([`rank`]); the list is in the diversified order of [`diversify`]: the best
/// placement of every face first, then the second best of every face, and so on, cut to
/// [`PlacementOptions::max_candidates`] but never below one placement per face.
///
/// # Errors
/// [`TargetError`] when the target is on no environment cluster. An empty
/// [`PlacementSet::placements`] with its rejection counts means no stable placement exists
/// (the CLI exits 1).
///
/// # Performance
/// Positions are visited nearest to the target first and each (object region, environment
/// region) pair stops after [`PlacementOptions::max_per_pair`] accepted poses, so the cost is
/// bounded by the candidates asked for, not by the size of the environment region.
pub fn candidates(
    object: &ObjectModel,
    env: &EnvironmentModel,
    target: &Point3,
    options: &PlacementOptions,
) -> Result<PlacementSet, TargetError> {
    let target_index = select_target(env, target, options)?;
    let mut env_indices: Vec<usize> = vec![target_index];
    let mut others: Vec<(Real, usize)> = env
        .regions
        .iter()
        .enumerate()
        .filter(|&(i, r)| i != target_index && upward(r, options))
        .map(|(i, r)| (distance_to_region(r, target), i))
        .filter(|&(d, _)| d <= options.search_radius)
        .collect();
    others.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    env_indices.extend(others.into_iter().map(|(_, i)| i));

    let supporting = &object.supporting;
    let mut placements = Vec::new();
    let mut rejections = Vec::new();
    for &e in &env_indices {
        let env_region = &env.regions[e];
        let mut counts = Rejections::default();
        for (o, object_region) in object.regions.iter().enumerate() {
            if !supporting[o] {
                continue;
            }
            if object_region.support.len() < 3 {
                // Only a line of the region touches its plane (a strip of a tessellated
                // cylinder): the object would roll on it, face-face or edge-face.
                counts.unstable += 1;
                continue;
            }
            let pair = RegionPair {
                object,
                o: object_region,
                o_index: o,
                env,
                e: env_region,
                target,
                options,
            };
            let found = if include_bounding_box(object_region, env_region) {
                if !face_face_can_be_stable(object, o, options) {
                    // No pose of this region can pass the stability test (Fig. 7): its support
                    // is too narrow for the margin (a strip of a tessellated cylinder).
                    counts.unstable += 1;
                    continue;
                }
                search_face_face(&pair, &mut counts)
            } else {
                let found = search_edge_face(&pair, &mut counts);
                if found.is_empty() {
                    counts.did_not_fit += 1;
                }
                found
            };
            counts.accepted += found.len();
            placements.extend(found);
        }
        rejections.push((env_region.cluster_id, counts));
    }
    placements.sort_by_key(|a| rank(a, object));
    let placements = diversify(placements, options.max_candidates);
    Ok(PlacementSet {
        target_cluster: env.regions[target_index].cluster_id,
        placements,
        rejections,
    })
}

/// Stable placements for a regrasp (Wan and Harada's regrasp graph: the object put down in an
/// intermediate pose and picked again with another grasp): [`candidates`] on the upward-facing
/// environment region under `around` and on every other one within `radius` (m) of it, with
/// every resting face of the object that can stand there represented (the diversified order
/// and the soft cap of [`PlacementOptions::max_candidates`] keep at least one placement per
/// face). The placements are as robust as any other (the same minimum margin and tipping
/// angle); each reports its `distance_to_target` from `around`.
///
/// # Errors
/// [`TargetError`] when `around` is on no upward-facing environment region.
pub fn intermediate_placements(
    object: &ObjectModel,
    env: &EnvironmentModel,
    around: &Point3,
    radius: Real,
    options: &PlacementOptions,
) -> Result<PlacementSet, TargetError> {
    let options = PlacementOptions {
        search_radius: radius.max(options.search_radius),
        ..*options
    };
    candidates(object, env, around, &options)
}

/// The resting face of a placement for [`diversify`]: its object cluster and contact kind.
pub fn face_of(p: &Placement) -> (usize, ContactKind) {
    (p.object_cluster, p.contact)
}

/// The diversified order of placements already sorted best first: round-robin over the resting
/// faces ([`face_of`]), the faces in the order of their best placement, each face's variants
/// best first. Round 0 holds the best placement of every face, round 1 the second best of every
/// face that has one, and so on. The list is then cut to `max` placements, but never below one
/// placement per face: no cap hides a resting face.
pub fn diversify(sorted: Vec<Placement>, max: usize) -> Vec<Placement> {
    let mut faces: Vec<((usize, ContactKind), Vec<Placement>)> = Vec::new();
    for p in sorted {
        let key = face_of(&p);
        match faces.iter_mut().find(|(k, _)| *k == key) {
            Some((_, list)) => list.push(p),
            None => faces.push((key, vec![p])),
        }
    }
    let keep = max.max(faces.len());
    let mut queues: Vec<std::vec::IntoIter<Placement>> = faces
        .into_iter()
        .map(|(_, list)| list.into_iter())
        .collect();
    let mut out = Vec::new();
    while out.len() < keep {
        let before = out.len();
        for q in &mut queues {
            if out.len() >= keep {
                break;
            }
            if let Some(p) = q.next() {
                out.push(p);
            }
        }
        if out.len() == before {
            break;
        }
    }
    out
}

/// Ranking key of a placement (smaller is better): the distance to the target, then the
/// stability margin (larger first), each compared at [`RANK_RESOLUTION`] so that poses equal to
/// within a tenth of a millimetre fall through to the next criterion; then the CoG's height
/// (lower first: the mug stands on its base rather than on its rim), then the
/// object cluster, for a total deterministic order.
pub fn rank(p: &Placement, object: &ObjectModel) -> (i64, i64, i64, usize, usize) {
    let q = |x: Real| (x / RANK_RESOLUTION).round() as i64;
    let cog_z = (p.world_from_object * object.cog).z;
    (
        q(p.distance_to_target),
        -q(p.stability_margin),
        q(cog_z),
        p.object_cluster,
        p.env_cluster,
    )
}

/// Resolution (m) at which distances and margins are compared when ranking (0.1 mm).
pub const RANK_RESOLUTION: Real = 1e-4;

/// Which object regions can touch a plane at all: every other object region lies on the inner
/// side of the region's contact plane. Checked on the regions' boundary points (cheap and exact
/// for clusters on the convex hull, such as a can's caps or a box's faces), through the
/// vertices of their convex hull: the farthest point along a normal is a hull vertex, so the
/// answer is the one over every boundary point, at a cost in the hull's size (a scanned object
/// has tens of thousands of boundary points and a few hundred hull vertices).
pub(crate) fn supporting_regions(regions: &[Region]) -> Vec<bool> {
    let tolerance = 0.002;
    let boundary: Vec<Point3> = regions
        .iter()
        .flat_map(|r| {
            r.polygon
                .outer
                .iter()
                .map(|q| r.parent_from_plane * Point3::new(q.x, q.y, 0.0))
        })
        .collect();
    // A flat or degenerate set has no 3D hull: every point is then checked.
    let extreme = crate::resting::hull_points(&boundary).unwrap_or(boundary);
    regions
        .iter()
        .map(|r| {
            let (n, origin) = (r.normal(), r.parent_from_plane.translation.vector);
            extreme
                .iter()
                .all(|p| n.dot(&(p.coords - origin)) <= tolerance)
        })
        .collect()
}

/// A bound checked before any face-face pose of object region `o` is tried: the support hull
/// of a face-face contact is the object's support intersected with the environment's region
/// (Fig. 7), so it lies inside the object's support, and the margin of the CoG can be no
/// larger than half the support's width (half the short side of its minimum-area rectangle,
/// which is at least the width). The CoG's height above the contact plane is the same for
/// every face-face pose, so the tipping-angle bound follows.
/// The bound is capped by the region's hull tipping angle ([`ObjectModel::tipping_limits`]).
pub(crate) fn face_face_can_be_stable(
    object: &ObjectModel,
    index: usize,
    options: &PlacementOptions,
) -> bool {
    let o = &object.regions[index];
    let Some(rect) = pickplace_geometry::polygon::min_area_rect(&o.support) else {
        return false;
    };
    let height = -o.to_plane(&object.cog).1;
    let bound = object.capped_margin(index, 0.5 * rect.sorted_sides().0, height) + 1e-9;
    stable(bound, height, options)
}

/// includeBoundingBox (paper Fig. 6(b), (d)): the object's 2D bounding box fits in the
/// environment's, in either orientation (side lengths compared sorted).
pub fn include_bounding_box(object: &Region, env: &Region) -> bool {
    let (os, ol) = object.rect.sorted_sides();
    let (es, el) = env.rect.sorted_sides();
    os <= es && ol <= el
}

/// The horizontal distance (m) between two world points: the length of their difference
/// projected on the xy plane (gravity along −z). [`Placement::distance_to_target`] is this
/// distance between the placed CoG and the target.
pub fn horizontal_distance(a: &Point3, b: &Point3) -> Real {
    (a.x - b.x).hypot(a.y - b.y)
}

#[cfg(test)]
mod tests;
