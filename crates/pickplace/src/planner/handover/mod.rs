//! The handover (paper §III-B.3, RIGHT-LEFT and LEFT-RIGHT): where the picking hand holds the
//! object in front of the torso, and which second grasp the placing hand takes there.
//!
//! The paper's planner hands the object over at one fixed pose. Here the pose is searched
//! ([`handover_candidates`]) and each feasible one is scored by both arms' reach margin and
//! the robot's clearance, so that the handover works for any object and grasp pair.

mod search;

use super::keypose::{Pick, Place};
use super::reason::{Attempt, Rejection, Role, Step, split};
use super::world::with_scratch;
use super::{Ctx, Memo as KeyMemo};
use crate::plan::StageCount;
use crate::setup::Setup;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{
    Isometry3, Matrix3, Point3, Real, Translation3, UnitQuaternion, Vector3,
};
use pickplace_geometry::obb::Obb;
use pickplace_grasp::{Grasp, GripperParams};
use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock};

/// Clearance kept between the two hands' gripper boxes in the cheap pre-test
/// ([`hands_overlap`]) (m); the real link geometry is then held to
/// [`crate::rules::HAND_CLEARANCE`].
const BOX_CLEARANCE: Real = 0.004;

/// A feasible handover.
#[derive(Debug, Clone)]
pub(super) struct Handover {
    /// The picking arm's grasp (index into the ranked grasps).
    pub g1: usize,
    /// The placing arm's grasp.
    pub g2: usize,
    /// Arm A's configuration at the handover (full).
    pub q_a: Vec<Real>,
    /// Arm B: pre-regrasp → regrasp (full configurations).
    pub approach: Vec<Vec<Real>>,
    /// Arm A: handover → retreat, fingers open (full configurations).
    pub retreat: Vec<Vec<Real>>,
}

/// Memo of the picking arm at a handover: per (picking arm, handover candidate, first
/// grasp), its configuration there or why it has none.
type ArmMemo = BTreeMap<(Arm, usize, usize), KeyMemo<Vec<Real>>>;

/// Memo of a second grasp at a handover: per (picking arm, handover candidate, first grasp,
/// second grasp), the scored handover or the reason the second grasp fails there.
type SecondGraspMemo =
    BTreeMap<(Arm, usize, usize, usize), std::result::Result<(Real, Handover), Rejection>>;

/// What the handover searches compute once per run and share between the placements.
#[derive(Default)]
pub(super) struct Memo {
    /// The picking arm at each handover candidate per first grasp.
    pub arm: Mutex<ArmMemo>,
    /// Each second grasp at each handover candidate per first grasp.
    pub second_grasp: Mutex<SecondGraspMemo>,
    /// The hands' clearance check, built once ([`Ctx::hands_too_close`]).
    pub hand_clearance: OnceLock<crate::Result<Option<crate::rules::HandClearance>>>,
}

