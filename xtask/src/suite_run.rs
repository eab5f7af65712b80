//! `cargo xtask suite run [--seeds 1,2,3] [--scenes GLOB] [--write-doc]`: plans every scene of
//! the suite (`scenes/suite/suite.toml`) with the release CLI, as a user would: `pickplace
//! plan` then `pickplace validate` for a feasible scene; for an infeasible one, exit status 1
//! and the manifest's stage and reason on stderr. Prints a table and a summary, and exits
//! non-zero when an expectation fails or when seeds disagree on a scene.
//!
//! Planning time is the wall-clock of the planning call (`pickplace::plan`, setup and cache
//! loading excluded) that the CLI prints ("planned in X ms" / "no plan (X ms)").

use anyhow::{Context, bail};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The manifest as written by `cargo xtask suite gen`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    pub format: u32,
    pub scene: Vec<Entry>,
}

/// One scene of the manifest.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    pub name: String,
    pub file: String,
    pub object: String,
    pub expect: String,
    #[serde(default)]
    pub stage: Option<String>,
    #[serde(default)]
    pub reason: Option<String>,
    pub tags: Vec<String>,
    pub about: String,
    /// Why a feasible scene is not met yet (an open failure: reported, not failing the run).
    #[serde(default)]
    pub open: Option<String>,
}

impl Entry {
    pub fn feasible(&self) -> bool {
        self.expect == "feasible"
    }
}

/// Reads `scenes/suite/suite.toml`.
pub fn load_manifest(root: &Path) -> anyhow::Result<Manifest> {
    let path = root.join("scenes/suite/suite.toml");
    let text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let m: Manifest = toml::from_str(&text).with_context(|| format!("{}", path.display()))?;
    if m.format != 1 {
        bail!("{}: format {} (expected 1)", path.display(), m.format);
    }
    Ok(m)
}

/// `*` matches any run of characters; everything else is literal.
pub fn glob_match(pattern: &str, name: &str) -> bool {
    let parts: Vec<&str> = pattern.split('*').collect();
    if parts.len() == 1 {
        return pattern == name;
    }
    let mut rest = name;
    for (i, part) in parts.iter().enumerate() {
        if i == 0 {
            match rest.strip_prefix(part) {
                Some(r) => rest = r,
                None => return false,
            }
        } else if i == parts.len() - 1 {
            return rest.ends_with(part);
        } else {
            match rest.find(part) {
                Some(at) => rest = &rest[at + part.len()..],
                None => return false,
            }
        }
    }
    true
}

/// What one run of one scene with one seed gave.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Planned and validated (feasible scene: success).
    Valid,
    /// Planned, but the validator refused the plan.
    Invalid(String),
    /// Exit 1, no plan.
    NoPlan(String),
    /// Any other exit status (bad input, crash).
    Error(String),
}

impl Outcome {
    fn word(&self) -> &'static str {
        match self {
            Outcome::Valid => "valid",
            Outcome::Invalid(_) => "invalid",
            Outcome::NoPlan(_) => "no plan",
            Outcome::Error(_) => "error",
        }
    }

    fn reason(&self) -> &str {
        match self {
            Outcome::Valid => "",
            Outcome::Invalid(r) | Outcome::NoPlan(r) | Outcome::Error(r) => r,
        }
    }
}

/// One row of the table.
#[derive(Debug, Clone)]
pub struct Row {
    pub scene: String,
    pub seed: u64,
    pub feasible: bool,
    pub outcome: Outcome,
    pub strategy: String,
    /// Planning time (s), when the CLI printed it.
    pub time: Option<f64>,
    /// Whether the outcome is what the manifest expects.
    pub as_expected: bool,
    /// The manifest's reason when the scene is known not to be met yet.
    pub open: Option<String>,
}

struct Args {
    seeds: Vec<u64>,
    glob: String,
    write_doc: bool,
}

