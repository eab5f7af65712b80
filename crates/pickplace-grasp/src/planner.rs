//! Grasp synthesis on parallel cluster pairs: Harada et al., §III-B.1, after their ref. \[15\].
//!
//! For every pair of opposite clusters found by finger-mode clustering (§III-A.1) whose width
//! fits the gripper, grasp centres are laid on a grid over the pair's overlap region, the
//! gripper is turned about the grasp axis to several approach directions, and each candidate is
//! checked (width at that point, pad tilt against the second plane, contact area, collision of
//! the fingers and the palm with the object), measured ([`GraspQuality`]) and scored. See
//! `docs/grasp.md` for the algorithm in full.

use crate::collide::ObjectCollider;
use crate::error::{Error, Result};
use crate::gripper::{GripperBox, GripperParams};
use crate::quality::{self, GraspQuality, ScoreModel};
use pad::{Footprint, Near};
use pickplace_geometry::cluster::{Cluster, ClusterPair, Clustering};
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::math::{
    Isometry3, Matrix3, Point2, Point3, Real, Translation3, UnitQuaternion, Vector2, Vector3,
    line_triangle,
};
use pickplace_geometry::mesh::{MassProperties, TriMesh};
use pickplace_geometry::polygon::Polygon;
use rayon::prelude::*;
use std::f64::consts::TAU;

mod options;
mod pad;

pub use options::GraspOptions;

/// One grasp: where the TCP goes on the object, how wide the gripper closes, how good it is.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Grasp {
    /// Pose of the TCP in the object frame.
    pub object_from_tcp: Isometry3,
    /// Distance between the pads when closed on the object (m).
    pub width: Real,
    /// Score in [0, 1], higher is better (see [`GraspOptions`] and `docs/grasp.md`).
    pub score: Real,
    /// Index of the cluster pair in [`Clustering::pairs`].
    pub pair: usize,
    /// Cluster touched by the pad on the TCP's `+closing` side.
    pub positive_cluster: u32,
    /// Cluster touched by the pad on the `−closing` side.
    pub negative_cluster: u32,
    /// Approach angle about the grasp axis, from the first cluster's frame axis `u` (rad).
    pub approach_angle: Real,
    /// The measured quality.
    pub quality: GraspQuality,
}

/// Why candidates were rejected, with counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
pub struct RejectionCounts {
    /// Pairs whose width does not fit the opening range (whole pairs, not candidates).
    pub pair_width: usize,
    /// Candidates whose width, measured on the mesh along the closing axis through the grasp
    /// centre, does not fit the opening range (the gripper opening by the clearance and the
    /// pad depth on each side), or whose grasp line misses one of the two contact patches.
    pub width: usize,
    /// Candidates whose pad on the second cluster turns away from that cluster's plane by more
    /// than `h_max` at a corner (the planes are not parallel enough), or where the contact
    /// patch under a pad rises more than `h_max` towards the pad above the contact point at
    /// the grasp centre: more than the pads' flexible sheet can absorb.
    pub pad_tilt: usize,
    /// Candidates with less than `min_contact_ratio` of the pad on both clusters.
    pub contact: usize,
    /// Candidates whose fingers would intersect the object.
    pub finger_collision: usize,
    /// Candidates whose palm would intersect the object.
    pub palm_collision: usize,
}

impl RejectionCounts {
    /// The non-zero counts with their reason, most frequent first (ties by reason):
    /// `("palm hits the object", 1452)`, …
    pub fn by_reason(&self) -> Vec<(&'static str, usize)> {
        let mut counts = [
            ("palm hits the object", self.palm_collision),
            ("finger hits the object", self.finger_collision),
            ("too wide or too narrow for the opening", self.width),
            ("surface too uneven under a pad", self.pad_tilt),
            ("too little pad contact", self.contact),
            ("surface pairs too wide or too narrow", self.pair_width),
        ];
        counts.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
        counts.into_iter().filter(|(_, n)| *n > 0).collect()
    }
}

