//! Independent re-check of a plan (`pickplace validate`): it trusts nothing the planner
//! computed except the trajectory and the events (and `object.placed_pose`, which it compares
//! with where the object really ends).
//!
//! The trajectory is interpolated linearly between its samples, densely enough that no joint
//! moves more than 1° and no tool frame more than 1 cm between two checked states. At every
//! state: joint limits; between samples: time running forward and velocity limits;
//! robot–robot and robot–environment collision; the two hands' clearance
//! ([`HAND_CLEARANCE`]); the held object against the environment and against the robot,
//! the holding hands included: only the finger pads of a hand holding it, closing on it or
//! opening from it may touch it, and they may press into it by the gripper's squeeze and no
//! more, at every state it is held (issue 32). Near a resting pose (the start, every intermediate rest of a regrasp, the final pose:
//! within [`CONTACT_ZONE`] and its [`CONTACT_ZONE_SLACK`]) the object may touch the support it rests on there.
//!
//! The object follows the events, whatever their sequence (a direct plan, a handover, a
//! regrasp by placing, after Wan and Harada): it stays where it is until a grasp, moves with
//! the holding link, and stays where it was left after a release that leaves no hand holding
//! it. At every such release it must rest on a support: not in mid-air, not penetrating, and
//! statically stable (paper Fig. 7: the CoG's vertical passes through the hull of the contact
//! points; `pickplace_placement::stability`, the test the placement planner uses). At the end
//! it must no longer be held, lie at the plan's placed pose, within the scene's
//! `target.tolerance` of the target point and on the target's surface (paper §III-B.2: the
//! user's click).
//!
//! Every failure of a lower layer (a collision query, a mesh) is an [`Error`], never read as
//! "no problem".
//!
//! Its cost follows what moves (issue 33): each checked state queries the collision world's
//! BVHs by bounding boxes, and an environment part's own collision mesh is prepared only when
//! a resting pose or the target point comes within its box (`parts`, counted in
//! [`ValidationReport::work`]); a setup made by [`Setup::load_for_validation`] clusters no
//! environment mesh and builds no roadmap.

mod checker;
mod dynamics;
mod frames;
mod grip;
mod parts;
#[cfg(test)]
mod tests;

pub use crate::rules::{
    CONTACT_ZONE, CONTACT_ZONE_SLACK, HAND_CLEARANCE, HAND_CLEARANCE_SLACK, HandClearance, HandGap,
    MAX_CARTESIAN_STEP, MAX_JOINT_STEP,
};
pub use dynamics::LIMIT_SLACK;
pub use frames::FRAME_TOLERANCE;
pub use parts::ValidationWork;

use checker::{Validator, closing_windows};
use dynamics::{at_rest_at_events, dynamics, short_number, short_time};

use crate::contact::{OBJECT_NAME, SUPPORT_DISTANCE};
use crate::error::{Error, Result, internal};
use crate::plan::{EventKind, Plan, TrajectoryPoint};
use crate::setup::Setup;
use crate::strategy::Arm;
use pickplace_geometry::io::fmt_real_fixed;
use pickplace_geometry::math::{Isometry3, Point2, Real, Vector3};
use pickplace_placement::stability::SupportHull;
use pickplace_robot::collision::{BodyId, CheckOptions, CollisionScratch, CollisionWorld};
use pickplace_robot::gripper::GripObject;
use pickplace_robot::srdf::DisableReason;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Most interpolated states one validation checks (a million: minutes of collision queries).
/// A plan that would need more (a joint jumping 1e4 rad between samples, an unlimited joint
/// far off) is refused with [`Error::BadPlan`] before any state is checked.
pub const MAX_CHECKED_STATES: usize = 1_000_000;
/// Position tolerance for "the object is where the plan says" (m).
pub const POSE_TOLERANCE: Real = 0.002;
/// Largest lift (m) under which the resting object must not intersect the environment: a
/// pose this much deep into its support penetrates it.
pub const PENETRATION_LIFT: Real = 1e-3;
/// Reach (m) of the contact points that make a resting object's support hull: the contact
/// model's tolerance ([`pickplace_placement::stability::CONTACT_TOLERANCE`], 1 mm) above the
/// 0.5 mm clearance placements are lifted by.
pub const REST_CONTACT_REACH: Real = pickplace_placement::stability::CONTACT_TOLERANCE + 5e-4;

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
    /// What the contact queries prepared of the environment ([`ValidationWork`]).
    pub work: ValidationWork,
}

