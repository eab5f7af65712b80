//! `pickplace demo`: the paper's Fig. 9 (NX-HIRO puts a drink can into a dent of a pallet),
//! planned end to end from the scene built into the binary.
//!
//! The robot files, the scene files and the meshes' generators are compiled in, so the demo
//! runs from any directory: it writes them into `<out>/scene/` and plans from there, twice —
//! the can near the right hand (RIGHT-RIGHT) and far to the left (a handover, LEFT-RIGHT) —
//! then re-checks each plan with the independent validator and draws the handover plan
//! (animated glTF and key-pose pictures) and the clusters of the can and the pallet.

use crate::output::note;
use crate::plan::{CacheChoice, PlanArgs, plan_setup, setup};
use anyhow::Context;
use pickplace::planner::Outcome;
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::export::{write_atomic, write_clusters_ply};
use pickplace_geometry::mesh::write_stl_binary;
use pickplace_objects as objects;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Files of the built-in scene: (path under `<out>/scene/`, contents).
const FILES: [(&str, &str); 6] = [
    (
        "robots/nx-hiro/nx-hiro.urdf",
        include_str!("../../../robots/nx-hiro/nx-hiro.urdf"),
    ),
    (
        "robots/nx-hiro/nx-hiro.srdf",
        include_str!("../../../robots/nx-hiro/nx-hiro.srdf"),
    ),
    (
        "robots/nx-hiro/gripper.toml",
        include_str!("../../../robots/nx-hiro/gripper.toml"),
    ),
    (
        "scenes/fig9-near.toml",
        include_str!("../../../scenes/fig9-near.toml"),
    ),
    (
        "scenes/fig9-far-left.toml",
        include_str!("../../../scenes/fig9-far-left.toml"),
    ),
    (
        "scenes/fig10a-edge.toml",
        include_str!("../../../scenes/fig10a-edge.toml"),
    ),
];

/// Arguments of `pickplace demo`.
#[derive(Debug, clap::Args)]
pub struct DemoArgs {
    /// Folder the outputs are written to (created if missing).
    #[arg(long, default_value = "pickplace-demo")]
    pub out: PathBuf,
    /// Use no cache: cluster databases and roadmaps are built in memory (by default they
    /// are kept in `<out>/cache`, and a second run is faster).
    #[arg(long)]
    pub no_cache: bool,
}

/// Runs the demo.
pub fn run(args: &DemoArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    note!("pickplace demo: the paper's Fig. 9, a can into a dent of a pallet, by NX-HIRO");
    crate::args::check_output_dir(&args.out, "--out", &[])?;
    let scene_dir = args.out.join("scene");
    write_scene(&scene_dir)?;
    let mut written: Vec<PathBuf> = Vec::new();

    // The offline phase's pictures: clusters of the can and the pallet (§III-A, Figs. 3–5).
    let can = objects::can_builder().build()?;
    let pallet = objects::pallet_builder().build()?;
    for (name, mesh, params) in [
        ("can.env-clusters.ply", &can, ClusterParams::environment()),
        ("can.finger-clusters.ply", &can, ClusterParams::finger()),
        (
            "pallet.env-clusters.ply",
            &pallet,
            ClusterParams::environment(),
        ),
    ] {
        let clustering = cluster_surface(mesh, &params)?;
        let path = args.out.join(name);
        write_clusters_ply(&path, mesh, &clustering)?;
        written.push(path);
    }

    let mut failed = false;
    for (case, scene) in [
        ("near", "scenes/fig9-near.toml"),
        ("far-left", "scenes/fig9-far-left.toml"),
    ] {
        let scene_path = scene_dir.join(scene);
        note!(
            "{case}: the can starts {}",
            match case {
                "near" => "near the right hand",
                _ => "far to the left",
            }
        );
        let cache = if args.no_cache {
            CacheChoice::Off
        } else {
            CacheChoice::Folder(args.out.join("cache"))
        };
        let setup = setup(&scene_path, cache, &[])?;
        let plan_args = PlanArgs {
            scene: scene_path.clone(),
            out: None,
            seed: None,
            strategy: None,
            no_timings: false,
            timing: crate::args::TimingArgs::default(),
            folders: crate::args::SceneFolders::default(),
        };
        let plan = match plan_setup(&setup, &plan_args)? {
            Outcome::Planned(plan) => plan,
            Outcome::NoPlan(_) => {
                failed = true;
                continue;
            }
        };
        let plan_path = args.out.join(format!("plan-{case}.json"));
        write_atomic(&plan_path, plan.to_json().as_bytes())
            .with_context(|| format!("{}: cannot write the plan", plan_path.display()))?;
        written.push(plan_path.clone());
        let report = pickplace::validate::validate(&setup, &plan, &plan_path)?;
        if report.problems.is_empty() {
            note!(
                "  validated: {} states checked densely, stability margin {:.1} mm",
                report.states_checked,
                report.stability_margin.unwrap_or(0.0) * 1e3
            );
        } else {
            failed = true;
            for p in &report.problems {
                note!("  INVALID: {p}");
            }
        }
        let view_dir = args.out.join(format!("view-{case}"));
        let pictures = crate::view::write_view(&setup.scene, &scene_path, &plan, &view_dir)?;
        note!(
            "  pictures: {} (animated glTF) and {} key-pose PNGs",
            pictures
                .first()
                .map_or(String::new(), |p| p.display().to_string()),
            pictures.len().saturating_sub(1)
        );
        written.extend(pictures);
    }
    note!("done in {:.2} s; wrote:", start.elapsed().as_secs_f64());
    let mut text = String::new();
    for path in &written {
        crate::output::outln!(text, "{}", path.display());
    }
    crate::output::print(&text)?;
    Ok(if failed {
        ExitCode::from(1)
    } else {
        ExitCode::SUCCESS
    })
}

/// Writes the built-in scene (robot, scenes, meshes) under `dir`.
fn write_scene(dir: &Path) -> anyhow::Result<()> {
    for (name, text) in FILES {
        let path = dir.join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent)
                .with_context(|| format!("{}: cannot create the folder", parent.display()))?;
        }
        write_atomic(&path, text.as_bytes())?;
    }
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes)
        .with_context(|| format!("{}: cannot create the folder", meshes.display()))?;
    for shipped in objects::shipped_meshes() {
        write_stl_binary(&shipped.builder, &meshes.join(shipped.file_name))?;
    }
    Ok(())
}
