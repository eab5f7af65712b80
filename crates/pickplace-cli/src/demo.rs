//! `pickplace demo`: the built-in scene of the paper's Fig. 9 (a drink can placed into a dent of
//! a pallet by NX-HIRO), run through every stage the workspace has so far.
//!
//! The scene is built into the binary (the shipped meshes' generators and the robot's gripper
//! configuration), so the demo runs from any directory. Stages: surface clustering of the can
//! and the pallet (Algorithm 1, pictures as PLY), stable placements of the can in the dent
//! (Algorithm 2), grasps of the can with NX-HIRO's gripper. The online planner that joins them
//! into a motion (Fig. 8) is not written yet; the demo says so.

use anyhow::Context;
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::export::{write_atomic, write_clusters_ply};
use pickplace_geometry::math::{Isometry3, Point3};
use pickplace_geometry::mesh::MassProperties;
use pickplace_geometry::shapes;
use pickplace_grasp::json::GraspsJson;
use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
use pickplace_placement::{EnvironmentModel, ObjectModel, PlacementOptions, candidates};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// NX-HIRO's gripper configuration, as shipped in `robots/nx-hiro/gripper.toml`.
const GRIPPER_TOML: &str = include_str!("../../../robots/nx-hiro/gripper.toml");

/// Arguments of `pickplace demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Folder the outputs are written to (created if missing).
    #[arg(long, default_value = "pickplace-demo")]
    pub out: PathBuf,
}

/// Runs the demo.
pub fn run(args: &DemoArgs) -> anyhow::Result<ExitCode> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("{}: cannot create the output folder", args.out.display()))?;
    let out = |name: &str| args.out.join(name);
    let start = Instant::now();
    eprintln!("pickplace demo: the paper's Fig. 9 scene, a can into a dent of a pallet");

    let can = shapes::can_builder().build()?;
    let pallet = shapes::pallet_builder().build()?;
    let env_params = ClusterParams::environment();
    let finger_params = ClusterParams::finger();
    let can_env = cluster_surface(&can, &env_params)?;
    let can_finger = cluster_surface(&can, &finger_params)?;
    let pallet_env = cluster_surface(&pallet, &env_params)?;
    write_clusters_ply(&out("can.env-clusters.ply"), &can, &can_env)?;
    write_clusters_ply(&out("can.finger-clusters.ply"), &can, &can_finger)?;
    write_clusters_ply(&out("pallet.env-clusters.ply"), &pallet, &pallet_env)?;
    eprintln!(
        "  clustering (§III-A): can {} env clusters, {} finger clusters in {} parallel pairs; pallet {} env clusters",
        can_env.clusters.len(),
        can_finger.clusters.len(),
        can_finger.pairs.len(),
        pallet_env.clusters.len()
    );

    // The pallet lies on a table in front of the robot; the user clicks the large dent.
    let world_from_pallet = Isometry3::translation(0.45, -0.10, 0.72);
    let dent = &shapes::PALLET_DENTS[0];
    let target = world_from_pallet
        * Point3::new(
            dent.center[0],
            dent.center[1],
            shapes::PALLET_SIZE[2] - dent.depth,
        );
    let cog = MassProperties::of(&can).center_of_mass;
    let object = ObjectModel::new(&can, &can_env, cog)?;
    let env = EnvironmentModel::new(&pallet, &pallet_env, &world_from_pallet)?;
    let placed = candidates(&object, &env, &target, &PlacementOptions::default())
        .map_err(|e| anyhow::anyhow!("built-in scene: {e}"))?;
    let placements_json = serde_json::json!({
        "format": "pickplace.placements.v1",
        "target": [target.x, target.y, target.z],
        "target_cluster": placed.target_cluster,
        "placements": placed.placements.iter().map(|p| {
            let t = p.world_from_object.translation.vector;
            let q = p.world_from_object.rotation.quaternion();
            serde_json::json!({
                "pose": { "position": [t.x, t.y, t.z], "orientation": [q.i, q.j, q.k, q.w] },
                "contact": p.contact,
                "object_cluster": p.object_cluster,
                "env_cluster": p.env_cluster,
                "stability_margin": p.stability_margin,
            })
        }).collect::<Vec<_>>(),
    });
    write_json(&out("placements.json"), &placements_json)?;
    match placed.placements.first() {
        Some(best) => {
            let t = best.world_from_object.translation.vector;
            eprintln!(
                "  placement (§III-B.2): {} stable candidates; best {:?} at ({:.3}, {:.3}, {:.3}), margin {:.1} mm",
                placed.placements.len(),
                best.contact,
                t.x,
                t.y,
                t.z,
                best.stability_margin * 1e3
            );
        }
        None => eprintln!("  placement (§III-B.2): no stable candidate"),
    }

    let gripper =
        GripperParams::from_toml_str(GRIPPER_TOML, Path::new("robots/nx-hiro/gripper.toml"))?;
    let planner = GraspPlanner::new(&can)?;
    let grasps = planner.plan(&can_finger, &gripper, &GraspOptions::default())?;
    let doc = GraspsJson::new(
        "built-in can",
        "robots/nx-hiro/gripper.toml",
        finger_params.h_max,
        &planner.center_of_mass(),
        &grasps,
    );
    write_json(&out("grasps.json"), &serde_json::to_value(&doc)?)?;
    eprintln!(
        "  grasps (§III-B.1): {} candidates on {} pairs, {} collision-free grasps",
        grasps.candidates,
        grasps.pairs,
        grasps.grasps.len()
    );
    eprintln!(
        "  not yet: strategy selection, key poses with IK, PRM motions and the plan (§III-B.3, §III-C)"
    );
    eprintln!("done in {:.2} s; wrote:", start.elapsed().as_secs_f64());
    for name in [
        "can.env-clusters.ply",
        "can.finger-clusters.ply",
        "pallet.env-clusters.ply",
        "placements.json",
        "grasps.json",
    ] {
        println!("{}", out(name).display());
    }
    Ok(
        if placed.placements.is_empty() || grasps.grasps.is_empty() {
            ExitCode::from(1)
        } else {
            ExitCode::SUCCESS
        },
    )
}

fn write_json(path: &Path, value: &serde_json::Value) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    write_atomic(path, text.as_bytes())?;
    Ok(())
}
