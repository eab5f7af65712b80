//! Issue 33: called with their default resolutions, `rrt_connect`, the roadmap queries and
//! `shortcut` return paths that are collision-free when re-checked at 1° per joint (the
//! validator's `MAX_JOINT_STEP`), even across walls thinner than the old default resolution
//! (0.05) and across joints whose distance weight is small.
//!
//! The planners see the walls inflated by half a degree per joint (Chebyshev clearance). A
//! segment whose states were checked at most 1° apart per joint has every point within half a
//! degree of a checked state, so it cannot touch the true (thin) walls: each returned segment is
//! intersected exactly with them. The planners' raw paths are also re-checked with their own
//! validity function at 1° (`Path::is_valid`, which samples each segment where the planners
//! did; a shortcut's piece of an old segment was checked on the old segment's samples, so only
//! the exact test applies to it).

use pickplace_prm::{
    JointSpace, Path, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, RrtOptions,
    ShortcutOptions, rrt_connect, shortcut,
};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// The validator's joint step (`pickplace::validate::MAX_JOINT_STEP`), written out here so
/// that this file also compiles against the code before the fix.
const ONE_DEGREE: f64 = std::f64::consts::PI / 180.0;

/// Closed axis-aligned boxes in joint space.
struct Walls {
    boxes: Vec<(Vec<f64>, Vec<f64>)>,
}

