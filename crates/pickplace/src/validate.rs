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
//! within [`CONTACT_ZONE`]) the object may touch the support it rests on there.
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

mod frames;
mod grip;
mod parts;

pub use frames::FRAME_TOLERANCE;
pub use parts::ValidationWork;

use crate::contact::{OBJECT_NAME, SUPPORT_DISTANCE};
use crate::error::{Error, Result, internal};
use crate::plan::{EventKind, Plan, TrajectoryPoint};
use crate::setup::Setup;
use crate::strategy::Arm;
use pickplace_geometry::io::fmt_real_fixed;
use pickplace_geometry::math::{Isometry3, Point2, Real, Vector3};
use pickplace_placement::stability::SupportHull;
use pickplace_robot::collision::{
    AllowedCollisionMatrix, BodyId, CheckOptions, CollisionScratch, CollisionWorld, PairScope,
};
use pickplace_robot::gripper::GripObject;
use pickplace_robot::srdf::DisableReason;
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::Path;

/// Most interpolated states one validation checks (a million: minutes of collision queries).
/// A plan that would need more (a joint jumping 1e4 rad between samples, an unlimited joint
/// far off) is refused with [`Error::BadPlan`] before any state is checked.
pub const MAX_CHECKED_STATES: usize = 1_000_000;
/// Largest joint change between checked states (rad): 1°.
pub const MAX_JOINT_STEP: Real = std::f64::consts::PI / 180.0;
/// Largest tool-frame displacement between checked states (m).
pub const MAX_CARTESIAN_STEP: Real = 0.01;
/// Within this distance (m) of a resting pose (the start, an intermediate rest, the final
/// pose) the object may touch the support it rests on there.
pub const CONTACT_ZONE: Real = 0.006;
/// Position tolerance for "the object is where the plan says" (m).
pub const POSE_TOLERANCE: Real = 0.002;
/// Least distance (m) between the two hands' links (each arm's gripper links and the link
/// carrying them), measured on their collision geometry at every checked state. The planner
/// keeps the same clearance at a handover.
pub const HAND_CLEARANCE: Real = 0.01;
/// What the hand clearance may lose to the linear interpolation between samples (m): the
/// validator reports hands closer than `HAND_CLEARANCE - HAND_CLEARANCE_SLACK`.
pub const HAND_CLEARANCE_SLACK: Real = 0.001;
/// Largest lift (m) under which the resting object must not intersect the environment: a
/// pose this much deep into its support penetrates it.
pub const PENETRATION_LIFT: Real = 1e-3;
/// Reach (m) of the contact points that make a resting object's support hull: the contact
/// model's tolerance ([`pickplace_placement::stability::CONTACT_TOLERANCE`], 1 mm) above the
/// 0.5 mm clearance placements are lifted by.
pub const REST_CONTACT_REACH: Real = pickplace_placement::stability::CONTACT_TOLERANCE + 5e-4;

/// `value` with 4 decimals, or in scientific notation from 1e6 on (1e300 is not 301 digits).
fn short_number(value: Real) -> String {
    fmt_real_fixed(value, 4)
}

