//! The rules the planner and the validator share (issue 34): how finely a motion is checked,
//! where a resting object may touch its support, and how far apart the two hands stay. The
//! planner keeps them when it plans; the validator reports a plan that breaks them; neither
//! imports the other.

use crate::error::{Error, Result, internal};
use crate::setup::Setup;
use crate::strategy::Arm;
use pickplace_geometry::math::Real;
use pickplace_robot::collision::{
    AllowedCollisionMatrix, BodyId, CheckOptions, CollisionScratch, CollisionWorld, PairScope,
};
use pickplace_robot::srdf::DisableReason;

/// Largest joint change between checked states (rad): 1°.
pub const MAX_JOINT_STEP: Real = std::f64::consts::PI / 180.0;
/// Largest tool-frame displacement between checked states (m).
pub const MAX_CARTESIAN_STEP: Real = 0.01;
/// Within this distance (m) of a resting pose (the start, an intermediate rest, the final
/// pose) the object may touch the support it rests on there: the planner's default
/// ([`crate::planner::PlanOptions::contact_zone`]).
pub const CONTACT_ZONE: Real = 0.005;
/// What the validator allows beyond [`CONTACT_ZONE`] (m): the object near a resting pose
/// between two samples of the timed trajectory is up to this much farther from it than at
/// the samples the planner checked. The validator accepts contact within
/// `CONTACT_ZONE + CONTACT_ZONE_SLACK`.
pub const CONTACT_ZONE_SLACK: Real = 0.001;
/// Least distance (m) between the two hands' links (each arm's gripper links and the link
/// carrying them), measured on their collision geometry at every checked state. The planner
/// keeps the same clearance at a handover.
pub const HAND_CLEARANCE: Real = 0.01;
/// What the hand clearance may lose to the linear interpolation between samples (m): the
/// validator reports hands closer than `HAND_CLEARANCE - HAND_CLEARANCE_SLACK`.
pub const HAND_CLEARANCE_SLACK: Real = 0.001;

/// The links of a hand: the gripper's links ([`crate::setup::ArmSetup::finger_links`]) and
/// the link carrying them (the nearest ancestor outside the hand that has collision
/// geometry).
fn hand_links(setup: &Setup, arm: Arm) -> Result<Vec<usize>> {
    let model = &setup.model;
    let mut links = Vec::new();
    for name in &setup.arm(arm).finger_links {
        let l = model.link_index(name).ok_or_else(|| Error::Internal {
            stage: "validator: hand clearance",
            reason: format!("the hand link {name:?} is not in the robot"),
        })?;
        links.push(l);
    }
    let fingers = links.clone();
    for &l in &fingers {
        let mut p = model.parent_link(l);
        while let Some(k) = p {
            if !fingers.contains(&k) && !model.links()[k].collisions.is_empty() {
                if !links.contains(&k) {
                    links.push(k);
                }
                break;
            }
            p = model.parent_link(k);
        }
    }
    links.sort_unstable();
    Ok(links)
}

/// The two hands' clearance (§III-B.3 handover, issue 17): a collision world of the robot
/// in which only the pairs of a right-hand link and a left-hand link (`hand_links`) are
/// checked, so that the margin and distance queries of the collision crate measure the hands
/// on their real link geometry. The planner keeps [`HAND_CLEARANCE`] with it; the validator
/// reports states below `HAND_CLEARANCE - HAND_CLEARANCE_SLACK`.
#[derive(Debug, Clone)]
pub struct HandClearance {
    world: CollisionWorld,
    /// The right hand's links.
    right: Vec<usize>,
}

/// The nearest pair of hand links at a state.
#[derive(Debug, Clone, PartialEq)]
pub struct HandGap {
    /// The right hand's link.
    pub right: String,
    /// The left hand's link.
    pub left: String,
    /// Their distance (m); 0 when they touch or overlap.
    pub distance: Real,
}

