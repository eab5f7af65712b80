//! Several robots in one model: [`RobotModel::combine`] puts parts side by side under a new
//! root link `world`, every name prefixed (two Pandas as `left/` and `right/`). The SRDF of
//! the whole is [`Srdf::prefixed`](crate::Srdf::prefixed) per part, then
//! [`Srdf::merge`](crate::Srdf::merge).

use crate::error::{Error, ModelErrorKind, Result};
use crate::model::{Joint, JointValueSource, Link, LoadWarning, RobotModel};
use pickplace_geometry::math::Isometry3;
use std::collections::BTreeSet;
use std::path::PathBuf;

/// The name of the root link of a combined model.
pub const COMBINED_ROOT: &str = "world";

impl RobotModel {
    /// One model holding every part, each under its prefix: a new root link `world` (no
    /// geometry) with a fixed joint `<prefix>world_joint` to each part's root, placed at
    /// `world_from_part_root`. Every link and joint name is prefixed; mimic joints follow
    /// their prefixed joint. Variables are the parts' variables in the parts' order.
    ///
    /// # Arguments
    /// * `name`: the combined robot's name.
    /// * `parts`: `(prefix, model, world_from_part_root)` for each part.
    ///
    /// # Errors
    /// [`Error::InvalidModel`] (path `<combined NAME>`) when there is no part
    /// ([`ModelErrorKind::NoLinks`]), when two names are equal after prefixing (also with
    /// `world`) ([`ModelErrorKind::DuplicateLink`], [`ModelErrorKind::DuplicateJoint`]), or
    /// when a placement is not finite ([`ModelErrorKind::NonFinite`]).
    pub fn combine(name: &str, parts: &[(String, &RobotModel, Isometry3)]) -> Result<RobotModel> {
        let path = PathBuf::from(format!("<combined {name}>"));
        let invalid = |kind| Error::InvalidModel {
            path: path.clone(),
            kind,
        };
        if parts.is_empty() {
            return Err(invalid(ModelErrorKind::NoLinks));
        }
        let mut link_names: BTreeSet<String> = BTreeSet::from([COMBINED_ROOT.to_owned()]);
        let mut joint_names: BTreeSet<String> = BTreeSet::new();
        let mut links = vec![Link {
            name: COMBINED_ROOT.to_owned(),
            parent_joint: None,
            collisions: Vec::new(),
            visuals: Vec::new(),
        }];
        let mut joints: Vec<Joint> = Vec::new();
        let mut warnings = Vec::new();
        let mut variable_offset = 0;
        for (prefix, model, world_from_root) in parts {
            let finite = world_from_root
                .translation
                .vector
                .iter()
                .all(|x| x.is_finite())
                && world_from_root
                    .rotation
                    .coords
                    .iter()
                    .all(|x| x.is_finite());
            let world_joint = format!("{prefix}world_joint");
            if !finite {
                return Err(invalid(ModelErrorKind::NonFinite {
                    element: "joint",
                    name: world_joint,
                    field: "origin",
                }));
            }
            let link_offset = links.len();
            // The part's joint `j` becomes `joint_offset + j`; the world joint sits just
            // before, so that joint `k` still moves link `k + 1`.
            let joint_offset = joints.len() + 1;
            if !joint_names.insert(world_joint.clone()) {
                return Err(invalid(ModelErrorKind::DuplicateJoint {
                    name: world_joint,
                }));
            }
            joints.push(Joint::fixed(
                world_joint,
                0,
                link_offset + model.root(),
                *world_from_root,
            ));
            for link in model.links() {
                let name = format!("{prefix}{}", link.name);
                if !link_names.insert(name.clone()) {
                    return Err(invalid(ModelErrorKind::DuplicateLink { name }));
                }
                links.push(Link {
                    name,
                    parent_joint: Some(match link.parent_joint {
                        Some(j) => joint_offset + j,
                        None => joint_offset - 1,
                    }),
                    collisions: link.collisions.clone(),
                    visuals: link.visuals.clone(),
                });
            }
            for joint in model.joints() {
                let name = format!("{prefix}{}", joint.name);
                if !joint_names.insert(name.clone()) {
                    return Err(invalid(ModelErrorKind::DuplicateJoint { name }));
                }
                let mut joint = joint.clone();
                joint.name = name;
                joint.parent_link += link_offset;
                joint.child_link += link_offset;
                if let Some(mimic) = &mut joint.mimic {
                    mimic.joint += joint_offset;
                }
                joint.source = match joint.source {
                    JointValueSource::Fixed => JointValueSource::Fixed,
                    JointValueSource::Variable(v) => {
                        JointValueSource::Variable(v + variable_offset)
                    }
                    JointValueSource::Mimic {
                        variable,
                        multiplier,
                        offset,
                    } => JointValueSource::Mimic {
                        variable: variable + variable_offset,
                        multiplier,
                        offset,
                    },
                };
                joints.push(joint);
            }
            variable_offset += model.variable_count();
            warnings.extend(model.warnings().iter().map(|w| prefixed_warning(w, prefix)));
        }
        Ok(RobotModel::from_parts(
            name.to_owned(),
            path,
            links,
            joints,
            warnings,
        ))
    }
}

