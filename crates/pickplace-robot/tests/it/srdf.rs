//! SRDF parsing and resolution.

use crate::common::nx;
use pickplace_robot::error::{Error, SrdfErrorKind};
use pickplace_robot::srdf::{DisableReason, Semantics, Srdf};
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
fn bad_srdf_errors_name_the_problem() {
    let (model, _) = nx();
    let unknown = Srdf::from_xml_str(
        r#"<robot><group name="g"><chain base_link="WAIST" tip_link="NOSE"/></group></robot>"#,
    )
    .expect("xml ok");
    let e = Semantics::resolve(model, &unknown, Path::new("x.srdf")).expect_err("unknown link");
    assert!(
        matches!(&e, Error::Srdf { kind: SrdfErrorKind::UnknownName { name, .. }, .. } if name == "NOSE"),
        "{e:?}"
    );
    assert!(e.to_string().contains("x.srdf"));
    let backwards = Srdf::from_xml_str(
        r#"<robot><group name="g"><chain base_link="RARM_TCP" tip_link="WAIST"/></group></robot>"#,
    )
    .expect("xml");
    assert!(matches!(
        Semantics::resolve(model, &backwards, Path::new("x")),
        Err(Error::Srdf {
            kind: SrdfErrorKind::BadChain { .. },
            ..
        })
    ));
    let recursive = Srdf::from_xml_str(r#"<robot><group name="g"><group name="h"/></group><group name="h"><group name="g"/></group></robot>"#).expect("xml");
    assert!(matches!(
        Semantics::resolve(model, &recursive, Path::new("x")),
        Err(Error::Srdf {
            kind: SrdfErrorKind::RecursiveGroup { .. },
            ..
        })
    ));
    assert!(matches!(
        Srdf::from_xml_str("<robot><group></robot>"),
        Err(Error::Srdf { .. })
    ));
    assert!(matches!(
        Srdf::from_xml_str(
            r#"<robot><group name="g"/><group_state name="s" group="g"><joint name="j" value="x"/></group_state></robot>"#
        ),
        Err(Error::Srdf {
            kind: SrdfErrorKind::BadNumber { .. },
            ..
        })
    ));
}
