//! `cargo xtask clusters [--objects GLOB] [--random N]`: the audit of the final merge pass
//! (issue 31) on meshes nobody here made and on scanned-like ones.
//!
//! Every object is clustered in both modes (`cluster_surface`, finger and environment
//! parameters), and `audit_adjacent_pairs` counts the adjacent cluster pairs whose union could
//! still be one cluster (Harada et al. §III-A: a slab of thickness `h_max` along *some* plane).
//! The set:
//! - `robosuite/…`: every `*.stl` and `*.obj` of robosuite 1.5.1's
//!   `models/assets/objects/meshes/` (metres, as shipped), from the wheel fetched pinned by
//!   hash into `target/objects` (or `$PICKPLACE_WHEELS/`);
//! - `pybullet/…` and `random/…`: the objects of `cargo xtask stability` (pybullet 3.2.7's
//!   `pybullet_data`, each at its URDF's scale; the first `--random` random objects, 120 by
//!   default);
//! - `generated/…`: the stability set's scanned-like meshes (xtask/src/scanned.rs, seed 31);
//! - `suite/scan-…` and `shipped/…`: the suite's scans and the shipped meshes of `meshes/`.
//!
//! Prints one line per object and mode (triangles, clusters, adjacent pairs, the three counts
//! of the audit, the clustering time in this parallel run) and a sum per family; exits with
//! status 1 when any pair that could be merged is left.

use crate::suite_run::glob_match;
use anyhow::{Context, bail};
use pickplace_geometry::cluster::{ClusterParams, audit_adjacent_pairs, cluster_surface};
use pickplace_geometry::math::{Real, Vector3};
use pickplace_geometry::mesh::{self, MeshOptions, TriMesh};
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use crate::stability::data as stability_data;

/// The robosuite wheel (pure Python, any platform), from PyPI.
const ROBOSUITE_WHEEL: &str = "robosuite-1.5.1-py3-none-any.whl";
/// Its sha256 (as PyPI lists it).
const ROBOSUITE_SHA256: &str = "39810a9e9f193455fcb13a9b4846424abef77481ac3091892c2077c88dcdc153";
/// The folder of object meshes inside the wheel.
const ROBOSUITE_MESHES: &str = "robosuite/models/assets/objects/meshes";
/// Seed of the generated meshes: the stability set's.
const GENERATED_SEED: u64 = 31;

#[derive(Debug)]
struct Args {
    objects: String,
    random: usize,
}

fn parse(args: &[String]) -> anyhow::Result<Args> {
    let mut out = Args {
        objects: "*".into(),
        random: 120,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--objects" => out.objects = it.next().context("--objects needs a glob")?.clone(),
            "--random" => {
                out.random = it
                    .next()
                    .context("--random needs a number")?
                    .parse()
                    .context("--random needs a number")?;
                if out.random > 1000 {
                    bail!("--random: pybullet has 1000 random objects");
                }
            }
            other => bail!("xtask clusters: unknown argument {other:?}"),
        }
    }
    Ok(out)
}

/// One mesh of the set.
#[derive(Debug, Clone)]
struct Object {
    /// `robosuite/milk.stl`, `random/007`, `generated/can-02-mm`.
    name: String,
    path: PathBuf,
    /// Per-axis scale to metres.
    scale: [Real; 3],
}

/// What one object in one mode gave.
#[derive(Debug)]
struct Row {
    name: String,
    mode: &'static str,
    triangles: usize,
    clusters: usize,
    adjacent: usize,
    thin: usize,
    facet: usize,
    mergeable: usize,
    cluster_ms: Real,
}

/// The robosuite wheel in `dir`, checked against [`ROBOSUITE_SHA256`]
/// ([`stability_data::fetch_pinned_wheel`]).
fn fetch_robosuite(dir: &Path) -> anyhow::Result<PathBuf> {
    stability_data::fetch_pinned_wheel(
        "xtask clusters",
        dir,
        ROBOSUITE_WHEEL,
        ROBOSUITE_SHA256,
        "robosuite==1.5.1",
        &[],
    )
}

