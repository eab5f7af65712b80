//! Shortcutting never lengthens a path, keeps its ends, and is reproducible from its seed.

use pickplace_prm::{Path, ShortcutOptions, shortcut};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

use crate::toy::{world_2d, world_7d};

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 64,
        rng_seed: RngSeed::Fixed(9),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    /// Any path, valid or not: no accepted shortcut makes it longer.
    #[test]
    fn never_lengthens_in_2d(
        points in prop::collection::vec(prop::array::uniform2(0.0..1.0f64), 2..12),
        seed in any::<u64>(),
        attempts in 0usize..200,
    ) {
        let world = world_2d();
        let checker = |q: &[f64]| world.free_at(q, 0.01);
        let path = Path::from_waypoints(2, &points).expect("path");
        let options = ShortcutOptions { attempts, resolution: 0.01, seed };
        let short = shortcut(&world.space, &checker, &path, &options).expect("shortcut");
        prop_assert!(short.length(&world.space) <= path.length(&world.space) + 1e-9);
        prop_assert_eq!(short.waypoint(0), path.waypoint(0));
        prop_assert_eq!(short.waypoint(short.len() - 1), path.waypoint(path.len() - 1));
        prop_assert!(short.len() <= path.len() + 2 * attempts);
        let again = shortcut(&world.space, &checker, &path, &options).expect("shortcut");
        prop_assert_eq!(again, short);
    }

    #[test]
    fn never_lengthens_in_7d(
        points in prop::collection::vec(prop::collection::vec(-1.4..0.3f64, 7), 2..10),
        seed in any::<u64>(),
    ) {
        let world = world_7d();
        let checker = |q: &[f64]| world.free_at(q, 0.05);
        let path = Path::from_waypoints(7, &points).expect("path");
        let options = ShortcutOptions { resolution: 0.05, seed, ..ShortcutOptions::default() };
        let short = shortcut(&world.space, &checker, &path, &options).expect("shortcut");
        prop_assert!(short.length(&world.space) <= path.length(&world.space) + 1e-9);
        prop_assert_eq!(short.waypoint(0), path.waypoint(0));
        prop_assert_eq!(short.waypoint(short.len() - 1), path.waypoint(path.len() - 1));
    }
}

/// A detour through free space is straightened; a valid path stays valid.
#[test]
fn a_valid_detour_is_straightened() {
    let world = world_2d();
    let checker = |q: &[f64]| world.free_at(q, 0.01);
    // Left of the first wall: up, across, down.
    let path = Path::from_waypoints(
        2,
        [
            [0.05, 0.05],
            [0.05, 0.9],
            [0.2, 0.9],
            [0.2, 0.1],
            [0.25, 0.05],
        ],
    )
    .expect("path");
    assert!(path.is_valid(&world.space, &checker, 0.01));
    let short = shortcut(
        &world.space,
        &checker,
        &path,
        &ShortcutOptions {
            resolution: 0.01,
            ..ShortcutOptions::default()
        },
    )
    .expect("shortcut");
    assert_eq!(short.len(), 2);
    assert!((short.length(&world.space) - 0.2).abs() < 1e-12);
}
