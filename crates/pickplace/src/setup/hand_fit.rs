//! The grasps the robot's real hand can close (issue 32). The grasp planner (paper §III-B.1)
//! checks a simple gripper model (pads, two finger boxes, a palm box); the robot's hand is
//! what its URDF says. Each grasp is tried once with that hand, closed on the object by the
//! grasp's command, and dropped when a link of the hand other than the pads enters the
//! object: the validator refuses such a grasp at every instant of the hold, so the planner
//! must never use it (a thumb's middle link, a finger's base link across the gap as in
//! example-robot-data's Alex SAKE hands). A hand with one moving jaw has each grasp's
//! command found on the object (a jaw that turns against a fixed one, SO-101's or Z1's,
//! meets the object where the object reaches, not where its opening table's innermost point
//! is), and the grasp is dropped when a pad then stands off the object by more than the
//! validator's [`GRIP_GAP`] or presses into it deeper than the squeeze. (A parallel
//! gripper's opening table is exact: its pads are not measured again here, which on a
//! scanned object of thousands of triangles would cost half a second.)

use crate::contact::OBJECT_NAME;
use pickplace_geometry::math::Real;
use pickplace_geometry::mesh::TriMesh;
use pickplace_grasp::{Grasp, GraspSet};
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{
    BodyId, CheckOptions, CollisionScratch, CollisionShape, CollisionWorld, PairScope,
};
use pickplace_robot::gripper::{
    FIXED_JAW_CLEARANCE, GRIP_GAP, GRIP_TOLERANCE, GripObject, Gripper,
};
use pickplace_robot::srdf::DisableReason;
use std::collections::BTreeMap;

/// Drops from `grasps` those where the hand of `gripper` (tool point at link `tcp_link`),
/// closed on the object (at the start state `start` otherwise), puts a link other than its
/// pads into the object, or (one moving jaw) leaves a pad off it or too deep in it; returns
/// how many each reason dropped ("hand link L in the object", "pad N off the object", "pad N
/// deeper than the squeeze").
///
/// # Errors
/// Errors of forward kinematics and of the collision library (a defect, never a rejection).
pub(crate) fn drop_grasps_the_hand_cannot_close(
    model: &RobotModel,
    self_world: &CollisionWorld,
    (gripper, tcp_link): (&Gripper, usize),
    start: &[Real],
    (object, object_mesh): (&CollisionShape, &TriMesh),
    grasps: &mut GraspSet,
) -> Result<BTreeMap<String, usize>, pickplace_robot::Error> {
    // The pads of a hand with one moving jaw are measured on the object itself (module
    // docs); a parallel gripper's table is exact, and the object's mesh (thousands of
    // triangles when scanned) is not queried for it.
    let grip_object = if gripper.has_fixed_jaw() {
        Some(GripObject::new(object_mesh).map_err(unmeasurable)?)
    } else {
        None
    };
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
        let mut g = *g;
        if let Some(object) = &grip_object {
            g.width = jaw_contact_width(model, (gripper, tcp_link), &mut q, &g, object)?;
        }
        gripper.set_grasp(&mut q, g.width);
        let poses = model.link_poses(&q)?;
        let root_from_tcp = poses[tcp_link];
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
        if let Some(l) = hit {
            *dropped
                .entry(format!("hand link {} in the object", model.links()[l].name))
                .or_default() += 1;
            continue;
        }
        let Some(object) = &grip_object else {
            keep.push(g);
            continue;
        };
        let world_from_root = g.object_from_tcp * root_from_tcp.inverse();
        let world_from_links: Vec<_> = poses.iter().map(|p| world_from_root * p).collect();
        let gaps = gripper
            .finger_gaps(
                &world_from_links,
                object,
                &pickplace_geometry::math::Isometry3::identity(),
            )
            .map_err(unmeasurable)?;
        let pad_problem = gaps.iter().enumerate().find_map(|(pad, &gap)| {
            if gap > GRIP_GAP {
                Some(format!("pad {} off the object", pad + 1))
            } else if -gap > gripper.squeeze() + GRIP_TOLERANCE {
                Some(format!("pad {} deeper than the squeeze", pad + 1))
            } else {
                None
            }
        });
        match pad_problem {
            Some(reason) => *dropped.entry(reason).or_default() += 1,
            None => keep.push(g),
        }
    }
    grasps.grasps = keep;
    Ok(dropped)
}

