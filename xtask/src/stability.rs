//! `cargo xtask stability [--objects GLOB] [--drops N] [--random N] [--write-doc]`: an
//! independent measurement of `pickplace_placement::resting_poses` (issue 31) on some 150
//! objects: pybullet's own objects (its 1000 random blobs, the first `--random` of them, the
//! duck, teddy, lego, jenga, …) and generated scanned-like meshes.
//!
//! For every object: every offered pose that is not a rolling class is dropped in rapier
//! (`pickplace_placement::simulate::drop_test`, must hold within 5 mm and 3°); pybullet drops
//! the object `--drops` times from random orientations and trimesh computes its quasi-static
//! stable poses (xtask/scripts/stable_poses.py, in a venv of pinned versions); recall is the
//! share of their frequent poses (≥ 5 %) that we offer. Writes target/objects/report.json,
//! with `--write-doc` docs/stability.md; exit status 1 when a goal is missed.

pub(crate) mod data;

use crate::suite_run::glob_match;
use anyhow::{Context, bail};
use data::ObjectSpec;
use pickplace_geometry::math::{Point3, Real, Vector3};
use pickplace_geometry::mesh::{self, MassMethod, MassProperties, MeshOptions, TriMesh};
use pickplace_placement::simulate::{Obstacle, drop_test};
use pickplace_placement::{RestingOptions, resting_poses};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// Seed of the generated meshes and of pybullet's drop orientations.
const SEED: u64 = 31;
/// An offered pose matches a measured one when the directions are within this angle (deg).
const MATCH_DEG: Real = 10.0;
/// Measured poses at least this frequent (pybullet) or probable (trimesh) must be offered.
const FREQUENT: Real = 0.05;
/// Goal: share of the offered (non-rolling) poses that hold in rapier.
const HOLD_GOAL: Real = 0.99;
/// Goal: recall against pybullet's frequent poses.
const RECALL_GOAL: Real = 0.95;
/// Objects with more triangles are dropped in rapier as their convex hull (a closed trimesh
/// of the hull's triangles): only hull points touch a plane, and the hull is much smaller.
const HULL_COLLIDER_ABOVE: usize = 20_000;

#[derive(Debug)]
struct Args {
    objects: String,
    drops: usize,
    random: usize,
    write_doc: bool,
}

fn parse(args: &[String]) -> anyhow::Result<Args> {
    let mut out = Args {
        objects: "*".into(),
        drops: 50,
        random: 120,
        write_doc: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--objects" => out.objects = it.next().context("--objects needs a glob")?.clone(),
            "--drops" => {
                out.drops = it
                    .next()
                    .context("--drops needs a number")?
                    .parse()
                    .context("--drops needs a number")?;
            }
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
            "--write-doc" => out.write_doc = true,
            other => bail!("xtask stability: unknown argument {other:?}"),
        }
    }
    if out.drops == 0 {
        bail!("--drops must be at least 1");
    }
    Ok(out)
}

/// An object loaded, with its CoG and hull.
struct Loaded {
    spec: ObjectSpec,
    mesh: TriMesh,
    hull: TriMesh,
    cog: Point3,
    /// "volume" (closed mesh) or "hull" (the solid hull's CoG, for open meshes).
    cog_from: &'static str,
}

fn convex_hull(mesh: &TriMesh) -> anyhow::Result<TriMesh> {
    let points: Vec<_> = mesh
        .vertices()
        .iter()
        .map(pickplace_geometry::parry::point)
        .collect();
    let (hull_points, triangles) = parry3d_f64::transformation::try_convex_hull(&points)
        .map_err(|e| anyhow::anyhow!("convex hull: {e:?}"))?;
    let hull_points: Vec<Point3> = hull_points
        .into_iter()
        .map(pickplace_geometry::parry::to_point)
        .collect();
    Ok(TriMesh::from_soup(
        &hull_points,
        &triangles,
        &MeshOptions::default(),
    )?)
}

