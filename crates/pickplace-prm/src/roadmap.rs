//! PRM roadmap construction (Harada et al. §III-C: "we plan collision free trajectories between
//! [key poses] by using the PRM").
//!
//! Construction is parallel (rayon) and deterministic: sample `i` draws from a generator derived
//! from `(seed, i)`, every node's neighbours are found independently, and the candidate edges are
//! merged by sorting. The same options give the same roadmap whatever the number of threads.

use rayon::prelude::*;

use crate::error::{Error, Result};
use crate::nn::NearestIndex;
use crate::rng::{Rng, stream};
use crate::space::JointSpace;
use crate::validity::{AlwaysValid, DEFAULT_MAX_JOINT_STEP, ValidityChecker};

/// Options of roadmap construction.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RoadmapOptions {
    /// Number of samples drawn; with a checker, a sample that stays invalid after
    /// `max_sample_attempts` draws is dropped (default: 1000).
    pub node_count: usize,
    /// Number of nearest neighbours each node tries to connect to (default: 10).
    pub neighbors: usize,
    /// Longest edge, as a weighted distance; `f64::INFINITY` for no limit (default: `f64::INFINITY`).
    pub max_edge_length: f64,
    /// Largest distance between two consecutive states checked along an edge, both as a
    /// weighted distance and per joint (max-norm, joint units; see
    /// [`crate::motion_valid_by_interpolation`]) (default: [`DEFAULT_MAX_JOINT_STEP`], 1°,
    /// the validator's joint step).
    ///
    /// The roadmap's queries ([`crate::PrmPlanner::query`]) check their edges at this
    /// resolution too. A coarser value (e.g. 0.05 rad) is faster but only proves the states
    /// sampled that far apart: a returned path may then cross obstacles thinner than it, unless
    /// the checker keeps a margin of half the resolution.
    pub resolution: f64,
    /// Seed of every random draw (default: 0).
    pub seed: u64,
    /// Draws per sample before giving up on it (default: 100).
    pub max_sample_attempts: usize,
}

impl Default for RoadmapOptions {
    fn default() -> Self {
        Self {
            node_count: 1000,
            neighbors: 10,
            max_edge_length: f64::INFINITY,
            resolution: DEFAULT_MAX_JOINT_STEP,
            seed: 0,
            max_sample_attempts: 100,
        }
    }
}

impl RoadmapOptions {
    /// Checks the option ranges.
    ///
    /// # Errors
    /// [`Error::InvalidOption`] naming the first offending field.
    pub fn validate(&self) -> Result<()> {
        if self.node_count > u32::MAX as usize / 2 {
            return Err(Error::InvalidOption {
                name: "node_count",
                value: self.node_count as f64,
                expected: "at most 2^31 nodes",
            });
        }
        if self.neighbors == 0 {
            return Err(Error::InvalidOption {
                name: "neighbors",
                value: 0.0,
                expected: "at least 1",
            });
        }
        if self.max_edge_length.is_nan() || self.max_edge_length <= 0.0 {
            return Err(Error::InvalidOption {
                name: "max_edge_length",
                value: self.max_edge_length,
                expected: "a positive length or infinity",
            });
        }
        if !(self.resolution > 0.0 && self.resolution.is_finite()) {
            return Err(Error::InvalidOption {
                name: "resolution",
                value: self.resolution,
                expected: "a finite positive distance",
            });
        }
        if self.max_sample_attempts == 0 {
            return Err(Error::InvalidOption {
                name: "max_sample_attempts",
                value: 0.0,
                expected: "at least 1",
            });
        }
        Ok(())
    }
}

/// How the roadmap's nodes and edges were validated at construction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Validation {
    /// Every node and edge was checked against the construction checker: the roadmap is valid in
    /// that environment only.
    Checked,
    /// Nothing was checked: nodes and edges are checked lazily by each query's checker, so one
    /// roadmap serves many environments (lazy PRM).
    Lazy,
    /// Nodes and edges were checked against an environment-independent checker (the robot's
    /// self-collisions): queries still check them lazily against their own environment. The
    /// roadmap serves every environment, without the nodes that no environment can use.
    Prefiltered,
}

/// A probabilistic roadmap: states, undirected edges, adjacency and connected components.
///
/// Immutable once built and `Send + Sync`: share one roadmap between planners of several
/// environments ([`crate::PrmPlanner`]).
#[derive(Debug)]
pub struct Roadmap {
    space: JointSpace,
    options: RoadmapOptions,
    validation: Validation,
    states: Vec<f64>,
    edges: Vec<[u32; 2]>,
    edge_lengths: Vec<f64>,
    offsets: Vec<u32>,
    adjacency: Vec<(u32, u32)>,
    components: Vec<u32>,
    component_count: usize,
    index: NearestIndex,
}

