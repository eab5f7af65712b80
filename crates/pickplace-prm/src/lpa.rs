//! Lifelong Planning A* (Koenig, Likhachev and Furcy, 2004): repeated shortest-path searches on
//! a graph that loses edges and nodes between searches, reusing the previous search's work.
//!
//! Lazy PRM removes one invalid edge (or a few invalid nodes) after each search and searches
//! again from the same start to the same goal. A fresh A* per search redoes the whole
//! exploration; LPA* repairs only the distances that the removal changed, which makes a query
//! with many invalidations several times cheaper.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

/// The graph searched: usable neighbours of a node, and a consistent heuristic toward the goal.
pub(crate) trait Graph {
    /// Appends the neighbours of `node` through edges not known to be invalid, as
    /// `(neighbour, edge id, length)`; nothing for a node known to be invalid.
    fn neighbors(&self, node: u32, out: &mut Vec<(u32, u32, f64)>);
    /// A consistent lower bound of the distance from `node` to the goal.
    fn heuristic(&self, node: u32) -> f64;
}

#[derive(Clone, Copy, Debug)]
struct Entry {
    key: [f64; 2],
    node: u32,
}

fn compare_keys(a: [f64; 2], b: [f64; 2]) -> Ordering {
    a[0].total_cmp(&b[0]).then_with(|| a[1].total_cmp(&b[1]))
}

impl PartialEq for Entry {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Entry {}
impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Entry {
    // Min-heap on the key, ties broken by the smaller node id (deterministic).
    fn cmp(&self, other: &Self) -> Ordering {
        compare_keys(other.key, self.key).then_with(|| other.node.cmp(&self.node))
    }
}

const NOT_QUEUED: [f64; 2] = [f64::NAN, f64::NAN];

fn same_key(a: [f64; 2], b: [f64; 2]) -> bool {
    a[0].to_bits() == b[0].to_bits() && a[1].to_bits() == b[1].to_bits()
}

/// LPA* state for one `(start, goal)` pair. The priority queue deletes lazily: a node's current
/// key is in `queued`, and heap entries with another key are stale.
#[derive(Debug, Default)]
pub(crate) struct Lpa {
    start: u32,
    goal: u32,
    g: Vec<f64>,
    rhs: Vec<f64>,
    h: Vec<f64>,
    queued: Vec<[f64; 2]>,
    heap: BinaryHeap<Entry>,
    outer: Vec<(u32, u32, f64)>,
    inner: Vec<(u32, u32, f64)>,
    /// Nodes taken from the queue since the last reset.
    pub(crate) expanded: usize,
}

impl Lpa {
    /// Starts over for `start` → `goal` on a graph of `node_count` nodes.
    pub(crate) fn reset<G: Graph>(&mut self, graph: &G, start: u32, goal: u32, node_count: usize) {
        self.start = start;
        self.goal = goal;
        for values in [&mut self.g, &mut self.rhs] {
            values.clear();
            values.resize(node_count, f64::INFINITY);
        }
        self.h.clear();
        self.h.resize(node_count, f64::NAN);
        self.queued.clear();
        self.queued.resize(node_count, NOT_QUEUED);
        self.heap.clear();
        self.expanded = 0;
        self.rhs[start as usize] = 0.0;
        self.enqueue(graph, start);
    }

    fn heuristic<G: Graph>(&mut self, graph: &G, node: u32) -> f64 {
        let cached = self.h[node as usize];
        if cached.is_nan() {
            let value = graph.heuristic(node);
            self.h[node as usize] = value;
            value
        } else {
            cached
        }
    }

    fn key<G: Graph>(&mut self, graph: &G, node: u32) -> [f64; 2] {
        let best = self.g[node as usize].min(self.rhs[node as usize]);
        [best + self.heuristic(graph, node), best]
    }

    /// Queues `node` with its current key when inconsistent, dequeues it otherwise.
    fn enqueue<G: Graph>(&mut self, graph: &G, node: u32) {
        let i = node as usize;
        if self.g[i] == self.rhs[i] {
            self.queued[i] = NOT_QUEUED;
        } else {
            let key = self.key(graph, node);
            self.queued[i] = key;
            self.heap.push(Entry { key, node });
        }
    }

