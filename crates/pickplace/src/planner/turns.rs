//! Taking turns between the strategies (paper Fig. 8): each gets its share of what is left
//! of the time budget, and one cut short comes back for the time the others left unused.

use super::assemble::Found;
use super::{Ctx, Rejection};
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::strategy::Strategy;
use pickplace_geometry::math::Real;

/// What taking turns needs of the planner: the time shares and one strategy's search (a trait
/// so that a test drives [`take_turns`] on a clock of its own).
pub(super) trait TakeTurns {
    /// A strategy's plan.
    type Found;
    /// Gives the next strategy its share of what is left (see [`super::state::Budget::share_time`]).
    fn share_time(&mut self, remaining: usize);
    /// Whether the budget or the current share is spent.
    fn out_of_time(&self) -> bool;
    /// Searches one strategy (`probe`: the nearer hand's quick first look).
    fn run(
        &mut self,
        strategy: Strategy,
        probe: bool,
    ) -> Result<std::result::Result<Self::Found, StrategyReport>>;
}

/// How taking turns ended.
pub(super) enum Turns<F> {
    /// A strategy found a plan.
    Found(F),
    /// None did: each strategy searched with its report, in the order tried.
    Failed(Vec<(Strategy, StrategyReport)>),
}

/// The strategies in turn (paper Fig. 8), the probe first. Each strategy gets its share of
/// what is left of the budget; one whose share ran out before its search did comes back for a
/// second turn, when the others have handed on the time they left unused (they ended early:
/// nothing more to try). A strategy never reached is named in `reasons`.
pub(super) fn take_turns<T: TakeTurns>(
    t: &mut T,
    probe: Option<Strategy>,
    order: Vec<Strategy>,
    time_budget: Real,
    reasons: &mut Vec<String>,
) -> Result<Turns<T::Found>> {
    let n_strategies = order.len();
    let attempts = probe
        .map(|s| (s, true))
        .into_iter()
        .chain(order.into_iter().map(|s| (s, false)));
    let mut turn = 0;
    let mut failed: Vec<(Strategy, StrategyReport)> = Vec::new();
    let mut cut: Vec<usize> = Vec::new();
    for (strategy, is_probe) in attempts {
        if !is_probe {
            t.share_time(n_strategies - turn);
            turn += 1;
            if t.out_of_time() {
                reasons.push(format!(
                    "{strategy}: not tried, the time budget of {} s is spent",
                    pickplace_geometry::io::fmt_real(time_budget)
                ));
                continue;
            }
        }
        let report = match t.run(strategy, is_probe)? {
            Ok(found) => return Ok(Turns::Found(found)),
            Err(report) => report,
        };
        if !is_probe {
            if was_cut_short(&report) {
                cut.push(failed.len());
            }
            failed.push((strategy, report));
        }
    }
    let n_cut = cut.len();
    for (k, &i) in cut.iter().enumerate() {
        t.share_time(n_cut - k);
        if t.out_of_time() {
            break;
        }
        let strategy = failed[i].0;
        match t.run(strategy, false)? {
            Ok(found) => return Ok(Turns::Found(found)),
            Err(report) => failed[i].1 = report,
        }
    }
    Ok(Turns::Failed(failed))
}

impl<'a> TakeTurns for Ctx<'a> {
    type Found = (Strategy, Found, StrategyReport);

    fn share_time(&mut self, remaining: usize) {
        self.budget.share_time(remaining);
    }

    fn out_of_time(&self) -> bool {
        self.budget.out_of_time()
    }

    fn run(
        &mut self,
        strategy: Strategy,
        probe: bool,
    ) -> Result<std::result::Result<Self::Found, StrategyReport>> {
        self.run_strategy(strategy, probe)
    }
}

/// Whether a strategy's search stopped because its share of the time budget ran out.
fn was_cut_short(report: &StrategyReport) -> bool {
    let spent = Rejection::TimeBudgetSpent.to_string();
    report
        .stages
        .values()
        .any(|count| count.rejected.get(&spent).is_some_and(|&n| n > 0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::reason::{self, Stage};
    use std::collections::BTreeMap;

    /// A planner on a clock of its own: each strategy needs so many seconds to find its plan
    /// (`None`: it finds none and stops after 0.1 s).
    struct FakeTurns {
        budget: Real,
        now: Real,
        deadline: Real,
        needs: Vec<(Strategy, Option<Real>)>,
        runs: Vec<Strategy>,
    }

    impl TakeTurns for FakeTurns {
        type Found = Strategy;

        fn share_time(&mut self, remaining: usize) {
            self.deadline = self.now + (self.budget - self.now).max(0.0) / remaining.max(1) as Real;
        }

        fn out_of_time(&self) -> bool {
            self.now >= self.budget || self.now >= self.deadline
        }

        fn run(
            &mut self,
            strategy: Strategy,
            _probe: bool,
        ) -> Result<std::result::Result<Strategy, StrategyReport>> {
            self.runs.push(strategy);
            let mut report = StrategyReport {
                strategy,
                success: false,
                stages: BTreeMap::new(),
            };
            let need = self
                .needs
                .iter()
                .find(|n| n.0 == strategy)
                .and_then(|n| n.1);
            match need {
                Some(need) if self.now + need <= self.deadline => {
                    self.now += need;
                    return Ok(Ok(strategy));
                }
                Some(_) => {
                    self.now = self.deadline;
                    reason::count(&mut report, Stage::Pick)
                        .reject(Rejection::TimeBudgetSpent.to_string());
                }
                None => {
                    self.now += 0.1;
                    reason::count(&mut report, Stage::Pick).reject("no IK");
                }
            }
            Ok(Err(report))
        }
    }

    #[test]
    fn time_a_strategy_leaves_unused_goes_to_the_one_cut_short() {
        // LEFT-RIGHT needs 6 s of a 10 s budget; its first share is 10/4 = 2.5 s. The three
        // others end at once: it gets a second turn with the 7.2 s they left, and plans.
        let order = vec![
            Strategy::LeftRight,
            Strategy::LeftLeft,
            Strategy::RightRight,
            Strategy::RightLeft,
        ];
        let mut fake = FakeTurns {
            budget: 10.0,
            now: 0.0,
            deadline: 0.0,
            needs: vec![(Strategy::LeftRight, Some(6.0))],
            runs: Vec::new(),
        };
        let mut reasons = Vec::new();
        let outcome = take_turns(&mut fake, None, order.clone(), 10.0, &mut reasons).expect("ok");
        assert!(matches!(outcome, Turns::Found(Strategy::LeftRight)));
        assert_eq!(fake.runs.len(), 5, "{:?}", fake.runs);
        assert!((fake.now - 8.8).abs() < 1e-9, "{}", fake.now);
        // Needing more than the whole budget: two turns, then the reasons of all four.
        let mut fake = FakeTurns {
            budget: 10.0,
            now: 0.0,
            deadline: 0.0,
            needs: vec![(Strategy::LeftRight, Some(11.0))],
            runs: Vec::new(),
        };
        let Turns::Failed(failed) =
            take_turns(&mut fake, None, order, 10.0, &mut reasons).expect("ok")
        else {
            panic!("11 s do not fit in 10")
        };
        assert_eq!(failed.len(), 4);
        assert!(was_cut_short(&failed[0].1));
        assert_eq!(fake.runs.len(), 5);
        assert!(reasons.is_empty(), "{reasons:?}");
    }
}
