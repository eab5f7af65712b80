//! The narrow phase of pairs with a robot shape: oriented boxes (separating axes) first, then
//! GJK with the climbing support function of link hulls (`support`), started along the line
//! between the shapes' box centres and, for a pair tested over and over (a moving view's self
//! pairs), tried first along the direction that separated it last time.

use super::{CollisionScratch, CollisionWorld, EnvironmentObject, RobotShape};
use crate::error::Result;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::{Matrix, Pose, Vector};
use parry3d_f64::query;
use parry3d_f64::query::gjk::{CsoPoint, GJKResult, VoronoiSimplex};
use parry3d_f64::shape::{SharedShape, SupportMap};
use pickplace_geometry::math::Real;

impl RobotShape {
    /// The support function GJK uses for this shape in a self pair with a climbing hull:
    /// `None` for a shape parry does not test as a support map against a hull (a ball has
    /// its own routine, a flat mesh is no support map).
    pub(super) fn support_map(&self) -> Option<&dyn SupportMap> {
        if let Some(c) = &self.climbing {
            Some(c)
        } else if self.shape.as_ball().is_some() {
            None
        } else {
            self.shape.as_support_map()
        }
    }
}

/// A shape's box in the world: its frame's rotation as a matrix and the box's centre,
/// computed once per shape and query ([`BoxFrame::of`]); the shape's world box
/// ([`BoxFrame::aabb`]) and each separating-axis test of its pairs use it, so that no pair
/// test converts a quaternion again.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BoxFrame {
    rotation: Matrix,
    centre: Vector,
}

impl BoxFrame {
    /// The frame of a box centred at `centre` in the frame `pose`.
    #[inline]
    pub(super) fn of(pose: &Pose, centre: Vector) -> Self {
        Self {
            rotation: Matrix::from_quat(pose.rotation),
            centre: pose.transform_point(centre),
        }
    }

    /// The world box around the box of half extents `half` (the same arithmetic as parry's
    /// `Aabb::transform_by` of the local box, so the same numbers).
    #[inline]
    pub(super) fn aabb(&self, half: Vector) -> Aabb {
        let extents = self.rotation.abs() * half;
        Aabb::new(self.centre + (-extents), self.centre + extents)
    }
}

/// Whether the oriented boxes of two robot shapes (at their frames), each loosened by half
/// the margin, overlap: false proves the shapes farther apart than the margin.
#[inline]
pub(super) fn boxes_overlap(
    frame1: &BoxFrame,
    s1: &RobotShape,
    frame2: &BoxFrame,
    s2: &RobotShape,
    margin: Real,
) -> bool {
    oriented_boxes_overlap(
        (frame1, s1.box_half_extents),
        (frame2, s2.box_half_extents),
        margin,
    )
}

/// Whether two oriented boxes (a frame and the box's half extents), each loosened by half
/// the margin, overlap: false proves whatever lies inside them farther apart than the
/// margin.
fn oriented_boxes_overlap(
    (frame1, half1): (&BoxFrame, Vector),
    (frame2, half2): (&BoxFrame, Vector),
    margin: Real,
) -> bool {
    let half = Vector::splat(margin / 2.0);
    let (e1, e2) = (half1 + half, half2 + half);
    let (r1, r2) = (frame1.rotation, frame2.rotation);
    let d = frame2.centre - frame1.centre;
    // The separating-axis test of two oriented boxes (Ericson, Real-Time Collision Detection,
    // §4.4.1): box 2's axes and the centres' offset in box 1's frame; the 15 candidate axes
    // (the 3 + 3 face normals, the 9 edge cross products), the cheapest first.
    let rot = r1.transpose() * r2;
    let t = (r1.transpose() * d).to_array();
    let c = rot.to_cols_array_2d();
    // m[i][j]: box 2's axis j along box 1's axis i.
    let m = [
        [c[0][0], c[1][0], c[2][0]],
        [c[0][1], c[1][1], c[2][1]],
        [c[0][2], c[1][2], c[2][2]],
    ];
    // The absolute values with a little more: edges nearly parallel make a cross-product
    // axis nearly zero, where rounding could claim a separation that is not there.
    let a = m.map(|row| row.map(|x| x.abs() + 1e-9));
    let (e1, e2) = (e1.to_array(), e2.to_array());
    // Slack on every comparison, so that rounding keeps a touching pair (the test may only
    // err towards "overlap": GJK decides then).
    let slack = 1e-9 * (1.0 + t.iter().fold(0.0, |m: Real, x| m.max(x.abs())));
    let apart = |distance: Real, r1: Real, r2: Real| distance.abs() > r1 + r2 + slack;
    for i in 0..3 {
        let r2 = e2[0] * a[i][0] + e2[1] * a[i][1] + e2[2] * a[i][2];
        if apart(t[i], e1[i], r2) {
            return false;
        }
    }
    for j in 0..3 {
        let r1 = e1[0] * a[0][j] + e1[1] * a[1][j] + e1[2] * a[2][j];
        let distance = t[0] * m[0][j] + t[1] * m[1][j] + t[2] * m[2][j];
        if apart(distance, r1, e2[j]) {
            return false;
        }
    }
    for i in 0..3 {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        for j in 0..3 {
            let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
            // Axis: box 1's axis i × box 2's axis j.
            let r1 = e1[i1] * a[i2][j] + e1[i2] * a[i1][j];
            let r2 = e2[j1] * a[i][j2] + e2[j2] * a[i][j1];
            let distance = t[i2] * m[i1][j] - t[i1] * m[i2][j];
            if apart(distance, r1, r2) {
                return false;
            }
        }
    }
    true
}

