//! The online pick-and-place planner of the paper's Fig. 8 (§III-C), with the manipulation
//! strategies of §III-B.3 and a searched handover.
//!
//! Order of work, cheapest test first so that most candidates are rejected for microseconds:
//! 1. placement candidates (Algorithm 2) on the cluster the target selects, ranked;
//! 2. grasp candidates on the object's parallel cluster pairs, ranked by quality; those below
//!    [`PlanOptions::min_grasp_quality`] of the best are dropped ("we evaluate the grasping
//!    posture; if it has good quality we check the collision of the key postures");
//! 3. strategies in the paper's order (the hand nearer the object picks, the hand nearer the
//!    target places), switching to the next one on failure;
//! 4. for each placement and grasp: reach, gripper against the environment, IK at the key
//!    poses, straight Cartesian approach and retreat (IK every centimetre, continuity
//!    checked), collision at every state with the object attached once grasped;
//! 5. PRM motions between the key poses on the arm's precomputed roadmap, checked lazily
//!    against this scene, shortcut, and time-parameterised.
//!
//! Every rejection is counted per strategy and stage with its reason, so a failure says why.

use crate::checker::ArmChecker;
use crate::error::{Error, Result};
use crate::plan::{
    Event, EventKind, GraspInfo, KeyPose, ObjectMotion, PLAN_FORMAT, PlacementInfo, Plan,
    StageCount, Stats, StrategyReport, TrajectoryPoint,
};
use crate::scene::{PoseSpec, StrategyChoice};
use crate::setup::Setup;
use crate::strategy::{Arm, Strategy};
use crate::validate::supports;
use pickplace_geometry::math::{Isometry3, Point3, Real, Translation3, UnitQuaternion, Vector3};
use pickplace_grasp::{Grasp, GraspOptions, GraspPlanner};
use pickplace_placement::{ContactKind, Placement, PlacementOptions};
use pickplace_prm::{
    Path as PrmPath, PrmPlanner, QueryOptions, RrtOptions, ShortcutOptions, TimingOptions,
    rrt_connect, shortcut, time_parameterize,
};
use pickplace_robot::IkOptions;
use pickplace_robot::collision::{BodyId, CheckOptions, CollisionScratch, CollisionWorld};
use pickplace_robot::srdf::DisableReason;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::time::Instant;

/// IK solutions tried per key pose before it is rejected (see `free_ik`).
const IK_SOLUTIONS: usize = 4;

/// Within this joint distance (rad, every joint) of a motion's ends the PRM applies no
/// clearance margin: the ends are grasp and release poses that may be close to the object.
const END_EXEMPT_RADIUS: Real = 0.1;

/// Candidates evaluated together on the thread pool (results are used in rank order).
const PARALLEL_CHUNK: usize = 16;

thread_local! {
    static SCRATCH: std::cell::RefCell<CollisionScratch> = Default::default();
}

/// Picks by the first arm kept for a handover search.
const HANDOVER_PICKS: usize = 12;

/// Clearance kept between the two hands at a handover (m).
const HAND_CLEARANCE: Real = 0.004;

/// Name of the object in collision worlds.
pub const OBJECT_NAME: &str = "object";

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
    /// Placement candidates tried, best first (default: 8).
    pub max_placements: usize,
    /// Grasps tried per placement and arm, best first (default: 48).
    pub max_grasps: usize,
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
    /// A budget makes the outcome depend on the machine's speed only when it runs out.
    pub time_budget: Real,
    /// Acceleration limit of every joint (rad/s² or m/s²): URDFs carry none (default: 3.0).
    pub max_acceleration: Real,
    /// Trajectory sampling period (s) (default: 0.04).
    pub sample_period: Real,
}

impl PlanOptions {
    /// The defaults with the scene's seed and strategy.
    pub fn for_setup(setup: &Setup) -> Self {
        Self {
            seed: setup.scene.planner.seed,
            strategy: setup.scene.planner.strategy,
            time_budget: setup.scene.planner.time_budget,
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
            max_placements: 8,
            max_grasps: 48,
            min_grasp_quality: 0.2,
            motion_margin: 0.01,
            handover_poses: 96,
            handover_feasible: 3,
            contact_zone: 0.005,
            timings: true,
            time_budget: 10.0,
            max_acceleration: 3.0,
            sample_period: 0.04,
        }
    }
}

/// What [`plan`] found.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// A plan.
    Planned(Box<Plan>),
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

/// One motion of the plan: full configurations, from rest to rest.
#[derive(Debug, Clone)]
struct Segment {
    /// Waypoints (full configurations).
    path: Vec<Vec<Real>>,
    /// Key pose reached at the end, if any.
    key: Option<(&'static str, Arm)>,
    /// Event at the end of the segment.
    event: Option<(EventKind, Arm, Isometry3)>,
}

impl Segment {
    /// A motion that ends at the key pose `name` of `arm`.
    fn reach(name: &'static str, arm: Arm, path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: Some((name, arm)),
            event: None,
        }
    }

    /// A motion with no key pose or event at its end (opening the hands at the start).
    fn plain(path: Vec<Vec<Real>>) -> Self {
        Self {
            path,
            key: None,
            event: None,
        }
    }
}

/// The result of picking with one arm and one grasp.
#[derive(Debug, Clone)]
struct Pick {
    /// pre-grasp → grasp (fingers open).
    approach: Vec<Vec<Real>>,
    /// grasp → lift (fingers closed, object attached).
    lift: Vec<Vec<Real>>,
}

/// The result of placing with one arm and one grasp.
#[derive(Debug, Clone)]
struct Place {
    /// pre-place → place (fingers closed, object attached).
    lower: Vec<Vec<Real>>,
    /// place → retreat (fingers open, object left).
    retreat: Vec<Vec<Real>>,
}

struct Ctx<'a> {
    /// When planning started (for the time budget).
    started: Instant,
    setup: &'a Setup,
    options: &'a PlanOptions,
    grasps: Vec<Grasp>,
    placements: Vec<Placement>,
    /// Environment bodies the object touches at the start.
    start_supports: Vec<String>,
    timings: BTreeMap<String, Real>,
}

