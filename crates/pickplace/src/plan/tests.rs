//! Unit tests of the plan's form and playback.

use super::*;

use crate::strategy::Strategy;

fn event(time: Real, kind: EventKind, link: &str) -> Event {
    Event {
        time,
        kind,
        arm: Arm::Right,
        link: link.into(),
        link_from_object: PoseSpec::from_isometry(&Isometry3::identity()),
    }
}

fn plan(events: Vec<Event>) -> Plan {
    let pose = PoseSpec::from_isometry(&Isometry3::identity());
    Plan {
        format: PLAN_FORMAT.into(),
        seed: 1,
        strategy: Strategy::RightLeft,
        joint_names: vec!["a".into(), "b".into()],
        base: None,
        arms: vec![],
        limits: None,
        trajectory: vec![],
        events,
        object: ObjectMotion {
            start_pose: pose,
            placed_pose: pose,
        },
        placement: PlacementInfo {
            contact: "face-face".into(),
            object_cluster: 0,
            environment: "table".into(),
            env_cluster: 0,
            stability_margin: 0.01,
            rank: 0,
        },
        rests: vec![],
        grasps: vec![],
        key_poses: vec![],
        stats: Stats::default(),
        warnings: Vec::new(),
    }
}

#[test]
fn a_handover_is_two_overlapping_holds() {
    let p = plan(vec![
        event(5.0, EventKind::Release, "R"),
        event(1.0, EventKind::Grasp, "R"),
        event(4.0, EventKind::Grasp, "L"),
        event(9.0, EventKind::Release, "L"),
    ]);
    let holds = p.holds().expect("consistent");
    let spans: Vec<_> = holds
        .iter()
        .map(|h| (h.link.as_str(), h.grasp_time, h.release_time))
        .collect();
    assert_eq!(spans, [("R", 1.0, Some(5.0)), ("L", 4.0, Some(9.0))]);
    let bad = plan(vec![event(1.0, EventKind::Release, "R")]);
    assert_eq!(
        bad.holds().unwrap_err(),
        "event 0: release by \"R\" without a grasp before it".into()
    );
}

#[test]
fn motions_end_where_the_robot_stops() {
    // Joint a moves from 0 to 4 over samples 0..=8; the velocities are 0 at 0, 3 (a
    // corner that was not blended), 5 (a grasp) and 8.
    let mut p = plan(vec![event(5.0, EventKind::Grasp, "R")]);
    p.trajectory = (0..=8)
        .map(|k| {
            let mut s =
                TrajectoryPoint::positions_only(f64::from(k), vec![0.5 * f64::from(k), 0.0]);
            let moving = ![0, 3, 5, 8].contains(&k);
            s.velocities = vec![if moving { 0.5 } else { 0.0 }, 0.0];
            s.accelerations = vec![0.0; 2];
            s
        })
        .collect();
    let key = |name: &str, time: Real| KeyPose {
        name: name.into(),
        arm: Arm::Right,
        time,
        world_from_tcp: p.object.start_pose,
        world_from_object: p.object.start_pose,
    };
    // "pre-grasp" is passed moving (sample 2): no cut; "lift" is at a stop (sample 8).
    p.key_poses = vec![key("pre-grasp", 2.0), key("lift", 8.0)];
    let cuts = |p: &Plan| -> Vec<(usize, usize, String)> {
        p.motions()
            .into_iter()
            .map(|m| (m.first, m.last, m.to))
            .collect()
    };
    let s = |x: &str| x.to_owned();
    assert_eq!(
        cuts(&p),
        [
            (0, 3, s("stop")),
            (3, 5, s("grasp (right)")),
            (5, 8, s("lift"))
        ]
    );
    // Without velocities (format 1) every key pose is a stop.
    for point in &mut p.trajectory {
        point.velocities.clear();
        point.accelerations.clear();
    }
    assert_eq!(
        cuts(&p),
        [
            (0, 2, s("pre-grasp")),
            (2, 5, s("grasp (right)")),
            (5, 8, s("lift"))
        ]
    );
}

