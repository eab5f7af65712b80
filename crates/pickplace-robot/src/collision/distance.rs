//! Distances for reports: the nearest pair of the world, and the signed distance of two
//! bodies.

use super::{BodyId, CollisionScratch, CollisionWorld, DistanceReport, PairScope};
use crate::error::{Error, Result};
use crate::model::RobotModel;
use parry3d_f64::bounding_volume::Aabb;
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::Real;

impl CollisionWorld {
    /// The smallest distance between any pair that is checked (robot–environment,
    /// robot–robot, attached–robot, attached–environment), or `None` when there is no pair.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`].
    pub fn min_distance(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
    ) -> Result<Option<DistanceReport>> {
        self.prepare(model, q, scratch, 0.0, PairScope::Every)?;
        let mut best: Option<DistanceReport> = None;
        // Each pair is skipped when the gap between its boxes, a lower bound of its
        // distance, is already no better than the best found; the cheap primitive pairs
        // (self-collision) go first so that the bound is tight before the meshes.
        let mut visit = |aabb1: &Aabb,
                         p1: &Pose,
                         s1: &SharedShape,
                         aabb2: &Aabb,
                         p2: &Pose,
                         s2: &SharedShape,
                         first: BodyId,
                         second: BodyId|
         -> Result<()> {
            if best.is_some_and(|b| aabb_gap(aabb1, aabb2) >= b.distance) {
                return Ok(());
            }
            let d = query::distance(p1, &*s1.0, p2, &*s2.0)
                .map_err(|_| Error::UnsupportedCollisionPair {
                    first: self.body_name(first).to_owned(),
                    second: self.body_name(second).to_owned(),
                })?
                .distance;
            if best.is_none_or(|b| d < b.distance) {
                best = Some(DistanceReport {
                    distance: d,
                    first,
                    second,
                });
            }
            Ok(())
        };
        for &(a, b) in &self.self_pairs {
            let (a, b) = (a as usize, b as usize);
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            visit(
                &scratch.shape_aabbs[a],
                &scratch.shape_poses[a],
                &sa.shape,
                &scratch.shape_aabbs[b],
                &scratch.shape_poses[b],
                &sb.shape,
                BodyId::Link(sa.link),
                BodyId::Link(sb.link),
            )?;
        }
        for (k, a) in self.attached.iter().enumerate() {
            for (i, s) in self.robot_shapes.iter().enumerate() {
                if !a.allowed_links[s.link] {
                    visit(
                        &scratch.attached_aabbs[k],
                        &scratch.attached_poses[k],
                        &a.shape,
                        &scratch.shape_aabbs[i],
                        &scratch.shape_poses[i],
                        &s.shape,
                        BodyId::Attached(k),
                        BodyId::Link(s.link),
                    )?;
                }
            }
        }
        for (i, s) in self.robot_shapes.iter().enumerate() {
            for (e, env) in self.environment.iter().enumerate() {
                if !env.allowed_links[s.link] {
                    visit(
                        &scratch.shape_aabbs[i],
                        &scratch.shape_poses[i],
                        &s.shape,
                        &self.environment_aabbs[e],
                        &env.world_from_shape,
                        &env.shape,
                        BodyId::Link(s.link),
                        BodyId::Environment(e),
                    )?;
                }
            }
        }
        for (k, a) in self.attached.iter().enumerate() {
            for (e, env) in self.environment.iter().enumerate() {
                if !a.allowed_environment[e] {
                    visit(
                        &scratch.attached_aabbs[k],
                        &scratch.attached_poses[k],
                        &a.shape,
                        &self.environment_aabbs[e],
                        &env.world_from_shape,
                        &env.shape,
                        BodyId::Attached(k),
                        BodyId::Environment(e),
                    )?;
                }
            }
        }
        Ok(best)
    }

    /// The signed distance between two bodies at `q` (m): the distance between their nearest
    /// shapes when they are apart, minus the deepest penetration of their shapes when they
    /// overlap (a mesh's penetration is measured from its triangles). For reports, e.g. of a
    /// start state in collision; the ACM is not consulted.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`]; [`Error::InvalidParameter`] for a body the
    /// world does not have or a link without collision geometry.
    pub fn signed_distance(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        first: BodyId,
        second: BodyId,
    ) -> Result<Real> {
        self.prepare(model, q, scratch, 0.0, PairScope::Every)?;
        let scratch = &*scratch;
        let exists = |b: BodyId| match b {
            BodyId::Link(i) => self.robot_shapes.iter().any(|s| s.link == i),
            BodyId::Environment(i) => i < self.environment.len(),
            BodyId::Attached(i) => i < self.attached.len(),
        };
        for b in [first, second] {
            if !exists(b) {
                let index = match b {
                    BodyId::Link(i) | BodyId::Environment(i) | BodyId::Attached(i) => i,
                };
                return Err(Error::InvalidParameter {
                    name: "body",
                    value: index as Real,
                    reason: "no such body with collision geometry in the world",
                });
            }
        }
        let shapes_of = |b: BodyId| -> Box<dyn Iterator<Item = (Pose, &SharedShape)> + '_> {
            match b {
                BodyId::Link(l) => Box::new(
                    self.robot_shapes
                        .iter()
                        .enumerate()
                        .filter(move |(_, s)| s.link == l)
                        .map(|(i, s)| (scratch.shape_poses[i], &s.shape)),
                ),
                BodyId::Environment(e) => Box::new(std::iter::once((
                    self.environment[e].world_from_shape,
                    &self.environment[e].shape,
                ))),
                BodyId::Attached(k) => Box::new(std::iter::once((
                    scratch.attached_poses[k],
                    &self.attached[k].shape,
                ))),
            }
        };
        let unsupported = |_| Error::UnsupportedCollisionPair {
            first: self.body_name(first).to_owned(),
            second: self.body_name(second).to_owned(),
        };
        let mut best = Real::INFINITY;
        for (p1, s1) in shapes_of(first) {
            for (p2, s2) in shapes_of(second) {
                let d = query::distance(&p1, &*s1.0, &p2, &*s2.0)
                    .map_err(unsupported)?
                    .distance;
                let d = if d > 0.0 {
                    d
                } else {
                    query::contact(&p1, &*s1.0, &p2, &*s2.0, 0.0)
                        .map_err(unsupported)?
                        .map_or(0.0, |c| c.dist.min(0.0))
                };
                best = best.min(d);
            }
        }
        Ok(best)
    }
}

/// The distance between two boxes (0 when they overlap): a lower bound of the distance
/// between the shapes inside them.
fn aabb_gap(a: &Aabb, b: &Aabb) -> Real {
    let gap = (a.mins - b.maxs)
        .max(b.mins - a.maxs)
        .max(parry3d_f64::math::Vector::ZERO);
    gap.length()
}