impl std::fmt::Display for RejectionCounts {
    /// The non-zero counts, most frequent first: `palm hits the object ×1452, finger hits the
    /// object ×132, too wide or too narrow ×1`; `nothing rejected` when all are zero.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self
            .by_reason()
            .into_iter()
            .map(|(what, n)| format!("{what} ×{n}"))
            .collect();
        if parts.is_empty() {
            f.write_str("nothing rejected")
        } else {
            f.write_str(&parts.join(", "))
        }
    }
}

/// The result of grasp planning.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct GraspSet {
    /// Accepted grasps, best first (ties keep the generation order).
    pub grasps: Vec<Grasp>,
    /// Number of cluster pairs considered.
    pub pairs: usize,
    /// Number of candidates evaluated (grid points × approach directions × flips over the
    /// pairs that fit).
    pub candidates: usize,
    /// Rejections by reason.
    pub rejected: RejectionCounts,
}

/// The object prepared for grasp planning: its collision mesh (BVH built once) and its centre
/// of gravity. Immutable and `Send + Sync`; plan as often as needed.
#[derive(Debug, Clone)]
pub struct GraspPlanner {
    collider: ObjectCollider,
    /// The mesh's vertices and triangles, where the width is measured.
    vertices: Vec<Point3>,
    triangles: Vec<[u32; 3]>,
    center_of_mass: Point3,
    /// Half the diagonal of the object's bounding box (m): the torque arm's scale.
    radius: Real,
}

/// Why a candidate failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Rejection {
    Width,
    PadTilt,
    Contact,
    Finger,
    Palm,
}

/// One grasp centre of one pair, shared by its approach directions.
#[derive(Debug, Clone, Copy)]
struct Site {
    pair: usize,
    /// The centre in the first cluster's frame (on its contact plane).
    on_first: Point2,
}

impl GraspPlanner {
    /// Prepares `mesh` (the object, in its own frame).
    ///
    /// # Errors
    /// [`Error::CollisionMesh`] when parry rejects the mesh.
    pub fn new(mesh: &TriMesh) -> Result<Self> {
        let collider = ObjectCollider::new(mesh)?;
        let center_of_mass = MassProperties::of(mesh).center_of_mass;
        let (lo, hi) = mesh.aabb();
        let radius = (0.5 * (hi - lo).norm()).max(1e-9);
        Ok(Self {
            collider,
            vertices: mesh.vertices().to_vec(),
            triangles: mesh.triangles().to_vec(),
            center_of_mass,
            radius,
        })
    }

    /// The object's centre of gravity (uniform density), object frame (m).
    pub fn center_of_mass(&self) -> Point3 {
        self.center_of_mass
    }

