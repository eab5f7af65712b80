//! Roadmap queries: connect start and goal, shortest paths over the roadmap (LPA*), lazy
//! checking, growth.
//!
//! A [`PrmPlanner`] is one environment's view of a shared, immutable [`Roadmap`]. It caches the
//! validity of every node and edge it has checked, so successive queries in the same environment
//! (the transfer motions between the key poses of Harada et al. §III-C) check each edge at most
//! once. Start, goal and growth nodes live in a per-query overlay that is discarded afterwards.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::error::{Error, Result};
use crate::lpa::{Graph, Lpa};
use crate::nn::GrowingIndex;
use crate::path::Path;
use crate::rng::{Rng, stream};
use crate::roadmap::{Roadmap, Validation};
use crate::space::JointSpace;
use crate::validity::ValidityChecker;

const NONE: u32 = u32::MAX;

/// The heuristic is the weighted distance to the goal scaled by this factor: consistent with a
/// margin of 1e-9 relative, far above rounding errors. LPA* stops early when rounding makes the
/// heuristic inconsistent by one ulp (a goal neighbour's key ties the goal's).
const HEURISTIC_SCALE: f64 = 1.0 - 1e-9;

/// Options of a roadmap query.
///
/// The resolution at which a query checks edges is not here: it is the roadmap's
/// ([`crate::RoadmapOptions::resolution`], default [`crate::DEFAULT_MAX_JOINT_STEP`]), so that
/// the query's edges and the roadmap's are checked alike.
#[derive(Clone, Debug, PartialEq)]
pub struct QueryOptions {
    /// Roadmap nodes the start and the goal each try to connect to (default: 10).
    pub connect_neighbors: usize,
    /// Growth rounds tried when start and goal are not joined (default: 4).
    pub growth_rounds: usize,
    /// Valid nodes sampled per growth round (default: 100).
    pub growth_nodes: usize,
    /// Draws per growth node before giving up on it (default: 100).
    pub max_sample_attempts: usize,
    /// Seed of the growth samples (default: 0).
    pub seed: u64,
}

impl Default for QueryOptions {
    fn default() -> Self {
        Self {
            connect_neighbors: 10,
            growth_rounds: 4,
            growth_nodes: 100,
            max_sample_attempts: 100,
            seed: 0,
        }
    }
}

/// What the last query did, for diagnostics and benchmarks.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct QueryStats {
    /// Shortest-path searches run (one more after each invalidated edge or set of nodes).
    pub searches: usize,
    /// Nodes expanded over all searches.
    pub nodes_expanded: usize,
    /// Roadmap nodes whose state was checked.
    pub states_checked: usize,
    /// Edges whose motion was checked.
    pub edges_checked: usize,
    /// Edges found invalid.
    pub edges_invalid: usize,
    /// Growth rounds run.
    pub growth_rounds: usize,
    /// Nodes added by growth.
    pub nodes_added: usize,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Status {
    Unknown,
    Valid,
    Invalid,
}

#[derive(Clone, Copy, Debug)]
struct OverlayEdge {
    ends: [u32; 2],
    length: f64,
    status: Status,
}

#[derive(Clone, Copy, Debug)]
struct Link {
    edge: u32,
    next: u32,
}

/// Per-query nodes and edges (start, goal, growth) linked into the roadmap.
#[derive(Debug)]
struct Overlay {
    states: Vec<f64>,
    /// The nearest-state index of `states` (a k-d tree once they are a few hundred).
    index: GrowingIndex,
    edges: Vec<OverlayEdge>,
    links: Vec<Link>,
    base_head: Vec<u32>,
    extra_head: Vec<u32>,
    touched: Vec<u32>,
}

impl Overlay {
    fn clear(&mut self) {
        for &node in &self.touched {
            self.base_head[node as usize] = NONE;
        }
        self.touched.clear();
        self.states.clear();
        self.index.clear();
        self.edges.clear();
        self.links.clear();
        self.extra_head.clear();
    }

    fn head_mut(&mut self, node: u32, base_count: u32) -> &mut u32 {
        if node < base_count {
            if self.base_head[node as usize] == NONE {
                self.touched.push(node);
            }
            &mut self.base_head[node as usize]
        } else {
            &mut self.extra_head[(node - base_count) as usize]
        }
    }