fn parse(args: &[String]) -> anyhow::Result<Args> {
    let mut out = Args {
        seeds: vec![1, 2, 3],
        glob: "*".into(),
        write_doc: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--seeds" => {
                let v = it.next().context("--seeds needs a list, e.g. 1,2,3")?;
                out.seeds = v
                    .split(',')
                    .map(|s| s.trim().parse::<u64>())
                    .collect::<Result<_, _>>()
                    .with_context(|| format!("--seeds {v}"))?;
            }
            "--scenes" => out.glob = it.next().context("--scenes needs a glob")?.clone(),
            "--write-doc" => out.write_doc = true,
            other => bail!(
                "unknown argument {other}; usage: cargo xtask suite run [--seeds 1,2,3] [--scenes GLOB] [--write-doc]"
            ),
        }
    }
    if out.seeds.is_empty() {
        bail!("--seeds: at least one seed");
    }
    Ok(out)
}

/// Builds the release CLI and returns its path.
fn build_cli(root: &Path) -> anyhow::Result<PathBuf> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let status = Command::new(cargo)
        .current_dir(root)
        .args(["build", "--release", "-p", "pickplace-cli"])
        .status()
        .context("cannot run cargo build")?;
    if !status.success() {
        bail!("cargo build --release -p pickplace-cli failed ({status})");
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root.join("target"));
    Ok(target.join("release/pickplace"))
}

/// The number after `key` up to " ms" in `text` (the CLI's timing lines), in seconds.
pub fn parse_ms(text: &str, key: &str) -> Option<f64> {
    let at = text.find(key)? + key.len();
    let rest = &text[at..];
    let end = rest.find(" ms")?;
    rest[..end].trim().parse::<f64>().ok().map(|ms| ms / 1e3)
}

/// The lines of the CLI's stderr that say why: `error:` lines and the reasons under
/// "no plan", joined; capped so that the table stays readable.
pub fn why(stderr: &str) -> String {
    let mut lines: Vec<&str> = Vec::new();
    let mut in_reasons = false;
    for l in stderr.lines() {
        let t = l.trim();
        if t.starts_with("error:") || t.starts_with("invalid") || t.starts_with("FAIL") {
            lines.push(t);
        } else if t.starts_with("no plan") {
            in_reasons = true;
        } else if in_reasons && l.starts_with("    ") {
            lines.push(t);
        }
    }
    if lines.is_empty() {
        lines = stderr.lines().rev().take(1).map(str::trim).collect();
    }
    let mut s = lines.join(" | ");
    if s.len() > 400 {
        let mut cut = 400;
        while !s.is_char_boundary(cut) {
            cut -= 1;
        }
        s.truncate(cut);
        s.push('…');
    }
    s
}

/// The validator's first problem (the lines after its "checked … states" line) and its count
/// line, if any.
pub fn why_invalid(stderr: &str) -> String {
    let problems: Vec<&str> = stderr
        .lines()
        .skip_while(|l| !l.trim_start().starts_with("checked "))
        .skip(1)
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    match problems.as_slice() {
        [] => why(stderr),
        [one] => (*one).to_owned(),
        [first, .., last] if last.contains("problems in all") => format!("{first} ({last})"),
        [first, rest @ ..] => format!("{first} (and {} more)", rest.len()),
    }
}