/// The robot is at rest at every grasp and release (docs/plan-format.md): an event is at a
/// trajectory sample, and from rest a joint whose acceleration is at most its limit `a`
/// ([`Setup::timing`]) moves at most `a h² / 2` in the time `h` to the sample before or
/// after it (5 % and 1e-9 of slack for rounding); where the plan has velocities, they are 0
/// there. Key poses are at trajectory samples; the robot may pass through them moving (a
/// blend between two motions, docs/trajectories.md).
fn at_rest_at_events(v: &mut Validator<'_>, plan: &Plan, names: &[&str]) {
    let samples = &plan.trajectory;
    for k in &plan.key_poses {
        if !samples
            .iter()
            .any(|p| (p.time_from_start - k.time).abs() <= 1e-6)
        {
            v.problem(
                k.time,
                format!("key pose {:?} is at no trajectory sample", k.name),
            );
        }
    }
    let stops = plan.events.iter().map(|e| {
        let what = match e.kind {
            EventKind::Grasp => "grasp",
            EventKind::Release => "release",
        };
        (e.time, format!("the {} hand's {what}", e.arm))
    });
    for (time, what) in stops {
        let Some(i) = samples
            .iter()
            .position(|p| (p.time_from_start - time).abs() <= 1e-6)
        else {
            v.problem(time, format!("{what} is at no trajectory sample"));
            continue;
        };
        if let Some((j, speed)) = samples[i]
            .velocities
            .iter()
            .enumerate()
            .map(|(j, s)| (j, s.abs()))
            .find(|&(_, s)| s > 1e-9)
        {
            v.problem(
                time,
                format!(
                    "the robot is not at rest at {what}: {} has velocity {}",
                    names.get(j).copied().unwrap_or("?"),
                    short_number(speed)
                ),
            );
            continue;
        }
        let neighbours = [i.checked_sub(1), Some(i + 1)];
        'sides: for n in neighbours.into_iter().flatten() {
            let Some(other) = samples.get(n) else {
                continue;
            };
            let h = (other.time_from_start - samples[i].time_from_start).abs();
            for (j, (a, b)) in samples[i]
                .positions
                .iter()
                .zip(&other.positions)
                .enumerate()
            {
                let acc = v.setup.timing.get(j).map_or(0.0, |l| l.acceleration);
                let bound = 0.5 * acc * h * h * 1.05 + 1e-9;
                if (a - b).abs() > bound {
                    v.problem(
                        time,
                        format!(
                            "the robot is not at rest at {what}: {} moves {} in the {} s to trajectory[{n}] (at most {} from rest at {} rad/s²)",
                            names.get(j).copied().unwrap_or("?"),
                            short_number((a - b).abs()),
                            short_time(h),
                            short_number(bound),
                            short_number(acc)
                        ),
                    );
                    break 'sides;
                }
            }
        }
    }
}

/// Relative slack of the velocity and acceleration checks (the timing meets its limits at
/// grid points; between them, and through rounding, a little more).
pub const LIMIT_SLACK: Real = 0.02;

/// Velocities and accelerations against the joints' limits ([`Setup::timing`]), where the
/// plan has them (format 2): each sample's values, and between samples the velocity change
/// (`|Δv| / h` at most the acceleration limit) and the position change (the trapezoid rule:
/// `|Δq − h (v₀ + v₁) / 2|` at most `a h² / 4`, exact for piecewise-constant acceleration
/// within one phase and bounded by it across phases). One problem per joint and kind.
fn dynamics(v: &mut Validator<'_>, plan: &Plan, names: &[&str]) {
    let timing = v.setup.timing.clone();
    let mut reported = vec![[false; 4]; timing.len()];
    let mut report = |v: &mut Validator<'_>, t: Real, j: usize, kind: usize, what: String| {
        if let Some(r) = reported.get_mut(j)
            && !r[kind]
        {
            r[kind] = true;
            v.problem(
                t,
                format!("{} {what}", names.get(j).copied().unwrap_or("?")),
            );
        }
    };
    let n = timing.len();
    for (i, p) in plan.trajectory.iter().enumerate() {
        if p.velocities.len() != n || p.accelerations.len() != n {
            continue;
        }
        let t = p.time_from_start;
        for (j, l) in timing.iter().enumerate() {
            let (vel, acc) = (p.velocities[j].abs(), p.accelerations[j].abs());
            if vel > l.velocity * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    0,
                    format!(
                        "velocity {} over its limit {}",
                        short_number(vel),
                        short_number(l.velocity)
                    ),
                );
            }
            if acc > l.acceleration * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    1,
                    format!(
                        "acceleration {} over its limit {}",
                        short_number(acc),
                        short_number(l.acceleration)
                    ),
                );
            }
        }
        let Some(next) = plan.trajectory.get(i + 1) else {
            continue;
        };
        if next.velocities.len() != n {
            continue;
        }
        let h = next.time_from_start - t;
        if h <= 0.0 {
            continue;
        }
        for (j, l) in timing.iter().enumerate() {
            let dv = (next.velocities[j] - p.velocities[j]).abs();
            // Times are rounded to the microsecond: h may be 2 µs off.
            if dv > l.acceleration * (h + 2e-6) * (1.0 + LIMIT_SLACK) + 1e-9 {
                report(
                    v,
                    t,
                    j,
                    2,
                    format!(
                        "changes velocity by {} in {} s: more than its acceleration limit {} allows",
                        short_number(dv),
                        short_time(h),
                        short_number(l.acceleration)
                    ),
                );
            }
            let dq = next.positions[j] - p.positions[j];
            let mean = 0.5 * h * (p.velocities[j] + next.velocities[j]);
            let bound =
                0.25 * l.acceleration * h * h * (1.0 + LIMIT_SLACK) + l.velocity * 2e-6 + 1e-7;
            if (dq - mean).abs() > bound {
                report(
                    v,
                    t,
                    j,
                    3,
                    format!(
                        "moves {} in {} s while its velocities say {}: positions and velocities disagree",
                        short_number(dq),
                        short_time(h),
                        short_number(mean)
                    ),
                );
            }
        }
    }
}

