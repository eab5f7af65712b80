//! `pickplace robot check | srdf` on the shipped NX-HIRO and on small robots of our own.

use crate::args;
use crate::support::{Scratch, fails_with, ok, run_in};

fn nx(file: &str) -> std::path::PathBuf {
    crate::root().join("robots/nx-hiro").join(file)
}

/// An arm of five joints with a two-finger gripper (finger boxes: the gripper is measured on
/// them), as a robot with no SRDF.
const GRIPPER_ARM: &str = r#"<robot name="g">
  <link name="base"><collision><geometry><box size="0.2 0.2 0.1"/></geometry></collision></link>
  <link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/><link name="l5"/>
  <link name="palm"><collision><geometry><box size="0.05 0.08 0.02"/></geometry></collision></link>
  <link name="fa"><collision><origin xyz="0.04 0.005 0"/><geometry><box size="0.04 0.01 0.02"/></geometry></collision></link>
  <link name="fb"><collision><origin xyz="0.04 -0.005 0"/><geometry><box size="0.04 0.01 0.02"/></geometry></collision></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/><origin xyz="0.2 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/><origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="j5" type="continuous"><parent link="l4"/><child link="l5"/><origin xyz="0.1 0 0"/><axis xyz="0 1 0"/><limit velocity="1" effort="1"/></joint>
  <joint name="palm_joint" type="fixed"><parent link="l5"/><child link="palm"/><origin xyz="0.05 0 0"/></joint>
  <joint name="fa_joint" type="prismatic"><parent link="palm"/><child link="fa"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
  <joint name="fb_joint" type="prismatic"><parent link="palm"/><child link="fb"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/><mimic joint="fa_joint"/></joint>
</robot>"#;

