//! `cargo xtask bench [--quick] [--no-run] [-- FILTER…]`: runs the criterion benches of
//! `pickplace-benches`, reads the medians criterion wrote (`target/criterion/**/new/`), and
//! rewrites the generated part of `docs/benchmarks.md`: medians per area, the machine, each
//! issue's target with PASS or MISS, and the ratios to the peers the issues named.
//!
//! The generated part sits between [`BEGIN`] and [`END`]; everything outside the markers (the
//! hand-written sections of each area) is kept byte for byte. Only results written by this run
//! are used (their files are newer than its start), so a bench that did not run shows as
//! "not run" rather than as a stale figure; `--no-run` regenerates from whatever results exist.
//! Criterion writes into `target/criterion-xtask` (`CRITERION_HOME`), not the shared
//! `target/criterion`, so that benches run by someone else at the same time are not mixed in.

use anyhow::{Context, bail};
use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// Opening marker of the generated part of `docs/benchmarks.md`.
pub const BEGIN: &str = "<!-- xtask bench: begin -->";
/// Closing marker of the generated part.
pub const END: &str = "<!-- xtask bench: end -->";

/// What an issue asks of one benchmark.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Goal {
    /// Median time at most this many seconds.
    AtMost(f64),
    /// Throughput (criterion `Elements` per second of the median) at least this.
    AtLeastPerSecond(f64),
}

/// One target set by an issue. `id` is a criterion id, or a prefix ending in `*` that applies
/// the target to every measured bench starting with it.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    /// Issue number.
    pub issue: u32,
    /// Criterion id (`group/function`) or prefix with a trailing `*`.
    pub id: &'static str,
    /// The target in the issue's words.
    pub words: &'static str,
    /// The machine-checkable form.
    pub goal: Goal,
}

/// The targets of issues 2 to 7. Ids of benches not written yet (the planner's `plan/…`)
/// are listed too: until their bench exists they show as "not run".
pub const TARGETS: &[Target] = &[
    Target {
        issue: 2,
        id: "clustering/env/*",
        words: "environment clustering ≥ 1 million triangles per second per core",
        goal: Goal::AtLeastPerSecond(1.0e6),
    },
    Target {
        issue: 2,
        id: "database/load_can_env",
        words: "loading the can's database under 1 ms",
        goal: Goal::AtMost(1e-3),
    },
    Target {
        issue: 2,
        id: "database/load_can_finger",
        words: "loading the can's database under 1 ms",
        goal: Goal::AtMost(1e-3),
    },
    Target {
        issue: 3,
        id: "placement/can_on_pallet_large_dent",
        words: "candidates for the can on the pallet ≤ 1 ms median",
        goal: Goal::AtMost(1e-3),
    },
    Target {
        issue: 3,
        id: "placement/mug_resting_poses",
        words: "resting poses on a plane for the mug ≤ 2 ms",
        goal: Goal::AtMost(2e-3),
    },
    Target {
        issue: 4,
        id: "robot/ik_right_arm_waist/pickplace",
        words: "IK, right arm with the waist: median ≤ 30 µs per solve on one thread (criterion \
                times the mean solve over 1 024 cycling targets, restarts included; the bench \
                prints the per-solve median of its acceptance run)",
        goal: Goal::AtMost(30e-6),
    },
    Target {
        issue: 4,
        id: "robot/collision_pallet_scene/free_configurations",
        words: "the full robot against the pallet scene ≤ 5 µs median per configuration",
        goal: Goal::AtMost(5e-6),
    },
    Target {
        issue: 5,
        id: "prm_nxhiro/roadmap_5000_prefiltered_2_threads",
        words: "a 5 000-node roadmap built in ≤ 1 s on two cores",
        goal: Goal::AtMost(1.0),
    },
    Target {
        issue: 5,
        id: "prm_nxhiro/roadmap_5000_checked_2_threads",
        words: "a 5 000-node roadmap built in ≤ 1 s on two cores",
        goal: Goal::AtMost(1.0),
    },
    Target {
        issue: 5,
        id: "prm_nxhiro/lazy_query_cold",
        words: "a query on the prebuilt lazy roadmap ≤ 2 ms median",
        goal: Goal::AtMost(2e-3),
    },
    Target {
        issue: 6,
        id: "grasps/plan/mug",
        words: "the mug's grasp set (≥ 500 candidates evaluated) ≤ 5 ms median",
        goal: Goal::AtMost(5e-3),
    },
    Target {
        issue: 7,
        id: "plan/fig9_near",
        words: "the whole plan for the Fig. 9 scene ≤ 100 ms median without handover",
        goal: Goal::AtMost(0.1),
    },
    Target {
        issue: 7,
        id: "plan/fig9_far_handover",
        words: "the whole plan for the Fig. 9 scene ≤ 300 ms median with handover",
        goal: Goal::AtMost(0.3),
    },
];

