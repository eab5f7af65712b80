//! Why a candidate was rejected, typed (paper Fig. 8: every test of the pipeline can fail, and
//! a failed plan must say which test failed how often).
//!
//! A [`Rejection`] is a property of the scene (no IK, a collision between two named bodies, a
//! gripper in the table, no path): the candidate is dropped, counted under its [`Stage`] and
//! the search goes on. An [`Error`] is a defect (a lower layer refused input the façade had
//! checked, the collision library failed): the search stops and the caller sees the cause.
//! [`Fail`] carries either out of a stage, so `?` keeps them apart.
//!
//! The words each value prints are the ones the plan's `stats` and the CLI show; they are
//! listed in `docs/plan-format.md`.

use crate::error::Error;
use crate::plan::{StageCount, StrategyReport};
use std::fmt;

/// A stage of the pipeline whose candidates are counted in [`StrategyReport::stages`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Stage {
    /// A placement candidate (Algorithm 2), tried with every grasp.
    Placement,
    /// A grasp of the picking arm at the object's start: key poses, approach and lift.
    Pick,
    /// A grasp of the placing arm at a placement: key poses, lowering, release and retreat.
    Place,
    /// A handover pose with a pick grasp (§III-B.3, RIGHT-LEFT and LEFT-RIGHT).
    Handover,
    /// A second grasp at a handover pose.
    Regrasp,
    /// The PRM motions joining the key poses of a candidate (§III-C).
    Motion,
    /// Putting the object down at an intermediate resting pose (regrasp by placing).
    Rest,
}

impl Stage {
    /// Every stage, in pipeline order.
    pub const ALL: [Stage; 7] = [
        Stage::Placement,
        Stage::Pick,
        Stage::Rest,
        Stage::Place,
        Stage::Handover,
        Stage::Regrasp,
        Stage::Motion,
    ];

    /// The name used as the key of [`StrategyReport::stages`].
    pub fn name(self) -> &'static str {
        match self {
            Stage::Placement => "placement",
            Stage::Pick => "pick",
            Stage::Place => "place",
            Stage::Handover => "handover",
            Stage::Regrasp => "regrasp",
            Stage::Motion => "motion",
            Stage::Rest => "rest",
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The step of a candidate at which a [`Rejection`] happened; printed before it
/// (`approach: no IK along the straight line`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Step {
    /// The grasp pose of the picking hand (fingers open).
    Grasp,
    /// The straight approach from the pre-grasp pose.
    Approach,
    /// The straight lift after the grasp.
    Lift,
    /// The grasp pose with the fingers closed on the object.
    GraspClosed,
    /// The place pose.
    Place,
    /// The straight lowering to the place pose.
    Lower,
    /// Opening the hand at the place pose.
    Release,
    /// The straight retreat after the release.
    Retreat,
    /// The picking arm at a handover pose.
    PickingArm,
    /// The placing arm's grasp at a handover pose.
    Regrasp,
    /// The placing arm's straight approach to that grasp.
    RegraspApproach,
    /// Opening the picking hand once the placing hand holds.
    FirstHandRelease,
    /// The picking hand's straight retreat after a handover.
    FirstHandRetreat,
    /// The motion from the start to the pre-grasp pose.
    ToPreGrasp,
    /// The motion to the pre-place pose.
    ToPrePlace,
    /// The motion carrying the object to the handover pose.
    ToHandover,
    /// The placing arm's motion to its pre-regrasp pose.
    ToPreRegrasp,
    /// The picking arm's motion back to its start after a handover.
    FirstArmHome,
    /// The motion back to the start after the retreat.
    Home,
    /// The motion carrying the object to an intermediate resting pose.
    ToRest,
}

impl Step {
    /// The words printed before the rejection.
    pub fn name(self) -> &'static str {
        match self {
            Step::Grasp => "grasp",
            Step::Approach => "approach",
            Step::Lift => "lift",
            Step::GraspClosed => "grasp (closed)",
            Step::Place => "place",
            Step::Lower => "lower",
            Step::Release => "release",
            Step::Retreat => "retreat",
            Step::PickingArm => "picking arm",
            Step::Regrasp => "regrasp",
            Step::RegraspApproach => "regrasp approach",
            Step::FirstHandRelease => "release of the first hand",
            Step::FirstHandRetreat => "first hand retreat",
            Step::ToPreGrasp => "to pre-grasp",
            Step::ToPrePlace => "to pre-place",
            Step::ToHandover => "to handover",
            Step::ToPreRegrasp => "to pre-regrasp",
            Step::FirstArmHome => "first arm back to start",
            Step::Home => "back to start",
            Step::ToRest => "to pre-rest",
        }
    }
}

/// Two bodies in contact: robot links, environment parts, the object lying free (`object`)
/// or the held object (`held object`).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Collision {
    /// The first body's name.
    pub a: String,
    /// The second body's name.
    pub b: String,
}

impl fmt::Display for Collision {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "collision {} / {}", self.a, self.b)
    }
}

