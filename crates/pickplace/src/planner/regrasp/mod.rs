//! Regrasp by placing: when no direct strategy and no handover works, or the robot has one
//! arm, the object is put down in an intermediate stable pose and picked up again with another
//! grasp. This is the successor of the paper's planner (Wan and Harada, "Developing and
//! Comparing Single-arm and Dual-arm Regrasp", and Harada's regrasp graph): a graph whose
//! nodes are (resting pose, arm, grasp) triples and whose edges are transfers (one hand
//! carries the object from one resting pose to another with one grasp) and regrasps (at an
//! intermediate resting pose, the hand lets go and a hand takes another grasp). The plan is
//! the shortest sequence of transfers from the start to a placement at the target.
//!
//! Sequences with no intermediate pose are the direct strategies (RIGHT-RIGHT, LEFT-LEFT,
//! [`super::search`]); this module searches the next shortest, with one intermediate pose:
//! start →(arm A, grasp g₁)→ rest k →(arm B, grasp g₂)→ placement, and when none works, those
//! with two: start →(A, g₁)→ rest k₁ →(B, g₂)→ rest k₂ →(B, g₃)→ placement
//! ([`super::PlanOptions::regrasp_rests`]). The graph is evaluated
//! lazily, cheapest test first, as the paper's planner does for its key poses: edges are first
//! kept by the cheap tests of [`Ctx::grasp_fits`](super::Ctx::grasp_fits) (reach, gripper
//! against the environment), then checked by IK and collision (pick, put down, pick again,
//! place), and last joined by motions. Every expensive result is computed once.
//!
//! | concern | module |
//! |---|---|
//! | the intermediate resting poses and the bodies the object touches there | `rests` |
//! | the cheap graph and the sequences through one rest (the strategy's entry) | `one_rest` |
//! | the sequences through two rests | `two_rests` |
//! | the key poses at the rests, each computed once (A's put-downs, B's pick-ups) | `keyposes` |

mod keyposes;
mod one_rest;
mod rests;
#[cfg(test)]
mod tests;
mod two_rests;

pub(super) use one_rest::RegraspLegs;
pub use rests::REST_RADIUS;
pub(super) use two_rests::TwoRestLegs;

use super::reason::{Rejection, Stage, count};
use crate::plan::StrategyReport;
use pickplace_placement::Placement;
use std::sync::OnceLock;

/// What the regrasp searches find once per run.
#[derive(Default)]
pub(super) struct Memo {
    /// The intermediate resting poses ([`super::Ctx::rests`]).
    pub rests: OnceLock<Vec<Placement>>,
    /// The environment bodies the object touches at each rest, found once.
    pub rest_supports: OnceLock<Vec<OnceLock<Vec<String>>>>,
}

/// Salt of the random choices at intermediate resting poses (distinct from the placements').
const REST_SALT: u64 = 1 << 62;

/// Counts a key-pose result under `stage`.
fn tally<T>(report: &mut StrategyReport, stage: Stage, r: &std::result::Result<T, Rejection>) {
    match r {
        Ok(_) => count(report, stage).accept(),
        Err(r) => count(report, stage).reject(r.to_string()),
    }
}
