//! The finger pads' gaps to the held object, measured once per relative pose (issue 33).
//!
//! While a hand carries the object, its pads keep their pose relative to the object: the
//! validator checks hundreds of states along a transfer, and each exact pad-to-mesh query
//! (contact with penetration depth against a scanned mesh of thousands of triangles) used to
//! be repeated for the same relative pose, 78 % of a handover's validation. The gaps are a
//! function of the pads' poses in the object's frame only, so they are memoized by those
//! poses, quantized to [`QUANTUM`]: two states in one bucket differ by at most a few
//! nanometres (and nanoradians) in any pad's pose, far below the grip's tolerances
//! ([`super::GRIP_TOLERANCE`], 0.5 mm); a pose near a bucket's border only costs a new
//! measurement.

use crate::error::{Result, internal};
use crate::strategy::Arm;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_robot::gripper::{GripObject, Gripper};
use std::collections::HashMap;

/// The grid of the memo's keys: metres for translations, unit-quaternion components for
/// rotations (a component step of 1e-9 is about 2e-9 rad).
const QUANTUM: Real = 1e-9;

/// Pad gaps by hand and by the pads' quantized poses in the object's frame.
#[derive(Debug, Default)]
pub(super) struct GripMemo {
    gaps: HashMap<(Arm, Vec<i64>), [Real; 2]>,
    /// Exact measurements made (the rest were found in the memo).
    pub(super) measured: usize,
}

impl GripMemo {
    /// The signed gaps of `gripper`'s two pads to `object` at `world_from_object`
    /// ([`Gripper::finger_gaps`]), `world_from_links` being every link's world pose.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when the collision library cannot measure a pad.
    pub(super) fn gaps(
        &mut self,
        arm: Arm,
        gripper: &Gripper,
        world_from_links: &[Isometry3],
        object: &GripObject,
        world_from_object: &Isometry3,
    ) -> Result<[Real; 2]> {
        let object_from_world = world_from_object.inverse();
        let mut key = Vec::new();
        for links in gripper.pad_links() {
            for link in links {
                let Some(pose) = world_from_links.get(link) else {
                    continue;
                };
                let rel = object_from_world * pose;
                let q = rel.rotation.quaternion().coords;
                // q and -q are one rotation: the sign with w >= 0 (a tie only misses).
                let sign = if q.w < 0.0 { -1.0 } else { 1.0 };
                let t = rel.translation.vector;
                key.extend(
                    [
                        t.x,
                        t.y,
                        t.z,
                        sign * q.x,
                        sign * q.y,
                        sign * q.z,
                        sign * q.w,
                    ]
                    .map(|v| (v / QUANTUM).round() as i64),
                );
            }
        }
        if let Some(gaps) = self.gaps.get(&(arm, key.clone())) {
            return Ok(*gaps);
        }
        let gaps = gripper
            .finger_gaps(world_from_links, object, world_from_object)
            .map_err(internal("grip check"))?;
        self.measured += 1;
        self.gaps.insert((arm, key), gaps);
        Ok(gaps)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Translation3, UnitQuaternion};

    #[test]
    fn a_carried_object_is_measured_once_and_a_moved_finger_again() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = &setup.arms[0];
        let object = GripObject::new(&setup.object_mesh).expect("mesh");
        let mut q = setup.start.clone();
        arm.gripper.set_open(&mut q);
        let links = |q: &[Real], carry: &Isometry3| -> Vec<Isometry3> {
            setup
                .model
                .link_poses(q)
                .expect("fk")
                .into_iter()
                .map(|p| carry * setup.world_from_root * p)
                .collect()
        };
        let mut memo = GripMemo::default();
        let here = Isometry3::identity();
        let first = memo
            .gaps(
                arm.arm,
                &arm.gripper,
                &links(&q, &here),
                &object,
                &setup.object_start,
            )
            .expect("measures");
        // The hand and the object moved together: the same relative pose, no new query.
        let carry = Isometry3::from_parts(
            Translation3::new(0.1, -0.2, 0.3),
            UnitQuaternion::from_euler_angles(0.2, -0.1, 0.4),
        );
        let moved = memo
            .gaps(
                arm.arm,
                &arm.gripper,
                &links(&q, &carry),
                &object,
                &(carry * setup.object_start),
            )
            .expect("measures");
        assert_eq!(memo.measured, 1);
        for (a, b) in first.iter().zip(&moved) {
            assert!((a - b).abs() < 1e-7, "{first:?} {moved:?}");
        }
        // The fingers moved: measured again, and the exact value.
        let mut closed = q.clone();
        arm.gripper.set_opening(&mut closed, 0.03);
        let world_from_links = links(&closed, &here);
        let again = memo
            .gaps(
                arm.arm,
                &arm.gripper,
                &world_from_links,
                &object,
                &setup.object_start,
            )
            .expect("measures");
        assert_eq!(memo.measured, 2);
        let exact = arm
            .gripper
            .finger_gaps(&world_from_links, &object, &setup.object_start)
            .expect("measures");
        assert_eq!(again, exact);
    }
}
