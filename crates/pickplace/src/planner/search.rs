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
pub(super) const PARALLEL_CHUNK: usize = 16;

/// How much nearer (m) one hand may be than the other to the object's start or to the
/// target for the paper's choice of the nearer hand to count as a close call
/// ([`Ctx::direct_first`]).
const NEARLY_EQUALLY_NEAR: Real = 0.10;

/// Places a probe of a single-arm strategy computes at most ([`Ctx::single_arm_search`]).
pub(super) const PROBE_PLACES: usize = 512;

/// Grasps whose pick and place a single-arm search computes together on the thread pool: a
/// few, since the first that passes ends the search (the others are extra work).
const SINGLE_ARM_CHUNK: usize = 4;

/// Picks by the first arm gathered at a time for a handover search (more are gathered when
/// these find no handover).
const HANDOVER_PICKS: usize = 12;

/// Grasps fitting at a placement counted for its rank: beyond this many, placements rank by
/// the paper's criteria alone.
pub(super) const FITTING_ENOUGH: usize = 8;

/// Second grasps gathered per placement in the first round of a handover search (each round
/// of picks gathers this many more).
const SECOND_GRASPS: usize = 48;

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
        let start = self.setup.start.clone();
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

    /// The grasps `arm` can take the object with at its start by the cheap tests
    /// ([`Ctx::grasp_fits`], open gripper), best first; the others are counted as rejected
    /// picks with their reason.
    pub(super) fn fitting_at_start(&self, arm: Arm, report: &mut StrategyReport) -> Vec<usize> {
        let results: Vec<_> = (0..self.grasps.len())
            .into_par_iter()
            .map(|gi| self.grasp_fits(arm, gi, &self.setup.object_start, true))
            .collect();
        let mut out = Vec::new();
        for (gi, r) in results.into_iter().enumerate() {
            match r {
                Ok(()) => out.push(gi),
                Err(r) => count(report, Stage::Pick).reject(r.to_string()),
            }
        }
        // Those the reachability map expects IK for first, each group in rank order.
        out.sort_by_key(|&gi| !self.reachable(arm, gi, &self.setup.object_start));
        out
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
        let start = &self.setup.object_start;
        let start_point = start * self.setup.cog;
        let target = self.setup.scene.target_point();
        let close = |p: &pickplace_geometry::math::Point3| {
            let d = |arm: Arm| (self.setup.arm(arm).shoulder - p).norm();
            (d(a) - d(b)).abs() <= NEARLY_EQUALLY_NEAR
        };
        // B picks too when the start was close; A places too when the target was.
        let candidates: Vec<Arm> = [(close(&start_point), b), (close(&target), a)]
            .into_iter()
            .filter_map(|(c, arm)| c.then_some(arm))
            .collect();
        let expected = |arm: Arm| {
            let at_start: Vec<usize> = (0..self.grasps.len())
                .filter(|&g| {
                    self.grasp_fits(arm, g, start, true).is_ok() && self.reachable(arm, g, start)
                })
                .collect();
            !at_start.is_empty()
                && (0..self.placements.len()).any(|pi| {
                    let pose = &self.placements[pi].world_from_object;
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

    /// Whether `arm`'s reachability map ([`crate::reach::ReachMap`]) expects IK for grasp
    /// `gi` with the object at `world_from_object`: a guess that orders the search, never a
    /// reason to skip a candidate.
    pub(super) fn reachable(&self, arm: Arm, gi: usize, world_from_object: &Isometry3) -> bool {
        let a = self.setup.arm(arm);
        let root_from_tcp = self.setup.world_from_root.inverse()
            * world_from_object
            * self.grasps[gi].object_from_tcp;
        a.reach_map.score(&root_from_tcp) > 0
    }

    /// Those of `grasps` (in their order) whose closed gripper fits `arm` at placement `pi`:
    /// [`Ctx::fitting_at_placement`] when it is known, else each of them tested (a one-arm
    /// search asks about the few grasps that pick the object, not the thousand of a
    /// scanned object's set).
    fn fitting_among(&self, arm: Arm, pi: usize, grasps: &[usize]) -> Vec<usize> {
        if let Some((fits, _)) = self.placement_fits[arm.index()][pi].get() {
            return grasps
                .iter()
                .copied()
                .filter(|g| fits.binary_search(g).is_ok())
                .collect();
        }
        let pose = self.placements[pi].world_from_object;
        grasps
            .iter()
            .copied()
            .filter(|&g| self.grasp_fits(arm, g, &pose, false).is_ok())
            .collect()
    }

    /// Whether any grasp's closed gripper fits `arm` at placement `pi`: the first that fits
    /// answers, without [`Ctx::fitting_at_placement`]'s full count.
    fn any_fits(&self, arm: Arm, pi: usize) -> bool {
        if let Some((fits, _)) = self.placement_fits[arm.index()][pi].get() {
            return !fits.is_empty();
        }
        let pose = self.placements[pi].world_from_object;
        (0..self.grasps.len()).any(|g| self.grasp_fits(arm, g, &pose, false).is_ok())
    }

    /// The grasps whose closed gripper fits `arm` at placement `pi` ([`Ctx::grasp_fits`]),
    /// best first, and the most frequent reason of the others; computed once per arm and
    /// placement.
    pub(super) fn fitting_at_placement(&self, arm: Arm, pi: usize) -> &(Vec<usize>, String) {
        self.placement_fits[arm.index()][pi].get_or_init(|| {
            let pose = self.placements[pi].world_from_object;
            let mut fits = Vec::new();
            // Counted by value, named once (a thousand grasps at each of a hundred placements).
            let mut reasons: BTreeMap<Rejection, usize> = BTreeMap::new();
            for gi in 0..self.grasps.len() {
                match self.grasp_fits(arm, gi, &pose, false) {
                    Ok(()) => fits.push(gi),
                    Err(r) => *reasons.entry(r).or_default() += 1,
                }
            }
            let top = reasons
                .into_iter()
                .map(|(r, n)| (r.to_string(), n))
                .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
                .map(|(r, _)| r)
                .unwrap_or_default();
            (fits, top)
        })
    }

    /// The order in which `arm` tries the placements, with grasps among `usable` (best
    /// first): placements and grasps searched together. A placement ranks by how many of
    /// `usable` also fit there ([`Ctx::fitting_at_placement`]), counted up to
    /// [`FITTING_ENOUGH`], then by the candidates' own rank (near the target, stable: paper
    /// §III-B.2). Placements where none fits are counted as rejected and left out. Each
    /// entry holds the placement and its fitting grasps, best first.
    pub(super) fn placement_order(
        &self,
        arm: Arm,
        usable: &[usize],
        picked_at_start: bool,
        report: &mut StrategyReport,
    ) -> Vec<(usize, Vec<usize>, usize)> {
        let fits: Vec<(Vec<usize>, usize, Option<String>)> = (0..self.placements.len())
            .into_par_iter()
            .map(|pi| {
                let here = self.fitting_among(arm, pi, usable);
                // No usable grasp fits: "none fits" (with the most frequent reason) when no
                // grasp of the set does, else "none reaches it".
                let none_fits = (here.is_empty() && !self.any_fits(arm, pi))
                    .then(|| self.fitting_at_placement(arm, pi).1.clone());
                let pose = self.placements[pi].world_from_object;
                // Those the reachability map expects IK for here first, each group in the
                // order of `usable`.
                let mut grasps: Vec<(bool, usize)> = here
                    .into_iter()
                    .map(|g| {
                        let expected = self.reachable(arm, g, &pose)
                            && (!picked_at_start
                                || self.reachable(arm, g, &self.setup.object_start));
                        (!expected, g)
                    })
                    .collect();
                grasps.sort_by_key(|&(unexpected, _)| unexpected);
                let expected = grasps.iter().filter(|(u, _)| !u).count();
                let grasps: Vec<usize> = grasps.into_iter().map(|(_, g)| g).collect();
                (grasps, expected, none_fits)
            })
            .collect();
        let mut order: Vec<(usize, usize, Vec<usize>)> = Vec::new();
        for (pi, (grasps, expected, none_fits)) in fits.into_iter().enumerate() {
            if let Some(why) = none_fits {
                count(report, Stage::Placement).reject(Rejection::NoGraspFits(why).to_string());
            } else if grasps.is_empty() {
                count(report, Stage::Placement).reject(Rejection::NoGraspReaches.to_string());
            } else {
                order.push((pi, expected, grasps));
            }
        }
        order.sort_by_key(|(pi, expected, g)| {
            (
                std::cmp::Reverse((*expected).min(FITTING_ENOUGH)),
                std::cmp::Reverse(g.len().min(FITTING_ENOUGH)),
                *pi,
            )
        });
        order.into_iter().map(|(pi, e, g)| (pi, g, e)).collect()
    }

    /// RIGHT-LEFT or LEFT-RIGHT: picks by arm A down the ranked grasps, gathered
    /// [`HANDOVER_PICKS`] at a time; placements in arm B's [`Ctx::placement_order`]; for
    /// each, the second grasps of arm B that place it and clear A's hand; handover poses
    /// tried with each pick until [`super::PlanOptions::handover_feasible`] are found; the
    /// best scored first through the motions. When a round of picks finds nothing at any
    /// placement, the next round takes the next picks: no count caps the search, only the
    /// strategy's share of the time budget.
    pub(super) fn handover_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.setup.start.clone();
        let pickable = self.fitting_at_start(a, report);
        let all: Vec<usize> = (0..self.grasps.len()).collect();
        let order = self.placement_order(b, &all, false, report);
        let handovers = handover_candidates(self.setup, a, self.options.handover_poses);
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
                                    h * self.grasps[*g1].object_from_tcp.inverse();
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
            .filter(|&g2| !hands_overlap(&self.setup.gripper, &self.grasps[g1], &self.grasps[g2]))
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
pub(super) mod tests {
    use super::super::tests::ctx;
    use super::*;

    /// An empty report of `strategy`.
    pub(in crate::planner) fn report(strategy: Strategy) -> StrategyReport {
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
        // The cheap tests ran; no pick was tried.
        assert!(r.stages.get("pick").is_none_or(|p| p.accepted == 0));
        assert!(!r.stages.contains_key("place"));
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

    /// The paper's order for the scene of `ctx`.
    fn paper_order(ctx: &Ctx<'_>) -> Vec<Strategy> {
        let shoulders = [
            ctx.setup.arm(Arm::Right).shoulder,
            ctx.setup.arm(Arm::Left).shoulder,
        ];
        Strategy::order(
            crate::scene::StrategyChoice::Auto,
            shoulders,
            &(ctx.setup.object_start * ctx.setup.cog),
            &ctx.setup.scene.target_point(),
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