impl Ctx<'_> {
    /// Tests a handover at object pose `world_from_object` (the `hi`-th candidate) with pick
    /// grasp `g1` of arm A; looks for a grasp of arm B among `places` (the grasps that place
    /// the object) that regrasps there. Returns the score (clearance and reach margin, higher
    /// is better) and the handover; each second grasp tried is counted in `regrasp`.
    ///
    /// Neither arm's result at a handover depends on the placement being searched: the
    /// picking arm's per (hi, g1) and each second grasp's per (hi, g1, g2) are computed once
    /// and replayed for the next placements (same result, same counts).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn handover_at(
        &self,
        strategy: Strategy,
        hi: usize,
        world_from_object: &Isometry3,
        g1: usize,
        pick: &Pick,
        places: &[(usize, Place)],
        regrasp: &mut StageCount,
    ) -> Attempt<(Real, Handover)> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let grasp1 = &self.run.grasps[g1];
        let pose_a = world_from_object * grasp1.object_from_tcp;
        let arm_a = self.run.setup.arm(a);
        if (pose_a.translation.vector - arm_a.shoulder.coords).norm() > arm_a.reach {
            return Err(Rejection::ArmOutOfReach(Role::Picking).into());
        }
        let lifted = super::end_of(&pick.lift)?;
        let salt = (hi as u64) << 24 | (g1 as u64) << 8 | 0x40;
        let holding_a = self.world_holding(a, &grasp1.object_from_tcp, &[])?;
        let memo = self
            .memo_lock(&self.handover.arm)
            .get(&(a, hi, g1))
            .cloned();
        let q_a = match memo {
            Some(r) => r?,
            None => {
                let r = split(
                    self.free_ik(a, &pose_a, lifted, salt, &holding_a)
                        .map_err(|f| f.at(Step::PickingArm)),
                )?;
                self.memo_lock(&self.handover.arm)
                    .insert((a, hi, g1), r.clone());
                r?
            }
        };
        // The second grasps the reachability map expects IK for here first, each group in
        // the order given.
        let mut places: Vec<&(usize, Place)> = places.iter().collect();
        places.sort_by_key(|(g2, _)| !self.reachable(b, *g2, world_from_object));
        for &&(g2, _) in &places {
            let key = (a, hi, g1, g2);
            let memo = self
                .memo_lock(&self.handover.second_grasp)
                .get(&key)
                .cloned();
            let outcome = match memo {
                Some(r) => r,
                None => {
                    let r = self.second_grasp_at(
                        strategy,
                        world_from_object,
                        (g1, g2),
                        (&q_a, salt),
                        &holding_a,
                    )?;
                    self.memo_lock(&self.handover.second_grasp)
                        .insert(key, r.clone());
                    r
                }
            };
            match outcome {
                Ok(found) => {
                    regrasp.accept();
                    return Ok(found);
                }
                Err(reason) => regrasp.reject(reason.to_string()),
            }
        }
        Err(Rejection::NoRegrasp.into())
    }

    /// Second grasp `g2` of arm B at the handover where arm A holds the object with `g1` at
    /// `world_from_object` in configuration `q_a`: the scored handover, or why `g2` fails
    /// there (the rejection as counted).
    ///
    /// # Errors
    /// [`crate::Error`] when a lower layer fails.
    fn second_grasp_at(
        &self,
        strategy: Strategy,
        world_from_object: &Isometry3,
        (g1, g2): (usize, usize),
        (q_a, salt): (&[Real], u64),
        holding_a: &pickplace_robot::collision::CollisionWorld,
    ) -> crate::Result<std::result::Result<(Real, Handover), Rejection>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let grasp1 = &self.run.grasps[g1];
        let pose_a = world_from_object * grasp1.object_from_tcp;
        let (arm_a, arm_b) = (self.run.setup.arm(a), self.run.setup.arm(b));
        let grasp2 = &self.run.grasps[g2];
        let pose_b = world_from_object * grasp2.object_from_tcp;
        if (pose_b.translation.vector - arm_b.shoulder.coords).norm() > arm_b.reach {
            return Ok(Err(Rejection::ArmOutOfReach(Role::Placing)));
        }
        // The two hands must not overlap: the second grasp's gripper against the first.
        if hands_overlap(&self.run.setup.gripper, grasp1, grasp2) {
            return Ok(Err(Rejection::HandsOverlap));
        }
        let seed = self.opened(b, q_a);
        let q_b = match split(self.free_ik(b, &pose_b, &seed, salt ^ (g2 as u64) << 40, holding_a))?
        {
            Ok(q) => q,
            Err(r) => return Ok(Err(r.at(Step::Regrasp))),
        };
        let pre_pose =
            pose_b * Translation3::from(-self.approach_axis() * self.run.options.approach_distance);
        let approach =
            match split(self.cartesian(b, &q_b, &pre_pose, &|_, _| holding_a, salt ^ 0x55))? {
                Ok(mut p) => {
                    p.reverse();
                    p
                }
                Err(r) => return Ok(Err(r.at(Step::RegraspApproach))),
            };
        // Both hold: B closes, then A opens and retreats with B holding.
        let both = self.gripping(b, &q_b, grasp2.width);
        // The two hands, as posed, keep the stated clearance on their real geometry.
        // (B open at its grasp, both closed, A open: the fingers sweep between them).
        if self.hands_too_close(&q_b)?
            || self.hands_too_close(&both)?
            || self.hands_too_close(&self.opened(a, &both))?
        {
            return Ok(Err(Rejection::HandsTooClose));
        }
        let holding_b = self.world_holding(b, &grasp2.object_from_tcp, &[])?;
        let a_open = self.opened(a, &both);
        if let Some(c) = self.collision(&holding_b, &a_open, 0.0)? {
            return Ok(Err(Rejection::Collision(c).at(Step::FirstHandRelease)));
        }
        let retreat_pose =
            pose_a * Translation3::from(-self.approach_axis() * self.run.options.approach_distance);
        let retreat = match split(self.cartesian(
            a,
            &a_open,
            &retreat_pose,
            &|_, _| &holding_b,
            salt ^ 0x66,
        ))? {
            Ok(p) => p,
            Err(r) => return Ok(Err(r.at(Step::FirstHandRetreat))),
        };
        // Score: clearance of the handover configuration (both arms at the object).
        let clearance = with_scratch(|scratch| {
            holding_a.min_distance(&self.run.setup.model, &approach[0], scratch)
        })
        .map_err(crate::error::internal("clearance"))?
        .map_or(1.0, |d| d.distance);
        let reach_margin = (arm_a.reach
            - (pose_a.translation.vector - arm_a.shoulder.coords).norm())
        .min(arm_b.reach - (pose_b.translation.vector - arm_b.shoulder.coords).norm());
        Ok(Ok((
            clearance.min(0.1) + reach_margin,
            Handover {
                g1,
                g2,
                q_a: q_a.to_vec(),
                approach,
                retreat,
            },
        )))
    }
}

