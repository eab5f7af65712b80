//! The online pick-and-place planner of the paper's Fig. 8 (§III-C), with the manipulation
//! strategies of §III-B.3 and a searched handover.
//!
//! Order of work, cheapest test first so that most candidates are rejected for microseconds.
//! Each step of Fig. 8 has its module:
//!
//! | Fig. 8 step | module |
//! |---|---|
//! | placement candidates on the clicked cluster (Algorithm 2), ranked | [`plan`] (calls `pickplace_placement::candidates`) |
//! | grasp candidates on parallel cluster pairs, ranked; those below [`PlanOptions::min_grasp_quality`] of the best dropped ("if it has good quality we check the collision of the key postures") | [`plan`] (calls `pickplace_grasp`) |
//! | strategies in the paper's order, switching on failure | [`plan`], `search`, `turns` (the time budget's shares) |
//! | key poses: reach, gripper against the environment, IK, collision with the object attached; straight approach, lift, lowering and retreat | `keypose`, `world` |
//! | the handover pose and second grasp (RIGHT-LEFT, LEFT-RIGHT) | `handover` |
//! | PRM motions between the key poses, shortcut | `motion` |
//! | time parameterisation, events and key poses of the plan | `assemble` |
//!
//! Every rejection is counted per strategy and [`Stage`] with its typed [`Rejection`], so a
//! failure says why; a defect of a lower layer is an [`crate::Error`], never a rejection.

mod assemble;
mod handover;
mod keypose;
mod motion;
mod reason;
mod regrasp;
mod search;
mod turns;
mod world;

pub use handover::handover_candidates;
pub use reason::{Attempt, Collision, End, Fail, Rejection, Role, Stage, Step};
pub use regrasp::REST_RADIUS;

use crate::contact::supports;
use crate::error::{Error, Result};
use crate::plan::{StageCount, Stats, StrategyReport};
use crate::scene::StrategyChoice;
use crate::setup::Setup;
use crate::strategy::{Arm, Strategy};
use assemble::Found;
use pickplace_geometry::math::Real;
use pickplace_grasp::{Grasp, GraspSet};
use pickplace_placement::{Placement, PlacementOptions, PlacementSet};
use std::collections::BTreeMap;
use std::sync::{Mutex, OnceLock};
use std::time::Instant;
use turns::{Turns, take_turns};

/// Options of [`plan`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// Seed of every random choice (default: the scene's `planner.seed`, else 1).
    pub seed: u64,
    /// Strategy (default: the scene's, else auto).
    pub strategy: StrategyChoice,
    /// Distance of the pre-grasp and retreat poses from the grasp, along the approach (m)
    /// (default: 0.08).
    pub approach_distance: Real,
    /// Height the object is lifted after the grasp and lowered before the place (m)
    /// (default: 0.10).
    pub lift_height: Real,
    /// Largest step of straight Cartesian motions (m) (default: 0.01).
    pub cartesian_step: Real,
    /// Largest joint change between two steps of a Cartesian motion (rad); more means the IK
    /// jumped to another branch (default: 0.2).
    pub max_joint_step: Real,
    /// Grasps scoring below this fraction of the best are not used (default: 0.2).
    pub min_grasp_quality: Real,
    /// Clearance kept by PRM motions (m) (default: 0.01).
    pub motion_margin: Real,
    /// Picking-hand poses tried for a handover (default: 96); see [`handover_candidates`].
    pub handover_poses: usize,
    /// Feasible handover poses compared before the best is kept (default: 3).
    pub handover_feasible: usize,
    /// Distance from the start or placed pose within which the object may touch the surface
    /// it rests on (m) (default: 0.005).
    pub contact_zone: Real,
    /// Record stage timings in the plan's stats (default: true).
    pub timings: bool,
    /// Wall-clock budget of the whole plan (s): once spent, no further placement or strategy
    /// is started and the failure says so (default: the scene's `planner.time_budget`, else 10).
    /// No count caps the search of placements and grasps: each strategy searches, best first,
    /// until it finds a plan, runs out of candidates, or has spent its share of what is left
    /// of the budget (what is left divided by the strategies still to try), so that a
    /// strategy that cannot succeed does not starve the next. A budget makes the outcome
    /// depend on the machine's speed only when it runs out.
    pub time_budget: Real,
    /// Trajectory sampling period (s) (default: 0.04).
    pub sample_period: Real,
    /// How far (rad, joint space) a motion through free space may cut a corner of its path
    /// (a roadmap vertex, a shortcut's waypoint) on a circular blend, so that the robot does
    /// not stop there; what the blends change is checked again for collisions, and a blend
    /// that collides is tightened (default: 0.1). Straight tool motions blend at most
    /// 0.005 rad and stay within 1 mm of their line.
    pub blend_tolerance: Real,
    /// Fraction of every joint's velocity limit the trajectory uses, in (0, 1] (MoveIt's
    /// velocity scaling factor; default: the scene's `trajectory.velocity_scaling`, else 1).
    pub velocity_scaling: Real,
    /// Fraction of every joint's acceleration limit the trajectory uses, in (0, 1] (default:
    /// the scene's `trajectory.acceleration_scaling`, else 1).
    pub acceleration_scaling: Real,
    /// Fewest and most intermediate resting poses of a regrasp by placing, searched in that
    /// order, fewest first: the shortest sequence of the regrasp graph (default: 1 and 2).
    pub regrasp_rests: (usize, usize),
}

