//! The data file `benches/targets.toml`: the document's areas with their notes, the targets the
//! issues set and the references they compare with. Read with serde; unknown keys are errors.

use anyhow::Context;
use serde::Deserialize;
use std::path::Path;

/// Path of the data file under the repository root.
pub const CATALOGUE_PATH: &str = "benches/targets.toml";

/// Everything `docs/benchmarks.md` says besides criterion's figures.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Catalogue {
    /// The document's title (its `#` heading).
    pub title: String,
    /// The paragraph under the title.
    pub intro: String,
    /// The areas, in the document's order.
    #[serde(rename = "area", default)]
    pub areas: Vec<Area>,
    /// The targets, in the summary's order.
    #[serde(rename = "target", default)]
    pub targets: Vec<Target>,
    /// The comparisons, in the summary's order.
    #[serde(rename = "reference", default)]
    pub references: Vec<Reference>,
    /// The MotionBenchMaker results `cargo xtask mbm --write` recorded
    /// ([`crate::mbm::RESULTS_PATH`]), when present.
    #[serde(skip)]
    pub mbm: Option<crate::mbm::Results>,
    /// OMPL's figures on the same problems (`cargo xtask mbm --ompl --write`,
    /// [`crate::mbm::ompl::RESULTS_PATH`]), when present.
    #[serde(skip)]
    pub mbm_ompl: Option<crate::mbm::ompl::OmplResults>,
}

/// One area of benches: a heading of the medians table and a section of notes.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Area {
    /// Title, without the issue.
    pub title: String,
    /// The issue that asked for these benches, if any.
    pub issue: Option<u32>,
    /// Criterion groups (first segment of a bench id) of this area; a trailing `*` matches
    /// every group starting with the rest.
    pub groups: Vec<String>,
    /// Hand-written notes (Markdown), the area's section after the summary; none when empty.
    #[serde(default)]
    pub notes: String,
}

impl Area {
    /// The heading: the title, and the issue in parentheses when there is one.
    pub fn heading(&self) -> String {
        match self.issue {
            Some(n) => format!("{} (issue {n})", self.title),
            None => self.title.clone(),
        }
    }

    /// Whether the bench `id` belongs to this area.
    pub fn contains(&self, id: &str) -> bool {
        let group = id.split('/').next().unwrap_or(id);
        self.groups.iter().any(|g| match g.strip_suffix('*') {
            Some(prefix) => group.starts_with(prefix),
            None => group == g,
        })
    }
}

/// What a target asks of one benchmark.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Goal {
    /// Median time at most this many seconds.
    AtMost(f64),
    /// Throughput (criterion `Elements` per second of the median) at least this.
    AtLeastPerSecond(f64),
}

/// One target, set by an issue or not.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// The issue that set it, if any.
    pub issue: Option<u32>,
    /// Criterion id (`group/function`) or prefix with a trailing `*`.
    pub bench: String,
    /// The target in words.
    pub text: String,
    /// The machine-checkable form.
    pub goal: Goal,
}

/// The other side of a comparison.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Theirs {
    /// Another bench of the same run (its criterion id).
    Bench(String),
    /// A figure an issue quotes, not measurable here.
    Quoted(Quoted),
}

/// A quoted range of times.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quoted {
    /// Low end (s).
    pub low: f64,
    /// High end (s).
    pub high: f64,
}

/// A comparison with a reference implementation: ratio = their time / our time (how many
/// times faster ours is).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Reference {
    /// The issue that asked for it, if any.
    pub issue: Option<u32>,
    /// What is compared, in words.
    pub text: String,
    /// Our bench.
    pub ours: String,
    /// The reference.
    pub theirs: Theirs,
    /// Least ratio asked for, if any.
    pub aim: Option<f64>,
}

impl Catalogue {
    /// Parses the data file's text.
    pub fn parse(text: &str) -> anyhow::Result<Self> {
        Ok(toml::from_str(text)?)
    }