    /// Recomputes `rhs(node)` from its neighbours and requeues it.
    fn update_vertex<G: Graph>(&mut self, graph: &G, node: u32) {
        if node != self.start {
            let mut inner = std::mem::take(&mut self.inner);
            inner.clear();
            graph.neighbors(node, &mut inner);
            self.rhs[node as usize] = inner
                .iter()
                .map(|&(other, _, length)| self.g[other as usize] + length)
                .fold(f64::INFINITY, f64::min);
            self.inner = inner;
        }
        self.enqueue(graph, node);
    }

    /// Call after the edge between `a` and `b` became unusable.
    pub(crate) fn edge_removed<G: Graph>(&mut self, graph: &G, a: u32, b: u32) {
        self.update_vertex(graph, a);
        self.update_vertex(graph, b);
    }

    /// Call after `node` became unusable, with its former neighbours.
    pub(crate) fn node_removed<G: Graph>(
        &mut self,
        graph: &G,
        node: u32,
        former_neighbors: &[u32],
    ) {
        self.update_vertex(graph, node);
        for &other in former_neighbors {
            self.update_vertex(graph, other);
        }
    }

    /// Brings the distances up to date; returns whether the goal is reachable.
    pub(crate) fn compute<G: Graph>(&mut self, graph: &G) -> bool {
        let goal = self.goal as usize;
        while let Some(&Entry { key, node }) = self.heap.peek() {
            let i = node as usize;
            if !same_key(self.queued[i], key) {
                self.heap.pop();
                continue;
            }
            let goal_key = self.key(graph, self.goal);
            if compare_keys(key, goal_key) != Ordering::Less && self.rhs[goal] == self.g[goal] {
                break;
            }
            self.heap.pop();
            self.queued[i] = NOT_QUEUED;
            self.expanded += 1;
            let mut outer = std::mem::take(&mut self.outer);
            outer.clear();
            graph.neighbors(node, &mut outer);
            if self.g[i] > self.rhs[i] {
                // Overconsistent: settle it and offer it to the neighbours.
                self.g[i] = self.rhs[i];
                for &(other, _, length) in &outer {
                    let candidate = self.g[i] + length;
                    if other != self.start && candidate < self.rhs[other as usize] {
                        self.rhs[other as usize] = candidate;
                        self.enqueue(graph, other);
                    }
                }
            } else {
                // Underconsistent: its distance grew; it and its neighbours are recomputed.
                self.g[i] = f64::INFINITY;
                self.update_vertex(graph, node);
                for &(other, _, _) in &outer {
                    self.update_vertex(graph, other);
                }
            }
            self.outer = outer;
        }
        self.g[goal].is_finite()
    }

