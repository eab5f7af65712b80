//! Motions between key poses (paper §III-C: "we plan collision free trajectories between
//! [the key poses] by using the PRM"): a lazy query on the arm's precomputed roadmap, checked
//! against this scene; RRT-Connect from both ends when a tight spot near the object keeps an
//! end off the roadmap; then seeded shortcutting. And the chains of motions and straight
//! segments that make up a single-arm or a handover plan.

use super::Ctx;
use super::assemble::Segment;
use super::handover::Handover;
use super::keypose::{Pick, Place};
use super::reason::{Attempt, End, Rejection, Step};
use crate::checker::ArmChecker;
use crate::plan::EventKind;
use crate::strategy::{Arm, Strategy};
use pickplace_base::rng::{Stream, salted};
use pickplace_geometry::math::Real;
use pickplace_prm::{PrmPlanner, QueryOptions, RrtOptions, ShortcutOptions, rrt_connect, shortcut};
use pickplace_robot::collision::CollisionWorld;
use std::sync::Arc;

/// Within this joint distance (rad, every joint) of a motion's ends the PRM applies no
/// clearance margin: the ends are grasp and release poses that may be close to the object.
pub(super) const END_EXEMPT_RADIUS: Real = 0.1;

/// True for the motion planner's "no path" outcomes (a fact about the scene); false for its
/// refusals of malformed input, which are defects of the façade.
fn is_search_failure(e: &pickplace_prm::Error) -> bool {
    use pickplace_prm::Error as E;
    matches!(
        e,
        E::StartInvalid
            | E::GoalInvalid
            | E::StartNotConnected { .. }
            | E::GoalNotConnected { .. }
            | E::NoPath { .. }
            | E::RrtExhausted { .. }
            | E::RrtOutOfTime { .. }
    )
}

