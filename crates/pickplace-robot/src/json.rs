//! The robot's JSON documents, printed by `pickplace robot check | fk | ik --json`: a model
//! summary ([`CheckJson`]), forward kinematics ([`FkJson`]) and an IK solution ([`IkJson`]),
//! with their format constants.
//!
//! The fields of every object are declared, and so printed, in alphabetical order, as these
//! documents have been written since their first version.

use crate::assistant::{CloseOptions, always_close_pairs, sampled_matrix};
use crate::collision::{
    AcmOptions, AllowedCollisionMatrix, CheckOptions, CollisionScratch, CollisionWorld,
};
use crate::error::Result;
use crate::ik::IkSolution;
use crate::model::RobotModel;
use crate::model::{JointType, LoadWarning};
use crate::srdf::Semantics;
use pickplace_geometry::math::{Isometry3, Real};
use std::collections::BTreeMap;
use std::path::Path;

/// The `format` of [`CheckJson`].
pub const CHECK_JSON_FORMAT: &str = "pickplace.robot.check/1";
/// The `format` of [`FkJson`].
pub const FK_JSON_FORMAT: &str = "pickplace.robot.fk/1";
/// The `format` of [`IkJson`].
pub const IK_JSON_FORMAT: &str = "pickplace.robot.ik/1";

/// A pose in the root frame: orientation quaternion `[x, y, z, w]` and position (m).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct LinkPoseJson {
    /// Unit quaternion, ROS order `[x, y, z, w]`.
    pub orientation: [Real; 4],
    /// Translation (m).
    pub position: [Real; 3],
}

impl From<&Isometry3> for LinkPoseJson {
    fn from(pose: &Isometry3) -> Self {
        let t = pose.translation.vector;
        let r = pose.rotation.coords;
        Self {
            orientation: [r.x, r.y, r.z, r.w],
            position: [t.x, t.y, t.z],
        }
    }
}

/// `pickplace robot fk`: the pose of every link in the root frame.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FkJson {
    /// Always [`FK_JSON_FORMAT`].
    pub format: &'static str,
    /// `root_from_link` of every link, by name.
    pub links: BTreeMap<String, LinkPoseJson>,
    /// The root link's name.
    pub root: String,
}

impl FkJson {
    /// Forward kinematics of `model` at `q`.
    ///
    /// # Errors
    /// As [`RobotModel::link_poses`] (wrong length, values out of limits).
    pub fn new(model: &RobotModel, q: &[Real]) -> Result<Self> {
        let poses = model.link_poses(q)?;
        Ok(Self {
            format: FK_JSON_FORMAT,
            links: model
                .links()
                .iter()
                .zip(&poses)
                .map(|(l, p)| (l.name.clone(), p.into()))
                .collect(),
            root: model.links()[model.root()].name.clone(),
        })
    }
}

/// `pickplace robot ik`: the solution of one IK query.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct IkJson {
    /// Attempts made (1 + restarts).
    pub attempts: usize,
    /// Always [`IK_JSON_FORMAT`].
    pub format: &'static str,
    /// The planning group solved for.
    pub group: String,
    /// TCP orientation error (rad).
    pub orientation_error: Real,
    /// TCP position error (m).
    pub position_error: Real,
    /// Every variable's value, by joint name.
    pub positions: BTreeMap<String, Real>,
    /// Why there is no solution, when there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// Whether both tolerances are met.
    pub success: bool,
}

impl IkJson {
    /// The document of `solution` for `group` of `model`.
    pub fn new(model: &RobotModel, group: &str, solution: &IkSolution) -> Self {
        Self {
            attempts: solution.attempts,
            format: IK_JSON_FORMAT,
            group: group.to_owned(),
            orientation_error: solution.orientation_error,
            position_error: solution.position_error,
            positions: model
                .variable_names()
                .zip(&solution.positions)
                .map(|(n, v)| (n.to_owned(), *v))
                .collect(),
            reason: (!solution.success).then(|| {
                format!(
                    "no solution within tolerances after {} attempts (best: position error {:.3e} m, orientation error {:.3e} rad); the pose may be out of reach",
                    solution.attempts, solution.position_error, solution.orientation_error
                )
            }),
            success: solution.success,
        }
    }
}