/// The other side of a comparison.
#[derive(Debug, Clone, Copy)]
pub enum PeerSide {
    /// Another bench of the same run.
    Bench(&'static str),
    /// A figure the issue quotes (not measurable here): a range in seconds.
    Quoted {
        /// Low end (s).
        low: f64,
        /// High end (s).
        high: f64,
    },
}

/// A comparison an issue asked for: ratio = peer time / our time (how many times faster).
#[derive(Debug, Clone, Copy)]
pub struct Peer {
    /// Issue number.
    pub issue: u32,
    /// What is compared, in words.
    pub words: &'static str,
    /// Our bench.
    pub ours: &'static str,
    /// The peer.
    pub theirs: PeerSide,
    /// Least ratio the issue asks for, if any.
    pub aim: Option<f64>,
}

/// The peers the issues named.
pub const PEERS: &[Peer] = &[
    Peer {
        issue: 3,
        words: "mug resting poses vs a widely used Python library (70–80 ms for a 900-triangle \
                mug, quoted by the issue, not run here)",
        ours: "placement/mug_resting_poses",
        theirs: PeerSide::Quoted {
            low: 70e-3,
            high: 80e-3,
        },
        aim: Some(30.0),
    },
    Peer {
        issue: 4,
        words: "IK, right arm with the waist: the `k` crate's JacobianIkSolver, same URDF and \
                targets",
        ours: "robot/ik_right_arm_waist/pickplace",
        theirs: PeerSide::Bench("robot/ik_right_arm_waist/k_jacobian_ik"),
        aim: None,
    },
    Peer {
        issue: 4,
        words: "TCP pose + Jacobian vs the `k` crate's FK + Jacobian of the same chain",
        ours: "robot/jacobian_tcp_right_arm_waist",
        theirs: PeerSide::Bench("robot/k_fk_and_jacobian_right_arm_waist"),
        aim: None,
    },
    Peer {
        issue: 5,
        words: "lazy PRM query (cold) vs our RRT-Connect baseline, NX-HIRO pallet scene",
        ours: "prm_nxhiro/lazy_query_cold",
        theirs: PeerSide::Bench("prm_nxhiro/rrt_connect"),
        aim: None,
    },
    Peer {
        issue: 5,
        words: "lazy PRM query (cold) vs our RRT-Connect baseline, toy 7-D problem",
        ours: "prm_toy/lazy_query_cold",
        theirs: PeerSide::Bench("prm_toy/rrt_connect"),
        aim: None,
    },
];

/// The area a bench id belongs to (its heading in the medians table).
pub fn area_of(id: &str) -> &'static str {
    let first = id.split('/').next().unwrap_or(id);
    match first {
        "mesh" | "mesh_io" => "Meshes (issue 2)",
        "clustering" | "database" => "Clustering and cluster database (issue 2)",
        "placement" => "Placement (issue 3)",
        "robot" => "Robot (issue 4)",
        f if f.starts_with("prm") => "PRM (issue 5)",
        "grasps" => "Grasps (issue 6)",
        "plan" => "Planner (issue 7)",
        _ => "Other",
    }
}

/// One bench result read from criterion's files.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurement {
    /// Criterion's full id (`group/function`).
    pub id: String,
    /// Median point estimate (s).
    pub median: f64,
    /// 95 % confidence interval of the median (s).
    pub interval: (f64, f64),
    /// Elements per iteration, when the bench declared a throughput.
    pub elements: Option<u64>,
}

impl Measurement {
    /// Elements per second at the median.
    pub fn per_second(&self) -> Option<f64> {
        self.elements
            .filter(|_| self.median > 0.0)
            .map(|n| n as f64 / self.median)
    }
}

/// Reads one `new/` directory: `benchmark.json` (id, throughput) and `estimates.json`.
pub fn read_measurement(new_dir: &Path) -> anyhow::Result<Measurement> {
    let read = |name: &str| -> anyhow::Result<serde_json::Value> {
        let path = new_dir.join(name);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))
    };
    let benchmark = read("benchmark.json")?;
    let estimates = read("estimates.json")?;
    let id = benchmark["full_id"]
        .as_str()
        .with_context(|| format!("{}: benchmark.json has no full_id", new_dir.display()))?
        .to_string();
    let median = &estimates["median"];
    let ns = |v: &serde_json::Value, what: &str| {
        v.as_f64()
            .with_context(|| format!("{}: estimates.json has no median {what}", new_dir.display()))
    };
    let point = ns(&median["point_estimate"], "point_estimate")?;
    let lower = ns(&median["confidence_interval"]["lower_bound"], "lower bound")?;
    let upper = ns(&median["confidence_interval"]["upper_bound"], "upper bound")?;
    let elements = benchmark["throughput"]["Elements"].as_u64();
    Ok(Measurement {
        id,
        median: point * 1e-9,
        interval: (lower * 1e-9, upper * 1e-9),
        elements,
    })
}

