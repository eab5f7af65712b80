//! Motion queries (issue 35): a collision-free, time-optimal motion of one planning group of a
//! robot from one joint state to another among obstacles, with no object to pick or place.
//! The pick-and-place planner's own motions (paper §III-C) use the same parts.
//!
//! ```no_run
//! use pickplace::motion::{MotionOptions, MotionOutcome, MotionRequest, MotionWorld, Obstacle,
//!     ObstacleShape, StateSpec, plan_motion};
//! use pickplace::geometry::math::{Isometry3, Translation3, UnitQuaternion};
//! use std::path::Path;
//!
//! let mut world = MotionWorld::for_robot(
//!     Path::new("panda.urdf"),
//!     Some(Path::new("panda.srdf")),
//!     &pickplace::SetupOptions::default(),
//! )?;
//! world.add_obstacle(&Obstacle {
//!     name: "table".into(),
//!     shape: ObstacleShape::Box { size: [1.0, 1.0, 0.05] },
//!     pose: Isometry3::from_parts(Translation3::new(0.5, 0.0, -0.03), UnitQuaternion::identity()),
//! })?;
//! let request = MotionRequest {
//!     group: Some("panda_arm".into()),
//!     start: StateSpec::Named("ready".into()),
//!     goal: StateSpec::Values(vec![0.5, -0.3, 0.0, -2.0, 0.0, 1.8, 0.8]),
//! };
//! match plan_motion(&world, &request, &MotionOptions::default())? {
//!     MotionOutcome::Planned(m) => println!("{:.2} s of motion", m.stats.duration),
//!     MotionOutcome::NoMotion(why) => println!("no motion: {why}"),
//! }
//! # Ok::<(), pickplace::Error>(())
//! ```
//!
//! The search is RRT-Connect ([`pickplace_prm::rrt_connect`], every segment checked at the
//! validator's 1° joint step) under a time limit, then seeded shortcutting; the path is timed
//! by TOPP-RA under the joints' velocity and acceleration limits with its corners blended
//! ([`crate::timing`]). Every pair of consecutive samples of the returned trajectory is
//! checked again, exactly (the links' convex pieces against the obstacles' shapes, no margin),
//! at 1° of joint motion: a blend that cuts into an obstacle is tightened until it does not,
//! so the motion is collision-free at the validator's resolution whatever the options.

mod world;

pub use crate::obstacle::{Obstacle, ObstacleShape};
pub use world::MotionWorld;

use crate::checker::ArmChecker;
use crate::error::Result;
use crate::plan::{Limits, TrajectoryPoint};
use crate::timing::{snap_part_ends, tighten, time_parts, timing_error};
use pickplace_geometry::io::fmt_real;
use pickplace_geometry::math::Real;
use pickplace_prm::toppra::{BlendedPath, ToppraOptions};
use pickplace_prm::{JointSpace, RrtOptions, ShortcutOptions, ValidityChecker};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

/// The format tag of a motion document.
pub const MOTION_FORMAT: &str = "pickplace.motion/1";

/// The random stream of the shortcutting ([`pickplace_prm::rng::Rng::derive`]); the search
/// takes the seed itself.
const SHORTCUT_STREAM: u64 = 1;

/// The random stream of the search, per attempt.
const SEARCH_STREAM: u64 = 2;

/// Clearance (m) added to the options' margin by each attempt of the search.
const EXTRA_MARGIN: [Real; 3] = [0.0, 0.001, 0.003];

/// The validator's resolution: 1° of joint motion between states checked.
const CHECK_STEP: Real = crate::rules::MAX_JOINT_STEP;

/// A joint state of a query.
#[derive(Debug, Clone, PartialEq)]
pub enum StateSpec {
    /// A `group_state` of the SRDF (its values for the group's joints).
    Named(String),
    /// One value per joint of the group, in the group's order (rad or m).
    Values(Vec<Real>),
    /// Values by joint name; the group's joints not named keep the world's start state.
    Joints(BTreeMap<String, Real>),
}

