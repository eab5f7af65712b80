//! The validator, rule by rule (issue 17: "the project's promise that a plan is safe"): a
//! valid plan of a shipped scene validates with no problem; each test injects exactly one
//! fault that breaks no other rule and asserts that the validator reports that rule, and
//! only that one.

use pickplace::geometry::math::{Isometry3, Real, Translation3, Vector3};
use pickplace::plan::{EventKind, TrajectoryPoint};
use pickplace::planner::{Outcome, PlanOptions};
use pickplace::robot::collision::CollisionScratch;
use pickplace::robot::gripper::GripObject;
use pickplace::robot::ik::IkOptions;
use pickplace::scene::PoseSpec;
use pickplace::validate::{HAND_CLEARANCE, HandClearance, ValidationReport, validate};
use pickplace::{Arm, Plan, Setup, SetupOptions};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

mod cost;
mod frames;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// A fresh setup of a shipped scene (the tests that change the scene own theirs).
fn load(scene: &str) -> Setup {
    let options = SetupOptions {
        cache_dir: Some(Path::new(env!("CARGO_TARGET_TMPDIR")).join("validate-cache")),
        ..SetupOptions::default()
    };
    Setup::load(&root().join("scenes").join(scene), &options).expect("shipped scene sets up")
}

fn plan_of(setup: &Setup) -> Plan {
    let options = PlanOptions {
        timings: false,
        ..PlanOptions::for_setup(setup)
    };
    match pickplace::plan(setup, &options).expect("plans") {
        Outcome::Planned(plan) => *plan,
        Outcome::NoPlan(f) => panic!("no plan: {:?}", f.reasons),
    }
}

/// The direct plan of `fig9-near` (right hand picks and places), planned once.
fn near() -> &'static (Setup, Plan) {
    static NEAR: OnceLock<(Setup, Plan)> = OnceLock::new();
    NEAR.get_or_init(|| {
        let setup = load("fig9-near.toml");
        let plan = plan_of(&setup);
        (setup, plan)
    })
}

/// The handover plan of `fig9-far-left`, planned once.
fn handover() -> &'static (Setup, Plan) {
    static FAR: OnceLock<(Setup, Plan)> = OnceLock::new();
    FAR.get_or_init(|| {
        let setup = load("fig9-far-left.toml");
        let plan = plan_of(&setup);
        assert!(plan.strategy.has_handover(), "{:?}", plan.strategy);
        (setup, plan)
    })
}

fn check(setup: &Setup, plan: &Plan) -> ValidationReport {
    validate(setup, plan, Path::new("plan.json")).expect("the plan fits the robot")
}

/// The report has problems, and every one of them is of the rule named by `needle`.
fn only(report: &ValidationReport, needle: &str) {
    assert!(
        !report.problems.is_empty(),
        "expected a problem with {needle:?}, the plan passed"
    );
    assert!(
        report.problems.iter().all(|p| p.contains(needle)),
        "expected only {needle:?}: {:#?}",
        report.problems
    );
}

/// `plan` with a detour inserted after its first sample: from the start state to `via` and
/// back, at `speed` times the joints' velocity limits (the rest of the plan is delayed).
fn with_detour(setup: &Setup, plan: &Plan, via: &[Real], speed: Real) -> Plan {
    with_path(setup, plan, &[via.to_vec()], speed)
}

/// `plan` with a detour inserted after its first sample: through `path` and back the same way
/// to the start state, each segment at `speed` times the joints' velocity limits.
fn with_path(setup: &Setup, plan: &Plan, path: &[Vec<Real>], speed: Real) -> Plan {
    let q0 = plan.trajectory[0].positions.clone();
    let limits: Vec<_> = setup.model.variable_limits().copied().collect();
    let segment = |a: &[Real], b: &[Real]| {
        limits
            .iter()
            .zip(a.iter().zip(b))
            .filter(|(l, _)| l.velocity > 0.0)
            .map(|(l, (a, b))| (b - a).abs() / (speed * l.velocity))
            .fold(1e-3, Real::max)
    };
    let mut states = vec![q0.clone()];
    states.extend(path.iter().cloned());
    states.extend(path.iter().rev().skip(1).cloned());
    let mut points = Vec::new();
    let mut t = 0.0;
    for (k, q) in states.iter().enumerate() {
        if k > 0 {
            t += segment(&states[k - 1], q);
        }
        points.push(TrajectoryPoint::positions_only(t, q.clone()));
    }
    let shift = t + segment(&states[states.len() - 1], &q0);
    let mut out = plan.clone();
    for p in &mut out.trajectory {
        p.time_from_start += shift;
    }
    for e in &mut out.events {
        e.time += shift;
    }
    for k in &mut out.key_poses {
        k.time += shift;
    }
    out.trajectory.splice(0..0, points);
    out
}

