//! The frames a plan states against the scene's robot (issue 33): where the robot stands
//! (`base`) and each arm's tool link (`arms[].tool`).
//!
//! A plan's hand poses (`events[].link_from_object`, `key_poses[].world_from_tcp`) are in the
//! tool links it states, its world poses in the world where its `base` stands the robot. The
//! validator reads them in the scene's robot's frames; a plan made for another gripper
//! configuration (another `tool_offset`) or another base pose would be read, by the validator
//! and by an executor, in frames it was not made for. Each stated frame that differs from the
//! scene's is a problem of the report, named by its field and listed first, without a time
//! (it holds at every instant); the rest of the plan is still checked, in the scene's frames.
//! A plan that states no frame (written before issue 33) is checked as before.

use crate::plan::Plan;
use crate::scene::PoseSpec;
use crate::setup::Setup;
use crate::tool_frame::{BaseFrame, ToolFrame};
use pickplace_geometry::io::{fmt_real, fmt_real_fixed};
use pickplace_geometry::math::{Isometry3, Real};

/// How far a stated frame may be from the scene's (m, and rad): rounding only.
pub const FRAME_TOLERANCE: Real = 1e-9;

/// The problems of the frames `plan` states against `setup`'s robot: a link name that is not
/// the scene's, a pose more than [`FRAME_TOLERANCE`] from the scene's (checked only where the
/// link names agree: a pose in another link's frame says nothing).
pub(super) fn problems(setup: &Setup, plan: &Plan) -> Vec<String> {
    let mut found = Vec::new();
    if let Some(stated) = &plan.base {
        let scene = BaseFrame::of_model(&setup.model, &setup.world_from_root);
        if stated.link != scene.link {
            found.push(format!(
                "base.link: {:?} is not the scene's robot's root link {:?}: the plan is for another robot",
                crate::plan::clip(&stated.link),
                scene.link
            ));
        } else if let Some(gap) = gap(&stated.world_from_root, &setup.world_from_root) {
            found.push(format!(
                "base.world_from_root: {gap} from where the scene's robot stands ({}): the plan's world poses are for another base pose",
                pose(&scene.world_from_root)
            ));
        }
    }
    for (i, a) in plan.arms.iter().enumerate() {
        let Some(stated) = &a.tool else { continue };
        let Some(arm) = setup.arms.iter().find(|s| s.arm == a.arm) else {
            found.push(format!(
                "arms[{i}].tool: the scene's robot has no {} arm",
                a.arm
            ));
            continue;
        };
        if stated.link != arm.tcp_name {
            found.push(format!(
                "arms[{i}].tool.link: {:?} is not the scene's {} arm tool link {:?}",
                crate::plan::clip(&stated.link),
                a.arm,
                arm.tcp_name
            ));
        }
        // The planner's tool link is always fixed: there is nothing else to compare with.
        let Some(scene) = ToolFrame::of_link(&setup.model, arm.tcp_link) else {
            continue;
        };
        let Ok(parent_from_tool) = scene.parent_from_tool.to_isometry() else {
            continue;
        };
        if stated.parent != scene.parent {
            found.push(format!(
                "arms[{i}].tool.parent: {:?} is not the link the scene's {} arm tool link is fixed to, {:?}",
                crate::plan::clip(&stated.parent),
                a.arm,
                scene.parent
            ));
        } else if let Some(gap) = gap(&stated.parent_from_tool, &parent_from_tool) {
            found.push(format!(
                "arms[{i}].tool.parent_from_tool: {gap} from the scene's {} arm tool frame ({} in {:?}): the plan's poses of the {} hand are for another tool point (gripper configuration)",
                a.arm,
                pose(&scene.parent_from_tool),
                scene.parent,
                a.arm
            ));
        }
    }
    found
}

/// How far `stated` is from `scene` (`1.0000 mm / 0.0000°`), or `None` within
/// [`FRAME_TOLERANCE`] (m and rad). An invalid pose (refused by the plan's form before the
/// validator runs) is infinitely far.
fn gap(stated: &PoseSpec, scene: &Isometry3) -> Option<String> {
    let Ok(stated) = stated.to_isometry() else {
        return Some("an invalid pose".to_owned());
    };
    let d = (stated.translation.vector - scene.translation.vector).norm();
    let between = (scene.rotation.inverse() * stated.rotation).into_inner();
    // 2 atan2(|v|, |w|): accurate for the smallest angles, where 2 acos(|w|) rounds to 0 or
    // to 1e-8.
    let a = 2.0 * between.imag().norm().atan2(between.w.abs());
    // Within the tolerance is 0 (rounding), beyond it every digit that says how far.
    let shown = |value: Real, unit: Real| -> String {
        fmt_real_fixed(
            if value > FRAME_TOLERANCE {
                value * unit
            } else {
                0.0
            },
            4,
        )
    };
    (d > FRAME_TOLERANCE || a > FRAME_TOLERANCE || !(d.is_finite() && a.is_finite())).then(|| {
        format!(
            "{} mm / {}°",
            shown(d, 1e3),
            shown(a, 180.0 / std::f64::consts::PI)
        )
    })
}

/// `position [x, y, z], orientation [x, y, z, w]`, every number in full.
fn pose(p: &PoseSpec) -> String {
    let list = |values: &[Real]| -> String {
        let items: Vec<String> = values.iter().map(|&v| fmt_real(v + 0.0)).collect();
        format!("[{}]", items.join(", "))
    };
    format!(
        "position {}, orientation {}",
        list(&p.position),
        list(&p.orientation)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Translation3, UnitQuaternion};

    #[test]
    fn a_gap_within_a_nanometre_and_a_nanoradian_is_none() {
        let scene = Isometry3::from_parts(
            Translation3::new(-0.1865, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(0.3, -1.2, 2.0),
        );
        let same = PoseSpec::from_isometry(&scene);
        assert_eq!(gap(&same, &scene), None);
        // The other sign of the quaternion is the same rotation.
        let mut negated = same;
        negated.orientation = negated.orientation.map(|v| -v);
        assert_eq!(gap(&negated, &scene), None);
        let mut moved = same;
        moved.position[2] += 0.001;
        assert_eq!(gap(&moved, &scene).as_deref(), Some("1.0000 mm / 0.0000°"));
        let turned =
            PoseSpec::from_isometry(&(scene * UnitQuaternion::from_euler_angles(1e-8, 0.0, 0.0)));
        assert_eq!(
            gap(&turned, &scene).as_deref(),
            Some("0.0000 mm / 5.7296e-7°")
        );
        let mut broken = same;
        broken.orientation = [0.0; 4];
        assert_eq!(gap(&broken, &scene).as_deref(), Some("an invalid pose"));
    }
}
