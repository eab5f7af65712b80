//! Issue 33: a plan states each arm's tool link (its URDF parent and `parent_from_tool`), and
//! that frame is the one its poses are in: read with the URDF alone, as an executor would.

use crate::{plan_with_threads, root, setup};
use pickplace::robot::{LoadOptions, RobotModel};
use pickplace::{Arm, Plan, Setup};

/// Every key pose where the robot is at rest (grasps, releases, …), by every arm of the
/// strategy: the URDF's forward kinematics of the stated parent link at the plan's state,
/// composed with the stated `parent_from_tool`, is the key pose's `world_from_tcp`.
fn check_tool_frames(setup: &Setup, plan: &Plan) {
    let urdf = RobotModel::from_urdf_file(
        &root().join("robots/nx-hiro/nx-hiro.urdf"),
        &LoadOptions::default(),
    )
    .expect("the URDF loads");
    let columns: Vec<usize> = urdf
        .variable_names()
        .map(|n| {
            plan.joint_names
                .iter()
                .position(|j| j == n)
                .expect("every URDF variable is a joint of the plan")
        })
        .collect();
    // Both arms' tool frames are stated (a handover uses both).
    assert_eq!(plan.arms.len(), 2);
    for a in &plan.arms {
        let tool = a.tool.as_ref().expect("the plan states the tool frame");
        assert!(urdf.link_index(&tool.parent).is_some(), "{tool:?}");
        assert!(urdf.link_index(&tool.link).is_none(), "{tool:?}");
        for e in plan.events.iter().filter(|e| e.arm == a.arm) {
            assert_eq!(e.link, tool.link);
        }
    }
    let mut checked: Vec<(Arm, &str)> = Vec::new();
    for k in &plan.key_poses {
        let sample = plan
            .trajectory
            .iter()
            .find(|p| (p.time_from_start - k.time).abs() < 1e-9)
            .expect("a key pose is at a sample");
        if sample.velocities.iter().any(|&v| v != 0.0) {
            continue; // passed moving on a blend: `world_from_tcp` is as planned
        }
        let tool = plan
            .arms
            .iter()
            .find(|a| a.arm == k.arm)
            .and_then(|a| a.tool.as_ref())
            .expect("the key pose's arm has a tool frame");
        let q: Vec<f64> = columns.iter().map(|&c| sample.positions[c]).collect();
        let parent = urdf.link_index(&tool.parent).expect("a URDF link");
        let world_from_tcp = setup.world_from_root
            * urdf.link_poses(&q).expect("fk")[parent]
            * tool.parent_from_tool.to_isometry().expect("a pose");
        let planned = k.world_from_tcp.to_isometry().expect("a pose");
        let gap = world_from_tcp.inverse() * planned;
        assert!(
            gap.translation.vector.norm() < 1e-9 && gap.rotation.angle() < 1e-9,
            "{} by the {} arm: {} m, {} rad",
            k.name,
            k.arm,
            gap.translation.vector.norm(),
            gap.rotation.angle()
        );
        checked.push((k.arm, &k.name));
    }
    for arm in plan.strategy.arms() {
        assert!(
            checked
                .iter()
                .any(|(a, name)| *a == arm && name.ends_with("grasp")),
            "no grasp of the {arm} arm checked: {checked:?}"
        );
    }
}

#[test]
fn the_stated_tool_frame_is_the_frame_of_world_from_tcp() {
    for (scene, handover) in [("fig9-near.toml", false), ("fig9-far-left.toml", true)] {
        let setup = setup(scene);
        let plan = plan_with_threads(&setup, 2);
        assert_eq!(plan.strategy.has_handover(), handover, "{scene}");
        check_tool_frames(&setup, &plan);
        // The plan file says the same.
        let back = Plan::from_json(&plan.to_json()).expect("reads back");
        assert_eq!(back.arms, plan.arms);
        check_tool_frames(&setup, &back);
    }
}

#[test]
fn a_plan_without_tool_frames_still_reads_and_a_contradicting_one_is_refused() {
    let setup = setup("fig9-near.toml");
    let plan = plan_with_threads(&setup, 2);
    let mut old = plan.clone();
    for a in &mut old.arms {
        a.tool = None;
    }
    let json = old.to_json();
    assert!(!json.contains("parent_from_tool"));
    assert_eq!(
        Plan::from_json(&json).expect("a plan of before issue 33"),
        old
    );
    assert_eq!(old.check_form(), Ok(()));
    let mut zero = plan.clone();
    zero.arms[1]
        .tool
        .as_mut()
        .expect("tool")
        .parent_from_tool
        .orientation = [0.0; 4];
    let err = Plan::from_json(&zero.to_json()).expect_err("a zero quaternion");
    assert!(err.starts_with("arms[1].tool.parent_from_tool:"), "{err}");
    let mut other = plan.clone();
    other.arms[0].tool.as_mut().expect("tool").link = "RARM_JOINT5_Link".into();
    let err = other
        .check_form()
        .expect_err("the events name another link");
    assert!(
        err.contains("is not the right arm's tool link \"RARM_JOINT5_Link\""),
        "{err}"
    );
}

#[test]
fn the_ros2_export_states_each_moving_arms_tool_frame() {
    let setup = setup("fig9-far-left.toml");
    let plan = plan_with_threads(&setup, 2);
    let messages = pickplace::export::joint_trajectories(&plan).expect("exports");
    for m in &messages {
        let a = plan.arms.iter().find(|a| a.arm == m.arm).expect("an arm");
        let tool = a.tool.as_ref().expect("a tool frame");
        let t = m.tool_frame.as_ref().expect("the message's tool frame");
        assert_eq!(t.header.frame_id, tool.parent);
        assert_eq!(t.child_frame_id, tool.link);
        let [x, y, z] = tool.parent_from_tool.position;
        let [qx, qy, qz, qw] = tool.parent_from_tool.orientation;
        let tr = t.transform;
        assert_eq!(
            [tr.translation.x, tr.translation.y, tr.translation.z],
            [x, y, z]
        );
        assert_eq!(
            [tr.rotation.x, tr.rotation.y, tr.rotation.z, tr.rotation.w],
            [qx, qy, qz, qw]
        );
        let json = serde_json::to_value(m).expect("json");
        assert_eq!(json["tool_frame"]["child_frame_id"], tool.link.as_str());
    }
    // The YAML stream starts with one comment per arm that moves (both, in a handover).
    let comments = pickplace::tool_frame::yaml_comments(&plan, &messages);
    for a in &plan.arms {
        let tool = a.tool.as_ref().expect("a tool frame");
        assert!(
            comments.contains(&format!(
                "# tool frame of the {} arm (link of link_from_object and world_from_tcp): {:?} in {:?} at position [",
                a.arm, tool.link, tool.parent
            )),
            "{comments}"
        );
        assert!(
            comments.contains(&format!(
                "--frame-id {} --child-frame-id {}\n",
                tool.parent, tool.link
            )),
            "{comments}"
        );
    }
    assert_eq!(comments.lines().count(), 4);
    assert!(comments.lines().all(|l| l.starts_with('#')));
}
