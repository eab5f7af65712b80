//! `cargo xtask fuzz --seconds N [TARGET…]`: runs the cargo-fuzz targets of `fuzz/` one after
//! the other, N seconds each, and prints executions and crashes per target; and
//! `cargo xtask fuzz-seeds`: writes the generated part of the seed corpora (`fuzz/seeds/`).
//!
//! Each target fuzzes from two corpus directories: `fuzz/corpus/TARGET` (grown by libFuzzer,
//! ignored by git) and `fuzz/seeds/TARGET` (the small committed seed set, read only). A crash
//! input lands in `fuzz/artifacts/TARGET/`; the task then exits with status 1.

use anyhow::{Context, bail};
use std::fmt::Write as _;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Instant;

/// Every fuzz target of `fuzz/Cargo.toml`, in the order they run.
pub const TARGETS: [&str; 13] = [
    "mesh_stl",
    "mesh_obj",
    "mesh_ply",
    "urdf",
    "srdf",
    "scene",
    "cluster_db",
    "prm_roadmap",
    "plan_json",
    "gripper",
    "srdf_writer",
    "joint_limits_yaml",
    "scene_numbers",
];

/// Command-line options of `cargo xtask fuzz`.
#[derive(Debug, PartialEq)]
pub struct FuzzArgs {
    /// Seconds per target (`--seconds`, default 60).
    pub seconds: u64,
    /// Targets to run (default: all of [`TARGETS`]).
    pub targets: Vec<String>,
}

/// Parses the arguments after `fuzz`.
pub fn parse_args(args: &[String]) -> anyhow::Result<FuzzArgs> {
    let mut seconds = 60;
    let mut targets = Vec::new();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        if let Some(value) = arg.strip_prefix("--seconds=") {
            seconds = value.parse().context("--seconds takes a whole number")?;
        } else if arg == "--seconds" {
            let value = it.next().context("--seconds takes a value")?;
            seconds = value.parse().context("--seconds takes a whole number")?;
        } else if arg.starts_with('-') {
            bail!("unknown option {arg:?}; usage: cargo xtask fuzz --seconds N [TARGET…]");
        } else if TARGETS.contains(&arg.as_str()) {
            targets.push(arg.clone());
        } else {
            bail!(
                "unknown fuzz target {arg:?}; targets: {}",
                TARGETS.join(", ")
            );
        }
    }
    if seconds == 0 {
        bail!("--seconds must be at least 1");
    }
    if targets.is_empty() {
        targets = TARGETS.iter().map(|t| t.to_string()).collect();
    }
    Ok(FuzzArgs { seconds, targets })
}

/// What one libFuzzer run reported.
#[derive(Debug, Default, PartialEq)]
pub struct RunStats {
    /// Inputs executed (`stat::number_of_executed_units`, else the last `#N` status line).
    pub executions: u64,
    /// Seconds of fuzzing: libFuzzer's `Done N runs in S second(s)`, else the wall-clock time
    /// of the whole `cargo fuzz run` (build included) as measured by this task.
    pub seconds: f64,
    /// Inputs in the corpus at the end (the last status line's `corp:` count).
    pub corpus: Option<u64>,
    /// Coverage counter at the end (`cov:` of the last status line).
    pub coverage: Option<u64>,
    /// Peak resident memory in MB (`stat::peak_rss_mb`, else `rss:`).
    pub peak_rss_mb: Option<u64>,
    /// Crash, timeout, leak or out-of-memory inputs written (`Test unit written to PATH`).
    pub artifacts: Vec<String>,
    /// The first line that names what went wrong (a panic message or a libFuzzer `ERROR`).
    pub failure: Option<String>,
}

impl RunStats {
    /// Executions per second over the run.
    pub fn execs_per_second(&self) -> f64 {
        if self.seconds > 0.0 {
            self.executions as f64 / self.seconds
        } else {
            0.0
        }
    }
}

