//! The robot's allowed-collision matrix for planning: the SRDF's `disable_collisions`,
//! completed. Links joined by a joint may always touch; a robot whose SRDF lists no pair (or
//! that has no SRDF) gets MoveIt's sampled matrix ([`sampled_matrix`]: Adjacent, Default,
//! Always at the scene's "usually in collision" fraction, Never), cached with the robot as
//! an SRDF file of `disable_collisions` lines, so that it is sampled once per robot and
//! options.

use crate::cache::Cache;
use crate::scene::CollisionMatrixSpec;
use pickplace_geometry::hash::ContentHasher;
use pickplace_geometry::math::Real;
use pickplace_robot::assistant::sampled_matrix;
use pickplace_robot::collision::{
    AllowedCollisionMatrix, BodyId, CheckOptions, CollisionScratch, CollisionWorld,
    SAMPLING_VERSION,
};
use pickplace_robot::srdf::DisableReason;
use pickplace_robot::{RobotModel, Semantics, Srdf};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Extension of a cached sampled matrix (an SRDF holding only `disable_collisions`).
const EXTENSION: &str = "acm.srdf";

/// The robot's matrix, completed: the SRDF's pairs; links joined by a joint (the SRDF often
/// lists them, not always); with no pair in the SRDF, the sampled matrix of
/// [`CollisionMatrixSpec`] (from the cache when there, else sampled and written there). Then,
/// still without pairs from the SRDF, pairs within one chain in collision at the start state
/// (geometry overlapping across a joint). Each addition is said in the log.
///
/// # Errors
/// Errors of the collision library while sampling.
pub(crate) fn complete_acm(
    model: &RobotModel,
    semantics: &Semantics,
    start: &[Real],
    (spec, key_text): (&CollisionMatrixSpec, &str),
    cache: &mut Cache,
    log: &mut Vec<String>,
) -> std::result::Result<AllowedCollisionMatrix, pickplace_robot::Error> {
    let mut acm = AllowedCollisionMatrix::from_srdf(semantics.srdf());
    let adjacent = AllowedCollisionMatrix::adjacent_links(model);
    let added = adjacent
        .iter()
        .filter(|(a, b, _)| !acm.is_allowed(a, b))
        .count();
    acm.merge(&adjacent);
    if added > 0 {
        log.push(format!(
            "{added} pairs of links joined by a joint may touch (the SRDF does not list them)"
        ));
    }
    if !semantics.srdf().disabled_collisions.is_empty() {
        return Ok(acm);
    }
    let t = Instant::now();
    let key = matrix_key(key_text, spec);
    let path = cache.dir().map(|dir| entry_path(dir, model.name(), key));
    let (sampled, loaded) = match path.as_deref().and_then(|p| read_entry(p, key)) {
        Some(sampled) => (sampled, true),
        None => {
            let report = sampled_matrix(model, &spec.options())?;
            if let Some(path) = &path {
                cache.write(path, entry_text(model, &report.acm, key, spec).as_bytes());
            }
            (report.acm, false)
        }
    };
    acm.merge(&sampled);
    log.push(format!(
        "no collision matrix in the SRDF: sampled as MoveIt's setup assistant does ({} configurations, seed {}, usually in collision from {:.0} %): {} link pairs never checked {}, {} in {:.1} ms; `pickplace robot check` prints them as SRDF lines",
        spec.samples,
        spec.seed,
        spec.min_collision_fraction * 100.0,
        sampled.len(),
        by_reason(&sampled),
        if loaded {
            "loaded from the cache"
        } else {
            "sampled"
        },
        t.elapsed().as_secs_f64() * 1e3
    ));
    let world = CollisionWorld::new(model, acm.clone())?;
    let pairs = world.colliding_pairs(
        model,
        start,
        &mut CollisionScratch::default(),
        &CheckOptions::default(),
    )?;
    let mut names = Vec::new();
    for (a, b) in pairs {
        // Only within one chain (a link and one of its ancestors: geometry overlapping
        // across a joint); two branches touching at the start is a collision, reported by
        // the start check.
        if let (BodyId::Link(a), BodyId::Link(b)) = (a, b)
            && (model.is_ancestor(a, b) || model.is_ancestor(b, a))
        {
            let (a, b) = (&model.links()[a].name, &model.links()[b].name);
            acm.allow(a, b, DisableReason::Default);
            names.push(format!("{a} ~ {b}"));
        }
    }
    if !names.is_empty() {
        log.push(format!(
            "{} link pairs of one chain touching at the start state may touch ({})",
            names.len(),
            names.join(", ")
        ));
    }
    Ok(acm)
}