/// One joint in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct JointJson {
    /// Child link.
    pub child: String,
    /// Lower limit (rad or m), none when unlimited.
    pub lower: Option<Real>,
    /// The joint this one copies, if it is a mimic joint.
    pub mimic: Option<String>,
    /// Name.
    pub name: String,
    /// Parent link.
    pub parent: String,
    /// URDF joint type.
    #[serde(rename = "type")]
    pub joint_type: &'static str,
    /// Upper limit (rad or m), none when unlimited.
    pub upper: Option<Real>,
    /// Velocity limit (rad/s or m/s).
    pub velocity: Real,
}

/// One planning group in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GroupJson {
    /// The group's actuated joints.
    pub joints: Vec<String>,
    /// Name.
    pub name: String,
    /// The tip link, if the group is a chain.
    pub tip: Option<String>,
}

/// One arm in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ArmJson {
    /// The group (or `arm_<tip link>` for an arm found in the URDF).
    pub group: String,
    /// The arm's actuated joints, root side first.
    pub joints: Vec<String>,
    /// The arm's last moving link, where the hand hangs.
    pub tip_link: Option<String>,
    /// The SRDF end effector of the group, if any.
    pub end_effector: Option<String>,
    /// The gripper, as measured.
    pub gripper: Option<GripperJson>,
    /// Why the gripper could not be measured.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gripper_error: Option<String>,
}

/// The gripper of an arm in [`CheckJson`], as measured on the URDF.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GripperJson {
    /// Opening between the pads, closed and fully open (mm).
    pub opening_mm: [Real; 2],
    /// The actuated joints that close it, each with its value closed and open.
    pub drives: Vec<DriveJson>,
    /// The finger links of each side.
    pub fingers: [Vec<String>; 2],
    /// The tool point in the tip link's frame: position (m) and orientation `[x, y, z, w]`
    /// (z the approach direction, y the closing direction).
    pub tool_point: ([Real; 3], [Real; 4]),
}

/// A gripper drive in [`GripperJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct DriveJson {
    /// The joint.
    pub joint: String,
    /// Its value when closed.
    pub closed: Real,
    /// Its value when fully open.
    pub open: Real,
}

/// A result as the JSON's pair of optional fields: the value, or the error's message.
fn split<T, E: std::fmt::Display>(r: std::result::Result<T, E>) -> (Option<T>, Option<String>) {
    match r {
        Ok(t) => (Some(t), None),
        Err(e) => (None, Some(e.to_string())),
    }
}

/// The arms of a robot for [`CheckJson::arms`].
fn arms_report(model: &RobotModel, semantics: Option<&Semantics>) -> Vec<ArmJson> {
    use crate::gripper::{Gripper, GripperOptions};
    use crate::limbs::find_arms;
    let name = |l: usize| model.links()[l].name.clone();
    let gripper =
        |variables: &[usize]| -> std::result::Result<GripperJson, crate::gripper::GripperError> {
            let g = Gripper::derive(model, variables, &GripperOptions::default())?;
            let (lo, hi) = g.opening_range();
            let t = g.tip_from_tcp();
            let q = t.rotation.quaternion();
            Ok(GripperJson {
                opening_mm: [lo * 1e3, hi * 1e3],
                drives: g
                    .drives()
                    .iter()
                    .map(|d| DriveJson {
                        joint: model.variable_joint(d.variable).name.clone(),
                        closed: d.closed,
                        open: d.open,
                    })
                    .collect(),
                fingers: g
                    .finger_links()
                    .clone()
                    .map(|side| side.into_iter().map(name).collect()),
                tool_point: (
                    [t.translation.x, t.translation.y, t.translation.z],
                    [q.i, q.j, q.k, q.w],
                ),
            })
        };
    let tip_of = |variables: &[usize]| {
        variables
            .iter()
            .map(|&v| model.variable_joint(v).child_link)
            .max_by_key(|&l| model.joint_path(l).len())
    };
    let mut arms = Vec::new();
    if let Some(semantics) = semantics {
        for g in semantics.groups() {
            if g.variables.len() < crate::assistant::MIN_ARM_JOINTS {
                continue;
            }
            let report = gripper(&g.variables);
            // Whole-body groups (several chains) are not arms: keep groups whose gripper was
            // measured, and report the others only when they are one chain.
            let one_chain = semantics.chain(model, &g.name).is_ok();
            if report.is_err() && !one_chain {
                continue;
            }
            let (gripper, gripper_error) = split(report);
            arms.push(ArmJson {
                group: g.name.clone(),
                joints: g
                    .variables
                    .iter()
                    .map(|&v| model.variable_joint(v).name.clone())
                    .collect(),
                tip_link: tip_of(&g.variables).map(name),
                end_effector: semantics.end_effector_of(&g.name).map(|e| e.name.clone()),
                gripper,
                gripper_error,
            });
        }
    }
    if arms.iter().all(|a| a.gripper.is_none()) {
        for a in find_arms(model, crate::assistant::MIN_ARM_JOINTS) {
            let (gripper, gripper_error) = split(gripper(&a.variables));
            arms.push(ArmJson {
                group: format!("arm_{}", name(a.tip_link)),
                joints: a
                    .variables
                    .iter()
                    .map(|&v| model.variable_joint(v).name.clone())
                    .collect(),
                tip_link: Some(name(a.tip_link)),
                end_effector: None,
                gripper,
                gripper_error,
            });
        }
    }
    arms
}

