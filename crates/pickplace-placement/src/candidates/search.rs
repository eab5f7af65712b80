//! The two searches of Algorithm 2 (§III-B.2): face-face contacts (`searchFaceFaceContact`:
//! positions on a grid nearest the target first, yaws spread over the turn) and edge-face
//! contacts (`searchEdgeFaceContact`: a hull segment laid on the plane, the object tilted
//! about it until a second contact appears), with the stability test of Fig. 7 on each pose.

use super::{
    ContactKind, EnvironmentModel, ObjectModel, Placement, PlacementOptions, RIGID_TOLERANCE,
    Rejections, horizontal_distance,
};
use crate::region::Region;
use crate::stability::{self, SupportHull};
use pickplace_geometry::math::{
    Isometry3, Point2, Point3, Real, Translation3, UnitQuaternion, Vector2, Vector3,
};
use pickplace_geometry::polygon::{Polygon, signed_margin};
use std::f64::consts::PI;

/// Positions on `env` (plane coordinates) on a grid of `step` aligned with its bounding
/// rectangle and inside its polygon, nearest to `target2` first; the target's own projection
/// comes first when it lies inside.
pub(super) fn grid_positions(
    env: &Region,
    target2: &Point2,
    step: Real,
    limit: usize,
    max_distance: Real,
) -> Vec<Point2> {
    let r = &env.rect;
    let (ax, ay) = (r.axis, Vector2::new(-r.axis.y, r.axis.x));
    let mut pts = Vec::new();
    if env.polygon.contains(target2) {
        pts.push((0.0, *target2));
    }
    let nx = ((2.0 * r.half_extents.x / step).floor() as i64).clamp(0, 2000);
    let ny = ((2.0 * r.half_extents.y / step).floor() as i64).clamp(0, 2000);
    // Centre the grid in the rectangle so that both sides get the same clearance.
    let (ox, oy) = (
        r.half_extents.x - step * nx as Real / 2.0,
        r.half_extents.y - step * ny as Real / 2.0,
    );
    // Only the rows and columns that can be within `max_distance` of the target: the grid
    // coordinate of the target, ± the distance, in cells.
    let t = target2 - r.center;
    let cells = |along: Real, half: Real, o: Real, n: i64| {
        let first = ((along - max_distance + half - o) / step - 0.5).ceil();
        let last = ((along + max_distance + half - o) / step - 0.5).floor();
        // NaN or infinite bounds clamp to the whole range.
        let lo = if first.is_finite() {
            first.clamp(0.0, n as Real) as i64
        } else {
            0
        };
        let hi = if last.is_finite() {
            (last + 1.0).clamp(0.0, n as Real) as i64
        } else {
            n
        };
        lo..hi
    };
    let (is, js) = (
        cells(t.dot(&ax), r.half_extents.x, ox, nx),
        cells(t.dot(&ay), r.half_extents.y, oy, ny),
    );
    for i in is {
        for j in js.clone() {
            let (u, v) = (
                -r.half_extents.x + ox + step * (i as Real + 0.5),
                -r.half_extents.y + oy + step * (j as Real + 0.5),
            );
            let p = r.center + ax * u + ay * v;
            let d = (p - target2).norm();
            if d <= max_distance && env.polygon.contains(&p) {
                pts.push((d, p));
            }
        }
    }
    pts.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then(a.1.x.total_cmp(&b.1.x))
            .then(a.1.y.total_cmp(&b.1.y))
    });
    pts.truncate(limit);
    pts.into_iter().map(|(_, p)| p).collect()
}

pub(super) fn rz(angle: Real) -> UnitQuaternion {
    UnitQuaternion::from_axis_angle(&Vector3::z_axis(), angle)
}

pub(super) fn rx(angle: Real) -> UnitQuaternion {
    UnitQuaternion::from_axis_angle(&Vector3::x_axis(), angle)
}

/// The stability test's verdict ([`stability::is_stable`]) with the options' minimum margin
/// and tipping angle.
pub(super) fn stable(margin: Real, height: Real, options: &PlacementOptions) -> bool {
    stability::is_stable(
        margin,
        height,
        options.min_margin,
        options.min_tipping_angle,
    )
}

/// An object region facing an environment region (Algorithm 2, lines 3–6): what both
/// contact searches work on.
#[derive(Clone, Copy)]
pub(super) struct RegionPair<'a> {
    pub(super) object: &'a ObjectModel,
    /// The object's region.
    pub(super) o: &'a Region,
    /// Its index in [`ObjectModel::regions`].
    pub(super) o_index: usize,
    pub(super) env: &'a EnvironmentModel,
    /// The environment's region.
    pub(super) e: &'a Region,
    pub(super) target: &'a Point3,
    pub(super) options: &'a PlacementOptions,
}

