//! `cargo xtask mbm --ompl`: the same Panda problems planned by OMPL 2.0.1's RRT-Connect with
//! collisions by coal through pinocchio (`benches/ompl_mbm.py`), for the side-by-side table
//! of docs/benchmarks.md (issue 35).

use anyhow::{Context, bail};
use pickplace_geometry::math::Real;
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::process::Command;

/// The packages of the comparison's environment, pinned.
const PACKAGES: [&str; 4] = ["ompl==2.0.1", "pin==4.1.0", "coal==3.0.3", "pyyaml==6.0.2"];
/// Where `--write` records the summaries, under the repository root.
pub const RESULTS_PATH: &str = "benches/mbm-ompl.json";

/// One scenario's figures, as the script writes them.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct OmplSummary {
    pub scenario: String,
    pub problems: usize,
    pub solved: usize,
    pub median: Real,
    pub p95: Real,
    pub mean_length: Real,
    pub colliding: usize,
    /// Starts and goals coal finds in collision (our checker's verdicts are in
    /// `target/mbm/outcomes.json`).
    pub invalid_starts: usize,
    pub invalid_goals: usize,
}

/// What `--ompl --write` records.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct OmplResults {
    pub machine: String,
    pub tools: String,
    pub seed: u64,
    pub summaries: Vec<OmplSummary>,
}

/// Runs the script on the problems unpacked in `dir` (first `sample` of each Panda scenario
/// when given) and prints its summaries; `write` records them in [`RESULTS_PATH`].
pub fn run(
    root: &Path,
    dir: &Path,
    sample: Option<usize>,
    seed: u64,
    write: bool,
) -> anyhow::Result<()> {
    let venv = std::env::var_os("PICKPLACE_OMPL_VENV")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| root.join("target/ompl-venv"));
    let python = crate::venv::ensure(
        &venv,
        "import ompl, pinocchio, coal, yaml",
        &PACKAGES,
        "xtask mbm",
    )?;
    let out = dir.join("ompl.json");
    let load_start = crate::bench::machine::load_average();
    let mut command = Command::new(&python);
    command
        .current_dir(root)
        .args(["-W", "ignore", "benches/ompl_mbm.py", "--resources"])
        .arg(dir.join(super::ROBOTS[0].1))
        .arg("--problems")
        .arg(dir.join("problems"))
        .arg("--out")
        .arg(&out)
        .args(["--seed", &seed.to_string()]);
    if let Some(n) = sample {
        command.args(["--sample", &n.to_string()]);
    }
    eprintln!(
        "xtask mbm: OMPL 2.0.1 RRTConnect, pinocchio 4.1.0 and coal 3.0.3 (benches/ompl_mbm.py)"
    );
    let status = command.status().context("cannot run benches/ompl_mbm.py")?;
    if !status.success() {
        bail!("benches/ompl_mbm.py failed ({status})");
    }
    let text =
        std::fs::read_to_string(&out).with_context(|| format!("reading {}", out.display()))?;
    let mut results: OmplResults =
        serde_json::from_str(&text).with_context(|| format!("parsing {}", out.display()))?;
    let info = crate::bench::machine::describe_machine(
        format!("cargo xtask mbm --ompl --seed {seed}"),
        load_start,
    );
    results.machine = info.one_line();
    if write {
        let json = serde_json::to_string_pretty(&results)? + "\n";
        pickplace_geometry::export::write_atomic(&root.join(RESULTS_PATH), json.as_bytes())?;
        crate::bench::run(root, &["--text-only".to_owned()])?;
    }
    Ok(())
}

/// The OMPL table of the MotionBenchMaker section, with our medians beside OMPL's.
pub fn render(results: &OmplResults, ours: &super::Results) -> String {
    use crate::bench::report::format_time;
    use std::fmt::Write;
    let mut out = format!(
        "\n### Side by side: OMPL 2.0.1 on the Panda's problems (`cargo xtask mbm --ompl`)\n\n\
         Written by `cargo xtask mbm --ompl --write` (seed {}); do not edit. Machine: {}. \
         Tools: {}. `benches/ompl_mbm.py`: OMPL's `RRTConnect` (its default range), states \
         checked every 1° of joint motion by pinocchio's `computeCollisions` on the links' \
         convex hulls (coal), the SRDF's and the scenes' allowed pairs removed, a time limit of \
         1 s, one thread, `solve()` timed (its checks call coal through Python); every path \
         found checked again at 1°. Invalid ends: starts and goals coal finds in collision.\n\n\
         | scenario | solved | median | 95th percentile | colliding | invalid ends | our median | OMPL's median / ours |\n\
         |---|---|---|---|---|---|---|---|\n",
        results.seed, results.machine, results.tools
    );
    for s in &results.summaries {
        let mine = ours.summaries.iter().find(|m| m.scenario == s.scenario);
        let _ = writeln!(
            out,
            "| {} | {}/{} | {} | {} | {} | {} | {} | {} |",
            s.scenario,
            s.solved,
            s.problems,
            format_time(s.median),
            format_time(s.p95),
            s.colliding,
            s.invalid_starts + s.invalid_goals,
            mine.map_or_else(|| "–".to_owned(), |m| format_time(m.median)),
            mine.filter(|m| m.median > 0.0)
                .map_or_else(|| "–".to_owned(), |m| format!("{:.0}", s.median / m.median)),
        );
    }
    out
}
