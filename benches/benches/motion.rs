//! Motion queries (issue 35; docs/motion.md): the shipped motion scene's world set up, and
//! queries of NX-HIRO's right arm through `pickplace::motion::plan_motion` (search, shortcut,
//! timing, the final check at 1°), each query alone, with its statistics printed first.

use criterion::{Criterion, criterion_group, criterion_main};
use pickplace::SetupOptions;
use pickplace::motion::{
    MotionOptions, MotionOutcome, MotionRequest, MotionWorld, StateSpec, plan_motion,
};
use std::hint::black_box;
use std::path::{Path, PathBuf};

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/motion/nx-hiro-table.toml")
}

/// Start and goal of the right arm: around the post, beside it, and back around it.
const QUERIES: [(&str, [f64; 6], [f64; 6]); 3] = [
    (
        "around_the_post",
        [-0.5, -0.3, -2.0, 0.2, 0.3, 0.1],
        [0.2, -0.5, -1.5, 0.0, 0.0, 0.0],
    ),
    (
        "beside_the_post",
        [-0.5, -0.3, -2.0, 0.2, 0.3, 0.1],
        [0.1, -0.5, -1.6, 0.0, 0.0, 0.0],
    ),
    (
        "back_around_the_post",
        [0.3, -0.5, -1.5, 0.0, 0.0, 0.0],
        [-0.6, -0.2, -2.2, 0.0, 0.5, 0.0],
    ),
];

fn request(start: &[f64; 6], goal: &[f64; 6]) -> MotionRequest {
    MotionRequest {
        group: Some("right_arm".into()),
        start: StateSpec::Values(start.to_vec()),
        goal: StateSpec::Values(goal.to_vec()),
    }
}

fn motion(c: &mut Criterion) {
    let options = SetupOptions::default();
    let mut group = c.benchmark_group("motion");
    group.bench_function("world_setup", |b| {
        b.iter(|| MotionWorld::load(black_box(&scene()), &options).expect("loads"));
    });
    let world = MotionWorld::load(&scene(), &options).expect("loads");
    let o = MotionOptions::default();
    for (name, start, goal) in QUERIES {
        let r = request(&start, &goal);
        match plan_motion(&world, &r, &o).expect("well formed") {
            MotionOutcome::Planned(m) => eprintln!(
                "motion/{name}: {} waypoints ({} searched), {:.2} rad, {:.2} s, search {:.2} ms \
                 ({} states), shortcut, timing and check {:.2} ms, {} attempt(s)",
                m.waypoints.len(),
                m.stats.raw_waypoints,
                m.stats.length,
                m.stats.duration,
                m.stats.search_ms,
                m.stats.states_checked,
                m.stats.timing_ms,
                m.stats.attempts
            ),
            MotionOutcome::NoMotion(why) => panic!("motion/{name}: {why}"),
        }
        group.bench_function(format!("query_{name}"), |b| {
            b.iter(|| plan_motion(&world, black_box(&r), &o).expect("plans"));
        });
    }
    let raw = MotionOptions {
        shortcut_attempts: 0,
        ..MotionOptions::default()
    };
    let (_, start, goal) = QUERIES[0];
    let r = request(&start, &goal);
    group.bench_function("query_around_the_post_no_shortcut", |b| {
        b.iter(|| plan_motion(&world, black_box(&r), &raw).expect("plans"));
    });
    group.finish();
}

criterion_group!(benches, motion);
criterion_main!(benches);