    /// Plans the grasps of the object on the pairs of `clustering` (finger mode, computed on
    /// the same mesh) for `gripper`.
    ///
    /// # Arguments
    /// - `clustering`: finger-contact clusters and pairs of the object (§III-A.1).
    /// - `gripper`: the gripper (validated here).
    /// - `options`: grid, approach directions, clearance and score (validated here).
    ///
    /// # Returns
    /// The accepted grasps ranked by score, with counts of candidates and rejections.
    /// The output is the same for the same input, whatever the number of threads.
    ///
    /// # Errors
    /// [`Error::InvalidGripper`], [`Error::InvalidOption`], [`Error::MissingCluster`] when
    /// a pair names a cluster the clustering does not have, [`Error::ForeignClustering`] when a
    /// paired cluster names a triangle the planner's mesh does not have,
    /// [`Error::GridTooFine`] when a pair's grid would exceed [`MAX_GRID_NODES`].
    ///
    /// # Performance
    /// Linear in the number of candidates; each costs a few polygon clips against the pad and
    /// up to three box-mesh intersection tests through the mesh's BVH. Candidates run in
    /// parallel (rayon) one grasp centre at a time.
    pub fn plan(
        &self,
        clustering: &Clustering,
        gripper: &GripperParams,
        options: &GraspOptions,
    ) -> Result<GraspSet> {
        gripper.validate()?;
        options.validate()?;
        let count = clustering.clusters.len();
        let cluster = |pair: usize, id: u32| {
            clustering
                .clusters
                .get(id as usize)
                .ok_or(Error::MissingCluster {
                    pair,
                    cluster: id,
                    count,
                })
        };
        let mut rejected = RejectionCounts::default();
        let mut sites = Vec::new();
        let max_width = gripper.opening_max - 2.0 * options.clearance;
        for (index, pair) in clustering.pairs.iter().enumerate() {
            for c in [cluster(index, pair.first)?, cluster(index, pair.second)?] {
                if let Some(&t) = c
                    .triangles
                    .iter()
                    .find(|&&t| t as usize >= self.triangles.len())
                {
                    return Err(Error::ForeignClustering {
                        cluster: c.id,
                        triangle: t,
                        count: self.triangles.len(),
                    });
                }
            }
            // The measured widths lie between the planes' distance less both thicknesses and
            // the planes' distance.
            let h = clustering.clusters[pair.first as usize].h
                + clustering.clusters[pair.second as usize].h;
            if pair.width < gripper.opening_min || pair.width - h > max_width {
                rejected.pair_width += 1;
                continue;
            }
            let points =
                grid_points(&pair.overlap, options.grid_step).ok_or(Error::GridTooFine {
                    pair: index,
                    grid_step: options.grid_step,
                    limit: MAX_GRID_NODES,
                })?;
            sites.extend(points.into_iter().map(|on_first| Site {
                pair: index,
                on_first,
            }));
        }
        let context = Context {
            planner: self,
            clustering,
            gripper,
            options,
            tcp_from_canonical: gripper.tcp_from_canonical(),
            score: ScoreModel {
                pad_area: gripper.pad_area(),
                torque_scale: self.radius,
                margin_scale: options.margin_scale,
                weights: [
                    options.contact_weight,
                    options.torque_weight,
                    options.margin_weight,
                ],
            },
        };
        let outcomes: Vec<Vec<std::result::Result<Grasp, Rejection>>> = sites
            .par_iter()
            .map(|site| context.evaluate_site(site))
            .collect();
        let mut grasps = Vec::new();
        let mut candidates = 0;
        for outcome in outcomes.into_iter().flatten() {
            candidates += 1;
            match outcome {
                Ok(g) => grasps.push(g),
                Err(Rejection::Width) => rejected.width += 1,
                Err(Rejection::PadTilt) => rejected.pad_tilt += 1,
                Err(Rejection::Contact) => rejected.contact += 1,
                Err(Rejection::Finger) => rejected.finger_collision += 1,
                Err(Rejection::Palm) => rejected.palm_collision += 1,
            }
        }
        // Stable: equal scores keep the generation order.
        grasps.sort_by(|a, b| b.score.total_cmp(&a.score));
        Ok(GraspSet {
            grasps,
            pairs: clustering.pairs.len(),
            candidates,
            rejected,
        })
    }
}

impl GraspPlanner {
    /// The outermost crossing of the line `origin + s·dir` with the triangles `triangles`
    /// (indices checked by [`GraspPlanner::plan`]): the largest `s` (of either sign) at which
    /// the line meets one of them; `None` when it meets none.
    fn crossing(&self, origin: &Point3, dir: &Vector3, triangles: &[u32]) -> Option<Real> {
        let mut best: Option<Real> = None;
        for &t in triangles {
            let Some(tri) = self.triangles.get(t as usize) else {
                continue;
            };
            let [a, b, c] = tri.map(|v| self.vertices[v as usize]);
            // A crossing on an edge counts (1e-9), so a line through a shared edge meets the patch.
            if let Some(s) = line_triangle(origin, dir, [&a, &b, &c], 1e-9)
                && best.is_none_or(|b| s > b)
            {
                best = Some(s);
            }
        }
        best
    }
}

