//! Unit tests of `planner`.

use super::*;
use crate::roadmap::RoadmapOptions;

fn square() -> JointSpace {
    JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space")
}

#[test]
fn lazy_query_goes_around_a_wall() {
    let roadmap = Roadmap::build_lazy(
        &square(),
        &RoadmapOptions {
            node_count: 400,
            resolution: 0.005,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let wall = |q: &[f64]| !((0.45..0.55).contains(&q[0]) && q[1] < 0.8);
    let mut planner = PrmPlanner::new(&roadmap, &wall, QueryOptions::default());
    let path = planner.query(&[0.1, 0.1], &[0.9, 0.1]).expect("path");
    assert_eq!(path.waypoint(0), &[0.1, 0.1]);
    assert_eq!(path.waypoint(path.len() - 1), &[0.9, 0.1]);
    assert!(path.is_valid(&square(), &wall, 0.0005));
    assert!(path.waypoints().any(|q| q[1] >= 0.8));
    let stats = planner.last_stats();
    assert!(
        stats.edges_invalid >= 1,
        "the direct edge crosses the wall: {stats:?}"
    );
    // A second query reuses the cached statuses.
    let again = planner.query(&[0.1, 0.1], &[0.9, 0.1]).expect("path");
    assert_eq!(again, path);
    assert!(planner.last_stats().edges_checked < stats.edges_checked);
}

#[test]
fn failures_carry_their_reason() {
    let roadmap = Roadmap::build_lazy(
        &square(),
        &RoadmapOptions {
            node_count: 100,
            resolution: 0.002,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    // A full wall: the two halves are not connected.
    let wall = |q: &[f64]| !(0.45..0.55).contains(&q[0]);
    let options = QueryOptions {
        growth_rounds: 2,
        growth_nodes: 20,
        ..QueryOptions::default()
    };
    let mut planner = PrmPlanner::new(&roadmap, &wall, options);
    assert!(matches!(
        planner.query(&[0.5, 0.5], &[0.9, 0.1]),
        Err(Error::StartInvalid)
    ));
    assert!(matches!(
        planner.query(&[0.1, 0.1], &[0.5, 0.1]),
        Err(Error::GoalInvalid)
    ));
    assert!(matches!(
        planner.query(&[0.1, 0.1], &[0.9, 0.1]),
        Err(Error::NoPath {
            growth_rounds: 2,
            nodes_added: 40
        })
    ));
    assert!(matches!(
        planner.query(&[0.1], &[0.9, 0.1]),
        Err(Error::StateDimension {
            expected: 2,
            found: 1
        })
    ));
    // A start boxed in by a small ring with no roadmap node inside: no edge leaves it.
    for i in 0..roadmap.node_count() {
        assert!(roadmap.space().distance(roadmap.state(i), &[0.2, 0.2]) > 0.02);
    }
    let ring = |q: &[f64]| {
        let r = ((q[0] - 0.2).powi(2) + (q[1] - 0.2).powi(2)).sqrt();
        !(0.01..0.02).contains(&r)
    };
    let mut planner = PrmPlanner::new(&roadmap, &ring, QueryOptions::default());
    assert!(matches!(
        planner.query(&[0.2, 0.2], &[0.9, 0.9]),
        Err(Error::StartNotConnected { growth_rounds: 4 })
    ));
    assert!(matches!(
        planner.query(&[0.9, 0.9], &[0.2, 0.2]),
        Err(Error::GoalNotConnected { growth_rounds: 4 })
    ));
}

#[test]
fn growth_bridges_a_sparse_roadmap() {
    // Edges too short to cross the gap between the few nodes: growth adds the missing nodes.
    let roadmap = Roadmap::build_lazy(
        &square(),
        &RoadmapOptions {
            node_count: 20,
            neighbors: 5,
            max_edge_length: 0.3,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let free = |_: &[f64]| true;
    let blocker = |q: &[f64]| !((0.3..0.7).contains(&q[0]) && (0.3..0.7).contains(&q[1]));
    let mut planner = PrmPlanner::new(&roadmap, &blocker, QueryOptions::default());
    let path = planner.query(&[0.1, 0.5], &[0.9, 0.5]).expect("path");
    assert!(path.is_valid(&square(), &blocker, 0.001));
    let mut free_planner = PrmPlanner::new(&roadmap, &free, QueryOptions::default());
    let direct = free_planner.query(&[0.1, 0.5], &[0.9, 0.5]).expect("path");
    assert_eq!(direct.len(), 2, "the direct edge is free");
}

/// After the lazy loop, the path LPA* repaired must be as short as a fresh A* over what is
/// known. (An earlier version stopped one step early when a goal neighbour's key exceeded the
/// goal's by rounding, and returned a stale, looping path.)
#[test]
fn lpa_repairs_match_a_fresh_search() {
    let space = JointSpace::new(
        vec![-3.0; 7],
        vec![3.0; 7],
        vec![2.0, 1.5, 1.5, 1.0, 0.8, 0.5, 0.3],
    )
    .expect("space");
    let roadmap = Roadmap::build_lazy(
        &space,
        &RoadmapOptions {
            node_count: 2000,
            resolution: 0.05,
            seed: 4,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let slab = |q: &[f64]| !(q[0].abs() < 0.2 && q[1] < 0.5);
    let mut planner = PrmPlanner::new(&roadmap, &slab, QueryOptions::default());
    for (i, y) in [-2.5, -1.5, -0.5, 0.0].into_iter().enumerate() {
        let start = [-1.0, y, 0.0, 0.1 * i as f64, 0.0, 1.0, 0.0];
        let goal = [1.0, y, 0.0, 0.0, -0.1 * i as f64, -1.0, 0.0];
        planner.overlay.clear();
        planner.forget_heuristic();
        let s = planner.add_overlay_node(&start);
        planner.connect(s, 10, f64::INFINITY);
        let g = planner.add_overlay_node(&goal);
        planner.connect(g, 10, f64::INFINITY);
        assert!(planner.search_and_validate(s, g));
        assert!(planner.last_stats().edges_invalid > 0);
        let nodes = planner.search.nodes.clone();
        let length: f64 = nodes
            .windows(2)
            .map(|w| {
                space.distance(
                    node_state(&roadmap, &planner.overlay, w[0]),
                    node_state(&roadmap, &planner.overlay, w[1]),
                )
            })
            .sum();
        assert!(planner.astar(s, g));
        let fresh = planner.search.g[g as usize];
        assert!(
            (length - fresh).abs() < 1e-9,
            "query {i}: LPA* {length}, A* {fresh}"
        );
    }
}

#[test]
fn prefiltered_roadmaps_are_still_checked_against_the_environment() {
    // The prefilter (a "self-collision" band) is part of every environment; the wall is not.
    let band = |q: &[f64]| !(0.2..0.25).contains(&q[1]);
    let roadmap = Roadmap::build_prefiltered(
        &square(),
        &band,
        &RoadmapOptions {
            node_count: 400,
            resolution: 0.005,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    assert_eq!(roadmap.validation(), Validation::Prefiltered);
    assert!((0..roadmap.node_count()).all(|i| band(roadmap.state(i))));
    let scene = |q: &[f64]| band(q) && !((0.45..0.55).contains(&q[0]) && q[1] > 0.3);
    let mut planner = PrmPlanner::new(&roadmap, &scene, QueryOptions::default());
    let path = planner.query(&[0.1, 0.9], &[0.9, 0.9]).expect("path");
    assert!(path.is_valid(&square(), &scene, 0.0005));
    assert!(
        planner.last_stats().edges_invalid >= 1,
        "the direct edge crosses the wall"
    );
}
