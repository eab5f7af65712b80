//! Regrasp by placing: when no direct strategy and no handover works, or the robot has one
//! arm, the object is put down in an intermediate stable pose and picked up again with another
//! grasp. This is the successor of the paper's planner (Wan and Harada, "Developing and
//! Comparing Single-arm and Dual-arm Regrasp", and Harada's regrasp graph): a graph whose
//! nodes are (resting pose, arm, grasp) triples and whose edges are transfers (one hand
//! carries the object from one resting pose to another with one grasp) and regrasps (at an
//! intermediate resting pose, the hand lets go and a hand takes another grasp). The plan is
//! the shortest sequence of transfers from the start to a placement at the target.
//!
//! Sequences with no intermediate pose are the direct strategies (RIGHT-RIGHT, LEFT-LEFT,
//! [`super::search`]); this module searches the next shortest, with one intermediate pose:
//! start →(arm A, grasp g₁)→ rest k →(arm B, grasp g₂)→ placement, and when none works, those
//! with two: start →(A, g₁)→ rest k₁ →(B, g₂)→ rest k₂ →(B, g₃)→ placement
//! ([`super::PlanOptions::regrasp_rests`]). The graph is evaluated
//! lazily, cheapest test first, as the paper's planner does for its key poses: edges are first
//! kept by the cheap tests of [`Ctx::grasp_fits`] (reach, gripper against the environment),
//! then checked by IK and collision (pick, put down, pick again, place), and last joined by
//! motions. Every expensive result is computed once.

use super::Ctx;
use super::assemble::Found;
use super::keypose::{Pick, Place};
use super::reason::{Rejection, Stage, count, split};
use crate::contact::supports;
use crate::error::Result;
use crate::plan::StrategyReport;
use crate::strategy::{Arm, Strategy};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector2};
use pickplace_placement::{Placement, PlacementOptions};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::collections::btree_map::Entry;
use std::sync::OnceLock;

/// Radius (m) around the object's start within which intermediate resting poses are sought
/// on the surfaces there.
pub const REST_RADIUS: Real = 0.15;

/// How far (m) the third anchor of the rests lies from halfway, towards the robot's base.
const REST_INWARD: Real = 0.10;

/// Spacing (m) of the positions searched for rests.
const REST_POSITION_STEP: Real = 0.02;

/// Salt of the random choices at intermediate resting poses (distinct from the placements').
const REST_SALT: u64 = 1 << 62;

