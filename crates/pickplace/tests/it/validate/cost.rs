//! What validating costs (issue 33: `pickplace validate` of a scene with a million-triangle
//! environment part did not finish in 120 s). The work is counted, not timed: the same plan,
//! validated in a scene whose extra part, out of the robot's reach, has 100 times more
//! triangles, sets up without clustering the environment or building roadmaps, and the
//! validator prepares exactly as much of the environment.

use super::{near, root};
use pickplace::planner::PlanOptions;
use pickplace::validate::{ValidationWork, validate};
use pickplace::{Setup, SetupOptions, SetupProgress};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// A binary STL of a cube of side `size` (m) standing on its bottom face's centre, each face
/// an `n` × `n` grid of squares, two triangles each (12 n² triangles), wound outwards.
fn tessellated_cube(n: usize, size: f32) -> Vec<u8> {
    let h = size / 2.0;
    // Each face: its corner, then two edge vectors whose cross product points outwards.
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([-h, -h, 0.0], [0.0, size, 0.0], [size, 0.0, 0.0]),
        ([-h, -h, size], [size, 0.0, 0.0], [0.0, size, 0.0]),
        ([-h, -h, 0.0], [size, 0.0, 0.0], [0.0, 0.0, size]),
        ([-h, h, 0.0], [0.0, 0.0, size], [size, 0.0, 0.0]),
        ([-h, -h, 0.0], [0.0, 0.0, size], [0.0, size, 0.0]),
        ([h, -h, 0.0], [0.0, size, 0.0], [0.0, 0.0, size]),
    ];
    let count = 12 * n * n;
    let mut bytes = vec![0u8; 80];
    bytes.extend_from_slice(&u32::try_from(count).expect("small").to_le_bytes());
    let at = |(o, u, v): &([f32; 3], [f32; 3], [f32; 3]), i: usize, j: usize| -> [f32; 3] {
        let (a, b) = (i as f32 / n as f32, j as f32 / n as f32);
        [0, 1, 2].map(|k| o[k] + u[k] * a + v[k] * b)
    };
    for face in &faces {
        for i in 0..n {
            for j in 0..n {
                let [p, q, r, s] = [
                    at(face, i, j),
                    at(face, i + 1, j),
                    at(face, i + 1, j + 1),
                    at(face, i, j + 1),
                ];
                for triangle in [[p, q, r], [p, r, s]] {
                    // The normal is left zero: readers take the winding.
                    bytes.extend_from_slice(&[0u8; 12]);
                    for corner in triangle {
                        for c in corner {
                            bytes.extend_from_slice(&c.to_le_bytes());
                        }
                    }
                    bytes.extend_from_slice(&[0u8; 2]);
                }
            }
        }
    }
    bytes
}

/// `fig9-near` with one more environment part: a 30 cm crate on the floor behind the table,
/// out of the robot's reach, each face an `n` × `n` grid.
fn scene_with_crate(n: usize) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("validate-cost");
    std::fs::create_dir_all(&dir).expect("folder");
    let mesh = dir.join(format!("crate-{n}.stl"));
    std::fs::write(&mesh, tessellated_cube(n, 0.3)).expect("mesh written");
    let shipped =
        std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("shipped scene");
    let absolute = shipped.replace("\"../", &format!("\"{}/", root().display()));
    let part = format!(
        "[[environment]]\nname = \"crate\"\nmesh = {:?}\npose = {{ position = [1.3, 0.6, 0.0] }}\n\n[target]",
        mesh.display().to_string()
    );
    let scene = dir.join(format!("scene-{n}.toml"));
    std::fs::write(&scene, absolute.replacen("[target]", &part, 1)).expect("scene written");
    scene
}

/// The validation setup of `scene` without a cache (so that any clustering or roadmap would
/// be built, and reported), with the stages its progress reported.
fn setup_for_validation(scene: &Path) -> (Setup, Vec<String>) {
    let stages: Arc<Mutex<Vec<String>>> = Arc::default();
    let sink = Arc::clone(&stages);
    let options = SetupOptions {
        cache_dir: None,
        progress: Some(Arc::new(move |p: SetupProgress<'_>| {
            let mut stages = sink.lock().expect("stages");
            if stages.last().is_none_or(|s| s != p.stage) {
                stages.push(p.stage.to_owned());
            }
        })),
        ..SetupOptions::default()
    };
    let setup = Setup::load_for_validation(scene, &options).expect("sets up");
    let stages = stages.lock().expect("stages").clone();
    (setup, stages)
}

#[test]
fn validating_costs_the_same_whatever_the_triangles_of_a_part_out_of_reach() {
    let (_, plan) = near();
    let mut found: Vec<(usize, ValidationWork)> = Vec::new();
    for n in [1, 10] {
        let (setup, stages) = setup_for_validation(&scene_with_crate(n));
        assert_eq!(setup.environment[2].mesh.triangle_count(), 12 * n * n);
        // Nothing is clustered but the object (it moves), no roadmap is built.
        assert!(
            stages
                .iter()
                .all(|s| s.starts_with("clustering object.mesh")),
            "{stages:?}"
        );
        assert!(
            setup
                .environment
                .iter()
                .all(|e| e.clustering.clusters.is_empty())
        );
        assert!(setup.arms.iter().all(|a| a.roadmap.node_count() == 0));
        let report = validate(&setup, plan, Path::new("plan.json")).expect("fits");
        assert!(report.problems.is_empty(), "{:?}", report.problems);
        found.push((report.states_checked, report.work));
    }
    assert_eq!(found[0], found[1], "12 and 1200 triangles out of reach");
    // What was prepared: the table (the start) and the pallet (the placement, the target's
    // surface), never the crate.
    let (near_setup, _) = near();
    let table_and_pallet: usize = near_setup
        .environment
        .iter()
        .map(|e| e.mesh.triangle_count())
        .sum();
    assert_eq!(
        found[0].1,
        ValidationWork {
            environment_parts_prepared: 2,
            environment_triangles_prepared: table_and_pallet,
        }
    );
}

#[test]
fn a_setup_made_for_validation_is_refused_by_the_planner() {
    let (setup, _) = setup_for_validation(&scene_with_crate(2));
    let options = PlanOptions::for_setup(&setup);
    let err = pickplace::planner::plan(&setup, &options).expect_err("refused");
    assert!(err.to_string().contains("validation only"), "{err}");
}
