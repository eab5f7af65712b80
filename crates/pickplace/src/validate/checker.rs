//! The state checker: the world at each checked state (what may touch what), the grip, the
//! resting poses and the target.

use super::*;

/// When each hand may touch the object besides holding it: from the start of its closing
/// motion (the arm at rest before the grasp event) to the grasp, and from a release to the end
/// of its opening (the arm at rest after it): `(arm, from, to)`. One window per event, of
/// whichever hand and in whatever sequence (a direct plan, the second hand at a handover, a
/// regrasp after a rest); the fingers' own joints are not part of the arm, so they may move
/// in the window.
pub(super) fn closing_windows(
    setup: &Setup,
    traj: &[TrajectoryPoint],
    events: &[Ev],
) -> Vec<(Arm, Real, Real)> {
    let at_rest = |arm: Arm, i: usize, k: usize| {
        setup
            .arm(arm)
            .variables
            .iter()
            .all(|&v| (traj[i].positions[v] - traj[k].positions[v]).abs() <= 1e-9)
    };
    let mut windows = Vec::new();
    for e in events {
        // The sample at (or just before) the event.
        let i = traj
            .partition_point(|p| p.time_from_start <= e.time + 1e-9)
            .saturating_sub(1);
        match e.kind {
            EventKind::Grasp => {
                let mut k = i;
                while k > 0 && at_rest(e.arm, i, k - 1) {
                    k -= 1;
                }
                windows.push((e.arm, traj[k].time_from_start, e.time));
            }
            EventKind::Release => {
                let mut k = i;
                while k + 1 < traj.len() && at_rest(e.arm, i, k + 1) {
                    k += 1;
                }
                windows.push((e.arm, e.time, traj[k].time_from_start));
            }
        }
    }
    windows
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub(super) enum WorldKey {
    /// The object lies free at rest `usize`; the right and left hand closing on it or opening
    /// from it (their fingers may touch it).
    Free(usize, bool, bool),
    /// Held (by one or two arms) in the holding state `usize` (the number of grasps and
    /// releases before it); `Option<usize>`: the rest it is near (it may touch that rest's
    /// supports); the last two: the right and left hand closing or opening.
    Held(usize, Option<usize>, bool, bool),
}

pub(super) struct Validator<'a> {
    pub(super) setup: &'a Setup,
    /// The object for the fingers' gaps.
    pub(super) grip_object: GripObject,
    /// Arms whose grip problem is reported already (once per hold).
    pub(super) grip_reported: Vec<Arm>,
    /// The pads' gaps by their pose relative to the object.
    pub(super) grip_memo: grip::GripMemo,
    pub(super) problems: Vec<String>,
    /// The state problems (collisions, clearance; by rule and bodies) of the previous checked
    /// state: a problem that lasts is reported once, when it starts.
    pub(super) ongoing: Vec<String>,
    pub(super) worlds: BTreeMap<WorldKey, CollisionWorld>,
    /// The two hands' clearance (two-armed robots).
    pub(super) hands: Option<HandClearance>,
    pub(super) scratch: CollisionScratch,
    /// The environment's parts, for the supports of a pose and the target's surface.
    pub(super) parts: parts::Parts<'a>,
    /// The start (index 0) and every pose where a release leaves the object.
    pub(super) rests: Vec<Rest>,
    pub(super) states: usize,
}

impl<'a> Validator<'a> {
    pub(super) fn new(setup: &'a Setup) -> Result<Self> {
        let grip_object = setup.grip_object()?.clone();
        let mut v = Self {
            setup,
            grip_object,
            grip_reported: Vec::new(),
            grip_memo: grip::GripMemo::default(),
            problems: Vec::new(),
            ongoing: Vec::new(),
            worlds: BTreeMap::new(),
            hands: HandClearance::new(setup)?,
            scratch: CollisionScratch::default(),
            parts: parts::Parts::new(setup),
            rests: Vec::new(),
            states: 0,
        };
        let supports = v.supports(&setup.object_start)?;
        v.rests = vec![Rest {
            pose: setup.object_start,
            supports,
        }];
        Ok(v)
    }

    pub(super) fn problem(&mut self, t: Real, what: String) {
        self.problems
            .push(format!("t = {} s: {what}", short_time(t)));
    }