impl Ctx<'_> {
    /// The intermediate resting poses (computed once): stable placements (paper §III-B.2,
    /// Algorithm 2 with every resting face) on the surface the object starts on, within
    /// [`REST_RADIUS`] of its start, then within [`REST_RADIUS`] of the point halfway to the
    /// target on that surface (where both arms reach when one hand picks and the other
    /// places), then of that point drawn [`REST_INWARD`] towards the robot's base (where
    /// both reach down when start and target lie far out on either side); the start pose
    /// itself and duplicates left out.
    pub(super) fn rests(&self) -> &[Placement] {
        self.rests.get_or_init(|| {
            let setup = self.setup;
            let start = setup.object_start;
            // Where the object stands: below its centre of mass, at its lowest point.
            let lowest = setup
                .object_mesh
                .vertices()
                .iter()
                .map(|v| (start * v).z)
                .fold(Real::INFINITY, Real::min);
            let cog = start * setup.cog;
            let target = setup.scene.target_point();
            let half = Point3::new(0.5 * (cog.x + target.x), 0.5 * (cog.y + target.y), lowest);
            // Halfway drawn towards the robot's base by REST_INWARD: far out on both sides,
            // the hands reach down to the middle only nearer the robot (the suite's stone
            // from far left to far right is put down 10 cm in from halfway).
            let base = setup.world_from_root.translation.vector;
            let inward = Vector2::new(base.x - half.x, base.y - half.y);
            let step = REST_INWARD.min(inward.norm());
            let inward = inward.try_normalize(1e-12).unwrap_or_else(Vector2::zeros) * step;
            let anchors = [
                Point3::new(cog.x, cog.y, lowest),
                half,
                Point3::new(half.x + inward.x, half.y + inward.y, lowest),
            ];
            // A rest needs a few stable poses per resting face near the anchor, not the
            // exhaustive search of the target's cluster: a small effort bounds its cost on
            // large tables and objects with many faces.
            let options = PlacementOptions {
                search_radius: REST_RADIUS,
                max_per_pair: 4,
                edge_segments: 2,
                edge_positions: 8,
                max_candidates: 48,
                max_distance: REST_RADIUS,
                // A rest need not be at a precise point: a coarse grid of positions and yaws
                // finds its few poses among obstacles in a sixteenth of the tests.
                position_step: REST_POSITION_STEP,
                yaw_steps: 8,
                ..PlacementOptions::default()
            };
            let mut rests: Vec<Placement> = Vec::new();
            for anchor in &anchors {
                let Ok(set) = pickplace_placement::candidates(
                    &setup.placement_object,
                    &setup.placement_env,
                    anchor,
                    &options,
                ) else {
                    continue;
                };
                for p in set.placements {
                    let same = |q: &Isometry3| {
                        (p.world_from_object.translation.vector - q.translation.vector).norm()
                            <= 0.01
                            && p.world_from_object.rotation.angle_to(&q.rotation)
                                <= 5f64.to_radians()
                    };
                    if !same(&start) && !rests.iter().any(|r| same(&r.world_from_object)) {
                        rests.push(p);
                    }
                }
            }
            rests
        })
    }

    /// The bodies the object touches at rest `k`, found once.
    pub(super) fn rest_supports(&self, k: usize) -> &[String] {
        let all = self
            .rest_supports
            .get_or_init(|| self.rests().iter().map(|_| OnceLock::new()).collect());
        match all.get(k) {
            Some(cell) => {
                cell.get_or_init(|| supports(self.setup, &self.rests()[k].world_from_object))
            }
            None => &[],
        }
    }

    /// Regrasp by placing with `strategy` (`right-place-right`, `right-place-left`, …): arm A
    /// picks the object with grasp g₁, puts it down at an intermediate rest k, arm B picks it
    /// up with grasp g₂ (another grasp when A = B) and places it at the target. Placements in
    /// arm B's order ([`Ctx::placement_order`]); rests by how many grasps fit both hands
    /// there; grasps best first. The search stops at the first candidate whose motions join,
    /// or when the strategy's share of the time budget is spent.
    pub(super) fn regrasp_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.setup.start.clone();
        let pickable = self.fitting_at_start(a, report);
        if pickable.is_empty() {
            return Ok(None);
        }
        let all: Vec<usize> = (0..self.grasps.len()).collect();
        let finals = self.placement_order(b, &all, false, report);
        if finals.is_empty() {
            return Ok(None);
        }
        let t = std::time::Instant::now();
        let n_rests = self.rests().len();
        if self.options.timings && !self.timings.contains_key("rests") {
            self.timings
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
            let enough = super::search::FITTING_ENOUGH;
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
        let (fewest, most) = self.options.regrasp_rests;
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
            for chunk in seconds.chunks(super::search::PARALLEL_CHUNK) {
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
                        for chunk in firsts.chunks(super::search::PARALLEL_CHUNK) {
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

    /// The next shortest sequences of the regrasp graph, through two intermediate rests:
    /// start →(A, g₁)→ rest k₁ →(B, g₂)→ rest k₂ →(B, g₃)→ placement, searched when no
    /// sequence through one rest works (or when asked for, [`super::PlanOptions::regrasp_rests`]).
    /// B's places at the target first (the most constrained leg), then the rests k₂ where B
    /// picks up with g₃, the rests k₁ where A puts the object down, B's grasps g₂ that pick it
    /// up at k₁ and put it down at k₂, and last A's grasps g₁ and the motions. Every key pose is
    /// computed once; the search stops at the first sequence whose motions join, or when the
    /// strategy's share of the time budget is spent.
    fn regrasp_two_rests(
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
                                    let lifted = super::end_of(&first_up.lift)?;
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
                            for chunk in firsts.chunks(super::search::PARALLEL_CHUNK) {
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

    /// B's pick-up of the object at rest `k` with grasp `g` (computed once, counted under
    /// the regrasp stage); `None` when it fails.
    fn pick_up(
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
}

/// What the two-rest search works on: the strategy, the start (and with both hands open),
/// the placements in B's order with the grasps that fit there, and per rest the grasps A puts
/// the object down with and those B picks it up with.
struct TwoRests<'s> {
    strategy: Strategy,
    start: &'s [Real],
    open_start: &'s [Real],
    finals: &'s [(usize, Vec<usize>, usize)],
    rest_edges: &'s [(usize, Vec<usize>, Vec<usize>)],
}

/// The key poses of a sequence through two rests, checked: A's pick at the start and put-down
/// at rest k₁ with g₁; B's pick-up at k₁ and put-down at k₂ with g₂; B's pick-up at k₂ and
/// place at placement `pi` with g₃.
pub(super) struct TwoRestLegs<'l> {
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

/// Memos of a regrasp search: A's picks at the start per grasp, and A's put-downs per
/// (rest, grasp).
type PutDownMemos<'m> = (
    &'m mut BTreeMap<usize, std::result::Result<Pick, Rejection>>,
    &'m mut BTreeMap<(usize, usize), std::result::Result<Place, Rejection>>,
);

impl Ctx<'_> {
    /// Whether A can put the object down at rest `k` with one of the grasps `down` (A's picks
    /// and put-downs computed a chunk at a time, until one works or the time is spent).
    fn can_put_down(
        &self,
        a: Arm,
        k: usize,
        down: &[usize],
        (picks, downs): PutDownMemos<'_>,
        report: &mut StrategyReport,
    ) -> Result<bool> {
        for chunk in down.chunks(super::search::PARALLEL_CHUNK) {
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
    fn put_downs(
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
                    Ok(p) => Some(super::end_of(&p.lift).map(|lifted| {
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

/// The key poses of one regrasp sequence, checked: arm A's pick at the start and put-down at
/// rest `k` with grasp `g1`; arm B's pick at the rest and place at placement `pi` with `g2`.
pub(super) struct RegraspLegs<'l> {
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

/// Counts a key-pose result under `stage`.
fn tally<T>(report: &mut StrategyReport, stage: Stage, r: &std::result::Result<T, Rejection>) {
    match r {
        Ok(_) => count(report, stage).accept(),
        Err(r) => count(report, stage).reject(r.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::super::search::tests::report;
    use super::super::tests::ctx;
    use super::*;
    use crate::strategy::Arm;

    #[test]
    fn rests_lie_near_the_start_on_its_table_and_leave_the_start_pose_out() {
        let ctx = ctx("fig9-near.toml");
        let start = ctx.setup.object_start;
        let rests = ctx.rests();
        assert!(!rests.is_empty());
        for r in rests {
            let d = r.world_from_object.translation.vector - start.translation.vector;
            assert!(d.xy().norm() <= REST_RADIUS + 0.05, "{d:?}");
            assert!(
                d.xy().norm() > 0.01
                    || r.world_from_object.rotation.angle_to(&start.rotation) > 0.08
            );
        }
    }

    #[test]
    fn the_right_hand_puts_the_can_down_and_picks_it_up_again() {
        let mut ctx = ctx("fig9-near.toml");
        let mut r = report(Strategy::RightPlaceRight);
        let found = ctx
            .regrasp_strategy(Strategy::RightPlaceRight, &mut r)
            .expect("no defect")
            .expect("a regrasp plan");
        assert_eq!(found.rests.len(), 1);
        assert_eq!(found.grasps.len(), 2);
        assert!(found.grasps.iter().all(|(a, _)| *a == Arm::Right));
        assert_ne!(found.grasps[0].1, found.grasps[1].1, "another grasp");
        let keys: Vec<&str> = found
            .segments
            .iter()
            .filter_map(|s| s.key.map(|k| k.0))
            .collect();
        for k in [
            "pre-grasp",
            "grasp",
            "lift",
            "pre-rest",
            "rest",
            "release-rest",
            "retreat-rest",
            "pre-regrasp",
            "regrasp",
            "lift-again",
            "pre-place",
            "place",
            "release",
            "retreat",
        ] {
            assert!(keys.contains(&k), "{k} missing from {keys:?}");
        }
        // Two grasps and two releases, alternating: the object is never held by two hands.
        let events: Vec<_> = found
            .segments
            .iter()
            .filter_map(|s| s.event.map(|e| (e.0, e.1)))
            .collect();
        use crate::plan::EventKind::{Grasp, Release};
        assert_eq!(
            events,
            [
                (Grasp, Arm::Right),
                (Release, Arm::Right),
                (Grasp, Arm::Right),
                (Release, Arm::Right)
            ]
        );
    }

    #[test]
    fn a_regrasp_plan_passes_the_validator_and_lists_its_rest() {
        let setup = crate::testing::setup("fig9-near.toml");
        let options = super::super::PlanOptions {
            strategy: crate::scene::StrategyChoice::LeftPlaceRight,
            timings: false,
            ..super::super::PlanOptions::for_setup(setup)
        };
        let super::super::Outcome::Planned(plan) =
            super::super::plan(setup, &options).expect("no defect")
        else {
            panic!("the left hand puts the can down for the right")
        };
        assert_eq!(plan.strategy, Strategy::LeftPlaceRight);
        assert_eq!(plan.rests.len(), 1);
        assert_eq!(plan.grasps[0].arm, Arm::Left);
        assert_eq!(plan.grasps[1].arm, Arm::Right);
        let report = crate::validate::validate(setup, &plan, std::path::Path::new("plan.json"))
            .expect("checks");
        assert!(report.problems.is_empty(), "{:?}", report.problems);
        // The object rests where the plan says between the release and the second grasp.
        let rest = plan.rests[0]
            .world_from_object
            .to_isometry()
            .expect("a pose");
        let released = plan
            .key_poses
            .iter()
            .find(|k| k.name == "release-rest")
            .expect("a release at the rest");
        let there = released.world_from_object.to_isometry().expect("a pose");
        assert!((there.translation.vector - rest.translation.vector).norm() < 1e-3);
    }

    /// The regrasp graph's next shortest sequences: through two rests, when asked for (the
    /// planner searches them when no sequence through one rest works). The plan lists both
    /// rests and three grasps, and the validator checks every release and resting pose.
    #[test]
    fn a_sequence_through_two_rests_passes_the_validator() {
        let setup = crate::testing::setup("fig9-near.toml");
        let options = super::super::PlanOptions {
            strategy: crate::scene::StrategyChoice::RightPlaceRight,
            timings: false,
            regrasp_rests: (2, 2),
            ..super::super::PlanOptions::for_setup(setup)
        };
        let super::super::Outcome::Planned(plan) =
            super::super::plan(setup, &options).expect("no defect")
        else {
            panic!("the right hand puts the can down twice")
        };
        assert_eq!(plan.strategy, Strategy::RightPlaceRight);
        assert_eq!(plan.rests.len(), 2);
        assert_eq!(plan.grasps.len(), 3);
        assert!(plan.grasps.iter().all(|g| g.arm == Arm::Right));
        let report = crate::validate::validate(setup, &plan, std::path::Path::new("plan.json"))
            .expect("checks");
        assert!(report.problems.is_empty(), "{:?}", report.problems);
        // Three grasps and three releases, alternating, and the object at each rest between.
        use crate::plan::EventKind::{Grasp, Release};
        let kinds: Vec<_> = plan.events.iter().map(|e| e.kind).collect();
        assert_eq!(kinds, [Grasp, Release, Grasp, Release, Grasp, Release]);
        let released: Vec<_> = plan
            .key_poses
            .iter()
            .filter(|k| k.name == "release-rest")
            .collect();
        assert_eq!(released.len(), 2);
        for (k, rest) in released.iter().zip(&plan.rests) {
            let there = k.world_from_object.to_isometry().expect("a pose");
            let rest = rest.world_from_object.to_isometry().expect("a pose");
            assert!((there.translation.vector - rest.translation.vector).norm() < 1e-3);
        }
        // Same seed, same plan.
        let super::super::Outcome::Planned(again) =
            super::super::plan(setup, &options).expect("no defect")
        else {
            panic!("plans again")
        };
        assert_eq!(again, plan);
    }
}
