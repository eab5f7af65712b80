//! The same seed gives the same roadmap, byte for byte, whatever the number of threads.

use pickplace_prm::{
    PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, codec, motion_valid_by_interpolation,
};

use crate::toy::{world_2d, world_7d};

fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
        .install(f)
}

#[test]
fn lazy_7d_roadmap_is_identical_on_one_and_two_threads() {
    let world = world_7d();
    let options = RoadmapOptions {
        node_count: 2000,
        seed: 42,
        ..RoadmapOptions::default()
    };
    let one = in_pool(1, || {
        Roadmap::build_lazy(&world.space, &options).expect("roadmap")
    });
    let two = in_pool(2, || {
        Roadmap::build_lazy(&world.space, &options).expect("roadmap")
    });
    let bytes_one = codec::encode(&one).expect("encode");
    let bytes_two = codec::encode(&two).expect("encode");
    assert_eq!(bytes_one, bytes_two);
    assert!(one.edge_count() >= 2000 * options.neighbors / 2);
    // Another seed gives another roadmap.
    let other = Roadmap::build_lazy(
        &world.space,
        &RoadmapOptions {
            seed: 43,
            ..options
        },
    )
    .expect("roadmap");
    assert_ne!(codec::encode(&other).expect("encode"), bytes_one);
}

#[test]
fn checked_and_prefiltered_roadmaps_are_identical_on_one_and_two_threads() {
    for (world, resolution) in [(world_2d(), 0.01), (world_7d(), 0.05)] {
        let options = RoadmapOptions {
            node_count: 800,
            resolution,
            seed: 7,
            ..RoadmapOptions::default()
        };
        let checker = |q: &[f64]| world.free_at(q, resolution);
        let one = in_pool(1, || {
            Roadmap::build(&world.space, &checker, &options).expect("roadmap")
        });
        let two = in_pool(2, || {
            Roadmap::build(&world.space, &checker, &options).expect("roadmap")
        });
        assert_eq!(
            codec::encode(&one).expect("encode"),
            codec::encode(&two).expect("encode")
        );
        let pre_one = in_pool(1, || {
            Roadmap::build_prefiltered(&world.space, &checker, &options).expect("roadmap")
        });
        let pre_two = in_pool(2, || {
            Roadmap::build_prefiltered(&world.space, &checker, &options).expect("roadmap")
        });
        assert_eq!(
            codec::encode(&pre_one).expect("encode"),
            codec::encode(&pre_two).expect("encode")
        );
        assert_eq!(
            pre_one.edges(),
            one.edges(),
            "same checks, another validation label"
        );
        // Every node and edge kept is valid.
        let mut scratch = vec![0.0; world.space.dimension()];
        for &[a, b] in one.edges() {
            let (a, b) = (one.state(a as usize), one.state(b as usize));
            assert!(checker(a) && checker(b));
            assert!(motion_valid_by_interpolation(
                &checker,
                &world.space,
                a,
                b,
                resolution,
                &mut scratch
            ));
        }
    }
}

#[test]
fn queries_are_reproducible() {
    let world = world_7d();
    let resolution = 0.05;
    let roadmap = Roadmap::build_lazy(
        &world.space,
        &RoadmapOptions {
            node_count: 1000,
            resolution,
            seed: 1,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let checker = |q: &[f64]| world.free_at(q, resolution);
    let start = world.free_state(100, resolution);
    let goal = world.free_state(101, resolution);
    let run = || {
        let mut planner = PrmPlanner::new(&roadmap, &checker, QueryOptions::default());
        (
            planner.query(&start, &goal).expect("path"),
            planner.last_stats(),
        )
    };
    let (a, stats_a) = in_pool(1, run);
    let (b, stats_b) = in_pool(2, run);
    assert_eq!(a, b);
    assert_eq!(stats_a, stats_b);
}