/// The number after `key` in `line` (digits only), e.g. `cov: 123` -> 123.
fn number_after(line: &str, key: &str) -> Option<u64> {
    let rest = &line[line.find(key)? + key.len()..];
    let digits: String = rest
        .trim_start()
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Reads libFuzzer's stderr (run with `-print_final_stats=1`). `seconds` is the run's
/// wall-clock time, used when libFuzzer did not print its own (a crash stops it early).
pub fn parse_libfuzzer_log(log: &str, seconds: f64) -> RunStats {
    let mut stats = RunStats {
        seconds,
        ..RunStats::default()
    };
    let mut final_executions = None;
    let mut final_rss = None;
    for line in log.lines() {
        let line = line.trim_end();
        if let Some(rest) = line.strip_prefix('#') {
            // Status lines: "#123456\tNEW    cov: 1234 ft: 2345 corp: 56/789b ... rss: 40Mb".
            if let Some(n) = number_after(rest, "")
                && rest.starts_with(|c: char| c.is_ascii_digit())
            {
                stats.executions = stats.executions.max(n);
                stats.coverage = number_after(rest, "cov:").or(stats.coverage);
                stats.corpus = number_after(rest, "corp:").or(stats.corpus);
                stats.peak_rss_mb = number_after(rest, "rss:").or(stats.peak_rss_mb);
            }
        } else if let Some(rest) = line.strip_prefix("Done ") {
            // "Done 60000 runs in 61 second(s)": libFuzzer's own time, without the build.
            if let Some(s) = number_after(rest, "runs in") {
                stats.seconds = s as f64;
            }
        } else if let Some(rest) = line.strip_prefix("stat::number_of_executed_units:") {
            final_executions = rest.trim().parse().ok();
        } else if let Some(rest) = line.strip_prefix("stat::peak_rss_mb:") {
            final_rss = rest.trim().parse().ok();
        } else if let Some(rest) = line.split("Test unit written to ").nth(1) {
            stats.artifacts.push(rest.trim().to_string());
        } else if stats.failure.is_none()
            && (line.contains("panicked at")
                || line.starts_with("==") && line.contains("ERROR: libFuzzer")
                || line.contains("ERROR: AddressSanitizer"))
        {
            stats.failure = Some(line.to_string());
        }
    }
    if let Some(n) = final_executions {
        stats.executions = n;
    }
    if final_rss.is_some() {
        stats.peak_rss_mb = final_rss;
    }
    stats
}

/// The summary table printed at the end of a run.
pub fn summary_table(rows: &[(String, RunStats)]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<12} {:>8} {:>14} {:>10} {:>8} {:>8} {:>8}  crashes",
        "target", "seconds", "executions", "execs/s", "corpus", "cov", "rss MB"
    );
    let opt = |v: Option<u64>| v.map_or_else(|| "-".to_string(), |v| v.to_string());
    for (target, s) in rows {
        let crashes = if s.artifacts.is_empty() && s.failure.is_none() {
            "0".to_string()
        } else {
            format!(
                "{} ({})",
                s.artifacts.len().max(1),
                if s.artifacts.is_empty() {
                    s.failure.clone().unwrap_or_default()
                } else {
                    s.artifacts.join(", ")
                }
            )
        };
        let _ = writeln!(
            out,
            "{:<12} {:>8.0} {:>14} {:>10.0} {:>8} {:>8} {:>8}  {}",
            target,
            s.seconds,
            s.executions,
            s.execs_per_second(),
            opt(s.corpus),
            opt(s.coverage),
            opt(s.peak_rss_mb),
            crashes
        );
    }
    out
}

