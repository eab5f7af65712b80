//! The planner's options ([`PlanOptions`]): defaults, the scene's values, and the check of
//! every number before any work.

use crate::error::Result;
use crate::setup::Setup;
use crate::strategy::StrategyChoice;
use pickplace_geometry::math::Real;

/// Options of [`super::plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Seed of every random choice (default: the scene's `planner.seed`, else 1).
    pub seed: u64,
    /// Strategy (default: the scene's, else auto).
    pub strategy: StrategyChoice,
    /// Distance of the pre-grasp and retreat poses from the grasp, along the approach (m)
    /// (default: 0.08).
    pub approach_distance: Real,
    /// Height the object is lifted after the grasp and lowered before the place (m)
    /// (default: 0.10).
    pub lift_height: Real,
    /// Largest step of straight Cartesian motions (m) (default: 0.01).
    pub cartesian_step: Real,
    /// Largest joint change between two steps of a Cartesian motion (rad); more means the IK
    /// jumped to another branch (default: 0.2).
    pub max_joint_step: Real,
    /// Grasps scoring below this fraction of the best are not used (default: 0.2).
    pub min_grasp_quality: Real,
    /// Clearance kept by PRM motions (m) (default: 0.01).
    pub motion_margin: Real,
    /// Picking-hand poses tried for a handover (default: 96); see [`super::handover_candidates`].
    pub handover_poses: usize,
    /// Feasible handover poses compared before the best is kept (default: 3).
    pub handover_feasible: usize,
    /// Distance from the start or placed pose within which the object may touch the surface
    /// it rests on (m) (default: [`crate::rules::CONTACT_ZONE`], 0.005; the validator allows
    /// [`crate::rules::CONTACT_ZONE_SLACK`] more).
    pub contact_zone: Real,
    /// Record stage timings in the plan's stats (default: true).
    pub timings: bool,
    /// Wall-clock budget of the whole plan (s): once spent, no further placement or strategy
    /// is started and the failure says so (default: the scene's `planner.time_budget`, else 10).
    /// No count caps the search of placements and grasps: each strategy searches, best first,
    /// until it finds a plan, runs out of candidates, or has spent its share of what is left
    /// of the budget (what is left divided by the strategies still to try), so that a
    /// strategy that cannot succeed does not starve the next. A budget makes the outcome
    /// depend on the machine's speed only when it runs out.
    pub time_budget: Real,
    /// Trajectory sampling period (s) (default: 0.04).
    pub sample_period: Real,
    /// How far (rad, joint space) a motion through free space may cut a corner of its path
    /// (a roadmap vertex, a shortcut's waypoint) on a circular blend, so that the robot does
    /// not stop there; what the blends change is checked again for collisions, and a blend
    /// that collides is tightened (default: 0.1). Straight tool motions blend at most
    /// 0.005 rad and stay within 1 mm of their line.
    pub blend_tolerance: Real,
    /// Fraction of every joint's velocity limit the trajectory uses, in (0, 1] (MoveIt's
    /// velocity scaling factor; default: the scene's `trajectory.velocity_scaling`, else 1).
    pub velocity_scaling: Real,
    /// Fraction of every joint's acceleration limit the trajectory uses, in (0, 1] (default:
    /// the scene's `trajectory.acceleration_scaling`, else 1).
    pub acceleration_scaling: Real,
    /// Fewest and most intermediate resting poses of a regrasp by placing, searched in that
    /// order, fewest first: the shortest sequence of the regrasp graph (default: 1 and 2).
    pub regrasp_rests: (usize, usize),
}

impl PlanOptions {
    /// Refuses options out of range ([`crate::ranges`]): every number, before any work, so
    /// that a library caller gets the CLI's message rather than an overflow.
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the option (and the scene).
    pub fn check(&self, setup: &Setup) -> Result<()> {
        match self.out_of_range() {
            None => Ok(()),
            Some(e) => Err(crate::Error::Invalid {
                path: setup.scene_path.clone(),
                field: format!("plan option {}", e.option),
                reason: e.reason,
            }),
        }
    }

