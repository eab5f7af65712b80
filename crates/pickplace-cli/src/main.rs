//! The `pickplace` command. Exit status: 0 success, 1 a well-formed problem with no solution,
//! 2 bad input or usage.

mod grasps;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Debug, Parser)]
#[command(name = "pickplace", version, about = "Pick-and-place planning for dual-arm robots")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Print what loading a mesh did (welding, degenerate triangles, open edges).
    MeshInfo {
        /// Mesh file (.stl, .obj, .ply).
        mesh: std::path::PathBuf,
    },
    /// Plan parallel-gripper grasps of an object (ranked, with rejection counts).
    Grasps(grasps::GraspsArgs),
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { ExitCode::from(2) } else { ExitCode::SUCCESS };
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(2)
        }
    }
}

fn run(cli: Cli) -> anyhow::Result<ExitCode> {
    match cli.command {
        Command::MeshInfo { mesh } => {
            let m = pickplace_geometry::mesh::load(&mesh, &Default::default())?;
            println!("{}", serde_json::to_string_pretty(m.report())?);
            Ok(ExitCode::SUCCESS)
        }
        Command::Grasps(args) => grasps::run(&args),
    }
}