/// Plans the scene.
///
/// # Errors
/// [`Error::Target`] when the target point is on no environment cluster; [`Error::Internal`]
/// when a lower layer fails on checked input.
pub fn plan(setup: &Setup, options: &PlanOptions) -> Result<Outcome> {
    let t_all = Instant::now();
    let mut timings = BTreeMap::new();
    let t = Instant::now();
    let target = setup.scene.target_point();
    let placement_set = pickplace_placement::candidates(
        &setup.placement_object,
        &setup.placement_env,
        &target,
        &PlacementOptions::default(),
    )
    .map_err(|source| Error::Target {
        path: setup.scene_path.clone(),
        source: Box::new(source),
    })?;
    timings.insert("placement".to_owned(), t.elapsed().as_secs_f64());
    let t = Instant::now();
    let grasp_set = GraspPlanner::new(&setup.object_mesh)
        .and_then(|p| {
            p.plan(
                &setup.object_finger,
                &setup.gripper,
                &GraspOptions::default(),
            )
        })
        .map_err(crate::error::internal("grasp planning"))?;
    timings.insert("grasp".to_owned(), t.elapsed().as_secs_f64());
    let best = grasp_set.grasps.first().map_or(0.0, |g| g.score);
    let grasps: Vec<Grasp> = grasp_set
        .grasps
        .iter()
        .filter(|g| g.score >= options.min_grasp_quality * best)
        .cloned()
        .collect();
    let mut stats = Stats {
        placement_candidates: placement_set.placements.len(),
        grasp_candidates: grasp_set.grasps.len(),
        ..Stats::default()
    };
    let mut ctx = Ctx {
        started: t_all,
        setup,
        options,
        start_supports: supports(setup, &setup.object_start),
        grasps,
        placements: placement_set.placements.clone(),
        timings,
    };
    let mut reasons = Vec::new();
    if ctx.placements.is_empty() {
        for (cluster, r) in &placement_set.rejections {
            reasons.push(format!(
                "no stable placement on environment cluster {cluster}: {} did not fit, {} unstable, {} penetrate",
                r.did_not_fit, r.unstable, r.penetrates
            ));
        }
        if reasons.is_empty() {
            reasons.push("no stable placement near the target".to_owned());
        }
    }
    if ctx.grasps.is_empty() {
        reasons.push(format!(
            "no grasp: {} candidates on {} cluster pairs, all rejected",
            grasp_set.candidates, grasp_set.pairs
        ));
    }
    if !reasons.is_empty() {
        ctx.finish_stats(&mut stats, t_all);
        return Ok(Outcome::NoPlan(Failure { reasons, stats }));
    }
    let shoulders = [setup.arms[0].shoulder, setup.arms[1].shoulder];
    let start_point = setup.object_start * setup.cog;
    let order = Strategy::order(options.strategy, shoulders, &start_point, &target);
    for strategy in order {
        if ctx.out_of_time() {
            reasons.push(format!(
                "{strategy}: not tried, the time budget of {} s is spent",
                options.time_budget
            ));
            continue;
        }
        let t = Instant::now();
        let mut report = StrategyReport {
            strategy,
            success: false,
            stages: BTreeMap::new(),
        };
        let found = if strategy.has_handover() {
            ctx.handover_strategy(strategy, &mut report)?
        } else {
            ctx.single_arm_strategy(strategy.pick_arm(), &mut report)?
        };
        ctx.timings.insert(
            format!("strategy {}", strategy.name()),
            t.elapsed().as_secs_f64(),
        );
        if let Some(found) = found {
            report.success = true;
            stats.strategies.push(report);
            let t = Instant::now();
            let plan = ctx.assemble(strategy, found, stats, t_all)?;
            let _ = t;
            return Ok(Outcome::Planned(Box::new(plan)));
        }
        reasons.push(format!("{strategy}: {}", summarize(&report)));
        stats.strategies.push(report);
    }
    ctx.finish_stats(&mut stats, t_all);
    Ok(Outcome::NoPlan(Failure { reasons, stats }))
}

/// The most frequent rejections of a strategy, for the failure message.
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
        parts.push(format!(
            "{stage} {}/{} passed{}{}",
            count.accepted,
            count.tried,
            if top.is_empty() { "" } else { " (" },
            if top.is_empty() {
                String::new()
            } else {
                top.join(", ") + ")"
            }
        ));
    }
    if parts.is_empty() {
        "nothing tried".to_owned()
    } else {
        parts.join("; ")
    }
}

/// A found motion: its segments, the grasps used, the placement.
struct Found {
    segments: Vec<Segment>,
    grasps: Vec<(Arm, usize)>,
    placement: usize,
}

