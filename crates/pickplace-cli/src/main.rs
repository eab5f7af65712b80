//! The `pickplace` command. Exit status: 0 success, 1 a well-formed problem with no solution,
//! 2 bad input or usage.

mod clusters;

use clap::{Parser, Subcommand};
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
    /// Print what loading a mesh did (welding, degenerate triangles, open edges).
    MeshInfo {
        /// Mesh file (.stl, .obj, .ply).
        mesh: std::path::PathBuf,
    },
    /// Cluster a mesh's surface into planar contact regions (paper §III-A, Algorithm 1).
    Clusters(clusters::ClustersArgs),
    /// Build the cluster databases of meshes (both contact modes unless --mode is given).
    Precompute(clusters::PrecomputeArgs),
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
            eprintln!("error: {}", error_message(&e));
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
        Command::Clusters(args) => clusters::run_clusters(args),
        Command::Precompute(args) => clusters::run_precompute(args),
    }
}

/// The error and its causes on one line, leaving out a cause whose text the message before it
/// already contains (library errors often print their source themselves).
fn error_message(e: &anyhow::Error) -> String {
    let mut out = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !out.contains(&text) {
            out.push_str(": ");
            out.push_str(&text);
        }
    }
    out
}
