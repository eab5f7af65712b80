//! The cheap tests that order every strategy's search (paper Fig. 8: "if it has good
//! quality we check the collision of the key postures"): which grasps fit a hand at the
//! start and at each placement (reach, gripper clear of the environment), what the
//! reachability maps expect, and the order in which a hand tries the placements.

use super::Ctx;
use super::reason::{Rejection, Stage, count};
use crate::plan::StrategyReport;
use crate::strategy::Arm;
use pickplace_geometry::math::Isometry3;
use rayon::prelude::*;
use std::collections::BTreeMap;

/// Candidates evaluated together on the thread pool (results are used in rank order, so the
/// outcome does not depend on the thread count).
pub(super) const PARALLEL_CHUNK: usize = 16;

/// Grasps fitting at a placement counted for its rank: beyond this many, placements rank by
/// the paper's criteria alone.
pub(super) const FITTING_ENOUGH: usize = 8;

impl Ctx<'_> {
    /// The grasps `arm` can take the object with at its start by the cheap tests
    /// ([`Ctx::grasp_fits`], open gripper), best first; the others are counted as rejected
    /// picks with their reason.
    pub(super) fn fitting_at_start(&self, arm: Arm, report: &mut StrategyReport) -> Vec<usize> {
        let results: Vec<_> = (0..self.run.grasps.len())
            .into_par_iter()
            .map(|gi| self.grasp_fits(arm, gi, &self.run.setup.object_start, true))
            .collect();
        let mut out = Vec::new();
        for (gi, r) in results.into_iter().enumerate() {
            match r {
                Ok(()) => out.push(gi),
                Err(r) => count(report, Stage::Pick).reject(r.to_string()),
            }
        }
        // Those the reachability map expects IK for first, each group in rank order.
        out.sort_by_key(|&gi| !self.reachable(arm, gi, &self.run.setup.object_start));
        out
    }

    /// Whether `arm`'s reachability map ([`crate::reach::ReachMap`]) expects IK for grasp
    /// `gi` with the object at `world_from_object`: a guess that orders the search, never a
    /// reason to skip a candidate.
    pub(super) fn reachable(&self, arm: Arm, gi: usize, world_from_object: &Isometry3) -> bool {
        let a = self.run.setup.arm(arm);
        let root_from_tcp = self.run.setup.world_from_root.inverse()
            * world_from_object
            * self.run.grasps[gi].object_from_tcp;
        a.reach_map.score(&root_from_tcp) > 0
    }

    /// Those of `grasps` (in their order) whose closed gripper fits `arm` at placement `pi`:
    /// [`Ctx::fitting_at_placement`] when it is known, else each of them tested (a one-arm
    /// search asks about the few grasps that pick the object, not the thousand of a
    /// scanned object's set).
    pub(super) fn fitting_among(&self, arm: Arm, pi: usize, grasps: &[usize]) -> Vec<usize> {
        if let Some((fits, _)) = self.memo.placement_fits[arm.index()][pi].get() {
            return grasps
                .iter()
                .copied()
                .filter(|g| fits.binary_search(g).is_ok())
                .collect();
        }
        let pose = self.run.placements[pi].world_from_object;
        grasps
            .iter()
            .copied()
            .filter(|&g| self.grasp_fits(arm, g, &pose, false).is_ok())
            .collect()
    }

    /// Whether any grasp's closed gripper fits `arm` at placement `pi`: the first that fits
    /// answers, without [`Ctx::fitting_at_placement`]'s full count.
    fn any_fits(&self, arm: Arm, pi: usize) -> bool {
        if let Some((fits, _)) = self.memo.placement_fits[arm.index()][pi].get() {
            return !fits.is_empty();
        }
        let pose = self.run.placements[pi].world_from_object;
        (0..self.run.grasps.len()).any(|g| self.grasp_fits(arm, g, &pose, false).is_ok())
    }

    /// The grasps whose closed gripper fits `arm` at placement `pi` ([`Ctx::grasp_fits`]),
    /// best first, and the most frequent reason of the others; computed once per arm and
    /// placement.
    pub(super) fn fitting_at_placement(&self, arm: Arm, pi: usize) -> &(Vec<usize>, String) {
        self.memo.placement_fits[arm.index()][pi].get_or_init(|| {
            let pose = self.run.placements[pi].world_from_object;
            let mut fits = Vec::new();
            // Counted by value, named once (a thousand grasps at each of a hundred placements).
            let mut reasons: BTreeMap<Rejection, usize> = BTreeMap::new();
            for gi in 0..self.run.grasps.len() {
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
        let fits: Vec<(Vec<usize>, usize, Option<String>)> = (0..self.run.placements.len())
            .into_par_iter()
            .map(|pi| {
                let here = self.fitting_among(arm, pi, usable);
                // No usable grasp fits: "none fits" (with the most frequent reason) when no
                // grasp of the set does, else "none reaches it".
                let none_fits = (here.is_empty() && !self.any_fits(arm, pi))
                    .then(|| self.fitting_at_placement(arm, pi).1.clone());
                let pose = self.run.placements[pi].world_from_object;
                // Those the reachability map expects IK for here first, each group in the
                // order of `usable`.
                let mut grasps: Vec<(bool, usize)> = here
                    .into_iter()
                    .map(|g| {
                        let expected = self.reachable(arm, g, &pose)
                            && (!picked_at_start
                                || self.reachable(arm, g, &self.run.setup.object_start));
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
}