/// The arm that never moves the object in the direct plan.
fn idle_arm(plan: &Plan) -> Arm {
    plan.events[0].arm.other()
}

#[test]
fn a_valid_plan_has_no_problem() {
    let (setup, plan) = near();
    let report = check(setup, plan);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    assert!(report.stability_margin.expect("rests on the pallet") > 0.0);
    assert!(report.states_checked > plan.trajectory.len());
}

#[test]
fn the_handover_plan_breaks_no_rule() {
    // The planner keeps HAND_CLEARANCE at the handover (the same check as the validator's),
    // and every other rule holds, including the second hand's touch window.
    let (setup, plan) = handover();
    let report = check(setup, plan);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    assert!(report.stability_margin.expect("rests on the pallet") > 0.0);
    // The second hand's pads touch the object (they squeeze it) in its closing motion, before
    // its grasp event, while the first hand holds it: accepted, it is its touch window.
    let second = plan
        .events
        .iter()
        .filter(|e| e.kind == EventKind::Grasp)
        .nth(1)
        .expect("the handover grasp");
    let i = sample_at(plan, second.time);
    let q = &plan.trajectory[i].positions;
    let world_from_links: Vec<Isometry3> = setup
        .model
        .link_poses(q)
        .expect("fk")
        .into_iter()
        .map(|p| setup.world_from_root * p)
        .collect();
    let tcp = setup.world_from_root * setup.arm(second.arm).ik.chain().pose(q);
    let object = tcp * second.link_from_object.to_isometry().expect("pose");
    let grip = GripObject::new(&setup.object_mesh).expect("grip object");
    let gaps = setup
        .arm(second.arm)
        .gripper
        .finger_gaps(&world_from_links, &grip, &object)
        .expect("gaps");
    assert!(gaps.iter().all(|&g| g <= 5e-5), "{gaps:?}");
}

#[test]
fn a_forearm_driven_slowly_through_the_table_is_caught_between_samples() {
    let (setup, plan) = near();
    let q0 = plan.trajectory[0].positions.clone();
    let mut world = setup.world.clone();
    world.add_environment("object", setup.object_shape.clone(), &setup.object_start);
    let mut scratch = CollisionScratch::default();
    let limits: Vec<_> = setup.model.variable_limits().copied().collect();
    let table_only = |q: &[Real], scratch: &mut CollisionScratch| -> Option<bool> {
        // None: a collision with something other than the table; Some(hit): the table or not.
        let pairs = world
            .colliding_pairs(&setup.model, q, scratch, &Default::default())
            .expect("query");
        if pairs
            .iter()
            .any(|&(a, b)| world.body_name(a) != "table" && world.body_name(b) != "table")
        {
            return None;
        }
        Some(!pairs.is_empty())
    };
    // A swing of one or two joints of the idle arm whose ends are both free but whose
    // straight line in joint space passes through the table.
    let arm = setup.arm(idle_arm(plan));
    let joints: Vec<usize> = arm.variables.clone();
    let mut found = None;
    'search: for &j in &joints {
        for &k in &joints {
            for step in 1..=12 {
                for sign in [-1.0, 1.0] {
                    for ratio in [0.0, 0.5, 1.0] {
                        let mut via = q0.clone();
                        via[j] += sign * 0.2 * step as Real;
                        if k != j {
                            via[k] += sign * ratio * 0.2 * step as Real;
                        } else if ratio > 0.0 {
                            continue;
                        }
                        if via.iter().zip(&limits).any(|(x, l)| !l.contains(*x, 0.0)) {
                            continue;
                        }
                        if table_only(&via, &mut scratch) != Some(false) {
                            continue;
                        }
                        // Through the table, not grazing it: a fifth of the swing inside.
                        let mut hits = 0;
                        let mut clean = true;
                        for s in 1..100 {
                            let f = s as Real / 100.0;
                            let q: Vec<Real> =
                                q0.iter().zip(&via).map(|(a, b)| a + f * (b - a)).collect();
                            match table_only(&q, &mut scratch) {
                                None => clean = false,
                                Some(h) => hits += usize::from(h),
                            }
                        }
                        if hits >= 20 && clean {
                            found = Some(via);
                            break 'search;
                        }
                    }
                }
            }
        }
    }
    let via = found.expect("a swing of the idle arm through the table");
    let faulty = with_detour(setup, plan, &via, 0.5);
    let report = check(setup, &faulty);
    only(&report, "/ table");
    assert!(
        report.problems[0].contains("collision"),
        "{:?}",
        report.problems
    );
}

