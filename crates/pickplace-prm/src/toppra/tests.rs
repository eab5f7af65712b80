//! Unit tests of `toppra`.

use super::blend::{distance, norm};
use super::*;

#[test]
fn corners_with_no_tolerance_split_and_every_piece_knows_its_waypoints() {
    // A square's corners: 1 and 3 blended, 2 not (a stop), 2 repeated.
    let w = vec![
        vec![0.0, 0.0],
        vec![1.0, 0.0],
        vec![1.0, 1.0],
        vec![1.0, 1.0],
        vec![0.0, 1.0],
        vec![0.0, 2.0],
    ];
    let parts = BlendedPath::split_with(&w, &[0.0, 0.1, 0.0, 0.3, 0.1, 0.0]).expect("paths");
    assert_eq!(parts.len(), 2);
    assert_eq!(parts[0].ends(), (0, 2));
    assert_eq!(parts[1].ends(), (2, 5));
    assert_eq!(parts[0].locate(0.1), Location::Line { from: 0 });
    let middle = parts[0].corner_middle(1).expect("corner 1 is blended");
    assert_eq!(
        parts[0].locate(middle - 1e-6),
        Location::Arc {
            corner: 1,
            past_middle: false
        }
    );
    assert_eq!(
        parts[0].locate(middle + 1e-6),
        Location::Arc {
            corner: 1,
            past_middle: true
        }
    );
    assert_eq!(
        parts[0].locate(parts[0].length()),
        Location::Line { from: 1 }
    );
    assert!(parts[0].corner_middle(2).is_none());
    assert_eq!(parts[0].corners_between(0.0, parts[0].length()), [1]);
    assert!(parts[0].corners_between(0.0, 0.1).is_empty());
    // The repeated waypoint's first copy (index 2) starts the second part; its corner
    // at index 4 is blended.
    assert_eq!(parts[1].locate(0.0), Location::Line { from: 2 });
    assert!(parts[1].corner_middle(4).is_some());
    let mut q = [0.0; 2];
    let (mut dq, mut ddq) = ([0.0; 2], [0.0; 2]);
    parts[1].eval(
        parts[1].corner_middle(4).expect("blended"),
        &mut q,
        &mut dq,
        &mut ddq,
    );
    let off = ((q[0] - 0.0f64).powi(2) + (q[1] - 1.0f64).powi(2)).sqrt();
    assert!(off <= 0.1 + 1e-9 && off > 0.01, "{off}");
    // Bad lists.
    assert!(BlendedPath::split_with(&w, &[0.1; 3]).is_err());
    assert!(BlendedPath::split_with(&w, &[0.1, -0.1, 0.1, 0.1, 0.1, 0.1]).is_err());
    assert!(BlendedPath::split_with(&w, &[0.1, f64::NAN, 0.1, 0.1, 0.1, 0.1]).is_err());
}

#[test]
fn a_path_shorter_than_one_grid_step_still_takes_time() {
    // A gripper closing by 7.5 mm at 0.1 m/s and 3 m/s²: a trapezoid of
    // L / v + v / a = 0.075 + 0.0333 s (one stage from rest to rest took no time).
    let parts = BlendedPath::split(&[vec![0.0], vec![0.0075]], 0.1).expect("path");
    let options = ToppraOptions {
        max_velocities: vec![0.1],
        max_accelerations: vec![3.0],
        ..ToppraOptions::default()
    };
    let timing = parameterize(&parts[0], &options).expect("times");
    let exact = 0.0075 / 0.1 + 0.1 / 3.0;
    assert!(
        (timing.duration() - exact).abs() < 0.002,
        "{}",
        timing.duration()
    );
}
use proptest::prelude::*;

fn opts(dof: usize, v: f64, a: f64) -> ToppraOptions {
    ToppraOptions {
        max_velocities: vec![v; dof],
        max_accelerations: vec![a; dof],
        grid_step: 0.002,
        sample_period: 0.005,
    }
}

#[test]
fn a_straight_line_takes_the_trapezoid_time() {
    // One joint, 1 rad, 1 rad/s, 2 rad/s²: accelerate 0.5 s over 0.25 rad, cruise 0.5 rad
    // in 0.5 s, decelerate 0.5 s: L / v + v / a = 1.5 s.
    let paths = BlendedPath::split(&[vec![0.0], vec![1.0]], 0.01).expect("path");
    assert_eq!(paths.len(), 1);
    let t = parameterize(&paths[0], &opts(1, 1.0, 2.0)).expect("timed");
    assert!((t.duration() - 1.5).abs() < 0.005, "{}", t.duration());
    // Triangle: 0.1 rad at 2 rad/s² peaks at √0.1 rad/s: 2 √(0.1 / 2) s.
    let short = BlendedPath::split(&[vec![0.0], vec![0.1]], 0.01).expect("path");
    let t = parameterize(&short[0], &opts(1, 1.0, 2.0)).expect("timed");
    let expected = 2.0 * (0.1f64 / 2.0).sqrt();
    assert!(
        (t.duration() - expected).abs() < 0.01 * expected,
        "{}",
        t.duration()
    );
}