impl Ctx<'_> {
    /// Whether the two hands' links come closer than [`crate::rules::HAND_CLEARANCE`] at
    /// the full configuration `q`, measured on their collision geometry by the validator's
    /// own check ([`crate::rules::HandClearance`]); never for a robot with one arm.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] when the collision library cannot measure a pair.
    pub(super) fn hands_too_close(&self, q: &[Real]) -> crate::Result<bool> {
        let check = match self
            .handover
            .hand_clearance
            .get_or_init(|| crate::rules::HandClearance::new(self.run.setup))
        {
            Ok(Some(check)) => check,
            Ok(None) => return Ok(false),
            // Built once; every later ask reports the same failure.
            Err(e) => {
                return Err(crate::Error::Internal {
                    stage: "hand clearance",
                    reason: e.to_string(),
                });
            }
        };
        with_scratch(|scratch| {
            check
                .closer_than(self.run.setup, q, crate::rules::HAND_CLEARANCE, scratch)
                .map(|gap| gap.is_some())
        })
    }
}

/// Whether the gripper of `second` (open) would overlap the gripper of `first` (closed on
/// the object) when both hold the object: any of their palm and finger boxes intersect
/// (separating-axis test on oriented boxes, [`Obb::intersects`], object frame), with
/// [`BOX_CLEARANCE`]. A cheap pre-test: the posed hands are then measured on the links'
/// collision geometry ([`Ctx::hands_too_close`]).
pub(super) fn hands_overlap(gripper: &GripperParams, first: &Grasp, second: &Grasp) -> bool {
    let boxes = |grasp: &Grasp, opening: Real| -> Vec<Obb> {
        let [f1, f2] = gripper.fingers(opening);
        [gripper.palm_box(), f1, f2]
            .into_iter()
            .map(|b| Obb {
                center: grasp.object_from_tcp * b.center,
                axes: grasp.object_from_tcp.rotation.to_rotation_matrix().matrix() * b.tcp_from_box,
                half: b.half_extents.add_scalar(BOX_CLEARANCE / 2.0),
            })
            .collect()
    };
    let a = boxes(first, first.width);
    let b = boxes(second, gripper.opening_max);
    a.iter().any(|x| b.iter().any(|y| x.intersects(y)))
}

