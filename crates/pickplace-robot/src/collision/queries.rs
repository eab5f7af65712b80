//! The collision queries: the exact test of a pair, the walk over the pairs a query checks
//! (self pairs, robot against environment, attached objects against both) and the queries
//! built on it.

use super::{BodyId, CheckOptions, CollisionScratch, CollisionWorld, PairScope};
use crate::error::{Error, Result};
use crate::model::RobotModel;
use parry3d_f64::bounding_volume::BoundingVolume;
use parry3d_f64::math::Pose;
use parry3d_f64::query::{self, ClosestPoints};
use parry3d_f64::shape::SharedShape;
use pickplace_geometry::math::{Isometry3, Real};

impl CollisionWorld {
    /// The exact test of two shapes: overlap (margin 0) or closer than the margin.
    pub(super) fn touching(
        &self,
        pose1: &Pose,
        shape1: &SharedShape,
        pose2: &Pose,
        shape2: &SharedShape,
        margin: Real,
        names: impl Fn() -> (String, String),
    ) -> Result<bool> {
        let unsupported = |_| {
            let (first, second) = names();
            Error::UnsupportedCollisionPair { first, second }
        };
        if margin == 0.0 {
            Ok(
                query::intersection_test(pose1, &*shape1.0, pose2, &*shape2.0)
                    .map_err(unsupported)?
                    .intersecting,
            )
        } else {
            Ok(!matches!(
                query::closest_points(pose1, &*shape1.0, pose2, &*shape2.0, margin)
                    .map_err(unsupported)?,
                ClosestPoints::Disjoint
            ))
        }
    }