/// An end of a motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum End {
    /// Where the motion starts.
    Start,
    /// Where it ends.
    Goal,
}

/// Which arm of a handover.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Role {
    /// The arm that picked the object and hands it over.
    Picking,
    /// The arm that takes it and places it.
    Placing,
}

/// Why a candidate was dropped: a fact about the scene, never a defect (see [`Error`]).
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum Rejection {
    /// The tool pose is farther from the shoulder than the arm's sampled reach.
    OutOfReach,
    /// At a handover, one arm's tool pose is out of its reach.
    ArmOutOfReach(Role),
    /// The open gripper (palm and fingers) intersects this environment part at the tool pose.
    GripperHits(String),
    /// No inverse-kinematics solution (§III-C: "we check the IK of the key postures").
    NoIk,
    /// Every IK solution tried collides; the last collision found.
    Collision(Collision),
    /// A collision between the checked states of a motion, found by the dense check at the
    /// validator's resolution.
    DenseCollision(Collision),
    /// A straight Cartesian motion has a step without an IK solution.
    NoIkOnLine,
    /// A straight Cartesian motion jumps between IK branches.
    BranchJump,
    /// An end of a PRM motion collides.
    EndInCollision(End, Collision),
    /// Neither the roadmap nor RRT-Connect joined the two ends (§III-C).
    NoPath {
        /// The roadmap query's failure.
        roadmap: String,
        /// RRT-Connect's failure.
        rrt: String,
    },
    /// The placing hand would overlap the picking hand on the object.
    HandsOverlap,
    /// At the handover the two hands' links come closer than the stated clearance
    /// (`pickplace::rules::HAND_CLEARANCE`).
    HandsTooClose,
    /// No second grasp regrasps at this handover pose.
    NoRegrasp,
    /// No second grasp clears the first hand and places the object.
    NoSecondGrasp,
    /// No handover pose led to a plan for this placement.
    NoHandover,
    /// No grasp both picks the object and places it here.
    NoGraspReaches,
    /// No grasp fits the placing hand here at all (the cheap tests: reach, gripper against
    /// the environment); the most frequent reason.
    NoGraspFits(String),
    /// Grasps pick and place, but no motion joins their key poses.
    NoMotionForAnyGrasp,
    /// The plan's wall-clock budget was spent before this candidate.
    TimeBudgetSpent,
    /// No intermediate resting pose for a regrasp by placing near the object's start.
    NoRest,
    /// No sequence pick → put down → pick again → place reached this placement.
    NoRegraspSequence,
    /// A rejection at a named step of the candidate.
    At(Step, Box<Rejection>),
}

impl Rejection {
    /// This rejection at `step`.
    pub fn at(self, step: Step) -> Self {
        Rejection::At(step, Box::new(self))
    }

    /// The rejection without its steps.
    pub fn cause(&self) -> &Rejection {
        match self {
            Rejection::At(_, inner) => inner.cause(),
            other => other,
        }
    }
}

impl fmt::Display for Rejection {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rejection::OutOfReach => f.write_str("out of reach"),
            Rejection::ArmOutOfReach(Role::Picking) => f.write_str("picking arm out of reach"),
            Rejection::ArmOutOfReach(Role::Placing) => f.write_str("placing arm out of reach"),
            Rejection::GripperHits(part) => write!(f, "gripper hits {part}"),
            Rejection::NoIk => f.write_str("no IK"),
            Rejection::Collision(c) => c.fmt(f),
            Rejection::NoIkOnLine => f.write_str("no IK along the straight line"),
            Rejection::BranchJump => f.write_str("IK branch jump along the straight line"),
            Rejection::EndInCollision(End::Start, c) => write!(f, "start in {c}"),
            Rejection::EndInCollision(End::Goal, c) => write!(f, "goal in {c}"),
            Rejection::NoPath { roadmap, rrt } => {
                write!(f, "no path: {roadmap}; RRT-Connect: {rrt}")
            }
            Rejection::HandsOverlap => f.write_str("the second hand would collide with the first"),
            Rejection::NoRegrasp => f.write_str("no regrasp"),
            Rejection::NoSecondGrasp => {
                f.write_str("no second grasp clears the first hand and places")
            }
            Rejection::NoHandover => f.write_str("no handover"),
            Rejection::NoGraspReaches => f.write_str("no grasp reaches it"),
            Rejection::NoMotionForAnyGrasp => f.write_str("no motion for any grasp"),
            Rejection::TimeBudgetSpent => f.write_str("time budget spent"),
            Rejection::DenseCollision(c) => write!(f, "{c} between checked states"),
            Rejection::NoGraspFits(why) => write!(f, "no grasp fits the hand here ({why})"),
            Rejection::HandsTooClose => write!(
                f,
                "hands closer than {:.0} mm",
                crate::rules::HAND_CLEARANCE * 1e3
            ),
            Rejection::NoRest => f.write_str("no intermediate resting pose near the start"),
            Rejection::NoRegraspSequence => {
                f.write_str("no put-down and pick-up sequence reaches it")
            }
            Rejection::At(step, inner) => write!(f, "{}: {inner}", step.name()),
        }
    }
}

