//! The next shortest sequences of the regrasp graph: through two intermediate rests.

use super::keyposes::PutDownMemos;
use super::{REST_SALT, tally};
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::planner::assemble::Found;
use crate::planner::fits::PARALLEL_CHUNK;
use crate::planner::keypose::{Pick, Place};
use crate::planner::reason::{Rejection, Stage, count, split};
use crate::planner::{Ctx, end_of};
use crate::strategy::Strategy;
use pickplace_geometry::math::Real;
use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

/// What the two-rest search works on: the strategy, the start (and with both hands open),
/// the placements in B's order with the grasps that fit there, and per rest the grasps A puts
/// the object down with and those B picks it up with.
pub(super) struct TwoRests<'s> {
    pub(super) strategy: Strategy,
    pub(super) start: &'s [Real],
    pub(super) open_start: &'s [Real],
    pub(super) finals: &'s [(usize, Vec<usize>, usize)],
    pub(super) rest_edges: &'s [(usize, Vec<usize>, Vec<usize>)],
}

/// The key poses of a sequence through two rests, checked: A's pick at the start and put-down
/// at rest k₁ with g₁; B's pick-up at k₁ and put-down at k₂ with g₂; B's pick-up at k₂ and
/// place at placement `pi` with g₃.
pub(in crate::planner) struct TwoRestLegs<'l> {
    pub strategy: Strategy,
    pub pi: usize,
    pub rests: (usize, usize),
    pub grasps: (usize, usize, usize),
    pub pick: &'l Pick,
    pub down: &'l Place,
    pub up: &'l Pick,
    pub moved: &'l Place,
    pub up_again: &'l Pick,
    pub place: &'l Place,
}

impl Ctx<'_> {
    /// The next shortest sequences of the regrasp graph, through two intermediate rests:
    /// start →(A, g₁)→ rest k₁ →(B, g₂)→ rest k₂ →(B, g₃)→ placement, searched when no
    /// sequence through one rest works (or when asked for,
    /// [`PlanOptions::regrasp_rests`](crate::planner::PlanOptions::regrasp_rests)).
    /// B's places at the target first (the most constrained leg), then the rests k₂ where B
    /// picks up with g₃, the rests k₁ where A puts the object down, B's grasps g₂ that pick it
    /// up at k₁ and put it down at k₂, and last A's grasps g₁ and the motions. Every key pose is
    /// computed once; the search stops at the first sequence whose motions join, or when the
    /// strategy's share of the time budget is spent.
    pub(super) fn regrasp_two_rests(
        &self,
        search: &TwoRests<'_>,
        (picks, downs): PutDownMemos<'_>,
        ups: &mut BTreeMap<(usize, usize), std::result::Result<Pick, Rejection>>,
        alive: &mut BTreeMap<usize, bool>,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let strategy = search.strategy;
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let mut moves: BTreeMap<(usize, usize, usize), std::result::Result<Place, Rejection>> =
            BTreeMap::new();
        for (pi, fit_final, _) in search.finals {
            let pi = *pi;
            for &g3 in fit_final {
                if self.out_of_time() {
                    count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                    return Ok(None);
                }
                // Computed (and counted) by the one-rest search when it ran.
                let Ok(place) = split(self.place(b, pi, g3))? else {
                    continue;
                };
                for (k2, _, up2) in search.rest_edges {
                    let k2 = *k2;
                    if up2.binary_search(&g3).is_err() {
                        continue;
                    }
                    let Some(last_up) = self.pick_up(b, k2, g3, search.open_start, ups, report)?
                    else {
                        continue;
                    };
                    let rest2 = self.rests()[k2].world_from_object;
                    for (k1, down1, up1) in search.rest_edges {
                        let k1 = *k1;
                        if k1 == k2 || self.out_of_time() {
                            continue;
                        }
                        if let Entry::Vacant(slot) = alive.entry(k1) {
                            slot.insert(self.can_put_down(
                                a,
                                k1,
                                down1,
                                (&mut *picks, &mut *downs),
                                report,
                            )?);
                        }
                        if alive.get(&k1) != Some(&true) {
                            continue;
                        }
                        for &g2 in up1 {
                            // The same hand with the same grasp gains nothing; g₂ must put the
                            // object down at k₂ with the gripper clear there.
                            if g2 == g3 || self.grasp_fits(b, g2, &rest2, false).is_err() {
                                continue;
                            }
                            if self.out_of_time() {
                                break;
                            }
                            let Some(first_up) =
                                self.pick_up(b, k1, g2, search.open_start, ups, report)?
                            else {
                                continue;
                            };
                            let moved = match moves.entry((k1, k2, g2)) {
                                Entry::Occupied(e) => e.get().clone(),
                                Entry::Vacant(slot) => {
                                    let lifted = end_of(&first_up.lift)?;
                                    let r = split(self.place_at(
                                        b,
                                        g2,
                                        &rest2,
                                        self.rest_supports(k2),
                                        lifted,
                                        REST_SALT | 1 << 61 | (k2 as u64) << 20 | (k1 as u64) << 36,
                                    ))?;
                                    tally(report, Stage::Rest, &r);
                                    slot.insert(r).clone()
                                }
                            };
                            let Ok(moved) = moved else {
                                continue;
                            };
                            let firsts: Vec<usize> = down1
                                .iter()
                                .copied()
                                .filter(|&g1| !(a == b && g1 == g2))
                                .collect();
                            for chunk in firsts.chunks(PARALLEL_CHUNK) {
                                if self.out_of_time() {
                                    break;
                                }
                                self.put_downs(a, k1, chunk, (&mut *picks, &mut *downs), report)?;
                                for &g1 in chunk {
                                    let (Some(Ok(pick)), Some(Ok(down))) =
                                        (picks.get(&g1), downs.get(&(k1, g1)))
                                    else {
                                        continue;
                                    };
                                    let legs = TwoRestLegs {
                                        strategy,
                                        pi,
                                        rests: (k1, k2),
                                        grasps: (g1, g2, g3),
                                        pick,
                                        down,
                                        up: &first_up,
                                        moved: &moved,
                                        up_again: &last_up,
                                        place: &place,
                                    };
                                    match split(self.two_rest_motions(search.start, &legs))? {
                                        Ok(segments) => {
                                            count(report, Stage::Motion).accept();
                                            count(report, Stage::Placement).accept();
                                            return Ok(Some(Found {
                                                segments,
                                                grasps: vec![(a, g1), (b, g2), (b, g3)],
                                                placement: pi,
                                                rests: vec![k1, k2],
                                            }));
                                        }
                                        Err(r) => {
                                            count(report, Stage::Motion).reject(r.to_string())
                                        }
                                    }
                                }
                            }
                        }
                    }
                }
            }
            count(report, Stage::Placement).reject(Rejection::NoRegraspSequence.to_string());
        }
        Ok(None)
    }
}
