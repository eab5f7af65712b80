//! Independent re-check of a plan (`pickplace validate`): it trusts nothing the planner
//! computed except the trajectory and the events.
//!
//! The trajectory is interpolated linearly between its samples, densely enough that no joint
//! moves more than 1° and no tool frame more than 1 cm between two checked states. At every
//! state: joint limits; between samples: velocity limits; robot–robot and robot–environment
//! collision; the held object against the environment (except while it is within
//! [`CONTACT_ZONE`] of its start or placed pose, where it rests on its support) and against the
//! robot (except the holding hand's links). The object follows the events: it stays where it
//! is until a grasp, moves with the holding link, and stays where it was released. At the end
//! it must lie at the plan's placed pose, not penetrate the environment, and be statically
//! stable there (paper Fig. 7: the CoG's vertical passes through the hull of the contact
//! points; `pickplace_placement::stability`, the test the placement planner uses).

use crate::contact::{OBJECT_NAME, supports};
use crate::error::{Error, Result};
use crate::plan::{EventKind, Plan};
use crate::setup::Setup;
use crate::strategy::Arm;
use pickplace_geometry::math::{Isometry3, Point2, Real, Vector3};
use pickplace_placement::stability::SupportHull;
use pickplace_robot::collision::{BodyId, CheckOptions, CollisionScratch, CollisionWorld};
use pickplace_robot::gripper::GripObject;
use pickplace_robot::srdf::DisableReason;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Largest joint change between checked states (rad): 1°.
pub const MAX_JOINT_STEP: Real = std::f64::consts::PI / 180.0;
/// Largest tool-frame displacement between checked states (m).
pub const MAX_CARTESIAN_STEP: Real = 0.01;
/// Within this distance (m) of its start or placed pose the object may touch its support.
pub const CONTACT_ZONE: Real = 0.006;
/// Clearance the two hands keep from each other, measured on their links' collision
/// geometry (m): the planner holds handovers to it.
pub const HAND_CLEARANCE: Real = 0.01;
/// Position tolerance for "the object is where the plan says" (m).
pub const POSE_TOLERANCE: Real = 0.002;

/// What `validate` found.
#[derive(Debug, Clone, Serialize)]
pub struct ValidationReport {
    /// `pickplace.validation/1`.
    pub format: &'static str,
    /// Interpolated states checked.
    pub states_checked: usize,
    /// Duration of the trajectory (s).
    pub duration: Real,
    /// Stability margin of the final pose (m), when the object ends on a support.
    pub stability_margin: Option<Real>,
    /// Every problem, in time order (empty: the plan is valid).
    pub problems: Vec<String>,
}

/// The largest gap (m) between a holding hand's finger pad and the object.
pub const GRIP_GAP: Real = 0.002;
/// Penetration (m) tolerated beyond the gripper's squeeze (the pads are convex hulls, the
/// object a triangle mesh).
pub const GRIP_TOLERANCE: Real = 0.0005;

