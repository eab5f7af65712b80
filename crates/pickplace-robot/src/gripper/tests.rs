//! Unit tests of the gripper measured on small URDFs.

use super::*;
use crate::limbs::find_arms;
use crate::model::LoadOptions;
use std::path::Path;

/// A one-joint arm with a hand: `fingers` is the URDF text of the finger links and joints
/// (parent link `hand`).
fn robot(fingers: &str) -> RobotModel {
    let text = format!(
        r#"<robot name="t">
  <link name="base"/>
  <link name="hand"><collision><origin xyz="0 0 -0.02"/><geometry><box size="0.04 0.1 0.04"/></geometry></collision></link>
  <joint name="wrist" type="revolute"><parent link="base"/><child link="hand"/>
<axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  {fingers}
</robot>"#
    );
    RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default()).expect("test URDF")
}

fn finger(
    name: &str,
    parent: &str,
    kind: &str,
    xyz: &str,
    axis: &str,
    limits: (f64, f64),
    mimic: &str,
    box_xyz: &str,
) -> String {
    format!(
        r#"<link name="{name}"><collision><origin xyz="{box_xyz}"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="{name}_joint" type="{kind}"><parent link="{parent}"/><child link="{name}"/>
<origin xyz="{xyz}"/><axis xyz="{axis}"/><limit lower="{}" upper="{}" velocity="1" effort="1"/>{mimic}</joint>"#,
        limits.0, limits.1
    )
}

fn derive(model: &RobotModel) -> Gripper {
    let wrist = model.variable_index("wrist").expect("wrist");
    Gripper::derive(
        model,
        &[wrist],
        &GripperOptions {
            squeeze: 0.0,
            ..GripperOptions::default()
        },
    )
    .expect("gripper")
}

#[test]
fn prismatic_mimic_fingers_open_by_twice_the_joint_value() {
    let model = robot(&format!(
        "{}\n{}",
        finger(
            "l",
            "hand",
            "prismatic",
            "0 0 0",
            "0 1 0",
            (0.0, 0.04),
            "",
            "0 0.005 0.03"
        ),
        finger(
            "r",
            "hand",
            "prismatic",
            "0 0 0",
            "0 -1 0",
            (0.0, 0.04),
            r#"<mimic joint="l_joint"/>"#,
            "0 -0.005 0.03"
        ),
    ));
    let g = derive(&model);
    let (lo, hi) = g.opening_range();
    assert!(lo.abs() < 1e-6 && (hi - 0.08).abs() < 1e-6, "{lo} {hi}");
    let mut q = model.zero_configuration();
    g.set_grasp(&mut q, 0.05);
    let v = model.variable_index("l_joint").expect("l");
    assert!((q[v] - 0.025).abs() < 1e-6, "{}", q[v]);
    // The TCP: midway between the pads, at their centre, z towards the tips.
    let t = g.tip_from_tcp();
    assert!(
        (t.translation.vector - Vector3::new(0.0, 0.0, 0.03)).norm() < 1e-6,
        "{t:?}"
    );
    let z = t.rotation * Vector3::z();
    assert!((z - Vector3::z()).norm() < 1e-6);
    let y = t.rotation * Vector3::y();
    assert!(y.y.abs() > 0.999);
    assert_eq!(g.pad_size().1, 0.06);
}

#[test]
fn a_finger_closed_at_its_upper_limit_is_commanded_there() {
    // Zero is fully open: the fingers start 40 mm out and move in.
    let model = robot(&format!(
        "{}\n{}",
        finger(
            "l",
            "hand",
            "prismatic",
            "0 0.04 0",
            "0 -1 0",
            (0.0, 0.04),
            "",
            "0 0.005 0.03"
        ),
        finger(
            "r",
            "hand",
            "prismatic",
            "0 -0.04 0",
            "0 1 0",
            (0.0, 0.04),
            r#"<mimic joint="l_joint"/>"#,
            "0 -0.005 0.03"
        ),
    ));
    let g = derive(&model);
    assert_eq!(g.drives()[0].closed, 0.04);
    assert_eq!(g.drives()[0].open, 0.0);
    let mut q = model.zero_configuration();
    g.set_grasp(&mut q, 0.03);
    let v = model.variable_index("l_joint").expect("l");
    assert!((q[v] - 0.025).abs() < 1e-6, "{}", q[v]);
}