/// A finger pad the collision library cannot measure against the object (a defect).
fn unmeasurable(_: pickplace_robot::gripper::GripperError) -> pickplace_robot::Error {
    pickplace_robot::Error::UnsupportedCollisionPair {
        first: "a finger pad".to_owned(),
        second: OBJECT_NAME.to_owned(),
    }
}

/// The width to give grasp `g` so that its command closes a hand's one moving jaw onto the
/// object by the squeeze. The opening table measures the jaw's innermost point; a jaw that
/// turns meets the object elsewhere when the object does not reach that point (a box held by
/// its top edge), so the command is found on the object itself: secant steps on the moving
/// pad's gap, from the table's command. A sliding jaw's table is exact: its width is kept.
///
/// # Errors
/// Errors of forward kinematics and of the collision library.
fn jaw_contact_width(
    model: &RobotModel,
    (gripper, tcp_link): (&Gripper, usize),
    q: &mut [Real],
    g: &Grasp,
    object: &GripObject,
) -> Result<Real, pickplace_robot::Error> {
    let (lo, hi) = gripper.opening_range();
    let squeeze = gripper.squeeze();
    // `set_grasp` commands the opening `width + offset`.
    let offset = FIXED_JAW_CLEARANCE - squeeze;
    let mut pressed = |opening: Real| -> Result<Real, pickplace_robot::Error> {
        gripper.set_opening(q, opening);
        let poses = model.link_poses(q)?;
        let world_from_root = g.object_from_tcp * poses[tcp_link].inverse();
        let world: Vec<_> = poses.iter().map(|p| world_from_root * p).collect();
        let gap = gripper
            .finger_gap(
                0,
                &world,
                object,
                &pickplace_geometry::math::Isometry3::identity(),
            )
            .map_err(unmeasurable)?;
        // Zero when the moving pad is in by the squeeze.
        Ok(gap + squeeze)
    };
    const CLOSE_ENOUGH: Real = 1e-5;
    let first = (g.width + offset).clamp(lo, hi);
    let mut a = (first, pressed(first)?);
    if a.1.abs() < CLOSE_ENOUGH {
        return Ok(g.width);
    }
    let second = (a.0 - a.1).clamp(lo, hi);
    let mut b = (second, pressed(second)?);
    for _ in 0..8 {
        if b.1.abs() < CLOSE_ENOUGH || (b.0 - a.0).abs() < 1e-9 {
            break;
        }
        let slope = (b.1 - a.1) / (b.0 - a.0);
        let next = if slope > 0.1 {
            b.0 - b.1 / slope
        } else {
            b.0 - b.1
        };
        let next = next.clamp(lo, hi);
        a = b;
        b = (next, pressed(next)?);
    }
    Ok(b.0 - offset)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strategy::Arm;
    use pickplace_geometry::math::Translation3;

    #[test]
    fn a_grasp_whose_fixed_jaw_stands_off_the_object_is_dropped() {
        // Our one-jaw arm: every grasp of the set holds as the validator asks; moved 10 mm
        // along the closing axis (the tool point is on the fixed jaw), the fixed jaw's pad
        // stands off the object and the grasp is dropped with that reason.
        let setup = crate::testing::setup("robots/one-jaw-arm.toml");
        let arm = setup.arm(Arm::Right);
        let gripper = &arm.gripper;
        let world = CollisionWorld::new(&setup.model, setup.world.acm().clone()).expect("world");
        let check = |grasps: &mut GraspSet| {
            drop_grasps_the_hand_cannot_close(
                &setup.model,
                &world,
                (gripper, arm.tcp_link),
                &setup.start,
                (&setup.object_shape, &setup.object_mesh),
                grasps,
            )
            .expect("measured")
        };
        let mut kept = setup.grasp_set.clone();
        assert!(!kept.grasps.is_empty());
        assert!(check(&mut kept).is_empty());
        assert_eq!(kept.grasps.len(), setup.grasp_set.grasps.len());
        let mut off = setup.grasp_set.clone();
        for g in &mut off.grasps {
            g.object_from_tcp *= Translation3::new(0.0, 0.01, 0.0);
        }
        let dropped = check(&mut off);
        assert!(off.grasps.is_empty(), "{} kept", off.grasps.len());
        assert_eq!(
            dropped.get("pad 2 off the object"),
            Some(&setup.grasp_set.grasps.len()),
            "{dropped:?}"
        );
    }
}