impl HandClearance {
    /// The check for a two-armed robot; `None` for a robot with one arm.
    ///
    /// # Errors
    /// [`Error::Internal`] when a hand link of the setup is not in the robot.
    pub fn new(setup: &Setup) -> Result<Option<Self>> {
        if !(setup.has_arm(Arm::Right) && setup.has_arm(Arm::Left)) {
            return Ok(None);
        }
        let right = hand_links(setup, Arm::Right)?;
        let left = hand_links(setup, Arm::Left)?;
        let names: Vec<&str> = setup
            .model
            .links()
            .iter()
            .map(|l| l.name.as_str())
            .collect();
        let hand_pair = |a: usize, b: usize| {
            (right.contains(&a) && left.contains(&b)) || (right.contains(&b) && left.contains(&a))
        };
        let mut acm = AllowedCollisionMatrix::new();
        let reason = || DisableReason::Custom("not a pair of the two hands".into());
        for a in 0..names.len() {
            for b in a + 1..names.len() {
                if !hand_pair(a, b) {
                    acm.allow(names[a], names[b], reason());
                }
            }
            // The environment is not this check's business.
            for e in &setup.environment {
                acm.allow(names[a], &e.name, reason());
            }
        }
        let mut world = setup.world.clone();
        world.detach_all();
        world.set_acm(acm);
        Ok(Some(Self { world, right }))
    }

    /// The first pair of hand links closer than `margin` (m) at `q`, if any.
    ///
    /// # Errors
    /// [`Error::Internal`] when the collision query fails.
    pub fn closer_than(
        &self,
        setup: &Setup,
        q: &[Real],
        margin: Real,
        scratch: &mut CollisionScratch,
    ) -> Result<Option<HandGap>> {
        let options = CheckOptions { margin };
        let pairs = self
            .world
            .colliding_pairs_in(&setup.model, q, scratch, &options, PairScope::Every)
            .map_err(internal("hand clearance"))?;
        for (a, b) in pairs {
            if let (BodyId::Link(_), BodyId::Link(_)) = (a, b) {
                let d = self
                    .world
                    .signed_distance(&setup.model, q, scratch, a, b)
                    .map_err(internal("hand clearance"))?;
                return Ok(Some(self.gap(a, b, d.max(0.0))));
            }
        }
        Ok(None)
    }

    /// The nearest pair of hand links at `q` and their distance.
    ///
    /// # Errors
    /// [`Error::Internal`] when the distance query fails or finds no pair.
    pub fn distance(
        &self,
        setup: &Setup,
        q: &[Real],
        scratch: &mut CollisionScratch,
    ) -> Result<HandGap> {
        let report = self
            .world
            .min_distance(&setup.model, q, scratch)
            .map_err(internal("hand clearance"))?
            .ok_or_else(|| Error::Internal {
                stage: "hand clearance",
                reason: "the hands have no collision geometry".into(),
            })?;
        Ok(self.gap(report.first, report.second, report.distance))
    }

    fn gap(&self, a: BodyId, b: BodyId, distance: Real) -> HandGap {
        let right_first = matches!(a, BodyId::Link(l) if self.right.contains(&l));
        let (r, l) = if right_first { (a, b) } else { (b, a) };
        HandGap {
            right: self.world.body_name(r).to_owned(),
            left: self.world.body_name(l).to_owned(),
            distance,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hands_clearance_is_measured_between_the_hands_links_only() {
        let setup = crate::testing::setup("fig9-near.toml");
        let hands = HandClearance::new(setup)
            .expect("hand links")
            .expect("two arms");
        let mut scratch = CollisionScratch::default();
        let gap = hands
            .distance(setup, &setup.start, &mut scratch)
            .expect("distance");
        // At the start the hands are far apart (and the arms touch nothing else either).
        assert!(gap.distance > 0.1, "{gap:?}");
        assert!(gap.right.starts_with("RARM"), "{gap:?}");
        assert!(gap.left.starts_with("LARM"), "{gap:?}");
        assert_eq!(
            hands
                .closer_than(setup, &setup.start, HAND_CLEARANCE, &mut scratch)
                .expect("query"),
            None
        );
        // The margin query finds the same pair once the margin covers the gap.
        let near = hands
            .closer_than(setup, &setup.start, gap.distance + 0.01, &mut scratch)
            .expect("query")
            .expect("within the margin");
        assert!(
            (near.distance - gap.distance).abs() < 1e-6,
            "{near:?} {gap:?}"
        );
        let links = hand_links(setup, Arm::Right).expect("links");
        assert!(links.len() > setup.arm(Arm::Right).finger_links.len());
    }
}