/// Every result under `criterion_dir` (recursively, each `new/` directory holding
/// `estimates.json`), keyed by id. With `since`, results whose `estimates.json` is older are
/// skipped (left over from earlier runs).
pub fn collect(
    criterion_dir: &Path,
    since: Option<SystemTime>,
) -> anyhow::Result<BTreeMap<String, Measurement>> {
    let mut out = BTreeMap::new();
    if !criterion_dir.is_dir() {
        return Ok(out);
    }
    let mut stack = vec![criterion_dir.to_path_buf()];
    while let Some(dir) = stack.pop() {
        let entries =
            std::fs::read_dir(&dir).with_context(|| format!("listing {}", dir.display()))?;
        for entry in entries {
            let path = entry?.path();
            if !path.is_dir() {
                continue;
            }
            let estimates = path.join("estimates.json");
            if path.file_name().is_some_and(|n| n == "new") && estimates.is_file() {
                if let Some(since) = since {
                    let modified = std::fs::metadata(&estimates)?.modified()?;
                    if modified < since {
                        continue;
                    }
                }
                let m = read_measurement(&path)?;
                out.insert(m.id.clone(), m);
            } else if path.file_name().is_some_and(|n| n != "report") {
                stack.push(path);
            }
        }
    }
    Ok(out)
}

/// A duration with three significant digits in ns, µs, ms or s.
pub fn format_time(seconds: f64) -> String {
    let (value, unit) = if seconds < 1e-6 {
        (seconds * 1e9, "ns")
    } else if seconds < 1e-3 {
        (seconds * 1e6, "µs")
    } else if seconds < 1.0 {
        (seconds * 1e3, "ms")
    } else {
        (seconds, "s")
    };
    let digits = if value >= 100.0 {
        0
    } else if value >= 10.0 {
        1
    } else {
        2
    };
    format!("{value:.digits$} {unit}")
}

/// A rate such as `1.23 M/s`.
fn format_rate(per_second: f64) -> String {
    if per_second >= 1e5 {
        format!("{:.2} M/s", per_second / 1e6)
    } else if per_second >= 1e3 {
        format!("{:.1} k/s", per_second / 1e3)
    } else {
        format!("{per_second:.0} /s")
    }
}

/// The machine and the run, for the report's header.
#[derive(Debug, Clone, PartialEq)]
pub struct RunInfo {
    /// CPU model.
    pub cpu: String,
    /// Logical cores.
    pub cores: usize,
    /// Memory (GiB).
    pub memory_gib: Option<f64>,
    /// Operating system and kernel.
    pub os: String,
    /// `rustc --version`.
    pub rustc: String,
    /// UTC date and time of the run.
    pub date: String,
    /// Load averages (1 min) at the start and the end of the run.
    pub load: (Option<f64>, Option<f64>),
    /// The command that ran the benches.
    pub command: String,
}

/// The CPU model from `lscpu`'s text ("Model name:") or `/proc/cpuinfo` ("model name").
pub fn cpu_model(lscpu: &str, cpuinfo: &str) -> Option<String> {
    let field = |text: &str, key: &str| {
        text.lines().find_map(|l| {
            let (k, v) = l.split_once(':')?;
            (k.trim() == key && !v.trim().is_empty()).then(|| v.trim().to_string())
        })
    };
    field(lscpu, "Model name").or_else(|| field(cpuinfo, "model name"))
}

/// `MemTotal` of `/proc/meminfo`, in GiB.
pub fn memory_gib(meminfo: &str) -> Option<f64> {
    let line = meminfo.lines().find(|l| l.starts_with("MemTotal:"))?;
    let kib: f64 = line
        .trim_start_matches("MemTotal:")
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kib / (1024.0 * 1024.0))
}

/// Civil date (y, m, d) of a count of days since 1970-01-01 (proleptic Gregorian).
pub fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// `YYYY-MM-DD HH:MM UTC` of a time.
pub fn utc_string(t: SystemTime) -> String {
    let secs = t
        .duration_since(SystemTime::UNIX_EPOCH)
        .map(|d| d.as_secs() as i64)
        .unwrap_or(0);
    let (y, m, d) = civil_from_days(secs.div_euclid(86_400));
    let s = secs.rem_euclid(86_400);
    format!(
        "{y:04}-{m:02}-{d:02} {:02}:{:02} UTC",
        s / 3600,
        s % 3600 / 60
    )
}

fn load_average() -> Option<f64> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()?
        .split_whitespace()
        .next()?
        .parse()
        .ok()
}