impl PartialEq for Roadmap {
    /// Roadmaps are equal when their space, options, validation, states and edges are equal
    /// (everything else is derived from these).
    fn eq(&self, other: &Self) -> bool {
        self.space == other.space
            && self.options == other.options
            && self.validation == other.validation
            && self.states == other.states
            && self.edges == other.edges
    }
}

/// Version of what the roadmap constructions compute. Bump it whenever [`Roadmap::build`],
/// [`Roadmap::build_prefiltered`] or [`Roadmap::build_lazy`] give other nodes or edges for the
/// same space, checker and options (a new sampling stream, another neighbour rule): callers
/// that cache roadmaps put it in their key, so a newer build never reuses an older one's.
///
/// 2: edges are checked at most `resolution` apart per joint as well as in the weighted
/// distance (issue 33), which removes edges of spaces with a weight below 1 (unit-weight
/// spaces build the same roadmaps as in 1).
pub const ALGORITHM_VERSION: u32 = 2;

/// Progress of a construction shared by the pool's threads: `done` out of `total` units,
/// passed on when it crosses a percent.
struct Ticks<'a> {
    progress: &'a (dyn Fn(usize, usize) + Sync),
    total: usize,
    done: std::sync::atomic::AtomicUsize,
}

impl<'a> Ticks<'a> {
    fn new(progress: &'a (dyn Fn(usize, usize) + Sync), total: usize) -> Self {
        Self {
            progress,
            total,
            done: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    fn report(&self, done: usize) {
        (self.progress)(done, self.total);
    }

    /// `k` more units; the total itself is said once, by [`Ticks::finish`].
    fn add(&self, k: usize) {
        if k == 0 {
            return;
        }
        let before = self.done.fetch_add(k, std::sync::atomic::Ordering::Relaxed);
        let after = before + k;
        let step = (self.total / 100).max(1);
        if after / step != before / step && after < self.total {
            self.report(after);
        }
    }

    fn finish(&self) {
        self.report(self.total);
    }
}

impl Roadmap {
    /// Builds a roadmap whose nodes and edges are all valid for `checker` ([`Validation::Checked`]).
    ///
    /// Runs on the current rayon pool (use `ThreadPool::install` to choose the threads).
    ///
    /// # Errors
    /// [`Error::InvalidOption`] for bad options; [`Error::NearestIndex`] if the k-d tree fails.
    ///
    /// # Performance
    /// `node_count` sampling calls (more when samples are invalid), `node_count` k-NN queries and
    /// one motion check per distinct candidate edge (at most `node_count * neighbors`), all spread
    /// over the pool's threads.
    pub fn build<C: ValidityChecker + ?Sized>(
        space: &JointSpace,
        checker: &C,
        options: &RoadmapOptions,
    ) -> Result<Self> {
        Self::construct(space, checker, options, Validation::Checked, &|_, _| {})
    }

    /// Builds a roadmap valid for `prefilter` ([`Validation::Prefiltered`]), for lazy queries in
    /// any environment that `prefilter` is part of (e.g. `prefilter` checks self-collisions and
    /// the queries check self-collisions and the scene).
    ///
    /// # Errors
    /// As [`Roadmap::build`].
    pub fn build_prefiltered<C: ValidityChecker + ?Sized>(
        space: &JointSpace,
        prefilter: &C,
        options: &RoadmapOptions,
    ) -> Result<Self> {
        Self::construct(
            space,
            prefilter,
            options,
            Validation::Prefiltered,
            &|_, _| {},
        )
    }

    /// [`Roadmap::build_prefiltered`], telling `progress(done, total)` how far it got: `total`
    /// is twice `node_count`, the samples count for the first half and the candidate edges
    /// checked for the second. Called from the pool's threads about a hundred times, not
    /// always in increasing order of `done`; the last call is `(total, total)`. The roadmap is
    /// the same as [`Roadmap::build_prefiltered`]'s.
    ///
    /// # Errors
    /// As [`Roadmap::build`].
    pub fn build_prefiltered_with_progress<C: ValidityChecker + ?Sized>(
        space: &JointSpace,
        prefilter: &C,
        options: &RoadmapOptions,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Self> {
        Self::construct(space, prefilter, options, Validation::Prefiltered, progress)
    }

    /// Builds a roadmap without any validity check ([`Validation::Lazy`]), for lazy queries in
    /// any environment.
    ///
    /// # Errors
    /// As [`Roadmap::build`].
    pub fn build_lazy(space: &JointSpace, options: &RoadmapOptions) -> Result<Self> {
        Self::construct(space, &AlwaysValid, options, Validation::Lazy, &|_, _| {})
    }

    fn construct<C: ValidityChecker + ?Sized>(
        space: &JointSpace,
        checker: &C,
        options: &RoadmapOptions,
        validation: Validation,
        progress: &(dyn Fn(usize, usize) + Sync),
    ) -> Result<Self> {
        options.validate()?;
        let dimension = space.dimension();
        let n = options.node_count;
        let ticks = Ticks::new(progress, 2 * n);
        ticks.report(0);

        // Sample in parallel; sample i is drawn from its own generator.
        let mut samples = vec![0.0; n * dimension];
        let mut sampled = vec![false; n];
        samples
            .par_chunks_mut(dimension)
            .zip(sampled.par_iter_mut())
            .enumerate()
            .for_each(|(i, (state, ok))| {
                let mut rng = Rng::derive(options.seed, stream::ROADMAP_SAMPLE, i as u64);
                for _ in 0..options.max_sample_attempts {
                    space.sample_into(&mut rng, state);
                    if checker.is_state_valid(state) {
                        *ok = true;
                        break;
                    }
                }
                ticks.add(1);
            });
        let states: Vec<f64> = samples
            .chunks_exact(dimension)
            .zip(&sampled)
            .filter(|(_, ok)| **ok)
            .flat_map(|(state, _)| state.iter().copied())
            .collect();
        let index = NearestIndex::build(&states, space.weights())?;
        let node_count = states.len() / dimension;

        // Candidate edges: each node's k nearest, found in parallel, merged in a fixed order.
        let max_squared = options.max_edge_length * options.max_edge_length;
        let mut candidates: Vec<[u32; 2]> = states
            .par_chunks_exact(dimension)
            .enumerate()
            .map_init(Vec::new, |found, (i, state)| {
                found.clear();
                index.k_nearest(state, options.neighbors + 1, found);
                found
                    .iter()
                    .filter(|&&(d2, j)| j as usize != i && d2 <= max_squared)
                    .map(|&(_, j)| {
                        let (i, j) = (i as u32, j);
                        if i < j { [i, j] } else { [j, i] }
                    })
                    .collect::<Vec<_>>()
            })
            .flatten_iter()
            .collect();
        candidates.par_sort_unstable();
        candidates.dedup();

        let state_of = |i: u32| &states[i as usize * dimension..(i as usize + 1) * dimension];
        let edges: Vec<[u32; 2]> = match validation {
            Validation::Lazy => candidates,
            Validation::Checked | Validation::Prefiltered => {
                // The second half of the work: edges checked, scaled to `n` units.
                let checked = std::sync::atomic::AtomicUsize::new(0);
                let edge_count = candidates.len().max(1);
                let keep: Vec<bool> = candidates
                    .par_iter()
                    .map_init(
                        || vec![0.0; dimension],
                        |scratch, &[a, b]| {
                            let ok = checker.is_motion_valid(
                                space,
                                state_of(a),
                                state_of(b),
                                options.resolution,
                                scratch,
                            );
                            let k = checked.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                            let before = n * k / edge_count;
                            let after = n * (k + 1) / edge_count;
                            ticks.add(after - before);
                            ok
                        },
                    )
                    .collect();
                candidates
                    .into_iter()
                    .zip(keep)
                    .filter_map(|(edge, ok)| ok.then_some(edge))
                    .collect()
            }
        };
        debug_assert!(edges.iter().all(|e| (e[1] as usize) < node_count));
        ticks.finish();
        Ok(Self::assemble(
            space.clone(),
            options.clone(),
            validation,
            states,
            edges,
            index,
        ))
    }

    /// Rebuilds a roadmap from stored parts, checking them (used by the codec).
    pub(crate) fn from_parts(
        space: JointSpace,
        options: RoadmapOptions,
        validation: Validation,
        states: Vec<f64>,
        edges: Vec<[u32; 2]>,
    ) -> Result<Self> {
        options.validate()?;
        let dimension = space.dimension();
        if !states.len().is_multiple_of(dimension) {
            return Err(Error::CorruptRoadmap {
                what: "state array length is not a multiple of the dimension",
                index: states.len(),
            });
        }
        let node_count = states.len() / dimension;
        if node_count > options.node_count {
            return Err(Error::CorruptRoadmap {
                what: "more nodes than the stored node_count",
                index: node_count,
            });
        }
        for (i, state) in states.chunks_exact(dimension).enumerate() {
            if !space.contains(state) {
                return Err(Error::CorruptRoadmap {
                    what: "state outside the joint bounds",
                    index: i,
                });
            }
        }
        let mut previous: Option<[u32; 2]> = None;
        for (e, &[a, b]) in edges.iter().enumerate() {
            if a >= b || b as usize >= node_count {
                return Err(Error::CorruptRoadmap {
                    what: "edge endpoints out of range or unordered",
                    index: e,
                });
            }
            if previous.is_some_and(|p| p >= [a, b]) {
                return Err(Error::CorruptRoadmap {
                    what: "edges not sorted or repeated",
                    index: e,
                });
            }
            previous = Some([a, b]);
        }
        let index = NearestIndex::build(&states, space.weights())?;
        Ok(Self::assemble(
            space, options, validation, states, edges, index,
        ))
    }

    fn assemble(
        space: JointSpace,
        options: RoadmapOptions,
        validation: Validation,
        states: Vec<f64>,
        edges: Vec<[u32; 2]>,
        index: NearestIndex,
    ) -> Self {
        let dimension = space.dimension();
        let n = states.len() / dimension;
        let state_of = |i: u32| &states[i as usize * dimension..(i as usize + 1) * dimension];
        let edge_lengths: Vec<f64> = edges
            .iter()
            .map(|&[a, b]| space.distance(state_of(a), state_of(b)))
            .collect();

        // Compressed adjacency, filled in edge order.
        let mut offsets = vec![0u32; n + 1];
        for &[a, b] in &edges {
            offsets[a as usize + 1] += 1;
            offsets[b as usize + 1] += 1;
        }
        for i in 0..n {
            offsets[i + 1] += offsets[i];
        }
        let mut fill: Vec<u32> = offsets[..n].to_vec();
        let mut adjacency = vec![(0u32, 0u32); edges.len() * 2];
        for (e, &[a, b]) in edges.iter().enumerate() {
            adjacency[fill[a as usize] as usize] = (b, e as u32);
            fill[a as usize] += 1;
            adjacency[fill[b as usize] as usize] = (a, e as u32);
            fill[b as usize] += 1;
        }

        // Connected components by union-find, labelled in order of their smallest node.
        let mut parent: Vec<u32> = (0..n as u32).collect();
        fn find(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                let grand = parent[parent[x as usize] as usize];
                parent[x as usize] = grand;
                x = grand;
            }
            x
        }
        for &[a, b] in &edges {
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            if ra != rb {
                let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
                parent[hi as usize] = lo;
            }
        }
        let mut label = vec![u32::MAX; n];
        let mut components = vec![0u32; n];
        let mut component_count = 0usize;
        for i in 0..n as u32 {
            let root = find(&mut parent, i) as usize;
            if label[root] == u32::MAX {
                label[root] = component_count as u32;
                component_count += 1;
            }
            components[i as usize] = label[root];
        }

        Self {
            space,
            options,
            validation,
            states,
            edges,
            edge_lengths,
            offsets,
            adjacency,
            components,
            component_count,
            index,
        }
    }

    /// The joint space the roadmap was built for.
    pub fn space(&self) -> &JointSpace {
        &self.space
    }

    /// The options the roadmap was built with.
    pub fn options(&self) -> &RoadmapOptions {
        &self.options
    }

    /// How nodes and edges were validated at construction.
    pub fn validation(&self) -> Validation {
        self.validation
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.components.len()
    }

    /// Number of undirected edges.
    pub fn edge_count(&self) -> usize {
        self.edges.len()
    }

    /// State of node `i` (panics when out of range, like slice indexing).
    #[inline]
    pub fn state(&self, i: usize) -> &[f64] {
        let d = self.space.dimension();
        &self.states[i * d..(i + 1) * d]
    }

    /// All node states, node after node.
    pub fn states(&self) -> &[f64] {
        &self.states
    }

    /// Edges as `[a, b]` with `a < b`, sorted.
    pub fn edges(&self) -> &[[u32; 2]] {
        &self.edges
    }

    /// Weighted length of edge `e`.
    #[inline]
    pub fn edge_length(&self, e: usize) -> f64 {
        self.edge_lengths[e]
    }

    /// Neighbours of node `i` as `(neighbour, edge index)`.
    #[inline]
    pub fn neighbors(&self, i: usize) -> &[(u32, u32)] {
        &self.adjacency[self.offsets[i] as usize..self.offsets[i + 1] as usize]
    }

    /// Connected component label of node `i` (labels are `0..component_count()`).
    pub fn component(&self, i: usize) -> u32 {
        self.components[i]
    }

    /// Number of connected components.
    pub fn component_count(&self) -> usize {
        self.component_count
    }

    /// Appends the `k` nearest nodes to `state` as `(squared weighted distance, node)`.
    #[inline]
    pub(crate) fn k_nearest(&self, state: &[f64], k: usize, out: &mut Vec<(f64, u32)>) {
        self.index.k_nearest(state, k, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> JointSpace {
        JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space")
    }

    #[test]
    fn checked_roadmap_avoids_the_obstacle() {
        let wall = |q: &[f64]| !((0.45..0.55).contains(&q[0]) && q[1] < 0.8);
        let options = RoadmapOptions {
            node_count: 300,
            resolution: 0.01,
            ..RoadmapOptions::default()
        };
        let roadmap = Roadmap::build(&square(), &wall, &options).expect("roadmap");
        assert_eq!(roadmap.validation(), Validation::Checked);
        assert_eq!(roadmap.node_count(), 300);
        for i in 0..roadmap.node_count() {
            assert!(wall(roadmap.state(i)));
        }
        let mut scratch = [0.0; 2];
        for &[a, b] in roadmap.edges() {
            assert!(crate::validity::motion_valid_by_interpolation(
                &wall,
                roadmap.space(),
                roadmap.state(a as usize),
                roadmap.state(b as usize),
                0.01,
                &mut scratch
            ));
        }
    }

    #[test]
    fn adjacency_and_components_are_consistent() {
        let options = RoadmapOptions {
            node_count: 200,
            neighbors: 3,
            max_edge_length: 0.08,
            ..RoadmapOptions::default()
        };
        let roadmap = Roadmap::build_lazy(&square(), &options).expect("roadmap");
        assert!(
            roadmap.component_count() > 1,
            "short edges split the roadmap"
        );
        let mut degree_sum = 0;
        for i in 0..roadmap.node_count() {
            for &(j, e) in roadmap.neighbors(i) {
                let [a, b] = roadmap.edges()[e as usize];
                assert!((a as usize == i && b == j) || (b as usize == i && a == j));
                assert_eq!(roadmap.component(i), roadmap.component(j as usize));
                assert!(roadmap.edge_length(e as usize) <= 0.08);
            }
            degree_sum += roadmap.neighbors(i).len();
        }
        assert_eq!(degree_sum, 2 * roadmap.edge_count());
    }

    #[test]
    fn invalid_options_are_rejected() {
        let bad = RoadmapOptions {
            resolution: 0.0,
            ..RoadmapOptions::default()
        };
        assert!(matches!(
            Roadmap::build_lazy(&square(), &bad),
            Err(Error::InvalidOption {
                name: "resolution",
                ..
            })
        ));
    }

    #[test]
    fn progress_reaches_twice_the_node_count_and_does_not_change_the_roadmap() {
        let space = square();
        let free = |q: &[f64]| !((0.4..0.6).contains(&q[0]) && q[1] < 0.7);
        let options = RoadmapOptions {
            node_count: 300,
            ..RoadmapOptions::default()
        };
        let calls = std::sync::Mutex::new(Vec::new());
        let with = Roadmap::build_prefiltered_with_progress(&space, &free, &options, &|d, t| {
            calls.lock().expect("calls").push((d, t));
        })
        .expect("roadmap");
        let calls = calls.into_inner().expect("calls");
        assert_eq!(calls.first(), Some(&(0, 600)), "{calls:?}");
        assert_eq!(calls.last(), Some(&(600, 600)), "{calls:?}");
        assert_eq!(calls.iter().filter(|c| c.0 == 600).count(), 1, "{calls:?}");
        assert!(calls.iter().all(|&(d, t)| d <= t && t == 600), "{calls:?}");
        assert!(
            calls.iter().any(|&(d, _)| d > 300 && d < 600),
            "edges: {calls:?}"
        );
        assert!(calls.len() <= 205, "{}", calls.len());
        assert!(with == Roadmap::build_prefiltered(&space, &free, &options).expect("again"));
    }
}