    /// Reads `<root>/benches/targets.toml`.
    pub fn load(root: &Path) -> anyhow::Result<Self> {
        let path = root.join(CATALOGUE_PATH);
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        let mut catalogue =
            Self::parse(&text).with_context(|| format!("parsing {}", path.display()))?;
        let mbm = root.join(crate::mbm::RESULTS_PATH);
        if mbm.is_file() {
            let text = std::fs::read_to_string(&mbm)
                .with_context(|| format!("reading {}", mbm.display()))?;
            catalogue.mbm = Some(
                serde_json::from_str(&text)
                    .with_context(|| format!("parsing {}", mbm.display()))?,
            );
        }
        let ompl = root.join(crate::mbm::ompl::RESULTS_PATH);
        if ompl.is_file() {
            let text = std::fs::read_to_string(&ompl)
                .with_context(|| format!("reading {}", ompl.display()))?;
            catalogue.mbm_ompl = Some(
                serde_json::from_str(&text)
                    .with_context(|| format!("parsing {}", ompl.display()))?,
            );
        }
        Ok(catalogue)
    }

    /// The index of the area of a bench id (the first that contains it) in [`Self::areas`].
    pub fn area_index(&self, id: &str) -> Option<usize> {
        self.areas.iter().position(|a| a.contains(id))
    }

    /// The bench ids (or prefixes) that the targets and references name, in file order.
    pub fn named_benches(&self) -> impl Iterator<Item = &str> {
        let targets = self.targets.iter().map(|t| t.bench.as_str());
        let ours = self.references.iter().map(|r| r.ours.as_str());
        let theirs = self.references.iter().filter_map(|r| match &r.theirs {
            Theirs::Bench(id) => Some(id.as_str()),
            Theirs::Quoted(_) => None,
        });
        targets.chain(ours).chain(theirs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_kind_of_entry() {
        let text = r#"
            title = "Benchmarks"
            intro = "Intro."
            [[area]]
            title = "PRM"
            issue = 5
            groups = ["prm*"]
            [[area]]
            title = "Meshes"
            groups = ["mesh", "mesh_io"]
            notes = "Hand-written."
            [[target]]
            bench = "prm_toy/lazy_query_cold"
            text = "fast"
            goal = { at_most = 2e-3 }
            [[target]]
            issue = 2
            bench = "mesh/*"
            text = "many"
            goal = { at_least_per_second = 1e6 }
            [[reference]]
            text = "vs RRT"
            ours = "prm_toy/lazy_query_cold"
            theirs = { bench = "prm_toy/rrt_connect" }
            [[reference]]
            issue = 3
            text = "vs Python"
            ours = "mesh/x"
            theirs = { quoted = { low = 0.07, high = 0.08 } }
            aim = 30
        "#;
        let c = Catalogue::parse(text).expect("valid");
        assert_eq!(c.areas[0].heading(), "PRM (issue 5)");
        assert_eq!(c.areas[1].heading(), "Meshes");
        assert_eq!(c.targets[0].goal, Goal::AtMost(2e-3));
        assert_eq!(c.targets[1].goal, Goal::AtLeastPerSecond(1e6));
        assert_eq!(c.targets[0].issue, None);
        assert_eq!(
            c.references[1].theirs,
            Theirs::Quoted(Quoted {
                low: 0.07,
                high: 0.08
            })
        );
        assert_eq!(c.references[1].aim, Some(30.0));
        assert_eq!(c.area_index("prm_nxhiro/rrt_connect"), Some(0));
        assert_eq!(c.area_index("mesh_io/read"), Some(1));
        assert!(c.area_index("mesh_other/x").is_none(), "groups match whole");
        assert!(c.area_index("view/x").is_none());
        assert_eq!(
            c.named_benches().collect::<Vec<_>>(),
            [
                "prm_toy/lazy_query_cold",
                "mesh/*",
                "prm_toy/lazy_query_cold",
                "mesh/x",
                "prm_toy/rrt_connect"
            ]
        );
    }

    #[test]
    fn unknown_keys_and_goals_are_errors() {
        let base = "title = \"B\"\nintro = \"\"\n";
        assert!(Catalogue::parse(&format!("{base}colour = 1\n")).is_err());
        let target = "[[target]]\nbench = \"a/b\"\ntext = \"t\"\n";
        assert!(Catalogue::parse(&format!("{base}{target}goal = {{ at_least = 1 }}\n")).is_err());
        assert!(Catalogue::parse(&format!("{base}{target}goal = {{ at_most = 1 }}\n")).is_ok());
    }

    #[test]
    fn the_shipped_file_parses() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
        let c = Catalogue::load(&root).expect("benches/targets.toml");
        assert!(!c.targets.is_empty() && !c.references.is_empty());
        // Every named bench has an area.
        for id in c.named_benches() {
            assert!(c.area_index(id).is_some(), "{id} has no area");
        }
    }
}