pub use pickplace_robot::gripper::{GRIP_GAP, GRIP_TOLERANCE};

/// A grasp or release with its arm and pose resolved.
#[derive(Debug, Clone, Copy)]
struct Ev {
    time: Real,
    kind: EventKind,
    arm: Arm,
    link_from_object: Isometry3,
}

/// Where the object rests (the start, or after a release that leaves no hand holding it) and
/// the environment parts it may touch there.
#[derive(Debug, Clone)]
struct Rest {
    pose: Isometry3,
    supports: Vec<String>,
}

/// Checks `plan` against `setup`'s scene. `plan_path` names the plan in errors.
///
/// # Errors
/// [`Error::BadPlan`] when the plan does not fit the robot (joint names, vector lengths,
/// non-finite numbers, a negative time, an invalid pose — zero or non-finite quaternion — in
/// an event, a key pose, a grasp, a rest or the object's poses, an event on a link that is no
/// arm's tool link), is empty, or would need more than [`MAX_CHECKED_STATES`] interpolated
/// states;
/// [`Error::Internal`] when a lower layer (collision queries, meshes) fails: a check that
/// cannot be made is never read as passed. A plan that fits but fails a check is not an
/// error: its problems are listed.
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
        if !p.time_from_start.is_finite() || p.positions.iter().any(|x| !x.is_finite()) {
            return Err(bad(format!("trajectory[{i}] has a non-finite number")));
        }
        if p.time_from_start < 0.0 {
            return Err(bad(format!(
                "trajectory[{i}]: time_from_start {} s is negative (times start at 0)",
                pickplace_geometry::io::fmt_real(p.time_from_start)
            )));
        }
    }
    plan.check_poses().map_err(|e| bad(e.to_string()))?;
    let end = plan.trajectory.last().map_or(0.0, |p| p.time_from_start);
    // Every value against its joint's limits before anything is interpolated: a value far
    // outside would make the interpolation endless. The first one is the plan's only problem.
    let limits: Vec<_> = model.variable_limits().copied().collect();
    for (i, p) in plan.trajectory.iter().enumerate() {
        for (j, (&q, l)) in p.positions.iter().zip(&limits).enumerate() {
            if !l.contains(q, 1e-6) {
                return Ok(ValidationReport {
                    format: "pickplace.validation/1",
                    states_checked: 0,
                    duration: end,
                    stability_margin: None,
                    work: ValidationWork::default(),
                    problems: vec![format!(
                        "t = {} s: {} = {} is outside its limits [{}, {}] (trajectory[{i}]; nothing else checked)",
                        short_time(p.time_from_start),
                        names[j],
                        short_number(q),
                        short_number(l.lower),
                        short_number(l.upper)
                    )],
                });
            }
        }
    }
    let arm_of_link = |link: &str| -> Option<Arm> {
        setup
            .arms
            .iter()
            .find(|a| a.tcp_name == link)
            .map(|a| a.arm)
    };
    let mut events = Vec::with_capacity(plan.events.len());
    for e in &plan.events {
        if !e.time.is_finite() {
            return Err(bad(format!(
                "event at {} s: the time is not finite",
                e.time
            )));
        }
        let arm = arm_of_link(&e.link).ok_or_else(|| {
            bad(format!(
                "event at {} s: {:?} is not the tool link of an arm",
                short_time(e.time),
                e.link
            ))
        })?;
        let link_from_object = e.link_from_object.to_isometry().map_err(|r| {
            bad(format!(
                "event at {} s: invalid pose: {r}",
                short_time(e.time)
            ))
        })?;
        events.push((
            Ev {
                time: e.time,
                kind: e.kind,
                arm,
                link_from_object,
            },
            e.arm,
        ));
    }
    // The rest of the plan's form (docs/plan-format.md): start at time 0, events in time
    // order and consistent with the strategy, grasps, rests and key poses.
    plan.check_form().map_err(|e| bad(e.to_string()))?;
    // Stable: a release and a grasp at one instant keep their order in the file.
    events.sort_by(|a, b| a.0.time.total_cmp(&b.0.time));
    let placed = plan
        .object
        .placed_pose
        .to_isometry()
        .map_err(|r| bad(format!("object.placed_pose: {r}")))?;

    let mut v = Validator::new(setup)?;
    // The frames the plan states (`base`, `arms[].tool`) against the scene's robot's, first.
    v.problems.extend(frames::problems(setup, plan));
    for (e, named) in &events {
        if *named != e.arm {
            v.problem(
                e.time,
                format!(
                    "the event names the {named} arm but its link is the {} hand's",
                    e.arm
                ),
            );
        }
        let at_sample = plan
            .trajectory
            .iter()
            .any(|p| (p.time_from_start - e.time).abs() <= 1e-6);
        if !at_sample {
            v.problem(
                e.time,
                format!(
                    "the {:?} of the {} hand is at no trajectory sample",
                    e.kind, e.arm
                ),
            );
        }
    }
    let events: Vec<Ev> = events.into_iter().map(|(e, _)| e).collect();
    at_rest_at_events(&mut v, plan, &names);
    dynamics(&mut v, plan, &names);
    v.rests = v.rest_poses(plan, &events)?;

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
    // The interpolated states between each pair of samples, counted and bounded before any
    // is checked.
    let mut steps = Vec::with_capacity(plan.trajectory.len());
    let mut total: Real = 0.0;
    for w in plan.trajectory.windows(2) {
        let (p, n_next) = (&w[0], &w[1]);
        let max_dq = p
            .positions
            .iter()
            .zip(&n_next.positions)
            .map(|(a, b)| (b - a).abs())
            .fold(0.0, Real::max);
        let tcp_move = setup
            .arms
            .iter()
            .map(|a| {
                (v.tcp(a.arm, &n_next.positions).translation.vector
                    - v.tcp(a.arm, &p.positions).translation.vector)
                    .norm()
            })
            .fold(0.0, Real::max);
        let n = (max_dq / MAX_JOINT_STEP)
            .max(tcp_move / MAX_CARTESIAN_STEP)
            .ceil()
            .max(1.0);
        total += n;
        if total.is_nan() || total > MAX_CHECKED_STATES as Real {
            return Err(bad(format!(
                "checking the trajectory up to trajectory[{}] would take more than {MAX_CHECKED_STATES} interpolated states (MAX_CHECKED_STATES; one per 1° of joint motion and 1 cm of tool motion): a joint or tool moves too far between samples",
                steps.len() + 1
            )));
        }
        steps.push(n as usize);
    }
    let windows = closing_windows(setup, &plan.trajectory, &events);
    let closing_at = |now: Real| {
        Arm::BOTH.map(|a| {
            windows
                .iter()
                .any(|&(w, t0, t1)| w == a && now >= t0 - 1e-9 && now <= t1 + 1e-9)
        })
    };
    let mut object = setup.object_start;
    // Holders: arm and link_from_object, in the order of their grasps.
    let mut holders: Vec<(Arm, Isometry3)> = Vec::new();
    // Counts the changes of `holders`: the collision worlds of a holding state are cached
    // under it (a regrasp by the same hand holds the object differently).
    let mut holding = 0;
    let mut last_object: Option<Isometry3> = None;
    let mut final_margin: Option<Option<Real>> = None;
    let mut next_event = 0;
    for i in 0..plan.trajectory.len() {
        let p = &plan.trajectory[i];
        let t = p.time_from_start;
        // Where the held object is at this sample, before its events (a release leaves it
        // here).
        if let Some(&(arm, link_from_object)) = holders.first() {
            object = v.tcp(arm, &p.positions) * link_from_object;
        }
        // Events at this sample.
        while next_event < events.len() && events[next_event].time <= t + 1e-9 {
            let e = events[next_event];
            next_event += 1;
            let tcp = v.tcp(e.arm, &p.positions);
            match e.kind {
                EventKind::Grasp => {
                    if holders.iter().any(|(h, _)| *h == e.arm) {
                        v.problem(
                            e.time,
                            format!(
                                "grasp by the {} hand, which holds the object already",
                                e.arm
                            ),
                        );
                    }
                    let implied = tcp * e.link_from_object;
                    let d = (implied.translation.vector - object.translation.vector).norm();
                    let a = implied.rotation.angle_to(&object.rotation);
                    if d > POSE_TOLERANCE || a > 2f64.to_radians() {
                        v.problem(
                            e.time,
                            format!(
                                "grasp by the {} hand: the object is {:.1} mm / {:.1}° from where the hand holds it",
                                e.arm,
                                d * 1e3,
                                a.to_degrees()
                            ),
                        );
                    }
                    holders.retain(|(h, _)| *h != e.arm);
                    holders.push((e.arm, e.link_from_object));
                    holding += 1;
                    v.grip_reported.retain(|&h| h != e.arm);
                }
                EventKind::Release => {
                    if !holders.iter().any(|(h, _)| *h == e.arm) {
                        v.problem(
                            e.time,
                            format!("release by the {} hand, which holds nothing", e.arm),
                        );
                        continue;
                    }
                    holders.retain(|(h, _)| *h != e.arm);
                    holding += 1;
                    if holders.is_empty() {
                        // The object is left: it must rest where it is. The last such rest
                        // is the placement.
                        let last = !events[next_event..]
                            .iter()
                            .any(|e| e.kind == EventKind::Grasp);
                        let what = if last {
                            "the placed object".to_owned()
                        } else {
                            format!("the object left by the {} hand", e.arm)
                        };
                        let margin = v.rest_check(e.time, &object, &what);
                        if last {
                            final_margin = Some(margin);
                        } else {
                            final_margin = None;
                        }
                    }
                }
            }
        }
        if let Some(&(arm, link_from_object)) = holders.first() {
            object = v.tcp(arm, &p.positions) * link_from_object;
        }
        if i + 1 == plan.trajectory.len() {
            v.check_state(t, &p.positions, (&holders, holding), &object, closing_at(t))?;
            break;
        }
        let n_next = &plan.trajectory[i + 1];
        let dt = n_next.time_from_start - t;
        if dt < 0.0 {
            v.problem(
                t,
                format!(
                    "time goes backwards (the next sample is {} s earlier)",
                    short_time(-dt)
                ),
            );
        } else {
            for (j, (a, b)) in p.positions.iter().zip(&n_next.positions).enumerate() {
                let dq = (b - a).abs();
                let vmax = setup
                    .timing
                    .get(j)
                    .map_or(limits[j].velocity, |l| l.velocity);
                if dq > 1e-9 && vmax > 0.0 && (dt <= 0.0 || dq / dt > vmax * 1.01 + 1e-6) {
                    v.problem(
                        t,
                        format!(
                            "{} moves at {} (limit {})",
                            names[j],
                            short_time(if dt > 0.0 { dq / dt } else { Real::INFINITY }),
                            short_time(vmax)
                        ),
                    );
                }
            }
        }
        // Dense interpolation between the samples (checked whatever the times say).
        let steps = steps[i];
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
            let now = t + f * dt.max(0.0);
            // Two hands holding must agree on where the object is.
            if let Some(&(arm, l)) = holders.get(1) {
                let other = v.tcp(arm, &q) * l;
                let d = (other.translation.vector - obj.translation.vector).norm();
                if d > POSE_TOLERANCE {
                    v.problem(
                        now,
                        format!("the two hands hold the object {:.1} mm apart", d * 1e3),
                    );
                }
            }
            v.check_state(now, &q, (&holders, holding), &obj, closing_at(now))?;
            // The pads' depth is checked at every state the object is held (a squeeze ramped
            // in while the hand rests is no better than one while it moves); their gap while
            // the held object moves (the fingers open and close with the hand at rest).
            let moved = last_object.is_some_and(|l: Isometry3| {
                (l.translation.vector - obj.translation.vector).norm() > 1e-6
                    || l.rotation.angle_to(&obj.rotation) > 1e-6
            });
            if !holders.is_empty() {
                v.check_grip(now, &q, &holders, &obj, moved)?;
            }
            last_object = Some(obj);
        }
    }
    if next_event < events.len() {
        let e = events[next_event];
        v.problem(
            e.time,
            format!(
                "the {:?} of the {} hand is after the end of the trajectory ({} s)",
                e.kind,
                e.arm,
                short_time(end)
            ),
        );
    }
    if let Some(&(arm, _)) = holders.first() {
        v.problem(
            end,
            format!("the object is still held at the end (by the {arm} hand)"),
        );
    }
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
    let stability_margin = match final_margin {
        Some(m) => m,
        // Never released (never grasped): the final pose is checked here.
        None if holders.is_empty() => v.rest_check(end, &object, "the placed object"),
        // Still held: not placed (reported above).
        None => None,
    };
    if holders.is_empty() {
        v.target_check(end, &object)?;
    }
    Ok(ValidationReport {
        format: "pickplace.validation/1",
        states_checked: v.states,
        duration: end,
        stability_margin,
        work: v.parts.work(),
        problems: v.problems,
    })
}