impl Ctx<'_> {
    fn out_of_time(&self) -> bool {
        self.started.elapsed().as_secs_f64() > self.options.time_budget
    }

    fn finish_stats(&self, stats: &mut Stats, t_all: Instant) {
        if self.options.timings {
            stats.timings = self.timings.clone();
            stats
                .timings
                .insert("total".to_owned(), t_all.elapsed().as_secs_f64());
        }
    }

    fn ik_options(&self, salt: u64) -> IkOptions {
        IkOptions {
            max_restarts: 6,
            seed: self.options.seed ^ salt.wrapping_mul(0x9e37_79b9_7f4a_7c15),
            ..IkOptions::default()
        }
    }

    /// IK of `arm` for `world_from_tcp`, seeded by `seed` (full configuration).
    fn ik(
        &self,
        arm: Arm,
        world_from_tcp: &Isometry3,
        seed: &[Real],
        salt: u64,
    ) -> Option<Vec<Real>> {
        let a = self.setup.arm(arm);
        let root_from_tcp = self.setup.world_from_root.inverse() * world_from_tcp;
        let sol =
            a.ik.solve(&root_from_tcp, seed, &self.ik_options(salt))
                .ok()?;
        sol.success.then_some(sol.positions)
    }

    /// A collision-free IK solution in `world`: the solution nearest the seed first, then
    /// up to [`IK_SOLUTIONS`] others from seeded restarts (IK branches differ in elbow and
    /// wrist, and one of them often clears an obstacle the first hits).
    fn free_ik(
        &self,
        arm: Arm,
        world_from_tcp: &Isometry3,
        seed: &[Real],
        salt: u64,
        world: &CollisionWorld,
    ) -> std::result::Result<Vec<Real>, String> {
        let mut reason = "no IK".to_owned();
        let a = self.setup.arm(arm);
        let mut rng = pickplace_robot::rng::Rng::new(
            self.options.seed ^ salt.wrapping_mul(0xa076_1d64_78bd_642f),
        );
        let mut seed = seed.to_vec();
        for k in 0..IK_SOLUTIONS {
            if k > 0 {
                for (c, &v) in a.variables.iter().enumerate() {
                    seed[v] = rng.uniform(a.space.lower()[c], a.space.upper()[c]);
                }
            }
            let Some(q) = self.ik(arm, world_from_tcp, &seed, salt.wrapping_add(k as u64)) else {
                continue;
            };
            match self.collision(world, &q, 0.0) {
                None => return Ok(q),
                Some(c) => reason = c,
            }
        }
        Err(reason)
    }

    /// `world_from_tcp` of the arm at `q`.
    fn tcp(&self, arm: Arm, q: &[Real]) -> Isometry3 {
        self.setup.world_from_root * self.setup.arm(arm).ik.chain().pose(q)
    }

    /// `q` with the arm's fingers at half-opening `half`.
    fn with_fingers(&self, arm: Arm, q: &[Real], half: Real) -> Vec<Real> {
        let mut q = q.to_vec();
        for &v in &self.setup.arm(arm).finger_variables {
            let l = self.setup.model.variable_joint(v).limits;
            q[v] = half.clamp(l.lower, l.upper);
        }
        q
    }

    fn open_half(&self) -> Real {
        self.setup.gripper.opening_max / 2.0
    }

    /// The world with the object lying at `world_from_object` as an obstacle.
    fn world_with_object_at(&self, world_from_object: &Isometry3) -> CollisionWorld {
        let mut w = self.setup.world.clone();
        w.add_environment(
            OBJECT_NAME,
            self.setup.object_shape.clone(),
            world_from_object,
        );
        w
    }

    /// The world with the object held by `arm` (grasp `object_from_tcp`), allowed to touch
    /// the environment bodies `supports`.
    fn world_holding(
        &self,
        arm: Arm,
        object_from_tcp: &Isometry3,
        supports: &[String],
    ) -> Result<CollisionWorld> {
        let mut w = self.setup.world.clone();
        if !supports.is_empty() {
            let mut acm = w.acm().clone();
            for s in supports {
                acm.allow(
                    OBJECT_NAME,
                    s,
                    DisableReason::Custom("resting contact".into()),
                );
            }
            w.set_acm(acm);
        }
        let a = self.setup.arm(arm);
        let touch: Vec<&str> = a.finger_links.iter().map(String::as_str).collect();
        w.attach(
            OBJECT_NAME,
            &a.tcp_name,
            self.setup.object_shape.clone(),
            &object_from_tcp.inverse(),
            &touch,
        )
        .map_err(crate::error::internal("attach"))?;
        Ok(w)
    }

    /// Why `q` collides in `world` (`None` when free).
    fn collision(&self, world: &CollisionWorld, q: &[Real], margin: Real) -> Option<String> {
        SCRATCH.with(|cell| self.collision_with(world, q, margin, &mut cell.borrow_mut()))
    }

    fn collision_with(
        &self,
        world: &CollisionWorld,
        q: &[Real],
        margin: Real,
        scratch: &mut CollisionScratch,
    ) -> Option<String> {
        let opts = CheckOptions { margin };
        match world.in_collision(&self.setup.model, q, scratch, &opts) {
            Ok(false) => None,
            Ok(true) => {
                let pairs = world
                    .colliding_pairs(&self.setup.model, q, scratch, &opts)
                    .unwrap_or_default();
                Some(match pairs.first() {
                    Some(&(a, b)) => format!(
                        "collision {} / {}",
                        body_kind(world, a),
                        body_kind(world, b)
                    ),
                    None => "collision".to_owned(),
                })
            }
            Err(e) => Some(format!("collision check failed: {e}")),
        }
    }

    /// A straight Cartesian motion of `arm` from configuration `from` (TCP at its pose) to
    /// `world_from_tcp`, IK every [`PlanOptions::cartesian_step`]; each state is checked in
    /// the world `world_at(i, n)` returns.
    fn cartesian<'w>(
        &self,
        arm: Arm,
        from: &[Real],
        to_pose: &Isometry3,
        world_at: &dyn Fn(usize, usize) -> &'w CollisionWorld,
        salt: u64,
    ) -> std::result::Result<Vec<Vec<Real>>, String> {
        let from_pose = self.tcp(arm, from);
        let distance = (to_pose.translation.vector - from_pose.translation.vector).norm();
        let angle = from_pose.rotation.angle_to(&to_pose.rotation);
        let n = ((distance / self.options.cartesian_step)
            .max(angle / 0.05)
            .ceil() as usize)
            .max(1);
        let mut path = vec![from.to_vec()];
        let variables = &self.setup.arm(arm).variables;
        for i in 1..=n {
            let s = i as Real / n as Real;
            let pose = Isometry3::from_parts(
                Translation3::from(
                    from_pose
                        .translation
                        .vector
                        .lerp(&to_pose.translation.vector, s),
                ),
                from_pose.rotation.slerp(&to_pose.rotation, s),
            );
            let prev = path.last().expect("the path starts with `from`");
            let q = self
                .ik(arm, &pose, prev, salt.wrapping_add(i as u64))
                .ok_or_else(|| "no IK along the straight line".to_owned())?;
            let jump = variables
                .iter()
                .map(|&v| (q[v] - prev[v]).abs())
                .fold(0.0, Real::max);
            if jump > self.options.max_joint_step {
                return Err("IK branch jump along the straight line".to_owned());
            }
            if let Some(c) = self.collision(world_at(i, n), &q, 0.0) {
                return Err(c);
            }
            path.push(q);
        }
        Ok(path)
    }

    /// The gripper (palm and fingers at `opening`) against the environment at `world_from_tcp`.
    fn hand_hits_environment(&self, world_from_tcp: &Isometry3, opening: Real) -> Option<String> {
        let g = &self.setup.gripper;
        let [f1, f2] = g.fingers(opening);
        let bodies = [g.palm_box(), f1, f2];
        for e in &self.setup.environment {
            if bodies
                .iter()
                .any(|b| e.collider.hits(world_from_tcp, b, 0.0))
            {
                return Some(format!("gripper hits {}", e.name));
            }
        }
        None
    }

    /// Picks the object with `arm` and grasp `gi`: approach and lift.
    fn pick(&self, arm: Arm, gi: usize, start: &[Real]) -> std::result::Result<Pick, String> {
        let a = self.setup.arm(arm);
        let g = &self.grasps[gi];
        let grasp_pose = self.setup.object_start * g.object_from_tcp;
        if (grasp_pose.translation.vector - a.shoulder.coords).norm() > a.reach {
            return Err("out of reach".to_owned());
        }
        if let Some(r) = self.hand_hits_environment(&grasp_pose, self.setup.gripper.opening_max) {
            return Err(r);
        }
        let salt = (gi as u64) << 8 | arm.index() as u64;
        let open = self.with_fingers(arm, start, self.open_half());
        let free = self.world_with_object_at(&self.setup.object_start);
        let q_grasp = self
            .free_ik(arm, &grasp_pose, &open, salt, &free)
            .map_err(|r| format!("grasp: {r}"))?;
        let pre_pose =
            grasp_pose * Translation3::from(-self.approach_axis() * self.options.approach_distance);
        let mut approach = self
            .cartesian(arm, &q_grasp, &pre_pose, &|_, _| &free, salt ^ 0x11)
            .map_err(|r| format!("approach: {r}"))?;
        approach.reverse();
        let closed = self.with_fingers(arm, &q_grasp, g.width / 2.0);
        let holding = self
            .world_holding(arm, &g.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        let holding_contact = self
            .world_holding(arm, &g.object_from_tcp, &self.start_supports)
            .map_err(|e| e.to_string())?;
        let lift_pose = Translation3::new(0.0, 0.0, self.options.lift_height) * grasp_pose;
        let zone = self.options.contact_zone;
        let lift_n = self.options.lift_height;
        let lift = self
            .cartesian(
                arm,
                &closed,
                &lift_pose,
                &|i, n| {
                    if (i as Real / n as Real) * lift_n <= zone {
                        &holding_contact
                    } else {
                        &holding
                    }
                },
                salt ^ 0x22,
            )
            .map_err(|r| format!("lift: {r}"))?;
        if let Some(c) = self.collision(&holding_contact, &closed, 0.0) {
            return Err(format!("grasp (closed): {c}"));
        }
        Ok(Pick { approach, lift })
    }

    fn approach_axis(&self) -> Vector3 {
        self.setup.gripper.approach()
    }

    /// Places the object with `arm`, grasp `gi`, at placement `pi`: lower and retreat.
    /// `seed` is a full configuration whose other joints are kept.
    fn place(
        &self,
        arm: Arm,
        pi: usize,
        gi: usize,
        seed: &[Real],
    ) -> std::result::Result<Place, String> {
        let a = self.setup.arm(arm);
        let g = &self.grasps[gi];
        let p = &self.placements[pi];
        let place_pose = p.world_from_object * g.object_from_tcp;
        if (place_pose.translation.vector - a.shoulder.coords).norm() > a.reach {
            return Err("out of reach".to_owned());
        }
        if let Some(r) = self.hand_hits_environment(&place_pose, g.width) {
            return Err(r);
        }
        let salt = (pi as u64) << 20 | (gi as u64) << 8 | 0x80 | arm.index() as u64;
        let closed_seed = self.with_fingers(arm, seed, g.width / 2.0);
        let supports = supports(self.setup, &p.world_from_object);
        let holding = self
            .world_holding(arm, &g.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        let holding_contact = self
            .world_holding(arm, &g.object_from_tcp, &supports)
            .map_err(|e| e.to_string())?;
        let q_place = self
            .free_ik(arm, &place_pose, &closed_seed, salt, &holding_contact)
            .map_err(|r| format!("place: {r}"))?;
        let pre_pose = Translation3::new(0.0, 0.0, self.options.lift_height) * place_pose;
        let zone = self.options.contact_zone;
        let lift_n = self.options.lift_height;
        let mut lower = self
            .cartesian(
                arm,
                &q_place,
                &pre_pose,
                &|i, n| {
                    if (i as Real / n as Real) * lift_n <= zone {
                        &holding_contact
                    } else {
                        &holding
                    }
                },
                salt ^ 0x33,
            )
            .map_err(|r| format!("lower: {r}"))?;
        lower.reverse();
        let opened = self.with_fingers(arm, &q_place, self.open_half());
        let left = self.world_with_object_at(&p.world_from_object);
        if let Some(c) = self.collision(&left, &opened, 0.0) {
            return Err(format!("release: {c}"));
        }
        let retreat_pose =
            place_pose * Translation3::from(-self.approach_axis() * self.options.approach_distance);
        let retreat = self
            .cartesian(arm, &opened, &retreat_pose, &|_, _| &left, salt ^ 0x44)
            .map_err(|r| format!("retreat: {r}"))?;
        Ok(Place { lower, retreat })
    }

    /// A collision-free motion of `arm` from `from` to `to` (full configurations that differ
    /// only in the arm's joints) in `world`, by the lazy PRM, shortcut.
    fn motion(
        &self,
        arm: Arm,
        world: &CollisionWorld,
        from: &[Real],
        to: &[Real],
        salt: u64,
    ) -> std::result::Result<Vec<Vec<Real>>, String> {
        let a = self.setup.arm(arm);
        let project = |q: &[Real]| -> Vec<Real> { a.variables.iter().map(|&v| q[v]).collect() };
        let (qa, qb) = (project(from), project(to));
        let checker = ArmChecker::new(
            &self.setup.model,
            world,
            &a.variables,
            from.to_vec(),
            self.options.motion_margin,
        )
        .exempt(vec![qa.clone(), qb.clone()], END_EXEMPT_RADIUS);
        for (what, q) in [("start", from), ("goal", to)] {
            if let Some(c) = self.collision(world, q, 0.0) {
                return Err(format!("{what} in {c}"));
            }
        }
        let seed = self.options.seed ^ salt.wrapping_mul(0xd1b5_4a32_d192_ed03);
        let mut planner = PrmPlanner::new(
            &a.roadmap,
            &checker,
            QueryOptions {
                seed,
                growth_rounds: 1,
                ..QueryOptions::default()
            },
        );
        // The roadmap first (paper §III-C); when its start or goal cannot join it (a tight
        // spot near the object), RRT-Connect from both ends, bounded.
        let path = match planner.query(&qa, &qb) {
            Ok(p) => p,
            Err(e) => rrt_connect(
                &a.space,
                &checker,
                &qa,
                &qb,
                &RrtOptions {
                    max_iterations: 3000,
                    step: 0.3,
                    resolution: a.roadmap.options().resolution,
                    seed,
                },
            )
            .map_err(|r| format!("no path: {e}; RRT-Connect: {r}"))?,
        };
        let path = shortcut(
            &a.space,
            &checker,
            &path,
            &ShortcutOptions {
                attempts: 40,
                resolution: 0.02,
                seed,
            },
        )
        .unwrap_or(path);
        Ok((0..path.len())
            .map(|i| checker.full(path.waypoint(i)))
            .collect())
    }

    fn single_arm_strategy(
        &mut self,
        arm: Arm,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let start = self.setup.start.clone();
        let mut pick_cache: Vec<Option<std::result::Result<Pick, String>>> =
            vec![None; self.grasps.len()];
        let n_grasps = self.grasps.len().min(self.options.max_grasps);
        for pi in 0..self.placements.len().min(self.options.max_placements) {
            if self.out_of_time() {
                stage(report, "placement").reject("time budget spent");
                break;
            }
            let mut any = false;
            for (gi, cached) in pick_cache.iter_mut().enumerate().take(n_grasps) {
                let pick = match cached.get_or_insert_with(|| self.pick(arm, gi, &start)) {
                    Ok(p) => p.clone(),
                    Err(r) => {
                        if pi == 0 {
                            stage(report, "pick").reject(r.clone());
                        }
                        continue;
                    }
                };
                if pi == 0 {
                    stage(report, "pick").accept();
                }
                let lifted = pick.lift.last().expect("non-empty").clone();
                let place = match self.place(arm, pi, gi, &lifted) {
                    Ok(p) => p,
                    Err(r) => {
                        stage(report, "place").reject(r);
                        continue;
                    }
                };
                stage(report, "place").accept();
                any = true;
                match self.single_arm_motions(arm, pi, gi, &start, &pick, &place) {
                    Ok(segments) => {
                        stage(report, "motion").accept();
                        stage(report, "placement").accept();
                        return Ok(Some(Found {
                            segments,
                            grasps: vec![(arm, gi)],
                            placement: pi,
                        }));
                    }
                    Err(r) => stage(report, "motion").reject(r),
                }
            }
            stage(report, "placement").reject(if any {
                "no motion for any grasp"
            } else {
                "no grasp reaches it"
            });
        }
        Ok(None)
    }

    fn single_arm_motions(
        &self,
        arm: Arm,
        pi: usize,
        gi: usize,
        start: &[Real],
        pick: &Pick,
        place: &Place,
    ) -> std::result::Result<Vec<Segment>, String> {
        let g = &self.grasps[gi];
        let p = &self.placements[pi];
        let salt = (pi as u64) << 20 | (gi as u64) << 8 | arm.index() as u64;
        let mut segments = Vec::new();
        let open_start = self.with_fingers(arm, start, self.open_half());
        if open_start != start {
            segments.push(Segment::plain(vec![start.to_vec(), open_start.clone()]));
        }
        let free = self.world_with_object_at(&self.setup.object_start);
        let pre_grasp = &pick.approach[0];
        let to_pre = self
            .motion(arm, &free, &open_start, pre_grasp, salt ^ 1)
            .map_err(|r| format!("to pre-grasp: {r}"))?;
        segments.push(Segment::reach("pre-grasp", arm, to_pre));
        segments.push(Segment::reach("grasp", arm, pick.approach.clone()));
        let q_grasp = pick.approach.last().expect("non-empty");
        let closed = self.with_fingers(arm, q_grasp, g.width / 2.0);
        segments.push(Segment {
            path: vec![q_grasp.clone(), closed],
            key: None,
            event: Some((EventKind::Grasp, arm, g.object_from_tcp.inverse())),
        });
        segments.push(Segment::reach("lift", arm, pick.lift.clone()));
        let holding = self
            .world_holding(arm, &g.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        let lifted = pick.lift.last().expect("non-empty");
        let carry = self
            .motion(arm, &holding, lifted, &place.lower[0], salt ^ 2)
            .map_err(|r| format!("to pre-place: {r}"))?;
        segments.push(Segment::reach("pre-place", arm, carry));
        segments.push(Segment::reach("place", arm, place.lower.clone()));
        let q_place = place.lower.last().expect("non-empty");
        let opened = self.with_fingers(arm, q_place, self.open_half());
        segments.push(Segment {
            path: vec![q_place.clone(), opened],
            key: Some(("release", arm)),
            event: Some((EventKind::Release, arm, g.object_from_tcp.inverse())),
        });
        segments.push(Segment::reach("retreat", arm, place.retreat.clone()));
        let left = self.world_with_object_at(&p.world_from_object);
        let retreated = place.retreat.last().expect("non-empty");
        if let Some(back) = self.back_to_start(arm, &left, retreated, start, salt ^ 3)? {
            segments.push(back);
        }
        Ok(segments)
    }

    fn handover_strategy(
        &mut self,
        strategy: Strategy,
        report: &mut StrategyReport,
    ) -> Result<Option<Found>> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let start = self.setup.start.clone();
        // Picks by arm A (independent of the placement): a handover needs two grasps that
        // leave room for each other, so the search goes down the whole ranked list until it
        // has [`HANDOVER_PICKS`] picks, not only the best grasps.
        // Chunks of grasps are tried in parallel; results are taken in rank order, so the
        // outcome does not depend on the thread count.
        let mut picks = Vec::new();
        let mut next = 0;
        'scan: while next < self.grasps.len() {
            let end = (next + PARALLEL_CHUNK).min(self.grasps.len());
            let results: Vec<_> = (next..end)
                .into_par_iter()
                .map(|gi| (gi, self.pick(a, gi, &start)))
                .collect();
            next = end;
            for (gi, result) in results {
                if picks.len() >= HANDOVER_PICKS {
                    break 'scan;
                }
                match result {
                    Ok(p) => {
                        stage(report, "pick").accept();
                        picks.push((gi, p));
                    }
                    Err(r) => stage(report, "pick").reject(r),
                }
            }
        }
        if picks.is_empty() {
            return Ok(None);
        }
        let handovers = handover_candidates(self.setup, a, self.options.handover_poses);
        for pi in 0..self.placements.len().min(self.options.max_placements) {
            if self.out_of_time() {
                stage(report, "placement").reject("time budget spent");
                break;
            }
            // Places by arm B, seeded from its start configuration, computed once per grasp:
            // for each pick grasp, the grasps whose hand clears the picking hand, best first.
            let mut places: BTreeMap<usize, Option<Place>> = BTreeMap::new();
            let mut feasible: Vec<(Real, Handover)> = Vec::new();
            // The handover: object poses in front of the torso (where the picking hand
            // holds it at a searched tool pose), scored by both arms' reach and clearance.
            'picks: for (g1, pick) in &picks {
                // Second grasps whose hand clears the first, best first, placed in parallel
                // chunks (each computed once per placement).
                let clear: Vec<usize> = (0..self.grasps.len())
                    .filter(|&g2| {
                        !hands_overlap(&self.setup.gripper, &self.grasps[*g1], &self.grasps[g2])
                    })
                    .collect();
                let mut mine = Vec::new();
                'grasps: for chunk in clear.chunks(PARALLEL_CHUNK) {
                    let todo: Vec<usize> = chunk
                        .iter()
                        .copied()
                        .filter(|g| !places.contains_key(g))
                        .collect();
                    let results: Vec<_> = todo
                        .par_iter()
                        .map(|&g2| (g2, self.place(b, pi, g2, &start)))
                        .collect();
                    for (g2, result) in results {
                        places.insert(
                            g2,
                            match result {
                                Ok(p) => {
                                    stage(report, "place").accept();
                                    Some(p)
                                }
                                Err(r) => {
                                    stage(report, "place").reject(r);
                                    None
                                }
                            },
                        );
                    }
                    for g2 in chunk {
                        if mine.len() >= self.options.max_grasps {
                            break 'grasps;
                        }
                        if let Some(Some(p)) = places.get(g2) {
                            mine.push((*g2, p.clone()));
                        }
                    }
                }
                if mine.is_empty() {
                    stage(report, "handover")
                        .reject("no second grasp clears the first hand and places");
                    continue;
                }
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
                        let total = stage(report, "regrasp");
                        total.tried += regrasp.tried;
                        total.accepted += regrasp.accepted;
                        for (reason, n) in regrasp.rejected {
                            *total.rejected.entry(reason).or_default() += n;
                        }
                        match result {
                            Ok(found) => {
                                stage(report, "handover").accept();
                                feasible.push(found);
                                if feasible.len() >= self.options.handover_feasible {
                                    break 'picks;
                                }
                            }
                            Err(r) => stage(report, "handover").reject(r),
                        }
                    }
                }
            }
            feasible.sort_by(|x, y| y.0.total_cmp(&x.0));
            for (_, h) in feasible {
                let (pick, place) = (
                    &picks
                        .iter()
                        .find(|(g, _)| *g == h.g1)
                        .expect("from picks")
                        .1,
                    places
                        .get(&h.g2)
                        .and_then(Option::as_ref)
                        .expect("a handover's second grasp places"),
                );
                match self.handover_motions(strategy, pi, &start, pick, place, &h) {
                    Ok(segments) => {
                        stage(report, "motion").accept();
                        stage(report, "placement").accept();
                        return Ok(Some(Found {
                            segments,
                            grasps: vec![(a, h.g1), (b, h.g2)],
                            placement: pi,
                        }));
                    }
                    Err(r) => stage(report, "motion").reject(r),
                }
            }
            stage(report, "placement").reject("no handover");
        }
        Ok(None)
    }

    /// Tests a handover at object pose `h` with pick grasp `g1` of arm A; looks for a grasp of
    /// arm B that regrasps there and places.
    fn handover_at(
        &self,
        strategy: Strategy,
        hi: usize,
        world_from_object: &Isometry3,
        g1: usize,
        pick: &Pick,
        places: &[(usize, Place)],
        regrasp: &mut StageCount,
    ) -> std::result::Result<(Real, Handover), String> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let grasp1 = &self.grasps[g1];
        let pose_a = world_from_object * grasp1.object_from_tcp;
        let arm_a = self.setup.arm(a);
        if (pose_a.translation.vector - arm_a.shoulder.coords).norm() > arm_a.reach {
            return Err("picking arm out of reach".to_owned());
        }
        let lifted = pick.lift.last().expect("non-empty");
        let salt = (hi as u64) << 24 | (g1 as u64) << 8 | 0x40;
        let holding_a = self
            .world_holding(a, &grasp1.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        let q_a = self
            .free_ik(a, &pose_a, lifted, salt, &holding_a)
            .map_err(|r| format!("picking arm: {r}"))?;
        let arm_b = self.setup.arm(b);
        for (g2, _) in places {
            let grasp2 = &self.grasps[*g2];
            let pose_b = world_from_object * grasp2.object_from_tcp;
            if (pose_b.translation.vector - arm_b.shoulder.coords).norm() > arm_b.reach {
                regrasp.reject("placing arm out of reach".to_owned());
                continue;
            }
            // The two hands must not overlap: the second grasp's gripper against the first.
            if hands_overlap(&self.setup.gripper, grasp1, grasp2) {
                regrasp.reject("the second hand would collide with the first".to_owned());
                continue;
            }
            let seed = self.with_fingers(b, &q_a, self.open_half());
            let q_b = match self.free_ik(b, &pose_b, &seed, salt ^ (*g2 as u64) << 40, &holding_a) {
                Ok(q) => q,
                Err(r) => {
                    regrasp.reject(format!("regrasp: {r}"));
                    continue;
                }
            };
            let pre_pose =
                pose_b * Translation3::from(-self.approach_axis() * self.options.approach_distance);
            let approach = match self.cartesian(b, &q_b, &pre_pose, &|_, _| &holding_a, salt ^ 0x55)
            {
                Ok(mut p) => {
                    p.reverse();
                    p
                }
                Err(r) => {
                    regrasp.reject(format!("regrasp approach: {r}"));
                    continue;
                }
            };
            // Both hold: B closes, then A opens and retreats with B holding.
            let both = self.with_fingers(b, &q_b, grasp2.width / 2.0);
            let holding_b = match self.world_holding(b, &grasp2.object_from_tcp, &[]) {
                Ok(w) => w,
                Err(e) => return Err(e.to_string()),
            };
            let a_open = self.with_fingers(a, &both, self.open_half());
            if let Some(c) = self.collision(&holding_b, &a_open, 0.0) {
                regrasp.reject(format!("release of the first hand: {c}"));
                continue;
            }
            let retreat_pose =
                pose_a * Translation3::from(-self.approach_axis() * self.options.approach_distance);
            let retreat =
                match self.cartesian(a, &a_open, &retreat_pose, &|_, _| &holding_b, salt ^ 0x66) {
                    Ok(p) => p,
                    Err(r) => {
                        regrasp.reject(format!("first hand retreat: {r}"));
                        continue;
                    }
                };
            // Score: clearance of the handover configuration (both arms at the object).
            let clearance = {
                SCRATCH.with(|cell| {
                    holding_a
                        .min_distance(&self.setup.model, &approach[0], &mut cell.borrow_mut())
                        .ok()
                        .flatten()
                        .map_or(1.0, |d| d.distance)
                })
            };
            let reach_margin = (arm_a.reach
                - (pose_a.translation.vector - arm_a.shoulder.coords).norm())
            .min(arm_b.reach - (pose_b.translation.vector - arm_b.shoulder.coords).norm());
            regrasp.accept();
            return Ok((
                clearance.min(0.1) + reach_margin,
                Handover {
                    g1,
                    g2: *g2,
                    q_a,
                    approach,
                    retreat,
                },
            ));
        }
        Err("no regrasp".to_owned())
    }

    fn handover_motions(
        &self,
        strategy: Strategy,
        pi: usize,
        start: &[Real],
        pick: &Pick,
        place: &Place,
        h: &Handover,
    ) -> std::result::Result<Vec<Segment>, String> {
        let (a, b) = (strategy.pick_arm(), strategy.place_arm());
        let (g1, g2) = (&self.grasps[h.g1], &self.grasps[h.g2]);
        let salt = (pi as u64) << 20 | (h.g1 as u64) << 8 | (h.g2 as u64) << 32;
        let mut segments = Vec::new();
        // Both hands open at the start.
        let open_start = self.with_fingers(
            b,
            &self.with_fingers(a, start, self.open_half()),
            self.open_half(),
        );
        if open_start != start {
            segments.push(Segment::plain(vec![start.to_vec(), open_start.clone()]));
        }
        let free = self.world_with_object_at(&self.setup.object_start);
        let to_pre = self
            .motion(
                a,
                &free,
                &open_start,
                &self.other_from(b, &pick.approach[0], &open_start),
                salt ^ 1,
            )
            .map_err(|r| format!("to pre-grasp: {r}"))?;
        let here = |seg: &Vec<Vec<Real>>| seg.last().expect("non-empty").clone();
        segments.push(Segment::reach("pre-grasp", a, to_pre.clone()));
        let approach: Vec<Vec<Real>> = pick
            .approach
            .iter()
            .map(|q| self.other_from(b, q, &open_start))
            .collect();
        segments.push(Segment::reach("grasp", a, approach.clone()));
        let q = here(&approach);
        let closed = self.with_fingers(a, &q, g1.width / 2.0);
        segments.push(Segment {
            path: vec![q, closed],
            key: None,
            event: Some((EventKind::Grasp, a, g1.object_from_tcp.inverse())),
        });
        let lift: Vec<Vec<Real>> = pick
            .lift
            .iter()
            .map(|q| self.other_from(b, q, &open_start))
            .collect();
        segments.push(Segment::reach("lift", a, lift.clone()));
        // A carries the object to the handover pose.
        let holding_a = self
            .world_holding(a, &g1.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        let q_handover = self.arm_from(a, &here(&lift), &h.q_a);
        let carry = self
            .motion(a, &holding_a, &here(&lift), &q_handover, salt ^ 2)
            .map_err(|r| format!("to handover: {r}"))?;
        segments.push(Segment::reach("handover", a, carry));
        // B comes to the pre-regrasp pose, then approaches.
        let q_pre_b = self.arm_from(b, &q_handover, &h.approach[0]);
        let to_b = self
            .motion(b, &holding_a, &q_handover, &q_pre_b, salt ^ 3)
            .map_err(|r| format!("to pre-regrasp: {r}"))?;
        segments.push(Segment::reach("pre-regrasp", b, to_b));
        let b_approach: Vec<Vec<Real>> = h
            .approach
            .iter()
            .map(|qb| self.arm_from(b, &q_pre_b, qb))
            .collect();
        segments.push(Segment::reach("regrasp", b, b_approach.clone()));
        let q = here(&b_approach);
        let b_closed = self.with_fingers(b, &q, g2.width / 2.0);
        segments.push(Segment {
            path: vec![q, b_closed.clone()],
            key: None,
            event: Some((EventKind::Grasp, b, g2.object_from_tcp.inverse())),
        });
        let a_open = self.with_fingers(a, &b_closed, self.open_half());
        segments.push(Segment {
            path: vec![b_closed, a_open.clone()],
            key: Some(("release-first", a)),
            event: Some((EventKind::Release, a, g1.object_from_tcp.inverse())),
        });
        let a_retreat: Vec<Vec<Real>> = h
            .retreat
            .iter()
            .map(|qa| self.arm_from(a, &a_open, qa))
            .collect();
        segments.push(Segment::reach("retreat-first", a, a_retreat.clone()));
        let holding_b = self
            .world_holding(b, &g2.object_from_tcp, &[])
            .map_err(|e| e.to_string())?;
        // A goes back to its start while B holds.
        let a_home = self.arm_from(a, &here(&a_retreat), start);
        let back_a = self
            .motion(a, &holding_b, &here(&a_retreat), &a_home, salt ^ 4)
            .map_err(|r| format!("first arm back to start: {r}"))?;
        segments.push(Segment::reach("home-first", a, back_a));
        // B carries the object to the pre-place pose.
        let lower: Vec<Vec<Real>> = place
            .lower
            .iter()
            .map(|qb| self.arm_from(b, &a_home, qb))
            .collect();
        let to_place = self
            .motion(b, &holding_b, &a_home, &lower[0], salt ^ 5)
            .map_err(|r| format!("to pre-place: {r}"))?;
        segments.push(Segment::reach("pre-place", b, to_place));
        segments.push(Segment::reach("place", b, lower.clone()));
        let q = here(&lower);
        let opened = self.with_fingers(b, &q, self.open_half());
        segments.push(Segment {
            path: vec![q, opened.clone()],
            key: Some(("release", b)),
            event: Some((EventKind::Release, b, g2.object_from_tcp.inverse())),
        });
        let retreat: Vec<Vec<Real>> = place
            .retreat
            .iter()
            .map(|qb| self.arm_from(b, &opened, qb))
            .collect();
        segments.push(Segment::reach("retreat", b, retreat.clone()));
        let left = self.world_with_object_at(&self.placements[pi].world_from_object);
        if let Some(back) = self.back_to_start(b, &left, &here(&retreat), start, salt ^ 6)? {
            segments.push(back);
        }
        Ok(segments)
    }

    /// The arm's motion back to its start configuration after the retreat, or `None` when
    /// the start configuration itself now collides (the object was placed where the hand
    /// rests): the plan then ends at the retreat pose.
    fn back_to_start(
        &self,
        arm: Arm,
        world: &CollisionWorld,
        from: &[Real],
        start: &[Real],
        salt: u64,
    ) -> std::result::Result<Option<Segment>, String> {
        let home = self.arm_from(arm, from, start);
        if self.collision(world, &home, 0.0).is_some() {
            return Ok(None);
        }
        let back = self
            .motion(arm, world, from, &home, salt)
            .map_err(|r| format!("back to start: {r}"))?;
        Ok(Some(Segment::reach("home", arm, back)))
    }

    /// `q` with arm `other`'s joints and fingers taken from `from`.
    fn other_from(&self, other: Arm, q: &[Real], from: &[Real]) -> Vec<Real> {
        let mut out = q.to_vec();
        let o = self.setup.arm(other);
        for &v in o.variables.iter().chain(&o.finger_variables) {
            out[v] = from[v];
        }
        out
    }

    /// `base` with `arm`'s joints (not its fingers) taken from `q`.
    fn arm_from(&self, arm: Arm, base: &[Real], q: &[Real]) -> Vec<Real> {
        let mut out = base.to_vec();
        for &v in &self.setup.arm(arm).variables {
            out[v] = q[v];
        }
        out
    }

    /// Times the segments and writes the plan.
    fn assemble(
        &mut self,
        strategy: Strategy,
        found: Found,
        mut stats: Stats,
        t_all: Instant,
    ) -> Result<Plan> {
        let t = Instant::now();
        let model = &self.setup.model;
        let n = model.variable_count();
        let velocities: Vec<Real> = model
            .variable_limits()
            .map(|l| if l.velocity > 0.0 { l.velocity } else { 1.0 })
            .collect();
        let timing = TimingOptions {
            max_velocities: velocities,
            max_accelerations: vec![self.options.max_acceleration; n],
            sample_period: self.options.sample_period,
        };
        let mut trajectory: Vec<TrajectoryPoint> = vec![TrajectoryPoint {
            time_from_start: 0.0,
            positions: self.setup.start.clone(),
        }];
        let mut events = Vec::new();
        let mut key_poses = Vec::new();
        let mut object_pose = self.setup.object_start;
        let mut holder: Option<(Arm, Isometry3)> = None;
        let placed = self.placements[found.placement].world_from_object;
        for seg in &found.segments {
            let path = PrmPath::from_waypoints(n, seg.path.iter().map(|q| q.as_slice()))
                .map_err(crate::error::internal("trajectory"))?;
            let offset = trajectory.last().map_or(0.0, |p| p.time_from_start);
            if path.len() >= 2 {
                let timed =
                    time_parameterize(&path, &timing).map_err(crate::error::internal("timing"))?;
                for p in timed.points.iter().skip(1) {
                    trajectory.push(TrajectoryPoint {
                        time_from_start: round_time(offset + p.time_from_start),
                        positions: p.positions.clone(),
                    });
                }
            }
            let end = trajectory.last().expect("non-empty");
            let q_end = end.positions.clone();
            let time = end.time_from_start;
            if let Some((kind, arm, link_from_object)) = seg.event {
                let a = self.setup.arm(arm);
                events.push(Event {
                    time,
                    kind,
                    arm,
                    link: a.tcp_name.clone(),
                    link_from_object: PoseSpec::from_isometry(&link_from_object),
                });
                match kind {
                    EventKind::Grasp => holder = Some((arm, link_from_object)),
                    EventKind::Release => {
                        if holder.is_some_and(|(h, _)| h == arm) {
                            holder = None;
                        }
                        // After a handover release the other hand holds it.
                        if let Some(&(other, g)) = found.grasps.iter().find(|(o, _)| *o != arm)
                            && kind == EventKind::Release
                            && found.grasps.len() == 2
                            && arm == found.grasps[0].0
                        {
                            holder = Some((other, self.grasps[g].object_from_tcp.inverse()));
                        }
                    }
                }
            }
            if let Some((arm, link_from_object)) = holder {
                object_pose = self.tcp(arm, &q_end) * link_from_object;
            }
            if let Some((name, arm)) = seg.key {
                key_poses.push(KeyPose {
                    name: name.to_owned(),
                    arm,
                    time,
                    world_from_tcp: PoseSpec::from_isometry(&self.tcp(arm, &q_end)),
                    world_from_object: PoseSpec::from_isometry(&object_pose),
                });
            }
        }
        let grasps = found
            .grasps
            .iter()
            .map(|&(arm, gi)| {
                let g = &self.grasps[gi];
                GraspInfo {
                    arm,
                    object_from_tcp: PoseSpec::from_isometry(&g.object_from_tcp),
                    width: g.width,
                    score: g.score,
                    rank: gi,
                }
            })
            .collect();
        let p = &self.placements[found.placement];
        let (env_index, env_cluster) = self
            .setup
            .environment_of_cluster(p.env_cluster)
            .unwrap_or((0, p.env_cluster));
        let placement = PlacementInfo {
            contact: match p.contact {
                ContactKind::FaceFace => "face-face",
                ContactKind::EdgeFace => "edge-face",
            }
            .to_owned(),
            object_cluster: p.object_cluster,
            environment: self.setup.environment[env_index].name.clone(),
            env_cluster,
            stability_margin: p.stability_margin,
            rank: found.placement,
        };
        self.timings
            .insert("trajectory".to_owned(), t.elapsed().as_secs_f64());
        stats.trajectory_points = trajectory.len();
        stats.duration = trajectory.last().map_or(0.0, |p| p.time_from_start);
        self.finish_stats(&mut stats, t_all);
        Ok(Plan {
            format: PLAN_FORMAT.to_owned(),
            seed: self.options.seed,
            strategy,
            joint_names: model.variable_names().map(str::to_owned).collect(),
            trajectory,
            events,
            object: ObjectMotion {
                start_pose: PoseSpec::from_isometry(&self.setup.object_start),
                placed_pose: PoseSpec::from_isometry(&placed),
            },
            placement,
            grasps,
            key_poses,
            stats,
        })
    }
}

