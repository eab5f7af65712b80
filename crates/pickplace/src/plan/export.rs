//! A plan as ROS 2 messages (`docs/ros2.md`): one `trajectory_msgs/msg/JointTrajectory` per
//! motion and per moving arm or gripper ([`joint_trajectories`]), for a ros2_control
//! `joint_trajectory_controller`, and one `moveit_msgs/msg/DisplayTrajectory` of the whole
//! plan ([`display_trajectory`]), for RViz. Where the robot stands and each arm's tool frame
//! go with the trajectories as the static transforms ROS has for them
//! ([`crate::tool_frame`]).
//!
//! The structs serialize (serde) with the field names and order of the ROS 2 message
//! definitions, so their JSON is what `rosidl_runtime_py.set_message_fields` takes;
//! [`to_yaml`] writes a [`JointTrajectory`] as the YAML `ros2 topic pub` takes. Pure
//! functions: nothing here reads or writes files.

use crate::plan::{ArmJoints, Plan, PlanFormError};
use crate::strategy::Arm;
use crate::tool_frame::{ToolFrame, TransformStamped};
use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::Real;
use serde::Serialize;
use std::fmt::Write as _;

/// `builtin_interfaces/msg/Duration` (and `Time`, the same fields): whole seconds and
/// nanoseconds in `[0, 1e9)`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, PartialOrd, Ord, Serialize)]
pub struct Duration {
    /// Whole seconds (`int32`).
    pub sec: i32,
    /// Nanoseconds, `0 ..= 999_999_999` (`uint32`).
    pub nanosec: u32,
}

impl Duration {
    /// `seconds` (s) rounded to the nearest nanosecond, the carry into `sec` included
    /// (1.9999999999 s is `{ sec: 2, nanosec: 0 }`).
    ///
    /// # Errors
    /// A negative or non-finite value, or one of 2³¹ s or more (`sec` is an `int32`).
    pub fn from_seconds(seconds: Real) -> Result<Self, PlanFormError> {
        if !seconds.is_finite() || seconds < 0.0 || seconds >= f64::from(i32::MAX) + 1.0 {
            return Err(format!(
                "time {} s is not a duration from 0 to 2^31 s",
                fmt_real(seconds)
            )
            .into());
        }
        // Whole seconds and the fraction are exact in f64 (subtracting the floor drops
        // bits only), so only the fraction is rounded.
        let whole = seconds.floor();
        let nanos = ((seconds - whole) * 1e9).round();
        // `whole` is in [0, 2^31) and `nanos` in [0, 1e9]: both casts are exact.
        let (mut sec, mut nanosec) = (whole as i64, nanos as u32);
        if nanosec >= 1_000_000_000 {
            sec += 1;
            nanosec -= 1_000_000_000;
        }
        let sec = i32::try_from(sec).map_err(|_| {
            format!(
                "time {} s is not a duration from 0 to 2^31 s",
                fmt_real(seconds)
            )
        })?;
        Ok(Self { sec, nanosec })
    }
}

/// `std_msgs/msg/Header`.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct Header {
    /// `builtin_interfaces/msg/Time`; always zero here: for a `joint_trajectory_controller`,
    /// "start as soon as received".
    pub stamp: Duration,
    /// Always empty here: joint values have no frame.
    pub frame_id: String,
}

/// `trajectory_msgs/msg/JointTrajectoryPoint`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectoryPoint {
    /// Joint positions (rad or m), one per joint name.
    pub positions: Vec<Real>,
    /// Joint velocities (rad/s or m/s), one per joint name; empty for a plan without them
    /// (format `pickplace.plan/1`: ROS makes them optional).
    pub velocities: Vec<Real>,
    /// Joint accelerations (rad/s² or m/s²), as `velocities`.
    pub accelerations: Vec<Real>,
    /// Always empty: the plan has no efforts.
    pub effort: Vec<Real>,
    /// Time since the trajectory's first point.
    pub time_from_start: Duration,
}

