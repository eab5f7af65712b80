//! Nearest-neighbour indexes over states: a kiddo k-d tree with the dimension chosen at run
//! time, immutable over a roadmap's states ([`NearestIndex`]) or growing with a single-query
//! tree ([`GrowingIndex`]).
//!
//! Coordinates are scaled by `sqrt(w_i)` so that the tree's squared Euclidean distance is the
//! space's squared weighted distance. kiddo's trees take the dimension as a const generic: the
//! dimensions 1 to [`MAX_DIMENSION`] are instantiated and dispatched by a `match`.

use std::num::NonZeroUsize;

use kiddo::{ImmutableKdTree, MutableKdTree, SquaredEuclidean};

use crate::error::{Error, Result};

/// Largest supported number of joints (enough for a dual-arm robot with waist and head).
pub const MAX_DIMENSION: usize = 16;

fn build_tree<const K: usize>(states: &[f64], scale: &[f64]) -> Result<ImmutableKdTree<f64, K>> {
    let points: Vec<[f64; K]> = states
        .chunks_exact(K)
        .map(|state| {
            let mut point = [0.0; K];
            for ((p, s), w) in point.iter_mut().zip(state).zip(scale) {
                *p = s * w;
            }
            point
        })
        .collect();
    ImmutableKdTree::new_from_slice(&points).map_err(|_| Error::NearestIndex {
        nodes: points.len(),
    })
}

fn scaled<const K: usize>(state: &[f64], scale: &[f64]) -> [f64; K] {
    let mut point = [0.0; K];
    for ((p, s), w) in point.iter_mut().zip(state).zip(scale) {
        *p = s * w;
    }
    point
}

fn add_to<const K: usize>(
    tree: &mut MutableKdTree<f64, K>,
    state: &[f64],
    scale: &[f64],
    item: u32,
) -> bool {
    tree.add(&scaled::<K>(state, scale), item).is_ok()
}

fn k_nearest_in<const K: usize>(
    tree: &MutableKdTree<f64, K>,
    state: &[f64],
    scale: &[f64],
    k: NonZeroUsize,
    out: &mut Vec<(f64, u32)>,
) {
    let found = tree
        .query(&scaled::<K>(state, scale))
        .nearest_n::<SquaredEuclidean<f64>>(k)
        .execute();
    out.extend(found.into_iter().map(|item| (item.distance, item.item)));
}

fn nearest_in<const K: usize>(tree: &MutableKdTree<f64, K>, state: &[f64], scale: &[f64]) -> u32 {
    tree.query(&scaled::<K>(state, scale))
        .nearest_one::<SquaredEuclidean<f64>>()
        .execute()
        .item
}

fn query_tree<const K: usize>(
    tree: &ImmutableKdTree<f64, K>,
    state: &[f64],
    scale: &[f64],
    k: NonZeroUsize,
    out: &mut Vec<(f64, u32)>,
) {
    let mut point = [0.0; K];
    for ((p, s), w) in point.iter_mut().zip(state).zip(scale) {
        *p = s * w;
    }
    let found = tree
        .query(&point)
        .nearest_n::<SquaredEuclidean<f64>>(k)
        .execute();
    out.extend(found.into_iter().map(|item| (item.distance, item.item)));
}