impl Ctx<'_> {
    /// A collision-free motion of `arm` from `from` to `to` (full configurations that differ
    /// only in the arm's joints) in `world`, by the lazy PRM, shortcut.
    ///
    /// Rejected when an end collides ([`Rejection::EndInCollision`]) or no path is found
    /// ([`Rejection::NoPath`]); an error when the motion planner or the collision library
    /// refuses its input.
    pub(super) fn motion(
        &self,
        arm: Arm,
        world: &CollisionWorld,
        from: &[Real],
        to: &[Real],
        salt: u64,
    ) -> Attempt<Vec<Vec<Real>>> {
        let a = self.run.setup.arm(arm);
        let project = |q: &[Real]| -> Vec<Real> { a.variables.iter().map(|&v| q[v]).collect() };
        let (qa, qb) = (project(from), project(to));
        let checker = ArmChecker::new(
            &self.run.setup.model,
            world,
            &a.variables,
            from.to_vec(),
            self.run.options.motion_margin,
        )
        .exempt(vec![qa.clone(), qb.clone()], END_EXEMPT_RADIUS);
        for (end, q) in [(End::Start, from), (End::Goal, to)] {
            if let Some(c) = self.collision(world, q, 0.0)? {
                return Err(Rejection::EndInCollision(end, c).into());
            }
        }
        let internal = crate::error::internal("motion planning");
        let seed = salted(self.run.options.seed, Stream::Motion, salt);
        let mut planner = PrmPlanner::new(
            &a.roadmap,
            &checker,
            QueryOptions {
                seed,
                growth_rounds: 1,
                ..QueryOptions::default()
            },
        );
        // The roadmap first (paper §III-C); when its start or goal cannot join it (a tight
        // spot near the object), RRT-Connect from both ends, bounded.
        let path = match planner.query(&qa, &qb) {
            Ok(p) => p,
            Err(e) if !is_search_failure(&e) => return Err(internal(e).into()),
            Err(e) => match rrt_connect(
                &a.space,
                &checker,
                &qa,
                &qb,
                &RrtOptions {
                    max_iterations: 3000,
                    step: 0.3,
                    resolution: a.roadmap.options().resolution,
                    seed,
                    time_limit: None,
                },
            ) {
                Ok(p) => p,
                Err(r) if !is_search_failure(&r) => return Err(internal(r).into()),
                Err(r) => {
                    checker.check_error()?;
                    return Err(Rejection::NoPath {
                        roadmap: e.to_string(),
                        rrt: r.to_string(),
                    }
                    .into());
                }
            },
        };
        let path = shortcut(
            &a.space,
            &checker,
            &path,
            &ShortcutOptions {
                attempts: 40,
                resolution: 0.02,
                seed,
            },
        )
        .unwrap_or(path);
        checker.check_error()?;
        let path: Vec<Vec<Real>> = (0..path.len())
            .map(|i| checker.full(path.waypoint(i)))
            .collect();
        // The dense re-check: only the pairs the arm moves (the others are as at the ends,
        // which are checked), for contact.
        let contact = ArmChecker::new(
            &self.run.setup.model,
            world,
            &a.variables,
            from.to_vec(),
            0.0,
        )
        .moving_pairs_only();
        let collides = |_: usize, q: &[Real]| -> crate::Result<Option<super::reason::Collision>> {
            let arm_q: Vec<Real> = a.variables.iter().map(|&v| q[v]).collect();
            let hit = contact.first_collision(&arm_q);
            contact.check_error()?;
            Ok(hit.map(|(x, y)| super::reason::Collision {
                a: super::world::body_name(world, x),
                b: super::world::body_name(world, y),
            }))
        };
        // Twice the validator's density near the ends, where the motion planner applies no
        // clearance margin and the hand passes close to the object; the validator's
        // density elsewhere, where the margin keeps the robot away from everything.
        let near_end = |q: &[Real]| {
            [from, to].iter().any(|end| {
                a.variables
                    .iter()
                    .all(|&v| (q[v] - end[v]).abs() <= 2.0 * END_EXEMPT_RADIUS)
            })
        };
        let density = |q: &[Real]| if near_end(q) { 2.0 } else { 1.0 };
        if let Some(r) = self.dense_collision(arm, &path, &density, &collides)? {
            return Err(r.into());
        }
        Ok(path)
    }

    /// The arm's motion back to its start configuration after the retreat, or `None` when
    /// the start configuration itself now collides (the object was placed where the hand
    /// rests): the plan then ends at the retreat pose.
    fn back_to_start(
        &self,
        arm: Arm,
        world: &Arc<CollisionWorld>,
        from: &[Real],
        start: &[Real],
        salt: u64,
    ) -> Attempt<Option<Segment>> {
        let home = self.arm_from(arm, from, start);
        if self.collision(world, &home, 0.0)?.is_some() {
            return Ok(None);
        }
        let back = self
            .motion(arm, world, from, &home, salt)
            .map_err(|f| f.at(Step::Home))?;
        Ok(Some(Segment::free("home", arm, back, world)))
    }

    /// The segments of a single-arm plan with `arm`, placement `pi` and grasp `gi`: open the
    /// hand, then one [`Ctx::transfer`] from the start to the placement, and go back to the
    /// start.
    pub(super) fn single_arm_motions(
        &self,
        arm: Arm,
        pi: usize,
        gi: usize,
        start: &[Real],
        pick: &Pick,
        place: &Place,
    ) -> Attempt<Vec<Segment>> {
        let salt = (pi as u64) << 20 | (gi as u64) << 8 | arm.index() as u64;
        self.rest_chain(
            start,
            [Transfer {
                arm,
                gi,
                pick,
                place,
                from: self.at_start(),
                to: self.at_placement(pi),
                keys: DIRECT,
                salts: (salt ^ 1, salt ^ 2),
            }],
            (salt ^ 3, salt ^ 3),
        )
    }

    /// One transfer of the object by one arm and grasp, appended to `segments` from the full
    /// configuration `current`: the motion to the pre-grasp pose (the object lying at
    /// `from`), the straight approach, the fingers closing, the straight lift, the motion to
    /// the pre-place pose, the straight lowering to `to`, the fingers opening and the
    /// straight retreat. The key poses were computed with the other arm at rest; their
    /// waypoints take the other arm's joints from `current`. The straight motions are
    /// re-checked densely ([`Ctx::check_pick`], [`Ctx::check_place`]) before the motions are
    /// planned. Returns the configuration at the end of the retreat.
    fn transfer(
        &self,
        segments: &mut Vec<Segment>,
        t: Transfer<'_>,
        current: &[Real],
    ) -> Attempt<Vec<Real>> {
        let (arm, g) = (t.arm, &self.run.grasps[t.gi]);
        let [pre_grasp, grasp, lift, pre_place, place, release, retreat] = t.keys.names;
        let graft = |q: &Vec<Real>, base: &[Real]| self.other_from(arm, base, q);
        let here = |seg: &[Vec<Real>]| super::end_of(seg).cloned();
        let approach: Vec<Vec<Real>> = t.pick.approach.iter().map(|q| graft(q, current)).collect();
        let q_grasp = here(&approach)?;
        let closed = self.gripping(arm, &q_grasp, g.width);
        let lifted: Vec<Vec<Real>> = t.pick.lift.iter().map(|q| graft(q, &closed)).collect();
        self.check_pick(arm, t.gi, t.from, &approach, &lifted)?;
        let lower: Vec<Vec<Real>> = t.place.lower.iter().map(|q| graft(q, &closed)).collect();
        let q_place = here(&lower)?;
        let opened = self.opened(arm, &q_place);
        let away: Vec<Vec<Real>> = t.place.retreat.iter().map(|q| graft(q, &opened)).collect();
        self.check_place(arm, t.gi, t.to, &lower, &away)?;
        let free = Arc::new(self.world_with_object_at(t.from.0));
        let to_pre = self
            .motion(arm, &free, current, &approach[0], t.salts.0)
            .map_err(|f| f.at(t.keys.to_pick))?;
        segments.push(Segment::free(pre_grasp, arm, to_pre, &free));
        segments.push(Segment::reach(grasp, arm, approach));
        segments.push(Segment::event(
            vec![q_grasp, closed],
            None,
            (EventKind::Grasp, arm, g.object_from_tcp.inverse()),
        ));
        let holding = Arc::new(self.world_holding(arm, &g.object_from_tcp, &[])?);
        let carry = self
            .motion(arm, &holding, &here(&lifted)?, &lower[0], t.salts.1)
            .map_err(|f| f.at(t.keys.to_place))?;
        segments.push(Segment::reach(lift, arm, lifted));
        segments.push(Segment::free(pre_place, arm, carry, &holding));
        segments.push(Segment::reach(place, arm, lower));
        segments.push(Segment::event(
            vec![q_place, opened],
            Some((release, arm)),
            (EventKind::Release, arm, g.object_from_tcp.inverse()),
        ));
        let end = here(&away)?;
        segments.push(Segment::reach(retreat, arm, away));
        Ok(end)
    }

    /// The segments of a handover plan (§III-B.3) at placement `pi`: arm A picks and carries
    /// the object to the handover pose, arm B comes, approaches and closes, A opens, retreats
    /// and goes home, B carries the object to the placement, lowers, releases, retreats and
    /// goes home.
    pub(super) fn handover_motions(
        &self,
        strategy: Strategy,
        pi: usize,
        start: &[Real],
        pick: &Pick,
        place: &Place,
        h: &Handover,
    ) -> Attempt<Vec<Segment>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let (g1, g2) = (&self.run.grasps[h.g1], &self.run.grasps[h.g2]);
        let salt = (pi as u64) << 20 | (h.g1 as u64) << 8 | (h.g2 as u64) << 32;
        let mut segments = Vec::new();
        // Both hands open at the start.
        let open_start = self.opened(b, &self.opened(a, start));
        if open_start != start {
            segments.push(Segment::plain(vec![start.to_vec(), open_start.clone()]));
        }
        let free = Arc::new(self.world_with_object_at(&self.run.setup.object_start));
        let to_pre = self
            .motion(
                a,
                &free,
                &open_start,
                &self.other_from(b, &pick.approach[0], &open_start),
                salt ^ 1,
            )
            .map_err(|f| f.at(Step::ToPreGrasp))?;
        let here = |seg: &[Vec<Real>]| super::end_of(seg).cloned();
        segments.push(Segment::free("pre-grasp", a, to_pre, &free));
        let approach: Vec<Vec<Real>> = pick
            .approach
            .iter()
            .map(|q| self.other_from(b, q, &open_start))
            .collect();
        segments.push(Segment::reach("grasp", a, approach.clone()));
        let q = here(&approach)?;
        let closed = self.gripping(a, &q, g1.width);
        segments.push(Segment::event(
            vec![q, closed],
            None,
            (EventKind::Grasp, a, g1.object_from_tcp.inverse()),
        ));
        let lift: Vec<Vec<Real>> = pick
            .lift
            .iter()
            .map(|q| self.other_from(b, q, &open_start))
            .collect();
        segments.push(Segment::reach("lift", a, lift.clone()));
        let start_rest = (
            &self.run.setup.object_start,
            self.run.start_supports.as_slice(),
        );
        self.check_pick(a, h.g1, start_rest, &approach, &lift)?;
        // A carries the object to the handover pose.
        let holding_a = Arc::new(self.world_holding(a, &g1.object_from_tcp, &[])?);
        let q_handover = self.arm_from(a, &here(&lift)?, &h.q_a);
        let carry = self
            .motion(a, &holding_a, &here(&lift)?, &q_handover, salt ^ 2)
            .map_err(|f| f.at(Step::ToHandover))?;
        segments.push(Segment::free("handover", a, carry, &holding_a));
        // B comes to the pre-regrasp pose, then approaches.
        let q_pre_b = self.arm_from(b, &q_handover, &h.approach[0]);
        let to_b = self
            .motion(b, &holding_a, &q_handover, &q_pre_b, salt ^ 3)
            .map_err(|f| f.at(Step::ToPreRegrasp))?;
        segments.push(Segment::free("pre-regrasp", b, to_b, &holding_a));
        let b_approach: Vec<Vec<Real>> = h
            .approach
            .iter()
            .map(|qb| self.arm_from(b, &q_pre_b, qb))
            .collect();
        self.check_straight(b, &b_approach, &|_, _| &*holding_a, true)
            .map_err(|f| f.at(Step::RegraspApproach))?;
        segments.push(Segment::reach("regrasp", b, b_approach.clone()));
        let q = here(&b_approach)?;
        let b_closed = self.gripping(b, &q, g2.width);
        segments.push(Segment::event(
            vec![q, b_closed.clone()],
            None,
            (EventKind::Grasp, b, g2.object_from_tcp.inverse()),
        ));
        let a_open = self.opened(a, &b_closed);
        segments.push(Segment::event(
            vec![b_closed, a_open.clone()],
            Some(("release-first", a)),
            (EventKind::Release, a, g1.object_from_tcp.inverse()),
        ));
        let a_retreat: Vec<Vec<Real>> = h
            .retreat
            .iter()
            .map(|qa| self.arm_from(a, &a_open, qa))
            .collect();
        let holding_b = Arc::new(self.world_holding(b, &g2.object_from_tcp, &[])?);
        self.check_straight(a, &a_retreat, &|_, _| &*holding_b, false)
            .map_err(|f| f.at(Step::FirstHandRetreat))?;
        segments.push(Segment::reach("retreat-first", a, a_retreat.clone()));
        // A goes back to its start while B holds.
        let a_home = self.arm_from(a, &here(&a_retreat)?, start);
        let back_a = self
            .motion(a, &holding_b, &here(&a_retreat)?, &a_home, salt ^ 4)
            .map_err(|f| f.at(Step::FirstArmHome))?;
        segments.push(Segment::free("home-first", a, back_a, &holding_b));
        // B carries the object to the pre-place pose.
        let lower: Vec<Vec<Real>> = place
            .lower
            .iter()
            .map(|qb| self.arm_from(b, &a_home, qb))
            .collect();
        let to_place = self
            .motion(b, &holding_b, &a_home, &lower[0], salt ^ 5)
            .map_err(|f| f.at(Step::ToPrePlace))?;
        segments.push(Segment::free("pre-place", b, to_place, &holding_b));
        segments.push(Segment::reach("place", b, lower.clone()));
        let q = here(&lower)?;
        let opened = self.opened(b, &q);
        segments.push(Segment::event(
            vec![q, opened.clone()],
            Some(("release", b)),
            (EventKind::Release, b, g2.object_from_tcp.inverse()),
        ));
        let retreat: Vec<Vec<Real>> = place
            .retreat
            .iter()
            .map(|qb| self.arm_from(b, &opened, qb))
            .collect();
        self.check_place(b, h.g2, self.at_placement(pi), &lower, &retreat)?;
        segments.push(Segment::reach("retreat", b, retreat.clone()));
        let left = Arc::new(self.world_with_object_at(&self.run.placements[pi].world_from_object));
        if let Some(back) = self.back_to_start(b, &left, &here(&retreat)?, start, salt ^ 6)? {
            segments.push(back);
        }
        Ok(segments)
    }

    /// The segments of a regrasp by placing ([`super::regrasp`]): arm A opens, picks the
    /// object at its start, carries it to the rest, puts it down, releases and retreats (and,
    /// when B is the other arm, goes back to its start); arm B comes to the rest, picks the
    /// object up with its grasp, carries it to the placement, lowers, releases, retreats and
    /// goes home. Arm B's key poses were computed from the start configuration; its
    /// waypoints take the other arm's joints from where that arm is.
    pub(super) fn regrasp_motions(
        &self,
        start: &[Real],
        legs: &super::regrasp::RegraspLegs<'_>,
    ) -> Attempt<Vec<Segment>> {
        let (a, b) = (legs.strategy.pick_arm(), legs.strategy.place_arm());
        let at_rest = self.at_rest(legs.k);
        let salt = (legs.pi as u64) << 20
            | (legs.g1 as u64) << 8
            | (legs.g2 as u64) << 32
            | (legs.k as u64) << 48;
        self.rest_chain(
            start,
            [
                Transfer {
                    arm: a,
                    gi: legs.g1,
                    pick: legs.pick,
                    place: legs.down,
                    from: self.at_start(),
                    to: at_rest,
                    keys: PUT_DOWN,
                    salts: (salt ^ 1, salt ^ 2),
                },
                Transfer {
                    arm: b,
                    gi: legs.g2,
                    pick: legs.up,
                    place: legs.place,
                    from: at_rest,
                    to: self.at_placement(legs.pi),
                    keys: PICK_UP,
                    salts: (salt ^ 4, salt ^ 5),
                },
            ],
            (salt ^ 3, salt ^ 6),
        )
    }

    /// The object at its start, and the bodies it rests on there.
    fn at_start(&self) -> Rest<'_> {
        (&self.run.setup.object_start, &self.run.start_supports)
    }

    /// The object at intermediate rest `k`, and the bodies it rests on there.
    fn at_rest(&self, k: usize) -> Rest<'_> {
        (&self.rests()[k].world_from_object, self.rest_supports(k))
    }

    /// The object at placement `pi`, and the bodies it rests on there.
    fn at_placement(&self, pi: usize) -> Rest<'_> {
        (
            &self.run.placements[pi].world_from_object,
            self.placement_supports(pi),
        )
    }

    /// The segments of a chain of transfers (one for a single-arm plan, more through
    /// intermediate rests): both hands open, the first transfer by arm A (which goes home when
    /// the next transfer is by the other arm), the next ones in turn, and the last arm home. `home_salts` seed A's and the last arm's
    /// motions home.
    fn rest_chain<const N: usize>(
        &self,
        start: &[Real],
        transfers: [Transfer<'_>; N],
        home_salts: (u64, u64),
    ) -> Attempt<Vec<Segment>> {
        let mut segments = Vec::new();
        let arms: Vec<Arm> = transfers.iter().map(|t| t.arm).collect();
        let mut open_start = start.to_vec();
        for &arm in &arms {
            open_start = self.opened(arm, &open_start);
        }
        if open_start != start {
            segments.push(Segment::plain(vec![start.to_vec(), open_start.clone()]));
        }
        let mut current = open_start;
        let mut last = None;
        for (i, t) in transfers.into_iter().enumerate() {
            let (arm, to) = (t.arm, *t.to.0);
            current = self.transfer(&mut segments, t, &current)?;
            // The first arm goes home before the other takes over.
            if i == 0
                && arms.get(1).is_some_and(|&next| next != arm)
                && let Some(back) = self.back_to_start(
                    arm,
                    &Arc::new(self.world_with_object_at(&to)),
                    &current,
                    start,
                    home_salts.0,
                )?
            {
                current = super::end_of(&back.path)?.clone();
                segments.push(Segment {
                    key: Some(("home-first", arm)),
                    ..back
                });
            }
            last = Some((arm, to));
        }
        if let Some((arm, placed)) = last {
            let left = Arc::new(self.world_with_object_at(&placed));
            if let Some(back) = self.back_to_start(arm, &left, &current, start, home_salts.1)? {
                segments.push(back);
            }
        }
        Ok(segments)
    }
}

