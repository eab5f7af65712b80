//! SRDF parsing and resolution.

use crate::common::nx;
use pickplace_robot::error::{Error, SrdfErrorKind};
use pickplace_robot::srdf::{DisableReason, Semantics, Srdf, SrdfWarning};
use std::path::Path;

#[test]
fn shipped_groups_resolve() {
    let (model, semantics) = nx();
    let names = |g: &str| -> Vec<String> {
        semantics
            .group(g)
            .expect("group")
            .variables
            .iter()
            .map(|&v| model.variable_joint(v).name.clone())
            .collect()
    };
    assert_eq!(
        names("right_arm"),
        (0..6).map(|i| format!("RARM_JOINT{i}")).collect::<Vec<_>>()
    );
    let waist = names("right_arm_waist");
    assert_eq!(waist.len(), 7);
    assert_eq!(waist[0], "CHEST_JOINT0");
    assert_eq!(names("both_arms").len(), 12);
    assert_eq!(names("head"), ["HEAD_JOINT0", "HEAD_JOINT1"]);
    assert_eq!(names("right_gripper"), ["RARM_FINGER0_JOINT"]);
    let tip = semantics
        .group("right_arm")
        .expect("group")
        .tip_link
        .expect("tip");
    assert_eq!(model.links()[tip].name, "RARM_TCP");
    assert_eq!(semantics.end_effectors().len(), 2);
    let mut q = vec![0.0; model.variable_count()];
    semantics.apply_state(model, "home", &mut q).expect("home");
    model
        .check_configuration(&q)
        .expect("home is within limits");
}

#[test]
fn parse_and_write_round_trip() {
    let text = r#"<?xml version="1.0"?>
<robot name="r">
  <virtual_joint name="v" type="fixed" parent_frame="world" child_link="a"/>
  <group name="g"><chain base_link="a" tip_link="b"/><joint name="j"/></group>
  <group name="h"><group name="g"/><link name="b"/></group>
  <group_state name="s" group="g"><joint name="j" value="0.5"/></group_state>
  <end_effector name="e" parent_link="b" group="h"/>
  <disable_collisions link1="a" link2="b" reason="Adjacent"/>
  <disable_collisions link1="a" link2="c" reason="Because"/>
</robot>"#;
    let srdf = Srdf::from_xml_str(text).expect("valid");
    assert_eq!(srdf.groups.len(), 2);
    assert_eq!(srdf.groups[1].subgroups, ["g"]);
    assert_eq!(srdf.group_states[0].values, [("j".to_owned(), 0.5)]);
    assert_eq!(
        srdf.disabled_collisions[1].reason,
        DisableReason::Custom("Because".into())
    );
    assert_eq!(srdf.end_effectors[0].parent_group, None);
    let again = Srdf::from_xml_str(&srdf.to_xml()).expect("round trip");
    assert_eq!(again, srdf);
}

#[test]
fn bad_srdf_parts_are_left_out_with_a_warning_and_broken_xml_is_an_error() {
    let (model, _) = nx();
    let warnings = |text: &str| -> Vec<String> {
        let srdf = Srdf::from_xml_str(text).expect("xml ok");
        Semantics::resolve(model, &srdf, Path::new("x.srdf"))
            .expect("resolves")
            .warnings()
            .iter()
            .map(ToString::to_string)
            .collect()
    };
    let unknown = warnings(
        r#"<robot><group name="g"><chain base_link="WAIST" tip_link="NOSE"/></group></robot>"#,
    );
    assert!(
        unknown.len() == 1 && unknown[0].contains("NOSE"),
        "{unknown:?}"
    );
    let backwards = warnings(
        r#"<robot><group name="g"><chain base_link="RARM_TCP" tip_link="WAIST"/></group></robot>"#,
    );
    assert!(backwards[0].contains("not below base"), "{backwards:?}");
    let recursive = warnings(
        r#"<robot><group name="g"><group name="h"/></group><group name="h"><group name="g"/></group></robot>"#,
    );
    assert!(
        recursive.len() == 1 && recursive[0].contains("again"),
        "{recursive:?}"
    );
    // A value that is not a number: the value is skipped, the state kept.
    let srdf = Srdf::from_xml_str(
        r#"<robot><group name="g"><joint name="RARM_JOINT0"/></group><group_state name="s" group="g"><joint name="RARM_JOINT0" value="x"/></group_state></robot>"#,
    )
    .expect("skipped, not refused");
    assert!(matches!(
        &srdf.skipped[0].reason,
        SrdfErrorKind::BadNumber { .. }
    ));
    let semantics = Semantics::resolve(model, &srdf, Path::new("x")).expect("resolves");
    assert_eq!(semantics.srdf().group_states.len(), 1);
    // XML that is not well-formed is still an error.
    assert!(matches!(
        Srdf::from_xml_str("<robot><group></robot>"),
        Err(Error::Srdf { .. })
    ));
}