/// Unzips the object meshes of the wheel into `dir/robosuite` once (a stamp file marks
/// completion); returns the meshes' folder.
fn unpack_robosuite(wheel: &Path, dir: &Path) -> anyhow::Result<PathBuf> {
    let root = dir.join("robosuite");
    let meshes = root.join(ROBOSUITE_MESHES);
    let stamp = dir.join("robosuite.unpacked");
    if std::fs::read_to_string(&stamp).ok().as_deref() == Some(ROBOSUITE_SHA256) && meshes.is_dir()
    {
        return Ok(meshes);
    }
    let status = Command::new("unzip")
        .args(["-q", "-o"])
        .arg(wheel)
        .arg(format!("{ROBOSUITE_MESHES}/*"))
        .arg("-d")
        .arg(&root)
        .status()
        .context("running unzip")?;
    if !status.success() {
        bail!("unzip {} failed ({status})", wheel.display());
    }
    std::fs::write(&stamp, ROBOSUITE_SHA256)?;
    Ok(meshes)
}

/// The `*.stl` and `*.obj` files of `dir`, sorted, as objects named `family/file`.
fn files_in(
    dir: &Path,
    family: &str,
    filter: &dyn Fn(&str) -> bool,
) -> anyhow::Result<Vec<Object>> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))? {
        let path = entry?.path();
        let Some(file) = path.file_name().and_then(|f| f.to_str()).map(str::to_owned) else {
            continue;
        };
        let lower = file.to_lowercase();
        if !(lower.ends_with(".stl") || lower.ends_with(".obj")) || !filter(&file) {
            continue;
        }
        // The suite's scans in millimetres say so in their name.
        let scale = if file.contains("-mm.") { 0.001 } else { 1.0 };
        out.push(Object {
            name: format!("{family}/{file}"),
            path,
            scale: [scale; 3],
        });
    }
    out.sort_by(|a, b| a.name.cmp(&b.name));
    Ok(out)
}

/// Every object of the set (module documentation).
fn objects(root: &Path, args: &Args) -> anyhow::Result<Vec<Object>> {
    let dir = root.join("target/objects");
    let wheel = fetch_robosuite(&dir)?;
    let mut out = files_in(&unpack_robosuite(&wheel, &dir)?, "robosuite", &|_| true)?;
    let pybullet = stability_data::fetch_wheel(&dir)?;
    let data = stability_data::unpack(&pybullet, &dir)?;
    for spec in stability_data::pybullet_objects(&data, args.random)? {
        out.push(Object {
            name: spec.name,
            path: spec.path,
            scale: spec.scale,
        });
    }
    for g in crate::scanned::generate(&dir.join("generated"), GENERATED_SEED)? {
        out.push(Object {
            name: format!("generated/{}", g.name),
            path: g.path,
            scale: [g.scale; 3],
        });
    }
    out.extend(files_in(&root.join("meshes/suite"), "suite", &|f| {
        f.starts_with("scan")
    })?);
    out.extend(files_in(&root.join("meshes"), "shipped", &|_| true)?);
    Ok(out)
}

fn load(object: &Object) -> anyhow::Result<TriMesh> {
    let [sx, sy, sz] = object.scale;
    let mesh = if sx == sy && sy == sz {
        mesh::load(
            &object.path,
            &MeshOptions {
                scale: sx,
                ..MeshOptions::default()
            },
        )?
    } else {
        mesh::load(&object.path, &MeshOptions::default())?
            .scaled(&Vector3::new(sx, sy, sz), &MeshOptions::default())?
    };
    Ok(mesh)
}