impl Ctx<'_> {
    /// The segments of a regrasp through two rests: arm A carries the object from the start
    /// to rest k₁ (and goes home when B is the other arm), B carries it from k₁ to rest k₂,
    /// then from k₂ to the placement, and goes home.
    pub(super) fn two_rest_motions(
        &self,
        start: &[Real],
        legs: &super::regrasp::TwoRestLegs<'_>,
    ) -> Attempt<Vec<Segment>> {
        let (a, b) = (legs.strategy.pick_arm(), legs.strategy.place_arm());
        let (k1, k2) = legs.rests;
        let (g1, g2, g3) = legs.grasps;
        let (at1, at2) = (self.at_rest(k1), self.at_rest(k2));
        let salt = 1 << 62
            | (legs.pi as u64) << 20
            | (g1 as u64) << 8
            | (g2 as u64) << 28
            | (g3 as u64) << 40
            | (k1 as u64) << 50
            | (k2 as u64) << 56;
        self.rest_chain(
            start,
            [
                Transfer {
                    arm: a,
                    gi: g1,
                    pick: legs.pick,
                    place: legs.down,
                    from: self.at_start(),
                    to: at1,
                    keys: PUT_DOWN,
                    salts: (salt ^ 1, salt ^ 2),
                },
                Transfer {
                    arm: b,
                    gi: g2,
                    pick: legs.up,
                    place: legs.moved,
                    from: at1,
                    to: at2,
                    keys: MOVE,
                    salts: (salt ^ 4, salt ^ 5),
                },
                Transfer {
                    arm: b,
                    gi: g3,
                    pick: legs.up_again,
                    place: legs.place,
                    from: at2,
                    to: self.at_placement(legs.pi),
                    keys: PICK_UP,
                    salts: (salt ^ 6, salt ^ 7),
                },
            ],
            (salt ^ 3, salt ^ 8),
        )
    }
}

