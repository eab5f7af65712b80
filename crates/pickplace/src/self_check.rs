//! The planner's output checked by the validator's rules before anyone gets it (issue 33):
//! [`plan`] runs the search ([`crate::planner::plan`]) and then [`crate::validate::validate`]
//! on the plan it found, with the same setup, so that `pickplace plan`, `batch`, the Python
//! package and library callers never receive a plan `pickplace validate` refuses. A refused
//! plan is no plan: the outcome is [`Outcome::NoPlan`] with the validator's first problems
//! as the reason (a planner defect, reported instead of written).
//!
//! The validator is the independent dense re-check of the paper's §IV output (every joint
//! limit, velocity and acceleration, collisions at 1° and 1 cm, grip and rest contacts); the
//! planner does not import it, this module joins the two.

use crate::planner::{Failure, Outcome, PlanOptions};
use crate::{Plan, Result, Setup};
use std::path::Path;
use std::time::Instant;

/// How many of the validator's problems a refusal quotes.
const QUOTED_PROBLEMS: usize = 3;

/// The name a refused plan has in the validator's messages (it was never written).
const UNWRITTEN: &str = "(the plan found)";

/// Plans `setup` with `options` (the paper's Fig. 8 pipeline, [`crate::planner::plan`]) and
/// re-checks the plan with the validator before returning it. With `options.timings`, the
/// check's time is in `stats.timings["validate"]`.
///
/// # Errors
/// As [`crate::planner::plan`]; and [`crate::Error::BadPlan`] or [`crate::Error::Internal`]
/// when the validator cannot check the plan (a defect).
pub fn plan(setup: &Setup, options: &PlanOptions) -> Result<Outcome> {
    match crate::planner::plan(setup, options)? {
        Outcome::Planned(plan) => gate(setup, plan, options.timings),
        none => Ok(none),
    }
}

/// `plan` when the validator finds no problem in it, else [`Outcome::NoPlan`] quoting the
/// problems.
fn gate(setup: &Setup, mut plan: Box<Plan>, timings: bool) -> Result<Outcome> {
    let t = Instant::now();
    let report = crate::validate::validate(setup, &plan, Path::new(UNWRITTEN))?;
    if timings {
        plan.stats
            .timings
            .insert("validate".to_owned(), t.elapsed().as_secs_f64());
    }
    if report.problems.is_empty() {
        return Ok(Outcome::Planned(plan));
    }
    let quoted: Vec<&str> = report
        .problems
        .iter()
        .take(QUOTED_PROBLEMS)
        .map(String::as_str)
        .collect();
    let more = report.problems.len().saturating_sub(QUOTED_PROBLEMS);
    let more = if more > 0 {
        format!("; and {more} more")
    } else {
        String::new()
    };
    let strategy = plan.strategy;
    let mut stats = plan.stats;
    for s in &mut stats.strategies {
        if s.strategy == strategy {
            s.success = false;
        }
    }
    Ok(Outcome::NoPlan(Failure {
        reasons: vec![format!(
            "{strategy}: the plan found fails the validator's checks, so it is not returned (a planner defect; please report it with the scene): {}{more}",
            quoted.join("; ")
        )],
        stats,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn planned(name: &str) -> (&'static Setup, Box<Plan>) {
        let setup = crate::testing::setup(name);
        let options = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        };
        match plan(setup, &options).expect("no defect") {
            Outcome::Planned(p) => (setup, p),
            Outcome::NoPlan(f) => panic!("{name}: {:?}", f.reasons),
        }
    }

    #[test]
    fn a_plan_that_passes_is_returned_unchanged() {
        let (setup, p) = planned("fig9-near.toml");
        let again = gate(setup, p.clone(), false).expect("checks");
        assert_eq!(again, Outcome::Planned(p));
    }

    #[test]
    fn a_plan_the_validator_refuses_is_no_plan_with_its_problems() {
        let (setup, mut p) = planned("fig9-near.toml");
        // A joint jumps between two samples: over its velocity limit, and the positions no
        // longer agree with the velocities.
        let mid = p.trajectory.len() / 2;
        let joint = &p.arms[0].joints[0];
        let j = p
            .joint_names
            .iter()
            .position(|n| n == joint)
            .expect("named");
        p.trajectory[mid].positions[j] += 0.5;
        let Outcome::NoPlan(f) = gate(setup, p, false).expect("checks") else {
            panic!("a jump must be refused")
        };
        assert_eq!(f.reasons.len(), 1);
        assert!(
            f.reasons[0].contains("fails the validator's checks"),
            "{:?}",
            f.reasons
        );
        assert!(f.stats.strategies.iter().all(|s| !s.success));
    }
}
