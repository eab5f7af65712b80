//! Key poses (paper Fig. 8, §III-C): the grasp and place poses of a hand, checked cheapest
//! test first (reach, the gripper against the environment, IK over several branches, the
//! collision of the whole robot with the object attached), and the straight Cartesian
//! motions between them and their pre-poses: approach and lift at the pick, lowering and
//! retreat at the place.

use super::Ctx;
use super::reason::{Attempt, Rejection, Step, split};
use crate::contact::supports;
use crate::strategy::Arm;
use pickplace_base::rng::{Stream, salted};
use pickplace_geometry::math::{Isometry3, Real, Translation3, Vector3};
use pickplace_robot::IkOptions;
use pickplace_robot::collision::CollisionWorld;
use std::sync::{Mutex, MutexGuard};

/// IK solutions tried per key pose before it is rejected (see [`Ctx::free_ik`]).
pub(super) const IK_SOLUTIONS: usize = 4;

/// The result of picking with one arm and one grasp.
#[derive(Debug, Clone)]
pub(super) struct Pick {
    /// pre-grasp → grasp (fingers open).
    pub approach: Vec<Vec<Real>>,
    /// grasp → lift (fingers closed, object attached).
    pub lift: Vec<Vec<Real>>,
}

/// The result of placing with one arm and one grasp.
#[derive(Debug, Clone)]
pub(super) struct Place {
    /// pre-place → place (fingers closed, object attached).
    pub lower: Vec<Vec<Real>>,
    /// place → retreat (fingers open, object left).
    pub retreat: Vec<Vec<Real>>,
}