    /// Writes a shortest path (nodes start..=goal, and the edge of each segment) after a
    /// successful [`Lpa::compute`]; returns false if there is none.
    pub(crate) fn path<G: Graph>(
        &mut self,
        graph: &G,
        nodes: &mut Vec<u32>,
        edges: &mut Vec<u32>,
    ) -> bool {
        nodes.clear();
        edges.clear();
        if !self.g[self.goal as usize].is_finite() {
            return false;
        }
        let mut node = self.goal;
        nodes.push(node);
        while node != self.start {
            // Distances strictly decrease toward the start; the bound guards zero-length loops.
            if nodes.len() > self.g.len() {
                return false;
            }
            let mut inner = std::mem::take(&mut self.inner);
            inner.clear();
            graph.neighbors(node, &mut inner);
            let best = inner
                .iter()
                .map(|&(other, edge, length)| (self.g[other as usize] + length, other, edge))
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            self.inner = inner;
            match best {
                Some((cost, other, edge)) if cost.is_finite() => {
                    nodes.push(other);
                    edges.push(edge);
                    node = other;
                }
                _ => return false,
            }
        }
        nodes.reverse();
        edges.reverse();
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::Rng;

    /// A random geometric graph in the unit square with removable edges.
    struct Toy {
        points: Vec<[f64; 2]>,
        edges: Vec<(u32, u32)>,
        removed: Vec<bool>,
        removed_nodes: Vec<bool>,
        goal: u32,
    }

    impl Toy {
        fn length(&self, e: usize) -> f64 {
            let (a, b) = self.edges[e];
            let (p, q) = (self.points[a as usize], self.points[b as usize]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        }

        fn dijkstra(&self, start: u32) -> Vec<f64> {
            let mut dist = vec![f64::INFINITY; self.points.len()];
            let mut done = vec![false; self.points.len()];
            dist[start as usize] = 0.0;
            loop {
                let next = (0..dist.len())
                    .filter(|&i| !done[i] && dist[i].is_finite())
                    .min_by(|&a, &b| dist[a].total_cmp(&dist[b]));
                let Some(u) = next else { break };
                done[u] = true;
                let mut out = Vec::new();
                self.neighbors(u as u32, &mut out);
                for (v, _, c) in out {
                    dist[v as usize] = dist[v as usize].min(dist[u] + c);
                }
            }
            dist
        }
    }

    impl Graph for Toy {
        fn neighbors(&self, node: u32, out: &mut Vec<(u32, u32, f64)>) {
            if self.removed_nodes[node as usize] {
                return;
            }
            for (e, &(a, b)) in self.edges.iter().enumerate() {
                if self.removed[e]
                    || self.removed_nodes[a as usize]
                    || self.removed_nodes[b as usize]
                {
                    continue;
                }
                if a == node {
                    out.push((b, e as u32, self.length(e)));
                } else if b == node {
                    out.push((a, e as u32, self.length(e)));
                }
            }
        }

        fn heuristic(&self, node: u32) -> f64 {
            let (p, q) = (self.points[node as usize], self.points[self.goal as usize]);
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()
        }
    }

    #[test]
    fn matches_dijkstra_while_edges_are_removed() {
        for seed in 0..5 {
            let mut rng = Rng::derive(seed, 99, 0);
            let n = 120;
            let points: Vec<[f64; 2]> = (0..n).map(|_| [rng.next_f64(), rng.next_f64()]).collect();
            let mut edges = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    let (p, q) = (points[a], points[b]);
                    if ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt() < 0.2 {
                        edges.push((a as u32, b as u32));
                    }
                }
            }
            let removed = vec![false; edges.len()];
            let removed_nodes = vec![false; n];
            let mut toy = Toy {
                points,
                edges,
                removed,
                removed_nodes,
                goal: 1,
            };
            let mut lpa = Lpa::default();
            lpa.reset(&toy, 0, 1, n);
            let (mut nodes, mut path_edges) = (Vec::new(), Vec::new());
            for _ in 0..60 {
                let reachable = lpa.compute(&toy);
                let expected = toy.dijkstra(0)[1];
                assert_eq!(reachable, expected.is_finite());
                if !reachable {
                    break;
                }
                assert!((lpa.g[1] - expected).abs() < 1e-9, "seed {seed}");
                assert!(lpa.path(&toy, &mut nodes, &mut path_edges));
                let length: f64 = path_edges.iter().map(|&e| toy.length(e as usize)).sum();
                assert!((length - expected).abs() < 1e-9);
                assert_eq!((nodes[0], *nodes.last().expect("nodes")), (0, 1));
                // Remove a path edge or an inner path node, chosen by the generator.
                if nodes.len() > 2 && rng.next_u64().is_multiple_of(2) {
                    let node = nodes[1 + (rng.next_u64() % (nodes.len() as u64 - 2)) as usize];
                    let former: Vec<u32> = toy
                        .edges
                        .iter()
                        .filter_map(|&(a, b)| (a == node).then_some(b).or((b == node).then_some(a)))
                        .collect();
                    toy.removed_nodes[node as usize] = true;
                    lpa.node_removed(&toy, node, &former);
                } else {
                    let pick = path_edges[(rng.next_u64() % path_edges.len() as u64) as usize];
                    toy.removed[pick as usize] = true;
                    let (a, b) = toy.edges[pick as usize];
                    lpa.edge_removed(&toy, a, b);
                }
            }
        }
    }
}