/// Fails with a clear message when `cargo +nightly` or `cargo fuzz` cannot run.
fn check_tools(fuzz_dir: &Path) -> anyhow::Result<()> {
    let nightly = Command::new("cargo")
        .args(["+nightly", "--version"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !nightly.is_ok_and(|s| s.success()) {
        bail!(
            "`cargo +nightly` does not run: fuzzing needs a nightly toolchain \
             (rustup toolchain install nightly)"
        );
    }
    let fuzz = Command::new("cargo")
        .args(["+nightly", "fuzz", "--version"])
        .current_dir(fuzz_dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status();
    if !fuzz.is_ok_and(|s| s.success()) {
        bail!("`cargo fuzz` is not installed: cargo install cargo-fuzz --locked");
    }
    Ok(())
}

/// `cargo xtask fuzz`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse_args(args)?;
    let fuzz_dir = root.join("fuzz");
    check_tools(&fuzz_dir)?;
    // Without libFuzzer's instrumentation the stable target dir would be rebuilt; the fuzz
    // builds go to their own triple directory, so the shared target dir is fine.
    eprintln!("== building the fuzz targets (cargo +nightly fuzz build) ==");
    let status = Command::new("cargo")
        .args(["+nightly", "fuzz", "build", "--sanitizer", "none"])
        .current_dir(root)
        .status()
        .context("running cargo +nightly fuzz build")?;
    if !status.success() {
        bail!("cargo +nightly fuzz build failed ({status})");
    }
    let mut rows = Vec::new();
    for target in &args.targets {
        let corpus = fuzz_dir.join("corpus").join(target);
        let seeds = fuzz_dir.join("seeds").join(target);
        std::fs::create_dir_all(&corpus)
            .with_context(|| format!("creating {}", corpus.display()))?;
        let mut command = Command::new("cargo");
        command
            .args(["+nightly", "fuzz", "run", "--sanitizer", "none", target])
            .arg(&corpus);
        if seeds.is_dir() {
            command.arg(&seeds);
        }
        command
            .arg("--")
            .arg(format!("-max_total_time={}", args.seconds))
            .args(["-print_final_stats=1", "-timeout=10", "-rss_limit_mb=2048"])
            .current_dir(root)
            .stdout(Stdio::inherit())
            .stderr(Stdio::piped());
        eprintln!("== {target}: {} s ==", args.seconds);
        let started = Instant::now();
        let output = command
            .output()
            .with_context(|| format!("running cargo fuzz run {target}"))?;
        let seconds = started.elapsed().as_secs_f64();
        let log = String::from_utf8_lossy(&output.stderr);
        let log_path = fuzz_dir.join("artifacts").join(format!("{target}.log"));
        if let Some(dir) = log_path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        std::fs::write(&log_path, log.as_bytes())
            .with_context(|| format!("writing {}", log_path.display()))?;
        let mut stats = parse_libfuzzer_log(&log, seconds);
        if !output.status.success() && stats.artifacts.is_empty() && stats.failure.is_none() {
            stats.failure = Some(format!(
                "cargo fuzz run exited with {}; see {}",
                output.status,
                log_path.display()
            ));
        }
        eprintln!(
            "{target}: {} executions in {seconds:.0} s ({:.0}/s), {} crash artifact(s); log {}",
            stats.executions,
            stats.execs_per_second(),
            stats.artifacts.len(),
            log_path.display()
        );
        rows.push((target.clone(), stats));
    }
    print!("{}", summary_table(&rows));
    let failed: Vec<&str> = rows
        .iter()
        .filter(|(_, s)| !s.artifacts.is_empty() || s.failure.is_some())
        .map(|(t, _)| t.as_str())
        .collect();
    if !failed.is_empty() {
        bail!(
            "crashes in {} (inputs under fuzz/artifacts/)",
            failed.join(", ")
        );
    }
    Ok(())
}

/// Writes `bytes` to `dir/name`, creating `dir`.
fn write_seed(dir: &Path, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let path = dir.join(name);
    std::fs::write(&path, bytes).with_context(|| format!("writing {}", path.display()))
}

/// `cargo xtask fuzz-seeds`: the generated seeds (binary formats and meshes converted to
/// OBJ and PLY). Hand-written seeds under `fuzz/seeds/` are left as they are.
pub fn write_seeds(root: &Path) -> anyhow::Result<()> {
    use pickplace_geometry::cluster::ClusterParams;
    use pickplace_geometry::db::ClusterDatabase;
    use pickplace_geometry::hash::mesh_hash;
    use pickplace_geometry::mesh::{MeshOptions, load};

    let seeds = root.join("fuzz/seeds");
    let options = MeshOptions::default();
    let the_box = load(&root.join("meshes/box.stl"), &options)?;
    let can = load(&root.join("meshes/can.stl"), &options)?;

    // Meshes: the shipped box as binary and ASCII STL, OBJ, and PLY in three encodings.
    let stl = seeds.join("mesh_stl");
    write_seed(
        &stl,
        "box_binary.stl",
        &std::fs::read(root.join("meshes/box.stl"))?,
    )?;
    write_seed(&stl, "box_ascii.stl", ascii_stl(&the_box).as_bytes())?;
    write_seed(&seeds.join("mesh_obj"), "box.obj", obj(&the_box).as_bytes())?;
    let ply = seeds.join("mesh_ply");
    write_seed(
        &ply,
        "box_ascii.ply",
        &ply_bytes(&the_box, PlyEncoding::Ascii),
    )?;
    write_seed(
        &ply,
        "box_le.ply",
        &ply_bytes(&the_box, PlyEncoding::LittleEndian),
    )?;
    write_seed(
        &ply,
        "box_be.ply",
        &ply_bytes(&the_box, PlyEncoding::BigEndian),
    )?;

    // Cluster databases of the can: mode byte (0 whole file, 1 payload only), params byte.
    let hash = mesh_hash(&can);
    write_seed(
        &seeds,
        "cluster_db.hash",
        format!("0x{hash:016x}\n").as_bytes(),
    )?;
    let db_dir = seeds.join("cluster_db");
    for (which, params) in [ClusterParams::environment(), ClusterParams::finger()]
        .into_iter()
        .enumerate()
    {
        let file = ClusterDatabase::build(&can, &params)?.to_bytes();
        let header_len = u32::from_le_bytes([file[12], file[13], file[14], file[15]]) as usize;
        let payload = &file[16 + header_len..];
        let name = params.mode.name();
        write_seed(
            &db_dir,
            &format!("can_{name}_file"),
            &[&[0, which as u8], &file[..]].concat(),
        )?;
        write_seed(
            &db_dir,
            &format!("can_{name}_payload"),
            &[&[1, which as u8], payload].concat(),
        )?;
    }

    // Roadmaps: a 2-D and a 3-D lazy roadmap, whole files (mode 0) and with the body
    // checksum recomputed by the target (mode 1).
    let prm_dir = seeds.join("prm_roadmap");
    for (name, lower, upper, weights, nodes) in [
        (
            "planar",
            vec![-1.0, -1.0],
            vec![1.0, 1.0],
            vec![1.0, 1.0],
            24,
        ),
        (
            "arm3",
            vec![-3.0, -2.0, -1.5],
            vec![3.0, 2.0, 1.5],
            vec![1.0, 0.5, 0.25],
            40,
        ),
    ] {
        let space = pickplace::prm::JointSpace::new(lower, upper, weights)?;
        let options = pickplace::prm::RoadmapOptions {
            node_count: nodes,
            neighbors: 4,
            seed: 3,
            ..pickplace::prm::RoadmapOptions::default()
        };
        let roadmap = pickplace::prm::Roadmap::build_lazy(&space, &options)?;
        let bytes = pickplace::prm::codec::encode(&roadmap)?;
        for mode in [0u8, 1] {
            write_seed(
                &prm_dir,
                &format!("{name}_{mode}"),
                &[&[mode], &bytes[..]].concat(),
            )?;
        }
    }
    eprintln!("seeds written under {}", seeds.display());
    Ok(())
}

fn ascii_stl(mesh: &pickplace_geometry::mesh::TriMesh) -> String {
    let mut out = String::from("solid box\n");
    for t in 0..mesh.triangle_count() {
        let n = mesh.triangle_normal(t);
        let _ = writeln!(
            out,
            "  facet normal {} {} {}\n    outer loop",
            n.x, n.y, n.z
        );
        for p in mesh.triangle_points(t) {
            let _ = writeln!(out, "      vertex {} {} {}", p.x, p.y, p.z);
        }
        out.push_str("    endloop\n  endfacet\n");
    }
    out.push_str("endsolid box\n");
    out
}

fn obj(mesh: &pickplace_geometry::mesh::TriMesh) -> String {
    let mut out = String::from("# box\no box\n");
    for p in mesh.vertices() {
        let _ = writeln!(out, "v {} {} {}", p.x, p.y, p.z);
    }
    out.push_str("vt 0 0\nvn 0 0 1\n");
    // Every corner syntax the reader accepts: a, a/t, a//n, a/t/n, and negative indices.
    let n = mesh.vertices().len() as i64;
    for (i, t) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = t.map(|v| i64::from(v) + 1);
        let line = match i % 4 {
            0 => format!("f {a} {b} {c}"),
            1 => format!("f {a}/1 {b}/1 {c}/1"),
            2 => format!("f {a}//1 {b}//1 {c}//1"),
            _ => format!("f {}/1/1 {}/1/1 {}/1/1", a - n - 1, b - n - 1, c - n - 1),
        };
        let _ = writeln!(out, "{line}");
    }
    out
}

#[derive(Clone, Copy)]
enum PlyEncoding {
    Ascii,
    LittleEndian,
    BigEndian,
}

fn ply_bytes(mesh: &pickplace_geometry::mesh::TriMesh, encoding: PlyEncoding) -> Vec<u8> {
    let format = match encoding {
        PlyEncoding::Ascii => "ascii",
        PlyEncoding::LittleEndian => "binary_little_endian",
        PlyEncoding::BigEndian => "binary_big_endian",
    };
    let mut out = format!(
        "ply\nformat {format} 1.0\ncomment seed\nelement vertex {}\nproperty float x\n\
         property float y\nproperty float z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        mesh.vertices().len(),
        mesh.triangle_count()
    )
    .into_bytes();
    let f32_bytes = |v: f32| match encoding {
        PlyEncoding::BigEndian => v.to_be_bytes(),
        _ => v.to_le_bytes(),
    };
    let i32_bytes = |v: i32| match encoding {
        PlyEncoding::BigEndian => v.to_be_bytes(),
        _ => v.to_le_bytes(),
    };
    for p in mesh.vertices() {
        let xyz = [p.x as f32, p.y as f32, p.z as f32];
        match encoding {
            PlyEncoding::Ascii => {
                out.extend(format!("{} {} {}\n", xyz[0], xyz[1], xyz[2]).bytes());
            }
            _ => xyz.iter().for_each(|&v| out.extend(f32_bytes(v))),
        }
    }
    for t in mesh.triangles() {
        match encoding {
            PlyEncoding::Ascii => out.extend(format!("3 {} {} {}\n", t[0], t[1], t[2]).bytes()),
            _ => {
                out.push(3);
                t.iter().for_each(|&v| out.extend(i32_bytes(v as i32)));
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const CLEAN_RUN: &str = "\
INFO: Running with entropic power schedule (0xFF, 100).
INFO: Seed: 1234
INFO:        3 files found in fuzz/seeds/mesh_stl
#2\tINITED cov: 410 ft: 420 corp: 3/2050b exec/s: 0 rss: 31Mb
#1024\tpulse  cov: 612 ft: 900 corp: 40/9000b lim: 4096 exec/s: 512 rss: 45Mb
#52311\tNEW    cov: 640 ft: 1011 corp: 61/12Kb lim: 4096 exec/s: 871 rss: 58Mb L: 300/4096 MS: 2 ChangeBit-CopyPart-
#60000\tDONE   cov: 641 ft: 1013 corp: 62/12Kb lim: 4096 exec/s: 1000 rss: 60Mb
Done 60000 runs in 61 second(s)
stat::number_of_executed_units: 60123
stat::average_exec_per_sec:     985
stat::new_units_added:          59
stat::slowest_unit_time_sec:    0
stat::peak_rss_mb:              61
";

    const CRASH_RUN: &str = "\
#2\tINITED cov: 410 ft: 420 corp: 3/2050b exec/s: 0 rss: 31Mb
#8192\tpulse  cov: 612 ft: 900 corp: 40/9000b lim: 4096 exec/s: 4096 rss: 45Mb

thread '<unnamed>' panicked at crates/pickplace-geometry/src/mesh/ply.rs:80:17:
index out of bounds: the len is 3 but the index is 7
==4242== ERROR: libFuzzer: deadly signal
MS: 1 ChangeByte-; base unit: 0123abcd
artifact_prefix='/repo/fuzz/artifacts/mesh_ply/'; Test unit written to /repo/fuzz/artifacts/mesh_ply/crash-deadbeef
Base64: cGx5Cg==
";

    #[test]
    fn clean_run_takes_the_final_stats() {
        let s = parse_libfuzzer_log(CLEAN_RUN, 75.0);
        assert_eq!(s.seconds, 61.0, "libFuzzer's own time, not the build");
        assert_eq!(s.executions, 60_123);
        assert_eq!(s.corpus, Some(62));
        assert_eq!(s.coverage, Some(641));
        assert_eq!(s.peak_rss_mb, Some(61));
        assert!(s.artifacts.is_empty());
        assert_eq!(s.failure, None);
        assert!((s.execs_per_second() - 985.62).abs() < 0.01);
    }

    #[test]
    fn crash_run_reports_the_artifact_and_the_panic() {
        let s = parse_libfuzzer_log(CRASH_RUN, 3.0);
        assert_eq!(s.executions, 8192, "last status line without final stats");
        assert_eq!(
            s.seconds, 3.0,
            "wall-clock time when libFuzzer stopped early"
        );
        assert_eq!(
            s.artifacts,
            vec!["/repo/fuzz/artifacts/mesh_ply/crash-deadbeef".to_string()]
        );
        assert!(
            s.failure
                .as_deref()
                .is_some_and(|f| f.contains("panicked at crates/pickplace-geometry"))
        );
        let table = summary_table(&[("mesh_ply".into(), s)]);
        assert!(table.contains("mesh_ply"));
        assert!(table.contains("1 (/repo/fuzz/artifacts/mesh_ply/crash-deadbeef)"));
    }

    #[test]
    fn summary_shows_zero_crashes_for_a_clean_run() {
        let table = summary_table(&[("scene".into(), parse_libfuzzer_log(CLEAN_RUN, 60.0))]);
        let row = table.lines().nth(1).expect("a row");
        assert!(row.starts_with("scene"));
        assert!(row.ends_with("  0"), "{row}");
        assert!(row.contains("60123"));
    }

    #[test]
    fn targets_are_the_bins_of_the_fuzz_crate() {
        let manifest = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fuzz/Cargo.toml");
        let text = std::fs::read_to_string(&manifest).expect("fuzz/Cargo.toml");
        let bins: Vec<&str> = text
            .split("[[bin]]")
            .skip(1)
            .filter_map(|bin| {
                let line = bin.lines().find(|l| l.trim_start().starts_with("name"))?;
                line.split('"').nth(1)
            })
            .collect();
        assert_eq!(bins, TARGETS, "TARGETS and the [[bin]] entries differ");
        for target in TARGETS {
            let seeds = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../fuzz/seeds")
                .join(target);
            let count = std::fs::read_dir(&seeds).map_or(0, |d| d.count());
            assert!(count > 0, "no seeds in {}", seeds.display());
        }
    }

    #[test]
    fn arguments() {
        let args = |a: &[&str]| parse_args(&a.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        let all = args(&[]).expect("defaults");
        assert_eq!(all.seconds, 60);
        assert_eq!(all.targets.len(), TARGETS.len());
        let some = args(&["--seconds", "600", "urdf", "scene"]).expect("valid");
        assert_eq!(
            some,
            FuzzArgs {
                seconds: 600,
                targets: vec!["urdf".into(), "scene".into()]
            }
        );
        assert_eq!(args(&["--seconds=5"]).expect("valid").seconds, 5);
        assert!(args(&["--seconds", "x"]).is_err());
        assert!(args(&["--seconds", "0"]).is_err());
        assert!(args(&["nope"]).is_err());
        assert!(args(&["--quick"]).is_err());
    }
}