    fn head(&self, node: u32, base_count: u32) -> u32 {
        if node < base_count {
            self.base_head[node as usize]
        } else {
            self.extra_head[(node - base_count) as usize]
        }
    }

    /// The overlay edges at `node`, newest first: `(overlay edge index, other end, edge)`.
    fn edges_at(
        &self,
        node: u32,
        base_count: u32,
    ) -> impl Iterator<Item = (u32, u32, OverlayEdge)> + '_ {
        let mut link = self.head(node, base_count);
        std::iter::from_fn(move || {
            if link == NONE {
                return None;
            }
            let Link { edge, next } = self.links[link as usize];
            link = next;
            let e = self.edges[edge as usize];
            let other = if e.ends[0] == node {
                e.ends[1]
            } else {
                e.ends[0]
            };
            Some((edge, other, e))
        })
    }

    fn add_edge(&mut self, a: u32, b: u32, length: f64, base_count: u32) {
        let edge = self.edges.len() as u32;
        self.edges.push(OverlayEdge {
            ends: [a, b],
            length,
            status: Status::Unknown,
        });
        for node in [a, b] {
            let link = self.links.len() as u32;
            let head = self.head_mut(node, base_count);
            let next = *head;
            *head = link;
            self.links.push(Link { edge, next });
        }
    }
}

#[derive(Clone, Copy, Debug)]
struct Open {
    f: f64,
    node: u32,
}

impl PartialEq for Open {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Open {}
impl PartialOrd for Open {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Open {
    // Min-heap on f, ties broken by the smaller node id (deterministic).
    fn cmp(&self, other: &Self) -> Ordering {
        other
            .f
            .total_cmp(&self.f)
            .then_with(|| other.node.cmp(&self.node))
    }
}

/// A* buffers, reused across searches.
#[derive(Debug, Default)]
struct Search {
    /// Heuristic per node for the `(start, goal)` pair `h_for` (NaN: not computed yet).
    h: Vec<f64>,
    h_for: Option<(u32, u32)>,
    g: Vec<f64>,
    parent: Vec<u32>,
    parent_edge: Vec<u32>,
    closed: Vec<bool>,
    /// Nodes expanded by the last search, in order.
    expanded: Vec<u32>,
    heap: BinaryHeap<Open>,
    nodes: Vec<u32>,
    edges: Vec<u32>,
}

/// Answers path queries on a shared [`Roadmap`] in one environment (one validity checker).
///
/// On a [`Validation::Lazy`] or [`Validation::Prefiltered`] roadmap, nodes and edges are checked
/// only when a candidate path uses them (lazy PRM): an invalid one is removed, the search is
/// repaired (LPA*) and run again. Results are cached for the planner's lifetime, so the planner
/// belongs to one environment; build another planner (cheap: two status arrays) for another
/// environment. On a [`Validation::Checked`] roadmap, roadmap edges are trusted and only the
/// start, goal and growth edges are checked.
///
/// When no path is found, the planner grows a per-query overlay of `growth_nodes` valid samples
/// per round, up to `growth_rounds` rounds, then reports why it failed.
#[derive(Debug)]
pub struct PrmPlanner<'a, C: ?Sized> {
    roadmap: &'a Roadmap,
    checker: &'a C,
    options: QueryOptions,
    node_status: Vec<Status>,
    edge_status: Vec<Status>,
    overlay: Overlay,
    search: Search,
    lpa: Lpa,
    scratch: Vec<f64>,
    found: Vec<(f64, u32)>,
    stats: QueryStats,
}

impl<'a, C: ValidityChecker + ?Sized> PrmPlanner<'a, C> {
    /// A planner for `checker`'s environment over `roadmap`.
    pub fn new(roadmap: &'a Roadmap, checker: &'a C, options: QueryOptions) -> Self {
        let initial = match roadmap.validation() {
            Validation::Checked => Status::Valid,
            Validation::Lazy | Validation::Prefiltered => Status::Unknown,
        };
        let n = roadmap.node_count();
        Self {
            roadmap,
            checker,
            options,
            node_status: vec![initial; n],
            edge_status: vec![initial; roadmap.edge_count()],
            overlay: Overlay {
                base_head: vec![NONE; n],
                states: Vec::new(),
                index: GrowingIndex::new(roadmap.space().weights()),
                edges: Vec::new(),
                links: Vec::new(),
                extra_head: Vec::new(),
                touched: Vec::new(),
            },
            search: Search::default(),
            lpa: Lpa::default(),
            scratch: vec![0.0; roadmap.space().dimension()],
            found: Vec::new(),
            stats: QueryStats::default(),
        }
    }