#[test]
fn blends_stay_within_the_tolerance_and_keep_the_tangent_continuous() {
    let w = vec![
        vec![0.0, 0.0, 0.0],
        vec![1.0, 0.0, 0.0],
        vec![1.0, 1.0, 0.5],
        vec![0.2, 1.2, 0.5],
    ];
    let tol = 0.05;
    let paths = BlendedPath::split(&w, tol).expect("path");
    assert_eq!(paths.len(), 1);
    let p = &paths[0];
    let (mut q, mut dq, mut ddq) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
    let mut prev: Option<Vec<f64>> = None;
    let n = 20_000;
    let mut nearest = [f64::INFINITY; 2];
    for k in 0..=n {
        let s = p.length() * k as f64 / n as f64;
        p.eval(s, &mut q, &mut dq, &mut ddq);
        assert!((norm(&dq) - 1.0).abs() < 1e-9, "unit tangent");
        if let Some(pd) = &prev {
            assert!(distance(pd, &dq) < 1e-2, "tangent jumps at s = {s}");
        }
        prev = Some(dq.clone());
        for (c, corner) in [&w[1], &w[2]].iter().enumerate() {
            nearest[c] = nearest[c].min(distance(&q, corner));
        }
    }
    for d in nearest {
        // The arc's middle is the tolerance away when the tolerance bounds the blend.
        assert!(d <= tol * (1.0 + 1e-6) && d > 0.5 * tol, "{d}");
    }
    // Ends are the first and last waypoints.
    p.eval(0.0, &mut q, &mut dq, &mut ddq);
    assert!(distance(&q, &w[0]) < 1e-12);
    p.eval(p.length(), &mut q, &mut dq, &mut ddq);
    assert!(distance(&q, &w[3]) < 1e-9);
}

#[test]
fn a_reversal_splits_the_path() {
    let w = vec![
        vec![0.0, 0.0],
        vec![1.0, 0.0],
        vec![0.5, 0.0],
        vec![0.5, 0.5],
    ];
    let paths = BlendedPath::split(&w, 0.01).expect("paths");
    assert_eq!(paths.len(), 2);
    assert!((paths[0].length() - 1.0).abs() < 1e-12);
}

#[test]
fn the_limits_hold_along_the_timed_path() {
    let w = vec![
        vec![0.0, 0.0, 0.0],
        vec![0.8, 0.1, -0.3],
        vec![1.0, 0.9, 0.2],
        vec![0.1, 1.3, 0.6],
        vec![-0.4, 0.2, 0.1],
    ];
    let o = ToppraOptions {
        max_velocities: vec![1.0, 0.7, 1.5],
        max_accelerations: vec![3.0, 2.0, 4.0],
        ..opts(3, 1.0, 1.0)
    };
    let paths = BlendedPath::split(&w, 0.05).expect("path");
    let timing = parameterize(&paths[0], &o).expect("timed");
    let traj = sample(&paths[0], &timing, 0.002).expect("sampled");
    let first = &traj.points[0];
    let last = traj.points.last().expect("points");
    assert!(first.velocities.iter().all(|v| v.abs() < 1e-9));
    assert!(last.velocities.iter().all(|v| v.abs() < 1e-6));
    assert!(distance(&last.positions, &w[4]) < 1e-9);
    for p in &traj.points {
        for j in 0..3 {
            assert!(
                p.velocities[j].abs() <= o.max_velocities[j] * 1.001,
                "{p:?}"
            );
            // The limits are met at both ends of every stage; in between, on an arc,
            // the acceleration may drift by a fraction of a percent.
            assert!(
                p.accelerations[j].abs() <= o.max_accelerations[j] * 1.01,
                "{p:?}"
            );
        }
    }
    // Time-optimal: some joint is at a limit almost everywhere.
    let saturated = traj
        .points
        .iter()
        .filter(|p| {
            (0..3).any(|j| {
                p.velocities[j].abs() >= 0.98 * o.max_velocities[j]
                    || p.accelerations[j].abs() >= 0.95 * o.max_accelerations[j]
            })
        })
        .count();
    assert!(
        saturated as f64 >= 0.9 * traj.points.len() as f64,
        "{saturated}"
    );
}

