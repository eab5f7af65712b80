//! The plan: what `pickplace plan` returns (JSON format `pickplace.plan/2`, documented in
//! `docs/plan-format.md`; plans of format `pickplace.plan/1`, positions only, are still read).
//!
//! A plan is self-contained for playback: the robot's actuated joints in model order, a
//! time-stamped trajectory of all of them, grasp/release events that say which link holds the
//! object and where, the object's start and placed poses, and the key poses of the paper's
//! Fig. 8 pipeline. `stats` says how the plan was found (candidate counts and rejection reasons
//! per strategy and stage, and the time of each stage).

use crate::scene::PoseSpec;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::{Isometry3, Real};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

pub mod export;
mod form;
mod playback;
#[cfg(test)]
mod tests;

pub use playback::Motion;

/// The names a key pose may have (`docs/plan-format.md`, `key_poses[]`).
pub const KEY_POSE_NAMES: [&str; 19] = [
    "pre-grasp",
    "grasp",
    "lift",
    "handover",
    "pre-regrasp",
    "regrasp",
    "release-first",
    "retreat-first",
    "home-first",
    "pre-rest",
    "rest",
    "release-rest",
    "retreat-rest",
    "lift-again",
    "pre-place",
    "place",
    "release",
    "retreat",
    "home",
];

/// At most 64 characters of a string from a plan, for messages.
pub(crate) fn clip(text: &str) -> String {
    match text.char_indices().nth(64) {
        Some((end, _)) => format!("{}…", &text[..end]),
        None => text.to_string(),
    }
}

/// The plan format written in [`Plan::format`].
pub const PLAN_FORMAT: &str = "pickplace.plan/2";

/// A plan file; default limit 1 GiB.
pub const PLAN_FILE: pickplace_geometry::io::FileKind =
    pickplace_geometry::io::FileKind::new("a plan", 1024 * pickplace_geometry::io::MIB);

/// What is wrong with a plan document: the parser's message (line and column) when the text
/// is not a plan of this format, else the first rule of its form it breaks, named by its
/// field (`trajectory[3] has 5 positions for 6 joints`). [`Plan::load`] adds the file.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{reason}")]
pub struct PlanFormError {
    reason: String,
}

impl PlanFormError {
    /// The message, without the file.
    pub fn reason(&self) -> &str {
        &self.reason
    }
}

impl From<String> for PlanFormError {
    fn from(reason: String) -> Self {
        Self { reason }
    }
}

impl From<&str> for PlanFormError {
    fn from(reason: &str) -> Self {
        Self {
            reason: reason.to_owned(),
        }
    }
}

/// The earlier format still read: its samples have positions only and it has no `arms`.
pub const PLAN_FORMAT_1: &str = "pickplace.plan/1";