#[test]
fn robot_srdf_writes_a_starting_srdf_that_check_accepts() {
    let dir = Scratch::new("robot-srdf");
    let urdf = dir.file("g.urdf", GRIPPER_ARM.as_bytes());
    let out = ok(&run_in(
        dir.path(),
        args![
            "robot",
            "srdf",
            &urdf,
            "--samples",
            "200",
            "--seed",
            "3",
            "--out",
            "g.srdf"
        ],
    ));
    assert!(out.contains("arm_0: 5 joints from base to l5"), "{out}");
    let text = std::fs::read_to_string(dir.join("g.srdf")).expect("written");
    assert!(
        text.contains("seed 3") && text.contains(r#"reason="Adjacent""#),
        "{text}"
    );
    assert!(
        text.contains(
            r#"<end_effector name="hand_0" parent_link="l5" group="hand_0" parent_group="arm_0"/>"#
        ),
        "{text}"
    );
    // Same seed, same file.
    ok(&run_in(
        dir.path(),
        args![
            "robot",
            "srdf",
            &urdf,
            "--samples",
            "200",
            "--seed",
            "3",
            "--out",
            "again.srdf"
        ],
    ));
    assert_eq!(
        std::fs::read(dir.join("again.srdf")).expect("again"),
        text.as_bytes()
    );

    let json = ok(&run_in(
        dir.path(),
        args!["robot", "check", &urdf, "--srdf", "g.srdf", "--json"],
    ));
    let doc: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    assert_eq!(doc["srdf_warnings"].as_array().map(Vec::len), Some(0));
    assert_eq!(doc["joints_without_limits"][0]["joint"], "j5");
    assert_eq!(doc["always_close"].as_array().map(Vec::len), Some(0));
    assert_eq!(doc["groups"][0]["tip"], "l5");
}

#[test]
fn robot_srdf_bad_input_exits_2() {
    let dir = Scratch::new("robot-srdf-bad");
    let urdf = dir.file("g.urdf", GRIPPER_ARM.as_bytes());
    let o = run_in(
        dir.path(),
        args!["robot", "srdf", &urdf, "--samples", "0", "--out", "x.srdf"],
    );
    // Out of range: a usage error from the flag's parser (clap adds a hint line).
    let usage = |o: &std::process::Output, needles: &[&str]| {
        let err = crate::support::stderr(o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(!err.contains("panicked"), "{err}");
        for n in needles {
            assert!(err.contains(n), "{n:?} not in {err}");
        }
    };
    usage(&o, &["--samples", "0 is not in [1, 1e7]"]);
    let o = run_in(
        dir.path(),
        args![
            "robot",
            "srdf",
            &urdf,
            "--min-collision-fraction",
            "0",
            "--out",
            "x.srdf"
        ],
    );
    usage(&o, &["--min-collision-fraction", "0 is not in (0, 1]"]);
    let broken = dir.file("broken.urdf", b"<robot name=\"b\"><link name=\"a\"/><joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"nope\"/></joint></robot>");
    let o = run_in(
        dir.path(),
        args!["robot", "srdf", &broken, "--out", "x.srdf"],
    );
    fails_with(&o, &["broken.urdf", "nope"]);
    assert!(!dir.join("x.srdf").exists());
}

#[test]
fn robot_check_reports_srdf_warnings_and_keeps_its_fields() {
    let dir = Scratch::new("robot-check");
    let srdf = std::fs::read_to_string(nx("nx-hiro.srdf")).expect("srdf");
    // The shipped SRDF with a virtual joint, an HPP gripper element and a prefix.
    let edited = srdf.replacen(
        "</robot>",
        r#"<virtual_joint name="world_joint" type="floating" parent_frame="world" child_link="WAIST"/>
           <gripper name="g" clearance="0.01"><link name="RARM_TCP"/></gripper></robot>"#,
        1,
    );
    let path = dir.file("nx.srdf", edited.as_bytes());
    let json = ok(&run_in(
        dir.path(),
        args![
            "robot",
            "check",
            nx("nx-hiro.urdf"),
            "--srdf",
            &path,
            "--json",
            "--samples",
            "20"
        ],
    ));
    let doc: serde_json::Value = serde_json::from_str(&json).expect("JSON");
    for field in [
        "format",
        "groups",
        "collision_matrix",
        "joints",
        "variables",
        "warnings",
    ] {
        assert!(doc.get(field).is_some(), "{field} kept");
    }
    let warnings = doc["srdf_warnings"].as_array().expect("warnings");
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    // The arms, each with its gripper measured on the URDF: NX-HIRO's prismatic fingers open
    // 0 to 80 mm, closed at 0 and open at 0.04 m, the tool point 0.1865 m out from the wrist.
    let arms = doc["arms"].as_array().expect("arms");
    let right = arms
        .iter()
        .find(|a| a["group"] == "right_arm")
        .expect("right_arm");
    let g = &right["gripper"];
    assert!(
        (g["opening_mm"][1].as_f64().expect("mm") - 80.0).abs() < 1e-6,
        "{g}"
    );
    assert_eq!(g["drives"][0]["joint"], "RARM_FINGER0_JOINT");
    assert_eq!(g["drives"][0]["closed"], 0.0);
    assert!((g["drives"][0]["open"].as_f64().expect("open") - 0.04).abs() < 1e-12);
    assert!(
        (g["tool_point"][0][0].as_f64().expect("x") + 0.1865).abs() < 0.02,
        "{g}"
    );
    let text = ok(&run_in(
        dir.path(),
        args![
            "robot",
            "check",
            nx("nx-hiro.urdf"),
            "--srdf",
            &path,
            "--samples",
            "20"
        ],
    ));
    assert!(
        text.contains("virtual joint \"world_joint\" (floating)"),
        "{text}"
    );
    assert!(text.contains("<gripper>"), "{text}");
    assert!(text.contains("gripper: opening 0.0 to 80.0 mm"), "{text}");
    // The SRDF details MoveIt ignores (issue 32): a group naming a joint the URDF does not
    // have, a group state naming a robot's toes, an end effector whose parent link is not a
    // link, a group state without a group. Each is left out with one warning naming it, in
    // the text and in the JSON; the arms and the collision pairs stay.
    let lenient = dir.file(
        "lenient.srdf",
        srdf.replacen(
            "</robot>",
            r#"<group name="x"><joint name="NO_SUCH_JOINT"/></group>
               <group_state name="half_sitting" group="right_arm"><joint name="RARM_JOINT0" value="0"/><joint name="LEFT_TOE" value="0"/></group_state>
               <end_effector name="foot" parent_link="left_sole" group="right_hand"/>
               <group_state name="nogroup"><joint name="RARM_JOINT0" value="0"/></group_state></robot>"#,
            1,
        )
        .as_bytes(),
    );
    let urdf = nx("nx-hiro.urdf");
    let check = |json: bool| {
        let mut a = args!["robot", "check", urdf, "--srdf", lenient, "--samples", "20"].to_vec();
        if json {
            a.push(std::ffi::OsStr::new("--json"));
        }
        ok(&run_in(dir.path(), &a))
    };
    let text = check(false);
    assert!(text.contains("SRDF warnings: 4"), "{text}");
    for needle in ["NO_SUCH_JOINT", "LEFT_TOE", "left_sole", "nogroup"] {
        assert_eq!(
            text.lines().filter(|l| l.contains(needle)).count(),
            1,
            "{needle}: {text}"
        );
    }
    let doc: serde_json::Value = serde_json::from_str(&check(true)).expect("JSON");
    assert_eq!(doc["srdf_warnings"].as_array().map(Vec::len), Some(4));
    assert_eq!(doc["arms"].as_array().map(Vec::len), Some(4));
    // XML that is not well-formed is refused, the file named once (not `P: P: …`).
    let broken = dir.file(
        "broken.srdf",
        b"<robot name=\"x\"><group name=\"a\"></robot>",
    );
    let o = run_in(
        dir.path(),
        args!["robot", "check", nx("nx-hiro.urdf"), "--srdf", &broken],
    );
    fails_with(&o, &["broken.srdf", "malformed XML"]);
    assert_eq!(crate::support::stderr(&o).matches("broken.srdf").count(), 1);
}