fn command_output(program: &str, args: &[&str]) -> Option<String> {
    let out = Command::new(program).args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn os_description() -> String {
    let pretty = std::fs::read_to_string("/etc/os-release")
        .ok()
        .and_then(|t| {
            t.lines()
                .find_map(|l| l.strip_prefix("PRETTY_NAME="))
                .map(|v| v.trim_matches('"').to_string())
        });
    let kernel = std::fs::read_to_string("/proc/sys/kernel/osrelease")
        .ok()
        .map(|k| k.trim().to_string());
    match (pretty, kernel) {
        (Some(p), Some(k)) => format!("{p}, Linux {k}"),
        (Some(p), None) => p,
        (None, Some(k)) => format!("Linux {k}"),
        (None, None) => std::env::consts::OS.to_string(),
    }
}

/// Describes this machine.
fn describe_machine(command: String, load_start: Option<f64>) -> RunInfo {
    let lscpu = command_output("lscpu", &[]).unwrap_or_default();
    let cpuinfo = std::fs::read_to_string("/proc/cpuinfo").unwrap_or_default();
    RunInfo {
        cpu: cpu_model(&lscpu, &cpuinfo).unwrap_or_else(|| "unknown CPU".to_string()),
        cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
        memory_gib: std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|m| memory_gib(&m)),
        os: os_description(),
        rustc: command_output("rustc", &["--version"]).unwrap_or_else(|| "rustc ?".to_string()),
        date: utc_string(SystemTime::now()),
        load: (load_start, load_average()),
        command,
    }
}

/// PASS, MISS or a reason, for a goal and a measurement.
fn verdict(goal: Goal, m: &Measurement) -> (String, &'static str) {
    match goal {
        Goal::AtMost(limit) => (
            format_time(m.median),
            if m.median <= limit { "PASS" } else { "MISS" },
        ),
        Goal::AtLeastPerSecond(rate) => match m.per_second() {
            Some(r) => (
                format!("{} ({})", format_rate(r), format_time(m.median)),
                if r >= rate { "PASS" } else { "MISS" },
            ),
            None => (format_time(m.median), "no throughput"),
        },
    }
}

