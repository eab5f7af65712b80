//! A starting SRDF for a robot that has none, as MoveIt's setup assistant writes it:
//! disabled collision pairs from seeded random sampling ([`AllowedCollisionMatrix::generate`]
//! plus the pairs in collision at the zero pose), and a group per arm found in the tree
//! ([`detect_arms`]) with an end effector for its hand. Also the checks of
//! `pickplace robot check` that need sampling ([`always_close_pairs`]).

use crate::collision::{
    AcmOptions, AcmReport, AllowedCollisionMatrix, CheckOptions, CollisionScratch, CollisionWorld,
};
use crate::error::{Error, Result};
use crate::model::{JointValueSource, RobotModel};
use crate::rng::Rng;
use crate::srdf::{ChainSpec, DisableReason, EndEffector, GroupSpec, Srdf};
use pickplace_geometry::math::{Isometry3, Real};

/// Fewest actuated joints of an arm found by [`detect_arms`].
pub const MIN_ARM_JOINTS: usize = 4;

/// An arm found in the kinematic tree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct DetectedArm {
    /// The arm's actuated joints, shoulder first (joint indices).
    pub joints: Vec<usize>,
    /// The parent link of the first joint (the chain's base).
    pub base_link: usize,
    /// The child link of the last joint (the chain's tip, where the hand is attached).
    pub tip_link: usize,
    /// The hand's actuated joints (the fingers), in model order.
    pub finger_joints: Vec<usize>,
}

/// Finds the arms of a robot: [`crate::limbs::find_arms`] (serial chains of at least
/// [`MIN_ARM_JOINTS`] actuated joints ending in a parallel gripper that
/// [`crate::gripper::Gripper::derive`] accepts, cut where another actuated branch leaves),
/// with their joints as joint indices and the hand's actuated joints. Arms are returned in
/// the order of their last joint.
pub fn detect_arms(model: &RobotModel) -> Vec<DetectedArm> {
    let joints = model.joints();
    let mut arms: Vec<DetectedArm> = crate::limbs::find_arms(model, MIN_ARM_JOINTS)
        .into_iter()
        .map(|a| DetectedArm {
            joints: a
                .variables
                .iter()
                .map(|&v| model.variable_joints()[v])
                .collect(),
            base_link: a.base_link,
            tip_link: a.tip_link,
            finger_joints: (0..joints.len())
                .filter(|&k| {
                    matches!(joints[k].source, JointValueSource::Variable(_))
                        && model.is_ancestor(a.tip_link, joints[k].parent_link)
                })
                .collect(),
        })
        .collect();
    arms.sort_by_key(|a| a.joints.last().copied());
    arms
}

/// Options of [`starting_srdf`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StarterOptions {
    /// The sampling of the collision matrix (default: [`AcmOptions::default`], 10 000
    /// samples, seed 0).
    pub acm: AcmOptions,
}

/// What [`starting_srdf`] made.
#[derive(Debug, Clone, PartialEq)]
pub struct StarterSrdf {
    /// The SRDF: groups `arm_<n>` and `hand_<n>`, end effectors `hand_<n>`, disabled pairs.
    pub srdf: Srdf,
    /// The arms found.
    pub arms: Vec<DetectedArm>,
    /// Link pairs that collided in some but not all samples (checked), with the count.
    pub sometimes: Vec<(String, String, usize)>,
    /// Configurations sampled.
    pub samples: usize,
}

impl StarterSrdf {
    /// The SRDF as XML text, with a comment saying how it was made (samples, seed, the
    /// meaning of each reason, the arm rule).
    pub fn to_xml(&self, seed: u64) -> String {
        let comment = format!(
            "<!-- Starting SRDF written by `pickplace robot srdf` ({} random configurations, seed {seed}).\n     \
             disable_collisions reasons: Adjacent = joined by a joint; Default = in collision at the zero pose;\n     \
             Always = in collision in at least the given fraction of the samples (default 95 %); Never = in no sample.\n     \
             Groups arm_<n>: serial chains of >= {MIN_ARM_JOINTS} actuated joints ending at a hand with finger joints\n     \
             (group hand_<n>, end effector hand_<n>). Review before use. -->\n",
            self.samples
        );
        self.srdf.to_xml_with_comment(&comment)
    }
}