#[test]
fn revolute_fingers_with_a_mimic_chain_close_on_the_width() {
    // Each finger: a proximal link hinged at the palm and a tip that counter-rotates
    // (a mimic of the driving joint) to keep the pad parallel, as on PR2.
    let prox = |name: &str, y: f64, axis: &str, mimic: &str| {
        format!(
            r#"<link name="{name}"><collision><origin xyz="0 0 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="{name}_joint" type="revolute"><parent link="hand"/><child link="{name}"/>
<origin xyz="0 {y} 0"/><axis xyz="{axis}"/><limit lower="0" upper="0.5" velocity="1" effort="1"/>{mimic}</joint>"#
        )
    };
    let tip = |name: &str, parent: &str, y: f64, axis: &str| {
        format!(
            r#"<link name="{name}"><collision><origin xyz="0 {y} 0.02"/><geometry><box size="0.02 0.01 0.04"/></geometry></collision></link>
  <joint name="{name}_joint" type="revolute"><parent link="{parent}"/><child link="{name}"/>
<origin xyz="0 0 0.06"/><axis xyz="{axis}"/><limit lower="0" upper="0.5" velocity="1" effort="1"/><mimic joint="l_joint"/></joint>"#
        )
    };
    let model = robot(&format!(
        "{}\n{}\n{}\n{}",
        prox("l", 0.012, "-1 0 0", ""),
        prox("r", -0.012, "1 0 0", r#"<mimic joint="l_joint"/>"#),
        tip("lt", "l", -0.007, "1 0 0"),
        tip("rt", "r", 0.007, "-1 0 0"),
    ));
    let g = derive(&model);
    let (lo, hi) = g.opening_range();
    assert!(lo < 0.002, "{lo}");
    // Open: each proximal link turns 0.5 rad outwards: the tips move 60 mm · sin 0.5 out.
    let expected = 2.0 * (0.012 + 0.06 * 0.5f64.sin() - 0.007 - 0.005);
    assert!((hi - expected).abs() < 0.002, "{hi} vs {expected}");
    // Commanded to 40 mm, the measured opening is 40 mm.
    let mut q = model.zero_configuration();
    g.set_opening(&mut q, 0.04);
    let s = g.parameter_of(&q);
    assert!((g.opening_at(s) - 0.04).abs() < 1e-4);
    let v = model.variable_index("l_joint").expect("l");
    assert!(q[v] > 0.0 && q[v] < 0.5);
}

#[test]
fn a_jaw_closing_against_a_fixed_one_is_a_gripper_with_its_tool_point_on_the_fixed_jaw() {
    // The fixed jaw's inner face at y = +0.01, the moving jaw's at y = +0.01 − 0 when
    // closed, sliding towards −y to open 40 mm.
    let model = robot(&format!(
        r#"<link name="fixed"><collision><origin xyz="0 0.015 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="fixed_joint" type="fixed"><parent link="hand"/><child link="fixed"/></joint>
  {}"#,
        finger(
            "moving",
            "hand",
            "prismatic",
            "0 0 0",
            "0 -1 0",
            (0.0, 0.04),
            "",
            "0 0.005 0.03",
        )
    ));
    let g = derive(&model);
    assert!(g.has_fixed_jaw());
    let (lo, hi) = g.opening_range();
    assert!(lo.abs() < 1e-6 && (hi - 0.04).abs() < 1e-6, "{lo} {hi}");
    // The tool point is on the fixed jaw's pad (y = 0.01 in the hand's frame), its y axis
    // towards the fixed jaw.
    let t = g.tip_from_tcp();
    assert!((t.translation.y - 0.01).abs() < 1e-6, "{t}");
    assert!((t.rotation * Vector3::y()).y > 0.99, "{t}");
    // A grasp 30 mm wide: its centre 16 mm from the tool point, the moving jaw at 31 mm
    // (the fixed jaw 1 mm off the object; squeeze 0 here).
    let c = g.centre_from_tcp(0.03);
    assert!((c.translation.y - 0.016).abs() < 1e-9, "{c}");
    let mut q = model.zero_configuration();
    g.set_grasp(&mut q, 0.03);
    let v = model.variable_index("moving_joint").expect("jaw");
    assert!((q[v] - 0.031).abs() < 1e-6, "{}", q[v]);
    // The pads: the moving jaw and the fixed jaw, not the hand's box.
    let pads = g.pad_links();
    let name = |l: &usize| model.links()[*l].name.as_str();
    assert_eq!(pads[0].iter().map(name).collect::<Vec<_>>(), ["moving"]);
    assert_eq!(pads[1].iter().map(name).collect::<Vec<_>>(), ["fixed"]);
}

#[test]
fn a_single_moving_finger_with_nothing_to_close_against_is_refused() {
    let text = r#"<robot name="t"><link name="base"/><link name="hand"/>
  <joint name="wrist" type="revolute"><parent link="base"/><child link="hand"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" velocity="1" effort="1"/></joint>
  <link name="l"><collision><origin xyz="0 0.005 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
  <joint name="l_joint" type="prismatic"><parent link="hand"/><child link="l"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
</robot>"#;
    let model = RobotModel::from_urdf_str(text, Path::new("."), &LoadOptions::default())
        .expect("test URDF");
    let wrist = model.variable_index("wrist").expect("wrist");
    let e = Gripper::derive(&model, &[wrist], &GripperOptions::default()).expect_err("one finger");
    assert!(
        matches!(e, GripperError::NotTwoFingers { found: 1, .. }),
        "{e}"
    );
}

#[test]
fn an_arm_without_a_gripper_is_refused() {
    let model = robot("");
    let wrist = model.variable_index("wrist").expect("wrist");
    let e = Gripper::derive(&model, &[wrist], &GripperOptions::default()).expect_err("no gripper");
    assert!(matches!(e, GripperError::NoDrive { .. }), "{e}");
    assert!(matches!(
        Gripper::derive(&model, &[], &GripperOptions::default()),
        Err(GripperError::NoArmJoints)
    ));
}

#[test]
fn a_single_arm_is_found_and_a_gripperless_chain_is_not() {
    // Four revolute joints, then the prismatic fingers of `robot`'s hand.
    let mut arm = String::new();
    let mut parent = "hand".to_owned();
    for k in 0..3 {
        arm.push_str(&format!(
            r#"<link name="a{k}"/><joint name="a{k}_joint" type="revolute"><parent link="{parent}"/><child link="a{k}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#
        ));
        parent = format!("a{k}");
    }
    arm.push_str(&format!(
        "{}\n{}",
        finger(
            "l",
            &parent,
            "prismatic",
            "0 0 0",
            "0 1 0",
            (0.0, 0.04),
            "",
            "0 0.005 0.03"
        ),
        finger(
            "r",
            &parent,
            "prismatic",
            "0 0 0",
            "0 -1 0",
            (0.0, 0.04),
            r#"<mimic joint="l_joint"/>"#,
            "0 -0.005 0.03"
        ),
    ));
    let model = robot(&arm);
    let arms = find_arms(&model, 4);
    assert_eq!(arms.len(), 1, "{arms:?}");
    assert_eq!(arms[0].variables.len(), 4);
    assert_eq!(model.links()[arms[0].tip_link].name, "a2");
    // Three joints are not an arm; a chain without fingers has no gripper.
    assert!(find_arms(&model, 5).is_empty());
    assert!(find_arms(&robot(""), 1).is_empty());
}

#[test]
fn nx_hiro_tcp_matches_its_tool_link() {
    let urdf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro/nx-hiro.urdf");
    let model = RobotModel::from_urdf_file(&urdf, &LoadOptions::default()).expect("nx-hiro");
    let arm: Vec<usize> = (0..6)
        .map(|i| {
            model
                .variable_index(&format!("RARM_JOINT{i}"))
                .expect("joint")
        })
        .collect();
    let g = Gripper::derive(
        &model,
        &arm,
        &GripperOptions {
            pad_depth: Some(0.025),
            ..GripperOptions::default()
        },
    )
    .expect("gripper");
    let tip = g.arm_tip();
    let tcp = model.require_link("RARM_TCP").expect("tcp");
    let q = model.zero_configuration();
    let poses = model.link_poses(&q).expect("fk");
    let want = poses[tip].inverse() * poses[tcp];
    let got = g.tip_from_tcp();
    assert!(
        (want.translation.vector - got.translation.vector).norm() < 1e-6,
        "{want:?} {got:?}"
    );
    // Same approach axis; the closing axis up to its sign.
    assert!(((want.rotation * Vector3::z()) - (got.rotation * Vector3::z())).norm() < 1e-6);
    assert!(
        (want.rotation * Vector3::y())
            .dot(&(got.rotation * Vector3::y()))
            .abs()
            > 1.0 - 1e-6
    );
    let (lo, hi) = g.opening_range();
    assert!(lo.abs() < 1e-6 && (hi - 0.08).abs() < 1e-6, "{lo} {hi}");
}