/// The generated part of `docs/benchmarks.md` (between the markers, markers excluded).
pub fn render(results: &BTreeMap<String, Measurement>, info: &RunInfo) -> String {
    let mut out = String::new();
    let w = &mut out;
    let _ = writeln!(w, "## Summary (generated by `cargo xtask bench`)\n");
    let _ = writeln!(
        w,
        "Written by `cargo xtask bench`; do not edit between the markers. Run: `{}`, {}.",
        info.command, info.date
    );
    let memory = info
        .memory_gib
        .map_or_else(String::new, |g| format!(", {g:.1} GiB"));
    let load = match info.load {
        (Some(a), Some(b)) => format!("; load average {a:.2} at the start, {b:.2} at the end"),
        _ => String::new(),
    };
    let _ = writeln!(
        w,
        "Machine: {}, {} logical cores{memory}; {}; {}{load}. Criterion medians with their 95 % \
         confidence intervals; on a shared machine they move by tens of percent between runs.\n",
        info.cpu, info.cores, info.os, info.rustc
    );

    // Targets.
    let _ = writeln!(w, "### Targets\n");
    let _ = writeln!(w, "| issue | bench | target | median | result |");
    let _ = writeln!(w, "|---|---|---|---|---|");
    for t in TARGETS {
        let matched: Vec<&Measurement> = match t.id.strip_suffix('*') {
            Some(prefix) => results
                .values()
                .filter(|m| m.id.starts_with(prefix))
                .collect(),
            None => results.get(t.id).into_iter().collect(),
        };
        if matched.is_empty() {
            let _ = writeln!(
                w,
                "| {} | `{}` | {} | — | not run |",
                t.issue, t.id, t.words
            );
        }
        for m in matched {
            let (value, result) = verdict(t.goal, m);
            let _ = writeln!(
                w,
                "| {} | `{}` | {} | {value} | {result} |",
                t.issue, m.id, t.words
            );
        }
    }

    // Peers.
    let _ = writeln!(w, "\n### Peers (same run)\n");
    let _ = writeln!(w, "| issue | comparison | ours | peer | peer / ours |");
    let _ = writeln!(w, "|---|---|---|---|---|");
    for p in PEERS {
        let ours = results.get(p.ours);
        let (peer, ratio) = match (p.theirs, ours) {
            (PeerSide::Bench(id), _) => {
                let theirs = results.get(id);
                let ratio = match (ours, theirs) {
                    (Some(o), Some(t)) if o.median > 0.0 => {
                        format!("{:.1}×", t.median / o.median)
                    }
                    _ => "not run".to_string(),
                };
                (
                    theirs.map_or_else(
                        || format!("`{id}` not run"),
                        |t| format!("{} (`{id}`)", format_time(t.median)),
                    ),
                    ratio,
                )
            }
            (PeerSide::Quoted { low, high }, _) => {
                let ratio = match ours {
                    Some(o) if o.median > 0.0 => {
                        let (a, b) = (low / o.median, high / o.median);
                        let aim = p.aim.map_or_else(String::new, |aim| {
                            let met = if a >= aim { "PASS" } else { "MISS" };
                            format!(" (aim ≥ {aim:.0}×: {met})")
                        });
                        format!("{a:.0}–{b:.0}×{aim}")
                    }
                    _ => "not run".to_string(),
                };
                (
                    format!("{}–{} (quoted)", format_time(low), format_time(high)),
                    ratio,
                )
            }
        };
        let ours = ours.map_or_else(
            || format!("`{}` not run", p.ours),
            |o| format!("{} (`{}`)", format_time(o.median), p.ours),
        );
        let _ = writeln!(
            w,
            "| {} | {} | {ours} | {peer} | {ratio} |",
            p.issue, p.words
        );
    }

    // Medians by area: every measured bench, and the targeted ones that did not run.
    let _ = writeln!(w, "\n### Medians\n");
    let mut by_area: BTreeMap<&str, Vec<(String, Option<&Measurement>)>> = BTreeMap::new();
    for m in results.values() {
        by_area
            .entry(area_of(&m.id))
            .or_default()
            .push((m.id.clone(), Some(m)));
    }
    let expected = TARGETS
        .iter()
        .map(|t| t.id)
        .chain(PEERS.iter().map(|p| p.ours))
        .chain(PEERS.iter().filter_map(|p| match p.theirs {
            PeerSide::Bench(id) => Some(id),
            PeerSide::Quoted { .. } => None,
        }));
    for id in expected {
        let present = match id.strip_suffix('*') {
            Some(prefix) => results.keys().any(|k| k.starts_with(prefix)),
            None => results.contains_key(id),
        };
        let rows = by_area.entry(area_of(id)).or_default();
        if !present && !rows.iter().any(|(r, _)| r == id) {
            rows.push((id.to_string(), None));
        }
    }
    // Areas in issue order.
    let mut areas: Vec<_> = by_area.into_iter().collect();
    areas.sort_by_key(|(area, _)| {
        (
            area.rsplit("issue ")
                .next()
                .and_then(|n| n.trim_end_matches(')').parse::<u32>().ok())
                .unwrap_or(u32::MAX),
            *area,
        )
    });
    for (area, mut rows) in areas {
        rows.sort_by(|a, b| a.0.cmp(&b.0));
        let _ = writeln!(w, "**{area}**\n");
        let _ = writeln!(w, "| bench | median | 95 % interval | throughput |");
        let _ = writeln!(w, "|---|---|---|---|");
        for (id, m) in rows {
            match m {
                Some(m) => {
                    let _ = writeln!(
                        w,
                        "| `{id}` | {} | {} – {} | {} |",
                        format_time(m.median),
                        format_time(m.interval.0),
                        format_time(m.interval.1),
                        m.per_second().map_or_else(String::new, format_rate)
                    );
                }
                None => {
                    let _ = writeln!(w, "| `{id}` | not run | | |");
                }
            }
        }
        let _ = writeln!(w);
    }
    out
}

/// Replaces the text between [`BEGIN`] and [`END`] in `document` by `generated`. Without the
/// markers, the block is inserted after the first line (the title) and a blank line.
pub fn splice(document: &str, generated: &str) -> anyhow::Result<String> {
    let block = format!("{BEGIN}\n{}\n{END}", generated.trim_end());
    match (document.find(BEGIN), document.find(END)) {
        (Some(b), Some(e)) if b < e => Ok(format!(
            "{}{block}{}",
            &document[..b],
            &document[e + END.len()..]
        )),
        (None, None) => {
            let (title, rest) = match document.split_once('\n') {
                Some((t, r)) => (t, r),
                None => (document, ""),
            };
            let title = if title.is_empty() {
                "# Benchmarks"
            } else {
                title
            };
            Ok(format!(
                "{title}\n\n{block}\n\n{}",
                rest.trim_start_matches('\n')
            ))
        }
        _ => bail!("{BEGIN} and {END} must both appear, in that order, or neither"),
    }
}

/// Writes `bytes` to `path` through a temporary file in the same directory and a rename.
fn write_atomically(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let tmp = dir.join(format!(
        ".{}.tmp{}",
        path.file_name().and_then(|n| n.to_str()).unwrap_or("out"),
        std::process::id()
    ));
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path)
        .with_context(|| format!("renaming {} to {}", tmp.display(), path.display()))
}