    /// The roadmap queried.
    pub fn roadmap(&self) -> &Roadmap {
        self.roadmap
    }

    /// Statistics of the last query.
    pub fn last_stats(&self) -> QueryStats {
        self.stats
    }

    /// Finds a valid path from `start` to `goal`.
    ///
    /// The path runs start → roadmap nodes → goal; every waypoint and segment has been checked at
    /// the roadmap's resolution ([`crate::RoadmapOptions::resolution`]) by this planner's checker
    /// (on a [`Validation::Checked`] roadmap, the roadmap's edges by the construction checker).
    /// It is not shortened: see [`crate::shortcut()`].
    ///
    /// # Guarantee
    /// With the default resolution ([`crate::DEFAULT_MAX_JOINT_STEP`]) and the default checker
    /// motion test, consecutive checked states along every segment are at most 1° apart in every
    /// joint (max-norm) and in the weighted distance: the validator's density. Nothing is claimed
    /// between checked states, nor for a coarser resolution beyond its own spacing.
    ///
    /// # Errors
    /// [`Error::StateDimension`] / [`Error::StateOutOfBounds`] for a malformed state;
    /// [`Error::StartInvalid`] / [`Error::GoalInvalid`]; after all growth rounds,
    /// [`Error::StartNotConnected`], [`Error::GoalNotConnected`] or [`Error::NoPath`].
    pub fn query(&mut self, start: &[f64], goal: &[f64]) -> Result<Path> {
        let space = self.roadmap.space();
        space.check_state(start)?;
        space.check_state(goal)?;
        self.stats = QueryStats::default();
        if !self.checker.is_state_valid(start) {
            return Err(Error::StartInvalid);
        }
        if !self.checker.is_state_valid(goal) {
            return Err(Error::GoalInvalid);
        }
        self.overlay.clear();
        self.forget_heuristic();
        let result = self.query_inner(start, goal);
        self.overlay.clear();
        result
    }

    fn base_count(&self) -> u32 {
        self.roadmap.node_count() as u32
    }

    fn add_overlay_node(&mut self, state: &[f64]) -> u32 {
        let id = self.base_count() + self.overlay.extra_head.len() as u32;
        self.overlay.states.extend_from_slice(state);
        self.overlay.extra_head.push(NONE);
        id
    }

    /// Links overlay node `node` to its `k` nearest roadmap nodes and to the `k` nearest earlier
    /// overlay nodes (within `max_length`).
    fn connect(&mut self, node: u32, k: usize, max_length: f64) {
        let n = self.base_count();
        let space = self.roadmap.space();
        let max_squared = max_length * max_length;
        let mut found = std::mem::take(&mut self.found);
        found.clear();
        let state = node_state(self.roadmap, &self.overlay, node);
        self.roadmap.k_nearest(state, k, &mut found);
        let base_found = found.len();
        let d = space.dimension();
        // Earlier overlay nodes only: each pair is linked once.
        let earlier = (node - n) as usize;
        let state = node_state(self.roadmap, &self.overlay, node).to_vec();
        self.overlay.index.k_nearest_within(
            &self.overlay.states[..earlier * d],
            &state,
            k,
            max_squared,
            &mut found,
        );
        for f in &mut found[base_found..] {
            f.1 += n;
        }
        for &(d2, other) in &found {
            if d2 <= max_squared
                && (other >= n || self.node_status[other as usize] != Status::Invalid)
            {
                // The length by the same formula as the heuristic's (not the k-d tree's).
                let length = space.distance(
                    node_state(self.roadmap, &self.overlay, node),
                    node_state(self.roadmap, &self.overlay, other),
                );
                self.overlay.add_edge(node, other, length, n);
            }
        }
        self.found = found;
    }