fn load(spec: &ObjectSpec) -> anyhow::Result<Loaded> {
    let [sx, sy, sz] = spec.scale;
    let mesh = if sx == sy && sy == sz {
        mesh::load(
            &spec.path,
            &MeshOptions {
                scale: sx,
                ..MeshOptions::default()
            },
        )?
    } else {
        mesh::load(&spec.path, &MeshOptions::default())?
            .scaled(&Vector3::new(sx, sy, sz), &MeshOptions::default())?
    };
    let hull = convex_hull(&mesh)?;
    let mass = MassProperties::of(&mesh);
    let (cog, cog_from) = if mass.method == MassMethod::Volume {
        (mass.center_of_mass, "volume")
    } else {
        (MassProperties::of(&hull).center_of_mass, "hull")
    };
    Ok(Loaded {
        spec: spec.clone(),
        mesh,
        hull,
        cog,
        cog_from,
    })
}

/// The job of stable_poses.py for one object.
#[derive(Serialize)]
struct JobObject<'a> {
    name: &'a str,
    vertices: Vec<[Real; 3]>,
    faces: &'a [[u32; 3]],
    cog: [Real; 3],
}

#[derive(Serialize)]
struct Job<'a> {
    drops: usize,
    seed: u64,
    workers: usize,
    objects: Vec<JobObject<'a>>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