/// searchFaceFaceContact (paper Fig. 6(c)).
pub(super) fn search_face_face(pair: &RegionPair<'_>, counts: &mut Rejections) -> Vec<Placement> {
    let RegionPair {
        object,
        o,
        o_index,
        env,
        e,
        target,
        options,
    } = *pair;
    let (target2, _) = e.to_plane(target);
    // The object's reference point is the foot of its CoG on its contact plane, so that the
    // CoG's vertical passes through the grid position (on a horizontal environment plane) and
    // the grid's order is the order of `distance_to_target`.
    let (reference, _) = o.to_plane(&object.cog);
    let plane_from_object = o.parent_from_plane.inverse();
    let lift = e.normal() * options.clearance;
    let mut out = Vec::new();
    // Enough positions to find max_per_pair poses even when most are rejected.
    let positions = grid_positions(
        e,
        &target2,
        options.position_step,
        64 * options.max_per_pair.max(1),
        options.max_distance,
    );
    let yaw_order = spread_order(options.yaw_steps.max(1));
    'positions: for p in positions {
        for &k in &yaw_order {
            let yaw = 2.0 * PI * k as Real / options.yaw_steps.max(1) as Real;
            // Object plane -> environment plane: flip (normals opposite), yaw, then put the
            // object's reference point at p.
            let flip_yaw = rz(yaw) * rx(PI);
            let r = flip_yaw * Point3::new(reference.x, reference.y, 0.0);
            let e_from_oplane =
                Isometry3::from_parts(Translation3::new(p.x - r.x, p.y - r.y, 0.0), flip_yaw);
            let world_from_object = e.parent_from_plane * e_from_oplane * plane_from_object;
            // Stability (Fig. 7): the object's polygon in environment-plane coordinates.
            let map = |q: &Point2| {
                let w = e_from_oplane * Point3::new(q.x, q.y, 0.0);
                Point2::new(w.x, w.y)
            };
            // The object's support is the hull of its points on S (its outer boundary for a
            // flat region), minus its holes.
            let moved = Polygon {
                outer: o.support.iter().map(map).collect(),
                holes: o
                    .polygon
                    .holes
                    .iter()
                    .map(|h| h.iter().map(map).collect())
                    .collect(),
            };
            let hull = SupportHull::of_regions(&moved, &e.polygon);
            let cog_world = world_from_object * object.cog;
            let Some(foot) = stability::cog_foot(e, &cog_world) else {
                counts.unstable += 1;
                continue;
            };
            let height = e.to_plane(&cog_world).1;
            let margin = object.capped_margin(o_index, hull.cog_margin(&foot), height);
            if !stable(margin, height, options) {
                counts.unstable += 1;
                continue;
            }
            if env
                .collision
                .intersects(&object.collision, &world_from_object, &lift)
            {
                counts.penetrates += 1;
                continue;
            }
            out.push(Placement {
                world_from_object,
                contact: ContactKind::FaceFace,
                object_cluster: o.cluster_id,
                env_cluster: e.cluster_id,
                stability_margin: margin,
                tipping_angle: stability::tipping_angle(margin, height),
                distance_to_target: horizontal_distance(&cog_world, target),
                tilt: 0.0,
            });
            if out.len() >= options.max_per_pair {
                break 'positions;
            }
        }
    }
    out
}