impl PlanOptions {
    /// Refuses options out of range ([`crate::ranges`]): every number, before any work, so
    /// that a library caller gets the CLI's message rather than an overflow.
    ///
    /// # Errors
    /// [`crate::Error::Invalid`] naming the option (and the scene).
    pub fn check(&self, setup: &Setup) -> Result<()> {
        use crate::ranges::{
            PLANNER_ANGLE, PLANNER_DISTANCE, Range, SAMPLE_PERIOD, SCALING, TIME_BUDGET,
        };
        let fraction = Range::closed(0.0, 1.0, "");
        let counts = Range::closed(1.0, 100_000.0, "");
        let checks: [(&str, Real, Range); 13] = [
            ("time_budget", self.time_budget, TIME_BUDGET),
            ("velocity_scaling", self.velocity_scaling, SCALING),
            ("acceleration_scaling", self.acceleration_scaling, SCALING),
            ("sample_period", self.sample_period, SAMPLE_PERIOD),
            ("blend_tolerance", self.blend_tolerance, PLANNER_ANGLE),
            ("max_joint_step", self.max_joint_step, PLANNER_ANGLE),
            (
                "approach_distance",
                self.approach_distance,
                PLANNER_DISTANCE,
            ),
            ("lift_height", self.lift_height, PLANNER_DISTANCE),
            ("motion_margin", self.motion_margin, PLANNER_DISTANCE),
            ("contact_zone", self.contact_zone, PLANNER_DISTANCE),
            ("min_grasp_quality", self.min_grasp_quality, fraction),
            ("handover_poses", self.handover_poses as Real, counts),
            ("handover_feasible", self.handover_feasible as Real, counts),
        ];
        for (field, value, range) in checks {
            range.check(value).map_err(|e| crate::Error::Invalid {
                path: setup.scene_path.clone(),
                field: format!("plan option {field}"),
                reason: e.to_string(),
            })?;
        }
        let bad = |field: &str, reason: &str| crate::Error::Invalid {
            path: setup.scene_path.clone(),
            field: format!("plan option {field}"),
            reason: reason.to_owned(),
        };
        if !(self.cartesian_step > 0.0 && PLANNER_DISTANCE.contains(self.cartesian_step)) {
            return Err(bad("cartesian_step", "must be in (0, 10] m"));
        }
        if self.regrasp_rests.0 > self.regrasp_rests.1 || self.regrasp_rests.1 > 8 {
            return Err(bad(
                "regrasp_rests",
                "must be (fewest, most) with fewest <= most <= 8",
            ));
        }
        Ok(())
    }

    /// The defaults with the scene's seed, strategy and time budget.
    pub fn for_setup(setup: &Setup) -> Self {
        Self {
            seed: setup.scene.planner.seed,
            strategy: setup.scene.planner.strategy,
            time_budget: setup.scene.planner.time_budget,
            velocity_scaling: setup.scaling.0,
            acceleration_scaling: setup.scaling.1,
            ..Self::default()
        }
    }
}