/// What to plan: a group's motion between two states.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionRequest {
    /// The planning group (an SRDF group or a scene's `groups`); `None`: the robot's only
    /// group that moves joints, or every actuated joint of a robot without groups.
    pub group: Option<String>,
    /// Where the motion starts.
    pub start: StateSpec,
    /// Where it ends.
    pub goal: StateSpec,
}

/// How to plan it.
#[derive(Debug, Clone, PartialEq)]
pub struct MotionOptions {
    /// Seed of every random choice (default: 1).
    pub seed: u64,
    /// How long the search may run before it gives up (default: 1 s).
    pub time_limit: Duration,
    /// Clearance kept from obstacles and between links the motion moves (m) (default: 0, as
    /// MoveIt; the ends of the motion are exempt).
    pub margin: Real,
    /// Random shortcut attempts on the path found (default: 100; 0 keeps the search's path).
    pub shortcut_attempts: usize,
    /// Fractions of the joints' velocity and acceleration limits used, in (0, 1] (default:
    /// the scene's `[trajectory]`, else the joint-limits file's, else 1).
    pub velocity_scaling: Option<Real>,
    /// See `velocity_scaling`.
    pub acceleration_scaling: Option<Real>,
    /// Period of the trajectory's samples (s) (default: 0.04, as a plan's).
    pub sample_period: Real,
    /// How far (rad) the timing may cut the path's corners (default: 0.1, as a plan's).
    pub blend_tolerance: Real,
}

impl Default for MotionOptions {
    fn default() -> Self {
        Self {
            seed: 1,
            time_limit: Duration::from_secs(1),
            margin: 0.0,
            shortcut_attempts: ShortcutOptions::default().attempts,
            velocity_scaling: None,
            acceleration_scaling: None,
            sample_period: 0.04,
            blend_tolerance: 0.1,
        }
    }
}

/// A planned motion: the document `pickplace motion --out` writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionPlan {
    /// Always [`MOTION_FORMAT`].
    pub format: String,
    /// The seed.
    pub seed: u64,
    /// The robot's name (its URDF's).
    pub robot: String,
    /// The planning group.
    pub group: String,
    /// The group's joints: the columns of the waypoints and of the trajectory.
    pub joint_names: Vec<String>,
    /// The limits the trajectory was timed with, scaling applied.
    pub limits: Limits,
    /// The collision-free path the trajectory follows (shortcut), start and goal included.
    pub waypoints: Vec<Vec<Real>>,
    /// The time-stamped trajectory, from rest at the start to rest at the goal.
    pub trajectory: Vec<TrajectoryPoint>,
    /// How it was found.
    pub stats: MotionStats,
    /// What loading went on from (robot files, cache), one line each.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
}

/// How a motion was found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionStats {
    /// Time of the search (ms).
    pub search_ms: f64,
    /// Time of shortcutting, timing and the final check (ms), over every attempt.
    pub timing_ms: f64,
    /// States the search checked.
    pub states_checked: usize,
    /// Searches made: 1, or more when a path's timed samples grazed an obstacle between the
    /// states its search checked and it was searched again further from everything.
    pub attempts: usize,
    /// Waypoints of the search's path, before shortcutting.
    pub raw_waypoints: usize,
    /// Joint-space length of the path (rad, or m for prismatic joints; Euclidean).
    pub length: Real,
    /// Duration of the trajectory (s).
    pub duration: Real,
}

impl MotionPlan {
    /// The motion as pretty JSON (with a final newline).
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a motion always serialises");
        s.push('\n');
        s
    }

    /// The same motion with its timings zeroed (for byte-identical outputs across runs).
    pub fn without_timings(mut self) -> Self {
        self.stats.search_ms = 0.0;
        self.stats.timing_ms = 0.0;
        self
    }
}

/// Why no motion came back: the query is well formed and has no solution within the options.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum NoMotion {
    /// The start state collides (the pair named, or clearance `margin` not kept).
    #[error("the start state is in collision: {0} touches {1}")]
    StartInCollision(String, String),
    /// The goal state collides.
    #[error("the goal state is in collision: {0} touches {1}")]
    GoalInCollision(String, String),
    /// The search found no path.
    #[error("no path found: {0}")]
    NotFound(String),
}