/// Options of `cargo xtask bench`.
#[derive(Debug, Default, PartialEq)]
pub struct BenchArgs {
    /// Criterion's quick mode.
    pub quick: bool,
    /// Do not run the benches; regenerate from every result on disk.
    pub no_run: bool,
    /// Criterion filters (after `--`).
    pub filters: Vec<String>,
}

/// Parses the arguments after `bench`.
pub fn parse_args(args: &[String]) -> anyhow::Result<BenchArgs> {
    let mut parsed = BenchArgs::default();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        match arg.as_str() {
            "--quick" => parsed.quick = true,
            "--no-run" => parsed.no_run = true,
            "--" => parsed.filters.extend(it.by_ref().cloned()),
            other => bail!(
                "unknown argument {other:?}; usage: cargo xtask bench [--quick] [--no-run] \
                 [-- FILTER…]"
            ),
        }
    }
    Ok(parsed)
}

fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|p| if p.is_relative() { root.join(p) } else { p })
        .unwrap_or_else(|| root.join("target"))
}

/// `cargo xtask bench`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse_args(args)?;
    let mut bench_args = vec!["bench", "-p", "pickplace-benches", "--benches", "--"];
    if args.quick {
        bench_args.push("--quick");
    }
    bench_args.extend(args.filters.iter().map(String::as_str));
    let command = format!("cargo {}", bench_args.join(" "));
    let load_start = load_average();
    // Criterion's files carry the time they were written; a second of slack for coarse clocks.
    let started = SystemTime::now() - std::time::Duration::from_secs(1);
    // A criterion directory of its own: the shared target/criterion receives the results of
    // whoever else benches at the same time, which would pass for this run's.
    let criterion = target_dir(root).join("criterion-xtask");
    if !args.no_run {
        eprintln!("== {command} (CRITERION_HOME={}) ==", criterion.display());
        let status = Command::new("cargo")
            .args(&bench_args)
            .env("CRITERION_HOME", &criterion)
            .current_dir(root)
            .status()
            .context("running cargo bench")?;
        if !status.success() {
            bail!("{command} failed ({status}); docs/benchmarks.md left unchanged");
        }
    }
    let results = collect(&criterion, (!args.no_run).then_some(started))?;
    let info = describe_machine(
        if args.no_run {
            "cargo xtask bench --no-run (results on disk)".to_string()
        } else {
            command
        },
        load_start,
    );
    let generated = render(&results, &info);
    let doc_path = root.join("docs/benchmarks.md");
    let document = match std::fs::read_to_string(&doc_path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => "# Benchmarks\n".to_string(),
        Err(e) => return Err(e).with_context(|| format!("reading {}", doc_path.display())),
    };
    let updated = splice(&document, &generated)?;
    write_atomically(&doc_path, updated.as_bytes())?;
    eprintln!(
        "{} results from {}; wrote {}",
        results.len(),
        criterion.display(),
        doc_path.display()
    );
    print!("{generated}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    /// A fresh directory under the system temp dir, removed on drop.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir().join(format!(
                "xtask-bench-{name}-{}-{:?}",
                std::process::id(),
                std::thread::current().id()
            ));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("temp dir");
            Self(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// Writes criterion's two files for one bench, as criterion 0.8 lays them out.
    fn fixture(root: &Path, id: &str, median_ns: f64, elements: Option<u64>) -> PathBuf {
        let new = root.join(id.replace('/', "_")).join("new");
        std::fs::create_dir_all(&new).expect("dir");
        let throughput = elements.map_or("null".to_string(), |n| format!("{{\"Elements\":{n}}}"));
        std::fs::write(
            new.join("benchmark.json"),
            format!(
                "{{\"group_id\":\"g\",\"function_id\":null,\"value_str\":null,\
                 \"throughput\":{throughput},\"full_id\":\"{id}\",\
                 \"directory_name\":\"{}\",\"title\":\"{id}\"}}",
                id.replace('/', "_")
            ),
        )
        .expect("benchmark.json");
        let ci = format!(
            "{{\"confidence_interval\":{{\"confidence_level\":0.95,\"lower_bound\":{},\
             \"upper_bound\":{}}},\"point_estimate\":{median_ns},\"standard_error\":1.0}}",
            median_ns * 0.9,
            median_ns * 1.1
        );
        std::fs::write(
            new.join("estimates.json"),
            format!(
                "{{\"mean\":{ci},\"median\":{ci},\"median_abs_dev\":{ci},\"slope\":null,\
                 \"std_dev\":{ci}}}"
            ),
        )
        .expect("estimates.json");
        new
    }

    fn info() -> RunInfo {
        RunInfo {
            cpu: "AMD EPYC".into(),
            cores: 2,
            memory_gib: Some(23.5),
            os: "Debian GNU/Linux 12 (bookworm), Linux 6.1".into(),
            rustc: "rustc 1.95.0".into(),
            date: "2025-11-21 21:00 UTC".into(),
            load: (Some(1.5), Some(2.0)),
            command: "cargo bench -p pickplace-benches --benches -- --quick".into(),
        }
    }

    fn measurement(id: &str, median: f64, elements: Option<u64>) -> (String, Measurement) {
        (
            id.to_string(),
            Measurement {
                id: id.to_string(),
                median,
                interval: (median * 0.9, median * 1.1),
                elements,
            },
        )
    }

    #[test]
    fn reads_criterion_files() {
        let dir = TempDir::new("read");
        fixture(&dir.0, "clustering/env/can_256", 200_000.0, Some(256));
        fixture(&dir.0, "placement/mug_resting_poses", 730_000.0, None);
        let results = collect(&dir.0, None).expect("collect");
        assert_eq!(results.len(), 2);
        let can = &results["clustering/env/can_256"];
        assert!((can.median - 200e-6).abs() < 1e-12);
        assert!((can.interval.0 - 180e-6).abs() < 1e-12);
        assert!((can.interval.1 - 220e-6).abs() < 1e-12);
        assert_eq!(can.elements, Some(256));
        assert!((can.per_second().expect("rate") - 1.28e6).abs() < 1.0);
        assert_eq!(results["placement/mug_resting_poses"].elements, None);
    }

    #[test]
    fn stale_results_are_skipped() {
        let dir = TempDir::new("stale");
        let old = fixture(&dir.0, "robot/fk_all_links", 400.0, None);
        fixture(&dir.0, "grasps/plan/mug", 1.8e6, None);
        let file = std::fs::File::options()
            .write(true)
            .open(old.join("estimates.json"))
            .expect("open");
        file.set_modified(SystemTime::now() - Duration::from_secs(3600))
            .expect("set mtime");
        let since = SystemTime::now() - Duration::from_secs(60);
        let fresh = collect(&dir.0, Some(since)).expect("collect");
        assert_eq!(fresh.keys().collect::<Vec<_>>(), ["grasps/plan/mug"]);
        assert_eq!(collect(&dir.0, None).expect("collect").len(), 2);
        // No criterion directory at all: nothing ran, not an error.
        assert!(
            collect(&dir.0.join("missing"), None)
                .expect("ok")
                .is_empty()
        );
    }

    #[test]
    fn malformed_estimates_name_the_file() {
        let dir = TempDir::new("malformed");
        let new = fixture(&dir.0, "mesh/weld_10k_soup", 1000.0, None);
        std::fs::write(new.join("estimates.json"), "{\"median\":{}}").expect("write");
        let e = collect(&dir.0, None).expect_err("no point estimate");
        assert!(format!("{e:#}").contains("weld_10k_soup"), "{e:#}");
    }

    #[test]
    fn targets_pass_miss_and_not_run() {
        let results: BTreeMap<_, _> = [
            measurement("clustering/env/can_256", 200e-6, Some(256)), // 1.28 M/s
            measurement("clustering/env/mug_1824", 2.4e-3, Some(1824)), // 0.76 M/s
            measurement("placement/mug_resting_poses", 0.73e-3, None),
            measurement("placement/can_on_pallet_large_dent", 0.634, None),
            measurement("robot/ik_right_arm_waist/pickplace", 66e-6, None),
            measurement("robot/ik_right_arm_waist/k_jacobian_ik", 289e-6, None),
            measurement("prm_nxhiro/lazy_query_cold", 0.291e-3, None),
        ]
        .into_iter()
        .collect();
        let text = render(&results, &info());
        let row = |needle: &str| {
            text.lines()
                .find(|l| l.contains(needle) && l.starts_with("| "))
                .unwrap_or_else(|| panic!("no row with {needle}:\n{text}"))
                .to_string()
        };
        assert!(row("`clustering/env/can_256` | environment").ends_with("| PASS |"));
        assert!(row("`clustering/env/mug_1824` | environment").contains("0.76 M/s"));
        assert!(row("`clustering/env/mug_1824` | environment").ends_with("| MISS |"));
        assert!(row("`placement/mug_resting_poses` | resting").ends_with("| PASS |"));
        assert!(row("`placement/can_on_pallet_large_dent` | candidates").ends_with("| MISS |"));
        assert!(row("`robot/ik_right_arm_waist/pickplace` | IK").ends_with("| MISS |"));
        assert!(row("`prm_nxhiro/lazy_query_cold` | a query").ends_with("| PASS |"));
        // Benches that do not exist yet, or did not run.
        assert!(row("`plan/fig9_near`").ends_with("| not run |"));
        assert!(row("`plan/fig9_far_handover`").ends_with("| not run |"));
        assert!(row("`grasps/plan/mug` | the mug").ends_with("| not run |"));
        // Peers: k / ours from the same run, and the quoted Python figure.
        let k = row("the `k` crate's JacobianIkSolver");
        assert!(k.ends_with("| 4.4× |"), "{k}");
        let python = row("Python library");
        assert!(python.contains("96–110× (aim ≥ 30×: PASS)"), "{python}");
        let rrt = row("toy 7-D problem");
        assert!(rrt.ends_with("| not run |"), "{rrt}");
        // Medians grouped by area, in issue order, with the missing planner benches.
        let clustering = text.find("**Clustering and cluster database (issue 2)**");
        let placement = text.find("**Placement (issue 3)**");
        let planner = text.find("**Planner (issue 7)**");
        assert!(clustering < placement && placement < planner && clustering.is_some());
        assert!(text.contains("| `plan/fig9_near` | not run | | |"));
        assert!(
            text.contains("| `clustering/env/can_256` | 200 µs | 180 µs – 220 µs | 1.28 M/s |")
        );
        assert!(text.contains("AMD EPYC, 2 logical cores, 23.5 GiB"));
        assert!(text.contains("rustc 1.95.0"));
    }

    #[test]
    fn empty_run_shows_every_target_as_not_run() {
        let text = render(&BTreeMap::new(), &info());
        let not_run = text
            .lines()
            .filter(|l| l.starts_with("| ") && l.ends_with("| not run |"))
            .count();
        // Every target row and every peer row.
        assert_eq!(not_run, TARGETS.len() + PEERS.len(), "{text}");
    }

    #[test]
    fn splice_keeps_the_prose() {
        let doc = "# Benchmarks\n\nIntro.\n\n## Robot (issue 4)\n\nHand-written.\n";
        let once = splice(doc, "GENERATED 1\n").expect("insert");
        assert!(once.starts_with(&format!("# Benchmarks\n\n{BEGIN}\nGENERATED 1\n{END}\n\n")));
        assert!(once.ends_with("Intro.\n\n## Robot (issue 4)\n\nHand-written.\n"));
        let twice = splice(&once, "GENERATED 2").expect("replace");
        assert_eq!(twice, once.replace("GENERATED 1", "GENERATED 2"));
        assert_eq!(splice(&twice, "GENERATED 2").expect("same"), twice);
        assert!(splice(&format!("# B\n{END}\n{BEGIN}\n"), "x").is_err());
        assert!(splice(&format!("# B\n{BEGIN}\n"), "x").is_err());
    }

    #[test]
    fn machine_fields() {
        let lscpu = "Architecture: x86_64\nModel name:                              AMD EPYC\n";
        assert_eq!(cpu_model(lscpu, "").as_deref(), Some("AMD EPYC"));
        let cpuinfo = "processor\t: 0\nmodel name\t: Intel(R) Xeon(R)\n";
        assert_eq!(cpu_model("", cpuinfo).as_deref(), Some("Intel(R) Xeon(R)"));
        assert_eq!(cpu_model("", ""), None);
        let gib = memory_gib("MemTotal:       24684084 kB\nMemFree: 1 kB\n").expect("mem");
        assert!((gib - 23.54).abs() < 0.01);
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(20_413), (2025, 11, 21));
        let t = SystemTime::UNIX_EPOCH + Duration::from_secs(20_413 * 86_400 + 21 * 3600 + 5 * 60);
        assert_eq!(utc_string(t), "2025-11-21 21:05 UTC");
    }

    #[test]
    fn times_and_arguments() {
        assert_eq!(format_time(390e-9), "390 ns");
        assert_eq!(format_time(1.82e-3), "1.82 ms");
        assert_eq!(format_time(66e-6), "66.0 µs");
        assert_eq!(format_time(0.742), "742 ms");
        assert_eq!(format_time(2.5), "2.50 s");
        let args = |a: &[&str]| parse_args(&a.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(
            args(&["--quick", "--", "placement", "--exact"]).expect("valid"),
            BenchArgs {
                quick: true,
                no_run: false,
                filters: vec!["placement".into(), "--exact".into()]
            }
        );
        assert!(args(&["--fast"]).is_err());
        assert_eq!(args(&[]).expect("valid"), BenchArgs::default());
    }

    #[test]
    fn areas() {
        assert_eq!(area_of("prm_toy/rrt_connect"), "PRM (issue 5)");
        assert_eq!(
            area_of("database/load_can_env"),
            area_of("clustering/env/x")
        );
        assert_eq!(area_of("mesh_io/read_stl_mug_1824"), "Meshes (issue 2)");
        assert_eq!(area_of("plan/fig9_near"), "Planner (issue 7)");
        assert_eq!(area_of("something/else"), "Other");
    }
}