/// `trajectory_msgs/msg/JointTrajectory`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointTrajectory {
    /// Stamp zero, empty frame.
    pub header: Header,
    /// The joints, in the plan's (model) order.
    pub joint_names: Vec<String>,
    /// The samples, the first at time 0, times strictly increasing.
    pub points: Vec<JointTrajectoryPoint>,
}

/// Which joints of an arm a trajectory drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum GroupKind {
    /// The arm's joints ([`ArmJoints::joints`]).
    Arm,
    /// Its gripper's joints ([`ArmJoints::gripper_joints`]).
    Gripper,
}

impl GroupKind {
    /// `arm` or `gripper`.
    pub fn name(self) -> &'static str {
        match self {
            GroupKind::Arm => "arm",
            GroupKind::Gripper => "gripper",
        }
    }
}

/// One message of [`joint_trajectories`] with where it belongs in the plan.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExportedTrajectory {
    /// Index of the motion in [`Plan::motions`] (from 0).
    pub motion: usize,
    /// What the motion reaches ([`crate::plan::Motion::to`]).
    pub to: String,
    /// The arm.
    pub arm: Arm,
    /// The arm's SRDF group ([`ArmJoints::group`]; the plan names no gripper group).
    pub group: String,
    /// The arm's joints or its gripper's.
    pub kind: GroupKind,
    /// When the motion starts in the plan (s).
    pub start: Real,
    /// The message.
    pub message: JointTrajectory,
    /// Where the robot stands, as a static transform from the world frame to its root link
    /// ([`crate::tool_frame::BaseFrame`]; absent when the plan does not state it or the root
    /// link is the world frame).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub base_frame: Option<TransformStamped>,
    /// Where the arm's tool link is, as a static transform from its parent link
    /// ([`crate::tool_frame`]; absent when the plan does not state it).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tool_frame: Option<TransformStamped>,
}

/// `trajectory_msgs/msg/MultiDOFJointTrajectory`, always empty here.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct MultiDofJointTrajectory {
    /// Stamp zero, empty frame.
    pub header: Header,
    /// Empty.
    pub joint_names: Vec<String>,
    /// Empty (the element type is never needed).
    pub points: Vec<()>,
}

/// `moveit_msgs/msg/RobotTrajectory`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotTrajectory {
    /// Every joint of the plan over the whole plan.
    pub joint_trajectory: JointTrajectory,
    /// Empty.
    pub multi_dof_joint_trajectory: MultiDofJointTrajectory,
}

/// `sensor_msgs/msg/JointState`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointState {
    /// Stamp zero, empty frame.
    pub header: Header,
    /// The joints.
    pub name: Vec<String>,
    /// Their positions (rad or m).
    pub position: Vec<Real>,
    /// Empty.
    pub velocity: Vec<Real>,
    /// Empty.
    pub effort: Vec<Real>,
}

/// `sensor_msgs/msg/MultiDOFJointState`, always empty here.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize)]
pub struct MultiDofJointState {
    /// Stamp zero, empty frame.
    pub header: Header,
    /// Empty.
    pub joint_names: Vec<String>,
    /// Empty.
    pub transforms: Vec<()>,
    /// Empty.
    pub twist: Vec<()>,
    /// Empty.
    pub wrench: Vec<()>,
}

/// `moveit_msgs/msg/RobotState`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RobotState {
    /// The plan's first sample.
    pub joint_state: JointState,
    /// Empty.
    pub multi_dof_joint_state: MultiDofJointState,
    /// Empty: the object is not shown.
    pub attached_collision_objects: Vec<()>,
    /// Always false: a complete state.
    pub is_diff: bool,
}

/// `moveit_msgs/msg/DisplayTrajectory`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DisplayTrajectory {
    /// The robot's name, as MoveIt's robot model has it.
    pub model_id: String,
    /// One trajectory: the whole plan.
    pub trajectory: Vec<RobotTrajectory>,
    /// Where it starts.
    pub trajectory_start: RobotState,
}