/// How far the rest of a finger's inner face may reach nearer the object than its pad (m):
/// a tenth of a millimetre, well within the pads' squeeze.
const FACE_TOLERANCE: Real = 1e-4;

/// The least depth of contact a pad drawn back on a thin object is asked for, as a fraction
/// of the pad's depth (5 mm of NX-HIRO's 25 mm pads): where the region offers less (a
/// narrow strip on a curved, noisy side), the pad must still touch that much of the mesh
/// within the sheet's reach.
const THIN_MIN_DEPTH: Real = 0.2;

/// Most grid nodes scanned over one pair's overlap region.
pub const MAX_GRID_NODES: u64 = 1_000_000;

/// Grid points inside a polygon set: a square grid of spacing `step`, aligned with the frame
/// axes and centred on the set's bounding box. When no grid point falls inside (a region
/// smaller than the step), the area centroid is used if it lies inside. `None` when the grid
/// would have more than [`MAX_GRID_NODES`] nodes.
fn grid_points(overlap: &[Polygon], step: Real) -> Option<Vec<Point2>> {
    let mut lo = Vector2::repeat(Real::INFINITY);
    let mut hi = Vector2::repeat(Real::NEG_INFINITY);
    for p in overlap.iter().flat_map(Polygon::points) {
        lo = lo.inf(&p.coords);
        hi = hi.sup(&p.coords);
    }
    if !(lo.x <= hi.x && lo.y <= hi.y) {
        return Some(Vec::new());
    }
    let inside = |q: &Point2| overlap.iter().any(|p| p.contains(q));
    let center = (lo + hi) * 0.5;
    // Grid points cover [lo, hi] (the float-to-int cast saturates on huge extents).
    let half_count = |extent: Real| ((0.5 * extent / step).floor() as i64).clamp(0, 1 << 31);
    let (nx, ny) = (half_count(hi.x - lo.x), half_count(hi.y - lo.y));
    if ((2 * nx + 1) as u64).saturating_mul((2 * ny + 1) as u64) > MAX_GRID_NODES {
        return None;
    }
    let mut out = Vec::new();
    for j in -ny..=ny {
        for i in -nx..=nx {
            let q = Point2::from(center + Vector2::new(i as Real, j as Real) * step);
            if inside(&q) {
                out.push(q);
            }
        }
    }
    if out.is_empty()
        && let Some(c) = pickplace_geometry::polygon::total_centroid(overlap)
        && inside(&c)
    {
        out.push(c);
    }
    Some(out)
}

/// How far the ray from `p` along `dir` (unit) runs inside `region` before it first crosses one
/// of its boundaries (m; infinite when it crosses none).
fn exit_distance(region: &[Polygon], p: &Point2, dir: &Vector2) -> Real {
    let cross = |a: &Vector2, b: &Vector2| a.x * b.y - a.y * b.x;
    let mut best = Real::INFINITY;
    for polygon in region {
        for ring in std::iter::once(&polygon.outer).chain(&polygon.holes) {
            for (i, a) in ring.iter().enumerate() {
                let e = ring[(i + 1) % ring.len()] - a;
                let denominator = cross(dir, &e);
                if denominator.abs() < 1e-300 {
                    continue;
                }
                // p + t·dir = a + u·e.
                let w = a - p;
                let t = cross(&w, &e) / denominator;
                let u = cross(&w, dir) / denominator;
                if t > 0.0 && (0.0..=1.0).contains(&u) {
                    best = best.min(t);
                }
            }
        }
    }
    best
}

struct Context<'a> {
    planner: &'a GraspPlanner,
    clustering: &'a Clustering,
    gripper: &'a GripperParams,
    options: &'a GraspOptions,
    tcp_from_canonical: Matrix3,
    score: ScoreModel,
}

