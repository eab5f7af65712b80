//! The search of one strategy (paper §III-B.3 and Fig. 8): placements best first; for each,
//! the grasps best first through pick, place and the motions between them; for a handover,
//! the handover poses and second grasps in between. The first candidate that passes every
//! test is the plan; every rejection is counted under its stage.

use super::Ctx;
use super::assemble::Found;
use super::handover::{Handover, handover_candidates, hands_overlap};
use super::keypose::{Pick, Place};
use super::reason::{Rejection, Stage, count, split};
use crate::error::Result;
use crate::plan::{StageCount, StrategyReport};
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{Isometry3, Real};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Candidates evaluated together on the thread pool (results are used in rank order, so the
/// outcome does not depend on the thread count).
const PARALLEL_CHUNK: usize = 16;

/// Picks by the first arm kept for a handover search.
const HANDOVER_PICKS: usize = 12;

impl Ctx<'_> {
    /// RIGHT-RIGHT or LEFT-LEFT with `arm`: for each placement (best first) and grasp (best
    /// first), pick, place and join them with motions. Picks do not depend on the placement
    /// and are computed once per grasp.
    pub(super) fn single_arm_strategy(
        &mut self,
        arm: Arm,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let start = self.setup.start.clone();
        let mut pick_cache: Vec<Option<std::result::Result<Pick, Rejection>>> =
            vec![None; self.grasps.len()];
        let n_grasps = self.grasps.len().min(self.options.max_grasps);
        for pi in 0..self.placements.len().min(self.options.max_placements) {
            if self.out_of_time() {
                count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                break;
            }
            let mut any = false;
            for (gi, cached) in pick_cache.iter_mut().enumerate().take(n_grasps) {
                let result = match cached {
                    Some(result) => result,
                    None => cached.insert(split(self.pick(arm, gi, &start))?),
                };
                let pick = match result {
                    Ok(p) => p.clone(),
                    Err(r) => {
                        if pi == 0 {
                            count(report, Stage::Pick).reject(r.to_string());
                        }
                        continue;
                    }
                };
                if pi == 0 {
                    count(report, Stage::Pick).accept();
                }
                let lifted = super::end_of(&pick.lift)?.clone();
                let place = match split(self.place(arm, pi, gi, &lifted))? {
                    Ok(p) => p,
                    Err(r) => {
                        count(report, Stage::Place).reject(r.to_string());
                        continue;
                    }
                };
                count(report, Stage::Place).accept();
                any = true;
                match split(self.single_arm_motions(arm, pi, gi, &start, &pick, &place))? {
                    Ok(segments) => {
                        count(report, Stage::Motion).accept();
                        count(report, Stage::Placement).accept();
                        return Ok(Some(Found {
                            segments,
                            grasps: vec![(arm, gi)],
                            placement: pi,
                        }));
                    }
                    Err(r) => count(report, Stage::Motion).reject(r.to_string()),
                }
            }
            count(report, Stage::Placement).reject(
                if any {
                    Rejection::NoMotionForAnyGrasp
                } else {
                    Rejection::NoGraspReaches
                }
                .to_string(),
            );
        }
        Ok(None)
    }

    /// RIGHT-LEFT or LEFT-RIGHT: picks by arm A down the ranked grasps; for each placement,
    /// the second grasps of arm B that place it and clear A's hand; handover poses tried with
    /// each pick until [`super::PlanOptions::handover_feasible`] are found; the best scored
    /// first through the motions.
    pub(super) fn handover_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.setup.start.clone();
        let picks = self.handover_picks(a, &start, report)?;
        if picks.is_empty() {
            return Ok(None);
        }
        let handovers = handover_candidates(self.setup, a, self.options.handover_poses);
        for pi in 0..self.placements.len().min(self.options.max_placements) {
            if self.out_of_time() {
                count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                break;
            }
            // Places by arm B, seeded from its start configuration, computed once per grasp.
            let mut places: BTreeMap<usize, Option<Place>> = BTreeMap::new();
            let mut feasible: Vec<(Real, Handover)> = Vec::new();
            'picks: for (g1, pick) in &picks {
                let mine = self.second_grasps(b, pi, *g1, &start, &mut places, report)?;
                if mine.is_empty() {
                    count(report, Stage::Handover).reject(Rejection::NoSecondGrasp.to_string());
                    continue;
                }
                // The handover: object poses in front of the torso (where the picking hand
                // holds it at a searched tool pose), scored by both arms' reach and clearance.
                let indexed: Vec<(usize, &Isometry3)> = handovers.iter().enumerate().collect();
                for chunk in indexed.chunks(PARALLEL_CHUNK) {
                    let results: Vec<_> = chunk
                        .par_iter()
                        .map(|&(hi, h)| {
                            // The object where the picking hand holds it at this tool pose.
                            let world_from_object = h * self.grasps[*g1].object_from_tcp.inverse();
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
                                if feasible.len() >= self.options.handover_feasible {
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
                let place = places
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
                        }));
                    }
                    Err(r) => count(report, Stage::Motion).reject(r.to_string()),
                }
            }
            count(report, Stage::Placement).reject(Rejection::NoHandover.to_string());
        }
        Ok(None)
    }

    /// Picks by arm `a` (independent of the placement): a handover needs two grasps that
    /// leave room for each other, so the search goes down the whole ranked list until it has
    /// [`HANDOVER_PICKS`] picks, not only the best grasps. Chunks of grasps are tried in
    /// parallel; results are taken in rank order.
    fn handover_picks(
        &self,
        a: Arm,
        start: &[Real],
        report: &mut StrategyReport,
    ) -> Result<Vec<(usize, Pick)>> {
        let mut picks = Vec::new();
        let mut next = 0;
        'scan: while next < self.grasps.len() {
            let end = (next + PARALLEL_CHUNK).min(self.grasps.len());
            let results: Vec<_> = (next..end)
                .into_par_iter()
                .map(|gi| (gi, self.pick(a, gi, start)))
                .collect();
            next = end;
            for (gi, result) in results {
                if picks.len() >= HANDOVER_PICKS {
                    break 'scan;
                }
                match split(result)? {
                    Ok(p) => {
                        count(report, Stage::Pick).accept();
                        picks.push((gi, p));
                    }
                    Err(r) => count(report, Stage::Pick).reject(r.to_string()),
                }
            }
        }
        Ok(picks)
    }

    /// For pick grasp `g1`: the grasps of arm `b` whose hand clears the first and that place
    /// the object at placement `pi`, best first, at most [`super::PlanOptions::max_grasps`].
    /// Places are computed in parallel chunks, each once per placement (kept in `places`).
    fn second_grasps(
        &self,
        b: Arm,
        pi: usize,
        g1: usize,
        start: &[Real],
        places: &mut BTreeMap<usize, Option<Place>>,
        report: &mut StrategyReport,
    ) -> Result<Vec<(usize, Place)>> {
        let clear: Vec<usize> = (0..self.grasps.len())
            .filter(|&g2| !hands_overlap(&self.setup.gripper, &self.grasps[g1], &self.grasps[g2]))
            .collect();
        let mut mine = Vec::new();
        for chunk in clear.chunks(PARALLEL_CHUNK) {
            let todo: Vec<usize> = chunk
                .iter()
                .copied()
                .filter(|g| !places.contains_key(g))
                .collect();
            let results: Vec<_> = todo
                .par_iter()
                .map(|&g2| (g2, self.place(b, pi, g2, start)))
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
                if mine.len() >= self.options.max_grasps {
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
    use super::super::tests::ctx;
    use super::*;

    fn report(strategy: Strategy) -> StrategyReport {
        StrategyReport {
            strategy,
            success: false,
            stages: BTreeMap::new(),
        }
    }

    #[test]
    fn the_near_can_is_picked_and_placed_by_the_right_hand() {
        let mut ctx = ctx("fig9-near.toml");
        let mut r = report(Strategy::RightRight);
        let found = ctx
            .single_arm_strategy(Arm::Right, &mut r)
            .expect("no defect")
            .expect("a plan");
        assert_eq!(found.grasps.len(), 1);
        assert_eq!(found.grasps[0].0, Arm::Right);
        assert_eq!(r.stages["placement"].accepted, 1);
        assert_eq!(r.stages["motion"].accepted, 1);
        let keys: Vec<&str> = found
            .segments
            .iter()
            .filter_map(|s| s.key.map(|k| k.0))
            .collect();
        assert_eq!(&keys[..4], ["pre-grasp", "grasp", "lift", "pre-place"]);
    }

    #[test]
    fn an_arm_that_reaches_nothing_says_so_per_placement() {
        let mut ctx = ctx("fig9-far-left.toml");
        let mut r = report(Strategy::RightRight);
        assert!(
            ctx.single_arm_strategy(Arm::Right, &mut r)
                .expect("no defect")
                .is_none()
        );
        let pick = &r.stages["pick"];
        assert_eq!(pick.accepted, 0);
        assert_eq!(pick.rejected.keys().collect::<Vec<_>>(), ["out of reach"]);
        let placement = &r.stages["placement"];
        assert_eq!(placement.rejected["no grasp reaches it"], placement.tried);
    }

    #[test]
    fn a_spent_budget_stops_the_search_and_is_counted() {
        let mut ctx = ctx("fig9-near.toml");
        let options = super::super::PlanOptions {
            time_budget: 0.0,
            ..ctx.options.clone()
        };
        ctx.options = Box::leak(Box::new(options));
        let mut r = report(Strategy::RightRight);
        assert!(
            ctx.single_arm_strategy(Arm::Right, &mut r)
                .expect("no defect")
                .is_none()
        );
        assert_eq!(r.stages["placement"].rejected["time budget spent"], 1);
        assert!(!r.stages.contains_key("pick"));
    }

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
