//! Time parameterization never exceeds a joint's velocity or acceleration limit, and the timed
//! trajectory passes through every waypoint at rest.

use pickplace_prm::{Path, TimingOptions, time_parameterize};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

fn config() -> ProptestConfig {
    ProptestConfig {
        cases: 64,
        rng_seed: RngSeed::Fixed(13),
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn limits_hold_in_7d(
        points in prop::collection::vec(prop::collection::vec(-2.0..2.0f64, 7), 1..8),
        max_velocities in prop::collection::vec(0.1..3.0f64, 7),
        max_accelerations in prop::collection::vec(0.2..10.0f64, 7),
        sample_period in 0.002..0.05f64,
    ) {
        let path = Path::from_waypoints(7, &points).expect("path");
        let options = TimingOptions { max_velocities, max_accelerations, sample_period };
        let trajectory = time_parameterize(&path, &options).expect("timing");
        let points = &trajectory.points;
        let tolerance = 1e-9;
        for p in points {
            for j in 0..7 {
                prop_assert!(p.velocities[j].abs() <= options.max_velocities[j] * (1.0 + tolerance));
                prop_assert!(p.accelerations[j].abs() <= options.max_accelerations[j] * (1.0 + tolerance));
            }
        }
        // Finite differences: mean velocity and mean acceleration over each interval.
        for w in points.windows(2) {
            let dt = w[1].time_from_start - w[0].time_from_start;
            prop_assert!(dt > 0.0);
            prop_assert!(dt <= sample_period * (1.0 + tolerance));
            for j in 0..7 {
                let v = (w[1].positions[j] - w[0].positions[j]) / dt;
                let a = (w[1].velocities[j] - w[0].velocities[j]) / dt;
                prop_assert!(v.abs() <= options.max_velocities[j] * (1.0 + 1e-6) + 1e-9, "joint {} mean velocity {}", j, v);
                prop_assert!(a.abs() <= options.max_accelerations[j] * (1.0 + 1e-6) + 1e-9, "joint {} mean acceleration {}", j, a);
            }
        }
        // Starts and ends at rest on the path's ends; every waypoint is a sample at rest.
        let first = &points[0];
        let last = points.last().expect("points");
        prop_assert_eq!(first.time_from_start, 0.0);
        prop_assert_eq!(first.positions.as_slice(), path.waypoint(0));
        prop_assert_eq!(last.positions.as_slice(), path.waypoint(path.len() - 1));
        prop_assert!(first.velocities.iter().chain(&last.velocities).all(|v| *v == 0.0));
        let mut cursor = 0;
        for waypoint in path.waypoints() {
            let found = points[cursor..].iter().position(|p| p.positions == waypoint && p.velocities.iter().all(|v| *v == 0.0));
            prop_assert!(found.is_some(), "waypoint {:?} missing", waypoint);
            cursor += found.unwrap_or(0);
        }
    }
}

/// Some joint reaches its velocity or acceleration limit on every segment: the profile is not
/// slower than the synchronised straight-line motion allows.
#[test]
fn each_segment_saturates_a_limit() {
    let path = Path::from_waypoints(
        3,
        [
            [0.0, 0.0, 0.0],
            [1.0, -0.5, 0.2],
            [1.0, 0.5, 0.2],
            [0.9, 0.5, 0.25],
        ],
    )
    .expect("path");
    let options = TimingOptions {
        max_velocities: vec![0.8, 1.0, 0.1],
        max_accelerations: vec![2.0, 1.0, 0.5],
        sample_period: 0.001,
    };
    let trajectory = time_parameterize(&path, &options).expect("timing");
    // Split the samples into segments at the waypoints (velocity zero after the start).
    let mut segment_peaks: Vec<f64> = Vec::new();
    let mut peak: f64 = 0.0;
    for p in trajectory.points.iter().skip(1) {
        let ratio = (0..3)
            .map(|j| {
                (p.velocities[j] / options.max_velocities[j])
                    .abs()
                    .max((p.accelerations[j] / options.max_accelerations[j]).abs())
            })
            .fold(0.0, f64::max);
        peak = peak.max(ratio);
        if p.velocities.iter().all(|v| *v == 0.0) {
            segment_peaks.push(peak);
            peak = 0.0;
        }
    }
    assert_eq!(segment_peaks.len(), 3);
    for peak in segment_peaks {
        assert!((peak - 1.0).abs() < 1e-9, "peak ratio {peak}");
    }
}