impl Context<'_> {
    fn evaluate_site(&self, site: &Site) -> Vec<std::result::Result<Grasp, Rejection>> {
        let pair = &self.clustering.pairs[site.pair];
        let first = &self.clustering.clusters[pair.first as usize];
        let second = &self.clustering.clusters[pair.second as usize];
        let n1 = first.normal;
        let on_first = first.frame.to_3d(&site.on_first);
        // The grasp line: through the site along n1, from the first plane to the second.
        let denominator = second.normal.dot(&n1);
        let plane_width = second.normal.dot(&(on_first - second.point)) / denominator;
        let middle = on_first - n1 * (0.5 * plane_width);
        // The width measured on the mesh (issue 17) starts where the grasp line crosses the two
        // contact patches, outermost crossing on each side (the planes of curved patches lie up
        // to h away from the surface); each approach direction then moves the pads out to the
        // highest point of their patch under them (`shared_checks`).
        let measured = self
            .planner
            .crossing(&middle, &n1, &first.triangles)
            .zip(self.planner.crossing(&middle, &(-n1), &second.triangles));
        let (width, tcp) = match measured {
            Some((out1, out2)) => (out1 + out2, middle + n1 * (0.5 * (out1 - out2))),
            // The line misses a patch (a site over a gap of the region): no contact there.
            None => (Real::NAN, middle),
        };
        let flips: &[Real] = if self.options.flip_closing {
            &[1.0, -1.0]
        } else {
            &[1.0]
        };
        // The triangles under either pad, whatever the approach direction: within the pad's half
        // diagonal of its contact point in the pad's plane, between the sheet's reach below it
        // and the open finger's back above it.
        let (g, h_max) = (self.gripper, self.clustering.params.h_max);
        let (hw, hd) = (0.5 * g.pad_width, 0.5 * g.pad_depth);
        // Thin objects (an improvement on §III-B.1): where the pair's region is shorter along
        // an approach direction than the pad is deep, a pad centred on the site puts the finger
        // tip past the region's far edge, below the table under a flat object. Such directions
        // also get a candidate drawn back along the approach until the tip stops `clearance`
        // short of that edge; the contact check then measures what the pad still covers.
        let count = self.options.approach_count;
        // Such a pad must cover `min_contact_ratio` of what the region offers in front of the
        // tip, or of `THIN_MIN_DEPTH` of the pad's depth where the region offers less: a
        // finger cluster on a curved scanned side is a strip of 2-3 mm, while the mesh
        // under the pad, within the sheet's reach, holds more (measured by the contact check).
        let clearance = self.options.clearance;
        let shifts: Vec<(Real, Real)> = (0..count)
            .map(|k| {
                let angle = TAU * k as Real / count as Real;
                let dir = Vector2::new(angle.cos(), angle.sin());
                let ahead = exit_distance(&pair.overlap, &site.on_first, &dir);
                let behind = exit_distance(&pair.overlap, &site.on_first, &(-dir));
                let offered = ahead + behind - clearance;
                if ahead + behind < g.pad_depth && offered > 0.0 {
                    let depth = offered.max(THIN_MIN_DEPTH * g.pad_depth);
                    ((hd + clearance - ahead).max(0.0), g.pad_width * depth)
                } else {
                    (0.0, 0.0)
                }
            })
            .collect();
        let max_shift = shifts.iter().map(|s| s.0).fold(0.0, Real::max);
        let radius = hw.hypot(hd + max_shift) + 1e-6;
        // Beyond the back of the open finger nothing is touched (a wall across a tube, whose
        // outer face looks the pad's way from behind its inner face).
        let ceiling = g.finger_thickness + self.options.clearance;
        let near = if width.is_finite() {
            [
                self.planner.facing_near(
                    &(tcp + n1 * (0.5 * width)),
                    &n1,
                    radius,
                    (h_max, ceiling),
                ),
                self.planner.facing_near(
                    &(tcp - n1 * (0.5 * width)),
                    &(-n1),
                    radius,
                    (h_max, ceiling),
                ),
            ]
        } else {
            [Near::empty(), Near::empty()]
        };
        let mut out = Vec::with_capacity(2 * count * flips.len());
        let pad_area = g.pad_area();
        for (k, &(tip_shift, offered_area)) in shifts.iter().enumerate() {
            let angle = TAU * k as Real / count as Real;
            let both = [(0.0, pad_area), (tip_shift, offered_area)];
            let shifts = if tip_shift > 0.0 {
                &both[..]
            } else {
                &both[..1]
            };
            for &(shift, full_area) in shifts {
                let mut candidate = Candidate {
                    site,
                    pair,
                    first,
                    second,
                    tcp,
                    width,
                    angle,
                    shift,
                    full_area,
                };
                match self.shared_checks(&mut candidate, [&near[0], &near[1]]) {
                    Ok((contact_area, pad_depth)) => out.extend(
                        flips
                            .iter()
                            .map(|&flip| self.finish(&candidate, contact_area, pad_depth, flip)),
                    ),
                    Err(reason) => out.extend(flips.iter().map(|_| Err(reason))),
                }
            }
        }
        out
    }

    /// The checks a 180° turn about the approach axis does not change (the pads and the fingers
    /// are symmetric under it): local width, pad tilt and depth, contact area, finger collision.
    /// Moves the pads (the candidate's TCP and width) out to where they first touch the mesh.
    /// Returns the contact area and the pad depth.
    fn shared_checks(
        &self,
        c: &mut Candidate<'_>,
        near: [&Near; 2],
    ) -> std::result::Result<(Real, Real), Rejection> {
        let (g, o) = (self.gripper, self.options);
        if !(c.width.is_finite()
            && c.width >= g.opening_min
            && c.width <= g.opening_max - 2.0 * o.clearance)
        {
            return Err(Rejection::Width);
        }
        let (approach, lateral) = c.axes(1.0);
        // Pad 2 lies on the plane through its contact point `tcp − n1·w/2` parallel to S1; its
        // corners must stay within h_max of the plane through that point parallel to S2: the
        // pads are parallel enough to the second patch for the flexible sheet to conform.
        let h_max = self.clustering.params.h_max;
        let (hw, hd) = (0.5 * g.pad_width, 0.5 * g.pad_depth);
        for (a, b) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
            let offset = lateral * (a * hw) + approach * (b * hd - c.shift);
            if c.second.normal.dot(&offset).abs() > h_max + 1e-9 {
                return Err(Rejection::PadTilt);
            }
        }
        // The surface under each pad may rise towards the pad above the grasp line's crossing
        // (a curved or concave patch): the rigid pad first touches the highest point under it,
        // and the flexible sheet of depth h_max reaches the rest only within h_max of it
        // (§III-A, Fig. 2). The width is the distance between the pads there. The pads' contact
        // points `tcp ± n1·w/2` are those of `near`.
        let footprint = Footprint {
            lateral,
            approach,
            half: (hw, hd),
            shift: c.shift,
        };
        let ceiling = g.finger_thickness + o.clearance;
        let limits = (h_max, ceiling);
        let rise1 = GraspPlanner::pad_scan(&footprint, limits, near[0], None);
        if rise1 > h_max + 1e-9 {
            return Err(Rejection::PadTilt);
        }
        let rise2 = GraspPlanner::pad_scan(&footprint, limits, near[1], None);
        let depth = rise1.max(rise2);
        if depth > h_max + 1e-9 {
            return Err(Rejection::PadTilt);
        }
        c.width += rise1 + rise2;
        c.tcp += c.first.normal * (0.5 * (rise1 - rise2)) - approach * c.shift;
        if c.width > g.opening_max - 2.0 * o.clearance {
            return Err(Rejection::Width);
        }
        // Contact: the surface both pads touch, measured on the mesh (issue 17).
        let area = |near: &Near, rise: Real| {
            GraspPlanner::pad_scan(&footprint, limits, near, Some(rise - h_max))
        };
        let contact_area = area(near[0], rise1).min(area(near[1], rise2));
        if contact_area < o.min_contact_ratio * c.full_area - 1e-12 {
            return Err(Rejection::Contact);
        }
        // The rigid finger, pad and all, must not reach the object before the pad's surface does
        // (a bottle's lip 2 mm proud of the neck the pad holds): the fingers closed to FACE_TOLERANCE
        // off the width touch nothing along their whole length.
        let object_from_tcp = self.pose(c, 1.0);
        for finger in g.fingers(c.width + 2.0 * FACE_TOLERANCE) {
            if self.planner.collider.hits(&object_from_tcp, &finger, 0.0) {
                return Err(Rejection::Finger);
            }
        }
        // Fingers open by the clearance on each side and grown by it along their other axes.
        for mut finger in g.fingers(c.width + 2.0 * o.clearance) {
            finger.half_extents += Vector3::new(o.clearance, 0.0, o.clearance);
            if self.planner.collider.hits(&object_from_tcp, &finger, 0.0) {
                return Err(Rejection::Finger);
            }
        }
        Ok((contact_area, depth))
    }

    /// The TCP pose of a candidate: the canonical axes (lateral, closing, approach) go to the
    /// object-frame axes.
    fn pose(&self, c: &Candidate<'_>, flip: Real) -> Isometry3 {
        let (approach, lateral) = c.axes(flip);
        let object_from_canonical =
            Matrix3::from_columns(&[lateral, c.first.normal * flip, approach]);
        // Both factors are orthonormal by construction; `from_matrix` (iterative) would stall on
        // rotations of 180°.
        let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
            object_from_canonical * self.tcp_from_canonical.transpose(),
        ));
        Isometry3::from_parts(Translation3::from(c.tcp.coords), rotation)
    }

    /// The palm check and the quality of one orientation of a candidate.
    fn finish(
        &self,
        c: &Candidate<'_>,
        contact_area: Real,
        pad_depth: Real,
        flip: Real,
    ) -> std::result::Result<Grasp, Rejection> {
        let object_from_tcp = self.pose(c, flip);
        let palm: GripperBox = self.gripper.palm_box();
        if self
            .planner
            .collider
            .hits(&object_from_tcp, &palm, self.options.clearance)
        {
            return Err(Rejection::Palm);
        }
        let torque_arm = (self.planner.center_of_mass - c.tcp)
            .cross(&c.first.normal)
            .norm();
        let boundary_margin = quality::boundary_margin(&c.site.on_first, &c.pair.overlap);
        let quality = GraspQuality {
            contact_area,
            torque_arm,
            boundary_margin,
            pad_depth,
            tip_shift: c.shift,
        };
        let (positive_cluster, negative_cluster) = if flip > 0.0 {
            (c.first.id, c.second.id)
        } else {
            (c.second.id, c.first.id)
        };
        Ok(Grasp {
            object_from_tcp,
            width: c.width,
            score: self.score.score(&quality),
            pair: c.site.pair,
            positive_cluster,
            negative_cluster,
            approach_angle: c.angle,
            quality,
        })
    }
}

/// A grasp centre with one approach direction, before the closing direction is chosen.
struct Candidate<'a> {
    site: &'a Site,
    pair: &'a ClusterPair,
    first: &'a Cluster,
    second: &'a Cluster,
    tcp: Point3,
    width: Real,
    angle: Real,
    /// How far the pads are drawn back along the approach from the site (m).
    shift: Real,
    /// The contact area a pad could have here (m²): the pad's, or for a pad drawn back, its
    /// width times the depth the region offers in front of the tip.
    full_area: Real,
}

impl Candidate<'_> {
    /// Approach and lateral axes (object frame) for the closing direction `flip · n1`.
    fn axes(&self, flip: Real) -> (Vector3, Vector3) {
        let approach =
            self.first.frame.u * self.angle.cos() + self.first.frame.v * self.angle.sin();
        let lateral = (self.first.normal * flip).cross(&approach);
        (approach, lateral)
    }
}

#[cfg(test)]
pub(crate) mod tests;