/// The collision matrix summary in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CollisionMatrixJson {
    /// Disabled pairs per SRDF reason.
    pub by_reason: BTreeMap<String, usize>,
    /// Pairs of collision shapes the world checks against each other.
    pub checked_shape_pairs: usize,
    /// Disabled link pairs.
    pub disabled_pairs: usize,
    /// Pairs of links that both have collision geometry.
    pub link_pairs_with_geometry: usize,
}

/// A pair of links that the SRDF lets collide-check but that is always close, in
/// [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ClosePairJson {
    /// The SRDF line that disables the pair.
    pub fix: String,
    /// First link.
    pub link1: String,
    /// Second link.
    pub link2: String,
}

/// A joint with missing limits, in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct JointIssueJson {
    /// What to change in the URDF.
    pub fix: String,
    /// The joint.
    pub joint: String,
    /// What is missing.
    pub problem: String,
}

/// A mesh the loader could not read (and skipped), in [`CheckJson`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct UnreadableMeshJson {
    /// What to do about it.
    pub fix: String,
    /// The link.
    pub link: String,
    /// Why it could not be read.
    pub reason: String,
    /// The `filename` as written in the URDF.
    pub uri: String,
}

/// `pickplace robot check`: a summary of a URDF (and SRDF) with warnings.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CheckJson {
    /// The arms found: the SRDF's groups that end in a parallel gripper (or, without an SRDF
    /// or such groups, the chains found in the URDF), each with its end effector, tool point
    /// and gripper; groups of four or more joints whose gripper could not be measured, with
    /// the reason.
    pub arms: Vec<ArmJson>,
    /// Link pairs checked for collision (not disabled in the SRDF) that are closer than
    /// the close distance at every sampled configuration (with an SRDF).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub always_close: Option<Vec<ClosePairJson>>,
    /// The collision matrix (with an SRDF).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub collision_matrix: Option<CollisionMatrixJson>,
    /// Always [`CHECK_JSON_FORMAT`].
    pub format: &'static str,
    /// The planning groups (with an SRDF).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub groups: Option<Vec<GroupJson>>,
    /// Every joint.
    pub joints: Vec<JointJson>,
    /// Actuated joints with missing limits (continuous joints, no position range, no
    /// velocity limit).
    pub joints_without_limits: Vec<JointIssueJson>,
    /// Number of links.
    pub links: usize,
    /// Chains of four or more actuated joints that are not usable arms, each with one reason
    /// ([`crate::limbs::unusable_limbs`]).
    pub not_arms: Vec<NotArmJson>,
    /// The robot's name.
    pub robot: String,
    /// The root link's name.
    pub root: String,
    /// With no SRDF, or an SRDF without `disable_collisions`: the matrix the planner
    /// samples for the robot ([`crate::assistant::sampled_matrix`]), with the lines to add
    /// to an SRDF to keep it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sampled_collision_matrix: Option<SampledMatrixJson>,
    /// Links whose collision meshes the loader split into convex pieces so that a hand with
    /// one moving jaw could be measured ([`RobotModel::split_links`]).
    pub split_links: Vec<crate::gripper::SplitLink>,
    /// The SRDF file, if one was given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub srdf: Option<String>,
    /// What the SRDF resolution accepted with a change of meaning
    /// ([`Semantics::warnings`]), with an SRDF.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub srdf_warnings: Option<Vec<String>>,
    /// Meshes the loader skipped.
    pub unreadable_meshes: Vec<UnreadableMeshJson>,
    /// The URDF file.
    pub urdf: String,
    /// Actuated joints, in configuration order.
    pub variables: Vec<String>,
    /// Loading warnings, and named states in self-collision.
    pub warnings: Vec<String>,
}

