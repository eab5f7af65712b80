//! Benchmarks of pickplace-prm (issue 5): roadmap construction, lazy queries, RRT-Connect,
//! shortcutting and time parameterization on a 7-joint problem, on a rayon pool of two threads.
//!
//! The problem is a stand-in: a 7-D toy space shaped like NX-HIRO's right arm with the waist
//! (7 joints) with analytic obstacles (a slab across the waist joint with one opening, eight
//! balls). When the robot crate lands, replace [`problem`] by the right arm + waist group in the
//! pallet scene (its joint limits, weights and collision checker); every bench below takes only a
//! [`Problem`], so nothing else changes.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace_prm::{
    JointSpace, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, RrtOptions, ShortcutOptions,
    TimingOptions, ValidityChecker, rrt_connect, shortcut, time_parameterize,
};

/// A planning problem: a joint space, a validity checker and one hard query.
struct Problem {
    space: JointSpace,
    checker: Box<dyn ValidityChecker + Send>,
    /// Largest weighted distance between two checked states along a motion.
    resolution: f64,
    start: Vec<f64>,
    goal: Vec<f64>,
    max_velocities: Vec<f64>,
    max_accelerations: Vec<f64>,
}

/// Balls of the weighted metric and a slab, checked by exact clearance.
struct ToyWorld {
    space: JointSpace,
    balls: Vec<[f64; 7]>,
    radius: f64,
    margin: f64,
}

impl ValidityChecker for ToyWorld {
    fn is_state_valid(&self, q: &[f64]) -> bool {
        // Slab |q0| < 0.15 except where q1 > 0.3, inflated by the margin (weight of q0: 2, of q1: 1.5).
        let m0 = self.margin / 2f64.sqrt();
        let m1 = self.margin / 1.5f64.sqrt();
        let in_slab = q[0].abs() < 0.15 + m0 && q[1] < 0.3 + m1;
        !in_slab
            && self
                .balls
                .iter()
                .all(|c| self.space.distance(q, c) > self.radius + self.margin)
    }
}

/// The 7-D toy stand-in for NX-HIRO's right arm with the waist in the pallet scene.
fn problem() -> Problem {
    let lower = vec![-2.8, -2.9, -2.4, -2.8, -1.8, -2.9, -2.9];
    let upper = vec![2.8, 1.5, 0.3, 2.8, 1.8, 2.9, 2.9];
    let weights = vec![2.0, 1.5, 1.5, 1.0, 0.8, 0.5, 0.3];
    let space = JointSpace::new(lower, upper, weights).expect("space");
    let resolution = 0.05;
    let world = ToyWorld {
        space: space.clone(),
        balls: vec![
            [-1.5, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0],
            [1.5, -1.0, -1.0, 0.0, 0.0, 0.0, 0.0],
            [-1.0, 0.5, -0.5, 1.5, 0.5, -1.0, 0.0],
            [1.0, 0.5, -0.5, -1.5, -0.5, 1.0, 0.0],
            [-2.0, -2.0, -2.0, -1.0, 1.0, 2.0, 1.0],
            [2.0, -2.0, -2.0, 1.0, -1.0, -2.0, -1.0],
            [0.0, 1.0, -1.5, 0.0, 0.0, 0.0, 2.0],
            [0.0, -2.0, 0.0, 2.0, 1.0, 0.0, -2.0],
        ],
        radius: 0.9,
        margin: 0.5 * resolution,
    };
    Problem {
        space,
        checker: Box::new(world),
        resolution,
        // Either side of the slab, below its opening: the direct motion is blocked.
        start: vec![-1.0, -1.5, 0.0, 0.0, 0.0, 1.0, 0.0],
        goal: vec![1.0, -1.5, 0.0, 0.0, 0.0, -1.0, 0.0],
        max_velocities: vec![1.0, 1.2, 1.2, 1.5, 1.5, 2.0, 2.0],
        max_accelerations: vec![3.0, 3.0, 3.0, 4.0, 4.0, 5.0, 5.0],
    }
}

fn roadmap_options(problem: &Problem) -> RoadmapOptions {
    RoadmapOptions {
        node_count: 5000,
        neighbors: 10,
        resolution: problem.resolution,
        seed: 1,
        ..RoadmapOptions::default()
    }
}

fn prm(c: &mut Criterion) {
    let problem = problem();
    let checker: &dyn ValidityChecker = problem.checker.as_ref();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let options = roadmap_options(&problem);

    let mut group = c.benchmark_group("prm");
    group.sample_size(20);
    group.bench_function("roadmap_5000_lazy_2_threads", |b| {
        b.iter(|| pool.install(|| Roadmap::build_lazy(&problem.space, &options).expect("roadmap")))
    });
    group.bench_function("roadmap_5000_checked_2_threads", |b| {
        b.iter(|| {
            pool.install(|| Roadmap::build(&problem.space, checker, &options).expect("roadmap"))
        })
    });
    group.finish();

    let roadmap = Roadmap::build_lazy(&problem.space, &options).expect("roadmap");
    let mut group = c.benchmark_group("prm");
    // A new environment each time: every node and edge on the way is checked (cold cache).
    group.bench_function("lazy_query_cold", |b| {
        b.iter(|| {
            let mut planner = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
            black_box(planner.query(&problem.start, &problem.goal).expect("path"))
        })
    });
    // The same environment again: statuses cached by the previous queries.
    let mut warm = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
    group.bench_function("lazy_query_warm", |b| {
        b.iter(|| black_box(warm.query(&problem.start, &problem.goal).expect("path")))
    });
    let rrt_options = RrtOptions {
        step: 0.5,
        resolution: problem.resolution,
        ..RrtOptions::default()
    };
    let mut seed = 0u64;
    group.bench_function("rrt_connect", |b| {
        b.iter(|| {
            seed += 1;
            let options = RrtOptions {
                seed,
                ..rrt_options.clone()
            };
            black_box(
                rrt_connect(
                    &problem.space,
                    checker,
                    &problem.start,
                    &problem.goal,
                    &options,
                )
                .expect("path"),
            )
        })
    });

    let mut planner = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
    let path = planner.query(&problem.start, &problem.goal).expect("path");
    let shortcut_options = ShortcutOptions {
        resolution: problem.resolution,
        ..ShortcutOptions::default()
    };
    group.bench_function("shortcut_100", |b| {
        b.iter(|| {
            black_box(
                shortcut(&problem.space, checker, &path, &shortcut_options).expect("shortcut"),
            )
        })
    });
    let short = shortcut(&problem.space, checker, &path, &shortcut_options).expect("shortcut");
    let timing = TimingOptions {
        max_velocities: problem.max_velocities.clone(),
        max_accelerations: problem.max_accelerations.clone(),
        sample_period: 0.01,
    };
    group.bench_function("time_parameterize_10ms", |b| {
        b.iter(|| black_box(time_parameterize(&short, &timing).expect("timing")))
    });
    group.finish();
}

criterion_group!(benches, prm);
criterion_main!(benches);