/// The columns of `names` in the plan.
fn columns(plan: &Plan, names: &[String]) -> Result<Vec<usize>, PlanFormError> {
    names
        .iter()
        .map(|name| {
            plan.joint_names
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| {
                    PlanFormError::from(format!("joint {name:?} is not in the plan's joint_names"))
                })
        })
        .collect()
}

/// A trajectory of the joints `names` (columns `columns`) over samples `first..=last`, its
/// times from the first sample's.
fn trajectory(
    plan: &Plan,
    names: &[String],
    columns: &[usize],
    first: usize,
    last: usize,
) -> Result<JointTrajectory, PlanFormError> {
    let samples = plan
        .trajectory
        .get(first..=last)
        .ok_or_else(|| format!("samples {first}..={last} are not in the trajectory"))?;
    let start = samples.first().map_or(0.0, |p| p.time_from_start);
    let pick = |values: &[Real]| -> Vec<Real> {
        if values.is_empty() {
            Vec::new()
        } else {
            columns.iter().map(|&c| values[c]).collect()
        }
    };
    let mut points: Vec<JointTrajectoryPoint> = Vec::with_capacity(samples.len());
    for (k, p) in samples.iter().enumerate() {
        let i = first + k;
        let n = plan.joint_names.len();
        if p.positions.len() != n
            || (!p.velocities.is_empty() && p.velocities.len() != n)
            || (!p.accelerations.is_empty() && p.accelerations.len() != n)
        {
            return Err(format!("trajectory[{i}] does not have one value per joint name").into());
        }
        let time_from_start = Duration::from_seconds(p.time_from_start - start)
            .map_err(|e| format!("trajectory[{i}]: {e}"))?;
        if let Some(previous) = points.last()
            && time_from_start <= previous.time_from_start
        {
            return Err(format!(
                "trajectory[{i}]: time_from_start {} s is not after the sample before it (to the nanosecond)",
                fmt_real(p.time_from_start)
            ).into());
        }
        points.push(JointTrajectoryPoint {
            positions: pick(&p.positions),
            velocities: pick(&p.velocities),
            accelerations: pick(&p.accelerations),
            effort: Vec::new(),
            time_from_start,
        });
    }
    Ok(JointTrajectory {
        header: Header::default(),
        joint_names: names.to_vec(),
        points,
    })
}

/// True when a value of one of `columns` changes over samples `first..=last`.
fn moves(plan: &Plan, columns: &[usize], first: usize, last: usize) -> bool {
    let samples = &plan.trajectory[first..=last];
    columns.iter().any(|&c| {
        let start = samples[0].positions.get(c);
        samples.iter().any(|p| p.positions.get(c) != start)
    })
}

/// The plan as `trajectory_msgs/msg/JointTrajectory` messages: for every motion of
/// [`Plan::motions`] (from one stop of the robot to the next) and every arm that moves in
/// it, one message of the arm's joints when they move and one of its gripper's joints when
/// they move. The points are the motion's samples, both ends included (the robot at rest),
/// `time_from_start` from the motion's first sample; velocities and accelerations are the
/// plan's, or empty for a plan without them (format `pickplace.plan/1`).
///
/// # Returns
/// The messages by motion, then by arm in [`Plan::arms`] order, the arm before its gripper.
///
/// # Errors
/// A plan without [`Plan::arms`] (format `pickplace.plan/1` has none: which joints each
/// arm's controller takes is unknown), an arm joint not in the plan's joint names, a sample
/// of the wrong length, or times that are not strictly increasing to the nanosecond.
pub fn joint_trajectories(plan: &Plan) -> Result<Vec<ExportedTrajectory>, PlanFormError> {
    if plan.arms.is_empty() {
        return Err(format!(
            "the plan has no `arms` (format {:?} lists no joints per arm); plan it again to get format {:?}",
            plan.format,
            crate::plan::PLAN_FORMAT
        ).into());
    }
    let base_frame = plan
        .base
        .as_ref()
        .and_then(crate::tool_frame::BaseFrame::to_transform_stamped);
    let mut out = Vec::new();
    for (index, motion) in plan.motions().into_iter().enumerate() {
        let start = plan.trajectory[motion.first].time_from_start;
        for arm_joints in plan.arms.iter().filter(|a| motion.arms.contains(&a.arm)) {
            let ArmJoints {
                arm,
                group,
                joints,
                gripper_joints,
                tool,
            } = arm_joints;
            for (kind, names) in [
                (GroupKind::Arm, joints),
                (GroupKind::Gripper, gripper_joints),
            ] {
                let cols = columns(plan, names)?;
                if names.is_empty() || !moves(plan, &cols, motion.first, motion.last) {
                    continue;
                }
                out.push(ExportedTrajectory {
                    motion: index,
                    to: motion.to.clone(),
                    arm: *arm,
                    group: group.clone(),
                    kind,
                    start,
                    message: trajectory(plan, names, &cols, motion.first, motion.last)?,
                    base_frame: base_frame.clone(),
                    tool_frame: tool.as_ref().map(ToolFrame::to_transform_stamped),
                });
            }
        }
    }
    Ok(out)
}