/// Times are rounded to the microsecond so that the JSON is short and stable.
fn round_time(t: Real) -> Real {
    (t * 1e6).round() / 1e6
}

fn body_kind(world: &CollisionWorld, b: BodyId) -> String {
    match b {
        BodyId::Link(_) => world.body_name(b).to_owned(),
        BodyId::Environment(_) => world.body_name(b).to_owned(),
        BodyId::Attached(_) => "held object".to_owned(),
    }
}

fn stage<'r>(report: &'r mut StrategyReport, name: &str) -> &'r mut StageCount {
    report.stages.entry(name.to_owned()).or_default()
}

/// A feasible handover.
#[derive(Debug, Clone)]
struct Handover {
    g1: usize,
    g2: usize,
    /// Arm A's configuration at the handover (full).
    q_a: Vec<Real>,
    /// Arm B: pre-regrasp → regrasp (full configurations).
    approach: Vec<Vec<Real>>,
    /// Arm A: handover → retreat, fingers open (full configurations).
    retreat: Vec<Vec<Real>>,
}

/// Whether the gripper of `second` (open) would overlap the gripper of `first` (closed on
/// the object) when both hold the object: any of their palm and finger boxes intersect
/// (separating-axis test on oriented boxes, object frame), with [`HAND_CLEARANCE`].
fn hands_overlap(gripper: &pickplace_grasp::GripperParams, first: &Grasp, second: &Grasp) -> bool {
    let boxes = |grasp: &Grasp, opening: Real| -> Vec<Obb> {
        let [f1, f2] = gripper.fingers(opening);
        [gripper.palm_box(), f1, f2]
            .into_iter()
            .map(|b| Obb {
                center: grasp.object_from_tcp * b.center,
                axes: grasp.object_from_tcp.rotation.to_rotation_matrix().matrix() * b.tcp_from_box,
                half: b.half_extents.add_scalar(HAND_CLEARANCE / 2.0),
            })
            .collect()
    };
    let a = boxes(first, first.width);
    let b = boxes(second, gripper.opening_max);
    a.iter().any(|x| b.iter().any(|y| x.intersects(y)))
}