/// The support function of an environment shape for GJK against a link hull: `None` for a
/// ball (parry's own routine is exact and cheaper) and for shapes that are no support map
/// (meshes, compounds).
fn environment_support_map(shape: &SharedShape) -> Option<&dyn SupportMap> {
    if shape.as_ball().is_some() {
        None
    } else {
        shape.as_support_map()
    }
}

/// GJK on two support maps, the second at `pos12` in the first's frame: whether they overlap
/// (margin 0) or are closer than the margin. `last`, a direction that separated the pair
/// before (in the first shape's frame, zero for none), is tried first: a gap along it beyond
/// the margin proves the pair apart (a separating axis, the test GJK itself ends with); GJK
/// stores the direction that separates them there. GJK starts along the line between the
/// shapes' box centres `centre1` and `centre2` (parry starts along the line between their
/// frames, which a link mesh may have far from its geometry): fewer iterations; the answer is
/// GJK's either way (a start changes it only within GJK's tolerance).
fn support_maps_touching(
    pos12: &Pose,
    (g1, centre1): (&dyn SupportMap, Vector),
    (g2, centre2): (&dyn SupportMap, Vector),
    margin: Real,
    last: Option<&mut Vector>,
) -> bool {
    if let Some(dir) = last.as_deref()
        && *dir != Vector::ZERO
    {
        let gap = -dir.dot(CsoPoint::from_shapes(pos12, g1, g2, *dir).point);
        if gap > margin {
            return false;
        }
    }
    let init = centre1 - pos12.transform_point(centre2);
    let init = (init.length_squared() > 0.0).then_some(init);
    let mut simplex = VoronoiSimplex::new();
    if margin == 0.0 {
        let (hit, dir) = query::details::intersection_test_support_map_support_map_with_params(
            pos12,
            g1,
            g2,
            &mut simplex,
            init.map(|d| -d),
        );
        if !hit
            && let Some(last) = last
            && let Some(dir) = dir.try_normalize()
        {
            *last = dir;
        }
        hit
    } else {
        match query::details::closest_points_support_map_support_map_with_params(
            pos12,
            g1,
            g2,
            margin,
            &mut simplex,
            init,
        ) {
            GJKResult::NoIntersection(dir) => {
                if let Some(last) = last {
                    *last = dir;
                }
                false
            }
            _ => true,
        }
    }
}

impl CollisionWorld {
    /// The exact test of two robot shapes, as [`CollisionWorld::touching`]: the same GJK query
    /// parry's dispatcher runs on two support maps, with the climbing support function of
    /// the hulls that have one.
    pub(super) fn robot_shapes_touching(
        &self,
        pose1: &Pose,
        s1: &RobotShape,
        pose2: &Pose,
        s2: &RobotShape,
        margin: Real,
    ) -> Result<bool> {
        self.robot_shapes_touching_from(pose1, s1, pose2, s2, margin, None)
    }