/// Why a stage of one candidate did not produce its result: rejected (the search goes on) or
/// a defect (the search stops).
#[derive(Debug)]
pub enum Fail {
    /// The candidate is infeasible for this reason.
    Rejected(Rejection),
    /// A lower layer failed: a bug or a broken input, reported with its cause.
    Error(Error),
}

impl Fail {
    /// The same failure at `step` (errors are left as they are).
    pub fn at(self, step: Step) -> Self {
        match self {
            Fail::Rejected(r) => Fail::Rejected(r.at(step)),
            e @ Fail::Error(_) => e,
        }
    }
}

impl From<Rejection> for Fail {
    fn from(r: Rejection) -> Self {
        Fail::Rejected(r)
    }
}

impl From<Error> for Fail {
    fn from(e: Error) -> Self {
        Fail::Error(e)
    }
}

/// Result of one stage of one candidate.
pub type Attempt<T> = std::result::Result<T, Fail>;

/// The candidate counts of `stage` in `report`.
pub(crate) fn count(report: &mut StrategyReport, stage: Stage) -> &mut StageCount {
    report.stages.entry(stage.name().to_owned()).or_default()
}

/// Splits a stage's outcome: `Ok(Ok(value))`, `Ok(Err(rejection))` to count, or the error.
pub(crate) fn split<T>(attempt: Attempt<T>) -> crate::Result<std::result::Result<T, Rejection>> {
    match attempt {
        Ok(v) => Ok(Ok(v)),
        Err(Fail::Rejected(r)) => Ok(Err(r)),
        Err(Fail::Error(e)) => Err(e),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::strategy::Strategy;
    use std::collections::BTreeMap;

    #[test]
    fn rejections_print_the_words_of_the_stats() {
        let c = Collision {
            a: "WAIST".into(),
            b: "LARM_JOINT2_Link".into(),
        };
        assert_eq!(
            Rejection::Collision(c.clone())
                .at(Step::Approach)
                .to_string(),
            "approach: collision WAIST / LARM_JOINT2_Link"
        );
        assert_eq!(
            Rejection::NoIkOnLine.at(Step::Lift).to_string(),
            "lift: no IK along the straight line"
        );
        assert_eq!(
            Rejection::EndInCollision(End::Goal, c)
                .at(Step::ToPrePlace)
                .to_string(),
            "to pre-place: goal in collision WAIST / LARM_JOINT2_Link"
        );
        assert_eq!(
            Rejection::GripperHits("pallet".into()).to_string(),
            "gripper hits pallet"
        );
        assert_eq!(Rejection::NoIk.at(Step::Grasp).to_string(), "grasp: no IK");
        assert_eq!(
            Rejection::ArmOutOfReach(Role::Placing).to_string(),
            "placing arm out of reach"
        );
        assert_eq!(
            Rejection::NoPath {
                roadmap: "a".into(),
                rrt: "b".into()
            }
            .to_string(),
            "no path: a; RRT-Connect: b"
        );
    }

    #[test]
    fn steps_nest_and_the_cause_is_the_innermost() {
        let r = Rejection::NoIk.at(Step::Regrasp).at(Step::PickingArm);
        assert_eq!(r.to_string(), "picking arm: regrasp: no IK");
        assert_eq!(r.cause(), &Rejection::NoIk);
        // An error stays an error at any step.
        let e = Fail::Error(Error::Internal {
            stage: "attach",
            reason: "no link".into(),
        });
        assert!(matches!(e.at(Step::Lift), Fail::Error(_)));
    }

    #[test]
    fn stages_are_counted_under_their_names() {
        let mut report = StrategyReport {
            strategy: Strategy::RightRight,
            success: false,
            stages: BTreeMap::new(),
        };
        count(&mut report, Stage::Pick).reject(Rejection::OutOfReach.to_string());
        count(&mut report, Stage::Pick).accept();
        let names: Vec<_> = report.stages.keys().cloned().collect();
        assert_eq!(names, ["pick"]);
        assert_eq!(report.stages["pick"].tried, 2);
        assert_eq!(report.stages["pick"].rejected["out of reach"], 1);
        let all: Vec<_> = Stage::ALL.iter().map(|s| s.to_string()).collect();
        assert_eq!(
            all,
            [
                "placement",
                "pick",
                "rest",
                "place",
                "handover",
                "regrasp",
                "motion"
            ]
        );
    }

    #[test]
    fn split_separates_rejections_from_errors() {
        assert!(matches!(
            split::<()>(Err(Rejection::NoIk.into())),
            Ok(Err(Rejection::NoIk))
        ));
        assert!(matches!(split(Ok::<_, Fail>(3)), Ok(Ok(3))));
        let e = Error::Internal {
            stage: "x",
            reason: "y".into(),
        };
        assert!(split::<()>(Err(e.into())).is_err());
    }
}
