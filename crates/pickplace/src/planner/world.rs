//! The collision worlds of a plan and the state check (paper §III-C: "collision between the
//! robot, the object and the environment is checked at the key postures"): the object lying
//! where it is (an obstacle), or held by a hand (attached to its tool link and allowed to
//! touch the fingers and, near a support, the support).

use super::Ctx;
use super::reason::{Collision, Rejection};
use crate::contact::OBJECT_NAME;
use crate::error::Result;
use crate::strategy::Arm;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_robot::collision::{
    BodyId, CheckOptions, CollisionScratch, CollisionWorld, PairScope,
};
use pickplace_robot::srdf::DisableReason;
use std::cell::RefCell;

/// A check of the full configuration on the segment ending at a waypoint: the first
/// collision, if any.
pub(super) type StateCheck<'c> = dyn Fn(usize, &[Real]) -> Result<Option<Collision>> + 'c;

thread_local! {
    static SCRATCH: RefCell<CollisionScratch> = Default::default();
}

/// Runs `f` with this thread's collision scratch space.
pub(super) fn with_scratch<T>(f: impl FnOnce(&mut CollisionScratch) -> T) -> T {
    SCRATCH.with(|cell| f(&mut cell.borrow_mut()))
}

impl Ctx<'_> {
    /// The world with the object lying at `world_from_object` as an obstacle.
    pub(super) fn world_with_object_at(&self, world_from_object: &Isometry3) -> CollisionWorld {
        let mut w = self.run.setup.world.clone();
        w.add_environment(
            OBJECT_NAME,
            self.run.setup.object_shape.clone(),
            world_from_object,
        );
        w
    }

    /// The world with the object held by `arm` (grasp `object_from_tcp`), allowed to touch
    /// the environment bodies `supports`.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when the arm's tool link is not in the world (a defect of
    /// the setup).
    pub(super) fn world_holding(
        &self,
        arm: Arm,
        object_from_tcp: &Isometry3,
        supports: &[String],
    ) -> Result<CollisionWorld> {
        let mut w = self.run.setup.world.clone();
        if !supports.is_empty() {
            let mut acm = w.acm().clone();
            for s in supports {
                acm.allow(
                    OBJECT_NAME,
                    s,
                    DisableReason::Custom("resting contact".into()),
                );
            }
            w.set_acm(acm);
        }
        let a = self.run.setup.arm(arm);
        let touch: Vec<&str> = a.finger_links.iter().map(String::as_str).collect();
        w.attach(
            OBJECT_NAME,
            &a.tcp_name,
            self.run.setup.object_shape.clone(),
            &object_from_tcp.inverse(),
            &touch,
        )
        .map_err(crate::error::internal("attach"))?;
        Ok(w)
    }

    /// The first colliding pair of the full configuration `q` in `world`, bodies closer than
    /// `margin` counting as colliding; `None` when free.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when the collision library fails (a configuration of the
    /// wrong length): a defect, never a rejection.
    pub(super) fn collision(
        &self,
        world: &CollisionWorld,
        q: &[Real],
        margin: Real,
    ) -> Result<Option<Collision>> {
        with_scratch(|scratch| {
            let opts = CheckOptions { margin };
            let model = &self.run.setup.model;
            // One pass, stopping at the first colliding pair in the query's (deterministic)
            // order: listing every pair to report the smallest cost as much again on a dense
            // object (issue 31: a third of a scanned object's planning time).
            let pair = world
                .first_collision(model, q, scratch, &opts, PairScope::Every)
                .map_err(crate::error::internal("collision check"))?;
            Ok(pair.map(|(a, b)| Collision {
                a: body_name(world, a),
                b: body_name(world, b),
            }))
        })
    }
}