/// The three SRDF details of issue 32 that MoveIt and Pinocchio load and this crate refused:
/// a group state naming joints the URDF lacks, an end effector whose parent link is not a
/// link, a group state without a group. Each is left out with one warning naming it; the
/// arm groups and every disabled pair are kept.
#[test]
fn details_moveit_ignores_are_left_out_and_the_collision_pairs_kept() {
    let (model, shipped) = nx();
    let text = r#"<robot name="nx">
  <group name="right_arm"><chain base_link="CHEST_JOINT0_Link" tip_link="RARM_TCP"/></group>
  <group name="right_hand"><joint name="RARM_FINGER0_JOINT"/></group>
  <group_state name="half_sitting" group="right_arm">
    <joint name="RARM_JOINT0" value="0.1"/><joint name="LEFT_TOE" value="0"/><joint name="EYE" value="0"/>
  </group_state>
  <group_state name="nowhere"><joint name="RARM_JOINT0" value="0"/></group_state>
  <end_effector name="foot" parent_link="left_sole_frame" group="right_hand"/>
  <end_effector name="hand" parent_link="RARM_TCP" group="right_hand" parent_group="right_arm"/>
  <group name="broken"><chain base_link="WAIST"/></group>
  <disable_collisions link1="WAIST" link2="CHEST_JOINT0_Link" reason="Adjacent"/>
  <disable_collisions link1="WAIST" link2="TOE_Link" reason="Never"/>
  <disable_collisions link1="RARM_JOINT4_Link" link2="RARM_JOINT5_Link" reason="Adjacent"/>
</robot>"#;
    let srdf = Srdf::from_xml_str(text).expect("parses: malformed elements are skipped");
    let semantics = Semantics::resolve(model, &srdf, Path::new("nx.srdf")).expect("resolves");
    let warnings: Vec<String> = semantics
        .warnings()
        .iter()
        .map(ToString::to_string)
        .collect();
    let about = |needle: &str| warnings.iter().filter(|w| w.contains(needle)).count();
    assert_eq!(about("LEFT_TOE"), 1, "{warnings:?}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("EYE") && w.contains("half_sitting"))
    );
    assert_eq!(about("nowhere"), 1, "{warnings:?}");
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("nowhere") && w.contains("\"group\""))
    );
    assert_eq!(about("left_sole_frame"), 1, "{warnings:?}");
    assert_eq!(about("TOE_Link"), 1, "{warnings:?}");
    assert_eq!(about("broken"), 1, "{warnings:?}");
    assert_eq!(warnings.len(), 5, "{warnings:?}");
    // What the planner needs is there.
    assert_eq!(
        semantics.group("right_arm").expect("arm").variables,
        shipped.group("right_arm").expect("arm").variables
    );
    assert_eq!(semantics.end_effectors().len(), 1);
    assert_eq!(semantics.srdf().disabled_collisions.len(), 2);
    let mut q = model.zero_configuration();
    semantics
        .apply_state(model, "half_sitting", &mut q)
        .expect("the state's known joints");
    // A group left out says why when it is asked for.
    let error = semantics.group("broken").expect_err("left out");
    assert!(
        matches!(&error, Error::GroupLeftOut { .. }) && error.to_string().contains("tip_link"),
        "{error}"
    );
}

/// A small robot of our own: a four-joint arm with a TCP and a finger, and a two-joint
/// head, on one base.
const TWO_BRANCHES: &str = r#"<robot name="t">
  <link name="base"/><link name="a1"/><link name="a2"/><link name="a3"/><link name="a4"/>
  <link name="tcp"/><link name="finger"/><link name="h1"/><link name="h2"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="a1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="a1"/><child link="a2"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j3" type="revolute"><parent link="a2"/><child link="a3"/><origin xyz="0.2 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j4" type="revolute"><parent link="a3"/><child link="a4"/><origin xyz="0.2 0 0"/>
    <axis xyz="1 0 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="tcp_joint" type="fixed"><parent link="a4"/><child link="tcp"/><origin xyz="0.1 0 0"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="a4"/><child link="finger"/>
    <axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
  <joint name="k1" type="revolute"><parent link="base"/><child link="h1"/><origin xyz="0 0 0.5"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="k2" type="revolute"><parent link="h1"/><child link="h2"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
</robot>"#;