    fn query_inner(&mut self, start: &[f64], goal: &[f64]) -> Result<Path> {
        let k = self.options.connect_neighbors;
        // The goal links to the start (the direct motion) and to its nearest roadmap nodes.
        let start_id = self.add_overlay_node(start);
        self.connect(start_id, k, f64::INFINITY);
        let goal_id = self.add_overlay_node(goal);
        self.connect(goal_id, k, f64::INFINITY);

        let mut round = 0usize;
        loop {
            if self.search_and_validate(start_id, goal_id) {
                let mut path = Path::new(self.roadmap.space().dimension());
                for &node in self.search.nodes.iter() {
                    path.push_unchecked(node_state(self.roadmap, &self.overlay, node));
                }
                return Ok(path);
            }
            if round == self.options.growth_rounds {
                break;
            }
            self.grow(round);
            round += 1;
        }
        let growth_rounds = self.stats.growth_rounds;
        if !self.reaches_roadmap(start_id, goal_id) {
            Err(Error::StartNotConnected { growth_rounds })
        } else if !self.reaches_roadmap(goal_id, start_id) {
            Err(Error::GoalNotConnected { growth_rounds })
        } else {
            Err(Error::NoPath {
                growth_rounds,
                nodes_added: self.stats.nodes_added,
            })
        }
    }

    /// Whether the nodes reachable from `from` (over edges not known invalid) include a roadmap
    /// node. Runs a search toward `to` that is known to fail, so it explores the whole set.
    fn reaches_roadmap(&mut self, from: u32, to: u32) -> bool {
        if self.astar(from, to) {
            return true;
        }
        let n = self.base_count() as usize;
        self.search.closed[..n].iter().any(|&closed| closed)
    }

    /// Adds one round of valid growth samples to the overlay, each linked to its neighbours.
    fn grow(&mut self, round: usize) {
        self.stats.growth_rounds += 1;
        self.forget_heuristic();
        let space = self.roadmap.space();
        let k = self.roadmap.options().neighbors;
        let max_length = self.roadmap.options().max_edge_length;
        let mut sample = vec![0.0; space.dimension()];
        for i in 0..self.options.growth_nodes {
            let index = (round * self.options.growth_nodes + i) as u64;
            let mut rng = Rng::derive(self.options.seed, stream::GROWTH_SAMPLE, index);
            for _ in 0..self.options.max_sample_attempts {
                space.sample_into(&mut rng, &mut sample);
                if self.checker.is_state_valid(&sample) {
                    let node = self.add_overlay_node(&sample);
                    self.connect(node, k, max_length);
                    self.stats.nodes_added += 1;
                    break;
                }
            }
        }
    }

