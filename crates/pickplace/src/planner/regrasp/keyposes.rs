//! The key poses at the intermediate rests, each computed once and shared by the one- and
//! two-rest searches: A's picks at the start and put-downs at a rest, B's pick-ups there.

use super::{REST_SALT, tally};
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::planner::fits::PARALLEL_CHUNK;
use crate::planner::keypose::{Pick, Place};
use crate::planner::reason::{Rejection, Stage, split};
use crate::planner::{Ctx, end_of};
use crate::strategy::Arm;
use pickplace_geometry::math::Real;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::collections::btree_map::Entry;

/// Memos of a regrasp search: A's picks at the start per grasp, and A's put-downs per
/// (rest, grasp).
pub(super) type PutDownMemos<'m> = (
    &'m mut BTreeMap<usize, std::result::Result<Pick, Rejection>>,
    &'m mut BTreeMap<(usize, usize), std::result::Result<Place, Rejection>>,
);

impl Ctx<'_> {
    /// B's pick-up of the object at rest `k` with grasp `g` (computed once, counted under
    /// the regrasp stage); `None` when it fails.
    pub(super) fn pick_up(
        &self,
        b: Arm,
        k: usize,
        g: usize,
        open_start: &[Real],
        ups: &mut BTreeMap<(usize, usize), std::result::Result<Pick, Rejection>>,
        report: &mut StrategyReport,
    ) -> Result<Option<Pick>> {
        if let Some(r) = ups.get(&(k, g)) {
            return Ok(r.as_ref().ok().cloned());
        }
        let rest_pose = self.rests()[k].world_from_object;
        let r = split(self.pick_at(
            b,
            g,
            &rest_pose,
            self.rest_supports(k),
            open_start,
            1 + k as u64,
        ))?;
        tally(report, Stage::Regrasp, &r);
        let out = r.as_ref().ok().cloned();
        ups.insert((k, g), r);
        Ok(out)
    }

    /// Whether A can put the object down at rest `k` with one of the grasps `down` (A's picks
    /// and put-downs computed a chunk at a time, until one works or the time is spent).
    pub(super) fn can_put_down(
        &self,
        a: Arm,
        k: usize,
        down: &[usize],
        (picks, downs): PutDownMemos<'_>,
        report: &mut StrategyReport,
    ) -> Result<bool> {
        for chunk in down.chunks(PARALLEL_CHUNK) {
            if self.out_of_time() {
                break;
            }
            self.put_downs(a, k, chunk, (&mut *picks, &mut *downs), report)?;
            if chunk
                .iter()
                .any(|g1| matches!(downs.get(&(k, *g1)), Some(Ok(_))))
            {
                return Ok(true);
            }
        }
        Ok(false)
    }

    /// A's picks and put-downs at rest `k` with the grasps of `chunk` not computed yet, on
    /// the thread pool; each result counted once, under its stage.
    pub(super) fn put_downs(
        &self,
        a: Arm,
        k: usize,
        chunk: &[usize],
        (picks, downs): PutDownMemos<'_>,
        report: &mut StrategyReport,
    ) -> Result<()> {
        let rest_pose = self.rests()[k].world_from_object;
        let todo: Vec<usize> = chunk
            .iter()
            .copied()
            .filter(|&g1| !downs.contains_key(&(k, g1)))
            .collect();
        let computed: Vec<_> = todo
            .par_iter()
            .map(|&g1| {
                let pick = self.pick(a, g1);
                let down = match &pick {
                    Ok(p) => Some(end_of(&p.lift).map(|lifted| {
                        self.place_at(
                            a,
                            g1,
                            &rest_pose,
                            self.rest_supports(k),
                            lifted,
                            REST_SALT | (k as u64) << 20,
                        )
                    })),
                    Err(_) => None,
                };
                (g1, pick, down)
            })
            .collect();
        for (g1, pick, down) in computed {
            if let Entry::Vacant(slot) = picks.entry(g1) {
                let r = split(pick)?;
                tally(report, Stage::Pick, &r);
                slot.insert(r);
            }
            if let Some(down) = down {
                let r = split(down?)?;
                tally(report, Stage::Rest, &r);
                downs.insert((k, g1), r);
            }
        }
        Ok(())
    }
}
