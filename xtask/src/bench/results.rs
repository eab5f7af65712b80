//! Criterion's results: the median of every bench that ran, read from the `new/` directories
//! criterion writes (`benchmark.json` and `estimates.json`).

use anyhow::Context;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::SystemTime;

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

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use std::path::PathBuf;
    use std::time::Duration;

    /// A fresh directory under the system temp dir, removed on drop.
    pub(crate) struct TempDir(pub(crate) PathBuf);

    impl TempDir {
        pub(crate) fn new(name: &str) -> Self {
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
    pub(crate) fn fixture(root: &Path, id: &str, median_ns: f64, elements: Option<u64>) -> PathBuf {
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
}