macro_rules! dimensions {
    ($($variant:ident = $k:literal),* $(,)?) => {
        enum Tree {
            Empty,
            $($variant(ImmutableKdTree<f64, $k>),)*
        }

        fn build_any(dimension: usize, states: &[f64], scale: &[f64]) -> Result<Tree> {
            if states.is_empty() {
                return Ok(Tree::Empty);
            }
            match dimension {
                $($k => build_tree::<$k>(states, scale).map(Tree::$variant),)*
                _ => Err(Error::DimensionTooLarge { dimension, max: MAX_DIMENSION }),
            }
        }

        enum GrowingTree {
            $($variant(MutableKdTree<f64, $k>),)*
        }

        fn new_growing(dimension: usize) -> Option<GrowingTree> {
            match dimension {
                $($k => Some(GrowingTree::$variant(MutableKdTree::default())),)*
                _ => None,
            }
        }

        fn add_growing(tree: &mut GrowingTree, state: &[f64], scale: &[f64], item: u32) -> bool {
            match tree {
                $(GrowingTree::$variant(t) => add_to::<$k>(t, state, scale, item),)*
            }
        }

        fn k_nearest_growing(
            tree: &GrowingTree,
            state: &[f64],
            scale: &[f64],
            k: NonZeroUsize,
            out: &mut Vec<(f64, u32)>,
        ) {
            match tree {
                $(GrowingTree::$variant(t) => k_nearest_in::<$k>(t, state, scale, k, out),)*
            }
        }

        fn nearest_growing(tree: &GrowingTree, state: &[f64], scale: &[f64]) -> u32 {
            match tree {
                $(GrowingTree::$variant(t) => nearest_in::<$k>(t, state, scale),)*
            }
        }

        fn query_any(
            tree: &Tree,
            state: &[f64],
            scale: &[f64],
            k: NonZeroUsize,
            out: &mut Vec<(f64, u32)>,
        ) {
            match tree {
                Tree::Empty => {}
                $(Tree::$variant(t) => query_tree::<$k>(t, state, scale, k, out),)*
            }
        }
    };
}

dimensions!(
    D1 = 1,
    D2 = 2,
    D3 = 3,
    D4 = 4,
    D5 = 5,
    D6 = 6,
    D7 = 7,
    D8 = 8,
    D9 = 9,
    D10 = 10,
    D11 = 11,
    D12 = 12,
    D13 = 13,
    D14 = 14,
    D15 = 15,
    D16 = 16,
);

/// An immutable k-d tree over a flat array of states.
pub(crate) struct NearestIndex {
    tree: Tree,
    scale: Vec<f64>,
    len: usize,
}

impl std::fmt::Debug for NearestIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NearestIndex")
            .field("dimension", &self.scale.len())
            .field("len", &self.len)
            .finish_non_exhaustive()
    }
}

impl NearestIndex {
    /// Builds the index over `states` (flat, `dimension` coordinates each) for the weighted metric.
    pub(crate) fn build(states: &[f64], weights: &[f64]) -> Result<Self> {
        let dimension = weights.len();
        let scale: Vec<f64> = weights.iter().map(|w| w.sqrt()).collect();
        let tree = build_any(dimension, states, &scale)?;
        Ok(Self {
            tree,
            scale,
            len: states.len() / dimension.max(1),
        })
    }

    /// Appends the `k` nearest states to `state` as `(squared weighted distance, index)`, sorted
    /// by distance then index.
    pub(crate) fn k_nearest(&self, state: &[f64], k: usize, out: &mut Vec<(f64, u32)>) {
        let Some(k) = NonZeroUsize::new(k.min(self.len)) else {
            return;
        };
        let start = out.len();
        query_any(&self.tree, state, &self.scale, k, out);
        out[start..].sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    }
}

/// Below this many states, [`GrowingIndex`] scans them: a scan of a few hundred short rows
/// beats a tree's descent and its upkeep.
pub(crate) const LINEAR_LIMIT: usize = 256;

/// The nearest-state index of a tree that grows one state at a time (RRT-Connect's): a linear
/// scan while it holds fewer than [`LINEAR_LIMIT`] states, then a mutable k-d tree (kiddo)
/// that takes the new states as they are asked about. Should kiddo refuse a state (a leaf it
/// cannot split), the index goes back to scanning: slower, never wrong.
pub(crate) struct GrowingIndex {
    tree: Option<GrowingTree>,
    /// The metric's weights (the scan's distance is the space's, `Σ w (a − b)²`).
    weights: Vec<f64>,
    /// Their square roots (the tree's coordinates).
    scale: Vec<f64>,
    /// States already in the tree (the first ones of the caller's array).
    indexed: usize,
}

impl std::fmt::Debug for GrowingIndex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GrowingIndex")
            .field("dimension", &self.scale.len())
            .field("indexed", &self.indexed)
            .finish_non_exhaustive()
    }
}