/// A complete pick-and-place plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plan {
    /// Always [`PLAN_FORMAT`].
    pub format: String,
    /// The seed every random choice derived from.
    pub seed: u64,
    /// The strategy that succeeded (paper §III-B.3).
    pub strategy: Strategy,
    /// Every actuated joint of the robot (grippers included), in model order: the columns of
    /// [`TrajectoryPoint::positions`].
    pub joint_names: Vec<String>,
    /// Where the robot stands: its root link and `world_from_root`, the frame of the world
    /// poses (`world_from_tcp`, `world_from_object`) on the robot's URDF (absent in format
    /// `pickplace.plan/1` and in plans written before it was stated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<crate::tool_frame::BaseFrame>,
    /// Each arm's joints and its gripper's (names from [`Plan::joint_names`]): the joints of
    /// the trajectories [`Plan::motions`] gives per arm, as a controller of that arm expects
    /// them (absent in format `pickplace.plan/1`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub arms: Vec<ArmJoints>,
    /// The limits the trajectory was timed with (absent in format `pickplace.plan/1`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<Limits>,
    /// The time-stamped joint trajectory, starting at the scene's start state.
    pub trajectory: Vec<TrajectoryPoint>,
    /// Grasps and releases, in time order.
    pub events: Vec<Event>,
    /// Where the object starts and where it ends.
    pub object: ObjectMotion,
    /// The placement chosen (paper §III-B.2).
    pub placement: PlacementInfo,
    /// The intermediate resting poses of a regrasp by placing, in time order (absent for the
    /// other strategies).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub rests: Vec<RestInfo>,
    /// The grasps used, in time order: one, or two with a handover or a regrasp by placing.
    pub grasps: Vec<GraspInfo>,
    /// The key poses of the motion, in time order.
    pub key_poses: Vec<KeyPose>,
    /// How the plan was found.
    pub stats: Stats,
    /// What the setup went on from: the robot's files (URDF load warnings, SRDF elements left
    /// out) and the scene's meshes, one line each (absent when there is none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// One sample of the trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrajectoryPoint {
    /// Time since the start (s).
    pub time_from_start: Real,
    /// Joint values, one per [`Plan::joint_names`] (rad or m).
    pub positions: Vec<Real>,
    /// Joint velocities, one per joint (rad/s or m/s; absent in format `pickplace.plan/1`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub velocities: Vec<Real>,
    /// Joint accelerations, one per joint (rad/s² or m/s²; absent in format
    /// `pickplace.plan/1`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub accelerations: Vec<Real>,
}

impl TrajectoryPoint {
    /// A sample with positions only (the form of format `pickplace.plan/1`).
    pub fn positions_only(time_from_start: Real, positions: Vec<Real>) -> Self {
        Self {
            time_from_start,
            positions,
            velocities: Vec::new(),
            accelerations: Vec::new(),
        }
    }
}

/// The limits a plan was timed with: each joint's (in [`Plan::joint_names`] order), the
/// scaling factors already applied.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Limits {
    /// Velocity limits (rad/s or m/s).
    pub velocities: Vec<Real>,
    /// Acceleration limits (rad/s² or m/s²).
    pub accelerations: Vec<Real>,
    /// The velocity scaling factor applied.
    pub velocity_scaling: Real,
    /// The acceleration scaling factor applied.
    pub acceleration_scaling: Real,
}

/// One arm's joints in a plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArmJoints {
    /// Which arm.
    pub arm: Arm,
    /// Its SRDF group.
    pub group: String,
    /// The arm's joints, in model order.
    pub joints: Vec<String>,
    /// Its gripper's actuated joints (the closing command), in model order.
    pub gripper_joints: Vec<String>,
    /// Where its tool link (the `link` of its events, the frame of `world_from_tcp`) is on
    /// the robot's URDF (absent in format `pickplace.plan/1` and in plans written before it
    /// was stated).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tool: Option<crate::tool_frame::ToolFrame>,
}

/// What happens to the object at an instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EventKind {
    /// The gripper closes: from this instant the object moves with `link`.
    Grasp,
    /// The gripper opens: the object no longer moves with `link`.
    Release,
}

/// A grasp or release.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Event {
    /// Time since the start (s); equal to a trajectory sample's time.
    pub time: Real,
    /// Grasp or release.
    pub kind: EventKind,
    /// The arm.
    pub arm: Arm,
    /// The link holding the object (the arm's tool frame).
    pub link: String,
    /// The object's pose in that link's frame while held.
    pub link_from_object: PoseSpec,
}

/// The object's start and end.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObjectMotion {
    /// `world_from_object` at the start.
    pub start_pose: PoseSpec,
    /// `world_from_object` once placed.
    pub placed_pose: PoseSpec,
}

/// The placement chosen.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlacementInfo {
    /// `face-face` or `edge-face`.
    pub contact: String,
    /// Object cluster in contact.
    pub object_cluster: usize,
    /// Environment mesh the object rests on (its scene name).
    pub environment: String,
    /// Environment cluster in contact (in that mesh's clustering).
    pub env_cluster: usize,
    /// Distance from the CoG's vertical to the support hull's boundary (m).
    pub stability_margin: Real,
    /// Rank among the placement candidates (0 = best).
    pub rank: usize,
}