impl Default for PlanOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            strategy: StrategyChoice::Auto,
            approach_distance: 0.08,
            lift_height: 0.10,
            cartesian_step: 0.01,
            max_joint_step: 0.2,
            min_grasp_quality: 0.2,
            motion_margin: 0.01,
            handover_poses: 96,
            handover_feasible: 3,
            contact_zone: 0.005,
            timings: true,
            time_budget: 10.0,
            sample_period: 0.04,
            blend_tolerance: 0.1,
            velocity_scaling: 1.0,
            acceleration_scaling: 1.0,
            regrasp_rests: (1, 2),
        }
    }
}

/// What [`plan`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// A plan.
    Planned(Box<crate::Plan>),
    /// No strategy succeeded: the stats say what was tried and why it failed.
    NoPlan(Failure),
}

/// Why no plan was found.
#[derive(Debug, Clone, PartialEq)]
pub struct Failure {
    /// One line per reason (no placement, per strategy the most frequent rejections).
    pub reasons: Vec<String>,
    /// Counts per strategy and stage.
    pub stats: Stats,
}

/// The grasps fitting a hand at a placement (best first) and the most frequent reason of
/// the others.
type Fits = (Vec<usize>, String);

/// A memoized key pose: the result, or why it was rejected.
type Memo<T> = std::result::Result<T, Rejection>;

/// One planning run: the scene, the options and the candidates every stage shares.
struct Ctx<'a> {
    /// When planning started (for the time budget).
    started: Instant,
    /// When the strategy being searched must stop (its share of the time budget).
    deadline: Instant,
    setup: &'a Setup,
    options: &'a PlanOptions,
    /// Grasps above the quality threshold, best first.
    grasps: Vec<Grasp>,
    /// Placement candidates, best first.
    placements: Vec<Placement>,
    /// Environment bodies the object touches at the start.
    start_supports: Vec<String>,
    /// Environment bodies the object touches at each placement, found once per placement
    /// (every grasp placing there asks; places run in parallel).
    placement_supports: Vec<OnceLock<Vec<String>>>,
    /// Per arm (right, left) and placement: the grasps whose closed gripper fits there
    /// (`Ctx::grasp_fits`), found once.
    placement_fits: [Vec<OnceLock<Fits>>; 2],
    /// The start configuration with both hands open: the seed of every place.
    open_start: Vec<Real>,
    /// Picks at the start per (arm, grasp), shared by the strategies.
    pick_memo: Mutex<BTreeMap<(Arm, usize), Memo<keypose::Pick>>>,
    /// Places per (arm, placement, grasp), shared by the strategies.
    place_memo: Mutex<BTreeMap<(Arm, usize, usize), Memo<keypose::Place>>>,
    /// The picking arm at each handover candidate per first grasp, shared by the placements.
    handover_arm_memo: Mutex<handover::HandoverArmMemo>,
    /// Each second grasp at each handover candidate per first grasp, shared by the placements.
    second_grasp_memo: Mutex<handover::SecondGraspMemo>,
    /// The hands' clearance check, built once (`Ctx::hands_too_close`).
    hand_clearance: OnceLock<Result<Option<crate::rules::HandClearance>>>,
    /// Intermediate resting poses for a regrasp by placing, found once (`Ctx::rests`).
    rests: OnceLock<Vec<Placement>>,
    /// Environment bodies the object touches at each rest, found once.
    rest_supports: OnceLock<Vec<OnceLock<Vec<String>>>>,
    timings: BTreeMap<String, Real>,
}

impl Ctx<'_> {
    fn out_of_time(&self) -> bool {
        self.started.elapsed().as_secs_f64() > self.options.time_budget
            || Instant::now() > self.deadline
    }

    /// Gives the next strategy its share of the time left: what is left of the budget
    /// divided by the `remaining` strategies still to try (this one included).
    fn share_time(&mut self, remaining: usize) {
        let left = (self.options.time_budget - self.started.elapsed().as_secs_f64()).max(0.0);
        let share = left / remaining.max(1) as Real;
        self.deadline = Instant::now() + std::time::Duration::from_secs_f64(share);
    }

    fn finish_stats(&self, stats: &mut Stats, t_all: Instant) {
        if self.options.timings {
            stats.timings = self.timings.clone();
            stats
                .timings
                .insert("total".to_owned(), t_all.elapsed().as_secs_f64());
        }
    }
}