/// Poses of the picking hand (`world_from_tcp`) tried for a handover, best guess first; the
/// object's handover pose is where this hand holds it. The original planner used one
/// hard-coded pose; here the pose is searched: tool positions in front of the torso between
/// the shoulders (0.30–0.42 m ahead, 0.15–0.25 m below the shoulders), approach directions
/// forward, forward and inward, forward and down, and down, each rolled in 90° steps. Each
/// feasible one is scored by both arms' reach margin and the robot's clearance.
pub fn handover_candidates(setup: &Setup, picking: Arm, count: usize) -> Vec<Isometry3> {
    let [r, l] = [
        setup.arm(Arm::Right).shoulder,
        setup.arm(Arm::Left).shoulder,
    ];
    let mid = Point3::from((r.coords + l.coords) / 2.0);
    let forward = setup.world_from_root.rotation * Vector3::x();
    let left = setup.world_from_root.rotation * Vector3::y();
    let up = Vector3::z();
    // The picking hand reaches across towards the other arm.
    let inward = match picking {
        Arm::Left => -left,
        Arm::Right => left,
    };
    let directions = [
        forward,
        (forward + inward).normalize(),
        (forward - up).normalize(),
        -up,
    ];
    let mut out = Vec::new();
    for &ahead in &[0.36, 0.30, 0.42] {
        for &height in &[-0.15, -0.25] {
            for approach in &directions {
                for roll in 0..4 {
                    let p = mid + forward * ahead + up * height;
                    // A frame with z along the approach; x from a reference not parallel to it.
                    let reference = if approach.cross(&up).norm() > 1e-6 {
                        up
                    } else {
                        forward
                    };
                    let x0 = reference.cross(approach).normalize();
                    let y0 = approach.cross(&x0);
                    let angle = Real::from(roll) * std::f64::consts::FRAC_PI_2;
                    let x = x0 * angle.cos() + y0 * angle.sin();
                    let y = approach.cross(&x);
                    let m = Matrix3::from_columns(&[x, y, *approach]);
                    let rotation = UnitQuaternion::from_matrix(&m);
                    out.push(Isometry3::from_parts(
                        Translation3::from(p.coords),
                        rotation,
                    ));
                }
            }
        }
    }
    out.truncate(count);
    out
}

#[cfg(test)]
mod tests {
    use super::super::tests::ctx;
    use super::*;

    #[test]
    fn candidates_are_right_handed_frames_approaching_along_z() {
        let setup = crate::testing::setup("fig9-near.toml");
        let poses = handover_candidates(setup, Arm::Right, 96);
        assert_eq!(poses.len(), 96);
        assert_eq!(handover_candidates(setup, Arm::Right, 5).len(), 5);
        for p in &poses {
            let m = p.rotation.to_rotation_matrix();
            assert!((m.matrix().determinant() - 1.0).abs() < 1e-9);
        }
        // The first pose approaches straight ahead; the right hand reaches across to the left.
        let forward = setup.world_from_root.rotation * Vector3::x();
        let z = poses[0].rotation * Vector3::z();
        assert!((z - forward).norm() < 1e-9);
        let inward = poses[4].rotation * Vector3::z();
        assert!(inward.dot(&(setup.world_from_root.rotation * Vector3::y())) > 0.5);
    }

    #[test]
    fn a_grasp_overlaps_itself_and_clears_its_opposite() {
        let ctx = ctx("fig9-near.toml");
        let g = &ctx.run.setup.gripper;
        let first = &ctx.run.grasps[0];
        assert!(hands_overlap(g, first, first));
        // The same grasp 20 cm away along the closing axis leaves room for the first.
        let mut away = *first;
        away.object_from_tcp *= Translation3::new(0.0, 0.2, 0.0);
        assert!(!hands_overlap(g, first, &away));
        // A grasp 1 mm from the first overlaps it.
        let mut near = *first;
        near.object_from_tcp *= Translation3::new(0.0, 0.0, -0.001);
        assert!(hands_overlap(g, first, &near));
    }
}
