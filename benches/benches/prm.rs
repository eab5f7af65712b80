//! Benchmarks of pickplace-prm (issue 5): roadmap construction, lazy queries, RRT-Connect,
//! shortcutting and time parameterization on a 7-joint problem, on a rayon pool of two threads.
//!
//! Two problems, each benched by [`bench_problem`], which sees only a [`Problem`]:
//! - `prm_toy`: a 7-D toy space shaped like NX-HIRO's right arm with the waist, with analytic
//!   obstacles (a slab across the waist joint with one opening, eight balls): the cost of the
//!   planner itself, with near-free checks;
//! - `prm_nxhiro`: the real problem, NX-HIRO's `right_arm_waist` group (7 joints) in the
//!   pallet scene of the robot benches, checked by `pickplace_robot`'s collision world (full
//!   robot, 1 cm margin), the other joints at the SRDF `home` state.

use pickplace_benches::{add_pallet_scene, nx_hiro};
use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace::checker::ArmChecker;
use pickplace_prm::{
    JointSpace, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, RrtOptions, ShortcutOptions,
    TimingOptions, ValidityChecker, rrt_connect, shortcut, time_parameterize,
};
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{AllowedCollisionMatrix, CollisionWorld};

/// A planning problem: a joint space, a validity checker and one hard query.
struct Problem {
    space: JointSpace,
    checker: Box<dyn ValidityChecker + Send>,
    /// An environment-independent part of `checker` (self-collisions) to prebuild the roadmap
    /// with ([`Roadmap::build_prefiltered`]); `None`: the queried roadmap is built lazy.
    prefilter: Option<Box<dyn ValidityChecker + Send>>,
    /// Largest weighted distance between two checked states along a motion.
    resolution: f64,
    /// Start and goal pairs whose direct motion is blocked; the query benches cycle through them.
    queries: Vec<(Vec<f64>, Vec<f64>)>,
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

/// The 7-D toy problem shaped like NX-HIRO's right arm with the waist.
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
        prefilter: None,
        resolution,
        // Either side of the slab, below its opening: the direct motion is blocked.
        queries: vec![(
            vec![-1.0, -1.5, 0.0, 0.0, 0.0, 1.0, 0.0],
            vec![1.0, -1.5, 0.0, 0.0, 0.0, -1.0, 0.0],
        )],
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

const GROUP: &str = "right_arm_waist";

/// The problem: NX-HIRO's right arm with the waist in the pallet scene. The roadmap is
/// prefiltered by self-collisions (no scene), the queries check the full scene lazily. Start and
/// goal are the first pair of seeded collision-free configurations whose direct motion collides
/// and that the roadmap joins (the first 8 such pairs).
fn nxhiro_problem() -> Problem {
    let (model, semantics) = nx_hiro();
    let mut home = model.zero_configuration();
    semantics
        .apply_state(&model, "home", &mut home)
        .expect("home exists");
    let variables = semantics
        .chain(&model, GROUP)
        .expect("group")
        .variables()
        .to_vec();
    let limits: Vec<_> = model.variable_limits().copied().collect();
    let lower: Vec<f64> = variables.iter().map(|&v| limits[v].lower).collect();
    let upper: Vec<f64> = variables.iter().map(|&v| limits[v].upper).collect();
    let max_velocities: Vec<f64> = variables
        .iter()
        .map(|&v| {
            if limits[v].velocity > 0.0 {
                limits[v].velocity
            } else {
                1.0
            }
        })
        .collect();
    let space = JointSpace::with_unit_weights(lower, upper).expect("group space");
    let mut world =
        CollisionWorld::new(&model, AllowedCollisionMatrix::from_srdf(semantics.srdf()))
            .expect("valid robot shapes");
    // The planner's own checker (the façade's), over data that lives as long as the bench.
    let model: &'static RobotModel = Box::leak(Box::new(model));
    let variables: &'static [usize] = Box::leak(variables.into_boxed_slice());
    let self_world: &'static CollisionWorld = Box::leak(Box::new(world.clone()));
    let self_collisions = ArmChecker::new(model, self_world, variables, home.clone(), 0.01);
    add_pallet_scene(&mut world);
    let world: &'static CollisionWorld = Box::leak(Box::new(world));
    let checker = ArmChecker::new(model, world, variables, home, 0.01);
    let resolution = 0.05;
    // Seeded collision-free configurations (splitmix64).
    let mut state = 5u64;
    let mut next = move || {
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut free = Vec::new();
    while free.len() < 32 {
        let q: Vec<f64> = space
            .lower()
            .iter()
            .zip(space.upper())
            .map(|(lo, hi)| lo + next() * (hi - lo))
            .collect();
        if checker.is_state_valid(&q) {
            free.push(q);
        }
    }
    let roadmap = Roadmap::build_prefiltered(
        &space,
        &self_collisions,
        &RoadmapOptions {
            node_count: 5000,
            resolution,
            seed: 1,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let mut scratch = vec![0.0; space.dimension()];
    let queries: Vec<(Vec<f64>, Vec<f64>)> = free
        .iter()
        .enumerate()
        .flat_map(|(i, a)| free[i + 1..].iter().map(move |b| (a, b)))
        .filter(|(a, b)| {
            !checker.is_motion_valid(&space, a, b, resolution, &mut scratch)
                && PrmPlanner::new(&roadmap, &checker, QueryOptions::default())
                    .query(a, b)
                    .is_ok()
        })
        .take(8)
        .map(|(a, b)| (a.clone(), b.clone()))
        .collect();
    assert_eq!(
        queries.len(),
        8,
        "8 blocked, solvable pairs among 32 free configurations"
    );
    Problem {
        space,
        checker: Box::new(checker),
        prefilter: Some(Box::new(self_collisions)),
        resolution,
        queries,
        max_accelerations: vec![3.0; max_velocities.len()],
        max_velocities,
    }
}

/// Benches the planner on `problem` under the criterion group `name`; `checked_samples` is the
/// sample count of the (slow) checked roadmap build.
fn bench_problem(c: &mut Criterion, name: &str, problem: &Problem, checked_samples: usize) {
    let checker: &dyn ValidityChecker = problem.checker.as_ref();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("thread pool");
    let options = roadmap_options(problem);

    let mut group = c.benchmark_group(name);
    group.sample_size(20);
    group.bench_function("roadmap_5000_lazy_2_threads", |b| {
        b.iter(|| pool.install(|| Roadmap::build_lazy(&problem.space, &options).expect("roadmap")))
    });
    group.sample_size(checked_samples);
    group.bench_function("roadmap_5000_checked_2_threads", |b| {
        b.iter(|| {
            pool.install(|| Roadmap::build(&problem.space, checker, &options).expect("roadmap"))
        })
    });
    if let Some(prefilter) = &problem.prefilter {
        let prefilter: &dyn ValidityChecker = prefilter.as_ref();
        group.bench_function("roadmap_5000_prefiltered_2_threads", |b| {
            b.iter(|| {
                pool.install(|| {
                    Roadmap::build_prefiltered(&problem.space, prefilter, &options)
                        .expect("roadmap")
                })
            })
        });
    }
    group.finish();

    // The roadmap queried: prefiltered when the problem has a prefilter, lazy otherwise.
    let roadmap = match &problem.prefilter {
        Some(prefilter) => Roadmap::build_prefiltered(&problem.space, prefilter.as_ref(), &options)
            .expect("roadmap"),
        None => Roadmap::build_lazy(&problem.space, &options).expect("roadmap"),
    };
    let mut group = c.benchmark_group(name);
    // A new environment each time: every node and edge on the way is checked (cold cache).
    let mut next = 0;
    group.bench_function("lazy_query_cold", |b| {
        b.iter(|| {
            next = (next + 1) % problem.queries.len();
            let (start, goal) = &problem.queries[next];
            let mut planner = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
            black_box(planner.query(start, goal).expect("path"))
        })
    });
    // The same environment again: statuses cached by the previous queries.
    let mut warm = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
    group.bench_function("lazy_query_warm", |b| {
        b.iter(|| {
            next = (next + 1) % problem.queries.len();
            let (start, goal) = &problem.queries[next];
            black_box(warm.query(start, goal).expect("path"))
        })
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
            let (start, goal) = &problem.queries[seed as usize % problem.queries.len()];
            let options = RrtOptions {
                seed,
                ..rrt_options.clone()
            };
            black_box(rrt_connect(&problem.space, checker, start, goal, &options).is_ok())
        })
    });

    let (start, goal) = &problem.queries[0];
    let mut planner = PrmPlanner::new(&roadmap, checker, QueryOptions::default());
    let path = planner.query(start, goal).expect("path");
    let cold = planner.last_stats();
    planner.query(start, goal).expect("path");
    let rrt = rrt_connect(&problem.space, checker, start, goal, &rrt_options).expect("path");
    println!(
        "{name}: roadmap {} nodes, {} edges, {} components; {} queries; the first from {:.3?} to {:.3?}; \
         cold {cold:?}; warm {:?}; path length {:.3} ({} waypoints), RRT-Connect {:.3} ({} waypoints)",
        roadmap.node_count(),
        roadmap.edge_count(),
        roadmap.component_count(),
        problem.queries.len(),
        start,
        goal,
        planner.last_stats(),
        path.length(&problem.space),
        path.len(),
        rrt.length(&problem.space),
        rrt.len(),
    );
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

/// TOPP-RA (issue 19's goal: a 1 000-waypoint path timed in at most 1 ms): a seeded random
/// walk of 1 000 waypoints through 7 joints, 5 cm (rad) apart with turns of up to about 60°,
/// corners blended within 1 cm, NX-HIRO-like limits (1–3 rad/s, 3 rad/s²), grid step 5 cm.
fn bench_toppra(c: &mut Criterion) {
    use pickplace_prm::toppra::{BlendedPath, ToppraOptions, parameterize};
    let mut rng = pickplace_prm::rng::Rng::new(19);
    let mut q = vec![0.0; 7];
    let mut dir = [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut waypoints = vec![q.clone()];
    for _ in 1..1000 {
        for d in dir.iter_mut() {
            *d += rng.uniform(-0.5, 0.5);
        }
        let n = dir.iter().map(|d| d * d).sum::<f64>().sqrt();
        for (qj, d) in q.iter_mut().zip(dir.iter_mut()) {
            *d /= n;
            *qj += 0.05 * *d;
        }
        waypoints.push(q.clone());
    }
    let paths = BlendedPath::split(&waypoints, 0.01).expect("path");
    let options = ToppraOptions {
        max_velocities: vec![1.0, 1.5, 2.0, 3.0, 3.0, 3.0, 3.0],
        max_accelerations: vec![3.0; 7],
        grid_step: 0.05,
        sample_period: 0.01,
    };
    let timed: f64 = paths
        .iter()
        .map(|p| parameterize(p, &options).expect("timed").duration())
        .sum();
    eprintln!(
        "toppra: {} waypoints, {} part(s), {:.2} rad long, {timed:.2} s of motion",
        waypoints.len(),
        paths.len(),
        paths.iter().map(BlendedPath::length).sum::<f64>()
    );
    let mut group = c.benchmark_group("toppra");
    group.bench_function("1000_waypoints", |b| {
        b.iter(|| {
            for p in &paths {
                black_box(parameterize(p, &options).expect("timed"));
            }
        })
    });
    group.bench_function("1000_waypoints_blend_and_time", |b| {
        b.iter(|| {
            for p in BlendedPath::split(&waypoints, 0.01).expect("path") {
                black_box(parameterize(&p, &options).expect("timed"));
            }
        })
    });
    group.finish();
}

fn prm(c: &mut Criterion) {
    bench_toppra(c);
    bench_problem(c, "prm_toy", &problem(), 20);
    bench_problem(c, "prm_nxhiro", &nxhiro_problem(), 10);
}

criterion_group!(benches, prm);
criterion_main!(benches);
