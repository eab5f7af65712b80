//! `pickplace clusters` and `pickplace precompute`: surface clustering (Harada et al., §III-A,
//! Algorithm 1) from the command line.
//!
//! Bad input (an unreadable or malformed mesh, invalid parameters, a database built for another
//! mesh, format version or parameters) is an error naming the file; `main` turns it into exit
//! status 2. Output files are written atomically (temporary file, then rename), and
//! `precompute` reads and checks every mesh before it writes any database, so a failed run
//! leaves no partial file behind.

use crate::output::note;
use anyhow::{Context, Result};
use pickplace::precompute::{self, DatabaseReport, Job, PrecomputeOptions, Rebuild};
use pickplace_geometry::cluster::{ClusterParams, Clustering, ContactMode};
use pickplace_geometry::db::{CacheStatus, ClusterDatabase};
use pickplace_geometry::hash::mesh_hash;
use pickplace_geometry::mesh::{self, MeshOptions, TriMesh};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Contact mode on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ModeArg {
    /// Object-environment contact (h_max 0.001 m by default).
    Env,
    /// Finger-object contact with parallel pairs (h_max 0.005 m by default).
    Finger,
}

impl ModeArg {
    /// The paper's parameters for this mode, with `h_max` replaced when given.
    fn params(self, h_max: Option<f64>) -> Result<ClusterParams> {
        let mut p = match self {
            ModeArg::Env => ClusterParams::environment(),
            ModeArg::Finger => ClusterParams::finger(),
        };
        if let Some(h) = h_max {
            p.h_max = h;
        }
        p.validate().context("--h-max")?;
        Ok(p)
    }
}

/// Arguments of `pickplace clusters`.
#[derive(Debug, clap::Args)]
pub struct ClustersArgs {
    /// Mesh file (.stl, .obj, .ply), in metres unless --scale is given.
    pub mesh: PathBuf,
    /// Contact mode.
    #[arg(long, value_enum, default_value = "env")]
    pub mode: ModeArg,
    /// Maximum cluster thickness h_max in metres (default: 0.001 env, 0.005 finger).
    #[arg(long, value_name = "M", allow_negative_numbers = true, value_parser = crate::args::number::h_max)]
    pub h_max: Option<f64>,
    /// Factor applied to the mesh's coordinates, for files not in metres.
    #[arg(
        long,
        value_name = "S",
        default_value_t = 1.0,
        allow_negative_numbers = true,
        value_parser = crate::args::number::mesh_scale
    )]
    pub scale: f64,
    /// Print the clusters as JSON on stdout (format `pickplace.clusters/1`).
    #[arg(long)]
    pub json: bool,
    /// Also write the clusters as a PLY mesh with one colour per cluster.
    #[arg(long, value_name = "FILE")]
    pub ply: Option<PathBuf>,
    /// Also draw the clusters as a PNG picture (each cluster in its own colour, the two
    /// clusters of a finger pair in one hue; the paper's Figs. 3-5).
    #[arg(long, value_name = "FILE")]
    pub png: Option<PathBuf>,
    /// Size of the --png picture, WIDTHxHEIGHT in pixels.
    #[arg(long, value_name = "WxH", default_value = "800x600", requires = "png")]
    pub size: String,
    /// Read the clusters from this database (written by `pickplace precompute`) instead of
    /// computing them; it must have been built for MESH with the same mode and h_max.
    #[arg(long, value_name = "FILE")]
    pub db: Option<PathBuf>,
}

/// Arguments of `pickplace precompute`.
#[derive(Debug, clap::Args)]
pub struct PrecomputeArgs {
    /// Mesh files (.stl, .obj, .ply), in metres.
    #[arg(required = true, value_name = "MESH")]
    pub meshes: Vec<PathBuf>,
    /// Build only this mode's databases (default: both).
    #[arg(long, value_enum)]
    pub mode: Option<ModeArg>,
    /// h_max in metres for the chosen --mode (default: the paper's value for that mode).
    #[arg(
        long,
        value_name = "M",
        requires = "mode",
        allow_negative_numbers = true,
        value_parser = crate::args::number::h_max
    )]
    pub h_max: Option<f64>,
    /// Folder for the databases (default: $PICKPLACE_CACHE, else $XDG_CACHE_HOME/pickplace,
    /// else ~/.cache/pickplace: where `plan` looks for them).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Rebuild even when a valid database exists.
    #[arg(long)]
    pub force: bool,
}

fn load_mesh(path: &Path, scale: f64) -> Result<TriMesh> {
    Ok(mesh::load(
        path,
        &MeshOptions {
            scale,
            ..MeshOptions::default()
        },
    )?)
}

/// `" 4 pairs"`-style suffix in finger mode.
fn pairs_note(c: &Clustering) -> String {
    if c.params.mode == ContactMode::Finger {
        format!(", {} parallel pairs", c.pairs.len())
    } else {
        String::new()
    }
}