/// searchEdgeFaceContact (paper Fig. 6(d), (e)).
///
/// Applies when one side of the object region's bounding box fits in the environment's (the
/// paper's condition). A segment of the 2D convex hull of the object region (the longest
/// [`PlacementOptions::edge_segments`] ones) is laid on the environment's contact plane,
/// parallel to a side of the environment's bounding rectangle (four directions, as in
/// Fig. 6(e)), at positions spread over the environment region; the object is then rotated
/// about the segment, lifting the region's interior, until the first angle at which it no
/// longer penetrates the environment: the second contact (bisection to
/// [`PlacementOptions::tilt_tolerance`]).
///
/// Improvements: the rotation stops where the CoG would cross the segment (past that angle the
/// object tips over whatever it touches), so hopeless positions cost one collision test
/// instead of a bisection; a segment whose region is too narrow along it for the margin is
/// rejected before any collision test (the support is the segment and [`second_contacts`]).
pub(super) fn search_edge_face(pair: &RegionPair<'_>, counts: &mut Rejections) -> Vec<Placement> {
    let RegionPair {
        object,
        o,
        o_index,
        env,
        e,
        target,
        options,
    } = *pair;
    // The segments are those of the hull of the points really on the contact plane.
    let hull = &object.rigid_supports[o_index];
    if hull.len() < 3 {
        return Vec::new();
    }
    let (object_short, _) = o.rect.sorted_sides();
    let (_, env_long) = e.rect.sorted_sides();
    if object_short > env_long {
        return Vec::new();
    }
    let (target2, _) = e.to_plane(target);
    let lift = e.normal() * options.clearance;
    let wanted = options.edge_positions.max(1);
    // Spread over the region, or over the disc around the target that can hold candidates.
    let area = e.area.min(PI * options.max_distance.powi(2));
    let step = options.position_step.max((area / wanted as Real).sqrt());
    let positions = grid_positions(e, &target2, step, wanted, options.max_distance);
    let rect_angle = e.rect.axis.y.atan2(e.rect.axis.x);
    let yaws: Vec<Real> = (0..4).map(|k| rect_angle + k as Real * PI / 2.0).collect();
    // The longest hull segments first (ties by index, so the order is deterministic).
    let mut segments: Vec<(Real, usize)> = (0..hull.len())
        .map(|i| ((hull[(i + 1) % hull.len()] - hull[i]).norm(), i))
        .collect();
    segments.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    segments.truncate(options.edge_segments.max(1));
    let mut out = Vec::new();
    for &(len, i) in &segments {
        if len < 1e-6 {
            continue;
        }
        let (a, b) = (hull[i], hull[(i + 1) % hull.len()]);
        // Segment frame in the object's plane: x along the segment, y into the region
        // (the hull is counter-clockwise), z the outward normal.
        let x = (b - a) / len;
        let m = Point2::from((a.coords + b.coords) * 0.5);
        let plane_from_segment = Isometry3::from_parts(
            Translation3::new(m.x, m.y, 0.0),
            UnitQuaternion::from_axis_angle(&Vector3::z_axis(), x.y.atan2(x.x)),
        );
        let segment_from_object = (o.parent_from_plane * plane_from_segment).inverse();
        // Both ends of the segment must lie on the environment's region.
        let (env_short, env_long) = e.rect.sorted_sides();
        if len > env_short.hypot(env_long) {
            continue;
        }
        // The CoG's offset into the region and its height above the plane; tilted by t, its
        // horizontal offset into the region is cy cos t - ch sin t.
        let c = segment_from_object * object.cog;
        let (cy, ch) = (c.y, -c.z);
        if cy <= 0.0 || ch <= 0.0 {
            counts.unstable += 1;
            continue;
        }
        // Tilted by t, the object tips about the segment once it rotates a further
        // atan2(cy, ch) - t: stability needs t <= atan2(cy, ch) - min_tipping_angle, so no
        // angle past that is worth a collision test.
        let tilt_limit = options
            .max_tilt
            .min(cy.atan2(ch) - options.min_tipping_angle);
        if tilt_limit <= 0.0 {
            counts.unstable += 1;
            continue;
        }
        // Sideways bound, before any collision test: the support is the segment and points of
        // the region's support (see `second_contacts`), all within the region's extent
        // [x_min, x_max] along the segment. On a horizontal environment plane the segment is
        // horizontal and the tilt about it keeps every x, so the CoG's vertical is no further
        // than min(c.x - x_min, x_max - c.x) from the support hull's boundary. A strip of a
        // tessellated cylinder (one facet wide) stood on its short edge fails here.
        if e.normal().z >= 1.0 - 1e-12 {
            let along = |q: &Point2| (q - m).dot(&x);
            let x_min = hull.iter().map(along).fold(Real::INFINITY, Real::min);
            let x_max = hull.iter().map(along).fold(Real::NEG_INFINITY, Real::max);
            let bound = (c.x - x_min).min(x_max - c.x) + 1e-9;
            if bound < options.min_margin {
                counts.unstable += 1;
                continue;
            }
        }
        for p in &positions {
            for &yaw in &yaws {
                // The line contact lies on the environment region: both ends inside it.
                if !e.polygon.contains(&e_point2(p, yaw, -len * 0.5))
                    || !e.polygon.contains(&e_point2(p, yaw, len * 0.5))
                {
                    continue;
                }
                let pose_at = |tilt: Real| {
                    // Interior side (+y of the segment frame) maps to -y by the flip; rotating
                    // by -tilt about x lifts it off the plane.
                    let e_from_segment = Isometry3::from_parts(
                        Translation3::new(p.x, p.y, 0.0),
                        rz(yaw) * rx(-tilt) * rx(PI),
                    );
                    e.parent_from_plane * e_from_segment * segment_from_object
                };
                let penetrates = |tilt: Real| {
                    env.collision
                        .intersects(&object.collision, &pose_at(tilt), &lift)
                };
                if !penetrates(0.0) {
                    // The region lies flat without touching anything else: not an edge contact.
                    continue;
                }
                // The first angle at which the object is free: a coarse scan (penetration is
                // not monotonic in the angle: tilting further may hit a wall behind the
                // segment), then bisection inside the bracket.
                let coarse = options.tilt_scan_step.clamp(
                    options.tilt_tolerance,
                    tilt_limit.max(options.tilt_tolerance),
                );
                let mut bracket = None;
                let mut prev = 0.0;
                let mut t = coarse.min(tilt_limit);
                loop {
                    if !penetrates(t) {
                        bracket = Some((prev, t));
                        break;
                    }
                    if t >= tilt_limit {
                        break;
                    }
                    prev = t;
                    t = (t + coarse).min(tilt_limit);
                }
                let Some((mut lo, mut hi)) = bracket else {
                    // Blocked up to the angle where the CoG crosses the segment: it would tip
                    // over, or it cannot be laid there at all.
                    counts.penetrates += 1;
                    continue;
                };
                while hi - lo > options.tilt_tolerance {
                    let mid = 0.5 * (lo + hi);
                    if penetrates(mid) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                let world_from_object = pose_at(hi);
                // Support (Fig. 7 for a line contact): the segment's ends and the points where
                // the object meets the environment again.
                let a_w = e.parent_from_plane * e_point(p, yaw, -len * 0.5);
                let b_w = e.parent_from_plane * e_point(p, yaw, len * 0.5);
                let second = second_contacts(object, (o, hull), env, &world_from_object, options);
                let horizontal = |q: &Point3| Point2::new(q.x, q.y);
                let mut support: Vec<Point2> = vec![horizontal(&a_w), horizontal(&b_w)];
                support.extend(second.iter().map(horizontal));
                let cog = world_from_object * object.cog;
                let margin = SupportHull::of_points(&support).cog_margin(&horizontal(&cog));
                let height = e.to_plane(&cog).1;
                if !stable(margin, height, options) {
                    counts.unstable += 1;
                    continue;
                }
                out.push(Placement {
                    world_from_object,
                    contact: ContactKind::EdgeFace,
                    object_cluster: o.cluster_id,
                    env_cluster: e.cluster_id,
                    stability_margin: margin,
                    tipping_angle: stability::tipping_angle(margin, height),
                    distance_to_target: horizontal_distance(&cog, target),
                    tilt: hi,
                });
                if out.len() >= options.max_per_pair {
                    return out;
                }
            }
        }
    }
    out
}

/// The indices `0..n` in a spread order: by the base-2 radical inverse of the index (van der
/// Corput), so yaw steps `k / n` of a turn come as 0, 1/2, 1/4, 3/4, 1/8, … when `n` is a power
/// of two: the first few variants of a face cover the whole turn.
pub(super) fn spread_order(n: usize) -> Vec<usize> {
    let radical_inverse = |mut k: usize| {
        let (mut r, mut f): (Real, Real) = (0.0, 0.5);
        while k > 0 {
            if k & 1 == 1 {
                r += f;
            }
            k >>= 1;
            f *= 0.5;
        }
        r
    };
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&a, &b| {
        radical_inverse(a)
            .total_cmp(&radical_inverse(b))
            .then(a.cmp(&b))
    });
    order
}