/// The whole plan as a `moveit_msgs/msg/DisplayTrajectory` for the robot `model_id`: one
/// trajectory of every joint of the plan over all its samples, starting at its first.
///
/// # Errors
/// An empty trajectory, a sample of the wrong length, or times that are not strictly
/// increasing to the nanosecond.
pub fn display_trajectory(plan: &Plan, model_id: &str) -> Result<DisplayTrajectory, PlanFormError> {
    let first = plan
        .trajectory
        .first()
        .ok_or_else(|| PlanFormError::from("the plan's trajectory is empty"))?;
    let all: Vec<usize> = (0..plan.joint_names.len()).collect();
    let joint_trajectory = trajectory(plan, &plan.joint_names, &all, 0, plan.trajectory.len() - 1)?;
    Ok(DisplayTrajectory {
        model_id: model_id.to_owned(),
        trajectory: vec![RobotTrajectory {
            joint_trajectory,
            multi_dof_joint_trajectory: MultiDofJointTrajectory::default(),
        }],
        trajectory_start: RobotState {
            joint_state: JointState {
                header: Header::default(),
                name: plan.joint_names.clone(),
                position: first.positions.clone(),
                velocity: Vec::new(),
                effort: Vec::new(),
            },
            multi_dof_joint_state: MultiDofJointState::default(),
            attached_collision_objects: Vec::new(),
            is_diff: false,
        },
    })
}

/// A float as YAML 1.1 (PyYAML, which `ros2 topic pub` uses) and YAML 1.2 both read as a
/// float: the shortest form that reads back to the same `f64`, always with a `.` and a
/// signed exponent (`1.0`, `-0.25`, `1.0e-7`, `1.5e+300`). Non-finite values as `.nan`,
/// `.inf`, `-.inf`.
pub fn yaml_float(value: Real) -> String {
    if value.is_nan() {
        return ".nan".into();
    }
    if value.is_infinite() {
        return if value > 0.0 { ".inf" } else { "-.inf" }.into();
    }
    // Debug is Rust's shortest round-trip form: `1.0`, `1e-7`, `1.5e300`.
    let text = format!("{value:?}");
    match text.split_once('e') {
        Some((mantissa, exponent)) => {
            let dot = if mantissa.contains('.') { "" } else { ".0" };
            let sign = if exponent.starts_with('-') { "" } else { "+" };
            format!("{mantissa}{dot}e{sign}{exponent}")
        }
        None if text.contains('.') => text,
        None => format!("{text}.0"),
    }
}

