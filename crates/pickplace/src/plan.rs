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

impl Plan {
    /// The plan's holds in time order of their grasps: each grasp lasts until the next
    /// release by the same link.
    ///
    /// # Errors
    /// `event I: …` for an event whose pose is invalid or a release without a grasp by the
    /// same link before it (events numbered in time order).
    pub fn holds(&self) -> Result<Vec<Hold>, PlanFormError> {
        let mut events: Vec<&Event> = self.events.iter().collect();
        events.sort_by(|a, b| a.time.total_cmp(&b.time));
        let mut holds: Vec<Hold> = Vec::new();
        let mut open: Vec<(&str, usize)> = Vec::new();
        for (i, e) in events.iter().enumerate() {
            match e.kind {
                EventKind::Grasp => {
                    let link_from_object = e
                        .link_from_object
                        .to_isometry()
                        .map_err(|r| format!("event {i}: link_from_object: {r}"))?;
                    open.push((&e.link, holds.len()));
                    holds.push(Hold {
                        link: e.link.clone(),
                        link_from_object,
                        grasp_time: e.time,
                        release_time: None,
                    });
                }
                EventKind::Release => {
                    let k = open
                        .iter()
                        .rposition(|(l, _)| *l == e.link)
                        .ok_or_else(|| {
                            format!(
                                "event {i}: release by {:?} without a grasp before it",
                                e.link
                            )
                        })?;
                    let (_, h) = open.remove(k);
                    holds[h].release_time = Some(e.time);
                }
            }
        }
        Ok(holds)
    }

    /// For each of `names` (a robot's actuated joints, in its order), the column of
    /// [`TrajectoryPoint::positions`] that holds it.
    ///
    /// # Errors
    /// When the plan's joints are not exactly these: the missing and the unknown names.
    pub fn columns(&self, names: &[&str]) -> Result<Vec<usize>, PlanFormError> {
        let found: Vec<Option<usize>> = names
            .iter()
            .map(|n| self.joint_names.iter().position(|p| p == n))
            .collect();
        let missing: Vec<&str> = names
            .iter()
            .zip(&found)
            .filter(|(_, c)| c.is_none())
            .map(|(n, _)| *n)
            .collect();
        let unknown: Vec<&str> = self
            .joint_names
            .iter()
            .map(String::as_str)
            .filter(|p| !names.contains(p))
            .collect();
        if !missing.is_empty() || !unknown.is_empty() {
            return Err(format!("missing {missing:?}, unknown {unknown:?}").into());
        }
        Ok(found.into_iter().flatten().collect())
    }