/// Where the object rests before or after a transfer, and the bodies it rests on.
type Rest<'r> = (&'r pickplace_geometry::math::Isometry3, &'r [String]);

/// One transfer of [`Ctx::transfer`]: the arm, its grasp (index into the ranked grasps),
/// the checked pick and place, where the object rests before and after, the key pose names,
/// and the salts of its two motions.
struct Transfer<'t> {
    arm: Arm,
    gi: usize,
    pick: &'t Pick,
    place: &'t Place,
    from: Rest<'t>,
    to: Rest<'t>,
    keys: TransferKeys,
    salts: (u64, u64),
}

/// The names of a transfer's key poses (pre-grasp, grasp, lift, pre-place, place, release,
/// retreat) and the steps its two motions are rejected at.
#[derive(Clone, Copy)]
struct TransferKeys {
    names: [&'static str; 7],
    to_pick: Step,
    to_place: Step,
}

/// A pick at the start and a place at the target.
const DIRECT: TransferKeys = TransferKeys {
    names: [
        "pre-grasp",
        "grasp",
        "lift",
        "pre-place",
        "place",
        "release",
        "retreat",
    ],
    to_pick: Step::ToPreGrasp,
    to_place: Step::ToPrePlace,
};

/// A pick at the start and a put-down at an intermediate rest.
const PUT_DOWN: TransferKeys = TransferKeys {
    names: [
        "pre-grasp",
        "grasp",
        "lift",
        "pre-rest",
        "rest",
        "release-rest",
        "retreat-rest",
    ],
    to_pick: Step::ToPreGrasp,
    to_place: Step::ToRest,
};

/// A pick-up at one intermediate rest and a put-down at the next.
const MOVE: TransferKeys = TransferKeys {
    names: [
        "pre-regrasp",
        "regrasp",
        "lift-again",
        "pre-rest",
        "rest",
        "release-rest",
        "retreat-rest",
    ],
    to_pick: Step::ToPreRegrasp,
    to_place: Step::ToRest,
};

/// A pick-up at an intermediate rest and a place at the target.
const PICK_UP: TransferKeys = TransferKeys {
    names: [
        "pre-regrasp",
        "regrasp",
        "lift-again",
        "pre-place",
        "place",
        "release",
        "retreat",
    ],
    to_pick: Step::ToPreRegrasp,
    to_place: Step::ToPrePlace,
};

#[cfg(test)]
mod tests {
    use super::super::reason::{Fail, Rejection};
    use super::super::tests::ctx;
    use super::*;

