//! Bidirectional RRT-Connect: a single-query baseline for the roadmap planners.

use crate::error::{Error, Result};
use crate::nn::GrowingIndex;
use crate::path::Path;
use crate::rng::{Rng, stream};
use crate::space::JointSpace;
use crate::validity::{DEFAULT_MAX_JOINT_STEP, ValidityChecker};

/// Options of [`rrt_connect`].
#[derive(Clone, Debug, PartialEq)]
pub struct RrtOptions {
    /// Iterations (one random sample each) before giving up (default: 10000).
    pub max_iterations: usize,
    /// Longest extension step, as a weighted distance (default: 0.3).
    pub step: f64,
    /// Largest distance between two consecutive checked states along a step, both as a
    /// weighted distance and per joint (max-norm, joint units; see
    /// [`crate::motion_valid_by_interpolation`]) (default: [`DEFAULT_MAX_JOINT_STEP`], 1°,
    /// the validator's joint step). A coarser value is faster but proves only the states
    /// sampled that far apart: the path may cross obstacles thinner than it.
    pub resolution: f64,
    /// Seed of the random samples (default: 0).
    pub seed: u64,
    /// Wall-clock time after which the search gives up (default: none: `max_iterations`
    /// alone ends it). With a limit, whether a path is found depends on the machine's speed
    /// when the limit is reached; the path found does not.
    pub time_limit: Option<std::time::Duration>,
}

impl Default for RrtOptions {
    fn default() -> Self {
        Self {
            max_iterations: 10_000,
            step: 0.3,
            resolution: DEFAULT_MAX_JOINT_STEP,
            seed: 0,
            time_limit: None,
        }
    }
}

/// A tree stored flat, with parent indices and its nearest-state index.
struct Tree {
    states: Vec<f64>,
    parents: Vec<u32>,
    index: GrowingIndex,
}

impl Tree {
    fn new(space: &JointSpace, root: &[f64]) -> Self {
        Self {
            states: root.to_vec(),
            parents: vec![u32::MAX],
            index: GrowingIndex::new(space.weights()),
        }
    }

    fn nearest(&mut self, target: &[f64]) -> usize {
        self.index.nearest(&self.states, target)
    }
}

#[derive(PartialEq, Eq)]
enum Extend {
    Trapped,
    Advanced,
    Reached,
}

struct Context<'a, C: ?Sized> {
    space: &'a JointSpace,
    checker: &'a C,
    options: &'a RrtOptions,
    new_state: Vec<f64>,
    scratch: Vec<f64>,
}

impl<C: ValidityChecker + ?Sized> Context<'_, C> {
    /// Extends `tree` one step toward `target`.
    fn extend(&mut self, tree: &mut Tree, target: &[f64]) -> Extend {
        let d = self.space.dimension();
        let near = tree.nearest(target);
        let from = &tree.states[near * d..(near + 1) * d];
        let distance = self.space.distance(from, target);
        let reached = distance <= self.options.step;
        let t = if reached {
            1.0
        } else {
            self.options.step / distance
        };
        self.space
            .interpolate_into(from, target, t, &mut self.new_state);
        if !self.checker.is_state_valid(&self.new_state)
            || !self.checker.is_motion_valid(
                self.space,
                from,
                &self.new_state,
                self.options.resolution,
                &mut self.scratch,
            )
        {
            return Extend::Trapped;
        }
        tree.states.extend_from_slice(&self.new_state);
        tree.parents.push(near as u32);
        if reached {
            Extend::Reached
        } else {
            Extend::Advanced
        }
    }
}