/// A point along the segment laid at `p` with `yaw`, in plane coordinates.
pub(super) fn e_point2(p: &Point2, yaw: Real, along: Real) -> Point2 {
    Point2::new(p.x + along * yaw.cos(), p.y + along * yaw.sin())
}

/// A point on the environment plane along the segment laid at `p` with `yaw` (plane coords).
pub(super) fn e_point(p: &Point2, yaw: Real, along: Real) -> Point3 {
    Point3::new(p.x + along * yaw.cos(), p.y + along * yaw.sin(), 0.0)
}

/// The second contact of an edge-face pose (paper Fig. 6(d)): the points where the object's
/// region `o` (its support, the part that lies flat) touches the environment at `pose`, world
/// frame, sorted. Contacts elsewhere on the object are left out: the support hull is then never
/// larger than the one that bears the load, so the stability test stays on the safe side, and
/// the sideways bound of [`search_edge_face`] holds.
pub(super) fn second_contacts(
    object: &ObjectModel,
    (o, support): (&Region, &[Point2]),
    env: &EnvironmentModel,
    pose: &Isometry3,
    options: &PlacementOptions,
) -> Vec<Point3> {
    let reach = options.clearance * 0.5;
    let slack = reach + RIGID_TOLERANCE;
    let object_from_world = pose.inverse();
    let mut out: Vec<Point3> = env
        .collision
        .touching_points(&object.collision, pose, reach)
        .into_iter()
        .filter(|w| {
            let (q, h) = o.to_plane(&(object_from_world * w));
            h.abs() <= slack && signed_margin(&q, support) >= -slack
        })
        .collect();
    out.sort_by(|a, b| {
        a.x.total_cmp(&b.x)
            .then(a.y.total_cmp(&b.y))
            .then(a.z.total_cmp(&b.z))
    });
    out.dedup_by(|a, b| (*a - *b).norm() < 1e-6);
    out
}