impl Walls {
    /// Chebyshev (max-norm, joint units) distance from `q` to the nearest box (0 inside one).
    fn clearance(&self, q: &[f64]) -> f64 {
        self.boxes
            .iter()
            .map(|(lower, upper)| {
                q.iter()
                    .zip(lower.iter().zip(upper))
                    .map(|(x, (lo, hi))| (lo - x).max(x - hi).max(0.0))
                    .fold(0.0, f64::max)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// What the planners see: the boxes inflated by half a degree per joint.
    fn planning_free(&self, q: &[f64]) -> bool {
        self.clearance(q) > 0.5 * ONE_DEGREE
    }

    /// The first box that the straight segment `a → b` touches (slab test, exact up to
    /// rounding).
    fn segment_hit(&self, a: &[f64], b: &[f64]) -> Option<usize> {
        self.boxes.iter().position(|(lower, upper)| {
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            for i in 0..a.len() {
                let v = b[i] - a[i];
                if v == 0.0 {
                    if a[i] < lower[i] || a[i] > upper[i] {
                        return false;
                    }
                    continue;
                }
                let (u0, u1) = ((lower[i] - a[i]) / v, (upper[i] - a[i]) / v);
                t0 = t0.max(u0.min(u1));
                t1 = t1.min(u0.max(u1));
                if t0 > t1 {
                    return false;
                }
            }
            true
        })
    }
}

/// `path` joins `start` to `goal`, no segment touches a true wall, and (when `recheck`) the
/// planners' validity function accepts it re-checked at 1°.
fn check(
    walls: &Walls,
    space: &JointSpace,
    path: &Path,
    (start, goal): (&[f64], &[f64]),
    what: &str,
    recheck: bool,
) -> Result<(), TestCaseError> {
    prop_assert!(path.len() >= 2, "{what}: {} waypoints", path.len());
    prop_assert_eq!(path.waypoint(0), start, "{}: start", what);
    prop_assert_eq!(path.waypoint(path.len() - 1), goal, "{}: goal", what);
    for (i, (a, b)) in path.waypoints().zip(path.waypoints().skip(1)).enumerate() {
        if let Some(wall) = walls.segment_hit(a, b) {
            return Err(TestCaseError::fail(format!(
                "{what}: segment {i} {a:?} -> {b:?} crosses wall {wall} \
                 (the default resolution missed it)"
            )));
        }
    }
    let free = |q: &[f64]| walls.planning_free(q);
    prop_assert!(
        !recheck || path.is_valid(space, &free, ONE_DEGREE),
        "{what}: a state collides when re-checked at 1°"
    );
    Ok(())
}

/// Plans `start → goal` with every planner at its default resolution (seeded by `seed`) and
/// checks each path and its shortcut.
fn plan_all_and_check(
    walls: &Walls,
    space: &JointSpace,
    node_count: usize,
    start: &[f64],
    goal: &[f64],
    seed: u64,
) -> Result<(), TestCaseError> {
    let free = |q: &[f64]| walls.planning_free(q);
    prop_assert!(free(start) && free(goal));
    let fail = |what: &'static str| {
        move |e: pickplace_prm::Error| TestCaseError::fail(format!("{what}: {e}"))
    };
    let mut paths = Vec::new();
    let rrt = RrtOptions {
        seed,
        ..RrtOptions::default()
    };
    paths.push((
        "rrt_connect",
        rrt_connect(space, &free, start, goal, &rrt).map_err(fail("rrt_connect"))?,
    ));
    let roadmap_options = RoadmapOptions {
        node_count,
        seed,
        ..RoadmapOptions::default()
    };
    let query = QueryOptions {
        seed,
        ..QueryOptions::default()
    };
    let lazy = Roadmap::build_lazy(space, &roadmap_options).map_err(fail("build_lazy"))?;
    let path = PrmPlanner::new(&lazy, &free, query.clone())
        .query(start, goal)
        .map_err(fail("lazy query"))?;
    paths.push(("lazy query", path));
    let checked = Roadmap::build(space, &free, &roadmap_options).map_err(fail("build"))?;
    let path = PrmPlanner::new(&checked, &free, query)
        .query(start, goal)
        .map_err(fail("checked query"))?;
    paths.push(("checked query", path));
    let shortcut_options = ShortcutOptions {
        seed,
        ..ShortcutOptions::default()
    };
    for (what, path) in paths {
        check(walls, space, &path, (start, goal), what, true)?;
        let short = shortcut(space, &free, &path, &shortcut_options).map_err(fail("shortcut"))?;
        let what = format!("shortcut of {what}");
        check(walls, space, &short, (start, goal), &what, false)?;
    }
    Ok(())
}

/// The unit square with a wall at `x ∈ [x0, x0 + thickness]`, open above `y = opening`.
fn wall_2d(x0: f64, thickness: f64, opening: f64) -> Walls {
    Walls {
        boxes: vec![(vec![x0, 0.0], vec![x0 + thickness, opening])],
    }
}

fn unit_square() -> JointSpace {
    JointSpace::with_unit_weights(vec![0.0; 2], vec![1.0; 2]).expect("space")
}

/// A wall 0.01 thick (0.027 as the planners see it, under the old default resolution of 0.05):
/// the old defaults joined start and goal straight through it.
#[test]
fn defaults_do_not_cross_a_thin_wall_in_2d() -> Result<(), TestCaseError> {
    let space = unit_square();
    let walls = wall_2d(0.5, 0.01, 0.8);
    for (i, y) in [0.1, 0.2, 0.3, 0.4].into_iter().enumerate() {
        let (start, goal) = ([0.1 + 0.01 * i as f64, y], [0.9, 0.5 - y]);
        plan_all_and_check(&walls, &space, 300, &start, &goal, i as u64)?;
    }
    Ok(())
}

/// 7 joints in [-1, 1], the last weighted 0.25: a wall across it (0.01 thick, open where
/// q0 > 0.5). A resolution counted only in the weighted distance lets that joint move 2° between
/// checked states (0.1 rad at the old 0.05): the default must bound every joint's step.
#[test]
fn defaults_do_not_cross_a_thin_wall_across_a_light_joint_in_7d() -> Result<(), TestCaseError> {
    let mut weights = vec![1.0; 7];
    weights[6] = 0.25;
    let space = JointSpace::new(vec![-1.0; 7], vec![1.0; 7], weights).expect("space");
    let mut lower = vec![-1.0; 7];
    let mut upper = vec![1.0; 7];
    (lower[0], upper[0]) = (-1.0, 0.5);
    (lower[6], upper[6]) = (0.32, 0.33);
    let walls = Walls {
        boxes: vec![(lower, upper)],
    };
    let mut start = vec![0.0; 7];
    let mut goal = vec![0.0; 7];
    (start[6], goal[6]) = (-1.0, 1.0);
    plan_all_and_check(&walls, &space, 500, &start, &goal, 0)?;
    (start[1], goal[2]) = (0.3, -0.4);
    plan_all_and_check(&walls, &space, 500, &start, &goal, 1)?;
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        rng_seed: RngSeed::Fixed(33),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Random thin walls (up to 0.02 thick, under the old default resolution even once
    /// inflated), openings, ends and seeds.
    #[test]
    fn defaults_do_not_cross_random_thin_walls(
        x0 in 0.3f64..0.7,
        thickness in 0.0f64..0.02,
        opening in 0.5f64..0.9,
        y in prop::array::uniform2(0.05f64..0.4),
        seed in any::<u64>(),
    ) {
        let walls = wall_2d(x0, thickness, opening);
        plan_all_and_check(&walls, &unit_square(), 200, &[0.1, y[0]], &[0.9, y[1]], seed)?;
    }
}