/// A direct right-hand plan of the documented form.
fn direct() -> Plan {
    let pose = PoseSpec::from_isometry(&Isometry3::identity());
    let mut p = plan(vec![
        event(1.0, EventKind::Grasp, "R"),
        event(2.0, EventKind::Release, "R"),
    ]);
    p.strategy = Strategy::RightRight;
    p.trajectory = (0..4)
        .map(|k| TrajectoryPoint::positions_only(f64::from(k), vec![0.0, 0.0]))
        .collect();
    p.grasps = vec![GraspInfo {
        arm: Arm::Right,
        object_from_tcp: pose,
        width: 0.05,
        score: 1.0,
        rank: 0,
    }];
    p.key_poses = [
        "pre-grasp",
        "grasp",
        "lift",
        "pre-place",
        "place",
        "release",
        "retreat",
    ]
    .iter()
    .enumerate()
    .map(|(k, name)| KeyPose {
        name: (*name).into(),
        arm: Arm::Right,
        time: 0.5 * k as f64,
        world_from_tcp: pose,
        world_from_object: pose,
    })
    .collect();
    p
}

/// `direct()` with `fault` applied breaks exactly the rule whose message holds `expected`.
fn check(fault: impl Fn(&mut Plan), expected: &str) {
    let mut p = direct();
    fault(&mut p);
    let e = p.check_form().expect_err(expected);
    assert!(e.reason().contains(expected), "`{expected}` not in: {e}");
}

#[test]
fn every_rule_of_the_plan_form_is_checked() {
    assert_eq!(direct().check_form(), Ok(()));
    check(|p| p.trajectory.clear(), "trajectory: empty");
    check(
        |p| {
            p.trajectory.remove(0);
        },
        "trajectory[0]: time_from_start 1 s, the trajectory starts at time 0",
    );
    check(
        |p| p.events[0].time = -1.0,
        "events[0]: time -1 s is not a finite time",
    );
    check(
        |p| p.events[1].time = f64::INFINITY,
        "events[1]: time inf s is not a finite time",
    );
    check(
        |p| p.events[1].time = 0.5,
        "events[1]: before the event above it",
    );
    check(
        |p| p.events[0].arm = Arm::Left,
        "events[0]: arm left is not an arm of the strategy right-right",
    );
    check(
        |p| p.events.insert(1, event(1.5, EventKind::Grasp, "R")),
        "events[1]: grasp by \"R\", which already holds the object",
    );
    check(
        |p| p.events.insert(0, event(0.5, EventKind::Release, "R")),
        "events[0]: release by \"R\" without a grasp before it",
    );
    check(
        |p| {
            p.strategy = Strategy::LeftRight;
            p.grasps.insert(0, p.grasps[0].clone());
            p.grasps[0].arm = Arm::Left;
        },
        "events: the first grasp is by the right arm, the strategy left-right picks with the left arm",
    );
    check(
        |p| {
            p.strategy = Strategy::RightLeft;
            p.grasps.push(p.grasps[0].clone());
            p.grasps[1].arm = Arm::Left;
        },
        "events: the last release is by the right arm, the strategy right-left places with the left arm",
    );
    check(
        |p| p.grasps.clear(),
        "grasps: 0 given, the strategy right-right uses 1",
    );
    check(
        |p| p.grasps[0].width = f64::NAN,
        "grasps[0]: a non-finite width or score",
    );
    check(
        |p| {
            p.strategy = Strategy::RightPlaceRight;
            p.grasps.push(p.grasps[0].clone());
        },
        "rests: 0 given",
    );
    check(
        |p| {
            p.rests.push(RestInfo {
                world_from_object: p.object.start_pose,
                placement: p.placement.clone(),
            })
        },
        "rests: 1 given",
    );
    check(
        |p| p.placement.contact = "x".repeat(1000),
        "placement.contact: \"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx…\" is neither",
    );
    check(
        |p| p.placement.stability_margin = f64::INFINITY,
        "placement.stability_margin: not a finite number",
    );
    check(
        |p| p.key_poses[2].name = "jump".into(),
        "key_poses[2]: \"jump\" is not a key pose name",
    );
    check(
        |p| p.key_poses.swap(2, 3),
        "key_poses[3]: before the key pose above it",
    );
    check(
        |p| p.key_poses[0].time = f64::NAN,
        "key_poses[0]: time NaN s",
    );
    check(
        |p| p.key_poses[6].arm = Arm::Left,
        "key_poses[6]: arm left is not an arm",
    );
}

#[test]
fn columns_map_a_robot_order_to_the_plan_order() {
    let p = plan(vec![]);
    assert_eq!(p.columns(&["b", "a"]).expect("the same joints"), [1, 0]);
    assert_eq!(
        p.columns(&["a", "c"]).unwrap_err(),
        "missing [\"c\"], unknown [\"b\"]".into()
    );
}
