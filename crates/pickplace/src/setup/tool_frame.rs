//! Where the plan's frames are on the robot: each arm's tool link, the frame of a plan's
//! `events[].link`, `events[].link_from_object` and `key_poses[].world_from_tcp`, and the
//! robot's root link in the world, the frame those world poses are in.
//!
//! The planner adds the tool link to the robot in memory (`<group>_tool`,
//! [`crate::robot_setup`]): a fixed link on the gripper's mounting link at the tool point it
//! measured (`docs/robot.md`). No URDF has it, so a plan states it per arm
//! ([`crate::plan::ArmJoints::tool`], `arms[].tool` in `docs/plan-format.md`). Where the
//! robot stands is the scene's (`robot.base_pose`), so a plan states that too
//! ([`crate::plan::Plan::base`], [`BaseFrame`]). `pickplace export` states both as ROS 2 has
//! them: static transforms ([`TransformStamped`], what `/tf_static` carries;
//! `docs/ros2.md`), from the world frame ([`WORLD_FRAME`]) to the root link and from a tool
//! link's parent to the tool link.

use crate::export::{ExportedTrajectory, Header};
use crate::plan::{ArmJoints, Event, Plan};
use crate::scene::PoseSpec;
use crate::strategy::Arm;
use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::{Isometry3, Real};
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
        transform_stamped(&self.parent, &self.link, &self.parent_from_tool)
    }

    /// The command that publishes the tool frame on `/tf_static`:
    /// `ros2 run tf2_ros static_transform_publisher --x X … --qw W --frame-id PARENT
    /// --child-frame-id LINK` (names quoted for a POSIX shell where they need it).
    pub fn static_transform_command(&self) -> String {
        static_transform_command(&self.parent, &self.link, &self.parent_from_tool)
    }
}

/// The name the ROS 2 export gives the world frame, the frame of the plan's world poses
/// (`world_from_tcp`, `world_from_object`, [`BaseFrame::world_from_root`]): `world`, the
/// parent frame of MoveIt's virtual joints by convention and the root link of several robots
/// combined ([`crate::robot_setup`]).
pub const WORLD_FRAME: &str = "world";

/// Where the robot stands, as a plan states it: its root link in the world frame, the frame
/// of the plan's world poses.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseFrame {
    /// The robot model's root link: the URDF's root, or [`WORLD_FRAME`] for several robots
    /// combined (each placed under it at its `base_pose`).
    pub link: String,
    /// The root link's pose in the world frame: the scene's `robot.base_pose` (the identity
    /// for several robots combined).
    pub world_from_root: PoseSpec,
}

impl BaseFrame {
    /// The base frame of `model` (its root link) standing at `world_from_root`.
    pub fn of_model(model: &RobotModel, world_from_root: &Isometry3) -> Self {
        Self {
            link: model.links()[model.root()].name.clone(),
            world_from_root: PoseSpec::from_isometry(world_from_root),
        }
    }

    /// True when the root link is the world frame itself ([`WORLD_FRAME`]: several robots
    /// combined): there is no transform to publish then.
    pub fn is_world(&self) -> bool {
        self.link == WORLD_FRAME
    }

    /// Where the robot stands as the static transform `world -> link` ROS 2 publishes on
    /// `/tf_static`: `header.frame_id` [`WORLD_FRAME`], `child_frame_id` the root link, stamp
    /// zero; `None` when the root link is the world frame ([`BaseFrame::is_world`]: tf2
    /// refuses a frame's transform to itself).
    pub fn to_transform_stamped(&self) -> Option<TransformStamped> {
        (!self.is_world())
            .then(|| transform_stamped(WORLD_FRAME, &self.link, &self.world_from_root))
    }

    /// The command that publishes [`BaseFrame::to_transform_stamped`] on `/tf_static`
    /// (`--frame-id world --child-frame-id ROOT`); `None` when the root link is the world
    /// frame.
    pub fn static_transform_command(&self) -> Option<String> {
        (!self.is_world())
            .then(|| static_transform_command(WORLD_FRAME, &self.link, &self.world_from_root))
    }
}