    /// [`CollisionWorld::touching`] of a mesh kept with its hull (an attached object, an
    /// environment object made [`CollisionShape::with_hull`]) and another shape: through the
    /// hull first when there is one (a hull clear of the other shape, or farther than the
    /// margin, leaves the mesh inside it clear too), then the mesh itself.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn hulled_touching(
        &self,
        pose1: &Pose,
        shape1: &SharedShape,
        hull1: Option<&SharedShape>,
        pose2: &Pose,
        shape2: &SharedShape,
        margin: Real,
        names: impl Fn() -> (String, String),
    ) -> Result<bool> {
        if let Some(hull) = hull1
            && !self.touching(pose1, hull, pose2, shape2, margin, &names)?
        {
            return Ok(false);
        }
        self.touching(pose1, shape1, pose2, shape2, margin, names)
    }

    /// Visits colliding pairs of the scope until `visit` returns false: the self pairs
    /// `self_pairs`, the robot shapes `env_shapes` (every shape when `None`) against the
    /// environment, the attached objects against both.
    pub(super) fn for_each_collision(
        &self,
        scratch: &mut CollisionScratch,
        margin: Real,
        scope: PairScope<'_>,
        self_pairs: &[(u32, u32)],
        env_shapes: Option<&[u32]>,
        visit: &mut dyn FnMut(BodyId, BodyId) -> bool,
    ) -> Result<()> {
        // Self-collision.
        for &(a, b) in self_pairs {
            let (a, b) = (a as usize, b as usize);
            let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
            let Some(pair_margin) =
                scope.pair_margin(scope.moves(sa.link) || scope.moves(sb.link), margin)
            else {
                continue;
            };
            if scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b])
                && self.robot_pair_touching(scratch, a, b, pair_margin)?
                && !visit(BodyId::Link(sa.link), BodyId::Link(sb.link))
            {
                return Ok(());
            }
        }
        // Robot against environment.
        let shape_count = env_shapes.map_or(self.robot_shapes.len(), <[u32]>::len);
        for n in 0..shape_count {
            let i = env_shapes.map_or(n, |shapes| shapes[n] as usize);
            let s = &self.robot_shapes[i];
            let Some(pair_margin) = scope.pair_margin(scope.moves(s.link), margin) else {
                continue;
            };
            // Most link boxes are far from every environment object: one box test, no BVH
            // traversal.
            if !self.environment_bounds.intersects(&scratch.shape_aabbs[i]) {
                continue;
            }
            scratch.candidates.clear();
            scratch
                .candidates
                .extend(self.environment_bvh.intersect_aabb(&scratch.shape_aabbs[i]));
            for c in 0..scratch.candidates.len() {
                let e = scratch.candidates[c] as usize;
                let env = &self.environment[e];
                if env.allowed_links[s.link] {
                    continue;
                }
                // A moving view's query keeps each pair's last separating direction.
                let slot = n * self.environment.len() + e;
                let last = if env_shapes.is_some() && scratch.view_key.is_some() {
                    scratch.env_directions.get_mut(slot)
                } else {
                    None
                };
                if self.robot_env_touching(
                    &scratch.shape_poses[i],
                    &scratch.shape_frames[i],
                    s,
                    env,
                    pair_margin,
                    last,
                )? && !visit(BodyId::Link(s.link), BodyId::Environment(e))
                {
                    return Ok(());
                }
            }
        }
        // Attached objects against robot and environment.
        for (k, a) in self.attached.iter().enumerate() {
            let attached_moves = scope.moves(a.link);
            for (i, s) in self.robot_shapes.iter().enumerate() {
                let Some(pair_margin) =
                    scope.pair_margin(attached_moves || scope.moves(s.link), margin)
                else {
                    continue;
                };
                if a.allowed_links[s.link]
                    || !scratch.attached_aabbs[k].intersects(&scratch.shape_aabbs[i])
                {
                    continue;
                }
                if self.hulled_touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    a.hull.as_ref(),
                    &scratch.shape_poses[i],
                    &s.shape,
                    pair_margin,
                    || (a.name.clone(), self.link_names[s.link].clone()),
                )? && !visit(BodyId::Attached(k), BodyId::Link(s.link))
                {
                    return Ok(());
                }
            }
            let Some(pair_margin) = scope.pair_margin(attached_moves, margin) else {
                continue;
            };
            scratch.candidates.clear();
            scratch.candidates.extend(
                self.environment_bvh
                    .intersect_aabb(&scratch.attached_aabbs[k]),
            );
            for c in 0..scratch.candidates.len() {
                let e = scratch.candidates[c] as usize;
                if a.allowed_environment[e] {
                    continue;
                }
                let env = &self.environment[e];
                if self.hulled_touching(
                    &scratch.attached_poses[k],
                    &a.shape,
                    a.hull.as_ref(),
                    &env.world_from_shape,
                    &env.shape,
                    pair_margin,
                    || (a.name.clone(), env.name.clone()),
                )? && !visit(BodyId::Attached(k), BodyId::Environment(e))
                {
                    return Ok(());
                }
            }
        }
        Ok(())
    }

    /// True when some pair that is not allowed is in collision (closer than the margin);
    /// stops at the first such pair. Every pair gets the margin ([`PairScope::Every`]).
    ///
    /// # Errors
    /// [`Error::WrongLength`] for `q`, [`Error::InvalidParameter`] for a bad margin,
    /// [`Error::UnsupportedCollisionPair`].
    ///
    /// # Performance
    /// FK, one AABB per shape, a BVH query per shape against the environment, an AABB test
    /// per self pair, and exact tests only on overlapping boxes.
    pub fn in_collision(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
    ) -> Result<bool> {
        Ok(self
            .first_collision(model, q, scratch, options, PairScope::Every)?
            .is_some())
    }

    /// The first colliding pair of `scope` that is not allowed (closer than its margin), or
    /// `None` when there is none; stops there. As cheap as [`CollisionWorld::in_collision`],
    /// which is this query with [`PairScope::Every`]; the pair is the first in the query's
    /// order (self pairs, robot–environment, attached objects), not the deepest.
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`], and [`Error::WrongLength`] for a mask that does
    /// not have one entry per link.
    ///
    /// # Performance
    /// As [`CollisionWorld::in_collision`]; with [`PairScope::MovingOnly`], static shapes
    /// skip their environment query and static pairs their box test.
    pub fn first_collision(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
        scope: PairScope<'_>,
    ) -> Result<Option<(BodyId, BodyId)>> {
        self.prepare(model, q, scratch, options.margin, scope)?;
        let mut found = None;
        self.for_each_collision(
            scratch,
            options.margin,
            scope,
            &self.self_pairs,
            None,
            &mut |a, b| {
                found = Some((a, b));
                false
            },
        )?;
        Ok(found)
    }

    /// Every colliding pair (link pairs reported once even when several shapes touch),
    /// sorted. Every pair gets the margin ([`PairScope::Every`]).
    ///
    /// # Errors
    /// As [`CollisionWorld::in_collision`].
    pub fn colliding_pairs(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
    ) -> Result<Vec<(BodyId, BodyId)>> {
        self.colliding_pairs_in(model, q, scratch, options, PairScope::Every)
    }

    /// Every colliding pair of `scope` (link pairs reported once even when several shapes
    /// touch), sorted.
    ///
    /// # Errors
    /// As [`CollisionWorld::first_collision`].
    pub fn colliding_pairs_in(
        &self,
        model: &RobotModel,
        q: &[Real],
        scratch: &mut CollisionScratch,
        options: &CheckOptions,
        scope: PairScope<'_>,
    ) -> Result<Vec<(BodyId, BodyId)>> {
        self.prepare(model, q, scratch, options.margin, scope)?;
        let mut pairs = Vec::new();
        self.for_each_collision(
            scratch,
            options.margin,
            scope,
            &self.self_pairs,
            None,
            &mut |a, b| {
                pairs.push((a, b));
                true
            },
        )?;
        pairs.sort_unstable();
        pairs.dedup();
        Ok(pairs)
    }

    /// Self-collision of link pairs only (no environment, no attached objects) for the
    /// given link poses: every colliding pair of link indices, sorted. Used to generate the
    /// allowed-collision matrix.
    ///
    /// # Errors
    /// [`Error::WrongLength`] for the poses; [`Error::UnsupportedCollisionPair`].
    pub fn colliding_link_pairs_all(
        &self,
        root_from_links: &[Isometry3],
        scratch: &mut CollisionScratch,
    ) -> Result<Vec<(usize, usize)>> {
        self.colliding_link_pairs_where(root_from_links, scratch, |_, _| true)
    }

    /// As [`CollisionWorld::colliding_link_pairs_all`], testing only the link pairs
    /// `(a, b)` (`a < b`, link indices) for which `wanted(a, b)` holds; the matrix
    /// generator leaves out the pairs it has already decided (links joined by a joint).
    ///
    /// # Errors
    /// As [`CollisionWorld::colliding_link_pairs_all`].
    pub fn colliding_link_pairs_where(
        &self,
        root_from_links: &[Isometry3],
        scratch: &mut CollisionScratch,
        wanted: impl Fn(usize, usize) -> bool,
    ) -> Result<Vec<(usize, usize)>> {
        if root_from_links.len() != self.link_names.len() {
            return Err(Error::WrongLength {
                what: "link poses",
                expected: self.link_names.len(),
                found: root_from_links.len(),
            });
        }
        scratch.link_poses.clear();
        scratch.link_poses.extend_from_slice(root_from_links);
        self.prepare_shapes(scratch, 0.0);
        let mut pairs = Vec::new();
        for a in 0..self.robot_shapes.len() {
            for b in a + 1..self.robot_shapes.len() {
                let (sa, sb) = (&self.robot_shapes[a], &self.robot_shapes[b]);
                let (la, lb) = (sa.link.min(sb.link), sa.link.max(sb.link));
                if la == lb
                    || !scratch.shape_aabbs[a].intersects(&scratch.shape_aabbs[b])
                    || !wanted(la, lb)
                {
                    continue;
                }
                if self.robot_shapes_touching(
                    &scratch.shape_poses[a],
                    sa,
                    &scratch.shape_poses[b],
                    sb,
                    0.0,
                )? {
                    pairs.push((la, lb));
                }
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        Ok(pairs)
    }
}