/// `pickplace clusters`.
pub fn run_clusters(args: ClustersArgs) -> Result<ExitCode> {
    let params = args.mode.params(args.h_max)?;
    let size = crate::view::parse_size(&args.size)?;
    // Before any work: no output may replace a link, a device or an input.
    let mut inputs: Vec<crate::args::Input<'_>> = vec![("the mesh", &args.mesh)];
    inputs.extend(args.db.as_deref().map(|db| ("the database", db)));
    for (option, path) in [("--ply", &args.ply), ("--png", &args.png)] {
        if let Some(path) = path {
            crate::args::check_output_file(path, option, &inputs)?;
        }
    }
    let mesh = load_mesh(&args.mesh, args.scale)?;
    let db = match &args.db {
        Some(db_path) => ClusterDatabase::load(db_path, mesh_hash(&mesh), &params)?,
        None => ClusterDatabase::build(&mesh, &params)?,
    };
    let c = &db.clustering;
    if let Some(ply) = &args.ply {
        pickplace_geometry::export::write_clusters_ply(ply, &mesh, c)?;
        note!("wrote {} ({} clusters)", ply.display(), c.clusters.len());
    }
    if let Some(png) = &args.png {
        let options = pickplace_view::PictureOptions {
            render: crate::view::render_options(size),
            ..Default::default()
        };
        pickplace_view::render_clusters(&mesh, c, &options)?.write_png(png)?;
        note!("wrote {} ({} clusters)", png.display(), c.clusters.len());
    }
    if args.json {
        let json = db.to_json(&mesh, &args.mesh.to_string_lossy());
        crate::output::print_json(&json)?;
    } else {
        let mut out = String::new();
        writeln!(
            out,
            "{}: {} triangles, {} {} clusters (h_max {} m){}",
            args.mesh.display(),
            mesh.report().input_triangles,
            c.clusters.len(),
            params.mode.name(),
            params.h_max,
            pairs_note(c),
        )?;
        for cl in &c.clusters {
            let n = cl.normal;
            writeln!(
                out,
                "  cluster {:>4}: {:>6} triangles, area {:.6} m², h {:.6} m, normal ({:+.3}, {:+.3}, {:+.3}), {} holes",
                cl.id,
                cl.triangles.len(),
                cl.area,
                cl.h,
                n.x,
                n.y,
                n.z,
                cl.region.holes.len()
            )?;
        }
        for p in &c.pairs {
            writeln!(
                out,
                "  pair {:>4} / {:<4}: width {:.4} m, overlap {:.6} m²",
                p.first, p.second, p.width, p.overlap_area
            )?;
        }
        crate::output::print(&out)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// Prints each database's line above the progress bar.
struct PrecomputeBar(indicatif::ProgressBar);

impl precompute::Progress for PrecomputeBar {
    fn started(&self, job: &Job<'_>) {
        self.0.set_message(format!(
            "{} ({})",
            job.mesh_path.display(),
            job.params.mode.name()
        ));
    }

    fn finished(&self, _job: &Job<'_>, outcome: &pickplace_geometry::Result<DatabaseReport>) {
        if let Ok(report) = outcome {
            let what = match &report.status {
                CacheStatus::Loaded => "loaded from cache".to_owned(),
                CacheStatus::Built { reason: Some(r) } => format!("rebuilt ({r})"),
                _ => "built".to_owned(),
            };
            let clustering = &report.database.clustering;
            let line = format!(
                "{}: {} {} clusters{}: {what} {} ({:.2} ms)",
                report.mesh_path.display(),
                clustering.clusters.len(),
                report.params.mode.name(),
                pairs_note(clustering),
                report.db_path.display(),
                report.elapsed.as_secs_f64() * 1e3
            );
            self.0.suspend(|| note!("{line}"));
            self.0.inc(1);
        }
    }
}

/// `pickplace precompute`.
pub fn run_precompute(args: PrecomputeArgs) -> Result<ExitCode> {
    let modes: Vec<ModeArg> = match args.mode {
        Some(m) => vec![m],
        None => vec![ModeArg::Env, ModeArg::Finger],
    };
    let params: Vec<ClusterParams> = modes
        .iter()
        .map(|m| m.params(args.h_max))
        .collect::<Result<_>>()?;
    let out = match args.out.clone() {
        Some(out) => out,
        // Writing the cache is this command's whole job: no folder is an error.
        None => pickplace::cache::default_dir().map_err(|_| {
            anyhow::anyhow!(
                "no cache folder: none of PICKPLACE_CACHE, XDG_CACHE_HOME and HOME is set; give the folder with --out"
            )
        })?,
    };
    let inputs: Vec<crate::args::Input<'_>> = args
        .meshes
        .iter()
        .map(|m| ("a mesh", m.as_path()))
        .collect();
    crate::args::check_output_dir(&out, "--out", &inputs)?;
    // Every mesh is read and checked before any database is written.
    let meshes: Vec<TriMesh> = args
        .meshes
        .iter()
        .map(|p| load_mesh(p, 1.0))
        .collect::<Result<_>>()?;
    std::fs::create_dir_all(&out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;

    let jobs: Vec<Job<'_>> = args
        .meshes
        .iter()
        .zip(&meshes)
        .flat_map(|(path, mesh)| Job::each_mode(path, mesh, &params))
        .collect();
    let bar = indicatif::ProgressBar::new(jobs.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template("precompute {bar:30} {pos}/{len} {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let options = PrecomputeOptions {
        rebuild: if args.force {
            Rebuild::Always
        } else {
            Rebuild::WhenInvalid
        },
    };
    let bar = PrecomputeBar(bar);
    precompute::precompute(&jobs, &out, &options, &bar)?;
    bar.0.finish_and_clear();
    Ok(ExitCode::SUCCESS)
}