/// A stage's bands as [`push_bands`] makes them: `lo ≤ 0 ≤ hi`, one slope each.
fn bands_strategy() -> impl Strategy<Value = Vec<Band>> {
    proptest::collection::vec((-50.0..50.0f64, 0.01..20.0f64, 0.01..20.0f64), 0..16).prop_map(|v| {
        v.into_iter()
            .map(|(slope, l, h)| Band {
                slope,
                lo: -l,
                hi: h,
            })
            .collect()
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        rng_seed: proptest::test_runner::RngSeed::Fixed(19),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Newton's method on the envelopes finds the pairwise intersection of the half-lines,
    /// whatever pair it starts from.
    #[test]
    fn x_range_is_the_pairwise_intersection(
        bands in bands_strategy(),
        x_max in 0.0..100.0f64,
        d in 1e-4..0.2f64,
        hi in prop_oneof![Just(0.0), 0.0..50.0f64],
        hints in proptest::collection::vec((0usize..20, 0usize..20), 0..4),
    ) {
        let (expected_a, expected_b) = x_range_pairwise(&bands, x_max, d, 0.0, hi);
        let ((a, b), binding) = x_range(&bands, x_max, d, (0.0, hi), &hints);
        prop_assert_eq!(a, expected_a);
        let tolerance = 1e-12 * (1.0 + expected_b.abs());
        prop_assert!((b.max(0.0) - expected_b.max(0.0)).abs() <= tolerance, "{b} {expected_b}");
        if let Some(pair) = binding {
            // The binding pair's root is the end.
            let next = Band { slope: -1.0 / (2.0 * d), lo: 0.0, hi: hi / (2.0 * d) };
            let (c, root) = pair_root(&bands, &next, pair);
            prop_assert!(c > 0.0);
            prop_assert!(b >= 0.0 || root == b || b == f64::NEG_INFINITY);
        }
    }

    /// `last_at_most` is `partition_point` whatever the hint.
    #[test]
    fn last_at_most_is_partition_point(
        mut v in proptest::collection::vec(0u8..20, 0..40),
        x in 0u8..22,
        hint in 0usize..45,
    ) {
        v.sort_unstable();
        let v: Vec<f64> = v.into_iter().map(f64::from).collect();
        let x = f64::from(x);
        let expected = v.partition_point(|&t| t <= x).saturating_sub(1);
        prop_assert_eq!(last_at_most(&v, x, hint), expected);
    }
}

#[test]
fn sampling_walks_as_state_and_eval_search() {
    let w = vec![
        vec![0.0, 0.0, 0.0],
        vec![0.8, 0.1, -0.3],
        vec![1.0, 0.9, 0.2],
        vec![0.1, 1.3, 0.6],
        vec![-0.4, 0.2, 0.1],
    ];
    let o = opts(3, 1.0, 2.0);
    let paths = BlendedPath::split(&w, 0.05).expect("path");
    let timing = parameterize(&paths[0], &o).expect("timed");
    let traj = sample(&paths[0], &timing, 0.003).expect("sampled");
    let (mut q, mut dq, mut ddq) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 3]);
    for p in &traj.points {
        let (s, sd, sdd) = timing.state(p.time_from_start);
        paths[0].eval(s, &mut q, &mut dq, &mut ddq);
        assert_eq!(p.positions, q);
        let v: Vec<f64> = dq.iter().map(|d| d * sd).collect();
        let a: Vec<f64> = (0..3).map(|j| dq[j] * sdd + ddq[j] * sd * sd).collect();
        assert_eq!(p.velocities, v);
        assert_eq!(p.accelerations, a);
    }
    assert_eq!(
        traj.points.last().map(|p| p.time_from_start),
        Some(timing.duration())
    );
}

#[test]
fn limits_so_small_they_allow_no_speed_are_refused_not_timed_at_zero() {
    // 1e-300 squared underflows to 0: every stage would get no speed, and used to take
    // no time, so the robot jumped along the path in 0 s.
    let path = BlendedPath::split(&[vec![0.0, 0.0], vec![1.0, 0.5]], 0.01).expect("a path");
    let o = ToppraOptions {
        max_velocities: vec![1e-300, 1.0],
        ..opts(2, 1.0, 1.0)
    };
    let e = parameterize(&path[0], &o).expect_err("no speed");
    assert!(matches!(e, Error::TooManyPoints { .. }), "{e}");
    assert!(e.to_string().contains("no speed"), "{e}");
}

#[test]
fn bad_options_are_refused() {
    let paths = BlendedPath::split(&[vec![0.0], vec![1.0]], 0.01).expect("path");
    let mut o = opts(1, 1.0, 1.0);
    o.max_velocities = vec![0.0];
    assert!(parameterize(&paths[0], &o).is_err());
    let mut o = opts(1, 1.0, 1.0);
    o.max_accelerations = vec![1.0, 1.0];
    assert!(parameterize(&paths[0], &o).is_err());
    let mut o = opts(1, 1.0, 1.0);
    o.grid_step = 1e-9;
    assert!(matches!(
        parameterize(&paths[0], &o),
        Err(Error::TooManyPoints { .. })
    ));
    assert!(BlendedPath::split(&[vec![0.0], vec![f64::NAN]], 0.01).is_err());
    assert!(BlendedPath::split(&[vec![0.0], vec![1.0]], 0.0).is_err());
}