/// Checks `plan` against `setup`'s scene. `plan_path` names the plan in errors.
///
/// # Errors
/// [`Error::BadPlan`] when the plan does not fit the robot (joint names, vector lengths) or
/// is empty. A plan that fits but fails a check is not an error: its problems are listed.
pub fn validate(setup: &Setup, plan: &Plan, plan_path: &Path) -> Result<ValidationReport> {
    let model = &setup.model;
    let names: Vec<&str> = model.variable_names().collect();
    let bad = |reason: String| Error::BadPlan {
        path: plan_path.to_path_buf(),
        reason,
    };
    if plan.joint_names.len() != names.len()
        || plan.joint_names.iter().zip(&names).any(|(a, b)| a != b)
    {
        return Err(bad(format!(
            "joint_names do not match the robot {:?} (expected {} joints: {})",
            model.name(),
            names.len(),
            names.join(", ")
        )));
    }
    if plan.trajectory.is_empty() {
        return Err(bad("the trajectory is empty".to_owned()));
    }
    for (i, p) in plan.trajectory.iter().enumerate() {
        if p.positions.len() != names.len() {
            return Err(bad(format!(
                "trajectory[{i}] has {} positions for {} joints",
                p.positions.len(),
                names.len()
            )));
        }
    }
    let mut events = plan.events.clone();
    events.sort_by(|a, b| a.time.total_cmp(&b.time));
    let arm_of_link = |link: &str| -> Option<Arm> {
        setup
            .arms
            .iter()
            .find(|a| a.tcp_name == link)
            .map(|a| a.arm)
    };
    for e in &events {
        if arm_of_link(&e.link).is_none() {
            return Err(bad(format!(
                "event at {:.3} s: {:?} is not the tool link of an arm",
                e.time, e.link
            )));
        }
        if e.link_from_object.to_isometry().is_err() {
            return Err(bad(format!("event at {:.3} s: invalid pose", e.time)));
        }
    }
    let placed = plan
        .object
        .placed_pose
        .to_isometry()
        .map_err(|r| bad(format!("object.placed_pose: {r}")))?;

    let grip_object =
        GripObject::new(&setup.object_mesh).map_err(crate::error::internal("grip check"))?;
    let mut v = Validator {
        setup,
        grip_object,
        grip_reported: Vec::new(),
        problems: Vec::new(),
        worlds: BTreeMap::new(),
        scratch: CollisionScratch::default(),
        start_supports: supports(setup, &setup.object_start),
        placed_supports: supports(setup, &placed),
        placed,
        states: 0,
    };
    let start = &plan.trajectory[0];
    if start
        .positions
        .iter()
        .zip(&setup.start)
        .any(|(a, b)| (a - b).abs() > 1e-6)
    {
        v.problem(
            0.0,
            "the trajectory does not begin at the scene's start state".into(),
        );
    }
    let limits: Vec<_> = model.variable_limits().copied().collect();
    let windows = closing_windows(setup, plan, &events, &arm_of_link);
    let mut object = setup.object_start;
    // Holders: arm and link_from_object.
    let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
    let mut last_object: Option<Isometry3> = None;
    let mut next_event = 0;
    for i in 0..plan.trajectory.len() {
        let p = &plan.trajectory[i];
        let t = p.time_from_start;
        for (j, (&q, l)) in p.positions.iter().zip(&limits).enumerate() {
            if !l.contains(q, 1e-6) {
                v.problem(t, format!("{} = {q:.4} is outside its limits", names[j]));
            }
        }
        // Events at this sample.
        while next_event < events.len() && events[next_event].time <= t + 1e-9 {
            let e = &events[next_event];
            next_event += 1;
            let arm = arm_of_link(&e.link).expect("checked above");
            let link_from_object = e.link_from_object.to_isometry().expect("checked above");
            let tcp = v.tcp(arm, &p.positions);
            match e.kind {
                EventKind::Grasp => {
                    let implied = tcp * link_from_object;
                    let d = (implied.translation.vector - object.translation.vector).norm();
                    let a = implied.rotation.angle_to(&object.rotation);
                    if d > POSE_TOLERANCE || a > 2f64.to_radians() {
                        v.problem(
                            e.time,
                            format!(
                                "grasp by the {arm} hand: the object is {:.1} mm / {:.1}° from where the hand holds it",
                                d * 1e3,
                                a.to_degrees()
                            ),
                        );
                    }
                    holders.retain(|(h, _)| *h != arm);
                    holders.push((arm, link_from_object));
                    v.grip_reported.retain(|&h| h != arm);
                }
                EventKind::Release => {
                    if !holders.iter().any(|(h, _)| *h == arm) {
                        v.problem(
                            e.time,
                            format!("release by the {arm} hand, which holds nothing"),
                        );
                    }
                    holders.retain(|(h, _)| *h != arm);
                }
            }
        }
        if let Some(&(arm, link_from_object)) = holders.first() {
            object = v.tcp(arm, &p.positions) * link_from_object;
        }
        if i + 1 == plan.trajectory.len() {
            let closing = [Arm::Right, Arm::Left].map(|a| {
                windows
                    .iter()
                    .any(|&(w, t0, t1)| w == a && t >= t0 - 1e-9 && t <= t1 + 1e-9)
            });
            v.check_state(t, &p.positions, &holders, &object, closing);
            break;
        }
        let n_next = &plan.trajectory[i + 1];
        let dt = n_next.time_from_start - t;
        if dt < 0.0 {
            v.problem(t, "time goes backwards".into());
            continue;
        }
        for (j, (a, b)) in p.positions.iter().zip(&n_next.positions).enumerate() {
            let dq = (b - a).abs();
            let vmax = limits[j].velocity;
            if dq > 1e-9 && vmax > 0.0 && (dt <= 0.0 || dq / dt > vmax * 1.01 + 1e-6) {
                v.problem(
                    t,
                    format!(
                        "{} moves at {:.3} (limit {vmax:.3})",
                        names[j],
                        if dt > 0.0 { dq / dt } else { Real::INFINITY }
                    ),
                );
            }
        }
        // Dense interpolation between the samples.
        let max_dq = p
            .positions
            .iter()
            .zip(&n_next.positions)
            .map(|(a, b)| (b - a).abs())
            .fold(0.0, Real::max);
        let tcp_move = setup
            .arms
            .iter()
            .map(|a| a.arm)
            .map(|a| {
                (v.tcp(a, &n_next.positions).translation.vector
                    - v.tcp(a, &p.positions).translation.vector)
                    .norm()
            })
            .fold(0.0, Real::max);
        let steps = ((max_dq / MAX_JOINT_STEP)
            .max(tcp_move / MAX_CARTESIAN_STEP)
            .ceil() as usize)
            .max(1);
        let mut q = p.positions.clone();
        for s in 0..steps {
            let f = s as Real / steps as Real;
            for (k, x) in q.iter_mut().enumerate() {
                *x = p.positions[k] + f * (n_next.positions[k] - p.positions[k]);
            }
            let obj = match holders.first() {
                Some(&(arm, l)) => v.tcp(arm, &q) * l,
                None => object,
            };
            // Two hands holding must agree on where the object is.
            if let Some(&(arm, l)) = holders.get(1) {
                let other = v.tcp(arm, &q) * l;
                let d = (other.translation.vector - obj.translation.vector).norm();
                if d > POSE_TOLERANCE {
                    v.problem(
                        t + f * dt,
                        format!("the two hands hold the object {:.1} mm apart", d * 1e3),
                    );
                }
            }
            let now = t + f * dt;
            let closing = [Arm::Right, Arm::Left].map(|a| {
                windows
                    .iter()
                    .any(|&(w, t0, t1)| w == a && now >= t0 - 1e-9 && now <= t1 + 1e-9)
            });
            v.check_state(now, &q, &holders, &obj, closing);
            // The grip is checked while the held object moves (the fingers open and close
            // with the hand at rest).
            let moved = last_object.is_some_and(|l: Isometry3| {
                (l.translation.vector - obj.translation.vector).norm() > 1e-6
                    || l.rotation.angle_to(&obj.rotation) > 1e-6
            });
            if moved {
                v.check_grip(t + f * dt, &q, &holders, &obj)?;
            }
            last_object = Some(obj);
        }
    }
    if !holders.is_empty() {
        v.problem(
            plan.trajectory.last().map_or(0.0, |p| p.time_from_start),
            "the object is still held at the end".into(),
        );
    }
    let end = plan.trajectory.last().map_or(0.0, |p| p.time_from_start);
    let d = (object.translation.vector - placed.translation.vector).norm();
    let a = object.rotation.angle_to(&placed.rotation);
    if d > POSE_TOLERANCE || a > 2f64.to_radians() {
        v.problem(
            end,
            format!(
                "the object ends {:.1} mm / {:.1}° from the plan's placed pose",
                d * 1e3,
                a.to_degrees()
            ),
        );
    }
    let stability_margin = v.final_pose(end, &object);
    let states = v.states;
    Ok(ValidationReport {
        format: "pickplace.validation/1",
        states_checked: states,
        duration: end,
        stability_margin,
        problems: v.problems,
    })
}