    /// [`CollisionWorld::robot_shapes_touching`], trying first the direction that separated
    /// the pair last time (`last`, a unit vector in the first shape's frame, or zero; set
    /// when GJK separates the pair): when the pair's gap along it exceeds the margin, the
    /// pair is apart (a separating axis, exact: the test GJK itself ends with), else GJK
    /// decides as without it.
    pub(super) fn robot_shapes_touching_from(
        &self,
        pose1: &Pose,
        s1: &RobotShape,
        pose2: &Pose,
        s2: &RobotShape,
        margin: Real,
        last: Option<&mut Vector>,
    ) -> Result<bool> {
        if (s1.climbing.is_some() || s2.climbing.is_some())
            && let (Some(g1), Some(g2)) = (s1.support_map(), s2.support_map())
        {
            let pos12 = pose1.inv_mul(pose2);
            return Ok(support_maps_touching(
                &pos12,
                (g1, s1.box_centre),
                (g2, s2.box_centre),
                margin,
                last,
            ));
        }
        self.touching(pose1, &s1.shape, pose2, &s2.shape, margin, || {
            (
                self.link_names[s1.link].clone(),
                self.link_names[s2.link].clone(),
            )
        })
    }

    /// The narrow phase of robot shapes `a` and `b` whose boxes overlap: their oriented boxes,
    /// then the exact test.
    #[inline]
    pub(super) fn robot_pair_touching(
        &self,
        scratch: &CollisionScratch,
        a: usize,
        b: usize,
        margin: Real,
    ) -> Result<bool> {
        let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
        let (pa, pb) = (&scratch.shape_poses[a], &scratch.shape_poses[b]);
        let (fa, fb) = (&scratch.shape_frames[a], &scratch.shape_frames[b]);
        Ok(boxes_overlap(fa, sa, fb, sb, margin)
            && self.robot_shapes_touching(pa, sa, pb, sb, margin)?)
    }

