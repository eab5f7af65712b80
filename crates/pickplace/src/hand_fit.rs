//! The grasps the robot's real hand can close (issue 32). The grasp planner (paper §III-B.1)
//! checks a simple gripper model (pads, two finger boxes, a palm box); the robot's hand is
//! what its URDF says. Each grasp is tried once with that hand, closed on the object by the
//! grasp's command, and dropped when a link of the hand other than the pads enters the
//! object: the validator refuses such a grasp at every instant of the hold, so the planner
//! must never use it (a thumb's middle link, a finger's base link across the gap as in
//! example-robot-data's Alex SAKE hands).

use crate::contact::OBJECT_NAME;
use crate::robot_setup::RobotArm;
use pickplace_geometry::math::Real;
use pickplace_grasp::GraspSet;
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{
    BodyId, CheckOptions, CollisionScratch, CollisionShape, CollisionWorld, PairScope,
};
use pickplace_robot::srdf::DisableReason;
use std::collections::BTreeMap;

/// Drops from `grasps` those where `arm`'s hand, closed on the object (at the start state
/// `start` otherwise), puts a link other than its pads into the object; returns how many
/// each link dropped, by link name.
///
/// # Errors
/// Errors of forward kinematics and of the collision library (a defect, never a rejection).
pub(crate) fn drop_grasps_the_hand_cannot_close(
    model: &RobotModel,
    self_world: &CollisionWorld,
    arm: &RobotArm,
    start: &[Real],
    object: &CollisionShape,
    grasps: &mut GraspSet,
) -> Result<BTreeMap<String, usize>, pickplace_robot::Error> {
    let gripper = &arm.gripper;
    let pads: Vec<usize> = gripper.pad_links().into_iter().flatten().collect();
    let mut world = self_world.clone();
    let mut acm = world.acm().clone();
    for &l in &pads {
        acm.allow(
            OBJECT_NAME,
            &model.links()[l].name,
            DisableReason::Custom("a pad on the grasped object".into()),
        );
    }
    world.set_acm(acm);
    world.add_environment(
        OBJECT_NAME,
        object.clone(),
        &pickplace_geometry::math::Isometry3::identity(),
    );
    // Only the hand's links move (they are checked against the object); pads are allowed.
    let mut hand = vec![false; model.links().len()];
    for &l in gripper.hand_links() {
        hand[l] = !pads.contains(&l) && !model.links()[l].collisions.is_empty();
    }
    let mut scratch = CollisionScratch::default();
    let mut dropped: BTreeMap<String, usize> = BTreeMap::new();
    let mut q = start.to_vec();
    let mut keep = Vec::with_capacity(grasps.grasps.len());
    for g in &grasps.grasps {
        gripper.set_grasp(&mut q, g.width);
        let poses = model.link_poses(&q)?;
        let root_from_tcp = poses[arm.tcp_link];
        world.set_world_from_root(g.object_from_tcp * root_from_tcp.inverse());
        let pairs = world.colliding_pairs_in(
            model,
            &q,
            &mut scratch,
            &CheckOptions { margin: 0.0 },
            PairScope::MovingOnly(&hand),
        )?;
        let hit = pairs.iter().find_map(|&(a, b)| match (a, b) {
            (BodyId::Link(l), BodyId::Environment(_))
            | (BodyId::Environment(_), BodyId::Link(l)) => Some(l),
            _ => None,
        });
        match hit {
            Some(l) => *dropped.entry(model.links()[l].name.clone()).or_default() += 1,
            None => keep.push(*g),
        }
    }
    grasps.grasps = keep;
    Ok(dropped)
}