/// A time (s) from a plan with 3 decimals, compact when huge (`fmt_real_fixed`).
fn short_time(t: Real) -> String {
    fmt_real_fixed(t, 3)
}

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
    plan.check_poses().map_err(bad)?;
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
    plan.check_form().map_err(bad)?;
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

/// When each hand may touch the object besides holding it: from the start of its closing
/// motion (the arm at rest before the grasp event) to the grasp, and from a release to the end
/// of its opening (the arm at rest after it): `(arm, from, to)`. One window per event, of
/// whichever hand and in whatever sequence (a direct plan, the second hand at a handover, a
/// regrasp after a rest); the fingers' own joints are not part of the arm, so they may move
/// in the window.
fn closing_windows(
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
enum WorldKey {
    /// The object lies free at rest `usize`; the right and left hand closing on it or opening
    /// from it (their fingers may touch it).
    Free(usize, bool, bool),
    /// Held (by one or two arms) in the holding state `usize` (the number of grasps and
    /// releases before it); `Option<usize>`: the rest it is near (it may touch that rest's
    /// supports); the last two: the right and left hand closing or opening.
    Held(usize, Option<usize>, bool, bool),
}

struct Validator<'a> {
    setup: &'a Setup,
    /// The object for the fingers' gaps.
    grip_object: GripObject,
    /// Arms whose grip problem is reported already (once per hold).
    grip_reported: Vec<Arm>,
    /// The pads' gaps by their pose relative to the object.
    grip_memo: grip::GripMemo,
    problems: Vec<String>,
    /// The state problems (collisions, clearance; by rule and bodies) of the previous checked
    /// state: a problem that lasts is reported once, when it starts.
    ongoing: Vec<String>,
    worlds: BTreeMap<WorldKey, CollisionWorld>,
    /// The two hands' clearance (two-armed robots).
    hands: Option<HandClearance>,
    scratch: CollisionScratch,
    /// The environment's parts, for the supports of a pose and the target's surface.
    parts: parts::Parts<'a>,
    /// The start (index 0) and every pose where a release leaves the object.
    rests: Vec<Rest>,
    states: usize,
}