#[test]
fn an_unstable_final_pose_is_refused() {
    // The placed can would tip over: its centre of mass (as the scene says) lies 2 mm
    // beyond the rim of its base, within the target's tolerance.
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    let report = check(&setup, plan);
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    let radius = setup
        .object_mesh
        .vertices()
        .iter()
        .map(|p| (p.x - setup.cog.x).hypot(p.y - setup.cog.y))
        .fold(0.0, Real::max);
    setup.cog.x += radius + 0.002;
    let report = check(&setup, plan);
    only(&report, "the placed object is unstable");
}

/// The first sample at or after `time`.
fn sample_at(plan: &Plan, time: Real) -> usize {
    plan.trajectory
        .iter()
        .position(|p| p.time_from_start >= time - 1e-9)
        .expect("a sample at the event")
}

#[test]
fn a_release_in_mid_air_is_refused() {
    // Halfway through the transport the hand lets go and grasps again at once: the object
    // is left in mid-air for an instant.
    let (setup, plan) = near();
    let (grasp, release) = (&plan.events[0], &plan.events[1]);
    let middle = (sample_at(plan, grasp.time) + sample_at(plan, release.time)) / 2;
    let t = plan.trajectory[middle].time_from_start;
    let mut faulty = plan.clone();
    let mut let_go = grasp.clone();
    let_go.kind = EventKind::Release;
    let_go.time = t;
    let mut again = grasp.clone();
    again.time = t;
    faulty.events.splice(1..1, [let_go, again]);
    let mut report = check(setup, &faulty);
    // The hand also opens and closes with the arm moving: that rule's problems aside, the
    // object in mid-air is the only one.
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("not at rest at the right hand's release"))
    );
    report
        .problems
        .retain(|p| !p.contains("not at rest at the right hand's"));
    only(
        &report,
        "the object left by the right hand does not rest on a support",
    );
}

#[test]
fn a_plan_ending_with_the_object_held_is_refused() {
    // The plan stops at the release sample and never releases.
    let (setup, plan) = near();
    let release = plan
        .events
        .iter()
        .rposition(|e| e.kind == EventKind::Release);
    let release = release.expect("a release");
    let mut faulty = plan.clone();
    let last = sample_at(plan, faulty.events[release].time);
    faulty.events.remove(release);
    faulty.trajectory.truncate(last + 1);
    let end = faulty.trajectory[last].time_from_start;
    faulty.key_poses.retain(|k| k.time <= end + 1e-9);
    let report = check(setup, &faulty);
    only(&report, "the object is still held at the end");
}

#[test]
fn a_grip_that_does_not_touch_is_refused() {
    // While the object is carried, the fingers stand 5.5 mm wider apart than the grasp
    // (opened and closed again smoothly over half a second each way, within the fingers'
    // limits, velocities and accelerations consistent with the positions).
    let (setup, plan) = near();
    let (grasp, release) = (&plan.events[0], &plan.events[1]);
    let arm = setup.arm(grasp.arm);
    let width = plan.grasps[0].width;
    let mut faulty = plan.clone();
    let (g, r) = (grasp.time, release.time);
    // Each finger variable's offset at time t.
    let offset = |q: &[Real], t: Real| -> Vec<Real> {
        let x = ((t - g) / 0.5).min((r - t) / 0.5).clamp(0.0, 1.0);
        let ease = x * x * (3.0 - 2.0 * x);
        let (mut wide, mut tight) = (q.to_vec(), q.to_vec());
        arm.gripper.set_opening(&mut wide, width + ease * 0.0055);
        arm.gripper.set_opening(&mut tight, width);
        arm.finger_variables
            .iter()
            .map(|&v| wide[v] - tight[v])
            .collect()
    };
    let h = 1e-4;
    for p in &mut faulty.trajectory {
        let t = p.time_from_start;
        if t > g + 1e-9 && t < r - 1e-9 {
            let q = p.positions.clone();
            let (before, at, after) = (offset(&q, t - h), offset(&q, t), offset(&q, t + h));
            for (k, &v) in arm.finger_variables.iter().enumerate() {
                p.positions[v] += at[k];
                p.velocities[v] += (after[k] - before[k]) / (2.0 * h);
                p.accelerations[v] += (after[k] - 2.0 * at[k] + before[k]) / (h * h);
            }
        }
    }
    let report = check(setup, &faulty);
    only(&report, "the grip does not close");
}