/// `child` at `parent_from_child` in `parent` as a static transform: stamp zero.
fn transform_stamped(parent: &str, child: &str, parent_from_child: &PoseSpec) -> TransformStamped {
    let [x, y, z] = parent_from_child.position;
    let [qx, qy, qz, qw] = parent_from_child.orientation;
    TransformStamped {
        header: Header {
            stamp: Default::default(),
            frame_id: parent.to_owned(),
        },
        child_frame_id: child.to_owned(),
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

/// `ros2 run tf2_ros static_transform_publisher --x X … --qw W --frame-id PARENT
/// --child-frame-id CHILD`, names quoted for a POSIX shell where they need it.
fn static_transform_command(parent: &str, child: &str, parent_from_child: &PoseSpec) -> String {
    let [x, y, z] = parent_from_child.position;
    let [qx, qy, qz, qw] = parent_from_child.orientation;
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
        shell_word(parent),
        shell_word(child)
    )
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
    /// Stamp zero (a static transform); `frame_id` the parent frame (a tool link's parent
    /// link, or [`WORLD_FRAME`]).
    pub header: Header,
    /// The child frame (a tool link, or the root link).
    pub child_frame_id: String,
    /// The child's pose in the parent's frame (`parent_from_tool`, `world_from_root`).
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

/// The comment lines a YAML stream of `messages` starts with: where the robot stands when
/// the plan states it ([`Plan::base`]; nothing when its root link is the world frame), then
/// for each arm of the messages whose tool frame the plan states (in [`Plan::arms`] order),
/// where its tool link is; each with the command that publishes it on `/tf_static`
/// ([`BaseFrame::static_transform_command`], [`ToolFrame::static_transform_command`]):
///
/// ```text
/// # robot base (frame of world_from_tcp and world_from_object): root link "WAIST" in "world" at position [0, 0, 0.92], orientation [0, 0, 0, 1]
/// #   ros2 run tf2_ros static_transform_publisher --x 0 --y 0 --z 0.92 --qx 0 --qy 0 --qz 0 --qw 1 --frame-id world --child-frame-id WAIST
/// # tool frame of the right arm (link of link_from_object and world_from_tcp): "right_arm_tool" in "RARM_JOINT5_Link" at position [-0.1865, 0, 0], orientation [0, -0.7071067811865475, 0, 0.7071067811865476]
/// #   ros2 run tf2_ros static_transform_publisher --x -0.1865 --y 0 --z 0 --qx 0 --qy -0.7071067811865475 --qz 0 --qw 0.7071067811865476 --frame-id RARM_JOINT5_Link --child-frame-id right_arm_tool
/// ```
///
/// Empty when there are no messages, or the plan states no base and no arm of the messages
/// has a stated tool frame.
pub fn yaml_comments(plan: &Plan, messages: &[ExportedTrajectory]) -> String {
    let mut out = String::new();
    let numbers = |values: &[Real]| -> String {
        let items: Vec<String> = values.iter().map(|&v| number(v)).collect();
        format!("[{}]", items.join(", "))
    };
    // The names come from the plan file: keep each comment on one line.
    let mut push = |frame: String, command: String| {
        out.push_str(&one_line(&frame));
        out.push('\n');
        out.push_str(&one_line(&format!("#   {command}")));
        out.push('\n');
    };
    if let Some(base) = plan.base.as_ref().filter(|_| !messages.is_empty())
        && let Some(command) = base.static_transform_command()
    {
        push(
            format!(
                "# robot base (frame of world_from_tcp and world_from_object): root link {:?} in {WORLD_FRAME:?} at position {}, orientation {}",
                base.link,
                numbers(&base.world_from_root.position),
                numbers(&base.world_from_root.orientation)
            ),
            command,
        );
    }
    for a in &plan.arms {
        let Some(tool) = &a.tool else { continue };
        if !messages.iter().any(|m| m.arm == a.arm) {
            continue;
        }
        push(
            format!(
                "# tool frame of the {} arm (link of link_from_object and world_from_tcp): {:?} in {:?} at position {}, orientation {}",
                a.arm,
                tool.link,
                tool.parent,
                numbers(&tool.parent_from_tool.position),
                numbers(&tool.parent_from_tool.orientation)
            ),
            tool.static_transform_command(),
        );
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
    use pickplace_geometry::math::{Translation3, UnitQuaternion};

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
    fn the_base_is_world_to_root_and_nothing_when_the_root_is_the_world() {
        let base = BaseFrame {
            link: "WAIST".into(),
            world_from_root: PoseSpec::from_isometry(&Isometry3::from_parts(
                Translation3::new(0.0, 0.0, 0.92),
                UnitQuaternion::identity(),
            )),
        };
        let t = base.to_transform_stamped().expect("a transform");
        assert_eq!(
            serde_json::to_value(&t).expect("json"),
            serde_json::json!({
                "header": { "stamp": { "sec": 0, "nanosec": 0 }, "frame_id": "world" },
                "child_frame_id": "WAIST",
                "transform": {
                    "translation": { "x": 0.0, "y": 0.0, "z": 0.92 },
                    "rotation": { "x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0 }
                }
            })
        );
        assert_eq!(
            base.static_transform_command().as_deref(),
            Some(
                "ros2 run tf2_ros static_transform_publisher --x 0 --y 0 --z 0.92 --qx 0 --qy 0 --qz 0 --qw 1 --frame-id world --child-frame-id WAIST"
            )
        );
        // Several robots combined: the root link is the world frame.
        let combined = BaseFrame {
            link: WORLD_FRAME.into(),
            world_from_root: PoseSpec::IDENTITY,
        };
        assert!(combined.is_world());
        assert_eq!(combined.to_transform_stamped(), None);
        assert_eq!(combined.static_transform_command(), None);
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