    /// The first option out of its range, if any.
    fn out_of_range(&self) -> Option<OutOfRange> {
        use crate::ranges::{
            PLANNER_ANGLE, PLANNER_DISTANCE, Range, SAMPLE_PERIOD, SCALING, TIME_BUDGET,
        };
        let fraction = Range::closed(0.0, 1.0, "");
        let counts = Range::closed(1.0, 100_000.0, "");
        let checks: [(&'static str, Real, Range); 13] = [
            ("time_budget", self.time_budget, TIME_BUDGET),
            ("velocity_scaling", self.velocity_scaling, SCALING),
            ("acceleration_scaling", self.acceleration_scaling, SCALING),
            ("sample_period", self.sample_period, SAMPLE_PERIOD),
            ("blend_tolerance", self.blend_tolerance, PLANNER_ANGLE),
            ("max_joint_step", self.max_joint_step, PLANNER_ANGLE),
            (
                "approach_distance",
                self.approach_distance,
                PLANNER_DISTANCE,
            ),
            ("lift_height", self.lift_height, PLANNER_DISTANCE),
            ("motion_margin", self.motion_margin, PLANNER_DISTANCE),
            ("contact_zone", self.contact_zone, PLANNER_DISTANCE),
            ("min_grasp_quality", self.min_grasp_quality, fraction),
            ("handover_poses", self.handover_poses as Real, counts),
            ("handover_feasible", self.handover_feasible as Real, counts),
        ];
        let bad = |option: &'static str, reason: String| Some(OutOfRange { option, reason });
        for (option, value, range) in checks {
            if let Err(e) = range.check(value) {
                return bad(option, e.to_string());
            }
        }
        if !(self.cartesian_step > 0.0 && PLANNER_DISTANCE.contains(self.cartesian_step)) {
            return bad("cartesian_step", "must be in (0, 10] m".to_owned());
        }
        if self.regrasp_rests.0 > self.regrasp_rests.1 || self.regrasp_rests.1 > 8 {
            return bad(
                "regrasp_rests",
                "must be (fewest, most) with fewest <= most <= 8".to_owned(),
            );
        }
        None
    }

    /// The scene's options ([`PlanOptions::for_setup`]) with a caller's `overrides` over
    /// them: the one place where the command line's flags, a batch's options and Python's
    /// keywords meet the scene's values.
    pub fn with_overrides(setup: &Setup, overrides: &PlanOverrides) -> Self {
        let mut options = Self::for_setup(setup);
        options.apply(overrides);
        options
    }

    fn apply(&mut self, o: &PlanOverrides) {
        if let Some(seed) = o.seed {
            self.seed = seed;
        }
        if let Some(strategy) = o.strategy {
            self.strategy = strategy;
        }
        if let Some(budget) = o.time_budget {
            self.time_budget = budget;
        }
        if let Some(f) = o.velocity_scaling {
            self.velocity_scaling = f;
        }
        if let Some(f) = o.acceleration_scaling {
            self.acceleration_scaling = f;
        }
        if let Some(p) = o.sample_period {
            self.sample_period = p;
        }
        if let Some(t) = o.timings {
            self.timings = t;
        }
    }

    /// The defaults with the scene's seed, strategy and time budget.
    pub fn for_setup(setup: &Setup) -> Self {
        Self {
            seed: setup.scene.planner.seed,
            strategy: setup.scene.planner.strategy,
            time_budget: setup.scene.planner.time_budget,
            velocity_scaling: setup.scaling.0,
            acceleration_scaling: setup.scaling.1,
            ..Self::default()
        }
    }
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            strategy: StrategyChoice::Auto,
            approach_distance: 0.08,
            lift_height: 0.10,
            cartesian_step: 0.01,
            max_joint_step: 0.2,
            min_grasp_quality: 0.2,
            motion_margin: 0.01,
            handover_poses: 96,
            handover_feasible: 3,
            contact_zone: crate::rules::CONTACT_ZONE,
            timings: true,
            time_budget: 10.0,
            sample_period: 0.04,
            blend_tolerance: 0.1,
            velocity_scaling: 1.0,
            acceleration_scaling: 1.0,
            regrasp_rests: (1, 2),
        }
    }
}

/// What a caller sets over a scene's own planner values: the command line's flags
/// (`pickplace plan`, `pickplace batch`), a batch's options and Python's keywords. Each `None`
/// leaves the scene's value (or the default); [`PlanOptions::with_overrides`] merges them.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlanOverrides {
    /// Seed of every random choice ([`PlanOptions::seed`]).
    pub seed: Option<u64>,
    /// Strategy ([`PlanOptions::strategy`]).
    pub strategy: Option<StrategyChoice>,
    /// Wall-clock budget (s) ([`PlanOptions::time_budget`]).
    pub time_budget: Option<Real>,
    /// Velocity scaling factor ([`PlanOptions::velocity_scaling`]).
    pub velocity_scaling: Option<Real>,
    /// Acceleration scaling factor ([`PlanOptions::acceleration_scaling`]).
    pub acceleration_scaling: Option<Real>,
    /// Trajectory sampling period (s) ([`PlanOptions::sample_period`]).
    pub sample_period: Option<Real>,
    /// Record stage timings ([`PlanOptions::timings`]).
    pub timings: Option<bool>,
}

impl PlanOverrides {
    /// Refuses values out of range before any scene is read, with the ranges
    /// [`PlanOptions::check`] applies.
    ///
    /// # Errors
    /// [`OutOfRange`] naming the first option out of its range.
    pub fn check(&self) -> std::result::Result<(), OutOfRange> {
        let mut options = PlanOptions::default();
        options.apply(self);
        options.out_of_range().map_or(Ok(()), Err)
    }
}

/// An option out of its range ([`PlanOverrides::check`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{option}: {reason}")]
pub struct OutOfRange {
    /// The option's name (its field).
    pub option: &'static str,
    /// What is wrong.
    pub reason: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overrides_replace_only_what_they_set_and_are_checked_with_the_planner_ranges() {
        let overrides = PlanOverrides {
            seed: Some(7),
            sample_period: Some(0.02),
            ..PlanOverrides::default()
        };
        let mut options = PlanOptions::default();
        options.apply(&overrides);
        assert_eq!(
            options,
            PlanOptions {
                seed: 7,
                sample_period: 0.02,
                ..PlanOptions::default()
            }
        );
        assert_eq!(overrides.check(), Ok(()));
        let e = PlanOverrides {
            velocity_scaling: Some(1.5),
            ..PlanOverrides::default()
        }
        .check()
        .expect_err("out of range");
        assert_eq!(e.option, "velocity_scaling");
    }
}
