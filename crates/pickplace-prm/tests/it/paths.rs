//! Every returned path is valid when re-checked at ten times finer resolution against the true
//! obstacles (the planners see them inflated by half their resolution: see `toy`).

use pickplace_prm::{
    Path, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, RrtOptions, ShortcutOptions,
    rrt_connect, shortcut,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

use crate::toy::{World, world_2d, world_7d};

fn config(cases: u32) -> ProptestConfig {
    ProptestConfig {
        cases,
        rng_seed: RngSeed::Fixed(5),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// The path starts at `start`, ends at `goal` and is valid at a tenth of `resolution`.
fn check_path(
    world: &World,
    path: &Path,
    start: &[f64],
    goal: &[f64],
    resolution: f64,
) -> Result<(), TestCaseError> {
    prop_assert!(path.len() >= 2);
    prop_assert_eq!(path.waypoint(0), start);
    prop_assert_eq!(path.waypoint(path.len() - 1), goal);
    let free = |q: &[f64]| world.free(q);
    prop_assert!(
        path.is_valid(&world.space, &free, resolution / 10.0),
        "path invalid at fine resolution"
    );
    Ok(())
}

fn plan_and_check(
    world: &World,
    roadmap: &Roadmap,
    seed: u64,
    lazy_start: u64,
) -> Result<(), TestCaseError> {
    let resolution = roadmap.options().resolution;
    let checker = |q: &[f64]| world.free_at(q, resolution);
    let options = QueryOptions {
        seed,
        ..QueryOptions::default()
    };
    let mut planner = PrmPlanner::new(roadmap, &checker, options);
    // Two queries on one planner: the second reuses the first's cached statuses.
    for k in 0..2 {
        let start = world.free_state(lazy_start * 4 + 2 * k, resolution);
        let goal = world.free_state(lazy_start * 4 + 2 * k + 1, resolution);
        let path = planner
            .query(&start, &goal)
            .map_err(|e| TestCaseError::fail(format!("query: {e}")))?;
        check_path(world, &path, &start, &goal, resolution)?;
        let short = shortcut(
            &world.space,
            &checker,
            &path,
            &ShortcutOptions {
                resolution,
                seed,
                ..ShortcutOptions::default()
            },
        )
        .map_err(|e| TestCaseError::fail(format!("shortcut: {e}")))?;
        check_path(world, &short, &start, &goal, resolution)?;
        prop_assert!(short.length(&world.space) <= path.length(&world.space) + 1e-9);
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(24))]

    #[test]
    fn lazy_prm_paths_in_2d_are_valid(roadmap_seed in any::<u64>(), seed in any::<u64>(), states in 0u64..1_000_000) {
        let world = world_2d();
        let options = RoadmapOptions { node_count: 300, resolution: 0.01, seed: roadmap_seed, ..RoadmapOptions::default() };
        let roadmap = Roadmap::build_lazy(&world.space, &options).expect("roadmap");
        plan_and_check(&world, &roadmap, seed, states)?;
    }

    #[test]
    fn checked_prm_paths_in_2d_are_valid(roadmap_seed in any::<u64>(), seed in any::<u64>(), states in 0u64..1_000_000) {
        let world = world_2d();
        let options = RoadmapOptions { node_count: 300, resolution: 0.01, seed: roadmap_seed, ..RoadmapOptions::default() };
        let checker = |q: &[f64]| world.free_at(q, 0.01);
        let roadmap = Roadmap::build(&world.space, &checker, &options).expect("roadmap");
        plan_and_check(&world, &roadmap, seed, states)?;
    }

    #[test]
    fn rrt_connect_paths_in_2d_are_valid(seed in any::<u64>(), states in 0u64..1_000_000) {
        let world = world_2d();
        let resolution = 0.01;
        let checker = |q: &[f64]| world.free_at(q, resolution);
        let start = world.free_state(2 * states, resolution);
        let goal = world.free_state(2 * states + 1, resolution);
        let options = RrtOptions { step: 0.1, resolution, seed, ..RrtOptions::default() };
        let path = rrt_connect(&world.space, &checker, &start, &goal, &options).map_err(|e| TestCaseError::fail(format!("rrt: {e}")))?;
        check_path(&world, &path, &start, &goal, resolution)?;
    }
}

proptest! {
    #![proptest_config(config(8))]

    #[test]
    fn lazy_prm_paths_in_7d_are_valid(roadmap_seed in any::<u64>(), seed in any::<u64>(), states in 0u64..1_000_000) {
        let world = world_7d();
        let options = RoadmapOptions { node_count: 1000, resolution: 0.05, seed: roadmap_seed, ..RoadmapOptions::default() };
        let roadmap = Roadmap::build_lazy(&world.space, &options).expect("roadmap");
        plan_and_check(&world, &roadmap, seed, states)?;
    }

    #[test]
    fn rrt_connect_paths_in_7d_are_valid(seed in any::<u64>(), states in 0u64..1_000_000) {
        let world = world_7d();
        let resolution = 0.05;
        let checker = |q: &[f64]| world.free_at(q, resolution);
        let start = world.free_state(2 * states, resolution);
        let goal = world.free_state(2 * states + 1, resolution);
        let options = RrtOptions { step: 0.5, resolution, seed, ..RrtOptions::default() };
        let path = rrt_connect(&world.space, &checker, &start, &goal, &options).map_err(|e| TestCaseError::fail(format!("rrt: {e}")))?;
        check_path(&world, &path, &start, &goal, resolution)?;
    }
}

/// The 7-D slab is crossed only through its opening: the planner has to find it.
#[test]
fn seven_d_query_across_the_slab_goes_through_the_opening() {
    let world = world_7d();
    let resolution = 0.05;
    let options = RoadmapOptions {
        node_count: 1500,
        resolution,
        seed: 3,
        ..RoadmapOptions::default()
    };
    let roadmap = Roadmap::build_lazy(&world.space, &options).expect("roadmap");
    let checker = |q: &[f64]| world.free_at(q, resolution);
    let start = [-1.0, -1.5, 0.0, 0.0, 0.0, 1.0, 0.0];
    let goal = [1.0, -1.5, 0.0, 0.0, 0.0, -1.0, 0.0];
    assert!(checker(&start) && checker(&goal));
    let mut planner = PrmPlanner::new(&roadmap, &checker, QueryOptions::default());
    let path = planner.query(&start, &goal).expect("path");
    assert!(path.is_valid(&world.space, &|q: &[f64]| world.free(q), resolution / 10.0));
    // Somewhere the path is inside the slab's extent in q0, and there q1 is above the opening.
    let mut crossed = false;
    let mut q = [0.0; 7];
    for (a, b) in path.waypoints().zip(path.waypoints().skip(1)) {
        for k in 0..=100 {
            world.space.interpolate_into(a, b, k as f64 / 100.0, &mut q);
            if q[0].abs() < 0.15 {
                assert!(q[1] > 0.3, "inside the slab at {q:?}");
                crossed = true;
            }
        }
    }
    assert!(crossed);
    let stats = planner.last_stats();
    assert!(
        stats.edges_invalid > 0,
        "the direct edge crosses the slab: {stats:?}"
    );
    assert!(
        stats.edges_checked < roadmap.edge_count() / 10,
        "lazy: few edges checked: {stats:?}"
    );
}