/// An intermediate resting pose of a regrasp by placing: where the object is put down and
/// picked up again.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RestInfo {
    /// `world_from_object` while it rests there.
    pub world_from_object: PoseSpec,
    /// The stable placement it is (its `rank` among the resting poses searched).
    pub placement: PlacementInfo,
}

/// A grasp used by the plan.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GraspInfo {
    /// The arm.
    pub arm: Arm,
    /// Tool frame pose in the object's frame.
    pub object_from_tcp: PoseSpec,
    /// Distance between the finger pads when closed (m).
    pub width: Real,
    /// Quality score (higher is better; `docs/grasp.md`).
    pub score: Real,
    /// Rank among the grasp candidates (0 = best).
    pub rank: usize,
}

/// A key pose of the motion (paper Fig. 8).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyPose {
    /// `pre-grasp`, `grasp`, `lift`, `handover`, `pre-regrasp`, `regrasp`, `pre-place`,
    /// `place`, `release`, `retreat`, ….
    pub name: String,
    /// The arm that reaches this pose.
    pub arm: Arm,
    /// Time since the start (s).
    pub time: Real,
    /// `world_from_tcp` of that arm.
    pub world_from_tcp: PoseSpec,
    /// `world_from_object` at that instant.
    pub world_from_object: PoseSpec,
}

/// How the plan was found.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Stats {
    /// Wall-clock time of each stage (s). The only part of a plan that changes between runs
    /// with the same seed; `pickplace plan --no-timings` leaves it empty.
    #[serde(default)]
    pub timings: BTreeMap<String, Real>,
    /// Every strategy tried, in order.
    pub strategies: Vec<StrategyReport>,
    /// Placement candidates found.
    pub placement_candidates: usize,
    /// Grasp candidates found (per arm, the same object grasps).
    pub grasp_candidates: usize,
    /// The candidate stages before any strategy, `grasp` (the object's grasp set: candidates
    /// tried, accepted, rejected per reason) and `placement` (placements on the target's
    /// surface, rejected per reason), so that a stage that ends empty says why.
    #[serde(default)]
    pub candidates: BTreeMap<String, StageCount>,
    /// Samples in the trajectory.
    pub trajectory_points: usize,
    /// Duration of the motion (s).
    pub duration: Real,
}

/// What happened with one strategy.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StrategyReport {
    /// The strategy.
    pub strategy: Strategy,
    /// True when it gave the plan.
    pub success: bool,
    /// Per stage (`placement`, `grasp`, `pick`, `place`, `handover`, `motion`, …): how many
    /// candidates were tried, accepted, and rejected per reason.
    pub stages: BTreeMap<String, StageCount>,
}

/// Candidate counts of one stage.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StageCount {
    /// Candidates tried.
    pub tried: usize,
    /// Candidates that passed.
    pub accepted: usize,
    /// Rejections by reason (`no IK`, `collision: RARM_JOINT5_Link / pallet`, …).
    pub rejected: BTreeMap<String, usize>,
}

impl StageCount {
    /// Counts a rejection.
    pub fn reject(&mut self, reason: impl Into<String>) {
        self.tried += 1;
        *self.rejected.entry(reason.into()).or_default() += 1;
    }

    /// Counts an acceptance.
    pub fn accept(&mut self) {
        self.tried += 1;
        self.accepted += 1;
    }
}

/// The object in one hand, from a grasp event to the release by the same link: how a plan is
/// played back (the object rides with `link` in between and stays where it was left after).
#[derive(Debug, Clone, PartialEq)]
pub struct Hold {
    /// The holding link (an arm's tool frame).
    pub link: String,
    /// The object's pose in that link's frame.
    pub link_from_object: Isometry3,
    /// When the grasp happens (s).
    pub grasp_time: Real,
    /// When the release happens (s); `None` when the plan ends with the object held.
    pub release_time: Option<Real>,
}