    /// The plan as pretty JSON (with a final newline).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a plan always serialises");
        s.push('\n');
        s
    }

    /// Checks every pose of the plan (the object's, events', rests', grasps', the base's, the
    /// arms' tool frames' and key poses'): finite numbers and a non-zero quaternion.
    ///
    /// # Errors
    /// The first invalid pose, by its field (`key_poses[3].world_from_tcp: orientation
    /// quaternion is zero`).
    pub fn check_poses(&self) -> Result<(), PlanFormError> {
        let check = |field: String, pose: &PoseSpec| {
            pose.to_isometry()
                .map(|_| ())
                .map_err(|r| format!("{field}: {r}"))
        };
        check("object.start_pose".into(), &self.object.start_pose)?;
        check("object.placed_pose".into(), &self.object.placed_pose)?;
        for (i, e) in self.events.iter().enumerate() {
            check(format!("events[{i}].link_from_object"), &e.link_from_object)?;
        }
        for (i, r) in self.rests.iter().enumerate() {
            check(
                format!("rests[{i}].world_from_object"),
                &r.world_from_object,
            )?;
        }
        for (i, g) in self.grasps.iter().enumerate() {
            check(format!("grasps[{i}].object_from_tcp"), &g.object_from_tcp)?;
        }
        if let Some(base) = &self.base {
            check("base.world_from_root".into(), &base.world_from_root)?;
        }
        for (i, a) in self.arms.iter().enumerate() {
            if let Some(tool) = &a.tool {
                check(
                    format!("arms[{i}].tool.parent_from_tool"),
                    &tool.parent_from_tool,
                )?;
            }
        }
        for (i, k) in self.key_poses.iter().enumerate() {
            check(format!("key_poses[{i}].world_from_tcp"), &k.world_from_tcp)?;
            check(
                format!("key_poses[{i}].world_from_object"),
                &k.world_from_object,
            )?;
        }
        Ok(())
    }

    /// Checks the rules of `docs/plan-format.md` that need no robot ("Form of a plan"): the
    /// trajectory starts at time 0; events are in time order, from time 0 on, each
    /// release after a grasp by the same link and no grasp by a link already holding, by the
    /// strategy's arms (the first grasp by the picking arm, the last release by the placing
    /// arm), each by its arm's tool link where the plan states it (`arms[].tool`); one grasp,
    /// or two with a handover or a regrasp by placing, the first by the picking arm and the
    /// last by the placing arm; `rests` exactly in a regrasp by placing;
    /// key poses with the documented names, in time order from time 0 on, by the
    /// strategy's arms; contacts `face-face` or `edge-face`; finite numbers everywhere.
    ///
    /// # Errors
    /// The first rule broken, by its field (`events[2]: …`).
    pub fn check_form(&self) -> Result<(), PlanFormError> {
        let Some(first) = self.trajectory.first() else {
            return Err("trajectory: empty (it starts at the scene's start state)".into());
        };
        if first.time_from_start != 0.0 {
            return Err(format!(
                "trajectory[0]: time_from_start {} s, the trajectory starts at time 0",
                fmt_real(first.time_from_start)
            )
            .into());
        }
        // An event or key pose after the end of the trajectory is a problem `validate`
        // reports (exit 1), not a matter of form.
        let within = |field: String, t: Real| -> Result<(), PlanFormError> {
            if !t.is_finite() || t < 0.0 {
                return Err(format!(
                    "{field}: time {} s is not a finite time from 0 on",
                    fmt_real(t)
                )
                .into());
            }
            Ok(())
        };
        let arms = self.strategy.arms();
        let by_strategy = |field: String, arm: Arm| -> Result<(), PlanFormError> {
            if !arms.contains(&arm) {
                return Err(format!(
                    "{field}: arm {arm} is not an arm of the strategy {}",
                    self.strategy
                )
                .into());
            }
            Ok(())
        };
        let mut holding: Vec<&str> = Vec::new();
        let mut previous = 0.0;
        for (i, e) in self.events.iter().enumerate() {
            let field = format!("events[{i}]");
            within(field.clone(), e.time)?;
            if e.time < previous {
                return Err(format!(
                    "{field}: before the event above it (events are in time order)"
                )
                .into());
            }
            previous = e.time;
            by_strategy(field.clone(), e.arm)?;
            match e.kind {
                EventKind::Grasp => {
                    if holding.contains(&e.link.as_str()) {
                        return Err(format!(
                            "{field}: grasp by {:?}, which already holds the object",
                            e.link
                        )
                        .into());
                    }
                    holding.push(&e.link);
                }
                EventKind::Release => {
                    let Some(k) = holding.iter().position(|l| *l == e.link) else {
                        return Err(format!(
                            "{field}: release by {:?} without a grasp before it",
                            e.link
                        )
                        .into());
                    };
                    holding.remove(k);
                }
            }
        }
        crate::tool_frame::check_events(&self.arms, &self.events).map_err(|e| e.to_string())?;
        let first_grasp = self.events.iter().find(|e| e.kind == EventKind::Grasp);
        let last_release = self
            .events
            .iter()
            .rev()
            .find(|e| e.kind == EventKind::Release);
        if let Some(g) = first_grasp
            && g.arm != self.strategy.pick_arm()
        {
            return Err(format!(
                "events: the first grasp is by the {} arm, the strategy {} picks with the {} arm",
                g.arm,
                self.strategy,
                self.strategy.pick_arm()
            )
            .into());
        }
        if let Some(r) = last_release
            && r.arm != self.strategy.place_arm()
        {
            return Err(format!(
                "events: the last release is by the {} arm, the strategy {} places with the {} arm",
                r.arm,
                self.strategy,
                self.strategy.place_arm()
            )
            .into());
        }
        // A regrasp by placing takes one more grasp than it has rests (one per transfer).
        let expected = if self.strategy.has_regrasp() {
            self.rests.len() + 1
        } else if self.strategy.has_handover() {
            2
        } else {
            1
        };
        if self.strategy.has_regrasp() && !(1..=2).contains(&self.rests.len()) {
            return Err(format!(
                "rests: {} given; a regrasp by placing has one or two (strategy {})",
                self.rests.len(),
                self.strategy
            )
            .into());
        }
        if self.grasps.len() != expected {
            let with = if self.strategy.has_regrasp() {
                format!(" with {} rest(s)", self.rests.len())
            } else {
                String::new()
            };
            return Err(format!(
                "grasps: {} given, the strategy {}{with} uses {expected}",
                self.grasps.len(),
                self.strategy
            )
            .into());
        }
        for (i, g) in self.grasps.iter().enumerate() {
            if !(g.width.is_finite() && g.score.is_finite()) {
                return Err(format!("grasps[{i}]: a non-finite width or score").into());
            }
        }
        let arm_of = |i: usize| self.grasps[i].arm;
        if arm_of(0) != self.strategy.pick_arm()
            || arm_of(expected - 1) != self.strategy.place_arm()
        {
            return Err(format!(
                "grasps: by the {} then the {} arm, the strategy {} picks with the {} and places with the {}",
                arm_of(0),
                arm_of(expected - 1),
                self.strategy,
                self.strategy.pick_arm(),
                self.strategy.place_arm()
            ).into());
        }
        if self.strategy.has_regrasp() == self.rests.is_empty() {
            return Err(format!(
                "rests: {} given; there is at least one exactly in a regrasp by placing (strategy {})",
                self.rests.len(),
                self.strategy
            ).into());
        }
        let contact = |field: String, p: &PlacementInfo| -> Result<(), PlanFormError> {
            if !matches!(p.contact.as_str(), "face-face" | "edge-face") {
                return Err(format!(
                    "{field}.contact: {:?} is neither \"face-face\" nor \"edge-face\"",
                    clip(&p.contact)
                )
                .into());
            }
            if !p.stability_margin.is_finite() {
                return Err(format!("{field}.stability_margin: not a finite number").into());
            }
            Ok(())
        };
        contact("placement".into(), &self.placement)?;
        for (i, r) in self.rests.iter().enumerate() {
            contact(format!("rests[{i}].placement"), &r.placement)?;
        }
        let mut previous = 0.0;
        for (i, k) in self.key_poses.iter().enumerate() {
            let field = format!("key_poses[{i}]");
            if !KEY_POSE_NAMES.contains(&k.name.as_str()) {
                return Err(format!(
                    "{field}: {:?} is not a key pose name (docs/plan-format.md)",
                    clip(&k.name)
                )
                .into());
            }
            within(field.clone(), k.time)?;
            if k.time < previous {
                return Err(format!(
                    "{field}: before the key pose above it (key poses are in time order)"
                )
                .into());
            }
            previous = k.time;
            by_strategy(field, k.arm)?;
        }
        Ok(())
    }

    /// Reads a plan file (at most the size [`pickplace_geometry::io::FileKind::Plan`]
    /// allows) and checks its form as [`Plan::from_json`] does: the one reader of plan files
    /// for the CLI and Python.
    ///
    /// # Errors
    /// [`crate::Error::BadPlan`] naming the file: `cannot read the plan: …` (missing, not a
    /// file, too large, not UTF-8) or `not a valid plan: …` ([`PlanFormError`]).
    pub fn load(path: &std::path::Path) -> crate::Result<Self> {
        let bad = |reason: String| crate::Error::BadPlan {
            path: path.to_path_buf(),
            reason,
        };
        let text = pickplace_geometry::io::read_text(path, pickplace_geometry::io::FileKind::Plan)
            .map_err(|e| bad(format!("cannot read the plan: {e}")))?;
        Self::from_json(&text).map_err(|e| bad(format!("not a valid plan: {e}")))
    }

    /// Reads a plan from JSON and checks its form: one position per joint name, finite
    /// numbers, times from 0 on that never decrease, valid poses ([`Plan::check_poses`]).
    /// The other rules of the form ([`Plan::check_form`]) are `validate`'s: `view` plays any
    /// trajectory with events.
    ///
    /// # Errors
    /// The parser's message (line and column) when the text is not a plan of this format, or
    /// the first sample or pose whose form is wrong.
    pub fn from_json(text: &str) -> Result<Self, PlanFormError> {
        let plan: Plan = serde_json::from_str(text)
            .map_err(|e| pickplace_geometry::io::short_message(&e.to_string()))?;
        let current = plan.format == PLAN_FORMAT;
        if !current && plan.format != PLAN_FORMAT_1 {
            return Err(format!(
                "format {:?} is not {PLAN_FORMAT:?} (or the earlier {PLAN_FORMAT_1:?})",
                plan.format
            )
            .into());
        }
        let n = plan.joint_names.len();
        for (i, p) in plan.trajectory.iter().enumerate() {
            if p.positions.len() != n {
                return Err(format!(
                    "trajectory[{i}] has {} positions for {n} joints",
                    p.positions.len()
                )
                .into());
            }
            for (what, values) in [
                ("velocities", &p.velocities),
                ("accelerations", &p.accelerations),
            ] {
                if current && values.len() != n {
                    return Err(format!(
                        "trajectory[{i}] has {} {what} for {n} joints",
                        values.len()
                    )
                    .into());
                }
                if !current && !values.is_empty() {
                    return Err(format!(
                        "trajectory[{i}] has {what}, which format {PLAN_FORMAT_1:?} does not have (write format {PLAN_FORMAT:?})"
                    ).into());
                }
            }
            if !p.time_from_start.is_finite()
                || p.positions
                    .iter()
                    .chain(&p.velocities)
                    .chain(&p.accelerations)
                    .any(|v| !v.is_finite())
            {
                return Err(format!("trajectory[{i}] has a non-finite number").into());
            }
            if p.time_from_start < 0.0 {
                return Err(format!(
                    "trajectory[{i}]: time_from_start {} s is negative (times start at 0)",
                    fmt_real(p.time_from_start)
                )
                .into());
            }
            if i > 0 && p.time_from_start < plan.trajectory[i - 1].time_from_start {
                return Err(format!("trajectory[{i}] goes back in time").into());
            }
        }
        if let Some(l) = &plan.limits {
            if !current {
                return Err(format!(
                    "limits: format {PLAN_FORMAT_1:?} has no limits (write format {PLAN_FORMAT:?})"
                )
                .into());
            }
            if l.velocities.len() != n || l.accelerations.len() != n {
                return Err(
                    format!("limits: one velocity and one acceleration per joint ({n})").into(),
                );
            }
            if l.velocities
                .iter()
                .chain(&l.accelerations)
                .chain([&l.velocity_scaling, &l.acceleration_scaling])
                .any(|v| !(v.is_finite() && *v > 0.0))
            {
                return Err("limits: every limit and factor is a positive number".into());
            }
        }
        for (i, a) in plan.arms.iter().enumerate() {
            if !current {
                return Err(format!(
                    "arms: format {PLAN_FORMAT_1:?} has no arms (write format {PLAN_FORMAT:?})"
                )
                .into());
            }
            if plan.arms[..i].iter().any(|b| b.arm == a.arm) {
                return Err(format!("arms[{i}]: arm {} is listed twice", a.arm).into());
            }
            if let Some(j) = a
                .joints
                .iter()
                .chain(&a.gripper_joints)
                .find(|j| !plan.joint_names.contains(j))
            {
                return Err(format!("arms[{i}]: joint {:?} is not in joint_names", clip(j)).into());
            }
        }
        plan.check_poses()?;
        Ok(plan)
    }

    /// The plan cut into its motions: from one stop of the robot to the next. The robot
    /// stops at the start, at every grasp and release, at the end, and wherever a sample's
    /// velocities are all 0 (format 2: a key pose it does not pass through moving, a corner
    /// that was not blended); in a plan without velocities (format 1), at every key pose. A
    /// motion is the samples from one stop to the next, both included. Times that fall
    /// between samples (a malformed plan) cut at the sample before.
    pub fn motions(&self) -> Vec<Motion> {
        let Some(last) = self.trajectory.len().checked_sub(1) else {
            return Vec::new();
        };
        let index_at = |t: Real| {
            self.trajectory
                .partition_point(|p| p.time_from_start <= t + 1e-9)
                .saturating_sub(1)
        };
        let at_rest = |i: usize| {
            self.trajectory
                .get(i)
                .is_some_and(|p| p.velocities.iter().all(|v| *v == 0.0))
        };
        // Each cut with what happens there (the latest name wins at one instant).
        let mut cuts: BTreeMap<usize, String> = BTreeMap::new();
        for k in &self.key_poses {
            let i = index_at(k.time);
            if at_rest(i) {
                cuts.insert(i, k.name.clone());
            }
        }
        for e in &self.events {
            let name = match e.kind {
                EventKind::Grasp => "grasp",
                EventKind::Release => "release",
            };
            cuts.entry(index_at(e.time))
                .or_insert_with(|| format!("{name} ({})", e.arm));
        }
        for i in 1..last {
            if self.trajectory[i].velocities.iter().any(|_| true) && at_rest(i) {
                cuts.entry(i).or_insert_with(|| "stop".into());
            }
        }
        cuts.entry(last).or_insert_with(|| "end".into());
        let mut motions = Vec::new();
        let mut from = 0;
        for (to, name) in cuts {
            if to <= from {
                continue;
            }
            let moved = |columns: &[usize]| {
                columns.iter().any(|&c| {
                    let first = self.trajectory[from].positions.get(c);
                    self.trajectory[from..=to]
                        .iter()
                        .any(|p| p.positions.get(c) != first)
                })
            };
            let column = |name: &String| self.joint_names.iter().position(|n| n == name);
            let arms = self
                .arms
                .iter()
                .filter(|a| {
                    let columns: Vec<usize> = a
                        .joints
                        .iter()
                        .chain(&a.gripper_joints)
                        .filter_map(column)
                        .collect();
                    moved(&columns)
                })
                .map(|a| a.arm)
                .collect();
            motions.push(Motion {
                first: from,
                last: to,
                to: name,
                arms,
            });
            from = to;
        }
        motions
    }
}

