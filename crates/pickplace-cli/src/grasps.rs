//! `pickplace grasps OBJECT_MESH --robot DIR_OR_CONFIG [--json]`: parallel-gripper grasps of an
//! object (Harada et al. §III-B.1), ranked, with the candidates rejected per reason.

use crate::output::note;
use anyhow::Context as _;
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_grasp::json::GraspsJson;
use pickplace_grasp::{GraspOptions, GraspPlanner, GripperParams};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Arguments of `pickplace grasps`.
#[derive(Debug, clap::Args)]
pub struct GraspsArgs {
    /// Object mesh (.stl, .obj, .ply), in metres unless --scale is given.
    pub mesh: PathBuf,
    /// Scale applied to the mesh on loading (0.001 for a file in millimetres).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true, value_parser = crate::args::number::mesh_scale)]
    pub scale: f64,
    /// The robot directory (its `gripper.toml` is read) or a gripper configuration file.
    #[arg(long, value_name = "DIR_OR_CONFIG")]
    pub robot: PathBuf,
    /// Print the machine-readable document (format `pickplace.grasps/1`) on stdout.
    #[arg(long)]
    pub json: bool,
    /// Finger-contact cluster thickness h_max (m).
    #[arg(long, value_name = "M", default_value_t = ClusterParams::finger().h_max, allow_negative_numbers = true, value_parser = crate::args::number::h_max)]
    pub h_max: f64,
    /// Spacing of the grid of grasp centres (m).
    #[arg(long, value_name = "M", default_value_t = GraspOptions::default().grid_step, allow_negative_numbers = true, value_parser = crate::args::number::grid_step)]
    pub grid_step: f64,
    /// Number of approach directions about each grasp axis.
    #[arg(long, value_name = "N", default_value_t = GraspOptions::default().approach_count, value_parser = crate::args::number::approaches)]
    pub approaches: usize,
    /// Clearance kept between the gripper and the object (m).
    #[arg(long, value_name = "M", default_value_t = GraspOptions::default().clearance, allow_negative_numbers = true, value_parser = crate::args::number::clearance)]
    pub clearance: f64,
}

/// The gripper configuration named by `--robot`: the file itself, or `DIR/gripper.toml`.
fn gripper_path(robot: &Path) -> PathBuf {
    if robot.is_dir() {
        robot.join("gripper.toml")
    } else {
        robot.to_path_buf()
    }
}

/// Runs the command. Bad input is an `Err` (exit 2); no grasp at all is exit 1.
pub fn run(args: &GraspsArgs) -> anyhow::Result<ExitCode> {
    let gripper_file = gripper_path(&args.robot);
    let gripper = GripperParams::load(&gripper_file)?;
    if !(args.scale.is_finite() && args.scale > 0.0) {
        anyhow::bail!("--scale {}: must be a positive number", args.scale);
    }
    let mesh = pickplace_geometry::mesh::load(
        &args.mesh,
        &pickplace_geometry::mesh::MeshOptions {
            scale: args.scale,
            ..Default::default()
        },
    )?;
    for w in pickplace::mesh_warning::check(&mesh, "object", &args.mesh, Some("--scale")) {
        note!("warning: {w}");
    }
    let params = ClusterParams {
        h_max: args.h_max,
        ..ClusterParams::finger()
    };
    let clustering = cluster_surface(&mesh, &params).context("--h-max")?;
    let options = GraspOptions {
        grid_step: args.grid_step,
        approach_count: args.approaches,
        clearance: args.clearance,
        ..GraspOptions::default()
    };
    let planner = GraspPlanner::new(&mesh).with_context(|| format!("{}", args.mesh.display()))?;
    let set = planner.plan(&clustering, &gripper, &options)?;
    let mut text = String::new();
    if args.json {
        let doc = GraspsJson::new(
            &args.mesh.display().to_string(),
            &gripper_file.display().to_string(),
            params.h_max,
            &planner.center_of_mass(),
            &set,
        );
        writeln!(text, "{}", serde_json::to_string_pretty(&doc)?)?;
    } else {
        writeln!(
            text,
            "{}: {} cluster pairs, {} candidates, {} grasps",
            args.mesh.display(),
            set.pairs,
            set.candidates,
            set.grasps.len()
        )?;
        let r = set.rejected;
        writeln!(
            text,
            "rejected: {} pairs too wide or narrow; candidates: {} width, {} pad tilt, {} contact, {} finger collision, {} palm collision",
            r.pair_width, r.width, r.pad_tilt, r.contact, r.finger_collision, r.palm_collision
        )?;
        for (rank, g) in set.grasps.iter().take(10).enumerate() {
            let t = g.object_from_tcp.translation.vector;
            writeln!(
                text,
                "#{rank}: score {:.3}  width {:.4} m  tcp ({:.4}, {:.4}, {:.4})  clusters {}/{}",
                g.score, g.width, t.x, t.y, t.z, g.positive_cluster, g.negative_cluster
            )?;
        }
    }
    crate::output::print(&text)?;
    if set.grasps.is_empty() {
        note!("no grasp: every candidate was rejected (see the counts above)");
        return Ok(ExitCode::from(1));
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(mesh: &str, robot: &str) -> GraspsArgs {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        GraspsArgs {
            mesh: root.join(mesh),
            scale: 1.0,
            robot: root.join(robot),
            // The text summary (a dozen lines): the JSON of every grasp filled the test log.
            json: false,
            h_max: 0.005,
            grid_step: 0.01,
            approaches: 8,
            clearance: 0.002,
        }
    }

    #[test]
    fn robot_dir_means_its_gripper_toml_and_bad_input_names_the_file() {
        let ok =
            run(&args("meshes/can.stl", "crates/pickplace-grasp/tests/data")).expect("valid input");
        assert_eq!(ok, ExitCode::SUCCESS);
        let e = run(&args("meshes/can.stl", "meshes")).expect_err("no gripper.toml in meshes/");
        assert!(format!("{e:#}").contains("meshes/gripper.toml"), "{e:#}");
        let e = run(&args(
            "meshes/none.stl",
            "crates/pickplace-grasp/tests/data",
        ))
        .expect_err("no mesh");
        assert!(format!("{e:#}").contains("none.stl"), "{e:#}");
    }
}