fn two_branches() -> pickplace_robot::RobotModel {
    pickplace_robot::RobotModel::from_urdf_str(
        TWO_BRANCHES,
        Path::new("."),
        &pickplace_robot::LoadOptions::default(),
    )
    .expect("valid URDF")
}

fn resolve(model: &pickplace_robot::RobotModel, body: &str) -> pickplace_robot::Result<Semantics> {
    let srdf = Srdf::from_xml_str(&format!("<robot name=\"t\">{body}</robot>"))?;
    Semantics::resolve(model, &srdf, Path::new("t.srdf"))
}

fn tip_name(model: &pickplace_robot::RobotModel, semantics: &Semantics, group: &str) -> String {
    let chain = semantics.chain(model, group).expect("a chain");
    model.links()[chain.tip_link()].name.clone()
}

#[test]
fn a_joint_list_arm_group_is_a_chain_to_its_deepest_joint() {
    let model = two_branches();
    let semantics = resolve(
        &model,
        r#"<group name="arm"><joint name="j1"/><joint name="j2"/><joint name="j3"/><joint name="j4"/></group>
           <group name="hand"><joint name="finger_joint"/></group>
           <end_effector name="ee" parent_link="tcp" group="hand"/>"#,
    )
    .expect("resolves");
    assert_eq!(tip_name(&model, &semantics, "arm"), "a4");
    assert_eq!(
        semantics.end_effector_of("arm").map(|e| e.name.as_str()),
        Some("ee")
    );
    assert!(
        semantics.warnings().is_empty(),
        "{:?}",
        semantics.warnings()
    );
}

#[test]
fn a_subgroup_arm_group_is_a_chain() {
    let model = two_branches();
    let semantics = resolve(
        &model,
        r#"<group name="shoulder"><joint name="j1"/><joint name="j2"/></group>
           <group name="forearm"><link name="a3"/><link name="a4"/></group>
           <group name="arm"><group name="shoulder"/><group name="forearm"/></group>
           <group name="hand"><joint name="finger_joint"/></group>
           <end_effector name="ee" parent_link="tcp" group="hand" parent_group="arm"/>"#,
    )
    .expect("resolves");
    // The end effector names the arm as its parent group: its link is the tip.
    assert_eq!(tip_name(&model, &semantics, "arm"), "tcp");
    assert_eq!(semantics.group("arm").expect("arm").variables.len(), 4);
    assert_eq!(tip_name(&model, &semantics, "forearm"), "a4");
}

