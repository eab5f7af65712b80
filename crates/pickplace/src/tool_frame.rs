//! Where each arm's tool link is: the frame of a plan's `events[].link`,
//! `events[].link_from_object` and `key_poses[].world_from_tcp`.
//!
//! The planner adds the tool link to the robot in memory (`<group>_tool`,
//! [`crate::robot_setup`]): a fixed link on the gripper's mounting link at the tool point it
//! measured (`docs/robot.md`). No URDF has it, so a plan states it per arm
//! ([`crate::plan::ArmJoints::tool`], `arms[].tool` in `docs/plan-format.md`), and
//! `pickplace export` states it as ROS 2 has it: a static transform from the parent link to
//! the tool link ([`TransformStamped`], what `/tf_static` carries; `docs/ros2.md`).

use crate::export::{ExportedTrajectory, Header};
use crate::plan::{ArmJoints, Event, Plan};
use crate::scene::PoseSpec;
use crate::strategy::Arm;
use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::Real;
use pickplace_robot::RobotModel;
use serde::{Deserialize, Serialize};

/// An arm's tool link as a plan states it: a link fixed to a link of the robot's URDF.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolFrame {
    /// The tool link's name (`<group>_tool`): the `link` of the arm's events.
    pub link: String,
    /// The link of the robot's URDF the tool link is fixed to (the gripper's mounting link).
    pub parent: String,
    /// The tool link's pose in the parent link's frame.
    pub parent_from_tool: PoseSpec,
}

impl ToolFrame {
    /// The tool frame of link `link` of `model`: its parent link and the pose of the fixed
    /// joint that carries it ([`RobotModel::with_fixed_link`] adds such a link).
    ///
    /// # Returns
    /// `None` when `link` is not a link of the model or is not carried by a fixed joint.
    pub fn of_link(model: &RobotModel, link: usize) -> Option<Self> {
        let joint = &model.joints()[model.links().get(link)?.parent_joint?];
        if joint.joint_type != pickplace_robot::JointType::Fixed {
            return None;
        }
        Some(Self {
            link: model.links()[link].name.clone(),
            parent: model.links()[joint.parent_link].name.clone(),
            parent_from_tool: PoseSpec::from_isometry(&joint.parent_from_joint),
        })
    }

    /// The tool frame as the static transform `parent -> link` ROS 2 publishes on
    /// `/tf_static`: `header.frame_id` the parent, `child_frame_id` the tool link, stamp zero.
    pub fn to_transform_stamped(&self) -> TransformStamped {
        let [x, y, z] = self.parent_from_tool.position;
        let [qx, qy, qz, qw] = self.parent_from_tool.orientation;
        TransformStamped {
            header: Header {
                stamp: Default::default(),
                frame_id: self.parent.clone(),
            },
            child_frame_id: self.link.clone(),
            transform: Transform {
                translation: Vector3 { x, y, z },
                rotation: Quaternion {
                    x: qx,
                    y: qy,
                    z: qz,
                    w: qw,
                },
            },
        }
    }

    /// The command that publishes the tool frame on `/tf_static`:
    /// `ros2 run tf2_ros static_transform_publisher --x X … --qw W --frame-id PARENT
    /// --child-frame-id LINK` (names quoted for a POSIX shell where they need it).
    pub fn static_transform_command(&self) -> String {
        let [x, y, z] = self.parent_from_tool.position;
        let [qx, qy, qz, qw] = self.parent_from_tool.orientation;
        let numbers: Vec<String> = [
            ("x", x),
            ("y", y),
            ("z", z),
            ("qx", qx),
            ("qy", qy),
            ("qz", qz),
            ("qw", qw),
        ]
        .iter()
        .map(|(name, value)| format!("--{name} {}", number(*value)))
        .collect();
        format!(
            "ros2 run tf2_ros static_transform_publisher {} --frame-id {} --child-frame-id {}",
            numbers.join(" "),
            shell_word(&self.parent),
            shell_word(&self.link)
        )
    }
}

