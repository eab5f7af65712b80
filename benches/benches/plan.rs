//! Benchmarks of the online planner (issue 7, paper Fig. 8): the whole plan of the paper's
//! Fig. 9 scene, the can near the right hand (RIGHT-RIGHT, target ≤ 100 ms) and far to the left
//! (a LEFT-RIGHT handover, target ≤ 300 ms), with the cluster databases and the roadmaps
//! precomputed (loaded from the cache before timing). What is timed: placement candidates,
//! grasp candidates, strategies, key poses with IK and collision, PRM motions, timing.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace::planner::{Outcome, PlanOptions};
use pickplace::{Setup, SetupOptions};
use pickplace_benches::repo;
use std::hint::black_box;

fn setup(scene: &str) -> Setup {
    let options = SetupOptions {
        cache_dir: Some(repo().join("target/pickplace-cache")),
        ..SetupOptions::default()
    };
    Setup::load(&repo().join("scenes").join(scene), &options).expect("shipped scene sets up")
}

fn bench_plan(c: &mut Criterion) {
    let mut group = c.benchmark_group("plan");
    group.sample_size(20);
    for (id, scene, handover) in [
        ("fig9_near", "fig9-near.toml", false),
        ("fig9_far_handover", "fig9-far-left.toml", true),
    ] {
        let setup = setup(scene);
        let options = PlanOptions {
            timings: false,
            ..PlanOptions::for_setup(&setup)
        };
        // The bench measures a plan that succeeds, with or without a handover as the issue says.
        match pickplace::plan(&setup, &options).expect("plans") {
            Outcome::Planned(plan) => assert_eq!(plan.strategy.has_handover(), handover),
            Outcome::NoPlan(f) => panic!("{scene}: no plan: {:?}", f.reasons),
        }
        group.bench_function(id, |b| {
            b.iter(|| black_box(pickplace::plan(black_box(&setup), &options).expect("plans")))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_plan);
criterion_main!(benches);
