//! Benchmarks of robots as their makers ship them (issues 16 and 32): PR2, Baxter, TALOS, two
//! Franka Pandas, TIAGo Pro and Z1 from the PyPI package example-robot-data 6.0.0, and our
//! own one-jaw arm (`scenes/robots/`), found
//! through `PICKPLACE_ROBOTS_PACKAGES` (the folder holding `example-robot-data/`; `cargo xtask
//! test` installs it into `target/robots-venv`).
//!
//! - `robots_setup/NAME`: the first setup of the scene with an empty cache (URDF, SRDF and
//!   meshes read, grippers measured, cluster databases and both arms' roadmaps built), goal
//!   ≤ 2 s on two cores;
//! - `robots_plan/NAME`: its plan, the setup loaded from the cache before timing, goal
//!   ≤ 100 ms.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace::planner::{Outcome, PlanOptions};
use pickplace::{Setup, SetupOptions};
use pickplace_benches::repo;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

/// The scenes of `scenes/robots/` that plan: the four of issue 16, TIAGo Pro (no SRDF: the
/// collision matrix sampled, linkage grippers), Z1 (a jaw turning against a fixed one, both
/// split into convex pieces) and our own one-jaw arm (issue 32).
const ROBOTS: [&str; 7] = [
    "pr2",
    "baxter",
    "talos",
    "two-pandas",
    "tiago-pro",
    "z1",
    "one-jaw-arm",
];

fn packages() -> PathBuf {
    match std::env::var_os("PICKPLACE_ROBOTS_PACKAGES").map(PathBuf::from) {
        Some(d) if d.join("example-robot-data/robots").is_dir() => d,
        _ => panic!(
            "PICKPLACE_ROBOTS_PACKAGES must name the folder that holds example-robot-data/ \
             (`cargo xtask test` installs it into target/robots-venv)"
        ),
    }
}

fn options(cache: Option<PathBuf>) -> SetupOptions {
    SetupOptions {
        cache_dir: cache,
        package_dirs: vec![packages()],
        ..SetupOptions::default()
    }
}

fn scene(name: &str) -> PathBuf {
    repo().join("scenes/robots").join(format!("{name}.toml"))
}

fn bench_setup(c: &mut Criterion) {
    let mut group = c.benchmark_group("robots_setup");
    group.sample_size(10);
    group.measurement_time(Duration::from_secs(20));
    for name in ROBOTS {
        let path = scene(name);
        group.bench_function(name, |b| {
            // No cache: everything is built, every time.
            b.iter(|| black_box(Setup::load(&path, &options(None)).expect("sets up")))
        });
    }
    group.finish();
}

fn bench_plan(c: &mut Criterion) {
    let mut group = c.benchmark_group("robots_plan");
    group.sample_size(20);
    for name in ROBOTS {
        let setup = Setup::load(
            &scene(name),
            &options(Some(repo().join("target/pickplace-cache"))),
        )
        .expect("sets up");
        let plan_options = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(&setup)
        };
        match pickplace::plan(&setup, &plan_options).expect("plans") {
            Outcome::Planned(_) => {}
            Outcome::NoPlan(f) => panic!("{name}: no plan: {:?}", f.reasons),
        }
        group.bench_function(name, |b| {
            b.iter(|| black_box(pickplace::plan(black_box(&setup), &plan_options).expect("plans")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_setup, bench_plan);
criterion_main!(benches);