/// `geometry_msgs/msg/Vector3`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Vector3 {
    /// x (m).
    pub x: Real,
    /// y (m).
    pub y: Real,
    /// z (m).
    pub z: Real,
}

/// `geometry_msgs/msg/Quaternion`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Quaternion {
    /// x.
    pub x: Real,
    /// y.
    pub y: Real,
    /// z.
    pub z: Real,
    /// w.
    pub w: Real,
}

/// `geometry_msgs/msg/Transform`: the child frame's pose in the parent's.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Transform {
    /// The child's origin in the parent's frame (m).
    pub translation: Vector3,
    /// The child's orientation in the parent's frame.
    pub rotation: Quaternion,
}

/// `geometry_msgs/msg/TransformStamped`: `child_frame_id` in `header.frame_id`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransformStamped {
    /// Stamp zero (a static transform); `frame_id` the parent link.
    pub header: Header,
    /// The tool link.
    pub child_frame_id: String,
    /// `parent_from_tool`.
    pub transform: Transform,
}

/// A rule of a plan's form about its tool frames that is broken ([`check_events`]).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ToolFrameError {
    /// An event of an arm names another link than the arm's stated tool link.
    #[error(
        "events[{event}]: link {link:?} is not the {arm} arm's tool link {tool:?} (arms[{arm_index}].tool.link)"
    )]
    EventLink {
        /// The event's index.
        event: usize,
        /// Its arm.
        arm: Arm,
        /// The link it names (at most 64 characters).
        link: String,
        /// The arm's index in `arms`.
        arm_index: usize,
        /// The arm's tool link (at most 64 characters).
        tool: String,
    },
}

/// Checks that every event of an arm whose tool frame the plan states names that tool link
/// (events of an arm without one are not checked: a plan written before the tool frames were
/// stated).
///
/// # Errors
/// [`ToolFrameError::EventLink`] for the first event that names another link.
pub fn check_events(arms: &[ArmJoints], events: &[Event]) -> Result<(), ToolFrameError> {
    for (event, e) in events.iter().enumerate() {
        let stated = arms
            .iter()
            .enumerate()
            .find_map(|(k, a)| Some((k, a.tool.as_ref()?)).filter(|_| a.arm == e.arm));
        if let Some((arm_index, tool)) = stated
            && tool.link != e.link
        {
            return Err(ToolFrameError::EventLink {
                event,
                arm: e.arm,
                link: crate::plan::clip(&e.link),
                arm_index,
                tool: crate::plan::clip(&tool.link),
            });
        }
    }
    Ok(())
}

/// The comment lines a YAML stream of `messages` starts with: for each arm of the messages
/// whose tool frame the plan states (in [`Plan::arms`] order), where its tool link is and the
/// command that publishes it on `/tf_static` ([`ToolFrame::static_transform_command`]):
///
/// ```text
/// # tool frame of the right arm (link of link_from_object and world_from_tcp): "right_arm_tool" in "RARM_JOINT5_Link" at position [-0.1865, 0, 0], orientation [0, -0.7071067811865475, 0, 0.7071067811865476]
/// #   ros2 run tf2_ros static_transform_publisher --x -0.1865 --y 0 --z 0 --qx 0 --qy -0.7071067811865475 --qz 0 --qw 0.7071067811865476 --frame-id RARM_JOINT5_Link --child-frame-id right_arm_tool
/// ```
///
/// Empty when no arm of the messages has a stated tool frame.
pub fn yaml_comments(plan: &Plan, messages: &[ExportedTrajectory]) -> String {
    let mut out = String::new();
    for a in &plan.arms {
        let Some(tool) = &a.tool else { continue };
        if !messages.iter().any(|m| m.arm == a.arm) {
            continue;
        }
        let numbers = |values: &[Real]| -> String {
            let items: Vec<String> = values.iter().map(|&v| number(v)).collect();
            format!("[{}]", items.join(", "))
        };
        // The names come from the plan file: keep each comment on one line.
        out.push_str(&one_line(&format!(
            "# tool frame of the {} arm (link of link_from_object and world_from_tcp): {:?} in {:?} at position {}, orientation {}",
            a.arm,
            tool.link,
            tool.parent,
            numbers(&tool.parent_from_tool.position),
            numbers(&tool.parent_from_tool.orientation)
        )));
        out.push('\n');
        out.push_str(&one_line(&format!(
            "#   {}",
            tool.static_transform_command()
        )));
        out.push('\n');
    }
    out
}