/// An oriented box: centre, axes as matrix columns, half extents.
struct Obb {
    center: Point3,
    axes: pickplace_geometry::math::Matrix3,
    half: Vector3,
}

impl Obb {
    /// Separating-axis test over the 15 candidate axes.
    fn intersects(&self, other: &Obb) -> bool {
        let d = other.center - self.center;
        let mut axes: Vec<Vector3> = Vec::with_capacity(15);
        for i in 0..3 {
            axes.push(self.axes.column(i).into_owned());
            axes.push(other.axes.column(i).into_owned());
        }
        for i in 0..3 {
            for j in 0..3 {
                let c = self.axes.column(i).cross(&other.axes.column(j));
                if c.norm_squared() > 1e-12 {
                    axes.push(c.normalize());
                }
            }
        }
        let radius = |b: &Obb, axis: &Vector3| -> Real {
            (0..3)
                .map(|i| b.half[i] * b.axes.column(i).dot(axis).abs())
                .sum()
        };
        axes.iter()
            .all(|axis| d.dot(axis).abs() <= radius(self, axis) + radius(other, axis))
    }
}

/// Poses of the picking hand (`world_from_tcp`) tried for a handover, best guess first; the
/// object's handover pose is where this hand holds it. The original planner used one
/// hard-coded pose; here the pose is searched: tool positions in front of the torso between
/// the shoulders (0.32–0.40 m ahead, 0.15–0.25 m below the shoulders), approach directions
/// forward, forward and inward, forward and down, and down, each rolled in 90° steps. Each
/// feasible one is scored by both arms' reach margin and the robot's clearance.
pub fn handover_candidates(setup: &Setup, picking: Arm, count: usize) -> Vec<Isometry3> {
    let [r, l] = [setup.arms[0].shoulder, setup.arms[1].shoulder];
    let mid = Point3::from((r.coords + l.coords) / 2.0);
    let forward = setup.world_from_root.rotation * Vector3::x();
    let left = setup.world_from_root.rotation * Vector3::y();
    let up = Vector3::z();
    // The picking hand reaches across towards the other arm.
    let inward = match picking {
        Arm::Left => -left,
        Arm::Right => left,
    };
    let directions = [
        forward,
        (forward + inward).normalize(),
        (forward - up).normalize(),
        -up,
    ];
    let mut out = Vec::new();
    for &ahead in &[0.36, 0.30, 0.42] {
        for &height in &[-0.15, -0.25] {
            for (d, approach) in directions.iter().enumerate() {
                for roll in 0..4 {
                    let p = mid + forward * ahead + up * height;
                    // A frame with z along the approach; x from a reference not parallel to it.
                    let reference = if approach.cross(&up).norm() > 1e-6 {
                        up
                    } else {
                        forward
                    };
                    let x0 = reference.cross(approach).normalize();
                    let y0 = approach.cross(&x0);
                    let angle = Real::from(roll) * std::f64::consts::FRAC_PI_2;
                    let x = x0 * angle.cos() + y0 * angle.sin();
                    let y = approach.cross(&x);
                    let m = pickplace_geometry::math::Matrix3::from_columns(&[x, y, *approach]);
                    let rotation = UnitQuaternion::from_matrix(&m);
                    out.push((
                        d,
                        out.len(),
                        Isometry3::from_parts(Translation3::from(p.coords), rotation),
                    ));
                }
            }
        }
    }
    out.into_iter().take(count).map(|(_, _, p)| p).collect()
}