#[test]
fn a_squeeze_ramped_in_while_the_hand_rests_is_refused() {
    // Issue 32: right after the grasp, with the arm at rest, the fingers close 6 mm past the
    // grasp and open again over two seconds (a pause inserted there, smoothly, within the
    // fingers' limits), then the plan goes on. The pads may press in by the squeeze and no
    // more, at every instant the hand holds the object, not only while it moves.
    let (setup, plan) = near();
    let grasp = &plan.events[0];
    let arm = setup.arm(grasp.arm);
    let width = plan.grasps[0].width;
    let i = sample_at(plan, grasp.time);
    let at_grasp = plan.trajectory[i].clone();
    assert!(
        at_grasp.velocities.iter().all(|v| v.abs() < 1e-9),
        "at rest"
    );
    let pause = 2.0;
    let offset = |t: Real| -> Vec<Real> {
        let x = (t / (pause / 2.0))
            .min((pause - t) / (pause / 2.0))
            .clamp(0.0, 1.0);
        let ease = x * x * (3.0 - 2.0 * x);
        let (mut tight, mut held) = (at_grasp.positions.clone(), at_grasp.positions.clone());
        arm.gripper.set_opening(&mut tight, width - ease * 0.006);
        arm.gripper.set_opening(&mut held, width);
        arm.finger_variables
            .iter()
            .map(|&v| tight[v] - held[v])
            .collect()
    };
    let h = 1e-4;
    let mut faulty = plan.clone();
    let mut inserted = Vec::new();
    let steps = 40;
    for k in 1..steps {
        let t = pause * k as Real / steps as Real;
        let mut p = at_grasp.clone();
        p.time_from_start = at_grasp.time_from_start + t;
        let (before, now, after) = (offset(t - h), offset(t), offset(t + h));
        for (c, &v) in arm.finger_variables.iter().enumerate() {
            p.positions[v] += now[c];
            p.velocities[v] = (after[c] - before[c]) / (2.0 * h);
            p.accelerations[v] = (after[c] - 2.0 * now[c] + before[c]) / (h * h);
        }
        inserted.push(p);
    }
    for p in &mut faulty.trajectory[i + 1..] {
        p.time_from_start += pause;
    }
    let mut later = faulty.trajectory.split_off(i + 1);
    faulty.trajectory.extend(inserted);
    faulty.trajectory.append(&mut later);
    for e in &mut faulty.events[1..] {
        e.time += pause;
    }
    for k in &mut faulty.key_poses {
        if k.time > grasp.time + 1e-9 {
            k.time += pause;
        }
    }
    // The same plan with the pause and no squeeze is valid: the pause alone breaks nothing.
    let mut paused = faulty.clone();
    for p in &mut paused.trajectory[i + 1..i + steps] {
        p.positions.clone_from(&at_grasp.positions);
        p.velocities.clone_from(&at_grasp.velocities);
        p.accelerations.clone_from(&at_grasp.accelerations);
    }
    let report = check(setup, &paused);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    let report = check(setup, &faulty);
    only(&report, "inside the object");
}

#[test]
fn a_hand_link_that_is_not_a_pad_must_not_touch_the_held_object() {
    // Issue 32: only the pads may touch a held object. Here one finger's pad links are no
    // longer pads for the validator: that finger presses into the object by the squeeze
    // while it is held, which is now a collision like any other link's.
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    let arm = plan.events[0].arm;
    let k = setup.arms.iter().position(|a| a.arm == arm).expect("arm");
    let pads = setup.arms[k].gripper.pad_links();
    let second: Vec<String> = pads[1]
        .iter()
        .map(|&l| setup.model.links()[l].name.clone())
        .collect();
    setup.arms[k].pad_links.retain(|l| !second.contains(l));
    let report = check(&setup, plan);
    assert!(!report.problems.is_empty(), "the plan passed");
    assert!(
        report
            .problems
            .iter()
            .all(|p| p.contains("held object") && second.iter().any(|l| p.contains(l.as_str()))),
        "{second:?}: {:#?}",
        report.problems
    );
}

/// The last joint of the idle arm (its wrist roll).
fn idle_wrist(setup: &Setup, plan: &Plan) -> usize {
    *setup
        .arm(idle_arm(plan))
        .variables
        .last()
        .expect("the arm has joints")
}