/// The last configuration of a path the planner built.
///
/// # Errors
/// [`Error::Internal`] when the path is empty: every path the planner builds starts at its
/// start configuration, so an empty one is a defect.
fn end_of(path: &[Vec<Real>]) -> Result<&Vec<Real>> {
    path.last().ok_or_else(|| Error::Internal {
        stage: "path",
        reason: "a motion with no configuration".to_owned(),
    })
}

/// The candidate stages' counts for [`Stats::candidates`]: `grasp` (tried = candidates
/// evaluated, accepted = grasps, rejected per reason, whole pairs of surfaces counted as
/// such) and `placement` (over the clusters searched; `far` placements beyond the target's
/// tolerance).
fn candidate_counts(
    placements: &PlacementSet,
    (grasps, hand): (&GraspSet, &BTreeMap<String, usize>),
    far: usize,
) -> BTreeMap<String, StageCount> {
    let mut grasp = StageCount {
        tried: grasps.candidates,
        accepted: grasps.grasps.len(),
        ..StageCount::default()
    };
    for (reason, n) in grasps.rejected.by_reason() {
        grasp.rejected.insert(reason.to_owned(), n);
    }
    for (reason, n) in hand {
        grasp.rejected.insert(reason.clone(), *n);
    }
    let mut placement = StageCount {
        accepted: placements.placements.len(),
        ..StageCount::default()
    };
    for (_, r) in &placements.rejections {
        for (reason, n) in [
            ("did not fit", r.did_not_fit),
            ("unstable", r.unstable),
            ("penetrates the environment", r.penetrates),
        ] {
            if n > 0 {
                *placement.rejected.entry(reason.to_owned()).or_default() += n;
            }
        }
    }
    if far > 0 {
        placement
            .rejected
            .insert("beyond the target's tolerance".to_owned(), far);
    }
    placement.tried = placement.accepted + placement.rejected.values().sum::<usize>();
    BTreeMap::from([
        ("grasp".to_owned(), grasp),
        ("placement".to_owned(), placement),
    ])
}

/// Beyond the target's tolerance, how far (m) placement positions are still searched.
const PLACEMENT_SEARCH_MARGIN: Real = 0.01;

/// A deadline that is never reached (a century), for budgets no [`Instant`] can hold.
const FAR_FUTURE: std::time::Duration = std::time::Duration::from_secs(100 * 365 * 86_400);

/// Fig. 8's first two steps: the placement candidates on the cluster the target selects
/// (Algorithm 2) and the grasp candidates on the object's parallel cluster pairs (§III-B.1),
/// each timed into `timings`.
fn candidates(
    setup: &Setup,
    timings: &mut BTreeMap<String, Real>,
) -> Result<(PlacementSet, GraspSet, usize)> {
    let t = Instant::now();
    let tolerance = setup.scene.target.tolerance();
    // Positions are searched only around the target (the foot of the CoG in the region's
    // plane, which on a region tilted up to `max_slope` is a little farther than its
    // horizontal distance); the exact rule is applied to the candidates below.
    let options = PlacementOptions {
        max_distance: tolerance + PLACEMENT_SEARCH_MARGIN,
        ..PlacementOptions::default()
    };
    let placement_set = pickplace_placement::candidates(
        &setup.placement_object,
        &setup.placement_env,
        &setup.scene.target_point(),
        &options,
    )
    .map_err(|source| Error::Target {
        path: setup.scene_path.clone(),
        source: Box::new(source),
    })?;
    // The object must end within the scene's tolerance of the target (the validator's rule):
    // candidates farther away on the clicked cluster are not offered.
    let mut placement_set = placement_set;
    let before = placement_set.placements.len();
    placement_set
        .placements
        .retain(|p| p.distance_to_target <= tolerance);
    let far = before - placement_set.placements.len();
    timings.insert("placement".to_owned(), t.elapsed().as_secs_f64());
    let t = Instant::now();
    // Planned (or read from the cache) by the setup, once per object and gripper.
    let grasp_set = setup.grasp_set.clone();
    timings.insert("grasp".to_owned(), t.elapsed().as_secs_f64());
    Ok((placement_set, grasp_set, far))
}