    /// Environment parts within [`SUPPORT_DISTANCE`] of the object at `world_from_object`,
    /// in scene order (the rule of [`crate::contact::supports`], on meshes built once, and
    /// only for the parts whose box is within reach: `parts::Parts::touching`).
    ///
    /// # Errors
    /// [`Error::Internal`] when a part's mesh cannot be prepared.
    pub(super) fn supports(&mut self, world_from_object: &Isometry3) -> Result<Vec<String>> {
        let object = &self.setup.placement_object.collision;
        self.parts
            .touching(object, world_from_object, SUPPORT_DISTANCE)
    }

    /// The resting poses: the start, then where each release that leaves no hand holding
    /// the object leaves it (computed from the samples at the events, before the dense
    /// pass, so that the approach to a rest may already touch its support).
    pub(super) fn rest_poses(&mut self, plan: &Plan, events: &[Ev]) -> Result<Vec<Rest>> {
        let mut rests = self.rests.clone();
        let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
        let mut object = self.setup.object_start;
        for e in events {
            let i = plan
                .trajectory
                .partition_point(|p| p.time_from_start <= e.time + 1e-9);
            let Some(p) = plan.trajectory.get(i.saturating_sub(1)) else {
                return Err(Error::Internal {
                    stage: "validator: resting poses",
                    reason: "an event before the empty trajectory".into(),
                });
            };
            if let Some(&(arm, l)) = holders.first() {
                object = self.tcp(arm, &p.positions) * l;
            }
            match e.kind {
                EventKind::Grasp => {
                    holders.retain(|(h, _)| *h != e.arm);
                    holders.push((e.arm, e.link_from_object));
                }
                EventKind::Release => {
                    let held = !holders.is_empty();
                    holders.retain(|(h, _)| *h != e.arm);
                    if held && holders.is_empty() {
                        rests.push(Rest {
                            pose: object,
                            supports: self.supports(&object)?,
                        });
                    }
                }
            }
        }
        // A plan that ends with the object held ends with it at its final pose all the same
        // (reported as still held; its support there is not a collision too).
        if let (Some(&(arm, l)), Some(p)) = (holders.first(), plan.trajectory.last()) {
            let pose = self.tcp(arm, &p.positions) * l;
            rests.push(Rest {
                pose,
                supports: self.supports(&pose)?,
            });
        }
        Ok(rests)
    }

    /// The grip (issue: fingers that never close): while an arm holds the object, its
    /// finger pads press into it no deeper than the gripper's squeeze (and
    /// [`GRIP_TOLERANCE`]), and, while the object moves (`moved`), both touch it, no more
    /// than [`GRIP_GAP`] away. Reported once per hold.
    ///
    /// # Errors
    /// [`Error::Internal`] when the collision library cannot measure a finger.
    pub(super) fn check_grip(
        &mut self,
        t: Real,
        q: &[Real],
        holders: &[(Arm, Isometry3)],
        object: &Isometry3,
        moved: bool,
    ) -> Result<()> {
        if holders.iter().all(|(a, _)| self.grip_reported.contains(a)) {
            return Ok(());
        }
        let setup = self.setup;
        let poses: Vec<Isometry3> = setup
            .model
            .link_poses(q)
            .map_err(internal("grip check"))?
            .into_iter()
            .map(|p| setup.world_from_root * p)
            .collect();
        for &(arm, _) in holders {
            if self.grip_reported.contains(&arm) {
                continue;
            }
            let gripper = &setup.arm(arm).gripper;
            let gaps = self
                .grip_memo
                .gaps(arm, gripper, &poses, &self.grip_object, object)?;
            for (pad, &gap) in gaps.iter().enumerate() {
                let problem = if moved && gap > GRIP_GAP {
                    Some(format!(
                        "the {arm} hand holds the object but its finger pad {} is {:.1} mm from it (at most {:.0} mm): the grip does not close",
                        pad + 1,
                        gap * 1e3,
                        GRIP_GAP * 1e3
                    ))
                } else if -gap > gripper.squeeze() + GRIP_TOLERANCE {
                    Some(format!(
                        "the {arm} hand's finger pad {} is {:.1} mm inside the object (the squeeze is {:.1} mm)",
                        pad + 1,
                        -gap * 1e3,
                        gripper.squeeze() * 1e3
                    ))
                } else {
                    None
                };
                if let Some(p) = problem {
                    self.problem(t, p);
                    self.grip_reported.push(arm);
                    break;
                }
            }
        }
        Ok(())
    }