fn measure(object: &Object, params: &ClusterParams) -> anyhow::Result<Row> {
    let mesh =
        load(object).with_context(|| format!("{} ({})", object.name, object.path.display()))?;
    let started = Instant::now();
    let clustering = cluster_surface(&mesh, params)?;
    let cluster_ms = started.elapsed().as_secs_f64() * 1e3;
    let audit = audit_adjacent_pairs(&mesh, &clustering);
    Ok(Row {
        name: object.name.clone(),
        mode: params.mode.name(),
        triangles: mesh.triangle_count(),
        clusters: clustering.clusters.len(),
        adjacent: audit.adjacent_pairs,
        thin: audit.thickness_only.len(),
        facet: audit.thickness_and_facet_angle.len(),
        mergeable: audit.mergeable.len(),
        cluster_ms,
    })
}

/// Runs the task (see the module doc).
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse(args)?;
    let started = Instant::now();
    let mut set = objects(root, &args)?;
    set.retain(|o| glob_match(&args.objects, &o.name));
    if set.is_empty() {
        bail!("no object matches {:?}", args.objects);
    }
    eprintln!("xtask clusters: {} objects, both modes", set.len());
    // Largest files first, so that the two cores finish together; rows in the set's order.
    let mut jobs: Vec<(usize, &Object, ClusterParams)> = set
        .iter()
        .enumerate()
        .flat_map(|(i, o)| {
            [
                (2 * i, o, ClusterParams::finger()),
                (2 * i + 1, o, ClusterParams::environment()),
            ]
        })
        .collect();
    let size = |o: &Object| std::fs::metadata(&o.path).map_or(0, |m| m.len());
    jobs.sort_by_key(|(i, o, _)| (std::cmp::Reverse(size(o)), *i));
    let mut done: Vec<(usize, anyhow::Result<Row>)> = jobs
        .par_iter()
        .with_max_len(1)
        .map(|(i, o, p)| (*i, measure(o, p)))
        .collect();
    done.sort_by_key(|(i, _)| *i);
    let rows: Vec<Row> = done
        .into_iter()
        .map(|(_, r)| r)
        .collect::<anyhow::Result<_>>()?;
    println!(
        "{:<34} {:>6} {:>9} {:>8} {:>8} {:>7} {:>7} {:>9} {:>10}",
        "mesh",
        "mode",
        "triangles",
        "clusters",
        "adjacent",
        "thin",
        "facet",
        "mergeable",
        "time ms"
    );
    for r in &rows {
        println!(
            "{:<34} {:>6} {:>9} {:>8} {:>8} {:>7} {:>7} {:>9} {:>10.1}",
            r.name,
            r.mode,
            r.triangles,
            r.clusters,
            r.adjacent,
            r.thin,
            r.facet,
            r.mergeable,
            r.cluster_ms
        );
    }
    // Sums per family and mode.
    let mut sums: BTreeMap<(String, &str), [usize; 6]> = BTreeMap::new();
    for r in &rows {
        let family = r.name.split('/').next().unwrap_or_default().to_owned();
        for key in [(family, r.mode), ("all".to_owned(), r.mode)] {
            let s = sums.entry(key).or_default();
            s[0] += 1;
            s[1] += r.clusters;
            s[2] += r.adjacent;
            s[3] += r.thin;
            s[4] += r.facet;
            s[5] += r.mergeable;
        }
    }
    println!(
        "\n{:<12} {:>6} {:>7} {:>9} {:>9} {:>7} {:>7} {:>9}",
        "family", "mode", "meshes", "clusters", "adjacent", "thin", "facet", "mergeable"
    );
    for ((family, mode), s) in &sums {
        println!(
            "{:<12} {:>6} {:>7} {:>9} {:>9} {:>7} {:>7} {:>9}",
            family, mode, s[0], s[1], s[2], s[3], s[4], s[5]
        );
    }
    println!(
        "\nthin: the union fits in h_max along some plane; facet: and every triangle within \
         max_facet_angle of it; mergeable: and the plane within MAX_FIT_DEVIATION of the \
         union's area-weighted normal (a cluster). {:.1} s",
        started.elapsed().as_secs_f64()
    );
    let left: usize = rows.iter().map(|r| r.mergeable).sum();
    if left > 0 {
        eprintln!("xtask clusters: {left} adjacent pairs could still be merged");
        std::process::exit(1);
    }
    Ok(())
}
