//! The handover search (paper §III-B.3, RIGHT-LEFT and LEFT-RIGHT): picks by the first arm,
//! placements in the second arm's order, and for each the second grasps that place the object
//! and clear the first hand, tried at the handover poses of [`super::Ctx::handover_at`].

use super::super::Ctx;
use super::super::assemble::Found;
use super::super::fits::PARALLEL_CHUNK;
use super::super::keypose::{Pick, Place};
use super::super::reason::{Rejection, Stage, count, split};
use super::{Handover, handover_candidates, hands_overlap};
use crate::error::Result;
use crate::plan::{StageCount, StrategyReport};
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{Isometry3, Real};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Picks by the first arm gathered at a time for a handover search (more are gathered when
/// these find no handover).
const HANDOVER_PICKS: usize = 12;

/// Second grasps gathered per placement in the first round of a handover search (each round
/// of picks gathers this many more).
const SECOND_GRASPS: usize = 48;

impl Ctx<'_> {
    /// RIGHT-LEFT or LEFT-RIGHT: picks by arm A down the ranked grasps, gathered
    /// [`HANDOVER_PICKS`] at a time; placements in arm B's [`Ctx::placement_order`]; for
    /// each, the second grasps of arm B that place it and clear A's hand; handover poses
    /// tried with each pick until [`super::PlanOptions::handover_feasible`] are found; the
    /// best scored first through the motions. When a round of picks finds nothing at any
    /// placement, the next round takes the next picks: no count caps the search, only the
    /// strategy's share of the time budget.
    pub(in crate::planner) fn handover_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.run.setup.start.clone();
        let pickable = self.fitting_at_start(a, report);
        let all: Vec<usize> = (0..self.run.grasps.len()).collect();
        let order = self.placement_order(b, &all, false, report);
        let handovers = handover_candidates(self.run.setup, a, self.run.options.handover_poses);
        // Places by arm B per placement, seeded from its start configuration, computed once
        // per grasp.
        let mut places: Vec<BTreeMap<usize, Option<Place>>> = vec![BTreeMap::new(); order.len()];
        let mut picks: Vec<(usize, Pick)> = Vec::new();
        let mut next_pick = 0;
        loop {
            let round = picks.len();
            self.handover_picks(a, &pickable, &mut next_pick, &mut picks, report)?;
            if picks.len() == round {
                break;
            }
            for (oi, (pi, fitting, _)) in order.iter().enumerate() {
                if self.out_of_time() {
                    count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                    return Ok(None);
                }
                let pi = *pi;
                let mut feasible: Vec<(Real, Handover)> = Vec::new();
                'picks: for (g1, pick) in &picks[round..] {
                    if self.out_of_time() {
                        break;
                    }
                    let limit = SECOND_GRASPS * (1 + round / HANDOVER_PICKS);
                    let mine =
                        self.second_grasps(b, pi, *g1, (fitting, limit), &mut places[oi], report)?;
                    if mine.is_empty() {
                        count(report, Stage::Handover).reject(Rejection::NoSecondGrasp.to_string());
                        continue;
                    }
                    // The handover: object poses in front of the torso (where the picking
                    // hand holds it at a searched tool pose), scored by both arms' reach and
                    // clearance.
                    let indexed: Vec<(usize, &Isometry3)> = handovers.iter().enumerate().collect();
                    for chunk in indexed.chunks(PARALLEL_CHUNK) {
                        let results: Vec<_> = chunk
                            .par_iter()
                            .map(|&(hi, h)| {
                                // The object where the picking hand holds it at this tool pose.
                                let world_from_object =
                                    h * self.run.grasps[*g1].object_from_tcp.inverse();
                                let mut regrasp = StageCount::default();
                                let result = self.handover_at(
                                    strategy,
                                    hi,
                                    &world_from_object,
                                    *g1,
                                    pick,
                                    &mine,
                                    &mut regrasp,
                                );
                                (result, regrasp)
                            })
                            .collect();
                        for (result, regrasp) in results {
                            let total = count(report, Stage::Regrasp);
                            total.tried += regrasp.tried;
                            total.accepted += regrasp.accepted;
                            for (reason, n) in regrasp.rejected {
                                *total.rejected.entry(reason).or_default() += n;
                            }
                            match split(result)? {
                                Ok(found) => {
                                    count(report, Stage::Handover).accept();
                                    feasible.push(found);
                                    if feasible.len() >= self.run.options.handover_feasible {
                                        break 'picks;
                                    }
                                }
                                Err(r) => count(report, Stage::Handover).reject(r.to_string()),
                            }
                        }
                    }
                }
                feasible.sort_by(|x, y| y.0.total_cmp(&x.0));
                for (_, h) in feasible {
                    // A handover is built from one of `picks` and one of `places`.
                    let missing = |what: &str| crate::Error::Internal {
                        stage: "handover",
                        reason: format!("the handover's {what} is not among the candidates"),
                    };
                    let pick = &picks
                        .iter()
                        .find(|(g, _)| *g == h.g1)
                        .ok_or_else(|| missing("pick"))?
                        .1;
                    let place = places[oi]
                        .get(&h.g2)
                        .and_then(Option::as_ref)
                        .ok_or_else(|| missing("place"))?;
                    match split(self.handover_motions(strategy, pi, &start, pick, place, &h))? {
                        Ok(segments) => {
                            count(report, Stage::Motion).accept();
                            count(report, Stage::Placement).accept();
                            return Ok(Some(Found {
                                segments,
                                grasps: vec![(a, h.g1), (b, h.g2)],
                                placement: pi,
                                rests: Vec::new(),
                            }));
                        }
                        Err(r) => count(report, Stage::Motion).reject(r.to_string()),
                    }
                }
                count(report, Stage::Placement).reject(Rejection::NoHandover.to_string());
            }
        }
        Ok(None)
    }

    /// The next [`HANDOVER_PICKS`] picks by arm `a` (independent of the placement) from
    /// `pickable` starting at `next`: a handover needs two grasps that leave room for each
    /// other, so the search goes down the whole ranked list, not only the best grasps.
    /// Chunks of grasps are tried in parallel; results are taken in rank order.
    fn handover_picks(
        &self,
        a: Arm,
        pickable: &[usize],
        next: &mut usize,
        picks: &mut Vec<(usize, Pick)>,
        report: &mut StrategyReport,
    ) -> Result<()> {
        let wanted = picks.len() + HANDOVER_PICKS;
        while *next < pickable.len() && picks.len() < wanted && !self.out_of_time() {
            let end = (*next + PARALLEL_CHUNK).min(pickable.len());
            let results: Vec<_> = pickable[*next..end]
                .par_iter()
                .map(|&gi| (gi, self.pick(a, gi)))
                .collect();
            for (gi, result) in results {
                *next += 1;
                match split(result)? {
                    Ok(p) => {
                        count(report, Stage::Pick).accept();
                        picks.push((gi, p));
                        if picks.len() >= wanted {
                            break;
                        }
                    }
                    Err(r) => count(report, Stage::Pick).reject(r.to_string()),
                }
            }
        }
        Ok(())
    }

    /// For pick grasp `g1`: the grasps among `fitting` (those that fit arm `b` at placement
    /// `pi`) whose hand clears the first and that place the object at placement `pi`, best
    /// first, at most `limit` (which grows with the rounds of picks). Places are computed in
    /// parallel chunks, each once per placement (kept in `places`).
    #[allow(clippy::too_many_arguments)]
    fn second_grasps(
        &self,
        b: Arm,
        pi: usize,
        g1: usize,
        (fitting, limit): (&[usize], usize),
        places: &mut BTreeMap<usize, Option<Place>>,
        report: &mut StrategyReport,
    ) -> Result<Vec<(usize, Place)>> {
        let clear: Vec<usize> = fitting
            .iter()
            .copied()
            .filter(|&g2| {
                !hands_overlap(
                    &self.run.setup.gripper,
                    &self.run.grasps[g1],
                    &self.run.grasps[g2],
                )
            })
            .collect();
        let mut mine = Vec::new();
        for chunk in clear.chunks(PARALLEL_CHUNK) {
            if self.out_of_time() {
                break;
            }
            let todo: Vec<usize> = chunk
                .iter()
                .copied()
                .filter(|g| !places.contains_key(g))
                .collect();
            let results: Vec<_> = todo
                .par_iter()
                .map(|&g2| (g2, self.place(b, pi, g2)))
                .collect();
            for (g2, result) in results {
                let place = match split(result)? {
                    Ok(p) => {
                        count(report, Stage::Place).accept();
                        Some(p)
                    }
                    Err(r) => {
                        count(report, Stage::Place).reject(r.to_string());
                        None
                    }
                };
                places.insert(g2, place);
            }
            for g2 in chunk {
                if mine.len() >= limit {
                    return Ok(mine);
                }
                if let Some(Some(p)) = places.get(g2) {
                    mine.push((*g2, p.clone()));
                }
            }
        }
        Ok(mine)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::tests::{ctx, report};

    #[test]
    fn the_far_left_can_is_handed_over_from_left_to_right() {
        let mut ctx = ctx("fig9-far-left.toml");
        let mut r = report(Strategy::LeftRight);
        let found = ctx
            .handover_strategy(Strategy::LeftRight, &mut r)
            .expect("no defect")
            .expect("a handover plan");
        assert_eq!(found.grasps[0].0, Arm::Left);
        assert_eq!(found.grasps[1].0, Arm::Right);
        assert!(r.stages["handover"].accepted >= 1);
        let keys: Vec<&str> = found
            .segments
            .iter()
            .filter_map(|s| s.key.map(|k| k.0))
            .collect();
        for k in [
            "handover",
            "pre-regrasp",
            "regrasp",
            "release-first",
            "release",
        ] {
            assert!(keys.contains(&k), "{keys:?}");
        }
    }
}
