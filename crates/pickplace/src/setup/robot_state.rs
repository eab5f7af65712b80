//! The robot's state and collision world at the start of a scene, shared by the
//! pick-and-place [`Setup`](super::Setup) and motion queries ([`crate::motion`]).

use crate::cache::Cache;
use crate::error::{Error, Result};
use crate::robot_setup::{RobotSetup, robot_err};
use crate::scene::{CollisionMatrixSpec, SceneOf};
use pickplace_geometry::math::Real;
use pickplace_robot::collision::CollisionWorld;
use std::path::Path;

/// The start configuration (every variable): zeros, the SRDF's `home` (or the robot's
/// `named_state`) when it has one, then the scene's `start_state` values; continuous joints
/// wrapped into [−π, π).
///
/// # Errors
/// [`Error::Invalid`] naming the scene field: a named state the SRDF lacks, a joint the robot
/// lacks, a value outside its limits; [`Error::Robot`] when the SRDF's state cannot be applied.
pub(crate) fn start_configuration<O, T>(
    scene: &SceneOf<O, T>,
    robot: &RobotSetup,
    scene_path: &Path,
) -> Result<Vec<Real>> {
    let invalid = |field: &str, reason: String| Error::Invalid {
        path: scene_path.to_path_buf(),
        field: field.to_owned(),
        reason,
    };
    let (model, semantics, srdf_path) = (&robot.model, &robot.semantics, &robot.srdf_path);
    // Start state: zeros, the SRDF's `home` when it has one, then the scene's values.
    let mut start = model.zero_configuration();
    let several = scene.robots.len() > 1;
    for (i, spec) in scene.robots.iter().enumerate() {
        let prefix = if several { spec.prefix.as_str() } else { "" };
        let state = match &spec.named_state {
            Some(name) => Some(format!("{prefix}{name}")),
            None => Some(format!("{prefix}home")),
        };
        if let Some(state) = state {
            let exists = semantics
                .srdf()
                .group_states
                .iter()
                .any(|s| s.name == state);
            if exists {
                semantics
                    .apply_state(model, &state, &mut start)
                    .map_err(robot_err(srdf_path))?;
            } else if spec.named_state.is_some() {
                let field = if several {
                    format!("robots[{i}].named_state")
                } else {
                    "robot.named_state".to_owned()
                };
                return Err(invalid(
                    &field,
                    format!(
                        "the SRDF has no group_state {state:?} (it has: {})",
                        semantics
                            .srdf()
                            .group_states
                            .iter()
                            .map(|s| s.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
        }
    }
    for (i, spec) in scene.robots.iter().enumerate() {
        for (name, &value) in &spec.start_state {
            let field = if several {
                format!("robots[{i}].start_state.{name}")
            } else {
                format!("robot.start_state.{name}")
            };
            let full = format!("{}{name}", if several { spec.prefix.as_str() } else { "" });
            let v = model.variable_index(&full).ok_or_else(|| {
                invalid(
                    &field,
                    format!(
                        "the robot {:?} has no actuated joint of that name",
                        model.name()
                    ),
                )
            })?;
            let limits = model.variable_joint(v).limits;
            if !limits.contains(value, 1e-9) {
                return Err(invalid(
                    &field,
                    format!(
                        "{value} is outside the joint's limits [{}, {}]",
                        limits.lower, limits.upper
                    ),
                ));
            }
            start[v] = value;
        }
    }
    // Continuous joints start within [−π, π), where the motion planner's space is.
    for (v, x) in start.iter_mut().enumerate() {
        let l = model.variable_joint(v).limits;
        if !l.lower.is_finite() && !l.upper.is_finite() {
            *x = (*x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
        }
    }
    Ok(start)
}

/// The robot's collision world without environment: its links, the allowed-collision matrix
/// (the SRDF's, completed by sampling when it has none: [`crate::collision_matrix`], cached)
/// and its base pose.
///
/// # Errors
/// [`Error::Robot`] naming the URDF when the collision library refuses the robot.
pub(crate) fn self_world(
    robot: &RobotSetup,
    start: &[Real],
    matrix: &CollisionMatrixSpec,
    cache: &mut Cache,
    log: &mut Vec<String>,
) -> Result<CollisionWorld> {
    let acm = crate::collision_matrix::complete_acm(
        &robot.model,
        &robot.semantics,
        start,
        (matrix, &robot.key_text),
        cache,
        log,
    )
    .map_err(robot_err(&robot.urdf_path))?;
    let mut world = CollisionWorld::new(&robot.model, acm).map_err(robot_err(&robot.urdf_path))?;
    world.set_world_from_root(robot.world_from_root);
    Ok(world)
}
