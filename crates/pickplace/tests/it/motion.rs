//! Motion queries (`pickplace::motion`, issue 35) on NX-HIRO's scene of the paper's Fig. 9:
//! paths around obstacles, checked again by the collision world's full query (every pair,
//! every link) at the validator's 1°, the joints' limits, determinism, reasons and errors.

use super::root;
use pickplace::SetupOptions;
use pickplace::geometry::math::{Isometry3, Real, Translation3, UnitQuaternion};
use pickplace::motion::{
    MotionOptions, MotionOutcome, MotionPlan, MotionRequest, MotionWorld, NoMotion, Obstacle,
    ObstacleShape, StateSpec, plan_motion,
};
use pickplace::robot::collision::{CheckOptions, CollisionScratch};

const START: [Real; 6] = [-0.5, -0.3, -2.0, 0.2, 0.3, 0.1];
const GOAL: [Real; 6] = [0.2, -0.5, -1.5, 0.0, 0.0, 0.0];

fn world() -> MotionWorld {
    MotionWorld::load(
        &root().join("scenes/fig9-near.toml"),
        &SetupOptions::default(),
    )
    .expect("the shipped scene loads for motion")
}

fn request(start: &[Real], goal: &[Real]) -> MotionRequest {
    MotionRequest {
        group: Some("right_arm".into()),
        start: StateSpec::Values(start.to_vec()),
        goal: StateSpec::Values(goal.to_vec()),
    }
}

fn planned(world: &MotionWorld, request: &MotionRequest) -> MotionPlan {
    match plan_motion(world, request, &MotionOptions::default()).expect("well formed") {
        MotionOutcome::Planned(m) => m,
        MotionOutcome::NoMotion(why) => panic!("no motion: {why}"),
    }
}

/// The full configuration of group values `q` (the right arm's joints by name).
fn full(world: &MotionWorld, plan: &MotionPlan, q: &[Real]) -> Vec<Real> {
    let mut out = world.start().to_vec();
    for (name, &x) in plan.joint_names.iter().zip(q) {
        let v = world.model().variable_index(name).expect("a joint");
        out[v] = x;
    }
    out
}

/// Every state between consecutive samples at 1°, by the world's full query (not the
/// planner's moving view): the colliding pairs, named, with the time.
fn collisions(world: &MotionWorld, plan: &MotionPlan) -> Vec<String> {
    let step = std::f64::consts::PI / 180.0;
    let mut scratch = CollisionScratch::default();
    let w = world.collision_world();
    let mut found = Vec::new();
    for pair in plan.trajectory.windows(2) {
        let (a, b) = (&pair[0].positions, &pair[1].positions);
        let span = a
            .iter()
            .zip(b)
            .map(|(x, y)| (y - x).abs())
            .fold(0.0, Real::max);
        let n = (span / step).ceil().max(1.0) as usize;
        for k in 0..=n {
            let t = k as Real / n as Real;
            let q: Vec<Real> = a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect();
            let hits = w
                .colliding_pairs(
                    world.model(),
                    &full(world, plan, &q),
                    &mut scratch,
                    &CheckOptions::default(),
                )
                .expect("checks");
            for (x, y) in hits {
                found.push(format!(
                    "{} touches {} at {} s",
                    w.body_name(x),
                    w.body_name(y),
                    pair[0].time_from_start
                ));
            }
        }
    }
    found
}