    /// Lazy PRM loop (Bohlin and Kavraki): shortest path over the nodes and edges not known to be
    /// invalid, then check its unknown nodes (all of them: one state each) and its unknown edges
    /// in order from the start; on an invalid one, remove it and search again. The searches are
    /// one LPA* that repairs its distances after each removal instead of starting over. Leaves
    /// the path in `search.nodes` / `search.edges` and returns whether one was found.
    fn search_and_validate(&mut self, start: u32, goal: u32) -> bool {
        let n = self.base_count() as usize;
        let base_edges = self.roadmap.edge_count() as u32;
        let resolution = self.roadmap.options().resolution;
        let total = n + self.overlay.extra_head.len();
        let mut lpa = std::mem::take(&mut self.lpa);
        let mut former = Vec::new();
        lpa.reset(&self.view(goal), start, goal, total);
        let found = loop {
            self.stats.searches += 1;
            let (mut nodes, mut edges) = (
                std::mem::take(&mut self.search.nodes),
                std::mem::take(&mut self.search.edges),
            );
            let view = self.view(goal);
            let found = lpa.compute(&view) && lpa.path(&view, &mut nodes, &mut edges);
            self.search.nodes = nodes;
            self.search.edges = edges;
            if !found {
                break false;
            }
            let mut invalid_nodes = Vec::new();
            for &node in &self.search.nodes {
                let i = node as usize;
                if i < n && self.node_status[i] == Status::Unknown {
                    self.stats.states_checked += 1;
                    let valid = self.checker.is_state_valid(self.roadmap.state(i));
                    self.node_status[i] = if valid {
                        Status::Valid
                    } else {
                        Status::Invalid
                    };
                    if !valid {
                        invalid_nodes.push(node);
                    }
                }
            }
            if !invalid_nodes.is_empty() {
                for node in invalid_nodes {
                    former.clear();
                    self.all_neighbors(node, &mut former);
                    lpa.node_removed(&self.view(goal), node, &former);
                }
                continue;
            }
            let mut invalid_edge = None;
            for i in 0..self.search.edges.len() {
                let edge = self.search.edges[i];
                let status = if edge < base_edges {
                    self.edge_status[edge as usize]
                } else {
                    self.overlay.edges[(edge - base_edges) as usize].status
                };
                if status != Status::Unknown {
                    continue;
                }
                let (a, b) = (self.search.nodes[i], self.search.nodes[i + 1]);
                self.stats.edges_checked += 1;
                let valid = self.checker.is_motion_valid(
                    self.roadmap.space(),
                    node_state(self.roadmap, &self.overlay, a),
                    node_state(self.roadmap, &self.overlay, b),
                    resolution,
                    &mut self.scratch,
                );
                let status = if valid {
                    Status::Valid
                } else {
                    Status::Invalid
                };
                if edge < base_edges {
                    self.edge_status[edge as usize] = status;
                } else {
                    self.overlay.edges[(edge - base_edges) as usize].status = status;
                }
                if !valid {
                    self.stats.edges_invalid += 1;
                    invalid_edge = Some((a, b));
                    break;
                }
            }
            match invalid_edge {
                Some((a, b)) => lpa.edge_removed(&self.view(goal), a, b),
                None => break true,
            }
        };
        self.stats.nodes_expanded += lpa.expanded;
        self.lpa = lpa;
        found
    }

    /// The graph as LPA* sees it: nodes and edges not known to be invalid.
    fn view(&self, goal: u32) -> View<'_> {
        View {
            roadmap: self.roadmap,
            overlay: &self.overlay,
            node_status: &self.node_status,
            edge_status: &self.edge_status,
            goal_state: node_state(self.roadmap, &self.overlay, goal),
        }
    }

    /// Every neighbour of `node`, whatever the statuses.
    fn all_neighbors(&self, node: u32, out: &mut Vec<u32>) {
        let n = self.base_count();
        if node < n {
            out.extend(
                self.roadmap
                    .neighbors(node as usize)
                    .iter()
                    .map(|&(other, _)| other),
            );
        }
        out.extend(self.overlay.edges_at(node, n).map(|(_, other, _)| other));
    }

