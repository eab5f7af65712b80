//! Issue 33: a plan states where the robot stands (`base`: its root link and
//! `world_from_root`) and each arm's tool link (its URDF parent and `parent_from_tool`), and
//! those are the frames its poses are in: read with the URDF alone, as an executor would.

use crate::{plan_with_threads, root, setup};
use pickplace::geometry::math::Isometry3;
use pickplace::plan::EventKind;
use pickplace::robot::{LoadOptions, RobotModel};
use pickplace::{Arm, Plan, Setup};

/// NX-HIRO's URDF, as an executor has it (no tool links).
fn urdf() -> RobotModel {
    RobotModel::from_urdf_file(
        &root().join("robots/nx-hiro/nx-hiro.urdf"),
        &LoadOptions::default(),
    )
    .expect("the URDF loads")
}

/// The distance (m) and angle (rad) between two poses.
fn gap(a: &Isometry3, b: &Isometry3) -> (f64, f64) {
    let g = a.inverse() * b;
    (g.translation.vector.norm(), g.rotation.angle())
}

/// Every key pose where the robot is at rest (grasps, releases, …), by every arm of the
/// strategy: the URDF's forward kinematics of the stated parent link at the plan's state,
/// placed by the stated base and composed with the stated `parent_from_tool`, is the key
/// pose's `world_from_tcp`.
fn check_tool_frames(setup: &Setup, plan: &Plan) {
    let urdf = urdf();
    let base = plan.base.as_ref().expect("the plan states the base");
    let (d, a) = gap(
        &base.world_from_root.to_isometry().expect("a pose"),
        &setup.world_from_root,
    );
    assert!(d < 1e-9 && a < 1e-9, "{base:?}");
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
        let world_from_tcp = base.world_from_root.to_isometry().expect("a pose")
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

/// The plan file alone and the URDF place the hand: at every grasp event, the stated
/// `world_from_root` (the scene's `robot.base_pose`: NX-HIRO's WAIST 0.92 m up) · the URDF's
/// forward kinematics of the tool's parent link · `parent_from_tool` is the grasp's
/// `world_from_tcp` (to 1e-9), and with the event's `link_from_object` the object's pose there
/// (to IK's tolerances).
#[test]
fn the_stated_base_and_tool_frames_place_every_grasp_with_the_urdf_alone() {
    let setup = setup("fig9-near.toml");
    let planned = plan_with_threads(&setup, 2);
    let json = planned.to_json();
    assert!(json.contains("\"world_from_root\""), "{json}");
    let plan = Plan::from_json(&json).expect("reads back");
    assert_eq!(plan, planned);
    let base = plan.base.as_ref().expect("the plan states the base");
    let urdf = urdf();
    assert_eq!(base.link, urdf.links()[urdf.root()].name);
    assert_eq!(base.link, "WAIST");
    let scene_base = setup.scene.robots[0]
        .base_pose
        .to_isometry()
        .expect("a pose");
    let world_from_root = base.world_from_root.to_isometry().expect("a pose");
    let (d, a) = gap(&world_from_root, &scene_base);
    assert!(d < 1e-9 && a < 1e-9, "{base:?}");
    assert!((base.world_from_root.position[2] - 0.92).abs() < 1e-12);
    let columns: Vec<usize> = urdf
        .variable_names()
        .map(|n| {
            plan.joint_names
                .iter()
                .position(|j| j == n)
                .expect("a joint")
        })
        .collect();
    let mut grasps = 0;
    for e in plan.events.iter().filter(|e| e.kind == EventKind::Grasp) {
        let tool = plan
            .arms
            .iter()
            .find(|a| a.arm == e.arm)
            .and_then(|a| a.tool.as_ref())
            .expect("the arm's tool frame");
        let sample = plan
            .trajectory
            .iter()
            .find(|p| (p.time_from_start - e.time).abs() < 1e-9)
            .expect("a grasp is at a sample");
        let q: Vec<f64> = columns.iter().map(|&c| sample.positions[c]).collect();
        let parent = urdf.link_index(&tool.parent).expect("a URDF link");
        let world_from_tcp = world_from_root
            * urdf.link_poses(&q).expect("fk")[parent]
            * tool.parent_from_tool.to_isometry().expect("a pose");
        // The grasp's key pose: the arm stops there, and rests while the fingers close.
        let key = plan
            .key_poses
            .iter()
            .rfind(|k| k.arm == e.arm && k.time <= e.time + 1e-9 && k.name.ends_with("grasp"))
            .expect("the grasp's key pose");
        let (d, a) = gap(
            &world_from_tcp,
            &key.world_from_tcp.to_isometry().expect("a pose"),
        );
        assert!(d < 1e-9 && a < 1e-9, "{}: {d} m, {a} rad", key.name);
        // The object where the hand holds it: `link_from_object` is the planned grasp's, the
        // hand where IK put it (within IK's tolerances, 0.1 mm and 1 mrad).
        let world_from_object = world_from_tcp * e.link_from_object.to_isometry().expect("a pose");
        let (d, a) = gap(
            &world_from_object,
            &key.world_from_object.to_isometry().expect("a pose"),
        );
        assert!(d < 1e-4 && a < 1e-3, "{}: {d} m, {a} rad", key.name);
        grasps += 1;
    }
    assert_eq!(grasps, 1);
}

#[test]
fn a_plan_without_tool_frames_still_reads_and_a_contradicting_one_is_refused() {
    let setup = setup("fig9-near.toml");
    let plan = plan_with_threads(&setup, 2);
    let mut old = plan.clone();
    old.base = None;
    for a in &mut old.arms {
        a.tool = None;
    }
    let json = old.to_json();
    assert!(!json.contains("parent_from_tool") && !json.contains("world_from_root"));
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
    assert!(
        err.reason().starts_with("arms[1].tool.parent_from_tool:"),
        "{err}"
    );
    for (orientation, reason) in [
        ([0.0; 4], "orientation quaternion is zero"),
        ([0.0, 0.0, f64::NAN, 1.0], "pose has a non-finite number"),
    ] {
        let mut bad = plan.clone();
        bad.base.as_mut().expect("base").world_from_root.orientation = orientation;
        assert_eq!(
            bad.check_poses(),
            Err(format!("base.world_from_root: {reason}").into())
        );
    }
    let mut zero = plan.clone();
    zero.base
        .as_mut()
        .expect("base")
        .world_from_root
        .orientation = [0.0; 4];
    let err = Plan::from_json(&zero.to_json()).expect_err("a zero quaternion");
    assert_eq!(
        err.reason(),
        "base.world_from_root: orientation quaternion is zero"
    );
    let mut other = plan.clone();
    other.arms[0].tool.as_mut().expect("tool").link = "RARM_JOINT5_Link".into();
    let err = other
        .check_form()
        .expect_err("the events name another link");
    assert!(
        err.reason()
            .contains("is not the right arm's tool link \"RARM_JOINT5_Link\""),
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
        // Where the robot stands, from the world frame to the root link, beside it.
        let base = m.base_frame.as_ref().expect("the message's base frame");
        assert_eq!(
            (base.header.frame_id.as_str(), base.child_frame_id.as_str()),
            (pickplace::tool_frame::WORLD_FRAME, "WAIST")
        );
        let tr = base.transform;
        assert_eq!(
            [tr.translation.x, tr.translation.y, tr.translation.z],
            setup.scene.robots[0].base_pose.position
        );
        assert_eq!(json["base_frame"]["child_frame_id"], "WAIST");
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
    // First where the robot stands, then the tool frames.
    assert!(
        comments.starts_with(
            "# robot base (frame of world_from_tcp and world_from_object): root link \"WAIST\" in \"world\" at position [0, 0, 0.92], orientation [0, 0, 0, 1]\n#   ros2 run tf2_ros static_transform_publisher --x 0 --y 0 --z 0.92 --qx 0 --qy 0 --qz 0 --qw 1 --frame-id world --child-frame-id WAIST\n"
        ),
        "{comments}"
    );
    assert_eq!(comments.lines().count(), 6);
    assert!(comments.lines().all(|l| l.starts_with('#')));
    // A plan that states no base has no base frame and no comment for it.
    let mut old = plan.clone();
    old.base = None;
    let messages = pickplace::export::joint_trajectories(&old).expect("exports");
    assert!(messages.iter().all(|m| m.base_frame.is_none()));
    let json = serde_json::to_string(&messages).expect("json");
    assert!(!json.contains("base_frame"));
    assert_eq!(
        pickplace::tool_frame::yaml_comments(&old, &messages)
            .lines()
            .count(),
        4
    );
}
