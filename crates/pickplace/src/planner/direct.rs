//! The direct strategies, RIGHT-RIGHT and LEFT-LEFT (paper §III-B.3 and Fig. 8): placements
//! best first; for each, the grasps best first through pick, place and the motion between
//! them. The first candidate that passes every test is the plan; every rejection is counted
//! under its stage.

use super::Ctx;
use super::assemble::Found;
use super::reason::{Rejection, Stage, count, split};
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::Real;
use rayon::prelude::*;

/// How much nearer (m) one hand may be than the other to the object's start or to the
/// target for the paper's choice of the nearer hand to count as a close call
/// ([`Ctx::direct_first`]).
const NEARLY_EQUALLY_NEAR: Real = 0.10;

/// Places a probe of a single-arm strategy computes at most ([`Ctx::single_arm_search`]).
pub(super) const PROBE_PLACES: usize = 512;

/// Grasps whose pick and place a single-arm search computes together on the thread pool: a
/// few, since the first that passes ends the search (the others are extra work).
const SINGLE_ARM_CHUNK: usize = 4;

impl Ctx<'_> {
    /// RIGHT-RIGHT or LEFT-LEFT with `arm`: placements and grasps searched together. The
    /// grasps that pass the cheap tests at the start ([`Ctx::grasp_fits`]: within reach,
    /// open gripper clear of the environment) are the candidates; placements are tried in
    /// [`Ctx::placement_order`] (most such grasps also fitting there first, then the paper's
    /// criteria), and at each placement every candidate fitting there, best first: pick,
    /// place and the motions between them. No count caps the search; it goes on until a
    /// plan is found, the candidates run out, or the strategy's share of the time budget is
    /// spent. Picks do not depend on the placement and are computed once per grasp.
    pub(super) fn single_arm_strategy(
        &mut self,
        arm: Arm,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        self.single_arm_search(arm, report, false)
    }

    /// [`Ctx::single_arm_strategy`], or with `probe` its quick form that [`Ctx::direct_first`]
    /// runs before the paper's order: the grasps the reachability maps expect only, and at
    /// most [`PROBE_PLACES`] places computed (a count, so the outcome does not depend on the
    /// machine's speed). A probe that finds nothing leaves the full search to the strategy's
    /// turn in the order, where the picks and places computed are reused.
    pub(super) fn single_arm_search(
        &mut self,
        arm: Arm,
        report: &mut StrategyReport,
        probe: bool,
    ) -> Result<Option<Found>> {
        let start = self.run.setup.start.clone();
        let mut places_computed = 0usize;
        let pickable = self.fitting_at_start(arm, report);
        let mut counted = std::collections::BTreeSet::new();
        let order = self.placement_order(arm, &pickable, true, report);
        // Two passes over the placements: first the grasps the reachability map expects
        // IK for at both the start and the placement, then the others. A placement whose
        // likely grasps all fail does not hold up the likely grasps of the next one.
        let mut any = vec![false; order.len()];
        let passes = if probe { 1 } else { 2 };
        for pass in 0..passes {
            for (oi, (pi, grasps, expected)) in order.iter().enumerate() {
                let pi = *pi;
                if self.out_of_time() {
                    count(report, Stage::Placement).reject(Rejection::TimeBudgetSpent.to_string());
                    return Ok(None);
                }
                let grasps = if pass == 0 {
                    &grasps[..*expected]
                } else {
                    &grasps[*expected..]
                };
                // Picks and places of a few grasps at a time on the thread pool (each
                // memoized), then taken in rank order: the plan and its counts are the same
                // whatever the thread count.
                for batch in grasps.chunks(SINGLE_ARM_CHUNK) {
                    if self.out_of_time() {
                        break;
                    }
                    if probe && places_computed >= PROBE_PLACES {
                        return Ok(None);
                    }
                    places_computed += batch.len();
                    let results: Vec<_> = batch
                        .par_iter()
                        .map(|&gi| {
                            let pick = self.pick(arm, gi);
                            let place = pick.is_ok().then(|| self.place(arm, pi, gi));
                            (gi, pick, place)
                        })
                        .collect();
                    for (gi, pick, place) in results {
                        let result = split(pick)?;
                        if counted.insert(gi) {
                            match &result {
                                Ok(_) => count(report, Stage::Pick).accept(),
                                Err(r) => count(report, Stage::Pick).reject(r.to_string()),
                            }
                        }
                        let (Ok(pick), Some(place)) = (result, place) else {
                            continue;
                        };
                        let place = match split(place)? {
                            Ok(p) => p,
                            Err(r) => {
                                count(report, Stage::Place).reject(r.to_string());
                                continue;
                            }
                        };
                        count(report, Stage::Place).accept();
                        any[oi] = true;
                        match split(self.single_arm_motions(arm, pi, gi, &start, &pick, &place))? {
                            Ok(segments) => {
                                count(report, Stage::Motion).accept();
                                count(report, Stage::Placement).accept();
                                return Ok(Some(Found {
                                    segments,
                                    grasps: vec![(arm, gi)],
                                    placement: pi,
                                    rests: Vec::new(),
                                }));
                            }
                            Err(r) => count(report, Stage::Motion).reject(r.to_string()),
                        }
                    }
                }
                if pass == 1 {
                    count(report, Stage::Placement).reject(
                        if any[oi] {
                            Rejection::NoMotionForAnyGrasp
                        } else {
                            Rejection::NoGraspReaches
                        }
                        .to_string(),
                    );
                }
            }
        }
        Ok(None)
    }

    /// An improvement on the paper's order (§III-B.3), which picks with the hand nearer the
    /// object and places with the hand nearer the target: when that makes a handover first
    /// and one of its two choices was close (the two hands' distances to the object's start,
    /// or to the target, within [`NEARLY_EQUALLY_NEAR`]), the single-arm strategy of the
    /// other choice is tried first if the reachability maps expect its arm to do the whole job
    /// (a grasp that fits and is expected at the start and at a placement). It needs one
    /// grasp instead of two and no second arm; an object near the middle is "nearer" one
    /// hand by centimetres. That strategy is probed first ([`Ctx::single_arm_search`]); the
    /// order itself, the paper's, is unchanged.
    pub(super) fn direct_first(&self, order: &[Strategy]) -> Option<Strategy> {
        let &first = order.first()?;
        if !first.has_handover() || first.has_regrasp() || order.len() < 2 {
            return None;
        }
        let (a, b) = (first.pick_arm(), first.place_arm());
        let start = &self.run.setup.object_start;
        let start_point = start * self.run.setup.cog;
        let target = self.run.setup.scene.target_point();
        let close = |p: &pickplace_geometry::math::Point3| {
            let d = |arm: Arm| (self.run.setup.arm(arm).shoulder - p).norm();
            (d(a) - d(b)).abs() <= NEARLY_EQUALLY_NEAR
        };
        // B picks too when the start was close; A places too when the target was.
        let candidates: Vec<Arm> = [(close(&start_point), b), (close(&target), a)]
            .into_iter()
            .filter_map(|(c, arm)| c.then_some(arm))
            .collect();
        let expected = |arm: Arm| {
            let at_start: Vec<usize> = (0..self.run.grasps.len())
                .filter(|&g| {
                    self.grasp_fits(arm, g, start, true).is_ok() && self.reachable(arm, g, start)
                })
                .collect();
            !at_start.is_empty()
                && (0..self.run.placements.len()).any(|pi| {
                    let pose = &self.run.placements[pi].world_from_object;
                    self.fitting_among(arm, pi, &at_start)
                        .into_iter()
                        .any(|g| self.reachable(arm, g, pose))
                })
        };
        candidates
            .into_iter()
            .find(|&arm| expected(arm))
            .map(|arm| Strategy::new(arm, arm))
            .filter(|s| order.contains(s))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::planner::tests::{ctx, report};

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
            ..ctx.run.options.clone()
        };
        ctx.run.options = Box::leak(Box::new(options));
        ctx.budget.total = 0.0;
        let mut r = report(Strategy::RightRight);
        assert!(
            ctx.single_arm_strategy(Arm::Right, &mut r)
                .expect("no defect")
                .is_none()
        );
        assert_eq!(r.stages["placement"].rejected["time budget spent"], 1);
        // The cheap tests ran; no pick was tried.
        assert!(r.stages.get("pick").is_none_or(|p| p.accepted == 0));
        assert!(!r.stages.contains_key("place"));
    }

    /// The paper's order for the scene of `ctx`.
    fn paper_order(ctx: &Ctx<'_>) -> Vec<Strategy> {
        let shoulders = [
            ctx.run.setup.arm(Arm::Right).shoulder,
            ctx.run.setup.arm(Arm::Left).shoulder,
        ];
        Strategy::order(
            crate::scene::StrategyChoice::Auto,
            shoulders,
            &(ctx.run.setup.object_start * ctx.run.setup.cog),
            &ctx.run.setup.scene.target_point(),
        )
    }

    #[test]
    fn a_close_call_of_the_nearer_hand_probes_the_one_arm_strategy() {
        // The box starts 2 cm left of the middle: the paper hands it over left to right; the
        // right hand alone does it, and its probe finds the plan.
        let mut ctx = ctx("suite/box-into-gap.toml");
        let order = paper_order(&ctx);
        assert_eq!(order[0], Strategy::LeftRight);
        assert_eq!(ctx.direct_first(&order), Some(Strategy::RightRight));
        let mut r = report(Strategy::RightRight);
        let found = ctx
            .single_arm_search(Arm::Right, &mut r, true)
            .expect("no defect");
        assert!(found.is_some(), "{:?}", r.stages);
        // A probe computes at most PROBE_PLACES places (in chunks).
        let computed: usize = r.stages.get("place").map_or(0, |p| p.tried);
        assert!(computed <= PROBE_PLACES + SINGLE_ARM_CHUNK, "{computed}");
    }

    #[test]
    fn a_probe_that_fails_stops_at_its_count_and_leaves_the_paper_order() {
        // The Fig. 9 can far to the left, the target on the pallet near the middle: the left
        // hand is nearer the target by less than NEARLY_EQUALLY_NEAR, so LEFT-LEFT is
        // probed; its places collide with the idle right arm, and the probe gives up after
        // its count of places. The plan is the paper's handover.
        let mut ctx = ctx("fig9-far-left.toml");
        let order = paper_order(&ctx);
        assert_eq!(order[0], Strategy::LeftRight);
        assert_eq!(ctx.direct_first(&order), Some(Strategy::LeftLeft));
        let mut r = report(Strategy::LeftLeft);
        let found = ctx
            .single_arm_search(Arm::Left, &mut r, true)
            .expect("no defect");
        assert!(found.is_none());
        let computed: usize = r.stages.get("pick").map_or(0, |p| p.accepted);
        assert!(computed <= PROBE_PLACES + SINGLE_ARM_CHUNK, "{computed}");
    }
}