#[test]
fn a_joint_beyond_its_limit_is_refused() {
    let (setup, plan) = near();
    let j = idle_wrist(setup, plan);
    let limits: Vec<_> = setup.model.variable_limits().copied().collect();
    let mut via = plan.trajectory[0].positions.clone();
    via[j] = limits[j].upper + 0.02;
    let faulty = with_detour(setup, plan, &via, 0.5);
    let report = check(setup, &faulty);
    only(&report, "is outside its limits");
}

#[test]
fn a_value_far_outside_its_limits_is_reported_first_and_nothing_is_interpolated() {
    // Issue 18: 1e4 rad made the interpolation run for seconds, larger values for ever.
    let (setup, plan) = near();
    let j = idle_wrist(setup, plan);
    let mut faulty = plan.clone();
    faulty.trajectory[3].positions[j] = 1e300;
    faulty.trajectory[5].positions[j] = -1e4;
    let report = check(setup, &faulty);
    assert_eq!(report.states_checked, 0);
    assert_eq!(report.problems.len(), 1, "{:#?}", report.problems);
    let name = &plan.joint_names[j];
    assert!(
        report.problems[0].contains(&format!("{name} = 1.0000e300 is outside its limits [")),
        "{}",
        report.problems[0]
    );
    assert!(
        report.problems[0].contains("trajectory[3]"),
        "{}",
        report.problems[0]
    );
}

#[test]
fn a_trajectory_needing_too_many_checked_states_is_refused_before_checking() {
    // Every value within its limits, but the idle wrist swings from limit to limit at every
    // one of many samples: more than MAX_CHECKED_STATES states at 1° each.
    let (setup, plan) = near();
    let j = idle_wrist(setup, plan);
    let l = setup
        .model
        .variable_limits()
        .nth(j)
        .copied()
        .expect("limits");
    let per_swing = ((l.upper - l.lower) / pickplace::validate::MAX_JOINT_STEP).ceil() as usize;
    let samples = pickplace::validate::MAX_CHECKED_STATES / per_swing + 10;
    let mut faulty = plan.clone();
    let start = plan.trajectory[0].positions.clone();
    faulty.trajectory = (0..samples)
        .map(|i| {
            let mut q = start.clone();
            q[j] = if i % 2 == 0 { l.lower } else { l.upper };
            TrajectoryPoint::positions_only(i as Real, q)
        })
        .collect();
    let e = validate(setup, &faulty, Path::new("plan.json")).expect_err("too many states");
    let message = e.to_string();
    assert!(
        message.starts_with("plan.json: ") && message.contains("MAX_CHECKED_STATES"),
        "{message}"
    );
}

#[test]
fn negative_times_and_invalid_key_poses_do_not_fit() {
    let (setup, plan) = near();
    let mut faulty = plan.clone();
    for p in &mut faulty.trajectory {
        p.time_from_start -= 1.0;
    }
    let e = validate(setup, &faulty, Path::new("plan.json")).expect_err("negative time");
    assert!(
        e.to_string()
            .contains("trajectory[0]: time_from_start -1 s is negative"),
        "{e}"
    );
    let mut faulty = plan.clone();
    faulty.key_poses[1].world_from_object.orientation = [0.0; 4];
    let e = validate(setup, &faulty, Path::new("plan.json")).expect_err("zero quaternion");
    assert!(
        e.to_string()
            .contains("key_poses[1].world_from_object: orientation quaternion is zero"),
        "{e}"
    );
    let mut faulty = plan.clone();
    faulty.grasps[0].object_from_tcp.orientation[0] = Real::NAN;
    let e = validate(setup, &faulty, Path::new("plan.json")).expect_err("NaN");
    assert!(
        e.to_string()
            .contains("grasps[0].object_from_tcp: pose has a non-finite number"),
        "{e}"
    );
}

#[test]
fn a_joint_faster_than_its_limit_is_refused() {
    let (setup, plan) = near();
    let j = idle_wrist(setup, plan);
    let mut via = plan.trajectory[0].positions.clone();
    via[j] -= 0.2;
    let faulty = with_detour(setup, plan, &via, 2.0);
    let report = check(setup, &faulty);
    only(&report, "(limit ");
    // The same detour within the limits passes.
    let slow = with_detour(setup, plan, &via, 0.5);
    assert!(check(setup, &slow).problems.is_empty());
}