fn prefixed_warning(warning: &LoadWarning, prefix: &str) -> LoadWarning {
    match warning {
        LoadWarning::SkippedMesh {
            link,
            usage,
            uri,
            reason,
            fix,
        } => LoadWarning::SkippedMesh {
            link: format!("{prefix}{link}"),
            usage: *usage,
            uri: uri.clone(),
            reason: reason.clone(),
            fix: fix.clone(),
        },
        LoadWarning::FrozenJoint { joint } => LoadWarning::FrozenJoint {
            joint: format!("{prefix}{joint}"),
        },
        // The mimicked name is not a joint of the model: it keeps its spelling.
        LoadWarning::MimicOfUnknownJoint { joint, mimicked } => LoadWarning::MimicOfUnknownJoint {
            joint: format!("{prefix}{joint}"),
            mimicked: mimicked.clone(),
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use crate::srdf::{Semantics, Srdf};
    use std::path::Path;

    const TINY: &str = r#"<robot name="tiny">
  <link name="base"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <link name="upper"/>
  <link name="lower"/>
  <link name="finger"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="lower"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" velocity="1" effort="1"/></joint>
  <joint name="finger_joint" type="prismatic"><parent link="lower"/><child link="finger"/>
    <origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/>
    <mimic joint="elbow" multiplier="0.01"/></joint>
</robot>"#;

    const TINY_SRDF: &str = r#"<robot name="tiny">
  <group name="arm"><joint name="shoulder"/><joint name="elbow"/></group>
  <group_state name="home" group="arm"><joint name="elbow" value="0.5"/></group_state>
  <end_effector name="hand" parent_link="lower" group="arm"/>
  <disable_collisions link1="base" link2="upper" reason="Adjacent"/>
</robot>"#;

    fn tiny() -> RobotModel {
        RobotModel::from_urdf_str(TINY, Path::new("."), &LoadOptions::default()).expect("tiny")
    }

    #[test]
    fn two_copies_side_by_side() {
        let model = tiny();
        let left = Isometry3::translation(0.0, 0.5, 0.0);
        let right = Isometry3::translation(0.0, -0.5, 0.0);
        let both = RobotModel::combine(
            "pair",
            &[
                ("left/".to_owned(), &model, left),
                ("right/".to_owned(), &model, right),
            ],
        )
        .expect("combined");
        assert_eq!(both.links().len(), 1 + 2 * model.links().len());
        assert_eq!(both.links()[both.root()].name, COMBINED_ROOT);
        assert_eq!(both.variable_count(), 2 * model.variable_count());
        assert_eq!(
            both.variable_names().collect::<Vec<_>>(),
            [
                "left/shoulder",
                "left/elbow",
                "right/shoulder",
                "right/elbow"
            ]
        );
        assert!(both.joint_index("left/world_joint").is_some());
        // Every link after its parent, joint k moves link k + 1.
        for (k, joint) in both.joints().iter().enumerate() {
            assert_eq!(joint.child_link, k + 1);
            assert!(joint.parent_link < joint.child_link);
            assert_eq!(both.links()[k + 1].parent_joint, Some(k));
        }
        // The mimic joint of the right copy follows the right elbow.
        let finger = both.joint_index("right/finger_joint").expect("finger");
        let elbow = both.joint_index("right/elbow").expect("elbow");
        assert_eq!(both.joints()[finger].mimic.map(|m| m.joint), Some(elbow));
        // FK: each copy is its own model moved by its placement.
        let mut q = both.zero_configuration();
        q[both.variable_index("right/elbow").expect("var")] = 0.7;
        let poses = both.link_poses(&q).expect("fk");
        let mut q1 = model.zero_configuration();
        q1[model.variable_index("elbow").expect("var")] = 0.7;
        let moved = model.link_poses(&q1).expect("fk");
        let still = model.link_poses(&model.zero_configuration()).expect("fk");
        for (l, link) in model.links().iter().enumerate() {
            for (prefix, place, single) in [("right/", right, &moved), ("left/", left, &still)] {
                let combined = both
                    .link_index(&format!("{prefix}{}", link.name))
                    .expect("link");
                let expected = place * single[l];
                assert!(
                    (poses[combined].translation.vector - expected.translation.vector).norm()
                        < 1e-12
                );
                assert!(poses[combined].rotation.angle_to(&expected.rotation) < 1e-12);
            }
        }

        // The SRDF of the pair resolves against the pair.
        let srdf = Srdf::from_xml_str(TINY_SRDF).expect("srdf");
        let pair = Srdf::merge(&[srdf.prefixed("left/"), srdf.prefixed("right/")], "pair");
        assert_eq!(pair.groups.len(), 2);
        let semantics = Semantics::resolve(&both, &pair, Path::new("pair.srdf")).expect("resolves");
        let chain = semantics.chain(&both, "right/arm").expect("a chain");
        assert_eq!(both.links()[chain.tip_link()].name, "right/lower");
        assert_eq!(
            semantics
                .end_effector_of("left/arm")
                .map(|e| e.name.as_str()),
            Some("left/hand")
        );
        assert_eq!(pair.disabled_collisions[1].link1, "right/base");
    }

    #[test]
    fn duplicate_names_after_prefixing_are_an_error() {
        let model = tiny();
        let error = RobotModel::combine(
            "pair",
            &[
                ("a/".to_owned(), &model, Isometry3::identity()),
                ("a/".to_owned(), &model, Isometry3::identity()),
            ],
        )
        .expect_err("same prefix twice");
        assert!(error.to_string().contains("a/world_joint"), "{error}");
        let error = RobotModel::combine("none", &[]).expect_err("no part");
        assert!(error.to_string().contains("<combined none>"), "{error}");
    }
}