    pub(super) fn tcp(&self, arm: Arm, q: &[Real]) -> Isometry3 {
        self.setup.world_from_root * self.setup.arm(arm).ik.chain().pose(q)
    }

    /// The resting pose the object is near (within [`CONTACT_ZONE`] and its [`CONTACT_ZONE_SLACK`], and 3°), if any: the
    /// latest in time order when several are.
    pub(super) fn near(&self, object: &Isometry3) -> Option<usize> {
        self.rests.iter().rposition(|r| {
            (object.translation.vector - r.pose.translation.vector).norm()
                <= CONTACT_ZONE + CONTACT_ZONE_SLACK
                && object.rotation.angle_to(&r.pose.rotation) <= 3f64.to_radians()
        })
    }

    /// The collision world of `key`, built once.
    ///
    /// # Errors
    /// [`Error::Internal`] when the object cannot be attached to a holding link.
    pub(super) fn world(
        &mut self,
        key: WorldKey,
        holders: &[(Arm, Isometry3)],
        object: &Isometry3,
    ) -> Result<()> {
        if self.worlds.contains_key(&key) {
            return Ok(());
        }
        let setup = self.setup;
        let mut w = setup.world.clone();
        let mut acm = w.acm().clone();
        let closing = match key {
            WorldKey::Free(_, right, left) | WorldKey::Held(_, _, right, left) => {
                [(Arm::Right, right), (Arm::Left, left)]
            }
        };
        match key {
            WorldKey::Free(..) => {
                // The free object is an obstacle where it lies; a hand closing on it or
                // opening from it may touch it.
                for (a, on) in closing {
                    if on && setup.has_arm(a) {
                        for link in &setup.arm(a).pad_links {
                            acm.allow(
                                OBJECT_NAME,
                                link,
                                DisableReason::Custom("closing on the object".into()),
                            );
                        }
                    }
                }
                w.set_acm(acm);
                w.add_environment(OBJECT_NAME, setup.object_shape.clone(), object);
            }
            WorldKey::Held(_, near, _, _) => {
                if let Some(r) = near.and_then(|r| self.rests.get(r)) {
                    for s in &r.supports {
                        acm.allow(
                            OBJECT_NAME,
                            s,
                            DisableReason::Custom("resting contact".into()),
                        );
                    }
                }
                w.set_acm(acm);
                if let Some(&(arm, link_from_object)) = holders.first() {
                    let mut touch: Vec<&str> = Vec::new();
                    // Only the pads may touch it (their depth is the grip check's); every
                    // other link of the hands is checked against it like any other body.
                    for (h, _) in holders {
                        touch.extend(setup.arm(*h).pad_links.iter().map(String::as_str));
                    }
                    for (a, on) in closing {
                        if on && setup.has_arm(a) {
                            touch.extend(setup.arm(a).pad_links.iter().map(String::as_str));
                        }
                    }
                    w.attach(
                        OBJECT_NAME,
                        &setup.arm(arm).tcp_name,
                        setup.object_shape.clone(),
                        &link_from_object,
                        &touch,
                    )
                    .map_err(internal("validator: attaching the held object"))?;
                }
            }
        }
        self.worlds.insert(key, w);
        Ok(())
    }