    #[test]
    fn a_motion_joins_its_ends_and_every_waypoint_is_free() {
        let ctx = ctx("fig9-near.toml");
        let setup = ctx.run.setup;
        let world = ctx.world_with_object_at(&setup.object_start);
        let arm = setup.arm(Arm::Right);
        // A goal away from the start: the arm's first node of the roadmap that is free here.
        let goal = (0..arm.roadmap.node_count())
            .map(|i| {
                let mut q = setup.start.clone();
                for (c, &v) in arm.variables.iter().enumerate() {
                    q[v] = arm.roadmap.state(i)[c];
                }
                q
            })
            .find(|q| ctx.collision(&world, q, 0.02).expect("checks").is_none())
            .expect("a free roadmap node");
        let path = ctx
            .motion(Arm::Right, &world, &setup.start, &goal, 5)
            .expect("the PRM joins two free states");
        assert_eq!(path.first(), Some(&setup.start));
        assert_eq!(path.last(), Some(&goal));
        for q in &path {
            assert_eq!(ctx.collision(&world, q, 0.0).expect("checks"), None);
            // Only the right arm moves.
            for (v, (x, s)) in q.iter().zip(&setup.start).enumerate() {
                if !arm.variables.contains(&v) {
                    assert_eq!(x, s);
                }
            }
        }
        // Same seed, same path.
        assert_eq!(
            ctx.motion(Arm::Right, &world, &setup.start, &goal, 5).ok(),
            Some(path)
        );
    }

    #[test]
    fn a_start_in_collision_is_rejected_with_the_bodies() {
        let ctx = ctx("fig9-near.toml");
        let setup = ctx.run.setup;
        // The object lying on the right wrist at the start configuration.
        let wrist = ctx.tcp(Arm::Right, &setup.start)
            * pickplace_geometry::math::Translation3::new(0.0, 0.0, -0.12);
        let world = ctx.world_with_object_at(&wrist);
        let other = setup.start.clone();
        match ctx.motion(Arm::Right, &world, &other, &setup.start, 1) {
            Err(Fail::Rejected(Rejection::EndInCollision(End::Start, c))) => {
                assert!(c.a == "object" || c.b == "object", "{c}");
            }
            other => panic!("{other:?}"),
        }
    }
}
