//! `cargo xtask bench [--quick] [--no-run | --text-only] [-- FILTER…]`: runs the criterion
//! benches of `pickplace-benches`, reads the medians criterion wrote (`new/` directories), and
//! writes `docs/benchmarks.md` from them and the data file `benches/targets.toml`: a summary
//! (medians per area, the machine, each target with PASS or MISS, the ratios to the reference
//! implementations) and each area's notes.
//!
//! Modules: [`catalogue`] reads the data file, [`results`] criterion's files, [`machine`]
//! describes the machine, [`report`] renders the document.
//!
//! Only results written by this run are used (their files are newer than its start), so a bench
//! that did not run shows as "not run" rather than as a stale figure; `--no-run` regenerates
//! from whatever results exist, and `--text-only` keeps the summary the document already holds
//! and rewrites the rest from the data file. Criterion writes into `target/criterion-xtask`
//! (`CRITERION_HOME`), not the shared `target/criterion`, so that benches run by someone else at
//! the same time are not mixed in.

pub mod catalogue;
pub mod machine;
pub mod report;
pub mod results;

use anyhow::{Context, bail};
use catalogue::Catalogue;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::SystemTime;

/// Path of the generated document under the repository root.
pub const DOCUMENT_PATH: &str = "docs/benchmarks.md";

/// What `cargo xtask bench` takes its figures from.
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub enum Figures {
    /// Run the benches and use the results of this run (default).
    #[default]
    Run,
    /// Do not run the benches; use every result on disk (`--no-run`).
    OnDisk,
    /// Keep the summary `docs/benchmarks.md` holds; rewrite the rest (`--text-only`).
    Kept,
}

/// Options of `cargo xtask bench`.
#[derive(Debug, Default, PartialEq)]
pub struct BenchArgs {
    /// Criterion's quick mode.
    pub quick: bool,
    /// Where the figures come from.
    pub figures: Figures,
    /// Criterion filters (after `--`).
    pub filters: Vec<String>,
}

/// The usage line.
pub const USAGE: &str = "usage: cargo xtask bench [--quick] [--no-run | --text-only] [-- FILTER…]";

/// Parses the arguments after `bench`.
pub fn parse_args(args: &[String]) -> anyhow::Result<BenchArgs> {
    let mut parsed = BenchArgs::default();
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let figures = match arg.as_str() {
            "--quick" => {
                parsed.quick = true;
                continue;
            }
            "--no-run" => Figures::OnDisk,
            "--text-only" => Figures::Kept,
            "--" => {
                parsed.filters.extend(it.by_ref().cloned());
                continue;
            }
            other => bail!("unknown argument {other:?}; {USAGE}"),
        };
        if parsed.figures != Figures::Run && parsed.figures != figures {
            bail!("--no-run and --text-only exclude each other; {USAGE}");
        }
        parsed.figures = figures;
    }
    Ok(parsed)
}

fn target_dir(root: &Path) -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .map(|p| if p.is_relative() { root.join(p) } else { p })
        .unwrap_or_else(|| root.join("target"))
}

/// Runs the benches (unless told not to) and returns the summary.
fn summary(root: &Path, args: &BenchArgs, catalogue: &Catalogue) -> anyhow::Result<String> {
    let mut bench_args = vec!["bench", "-p", "pickplace-benches", "--benches", "--"];
    if args.quick {
        bench_args.push("--quick");
    }
    bench_args.extend(args.filters.iter().map(String::as_str));
    let command = format!("cargo {}", bench_args.join(" "));
    let load_start = machine::load_average();
    // Criterion's files carry the time they were written; a second of slack for coarse clocks.
    let started = SystemTime::now() - std::time::Duration::from_secs(1);
    // A criterion directory of its own: the shared target/criterion receives the results of
    // whoever else benches at the same time, which would pass for this run's.
    let criterion = target_dir(root).join("criterion-xtask");
    let run = args.figures == Figures::Run;
    if run {
        eprintln!("== {command} (CRITERION_HOME={}) ==", criterion.display());
        let status = Command::new("cargo")
            .args(&bench_args)
            .env("CRITERION_HOME", &criterion)
            .current_dir(root)
            .status()
            .context("running cargo bench")?;
        if !status.success() {
            bail!("{command} failed ({status}); {DOCUMENT_PATH} left unchanged");
        }
    }
    let results = results::collect(&criterion, run.then_some(started))?;
    let info = machine::describe_machine(
        if run {
            command
        } else {
            "cargo xtask bench --no-run (results on disk)".to_string()
        },
        load_start,
    );
    eprintln!("{} results from {}", results.len(), criterion.display());
    Ok(report::render_summary(catalogue, &results, &info))
}

/// `cargo xtask bench`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse_args(args)?;
    let catalogue = Catalogue::load(root)?;
    let doc_path = root.join(DOCUMENT_PATH);
    let summary = match args.figures {
        Figures::Kept => {
            let document = std::fs::read_to_string(&doc_path)
                .with_context(|| format!("reading {}", doc_path.display()))?;
            report::summary_of(&document)
                .with_context(|| format!("{}", doc_path.display()))?
                .to_string()
        }
        Figures::Run | Figures::OnDisk => summary(root, &args, &catalogue)?,
    };
    let document = report::render_document(&catalogue, &summary);
    pickplace_geometry::export::write_atomic(&doc_path, document.as_bytes())?;
    eprintln!(
        "wrote {} from {} and criterion's results",
        doc_path.display(),
        catalogue::CATALOGUE_PATH
    );
    if args.figures != Figures::Kept {
        print!("{summary}");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments() {
        let args = |a: &[&str]| parse_args(&a.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        assert_eq!(
            args(&["--quick", "--", "placement", "--exact"]).expect("valid"),
            BenchArgs {
                quick: true,
                figures: Figures::Run,
                filters: vec!["placement".into(), "--exact".into()]
            }
        );
        assert_eq!(args(&["--no-run"]).expect("valid").figures, Figures::OnDisk);
        assert_eq!(
            args(&["--text-only"]).expect("valid").figures,
            Figures::Kept
        );
        assert!(args(&["--no-run", "--text-only"]).is_err());
        assert!(args(&["--fast"]).is_err());
        assert_eq!(args(&[]).expect("valid"), BenchArgs::default());
    }
}