#[test]
fn a_motion_joins_its_states_within_the_limits_and_is_free_at_one_degree() {
    let world = world();
    let plan = planned(&world, &request(&START, &GOAL));
    assert_eq!(plan.group, "right_arm");
    assert_eq!(plan.joint_names.len(), 6);
    let (first, last) = (
        &plan.trajectory[0],
        plan.trajectory.last().expect("samples"),
    );
    for (q, want) in [(&first.positions, &START), (&last.positions, &GOAL)] {
        for (x, y) in q.iter().zip(want.iter()) {
            assert!((x - y).abs() < 1e-9, "{q:?} is not {want:?}");
        }
    }
    assert!(
        first
            .velocities
            .iter()
            .chain(&last.velocities)
            .all(|v| *v == 0.0)
    );
    for pair in plan.trajectory.windows(2) {
        assert!(pair[1].time_from_start > pair[0].time_from_start);
    }
    for p in &plan.trajectory {
        for (j, v) in p.velocities.iter().enumerate() {
            assert!(
                v.abs() <= plan.limits.velocities[j] * 1.001,
                "{v} over the limit"
            );
        }
    }
    assert!((plan.stats.duration - last.time_from_start).abs() < 1e-9);
    assert!(collisions(&world, &plan).is_empty());
}

#[test]
fn an_obstacle_on_the_straight_line_is_gone_around_and_never_touched() {
    let mut world = world();
    let direct = planned(&world, &request(&START, &GOAL));
    // A ball where the wrist passes halfway along the straight motion.
    let middle: Vec<Real> = START
        .iter()
        .zip(GOAL.iter())
        .map(|(a, b)| (a + b) / 2.0)
        .collect();
    let q = full(&world, &direct, &middle);
    let wrist = world
        .model()
        .link_index("RARM_JOINT5_Link")
        .expect("NX-HIRO's wrist");
    let poses = world.model().link_poses(&q).expect("FK");
    let centre = world.collision_world().world_from_root() * poses[wrist];
    world
        .add_obstacle(&Obstacle {
            name: "ball".into(),
            shape: ObstacleShape::Sphere { radius: 0.03 },
            pose: Isometry3::from_parts(
                Translation3::from(centre.translation.vector),
                UnitQuaternion::identity(),
            ),
        })
        .expect("adds");
    let around = planned(&world, &request(&START, &GOAL));
    assert!(
        around.waypoints.len() > 2,
        "the straight line is blocked: {:?}",
        around.waypoints
    );
    assert!(collisions(&world, &around).is_empty());
    // The same query, the same bytes.
    let again = planned(&world, &request(&START, &GOAL));
    assert_eq!(
        around.clone().without_timings().to_json(),
        again.without_timings().to_json()
    );
}