#[test]
fn time_going_backwards_is_refused() {
    let (setup, plan) = near();
    let (grasp, release) = (&plan.events[0], &plan.events[1]);
    let i = (sample_at(plan, grasp.time) + sample_at(plan, release.time)) / 2;
    let mut faulty = plan.clone();
    faulty.trajectory[i].time_from_start = plan.trajectory[i - 1].time_from_start - 0.01;
    let mut report = check(setup, &faulty);
    // The velocities no longer match the moved sample either.
    report
        .problems
        .retain(|p| !p.contains("positions and velocities disagree"));
    only(&report, "time goes backwards");
}

#[test]
fn a_grasp_where_the_object_is_not_is_refused() {
    // The scene puts the can 3 mm farther from the robot than the plan picks it.
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    setup.object_start = Translation3::new(0.003, 0.0, 0.0) * setup.object_start;
    let report = check(&setup, plan);
    only(&report, "from where the hand holds it");
}

#[test]
fn an_object_placed_away_from_the_target_is_refused() {
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    // 6 cm along the pallet (the point is then inside it; the pallet is still the surface).
    setup.scene.target.point[0] += 0.06;
    let report = check(&setup, plan);
    only(&report, "from the target point");
    // A plan for the scene whose click is 14 cm away (fig10a-edge's groove).
    setup.scene.target.point = [0.42, -0.34, 0.748];
    only(&check(&setup, plan), "from the target point");
    // Within a wider tolerance it passes.
    setup.scene.target.tolerance = Some(0.2);
    assert!(check(&setup, plan).problems.is_empty());
}

#[test]
fn an_object_placed_on_another_surface_than_the_target_is_refused() {
    // The click is on the table beside the pallet, and the tolerance wide enough to cover
    // the distance: the object stands on the pallet, not on the table.
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    setup.scene.target.point = [0.40, 0.0, 0.72];
    setup.scene.target.tolerance = Some(0.5);
    let report = check(&setup, plan);
    only(
        &report,
        "does not rest on \"table\", the surface of the target point",
    );
}

#[test]
fn a_trajectory_not_starting_at_the_start_state_is_refused() {
    let (_, plan) = near();
    let mut setup = load("fig9-near.toml");
    let j = idle_wrist(&setup, plan);
    setup.start[j] += 0.01;
    let report = check(&setup, plan);
    only(&report, "does not begin at the scene's start state");
}

#[test]
fn two_hands_passing_5_mm_apart_are_refused() {
    // The two hands are brought together (IK along the line between the two tool points,
    // each at its own orientation) until their links are 5 mm apart, and back.
    let (setup, plan) = near();
    let hands = HandClearance::new(setup)
        .expect("hand links")
        .expect("two arms");
    let mut scratch = CollisionScratch::default();
    let q0 = plan.trajectory[0].positions.clone();
    let tcp = |arm: Arm, q: &[Real]| setup.world_from_root * setup.arm(arm).ik.chain().pose(q);
    let (right, left) = (tcp(Arm::Right, &q0), tcp(Arm::Left, &q0));
    let toward: Vector3 = right.translation.vector - left.translation.vector;
    // Both hands move toward the point between them, each keeping its orientation.
    let solve = |f: Real, seed: &[Real]| -> Option<Vec<Real>> {
        let options = IkOptions {
            max_restarts: 0,
            ..IkOptions::default()
        };
        let mut q = seed.to_vec();
        for (arm, from, sign) in [(Arm::Left, &left, 0.5), (Arm::Right, &right, -0.5)] {
            let target = Isometry3::from_parts(
                Translation3::from(from.translation.vector + sign * f * toward),
                from.rotation,
            );
            let root_target = setup.world_from_root.inverse() * target;
            let s = setup.arm(arm).ik.solve(&root_target, &q, &options).ok()?;
            if !s.success {
                return None;
            }
            q = s.positions;
        }
        Some(q)
    };
    let gap = |q: &[Real], scratch: &mut CollisionScratch| {
        hands
            .distance(setup, q, scratch)
            .expect("distance")
            .distance
    };
    // Walk toward the right hand, then bisect to 5 mm.
    let (mut lo, mut hi) = (0.0, 0.0);
    let mut q_lo = q0.clone();
    let mut step_q = q0.clone();
    let mut path = Vec::new();
    for k in 1..=100 {
        let f = k as Real * 0.01;
        let q = solve(f, &step_q).expect("reachable beside the right hand");
        if gap(&q, &mut scratch) < 0.005 {
            hi = f;
            break;
        }
        lo = f;
        q_lo = q.clone();
        path.push(q.clone());
        step_q = q;
    }
    assert!(hi > 0.0, "the hands never came within 5 mm");
    let mut via = q_lo.clone();
    for _ in 0..30 {
        let mid = 0.5 * (lo + hi);
        let q = solve(mid, &q_lo).expect("reachable");
        let d = gap(&q, &mut scratch);
        via = q.clone();
        if (d - 0.005).abs() < 2e-4 {
            break;
        }
        if d > 0.005 {
            lo = mid;
            q_lo = q;
        } else {
            hi = mid;
        }
    }
    let d = gap(&via, &mut scratch);
    assert!((d - 0.005).abs() < 5e-4, "{d}");
    assert!(d < HAND_CLEARANCE);
    path.push(via);
    let faulty = with_path(setup, plan, &path, 0.5);
    let report = check(setup, &faulty);
    only(&report, "mm apart (hand clearance 10 mm)");
}