/// `(adjacent 12, default 3, always 2, never 200)`: the pairs' count per reason.
fn by_reason(acm: &AllowedCollisionMatrix) -> String {
    let parts: Vec<String> = acm
        .counts_by_reason()
        .into_iter()
        .map(|(reason, n)| format!("{} {n}", reason.as_str().to_lowercase()))
        .collect();
    format!("({})", parts.join(", "))
}

/// The key of a sampled matrix: the robot's files and options ([`crate::RobotSetup`]'s key
/// text), the sampling options and the sampling's version.
fn matrix_key(key_text: &str, spec: &CollisionMatrixSpec) -> u64 {
    let mut h = ContentHasher::default();
    h.bytes(key_text.as_bytes());
    h.word(spec.samples as u64);
    h.word(spec.seed);
    h.word(spec.min_collision_fraction.to_bits());
    h.word(u64::from(SAMPLING_VERSION));
    h.finish()
}

/// `<dir>/<robot>.<key>.acm.srdf`.
fn entry_path(dir: &Path, robot: &str, key: u64) -> PathBuf {
    dir.join(format!("{robot}.{key:016x}.{EXTENSION}"))
}

/// The first line after the XML declaration of an entry made for `key`.
fn key_line(key: u64) -> String {
    format!("<!-- pickplace sampled collision matrix {key:016x} -->")
}

/// An SRDF holding the matrix, with its key and how it was sampled in comments.
fn entry_text(
    model: &RobotModel,
    acm: &AllowedCollisionMatrix,
    key: u64,
    spec: &CollisionMatrixSpec,
) -> String {
    let srdf = Srdf {
        robot_name: model.name().to_owned(),
        disabled_collisions: acm.to_disabled_pairs(),
        ..Srdf::default()
    };
    let comment = format!(
        "{}\n<!-- {} random configurations, seed {}, Always from {} of the samples; written by pickplace for a robot whose SRDF has no disable_collisions. -->\n",
        key_line(key),
        spec.samples,
        spec.seed,
        spec.min_collision_fraction
    );
    srdf.to_xml_with_comment(&comment)
}