struct DropPose {
    down: [Real; 3],
    count: usize,
    frequency: Real,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
struct Drops {
    poses: Vec<DropPose>,
    unsettled: usize,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
struct TrimeshPose {
    down: [Real; 3],
    probability: Real,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
struct TrimeshPoses {
    poses: Vec<TrimeshPose>,
}

#[derive(Debug, Clone, Deserialize)]
struct Measured {
    name: String,
    drops: Drops,
    trimesh: TrimeshPoses,
}

#[derive(Debug, Deserialize)]
struct MeasuredAll {
    trimesh: String,
    objects: Vec<Measured>,
}

/// One offered pose and what the drop test made of it.
#[derive(Debug, Clone, Serialize)]
struct OfferedPose {
    support_normal: [Real; 3],
    stability_margin: Real,
    tipping_angle_deg: Real,
    rolling_axis: Option<[Real; 3]>,
    /// `None` for rolling classes (not dropped).
    held: Option<bool>,
    drift_mm: Option<Real>,
    drift_deg: Option<Real>,
}

/// A measured pose and whether we offer it.
#[derive(Debug, Clone, Serialize)]
struct Target {
    down: [Real; 3],
    /// Frequency (pybullet) or probability (trimesh).
    share: Real,
    offered: bool,
}

#[derive(Debug, Clone, Serialize)]
struct ObjectResult {
    name: String,
    file: String,
    triangles: usize,
    hull_triangles: usize,
    cog_from: &'static str,
    collider: &'static str,
    error: Option<String>,
    offered: Vec<OfferedPose>,
    tested: usize,
    held: usize,
    pybullet: Vec<Target>,
    pybullet_unsettled: usize,
    trimesh: Vec<Target>,
    seconds: Real,
}

impl ObjectResult {
    fn recall(targets: &[Target]) -> (usize, usize) {
        (targets.iter().filter(|t| t.offered).count(), targets.len())
    }
    /// Offered poses that fell in rapier (an error counts as one).
    fn fallen(&self) -> usize {
        self.tested - self.held + usize::from(self.error.is_some())
    }
    /// Frequent poses not offered: pybullet's, trimesh's.
    fn missed(&self) -> (usize, usize) {
        let (pm, pn) = Self::recall(&self.pybullet);
        let (tm, tn) = Self::recall(&self.trimesh);
        (pn - pm, tn - tm)
    }
}

fn arr(v: &Vector3) -> [Real; 3] {
    [v.x, v.y, v.z]
}

/// Whether `offered` covers the measured down direction `down` (object frame).
fn covers(offered: &OfferedPose, down: &Vector3) -> bool {
    let down = down.normalize();
    match offered.rolling_axis {
        Some(axis) => {
            let axis = Vector3::from(axis).normalize();
            axis.dot(&down).abs() <= MATCH_DEG.to_radians().sin()
        }
        None => {
            let n = Vector3::from(offered.support_normal).normalize();
            n.dot(&down).clamp(-1.0, 1.0).acos() <= MATCH_DEG.to_radians()
        }
    }
}

fn measure(object: &Loaded, measured: Option<&Measured>) -> ObjectResult {
    let start = Instant::now();
    let collider_is_hull = object.mesh.triangle_count() > HULL_COLLIDER_ABOVE;
    let mut result = ObjectResult {
        name: object.spec.name.clone(),
        file: object.spec.path.display().to_string(),
        triangles: object.mesh.triangle_count(),
        hull_triangles: object.hull.triangle_count(),
        cog_from: object.cog_from,
        collider: if collider_is_hull { "hull" } else { "mesh" },
        error: None,
        offered: Vec::new(),
        tested: 0,
        held: 0,
        pybullet: Vec::new(),
        pybullet_unsettled: 0,
        trimesh: Vec::new(),
        seconds: 0.0,
    };
    match resting_poses(&object.mesh, &object.cog, &RestingOptions::default()) {
        Ok(poses) => {
            // A large flat floor whose top is z = 0.
            let floor = [Obstacle::Cuboid([0.0, 0.0, -0.05], [2.0, 2.0, 0.05])];
            let collider = if collider_is_hull {
                &object.hull
            } else {
                &object.mesh
            };
            for pose in &poses {
                let mut offered = OfferedPose {
                    support_normal: arr(&pose.support_normal),
                    stability_margin: pose.stability_margin,
                    tipping_angle_deg: pose.tipping_angle.to_degrees(),
                    rolling_axis: pose.rolling_axis.as_ref().map(arr),
                    held: None,
                    drift_mm: None,
                    drift_deg: None,
                };
                if pose.rolling_axis.is_none() {
                    let drift = drop_test(collider, &object.cog, &pose.world_from_object, &floor);
                    offered.held = Some(drift.settled());
                    offered.drift_mm = Some(drift.distance * 1000.0);
                    offered.drift_deg = Some(drift.angle.to_degrees());
                    result.tested += 1;
                    result.held += usize::from(drift.settled());
                }
                result.offered.push(offered);
            }
        }
        Err(e) => result.error = Some(e.to_string()),
    }
    if let Some(m) = measured {
        let target = |down: [Real; 3], share: Real| Target {
            down,
            share,
            offered: result
                .offered
                .iter()
                .any(|o| covers(o, &Vector3::from(down))),
        };
        result.pybullet = m
            .drops
            .poses
            .iter()
            .filter(|p| p.frequency >= FREQUENT)
            .map(|p| target(p.down, p.frequency))
            .collect();
        result.pybullet_unsettled = m.drops.unsettled;
        result.trimesh = m
            .trimesh
            .poses
            .iter()
            .filter(|p| p.probability >= FREQUENT)
            .map(|p| target(p.down, p.probability))
            .collect();
    }
    result.seconds = start.elapsed().as_secs_f64();
    result
}

/// Figures over all objects.
#[derive(Debug, Clone, Serialize)]
struct Summary {
    objects: usize,
    objects_pybullet: usize,
    objects_generated: usize,
    errors: usize,
    offered: usize,
    rolling: usize,
    tested: usize,
    held: usize,
    hold_rate: Real,
    pybullet_frequent: usize,
    pybullet_matched: usize,
    recall_pybullet: Real,
    trimesh_frequent: usize,
    trimesh_matched: usize,
    recall_trimesh: Real,
    drops_per_object: usize,
    pybullet_unsettled_drops: usize,
    trimesh_version: String,
    seconds: Real,
    goals_met: bool,
}

fn ratio(a: usize, b: usize) -> Real {
    if b == 0 { 1.0 } else { a as Real / b as Real }
}

fn summarize(results: &[ObjectResult], drops: usize, trimesh: &str, seconds: Real) -> Summary {
    let sum = |f: &dyn Fn(&ObjectResult) -> usize| results.iter().map(f).sum::<usize>();
    let tested = sum(&|r| r.tested);
    let held = sum(&|r| r.held);
    let pybullet_frequent = sum(&|r| r.pybullet.len());
    let pybullet_matched = sum(&|r| ObjectResult::recall(&r.pybullet).0);
    let trimesh_frequent = sum(&|r| r.trimesh.len());
    let trimesh_matched = sum(&|r| ObjectResult::recall(&r.trimesh).0);
    let hold_rate = ratio(held, tested);
    let recall_pybullet = ratio(pybullet_matched, pybullet_frequent);
    Summary {
        objects: results.len(),
        objects_pybullet: results
            .iter()
            .filter(|r| !r.name.starts_with("generated/"))
            .count(),
        objects_generated: results
            .iter()
            .filter(|r| r.name.starts_with("generated/"))
            .count(),
        errors: results.iter().filter(|r| r.error.is_some()).count(),
        offered: sum(&|r| r.offered.len()),
        rolling: sum(&|r| {
            r.offered
                .iter()
                .filter(|o| o.rolling_axis.is_some())
                .count()
        }),
        tested,
        held,
        hold_rate,
        pybullet_frequent,
        pybullet_matched,
        recall_pybullet,
        trimesh_frequent,
        trimesh_matched,
        recall_trimesh: ratio(trimesh_matched, trimesh_frequent),
        drops_per_object: drops,
        pybullet_unsettled_drops: sum(&|r| r.pybullet_unsettled),
        trimesh_version: trimesh.to_owned(),
        seconds,
        goals_met: hold_rate >= HOLD_GOAL
            && recall_pybullet >= RECALL_GOAL
            && results.iter().all(|r| r.error.is_none()),
    }
}

fn fmt_dir(d: &[Real; 3]) -> String {
    format!("({:+.2}, {:+.2}, {:+.2})", d[0], d[1], d[2])
}

/// A line per bad thing of one object, for the worst-objects list.
fn describe(r: &ObjectResult) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(e) = &r.error {
        out.push(format!("error: {e}"));
    }
    for o in r.offered.iter().filter(|o| o.held == Some(false)) {
        out.push(format!(
            "offered {} (margin {:.1} mm, tipping {:.1}°) fell: drift {:.1} mm, {:.1}°",
            fmt_dir(&o.support_normal),
            o.stability_margin * 1000.0,
            o.tipping_angle_deg,
            o.drift_mm.unwrap_or(0.0),
            o.drift_deg.unwrap_or(0.0)
        ));
    }
    for t in r.pybullet.iter().filter(|t| !t.offered) {
        out.push(format!(
            "pybullet settles {} in {:.0} % of drops: not offered",
            fmt_dir(&t.down),
            t.share * 100.0
        ));
    }
    for t in r.trimesh.iter().filter(|t| !t.offered) {
        out.push(format!(
            "trimesh pose {} (p = {:.2}): not offered",
            fmt_dir(&t.down),
            t.share
        ));
    }
    out
}

/// The worst objects: those with most offered poses that fell (then most missed), and
/// those with most frequent poses missed (pybullet's, then trimesh's), `n` of each.
fn worst(results: &[ObjectResult], n: usize) -> (Vec<&ObjectResult>, Vec<&ObjectResult>) {
    let mut fallen: Vec<&ObjectResult> = results.iter().filter(|r| r.fallen() > 0).collect();
    fallen.sort_by(|a, b| {
        (b.fallen(), b.missed())
            .cmp(&(a.fallen(), a.missed()))
            .then(a.name.cmp(&b.name))
    });
    fallen.truncate(n);
    let mut missed: Vec<&ObjectResult> = results.iter().filter(|r| r.missed() != (0, 0)).collect();
    missed.sort_by(|a, b| b.missed().cmp(&a.missed()).then(a.name.cmp(&b.name)));
    missed.truncate(n);
    (fallen, missed)
}

fn print_table(results: &[ObjectResult]) {
    println!(
        "{:<28} {:>6} {:>5} {:>8} {:>7} {:>10} {:>10} {:>6}",
        "object", "tris", "cog", "offered", "held", "pybullet", "trimesh", "s"
    );
    for r in results {
        let (pm, pn) = ObjectResult::recall(&r.pybullet);
        let (tm, tn) = ObjectResult::recall(&r.trimesh);
        let rolling = r
            .offered
            .iter()
            .filter(|o| o.rolling_axis.is_some())
            .count();
        println!(
            "{:<28} {:>6} {:>5} {:>8} {:>7} {:>10} {:>10} {:>6.1}{}",
            r.name,
            r.triangles,
            r.cog_from,
            if rolling > 0 {
                format!("{}+{}r", r.offered.len() - rolling, rolling)
            } else {
                r.offered.len().to_string()
            },
            format!("{}/{}", r.held, r.tested),
            format!("{pm}/{pn}"),
            format!("{tm}/{tn}"),
            r.seconds,
            if r.error.is_some() { "  ERROR" } else { "" }
        );
    }
}

fn run_python(
    python: &Path,
    script: &Path,
    dir: &Path,
    objects: &[Loaded],
    drops: usize,
) -> anyhow::Result<MeasuredAll> {
    let job = Job {
        drops,
        seed: SEED,
        workers: rayon::current_num_threads().max(1),
        objects: objects
            .iter()
            .map(|o| JobObject {
                name: &o.spec.name,
                vertices: o.hull.vertices().iter().map(|p| [p.x, p.y, p.z]).collect(),
                faces: o.hull.triangles(),
                cog: [o.cog.x, o.cog.y, o.cog.z],
            })
            .collect(),
    };
    let job_path = dir.join("job.json");
    let out_path = dir.join("measured.json");
    std::fs::write(&job_path, serde_json::to_vec(&job)?)?;
    let status = Command::new(python)
        .arg(script)
        .arg(&job_path)
        .arg(&out_path)
        .status()
        .with_context(|| format!("running {}", script.display()))?;
    if !status.success() {
        bail!("{} failed ({status})", script.display());
    }
    let text = std::fs::read_to_string(&out_path)?;
    serde_json::from_str(&text).with_context(|| format!("{}", out_path.display()))
}

/// Runs the task (see the module doc).
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse(args)?;
    let started = Instant::now();
    let dir = root.join("target/objects");
    let wheel = data::fetch_wheel(&dir)?;
    let data = data::unpack(&wheel, &dir)?;
    let python = data::venv(&wheel, &dir)?;
    let mut specs = data::pybullet_objects(&data, args.random)?;
    for g in crate::scanned::generate(&dir.join("generated"), SEED)? {
        specs.push(ObjectSpec {
            name: format!("generated/{}", g.name),
            path: g.path,
            scale: [g.scale; 3],
        });
    }
    specs.retain(|s| glob_match(&args.objects, &s.name));
    if specs.is_empty() {
        bail!("no object matches {:?}", args.objects);
    }
    eprintln!("xtask stability: loading {} objects", specs.len());
    let loaded: Vec<anyhow::Result<Loaded>> = specs.par_iter().map(load).collect();
    let mut objects = Vec::new();
    for (spec, l) in specs.iter().zip(loaded) {
        match l {
            Ok(l) => objects.push(l),
            Err(e) => bail!("{} ({}): {e:#}", spec.name, spec.path.display()),
        }
    }
    eprintln!(
        "xtask stability: pybullet drops ({} per object) and trimesh poses",
        args.drops
    );
    let t = Instant::now();
    let script = root.join("xtask/scripts/stable_poses.py");
    let measured = run_python(&python, &script, &dir, &objects, args.drops)?;
    eprintln!(
        "xtask stability: measured in {:.0} s",
        t.elapsed().as_secs_f64()
    );
    let by_name: BTreeMap<&str, &Measured> = measured
        .objects
        .iter()
        .map(|m| (m.name.as_str(), m))
        .collect();
    eprintln!("xtask stability: resting_poses and rapier drop tests");
    let t = Instant::now();
    let results: Vec<ObjectResult> = objects
        .par_iter()
        .map(|o| measure(o, by_name.get(o.spec.name.as_str()).copied()))
        .collect();
    eprintln!(
        "xtask stability: dropped in {:.0} s",
        t.elapsed().as_secs_f64()
    );
    let summary = summarize(
        &results,
        args.drops,
        &measured.trimesh,
        started.elapsed().as_secs_f64(),
    );
    print_table(&results);
    println!();
    print_summary(&summary);
    let (fallen, missed) = worst(&results, 10);
    for (title, list) in [
        ("worst objects: offered poses that fell in rapier", fallen),
        ("worst objects: frequent poses not offered", missed),
    ] {
        if !list.is_empty() {
            println!("\n{title}:");
        }
        for r in list {
            println!("  {}", r.name);
            for line in describe(r) {
                println!("    {line}");
            }
        }
    }
    let report = serde_json::json!({ "summary": summary, "objects": results });
    let report_path = dir.join("report.json");
    std::fs::write(&report_path, serde_json::to_string_pretty(&report)?)?;
    println!("\nwrote {}", report_path.display());
    if args.write_doc {
        let doc = root.join("docs/stability.md");
        std::fs::write(&doc, document(&summary, &results, &args))?;
        println!("wrote {}", doc.display());
    }
    if !summary.goals_met {
        eprintln!(
            "xtask stability: goals missed (hold >= {:.0} %, recall vs pybullet >= {:.0} %, no error)",
            HOLD_GOAL * 100.0,
            RECALL_GOAL * 100.0
        );
        std::process::exit(1);
    }
    Ok(())
}

fn print_summary(s: &Summary) {
    println!(
        "{} objects ({} from pybullet_data, {} generated), {} errors; {} poses offered ({} rolling)",
        s.objects, s.objects_pybullet, s.objects_generated, s.errors, s.offered, s.rolling
    );
    println!(
        "hold (rapier drop test): {}/{} = {:.1} % (goal {:.0} %)",
        s.held,
        s.tested,
        s.hold_rate * 100.0,
        HOLD_GOAL * 100.0
    );
    println!(
        "recall vs pybullet drops (poses >= 5 % of {} drops): {}/{} = {:.1} % (goal {:.0} %)",
        s.drops_per_object,
        s.pybullet_matched,
        s.pybullet_frequent,
        s.recall_pybullet * 100.0,
        RECALL_GOAL * 100.0
    );
    println!(
        "recall vs trimesh {} compute_stable_poses (p >= 0.05): {}/{} = {:.1} %",
        s.trimesh_version,
        s.trimesh_matched,
        s.trimesh_frequent,
        s.recall_trimesh * 100.0
    );
    println!(
        "pybullet drops not at rest after 6 s: {}; {:.0} s in all",
        s.pybullet_unsettled_drops, s.seconds
    );
}

fn document(s: &Summary, results: &[ObjectResult], args: &Args) -> String {
    let mut d = String::new();
    let mut line = |t: &str| {
        d.push_str(t);
        d.push('\n');
    };
    line("# Resting poses on a plane: an independent measurement");
    line("");
    line("Written by `cargo xtask stability --write-doc` (issue 31); the figures below are those");
    line("of the last run that wrote this file. `pickplace_placement::resting_poses(mesh, cog,");
    line("&RestingOptions::default())` is checked on objects we did not make, against two physics");
    line("codes that share no code with ours.");
    line("");
    line("## Run it");
    line("");
    line("```sh");
    line("cargo xtask stability                       # every object, 50 pybullet drops each");
    line("cargo xtask stability --objects 'random/0*' --drops 20");
    line("cargo xtask stability --write-doc           # and rewrite this file");
    line("```");
    line("");
    line("`--random N` sets how many of pybullet's random objects are used (default 120 of 1000).");
    line("The first run downloads the pinned pybullet wheel (`pip download --no-deps");
    line("pybullet==3.2.7`, CPython 3.11 manylinux x86-64, sha256 checked against");
    line("`stability::data::WHEEL_SHA256`; a copy in `$PICKPLACE_WHEELS/` with that hash is used");
    line(
        "instead) into `target/objects/`, unzips its `pybullet_data/` there, and creates the venv",
    );
    line("`target/objects/venv` (the wheel, trimesh 4.12.2, numpy 2.4.6, scipy 1.17.1, networkx");
    line("3.6.1). Later runs reuse all three. The report of every object (offered poses, drifts,");
    line("measured poses, matches) is `target/objects/report.json`. Exit status 1 when a goal is");
    line("missed (below), so CI can run it.");
    line("");
    line("## The test set");
    line("");
    line(&format!(
        "{} objects: {} from pybullet's `pybullet_data` (its random blobs `random_urdfs/NNN`, the",
        s.objects, s.objects_pybullet
    ));
    line("first 120, each mesh with the scale of its URDF's `<mesh scale>`; the duck (`duck.obj`,");
    line("the visual surface, since the collision model is a V-HACD decomposition), teddy, lego,");
    line("jenga, domino, mug, the small cube and three toys; not the 2 m `concave_box`) and");
    line(&format!(
        "{} generated scanned-like meshes (`target/objects/generated/*.stl`, xtask/src/scanned.rs):",
        s.objects_generated
    ));
    line(
        "boxes, bricks, boxes with rounded edges, standing cylinders, soup cans with rims, discs,",
    );
    line("cone frustums and lobed blobs cut flat at the base, sampled at 12 000 to 56 000");
    line("triangles, every vertex moved by up to 1 mm (uniform, seeded), placed at a random pose");
    line("(the scanner's frame, not the object's axes); every third file is in millimetres and");
    line("loaded with scale 0.001.");
    line("");
    line("The centre of gravity is `MassProperties::of(&mesh).center_of_mass` for closed,");
    line("consistently wound meshes, and the solid convex hull's for the others (for them");
    line("`MassProperties` falls back to the surface centroid): here");
    let hull_cog: Vec<String> = results
        .iter()
        .filter(|r| r.cog_from == "hull")
        .map(|r| format!("`{}`", r.name))
        .collect();
    line(&format!(
        "{} ({}).",
        hull_cog.len(),
        if hull_cog.is_empty() {
            "none".to_owned()
        } else {
            hull_cog.join(", ")
        }
    ));
    line("");
    line("## What is measured");
    line("");
    line(
        "- **Hold**: every offered pose except rolling classes is dropped from 1 mm in rapier3d-f64",
    );
    line("  (`pickplace_placement::simulate::drop_test`, feature `physics`, the drop test of the");
    line(
        "  integration tests) onto a flat floor; it holds when the object moved at most 5 mm and 3°",
    );
    line(
        "  after 2 s. The object collides as its triangle mesh, or as the triangles of its convex",
    );
    line(&format!(
        "  hull when it has more than {HULL_COLLIDER_ABOVE} (only hull points touch a plane). Goal: {:.0} %.",
        HOLD_GOAL * 100.0
    ));
    line(
        "- **Recall vs pybullet**: pybullet 3.2.7 drops the object (its convex hull, CoG as above,",
    );
    line(
        "  friction 0.8, no restitution) from random orientations (seeded), the lowest point 1 cm",
    );
    line(
        "  above a plane, angular damping 0.3, until at rest (1 s at least) or 6 s; the final down directions (object frame) of the drops at rest are",
    );
    line("  clustered within 5°. Every cluster holding at least 5 % of the drops must be offered:");
    line("  some offered support normal within 10° of it, or a rolling class whose axis is within");
    line(&format!(
        "  10° of perpendicular to it. Goal: {:.0} %.",
        RECALL_GOAL * 100.0
    ));
    line("- **Recall vs trimesh**: the same for `trimesh.poses.compute_stable_poses(mesh,");
    line("  center_mass=cog)` poses of probability at least 0.05 (quasi-static toppling from a");
    line("  uniform sphere of directions). No goal: reported.");
    line("");
    line("## Figures");
    line("");
    line(&format!(
        "Last run: `cargo xtask stability --drops {}{}`, {:.0} s on 2 cores.",
        args.drops,
        if args.objects == "*" {
            String::new()
        } else {
            format!(" --objects '{}'", args.objects)
        },
        s.seconds
    ));
    line("");
    line("| figure | value | goal |");
    line("|---|---|---|");
    line(&format!(
        "| objects | {} ({} errors) | no error |",
        s.objects, s.errors
    ));
    line(&format!(
        "| poses offered | {} ({} rolling classes) | |",
        s.offered, s.rolling
    ));
    line(&format!(
        "| hold in rapier | {}/{} = {:.1} % | ≥ {:.0} % |",
        s.held,
        s.tested,
        s.hold_rate * 100.0,
        HOLD_GOAL * 100.0
    ));
    line(&format!(
        "| recall vs pybullet (≥ 5 % of drops) | {}/{} = {:.1} % | ≥ {:.0} % |",
        s.pybullet_matched,
        s.pybullet_frequent,
        s.recall_pybullet * 100.0,
        RECALL_GOAL * 100.0
    ));
    line(&format!(
        "| recall vs trimesh (p ≥ 0.05) | {}/{} = {:.1} % | |",
        s.trimesh_matched,
        s.trimesh_frequent,
        s.recall_trimesh * 100.0
    ));
    line(&format!(
        "| pybullet drops not at rest after 6 s | {} of {} | |",
        s.pybullet_unsettled_drops,
        s.objects * s.drops_per_object
    ));
    line(&format!(
        "| goals met | {} | |",
        if s.goals_met { "yes" } else { "no" }
    ));
    line("");
    line("By group:");
    line("");
    line("| group | objects | offered (rolling) | hold | recall vs pybullet | recall vs trimesh |");
    line("|---|---|---|---|---|---|");
    for (group, prefix) in [
        ("pybullet's everyday objects", "pybullet/"),
        ("pybullet's random blobs", "random/"),
        ("generated, scanned-like", "generated/"),
    ] {
        let members: Vec<ObjectResult> = results
            .iter()
            .filter(|r| r.name.starts_with(prefix))
            .cloned()
            .collect();
        let g = summarize(&members, s.drops_per_object, &s.trimesh_version, 0.0);
        line(&format!(
            "| {group} | {} | {} ({}) | {}/{} = {:.1} % | {}/{} = {:.1} % | {}/{} = {:.1} % |",
            g.objects,
            g.offered,
            g.rolling,
            g.held,
            g.tested,
            g.hold_rate * 100.0,
            g.pybullet_matched,
            g.pybullet_frequent,
            g.recall_pybullet * 100.0,
            g.trimesh_matched,
            g.trimesh_frequent,
            g.recall_trimesh * 100.0
        ));
    }
    line("");
    let (fallen, missed) = worst(results, 10);
    for (title, list) in [
        ("Worst objects: offered poses that fell in rapier", fallen),
        (
            "Worst objects: frequent poses (pybullet's, then trimesh's) not offered",
            missed,
        ),
    ] {
        if list.is_empty() {
            continue;
        }
        line(&format!("{title}:"));
        line("");
        for r in list {
            line(&format!("- `{}`", r.name));
            for l in describe(r) {
                line(&format!("  - {l}"));
            }
        }
        line("");
    }
    d
}
