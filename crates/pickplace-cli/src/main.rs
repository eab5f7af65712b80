//! The `pickplace` command. Exit status: 0 success, 1 a well-formed problem with no solution
//! (no plan, or an infeasible scene such as a start state in collision), 2 bad input or usage.
//! `pickplace batch` gives the worst of its scenes' statuses (`batch.rs`).
//! Everything printed on standard output goes through [`output`]: a closed standard output
//! (`pickplace plan … | head`) ends the printing quietly, never with a panic.

mod args;
mod batch;
mod clusters;
mod demo;
mod export;
mod grasps;
mod motion;
mod output;
mod placements;
mod plan;
mod progress;
mod robot;
mod view;

use clap::{Parser, Subcommand};
use output::note;
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(
    name = "pickplace",
    version,
    about = "Pick-and-place planning for dual-arm robots"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// The main job on the built-in scene (the paper's Fig. 9): clusters, placements, grasps.
    Demo(demo::DemoArgs),
    /// Print what loading a mesh did (welding, degenerate triangles, open edges).
    MeshInfo {
        /// Mesh file (.stl, .obj, .ply).
        mesh: std::path::PathBuf,
    },
    /// Cluster a mesh's surface into planar contact regions (paper §III-A, Algorithm 1).
    Clusters(clusters::ClustersArgs),
    /// Build the cluster databases of meshes (both contact modes unless --mode is given).
    Precompute(clusters::PrecomputeArgs),
    /// Stable placements of an object on an environment (Algorithm 2), best first; without
    /// `--on`, its resting poses on a horizontal plane.
    Placements(placements::PlacementsArgs),
    /// Robot model: check a URDF/SRDF, forward and inverse kinematics.
    Robot {
        #[command(subcommand)]
        command: robot::RobotCommand,
    },
    /// Plan parallel-gripper grasps of an object (ranked, with rejection counts).
    Grasps(grasps::GraspsArgs),
    /// Plan a pick-and-place motion for a scene (paper Fig. 8): strategy, grasps, placement,
    /// key poses and a timed trajectory.
    Plan(plan::PlanArgs),
    /// A collision-free, timed motion of one planning group between two joint states among
    /// the scene's obstacles (docs/motion.md).
    Motion(motion::MotionArgs),
    /// Plan many scenes in parallel into one folder: a plan file per scene and a JSON-lines
    /// summary, resumable (docs/batch.md).
    Batch(batch::BatchArgs),
    /// Re-check a plan independently: dense interpolation, limits, collisions, stability.
    Validate(plan::ValidateArgs),
    /// Pictures of a plan: an animated glTF (plan.glb) and PNGs of the key poses.
    View(view::ViewArgs),
    /// A plan as ROS 2 messages: JointTrajectory per motion and arm (YAML or JSON), or a
    /// MoveIt DisplayTrajectory (docs/ros2.md).
    Export(export::ExportArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            note!("error: {}", message(&e));
            exit_code(&e)
        }
    }
}

/// 1 for an infeasible scene (a start state in collision: well-formed, no solution), 2 for
/// every other error (bad input or usage).
fn exit_code(e: &anyhow::Error) -> ExitCode {
    let infeasible = e.chain().any(|cause| {
        cause
            .downcast_ref::<pickplace::Error>()
            .is_some_and(pickplace::Error::is_infeasible)
    });
    ExitCode::from(if infeasible { 1 } else { 2 })
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::Demo(args) => demo::run(&args),
        Command::MeshInfo { mesh } => {
            let m = pickplace_geometry::mesh::load(&mesh, &Default::default())?;
            output::print_json(m.report())?;
            Ok(ExitCode::SUCCESS)
        }
        Command::Clusters(args) => clusters::run_clusters(args),
        Command::Precompute(args) => clusters::run_precompute(args),
        Command::Placements(args) => placements::run(&args),
        Command::Robot { command } => robot::run(command),
        Command::Grasps(args) => grasps::run(&args),
        Command::Plan(args) => plan::run(&args),
        Command::Motion(args) => motion::run(&args),
        Command::Batch(args) => batch::run(&args),
        Command::Validate(args) => plan::run_validate(&args),
        Command::View(args) => view::run(&args),
        Command::Export(args) => export::run(&args),
    }
}

/// The error and its causes on one line, each cause once ([`pickplace::error::message`]).
fn message(e: &anyhow::Error) -> String {
    pickplace::error::message(e.as_ref())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_start_state_in_collision_exits_1_and_bad_input_2() {
        let start = anyhow::Error::new(pickplace::Error::StartInCollision {
            first: "RARM_JOINT5_Link".into(),
            second: "table".into(),
            distance: -0.0032,
        });
        assert_eq!(exit_code(&start), ExitCode::from(1));
        assert_eq!(
            message(&start),
            "start state in collision: RARM_JOINT5_Link and table (penetration 3.2 mm)"
        );
        let bad = anyhow::anyhow!("bad input");
        assert_eq!(exit_code(&bad), ExitCode::from(2));
    }
}