#[test]
fn a_plan_that_does_not_fit_is_an_error_not_a_list_of_problems() {
    let (setup, plan) = near();
    let mut faulty = plan.clone();
    faulty.events[0].link = "WAIST".into();
    let err = validate(setup, &faulty, Path::new("plan.json")).expect_err("refused");
    assert!(
        err.to_string().contains("is not the tool link of an arm"),
        "{err}"
    );
    let mut faulty = plan.clone();
    faulty.trajectory[3].positions[0] = Real::NAN;
    let err = validate(setup, &faulty, Path::new("plan.json")).expect_err("refused");
    assert!(err.to_string().contains("non-finite"), "{err}");
    let mut faulty = plan.clone();
    faulty.events[0].link_from_object = PoseSpec {
        orientation: [0.0; 4],
        ..PoseSpec::IDENTITY
    };
    assert!(validate(setup, &faulty, Path::new("plan.json")).is_err());
}

#[test]
fn a_robot_still_moving_at_a_grasp_is_refused() {
    // The sample after the grasp is moved 1 cm (rad) along: the hand would pass the grasp
    // without stopping there, though its velocities say 0.
    let (setup, plan) = near();
    let grasp = plan
        .events
        .iter()
        .find(|e| e.kind == pickplace::plan::EventKind::Grasp)
        .expect("a grasp");
    let i = sample_at(plan, grasp.time);
    let mut faulty = plan.clone();
    let j = setup.arm(pickplace::strategy::Arm::Right).variables[0];
    faulty.trajectory[i + 1].positions[j] += 0.01;
    let report = check(setup, &faulty);
    assert!(
        report.problems.iter().any(|p| p
            .contains("the robot is not at rest at the right hand's grasp")
            && p.contains("moves")),
        "{:#?}",
        report.problems
    );
}

/// Index of the joint that moves most in the plan (a joint of the arm that works).
fn busiest_joint(plan: &Plan) -> usize {
    let first = &plan.trajectory[0].positions;
    (0..first.len())
        .max_by(|&a, &b| {
            let travel = |j: usize| {
                plan.trajectory
                    .windows(2)
                    .map(|w| (w[1].positions[j] - w[0].positions[j]).abs())
                    .sum::<Real>()
            };
            travel(a).total_cmp(&travel(b))
        })
        .expect("joints")
}

#[test]
fn velocities_over_the_limit_are_reported() {
    let (setup, plan) = near();
    assert!(check(setup, plan).problems.is_empty());
    let j = busiest_joint(plan);
    let mut faulty = plan.clone();
    // One sample in the middle of a motion claims twice the joint's velocity limit.
    let i = (1..faulty.trajectory.len())
        .find(|&i| faulty.trajectory[i].velocities[j].abs() > 0.1)
        .expect("the joint moves");
    faulty.trajectory[i].velocities[j] = 2.0 * setup.timing[j].velocity;
    let report = check(setup, &faulty);
    assert!(
        report.problems.iter().any(|p| p.contains("over its limit")),
        "{:#?}",
        report.problems
    );
}

#[test]
fn positions_that_disagree_with_velocities_are_reported() {
    let (setup, plan) = near();
    let j = busiest_joint(plan);
    let mut faulty = plan.clone();
    // The velocities of one motion zeroed: the positions still change.
    for p in &mut faulty.trajectory {
        if p.velocities[j].abs() > 0.05 {
            p.velocities[j] = 0.0;
            p.accelerations[j] = 0.0;
        }
    }
    let report = check(setup, &faulty);
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("positions and velocities disagree")),
        "{:#?}",
        report.problems
    );
}

