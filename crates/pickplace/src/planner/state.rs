//! The planner's state for one run of [`super::plan`], in parts that each have one owner
//! (issue 34):
//!
//! | part | what it holds | owner |
//! |---|---|---|
//! | [`Run`] | what is fixed once the candidates are known: setup, options, ranked grasps and placements, the bodies the object starts on | this module, read by all |
//! | [`Budget`] | the time budget, the current strategy's share and the stage timings | `turns` (the shares) |
//! | [`KeyPoseMemo`] | picks, places and the cheap tests at the placements, shared by every strategy | `keypose`, `fits` |
//! | `handover::Memo` | the picking arm and the second grasps at each handover pose | `handover` |
//! | `regrasp::Memo` | the intermediate rests and what the object touches there | `regrasp` |
//!
//! [`Ctx`] joins them; the searchers of the three strategy families (`direct`, `handover`,
//! `regrasp`) are `impl Ctx` blocks in their own modules.

use super::{Memo, PlanOptions, handover, keypose, regrasp};
use crate::contact::supports;
use crate::setup::Setup;
use crate::strategy::Arm;
use pickplace_geometry::math::Real;
use pickplace_grasp::{Grasp, GraspSet};
use pickplace_placement::{Placement, PlacementSet};
use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock};
use std::time::{Duration, Instant};

/// A deadline that is never reached (a century), for budgets no [`Instant`] can hold.
const FAR_FUTURE: Duration = Duration::from_secs(100 * 365 * 86_400);

/// The grasps fitting a hand at a placement (best first) and the most frequent reason of
/// the others.
pub(super) type Fits = (Vec<usize>, String);

/// What is fixed for a run once its candidates are known (paper Fig. 8's first two steps).
pub(super) struct Run<'a> {
    pub setup: &'a Setup,
    pub options: &'a PlanOptions,
    /// Grasps above the quality threshold, best first.
    pub grasps: Vec<Grasp>,
    /// Placement candidates, best first.
    pub placements: Vec<Placement>,
    /// Environment bodies the object touches at the start.
    pub start_supports: Vec<String>,
    /// The start configuration with both hands open: the seed of every place.
    pub open_start: Vec<Real>,
}

/// The time budget of a run ([`PlanOptions::time_budget`]) and what it was spent on.
pub(super) struct Budget {
    /// When planning started.
    pub started: Instant,
    /// When the strategy being searched must stop (its share of the time budget).
    pub deadline: Instant,
    /// The whole budget (s).
    pub total: Real,
    /// Seconds per stage, for the plan's stats.
    pub timings: BTreeMap<String, Real>,
}

impl Budget {
    /// A budget of `total` seconds started at `started`.
    fn new(started: Instant, total: Real, timings: BTreeMap<String, Real>) -> Self {
        // The budget is checked against ranges::TIME_BUDGET; a library caller who skipped
        // the check still gets no panic: a budget no Duration holds has no deadline.
        let budget = Duration::try_from_secs_f64(total.max(0.0)).unwrap_or(Duration::MAX);
        let deadline = started.checked_add(budget).unwrap_or(started + FAR_FUTURE);
        Self {
            started,
            deadline,
            total,
            timings,
        }
    }

    /// Whether the whole budget or the current strategy's share is spent.
    pub fn out_of_time(&self) -> bool {
        self.started.elapsed().as_secs_f64() > self.total || Instant::now() > self.deadline
    }

    /// Gives the next strategy its share of the time left: what is left of the budget
    /// divided by the `remaining` strategies still to try (this one included).
    pub fn share_time(&mut self, remaining: usize) {
        let left = (self.total - self.started.elapsed().as_secs_f64()).max(0.0);
        let share = left / remaining.max(1) as Real;
        self.deadline = Instant::now() + Duration::from_secs_f64(share);
    }
}

/// The key poses every strategy shares, each computed once: picks at the start, places at
/// the placements, and the cheap tests at each placement.
pub(super) struct KeyPoseMemo {
    /// Picks at the start per (arm, grasp).
    pub pick: Mutex<BTreeMap<(Arm, usize), Memo<keypose::Pick>>>,
    /// Places per (arm, placement, grasp).
    pub place: Mutex<BTreeMap<(Arm, usize, usize), Memo<keypose::Place>>>,
    /// Environment bodies the object touches at each placement, found once per placement
    /// (every grasp placing there asks; places run in parallel).
    pub placement_supports: Vec<OnceLock<Vec<String>>>,
    /// Per arm (right, left) and placement: the grasps whose closed gripper fits there
    /// (`Ctx::grasp_fits`), found once.
    pub placement_fits: [Vec<OnceLock<Fits>>; 2],
}

impl KeyPoseMemo {
    fn new(placements: usize) -> Self {
        fn cells<T>(n: usize) -> Vec<OnceLock<T>> {
            (0..n).map(|_| OnceLock::new()).collect()
        }
        Self {
            pick: Mutex::new(BTreeMap::new()),
            place: Mutex::new(BTreeMap::new()),
            placement_supports: cells(placements),
            placement_fits: [cells(placements), cells(placements)],
        }
    }
}

/// One planning run: its fixed inputs, its budget and the memos of the searches.
pub(super) struct Ctx<'a> {
    pub run: Run<'a>,
    pub budget: Budget,
    pub memo: KeyPoseMemo,
    pub handover: handover::Memo,
    pub regrasp: regrasp::Memo,
}

impl<'a> Ctx<'a> {
    /// The context of a run started at `started`: the grasps scoring at least
    /// [`PlanOptions::min_grasp_quality`] of the best, every placement candidate, and the
    /// environment parts the object rests on at its start.
    pub fn new(
        setup: &'a Setup,
        options: &'a PlanOptions,
        started: Instant,
        placement_set: &PlacementSet,
        grasp_set: &GraspSet,
        timings: BTreeMap<String, Real>,
    ) -> Self {
        let best = grasp_set.grasps.first().map_or(0.0, |g| g.score);
        let mut open_start = setup.start.clone();
        for a in &setup.arms {
            a.gripper.set_open(&mut open_start);
        }
        Ctx {
            run: Run {
                setup,
                options,
                grasps: grasp_set
                    .grasps
                    .iter()
                    .filter(|g| g.score >= options.min_grasp_quality * best)
                    .cloned()
                    .collect(),
                placements: placement_set.placements.clone(),
                start_supports: supports(setup, &setup.object_start),
                open_start,
            },
            budget: Budget::new(started, options.time_budget, timings),
            memo: KeyPoseMemo::new(placement_set.placements.len()),
            handover: handover::Memo::default(),
            regrasp: regrasp::Memo::default(),
        }
    }

    /// Whether the whole budget or the current strategy's share is spent.
    pub fn out_of_time(&self) -> bool {
        self.budget.out_of_time()
    }
}