    /// A* from `start` to `goal` over edges and nodes not known to be invalid. Fills
    /// `search.nodes` (start..=goal) and `search.edges` (one per segment; roadmap edge ids, then
    /// overlay edges offset by the roadmap's edge count).
    ///
    /// Used to explain a failure (which nodes the start reaches); the lazy loop uses LPA*.
    fn astar(&mut self, start: u32, goal: u32) -> bool {
        let n = self.base_count();
        let total = n as usize + self.overlay.extra_head.len();
        let base_edges = self.roadmap.edge_count() as u32;
        let space: &JointSpace = self.roadmap.space();
        let goal_state = node_state(self.roadmap, &self.overlay, goal);
        let s = &mut self.search;
        if s.h_for != Some((start, goal)) {
            s.h.clear();
            s.h_for = Some((start, goal));
        }
        s.h.resize(total, f64::NAN);
        s.g.clear();
        s.g.resize(total, f64::INFINITY);
        s.parent.clear();
        s.parent.resize(total, NONE);
        s.parent_edge.clear();
        s.parent_edge.resize(total, NONE);
        s.closed.clear();
        s.closed.resize(total, false);
        s.heap.clear();
        s.expanded.clear();
        let heuristic = |h: &mut [f64], node: u32| {
            let value = h[node as usize];
            if value.is_nan() {
                let value = HEURISTIC_SCALE
                    * space.distance(node_state(self.roadmap, &self.overlay, node), goal_state);
                h[node as usize] = value;
                value
            } else {
                value
            }
        };
        s.g[start as usize] = 0.0;
        let f = heuristic(&mut s.h, start);
        s.heap.push(Open { f, node: start });
        let mut reached = false;
        while let Some(Open { node, .. }) = s.heap.pop() {
            if s.closed[node as usize] {
                continue;
            }
            if node == goal {
                reached = true;
                break;
            }
            s.closed[node as usize] = true;
            s.expanded.push(node);
            let g = s.g[node as usize];
            let relax = |other: u32, edge: u32, length: f64, s: &mut Search| {
                if s.closed[other as usize] {
                    return;
                }
                let candidate = g + length;
                if candidate < s.g[other as usize] {
                    s.g[other as usize] = candidate;
                    s.parent[other as usize] = node;
                    s.parent_edge[other as usize] = edge;
                    let h = heuristic(&mut s.h, other);
                    s.heap.push(Open {
                        f: candidate + h,
                        node: other,
                    });
                }
            };
            if node < n {
                for &(other, edge) in self.roadmap.neighbors(node as usize) {
                    if self.edge_status[edge as usize] != Status::Invalid
                        && self.node_status[other as usize] != Status::Invalid
                    {
                        relax(other, edge, self.roadmap.edge_length(edge as usize), s);
                    }
                }
            }
            for (edge, other, e) in self.overlay.edges_at(node, n) {
                if e.status != Status::Invalid
                    && (other >= n || self.node_status[other as usize] != Status::Invalid)
                {
                    relax(other, base_edges + edge, e.length, s);
                }
            }
        }
        self.stats.nodes_expanded += s.expanded.len();
        if !reached {
            return false;
        }
        s.nodes.clear();
        s.edges.clear();
        let mut node = goal;
        while node != start {
            s.nodes.push(node);
            s.edges.push(s.parent_edge[node as usize]);
            node = s.parent[node as usize];
        }
        s.nodes.push(start);
        s.nodes.reverse();
        s.edges.reverse();
        true
    }

    /// Drops the cached heuristic (after growth added edges, the adaptive bounds may be too high).
    fn forget_heuristic(&mut self) {
        self.search.h_for = None;
    }
}

/// One environment's view of the roadmap plus overlay, for LPA*.
struct View<'p> {
    roadmap: &'p Roadmap,
    overlay: &'p Overlay,
    node_status: &'p [Status],
    edge_status: &'p [Status],
    goal_state: &'p [f64],
}

impl Graph for View<'_> {
    fn neighbors(&self, node: u32, out: &mut Vec<(u32, u32, f64)>) {
        let n = self.roadmap.node_count() as u32;
        let usable = |other: u32| other >= n || self.node_status[other as usize] != Status::Invalid;
        if !usable(node) {
            return;
        }
        if node < n {
            for &(other, edge) in self.roadmap.neighbors(node as usize) {
                if self.edge_status[edge as usize] != Status::Invalid && usable(other) {
                    out.push((other, edge, self.roadmap.edge_length(edge as usize)));
                }
            }
        }
        let base_edges = self.roadmap.edge_count() as u32;
        for (edge, other, e) in self.overlay.edges_at(node, n) {
            if e.status != Status::Invalid && usable(other) {
                out.push((other, base_edges + edge, e.length));
            }
        }
    }

    fn heuristic(&self, node: u32) -> f64 {
        HEURISTIC_SCALE
            * self.roadmap.space().distance(
                node_state(self.roadmap, self.overlay, node),
                self.goal_state,
            )
    }
}

fn node_state<'r>(roadmap: &'r Roadmap, overlay: &'r Overlay, node: u32) -> &'r [f64] {
    let n = roadmap.node_count();
    let node = node as usize;
    if node < n {
        roadmap.state(node)
    } else {
        let d = roadmap.space().dimension();
        &overlay.states[(node - n) * d..(node - n + 1) * d]
    }
}

#[cfg(test)]
mod tests;