/// A number as [`fmt_real`] writes it, in full precision, `-0` as `0`.
fn number(value: Real) -> String {
    // Adding 0 turns -0 into 0 and changes no other value.
    fmt_real(value + 0.0)
}

/// `text` with every control character (a line break) replaced by a space.
fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// `word` as one word of a POSIX shell: as it is when it holds only letters, digits and
/// `_ . / : + -` (and is not empty), else in single quotes (a `'` in it as `'\''`).
fn shell_word(word: &str) -> String {
    let plain = !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "_./:+-".contains(c));
    if plain {
        word.to_owned()
    } else {
        format!("'{}'", word.replace('\'', "'\\''"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::EventKind;
    use pickplace_geometry::math::{Isometry3, Translation3, UnitQuaternion};

    fn tool(link: &str) -> ToolFrame {
        ToolFrame {
            link: link.into(),
            parent: "RARM_JOINT5_Link".into(),
            parent_from_tool: PoseSpec::from_isometry(&Isometry3::from_parts(
                Translation3::new(-0.065, 0.0, -0.1),
                UnitQuaternion::identity(),
            )),
        }
    }

    #[test]
    fn the_transform_is_parent_to_tool_and_the_command_says_the_same() {
        let t = tool("right_arm_tool").to_transform_stamped();
        let json = serde_json::to_value(&t).expect("json");
        assert_eq!(
            json,
            serde_json::json!({
                "header": { "stamp": { "sec": 0, "nanosec": 0 }, "frame_id": "RARM_JOINT5_Link" },
                "child_frame_id": "right_arm_tool",
                "transform": {
                    "translation": { "x": -0.065, "y": 0.0, "z": -0.1 },
                    "rotation": { "x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0 }
                }
            })
        );
        assert_eq!(
            tool("right_arm_tool").static_transform_command(),
            "ros2 run tf2_ros static_transform_publisher --x -0.065 --y 0 --z -0.1 --qx 0 --qy 0 --qz 0 --qw 1 --frame-id RARM_JOINT5_Link --child-frame-id right_arm_tool"
        );
        assert!(
            tool("it's a tool")
                .static_transform_command()
                .ends_with(" --child-frame-id 'it'\\''s a tool'")
        );
    }

    #[test]
    fn an_event_names_its_arms_stated_tool_link() {
        let arms = vec![ArmJoints {
            arm: Arm::Right,
            group: "right_arm".into(),
            joints: vec![],
            gripper_joints: vec![],
            tool: Some(tool("right_arm_tool")),
        }];
        let event = |arm: Arm, link: &str| Event {
            time: 1.0,
            kind: EventKind::Grasp,
            arm,
            link: link.into(),
            link_from_object: PoseSpec::IDENTITY,
        };
        assert_eq!(
            check_events(
                &arms,
                &[event(Arm::Right, "right_arm_tool"), event(Arm::Left, "x")]
            ),
            Ok(())
        );
        let e = check_events(&arms, &[event(Arm::Right, "WAIST")]).expect_err("not the tool");
        assert_eq!(
            e.to_string(),
            "events[0]: link \"WAIST\" is not the right arm's tool link \"right_arm_tool\" (arms[0].tool.link)"
        );
        let mut without = arms.clone();
        without[0].tool = None;
        assert_eq!(
            check_events(&without, &[event(Arm::Right, "WAIST")]),
            Ok(())
        );
    }
}