impl Ctx<'_> {
    /// IK options of one solve: six restarts, seeded from the plan's seed and `salt`.
    fn ik_options(&self, salt: u64) -> IkOptions {
        IkOptions {
            max_restarts: 6,
            seed: salted(self.run.options.seed, Stream::Ik, salt),
            ..IkOptions::default()
        }
    }

    /// IK of `arm` for `world_from_tcp`, seeded by `seed` (full configuration).
    pub(super) fn ik(
        &self,
        arm: Arm,
        world_from_tcp: &Isometry3,
        seed: &[Real],
        salt: u64,
    ) -> Option<Vec<Real>> {
        let a = self.run.setup.arm(arm);
        let root_from_tcp = self.run.setup.world_from_root.inverse() * world_from_tcp;
        let sol =
            a.ik.solve(&root_from_tcp, seed, &self.ik_options(salt))
                .ok()?;
        sol.success.then_some(sol.positions)
    }

    /// A collision-free IK solution in `world`: the solution nearest the seed first, then
    /// up to [`IK_SOLUTIONS`] others from seeded restarts (IK branches differ in elbow and
    /// wrist, and one of them often clears an obstacle the first hits). When the first solve
    /// (itself with seeded restarts) finds no solution, the pose is taken as out of the arm's
    /// reach at once: most candidates that fail, fail there.
    ///
    /// Rejected with [`Rejection::NoIk`], or the last [`Rejection::Collision`] found.
    pub(super) fn free_ik(
        &self,
        arm: Arm,
        world_from_tcp: &Isometry3,
        seed: &[Real],
        salt: u64,
        world: &CollisionWorld,
    ) -> Attempt<Vec<Real>> {
        // The solver's own seeded restarts found no solution at all: other branches are
        // sought to clear obstacles, not to reach.
        let first = self
            .ik(arm, world_from_tcp, seed, salt)
            .ok_or(Rejection::NoIk)?;
        self.free_ik_after(arm, first, world_from_tcp, seed, salt, world)
    }

    /// [`Ctx::free_ik`] once its first solve (from `seed`, with `salt`) has found `first`: a
    /// caller that builds the collision world only for poses with IK solves first.
    pub(super) fn free_ik_after(
        &self,
        arm: Arm,
        first: Vec<Real>,
        world_from_tcp: &Isometry3,
        seed: &[Real],
        salt: u64,
        world: &CollisionWorld,
    ) -> Attempt<Vec<Real>> {
        let reason = match self.collision(world, &first, 0.0)? {
            None => return Ok(first),
            Some(c) => Rejection::Collision(c),
        };
        let mut reason = reason;
        let a = self.run.setup.arm(arm);
        let mut rng =
            pickplace_prm::rng::Rng::new(salted(self.run.options.seed, Stream::IkSolutions, salt));
        let mut seed = seed.to_vec();
        for k in 1..IK_SOLUTIONS {
            for (c, &v) in a.variables.iter().enumerate() {
                seed[v] = rng.uniform(a.space.lower()[c], a.space.upper()[c]);
            }
            let Some(q) = self.ik(arm, world_from_tcp, &seed, salt.wrapping_add(k as u64)) else {
                continue;
            };
            match self.collision(world, &q, 0.0)? {
                None => return Ok(q),
                Some(c) => reason = Rejection::Collision(c),
            }
        }
        Err(reason.into())
    }

    /// `world_from_tcp` of the arm at `q`.
    pub(super) fn tcp(&self, arm: Arm, q: &[Real]) -> Isometry3 {
        self.run.setup.world_from_root * self.run.setup.arm(arm).ik.chain().pose(q)
    }

    /// `q` with the arm's pads `opening` apart (clamped into the gripper's range): the joint
    /// values come from the gripper measured on the URDF (revolute fingers, fingers closed at
    /// their upper limit and mimic chains alike).
    #[cfg(test)]
    pub(super) fn with_fingers(&self, arm: Arm, q: &[Real], opening: Real) -> Vec<Real> {
        let mut q = q.to_vec();
        self.run.setup.arm(arm).gripper.set_opening(&mut q, opening);
        q
    }

    /// `q` with the arm's fingers closed on a grasp `width` wide (the pads at the width less
    /// the gripper's squeeze).
    pub(super) fn gripping(&self, arm: Arm, q: &[Real], width: Real) -> Vec<Real> {
        let mut q = q.to_vec();
        self.run.setup.arm(arm).gripper.set_grasp(&mut q, width);
        q
    }

    /// `q` with the arm's hand open.
    pub(super) fn opened(&self, arm: Arm, q: &[Real]) -> Vec<Real> {
        let mut q = q.to_vec();
        self.run.setup.arm(arm).gripper.set_open(&mut q);
        q
    }

    /// The gripper's approach direction in its tool frame.
    pub(super) fn approach_axis(&self) -> Vector3 {
        self.run.setup.gripper.approach()
    }

    /// `q` with arm `other`'s joints and fingers taken from `from`.
    pub(super) fn other_from(&self, other: Arm, q: &[Real], from: &[Real]) -> Vec<Real> {
        let mut out = q.to_vec();
        let o = self.run.setup.arm(other);
        for &v in o.variables.iter().chain(&o.finger_variables) {
            out[v] = from[v];
        }
        out
    }

    /// `base` with `arm`'s joints (not its fingers) taken from `q`.
    pub(super) fn arm_from(&self, arm: Arm, base: &[Real], q: &[Real]) -> Vec<Real> {
        let mut out = base.to_vec();
        for &v in &self.run.setup.arm(arm).variables {
            out[v] = q[v];
        }
        out
    }

    /// A straight Cartesian motion of `arm` from configuration `from` (TCP at its pose) to
    /// `to_pose`, IK every [`super::PlanOptions::cartesian_step`]; each state is checked in
    /// the world `world_at(i, n)` returns.
    pub(super) fn cartesian<'w>(
        &self,
        arm: Arm,
        from: &[Real],
        to_pose: &Isometry3,
        world_at: &dyn Fn(usize, usize) -> &'w CollisionWorld,
        salt: u64,
    ) -> Attempt<Vec<Vec<Real>>> {
        let from_pose = self.tcp(arm, from);
        let distance = (to_pose.translation.vector - from_pose.translation.vector).norm();
        let angle = from_pose.rotation.angle_to(&to_pose.rotation);
        let n = ((distance / self.run.options.cartesian_step)
            .max(angle / 0.05)
            .ceil() as usize)
            .max(1);
        let mut path = vec![from.to_vec()];
        let variables = &self.run.setup.arm(arm).variables;
        for i in 1..=n {
            let s = i as Real / n as Real;
            let pose = Isometry3::from_parts(
                Translation3::from(
                    from_pose
                        .translation
                        .vector
                        .lerp(&to_pose.translation.vector, s),
                ),
                from_pose.rotation.slerp(&to_pose.rotation, s),
            );
            // The path holds `from` and the i − 1 steps before this one.
            let prev = &path[i - 1];
            let q = self
                .ik(arm, &pose, prev, salt.wrapping_add(i as u64))
                .ok_or(Rejection::NoIkOnLine)?;
            let jump = variables
                .iter()
                .map(|&v| (q[v] - prev[v]).abs())
                .fold(0.0, Real::max);
            if jump > self.run.options.max_joint_step {
                return Err(Rejection::BranchJump.into());
            }
            if let Some(c) = self.collision(world_at(i, n), &q, 0.0)? {
                return Err(Rejection::Collision(c).into());
            }
            path.push(q);
        }
        Ok(path)
    }

    /// The gripper (palm and fingers at `opening`) against the environment at
    /// `world_from_tcp`: the first environment part it hits.
    pub(super) fn hand_hits_environment(
        &self,
        world_from_tcp: &Isometry3,
        opening: Real,
    ) -> Option<Rejection> {
        let g = &self.run.setup.gripper;
        let [f1, f2] = g.fingers(opening);
        let bodies = [g.palm_box(), f1, f2];
        self.run
            .setup
            .environment
            .iter()
            .find(|e| {
                bodies.iter().any(|b| {
                    e.collider
                        .as_ref()
                        .is_some_and(|c| c.hits(world_from_tcp, b, 0.0))
                })
            })
            .map(|e| Rejection::GripperHits(e.name.clone()))
    }

    /// The world while `arm` moves the held object within
    /// [`super::PlanOptions::contact_zone`] of its support: the object may touch `supports`
    /// in the first part of the straight motion, nothing after.
    pub(super) fn contact_worlds(
        &self,
        arm: Arm,
        object_from_tcp: &Isometry3,
        supports: &[String],
    ) -> crate::Result<[CollisionWorld; 2]> {
        Ok([
            self.world_holding(arm, object_from_tcp, &[])?,
            self.world_holding(arm, object_from_tcp, supports)?,
        ])
    }

    /// Picks the object at its start with `arm` and grasp `gi`, from the scene's start
    /// configuration: the approach from the pre-grasp pose (fingers open) and the lift
    /// (fingers closed, object attached). Computed once per arm and grasp for every strategy
    /// of the plan (the result does not depend on the strategy).
    pub(super) fn pick(&self, arm: Arm, gi: usize) -> Attempt<Pick> {
        if let Some(r) = self.memo_lock(&self.memo.pick).get(&(arm, gi)) {
            return r.clone().map_err(Into::into);
        }
        let result = split(self.pick_at(
            arm,
            gi,
            &self.run.setup.object_start,
            &self.run.start_supports,
            &self.run.setup.start,
            0,
        ))?;
        self.memo_lock(&self.memo.pick)
            .insert((arm, gi), result.clone());
        result.map_err(Into::into)
    }

    /// Picks the object lying at `world_from_object` on `supports` with `arm` and grasp
    /// `gi`, from the full configuration `start`: the approach from the pre-grasp pose
    /// (fingers open) and the lift (fingers closed, object attached). `rest` tells the
    /// random choices of one resting pose from another's (0 for the object's start).
    pub(super) fn pick_at(
        &self,
        arm: Arm,
        gi: usize,
        world_from_object: &Isometry3,
        supports: &[String],
        start: &[Real],
        rest: u64,
    ) -> Attempt<Pick> {
        let a = self.run.setup.arm(arm);
        let g = &self.run.grasps[gi];
        let grasp_pose = world_from_object * g.object_from_tcp;
        if (grasp_pose.translation.vector - a.shoulder.coords).norm() > a.reach {
            return Err(Rejection::OutOfReach.into());
        }
        if let Some(r) = self.hand_hits_environment(&grasp_pose, self.run.setup.gripper.opening_max)
        {
            return Err(r.into());
        }
        let salt = salted((gi as u64) << 8 | arm.index() as u64, Stream::Rest, rest);
        let open = self.opened(arm, start);
        // IK first: most picks that fail have none, and need no world built.
        let first = self
            .ik(arm, &grasp_pose, &open, salt)
            .ok_or(Rejection::NoIk.at(Step::Grasp))?;
        let free = self.world_with_object_at(world_from_object);
        let q_grasp = self
            .free_ik_after(arm, first, &grasp_pose, &open, salt, &free)
            .map_err(|f| f.at(Step::Grasp))?;
        let pre_pose = grasp_pose
            * Translation3::from(-self.approach_axis() * self.run.options.approach_distance);
        let mut approach = self
            .cartesian(arm, &q_grasp, &pre_pose, &|_, _| &free, salt ^ 0x11)
            .map_err(|f| f.at(Step::Approach))?;
        approach.reverse();
        let closed = self.gripping(arm, &q_grasp, g.width);
        let [holding, holding_contact] = self.contact_worlds(arm, &g.object_from_tcp, supports)?;
        let lift_pose = Translation3::new(0.0, 0.0, self.run.options.lift_height) * grasp_pose;
        let world_at = self.near_support(&holding, &holding_contact);
        let lift = self
            .cartesian(arm, &closed, &lift_pose, &world_at, salt ^ 0x22)
            .map_err(|f| f.at(Step::Lift))?;
        if let Some(c) = self.collision(&holding_contact, &closed, 0.0)? {
            return Err(Rejection::Collision(c).at(Step::GraspClosed).into());
        }
        Ok(Pick { approach, lift })
    }

    /// Places the object with `arm`, grasp `gi`, at placement `pi`: the lowering from the
    /// pre-place pose and the retreat after the release, seeded from the start configuration
    /// with both hands open (the other arm rests there). Computed once per arm, placement
    /// and grasp for every strategy of the plan; the motions take the other arm's joints
    /// from where that arm is.
    pub(super) fn place(&self, arm: Arm, pi: usize, gi: usize) -> Attempt<Place> {
        if let Some(r) = self.memo_lock(&self.memo.place).get(&(arm, pi, gi)) {
            return r.clone().map_err(Into::into);
        }
        let p = &self.run.placements[pi];
        let supports = self.placement_supports(pi);
        let result = split(self.place_at(
            arm,
            gi,
            &p.world_from_object,
            supports,
            &self.run.open_start,
            (pi as u64) << 20,
        ))?;
        self.memo_lock(&self.memo.place)
            .insert((arm, pi, gi), result.clone());
        result.map_err(Into::into)
    }

    /// The environment bodies the object touches at placement `pi`, found once.
    pub(super) fn placement_supports(&self, pi: usize) -> &[String] {
        let p = &self.run.placements[pi];
        self.memo.placement_supports[pi]
            .get_or_init(|| supports(self.run.setup, &p.world_from_object))
    }

    /// The memo behind `mutex` (a poisoned lock still holds valid entries: each is inserted
    /// whole).
    pub(super) fn memo_lock<'m, T>(&self, mutex: &'m Mutex<T>) -> MutexGuard<'m, T> {
        mutex
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// Places the object with `arm` and grasp `gi` at `world_from_object`, where it rests on
    /// `supports`: the lowering from the pre-place pose and the retreat after the release.
    /// `seed` is a full configuration whose other joints are kept; `salt` tells the random
    /// choices of one placement from another's.
    pub(super) fn place_at(
        &self,
        arm: Arm,
        gi: usize,
        world_from_object: &Isometry3,
        supports: &[String],
        seed: &[Real],
        salt: u64,
    ) -> Attempt<Place> {
        let a = self.run.setup.arm(arm);
        let g = &self.run.grasps[gi];
        let place_pose = world_from_object * g.object_from_tcp;
        if (place_pose.translation.vector - a.shoulder.coords).norm() > a.reach {
            return Err(Rejection::OutOfReach.into());
        }
        if let Some(r) = self.hand_hits_environment(&place_pose, g.width) {
            return Err(r.into());
        }
        let salt = salt | (gi as u64) << 8 | 0x80 | arm.index() as u64;
        let closed_seed = self.gripping(arm, seed, g.width);
        // IK first: most places that fail have none, and need no world built.
        let first = self
            .ik(arm, &place_pose, &closed_seed, salt)
            .ok_or(Rejection::NoIk.at(Step::Place))?;
        let [holding, holding_contact] = self.contact_worlds(arm, &g.object_from_tcp, supports)?;
        let q_place = self
            .free_ik_after(
                arm,
                first,
                &place_pose,
                &closed_seed,
                salt,
                &holding_contact,
            )
            .map_err(|f| f.at(Step::Place))?;
        let pre_pose = Translation3::new(0.0, 0.0, self.run.options.lift_height) * place_pose;
        let world_at = self.near_support(&holding, &holding_contact);
        let mut lower = self
            .cartesian(arm, &q_place, &pre_pose, &world_at, salt ^ 0x33)
            .map_err(|f| f.at(Step::Lower))?;
        lower.reverse();
        let opened = self.opened(arm, &q_place);
        let left = self.world_with_object_at(world_from_object);
        if let Some(c) = self.collision(&left, &opened, 0.0)? {
            return Err(Rejection::Collision(c).at(Step::Release).into());
        }
        let retreat_pose = place_pose
            * Translation3::from(-self.approach_axis() * self.run.options.approach_distance);
        let retreat = self
            .cartesian(arm, &opened, &retreat_pose, &|_, _| &left, salt ^ 0x44)
            .map_err(|f| f.at(Step::Retreat))?;
        Ok(Place { lower, retreat })
    }

    /// Whether `arm` can hold grasp `gi` with the object at `world_from_object`, by the
    /// cheap tests that come before any IK: the tool pose within the arm's reach, and the
    /// gripper (open when `open`, else closed on the grasp's width) clear of every
    /// environment part. The search ranks placements by how many grasps pass.
    pub(super) fn grasp_fits(
        &self,
        arm: Arm,
        gi: usize,
        world_from_object: &Isometry3,
        open: bool,
    ) -> std::result::Result<(), Rejection> {
        let a = self.run.setup.arm(arm);
        let g = &self.run.grasps[gi];
        let pose = world_from_object * g.object_from_tcp;
        if (pose.translation.vector - a.shoulder.coords).norm() > a.reach {
            return Err(Rejection::OutOfReach);
        }
        let opening = if open {
            self.run.setup.gripper.opening_max
        } else {
            g.width
        };
        match self.hand_hits_environment(&pose, opening) {
            Some(r) => Err(r),
            None => Ok(()),
        }
    }

    /// The dense re-check of a straight motion of `arm` (`path` as the plan uses it) in the
    /// worlds its search used (`world_at(0, n)` near the key pose, `world_at(n, n)` beyond
    /// its contact zone; `reversed` when the path runs towards the key pose): the states
    /// between its IK steps at the validator's resolution (`Ctx::dense_collision`). Deferred from the
    /// search to the candidates whose motions are planned, since most straight motions
    /// computed belong to candidates rejected later.
    pub(super) fn check_straight<'w>(
        &self,
        arm: Arm,
        path: &[Vec<Real>],
        world_at: &dyn Fn(usize, usize) -> &'w CollisionWorld,
        reversed: bool,
    ) -> Attempt<()> {
        let n = path.len().saturating_sub(1);
        // Within the contact zone of the key pose (by the tool frame's distance from it, as
        // the validator measures the object's), the world of the key pose; beyond, the
        // world of the far end.
        let key = if reversed { path.last() } else { path.first() };
        let key_tcp = key.map(|q| self.tcp(arm, q).translation.vector);
        let collides = |_: usize, q: &[Real]| {
            let near = key_tcp.is_some_and(|k| {
                (self.tcp(arm, q).translation.vector - k).norm() <= self.run.options.contact_zone
            });
            self.collision(world_at(if near { 0 } else { n }, n), q, 0.0)
        };
        match self.dense_collision(arm, path, &|_| 1.0, &collides)? {
            Some(r) => Err(r.into()),
            None => Ok(()),
        }
    }

    /// [`Ctx::check_straight`] of a pick's straight motions as the plan uses them: the
    /// approach with the object lying at `at`, the lift with it held by grasp `gi` (touching
    /// `supports` within the contact zone).
    pub(super) fn check_pick(
        &self,
        arm: Arm,
        gi: usize,
        (at, supports): (&Isometry3, &[String]),
        approach: &[Vec<Real>],
        lift: &[Vec<Real>],
    ) -> Attempt<()> {
        let free = self.world_with_object_at(at);
        self.check_straight(arm, approach, &|_, _| &free, true)
            .map_err(|f| f.at(Step::Approach))?;
        let [holding, contact] =
            self.contact_worlds(arm, &self.run.grasps[gi].object_from_tcp, supports)?;
        self.check_straight(arm, lift, &self.near_support(&holding, &contact), false)
            .map_err(|f| f.at(Step::Lift))
    }

    /// [`Ctx::check_straight`] of a place's straight motions as the plan uses them: the
    /// lowering with the object held by grasp `gi` (touching `supports` within the contact
    /// zone of `at`), the retreat with it lying at `at`.
    pub(super) fn check_place(
        &self,
        arm: Arm,
        gi: usize,
        (at, supports): (&Isometry3, &[String]),
        lower: &[Vec<Real>],
        retreat: &[Vec<Real>],
    ) -> Attempt<()> {
        let [holding, contact] =
            self.contact_worlds(arm, &self.run.grasps[gi].object_from_tcp, supports)?;
        self.check_straight(arm, lower, &self.near_support(&holding, &contact), true)
            .map_err(|f| f.at(Step::Lower))?;
        let left = self.world_with_object_at(at);
        self.check_straight(arm, retreat, &|_, _| &left, false)
            .map_err(|f| f.at(Step::Retreat))
    }

    /// For a vertical motion of [`super::PlanOptions::lift_height`] away from a support in
    /// `n` steps: the world of step `i`, `contact` within the contact zone, `holding` above.
    pub(super) fn near_support<'w>(
        &self,
        holding: &'w CollisionWorld,
        contact: &'w CollisionWorld,
    ) -> impl Fn(usize, usize) -> &'w CollisionWorld + use<'w> {
        let zone = self.run.options.contact_zone;
        let height = self.run.options.lift_height;
        move |i, n| {
            if (i as Real / n as Real) * height <= zone {
                contact
            } else {
                holding
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::reason::{Fail, Rejection, Step};
    use super::super::tests::ctx;
    use super::*;

    /// The largest distance of the tool frame along `path` from the segment `a`–`b`.
    fn off_line(ctx: &Ctx<'_>, arm: Arm, path: &[Vec<Real>]) -> Real {
        let a = ctx.tcp(arm, &path[0]).translation.vector;
        let b = ctx.tcp(arm, path.last().unwrap()).translation.vector;
        let d = (b - a).normalize();
        path.iter()
            .map(|q| {
                let p = ctx.tcp(arm, q).translation.vector - a;
                (p - d * p.dot(&d)).norm()
            })
            .fold(0.0, Real::max)
    }

    #[test]
    fn fingers_are_clamped_to_their_limits_and_grip_below_the_width() {
        let ctx = ctx("fig9-near.toml");
        let setup = ctx.run.setup;
        let wide = ctx.with_fingers(Arm::Right, &setup.start, 10.0);
        for &v in &setup.arm(Arm::Right).finger_variables {
            assert_eq!(wide[v], setup.model.variable_joint(v).limits.upper);
        }
        // NX-HIRO's prismatic fingers each move half the opening; a grip squeezes.
        let g = &setup.arm(Arm::Right).gripper;
        let gripping = ctx.gripping(Arm::Right, &setup.start, 0.05);
        for &v in &setup.arm(Arm::Right).finger_variables {
            assert!(
                (gripping[v] - (0.05 - g.squeeze()) / 2.0).abs() < 1e-6,
                "{}",
                gripping[v]
            );
        }
        // The other arm's fingers and every arm joint are untouched.
        for &v in &setup.arm(Arm::Left).finger_variables {
            assert_eq!(wide[v], setup.start[v]);
        }
        for &v in &setup.arm(Arm::Right).variables {
            assert_eq!(wide[v], setup.start[v]);
        }
    }

    #[test]
    fn ik_reaches_the_tool_pose_it_was_given() {
        let ctx = ctx("fig9-near.toml");
        let setup = ctx.run.setup;
        let target = ctx.tcp(Arm::Right, &setup.start) * Translation3::new(0.02, 0.01, -0.03);
        let q = ctx
            .ik(Arm::Right, &target, &setup.start, 7)
            .expect("a nearby pose is reachable");
        let reached = ctx.tcp(Arm::Right, &q);
        assert!((reached.translation.vector - target.translation.vector).norm() < 1e-3);
    }

    #[test]
    fn the_best_reachable_pick_approaches_and_lifts_in_straight_lines() {
        let ctx = ctx("fig9-near.toml");

        let (gi, pick) = (0..ctx.run.grasps.len())
            .find_map(|gi| ctx.pick(Arm::Right, gi).ok().map(|p| (gi, p)))
            .expect("the right hand picks the near can");
        assert!(off_line(&ctx, Arm::Right, &pick.approach) < 1e-3);
        assert!(off_line(&ctx, Arm::Right, &pick.lift) < 1e-3);
        // The approach ends where the lift starts (fingers aside), at the grasp pose.
        let grasp = ctx.run.setup.object_start * ctx.run.grasps[gi].object_from_tcp;
        let at = ctx.tcp(Arm::Right, pick.approach.last().unwrap());
        assert!((at.translation.vector - grasp.translation.vector).norm() < 1e-3);
        let lifted = ctx.tcp(Arm::Right, pick.lift.last().unwrap());
        let rise = lifted.translation.vector.z - at.translation.vector.z;
        assert!((rise - ctx.run.options.lift_height).abs() < 1e-3, "{rise}");
    }

    #[test]
    fn a_grasp_far_from_the_shoulder_is_out_of_reach() {
        // In the far-left scene the can is beyond the right arm's reach.
        let ctx = ctx("fig9-far-left.toml");

        for gi in 0..ctx.run.grasps.len().min(8) {
            match ctx.pick(Arm::Right, gi) {
                Err(Fail::Rejected(r)) => assert_eq!(r, Rejection::OutOfReach),
                other => panic!("grasp {gi}: {other:?}"),
            }
        }
    }

    #[test]
    fn a_gripper_inside_the_table_is_named() {
        let ctx = ctx("fig9-near.toml");
        // The tool frame 5 cm above the table top, approaching upwards: the palm (behind the tool frame along the approach axis)
        // goes through the table top.
        let pose = Translation3::new(0.0, 0.0, 0.05) * ctx.run.setup.object_start;
        assert_eq!(
            ctx.hand_hits_environment(&pose, ctx.run.setup.gripper.opening_max),
            Some(Rejection::GripperHits("table".into()))
        );
        let above = Translation3::new(0.0, 0.0, 0.5) * ctx.run.setup.object_start;
        assert_eq!(ctx.hand_hits_environment(&above, 0.0), None);
    }

    #[test]
    fn rejections_of_a_pick_name_their_step() {
        let ctx = ctx("fig9-near.toml");

        // Every rejection of the left hand's picks is a known one, with a step where the
        // pick got past the reach and gripper tests.
        for gi in 0..ctx.run.grasps.len().min(24) {
            if let Err(Fail::Rejected(r)) = ctx.pick(Arm::Left, gi) {
                match &r {
                    Rejection::OutOfReach | Rejection::GripperHits(_) => {}
                    Rejection::At(step, _) => assert!(matches!(
                        step,
                        Step::Grasp | Step::Approach | Step::Lift | Step::GraspClosed
                    )),
                    other => panic!("unexpected {other}"),
                }
            }
        }
    }
}