impl<'a> Ctx<'a> {
    /// The context of a run started at `started`: the grasps scoring at least
    /// [`PlanOptions::min_grasp_quality`] of the best, every placement candidate, and the
    /// environment parts the object rests on at its start.
    fn new(
        setup: &'a Setup,
        options: &'a PlanOptions,
        started: Instant,
        placement_set: &PlacementSet,
        grasp_set: &GraspSet,
        timings: BTreeMap<String, Real>,
    ) -> Self {
        let best = grasp_set.grasps.first().map_or(0.0, |g| g.score);
        let n = placement_set.placements.len();
        // The budget is checked against ranges::TIME_BUDGET; a library caller who skipped
        // the check still gets no panic: a budget no Duration holds has no deadline.
        let budget = std::time::Duration::try_from_secs_f64(options.time_budget.max(0.0))
            .unwrap_or(std::time::Duration::MAX);
        let deadline = started.checked_add(budget).unwrap_or(started + FAR_FUTURE);
        Ctx {
            started,
            deadline,
            placement_fits: [
                (0..n).map(|_| OnceLock::new()).collect(),
                (0..n).map(|_| OnceLock::new()).collect(),
            ],
            rests: OnceLock::new(),
            rest_supports: OnceLock::new(),
            hand_clearance: OnceLock::new(),
            open_start: {
                let mut q = setup.start.clone();
                for a in &setup.arms {
                    a.gripper.set_open(&mut q);
                }
                q
            },
            pick_memo: Mutex::new(BTreeMap::new()),
            place_memo: Mutex::new(BTreeMap::new()),
            handover_arm_memo: Mutex::new(BTreeMap::new()),
            second_grasp_memo: Mutex::new(BTreeMap::new()),
            setup,
            options,
            grasps: grasp_set
                .grasps
                .iter()
                .filter(|g| g.score >= options.min_grasp_quality * best)
                .cloned()
                .collect(),
            placements: placement_set.placements.clone(),
            placement_supports: placement_set
                .placements
                .iter()
                .map(|_| OnceLock::new())
                .collect(),
            start_supports: supports(setup, &setup.object_start),
            timings,
        }
    }
}