/// Plans from `start` to `goal` by growing one tree from each and connecting them greedily
/// (Kuffner and LaValle's RRT-Connect).
///
/// Nearest neighbours are found by a linear scan while a tree is small and by a k-d tree
/// (kiddo) once it holds a few hundred states.
/// The path is not shortened: see [`crate::shortcut()`].
///
/// # Guarantee
/// The path starts at `start` and ends at `goal`; every waypoint was accepted by
/// [`ValidityChecker::is_state_valid`] and every segment between consecutive waypoints by
/// [`ValidityChecker::is_motion_valid`] at `options.resolution`. With the default checker
/// motion test and the default resolution ([`DEFAULT_MAX_JOINT_STEP`]), consecutive checked
/// states are at most 1° apart in every joint (max-norm) and in the weighted distance: the
/// validator's density. Nothing is claimed between checked states.
///
/// # Errors
/// [`Error::StateDimension`] / [`Error::StateOutOfBounds`]; [`Error::StartInvalid`] /
/// [`Error::GoalInvalid`]; [`Error::InvalidOption`] for a non-positive step or resolution;
/// [`Error::RrtExhausted`] after `max_iterations`; [`Error::RrtOutOfTime`] once
/// `options.time_limit` is spent.
pub fn rrt_connect<C: ValidityChecker + ?Sized>(
    space: &JointSpace,
    checker: &C,
    start: &[f64],
    goal: &[f64],
    options: &RrtOptions,
) -> Result<Path> {
    space.check_state(start)?;
    space.check_state(goal)?;
    for (name, value) in [("step", options.step), ("resolution", options.resolution)] {
        if !(value > 0.0 && value.is_finite()) {
            return Err(Error::InvalidOption {
                name,
                value,
                expected: "a finite positive distance",
            });
        }
    }
    if !checker.is_state_valid(start) {
        return Err(Error::StartInvalid);
    }
    if !checker.is_state_valid(goal) {
        return Err(Error::GoalInvalid);
    }
    let d = space.dimension();
    let mut context = Context {
        space,
        checker,
        options,
        new_state: vec![0.0; d],
        scratch: vec![0.0; d],
    };
    let mut from_start = Tree::new(space, start);
    let mut from_goal = Tree::new(space, goal);
    let mut sample = vec![0.0; d];
    let mut target = vec![0.0; d];
    let mut rng = Rng::derive(options.seed, stream::RRT, 0);
    let deadline = options
        .time_limit
        .and_then(|limit| std::time::Instant::now().checked_add(limit));
    for iteration in 0..options.max_iterations {
        // The clock every 32 iterations: reading it costs about what a nearest-state
        // query on a small tree does.
        if iteration % 32 == 31
            && let Some(deadline) = deadline
            && std::time::Instant::now() >= deadline
        {
            return Err(Error::RrtOutOfTime {
                seconds: options.time_limit.map_or(0.0, |l| l.as_secs_f64()),
                iterations: iteration,
            });
        }
        let start_side = iteration % 2 == 0;
        let (a, b) = if start_side {
            (&mut from_start, &mut from_goal)
        } else {
            (&mut from_goal, &mut from_start)
        };
        space.sample_into(&mut rng, &mut sample);
        if context.extend(a, &sample) == Extend::Trapped {
            continue;
        }
        target.copy_from_slice(&context.new_state);
        let mut status = Extend::Advanced;
        while status == Extend::Advanced {
            status = context.extend(b, &target);
        }
        if status == Extend::Reached {
            let (a_leaf, b_leaf) = (a.parents.len() - 1, b.parents.len() - 1);
            let (start_leaf, goal_leaf) = if start_side {
                (a_leaf, b_leaf)
            } else {
                (b_leaf, a_leaf)
            };
            return Ok(assemble(d, &from_start, start_leaf, &from_goal, goal_leaf));
        }
    }
    Err(Error::RrtExhausted {
        iterations: options.max_iterations,
    })
}

/// Root-to-leaf of the start tree, then leaf-to-root of the goal tree (the two leaves coincide).
fn assemble(d: usize, start: &Tree, start_leaf: usize, goal: &Tree, goal_leaf: usize) -> Path {
    let mut chain = Vec::new();
    let mut node = start_leaf as u32;
    while node != u32::MAX {
        chain.push(node);
        node = start.parents[node as usize];
    }
    let mut path = Path::new(d);
    for &i in chain.iter().rev() {
        path.push_unchecked(&start.states[i as usize * d..(i as usize + 1) * d]);
    }
    // Skip the goal tree's leaf: it equals the start tree's leaf.
    let mut node = goal.parents[goal_leaf];
    while node != u32::MAX {
        path.push_unchecked(&goal.states[node as usize * d..(node as usize + 1) * d]);
        node = goal.parents[node as usize];
    }
    path
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_a_way_through_a_gap() {
        let space = JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space");
        let wall = |q: &[f64]| !(0.45..0.55).contains(&q[0]) || (0.6..0.7).contains(&q[1]);
        let options = RrtOptions {
            resolution: 0.005,
            step: 0.1,
            ..RrtOptions::default()
        };
        let path = rrt_connect(&space, &wall, &[0.1, 0.1], &[0.9, 0.1], &options).expect("path");
        assert_eq!(path.waypoint(0), &[0.1, 0.1]);
        assert_eq!(path.waypoint(path.len() - 1), &[0.9, 0.1]);
        assert!(path.is_valid(&space, &wall, 0.0005));
        let closed = |q: &[f64]| !(0.45..0.55).contains(&q[0]);
        let short = RrtOptions {
            max_iterations: 200,
            ..options
        };
        assert!(matches!(
            rrt_connect(&space, &closed, &[0.1, 0.1], &[0.9, 0.1], &short),
            Err(Error::RrtExhausted { iterations: 200 })
        ));
    }
}