#[test]
fn ends_in_collision_are_reasons_naming_the_pair() {
    let mut world = world();
    let blocked = planned(&world, &request(&START, &GOAL));
    let q = full(&world, &blocked, &GOAL);
    let hand = world.model().link_index("RARM_JOINT5_Link").expect("hand");
    let at =
        world.collision_world().world_from_root() * world.model().link_poses(&q).expect("FK")[hand];
    world
        .add_obstacle(&Obstacle {
            name: "post".into(),
            shape: ObstacleShape::Cylinder {
                radius: 0.02,
                length: 0.3,
            },
            pose: at,
        })
        .expect("adds");
    match plan_motion(&world, &request(&START, &GOAL), &MotionOptions::default()) {
        Ok(MotionOutcome::NoMotion(NoMotion::GoalInCollision(a, b))) => {
            assert!(a == "post" || b == "post", "{a} / {b}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn bad_queries_name_the_field_and_what_is_wrong() {
    let mut world = world();
    let err = |r: &MotionRequest, options: &MotionOptions| {
        plan_motion(&world, r, options)
            .expect_err("refused")
            .to_string()
    };
    let o = MotionOptions::default();
    let mut r = request(&START, &GOAL);
    r.group = Some("tail".into());
    let e = err(&r, &o);
    assert!(
        e.contains("group") && e.contains("right_arm (6 joints)"),
        "{e}"
    );
    r.group = None;
    assert!(err(&r, &o).contains("name one"));
    let mut r = request(&START, &GOAL[..5]);
    assert!(err(&r, &o).contains("5 values for the 6 joints"));
    r.goal = StateSpec::Values(vec![9.0; 6]);
    assert!(err(&r, &o).contains("outside its limits"));
    r.goal = StateSpec::Named("dance".into());
    assert!(err(&r, &o).contains("no group_state \"dance\""));
    r.goal = StateSpec::Joints([("LARM_JOINT0".to_owned(), 0.1)].into());
    assert!(err(&r, &o).contains("no actuated joint \"LARM_JOINT0\""));
    let bad = MotionOptions {
        margin: -1.0,
        ..MotionOptions::default()
    };
    assert!(err(&request(&START, &GOAL), &bad).contains("options.margin"));
    let ball = |radius: Real| Obstacle {
        name: "object".into(),
        shape: ObstacleShape::Sphere { radius },
        pose: Isometry3::identity(),
    };
    let e = world
        .add_obstacle(&ball(0.1))
        .expect_err("the scene's object");
    assert!(e.to_string().contains("two obstacles"), "{e}");
    let e = world
        .add_obstacle(&Obstacle {
            name: "flat".into(),
            ..ball(0.0)
        })
        .expect_err("no size");
    assert!(e.to_string().contains("radius"), "{e}");
}

#[test]
fn a_scene_without_object_or_target_is_a_motion_scene_only() {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("motion-scene");
    std::fs::create_dir_all(&dir).expect("a folder");
    let text = std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("reads");
    // The robot and environment only.
    let robot_end = text.find("[object]").expect("an object table");
    let robot =
        text[..robot_end].replace("../robots", &root().join("robots").display().to_string());
    let path = dir.join("bare.toml");
    std::fs::write(&path, robot).expect("writes");
    let world = MotionWorld::load(&path, &SetupOptions::default()).expect("loads for motion");
    assert_eq!(world.obstacle_names().count(), 0);
    let e = pickplace::Scene::load(&path).expect_err("no pick and place");
    assert!(e.to_string().contains("object: missing"), "{e}");
    // And it plans.
    planned(&world, &request(&START, &GOAL));
}

#[test]
fn every_motion_of_random_queries_and_options_is_free_at_one_degree() {
    // The shipped motion scene: a table box, the pallet mesh, a post and a ball.
    let world = MotionWorld::load(
        &root().join("scenes/motion/nx-hiro-table.toml"),
        &SetupOptions::default(),
    )
    .expect("loads");
    let mut rng = pickplace::prm::rng::Rng::new(7);
    let space = pickplace::roadmaps::arm_space(
        world.model(),
        &(0..6)
            .map(|j| {
                world
                    .model()
                    .variable_index(&format!("RARM_JOINT{j}"))
                    .expect("NX-HIRO's right arm")
            })
            .collect::<Vec<_>>(),
    )
    .expect("a space");
    let sample = |rng: &mut pickplace::prm::rng::Rng| -> Vec<Real> {
        space
            .lower()
            .iter()
            .zip(space.upper())
            .map(|(&lo, &hi)| rng.uniform(lo, hi))
            .collect()
    };
    let (mut planned, mut retried) = (0, 0);
    for k in 0..300u64 {
        let options = MotionOptions {
            seed: k,
            shortcut_attempts: [0, 100][k as usize % 2],
            blend_tolerance: [0.1, 0.3, 0.02][k as usize % 3],
            sample_period: [0.04, 0.1][k as usize % 2],
            ..MotionOptions::default()
        };
        let (a, b) = (sample(&mut rng), sample(&mut rng));
        match plan_motion(&world, &request(&a, &b), &options).expect("well formed") {
            MotionOutcome::Planned(m) => {
                planned += 1;
                retried += usize::from(m.stats.attempts > 1);
                let hits = collisions(&world, &m);
                assert!(hits.is_empty(), "query {k}: {hits:?}");
            }
            MotionOutcome::NoMotion(_) => {}
        }
    }
    eprintln!("{planned} of 300 random queries planned, {retried} searched again");
    assert!(planned >= 50, "only {planned} planned");
}