/// Runs one scene with one seed.
fn run_one(
    cli: &Path,
    root: &Path,
    cache: &Path,
    scratch: &Path,
    e: &Entry,
    seed: u64,
) -> anyhow::Result<Row> {
    let scene = root.join("scenes/suite").join(&e.file);
    let out = scratch.join(format!("{}-{seed}.json", e.name));
    let _ = std::fs::remove_file(&out);
    let plan = Command::new(cli)
        .current_dir(root)
        .arg("plan")
        .arg(&scene)
        .arg("--seed")
        .arg(seed.to_string())
        .arg("--cache")
        .arg(cache)
        .arg("--out")
        .arg(&out)
        .output()
        .with_context(|| format!("running {}", cli.display()))?;
    let err = String::from_utf8_lossy(&plan.stderr).into_owned();
    let time = parse_ms(&err, "planned in ").or_else(|| parse_ms(&err, "no plan ("));
    let mut strategy = String::new();
    let outcome = match plan.status.code() {
        Some(0) => {
            let json: serde_json::Value = serde_json::from_slice(
                &std::fs::read(&out).with_context(|| format!("{}", out.display()))?,
            )
            .with_context(|| format!("{}: plan JSON", out.display()))?;
            strategy = json["strategy"].as_str().unwrap_or_default().to_owned();
            let v = Command::new(cli)
                .current_dir(root)
                .arg("validate")
                .arg(&scene)
                .arg(&out)
                .arg("--cache")
                .arg(cache)
                .output()
                .with_context(|| format!("running {} validate", cli.display()))?;
            let verr = String::from_utf8_lossy(&v.stderr).into_owned();
            match v.status.code() {
                Some(0) => Outcome::Valid,
                Some(1) => Outcome::Invalid(why_invalid(&verr)),
                _ => Outcome::Error(format!("validate: {}", why(&verr))),
            }
        }
        Some(1) => Outcome::NoPlan(why(&err)),
        code => Outcome::Error(format!("exit {code:?}: {}", why(&err))),
    };
    let as_expected = if e.feasible() {
        outcome == Outcome::Valid
    } else {
        let low = err.to_lowercase();
        plan.status.code() == Some(1)
            && e.stage
                .iter()
                .chain(&e.reason)
                .all(|s| low.contains(&s.to_lowercase()))
    };
    Ok(Row {
        scene: e.name.clone(),
        seed,
        feasible: e.feasible(),
        outcome,
        strategy,
        time,
        as_expected,
        open: e.open.clone(),
    })
}