/// MoveIt's sampled collision matrix for `model`: [`AllowedCollisionMatrix::generate`]
/// (`Adjacent`, `Always` at or above `options.min_collision_fraction` of the samples,
/// `Never`), then the pairs in collision at the zero configuration become `Default`
/// (MoveIt's order: Adjacent, Default, the sampled reasons). What `pickplace robot srdf`
/// writes and what the planner uses when a robot comes without a matrix.
///
/// # Errors
/// As [`AllowedCollisionMatrix::generate`] (zero samples, a fraction outside (0, 1],
/// collision-library errors).
pub fn sampled_matrix(model: &RobotModel, options: &AcmOptions) -> Result<AcmReport> {
    let mut report = AllowedCollisionMatrix::generate(model, options)?;
    let world = CollisionWorld::new(model, AllowedCollisionMatrix::new())?;
    let mut scratch = CollisionScratch::default();
    let mut poses = vec![Isometry3::identity(); model.links().len()];
    model.forward_kinematics(&model.zero_configuration(), &mut poses)?;
    let names = |a: usize, b: usize| (&model.links()[a].name, &model.links()[b].name);
    for (a, b) in world.colliding_link_pairs_all(&poses, &mut scratch)? {
        let (na, nb) = names(a, b);
        if report.acm.reason(na, nb) != Some(&DisableReason::Adjacent) {
            report.acm.allow(na, nb, DisableReason::Default);
            report
                .sometimes
                .retain(|(x, y, _)| !((x == na && y == nb) || (x == nb && y == na)));
        }
    }
    Ok(report)
}

/// A starting SRDF for `model`: MoveIt's disabled pairs ([`sampled_matrix`]) and a group,
/// a hand group and an end effector per detected arm.
///
/// # Errors
/// As [`sampled_matrix`].
pub fn starting_srdf(model: &RobotModel, options: &StarterOptions) -> Result<StarterSrdf> {
    let report = sampled_matrix(model, &options.acm)?;
    let arms = detect_arms(model);
    let mut srdf = Srdf {
        robot_name: model.name().to_owned(),
        disabled_collisions: report.acm.to_disabled_pairs(),
        ..Srdf::default()
    };
    for (n, arm) in arms.iter().enumerate() {
        let link = |l: usize| model.links()[l].name.clone();
        srdf.groups.push(GroupSpec {
            name: format!("arm_{n}"),
            chains: vec![ChainSpec {
                base_link: link(arm.base_link),
                tip_link: link(arm.tip_link),
            }],
            ..GroupSpec::default()
        });
        srdf.groups.push(GroupSpec {
            name: format!("hand_{n}"),
            joints: arm
                .finger_joints
                .iter()
                .map(|&j| model.joints()[j].name.clone())
                .collect(),
            ..GroupSpec::default()
        });
        srdf.end_effectors.push(EndEffector {
            name: format!("hand_{n}"),
            parent_link: link(arm.tip_link),
            group: format!("hand_{n}"),
            parent_group: Some(format!("arm_{n}")),
        });
    }
    Ok(StarterSrdf {
        srdf,
        arms,
        sometimes: report.sometimes,
        samples: report.samples,
    })
}

/// Options of [`always_close_pairs`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CloseOptions {
    /// Random configurations sampled, uniform within the limits (default: 200).
    pub samples: usize,
    /// Seed of the sampling (default: 0).
    pub seed: u64,
    /// Pairs closer than this (m) count as close (default: 0.01).
    pub distance: Real,
}

impl Default for CloseOptions {
    fn default() -> Self {
        Self {
            samples: 200,
            seed: 0,
            distance: 0.01,
        }
    }
}