/// A string as a YAML double-quoted scalar: printable ASCII as it is (`"` and `\` escaped),
/// every other character as `\uXXXX` or `\UXXXXXXXX`.
pub fn yaml_string(text: &str) -> String {
    let mut out = String::with_capacity(text.len() + 2);
    out.push('"');
    for c in text.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            c if u32::from(c) <= 0xFFFF => {
                let _ = write!(out, "\\u{:04X}", u32::from(c));
            }
            c => {
                let _ = write!(out, "\\U{:08X}", u32::from(c));
            }
        }
    }
    out.push('"');
    out
}

/// `values` as a YAML flow sequence of floats.
fn yaml_floats(values: &[Real]) -> String {
    let items: Vec<String> = values.iter().map(|&v| yaml_float(v)).collect();
    format!("[{}]", items.join(", "))
}

/// `{sec: S, nanosec: N}`.
fn yaml_duration(d: Duration) -> String {
    format!("{{sec: {}, nanosec: {}}}", d.sec, d.nanosec)
}

/// A `JointTrajectory` as one YAML document body (no `---`), block style with flow
/// sequences, as `ros2 topic pub TOPIC trajectory_msgs/msg/JointTrajectory "…"` takes it.
/// Floats are always written as floats ([`yaml_float`]), `sec` and `nanosec` as integers.
pub fn to_yaml(message: &JointTrajectory) -> String {
    let mut out = String::new();
    let h = &message.header;
    let _ = writeln!(
        out,
        "header:\n  stamp: {}\n  frame_id: {}",
        yaml_duration(h.stamp),
        yaml_string(&h.frame_id)
    );
    let names: Vec<String> = message.joint_names.iter().map(|n| yaml_string(n)).collect();
    let _ = writeln!(out, "joint_names: [{}]", names.join(", "));
    if message.points.is_empty() {
        out.push_str("points: []\n");
    } else {
        out.push_str("points:\n");
    }
    for p in &message.points {
        let _ = writeln!(
            out,
            "- positions: {}\n  velocities: {}\n  accelerations: {}\n  effort: {}\n  time_from_start: {}",
            yaml_floats(&p.positions),
            yaml_floats(&p.velocities),
            yaml_floats(&p.accelerations),
            yaml_floats(&p.effort),
            yaml_duration(p.time_from_start)
        );
    }
    out
}

