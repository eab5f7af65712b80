//! Resume: the plan file an earlier run left is kept when it reads as a plan, was made with
//! this batch's options and passes the validator.

use super::error_message;
use crate::plan::Plan;
use crate::planner::PlanOptions;
use crate::setup::Setup;
use std::path::Path;

/// What a resumed run found at a scene's plan path.
pub(super) enum Kept {
    /// Nothing.
    Absent,
    /// A plan to keep.
    Valid(Box<Plan>),
    /// A file not to keep, and why.
    Invalid(String),
}

/// Reads and checks the plan file a previous run left at `plan_path`.
pub(super) fn kept_plan(setup: &Setup, plan_options: &PlanOptions, plan_path: &Path) -> Kept {
    if std::fs::symlink_metadata(plan_path).is_err() {
        return Kept::Absent;
    }
    let shown = plan_path.display();
    let plan = match Plan::load(plan_path) {
        Ok(plan) => plan,
        Err(e) => return Kept::Invalid(e.to_string()),
    };
    if let Some(reason) = other_options(&plan, plan_options) {
        return Kept::Invalid(format!("{shown}: {reason}"));
    }
    match crate::validate::validate(setup, &plan, plan_path) {
        Ok(report) if report.problems.is_empty() => Kept::Valid(Box::new(plan)),
        Ok(report) => Kept::Invalid(format!(
            "{shown}: fails validation ({} problem(s)), first: {}",
            report.problems.len(),
            report.problems.first().map_or("", String::as_str)
        )),
        Err(e) => Kept::Invalid(error_message(&e)),
    }
}

/// Why a plan was made with other options than this batch's, as far as the plan records
/// them: the seed, the strategy when one is forced (by the batch or the scene), the scaling
/// factors.
fn other_options(plan: &Plan, plan_options: &PlanOptions) -> Option<String> {
    if plan.seed != plan_options.seed {
        return Some(format!(
            "planned with seed {}, this batch uses {}",
            plan.seed, plan_options.seed
        ));
    }
    if let Some(forced) = plan_options.strategy.strategy()
        && forced != plan.strategy
    {
        return Some(format!(
            "planned with strategy {}, this batch asks for {forced}",
            plan.strategy
        ));
    }
    if let Some(limits) = &plan.limits
        && (limits.velocity_scaling != plan_options.velocity_scaling
            || limits.acceleration_scaling != plan_options.acceleration_scaling)
    {
        return Some(format!(
            "planned with scaling factors {} (velocity) and {} (acceleration), this batch uses {} and {}",
            limits.velocity_scaling,
            limits.acceleration_scaling,
            plan_options.velocity_scaling,
            plan_options.acceleration_scaling
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::batch::tests::direct_plan;
    use crate::scene::StrategyChoice;

    #[test]
    fn a_plan_made_with_other_options_is_not_kept() {
        let plan = Plan::from_json(&direct_plan("fig9-near.toml")).expect("plan");
        let setup = crate::testing::setup("fig9-near.toml");
        let same = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        };
        assert_eq!(other_options(&plan, &same), None);
        let forced = PlanOptions {
            strategy: StrategyChoice::Only(crate::Strategy::LeftLeft),
            ..same.clone()
        };
        assert_eq!(
            other_options(&plan, &forced).as_deref(),
            Some("planned with strategy right-right, this batch asks for left-left")
        );
        let slower = PlanOptions {
            velocity_scaling: 0.5,
            ..same.clone()
        };
        let why = other_options(&plan, &slower).expect("another factor");
        assert!(why.contains("scaling factors 1 (velocity)"), "{why}");
    }
}
