//! Roadmaps saved and loaded answer queries as the original; loading for another space fails
//! clearly.

use pickplace_prm::{Error, JointSpace, PrmPlanner, QueryOptions, Roadmap, RoadmapOptions, codec};

use crate::toy::world_7d;

#[test]
fn a_loaded_roadmap_plans_like_the_original() {
    let world = world_7d();
    let resolution = 0.05;
    let options = RoadmapOptions {
        node_count: 1000,
        resolution,
        seed: 17,
        ..RoadmapOptions::default()
    };
    let roadmap = Roadmap::build_lazy(&world.space, &options).expect("roadmap");
    let dir = std::env::temp_dir().join(format!("pickplace-prm-it-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let file = dir.join("right_arm_waist.roadmap");
    std::fs::write(&file, codec::encode(&roadmap).expect("encode")).expect("write");
    let bytes = std::fs::read(&file).expect("read");
    std::fs::remove_dir_all(&dir).expect("clean up");
    let loaded = codec::decode(&bytes, &world.space).expect("decode");
    assert_eq!(loaded, roadmap);
    assert_eq!(loaded.component_count(), roadmap.component_count());

    let checker = |q: &[f64]| world.free_at(q, resolution);
    let start = world.free_state(5, resolution);
    let goal = world.free_state(6, resolution);
    let mut original = PrmPlanner::new(&roadmap, &checker, QueryOptions::default());
    let mut reloaded = PrmPlanner::new(&loaded, &checker, QueryOptions::default());
    assert_eq!(
        original.query(&start, &goal).expect("path"),
        reloaded.query(&start, &goal).expect("path")
    );
}

#[test]
fn a_roadmap_for_another_arm_is_refused() {
    let world = world_7d();
    let roadmap = Roadmap::build_lazy(
        &world.space,
        &RoadmapOptions {
            node_count: 50,
            ..RoadmapOptions::default()
        },
    )
    .expect("roadmap");
    let bytes = codec::encode(&roadmap).expect("encode");
    // The left arm: mirrored first joint bounds.
    let mut lower = world.space.lower().to_vec();
    lower[0] = -2.7;
    let left = JointSpace::new(
        lower,
        world.space.upper().to_vec(),
        world.space.weights().to_vec(),
    )
    .expect("space");
    let error = codec::decode(&bytes, &left).expect_err("another space");
    assert!(matches!(
        error,
        Error::SpaceMismatch {
            joint: 0,
            field: "lower bound",
            ..
        }
    ));
    assert!(
        error.to_string().contains("built for another space"),
        "{error}"
    );
    let six = JointSpace::with_unit_weights(vec![0.0; 6], vec![1.0; 6]).expect("space");
    assert!(matches!(
        codec::decode(&bytes, &six),
        Err(Error::DimensionMismatch {
            stored: 7,
            expected: 6
        })
    ));
}