/// A motion of a plan ([`Plan::motions`]): samples `first..=last` of the trajectory.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Motion {
    /// Index of its first sample (the robot at rest).
    pub first: usize,
    /// Index of its last sample (the robot at rest).
    pub last: usize,
    /// What it reaches: the key pose's name, `grasp (right)`, `release (left)`, `stop` (a
    /// corner that was not blended) or `end`.
    pub to: String,
    /// The arms (from [`Plan::arms`]) whose joints or gripper move in it.
    pub arms: Vec<Arm>,
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::strategy::Strategy;

    fn event(time: Real, kind: EventKind, link: &str) -> Event {
        Event {
            time,
            kind,
            arm: Arm::Right,
            link: link.into(),
            link_from_object: PoseSpec::from_isometry(&Isometry3::identity()),
        }
    }

    fn plan(events: Vec<Event>) -> Plan {
        let pose = PoseSpec::from_isometry(&Isometry3::identity());
        Plan {
            format: PLAN_FORMAT.into(),
            seed: 1,
            strategy: Strategy::RightLeft,
            joint_names: vec!["a".into(), "b".into()],
            base: None,
            arms: vec![],
            limits: None,
            trajectory: vec![],
            events,
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
            key_poses: vec![],
            stats: Stats::default(),
            warnings: Vec::new(),
        }
    }

    #[test]
    fn a_handover_is_two_overlapping_holds() {
        let p = plan(vec![
            event(5.0, EventKind::Release, "R"),
            event(1.0, EventKind::Grasp, "R"),
            event(4.0, EventKind::Grasp, "L"),
            event(9.0, EventKind::Release, "L"),
        ]);
        let holds = p.holds().expect("consistent");
        let spans: Vec<_> = holds
            .iter()
            .map(|h| (h.link.as_str(), h.grasp_time, h.release_time))
            .collect();
        assert_eq!(spans, [("R", 1.0, Some(5.0)), ("L", 4.0, Some(9.0))]);
        let bad = plan(vec![event(1.0, EventKind::Release, "R")]);
        assert_eq!(
            bad.holds().unwrap_err(),
            "event 0: release by \"R\" without a grasp before it".into()
        );
    }

    #[test]
    fn motions_end_where_the_robot_stops() {
        // Joint a moves from 0 to 4 over samples 0..=8; the velocities are 0 at 0, 3 (a
        // corner that was not blended), 5 (a grasp) and 8.
        let mut p = plan(vec![event(5.0, EventKind::Grasp, "R")]);
        p.trajectory = (0..=8)
            .map(|k| {
                let mut s =
                    TrajectoryPoint::positions_only(f64::from(k), vec![0.5 * f64::from(k), 0.0]);
                let moving = ![0, 3, 5, 8].contains(&k);
                s.velocities = vec![if moving { 0.5 } else { 0.0 }, 0.0];
                s.accelerations = vec![0.0; 2];
                s
            })
            .collect();
        let key = |name: &str, time: Real| KeyPose {
            name: name.into(),
            arm: Arm::Right,
            time,
            world_from_tcp: p.object.start_pose,
            world_from_object: p.object.start_pose,
        };
        // "pre-grasp" is passed moving (sample 2): no cut; "lift" is at a stop (sample 8).
        p.key_poses = vec![key("pre-grasp", 2.0), key("lift", 8.0)];
        let cuts = |p: &Plan| -> Vec<(usize, usize, String)> {
            p.motions()
                .into_iter()
                .map(|m| (m.first, m.last, m.to))
                .collect()
        };
        let s = |x: &str| x.to_owned();
        assert_eq!(
            cuts(&p),
            [
                (0, 3, s("stop")),
                (3, 5, s("grasp (right)")),
                (5, 8, s("lift"))
            ]
        );
        // Without velocities (format 1) every key pose is a stop.
        for point in &mut p.trajectory {
            point.velocities.clear();
            point.accelerations.clear();
        }
        assert_eq!(
            cuts(&p),
            [
                (0, 2, s("pre-grasp")),
                (2, 5, s("grasp (right)")),
                (5, 8, s("lift"))
            ]
        );
    }

    /// A direct right-hand plan of the documented form.
    fn direct() -> Plan {
        let pose = PoseSpec::from_isometry(&Isometry3::identity());
        let mut p = plan(vec![
            event(1.0, EventKind::Grasp, "R"),
            event(2.0, EventKind::Release, "R"),
        ]);
        p.strategy = Strategy::RightRight;
        p.trajectory = (0..4)
            .map(|k| TrajectoryPoint::positions_only(f64::from(k), vec![0.0, 0.0]))
            .collect();
        p.grasps = vec![GraspInfo {
            arm: Arm::Right,
            object_from_tcp: pose,
            width: 0.05,
            score: 1.0,
            rank: 0,
        }];
        p.key_poses = [
            "pre-grasp",
            "grasp",
            "lift",
            "pre-place",
            "place",
            "release",
            "retreat",
        ]
        .iter()
        .enumerate()
        .map(|(k, name)| KeyPose {
            name: (*name).into(),
            arm: Arm::Right,
            time: 0.5 * k as f64,
            world_from_tcp: pose,
            world_from_object: pose,
        })
        .collect();
        p
    }

    /// `direct()` with `fault` applied breaks exactly the rule whose message holds `expected`.
    fn check(fault: impl Fn(&mut Plan), expected: &str) {
        let mut p = direct();
        fault(&mut p);
        let e = p.check_form().expect_err(expected);
        assert!(e.reason().contains(expected), "`{expected}` not in: {e}");
    }

    #[test]
    fn every_rule_of_the_plan_form_is_checked() {
        assert_eq!(direct().check_form(), Ok(()));
        check(|p| p.trajectory.clear(), "trajectory: empty");
        check(
            |p| {
                p.trajectory.remove(0);
            },
            "trajectory[0]: time_from_start 1 s, the trajectory starts at time 0",
        );
        check(
            |p| p.events[0].time = -1.0,
            "events[0]: time -1 s is not a finite time",
        );
        check(
            |p| p.events[1].time = f64::INFINITY,
            "events[1]: time inf s is not a finite time",
        );
        check(
            |p| p.events[1].time = 0.5,
            "events[1]: before the event above it",
        );
        check(
            |p| p.events[0].arm = Arm::Left,
            "events[0]: arm left is not an arm of the strategy right-right",
        );
        check(
            |p| p.events.insert(1, event(1.5, EventKind::Grasp, "R")),
            "events[1]: grasp by \"R\", which already holds the object",
        );
        check(
            |p| p.events.insert(0, event(0.5, EventKind::Release, "R")),
            "events[0]: release by \"R\" without a grasp before it",
        );
        check(
            |p| {
                p.strategy = Strategy::LeftRight;
                p.grasps.insert(0, p.grasps[0].clone());
                p.grasps[0].arm = Arm::Left;
            },
            "events: the first grasp is by the right arm, the strategy left-right picks with the left arm",
        );
        check(
            |p| {
                p.strategy = Strategy::RightLeft;
                p.grasps.push(p.grasps[0].clone());
                p.grasps[1].arm = Arm::Left;
            },
            "events: the last release is by the right arm, the strategy right-left places with the left arm",
        );
        check(
            |p| p.grasps.clear(),
            "grasps: 0 given, the strategy right-right uses 1",
        );
        check(
            |p| p.grasps[0].width = f64::NAN,
            "grasps[0]: a non-finite width or score",
        );
        check(
            |p| {
                p.strategy = Strategy::RightPlaceRight;
                p.grasps.push(p.grasps[0].clone());
            },
            "rests: 0 given",
        );
        check(
            |p| {
                p.rests.push(RestInfo {
                    world_from_object: p.object.start_pose,
                    placement: p.placement.clone(),
                })
            },
            "rests: 1 given",
        );
        check(
            |p| p.placement.contact = "x".repeat(1000),
            "placement.contact: \"xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx…\" is neither",
        );
        check(
            |p| p.placement.stability_margin = f64::INFINITY,
            "placement.stability_margin: not a finite number",
        );
        check(
            |p| p.key_poses[2].name = "jump".into(),
            "key_poses[2]: \"jump\" is not a key pose name",
        );
        check(
            |p| p.key_poses.swap(2, 3),
            "key_poses[3]: before the key pose above it",
        );
        check(
            |p| p.key_poses[0].time = f64::NAN,
            "key_poses[0]: time NaN s",
        );
        check(
            |p| p.key_poses[6].arm = Arm::Left,
            "key_poses[6]: arm left is not an arm",
        );
    }

    #[test]
    fn columns_map_a_robot_order_to_the_plan_order() {
        let p = plan(vec![]);
        assert_eq!(p.columns(&["b", "a"]).unwrap(), [1, 0]);
        assert_eq!(
            p.columns(&["a", "c"]).unwrap_err(),
            "missing [\"c\"], unknown [\"b\"]".into()
        );
    }
}
