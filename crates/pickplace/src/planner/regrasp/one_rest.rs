//! The regrasp strategy's entry: the cheap graph of rests and grasps, then the sequences
//! through one intermediate rest, ending with the two-rest search when none works.

use super::tally;
use super::two_rests::TwoRests;
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::planner::Ctx;
use crate::planner::assemble::Found;
use crate::planner::fits::{FITTING_ENOUGH, PARALLEL_CHUNK};
use crate::planner::keypose::{Pick, Place};
use crate::planner::reason::{Rejection, Stage, count, split};
use crate::strategy::{Arm, Strategy};
use rayon::prelude::*;
use std::collections::BTreeMap;

impl Ctx<'_> {
    /// Regrasp by placing with `strategy` (`right-place-right`, `right-place-left`, …): arm A
    /// picks the object with grasp g₁, puts it down at an intermediate rest k, arm B picks it
    /// up with grasp g₂ (another grasp when A = B) and places it at the target. Placements in
    /// arm B's order ([`Ctx::placement_order`]); rests by how many grasps fit both hands
    /// there; grasps best first. The search stops at the first candidate whose motions join,
    /// or when the strategy's share of the time budget is spent.
    pub(in crate::planner) fn regrasp_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.run.setup.start.clone();
        let pickable = self.fitting_at_start(a, report);
        if pickable.is_empty() {
            return Ok(None);
        }
        let all: Vec<usize> = (0..self.run.grasps.len()).collect();
        let finals = self.placement_order(b, &all, false, report);
        if finals.is_empty() {
            return Ok(None);
        }
        let t = std::time::Instant::now();
        let n_rests = self.rests().len();
        if self.run.options.timings && !self.budget.timings.contains_key("rests") {
            self.budget
                .timings
                .insert("rests".to_owned(), t.elapsed().as_secs_f64());
        }
        if n_rests == 0 {
            count(report, Stage::Rest).reject(Rejection::NoRest.to_string());
            return Ok(None);
        }
        // The cheap graph: per rest, the grasps A can put it down with (closed gripper) and
        // those B can pick it up with (open gripper).
        let mut rest_edges: Vec<(usize, usize, Vec<usize>, Vec<usize>)> = Vec::new();
        for k in 0..n_rests {
            let pose = self.rests()[k].world_from_object;
            let mut down: Vec<usize> = pickable
                .iter()
                .copied()
                .filter(|&g| self.grasp_fits(a, g, &pose, false).is_ok())
                .collect();
            let up: Vec<usize> = all
                .iter()
                .copied()
                .filter(|&g| self.grasp_fits(b, g, &pose, true).is_ok())
                .collect();
            if down.is_empty() || up.is_empty() {
                count(report, Stage::Rest).reject(Rejection::NoGraspReaches.to_string());
                continue;
            }
            // The put-downs the reachability maps expect IK for first (`pickable` has those
            // expected at the start first); the rest ranks by how many are expected.
            down.sort_by_key(|&g| !self.reachable(a, g, &pose));
            let expected = |arm: Arm, list: &[usize]| {
                list.iter()
                    .filter(|&&g| self.reachable(arm, g, &pose))
                    .count()
            };
            let likely = expected(a, &down).min(expected(b, &up));
            rest_edges.push((k, likely, down, up));
        }
        rest_edges.sort_by_key(|(k, likely, down, up)| {
            let enough = FITTING_ENOUGH;
            (
                std::cmp::Reverse((*likely).min(enough)),
                std::cmp::Reverse(down.len().min(up.len()).min(enough)),
                *k,
            )
        });
        let rest_edges: Vec<(usize, Vec<usize>, Vec<usize>)> = rest_edges
            .into_iter()
            .map(|(k, _, down, up)| (k, down, up))
            .collect();
        if rest_edges.is_empty() {
            return Ok(None);
        }
        // Second grasps that can pick the object up at some rest.
        let mut liftable: Vec<usize> = rest_edges
            .iter()
            .flat_map(|(_, _, up)| up.iter().copied())
            .collect();
        liftable.sort_unstable();
        liftable.dedup();
        // Both hands open at the start; the second pick is seeded with them open.
        let open_start = self.opened(b, &self.opened(a, &start));
        let mut picks: BTreeMap<usize, std::result::Result<Pick, Rejection>> = BTreeMap::new();
        let mut downs: BTreeMap<(usize, usize), std::result::Result<Place, Rejection>> =
            BTreeMap::new();
        let mut ups: BTreeMap<(usize, usize), std::result::Result<Pick, Rejection>> =
            BTreeMap::new();
        // Per rest: whether A can put the object down there with some grasp.
        let mut alive: BTreeMap<usize, bool> = BTreeMap::new();
        let (fewest, most) = self.run.options.regrasp_rests;
        let one_rest = if fewest <= 1 && most >= 1 {
            finals.as_slice()
        } else {
            &[]
        };
        for (pi, fit_final, _) in one_rest {
            let pi = *pi;
            // The most constrained leg first: B's places at the target, seeded from the
            // start, in parallel chunks; then the rests where B can pick up with that grasp,
            // then A's grasps that put it down there.
            let seconds: Vec<usize> = fit_final
                .iter()
                .copied()
                .filter(|g| liftable.binary_search(g).is_ok())
                .collect();
            for chunk in seconds.chunks(PARALLEL_CHUNK) {
                if self.out_of_time() {
                    count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                    return Ok(None);
                }
                let results: Vec<_> = chunk
                    .par_iter()
                    .map(|&g2| (g2, self.place(b, pi, g2)))
                    .collect();
                for (g2, r) in results {
                    let r = split(r)?;
                    tally(report, Stage::Place, &r);
                    let Ok(place) = r else {
                        continue;
                    };
                    // A rest where A puts the object down with no grasp is no use: found
                    // once per rest, before any pick-up there is computed.
                    for (k, down, up) in &rest_edges {
                        if up.binary_search(&g2).is_err() || alive.contains_key(k) {
                            continue;
                        }
                        let any =
                            self.can_put_down(a, *k, down, (&mut picks, &mut downs), report)?;
                        alive.insert(*k, any);
                    }
                    // B's pick-ups of `g2` at every such rest where it fits, on the thread
                    // pool.
                    let todo: Vec<usize> = rest_edges
                        .iter()
                        .filter(|(k, _, up)| {
                            up.binary_search(&g2).is_ok()
                                && alive.get(k) == Some(&true)
                                && !ups.contains_key(&(*k, g2))
                        })
                        .map(|(k, _, _)| *k)
                        .collect();
                    let computed: Vec<_> = todo
                        .par_iter()
                        .map(|&k| {
                            let rest_pose = self.rests()[k].world_from_object;
                            let supports = self.rest_supports(k);
                            let r = self.pick_at(
                                b,
                                g2,
                                &rest_pose,
                                supports,
                                &open_start,
                                1 + k as u64,
                            );
                            (k, r)
                        })
                        .collect();
                    for (k, r) in computed {
                        let r = split(r)?;
                        tally(report, Stage::Regrasp, &r);
                        ups.insert((k, g2), r);
                    }
                    for (k, down, up) in &rest_edges {
                        let k = *k;
                        if up.binary_search(&g2).is_err() {
                            continue;
                        }
                        if self.out_of_time() {
                            break;
                        }
                        let Some(Ok(up_pick)) = ups.get(&(k, g2)) else {
                            continue;
                        };
                        let up_pick = up_pick.clone();
                        // The same hand with the same grasp gains nothing.
                        let firsts: Vec<usize> = down
                            .iter()
                            .copied()
                            .filter(|&g1| !(a == b && g2 == g1))
                            .collect();
                        for chunk in firsts.chunks(PARALLEL_CHUNK) {
                            if self.out_of_time() {
                                break;
                            }
                            // A's picks and put-downs at this rest, on the thread pool, then
                            // taken in rank order.
                            self.put_downs(a, k, chunk, (&mut picks, &mut downs), report)?;
                            for &g1 in chunk {
                                let Some(Ok(pick)) = picks.get(&g1) else {
                                    continue;
                                };
                                let pick = pick.clone();
                                let Some(Ok(down_place)) = downs.get(&(k, g1)) else {
                                    continue;
                                };
                                let down_place = down_place.clone();
                                let legs = RegraspLegs {
                                    strategy,
                                    pi,
                                    k,
                                    g1,
                                    g2,
                                    pick: &pick,
                                    down: &down_place,
                                    up: &up_pick,
                                    place: &place,
                                };
                                match split(self.regrasp_motions(&start, &legs))? {
                                    Ok(segments) => {
                                        count(report, Stage::Motion).accept();
                                        count(report, Stage::Placement).accept();
                                        return Ok(Some(Found {
                                            segments,
                                            grasps: vec![(a, g1), (b, g2)],
                                            placement: pi,
                                            rests: vec![k],
                                        }));
                                    }
                                    Err(r) => count(report, Stage::Motion).reject(r.to_string()),
                                }
                            }
                        }
                    }
                }
            }
            count(report, Stage::Placement).reject(Rejection::NoRegraspSequence.to_string());
        }
        if most < 2 || self.out_of_time() {
            return Ok(None);
        }
        let search = TwoRests {
            strategy,
            start: &start,
            open_start: &open_start,
            finals: &finals,
            rest_edges: &rest_edges,
        };
        self.regrasp_two_rests(
            &search,
            (&mut picks, &mut downs),
            &mut ups,
            &mut alive,
            report,
        )
    }
}

/// The key poses of one regrasp sequence, checked: arm A's pick at the start and put-down at
/// rest `k` with grasp `g1`; arm B's pick at the rest and place at placement `pi` with `g2`.
pub(in crate::planner) struct RegraspLegs<'l> {
    pub strategy: Strategy,
    pub pi: usize,
    pub k: usize,
    pub g1: usize,
    pub g2: usize,
    pub pick: &'l Pick,
    pub down: &'l Place,
    pub up: &'l Pick,
    pub place: &'l Place,
}