/// The outcome of a well-formed query.
#[derive(Debug, Clone, PartialEq)]
#[allow(clippy::large_enum_variant)]
pub enum MotionOutcome {
    /// A motion.
    Planned(MotionPlan),
    /// None, and why.
    NoMotion(NoMotion),
}

/// A collision-free, time-optimal motion of `request.group` from `request.start` to
/// `request.goal` (see the module's documentation).
///
/// # Errors
/// [`crate::Error::Invalid`] naming the world's file and the field (`group`, `start`, `goal`,
/// `options.…`) for a group the robot lacks or a state it cannot take (unknown joint or named
/// state, wrong count, outside the limits); [`crate::Error::TrajectoryLimit`] for a trajectory too
/// long to sample; [`crate::Error::Internal`] when the collision library fails.
pub fn plan_motion(
    world: &MotionWorld,
    request: &MotionRequest,
    options: &MotionOptions,
) -> Result<MotionOutcome> {
    check_options(world, options)?;
    let model = world.model();
    let (group, variables) = resolve_group(world, request.group.as_deref())?;
    let start = state(world, &group, &variables, &request.start, "start")?;
    let goal = state(world, &group, &variables, &request.goal, "goal")?;
    let space = crate::roadmaps::arm_space(model, &variables)?;
    let collision_world = world.collision_world();
    let name = |b| collision_world.body_name(b).to_owned();
    // The ends, exactly (the margin does not apply there).
    let exact = ArmChecker::new(
        model,
        collision_world,
        &variables,
        world.start().to_vec(),
        0.0,
    );
    for (q, is_start) in [(&start, true), (&goal, false)] {
        if let Some((a, b)) = exact.first_collision(q) {
            exact.check_error()?;
            let (a, b) = (name(a), name(b));
            return Ok(MotionOutcome::NoMotion(if is_start {
                NoMotion::StartInCollision(a, b)
            } else {
                NoMotion::GoalInCollision(a, b)
            }));
        }
    }
    let limits = timing_limits(world, &variables, options);
    let began = Instant::now();
    let (mut search_ms, mut states) = (0.0, 0);
    let mut attempt = 0;
    let (raw, path, trajectory) = loop {
        // The search keeps `margin`, then a little more on each new attempt: a path whose
        // timed samples graze an obstacle between the states the search checked is searched
        // again, further from everything (the ends exempt).
        let checker = ArmChecker::new(
            model,
            collision_world,
            &variables,
            world.start().to_vec(),
            options.margin + EXTRA_MARGIN[attempt],
        )
        .exempt(vec![start.clone(), goal.clone()], CHECK_STEP);
        let counting = Counting {
            inner: &checker,
            states: 0.into(),
        };
        let t = Instant::now();
        let found = pickplace_prm::rrt_connect(
            &space,
            &counting,
            &start,
            &goal,
            &RrtOptions {
                seed: pickplace_prm::rng::Rng::derive(options.seed, SEARCH_STREAM, attempt as u64)
                    .next_u64(),
                max_iterations: usize::MAX,
                time_limit: Some(options.time_limit.saturating_sub(began.elapsed())),
                resolution: CHECK_STEP,
                ..RrtOptions::default()
            },
        );
        search_ms += t.elapsed().as_secs_f64() * 1e3;
        states += counting.states.into_inner();
        checker.check_error()?;
        let raw = match found {
            Ok(path) => path,
            Err(e) => return Ok(MotionOutcome::NoMotion(NoMotion::NotFound(e.to_string()))),
        };
        let path = if options.shortcut_attempts > 0 {
            pickplace_prm::shortcut(
                &space,
                &checker,
                &raw,
                &ShortcutOptions {
                    attempts: options.shortcut_attempts,
                    resolution: CHECK_STEP,
                    seed: pickplace_prm::rng::Rng::derive(
                        options.seed,
                        SHORTCUT_STREAM,
                        attempt as u64,
                    )
                    .next_u64(),
                },
            )
            .unwrap_or_else(|_| raw.clone())
        } else {
            raw.clone()
        };
        checker.check_error()?;
        let waypoints: Vec<Vec<Real>> = path.waypoints().map(<[Real]>::to_vec).collect();
        let trajectory = time_checked(&waypoints, &limits, options.blend_tolerance, &exact)?;
        exact.check_error()?;
        attempt += 1;
        match trajectory {
            Some(trajectory) => break (raw, path, trajectory),
            None if attempt < EXTRA_MARGIN.len() => {}
            None => {
                return Ok(MotionOutcome::NoMotion(NoMotion::NotFound(format!(
                    "{attempt} paths found touch an obstacle between the states their search \
                     checked (at 1°), even {:.0} mm away from everything",
                    EXTRA_MARGIN[attempt - 1] * 1e3
                ))));
            }
        }
    };
    let waypoints: Vec<Vec<Real>> = path.waypoints().map(<[Real]>::to_vec).collect();
    let timing_ms = began.elapsed().as_secs_f64() * 1e3 - search_ms;
    let unit = JointSpace::with_unit_weights(space.lower().to_vec(), space.upper().to_vec())
        .map_err(crate::error::internal("joint space"))?;
    let names: Vec<String> = variables
        .iter()
        .filter_map(|&v| model.variable_names().nth(v).map(str::to_owned))
        .collect();
    let duration = trajectory.last().map_or(0.0, |p| p.time_from_start);
    Ok(MotionOutcome::Planned(MotionPlan {
        format: MOTION_FORMAT.into(),
        seed: options.seed,
        robot: model.name().to_owned(),
        group,
        joint_names: names,
        limits: Limits {
            velocities: limits.max_velocities.clone(),
            accelerations: limits.max_accelerations.clone(),
            velocity_scaling: options.velocity_scaling.unwrap_or(world.scaling.0),
            acceleration_scaling: options.acceleration_scaling.unwrap_or(world.scaling.1),
        },
        stats: MotionStats {
            search_ms,
            timing_ms,
            states_checked: states,
            attempts: attempt,
            raw_waypoints: raw.len(),
            length: path.length(&unit),
            duration,
        },
        waypoints,
        trajectory,
        warnings: world.warnings().to_vec(),
    }))
}