    /// Collisions and the hands' clearance at one state; a problem that lasts over
    /// consecutive states is reported once, when it starts.
    ///
    /// # Errors
    /// [`Error::Internal`] when a collision query fails.
    pub(super) fn check_state(
        &mut self,
        t: Real,
        q: &[Real],
        (holders, holding): (&[(Arm, Isometry3)], usize),
        object: &Isometry3,
        closing: [bool; 2],
    ) -> Result<()> {
        self.states += 1;
        let [right, left] = closing;
        let near = self.near(object);
        let key = if holders.is_empty() {
            match near {
                Some(r) => WorldKey::Free(r, right, left),
                None => {
                    // Left where no rest was foreseen (an event between samples): a world
                    // of its own, never reused.
                    let key = WorldKey::Free(usize::MAX, right, left);
                    self.worlds.remove(&key);
                    key
                }
            }
        } else {
            WorldKey::Held(holding, near, right, left)
        };
        self.world(key, holders, object)?;
        let model = &self.setup.model;
        let mut now = Vec::new();
        if let Some(w) = self.worlds.get(&key) {
            let pairs = w
                .colliding_pairs(model, q, &mut self.scratch, &CheckOptions::default())
                .map_err(internal("validator: collision check"))?;
            if let Some(&(a, b)) = pairs.first() {
                let name = |x: BodyId| match x {
                    BodyId::Attached(_) => "held object".to_owned(),
                    _ => w.body_name(x).to_owned(),
                };
                let m = format!("collision {} / {}", name(a), name(b));
                now.push((m.clone(), m));
            }
        } else {
            return Err(Error::Internal {
                stage: "validator: collision check",
                reason: format!("no collision world for {key:?}"),
            });
        }
        if let Some(h) = &self.hands {
            let margin = HAND_CLEARANCE - HAND_CLEARANCE_SLACK;
            if let Some(gap) = h.closer_than(self.setup, q, margin, &mut self.scratch)? {
                now.push((
                    format!("hands {} / {}", gap.right, gap.left),
                    format!(
                        "the hands' links {} and {} are {:.1} mm apart (hand clearance {:.0} mm)",
                        gap.right,
                        gap.left,
                        gap.distance * 1e3,
                        HAND_CLEARANCE * 1e3
                    ),
                ));
            }
        }
        for (key, p) in &now {
            if !self.ongoing.contains(key) {
                self.problems.push(format!("t = {} s: {p}", short_time(t)));
            }
        }
        self.ongoing = now.into_iter().map(|(key, _)| key).collect();
        Ok(())
    }

    /// A resting pose (after a release that leaves no hand holding the object, and the final
    /// pose): not penetrating the environment, on a support (at least three contact points
    /// spanning an area) and statically stable on it (paper Fig. 7). Returns the stability
    /// margin when it rests on a support.
    pub(super) fn rest_check(&mut self, t: Real, object: &Isometry3, what: &str) -> Option<Real> {
        let setup = self.setup;
        let env = &setup.placement_env.collision;
        let obj = &setup.placement_object.collision;
        if env.intersects(obj, object, &Vector3::new(0.0, 0.0, PENETRATION_LIFT)) {
            self.problem(t, format!("{what} penetrates the environment"));
        }
        let points = env.touching_points(obj, object, REST_CONTACT_REACH);
        let ring: Vec<Point2> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
        let support = SupportHull::of_points(&ring);
        let cog = object * setup.cog;
        if !support.has_area() {
            self.problem(
                t,
                format!("{what} does not rest on a support (fewer than 3 contacts): it would fall"),
            );
            return None;
        }
        let margin = support.cog_margin(&Point2::new(cog.x, cog.y));
        if margin <= 0.0 {
            self.problem(
                t,
                format!(
                    "{what} is unstable: the CoG's vertical is {:.1} mm outside its support",
                    -margin * 1e3
                ),
            );
        }
        Some(margin)
    }

    /// The target (paper §III-B.2, the user's click): the vertical through the placed
    /// object's centre of mass passes within the scene's `target.tolerance` of the target
    /// point, and the object rests on the environment part whose surface holds the point
    /// (the part nearest to it).
    ///
    /// # Errors
    /// [`Error::Internal`] when the scene has no environment (the setup refuses that).
    pub(super) fn target_check(&mut self, t: Real, object: &Isometry3) -> Result<()> {
        let scene = &self.setup.scene;
        let target = scene.target_point();
        let tolerance = scene.target.tolerance();
        let cog = object * self.setup.cog;
        let d = (cog.x - target.x).hypot(cog.y - target.y);
        if d > tolerance {
            self.problem(
                t,
                format!(
                    "the placed object is {:.1} mm from the target point (tolerance {:.1} mm)",
                    d * 1e3,
                    tolerance * 1e3
                ),
            );
        }
        let surface = self
            .parts
            .nearest(&target)?
            .ok_or_else(|| Error::Internal {
                stage: "validator: target",
                reason: "the scene has no environment".into(),
            })?;
        let touched = self.supports(object)?;
        if !touched.contains(&surface) {
            self.problem(
                t,
                format!(
                    "the placed object does not rest on {surface:?}, the surface of the target point (it touches: {})",
                    if touched.is_empty() {
                        "nothing".to_owned()
                    } else {
                        touched.join(", ")
                    }
                ),
            );
        }
        Ok(())
    }
}