/// When each hand may touch the object besides holding it: from the start of its closing
/// motion (the arm at rest before the grasp event) to the grasp, and from a release to the end
/// of its opening (the arm at rest after it): `(arm, from, to)`.
fn closing_windows(
    setup: &Setup,
    plan: &Plan,
    events: &[crate::plan::Event],
    arm_of_link: &dyn Fn(&str) -> Option<Arm>,
) -> Vec<(Arm, Real, Real)> {
    let traj = &plan.trajectory;
    let at_rest = |arm: Arm, i: usize, k: usize| {
        setup
            .arm(arm)
            .variables
            .iter()
            .all(|&v| (traj[i].positions[v] - traj[k].positions[v]).abs() <= 1e-9)
    };
    let mut windows = Vec::new();
    for e in events {
        let Some(arm) = arm_of_link(&e.link) else {
            continue;
        };
        // The sample at (or just before) the event.
        let i = traj
            .partition_point(|p| p.time_from_start <= e.time + 1e-9)
            .saturating_sub(1);
        match e.kind {
            EventKind::Grasp => {
                let mut k = i;
                while k > 0 && at_rest(arm, i, k - 1) {
                    k -= 1;
                }
                windows.push((arm, traj[k].time_from_start, e.time));
            }
            EventKind::Release => {
                let mut k = i;
                while k + 1 < traj.len() && at_rest(arm, i, k + 1) {
                    k += 1;
                }
                windows.push((arm, e.time, traj[k].time_from_start));
            }
        }
    }
    windows
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum WorldKey {
    /// The object lies free (not held).
    Free,
    /// Held by one or two arms; `bool`: may touch its support; the last two: the right and
    /// left hand closing on it or opening from it (their fingers may touch it).
    Held(Arm, Option<Arm>, bool, bool, bool),
}

struct Validator<'a> {
    setup: &'a Setup,
    /// The object for the fingers' gaps.
    grip_object: GripObject,
    /// Arms whose grip problem is reported already (once per hold).
    grip_reported: Vec<Arm>,
    problems: Vec<String>,
    worlds: BTreeMap<WorldKey, CollisionWorld>,
    scratch: CollisionScratch,
    start_supports: Vec<String>,
    placed_supports: Vec<String>,
    placed: Isometry3,
    states: usize,
}