/// The `q`-quantile of sorted values (nearest rank).
pub fn quantile(sorted: &[f64], q: f64) -> Option<f64> {
    if sorted.is_empty() {
        return None;
    }
    let rank = ((q * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    Some(sorted[rank - 1])
}

/// The summary of a run.
#[derive(Debug)]
pub struct Summary {
    pub feasible_runs: usize,
    pub feasible_ok: usize,
    pub infeasible_runs: usize,
    pub infeasible_ok: usize,
    pub median: Option<f64>,
    pub p95: Option<f64>,
    /// The same over the runs that planned and validated.
    pub median_ok: Option<f64>,
    pub p95_ok: Option<f64>,
    /// Scenes whose seeds gave different expectations met.
    pub disagreeing: Vec<String>,
    pub failures: Vec<Row>,
}

pub fn summarize(rows: &[Row]) -> Summary {
    let feasible: Vec<&Row> = rows.iter().filter(|r| r.feasible).collect();
    let infeasible: Vec<&Row> = rows.iter().filter(|r| !r.feasible).collect();
    // Planning times of the feasible scenes (successes and failures alike: a failure's time is
    // the time spent before giving up).
    let mut times: Vec<f64> = feasible.iter().filter_map(|r| r.time).collect();
    times.sort_by(f64::total_cmp);
    let mut ok_times: Vec<f64> = feasible
        .iter()
        .filter(|r| r.as_expected)
        .filter_map(|r| r.time)
        .collect();
    ok_times.sort_by(f64::total_cmp);
    let mut by_scene: BTreeMap<&str, Vec<bool>> = BTreeMap::new();
    for r in rows {
        by_scene.entry(&r.scene).or_default().push(r.as_expected);
    }
    Summary {
        feasible_runs: feasible.len(),
        feasible_ok: feasible.iter().filter(|r| r.as_expected).count(),
        infeasible_runs: infeasible.len(),
        infeasible_ok: infeasible.iter().filter(|r| r.as_expected).count(),
        median: quantile(&times, 0.5),
        p95: quantile(&times, 0.95),
        median_ok: quantile(&ok_times, 0.5),
        p95_ok: quantile(&ok_times, 0.95),
        disagreeing: by_scene
            .into_iter()
            .filter(|(_, v)| v.iter().any(|&b| b != v[0]))
            .map(|(s, _)| s.to_owned())
            .collect(),
        failures: rows.iter().filter(|r| !r.as_expected).cloned().collect(),
    }
}

fn ms(t: Option<f64>) -> String {
    t.map_or_else(|| "-".into(), |t| format!("{:.1} ms", t * 1e3))
}

fn pct(n: usize, d: usize) -> String {
    if d == 0 {
        "-".into()
    } else {
        format!("{:.1} %", 100.0 * n as f64 / d as f64)
    }
}

/// The table and the summary as Markdown.
pub fn render(rows: &[Row], s: &Summary, entries: &[Entry]) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "- feasible scenes planned and validated: {} of {} runs ({})",
        s.feasible_ok,
        s.feasible_runs,
        pct(s.feasible_ok, s.feasible_runs)
    );
    let _ = writeln!(
        t,
        "- infeasible scenes refused with the expected stage and reason: {} of {} runs",
        s.infeasible_ok, s.infeasible_runs
    );
    let _ = writeln!(
        t,
        "- planning time over the feasible scenes' runs: median {}, 95th percentile {}; over \
         the runs that planned and validated: median {}, 95th percentile {}",
        ms(s.median),
        ms(s.p95),
        ms(s.median_ok),
        ms(s.p95_ok)
    );
    let _ = writeln!(
        t,
        "- scenes whose seeds disagree: {}",
        if s.disagreeing.is_empty() {
            "none".to_owned()
        } else {
            s.disagreeing.join(", ")
        }
    );
    // Success per tag and per object (runs as expected / runs).
    let mut per: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for r in rows {
        if let Some(e) = entries.iter().find(|e| e.name == r.scene) {
            for key in e
                .tags
                .iter()
                .map(|t| format!("tag {t}"))
                .chain([format!("object {}", e.object)])
            {
                let c = per.entry(key).or_default();
                c.0 += usize::from(r.as_expected);
                c.1 += 1;
            }
        }
    }
    let per: Vec<String> = per
        .iter()
        .map(|(k, (ok, n))| format!("{k} {ok}/{n}"))
        .collect();
    let _ = writeln!(
        t,
        "- runs as expected per tag and object: {}",
        per.join(", ")
    );
    let mut failed: Vec<&str> = s.failures.iter().map(|r| r.scene.as_str()).collect();
    failed.dedup();
    if !failed.is_empty() {
        let _ = writeln!(t, "\nScenes with a run not as expected:\n");
        for name in failed {
            if let Some(e) = entries.iter().find(|e| e.name == name) {
                let reason = match s.failures.iter().find(|r| r.scene == name) {
                    Some(r) if r.outcome == Outcome::Valid => {
                        "planned and validated, but the scene has no solution"
                    }
                    Some(r) => r.outcome.reason(),
                    None => "",
                };
                let _ = writeln!(
                    t,
                    "- `{}` ({}; {}): {} — {}",
                    e.name,
                    e.expect,
                    e.tags.join(", "),
                    e.about,
                    if reason.is_empty() {
                        "refused, but not for the stated reason"
                    } else {
                        reason
                    }
                );
            }
        }
    }
    let _ = writeln!(
        t,
        "\n| scene | seed | expected | outcome | strategy | time | reason |"
    );
    let _ = writeln!(t, "|---|---|---|---|---|---|---|");
    for r in rows {
        let expected = entries
            .iter()
            .find(|e| e.name == r.scene)
            .map(|e| match (&e.stage, &e.reason) {
                (Some(st), Some(re)) => format!("no solution: {st} / {re}"),
                _ => e.expect.clone(),
            })
            .unwrap_or_default();
        let _ = writeln!(
            t,
            "| {}{} | {} | {} | {} | {} | {} | {} |",
            r.scene,
            if r.as_expected { "" } else { " ✗" },
            r.seed,
            expected,
            r.outcome.word(),
            r.strategy,
            ms(r.time),
            r.outcome.reason().replace('|', "/")
        );
    }
    t
}

