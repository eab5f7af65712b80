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
//! | strategies in the paper's order, switching on failure | [`plan`], `turns` (the time budget's shares) |
//! | the cheap tests that order every search: grasps fitting a hand at the start and at each placement, the placements' order | `fits` |
//! | the direct strategies (RIGHT-RIGHT, LEFT-LEFT) | `direct` |
//! | key poses: reach, gripper against the environment, IK, collision with the object attached; straight approach, lift, lowering and retreat | `keypose`, `world` |
//! | the handover pose and second grasp (RIGHT-LEFT, LEFT-RIGHT) and their search | `handover` |
//! | regrasp by placing (one or two intermediate rests) | `regrasp` |
//! | PRM motions between the key poses, shortcut | `motion` |
//! | time parameterisation, events and key poses of the plan | `assemble` |
//!
//! One run's state is split by owner (`state`): what is fixed once the candidates are known,
//! the time budget, the key poses' memo every strategy shares, and each strategy family's
//! own memo (handover, regrasp); [`PlanOptions`] are in `options`.
//!
//! Every rejection is counted per strategy and [`Stage`] with its typed [`Rejection`], so a
//! failure says why; a defect of a lower layer is an [`crate::Error`], never a rejection.

mod assemble;
mod direct;
mod fits;
mod handover;
mod keypose;
mod motion;
mod options;
mod reason;
mod regrasp;
pub(crate) mod start;
mod state;
pub(crate) mod timing;
mod turns;
mod world;

pub use handover::handover_candidates;
pub use options::{OutOfRange, PlanOptions, PlanOverrides};
pub use reason::{Attempt, Collision, End, Fail, Rejection, Role, Stage, Step};
pub use regrasp::REST_RADIUS;

use crate::error::{Error, Result};
use crate::plan::{StageCount, Stats, StrategyReport};
use crate::setup::Setup;
use crate::strategy::{Arm, Strategy};
use assemble::Found;
use pickplace_geometry::math::Real;
use pickplace_grasp::GraspSet;
use pickplace_placement::{PlacementOptions, PlacementSet};
use state::Ctx;
use std::collections::BTreeMap;
use std::time::Instant;
use turns::{Turns, take_turns};

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

/// A memoized key pose: the result, or why it was rejected.
type Memo<T> = std::result::Result<T, Rejection>;

impl Ctx<'_> {
    fn finish_stats(&self, stats: &mut Stats, t_all: Instant) {
        if self.run.options.timings {
            stats.timings = self.budget.timings.clone();
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
    if ctx.run.placements.is_empty() {
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
    if ctx.run.grasps.is_empty() {
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
        self.budget.timings.insert(
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
pub(super) mod tests {
    use super::*;

    /// An empty report of `strategy`.
    pub(in crate::planner) fn report(strategy: Strategy) -> StrategyReport {
        StrategyReport {
            strategy,
            success: false,
            stages: BTreeMap::new(),
        }
    }

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
