//! The arms of a pick-and-place scene's robot and their grippers: the scene's groups, else the
//! SRDF's `right_arm` / `left_arm`, else the chains of the URDF that end in a parallel gripper
//! (paper §II: a dual-arm robot with a parallel gripper on each arm).

use super::{GripperOverrides, RobotArm, grasp_model};
use crate::error::{Error, Result};
use crate::scene::PlannerOptions;
use crate::strategy::Arm;
use pickplace_robot::gripper::Gripper;
use pickplace_robot::limbs::find_arms;
use pickplace_robot::{RobotModel, Semantics};
use std::path::Path;

/// Fewest joints of a chain taken for an arm when the URDF is searched.
const MIN_ARM_JOINTS: usize = 4;

/// The arms (right first), the model with a tool link per arm, and the gripper overrides read
/// from `gripper_file` (for cache keys). Notes what was found or completed.
///
/// # Errors
/// [`Error::Invalid`] naming the scene field: a group that does not exist or moves nothing, no
/// arm at all, a gripper that cannot be measured or an override out of range.
pub(super) fn choose(
    model: RobotModel,
    semantics: &Semantics,
    p: &PlannerOptions,
    gripper_file: Option<&Path>,
    first_urdf: &Path,
    scene_path: &Path,
    notes: &mut Vec<String>,
) -> Result<(RobotModel, Vec<RobotArm>, GripperOverrides)> {
    let invalid = |field: &str, reason: String| Error::Invalid {
        path: scene_path.to_path_buf(),
        field: field.to_owned(),
        reason,
    };
    // The arms: the scene's groups, else `right_arm` / `left_arm`, else found in the URDF.
    let overrides = match gripper_file {
        Some(path) => GripperOverrides::load(path)?,
        None => GripperOverrides::default(),
    };
    let has_group = |name: &str| semantics.group(name).is_ok();
    let pick = |given: &Option<String>, default: &str| -> Option<String> {
        match given {
            Some(g) if g.is_empty() => None,
            Some(g) => Some(g.clone()),
            None => has_group(default).then(|| default.to_owned()),
        }
    };
    let mut chosen: Vec<(Arm, String, Vec<usize>, &'static str)> = Vec::new();
    for (arm, given, default, f) in [
        (Arm::Right, &p.right_arm, "right_arm", "planner.right_arm"),
        (Arm::Left, &p.left_arm, "left_arm", "planner.left_arm"),
    ] {
        if let Some(group) = pick(given, default) {
            let g = semantics.group(&group).map_err(|e| {
                invalid(
                    f,
                    format!(
                        "{e} (groups: {})",
                        semantics
                            .groups()
                            .iter()
                            .map(|g| g.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                )
            })?;
            if g.variables.is_empty() {
                let why = semantics
                    .left_out_of(&group)
                    .map(|w| format!(" ({w})"))
                    .unwrap_or_default();
                return Err(invalid(
                    f,
                    format!("group {group:?} has no actuated joint{why}"),
                ));
            }
            chosen.push((arm, group, g.variables.clone(), f));
        }
    }
    let explicit = p.right_arm.is_some() || p.left_arm.is_some();
    if chosen.is_empty() && !explicit {
        let found = find_arms(&model, MIN_ARM_JOINTS);
        if found.is_empty() {
            return Err(invalid(
                "planner.right_arm",
                format!(
                    "the SRDF has no group right_arm or left_arm and no arm ending in a parallel gripper was found in {}; name the arm groups",
                    first_urdf.display()
                ),
            ));
        }
        // Which is right: the hand farther to the robot's right (−y of the root frame) at
        // the zero configuration.
        let q = model.zero_configuration();
        let poses = model
            .link_poses(&q)
            .map_err(crate::error::internal("forward kinematics"))?;
        let mut by_side: Vec<_> = found
            .into_iter()
            .map(|a| (poses[a.tip_link].translation.vector.y, a))
            .collect();
        by_side.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (k, (_, a)) in by_side.into_iter().take(2).enumerate() {
            let arm = if k == 0 { Arm::Right } else { Arm::Left };
            let group = format!("arm_{}", model.links()[a.tip_link].name);
            notes.push(format!(
                "{arm} arm found in the URDF: {} joints from {:?} to {:?} (name it with planner.{arm}_arm)",
                a.variables.len(),
                model.links()[a.base_link].name,
                model.links()[a.tip_link].name
            ));
            chosen.push((arm, group, a.variables, "planner.right_arm"));
        }
    }
    if chosen.len() == 1 {
        let (arm, group, ..) = &chosen[0];
        notes.push(format!(
            "one arm ({arm}: {group}): single-arm strategies only; a handover needs two arms"
        ));
    }
    if chosen.is_empty() {
        return Err(invalid(
            "planner.right_arm",
            "no arm: both arm groups are empty".into(),
        ));
    }

    // Grippers and tool links.
    let options = overrides.options();
    let mut model = model;
    let mut arms = Vec::with_capacity(chosen.len());
    for (arm, group, variables, f) in chosen {
        let gripper = Gripper::derive(&model, &variables, &options)
            .map_err(|e| invalid(f, format!("arm {group:?}: {e}")))?;
        let mut name = format!("{group}_tool");
        while model.link_index(&name).is_some() {
            name.push('_');
        }
        model = model
            .with_fixed_link(&name, gripper.arm_tip(), *gripper.tip_from_tcp())
            .map_err(crate::error::internal("tool link"))?;
        let tcp_link = model
            .link_index(&name)
            .ok_or_else(|| crate::error::internal("tool link")("missing"))?;
        // A bad value names the overrides file when there is one, else the URDF it was
        // measured on.
        let source = gripper_file.unwrap_or(first_urdf);
        let gripper_params = grasp_model(&gripper, &overrides, source)
            .map_err(|e| invalid(f, format!("arm {group:?}: gripper: {e}")))?;
        arms.push(RobotArm {
            arm,
            group,
            variables,
            gripper,
            gripper_params,
            tcp_link,
            tcp_name: name,
        });
    }
    Ok((model, arms, overrides))
}