/// The comment line that precedes a message in a YAML stream:
/// `# motion N: TO (ARM arm|gripper, group G), starts at T s in the plan`.
pub fn yaml_comment(t: &ExportedTrajectory) -> String {
    // `to` and `group` come from the plan file: keep the comment on one line.
    let one_line = |s: &str| -> String {
        s.chars()
            .map(|c| if c.is_control() { ' ' } else { c })
            .collect()
    };
    format!(
        "# motion {}: {} ({} {}, group {}), starts at {} s in the plan",
        t.motion,
        one_line(&t.to),
        t.arm.name(),
        t.kind.name(),
        one_line(&t.group),
        fmt_real(t.start)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{
        Event, EventKind, KeyPose, ObjectMotion, PLAN_FORMAT, PLAN_FORMAT_1, PlacementInfo, Stats,
        TrajectoryPoint,
    };
    use crate::scene::PoseSpec;
    use crate::strategy::Strategy;
    use pickplace_geometry::math::Isometry3;

    fn d(sec: i32, nanosec: u32) -> Duration {
        Duration { sec, nanosec }
    }

    #[test]
    fn durations_round_to_the_nanosecond_with_the_carry() {
        for (seconds, expected) in [
            (0.0, d(0, 0)),
            (1.5, d(1, 500_000_000)),
            (1.999_999_999_999, d(2, 0)),
            (1.999_999_999_4, d(1, 999_999_999)),
            (0.000_000_000_6, d(0, 1)),
            (12.345_678_901, d(12, 345_678_901)),
            (2_147_483_647.0, d(i32::MAX, 0)),
        ] {
            assert_eq!(Duration::from_seconds(seconds), Ok(expected), "{seconds}");
        }
        for bad in [-1e-9, f64::NAN, f64::INFINITY, 2_147_483_648.0] {
            assert!(Duration::from_seconds(bad).is_err(), "{bad}");
        }
        // Rounding up into 2^31 s is out of range too.
        assert!(Duration::from_seconds(2_147_483_647.999_999_9).is_err());
    }

    #[test]
    fn floats_look_like_floats_to_yaml_1_1() {
        for (value, expected) in [
            (1.0, "1.0"),
            (0.0, "0.0"),
            (-0.0, "-0.0"),
            (-0.25, "-0.25"),
            (1e-7, "1.0e-7"),
            (1.5e300, "1.5e+300"),
            (-2.5e-9, "-2.5e-9"),
            (0.1 + 0.2, "0.30000000000000004"),
            (f64::NAN, ".nan"),
            (f64::NEG_INFINITY, "-.inf"),
        ] {
            assert_eq!(yaml_float(value), expected);
        }
        for value in [1e-7, 1.5e300, 0.1 + 0.2, -2.5e-9, 123_456_789.0] {
            let text = yaml_float(value);
            assert_eq!(text.parse::<f64>(), Ok(value), "{text}");
        }
    }

    #[test]
    fn strings_are_quoted_and_escaped() {
        assert_eq!(yaml_string("RARM_JOINT0"), "\"RARM_JOINT0\"");
        assert_eq!(yaml_string("a\"b\\c"), "\"a\\\"b\\\\c\"");
        assert_eq!(yaml_string("é\n😀"), "\"\\u00E9\\u000A\\U0001F600\"");
    }

    /// Two arms of one joint and one gripper joint each; the right arm moves in samples
    /// 0..=2, its gripper closes in 2..=3 (a grasp), the left arm moves in 3..=5.
    fn plan(format: &str) -> Plan {
        let pose = PoseSpec::from_isometry(&Isometry3::identity());
        let times = [0.0, 1.0, 2.0, 3.0, 3.5, 4.25];
        // Columns r1, rg, l1, lg.
        let positions = [
            [0.0, 0.04, 0.0, 0.04],
            [0.5, 0.04, 0.0, 0.04],
            [1.0, 0.04, 0.0, 0.04],
            [1.0, 0.02, 0.0, 0.04],
            [1.0, 0.02, 0.5, 0.04],
            [1.0, 0.02, 1.0, 0.04],
        ];
        let trajectory = times
            .iter()
            .zip(positions)
            .map(|(&t, q)| TrajectoryPoint {
                time_from_start: t,
                positions: q.to_vec(),
                // Moving in the middle of each motion, at rest where they meet.
                velocities: vec![
                    if t == 1.0 { 1.0 } else { 0.0 },
                    0.0,
                    if t == 3.5 { 1.0 } else { 0.0 },
                    0.0,
                ],
                accelerations: vec![0.0; 4],
            })
            .collect();
        let arm = |arm: Arm, prefix: &str| ArmJoints {
            arm,
            group: format!("{}_arm", arm.name()),
            joints: vec![format!("{prefix}1")],
            gripper_joints: vec![format!("{prefix}g")],
            tool: None,
        };
        Plan {
            format: format.into(),
            seed: 1,
            strategy: Strategy::RightLeft,
            joint_names: ["r1", "rg", "l1", "lg"].map(String::from).to_vec(),
            base: None,
            arms: vec![arm(Arm::Right, "r"), arm(Arm::Left, "l")],
            limits: None,
            trajectory,
            events: vec![Event {
                time: 3.0,
                kind: EventKind::Grasp,
                arm: Arm::Right,
                link: "r_tool".into(),
                link_from_object: pose,
            }],
            object: ObjectMotion {
                start_pose: pose,
                placed_pose: pose,
            },
            placement: PlacementInfo {
                contact: "face-face".into(),
                object_cluster: 0,
                environment: "table".into(),
                env_cluster: 0,
                stability_margin: 0.01,
                rank: 0,
            },
            rests: vec![],
            grasps: vec![],
            key_poses: vec![KeyPose {
                name: "grasp".into(),
                arm: Arm::Right,
                time: 2.0,
                world_from_tcp: pose,
                world_from_object: pose,
            }],
            stats: Stats::default(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn one_message_per_motion_and_moving_group() {
        let p = plan(PLAN_FORMAT);
        let t = joint_trajectories(&p).expect("exports");
        let summary: Vec<(usize, &str, Arm, GroupKind, usize)> = t
            .iter()
            .map(|t| {
                (
                    t.motion,
                    t.to.as_str(),
                    t.arm,
                    t.kind,
                    t.message.points.len(),
                )
            })
            .collect();
        assert_eq!(
            summary,
            [
                (0, "grasp", Arm::Right, GroupKind::Arm, 3),
                (1, "grasp (right)", Arm::Right, GroupKind::Gripper, 2),
                (2, "end", Arm::Left, GroupKind::Arm, 3),
            ]
        );
        let left = &t[2];
        assert_eq!(left.message.joint_names, ["l1"]);
        assert_eq!(left.start, 3.0);
        assert_eq!(left.group, "left_arm");
        let times: Vec<Duration> = left
            .message
            .points
            .iter()
            .map(|p| p.time_from_start)
            .collect();
        assert_eq!(times, [d(0, 0), d(0, 500_000_000), d(1, 250_000_000)]);
        assert_eq!(left.message.points[1].positions, [0.5]);
        assert_eq!(left.message.points[1].velocities, [1.0]);
        assert_eq!(left.message.points[1].accelerations, [0.0]);
        assert!(left.message.points[1].effort.is_empty());
        assert_eq!(
            yaml_comment(left),
            "# motion 2: end (left arm, group left_arm), starts at 3 s in the plan"
        );
    }

    #[test]
    fn a_plan_without_velocities_exports_empty_lists_and_one_without_arms_is_refused() {
        let mut p = plan(PLAN_FORMAT_1);
        for s in &mut p.trajectory {
            *s = TrajectoryPoint::positions_only(s.time_from_start, s.positions.clone());
        }
        let t = joint_trajectories(&p).expect("exports");
        assert!(
            t.iter()
                .flat_map(|t| &t.message.points)
                .all(|p| p.velocities.is_empty() && p.accelerations.is_empty())
        );
        assert!(to_yaml(&t[0].message).contains("  velocities: []\n"));
        p.arms.clear();
        let e = joint_trajectories(&p).expect_err("no arms");
        assert!(e.reason().contains("the plan has no `arms`"), "{e}");
        // The display trajectory needs no arms.
        let shown = display_trajectory(&p, "robot").expect("display");
        assert_eq!(shown.trajectory[0].joint_trajectory.points.len(), 6);
    }

    #[test]
    fn samples_closer_than_a_nanosecond_are_refused() {
        let mut p = plan(PLAN_FORMAT);
        p.trajectory[4].time_from_start = p.trajectory[3].time_from_start + 1e-10;
        let e = joint_trajectories(&p).expect_err("same nanosecond");
        assert!(
            e.reason().starts_with("trajectory[4]: time_from_start"),
            "{e}"
        );
    }

    #[test]
    fn the_display_trajectory_has_every_joint_over_the_whole_plan() {
        let p = plan(PLAN_FORMAT);
        let shown = display_trajectory(&p, "hironx").expect("display");
        let jt = &shown.trajectory[0].joint_trajectory;
        assert_eq!(jt.joint_names, p.joint_names);
        assert_eq!(jt.points.len(), p.trajectory.len());
        assert_eq!(jt.points[5].positions, p.trajectory[5].positions);
        assert_eq!(
            shown.trajectory_start.joint_state.position,
            p.trajectory[0].positions
        );
        let json = serde_json::to_value(&shown).expect("json");
        assert_eq!(json["model_id"], "hironx");
        assert_eq!(
            json["trajectory"][0]["multi_dof_joint_trajectory"]["points"],
            serde_json::json!([])
        );
        assert_eq!(json["trajectory_start"]["is_diff"], false);
    }
}