/// Plans the scene (paper Fig. 8): placements on the target's cluster, grasps, then the
/// strategies in the paper's order until one yields a plan.
///
/// # Errors
/// [`Error::StartInCollision`] when the start state is in collision (checked first, naming the
/// pair and the depth), [`Error::ObjectNotResting`] and [`Error::TargetUnusable`] (checked
/// next, `crate::start::check_scene`); [`Error::Target`] when the target point is on no environment cluster;
/// [`Error::Internal`]
/// when a lower layer fails on checked input (the collision library, the motion planner).
/// An infeasible scene is not an error: it is [`Outcome::NoPlan`] with the reasons.
pub fn plan(setup: &Setup, options: &PlanOptions) -> Result<Outcome> {
    options.check(setup)?;
    // The scene, before any search: the start state free, the object resting, the target
    // on a surface; otherwise the scene is infeasible at once.
    crate::start::check_scene(setup)?;
    let t_all = Instant::now();
    let mut timings = BTreeMap::new();
    let target = setup.scene.target_point();
    let (placement_set, grasp_set, far) = candidates(setup, &mut timings)?;
    let mut stats = Stats {
        placement_candidates: placement_set.placements.len(),
        grasp_candidates: grasp_set.grasps.len(),
        candidates: candidate_counts(
            &placement_set,
            (&grasp_set, &setup.grasp_hand_rejections),
            far,
        ),
        ..Stats::default()
    };
    let mut ctx = Ctx::new(setup, options, t_all, &placement_set, &grasp_set, timings);
    let mut reasons = Vec::new();
    if ctx.placements.is_empty() {
        for (cluster, r) in &placement_set.rejections {
            reasons.push(format!(
                "no stable placement on environment cluster {cluster}: {} did not fit, {} unstable, {} penetrate",
                r.did_not_fit, r.unstable, r.penetrates
            ));
        }
        if far > 0 {
            reasons.push(format!(
                "no stable placement within {:.0} mm of the target ({far} farther away; target.tolerance)",
                setup.scene.target.tolerance() * 1e3
            ));
        }
        if reasons.is_empty() {
            reasons.push("no stable placement near the target".to_owned());
        }
    }
    if ctx.grasps.is_empty() {
        reasons.push(if grasp_set.pairs == 0 {
            "no grasp: the object has no two opposite surfaces the fingers can hold (no finger-contact cluster pair; planner.h_max_finger, docs/grasp.md)".to_owned()
        } else {
            let hand: Vec<String> = setup
                .grasp_hand_rejections
                .iter()
                .map(|(reason, n)| format!("{reason} ×{n}"))
                .collect();
            format!(
                "no grasp: {} candidates on {} cluster pairs, all rejected ({}{}{})",
                grasp_set.candidates,
                grasp_set.pairs,
                grasp_set.rejected,
                if hand.is_empty() { "" } else { ", " },
                hand.join(", ")
            )
        });
    }
    if !reasons.is_empty() {
        ctx.finish_stats(&mut stats, t_all);
        return Ok(Outcome::NoPlan(Failure { reasons, stats }));
    }
    let shoulders = [
        setup.arm(Arm::Right).shoulder,
        setup.arm(Arm::Left).shoulder,
    ];
    let start_point = setup.object_start * setup.cog;
    let order = Strategy::order(options.strategy, shoulders, &start_point, &target);
    // A single-arm robot: the strategies that need the other arm do not apply.
    let (order, skipped): (Vec<Strategy>, Vec<Strategy>) = order
        .into_iter()
        .partition(|s| setup.has_arm(s.pick_arm()) && setup.has_arm(s.place_arm()));
    for strategy in skipped {
        let missing = [strategy.pick_arm(), strategy.place_arm()]
            .into_iter()
            .find(|&a| !setup.has_arm(a))
            .unwrap_or(strategy.pick_arm());
        reasons.push(format!(
            "{strategy}: does not apply: the robot has no {missing} arm (it has one arm, {} {:?})",
            setup.arms[0].arm, setup.arms[0].group
        ));
    }
    // A close call of the paper's nearer-hand rule: the one-arm strategy probed first
    // (`Ctx::direct_first`); its full search comes in its turn, which counts every candidate
    // again, so a probe that finds nothing is not reported.
    let probe = ctx.direct_first(&order);
    let failed = match take_turns(&mut ctx, probe, order, options.time_budget, &mut reasons)? {
        Turns::Found(found) => return ctx.finish_plan(found, stats, t_all),
        Turns::Failed(failed) => failed,
    };
    for (strategy, report) in failed {
        reasons.push(format!("{strategy}: {}", summarize(&report)));
        stats.strategies.push(report);
    }
    ctx.finish_stats(&mut stats, t_all);
    Ok(Outcome::NoPlan(Failure { reasons, stats }))
}

impl Ctx<'_> {
    /// Searches one strategy (`probe`: the nearer hand's quick first look,
    /// [`Ctx::direct_first`]); the plan's pieces when it finds one, else its report.
    fn run_strategy(
        &mut self,
        strategy: Strategy,
        probe: bool,
    ) -> Result<std::result::Result<(Strategy, Found, StrategyReport), StrategyReport>> {
        let t = Instant::now();
        let mut report = StrategyReport {
            strategy,
            success: false,
            stages: BTreeMap::new(),
        };
        let found = if probe {
            self.single_arm_search(strategy.pick_arm(), &mut report, true)?
        } else if strategy.has_regrasp() {
            self.regrasp_strategy(strategy, &mut report)?
        } else if strategy.has_handover() {
            self.handover_strategy(strategy, &mut report)?
        } else {
            self.single_arm_strategy(strategy.pick_arm(), &mut report)?
        };
        let what = if probe { "probe" } else { "strategy" };
        self.timings.insert(
            format!("{what} {}", strategy.name()),
            t.elapsed().as_secs_f64(),
        );
        Ok(match found {
            Some(found) => {
                report.success = true;
                Ok((strategy, found, report))
            }
            None => Err(report),
        })
    }

    /// The plan of a strategy that found one.
    fn finish_plan(
        &mut self,
        (strategy, found, report): (Strategy, Found, StrategyReport),
        mut stats: Stats,
        t_all: Instant,
    ) -> Result<Outcome> {
        stats.strategies.push(report);
        let plan = self.assemble(strategy, found, stats, t_all)?;
        Ok(Outcome::Planned(Box::new(plan)))
    }
}