impl Ctx<'_> {
    /// The first collision (margin 0) or breach of the hands' clearance along `path`, where
    /// `arm` moves, checked `density(a)` times as densely as the validator interpolates on
    /// the segment starting at `a` (no joint more than [`crate::rules::MAX_JOINT_STEP`] /
    /// density and the tool frame no more than [`crate::rules::MAX_CARTESIAN_STEP`] /
    /// density between two checked states). At a density of 2 the validator's states (at
    /// another phase) fall between these, and a grazing contact deep enough for it to see is
    /// seen here. The motion planner
    /// checks its edges at its own resolution and the straight motions at their IK steps; a
    /// grazing contact between those states would otherwise reach the plan and be refused by
    /// `pickplace validate`. `collides(i, q)` checks the full configuration `q` on the segment
    /// ending at waypoint `i`.
    pub(super) fn dense_collision(
        &self,
        arm: Arm,
        path: &[Vec<Real>],
        density: &dyn Fn(&[Real]) -> Real,
        collides: &StateCheck<'_>,
    ) -> Result<Option<Rejection>> {
        use crate::rules::{MAX_CARTESIAN_STEP, MAX_JOINT_STEP};
        let mut q = Vec::new();
        for i in 1..path.len() {
            let (a, b) = (&path[i - 1], &path[i]);
            let max_dq = a
                .iter()
                .zip(b)
                .map(|(x, y)| (y - x).abs())
                .fold(0.0, Real::max);
            let moved =
                (self.tcp(arm, b).translation.vector - self.tcp(arm, a).translation.vector).norm();
            let density = density(a);
            let steps = ((density * max_dq / MAX_JOINT_STEP)
                .max(density * moved / MAX_CARTESIAN_STEP)
                .ceil() as usize)
                .max(1);
            // Every state the motion adds (the hands' clearance is the validator's rule at
            // every state too).
            for s in 1..=steps {
                let f = s as Real / steps as Real;
                q.clear();
                q.extend(a.iter().zip(b).map(|(x, y)| x + f * (y - x)));
                if let Some(c) = collides(i, &q)? {
                    return Ok(Some(Rejection::DenseCollision(c)));
                }
                if self.hands_too_close(&q)? {
                    return Ok(Some(Rejection::HandsTooClose));
                }
            }
        }
        Ok(None)
    }
}

/// A body's name as the rejections print it: the held object is `held object`.
pub(super) fn body_name(world: &CollisionWorld, b: BodyId) -> String {
    match b {
        BodyId::Link(_) | BodyId::Environment(_) => world.body_name(b).to_owned(),
        BodyId::Attached(_) => "held object".to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::ctx;
    use super::*;
    use pickplace_geometry::math::Translation3;

    #[test]
    fn the_start_state_is_free_and_a_hand_inside_the_object_is_not() {
        let ctx = ctx("fig9-near.toml");
        let setup = ctx.run.setup;
        let free = ctx.world_with_object_at(&setup.object_start);
        assert_eq!(
            ctx.collision(&free, &setup.start, 0.0).expect("checks"),
            None
        );
        // The object moved onto the right wrist (behind the tool frame, along the approach
        // axis): the hand is inside it.
        let tcp = ctx.tcp(Arm::Right, &setup.start);
        let inside = ctx.world_with_object_at(&(tcp * Translation3::new(0.0, 0.0, -0.12)));
        let c = ctx
            .collision(&inside, &setup.start, 0.0)
            .expect("checks")
            .expect("collides");
        assert!(c.a == OBJECT_NAME || c.b == OBJECT_NAME, "{c}");
    }

    #[test]
    fn a_configuration_of_the_wrong_length_is_an_error_not_a_rejection() {
        let ctx = ctx("fig9-near.toml");
        let free = ctx.world_with_object_at(&ctx.run.setup.object_start);
        assert!(ctx.collision(&free, &[0.0; 3], 0.0).is_err());
    }

    #[test]
    fn the_held_object_is_named_as_such() {
        let ctx = ctx("fig9-near.toml");
        let g = &ctx.run.grasps[0];
        let holding = ctx
            .world_holding(Arm::Right, &g.object_from_tcp, &[])
            .expect("attaches");
        assert_eq!(body_name(&holding, BodyId::Attached(0)), "held object");
        assert_eq!(holding.body_name(BodyId::Attached(0)), OBJECT_NAME);
        assert!(
            ctx.world_holding(Arm::Right, &g.object_from_tcp, &["table".into()])
                .is_ok()
        );
    }
}