impl Validator<'_> {
    fn problem(&mut self, t: Real, what: String) {
        self.problems.push(format!("t = {t:.3} s: {what}"));
    }

    /// The grip (issue: fingers that never close): while an arm holds the object, both of
    /// its finger pads touch it, no more than [`GRIP_GAP`] away and no deeper than the
    /// gripper's squeeze (and [`GRIP_TOLERANCE`]). Reported once per hold.
    ///
    /// # Errors
    /// [`Error::Internal`] when the collision library cannot measure a finger.
    fn check_grip(
        &mut self,
        t: Real,
        q: &[Real],
        holders: &[(Arm, Isometry3)],
        object: &Isometry3,
    ) -> Result<()> {
        if holders.iter().all(|(a, _)| self.grip_reported.contains(a)) {
            return Ok(());
        }
        let setup = self.setup;
        let poses: Vec<Isometry3> = setup
            .model
            .link_poses(q)
            .map_err(crate::error::internal("grip check"))?
            .into_iter()
            .map(|p| setup.world_from_root * p)
            .collect();
        for &(arm, _) in holders {
            if self.grip_reported.contains(&arm) {
                continue;
            }
            let gripper = &setup.arm(arm).gripper;
            let gaps = gripper
                .finger_gaps(&poses, &self.grip_object, object)
                .map_err(crate::error::internal("grip check"))?;
            for (pad, &gap) in gaps.iter().enumerate() {
                let problem = if gap > GRIP_GAP {
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

    fn tcp(&self, arm: Arm, q: &[Real]) -> Isometry3 {
        self.setup.world_from_root * self.setup.arm(arm).ik.chain().pose(q)
    }

    fn near(&self, object: &Isometry3) -> bool {
        let close = |p: &Isometry3| {
            (object.translation.vector - p.translation.vector).norm() <= CONTACT_ZONE
                && object.rotation.angle_to(&p.rotation) <= 3f64.to_radians()
        };
        close(&self.setup.object_start) || close(&self.placed)
    }

    fn world(&mut self, key: WorldKey, holders: &[(Arm, Isometry3)]) -> &CollisionWorld {
        let setup = self.setup;
        let (start_supports, placed_supports) = (&self.start_supports, &self.placed_supports);
        self.worlds.entry(key).or_insert_with(|| {
            let mut w = setup.world.clone();
            if let WorldKey::Held(_, _, true, _, _) = key {
                let mut acm = w.acm().clone();
                for s in start_supports.iter().chain(placed_supports) {
                    acm.allow(
                        OBJECT_NAME,
                        s,
                        DisableReason::Custom("resting contact".into()),
                    );
                }
                w.set_acm(acm);
            }
            if let Some(&(arm, link_from_object)) = holders.first() {
                let mut touch: Vec<&str> = Vec::new();
                for (h, _) in holders {
                    touch.extend(setup.arm(*h).finger_links.iter().map(String::as_str));
                }
                if let WorldKey::Held(_, _, _, right, left) = key {
                    for (a, closing) in [(Arm::Right, right), (Arm::Left, left)] {
                        if closing && setup.has_arm(a) {
                            touch.extend(setup.arm(a).finger_links.iter().map(String::as_str));
                        }
                    }
                }
                // The link and fingers exist: the setup found them in this model.
                let _ = w.attach(
                    OBJECT_NAME,
                    &setup.arm(arm).tcp_name,
                    setup.object_shape.clone(),
                    &link_from_object,
                    &touch,
                );
            }
            w
        })
    }

    fn check_state(
        &mut self,
        t: Real,
        q: &[Real],
        holders: &[(Arm, Isometry3)],
        object: &Isometry3,
        closing: [bool; 2],
    ) {
        self.states += 1;
        let [right, left] = closing;
        let key = match holders {
            [] => WorldKey::Free,
            [(a, _)] => WorldKey::Held(*a, None, self.near(object), right, left),
            [(a, _), (b, _), ..] => WorldKey::Held(*a, Some(*b), self.near(object), right, left),
        };
        if key == WorldKey::Free {
            // The free object is an obstacle where it lies; a hand closing on it or opening
            // from it may touch it.
            let mut w = self.setup.world.clone();
            let mut acm = w.acm().clone();
            for (a, on) in [(Arm::Right, right), (Arm::Left, left)] {
                if on && self.setup.has_arm(a) {
                    for link in &self.setup.arm(a).finger_links {
                        acm.allow(
                            OBJECT_NAME,
                            link,
                            DisableReason::Custom("closing on the object".into()),
                        );
                    }
                }
            }
            w.set_acm(acm);
            w.add_environment(OBJECT_NAME, self.setup.object_shape.clone(), object);
            let pairs = w
                .colliding_pairs(
                    &self.setup.model,
                    q,
                    &mut self.scratch,
                    &CheckOptions::default(),
                )
                .unwrap_or_default();
            if let Some(&(a, b)) = pairs.first() {
                let msg = format!("collision {} / {}", w.body_name(a), w.body_name(b));
                self.problem(t, msg);
            }
            return;
        }
        let model = &self.setup.model;
        let mut scratch = std::mem::take(&mut self.scratch);
        let w = self.world(key, holders);
        let pairs = w
            .colliding_pairs(model, q, &mut scratch, &CheckOptions::default())
            .unwrap_or_default();
        let msg = pairs.first().map(|&(a, b)| {
            let name = |x: BodyId| match x {
                BodyId::Attached(_) => "held object".to_owned(),
                _ => w.body_name(x).to_owned(),
            };
            format!("collision {} / {}", name(a), name(b))
        });
        self.scratch = scratch;
        if let Some(msg) = msg {
            self.problem(t, msg);
        }
    }

    /// Penetration and stability of the final pose; returns the stability margin.
    fn final_pose(&mut self, t: Real, object: &Isometry3) -> Option<Real> {
        let setup = self.setup;
        let env = &setup.placement_env.collision;
        let obj = &setup.placement_object.collision;
        if env.intersects(obj, object, &Vector3::new(0.0, 0.0, 1e-3)) {
            self.problem(t, "the placed object penetrates the environment".into());
        }
        let points = env.touching_points(obj, object, 1.5e-3);
        let ring: Vec<Point2> = points.iter().map(|p| Point2::new(p.x, p.y)).collect();
        let support = SupportHull::of_points(&ring);
        let cog = object * setup.cog;
        if !support.has_area() {
            self.problem(
                t,
                "the placed object does not rest on a support (fewer than 3 contacts)".into(),
            );
            return None;
        }
        let margin = support.cog_margin(&Point2::new(cog.x, cog.y));
        if margin <= 0.0 {
            self.problem(
                t,
                format!(
                    "the placed object is unstable: the CoG's vertical is {:.1} mm outside its support",
                    -margin * 1e3
                ),
            );
        }
        Some(margin)
    }
}