/// The options' values in range.
fn check_options(world: &MotionWorld, o: &MotionOptions) -> Result<()> {
    use crate::ranges;
    let check = |field: &str, value: Real, range: ranges::Range| {
        range
            .check(value)
            .map_err(|e| world.invalid(&format!("options.{field}"), e.to_string()))
    };
    check(
        "time_limit",
        o.time_limit.as_secs_f64(),
        ranges::TIME_BUDGET,
    )?;
    check("margin", o.margin, ranges::CLEARANCE)?;
    check("sample_period", o.sample_period, ranges::SAMPLE_PERIOD)?;
    check("blend_tolerance", o.blend_tolerance, ranges::PLANNER_ANGLE)?;
    for (field, v) in [
        ("velocity_scaling", o.velocity_scaling),
        ("acceleration_scaling", o.acceleration_scaling),
    ] {
        if let Some(v) = v {
            check(field, v, ranges::SCALING)?;
        }
    }
    Ok(())
}

/// The group's name and variables: the one asked for, else the robot's only group that moves
/// joints, else (no group at all) every actuated joint as `all`.
fn resolve_group(world: &MotionWorld, group: Option<&str>) -> Result<(String, Vec<usize>)> {
    let semantics = &world.robot.semantics;
    let moving: Vec<_> = semantics
        .groups()
        .iter()
        .filter(|g| !g.variables.is_empty())
        .collect();
    let too_many = |name: &str, n: usize| {
        if n > pickplace_prm::MAX_DIMENSION {
            Err(world.invalid(
                "group",
                format!(
                    "group {name:?} moves {n} joints; a motion plans at most {} at once: name a \
                     smaller group",
                    pickplace_prm::MAX_DIMENSION
                ),
            ))
        } else {
            Ok(())
        }
    };
    let listing = || {
        if moving.is_empty() {
            "the robot has no planning group".to_owned()
        } else {
            format!(
                "groups: {}",
                moving
                    .iter()
                    .map(|g| {
                        let n = g.variables.len();
                        format!("{} ({n} joint{})", g.name, if n == 1 { "" } else { "s" })
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        }
    };
    match group {
        Some(name) => {
            let g = semantics
                .group(name)
                .map_err(|e| world.invalid("group", format!("{e} ({})", listing())))?;
            if g.variables.is_empty() {
                return Err(world.invalid(
                    "group",
                    format!("group {name:?} moves no actuated joint ({})", listing()),
                ));
            }
            too_many(name, g.variables.len())?;
            Ok((name.to_owned(), g.variables.clone()))
        }
        None => match moving.as_slice() {
            [g] => Ok((g.name.clone(), g.variables.clone())),
            [] if semantics.groups().is_empty() => {
                let n = world.model().variable_count();
                too_many("all", n)?;
                Ok(("all".into(), (0..n).collect()))
            }
            _ => Err(world.invalid(
                "group",
                format!("missing: the robot has several; name one ({})", listing()),
            )),
        },
    }
}

/// The group's values of a state, within the joints' limits (continuous joints wrapped into
/// [−π, π)).
fn state(
    world: &MotionWorld,
    group: &str,
    variables: &[usize],
    spec: &StateSpec,
    field: &str,
) -> Result<Vec<Real>> {
    let model = world.model();
    let name_of = |v: usize| model.variable_names().nth(v).unwrap_or_default().to_owned();
    let mut full = world.start().to_vec();
    match spec {
        StateSpec::Named(name) => {
            let semantics = &world.robot.semantics;
            let states = &semantics.srdf().group_states;
            if !states.iter().any(|s| &s.name == name) {
                let known: Vec<&str> = states
                    .iter()
                    .filter(|s| s.group == group)
                    .map(|s| s.name.as_str())
                    .collect();
                return Err(world.invalid(
                    field,
                    format!(
                        "the SRDF has no group_state {name:?} (those of group {group:?}: {})",
                        if known.is_empty() {
                            "none".to_owned()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            }
            semantics
                .apply_state(model, name, &mut full)
                .map_err(|e| world.invalid(field, e.to_string()))?;
        }
        StateSpec::Values(values) => {
            if values.len() != variables.len() {
                return Err(world.invalid(
                    field,
                    format!(
                        "{} values for the {} joints of group {group:?} ({})",
                        values.len(),
                        variables.len(),
                        variables
                            .iter()
                            .map(|&v| name_of(v))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                ));
            }
            for (&v, &x) in variables.iter().zip(values) {
                full[v] = x;
            }
        }
        StateSpec::Joints(by_name) => {
            for (name, &x) in by_name {
                let v = model
                    .variable_index(name)
                    .filter(|v| variables.contains(v))
                    .ok_or_else(|| {
                        world.invalid(
                            field,
                            format!("group {group:?} has no actuated joint {name:?}"),
                        )
                    })?;
                full[v] = x;
            }
        }
    }
    let mut out = Vec::with_capacity(variables.len());
    for &v in variables {
        let mut x = full[v];
        let limits = model.variable_joint(v).limits;
        if !x.is_finite() {
            return Err(world.invalid(
                field,
                format!("joint {:?}: {} is not finite", name_of(v), fmt_real(x)),
            ));
        }
        if !limits.lower.is_finite() && !limits.upper.is_finite() {
            x = (x + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        } else if !limits.contains(x, 1e-9) {
            return Err(world.invalid(
                field,
                format!(
                    "joint {:?}: {} is outside its limits [{}, {}]",
                    name_of(v),
                    fmt_real(x),
                    fmt_real(limits.lower),
                    fmt_real(limits.upper)
                ),
            ));
        }
        out.push(x.clamp(limits.lower, limits.upper));
    }
    Ok(out)
}

/// The group's timing limits, scaled.
fn timing_limits(world: &MotionWorld, variables: &[usize], o: &MotionOptions) -> ToppraOptions {
    let vs = o.velocity_scaling.unwrap_or(world.scaling.0);
    let acs = o.acceleration_scaling.unwrap_or(world.scaling.1);
    let timing = &world.robot.timing;
    ToppraOptions {
        max_velocities: variables.iter().map(|&v| timing[v].velocity * vs).collect(),
        max_accelerations: variables
            .iter()
            .map(|&v| timing[v].acceleration * acs)
            .collect(),
        sample_period: o.sample_period,
        ..ToppraOptions::default()
    }
}

/// The path timed with its corners blended, every pair of consecutive samples free at 1° by
/// `exact`; a blend that is not is tightened ([`crate::timing::tighten`]) until it is or the
/// robot stops at that corner. `None` when a pair collides with no corner to tighten (a
/// straight piece between the search's checks).
fn time_checked(
    waypoints: &[Vec<Real>],
    limits: &ToppraOptions,
    blend: Real,
    exact: &ArmChecker<'_>,
) -> Result<Option<Vec<TrajectoryPoint>>> {
    let n = waypoints.first().map_or(0, Vec::len);
    let mut tolerances = vec![blend; waypoints.len()];
    let mut tightened = vec![0usize; waypoints.len()];
    loop {
        let parts = BlendedPath::split_with(waypoints, &tolerances).map_err(timing_error)?;
        let mut timed = time_parts(&parts, limits, waypoints.first(), n)?;
        snap_part_ends(&mut timed, &parts, waypoints);
        let mut failed = std::collections::BTreeSet::new();
        let mut unfixable = false;
        for (i, w) in timed.points.windows(2).enumerate() {
            if !segment_free(exact, &w[0].positions, &w[1].positions) {
                let ((k0, s0), (k1, s1)) = (timed.at[i], timed.at[i + 1]);
                let s0 = if k0 == k1 { s0 } else { 0.0 };
                let corners = parts
                    .get(k1)
                    .map(|p| p.corners_between(s0, s1))
                    .unwrap_or_default();
                unfixable |= corners.is_empty();
                failed.extend(corners);
            }
        }
        if unfixable {
            return Ok(None);
        }
        if failed.is_empty() {
            return Ok(Some(
                timed
                    .points
                    .into_iter()
                    .map(|p| TrajectoryPoint {
                        time_from_start: round_time(p.time_from_start),
                        positions: p.positions,
                        velocities: p.velocities,
                        accelerations: p.accelerations,
                    })
                    .collect(),
            ));
        }
        tighten(&mut tolerances, &mut tightened, failed);
    }
}

/// Times rounded to the microsecond, as a plan's.
fn round_time(t: Real) -> Real {
    (t * 1e6).round() / 1e6
}

/// Whether every state from `a` to `b` (straight in joint space, at most 1° apart, both ends
/// included) is valid.
fn segment_free(checker: &ArmChecker<'_>, a: &[Real], b: &[Real]) -> bool {
    let span = a
        .iter()
        .zip(b)
        .map(|(x, y)| (y - x).abs())
        .fold(0.0, Real::max);
    let steps = (span / CHECK_STEP).ceil().max(1.0) as usize;
    let mut q = a.to_vec();
    (0..=steps).all(|k| {
        let t = k as Real / steps as Real;
        for ((qi, x), y) in q.iter_mut().zip(a).zip(b) {
            *qi = x + (y - x) * t;
        }
        checker.is_state_valid(&q)
    })
}

/// A checker that counts the states it is asked about.
struct Counting<'a, C> {
    inner: &'a C,
    states: std::sync::atomic::AtomicUsize,
}

impl<C: ValidityChecker> ValidityChecker for Counting<'_, C> {
    fn is_state_valid(&self, q: &[Real]) -> bool {
        self.states
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.is_state_valid(q)
    }
}