/// Machine and load, for the document.
fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|c| {
            c.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_owned())
        })
        .unwrap_or_else(|| "unknown CPU".into());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let load = std::fs::read_to_string("/proc/loadavg")
        .map(|l| l.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into());
    format!(
        "{cpu}, {cores} cores (nproc), load average {load} (1, 5, 15 min) at the end of the run"
    )
}

/// Opening marker of the generated part of the suite's notes in `benches/targets.toml`.
pub const DOC_BEGIN: &str = "<!-- xtask suite run: begin -->";
/// Closing marker.
pub const DOC_END: &str = "<!-- xtask suite run: end -->";

/// Puts `text` between the markers of `benches/targets.toml` and rewrites docs/benchmarks.md
/// from it (`cargo xtask bench --text-only`: the criterion figures are kept).
fn write_doc(root: &Path, text: &str) -> anyhow::Result<()> {
    let path = root.join("benches/targets.toml");
    let toml_text =
        std::fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
    let (b, e) = match (toml_text.find(DOC_BEGIN), toml_text.find(DOC_END)) {
        (Some(b), Some(e)) if b < e => (b + DOC_BEGIN.len(), e),
        _ => bail!("{}: {DOC_BEGIN} … {DOC_END} not found", path.display()),
    };
    // The notes are a TOML basic multi-line string: escape what it cannot hold.
    let escaped = text.replace('\\', "\\\\").replace("\"\"\"", "\\\"\\\"\\\"");
    let new = format!(
        "{}\n{}\n{}",
        &toml_text[..b],
        escaped.trim_end(),
        &toml_text[e..]
    );
    std::fs::write(&path, new).with_context(|| format!("writing {}", path.display()))?;
    crate::bench::run(root, &["--text-only".to_owned()])
}