impl<'a> Validator<'a> {
    fn new(setup: &'a Setup) -> Result<Self> {
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

    fn problem(&mut self, t: Real, what: String) {
        self.problems
            .push(format!("t = {} s: {what}", short_time(t)));
    }

    /// Environment parts within [`SUPPORT_DISTANCE`] of the object at `world_from_object`,
    /// in scene order (the rule of [`crate::contact::supports`], on meshes built once, and
    /// only for the parts whose box is within reach: `parts::Parts::touching`).
    ///
    /// # Errors
    /// [`Error::Internal`] when a part's mesh cannot be prepared.
    fn supports(&mut self, world_from_object: &Isometry3) -> Result<Vec<String>> {
        let object = &self.setup.placement_object.collision;
        self.parts
            .touching(object, world_from_object, SUPPORT_DISTANCE)
    }

    /// The resting poses: the start, then where each release that leaves no hand holding
    /// the object leaves it (computed from the samples at the events, before the dense
    /// pass, so that the approach to a rest may already touch its support).
    fn rest_poses(&mut self, plan: &Plan, events: &[Ev]) -> Result<Vec<Rest>> {
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
    fn check_grip(
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

    fn tcp(&self, arm: Arm, q: &[Real]) -> Isometry3 {
        self.setup.world_from_root * self.setup.arm(arm).ik.chain().pose(q)
    }

    /// The resting pose the object is near (within [`CONTACT_ZONE`] and 3°), if any: the
    /// latest in time order when several are.
    fn near(&self, object: &Isometry3) -> Option<usize> {
        self.rests.iter().rposition(|r| {
            (object.translation.vector - r.pose.translation.vector).norm() <= CONTACT_ZONE
                && object.rotation.angle_to(&r.pose.rotation) <= 3f64.to_radians()
        })
    }

    /// The collision world of `key`, built once.
    ///
    /// # Errors
    /// [`Error::Internal`] when the object cannot be attached to a holding link.
    fn world(
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
    fn check_state(
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
    fn rest_check(&mut self, t: Real, object: &Isometry3, what: &str) -> Option<Real> {
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
    fn target_check(&mut self, t: Real, object: &Isometry3) -> Result<()> {
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
    use pickplace_geometry::math::Translation3;

    #[test]
    fn every_grasp_and_release_of_either_hand_has_its_touch_window() {
        // A synthetic handover followed by a regrasp: the right hand picks, the left takes
        // the object over, the right lets go, the left puts it down and grasps it again.
        // Each hand may touch the object from the start of its closing (its arm at rest) to
        // the grasp, and from a release to the end of its opening.
        let setup = crate::testing::setup("fig9-near.toml");
        let r = setup.arm(Arm::Right).variables[0];
        let l = setup.arm(Arm::Left).variables[0];
        let rf = setup.arm(Arm::Right).finger_variables[0];
        let lf = setup.arm(Arm::Left).finger_variables[0];
        // (right arm, left arm, right fingers, left fingers) per second.
        let samples = [
            (0.0, 0.0, 0.0, 0.0),
            (0.1, 0.0, 0.0, 0.0),
            (0.2, 0.0, 0.0, 0.0),  // the right arm arrives
            (0.2, 0.0, 0.01, 0.0), // its fingers close
            (0.2, 0.0, 0.02, 0.0), // grasp (right)
            (0.3, 0.0, 0.02, 0.0),
            (0.3, 0.1, 0.02, 0.0),
            (0.3, 0.2, 0.02, 0.0),  // the left arm arrives
            (0.3, 0.2, 0.02, 0.01), // its fingers close
            (0.3, 0.2, 0.02, 0.02), // grasp (left)
            (0.3, 0.2, 0.02, 0.02), // release (right)
            (0.3, 0.2, 0.0, 0.02),  // the right fingers open
            (0.4, 0.2, 0.0, 0.02),  // the right arm leaves
            (0.4, 0.3, 0.0, 0.02),  // the left arm places
            (0.4, 0.3, 0.0, 0.02),  // release (left)
            (0.4, 0.3, 0.0, 0.0),   // its fingers open
            (0.4, 0.3, 0.0, 0.02),  // regrasp (left), fingers closed again
            (0.4, 0.4, 0.0, 0.02),
        ];
        let traj: Vec<TrajectoryPoint> = samples
            .iter()
            .enumerate()
            .map(|(i, &(qr, ql, fr, fl))| {
                let mut q = setup.start.clone();
                q[r] += qr;
                q[l] += ql;
                q[rf] += fr;
                q[lf] += fl;
                TrajectoryPoint::positions_only(i as Real, q)
            })
            .collect();
        let ev = |time: Real, kind: EventKind, arm: Arm| Ev {
            time,
            kind,
            arm,
            link_from_object: Isometry3::identity(),
        };
        let events = [
            ev(4.0, EventKind::Grasp, Arm::Right),
            ev(9.0, EventKind::Grasp, Arm::Left),
            ev(10.0, EventKind::Release, Arm::Right),
            ev(14.0, EventKind::Release, Arm::Left),
            ev(16.0, EventKind::Grasp, Arm::Left),
        ];
        let windows = closing_windows(setup, &traj, &events);
        assert_eq!(
            windows,
            [
                (Arm::Right, 2.0, 4.0),
                (Arm::Left, 7.0, 9.0),
                (Arm::Right, 10.0, 11.0),
                (Arm::Left, 14.0, 16.0),
                (Arm::Left, 13.0, 16.0),
            ]
        );
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig { cases: 200, ..Default::default() })]

        /// A touch window runs exactly over the samples where the hand's arm stands where it
        /// is at the event: it ends (grasp) or starts (release) at the event, and the sample
        /// just outside it has the arm elsewhere.
        #[test]
        fn a_touch_window_spans_exactly_the_arm_at_rest(
            moves in proptest::collection::vec(proptest::bool::ANY, 2..40),
            at in 0usize..40,
            grasp in proptest::bool::ANY,
            left in proptest::bool::ANY,
        ) {
            let setup = crate::testing::setup("fig9-near.toml");
            let arm = if left { Arm::Left } else { Arm::Right };
            let v = setup.arm(arm).variables[0];
            let mut value = 0.0;
            let traj: Vec<TrajectoryPoint> = moves
                .iter()
                .enumerate()
                .map(|(i, &m)| {
                    if m {
                        value += 0.01;
                    }
                    let mut q = setup.start.clone();
                    q[v] += value;
                    TrajectoryPoint::positions_only(i as Real * 0.5, q)
                })
                .collect();
            let k = at % traj.len();
            let kind = if grasp { EventKind::Grasp } else { EventKind::Release };
            let event = Ev {
                time: traj[k].time_from_start,
                kind,
                arm,
                link_from_object: Isometry3::identity(),
            };
            let windows = closing_windows(setup, &traj, &[event]);
            proptest::prop_assert_eq!(windows.len(), 1);
            let (w, t0, t1) = windows[0];
            proptest::prop_assert_eq!(w, arm);
            proptest::prop_assert!(t0 <= t1);
            let at_event = if grasp { t1 } else { t0 };
            proptest::prop_assert_eq!(at_event, event.time);
            let here = traj[k].positions[v];
            for p in &traj {
                let inside = p.time_from_start >= t0 && p.time_from_start <= t1;
                if inside {
                    proptest::prop_assert_eq!(p.positions[v], here);
                }
            }
            let before = traj.iter().rposition(|p| p.time_from_start < t0);
            let after = traj.iter().position(|p| p.time_from_start > t1);
            if let Some(b) = before.filter(|_| grasp) {
                proptest::prop_assert!(traj[b].positions[v] != here);
            }
            if let Some(a) = after.filter(|_| !grasp) {
                proptest::prop_assert!(traj[a].positions[v] != here);
            }
        }
    }

    /// The can upright with its base centre at `(x, y, z)`.
    fn can_at(setup: &Setup, x: Real, y: Real, z: Real) -> Isometry3 {
        let start = setup.object_start;
        let t = start.translation.vector;
        Translation3::new(x - t.x, y - t.y, z - t.z) * start
    }

    fn rest_problems(x: Real, z: Real) -> (Vec<String>, Option<Real>) {
        let setup = crate::testing::setup("fig9-near.toml");
        let mut v = Validator::new(setup).expect("validator");
        let margin = v.rest_check(1.0, &can_at(setup, x, -0.25, z), "the placed object");
        (v.problems, margin)
    }

    #[test]
    fn a_resting_pose_must_stand_on_a_support_without_penetrating_or_tipping() {
        // The pallet's top is at z = 0.76, its edge at x = 0.30.
        let (problems, margin) = rest_problems(0.36, 0.76);
        assert!(problems.is_empty(), "{problems:?}");
        assert!(margin.is_some_and(|m| m > 0.02), "{margin:?}");
        // Overhanging the edge: the CoG 1 cm beyond it.
        let (problems, margin) = rest_problems(0.29, 0.76);
        assert!(margin.is_some_and(|m| m < 0.0), "{margin:?}");
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].contains("the placed object is unstable"),
            "{problems:?}"
        );
        // In mid-air.
        let (problems, margin) = rest_problems(0.36, 0.80);
        assert_eq!(margin, None);
        assert_eq!(problems.len(), 1, "{problems:?}");
        assert!(
            problems[0].contains("does not rest on a support"),
            "{problems:?}"
        );
        // Sunk 5 mm into the pallet.
        let (problems, _) = rest_problems(0.36, 0.755);
        assert!(
            problems
                .iter()
                .any(|p| p.contains("penetrates the environment")),
            "{problems:?}"
        );
    }

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