#[test]
fn a_hand_that_closes_while_the_arm_moves_is_reported() {
    let (setup, plan) = near();
    let mut faulty = plan.clone();
    let t = faulty.events[0].time;
    let i = faulty
        .trajectory
        .iter()
        .position(|p| (p.time_from_start - t).abs() < 1e-6)
        .expect("the grasp is at a sample");
    let j = busiest_joint(plan);
    faulty.trajectory[i].velocities[j] = 0.01;
    let report = check(setup, &faulty);
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("not at rest at the right hand's grasp")),
        "{:#?}",
        report.problems
    );
}

#[test]
fn the_timed_plans_keep_their_limits_and_stop_only_where_the_task_needs_it() {
    for (setup, plan) in [near(), handover()] {
        assert!(check(setup, plan).problems.is_empty());
        let events: Vec<Real> = plan.events.iter().map(|e| e.time).collect();
        let end = plan.trajectory.last().expect("samples").time_from_start;
        // The robot stops at the start, the end, and at grasps and releases (the fingers
        // close and open at rest), nowhere else: it passes the other key poses moving.
        // The columns of the fingers' joints.
        let fingers: Vec<usize> = plan
            .arms
            .iter()
            .flat_map(|a| &a.gripper_joints)
            .filter_map(|name| plan.joint_names.iter().position(|n| n == name))
            .collect();
        for (i, p) in plan.trajectory.iter().enumerate() {
            let at_rest = p.velocities.iter().all(|v| v.abs() < 1e-9);
            let t = p.time_from_start;
            // The event is where the fingers have closed (or opened); they start from rest
            // at the sample where only they move up to the event.
            let closing = events.iter().any(|&e| {
                let Some(k) = plan
                    .trajectory
                    .iter()
                    .position(|q| (q.time_from_start - e).abs() < 1e-6)
                else {
                    return false;
                };
                k >= i
                    && plan.trajectory[i..=k].iter().all(|q| {
                        q.positions
                            .iter()
                            .zip(&p.positions)
                            .enumerate()
                            .all(|(j, (a, b))| a == b || fingers.contains(&j))
                    })
            });
            let planned = t == 0.0 || t == end || closing;
            assert!(
                !at_rest || planned,
                "{:?}: the robot stops at {t} s",
                plan.strategy
            );
        }
        let passed = plan
            .key_poses
            .iter()
            .filter(|k| {
                let i = sample_at(plan, k.time);
                plan.trajectory[i].velocities.iter().any(|v| v.abs() > 1e-6)
            })
            .count();
        assert!(
            passed >= 3,
            "{:?}: {passed} key poses passed moving",
            plan.strategy
        );
    }
}

#[test]
fn straight_motions_stay_within_a_millimetre_of_their_line() {
    use pickplace::plan::KeyPose;
    for (setup, plan) in [near(), handover()] {
        let straight = [
            "grasp",
            "lift",
            "place",
            "retreat",
            "regrasp",
            "retreat-first",
        ];
        let keys: Vec<&KeyPose> = plan.key_poses.iter().collect();
        let mut checked = 0;
        for w in keys.windows(2) {
            let (a, b) = (w[0], w[1]);
            if !straight.contains(&b.name.as_str()) || a.arm != b.arm || a.time == b.time {
                continue;
            }
            let arm = setup.arm(b.arm);
            let tcp = |q: &[Real]| {
                (setup.world_from_root * arm.ik.chain().pose(q))
                    .translation
                    .vector
            };
            let samples: Vec<&TrajectoryPoint> = plan
                .trajectory
                .iter()
                .filter(|p| {
                    p.time_from_start >= a.time - 1e-9 && p.time_from_start <= b.time + 1e-9
                })
                .collect();
            // The line between the key poses as planned (the robot may pass through the
            // first one moving, on a blend).
            let pose = |k: &KeyPose| {
                k.world_from_tcp
                    .to_isometry()
                    .expect("a pose")
                    .translation
                    .vector
            };
            let (p0, p1) = (pose(a), pose(b));
            let line = p1 - p0;
            for s in &samples {
                let x = tcp(&s.positions) - p0;
                let f = (x.dot(&line) / line.norm_squared()).clamp(0.0, 1.0);
                let off = (x - line * f).norm();
                assert!(
                    off <= 1e-3 + 1e-9,
                    "{} → {}: {:.2} mm off the line",
                    a.name,
                    b.name,
                    off * 1e3
                );
            }
            checked += 1;
        }
        assert!(checked >= 3, "{checked} straight motions");
    }
}