/// A chain that is not a usable arm, in [`CheckJson::not_arms`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct NotArmJson {
    /// The link where the chain starts.
    pub base_link: String,
    /// Its actuated joints, from the base.
    pub joints: Vec<String>,
    /// Why it is not an arm.
    pub reason: String,
    /// Its last link.
    pub tip_link: String,
}

/// [`CheckJson::sampled_collision_matrix`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SampledMatrixJson {
    /// Pairs never checked, by reason (`Adjacent`, `Default`, `Always`, `Never`).
    pub by_reason: BTreeMap<String, usize>,
    /// Pairs never checked.
    pub disabled_pairs: usize,
    /// The fraction of the samples from which a pair counts as always in collision.
    pub min_collision_fraction: Real,
    /// Configurations sampled.
    pub samples: usize,
    /// Seed of the sampling.
    pub seed: u64,
    /// Link pairs still checked that collided in some samples.
    pub sometimes_in_collision: usize,
    /// The `<disable_collisions …/>` lines to add to an SRDF, sorted by link names.
    pub srdf_lines: Vec<String>,
}

impl CheckJson {
    /// The summary of `model` loaded from `urdf`, with its semantics when an SRDF was given:
    /// groups, the collision matrix, and a warning for every named state in self-collision;
    /// always-close pairs with [`CloseOptions::default`].
    ///
    /// # Errors
    /// When the collision world cannot be built or a named state cannot be applied.
    pub fn new(model: &RobotModel, urdf: &Path, semantics: Option<&Semantics>) -> Result<Self> {
        Self::with_options(
            model,
            urdf,
            semantics,
            &CloseOptions::default(),
            &AcmOptions::default(),
        )
    }