/// `cargo xtask suite run`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse(args)?;
    let manifest = load_manifest(root)?;
    let entries: Vec<Entry> = manifest
        .scene
        .iter()
        .filter(|e| glob_match(&args.glob, &e.name))
        .cloned()
        .collect();
    if entries.is_empty() {
        bail!("no scene matches {}", args.glob);
    }
    let cli = build_cli(root)?;
    // xtask's own folder, as `cargo xtask precompute` fills it (passed with --cache).
    let cache = pickplace::precompute::cache_dir(root);
    let scratch = root.join("target/suite-plans");
    std::fs::create_dir_all(&scratch)?;
    let start = std::time::Instant::now();
    let mut rows = Vec::new();
    for e in &entries {
        for &seed in &args.seeds {
            let row = run_one(&cli, root, &cache, &scratch, e, seed)?;
            eprintln!(
                "{:<45} seed {seed}: {}{} {} {} {}",
                row.scene,
                row.outcome.word(),
                if row.as_expected { "" } else { " (UNEXPECTED)" },
                row.strategy,
                ms(row.time),
                row.outcome.reason()
            );
            rows.push(row);
        }
    }
    let summary = summarize(&rows);
    let table = render(&rows, &summary, &entries);
    println!("{table}");
    if args.write_doc {
        let seeds: Vec<String> = args.seeds.iter().map(u64::to_string).collect();
        let text = format!(
            "`cargo xtask suite run --seeds {} --write-doc` ({} scenes, {:.0} s in all, cluster \
             databases, grasp sets and roadmaps from the cache), release build, on {}. Planning \
             time: the wall-clock of the planning call that `pickplace plan` prints (setup and \
             cache loading excluded; the setup plans the object's grasp set, 1–50 ms once per \
             object and gripper, as it clusters the object's surface), over every run of a feasible scene. ✗ marks a run whose outcome is not the manifest's \
             expectation.\n\n{table}",
            seeds.join(","),
            entries.len(),
            start.elapsed().as_secs_f64(),
            machine(),
        );
        write_doc(root, &text)?;
    }
    let open: Vec<&Row> = summary
        .failures
        .iter()
        .filter(|r| r.open.is_some())
        .collect();
    if !open.is_empty() {
        eprintln!(
            "open (feasible scenes the planner does not meet yet, listed in the manifest): {}",
            open.iter()
                .map(|r| format!("{} (seed {})", r.scene, r.seed))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let failed: Vec<&Row> = summary
        .failures
        .iter()
        .filter(|r| r.open.is_none())
        .collect();
    if !failed.is_empty() || !summary.disagreeing.is_empty() {
        let names: Vec<String> = failed
            .iter()
            .map(|r| format!("{} (seed {})", r.scene, r.seed))
            .collect();
        bail!(
            "{} run(s) not as expected: {}; seeds disagree on: {:?}",
            failed.len(),
            names.join(", "),
            summary.disagreeing
        );
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs() {
        assert!(glob_match("*", "can-right"));
        assert!(glob_match("can-*", "can-right"));
        assert!(!glob_match("can-*", "box-right"));
        assert!(glob_match("*-gap", "can-into-gap"));
        assert!(glob_match("*into*gap", "can-into-narrow-gap"));
        assert!(glob_match("can-right", "can-right"));
        assert!(!glob_match("can", "can-right"));
    }

    #[test]
    fn timing_lines_parse() {
        let ok = "  plan: right-right with … samples; planned in 45.0 ms\n  wrote x";
        assert_eq!(parse_ms(ok, "planned in "), Some(0.045));
        let no = "  no plan (740.2 ms):\n    right-right: out of reach\n";
        let t = parse_ms(no, "no plan (").expect("a time");
        assert!((t - 0.7402).abs() < 1e-12, "{t}");
        assert_eq!(why(no), "right-right: out of reach");
        assert_eq!(parse_ms("nothing", "planned in "), None);
    }

    #[test]
    fn quantiles_and_disagreement() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0];
        assert_eq!(quantile(&v, 0.5), Some(5.0));
        assert_eq!(quantile(&v, 0.95), Some(10.0));
        assert_eq!(quantile(&[], 0.5), None);
        let row = |scene: &str, seed, ok| Row {
            scene: scene.into(),
            seed,
            feasible: true,
            outcome: if ok {
                Outcome::Valid
            } else {
                Outcome::NoPlan("x".into())
            },
            strategy: String::new(),
            time: Some(0.01 * seed as f64),
            as_expected: ok,
            open: None,
        };
        let rows = [row("a", 1, true), row("a", 2, false), row("b", 1, true)];
        let s = summarize(&rows);
        assert_eq!(s.disagreeing, vec!["a".to_owned()]);
        assert_eq!((s.feasible_ok, s.feasible_runs), (2, 3));
        assert_eq!(s.failures.len(), 1);
        assert_eq!(s.median_ok, Some(0.01));
        let v = "  set up in 48 ms\n  checked 1432 states in 57 ms\n  t = 1.0 s: collision a / b\n  t = 1.1 s: collision a / b\n  … 49 problems in all\n";
        assert_eq!(
            why_invalid(v),
            "t = 1.0 s: collision a / b (… 49 problems in all)"
        );
    }

    /// The manifest the generator writes parses, and names files that exist.
    #[test]
    fn manifest_parses_and_names_existing_scenes() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let m = load_manifest(&root).expect("manifest");
        assert_eq!(m.scene.len(), crate::suite::scenes().len());
        for e in &m.scene {
            assert!(
                root.join("scenes/suite").join(&e.file).is_file(),
                "{}",
                e.file
            );
            assert_eq!(e.feasible(), e.stage.is_none(), "{}", e.name);
        }
    }
}