/// The matrix of a cache entry made for `key`; none when missing, made for another key,
/// damaged or unreadable (then it is sampled again and written over).
fn read_entry(path: &Path, key: u64) -> Option<AllowedCollisionMatrix> {
    let text = pickplace_geometry::io::read_text(path, pickplace_geometry::io::CACHE_ENTRY).ok()?;
    if !text.lines().take(3).any(|l| l == key_line(key)) {
        return None;
    }
    let srdf = Srdf::from_xml_str(&text).ok()?;
    (!srdf.disabled_collisions.is_empty() && srdf.skipped.is_empty())
        .then(|| AllowedCollisionMatrix::from_srdf(&srdf))
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_robot::LoadOptions;

    /// A base with two links that overlap at every angle (a four-bar linkage's inner and
    /// outer links: siblings, not joined by a joint) and one far away that never touches.
    fn linkage() -> RobotModel {
        let text = r#"<robot name="bar">
          <link name="base"><collision><geometry><box size="0.02 0.02 0.02"/></geometry></collision></link>
          <link name="inner"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.01 0.01 0.1"/></geometry></collision></link>
          <link name="outer"><collision><origin xyz="0 0 0.05"/><geometry><box size="0.01 0.01 0.1"/></geometry></collision></link>
          <link name="far"><collision><geometry><box size="0.01 0.01 0.01"/></geometry></collision></link>
          <joint name="j_inner" type="revolute"><parent link="base"/><child link="inner"/><origin xyz="0 0 0.02"/><axis xyz="0 1 0"/><limit lower="-0.3" upper="0.3" velocity="1" effort="1"/></joint>
          <joint name="j_outer" type="revolute"><parent link="base"/><child link="outer"/><origin xyz="0.005 0 0.02"/><axis xyz="0 1 0"/><limit lower="-0.3" upper="0.3" velocity="1" effort="1"/><mimic joint="j_inner"/></joint>
          <joint name="j_far" type="fixed"><parent link="base"/><child link="far"/><origin xyz="1 0 0"/></joint>
        </robot>"#;
        RobotModel::from_urdf_str(text, Path::new("."), &LoadOptions::default()).expect("valid")
    }

    #[test]
    fn without_pairs_in_the_srdf_the_matrix_is_sampled_and_cached() {
        let model = linkage();
        let semantics =
            Semantics::resolve(&model, &Srdf::default(), Path::new("none")).expect("resolves");
        let spec = CollisionMatrixSpec {
            samples: 300,
            ..CollisionMatrixSpec::default()
        };
        let dir = std::env::temp_dir().join(format!("pickplace-acm-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let start = model.zero_configuration();
        let mut log = Vec::new();
        let mut cache = Cache::open(Some(&dir));
        let acm = complete_acm(
            &model,
            &semantics,
            &start,
            (&spec, "k"),
            &mut cache,
            &mut log,
        )
        .expect("sampled");
        // The linkage's links overlap in every sample: Default at the zero pose.
        assert!(acm.is_allowed("inner", "outer"), "{log:?}");
        assert_eq!(acm.reason("inner", "far"), Some(&DisableReason::Never));
        assert!(log.iter().any(|l| l.contains("sampled in")), "{log:?}");
        // The second time, from the cache, the same matrix.
        let mut log = Vec::new();
        let again = complete_acm(
            &model,
            &semantics,
            &start,
            (&spec, "k"),
            &mut cache,
            &mut log,
        )
        .expect("loaded");
        assert_eq!(again, acm);
        assert!(
            log.iter().any(|l| l.contains("loaded from the cache")),
            "{log:?}"
        );
        // Other options, another entry.
        let other = CollisionMatrixSpec {
            min_collision_fraction: 1.0,
            ..spec.clone()
        };
        let mut log = Vec::new();
        complete_acm(
            &model,
            &semantics,
            &start,
            (&other, "k"),
            &mut cache,
            &mut log,
        )
        .expect("sampled");
        assert!(log.iter().any(|l| l.contains("sampled in")), "{log:?}");
        // A damaged entry is sampled again.
        for entry in std::fs::read_dir(&dir).expect("dir").flatten() {
            std::fs::write(entry.path(), "<robot").expect("write");
        }
        let mut log = Vec::new();
        let rebuilt = complete_acm(
            &model,
            &semantics,
            &start,
            (&spec, "k"),
            &mut cache,
            &mut log,
        )
        .expect("sampled");
        assert_eq!(rebuilt, acm);
        assert!(cache.into_warnings().is_empty());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn pairs_in_the_srdf_are_used_as_they_are() {
        let model = linkage();
        let srdf = Srdf::from_xml_str(
            r#"<robot name="bar"><disable_collisions link1="inner" link2="outer" reason="Always"/></robot>"#,
        )
        .expect("parses");
        let semantics = Semantics::resolve(&model, &srdf, Path::new("bar.srdf")).expect("ok");
        let mut log = Vec::new();
        let acm = complete_acm(
            &model,
            &semantics,
            &model.zero_configuration(),
            (&CollisionMatrixSpec::default(), "k"),
            &mut Cache::open(None),
            &mut log,
        )
        .expect("ok");
        assert!(!acm.is_allowed("inner", "far"));
        assert!(!log.iter().any(|l| l.contains("sampled")), "{log:?}");
    }
}