impl GrowingIndex {
    /// An index for states of `weights.len()` coordinates under the weighted metric.
    pub(crate) fn new(weights: &[f64]) -> Self {
        Self {
            tree: new_growing(weights.len()),
            weights: weights.to_vec(),
            scale: weights.iter().map(|w| w.sqrt()).collect(),
            indexed: 0,
        }
    }

    /// Forgets every state (the caller's array starts again from empty).
    pub(crate) fn clear(&mut self) {
        self.tree = new_growing(self.scale.len());
        self.indexed = 0;
    }

    /// Takes the states of `states` not yet in the tree, once it is past
    /// [`LINEAR_LIMIT`]; false when there is no tree (small, or refused by kiddo).
    fn catch_up(&mut self, states: &[f64]) -> bool {
        let d = self.scale.len().max(1);
        let n = states.len() / d;
        if n < LINEAR_LIMIT {
            return false;
        }
        let Some(tree) = &mut self.tree else {
            return false;
        };
        while self.indexed < n {
            let state = &states[self.indexed * d..(self.indexed + 1) * d];
            if !add_growing(tree, state, &self.scale, self.indexed as u32) {
                self.tree = None;
                return false;
            }
            self.indexed += 1;
        }
        true
    }

    /// The squared weighted distance between two states, by the formula of
    /// [`crate::JointSpace::distance_squared`].
    fn distance_squared(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.weights)
            .map(|((x, y), w)| w * (x - y) * (x - y))
            .sum()
    }

    /// Appends the (at most) `k` states of `states` nearest to `target` within squared
    /// distance `max_squared`, as `(squared weighted distance, index)`, sorted by distance then
    /// index. `states` only ever grows between calls (or the index is cleared).
    pub(crate) fn k_nearest_within(
        &mut self,
        states: &[f64],
        target: &[f64],
        k: usize,
        max_squared: f64,
        out: &mut Vec<(f64, u32)>,
    ) {
        let start = out.len();
        let d = self.scale.len().max(1);
        let n = states.len() / d;
        let Some(k_nonzero) = NonZeroUsize::new(k.min(n)) else {
            return;
        };
        if self.catch_up(states)
            && let Some(tree) = &self.tree
        {
            k_nearest_growing(tree, target, &self.scale, k_nonzero, out);
            out.truncate(start + k);
            let mut kept = start;
            for i in start..out.len() {
                if out[i].0 <= max_squared {
                    out[kept] = out[i];
                    kept += 1;
                }
            }
            out.truncate(kept);
        } else {
            for (i, state) in states.chunks_exact(d).enumerate() {
                let d2 = self.distance_squared(state, target);
                if d2 <= max_squared {
                    out.push((d2, i as u32));
                }
            }
        }
        out[start..].sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out.truncate(start + k);
    }

    /// The index of the state of `states` (flat, the index's dimension each) nearest to
    /// `target` under the weighted metric; `states` only ever grows between calls. `states`
    /// must not be empty.
    pub(crate) fn nearest(&mut self, states: &[f64], target: &[f64]) -> usize {
        if self.catch_up(states)
            && let Some(tree) = &self.tree
        {
            return nearest_growing(tree, target, &self.scale) as usize;
        }
        let d = self.scale.len().max(1);
        let mut best = (f64::INFINITY, 0);
        for (i, state) in states.chunks_exact(d).enumerate() {
            let d2 = self.distance_squared(state, target);
            if d2 < best.0 {
                best = (d2, i);
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn matches_brute_force_in_every_dimension() {
        for dimension in 1..=MAX_DIMENSION {
            let mut rng = Rng::derive(dimension as u64, 0, 0);
            let n = 300;
            let states: Vec<f64> = (0..n * dimension).map(|_| rng.next_f64()).collect();
            let weights: Vec<f64> = (0..dimension).map(|i| 1.0 + i as f64 * 0.25).collect();
            let index = NearestIndex::build(&states, &weights).expect("index");
            let query: Vec<f64> = (0..dimension).map(|_| rng.next_f64()).collect();
            let mut found = Vec::new();
            index.k_nearest(&query, 7, &mut found);
            let mut brute: Vec<(f64, u32)> = states
                .chunks_exact(dimension)
                .enumerate()
                .map(|(i, s)| {
                    let d: f64 = s
                        .iter()
                        .zip(&query)
                        .zip(&weights)
                        .map(|((a, b), w)| w * (a - b) * (a - b))
                        .sum();
                    (d, i as u32)
                })
                .collect();
            brute.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let ids: Vec<u32> = found.iter().map(|x| x.1).collect();
            let expected: Vec<u32> = brute[..7].iter().map(|x| x.1).collect();
            assert_eq!(ids, expected, "dimension {dimension}");
            for ((d, _), (e, _)) in found.iter().zip(&brute) {
                assert!((d - e).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn a_growing_index_finds_what_a_scan_finds_before_and_after_it_builds_its_tree() {
        for dimension in [2, 7, 14] {
            let mut rng = Rng::derive(dimension as u64, 1, 0);
            let weights: Vec<f64> = (0..dimension).map(|i| 1.0 + i as f64 * 0.5).collect();
            let mut index = GrowingIndex::new(&weights);
            let mut states = Vec::new();
            for n in 1..=3 * LINEAR_LIMIT {
                states.extend((0..dimension).map(|_| rng.next_f64()));
                if n % 37 != 0 && n != LINEAR_LIMIT {
                    continue;
                }
                let query: Vec<f64> = (0..dimension).map(|_| rng.next_f64()).collect();
                let brute = states
                    .chunks_exact(dimension)
                    .enumerate()
                    .map(|(i, s)| {
                        let d: f64 = s
                            .iter()
                            .zip(&query)
                            .zip(&weights)
                            .map(|((a, b), w)| w * (a - b) * (a - b))
                            .sum();
                        (d, i)
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|x| x.1);
                assert_eq!(
                    Some(index.nearest(&states, &query)),
                    brute,
                    "dimension {dimension}, {n} states"
                );
            }
            assert!(index.tree.is_some() && index.indexed > LINEAR_LIMIT);
        }
    }

    #[test]
    fn a_growing_index_finds_the_k_nearest_within_a_radius_as_a_scan_does() {
        let dimension = 6;
        let mut rng = Rng::derive(9, 2, 0);
        let weights: Vec<f64> = (0..dimension).map(|i| 0.5 + i as f64 * 0.25).collect();
        let mut index = GrowingIndex::new(&weights);
        let mut states = Vec::new();
        for n in 1..=2 * LINEAR_LIMIT + 50 {
            states.extend((0..dimension).map(|_| rng.next_f64()));
            if n % 41 != 0 {
                continue;
            }
            let query: Vec<f64> = (0..dimension).map(|_| rng.next_f64()).collect();
            let max_squared = 0.3;
            let mut brute: Vec<(f64, u32)> = states
                .chunks_exact(dimension)
                .enumerate()
                .map(|(i, s)| (index.distance_squared(s, &query), i as u32))
                .filter(|x| x.0 <= max_squared)
                .collect();
            brute.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            brute.truncate(7);
            let mut found = vec![(-1.0, u32::MAX)];
            index.k_nearest_within(&states, &query, 7, max_squared, &mut found);
            assert_eq!(found[0], (-1.0, u32::MAX), "what was there is kept");
            let ids: Vec<u32> = found[1..].iter().map(|x| x.1).collect();
            let expected: Vec<u32> = brute.iter().map(|x| x.1).collect();
            assert_eq!(ids, expected, "{n} states");
        }
        assert!(index.tree.is_some() && index.indexed > LINEAR_LIMIT);
        index.clear();
        let mut found = Vec::new();
        index.k_nearest_within(
            &states[..dimension * 3],
            &states[..dimension],
            2,
            10.0,
            &mut found,
        );
        // After clearing, a small array is scanned again: the target itself first.
        assert_eq!(found.len(), 2);
        assert_eq!(found[0], (0.0, 0));
    }

    #[test]
    fn empty_index_finds_nothing() {
        let index = NearestIndex::build(&[], &[1.0, 1.0]).expect("index");
        let mut found = Vec::new();
        index.k_nearest(&[0.0, 0.0], 3, &mut found);
        assert!(found.is_empty());
    }
}