    /// As [`CheckJson::new`], sampling always-close pairs with `close` and, for a robot
    /// without a collision matrix, the matrix with `matrix`.
    ///
    /// # Errors
    /// As [`CheckJson::new`]; [`crate::Error::InvalidParameter`] for zero samples or a
    /// fraction outside (0, 1].
    pub fn with_options(
        model: &RobotModel,
        urdf: &Path,
        semantics: Option<&Semantics>,
        close: &CloseOptions,
        matrix: &AcmOptions,
    ) -> Result<Self> {
        let finite = |x: Real| x.is_finite().then_some(x);
        let joints = model
            .joints()
            .iter()
            .map(|j| JointJson {
                child: model.links()[j.child_link].name.clone(),
                lower: finite(j.limits.lower),
                mimic: j.mimic.map(|m| model.joints()[m.joint].name.clone()),
                name: j.name.clone(),
                parent: model.links()[j.parent_link].name.clone(),
                joint_type: j.joint_type.as_str(),
                upper: finite(j.limits.upper),
                velocity: j.limits.velocity,
            })
            .collect();
        let issue = |joint: &str, problem: &str, fix: String| JointIssueJson {
            fix,
            joint: joint.to_owned(),
            problem: problem.to_owned(),
        };
        let mut joints_without_limits = Vec::new();
        for &j in model.variable_joints() {
            let joint = &model.joints()[j];
            let name = joint.name.as_str();
            if joint.joint_type == JointType::Continuous {
                joints_without_limits.push(issue(
                    name,
                    "continuous: no position limits (sampled in [-pi, pi])",
                    "if it cannot turn freely, make it revolute with <limit lower=\"…\" upper=\"…\">".to_owned(),
                ));
            } else if joint.limits.lower == 0.0 && joint.limits.upper == 0.0 {
                joints_without_limits.push(issue(
                    name,
                    "no position range (lower = upper = 0): it cannot move",
                    "give its <limit> lower and upper attributes".to_owned(),
                ));
            }
            if joint.limits.velocity == 0.0 {
                joints_without_limits.push(issue(
                    name,
                    "no velocity limit",
                    "give its <limit> a velocity attribute (rad/s or m/s): timing needs it"
                        .to_owned(),
                ));
            }
        }
        let unreadable_meshes = model
            .warnings()
            .iter()
            .filter_map(|w| match w {
                LoadWarning::SkippedMesh {
                    link,
                    uri,
                    reason,
                    fix,
                    ..
                } => Some(UnreadableMeshJson {
                    fix: fix.clone(),
                    link: link.clone(),
                    reason: reason.clone(),
                    uri: uri.clone(),
                }),
                _ => None,
            })
            .collect();
        let mut doc = Self {
            arms: arms_report(model, semantics),
            always_close: None,
            collision_matrix: None,
            format: CHECK_JSON_FORMAT,
            groups: None,
            joints,
            joints_without_limits,
            links: model.links().len(),
            not_arms: crate::limbs::unusable_limbs(model, crate::assistant::MIN_ARM_JOINTS)
                .into_iter()
                .map(|l| NotArmJson {
                    base_link: model.links()[l.base_link].name.clone(),
                    joints: l
                        .variables
                        .iter()
                        .map(|&v| model.variable_joint(v).name.clone())
                        .collect(),
                    reason: l.reason.to_string(),
                    tip_link: model.links()[l.tip_link].name.clone(),
                })
                .collect(),
            robot: model.name().to_owned(),
            root: model.links()[model.root()].name.clone(),
            sampled_collision_matrix: None,
            split_links: model.split_links().to_vec(),
            srdf: None,
            srdf_warnings: None,
            unreadable_meshes,
            urdf: urdf.display().to_string(),
            variables: model.variable_names().map(str::to_owned).collect(),
            warnings: model.warnings().iter().map(ToString::to_string).collect(),
        };
        // A robot without a matrix: the one the planner samples (also for the named states).
        let sampled = semantics
            .is_none_or(|s| s.srdf().disabled_collisions.is_empty())
            .then(|| sampled_matrix(model, matrix))
            .transpose()?;
        if let Some(semantics) = semantics {
            doc.groups = Some(
                semantics
                    .groups()
                    .iter()
                    .map(|g| GroupJson {
                        joints: g
                            .variables
                            .iter()
                            .map(|&v| model.variable_joint(v).name.clone())
                            .collect(),
                        name: g.name.clone(),
                        tip: g.tip_link.map(|t| model.links()[t].name.clone()),
                    })
                    .collect(),
            );
            let mut acm = AllowedCollisionMatrix::from_srdf(semantics.srdf());
            if let Some(report) = &sampled {
                acm.merge(&report.acm);
            }
            let with_geometry = model
                .links()
                .iter()
                .filter(|l| !l.collisions.is_empty())
                .count();
            let world = CollisionWorld::new(model, acm.clone())?;
            // Named states should be free of self-collision.
            let mut scratch = CollisionScratch::default();
            for state in &semantics.srdf().group_states {
                let mut q = model.zero_configuration();
                semantics.apply_state(model, &state.name, &mut q)?;
                for (a, b) in
                    world.colliding_pairs(model, &q, &mut scratch, &CheckOptions::default())?
                {
                    doc.warnings.push(format!(
                        "state {:?}: {} and {} collide",
                        state.name,
                        world.body_name(a),
                        world.body_name(b)
                    ));
                }
            }
            doc.srdf = Some(semantics.source().display().to_string());
            doc.srdf_warnings = Some(
                semantics
                    .warnings()
                    .iter()
                    .map(ToString::to_string)
                    .collect(),
            );
            doc.always_close = Some(
                always_close_pairs(model, &acm, close)?
                    .into_iter()
                    .map(|(link1, link2)| ClosePairJson {
                        fix: format!(
                            "<disable_collisions link1=\"{link1}\" link2=\"{link2}\" reason=\"Always\"/>"
                        ),
                        link1,
                        link2,
                    })
                    .collect(),
            );
            doc.collision_matrix = Some(CollisionMatrixJson {
                by_reason: acm
                    .counts_by_reason()
                    .into_iter()
                    .map(|(r, n)| (r.as_str().to_owned(), n))
                    .collect(),
                checked_shape_pairs: world.self_pair_count(),
                disabled_pairs: acm.len(),
                link_pairs_with_geometry: with_geometry * with_geometry.saturating_sub(1) / 2,
            });
        }
        if let Some(report) = sampled {
            let pairs = report.acm.to_disabled_pairs();
            doc.sampled_collision_matrix = Some(SampledMatrixJson {
                by_reason: report
                    .acm
                    .counts_by_reason()
                    .into_iter()
                    .map(|(r, n)| (r.as_str().to_owned(), n))
                    .collect(),
                disabled_pairs: pairs.len(),
                min_collision_fraction: matrix.min_collision_fraction,
                samples: matrix.samples,
                seed: matrix.seed,
                sometimes_in_collision: report.sometimes.len(),
                srdf_lines: pairs
                    .iter()
                    .map(|p| {
                        format!(
                            "<disable_collisions link1=\"{}\" link2=\"{}\" reason=\"{}\"/>",
                            p.link1,
                            p.link2,
                            p.reason.as_str()
                        )
                    })
                    .collect(),
            });
        }
        Ok(doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use pickplace_geometry::math::{Translation3, UnitQuaternion};

    #[test]
    fn link_poses_are_quaternion_then_position() {
        let pose = Isometry3::from_parts(
            Translation3::new(1.0, 2.0, 3.0),
            UnitQuaternion::from_euler_angles(0.0, 0.0, std::f64::consts::FRAC_PI_2),
        );
        let json = LinkPoseJson::from(&pose);
        assert_eq!(json.position, [1.0, 2.0, 3.0]);
        let s = std::f64::consts::FRAC_1_SQRT_2;
        assert!((json.orientation[2] - s).abs() < 1e-12 && (json.orientation[3] - s).abs() < 1e-12);
    }

    #[test]
    fn nx_hiro_check_and_fk() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro");
        let urdf = root.join("nx-hiro.urdf");
        let model = RobotModel::from_urdf_file(&urdf, &LoadOptions::default()).expect("urdf");
        let semantics = Semantics::from_file(&model, &root.join("nx-hiro.srdf")).expect("srdf");
        let check = CheckJson::new(&model, &urdf, Some(&semantics)).expect("check");
        assert_eq!(check.variables.len(), model.variable_count());
        let matrix = check.collision_matrix.expect("with an SRDF");
        assert_eq!(
            matrix.disabled_pairs,
            matrix.by_reason.values().sum::<usize>()
        );
        assert!(
            check
                .groups
                .expect("groups")
                .iter()
                .any(|g| g.name == "right_arm")
        );
        let bare = CheckJson::new(&model, &urdf, None).expect("check");
        assert!(bare.groups.is_none() && bare.collision_matrix.is_none() && bare.srdf.is_none());
        // Without an SRDF, the matrix the planner samples, as SRDF lines.
        let sampled = bare
            .sampled_collision_matrix
            .expect("sampled without an SRDF");
        assert_eq!(sampled.srdf_lines.len(), sampled.disabled_pairs);
        assert!(sampled.by_reason.get("Adjacent").is_some_and(|&n| n > 0));
        assert!(
            sampled
                .srdf_lines
                .iter()
                .all(|l| l.starts_with("<disable_collisions link1="))
        );
        assert!(check.sampled_collision_matrix.is_none());

        let fk = FkJson::new(&model, &model.zero_configuration()).expect("fk");
        assert_eq!(fk.links.len(), model.links().len());
        assert_eq!(fk.links[&fk.root].position, [0.0; 3]);
    }
}