/// Link pairs that `acm` checks but that are closer than `options.distance` in every
/// sampled configuration (and at the zero configuration): a collision checker will reject
/// every state, so the pair most likely belongs in the SRDF's `disable_collisions`.
/// Sorted by name.
///
/// # Errors
/// [`Error::InvalidParameter`] for zero samples or a bad distance; collision-library errors.
pub fn always_close_pairs(
    model: &RobotModel,
    acm: &AllowedCollisionMatrix,
    options: &CloseOptions,
) -> Result<Vec<(String, String)>> {
    if options.samples == 0 {
        return Err(Error::InvalidParameter {
            name: "samples",
            value: 0.0,
            reason: "at least one configuration must be sampled",
        });
    }
    let world = CollisionWorld::new(model, acm.clone())?;
    let mut scratch = CollisionScratch::default();
    let check = CheckOptions {
        margin: options.distance,
    };
    let mut candidates =
        world.colliding_pairs(model, &model.zero_configuration(), &mut scratch, &check)?;
    let mut rng = Rng::new(options.seed);
    let limits = model.sampling_limits();
    let mut q = vec![0.0; model.variable_count()];
    for _ in 0..options.samples {
        if candidates.is_empty() {
            break;
        }
        for (value, &(lower, upper)) in q.iter_mut().zip(&limits) {
            *value = rng.uniform(lower, upper);
        }
        let close = world.colliding_pairs(model, &q, &mut scratch, &check)?;
        candidates.retain(|pair| close.contains(pair));
    }
    let mut out: Vec<(String, String)> = candidates
        .into_iter()
        .map(|(a, b)| {
            let (a, b) = (world.body_name(a).to_owned(), world.body_name(b).to_owned());
            if a <= b { (a, b) } else { (b, a) }
        })
        .collect();
    out.sort();
    out.dedup();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use std::path::Path;

    /// A torso with two five-joint arms, each with a two-finger gripper (finger boxes: the
    /// gripper is measured on them), and a head.
    fn two_arms() -> String {
        let mut links =
            String::from(r#"<link name="base"/><link name="torso"/><link name="head"/>"#);
        let mut joints = String::from(
            r#"<joint name="waist" type="revolute"><parent link="base"/><child link="torso"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>
               <joint name="neck" type="revolute"><parent link="torso"/><child link="head"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#,
        );
        for side in ["l", "r"] {
            let mut parent = "torso".to_owned();
            for k in 0..5 {
                let link = format!("{side}{k}");
                links.push_str(&format!(r#"<link name="{link}"/>"#));
                joints.push_str(&format!(
                    r#"<joint name="{side}_j{k}" type="revolute"><parent link="{parent}"/><child link="{link}"/><origin xyz="0.1 0 0"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#
                ));
                parent = link;
            }
            links.push_str(&format!(
                r#"<link name="{side}_palm"/>
                   <link name="{side}_fa"><collision><origin xyz="0.03 0.005 0"/><geometry><box size="0.06 0.01 0.02"/></geometry></collision></link>
                   <link name="{side}_fb"><collision><origin xyz="0.03 -0.005 0"/><geometry><box size="0.06 0.01 0.02"/></geometry></collision></link>"#
            ));
            joints.push_str(&format!(
                r#"<joint name="{side}_palm_joint" type="fixed"><parent link="{parent}"/><child link="{side}_palm"/></joint>
                   <joint name="{side}_fa_joint" type="prismatic"><parent link="{side}_palm"/><child link="{side}_fa"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
                   <joint name="{side}_fb_joint" type="prismatic"><parent link="{side}_palm"/><child link="{side}_fb"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/><mimic joint="{side}_fa_joint"/></joint>"#
            ));
        }
        format!(r#"<robot name="two">{links}{joints}</robot>"#)
    }

    #[test]
    fn both_arms_are_found_without_the_torso_or_the_head() {
        let model = RobotModel::from_urdf_str(&two_arms(), Path::new("."), &LoadOptions::default())
            .expect("valid");
        let arms = detect_arms(&model);
        assert_eq!(arms.len(), 2);
        for (arm, side) in arms.iter().zip(["l", "r"]) {
            let names: Vec<&str> = arm
                .joints
                .iter()
                .map(|&j| model.joints()[j].name.as_str())
                .collect();
            assert_eq!(
                names,
                (0..5).map(|k| format!("{side}_j{k}")).collect::<Vec<_>>()
            );
            assert_eq!(model.links()[arm.base_link].name, "torso");
            assert_eq!(model.links()[arm.tip_link].name, format!("{side}4"));
            assert_eq!(arm.finger_joints.len(), 1);
        }
        let starter = starting_srdf(
            &model,
            &StarterOptions {
                acm: AcmOptions {
                    samples: 10,
                    seed: 1,
                    ..AcmOptions::default()
                },
            },
        )
        .expect("srdf");
        let xml = starter.to_xml(1);
        assert!(xml.contains("seed 1") && xml.contains("arm_1"), "{xml}");
        // What was written resolves against the model, and each arm is a chain with a hand.
        let srdf = Srdf::from_xml_str(&xml).expect("parses");
        let semantics =
            crate::Semantics::resolve(&model, &srdf, Path::new("x.srdf")).expect("resolves");
        assert!(semantics.warnings().is_empty());
        let chain = semantics.chain(&model, "arm_0").expect("chain");
        assert_eq!(chain.variables().len(), 5);
        assert_eq!(
            semantics.end_effector_of("arm_1").map(|e| e.name.as_str()),
            Some("hand_1")
        );
    }

    #[test]
    fn a_plain_six_joint_arm_is_not_an_arm_with_a_hand() {
        let mut text = String::from(r#"<robot name="six"><link name="l0"/>"#);
        for k in 1..=6 {
            text.push_str(&format!(
                r#"<link name="l{k}"/><joint name="j{k}" type="revolute"><parent link="l{}"/><child link="l{k}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#,
                k - 1
            ));
        }
        text.push_str("</robot>");
        let model = RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default())
            .expect("valid");
        assert!(detect_arms(&model).is_empty());
    }
}