    /// The exact test of robot shape `s` at `pose` against environment object `env`: their
    /// oriented boxes first (an obstacle's box around its shape, a link's around its hull),
    /// then, for a link hull with a climbing support function and an obstacle that is a
    /// support map (a box, a cylinder, a convex shape), the same GJK query as a self pair's,
    /// tried first along `last` (the direction that separated the pair last time, kept by a
    /// moving view's queries); otherwise parry's dispatcher
    /// ([`CollisionWorld::hulled_touching`]).
    pub(super) fn robot_env_touching(
        &self,
        pose: &Pose,
        frame: &BoxFrame,
        s: &RobotShape,
        env: &EnvironmentObject,
        margin: Real,
        last: Option<&mut Vector>,
    ) -> Result<bool> {
        if !oriented_boxes_overlap(
            (frame, s.box_half_extents),
            (&env.frame, env.box_half_extents),
            margin,
        ) {
            return Ok(false);
        }
        if env.hull.is_none()
            && s.climbing.is_some()
            && let (Some(g1), Some(g2)) = (s.support_map(), environment_support_map(&env.shape))
        {
            let pos12 = pose.inv_mul(&env.world_from_shape);
            return Ok(support_maps_touching(
                &pos12,
                (g1, s.box_centre),
                (g2, env.box_centre),
                margin,
                last,
            ));
        }
        self.hulled_touching(
            &env.world_from_shape,
            &env.shape,
            env.hull.as_ref(),
            pose,
            &s.shape,
            margin,
            || (env.name.clone(), self.link_names[s.link].clone()),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use parry3d_f64::math::Rotation;
    use parry3d_f64::shape::Cuboid;

    /// The separating-axis test answers as parry's cuboid–cuboid intersection test on random
    /// boxes, and never "apart" for boxes that touch.
    #[test]
    fn oriented_boxes_answer_as_parry() {
        let mut rng = crate::rng::Rng::new(35);
        let mut r = |lo: Real, hi: Real| rng.uniform(lo, hi);
        let (mut disagreements, mut touching, mut apart) = (0, 0, 0);
        for _ in 0..20_000 {
            let random_pose = |r: &mut dyn FnMut(Real, Real) -> Real| {
                let axis = Vector::new(r(-1.0, 1.0), r(-1.0, 1.0), r(-1.0, 1.0));
                let rotation = if axis.length() > 1e-3 {
                    Rotation::from_axis_angle(axis.normalize(), r(-3.2, 3.2))
                } else {
                    Rotation::IDENTITY
                };
                Pose::from_parts(
                    Vector::new(r(-0.3, 0.3), r(-0.3, 0.3), r(-0.3, 0.3)),
                    rotation,
                )
            };
            let (p1, p2) = (random_pose(&mut r), random_pose(&mut r));
            let c1 = Vector::new(r(-0.1, 0.1), r(-0.1, 0.1), r(-0.1, 0.1));
            let c2 = Vector::new(r(-0.1, 0.1), r(-0.1, 0.1), r(-0.1, 0.1));
            let h1 = Vector::new(r(0.001, 0.2), r(0.001, 0.2), r(0.001, 0.2));
            let h2 = Vector::new(r(0.001, 0.2), r(0.001, 0.2), r(0.001, 0.2));
            let margin = if r(0.0, 1.0) < 0.5 { 0.0 } else { r(0.0, 0.02) };
            let (f1, f2) = (BoxFrame::of(&p1, c1), BoxFrame::of(&p2, c2));
            let ours = oriented_boxes_overlap((&f1, h1), (&f2, h2), margin);
            let half = Vector::splat(margin / 2.0);
            let q1 = Pose::from_parts(p1.transform_point(c1), p1.rotation);
            let q2 = Pose::from_parts(p2.transform_point(c2), p2.rotation);
            let theirs =
                query::distance(&q1, &Cuboid::new(h1 + half), &q2, &Cuboid::new(h2 + half))
                    .expect("two cuboids")
                    .distance;
            if theirs <= 0.0 {
                assert!(ours, "boxes {theirs} apart called apart");
                touching += 1;
            } else {
                apart += 1;
                if ours && theirs > 1e-9 {
                    disagreements += 1;
                }
            }
        }
        // Both answers are exercised.
        assert!(
            touching > 2_000 && apart > 2_000,
            "{touching} touching, {apart} apart"
        );
        // The 15 axes decide exactly for boxes: a pair called overlapping is within rounding.
        assert_eq!(disagreements, 0);
    }

    /// A link hull's climbing support function against a box and a cylinder answers as parry's
    /// dispatcher on the hull itself, with and without a margin.
    #[test]
    fn a_climbing_hull_against_obstacles_answers_as_parry() {
        let mut rng = crate::rng::Rng::new(36);
        let points: Vec<Vector> = (0..200)
            .map(|_| {
                let v = Vector::new(
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                    rng.uniform(-1.0, 1.0),
                );
                v.normalize() * Vector::new(0.05, 0.05, 0.15)
            })
            .collect();
        let hull = SharedShape::convex_hull(&points).expect("hull");
        let climbing = super::super::support::ClimbingHull::of(&hull).expect("a climbing hull");
        let centre = hull.compute_local_aabb().center();
        let obstacles = [
            SharedShape::cuboid(0.1, 0.02, 0.3),
            SharedShape::cylinder(0.1, 0.03),
        ];
        let (mut hits, mut misses) = (0, 0);
        for k in 0..4_000 {
            let obstacle = &obstacles[k % 2];
            let axis = Vector::new(
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
                rng.uniform(-1.0, 1.0),
            )
            .normalize();
            let pose = Pose::from_parts(
                Vector::new(
                    rng.uniform(-0.12, 0.12),
                    rng.uniform(-0.12, 0.12),
                    rng.uniform(-0.25, 0.25),
                ),
                Rotation::from_axis_angle(axis, rng.uniform(-3.2, 3.2)),
            );
            let margin = if k % 3 == 0 { 0.01 } else { 0.0 };
            let obstacle_map = environment_support_map(obstacle).expect("a support map");
            let ours = support_maps_touching(
                &pose,
                (&climbing, centre),
                (obstacle_map, obstacle.compute_local_aabb().center()),
                margin,
                None,
            );
            let distance = query::distance(&Pose::IDENTITY, &*hull.0, &pose, &*obstacle.0)
                .expect("supported")
                .distance;
            // Away from the boundary (GJK's tolerance), the answers agree.
            if (distance - margin).abs() > 1e-6 {
                assert_eq!(
                    ours,
                    distance <= margin,
                    "distance {distance}, margin {margin}"
                );
                if ours {
                    hits += 1;
                } else {
                    misses += 1;
                }
            }
        }
        assert!(hits > 400 && misses > 400, "{hits} hits, {misses} misses");
    }
}