/// The most frequent rejections of a strategy, for the failure message: per stage (in name
/// order) the counts and the three most frequent reasons.
fn summarize(report: &StrategyReport) -> String {
    let mut parts = Vec::new();
    for (stage, count) in &report.stages {
        let mut reasons: Vec<_> = count.rejected.iter().collect();
        reasons.sort_by(|a, b| b.1.cmp(a.1).then(a.0.cmp(b.0)));
        let top: Vec<String> = reasons
            .iter()
            .take(3)
            .map(|(r, n)| format!("{r} ×{n}"))
            .collect();
        let top = if top.is_empty() {
            String::new()
        } else {
            format!(" ({})", top.join(", "))
        };
        parts.push(format!(
            "{stage} {}/{} passed{top}",
            count.accepted, count.tried
        ));
    }
    if parts.is_empty() {
        "nothing tried".to_owned()
    } else {
        parts.join("; ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A planning context on a shipped scene, as [`plan`] builds it (default options).
    pub(super) fn ctx(scene: &str) -> Ctx<'static> {
        let setup = crate::testing::setup(scene);
        let options: &'static PlanOptions = Box::leak(Box::new(PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        }));
        let (placements, grasps, _) = candidates(setup, &mut BTreeMap::new()).expect("candidates");
        Ctx::new(
            setup,
            options,
            Instant::now(),
            &placements,
            &grasps,
            BTreeMap::new(),
        )
    }

    #[test]
    fn the_summary_lists_stages_with_their_three_most_frequent_reasons() {
        let mut report = StrategyReport {
            strategy: Strategy::LeftLeft,
            success: false,
            stages: BTreeMap::new(),
        };
        assert_eq!(summarize(&report), "nothing tried");
        let pick = reason::count(&mut report, Stage::Pick);
        pick.accept();
        for (r, n) in [("a", 1), ("b", 5), ("c", 3), ("d", 3)] {
            for _ in 0..n {
                pick.reject(r);
            }
        }
        reason::count(&mut report, Stage::Placement).reject(Rejection::NoGraspReaches.to_string());
        assert_eq!(
            summarize(&report),
            "pick 1/13 passed (b ×5, c ×3, d ×3); placement 0/1 passed (no grasp reaches it ×1)"
        );
    }

    #[test]
    fn the_same_seed_gives_the_same_plan_and_another_seed_still_plans() {
        let setup = crate::testing::setup("fig9-near.toml");
        let options = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(setup)
        };
        let one = plan(setup, &options).expect("no defect");
        let two = plan(setup, &options).expect("no defect");
        assert_eq!(one, two);
        let Outcome::Planned(p) = one else {
            panic!("the near scene plans")
        };
        assert_eq!(p.strategy, Strategy::RightRight);
        assert!(p.stats.timings.is_empty());
    }

    #[test]
    fn a_strategy_not_started_for_lack_of_time_is_said() {
        let setup = crate::testing::setup("fig9-near.toml");
        let options = PlanOptions {
            time_budget: 0.0,
            ..PlanOptions::for_setup(setup)
        };
        let Outcome::NoPlan(f) = plan(setup, &options).expect("no defect") else {
            panic!("no time, no plan")
        };
        assert!(
            f.reasons
                .iter()
                .all(|r| r.contains("the time budget of 0 s is spent")),
            "{:?}",
            f.reasons
        );
        assert!(f.stats.timings.contains_key("total"));
    }
}