#[test]
fn groups_that_are_not_one_chain_or_have_no_joint_are_named_errors() {
    let model = two_branches();
    let semantics = resolve(
        &model,
        r#"<group name="both"><joint name="j1"/><joint name="k1"/></group>
           <group name="fixed_only"><joint name="tcp_joint"/></group>"#,
    )
    .expect("resolves: only arms need a chain");
    let error = semantics.chain(&model, "both").expect_err("two branches");
    assert!(
        matches!(&error, Error::Srdf { kind: SrdfErrorKind::NotOneChain { group, .. }, .. } if group == "both"),
        "{error:?}"
    );
    assert!(error.to_string().contains("t.srdf"), "{error}");
    let error = semantics.chain(&model, "fixed_only").expect_err("no joint");
    assert!(
        matches!(
            &error,
            Error::Srdf {
                kind: SrdfErrorKind::GroupWithoutJoints { .. },
                ..
            }
        ),
        "{error:?}"
    );
    // Unknown names are left out, each with one warning naming the element and the name
    // (MoveIt's loader does the same); the rest of the file is used.
    for (body, name) in [
        (r#"<group name="g"><joint name="nope"/></group>"#, "nope"),
        (r#"<group name="g"><link name="nolink"/></group>"#, "nolink"),
        (r#"<passive_joint name="ghost"/>"#, "ghost"),
        (
            r#"<disable_collisions link1="a1" link2="zz" reason="Never"/>"#,
            "zz",
        ),
        (
            r#"<group name="g"><joint name="j1"/></group><group_state name="s" group="g"><joint name="j9" value="1"/></group_state>"#,
            "j9",
        ),
        (
            r#"<virtual_joint name="w" type="fixed" parent_frame="world" child_link="nowhere"/>"#,
            "nowhere",
        ),
    ] {
        let semantics = resolve(&model, body).expect(body);
        let left_out: Vec<String> = semantics
            .warnings()
            .iter()
            .filter(|w| matches!(w, SrdfWarning::LeftOut { .. }))
            .map(ToString::to_string)
            .collect();
        assert_eq!(left_out.len(), 1, "{body}: {left_out:?}");
        assert!(left_out[0].contains(name), "{}", left_out[0]);
    }
}

#[test]
fn virtual_joints_in_groups_and_states_are_one_warning_each() {
    let model = two_branches();
    let semantics = resolve(
        &model,
        r#"<virtual_joint name="world_joint" type="planar" parent_frame="odom" child_link="base"/>
           <passive_joint name="world_joint"/>
           <group name="base"><joint name="world_joint"/></group>
           <group name="all"><group name="base"/><joint name="j1"/></group>
           <group_state name="s" group="all">
             <joint name="world_joint" value="0.1 0.2 0.3"/>
             <joint name="root_joint" value="0 0 1.01927 0 0 0 1"/>
             <joint name="j1" value="0.5"/>
           </group_state>"#,
    )
    .expect("virtual joints are not errors");
    let warnings = semantics.warnings();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert!(matches!(
        &warnings[0],
        SrdfWarning::VirtualJoint { name, joint_type: None, used_in } if name == "root_joint" && used_in.len() == 1
    ));
    assert!(matches!(
        &warnings[1],
        SrdfWarning::VirtualJoint { name, joint_type: Some(t), used_in }
            if name == "world_joint" && t == "planar" && used_in.len() == 4
    ));
    assert!(warnings[1].to_string().contains("world_joint"));
    assert!(semantics.group("base").expect("base").variables.is_empty());
    assert_eq!(semantics.group("all").expect("all").variables.len(), 1);
    let mut q = model.zero_configuration();
    semantics.apply_state(&model, "s", &mut q).expect("state");
    assert_eq!(q[model.variable_index("j1").expect("j1")], 0.5);
    // Multi-value numbers parse and round-trip.
    let srdf = semantics.srdf();
    assert_eq!(srdf.group_states[0].multi_dof_values[1].1.len(), 7);
    assert_eq!(Srdf::from_xml_str(&srdf.to_xml()).expect("again"), *srdf);
}

#[test]
fn a_common_prefix_is_stripped_and_unknown_elements_are_ignored() {
    let model = two_branches();
    let semantics = resolve(
        &model,
        r#"<gripper name="g1" clearance="0.02"><link name="not_a_link"/><position>0 0 0</position></gripper>
           <gripper name="g2"/>
           <contact name="c"><link name="x"/></contact>
           <group name="arm"><joint name="bot/j1"/><joint name="bot/j2"/><joint name="bot/j3"/><joint name="bot/j4"/></group>
           <group_state name="home" group="arm"><joint name="bot/j2" value="0.3"/></group_state>
           <disable_collisions link1="bot/a1" link2="a2" reason="Adjacent"/>"#,
    )
    .expect("prefix stripped");
    let warnings: Vec<String> = semantics
        .warnings()
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(warnings.len(), 3, "{warnings:?}");
    assert!(matches!(
        &semantics.warnings()[0],
        SrdfWarning::StrippedPrefix { prefix, names: 5 } if prefix == "bot/"
    ));
    assert!(matches!(
        &semantics.warnings()[1],
        SrdfWarning::IgnoredElement { element, count: 2 } if element == "gripper"
    ));
    assert_eq!(tip_name(&model, &semantics, "arm"), "a4");
    assert_eq!(semantics.srdf().disabled_collisions[0].link1, "a1");
    // A prefix that does not make every name known is not stripped: the names are left out,
    // and the warning names them.
    let semantics = resolve(
        &model,
        r#"<group name="arm"><joint name="bot/j1"/><joint name="bot/nope"/></group>"#,
    )
    .expect("unknown names are left out");
    let text = semantics.warnings()[0].to_string();
    assert!(
        text.contains("bot/j1") && text.contains("bot/nope"),
        "{text}"
    );
    assert!(semantics.group("arm").expect("kept").variables.is_empty());
}

#[test]
fn written_names_keep_tabs_and_newlines_for_every_xml_reader() {
    // Found by the srdf_writer fuzz target: raw tab/newline in attribute values came back as
    // spaces from standard XML readers (attribute-value normalisation).
    let text =
        "<robot name=\"r&#9;x\"><group name=\"a&#10;b&#13;c\"><joint name=\"j\"/></group></robot>";
    let srdf = Srdf::from_xml_str(text).expect("valid");
    assert_eq!(srdf.robot_name, "r\tx");
    assert_eq!(srdf.groups[0].name, "a\nb\rc");
    let xml = srdf.to_xml();
    assert!(
        xml.contains("a&#10;b&#13;c") && xml.contains("r&#9;x"),
        "{xml}"
    );
    assert_eq!(Srdf::from_xml_str(&xml).expect("again"), srdf);
}
